"""Orientation workspaces of an arm with wrist offsets (issue 40 item 1): the UR5's 20 degree cone about straight
down (the section ``(rho^2, z)`` of a varying lateral offset) and its tool down (the wrist centre's section), both in
the partial sums of its parallel joints.  References: the robot's own forward kinematics (``fk_numeric``),
sampled admissible configurations, an inverse kinematics at 50 digits, a sampled volume (Pappus on the hit cells),
exact volumes of turned rectangles."""

from __future__ import annotations

import functools
import math

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from reach_checks import admissible_configurations, arcs_volume, in_any_box, industrial_arm, offset_arm
from workspace_sym import Pose
from workspace_sym.interval.image import CellGrid
from workspace_sym.interval.verdict import INSIDE as INNER
from workspace_sym.interval.verdict import OUTSIDE as OUTER
from workspace_sym.interval.verdict import UNDECIDED
from workspace_sym.serial import reach
from workspace_sym.serial.pose import constraint_from, pose_structure, squared_volume_bracket
from workspace_sym.transforms import rot_x, translation

CONE = dict(approach=(0, 0, -1), cone=20)
TOOL_DOWN = dict(rpy=(180, 0, 0))


@pytest.fixture(scope="module")
def ur5():
    return industrial_arm("ur5")


@pytest.fixture(scope="module")
def ur5_cone(ur5):
    return reach(ur5, delta=0.4, pose=Pose(**CONE))


@pytest.fixture(scope="module")
def ur5_down(ur5):
    return reach(ur5, delta=0.4, pose=Pose(**TOOL_DOWN))


EDGES = [-math.pi, -math.pi / 2, 0.0, math.pi / 2, math.pi]
ANGLE = st.one_of(st.sampled_from(EDGES), st.floats(-math.pi, math.pi))


@settings(derandomize=True, max_examples=30, deadline=None)
@given(q=st.lists(ANGLE, min_size=6, max_size=6))
@example(q=[math.pi] * 6)
@example(q=[0.0, -math.pi, math.pi, -math.pi, math.pi / 2, 0.0])
def test_the_cone_section_in_summed_angles_is_the_robots_own_kinematics(ur5, q):
    # Reference: the robot's forward kinematics (fk_numeric, floats) at q1 = 0: the section's t = x^2 + y^2, its
    # z, and the approach's horizontal part a_x^2 + a_y^2, evaluated in the new variables (each the sum of the
    # joints its name lists), agree to rounding, whatever the joints (their sums leave [-pi, pi]: periodicity).
    model = pose_structure(ur5, (), constraint_from(**CONE)).model
    assert "theta2+theta3+theta4" in [str(v) for v in model.variables]
    aim = model.proof.aim
    values = dict(zip([str(v) for v in ur5.q], q))
    phi = [sum(values[name] for name in str(v).split("+")) for v in aim.variables]
    t, z, a1, a2 = (float(sp.sympify(e).subs(dict(zip(aim.variables, phi)))) for e in aim.expressions)
    T = ur5.fk_numeric(np.array([[0.0, *q[1:]]]))[0]
    assert t == pytest.approx(T[0, 3] ** 2 + T[1, 3] ** 2, abs=1e-12)
    assert z == pytest.approx(T[2, 3], abs=1e-12)
    assert a1 ** 2 + a2 ** 2 == pytest.approx(T[0, 2] ** 2 + T[1, 2] ** 2, abs=1e-12)


def test_joints_that_do_not_turn_fully_keep_their_own_variables(puma):
    # Reference: the Puma 560's joint 3 is limited (-225..45 degrees, not a whole turn), so q2 + q3 is no free
    # variable: its models keep the robot's joints (and its results of issue 25 stay as they were).
    for options in (CONE, TOOL_DOWN):
        model = pose_structure(puma, (), constraint_from(**options)).model
        assert not any("+" in str(v) for v in model.variables)


@settings(derandomize=True, max_examples=40, deadline=None)
@given(t=st.tuples(st.integers(-2, 6), st.integers(1, 6)), z=st.tuples(st.integers(-3, 3), st.integers(1, 5)),
       undecided=st.booleans())
