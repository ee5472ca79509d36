"""Arms and checks shared by the soundness tests of ``reach`` (tests/serial/, tests/interval/test_fingerprint.py)
and the benchmarks: inverse kinematics at 50 digits from sampled seeds, the industrial arms of issue 24,
configurations sampled within the limits and placed by the robot's own position, the reference volume of an arm
turned by its first joint from them (the sampled section with its arcs, or Pappus's theorem on its cells), and
small arms whose workspace is known (the offset arm, the swing arm, the shell arm with its exact annulus)."""

from __future__ import annotations

import functools
import itertools
import math
from pathlib import Path

import mpmath
import numpy as np
import rtbdata
import sympy as sp

from paths import DATA
from workspace_sym.interval.verdict import INSIDE
from workspace_sym.kinematics import DHJoint, DHRobot, numeric_function
from workspace_sym.serial import ReachModel
from workspace_sym.serial.section import to_first_frame
from workspace_sym.serial.structure import structure_of
from workspace_sym.transforms import translation

XACRO = Path(rtbdata.__file__).parent / "xacro"
KR16 = XACRO / "kuka_description/kuka_kr16/urdf/kr16_2.urdf"
IIWA = XACRO / "kuka_description/kuka_lbr_iiwa/urdf/lbr_iiwa_14_r820.urdf"


@functools.cache
def industrial_arm(name):
    """The UR5 and the UR10 (``tests/data/dh/ur5.json``, ``ur10.json``), the KUKA KR16 or the LBR iiwa 14 (rtb-data's
    URDFs, limits from the files) or the Panda (``tests/data/dh/panda.json``), one object per process so that the
    symbolic section is prepared once."""
    if name in ("ur5", "ur10", "panda"):
        return DHRobot.from_file(DATA / "dh" / f"{name}.json")
    return DHRobot.from_urdf({"kr16": KR16, "iiwa": IIWA}[name])


def _least_squares():
    """scipy's least_squares, imported when a fit runs (not by every test module that imports this one)."""
    from scipy.optimize import least_squares

    return least_squares


def sampled_positions(robot, n, seed, chunk=100_000):
    """Chunks ``(q, p)`` of ``n`` configurations uniform within the joint limits (``joint_limits``: the file's,
    or a full turn for a joint without limits) and their positions by the robot's own numeric position
    (``DHRobot.numeric(robot.position)``, not the reach model, which drops joints)."""
    rng = np.random.default_rng(seed)
    limits = robot.joint_limits()
    position = robot.numeric(robot.position)
    for start in range(0, n, chunk):
        q = rng.uniform(limits[:, 0], limits[:, 1], size=(min(chunk, n - start), robot.n))
        yield q, position(q)[:, :, 0]


def first_axis(robot, rng):
    """The first joint's axis (a point and a unit direction), found from the points alone: the points of one
    configuration with the first joint turned by 0, 120 and 240 degrees lie on a circle about the axis (their
    centroid its centre, the normal of their plane its direction, oriented so that the first joint turns them
    counterclockwise about it)."""
    q = rng.uniform(-1, 1, size=(1, robot.n)).repeat(3, axis=0)
    q[:, 0] += np.array([0, 2, 4]) * np.pi / 3
    p = robot.fk_numeric(q)[:, :3, 3]
    a = np.cross(p[1] - p[0], p[2] - p[0])
    return p.mean(axis=0), a / np.linalg.norm(a)


