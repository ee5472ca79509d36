"""Issue 24 benchmark: certified position workspaces of industrial arms turned by their first joint.

For each arm, delta and time limit (one cold process per arm: nothing cached): the method, the seconds, where
they go (symbolic preparation of the model and of the section, the paving of the section, the classification of
the (x, y, z) boxes), the proved brackets (the boxes', the section cells' by Pappus when the first joint turns a
full circle, and their intersection, the reach's), its width as a share of its upper bound, and a reference volume
the bracket must hold: Pappus's theorem on the section sampled at 1.6 10^7 configurations (cells of (rho, z) of
side h hit by a sample, each turned through a full circle, extrapolated to h = 0 from h = 5 mm and 1 cm; an
estimate, no bound).

Arms: UR5 (``tests/data/dh/ur5.json``), KUKA KR16 (rtb-data's ``kr16_2.urdf``, limits from the file), the
glass-handling arm and the Puma 560 of the catalog (the constant-offset section, for the before/after check);
named only: ``iiwa`` (rtb-data's ``lbr_iiwa_14_r820.urdf``), ``panda`` (``tests/data/dh/panda.json``) and
``panda8`` (rtb-data's ``panda_arm.urdf.xacro`` to ``panda_link8``; its loading, about 10 s, is not counted),
whose first joint is limited (reach_turn): their reference is the sampled section with the arcs of theta_1
(``arcs``); each at delta 0.1, 0.05 and 0.025 within 120 s (issue 41 item 2: a finer delta never wider).

Run: python benchmarks/bench_reach_arms.py [--quick] [ARM ...]   (e.g. ``iiwa panda``), or one line:
python benchmarks/bench_reach_arms.py ARM DELTA LIMIT
"""

import datetime
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "helpers"))
from reach_checks import industrial_arm, sampled_arcs_volume  # noqa: E402  (the tests' arms and reference)

ARMS = {"ur5": [(0.2, 60), (0.1, 60)], "kr16": [(0.1, 120)], "glass": [(0.0125, 60)], "puma": [(0.02, 60)],
        "iiwa": [(0.1, 120), (0.05, 120), (0.025, 120)], "panda": [(0.1, 120), (0.05, 120), (0.025, 120)],
        "panda8": [(0.1, 120), (0.05, 120)]}
LIMITED = ("iiwa", "panda", "panda8")     # first joint limited (340 and 332 deg): run only when named
# Issue 41 item 2: the Panda as rtb-data's xacro describes it, to the flange (tip panda_link8, no hand)
PANDA_XACRO = ("qut_frankie_description", "robots/panda_arm.urdf.xacro")


def load(name):
    from workspace_sym import robots

    if name in ("ur5", "kr16", "iiwa", "panda"):
        return industrial_arm(name)
    if name == "panda8":
        import rtbdata

        from workspace_sym.kinematics import DHRobot

        package = Path(rtbdata.__file__).parent / "xacro" / PANDA_XACRO[0]
        return DHRobot.from_urdf(package / PANDA_XACRO[1], tip_link="panda_link8", packages={PANDA_XACRO[0]: package})
    return robots.build({"glass": "glass-handling", "puma": "puma560"}[name])


