"""Certified orientation workspaces (issue 25): bad input, the CLI, and the verdicts against independent
references (the position workspace of ``reach``, sampled configurations, an inverse kinematics at 50 digits)."""

from __future__ import annotations

import json
import math

import mpmath
import numpy as np
import pytest
import sympy as sp

import workspace_sym as ws
from workspace_sym import Pose, StopAt, robots
from workspace_sym.cli import main
from workspace_sym.errors import InvalidParameterError, WorkspaceError
from workspace_sym.serial import Tuning, reach
from workspace_sym.serial.pose import constraint_from, orientation_constraint, pose_structure


@pytest.mark.parametrize("options, parameter, fragment", [
    (dict(approach=(0, 0, 0), cone=20), "approach", "non-zero"),
    (dict(approach=(0, 0), cone=20), "approach", "three numbers"),
    (dict(approach=(0, 0, float("nan")), cone=20), "approach", "finite"),
    (dict(approach=(0, 0, -1), cone=181), "cone", "between 0 and 180"),
    (dict(approach=(0, 0, -1), cone=-1), "cone", "between 0 and 180"),
    (dict(approach=(0, 0, -1), cone=float("inf")), "cone", "between 0 and 180"),
    (dict(approach=(0, 0, -1)), "cone", "cone must be given"),
    (dict(approach=(0, 0, -1), cone=20, every=True), "every", "not implemented"),
    (dict(orientation=[[1, 0, 0], [0, 1, 0], [0, 0, 2]]), "orientation", "rotation matrix"),
    (dict(orientation=[[1, 0, 0], [0, 1, 0], [0, 0, -1]]), "orientation", "determinant"),
    (dict(orientation=[[1, 0], [0, 1]]), "orientation", "3 x 3"),
    (dict(rpy=(0, 180)), "rpy", "three angles"),
    (dict(approach=(0, 0, -1), cone=20, rpy=(0, 0, 0)), "approach", "not both"),
    (dict(cone=20, rpy=(0, 0, 0)), "cone", "need approach"),
])
def test_bad_constraints_name_the_parameter_value_and_expectation(options, parameter, fragment, scara):
    with pytest.raises(InvalidParameterError) as caught:
        reach(scara, delta=0.05, pose=Pose(**options))
    assert caught.value.parameter == parameter
    assert fragment in str(caught.value)


def test_a_budget_of_section_boxes_is_refused_with_a_pose(scara):
    """A tool constraint paves its own section, without a budget of boxes: ``StopAt(section_boxes=...)`` is
    refused by name, never ignored."""
    with pytest.raises(InvalidParameterError) as caught:
        reach(scara, delta=0.05, pose=Pose(rpy=(180, 0, 0)), stop=StopAt(section_boxes=10))
    assert caught.value.parameter == "section_boxes" and "got 10, expected None" in str(caught.value)


def test_rotation_is_made_exact_and_keeps_the_matrix_given():
    # Reference: the exact rotation by pi about x (tool down), given as floats off by a rounding error.
    c = orientation_constraint([[1, 0, 0], [0, -1, 1e-17], [0, -1e-17, -1]])
    assert c.rotation == sp.Matrix([[1, 0, 0], [0, -1, 0], [0, 0, -1]])
    assert abs(c.rpy[0]) == sp.pi and c.rpy[1:] == (0, 0)
    # a float angle that is not a multiple of pi/360 is kept as its exact binary value (numbers are degrees)
    R = np.array(sp.N(orientation_constraint(rpy=(0, 0, "1/3")).rotation, 30).tolist(), dtype=float)
    c2 = orientation_constraint(R)
    assert abs(float(c2.rpy[2]) - math.pi / 540) < 1e-12        # 1/3 degree: no multiple of pi/360
    assert sp.simplify(c2.rotation.T * c2.rotation - sp.eye(3)) == sp.zeros(3)


def test_every_direction_of_a_zero_cone_is_the_direction():
    assert constraint_from(approach=(0, 0, -1), cone=0, every=True).cone == 0


