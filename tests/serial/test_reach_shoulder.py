"""The outer bound of turned sections by the distance from the shoulder, on the UR5 and the KUKA KR16
(workspace_sym.reach_section.ShoulderReach, issue 24).

References, each named in its test:
* independent numerics: 10^5 random configurations (vectorised floats) have ``h`` below the proved bound, satisfy
  the inequality the bound rests on, and never land in a cell declared outside; the bound is within its
  tolerance of the largest sampled value refined by Newton's method on the gradient;
* a second method: Pappus's theorem on the section sampled at 3 10^5 configurations (cells of side h of (rho, z)
  hit by a sample, each turned through a full circle), which the proved bracket of the paving must hold.
"""

from __future__ import annotations

import contextlib
import functools
import itertools

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from reach_checks import industrial_arm
from workspace_sym.interval.image import CellGrid
from workspace_sym.interval.verdict import INSIDE as INNER
from workspace_sym.interval.verdict import OUTSIDE as OUTER
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial.section import ShoulderReach, section_paving, shoulder_distance, turned_volume
from workspace_sym.serial.structure import structure_of


@pytest.fixture(scope="module", params=["ur5", "kr16"])
def arm(request):
    robot = industrial_arm(request.param)
    return request.param, robot, structure_of(robot, ())


def _section_points(image, n, seed):
    q = image.random_configurations(n, np.random.default_rng(seed))
    return q, image.position_float(q)


def _h(reach, image, q):
    cols = [image.variables.index(v) for v in reach.map.variables]
    return reach.map.position_float(q[:, cols])[:, 0], cols


def test_shoulder_distance_bound_holds_every_sampled_configuration(arm):
    """The shoulder point lies on the second joint's axis: ``h`` does not depend on that joint (dropped from
    its variables). Independent numerics: at 10^5 configurations ``h`` is below the bound, above the squared
    section distance to the centre (the inequality of the outer proof), and the bound is within its tolerance
    (plus 10^-6) of the largest sampled value refined by gradient steps."""
    name, robot, plan = arm
    image, reach = plan.section, plan.section.reach
    assert reach is not None and image.variables[0] not in reach.map.variables
    q, p = _section_points(image, 100_000, 1)
    h, cols = _h(reach, image, q)
    tolerance = 1e-3
    bound = reach.bound(tolerance)
    assert h.max() <= bound
    (sr, _), (sz, _) = reach.centre
    assert np.all((p[:, 0] - sr) ** 2 + (p[:, 1] - sz) ** 2 <= h + 1e-12)
    # Gradient ascent from the 20 best samples, in the joints of h (limits held).
    best = q[np.argsort(h)[-20:]][:, cols]
    lo, hi = reach.map.limits[:, 0], reach.map.limits[:, 1]
    for _ in range(200):
        grad = reach.map.jacobian_float(best)[:, 0, :]
        best = np.clip(best + 0.05 * grad, lo, hi)
    top = reach.map.position_float(best)[:, 0].max()
    assert top <= bound <= top + tolerance + 1e-6, (top, bound)


@settings(max_examples=25, deadline=None, derandomize=True)
@given(centre=st.lists(st.sampled_from([-np.pi, -1.0, 0.0, 0.3, np.pi / 2, np.pi]), min_size=3, max_size=3),
       width=st.sampled_from([0.0, 1e-9, 0.05, 0.5, 2 * np.pi]))
def test_centred_enclosure_holds_the_values_of_its_box(centre, width):
    """The enclosure of ``h`` (natural form intersected with the centred form) holds its values at the
    corners, the centre and 200 random points of boxes around edge points (the joint limits, zero, pi/2);
    independent numerics: float evaluation of the simplified expression."""
    reach = structure_of(industrial_arm("ur5"), ()).section.reach
    k = reach.map.k
    c = np.resize(np.array(centre), k)
    Q = np.stack([c - width / 2, c + width / 2], axis=1)[None]
    lo, hi = reach.enclose(Q)
    rng = np.random.default_rng(0)
    points = np.concatenate([rng.uniform(Q[0, :, 0], Q[0, :, 1], size=(200, k)), Q[0].T, c[None]])
    values = reach.map.position_float(points)[:, 0]
    assert lo[0] <= values.min() + 1e-12 and values.max() <= hi[0] + 1e-12


