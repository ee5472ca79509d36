"""No false certificate: every box declared inner or outer is checked point by point in exact arithmetic.

Reference: an independent evaluator of the SymPy constraint at the float
coordinates of a box's corners and of random points inside it, exact with
``fractions.Fraction`` for the polynomial parts and with mpmath at 100
digits for sin, cos and sqrt.  It shares no code with the interval engines.

Constraints are drawn adversarially: coefficients from 1e-300 to 1e10, a
constant chosen so that the constraint vanishes at a point on a face of the
box (the root lies on or within a few floats of a face), and both paving
modes (plain and contracted) as well as single-box certificates on both
backends.  Issue 19's reproduction is pinned as an example.
"""

from __future__ import annotations

import functools
import itertools
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import workspace_sym as ws
from workspace_sym import StopAt
from workspace_sym.interval import Certificate

X, Y, Z = sp.symbols("x y z")
VARS = (X, Y, Z)


# ----------------------------------------------------------------------------- exact reference
def _mp(v):
    if isinstance(v, Fraction):
        return mpmath.mpf(v.numerator) / v.denominator
    return v


def exact(expr, point: dict):
    """``expr`` at ``point`` (floats taken as exact binary numbers): a Fraction, or an mpf at 100 digits."""
    return _evaluator(expr)(point)


@functools.cache
def _evaluator(expr):
    """:func:`exact` of ``expr`` as a function of the point: the SymPy tree is walked once, when the evaluator is
    built, instead of at every point (the same arithmetic node by node: Fractions while every operand is one,
    mpmath at the working precision of the call otherwise)."""
    if expr.is_Symbol:
        return lambda point: Fraction(point[expr])
    if expr.is_Rational or expr.is_Float:  # a Float: the binary number it holds
        r = sp.Rational(expr)
        value = Fraction(int(r.p), int(r.q))
        return lambda point: value
    if expr is sp.pi:
        return lambda point: +mpmath.pi
    parts = [_evaluator(a) for a in expr.args]
    if expr.is_Add:
        def add(point):
            args = [f(point) for f in parts]
            if all(isinstance(a, Fraction) for a in args):
                return sum(args, Fraction(0))
            return mpmath.fsum(_mp(a) for a in args)
        return add
    if expr.is_Mul:
        def mul(point):
            args = [f(point) for f in parts]
            if all(isinstance(a, Fraction) for a in args):
                out = Fraction(1)
                for a in args:
                    out *= a
                return out
            return mpmath.fprod(_mp(a) for a in args)
        return mul
    if expr.is_Pow:
        fbase, fexp = parts

        def power(point):
            base, e = fbase(point), fexp(point)
            if isinstance(base, Fraction) and isinstance(e, Fraction) and e.denominator == 1:
                return base ** int(e)
            return mpmath.power(_mp(base), _mp(e))
        return power
    (arg,) = parts
    if type(expr) is sp.Abs:
        return lambda point: abs(arg(point))
    fn = {sp.sin: mpmath.sin, sp.cos: mpmath.cos}[type(expr)]
    return lambda point: fn(_mp(arg(point)))


def _points(box: np.ndarray, rng, k: int = 2):
    """The corners of a box and ``k`` random points inside it, as float tuples."""
    corners = itertools.product(*box)
    inside = [tuple(rng.uniform(lo, hi) if hi > lo else lo for lo, hi in box) for _ in range(k)]
    return list(corners) + inside


