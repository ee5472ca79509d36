"""Bastien (2018), figure 7 redone: time of the alignment method (Steps 0-2) on random planar chains.

For each p = 2..12, ``--chains`` random chains (lengths uniform in [0.1, 1], limits uniform in
(-179, 179) degrees, sorted) are solved from scratch; the script prints the median and 95th
percentile time per p, the mean arc counts of each step, the number of faces left undecided,
and draws a log-time plot.  Paper (Matlab, i5-6300HQ): under 0.1 s up to p = 4, 95 % under
1 s at p = 6, about 7 min at p = 11 and over 50 min at p = 12.

    python benchmarks/bench_planar.py [--chains 200] [--pmax 12] [--plot benchmarks/planar_times.png]
"""

import argparse
import datetime
import time
import warnings

import numpy as np

from _common import machine
from workspace_sym.planar import PlanarChain

GOALS = {6: "median < 0.1 s, 95 % < 0.3 s", 11: "median < 20 s", 12: "< 60 s"}
PAPER = {4: "< 0.1 s", 6: "95 % < 1 s", 11: "about 7 min", 12: "over 50 min"}


def random_chain(rng, p):
    limits = np.sort(rng.uniform(-179, 179, (p, 2)), axis=1)
    return PlanarChain(rng.uniform(0.1, 1.0, p), limits[:, 0], limits[:, 1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--chains", type=int, default=200)
    ap.add_argument("--pmin", type=int, default=2)
    ap.add_argument("--pmax", type=int, default=12)
    ap.add_argument("--seed", type=int, default=2018)
    ap.add_argument("--plot", default=None)
    args = ap.parse_args()
    print(f"# planar boundary benchmark, {datetime.date.today()}, {machine()}")
    print(f"{'p':>3} {'chains':>6} {'median s':>9} {'95% s':>8} {'max s':>8} {'step0':>8} {'step1':>6} {'step2':>5} "
          f"{'undecided':>9}  goal / paper")
    rng = np.random.default_rng(args.seed)
    rows = {}
    for p in range(args.pmin, args.pmax + 1):
        times, counts, undecided = [], [], 0
        for _ in range(args.chains):
            chain = random_chain(rng, p)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                t = time.perf_counter()
                b = chain.boundary()
                times.append(time.perf_counter() - t)
            undecided += any("could not be classified" in str(w.message) for w in caught)
            counts.append((b.counts["step0"], b.counts["step1"], b.counts["step2"]))
        t = np.array(times)
        c = np.mean(counts, axis=0)
        rows[p] = t
        note = " / ".join(x for x in (GOALS.get(p), PAPER.get(p)) if x)
        print(f"{p:>3} {len(t):>6} {np.median(t):>9.4f} {np.percentile(t, 95):>8.4f} {t.max():>8.3f} {c[0]:>8.0f} "
              f"{c[1]:>6.0f} {c[2]:>5.1f} {undecided:>9}  {note}", flush=True)
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4))
        ps = sorted(rows)
        ax.boxplot([rows[p] for p in ps], positions=ps, whis=(5, 95), showfliers=False)
        ax.plot(ps, [np.median(rows[p]) for p in ps], "o-", label="median")
        ax.set_yscale("log")
        ax.set_xlabel("p (joints)")
        ax.set_ylabel("time per chain (s)")
        ax.set_title("alignment method, Steps 0-2 (cf. Bastien 2018, figure 7)")
        ax.legend()
        fig.savefig(args.plot, dpi=110, bbox_inches="tight")
        print(f"plot: {args.plot}")


if __name__ == "__main__":
    main()
