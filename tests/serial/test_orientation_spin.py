"""Issue 40: a constant orientation (tool down) of the LBR iiwa 14 (rtb-data URDF) through its wrist centre
(docs/methods.md section 8, "A constant orientation through the wrist centre"): the tool point is the wrist centre
plus 0.126 m straight down; of the wrist's two solutions, the one within the limits of the roll (joint 5, 340 deg)
and of the last joint (joint 7, 350 deg, which spins the tool about its approach) depends on the first joint's turn,
so each direction proof holds on sectors of that turn (turn.SpinSectors), at sixteen directions.

References: a least-squares wrist solution within the limits (scipy) for the wrist's condition, configurations
sampled within the limits with the frame made exact by Newton (floats), an inverse kinematics at 50 digits
(mpmath) for points of inner boxes, and a brute-force reading of the sectors' cover at random angles.
"""

import dataclasses
import math
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from reach_checks import (
    admissible_configurations,
    arcs_volume,
    arm_in_pose_at_50_digits,
    in_any_box,
    industrial_arm,
    oriented_configurations,
)
from workspace_sym.serial import Pose, reach
from workspace_sym.serial.pose import SpinCondition, constraint_from, pose_structure
from workspace_sym.serial.tuning import DEFAULT
from workspace_sym.serial.turn import SpinSectors

TOOL_DOWN = dict(rpy=(180, 0, 0))
# Coarse cells and few seeds: a bracket in seconds (300 s give [1.64, 1.94] m^3, BENCHMARKS.md session 29)
TUNING = dataclasses.replace(DEFAULT, budget_cells=16, direction_samples=20_000)


@pytest.fixture(scope="module")
def iiwa():
    return industrial_arm("iiwa")


@pytest.fixture(scope="module")
def paving(iiwa):
    return reach(iiwa, delta=0.2, pose=Pose(**TOOL_DOWN), tuning=TUNING)


@pytest.fixture(scope="module")
def oriented(iiwa):
    """Tool-down configurations of the iiwa (floats) and their tool points."""
    R = np.array(constraint_from(**TOOL_DOWN).matrix, dtype=float)
    return oriented_configurations(iiwa, 300_000, 5, R)


@pytest.mark.slow
def test_the_iiwa_tool_down_goes_through_its_wrist_centre(iiwa, paving):
    """The structure is recognised with the URDF's numbers (flange 63/500 m, an exact approach, the spin's
    condition) and the run proves boxes of both kinds with a bracket."""
    centre = pose_structure(iiwa, (), constraint_from(**TOOL_DOWN), TUNING).centre
    assert centre is not None and centre.cone == 0 and centre.spin is not None
    assert centre.length == sp.Rational(63, 500) and centre.sign == -1
    assert paving.method == "section" and paving.counts["inner"] > 0 and paving.counts["outer"] > 0
    lo, hi = paving.measure_bounds
    assert 0 < lo < hi


@pytest.mark.slow
def test_tool_down_configurations_never_land_in_an_outer_box_and_the_bracket_holds_their_volume(iiwa, paving,
                                                                                               oriented):
    """Sampled configurations within the limits with the tool frame exactly down: their tool points never lie in
    an outer box (narrowed by 1e-9 for float rounding), and their volume estimate (cells of 0.02 with their arcs,
    ``arcs_volume``: no bound, about half a cell high along the boundary; with the configurations of 6e5 samples,
    1.85 m^3, 1.98 at cells of 0.04; 1.81 at 0.01 with 6.1e5 configurations, session 29) lies in the bracket."""
    q, points = oriented
    assert len(points) > 25_000
    assert not in_any_box(points, paving.outer, pad=-1e-9).any()
    lo, hi = paving.measure_bounds
    assert lo <= arcs_volume(iiwa, q[:, 0], points, 0.02) <= hi


