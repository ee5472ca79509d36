"""URDF files nobody here wrote (the rtb-data package), and float DH tables made exact.

References: the URDF library's own forward kinematics (yourdfpy, an independent
implementation of the same file), exact SymPy identities between the float and
the exact Puma tables, and substitution of configurations into the Jacobian.
"""

from __future__ import annotations

import functools
import json
import math
from pathlib import Path

import numpy as np
import pytest
import rtbdata
import sympy as sp
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from workspace_sym import DHRobot
from workspace_sym.cli import main
from workspace_sym.errors import URDFError
from workspace_sym.snap import Snapper, exact_decimal, snap_angle, written_unit

XACRO = Path(rtbdata.__file__).parent / "xacro"
URDFS = {
    "irb140": (XACRO / "abb_irb140_description/urdf/irb140.urdf", None),
    "kr16": (XACRO / "kuka_description/kuka_kr16/urdf/kr16_2.urdf", None),
    "kr210": (XACRO / "kuka_description/kuka_kr210/urdf/kr210l150.urdf", "tool0"),   # Link1 branches off link_1
    "iiwa14": (XACRO / "kuka_description/kuka_lbr_iiwa/urdf/lbr_iiwa_14_r820.urdf", None),
}
# 1.57079632679 in the tool0 origins of irb140 and kr16 is pi/2 - 4.9e-12: snapped at tol 1e-9, so the exact
# model differs from the file by that much (the note says so); the others have only exact angles.
SNAP_GAP = {"irb140": 4.9e-12, "kr16": 4.9e-12, "kr210": 0.0, "iiwa14": 0.0}


def _library_fk(path, tip, qs):
    """Tip poses from yourdfpy itself (scene graph without meshes)."""
    import yourdfpy  # here, not at the top: only the worker that runs this file imports it (and trimesh)

    model = yourdfpy.URDF.load(str(path), build_scene_graph=True, load_meshes=False)
    out = []
    for q in qs:
        model.update_cfg(q)
        out.append(model.get_transform(tip, model.base_link))
    return np.array(out)


@functools.cache
def _read(name):
    """The URDF of ``name`` read with the default options, once per module (the tests only read it: its fk,
    Jacobian and factors are derived once and kept)."""
    path, tip = URDFS[name]
    return DHRobot.from_urdf(path, tip_link=tip)


@pytest.mark.parametrize("name", sorted(URDFS))
def test_fk_equals_the_urdf_library(name):
    path, tip = URDFS[name]
    robot = _read(name)
    qs = np.random.default_rng(7).uniform(-3.0, 3.0, size=(12, robot.n))
    reference = _library_fk(path, tip or "tool0", qs)
    # nothing snapped (tol = 0: only angles that are exactly 0 or a multiple of pi/360 as floats): the DH
    # extraction alone, to 1e-12 (reference: yourdfpy)
    as_written = DHRobot.from_urdf(path, tip_link=tip, tol=0.0) if SNAP_GAP[name] else robot   # same when no snap
    assert np.abs(as_written.fk_numeric(qs) - reference).max() < 1e-12
    # exact (default): off by the snapped amount only, times a reach of about 3 m
    assert np.abs(robot.fk_numeric(qs) - reference).max() < 1e-12 + 4 * SNAP_GAP[name]
    assert not robot.fk().atoms(sp.Float), "an exact URDF gives an exact FK"


