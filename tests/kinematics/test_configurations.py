"""A robot at a configuration (``robot.fk(q)``) and in the other DH convention (``robot.to_convention``), issue 27.

Reference for both: the DH rows multiplied here in numpy, one 4 x 4 matrix per row from the table's own numbers
(no SymPy product, no simplification), at configurations drawn by hypothesis, joint limits and zero included.
"""

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from paths import DATA
from workspace_sym import DHRobot, robots
from workspace_sym.errors import WorkspaceError

PANDA = DATA / "dh" / "panda.json"


def _row(theta, d, a, alpha, convention):
    ct, st_, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    rz = np.array([[ct, -st_, 0, 0], [st_, ct, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    rx = np.array([[1, 0, 0, 0], [0, ca, -sa, 0], [0, sa, ca, 0], [0, 0, 0, 1]])
    tz, tx = np.eye(4), np.eye(4)
    tz[2, 3], tx[0, 3] = d, a
    return rz @ tz @ tx @ rx if convention == "standard" else rx @ tx @ rz @ tz


def _numpy_fk(robot, q) -> np.ndarray:
    """base * A_1(q_1) ... A_n(q_n) * tool from the table's numbers (default parameters)."""
    values = {**{s: v for s, v in robot.parameters.items()}, **dict(zip(robot.q, q))}

    def num(e):
        return float(sp.sympify(e).xreplace(values))

    T = np.eye(4) if robot.base is None else np.array(robot.base.xreplace(values), dtype=float)
    for j in robot.joints:
        T = T @ _row(num(j.theta), num(j.d), num(j.a), num(j.alpha), robot.convention)
    return T if robot.tool is None else T @ np.array(robot.tool.xreplace(values), dtype=float)


ROBOTS = {name: robots.build(name) for name in ("puma560", "scara", "planar-3r")}
ROBOTS["panda"] = DHRobot.from_file(PANDA)


def _configurations(name):
    lo, hi = ROBOTS[name].joint_limits().T
    edge = st.sampled_from([0.0, 1.0])
    return st.lists(st.one_of(st.floats(0, 1), edge), min_size=len(lo), max_size=len(lo)).map(
        lambda u: list(lo + np.array(u) * (hi - lo)))


# ------------------------------------------------------------------------------ fk at a configuration
def test_fk_of_a_list_is_the_pose_there():
    """Issue 27: robot.fk([0]*6) raised TypeError ('<=' not supported).  It is the pose at that configuration, with
    the default lengths (or those given); exact values stay exact (planar 2R at (0, pi/2): the end at (l1, l2))."""
    puma = ROBOTS["puma560"]
    assert np.allclose(np.array(puma.fk([0] * 6), dtype=float), _numpy_fk(puma, [0] * 6), atol=1e-12)
    arm = robots.build("planar-2r")
    T = arm.fk([0, sp.pi / 2])
    assert T[:2, :2] == sp.Matrix([[0, -1], [1, 0]]) and np.allclose(np.array(T[:2, 3], dtype=float), [[1], [0.5]])
    assert arm.fk((0, sp.pi / 2), parameters={"l1": 2, "l2": sp.Rational(1, 3)})[:2, 3] == sp.Matrix(
        [2, sp.Rational(1, 3)])
    assert arm.fk(np.array([0.0, 0.0]))[0, 3] == pytest.approx(1.5, abs=1e-15)
    assert arm.fk(2) == arm.fk()            # a frame number still names a frame
    with pytest.raises(WorkspaceError, match="parameters apply to a configuration"):
        arm.fk(2, parameters={"l1": 1})


@pytest.mark.parametrize(("q", "words"), [
    ([0] * 5, "q must hold 6 joint values (one per joint); got 5"),
    ([0, 0, 0, 0, 0, "__import__('os')"], "q"),
    ([0, 0, 0, 0, 0, float("nan")], "finite"),
    ([0, 0, 0, 0, 0, [1]], "q"),
    (1.5, "k must be a frame number from 0 to 6 or a configuration"),
])
def test_fk_of_a_bad_configuration_names_it(q, words):
    with pytest.raises(WorkspaceError, match=words.replace("(", r"\(").replace(")", r"\)")):
        ROBOTS["puma560"].fk(q)


@pytest.mark.parametrize("name", ["puma560", "scara"])
def test_fk_at_random_configurations(name):
    robot = ROBOTS[name]

    @settings(derandomize=True, max_examples=25, deadline=None)
    @given(_configurations(name))
    def check(q):
        assert np.allclose(np.array(robot.fk(q), dtype=float), _numpy_fk(robot, q), atol=1e-12)

    check()


# ------------------------------------------------------------------------------ the other DH convention
@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_other_convention_has_the_same_fk(name):
    """Standard <-> modified DH: the same joints, limits and variables; FK equal at random configurations (numpy
    products of each table in its own convention); converting back gives the original table."""
    robot = ROBOTS[name]
    other = "modified" if robot.convention == "standard" else "standard"
    converted = robot.to_convention(other)
    assert converted.convention == other and converted.q == robot.q and converted.n == robot.n
    assert [j.limits for j in converted.joints] == [j.limits for j in robot.joints]
    assert [j.kind for j in converted.joints] == [j.kind for j in robot.joints]
    assert any(other in note for note in converted.input_notes)

    @settings(derandomize=True, max_examples=25, deadline=None)
    @given(_configurations(name))
    def check(q):
        assert np.allclose(_numpy_fk(converted, q), _numpy_fk(robot, q), atol=1e-12)

    check()
    back = converted.to_convention(robot.convention)     # the same table, but for the pair moved to base or tool
    kept = slice(0, -1) if robot.convention == "standard" else slice(1, None)
    assert [(j.theta, j.d, j.a, j.alpha) for j in back.joints][kept] == [(j.theta, j.d, j.a, j.alpha)
                                                                         for j in robot.joints][kept]
    assert robot.to_convention(robot.convention) is robot


def test_other_convention_of_the_planar_arm_is_exact():
    """Planar 3R (a = l1, l2, l3, alpha = 0): in modified DH the lengths move one row down and the last one becomes
    the tool, a translation by l3 along x (textbook: Craig, Introduction to Robotics, 3.4); FK identical in SymPy."""
    arm = robots.build("planar-3r")
    modified = arm.to_convention("modified")
    assert [j.a for j in modified.joints] == [0, *(j.a for j in arm.joints[:2])]
    assert modified.tool == sp.Matrix([[1, 0, 0, arm.joints[2].a], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    assert sp.simplify(modified.fk() - arm.fk()) == sp.zeros(4, 4)
    with pytest.raises(WorkspaceError, match="convention"):
        arm.to_convention("craig")
