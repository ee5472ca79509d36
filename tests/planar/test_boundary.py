"""Step 2 of the alignment method (Bastien 2018): the boundary loops, closed forms, point queries,
and independent checks (forward kinematics, witnesses, interval exclusion, an exact area formula)."""

import json
import math
import warnings

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from workspace_sym.boundary import prove_unreachable, witness_near
from workspace_sym.exact import exact_arcs, exact_area
from workspace_sym.planar import PlanarChain

HUMAN_ARM = (["0.186", "0.146", "0.108"], [-60, 0, -10], [120, 130, 25])     # Table 1, case iii
CASE_II = ([0.186, 0.254], [-60, 0], [120, 130])                              # Table 1, case ii
P2 = ([0.30, 0.15], [-120, -30], [0, 30])
P6 = ([0.20, 0.20, 0.15, 0.35, 0.20, 0.20], [-120, -120, -30, -90, -45, -23], [60, 170, 30, 91, 23, 24])

# Bastien 2018, Table 2 (case iii): type and Theta_1..3 in degrees, singletons as 1-tuples
TABLE2 = [("II", (-60, 120), (0,), (0,)), ("II", (120,), (0, 130), (0,)), ("III", (120,), (130,), (0, 25)),
          ("III", (-60, 120), (130,), (25,)), ("III", (-60,), (0, 130), (25,)), ("III", (-60,), (0,), (10, 25)),
          ("III", (-60, -55.1005), (0,), (-10,)), ("III", (-60,), (0,), (-10, 0))]


def random_chain(p, seed):
    rng = np.random.default_rng(seed)
    limits = np.sort(rng.uniform(-179, 179, (p, 2)), axis=1)
    return PlanarChain(rng.uniform(0.1, 1.0, p), limits[:, 0], limits[:, 1])


def boundary_of(chain):
    with warnings.catch_warnings():
        warnings.simplefilter("error")       # an undecided face would make these checks vacuous
        return chain.boundary()


@pytest.mark.parametrize("chain, counts", [
    (HUMAN_ARM, (16, 11, 8)),      # figure 4
    (CASE_II, (4, 4, 4)),          # figure 3: the three steps give the same 4 arcs
    (P6, (506, 75, 9)),            # figure 6
], ids=["table1-iii", "table1-ii", "p6"])
def test_paper_step_counts(chain, counts):
    b = PlanarChain(*chain).boundary()
    assert (b.counts["step0"], b.counts["step1"], b.counts["step2"]) == counts


def test_table2_reproduced():
    """Bastien 2018, Table 2: the eight boundary arcs of the human arm, to 5e-5 degrees.

    The paper prints 4 decimals.
    """
    rows = PlanarChain(*HUMAN_ARM).boundary().table()
    got = sorted((r["type"],) + tuple(tuple(round(v, 4) + 0.0 for v in s) for s in r["theta_sets"]) for r in rows)
    want = sorted((t,) + tuple(tuple(float(v) for v in s) for s in sets) for t, *sets in TABLE2)
    assert len(got) == len(want) == 8
    for g, w in zip(got, want):
        assert g[0] == w[0]
        for sg, sw in zip(g[1:], w[1:]):
            assert len(sg) == len(sw) and all(abs(a - b) <= 5e-5 for a, b in zip(sg, sw))


def test_table2_angle_in_closed_form():
    """The -55.1005 deg of Table 2 is -60 deg + 2 atan(l3 sin 10 / (l1 + l2 + l3 cos 10)) (the circle about O through
    theta_3 = -10 meets the hand's circle at theta_3 = +10 by symmetry): exact identity checked to 30 digits."""
    b = PlanarChain(*HUMAN_ARM).boundary()
    rows = exact_arcs(b)
    k = next(k for k, a in enumerate(b.arcs) if a.free_joint == 1 and abs(math.degrees(a.theta_sets[2][0]) + 10) < 1e-9)
    value = rows[k]["theta_sets"][0][1]
    l1, l2, l3 = sp.Rational(186, 1000), sp.Rational(146, 1000), sp.Rational(108, 1000)
    ten = sp.pi / 18
    expected = -60 + 2 * sp.atan(l3 * sp.sin(ten) / (l1 + l2 + l3 * sp.cos(ten))) * 180 / sp.pi
    assert abs(sp.N(value - expected, 30)) < 1e-25
    assert abs(float(value) - (-55.1005)) < 5e-5


