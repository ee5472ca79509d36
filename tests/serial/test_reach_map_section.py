"""Reach maps by the section method (workspace_sym/serial/mapsection.py, reach_map(method="section")): every
proved-reachable pair checked by a 50-digit inverse kinematics, unreachable pairs against sampled configurations,
the same cone's pose paving as a second method, the cell geometry's bounds at the edges, files and bad input."""

from __future__ import annotations

import warnings
from concurrent.futures import ProcessPoolExecutor
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from reach_checks import arm_in_cone_at_50_digits, industrial_arm, wrist_arm_in_cone_at_50_digits
from workspace_sym import Pose, reach, robots
from workspace_sym.errors import InvalidParameterError, WorkerResultError
from workspace_sym.interval.driver import RunOn
from workspace_sym.kinematics import DHJoint, DHRobot, numeric_function
from workspace_sym.serial import mapsection
from workspace_sym.serial.mapsection import (
    _aimed_newton,
    _cell_geometry,
    _columns,
    _least_norm_step,
    _turning,
    local_directions,
    section_prover,
    section_reachable,
)
from workspace_sym.serial.reachmap import (
    ReachMap,
    _checked_paving,
    _checked_section,
    _grid,
    _section_parts,
    covered_cells,
    map_problem,
    reach_map,
    sphere_directions,
)
from workspace_sym.transforms import rot_x, translation

PUMA = dict(delta=0.1, directions=6, cone=45, method="section")


@pytest.fixture(scope="module")
def puma_map(puma):
    # the session's Puma (tests/conftest.py): the pose paving below and the other files share its derivations
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)            # six cones of 45 deg do not cover the sphere
        return reach_map(puma, **PUMA)


def _cell(m, i, j, k):
    return np.array([[m.edges[a][c], m.edges[a][c + 1]] for a, c in enumerate((i, j, k))])


def test_points_of_section_proved_pairs_are_reached_in_the_cone_at_50_digits(puma, puma_map):
    # Reference: an inverse kinematics at 50 digits (tests/helpers/reach_checks.py), within the limits, with the
    # approach axis within the cone, at random points (corners included) of proved-reachable cells.
    robot = puma
    rng = np.random.default_rng(7)
    pairs = np.argwhere(puma_map.codes == 1)
    assert len(pairs) > 500 and puma_map.method == "section proofs and the position paving"
    for i, j, l, k in pairs[rng.choice(len(pairs), size=4, replace=False)]:
        cell = _cell(puma_map, i, j, l)
        for target in (rng.uniform(cell[:, 0], cell[:, 1]), cell[:, 1]):
            found = wrist_arm_in_cone_at_50_digits(robot, target, puma_map.directions[k], puma_map.cone, rng)
            assert found is not None, f"{target} of a proved-reachable cell, direction {puma_map.directions[k]}"


def test_sampled_configurations_never_fall_in_a_section_map_s_unreachable_pair(puma, puma_map):
    # Reference: forward kinematics of 200,000 configurations within the limits (floats): each point is reached,
    # so its cell is not proved unreachable for any direction, and it lies in the grid.
    robot = puma
    T = numeric_function(robot.substitute(robot.fk()), robot.q)
    lim = robot.joint_limits()
    M = T(np.random.default_rng(3).uniform(lim[:, 0], lim[:, 1], size=(200_000, len(lim))))
    index, inside = puma_map.cells_of(M[:, :3, 3])
    assert inside.all() and puma_map.outside_proved
    assert not (puma_map.codes[index[:, 0], index[:, 1], index[:, 2]] == -1).any()
    assert (puma_map.codes == -1).sum() > 1000


def test_section_proved_pairs_are_never_outer_in_the_pose_paving_of_the_same_cone(puma, puma_map):
    # Reference: a second method, the certified pose paving of the vertical cone (the section of docs/methods.md
    # section 8): no cell proved reachable here lies in the union of its outer boxes and the outside of its root.
    # At the map's own delta (0.1) its outer boxes cover 2162 of the map's cells (2481 at delta 0.05, in 2.5 times
    # the time), against 862 cells proved reachable for that direction.
    up = int(np.argmax(puma_map.directions[:, 2]))
    paving = reach(puma, delta=0.1, pose=Pose(approach=tuple(puma_map.directions[up]), cone=45))
    root = np.array([paving.box.lower, paving.box.upper]).T
    outer = covered_cells(puma_map.edges, paving.outer.reshape(-1, 3, 2), exterior=root)
    assert outer.sum() > 2000 and (puma_map.codes[..., up] == 1).sum() > 800
    assert not (outer & (puma_map.codes[..., up] == 1)).any()


