"""Issue 14 benchmark: certified position workspaces of serial arms (``workspace_sym.serial_workspace``).

For each robot and delta: seconds, proved inner / boundary / outer boxes, the measure
bracket and its width relative to the reference, beside the references computed in the
same run:

* exact: the 2R arm with full joint ranges reaches an annulus (area 2 pi); the human arm of
  Bastien (2018), Table 1 case iii, as a DH robot has the area of Bastien's exact boundary
  (``PlanarChain``);
* exact: the SCARA's volume, the area of its (x, y) region (Bastien's method) times its stroke;
* independent: the glass-handling arm's volume, its section by Bastien's method turned
  through the theta1 range (``tests/serial/test_serial_workspace.py::_glass_section_volume``);
* sampled: the measure of the grid cells of side delta / sqrt(n) hit by 10^6 random
  configurations within the limits (no bound either way: the usual scatter-plot answer).

For the spatial robots the time is split into the critical paving of the (u, v) section and
the classification of the (x, y, z) boxes.

Run: python benchmarks/bench_reach.py [--quick]
"""

import datetime
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp

import workspace_sym as ws
from _common import machine
from workspace_sym import StopAt, robots
from workspace_sym.interval.image import critical_paving
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial import ReachModel, reach, resolve_method
from workspace_sym.serial.model import cell_width
from workspace_sym.serial.structure import structure_of
from workspace_sym.serial.tuning import DEFAULT

TESTS = Path(__file__).resolve().parents[1] / "tests"
sys.path[:0] = [str(TESTS / "helpers"), str(TESTS / "serial")]     # the tests' helpers and the glass arm's reference
from test_serial_workspace import _glass_section_volume, human_arm  # noqa: E402

HUMAN = ([0.186, 0.146, 0.108], [-60, 0, -10], [120, 130, 25])      # Bastien 2018, Table 1 case iii


def cases(quick: bool):
    two_r = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=sp.Rational(1, 2))], name="2R")
    human_area = ws.PlanarChain(*HUMAN).boundary().area
    glass_volume = _glass_section_volume(600, 1200)
    # the SCARA: its (x, y) region, a planar 2R chain (Bastien's exact area), times the 0.21 m stroke of d3
    scara_volume = ws.PlanarChain([0.325, 0.275], [-50, -88], [50, 88]).boundary().area * 0.21
    return [
        ("2R, l = (1, 1/2), full range", two_r, (0.1, 0.03), 2 * np.pi, "exact"),
        ("human arm (Bastien Table 1 iii) as DH", human_arm(), (0.004, 0.002, 0.001, 0.0008), human_area, "exact"),
        ("glass-handling arm", robots.build("glass-handling"),
         (0.025, 0.0125) if quick else (0.025, 0.0125, 0.008, 0.005), glass_volume, "independent"),
        ("Puma 560", robots.build("puma560"), (0.05, 0.02), None, ""),
        ("SCARA", robots.build("scara"), (0.05, 0.02, 0.01), scara_volume, "exact"),
    ]


def sampled_measure(model: ReachModel, delta: float, n: int = 1_000_000, seed: int = 0):
    rng = np.random.default_rng(seed)
    q = rng.uniform(model.limits[:, 0], model.limits[:, 1], size=(n, model.k))
    p = model.position_float(q)
    cell = delta / np.sqrt(model.m)
    cells = np.unique(np.floor(p / cell).astype(np.int64), axis=0)
    return len(cells) * cell**model.m


def section_seconds(robot, delta):
    revolved = structure_of(robot, ())
    start = time.perf_counter()
    critical_paving(revolved.section, DEFAULT.section_ratio * cell_width(delta, "diameter", 3))
    return time.perf_counter() - start


def main():
    quick = "--quick" in sys.argv
    print(f"# reach benchmark, {datetime.date.today()}, {machine()}")
    print("| robot | method | delta | seconds | inner / boundary / outer boxes | measure bracket | (hi - lo) / ref "
          "| reference | sampled |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, robot, deltas, ref, kind in cases(quick):
        model = ReachModel(robot)
        method = resolve_method(robot)
        reach(robot, delta=deltas[0])                     # compile once, as a notebook session would
        for delta in deltas:
            start = time.perf_counter()
            p = reach(robot, delta=delta, stop=StopAt(time_limit=600))
            seconds = time.perf_counter() - start
            lo, hi = p.measure_bounds
            split = ""
            if method == "critical" and model.m == 3:
                s = section_seconds(robot, delta)
                split = f" (section {s:.1f} + boxes {max(seconds - s, 0):.1f})"
            rel = f"{(hi - lo) / ref:.2%}" if ref else f"{(hi - lo) / (0.5 * (lo + hi)):.2%} of the mid"
            ref_text = f"{ref:.5f} ({kind})" if ref else "—"
            done = "" if p.complete else f" ({p.stop_reason})"
            print(f"| {name} | {method} | {delta} | {seconds:.2f}{split}{done} | {len(p.inner)} / {len(p.boundary)} / "
                  f"{len(p.outer)} | [{lo:.5f}, {hi:.5f}] | {rel} | {ref_text} | "
                  f"{sampled_measure(model, delta):.5f} |", flush=True)


if __name__ == "__main__":
    main()
