"""The roll-pitch wrist reduction of orientation.py (a cone on the approach axis as a cone on the wrist's roll axis,
docs/methods.md section 8): the theorem against sampled wrists and a wrist inverse kinematics, the constant
orientation "tool down" and every direction of a cone (``every=True``) against an inverse kinematics at 50 digits
on the full pose, and the outer boxes against sampled configurations."""

from __future__ import annotations

import functools
import math

import mpmath
import numpy as np
import pytest
import sympy as sp

from workspace_sym import robots
from workspace_sym.interval.image import ImageMap
from workspace_sym.serial import Pose, reach
from workspace_sym.serial.pose import constraint_from, wrist_reduction

PUMA = robots.build("puma560")
T = PUMA.substitute(PUMA.fk())
Z3 = PUMA.substitute(PUMA.fk(3))[:3, 2]
LIMITS = PUMA.joint_limits()
RNG_SEED = 11


def test_puma_wrist_is_a_cap_of_100_degrees_about_the_forearm():
    # Reference: the exact identity a . z3 = cos(theta5) (SymPy) and the reduced cone: 100 deg (theta5's limit)
    # plus the 20 deg cone; every=True: 100 deg for the drops, 80 deg for the inner proof.
    assert sp.simplify(T[:3, 2].dot(Z3) - sp.cos(PUMA.q[4])) == 0
    axis, reduced, proof = wrist_reduction(PUMA, None, constraint_from(approach=(0, 0, -1), cone=20), T)
    assert sp.simplify(sp.Matrix(axis) - Z3) == sp.zeros(3, 1)
    assert reduced.cone == sp.pi * 2 / 3 and proof is None
    _, every, proof = wrist_reduction(PUMA, None, constraint_from(approach=(0, 0, -1), cone=20, every=True), T)
    assert every.cone == sp.pi * 5 / 9 and proof == sp.pi * 4 / 9