def test_squared_cells_turn_into_their_exact_volume(t, z, undecided):
    # Reference: a rectangle [t0, t1] x [z0, z1] of (rho^2, z) (t clipped at 0) turns into the solid
    # pi (t1 - t0) (z1 - z0) exactly (rho dr = dt / 2); cells at the grid's edges and below t = 0 included.
    grid = CellGrid(np.array([[0.0, 2.0], [-1.0, 1.0]]), 0.25)
    e0, e1 = grid.edges
    i0, j0 = t[0] + 4, z[0] + 6
    i1, j1 = min(i0 + t[1], grid.shape[0]), min(j0 + z[1], grid.shape[1])
    classes = np.full(grid.shape, OUTER, dtype=np.int8)
    classes[i0:i1, j0:j1] = UNDECIDED if undecided else INNER
    volume = math.pi * (max(e0[i1], 0.0) - max(e0[i0], 0.0)) * (e1[j1] - e1[j0])
    lo, hi = squared_volume_bracket(grid, classes)
    assert lo <= volume <= hi
    assert (lo == 0.0) if undecided else (hi - lo <= 1e-12 * max(volume, 1.0))
    assert hi - volume <= 1e-12 * max(volume, 1.0)


@pytest.mark.parametrize("options", [CONE, TOOL_DOWN], ids=["cone", "tool down"])
def test_ur5_admissible_configurations_never_land_in_an_outer_box(ur5, ur5_cone, ur5_down, options):
    # Reference: configurations sampled within the limits whose approach is in the cone (or, tool down, made
    # (0, 0, -1) by Newton on joints 4 and 5; the last joint spins the frame to Rx(pi)), placed by the robot's
    # own fk_numeric: none lies in an outer box (narrowed by 1e-9 for float rounding); both runs prove boxes
    # of each kind by the section method.
    paving = ur5_cone if options is CONE else ur5_down
    _, _, points = admissible_configurations(ur5, 100_000 if options is CONE else 20_000, 11,
                                             approach=(0, 0, -1), cone=options.get("cone"))
    assert len(points) > 1000
    assert not in_any_box(points, paving.outer, pad=-1e-9).any()
    assert paving.method == "section" and paving.counts["inner"] > 0 and paving.counts["outer"] > 0


@pytest.mark.parametrize("options", [CONE, TOOL_DOWN], ids=["cone", "tool down"])
def test_ur5_bracket_holds_the_sampled_volume(ur5, ur5_cone, ur5_down, options):
    # Reference: the admissible samples' tool points binned in (rho, z) cells of 0.02 and turned by Pappus
    # (arcs_volume, an estimate: 3.17 m^3 for the cone and 3.03 for tool down with 4e6 samples at 0.01,
    # BENCHMARKS.md session 16) inside the certified bracket.
    paving = ur5_cone if options is CONE else ur5_down
    q, _, points = admissible_configurations(ur5, 400_000 if options is CONE else 100_000, 5,
                                             approach=(0, 0, -1), cone=options.get("cone"))
    reference = arcs_volume(ur5, q[:, 0], points, 0.02)
    lo, hi = paving.measure_bounds
    assert 0 < lo <= reference <= hi


@pytest.mark.slow          # another industrial arm's symbolic preparation, about 12 s (make test-fast leaves it out)
@pytest.mark.parametrize("options", [CONE, TOOL_DOWN], ids=["cone", "tool down"])
def test_the_ur10_is_paved_as_the_ur5_and_its_samples_agree(options):
    # Reference: the UR10 (tests/data/dh/ur10.json, roboticstoolbox-python's table of Universal Robots' published
    # parameters: the UR5's structure, longer links and offsets) sampled as the UR5 above: no admissible
    # configuration's tool point in an outer box (narrowed by 1e-9).  (A Pappus estimate from this many samples
    # falls below the bracket: 3,867 admissible samples of 200,000 (cone) leave most cells of 0.02 of a 7 m^3 volume
    # empty; benchmarks/bench_orientation.py checks the bracket against 4 x 10^6.)
    ur10 = industrial_arm("ur10")
    paving = reach(ur10, delta=0.4, pose=Pose(**options))
    _, _, points = admissible_configurations(ur10, 100_000 if options is CONE else 30_000, 7,
                                             approach=(0, 0, -1), cone=options.get("cone"))
    assert len(points) > 1000
    assert paving.method == "section" and paving.counts["inner"] > 0 and paving.counts["outer"] > 0
    assert not in_any_box(points, paving.outer, pad=-1e-9).any()
    lo, hi = paving.measure_bounds
    assert 0 < lo < hi


def _fk50(robot):
    T = robot.substitute(robot.fk())
    return (sp.lambdify(robot.q, list(T[:3, 3]), modules="mpmath"),
            sp.lambdify(robot.q, T[:3, :3], modules="mpmath"))


