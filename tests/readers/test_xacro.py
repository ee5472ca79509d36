"""Xacro files read as URDF (issue 27, engineer): expanded with the ``xacro`` package (the ``xacro`` extra),
``$(find pkg)`` resolved in the tree the file lives in or through ``packages`` / ``--package pkg=DIR``.
Reference: rtb-data ships the KUKA KR16 both as xacro and as the URDF ROS's xacro expanded it to; the DH robot read
from either is the same exact model (table, base and tool compared as SymPy objects)."""

import json
import re
import sys
from pathlib import Path
from xml.sax.saxutils import quoteattr

import pytest
import rtbdata
import xacro  # noqa: F401  (the xacro extra is part of [test])

from hostile import RUNS
from workspace_sym import DHRobot
from workspace_sym.cli import main
from workspace_sym.errors import URDFError

XACRO = Path(rtbdata.__file__).parent / "xacro"
KR16 = XACRO / "kuka_description" / "kuka_kr16"
KR16_PACKAGE = {"kuka_kr16_support": str(KR16)}       # rtb-data renamed the folder of ROS's kuka_kr16_support

MACRO = """<robot xmlns:xacro="http://ros.org/wiki/xacro">
  <xacro:macro name="arm" params="prefix length">
    <link name="${prefix}base"/><link name="${prefix}upper"/><link name="${prefix}tip"/>
    <joint name="${prefix}j1" type="revolute"><parent link="${prefix}base"/><child link="${prefix}upper"/>
      <origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <joint name="${prefix}j2" type="revolute"><parent link="${prefix}upper"/><child link="${prefix}tip"/>
      <origin xyz="${length} 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  </xacro:macro>
</robot>
"""
ROBOT = """<robot name="two" xmlns:xacro="http://ros.org/wiki/xacro">
  <xacro:include filename="$(find {package})/urdf/macro.xacro"/>
  <xacro:arm prefix="" length="0.5"/>
</robot>
"""


def test_xacro_is_the_urdf_it_expands_to():
    robot = DHRobot.from_urdf(KR16 / "urdf" / "kr16_2.xacro", packages=KR16_PACKAGE)
    expanded = DHRobot.from_urdf(KR16 / "urdf" / "kr16_2.urdf")
    assert robot.joints == expanded.joints and robot.base == expanded.base and robot.tool == expanded.tool


