"""A resumed run is the run it claims to be (issue 37 item 1): every checkpoint, kept section and box store names
its whole problem, and one of another problem is refused, naming what differs.

The failures reproduced first (each test below failed on the code before the fix: the resume was accepted and
the other problem's boxes were returned as certificates):
* pairs method: a planar 2R (``a = 1, 1/2``, full turns) and the same arm with joint 2 limited to +-30 deg share
  the default name and the root enclosure; the limited arm resumed from the full arm's finished checkpoint
  returned the full arm's 2,082 inner boxes, most of them in the limited arm's hole (it reaches exactly the
  annulus ``sqrt(5/4 + cos 30 deg) <= r <= 3/2``: checked here on the boxes a fresh run proves);
* section path (a first joint limited to part of a turn): the same arm with ``q1`` in [-90, 180] deg and in
  [-180, 90] deg; a base turned by 180 deg;
* the command line: ``reach --dh arm.json --resume ck.npz`` after the limits in ``arm.json`` were edited.

The property: changing any one field of the problem (a DH entry, a joint type, a limit, the base, the tool, a
parameter value, the method, delta, size, a tuning option or constant, the tool constraint, the format
version) makes the resume refuse, naming that field; so does a store of another run, a part or an array changed
since the checkpoint was written.
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from reach_checks import offset_arm, swing_arm
from workspace_sym import RunOn, StopAt, robots
from workspace_sym.cli import main
from workspace_sym.errors import InvalidParameterError
from workspace_sym.interval import fingerprint as fingerprint_module
from workspace_sym.interval import pave
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial import Pose, Tuning, reach

R = sp.Rational
QUIET = StopAt()
DEG = sp.pi / 180


HALF = R(1, 2)


def two_r(limits2=None, *, a2=HALF, kind2="R", base=None, tool=None, alpha2=0, d2=0, offset2=0,
          parameters=None):
    """Issue 37's planar 2R, ``a = 1, 1/2``, full turns unless ``limits2`` (joint 2)."""
    second = (DHJoint.revolute(2, a=a2, alpha=alpha2, d=d2, offset=offset2, limits=limits2) if kind2 == "R" else
              DHJoint.prismatic(2, a=a2, alpha=alpha2, theta=offset2, limits=limits2 or (0, R(1, 2))))
    return DHRobot([DHJoint.revolute(1, a=1), second], base=base, tool=tool, parameters=parameters)


def rotz(angle):
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def shift(x=0, y=0, z=0):
    return sp.Matrix([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]])


@pytest.fixture(scope="module")
def full_arm(tmp_path_factory):
    """The full-turn 2R paved by the pairs method at delta 0.1 (issue 37's robot A), and its finished checkpoint."""
    path = tmp_path_factory.mktemp("a") / "ck.npz"
    paving = reach(two_r(), delta=0.1, method="pairs", stop=QUIET, run=RunOn(resume=path))
    assert paving.complete and paving.counts["inner"] > 2000
    return paving, path


@pytest.fixture(scope="module")
def full_arm_checkpoint(full_arm):
    return full_arm[1]


def _copy(path: Path, directory: Path) -> Path:
    copy = directory / path.name
    shutil.copy(path, copy)
    return copy


def test_a_pairs_checkpoint_of_the_arm_with_other_limits_is_refused(full_arm, tmp_path):
    """Robot B (joint 2 within +-30 deg) resumed from robot A's checkpoint: refused, naming the limits.  What the
    old resume returned was wrong: A's proved inner measure is larger than B's whole workspace, the annulus
    sqrt(5/4 + cos 30 deg) <= r <= 3/2 (exact area pi (1 - cos 30 deg) = 0.421, held by B's own bracket)."""
    paving, checkpoint = full_arm
    limited = two_r((-30 * DEG, 30 * DEG))
    ck = _copy(checkpoint, tmp_path)
    with pytest.raises(InvalidParameterError, match=r"checkpoint of another run \(it differs in robot limits\)") \
            as caught:
        reach(limited, delta=0.1, method="pairs", stop=QUIET, run=RunOn(resume=ck))
    assert caught.value.parameter == "resume"
    exact = math.pi * (1 - math.cos(math.pi / 6))
    lo, hi = reach(limited, delta=0.1, method="pairs", stop=QUIET).measure_bounds
    assert lo <= exact <= hi < paving.measure_bounds[0]