def test_a_section_that_cannot_aim_with_a_limited_first_joint_is_proved_at_50_digits_too(scara):
    # Reference: the 50-digit inverse kinematics (reach_checks.arm_in_cone_at_50_digits) at a corner and a random
    # point of SCARA cells proved reachable: two section joints (no aim: the seeds are the solution branches) and
    # a first joint of limited range (the polar condition of docs/methods.md section 9).
    prover = section_prover(scara, (), 30.0)
    assert not isinstance(prover, str) and not prover.aims and prover.theta_range is not None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)            # six cones of 30 deg do not cover the sphere
        made = reach_map(scara, delta=0.05, directions=6, cone=30, method="section")
    pairs = np.argwhere(made.codes == 1)
    assert len(pairs) >= 50
    rng = np.random.default_rng(5)
    for i, j, k, d in pairs[rng.choice(len(pairs), size=4, replace=False)]:
        cell = _cell(made, i, j, k)
        for target in (cell[np.arange(3), rng.integers(0, 2, 3)], rng.uniform(cell[:, 0], cell[:, 1])):
            assert arm_in_cone_at_50_digits(scara, target, made.directions[d], 30.0, rng) is not None, (target, d)


def _cells_in(robot, box):
    """The map cells of 0.1 (the robot's enclosure grid) whose centres lie strictly inside ``box``."""
    origin, shape, _ = _grid(robot, (), 0.1)
    edges = tuple(origin[a] + np.arange(shape[a] + 1) * 0.1 for a in range(3))
    centres = np.meshgrid(*[0.5 * (e[1:] + e[:-1]) for e in edges], indexing="ij")
    return edges, np.logical_and.reduce([(lo < c) & (c < hi) for c, (lo, hi) in zip(centres, box)])


def _reached_at_50_digits(robot, edges, pairs, directions, size):
    """A corner and a random point of ``size`` of the proved ``pairs`` (cell, direction), drawn with seed 3, each
    reached by the whole arm's 50-digit inverse kinematics within the limits, the approach within 30 deg."""
    rng = np.random.default_rng(3)
    for i, j, l, k in pairs[rng.choice(len(pairs), size=size, replace=False)]:
        cell = np.array([[edges[a][c], edges[a][c + 1]] for a, c in enumerate((i, j, l))])
        for target in (cell[np.arange(3), rng.integers(0, 2, 3)], rng.uniform(cell[:, 0], cell[:, 1])):
            assert arm_in_cone_at_50_digits(robot, target, directions[k], 30.0, rng) is not None, (target, k)


@pytest.mark.parametrize("name", ["ur5", "kr16 (URDF, base upside down)", "ur5 on a tilted base"])
def test_points_of_aimed_section_pairs_are_reached_in_the_cone_at_50_digits(name):
    # Reference: the 50-digit inverse kinematics of the whole arm, base included (reach_checks.
    # arm_in_cone_at_50_digits), at a corner and a random point of cells proved reachable by the aimed section
    # (four section joints or more: Newton aims the approach): the UR5; the KR16 of rtb-data's URDF (base rpy
    # pi 0 0: z down); the UR5 on a base turned 0.4 rad about x and moved (the world pieces enter the first
    # joint's frame as outward boxes).
    # The candidate cells: a few map cells of 0.1 each (6, 8 and 8), where the section proves 22, 24 and 14 pairs
    # of which three are checked; the time goes to the section cells under them (the KR16's 32 cells of before
    # took 4.5 s to prove 105 pairs).
    ur5 = industrial_arm("ur5")             # tests/data/dh/ur5.json, the object the other files prepare too
    if name == "ur5":
        robot, box = ur5, ((0.25, 0.55), (0.05, 0.25), (0.1, 0.2))
    elif name.startswith("kr16"):
        robot, box = industrial_arm("kr16"), ((0.6, 0.8), (0.05, 0.25), (0.6, 0.8))
    else:
        robot = DHRobot(list(ur5.joints), convention=ur5.convention, name="tilted ur5", units=ur5.units,
                        base=translation(x=sp.Rational(1, 10), y=sp.Rational(-1, 5), z=sp.Rational(3, 10))
                        * rot_x(sp.Rational(2, 5)))
        box = ((0.35, 0.65), (-0.2, 0.0), (0.3, 0.5))
    prover = section_prover(robot, (), 30.0)
    assert not isinstance(prover, str) and prover.aims and (prover.inverse is None) == (name == "ur5")
    assert name != "ur5" or prover.theta_range is None
    edges, candidates = _cells_in(robot, box)
    directions = sphere_directions(6)
    proved = section_reachable(prover, edges, candidates, directions, cell=0.01, local=sphere_directions(16),
                                samples=40_000)
    assert not proved[~candidates].any()
    pairs = np.argwhere(proved)
    assert len(pairs) >= 6
    _reached_at_50_digits(robot, edges, pairs, directions, 3)


