"""Issue 3 benchmark: Rybak's 2-RPR robot (l_min = 8, l_max = 12, l0 = 5, box [-12, 17] x [0, 12]).

Ours (numpy engine) against the paper's timings (Rybak et al. 2016: 0.9 / 2.4 / 6.6 s at
delta = 0.5 / 0.25 / 0.07, Python on a 2.2 GHz i7) and against codac 2.x run in this
process: codac.sivia and codac.pave(SepInverse).  codac's eps bounds the largest edge
of a box, so ours runs with size="width" for the side-by-side comparison and with the
paper's diameter as well; ``contract=True`` (forward-backward contraction, the
counterpart of SepInverse) runs with the width.  Needs the bench extra (pip install -e .[bench]).

Run: python benchmarks/bench_paving.py
"""

import datetime
import subprocess
import sys

from _common import best_of, machine
from workspace_sym import robots

PAPER = {0.5: 0.9, 0.25: 2.4, 0.07: 6.6}


def codac_runs(delta):
    try:
        import codac as C
    except ImportError:
        return None
    x = C.VectorVar(2)
    f = C.AnalyticFunction([x], C.vec(C.sqr(x[0]) + C.sqr(x[1]), C.sqr(x[0] - 5) + C.sqr(x[1])))
    X0 = C.IntervalVector([[-12, 17], [0, 12]])
    Y = C.IntervalVector([[64, 144], [64, 144]])

    def area(boxes):
        return sum((b[0].ub() - b[0].lb()) * (b[1].ub() - b[1].lb()) for b in boxes)

    out = {}
    for name, run in (("codac.sivia", lambda: C.sivia(X0, f, Y, delta)),
                      ("codac.pave(SepInverse)", lambda: C.pave(X0, C.SepInverse(f, Y), delta))):
        t, p = best_of(run, repeat=10)
        inner, bound = p.boxes(C.PavingInOut.inner), p.boxes(C.PavingInOut.bound)
        out[name] = (t, area(inner), area(bound), len(inner), len(bound))
    return out


OURS_COLD = """
import time
from workspace_sym import robots
model = robots.build("rpr2")
t0 = time.perf_counter()
p = model.pave(delta={delta}, size="width")
print(p.seconds, time.perf_counter() - t0)
"""

CODAC_COLD = """
import time
import codac as C
t0 = time.perf_counter()
x = C.VectorVar(2)
f = C.AnalyticFunction([x], C.vec(C.sqr(x[0]) + C.sqr(x[1]), C.sqr(x[0] - 5) + C.sqr(x[1])))
C.sivia(C.IntervalVector([[-12, 17], [0, 12]]), f, C.IntervalVector([[64, 144], [64, 144]]), {delta})
print(time.perf_counter() - t0)
"""


def cold(script: str, delta: float, repeat: int = 10) -> list[float]:
    """Best of ``repeat`` fresh processes for each figure the script prints: the time the process itself reports
    for its first paving (ours: the paving's ``seconds``, then the whole ``pave`` call with the parsing and
    compiling of the constraints; codac: building the function plus ``sivia``), imports excluded on both
    sides."""
    runs = [subprocess.run([sys.executable, "-c", script.format(delta=delta)], capture_output=True, text=True,
                           check=True) for _ in range(repeat)]
    return [min(column) for column in zip(*(map(float, r.stdout.split()) for r in runs))]


def cold_rows():
    """Issue 28 item 3: the first paving in a process, ours against codac.sivia's, at delta 0.07 and 0.01:
    ``{delta: (ours seconds, ours whole call, codac)}``."""
    try:
        import codac  # noqa: F401
    except ImportError:
        print("  (codac not installed: no cold comparison)")
        return {}
    print("cold start (fresh process, best of 10), width:")
    out = {}
    for delta in (0.07, 0.01):
        (ours, call), (theirs,) = cold(OURS_COLD, delta), cold(CODAC_COLD, delta)
        out[delta] = (ours, call, theirs)
        print(f"{delta:>6} workspace_sym {ours:.4f} s (whole pave call {call:.4f} s)   codac.sivia {theirs:.4f} s   "
              f"{theirs / ours:.1f}x faster ({theirs / call:.1f}x by the whole call)")
    return out


def summary(warm: dict, cold_: dict):
    """One table of what issue 28 item 3 asks, from this run: warm and cold against codac.sivia, and the
    contracted boundary against codac.pave(SepInverse) at every delta."""
    print()
    print("| delta | ours warm (width) | codac.sivia warm | ratio | ours cold | codac.sivia cold | ratio "
          "| boundary: ours contract vs codac.pave(SepInverse) |")
    print("|---|---|---|---|---|---|---|---|")
    for delta, (ours, sivia, bd, bd_sep) in warm.items():
        c = cold_.get(delta)
        cold_cells = (f"{c[0]:.4f} | {c[2]:.4f} | {c[2] / c[0]:.1f}x" if c else " | | ")
        verdict = "smaller" if bd < bd_sep else "codac smaller"
        print(f"| {delta} | {ours:.4f} | {sivia:.4f} | {sivia / ours:.1f}x | {cold_cells} | {bd:.4f} vs {bd_sep:.4f} "
              f"({verdict}) |")


def main():
    print(f"# bench_paving  {datetime.date.today()}  {machine()}")
    model = robots.build("rpr2")
    exact = float(model.exact_measure)
    print(f"exact area {exact:.6f}")
    model.pave(delta=0.5)  # compile once
    header = f"{'delta':>6} {'method':<34} {'seconds':>9} {'inner area':>11} {'boundary area':>14} {'boxes in/bd':>14}"
    print(header)
    warm = {}
    for delta in (0.5, 0.25, 0.07, 0.01):
        rows = []
        for size, contract in (("diameter", False), ("width", False), ("width", True)):
            t, p = best_of(lambda d=delta, s=size, c=contract: model.pave(delta=d, size=s, contract=c), repeat=10)
            m = p.measures
            assert m["inner"] <= exact <= m["inner"] + m["boundary"]
            name = f"workspace_sym ({size}{', contract' if contract else ''})"
            rows.append((name, t, m["inner"], m["boundary"], len(p.inner), len(p.boundary)))
        if delta in PAPER:
            rows.append(("paper (Rybak et al. 2016)", PAPER[delta], float("nan"), float("nan"), 0, 0))
        peers = codac_runs(delta)
        if peers is None:
            print("  (codac not installed: pip install -e .[bench])")
        else:
            for name, (t, a_in, a_bd, n_in, n_bd) in peers.items():
                rows.append((name, t, a_in, a_bd, n_in, n_bd))
        for name, t, a_in, a_bd, n_in, n_bd in rows:
            print(f"{delta:>6} {name:<34} {t:>9.4f} {a_in:>11.4f} {a_bd:>14.4f} {n_in:>6}/{n_bd:<7}")
        if peers is not None:
            plain, cut = rows[1], rows[2]
            sivia, sep = peers["codac.sivia"], peers["codac.pave(SepInverse)"]
            print(f"{'':>6} plain vs codac.sivia at the same width: {sivia[0] / plain[1]:.1f}x faster, boundary "
                  f"{plain[3]:.4f} vs {sivia[2]:.4f}")
            print(f"{'':>6} contract vs codac.pave(SepInverse): {sep[0] / cut[1]:.1f}x faster, boundary "
                  f"{cut[3]:.4f} vs {sep[2]:.4f}")
            warm[delta] = (plain[1], sivia[0], cut[3], sep[2])
    cold_ = cold_rows()
    if warm:
        summary(warm, cold_)


if __name__ == "__main__":
    main()
