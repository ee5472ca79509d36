"""Non-uniform covering: soundness (exact rational checks, hypothesis), numpy vs mpmath,
refinement, budgets, Rybak's published example and its exact area."""

from fractions import Fraction
from itertools import pairwise

import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from workspace_sym import RunOn, StopAt, robots
from workspace_sym.errors import BoxError, ConstraintError, InvalidParameterError
from workspace_sym.interval import Box, Certificate, certify_box, hausdorff, parse_constraints, pave
from workspace_sym.parallel import lens_area, rpr2

x1, x2 = sp.symbols("x1 x2")
VARS = (x1, x2)


# -------------------------------------------------------------------------- random polynomial constraints
@st.composite
def polynomial(draw):
    """A polynomial in x1, x2 of degree <= 3 with small integer coefficients."""
    terms = draw(st.lists(st.tuples(st.integers(-4, 4), st.integers(0, 3), st.integers(0, 3)), min_size=1,
                          max_size=5))
    expr = sum((c * x1**i * x2**j for c, i, j in terms if i + j <= 3), sp.Integer(0))
    return expr + draw(st.integers(-6, 6))


@st.composite
def constraint_set(draw):
    polys = draw(st.lists(polynomial(), min_size=1, max_size=3))
    box = {}
    for v in VARS:
        a = draw(st.integers(-4, 3))
        w = draw(st.integers(1, 4))
        box[v] = (a, a + w)
    return [p <= 0 for p in polys], box


def _exact_value(poly, point):
    """Exact rational value at a float point (floats are exact binary fractions).  ``xreplace``, not ``subs``:
    the same exact rational arithmetic as the polynomial is rebuilt at the point, without subs's pattern matching
    (most of the property tests' time)."""
    exact = {x1: sp.Rational(Fraction(point[0])), x2: sp.Rational(Fraction(point[1]))}
    return sp.Rational(sp.sympify(poly).xreplace(exact))


def _sample(boxes, rng, k=8):
    if len(boxes) == 0:
        return []
    idx = rng.choice(len(boxes), size=min(k, len(boxes)), replace=False)
    pts = []
    for b in boxes[idx]:
        t = rng.random(2)
        p = b[:, 0] + t * (b[:, 1] - b[:, 0])
        pts.append(np.clip(p, b[:, 0], b[:, 1]))
        pts.append(b[:, 0].copy())  # corners are the riskiest points
        pts.append(b[:, 1].copy())
    return pts


@pytest.mark.parametrize("contract", [False, True])
@settings(max_examples=60, deadline=None)
@given(constraint_set(), st.integers(0, 2**31))
@example(([x1 <= 0], {x1: (-1, 1), x2: (0, 1)}), 0)  # an exact cut at 0: the face x1 = 0 is not outer
@example(([x1**2 + x2**2 - 4 <= 0, x1 * x2 - 1 <= 0], {x1: (-3, 3), x2: (-3, 3)}), 1)
def test_inner_points_satisfy_and_outer_points_violate_exactly(contract, cs, seed):
    """Property: a point of an inner box satisfies every constraint in exact rational arithmetic;
    a point of an outer box violates one.  With ``contract``, the boxes include the slices cut off
    by forward-backward contraction."""
    constraints, box = cs
    p = pave(constraints, box, delta=0.3, contract=contract)
    gs = [c.g for c in parse_constraints(constraints, VARS)]  # g = lhs - rhs; constant True -> -1
    rng = np.random.default_rng(seed)
    for pt in _sample(p.inner, rng):
        assert all(_exact_value(g, pt) <= 0 for g in gs), (pt, gs)
    for pt in _sample(p.outer, rng):
        assert any(_exact_value(g, pt) > 0 for g in gs), (pt, gs)


@settings(max_examples=40, deadline=None)
@given(constraint_set(), st.data())
def test_numpy_never_contradicts_mpmath_at_100_digits(cs, data):
    """Property: no box is decided one way by the numpy engine and the other way by mpmath."""
    constraints, box = cs
    (a1, b1), (a2, b2) = box[x1], box[x2]
    for _ in range(5):
        u = sorted(data.draw(st.lists(st.floats(a1, b1), min_size=2, max_size=2)))
        v = sorted(data.draw(st.lists(st.floats(a2, b2), min_size=2, max_size=2)))
        sub = {x1: tuple(u), x2: tuple(v)}
        c_np = certify_box(sub, constraints)
        c_mp = certify_box(sub, constraints, backend="mpmath", digits=100)
        assert {c_np, c_mp} != {Certificate.IN, Certificate.OUT}