def check_sound(inner, outer, constraints, variables, *, seed: int = 0, limit: int = 150):
    """Every checked point of an inner box meets every constraint; an outer box violates one at all its points."""
    rng = np.random.default_rng(seed)
    gs = [(c.g, c.strict) for c in ws.interval.parse_constraints(constraints, variables)]
    with mpmath.workdps(100):
        for box in _sample(inner, rng, limit):
            for p in _points(box, rng):
                point = dict(zip(variables, p))
                for g, strict in gs:
                    v = exact(g, point)
                    assert (v < 0) if strict else (v <= 0), f"inner box {box.tolist()} has {g} = {v} at {p}"
        for box in _sample(outer, rng, limit):
            pts = [dict(zip(variables, p)) for p in _points(box, rng)]
            if any(all(_violated(g, strict, pt) for pt in pts) for g, strict in gs):
                continue                      # one constraint fails at every checked point: plainly outside
            # Contraction proves a box outside when the constraints cannot hold *together* in it, though each
            # holds somewhere (x + y >= -1 and x**2 + y**2 > 1 below the chord).  The property itself is then
            # checked: no point of a 7 x 7 x 7 grid and of 64 random points meets every constraint.
            for p in _points(box, rng, k=64) + _grid(box, 7):
                pt = dict(zip(variables, p))
                assert any(_violated(g, strict, pt) for g, strict in gs), \
                    f"outer box {box.tolist()} has a point {p} that meets every constraint"


def _violated(g, strict: bool, point: dict) -> bool:
    v = exact(g, point)
    return v >= 0 if strict else v > 0


def _grid(box: np.ndarray, n: int):
    """An ``n``-per-axis grid over a box, faces included, as float tuples."""
    return list(itertools.product(*(np.linspace(lo, hi, n).tolist() for lo, hi in box)))


def _sample(boxes, rng, limit):
    if len(boxes) <= limit:
        return boxes
    return boxes[rng.choice(len(boxes), limit, replace=False)]


# ----------------------------------------------------------------------------- strategies
MONOMIALS = [X**2 * Z**2, X * Y**2, X, Y**2, X * Y, Z**3, sp.sin(Z), sp.cos(X + Y), sp.sqrt(X + 2), X**2 + Y**2,
             (X - Y) ** 2, Y * Z]


@st.composite
def coefficients(draw):
    exponent = draw(st.integers(-300, 10))
    mantissa = draw(st.floats(1.0, 10.0, exclude_max=True))
    sign = draw(st.sampled_from((1, -1)))
    kind = draw(st.sampled_from(("float", "rational")))
    if kind == "rational":
        return sp.Rational(sign * draw(st.integers(1, 12)), draw(st.integers(1, 12)))
    return sp.Float(sign * mantissa * 10.0**exponent)


@st.composite
def adversarial(draw):
    """A box in [-1, 1]^3 with two constraints, one of them vanishing at a point of a face."""
    bounds = []
    for _ in VARS:
        a, b = sorted(draw(st.lists(st.floats(-1, 1, allow_subnormal=False), min_size=2, max_size=2, unique=True)))
        bounds.append((a, b))
    box = dict(zip(VARS, bounds))
    terms = draw(st.lists(st.tuples(coefficients(), st.sampled_from(MONOMIALS)), min_size=1, max_size=3))
    body = sp.Add(*(c * m for c, m in terms))
    # A point on a face: the root passes through it (up to the rounding of the constant).
    face_var = draw(st.integers(0, 2))
    point = {v: draw(st.floats(lo, hi)) for v, (lo, hi) in box.items()}
    point[VARS[face_var]] = bounds[face_var][draw(st.integers(0, 1))]
    value = float(body.xreplace({k: sp.Float(v) for k, v in point.items()}))
    shift = draw(st.sampled_from((0.0, 1e-16, -1e-16, 1e-9)))
    constraint = sp.LessThan(body - sp.Float(value + shift), 0) if draw(st.booleans()) else \
        sp.StrictGreaterThan(sp.Float(value + shift), body)
    other = draw(st.sampled_from((sp.LessThan(-sp.sin(Z), 3), sp.LessThan(X**2 + Y**2 + Z**2, 2),
                                  sp.GreaterThan(X + Y, -1))))
    return [other, constraint], {str(v): b for v, b in box.items()}


