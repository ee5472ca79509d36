"""Float input made exact where it clearly is, every replacement recorded.

Robot descriptions copied from datasheets, other toolboxes or URDF files hold
floats: ``alpha = 1.5707963267948966``, ``a = 0.4318``.  Kept as floats they
leave ``2.6e-17*sin(q1)`` terms in every product and make the exact machinery
(textbook form, singular factors) crawl.  A :class:`Snapper` reads them as
exact values by two rules:

- an **angle** (radians) within ``tol`` of a multiple of ``pi/360`` (every
  whole and half degree: ``pi/2``, ``pi/3``, ``pi/8``, ``37*pi/36``) becomes
  that multiple; so does an angle written with at least
  ``ROUNDED_DIGITS`` significant digits that lies within two units of its
  last digit of such a multiple: ROS files write ``pi/2`` as ``1.570796325``
  (1.8e-9 away) and ``pi`` as ``3.14159265``, and a float written to ten
  digits says no more than ten digits (a random angle lands that close to the
  grid with odds below 1 in 10,000; ``tol = 0`` turns this rule off too);
  any other angle stays the float it was (nothing suggests an exact value)
  **(choice)**;
- a **length** becomes the shortest decimal that the float stands for
  (``0.4318`` is ``2159/5000``), the decimal the file or the user wrote.

Each replacement is kept in :attr:`Snapper.notes` (a rounded angle's note says
that ``exact=False``, ``--keep-floats`` on the command line, keeps the float);
an angle that is close to a multiple of ``pi/360`` but snaps by neither rule
(``1.5708`` is ``3.7e-6`` from ``pi/2``) gets a note too, saying which
tolerance would snap it.

With ``exact=False`` nothing is snapped: floats stay floats, and
:func:`chop` removes the terms below ``tol`` that their products leave.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from decimal import Decimal
from functools import cache

import sympy as sp

from .errors import DHTableError, InvalidParameterError
from .expressions import as_sympy

__all__ = ["Snapper", "exact_decimal", "snap_angle", "written_unit", "chop", "summary", "ANGLE_GRID", "DEFAULT_TOL",
           "ROUNDED_DIGITS"]

#: Angles snap to multiples of ``pi / ANGLE_GRID`` (whole and half degrees).
ANGLE_GRID = 360
#: Default snapping (and chopping) tolerance, radians for angles.
DEFAULT_TOL = 1e-9
# An angle this close to the grid but beyond tol is worth a note (a URDF's 1.5708 is 3.7e-6 from pi/2).
_NEAR = 1e-4
#: An angle written with at least this many significant digits snaps within two units of its last digit.
ROUNDED_DIGITS = 8
# The shortest decimal may differ from the float by a few units in the last place
# (0.30000000000000004 is 0.3): floats that went through arithmetic lose their last bit.
_ULPS = 4


def check_tol(tol) -> float:
    """``tol`` as a float, which must be finite and non-negative."""
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not math.isfinite(tol) or tol < 0:
        raise InvalidParameterError(f"tol must be a finite number >= 0; got {tol!r}", parameter="tol")
    return float(tol)


def snap_angle(value: float, tol: float = DEFAULT_TOL) -> sp.Expr | None:
    """The multiple of ``pi/360`` within ``tol`` of ``value`` (radians), or ``None``.

    Parameters
    ----------
    value : float
        The angle, in radians.
    tol : float
        The largest distance accepted, in radians (default :data:`DEFAULT_TOL`).

    Returns
    -------
    sympy.Expr or None
        ``k*pi/360`` for the nearest multiple when it lies within ``tol``; None otherwise, and for a value so
        large that no multiple can be found.

    Examples
    --------
    >>> snap_angle(1.5707963267948966)
    pi/2
    >>> snap_angle(3.22885911619)      # 185 degrees, as KUKA URDF limits write it
    37*pi/36
    >>> snap_angle(1.5708) is None     # 3.7e-6 away: a rounded pi/2, but not within 1e-9
    True
    """
    turns = value * ANGLE_GRID / math.pi
    if not math.isfinite(turns):          # 1e308 rad: no multiple of pi/360 is within any tolerance worth having
        return None
    k = round(turns)
    if abs(value - k * math.pi / ANGLE_GRID) <= tol:
        return sp.Rational(k, ANGLE_GRID) * sp.pi
    return None


def exact_decimal(value: float) -> sp.Rational:
    """The shortest decimal within a few units in the last place of ``value``, as a Rational.

    Parameters
    ----------
    value : float
        The number.

    Returns
    -------
    sympy.Rational or sympy.Float
        The decimal, as a Rational (0 for zero); a value that is not finite comes back as a ``Float``.

    Examples
    --------
    >>> exact_decimal(0.4318)
    2159/5000
    >>> exact_decimal(0.1 + 0.2)
    3/10
    >>> exact_decimal(-9.8483e-05)
    -98483/1000000000
    """
    if value == 0 or not math.isfinite(value):
        return sp.Rational(0) if value == 0 else sp.Float(value)
    return sp.Rational(_shortest(value))


def _shortest(value: float) -> str:
    """The shortest decimal text within :data:`_ULPS` units in the last place of ``value`` (nonzero, finite)."""
    slack = _ULPS * math.ulp(value)
    for digits in range(1, 18):
        text = f"{value:.{digits}g}"
        if abs(float(text) - value) <= slack:
            return text
    return repr(value)


def written_unit(value: float) -> tuple[int, float]:
    """``(digits, unit)``: significant digits of the decimal ``value`` was written as, and its last digit's unit.

    Parameters
    ----------
    value : float
        The number, taken to be written as its shortest decimal (:func:`exact_decimal`).

    Returns
    -------
    tuple of (int, float)
        The number of significant digits and the unit of the last one; ``(1, 1.0)`` for zero and for a value that
        is not finite.

    Examples
    --------
    >>> written_unit(1.570796325)
    (10, 1e-09)
    >>> written_unit(-3.14159265)
    (9, 1e-08)
    """
    if value == 0 or not math.isfinite(value):
        return 1, 1.0
    written = Decimal(_shortest(value)).normalize().as_tuple()
    assert isinstance(written.exponent, int)         # 'n', 'N', 'F' only for NaN and infinities, returned above
    return len(written.digits), 10.0 ** written.exponent


def chop(expr, tol: float):
    """``expr`` with every float coefficient of magnitude below ``tol`` set to zero.

    Works on expressions and matrices; exact numbers are left alone.

    Parameters
    ----------
    expr : SymPy expression, matrix, number or str
        What to chop; text is read by :func:`~workspace_sym.expressions.parse_expr`.
    tol : float
        Float coefficients of magnitude below it become 0.

    Returns
    -------
    sympy.Basic or sympy.Matrix
        The chopped expression, or matrix entry by entry.

    Raises
    ------
    ExpressionError
        When ``expr`` is text that cannot be read, or of another type (from
        :func:`~workspace_sym.expressions.as_sympy`).

    Examples
    --------
    >>> q = sp.Symbol("q")
    >>> chop(6.123e-17 * sp.sin(q) + 1.0 * sp.cos(q), 1e-9)
    1.0*cos(q)
    """
    if isinstance(expr, sp.MatrixBase):
        return expr.applyfunc(lambda e: chop(e, tol))
    expr = as_sympy(expr, "expr")                 # text through the restricted parser, never sympify
    small = {f: sp.Integer(0) for f in expr.atoms(sp.Float) if abs(f) < tol}
    return expr.xreplace(small) if small else expr


def _differs(exact: sp.Expr, value: float) -> bool:
    """Whether ``exact`` is another number than the float (``1/2`` is ``0.5``; ``pi/2`` is not a float)."""
    return not (exact.is_Rational and sp.Rational(value) == exact)


@dataclass
class Snapper:
    """Reads floats as exact values (or keeps them, with ``exact=False``) and records each replacement.

    Parameters
    ----------
    exact : bool
        Snap angles and read lengths as decimals (default); ``False`` keeps floats.
    tol : float
        Angles within ``tol`` radians of a multiple of ``pi/360`` snap; with
        ``exact=False`` it is the chopping threshold.  Default :data:`DEFAULT_TOL`.
    notes : list of str
        The notes written so far (default empty): one sentence per replacement and per near miss is appended.
    error : type
        The :class:`~workspace_sym.errors.WorkspaceError` subclass raised, naming the field, for a number that is
        not finite (default :class:`~workspace_sym.errors.DHTableError`; the URDF reader passes ``URDFError``).

    Raises
    ------
    InvalidParameterError
        When ``tol`` is not a finite number >= 0.

    Examples
    --------
    >>> s = Snapper()
    >>> s.angle(1.5707963267948966, "joint 1 alpha"), s.length(0.4318, "joint 2 a")
    (pi/2, 2159/5000)
    >>> s.notes
    ['joint 1 alpha: 1.5707963267948966 -> pi/2', 'joint 2 a: 0.4318 -> 2159/5000']
    >>> s.angle(1.570796325, "j1 rpy"), s.notes[-1]         # doctest: +ELLIPSIS
    (pi/2, 'j1 rpy: 1.570796325 -> pi/2 (it is written to 10 digits; exact=False, or --keep-floats, keeps the float)')
    >>> s.angle(1.5708, "j2 rpy"), s.notes[-1]              # doctest: +ELLIPSIS
    (1.57080000000000, 'j2 rpy: 1.5708 kept as a float: it is 3.7e-06 rad from pi/2, above tol = 1e-09 ...')
    >>> s.angle(90.0, "joint 3 alpha", degrees=True)
    pi/2
    """

    exact: bool = True
    tol: float = DEFAULT_TOL
    #: One sentence per replacement (and per near miss).
    notes: list[str] = field(default_factory=list)
    #: Raised, naming the field, for a number that is not finite (NaN or infinite) or too large.
    error: type = field(default=DHTableError, repr=False)

    def __post_init__(self):
        self.tol = check_tol(self.tol)

    def _finite(self, value, where: str, *, degrees: bool = False) -> float:
        """``value`` as a float, refused (:attr:`error`) unless finite, also once in radians."""
        number = float(value)
        if not math.isfinite(number) or (degrees and not math.isfinite(math.radians(number))):
            raise self.error(f"{where}: expected a finite number; got {number!r}", parameter=where)
        return number

    def angle(self, value, where: str, *, degrees: bool = False) -> sp.Expr:
        """An angle, returned in radians: snapped to ``k pi / 360`` within ``tol`` radians, else the float.

        Parameters
        ----------
        value : float
            The angle as given (anything ``float`` accepts).
        where : str
            What the value is (``"joint 1 alpha"``), for the notes and the error.
        degrees : bool
            Whether ``value`` is in degrees (default False: radians).

        Returns
        -------
        sympy.Expr
            The angle in radians: the snapped multiple of ``pi/360``, or the float (times ``pi/180`` for
            degrees); with ``exact=False`` always the float.

        Raises
        ------
        WorkspaceError
            Of the class :attr:`error`, when the value is not finite (in radians too).
        """
        value = self._finite(value, where, degrees=degrees)
        radians = math.radians(value) if degrees else value
        kept = sp.Float(value) * sp.pi / 180 if degrees else sp.Float(value)
        if not self.exact:
            return kept
        snapped, rounded = snap_angle(radians, self.tol), ""
        if snapped is None:
            digits, unit = written_unit(value)
            if digits >= ROUNDED_DIGITS and self.tol > 0:      # tol = 0: only floats on the grid snap
                snapped = snap_angle(radians, 2 * (math.radians(unit) if degrees else unit))
                rounded = (f" (it is written to {digits} digits; exact=False, or --keep-floats, keeps the float)")
        if snapped is not None:
            exact_given = snapped * 180 / sp.pi if degrees else snapped
            if _differs(exact_given, value):
                self.notes.append(f"{where}: {value!r} -> {sp.sstr(exact_given)}{rounded}")
            return snapped
        near = snap_angle(radians, _NEAR)
        if near is not None:
            gap = abs(radians - float(near))
            self.notes.append(f"{where}: {value!r} kept as a float: it is {gap:.2g} rad from "
                                          f"{sp.sstr(near)}, above tol = {self.tol:g} (a larger tol would snap it)")
        return kept

    def length(self, value, where: str) -> sp.Expr:
        """A length (or any non-angle number): the decimal it spells, or the float with ``exact=False``.

        Parameters
        ----------
        value : float
            The number as given (anything ``float`` accepts).
        where : str
            What the value is (``"joint 2 a"``), for the notes and the error.

        Returns
        -------
        sympy.Expr
            The decimal as a Rational (:func:`exact_decimal`), or a ``Float`` with ``exact=False``.

        Raises
        ------
        WorkspaceError
            Of the class :attr:`error`, when the value is not finite.
        """
        value = self._finite(value, where)
        if not self.exact:
            return sp.Float(value)
        exact = exact_decimal(value)
        if _differs(exact, value):
            self.notes.append(f"{where}: {value!r} -> {sp.sstr(exact)}")
        return exact

    def cosine(self, value, where: str) -> sp.Expr:
        """An entry of a rotation matrix or a unit axis: ``cos(k pi/12)`` within ``tol``, else :meth:`length`.

        ``0, 1/2, sqrt(2)/2, sqrt(3)/2, 1`` and their negatives (and the
        ``(sqrt(6) +- sqrt(2))/4`` of 15 and 75 degrees) are the exact values
        such entries take in real robots.

        Parameters
        ----------
        value : float
            The entry as given (anything ``float`` accepts).
        where : str
            What the value is, for the notes and the error.

        Returns
        -------
        sympy.Expr
            The exact cosine within ``tol``, else as :meth:`length`; a ``Float`` with ``exact=False``.

        Raises
        ------
        WorkspaceError
            Of the class :attr:`error`, when the value is not finite.
        """
        value = self._finite(value, where)
        if not self.exact:
            return sp.Float(value)
        for candidate, approx in _cosines():
            if abs(value - approx) <= self.tol:
                if _differs(candidate, value):
                    self.notes.append(f"{where}: {value!r} -> {sp.sstr(candidate)}")
                return candidate
        return self.length(value, where)

    def chop(self, expr):
        """``expr`` chopped below ``tol`` when floats are kept; unchanged in exact mode.

        Parameters
        ----------
        expr : SymPy expression or matrix
            What to chop.

        Returns
        -------
        sympy.Basic or sympy.Matrix
            ``expr`` itself in exact mode, else :func:`chop` ``(expr, tol)``.
        """
        return expr if self.exact else chop(expr, self.tol)


@cache
def _cosines() -> tuple:
    """``(cos(k pi/12), float)`` and the negatives, ``k = 0 .. 12``, in the order :meth:`Snapper.cosine` tries."""
    out = []
    for k in range(13):
        exact = sp.cos(k * sp.pi / 12)
        out += [(c, float(c)) for c in ((exact, -exact) if exact != 0 else (exact,))]
    return tuple(out)


def summary(notes) -> str:
    """One line for the command line: snapped angles in full, decimals and near misses counted.

    Reads the notes a :class:`Snapper` writes; other notes (how a URDF chain
    became a DH table) are left to ``robot.input_notes``.

    Parameters
    ----------
    notes : iterable of str
        The notes, as :attr:`Snapper.notes` holds them.

    Returns
    -------
    str
        The line, ending with where the notes are; the empty string when no note is a snapper's.

    Examples
    --------
    >>> s = Snapper()
    >>> _ = s.angle(1.5707963267948966, "joint 1 alpha"), s.length(0.4318, "joint 2 a"), s.angle(3.1416, "limit")
    >>> summary(s.notes)
    'joint 1 alpha: 1.5707963267948966 -> pi/2; 1 float read as the decimal written; 1 angle near a multiple \
of pi/360 kept as a float (above tol); all in robot.input_notes'
    """
    snapped, decimals, near = [], 0, 0
    for note in notes:
        if " kept as a float" in note:
            near += 1
        elif " -> " in note:
            if note.rsplit(" -> ", 1)[1].lstrip("-").replace("/", "").isdigit():
                decimals += 1
            else:
                snapped.append(note)
    parts = snapped
    if decimals:
        plural = "s" if decimals > 1 else ""
        parts.append(f"{decimals} float{plural} read as the decimal{plural} written")
    if near:
        plural = "s" if near > 1 else ""
        parts.append(f"{near} angle{plural} near a multiple of pi/360 kept as {'floats' if plural else 'a float'} "
                     "(above tol)")
    return "; ".join(parts) + "; all in robot.input_notes" if parts else ""