@settings(max_examples=25, deadline=None)
@given(constraint_set())
def test_refinement_never_loses_a_proved_box(cs):
    """Property: every inner / outer box at delta = 0.5 is covered by boxes of the same kind at delta = 0.125
    (the same bisection tree; the finer run may reach it in smaller pieces)."""
    constraints, box = cs
    coarse, fine = pave(constraints, box, delta=0.5), pave(constraints, box, delta=0.125)
    for kind in ("inner", "outer"):
        pieces = getattr(fine, kind)
        for b in getattr(coarse, kind):
            within = np.all((pieces[:, :, 0] >= b[:, 0]) & (pieces[:, :, 1] <= b[:, 1]), axis=1)
            covered = np.prod(pieces[within, :, 1] - pieces[within, :, 0], axis=1).sum()
            assert covered == pytest.approx(np.prod(b[:, 1] - b[:, 0]), rel=1e-12)
    assert fine.measures["inner"] >= coarse.measures["inner"]


@pytest.mark.parametrize("contract", [False, True])
@settings(max_examples=30, deadline=None)
@given(constraint_set())
def test_measures_add_up_and_bracket(contract, cs):
    """Property: the boxes tile the initial box (they lie in it and their measures add up to it)."""
    constraints, box = cs
    p = pave(constraints, box, delta=0.25, contract=contract)
    m = p.measures
    b = Box.from_bounds(box)
    total = b.measure
    assert abs(sum(m.values()) - total) <= 1e-9 * total
    assert p.measure_bounds[0] <= p.measure_bounds[1]
    for kind in ("inner", "boundary", "outer"):
        boxes = getattr(p, kind)
        assert np.all(boxes[:, :, 0] <= boxes[:, :, 1])
        assert np.all(boxes[:, :, 0] >= b.array[:, 0]) and np.all(boxes[:, :, 1] <= b.array[:, 1])


def test_interval_trig_constraint_is_sound():
    """A trigonometric constraint: inner points satisfy it (checked at 50 digits)."""
    import mpmath

    p = pave(["sin(x1) + cos(3*x2) <= 0.5"], {x1: (-3, 3), x2: (-2, 2)}, delta=0.2)
    rng = np.random.default_rng(0)
    with mpmath.workdps(50):
        for pt in _sample(p.inner, rng, k=30):
            assert mpmath.sin(mpmath.mpf(pt[0])) + mpmath.cos(3 * mpmath.mpf(pt[1])) <= mpmath.mpf("0.5")
    assert len(p.inner) > 0 and len(p.outer) > 0


# -------------------------------------------------------------------------- Rybak et al. 2016
@pytest.fixture(scope="module")
def rybak():
    return robots.build("rpr2")


def test_exact_area_closed_form_matches_monte_carlo(rybak):
    """Independent cross-check of the closed form: 4e6-point Monte Carlo (5 sigma)."""
    rng = np.random.default_rng(2024)
    n = 4_000_000
    a, b = rng.uniform(-12, 17, n), rng.uniform(0, 12, n)
    r1, r2 = a * a + b * b, (a - 5) ** 2 + b * b
    frac = np.mean((r1 <= 144) & (r1 >= 64) & (r2 <= 144) & (r2 >= 64))
    mc, sigma = frac * 348, 348 * np.sqrt(frac * (1 - frac) / n)
    assert abs(float(rybak.exact_measure) - mc) < 5 * sigma


def test_lens_area_identities():
    assert lens_area(2, 3, 0) == 4 * sp.pi
    assert lens_area(2, 3, 6) == 0
    # Two unit circles through each other's centres: 2 pi / 3 - sqrt(3) / 2 (textbook value).
    assert sp.simplify(lens_area(1, 1, 1) - (2 * sp.pi / 3 - sp.sqrt(3) / 2)) == 0


@pytest.mark.parametrize("contract", [False, True])
@pytest.mark.parametrize("delta", [0.5, 0.25, 0.07])
def test_every_paving_brackets_the_exact_area(rybak, delta, contract):
    """Rybak et al. 2016, figure 4a-c: the exact area lies between inner and inner + boundary."""
    p = rybak.pave(delta=delta, contract=contract)
    lo, hi = p.measure_bounds
    exact = float(rybak.exact_measure)
    assert lo <= exact <= hi
    assert p.complete and len(p.pending) == 0
    assert np.all(np.sqrt(np.sum((p.boundary[:, :, 1] - p.boundary[:, :, 0]) ** 2, axis=1)) <= delta)


def test_bracket_shrinks_with_delta(rybak):
    widths = [np.subtract(*rybak.pave(delta=d).measure_bounds[::-1]) for d in (0.5, 0.25, 0.07, 0.02)]
    assert all(a > b for a, b in pairwise(widths))


def test_mpmath_backend_gives_the_same_paving(rybak):
    a = rybak.pave(delta=0.5)
    b = rybak.pave(delta=0.5, backend="mpmath", digits=40)
    for kind in ("inner", "boundary", "outer"):
        assert len(getattr(a, kind)) == len(getattr(b, kind))


