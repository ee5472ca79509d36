"""Robot files are data (issue 37): hostile text in every attribute of a URDF, an MJCF and a DH file.

Each injection string of the expression reader (tests/helpers/hostile.py) and each piece of xacro syntax (an
expression that starts a process, substitutions), placed in any one attribute or field of a small valid file saved
as UTF-8, UTF-16 or UTF-32, is refused with a :class:`WorkspaceError` or read as inert text: a name comes back as
written, no process is started (an audit hook watches ``subprocess.Popen``, ``os.system``, ``os.exec*``,
``os.posix_spawn``, ``os.spawn*``, ``os.fork``) and no file appears.  And every XML reader (URDF, xacro input,
MJCF) refuses a document type declaration, whatever entities it declares, in every encoding the parser reads.

References: the injection strings of tests/helpers/hostile.py; xacro's syntax (``${...}`` expressions,
``$(...)`` substitutions); the XML 1.0 grammar of document type and entity declarations (sections 2.8 and 4.2).
"""

from __future__ import annotations

import contextlib
import importlib.util
import json
import math
import os
import sys
from xml.sax.saxutils import quoteattr

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from hostile import INJECTIONS, MARKER, RUNS
from workspace_sym import DHRobot
from workspace_sym.errors import MJCFError, URDFError, WorkspaceError

# yourdfpy is part of the test extra; looked up, not imported (both workers collect this file; one runs it)
pytestmark = pytest.mark.skipif(importlib.util.find_spec("yourdfpy") is None, reason="yourdfpy is not installed")

XACRO_SYNTAX = [RUNS, f"$(eval __import__('os').system('touch {MARKER}'))", "$(env HOME)", "$(find mypkg)/x",
                "${1 + 1}", "${python.vars(python.type)}", '"/><xacro:include filename="/etc/hostname"/><a b="',
                "&amp; &lt; ]]> <!-- -->"]
HOSTILE = INJECTIONS + XACRO_SYNTAX
ENCODINGS = ["utf-8", "utf-16", "utf-32"]      # Python's utf-16 and utf-32 codecs write a byte order mark

# ---------------------------------------------------------------------------- nothing runs
_SPAWNING = ("subprocess.Popen", "os.system", "os.exec", "os.posix_spawn", "os.spawn", "os.fork", "os.forkpty")
_seen: list[str] = []
_watch = {"on": False}


def _audit(event, args):
    if _watch["on"] and event in _SPAWNING:
        _seen.append(event)


sys.addaudithook(_audit)       # for the life of the process (hooks cannot be removed); idle unless watching


@contextlib.contextmanager
def nothing_runs(folder):
    """Run the block in ``folder`` (where the payloads' relative paths land); fail if it started a process or made
    a file there."""
    before, cwd = sorted(os.listdir(folder)), os.getcwd()
    _seen.clear()
    os.chdir(folder)
    _watch["on"] = True
    try:
        yield
    finally:
        _watch["on"] = False
        os.chdir(cwd)
    assert not _seen, f"a process was started ({_seen[0]})"
    assert sorted(os.listdir(folder)) == before, "a file was created"


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("hostile")


