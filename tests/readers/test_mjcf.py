"""MuJoCo models (MJCF) read as DH robots (workspace_sym.readers.mjcf).

Reference: MuJoCo's own forward kinematics (``mujoco.mj_kinematics``, an independent implementation of the
same file): the tip body's ``xpos``/``xmat`` relative to the base body equal ``robot.fk_numeric`` to 1e-12 at
configurations drawn by hypothesis, on small models written here and on the model that the mujoco package
ships as test data (``mujoco/testdata/model.xml``: default classes, two hinges in one body, Euler angles in
degrees, a slide joint).  Exact SymPy identities for a planar arm.
"""

from __future__ import annotations

import inspect
import json
from pathlib import Path

import mujoco
import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from workspace_sym import DHRobot
from workspace_sym.cli import main
from workspace_sym.errors import MJCFError
from workspace_sym.readers.mjcf import read_mjcf

GEOM = '<geom size="0.02"/>'      # MuJoCo refuses moving bodies without mass; the reader ignores geoms
MODELS = {
    # radian angles, every orientation attribute, hinge anchors off the body origin, ref on hinge and slide
    # (one or two joints per model: the textbook form of long chains of float angles takes minutes)
    "euler": f"""<mujoco model="euler"><compiler angle="radian"/><worldbody>
      <body name="b1" pos="0.1 0.2 0.3" euler="0.3 -0.2 0.5">{GEOM}
        <joint type="hinge" axis="0 1 1" pos="0.05 0 0" range="-1 1" ref="0.3"/>
        <body name="tip" pos="0.3 0 0.1" axisangle="1 1 0 0.7">{GEOM}</body></body></worldbody></mujoco>""",
    "quat": f"""<mujoco model="quat"><worldbody>
      <body name="b2" pos="0.4 0 0" quat="0.9 0.1 -0.3 0.2">{GEOM}
        <joint type="slide" axis="1 0 0" ref="0.1"/><joint axis="0 0 1" pos="0 0.1 0" ref="30"/>
        <body name="tip" pos="0.2 0 0.1">{GEOM}</body></body></worldbody></mujoco>""",
    "axes": f"""<mujoco model="axes"><worldbody>
      <body name="b3" pos="0 0.2 0" xyaxes="0 1 0 -1 0.2 0">{GEOM}<joint axis="1 0 0"/>
        <body name="b4" pos="0.1 0 0" zaxis="0.3 -0.4 0.8">{GEOM}<joint axis="0 1 0" pos="0 0 0.05"/>
        </body></body></worldbody></mujoco>""",
    # degrees (MuJoCo's default), extrinsic Euler sequence, default classes with childclass and inheritance
    "defaults": f"""<mujoco model="defaults"><compiler eulerseq="ZYX"/>
      <default><joint axis="0 1 0" range="-90 90"/>
        <default class="arm"><joint axis="1 0 0"/><default class="wrist"><joint range="-45 30"/></default></default>
      </default>
      <worldbody><body name="base" pos="0 0 0.5" euler="90 0 -90">{GEOM}<joint axis="0 0 1" limited="false"/>
        <body name="upper" childclass="arm" pos="0 0.1 0.2">{GEOM}<joint/>
          <body name="fore" pos="0 0 0.35" euler="0 90 0">{GEOM}<joint class="wrist"/>
            <body name="hand" pos="0.05 0 0.25">{GEOM}<joint class="main" type="slide" range="0 0.1"/>
            </body></body></body></body></worldbody></mujoco>""",
}
REAL = Path(mujoco.__file__).parent / "testdata" / "model.xml"
# Names given to three of the model's unnamed bodies, so that a chain can end there (names change no kinematics).
REAL_NAMES = {'<body euler="0 0 120" pos="-.15 .2 -.2">': '<body name="leg1" euler="0 0 120" pos="-.15 .2 -.2">',
              '<body pos=".45 0 -.3">\n          <joint name="wheel_1"':
              '<body name="wheel1" pos=".45 0 -.3">\n          <joint name="wheel_1"',
              '<body pos="-.33 0 1">': '<body name="slider" pos="-.33 0 1">'}
CHAINS = {   # name: (model text key, base body, tip body)
    "euler": ("euler", "world", "tip"),
    "quat": ("quat", "world", "tip"),
    "axes": ("axes", "world", "b4"),
    "defaults": ("defaults", "world", "hand"),
    "real-leg": ("real", "head", "wheel1"),
    "real-slider": ("real", "world", "slider"),
}