def _overlap(A, B, pad=1e-9):
    """Pairs of boxes of A and B whose interiors (shrunk by pad) meet: (N, M) mask."""
    if not len(A) or not len(B):
        return np.zeros((len(A), len(B)), dtype=bool)
    lo = np.maximum(A[:, None, :, 0], B[None, :, :, 0])
    hi = np.minimum(A[:, None, :, 1], B[None, :, :, 1])
    return np.all(hi - lo > pad, axis=2)


@pytest.fixture(scope="module")
def scara_tool_down(scara):
    return reach(scara, delta=0.05, pose=Pose(rpy=(180, 0, 0)))


def test_scara_tool_down_is_its_position_workspace(scara_tool_down, scara):
    # Reference: the SCARA's approach axis is always straight down and its last joint spins the tool through
    # a full turn, so tool down is reached wherever the position is: its constant-orientation workspace is the
    # position workspace of reach (an independent method, the critical section), checked both ways, and holds
    # the exact volume (Bastien's area of the x, y region times the 0.21 m stroke).
    position = reach(scara, delta=0.05)
    oriented = scara_tool_down
    assert not _overlap(oriented.inner, position.outer).any()
    assert not _overlap(position.inner, oriented.outer).any()
    exact = ws.PlanarChain([0.325, 0.275], [-50, -88], [50, 88]).boundary().area * 0.21
    lo, hi = oriented.measure_bounds
    assert lo <= exact <= hi and lo > 0.2 * exact
    assert oriented.method == "pairs"


def test_an_unreachable_direction_is_proved_outer_everywhere(scara):
    # Reference: the SCARA's approach axis is (0, 0, -1) for every configuration: 90 degrees from x.
    p = reach(scara, delta=0.05, pose=Pose(approach=(1, 0, 0), cone=30))
    assert p.counts["inner"] == 0 and p.complete
    assert p.measures["outer"] == pytest.approx(p.box.measure)


@pytest.fixture(scope="module")
def puma_cone(puma):
    return reach(puma, delta=0.3, pose=Pose(approach=(0, 0, -1), cone=20))


def _fk(robot):
    T = robot.substitute(robot.fk())
    return sp.lambdify([robot.q], T, modules="numpy"), T


def test_puma_configurations_in_the_cone_never_land_in_an_outer_box(puma_cone, puma):
    # Reference: random configurations within the limits whose approach axis is in the cone (with a margin of
    # 1e-9 for float rounding): none may be the position of a point of an outer box.
    robot = puma
    f, _ = _fk(robot)
    rng = np.random.default_rng(7)
    lim = robot.joint_limits()
    q = rng.uniform(lim[:, 0], lim[:, 1], size=(20000, 6))
    T = np.stack([np.asarray(f(qi), dtype=float) for qi in q[:20000:4]])
    keep = -T[:, 2, 2] >= math.cos(math.radians(20)) + 1e-9
    points = T[keep, :3, 3]
    assert len(points) > 100
    outer = puma_cone.outer
    inside = np.all((points[:, None, :] > outer[None, :, :, 0] + 1e-9) & (points[:, None, :] < outer[None, :, :, 1]
                                                                             - 1e-9), axis=2)
    assert not inside.any()
    assert puma_cone.method == "section" and puma_cone.counts["inner"] > 0


def _solve_pose_50_digits(robot, target, q0, equations):
    """A root of ``equations(q)`` (position minus target, then the constraint) near ``q0`` at 50 digits."""
    with mpmath.workdps(50):
        root = mpmath.findroot(lambda *q: equations(q, target), [mpmath.mpf(float(v)) for v in q0])
        return [root[i] for i in range(len(q0))]