def pappus(robot, plan, n=16_000_000, h=0.005, chunk=1_000_000):
    """Volume of the sampled section turned through a full circle (the first joint's range ignored), extrapolated
    to cells of side zero: ``2 V(h) - V(2 h)`` (Richardson), ``V(h)`` the solids of the cells of side ``h`` hit by
    one of ``n`` samples (it overestimates by about half a cell along the boundary, and 10^6 samples leave cells of
    the KR16's section unhit: 19.37 m^3 at 10^6 samples, 19.91 at 1.6 10^7)."""
    from workspace_sym.serial import ReachModel
    from workspace_sym.serial.section import Turned, to_first_frame

    if not isinstance(plan, Turned) or not plan.full:
        return None
    model = ReachModel(robot)
    rng = np.random.default_rng(0)
    cells = {side: np.empty((0, 2)) for side in (h, 2 * h)}
    for _ in range(n // chunk):
        p = model.position_float(model.random_configurations(chunk, rng))
        F = to_first_frame(plan.inverse, np.repeat(p[:, :, None], 2, axis=2))[:, :, 0]
        rz = np.stack([np.hypot(F[:, 0], F[:, 1]), F[:, 2]], axis=1)
        for side in cells:
            cells[side] = np.unique(np.concatenate([cells[side], np.floor(rz / side)]), axis=0)
    volume = {side: float(np.sum(2 * np.pi * (c[:, 0] + 0.5) * side ** 3)) for side, c in cells.items()}
    return 2 * volume[h] - volume[2 * h]


def arcs(robot, n=1_000_000, h=0.005):
    """Volume for a limited first joint: the section sampled, each (rho, z) cell of side h hit by a sample turned
    through the union of the arcs of its samples (``reach_checks.sampled_arcs_volume``, the tests' reference;
    an estimate)."""
    return sampled_arcs_volume(robot, n, h)


def one(name, delta, limit):
    """One arm in this process: a line of the table."""
    from workspace_sym import StopAt
    from workspace_sym.serial import model, plans, reach, structure

    phases = {"section paving": 0.0}

    def timed(fn):
        def wrapper(*args, **kwargs):
            t = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                phases["section paving"] += time.perf_counter() - t
        return wrapper

    plans.section_paving = timed(plans.section_paving)
    plans.pave_limited = timed(plans.pave_limited)
    plans.critical_paving = timed(plans.critical_paving)
    robot = load(name)
    t = time.perf_counter()
    paving = reach(robot, delta=delta, stop=StopAt(time_limit=limit))
    total = time.perf_counter() - t
    plan = structure.structure_of(robot, ())
    t = time.perf_counter()
    structure.structure_of.cache_clear()
    model.reach_model.cache_clear()
    structure.structure_of(robot, ())
    prep = time.perf_counter() - t
    lo, hi = paving.measure_bounds
    ref = pappus(robot, plan) if name not in LIMITED else arcs(robot)
    c = paving.counts
    holds = "" if ref is None else ("holds" if lo <= ref <= hi else "MISSES")
    rest = total - prep - phases["section paving"]
    ref_text = "-" if ref is None else f"{ref:.4f} ({holds})"
    blo, bhi = paving.box_measure_bounds
    pappus_text = "-" if paving.volume_bounds is None else "[{:.4f}, {:.4f}]".format(*paving.volume_bounds)
    print(f"| {name} | {paving.method} | {delta} | {limit} | {total:.1f} (prep {prep:.1f} + section "
          f"{phases['section paving']:.1f} + boxes {rest:.1f}) | {c['inner']} / {c['boundary']} / {c['outer']} "
          f"/ {c['pending']} | [{blo:.4f}, {bhi:.4f}] | {pappus_text} | [{lo:.4f}, {hi:.4f}] "
          f"| {100 * (hi - lo) / hi:.1f}% | {ref_text} |", flush=True)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) == 3 and args[0] in ARMS and args[1].replace(".", "", 1).isdigit():     # child: one arm
        one(args[0], float(args[1]), float(args[2]))
        return
    from _common import machine

    with open("/proc/loadavg") as f:
        load_avg = f.read().split()[0]
    print(f"{datetime.date.today()}, {machine()}, load average {load_avg} at the start")
    print("| arm | method | delta | time limit | seconds (where) | inner / boundary / outer / pending | boxes' bracket "
          "| section's bracket (Pappus on proved cells) | bracket | width / upper | Pappus reference (sampled) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    names = args or [name for name in ARMS if name not in LIMITED]
    for name in names:
        for delta, limit in ARMS[name][:1] if "--quick" in sys.argv else ARMS[name]:
            subprocess.run([sys.executable, __file__, name, str(delta), str(limit)], check=False,
                           cwd=Path(__file__).parent)


if __name__ == "__main__":
    main()
