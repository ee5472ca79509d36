"""Symbolic kinematics benchmarks.

Issue 2: FK + geometric Jacobian of the 6R glass arm in textbook form against plain
sympy.simplify of the DH product (same run), and numeric FK of 10^6 configurations.
Issue 18: per robot (glass arm, Puma 560, UR5, Panda) the cold times of fk + J, singular
factors and the characteristic polynomial of J J^T (3 x n position and 6 x n geometric),
with the size of T against sympy.simplify of the raw DH product in the same run.

The 6 x n column also gives how many minors stayed unexpanded determinants (not factored within their share of
the budget; exact all the same) and the largest relative difference of the polynomial's roots from numpy's
eigenvalues of J J^T at 3 random configurations.

Run: python benchmarks/bench_kinematics.py [--skip-panda-simplify] [--skip-panda-6xn]
"""

import datetime
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp

from _common import best_of, machine
from workspace_sym import robots
from workspace_sym.kinematics import DHRobot, dh_matrix, eigenvalues_from_charpoly

TABLES = Path(__file__).resolve().parents[1] / "tests" / "data" / "dh"


def textbook_fk_and_jacobian():
    robot = robots.build("glass-handling")  # fresh: nothing cached
    return robot.fk(), robot.geometric_jacobian


def plain_simplify():
    robot = robots.build("glass-handling")
    T = sp.eye(4)
    for j in robot.joints:
        T = T * dh_matrix(j.theta, j.d, j.a, j.alpha)
    return sp.simplify(T)


def main():
    print(f"# bench_kinematics  {datetime.date.today()}  {machine()}")
    t_ours, (T, J) = best_of(textbook_fk_and_jacobian, repeat=3)
    t0 = time.perf_counter()
    T_plain = plain_simplify()
    t_plain = time.perf_counter() - t0
    ops = lambda M: sum(sp.count_ops(e) for e in M)  # noqa: E731
    print(f"glass arm FK + geometric Jacobian, textbook form : {t_ours:7.3f} s  ({ops(T)} ops in T)")
    print(f"plain sympy.simplify of the DH product (FK only)  : {t_plain:7.3f} s  ({ops(T_plain)} ops in T)")
    print(f"  ratio ours / plain: {t_ours / t_plain:.3f}  (goal < 0.5, aim: ours < 1 s)")
    print(f"  plain simplify x = {T_plain[0, 3]}")
    robot = robots.build("glass-handling")
    f = robot.fk_numeric
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (1_000_000, 6))
    f(q[:10])
    t_num, _ = best_of(lambda: f(q), repeat=3)
    print(f"numeric FK, 10^6 configurations (4x4 each)        : {t_num:7.3f} s  (goal < 0.5 s)")


def _ops(M):
    return sum(sp.count_ops(e) for e in M)


def _root_error(robot, poly, points=3):
    """Largest difference of the roots of ``poly`` from numpy's eigenvalues of J J^T, relative to the largest."""
    Jf = robot.numeric(robot.geometric_jacobian)
    rng = np.random.default_rng(1)
    worst = 0.0
    for _ in range(points):
        q = rng.uniform(-np.pi, np.pi, robot.n)
        J = Jf(q)
        expected = np.linalg.eigvalsh(J @ J.T)
        ours = eigenvalues_from_charpoly(poly, {**robot.parameters, **dict(zip(robot.q, q))})
        worst = max(worst, float(np.max(np.abs(ours - expected)) / max(1.0, expected.max())))
    return worst


def robot_table(skip_panda_simplify: bool = False, skip_panda_6xn: bool = False):
    """One cold robot per row (nothing cached between the columns' first calls)."""
    print("\nrobot | fk + J | singular factors | charpoly 3 x n | charpoly 6 x n | T ops (ours / simplify, time)")
    for name in ("glass-handling", "puma560", "ur5", "panda"):
        build = (lambda n=name: robots.build(n)) if name in ("glass-handling", "puma560") else \
            (lambda n=name: DHRobot.from_file(TABLES / f"{n}.json"))
        robot = build()
        t_fk, (T, _) = best_of(lambda r=robot: (r.fk(), r.geometric_jacobian), repeat=1)
        t_sing, factors = best_of(lambda r=robot: r.singular_factors(multiplicity=True), repeat=1)
        t_pos, _ = best_of(lambda r=robot: r.characteristic_polynomial("position"), repeat=1)
        if skip_panda_6xn and name == "panda":
            geo = "skipped"
        else:
            t_geo, P = best_of(lambda r=robot: r.characteristic_polynomial("geometric"), repeat=1)
            dets = len(P.as_expr().atoms(sp.Determinant))
            geo = (f"{t_geo:.2f} s ({_ops(P.all_coeffs())} ops, {dets} determinants, "
                   f"{_root_error(robot, P):.1e} from numpy)")
        if skip_panda_simplify and name == "panda":
            simp = "skipped"
        else:
            t_s, S = best_of(lambda r=robot: sp.simplify(r.raw_fk()), repeat=1)
            simp = f"{_ops(S)}, {t_s:.1f} s"
        print(f"{robot.name} | {t_fk:.2f} s | {t_sing:.2f} s ({len(factors)} factors) | {t_pos:.2f} s | "
              f"{geo} | {_ops(T)} / {simp}", flush=True)


if __name__ == "__main__":
    main()
    robot_table(skip_panda_simplify="--skip-panda-simplify" in sys.argv, skip_panda_6xn="--skip-panda-6xn" in sys.argv)