# ----------------------------------------------------------------------------- properties
ISSUE_19 = (["-sin(z) <= 3", "10000000000.0*x**2*z**2 + 8*x*y**2/7 <= 2"],
            {"x": (0, 1), "y": (-2, 4), "z": (-1, 0)})
# Found by a CI run: an outer box where each constraint holds somewhere but never both (below the chord x + y = -1
# the unit disc's complement is empty); the earlier oracle wanted one constraint failing everywhere.
OUTSIDE_TOGETHER = (["x + y >= -1", "-1.0 > -1.0*x**2 - 1.0*y**2"],
                    {"x": (-1.0, 0.0), "y": (-1.0, 0.0), "z": (0.0, 1.0)})


def test_issue_19_reproduction_has_no_false_inner_box():
    """Issue 19: 56 of 255 inner boxes had a corner outside; now none (checked on every box)."""
    constraints, box = ISSUE_19
    p = ws.pave(constraints, box, delta=0.1926379375927805, contract=True)
    assert len(p.inner) > 100
    check_sound(p.inner, p.outer, constraints, VARS, limit=10_000)


# 60 drawn cases (150 before: a minute and more): every one has its root on a face of its box (the strategy puts it
# there), so each aims at the edge; `make explore` draws fresh ones on every run, and the cases found so far are
# pinned below.
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=adversarial(), contract=st.booleans(), delta=st.sampled_from((0.3, 0.1, 0.05)))
@example(case=(ISSUE_19[0], ISSUE_19[1]), contract=True, delta=0.1926379375927805)
@example(case=OUTSIDE_TOGETHER, contract=True, delta=0.3)
def test_paving_never_certifies_a_false_box(case, contract, delta):
    constraints, box = case
    variables = tuple(sp.Symbol(v) for v in box)
    p = ws.pave(constraints, box, delta=delta, contract=contract, stop=StopAt(max_boxes=3000))
    check_sound(p.inner, p.outer, constraints, variables)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=adversarial(), backend=st.sampled_from(("numpy", "mpmath")), data=st.data())
def test_certify_box_never_certifies_a_false_box(case, backend, data):
    constraints, box = case
    variables = tuple(sp.Symbol(v) for v in box)
    # A sub-box touching the face where the root was placed, or the whole box.
    shrink = data.draw(st.sampled_from((1.0, 1e-3, 1e-9)))
    sub = {k: (lo, lo + (hi - lo) * shrink) for k, (lo, hi) in box.items()}
    verdict = ws.certify_box(sub, constraints, backend=backend)
    boxes = np.array([list(sub.values())])
    none = boxes[:0]
    check_sound(boxes if verdict is Certificate.IN else none, boxes if verdict is Certificate.OUT else none,
                constraints, variables)


def test_reference_evaluator_is_exact():
    """The reference itself: a float that rounds 0.1 + 0.2 - 0.3 to nonzero is exactly that nonzero."""
    v = exact(X + Y - Z, {X: 0.1, Y: 0.2, Z: 0.3})
    assert v == Fraction(0.1) + Fraction(0.2) - Fraction(0.3) and v != 0
    with mpmath.workdps(100):
        s = exact(sp.sin(X) - sp.Rational(1, 2), {X: float(np.pi / 6)})
        assert abs(s) < 1e-16 and s != 0


@pytest.mark.parametrize("text", ["x*(1e10*x*z**2 + 8*y**2/7) - 2 <= 0", "1e-300*x**2 + 1e10*y**2 <= 1"])
def test_extreme_constants_are_kept_exact(text):
    """The chosen form is an identity of the constraint (exact SymPy check), constants included."""
    from workspace_sym.interval import best_form
    c = ws.interval.parse_constraints([text], VARS)[0]
    form = best_form(c.g, VARS)
    exact_g = c.g.xreplace({f: sp.Rational(f) for f in c.g.atoms(sp.Float)})     # Floats are binary numbers
    assert sp.expand(form - exact_g) == 0
    assert not form.atoms(sp.Float)