def test_points_of_puma_inner_boxes_are_reached_in_the_cone_at_50_digits(puma_cone, puma):
    # Reference: an inverse kinematics at 50 digits (mpmath findroot on the position in three joints, the
    # wrist kept where a float search put it), within the limits, with the approach in the cone.
    robot = puma
    _, T = _fk(robot)
    q = robot.q
    position = sp.lambdify(q, list(T[:3, 3]), modules="mpmath")
    approach_z = sp.lambdify(q, T[2, 2], modules="mpmath")
    p_float = sp.lambdify(q, list(T[:3, 3]), modules="numpy")
    j_float = sp.lambdify(q, T[:3, 3].jacobian(q), modules="numpy")
    a_float = sp.lambdify(q, T[2, 2], modules="numpy")
    plan = pose_structure(robot, (), constraint_from(approach=(0, 0, -1), cone=20))
    rng = np.random.default_rng(3)
    boxes = puma_cone.inner[rng.choice(len(puma_cone.inner), size=6, replace=False)]
    lim = robot.joint_limits()
    for box in boxes:
        y = rng.uniform(box[:, 0], box[:, 1])
        found = False
        for _ in range(400):
            q0 = rng.uniform(lim[:, 0], lim[:, 1])
            # float search: the position by least squares from a random start, then a wrist among random ones
            # whose approach is in the cone (the Puma's wrist does not move its position)
            for _ in range(30):
                p = np.array(p_float(*q0), dtype=float) - y
                J = np.array(j_float(*q0), dtype=float)
                q0 = np.clip(q0 - np.linalg.lstsq(J, p, rcond=None)[0], lim[:, 0], lim[:, 1])
            p = np.array(p_float(*q0), dtype=float) - y
            if np.linalg.norm(p) > 1e-8:
                continue
            wrists = rng.uniform(lim[3:, 0], lim[3:, 1], size=(2000, 3))
            values = np.broadcast_to(a_float(*q0[:3], *wrists.T), (2000,))
            good = np.nonzero(-values >= math.cos(math.radians(20)) + 1e-6)[0]
            if not len(good):
                continue
            q0[3:] = wrists[good[0]]

            def equations(qa, target, q0=q0):
                full = list(qa) + [mpmath.mpf(float(v)) for v in q0[3:]]
                return [a - mpmath.mpf(float(b)) for a, b in zip(position(*full), target)]

            with mpmath.workdps(50):
                qa = _solve_pose_50_digits(robot, y, q0[:3], equations)
                full = qa + [mpmath.mpf(float(v)) for v in q0[3:]]
                residual = max(abs(a - mpmath.mpf(float(b))) for a, b in zip(position(*full), y))
                within = all(mpmath.mpf(lim[i, 0]) <= full[i] <= mpmath.mpf(lim[i, 1]) for i in range(6))
                if residual < mpmath.mpf(10) ** -40 and within and -approach_z(*full) >= mpmath.cos(mpmath.pi / 9):
                    found = True
                    break
        assert found, f"no configuration in the cone reaches {y} of inner box {box.tolist()}"
    assert plan.revolved is not None


def test_cli_reach_with_a_constraint_echoes_it(capsys):
    code = main(["reach", "scara", "--delta", "0.05", "--approach", "1,0,0", "--cone", "30", "--json"])
    out, _ = capsys.readouterr()
    assert code == 0
    data = json.loads(out)
    assert data["constraint"] == {"approach": [1.0, 0.0, 0.0], "cone_deg": 30.0, "every": False}
    assert data["inner"]["boxes"] == 0 and data["complete"]


@pytest.mark.parametrize("argv, flag", [
    (["--approach", "0,0,0", "--cone", "20"], "--approach"),
    (["--approach", "0,0,-1", "--cone", "200"], "--cone"),
    (["--approach", "0,0,-1", "--cone", "20", "--every"], "--every"),
    (["--orientation", "1,0,0,0,1,0,0,0,2"], "--orientation"),
    (["--orientation", "rpy:0,180"], "--orientation"),
])
def test_cli_bad_constraint_is_exit_2_and_one_line(capsys, argv, flag):
    code = main(["reach", "scara", "--delta", "0.05", *argv])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"workspace-sym reach: error: {flag}:")


def test_errors_are_workspace_errors():
    assert issubclass(InvalidParameterError, WorkspaceError)
    with pytest.raises(WorkspaceError):
        reach(robots.build("planar-2r"), delta=0.1, pose=Pose(approach=(0, 0, 1), cone=10))