@pytest.mark.slow
def test_points_of_inner_boxes_are_reached_tool_down_at_50_digits(iiwa, paving):
    """A point drawn in each of 4 inner boxes is the tool point of a configuration within the limits whose tool
    frame is exactly Rx(pi), found by least squares and refined at 50 digits (checked there)."""
    rng = np.random.default_rng(8)
    R = constraint_from(**TOOL_DOWN).matrix
    for box in paving.inner[rng.choice(len(paving.inner), 4, replace=False)]:
        point = rng.uniform(box[:, 0], box[:, 1])
        assert arm_in_pose_at_50_digits(iiwa, point, R, rng) is not None, point


@pytest.mark.slow
def test_an_exact_approach_is_the_wrist_centres_section_translated(iiwa):
    """An exact approach straight down (a cone of 0: no spin asked) goes through the wrist centre with one tilt;
    configurations with the approach made exact by Newton on joints 5 and 6 (floats) never land in an outer box,
    and their volume estimate (cells of 0.02 with their arcs) lies in the bracket."""
    exact = dict(approach=(0, 0, -1), cone=0)
    centre = pose_structure(iiwa, (), constraint_from(**exact), TUNING).centre
    assert centre is not None and centre.cone == 0 and centre.spin is None
    paving = reach(iiwa, delta=0.2, pose=Pose(**exact), tuning=TUNING)
    q, _, points = admissible_configurations(iiwa, 150_000, 6, approach=(0, 0, -1), wrist=(4, 5))
    assert len(points) > 10_000
    assert not in_any_box(points, paving.outer, pad=-1e-9).any()
    lo, hi = paving.measure_bounds
    assert 0 < lo <= arcs_volume(iiwa, q[:, 0], points, 0.02) <= hi


@pytest.mark.slow
@pytest.mark.parametrize("yaw", [0, 135])
def test_the_spin_condition_agrees_with_a_wrist_solved_within_the_limits(iiwa, yaw):
    """Second method for SpinCondition: at arm configurations with the roll axis within the wrist's reach of straight
    down (joint 3 near 0, where one wrist solution leaves the roll's limits), one of the two solutions is within
    the limits per the condition (floats) iff one of the wrist's solutions (joints 5-7 by least squares from 12
    starts, without limits, then wrapped into them by whole turns) lies within the limits; 12 configurations the
    condition admits and 8 it refuses (drawn until both counts are met)."""
    from scipy.optimize import least_squares

    con = constraint_from(rpy=(180, 0, yaw))
    centre = pose_structure(iiwa, (), con).centre
    spin, R = centre.spin, np.array(con.matrix, dtype=float)
    q_all = list(iiwa.q)
    X, V2, side = (sp.lambdify([q_all], e) for e in (spin.X, spin.V2, centre.side))
    Y = sp.lambdify([[spin.turn] + q_all], spin.Y)
    theta_1 = sp.lambdify([q_all], iiwa.joints[0].theta)
    c_roll, c_spin = float(spin.roll) ** 0.5, float(spin.spin) ** 0.5
    limits = iiwa.joint_limits()
    rng = np.random.default_rng(yaw)
    wanted = {True: 8, False: 8}
    answers = []
    for _ in range(200_000):
        if not any(wanted.values()):
            break
        q = rng.uniform(limits[:, 0], limits[:, 1])
        q[2] = rng.uniform(-0.15, 0.15)
        if side(q) < math.cos(float(centre.psi)) + 0.02:
            continue
        x, v, y = X(q), math.sqrt(max(V2(q), 0.0)), Y([theta_1(q)] + list(q))
        margins = [-x + c_roll * v, x + c_roll * v, -y + c_spin * v, y + c_spin * v]
        predicted = bool((margins[0] >= 0 and margins[2] >= 0) or (margins[1] >= 0 and margins[3] >= 0))
        if min(abs(m) for m in margins) < 1e-3 or not wanted[predicted]:
            continue                                 # near the condition's boundary for floats, or enough
        wanted[predicted] -= 1

        def residual(w, q=q):
            return (iiwa.fk_numeric(np.r_[q[:4], w][None])[0][:3, :3] - R).ravel()

        # the wrist's solutions without limits (two, modulo a turn), each wrapped into the limits and checked
        fits = [least_squares(residual, rng.uniform(-np.pi, np.pi, 3), xtol=1e-15, ftol=1e-15, gtol=1e-15)
                for _ in range(12)]
        low, high = limits[4:, 0], limits[4:, 1]
        wrapped = [np.remainder(fit.x - low, 2 * np.pi) + low for fit in fits if np.abs(fit.fun).max() < 1e-9]
        assert wrapped
        answers.append((predicted, any(bool((w <= high).all()) for w in wrapped)))
    assert not any(wanted.values())
    assert all(p == a for p, a in answers), [(i, p, a) for i, (p, a) in enumerate(answers) if p != a]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(0, 2 ** 12 - 1), min_size=16, max_size=16), st.integers(0, 10 ** 6))
