"""One paving driver over a runner seam, with its options as objects (issue 26 items 1 to 3).

References: the layer order stated in ``workspace_sym/interval/__init__.py`` (read from the source
by ``ast``, not by importing), the area ``pi`` of the unit disc, the annulus ``1/2 <= r <= 3/2``
reached by the 2R arm (l = 1, 1/2) for the cell classes, and the run of the same paving in line
for the other runners (same boxes as sets).
"""

import ast
import inspect
import math
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import workspace_sym
from workspace_sym import Pose, RunOn, StopAt, pave, reach
from workspace_sym.errors import InvalidParameterError
from workspace_sym.interval import driver
from workspace_sym.interval.verdict import CODE, INSIDE, OUTSIDE, VERDICTS
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.orthoglide import Orthoglide
from workspace_sym.orthoglide.certificate import dextrous

PACKAGE = Path(workspace_sym.__file__).parent
DISC = (["x**2 + y**2 <= 1"], {"x": (-1.1, 1.1), "y": (-1.1, 1.1)})
# Each module of interval/ and the modules of interval/ it may import (the layers, lowest first).
LAYERS = {
    "arith": set(), "mp": {"arith"}, "graph": {"arith", "mp"}, "compiler": {"arith", "mp", "graph"},
    "contractor": {"arith", "boxes", "graph", "verdict"},
    "verdict": set(), "fingerprint": set(), "store": set(), "boxes": {"store"}, "executor": {"arith", "verdict"},
    "driver": {"arith", "boxes", "contractor", "executor", "fingerprint", "store", "verdict"},
}


def _imports(path: Path, level: int | None = None) -> list[tuple[str, list[str]]]:
    """``(module, names)`` of every relative ``from .x import ...`` in a file (of the given level only)."""
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level and level in (None, node.level):
            out.append((node.module or "", [a.name for a in node.names]))
    return out


@pytest.mark.parametrize("module", sorted(LAYERS))
def test_lower_layers_of_the_engine_import_only_what_is_below_them(module):
    """No cycle: the runner seam (executor) and the boxes import neither the driver nor the pavings."""
    used = set()
    for name, names in _imports(PACKAGE / "interval" / f"{module}.py", level=1):
        top = name.split(".")[0]
        used |= {top} if top else set(names)
    assert used <= LAYERS[module], f"{module} imports {sorted(used - LAYERS[module])}"


@pytest.mark.parametrize("path", [PACKAGE / "serial_workspace.py", *sorted((PACKAGE / "interval").glob("*.py"))],
                         ids=lambda p: p.name)
def test_interval_is_used_through_public_names_only(path):
    """serial_workspace and the engine's modules import no private name of another interval module."""
    private = [(m, n) for m, names in _imports(path) for n in names
               if n.startswith("_") and (path.parent.name == "interval" or m.startswith("interval"))]
    assert private == []


@pytest.mark.parametrize("fn", [pave, reach, dextrous, Orthoglide.dextrous], ids=lambda f: f.__qualname__)
def test_entry_points_take_at_most_ten_parameters(fn):
    parameters = [p for p in inspect.signature(fn).parameters if p != "self"]
    assert len(parameters) <= 10 and {"stop", "run"} <= set(parameters)


def test_the_clock_is_made_from_the_options_alone():
    """RunBudget has no measure to patch afterwards: the bar is moved by the share decided."""
    assert list(inspect.signature(driver.RunBudget).parameters) == ["stop", "label", "progress"]
    budget = driver.RunBudget(StopAt(max_boxes=10), "test", False)
    assert budget.stop_reason(9) == "" and budget.stop_reason(10) == "budget of 10 boxes reached"


@pytest.mark.parametrize("make, parameter", [
    (lambda: StopAt(max_boxes=0), "max_boxes"),
    (lambda: StopAt(max_boxes=True), "max_boxes"),
    (lambda: StopAt(section_boxes=0), "section_boxes"),
    (lambda: StopAt(time_limit=-1), "time_limit"),
    (lambda: StopAt(time_limit=math.inf), "time_limit"),
    (lambda: RunOn(chunk=0), "chunk"),
    (lambda: RunOn(max_memory="lots"), "max_memory"),
])
def test_bad_options_name_their_parameter(make, parameter):
    with pytest.raises(InvalidParameterError) as caught:
        make()
    assert caught.value.parameter == parameter


def test_reach_refuses_what_it_cannot_do_with_its_boxes(tmp_path):
    arm = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=sp.Rational(1, 2))])
    with pytest.raises(InvalidParameterError) as caught:
        reach(arm, delta=0.2, run=RunOn(store=tmp_path / "boxes"))
    assert caught.value.parameter == "run"
    with pytest.raises(InvalidParameterError) as caught:
        reach(arm, delta=0.2, pose={"approach": (0, 0, 1)})
    assert caught.value.parameter == "pose"
    assert Pose(cone=20).cone == 20


