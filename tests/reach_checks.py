"""Checks shared by the soundness tests of ``reach`` (test_serial_workspace.py, test_reach_section.py,
test_reach_turn.py, test_reach_shoulder.py, test_reach_real_arms.py): inverse kinematics at 50 digits from
sampled seeds, the industrial arms of issue 24."""

from __future__ import annotations

import functools
import itertools
from pathlib import Path

import mpmath
import numpy as np
import rtbdata
import sympy as sp
from scipy.optimize import least_squares

from workspace_sym.kinematics import DHRobot

ROOT = Path(__file__).resolve().parents[1]
KR16 = Path(rtbdata.__file__).parent / "xacro/kuka_description/kuka_kr16/urdf/kr16_2.urdf"


@functools.cache
def industrial_arm(name):
    """The UR5 (``tests/data/dh/ur5.json``) or the KUKA KR16 (rtb-data's URDF, limits from the file), one object
    per process so that the symbolic section is prepared once."""
    if name == "ur5":
        return DHRobot.from_file(ROOT / "tests" / "data" / "dh" / "ur5.json")
    return DHRobot.from_urdf(KR16)


def reached_at_50_digits(model, target, q, pos, tries=6):
    """A configuration within the limits reaching ``target`` at 50 digits (:func:`solve_50_digits`), False if
    none is found.  Started at the sampled configurations ``q`` (positions ``pos``) nearest to ``target``:
    float Newton from each, then, where Newton stops or leaves the limits, least squares bounded by the
    limits (a point near a limit is reached with a joint close to it, where Newton's steps overshoot)."""
    lo, hi = model.limits[:, 0], model.limits[:, 1]
    bounds = (np.where(model.periodic, -np.inf, lo), np.where(model.periodic, np.inf, hi))
    near = np.argsort(np.linalg.norm(pos - target, axis=1))[:tries]
    for seed in q[near]:
        sol, ok = model.newton(np.array([target]), seed[None], steps=30)
        starts = [sol[0]] if ok[0] else []
        fit = least_squares(lambda x: model.position_float(x[None])[0] - target, np.clip(seed, *bounds),
                            jac=lambda x: model.jacobian_float(x[None])[0], bounds=bounds, xtol=1e-15, ftol=1e-15,
                            gtol=1e-15)
        if np.max(np.abs(fit.fun)) < 1e-9:
            starts.append(fit.x)
        for start in starts:
            exact = solve_50_digits(model, target, start, _solving_joints(model, start))
            if exact is not None and all(model.periodic[j] or lo[j] <= float(exact[j]) <= hi[j]
                                         for j in range(model.k)):
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
        exprs = [sp.lambdify(model.variables, e - t, "mpmath") for e, t in zip(model.expressions, target)]

        def f(*u):
            vals = dict(fixed)
            for c, x in zip(cols, u):
                vals[model.variables[c]] = x
            args = [vals[v] for v in model.variables]
            return [g(*args) for g in exprs]
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