P4 = tuple(v[:4] for v in P6)       # figure 6's first four links: every pair of links a < b of the area formula


@pytest.mark.parametrize("chain, area", [(HUMAN_ARM, True), (P2, True), (P4, True), (P6, False)],
                         ids=["table1-iii", "p2", "p4", "p6"])
def test_closed_forms_match_floats(chain, area):
    """The closed forms of every arc (centre, radius, angles, joint values) and of the enclosed area agree with the
    floats to 1e-12 (30 digits).  Figure 6's six links are checked arc by arc, their area on the first four links
    (``P4``): the area's closed form of all six takes half a minute in SymPy (sines of long sums of arctangents)
    and its terms are the same pairs of links as for four."""
    b = PlanarChain(*chain).boundary()
    rows = exact_arcs(b)
    assert all(r["exact"] for r in rows)
    for r, a in zip(rows, b.arcs):
        for e, v in ((r["center"][0], a.center[0]), (r["center"][1], a.center[1]), (r["radius"], a.radius),
                     (r["start_angle"], a.start_angle), (r["end_angle"], a.end_angle)):
            assert abs(float(sp.N(e, 30)) - v) < 1e-12
        for j, s in enumerate(r["theta_sets"]):
            assert all(abs(float(sp.N(e, 30)) - math.degrees(v)) < 1e-9 for e, v in zip(s, a.theta_sets[j]))
    if area:
        assert abs(float(sp.N(exact_area(b), 30)) - b.area) < 1e-12


@pytest.mark.parametrize("l1, l2, lo, hi", [
    ("0.3", "0.15", (-120, 10), (0, 170)), ("1/2", "1/3", (-170, -150), (100, -20)), ("0.7", "0.9", (0, 5), (179, 95)),
    ("0.186", "0.254", (-60, 0), (120, 130)),     # Table 1 (ii): the circles about O and A_1 are tangent at theta_2 = 0
])
def test_two_link_area_against_the_jacobian_integral(l1, l2, lo, hi):
    """Independent exact reference: when theta_2 keeps one sign the 2R map is injective, so the area is
    int |det J| = l1 l2 (theta_1^+ - theta_1^-) |cos theta_2^- - cos theta_2^+|."""
    c = PlanarChain([l1, l2], lo, hi)
    b = boundary_of(c)
    ref = float(sp.Rational(sp.nsimplify(l1)) * sp.Rational(sp.nsimplify(l2))) * (c.upper[0] - c.lower[0]) * abs(
        math.cos(c.lower[1]) - math.cos(c.upper[1]))
    assert b.area == pytest.approx(ref, rel=1e-12)
    assert float(sp.N(exact_area(b), 30)) == pytest.approx(ref, rel=1e-12)


@pytest.mark.parametrize("p, seed", [(2, 1), (3, 2), (4, 3), (5, 4), (6, 5), (3, 33)])
def test_random_configurations_never_outside(p, seed):
    """Property: forward kinematics of random configurations (and of every corner of the joint box, where
    the boundary is made) is inside or on the boundary."""
    c = random_chain(p, seed)
    b = boundary_of(c)
    verdicts = b.classify(c.forward(c.sample(3000, seed=seed + 100)))
    assert (verdicts != "outside").all()


