"""Where the boxes of a paving are decided: local threads, a ``concurrent.futures`` executor, or a Dask cluster.

The unit of work is a **chunk of boxes with its step**: :class:`Step` holds
the decider (and the contraction, for ``pave(..., contract=True)``), and one
call decides a chunk, bisects what is undecided and returns the inner,
boundary and outer boxes and the children (:func:`~workspace_sym.interval.paving.expand`).
Every box is decided on its own, so however the boxes are cut into chunks,
in whatever order and on whichever machine, a complete run ends with the
same boxes; with the measures summed exactly
(:class:`~workspace_sym.interval.store.ExactSum`) it reports the same
counts and measures to the last bit.

What crosses the network: the step once to the scheduler, as a task that
returns it, and from there to each worker that runs a chunk (a constraint
decider pickles as its SymPy constraints and is compiled once on each
worker, see ``_Decider.__reduce__``; if every worker holding it dies, the
task runs again), then per
chunk its boxes (``48 N`` bytes for ``N`` boxes in 3D) one way and the
decided boxes and children the other way.  A ``concurrent.futures``
executor has no such task: the step goes with every chunk, still as its SymPy
recipe, compiled once per process by the same cache.

The driver (:func:`run_paving`) keeps the undecided boxes as a stack of
arrays.  It takes the oldest (breadth-first, as the local loop does: the
frontier grows wide and the chunks large) unless memory is bounded
(``max_memory``): then it takes the newest, and the paving proceeds
depth-first by chunks, so the frontier stays about ``depth x chunk`` boxes
however large the paving grows.  Decided boxes go to a
:class:`~workspace_sym.interval.store.BoxStore`, in memory or streamed to
disk; a checkpoint file (``resume=``) holds the undecided boxes and the
store's state, so that a run stopped by a time limit, Ctrl-C or a crash can
go on where it stopped.
"""

from __future__ import annotations

import concurrent.futures
import ctypes
import ctypes.util
import json
import math
import os
import tempfile
import time
from collections import deque
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cache, cached_property, partial
from pathlib import Path
from typing import Any

import numpy as np
import sympy as sp

from ..errors import InvalidParameterError, MissingExtraError, WorkerResultError, WorkspaceError
from ..numbers import fmt_bracket
from . import arith
from .paving import Box, Paving, RunBudget, box_measure, expand, initial_boxes
from .store import KINDS, BoxStore, ExactSum, measures_of, parse_memory
from .verdict import VERDICTS, Decider

__all__ = ["Step", "StoredPaving", "connect", "map_codes", "run_paving", "tune_malloc", "MissingExtraError"]

_EXTRA = "pip install 'workspace_sym[distributed]'"
_BYTES_PER_BOX = 16 * 1024       # working memory of a box being decided (Orthoglide certificate: 2.7 KB measured)
_MIN_CHUNK = 1024                # below this a chunk costs more in overhead than in work
_CHECKPOINT_EVERY = 60.0         # seconds between checkpoints of a streamed run


def _distributed():
    try:
        import distributed
    except ImportError:
        raise MissingExtraError(f"a Dask scheduler needs dask.distributed, which is not installed: {_EXTRA}",
                                parameter="scheduler") from None
    return distributed


# ----------------------------------------------------------------------------- the unit of work
@dataclass(frozen=True)
class Step:
    """One branch-and-bisect step on a chunk of boxes (picklable: it travels to the workers once)."""

    decide: object
    separate: object
    delta: float
    size: str

    def __call__(self, boxes):
        # plain float arrays only: what a worker sends back is checked by _checked_step on the driver
        return tuple(np.ascontiguousarray(a, dtype=float) for a in
                     expand(boxes, self.decide, self.separate, self.delta, self.size))


@arith.nearest_rounding
def _call(fn, boxes):
    """The entry point in this process's threads: every proof runs in round-to-nearest."""
    return fn(boxes)


