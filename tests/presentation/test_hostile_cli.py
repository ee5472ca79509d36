"""Every subcommand against hostile input: one line on stderr naming the command, exit 2, nothing written.

Issue 30 item 4, issue 27 and issue 31 item 4: limits of 1e308, files that are
not UTF-8, JSON nested 100,000 deep, NaN and infinite URDF numbers, boxes whose
width overflows, repeated variables, figures into missing directories or with
unknown extensions, reports into places that cannot hold a directory, and
unknown options each gave a traceback (exit 1) or a silent wrong choice.
Reference: the contract of docs/cli.md (bad input: exit 2, one line).
"""

from __future__ import annotations

import importlib.util
import json

import pytest

from workspace_sym.cli import main
from workspace_sym.errors import OutputError

# yourdfpy is part of the test extra; looked up, not imported (both workers collect this file; one runs it)
pytestmark = pytest.mark.skipif(importlib.util.find_spec("yourdfpy") is None, reason="yourdfpy is not installed")

_JOINT = ('<joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>'
          '<origin xyz="{xyz}" rpy="0 0 0"/><axis xyz="{axis}"/><limit lower="{lower}" upper="1"/></joint>'
          '<joint name="flange" type="fixed"><parent link="upper"/><child link="tip"/><origin xyz="0.3 0 0"/></joint>')
_URDFS = {"good": {}, "nan-xyz": {"xyz": "nan 0 0"}, "inf-xyz": {"xyz": "inf 0 0"}, "nan-axis": {"axis": "0 nan 1"},
          "nan-limit": {"lower": "nan"}}
_CHAIN = ["--lengths", "0.3,0.15", "--lower", "-120,-30", "--upper", "0,30"]
_VARS = ["--var", "x=-1:1", "--var", "y=-1:1", "--constraint", "x + y <= 0", "--delta", "0.5"]


@pytest.fixture()
def files(tmp_path):
    """The hostile files, and a plain file standing where a directory is needed (unwritable even for root)."""
    made = {"tmp": tmp_path, "file": tmp_path / "plain.txt"}
    made["file"].write_text("not a directory\n")
    made["latin"] = tmp_path / "latin1.json"
    made["latin"].write_bytes('{"name": "bras articulé", "joints": []}'.encode("latin-1"))
    made["deep"] = tmp_path / "deep.json"
    made["deep"].write_text("[" * 100_000 + "]" * 100_000)
    made["answers"] = tmp_path / "answers.csv"
    made["answers"].write_text("student,question,answer\nann,1,0\n")
    for name, values in _URDFS.items():
        path = tmp_path / f"{name}.urdf"
        fields = {"xyz": "0 0 0", "axis": "0 0 1", "lower": "-1", **values}
        path.write_text('<robot name="arm"><link name="base"/><link name="upper"/><link name="tip"/>'
                        + _JOINT.format(**fields) + "</robot>")
        made[name] = path
    return made


