"""Arms turned by a LIMITED first joint (workspace_sym.reach_turn, issue 24): cells proved at every polar angle.

References, each named in its test:
* independent numerics: 10^5 random configurations (vectorised forward kinematics, the first joint within its
  limits) never land in an outer box; points drawn in inner boxes are reached within every limit by an inverse
  kinematics refined at 50 digits;
* a second method: a Monte Carlo volume of the sampled section with its arcs (``reach_checks.arcs_volume``:
  configurations sampled within the limits, placed by the robot's own numeric position, in cylindrical
  coordinates about the first joint's axis found from the points; each (rho, z) cell hit by a sample turns
  through the union of the arcs psi - q1 + [a, b] of its samples: sum of rho h^2 times that measure), which the
  proved bracket must hold;
* exact arithmetic: which pairs of directions cover the circle is decided exactly on the length of the first
  joint's range.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import sympy as sp

from reach_checks import (
    IIWA_LIKE,
    FreeRun,
    arcs_volume,
    check_sampled_and_reached,
    offset_arm,
    pappus_volume,
    paved_alike_twice,
    reached_at_50_digits,
    sampled_arcs_volume,
    sampled_positions,
    swing_arm,
)
from workspace_sym import StopAt
from workspace_sym.interval.image import CellGrid
from workspace_sym.interval.verdict import INSIDE as INNER
from workspace_sym.interval.verdict import OUTSIDE as OUTER
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial import ReachModel, reach
from workspace_sym.serial.model import cell_width, reach_model
from workspace_sym.serial.section import Turned, turned_volume
from workspace_sym.serial.structure import structure_of
from workspace_sym.serial.tuning import DEFAULT
from workspace_sym.serial.turn import (
    cell_level,
    covering_pairs,
    direction_seeds,
    limited_turn,
    limited_volume,
    pave_limited,
    pieces_upper,
    prove_directions,
)

R = sp.Rational
def test_the_arcs_of_a_section_of_one_angle_turn_through_the_first_joint_s_range():
    """The reference of the bracket: an arm whose second link swings in the plane of the first (alpha 90 deg,
    a1 > a2) reaches each (rho, z) at one polar angle, so its arcs' volume (``arcs_volume``) is the first
    joint's range over 2 pi times Pappus's volume of the same hit cells (the full turn: the same samples with
    q1 at 0 and the limits widened to a full turn), to rounding; counted against the turn the wrong way, the
    arcs spread over the circle and the ratio is not kept."""
    def arm(first):
        return DHRobot([DHJoint.revolute(1, a=1, alpha=sp.pi / 2, limits=first),
                        DHJoint.revolute(2, a=R(1, 2))], name="vertical 2R")

    robot = arm((-sp.pi / 6, sp.pi / 3))
    q, p = map(np.concatenate, zip(*sampled_positions(robot, 100_000, seed=3)))
    full = arcs_volume(arm(None), q[:, 0], p, 0.01)
    assert arcs_volume(robot, q[:, 0], p, 0.01) == pytest.approx(full / 4, rel=1e-12)
    assert arcs_volume(robot, -q[:, 0], p, 0.01) > 1.5 * full / 4


def test_pairs_of_directions_are_decided_exactly():
    """Exact arithmetic: a range of exactly 3 pi / 2 lets any two axis directions cover the circle, a range a
    hair over pi only opposite ones, a hair under pi none (then the arm keeps outer boxes only)."""
    tiny = R(1, 10**12)
    assert covering_pairs(3 * sp.pi / 2) == ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))
    assert covering_pairs(3 * sp.pi / 2 - tiny) == ((0, 2), (1, 3))
    assert covering_pairs(sp.pi + tiny) == covering_pairs(sp.pi) == ((0, 2), (1, 3))
    assert covering_pairs(sp.pi - tiny) == ()
    assert covering_pairs(2 * sp.pi) == covering_pairs(3 * sp.pi / 2)


def test_a_limited_first_joint_is_recognised(limited_paving):
    """The +-170 deg first joint of the swing arm: every pair qualifies, the share of the circle is 17/18
    rounded down; a full turn and the two-joint section of the offset arm are left to the other paths."""
    robot, _ = limited_paving
    turn = limited_turn(structure_of(robot, ()), reach_model(robot, ()))
    assert len(turn.pairs) == 6 and turn.share <= 17 / 18 and 17 / 18 - turn.share < 1e-15
    assert limited_turn(structure_of(swing_arm(None), ()), reach_model(swing_arm(None), ())) is None
    two = offset_arm(first=IIWA_LIKE)
    assert limited_turn(structure_of(two, ()), reach_model(two, ())) is None


@pytest.fixture(scope="module")
def limited_paving():
    robot = swing_arm()
    return robot, reach(robot, delta=0.25)


@functools.cache
def _arcs_volume(robot):
    """The Monte Carlo volume with arcs of 4 10^5 sampled configurations (cells of 0.01), once per arm object
    (the free and the budgeted pavings of the fixture's arm and the pieces of its cut cells are held to the same
    reference)."""
    return sampled_arcs_volume(robot, 400_000, 0.01)


def test_limited_first_joint_gets_inner_boxes_and_a_bracket(limited_paving):
    """Independent numerics: 10^5 sampled configurations (first joint within +-170 deg) never in an outer box;
    points of inner boxes reached within every limit at 50 digits; second method: the bracket holds the Monte
    Carlo volume of the sampled section with its arcs."""
    robot, paving = limited_paving
    plan = structure_of(robot, ())
    assert isinstance(plan, Turned) and not plan.full and plan.section.k == 3
    assert paving.method == "critical" and paving.complete
    assert len(paving.inner) and len(paving.outer) and paving.volume_bounds is not None
    check_sampled_and_reached(robot, paving, samples=100_000, seed=11)
    lo, hi = paving.measure_bounds
    volume = _arcs_volume(robot)
    assert lo <= volume <= hi, (lo, volume, hi)
    vlo, vhi = paving.volume_bounds
    assert 0 < vlo <= volume <= vhi


def test_boxes_on_the_first_axis_beyond_the_arm_are_outer(limited_paving):
    """Boxes touching the first joint's axis are classified like any other (their x^2 + y^2 starts at 0, which
    outward rounding once turned into -5e-324 and a NaN radius: such boxes stayed boundary up to the enclosure's
    ends, 1.7 m above and below the Panda).  Reference: the triangle inequality, |tool - S| <= the sum of the
    link lengths after the shoulder S = (0, 0, 3/10); no box touching the axis lies wholly beyond it undecided."""
    robot, paving = limited_paving
    reach_bound = sum(float(abs(j.a) + abs(j.d)) for j in robot.joints[1:])
    kept = np.concatenate([paving.boundary.reshape(-1, 3, 2), paving.pending.reshape(-1, 3, 2)])
    on_axis = (kept[:, 0, 0] <= 0) & (kept[:, 0, 1] >= 0) & (kept[:, 1, 0] <= 0) & (kept[:, 1, 1] >= 0)
    gap = np.maximum(np.maximum(kept[:, 2, 0] - 0.3, 0.3 - kept[:, 2, 1]), 0.0)
    assert on_axis.any()                  # the axis is crossed near the shoulder: the test looks where it should
    beyond = on_axis & (gap > reach_bound + 1e-9)
    assert not beyond.any(), kept[beyond][:3]


@pytest.mark.slow
def test_a_budget_of_boxes_stops_the_limited_section_at_its_shares(limited_paving):
    """``StopAt(section_boxes=...)`` on the swing arm: the section's stages stop at the shares of the budget
    that they take of a time limit (the proofs at the four directions at ``DIRECTIONS_SHARE``, the blocks at
    ``Tuning.blocks_end``, the step under way ending first: ``pave_limited`` with 3000 boxes evaluates between 92 %
    of them and one chunk more), on the same cells every run (two runs of reach stopped at 2500 give the same
    boxes, on the cells a budget picks: ``turn.budgeted_width``); fewer cells are proved than without the budget
    and what is proved is still sound: sampled configurations never in an outer box, inner points reached at 50 digits,
    the bracket holds the Monte Carlo volume with arcs (second method)."""
    robot, free = limited_paving
    turn = limited_turn(structure_of(robot, ()), reach_model(robot, ()))
    budget = 3000                       # of the 70,425 the stages take to their ends on these cells
    width = DEFAULT.section_ratio * cell_width(0.25, "diameter", 3)
    _, _, pieces, evaluated, reason = pave_limited(turn, width, FreeRun(), boxes=budget)
    assert reason == "" and DEFAULT.blocks_end * budget <= evaluated < budget + DEFAULT.direction_chunk
    cut = paved_alike_twice(robot, 0.25, StopAt(section_boxes=2500))      # cells of budgeted_width
    assert cut.complete and 0 < len(cut.inner) < len(free.inner) and len(cut.outer)
    lo, hi = cut.measure_bounds
    assert lo < free.measure_bounds[0] and lo <= _arcs_volume(robot) <= hi
    check_sampled_and_reached(robot, cut, samples=30_000, seed=13)


def test_inner_boxes_lie_where_the_first_joint_cannot_reach_from_one_side(limited_paving):
    """Inner boxes are not confined to the arc of one direction: some hold points whose polar angle lies in the
    gap of the +x direction's arc (within 10 deg of the -x axis of the first joint's frame), reached only by a
    second direction; each such point is reached at 50 digits within the limits."""
    robot, paving = limited_paving
    model = ReachModel(robot)
    centre = 0.5 * (paving.inner[:, :, 0] + paving.inner[:, :, 1])
    gap = np.abs(np.arctan2(centre[:, 1], -centre[:, 0])) < np.radians(10)
    assert gap.any()
    rng = np.random.default_rng(5)
    q = model.random_configurations(30_000, rng)
    pos = model.position_float(q)
    for box in paving.inner[gap][rng.integers(gap.sum(), size=3)]:
        assert reached_at_50_digits(model, rng.uniform(box[:, 0], box[:, 1]), q, pos), box


class _Stopped:
    """A run of :func:`pave_limited` stopped before its first proof (no time limit): only the cells decided
    before the proofs at the four directions are left."""

    time_limit, seconds = None, 0.0

    @staticmethod
    def stop_reason(count):
        return "stopped"


def test_the_hole_around_the_shoulder_is_outside_at_every_angle():
    """The swing arm with its elbow (joint 3) within +-90 deg: the tool point stays at least sqrt(0.29) (0.54)
    from the shoulder ``S = (0, 0, 0.3)`` (h = |r|^2 + 0.25 + cos(q3) (0.4 + 0.2 cos q4) with |r| >= 0.2), so
    the cells of the section within that distance at every polar angle are outside before any other proof,
    and so are those beyond 1.1 (0.5 + 0.4 + 0.2); the volume's upper bound on pieces of cells follows that
    shell to within 1 %.  Exact: the lower bound of ``h`` is within 0.01 below 0.29
    and the upper within 0.01 above 1.21; independent numerics: 10^5 sampled configurations never land in an
    outer cell, and the outer cells include the disc of radius 0.5 around (0, 0.3)."""
    robot = DHRobot([DHJoint.revolute(1, d=R(3, 10), alpha=sp.pi / 2, limits=IIWA_LIKE),
                     DHJoint.revolute(2, a=R(1, 2), alpha=sp.pi / 2),
                     DHJoint.revolute(3, a=R(2, 5), alpha=sp.pi / 2, limits=(-sp.pi / 2, sp.pi / 2)),
                     DHJoint.revolute(4, a=R(1, 5))], name="swing arm, elbow +-90 deg")
    turn = limited_turn(structure_of(robot, ()), reach_model(robot, ()))
    reach_ = turn.plan.section.reach
    assert [str(v) for v in reach_.map.variables] == ["theta3", "theta4"]
    assert 0.28 <= reach_.lowest(1e-3) <= 0.29 and 1.21 <= reach_.bound(1e-3) <= 1.22
    grid, classes, _, _, reason = pave_limited(turn, 0.02, _Stopped())
    assert reason == "stopped"
    outer = classes == OUTER
    e0, e1 = grid.edges
    rho, z = np.maximum(e0[1:], 0.0)[:, None], np.maximum(np.abs(e1[:-1] - 0.3), np.abs(e1[1:] - 0.3))[None, :]
    assert np.all(outer[np.hypot(rho, z) < 0.5])
    section = turn.plan.section
    p = section.position_float(section.random_configurations(100_000, np.random.default_rng(3)))
    cells, _ = grid.span(np.repeat(p[:, :, None], 2, axis=2))
    assert not outer[cells[:, 0], cells[:, 1]].any()
    assert (np.hypot(p[:, 0], p[:, 1] - 0.3) >= 0.53).all()          # the hole is there
    # The volume's upper bound on pieces of the undecided cells: within 1 % of the shell between the two
    # distances (closed form), which holds the workspace; never below the Pappus volume of the sampled section
    # (cells of side 0.005: an estimate, second method); below the coarse cells' bound; one piece: that bound.
    top = pieces_upper(reach_, grid, classes)
    shell = 4 / 3 * np.pi * (1.1 ** 3 - 0.29 ** 1.5)
    coarse = turned_volume(grid, classes)[1]
    assert pappus_volume(robot, n=400_000, h=0.005) <= top <= 1.01 * shell < coarse
    assert pieces_upper(reach_, grid, classes, 1) == pytest.approx(coarse, rel=1e-15)



def test_pieces_of_cut_cells_count_for_the_volume_and_are_reached(limited_paving):
    """The cells of the swing arm's section that fail whole (cut by its boundary) keep the pieces proved at two
    directions of a covering pair (or one, for the share of the circle): the lower bound of the volume gains on
    the cells' (all pieces or none), the bracket still holds the Monte Carlo volume of the sampled section with
    its arcs (second method), and points of such pieces at random polar angles are reached within every limit by
    an inverse kinematics at 50 digits (independent numerics)."""
    robot, _ = limited_paving                   # the swing arm, its section prepared once for the module
    turn = limited_turn(structure_of(robot, ()), reach_model(robot, ()))
    grid, classes, pieces, _, reason = pave_limited(turn, 0.08, FreeRun())     # cells of 0.08: cut ones already
    assert reason == ""
    lo, hi = limited_volume(turn, grid, classes, pieces)
    F = pieces.shape[1] // grid.shape[0]
    whole = np.repeat(np.repeat(cell_level(pieces, grid), F, axis=1), F, axis=2)
    assert limited_volume(turn, grid, classes, whole)[0] < lo <= _arcs_volume(robot) <= hi
    both = np.zeros(pieces.shape[1:], dtype=bool)
    for j, k in turn.pairs:
        both |= pieces[j] & pieces[k]
    cut = both & ~np.repeat(np.repeat(classes == INNER, F, axis=0), F, axis=1)
    assert cut.any()
    model = ReachModel(robot)
    rng = np.random.default_rng(8)
    q = model.random_configurations(30_000, rng)
    pos = model.position_float(q)
    e0, e1 = grid.edges
    for a, b in np.argwhere(cut)[rng.integers(cut.sum(), size=4)]:
        rho = e0[a // F] + (e0[a // F + 1] - e0[a // F]) * (a % F + rng.uniform()) / F
        z = e1[b // F] + (e1[b // F + 1] - e1[b // F]) * (b % F + rng.uniform()) / F
        psi = rng.uniform(-np.pi, np.pi)
        assert reached_at_50_digits(model, np.array([rho * np.cos(psi), rho * np.sin(psi), z]), q, pos), (rho, z)


def test_directions_resume_where_they_stopped(limited_paving):
    """A run of the proofs at the four directions stopped after a third of its tests and resumed from its state
    proves the same pieces as one run with the same tests in all (the cells tried at a level are not tried again:
    the time a stopped stage leaves goes to new cells), on the swing arm's section (cells of width 0.08, one
    level of pieces)."""
    robot, _ = limited_paving
    section = limited_turn(structure_of(robot, ()), reach_model(robot, ())).plan.section
    grid = CellGrid(section.enclose(section.limits[None])[0], 0.08)
    sampled = direction_seeds(section.lateral, grid, n=20_000)
    every = np.ones(grid.shape, dtype=bool)
    whole, tests, stopped = prove_directions(section.lateral, grid, every, sampled=sampled, depth=1)
    assert stopped == "" and whole.any()
    state: dict = {}
    part, first, stopped = prove_directions(section.lateral, grid, every, sampled=sampled, state=state, depth=1,
                                            budget=lambda count, ahead=0.0: "stop" if count >= tests // 3 else "")
    assert stopped == "stop" and part.sum() < whole.sum()
    again, total, stopped = prove_directions(section.lateral, grid, every, sampled=sampled, state=state,
                                             evaluated=first, depth=1)
    assert stopped == "" and np.array_equal(again, whole) and total == tests


@functools.cache
def _short_shoulder_arm():
    """The swing arm with its shoulder (joint 2) within +-60 deg: the elbow sweeps an arc of the circle of
    radius 1/2 about the shoulder, so the distance from the elbow (at most 0.6 to the tool) cuts the section
    where the distance from the shoulder (0.3 to 1.1) does not.  One object for the two tests that read it: its
    section is prepared once."""
    return DHRobot([DHJoint.revolute(1, d=R(3, 10), alpha=sp.pi / 2, limits=IIWA_LIKE),
                    DHJoint.revolute(2, a=R(1, 2), alpha=sp.pi / 2, limits=(-sp.pi / 3, sp.pi / 3)),
                    DHJoint.revolute(3, a=R(2, 5), alpha=sp.pi / 2),
                    DHJoint.revolute(4, a=R(1, 5))], name="swing arm, shoulder +-60 deg")


def _at_limits(model, n, rng):
    """``n`` configurations within the limits, each joint at one of its limits with probability 1/3 (the
    section's boundary comes from the limits: the edge the elbow's bound must not cross)."""
    q = model.random_configurations(n, rng)
    limits = model.limits
    for j in range(q.shape[1]):
        if not model.periodic[j]:
            pick = rng.integers(3, size=n)
            q[pick == 0, j], q[pick == 1, j] = limits[j, 0], limits[j, 1]
    return q


def test_the_elbow_s_distance_proves_outside_only_what_no_configuration_reaches():
    """The distance from the elbow (``section.ElbowReach``, docs/methods.md section 5): on the swing arm with a
    shoulder of +-60 deg, the elbow is the origin of the frame on joint 3's axis (a function of theta2 only), the
    squared distance from it to the tool of theta4 only (joint 3 turns about an axis through the elbow), at most
    0.36 (0.4 + 0.2 squared, exact, within 0.01).  Independent
    numerics, aimed at the edge: 10^5 configurations, a third of their joints at a limit, never lie in a
    rectangle (a point, or a square of side 10^-3 around it) the bound proves outside, nor in a cell of the
    section that ``pave_limited`` makes outer; and the bound proves cells outside that the shoulder's distance
    leaves (the side the shoulder cannot turn to)."""
    robot = _short_shoulder_arm()
    model = reach_model(robot, ())
    turn = limited_turn(structure_of(robot, ()), model)
    elbow = turn.elbow
    assert elbow is not None and [str(v) for v in elbow.map.variables] == ["theta2"]
    assert [str(v) for v in elbow.distance.map.variables] == ["theta4"]
    assert 0.36 <= elbow.distance.bound(1e-3) <= 0.37
    section = turn.plan.section
    w = section.lateral.position_float(_at_limits(section.lateral, 100_000, np.random.default_rng(21)))
    rho, z = np.hypot(w[:, 0], w[:, 1]), w[:, 2]
    for pad in (0.0, 5e-4):
        assert not elbow.outside(rho - pad, rho + pad, z - pad, z + pad, 0.02).any()
    grid, classes, _, _, reason = pave_limited(turn, 0.02, _Stopped())
    assert reason == "stopped"
    cells, _ = grid.span(np.stack([np.stack([rho, rho], axis=1), np.stack([z, z], axis=1)], axis=1))
    assert not (classes[cells[:, 0], cells[:, 1]] == OUTER).any()
    e0, e1 = grid.edges
    shoulder = section.reach.outside_cells(grid)
    by_elbow = elbow.outside(e0[:-1, None], e0[1:, None], e1[None, :-1], e1[None, 1:], grid.width)
    assert (by_elbow & ~shoulder).sum() > 100 and np.all(classes[by_elbow] == OUTER)


def test_a_finer_delta_within_the_same_budget_gives_the_same_section_bracket():
    """A budget of section boxes (``StopAt(section_boxes=...)``, the same cells on every machine) picks the
    section's cells whatever ``delta`` (``turn.budgeted_width``): the short-shoulder swing arm at delta 0.25 and
    0.125 proves the same volume bracket, so the finer run's bracket is never wider; it holds the Monte Carlo
    volume of the sampled section with its arcs (second method) and 3 10^4 sampled configurations never land
    in an outer box of the finer run (independent numerics)."""
    robot = _short_shoulder_arm()
    stop = StopAt(section_boxes=800)
    coarse, fine = (reach(robot, delta=delta, stop=stop) for delta in (0.25, 0.125))
    assert coarse.volume_bounds == fine.volume_bounds
    (a, b), (c, d) = coarse.measure_bounds, fine.measure_bounds
    assert d - c <= b - a
    volume = sampled_arcs_volume(robot, 200_000, 0.01)
    assert a <= volume <= b and c <= volume <= d
    check_sampled_and_reached(robot, fine, samples=30_000, seed=17)
