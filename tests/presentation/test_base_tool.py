"""`fk` and the DH report show the base and tool transforms around the DH table (issue 39, Engineer item 1).

A reader must be able to rebuild the printed T from what is printed: the printed base, the DH table's product
``T_0^n`` and the printed tool multiply back to the printed T.  References: that exact SymPy identity; the DH
product itself checked against the plain-numpy DH product of the table rows (``dh_reference.fk_numpy``); the KR16's
base ``diag(1, -1, -1)`` and tool (``-79/500`` along z, x and z turned) as the URDF file writes them
(``kr16_2.urdf``: ``base_link-base`` rpy ``pi 0 0``, ``joint_a6-tool0`` rpy ``0 -pi/2 0`` after the axes set for DH).
"""

import json
from pathlib import Path

import numpy as np
import pytest
import rtbdata
import sympy as sp

from dh_reference import fk_numpy, unshorthand
from reports import report_with_document
from workspace_sym import DHRobot
from workspace_sym.cli import main
from workspace_sym.report import dh_robot_report

KR16 = Path(rtbdata.__file__).parent / "xacro/kuka_description/kuka_kr16/urdf/kr16_2.urdf"

# one revolute and one prismatic joint between a base turned about x (and lifted) and a tool turned about z
ARM = ('{"name": "bt", "convention": "standard", "angles": "degrees", "joints": ['
       '{"type": "R", "d": "0.3", "a": "0.2", "alpha": 90}, {"type": "P", "theta": 0, "a": 0, "alpha": 0}], '
       '"base": {"xyz": [0, 0, "0.5"], "rpy": [180, 0, 0]}, "tool": {"xyz": [0, 0, "0.3"], "rpy": [0, 0, 90]}}')


@pytest.fixture
def arm_file(tmp_path):
    path = tmp_path / "bt.json"
    path.write_text(ARM)
    return path


def _fk_json(capsys, *argv):
    assert main(["fk", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _matrix(rows):
    return sp.Matrix([[sp.sympify(e) for e in row] for row in rows])


def _rebuilds(data, robot):
    """The JSON's base · dh_product · tool is its T, exactly; the DH product is the table's (plain numpy)."""
    T, chain = _matrix(data["T"]), _matrix(data["dh_product"])
    base = _matrix(data["base"]) if data["base"] is not None else sp.eye(4)
    tool = _matrix(data["tool"]) if data["tool"] is not None else sp.eye(4)
    assert sp.simplify(base * chain * tool - T) == sp.zeros(4, 4)
    q = np.array([0.3, -0.7, 1.1, 0.4, -0.9, 0.5][:robot.n])
    at = dict(zip(robot.q, q))
    assert np.allclose(np.array(chain.subs(at), dtype=float), fk_numpy(robot, q), atol=1e-12)
    return base, tool


def test_fk_json_of_a_dh_file_with_base_and_tool_rebuilds_T(arm_file, capsys):
    data = _fk_json(capsys, "--dh", str(arm_file))
    base, tool = _rebuilds(data, DHRobot.from_file(arm_file))
    assert data["T_is"] == "T = base · T_0^2 · tool"
    # the file's base: turned 180 deg about x, 0.5 up; its tool: turned 90 deg about z, 0.3 along z
    assert base == sp.Matrix([[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, sp.Rational(1, 2)], [0, 0, 0, 1]])
    assert tool == sp.Matrix([[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, sp.Rational(3, 10)], [0, 0, 0, 1]])
    assert data["textbook"]["tool"][2][3] == "0.3" and "mathrm" not in data["latex"]["base"]


def test_fk_json_without_base_or_tool_says_so(capsys):
    data = _fk_json(capsys, "planar-2r")
    assert data["base"] is None and data["tool"] is None and data["T_is"] == "T = T_0^2"
    assert data["dh_product"] == data["T"]


def test_fk_text_and_latex_print_base_and_tool(arm_file, capsys):
    assert main(["fk", "--dh", str(arm_file)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("bt: T = base · T_0^2 · tool (standard DH)")
    assert "  base: 1 | 0 | 0 | 0; 0 | -1 | 0 | 0; 0 | 0 | -1 | 1/2" in out
    assert "  tool: 0 | -1 | 0 | 0; 1 | 0 | 0 | 0; 0 | 0 | 1 | 0.3" in out
    assert main(["fk", "--dh", str(arm_file), "--latex"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(" = ")[0] for line in lines] == [r"\mathrm{base}", r"\mathrm{tool}", "T_0^{2}", "T"]
    assert lines[3].startswith(r"T = \mathrm{base}\,T_0^{2}\,\mathrm{tool} = \left[")


def test_fk_of_the_kr16_urdf_shows_its_base_and_tool(capsys):
    data = _fk_json(capsys, "--urdf", str(KR16))
    base, tool = _rebuilds(data, DHRobot.from_urdf(KR16))
    assert base == sp.diag(1, -1, -1, 1)
    assert tool[:3, 3] == sp.Matrix([0, 0, sp.Rational(-79, 500)]) and tool[:3, :3] == sp.diag(-1, 1, -1)
    # the puzzle: the table's d1 = -0.675 and T's p_z ending in + 0.675 (the base turns z over)
    q = sp.symbols("theta1:7")
    constant = [sp.expand(sp.sympify(rows[2][3])).as_independent(*q, as_Add=True)[0]
                for rows in (data["dh_product"], data["T"])]
    assert constant == [sp.Rational(-27, 40), sp.Rational(27, 40)]
    assert data["T_is"] == "T = base · T_0^6 · tool"


def test_dh_report_shows_base_and_tool_and_they_rebuild_T(arm_file, tmp_path):
    robot = DHRobot.from_file(arm_file)
    md_path, doc = report_with_document(lambda f: dh_robot_report(robot, f, samples=200), tmp_path / "r")
    md = md_path.read_text()
    assert "## Forward kinematics T = base · T\\_0^2 · tool" in md
    assert "\\text{base} = \\begin{pmatrix}" in md and "\\text{tool} = \\begin{pmatrix}" in md
    html = (md_path.parent / "report.html").read_text()
    assert "<mtext>base</mtext>" in html and "<mtext>tool</mtext>" in html
    tex = (md_path.parent / "report.tex").read_text()
    assert "\\text{tool} &= \\begin{pmatrix}" in tex
    shown = {str(lhs): e for block in doc.blocks if block[0] == "eqs" for lhs, e in block[1]}
    base, tool = (unshorthand(shown[k], robot.q) for k in ("base", "tool"))
    T = sp.Matrix(4, 4, lambda i, j: unshorthand(shown[f"r_{i + 1}{j + 1}"], robot.q) if i < 3 and j < 3 else
                  unshorthand(shown["p_" + "xyz"[i]], robot.q) if i < 3 else int(j == 3))
    chain = sp.eye(4)
    for k in range(1, robot.n + 1):            # the table's rows, as the report's DH table lists them
        chain = chain * robot.row_matrix(k)
    assert sp.simplify(base * chain * tool - T) == sp.zeros(4, 4)
    assert base != sp.eye(4) and tool != sp.eye(4)


def test_dh_report_of_a_bare_table_names_T_0_n(tmp_path):
    robot = DHRobot.from_dict({"joints": [{"type": "R", "d": 0, "a": 1, "alpha": 0}]})
    md = dh_robot_report(robot, tmp_path / "r", samples=100).read_text()
    assert "## Forward kinematics T\\_0^1\n" in md and "(no base or tool transform)" in md
    assert "\\text{base}" not in md