def test_hausdorff_between_pavings(rybak):
    """Deviation of the delta = 0.5 cover from the delta = 0.07 one is at most about delta = 0.5
    (paper's theorem: both lie within eps of X); bracket is ordered."""
    coarse, fine = rybak.pave(delta=0.5), rybak.pave(delta=0.07)
    A = np.concatenate([coarse.inner, coarse.boundary])
    B = np.concatenate([fine.inner, fine.boundary])
    lo, hi = hausdorff(A, B)
    assert 0 <= lo <= hi <= 1.0
    assert hausdorff(B, A)[1] <= 1e-12  # the fine cover lies inside the coarse one


def test_hausdorff_of_known_boxes():
    A = np.array([[[0.0, 1.0], [0.0, 1.0]]])
    B = np.array([[[2.0, 3.0], [0.0, 1.0]]])
    assert hausdorff(A, B) == (2.0, 2.0)  # farthest point of A (x = 0) is 2 away from B
    assert hausdorff(A, A) == (0.0, 0.0)


# -------------------------------------------------------------------------- budgets and bad input
def test_budget_leaves_pending_boxes_unclassified(rybak):
    p = rybak.pave(delta=0.07, stop=StopAt(max_boxes=50))
    assert not p.complete and "budget" in p.stop_reason
    assert len(p.pending) > 0 and p.evaluated == 50
    full = rybak.pave(delta=0.07)
    full_inner = {tuple(b.ravel()) for b in full.inner}
    assert all(tuple(b.ravel()) in full_inner for b in p.inner)
    m = p.measures
    assert abs(sum(m.values()) - 348) < 1e-9


def test_keyboard_interrupt_returns_partial(monkeypatch, rybak):
    from workspace_sym.interval import paving as mod

    real = mod.subdivide

    def interrupted_at_fourth_batch(decide, box, **options):
        calls = 0

        def flaky(boxes):
            nonlocal calls
            calls += 1
            if calls == 4:
                raise KeyboardInterrupt
            return decide(boxes)

        return real(flaky, box, **options)

    monkeypatch.setattr(mod, "subdivide", interrupted_at_fourth_batch)  # pave's loop, with Ctrl-C in the decider
    p = rybak.pave(delta=0.07)
    assert p.stop_reason == "interrupted" and not p.complete and len(p.pending) > 0
    assert abs(sum(p.measures.values()) - 348) < 1e-9  # the interrupted batch is pending, not lost


def test_certificate_is_not_a_boolean():
    with pytest.raises(TypeError):
        bool(Certificate.UNDECIDED)


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(delta=0), InvalidParameterError, "delta must be a positive finite number; got 0"),
    (dict(delta=-1.0), InvalidParameterError, "delta"),
    (dict(delta=float("nan")), InvalidParameterError, "delta"),
])
def test_bad_delta(kwargs, error, match):
    with pytest.raises(error, match=match):
        pave(["x1 <= 0"], {x1: (0, 1)}, **kwargs)


def test_bad_boxes_and_constraints():
    with pytest.raises(BoxError, match=r"lower bound of x1 \(2\) must not exceed its upper bound \(1\)"):
        pave(["x1 <= 0"], {x1: (2, 1)}, delta=0.1)
    with pytest.raises(BoxError, match="finite"):
        pave(["x1 <= 0"], {x1: (0, float("inf"))}, delta=0.1)
    with pytest.raises(ConstraintError, match="not an inequality"):
        pave(["x1 - 1"], {x1: (0, 1)}, delta=0.1)
    with pytest.raises(ConstraintError, match="not an inequality"):
        pave([sp.Eq(x1, 1)], {x1: (0, 1)}, delta=0.1)
    with pytest.raises(ConstraintError, match="unknown symbol"):
        pave(["x1 + q <= 0"], {x1: (0, 1)}, delta=0.1)


def test_rpr2_bad_parameters():
    with pytest.raises(InvalidParameterError, match="lmin"):
        rpr2(lmin=12, lmax=8)


def test_variables_match_by_name(rybak):
    """A box typed with names certifies the model's constraints (whose symbols are real=True)."""
    assert certify_box({"x1": (2, 3), "x2": (9, 10)}, rybak.constraints) is Certificate.IN
    assert certify_box({"x1": (-12, -11), "x2": (0, 1)}, rybak.constraints) is Certificate.OUT


# ------------------------------------------------------------------ the measure bracket, rounded outward
def _exact_measure(boxes) -> Fraction:
    return sum((np.prod([Fraction(float(b[k, 1])) - Fraction(float(b[k, 0])) for k in range(b.shape[0])])
                for b in boxes), Fraction(0))


_EDGES = st.floats(-1e3, 1e3, allow_nan=False, allow_subnormal=True)


