"""Issue 2 benchmark: symbolic FK + geometric Jacobian of the 6R glass arm in textbook form,
against plain sympy.simplify of the DH product (same run), and numeric FK of 10^6 configurations.

Run: python benchmarks/bench_kinematics.py
"""

import datetime
import time

import numpy as np
import sympy as sp

from _common import best_of, machine
from workspace_sym import robots
from workspace_sym.kinematics import dh_matrix


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


if __name__ == "__main__":
    main()
