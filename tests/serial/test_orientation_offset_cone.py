"""Issue 40: an exact approach and a cone about straight down on the Panda (roboticstoolbox's modified DH table,
``tests/data/dh/panda.json``), whose flange is offset 0.088 m sideways from its last joint's axis (docs/methods.md
section 8, "A flange offset sideways: an exact approach and a cone").  The wrist's two solutions at the exact
approach are paved as for tool down, without the spin's condition (each proof holds on its whole arc); a cone adds
the outer proofs of every approach within it: the solutions' maps widened to every approach
(``FlangeMap.enclose_outer``, their conditions with a slack) and the tool point's own section pruned where the
approach is proved outside the cone.

References: the robot's own forward kinematics of configurations sampled within the limits (approach within the
cone by ``fk_numeric``, or made exactly down by Newton on joints 5 and 6); an inverse kinematics at 50 digits
(mpmath) for points of proved pieces.
"""

import dataclasses

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from reach_checks import (
    FreeRun,
    admissible_configurations,
    arm_in_cone_at_50_digits,
    arm_in_pose_at_50_digits,
    in_any_box,
    industrial_arm,
    paved_roots,
    piece_point,
)
from workspace_sym.serial import Pose, reach
from workspace_sym.serial.pose import constraint_from, offset_flange, pose_structure
from workspace_sym.serial.tuning import DEFAULT
from workspace_sym.serial.turn import SideMap, SpinSectors, pave_limited, roots_volume

DOWN = (0, 0, -1)
CONE = 20
# Coarse cells and few seeds: outer boxes and a bracket in seconds
TUNING = dataclasses.replace(DEFAULT, budget_cells=8, direction_samples=5_000, direction_depth=1, flange_pairs=15_000)
BOXES = 30_000          # the sections' budget of boxes (the same cells on every machine)


@pytest.fixture(scope="module")
def panda():
    return industrial_arm("panda")


@pytest.fixture(scope="module")
def cone(panda):
    return pose_structure(panda, (), constraint_from(approach=DOWN, cone=CONE), TUNING).flange


@pytest.fixture(scope="module")
def exact(panda):
    return pose_structure(panda, (), constraint_from(approach=DOWN, cone=0), TUNING).flange


@pytest.fixture(scope="module")
def in_cone(panda):
    """Configurations within the limits whose approach lies within the cone (floats), with their tool points; the
    tenth nearest the cone's rim first."""
    q, R, p = admissible_configurations(panda, 600_000, 11, approach=DOWN, cone=CONE)
    order = np.argsort(-R[:, 2, 2])         # a_z from -cos(c) (the rim) down to -1
    return q[order], p[order]


def _section_frame(q, p):
    """Tool points turned back by the first joint (``theta_1 = q_1`` on the Panda's table): the section's frame."""
    c, s = np.cos(-q[:, 0]), np.sin(-q[:, 0])
    return np.stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1], p[:, 2]], axis=1)


def test_the_structures_of_an_exact_approach_and_of_a_cone(panda, exact, cone):
    """The exact approach: the two solutions with their pitch and roll conditions, each proof kept on its arc (a
    condition-free SpinSectors of one sector), no outer map.  The cone of 20 deg: the same solutions at the exact
    approach, their conditions' slack c and 2 c (radians), and the tool point's section pruned by ``a_z <= -cos c``.
    Every direction of a cone, and a cone of a quarter turn, are not this structure."""
    assert exact is not None and exact.outer is None and exact.sign == -1
    for _, limited in exact.roots:
        lateral = limited.plan.section.lateral
        assert isinstance(lateral, SideMap) and lateral.prune and len(lateral.sides) == 2
        assert isinstance(lateral.spin, SpinSectors) and lateral.spin.condition is None and lateral.spin.count == 1
        assert lateral.slack == (0.0, 0.0) and lateral.cone is None
    c = np.radians(CONE)
    for _, limited in cone.roots:
        lateral = limited.plan.section.lateral
        assert lateral.slack == pytest.approx((c, 2 * c), abs=1e-15) and lateral.slack[0] >= c
    outer = cone.outer.plan.section.lateral
    assert outer.prune and len(outer.variables) == 5 and outer.sides[0][1] == pytest.approx(np.cos(c), abs=1e-15)
    assert offset_flange(panda, (), constraint_from(approach=DOWN, cone=CONE, every=True)) is None
    assert offset_flange(panda, (), constraint_from(approach=DOWN, cone=90)) is None