def _real_text() -> str:
    text = REAL.read_text()
    for old, new in REAL_NAMES.items():
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    return text


@pytest.fixture(scope="module")
def chains(tmp_path_factory):
    """``chains[name] = (robot, mujoco model, qpos addresses of the robot's joints, base id, tip id)``."""
    directory = tmp_path_factory.mktemp("mjcf")
    texts = {**MODELS, "real": _real_text()}
    out = {}
    for name, (key, base, tip) in CHAINS.items():
        path = directory / f"{key}.xml"
        path.write_text(texts[key])
        robot = DHRobot.from_mjcf(path, base_link=base, tip_link=tip)
        model = mujoco.MjModel.from_xml_string(texts[key])
        tip_id, base_id = model.body(tip).id, model.body(base).id
        chain, body = [], tip_id
        while body != base_id:          # the joints from base to tip, in order
            first, count = model.body_jntadr[body], model.body_jntnum[body]
            chain = [model.jnt_qposadr[j] for j in range(first, first + count)] + chain
            body = model.body_parentid[body]
        assert len(chain) == robot.n
        out[name] = (robot, model, chain, base_id, tip_id)
    return out


def _mujoco_pose(model, addresses, base_id, tip_id, q) -> np.ndarray:
    data = mujoco.MjData(model)
    data.qpos[addresses] = q
    mujoco.mj_kinematics(model, data)

    def pose(b):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = data.xmat[b].reshape(3, 3), data.xpos[b]
        return T

    return np.linalg.inv(pose(base_id)) @ pose(tip_id)


@pytest.mark.parametrize("name", sorted(CHAINS))
@settings(derandomize=True, max_examples=30, deadline=None)
@given(q=st.lists(st.floats(-3.5, 3.5, allow_nan=False), min_size=5, max_size=5).map(np.array))
@example(q=np.zeros(5))
@example(q=np.full(5, np.pi))
def test_fk_matches_mujoco(chains, name, q):
    robot, model, addresses, base_id, tip_id = chains[name]
    q = q[:robot.n]
    np.testing.assert_allclose(robot.fk_numeric(q), _mujoco_pose(model, addresses, base_id, tip_id, q),
                               rtol=0, atol=1e-12)


def test_limits_follow_compiler_units_classes_and_limited(chains):
    """Degrees made exact radians; limited="false" drops the range; a class's range is inherited; slide in m."""
    robot = chains["defaults"][0]
    assert [j.limits for j in robot.joints] == [None, (-sp.pi / 2, sp.pi / 2), (-sp.pi / 4, sp.pi / 6),
                                                (0, sp.Rational(1, 10))]
    assert [j.kind for j in robot.joints] == ["R", "R", "R", "P"]
    leg = chains["real-leg"][0]
    assert leg.joints[0].limits == (-sp.pi / 3, sp.pi / 3)          # class hip1: range="-60 60" degrees
    assert leg.joints[1].limits is None and leg.joints[2].limits is None
    assert "theta1 = hipz_1, theta2 = hipy_1, theta3 = wheel_1" in leg.input_notes[1]
    slider = chains["real-slider"][0]
    assert slider.joints[0].limits == (-sp.Rational(1, 5), sp.Rational(1, 2))


def test_unlimited_slide_has_no_limits(tmp_path):
    path = tmp_path / "slide.xml"
    path.write_text(f'<mujoco><worldbody><body name="s">{GEOM}<joint type="slide" axis="0 0 1"/></body>'
                    '</worldbody></mujoco>')
    robot = DHRobot.from_mjcf(path)
    assert robot.joints[0].kind == "P" and robot.joints[0].limits is None


def test_planar_arm_is_exactly_the_dh_arm(tmp_path):
    """Exact identity: the MJCF 2R arm has the DH table a = 2/5, 3/10 (lengths snapped to the decimals written)."""
    path = tmp_path / "arm.xml"
    path.write_text('<mujoco model="arm"><worldbody><body name="upper"><joint axis="0 0 1"/>'
                    '<body name="fore" pos="0.4 0 0"><joint axis="0 0 1"/><body name="tip" pos="0.3 0 0"/>'
                    '</body></body></worldbody></mujoco>')
    robot = DHRobot.from_mjcf(path)
    t1, t2 = robot.q
    expected = sp.Matrix([sp.Rational(2, 5) * sp.cos(t1) + sp.Rational(3, 10) * sp.cos(t1 + t2),
                          sp.Rational(2, 5) * sp.sin(t1) + sp.Rational(3, 10) * sp.sin(t1 + t2), 0])
    assert sp.simplify(robot.position - expected) == sp.zeros(3, 1)
    assert robot.name == "arm"