@cache
def tune_malloc() -> bool:
    """Let glibc keep freed memory for reuse in this process (True when it could be asked); done in workers.

    Dask's nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``, which
    also fixes glibc's mmap threshold at 128 KiB: every temporary array of a
    chunk is then mapped, zero-filled and unmapped, and the Orthoglide's
    certificate ran 3 to 8 times slower in a worker than here (BENCHMARKS.md).
    Arrays up to 32 MiB are served from the heap again, and only more than
    128 MiB free at its top is returned to the system.  The local threads
    gain as much (BENCHMARKS.md); calling it here is left to the user, since
    it changes the whole process's allocator.
    """
    name = ctypes.util.find_library("c")
    libc = ctypes.CDLL(name) if name else None
    mallopt = getattr(libc, "mallopt", None)
    if mallopt is None:
        return False
    m_trim_threshold, m_mmap_threshold = -1, -3
    return bool(mallopt(m_mmap_threshold, 32 * 2**20)) and bool(mallopt(m_trim_threshold, 128 * 2**20))


def _call_in_worker(fn, boxes):
    """The entry point in another process: its allocator tuned once, then as :func:`_call`."""
    tune_malloc()
    return _call(fn, boxes)


def _refuse(what: str, got: str):
    raise WorkerResultError(f"executor: a worker returned {what}; got {got} (a worker of another version or an "
                            "untrusted cluster?)", parameter="executor")


