"""Progress of long runs with ``tqdm.auto``: a widget in Jupyter, a bar on a terminal, nothing otherwise.

Every long computation (pavings, contraction, ``reach``, the Orthoglide's
dextrous workspace and largest cube, the boundary of a long chain) takes
``progress``:

* ``None`` (default): a bar when the output is interactive (a terminal on
  stderr, or a Jupyter kernel), shown only once the run has lasted a second;
* ``True``: a bar from the start, wherever stderr goes;
* ``False``: nothing.

Examples
--------
>>> with progress_bar(False, total=3, desc="demo") as bar:
...     bar.update(3)
>>> bar.disable
True
"""

from __future__ import annotations

import sys

__all__ = ["interactive", "progress_bar", "stage_bar"]

DELAY = 1.0          # seconds before an automatic bar appears: short runs stay silent


def _in_kernel() -> bool:
    """True inside a Jupyter (IPython) kernel, where tqdm.auto draws a widget."""
    ipython = sys.modules.get("IPython")
    if ipython is None:
        return False
    try:
        shell = ipython.get_ipython()
    except AttributeError:
        return False
    return shell is not None and "IPKernelApp" in getattr(shell, "config", {})


def interactive() -> bool:
    """Whether a person is watching: stderr is a terminal, or the code runs in a Jupyter kernel.

    Returns
    -------
    bool
        True when stderr is a terminal or the code runs in a Jupyter (IPython) kernel.
    """
    stream = sys.stderr
    return _in_kernel() or bool(stream is not None and hasattr(stream, "isatty") and stream.isatty())


def _tqdm_class():
    """tqdm.auto's class, or the terminal one in a kernel without ipywidgets (the widget cannot be drawn)."""
    if _in_kernel():
        try:
            import ipywidgets  # noqa: F401
        except ImportError:
            from tqdm.std import tqdm

            return tqdm
    from tqdm.auto import tqdm

    return tqdm


class _SilentBar:
    """The part of tqdm's interface used here, drawing nothing: a silent run does not pay tqdm's import and its
    multiprocessing lock (0.13 s, most of a cold ``pave`` of the rpr2 mechanism)."""

    disable = True

    def __init__(self, total):
        self.total, self.n = total, 0

    def update(self, n=1):
        self.n += n

    def set_postfix_str(self, text="", refresh=True):
        pass

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def progress_bar(progress: bool | None, *, total: float | None, desc: str, unit: str = "it", **options):
    """A ``tqdm`` bar following the ``progress`` convention of this module (disabled when it must stay silent).

    ``options`` go to ``tqdm`` (``bar_format``, ``unit_scale``...).  The bar
    is a context manager; a disabled bar accepts every call and draws nothing.

    Parameters
    ----------
    progress : bool or None
        None: a bar only when :func:`interactive`, shown once the run has lasted :data:`DELAY` seconds and
        removed when it ends; True: a bar from the start, on stderr, left in place; False: no bar.
    total : float or None
        The count the bar goes to (None: unknown).
    desc : str
        The label in front of the bar.
    unit : str
        The unit of the count (default ``"it"``).
    **options
        Further keyword arguments of ``tqdm``.

    Returns
    -------
    tqdm.tqdm or silent bar
        A ``tqdm`` bar writing to stderr, or, when no bar is to be drawn, an object with the same ``update``,
        ``set_postfix_str``, ``close``, ``n``, ``total`` and ``disable`` (True) that draws nothing.
    """
    enabled = interactive() if progress is None else bool(progress)
    if not enabled:
        return _SilentBar(total)
    tqdm = _tqdm_class()
    return tqdm(total=total, desc=desc, unit=unit, disable=not enabled, delay=DELAY if progress is None else 0.0,
                file=sys.stderr, leave=False if progress is None else True, dynamic_ncols=True, **options)


def stage_bar(progress: bool | None, label: str, total: int):
    """``say(text)`` starts the stage ``text`` of a run of ``total`` stages on a progress bar; ``say(None)``
    ends the run (the bar closes).  For runs made of a few long steps rather than many small ones.

    Parameters
    ----------
    progress : bool or None
        As for :func:`progress_bar`.
    label : str
        The label in front of the bar.
    total : int
        The number of stages.

    Returns
    -------
    callable
        ``say(text)``: ``text`` (str) names the stage that starts now, and the stage before it counts as done;
        ``None`` fills the bar and closes it.
    """
    bar = progress_bar(progress, total=total, desc=label, unit="stage",
                       bar_format="{desc}: stage {n_fmt}/{total_fmt}{postfix} |{bar}| [{elapsed}]")
    started = [False]

    def say(text):
        if text is None:
            bar.update(bar.total - bar.n)
            bar.close()
            return
        if started[0]:
            bar.update(1)
        started[0] = True
        bar.set_postfix_str(text)

    return say
