"""reach's task boxes through the one driver loop: the same boxes as the breadth-first classification it
replaced, boxes on disk (max_memory, store) and a checkpoint to go on from (resume) for the section and pairs
methods, issues 24 item 4 and 26.

References, each named in its test: a second implementation of the classification (the breadth-first loop
``serial_workspace`` ran before it used the driver, written here from its description), and the uninterrupted
in-memory run of the same arm (same boxes as sets, same counts, measures to the last bit).
"""

from __future__ import annotations

import ast
import inspect
import json

import numpy as np
import pytest

from workspace_sym import RunOn, StopAt, robots, serial_workspace
from workspace_sym.cli import main
from workspace_sym.errors import InvalidParameterError
from workspace_sym.interval.boxes import StoredPaving, bisect, box_sizes
from workspace_sym.serial_workspace import Pose, reach

QUIET = StopAt(progress=False)
DELTA = 0.1


def as_set(boxes) -> set:
    return {tuple(np.asarray(b).ravel()) for b in boxes}


def assert_same(a, b):
    """Same boxes of every class (as sets), counts, measures to the last bit, bracket and boxes evaluated."""
    assert a.counts == b.counts
    assert a.measures == b.measures and a.measure_bounds == b.measure_bounds
    assert a.evaluated == b.evaluated and a.complete and b.complete
    for kind in ("inner", "boundary", "outer"):
        assert as_set(getattr(a, kind)) == as_set(getattr(b, kind)), kind


@pytest.fixture(scope="module")
def scara():
    return robots.build("scara")


@pytest.fixture(scope="module")
def whole(scara):
    """The uninterrupted in-memory run (the reference of the stored and resumed runs)."""
    return reach(scara, delta=DELTA, stop=QUIET)


def _section_count(robot) -> int:
    """Boxes the section (the plane factor of the SCARA) takes before the task boxes are classified."""
    budget = serial_workspace.RunBudget(QUIET, "reach")
    values = ()
    serial_workspace._spatial(robot, values, DELTA, "diameter", budget, executor=None, where=RunOn())
    budget.close()
    return budget.spent


def test_classification_is_the_drivers_bisection(scara, whole):
    """The task boxes classified by the driver are those of the breadth-first loop the module ran before
    (reimplemented here: each generation tested, proved boxes kept, undecided ones bisected or kept as
    boundary at delta), with the same test built from the same section."""
    model = serial_workspace._model(scara, ())
    plan = serial_workspace._section(scara, ())
    grid, classes, _, reason = serial_workspace.critical_paving(
        plan.section, serial_workspace.SECTION_RATIO * serial_workspace._cell_width(DELTA, "diameter", 3),
        budget=lambda count: "")
    assert not reason
    test = serial_workspace._ProductTest(plan, grid, classes)
    T = model.enclose(model.limits[None])[0][None].copy()
    kinds: dict[str, list] = {"inner": [], "boundary": [], "outer": []}
    count = 0
    while len(T):
        count += len(T)
        is_in, is_out = test(T)
        kinds["inner"].append(T[is_in])
        kinds["outer"].append(T[is_out])
        und = ~is_in & ~is_out
        small = und & (box_sizes(T, "diameter") <= DELTA)
        kinds["boundary"].append(T[small])
        T, thin = bisect(T[und & ~small])
        kinds["boundary"].append(thin)
    for kind, parts in kinds.items():
        assert as_set(np.concatenate(parts)) == as_set(getattr(whole, kind)), kind
    assert whole.evaluated == _section_count(scara) + count


def test_serial_workspace_uses_only_public_names_of_interval():
    """Issue 26 item 3: no private name of the interval package is imported by serial_workspace."""
    tree = ast.parse(inspect.getsource(serial_workspace))
    private = [(node.module, alias.name) for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
               and node.module and "interval" in node.module for alias in node.names if alias.name.startswith("_")]
    assert private == []
    assert "bisect(" not in inspect.getsource(serial_workspace.classify_task_boxes)


def test_boxes_on_disk_equal_the_run_in_memory(scara, whole, tmp_path):
    """max_memory streams the decided boxes to .npy parts: a StoredPaving with the counts and measures of the
    in-memory run, read back only when asked."""
    stored = reach(scara, delta=DELTA, stop=QUIET, run=RunOn(max_memory="64MB", store=tmp_path / "boxes"))
    assert isinstance(stored, StoredPaving) and stored._loaded == {}
    assert stored.counts == whole.counts and stored.measures == whole.measures
    assert stored.measure_bounds == whole.measure_bounds and stored.method == "critical"
    assert stored.to_dict()["store"] == str(tmp_path / "boxes")
    assert_same(whole, stored)


def test_boxes_on_disk_keep_the_section_bracket(tmp_path):
    """A turned section proves a second bracket (Pappus, volume_bounds); with the boxes on disk measure_bounds
    is still its intersection with the boxes' bracket, as in memory (the run in memory is the reference)."""
    import sympy as sp

    from workspace_sym.kinematics import DHJoint, DHRobot

    half, tenth = sp.Rational(1, 2), sp.Rational(1, 10)
    arm = DHRobot([DHJoint.revolute(1, d=3 * tenth, alpha=sp.pi / 2), DHJoint.revolute(2, a=half, alpha=sp.pi / 2),
                   DHJoint.revolute(3, a=4 * tenth, d=tenth)], name="offset arm")
    memory = reach(arm, delta=0.3, stop=QUIET)
    stored = reach(arm, delta=0.3, stop=QUIET, run=RunOn(max_memory="64MB", store=tmp_path / "boxes"))
    assert memory.volume_bounds is not None and stored.volume_bounds == memory.volume_bounds
    assert memory.measure_bounds != memory.box_measure_bounds       # the section's bracket is the tighter here
    assert stored.box_measure_bounds == memory.box_measure_bounds
    assert stored.measure_bounds == memory.measure_bounds
    assert stored.to_dict()["measure_bounds"] == memory.to_dict()["measure_bounds"]


