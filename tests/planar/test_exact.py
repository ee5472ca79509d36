"""Closed forms as a person writes them (workspace_sym.exact): each short form is checked against the float
computation or an exact SymPy identity, and the Table 1 iii forms against Bastien (2018), Table 2."""

import math

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from workspace_sym.exact import area_terms, exact_arcs, norm2, polar_angle, short_atan2, short_sqrt
from workspace_sym.planar import PlanarChain

HUMAN_ARM = (["0.186", "0.146", "0.108"], [-60, 0, -10], [120, 130, 25])     # Bastien 2018, Table 1 case iii
PI = sp.pi


@pytest.fixture(scope="module")
def arm():
    b = PlanarChain(*HUMAN_ARM).boundary()
    return b, exact_arcs(b)


def test_atan_of_a_cotangent_is_reduced():
    """atan(cos(7 pi/18) / sin(7 pi/18)) = pi/2 - 7 pi/18 = pi/9 (exact identity), and the quadrant is kept."""
    assert short_atan2(sp.cos(7 * PI / 18), sp.sin(7 * PI / 18)) == PI / 9
    assert short_atan2(-sp.cos(7 * PI / 18), -sp.sin(7 * PI / 18)) == -8 * PI / 9
    assert math.isclose(float(-8 * PI / 9), math.atan2(-math.cos(7 * math.pi / 18), -math.sin(7 * math.pi / 18)))


def test_atan2_arguments_are_integer_and_sign_pulled_out():
    y, x = -sp.Rational(27, 250) * sp.sin(PI / 18), sp.Rational(83, 250) + sp.Rational(27, 250) * sp.cos(PI / 18)
    e = short_atan2(y, x)
    assert str(e) == "-atan2(27*sin(pi/18), 27*cos(pi/18) + 83)"
    assert float(e) == pytest.approx(math.atan2(float(y), float(x)), abs=1e-15)


angles = st.integers(-179, 180).map(lambda d: sp.Rational(d, 180) * PI)
lengths = st.fractions(min_value=-3, max_value=3, max_denominator=1000).map(sp.Rational)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(lengths, angles), min_size=1, max_size=4))
def test_polar_angle_and_norm_match_floats(terms):
    """Property: the short polar angle and squared norm of sum L u(a) agree with plain floats (math.atan2)."""
    x = sum(-float(L) * math.sin(float(a)) for L, a in terms)
    y = sum(float(L) * math.cos(float(a)) for L, a in terms)
    assert float(norm2(terms)) == pytest.approx(x * x + y * y, abs=1e-12)
    angle = polar_angle(terms)
    if math.hypot(x, y) < 1e-9:
        return
    assert angle is not None and not angle.has(sp.atan)          # atan2 of the vector, never atan of a quotient
    diff = (float(angle) - math.atan2(y, x)) / (2 * math.pi)
    assert abs(diff - round(diff)) < 1e-11


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.fractions(min_value=0, max_value=2, max_denominator=500).map(sp.Rational), angles),
                min_size=2, max_size=3))
def test_short_sqrt_is_the_square_root(terms):
    value = sp.expand(sum(L * sp.cos(a) for L, a in terms)) + 7       # positive: |sum| <= 6
    assert float(short_sqrt(value)) == pytest.approx(math.sqrt(float(value)), rel=1e-14)


def test_table2_vertex_is_the_symmetric_angle(arm):
    """Bastien 2018, Table 2: Theta_1 of the arc about O with theta_3 = -10 ends at -55.1005 deg; the closed form
    is exactly -60 deg + 2 atan2(l3 sin 10 deg, l1 + l2 + l3 cos 10 deg), lengths 93/500, 73/500, 27/250 scaled to
    integers (27 and 83 = 250 (l1 + l2))."""
    b, rows = arm
    k = next(k for k, a in enumerate(b.arcs) if a.free_joint == 1 and abs(math.degrees(a.theta_sets[2][0]) + 10) < 1e-9)
    value = rows[k]["theta_sets"][0][1]
    assert value == -60 + 360 * sp.atan2(27 * sp.sin(PI / 18), 27 * sp.cos(PI / 18) + 83, evaluate=False) / PI
    assert float(value) == pytest.approx(-55.1005, abs=5e-5)
    assert float(value) == pytest.approx(math.degrees(b.arcs[k].theta_sets[0][1]), abs=1e-10)


def test_arc_lower_end_reduced_to_zero(arm):
    """Arc 4 (about P_2 at theta = 120, 130) starts where arc 3 ends, at theta_3 = 0: written 0, not an acos."""
    b, rows = arm
    k = next(k for k, a in enumerate(b.arcs)
             if a.free_joint == 3 and abs(math.degrees(a.theta_sets[0][0]) - 120) < 1e-9)
    assert rows[k]["theta_sets"][2] == (0, 25)
    assert [math.degrees(v) for v in b.arcs[k].theta_sets[2]] == pytest.approx([0, 25], abs=1e-10)