def arcs_volume(robot, q1, points, h):
    """Monte Carlo volume of the workspace of an arm turned by its revolute first joint, from the positions
    ``points`` of sampled configurations whose first joint is at ``q1``: in cylindrical coordinates
    ``(rho, z, psi)`` about the first joint's axis (:func:`first_axis`: from the points, not from the reach
    model), each cell of side ``h`` of ``(rho, z)`` hit by a sample turns through the union of the arcs
    ``psi - q1 + [lo, hi]`` of its samples (``[lo, hi]`` the first joint's limits), of measure ``2 pi`` less
    the gaps between consecutive angles beyond ``hi - lo``: the sum of ``(rho_cell + h / 2) h^2`` times that
    measure.  A first joint turning a full circle or more: Pappus's theorem on the sampled section.  An
    estimate, no bound (the hit cells overlap the section's boundary by about half a cell; too few samples
    leave cells, or arcs, unhit)."""
    centre, axis = first_axis(robot, np.random.default_rng(0))
    d = points - centre
    z = d @ axis
    radial = d - z[:, None] * axis
    e1 = np.cross(axis, np.eye(3)[np.argmin(np.abs(axis))])
    e1 /= np.linalg.norm(e1)
    psi = np.remainder(np.arctan2(radial @ np.cross(axis, e1), radial @ e1) - q1, 2 * np.pi)
    rho = np.floor(np.linalg.norm(radial, axis=1) / h).astype(np.int64)
    row = np.floor(z / h).astype(np.int64)
    order = np.lexsort((psi, row, rho))
    rho, row, psi = rho[order], row[order], psi[order]
    new = np.r_[True, (np.diff(rho) != 0) | (np.diff(row) != 0)]
    start = np.flatnonzero(new)
    group = np.cumsum(new) - 1
    gap = np.r_[psi[1:], 0.0] - psi                     # to the next angle of the cell, the last round to the first
    last = np.r_[start[1:], len(psi)] - 1
    gap[last] = psi[start] + 2 * np.pi - psi[last]
    lo, hi = robot.joint_limits()[0]
    lost = np.bincount(group, weights=np.maximum(gap - (hi - lo), 0.0), minlength=len(start))
    return float(np.sum((rho[start] + 0.5) * h ** 3 * (2 * np.pi - lost)))


def sampled_arcs_volume(robot, n, h, seed=0):
    """:func:`arcs_volume` of ``n`` configurations sampled by :func:`sampled_positions`."""
    q, p = map(np.concatenate, zip(*sampled_positions(robot, n, seed)))
    return arcs_volume(robot, q[:, 0], p, h)



def admissible_configurations(robot, n, seed, *, approach=None, cone=None, wrist=(3, 4), chunk=200_000):
    """Configurations uniform within the limits that satisfy a tool constraint, and their rotations and
    positions ``(q, R, p)``: with ``cone`` (degrees), those whose approach axis (``z`` of the tool frame, by the
    robot's own ``fk_numeric``) lies within ``cone`` of ``approach`` (a margin of 1e-9 for float rounding); with
    ``cone=None``, the approach made exactly ``approach`` (a unit axis, to 1e-10) by Newton on the two ``wrist``
    joints (central differences, floats) from each sample, kept when within the limits.  No proof: a sample of
    the admissible set, for the soundness tests and the sampled reference volumes."""
    rng = np.random.default_rng(seed)
    limits = robot.joint_limits()
    d = np.asarray(approach, dtype=float)
    d = d / np.linalg.norm(d)
    # Two unit vectors normal to d: the approach is d when its components along them vanish and a . d > 0.
    e1 = np.cross(d, np.eye(3)[np.argmin(np.abs(d))])
    e1 /= np.linalg.norm(e1)
    normal = np.stack([e1, np.cross(d, e1)])
    out = []
    for start in range(0, n, chunk):
        q = rng.uniform(limits[:, 0], limits[:, 1], size=(min(chunk, n - start), robot.n))
        if cone is not None:
            T = robot.fk_numeric(q)
            ok = T[:, :3, 2] @ d >= np.cos(np.radians(cone)) + 1e-9
        else:
            # Newton's steps only on the rows not yet converged: a row whose components are below 1e-15 (far below
            # the 1e-10 it is kept at) would move by less than that; the others take the same steps as with all rows
            active = np.arange(len(q))
            for _ in range(12):
                g = robot.fk_numeric(q[active])[:, :3, 2] @ normal.T
                moving = np.abs(g).max(axis=1) >= 1e-15
                active, g = active[moving], g[moving]
                if not len(active):
                    break
                qa = q[active]
                J = np.empty((len(qa), 2, 2))
                for c, j in enumerate(wrist):
                    dq = np.zeros(robot.n)
                    dq[j] = 1e-7
                    turned = robot.fk_numeric(qa + dq)[:, :3, 2] - robot.fk_numeric(qa - dq)[:, :3, 2]
                    J[:, :, c] = turned @ normal.T / 2e-7
                with np.errstate(all="ignore"):
                    step = np.linalg.solve(J + 1e-12 * np.eye(2), g[:, :, None])[:, :, 0]
                qa[:, list(wrist)] -= np.where(np.isfinite(step), step, 0.0)
                q[active] = qa
            T = robot.fk_numeric(q)
            within = ((q >= limits[:, 0]) & (q <= limits[:, 1])).all(axis=1)
            ok = within & (np.abs(T[:, :3, 2] @ normal.T).max(axis=1) < 1e-10) & (T[:, :3, 2] @ d > 0)
        out.append((q[ok], T[ok, :3, :3], T[ok, :3, 3]))
    return tuple(np.concatenate(parts) for parts in zip(*out))


