"""One budgeted box search: prove a statement on every box of a list, bisecting what is undecided.

:func:`workspace_sym.interval.driver.subdivide` keeps every box and measures
the three kinds; a proof that a whole region has a property needs less: stop
at the first box proved to break it, give up when the budget runs out or the
undecided boxes get too thin, and otherwise bisect.  The largest-cube
certificates of the Orthoglide and the planar interval exclusion are this
search with different tests.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..errors import InvalidParameterError, check_choice
from . import arith
from .driver import RunOn, StopAt, refuse_storage, with_legacy_keywords
from .executor import map_codes
from .verdict import OUTSIDE, UNDECIDED

__all__ = ["SPLITS", "prove_all", "bisect_along", "split_every_axis", "split_widest"]

SPLITS = ("widest", "every", "given")


def split_every_axis(boxes: np.ndarray) -> np.ndarray:
    """The ``2^n`` halves-in-every-direction of each box of an ``(N, n, 2)`` array (children grouped by corner).

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.

    Returns
    -------
    numpy.ndarray
        ``(2^n N, n, 2)``: for each corner in turn, that corner's child of every box.
    """
    mid = 0.5 * (boxes[:, :, 0] + boxes[:, :, 1])
    n = boxes.shape[1]
    parts = []
    for corner in range(2 ** n):
        part = boxes.copy()
        for k in range(n):
            part[:, k, 1 - (corner >> k & 1)] = mid[:, k]
        parts.append(part)
    return np.concatenate(parts)


def bisect_along(boxes: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Each box of an ``(N, n, 2)`` array cut in two at the middle of edge ``axis[i]``: lower halves, then upper.

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.
    axis : numpy.ndarray of int
        ``(N,)``: the edge to cut in each box.

    Returns
    -------
    numpy.ndarray
        ``(2 N, n, 2)``: the ``N`` lower halves, then the ``N`` upper ones.
    """
    rows = np.arange(len(boxes))
    mid = 0.5 * (boxes[rows, axis, 0] + boxes[rows, axis, 1])
    lower, upper = boxes.copy(), boxes.copy()
    lower[rows, axis, 1] = mid
    upper[rows, axis, 0] = mid
    return np.concatenate([lower, upper])


def split_widest(boxes: np.ndarray) -> np.ndarray:
    """Each box cut in two across its widest edge.

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.

    Returns
    -------
    numpy.ndarray
        ``(2 N, n, 2)``: the lower halves, then the upper ones (:func:`bisect_along`).
    """
    return bisect_along(boxes, np.argmax(boxes[:, :, 1] - boxes[:, :, 0], axis=1))