@pytest.mark.parametrize("p, seed", [(2, 1), (3, 2), (4, 3), (6, 5)])
def test_sides_proved_by_witnesses_and_exclusion(p, seed):
    """Independent of the arrangement: a point just inside each boundary arc is reached by a configuration
    found by least squares, and a point just outside it, when the loops put it outside, is proved unreachable
    by interval exclusion."""
    c = random_chain(p, seed)
    b = boundary_of(c)
    starts = c.sample(20000, seed=7)
    pts = c.forward(starts)
    for a in b.arcs:
        m = 0.5 * (a.start_angle + a.end_angle)
        inward = -1 if a.end_angle > a.start_angle else 1      # the workspace is on the left of travel
        d = 0.01 * c.reach
        q_in = a.point(m) + inward * d * np.array([math.cos(m), math.sin(m)]) * (1 if a.radius > d else 0)
        q_out = a.point(m) - inward * 3 * d * np.array([math.cos(m), math.sin(m)])
        if b.contains(q_in) == "inside":
            _, err = witness_near(c, q_in, starts=starts, points=pts, k=128, iterations=150)
            assert err[0] < 1e-9
        if b.contains(q_out) == "outside":
            assert prove_unreachable(c, q_out, max_boxes=1_000_000) is True


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 5), st.integers(0, 10_000), st.floats(0, 1), st.floats(0, 1))
def test_exclusion_never_rejects_a_reachable_point(p, seed, u, v):
    """Soundness of the outward-rounded exclusion: the image of a configuration is never proved unreachable."""
    c = random_chain(p, seed)
    theta = np.array(c.lower) + np.array([u, v] * p)[:p] * (np.array(c.upper) - np.array(c.lower))
    assert prove_unreachable(c, c.forward(theta), max_boxes=20_000) is not True


def test_hole_found_and_proved():
    """The p = 6 chain of the paper has a hole around the origin (figure 6): one outer loop and one hole,
    the hole's face proved outside by interval exclusion."""
    b = PlanarChain(*P6).boundary()
    kinds = sorted(l.kind for l in b.loops)
    assert kinds == ["hole", "outer"]
    assert any(e["method"] == "interval exclusion" for e in b.evidence.values())
    assert b.contains((0.0, 0.0)) == "outside"
    hole = next(l for l in b.loops if l.kind == "hole")
    assert hole.area < 0 and b.area == pytest.approx(sum(l.area for l in b.loops))


def test_area_and_perimeter_match_the_polygon_of_the_loops():
    """Green's theorem over the arcs against the shoelace formula on the densely sampled loops."""
    b = PlanarChain(*P6).boundary()
    shoelace = 0.0
    for poly in b.polygon(step=1e-4):
        x, y = poly[:, 0], poly[:, 1]
        shoelace += 0.5 * (x @ np.roll(y, -1) - y @ np.roll(x, -1))
        assert np.hypot(*np.diff(poly, axis=0).T).max() < 1e-3
    assert shoelace == pytest.approx(b.area, rel=1e-6)
    lengths = sum(np.hypot(*np.diff(p, axis=0).T).sum() for p in b.polygon(step=1e-4))
    assert lengths == pytest.approx(b.perimeter, rel=1e-6)


def test_contains_and_configurations():
    c = PlanarChain(*HUMAN_ARM)
    b = c.boundary()
    assert b.contains((0.0, 0.44)) == "boundary"              # arm stretched along +y (theta = 0)
    assert b.contains((0.0, 0.30)) == "inside"
    assert b.contains((0.0, 0.45)) == "outside"
    assert b.contains((0.0, -0.30)) == "outside"
    configs = b.configurations((0.0, 0.44))
    assert len(configs) >= 1 and np.allclose(c.forward(configs), [0.0, 0.44], atol=1e-12)
    assert len(b.configurations((0.0, 0.30))) == 0
    # the vertex at theta_1 = -55.1005 deg of Table 2: two configurations reach it
    k = next(k for k, a in enumerate(b.arcs) if a.free_joint == 1 and abs(math.degrees(a.theta_sets[2][0]) + 10) < 1e-9)
    theta = [s[-1] for s in b.arcs[k].theta_sets]          # theta_1 = -55.1005, 0, -10
    v = c.forward(theta)
    configs = b.configurations(v)
    assert len(configs) >= 2
    assert np.allclose(c.forward(configs), v, atol=1e-12)
    assert (configs >= np.array(c.lower) - 1e-12).all() and (configs <= np.array(c.upper) + 1e-12).all()


def test_one_joint_is_an_arc():
    """Table 1, case i: one joint, the workspace is a single arc (figure 2), of area 0."""
    b = PlanarChain([0.44], [-60], [120]).boundary()
    assert b.counts == {"step0": 1, "step1": 1, "step2": 1} and b.area == 0.0
    assert b.arcs[0].radius == pytest.approx(0.44)