def paved_alike_twice(robot, delta, stop):
    """``reach(robot, delta, stop)`` run twice, asserting both runs decide the same boxes (a budget of boxes, not of
    seconds, stops it at the same cells on every run); the first paving."""
    from workspace_sym.serial import reach

    runs = [reach(robot, delta=delta, stop=stop) for _ in range(2)]
    for kind in ("inner", "boundary", "outer"):
        assert np.array_equal(getattr(runs[0], kind), getattr(runs[1], kind)), kind
    return runs[0]


def in_any_box(points, boxes, pad=0.0):
    """Mask of the points lying in some closed box widened by ``pad`` (narrowed if negative), for many points and
    boxes: the points sorted along x, each box looks only at those within its x range."""
    order = np.argsort(points[:, 0])
    xs = points[order, 0]
    hit = np.zeros(len(points), dtype=bool)
    for box in boxes:
        lo, hi = box[:, 0] - pad, box[:, 1] + pad
        a, b = np.searchsorted(xs, [lo[0], hi[0]])
        rows = order[a:b]
        hit[rows] |= ((points[rows] >= lo) & (points[rows] <= hi)).all(axis=1)
    return hit


def reached_at_50_digits(model, target, q, pos, tries=6):
    """A configuration within the limits reaching ``target`` at 50 digits (:func:`solve_50_digits`), False if
    none is found.  Started at the sampled configurations ``q`` (positions ``pos``) nearest to ``target``:
    float Newton from each, then, where Newton stops or leaves the limits, least squares bounded by the
    limits (a point near a limit is reached with a joint close to it, where Newton's steps overshoot)."""
    lo, hi = model.limits[:, 0], model.limits[:, 1]
    bounds = (np.where(model.periodic, -np.inf, lo), np.where(model.periodic, np.inf, hi))
    near = np.argsort(np.linalg.norm(pos - target, axis=1))[:tries]

    def reaches(start):
        exact = solve_50_digits(model, target, start, _solving_joints(model, start))
        return exact is not None and all(model.periodic[j] or lo[j] <= float(exact[j]) <= hi[j]
                                         for j in range(model.k))

    for seed in q[near]:
        sol, ok = model.newton(np.array([target]), seed[None], steps=30)
        if ok[0] and reaches(sol[0]):
            return True
        # Least squares only where Newton's start did not give the answer (it is most of the time of a check).
        fit = _least_squares()(lambda x: model.position_float(x[None])[0] - target, np.clip(seed, *bounds),
                            jac=lambda x: model.jacobian_float(x[None])[0], bounds=bounds, xtol=1e-15, ftol=1e-15,
                            gtol=1e-15)
        if np.max(np.abs(fit.fun)) < 1e-9 and reaches(fit.x):
            return True
    return False


def _solving_joints(model, q):
    """The ``m`` joints the 50-digit solve moves: the best conditioned columns of the Jacobian at ``q``, among
    joints clear of their limits where there are enough of those."""
    J = model.jacobian_float(q[None])[0]
    lo, hi = model.limits[:, 0], model.limits[:, 1]
    clear = model.periodic | ((q - lo > 1e-6) & (hi - q > 1e-6))
    choices = list(itertools.combinations(range(model.k), model.m))
    return list(max(choices, key=lambda c: (all(clear[list(c)]), abs(np.linalg.det(J[:, list(c)])))))