def test_pairs_proved_by_the_second_branch_of_a_limited_first_joint_are_reached_at_50_digits(monkeypatch):
    # The Panda (tests/data/dh/panda.json): its first joint within +-2.8973 rad, so theta_1 = psi - beta must avoid
    # a forbidden arc, and its redundant section keeps a second proof per square with beta swung away from the
    # first's (_SectionCells.second).  The same cells are proved without the second proofs (the method turned
    # off): those pairs must be among the others (the second only adds candidates), and the pairs proved only
    # with it are checked by the whole arm's 50-digit inverse kinematics, first joint's limits included.
    # The box: eight map cells of 0.1 behind the base (x < 0), where the first proof's beta forbids theta_1: the
    # first proofs alone prove none of their pairs there, the second ones 8 (the box of 32 cells (-0.65, -0.25) x
    # (-0.1, 0.3) x (0.3, 0.5) of before: 12 pairs, all by the second proofs, in twice the time).
    robot = industrial_arm("panda")
    prover = section_prover(robot, (), 30.0)
    assert prover.aims and prover.theta_range is not None
    edges, candidates = _cells_in(robot, ((-0.55, -0.35), (-0.1, 0.1), (0.3, 0.5)))
    assert candidates.sum() == 8
    directions = sphere_directions(6)
    options = dict(cell=0.01, local=sphere_directions(16), samples=40_000)
    asked, second = [], mapsection._SectionCells.second

    def counted(self, s, l):
        asked.append((len(s), int(self.aimed.sum())))
        return second(self, s, l)

    monkeypatch.setattr(mapsection._SectionCells, "second", counted)
    both = section_reachable(prover, edges, candidates, directions, **options)
    # second proofs only where a failing pair needs them (asked for by the first cell test): far fewer than first ones
    assert asked and sum(n for n, _ in asked) < 0.5 * asked[-1][1]
    monkeypatch.setattr(mapsection._SectionCells, "second", lambda self, s, l: np.zeros(0, dtype=np.int64))
    first = section_reachable(prover, edges, candidates, directions, **options)
    assert not (first & ~both).any() and not both[~candidates].any()
    only = np.argwhere(both & ~first)
    assert len(only) >= 2
    _reached_at_50_digits(robot, edges, only, directions, 2)


def _beside_the_ur5_base():
    """The UR5's prover, the 36 map cells of 0.1 beside and below its base (x in (-0.3, 0.3), y in (0, 0.3), z in
    (-0.3, -0.1)), six directions and the section options of the tests below."""
    robot = industrial_arm("ur5")
    edges, candidates = _cells_in(robot, ((-0.3, 0.3), (0.0, 0.3), (-0.3, -0.1)))
    assert candidates.sum() == 36
    options = dict(cell=0.01, local=sphere_directions(16), samples=40_000)
    return robot, section_prover(robot, (), 30.0), edges, candidates, sphere_directions(6), options


def test_pairs_proved_near_the_axis_by_the_turning_bound_are_reached_at_50_digits(monkeypatch):
    # The cell test allows b within c - gamma r of E = e(psi_c), r = sin of the direction's angle from the first
    # axis (mapsection._turning: e(psi) turns by at most r |psi - psi_c|), where it allowed c - gamma: a vertical
    # direction does not turn at all.  The box: 36 UR5 map cells of 0.1 beside and below the base (x in (-0.3,
    # 0.3), y in (0, 0.3), z in (-0.3, -0.1)), whose pieces are seen from the axis under polar spreads of up to
    # 45 deg: with the spread counted in full (_turning made 1) none of their pairs is proved, with the bound
    # 36, all of them for +-z.  Reference: the 50-digit inverse kinematics of the whole arm at a corner and a
    # random point of two of them, the approach within 30 deg of the direction.
    robot, prover, edges, candidates, directions, options = _beside_the_ur5_base()
    bound = section_reachable(prover, edges, candidates, directions, **options)
    monkeypatch.setattr(mapsection, "_turning", lambda D: np.ones(len(D)))
    full = section_reachable(prover, edges, candidates, directions, **options)
    assert not (full & ~bound).any() and not bound[~candidates].any()
    only = np.argwhere(bound & ~full)
    assert len(only) >= 20 and set(only[:, 3]) <= {2, 3}          # +-z: sphere_directions(6)[2:4]
    _reached_at_50_digits(robot, edges, only, directions, 2)