def test_sectors_without_a_condition_pass_everywhere(exact):
    """A SpinSectors without a condition sets its one sector on every box, and a proof at direction k covers the bins
    of its arc only (the first joint's 332 deg from k pi / 2), as the arcs of the limited turn say."""
    spin = exact.roots[0][1].plan.section.lateral.spin
    masks = spin.masks(np.zeros((5, 3, 2)))
    assert (masks == 1).all()
    one = np.zeros((4, 1), dtype=np.uint64)
    one[0] = 1
    covered = spin.covered_bins(one)[0]
    a, b = spin.edges[0], spin.edges[-1]
    centres = (np.arange(spin.bins) + 0.5) * 2 * np.pi / spin.bins
    in_arc = np.remainder(centres - a, 2 * np.pi) <= b - a
    assert covered.sum() > 0.9 * spin.bins * (b - a) / (2 * np.pi)
    assert not (covered & ~in_arc).any()
    one[1] = 1
    assert spin.covered_bins(one)[0].all()


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.floats(1e-6, 0.3), st.booleans())
def test_the_widened_enclosures_hold_every_approach_of_the_cone(cone, in_cone, seed, size, rim):
    """Property (the outer proofs' soundness): for configurations sampled with the approach within the cone (half of
    the examples drawn from the tenth nearest the rim), a joint box of random size about joints 2-4 holds the
    tool point (in the section's frame) in the widened enclosure (``enclose_outer``) of a solution whose
    conditions it is not refused on (slack included), and a box about joints 2-6 is never refused by the tool
    point's section and holds its tool point."""
    q, p = in_cone
    rng = np.random.default_rng(seed)
    pick = rng.integers(0, len(q) // 10 if rim else len(q), 40)
    q, p = q[pick], _section_frame(q[pick], p[pick])
    held = np.zeros(len(q), dtype=bool)
    for _, limited in cone.roots:
        lateral = limited.plan.section.lateral
        lo, hi = lateral.limits[:, 0], lateral.limits[:, 1]
        box = np.stack([np.maximum(q[:, 1:4] - size, lo), np.minimum(q[:, 1:4] + size, hi)], axis=2)
        E = lateral.enclose_outer(box)
        held |= ((E[:, :, 0] <= p) & (p <= E[:, :, 1])).all(axis=1) & ~lateral.refused(box)
    assert held.all(), np.nonzero(~held)
    outer = cone.outer.plan.section.lateral
    lo, hi = outer.limits[:, 0], outer.limits[:, 1]
    box = np.stack([np.maximum(q[:, 1:6] - size, lo), np.minimum(q[:, 1:6] + size, hi)], axis=2)
    E = outer.enclose_outer(box)
    assert not outer.refused(box).any()
    assert ((E[:, :, 0] <= p + 1e-12) & (p - 1e-12 <= E[:, :, 1])).all()


def test_the_widened_enclosure_holds_approaches_on_the_rim_in_every_azimuth(panda, cone):
    """Second method at the edge: configurations whose approach is made exactly a direction on the cone's rim (20
    deg from straight down, 8 azimuths; Newton on joints 5 and 6) have their tool points in a solution's widened
    point enclosure (not refused), and the widening is needed: some lie outside the exact approach's."""
    c = np.radians(CONE)
    held, needed = 0, 0
    for k, azimuth in enumerate(np.linspace(0, 2 * np.pi, 8, endpoint=False)):
        a = (np.sin(c) * np.cos(azimuth), np.sin(c) * np.sin(azimuth), -np.cos(c))
        q, _, p = admissible_configurations(panda, 40_000, 20 + k, approach=a, cone=None, wrist=(4, 5))
        p = _section_frame(q, p)
        box = np.repeat(q[:, 1:4, None], 2, axis=2)
        ok, exact = np.zeros(len(q), dtype=bool), np.zeros(len(q), dtype=bool)
        for _, limited in cone.roots:
            lateral = limited.plan.section.lateral
            E, E0 = lateral.enclose_outer(box), lateral.enclose(box)
            ok |= ((E[:, :, 0] <= p) & (p <= E[:, :, 1])).all(axis=1) & ~lateral.refused(box)
            exact |= ((E0[:, :, 0] - 1e-9 <= p) & (p <= E0[:, :, 1] + 1e-9)).all(axis=1)
        assert len(q) > 50 and ok.all()
        held, needed = held + len(q), needed + int((~exact).sum())
    assert needed > 0.9 * held


@pytest.fixture(scope="module")
def runs(panda):
    """The exact approach and the cone, each paved by the plan with the coarse tuning."""
    return {cone: reach(panda, delta=0.1, pose=Pose(approach=DOWN, cone=cone), tuning=TUNING) for cone in (0, CONE)}


@pytest.mark.slow
def test_sampled_configurations_never_land_in_an_outer_box(panda, runs, in_cone):
    """Configurations within the limits with the approach exactly down (Newton on joints 5 and 6) never put the
    tool point in an outer box of the exact approach's paving, nor those within the cone in the cone's (narrowed
    by 1e-9 for float rounding); both runs go through the flange's sections and prove outer boxes, the cone's
    upper bound above the exact approach's lower."""
    q, _, points = admissible_configurations(panda, 300_000, 3, approach=DOWN, cone=None, wrist=(4, 5))
    assert len(points) > 20_000
    exact, wide = runs[0], runs[CONE]
    assert exact.method == wide.method == "section"
    assert exact.counts["outer"] > 0 and wide.counts["outer"] > 0
    assert not in_any_box(points, exact.outer, pad=-1e-9).any()
    assert not in_any_box(points, wide.outer, pad=-1e-9).any()
    assert not in_any_box(in_cone[1], wide.outer, pad=-1e-9).any()
    assert wide.measure_bounds[1] >= exact.measure_bounds[0]


@pytest.fixture(scope="module")
def sections(exact):
    """Both solutions' sections at the exact approach on one grid of 0.03 m (no time limit, a budget of boxes)."""
    return paved_roots([limited for _, limited in exact.roots], 0.03,
                       dataclasses.replace(DEFAULT, direction_samples=20_000, direction_depth=1), BOXES)


@pytest.mark.slow
def test_points_of_proved_pieces_are_reached_with_the_approach_down_at_50_digits(panda, sections):
    """A point drawn in each of 4 pieces proved at a direction, at a polar angle of that direction's arc, is the
    tool point of a configuration within the limits whose tool frame is exactly ``Rz(yaw) Rx(pi)`` for one of six
    yaws (any spin will do: the approach is then exactly down), found by least squares and refined at 50 digits."""
    grid, parts = sections
    rng = np.random.default_rng(4)
    found = [(p, *where) for p, (_, _, pieces, _) in enumerate(parts) for where in np.argwhere(pieces)]
    assert len(found) > 100
    frames = [sp.ImmutableMatrix(constraint_from(rpy=(180, 0, yaw)).matrix) for yaw in range(0, 360, 60)]
    for p, k, a, b in [found[i] for i in rng.choice(len(found), 4, replace=False)]:
        limited, _, pieces, _ = parts[p]
        point = piece_point(grid, pieces, k, a, b, rng, limited.inner_range)
        assert any(arm_in_pose_at_50_digits(panda, point, R, rng, starts=8) is not None for R in frames), point


@pytest.mark.slow
def test_points_of_the_cone_maps_proofs_are_reached_in_the_cone_at_50_digits(panda, cone):
    """The tool point's section pruned by the cone proves pieces too (its Krawczyk boxes with ``a_z <= -cos c``
    proved): a point drawn in 3 of them, at a polar angle of the direction's arc, is reached within 20 deg of
    straight down at 50 digits."""
    tuning = dataclasses.replace(DEFAULT, direction_samples=5_000, direction_depth=1)
    grid, _, pieces, _, _ = pave_limited(cone.outer, 0.05, FreeRun(), tuning=tuning, boxes=3_000)
    found = np.argwhere(pieces)
    assert len(found) > 20
    rng = np.random.default_rng(6)
    for k, a, b in found[rng.choice(len(found), 3, replace=False)]:
        point = piece_point(grid, pieces, k, a, b, rng, cone.outer.inner_range)
        assert arm_in_cone_at_50_digits(panda, point, DOWN, CONE, rng, anywhere=True) is not None, point


def test_the_cones_outer_cells_are_given_to_the_union(sections):
    """roots_volume with its ``outer``: those cells and no others are outer, whatever the maps' own outer cells."""
    grid, parts = sections
    outer = np.zeros(grid.shape, dtype=bool)
    outer[: grid.shape[0] // 3] = True
    codes, (lo, hi) = roots_volume(parts, grid, outer=outer)
    assert ((codes == -1) == outer).all()
    alone, (lo0, hi0) = roots_volume(parts, grid)
    assert ((alone == -1) == ((parts[0][1] == -1) & (parts[1][1] == -1))).all()
    assert lo <= hi and lo0 <= hi0


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.floats(0.01, 1.5))
def test_the_widening_of_the_offsets_direction_holds_on_random_axes_and_approaches(seed, c):
    """Property for the theorem behind ``enclose_outer`` (docs/methods.md section 8), independent of any robot: for
    random unit roll axes ``z`` and approaches ``a`` within ``c`` of ``d = (0, 0, -1)`` (a quarter of them on the
    rim), the unit ``u_a`` of ``z - (z . a) a`` differs from ``u_d`` in each horizontal component by at most the
    lesser of ``c / s`` and ``c sqrt(sin(c)^2 + (min(1, |z_z| + V sin c) / s)^2)``, ``s = V cos c - |z_z| sin c >
    0``, and ``|u_a . d| <= 2 sin(c / 2)``."""
    rng = np.random.default_rng(seed)
    n = 20_000
    z = rng.normal(size=(n, 3))
    z /= np.linalg.norm(z, axis=1)[:, None]
    tilt = c * np.sqrt(rng.uniform(0, 1, n))
    tilt[: n // 4] = c
    azimuth = rng.uniform(0, 2 * np.pi, n)
    a = np.stack([np.sin(tilt) * np.cos(azimuth), np.sin(tilt) * np.sin(azimuth), -np.cos(tilt)], axis=1)
    d = np.broadcast_to(np.array([0.0, 0.0, -1.0]), (n, 3))

    def unit(v):
        h = z - (z * v).sum(axis=1)[:, None] * v
        return h / np.linalg.norm(h, axis=1)[:, None]

    u_a, u_d = unit(a), unit(d)
    V, zz = np.hypot(z[:, 0], z[:, 1]), np.abs(z[:, 2])
    s = V * np.cos(c) - zz * np.sin(c)
    bound = np.minimum(c / s, c * np.sqrt(np.sin(c) ** 2 + (np.minimum(1.0, zz + V * np.sin(c)) / s) ** 2))
    ok = s > 1e-6
    assert ok.sum() > n // 10
    assert (np.abs(u_a - u_d)[ok, :2].max(axis=1) <= bound[ok] * (1 + 1e-9) + 1e-12).all()
    assert (np.abs(u_a[:, 2]) <= 2 * np.sin(c / 2) + 1e-12).all()


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2 ** 32 - 1))
def test_the_widened_enclosures_hold_the_formula_at_exact_points(panda, cone, seed):
    """Exact-rational property for the cone's outer proofs (FlangeMap.enclose_outer): over 10 random joint boxes of
    joints 2-4 (1e-4 to 0.3 rad), at 3 rational points of each and approaches of rational tilt (a third exactly on
    the rim, 20 deg) and azimuth, the tool point ``w + L a - sigma e u_a`` of each solution, evaluated at 50 digits
    from the robot's own roll frame (``L`` = 0.107 + 0.103 m and ``e`` = 0.088 m of the table), lies in that
    solution's widened enclosure."""
    import mpmath

    frame = sp.lambdify([list(panda.q)], list(panda.substitute(panda.fk(5))[:3, 2:4]), modules="mpmath")
    rng = np.random.default_rng(seed)
    with mpmath.workdps(50):
        L, e, c = mpmath.mpf("0.107") + mpmath.mpf("0.103"), mpmath.mpf("0.088"), mpmath.radians(CONE)
        for sigma, limited in cone.roots:
            lateral = limited.plan.section.lateral
            lo, hi = lateral.inner_limits[:, 0], lateral.inner_limits[:, 1]
            centres = rng.uniform(lo, hi, size=(10, 3))
            size = rng.uniform(1e-4, 0.3, size=(10, 1))
            boxes = np.stack([np.maximum(centres - size, lo), np.minimum(centres + size, hi)], axis=2)
            E = lateral.enclose_outer(boxes)
            for b in range(len(boxes)):
                for i in range(3):
                    q = [mpmath.mpf(0)] + [mpmath.mpf(float(rng.uniform(boxes[b, j, 0], boxes[b, j, 1])))
                                           for j in range(3)] + [mpmath.mpf(0)] * 3
                    values = frame(q)
                    z, w = values[0::2], values[1::2]          # the rows of (z | o), flattened
                    tilt = c if i == 0 else c * mpmath.mpf(float(rng.uniform(0, 1)))
                    azimuth = mpmath.mpf(float(rng.uniform(-np.pi, np.pi)))
                    a = [mpmath.sin(tilt) * mpmath.cos(azimuth), mpmath.sin(tilt) * mpmath.sin(azimuth),
                         -mpmath.cos(tilt)]
                    za = sum(x * y for x, y in zip(z, a))
                    h = [x - za * y for x, y in zip(z, a)]
                    norm = mpmath.sqrt(sum(x * x for x in h))
                    p = [w[k] + L * a[k] - sigma * e * h[k] / norm for k in range(3)]
                    assert all(E[b, k, 0] <= p[k] <= E[b, k, 1] for k in range(3)), (sigma, b, p, E[b])
