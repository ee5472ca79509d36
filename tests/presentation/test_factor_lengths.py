"""Singular factors are printed in the robot's own lengths, not scaled to integers (issue 39, Engineer item 2).

The gcd of the maximal minors returns each factor primitive (the UR5's ``8500*c2 + 7845*c23 - 1893*s234``, the
KR16's ``7*c3 + 134*s3``); printed, a factor reads in the table's lengths (``0.425 c2 + 0.39225 c23 - 0.09465
s234``).  References: the lengths as the robot files write them (the UR5's JSON table, the ``xyz`` of the KR16
URDF's joint origins), and the exact SymPy ratio of each printed factor to the exact one (a non-zero constant:
a factor is defined up to one).
"""

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import rtbdata
import sympy as sp

from dh_reference import unshorthand
from paths import DATA
from workspace_sym import DHRobot
from workspace_sym.cli import main

UR5 = DATA / "dh" / "ur5.json"
KR16 = Path(rtbdata.__file__).parent / "xacro/kuka_description/kuka_kr16/urdf/kr16_2.urdf"


def _ur5_lengths():
    rows = json.loads(UR5.read_text())["joints"]
    return {abs(sp.Rational(str(row[k]))) for row in rows for k in ("d", "a")} - {0}


def _kr16_lengths():
    origins = ET.parse(KR16).getroot().iter("origin")
    return {abs(sp.Rational(v)) for o in origins for v in o.get("xyz", "").split()} - {0}


def _printed_factors(capsys, *robot):
    assert main(["jacobian", *robot, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    return [(sp.sympify(s["textbook"]), sp.sympify(s["factor"])) for s in data["singularities"]], data


def _check(pairs, lengths, q, expected):
    sums = []
    for printed, exact in pairs:
        ratio = sp.simplify(unshorthand(printed, q) / exact)
        assert ratio.is_number and ratio.is_positive, (printed, exact, ratio)        # the same factor
        if printed.is_Add:
            coefficients = {abs(sp.Rational(str(t.as_coeff_Mul()[0]))) for t in printed.args}
            assert coefficients <= lengths, (printed, coefficients - lengths)      # every one a length
            sums.append(coefficients)
    assert sums == expected


def test_ur5_factor_prints_in_the_tables_lengths(capsys):
    pairs, data = _printed_factors(capsys, "--dh", str(UR5))
    q = sp.symbols("theta1:7")
    _check(pairs, _ur5_lengths(), q, [{sp.Rational("0.425"), sp.Rational("0.39225"), sp.Rational("0.09465")}])
    assert data["textbook"]["singular"][2] == "0.425*c2 + 0.39225*c23 - 0.09465*s234"
    assert "8500*cos(theta2)" in data["singular"][2]             # the exact primitive factor is kept for code
    assert main(["jacobian", "--dh", str(UR5)]) == 0
    assert "singular where: s3 * s5 * (0.425*c2 + 0.39225*c23 - 0.09465*s234) = 0" in capsys.readouterr().out


def test_kr16_factors_print_in_the_urdfs_lengths(capsys):
    pairs, data = _printed_factors(capsys, "--urdf", str(KR16))
    q = sp.symbols("theta1:7")
    L = sp.Rational
    _check(pairs, _kr16_lengths(), q, [{L("0.035"), L("0.67")}, {L("0.68"), L("0.67"), L("0.035"), L("0.26")}])
    assert data["textbook"]["singular"][1] == "0.035*c3 + 0.67*s3"


def test_dh_report_prints_factors_in_lengths(tmp_path):
    from workspace_sym.report import dh_robot_report

    md = dh_robot_report(DHRobot.from_file(UR5), tmp_path / "r", samples=100).read_text()
    assert "f_{3} = 0.425 c_{2} + 0.39225 c_{23} - 0.09465 s_{234}" in md and "8500" not in md