def test_irb140_table_limits_and_notes():
    robot = _read("irb140")
    assert robot.name == "abb_irb140" and robot.n == 6 and robot.base is None
    # joint_2 sits 0.28 out and 1.38 up: a1 = 7/25, d1 = 69/50 exactly (decimals of the file)
    assert (robot.joints[0].a, robot.joints[0].d, robot.joints[0].alpha) == (sp.Rational(7, 25), sp.Rational(69, 50),
                                                                             -sp.pi / 2)
    assert robot.joints[1].a == sp.Rational(71, 50)
    notes = "\n".join(robot.input_notes)
    assert "joint 'joint_6-tool0' origin rpy: 1.57079632679 -> pi/2" in notes
    # 3.1416 is 7.3e-6 from pi: not snapped at 1e-9, and the note says so
    assert "3.1416 kept as a float" in notes
    assert robot.joints[0].limits == (sp.Float(-3.1416), sp.Float(3.1416))
    assert "frame 0 is the base link's frame" in robot.input_notes[0]
    # z of the tip from the file by hand at q = 0: 1.38 + 1.42 + 0.02 (joint_6 is 0.02 above joint_5)
    tip_z = robot.fk().subs({q: 0 for q in robot.q})[2, 3]
    assert tip_z == sp.Rational("1.38") + sp.Rational("1.42") + sp.Rational("0.02")


def test_kuka_limits_snap_to_whole_degrees_and_base_transform():
    robot = _read("kr16")
    # KUKA writes 185 deg as 3.22885911619 (37*pi/36 to 5e-13): snapped
    assert robot.joints[0].limits == (-37 * sp.pi / 36, 37 * sp.pi / 36)
    assert robot.joints[1].limits == (-31 * sp.pi / 36, 7 * sp.pi / 36)
    # axis 1 is -z: frame 0 needs a base transform, and the reader says so
    assert robot.base is not None and "with a base transform" in robot.input_notes[0]


def _jacobian_singular_values(robot, q):
    J = robot.jacobian_numeric(np.atleast_2d(q))[0]
    return np.linalg.svd(J, compute_uv=False)


@pytest.mark.parametrize("name", ["kr16", "irb140"])
def test_singular_factors_checked_by_substitution(name):
    """Each factor's zero set makes J lose rank; away from them det J is a constant times their product."""
    robot = _read(name)
    factors = robot.singular_factors(multiplicity=True)
    if name == "kr16":   # wrist-partitioned: wrist s5, an elbow and a shoulder factor (theta2, theta3 only)
        assert len(factors) == 3 and factors[0] == (sp.sin(robot.q[4]), 1)
        assert factors[1][0].free_symbols == {robot.q[2]}
        assert factors[2][0].free_symbols == {robot.q[1], robot.q[2]}
    rng = np.random.default_rng(3)
    product = sp.lambdify(robot.q, sp.Mul(*[f ** m for f, m in factors]))
    ratios = []
    for _ in range(5):
        q = rng.uniform(-2.5, 2.5, robot.n)
        J = robot.jacobian_numeric(q)
        ratios.append(np.linalg.det(J) / product(*q))
    assert np.allclose(ratios, ratios[0], rtol=1e-8) and abs(ratios[0]) > 1e-6
    for f, _ in factors:
        g = sp.lambdify(robot.q, f)
        var = sorted(f.free_symbols, key=str)[0]
        k = robot.q.index(var)
        q = rng.uniform(-2.5, 2.5, robot.n)
        grid = np.linspace(-math.pi, math.pi, 721)
        values = []
        for t in grid:
            q[k] = t
            values.append(g(*q))
        i = int(np.flatnonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0])
        lo, hi = grid[i], grid[i + 1]
        for _ in range(60):   # bisection on the factor: a configuration where it vanishes
            q[k] = mid = (lo + hi) / 2
            if np.sign(g(*q)) == np.sign(values[i]):
                lo = mid
            else:
                hi = mid
        s = _jacobian_singular_values(robot, q)
        assert s[-1] < 1e-9 * s[0], f"{f} = 0 but J has full rank"


# ------------------------------------------------------------------------------ float DH tables
PUMA_ROWS = [(0, 0, "pi/2"), (0, "0.4318", 0), ("0.15005", "0.0203", "-pi/2"), ("0.4318", 0, "pi/2"),
             (0, 0, "-pi/2"), (0, 0, 0)]
