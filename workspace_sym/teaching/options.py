"""The options of the teaching functions: which fields of :class:`~workspace_sym.interval.driver.StopAt` apply to
each, and the keywords of earlier releases.

:func:`~workspace_sym.teaching.checks.check_reachable`, :func:`~workspace_sym.teaching.grading.grade_answers` and
:func:`~workspace_sym.teaching.exercises.make_exercises` take ``stop=StopAt(...)`` as the rest of the package does:
``max_boxes`` and ``time_limit`` are budgets of the whole call.  A field that a function cannot honour is refused,
never ignored (``progress`` only shows a bar: none of them has one, and it is not refused).
"""

from __future__ import annotations

import warnings

from ..errors import InvalidParameterError
from ..interval.driver import StopAt

__all__ = ["refuse_stop", "deprecated"]

_BUDGETS = ("max_boxes", "time_limit", "section_boxes")


def refuse_stop(where: str, stop: StopAt, applies: tuple[str, ...], why: str) -> None:
    """Raise :class:`~workspace_sym.errors.InvalidParameterError` (``parameter="stop"``) when ``stop`` is not a
    :class:`StopAt` or sets a budget that ``where`` does not apply (those not in ``applies``); ``why`` says what it
    stops on instead.

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


def deprecated(where: str, old: str, new: str, *, stacklevel: int = 3) -> None:
    """Warn that the keyword ``old`` of ``where`` is deprecated, naming its new spelling ``new``
    (:class:`DeprecationWarning`, shown at the caller of ``where`` with the default ``stacklevel``).

    Examples
    --------
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     deprecated("check_reachable", "max_boxes", "stop=StopAt(max_boxes=...)")
    >>> str(caught[0].message)
    'check_reachable: max_boxes= is deprecated; pass stop=StopAt(max_boxes=...)'
    """
    warnings.warn(f"{where}: {old}= is deprecated; pass {new}", DeprecationWarning, stacklevel=stacklevel)