CASES = [
    (["robots", "--bogus"], "unrecognized arguments: --bogus"),
    (["fk", "--dh", "{latin}"], "--dh: '{latin}' is not UTF-8 text (byte 0xe9"),
    (["fk", "--dh", "{deep}"], "--dh: '{deep}' is not valid JSON (nested too deeply)"),
    (["fk", "--urdf", "{nan-xyz}"], "joint 'shoulder' origin xyz: expected a finite number; got nan"),
    (["fk", "--urdf", "{inf-xyz}"], "joint 'shoulder' origin xyz: expected a finite number"),
    (["fk", "--urdf", "{nan-axis}"], "joint 'shoulder' axis: expected a finite number; got nan"),
    (["fk", "--urdf", "{nan-limit}"], "joint 'shoulder' limit: expected a finite number; got nan"),
    (["fk", "--urdf", "{good}", "--base", "tip"], "--base: no joint moves a link below 'tip'"),
    (["fk", "--urdf", "{good}", "--base", "nowhere"], "--base: no link 'nowhere' in good.urdf"),
    (["fk", "puma560", "--bogus"], "unrecognized arguments: --bogus"),
    (["jacobian", "--dh", "{deep}"], "--dh: '{deep}' is not valid JSON"),
    (["jacobian", "--urdf", "{tmp}/missing.urdf"], "--urdf: cannot read '{tmp}/missing.urdf'"),
    (["pave", "--var", "x=-1e308:1e308", "--constraint", "x <= 1", "--delta", "0.5"], "width overflows"),
    (["pave", "--var", "x=-1:1", "--var", "x=0:1", "--constraint", "x <= 0", "--delta", "0.5"],
     "--var: x is given 2 times"),
    (["pave", *_VARS, "--plot", "/missing/dir/x.png"], "--plot: cannot write '/missing/dir/x.png': directory"),
    (["pave", *_VARS, "--plot", "{tmp}/x.txt"], "--plot: cannot write '{tmp}/x.txt': unknown image format 'txt'"),
    (["pave", "--delta", "1", "--bogus"], "unrecognized arguments: --bogus"),
    (["reach", "planar-2r", "--delta", "0.5", "--plot", "{file}/x.png"], "--plot: cannot write '{file}/x.png'"),
    (["dextrous", "orthoglide", "--slices", "{tmp}/s.unknown"], "--slices: cannot write"),
    (["dextrous", "orthoglide", "--plot", "/missing/x.png"], "--plot: cannot write"),
    (["cube", "orthoglide", "--bogus"], "unrecognized arguments: --bogus"),
    (["boundary", *_CHAIN, "--report", "{file}/rep"], "--report: cannot write"),
    (["boundary", *_CHAIN, "--plot", "{tmp}/b.foo"], "--plot: cannot write '{tmp}/b.foo': unknown image format"),
    (["report", "chain", *_CHAIN, "--out", "{file}/rep"], "--out: cannot write"),
    (["report", "--dh", "{latin}", "--out", "{tmp}/r"], "--dh: '{latin}' is not UTF-8 text"),
    (["grade", "{deep}", "{answers}", "--out", "{tmp}/g"], "key: '{deep}' is not valid JSON (nested too deeply)"),
    (["grade", "{latin}", "{answers}", "--out", "{tmp}/g"], "key: '{latin}' is not UTF-8 text"),
    (["grade", "{deep}", "{answers}", "--out", "{file}/g"], "--out: cannot write"),
    (["exercises", "--out", "{file}/ex"], "--out: cannot write '{file}/ex': '{file}' is not a directory"),
    (["demo", "--out", "{file}/d"], "--out: cannot write '{file}/d': '{file}' is not a directory"),
    (["codegen", "planar-3r", "--out", "{file}"], "--out: cannot write into '{file}': it is a file, not a directory"),
    (["codegen", "--dh", "{deep}", "--out", "{tmp}/c"], "--dh: '{deep}' is not valid JSON (nested too deeply)"),
    (["reach-map", "scara", "--delta", "0.2", "--out", "{file}/m.npz"], "--out: cannot write '{file}/m.npz'"),
    (["reach-map", "--dh", "{deep}", "--delta", "0.2", "--out", "{tmp}/m.npz"], "--dh: '{deep}' is not valid JSON"),
    (["query", "{deep}", "--points", "{answers}"], "map: '{deep}' is not a reach map"),
    (["query", "{tmp}/missing.npz", "--points", "{answers}"], "map: '{tmp}/missing.npz' is not a reach map"),
]


def test_every_subcommand_is_driven():
    from workspace_sym.cli import build_parser

    assert {argv[0] for argv, _ in CASES} == set(build_parser().commands)


@pytest.mark.parametrize("argv, needle", CASES, ids=[" ".join(a[:2]) + f" {k}" for k, (a, _) in enumerate(CASES)])
def test_hostile_input_one_line_exit_2_nothing_written(files, capsys, argv, needle):
    fill = {k: str(v) for k, v in files.items()}
    before = sorted(p.name for p in files["tmp"].iterdir())
    try:
        code = main([a.format(**fill) for a in argv])
    except SystemExit as stop:              # argparse's own errors (unknown options)
        code = stop.code
    out, err = capsys.readouterr()
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"workspace-sym {argv[0]}: error: "), err
    assert needle.format(**fill) in err, err
    assert out == ""
    assert sorted(p.name for p in files["tmp"].iterdir()) == before       # nothing half-written


