"""Where the chunks of a paving run: the :class:`Runner` seam under the driver loop.

A runner applies one picklable function (a driver :class:`~workspace_sym.interval.driver.Step`, a decider, a
cover step) to chunks of boxes and hands back futures: :class:`Inline` in this process when the result is asked
for, :class:`Futures` on a ``concurrent.futures`` executor (this process's threads by default), :class:`Dask` on a
``dask.distributed`` cluster.  The driver (:func:`~workspace_sym.interval.driver.subdivide`) and the searches
that spread one generation (:func:`map_codes`) go through :func:`runner_for`; this module imports nothing of
theirs.

What crosses the network: the function once to the scheduler, as a task that
returns it, and from there to each worker that runs a chunk (a constraint
decider pickles as its SymPy constraints and is compiled once on each
worker, see ``paving._Decider.__reduce__``; if every worker holding it dies,
the task runs again), then per chunk its boxes (``48 N`` bytes for ``N``
boxes in 3D) one way and the results the other way.  A
``concurrent.futures`` executor has no such task: the function goes with
every chunk, still as its SymPy recipe, compiled once per process by the same
cache.  A result that comes from another process is checked before it is used
(:func:`refuse_result`).
"""

from __future__ import annotations

import concurrent.futures
import ctypes
import ctypes.util
import math
import os
from contextlib import contextmanager
from functools import cache

import numpy as np

from ..errors import InvalidParameterError, MissingExtraError, WorkerResultError, WorkspaceError
from . import arith
from .verdict import VERDICTS, Decider

__all__ = ["Runner", "Inline", "Futures", "Dask", "runner_for", "thread_pool", "MIN_CHUNK", "connect", "map_codes",
           "tune_malloc", "refuse_result", "MissingExtraError"]

_EXTRA = "pip install 'workspace_sym[distributed]'"
MIN_CHUNK = 1024                 # below this a chunk sent elsewhere costs more in overhead than in work


def _distributed():
    try:
        import distributed
    except ImportError:
        raise MissingExtraError(f"a Dask scheduler needs dask.distributed, which is not installed: {_EXTRA}",
                                parameter="scheduler") from None
    return distributed


# ----------------------------------------------------------------------------- entry points
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


def refuse_result(what: str, got: str):
    """Raise the error of a worker's result that is not what was asked for.

    Parameters
    ----------
    what : str
        What the worker returned, described (``"codes other than 1, 0 and -1"``).
    got : str
        A short account of the value (its type, shape or some of its entries).

    Raises
    ------
    WorkerResultError
        Always, with ``parameter="executor"``.
    """
    raise WorkerResultError(f"executor: a worker returned {what}; got {got} (a worker of another version or an "
                            "untrusted cluster?)", parameter="executor")


def _checked_codes(codes, chunk: np.ndarray) -> np.ndarray:
    """A decider's codes for ``chunk`` as sent back: one integer 1, 0 or -1 a box."""
    if type(codes) is not np.ndarray:
        refuse_result("codes that are not a numpy array", type(codes).__name__)
    if codes.dtype.kind not in "iuf" or codes.shape != (len(chunk),):
        refuse_result(f"codes that are not {len(chunk)} numbers", f"{codes.dtype} {codes.shape}")
    if not np.isin(codes, VERDICTS).all():
        refuse_result("codes other than 1, 0 and -1", repr(sorted(set(np.unique(codes).tolist()) - set(VERDICTS))[:5]))
    return codes


def _itself(value):
    return value


def _is_dask_client(executor) -> bool:
    return type(executor).__name__ == "Client" and type(executor).__module__.startswith("distributed")