@pytest.mark.parametrize("options", [CONE, TOOL_DOWN], ids=["cone", "tool down"])
def test_points_of_ur5_inner_boxes_are_reached_at_50_digits(ur5, ur5_cone, ur5_down, options):
    from scipy.optimize import least_squares

    # Reference: an inverse kinematics at 50 digits from a float least-squares start: the cone fixes q4, q5, q6
    # and solves the position in q1, q2, q3 (then checks a . (0, 0, -1) >= cos 20 deg at 50 digits); tool down
    # solves position and the three skew entries of Rx(pi)^T R(q) in all six joints (then checks every entry of
    # R(q) - Rx(pi) below 1e-40).  All joints of the UR5 turn fully: every configuration is within its limits.
    paving = ur5_cone if options is CONE else ur5_down
    position, rotation = _fk50(ur5)
    rng = np.random.default_rng(2)
    boxes = paving.inner[rng.choice(len(paving.inner), size=4, replace=False)]
    target = np.diag([1.0, -1.0, -1.0])
    for box in boxes:
        y = rng.uniform(box[:, 0], box[:, 1])
        found = False
        for _ in range(40):
            def residual(q, y=y):
                T = ur5.fk_numeric(q[None])[0]
                r = [T[:3, 3] - y]
                r.append(T[:2, 2] if options is CONE else (T[:3, :3] - target).ravel())
                return np.concatenate(r)
            fit = least_squares(residual, rng.uniform(-math.pi, math.pi, 6), xtol=1e-15, ftol=1e-15, gtol=1e-15)
            if np.abs(fit.fun).max() > 1e-9:
                continue
            with mpmath.workdps(50):
                q0 = [mpmath.mpf(float(v)) for v in fit.x]
                if options is CONE:
                    def f(a, b, c, q0=q0, y=y):
                        return [p - mpmath.mpf(float(t)) for p, t in zip(position(a, b, c, *q0[3:]), y)]
                    sol = list(mpmath.findroot(f, q0[:3], tol=mpmath.mpf(10) ** -45))
                    q = [*sol, *q0[3:]]
                    R = rotation(*q)
                    ok = -R[2, 2] >= mpmath.cos(mpmath.pi / 9)
                else:
                    def f(*q, y=y):
                        R = rotation(*q)
                        M = mpmath.matrix(target.tolist()).T * R
                        return ([p - mpmath.mpf(float(t)) for p, t in zip(position(*q), y)]
                                + [M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]])
                    q = list(mpmath.findroot(f, q0, tol=mpmath.mpf(10) ** -45))
                    R = rotation(*q)
                    ok = max(abs(R[i, j] - target[i, j]) for i in range(3) for j in range(3)) < mpmath.mpf(10) ** -40
                residual50 = max(abs(p - mpmath.mpf(float(t))) for p, t in zip(position(*q), y))
                if ok and residual50 < mpmath.mpf(10) ** -40:
                    found = True
                    break
        assert found, f"no admissible configuration reaches {y} of inner box {box.tolist()}"


def _flipped_arm():
    return offset_arm(wrist=True, base=translation(z=sp.Rational(1, 4)) * rot_x(sp.pi))


@pytest.fixture(scope="module")
def flipped_cone():
    return reach(_flipped_arm(), delta=0.3, pose=Pose(approach=(0, 0, -1), cone=30))


def test_a_base_turned_upside_down_turns_the_cone_with_it(flipped_cone):
    # Reference: a rigid base B = Tz(1/4) Rx(pi) moves the workspace rigidly and turns the approach by B's
    # rotation, so the flipped arm's workspace with the approach within 30 degrees of -z is the plain arm's with
    # the approach within 30 degrees of +z, moved: the same volume.  Both run the section (rho^2, z) of a varying
    # lateral offset, the flipped one through B^-1; their Pappus brackets are the same numbers.
    plain = reach(offset_arm(wrist=True), delta=0.3, pose=Pose(approach=(0, 0, 1), cone=30))
    assert flipped_cone.method == plain.method == "section"
    assert flipped_cone.volume_bounds == plain.volume_bounds
    assert flipped_cone.volume_bounds[0] > 0


def test_flipped_arm_configurations_in_the_cone_never_land_in_an_outer_box(flipped_cone):
    # Reference: configurations within the limits with the approach within 30 degrees of -z, placed by the
    # robot's own fk_numeric (base included): none in an outer box (narrowed by 1e-9); the sampled volume
    # (Pappus on cells of 0.02 about the first axis found from the points) inside the bracket.
    robot = _flipped_arm()
    q, _, points = admissible_configurations(robot, 200_000, 9, approach=(0, 0, -1), cone=30)
    assert len(points) > 1000 and flipped_cone.counts["outer"] > 0 and flipped_cone.measure_bounds[0] > 0
    assert not in_any_box(points, flipped_cone.outer, pad=-1e-9).any()
    lo, hi = flipped_cone.measure_bounds
    assert lo <= arcs_volume(robot, q[:, 0], points, 0.02) <= hi


