"""Issue 40: a constant orientation (tool down) of the Panda (roboticstoolbox's modified DH table,
``tests/data/dh/panda.json``), whose flange is offset 0.088 m sideways from its last joint's axis (docs/methods.md
section 8, "A flange offset sideways"): each of the wrist's two solutions puts the tool point at
``w + L d - sigma e h / |h|``, a map of joints 2-4 turned by the first (pose.OffsetFlange), paved as a limited turn
with its own pitch, roll and spin conditions; the two sections are read together (turn.roots_volume).

References: the robot's own forward kinematics with the wrist solved by least squares without limits (scipy), then
wrapped into the limits; configurations sampled within the limits with the frame made exact by Newton (floats); an
inverse kinematics at 50 digits (mpmath) for points of inner boxes.
"""

import dataclasses
import functools

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from reach_checks import (
    arcs_volume,
    arm_in_pose_at_50_digits,
    in_any_box,
    industrial_arm,
    oriented_configurations,
    paved_roots,
    piece_point,
)
from workspace_sym.serial import Pose, reach
from workspace_sym.serial.pose import constraint_from, offset_flange, pose_structure
from workspace_sym.serial.tuning import DEFAULT
from workspace_sym.serial.turn import roots_volume, spin_volume

TOOL_DOWN = dict(rpy=(180, 0, 0))
# Coarse cells and few seeds: outer boxes in seconds, no inner cell (a 300 s limit: BENCHMARKS.md, session 30)
TUNING = dataclasses.replace(DEFAULT, budget_cells=12, direction_samples=5_000, direction_depth=1)
BOXES = 30_000          # the sections' budget of boxes (the same cells on every machine)


@pytest.fixture(scope="module")
def panda():
    return industrial_arm("panda")


@pytest.fixture(scope="module")
def flange(panda):
    return pose_structure(panda, (), constraint_from(**TOOL_DOWN), TUNING).flange


@pytest.fixture(scope="module")
def paving(panda):
    return reach(panda, delta=0.1, pose=Pose(**TOOL_DOWN), tuning=TUNING)


@pytest.fixture(scope="module")
def oriented(panda):
    """Tool-down configurations of the Panda (floats) and their tool points."""
    R = np.array(constraint_from(**TOOL_DOWN).matrix, dtype=float)
    return oriented_configurations(panda, 200_000, 5, R, wrist=(4, 5))


def _world(lateral, q):
    """The tool points of a root's map at configurations ``q`` (all seven joints), turned by the first joint
    (``theta_1 = q_1`` in the Panda's table)."""
    p = lateral.position_float(q[:, 1:4])
    c, s = np.cos(q[:, 0]), np.sin(q[:, 0])
    return np.stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1], p[:, 2]], axis=1)


@pytest.mark.slow
def test_the_panda_tool_down_goes_through_the_wrists_two_solutions(panda, flange, paving):
    """The structure is recognised with the table's numbers (two roots, each with its pitch's and roll's side
    conditions, pruning its outer proofs, and its own root's spin condition) and the run proves outer boxes with a
    bracket."""
    assert flange is not None and flange.sign == -1 and [s for s, _ in flange.roots] == [1, -1]
    for sigma, limited in flange.roots:
        lateral = limited.plan.section.lateral
        assert lateral.spin is not None and lateral.spin.root == sigma and len(lateral.sides) == 2 and lateral.prune
    every = constraint_from(approach=(0, 0, -1), cone=20, every=True)
    assert offset_flange(panda, (), every) is None                      # every direction of a cone: not this
    assert paving.method == "section" and paving.counts["outer"] > 0
    lo, hi = paving.measure_bounds
    assert 0 <= lo < hi


@pytest.mark.slow
def test_each_roots_map_is_the_tool_point_of_the_configurations_of_that_root(flange, oriented):
    """Second method for the map: the tool points of tool-down configurations (the robot's own forward kinematics)
    are those of the map of their root, read from the pitch (``sin(theta_6) = -sigma |z x d|`` for the Panda's
    twists), to 1e-9; both roots occur.  The structure carries the wrist's ring for its outer cells (its own
    tests: tests/serial/test_reach_map_ring.py)."""
    assert flange.ring is not None and flange.cone == 0 and flange.sign == -1
    q, points = oriented
    maps = dict(flange.roots)
    sigma = -np.sign(np.sin(q[:, 5]))
    for root in (1, -1):
        mine = sigma == root
        assert mine.sum() > 500
        assert np.abs(_world(maps[root].plan.section.lateral, q[mine]) - points[mine]).max() < 1e-9