def solve_50_digits(model, target, q0, cols):
    """Newton at 50 digits on the joints ``cols`` (the others fixed at q0): a configuration reaching
    ``target`` exactly to 1e-40, or None."""
    with mpmath.workdps(50):
        fixed = {v: mpmath.mpf(float(x)) for v, x in zip(model.variables, q0)}
        aim = [mpmath.mpf(float(t)) for t in target]          # the float target, exactly
        exprs = _mpmath_position(model)

        def f(*u):
            vals = dict(fixed)
            for c, x in zip(cols, u):
                vals[model.variables[c]] = x
            args = [vals[v] for v in model.variables]
            return [g(*args) - t for g, t in zip(exprs, aim)]
        try:
            u = mpmath.findroot(f, [fixed[model.variables[c]] for c in cols], tol=mpmath.mpf(10) ** -45)
        except (ValueError, ZeroDivisionError):
            return None
        u = [u] if model.m == 1 else list(u)
        q = [fixed[v] for v in model.variables]
        for c, x in zip(cols, u):
            q[c] = x
        if max(abs(r) for r in f(*u)) > mpmath.mpf(10) ** -40:
            return None
        return q


@functools.lru_cache(maxsize=32)
def _mpmath_position(model):
    """The model's position expressions lambdified for mpmath, once per model (the models are compared by
    identity): lambdify took as long as the 50-digit solve itself."""
    return [sp.lambdify(model.variables, e, "mpmath") for e in model.expressions]


# ---------------------------------------------------------------------- small arms with known workspaces
R = sp.Rational
THIRD = R(2, 5)


IIWA_LIKE = (-R(17, 18) * sp.pi, R(17, 18) * sp.pi)          # +-170 deg, the LBR iiwa's first joint


def offset_arm(*, base=None, wrist=False, first=None, a3=THIRD):
    """A spatial arm whose third link swings out of the arm's plane (alpha_2 = 90 deg): its lateral offset
    ``c`` varies with theta2 and theta3; ``wrist`` adds a fourth joint (a three-joint section)."""
    joints = [DHJoint.revolute(1, d=R(3, 10), alpha=sp.pi / 2, limits=first),
              DHJoint.revolute(2, a=R(1, 2), alpha=sp.pi / 2),
              DHJoint.revolute(3, a=a3, d=R(1, 10), alpha=sp.pi / 2 if wrist else 0)]
    if wrist:
        joints.append(DHJoint.revolute(4, a=R(1, 10)))
    return DHRobot(joints, name="offset arm", base=base)


def swing_arm(first=IIWA_LIKE):
    """Three links swinging out of the first joint's plane (each alpha 90 deg, no joint offsets), the first joint
    limited: its section, moved by three joints, is reached in the plane of the first link (c = 0) except near
    the shoulder."""
    return DHRobot([DHJoint.revolute(1, d=R(3, 10), alpha=sp.pi / 2, limits=first),
                    DHJoint.revolute(2, a=R(1, 2), alpha=sp.pi / 2),
                    DHJoint.revolute(3, a=R(2, 5), alpha=sp.pi / 2),
                    DHJoint.revolute(4, a=R(1, 5))], name="swing arm")


def shell_arm():
    """A first joint turning three parallel revolute joints in a vertical plane, behind a shifted base (the
    turned-section path): the section is the planar arm's annulus folded onto rho >= 0, so the workspace is
    the spherical shell of radii ``2 max a_i - sum a_i = 3/10`` and ``sum a_i = 7/10`` about the shoulder."""
    lengths = (R(1, 2), R(1, 10), R(1, 10))
    joints = [DHJoint.revolute(1, alpha=sp.pi / 2)] + [DHJoint.revolute(i + 2, a=a) for i, a in enumerate(lengths)]
    return DHRobot(joints, name="shell arm", base=translation(R(1, 10), R(-1, 5), R(3, 10)))


def agrees_with_shell(r0, r1, z0, z1, kind):
    """Exact rationals: a rectangle ``[r0, r1] x [z0, z1]`` of ``(rho, z)`` declared inner lies in the shell
    arm's annulus (nearest point to the shoulder at least ``r``, farthest corner at most ``R``), one declared
    outer misses it."""
    r, big = R(3, 10), R(7, 10)
    near = max(r0, 0) ** 2 + (0 if z0 <= 0 <= z1 else min(abs(z0), abs(z1))) ** 2
    far = max(r0 ** 2, r1 ** 2) + max(z0 ** 2, z1 ** 2)
    if kind == INSIDE:
        return r0 >= 0 and near >= r ** 2 and far <= big ** 2
    return r1 < 0 or near > big ** 2 or far < r ** 2


