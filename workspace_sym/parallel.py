"""Parallel robots described by inequality constraints on the platform position.

:class:`ConstraintModel` is what :func:`workspace_sym.pave` needs (variables,
inequalities, an initial box) plus what a report prints (source, units, the
exact measure when it is known in closed form).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .errors import InvalidParameterError
from .expressions import parse_expr

__all__ = ["ConstraintModel", "rpr2", "lens_area", "rpr2_exact_area"]


@dataclass(frozen=True)
class ConstraintModel:
    """A workspace ``{x in box : g_j(x) <= 0}`` with its provenance.

    Parameters
    ----------
    name : str
        The model's name (``"rpr2"``).
    variables : tuple of sympy.Symbol
        The platform coordinates.
    constraints : tuple of sympy.Rel
        The inequalities that define the workspace.
    box : dict
        ``{variable: (lo, hi)}``: the initial box of the paving.
    source : str
        The publication the model comes from.
    units : str
        The unit of lengths.
    parameters : dict
        The dimensions used, by name.
    exact_measure : sympy.Expr or None, optional
        The area (or volume) of the workspace in closed form, when known.
    """

    name: str
    variables: tuple
    constraints: tuple
    box: dict
    source: str
    units: str
    parameters: dict
    exact_measure: sp.Expr | None = None

    def pave(self, *, delta, **options):
        """:func:`workspace_sym.interval.pave` on this model (exact measure attached).

        Parameters
        ----------
        delta : float
            Undecided boxes whose size is at most ``delta`` become boundary boxes.
        **options
            The other keywords of :func:`~workspace_sym.interval.pave` (``backend``, ``size``, ``contract``,
            ``stop``, ``run``...).

        Returns
        -------
        Paving
            The paving of :attr:`constraints` over :attr:`box`, with :attr:`exact_measure` attached.
        """
        from .interval import pave

        return pave(self.constraints, self.box, delta=delta, **options).with_exact_measure(self.exact_measure)


def lens_area(r, R, d) -> sp.Expr:
    """Exact area of the intersection of two discs of radii ``r``, ``R`` whose centres are ``d`` apart.

    Parameters
    ----------
    r, R : number or sympy.Expr
        The radii, non-negative; a float is read as the simple rational near it (:func:`sympy.nsimplify`).
    d : number or sympy.Expr
        The distance between the centres, non-negative.

    Returns
    -------
    sympy.Expr
        The area: 0 when the discs are apart or tangent outside, that of the smaller disc when one holds the
        other.

    Examples
    --------
    >>> lens_area(1, 1, 0)
    pi
    >>> lens_area(1, 1, 2)
    0
    >>> lens_area(1, 1, 1)
    -sqrt(3)/2 + 2*pi/3
    """
    r, R, d = map(sp.nsimplify, (r, R, d))
    if d >= r + R:
        return sp.Integer(0)
    if d <= abs(R - r):
        return sp.pi * sp.Min(r, R) ** 2
    # Two circular segments; the chord is where the circles meet.
    alpha = sp.acos((d**2 + r**2 - R**2) / (2 * d * r))
    beta = sp.acos((d**2 + R**2 - r**2) / (2 * d * R))
    kite = sp.sqrt((-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R)) / 2
    return sp.simplify(r**2 * alpha + R**2 * beta - kite)


def rpr2_exact_area(l0, lmin1, lmax1, lmin2, lmax2) -> sp.Expr:
    """Area of the 2-RPR workspace in the half-plane ``x2 >= 0``, in closed form.

    The workspace is the intersection of the annuli ``lmin1 <= |x| <= lmax1``
    and ``lmin2 <= |x - (l0, 0)| <= lmax2``; by inclusion-exclusion over the
    four discs ``|A1 n A2| = L(M1, M2) - L(m1, M2) - L(M1, m2) + L(m1, m2)``
    with ``L`` the lens area, and the half-plane holds half of it by symmetry.

    Parameters
    ----------
    l0 : number or sympy.Expr
        The distance between the base joints.
    lmin1, lmax1 : number or sympy.Expr
        The range of the first leg's length.
    lmin2, lmax2 : number or sympy.Expr
        The range of the second leg's length.

    Returns
    -------
    sympy.Expr
        The area, simplified.
    """
    return sp.simplify((lens_area(lmax1, lmax2, l0) - lens_area(lmin1, lmax2, l0)
                        - lens_area(lmax1, lmin2, l0) + lens_area(lmin1, lmin2, l0)) / 2)


def rpr2(l0=5, lmin=8, lmax=12, *, lmin2=None, lmax2=None) -> ConstraintModel:
    """Rybak's planar 2-RPR robot (Rybak, Posypkin, Turkin 2016, section 4).

    Two legs of lengths in ``[lmin, lmax]`` from base joints at ``(0, 0)`` and
    ``(l0, 0)`` meet at the platform point ``(x1, x2)``; the initial box is
    ``[-lmax1, l0 + lmax2] x [0, min(lmax1, lmax2)]`` as in the paper.

    Parameters
    ----------
    l0 : number or str, default 5
        The distance between the base joints, positive.  Text is read by the restricted grammar
        (:func:`~workspace_sym.expressions.parse_expr`, no symbols).
    lmin, lmax : number or str, default 8 and 12
        The range of the legs' lengths, ``0 <= lmin < lmax`` (of the first leg alone when the second has its
        own).
    lmin2, lmax2 : number or str, optional
        The range of the second leg, by default that of the first.

    Returns
    -------
    ConstraintModel
        The four annulus constraints on ``(x1, x2)``, the box and the exact area (:func:`rpr2_exact_area`).

    Raises
    ------
    InvalidParameterError
        When a dimension is not a real number, ``l0`` is not positive or a leg range is not
        ``0 <= lmin < lmax``.
    ExpressionError
        When a dimension given as text cannot be read.

    Examples
    --------
    >>> m = rpr2()
    >>> m.box
    {x1: (-12, 17), x2: (0, 12)}
    >>> round(float(m.exact_measure), 6)
    35.05335
    """
    l0, lmin1, lmax1 = (parse_expr(v, n, new_symbols=False) for v, n in ((l0, "l0"), (lmin, "lmin"), (lmax, "lmax")))
    lmin2 = lmin1 if lmin2 is None else parse_expr(lmin2, "lmin2", new_symbols=False)
    lmax2 = lmax1 if lmax2 is None else parse_expr(lmax2, "lmax2", new_symbols=False)
    for name, v in (("l0", l0), ("lmin", lmin1), ("lmax", lmax1), ("lmin2", lmin2), ("lmax2", lmax2)):
        if not v.is_number or not v.is_real:
            raise InvalidParameterError(f"{name} must be a real number; got {v}", parameter=name)
    if not l0 > 0:
        raise InvalidParameterError(f"l0 must be positive; got {l0}", parameter="l0")
    for lo_name, lo, hi_name, hi in (("lmin", lmin1, "lmax", lmax1), ("lmin2", lmin2, "lmax2", lmax2)):
        if not 0 <= lo < hi:
            raise InvalidParameterError(f"leg range needs 0 <= {lo_name} < {hi_name}; got {lo_name} = {lo}, "
                                        f"{hi_name} = {hi}")
    x1, x2 = sp.symbols("x1 x2", real=True)
    constraints = (
        x1**2 + x2**2 - lmax1**2 <= 0,
        lmin1**2 - x1**2 - x2**2 <= 0,
        (x1 - l0) ** 2 + x2**2 - lmax2**2 <= 0,
        lmin2**2 - (x1 - l0) ** 2 - x2**2 <= 0,
    )
    box = {x1: (-lmax1, l0 + lmax2), x2: (0, sp.Min(lmax1, lmax2))}
    return ConstraintModel(
        name="rpr2", variables=(x1, x2), constraints=constraints, box=box,
        source="L. A. Rybak, M. A. Posypkin, A. V. Turkin, Method for approximating the workspace of the "
               "parallel robot, IJPT 2016",
        units="length units of the paper", parameters={"l0": l0, "lmin": lmin1, "lmax": lmax1,
                                                       "lmin2": lmin2, "lmax2": lmax2},
        exact_measure=rpr2_exact_area(l0, lmin1, lmax1, lmin2, lmax2),
    )