def test_find_resolves_in_the_tree_or_through_package(tmp_path, capsys):
    """$(find mypkg) from inside mypkg/ (a folder of that name above the file) needs nothing; a package elsewhere
    needs --package, and without it the one line names the package and the option."""
    (tmp_path / "ws" / "mypkg" / "urdf").mkdir(parents=True)
    (tmp_path / "ws" / "mypkg" / "urdf" / "macro.xacro").write_text(MACRO)
    inside = tmp_path / "ws" / "mypkg" / "urdf" / "two.urdf.xacro"
    inside.write_text(ROBOT.format(package="mypkg"))
    robot = DHRobot.from_urdf(inside)
    assert robot.n == 2 and robot.to_str(robot.position[0]) == "c1/2"
    elsewhere = tmp_path / "other" / "two.urdf.xacro"
    elsewhere.parent.mkdir()
    elsewhere.write_text(ROBOT.format(package="arm_support"))
    assert main(["fk", "--urdf", str(elsewhere), "--json"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "$(find arm_support)" in err and "--package arm_support=DIR" in err
    assert err.startswith("workspace-sym fk: error: --package:")
    assert main(["fk", "--urdf", str(elsewhere), "--package", f"arm_support={tmp_path / 'ws' / 'mypkg'}",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["position"][0] == "cos(theta1)/2"
    out = tmp_path / "rep"
    assert main(["report", "--urdf", str(elsewhere), "--package", f"arm_support={tmp_path / 'ws' / 'mypkg'}",
                 "--out", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["joints"] == 2


@pytest.mark.parametrize(("argv", "needle"), [
    (["fk", "glass-handling", "--package", "a=b"], "--package names the directory of a package"),
    (["fk", "--urdf", "{kr16}", "--package", "nodir"], "--package: expected PKG=DIR"),
    (["fk", "--urdf", "{kr16}", "--package", "kuka_kr16_support={missing}"], "an existing directory"),
])
def test_package_option_bad_input(tmp_path, capsys, argv, needle):
    values = {"kr16": KR16 / "urdf" / "kr16_2.xacro", "missing": tmp_path / "none"}
    assert main([a.format(**values) for a in argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err


def test_a_xacro_that_cannot_expand_is_one_line(tmp_path, capsys):
    path = tmp_path / "bad.urdf.xacro"
    path.write_text('<robot name="b" xmlns:xacro="http://ros.org/wiki/xacro"><link name="${nowhere}"/></robot>')
    assert main(["fk", "--urdf", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is a xacro file that could not be expanded" in err and "nowhere" in err


def test_without_the_extra_a_xacro_file_is_refused_with_the_way_out(monkeypatch):
    monkeypatch.setitem(sys.modules, "xacro", None)          # as if the extra were not installed
    with pytest.raises(URDFError, match=r"install the xacro extra .*or expand it first \(xacro FILE > robot.urdf\)"):
        DHRobot.from_urdf(KR16 / "urdf" / "kr16_2.xacro", packages=KR16_PACKAGE)

ARM = ('<robot name={name}><link name="base"/><link name="upper"/>'
       '<joint name="j1" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>'
       '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')


def test_a_urdf_is_data_and_never_runs_what_it_holds(tmp_path, monkeypatch, capsys):
    """Issue 37 item 2: a .urdf whose robot name holds a xacro expression was expanded, and the expression ran.
    A .urdf is now read as URDF only: markup of xacro is refused with the way to expand it knowingly."""
    monkeypatch.chdir(tmp_path)
    sentinel = tmp_path / "SENTINEL"
    text = ARM.format(name=quoteattr(RUNS))
    (tmp_path / "arm.urdf").write_text(text)
    with pytest.raises(URDFError, match=r"path: '.*arm.urdf' looks like xacro, not URDF \(<robot name=") as info:
        DHRobot.from_urdf(tmp_path / "arm.urdf")
    assert "\n" not in str(info.value) and ".xacro" in str(info.value)
    assert main(["fk", "--urdf", str(tmp_path / "arm.urdf")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("workspace-sym fk: error: --urdf: ") and "looks like xacro" in err
    assert not sentinel.exists(), "a .urdf file ran a command"
    # the payload is live: the same text named as xacro is expanded, and expanding runs it (as xacro does; the
    # docs say so), which is why only a file the user names .xacro is expanded
    (tmp_path / "arm.urdf.xacro").write_text(text)
    assert DHRobot.from_urdf(tmp_path / "arm.urdf.xacro").n == 1
    assert sentinel.exists()


@pytest.mark.parametrize(("body", "shown"), [
    ('<xacro:property name="l" value="1"/>', "(<xacro:property>)"),
    ('<link name="$(arg prefix)base"/>', "(<link name='$(arg prefix)base'>)"),
    ('<link name="base"><visual>${1 + 1}</visual></link>', "(<visual> with the text '${1 + 1}')"),
])
def test_xacro_markup_in_a_urdf_is_named(tmp_path, body, shown):
    """Each kind of xacro markup (an element of its namespace, a substitution, an expression in a text) makes a
    .urdf refused, the markup shown; the xmlns:xacro declaration an expanded file keeps is not markup."""
    path = tmp_path / "arm.urdf"
    path.write_text(ARM.format(name='"arm" xmlns:xacro="http://www.ros.org/wiki/xacro"').replace("</robot>",
                                                                                                 body + "</robot>"))
    with pytest.raises(URDFError, match="looks like xacro, not URDF " + re.escape(shown)):
        DHRobot.from_urdf(path)
    path.write_text(ARM.format(name='"arm" xmlns:xacro="http://www.ros.org/wiki/xacro"'))
    assert DHRobot.from_urdf(path).n == 1


def test_packages_are_for_a_xacro_file_only(tmp_path):
    path = tmp_path / "arm.urdf"
    path.write_text(ARM.format(name='"arm"'))
    with pytest.raises(URDFError, match=r"packages: arm.urdf is read as URDF, not expanded as xacro") as info:
        DHRobot.from_urdf(path, packages={"mypkg": str(tmp_path)})
    assert info.value.parameter == "packages"


def test_an_answer_key_cannot_reach_xacro(tmp_path, monkeypatch, capsys):
    """Grading reads others' files: a key's robot is a catalog name or a DH table, never a file, so a key naming
    a live xacro file (by path, or as a DH table's name) is refused or inert, and the file is never expanded."""
    from workspace_sym.errors import UnknownNameError, WorkspaceError
    from workspace_sym.grading import AnswerKey

    monkeypatch.chdir(tmp_path)
    evil = tmp_path / "evil.urdf.xacro"
    evil.write_text(ARM.format(name=quoteattr(RUNS)))
    question = {"id": "1", "kind": "expression", "robot": "R", "answer": "c1"}
    key = {"format": "workspace-sym key", "questions": [question]}
    for robot in (str(evil), "evil.urdf.xacro"):
        with pytest.raises(UnknownNameError, match="is not in the catalog"):
            AnswerKey.from_dict({**key, "robots": {"R": robot}})
    with pytest.raises(WorkspaceError):          # a DH table whose fields name the file: text, not a path
        AnswerKey.from_dict({**key, "robots": {"R": {"name": str(evil), "joints": str(evil)}}})
    (tmp_path / "key.json").write_text(json.dumps({**key, "robots": {"R": str(evil)}}))
    (tmp_path / "answers.csv").write_text("student,question,answer\nann,1,c1\n")
    assert main(["grade", "key.json", "answers.csv", "--out", "graded"]) == 2
    assert "is not in the catalog" in capsys.readouterr().err
    assert not (tmp_path / "SENTINEL").exists()


@pytest.mark.parametrize("where", ["file", "include"])
@pytest.mark.parametrize("encoding", ["utf-8", "utf-16"])
def test_xacro_input_with_entities_is_refused(tmp_path, where, encoding):
    """Issue 37 item 3: xacro parses with minidom, which expands internal entities (&L; would be 0.5); every file
    xacro reads, the file and what it includes, is now checked with defusedxml first."""
    doctype = f'<?xml version="1.0" encoding="{encoding}"?><!DOCTYPE robot [<!ENTITY L "0.5">]>'
    folder = tmp_path / "mypkg" / "urdf"
    folder.mkdir(parents=True)
    macro, robot = MACRO, ROBOT.format(package="mypkg")
    if where == "include":
        macro = doctype + macro.replace("${length} 0 0", "&L; 0 0")
    else:
        robot = doctype + robot.replace('length="0.5"', 'length="&L;"')
    (folder / "macro.xacro").write_bytes(macro.encode(encoding))
    (folder / "two.urdf.xacro").write_bytes(robot.encode(encoding))
    refused = folder / ("two.urdf.xacro" if where == "file" else "macro.xacro")
    with pytest.raises(URDFError, match=re.escape(f"path: '{refused}' declares a document type or entities; xacro "
                                                  "needs neither")):
        DHRobot.from_urdf(folder / "two.urdf.xacro")


PX100 = XACRO / "trossen_descriptions" / "urdf" / "px100.urdf.xacro"


def test_xacro_args_give_px100_its_link_names(tmp_path, capsys):
    """Issue 39: px100.urdf.xacro names its links $(arg robot_name)/...; xacro_args / --xacro-arg pass
    robot_name:=px100.  Reference: yourdfpy's forward kinematics of the URDF xacro itself expands with that argument
    (an independent reading of the same file), tip to base, at random configurations."""
    import numpy as np
    import xacro as ros_xacro
    import yourdfpy

    robot = DHRobot.from_urdf(PX100, xacro_args={"robot_name": "px100"}, tip_link="px100/ee_gripper_link")
    assert robot.name == "px100" and robot.n == 4 and "from 'px100/base_link'" in robot.input_notes[0]
    expanded = tmp_path / "px100.urdf"
    expanded.write_text(ros_xacro.process_file(str(PX100), mappings={"robot_name": "px100"}).toxml())
    model = yourdfpy.URDF.load(str(expanded), build_scene_graph=True, load_meshes=False)
    names = [j.name for j in model.robot.joints if j.type in ("revolute", "continuous", "prismatic")]
    for q in np.random.default_rng(3).uniform(-1.5, 1.5, size=(6, robot.n)):
        model.update_cfg(dict(zip(["waist", "shoulder", "elbow", "wrist_angle"], q)) | {
            n: 0.0 for n in names if n not in ("waist", "shoulder", "elbow", "wrist_angle")})
        reference = model.get_transform("px100/ee_gripper_link", "px100/base_link")
        assert np.abs(robot.fk_numeric(q) - reference).max() < 1e-12
    assert main(["fk", "--urdf", str(PX100), "--xacro-arg", "robot_name=px100", "--tip", "px100/ee_gripper_link",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["robot"] == "px100"


@pytest.mark.parametrize(("argv", "needle"), [
    (["--xacro-arg", "robot_nme=px100"], "--xacro-arg: px100.urdf.xacro has no argument 'robot_nme'; its arguments: "
                                         "'external_urdf_loc', 'load_gazebo_configs', 'robot_name',"),
    (["--xacro-arg", "robot_name"], "--xacro-arg: expected NAME=VALUE"),
    (["--xacro-arg", "=px100"], "--xacro-arg: expected NAME=VALUE"),
])
def test_xacro_arg_bad_input_is_one_line(capsys, argv, needle):
    assert main(["fk", "--urdf", str(PX100), "--tip", "px100/ee_gripper_link", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err


def test_xacro_args_are_for_a_xacro_file_and_hold_text(tmp_path, capsys):
    path = tmp_path / "arm.urdf"
    path.write_text(ARM.format(name='"arm"'))
    with pytest.raises(URDFError, match=r"xacro_args: arm.urdf is read as URDF, not expanded as xacro"):
        DHRobot.from_urdf(path, xacro_args={"robot_name": "px100"})
    with pytest.raises(URDFError, match=r"xacro_args: expected an argument name and its value \(text or a number"):
        DHRobot.from_urdf(PX100, xacro_args={"robot_name": ["px100"]})
    assert main(["fk", "glass-handling", "--xacro-arg", "robot_name=px100"]) == 2
    assert "--xacro-arg names an argument of a xacro file: give --urdf FILE" in capsys.readouterr().err