class Runner:
    """``fn`` applied to chunks of boxes somewhere, with futures: the seam every paving goes through.

    ``slots`` is how many chunks the driver keeps in flight; ``local`` is True when results are computed in
    this process's threads (never unpickled, so not checked).  A subclass defines :meth:`submit`.
    """

    slots = 1
    local = False                   # results computed in this process's threads: never unpickled, not checked

    def submit(self, boxes):
        """Start ``fn`` on a chunk of boxes.

        Parameters
        ----------
        boxes : numpy.ndarray
            The ``(N, n, 2)`` chunk.

        Returns
        -------
        future
            Its future (``result()`` gives ``fn(boxes)``).  The base class raises ``NotImplementedError``.
        """
        raise NotImplementedError

    def result(self, future, boxes: np.ndarray, check):
        """The result of ``future`` (the task on ``boxes``), checked by ``check`` when it came from elsewhere.

        Parameters
        ----------
        future : future
            A future of :meth:`submit`.
        boxes : numpy.ndarray
            The chunk it was given.
        check : callable
            ``check(value, boxes)`` returns the value checked or raises
            (:func:`~workspace_sym.interval.driver.checked_step`).

        Returns
        -------
        object
            ``fn(boxes)``, checked unless the runner is :attr:`local`.
        """
        value = future.result()
        return value if self.local else check(value, boxes)

    def wait(self, futures, timeout: float) -> list:
        """The futures that are done, waiting until one is or ``timeout`` passes.

        Parameters
        ----------
        futures : iterable of future
            Futures of :meth:`submit`.
        timeout : float
            The most seconds to wait.

        Returns
        -------
        list
            The futures done (empty when none is by then).
        """
        done, _ = concurrent.futures.wait(futures, timeout=timeout, return_when=concurrent.futures.FIRST_COMPLETED)
        return list(done)

    def cancel(self, futures) -> None:
        """Cancel the futures not yet started (those running finish; their results are not asked for).

        Parameters
        ----------
        futures : iterable of future
            Futures of :meth:`submit`.
        """
        for f in futures:
            f.cancel()

    def close(self) -> None:
        """Release what the runner holds elsewhere (nothing here; the executor is the caller's)."""
        pass


class Futures(Runner):
    """A ``concurrent.futures.Executor`` (threads or processes): the step is pickled with each chunk.

    Parameters
    ----------
    executor : concurrent.futures.Executor
        Where the chunks run; a ``ThreadPoolExecutor`` makes the runner :attr:`local` (results not checked).
    fn : callable
        The function applied to each chunk, in round-to-nearest.
    slots : int
        How many chunks the driver keeps in flight.
    """

    def __init__(self, executor, fn, slots: int):
        self.executor, self.fn, self.slots = executor, fn, slots
        self.local = isinstance(executor, concurrent.futures.ThreadPoolExecutor)
        self.entry = _call if self.local else _call_in_worker

    def submit(self, boxes):
        """Submit ``fn`` on a chunk to the executor.

        Parameters
        ----------
        boxes : numpy.ndarray
            The ``(N, n, 2)`` chunk.

        Returns
        -------
        concurrent.futures.Future
            Its future.
        """
        return self.executor.submit(self.entry, self.fn, boxes)


class Dask(Runner):
    """A ``dask.distributed.Client``: the step is one task whose result every chunk depends on.

    ``slots`` is twice the number of the cluster's worker threads when the runner is made.

    Parameters
    ----------
    client : dask.distributed.Client
        The cluster's client (the caller's: it stays open).
    fn : callable
        The function applied to each chunk; it must pickle.

    Raises
    ------
    MissingExtraError
        When ``dask.distributed`` is not installed.
    """

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
        """Submit ``fn`` on a chunk to the cluster.

        Parameters
        ----------
        boxes : numpy.ndarray
            The ``(N, n, 2)`` chunk.

        Returns
        -------
        distributed.Future
            Its future.
        """
        return self.client.submit(_call_in_worker, self.fn, boxes, pure=False)

    def wait(self, futures, timeout: float) -> list:
        """The futures that are done, waiting until one is or ``timeout`` passes.

        Parameters
        ----------
        futures : iterable of distributed.Future
            Futures of :meth:`submit`.
        timeout : float
            The most seconds to wait.

        Returns
        -------
        list
            The futures done (empty when none is by then).
        """
        done = [f for f in futures if f.done()]
        if done:
            return done
        try:
            self.distributed.wait(list(futures), timeout=timeout, return_when="FIRST_COMPLETED")
        except TimeoutError:
            return []
        return [f for f in futures if f.done()]

    def cancel(self, futures) -> None:
        """Cancel the futures on the cluster.

        Parameters
        ----------
        futures : iterable of distributed.Future
            Futures of :meth:`submit`.
        """
        if futures:
            self.client.cancel(list(futures))

    def close(self) -> None:
        """Release the task that holds ``fn`` on the cluster (the client stays open)."""
        self.client.cancel([self.fn])


@cache
def thread_pool(workers: int) -> concurrent.futures.ThreadPoolExecutor:
    """One pool per worker count for the whole process (its threads end with the interpreter)."""
    return concurrent.futures.ThreadPoolExecutor(workers, thread_name_prefix="workspace_sym")


class _Deferred:
    """A chunk of :class:`Inline` work, done when its result is asked for (so that Ctrl-C during the work
    finds the chunk still in the driver's hands)."""

    def __init__(self, fn, boxes):
        self.fn, self.boxes = fn, boxes

    def result(self):
        return self.fn(self.boxes)


