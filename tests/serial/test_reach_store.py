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
import time
from pathlib import Path

import numpy as np
import pytest

from workspace_sym import RunOn, StopAt, robots
from workspace_sym.cli import main
from workspace_sym.errors import InvalidParameterError
from workspace_sym.interval.boxes import StoredPaving, bisect, box_sizes
from workspace_sym.interval.driver import RunBudget
from workspace_sym.interval.image import critical_paving
from workspace_sym.serial import Pose, Tuning, plans, reach
from workspace_sym.serial.classify import ProductTest
from workspace_sym.serial.model import cell_width, reach_model
from workspace_sym.serial.structure import structure_of
from workspace_sym.serial.tuning import DEFAULT

QUIET = StopAt()
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
    budget = RunBudget(QUIET, "reach")
    section = plans.SectionPlan(robot, (), DELTA, "diameter", DEFAULT, {}).pave(budget, RunOn())
    budget.close()
    return section.evaluated


def test_classification_is_the_drivers_bisection(scara, whole):
    """The task boxes classified by the driver are those of the breadth-first loop the module ran before
    (reimplemented here: each generation tested, proved boxes kept, undecided ones bisected or kept as
    boundary at delta), with the same test built from the same section."""
    model = reach_model(scara, ())
    plan = structure_of(scara, ())
    grid, classes, _, reason = critical_paving(plan.section, DEFAULT.section_ratio * cell_width(DELTA, "diameter", 3),
                                               budget=lambda count: "")
    assert not reason
    test = ProductTest(plan, grid, classes)
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


def test_the_reach_engine_uses_only_public_names_of_interval():
    """Issue 26 item 3: no private name of the interval package is imported by the reach engine, and the
    classification of task boxes is the driver's bisection, not a loop of its own."""
    import workspace_sym.serial as package
    from workspace_sym.serial.classify import classify_task_boxes

    for path in Path(package.__file__).parent.glob("*.py"):
        tree = ast.parse(path.read_text())
        private = [(node.module, alias.name) for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
                   and node.module and "interval" in node.module for alias in node.names
                   if alias.name.startswith("_")]
        assert private == [], path.name
    assert "bisect(" not in inspect.getsource(classify_task_boxes)


def test_boxes_on_disk_equal_the_run_in_memory(scara, whole, tmp_path):
    """max_memory streams the decided boxes to .npy parts: a StoredPaving with the counts and measures of the
    in-memory run, read back only when asked."""
    stored = reach(scara, delta=DELTA, stop=QUIET, run=RunOn(max_memory="64MB", store=tmp_path / "boxes"))
    assert isinstance(stored.paving, StoredPaving) and stored.paving._loaded == {}
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
    stopped = reach(scara, delta=DELTA, stop=StopAt(max_boxes=section + 300),
                    run=RunOn(resume=checkpoint))
    assert not stopped.complete and len(stopped.pending) and checkpoint.exists()
    assert stopped.evaluated == section + 300 and "budget of" in stopped.stop_reason
    resumed = reach(scara, delta=DELTA, stop=QUIET, run=RunOn(resume=checkpoint))
    assert_same(whole, resumed)
    early = tmp_path / "early.npz"
    first = reach(scara, delta=DELTA, stop=StopAt(max_boxes=1), run=RunOn(resume=early))
    assert not first.complete and not early.exists()
    assert_same(whole, reach(scara, delta=DELTA, stop=QUIET, run=RunOn(resume=early)))