@settings(derandomize=True, max_examples=150, deadline=None)
@given(st.lists(st.tuples(_EDGES, _EDGES, _EDGES, _EDGES), min_size=0, max_size=12), st.integers(0, 12))
@example([(0.0, 0.9, -0.7, 0.9)], 1)          # the float product 0.9 x 1.6 = 1.4400000000000002 exceeds the exact one
def test_measure_bounds_hold_the_exact_measure(edges, split):
    """Reference: the exact rational measure of the boxes (Fractions).  The bracket was the float sum of float
    products before (a few ulps either side of the exact one); now inner is summed rounded down, the rest up."""
    from workspace_sym.interval.boxes import Paving

    boxes = np.array([[sorted(e[:2]), sorted(e[2:])] for e in edges], dtype=float).reshape(-1, 2, 2)
    inner, boundary = boxes[:split], boxes[split:]
    empty = np.empty((0, 2, 2))
    p = Paving(("x", "y"), Box.from_bounds({"x": (-1e3, 1e3), "y": (-1e3, 1e3)}), (), 1.0, "numpy", "diameter",
               inner, boundary, empty, empty, 0.0, True, len(boxes))
    lo, hi = p.measure_bounds
    assert Fraction(lo) <= _exact_measure(inner) and Fraction(hi) >= _exact_measure(boxes)
    assert lo <= p.measures["inner"] and hi >= p.measures["inner"] + p.measures["boundary"] - 1e-9 * (1 + hi)


@settings(derandomize=True, max_examples=300, deadline=None)
@given(st.lists(st.floats(-1e300, 1e300, allow_nan=False, allow_subnormal=True), min_size=6, max_size=6))
@example([0.0, 0.9, -0.7, 0.9, 0.0, 1.0])
@example([-1e300, 1e300, 0.0, 5e-324, 1e-160, 3e-160])
def test_measures_of_rounds_each_box_outward(edges):
    """Reference: the exact rational product of the exact widths, over the whole float range (overflow to inf,
    subnormal widths, exact products left unmoved by the error-free transformations)."""
    from workspace_sym.interval.store import measures_of

    box = np.array([sorted(edges[k:k + 2]) for k in (0, 2, 4)], dtype=float)[None]
    exact = _exact_measure(box)
    down, up = measures_of(box, "down")[0], measures_of(box, "up")[0]
    assert Fraction(down) <= exact if np.isfinite(down) else down == np.inf and exact > Fraction(1e300)
    assert np.isinf(up) or Fraction(up) >= exact


def test_stored_paving_has_the_same_outward_bracket(tmp_path):
    constraints, box = ["x**2 + y**2 <= 1"], {"x": (-1.1, 1.1), "y": (-1.1, 1.1)}
    local = pave(constraints, box, delta=0.1)
    stored = pave(constraints, box, delta=0.1, run=RunOn(store=tmp_path / "boxes"))
    assert stored.measure_bounds == local.measure_bounds
    lo, hi = local.measure_bounds
    assert Fraction(lo) <= _exact_measure(local.inner)
    assert Fraction(hi) >= _exact_measure(np.concatenate([local.inner, local.boundary]))


# ------------------------------------------------------------------ issue 23 item 7, issue 30 item 4
def test_huge_power_of_a_sum_is_paved_within_seconds():
    """``(x + y + 1)**1000 <= 1`` ran without bound (the form search expanded the power).  Reference: the set is
    ``-2 <= x + y <= 0``; inner boxes lie inside it, outer ones outside (exact check on the box corners)."""
    import time

    start = time.perf_counter()
    p = pave(["(x1+x2+1)**1000 <= 1"], {"x1": (-1, 1), "x2": (-1, 1)}, delta=0.25)
    assert time.perf_counter() - start < 10
    assert len(p.inner) and len(p.outer)
    for b in p.inner:
        assert -2 <= b[0][0] + b[1][0] and b[0][1] + b[1][1] <= 0
    for b in p.outer:
        assert b[0][0] + b[1][0] > 0 or b[0][1] + b[1][1] < -2


@pytest.mark.parametrize("text, edge", [("Abs(x1) + x1 <= 1", 0.5), ("sqrt(x1)**3 <= x1/2", 0.25)])
def test_abs_and_half_integer_powers_are_paved(text, edge):
    """``Abs(x) + x <= 1`` failed with a message about re(x) (the mean-value form differentiated Abs);
    ``sqrt(x)**3`` (SymPy's ``x**(3/2)``) was refused.  Reference: both sets are ``x1 <= edge`` on the box."""
    p = pave([text], {"x1": (0, 2), "x2": (0, 1)}, delta=0.1)
    assert len(p.inner) and len(p.outer)
    assert all(b[0][1] <= edge for b in p.inner) and all(b[0][0] > edge for b in p.outer)