class Inline(Runner):
    """``fn`` in this process's thread, one chunk at a time, when its result is asked for.

    Parameters
    ----------
    fn : callable
        The function applied to each chunk (in the thread and rounding mode of the caller).
    """

    local = True

    def __init__(self, fn):
        self.fn = fn

    def submit(self, boxes):
        """A deferred chunk: nothing runs until its ``result()`` is asked for.

        Parameters
        ----------
        boxes : numpy.ndarray
            The ``(N, n, 2)`` chunk.

        Returns
        -------
        object
            A future-like object whose ``result()`` computes ``fn(boxes)``.
        """
        return _Deferred(self.fn, boxes)

    def wait(self, futures, timeout: float) -> list:
        """Every future, at once (each is done when its result is asked for).

        Parameters
        ----------
        futures : iterable
            Futures of :meth:`submit`.
        timeout : float
            Not used.

        Returns
        -------
        list
            ``futures`` as a list.
        """
        return list(futures)

    def cancel(self, futures) -> None:
        """Nothing to cancel: a chunk not asked for never runs.

        Parameters
        ----------
        futures : iterable
            Futures of :meth:`submit`.
        """
        pass


def runner_for(executor, fn) -> Runner:
    """The seam: local threads (``None``), a ``concurrent.futures.Executor``, or a Dask client.

    Parameters
    ----------
    executor : concurrent.futures.Executor, dask.distributed.Client or None
        None: a pool of this process's threads (as many as the cores, at most 4), shared by the process.
    fn : callable
        The function applied to each chunk.

    Returns
    -------
    Runner
        :class:`Futures` (this process's threads, a slot each; an executor, two slots a worker) or
        :class:`Dask`.

    Raises
    ------
    InvalidParameterError
        ``parameter="executor"``, for any other executor.
    MissingExtraError
        For a Dask client when ``dask.distributed`` cannot be imported.
    """
    if executor is None:
        workers = min(os.cpu_count() or 1, 4)
        return Futures(thread_pool(workers), fn, workers)
    if _is_dask_client(executor):
        return Dask(executor, fn)
    if isinstance(executor, concurrent.futures.Executor):
        workers = getattr(executor, "_max_workers", None) or os.cpu_count() or 1
        return Futures(executor, fn, 2 * workers)
    raise InvalidParameterError(f"executor must be a concurrent.futures.Executor or a dask.distributed.Client; got "
                                f"{type(executor).__name__}", parameter="executor")


@contextmanager
def connect(address: str):
    """A Dask client for ``address``: ``tcp://host:8786`` (a running scheduler) or ``local:N``.

    ``local:N`` starts a ``LocalCluster`` of ``N`` worker processes (one
    thread each) for the duration of the block and stops it afterwards.

    Parameters
    ----------
    address : str
        ``local:N`` with ``N`` at least 1, or a scheduler's address with a scheme (``tcp://host:8786``).

    Yields
    ------
    dask.distributed.Client
        The client, closed when the block ends.

    Raises
    ------
    MissingExtraError
        When ``dask.distributed`` is not installed.
    InvalidParameterError
        ``parameter="scheduler"``, for an address of neither form.
    WorkspaceError
        ``parameter="scheduler"``, when the scheduler cannot be reached within 30 seconds.
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

    Parameters
    ----------
    decide : Decider
        The verdicts; it must pickle for an executor of other processes.
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.
    executor : concurrent.futures.Executor, dask.distributed.Client or None
        Where the chunks run (:func:`runner_for`).  None, or at most :data:`MIN_CHUNK` boxes: ``decide(boxes)``
        in this thread.
    chunk : int
        The most boxes in one chunk (default 50,000).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` codes, in the order of ``boxes``.

    Raises
    ------
    WorkerResultError
        When codes sent back from another process are not one number 1, 0 or -1 a box.
    InvalidParameterError
        For an executor of another kind (:func:`runner_for`).
    """
    if executor is None or len(boxes) <= MIN_CHUNK:
        return decide(boxes)
    runner = runner_for(executor, decide)
    try:
        parts = max(1, min(runner.slots, math.ceil(len(boxes) / MIN_CHUNK)), math.ceil(len(boxes) / chunk))
        chunks = np.array_split(boxes, parts)
        futures = [runner.submit(b) for b in chunks]
        return np.concatenate([runner.result(f, b, _checked_codes) for f, b in zip(futures, chunks)])
    finally:
        runner.close()
