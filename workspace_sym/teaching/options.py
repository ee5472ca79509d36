"""The options of the teaching functions: which fields of :class:`~workspace_sym.interval.driver.StopAt` and
:class:`~workspace_sym.interval.driver.RunOn` apply to each, and the keywords of earlier releases.

:func:`~workspace_sym.teaching.checks.check_reachable`, :func:`~workspace_sym.teaching.grading.grade_answers` and
:func:`~workspace_sym.teaching.exercises.make_exercises` take ``stop=StopAt(...)`` as the rest of the package does:
``max_boxes`` and ``time_limit`` are budgets of the whole call.  The two that run long (a batch of answers, a
sheet) take ``run=RunOn(progress=...)`` for their progress bar; they run in this process and keep no boxes.  A
field that a function cannot honour is refused, never ignored.
"""

from __future__ import annotations

import warnings

from ..errors import InvalidParameterError
from ..interval.driver import RunOn, StopAt

__all__ = ["refuse_stop", "refuse_run", "deprecated"]

_BUDGETS = ("max_boxes", "time_limit", "section_boxes")


def refuse_stop(where: str, stop: StopAt, applies: tuple[str, ...], why: str) -> None:
    """Raise :class:`~workspace_sym.errors.InvalidParameterError` (``parameter="stop"``) when ``stop`` is not a
    :class:`StopAt` or sets a budget that ``where`` does not apply (those not in ``applies``); ``why`` says what it
    stops on instead.

    Parameters
    ----------
    where : str
        The function's name, for the message.
    stop : StopAt
        The caller's ``stop``.
    applies : tuple of str
        The budgets ``where`` honours, among ``max_boxes``, ``time_limit`` and ``section_boxes``.
    why : str
        What ``where`` stops on, for the message (``"stops on boxes only"``).

    Raises
    ------
    InvalidParameterError
        As above.

    Examples
    --------
    >>> refuse_stop("check_reachable", StopAt(max_boxes=10), ("max_boxes",), "stops on boxes only")
    >>> try:
    ...     refuse_stop("check_reachable", StopAt(time_limit=5), ("max_boxes",), "stops on boxes only")
    ... except InvalidParameterError as error:
    ...     print(error, "|", error.parameter)
    stop: check_reachable stops on boxes only; time_limit does not apply; got time_limit=5 | stop
    """
    if not isinstance(stop, StopAt):
        raise InvalidParameterError(f"stop must be a StopAt; got {type(stop).__name__}", parameter="stop")
    given = [name for name in _BUDGETS if name not in applies and getattr(stop, name) is not None]
    if given:
        raise InvalidParameterError(f"stop: {where} {why}; {' and '.join(given)} "
                                    f"{'does' if len(given) == 1 else 'do'} not apply; got "
                                    + ", ".join(f"{name}={getattr(stop, name)!r}" for name in given),
                                    parameter="stop")


def refuse_run(where: str, run: RunOn) -> None:
    """Raise :class:`~workspace_sym.errors.InvalidParameterError` (``parameter="run"``) when ``run`` is not a
    :class:`RunOn` or says anything but ``progress``: ``where`` runs in this process and keeps no boxes.

    Parameters
    ----------
    where : str
        The function's name, for the message.
    run : RunOn
        The caller's ``run``.

    Raises
    ------
    InvalidParameterError
        When ``run`` is not a :class:`RunOn` or sets ``executor``, ``chunk``, ``max_memory``, ``store`` or
        ``resume``.

    Examples
    --------
    >>> refuse_run("grade_answers", RunOn(progress=False))
    >>> try:
    ...     refuse_run("grade_answers", RunOn(chunk=10))
    ... except InvalidParameterError as error:
    ...     print(error)
    run: grade_answers runs in this process and keeps no boxes: only progress applies; got chunk=10
    """
    if not isinstance(run, RunOn):
        raise InvalidParameterError(f"run must be a RunOn; got {type(run).__name__}", parameter="run")
    given = [f"{name}={getattr(run, name)!r}" for name in ("executor", "chunk", "max_memory", "store", "resume")
             if getattr(run, name) is not None]
    if given:
        raise InvalidParameterError(f"run: {where} runs in this process and keeps no boxes: only progress applies; "
                                    f"got {', '.join(given)}", parameter="run")


def deprecated(where: str, old: str, new: str, *, stacklevel: int = 3) -> None:
    """Warn that the keyword ``old`` of ``where`` is deprecated, naming its new spelling ``new``
    (:class:`DeprecationWarning`, shown at the caller of ``where`` with the default ``stacklevel``).

    Parameters
    ----------
    where : str
        The function's name.
    old : str
        The deprecated keyword, without ``=``.
    new : str
        What to pass instead (``"stop=StopAt(max_boxes=...)"``).
    stacklevel : int, default 3
        Passed to :func:`warnings.warn`.

    Warns
    -----
    DeprecationWarning
        Always.

    Examples
    --------
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     deprecated("check_reachable", "max_boxes", "stop=StopAt(max_boxes=...)")
    >>> str(caught[0].message)
    'check_reachable: max_boxes= is deprecated; pass stop=StopAt(max_boxes=...)'
    """
    warnings.warn(f"{where}: {old}= is deprecated; pass {new}", DeprecationWarning, stacklevel=stacklevel)