def _hull(boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lowest lower and highest upper bound of ``boxes`` per variable (column by column: a reduction along
    the first axis of the strided array is several times slower)."""
    n = boxes.shape[1]
    return (np.array([boxes[:, k, 0].min() for k in range(n)]), np.array([boxes[:, k, 1].max() for k in range(n)]))


def _checked_boxes(name: str, value, n: int, hull: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """``value`` if it is a plain float64 ``(N, n, 2)`` array of finite boxes inside ``hull`` (that of the chunk)."""
    if type(value) is not np.ndarray:
        _refuse(f"{name} that is not a numpy array", type(value).__name__)
    if value.dtype != np.float64 or value.ndim != 3 or value.shape[1:] != (n, 2):
        _refuse(f"{name} that is not a float64 array of shape (N, {n}, 2)", f"{value.dtype} {value.shape}")
    if not len(value):
        return value
    if not np.isfinite(value).all() or (value[:, :, 0] > value[:, :, 1]).any():
        _refuse(f"{name} with non-finite or inverted bounds", f"{int((~np.isfinite(value)).sum())} non-finite")
    lo, hi = _hull(value)
    if (lo < hull[0]).any() or (hi > hull[1]).any():
        _refuse(f"{name} outside the boxes it was sent", f"{len(value)} boxes")
    return value


def _checked_step(result, chunk: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A step's result ``(inner, boundary, outer, children)`` as sent back for ``chunk``, checked before it is
    stored: plain float arrays of the chunk's dimension, finite, ordered, inside the chunk's hull.  It cannot
    check the verdicts themselves (that would be doing the work again): an untrusted cluster stays untrusted."""
    if type(result) not in (tuple, list) or len(result) != 4:
        _refuse("something other than 4 arrays (inner, boundary, outer, children)", type(result).__name__)
    n, hull = chunk.shape[1], _hull(chunk)
    inner, boundary, outer, children = (_checked_boxes(name, value, n, hull) for name, value in
                                        zip(("inner boxes", "boundary boxes", "outer boxes", "children"), result))
    return inner, boundary, outer, children


def _checked_codes(codes, chunk: np.ndarray) -> np.ndarray:
    """A decider's codes for ``chunk`` as sent back: one integer 1, 0 or -1 a box."""
    if type(codes) is not np.ndarray:
        _refuse("codes that are not a numpy array", type(codes).__name__)
    if codes.dtype.kind not in "iuf" or codes.shape != (len(chunk),):
        _refuse(f"codes that are not {len(chunk)} numbers", f"{codes.dtype} {codes.shape}")
    if not np.isin(codes, VERDICTS).all():
        _refuse("codes other than 1, 0 and -1", repr(sorted(set(np.unique(codes).tolist()) - set(VERDICTS))[:5]))
    return codes


def _itself(value):
    return value


def _is_dask_client(executor) -> bool:
    return type(executor).__name__ == "Client" and type(executor).__module__.startswith("distributed")


class _Runner:
    """``fn`` applied to chunks of boxes somewhere, with futures: the seam every paving goes through."""

    slots = 1
    local = False                   # results computed in this process's threads: never unpickled, not checked

    def submit(self, boxes):
        raise NotImplementedError

    def result(self, future, boxes: np.ndarray, check):
        """The result of ``future`` (the task on ``boxes``), checked by ``check`` when it came from elsewhere."""
        value = future.result()
        return value if self.local else check(value, boxes)

    def wait(self, futures, timeout: float) -> list:
        done, _ = concurrent.futures.wait(futures, timeout=timeout, return_when=concurrent.futures.FIRST_COMPLETED)
        return list(done)

    def cancel(self, futures) -> None:
        for f in futures:
            f.cancel()

    def close(self) -> None:
        pass


class _Futures(_Runner):
    """A ``concurrent.futures.Executor`` (threads or processes): the step is pickled with each chunk."""

    def __init__(self, executor, fn, slots: int):
        self.executor, self.fn, self.slots = executor, fn, slots
        self.local = isinstance(executor, concurrent.futures.ThreadPoolExecutor)
        self.entry = _call if self.local else _call_in_worker

    def submit(self, boxes):
        return self.executor.submit(self.entry, self.fn, boxes)


class _Dask(_Runner):
    """A ``dask.distributed.Client``: the step is one task whose result every chunk depends on."""

    def __init__(self, client, fn):
        self.distributed = _distributed()
        self.client = client
        workers = client.scheduler_info().get("workers", {})
        self.slots = 2 * max(1, sum(w.get("nthreads", 1) for w in workers.values()))
        # A task that returns the step, not a scatter: scattered data has no recipe, so when the workers
        # holding it die (and Dask's memory manager keeps only one replica once no chunk waits for it) it
        # is lost for good and every later chunk fails; a task's result is computed again instead.
        self.fn = client.submit(_itself, fn, pure=False)

    def submit(self, boxes):
        return self.client.submit(_call_in_worker, self.fn, boxes, pure=False)

    def wait(self, futures, timeout: float) -> list:
        done = [f for f in futures if f.done()]
        if done:
            return done
        try:
            self.distributed.wait(list(futures), timeout=timeout, return_when="FIRST_COMPLETED")
        except TimeoutError:
            return []
        return [f for f in futures if f.done()]

    def cancel(self, futures) -> None:
        if futures:
            self.client.cancel(list(futures))

    def close(self) -> None:
        self.client.cancel([self.fn])


def _runner(executor, fn) -> _Runner:
    """The seam: local threads (``None``), a ``concurrent.futures.Executor``, or a Dask client."""
    if executor is None:
        from .paving import _thread_pool

        workers = min(os.cpu_count() or 1, 4)
        return _Futures(_thread_pool(workers), fn, workers)
    if _is_dask_client(executor):
        return _Dask(executor, fn)
    if isinstance(executor, concurrent.futures.Executor):
        workers = getattr(executor, "_max_workers", None) or os.cpu_count() or 1
        return _Futures(executor, fn, 2 * workers)
    raise InvalidParameterError(f"executor must be a concurrent.futures.Executor or a dask.distributed.Client; got "
                                f"{type(executor).__name__}", parameter="executor")


@contextmanager
def connect(address: str):
    """A Dask client for ``address``: ``tcp://host:8786`` (a running scheduler) or ``local:N``.

    ``local:N`` starts a ``LocalCluster`` of ``N`` worker processes (one
    thread each) for the duration of the block and stops it afterwards.
    """
    distributed = _distributed()
    text = str(address).strip()
    if text.startswith("local:"):
        try:
            n = int(text[len("local:"):])
        except ValueError:
            n = 0
        if n < 1:
            raise InvalidParameterError(f"scheduler 'local:N' needs a number of workers N >= 1; got {address!r}",
                                        parameter="scheduler")
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                      silence_logs=40) as cluster, distributed.Client(cluster) as client:
            yield client
        return
    if "://" not in text:
        raise InvalidParameterError(f"scheduler must be an address such as tcp://host:8786 or local:N; got "
                                    f"{address!r}", parameter="scheduler")
    try:
        client = distributed.Client(text, timeout=30)
    except (OSError, TimeoutError) as exc:
        raise WorkspaceError(f"scheduler {address!r} could not be reached: {exc}", parameter="scheduler") from None
    with client:
        yield client


