"""The user surfaces of reach with a tool constraint (issues 24 and 25): the result names its constraint and
method (notebook display, JSON), options that do not apply are refused with one line, and a refused
``every=True`` says why for that robot."""

from __future__ import annotations

import html
import json
from concurrent.futures import ThreadPoolExecutor

import pytest

from workspace_sym import robots
from workspace_sym.cli import main
from workspace_sym.errors import InvalidParameterError
from workspace_sym.interval.driver import RunOn
from workspace_sym.orientation import constraint_from
from workspace_sym.serial_workspace import Pose, reach

SCARA_CONE = dict(approach=(1, 0, 0), cone=30)      # never met: the SCARA's approach axis is always vertical


@pytest.fixture(scope="module")
def scara_cone():
    return reach(robots.build("scara"), delta=0.05, pose=Pose(**SCARA_CONE))


def test_the_display_of_a_constrained_reach_names_its_constraint_and_method(scara_cone):
    # Reference: the constraint's wording is the report section's (PoseConstraint.words, one function for both),
    # and the method the result records; the JSON keys are those the command line already wrote.
    words = constraint_from(**SCARA_CONE).words()
    assert words == "the tool's approach axis (z of the tool frame) can lie within 30 degrees of (1, 0, 0)"
    page = scara_cone._repr_html_()
    assert f"tool constraint: {html.escape(words)}" in page
    assert scara_cone.method == "pairs" and "method pairs" in page
    data = scara_cone.to_dict()
    assert data["constraint"] == {"approach": [1.0, 0.0, 0.0], "cone_deg": 30.0, "every": False}
    assert data["constraint_words"] == words and data["method"] == "pairs"


def test_a_reach_without_a_constraint_names_none():
    p = reach(robots.build("planar-2r"), delta=0.2)
    assert p.tool_constraint is None and "constraint" not in p.to_dict()
    assert "tool constraint" not in p._repr_html_() and f"method {p.method}" in p._repr_html_()


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

