"""Issue 38 check: the same boxes before and after a restructuring of the engines.

For each run below, the SHA-256 of the sorted inner, boundary, outer and pending boxes, their counts, the boxes
evaluated and the proved bracket (``measure_bounds``), printed as JSON.  Runs that depend on the clock are not
listed: every run stops on a box budget or not at all, so two machines give the same figures.

Runs (issue 38's list): pave of Rybak's 2-RPR at delta 0.07 and 0.01, the Orthoglide's dextrous workspace at eps
0.05, reach of the planar 3R and of the glass-handling arm, the Puma 560, UR5 and KR16 at delta 0.1 under a box
budget, the Puma with its tool within 20 deg of straight down and with its tool pointing down.

Run: python benchmarks/bench_identity.py [--out FILE] [--against FILE] [NAME ...]
``--against`` compares with a file written earlier by ``--out`` and exits 1 on any difference.
"""

import argparse
import hashlib
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "helpers"))
import workspace_sym as ws  # noqa: E402
from reach_checks import industrial_arm  # noqa: E402  (the tests' UR5 and KR16)


def digest(boxes: np.ndarray) -> str:
    boxes = np.asarray(boxes, dtype=float)
    if not len(boxes):
        return hashlib.sha256(b"").hexdigest()
    flat = np.ascontiguousarray(boxes.reshape(len(boxes), -1))
    return hashlib.sha256(flat[np.lexsort(flat.T[::-1])].tobytes()).hexdigest()


def figures(result) -> dict:
    paving = getattr(result, "paving", result)
    kinds = ("inner", "boundary", "outer", "pending")
    out = {k: {"boxes": len(getattr(paving, k)), "sha256": digest(getattr(paving, k))} for k in kinds}
    out["evaluated"] = int(paving.evaluated)
    # A reach result (a Paving with a method before the reach package, a ReachResult after) brackets with its
    # volume proved another way too; a dextrous result's paving holds its bracket.
    bounds = result.measure_bounds if hasattr(result, "method") else paving.measure_bounds
    out["measure_bounds"] = [float(v) for v in bounds]
    return out


def rpr2(delta):
    from workspace_sym.parallel import rpr2 as model

    return model().pave(delta=delta, stop=QUIET)


def orthoglide():
    from workspace_sym.orthoglide import Orthoglide

    return Orthoglide().dextrous(eps=0.05, stop=QUIET)


QUIET = ws.StopAt(progress=False)
BUDGET = ws.StopAt(max_boxes=20_000, section_boxes=3_000, progress=False)
ARM_BUDGET = ws.StopAt(max_boxes=100_000, section_boxes=3_000, progress=False)
CONE = ws.Pose(approach=(0, 0, -1), cone=20)
DOWN = ws.Pose(rpy=(180, 0, 0))

RUNS = {
    "pave rpr2 0.07": lambda: rpr2(0.07),
    "pave rpr2 0.01": lambda: rpr2(0.01),
    "orthoglide 0.05": orthoglide,
    "reach planar-3r 0.05": lambda: ws.reach(ws.robots.build("planar-3r"), delta=0.05, stop=QUIET),
    "reach glass 0.05": lambda: ws.reach(ws.robots.build("glass-handling"), delta=0.05, stop=QUIET),
    "reach puma 0.1": lambda: ws.reach(ws.robots.build("puma560"), delta=0.1, stop=BUDGET),
    "reach ur5 0.1": lambda: ws.reach(industrial_arm("ur5"), delta=0.1, stop=ARM_BUDGET),
    "reach kr16 0.1": lambda: ws.reach(industrial_arm("kr16"), delta=0.1, stop=ARM_BUDGET),
    "reach puma cone 0.1": lambda: ws.reach(ws.robots.build("puma560"), delta=0.1, stop=QUIET, pose=CONE),
    "reach puma tool-down 0.1": lambda: ws.reach(ws.robots.build("puma560"), delta=0.1, stop=QUIET, pose=DOWN),
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help=f"runs to do (default: all): {', '.join(RUNS)}")
    parser.add_argument("--out", help="write the figures to this JSON file")
    parser.add_argument("--against", help="compare with figures written earlier; exit 1 on a difference")
    args = parser.parse_args()
    names = args.names or list(RUNS)
    results = {}
    for name in names:
        start = time.perf_counter()
        results[name] = figures(RUNS[name]())
        print(f"{name}: {time.perf_counter() - start:.1f} s  "
              + ", ".join(f"{k} {results[name][k]['boxes']}" for k in ("inner", "boundary", "outer", "pending"))
              + f", bracket {results[name]['measure_bounds']}", flush=True)
    if args.out:                # runs named on the command line are added to (or replace) those of the file
        out = Path(args.out)
        kept = json.loads(out.read_text()) if out.exists() and args.names else {}
        out.write_text(json.dumps({**kept, **results}, indent=1, sort_keys=True) + "\n")
    if args.against:
        before = json.loads(Path(args.against).read_text())
        differ = [name for name in names if before.get(name) != results[name]]
        print("identical" if not differ else f"DIFFERENT: {', '.join(differ)}")
        return 1 if differ else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
