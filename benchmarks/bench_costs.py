"""Issue 41 item 4: how each engine's cost grows with its work, measured in one run, with the slope of each curve.

* **pave** -- Rybak's 2-RPR robot (``robots.build("rpr2")``), ``size="width"``: boxes and seconds against delta
  from 0.5 to 0.002, beside codac.sivia and codac.pave(SepInverse) at the same eps (the bench extra);
* **reach** -- UR5, KR16 (both full turns, delta 0.1) and the LBR iiwa 14 (limited first joint, delta 0.1): the
  bracket's width against the time limit, 10 s to 600 s, one cold process per run;
* **planar** -- the alignment method against the number of links, 2 to 12 (random chains as
  ``bench_planar.py`` draws them, the median of ``--chains`` per count);
* **symbolic** -- fk + Jacobian, singular factors and the 3 x n characteristic polynomial against the number of
  joints, 3 to 7: the first n rows of the Panda's table (``tests/data/dh/panda.json``, modified DH), one cold
  process per n;
* **dask** -- the same paving (the Orthoglide's dextrous workspace, eps 0.005) in one process and on a Dask
  LocalCluster of 1 and 2 workers.

Each curve's slope is the least-squares slope of log(cost) against log(work) (for the reach curve, log(width)
against log(seconds)): cost ~ work^slope.  The figures go to stdout as Markdown, to ``--json`` and, with
``--plot``, to one figure of five panels.

Run: python benchmarks/bench_costs.py [pave reach planar symbolic dask] [--limits 10,30,60,120,300,600]
     [--chains 20] [--json costs.json] [--plot docs/site/cost_curves.png]
"""

import argparse
import datetime
import json
import os
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from _common import machine

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CURVES = ("pave", "reach", "planar", "symbolic", "dask")
DELTAS = (0.5, 0.25, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002)
ARMS = ("ur5", "kr16", "iiwa")