def test_a_resumed_reach_takes_the_section_kept_beside_its_checkpoint(tmp_path, monkeypatch):
    """A time limit lets a turned section refine as far as the time allows, so paving it again on resuming
    could give other cells and a checkpoint refused.  The section is kept beside the checkpoint
    (``.section.npz``) and taken on resuming: the section is not paved again (its paving fails if called), and
    the result is the uninterrupted run's (the reference).  A kept section of another delta is refused, naming
    what differs."""
    import sympy as sp

    from workspace_sym.kinematics import DHJoint, DHRobot

    half, tenth = sp.Rational(1, 2), sp.Rational(1, 10)
    arm = DHRobot([DHJoint.revolute(1, d=3 * tenth, alpha=sp.pi / 2), DHJoint.revolute(2, a=half, alpha=sp.pi / 2),
                   DHJoint.revolute(3, a=4 * tenth, d=tenth)], name="offset arm")
    whole_arm = reach(arm, delta=DELTA, stop=QUIET)
    checkpoint = tmp_path / "arm.npz"
    kept = tmp_path / "arm.npz.section.npz"
    stopped = reach(arm, delta=DELTA, stop=StopAt(max_boxes=_section_count(arm) + 200),
                    run=RunOn(resume=checkpoint))
    assert not stopped.complete and checkpoint.exists() and kept.exists()
    assert not list(tmp_path.glob("*.part"))

    def paved_again(*args, **kwargs):
        raise AssertionError("the section was paved again")

    with monkeypatch.context() as patch:
        patch.setattr(plans, "critical_paving", paved_again)
        resumed = reach(arm, delta=DELTA, stop=QUIET, run=RunOn(resume=checkpoint))
    assert_same(whole_arm, resumed)
    assert resumed.volume_bounds == whole_arm.volume_bounds
    with pytest.raises(InvalidParameterError, match=r"section kept beside a checkpoint of another run \(it differs "
                                                    r"in delta, section cell\)") as caught:
        reach(arm, delta=2 * DELTA, stop=QUIET, run=RunOn(resume=checkpoint))
    assert caught.value.parameter == "resume"


