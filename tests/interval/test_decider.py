"""The numpy decider of a paving (issue 28 item 3): one forward sweep for every constraint, exact comparisons.

References: exact rational arithmetic (Fractions) on the box's corners, where the enclosure of the constraint's
variable part is exact (a variable), so the decision must be exact too; the mpmath backend at 100 digits as an
independent second decider; the node count of Rybak's four constraints written out by hand.
"""

import math
from fractions import Fraction

import numpy as np
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from workspace_sym import robots
from workspace_sym.interval.paving import _decider, _setup
from workspace_sym.interval.verdict import INSIDE, OUTSIDE, UNDECIDED

x, y = sp.symbols("x y")
BOX = {x: (-4, 4), y: (0, 1)}


def _step(t: float, k: int) -> float:
    """``t`` moved ``k`` floats up (down when ``k < 0``)."""
    for _ in range(abs(k)):
        t = math.nextafter(t, math.inf if k > 0 else -math.inf)
    return t


def _decide(constraint, lo, hi):
    cons, box = _setup([constraint], BOX, None)
    return int(_decider(cons, box.variables, "numpy", 30)(np.array([[[lo, hi], [0.0, 1.0]]]))[0])


@settings(derandomize=True, max_examples=300, deadline=None)
@given(st.sampled_from([1, -1]), st.booleans(), st.floats(-1e3, 1e3, allow_nan=False, allow_subnormal=True),
       st.integers(-2, 2), st.integers(0, 3))
@example(1, False, 3.0, 0, 0)          # x + 3 <= 0 on [-3, -3]: g = 0 exactly, inside
@example(1, True, 3.0, -1, 1)          # x + 3 < 0 on a box ending at -3: not inside, not outside
@example(-1, False, 0.1, 0, 2)         # 0.1 - x <= 0 with the float 0.1 exactly on the box's corner
@example(1, False, 5e-324, -1, 0)      # a subnormal constant
def test_a_constraint_against_a_float_constant_is_decided_exactly(sign, strict, c, start, width):
    """``sign * x + c <= 0`` (or ``< 0``) with ``c`` a float: the enclosure of ``x`` is the box itself, so the
    decider must prove inside exactly when the largest value of ``g`` on the box meets the constraint, and outside
    exactly when the smallest violates it (exact rationals).  Rounding the sum ``e + c`` outward, as the decider
    did before, left the boxes whose corner is on the boundary undecided."""
    t = -sign * c                             # where g = 0
    lo = _step(t, start)
    hi = _step(lo, width)
    if not (-4 <= lo and hi <= 4):
        return
    g = sign * x + sp.Rational(Fraction(c))
    code = _decide(sp.StrictLessThan(g, 0) if strict else sp.LessThan(g, 0), lo, hi)
    values = [sign * Fraction(v) + Fraction(c) for v in (lo, hi)]
    top, bottom = max(values), min(values)
    inside = top < 0 if strict else top <= 0
    outside = bottom >= 0 if strict else bottom > 0
    assert code == (INSIDE if inside else OUTSIDE if outside else UNDECIDED), (lo, hi, values)


@settings(derandomize=True, max_examples=200, deadline=None)
@given(st.sampled_from([1, -1]), st.booleans(), st.integers(1, 60), st.integers(1, 60), st.integers(-3, 3),
       st.integers(0, 3))
@example(1, False, 1, 3, 0, 0)
@example(-1, True, 1, 10, 0, 1)
def test_a_rational_constant_is_never_rounded_into_a_false_verdict(sign, strict, p, q, start, width):
    """A constant that is no float (``1/3``, ``7/10``) is enclosed, and the decider's verdicts stay true in exact
    arithmetic at the box's corners (where ``g`` reaches its extremes), and agree with the mpmath backend."""
    c = Fraction(p, q)
    t = float(-sign * c)
    lo = _step(t, start)
    hi = _step(lo, width)
    g = sign * x + sp.Rational(p, q)
    constraint = sp.StrictLessThan(g, 0) if strict else sp.LessThan(g, 0)
    code = _decide(constraint, lo, hi)
    values = [sign * Fraction(v) + c for v in (lo, hi)]
    if code == INSIDE:
        assert all((v < 0) if strict else (v <= 0) for v in values)
    if code == OUTSIDE:
        assert all((v >= 0) if strict else (v > 0) for v in values)
    cons, box = _setup([constraint], BOX, None)
    reference = int(_decider(cons, box.variables, "mpmath", 100)(np.array([[[lo, hi], [0.0, 1.0]]]))[0])
    assert {code, reference} != {INSIDE, OUTSIDE}


def test_rybak_constraints_are_one_sweep_of_nine_nodes():
    """x1, x2, x1^2, x2^2, x1^2 + x2^2, the constant -5, x1 - 5, (x1 - 5)^2, (x1 - 5)^2 + x2^2: the four
    constraints have two distinct parts sharing x2^2, and the decider sweeps them once."""
    m = robots.build("rpr2")
    cons, box = _setup(m.constraints, m.box, None)
    decide = _decider(cons, box.variables, "numpy", 30)
    assert len(decide.graph.nodes) == 9 and len(decide.graph.roots) == 2
    assert [k for k, *_ in decide.tests] == [0, 0, 1, 1]