# (model, the API parameter blamed, the message after "parameter: ")
BAD = [
    ('<mujoco><worldbody><body name="b" pos="0.1 abc 0"><joint/></body></worldbody></mujoco>',
     "path", r"<body name='b'> pos: expected 3 numbers; got '0.1 abc 0'"),
    ('<mujoco><worldbody><body name="b" pos="0 nan 0"><joint/></body></worldbody></mujoco>',
     "path", r"<body name='b'> pos: expected 3 numbers; got '0 nan 0'"),
    ('<mujoco><worldbody><body name="b" pos="1e999 0 0"><joint/></body></worldbody></mujoco>',
     "path", r"<body name='b'> pos: numbers must be finite"),
    ('<mujoco><worldbody><body name="b" quat="1 0 0"><joint/></body></worldbody></mujoco>',
     "path", r"<body name='b'> quat: expected 4 numbers"),
    ('<mujoco><worldbody><body name="b" quat="1 0 0 0" euler="0 0 1"><joint/></body></worldbody></mujoco>',
     "path", r"<body name='b'> gives the orientation twice \(quat and euler\)"),
    ('<mujoco><worldbody><body name="b"><joint name="j" type="ball"/></body></worldbody></mujoco>',
     "path", r"joint 'j' is ball; a serial chain takes hinge and slide joints only"),
    ('<mujoco><worldbody><body name="b"><freejoint/></body></worldbody></mujoco>',
     "path", r"joint 'joint 1 of body b' is free"),
    ('<mujoco><worldbody><body name="b"><joint name="j" axis="0 0 0"/></body></worldbody></mujoco>',
     "path", r"<joint name='j'> axis: a zero vector"),
    ('<mujoco><worldbody><body name="b"><joint name="j" limited="true"/></body></worldbody></mujoco>',
     "path", r"<joint name='j'> is limited but has no range"),
    ('<mujoco><worldbody><body name="b"><joint name="j" limited="yes" range="0 1"/></body></worldbody></mujoco>',
     "path", r"<joint name='j'> limited: expected true, false or auto; got 'yes'"),
    ('<mujoco><worldbody><body name="b"><joint name="j" class="nope"/></body></worldbody></mujoco>',
     "path", r"<joint name='j'> class: no default class 'nope'"),
    ('<mujoco><compiler angle="grad"/><worldbody/></mujoco>', "path", r"<compiler angle> must be 'degree' or 'radian'"),
    ('<mujoco><compiler coordinate="global"/><worldbody/></mujoco>',
     "path", r"<compiler coordinate='global'> is not supported"),
    ('<mujoco><compiler eulerseq="xyw"/><worldbody/></mujoco>', "path", r"<compiler eulerseq> must be three of"),
    ("<mujoco/>", "path", r"the model has no <worldbody>"),
    ('<mujoco><default><default><joint/></default></default><worldbody/></mujoco>',
     "path", r"a nested <default> needs a class attribute"),
    ('<mujoco><worldbody><frame/></worldbody></mujoco>', "path", r"<frame> elements are not supported"),
    ('<mujoco><worldbody><body name="b"><joint/></body><body name="b"/></worldbody></mujoco>',
     "path", r"two bodies are named 'b'"),
    ('<!DOCTYPE m [<!ENTITY a "aaaa">]><mujoco><worldbody/></mujoco>',
     "path", r".* declares a document type or entities"),
    ('<mujoco><worldbody><body', "path", r".* is not well-formed XML"),
    ('<model name="r"/>', "path", r"'.*bad.xml' is not an MJCF model \(root element <model>, expected <mujoco>\)"),
    ('<mujoco><include file="other.xml"/><worldbody/></mujoco>', "path", r"'.*bad.xml' uses <include>"),
    ('<mujoco><worldbody><body name="b"/></worldbody></mujoco>', "tip_link", r"the model has no body moved by a joint"),
]


