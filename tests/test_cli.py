"""The command line: JSON contract of INTERFACE.md, exit status 2 and one stderr line on bad input."""

import json
import subprocess
import sys

import sympy as sp

from workspace_sym.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_fk_json_contract(capsys):
    code, out, err = run(capsys, "fk", "glass-handling", "--json")
    assert code == 0
    data = json.loads(out)
    assert len(data["T"]) == 4 and all(len(row) == 4 for row in data["T"])
    x = sp.sympify(data["position"][0])
    t1, t2, t3, t4 = sp.symbols("theta1:5")
    a1, a2, a3, d5 = sp.symbols("a1 a2 a3 d5")
    assert sp.simplify(x - sp.cos(t1) * (a1 + a2 * sp.cos(t2) + a3 * sp.cos(t2 + t3) + d5 * sp.sin(t2 + t3 + t4))) == 0
    assert data["textbook"]["position"][0] == "c1*(a1 + a2*c2 + a3*c23 + d5*s234)"
    assert isinstance(data["seconds"], float)


def test_jacobian_json_contract(capsys):
    code, out, _ = run(capsys, "jacobian", "planar-3r", "--json")
    data = json.loads(out)
    assert code == 0 and data["kind"] == "geometric"
    assert len(data["J"]) == 6 and len(data["J"][0]) == 3
    assert "sin(theta2)" in data["singular"]


def test_jacobian_analytic_states_representation_singularity(capsys):
    code, out, _ = run(capsys, "jacobian", "glass-handling", "--kind", "analytic", "--json")
    data = json.loads(out)
    assert code == 0 and data["kind"] == "analytic" and data["euler"] == "zyz"
    assert "= 0" in data["representation_singularity"]


def test_latex_output(capsys):
    code, out, _ = run(capsys, "fk", "planar-2r", "--latex")
    assert code == 0 and r"\left[" in out and "c_{12}" in out


def test_robots_lists_catalog(capsys):
    code, out, _ = run(capsys, "robots", "--json")
    names = {r["name"] for r in json.loads(out)["robots"]}
    assert {"glass-handling", "puma560", "scara", "planar-2r", "planar-3r"} <= names


def test_dh_file(tmp_path, capsys):
    f = tmp_path / "arm.json"
    f.write_text(json.dumps({"joints": [{"type": "R", "d": 0, "a": "l1", "alpha": 0},
                                        {"type": "R", "d": 0, "a": "l2", "alpha": 0}]}))
    code, out, _ = run(capsys, "fk", "--dh", str(f), "--json")
    assert code == 0
    assert json.loads(out)["position"][0] == "l1*cos(theta1) + l2*cos(theta1 + theta2)"


def test_bad_input_exit_2_one_line(tmp_path, capsys):
    f = tmp_path / "bad.json"
    f.write_text(json.dumps({"joints": [{"type": "R", "d": 0, "a": 1}]}))
    code, out, err = run(capsys, "fk", "--dh", str(f), "--json")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "missing field 'alpha'" in err


def test_unknown_robot_exit_2(capsys):
    code, _, err = run(capsys, "fk", "nosuchbot")
    assert code == 2 and "nosuchbot" in err and err.count("\n") == 1


def test_python_dash_m_entry_point():
    proc = subprocess.run([sys.executable, "-m", "workspace_sym", "fk", "nosuch"], capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
    proc = subprocess.run([sys.executable, "-m", "workspace_sym", "fk", "--bogus"], capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