def test_radii_are_sqrt_of_integer_forms(arm):
    """Radius of the arc about O with theta = (*, 130, 25): |l1 + l2 u(130) + l3 u(155)|, law of cosines
    (cos 130 = -cos 50, cos 25), no sin^2 + cos^2 left; equal to the float radius."""
    b, rows = arm
    r5 = sp.sqrt(16894 - 13578 * sp.cos(5 * PI / 18) - 2160 * sp.cos(5 * PI / 36)) / 500
    assert r5 in [r["radius"] for r in rows]
    for r, a in zip(rows, b.arcs):
        assert float(r["radius"]) == pytest.approx(a.radius, abs=1e-13)
        assert ")**2" not in str(r["radius"])


def test_every_cell_short_and_equal_to_its_float(arm):
    """Issue 12 target: every closed form of Table 1 iii is at most 80 characters of SymPy str and equals the float
    computation (theta sets in degrees, centres, radii)."""
    b, rows = arm
    for r, a in zip(rows, b.arcs):
        cells = [*r["center"], r["radius"]] + [e for s in r["theta_sets"] for e in s]
        assert max(len(str(c)) for c in cells) <= 80
        for e, v in zip(r["center"], a.center):
            assert float(e) == pytest.approx(v, abs=1e-13)
        for s, fs in zip(r["theta_sets"], a.theta_sets):
            assert [float(e) for e in s] == pytest.approx([math.degrees(v) for v in fs], abs=1e-10)


@pytest.mark.parametrize("chain", [HUMAN_ARM, ([0.30, 0.15], [-120, -30], [0, 30]), ([1, 1], [-90, 0], [90, 90])],
                         ids=["table1-iii", "p2", "2R"])
def test_area_terms_match_the_float_green_integral(chain):
    """Each per-arc term (joint-space form) equals Green's integral over that arc computed from the float centre,
    radius and polar angles (an independent formula); the sum is the area."""
    b = PlanarChain(*chain).boundary()
    terms = area_terms(b)
    assert len(terms) == len(b.arcs)
    for t, a in zip(terms, b.arcs):
        (cx, cy), r, a0, a1 = a.center, a.radius, a.start_angle, a.end_angle
        green = (r * r * (a1 - a0) + r * cx * (math.sin(a1) - math.sin(a0))
                 - r * cy * (math.cos(a1) - math.cos(a0))) / 2
        assert float(t) == pytest.approx(green, abs=1e-12)
    assert float(sum(terms)) == pytest.approx(b.area, abs=1e-12)
    if chain is HUMAN_ARM:
        assert max(len(str(t)) for t in terms) <= 80


# Issue 39 (notebook user): `boundary --exact` printed `-2*pi + pi*(sqrt(3) + 2)` for `sqrt(3)*pi`.  Two 2R arms with
# 30-degree limits on the elbow; the areas by hand: the annulus between |p| = 2 cos(15 deg) and 2 cos(75 deg), whole
# (the shoulder turning) or half of it (the shoulder over 0..180 deg): pi (4 cos^2 15 - 4 cos^2 75) = 2 sqrt(3) pi;
@pytest.mark.parametrize(("lower", "upper", "simplest"), [([-180, 30], [180, 150], 2 * sp.sqrt(3) * PI),
                                                          ([0, 30], [180, 150], sp.sqrt(3) * PI),
                                                          ([-180, -150], [180, 150], PI * (2 + sp.sqrt(3)))])
def test_exact_area_is_printed_in_its_short_form(lower, upper, simplest):
    from workspace_sym.exact import exact_area

    b = PlanarChain([1, 1], lower, upper).boundary()
    printed, summed = exact_area(b), sp.Add(*area_terms(b))
    assert sp.simplify(printed - summed) == 0                 # the same number as the sum of the arcs' terms
    assert sp.simplify(printed - simplest) == 0               # ... and the one computed by hand above
    assert len(str(printed)) <= len(str(simplest))
    assert float(printed) == pytest.approx(b.area, rel=1e-9)  # the float boundary's area agrees


def test_exact_area_of_the_human_arm_is_no_longer_than_its_sum(arm):
    from workspace_sym.exact import exact_area

    b, rows = arm
    printed, summed = exact_area(b, rows), sp.Add(*area_terms(b, rows))
    assert len(str(printed)) <= len(str(summed))
    assert abs(sp.N(printed - summed, 50)) < 1e-40            # Bastien (2018) Table 1 iii: same area
