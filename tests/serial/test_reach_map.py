"""Certified reachability maps (workspace_sym/serial/reachmap.py): the directions and their cover, the exact
covering test, soundness against sampled configurations and a 50-digit inverse kinematics, files, bad input."""

from __future__ import annotations

import math
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from reach_checks import wrist_arm_in_cone_at_50_digits
from workspace_sym import robots
from workspace_sym.errors import InvalidParameterError, WorkspaceError
from workspace_sym.interval.driver import RunOn, StopAt
from workspace_sym.kinematics import numeric_function
from workspace_sym.serial.reachmap import (
    MAP_FORMAT,
    ReachMap,
    covered_cells,
    covering_angle,
    map_problem,
    reach_map,
    sphere_directions,
)

PUMA = dict(delta=0.2, reach_delta=0.3, directions=[[0, 0, 1]], cone=30)   # about the vertical: the section method
SCARA = dict(delta=0.2, directions=6, cone=30)


def _quiet(robot, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)        # the cones do not cover the sphere: said, not tested
        return reach_map(robot, **options)


@pytest.fixture(scope="module")
def puma_map():
    return _quiet(robots.build("puma560"), **PUMA)


@pytest.fixture(scope="module")
def scara_map():
    return _quiet(robots.build("scara"), **SCARA)


def _sampled(robot, n, seed):
    """Tool points and approach axes of ``n`` configurations drawn uniformly within the limits (forward
    kinematics of the robot's own matrices, in floats)."""
    T = numeric_function(robot.substitute(robot.fk()), robot.q)
    lim = robot.joint_limits()
    q = np.random.default_rng(seed).uniform(lim[:, 0], lim[:, 1], size=(n, len(lim)))
    M = T(q)
    return M[:, :3, 3], M[:, :3, 2]


# the directions --------------------------------------------------------------------------------------------------
def test_the_26_directions_are_the_cube_s_faces_edges_and_corners_and_cones_of_30_degrees_cover_the_sphere():
    # Reference: the 26 nonzero vectors of {-1, 0, 1}^3 normalised; the covering angle of the 6 faces is the
    # angle from a face to a corner, acos(1/sqrt 3) (an exact identity), and the 26's is below 30 degrees.
    d = sphere_directions(26)
    assert np.allclose(np.linalg.norm(d, axis=1), 1) and len({tuple(np.sign(v).astype(int)) for v in d}) == 26
    assert covering_angle(sphere_directions(6)) == pytest.approx(math.degrees(math.acos(1 / math.sqrt(3))), abs=1e-9)
    assert covering_angle(d) < 30
    assert np.array_equal(sphere_directions(26), d)             # deterministic


def test_the_spiral_s_covering_angle_agrees_with_a_dense_search():
    # Reference: the largest angle from 200,000 random unit vectors to the nearest of 40 spiral directions (a
    # lower bound of the covering angle, close to it).
    d = sphere_directions(40)
    v = np.random.default_rng(0).normal(size=(200_000, 3))
    v /= np.linalg.norm(v, axis=1)[:, None]
    dense = math.degrees(math.acos((v @ d.T).max(axis=1).min()))
    assert dense <= covering_angle(d) + 1e-9 and covering_angle(d) - dense < 1.0


# the covering test -----------------------------------------------------------------------------------------------
def test_a_cell_covered_only_up_to_one_ulp_is_not_covered():
    # Reference: by construction: two boxes meeting at x = 1.5 cover the cells [1, 2]; moved apart by one ulp
    # they leave a gap of positive width, so the cells x in [1, 2] are not covered (no float tolerance is used).
    e = [np.array([0.0, 1.0, 2.0])] * 3
    whole = np.array([[[0, 1.5], [0, 2], [0, 2]], [[1.5, 2], [0, 2], [0, 2]]], dtype=float)
    assert covered_cells(e, whole).all()
    gap = whole.copy()
    gap[1, 0, 0] = np.nextafter(1.5, 2)
    covered = covered_cells(e, gap)
    assert covered[0].all() and not covered[1].any()


def test_the_outside_of_the_root_counts_open_so_a_cell_touching_its_face_needs_the_face_covered():
    # Reference: by construction: the root box [0.5, 2] x [0, 2] x [0, 2] (a point on its face x = 0.5 may be
    # reached); the cells x in [0, 1] are covered by the open outside and an outer box [0.5, 1] x ..., which holds
    # the face; an outer box from the next float after 0.5 leaves the face uncovered; a cell wholly below 0.5
    # (x in [0, 0.25]) is covered by the open outside alone.
    e = [np.array([0.0, 1.0, 2.0])] * 3
    root = np.array([[0.5, 2.0], [0.0, 2.0], [0.0, 2.0]])
    outer = np.array([[[0.5, 1.0], [0, 2], [0, 2]]], dtype=float)
    assert covered_cells(e, outer, exterior=root)[0].all()
    shifted = outer.copy()
    shifted[0, 0, 0] = np.nextafter(0.5, 1)
    assert not covered_cells(e, shifted, exterior=root)[0].any()
    assert not covered_cells(e, np.zeros((0, 3, 2)), exterior=root)[0].any()
    low = [np.array([0.0, 0.25, 2.0]), e[1], e[2]]
    assert covered_cells(low, np.zeros((0, 3, 2)), exterior=root)[0].all()


