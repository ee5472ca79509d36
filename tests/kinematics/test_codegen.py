"""Generated C code (workspace_sym.codegen), compiled with the system C compiler and loaded with ctypes.

References: the library's own numeric evaluators ``fk_numeric`` / ``jacobian_numeric`` (lambdified from
the same SymPy expressions, evaluated by numpy) at configurations drawn by hypothesis, and for one arm
the plain-numpy product of DH matrices (tests/helpers/dh_reference.py), which shares no code with either.
"""

from __future__ import annotations

import ctypes
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from dh_reference import fk_numpy
from paths import DATA
from system_tools import require_tool
from workspace_sym import DHJoint, DHRobot, robots
from workspace_sym.cli import main
from workspace_sym.codegen import c_code, write_code
from workspace_sym.errors import InvalidParameterError, UnknownNameError, WorkspaceError
from workspace_sym.kinematics import xyz_rpy

DH = DATA / "dh"
CATALOG = ["glass-handling", "puma560", "scara", "planar-3r"]
FILES = ["ur5", "kr5", "irb140", "stanford", "cobra600", "panda"]
# Strict ISO C: the math.h constants (M_PI, M_SQRT2) must come from the generated fallbacks, and any warning fails.
CFLAGS = ["-std=c99", "-pedantic", "-Wall", "-Wextra", "-Werror", "-O1", "-shared", "-fPIC"]
DOUBLE_P = ctypes.POINTER(ctypes.c_double)


def _mixed_robot() -> DHRobot:
    """Base and tool transforms, a prismatic joint, a constant offset pi/7 and alpha = pi/4 (M_PI, M_SQRT2 in the
    C), a reversed joint and a symbolic length with a value: every feature the generator must carry."""
    L = sp.Symbol("L")
    joints = [DHJoint.revolute(1, d=sp.Rational(3, 10), a=L, alpha=sp.pi / 4, offset=sp.pi / 7),
              DHJoint.prismatic(2, theta=sp.pi / 2, a=sp.Rational(1, 10), alpha=-sp.pi / 2, offset=sp.Rational(1, 5)),
              DHJoint("R", -sp.Symbol("theta3"), 0, sp.Rational(1, 4), 0, sp.Symbol("theta3"))]
    base = xyz_rpy((sp.Rational(1, 2), 0, sp.Rational(1, 10)), (0, 0, sp.pi / 6))
    tool = xyz_rpy((0, 0, sp.Rational(1, 20)), (sp.pi / 2, 0, 0))
    return DHRobot(joints, name="mixed arm", parameters={"L": 0.35}, base=base, tool=tool)


def _robot(name: str) -> DHRobot:
    if name == "mixed":
        return _mixed_robot()
    return DHRobot.from_file(DH / f"{name}.json") if name in FILES else robots.build(name)


def _compile(files: list[Path], lib: Path) -> ctypes.CDLL:
    require_tool("cc", install="gcc libc6-dev")
    sources = [str(f) for f in files if f.suffix == ".c"]
    subprocess.run(["cc", *CFLAGS, "-o", str(lib), *sources, "-lm"], check=True, capture_output=True, text=True)
    return ctypes.CDLL(str(lib))


class Compiled:
    """A robot, its generated C loaded with ctypes, and calls of ``fk`` / ``jacobian`` on numpy arrays."""

    def __init__(self, robot: DHRobot, directory: Path):
        self.robot = robot
        self.files = write_code(robot, directory, prefix="ws_")
        self.lib = _compile(self.files, directory / "libkin.so")
        for name in ("ws_fk", "ws_jacobian"):
            getattr(self.lib, name).argtypes = [DOUBLE_P, DOUBLE_P]
            getattr(self.lib, name).restype = None

    def _call(self, name: str, q, shape) -> np.ndarray:
        q = np.ascontiguousarray(q, dtype=float)
        out = np.full(shape, np.nan)
        getattr(self.lib, name)(q.ctypes.data_as(DOUBLE_P), out.ctypes.data_as(DOUBLE_P))
        return out

    def fk(self, q) -> np.ndarray:
        return self._call("ws_fk", q, (4, 4))

    def jacobian(self, q) -> np.ndarray:
        return self._call("ws_jacobian", q, (6, self.robot.n))


_COMPILED: dict[str, Compiled] = {}


@pytest.fixture(scope="module")
def compiled(tmp_path_factory):
    """``compiled(name)``: the robot's C, generated and compiled once per module."""
    def get(name: str) -> Compiled:
        if name not in _COMPILED:
            _COMPILED[name] = Compiled(_robot(name), tmp_path_factory.mktemp(f"c-{name}"))
        return _COMPILED[name]
    return get


