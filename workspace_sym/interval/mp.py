"""The arbitrary-precision reference backend: ``mpmath.iv``, one box at a time.

``mpmath.iv`` rounds outward at its working precision.  Two traps are avoided
here: it has no ``workprec`` (:func:`precision` restores the precision in
``finally``), and its comparisons of overlapping intervals return ``None``,
which ``if`` would read as False; every decision compares endpoints
(``x.a``, ``x.b``) explicitly.
"""

from __future__ import annotations

from contextlib import contextmanager

import mpmath

__all__ = ["precision", "iv", "from_float_bounds", "sqrt", "sqr", "ipow", "sin", "cos", "div",
           "iabs", "const_rational", "const_float"]

iv = mpmath.iv


@contextmanager
def precision(digits: int | None = None, *, bits: int | None = None):
    """Set ``mpmath.iv``'s precision inside a ``with`` block, restored afterwards.

    Examples
    --------
    >>> with precision(50):
    ...     iv.dps
    50
    >>> iv.dps
    15
    """
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
    """The exact interval ``[lo, hi]`` of two floats (floats are exact binary numbers)."""
    return iv.mpf([lo, hi])


def const_rational(p: int, q: int):
    return iv.mpf(p) / iv.mpf(q)


def const_float(text: str):
    """Enclosure of a decimal literal such as ``"0.1"`` (mpmath rounds the string outward)."""
    return iv.mpf(text)


def _undefined():
    # mpmath.iv has no NaN interval; use the whole line, which decides nothing.
    return iv.mpf(["-inf", "inf"])


def sqr(x):
    a, b = x.a, x.b
    if a >= 0:
        return x * x
    if b <= 0:
        return x * x
    m = max(-a, b)
    return iv.mpf([0, (iv.mpf(m) * iv.mpf(m)).b])


def ipow(x, n: int):
    if n == 2:
        return sqr(x)
    if n % 2 == 0 and x.a < 0 < x.b:
        m = iv.mpf(max(-x.a, x.b))
        return iv.mpf([0, (m**n).b])
    return x**n


def sqrt(x):
    if x.a < 0:
        return None  # domain error: the caller decides nothing for this box
    return iv.sqrt(x)


def sin(x):
    return iv.sin(x)


def cos(x):
    return iv.cos(x)


def div(x, y):
    if y.a <= 0 <= y.b:
        return _undefined()
    return x / y


def iabs(x):
    if x.a >= 0:
        return x
    if x.b <= 0:
        return -x
    return iv.mpf([0, max(-x.a, x.b)])