@pytest.mark.slow
@pytest.mark.parametrize("yaw", [0, 120])
def test_the_conditions_agree_with_a_wrist_solved_within_the_limits(panda, yaw):
    """Second method for the pitch, roll and spin conditions: at random arm configurations (joints 1-4 within the
    limits), each root's conditions (floats) hold iff the wrist's solution of that root (joints 5-7 by least
    squares from 10 starts, without limits, then wrapped into them by whole turns; its root read from the pitch
    axis) lies within the limits; 10 configurations per root admitted and 10 refused."""
    from scipy.optimize import least_squares

    con = constraint_from(rpy=(180, 0, yaw))
    flange = pose_structure(panda, (), con, TUNING).flange         # yaw 0: the module's structure
    R = np.array(con.matrix, dtype=float)
    d = R[:, 2]
    limits = panda.joint_limits()
    low, high = limits[4:, 0], limits[4:, 1]
    z_roll = sp.lambdify([list(panda.q)], list(panda.substitute(panda.fk(5))[:3, 2]))
    z_pitch = sp.lambdify([list(panda.q)], list(panda.substitute(panda.fk(6))[:3, 2]))
    rng = np.random.default_rng(yaw)
    for sigma, limited in flange.roots:
        lateral = limited.plan.section.lateral
        spin, side = lateral.spin.condition, lateral._sides_float[0]
        X = sp.lambdify([[spin.turn] + list(lateral.variables)], spin.X)
        Y = sp.lambdify([[spin.turn] + list(lateral.variables)], spin.Y)
        V = sp.lambdify([[spin.turn] + list(lateral.variables)], sp.sqrt(spin.V2))
        c_roll, c_spin = -float(spin.roll) ** 0.5 if spin.roll is not None else -1.0, -float(spin.spin) ** 0.5
        wanted = {True: 10, False: 10}
        for _ in range(20_000):
            if not any(wanted.values()):
                break
            q = rng.uniform(limits[:, 0], limits[:, 1])
            args = [q[0]] + list(q[1:4])
            x, y, v = X(args), Y(args), V(args)
            margins = [-sigma * x - c_roll * v, -sigma * y - c_spin * v, side(q[1:4]) - lateral.sides[0][1]]
            predicted = bool(min(margins) >= 0)
            if v < 1e-2 or min(abs(m) for m in margins) < 1e-3 or not wanted[predicted]:
                continue                                # near a condition's boundary for floats, or enough
            wanted[predicted] -= 1

            def residual(w, q=q):
                return (panda.fk_numeric(np.r_[q[:4], w][None])[0][:3, :3] - R).ravel()

            fits = [least_squares(residual, rng.uniform(-np.pi, np.pi, 3), xtol=1e-15, ftol=1e-15, gtol=1e-15)
                    for _ in range(10)]
            mine = []
            for fit in fits:
                if np.abs(fit.fun).max() > 1e-9:
                    continue
                full = np.r_[q[:4], fit.x]
                root = np.sign(np.dot(z_pitch(full), np.cross(z_roll(full), d)))
                if root == sigma:
                    mine.append(np.remainder(fit.x - low, 2 * np.pi) + low)
            assert mine, (sigma, q)
            assert predicted == any(bool((w <= high).all()) for w in mine), (sigma, q, predicted)
        assert not any(wanted.values())


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.floats(1e-4, 0.5))
def test_the_maps_enclosures_hold_their_points_even_where_the_roll_axis_is_vertical(flange, seed, size):
    """Property: over random joint boxes (a third of them centred where the roll axis is vertical, joint 4 set so
    that joints 2-4 sum to a vertical axis, ``|h| = 0``: the unit vector's own enclosure is unbounded there), each
    root map's enclosure holds its points at random configurations of the box, and at a vertical roll axis it
    holds the points ``w + L d - sigma e u`` for every horizontal unit ``u`` (the tool points of both solutions'
    limits)."""
    rng = np.random.default_rng(seed)
    for _, limited in flange.roots:
        lateral = limited.plan.section.lateral
        lo, hi = lateral.limits[:, 0], lateral.limits[:, 1]
        centre = rng.uniform(lo, hi)
        box = np.stack([np.maximum(centre - size, lo), np.minimum(centre + size, hi)], axis=1)
        E = lateral.enclose(box[None])[0]
        Q = rng.uniform(box[:, 0], box[:, 1], size=(200, 3))
        P = lateral.position_float(Q)
        ok = np.isfinite(P).all(axis=1)
        assert ((P[ok] >= E[:, 0]) & (P[ok] <= E[:, 1])).all()
    # a box holding configurations whose roll axis is vertical
    panda = industrial_arm("panda")
    z_roll = sp.lambdify([list(panda.q)], list(panda.substitute(panda.fk(5))[:3, 2]))
    base = sp.lambdify([list(panda.q)], list(panda.substitute(panda.fk(5))[:3, 3]))
    from scipy.optimize import brentq

    q = np.zeros(7)
    q[1], q[2] = rng.uniform(-1.0, 1.0), 0.0

    def tilt(q4, q=q):
        q[3] = q4
        return z_roll(q)[0]

    grid = np.linspace(-3.0, -0.1, 60)
    values = [tilt(g) for g in grid]
    changes = [i for i in range(59) if values[i] * values[i + 1] < 0]
    if not changes:
        return
    q[3] = brentq(tilt, grid[changes[0]], grid[changes[0] + 1], xtol=1e-15)
    w = np.array(base(q))
    for sigma, limited in flange.roots:
        lateral = limited.plan.section.lateral
        box = np.stack([q[1:4] - 1e-6, q[1:4] + 1e-6], axis=1)
        E = lateral.enclose(box[None])[0]
        for angle in np.linspace(0, 2 * np.pi, 13):
            u = np.array([np.cos(angle), np.sin(angle)])
            p = w + [-sigma * 0.088 * u[0], -sigma * 0.088 * u[1], -0.21]
            assert ((p >= E[:, 0] - 1e-9) & (p <= E[:, 1] + 1e-9)).all(), (sigma, angle, p, E)