def map_codes(decide: Decider, boxes: np.ndarray, executor, *, chunk: int = 50_000) -> np.ndarray:
    """``decide(boxes)`` computed chunk by chunk through ``executor`` (same codes, in order).

    For searches whose loop stays here (:func:`~workspace_sym.interval.search.prove_all`):
    only the evaluation of each generation is spread.
    """
    if executor is None or len(boxes) <= _MIN_CHUNK:
        return decide(boxes)
    runner = _runner(executor, decide)
    try:
        parts = max(1, min(runner.slots, math.ceil(len(boxes) / _MIN_CHUNK)), math.ceil(len(boxes) / chunk))
        chunks = np.array_split(boxes, parts)
        futures = [runner.submit(b) for b in chunks]
        return np.concatenate([runner.result(f, b, _checked_codes) for f, b in zip(futures, chunks)])
    finally:
        runner.close()


# ----------------------------------------------------------------------------- results on disk
@dataclass(frozen=True, eq=False)
class StoredPaving(Paving):
    """A :class:`~workspace_sym.interval.paving.Paving` whose decided boxes are on disk.

    The boxes are in the ``.npy`` parts listed in ``files``: :meth:`parts`
    streams a class part by part, while ``inner``, ``boundary`` and ``outer``
    (and :meth:`load`) read the whole class into memory the first time they
    are asked for, so that everything that takes a Paving (pictures, the
    notebook display, reports) sees the same boxes as with an in-memory run.
    The counts and measures are those accumulated while the boxes were
    written (exact sums), without reading them back.
    """

    store: str = ""
    stored_counts: dict = field(default_factory=dict)
    stored_sums: dict = field(default_factory=dict)
    stored_bounds: dict = field(default_factory=dict)        # {"down": sums, "up": sums}: outward measure sums
    files: dict = field(default_factory=dict)
    _loaded: dict = field(default_factory=dict, repr=False)

    def __getattribute__(self, name):
        # The decided classes are fields of Paving, empty in a stored one: read them from disk on demand.
        if name in KINDS:
            loaded = object.__getattribute__(self, "_loaded")
            if name not in loaded:
                loaded[name] = object.__getattribute__(self, "load")(name)
            return loaded[name]
        return object.__getattribute__(self, name)

    @property
    def counts(self) -> dict:
        return {**self.stored_counts, "pending": len(self.pending)}

    @property
    def measures(self) -> dict:
        return {**{k: ExactSum.parse(v).value for k, v in self.stored_sums.items()},
                "pending": box_measure(self.pending)}

    @cached_property
    def measure_bounds(self) -> tuple[float, float]:
        """The certified bracket from the outward sums kept while the boxes were written (see Paving)."""
        down, up = ({k: ExactSum.parse(v) for k, v in self.stored_bounds[d].items()} for d in ("down", "up"))
        high = ExactSum.of(measures_of(self.pending, "up"))
        high.merge(up["inner"])
        high.merge(up["boundary"])
        return down["inner"].value_down, high.value_up

    def parts(self, kind: str):
        """The boxes of a class, part by part (memory-mapped ``(N, n, 2)`` arrays)."""
        for path in self.files[kind]:
            yield np.load(path, mmap_mode="r")

    def load(self, kind: str) -> np.ndarray:
        """All the boxes of a class as one array (when they fit in memory)."""
        parts = list(self.parts(kind))
        return np.concatenate(parts) if parts else np.empty((0, len(self.variables), 2))

    def to_dict(self) -> dict:
        out = super().to_dict()
        for k in KINDS:
            out[k]["files"] = [str(p) for p in self.files[k]]
        out["store"] = self.store
        return out

    def __repr__(self):
        lo, hi = self.measure_bounds
        c = self.counts
        return (f"StoredPaving({c['inner']} inner, {c['boundary']} boundary, {c['outer']} outer, {c['pending']} "
                f"pending in {self.store}; measure in {fmt_bracket(lo, hi, 6, 'g')}, delta={self.delta})")