def test_covered_bins_hold_only_angles_of_passing_sectors(masks, seed):
    """SpinSectors.covered_bins: every angle of a bin it marks lies in a sector that passes at some direction
    (checked at 50 random angles per covered bin and at its two ends, each direction's sector found from the
    angle and the sectors' edges); and with every sector passing at two opposite directions, the whole circle is
    covered (reference: two arcs of 340 deg half a turn apart cover it)."""
    t = sp.Symbol("t")
    condition = SpinCondition(t, sp.S.Zero, t, sp.S.One, None, sp.S.Zero)     # the masks are given, not computed
    a, b = -2.9668 + math.pi, 2.9668 + math.pi
    spin = SpinSectors(condition, (), (a, b), count=12, bins=180, directions=16)
    bits = np.array([[m] for m in masks], dtype=np.uint64)
    covered = spin.covered_bins(bits)[0]
    assert spin.bins_covered(bits)[0] == covered.sum()
    rng = np.random.default_rng(seed)
    width = 2 * math.pi / spin.bins
    at = np.nonzero(covered)[0][:, None]                 # each covered bin's two ends and 50 angles drawn in it
    psi = np.concatenate([at * width, (at + 1) * width, rng.uniform(at * width, (at + 1) * width, (len(at), 50))], 1)
    passes = np.zeros(psi.shape, dtype=bool)
    for k in range(16):
        passes |= _sector_passes(spin, masks[k], psi, k)
    assert passes.all(), (at[:, 0][~passes.all(axis=1)], psi[~passes])
    full = np.zeros((16, 1), dtype=np.uint64)
    full[[0, 8]] = (1 << 12) - 1
    assert spin.bins_covered(full)[0] == spin.bins


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.floats(1e-4, 0.5), st.integers(1, 64))
def test_sectors_read_from_the_linear_form_hold_at_random_points(seed, size, count):
    """SpinSectors.masks from ``Y = A cos(t) + B sin(t) + C`` (SpinCondition.linear: three enclosures a box, the
    sectors' intersection of the natural and mean-value forms) against brute force: ``A, B, C, V^2`` are the box's
    own variables, the last joint's half range 120 deg; wherever a sector is marked, one solution's inequality
    (``-Y >= cos(h) V`` or ``Y >= cos(h) V``) holds at all of 400 random points of (sector x box) and its corners;
    with narrow sectors, boxes of width zero pass somewhere."""
    a, b, c, v, t = sp.symbols("a b c v t")
    condition = SpinCondition(t, sp.S.Zero, a * sp.cos(t) + b * sp.sin(t) + c, v, None, sp.Rational(1, 4),
                              linear=(a, b, c))
    spin = SpinSectors(condition, (a, b, c, v), (-2.9, 2.9), count=count, bins=72, directions=4)
    rng = np.random.default_rng(seed)
    centre = np.concatenate([rng.uniform(-1, 1, (30, 3)), rng.uniform(0.05, 1, (30, 1))], axis=1)
    U = np.stack([centre - size, centre + size], axis=2)
    U[:, 3, 0] = np.maximum(U[:, 3, 0], 0.0)
    masks = spin.masks(U)
    for box, mask in zip(U, masks):
        for i in range(count):
            if not int(mask) >> i & 1:
                continue
            pts = rng.uniform(box[:, 0], box[:, 1], (400, 4))
            ts = rng.uniform(spin.edges[i], spin.edges[i + 1], 400)
            pts[:2], ts[:2] = box[:, [0, 1]].T, spin.edges[i:i + 2]
            y = pts[:, 0] * np.cos(ts) + pts[:, 1] * np.sin(ts) + pts[:, 2]
            bound = -0.5 * np.sqrt(pts[:, 3])
            assert (-y >= bound - 1e-12).all() or (y >= bound - 1e-12).all(), (box, i)
    if count >= 16:                 # narrow sectors: boxes of width zero pass somewhere (the test is not empty)
        assert spin.masks(np.repeat(centre[:, :, None], 2, axis=2)).any()