def test_the_wrist_reaches_exactly_the_cap():
    # Reference: sampled wrists (every approach lies in the cap: angle(a, z3) <= 100 deg) and a float inverse
    # kinematics of the wrist (Newton on q4, q5 from several starts) for directions drawn inside the cap at
    # 99 deg at most: each is reached within the limits.
    rng = np.random.default_rng(RNG_SEED)
    a_of = sp.lambdify([PUMA.q], list(T[:3, 2]), modules="numpy")
    z_of = sp.lambdify([PUMA.q], list(Z3), modules="numpy")
    q = rng.uniform(LIMITS[:, 0], LIMITS[:, 1], size=(5000, 6))
    a = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (5000,)) for v in a_of(q.T)], axis=1)
    z = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (5000,)) for v in z_of(q.T)], axis=1)
    assert np.all(np.einsum("ij,ij->i", a, z) >= math.cos(math.radians(100)) - 1e-12)
    for arm in q[:12, :3]:
        z0 = np.array(z_of(np.concatenate([arm, [0, 0, 0]])), dtype=float)
        tilt, spin = math.radians(rng.uniform(0, 99)), rng.uniform(0, 2 * math.pi)
        e1 = np.cross(z0, [1.0, 0.0, 0.0] if abs(z0[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        target = math.cos(tilt) * z0 + math.sin(tilt) * (math.cos(spin) * e1 + math.sin(spin) * np.cross(z0, e1))
        # Newton on the two components other than the largest, whose sign then tells the solution from its mirror
        keep = [i for i in range(3) if i != int(np.argmax(np.abs(target)))]
        fixed = {PUMA.q[i]: sp.Float(arm[i], 17) for i in range(3)}
        approach = [e.subs(fixed) for e in T[:3, 2]]
        wrist = ImageMap([approach[i] for i in keep], PUMA.q[3:5], [tuple(r) for r in LIMITS[3:5]], [False, False])
        a_w = sp.lambdify([PUMA.q[3:5]], approach, modules="numpy")
        found = False
        for _ in range(40):
            w0 = rng.uniform(LIMITS[3:5, 0], LIMITS[3:5, 1])
            sol, ok = wrist.newton(target[keep][None], w0[None], steps=40)
            within = np.all((sol[0] >= LIMITS[3:5, 0]) & (sol[0] <= LIMITS[3:5, 1]))
            if ok[0] and within and np.linalg.norm(np.array(a_w(sol[0]), dtype=float) - target) < 1e-9:
                found = True
                break
        assert found, f"direction {target} at {math.degrees(tilt):.1f} deg from z3 not reached at {arm}"


@pytest.fixture(scope="module")
def tool_down():
    # delta 0.2: the proofs checked here (inner points reached, outer boxes hold no sample) do not depend on it;
    # 0.15 paved four times as long for the same checks (2.4 s against 0.7 s)
    return reach(PUMA, delta=0.2, pose=Pose(rpy=(180, 0, 0)))


@functools.cache
def _pose_equations(R):
    """The equations of :func:`_pose_50_digits` for the frame ``R`` (an immutable matrix), built and compiled once
    for all the boxes tried: the skew part of R^T R(q), the arm's position map and the mpmath and float
    functions."""
    M = R.T * T[:3, :3]
    skew = [M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]]
    arm = ImageMap(list(T[:3, 3]), PUMA.q[:3], [tuple(r) for r in LIMITS[:3]], [False] * 3)
    f = sp.lambdify(PUMA.q, list(T[:3, 3]) + skew, modules="mpmath")
    pose = sp.lambdify(PUMA.q, T, modules="mpmath")
    trace = sp.lambdify([PUMA.q], M.trace(), modules="numpy")
    return skew, arm, f, pose, trace


def _pose_50_digits(rng, y, R):
    """A configuration within the limits with position y and frame R (residual < 1e-40), or None: in floats,
    Newton on the position in the arm joints from random starts, then on the skew part of R^T R(q) in the wrist
    joints with the arm fixed (trace > 0 tells R from a half turn about it); then mpmath findroot on all six
    equations at 50 digits."""
    skew, arm, f, pose, trace = _pose_equations(sp.ImmutableMatrix(R))
    q, ok = arm.newton(np.repeat(y[None], 200, axis=0), rng.uniform(LIMITS[:3, 0], LIMITS[:3, 1], size=(200, 3)),
                       steps=40)
    within = ok & np.all((q >= LIMITS[:3, 0]) & (q <= LIMITS[:3, 1]), axis=1)
    for solution in np.unique(np.round(q[within], 9), axis=0):
        fixed = {PUMA.q[i]: sp.Float(solution[i], 17) for i in range(3)}
        wrist = ImageMap([e.subs(fixed) for e in skew], PUMA.q[3:], [tuple(r) for r in LIMITS[3:]], [False] * 3)
        w, good = wrist.newton(np.zeros((60, 3)), rng.uniform(LIMITS[3:, 0], LIMITS[3:, 1], size=(60, 3)), steps=40)
        full = np.concatenate([np.repeat(solution[None], 60, axis=0), w], axis=1)
        good &= np.all((w >= LIMITS[3:, 0]) & (w <= LIMITS[3:, 1]), axis=1)
        good &= np.asarray(trace(full.T), dtype=float) > 0
        for start in full[good][:3]:
            with mpmath.workdps(50):
                goal = [mpmath.mpf(float(v)) for v in y] + [0, 0, 0]
                root = mpmath.findroot(lambda *x, goal=goal: [e - g for e, g in zip(f(*x), goal)],
                                       [mpmath.mpf(v) for v in start])
                x = [root[i] for i in range(6)]
                P = pose(*x)
                error = max(max(abs(P[i, 3] - goal[i]) for i in range(3)),
                            max(abs(P[i, j] - sp.Float(R[i, j], 50)) for i in range(3) for j in range(3)))
                inside = all(mpmath.mpf(LIMITS[i, 0]) <= x[i] <= mpmath.mpf(LIMITS[i, 1]) for i in range(6))
                if error < mpmath.mpf(10) ** -40 and inside:
                    return x
    return None


def test_points_of_tool_down_inner_boxes_are_reached_with_the_frame_at_50_digits(tool_down):
    # Reference: an inverse kinematics of the full pose (position and all nine entries of R = Rx(pi)) at 50
    # digits, within the limits.
    assert tool_down.method == "section" and tool_down.counts["inner"] > 0
    rng = np.random.default_rng(RNG_SEED)
    R = constraint_from(rpy=(180, 0, 0)).rotation
    for box in tool_down.inner[rng.choice(len(tool_down.inner), size=4, replace=False)]:
        y = rng.uniform(box[:, 0], box[:, 1])
        assert _pose_50_digits(rng, y, R) is not None, f"tool down not reached at {y} of {box.tolist()}"


def _points_reaching_down(seed, count=2000):
    """Tool points of sampled arm configurations whose wrist reaches the approach (0, 0, -1) within the limits
    (float Newton on a_x = a_y = 0 in q4, q5, vectorised; a_z = -1 checked)."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(LIMITS[:, 0], LIMITS[:, 1], size=(count, 6))
    g = sp.lambdify([PUMA.q], [T[0, 2], T[1, 2]], modules="numpy")
    J = sp.lambdify([PUMA.q], sp.Matrix([T[0, 2], T[1, 2]]).jacobian(PUMA.q[3:5]).tolist(), modules="numpy")
    for _ in range(30):
        value = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (len(q),)) for v in g(q.T)], axis=1)
        jac = np.moveaxis(np.array([[np.broadcast_to(np.asarray(v, dtype=float), (len(q),)) for v in row]
                                    for row in J(q.T)]), -1, 0)
        with np.errstate(all="ignore"):
            step = np.linalg.solve(jac + 1e-14 * np.eye(2), value[:, :, None])[:, :, 0]
        q[:, 3:5] -= np.where(np.isfinite(step), step, 0.0)
    a_z = np.asarray(sp.lambdify([PUMA.q], T[2, 2], modules="numpy")(q.T), dtype=float)
    within = np.all((q[:, 3:5] >= LIMITS[3:5, 0]) & (q[:, 3:5] <= LIMITS[3:5, 1]), axis=1)
    reached = within & (a_z < -1 + 1e-12)
    return np.stack([np.asarray(v, dtype=float) for v in sp.lambdify([PUMA.q], list(T[:3, 3]),
                                                                      modules="numpy")(q[reached].T)], axis=1)


def _in_some(points, boxes):
    return np.all((points[:, None, :] > boxes[None, :, :, 0] + 1e-9)
                  & (points[:, None, :] < boxes[None, :, :, 1] - 1e-9), axis=2).any(axis=1)


def test_tool_down_outer_boxes_hold_no_configuration_reaching_tool_down(tool_down):
    # Reference: sampled configurations reaching the approach (0, 0, -1) (q6 then turns the frame to R about it):
    # their tool point (the wrist centre, d6 = 0) lies in no outer box.
    points = _points_reaching_down(RNG_SEED + 1)
    assert len(points) > 200
    assert not _in_some(points, tool_down.outer).any()


@pytest.fixture(scope="module")
def every_cone():
    return reach(PUMA, delta=0.25, pose=Pose(approach=(0, 0, -1), cone=20, every=True))


def test_every_direction_drops_only_where_the_axis_is_unreachable(every_cone):
    # Reference: as above; the axis (0, 0, -1) is a direction of the cone, so a position reaching it with some
    # configuration may not be outer.
    points = _points_reaching_down(RNG_SEED + 2)
    assert every_cone.counts["outer"] > 0 and not _in_some(points, every_cone.outer).any()


def test_points_of_every_direction_inner_boxes_reach_the_whole_cone_at_50_digits(every_cone):
    # Reference: for a point of each of two inner boxes and five directions of the cone (its axis and four on
    # its rim, 20 deg from it), an inverse kinematics at 50 digits: position and the approach's two smallest
    # components exact (residual below 1e-40; the third's sign then fixes the unit vector), within the limits.
    assert every_cone.counts["inner"] > 0
    rng = np.random.default_rng(RNG_SEED + 3)
    tilt = math.radians(20 - 1e-6)        # on the rim, inside by more than the rounding of the floats
    directions = [np.array([0.0, 0.0, -1.0])] + [np.array([math.sin(tilt) * math.cos(s), math.sin(tilt) * math.sin(s),
                                                           -math.cos(tilt)]) for s in np.arange(4) * math.pi / 2]
    q5 = PUMA.q[:5]
    arm = ImageMap(list(T[:3, 3]), PUMA.q[:3], [tuple(r) for r in LIMITS[:3]], [False] * 3)
    a_of = sp.lambdify(q5, list(T[:3, 2].subs(PUMA.q[5], 0)), modules="mpmath")
    equations_of = {}                               # each direction's equations, lambdified once for both boxes
    for d in directions:
        keep = [i for i in range(3) if i != int(np.argmax(np.abs(d)))]
        equations = list(T[:3, 3]) + [T[i, 2] for i in keep]
        equations_of[d.tobytes()] = keep, sp.lambdify(q5, [e.subs(PUMA.q[5], 0) for e in equations], modules="mpmath")
    for box in every_cone.inner[rng.choice(len(every_cone.inner), size=2, replace=False)]:
        y = rng.uniform(box[:, 0], box[:, 1])
        q, ok = arm.newton(np.repeat(y[None], 200, axis=0), rng.uniform(LIMITS[:3, 0], LIMITS[:3, 1], (200, 3)),
                           steps=40)
        arms = np.unique(np.round(q[ok & np.all((q >= LIMITS[:3, 0]) & (q <= LIMITS[:3, 1]), axis=1)], 9), axis=0)
        for d in directions:
            keep, f = equations_of[d.tobytes()]
            goal = list(y) + [d[i] for i in keep]
            found = False
            for solution in arms:
                fixed = {PUMA.q[i]: sp.Float(solution[i], 17) for i in range(3)}
                wrist = ImageMap([T[i, 2].subs(fixed) for i in keep], PUMA.q[3:5], [tuple(r) for r in LIMITS[3:5]],
                                 [False, False])
                w, good = wrist.newton(np.repeat(d[keep][None], 40, axis=0),
                                       rng.uniform(LIMITS[3:5, 0], LIMITS[3:5, 1], (40, 2)), steps=40)
                good &= np.all((w >= LIMITS[3:5, 0]) & (w <= LIMITS[3:5, 1]), axis=1)
                a_float = sp.lambdify([PUMA.q[3:5]], [T[i, 2].subs(fixed) for i in range(3)], modules="numpy")
                # not the mirror solution (the third component's sign)
                good &= np.array([np.abs(np.array(a_float(v), dtype=float) - d).max() < 1e-8 for v in w])
                for start in w[good][:2]:
                    with mpmath.workdps(50):
                        target = [mpmath.mpf(float(v)) for v in goal]
                        root = mpmath.findroot(lambda *x, f=f, target=target: [e - g for e, g in zip(f(*x), target)],
                                               [mpmath.mpf(v) for v in np.concatenate([solution, start])])
                        x = [root[i] for i in range(5)]
                        a = a_of(*x)
                        # the kept components exact, the third of d's sign (a is a unit vector)
                        largest = int(np.argmax(np.abs(d)))
                        error = max(abs(e - g) for e, g in zip(f(*x), target))
                        error += 0 if a[largest] * d[largest] > 0 else 1
                        inside = all(mpmath.mpf(LIMITS[i, 0]) <= x[i] <= mpmath.mpf(LIMITS[i, 1]) for i in range(5))
                        if error < mpmath.mpf(10) ** -40 and inside:
                            found = True
                            break
                if found:
                    break
            assert found, f"direction {d} not reached at {y} of inner box {box.tolist()}"
