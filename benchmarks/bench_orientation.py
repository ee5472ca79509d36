"""Issue 25 benchmark: certified orientation workspaces (``workspace_sym.serial.pose``) beside a sampled
capability map computed in the same run.

For each robot and constraint: seconds, proved inner / boundary / outer boxes, the measure bracket and its
width against its upper bound (the target: at most 20 % within 120 s for the Puma 560).  The capability map
is the usual sampled answer (no bound either way), on a grid of cells of side ``CELL``:

* approach cone: a cell is "reachable" when one of ``SAMPLES`` random configurations within the limits with
  its approach axis in the cone puts the tool point in it (a reachability map);
* constant orientation: a cell is "reachable" when a damped Newton method from ``STARTS`` random
  configurations reaches its centre with the tool frame within 1e-9 of R (an IK-based capability map).

Each cell is then looked up in the certified paving, at the point the sampling reached (a sampled tool point
in the cell, or the centre for the IK map), else at its centre: the certificate *confirms* the sample
(reachable and inner, or not reachable and outer), *refutes* it (reachable but outer: impossible unless the
certificate is wrong, so it must be 0; or not reachable but inner: a cell the sampling missed), or leaves it
undecided (boundary or pending box).

Session 16 (issue 40 item 1): ``--arms`` runs the Puma 560 (120 s), UR5 and KR16 (300 s) rows alone at the issue's
budgets with an independent sampled reference volume beside each bracket: for the cone, configurations uniform
within the limits whose approach lies in the cone; for the tool down, uniform configurations whose joints 4 and 5
are then solved by Newton (floats) for the approach (0, 0, -1); their tool points binned in (rho, z) cells of side
``REF_CELL`` and turned by Pappus (``tests/helpers/reach_checks.py`` ``arcs_volume``: an estimate, no bound).

Run: python benchmarks/bench_orientation.py [--quick | --arms [NAME ...] [--cone | --down]]   (e.g. ``--arms iiwa
panda``: the rows whose robot's name holds one of the names; ``--cone``: the cone rows only; ``--down``: the tool-down
rows only)
"""

import datetime
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp

from _common import machine

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "helpers"))
from reach_checks import admissible_configurations, arcs_volume, in_any_box, industrial_arm, oriented_configurations
from workspace_sym import StopAt, robots
from workspace_sym.interval.image import ImageMap
from workspace_sym.kinematics import DHRobot
from workspace_sym.serial import Pose, reach
from workspace_sym.serial.pose import constraint_from

UR5 = Path(__file__).resolve().parents[1] / "tests" / "data" / "dh" / "ur5.json"
CELL = 0.05
SAMPLES = 1_000_000
STARTS = 6


def cases(quick: bool):
    puma, ur5 = robots.build("puma560"), DHRobot.from_file(UR5)
    down = dict(approach=(0, 0, -1), cone=20)
    tool_down = dict(rpy=(180, 0, 0))
    return [("Puma 560", puma, down, (0.05,) if quick else (0.03, 0.02)),
            ("Puma 560", puma, tool_down, (0.1,) if quick else (0.07, 0.03)),
            ("UR5", ur5, down, (0.2,)), ("UR5", ur5, tool_down, (0.2,))]


REF_CELL = 0.01
REF_SAMPLES = 4_000_000


def arm_cases():
    """The issue 40 rows: (name, robot, options, deltas, time limit).  Under a time limit the constrained section's
    cells do not follow delta (docs/methods.md section 8), so two deltas show the bracket's independence of it."""
    ur5, ur10, kr16, puma = (industrial_arm("ur5"), industrial_arm("ur10"), industrial_arm("kr16"),
                             robots.build("puma560"))
    down = dict(approach=(0, 0, -1), cone=20)
    tool_down = dict(rpy=(180, 0, 0))
    rows = [("Puma 560", puma, down, (0.05, 0.02), 120), ("Puma 560", puma, tool_down, (0.05, 0.02), 120),
            ("UR5", ur5, down, (0.05,), 300), ("UR5", ur5, tool_down, (0.05,), 300),
            ("UR10", ur10, down, (0.05,), 300), ("UR10", ur10, tool_down, (0.05,), 300),
            ("KR16 (URDF)", kr16, down, (0.15, 0.1), 300), ("KR16 (URDF)", kr16, tool_down, (0.15,), 300)]
    # The seven-joint arms (first joint limited, docs/methods.md section 8): the iiwa through its wrist centre (the
    # cone since session 24, tool down since session 29); the Panda's tool down (session 30), exact approach and cone
    # (session 31) through the sections of its wrist's two solutions.
    iiwa, panda = industrial_arm("iiwa"), industrial_arm("panda")
    rows += [("LBR iiwa 14 (URDF)", iiwa, down, (0.1,), 300), ("LBR iiwa 14 (URDF)", iiwa, tool_down, (0.1,), 300),
             ("Panda", panda, down, (0.1,), 300), ("Panda", panda, dict(approach=(0, 0, -1), cone=0), (0.1,), 300),
             ("Panda", panda, tool_down, (0.1,), 300)]
    return rows


