"""``report`` reads a robot as every other subcommand does (``--urdf``, ``--mjcf``, ``--base``, ``--tip``,
``--snap-tol``, ``--keep-floats``) and ``report`` / ``demo`` print JSON (issue 27, engineer).  References: the
report of the same robot given as a DH file, and the JSON contract of docs/cli.md (keys added, never renamed)."""

import json

import pytest

from workspace_sym.cli import main

# A planar 2R arm, l0 -> l1 -> l2 -> tool: links 0.5 and 0.25 long, the tool frame turned by 1.5707963 (pi/2 to the
# 8 digits written: snapped to pi/2 by default, kept as a float with --snap-tol 0 or --keep-floats).
URDF = """<?xml version="1.0"?>
<robot name="two">
  <link name="l0"/><link name="l1"/><link name="l2"/><link name="tool"/>
  <joint name="j1" type="revolute"><parent link="l0"/><child link="l1"/>
    <origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.5 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="t" type="fixed"><parent link="l2"/><child link="tool"/>
    <origin xyz="0.25 0 0" rpy="0 0 1.5707963"/></joint>
</robot>
"""


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def urdf(tmp_path):
    path = tmp_path / "two.urdf"
    path.write_text(URDF)
    return path


def test_report_reads_a_urdf_with_the_robot_options(urdf, tmp_path, capsys):
    """report --urdf FILE was refused (unrecognized arguments).  The report of the URDF arm shows the position fk
    prints for the same options (reference: fk --json): --tip picks the chain (l2: 0.5 c1 only), --snap-tol and
    --keep-floats act as for fk (the tool's 1.5707963 snapped to pi/2, or kept as a float)."""
    code, out, err = run(capsys, "report", "--urdf", str(urdf), "--tip", "l2", "--out", str(tmp_path / "r"),
                         "--json")
    assert code == 0, err
    summary = json.loads(out)
    md = (tmp_path / "r" / "report.md").read_text()
    assert summary["report"] == str(tmp_path / "r" / "report.md") and summary["joints"] == 2
    assert set(summary["files"]) >= {"markdown", "html", "latex"}
    assert json.loads(run(capsys, "fk", "--urdf", str(urdf), "--tip", "l2", "--json")[1])["position"][0] == \
        "cos(theta1)/2"
    assert "$$ p_{x} = \\frac{c_{1}}{2} $$" in md
    reports = {}
    for name, argv in (("snapped", []), ("tol0", ["--snap-tol", "0"]), ("floats", ["--keep-floats"])):
        code, out, err = run(capsys, "report", "--urdf", str(urdf), "--base", "l0", "--tip", "tool", *argv,
                             "--out", str(tmp_path / name))
        assert code == 0, err
        reports[name] = (tmp_path / name / "report.md").read_text(), err
    assert "1.5707963 -> pi/2" in reports["snapped"][1] and "r_{11} = - s_{12}" in reports["snapped"][0]
    assert "kept as a float" in reports["tol0"][1] and "2.6794896585028633 \\cdot 10^{-8}" in reports["tol0"][0]
    assert "0.5 c_{1}" in reports["floats"][0] and "0.5 c_{1}" not in reports["tol0"][0]


@pytest.mark.parametrize(("argv", "needle"), [
    (["planar-2r", "--urdf", "{urdf}"], "give either 'planar-2r' or a robot file"),
    (["--dh", "{urdf}", "--urdf", "{urdf}"], "give one of"),
    (["planar-2r", "--tip", "l2"], "--base and --tip name links"),
    (["--urdf", "{urdf}", "--tip", "nowhere"], "--tip"),
    (["chain", "--lengths", "1,1", "--lower", "0,0", "--upper", "90,90", "--urdf", "{urdf}"], "chain"),
])
def test_report_robot_options_bad_input(urdf, tmp_path, capsys, argv, needle):
    code, out, err = run(capsys, "report", *[a.format(urdf=urdf) for a in argv], "--out", str(tmp_path / "no"))
    assert code == 2 and err.count("\n") == 1 and needle in err, err
    assert err.startswith("workspace-sym report: error:") and not (tmp_path / "no").exists()


def test_report_json_of_a_catalog_robot_and_a_chain(tmp_path, capsys):
    code, out, err = run(capsys, "report", "planar-2r", "--out", str(tmp_path / "a"), "--json")
    assert code == 0
    summary = json.loads(out)
    assert summary["report"] == str(tmp_path / "a" / "report.md") and summary["robot"] == "planar-2r"
    assert summary["files"]["html"] == str(tmp_path / "a" / "report.html") and summary["seconds"] >= 0
    assert all(f.startswith(str(tmp_path / "a")) for f in summary["figures"])
    code, out, err = run(capsys, "report", "chain", "--lengths", "1,0.5", "--lower", "0,-90", "--upper", "90,90",
                         "--out", str(tmp_path / "c"), "--json")
    assert code == 0
    summary = json.loads(out)
    assert summary["report"] == str(tmp_path / "c" / "report.md") and summary["figures"]
    assert "wrote" in err and "report:" not in out.replace('"report":', "")


def test_demo_json(tmp_path, capsys):
    """demo --json: the report's files and the two results it prints as text (reference: the demo's own text, as
    pinned by tests/presentation/test_cli.py::test_demo_writes_the_report: 16 / 11 / 8 arcs; the 2-RPR bracket holds
    its exact
    area 35.05335)."""
    code, out, err = run(capsys, "demo", "--out", str(tmp_path / "d"), "--json")
    assert code == 0
    summary = json.loads(out)
    assert summary["report"] == str(tmp_path / "d" / "report.md")
    assert summary["boundary"]["counts"] == {"step0": 16, "step1": 11, "step2": 8}
    lo, hi = summary["paving"]["measure_bounds"]
    assert lo <= summary["paving"]["exact_measure"] <= hi and abs(summary["paving"]["exact_measure"] - 35.05335) < 1e-5
    assert summary["boundary"]["area"] > 0 and summary["seconds"] > 0
