"""Certified position workspaces of serial robots (workspace_sym.serial_workspace).

References, each named in its test:
* exact: the 2R arm with full joint ranges reaches the annulus ``|l1 - l2| <= r <= l1 + l2``
  (area ``pi ((l1 + l2)^2 - (l1 - l2)^2)``), checked in exact rational arithmetic point by point;
* a second method: Bastien's alignment boundary of the same chain with joint limits (PlanarChain);
* independent numerics: random configurations never land in an outer box, and a damped
  least-squares inverse kinematics reaches points of inner boxes within the limits.
"""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import workspace_sym as ws
from workspace_sym.errors import InvalidParameterError, JointLimitError
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial_workspace import ReachModel, reach


def planar_robot(lengths, lower=None, upper=None):
    """A DH robot of revolute joints in a plane (a_i = l_i, alpha_i = 0), limits in radians."""
    joints = []
    for k, l in enumerate(lengths, start=1):
        limits = None if lower is None else (lower[k - 1], upper[k - 1])
        joints.append(DHJoint.revolute(k, a=l, limits=limits))
    return DHRobot(joints, name="planar")


def _points(box, rng, k=3):
    return list(itertools.product(*box)) + [tuple(rng.uniform(lo, hi) for lo, hi in box) for _ in range(k)]


def test_two_r_full_range_is_the_annulus_exactly():
    """Exact reference: r^2 in [(l1 - l2)^2, (l1 + l2)^2], in Fractions at every corner and random point."""
    l1, l2 = Fraction(1), Fraction(1, 2)
    p = reach(planar_robot([sp.Integer(1), sp.Rational(1, 2)]), delta=0.06)
    assert p.variables == (sp.Symbol("x"), sp.Symbol("y"))
    lo, hi = p.measure_bounds
    area = np.pi * (1.5**2 - 0.5**2)
    assert lo <= area <= hi and hi - lo < 0.2 * area        # 0.14 at delta 0.06, 0.07 at delta 0.03
    assert len(p.inner) > 50 and len(p.outer) > 50
    rng = np.random.default_rng(0)
    for box in p.inner:
        for x, y in _points(box, rng):
            r2 = Fraction(x) ** 2 + Fraction(y) ** 2
            assert (l1 - l2) ** 2 <= r2 <= (l1 + l2) ** 2, (box, x, y)
    for box in p.outer:
        pts = [Fraction(x) ** 2 + Fraction(y) ** 2 for x, y in _points(box, rng)]
        assert all(r2 < (l1 - l2) ** 2 for r2 in pts) or all(r2 > (l1 + l2) ** 2 for r2 in pts), box


@settings(max_examples=8, deadline=None)
@given(lengths=st.lists(st.sampled_from([0.3, 0.5, 0.75, 1.0]), min_size=2, max_size=3),
       limits=st.lists(st.tuples(st.integers(-170, 0), st.integers(10, 170)), min_size=3, max_size=3))
def test_planar_verdicts_agree_with_the_alignment_boundary(lengths, limits):
    """Second method: Bastien's exact boundary classifies every checked point of inner boxes inside
    (or on the boundary) and of outer boxes outside (or on it); its area lies in the bracket."""
    p_ = len(lengths)
    lower = [lo for lo, _ in limits[:p_]]
    upper = [hi for _, hi in limits[:p_]]
    chain = ws.PlanarChain(lengths, lower, upper)
    robot = planar_robot([sp.nsimplify(l) for l in lengths], [np.radians(v) for v in lower],
                         [np.radians(v) for v in upper])
    paving = reach(robot, delta=0.1 * sum(lengths), max_boxes=20_000)
    boundary = chain.boundary()
    lo, hi = paving.measure_bounds
    assert lo - 1e-9 <= boundary.area <= hi + 1e-9
    rng = np.random.default_rng(1)
    for kind, wrong in (("inner", "outside"), ("outer", "inside")):
        boxes = getattr(paving, kind)
        for box in boxes[rng.permutation(len(boxes))[:60]]:
            x, y = np.array(_points(box, rng)).T
            verdicts = boundary.classify(np.stack([-y, x], axis=1), tol=1e-7)   # PlanarChain's theta1 is from +y
            assert wrong not in set(verdicts), (kind, box.tolist(), verdicts)


def test_no_configuration_lands_in_an_outer_box_and_inner_points_are_reached():
    """Independent numerics on the SCARA (two revolute joints and a prismatic one move the position):
    200,000 random configurations within the limits miss every outer box; points drawn in inner
    boxes are reached by a damped least-squares inverse kinematics within the limits (residual
    below 1e-9)."""
    robot = ws.robots.build("scara")
    model = ReachModel(robot)
    assert model.joints == [0, 1, 2] and model.coordinates == [0, 1, 2]
    p = reach(robot, delta=0.08)
    assert len(p.outer) > 0 and len(p.inner) > 0
    rng = np.random.default_rng(2)
    q = rng.uniform(model.limits[:, 0], model.limits[:, 1], size=(200_000, 3))
    pos = model.position_float(q)
    out = p.outer
    for k in range(0, len(out), 256):
        chunk = out[k:k + 256]
        hit = ((pos[:, None, :] > chunk[None, :, :, 0]) & (pos[:, None, :] < chunk[None, :, :, 1])).all(axis=2)
        assert not hit.any()
    boxes = p.inner[rng.permutation(len(p.inner))[:40]]
    targets = np.array([[rng.uniform(lo, hi) for lo, hi in b] for b in boxes])
    reached = np.zeros(len(targets), dtype=bool)
    for _ in range(20):                          # random restarts
        q = rng.uniform(model.limits[:, 0], model.limits[:, 1], size=(len(targets), 3))
        for _ in range(60):
            J = model.jacobian_float(q)
            r = model.position_float(q) - targets
            step = np.einsum("nij,nj->ni", np.linalg.pinv(J, rcond=1e-10), r)
            q = np.clip(q - step, model.limits[:, 0], model.limits[:, 1])
        reached |= np.linalg.norm(model.position_float(q) - targets, axis=1) < 1e-9
    assert reached.all()


def test_method_on_the_robot_is_the_function():
    robot = planar_robot([sp.Integer(1), sp.Rational(1, 2)])
    a, b = robot.reach(delta=0.2), reach(robot, delta=0.2)
    assert all(np.array_equal(getattr(a, k), getattr(b, k)) for k in ("inner", "boundary", "outer"))


def test_only_position_joints_are_subdivided():
    """The glass-handling arm's theta5 and theta6 do not move the position (paper 004's arm)."""
    model = ReachModel(ws.robots.build("glass-handling"))
    assert model.joints == [0, 1, 2, 3] and model.m == 3


def test_budget_and_time_limit_leave_pending_boxes():
    robot = planar_robot([sp.Integer(1), sp.Integer(1)])
    p = reach(robot, delta=0.01, max_boxes=50)
    assert not p.complete and len(p.pending) > 0 and "budget" in p.stop_reason
    total = sum(p.measures.values())
    assert total == pytest.approx(p.box.measure, rel=1e-12)       # the classes tile the initial box


def test_bad_input_is_a_clear_error():
    with pytest.raises(InvalidParameterError, match="delta"):
        reach(planar_robot([1, 1]), delta=0)
    with pytest.raises(JointLimitError, match="prismatic: reach needs its limits"):
        reach(DHRobot([DHJoint.revolute(1, a=1), DHJoint.prismatic(2)]), delta=0.1)
    a = sp.Symbol("a")
    with pytest.raises(InvalidParameterError, match="give values for a"):
        reach(DHRobot([DHJoint.revolute(1, a=a)]), delta=0.1)
