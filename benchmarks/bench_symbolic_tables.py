"""Symbolic kinematics of random 6-joint DH tables (issue 29).

Tables: R or P joints, theta offsets and twists drawn in whole degrees in (-180, 180], lengths a and d
decimals with 1 to 3 digits, a tool with rpy in whole degrees (the issue's shape). Per table, cold: fk +
geometric Jacobian, singular factors (under a 30 s budget: the result or "not factored within budget"),
the 3 x n characteristic polynomial of J J^T (same budget; its minors factored until their share of the budget
is spent, the rest kept as exact unexpanded determinants, counted), and the size of T against the raw DH product.
Targets: fk + J < 5 s, singular factors < 30 s or an explicit budget message, charpoly 3 x n < 30 s.

Also: the DH lengths (l1 + 1)**1000 and (l1 + l2 + 1)**60 of issue 23 item 7 (fk, Jacobian, singular factors,
charpoly: seconds to a result or to the one SymbolicBudgetError), and a cold reach of the UR5 with a 4 s time
limit (issue 31 item 3: wall time to its end, result or error).

Run: python benchmarks/bench_symbolic_tables.py [--tables 5] [--seed 0] [--budget 30]
"""

import argparse
import datetime
import random
import time

import sympy as sp

from _common import machine
from workspace_sym import StopAt, symbolic
from workspace_sym.errors import SymbolicError
from workspace_sym.kinematics import DHRobot


def random_table(seed: int, n: int = 6) -> dict:
    rng = random.Random(seed)
    def length():
        return round(rng.uniform(0, 1), rng.choice([1, 2, 3]))

    joints = [{"type": rng.choice("RRRP"), "theta": rng.randint(-179, 180), "alpha": rng.randint(-179, 180),
               "a": length(), "d": length()} for _ in range(n)]
    return {"joints": joints, "tool": {"xyz": [0.1, 0, 0.05], "rpy": [rng.randint(-90, 90) for _ in range(3)]}}


ISSUE_TABLE = {   # issue 29 item 3: mixed R/P, offsets 120, -25, 75, 97, twists 60 .. -105, tool rpy (-31, 7, -78)
    "joints": [{"type": "R", "theta": 120, "alpha": 60, "a": 0.3, "d": 0.4},
               {"type": "P", "theta": -25, "alpha": 150, "a": 0.25, "d": 0.1},
               {"type": "R", "theta": 75, "alpha": -60, "a": 0.425, "d": 0.0},
               {"type": "R", "theta": 97, "alpha": 135, "a": 0.1, "d": 0.39225},
               {"type": "P", "theta": 0, "alpha": 15, "a": 0.05, "d": 0.2},
               {"type": "R", "theta": 0, "alpha": -105, "a": 0.0, "d": 0.0823}],
    "tool": {"xyz": [0.0, 0.0, 0.1], "rpy": [-31, 7, -78]}}


def timed(fn, budget):
    start = time.perf_counter()
    try:
        with symbolic.symbolic_budget(budget, "bench"):
            out = fn()
        return time.perf_counter() - start, out, None
    except SymbolicError as exc:
        return time.perf_counter() - start, None, str(exc).split(":")[-1].strip()


def _unfactored(poly) -> str:
    """How many minors stayed exact unexpanded determinants (not factored within their share of the budget)."""
    dets = len(poly.as_expr().atoms(sp.Determinant))
    return "all minors factored" if not dets else f"{dets} minors kept as determinants"


def ops(M):
    return sum(sp.count_ops(e) for e in M)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tables", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--budget", type=float, default=30.0)
    args = ap.parse_args()
    print(f"# bench_symbolic_tables  {datetime.date.today()}  {machine()}")
    print("table | fk + J | singular factors | charpoly 3 x n | ops in T: ours / raw product | longer entries")
    tables = [("issue 29", ISSUE_TABLE)] + [(f"seed {args.seed + k}", random_table(args.seed + k))
                                            for k in range(args.tables)]
    for name, data in tables:
        robot = DHRobot.from_dict(data)
        t_fk, out, err = timed(lambda r=robot: (r.fk(), r.geometric_jacobian), 10 * args.budget)
        if err:
            print(f"{name} | {t_fk:.2f} s: {err} | - | - | - | -", flush=True)
            continue
        T, raw = out[0], robot.raw_fk()
        longer = sum(sp.count_ops(a) > sp.count_ops(b) for a, b in zip(T, raw))
        t_sing, pairs, err_s = timed(lambda r=robot: r.singular_factors(multiplicity=True), args.budget)
        sing = f"{t_sing:.2f} s ({len(pairs)} factors)" if err_s is None else f"{t_sing:.2f} s, {err_s}"
        t_cp, P, err_c = timed(lambda r=robot: r.characteristic_polynomial("position"), args.budget)
        cp = f"{t_cp:.2f} s, {_unfactored(P)}" if err_c is None else f"{t_cp:.2f} s, {err_c}"
        print(f"{name} | {t_fk:.2f} s | {sing} | {cp} | {ops(T)} / {ops(raw)} | {longer} of 16", flush=True)
    print("huge length | fk + J + singular factors + charpoly | outcome")
    for length in ("(l1 + 1)**1000", "(l1 + l2 + 1)**60"):
        robot = DHRobot.from_dict({"joints": [{"type": "R", "theta": 0, "d": 0, "a": length, "alpha": 0},
                                              {"type": "R", "theta": 0, "d": 0, "a": "l1", "alpha": 0}]})
        t, out, err = timed(lambda r=robot: (r.fk(), r.geometric_jacobian, r.singular_factors(),
                                             r.characteristic_polynomial("position")), args.budget)
        print(f"{length} | {t:.2f} s | {err or f'factors {out[2]}'}", flush=True)
    from pathlib import Path

    from workspace_sym.serial import reach

    path = Path(__file__).resolve().parent.parent / "tests" / "data" / "dh" / "ur5.json"
    start = time.perf_counter()
    try:
        paving = reach(DHRobot.from_file(path), delta=0.05, stop=StopAt(time_limit=4.0, progress=False))
        outcome = f"paving, complete={paving.complete}, {len(paving.pending)} pending"
    except SymbolicError as exc:
        outcome = f"SymbolicBudgetError: {str(exc)[:80]}"
    print(f"cold UR5 reach, time limit 4 s | {time.perf_counter() - start:.2f} s | {outcome}", flush=True)


if __name__ == "__main__":
    main()