PUMA_LIMITS_DEG = [(-160, 160), (-110, 110), (-135, 135), (-266, 266), (-100, 100), (-266, 266)]


def _puma(floats: bool) -> dict:
    """The Puma 560 as a radians DH table: floats as another toolbox prints them, or exact strings."""
    joints = []
    for (d, a, alpha), (lo, hi) in zip(PUMA_ROWS, PUMA_LIMITS_DEG):
        if floats:
            joints.append({"d": float(sp.sympify(d)), "a": float(sp.sympify(a)), "alpha": float(sp.sympify(alpha)),
                           "limits": [math.radians(lo), math.radians(hi)]})
        else:
            joints.append({"d": d, "a": a, "alpha": alpha, "limits": [f"{lo}*pi/180", f"{hi}*pi/180"]})
    return {"angles": "radians", "joints": joints}


def test_float_puma_is_the_exact_puma():
    """Identical expressions (exact SymPy equality), not just close numbers."""
    exact, floats = DHRobot.from_dict(_puma(False)), DHRobot.from_dict(_puma(True))
    assert _puma(True)["joints"][0]["alpha"] == 1.5707963267948966
    assert floats.fk() == exact.fk()
    assert floats.geometric_jacobian == exact.geometric_jacobian
    assert floats.singular_factors(multiplicity=True) == exact.singular_factors(multiplicity=True)
    assert [j.limits for j in floats.joints] == [j.limits for j in exact.joints]
    assert "joint 1 alpha: 1.5707963267948966 -> pi/2" in floats.input_notes
    assert "joint 2 a: 0.4318 -> 2159/5000" in floats.input_notes and not exact.input_notes
    # and the catalog Puma (symbolic lengths) with the same lengths substituted: same position, exactly
    from workspace_sym import robots

    catalog = robots.build("puma560")
    lengths = {sp.Symbol(k): sp.Rational(v) for k, v in (("a2", "0.4318"), ("a3", "0.0203"), ("d3", "0.15005"),
                                                          ("d4", "0.4318"))}
    assert all(sp.expand(sp.expand_trig(e)) == 0 for e in catalog.position.subs(lengths) - floats.position)


def test_keep_floats_chops_the_dust():
    robot = DHRobot.from_dict(_puma(True), exact=False)
    T = robot.fk()
    assert T.atoms(sp.Float) and min(abs(f) for f in T.atoms(sp.Float) if f != 0) > 1e-9
    assert not robot.input_notes
    q = np.random.default_rng(0).uniform(-3, 3, size=(20, 6))
    assert np.abs(robot.fk_numeric(q) - DHRobot.from_dict(_puma(True)).fk_numeric(q)).max() < 1e-12


def test_degrees_table_and_transforms_snap():
    data = {"joints": [{"d": 0, "a": 0.5, "alpha": 90.0}, {"d": 0.0, "a": 0.25, "alpha": 0}],
            "tool": {"xyz": [0, 0, 0.1], "rpy": [0, 1.5707963267948966, 0]}}
    robot = DHRobot.from_dict({**data, "angles": "degrees", "tool": {"xyz": [0, 0, 0.1], "rpy": [0, 90.0, 0]}})
    assert robot.joints[0].alpha == sp.pi / 2 and robot.joints[0].a == sp.Rational(1, 2)
    assert robot.tool[:3, :3] == sp.Matrix([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    radians = DHRobot.from_dict({**data, "joints": [{"d": 0, "a": 0.5, "alpha": 1.5707963267948966},
                                                    data["joints"][1]], "angles": "radians"})
    assert radians.fk() == robot.fk()


@settings(max_examples=200, deadline=None)
@given(st.integers(-1440, 1440), st.floats(-0.9, 0.9))
def test_snap_angle_property(k, fraction):
    """A multiple of pi/360 moved by less than tol snaps back to it; moved by more than tol, never to it."""
    tol = 1e-9
    exact = sp.Rational(k, 360) * sp.pi
    assert snap_angle(float(exact) + fraction * tol, tol) == exact
    moved = float(exact) + math.copysign(3 * tol, fraction or 1.0)
    assert snap_angle(moved, tol) is None


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e6, 1e6, allow_nan=False))
def test_exact_decimal_stands_for_the_float(x):
    r = exact_decimal(x)
    assert abs(float(r) - x) <= 4 * math.ulp(x)
    # a decimal: the denominator divides a power of ten, and at most 17 significant digits
    assert 10 ** 400 % r.q == 0 and abs(r.p) < 10 ** 17


