"""The user surfaces of reach with a tool constraint (issues 24 and 25): the result names its constraint and
method (notebook display, JSON), options that do not apply are refused with one line, and a refused
``every=True`` says why for that robot."""

from __future__ import annotations

import html
import json
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest
import rtbdata
import sympy as sp

from paths import DATA
from workspace_sym import robots
from workspace_sym.cli import main
from workspace_sym.display import to_html
from workspace_sym.errors import InvalidParameterError
from workspace_sym.interval.driver import RunOn
from workspace_sym.kinematics import DHRobot
from workspace_sym.serial import Pose, reach
from workspace_sym.serial.pose import constraint_from

SCARA_CONE = dict(approach=(1, 0, 0), cone=30)      # never met: the SCARA's approach axis is always vertical


@pytest.fixture(scope="module")
def scara_cone():
    return reach(robots.build("scara"), delta=0.05, pose=Pose(**SCARA_CONE))


def test_the_display_of_a_constrained_reach_names_its_constraint_and_method(scara_cone):
    # Reference: the constraint's wording is the report section's (PoseConstraint.words, one function for both),
    # and the method the result records; the JSON keys are those the command line already wrote.
    words = constraint_from(**SCARA_CONE).words()
    assert words == "the tool's approach axis (z of the tool frame) can lie within 30 degrees of (1, 0, 0)"
    page = to_html(scara_cone)
    assert f"tool constraint: {html.escape(words)}" in page
    assert scara_cone.method == "pairs" and "method pairs" in page
    data = scara_cone.to_dict()
    assert data["constraint"] == {"approach": [1.0, 0.0, 0.0], "cone_deg": 30.0, "every": False}
    assert data["constraint_words"] == words and data["method"] == "pairs"


def test_a_reach_without_a_constraint_names_none():
    p = reach(robots.build("planar-2r"), delta=0.2)
    assert p.tool_constraint is None and "constraint" not in p.to_dict()
    assert "tool constraint" not in to_html(p) and f"method {p.method}" in to_html(p)


def test_the_cli_json_keeps_its_constraint_key_and_adds_the_words(capsys):
    code = main(["reach", "scara", "--delta", "0.05", "--approach", "1,0,0", "--cone", "30", "--json"])
    out, _ = capsys.readouterr()
    data = json.loads(out)
    assert code == 0 and data["constraint"] == {"approach": [1.0, 0.0, 0.0], "cone_deg": 30.0, "every": False}
    assert data["constraint_words"] == constraint_from(**SCARA_CONE).words()


def test_a_scheduler_with_a_tool_constraint_is_refused_in_one_line(capsys):
    # Reference: the contract of bad input (exit 2, one line naming the option, its value and what takes it); the
    # refusal comes before any cluster is started (local:1 would start one).
    code = main(["reach", "scara", "--delta", "0.05", "--approach", "1,0,0", "--cone", "30", "--scheduler",
                 "local:1"])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2 and out == "" and len(lines) == 1
    assert lines[0].startswith("workspace-sym reach: error: --scheduler:")
    assert "'local:1'" in lines[0] and "applies to reach without a tool constraint" in lines[0]


@pytest.mark.parametrize("run, given", [(RunOn(chunk=10), "chunk=10"), ("executor", "executor=")])
def test_an_executor_or_chunk_with_a_pose_is_refused(run, given):
    # Reference: reach with a pose decides every box in this process: an executor or a chunk size it would not
    # use is refused, naming what was given (it was dropped without a word).
    with ThreadPoolExecutor(1) as pool:
        where = RunOn(executor=pool) if run == "executor" else run
        with pytest.raises(InvalidParameterError) as caught:
            reach(robots.build("scara"), delta=0.05, pose=Pose(**SCARA_CONE), run=where)
    assert caught.value.parameter == "run" and given in str(caught.value)
    assert "apply to reach without a pose" in str(caught.value)


def test_a_method_other_than_auto_with_a_pose_is_refused(capsys):
    # Reference: the contract of bad input; a constrained reach picks its own method (section or pairs), so a
    # method asked for was dropped without a word before.  API and command line, one line and exit 2.
    with pytest.raises(InvalidParameterError) as caught:
        reach(robots.build("scara"), delta=0.05, method="pairs", pose=Pose(**SCARA_CONE))
    assert caught.value.parameter == "method" and "'pairs'" in str(caught.value)
    code = main(["reach", "scara", "--delta", "0.05", "--approach", "1,0,0", "--cone", "30", "--method", "critical"])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2 and out == "" and len(lines) == 1 and "'critical'" in lines[0]


def test_inner_depth_and_max_pairs_reach_the_constrained_pairs_method(monkeypatch, capsys):
    # Reference: the tuning the constrained path is called with (the keywords were once dropped); the keywords of
    # earlier releases become the pose's figures with a DeprecationWarning, and unset, the defaults apply, so a run
    # without them is unchanged.
    from workspace_sym.serial import api
    from workspace_sym.serial.tuning import DEFAULT

    calls = []
    monkeypatch.setattr(api, "_reach_pose", lambda robot, **kw: calls.append(kw) or None)
    with pytest.warns(DeprecationWarning) as caught:
        reach(robots.build("scara"), delta=0.05, pose=Pose(**SCARA_CONE), inner_depth=0, max_pairs=500)
    assert {str(w.message) for w in caught} == {
        "reach: inner_depth= is deprecated; pass tuning=Tuning(pose_inner_depth=...)",
        "reach: max_pairs= is deprecated; pass tuning=Tuning(pose_max_pairs=...)"}
    reach(robots.build("scara"), delta=0.05, pose=Pose(**SCARA_CONE))
    assert (calls[0]["tuning"].pose_inner_depth, calls[0]["tuning"].pose_max_pairs) == (0, 500)
    assert calls[1]["tuning"] == DEFAULT
    main(["reach", "scara", "--delta", "0.05", "--approach", "1,0,0", "--cone", "30", "--inner-depth", "3"])
    capsys.readouterr()
    assert calls[2]["tuning"].pose_inner_depth == 3


