"""The arbitrary-precision reference backend: ``mpmath.iv``, one box at a time.

``mpmath.iv`` rounds outward at its working precision.  Two traps are avoided
here: it has no ``workprec`` (:func:`precision` restores the precision in
``finally``, holding a lock: ``iv``'s precision is one global of the process,
and two threads setting and restoring it unguarded could leave it raised for
good), and its comparisons of overlapping intervals return ``None``, which
``if`` would read as False; every decision compares endpoints (``x.a``,
``x.b``) explicitly.
"""

from __future__ import annotations

import threading
from contextlib import contextmanager

import mpmath

__all__ = ["precision", "iv", "from_float_bounds", "sqrt", "sqr", "ipow", "sin", "cos", "div",
           "iabs", "const_rational", "const_float"]

iv = mpmath.iv

# One precision for the whole process: a thread saving 15 digits, another saving the first one's 60 and both
# restoring in the wrong order left ``iv`` at 60 digits (found by CI: a later test's 53-bit ends were no longer
# floats).  Reentrant, so a ``precision`` block may call code that opens another.
_PRECISION_LOCK = threading.RLock()


@contextmanager
def precision(digits: int | None = None, *, bits: int | None = None):
    """Set ``mpmath.iv``'s precision inside a ``with`` block, restored afterwards.

    The block holds a process-wide lock: threads that change the precision run their blocks one at a time, so each
    restores what it found.  Code inside a block must not wait for another thread that opens one.

    Parameters
    ----------
    digits : int or None
        Decimal digits (``iv.dps``).  None, with ``bits`` None too: the precision in force is kept.
    bits : int or None
        Binary digits (``iv.prec``); takes precedence over ``digits``.

    Examples
    --------
    >>> with precision(50):
    ...     iv.dps
    50
    >>> iv.dps
    15
    """
    with _PRECISION_LOCK:
        old = iv.prec
        try:
            if bits is not None:
                iv.prec = bits
            elif digits is not None:
                iv.dps = digits
            yield
        finally:
            iv.prec = old


def from_float_bounds(lo: float, hi: float):
    """The exact interval ``[lo, hi]`` of two floats (floats are exact binary numbers).

    Parameters
    ----------
    lo, hi : float
        The endpoints, ``lo <= hi``.

    Returns
    -------
    mpmath.iv.mpf
        ``[lo, hi]``, rounded outward only when the precision in force is below 53 bits.
    """
    return iv.mpf([lo, hi])


def const_rational(p: int, q: int):
    """Enclosure of the rational ``p / q`` at the precision in force.

    Parameters
    ----------
    p, q : int
        Numerator and denominator.  ``q = 0`` gives the whole line ``[-inf, +inf]`` (mpmath's quotient).

    Returns
    -------
    mpmath.iv.mpf
        An interval containing ``p / q``, rounded outward.
    """
    return iv.mpf(p) / iv.mpf(q)


def const_float(text: str):
    """Enclosure of a decimal literal such as ``"0.1"`` (mpmath rounds the string outward).

    Parameters
    ----------
    text : str
        The decimal literal.

    Returns
    -------
    mpmath.iv.mpf
        An interval containing the decimal's value, at the precision in force.
    """
    return iv.mpf(text)


def _undefined():
    # mpmath.iv has no NaN interval; use the whole line, which decides nothing.
    return iv.mpf(["-inf", "inf"])


def sqr(x):
    """Enclosure of ``x**2``, never below 0 (``x * x`` alone would give ``[-2, 4]`` for ``[-1, 2]``).

    Parameters
    ----------
    x : mpmath.iv.mpf
        The interval.

    Returns
    -------
    mpmath.iv.mpf
        An interval containing ``t**2`` for every ``t`` in ``x``.
    """
    a, b = x.a, x.b
    if a >= 0:
        return x * x
    if b <= 0:
        return x * x
    m = max(-a, b)
    return iv.mpf([0, (iv.mpf(m) * iv.mpf(m)).b])


def ipow(x, n: int):
    """Enclosure of ``x**n``, never below 0 for an even ``n``.

    Parameters
    ----------
    x : mpmath.iv.mpf
        The interval.
    n : int
        The exponent, an integer (the expression graph's ``pow`` nodes are positive; a negative power is a
        reciprocal there).  A negative ``n`` with ``x`` holding 0 gives the whole line (``[0, +inf]`` for an even
        ``n``): ``t**n`` is unbounded near 0.

    Returns
    -------
    mpmath.iv.mpf
        An interval containing ``t**n`` for every ``t`` in ``x``.
    """
    if n == 2:
        return sqr(x)
    if n < 0 and x.a <= 0 <= x.b:
        # t**n is unbounded near t = 0 (and undefined at it): the only enclosure is unbounded
        return iv.mpf([0, mpmath.inf]) if n % 2 == 0 else iv.mpf([-mpmath.inf, mpmath.inf])
    if n % 2 == 0 and x.a < 0 < x.b:
        m = iv.mpf(max(-x.a, x.b))
        return iv.mpf([0, (m**n).b])
    return x**n


def sqrt(x):
    """Enclosure of ``sqrt(x)``, or None when ``x`` reaches below 0.

    Parameters
    ----------
    x : mpmath.iv.mpf
        The interval.

    Returns
    -------
    mpmath.iv.mpf or None
        An interval containing ``sqrt(t)`` for every ``t`` in ``x``; None (a domain error, which decides nothing
        for the box) when ``x.a < 0``.
    """
    if x.a < 0:
        return None  # domain error: the caller decides nothing for this box
    return iv.sqrt(x)


def sin(x):
    """Enclosure of ``sin(x)`` (``mpmath.iv.sin``).

    Parameters
    ----------
    x : mpmath.iv.mpf
        The interval, radians.

    Returns
    -------
    mpmath.iv.mpf
        An interval containing ``sin(t)`` for every ``t`` in ``x``.
    """
    return iv.sin(x)


def cos(x):
    """Enclosure of ``cos(x)`` (``mpmath.iv.cos``).

    Parameters
    ----------
    x : mpmath.iv.mpf
        The interval, radians.

    Returns
    -------
    mpmath.iv.mpf
        An interval containing ``cos(t)`` for every ``t`` in ``x``.
    """
    return iv.cos(x)


def div(x, y):
    """Enclosure of ``x / y``; the whole line when ``y`` contains 0.

    Parameters
    ----------
    x, y : mpmath.iv.mpf
        Dividend and divisor.

    Returns
    -------
    mpmath.iv.mpf
        An interval containing ``s / t`` for every ``s`` in ``x`` and ``t`` in ``y``; ``[-inf, +inf]`` (which
        decides nothing) when ``y`` contains 0.
    """
    if y.a <= 0 <= y.b:
        return _undefined()
    return x / y


def iabs(x):
    """Enclosure of ``abs(x)``.

    Parameters
    ----------
    x : mpmath.iv.mpf
        The interval.

    Returns
    -------
    mpmath.iv.mpf
        ``{|t| : t in x}``, exactly (no rounding needed).
    """
    if x.a >= 0:
        return x
    if x.b <= 0:
        return -x
    return iv.mpf([0, max(-x.a, x.b)])