def _sector_passes(spin, mask, psi, k):
    """Whether each polar angle of the array ``psi`` is ``theta_1 + k 2 pi / 16`` for a ``theta_1`` in a passing sector
    of ``k`` (the sectors' closed intervals between consecutive edges, read one by one with numpy's comparisons)."""
    theta = np.remainder(psi - k * 2 * math.pi / 16 - spin.edges[0], 2 * math.pi) + spin.edges[0]
    edges = np.asarray(spin.edges, dtype=float)
    passing = np.array([bool(mask >> i & 1) for i in range(spin.count)])
    inside = (edges[:-1] <= theta[..., None]) & (theta[..., None] <= edges[1:])
    return (inside & passing).any(axis=-1)


@pytest.mark.slow
def test_a_passing_sector_holds_a_solution_within_the_limits_at_exact_points(iiwa):
    """SpinSectors.masks against SpinCondition's exact inequalities: over small random boxes of joints 2-4 with the
    roll axis within the wrist's reach, every sector marked as passing has, at 2 random rational points of (sector
    x box) and at the box's corner with the sector's ends, one of the two solutions within the roll's and the last
    joint's limits, the inequalities evaluated at 50 digits with no tolerance (the limits' constants exact); and
    some sectors pass and some fail."""
    import mpmath

    con = constraint_from(**TOOL_DOWN)
    centre = pose_structure(iiwa, (), con).centre
    (_, limited), = centre.levels()
    lateral = limited.plan.section.lateral
    spin, condition = lateral.spin, centre.spin
    names = list(lateral.variables)
    X, V2, roll, turn = (sp.lambdify([names], e, modules="mpmath")
                         for e in (condition.X, condition.V2, sp.sqrt(condition.roll), sp.sqrt(condition.spin)))
    Y = sp.lambdify([[condition.turn] + names], condition.Y, modules="mpmath")
    rng = np.random.default_rng(3)
    centres = lateral.random_configurations(50, rng)
    U = np.stack([centres - 0.01, centres + 0.01], axis=2)
    masks = spin.masks(U)
    passing = failing = 0
    with mpmath.workdps(50):
        c_roll, c_spin = roll(names), turn(names)         # constants: |cos(h)|, exact to 50 digits
        for box, mask in zip(U, masks):
            for i in range(spin.count):
                if not int(mask) >> i & 1:
                    failing += 1
                    continue
                passing += 1
                corners = [(box[:, 0], spin.edges[i]), (box[:, 1], spin.edges[i + 1])]
                points = corners + [(rng.uniform(box[:, 0], box[:, 1]), rng.uniform(spin.edges[i], spin.edges[i + 1]))
                                    for _ in range(2)]
                for q, t in points:
                    q = [mpmath.mpf(Fraction(float(v)).numerator) / Fraction(float(v)).denominator for v in q]
                    t = mpmath.mpf(Fraction(float(t)).numerator) / Fraction(float(t)).denominator
                    x, v, y = X(q), mpmath.sqrt(max(V2(q), 0)), Y([t] + q)
                    plus = -x >= -c_roll * v and -y >= -c_spin * v
                    minus = x >= -c_roll * v and y >= -c_spin * v
                    assert plus or minus, (box, i, t, q)
    assert passing > 250 and failing > 10