def test_pairs_proved_by_aims_tried_again_are_reached_at_50_digits():
    # Where a direction of a cell fails at a few section cells (mapsection.FEW) whose proofs were aimed at local
    # directions that its e(psi) is not near enough, Newton aims at e(psi) itself there from random starts and
    # the failing cells are tested again (section_reachable(retries=...)).  The same 36 UR5 cells of 0.1 beside
    # and below the base as above: 36 pairs without the retries, 52 with 16 starts.  The pairs proved without
    # must stay proved (a replaced proof was a proof all the same), and two of those proved only with the retries
    # are checked by the whole arm's 50-digit inverse kinematics, the approach within 30 deg.
    robot, prover, edges, candidates, directions, options = _beside_the_ur5_base()
    once = section_reachable(prover, edges, candidates, directions, **options)
    again = section_reachable(prover, edges, candidates, directions, retries=16, **options)
    assert not (once & ~again).any() and not again[~candidates].any()
    only = np.argwhere(again & ~once)
    assert len(only) >= 8
    _reached_at_50_digits(robot, edges, only, directions, 2)


def test_a_cell_test_of_some_directions_gives_their_verdicts_of_the_whole_test(monkeypatch):
    # The section tests failing cells again on their failing directions only (_CellTest(todo=...)): on the Panda's
    # eight cells behind its base (the second proofs' box above), every random choice of directions gets exactly
    # the verdicts the whole test gives them, and False elsewhere.  Independent of the proofs: the same grid read
    # twice.
    robot = industrial_arm("panda")
    prover = section_prover(robot, (), 30.0)
    edges, candidates = _cells_in(robot, ((-0.55, -0.35), (-0.1, 0.1), (0.3, 0.5)))
    tests = []

    class Kept(mapsection._CellTest):
        def __init__(self, *args):
            super().__init__(*args)
            tests.append(self)

    monkeypatch.setattr(mapsection, "_CellTest", Kept)
    directions = sphere_directions(6)
    proved = section_reachable(prover, edges, candidates, directions, cell=0.01, local=sphere_directions(16),
                               samples=40_000)
    test, cells = tests[0], np.arange(int(candidates.sum()))
    whole = test(cells)
    assert whole.any() and not whole.all() and whole.sum() <= proved.sum()
    rng = np.random.default_rng(5)
    for _ in range(4):
        todo = rng.random(whole.shape) < 0.5
        assert (test(cells, todo) == (whole & todo)).all()


@settings(max_examples=200, deadline=None)
@given(st.sampled_from([(0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.6, -0.8, 0.0), (1e-9, 0.0, -1.0), (0.3, 0.2, 0.9)])
       | st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(lambda v: max(map(abs, v)) > 1e-6),
       st.floats(-np.pi, np.pi), st.floats(0, np.pi))
def test_the_turning_bounds_the_angle_a_direction_turns_through_at_50_digits(d, psi, t):
    # Reference: the angle between Rz(-psi) d and Rz(-psi - t) d at 50 digits (mpmath, the float d as it is; by
    # atan2 of the cross and dot products, accurate at 0 and pi where asin of the chord is not):
    # at most t times _turning(d), for directions on the axis, normal to it, nearly on it, and any.
    bound = _turning(np.array([d]))[0]
    with mpmath.workdps(50):
        v = [mpmath.mpf(x) for x in d]
        n = mpmath.sqrt(sum(x * x for x in v))

        def e(angle):
            c, s = mpmath.cos(angle), mpmath.sin(angle)
            return [(c * v[0] + s * v[1]) / n, (-s * v[0] + c * v[1]) / n, v[2] / n]

        a, b = e(mpmath.mpf(psi)), e(mpmath.mpf(psi) + mpmath.mpf(t))
        cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
        angle = mpmath.atan2(mpmath.sqrt(sum(x * x for x in cross)), sum(x * y for x, y in zip(a, b)))
        assert angle <= mpmath.mpf(t) * mpmath.mpf(float(bound)) + mpmath.mpf(10) ** -40, (angle, bound)