# soundness --------------------------------------------------------------------------------------------------------
def test_sampled_puma_configurations_never_fall_in_a_proved_unreachable_pair(puma_map):
    # Reference: forward kinematics of 200,000 configurations within the limits: each is reached, so the pair
    # (its cell, a direction whose cone holds its approach axis, with a margin of 1e-9) is not proved
    # unreachable; nor is its point outside the grid.
    points, approach = _sampled(robots.build("puma560"), 200_000, seed=1)
    codes = puma_map.query(points, approach=approach)
    assert not (codes == -1).any()
    index, inside = puma_map.cells_of(points)
    assert inside.all()
    cos_c = math.cos(math.radians(puma_map.cone))
    for k, d in enumerate(puma_map.directions):
        held = approach @ d >= cos_c + 1e-9
        assert held.sum() > 1000
        assert not (puma_map.codes[index[held, 0], index[held, 1], index[held, 2], k] == -1).any()
    assert (puma_map.codes == -1).sum() > 100 and puma_map.outside_proved


def test_the_capability_bracket_holds_the_sampled_capability(puma_map):
    # Reference: a direction with a sampled configuration in the cell and its approach in the cone is reached
    # somewhere in the cell, so it is not proved unreachable: the sampled count is at most K - unreachable.
    points, approach = _sampled(robots.build("puma560"), 200_000, seed=2)
    index, _ = puma_map.cells_of(points)
    k = puma_map.codes.shape[-1]
    cos_c = math.cos(math.radians(puma_map.cone))
    seen = np.zeros(puma_map.codes.shape, dtype=bool)
    for j, d in enumerate(puma_map.directions):
        held = approach @ d >= cos_c + 1e-9
        seen[index[held, 0], index[held, 1], index[held, 2], j] = True
    sampled = seen.sum(-1) / k
    bracket = puma_map.capability
    assert (bracket[..., 0] <= bracket[..., 1]).all()
    assert (sampled <= bracket[..., 1]).all() and (sampled > 0).sum() > 50


def test_points_of_proved_reachable_pairs_are_reached_in_the_cone_at_50_digits(puma_map):
    # Reference: an inverse kinematics at 50 digits (tests/helpers/reach_checks.py), within the limits, with the
    # approach axis within the cone of the pair's direction, at random points of proved-reachable cells.
    robot = robots.build("puma560")
    rng = np.random.default_rng(5)
    pairs = np.argwhere(puma_map.codes == 1)
    assert len(pairs) >= 2
    edges = puma_map.edges
    for i, j, l, k in pairs[rng.choice(len(pairs), size=min(3, len(pairs)), replace=False)]:
        cell = np.array([[edges[a][c], edges[a][c + 1]] for a, c in enumerate((i, j, l))])
        target = rng.uniform(cell[:, 0], cell[:, 1])
        found = wrist_arm_in_cone_at_50_digits(robot, target, puma_map.directions[k], puma_map.cone, rng)
        assert found is not None, f"{target} of a proved-reachable cell, direction {puma_map.directions[k]}"


def test_the_scara_points_straight_down_so_every_other_cone_is_proved_unreachable(scara_map):
    # Reference: the SCARA's approach axis is (0, 0, -1) for every configuration (its axes are vertical): 90 or
    # 180 degrees from the other five cube directions, outside their 30-degree cones.
    down = np.flatnonzero(np.all(scara_map.directions == (0, 0, -1), axis=1))[0]
    others = [k for k in range(6) if k != down]
    assert (scara_map.codes[..., others] == -1).all()
    assert (scara_map.codes[..., down] == -1).any() and (scara_map.codes[..., down] != -1).any()


# files ------------------------------------------------------------------------------------------------------------
def test_a_saved_map_loads_and_answers_the_same(puma_map, tmp_path):
    # Reference: the map itself; its file read back must give the same arrays and the same answers.
    path = puma_map.save(tmp_path / "puma.npz")
    again = ReachMap.load(path, expect=map_problem(robots.build("puma560"), **PUMA))
    assert np.array_equal(again.codes, puma_map.codes) and again.codes.dtype == np.int8
    assert np.array_equal(again.directions, puma_map.directions) and again.fingerprint == puma_map.fingerprint
    points, approach = _sampled(robots.build("puma560"), 5000, seed=3)
    points = np.concatenate([points, [[5.0, 0, 0]]])
    approach = np.concatenate([approach, [[0, 0, 1.0]]])
    assert np.array_equal(again.query(points, approach=approach), puma_map.query(points, approach=approach))
    assert np.array_equal(again.query(points), puma_map.query(points))
    assert again.summary() == puma_map.summary()