MAX_JOINTS = 7
# Joint values over two turns either way (the C code has no limits to respect), edges included; a robot with
# fewer joints takes the first n.
CONFIGURATIONS = st.lists(st.floats(-2 * np.pi, 2 * np.pi, allow_nan=False), min_size=MAX_JOINTS,
                          max_size=MAX_JOINTS).map(np.array)
ROBOTS = CATALOG + FILES[:-1] + [pytest.param("panda", marks=pytest.mark.slow), "mixed"]


@pytest.mark.parametrize("name", ROBOTS)
@settings(derandomize=True, max_examples=40, deadline=None)
@given(q=CONFIGURATIONS)
@example(q=np.zeros(MAX_JOINTS))
@example(q=np.full(MAX_JOINTS, np.pi))
@example(q=np.full(MAX_JOINTS, -2 * np.pi))
def test_c_matches_fk_numeric_and_jacobian_numeric(compiled, name, q):
    """Reference: the library's numpy evaluators of the same expressions, to 1e-12 (lengths in metres)."""
    c = compiled(name)
    q = q[:c.robot.n]
    np.testing.assert_allclose(c.fk(q), c.robot.fk_numeric(q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(c.jacobian(q), c.robot.jacobian_numeric(q), rtol=0, atol=1e-12)


def test_c_fk_matches_a_plain_numpy_dh_product(compiled):
    """Independent reference: the product of numeric DH matrices built from the table rows
    (tests/helpers/dh_reference.py)."""
    c = compiled("puma560")
    rng = np.random.default_rng(7)
    for q in rng.uniform(-np.pi, np.pi, size=(20, 6)):
        np.testing.assert_allclose(c.fk(q), fk_numpy(c.robot, q), rtol=0, atol=1e-12)


def test_c_jacobian_is_the_derivative_of_the_c_fk(compiled):
    """Central differences of the compiled fk: linear rows from the position, angular rows from R' R^T."""
    c = compiled("mixed")
    q, h = np.array([0.3, 0.15, -1.1]), 1e-6
    J = np.empty((6, 3))
    for k in range(3):
        dq = np.zeros(3)
        dq[k] = h
        Tp, Tm = c.fk(q + dq), c.fk(q - dq)
        dT = (Tp - Tm) / (2 * h)
        W = dT[:3, :3] @ c.fk(q)[:3, :3].T
        J[:, k] = np.concatenate([dT[:3, 3], [W[2, 1], W[0, 2], W[1, 0]]])
    np.testing.assert_allclose(c.jacobian(q), J, atol=1e-8)


def test_generated_code_shares_subexpressions_and_substitutes_parameters(compiled):
    """cse leaves temporaries; no symbolic length remains; the offset pi/7 and alpha = pi/4 appear through the
    math.h constants, with fallbacks for strict C99 (the -std=c99 -pedantic -Werror compile above proves they
    suffice)."""
    header, source = (p.read_text() for p in compiled("mixed").files)
    assert "const double w0 = " in source
    assert "L" not in source.split("*/", 1)[1]          # L = 0.35 substituted (the comment names it)
    assert "(1.0/7.0)*M_PI" in source
    assert "#ifndef M_PI\n#define M_PI 3.14159265358979323846\n#endif" in source
    assert "#ifndef M_SQRT2\n#define M_SQRT2 1.41421356237309504880\n#endif" in source
    assert "void ws_fk(const double * q, double * T);" in header
    assert "void ws_jacobian(const double * q, double * J);" in header
    assert "#define MIXED_ARM_N_JOINTS 3" in header
    assert "malloc" not in source and "static" not in source


def test_symbolic_length_without_value_is_named():
    robot = robots.build("glass-handling")
    bare = DHRobot(robot.joints, name="bare", parameters={"d1": 0.3, "a1": 0.05})
    with pytest.raises(InvalidParameterError, match=r"needs numeric values for a2, a3, d5") as info:
        c_code(bare)
    assert info.value.parameter == "parameters"


def test_errors_write_nothing(tmp_path):
    """A missing value, a bad prefix or language: the output directory stays empty."""
    bare = DHRobot([DHJoint.revolute(1, a=sp.Symbol("l1"))], name="bare")
    with pytest.raises(InvalidParameterError, match="l1"):
        write_code(bare, tmp_path)
    planar = robots.build("planar-2r")
    with pytest.raises(InvalidParameterError, match=r"prefix must be empty or a C identifier.*'2x'"):
        write_code(planar, tmp_path, prefix="2x")
    with pytest.raises(UnknownNameError, match=r"lang must be one of 'c'; got 'fortran'"):
        write_code(planar, tmp_path, lang="fortran")
    assert list(tmp_path.iterdir()) == []


def test_untrusted_robot_name_cannot_leave_the_directory_or_the_comment(tmp_path):
    """A DH file's name is data: the file stem keeps letters, digits and underscores, a comment cannot be closed."""
    robot = DHRobot([DHJoint.revolute(1, a=1)], name="../../x */ int evil; /*")
    paths = write_code(robot, tmp_path)
    assert [p.parent for p in paths] == [tmp_path, tmp_path]
    assert [p.name for p in paths] == ["x_int_evil.h", "x_int_evil.c"]
    assert "int evil;" not in paths[1].read_text().replace("'../../x * / int evil; / *'", "")


def test_out_is_a_file(tmp_path):
    target = tmp_path / "taken"
    target.write_text("keep me")
    with pytest.raises(WorkspaceError, match=r"out: expected a directory") as info:
        robots.build("planar-2r").codegen(out=target)
    assert info.value.parameter == "out"
    assert target.read_text() == "keep me"


def test_cli_codegen_dh_file(tmp_path, capsys):
    out = tmp_path / "ur5"
    assert main(["codegen", "--dh", str(DH / "ur5.json"), "--lang", "c", "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["files"] == [str(out / "UR5.h"), str(out / "UR5.c")]
    assert data["functions"]["jacobian"] == "void jacobian(const double *q, double *J)"
    assert data["joints"] == 6
    assert sorted(p.name for p in out.iterdir()) == ["UR5.c", "UR5.h"]


def test_cli_codegen_catalog_robot_with_prefix(tmp_path, capsys):
    assert main(["codegen", "planar-3r", "--prefix", "p3_", "--out", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    assert "void p3_fk(const double *q, double *T)" in captured.out
    assert "wrote" in captured.err and "planar_3r.c" in captured.err
    assert "void p3_jacobian(const double * q, double * J)" in (tmp_path / "planar_3r.h").read_text()


def test_cli_codegen_bad_out_is_one_line_exit_2(tmp_path, capsys):
    target = tmp_path / "file"
    target.write_text("")
    assert main(["codegen", "planar-3r", "--out", str(target)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith("workspace-sym codegen: error: --out: cannot write into") and "not a directory" in err


ARM_URDF = ('<robot name="arm"><link name="base"/><link name="upper"/><link name="fore"/><link name="tip"/>'
            '<joint name={0} type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>'
            '<limit lower="-2" upper="2"/></joint>'
            '<joint name="elbow" type="continuous"><parent link="upper"/><child link="fore"/>'
            '<origin xyz="0.4 0 0"/><axis xyz="0 0 1"/></joint>'
            '<joint name="flange" type="fixed"><parent link="fore"/><child link="tip"/><origin xyz="0.3 0 0"/></joint>'
            '</robot>')
ARM_MJCF = ('<mujoco model="arm"><worldbody><body name="upper"><joint name="shoulder" axis="0 0 1"/>'
            '<geom size="0.02"/><body name="fore" pos="0.4 0 0"><joint axis="0 0 1"/><geom size="0.02"/>'
            '<body name="tip" pos="0.3 0 0"/></body></body></worldbody></mujoco>')


def test_header_names_the_joints_of_the_file(tmp_path):
    """Issue 39: for a robot read from a URDF or MJCF file the header says which of the file's joints each q[k] is
    (fixed joints skipped); a name is comment text, so one holding '*/' and '/*' still compiles under -Werror.
    Reference: the compiled fk against fk_numeric, and the plain 2R arm 0.4 c1 + 0.3 c12 by hand."""
    from xml.sax.saxutils import quoteattr

    pytest.importorskip("yourdfpy")
    hostile = "shoulder */ int evil; /* x"
    path = tmp_path / "arm.urdf"
    path.write_text(ARM_URDF.format(quoteattr(hostile)))
    mjcf = tmp_path / "arm.xml"
    mjcf.write_text(ARM_MJCF)
    for robot, names in ((DHRobot.from_urdf(path), ("shoulder * / int evil; / * x", "elbow")),
                         (DHRobot.from_mjcf(mjcf), ("shoulder", "joint 1 of body fore"))):
        c = Compiled(robot, tmp_path / f"c-{len(list(tmp_path.iterdir()))}")
        header = c.files[0].read_text()
        assert (f"Joint vector: q[0] = theta1 = joint '{names[0]}' (revolute, rad), q[1] = theta2 = joint "
                f"'{names[1]}' (revolute, rad).") in header
        assert "No allocation" in header[:header.index("*/")]     # the hostile name did not close the comment
        q = np.array([0.3, -0.7])
        np.testing.assert_allclose(c.fk(q), robot.fk_numeric(q), atol=1e-12)
        np.testing.assert_allclose(c.fk(q)[:2, 3], [0.4 * np.cos(0.3) + 0.3 * np.cos(-0.4),
                                                    0.4 * np.sin(0.3) + 0.3 * np.sin(-0.4)], atol=1e-12)
    assert robot.to_convention("modified").joints[0].name == "shoulder"       # a label the conversion keeps
    assert "q[0] = theta1 (revolute, rad)," in c_code(robots.build("planar-2r"))["planar_2r.h"]   # a DH table