def test_newton_meets_feasible_aims_from_random_starts_and_says_so_truly():
    # The section's seeds aim b at a local direction ell by Newton on b . e_1 = b . e_2 = 0, which b = -ell solves
    # too, and which wanders where ell is out of reach; the rows that miss take damped least-squares steps towards
    # b = ell from their seeds (mapsection._nearest_aim), then Newton again.  Reference: 2,000 aims met by
    # construction (the position and b of random UR5 section configurations), solved from other random
    # configurations: 30 % were met before those steps, 85 % with them (at least 75 % asked); every row flagged
    # aimed has its position within 1e-9 and b . ell > 0.99, evaluated again.
    prover = section_prover(industrial_arm("ur5"), (), 30.0)
    square = prover.square
    rng = np.random.default_rng(2)
    q0 = square.random_configurations(2000, rng)
    targets, ell = square.position_float(q0), _columns(prover.b_float, q0)
    q, converged, aimed = _aimed_newton(prover, targets, ell, square.random_configurations(2000, rng))
    assert aimed.mean() >= 0.75 and not (aimed & ~converged).any()
    residual = np.abs(square.position_float(q[aimed]) - targets[aimed]).max(axis=1)
    assert residual.max() < 1e-9 * (1 + np.abs(targets).max())
    assert (np.einsum("ni,ni->n", _columns(prover.b_float, q[aimed]), ell[aimed]) > 0.99).all()


def test_newton_s_step_survives_a_batch_with_an_exactly_singular_system():
    # The KR16's map stopped on numpy's LinAlgError: a joint held at its limit (its column dropped) in a square
    # system whose entries swallow the damping.  Reference: the least-norm solution J^T (J J^T)^+ f, checked by
    # its residual and its norm, beside a regular row (the exact step) and a NaN row (NaN, as before).
    J = np.array([[[1e5, 0.0], [1e5, 0.0]], [[2.0, 1.0], [0.0, 1.0]], [[np.nan, 0.0], [0.0, 1.0]]])
    f = np.array([[2e5, 2e5], [3.0, 1.0], [1.0, 1.0]])
    step = _least_norm_step(J, f, 1e-12)
    assert np.allclose(np.einsum("ik,k->i", J[0], step[0]), f[0], rtol=1e-9) and np.allclose(step[0], [2.0, 0.0])
    assert np.allclose(np.einsum("ik,k->i", J[1], step[1]), f[1], rtol=1e-9)
    assert np.isnan(step[2]).all()


class _Frame:
    def __init__(self, rotation):
        self.rotation = rotation


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 30), st.integers(8, 200), st.integers(0, 2**32 - 1), st.booleans())
def test_local_directions_lie_near_every_direction_seen_from_the_turning_frame(k, count, seed, turned):
    # Reference: e(psi) = Rz(-psi) R^T d on a grid of 721 angles psi, for random map directions (vertical ones
    # included) and a random rotation R: each within 60 deg of a local direction (at least three a circle, evenly
    # spread); for the 26 cube directions and 96 local ones, within 7.95 deg (docs/methods.md section 9), below the
    # 15.96 deg that sphere_directions(96) leaves.
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(k, 3))
    d[rng.random(k) < 0.2] = [0.0, 0.0, 1.0]
    d /= np.linalg.norm(d, axis=1)[:, None]
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0] if turned else np.eye(3)
    cases = [(d, count, 60.0 + 1e-9)] + ([(sphere_directions(26), 96, 7.95)] if not turned else [])
    for dirs, n, bound in cases:
        local = local_directions(_Frame(R), dirs, n)
        assert np.allclose(np.linalg.norm(local, axis=1), 1.0)
        psi = np.linspace(0.0, 2 * np.pi, 721)
        seen = dirs @ R.T
        for v in seen:
            E = np.stack([np.cos(psi) * v[0] + np.sin(psi) * v[1], -np.sin(psi) * v[0] + np.cos(psi) * v[1],
                          np.full_like(psi, v[2])], 1)
            assert np.degrees(np.arccos(np.clip((E @ local.T).max(axis=1), -1, 1))).max() <= bound