def reference_volume(robot, options, n=REF_SAMPLES):
    """The sampled reference volume (module docstring) and the admissible samples' tool points; a seven-joint arm's
    tool down: its wrist (joints 5 and 6) points the approach and its last joint, which turns less than a turn, is
    turned to the frame's spin and kept within its limits (``oriented_configurations``)."""
    if "rpy" in options and robot.n == 7:
        R = np.array(constraint_from(**options).matrix, dtype=float)
        q, points = oriented_configurations(robot, n, 0, R, wrist=(4, 5))
        return arcs_volume(robot, q[:, 0], points, REF_CELL), points
    exact = options.get("cone") == 0             # the approach made exact by Newton on the wrist's two joints
    q, _, points = admissible_configurations(robot, n, 0, approach=options.get("approach", (0, 0, -1)),
                                             cone=None if exact else options.get("cone"),
                                             wrist=(4, 5) if exact and robot.n == 7 else (3, 4))
    return arcs_volume(robot, q[:, 0], points, REF_CELL), points


def arms():
    """Session 16 rows: bracket, width, the sampled reference and whether the bracket holds it."""
    print(f"# orientation of the arms (issue 40), {datetime.date.today()}, {machine()}")
    print("| robot | constraint | method | delta | seconds | inner / boundary / outer | bracket (m³) | width / upper "
          "| sampled reference (admissible samples) | inside | samples in outer boxes (must be 0) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    chosen = [a.lower() for a in sys.argv[sys.argv.index("--arms") + 1:] if not a.startswith("--")]
    for name, robot, options, deltas, limit in arm_cases():
        if (chosen and not any(c in name.lower() for c in chosen)) or ("--cone" in sys.argv and "cone" not in options) \
                or ("--down" in sys.argv and "rpy" not in options):
            continue
        constraint = constraint_from(**options)
        reach(robot, delta=0.4, stop=StopAt(time_limit=60), pose=Pose(**options))   # compile once
        reference, points = reference_volume(robot, options)
        for delta in deltas:
            start = time.perf_counter()
            p = reach(robot, delta=delta, stop=StopAt(time_limit=limit), pose=Pose(**options))
            seconds = time.perf_counter() - start
            lo, hi = p.measure_bounds
            done = "" if p.complete else f" ({p.stop_reason})"
            rel = f"{(hi - lo) / hi:.1%}" if hi > 0 else "—"
            print(f"| {name} | {constraint} | {p.method} | {delta} | {seconds:.1f}{done} | {p.counts['inner']} / "
                  f"{p.counts['boundary']} / {p.counts['outer']} | [{lo:.4f}, {hi:.4f}] | {rel} | {reference:.4f} "
                  f"({len(points):,}) | {'yes' if lo <= reference <= hi else '**no**'} "
                  f"| {int(in_any_box(points, p.outer, pad=-1e-9).sum())} |", flush=True)


def capability_map(robot, options, box, rng):
    """Boolean grid of the cells (side CELL over ``box``) the sampling says are reachable, and the centres."""
    edges = [np.arange(lo, hi + CELL, CELL) for lo, hi in box]
    shape = tuple(len(e) - 1 for e in edges)
    centres = np.stack(np.meshgrid(*[0.5 * (e[:-1] + e[1:]) for e in edges], indexing="ij"), axis=-1)
    T = robot.substitute(robot.fk())
    lim = robot.joint_limits()
    hit = np.zeros(shape, dtype=bool)
    where = centres.copy()
    if "approach" in options:
        d = np.array(options["approach"], dtype=float)
        d /= np.linalg.norm(d)
        f = sp.lambdify([robot.q], list(T[:3, 3]) + list(T[:3, 2]), modules="numpy")
        for _ in range(SAMPLES // 200_000):
            q = rng.uniform(lim[:, 0], lim[:, 1], size=(200_000, robot.n))
            v = np.stack([np.broadcast_to(np.asarray(e, dtype=float), (len(q),)) for e in f(q.T)], axis=1)
            ok = v[:, 3:] @ d >= np.cos(np.radians(options["cone"])) + 1e-9     # a margin for float rounding
            idx = np.floor((v[ok, :3] - box[:, 0]) / CELL).astype(int)
            fits = np.all((idx >= 0) & (idx < np.array(shape)), axis=1)
            hit[tuple(idx[fits].T)] = True
            where[tuple(idx[fits].T)] = v[ok, :3][fits]
        return hit, where
    R = constraint_from(**options).rotation
    M = R.T * T[:3, :3]
    skew = [M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]]
    ik = ImageMap(list(T[:3, 3]) + skew, robot.q, [tuple(r) for r in lim], [False] * robot.n)
    flat = centres.reshape(-1, 3)
    target = np.concatenate([flat, np.zeros((len(flat), 3))], axis=1)
    reached = np.zeros(len(flat), dtype=bool)
    trace = sp.lambdify([robot.q], M.trace(), modules="numpy")
    for _ in range(STARTS):
        rows = np.nonzero(~reached)[0]
        q, ok = ik.newton(target[rows], ik.random_configurations(len(rows), rng), steps=30)
        ok &= np.asarray(trace(q.T), dtype=float) > 0
        reached[rows[ok]] = True
    return reached.reshape(shape), centres


def lookup(paving, points):
    """Class of each point (``(..., 3)``) in the paving: 1 inner, 0 outer (its interior), 2 undecided."""
    flat = points.reshape(-1, 3)
    out = np.full(len(flat), 2, dtype=np.int8)
    order = np.argsort(flat[:, 0])
    xs = flat[order, 0]
    for value, boxes in ((1, paving.inner), (0, paving.outer)):
        # The points whose x lies in the box's x range (a sorted search), then the other two coordinates.
        first = np.searchsorted(xs, boxes[:, 0, 0], side="left" if value == 1 else "right")
        last = np.searchsorted(xs, boxes[:, 0, 1], side="right" if value == 1 else "left")
        for b, i, j in zip(boxes, first, last):
            if i >= j:
                continue
            rows = order[i:j]
            p = flat[rows, 1:]
            if value == 1:
                inside = np.all((p >= b[1:, 0]) & (p <= b[1:, 1]), axis=1)
            else:       # the interior of an outer box: a point on a face it shares with a boundary box is undecided
                inside = np.all((p > b[1:, 0]) & (p < b[1:, 1]), axis=1)
            out[rows[inside]] = value
    return out.reshape(points.shape[:-1])


def main():
    if "--arms" in sys.argv:
        return arms()
    quick = "--quick" in sys.argv
    rng = np.random.default_rng(0)
    print(f"# orientation benchmark, {datetime.date.today()}, {machine()}")
    print("| robot | constraint | method | delta | seconds | inner / boundary / outer boxes | measure bracket "
          "| (hi - lo) / hi | capability map cells: confirmed / refuted (sampled but outer + inner but missed) "
          "/ undecided (cells reached by sampling) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, robot, options, deltas in cases(quick):
        constraint = constraint_from(**options)
        reach(robot, delta=0.4, stop=StopAt(time_limit=60), pose=Pose(**options))   # compile once, as a session would
        for delta in deltas:
            start = time.perf_counter()
            p = reach(robot, delta=delta, stop=StopAt(time_limit=120), pose=Pose(**options))
            seconds = time.perf_counter() - start
            lo, hi = p.measure_bounds
            box = np.array([p.box.lower, p.box.upper]).T
            hit, points = capability_map(robot, options, box, rng)
            verdict = lookup(p, points)
            confirmed = int(((verdict == 1) & hit).sum() + ((verdict == 0) & ~hit).sum())
            false_positive = int(((verdict == 0) & hit).sum())
            missed = int(((verdict == 1) & ~hit).sum())
            undecided = int((verdict == 2).sum())
            done = "" if p.complete else f" ({p.stop_reason})"
            rel = f"{(hi - lo) / hi:.1%}" if hi > 0 else "—"
            print(f"| {name} | {constraint} | {p.method} | {delta} | {seconds:.1f}{done} | {p.counts['inner']} / "
                  f"{p.counts['boundary']} / {p.counts['outer']} | [{lo:.4f}, {hi:.4f}] | {rel} | {confirmed} / "
                  f"{false_positive} + {missed} / {undecided} ({int(hit.sum())}) |", flush=True)


if __name__ == "__main__":
    main()