# ----------------------------------------------------------------------------- checkpoints
def _describe(fn) -> str:
    """What a decider is, for checking that a checkpoint belongs to this run."""
    if isinstance(fn, partial):
        keywords = ", ".join(f"{k}={v!r}" for k, v in sorted(fn.keywords.items()))
        return f"{_describe(fn.func)}({keywords})"
    if hasattr(fn, "constraints") and hasattr(fn, "backend"):
        return f"constraints {[sp.sstr(c.g) for c in fn.constraints]} ({fn.backend})"
    return f"{getattr(fn, '__module__', '')}.{getattr(fn, '__qualname__', type(fn).__qualname__)}"


def _fingerprint(step: Step, box: Box, constraints, backend) -> dict:
    return {"variables": [str(v) for v in box.variables], "lower": list(box.lower), "upper": list(box.upper),
            "constraints": [sp.sstr(c.g) + (" < 0" if c.strict else " <= 0") for c in constraints],
            "decider": _describe(step.decide), "contract": step.separate is not None,
            "delta": step.delta, "size": step.size, "backend": backend}


def _write_checkpoint(path: Path, meta: dict, pending: np.ndarray, store: BoxStore) -> None:
    arrays: dict[str, Any] = {"pending": pending}
    if store.directory is None:
        arrays.update({k: store.arrays(k) for k in KINDS})
    else:
        store.flush()
    meta = {**meta, "store": store.state()}
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as f:
        np.savez(f, meta=np.array(json.dumps(meta)), **arrays)
    os.replace(tmp, path)


def _read_checkpoint(path: Path, fingerprint: dict):
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            arrays = {k: data[k] for k in data.files if k != "meta"}
    except (OSError, ValueError, KeyError) as exc:
        raise InvalidParameterError(f"resume: {str(path)!r} is not a checkpoint of a paving ({exc})",
                                    parameter="resume") from None
    if meta.get("fingerprint") != fingerprint:
        theirs = meta.get("fingerprint", {})
        diff = sorted(k for k in set(theirs) | set(fingerprint) if theirs.get(k) != fingerprint.get(k))
        raise InvalidParameterError(f"resume: {str(path)!r} is the checkpoint of another run (it differs in "
                                    f"{', '.join(diff)})", parameter="resume")
    return meta, arrays


# ----------------------------------------------------------------------------- the driver
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