@settings(max_examples=300, deadline=None)
@given(st.floats(-1, 1), st.floats(-1, 1), st.sampled_from([1e-9, 1e-4, 0.01, 0.05, 0.3]),
       st.sampled_from([1e-9, 1e-4, 0.01, 0.05, 0.3]), st.integers(0, 2**32 - 1))
@example(2.2250738585e-313, 2.2250738585e-313, 1e-9, 1e-9, 0)     # a subnormal corner: hypot's ulp is not relative
def test_the_cell_geometry_bounds_radius_and_polar_angle_of_every_point(x0, y0, wx, wy, seed):
    # Reference: the four corners and points drawn in the rectangle (rectangles touching the axes or tiny),
    # whenever it does not hold the axis (rmin > 0): their squared radius in [rmin^2, rmax^2] in exact rationals
    # (the floats as Fractions), their polar angle within gamma of the centre's at 50 digits (mpmath).
    X, Y = np.array([[x0, x0 + wx]]), np.array([[y0, y0 + wy]])
    rmin, rmax, psi, gamma = _cell_geometry(X, Y)
    if rmin[0] <= 0:
        return
    rng = np.random.default_rng(seed)
    px = np.r_[X[0, [0, 1, 0, 1]], rng.uniform(X[0, 0], X[0, 1], 60)]
    py = np.r_[Y[0, [0, 0, 1, 1]], rng.uniform(Y[0, 0], Y[0, 1], 60)]
    lo, hi = Fraction(float(rmin[0])) ** 2, Fraction(float(rmax[0])) ** 2
    with mpmath.workdps(50):
        for x, y in zip(px.tolist(), py.tolist()):
            assert lo <= Fraction(x) ** 2 + Fraction(y) ** 2 <= hi, (x, y)
            turn = mpmath.atan2(mpmath.mpf(y), mpmath.mpf(x)) - mpmath.mpf(float(psi[0]))
            spread = abs(turn - 2 * mpmath.pi * mpmath.nint(turn / (2 * mpmath.pi)))
            assert spread <= mpmath.mpf(float(gamma[0])), (x, y)


def test_a_section_map_built_in_parts_on_two_processes_proves_what_one_process_does(puma, puma_map):
    # Reference: the map built in this process (puma_map).  On two processes the pavings run side by side and the
    # section in two parts of their own cells, each part's continuation stopping at its edge: the same pavings
    # give the same unreachable pairs (a reachable pair is never proved unreachable), the reachable ones differ
    # at the parts' edge only (4,505 against 4,577 when written), and those only the parts proved are reached by
    # the 50-digit inverse kinematics.
    with warnings.catch_warnings(), ProcessPoolExecutor(2) as pool:
        warnings.simplefilter("ignore", UserWarning)
        parts = reach_map(puma, **PUMA, run=RunOn(executor=pool))
    assert parts.info["section_parts"] == 2 and puma_map.info["section_parts"] == 1
    assert np.array_equal(parts.codes == -1, puma_map.codes == -1)
    one, two = (puma_map.codes == 1).sum(), (parts.codes == 1).sum()
    assert 0.95 * one <= two <= 1.05 * one
    rng = np.random.default_rng(11)
    only = np.argwhere((parts.codes == 1) & (puma_map.codes != 1))
    for i, j, l, k in only[rng.choice(len(only), size=min(3, len(only)), replace=False)]:
        target = rng.uniform(*_cell(parts, i, j, l).T)
        assert wrist_arm_in_cone_at_50_digits(puma, target, parts.directions[k], parts.cone, rng) is not None


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.integers(1, 4), st.integers(0, 2), st.floats(0.0, 1.0))
def test_the_section_parts_are_whole_layers_along_the_first_axis_and_hold_every_candidate(seed, parts, axis, fill):
    # Reference: the definition (reachmap._section_parts), checked on random candidate masks, sparse to full, with
    # the first joint's axis along x, y or z: every candidate in exactly one part of 0 .. parts - 1, no other cell
    # in any, a layer across that axis in one part, the parts in order along it, and no part beyond an even share
    # by more than one layer's candidates.
    rng = np.random.default_rng(seed)
    candidates = rng.random((5, 6, 7)) < fill
    rotation = np.roll(np.eye(3), axis - 2, axis=1)            # row 2: the first joint's axis in the world
    part_of = _section_parts(candidates, type("Prover", (), {"rotation": rotation})(), parts)
    assert ((part_of >= 0) == candidates).all() and part_of.max(initial=-1) < parts
    layers = np.moveaxis(part_of, axis, 0).reshape(candidates.shape[axis], -1)
    owner = [set(row[row >= 0].tolist()) for row in layers]
    assert all(len(o) <= 1 for o in owner)
    order = [o.pop() for o in owner if o]
    assert order == sorted(order)
    counts = np.bincount(part_of[candidates], minlength=parts)
    widest = np.moveaxis(candidates, axis, 0).reshape(candidates.shape[axis], -1).sum(axis=1).max(initial=0)
    assert (np.abs(counts - candidates.sum() / parts) <= widest).all()