def pappus_volume(robot, n=1_000_000, h=0.004, seed=0):
    """Volume of the solid turned from the section sampled at ``n`` configurations: cells of side ``h`` of
    (rho, z) hit by a sample, each turned through a full circle (2 pi rho_cell h^2)."""
    model = ReachModel(robot)
    rng = np.random.default_rng(seed)
    q = model.random_configurations(n, rng)
    p = model.position_float(q)
    plan = structure_of(robot, ())
    F = to_first_frame(plan.inverse, np.repeat(p[:, :, None], 2, axis=2))[:, :, 0]
    rho, z = np.hypot(F[:, 0], F[:, 1]), F[:, 2]
    cells = np.unique(np.stack([np.floor(rho / h), np.floor(z / h)], axis=1).astype(np.int64), axis=0)
    return float(np.sum(2 * np.pi * (cells[:, 0] + 0.5) * h * h * h))


def check_sampled_and_reached(robot, paving, *, samples: int, seed: int, chunk: int = 512):
    """Soundness against sampling and inverse kinematics: ``samples`` configurations within the limits never
    land in an outer box, and a random point of four random inner boxes is reached at 50 digits."""
    model = ReachModel(robot)
    rng = np.random.default_rng(seed)
    q = model.random_configurations(samples, rng)
    pos = model.position_float(q)
    for k in range(0, len(paving.outer), chunk):
        assert not in_any_box(pos, paving.outer[k:k + chunk]).any()
    for box in paving.inner[rng.integers(len(paving.inner), size=4)]:
        assert reached_at_50_digits(model, rng.uniform(box[:, 0], box[:, 1]), q, pos), box


@functools.lru_cache(maxsize=16)
def _wrist_arm_functions(robot):
    """The tool point and the approach of ``robot`` (mpmath), and the tool point, its Jacobian and the approach
    (numpy), lambdified once per robot object (lambdify took a third of a 50-digit check)."""
    T = robot.substitute(robot.fk())
    q = robot.q
    return (sp.lambdify(q, list(T[:3, 3]), modules="mpmath"), sp.lambdify(q, list(T[:3, 2]), modules="mpmath"),
            sp.lambdify(q, list(T[:3, 3]), modules="numpy"), sp.lambdify(q, T[:3, 3].jacobian(q), modules="numpy"),
            sp.lambdify(q, list(T[:3, 2]), modules="numpy"))


@functools.lru_cache(maxsize=16)
def _cone_arm_functions(robot):
    """The tool point and the approach of ``robot`` (mpmath), both together and the tool point's Jacobian (numpy),
    lambdified once per robot object."""
    T = robot.substitute(robot.fk())
    q = robot.q
    return (sp.lambdify(q, list(T[:3, 3]), modules="mpmath"), sp.lambdify(q, list(T[:3, 2]), modules="mpmath"),
            sp.lambdify([q], list(T[:3, 3]) + list(T[:3, 2]), modules="numpy"),
            sp.lambdify(q, T[:3, 3].jacobian(q), modules="numpy"))


@functools.lru_cache(maxsize=16)
def _pose_arm_functions(robot, R):
    """For the tool frame ``R`` (an immutable matrix): the tool point and three entries of ``R^T R(q) - I`` and the
    frame (mpmath), the tool point and the frame and the conditions' Jacobian (numpy), once per robot object and
    frame."""
    T = robot.substitute(robot.fk())
    q = robot.q
    err = R.T * T[:3, :3]
    conditions = list(T[:3, 3]) + [err[2, 1], err[0, 2], err[1, 0]]
    return (sp.lambdify(q, conditions, modules="mpmath"), sp.lambdify(q, list(T[:3, :3]), modules="mpmath"),
            sp.lambdify([q], list(T[:3, 3]) + list(T[:3, :3]), modules="numpy"),
            sp.lambdify(q, sp.Matrix(conditions).jacobian(q), modules="numpy"))


