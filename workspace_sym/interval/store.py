"""Where a paving's decided boxes go: kept in memory, or streamed to disk in parts; and their exact measures.

A paving that outgrows memory (the Orthoglide at eps = 0.00125 decides
about 10^8 boxes) cannot hold its inner, boundary and outer boxes as arrays.
:class:`BoxStore` takes boxes class by class as they are decided and either
keeps them (the default) or writes them to a directory, one ``.npy`` file per
flushed part (``inner/part-000001.npy``, ...): each part is written to a
temporary name and renamed, so a part on disk is whole, and a checkpoint
that lists how many parts it accounts for can be resumed after a crash.  A
store on disk names the problem its boxes belong to (``problem.json``: the
digest of its :class:`~workspace_sym.interval.fingerprint.Fingerprint`) and
a checkpoint lists the SHA-256 of every part: a store of another run, or a
part changed since, is refused when a run resumes.

Measures are **exact sums**: every box's measure (the product of its edge
widths, in floats, as :func:`~workspace_sym.interval.paving.box_measure`
has always computed it) is added exactly, as an integer multiple of
``2^-1074``, and rounded once at the end (:class:`ExactSum`).  The total
does not depend on the order in which the boxes arrive, so a distributed,
streamed or resumed run reports the same measures, to the last bit, as a
local one.

The certified bracket of a paving's measure is summed from per-box measures
rounded outward instead (``measures_of(boxes, "down")`` for the inner boxes,
``"up"`` for the others) and its exact sums are rounded down and up
(:attr:`ExactSum.value_down`, :attr:`ExactSum.value_up`): the bracket holds
the exact measure of the boxes, not only its nearest float.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from fractions import Fraction
from pathlib import Path

import numpy as np

from ..errors import InvalidParameterError

__all__ = ["ExactSum", "BoxStore", "measures_of", "parse_memory", "KINDS"]

KINDS = ("inner", "boundary", "outer")

_SHIFT = 1074 + 53          # the sum is kept in units of 2^-(1074 + 53): every float64 is a whole number of them
_HALF = 26                  # mantissas are split in two halves below 2^27 so that float64 sums of 2^25 are exact
_BLOCK = 2**25
_ROUNDINGS = ("nearest", "down", "up")


class ExactSum:
    """Exact sum of float64 values, rounded once when read.

    The state is a Python integer, the sum in units of ``2^-(1074 + 53)``:
    values are split by :func:`numpy.frexp` into 53-bit integer mantissas and
    exponents; per exponent, the upper and lower halves of the mantissas are
    summed with :func:`numpy.bincount` (float64 sums of fewer than ``2^26``
    integers below ``2^27`` are exact) and shifted into place.

    Parameters
    ----------
    total : int
        The starting sum, in units of ``2^-(1074 + 53)`` (default 0).
    finite : float
        0.0 while every value added was finite; otherwise the float sum of the non-finite ones (``inf``,
        ``-inf`` or NaN), which is then the sum's value.

    Examples
    --------
    >>> s = ExactSum()
    >>> s.add(np.array([1e16, 1.0, -1e16]))
    >>> s.value                                   # numpy.sum gives 0.0
    1.0
    >>> ExactSum.parse(str(ExactSum.of([0.1, 0.2]))).value == float(Fraction(0.1) + Fraction(0.2))
    True
    """

    __slots__ = ("total", "finite")

    def __init__(self, total: int = 0, finite: float = 0.0):
        self.total = int(total)
        self.finite = finite            # inf or nan once a non-finite value was added

    @classmethod
    def of(cls, values) -> ExactSum:
        """The exact sum of ``values``.

        Parameters
        ----------
        values : array_like of float
            The values, of any shape.

        Returns
        -------
        ExactSum
            A new sum holding them.
        """
        s = cls()
        s.add(np.asarray(values, dtype=float))
        return s

    def add(self, values: np.ndarray) -> None:
        """Add ``values`` to the sum, exactly.

        Parameters
        ----------
        values : numpy.ndarray of float
            The values, of any shape; non-finite ones go to ``finite``.
        """
        values = np.ravel(values)
        if not len(values):
            return
        if not np.isfinite(values).all():
            self.finite = self.finite + float(np.sum(values[~np.isfinite(values)]))
            values = values[np.isfinite(values)]
        for start in range(0, len(values), _BLOCK):
            m, e = np.frexp(values[start:start + _BLOCK])
            mant = (m * 2.0**53).astype(np.int64)            # exact: m has 53 significant bits
            hi, lo = mant >> _HALF, mant & ((1 << _HALF) - 1)
            shift = e + 1074                                  # value = mant 2^(e - 53); units 2^-(1074 + 53)
            base = int(shift.min())
            sums_hi = np.bincount(shift - base, weights=hi)
            sums_lo = np.bincount(shift - base, weights=lo)
            for k in np.flatnonzero(sums_hi):
                self.total += int(sums_hi[k]) << (int(k) + base + _HALF)
            for k in np.flatnonzero(sums_lo):
                self.total += int(sums_lo[k]) << (int(k) + base)

    def merge(self, other: ExactSum) -> None:
        """Add another exact sum to this one (``other`` is unchanged).

        Parameters
        ----------
        other : ExactSum
            The sum to add.
        """
        self.total += other.total
        self.finite = self.finite + other.finite

    @property
    def value(self) -> float:
        """The sum rounded to the nearest float."""
        if self.finite != 0.0:
            return self.finite
        return float(Fraction(self.total, 1 << _SHIFT))

    def _directed(self, toward: float) -> float:
        if self.finite != 0.0:
            return self.finite
        exact = Fraction(self.total, 1 << _SHIFT)
        nearest = float(exact)
        if (toward < 0 and Fraction(nearest) > exact) or (toward > 0 and Fraction(nearest) < exact):
            nearest = float(np.nextafter(nearest, toward))
        return nearest

    @property
    def value_down(self) -> float:
        """The sum rounded down: the largest float at most the exact sum."""
        return self._directed(-np.inf)

    @property
    def value_up(self) -> float:
        """The sum rounded up: the smallest float at least the exact sum."""
        return self._directed(np.inf)

    def __str__(self):
        return str(self.total) if self.finite == 0.0 else repr(self.finite)

    @classmethod
    def parse(cls, text: str) -> ExactSum:
        """The sum that ``str()`` wrote as ``text``.

        Parameters
        ----------
        text : str
            An integer (the exact total) or a float's repr (a non-finite sum: ``inf``, ``-inf``, ``nan``).

        Returns
        -------
        ExactSum
            The sum.  Text that is neither raises ``ValueError``.
        """
        try:
            return cls(int(text))
        except ValueError:
            return cls(0, float(text))


def measures_of(boxes: np.ndarray, rounding: str = "nearest") -> np.ndarray:
    """Measure of each box of an ``(N, n, 2)`` array (the product of its edge widths).

    ``rounding="nearest"`` is the float product; ``"down"`` and ``"up"``
    round every width and every product outward, so that the result is at
    most (at least) the exact measure of the box.

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.
    rounding : str
        ``"nearest"`` (default), ``"down"`` or ``"up"``; any other text rounds as ``"up"``.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` measures; 0 for a box with an edge of width 0, never below 0.

    Examples
    --------
    >>> box = np.array([[[0.0, 0.1], [0.0, 0.3]]])          # 0.1 x 0.3 is not a float
    >>> lo, mid, hi = (measures_of(box, r)[0] for r in ("down", "nearest", "up"))
    >>> bool(lo <= mid <= hi and lo < hi), float(hi - lo)
    (True, 3.469446951953614e-18)
    >>> [measures_of(np.array([[[0.0, 0.5], [-1.0, 0.75]]]), r)[0] for r in ("down", "up")]    # exact: unmoved
    [np.float64(0.875), np.float64(0.875)]
    """
    hi, lo = boxes[:, :, 1], boxes[:, :, 0]
    widths = hi - lo
    flat = (widths == 0).any(axis=1)                # measure 0, even where other widths overflow (inf x 0)
    if rounding == "nearest":
        return np.where(flat, 0.0, np.prod(widths, axis=1))
    toward = -np.inf if rounding == "down" else np.inf
    product = _directed(widths, _two_sum_error(hi, -lo, widths), toward)[:, 0]
    for k in range(1, widths.shape[1]):
        width = _directed(widths[:, k], _two_sum_error(hi[:, k], -lo[:, k], widths[:, k]), toward)
        with np.errstate(over="ignore", invalid="ignore"):
            p = product * width
        product = _directed(p, _two_product_error(product, width, p), toward)
    return np.where(flat, 0.0, np.maximum(product, 0.0))


# Error-free transformations (Knuth's TwoSum, Dekker's TwoProduct with Veltkamp's split): the exact rounding
# error of one float operation, so that a result is moved by one ulp only when it was inexact (a width or a
# product of dyadic numbers, as bisection makes them, usually is exact).  They hold in round-to-nearest without
# overflow or underflow; outside that range _directed steps whatever the error says.
_SPLIT = 2.0**27 + 1
_SAFE = (2.0**-960, 2.0**960)


def _two_sum_error(a, b, s):
    bb = s - a
    return (a - (s - bb)) + (b - bb)


def _two_product_error(a, b, p):
    with np.errstate(over="ignore", invalid="ignore"):
        ca, cb = _SPLIT * a, _SPLIT * b
        ah, bh = ca - (ca - a), cb - (cb - b)
        al, bl = a - ah, b - bh
        error = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    small = (np.abs(a) < _SAFE[1]) & (np.abs(b) < _SAFE[1])      # the split itself must not overflow
    return np.where(small, error, np.nan)


def _directed(x, error, toward):
    """``x`` (the nearest float to ``x + error``) moved one step toward ``toward`` unless that is not needed."""
    with np.errstate(invalid="ignore", over="ignore"):
        magnitude = np.abs(x)
        trusted = np.isfinite(error) & (((magnitude > _SAFE[0]) & (magnitude < _SAFE[1])) | (x == 0) & (error == 0))
        needed = (error < 0) if toward < 0 else (error > 0)
        return np.where(trusted & ~needed, x, np.nextafter(x, toward))


_UNITS = {"": 1, "b": 1, "kb": 10**3, "mb": 10**6, "gb": 10**9, "tb": 10**12,
          "kib": 2**10, "mib": 2**20, "gib": 2**30, "tib": 2**40}


def parse_memory(value, name: str = "max_memory") -> int:
    """Bytes from a number or text such as ``"2GB"``, ``"512 MiB"``.

    Parameters
    ----------
    value : int, float or str
        A number of bytes, or a number followed by a unit (``B``, ``kB``, ``MB``, ``GB``, ``TB`` in powers of
        1000, ``KiB``, ``MiB``, ``GiB``, ``TiB`` in powers of 1024; any case, a space allowed before it).
    name : str
        The parameter's name for the error message (default ``"max_memory"``).

    Returns
    -------
    int
        The number of bytes, rounded toward zero.

    Raises
    ------
    InvalidParameterError
        For a value that is not such a size, or a size below 1 MiB.

    Examples
    --------
    >>> parse_memory("2GB"), parse_memory("1.5 GiB"), parse_memory(2**22)
    (2000000000, 1610612736, 4194304)
    """
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        number, unit = float(value), ""
    elif isinstance(value, str):
        text = value.strip().lower()
        digits = text.rstrip("abcdefghijklmnopqrstuvwxyz ")
        number_text, unit = digits.strip(), text[len(digits):].strip()
        try:
            number = float(number_text)
        except ValueError:
            number = float("nan")
    else:
        number, unit = float("nan"), ""
    if unit not in _UNITS or not np.isfinite(number) or number * _UNITS[unit] < 2**20:
        raise InvalidParameterError(f"{name} must be a memory size of at least 1 MiB such as '2GB' or '512MiB'; "
                                    f"got {value!r}", parameter=name)
    return int(number * _UNITS[unit])


class BoxStore:
    """Decided boxes of a run, class by class, with their counts and exact measures.

    ``directory=None`` keeps the arrays in memory; otherwise each class is
    buffered up to ``flush_bytes`` and written to ``directory/<class>/part-NNNNNN.npy``.
    The exact sums of a store on disk are kept as the boxes arrive (its boxes leave memory); those of a
    store in memory are summed from its arrays when asked for (a paving run here asks only for a
    checkpoint), to the same bits since the sums are exact.

    Parameters
    ----------
    n : int
        Number of variables: the boxes are ``(N, n, 2)`` arrays.
    directory : path or None
        Where the parts are written (the class folders are made, and ``problem.json`` written, at once);
        None (default): in memory.
    flush_bytes : int
        Bytes of a class buffered before they are written as one part (default 64 MiB; disk stores only).
    problem : str
        The digest of the run's :class:`~workspace_sym.interval.fingerprint.Fingerprint`, recorded in
        ``problem.json`` (default ``""``).

    Raises
    ------
    InvalidParameterError
        Only from :meth:`restore`, for a checkpoint that does not match its store.  The constructor raises
        ``OSError`` when the directory cannot be written.
    """

    def __init__(self, n: int, directory=None, *, flush_bytes: int = 64 * 2**20, problem: str = ""):
        self.n = n
        self.directory = None if directory is None else Path(directory)
        self.flush_bytes = flush_bytes
        self.problem = problem                       # the digest of the run's fingerprint (stores on disk)
        self.hashes: dict[str, list[str]] = {k: [] for k in KINDS}
        self.counts = dict.fromkeys(KINDS, 0)
        # per rounding ("nearest"; "down" and "up": per-box measures rounded outward, for proved bounds)
        self._sums = {r: {k: ExactSum() for k in KINDS} for r in _ROUNDINGS}
        self.parts = dict.fromkeys(KINDS, 0)
        self._buffer: dict[str, list[np.ndarray]] = {k: [] for k in KINDS}
        self._buffered = dict.fromkeys(KINDS, 0)
        if self.directory is not None:
            for k in KINDS:
                (self.directory / k).mkdir(parents=True, exist_ok=True)
            _write_whole(self.directory / _MANIFEST, json.dumps({"problem": problem}).encode())

    def add(self, kind: str, boxes: np.ndarray) -> None:
        """Keep decided boxes of one class (a disk store writes a part once ``flush_bytes`` are buffered).

        Parameters
        ----------
        kind : str
            The class: ``"inner"``, ``"boundary"`` or ``"outer"``.
        boxes : numpy.ndarray
            ``(N, n, 2)`` boxes; kept as given, not copied.
        """
        if not len(boxes):
            return
        self.counts[kind] += len(boxes)
        if self.directory is not None:
            for r in _ROUNDINGS:
                self._sums[r][kind].add(measures_of(boxes, r))
        self._buffer[kind].append(boxes)
        self._buffered[kind] += boxes.nbytes
        if self.directory is not None and self._buffered[kind] >= self.flush_bytes:
            self._flush(kind)

    def _sums_of(self, rounding: str) -> dict[str, ExactSum]:
        if self.directory is not None:
            return self._sums[rounding]
        return {k: ExactSum.of(measures_of(self.arrays(k), rounding)) if self.counts[k] else ExactSum()
                for k in KINDS}

    @property
    def sums(self) -> dict[str, ExactSum]:
        """Exact sums of the measures of each class's boxes."""
        return self._sums_of("nearest")

    @property
    def sums_down(self) -> dict[str, ExactSum]:
        """Exact sums of the measures of each class's boxes, each rounded down."""
        return self._sums_of("down")

    @property
    def sums_up(self) -> dict[str, ExactSum]:
        """Exact sums of the measures of each class's boxes, each rounded up."""
        return self._sums_of("up")

    def _part(self, kind: str, number: int) -> Path:
        assert self.directory is not None, "parts exist only for a store on disk"
        return self.directory / kind / f"part-{number:06d}.npy"

    def _flush(self, kind: str) -> None:
        if not self._buffer[kind]:
            return
        self.parts[kind] += 1
        data = io.BytesIO()
        np.save(data, np.concatenate(self._buffer[kind]))
        _write_whole(self._part(kind, self.parts[kind]), data.getbuffer())
        self.hashes[kind].append(hashlib.sha256(data.getbuffer()).hexdigest())
        self._buffer[kind], self._buffered[kind] = [], 0

    def flush(self) -> None:
        """Write every buffered box (disk stores); a no-op in memory."""
        if self.directory is not None:
            for k in KINDS:
                self._flush(k)

    def arrays(self, kind: str) -> np.ndarray:
        """The boxes of a class held in memory (memory stores only).

        Parameters
        ----------
        kind : str
            ``"inner"``, ``"boundary"`` or ``"outer"``.

        Returns
        -------
        numpy.ndarray
            ``(N, n, 2)``: the boxes in the order they came; for a disk store, only those not yet written.
        """
        parts = self._buffer[kind]
        return np.concatenate(parts) if parts else np.empty((0, self.n, 2))

    def files(self, kind: str) -> list[Path]:
        """The parts of a class written so far (disk stores).

        Parameters
        ----------
        kind : str
            ``"inner"``, ``"boundary"`` or ``"outer"``.

        Returns
        -------
        list of pathlib.Path
            ``directory/<kind>/part-NNNNNN.npy`` in order; empty for a store in memory.
        """
        return [self._part(kind, i) for i in range(1, self.parts[kind] + 1)]

    # ------------------------------------------------------------ checkpoints
    def state(self) -> dict:
        """What a checkpoint records (after :meth:`flush`): counts, exact sums, parts and their SHA-256.

        Returns
        -------
        dict
            JSON-ready: ``counts``, ``sums``, ``sums_down``, ``sums_up`` (exact sums as text, by class),
            ``parts``, ``hashes`` and ``directory`` (text, or None in memory).
        """
        return {"counts": dict(self.counts), "sums": {k: str(s) for k, s in self.sums.items()},
                "sums_down": {k: str(s) for k, s in self.sums_down.items()},
                "sums_up": {k: str(s) for k, s in self.sums_up.items()},
                "parts": dict(self.parts), "hashes": {k: list(v) for k, v in self.hashes.items()},
                "directory": None if self.directory is None else str(self.directory)}

    @classmethod
    def restore(cls, n: int, state: dict, arrays: dict | None = None, *, problem: str = "") -> BoxStore:
        """The store a checkpoint describes; parts written after it (a crash) are removed.  A store on disk
        must name the problem ``problem`` (the digest of the run's fingerprint) and hold the parts the
        checkpoint lists, byte for byte: another run's store, or a part changed since, is refused.

        Parameters
        ----------
        n : int
            Number of variables.
        state : dict
            The checkpoint's record, as :meth:`state` wrote it.
        arrays : dict or None
            For a store in memory: the boxes of each class, by class (None: none).
        problem : str
            The digest of this run's fingerprint.

        Returns
        -------
        BoxStore
            The store, ready to take more boxes.

        Raises
        ------
        InvalidParameterError
            ``parameter="resume"``: the store's ``problem.json`` names another problem, the record is damaged,
            or a listed part is missing or changed.
        """
        directory = state["directory"]
        if directory is not None:
            _check_manifest(Path(directory), problem)
        store = cls(n, directory, problem=problem)
        try:
            store.counts = {k: int(state["counts"][k]) for k in KINDS}
            store._sums = {r: {k: ExactSum.parse(state[name][k]) for k in KINDS}
                           for r, name in zip(_ROUNDINGS, ("sums", "sums_down", "sums_up"))}
            store.parts = {k: int(state["parts"][k]) for k in KINDS}
            store.hashes = {k: [str(h) for h in state["hashes"][k]] for k in KINDS}
            if any(len(store.hashes[k]) != store.parts[k] for k in KINDS):
                raise ValueError("a hash per part")
        except (KeyError, ValueError, TypeError) as exc:
            raise InvalidParameterError(f"resume: the checkpoint's record of its box store is damaged ({exc})",
                                        parameter="resume") from None
        if store.directory is None:
            for k in KINDS:
                store._buffer[k] = [arrays[k]] if arrays is not None and len(arrays[k]) else []
        else:
            for k in KINDS:
                for path in (store.directory / k).glob("part-*.npy"):
                    if int(path.stem.split("-")[1]) > store.parts[k]:
                        path.unlink()
                for path, digest in zip(store.files(k), store.hashes[k]):
                    try:
                        whole = hashlib.sha256(path.read_bytes()).hexdigest() == digest
                    except OSError:
                        whole = False
                    if not whole:
                        raise InvalidParameterError(f"resume: {str(path)!r} is not the part of the box store "
                                                    "that the checkpoint recorded (missing or changed since); "
                                                    "start the run again", parameter="resume")
        return store


_MANIFEST = "problem.json"


def _write_whole(path: Path, data) -> None:
    """Write ``data`` to ``path`` under a temporary name, then rename it: a file on disk is whole."""
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def _check_manifest(directory: Path, problem: str) -> None:
    """Refuse a box store whose ``problem.json`` does not name the problem ``problem``."""
    try:
        named = json.loads((directory / _MANIFEST).read_text()).get("problem")
    except (OSError, ValueError, AttributeError):
        named = None
    if named != problem:
        raise InvalidParameterError(f"resume: the box store {str(directory)!r} holds the boxes of another run "
                                    f"(its {_MANIFEST} names {'no problem' if named is None else 'another'}); give "
                                    "the store of this checkpoint's run", parameter="resume")