@pytest.mark.slow
def test_paving_of_industrial_arms_is_sound_and_holds_pappus(arm):
    """A coarse paving of the section stopped after a fixed count of boxes (the same on any machine): every
    cell beyond the shoulder bound is declared outside, none beyond a tighter bound inside; independent
    numerics: 10^5 configurations never land in an outer cell; second method: the Pappus bracket holds the
    volume of the sampled section."""
    name, robot, plan = arm
    image = plan.section
    width = 0.05
    grid, classes, evaluated, stopped, pieces = section_paving(
        image, width, budget=lambda count, ahead=0.0: "count" if count > 5_000 else "")
    far = image.reach.far_cells(grid, image.reach.bound(1.0))        # the paving's bound (kept: tighter than 1)
    assert far.any() and np.all(classes[far] == OUTER)
    tight = image.reach.far_cells(grid, image.reach.bound(1e-4))
    assert not np.any(classes[tight] == INNER)
    assert (classes == INNER).any()
    _, p = _section_points(image, 100_000, 2)
    first, _ = grid.span(np.repeat(p[:, :, None], 2, axis=2))
    assert not np.any(classes[first[:, 0], first[:, 1]] == OUTER)
    lo, hi = turned_volume(grid, classes, pieces)
    q, p = _section_points(image, 300_000, 3)
    h = 0.012
    cells = np.unique(np.floor(p / h).astype(np.int64), axis=0)
    volume = float(np.sum(2 * np.pi * (cells[:, 0] + 0.5) * h ** 3))
    assert lo <= volume <= hi, (lo, volume, hi)


def test_far_cells_are_outside_the_bound_disc():
    """The far cells of a grid are those whose nearest point to the centre is beyond the square root of the
    bound (a cell corner exactly on the circle is not far): the cell grid of [0, 2] x [0, 2] with unit-width
    cells around a centre at (0, 0) and bound 1."""
    reach = structure_of(industrial_arm("ur5"), ()).section.reach
    with _centred(reach, ((0.0, 0.0), (0.0, 0.0))):
        far = reach.far_cells(UNIT_GRID, 1.0)
    e0, e1 = UNIT_GRID.edges
    near = np.hypot(np.maximum(0, np.maximum(e0[:-1], -e0[1:]))[:, None],
                    np.maximum(0, np.maximum(e1[:-1], -e1[1:]))[None, :])
    assert np.array_equal(far, near > 1.0)
    assert far[3, 0] and not far[2, 2] and far[3, 3]


UNIT_GRID = CellGrid(np.array([[0.0, 2.0], [0.0, 2.0]]), 1.0)     # edges -1.5, -0.5, 0.5, 1.5, 2.5


@contextlib.contextmanager
def _centred(reach, centre):
    """``reach`` with its centre ``(|s_xy|, s_z)`` (each an enclosure) moved to ``centre`` inside the block."""
    saved = reach.centre
    reach.centre = centre
    try:
        yield
    finally:
        reach.centre = saved


# --- 7-joint arms: the joints turning about the shoulder dropped (shoulder_distance) -----------------------------

@functools.cache
def _seven(name):
    """``(robot, h, variables, reach)`` of the LBR iiwa 14 (URDF) or the Panda: the squared distance from the
    origin of the second joint's frame, and its :class:`ShoulderReach` over the joints' limits."""
    robot = industrial_arm(name)        # reach_checks: the objects the other files prepare too
    h, variables = shoulder_distance(robot, None, 1)
    limits = [robot.joints[robot.q.index(v)].limits for v in variables]
    return robot, h, variables, ShoulderReach(h, variables, limits, [False] * len(variables), (0, 0))


def _float_frames(robot, q):
    """Frames 0..n and the tool point of the DH table at the configurations ``q`` (``(N, n)``), by a float
    product of the numeric DH matrices (independent of the symbolic kinematics)."""
    def entry(e):
        f = sp.lambdify([robot.q], robot.substitute(e), "numpy")
        return np.broadcast_to(np.asarray(f(q.T), dtype=float), (len(q),))

    def eye():
        return np.broadcast_to(np.eye(4), (len(q), 4, 4)).copy()

    def turn(angle, i, j):                  # rotation by angle in the plane of axes i, j
        M = eye()
        M[:, i, i], M[:, i, j], M[:, j, i], M[:, j, j] = np.cos(angle), -np.sin(angle), np.sin(angle), np.cos(angle)
        return M

    T = eye()
    frames = [T]
    for j in robot.joints:
        th, d, a, al = (entry(e) for e in (j.theta, j.d, j.a, j.alpha))
        Rz, Rx, Tz, Tx = turn(th, 0, 1), turn(al, 1, 2), eye(), eye()
        Tz[:, 2, 3], Tx[:, 0, 3] = d, a
        A = Rz @ Tz @ Tx @ Rx if robot.convention == "standard" else Rx @ Tx @ Rz @ Tz
        T = T @ A
        frames.append(T)
    tool = np.array(robot.tool.evalf(), dtype=float) if robot.tool is not None else np.eye(4)
    return frames, (T @ tool)[:, :3, 3]


