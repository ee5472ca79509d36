"""Numbers as a person or a script reads them: no negative zero, no float noise on exact values.

Float geometry leaves ``-59.99999999999999`` where the exact value is -60,
``7.95e-15`` where it is 0 and ``-0.0`` after a product with a negative
number.  :func:`clean` removes that noise from a value, :func:`fmt` formats
one for text, :func:`clean_json` removes negative zeros from a JSON tree.

Certified bounds must never be moved: :func:`clean_json` only turns ``-0.0``
into ``0.0`` (the same number), while :func:`clean` snaps to a nearby short
decimal and is meant for float-geometry values (angles of a boundary, centres
of arcs), not for the ends of a proved bracket.

:func:`md_escape` makes plain text inert in Markdown, for the tables a
result shows in a notebook and for reports (:mod:`workspace_sym.report`).

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

__all__ = ["clean", "fmt", "fmt_bound", "fmt_bracket", "measure_text", "clean_json", "md_escape"]

_NOISE = 1e-12          # relative size of the float noise that clean() removes
_SHORT = 9              # a "short" decimal has at most this many significant digits


def clean(x, *, scale: float = 1.0):
    """``x`` without float noise: 0.0 when ``|x| <= 1e-12 * scale``, the nearest decimal of at most 9 significant
    digits when ``x`` is within ``1e-12 * |x|`` of it, else ``x`` itself; never ``-0.0``.

    ``scale`` is the size of the quantity's range (360 for angles in degrees,
    the reach for lengths), below which a value is taken as zero.  Integers,
    non-finite values and anything that is not a real number are returned as
    they are (integers and NaN have no noise to remove).

    Parameters
    ----------
    x : number or object
        The value; anything ``float()`` accepts is cleaned.
    scale : float
        The size of the quantity's range (default 1.0).

    Returns
    -------
    float or object
        The cleaned float; ``x`` itself when it is an int or bool or ``float(x)`` fails; ``float(x)`` when that
        is not finite.
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

    Parameters
    ----------
    x : real number
        The value (converted with ``float``).
    digits : int
        The precision of the format (default 4).
    spec : str
        The presentation type (default ``"f"``).

    Returns
    -------
    str
        The formatted number.
    """
    text = format(float(x), f".{digits}{spec}")
    return _NEGATIVE_ZERO.sub("", text)


def fmt_bound(x, digits: int = 4, spec: str = "f", *, up: bool) -> str:
    """``x`` printed with ``digits`` decimals (``spec="f"``) or significant digits (``spec="g"``), rounded up
    (``up=True``) or down, never to nearest: the printed number stays on the proved side of a certified bound.

    Every certified bound the package prints or writes as text goes through
    this function (or :func:`fmt_bracket`); a lower bound rounded to nearest
    could print above the proved one.

    Parameters
    ----------
    x : real number
        The bound (converted with ``float``, then rounded from that float's exact value).
    digits : int
        Decimals with ``spec="f"`` (default 4); significant digits with ``spec="g"``, taken between 1 and 15.
    spec : {"f", "g"}
        Fixed-point or significant-digit form.
    up : bool
        True to round towards +inf (an upper bound), False towards -inf (a lower bound).

    Returns
    -------
    str
        The rounded number, without a minus sign when every printed digit is zero; ``"inf"``, ``"-inf"`` or
        ``"nan"`` for a value that is not finite.

    Raises
    ------
    ValueError
        When ``spec`` is neither ``"f"`` nor ``"g"``.

    Examples
    --------
    >>> fmt_bound(34.06668091, 6, "g", up=False), fmt_bound(36.04998779, 6, "g", up=True)
    ('34.0666', '36.05')
    >>> fmt_bound(0.1, 3, up=True), fmt_bound(-0.0001, 2, up=True), fmt_bound(9.99999, 3, "g", up=True)
    ('0.101', '0.00', '10')
    """
    from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal

    if spec not in ("f", "g"):
        raise ValueError(f"spec must be 'f' or 'g'; got {spec!r}")
    value = float(x)
    if not math.isfinite(value):
        return format(value, "g")
    exact = Decimal(value)                          # Decimal(float) is the float exactly
    rounding = ROUND_CEILING if up else ROUND_FLOOR
    if spec == "f":
        return _NEGATIVE_ZERO.sub("", format(exact.quantize(Decimal(1).scaleb(-digits), rounding=rounding), "f"))
    if value == 0:
        return "0"
    digits = min(max(digits, 1), 15)
    rounded = exact.quantize(Decimal(1).scaleb(exact.adjusted() - digits + 1), rounding=rounding)
    # ``rounded`` has at most digits + 1 <= 16 significant digits (9.99 -> 10.0), the last one a zero, so the float
    # nearest to it prints back as ``rounded`` exactly with ``digits`` significant digits.
    return _NEGATIVE_ZERO.sub("", format(float(rounded), f".{digits}g"))


def fmt_bracket(lo, hi, digits: int = 4, spec: str = "f") -> str:
    """``"[lo, hi]"`` with ``digits`` decimals (or significant digits with ``spec="g"``), ``lo`` rounded down and
    ``hi`` up: the printed bracket still holds the certified one (``fmt`` would round to nearest and could cut it).

    Parameters
    ----------
    lo, hi : real number
        The ends of the certified bracket.
    digits : int
        Decimals, or significant digits with ``spec="g"`` (default 4).
    spec : {"f", "g"}
        As for :func:`fmt_bound`.

    Returns
    -------
    str
        ``"[lo, hi]"`` with both ends rounded outwards.

    Raises
    ------
    ValueError
        When ``spec`` is neither ``"f"`` nor ``"g"`` (from :func:`fmt_bound`).

    Examples
    --------
    >>> fmt_bracket(4.6318359375, 7.27734375)
    '[4.6318, 7.2774]'
    >>> fmt_bracket(-1e-12, 0.0, 6)
    '[-0.000001, 0.000000]'
    >>> fmt_bracket(34.06668091, 36.04998779, 6, "g")
    '[34.0666, 36.05]'
    """
    return f"[{fmt_bound(lo, digits, spec, up=False)}, {fmt_bound(hi, digits, spec, up=True)}]"


def measure_text(kind: str, value, digits: int = 6, spec: str = "f") -> str:
    """The measure of one class of boxes of a paving, as text: the inner and outer measures are proved lower
    bounds (of the set and of its complement) and are rounded down; boundary and pending measures, which bound
    nothing alone, to nearest.

    Parameters
    ----------
    kind : str
        The class of boxes: ``"inner"`` and ``"outer"`` are rounded down, any other kind to nearest.
    value : real number
        The measure.
    digits : int
        Decimals, or significant digits with ``spec="g"`` (default 6).
    spec : str
        The presentation type (default ``"f"``; ``"f"`` or ``"g"`` for the inner and outer measures).

    Returns
    -------
    str
        The measure as text.

    Examples
    --------
    >>> measure_text("inner", 0.1234567), measure_text("boundary", 0.1234567)
    ('0.123456', '0.123457')
    """
    if kind in ("inner", "outer"):
        return fmt_bound(value, digits, spec, up=False)
    return fmt(value, digits, spec)


def clean_json(obj):
    """A copy of a JSON tree (dicts, lists, tuples, numbers, strings) with every ``-0.0`` replaced by ``0.0``.

    Values are otherwise unchanged (certified bounds stay bit for bit what
    they were); tuples become lists, as JSON writes them anyway.

    Parameters
    ----------
    obj : JSON-like value
        Dicts, lists, tuples, floats and other leaves; a NumPy scalar is turned into its Python value first.

    Returns
    -------
    object
        The copy; leaves other than floats and NumPy scalars are returned as they are.
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


_MD_SPECIAL = re.compile(r"[\\`*_|$~]")
_MD_LINE_START = re.compile(r"^(\s*)([#>=+-]|\d+[.)])")


def md_escape(text, *, block: bool = False) -> str:
    r"""Plain text made inert in Markdown (CommonMark and GitHub tables): on one line, markup characters
    backslash-escaped, ``<`` and ``&`` as entities (no inline HTML), no link; with ``block`` (a paragraph of
    its own) no block marker (heading, list, quote) at the start either.

    Parameters
    ----------
    text : object
        The text (``str(text)`` is escaped); runs of whitespace, newlines included, become one space.
    block : bool
        True when the text stands as a paragraph of its own: a block marker at its start is escaped too.

    Returns
    -------
    str
        The escaped text, on one line.

    Examples
    --------
    >>> print(md_escape("|p|^2 <b>x</b> & *a_1*"))
    \|p\|^2 &lt;b>x&lt;/b> &amp; \*a\_1\*
    >>> print(md_escape("# [site](http://x)\n- item", block=True))
    \# [site]\(http://x) - item
    """
    text = " ".join(str(text).split())
    text = text.replace("&", "&amp;").replace("<", "&lt;")
    text = _MD_SPECIAL.sub(lambda m: "\\" + m.group(), text).replace("](", "]\\(")
    return _MD_LINE_START.sub(lambda m: m.group(1) + "\\" + m.group(2), text) if block else text