def wrist_arm_in_cone_at_50_digits(robot, target, direction, cone_deg, rng, starts=300):
    """A configuration of an arm whose last three joints do not move the tool point (the Puma 560) putting the
    tool point at ``target`` with the approach axis (z of the tool frame) within ``cone_deg`` of ``direction``, at
    50 digits and within the limits; None if none is found.  Float search: the position by least squares in the
    first three joints from random starts, then a wrist among random ones whose approach is in the cone (a
    margin of 1e-6); then mpmath ``findroot`` on the position in the three arm joints at 50 digits, the wrist
    kept, and every condition checked again at 50 digits."""
    position, approach, p_float, j_float, a_float = _wrist_arm_functions(robot)
    d = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    cos_c = np.cos(np.radians(cone_deg))
    lim = robot.joint_limits()
    for _ in range(starts):
        q0 = rng.uniform(lim[:, 0], lim[:, 1])
        for _ in range(30):
            J = np.array(j_float(*q0), dtype=float)
            q0 = np.clip(q0 - np.linalg.lstsq(J, np.array(p_float(*q0), dtype=float) - target, rcond=None)[0],
                         lim[:, 0], lim[:, 1])
        if np.linalg.norm(np.array(p_float(*q0), dtype=float) - target) > 1e-8:
            continue
        wrists = rng.uniform(lim[3:, 0], lim[3:, 1], size=(2000, 3))
        a = np.stack([np.broadcast_to(np.asarray(c, dtype=float), (2000,))
                      for c in a_float(*q0[:3], *wrists.T)], 1)
        good = np.nonzero(a @ d >= cos_c + 1e-6)[0]
        if not len(good):
            continue
        q0[3:] = wrists[good[0]]
        with mpmath.workdps(50):
            wrist = [mpmath.mpf(float(v)) for v in q0[3:]]
            goal = [mpmath.mpf(float(v)) for v in target]
            try:
                arm = mpmath.findroot(lambda *x, w=wrist, y=goal: [p - g for p, g in zip(position(*x, *w), y)],
                                      [mpmath.mpf(float(v)) for v in q0[:3]])
            except (ValueError, ZeroDivisionError):
                continue
            full = [arm[i] for i in range(3)] + wrist
            if _holds_at_50_digits(position, approach, full, goal, lim, direction, cone_deg):
                return full
    return None


def arm_in_cone_at_50_digits(robot, target, direction, cone_deg, rng, starts=60, *, anywhere=False):
    """A configuration of any arm of three joints or more putting the tool point at ``target`` with the approach
    axis within ``cone_deg`` of ``direction``, at 50 digits and within the limits; None if none is found.  Float search:
    least squares on the position and on the approach aimed at ``direction`` (scipy, within the limits) from
    random starts (``anywhere``: the approach only kept within the cone less 0.2 deg, by a penalty that vanishes
    inside it, for points reached only near the rim); then mpmath ``findroot`` on the position in the three joints
    of the best-conditioned minor, the others kept, and every condition checked again at 50 digits."""
    position, approach, pose_float, j_float = _cone_arm_functions(robot)
    d = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    lim = robot.joint_limits()
    inner = np.stack([lim[:, 0] + 1e-9, lim[:, 1] - 1e-9], 1)
    rim = np.cos(np.radians(max(cone_deg - 0.2, 0.0)))

    def aim(a):
        return [3.0 * max(0.0, rim - float(a @ d))] if anywhere else 0.3 * (a - d)

    for _ in range(starts):
        q0 = rng.uniform(inner[:, 0], inner[:, 1])
        fit = _least_squares()(lambda x: np.r_[np.array(pose_float(x)[:3], dtype=float) - target,
                                            aim(np.array(pose_float(x)[3:], dtype=float))],
                            q0, bounds=(inner[:, 0], inner[:, 1]), xtol=1e-15, ftol=1e-15, gtol=1e-15)
        x = fit.x
        if np.linalg.norm(np.array(pose_float(x)[:3], dtype=float) - target) > 1e-8:
            continue
        with mpmath.workdps(50):
            goal = [mpmath.mpf(float(v)) for v in target]
            full = _refined_at_50_digits(position, goal, x, np.array(j_float(*x), dtype=float))
            if full is not None and _holds_at_50_digits(position, approach, full, goal, lim, direction, cone_deg):
                return full
    return None


def _refined_at_50_digits(equations, goal, x, J):
    """``equations(*q) = goal`` solved by mpmath ``findroot`` at the working precision in the joints of the
    best-conditioned square minor of the float Jacobian ``J`` at ``x``, the others kept at ``x``; None when it
    fails."""
    cols = max(itertools.combinations(range(len(x)), len(goal)), key=lambda c: abs(np.linalg.det(J[:, list(c)])))
    fixed = [mpmath.mpf(float(v)) for v in x]

    def residual(*y):
        full = list(fixed)
        for i, c in enumerate(cols):
            full[c] = y[i]
        return [e - g for e, g in zip(equations(*full), goal)]

    try:
        sol = mpmath.findroot(residual, [fixed[c] for c in cols])
    except (ValueError, ZeroDivisionError):
        return None
    full = list(fixed)
    for i, c in enumerate(cols):
        full[c] = sol[i]
    return full