def test_reach_pose_of_earlier_releases_still_works_with_a_deprecation_warning(scara):
    """The entry point of earlier releases, ``orientation.reach_pose``, gives the boxes of ``reach(pose=...)``
    (reference: the same call spelt the new way) and says how to spell it."""
    from workspace_sym.orientation import reach_pose

    with pytest.warns(DeprecationWarning, match=r"reach_pose is deprecated; pass reach\(robot, delta=\.\.\., "
                                                r"pose=Pose"):
        old = reach_pose(scara, delta=0.2, approach=(1, 0, 0), cone=30, max_boxes=400, inner_depth=0)
    new = reach(scara, delta=0.2, pose=Pose(approach=(1, 0, 0), cone=30), stop=StopAt(max_boxes=400),
                tuning=Tuning(pose_inner_depth=0))
    assert old.counts == new.counts and old.measure_bounds == new.measure_bounds and old.method == new.method


def _full_wrist_puma(d6=0):
    """The Puma 560 with its wrist joints over a full turn (the wrist then reaches every orientation) and a tool
    length d6 along the last axis."""
    base = robots.build("puma560")
    wrist = [ws.DHJoint.revolute(k + 4, d=d6 if k == 2 else j.d, a=j.a, alpha=j.alpha, limits=(-sp.pi, sp.pi))
             for k, j in enumerate(base.joints[3:])]
    return ws.DHRobot(list(base.joints[:3]) + wrist, name="puma-full-wrist", parameters=base.parameters, units="m")


def test_spherical_wrist_tool_down_is_the_wrist_centre_workspace():
    # Reference: for a spherical wrist reaching every orientation, the tool point p = w + d6 R z; the Puma's
    # table has d6 = 0 (the tool point is the wrist centre), so the constant-orientation workspace is the
    # position workspace of the wrist centre (reach's critical section, an independent method), shifted by
    # -d6 R z = 0: checked both ways (no inner box of one meets an outer box of the other), and its bracket
    # meets the position's.
    robot = _full_wrist_puma()
    oriented = reach(robot, delta=0.4, pose=Pose(rpy=(180, 0, 0)))
    position = reach(robot, delta=0.4)
    assert oriented.method == "section" and position.counts["inner"] > 0 and oriented.counts["outer"] > 0
    assert not _overlap(position.inner, oriented.outer).any()
    assert not _overlap(oriented.inner, position.outer).any()
    lo, hi = oriented.measure_bounds
    p_lo, p_hi = position.measure_bounds
    assert lo <= p_hi and p_lo <= hi


def test_spherical_wrist_with_a_tool_length_is_the_shifted_wrist_centre_workspace():
    # Reference: with a tool length d6 = 1/8 along the last axis, the tool point of a spherical wrist is
    # p = w + d6 R z, so with the frame fixed to R = Rx(pi) (tool down, R z = (0, 0, -1)) the constant-orientation
    # workspace is the wrist centre's position workspace (the d6 = 0 arm's, by reach's critical section, an
    # independent method) moved by d6 R z = (0, 0, -1/8) (exact in floats): checked both ways, no inner box of one
    # meets an outer box of the other moved, with proved boxes of each kind on both sides.
    oriented = reach(_full_wrist_puma(sp.Rational(1, 8)), delta=0.3, pose=Pose(rpy=(180, 0, 0)))
    centre = reach(_full_wrist_puma(), delta=0.3)
    moved = {kind: getattr(centre, kind) + np.array([0.0, 0.0, -0.125])[None, :, None] for kind in ("inner", "outer")}
    assert oriented.method == "section"
    assert min(oriented.counts["inner"], oriented.counts["outer"], len(moved["inner"]), len(moved["outer"])) > 0
    assert not _overlap(moved["inner"], oriented.outer).any()
    assert not _overlap(oriented.inner, moved["outer"]).any()
    # a shift keeps the volume: the two certified brackets meet
    lo, hi = oriented.measure_bounds
    c_lo, c_hi = centre.measure_bounds
    assert lo <= c_hi and c_lo <= hi


def test_a_section_cut_by_the_budget_keeps_a_sound_bracket(puma_cone, puma):
    # Reference: the complete run (fixture); a run stopped early proves less, never something else.
    cut = reach(puma, delta=0.3, stop=StopAt(max_boxes=40), pose=Pose(approach=(0, 0, -1), cone=20))
    assert not cut.complete and "budget" in cut.stop_reason
    assert not _overlap(cut.outer, puma_cone.inner).any() and not _overlap(cut.inner, puma_cone.outer).any()
    lo, hi = cut.measure_bounds
    full_lo, full_hi = puma_cone.measure_bounds
    assert lo <= full_hi and full_lo <= hi and hi - lo >= full_hi - full_lo - 1e-9