def test_snapper_tolerance_is_settable():
    # tol = 0: only floats on the grid snap (the ROS rounding rule is off too); tol = 2e-9 snaps the Puma's pi/2
    assert Snapper(tol=0.0).angle(1.570796325, "x") == sp.Float(1.570796325)
    assert Snapper(tol=2e-9).angle(1.570796325, "x") == sp.pi / 2


def test_ros_rounded_angles_snap_by_default():
    """Issue 23 item 4: ROS files write pi/2 as 1.570796325 (1.8e-9 off, 10 digits) and pi as 3.14159265 (3.6e-9
    off, 9 digits): both snap at the default, each with a note saying how to keep the float; 1.5708 (5 digits) is
    kept, since a 5-digit angle lands that close to the grid by chance one time in 40."""
    s = Snapper()
    assert (s.angle(1.570796325, "j1"), s.angle(-3.14159265, "j2"), s.angle(1.5707963, "j3")) == (
        sp.pi / 2, -sp.pi, sp.pi / 2)
    assert all("exact=False" in note and "--keep-floats" in note for note in s.notes) and len(s.notes) == 3
    assert "j1: 1.570796325 -> pi/2 (it is written to 10 digits" in s.notes[0]
    assert s.angle(1.5708, "j4") == sp.Float(1.5708) and "1.5708 kept as a float" in s.notes[-1]
    assert Snapper(exact=False).angle(1.570796325, "j1") == sp.Float(1.570796325)      # the way to keep it


@settings(derandomize=True, max_examples=150, deadline=None)
@given(st.integers(-1440, 1440), st.integers(8, 12), st.floats(0.0, 1.0))
def test_rounded_multiples_of_the_grid_snap_and_others_do_not(k, digits, shift):
    """Property: k pi/360 written to 8-12 significant digits snaps back to it (exact reference); a value moved
    off it snaps only within two units of its own last written digit."""
    exact = sp.Rational(k, 360) * sp.pi
    text = f"{float(exact):.{digits}g}"
    written, unit = written_unit(float(text))
    assume(written >= 8)                       # 3.9706240 prints as 3.970624: seven digits, not snapped
    assert Snapper().angle(float(text), "a") == exact
    moved = float(text) + 5 * unit * (1 + shift)
    # moved by 5 units it may still snap, but only if it is written coarser: never farther than 2 units of its own
    # last digit (or tol) from the multiple it snaps to
    snapped = Snapper().angle(moved, "a")
    assert not snapped.has(sp.pi) or abs(moved - float(snapped)) <= max(1e-9, 2 * written_unit(moved)[1])


def test_puma_urdf_is_exact_and_prints_its_lengths():
    """The Puma URDF (1.570796325 and 3.14159265 throughout) gave FK terms such as
    1.79e-9*s235*sin(theta4 + 3.14159265358979); now the FK is exact, equals yourdfpy's to the snapped amount
    (reference), and the length sqrt(0.4318^2 + 0.0203^2) = sqrt(18686333)/10000 does not print as 0.43."""
    path = XACRO / "unimation_puma560_description/urdf/puma560_robot.urdf"
    robot = DHRobot.from_urdf(path)
    T = robot.fk()
    assert not T.atoms(sp.Float)
    qs = np.random.default_rng(3).uniform(-1.5, 1.5, size=(8, robot.n))
    assert np.abs(robot.fk_numeric(qs) - _library_fk(path, "link7", qs)).max() < 1e-7    # 3.6e-9 rad x ~2 m
    notes = "\n".join(robot.input_notes)
    assert "1.570796325 -> pi/2" in notes and "3.14159265 -> pi" in notes and "exact=False" in notes
    text = robot.to_str(robot.position[0])
    assert "0.43*" not in text and "sqrt(18686333)" in text