def test_huge_dh_limits_give_the_forward_kinematics(tmp_path, capsys):
    """Limits of +-1e308 degrees were a traceback (the snapper rounded an infinite multiple of pi/360); they are
    finite numbers, so fk answers.  Reference: the FK of a one-joint arm of length 1, cos(theta1)."""
    path = tmp_path / "huge.json"
    path.write_text(json.dumps({"joints": [{"type": "R", "a": 1, "alpha": 0, "d": 0, "limits": [-1e308, 1e308]}]}))
    assert main(["fk", "--dh", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["position"] == ["cos(theta1)", "sin(theta1)", "0"]


def test_publishing_a_directory_is_all_or_nothing(tmp_path, monkeypatch):
    """A failure while the files are copied leaves neither the new directory nor hidden pieces, and an existing
    directory keeps its old files."""
    from workspace_sym import files

    source = tmp_path / "src"
    source.mkdir()
    for name in ("a.md", "b.html", "c.png"):
        (source / name).write_text(name)
    calls = []
    real = files._copy

    def failing(src, dst):
        calls.append(src.name)
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        real(src, dst)

    monkeypatch.setattr(files, "_copy", failing)
    with pytest.raises(OutputError, match="No space left on device"):
        files.publish_dir(source, tmp_path / "new")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["src"]
    old = tmp_path / "old"
    old.mkdir()
    (old / "a.md").write_text("before")
    calls.clear()
    with pytest.raises(OutputError):
        files.publish_dir(source, old)
    assert sorted(p.name for p in old.iterdir()) == ["a.md"] and (old / "a.md").read_text() == "before"
    monkeypatch.setattr(files, "_copy", real)
    files.publish_dir(source, old)
    assert sorted(p.name for p in old.iterdir()) == ["a.md", "b.html", "c.png"] and (old / "a.md").read_text() == "a.md"


@pytest.mark.parametrize("rows", [25, 10_000])
def test_a_table_past_the_joint_limit_is_refused_at_once(tmp_path, capsys, rows):
    """Issue 30 item 6: fk of a 50-joint planar chain did not finish in 60 s and a 10,000-row file never answered,
    without a message.  Now the table is refused before any row is read or derived, naming the limit."""
    import time

    from workspace_sym.kinematics import MAX_JOINTS

    path = tmp_path / "long.json"
    path.write_text(json.dumps({"joints": [{"type": "R", "d": 0, "a": 1, "alpha": 0}] * rows}))
    start = time.perf_counter()
    assert main(["fk", "--dh", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"at most {MAX_JOINTS} joints" in err and f"got {rows}" in err
    assert time.perf_counter() - start < 30                     # generous: the refusal reads no row


def test_an_unforeseen_failure_is_one_line_exit_2(tmp_path, capsys, monkeypatch):
    """Issue 30 ('every CLI path turns any failure into one line and exit 2'): a 2R table with a 36 degree offset
    made the singular factors raise SymPy's ValueError (issue 29) and the CLI printed a traceback with exit 1.
    Whatever the symbolic layer does with it, the command line answers or says one line."""
    path = tmp_path / "offset36.json"
    rows = [{"type": "R", "theta": t, "d": 0, "a": "1", "alpha": 0} for t in (0, 36)]
    path.write_text(json.dumps({"angles": "degrees", "joints": rows}))
    code = main(["jacobian", "--dh", str(path)])
    err = capsys.readouterr().err
    assert code == 0 or (code == 2 and err.count("\n") == 1 and "Traceback" not in err)
    # the mechanism itself, on a failure no command foresees
    monkeypatch.setattr("workspace_sym.cli.cmd_fk", lambda args: 1 / 0)
    assert main(["fk", "puma560"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("workspace-sym fk: error: could not complete this command (ZeroDivisionError")
    assert err.count("\n") == 1
