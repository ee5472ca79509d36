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
    """A workspace ``{x in box : g_j(x) <= 0}`` with its provenance."""

    name: str
    variables: tuple
    constraints: tuple
    box: dict
    source: str
    units: str
    parameters: dict
    exact_measure: sp.Expr | None = None

    def pave(self, *, delta, **options):
        """:func:`workspace_sym.interval.pave` on this model (exact measure attached)."""
        from .interval import pave

        return pave(self.constraints, self.box, delta=delta, **options).with_exact_measure(self.exact_measure)


def lens_area(r, R, d) -> sp.Expr:
    """Exact area of the intersection of two discs of radii ``r``, ``R`` whose centres are ``d`` apart.

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
    """
    return sp.simplify((lens_area(lmax1, lmax2, l0) - lens_area(lmin1, lmax2, l0)
                        - lens_area(lmax1, lmin2, l0) + lens_area(lmin1, lmin2, l0)) / 2)


def rpr2(l0=5, lmin=8, lmax=12, *, lmin2=None, lmax2=None) -> ConstraintModel:
    """Rybak's planar 2-RPR robot (Rybak, Posypkin, Turkin 2016, section 4).

    Two legs of lengths in ``[lmin, lmax]`` from base joints at ``(0, 0)`` and
    ``(l0, 0)`` meet at the platform point ``(x1, x2)``; the initial box is
    ``[-lmax1, l0 + lmax2] x [0, min(lmax1, lmax2)]`` as in the paper.

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
