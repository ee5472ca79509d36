"""Numbers as a person or a script reads them: no negative zero, no float noise on exact values.

Float geometry leaves ``-59.99999999999999`` where the exact value is -60,
``7.95e-15`` where it is 0 and ``-0.0`` after a product with a negative
number.  :func:`clean` removes that noise from a value, :func:`fmt` formats
one for text, :func:`clean_json` removes negative zeros from a JSON tree.

Certified bounds must never be moved: :func:`clean_json` only turns ``-0.0``
into ``0.0`` (the same number), while :func:`clean` snaps to a nearby short
decimal and is meant for float-geometry values (angles of a boundary, centres
of arcs), not for the ends of a proved bracket.

Examples
--------
>>> clean(-59.99999999999999), clean(7.95e-15, scale=360), clean(-0.0)
(-60.0, 0.0, 0.0)
>>> clean(0.2684793913989452)             # no short decimal nearby: unchanged
0.2684793913989452
>>> fmt(-1e-9, 4), fmt(-0.0, 2), fmt(-2.5, 1)
('0.0000', '0.00', '-2.5')
"""

from __future__ import annotations

import math
import re

__all__ = ["clean", "fmt", "fmt_bracket", "clean_json"]

_NOISE = 1e-12          # relative size of the float noise that clean() removes
_SHORT = 9              # a "short" decimal has at most this many significant digits


def clean(x, *, scale: float = 1.0):
    """``x`` without float noise: 0.0 when ``|x| <= 1e-12 * scale``, the nearest decimal of at most 9 significant
    digits when ``x`` is within ``1e-12 * |x|`` of it, else ``x`` itself; never ``-0.0``.

    ``scale`` is the size of the quantity's range (360 for angles in degrees,
    the reach for lengths), below which a value is taken as zero.  Integers,
    non-finite values and anything that is not a real number are returned as
    they are (integers and NaN have no noise to remove).
    """
    if isinstance(x, int):                  # bool and int: exact already
        return x
    try:
        v = float(x)
    except (TypeError, ValueError):
        return x
    if not math.isfinite(v):
        return v
    if abs(v) <= _NOISE * scale:
        return 0.0
    short = float(f"{v:.{_SHORT}g}")
    if abs(short - v) <= _NOISE * abs(v):
        v = short
    return v + 0.0                          # -0.0 + 0.0 is +0.0


_NEGATIVE_ZERO = re.compile(r"^-(?=[0.]*(?:e[-+]?\d+)?%?$)")


def fmt(x, digits: int = 4, spec: str = "f") -> str:
    """``format(x, f".{digits}{spec}")`` with the minus sign dropped when every printed digit is zero.

    ``spec`` is a float presentation type (``"f"``, ``"g"``, ``"e"``, ``"%"``).
    """
    text = format(float(x), f".{digits}{spec}")
    return _NEGATIVE_ZERO.sub("", text)


def fmt_bracket(lo, hi, digits: int = 4) -> str:
    """``"[lo, hi]"`` with ``digits`` decimals, ``lo`` rounded down and ``hi`` up: the printed bracket still holds
    the certified one (``fmt`` would round to nearest and could cut it).

    Examples
    --------
    >>> fmt_bracket(4.6318359375, 7.27734375)
    '[4.6318, 7.2774]'
    >>> fmt_bracket(-1e-12, 0.0, 6)
    '[-0.000001, 0.000000]'
    """
    from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal

    quantum = Decimal(1).scaleb(-digits)
    down = Decimal(float(lo)).quantize(quantum, rounding=ROUND_FLOOR)      # Decimal(float) is the float exactly
    up = Decimal(float(hi)).quantize(quantum, rounding=ROUND_CEILING)
    return f"[{_NEGATIVE_ZERO.sub('', str(down))}, {_NEGATIVE_ZERO.sub('', str(up))}]"


def clean_json(obj):
    """A copy of a JSON tree (dicts, lists, tuples, numbers, strings) with every ``-0.0`` replaced by ``0.0``.

    Values are otherwise unchanged (certified bounds stay bit for bit what
    they were); tuples become lists, as JSON writes them anyway.
    """
    if isinstance(obj, float):
        return obj + 0.0
    if isinstance(obj, dict):
        return {k: clean_json(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [clean_json(v) for v in obj]
    if type(obj).__module__ == "numpy" and hasattr(obj, "item"):
        return clean_json(obj.item())
    return obj