def test_a_limited_turn_resumed_with_other_limits_of_its_first_joint_is_refused(tmp_path):
    """Section path: the arm with q1 in [-90, 180] deg resumed from the checkpoint (and the section kept beside
    it) of the same arm with q1 in [-180, 90] deg is refused, naming the limits, before any box is decided."""
    ck = tmp_path / "turn.npz"
    stop = StopAt(section_boxes=100, max_boxes=2_000)
    first = reach(swing_arm((-sp.pi, sp.pi / 2)), delta=0.4, stop=stop, run=RunOn(resume=ck))
    assert first.method == "critical" and ck.exists() and Path(f"{ck}.section.npz").exists()
    with pytest.raises(InvalidParameterError, match=r"section kept beside a checkpoint of another run \(it differs "
                                                    r"in joint limits, robot limits\)") as refused:
        reach(swing_arm((-sp.pi / 2, sp.pi)), delta=0.4, stop=stop, run=RunOn(resume=ck))
    assert "not a section kept by reach" not in str(refused.value)     # a readable file of another problem


def test_a_turned_section_resumed_with_its_base_turned_by_half_a_turn_is_refused(tmp_path):
    """The base turned by 180 deg about z (the same name, table and limits) is another problem."""
    ck = tmp_path / "base.npz"
    reach(offset_arm(), delta=0.25, stop=QUIET, run=RunOn(resume=ck))
    assert ck.exists()
    with pytest.raises(InvalidParameterError, match=r"differs in robot base\)"):
        reach(offset_arm(base=rotz(sp.pi)), delta=0.25, stop=QUIET, run=RunOn(resume=ck))


def test_cli_refuses_a_checkpoint_after_the_limits_were_edited(tmp_path, capsys):
    """``reach --dh arm.json --resume ck.npz``, then the limits in ``arm.json`` edited and the same command
    again: exit 2 and one line naming --resume and the limits, where the old bracket used to be printed."""
    arm = {"name": "arm", "angles": "degrees",
           "joints": [{"type": "R", "a": 1, "d": 0, "alpha": 0}, {"type": "R", "a": 0.5, "d": 0, "alpha": 0}]}
    path, ck = tmp_path / "arm.json", tmp_path / "ck.npz"
    path.write_text(json.dumps(arm))
    argv = ["reach", "--dh", str(path), "--delta", "0.25", "--method", "pairs", "--resume", str(ck), "--json",
            "--no-progress"]
    assert main(argv) == 0 and ck.exists()
    capsys.readouterr()
    arm["joints"][1]["limits"] = [-30, 30]
    path.write_text(json.dumps(arm))
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    err = captured.err.strip()
    assert err.count("\n") == 0 and "--resume" in err and "robot limits" in err


# ------------------------------------------------------------------------------ the property
# Each mutation of issue 37's robot A or of its call, with the field the refusal must name.
MUTATIONS = {
    "a of joint 2": (lambda v: dict(robot=two_r(a2=v)), "robot table"),
    "alpha of joint 2": (lambda v: dict(robot=two_r(alpha2=v)), "robot table"),
    "d of joint 2": (lambda v: dict(robot=two_r(d2=v)), "robot table"),
    "offset of joint 2": (lambda v: dict(robot=two_r(offset2=v)), "robot table"),
    "type of joint 2": (lambda v: dict(robot=two_r(kind2="P", limits2=(0, v))), "robot table"),
    "limits of joint 2": (lambda v: dict(robot=two_r((-v, v))), "robot limits"),
    "base": (lambda v: dict(robot=two_r(base=shift(x=v))), "robot base"),
    "tool": (lambda v: dict(robot=two_r(tool=shift(y=v))), "robot tool"),
    "parameter value": (lambda v: dict(robot=two_r(a2=sp.Symbol("a2"), parameters={"a2": v})), "robot table"),
    "delta": (lambda v: dict(delta=0.1 + float(v) / 100), "delta"),
    "size": (lambda v: dict(size="width"), "size"),
    "max_pairs": (lambda v: dict(tuning=Tuning(max_pairs=100_000 + int(100 * v))), "max_pairs"),
    "inner_depth": (lambda v: dict(tuning=Tuning(inner_depth=int(bool(v > HALF)))), "inner_depth"),  # default 2
}


