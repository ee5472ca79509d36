"""The report section of an orientation workspace (``dh_robot_report(..., reach_constraint=...)``): the constraint
stated, and the numbers those of the Paving ``reach`` returned under it (reference: that Paving)."""

from __future__ import annotations

import re

import pytest

from workspace_sym import robots
from workspace_sym.kinematics import DHRobot
from workspace_sym.numbers import fmt_bracket
from workspace_sym.orientation import constraint_from
from workspace_sym.report import Document, _pose_section, dh_robot_report
from workspace_sym.serial_workspace import Pose


def test_scara_tool_down_report_states_the_constraint_and_the_pavings_numbers(tmp_path, scara):
    calls = []
    reach = DHRobot.reach

    def keep(self, **kwargs):
        calls.append((kwargs, reach(self, **kwargs)))
        return calls[-1][1]

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(DHRobot, "reach", keep)
        path = dh_robot_report(scara, tmp_path / "r", samples=300, reach_delta=0.1,
                               reach_constraint={"rpy": (180, 0, 0)})
    (kwargs, paving), = calls
    assert kwargs["pose"].rpy == (180, 0, 0) and kwargs["delta"] == 0.1
    md = path.read_text()
    text = md[md.index("## Certified orientation workspace (proved boxes)"):md.index("## Reproducibility")]
    assert "the tool frame can be exactly the rotation of roll, pitch, yaw (180, 0, 0) degrees" in text
    assert "satisfying the constraint exactly" in text and f"method {paving.method}" in text
    for kind in ("inner", "boundary", "outer"):
        count = re.search(rf"^\| {kind} \| (\d+) \|", text, re.M).group(1)
        assert int(count) == paving.counts[kind]
    lo, hi = paving.measure_bounds
    assert fmt_bracket(lo, hi, 6) in text


def test_a_section_run_reports_its_pappus_bracket(tmp_path):
    robot = robots.build("puma560")
    constraint = constraint_from(approach=(0, 0, -1), cone=20)
    paving = robot.reach(delta=0.3, pose=Pose(approach=(0, 0, -1), cone=20))
    doc = Document("t")
    _pose_section(doc, robot, paving, constraint, tmp_path)
    text = " ".join(str(b) for b in doc.blocks)
    assert "can lie within 20 degrees of (0, 0, -1)" in text
    assert "Pappus" in text and fmt_bracket(*paving.volume_bounds, 6) in text
