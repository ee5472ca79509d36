"""The user surfaces of reach with a tool constraint (issues 24 and 25): the result names its constraint and
method (notebook display, JSON), options that do not apply are refused with one line, and a refused
``every=True`` says why for that robot."""

from __future__ import annotations

import html
import json

import pytest

from workspace_sym import robots
from workspace_sym.cli import main
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

