"""Issue 24 item 1 benchmark: the critical-set method for any serial position map into space.

Prints, per case: seconds, the joint boxes of the critical cover (``evaluated`` counts them with the proofs),
proved inner / boundary / outer boxes, the volume bracket and its width in % of its upper bound:

* the robot on a rail of ``tests/serial/test_reach_critical3d.py`` (prismatic first joint, then two limited revolute
  joints and a full turn: no structure, so ``reach``'s own choice) at two deltas;
* the oblique prism of the same file, whose exact volume is ``4 pi / 5``, at two deltas;
* the three arms of ``tests/serial/test_reach_turn3d.py`` turned by a limited first joint whose section proves no inner
  box (an elbow on a pedestal, a skew elbow, a turn of +-60 deg), on the section path they took before (outer
  boxes only) and on the 3-D cells ``reach`` now gives them, at two deltas;
* the UR5 (``tests/data/dh/ur5.json``, every joint a full turn) forced through the 3-D method (its section
  hidden) at delta 0.2 with a time limit of 120 s: the cover's count of joint boxes, or ``CoverTooLarge``.

Run: python benchmarks/bench_reach_critical3d.py [--quick]   (--quick: no UR5)
"""

import sys
import time
from pathlib import Path
from unittest import mock

import sympy as sp

import workspace_sym.interval.image as image
from _common import machine
from workspace_sym import StopAt
from workspace_sym.errors import CoverTooLarge, InvalidParameterError
from workspace_sym.kinematics import DHRobot
from workspace_sym.serial import model, plans, reach

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests" / "helpers"), str(ROOT / "tests" / "serial")]
from test_reach_critical3d import OBLIQUE, OBLIQUE_VOLUME, RAIL  # noqa: E402
from test_reach_turn3d import ARMS as TURNED  # noqa: E402


def _cover_counter():
    """Wrap ``critical_cover`` to record the joint boxes each call examined."""
    counts = []
    original = image.critical_cover

    def counted(*args, **kwargs):
        E, evaluated = original(*args, **kwargs)
        counts.append((evaluated, len(E)))
        return E, evaluated
    return counts, counted


def run(name, robot, delta, *, forced=False, section=False, time_limit=None, exact=None):
    """One paving: ``forced`` through the 3-D cells (the section hidden), ``section`` on the section path (the 3-D
    cells refused), else ``reach``'s own choice."""
    counts, counted = _cover_counter()
    patches = [mock.patch.object(image, "critical_cover", counted)]
    if forced:
        patches.append(mock.patch.object(plans, "structure_of", lambda robot, parameters: None))
    if section:
        patches.append(mock.patch.object(plans, "on_cells", lambda robot, values, stored=False, tuning=None: False))
    start = time.perf_counter()
    try:
        for p in patches:
            p.start()
        _ = model.reach_model(robot, ()).minors
        prepared = time.perf_counter() - start
        paving = reach(robot, delta=delta, method="critical" if forced else "auto",
                              stop=StopAt(time_limit=time_limit, progress=False))
    except (CoverTooLarge, InvalidParameterError) as error:
        print(f"{name:28s} delta {delta:<5g} cover too large after {time.perf_counter() - start:.1f} s: {error}")
        return
    finally:
        for p in reversed(patches):
            p.stop()
    seconds = time.perf_counter() - start
    lo, hi = paving.measure_bounds
    cover = f"cover {counts[0][0]} joint boxes ({counts[0][1]} kept)" if counts else "cover not finished"
    c = paving.counts
    line = (f"{name:28s} delta {delta:<5g} {seconds:7.1f} s (model and minors {prepared:.1f} s), {cover}, "
            f"{paving.evaluated} evaluated; inner {c['inner']}, boundary {c['boundary']}, outer {c['outer']}, "
            f"pending {c['pending']}; volume in [{lo:.5g}, {hi:.5g}], width {100 * (hi - lo) / hi:.1f} %")
    if exact is not None:
        line += f"; exact {float(exact):.5g} inside: {bool(sp.Rational(lo) <= exact <= sp.Rational(hi))}"
    if not paving.complete:
        line += f"; stopped: {paving.stop_reason}"
    print(line, flush=True)


def main(quick: bool):
    print(machine())
    for delta in (0.2, 0.1):
        run("rail (P, R, R, full R)", RAIL, delta)
    for delta in (0.25, 0.1):
        run("oblique prism (exact 4pi/5)", OBLIQUE, delta, exact=OBLIQUE_VOLUME)
    for name, robot in TURNED.items():
        for delta in (0.25, 0.125):
            run(f"{name}, section path", robot, delta, section=True)
            run(f"{name}, 3-D cells", robot, delta)
    if not quick:
        ur5 = DHRobot.from_file(ROOT / "tests" / "data" / "dh" / "ur5.json")
        run("UR5 forced 3-D", ur5, 0.2, forced=True, time_limit=120)


if __name__ == "__main__":
    main("--quick" in sys.argv)