def test_a_stopped_reach_resumed_gives_the_uninterrupted_boxes(scara, whole, tmp_path):
    """A box budget stops the classification part way (pending boxes, a checkpoint written); the same call
    with the checkpoint goes on to exactly the boxes, counts and measures of the run never stopped.  A budget
    spent in the section leaves no checkpoint: the resumed call starts over, with the same result."""
    section = _section_count(scara)
    checkpoint = tmp_path / "reach.npz"
    stopped = reach(scara, delta=DELTA, stop=StopAt(max_boxes=section + 300, progress=False),
                    run=RunOn(resume=checkpoint))
    assert not stopped.complete and len(stopped.pending) and checkpoint.exists()
    assert stopped.evaluated == section + 300 and "budget of" in stopped.stop_reason
    resumed = reach(scara, delta=DELTA, stop=QUIET, run=RunOn(resume=checkpoint))
    assert_same(whole, resumed)
    early = tmp_path / "early.npz"
    first = reach(scara, delta=DELTA, stop=StopAt(max_boxes=1, progress=False), run=RunOn(resume=early))
    assert not first.complete and not early.exists()
    assert_same(whole, reach(scara, delta=DELTA, stop=QUIET, run=RunOn(resume=early)))


def test_a_checkpoint_of_another_reach_is_refused(scara, tmp_path):
    checkpoint = tmp_path / "reach.npz"
    section = _section_count(scara)
    reach(scara, delta=DELTA, stop=StopAt(max_boxes=section + 10, progress=False), run=RunOn(resume=checkpoint))
    with pytest.raises(InvalidParameterError, match="checkpoint of another run") as caught:
        reach(scara, delta=0.2, stop=QUIET, run=RunOn(resume=checkpoint))
    assert caught.value.parameter == "resume"


def test_the_pairs_method_stores_and_resumes(tmp_path):
    """The pairs method (its own loop: task boxes with their joint boxes) takes the same options: stopped by a
    box budget with a checkpoint (the task boxes left and their joint boxes), then resumed with its boxes on
    disk, it gives the boxes, counts and measures of the uninterrupted in-memory run."""
    arm = robots.build("planar-2r")
    options = dict(delta=0.25, method="pairs")
    whole = reach(arm, **options, stop=QUIET)
    checkpoint = tmp_path / "pairs.npz"
    stopped = reach(arm, **options, stop=StopAt(max_boxes=whole.evaluated // 2, progress=False),
                    run=RunOn(resume=checkpoint, store=tmp_path / "boxes"))
    assert not stopped.complete and len(stopped.pending) and checkpoint.exists()
    resumed = reach(arm, **options, stop=QUIET, run=RunOn(resume=checkpoint))
    assert isinstance(resumed, StoredPaving) and resumed.method == "pairs"
    assert_same(whole, resumed)
    with pytest.raises(InvalidParameterError, match="checkpoint of another run"):
        reach(arm, delta=0.25, method="pairs", inner_depth=1, stop=QUIET, run=RunOn(resume=checkpoint))


def test_the_planar_grid_and_a_pose_refuse_storage(tmp_path):
    """The planar critical method decides its grid of cells in one pass, reach with a pose keeps its boxes in
    memory: both refuse max_memory, store and resume, naming run and why."""
    with pytest.raises(InvalidParameterError, match="planar critical method") as caught:
        reach(robots.build("planar-2r"), delta=0.5, stop=QUIET, run=RunOn(resume=tmp_path / "x.npz"))
    assert caught.value.parameter == "run"
    with pytest.raises(InvalidParameterError, match="with a pose keeps its boxes in memory"):
        reach(robots.build("puma560"), delta=0.5, pose=Pose(approach=(0, 0, 1), cone=10),
              run=RunOn(max_memory="1GB"))


def test_cli_reach_max_memory_and_resume(whole, tmp_path, capsys):
    """--max-memory, --store and --resume on reach, as on pave: the JSON of the resumed run has the counts and
    measures of the in-memory run, and names the files of its boxes."""
    argv = ["reach", "scara", "--delta", str(DELTA), "--json", "--no-progress"]
    checkpoint = str(tmp_path / "run.npz")
    assert main([*argv, "--max-boxes", str(whole.evaluated - 50), "--resume", checkpoint,
                 "--max-memory", "64MB"]) == 0
    stopped = json.loads(capsys.readouterr().out)
    assert not stopped["complete"] and stopped["pending"]["boxes"] > 0
    assert main([*argv, "--resume", checkpoint, "--max-memory", "64MB"]) == 0
    resumed = json.loads(capsys.readouterr().out)
    for kind in ("inner", "boundary", "outer"):
        assert resumed[kind]["boxes"] == whole.counts[kind] and resumed[kind]["measure"] == whole.measures[kind]
        assert resumed[kind]["files"]
    assert resumed["boxes_evaluated"] == whole.evaluated and resumed["complete"]
    assert main(["reach", "planar-2r", "--delta", "0.5", "--resume", checkpoint]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "planar critical method" in err
