"""Arms turned by a limited first joint whose section proves no inner box go to the 3-D critical method (issue 24).

A section turned by a first joint limited to less than a period (``reach_section.Turned``: a base transform, modified
DH or a lateral offset varying with the other joints) proves inner boxes only for a section moved by three joints or
more and a turn of half a circle or more (``reach_turn``).  Otherwise the section path proves outer boxes only; such
arms moved by at most ``Tuning.cells_max_joints`` joints are paved by the critical method in space instead.  Three small
arms of the kinds of the issue, paved at a coarse delta (a budget of boxes, never of seconds):

* an elbow arm on a pedestal (a base transform), its first joint within +-100 deg (a two-joint section);
* an elbow arm whose third axis is skew to the second (the lateral offset varies with q2, q3), +-100 deg;
* a modified-DH arm whose first joint turns +-60 deg, less than half a turn.

References, each named in its test: the section path (what ``reach`` gave before) proves no inner box on them;
10^5 configurations within the limits placed by the robot's own numeric position never lie in an outer box;
corners and centres of inner boxes are reached within the limits by inverse kinematics at 50 digits; the proved
volume bracket holds the sampled volume of the section turned through the arcs of the first joint's range
(``reach_checks.sampled_arcs_volume``, computed from the positions alone).
"""

from __future__ import annotations

import functools
import itertools

import numpy as np
import pytest
import sympy as sp

import workspace_sym.interval.image as image
from reach_checks import reached_at_50_digits, sampled_arcs_volume, sampled_positions
from workspace_sym import RunOn, StopAt
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial import reach, resolve_method
from workspace_sym.serial.model import reach_model
from workspace_sym.serial.plans import on_cells
from workspace_sym.serial.section import Turned
from workspace_sym.serial.structure import Revolved, structure_of
from workspace_sym.serial.tuning import DEFAULT
from workspace_sym.serial.turn import limited_turn

HALF, FIFTH = sp.Rational(1, 2), sp.Rational(1, 5)
STOP = StopAt(max_boxes=200_000)
DELTA = 0.25


def _lift(x=0, z=0):
    return sp.Matrix([[1, 0, 0, x], [0, 1, 0, 0], [0, 0, 1, z], [0, 0, 0, 1]])


ARMS = {
    "pedestal": DHRobot([DHJoint.revolute(1, alpha=sp.pi / 2, limits=(-5 * sp.pi / 9, 5 * sp.pi / 9)),
                         DHJoint.revolute(2, a=HALF, limits=(-sp.pi / 2, sp.pi / 2)),
                         DHJoint.revolute(3, a=2 * FIFTH, limits=(-2 * sp.pi / 3, 2 * sp.pi / 3))],
                        name="elbow on a pedestal", base=_lift(x=sp.Rational(1, 10), z=FIFTH)),
    "skew": DHRobot([DHJoint.revolute(1, alpha=sp.pi / 2, limits=(-5 * sp.pi / 9, 5 * sp.pi / 9)),
                     DHJoint.revolute(2, a=HALF, alpha=sp.pi / 2, limits=(-sp.pi / 2, sp.pi / 2)),
                     DHJoint.revolute(3, a=2 * FIFTH, limits=(-2 * sp.pi / 3, 2 * sp.pi / 3))], name="skew elbow"),
    "short turn": DHRobot([DHJoint.revolute(1, d=FIFTH, limits=(-sp.pi / 3, sp.pi / 3)),
                           DHJoint.revolute(2, alpha=sp.pi / 2, d=sp.Rational(1, 10), limits=(-sp.pi / 2, sp.pi / 2)),
                           DHJoint.revolute(3, a=HALF, limits=(-2 * sp.pi / 3, 2 * sp.pi / 3))],
                          convention="modified", tool=_lift(x=2 * FIFTH), name="short turn"),
}


@pytest.fixture(scope="module", params=list(ARMS))
def arm(request):
    robot = ARMS[request.param]
    return robot, reach(robot, delta=DELTA, stop=STOP)


