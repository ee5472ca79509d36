"""The report section of an orientation workspace (``dh_robot_report(..., pose=Pose(...))``): the constraint
stated, and the numbers those of the Paving ``reach`` returned under it (reference: that Paving)."""

from __future__ import annotations

from workspace_sym import robots
from workspace_sym.numbers import fmt_bracket
from workspace_sym.report import Document, _pose_section
from workspace_sym.serial import Pose
from workspace_sym.serial.pose import constraint_from


def test_a_section_run_reports_its_pappus_bracket(tmp_path):
    robot = robots.build("puma560")
    constraint = constraint_from(approach=(0, 0, -1), cone=20)
    paving = robot.reach(delta=0.3, pose=Pose(approach=(0, 0, -1), cone=20))
    doc = Document("t")
    _pose_section(doc, robot, paving, constraint, tmp_path)
    text = " ".join(str(b) for b in doc.blocks)
    assert "can lie within 20 degrees of (0, 0, -1)" in text
    assert "Pappus" in text and fmt_bracket(*paving.volume_bounds, 6) in text