def _holds_at_50_digits(position, approach, full, goal, lim, direction, cone_deg):
    """At the working precision (50 digits): ``full`` puts the tool point within 1e-40 of ``goal``, lies within the
    limits, and turns the approach within ``cone_deg`` of ``direction``."""
    residual = max(abs(p - g) for p, g in zip(position(*full), goal))
    within = all(mpmath.mpf(float(lim[i, 0])) <= full[i] <= mpmath.mpf(float(lim[i, 1])) for i in range(len(full)))
    dd = [mpmath.mpf(float(v)) for v in direction]
    dot = sum(x * y for x, y in zip(approach(*full), dd))
    return residual < mpmath.mpf(10) ** -40 and within and dot >= mpmath.sqrt(sum(v * v for v in dd)) * mpmath.cos(
        mpmath.radians(mpmath.mpf(float(cone_deg))))


def oriented_configurations(robot, n, seed, rotation, *, wrist=(4, 5)):
    """Configurations within the limits whose tool frame is exactly ``rotation`` (a 3 x 3 array whose third column
    is vertical), with their tool points ``(q, p)``: :func:`admissible_configurations` points the approach (Newton on
    the two ``wrist`` joints), then the last joint, which spins the tool about its approach, is turned to the
    frame's spin and kept when within its limits (the rotation checked to 1e-9 by the robot's own ``fk_numeric``).
    No proof: a sample of the constant-orientation workspace, for the soundness tests and reference volumes."""
    R = np.asarray(rotation, dtype=float)
    q, Rs, _ = admissible_configurations(robot, n, seed, approach=R[:, 2], cone=None, wrist=wrist)
    M = np.einsum("ji,njk->nik", R, Rs)                   # R^T R(q): a turn about z by delta
    delta = np.arctan2(M[:, 1, 0], M[:, 0, 0])
    lo, hi = robot.joint_limits()[-1]
    for sign in (1.0, -1.0):                               # the last joint's sense about the approach
        turned = q.copy()
        turned[:, -1] = np.remainder(q[:, -1] - sign * delta - lo, 2 * np.pi) + lo
        T = robot.fk_numeric(turned)
        exact = np.abs(T[:, :3, :3] - R).max(axis=(1, 2)) < 1e-9
        if exact.mean() > 0.5:
            keep = exact & (turned[:, -1] <= hi)
            return turned[keep], T[keep, :3, 3]
    raise AssertionError("the last joint does not spin the tool about its approach")


def arm_in_pose_at_50_digits(robot, target, rotation, rng, starts=40):
    """A configuration of a robot of six joints or more putting the tool point at ``target`` with the tool frame
    exactly ``rotation``, at 50 digits and within the limits; None if none is found.  Float search: least squares on
    the position and the frame (scipy, within the limits) from random starts; then mpmath ``findroot`` on the
    position and three entries of ``rotation^T R(q) - I`` in the six joints of the best-conditioned minor, the
    others kept, and the whole frame, the position and the limits checked again at 50 digits."""
    R = sp.ImmutableMatrix(rotation)
    equations, frame, pose_float, j_float = _pose_arm_functions(robot, R)
    Rf = np.array(R, dtype=float)
    lim = robot.joint_limits()
    inner = np.stack([lim[:, 0] + 1e-9, lim[:, 1] - 1e-9], 1)
    target = np.asarray(target, dtype=float)
    for _ in range(starts):
        q0 = rng.uniform(inner[:, 0], inner[:, 1])
        fit = _least_squares()(lambda x: np.r_[np.array(pose_float(x)[:3], dtype=float) - target,
                                            0.3 * (np.array(pose_float(x)[3:], dtype=float) - Rf.ravel())],
                            q0, bounds=(inner[:, 0], inner[:, 1]), xtol=1e-15, ftol=1e-15, gtol=1e-15)
        x = fit.x
        if np.abs(fit.fun).max() > 1e-8:
            continue
        with mpmath.workdps(50):
            goal = [mpmath.mpf(float(v)) for v in target] + [mpmath.mpf(0)] * 3
            full = _refined_at_50_digits(equations, goal, x, np.array(j_float(*x), dtype=float))
            if full is None:
                continue
            tiny = mpmath.mpf(10) ** -40
            position = equations(*full)[:3]
            within = all(mpmath.mpf(float(lim[i, 0])) <= full[i] <= mpmath.mpf(float(lim[i, 1]))
                         for i in range(len(full)))
            exact = all(abs(e - mpmath.mpf(str(sp.N(r, 60)))) < tiny for e, r in zip(frame(*full), R))
            if within and exact and max(abs(p - g) for p, g in zip(position, goal[:3])) < tiny:
                return full
    return None