@functools.cache
def _section_path(robot):
    """``reach`` on the section path (what it was before the 3-D cells took these arms), once per arm (the
    pedestal's is the reference of two tests)."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr("workspace_sym.serial.plans.on_cells", lambda robot, values, stored=False, tuning=None: False)
        return reach(robot, delta=DELTA, stop=STOP)


def test_the_section_path_proves_no_inner_box_and_the_3d_cells_do(arm):
    """The reproduction: each arm is a section turned by a limited first joint (not a full turn) with no covering
    pair of directions (a two-joint section, or +-60 deg), so the section path ends with outer boxes and no inner
    box; 'auto' and 'critical' pave it on 3-D cells instead, complete, with inner boxes."""
    robot, paving = arm
    plan, model = structure_of(robot, ()), reach_model(robot, ())
    assert isinstance(plan, Turned) and not plan.full and limited_turn(plan, model) is None
    assert on_cells(robot, ()) and not on_cells(robot, (), stored=True)
    assert resolve_method(robot) == resolve_method(robot, "critical") == "critical"
    before = _section_path(robot)
    assert before.complete and len(before.outer) > 0 and len(before.inner) == 0
    assert paving.method == "critical" and paving.complete and len(paving.inner) > 0 and len(paving.outer) > 0
    again = reach(robot, delta=DELTA, stop=STOP, method="critical")
    assert again.counts == paving.counts and again.measure_bounds == paving.measure_bounds


def _in_closed_boxes(points, boxes):
    hit = np.zeros(len(points), dtype=bool)
    for box in boxes:
        hit |= ((points >= box[:, 0]) & (points <= box[:, 1])).all(axis=1)
    return hit


def test_sampled_configurations_miss_every_outer_box_and_the_sampled_volume_is_in_the_bracket(arm):
    """Independent numerics: 10^5 configurations of all joints within the limits, placed by the robot's own numeric
    position, never lie in a closed outer box; the volume of the sampled section turned through the arcs of the
    first joint's range (from the positions alone, cells of 0.02) lies in the proved bracket."""
    robot, paving = arm
    _, points = next(sampled_positions(robot, 100_000, seed=7))
    assert not _in_closed_boxes(points, paving.outer).any()
    lo, hi = paving.measure_bounds
    volume = sampled_arcs_volume(robot, 100_000, 0.02, seed=8)
    assert 0 < lo <= volume <= hi, (lo, volume, hi)


def test_inner_boxes_are_reached_at_50_digits(arm):
    """Inverse kinematics at 50 digits: the corners and the centre of up to 6 inner boxes spread over the list are
    reached within the limits (residual below 1e-40), from sampled seeds."""
    robot, paving = arm
    model = reach_model(robot, ())
    q = model.random_configurations(40_000, np.random.default_rng(5))
    pos = model.position_float(q)
    inner = paving.inner
    for box in inner[np.unique(np.linspace(0, len(inner) - 1, 6).astype(int))]:
        for point in [*itertools.product(*box), box.mean(axis=1)]:
            assert reached_at_50_digits(model, np.array(point), q, pos), (box.tolist(), point)


def test_storage_and_a_cover_too_large_keep_the_section_path(monkeypatch, tmp_path):
    """Storage options keep the section path, which stores its boxes (as before; never refused), under 'auto' and
    'critical'; a 3-D cover too large (raised by the 3-D cells alone: the section's own cover is smaller) falls back
    to the section path too (the same counts as the section path), under both methods."""
    robot = ARMS["pedestal"]
    before = _section_path(robot)
    for method in ("auto", "critical"):
        stored = reach(robot, delta=DELTA, stop=STOP, method=method, run=RunOn(max_memory="2GB"))
        assert stored.method == "critical" and stored.counts == before.counts
    def too_large(*args, **options):
        raise image.CoverTooLarge("the critical sets of 27 faces need more than 4000000 joint boxes")

    monkeypatch.setattr("workspace_sym.serial.plans.CellsPlan.pave", too_large)    # the 3-D cover only
    for method in ("auto", "critical"):
        fallback = reach(robot, delta=DELTA, stop=STOP, method=method)
        assert fallback.method == "critical" and fallback.counts == before.counts


def test_the_rule_counts_the_joints_that_move_the_position(glass, puma):
    """Up to Tuning.cells_max_joints moving joints (three: a two-joint section turned +-60 deg) the 3-D cells take
    the arm; one more joint moving the point (four: a three-joint section, the 3-D cover ten times the section's
    time) keeps the section path; the constant-offset arms of the catalog (glass arm, Puma: ``Revolved``, whose
    limited turn proves inner boxes) keep theirs.  The UR5, KR16, LBR iiwa and Panda:
    tests/serial/test_reach_real_arms.py
    (their sections are prepared there)."""
    rows = [DHJoint.revolute(1, alpha=sp.pi / 2, limits=(-sp.pi / 3, sp.pi / 3)),
            DHJoint.revolute(2, a=HALF, limits=(-sp.pi / 2, sp.pi / 2)),
            DHJoint.revolute(3, a=2 * FIFTH, limits=(-2 * sp.pi / 3, 2 * sp.pi / 3)),
            DHJoint.revolute(4, a=FIFTH, limits=(-sp.pi / 2, sp.pi / 2))]
    three = DHRobot(rows[:3], name="three joints", base=_lift(z=FIFTH))
    four = DHRobot(rows, name="four joints", base=_lift(z=FIFTH))
    for robot, k, cells in ((three, DEFAULT.cells_max_joints, True), (four, DEFAULT.cells_max_joints + 1, False)):
        plan, model = structure_of(robot, ()), reach_model(robot, ())
        assert isinstance(plan, Turned) and not plan.full and limited_turn(plan, model) is None and model.k == k
        assert on_cells(robot, ()) is cells and resolve_method(robot) == "critical"
    for robot in (glass, puma):                 # the session's objects: their sections are prepared once
        assert isinstance(structure_of(robot, ()), Revolved) and not on_cells(robot, ())
        assert resolve_method(robot) == "critical"
