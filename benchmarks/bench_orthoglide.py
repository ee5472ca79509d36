"""Issue 4 benchmark: Orthoglide dextrous workspace, sigma in [0.25, 4] (Chablat, Wenger, Merlet 2002:
eps = 0.05 gives volume 1.468 with E in [0, 0.48] in about 5 hours, Maple + C++).

Run: python benchmarks/bench_orthoglide.py [eps ...]
"""

import cProfile
import datetime
import pstats
import sys
import time

from _common import machine
from workspace_sym.orthoglide import Orthoglide


def main(epsilons):
    print(f"# bench_orthoglide  {datetime.date.today()}  {machine()}")
    o = Orthoglide()
    t = time.perf_counter()
    o._compiled(0.25, 4.0)
    print(f"symbolic model and compiled evaluators: {time.perf_counter() - t:.1f} s (once per sigma range)")
    print("paper, eps = 0.05: inside 1.468, E = 0.48, about 5 h")
    for eps in epsilons:
        r = o.dextrous(eps=eps)
        d = r.to_dict()
        print(f"eps = {eps}: {d['seconds']:.1f} s, {d['boxes_evaluated']} boxes evaluated, inside "
              f"{d['volume_inner']:.4f} ({d['boxes']['inner']} boxes), E {d['volume_undecided']:.4f} "
              f"({d['boxes']['undecided']} boxes), outside {d['boxes']['outer']} boxes")
    print("paper, largest cube (alpha = 0.001): centre 0.085938 (x = y = z), edge 0.643950, none above 0.643952")
    for alpha in (0.01, 0.001):
        c = o.largest_cube(alpha=alpha).to_dict()
        print(f"cube, alpha = {alpha}: {c['seconds']:.1f} s, centre {c['center'][0]:.6f}, edge in "
              f"[{c['edge_lower']:.6f}, {c['edge_upper']:.6f}], boxes {c['boxes']}")
    prof = cProfile.Profile()
    prof.runcall(o.dextrous, eps=0.125)
    print("profile at eps = 0.125 (top 6 by own time):")
    pstats.Stats(prof, stream=sys.stdout).sort_stats("tottime").print_stats(6)


if __name__ == "__main__":
    main([float(a) for a in sys.argv[1:]] or [0.25, 0.125, 0.05])
