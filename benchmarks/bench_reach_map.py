"""Issue 40 benchmark: a certified reachability map (``ws.reach_map``) beside a sampled one built the way the
sampled tools build theirs, in one run.

The sampled map: ``N`` joint configurations drawn uniformly within the limits (10^6 and 10^7), their tool points
binned into the certified map's cells and their approach axes into every direction's cone (``a . d_k >= cos
cone``, floats); a (cell, direction) pair is "reached" when one sample lands in it.  Beside ours:

* **false negatives** of the sampled map: pairs it calls unreached that we prove reachable (code 1: every
  point of the cell reached with an approach in the cone);
* **"reached somewhere" overclaims**: pairs it calls reached that we do not prove reachable at every point
  (code 0 or -1).  Of these, the ones we prove unreachable (-1) must be 0 (a sample in a proved-unreachable pair
  is a false certificate; a sample within 1e-9 of the cone's rim is not counted);
* our decided fraction (all pairs, the pairs whose cell centre lies in the arm's certified bounding box, and
  those whose centre lies in the extent of the largest sampled map's tool points, which far cells do not inflate);
* the build time of each, and the query throughput of ours (10^6 points with approach vectors, best of 3).

Run: python benchmarks/bench_reach_map.py [--robot puma560] [--delta 0.05] [--directions 26] [--cone 30]
     [--time-limit 1200] [--samples 1000000,10000000] [--reach-delta D] [--method pavings|section] [--save PATH]
     [--workers N] (processes the map is built on, default the cores: a spawned process pool)
     (--robot: a name of ``robots.build``, of a table in tests/data/dh (ur5, panda), or kr16, iiwa: rtb-data's URDFs)
"""

from __future__ import annotations

import argparse
import concurrent.futures
import contextlib
import datetime
import json
import math
import multiprocessing
import os
import time
import warnings
from pathlib import Path

import numpy as np

from _common import machine
from workspace_sym import RunOn, StopAt, robots
from workspace_sym.kinematics import DHRobot, numeric_function
from workspace_sym.serial.reachmap import reach_map


def sampled_map(robot, made, n, seed=0, chunk=500_000):
    """Which pairs ``n`` sampled configurations reach, and those with a sample at least 1e-9 inside the cone."""
    T = numeric_function(robot.substitute(robot.fk()), robot.q)
    lim = robot.joint_limits()
    rng = np.random.default_rng(seed)
    cos_c = math.cos(math.radians(made.cone))
    reached = np.zeros(made.codes.shape, dtype=bool)
    firmly = np.zeros(made.codes.shape, dtype=bool)
    extent = np.array([[np.inf, -np.inf]] * 3)
    started = time.perf_counter()
    for at in range(0, n, chunk):
        q = rng.uniform(lim[:, 0], lim[:, 1], size=(min(chunk, n - at), len(lim)))
        M = T(q)
        index, inside = made.cells_of(M[:, :3, 3])
        extent = np.stack([np.minimum(extent[:, 0], M[:, :3, 3].min(axis=0)),
                           np.maximum(extent[:, 1], M[:, :3, 3].max(axis=0))], 1)
        dots = M[:, :3, 2] @ made.directions.T
        for k in range(len(made.directions)):
            for mask, into in ((dots[:, k] >= cos_c, reached), (dots[:, k] >= cos_c + 1e-9, firmly)):
                take = mask & inside
                into[index[take, 0], index[take, 1], index[take, 2], k] = True
    return reached, firmly, extent, time.perf_counter() - started


URDFS = {"kr16": "kuka_description/kuka_kr16/urdf/kr16_2.urdf",
         "iiwa": "kuka_description/kuka_lbr_iiwa/urdf/lbr_iiwa_14_r820.urdf"}


def robot_named(name):
    """A catalogue robot, a table of tests/data/dh, or the KR16 / iiwa 14 of rtb-data's URDFs (their limits)."""
    if name in URDFS:
        import rtbdata

        return DHRobot.from_urdf(Path(rtbdata.__file__).parent / "xacro" / URDFS[name])
    table = Path(__file__).resolve().parent.parent / "tests" / "data" / "dh" / f"{name}.json"
    return DHRobot.from_file(table) if table.is_file() else robots.build(name)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--robot", default="puma560")
    parser.add_argument("--delta", type=float, default=0.05)
    parser.add_argument("--directions", type=int, default=26)
    parser.add_argument("--cone", type=float, default=30.0)
    parser.add_argument("--time-limit", type=float, default=1200.0)
    parser.add_argument("--reach-delta", type=float, default=None)
    parser.add_argument("--samples", default="1000000,10000000")
    parser.add_argument("--method", default="pavings", choices=("pavings", "section"))
    parser.add_argument("--save", default=None, help="write the map to this .npz")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="processes the map is built on (default: the cores; 1: in this process)")
    args = parser.parse_args()
    robot = robot_named(args.robot)
    load = os.getloadavg()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        with contextlib.ExitStack() as stack:
            pool = None if args.workers <= 1 else stack.enter_context(concurrent.futures.ProcessPoolExecutor(
                args.workers, mp_context=multiprocessing.get_context("spawn")))
            made = reach_map(robot, delta=args.delta, directions=args.directions, cone=args.cone,
                             reach_delta=args.reach_delta, method=args.method,
                             stop=StopAt(time_limit=args.time_limit), run=RunOn(executor=pool))
    s = made.summary()
    codes = made.codes
    out = {"date": datetime.datetime.now(datetime.UTC).isoformat(timespec="minutes"), "machine": machine(),
           "load_before": [round(v, 2) for v in load], "robot": args.robot, "method": args.method,
           "workers": args.workers, "summary": s,
           "stage_seconds": made.info.get("stage_seconds"),
           "direction_seconds": [round(v or 0, 1) for v in made.info["direction_seconds"]],
           "direction_methods": made.info["direction_methods"], "sampled": []}
    for n in (int(v) for v in args.samples.split(",")):
        reached, firmly, extent, seconds = sampled_map(robot, made, n)
        out["sampled"].append({
            "samples": n, "seconds": round(seconds, 1), "reached_pairs": int(reached.sum()),
            "false_negatives": int((~reached & (codes == 1)).sum()),
            "overclaims": int((reached & (codes != 1)).sum()),
            "overclaims_we_prove_unreachable": int((firmly & (codes == -1)).sum()),
            "reached_and_proved_reachable": int((reached & (codes == 1)).sum())})
    # the certified bounding box (info["root"]) holds the arm's true one; the samples' extent lies inside it: the
    # decided fraction over the cells whose centre the samples' extent holds does not count far cells
    inner_box = made.bounding_mask(extent)
    out["sampled_extent"] = extent.round(4).tolist()
    out["decided_fraction_in_sampled_extent"] = float((codes[inner_box] != 0).mean())
    if args.save:
        made.save(args.save)
    rng = np.random.default_rng(1)
    root = np.array(made.info["root"])
    points = rng.uniform(root[:, 0], root[:, 1], size=(1_000_000, 3))
    approach = rng.normal(size=(1_000_000, 3))
    best = min(_timed(made.query, points, approach) for _ in range(3))
    out["queries_per_second_with_approach"] = round(1e6 / best)
    best = min(_timed(made.query, points, None) for _ in range(3))
    out["queries_per_second_capability"] = round(1e6 / best)
    out["load_after"] = [round(v, 2) for v in os.getloadavg()]
    print(json.dumps(out, indent=1))


def _timed(fn, points, approach):
    t = time.perf_counter()
    fn(points, approach=approach)
    return time.perf_counter() - t


if __name__ == "__main__":
    main()