# ---------------------------------------------------------------- the admissible positions' enclosure
@functools.lru_cache(maxsize=4)
def _exact_model(model):
    """The model's position (arm joints) and ``a . d`` (all joints) as mpmath functions, made once per model."""

    return (sp.lambdify([model.variables[:model.ka]], model.position.expressions, modules="mpmath"),
            sp.lambdify([model.variables], model.lead, modules="mpmath"))


@settings(derandomize=True, max_examples=40, deadline=None)
@given(arm=st.sampled_from(["ur5", "kr16"]), width=st.sampled_from([1.0, 0.5, 0.1, 1e-3, 0.0]),
       at=st.lists(st.sampled_from([0.0, 1.0]) | st.floats(0, 1), min_size=6, max_size=6),
       seed=st.integers(0, 2**16))
@example(arm="kr16", width=1.0, at=[0.5] * 6, seed=0)
@example(arm="ur5", width=0.0, at=[1.0] * 6, seed=1)
def test_every_admissible_position_lies_in_the_enclosure_of_the_admissible_positions(arm, width, at, seed):
    # Reference: the model's own position and approach in floats (the first test above ties them to fk_numeric) at
    # 2000 configurations sampled in an arm box (from the whole limits to a point, at the limits or anywhere
    # within) times the wrist limits, kept when their approach lies 1e-9 inside the 20 degree cone: each position
    # lies in the enclosure of the admissible positions (``o + L (a & C)`` for the tool point at L along the
    # approach from the wrist, intersected with the plain enclosure), which is never empty when one of them is
    # admissible.  Both arms have the offset (the UR5's flange, the KR16's 0.158 m), and it narrows the root.
    model = pose_structure(industrial_arm(arm), (), constraint_from(**CONE)).model
    assert model.offset is not None
    limits = model.position.limits
    span = limits[:, 1] - limits[:, 0]
    centre = limits[:, 0] + np.array(at[:model.ka]) * span
    A = np.stack([np.maximum(limits[:, 0], centre - width * span / 2),
                  np.minimum(limits[:, 1], centre + width * span / 2)], axis=1)[None]
    plain = model.position.enclose(A)
    E = model._admissible(plain, A)[0]
    rng = np.random.default_rng(seed)
    wrist = np.reshape(model.wrist.limits, (-1, 2))
    q = np.concatenate([rng.uniform(A[0, :, 0], A[0, :, 1], size=(2000, model.ka)),
                        rng.uniform(wrist[:, 0], wrist[:, 1], size=(2000, len(wrist)))], axis=1)
    lead = np.broadcast_to(np.asarray(model._lead_float(q.T), dtype=float), (len(q),))
    admissible = lead >= model.bound[1] + 1e-9
    P = model.position.position_float(q[admissible, :model.ka])
    tol = 1e-9 * (1 + np.abs(P))
    assert ((P >= E[:, 0] - tol) & (P <= E[:, 1] + tol)).all(), (E, P.min(axis=0), P.max(axis=0))
    # And exactly, for up to 40 of the sampled configurations (each float joint value read as the exact binary
    # number it is): the approach and the position at 50 digits, no tolerance.
    position, exact_lead = _exact_model(model)
    checked = 0
    with mpmath.workdps(50):
        cos_cone = mpmath.cos(mpmath.pi / 9)                  # the cone of 20 degrees
        for row in q[lead >= model.bound[1] - 1e-6][:40]:
            values = [mpmath.mpf(float(v)) for v in row]
            if exact_lead(values) < cos_cone:
                continue
            checked += 1
            for (lo, hi), p in zip(E, position(values[:model.ka])):
                assert mpmath.mpf(float(lo)) <= p <= mpmath.mpf(float(hi)), (arm, row, lo, p, hi)
    if width == 1.0:
        assert checked > 0                          # the whole limits hold admissible configurations
    if admissible.any():
        assert (E[:, 0] <= E[:, 1]).all()
    if width == 1.0:
        assert ((E[:, 1] - E[:, 0]) < (plain[0, :, 1] - plain[0, :, 0]) - 1e-3).any(), (E, plain)
