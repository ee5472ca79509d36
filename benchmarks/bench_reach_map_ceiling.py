"""Issue 40: how much of a saved reach map any sound map could decide (a ceiling on the decided fraction).

A pair (cell, direction) is out of every sound map's reach when both of these hold:

* a sampled configuration within the limits puts its tool point in the cell (at least 1e-9 inside each face) with
  its approach at least 1e-9 inside the direction's cone (floats): the pair is reached somewhere, so never -1;
* a point of the cell is proved unreachable with that cone: the wrist's ring (``WristRing.bound``, the test of
  ``ring_unreachable`` on a single point, outward-rounded) at a lattice of points of the cell (``steps + 1`` a
  side, the cell's edges included): the pair is not reached everywhere, so never 1.

The ceiling is one minus those pairs' share of the pairs inside the certified bounding box.  It is a bound on what
any sound map at this delta decides, not a property of ours; the sampled side is floats (an estimate, with the
margins above), the unreachable side a proof.  Also printed: the map's pairs that conflict with either side (a
proved-reachable pair with a point proved unreachable, a proved-unreachable pair reached by a sample: both must
be 0), and where the undecided pairs are.

Run: python benchmarks/bench_reach_map_ceiling.py --robot ur5 --map MAP.npz [--steps 4] [--samples 8000000]
     (MAP: a map saved by bench_reach_map.py --save; for the UR5 half the samples have the elbow, the joint
     that stretches the arm, within 0.25 rad of straight, where the far shell's points are)
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np
from bench_reach_map import robot_named

from workspace_sym.interval import arith
from workspace_sym.kinematics import numeric_function
from workspace_sym.serial.reachmap import ReachMap
from workspace_sym.serial.ring import wrist_ring

ELBOW = {"ur5": 2}      # the joint whose zero stretches the arm (0-based); other arms: uniform samples only


def unreachable_somewhere(made: ReachMap, ring, steps: int) -> np.ndarray:
    """Pairs with a lattice point of their cell proved unreachable by the ring (``bool``, the codes' shape)."""
    edges = made.edges
    lattice = []
    for e in edges:
        full = np.empty(steps * (len(e) - 1) + 1)
        for s in range(steps):
            full[s:-1:steps] = e[:-1] + (e[1:] - e[:-1]) * (s / steps)
        full[-1] = e[-1]
        lattice.append(full)
    shape = tuple(len(v) for v in lattice)
    y = [arith.sub((lattice[a], lattice[a]), (ring.centre[a, 0], ring.centre[a, 1])) for a in range(3)]
    sq = [arith.sqr(v)[0] for v in y]
    r0_sq = np.maximum(arith.down(arith.down(sq[0][:, None, None] + sq[1][None, :, None]) + sq[2][None, None, :]), 0)
    yc = np.stack(np.meshgrid(*[(v[0] + v[1]) / 2 for v in y], indexing="ij"), -1).reshape(-1, 3)
    d = made.directions / np.linalg.norm(made.directions, axis=1, keepdims=True)
    c = math.radians(made.cone)
    out = np.zeros(made.codes.shape, dtype=bool)
    for k in range(len(d)):
        angle = np.arctan2(np.linalg.norm(np.cross(yc, d[k]), axis=-1), yc @ d[k]).reshape(shape)
        with np.errstate(all="ignore"):
            g = ring.bound(r0_sq, ring.gap(angle - c - 1e-9, angle + c + 1e-9))
        proved = np.where(np.isnan(g), False, g > ring.reach)
        window = np.lib.stride_tricks.sliding_window_view(proved, (steps + 1,) * 3)[::steps, ::steps, ::steps]
        out[..., k] = window.any(axis=(-3, -2, -1))
    return out


def reached_somewhere(robot, made: ReachMap, n: int, elbow: int | None, seed: int = 7, chunk: int = 500_000):
    """Pairs a sampled configuration reaches (1e-9 inside the cell and the cone), half of them stretched."""
    T = numeric_function(robot.substitute(robot.fk()), robot.q)
    lim = robot.joint_limits()
    rng = np.random.default_rng(seed)
    d = made.directions / np.linalg.norm(made.directions, axis=1, keepdims=True)
    cos_c = math.cos(math.radians(made.cone))
    edges = made.edges
    out = np.zeros(made.codes.shape, dtype=bool)
    for b, at in enumerate(range(0, n, chunk)):
        q = rng.uniform(lim[:, 0], lim[:, 1], size=(min(chunk, n - at), len(lim)))
        if elbow is not None and b % 2:
            q[:, elbow] = np.clip(rng.uniform(-0.25, 0.25, size=len(q)), lim[elbow, 0], lim[elbow, 1])
        M = T(q)
        p = M[:, :3, 3]
        index, inside = made.cells_of(p)
        for a in range(3):
            e = edges[a]
            i = np.clip(index[:, a], 0, len(e) - 2)
            inside &= (p[:, a] >= e[i] + 1e-9) & (p[:, a] <= e[i + 1] - 1e-9)
        dots = M[:, :3, 2] @ d.T
        for k in range(len(d)):
            take = inside & (dots[:, k] >= cos_c + 1e-9)
            out[index[take, 0], index[take, 1], index[take, 2], k] = True
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--robot", default="ur5")
    parser.add_argument("--map", required=True)
    parser.add_argument("--steps", type=int, default=4)
    parser.add_argument("--samples", type=int, default=8_000_000)
    args = parser.parse_args()
    robot = robot_named(args.robot)
    made = ReachMap.load(args.map)
    ring = wrist_ring(robot, ())
    if ring is None:
        raise SystemExit(f"{args.robot}: no wrist ring, no ceiling by this method")
    started = time.perf_counter()
    unreach = unreachable_somewhere(made, ring, args.steps)
    lattice_seconds = time.perf_counter() - started
    reached = reached_somewhere(robot, made, args.samples, ELBOW.get(args.robot))
    codes = made.codes
    box = np.broadcast_to(made.bounding_mask()[..., None], codes.shape)
    undecided = (codes == 0) & box
    never = undecided & reached & unreach
    total = int(box.sum())
    out = {"robot": args.robot, "map": args.map, "steps": args.steps, "samples": args.samples,
           "lattice_seconds": round(lattice_seconds, 1),
           "pairs_in_box": total, "decided_in_box": int(((codes != 0) & box).sum()),
           "decided_fraction_in_box": float(((codes != 0) & box).sum() / total),
           "conflicts_proved_reachable_with_a_point_unreachable": int(((codes == 1) & unreach).sum()),
           "conflicts_proved_unreachable_yet_reached": int(((codes == -1) & reached).sum()),
           "undecided_in_box": int(undecided.sum()),
           "undecided_reached_with_a_point_unreachable": int(never.sum()),
           "undecided_reached_no_point_proved_unreachable": int((undecided & reached & ~unreach).sum()),
           "undecided_not_reached_a_point_unreachable": int((undecided & ~reached & unreach).sum()),
           "undecided_neither": int((undecided & ~reached & ~unreach).sum()),
           "ceiling_in_box": 1 - float(never.sum() / total),
           "decided_share_of_decidable": float(((codes != 0) & box).sum() / (total - never.sum()))}
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
