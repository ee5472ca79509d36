"""The one driver loop of every paving: breadth-first branch and bisect of a box with any decider.

:func:`subdivide` keeps the undecided boxes as a stack of arrays and hands
chunks of them, with the :class:`Step` that decides and bisects them
(:func:`expand`), to a :class:`~workspace_sym.interval.executor.Runner`:
in line in this process (the default), in local threads, a
``concurrent.futures`` executor or a Dask cluster.  Where the chunks run is the
runner's business; what the loop does with the results (store the decided
boxes, queue the children, check the budget, write checkpoints) is the same
everywhere.  Every box is decided on its own, so however the boxes are cut
into chunks, in whatever order and on whichever machine, a complete run ends
with the same boxes; with the measures summed exactly
(:class:`~workspace_sym.interval.store.ExactSum`) it reports the same counts
and measures to the last bit.

What to stop at (boxes, time) is a :class:`StopAt`, where and how to run
(executor, chunk size, memory, store, checkpoint, progress) a :class:`RunOn`: two small
frozen option objects that the public entry points (``pave``, ``reach``,
``dextrous``) take as they are.

The loop takes the oldest boxes first (breadth-first: the frontier grows wide
and the chunks large) unless memory is bounded (``max_memory``): then it takes
the newest, and the paving proceeds depth-first by chunks, so the frontier
stays about ``depth x chunk`` boxes however large the paving grows.  Decided
boxes go to a :class:`~workspace_sym.interval.store.BoxStore`, in memory or
streamed to disk; a checkpoint file (``resume=``) holds the undecided boxes
and the store's state, so that a run stopped by a time limit, Ctrl-C or a
crash can go on where it stopped.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import tempfile
import time
import warnings
import zipfile
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache, partial
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InvalidParameterError, check_choice
from ..files import write_npz
from ..progress import progress_bar
from . import arith
from .boxes import SIZES, Box, Paving, StoredPaving, bisect, box_measure, box_sizes, check_delta
from .contractor import confirm
from .executor import MIN_CHUNK, Inline, Runner, refuse_result, runner_for
from .fingerprint import Fingerprint, check_fingerprint
from .store import KINDS, BoxStore, parse_memory
from .verdict import INSIDE, OUTSIDE, UNDECIDED, Decider

__all__ = ["StopAt", "RunOn", "RunBudget", "Step", "expand", "initial_boxes", "subdivide", "checked_step",
           "with_legacy_keywords", "refuse_stop", "refuse_run", "deprecated", "refuse_storage", "store_for",
           "write_checkpoint", "read_checkpoint", "paving_of"]

_BYTES_PER_BOX = 16 * 1024       # working memory of a box being decided (Orthoglide certificate: 2.7 KB measured)
_CHECKPOINT_EVERY = 60.0         # seconds between checkpoints of a streamed run
_CHUNK = 200_000                 # the most boxes in one chunk when RunOn does not say


# ----------------------------------------------------------------------------- options
@dataclass(frozen=True, slots=True)
class StopAt:
    """When a run stops: after ``max_boxes`` boxes evaluated in all (a total budget), or ``time_limit`` seconds.
    What is left when it stops is pending.

    Parameters
    ----------
    max_boxes : int or None
        The most boxes evaluated in all, 1 or more (None: no budget).
    time_limit : float or None
        Seconds, positive and finite (None: no limit); checked between chunks of work.
    section_boxes : int or None
        Of :func:`~workspace_sym.serial.api.reach` only: a budget of boxes, 1 or more, for the stages of the
        section of an arm turned by its first joint, the same cells on every machine where a time limit is not.
    progress : bool or None
        The spelling of earlier releases of ``RunOn(progress=...)`` (how a run is shown, not when it stops):
        still taken, with a :class:`DeprecationWarning`; None: not given.

    Raises
    ------
    InvalidParameterError
        For a budget that is not a whole number of at least 1, or a time limit that is not a positive finite
        number (a bool is neither).

    Examples
    --------
    >>> StopAt(time_limit=5)
    StopAt(max_boxes=None, time_limit=5, section_boxes=None, progress=None)
    >>> StopAt(max_boxes=0)
    Traceback (most recent call last):
    ...
    workspace_sym.errors.InvalidParameterError: max_boxes must be at least 1; got 0
    """

    max_boxes: int | None = None
    time_limit: float | None = None
    section_boxes: int | None = None
    progress: bool | None = None

    def __post_init__(self):
        for name, count in (("max_boxes", self.max_boxes), ("section_boxes", self.section_boxes)):
            if count is not None and not (isinstance(count, int) and not isinstance(count, bool) and count >= 1):
                raise InvalidParameterError(f"{name} must be at least 1; got {count!r}", parameter=name)
        t = self.time_limit
        if t is not None and not (isinstance(t, int | float) and not isinstance(t, bool) and math.isfinite(t)
                                  and t > 0):
            raise InvalidParameterError(f"time_limit must be a positive number of seconds; got {t!r}",
                                        parameter="time_limit")
        if self.progress is not None:
            warnings.warn("StopAt(progress=...) is deprecated; pass run=RunOn(progress=...)", DeprecationWarning,
                          stacklevel=3)


@dataclass(frozen=True, slots=True)
class RunOn:
    """Where a run's chunks of boxes go and where its decided boxes stay.

    The boxes, counts and measures are those of a run here.

    Parameters
    ----------
    executor : concurrent.futures.Executor, dask.distributed.Client or None
        Where the chunks run: None (this process), an executor or a Dask client
        (:func:`~workspace_sym.interval.executor.connect`).
    chunk : int or None
        The most boxes in one chunk of work, 1 or more (None: the entry point's own, 200,000 for ``pave``).
    max_memory : int, str or None
        Bytes, or text such as ``"2GB"``: stream the decided boxes to disk and cap the chunks so that the boxes
        being decided fit (the result is a :class:`~workspace_sym.interval.boxes.StoredPaving`).  None: no cap.
    store : path or None
        The directory for the decided boxes (the result is then a StoredPaving).  None: in memory unless
        ``max_memory`` is given, and then ``<resume>.boxes`` with a checkpoint, else a new temporary directory.
    resume : path or None
        A checkpoint, written when the run ends (complete or stopped) and every minute while a streamed run
        goes on, and read to go on from it when it exists.  None: no checkpoint.
    progress : bool or None
        How the run is shown, a progress bar: None, on an interactive output once the run has lasted a second;
        True, always; False, never (:mod:`workspace_sym.progress`).

    Raises
    ------
    InvalidParameterError
        For a ``chunk`` that is not a whole number of at least 1, or a ``max_memory`` that is not a size of
        at least 1 MiB (:func:`~workspace_sym.interval.store.parse_memory`).
    """

    executor: Any = None
    chunk: int | None = None
    max_memory: int | str | None = None
    store: str | os.PathLike | None = None
    resume: str | os.PathLike | None = None
    progress: bool | None = None

    def __post_init__(self):
        if self.chunk is not None and (not isinstance(self.chunk, int) or isinstance(self.chunk, bool)
                                       or self.chunk < 1):
            raise InvalidParameterError(f"chunk must be a whole number of boxes, 1 or more; got {self.chunk!r}",
                                        parameter="chunk")
        if self.max_memory is not None:
            parse_memory(self.max_memory)

    @property
    def here(self) -> bool:
        """Whether everything runs in line in this process, the boxes kept in memory, with no checkpoint.

        Returns
        -------
        bool
            True when ``executor``, ``max_memory``, ``store`` and ``resume`` are all None.
        """
        return self.executor is None and self.max_memory is None and self.store is None and self.resume is None


def with_legacy_keywords(where: str, stop: StopAt, run: RunOn, *, executor=None, progress=None,
                         stacklevel: int = 3) -> tuple[StopAt, RunOn]:
    """``stop`` and ``run`` with the keywords that came before the option objects folded in (``executor=``
    and ``progress=`` into ``run``), each with a :class:`DeprecationWarning` naming its replacement.  For the
    entry points whose documentation used them (``largest_cube``, ``cube_inside``,
    ``no_enclosed_cube``, ``prove_all``); None means not given.

    Parameters
    ----------
    where : str
        The entry point's name, for the warnings and the error.
    stop : StopAt
        Returned as it is.
    run : RunOn
        The run options given.
    executor : object or None
        The earlier ``executor=`` keyword.
    progress : bool or None
        The earlier ``progress=`` keyword.
    stacklevel : int
        The warnings' ``stacklevel`` (default 3: the caller of the entry point).

    Returns
    -------
    tuple
        ``(stop, run)`` with ``run`` carrying the keywords given.

    Raises
    ------
    InvalidParameterError
        When ``executor=`` and ``run.executor`` are two different executors.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     stop, run = with_legacy_keywords("largest_cube", StopAt(), RunOn(), progress=False)
    >>> run.progress, str(caught[0].message)
    (False, 'largest_cube: progress= is deprecated; pass run=RunOn(progress=...)')
    """
    if executor is not None:
        warnings.warn(f"{where}: executor= is deprecated; pass run=RunOn(executor=...)", DeprecationWarning,
                      stacklevel=stacklevel)
        if run.executor is not None and run.executor is not executor:
            raise InvalidParameterError(f"executor: {where} was given two executors (executor= and "
                                        "run=RunOn(executor=)); give run= alone", parameter="executor")
        run = dataclasses.replace(run, executor=executor)
    if progress is not None:
        warnings.warn(f"{where}: progress= is deprecated; pass run=RunOn(progress=...)", DeprecationWarning,
                      stacklevel=stacklevel)
        run = dataclasses.replace(run, progress=progress)
    return stop, run


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


def refuse_storage(where: str, run: RunOn, *, why: str = "keeps no boxes", supported: str = "") -> None:
    """Refuse ``max_memory``, ``store`` and ``resume`` for an entry point that keeps no boxes (a search that
    stops at its first counterexample) or keeps them in memory (``why``): its ``run`` carries an executor and a
    chunk size only.  The error names the options given with their values, and what takes them
    (``supported``).

    Parameters
    ----------
    where : str
        The entry point's name, for the error.
    run : RunOn
        The run options given.
    why : str
        Why the options do not apply (default ``"keeps no boxes"``).
    supported : str
        What takes them instead, named in the error (default ``""``: not named).

    Raises
    ------
    InvalidParameterError
        ``parameter="run"``, when ``run`` has ``max_memory``, ``store`` or ``resume``.

    Examples
    --------
    >>> try:
    ...     refuse_storage("prove_all", RunOn(resume="run.npz"))
    ... except InvalidParameterError as error:
    ...     print(str(error).split("; ")[-1], error.parameter)
    got resume='run.npz' run
    """
    given = [f"{name}={getattr(run, name)!r}" for name in ("max_memory", "store", "resume")
             if getattr(run, name) is not None]
    if given:
        raise InvalidParameterError(f"run: {where} {why}; max_memory, store and resume do not apply; got "
                                    f"{', '.join(given)}" + (f"; they apply to {supported}" if supported else ""),
                                    parameter="run")


class RunBudget:
    """The clock, stopping rules and progress bar of a running branch and bisect (:func:`subdivide`, ``reach``).

    The clock starts when it is made.  ``stop_reason(evaluated)`` is empty
    while the run may go on, else why it stops (the time limit or the box
    budget); ``show(share, evaluated)`` moves the bar to the share of the task
    box decided so far.  A run of several phases (``reach``: a section paved,
    then its task boxes classified by :func:`subdivide`) hands one budget to
    each phase in turn: ``spent`` is the count of boxes the earlier phases
    evaluated, counted against ``max_boxes`` and shown on the bar.

    Parameters
    ----------
    stop : StopAt
        The budget and time limit.
    label : str
        The bar's label.
    progress : bool or None
        Whether the bar draws (:class:`RunOn`'s ``progress``); None: ``stop.progress`` (the earlier spelling),
        and when that is None too, on an interactive output once the run has lasted a second.
    """

    def __init__(self, stop: StopAt, label: str, progress: bool | None = None):
        self.max_boxes, self.time_limit, self.section_boxes = stop.max_boxes, stop.time_limit, stop.section_boxes
        self.spent = 0
        self.start = time.perf_counter()
        shown = progress if progress is not None else stop.progress      # RunOn's, else the earlier spelling's
        self.bar = progress_bar(shown, total=100.0, desc=label, unit="%",
                                bar_format="{desc}: {percentage:5.1f}% of the box decided{postfix} |{bar}| "
                                           "[{elapsed}]")

    @property
    def seconds(self) -> float:
        """Seconds since the budget was made (wall clock).

        Returns
        -------
        float
            The elapsed time.
        """
        return time.perf_counter() - self.start

    @property
    def showing(self) -> bool:
        """Whether the bar draws (callers skip computing what it would show otherwise).

        Returns
        -------
        bool
            True when the bar is enabled.
        """
        return not self.bar.disable

    def stop_reason(self, evaluated: int, *, ahead: float = 0.0) -> str:
        """Why the run stops now, or ``""`` while it may go on.

        Parameters
        ----------
        evaluated : int
            Boxes this phase has evaluated (added to ``spent`` against ``max_boxes``).
        ahead : float
            Seconds the next step is expected to take; the run stops before a step that would end past the time
            limit (default 0).

        Returns
        -------
        str
            ``"time limit of T s reached"``, ``"budget of N boxes reached"``, or ``""``.
        """
        elapsed = self.seconds
        if self.time_limit is not None and elapsed + ahead > self.time_limit:
            return f"time limit of {self.time_limit} s reached"
        if self.max_boxes is not None and self.spent + evaluated >= self.max_boxes:
            return f"budget of {self.max_boxes} boxes reached"
        return ""

    def show(self, share: float, evaluated: int) -> None:
        """The bar at ``share`` (0 to 1) of the task box decided, after ``evaluated`` boxes.

        Parameters
        ----------
        share : float
            The share of the task box decided, clipped to 0 to 1.
        evaluated : int
            Boxes this phase has evaluated (shown with ``spent`` added).
        """
        if not self.showing:
            return
        self.bar.set_postfix_str(f"{self.spent + evaluated} boxes", refresh=False)
        self.bar.update(100.0 * min(1.0, max(0.0, share)) - self.bar.n)

    def close(self) -> None:
        """Close the bar (the caller that made the budget does, once every phase is done)."""
        self.bar.close()


# ----------------------------------------------------------------------------- the unit of work
def initial_boxes(box: Box, delta: float, size: str, presplit: int) -> np.ndarray:
    """The box bisected, unevaluated, into about ``presplit`` boxes larger than ``delta`` (see :func:`subdivide`).

    A fresh array each call, from a cache: the same box, delta and size give the same boxes, and bisecting them
    costs about as much as deciding them (nine generations of numpy calls for 512 boxes).

    Parameters
    ----------
    box : Box
        The box to pave.
    delta : float
        No box is bisected unless every box of its generation is larger than ``delta``.
    size : str
        ``"diameter"`` or ``"width"``: how a box's size is measured.
    presplit : int
        Bisect (each generation doubling the boxes) while there are fewer boxes than this.

    Returns
    -------
    numpy.ndarray
        ``(N, n, 2)`` boxes covering ``box``; ``box`` alone when ``presplit`` is at most 1 or ``box`` is not
        larger than ``delta``.
    """
    return _initial_boxes(box.lower, box.upper, float(delta), size, presplit).copy()


@lru_cache(maxsize=64)
def _initial_boxes(lower: tuple, upper: tuple, delta: float, size: str, presplit: int) -> np.ndarray:
    work = np.array([lower, upper], dtype=float).T[None, :, :].copy()
    while len(work) < presplit and (box_sizes(work, size) > delta).all():
        work, thin = bisect(work)
        if len(thin):
            return np.concatenate([work, thin])
    return work


def expand(batch: np.ndarray, decide: Decider, separate, delta: float, size: str, sized_before_cut: bool = False):
    """One step of the branch and bisect on a batch: ``(inner, boundary, outer, children)`` arrays.

    Each box is decided on its own, so the union of the results does not
    depend on how the boxes are batched: this is the unit of work a runner
    sends to other processes.  With ``separate``, what is left undecided of a
    box after its contraction is bisected when it is itself larger than
    ``delta``, or, with ``sized_before_cut``, when the box was larger than
    ``delta`` before the contraction (:func:`subdivide`).

    Parameters
    ----------
    batch : numpy.ndarray
        ``(N, n, 2)`` boxes.
    decide : Decider
        The verdicts.
    separate : callable or None
        The contraction (a :class:`~workspace_sym.interval.contractor.Separation` of undecided boxes), or None.
    delta : float
        Undecided boxes of size at most ``delta`` are boundary boxes; larger ones are bisected.
    size : str
        ``"diameter"`` or ``"width"``: how a box's size is measured.
    sized_before_cut : bool
        Size the remainder of a contracted box by the box before the contraction (default False).

    Returns
    -------
    inner : numpy.ndarray
        ``(M, n, 2)`` boxes (or contracted slices) proved inside.
    boundary : numpy.ndarray
        Undecided boxes not to be bisected: those of size at most ``delta``, and those one float wide.
    outer : numpy.ndarray
        Boxes (or slices) proved outside.
    children : numpy.ndarray
        The halves of the other undecided boxes.
    """
    codes = decide(batch)
    und = batch[codes == UNDECIDED]
    inner, outer = [batch[codes == INSIDE]], [batch[codes == OUTSIDE]]
    if separate is not None:
        arrived_large = box_sizes(und, size) > delta
        cut = separate(und)
        # The contraction proposes slices; each is declared only when the forward evaluation
        # that decides every other box proves it too, whole or piece by piece.  The rest stays undecided.
        proved_in, proved_out = confirm(decide, cut.inner, cut.outer)
        inner.append(cut.inner[proved_in])
        outer.append(cut.outer[proved_out])
        und = np.concatenate([cut.kept, cut.inner[~proved_in], cut.outer[~proved_out]])
        if sized_before_cut:
            small = ~arrived_large[np.concatenate([cut.kept_from, cut.inner_from[~proved_in],
                                                   cut.outer_from[~proved_out]])]
        else:
            small = box_sizes(und, size) <= delta
    else:
        small = box_sizes(und, size) <= delta
    children, thin = bisect(und[~small])
    return np.concatenate(inner), np.concatenate([und[small], thin]), np.concatenate(outer), children


@dataclass(frozen=True)
class Step:
    """One branch-and-bisect step on a chunk of boxes (picklable: it travels to the workers once).

    Calling it on ``(N, n, 2)`` boxes runs :func:`expand` and returns its four arrays as contiguous float64.

    Parameters
    ----------
    decide, separate, delta, size, sized_before_cut
        As for :func:`expand`.
    """

    decide: object
    separate: object
    delta: float
    size: str
    sized_before_cut: bool = False

    def __call__(self, boxes):
        # plain float arrays only: what a worker sends back is checked by checked_step on the driver
        return tuple(np.ascontiguousarray(a, dtype=float) for a in
                     expand(boxes, self.decide, self.separate, self.delta, self.size, self.sized_before_cut))


def _hull(boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lowest lower and highest upper bound of ``boxes`` per variable (column by column: a reduction along
    the first axis of the strided array is several times slower)."""
    n = boxes.shape[1]
    return (np.array([boxes[:, k, 0].min() for k in range(n)]), np.array([boxes[:, k, 1].max() for k in range(n)]))


def _checked_boxes(name: str, value, n: int, hull: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """``value`` if it is a plain float64 ``(N, n, 2)`` array of finite boxes inside ``hull`` (that of the chunk)."""
    if type(value) is not np.ndarray:
        refuse_result(f"{name} that is not a numpy array", type(value).__name__)
    if value.dtype != np.float64 or value.ndim != 3 or value.shape[1:] != (n, 2):
        refuse_result(f"{name} that is not a float64 array of shape (N, {n}, 2)", f"{value.dtype} {value.shape}")
    if not len(value):
        return value
    if not np.isfinite(value).all() or (value[:, :, 0] > value[:, :, 1]).any():
        refuse_result(f"{name} with non-finite or inverted bounds", f"{int((~np.isfinite(value)).sum())} non-finite")
    lo, hi = _hull(value)
    if (lo < hull[0]).any() or (hi > hull[1]).any():
        refuse_result(f"{name} outside the boxes it was sent", f"{len(value)} boxes")
    return value


def checked_step(result, chunk: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A step's result ``(inner, boundary, outer, children)`` as sent back for ``chunk``, checked before it is
    stored: plain float arrays of the chunk's dimension, finite, ordered, inside the chunk's hull.  It cannot
    check the verdicts themselves (that would be doing the work again): an untrusted cluster stays untrusted.

    Parameters
    ----------
    result : object
        What the worker sent back.
    chunk : numpy.ndarray
        The ``(N, n, 2)`` boxes it was sent.

    Returns
    -------
    tuple of numpy.ndarray
        ``(inner, boundary, outer, children)``, the arrays of ``result`` as they are.

    Raises
    ------
    WorkerResultError
        For anything else (:func:`~workspace_sym.interval.executor.refuse_result`).
    """
    if type(result) not in (tuple, list) or len(result) != 4:
        refuse_result("something other than 4 arrays (inner, boundary, outer, children)", type(result).__name__)
    n, hull = chunk.shape[1], _hull(chunk)
    inner, boundary, outer, children = (_checked_boxes(name, value, n, hull) for name, value in
                                        zip(("inner boxes", "boundary boxes", "outer boxes", "children"), result))
    return inner, boundary, outer, children


# ----------------------------------------------------------------------------- checkpoints
def _describe(fn) -> Any:
    """What a decider (or a separator) is, for the fingerprint of a checkpoint: a decider may say it itself, with a
    ``describe()`` method returning a text or a mapping of named fields (``reach``'s classification of task boxes
    names its whole problem: robot, limits, pose, method, tuning, the section's cells)."""
    if fn is None:
        return None
    if callable(getattr(fn, "describe", None)):
        described = fn.describe()
        return dict(described) if isinstance(described, Mapping) else str(described)
    if isinstance(fn, partial):
        keywords = ", ".join(f"{k}={v!r}" for k, v in sorted(fn.keywords.items()))
        return f"{_describe(fn.func)}({keywords})"
    if hasattr(fn, "constraints") and hasattr(fn, "backend"):
        digits = getattr(fn, "digits", None) if fn.backend == "mpmath" else None    # the precision of the reference
        return {"constraints": [c.g for c in fn.constraints], "strict": [c.strict for c in fn.constraints],
                "backend": fn.backend, "digits": digits}
    return f"{getattr(fn, '__module__', '')}.{getattr(fn, '__qualname__', type(fn).__qualname__)}"


def _fingerprint(step: Step, box: Box, constraints, backend) -> Fingerprint:
    """The fingerprint of a run of :func:`subdivide`: the box, every option that changes boxes, and what the
    decider and the separator say they are (a decider's named fields enter under their own names)."""
    decider = _describe(step.decide)
    named = decider if isinstance(decider, dict) else {"decider": decider}
    return Fingerprint({"variables": [str(v) for v in box.variables], "lower": list(box.lower),
                        "upper": list(box.upper),
                        "constraints": [(c.g, c.strict) for c in constraints], **named,
                        "separator": _describe(step.separate), "sized_before_cut": step.sized_before_cut,
                        "delta": step.delta, "size": step.size, "backend": backend})


def write_checkpoint(path: Path, meta: dict, pending: np.ndarray, store: BoxStore, extra: dict | None = None) -> None:
    """Write the checkpoint of a run at ``path`` (atomically): ``meta`` (its ``fingerprint``, a
    :class:`~workspace_sym.interval.fingerprint.Fingerprint`, ``evaluated``, ``seconds``), the ``pending``
    boxes, the store's state (its boxes too when in memory) and ``extra`` arrays a loop carries with its pending
    boxes (``reach``'s pairs: the joint boxes and their owners); the SHA-256 of every array goes with them.

    Parameters
    ----------
    path : pathlib.Path
        The checkpoint file (an ``.npz`` archive), written under ``<path>.tmp`` and renamed.
    meta : dict
        The run's record, JSON-ready but for ``fingerprint``.
    pending : numpy.ndarray
        The ``(N, n, 2)`` boxes not yet decided.
    store : BoxStore
        The decided boxes (a store on disk is flushed first).
    extra : dict or None
        More arrays by name (None: none).
    """
    arrays: dict[str, Any] = {"pending": pending, **(extra or {})}
    if store.directory is None:
        arrays.update({k: store.arrays(k) for k in KINDS})
    else:
        store.flush()
    meta = {**meta, "fingerprint": meta["fingerprint"].to_json(), "store": store.state(),
            "arrays": {k: _array_digest(v) for k, v in arrays.items()}}
    write_npz(path, meta=np.array(json.dumps(meta)), **arrays)


def _array_digest(array: np.ndarray) -> str:
    data = np.ascontiguousarray(array)
    return hashlib.sha256(f"{data.dtype.str} {data.shape}".encode() + data.tobytes()).hexdigest()


def read_checkpoint(path: Path, fingerprint: Fingerprint):
    """``(meta, arrays)`` of the checkpoint at ``path``, refused (``resume``) unless it is one of the run that
    ``fingerprint`` describes (:func:`~workspace_sym.interval.fingerprint.check_fingerprint`, naming the fields
    that differ), whole (every array as written) and with its store (:meth:`BoxStore.restore` checks that).

    Parameters
    ----------
    path : pathlib.Path
        The checkpoint file.
    fingerprint : Fingerprint
        The fingerprint of this run.

    Returns
    -------
    meta : dict
        The run's record, as :func:`write_checkpoint` wrote it.
    arrays : dict
        The arrays by name: ``pending``, the store's classes when it was in memory, and any ``extra``.

    Raises
    ------
    InvalidParameterError
        ``parameter="resume"``: the file is not a checkpoint, is of another version or another run, or its
        arrays are not those it recorded.
    """
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            if not isinstance(meta, dict):
                raise ValueError("no record of the run")
            arrays = {k: data[k] for k in data.files if k != "meta"}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
        raise InvalidParameterError(f"resume: {str(path)!r} is not a checkpoint of a paving ({exc})",
                                    parameter="resume") from None
    check_fingerprint(meta.get("fingerprint"), fingerprint, what=f"{str(path)!r} is the checkpoint")
    listed = meta.get("arrays")
    if not isinstance(listed, dict) or set(listed) != set(arrays) or \
            any(listed[k] != _array_digest(v) for k, v in arrays.items()):
        raise InvalidParameterError(f"resume: {str(path)!r} is damaged (its arrays are not those it recorded); "
                                    "start the run again", parameter="resume")
    return meta, arrays


# ----------------------------------------------------------------------------- the loop
def _take(stack: deque, size: int, depth_first: bool) -> np.ndarray:
    """Up to ``size`` boxes off the stack: the newest (depth-first) or the oldest (breadth-first)."""
    if depth_first:
        top = stack.pop()
        if len(top) > size:
            stack.append(top[:-size])
            return top[-size:]
        return top
    first = stack.popleft()
    if len(first) > size:
        stack.appendleft(first[size:])
        return first[:size]
    return first


def store_for(n: int, run: RunOn, problem: str = "") -> tuple[BoxStore, int | None]:
    """Where the decided boxes of a run of dimension ``n`` go (in memory, or ``.npy`` parts when ``run`` asks
    for ``max_memory`` or a ``store``, naming ``problem``, the digest of the run's fingerprint), and the memory
    budget in bytes (None: unbounded).

    Parameters
    ----------
    n : int
        Number of variables.
    run : RunOn
        The run options.
    problem : str
        The digest of the run's fingerprint (default ``""``).

    Returns
    -------
    store : BoxStore
        A new store, in memory or on disk.
    budget : int or None
        ``run.max_memory`` in bytes.

    Raises
    ------
    InvalidParameterError
        ``parameter="store"``, when the directory already holds parts of boxes.
    """
    if run.max_memory is None and run.store is None:
        return BoxStore(n), None
    budget = None if run.max_memory is None else parse_memory(run.max_memory)
    if run.store is None:
        store = (Path(str(run.resume) + ".boxes") if run.resume is not None
                 else Path(tempfile.mkdtemp(prefix="workspace_sym-paving-")))
    else:
        store = Path(run.store)
    if store.exists() and any(store.glob("*/part-*.npy")):
        raise InvalidParameterError(f"store directory {str(store)!r} already holds boxes of another run; give an "
                                    "empty directory, or resume= the checkpoint of that run", parameter="store")
    flush = 64 * 2**20 if budget is None else max(2**20, min(64 * 2**20, budget // 32))
    return BoxStore(n, store, flush_bytes=flush, problem=problem), budget


@arith.nearest_rounding
def subdivide(decide: Decider, box: Box, *, delta: float, size: str = "diameter", stop: StopAt | RunBudget = StopAt(),
              run: RunOn = RunOn(), constraints=(), backend: str = "numpy", label: str = "paving",
              presplit: int = 512, separate=None, sized_before_cut: bool = False) -> Paving:
    """Branch and bisect with any box classifier: the loop behind :func:`~workspace_sym.interval.paving.pave`
    and the Orthoglide's dextrous workspace.

    ``decide(boxes)`` (a :class:`~workspace_sym.interval.verdict.Decider`)
    takes an ``(N, n, 2)`` array and returns codes: 1 for a box proved inside,
    -1 proved outside, 0 undecided.  Undecided boxes larger than ``delta`` are
    bisected along their longest edge; the others become boundary boxes.  A
    budget, time limit or Ctrl-C (``stop``) returns the unexamined boxes as
    pending.

    The first generations are bisected without being evaluated until there are
    ``presplit`` boxes (none smaller than ``delta``): one numpy call costs about
    the same for one box or five hundred, and a box decided at a coarse level
    has its children decided too, so only the number of boxes changes (the
    measures of the Rybak benchmark are identical with and without; 1.3x to
    1.8x faster).  ``presplit=0`` evaluates from the initial box.

    ``separate(boxes)``, optional, runs on the undecided boxes and returns a
    :class:`~workspace_sym.interval.contractor.Separation`: inner and outer
    slices and the undecided remainder.  A slice is declared inner (outer)
    only when ``decide`` also proves it so, on the whole slice or on each of
    its pieces (:func:`~workspace_sym.interval.contractor.confirm`: near a
    corner of the set, different constraints fail on different parts of a
    slice); the remainder and the slices ``decide`` does not confirm go on to
    the size test and the bisection.  So every verdict of the paving comes
    from ``decide``.  The size test is on what the contraction left of a box,
    or, with ``sized_before_cut`` (``pave(contract=True)``), on the box as
    the bisection made it: the remainder of a box larger than ``delta`` is
    bisected even when it is no longer larger, so that each boundary box is
    the contracted part of a box of at most ``delta`` (on Rybak's robot, 0.8
    times the boundary area of the first rule at every ``delta``, for 1.2
    times its boxes; the Orthoglide's shaving of the last level keeps the
    first).

    ``stop`` is a :class:`StopAt`, or the :class:`RunBudget` of a run of
    several phases that this paving continues (its clock, bar and the boxes
    its earlier phases ``spent`` count; the caller closes it).

    ``run`` says where the chunks go (:class:`RunOn`): by default in line,
    here; ``decide`` and ``separate`` must pickle when the executor is
    another process (the deciders of ``pave`` and of the Orthoglide do).
    ``constraints`` and ``backend`` describe the decider in the result (and
    in a checkpoint's fingerprint).

    Parameters
    ----------
    decide : Decider
        The verdicts (see above).
    box : Box
        The box to pave.
    delta : float
        Positive: undecided boxes of size at most ``delta`` are boundary boxes.
    size : str
        How a box's size is measured: ``"diameter"`` (default, its diagonal) or ``"width"`` (its widest edge).
    stop : StopAt or RunBudget
        When to stop (see above; default: never).
    run : RunOn
        Where to run (see above; default: here).
    constraints : tuple
        The constraints (:class:`~workspace_sym.interval.paving.Constraint`) that ``decide`` tests, for the
        result and the fingerprint (default: none).
    backend : str
        The arithmetic that ``decide`` uses, for the result and the fingerprint (default ``"numpy"``).
    label : str
        The progress bar's label (default ``"paving"``).
    presplit : int
        Boxes bisected before the first evaluation (default 512; see above).
    separate : callable or None
        The contraction (see above); None (default): none.
    sized_before_cut : bool
        Size the remainder of a contracted box by the box before the contraction (default False; see above).

    Returns
    -------
    Paving
        Or a :class:`~workspace_sym.interval.boxes.StoredPaving` when the boxes are on disk.

    Raises
    ------
    InvalidParameterError
        For a ``delta`` that is not a positive finite number; a checkpoint (``resume``) of another run,
        version or store, or damaged; a ``store`` directory that already holds boxes.
    UnknownNameError
        For a ``size`` other than ``"diameter"`` and ``"width"``.
    WorkerResultError
        When a worker of another process sends back something other than a step's result.
    """
    check_delta(delta)
    check_choice("size", size, SIZES)
    step = Step(decide, separate, float(delta), size, bool(sized_before_cut))
    n = len(box.variables)
    path = None if run.resume is None else Path(run.resume)
    # The fingerprint names the problem in a checkpoint and a store on disk (it prints every constraint: only a
    # run that writes one makes it).
    kept = path is not None or run.max_memory is not None or run.store is not None
    fingerprint = _fingerprint(step, box, constraints, backend) if kept else Fingerprint()
    evaluated, seconds_before = 0, 0.0
    if path is not None and path.exists():
        meta, arrays = read_checkpoint(path, fingerprint)
        keeper = BoxStore.restore(n, meta["store"], arrays, problem=fingerprint.digest)
        budget = None if run.max_memory is None else parse_memory(run.max_memory)
        stack = deque([arrays["pending"]] if len(arrays["pending"]) else [])
        evaluated, seconds_before = int(meta["evaluated"]), float(meta["seconds"])
    else:
        keeper, budget = store_for(n, run, fingerprint.digest)
        stack = deque([initial_boxes(box, delta, size, presplit)])
    own_clock = isinstance(stop, StopAt)
    clock = RunBudget(stop, label, run.progress) if isinstance(stop, StopAt) else stop
    # in line the step's results stay in this process: expand itself, without the copies for a worker's reply
    runner: Runner = (Inline(partial(expand, decide=decide, separate=separate, delta=float(delta), size=size,
                                     sized_before_cut=bool(sized_before_cut)))
                      if run.here else runner_for(run.executor, step))
    smallest = 1 if run.here else MIN_CHUNK
    chunk = _CHUNK if run.chunk is None else run.chunk
    largest = chunk if budget is None else max(MIN_CHUNK, min(chunk, budget // (2 * runner.slots * _BYTES_PER_BOX)))
    max_boxes = None if clock.max_boxes is None else clock.max_boxes - clock.spent
    inflight: dict = {}
    reason, last_checkpoint = "", time.perf_counter()

    def pending():
        parts = [*stack, *inflight.values()]
        return np.concatenate(parts) if parts else np.empty((0, n, 2))

    def checkpoint():
        assert path is not None
        write_checkpoint(path, {"fingerprint": fingerprint, "evaluated": evaluated,
                                 "seconds": seconds_before + clock.seconds}, pending(), keeper)

    try:
        while stack or inflight:
            reason = clock.stop_reason(evaluated)
            if reason:
                break
            queued = sum(len(b) for b in inflight.values())
            frontier = sum(len(b) for b in stack)
            size_now = max(smallest, min(largest, math.ceil(frontier / runner.slots)))
            while stack and len(inflight) < runner.slots:
                room = size_now if max_boxes is None else min(size_now, max_boxes - evaluated - queued)
                if room <= 0:
                    break
                boxes = _take(stack, room, depth_first=budget is not None)
                inflight[runner.submit(boxes)] = boxes
                queued += len(boxes)
            if not inflight:
                break
            for future in runner.wait(inflight, timeout=0.25):
                # the chunk leaves `inflight` (what stays pending) only once its result is in hand and checked
                inner, boundary, outer, children = runner.result(future, inflight[future], checked_step)
                evaluated += len(inflight.pop(future))
                for kind, boxes in zip(KINDS, (inner, boundary, outer)):
                    keeper.add(kind, boxes)
                if len(children):
                    stack.append(children)
            if clock.showing:                 # everything not pending is decided
                clock.show(1.0 - box_measure(pending()) / box.measure if box.measure > 0 else 1.0, evaluated)
            if path is not None and keeper.directory is not None and \
                    time.perf_counter() - last_checkpoint > _CHECKPOINT_EVERY:
                checkpoint()
                last_checkpoint = time.perf_counter()
    except KeyboardInterrupt:
        reason = "interrupted"
    finally:
        runner.cancel(list(inflight))
        runner.close()
        if own_clock:
            clock.close()
    left = pending()
    if path is not None:
        checkpoint()
    keeper.flush()
    return paving_of(keeper, variables=box.variables, box=box, constraints=tuple(constraints), delta=float(delta),
                     backend=backend, size=size, pending=left, seconds=seconds_before + clock.seconds,
                     complete=not len(left), evaluated=evaluated, stop_reason=reason if len(left) else "",
                     contract=separate is not None)


def paving_of(keeper: BoxStore, **common) -> Paving:
    """The result of a run whose decided boxes are in ``keeper``: a :class:`Paving`, or a
    :class:`StoredPaving` when they are on disk; ``common`` are the other fields of a Paving.

    Parameters
    ----------
    keeper : BoxStore
        The decided boxes (flushed, when on disk).
    **common
        The fields of a Paving other than ``inner``, ``boundary`` and ``outer``.

    Returns
    -------
    Paving
        A Paving holding the boxes, or a StoredPaving naming the store's files, counts and exact sums.
    """
    empty = np.empty((0, keeper.n, 2))
    if keeper.directory is None:
        return Paving(inner=keeper.arrays("inner"), boundary=keeper.arrays("boundary"),
                      outer=keeper.arrays("outer"), **common)
    return StoredPaving(inner=empty, boundary=empty, outer=empty, **common, store=str(keeper.directory),
                        stored_counts=dict(keeper.counts), stored_sums={k: str(s) for k, s in keeper.sums.items()},
                        stored_bounds={"down": {k: str(s) for k, s in keeper.sums_down.items()},
                                       "up": {k: str(s) for k, s in keeper.sums_up.items()}},
                        files={k: keeper.files(k) for k in KINDS})