def slope(x, y) -> float:
    """Least-squares slope of log y against log x (points with y <= 0 left out)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    keep = (x > 0) & (y > 0)
    if keep.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def child(*args: str) -> dict:
    """One measurement in a cold process: this script with ``run ARGS``; its last line is JSON."""
    proc = subprocess.run([sys.executable, __file__, "run", *args], capture_output=True, text=True, cwd=HERE,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), str(HERE)])})
    if proc.returncode:
        raise RuntimeError(f"run {' '.join(args)} failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


# ------------------------------------------------------------------------------------------------ the children
def run_reach(name: str, limit: float) -> dict:
    sys.path.insert(0, str(ROOT / "tests" / "helpers"))
    from reach_checks import industrial_arm
    from workspace_sym import StopAt, reach
    from workspace_sym.errors import SymbolicBudgetError

    robot = industrial_arm(name)
    t = time.perf_counter()
    try:
        result = reach(robot, delta=0.1, stop=StopAt(time_limit=limit))
    except SymbolicBudgetError:                     # the model was not ready within the limit: no answer
        return {"arm": name, "limit": limit, "seconds": time.perf_counter() - t, "lo": 0.0, "hi": float("inf"),
                "width": 1.0, "method": "none (model not ready)"}
    seconds = time.perf_counter() - t
    lo, hi = result.measure_bounds
    return {"arm": name, "limit": limit, "seconds": seconds, "lo": lo, "hi": hi, "width": (hi - lo) / hi,
            "method": result.method}


def run_symbolic(n: int) -> dict:
    from workspace_sym.kinematics import DHRobot

    table = json.loads((ROOT / "tests" / "data" / "dh" / "panda.json").read_text())
    table = {**table, "joints": table["joints"][:n]}
    table.pop("tool", None)
    out = {"joints": n}
    t = time.perf_counter()
    robot = DHRobot.from_dict(table)
    robot.fk(), robot.jacobian()
    out["fk_jacobian"] = time.perf_counter() - t        # read, fk and Jacobian, cold
    t = time.perf_counter()
    robot.singular_factors("position")
    out["singular_factors"] = time.perf_counter() - t
    t = time.perf_counter()
    robot.characteristic_polynomial("position")
    out["charpoly_3xn"] = time.perf_counter() - t
    return out


def run_dask(mode: str, eps: float) -> dict:
    from workspace_sym import RunOn
    from workspace_sym.interval import executor
    from workspace_sym.orthoglide import Orthoglide

    o = Orthoglide()
    if mode == "process":
        t = time.perf_counter()
        d = o.dextrous(eps=eps)
        seconds = time.perf_counter() - t
    else:
        with executor.connect(f"local:{int(mode.split(':')[1])}") as client:
            client.run(lambda: __import__("workspace_sym.orthoglide"))          # warm workers: imports not timed
            t = time.perf_counter()
            d = o.dextrous(eps=eps, run=RunOn(executor=client))
            seconds = time.perf_counter() - t
    data = d.to_dict()
    return {"mode": mode, "seconds": seconds, "evaluated": data["boxes_evaluated"], "inside": data["volume_inner"]}


# ------------------------------------------------------------------------------------------------ the curves
def pave_curve() -> dict:
    from bench_paving import codac_runs

    from _common import best_of
    from workspace_sym import robots

    model = robots.build("rpr2")
    model.pave(delta=0.5, size="width")                 # compile once
    rows = []
    for delta in DELTAS:
        t, p = best_of(lambda d=delta: model.pave(delta=d, size="width"), repeat=3 if delta >= 0.01 else 1)
        row = {"delta": delta, "ours_s": t, "ours_boxes": int(p.evaluated),
               "ours_leaves": len(p.inner) + len(p.boundary)}
        peers = codac_runs(delta)
        if peers:
            for name, key in (("codac.sivia", "sivia"), ("codac.pave(SepInverse)", "sep")):
                row[f"{key}_s"] = peers[name][0]
                row[f"{key}_boxes"] = peers[name][3] + peers[name][4]        # its inner and boundary boxes
        rows.append(row)
        print(f"  pave delta {delta}: ours {t:.4f} s ({row['ours_boxes']} boxes)"
              + (f", codac.sivia {row['sivia_s']:.4f} s, codac.pave {row['sep_s']:.4f} s" if peers else ""),
              flush=True)
    inv = [1 / r["delta"] for r in rows]
    out = {"rows": rows, "slope_ours_s": slope(inv, [r["ours_s"] for r in rows]),
           "slope_ours_boxes": slope(inv, [r["ours_boxes"] for r in rows])}
    if "sivia_s" in rows[0]:
        out["slope_sivia_s"] = slope(inv, [r["sivia_s"] for r in rows])
        out["slope_sep_s"] = slope(inv, [r["sep_s"] for r in rows])
    return out


def reach_curve(limits) -> dict:
    rows = []
    for name in ARMS:
        for limit in limits:
            r = child("reach", name, str(limit))
            rows.append(r)
            print(f"  reach {name} limit {limit} s: {r['seconds']:.1f} s, [{r['lo']:.4f}, {r['hi']:.4f}], "
                  f"{100 * r['width']:.1f} %", flush=True)
    answered = [r for r in rows if r["hi"] < float("inf")]
    slopes = {name: slope([r["seconds"] for r in answered if r["arm"] == name],
                          [r["width"] for r in answered if r["arm"] == name]) for name in ARMS}
    return {"rows": rows, "slopes": slopes}


def planar_curve(chains: int) -> dict:
    from bench_planar import random_chain

    rng = np.random.default_rng(2018)
    random_chain(rng, 3).boundary()                     # imports and first compilations not timed
    rows = []
    for p in range(2, 13):
        times = []
        for _ in range(chains):
            chain = random_chain(rng, p)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                t = time.perf_counter()
                chain.boundary()
                times.append(time.perf_counter() - t)
        rows.append({"links": p, "median_s": statistics.median(times), "max_s": max(times)})
        print(f"  planar {p} links: median {rows[-1]['median_s']:.4f} s", flush=True)
    return {"rows": rows, "slope": slope([r["links"] for r in rows], [r["median_s"] for r in rows])}


def symbolic_curve() -> dict:
    rows = []
    for n in range(3, 8):
        r = child("symbolic", str(n))
        rows.append(r)
        print(f"  symbolic {n} joints: fk + J {r['fk_jacobian']:.2f} s, singular factors "
              f"{r['singular_factors']:.2f} s, charpoly 3 x n {r['charpoly_3xn']:.2f} s", flush=True)
    joints = [r["joints"] for r in rows]
    return {"rows": rows, **{f"slope_{k}": slope(joints, [r[k] for r in rows])
                             for k in ("fk_jacobian", "singular_factors", "charpoly_3xn")}}


def dask_curve(eps: float = 0.005) -> dict:
    rows = [child("dask", mode, str(eps)) for mode in ("process", "dask:1", "dask:2")]
    for r in rows:
        print(f"  dask {r['mode']}: {r['seconds']:.1f} s, {r['evaluated']} boxes", flush=True)
    same = len({(r["evaluated"], r["inside"]) for r in rows}) == 1
    return {"rows": rows, "same_answer": same, "eps": eps,
            "slope_workers": slope([1, 2], [rows[1]["seconds"], rows[2]["seconds"]])}


# ------------------------------------------------------------------------------------------------ output
def markdown(results: dict) -> str:
    lines = []
    if "pave" in results:
        r = results["pave"]
        lines += ["| delta | ours s | ours boxes evaluated (inner + boundary) | codac.sivia s | codac.sivia boxes "
                  "(inner + boundary) | codac.pave s | codac.pave boxes |", "|---|---|---|---|---|---|---|"]
        for row in r["rows"]:
            lines.append(f"| {row['delta']} | {row['ours_s']:.4f} | {row['ours_boxes']:,} ({row['ours_leaves']:,}) | "
                         f"{row.get('sivia_s', float('nan')):.4f} | {row.get('sivia_boxes', 0):,} | "
                         f"{row.get('sep_s', float('nan')):.4f} | {row.get('sep_boxes', 0):,} |")
        lines.append(f"\nslopes against 1/delta: ours seconds {r['slope_ours_s']:.2f}, "
                     f"boxes {r['slope_ours_boxes']:.2f}"
                     + (f"; codac.sivia {r['slope_sivia_s']:.2f}, codac.pave {r['slope_sep_s']:.2f}"
                        if "slope_sivia_s" in r else "") + "\n")
    if "reach" in results:
        r = results["reach"]
        lines += ["| arm | time limit s | seconds | bracket | width |", "|---|---|---|---|---|"]
        for row in r["rows"]:
            lines.append(f"| {row['arm']} | {row['limit']} | {row['seconds']:.1f} | [{row['lo']:.4f}, {row['hi']:.4f}] "
                         f"| {100 * row['width']:.1f} % |")
        lines.append("\nslopes of log(width) against log(seconds): "
                     + ", ".join(f"{k} {v:.2f}" for k, v in r["slopes"].items()) + "\n")
    if "planar" in results:
        r = results["planar"]
        lines += ["| links | median s | max s |", "|---|---|---|"]
        lines += [f"| {row['links']} | {row['median_s']:.4f} | {row['max_s']:.4f} |" for row in r["rows"]]
        lines.append(f"\nslope against the number of links (log-log): {r['slope']:.2f}\n")
    if "symbolic" in results:
        r = results["symbolic"]
        lines += ["| joints | fk + J s | singular factors s | charpoly 3 x n s |", "|---|---|---|---|"]
        lines += [f"| {row['joints']} | {row['fk_jacobian']:.2f} | {row['singular_factors']:.2f} | "
                  f"{row['charpoly_3xn']:.2f} |" for row in r["rows"]]
        lines.append(f"\nslopes against the number of joints (log-log): fk + J {r['slope_fk_jacobian']:.2f}, "
                     f"singular factors {r['slope_singular_factors']:.2f}, charpoly {r['slope_charpoly_3xn']:.2f}\n")
    if "dask" in results:
        r = results["dask"]
        lines += ["| run | seconds | boxes |", "|---|---|---|"]
        lines += [f"| {row['mode']} | {row['seconds']:.1f} | {row['evaluated']:,} |" for row in r["rows"]]
        lines.append(f"\nsame answer in every run: {r['same_answer']}; "
                     f"slope 1 -> 2 workers: {r['slope_workers']:.2f}\n")
    return "\n".join(lines)


def plot(results: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [k for k in CURVES if k in results]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 3.6), squeeze=False)
    for ax, key in zip(axes[0], panels):
        r = results[key]
        if key == "pave":
            x = [1 / row["delta"] for row in r["rows"]]
            ax.loglog(x, [row["ours_s"] for row in r["rows"]], "o-", label=f"ours ({r['slope_ours_s']:.2f})")
            if "slope_sivia_s" in r:
                ax.loglog(x, [row["sivia_s"] for row in r["rows"]], "s--",
                          label=f"codac.sivia ({r['slope_sivia_s']:.2f})")
                ax.loglog(x, [row["sep_s"] for row in r["rows"]], "^:", label=f"codac.pave ({r['slope_sep_s']:.2f})")
            ax.set(xlabel="1 / delta", ylabel="seconds", title="pave: 2-RPR")
        elif key == "reach":
            for name in ARMS:
                rows = [row for row in r["rows"] if row["arm"] == name]
                ax.loglog([row["seconds"] for row in rows], [100 * row["width"] for row in rows], "o-",
                          label=f"{name} ({r['slopes'][name]:.2f})")
            ax.set(xlabel="seconds (time limit)", ylabel="bracket width, % of upper", title="reach: delta 0.1")
        elif key == "planar":
            ax.semilogy([row["links"] for row in r["rows"]], [row["median_s"] for row in r["rows"]], "o-",
                        label=f"median (log-log slope {r['slope']:.2f})")
            ax.set(xlabel="links", ylabel="seconds", title="planar boundary")
        elif key == "symbolic":
            n = [row["joints"] for row in r["rows"]]
            for k, label in (("fk_jacobian", "fk + J"), ("singular_factors", "singular factors"),
                             ("charpoly_3xn", "charpoly 3 x n")):
                ax.semilogy(n, [row[k] for row in r["rows"]], "o-", label=f"{label} ({r['slope_' + k]:.2f})")
            ax.set(xlabel="joints (Panda's first rows)", ylabel="seconds", title="symbolic")
        else:
            ax.bar([row["mode"] for row in r["rows"]], [row["seconds"] for row in r["rows"]])
            ax.set(ylabel="seconds", title=f"Dask: Orthoglide eps {r['eps']}")
        if key != "dask":
            ax.legend(fontsize=7)
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    if sys.argv[1:2] == ["run"]:
        kind, *args = sys.argv[2:]
        fn = {"reach": lambda: run_reach(args[0], float(args[1])), "symbolic": lambda: run_symbolic(int(args[0])),
              "dask": lambda: run_dask(args[0], float(args[1]))}[kind]
        print(json.dumps(fn()))
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("curves", nargs="*", help=f"any of {', '.join(CURVES)} (default: all)")
    ap.add_argument("--limits", default="10,30,60,120,300,600")
    ap.add_argument("--chains", type=int, default=20)
    ap.add_argument("--json", default=None)
    ap.add_argument("--plot", default=None)
    args = ap.parse_args()
    unknown = set(args.curves) - set(CURVES)
    if unknown:
        ap.error(f"unknown curves {sorted(unknown)}: expected any of {', '.join(CURVES)}")
    print(f"# bench_costs  {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC  {machine()}  "
          f"load {os.getloadavg()[0]:.2f}", flush=True)
    results = {}
    for curve in args.curves or CURVES:
        print(f"## {curve}", flush=True)
        if curve == "pave":
            results["pave"] = pave_curve()
        elif curve == "reach":
            results["reach"] = reach_curve([float(x) for x in args.limits.split(",")])
        elif curve == "planar":
            results["planar"] = planar_curve(args.chains)
        elif curve == "symbolic":
            results["symbolic"] = symbolic_curve()
        else:
            results["dask"] = dask_curve()
    print(f"\nload at the end {os.getloadavg()[0]:.2f}\n")
    print(markdown(results))
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1))
    if args.plot:
        plot(results, args.plot)


if __name__ == "__main__":
    main()