@pytest.mark.parametrize("encoding", ["utf-8", "utf-16", "utf-16-be", "utf-32", "utf-32-le"])
def test_entities_are_refused_in_every_encoding(tmp_path, encoding):
    """Issue 37 item 3: the refusal looked for the bytes '<!DOCTYPE'; saved as UTF-16 the same model passed and
    &L; was expanded.  Now the parsed document is checked, whatever the encoding (BOM or none)."""
    bom = {"utf-16-be": "\ufeff", "utf-32-le": "\ufeff"}.get(encoding, "")      # the other codecs write their own
    text = (f'{bom}<?xml version="1.0" encoding="{encoding}"?><!DOCTYPE m [<!ENTITY L "0.5">]><mujoco model="arm">'
            '<worldbody><body name="b" pos="&L; 0 0"><joint/></body></worldbody></mujoco>')
    path = tmp_path / "m.xml"
    path.write_bytes(text.encode(encoding))
    with pytest.raises(MJCFError, match=r"path: '.*m.xml' declares a document type or entities; MJCF needs neither"):
        DHRobot.from_mjcf(path)


@pytest.mark.parametrize("text, parameter, message", BAD)
def test_bad_models_name_element_and_attribute(tmp_path, text, parameter, message):
    """Each message names the element and the attribute, after the API parameter it blames: issue 38 item 5, 19
    messages began with the command-line flag "--mjcf:" and blamed a parameter "mjcf" that read_mjcf does not
    have; only the command line turns a parameter into its flag (cli._FLAGS, and --mjcf for path)."""
    path = tmp_path / "bad.xml"
    path.write_text(text)
    with pytest.raises(MJCFError, match=f"^{parameter}: {message}") as info:
        DHRobot.from_mjcf(path)
    assert info.value.parameter == parameter
    assert parameter in inspect.signature(read_mjcf).parameters


def test_unknown_tip_body_is_named(tmp_path):
    path = tmp_path / "m.xml"
    path.write_text(MODELS["euler"])
    with pytest.raises(MJCFError, match=r"tip_link: no body 'hand' in the model; bodies: 'world', 'b1', 'tip'") \
            as info:
        DHRobot.from_mjcf(path, tip_link="hand")
    assert info.value.parameter == "tip_link"