@pytest.mark.parametrize("name", ["iiwa", "panda"])
def test_shoulder_distance_of_seven_joint_arms_keeps_the_elbow_and_wrist_only(name):
    """The origin of the second joint's frame (the shoulder: joints 2 and 3 turn about axes through it) is at a
    distance from the tool point that only joints 4, 5 and 6 change (joint 7 turns the tool about its own axis):
    ``h`` has those three variables, where expanding ``|p - S|^2`` of the whole chain kept five (issue 24).
    Independent numerics: at 2000 random configurations ``h`` equals the squared distance of the tool point to
    that origin by a float product of the DH matrices, within 1e-12."""
    robot, h, variables, _ = _seven(name)
    assert [str(v) for v in variables] == ["theta4", "theta5", "theta6"]
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, size=(2000, robot.n))
    frames, p = _float_frames(robot, q)
    origin = frames[1 if robot.convention == "standard" else 2][:, :3, 3]
    values = sp.lambdify([variables], h, "numpy")(q[:, 3:6].T)
    assert np.max(np.abs(values - np.sum((p - origin) ** 2, axis=1))) < 1e-12


def test_shoulder_distance_is_cached_per_robot_parameters_and_joint():
    """A second request for the same robot, parameter values (a dict in any order) and joint is the same
    expression, in a list of its own (the caller may change it); other values or another joint are not served
    from that entry: exact SymPy identities against the distance derived with the values substituted."""
    a, b = sp.symbols("a b")
    robot = DHRobot([DHJoint.revolute(1, a=a), DHJoint.revolute(2, a=b)], parameters={a: 1, b: 1})
    q2 = robot.q[1]
    h, variables = shoulder_distance(robot, {a: 2, b: 3}, 0)
    again, more = shoulder_distance(robot, {b: 3, a: 2}, 0)
    assert again is h and more == variables and more is not variables
    more.append(a)
    assert shoulder_distance(robot, {a: 2, b: 3}, 0)[1] == [q2]
    other, _ = shoulder_distance(robot, {a: 5, b: 3}, 0)
    assert sp.expand(other - (25 + 9 + 30 * sp.cos(q2))) == 0
    assert sp.expand(h - (4 + 9 + 12 * sp.cos(q2))) == 0
    assert sp.expand(shoulder_distance(robot, {a: 2, b: 3}, 1)[0] - 9) == 0


@settings(max_examples=12, deadline=None, derandomize=True)
@given(name=st.sampled_from(["iiwa", "panda"]),
       ends=st.lists(st.tuples(st.sampled_from([0.0, 0.25, 0.5, 0.999, 1.0]),
                               st.sampled_from([0.0, 1e-9, 0.1, 0.5, 1.0])), min_size=3, max_size=3),
       tolerance=st.sampled_from([1e-3, 0.05, 1.0]))
def test_shoulder_bounds_hold_every_sampled_distance(name, ends, tolerance):
    """Property, aimed at edges (sub-boxes of the joint limits from a whole range down to a point, at the
    limits; tolerances from tight to loose): the proved upper bound of ``h`` is never below, the proved lower
    bound never above, its value at 3000 random configurations of the box and at its corners; both are within
    the tolerance (plus 10^-3 of the range of h, for the box search stopping at its count) of those values when
    the box is the whole range.  Independent numerics: float evaluation of ``h``."""
    robot, h, variables, whole = _seven(name)
    limits = whole.map.limits
    box = []
    for (start, span), (lo, hi) in zip(ends, limits):
        a = min(hi, lo + start * (hi - lo))
        box.append((a, min(hi, a + span * (hi - lo))))
    box = np.array(box)
    reach = ShoulderReach(h, variables, [tuple(sp.Rational(float(x)) for x in row) for row in box],
                          [False] * 3, (0, 0))
    rng = np.random.default_rng(1)
    corners = np.array(list(itertools.product(*box)))
    points = np.concatenate([rng.uniform(box[:, 0], box[:, 1], size=(3000, 3)), corners])
    values = reach.map.position_float(points)[:, 0]
    top, bottom = reach.bound(tolerance), reach.lowest(tolerance)
    assert bottom <= values.min() and values.max() <= top
    if np.all(box == limits):
        slack = tolerance + 1e-3 * (values.max() - values.min())
        assert top - values.max() <= slack and values.min() - bottom <= slack


def test_near_cells_lie_within_the_least_distance_at_every_polar_angle():
    """The near cells of a grid are those whose farthest point from ``S`` at any polar angle (``rho`` plus the
    centre's distance from the axis, here 0.5) is within the square root of the lower bound: a cell reaching
    exactly that distance is not near.  The unit-width grid over [0, 2] x [0, 2], ``S`` at (0.5, 0), bound 6.25
    (distance 2.5)."""
    reach = _seven("panda")[3]
    with _centred(reach, ((0.5, 0.5), (0.0, 0.0))):
        near = reach.near_cells(UNIT_GRID, 6.25)
    e0, e1 = UNIT_GRID.edges
    far = np.hypot(np.maximum(e0[1:], 0.0)[:, None] + 0.5, np.maximum(np.abs(e1[:-1]), np.abs(e1[1:]))[None, :])
    assert np.array_equal(near, far < 2.5)
    assert near[0, 1] and near[2, 1] and not near[2, 2] and not near[1, 3]      # [2, 2]: exactly 2.5