def test_puma_cone_section_bracket_meets_the_box_bracket(puma_cone):
    # Reference: the bracket of the three-dimensional boxes of the same run (a second certified answer from the
    # same section, classified box by box): the two must meet, and the section's is the tighter one here.
    p = puma_cone
    assert p.volume_bounds is not None and p.complete
    box_lo, box_hi = p.box_measure_bounds
    lo, hi = p.volume_bounds
    assert lo <= box_hi and box_lo <= hi
    assert hi - lo < box_hi - box_lo
    assert p.measure_bounds == (max(lo, box_lo), min(hi, box_hi))
    assert p.to_dict()["volume_bounds"] == [lo, hi]


# ---------------------------------------------------------------------- a time limit: the section's cells, not delta's
COARSE_TIMED = Tuning(pose_timed_cells=128)     # cells of 2^-6 m on the Puma's section (delta 0.3: 2^-5)


def test_under_a_time_limit_the_section_and_its_bracket_do_not_depend_on_delta(puma_cone, puma):
    """Issue 40 / 41: with a time limit the constrained section is paved toward cells set by its enclosure
    (``Tuning.pose_timed_cells``), not by delta, so two deltas give the same section and the same Pappus bracket
    (here the section completes well within its share, so the clock does not enter).  Reference: the untimed run
    of the fixture (cells of delta 0.3), which the timed runs must meet and never contradict, and whose cells
    are coarser than the timed ones (so its bracket is the wider)."""
    runs = [reach(puma, delta=delta, stop=StopAt(time_limit=600), tuning=COARSE_TIMED,
                  pose=Pose(approach=(0, 0, -1), cone=20)) for delta in (0.5, 0.3)]
    assert runs[0].volume_bounds == runs[1].volume_bounds and runs[0].method == runs[1].method == "section"
    lo, hi = runs[1].volume_bounds
    full_lo, full_hi = puma_cone.volume_bounds
    assert full_lo <= lo <= hi <= full_hi and hi - lo < 0.8 * (full_hi - full_lo)
    for run in runs:
        assert run.complete
        assert not _overlap(run.outer, puma_cone.inner).any() and not _overlap(run.inner, puma_cone.outer).any()


def test_a_short_time_limit_paves_a_coarser_section(monkeypatch, puma, puma_cone):
    """The grid of a timed section is counted, classified and summed after its paving, outside its share: a short
    limit gets fewer cells (``pose_timed_cells`` times the square root of the share of ``pose_timed_seconds`` left),
    so that it is not overshot by a grid it had no time to refine (a review found a 1 s limit taking 7 s and 2 GB
    on a 17-million-cell grid).  Reference: the width asked of the section, against the enclosure's longest
    side (the model is in the cache: the fixture's run built it)."""
    from workspace_sym.serial import plans

    asked = []

    class Asked(Exception):
        pass

    def record(model, width, run, **kwargs):
        enclosure = model.position.enclose(model.position.limits[None])[0]
        asked.append(float(np.max(enclosure[:, 1] - enclosure[:, 0])) / width)
        raise Asked

    monkeypatch.setattr(plans, "section_classes", record)
    for limit in (600.0, 30.0, 1.2):
        with pytest.raises(Asked):
            reach(puma, delta=0.3, stop=StopAt(time_limit=limit), pose=Pose(approach=(0, 0, -1), cone=20))
    long, medium, short = asked
    assert long == pytest.approx(4096) and 0.5 * 4096 - 50 < medium < 0.5 * 4096 + 1
    assert short <= 4096 * (1.2 / 120) ** 0.5 + 1e-9