def test_a_checkpoint_of_another_reach_is_refused(scara, tmp_path):
    checkpoint = tmp_path / "reach.npz"
    section = _section_count(scara)
    reach(scara, delta=DELTA, stop=StopAt(max_boxes=section + 10), run=RunOn(resume=checkpoint))
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
    stopped = reach(arm, **options, stop=StopAt(max_boxes=whole.evaluated // 2),
                    run=RunOn(resume=checkpoint, store=tmp_path / "boxes"))
    assert not stopped.complete and len(stopped.pending) and checkpoint.exists()
    resumed = reach(arm, **options, stop=QUIET, run=RunOn(resume=checkpoint))
    assert isinstance(resumed.paving, StoredPaving) and resumed.method == "pairs"
    assert_same(whole, resumed)
    with pytest.raises(InvalidParameterError, match="checkpoint of another run"):
        reach(arm, delta=0.25, method="pairs", tuning=Tuning(inner_depth=1), stop=QUIET, run=RunOn(resume=checkpoint))


def test_the_planar_grid_and_a_pose_by_pairs_refuse_storage(tmp_path):
    """The planar critical method decides its grid of cells in one pass, reach with a pose by the pairs method
    keeps its boxes in memory: both refuse max_memory, store and resume, naming run, the option given with its
    value, and what takes them."""
    with pytest.raises(InvalidParameterError, match="planar critical method") as caught:
        reach(robots.build("planar-2r"), delta=0.5, stop=QUIET, run=RunOn(resume=tmp_path / "x.npz"))
    assert caught.value.parameter == "run"
    assert f"got resume={tmp_path / 'x.npz'!r}; they apply to method='pairs'" in str(caught.value)
    with pytest.raises(InvalidParameterError, match=r"the pairs method\) keeps its boxes in memory") as caught:
        reach(robots.build("puma560"), delta=0.5, pose=Pose(approach=(1, 0, 0), cone=10),
              run=RunOn(max_memory="1GB"))
    assert caught.value.parameter == "run"
    assert "got max_memory='1GB'; they apply to the section method" in str(caught.value)


CONE = Pose(approach=(0, 0, -1), cone=20)


@pytest.fixture(scope="module")
def puma():
    return robots.build("puma560")


@pytest.fixture(scope="module")
def cone_whole(puma):
    """The uninterrupted in-memory run of the Puma 560 with its tool within 20 degrees of straight down (the
    section method): the reference of the stored and resumed runs."""
    whole = reach(puma, delta=0.3, stop=QUIET, pose=CONE)
    assert whole.method == "section" and whole.complete and whole.counts["inner"] > 0
    return whole


def test_a_pose_reach_stopped_and_resumed_gives_the_uninterrupted_boxes(puma, cone_whole, tmp_path):
    """Issue 24 item 4 with a tool constraint: a box budget stops the classification of the task boxes (after
    the section), a checkpoint is written; a checkpoint of another constraint or delta is refused; the same
    call with the checkpoint, its boxes on disk, goes on to exactly the boxes, counts, measures and volume
    bracket of the run never stopped."""
    checkpoint = tmp_path / "cone.npz"
    run = RunOn(resume=checkpoint, max_memory="64MB")
    stopped = reach(puma, delta=0.3, stop=StopAt(max_boxes=cone_whole.evaluated - 300),
                    pose=CONE, run=run)
    assert not stopped.complete and len(stopped.pending) and checkpoint.exists()
    assert stopped.evaluated == cone_whole.evaluated - 300 and "budget of" in stopped.stop_reason
    with pytest.raises(InvalidParameterError, match="checkpoint of another run") as caught:
        reach(puma, delta=0.3, stop=QUIET, pose=Pose(approach=(0, 0, -1), cone=25), run=run)
    assert caught.value.parameter == "resume"
    resumed = reach(puma, delta=0.3, stop=QUIET, pose=CONE, run=run)
    assert isinstance(resumed.paving, StoredPaving) and resumed.method == "section"
    # The stored run's bracket is also the intersection of the boxes' and the section's (Pappus) brackets.
    assert resumed.volume_bounds == cone_whole.volume_bounds
    assert resumed.box_measure_bounds == cone_whole.box_measure_bounds
    assert resumed.to_dict()["measure_bounds"] == list(cone_whole.measure_bounds)
    assert_same(cone_whole, resumed)


def test_a_pose_reach_cut_in_its_section_writes_no_checkpoint(puma, cone_whole, tmp_path):
    """A budget spent in the section: every task box is still classified from its cells (a bracket holding the
    uninterrupted one, reported incomplete) and no checkpoint is written: a resumed call starts over.  Its
    seconds are those of the whole call (reference: the wall time around it), not of the classification alone."""
    early = tmp_path / "early.npz"
    start = time.perf_counter()
    cut = reach(puma, delta=0.3, stop=StopAt(max_boxes=40), pose=CONE, run=RunOn(resume=early))
    wall = time.perf_counter() - start
    assert not cut.complete and "budget" in cut.stop_reason and not early.exists()
    assert 0.5 * wall <= cut.seconds <= wall
    lo, hi = cut.measure_bounds
    full_lo, full_hi = cone_whole.measure_bounds
    assert lo <= full_lo and full_hi <= hi


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


@pytest.mark.slow
def test_cli_reach_with_a_tool_constraint_resumes(cone_whole, tmp_path, capsys):
    """--max-memory and --resume with --approach/--cone (the section method): a checkpoint of another --delta
    is refused (exit 2, one line naming --resume); the resumed JSON has the counts, measures and bracket of the
    in-memory run; --plot with --max-memory is refused before any work."""
    argv = ["reach", "puma560", "--delta", "0.3", "--approach", "0,0,-1", "--cone", "20", "--json",
            "--no-progress", "--resume", str(tmp_path / "cone.npz"), "--max-memory", "64MB"]
    assert main([*argv, "--max-boxes", str(cone_whole.evaluated - 200)]) == 0
    stopped = json.loads(capsys.readouterr().out)
    assert not stopped["complete"] and stopped["pending"]["boxes"] > 0
    assert main([*argv[:2], "--delta", "0.5", *argv[4:]]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--resume:" in err and "checkpoint of another run" in err
    assert main(argv) == 0
    resumed = json.loads(capsys.readouterr().out)
    for kind in ("inner", "boundary", "outer"):
        assert resumed[kind]["boxes"] == cone_whole.counts[kind]
        assert resumed[kind]["measure"] == cone_whole.measures[kind] and resumed[kind]["files"]
    assert resumed["measure_bounds"] == list(cone_whole.measure_bounds) and resumed["method"] == "section"
    assert resumed["constraint"] == {"approach": [0.0, 0.0, -1.0], "cone_deg": 20.0, "every": False}
    plot = tmp_path / "cone.png"
    assert main([*argv, "--plot", str(plot)]) == 2
    assert "--plot and --slices draw boxes held in memory" in capsys.readouterr().err and not plot.exists()