def test_json_contract():
    d = PlanarChain(*HUMAN_ARM).boundary().to_dict(exact=True)
    json.dumps(d)
    assert set(d) >= {"arcs", "loops", "area", "area_exact", "counts", "seconds"}
    arc = d["arcs"][0]
    assert set(arc) >= {"type", "free_joint", "theta_sets", "center", "radius", "start_angle", "end_angle", "side",
                        "exact"}
    assert float(sp.sympify(d["area_exact"])) == pytest.approx(d["area"], rel=1e-12)
    assert float(sp.sympify(arc["exact"]["radius"])) == pytest.approx(arc["radius"], rel=1e-12)
    assert d["loops"][0]["kind"] == "outer" and sorted(d["loops"][0]["arcs"]) == list(range(8))


@settings(max_examples=30, deadline=None)
@given(st.integers(2, 5), st.integers(0, 10_000), st.lists(st.floats(0, 1), min_size=5, max_size=5))
def test_subchain_argument_never_rejects_a_reachable_point(p, seed, u):
    """Soundness of the argument through the workspace of joints 2..p: the image of a configuration is never
    declared unreachable, and a witness it returns reaches the point."""
    from workspace_sym.boundary import unreachable_via_subchain

    c = random_chain(p, seed)
    theta = np.array(c.lower) + np.array(u[:p]) * (np.array(c.upper) - np.array(c.lower))
    q = c.forward(theta)
    decided, witness = unreachable_via_subchain(c, q)
    assert decided is not True
    if witness is not None:
        assert math.dist(c.forward(witness), q) < 1e-9 * c.reach
        assert (witness >= np.array(c.lower) - 1e-12).all() and (witness <= np.array(c.upper) + 1e-12).all()


def test_subchain_argument_agrees_with_interval_exclusion():
    """Independent cross-check on points of holes: where interval exclusion proves a point unreachable,
    the argument through joints 2..p says unreachable too."""
    from workspace_sym.boundary import unreachable_via_subchain

    c = PlanarChain(*P6)
    b = c.boundary()
    hole = next(e for e in b.evidence.values() if e["method"] in ("interval exclusion", "workspace of joints 2..p"))
    q = np.array(hole["point"])
    assert prove_unreachable(c, q, max_boxes=400_000) is True
    assert unreachable_via_subchain(c, q) == (True, None)


@pytest.mark.parametrize("p, seed", [(2, 1), (2, 2), (3, 1), (3, 2), (3, 3), (4, 1), (4, 4), (5, 1), (5, 2), (6, 1),
                                     (6, 3)])
def test_area_against_the_sweep_of_the_first_joint(p, seed):
    """Independent estimate (tests/helpers/polar_reference.py): the sweep of joint 1 integrated on circles about O,
    with exact angular sets of the region l_1 e_y + W.  For p <= 3, W is built from the two-link sheets
    alone (independent of the alignment method); for p >= 4 it is the boundary of joints 2..p one level
    down, itself checked by this test at p - 1.  Agreement within 0.2 %."""
    from polar_reference import reference_area

    c = random_chain(p, seed)
    b = boundary_of(c)
    sub = None
    if p >= 4:
        w = boundary_of(PlanarChain(c.lengths[1:], c.lower[1:], c.upper[1:], degrees=False))
        sub = [(poly, loop.kind) for poly, loop in zip(w.polygon(step=1e-3), w.loops)]
    assert b.area == pytest.approx(reference_area(c, sub), rel=2e-3)


def test_area_of_a_thin_joint_range_against_the_sweep():
    """A chain whose second joint moves 2.2 degrees (thin sheets, where grid-based estimates lose 3-7 %)."""
    from polar_reference import reference_area

    c = PlanarChain([0.8083872473993209, 0.27245463311812174, 0.822127745021077],
                    [-149.804, 127.171, -10.0563], [-110.506, 129.339, 134.8])
    assert boundary_of(c).area == pytest.approx(reference_area(c), rel=2e-3)