def test_a_worker_s_answer_is_refused_unless_it_is_what_its_task_asked_for():
    # Reference: the task each answer came for.  A section part may prove pairs of its own cells only; a paving
    # must come back as float boxes of the arm's three coordinates.
    part_of = np.array([-1, 0, 1, 1]).reshape(1, 2, 2)
    task = np.array([[1, float("nan")]])
    good = {"part": 1, "inner": np.zeros((1, 2, 2, 3), dtype=bool), "seconds": 1.0}
    assert _checked_section(good, task, part_of=part_of, count=3) is good
    theirs = np.zeros((1, 2, 2, 3), dtype=bool)
    theirs[0, 0, 1, 2] = True                                   # a cell of part 0
    for forged, what in (({**good, "inner": theirs}, "outside its part"), ({**good, "part": 0}, "part asked for"),
                         ({**good, "inner": good["inner"].astype(np.int8)}, "booleans"),
                         ({**good, "inner": np.zeros((1, 2, 2, 2), dtype=bool)}, "booleans")):
        with pytest.raises(WorkerResultError, match=what):
            _checked_section(forged, task, part_of=part_of, count=3)
    paving = {"which": 0, "outer": np.zeros((5, 3, 2)), "kept": np.zeros((0, 3, 2)), "box": np.zeros((3, 2)),
              "complete": True, "method": "section", "seconds": 1.0}
    assert _checked_paving(paving, np.array([[0, 1.0]])) is paving
    for forged, what in (({**paving, "outer": np.zeros((5, 2, 2))}, "outer are not float boxes"),
                         ({**paving, "box": np.zeros((3, 2), dtype=np.float32)}, "box are not float boxes"),
                         ({**paving, "which": 1}, "paving asked for"), ({**paving, "complete": 1}, "completeness"),
                         ({**paving, "seconds": "1"}, "seconds")):
        with pytest.raises(WorkerResultError, match=what):
            _checked_paving(forged, np.array([[0, 1.0]]))


def test_a_section_map_saves_and_is_refused_as_another_method(puma, puma_map, tmp_path):
    path = puma_map.save(tmp_path / "puma.npz")
    again = ReachMap.load(path, expect=map_problem(robots.build("puma560"), **PUMA))     # a new object, same problem
    assert np.array_equal(again.codes, puma_map.codes) and again.method == puma_map.method
    with pytest.raises(InvalidParameterError, match="method"):
        ReachMap.load(path, expect=map_problem(puma, **{**PUMA, "method": "pavings"}))


@pytest.mark.filterwarnings("ignore:reach_map. the cones")
def test_bad_section_options_are_one_clear_error(puma, tmp_path):
    with pytest.raises(InvalidParameterError, match="method must be one of"):
        reach_map(puma, delta=0.2, directions=6, method="sampled")
    with pytest.raises(InvalidParameterError, match="resume"):
        reach_map(puma, delta=0.2, directions=6, method="section", run=RunOn(resume=tmp_path / "c.npz"))
    q1, q2, q3 = sp.symbols("q1:4")
    coupled = DHRobot([DHJoint("R", q1, sp.Rational(3, 10), 0, sp.pi / 2, q1),
                       DHJoint("R", q2 - q1, 0, sp.Rational(1, 2), 0, q2), DHJoint.revolute(3, a=sp.Rational(2, 5))],
                      name="coupled arm")
    with pytest.raises(InvalidParameterError, match="does not turn the rest of the arm"):
        reach_map(coupled, delta=0.2, directions=6, method="section")
    with pytest.raises(InvalidParameterError, match="needs a spatial robot"):
        reach_map(robots.build("planar-2r"), delta=0.2, directions=6, method="section")