def test_a_section_cut_by_its_share_of_the_time_keeps_a_sound_bracket(monkeypatch, puma_cone, puma):
    """The section stops when its share of the time limit is spent (here: made to stop at its third look, so the
    test does not depend on the clock); the task boxes are then classified from the cells it proved, the run is
    complete (its share is not the run's limit) and its bracket holds the untimed run's (reference: the fixture,
    from another section: they must meet and never contradict)."""
    from workspace_sym.serial import plans

    looks = []

    def stop_at_the_third_look(self, evaluated, *, ahead=0.0):
        looks.append(evaluated)
        return self.REASON if len(looks) >= 3 else ""

    monkeypatch.setattr(plans.SectionShare, "stop_reason", stop_at_the_third_look)
    cut = reach(puma, delta=0.3, stop=StopAt(time_limit=600), tuning=COARSE_TIMED,
                pose=Pose(approach=(0, 0, -1), cone=20))
    assert len(looks) == 3 and cut.complete and cut.stop_reason in ("", None)
    lo, hi = cut.measure_bounds
    full_lo, full_hi = puma_cone.measure_bounds
    assert lo <= full_hi and full_lo <= hi
    assert not _overlap(cut.outer, puma_cone.inner).any() and not _overlap(cut.inner, puma_cone.outer).any()


def test_the_share_of_a_section_stops_it_before_a_step_that_would_end_late():
    """:class:`~workspace_sym.serial.plans.SectionShare`: the run's own reason first, then the share's when the
    step expected (times the reserve) would end past its end (reference: the arithmetic of a clock held still)."""
    from types import SimpleNamespace

    from workspace_sym.serial.plans import SectionShare

    clock = SimpleNamespace(seconds=10.0, showing=False, reason="",
                            stop_reason=lambda evaluated, ahead=0.0: clock.reason)
    share = SectionShare(clock, end=12.0, reserve=1.5)
    assert share.stop_reason(5) == "" and share.stop_reason(5, ahead=1.0) == ""        # 10 + 1.5 <= 12
    assert share.stop_reason(5, ahead=1.4) == SectionShare.REASON                       # 10 + 2.1 > 12
    clock.reason = "time limit of 20 s reached"
    assert share.stop_reason(5) == "time limit of 20 s reached" and not share.showing


def test_a_timed_section_is_kept_beside_the_checkpoint_and_taken_back(tmp_path, monkeypatch, puma):
    """A time-limited run may pave its section differently each time (the clock), so it keeps the section beside
    its checkpoint and a resumed run classifies from that one (reference: the first run's boxes; the resumed
    run must not pave a section at all)."""
    from workspace_sym.interval.driver import RunOn
    from workspace_sym.serial import plans

    checkpoint = tmp_path / "cone.ckpt"
    options = dict(delta=0.3, stop=StopAt(time_limit=600), tuning=COARSE_TIMED,
                   pose=Pose(approach=(0, 0, -1), cone=20))
    first = reach(puma, run=RunOn(resume=checkpoint), **options)
    assert (tmp_path / "cone.ckpt.section.npz").is_file()

    def no_section(*args, **kwargs):
        raise AssertionError("the resumed run paved its section again")

    monkeypatch.setattr(plans, "section_classes", no_section)
    again = reach(puma, run=RunOn(resume=checkpoint), **options)
    assert again.volume_bounds == first.volume_bounds and again.counts == first.counts


def test_the_section_bar_moves_while_the_section_is_paved(monkeypatch, puma_cone, puma):
    """Issue 24 item 4 (a progress bar that moves during the long phases): the section of a constrained arm,
    most of the run, reports its share decided chunk by chunk on the section's bar, growing from 0 to below 1,
    before the task boxes are classified (reference: the boxes the complete run evaluated)."""
    from contextlib import contextmanager

    from workspace_sym.serial import pose

    seen = []

    @contextmanager
    def recorder(progress):
        yield lambda share, evaluated: seen.append((share, evaluated))

    monkeypatch.setattr(pose, "section_bar", recorder)
    p = reach(puma, delta=0.3, stop=StopAt(), pose=Pose(approach=(0, 0, -1),
                                                                                         cone=20))
    assert p.counts == puma_cone.counts
    shares, counts = np.array([s for s, _ in seen]), np.array([n for _, n in seen])
    assert len(seen) >= 5 and np.all(np.diff(shares) >= 0) and np.all(np.diff(counts) > 0)
    assert 0 <= shares[0] < shares[-1] <= 1 and counts[-1] < p.evaluated