@pytest.mark.parametrize("lengths, hole", [
    ([0.582, 0.786, 0.944, 0.69, 0.578], False),      # issue 19 item 3a: the longest link is shorter than the rest
    ([0.582, 0.786, 2.944, 0.69, 0.578], True),       # one link longer than the others together: an annulus
], ids=["disc", "annulus"])
def test_near_full_range_slivers_are_merged(lengths, hole):
    """Issue 19 item 3a: with every joint in [-179.999, 180] deg the arrangement has hundreds of sliver faces
    (nearly tangent circles); merged, the loops are those of the full-range workspace (every joint in
    [-180, 180]: a disc of radius sum(l), or an annulus of inner radius 2 max(l) - sum(l)) and the area is
    within 1e-9 of its closed form.  Before the merge: 17 outer loops, 26 holes, 133 unclassified faces."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        b = PlanarChain(lengths, [-179.999] * 5, [180] * 5).boundary()
    R, inner = sum(lengths), max(0.0, 2 * max(lengths) - sum(lengths))
    kinds = sorted(loop.kind for loop in b.loops)
    assert kinds == (["hole", "outer"] if hole else ["outer"])
    assert b.area == pytest.approx(math.pi * (R * R - inner * inner), abs=1e-9)
    assert b.merged["faces"] > 100 and b.merged["area"] < 1e-8 and b.merged["into"]["inside"] > 100
    assert b.to_dict()["merged"] == b.merged
    assert b.contains([0.0, 0.0]) == ("outside" if hole else "inside")
    if not hole:
        assert b.undecided_area == 0 and "undecided" not in b.faces.values() and not caught


def _forward_100_digits(chain, theta):
    """``P_p`` of the configuration ``theta`` (radians) at 100 digits (mpmath), from the definition."""
    import mpmath

    with mpmath.workdps(100):
        phi, x, y = mpmath.mpf(0), mpmath.mpf(0), mpmath.mpf(0)
        for length, t in zip(chain.exact_lengths, theta):
            phi += mpmath.mpf(float(t))
            length = mpmath.mpf(sp.Rational(length).p) / sp.Rational(length).q
            x -= length * mpmath.sin(phi)
            y += length * mpmath.cos(phi)
        return x, y


@settings(max_examples=50, deadline=None)
@given(p=st.integers(2, 4), seed=st.integers(0, 10_000),
       joints=st.lists(st.sampled_from(["lower", "upper", "free"]), min_size=4, max_size=4),
       u=st.lists(st.floats(0, 1), min_size=4, max_size=4),
       offset=st.floats(0, 1e-10), angle=st.floats(0, 2 * math.pi))
def test_exclusion_never_proves_a_point_near_an_image_unreachable(p, seed, joints, u, offset, angle):
    """Issue 19 item 1 (ii), false exclusions: a configuration drawn adversarially on the faces and corners of
    the joint box (where the boundary is made), its image evaluated at 100 digits and moved by at most 1e-10
    of the reach, well inside the method's 1e-9 margin: interval exclusion never proves that point
    unreachable."""
    import mpmath

    c = random_chain(p, seed)
    lo, hi = np.array(c.lower), np.array(c.upper)
    theta = np.array([{"lower": lo[k], "upper": hi[k], "free": lo[k] + u[k] * (hi[k] - lo[k])}[joints[k]]
                      for k in range(p)])
    x, y = _forward_100_digits(c, theta)
    with mpmath.workdps(100):
        q = (float(x + offset * c.reach * mpmath.cos(angle)), float(y + offset * c.reach * mpmath.sin(angle)))
    assert prove_unreachable(c, q, max_boxes=20_000) is not True


def test_faces_proved_outside_are_reached_by_no_sampled_configuration():
    """Issue 19 item 1 (ii): the probe point of every face of the p = 6 chain proved outside by interval
    exclusion is farther
    from the images of 200000 configurations (corners of the joint box included), the nearest 20 re-evaluated
    at 100 digits, than the 1e-9 margin; and the loops agree that the probe is outside."""
    c = PlanarChain(*P6)                 # its hole is proved outside by interval exclusion (figure 6)
    b = boundary_of(c)
    proved = [e["point"] for e in b.evidence.values() if e["method"] == "interval exclusion"]
    assert proved
    theta = c.sample(200_000, seed=6)
    pts = c.forward(theta)
    for q in proved:
        assert b.contains(q) == "outside"
        near = np.argsort(np.hypot(*(pts - np.array(q)).T))[:20]
        for k in near:
            x, y = _forward_100_digits(c, theta[k])
            assert float(abs((x - q[0]) ** 2 + (y - q[1]) ** 2)) ** 0.5 > 1e-9 * c.reach