def _store_for(n, max_memory, store, resume):
    if max_memory is None and store is None:
        return BoxStore(n), None
    budget = None if max_memory is None else parse_memory(max_memory)
    if store is None:
        store = (Path(str(resume) + ".boxes") if resume is not None
                 else Path(tempfile.mkdtemp(prefix="workspace_sym-paving-")))
    store = Path(store)
    if store.exists() and any(store.glob("*/part-*.npy")):
        raise InvalidParameterError(f"store directory {str(store)!r} already holds boxes of another run; give an "
                                    "empty directory, or resume= the checkpoint of that run", parameter="store")
    flush = 64 * 2**20 if budget is None else max(2**20, min(64 * 2**20, budget // 32))
    return BoxStore(n, store, flush_bytes=flush), budget


def run_paving(decide: Decider, box: Box, *, delta: float, size: str = "diameter", max_boxes: int | None = None,
               time_limit: float | None = None, progress: bool | None = None, chunk: int = 200_000,
               constraints=(), backend: str = "numpy", exact_measure=None, label: str = "paving",
               presplit: int = 512, separate=None, executor=None, max_memory=None, store=None,
               resume=None) -> Paving:
    """Branch and bisect (:func:`~workspace_sym.interval.paving.subdivide`) by chunks through an executor.

    Parameters
    ----------
    decide, separate : the decider and the optional contraction; both must
        pickle when ``executor`` is another process (the deciders of
        :func:`~workspace_sym.interval.paving.pave` and of the Orthoglide do).
    executor : None (local threads), a :class:`concurrent.futures.Executor`,
        or a ``dask.distributed.Client`` (:func:`connect`).
    max_memory : bytes or text such as ``"2GB"``: stream the decided boxes to
        disk (``store``) and cap the chunks so that the boxes being decided
        fit; the result is a :class:`StoredPaving`.
    store : directory for the decided boxes (default: a new temporary
        directory, or ``<resume>.boxes`` with a checkpoint).
    resume : path of a checkpoint.  If it exists, the run goes on from it
        (same constraints, box, delta: checked); the checkpoint is written
        when the run ends, complete or stopped (time limit, budget,
        Ctrl-C), and every minute while a streamed run goes on.

    Returns
    -------
    Paving, or StoredPaving when the boxes are on disk.  A stopped run keeps
    every undecided box pending.
    """
    step = Step(decide, separate, float(delta), size)
    n = len(box.variables)
    fingerprint = _fingerprint(step, box, constraints, backend)
    path = None if resume is None else Path(resume)
    evaluated, seconds_before = 0, 0.0
    if path is not None and path.exists():
        meta, arrays = _read_checkpoint(path, fingerprint)
        state = meta["store"]
        keeper = BoxStore.restore(n, state, arrays)
        budget = None if max_memory is None else parse_memory(max_memory)
        stack = deque([arrays["pending"]] if len(arrays["pending"]) else [])
        evaluated, seconds_before = int(meta["evaluated"]), float(meta["seconds"])
    else:
        keeper, budget = _store_for(n, max_memory, store, resume)
        stack = deque([initial_boxes(box, delta, size, presplit)])
    run = RunBudget(max_boxes=max_boxes, time_limit=time_limit, progress=progress, total=box.measure, label=label)
    runner = _runner(executor, step)
    largest = chunk if budget is None else max(_MIN_CHUNK, min(chunk, budget // (2 * runner.slots * _BYTES_PER_BOX)))
    inflight: dict = {}
    reason, last_checkpoint = "", time.perf_counter()

    def pending():
        parts = [*stack, *inflight.values()]
        return np.concatenate(parts) if parts else np.empty((0, n, 2))

    def checkpoint():
        _write_checkpoint(path, {"fingerprint": fingerprint, "evaluated": evaluated,
                                 "seconds": seconds_before + run.seconds}, pending(), keeper)

    try:
        while stack or inflight:
            reason = run.stop_reason(evaluated)
            if reason:
                break
            queued = sum(len(b) for b in inflight.values())
            frontier = sum(len(b) for b in stack)
            size_now = max(_MIN_CHUNK, min(largest, math.ceil(frontier / runner.slots)))
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
                inner, boundary, outer, children = runner.result(future, inflight[future], _checked_step)
                evaluated += len(inflight.pop(future))
                for kind, boxes in zip(KINDS, (inner, boundary, outer)):
                    keeper.add(kind, boxes)
                if len(children):
                    stack.append(children)
            if run.showing:                 # everything not pending is decided
                run.show(sum(keeper.sums[k].value for k in KINDS), evaluated)
            if path is not None and keeper.directory is not None and \
                    time.perf_counter() - last_checkpoint > _CHECKPOINT_EVERY:
                checkpoint()
                last_checkpoint = time.perf_counter()
    except KeyboardInterrupt:
        reason = "interrupted"
    finally:
        runner.cancel(list(inflight))
        runner.close()
        run.close()
    left = pending()
    if path is not None:
        checkpoint()
    keeper.flush()
    empty = np.empty((0, n, 2))
    common = (box.variables, box, tuple(constraints), float(delta), backend, size)
    tail = dict(pending=left, seconds=seconds_before + run.seconds, complete=not len(left), evaluated=evaluated,
                stop_reason=reason if len(left) else "", exact_measure=exact_measure,
                contract=separate is not None)
    if keeper.directory is None:
        return Paving(*common, inner=keeper.arrays("inner"), boundary=keeper.arrays("boundary"),
                      outer=keeper.arrays("outer"), **tail)
    return StoredPaving(*common, inner=empty, boundary=empty, outer=empty, **tail, store=str(keeper.directory),
                        stored_counts=dict(keeper.counts), stored_sums={k: str(s) for k, s in keeper.sums.items()},
                        stored_bounds={"down": {k: str(s) for k, s in keeper.sums_down.items()},
                                       "up": {k: str(s) for k, s in keeper.sums_up.items()}},
                        files={k: keeper.files(k) for k in KINDS})