@arith.nearest_rounding
def prove_all(boxes, test, *, min_width: float = 0.0, split: str = "widest", stop: StopAt = StopAt(),
              run: RunOn = RunOn(), executor=None):
    """Prove ``test`` on every box of ``boxes`` (an ``(N, n, 2)`` array), bisecting the undecided ones.

    ``test(boxes)`` returns one code a box: 1 proved, -1 proved false (the
    statement fails somewhere in the box), 0 undecided.  With
    ``split="given"`` it returns ``(codes, axis)`` instead, ``axis[i]`` the
    edge along which box ``i`` is bisected when undecided; ``"widest"``
    bisects across the widest edge, ``"every"`` halves every edge at once.

    Only the test proves anything: the search never turns an undecided box
    into a verdict.  A search needs a bound: a box budget, a time limit or
    ``min_width > 0`` (``run.progress`` does not apply: the search shows no
    bar).

    ``run`` (:class:`~workspace_sym.interval.driver.RunOn`): ``executor`` (a
    ``concurrent.futures.Executor`` or a ``dask.distributed.Client``)
    evaluates each generation in chunks of at most ``chunk`` boxes elsewhere
    (:func:`~workspace_sym.interval.executor.map_codes`); ``test`` must then
    pickle.  The search and its verdict are unchanged.  With
    ``split="given"`` the test runs here all the same: the executor is not
    used.  The search keeps no boxes: ``max_memory``, ``store`` and
    ``resume`` are refused.  ``executor=`` is the deprecated spelling of
    ``run=RunOn(executor=...)``.

    Parameters
    ----------
    boxes : array_like
        ``(N, n, 2)`` boxes.
    test : callable
        ``test(boxes)`` returns the codes (with ``split="given"``, ``(codes, axis)``), as above.
    min_width : float
        Give up when every edge of every undecided box is narrower than this (default 0: never), 0 or more.
    split : {"widest", "every", "given"}
        How an undecided box is bisected (default ``"widest"``).
    stop : StopAt
        ``max_boxes`` and ``time_limit`` (checked before each generation); ``section_boxes`` is not used.
    run : RunOn
        ``executor`` and ``chunk``; the others do not apply.
    executor : object or None
        Deprecated: ``run=RunOn(executor=...)``.

    Returns
    -------
    verdict : bool or None
        ``True`` when every box was proved, ``False`` as soon as one box is
        proved false, ``None`` when the next generation would take the count
        ``used`` past ``stop.max_boxes``, when ``stop.time_limit`` seconds
        have passed before a generation, or when every undecided box is
        narrower than ``min_width`` on all its edges.
    used : int
        The number of boxes evaluated (a generation that would pass the
        budget is not evaluated, nor counted).

    Raises
    ------
    InvalidParameterError
        For ``min_width`` below 0 (or NaN), no bound at all, ``max_memory``, ``store`` or ``resume`` in
        ``run``, or two different executors (``executor=`` and ``run``).
    UnknownNameError
        For a ``split`` outside :data:`SPLITS`.

    Examples
    --------
    >>> box = np.array([[[0.0, 1.0], [0.0, 1.0]]])
    >>> below = lambda b: np.where(b[:, :, 1].sum(1) < 1.5, 1, np.where(b[:, :, 0].sum(1) >= 1.5, -1, 0))
    >>> prove_all(box, below, stop=StopAt(max_boxes=100))
    (False, 21)
    >>> prove_all(box, lambda b: np.where(b[:, :, 1].sum(1) <= 2.0, 1, 0), stop=StopAt(max_boxes=100))
    (True, 1)
    >>> prove_all(box, lambda b: np.zeros(len(b), int), stop=StopAt(max_boxes=10))
    (None, 7)
    """
    stop, run = with_legacy_keywords("prove_all", stop, run, executor=executor)
    refuse_storage("prove_all", run)
    check_choice("split", split, SPLITS)
    if not min_width >= 0:
        raise InvalidParameterError(f"min_width must be a non-negative number; got {min_width!r}",
                                    parameter="min_width")
    if stop.max_boxes is None and stop.time_limit is None and min_width == 0:
        raise InvalidParameterError(f"stop: prove_all needs a bound (StopAt(max_boxes=) or time_limit=, or "
                                    f"min_width > 0); got {stop!r}", parameter="stop")
    max_boxes = math.inf if stop.max_boxes is None else stop.max_boxes
    chunk = {} if run.chunk is None else {"chunk": run.chunk}
    start = time.perf_counter()
    work = np.asarray(boxes, dtype=float)
    used = 0
    while len(work):
        if stop.time_limit is not None and time.perf_counter() - start > stop.time_limit:
            return None, used
        if used + len(work) > max_boxes:
            return None, used
        used += len(work)
        if split == "given":
            codes, axis = test(work)
        else:
            codes, axis = map_codes(test, work, run.executor, **chunk), None
        codes = np.asarray(codes)
        if (codes == OUTSIDE).any():
            return False, used
        undecided = codes == UNDECIDED
        work = work[undecided]
        if not len(work):
            return True, used
        if (work[:, :, 1] - work[:, :, 0]).max() < min_width:
            return None, used
        if split == "widest":
            work = split_widest(work)
        elif split == "every":
            work = split_every_axis(work)
        else:
            work = bisect_along(work, np.asarray(axis)[undecided])
    return True, used