# ---------------------------------------------------------------------------- the three files
URDF = ('<?xml version="1.0" encoding="{encoding}"?>'
        '<robot name={robot_name}><link name={base_name}/><link name={upper_name}/><link name="tip"/>'
        '<joint name={joint_name} type={joint_type}><parent link={parent_link}/><child link={child_link}/>'
        '<origin xyz={origin_xyz} rpy={origin_rpy}/><axis xyz={axis_xyz}/>'
        '<limit lower={limit_lower} upper={limit_upper} effort={limit_effort} velocity={limit_velocity}/></joint>'
        '<joint name="j2" type="revolute"><parent link="upper"/><child link="tip"/><origin xyz="0.4 0 0"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
URDF_FIELDS = {"robot_name": "arm", "base_name": "base", "upper_name": "upper", "joint_name": "j1",
               "joint_type": "revolute", "parent_link": "base", "child_link": "upper", "origin_xyz": "0 0 0.1",
               "origin_rpy": "0 0 0", "axis_xyz": "0 0 1", "limit_lower": "-1", "limit_upper": "1",
               "limit_effort": "1", "limit_velocity": "1"}
MJCF = ('<?xml version="1.0" encoding="{encoding}"?>'
        '<mujoco model={model}><compiler angle={compiler_angle} eulerseq={compiler_eulerseq}/>'
        '<default><joint damping={default_damping}/></default>'
        '<worldbody><body name={body_name} pos={body_pos} euler={body_euler} childclass={body_childclass}>'
        '<joint name={joint_name} type={joint_type} axis={joint_axis} pos={joint_pos} range={joint_range} '
        'limited={joint_limited} ref={joint_ref}/><geom size={geom_size}/>'
        '<body name={tip_name} pos={tip_pos}><geom size="0.02"/></body></body></worldbody></mujoco>')
MJCF_FIELDS = {"model": "arm", "compiler_angle": "degree", "compiler_eulerseq": "xyz", "default_damping": "1",
               "body_name": "upper", "body_pos": "0 0 0.1", "body_euler": "0 0 0", "body_childclass": "main",
               "joint_name": "j1", "joint_type": "hinge", "joint_axis": "0 0 1", "joint_pos": "0 0 0",
               "joint_range": "-90 90", "joint_limited": "true", "joint_ref": "0", "geom_size": "0.02",
               "tip_name": "tip", "tip_pos": "0.4 0 0"}
DH_FIELDS = {"name": "arm", "units": "m", "convention": "standard", "angles": "degrees", "joint_type": "R",
             "joint_variable": "theta1", "theta": "0", "d": "1/10", "a": "a1", "alpha": "0", "limit_lower": "-90",
             "limit_upper": "90", "parameter_name": "a1", "parameter_value": "2/5", "base_x": "0", "base_roll": "0",
             "tool_z": "0"}
NAMES = {("urdf", "robot_name"), ("mjcf", "model"), ("dh", "name")}       # read back as the robot's name


def _dh_text(f: dict) -> str:
    return json.dumps({"name": f["name"], "units": f["units"], "convention": f["convention"], "angles": f["angles"],
                       "joints": [{"type": f["joint_type"], "variable": f["joint_variable"], "theta": f["theta"],
                                   "d": f["d"], "a": f["a"], "alpha": f["alpha"],
                                   "limits": [f["limit_lower"], f["limit_upper"]]},
                                  {"d": 0, "a": "3/10", "alpha": 0}],
                       "parameters": {f["parameter_name"]: f["parameter_value"]},
                       "base": {"xyz": [f["base_x"], 0, 0], "rpy": [f["base_roll"], 0, 0]},
                       "tool": {"xyz": [0, 0, f["tool_z"]]}})


def _write(folder, kind: str, fields: dict, encoding: str):
    """The file of ``kind`` with ``fields``, saved in ``encoding``; returns the reader to call on it."""
    if kind == "dh":
        path = folder / "arm.json"
        path.write_bytes(_dh_text(fields).encode(encoding))
        return lambda: DHRobot.from_file(path)
    template, suffix, read = ((URDF, "urdf", DHRobot.from_urdf) if kind == "urdf" else
                              (MJCF, "xml", DHRobot.from_mjcf))
    path = folder / f"arm.{suffix}"
    quoted = {k: quoteattr(v) for k, v in fields.items()}
    path.write_bytes(template.format(encoding=encoding, **quoted).encode(encoding))
    return lambda: read(path)


FIELDS = {"urdf": URDF_FIELDS, "mjcf": MJCF_FIELDS, "dh": DH_FIELDS}
CASES = [(kind, name) for kind, fields in FIELDS.items() for name in fields]


@pytest.mark.parametrize("kind", ["urdf", "mjcf", "dh"])
@pytest.mark.parametrize("encoding", ENCODINGS)
def test_the_clean_files_read_in_every_encoding(folder, kind, encoding):
    """Without a hostile field each file is the arm written in it (so a refusal below is the hostile field's doing):
    the tip at q = (0.3, -0.7) by hand, from the lengths of the file (0.1 up, 0.4 out, and 0.3 more in the DH
    table).  A DH file is JSON, which must be UTF-8 (RFC 8259, section 8.1): UTF-16 and UTF-32 are refused, naming
    the encoding expected."""
    read = _write(folder, kind, FIELDS[kind], encoding)
    if kind == "dh" and encoding != "utf-8":
        with pytest.raises(WorkspaceError, match="is not UTF-8 text"):
            read()
        return
    robot = read()
    q1, q2 = 0.3, -0.7
    tip = [0.4 * math.cos(q1), 0.4 * math.sin(q1), 0.1]
    if kind == "dh":
        tip = [tip[0] + 0.3 * math.cos(q1 + q2), tip[1] + 0.3 * math.sin(q1 + q2), 0.1]
    assert robot.name == "arm"
    assert np.abs(robot.fk_numeric(np.array([q1, q2][:robot.n]))[:3, 3] - tip).max() < 1e-12


@pytest.mark.parametrize(("kind", "field"), CASES, ids=[f"{k}-{f}" for k, f in CASES])
@settings(derandomize=True, max_examples=20, deadline=None)
@given(text=st.sampled_from(HOSTILE), encoding=st.sampled_from(ENCODINGS))
@example(text=RUNS, encoding="utf-8")
@example(text=RUNS, encoding="utf-16")
@example(text=XACRO_SYNTAX[1], encoding="utf-32")
@example(text=INJECTIONS[0], encoding="utf-8")
def test_hostile_text_in_any_field_is_refused_or_inert(folder, kind, field, text, encoding):
    read = _write(folder, kind, {**FIELDS[kind], field: text}, encoding)
    with nothing_runs(folder):
        try:
            robot = read()
        except WorkspaceError as exc:
            assert "\n" not in str(exc)
            return
    if (kind, field) in NAMES:
        assert robot.name == text, "a name is read as written"


# ---------------------------------------------------------------------------- document types, every reader
ENTITY_NAMES = st.sampled_from(["L", "lol", "x1"])
DECLARATIONS = st.one_of(
    st.builds('<!ENTITY {} "{}">'.format, ENTITY_NAMES, st.sampled_from(["0.5", "&#60;x/&#62;", ""])),
    st.builds('<!ENTITY {} SYSTEM "{}">'.format, ENTITY_NAMES,
              st.sampled_from(["/etc/hostname", "file:///etc/passwd", "http://127.0.0.1:9/x"])),
    st.builds('<!ENTITY % {0} "<!ENTITY q \'1\'>"> %{0};'.format, ENTITY_NAMES),        # a parameter entity
    st.just('<!ENTITY a "aaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;">'),           # the billion laughs' step
    st.just('<!ELEMENT robot ANY><!ATTLIST robot name CDATA "arm">'),
)
EXTERNAL = st.sampled_from(["", ' SYSTEM "/etc/hostname"', ' PUBLIC "-//x//DTD y//EN" "http://127.0.0.1:9/y.dtd"'])
BEFORE = st.sampled_from(["", "<!-- a comment -->", "<?pi data?>", "\n  "])
XML_ENCODINGS = ["utf-8", "utf-16", "utf-16-le", "utf-16-be", "utf-32", "utf-32-le", "utf-32-be", "latin-1"]
XACRO = ('<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:property name="l" value="0.4"/>'
         '<link name="base"/><link name="upper"/><joint name="j1" type="revolute"><parent link="base"/>'
         '<child link="upper"/><origin xyz="${l} 0 0"/><axis xyz="0 0 1"/>'
         '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')


def _model(reader: str) -> str:
    """The clean model of ``reader``, without its XML declaration."""
    if reader == "xacro":
        return XACRO
    template, fields = (URDF, URDF_FIELDS) if reader == "urdf" else (MJCF, MJCF_FIELDS)
    return template.split("?>", 1)[1].format(**{k: quoteattr(v) for k, v in fields.items()})


READERS = {   # reader: file name, reading function, its error, the kind of file named in the message, joints
    "urdf": ("arm.urdf", DHRobot.from_urdf, URDFError, "URDF", 2),
    "xacro": ("arm.urdf.xacro", DHRobot.from_urdf, URDFError, "xacro", 1),
    "mjcf": ("arm.xml", DHRobot.from_mjcf, MJCFError, "MJCF", 1),
}


@pytest.mark.parametrize("reader", sorted(READERS))
@settings(derandomize=True, max_examples=40, deadline=None)
@given(declarations=st.lists(DECLARATIONS, max_size=3), external=EXTERNAL, before=BEFORE,
       encoding=st.sampled_from(XML_ENCODINGS))
@example(declarations=['<!ENTITY L "0.5">'], external="", before="", encoding="utf-16")
@example(declarations=['<!ENTITY L "0.5">'], external="", before="", encoding="utf-32-be")
def test_a_document_type_is_refused_by_every_xml_reader(folder, reader, declarations, external, before, encoding):
    name, read, error, kind, joints = READERS[reader]
    subset = f" [{''.join(declarations)}]" if declarations else ""
    root = "mujoco" if reader == "mjcf" else "robot"
    text = f'<?xml version="1.0" encoding="{encoding}"?>{before}<!DOCTYPE {root}{external}{subset}>{_model(reader)}'
    bom = "\ufeff" if encoding[-3:] in ("-le", "-be") else ""      # the plain utf-16 and utf-32 codecs write one
    path = folder / name
    path.write_bytes((bom + text).encode(encoding))
    with nothing_runs(folder), pytest.raises(error, match=f"declares a document type or entities; {kind} needs "
                                                          "neither"):
        read(path)
    path.write_bytes((bom + f'<?xml version="1.0" encoding="{encoding}"?>{before}{_model(reader)}').encode(encoding))
    if reader != "xacro" or encoding in ("utf-8", "latin-1", "utf-16"):   # xacro reads what expat reads unaided
        assert read(path).n == joints, "the same file without its document type reads"


def test_the_watch_sees_a_process(folder):
    """The audit hook is live: expanding a .xacro file that starts a process (what a user who names a file .xacro
    accepts) is caught by :func:`nothing_runs`, so its silence above means something."""
    path = folder / "live.urdf.xacro"
    path.write_text(URDF.split("?>", 1)[1].format(**{k: quoteattr(v) for k, v in
                                                      {**URDF_FIELDS, "robot_name": RUNS}.items()}))
    with pytest.raises(AssertionError, match=r"a process was started \(subprocess.Popen\)"), nothing_runs(folder):
        DHRobot.from_urdf(path)
    (folder / "SENTINEL").unlink()
    path.unlink()