def test_a_map_of_another_robot_delta_or_format_is_refused_by_name(scara_map, tmp_path):
    path = scara_map.save(tmp_path / "scara.npz")
    with pytest.raises(InvalidParameterError, match="delta"):
        ReachMap.load(path, expect=map_problem(robots.build("scara"), **{**SCARA, "delta": 0.1}))
    with pytest.raises(InvalidParameterError, match="robot"):
        ReachMap.load(path, expect=map_problem(robots.build("puma560"), **SCARA))
    with np.load(path, allow_pickle=False) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["format"] = np.array(MAP_FORMAT + 1)
    np.savez(tmp_path / "later.npz", **arrays)
    with pytest.raises(InvalidParameterError, match="format version"):
        ReachMap.load(tmp_path / "later.npz")


def test_a_corrupted_or_truncated_map_is_refused(scara_map, tmp_path):
    path = scara_map.save(tmp_path / "scara.npz")
    with np.load(path, allow_pickle=False) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["codes"] = arrays["codes"].copy()
    arrays["codes"].flat[0] = -arrays["codes"].flat[0] or 1        # one verdict changed, the digest kept
    np.savez(tmp_path / "changed.npz", **arrays)
    with pytest.raises(InvalidParameterError, match="digest"):
        ReachMap.load(tmp_path / "changed.npz")
    data = path.read_bytes()
    (tmp_path / "cut.npz").write_bytes(data[: len(data) // 2])
    with pytest.raises(InvalidParameterError, match="not a reach map"):
        ReachMap.load(tmp_path / "cut.npz")


def test_a_resumed_map_takes_its_finished_directions_and_refuses_another_problem(scara_map, tmp_path):
    # Reference: the map built in one go (no time limit); a checkpoint of another cone is refused naming it.
    check = tmp_path / "run.ckpt.npz"
    first = _quiet(robots.build("scara"), **SCARA, run=RunOn(resume=check), stop=StopAt(time_limit=120))
    assert np.array_equal(first.codes, scara_map.codes) and check.is_file()
    again = _quiet(robots.build("scara"), **SCARA, run=RunOn(resume=check))
    assert np.array_equal(again.codes, scara_map.codes)
    assert again.info["direction_seconds"] == first.info["direction_seconds"]     # read back, not built again
    with pytest.raises(InvalidParameterError, match="cone"):
        _quiet(robots.build("scara"), **{**SCARA, "cone": 40}, run=RunOn(resume=check))


def test_directions_sent_to_an_executor_give_the_same_map(scara_map):
    # Reference: the map built in this thread.
    with ThreadPoolExecutor(2) as pool:
        there = _quiet(robots.build("scara"), **SCARA, run=RunOn(executor=pool))
    assert np.array_equal(there.codes, scara_map.codes)


# bad input --------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("options, name", [
    (dict(cone=0), "cone"), (dict(cone=181), "cone"), (dict(cone=float("nan")), "cone"),
    (dict(directions=0), "directions"), (dict(directions=2.5), "directions"),
    (dict(directions=[[0, 0, 0], [0, 0, 1]]), "directions"), (dict(delta=0), "delta"),
    (dict(run=RunOn(store="x")), "store"),
])
def test_bad_build_options_are_one_clear_error(options, name):
    with pytest.raises(WorkspaceError) as info:
        reach_map(robots.build("scara"), **{**SCARA, **options})
    assert info.value.parameter == name


def test_bad_queries_are_one_clear_error(scara_map):
    for points, approach, name in [([[0, 0, 0]], [[0, 0, 0]], "approach"), ([[0, 0, float("nan")]], None, "points"),
                                   ([[0, 0]], None, "points"), ([[0, 0, 0]] * 2, [[0, 0, 1]] * 3, "approach")]:
        with pytest.raises(InvalidParameterError) as info:
            scara_map.query(points, approach=approach)
        assert info.value.parameter == name


def test_an_approach_no_cone_holds_is_undecided_and_the_outside_is_proved_only_when_proved(scara_map):
    # Reference: the 6 cube directions with cones of 30 degrees leave (1, 1, 1) (54.7 degrees from each) unheld.
    inside = np.array([[0.3, 0.0, 0.1]])
    assert scara_map.query(inside, approach=[[1, 1, 1]]).tolist() == [0]
    far = np.array([[9.0, 9.0, 9.0]])
    assert scara_map.query(far, approach=[[1, 0, 0]]).tolist() == [-1] and scara_map.outside_proved
    assert scara_map.query(far).tolist() == [[0.0, 0.0]]
