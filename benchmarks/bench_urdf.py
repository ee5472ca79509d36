"""Issue 16 benchmark: cold command-line time of `fk` + `jacobian` (with singular factors) for the URDF
robots of the rtb-data package, and the float Puma DH table against the exact one.

Each figure is one fresh `python -m workspace_sym` process (import, URDF parse, DH extraction, symbolic
work, printing): what a user waits for.  Run once: python benchmarks/bench_urdf.py
"""

import datetime
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import rtbdata

from _common import machine

XACRO = Path(rtbdata.__file__).parent / "xacro"
ROBOTS = [
    ("ABB IRB140", XACRO / "abb_irb140_description/urdf/irb140.urdf", []),
    ("KUKA KR16-2", XACRO / "kuka_description/kuka_kr16/urdf/kr16_2.urdf", []),
    ("KUKA KR210 L150", XACRO / "kuka_description/kuka_kr210/urdf/kr210l150.urdf", ["--tip", "tool0"]),
    ("KUKA LBR iiwa 14 R820", XACRO / "kuka_description/kuka_lbr_iiwa/urdf/lbr_iiwa_14_r820.urdf", []),
]
PUMA = [(0, 0, math.pi / 2), (0, 0.4318, 0.0), (0.15005, 0.0203, -math.pi / 2), (0.4318, 0, math.pi / 2),
        (0, 0, -math.pi / 2), (0, 0, 0.0)]


def cold(*args) -> tuple[float, str]:
    """Wall time of one fresh process and its JSON's seconds field."""
    t = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "workspace_sym", *args, "--json"], capture_output=True, text=True,
                         check=True).stdout
    return time.perf_counter() - t, json.loads(out)


def main():
    print(f"# bench_urdf  {datetime.date.today()}  {machine()}")
    print("robot | fk cold (s) | jacobian + singular cold (s) | singular factors")
    for name, path, extra in ROBOTS:
        t_fk, _ = cold("fk", "--urdf", str(path), *extra)
        t_j, data = cold("jacobian", "--urdf", str(path), *extra)
        print(f"{name} | {t_fk:.1f} | {t_j:.1f} | {len(data['singular'])}: {', '.join(data['textbook']['singular'])}")
    with tempfile.TemporaryDirectory() as tmp:
        for label, alpha in (("float", lambda a: a), ("exact", lambda a: f"{a / math.pi:+}*pi" if a else 0)):
            rows = [{"d": d, "a": a, "alpha": alpha(al)} for d, a, al in PUMA]
            if label == "exact":
                rows = [{"d": str(d), "a": str(a), "alpha": alpha(al)} for d, a, al in PUMA]
            path = Path(tmp) / f"puma_{label}.json"
            path.write_text(json.dumps({"angles": "radians", "joints": rows}))
            t_fk, _ = cold("fk", "--dh", str(path))
            t_j, data = cold("jacobian", "--dh", str(path))
            print(f"Puma 560 DH, {label} | {t_fk:.1f} | {t_j:.1f} | {', '.join(data['textbook']['singular'])}")


if __name__ == "__main__":
    main()