@pytest.mark.slow
def test_tool_down_configurations_never_land_in_an_outer_box_and_the_bracket_holds_their_volume(panda, paving,
                                                                                               oriented):
    """Sampled configurations within the limits with the tool frame exactly down (both roots): their tool points
    never lie in an outer box (narrowed by 1e-9 for float rounding), and their volume estimate (cells of 0.02 with
    their arcs, ``arcs_volume``: no bound; 1.96 m^3 from 3.5e5 configurations, 1.90 at cells of 0.01, session 30)
    lies in the bracket."""
    q, points = oriented
    assert len(points) > 25_000
    assert not in_any_box(points, paving.outer, pad=-1e-9).any()
    lo, hi = paving.measure_bounds
    assert lo <= arcs_volume(panda, q[:, 0], points, 0.02) <= hi


@pytest.fixture(scope="module")
def sections(flange):
    """Both roots' sections paved on one grid of 0.03 m (no time limit, few seeds, pieces of 7.5 mm, a budget of
    boxes), as FlangePlan paves them, with their union (roots_volume)."""
    tuning = dataclasses.replace(DEFAULT, direction_samples=40_000, direction_depth=2)
    grid, parts = paved_roots([limited for _, limited in flange.roots], 0.03, tuning, BOXES)
    return grid, parts, tuning


@pytest.mark.slow
def test_points_of_proved_pieces_are_reached_tool_down_at_50_digits(panda, sections):
    """A point drawn in each of 6 pieces proved at a direction, at a polar angle of a sector that passes there, is
    the tool point of a configuration within the limits whose tool frame is exactly Rx(pi), found by least squares
    and refined at 50 digits (checked there): the certificate the lower bound and the inner cells rest on."""
    grid, parts, _ = sections
    rng = np.random.default_rng(8)
    R = constraint_from(**TOOL_DOWN).matrix
    found = [(p, *where) for p, (_, _, _, sectors) in enumerate(parts) for where in np.argwhere(sectors != 0)]
    assert len(found) > 100
    for p, k, a, b in [found[i] for i in rng.choice(len(found), 6, replace=False)]:
        limited, _, pieces, sectors = parts[p]
        spin = limited.plan.section.lateral.spin
        passing = [i for i in range(spin.count) if int(sectors[k, a, b]) >> i & 1]
        i = rng.choice(passing)
        point = piece_point(grid, pieces, k, a, b, rng, spin.edges[i:i + 2])
        assert arm_in_pose_at_50_digits(panda, point, R, rng) is not None, (p, k, point)


