"""Issue 4 benchmark: Orthoglide dextrous workspace, sigma in [0.25, 4] (Chablat, Wenger, Merlet 2002:
eps = 0.05 gives volume 1.468 with E in [0, 0.48] in about 5 hours, Maple + C++), and the largest cube.
At eps = 0.05 also without shaving the last-level boxes (the paper's plain bisection) and with finer slabs
(issue 28 item 2).

Run: python benchmarks/bench_orthoglide.py [eps ...]
"""

import cProfile
import datetime
import pstats
import subprocess
import sys
import time
from pathlib import Path

from _common import machine
from workspace_sym.orthoglide import Orthoglide
from workspace_sym.orthoglide.certificate import SHAVE


def dextrous_row(o, eps, shave):
    d = o.dextrous(eps=eps, shave=shave).to_dict()
    ratio = f"{100 * d['volume_undecided'] / d['volume_inner']:.1f} %" if d["volume_inner"] else "-"
    print(f"eps = {eps}, shave {shave}: {d['seconds']:.1f} s, {d['boxes_evaluated']} boxes evaluated, inside "
          f"{d['volume_inner']:.4f} ({d['boxes']['inner']} boxes), E {d['volume_undecided']:.4f} "
          f"({d['boxes']['undecided']} boxes), E / inside {ratio}, "
          f"outside {d['boxes']['outer']} boxes", flush=True)


def main(epsilons):
    print(f"# bench_orthoglide  {datetime.date.today()}  {machine()}")
    o = Orthoglide()
    print("paper, eps = 0.05: inside 1.468, E = 0.48, about 5 h")
    for shave in ((), (0.5, 0.25)):            # the paper's plain bisection, and a finer shaving than the default
        dextrous_row(o, 0.05, shave)
    for eps in epsilons:
        dextrous_row(o, eps, SHAVE)
    print("paper, largest cube (alpha = 0.001): centre 0.085938 (x = y = z), edge 0.643950, none above 0.643952")
    for alpha in (0.001, 1e-6, 1e-9):
        r = o.largest_cube(alpha=alpha)
        c = r.to_dict()
        print(f"cube, alpha = {alpha:g}: {c['seconds']:.2f} s, centre {c['center'][0]:.9f}, edge in "
              f"[{c['edge_lower']:.10f}, {c['edge_upper']:.10f}], boxes {c['boxes']}")
    print(f"closed form: {r.closed_form}")
    exe = Path(sys.executable).with_name("workspace-sym")
    t = time.perf_counter()
    subprocess.run([str(exe), "cube", "orthoglide", "--alpha", "1e-6"], check=True, capture_output=True)
    print(f"`workspace-sym cube orthoglide --alpha 1e-6` from a cold start: {time.perf_counter() - t:.1f} s wall")
    prof = cProfile.Profile()
    prof.runcall(o.dextrous, eps=0.05)
    print("profile at eps = 0.05 (top 8 by own time; the two threads' work shows in the main thread's waits):")
    pstats.Stats(prof, stream=sys.stdout).sort_stats("tottime").print_stats(8)


if __name__ == "__main__":
    main([float(a) for a in sys.argv[1:]] or [0.25, 0.125, 0.05, 0.01, 0.005, 0.0025])