# ------------------------------------------------------------------------------ bad input
GOOD_JOINT = """<joint name="j{i}" type="{kind}"><parent link="l{p}"/><child link="l{i}"/>
  <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>{extra}</joint>"""


def _urdf(tmp_path, joints, links=3, name="bad.urdf"):
    body = "".join(f'<link name="l{i}"/>' for i in range(links)) + "".join(joints)
    path = tmp_path / name
    path.write_text(f'<?xml version="1.0"?><robot name="t">{body}</robot>')
    return path


LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'


@pytest.mark.parametrize("case, message", [
    ("unparsable", "is not well-formed XML"),
    ("xacro", "is a xacro file that could not be expanded"),
    ("missing", "cannot read"),
    ("branching", "--tip: bad.urdf has leaves"),
    ("mimic", "mimic"),
    ("floating", "is floating"),
    ("no_limit", "has no <limit>"),
    ("not_connected", "is not connected below"),
])
def test_bad_urdf_one_line_exit_2(tmp_path, capsys, case, message):
    args = []
    if case == "unparsable":
        path = tmp_path / "broken.urdf"
        path.write_text('<robot name="t"><link name="l0"/><joint name="j1" type="revolute"></robot')
    elif case == "xacro":
        path = tmp_path / "arm.urdf.xacro"
        path.write_text('<robot xmlns:xacro="http://ros.org/wiki/xacro"><link name="${undefined}"/></robot>')
    elif case == "missing":
        path = tmp_path / "nowhere.urdf"
    elif case == "branching":   # l0 -> l1 and l0 -> l2, both revolute
        path = _urdf(tmp_path, [GOOD_JOINT.format(i=1, p=0, kind="revolute", extra=LIMIT),
                                GOOD_JOINT.format(i=2, p=0, kind="revolute", extra=LIMIT)])
    elif case == "mimic":
        path = _urdf(tmp_path, [GOOD_JOINT.format(i=1, p=0, kind="revolute", extra=LIMIT),
                                GOOD_JOINT.format(i=2, p=1, kind="revolute", extra=LIMIT + '<mimic joint="j1"/>')])
    elif case == "floating":
        path = _urdf(tmp_path, [GOOD_JOINT.format(i=1, p=0, kind="floating", extra=""),
                                GOOD_JOINT.format(i=2, p=1, kind="revolute", extra=LIMIT)])
    elif case == "no_limit":
        path = _urdf(tmp_path, [GOOD_JOINT.format(i=1, p=0, kind="revolute", extra=""),
                                GOOD_JOINT.format(i=2, p=1, kind="revolute", extra=LIMIT)])
    else:
        path = _urdf(tmp_path, [GOOD_JOINT.format(i=1, p=0, kind="revolute", extra=LIMIT),
                                GOOD_JOINT.format(i=2, p=0, kind="revolute", extra=LIMIT)])
        args = ["--base", "l1", "--tip", "l2"]
    assert main(["fk", "--urdf", str(path), *args]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err, err
    with pytest.raises(URDFError) as info:
        DHRobot.from_urdf(path, base_link="l1" if args else None, tip_link="l2" if args else None)
    # issue 26: the library names its parameters (path, base_link, tip_link); only the CLI speaks of --urdf, --tip
    assert "--" not in str(info.value) and info.value.parameter in ("path", "base_link", "tip_link")


# A document type with an internal entity (&L; would be 0.5), one naming a file (read by a parser that resolves it),
# and a parameter entity: each is refused wherever it sits, before yourdfpy's lxml sees the file.
DOCTYPES = ['<!DOCTYPE robot [<!ENTITY L "0.5">]>', '<!DOCTYPE robot [<!ENTITY L SYSTEM "/etc/hostname">]>',
            '<!DOCTYPE robot [<!ENTITY % p "x"> %p;]>', '<!DOCTYPE robot>']


@pytest.mark.parametrize("doctype", DOCTYPES)
@pytest.mark.parametrize("encoding", ["utf-8", "utf-16", "utf-32", "latin-1"])
def test_urdf_entities_are_refused_in_every_encoding(tmp_path, encoding, doctype):
    """Issue 37 item 3: yourdfpy parses with lxml, which expands the internal entities of a URDF (in any encoding);
    the file is now parsed with defusedxml first, and yourdfpy gets only the document it checked."""
    joint = GOOD_JOINT.format(i=1, p=0, kind="revolute", extra=LIMIT).replace('xyz="0 0 0.1"', 'xyz="0 0 &L;"')
    path = tmp_path / "arm.urdf"
    path.write_bytes(f'<?xml version="1.0" encoding="{encoding}"?>{doctype}<robot name="t"><link name="l0"/>'
                     f'<link name="l1"/>{joint}</robot>'.encode(encoding))
    with pytest.raises(URDFError, match=r"path: '.*arm.urdf' declares a document type or entities; URDF needs "
                                        r"neither"):
        DHRobot.from_urdf(path)


def test_a_urdf_in_utf16_or_utf32_is_read(tmp_path):
    """The same arm saved as UTF-8, UTF-16 and UTF-32 (with their byte order marks) is the same robot."""
    joint = GOOD_JOINT.format(i=1, p=0, kind="revolute", extra=LIMIT)
    text = f'<?xml version="1.0"?><robot name="t"><link name="l0"/><link name="l1"/>{joint}</robot>'
    robots = []
    for encoding in ("utf-8", "utf-16", "utf-32"):
        path = tmp_path / f"{encoding}.urdf"
        path.write_bytes(text.encode(encoding))
        robots.append(DHRobot.from_urdf(path))
    assert robots[0].fk()[2, 3] == sp.Rational(1, 10)       # the origin's z, 0.1, as the exact decimal
    assert all(r.joints == robots[0].joints and r.fk() == robots[0].fk() for r in robots)


def test_cli_urdf_and_float_dh(tmp_path, capsys):
    path, _ = URDFS["kr16"]
    assert main(["fk", "--urdf", str(path), "--json"]) == 0
    out, err = capsys.readouterr()
    data = json.loads(out)
    assert data["robot"] == "kuka_kr16_2"
    assert err.count("\n") == 1 and "1.57079632679 -> pi/2" in err
    dh = tmp_path / "puma.json"
    dh.write_text(json.dumps(_puma(True)))
    assert main(["fk", "--dh", str(dh), "--json"]) == 0
    out, err = capsys.readouterr()
    assert "joint 1 alpha: 1.5707963267948966 -> pi/2" in err and err.count("\n") == 1
    assert json.loads(out)["position"] == [sp.sstr(e) for e in DHRobot.from_dict(_puma(False)).position]
    assert main(["fk", "--dh", str(dh), "--tip", "x"]) == 2
    assert main(["fk", "puma560", "--urdf", str(path)]) == 2


SKEW = """<?xml version="1.0"?>
<robot name="skew">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/><link name="d"/><link name="tip"/>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="a"/>
    <origin xyz="0.1 -0.2 0.3" rpy="0.3 0 0.7853981633974483"/><axis xyz="0 0.6 0.8"/>
    <limit lower="-0.25" upper="0.5" effort="1" velocity="1"/></joint>
  <joint name="spin" type="continuous"><parent link="a"/><child link="b"/>
    <origin xyz="0.05 0.4 0" rpy="0 0.2 0"/><axis xyz="1 1 0"/></joint>
  <joint name="bolt" type="fixed"><parent link="b"/><child link="c"/>
    <origin xyz="0 0 0.12" rpy="1.5707963267948966 0 0"/></joint>
  <joint name="swing" type="revolute"><parent link="c"/><child link="d"/>
    <origin xyz="0.3 0 0" rpy="0 0 0"/><axis xyz="0 0 -1"/>
    <limit lower="-1.5" upper="2" effort="1" velocity="1"/></joint>
  <joint name="flange" type="fixed"><parent link="d"/><child link="tip"/>
    <origin xyz="0.07 0.01 0" rpy="0 0.5 0"/></joint>
</robot>"""


@pytest.mark.parametrize("exact", [True, False])
def test_skew_prismatic_continuous_chain_equals_the_library(tmp_path, exact):
    """Skew axes, a tilted non-unit-looking axis, a prismatic and a continuous joint, fixed joints between:
    the DH table with base and tool reproduces yourdfpy's FK (floats kept unchopped with exact=False)."""
    path = tmp_path / "skew.urdf"
    path.write_text(SKEW)
    robot = DHRobot.from_urdf(path, exact=exact, tol=1e-9 if exact else 0.0)
    assert [j.kind for j in robot.joints] == ["P", "R", "R"] and robot.q == sp.symbols("d1 theta2 theta3")
    assert robot.joints[1].limits is None                                  # continuous
    assert robot.joints[0].limits == ((sp.Rational(-1, 4), sp.Rational(1, 2)) if exact else
                                      (sp.Float(-0.25), sp.Float(0.5)))
    qs = np.random.default_rng(11).uniform(-2.0, 2.0, size=(15, 3))
    reference = _library_fk(path, "tip", qs)
    assert np.abs(robot.fk_numeric(qs) - reference).max() < 1e-12


def test_keep_floats_recognises_an_identity_base():
    """With floats kept, the IRB140's frame 0 is still the base link's frame (Float(1.0) is not Integer(1),
    yet the matrix is the identity): no base transform, and the note says so, as in exact mode."""
    path, _ = URDFS["irb140"]
    robot = DHRobot.from_urdf(path, exact=False)
    assert robot.base is None and "frame 0 is the base link's frame" in robot.input_notes[0]


def test_an_origin_angle_snapped_from_its_written_digits_gives_the_exact_rotation(tmp_path):
    """An origin rpy of 1.5707963 (pi/2 written to 8 digits, 2.7e-8 short) is snapped to pi/2, as the note says, so
    the rotation is the exact quarter turn (reference: Rz(pi/2)); it was the matrix of the float, with entries
    2.68e-8 (the 'Euler angles recovered badly' check compared the snapped rotation with the float one at tol
    alone)."""
    path = _urdf(tmp_path, [GOOD_JOINT.format(i=1, p=0, kind="revolute", extra=LIMIT),
                            GOOD_JOINT.format(i=2, p=1, kind="fixed", extra="").replace(
                                'rpy="0 0 0"', 'rpy="0 0 1.5707963"')])
    robot = DHRobot.from_urdf(path)
    assert any("1.5707963 -> pi/2" in note for note in robot.input_notes)
    assert robot.tool[:3, :3] == sp.Matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    q = sp.Symbol("theta1")
    assert sp.simplify(robot.fk()[:3, :3] - sp.Matrix([[-sp.sin(q), -sp.cos(q), 0], [sp.cos(q), -sp.sin(q), 0],
                                                       [0, 0, 1]])) == sp.zeros(3, 3)
    kept = DHRobot.from_urdf(path, exact=False)          # the float, on request
    assert abs(float(kept.tool[0, 0]) - math.cos(1.5707963)) < 1e-15
