"""Issue 27 benchmark: evaluations per second of the generated C (workspace_sym.codegen) against the numpy
evaluators ``fk_numeric`` / ``jacobian_numeric``, on the same batch of configurations.

The C is compiled with ``cc -std=c99 -O2`` together with a small driver that loops over the batch, so one ctypes
call times N evaluations; a Python loop of one ctypes call per configuration is timed too (what a caller without
a driver gets).  The largest difference from numpy over the batch is printed beside each figure.
Run once: python benchmarks/bench_codegen.py [N]
"""

import ctypes
import datetime
import os
import subprocess
import sys
import tempfile
from functools import partial
from pathlib import Path

import numpy as np

from _common import best_of, machine
from workspace_sym import DHRobot, robots

DH = Path(__file__).parents[1] / "tests" / "data" / "dh"
ROBOTS = [("glass-handling", lambda: robots.build("glass-handling")), ("puma560", lambda: robots.build("puma560")),
          ("UR5", lambda: DHRobot.from_file(DH / "ur5.json")), ("Panda", lambda: DHRobot.from_file(DH / "panda.json"))]
DRIVER = """
#include "{header}"
void run_fk(const double *qs, long count, double *out) {{
    for (long i = 0; i < count; ++i) fk(qs + i * {n}, out + 16 * i);
}}
void run_jacobian(const double *qs, long count, double *out) {{
    for (long i = 0; i < count; ++i) jacobian(qs + i * {n}, out + {size} * i);
}}
"""
DOUBLE_P = ctypes.POINTER(ctypes.c_double)


def compile_robot(robot, directory: Path) -> ctypes.CDLL:
    header, source = robot.codegen(out=directory)
    driver = directory / "driver.c"
    driver.write_text(DRIVER.format(header=header.name, n=robot.n, size=6 * robot.n))
    lib = directory / "libbench.so"
    subprocess.run(["cc", "-std=c99", "-O2", "-shared", "-fPIC", "-o", str(lib), str(source), str(driver), "-lm"],
                   check=True)
    lib = ctypes.CDLL(str(lib))
    for name in ("run_fk", "run_jacobian"):
        getattr(lib, name).argtypes = [DOUBLE_P, ctypes.c_long, DOUBLE_P]
    for name in ("fk", "jacobian"):
        getattr(lib, name).argtypes = [DOUBLE_P, DOUBLE_P]
    return lib


def rate(seconds: float, count: int) -> str:
    return f"{count / seconds / 1e6:.2f} M/s"


def per_call(fn, rows, out) -> None:
    """One ctypes call per configuration."""
    for q in rows:
        fn(q, out)


def measure(lib, what: str, numeric, qs: np.ndarray, size: int) -> str:
    """One table row's figures: numpy, the C driver loop, a ctypes call per configuration, the largest difference."""
    count = len(qs)
    numeric(qs[:10])                                     # lambdify once, outside the timing
    t_np, ref = best_of(partial(numeric, qs))
    out = np.empty((count, size))
    run = getattr(lib, f"run_{what}")
    t_c, _ = best_of(partial(run, qs.ctypes.data_as(DOUBLE_P), count, out.ctypes.data_as(DOUBLE_P)))
    err = float(np.abs(out - ref.reshape(count, size)).max())
    few, single = qs[:count // 10], np.empty(size)
    rows = [q.ctypes.data_as(DOUBLE_P) for q in few]
    t_call, _ = best_of(partial(per_call, getattr(lib, what), rows, single.ctypes.data_as(DOUBLE_P)))
    return f"{rate(t_np, count)} | {rate(t_c, count)} | {rate(t_call, len(few))} | {err:.1e}"


def main():
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    print(f"# bench_codegen  {datetime.date.today()}  {machine()}  N = {count}, best of 3, load average {load}")
    print("robot | what | numpy (fk_numeric / jacobian_numeric) | C, driver loop | C, ctypes call per configuration "
          "(N/10) | max |C - numpy|")
    rng = np.random.default_rng(0)
    for label, build in ROBOTS:
        robot = build()
        with tempfile.TemporaryDirectory() as tmp:
            lib = compile_robot(robot, Path(tmp))
            qs = np.ascontiguousarray(rng.uniform(-np.pi, np.pi, size=(count, robot.n)))
            print(f"{label} | fk | {measure(lib, 'fk', robot.fk_numeric, qs, 16)}")
            print(f"{label} | jacobian | {measure(lib, 'jacobian', robot.jacobian_numeric, qs, 6 * robot.n)}")


if __name__ == "__main__":
    main()
