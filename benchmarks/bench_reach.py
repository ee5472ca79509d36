"""Issue 14 benchmark: certified position workspaces of serial arms (``workspace_sym.serial_workspace``).

For each robot and delta, ours (proved inner / boundary / outer boxes and the measure
bracket) beside two references computed in the same run: the exact measure where one is
known (the 2R arm with full joint ranges reaches an annulus), and what sampling gives, the
measure of the grid cells of side delta / sqrt(n) hit by 10^6 random configurations within
the limits (an estimate with no guarantee either way, the usual scatter-plot answer).

Run: python benchmarks/bench_reach.py
"""

import datetime
import time

import numpy as np
import sympy as sp

from _common import machine
from workspace_sym import robots
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial_workspace import ReachModel, reach

CASES = [
    ("2R, l = (1, 1/2), full range", DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=sp.Rational(1, 2))]),
     (0.1, 0.03), float(sp.pi * ((sp.Rational(3, 2)) ** 2 - sp.Rational(1, 2) ** 2))),
    ("planar 3R (catalog)", robots.build("planar-3r"), (0.2, 0.1), None),
    ("SCARA (catalog)", robots.build("scara"), (0.1, 0.05), None),
    ("Puma 560, 3 position joints", robots.build("puma560"), (0.3, 0.2), None),
]


def sampled_measure(model: ReachModel, delta: float, n: int = 1_000_000, seed: int = 0):
    rng = np.random.default_rng(seed)
    start = time.perf_counter()
    q = rng.uniform(model.limits[:, 0], model.limits[:, 1], size=(n, model.k))
    p = model.position_float(q)
    cell = delta / np.sqrt(model.m)
    cells = np.unique(np.floor(p / cell).astype(np.int64), axis=0)
    return len(cells) * cell**model.m, time.perf_counter() - start


def main():
    print(f"# reach benchmark, {datetime.date.today()}, {machine()}")
    print("| robot | delta | seconds | inner / boundary / outer boxes | measure bracket | exact | sampled (s) |")
    print("|---|---|---|---|---|---|---|")
    for name, robot, deltas, exact in CASES:
        model = ReachModel(robot)
        for delta in deltas:
            start = time.perf_counter()
            p = reach(robot, delta=delta, time_limit=600)
            seconds = time.perf_counter() - start
            lo, hi = p.measure_bounds
            sampled, t_s = sampled_measure(model, delta)
            exact_text = f"{exact:.4f}" if exact is not None else "—"
            done = "" if p.complete else f" ({p.stop_reason})"
            print(f"| {name} | {delta} | {seconds:.1f}{done} | {len(p.inner)} / {len(p.boundary)} / {len(p.outer)} "
                  f"| [{lo:.4f}, {hi:.4f}] | {exact_text} | {sampled:.4f} ({t_s:.1f}) |")


if __name__ == "__main__":
    main()
