"""Vectorised interval arithmetic on numpy arrays, outward-rounded on every operation.

An interval array is a pair ``(lo, hi)`` of float64 arrays of one shape.  Every
operation returns an enclosure of the exact result: the round-to-nearest float
result is pushed outward by one to two spacings (:func:`down`, :func:`up`), or
by a few ulps for the library functions whose error bound is larger than half
an ulp.  NaN anywhere means "no enclosure"
and makes the caller undecided; the operations never turn a NaN into a
finite bound.

Pure functions, no I/O.  Overflow to infinity is a valid (outward) result;
callers that evaluate many boxes silence numpy's floating-point warnings.
The module-level names are the interval operations used by
:mod:`workspace_sym.interval.graph`.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
from contextlib import contextmanager

import numpy as np

__all__ = [
    "round_to_nearest", "rounding_mode", "nearest_rounding",
    "down", "up", "const", "point", "add", "sub", "neg", "mul", "div", "sqr", "ipow", "sqrt", "sin", "cos",
    "iabs", "intersect", "Interval",
]

_INF = np.inf
_TWO_PI = 2 * np.pi


_REL = 2.0**-52          # |x| * 2^-52 is between one and two spacings of the floats around x
_TINY = 2.0**-1074       # the smallest subnormal: covers an underflowed result
_MAX = np.finfo(float).max
_SMALL = 256             # below this size numpy.nextafter is the cheaper way out
_BELOW, _ABOVE = 1.0 - _REL, 1.0 + _REL     # both exact floats


# ----------------------------------------------------------------------------- rounding mode
# Every bound below assumes IEEE round-to-nearest, the mode C programs start in.  A library
# in the same process may leave another one set: importing codac (IBEX) switches the main
# thread to upward rounding for good.  The operations stay outward under a directed mode,
# but the accuracy of libm's and numpy's sin and cos is only documented for the default,
# so every proof runs under round_to_nearest().
_FE_TONEAREST = 0          # glibc (x86-64, aarch64) and macOS
_PROBE = [1.0, 2.0**-60]


def rounding_mode() -> str:
    """The rounding mode in force in this thread: 'nearest', 'upward', 'downward' or 'toward zero'.

    Returns
    -------
    str
        The mode, read from the results of two float additions.
    """
    one, tiny = _PROBE                       # variables: a literal sum would be folded when compiled
    up_, down_ = one + tiny > one, one - tiny < one
    if not (up_ or down_):
        return "nearest"
    if up_:
        return "upward"
    return "downward" if -one - tiny < -one else "toward zero"


@functools.cache
def _libm():
    name = ctypes.util.find_library("m")
    return ctypes.CDLL(name) if name else None


@contextmanager
def round_to_nearest():
    """Run the block in round-to-nearest, restoring the thread's previous mode afterwards.

    Examples
    --------
    >>> with round_to_nearest():
    ...     rounding_mode()
    'nearest'
    """
    if rounding_mode() == "nearest":
        yield
        return
    libm = _libm()
    if libm is None:
        raise RuntimeError(f"the floating-point rounding mode is {rounding_mode()} and libm is not available to "
                           "restore round-to-nearest; interval proofs need it")
    old = libm.fegetround()
    libm.fesetround(_FE_TONEAREST)
    try:
        if rounding_mode() != "nearest":
            raise RuntimeError("could not set round-to-nearest for interval proofs")
        yield
    finally:
        libm.fesetround(old)


def nearest_rounding(fn):
    """``fn`` run under :func:`round_to_nearest` (for functions that prove).

    Parameters
    ----------
    fn : callable
        The function to wrap.

    Returns
    -------
    callable
        A function with ``fn``'s signature and name that calls ``fn`` inside :func:`round_to_nearest` (and so
        raises ``RuntimeError`` where that does).
    """

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with round_to_nearest():
            return fn(*args, **kwargs)

    return wrapper


def down(x):
    """A float at most the exact value that ``x`` is the round-to-nearest result of.

    The exact value is within half a spacing of ``x`` (or within ``2^-1075``
    after underflow).  ``x - (|x| 2^-52 + 2^-1074)`` is at least one spacing
    below ``x`` however it rounds (one spacing is the most ``|x| 2^-52`` can
    lose to rounding, and at a power of two the spacing below halves), so it is
    a lower bound; on large arrays it is several times cheaper than
    ``numpy.nextafter``, which small arrays keep (call overhead dominates
    there).  Both are tested against exact rationals in
    ``tests/interval/test_interval.py``.  ``+inf`` (an overflow) becomes the largest
    float, ``-inf`` and NaN stay.

    Parameters
    ----------
    x : float or numpy.ndarray
        Round-to-nearest results.

    Returns
    -------
    numpy.ndarray or float
        Lower bounds, element by element, of the same shape.
    """
    if np.size(x) < _SMALL:
        return np.nextafter(x, -_INF)
    r = np.minimum(x, _MAX)
    step = np.abs(r)
    step *= _REL
    step += _TINY
    r -= step
    return r


def up(x):
    """A float at least the exact value that ``x`` is the round-to-nearest result of (see :func:`down`).

    ``-inf`` (an overflow) becomes the most negative float; ``+inf`` and NaN stay.

    Parameters
    ----------
    x : float or numpy.ndarray
        Round-to-nearest results.

    Returns
    -------
    numpy.ndarray or float
        Upper bounds, element by element, of the same shape.
    """
    if np.size(x) < _SMALL:
        return np.nextafter(x, _INF)
    r = np.maximum(x, -_MAX)
    step = np.abs(r)
    step *= _REL
    step += _TINY
    r += step
    return r


def _down_ulps(x, k):
    # k ulps of |x| below x; spacing is the ulp above |x|, so this is at least k ulps.
    return np.where(np.isfinite(x), x - k * np.abs(np.spacing(x)), x)


def _up_ulps(x, k):
    return np.where(np.isfinite(x), x + k * np.abs(np.spacing(x)), x)


def const(lo: float, hi: float, shape=()):
    """A constant interval broadcast to ``shape``.

    Parameters
    ----------
    lo, hi : float
        The bounds, taken as they are (no rounding).
    shape : int or tuple of int
        Shape of the arrays (default ``()``: scalars as 0-d arrays).

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, each filled with its bound.
    """
    return np.full(shape, lo, dtype=float), np.full(shape, hi, dtype=float)


def point(x):
    """The degenerate interval ``[x, x]`` of a float array (exact).

    Parameters
    ----------
    x : array_like
        The points, converted to float64 (a conversion that rounds is not made exact here).

    Returns
    -------
    tuple of numpy.ndarray
        ``(x, copy of x)``: two arrays that do not share memory.
    """
    x = np.asarray(x, dtype=float)
    return x, x.copy()


def add(a, b):
    """``a + b``, outward.

    Parameters
    ----------
    a, b : pair of numpy.ndarray
        Intervals ``(lo, hi)`` of shapes that broadcast together.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, an enclosure of the exact sum; NaN where an input bound is NaN.
    """
    return down(a[0] + b[0]), up(a[1] + b[1])


def sub(a, b):
    """``a - b``, outward.

    Parameters
    ----------
    a, b : pair of numpy.ndarray
        Intervals ``(lo, hi)`` of shapes that broadcast together.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, an enclosure of the exact difference; NaN where an input bound is NaN.
    """
    return down(a[0] - b[1]), up(a[1] - b[0])


def neg(a):
    """``-a`` (exact).

    Parameters
    ----------
    a : pair of numpy.ndarray
        The interval ``(lo, hi)``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(-hi, -lo)``.
    """
    return -a[1], -a[0]


def _nan_to(x, value):
    return np.where(np.isnan(x), value, x)


def mul(a, b):
    """``a * b``, outward; ``0 * inf`` counts as 0 (IEEE 1788).

    Parameters
    ----------
    a, b : pair of numpy.ndarray
        Intervals ``(lo, hi)`` of shapes that broadcast together.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, an enclosure of the exact product; NaN (no enclosure) where an input bound is NaN or the
        four bounds sum to NaN (an input ``[-inf, inf]``, or infinities of both signs across the two).
    """
    (al, ah), (bl, bh) = a, b
    with np.errstate(invalid="ignore", over="ignore"):
        p1, p2, p3, p4 = al * bl, al * bh, ah * bl, ah * bh
        # 0 * inf is NaN in floats and 0 in interval arithmetic (IEEE 1788); fmin / fmax skip it,
        # which is sound because 0 is then also among the other products (or all four are NaN).
        lo = np.fmin(np.fmin(p1, p2), np.fmin(p3, p4))
        hi = np.fmax(np.fmax(p1, p2), np.fmax(p3, p4))
        # A NaN input (or an unbounded [-inf, inf], whose sum is NaN too) leaves no enclosure.
        bad = np.isnan(al + ah + bl + bh)
    if bad.any() or not np.ndim(bad):          # (np.where keeps 0-d results arrays)
        return np.where(bad, np.nan, down(lo)), np.where(bad, np.nan, up(hi))
    return down(lo), up(hi)


def div(a, b):
    """``a / b``; a divisor that contains zero gives the whole line (sound, possibly loose).

    Parameters
    ----------
    a, b : pair of numpy.ndarray
        Dividend and divisor, intervals ``(lo, hi)`` of shapes that broadcast together.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, an enclosure of the exact quotient: ``(-inf, inf)`` where ``b`` contains 0, NaN where an
        input bound is NaN.
    """
    (al, ah), (bl, bh) = a, b
    zero = (bl <= 0) & (bh >= 0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        q = (al / bl, al / bh, ah / bl, ah / bh)
    lo = np.minimum.reduce([_nan_to(x, -_INF) for x in q])
    hi = np.maximum.reduce([_nan_to(x, _INF) for x in q])
    lo, hi = np.where(zero, -_INF, down(lo)), np.where(zero, _INF, up(hi))
    bad = np.isnan(al) | np.isnan(ah) | np.isnan(bl) | np.isnan(bh)
    return np.where(bad, np.nan, lo), np.where(bad, np.nan, hi)


def _down_nonnegative(x):
    """:func:`down` of an array ``x >= 0`` (NaN stays) in four operations instead of six.

    For a normal ``x`` in ``[2^e, 2^(e+1))``, ``x 2^-52`` is at least its
    spacing, so the exact ``x (1 - 2^-52)`` is at most ``x - spacing``, a
    float below the float before ``x``, and rounding keeps it there; a
    subnormal ``x`` is unchanged by the product and ``- 2^-1074`` is then
    the exact step to the float before it.  ``+inf`` (an overflow) becomes
    the largest float, and the floor is 0 (a square is never negative).
    """
    r = np.minimum(x, _MAX)
    r *= _BELOW
    r -= _TINY
    return np.maximum(r, 0.0, out=r)


def _up_nonnegative(x):
    """:func:`up` of an array ``x >= 0`` (NaN and ``+inf`` stay) in two operations: ``x (1 + 2^-52)`` is at least
    the float after a normal ``x`` (as in :func:`_down_nonnegative`); ``+ 2^-1074`` is the step after a
    subnormal one."""
    r = x * _ABOVE
    r += _TINY
    return r


def sqr(a):
    """Tight square: ``[-1, 2]**2 = [0, 4]``, not ``[-2, 4]`` as ``x*x`` would give.

    Parameters
    ----------
    a : pair of numpy.ndarray
        The interval ``(lo, hi)``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, an enclosure of the squares, ``lo >= 0``.
    """
    lo, hi = a
    # Smallest |x| on [lo, hi] is max(lo, -hi, 0), largest is max(-lo, hi).
    small = np.maximum(np.maximum(lo, -hi), 0.0)
    large = np.maximum(-lo, hi)
    if np.size(small) < _SMALL:
        return np.maximum(down(small * small), 0.0), up(large * large)
    return _down_nonnegative(small * small), _up_nonnegative(large * large)


def ipow(a, n: int):
    """``a**n`` for an integer ``n >= 1``; even powers are tight like :func:`sqr`.

    Parameters
    ----------
    a : pair of numpy.ndarray
        The interval ``(lo, hi)``.
    n : int
        The exponent, 1 or more.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, an enclosure of the powers (``n`` ulps outward: ``numpy.power`` is not correctly rounded);
        ``a`` itself for ``n = 1``.
    """
    if n == 1:
        return a
    if n == 2:
        return sqr(a)
    lo, hi = a
    # np.power of a float to an integer is not correctly rounded: allow n ulps.
    with np.errstate(over="ignore"):
        pl, ph = np.power(lo, n), np.power(hi, n)
    if n % 2:
        return _down_ulps(pl, n), _up_ulps(ph, n)
    low = np.where(lo >= 0, pl, np.where(hi <= 0, ph, 0.0))
    return np.maximum(_down_ulps(low, n), 0.0), _up_ulps(np.maximum(pl, ph), n)


def sqrt(a):
    """Square root; an interval reaching below zero is a domain error: NaN (undecided).

    Parameters
    ----------
    a : pair of numpy.ndarray
        The interval ``(lo, hi)``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, an enclosure of the square roots; both NaN where ``lo < 0``, and a NaN bound stays NaN.
    """
    lo, hi = a
    with np.errstate(invalid="ignore"):
        r_lo = np.maximum(down(np.sqrt(np.maximum(lo, 0.0))), 0.0)
        r_hi = up(np.sqrt(hi))
    bad = lo < 0
    return np.where(bad, np.nan, r_lo), np.where(bad, np.nan, r_hi)


def iabs(a):
    """``|a|`` (exact).

    Parameters
    ----------
    a : pair of numpy.ndarray
        The interval ``(lo, hi)``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, the absolute values' range; a NaN bound in ``a`` gives NaN bounds (no enclosure is
        never turned into a finite bound).
    """
    lo, hi = a
    low = np.where(lo >= 0, lo, np.where(hi <= 0, -hi, 0.0))
    nan = np.isnan(lo) | np.isnan(hi)
    return np.where(nan, np.nan, low), np.where(nan, np.nan, np.maximum(np.abs(lo), np.abs(hi)))


def _trig(a, fn, phase_max, phase_min):
    lo, hi = a
    with np.errstate(invalid="ignore"):
        fl, fh = fn(lo), fn(hi)
        # numpy's sin / cos are faithful (error below one ulp) on this range: widen by 2 ulps.  The values are
        # within [-1, 1] or NaN, so the ulps are finite wherever the value is: the widening needs no mask.
        low = np.minimum(fl, fh)
        low -= 2 * np.abs(np.spacing(low))
        high = np.maximum(fl, fh)
        high += 2 * np.abs(np.spacing(high))
        magnitude = np.maximum(np.abs(lo), np.abs(hi))
        wide = ~((hi - lo) < _TWO_PI) | (magnitude > 2.0**20)
        # Whether [lo, hi] may contain phase + 2 k pi for some integer k, for both phases (one tolerance),
        # decided generously: yes when unsure only loosens the enclosure (an extremum of +-1 is included).
        tol = 1e-9 * (1.0 + np.abs(lo) + np.abs(hi))
        below, above = lo - tol, hi + tol
        top = np.floor((above - phase_max) / _TWO_PI) >= np.ceil((below - phase_max) / _TWO_PI)
        bottom = np.floor((above - phase_min) / _TWO_PI) >= np.ceil((below - phase_min) / _TWO_PI)
    high = np.where(wide | top, 1.0, np.minimum(high, 1.0))
    low = np.where(wide | bottom, -1.0, np.maximum(low, -1.0))
    bad = np.isnan(lo) | np.isnan(hi)
    if bad.any() or not np.ndim(bad):          # (np.where keeps 0-d results arrays)
        return np.where(bad, np.nan, low), np.where(bad, np.nan, high)
    return low, high


def sin(a):
    """``sin(a)``, outward (2 ulps: numpy's sine is faithful).

    Parameters
    ----------
    a : pair of numpy.ndarray
        The interval ``(lo, hi)``, radians.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)`` within ``[-1, 1]``, an enclosure of the sines: ``[-1, 1]`` where the interval is a full
        turn wide or reaches beyond ``2^20`` in magnitude; NaN where a bound is NaN.
    """
    return _trig(a, np.sin, np.pi / 2, -np.pi / 2)


def cos(a):
    """``cos(a)``, outward (2 ulps: numpy's cosine is faithful).

    Parameters
    ----------
    a : pair of numpy.ndarray
        The interval ``(lo, hi)``, radians.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)`` within ``[-1, 1]``, an enclosure of the cosines: ``[-1, 1]`` where the interval is a full
        turn wide or reaches beyond ``2^20`` in magnitude; NaN where a bound is NaN.
    """
    return _trig(a, np.cos, 0.0, np.pi)


def intersect(a, b):
    """``a`` intersected with ``b`` where ``b`` is defined; NaN in ``a`` stays NaN.

    Parameters
    ----------
    a, b : pair of numpy.ndarray
        Intervals ``(lo, hi)``; a NaN bound of ``b`` leaves ``a``'s bound as it is.

    Returns
    -------
    tuple of numpy.ndarray
        ``(max(a_lo, b_lo), min(a_hi, b_hi))``, exact.  An empty result (``lo > hi``) is returned as it is.
    """
    lo = np.where(np.isnan(b[0]), a[0], np.maximum(a[0], b[0]))
    hi = np.where(np.isnan(b[1]), a[1], np.minimum(a[1], b[1]))
    return lo, hi


class Interval:
    """An interval array with operators, so that one formula serves SymPy symbols and intervals.

    ``a + b``, ``a - b``, ``a * b`` and ``a.sq()`` call the outward-rounded
    functions above; floats and integers mix in as exact constants.

    Parameters
    ----------
    lo, hi : float or numpy.ndarray
        The bounds, kept as given.
    """

    __slots__ = ("lo", "hi")

    def __init__(self, lo, hi):
        self.lo, self.hi = lo, hi

    @property
    def pair(self):
        """The bounds as the module's functions take them.

        Returns
        -------
        tuple
            ``(lo, hi)``.
        """
        return self.lo, self.hi

    @staticmethod
    def _lift(other):
        if isinstance(other, Interval):
            return other.pair
        return other, other

    def __add__(self, other):
        return Interval(*add(self.pair, self._lift(other)))

    __radd__ = __add__

    def __sub__(self, other):
        return Interval(*sub(self.pair, self._lift(other)))

    def __rsub__(self, other):
        return Interval(*sub(self._lift(other), self.pair))

    def __mul__(self, other):
        if not isinstance(other, Interval) and other == 2:      # exact: a power of two
            return Interval(2 * self.lo, 2 * self.hi)
        return Interval(*mul(self.pair, self._lift(other)))

    __rmul__ = __mul__

    def sq(self):
        """The tight square (:func:`sqr`).

        Returns
        -------
        Interval
            An enclosure of the squares.
        """
        return Interval(*sqr(self.pair))