@pytest.fixture(scope="module")
def copies(tmp_path_factory):
    return tmp_path_factory.mktemp("copies")


@settings(max_examples=20, deadline=None)
@given(field=st.sampled_from(sorted(MUTATIONS)),
       value=st.fractions(min_value=R(1, 10), max_value=R(9, 10), max_denominator=97).map(sp.Rational))
@example(field="limits of joint 2", value=30 * DEG)
def test_changing_any_one_field_makes_the_resume_refuse(full_arm_checkpoint, copies, field, value):
    change, named = MUTATIONS[field]
    call = {"robot": two_r(), "delta": 0.1, "method": "pairs", **change(value)}
    ck = _copy(full_arm_checkpoint, copies)
    with pytest.raises(InvalidParameterError, match=rf"checkpoint of another run \(it differs in [^)]*{named}"):
        reach(call.pop("robot"), **call, stop=QUIET, run=RunOn(resume=ck))


def test_a_parameter_value_given_to_reach_is_part_of_the_problem(tmp_path):
    arm = two_r(a2=sp.Symbol("a2"), parameters={"a2": 0.5})
    ck = tmp_path / "p.npz"
    reach(arm, delta=0.25, method="pairs", stop=QUIET, run=RunOn(resume=ck))
    with pytest.raises(InvalidParameterError, match=r"differs in [^)]*parameters"):
        reach(arm, delta=0.25, method="pairs", parameters={sp.Symbol("a2"): 0.25}, stop=QUIET, run=RunOn(resume=ck))


def test_the_method_and_a_tuning_constant_are_part_of_the_problem(tmp_path):
    """The SCARA by the section (critical) method, then by pairs, from one checkpoint; and a tuning figure of
    the section changed between two runs."""
    from workspace_sym.serial import Tuning

    scara = robots.build("scara")
    ck = tmp_path / "m.npz"
    reach(scara, delta=0.5, stop=QUIET, run=RunOn(resume=ck))
    assert ck.exists()
    with pytest.raises(InvalidParameterError, match=r"differs in [^)]*method"):
        reach(scara, delta=0.5, method="pairs", stop=QUIET, run=RunOn(resume=ck))
    with pytest.raises(InvalidParameterError, match=r"differs in [^)]*tuning"):
        reach(scara, delta=0.5, stop=QUIET, run=RunOn(resume=ck), tuning=Tuning(section_ratio=0.5))


def test_the_tool_constraint_is_part_of_the_problem(tmp_path):
    puma = robots.build("puma560")
    ck = tmp_path / "pose.npz"
    cone = Pose(approach=(0, 0, -1), cone=20)
    first = reach(puma, delta=0.5, pose=cone, stop=StopAt(max_boxes=2_000), run=RunOn(resume=ck))
    assert first.method == "section" and ck.exists()
    with pytest.raises(InvalidParameterError, match=r"differs in [^)]*constraint"):
        reach(puma, delta=0.5, pose=Pose(approach=(0, 0, -1), cone=25), stop=QUIET, run=RunOn(resume=ck))


def test_a_checkpoint_of_another_format_version_is_refused(full_arm_checkpoint, tmp_path, monkeypatch):
    ck = _copy(full_arm_checkpoint, tmp_path)
    monkeypatch.setattr(fingerprint_module, "FORMAT", fingerprint_module.FORMAT + 1)
    with pytest.raises(InvalidParameterError, match="another version of workspace_sym"):
        reach(two_r(), delta=0.1, method="pairs", stop=QUIET, run=RunOn(resume=ck))


