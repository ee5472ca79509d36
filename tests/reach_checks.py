"""Checks shared by the soundness tests of ``reach`` (test_reach_section.py, test_reach_turn.py,
test_reach_shoulder.py, test_reach_real_arms.py): points in boxes and the 50-digit solve (those of
test_serial_workspace.py), inverse kinematics at 50 digits from sampled seeds, the industrial arms of issue 24."""

from __future__ import annotations

import functools
import itertools
from pathlib import Path

import numpy as np
import rtbdata
from test_serial_workspace import _solve_50_digits as solve_50_digits

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
    """A configuration within the limits reaching ``target`` at 50 digits (mpmath ``findroot``), from float
    Newton started at the sampled configurations ``q`` (positions ``pos``) nearest to it; False if none."""
    near = np.argsort(np.linalg.norm(pos - target, axis=1))[:tries]
    for seed in q[near]:
        sol, ok = model.newton(np.array([target]), seed[None], steps=30)
        if not ok[0]:
            continue
        J = model.jacobian_float(sol)[0]
        cols = max(itertools.combinations(range(model.k), model.m),
                   key=lambda c: abs(np.linalg.det(J[:, list(c)])))
        exact = solve_50_digits(model, target, sol[0], list(cols))
        lo, hi = model.limits[:, 0], model.limits[:, 1]
        if exact is not None and all(model.periodic[j] or lo[j] <= float(exact[j]) <= hi[j]
                                     for j in range(model.k)):
            return True
    return False