ARMS = {"ur5": lambda: DHRobot.from_file(DATA / "dh" / "ur5.json"),
        "kr16": lambda: DHRobot.from_urdf(Path(rtbdata.__file__).parent
                                          / "xacro/kuka_description/kuka_kr16/urdf/kr16_2.urdf")}


@pytest.mark.parametrize("name", sorted(ARMS))
def test_every_direction_refused_says_which_joints_move_the_tool_point(name):
    # Reference: finite differences of the tool point and of the approach axis at a random configuration (an
    # independent numeric check of which joints move what): no joint turns the approach without moving the point,
    # and the message names those that move both.
    robot = ARMS[name]()
    with pytest.raises(InvalidParameterError) as caught:
        reach(robot, delta=0.1, pose=Pose(approach=(0, 0, -1), cone=20, every=True))
    message = str(caught.value)
    T = robot.substitute(robot.fk())
    pose = sp.lambdify([robot.q], list(T[:3, 3]) + list(T[:3, 2]), modules="numpy")
    q = np.random.default_rng(5).uniform(-1, 1, robot.n)
    moved = []
    for i in range(robot.n):
        step = np.eye(robot.n)[i] * 1e-6
        change = np.abs(np.array(pose(q + step), dtype=float) - np.array(pose(q - step), dtype=float))
        moved.append((change[:3].max() > 1e-9, change[3:].max() > 1e-9))
    assert not any(a and not p for p, a in moved)
    both = [f"joint {i + 1} ({robot.q[i]})" for i, (p, a) in enumerate(moved) if p and a]
    assert len(both) >= 3
    assert ("the joints that turn the approach axis without moving the tool point are none, not two (the tool "
            f"point moves with {', '.join(both)}, which also turn the approach axis)") in message
    assert caught.value.parameter == "every" and robot.name in message
    assert "roll-pitch wrist" in message and "use every=False" in message


def test_every_direction_refused_on_the_scara_says_its_approach_never_turns():
    # Reference: the SCARA's approach axis is (0, 0, -1) in every configuration (its joints turn about vertical
    # axes or slide along one), so no joint turns it.
    with pytest.raises(InvalidParameterError) as caught:
        reach(robots.build("scara"), delta=0.1, pose=Pose(approach=(0, 0, -1), cone=20, every=True))
    assert "no joint turns the approach axis (it is the same in every configuration)" in str(caught.value)


def test_the_section_bar_of_the_puma_moves_during_its_critical_cover(monkeypatch):
    # Reference: the calls the bar receives (share decided, boxes evaluated): during the cover nothing is decided
    # and the count grows generation by generation; then the share grows.  And the same paving of the section with
    # and without the bar (the bar changes no cell and no count).
    from workspace_sym.interval.image import critical_paving
    from workspace_sym.serial import plans
    from workspace_sym.serial.model import cell_width
    from workspace_sym.serial.structure import structure_of
    from workspace_sym.serial.tuning import DEFAULT

    calls = []

    @contextmanager
    def recording(progress):
        yield lambda share, evaluated: calls.append((share, evaluated))

    monkeypatch.setattr(plans, "section_bar", recording)
    puma = robots.build("puma560")
    paving = reach(puma, delta=0.3)
    assert paving.method == "critical"
    cover = [evaluated for share, evaluated in calls if share == 0.0]
    assert len(cover) >= 5 and cover == sorted(cover) and cover[0] < cover[-1]
    shares = [share for share, _ in calls]
    assert shares == sorted(shares) and shares[-1] > 0.5
    section = structure_of(puma, ()).section
    width = DEFAULT.section_ratio * cell_width(0.3, "diameter", 3)
    quiet = critical_paving(section, width)
    shown = critical_paving(section, width, show=lambda share, evaluated: None)
    assert np.array_equal(quiet[1], shown[1]) and quiet[2:] == shown[2:]


def test_the_reach_text_says_where_each_bracket_comes_from(tmp_path, capsys):
    """Issue 39 (engineer): the terminal text of a turned arm printed the boxes' measures, then a bracket that
    did not follow from them (the section's, by Pappus), without a word.  Now each box count says what it means,
    the boxes' bracket and the section's are both printed with their source, and the last one is their
    intersection (reference: the result's own brackets)."""
    import json

    arm = {"name": "offset arm", "angles": "degrees",
           "joints": [{"type": "R", "d": 0.3, "a": 0, "alpha": 90}, {"type": "R", "d": 0, "a": 0.5, "alpha": 90},
                      {"type": "R", "d": 0.1, "a": 0.4, "alpha": 0}]}
    path = tmp_path / "arm.json"
    path.write_text(json.dumps(arm))
    assert main(["reach", "--dh", str(path), "--delta", "0.25", "--no-progress"]) == 0
    out = capsys.readouterr().out
    result = reach(DHRobot.from_file(path), delta=0.25)
    assert result.volume_bounds is not None
    assert "(proved inside)" in out and "(proved outside)" in out and "(undecided, at most delta = 0.25)" in out
    assert "the boxes bound the measure to [" in out and "the section's cells bound it to [" in out
    assert "(the intersection of the two)" in out
    assert out.count("measure in [") == 1