DISC = (["x**2 + y**2 <= 1"], {"x": (-1.1, 1.1), "y": (-1.1, 1.1)})
PAVE_MUTATIONS = {
    "constraints": dict(constraints=["x**2 + y**2 <= 1.01"]),
    "strict": dict(constraints=["x**2 + y**2 < 1"]),
    "lower": dict(box={"x": (-1.2, 1.1), "y": (-1.1, 1.1)}),
    "variables": dict(box={"u": (-1.1, 1.1), "y": (-1.1, 1.1)}, constraints=["u**2 + y**2 <= 1"]),
    "delta": dict(delta=0.11),
    "size": dict(size="width"),
    "backend": dict(backend="mpmath"),
    "separator": dict(contract=True),
}


@pytest.mark.parametrize("field", sorted(PAVE_MUTATIONS))
def test_a_paving_checkpoint_names_every_field_of_its_problem(field, tmp_path):
    ck = tmp_path / "pave.npz"
    base = dict(constraints=DISC[0], box=DISC[1], delta=0.1)
    stopped = pave(**base, stop=StopAt(max_boxes=200), run=RunOn(resume=ck))
    assert not stopped.complete
    changed = {**base, **PAVE_MUTATIONS[field]}
    with pytest.raises(InvalidParameterError, match=rf"checkpoint of another run \(it differs in [^)]*{field}"):
        pave(changed.pop("constraints"), changed.pop("box"), **changed, stop=QUIET, run=RunOn(resume=ck))


# ------------------------------------------------------------------------------ stores and damaged files
def _stopped_on_disk(tmp_path, name="run"):
    ck, store = tmp_path / f"{name}.npz", tmp_path / f"{name}-boxes"
    pave(*DISC, delta=0.02, stop=StopAt(max_boxes=3_000),
         run=RunOn(resume=ck, store=store, max_memory="64MB"))
    parts = sorted(store.glob("*/part-*.npy"))
    assert parts and (store / "problem.json").exists()
    return ck, store, parts


def test_a_store_of_another_run_is_refused(tmp_path):
    """The checkpoint names its store; a store holding another problem's boxes in its place is refused."""
    ck, store, _ = _stopped_on_disk(tmp_path)
    other = tmp_path / "other"
    pave(["x**2 + y**2 <= 0.5"], DISC[1], delta=0.02, stop=StopAt(max_boxes=3_000),
         run=RunOn(resume=other / "o.npz", store=other / "boxes", max_memory="64MB"))
    shutil.rmtree(store)
    shutil.copytree(other / "boxes", store)
    with pytest.raises(InvalidParameterError, match="holds the boxes of another run"):
        pave(*DISC, delta=0.02, stop=QUIET, run=RunOn(resume=ck, max_memory="64MB"))


def test_a_part_changed_since_the_checkpoint_is_refused(tmp_path):
    ck, store, parts = _stopped_on_disk(tmp_path)
    boxes = np.load(parts[0])
    boxes[0] = boxes[-1]
    np.save(parts[0], boxes)
    with pytest.raises(InvalidParameterError, match="not the part of the box store that the checkpoint recorded"):
        pave(*DISC, delta=0.02, stop=QUIET, run=RunOn(resume=ck, max_memory="64MB"))


def test_a_damaged_checkpoint_is_refused_never_half_read(tmp_path):
    """A checkpoint whose pending boxes were changed, or which was cut short, is refused as a whole."""
    ck = tmp_path / "run.npz"
    pave(*DISC, delta=0.02, stop=StopAt(max_boxes=500), run=RunOn(resume=ck))
    with np.load(ck) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["pending"] = arrays["pending"][1:]
    changed = tmp_path / "changed.npz"
    np.savez(changed, **arrays)
    with pytest.raises(InvalidParameterError, match="is damaged"):
        pave(*DISC, delta=0.02, stop=QUIET, run=RunOn(resume=changed))
    cut = tmp_path / "cut.npz"
    cut.write_bytes(ck.read_bytes()[: ck.stat().st_size // 2])
    with pytest.raises(InvalidParameterError, match="is not a checkpoint of a paving"):
        pave(*DISC, delta=0.02, stop=QUIET, run=RunOn(resume=cut))