@pytest.mark.slow
def test_tool_down_configurations_never_lie_in_a_cell_outer_for_both_roots(sections, oriented):
    """The union's outer cells (outer for both roots; more than 100 of them) hold no sampled tool-down point (both
    roots' samples)."""
    grid, parts, _ = sections
    codes, _ = roots_volume(parts, grid)
    _, points = oriented
    rz = np.stack([np.hypot(points[:, 0], points[:, 1]), points[:, 2]], axis=1)
    cells, _ = grid.span(np.repeat(rz[:, :, None], 2, axis=2))
    assert not (codes[tuple(cells.T)] == -1).any()
    assert (codes == -1).sum() > 100


def test_the_union_of_one_section_is_its_spin_volume(sections):
    """Second method for roots_volume: one map's union is spin_volume's bracket and full-turn cells; the union of
    both roots is at least each root's lower and upper bound, and its outer cells are those outer in both."""
    grid, parts, tuning = sections
    for limited, full, pieces, sectors in parts:
        codes, (lo, hi) = roots_volume([(limited, full, pieces, sectors)], grid)
        alone = spin_volume(limited, grid, full, pieces, sectors, tuning)
        assert (codes == full).all()
        assert lo >= alone[0] and hi == alone[1] and lo < hi
    codes, (lo, hi) = roots_volume(parts, grid)
    assert lo >= max(spin_volume(limited, grid, full, pieces, sectors, tuning)[0]
                     for limited, full, pieces, sectors in parts)
    assert ((codes == -1) == ((parts[0][1] == -1) & (parts[1][1] == -1))).all()
    assert lo < hi and hi >= max(spin_volume(limited, grid, full, pieces, sectors, tuning)[1]
                                 for limited, full, pieces, sectors in parts)


@functools.cache
def _at_50_digits(lateral):
    """The map's three coordinates and its side conditions, lambdified for mpmath (evaluated at 50 digits)."""
    return (sp.lambdify(lateral.variables, lateral.expressions, modules="mpmath"),
            [sp.lambdify(lateral.variables, side, modules="mpmath") for side, _ in lateral.sides])


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2 ** 32 - 1))
def test_boxes_the_outer_proofs_leave_break_a_condition_at_exact_points(flange, seed):
    """Exact-rational property for the pruning of the outer proofs (SideMap.refused): over 20 random joint boxes
    per root, at 3 rational points of each box refused, some side condition (pitch or roll within its limits) is
    broken by more than the 1e-12 margin, evaluated at 50 digits; and the map's clipped enclosure (FlangeMap) holds
    the tool point at a rational point of every box, at 50 digits."""
    rng = np.random.default_rng(seed)
    refused_seen = 0
    for _, limited in flange.roots:
        lateral = limited.plan.section.lateral
        position, sides = _at_50_digits(lateral)
        lo, hi = lateral.inner_limits[:, 0], lateral.inner_limits[:, 1]
        centres = rng.uniform(lo, hi, size=(20, 3))
        size = rng.uniform(1e-3, 0.1, size=(20, 1))
        boxes = np.stack([np.maximum(centres - size, lo), np.minimum(centres + size, hi)], axis=2)
        refused, E = lateral.refused(boxes), lateral.enclose(boxes)
        with mpmath.workdps(50):
            margin = mpmath.mpf(10) ** -12
            for b in range(len(boxes)):
                for _ in range(3 if refused[b] else 1):
                    # a float is a binary fraction: mpf holds it exactly, a rational point of the box
                    point = [mpmath.mpf(float(rng.uniform(boxes[b, j, 0], boxes[b, j, 1]))) for j in range(3)]
                    p = position(*point)
                    assert all(E[b, i, 0] <= p[i] <= E[b, i, 1] for i in range(3)), (b, p, E[b])
                    if refused[b]:
                        refused_seen += 1
                        assert any(side(*point) < bound - margin
                                   for side, (_, bound) in zip(sides, lateral.sides)), (b, point)
    assert refused_seen > 0