def _as_set(boxes) -> set:
    return {tuple(b.ravel()) for b in boxes}


def test_every_runner_gives_the_boxes_of_the_run_in_line(tmp_path):
    here = pave(*DISC, delta=0.05)
    lo, hi = here.measure_bounds
    assert lo <= math.pi <= hi                                   # the unit disc
    with ThreadPoolExecutor(2) as pool:
        threads = pave(*DISC, delta=0.05, run=RunOn(executor=pool, chunk=64))
    stored = pave(*DISC, delta=0.05, run=RunOn(store=tmp_path / "boxes", chunk=100))
    for other in (threads, stored):
        assert other.counts == here.counts and other.measures == here.measures
        for kind in ("inner", "boundary", "outer"):
            assert _as_set(getattr(other, kind)) == _as_set(getattr(here, kind))


def test_a_box_budget_stops_the_run_in_line_where_it_says():
    p = pave(*DISC, delta=0.01, stop=StopAt(max_boxes=1000))
    assert not p.complete and p.evaluated == 1000 and p.stop_reason == "budget of 1000 boxes reached"
    total = sum(p.measures.values())
    assert abs(total - 2.2 * 2.2) <= 1e-12                        # decided and pending tile the box


def test_exact_measure_is_attached_without_copying_the_boxes():
    p = pave(*DISC, delta=0.2)
    q = p.with_exact_measure(sp.pi)
    assert q.exact_measure == sp.pi and p.exact_measure is None and q.inner is p.inner
    assert q.to_dict()["exact_measure"] == pytest.approx(math.pi, abs=1e-15)


def test_image_cells_carry_the_verdict_codes():
    """Issue 26 item 3: the cell classes of critical_paving are the int8 codes of verdict.py; every cell
    proved inside lies in the annulus 1/2 <= r <= 3/2 of the 2R arm, every cell proved outside misses it."""
    from workspace_sym.interval import image
    from workspace_sym.serial import ReachModel

    arm = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=sp.Rational(1, 2))])
    grid, classes, _, reason = image.critical_paving(ReachModel(arm), 0.1)
    assert reason == "" and classes.dtype == CODE and np.isin(classes, VERDICTS).all()
    assert not any(hasattr(image, name) for name in ("INNER", "OUTER"))
    inner, outer = grid.boxes(classes, INSIDE), grid.boxes(classes, OUTSIDE)
    assert len(inner) and len(outer)
    def near(b):                   # distance from the origin to each box, and to its farthest point (a corner)
        return np.hypot(np.clip(0.0, b[:, 0, 0], b[:, 0, 1]), np.clip(0.0, b[:, 1, 0], b[:, 1, 1]))

    def far(b):
        return np.max([np.hypot(b[:, 0, i], b[:, 1, j]) for i in (0, 1) for j in (0, 1)], axis=0)

    assert ((near(inner) >= 0.5) & (far(inner) <= 1.5)).all()
    assert ((near(outer) > 1.5) | (far(outer) < 0.5)).all()


def test_a_run_without_checkpoint_does_not_describe_itself(monkeypatch, tmp_path):
    """The checkpoint's fingerprint prints every constraint with SymPy (a third of a small paving's time):
    only a run with ``resume`` (or a store on disk, which names its problem) makes one."""
    def refuse(*args):
        raise AssertionError("fingerprint made without a checkpoint")

    monkeypatch.setattr(driver, "_fingerprint", refuse)
    assert pave(*DISC, delta=0.2).complete
    with pytest.raises(AssertionError, match="fingerprint"):
        pave(*DISC, delta=0.2, run=RunOn(resume=tmp_path / "run.npz"))


def test_a_store_in_memory_sums_its_boxes_as_one_on_disk_does(tmp_path):
    """Reference: the exact sums do not depend on the order of the boxes nor on when they are summed."""
    from workspace_sym.interval.store import BoxStore

    p = pave(*DISC, delta=0.05)
    memory, disk = BoxStore(2), BoxStore(2, tmp_path / "boxes")
    for kind in ("inner", "boundary", "outer"):
        boxes = getattr(p, kind)
        memory.add(kind, boxes[::-1])
        for part in np.array_split(boxes, 3):
            disk.add(kind, part)
    for sums in ("sums", "sums_down", "sums_up"):
        assert {k: str(s) for k, s in getattr(memory, sums).items()} == \
               {k: str(s) for k, s in getattr(disk, sums).items()}
    assert memory.sums["inner"].value == p.measures["inner"]