def test_cli_fk_of_an_mjcf_chain(tmp_path, capsys):
    path = tmp_path / "model.xml"
    path.write_text(_real_text())
    assert main(["fk", "--mjcf", str(path), "--base", "head", "--tip", "wheel1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert len(data["position"]) == 3 and data["robot"] == "model"


def test_cli_bad_mjcf_is_one_line_exit_2(tmp_path, capsys):
    """The command line names the option that gave the file where the library names its parameter, path."""
    path = tmp_path / "bad.xml"
    path.write_text(BAD[0][0])
    assert main(["fk", "--mjcf", str(path)]) == 2
    err = capsys.readouterr().err
    assert err == "workspace-sym fk: error: --mjcf: <body name='b'> pos: expected 3 numbers; got '0.1 abc 0'\n"


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    return tmp_path_factory.mktemp("untrusted") / "model.xml"


TOKENS = ["1", "-2.5", ".5", "1e-3", "nan", "inf", "0x1", "1_0", "+", "1e", "--1", "0.5e+2"]


@settings(derandomize=True, max_examples=25, deadline=None)
@given(value=st.one_of(st.text(st.characters(blacklist_categories=("Cs", "Cc")), max_size=24),
                       st.lists(st.sampled_from(TOKENS), max_size=4).map(" ".join)))
@example(value="1e400 0 0")
@example(value="0 0 0")
def test_any_pos_attribute_is_read_or_refused_with_mjcf_error(scratch, value):
    """Untrusted attribute text: either three plain numbers (read as MuJoCo reads them) or MJCFError, nothing else."""
    from xml.sax.saxutils import quoteattr

    scratch.write_text(f'<mujoco><worldbody><body name="b" pos={quoteattr(value)}><joint axis="0 0 1"/></body>'
                       '</worldbody></mujoco>')
    try:
        robot = DHRobot.from_mjcf(scratch)
    except MJCFError as exc:
        assert "<body name='b'> pos" in str(exc)
        return
    tokens = value.split()
    assert len(tokens) == 3
    np.testing.assert_allclose(robot.fk_numeric(np.zeros(1))[:3, 3], [float(t) for t in tokens], atol=1e-12)


def test_each_reader_names_the_other_format(tmp_path, capsys):
    """Issue 39: --urdf given an MJCF model said "cannot read ... as URDF ('name')"; each reader now names the
    format it was given and the option that reads it, both ways."""
    model = tmp_path / "arm.xml"
    model.write_text(MODELS["euler"])
    urdf = tmp_path / "arm.urdf"
    urdf.write_text('<robot name="arm"><link name="base"/></robot>')
    assert main(["fk", "--urdf", str(model)]) == 2
    err = capsys.readouterr().err
    assert err == (f"workspace-sym fk: error: --urdf: {str(model)!r} is an MJCF model (root element <mujoco>), not "
                   "URDF; read it as MJCF (DHRobot.from_mjcf, --mjcf FILE)\n")
    assert main(["fk", "--mjcf", str(urdf)]) == 2
    err = capsys.readouterr().err
    assert err == (f"workspace-sym fk: error: --mjcf: {str(urdf)!r} is a URDF file (root element <robot>), not an "
                   "MJCF model; read it as URDF (DHRobot.from_urdf, --urdf FILE)\n")
    sdf = tmp_path / "arm.sdf"
    sdf.write_text('<sdf version="1.6"><model name="arm"/></sdf>')
    assert main(["fk", "--urdf", str(sdf)]) == 2
    assert "is not a URDF file (root element <sdf>, expected <robot>)" in capsys.readouterr().err


# A 4-joint arm as files write it (issue 39, Engineer item 3): quaternions of 30, 90 and 45 degree turns rounded to
# 7 significant digits, and a hinge off its body's origin with a reference angle (pos and ref).
ROUNDED = f"""<mujoco model="rounded"><worldbody>
  <body name="upper" pos="0 0 0.3" quat="0.9659258 0.258819 0 0">{GEOM}<joint name="j1" axis="0 0 1"/>
    <body name="fore" pos="0.4 0 0" quat="0.7071068 0 0.7071068 0">{GEOM}
      <joint name="j2" axis="0 0 1" pos="0.1 0 0" ref="10"/>
      <body name="wrist" pos="0.3 0 0" quat="0.9238795 0 0 0.3826834">{GEOM}<joint name="j3" axis="0 1 0"/>
        <body name="tip" pos="0.1 0 0">{GEOM}<joint name="j4" axis="1 0 0"/></body></body></body></body>
</worldbody></mujoco>"""


def _exact_quaternions(text: str) -> str:
    """``ROUNDED`` with each quaternion written to full double precision (the turns it rounds)."""
    c15, s15, h = (repr(float(v)) for v in (np.cos(np.pi / 12), np.sin(np.pi / 12), np.sqrt(0.5)))
    c22, s22 = (repr(float(v)) for v in (np.cos(np.pi / 8), np.sin(np.pi / 8)))
    for old, new in (("0.9659258 0.258819 0 0", f"{c15} {s15} 0 0"), ("0.7071068 0 0.7071068 0", f"{h} 0 {h} 0"),
                     ("0.9238795 0 0 0.3826834", f"{c22} 0 0 {s22}")):
        text = text.replace(old, new)
    return text


@pytest.fixture(scope="module")
def rounded(tmp_path_factory):
    path = tmp_path_factory.mktemp("rounded") / "arm.xml"
    path.write_text(ROUNDED)
    return path, DHRobot.from_mjcf(path)


def _pose_of(text: str, q) -> np.ndarray:
    model = mujoco.MjModel.from_xml_string(text)
    return _mujoco_pose(model, list(range(4)), 0, model.body("tip").id, q)


def test_rounded_quaternions_read_as_the_exact_turns(rounded):
    """No float is left in T (no 4e-17*s1, no 8e-35*c4); T is MuJoCo's pose of the exact turns (to 1e-12) and of
    the file as written within what its 7 digits allow; each quaternion read so has a note."""
    _, robot = rounded
    T = robot.fk()
    assert not T.has(sp.Float) and "e-" not in robot.to_str(T)
    for q in (np.zeros(4), np.array([0.3, -1.2, 2.0, 0.7]), np.array([-2.5, 0.4, -0.9, 3.0])):
        np.testing.assert_allclose(robot.fk_numeric(q), _pose_of(_exact_quaternions(ROUNDED), q), rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.fk_numeric(q), _pose_of(ROUNDED, q), rtol=0, atol=2e-6)
    notes = [n for n in robot.input_notes if " quat " in n]
    assert notes[0] == ("<body name='upper'> quat '0.9659258 0.258819 0 0' (its digits within 5e-07): read as a turn "
                        "of 30 deg about (1, 0, 0)") and len(notes) == 3


def test_hinge_with_pos_and_ref_gives_short_exact_numbers(tmp_path):
    """The turn by -ref and the shift by -pos stay two transforms: no 16-digit decimal (3472963553338607/10^18)
    beside cos(pi/18); every rational in T has a denominator of at most 1000, and T is MuJoCo's pose."""
    text = f"""<mujoco model="ref"><worldbody>
      <body name="upper" pos="0 0 0.3">{GEOM}<joint axis="0 0 1"/>
        <body name="fore" pos="0.4 0 0">{GEOM}<joint axis="0 0 1" pos="0.3 0 0" ref="10"/>
          <body name="tip" pos="0.3 0.1 0">{GEOM}</body></body></body></worldbody></mujoco>"""
    path = tmp_path / "ref.xml"
    path.write_text(text)
    robot = DHRobot.from_mjcf(path)
    rationals = {r for e in robot.fk() for r in e.atoms(sp.Rational)}
    assert max(r.q for r in rationals) <= 1000, sorted(rationals, key=lambda r: r.q)[-3:]
    model = mujoco.MjModel.from_xml_string(text)
    for q in (np.zeros(2), np.array([0.4, -1.3])):
        np.testing.assert_allclose(robot.fk_numeric(q), _mujoco_pose(model, [0, 1], 0, model.body("tip").id, q),
                                   rtol=0, atol=1e-12)


def test_exact_form_is_not_longer_than_the_floats(rounded):
    """Every printed entry of the exact T is no longer than the same entry read with --keep-floats."""
    path, robot = rounded
    floats = DHRobot.from_mjcf(path, exact=False)
    exact_lengths = [len(robot.to_str(e)) for e in robot.fk()]
    float_lengths = [len(floats.to_str(e)) for e in floats.fk()]
    assert all(a <= b for a, b in zip(exact_lengths, float_lengths)), (exact_lengths, float_lengths)


def test_a_quaternion_of_few_digits_is_read_as_written(tmp_path):
    """``0.9 0.1 -0.3 0.2`` (one decimal) is no rounded turn: no note, and T is MuJoCo's (the chains above)."""
    path = tmp_path / "q.xml"
    path.write_text(MODELS["quat"])
    assert not [n for n in DHRobot.from_mjcf(path).input_notes if " quat " in n]


def test_turns_off_the_grid_leave_no_float_dust(tmp_path):
    """Quaternions of 0.4 and 0.7 rad turns (on no grid) stay floats: the DH offsets that are pi/2 and pi to the
    last bit print as exact (``c1``, not ``cos(theta1 - 1.5707963267949)``), no float coefficient below tol is left
    (``1.7e-17`` where two float terms cancel), a note says so, and T is still MuJoCo's pose (to 1e-8)."""
    text = f"""<mujoco model="generic"><worldbody>
      <body name="upper" pos="0 0 0.3" quat="0.9393727 0.3428978 0 0">{GEOM}<joint axis="0 0 1"/>
        <body name="fore" pos="0.4 0 0" quat="0.9800666 0 0.1986693 0">{GEOM}<joint axis="0 0 1"/>
          <body name="tip" pos="0.3 0 0">{GEOM}<joint axis="1 0 0"/></body></body></body></worldbody></mujoco>"""
    path = tmp_path / "generic.xml"
    path.write_text(text)
    robot = DHRobot.from_mjcf(path)
    T = robot.fk()
    assert not [f for e in T for f in e.atoms(sp.Float) if abs(f) < 1e-9]
    assert "1.5707963" not in robot.to_str(T) and "3.1415926" not in robot.to_str(T)
    assert any(n.startswith("floats kept") for n in robot.input_notes)
    model = mujoco.MjModel.from_xml_string(text)
    for q in (np.zeros(3), np.array([0.4, -1.3, 2.2])):
        np.testing.assert_allclose(robot.fk_numeric(q), _mujoco_pose(model, [0, 1, 2], 0, model.body("tip").id, q),
                                   rtol=0, atol=1e-8)