class FreeRun:
    """A run of :func:`~workspace_sym.serial.turn.pave_limited` without a time limit nor a count: every stage to its
    end."""

    time_limit, seconds = None, 0.0

    @staticmethod
    def stop_reason(count):
        return ""


def piece_point(grid, pieces, k, a, b, rng, arc):
    """A point drawn uniformly in piece ``(a, b)`` of a limited turn's section grid (``pieces`` the ``(D, n0 F,
    n1 F)`` masks of :func:`~workspace_sym.serial.turn.prove_directions`), turned to a polar angle drawn in ``arc``
    (a pair of floats) plus direction ``k``'s angle ``k 2 pi / D``: a point the proof at that direction covers
    when ``arc`` lies within the first joint's range."""
    F = pieces.shape[-1] // grid.shape[1]
    cell = grid.cells(np.array([[a // F, b // F]]))[0]
    size = (cell[:, 1] - cell[:, 0]) / F
    low = cell[:, 0] + size * np.array([a % F, b % F])
    rho, z = rng.uniform(low, low + size)
    angle = rng.uniform(arc[0], arc[1]) + k * 2 * np.pi / len(pieces)
    return np.array([rho * np.cos(angle), rho * np.sin(angle), z])


def paved_roots(roots, width, tuning, boxes):
    """Several limited turns' sections paved on one grid holding all their enclosures, as ``FlangePlan`` paves a
    wrist's solutions, without a time limit and with a budget of ``boxes`` each: ``(grid, parts)``, ``parts`` the
    ``(limited, full classes, pieces, sectors)`` that :func:`~workspace_sym.serial.turn.roots_volume` reads."""
    from workspace_sym.serial.turn import pave_limited

    enclosures = [limited.plan.section.enclose(limited.plan.section.limits[None])[0] for limited in roots]
    box = np.stack([np.min([e[:, 0] for e in enclosures], axis=0), np.max([e[:, 1] for e in enclosures], axis=0)],
                   axis=1)
    parts, grid = [], None
    for limited in roots:
        state: dict = {}
        grid, full, pieces, _, _ = pave_limited(limited, width, FreeRun(), tuning=tuning, state=state, box=box,
                                                boxes=boxes)
        parts.append((limited, full, pieces, state["sectors"]))
    return grid, parts


def on_cone(d, cone_deg, t_frac, phi):
    """The unit vector at angle ``t_frac * cone_deg`` degrees from ``d``, turned by ``phi`` about it (floats)."""
    d = np.asarray(d, dtype=float) / np.linalg.norm(d)
    u = np.cross(d, [0.3, -0.7, 0.2])
    if np.linalg.norm(u) < 1e-6:
        u = np.cross(d, [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(d, u)
    t = math.radians(cone_deg) * t_frac
    return math.cos(t) * d + math.sin(t) * (math.cos(phi) * u + math.sin(phi) * v)


def sampled_pairs(robot, edges, directions, cone, q):
    """The reach-map pairs (cell index, direction) that the configurations ``q`` reach, their approach at least
    1e-9 inside the cone (a sample on the rim in floats may be outside it exactly)."""
    T = numeric_function(robot.fk(), robot.q)(q)
    p, a = T[:, :3, 3], T[:, :3, 2]
    index = np.stack([np.searchsorted(e, p[:, k], side="right") - 1 for k, e in enumerate(edges)], 1)
    inside = ((index >= 0) & (index < np.array([len(e) - 1 for e in edges]))).all(axis=1)
    hits = (a @ directions.T) >= math.cos(math.radians(cone)) + 1e-9
    rows, ks = np.nonzero(hits & inside[:, None])
    return index[rows], ks
