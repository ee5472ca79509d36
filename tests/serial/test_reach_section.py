"""Arms turned by their first joint with a lateral offset that varies (workspace_sym.reach_section, issue 24).

References, each named in its test:
* a second method: Pappus's theorem on a densely sampled section (10^6 configurations of the other joints
  rasterised in (rho, z), each hit cell turned through a full circle), which the proved bracket must hold;
* independent numerics: random configurations (vectorised) never land in an outer box, and points drawn in
  inner boxes are reached within the limits by an inverse kinematics refined at 50 digits;
* invariance: a rigid base transform moves the workspace rigidly, so the bracket with a base holds the same
  reference volume.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from reach_checks import (
    agrees_with_shell,
    check_sampled_and_reached,
    in_any_box,
    offset_arm,
    pappus_volume,
    paved_alike_twice,
    reached_at_50_digits,
    shell_arm,
)
from workspace_sym import StopAt
from workspace_sym.errors import InvalidParameterError, JointLimitError
from workspace_sym.interval.image import CellGrid
from workspace_sym.interval.verdict import INSIDE as INNER
from workspace_sym.interval.verdict import OUTSIDE as OUTER
from workspace_sym.interval.verdict import UNDECIDED
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial import ReachModel, reach
from workspace_sym.serial.plans import on_cells
from workspace_sym.serial.section import RadialMap, Turned, section_bar, section_paving, turned_volume
from workspace_sym.serial.structure import structure_of
from workspace_sym.serial.tuning import Tuning
from workspace_sym.serial.turn import limited_turn
from workspace_sym.transforms import rot_x, translation

R = sp.Rational
def test_offset_arm_takes_the_cylindrical_section():
    """The lateral offset of the offset arm varies (the constant-offset section does not fit): the section
    is (rho, z) of theta2, theta3 (exact expressions), and with a rotated and shifted base too."""
    plan = structure_of(offset_arm(), ())
    assert isinstance(plan, Turned) and plan.full and plan.inverse is None
    assert [str(v) for v in plan.section.variables] == ["theta2", "theta3"]
    base = rot_x(sp.pi / 2) * translation(R(1, 10), R(-1, 5), R(3, 10))
    moved = structure_of(offset_arm(base=base), ())
    assert isinstance(moved, Turned) and moved.inverse is not None
    assert [str(v) for v in moved.section.variables] == ["theta2", "theta3"]


@functools.cache
def _offset_arm_pappus():
    """Pappus's volume of the offset arm's section sampled at 4 10^5 configurations (cells of 0.006), once for
    both bases (the reference is the arm without one)."""
    return pappus_volume(offset_arm(), n=400_000, h=0.006)


@functools.cache
def _wrist_pappus(robot):
    """Pappus's volume of the wrist arm's section sampled at 4 10^5 configurations (cells of 0.01), once for the
    free and the budgeted paving of the same arm."""
    return pappus_volume(robot, n=400_000, h=0.01)


@pytest.mark.parametrize("base", [None, rot_x(sp.pi / 2) * translation(R(1, 10), R(-1, 5), R(3, 10))])
def test_offset_arm_bracket_holds_pappus_and_sampled_points(base):
    """Second method: the bracket holds Pappus's volume of the sampled section (the same with a rigid base);
    independent numerics: 10^5 configurations never in an outer box, inner points reached at 50 digits."""
    robot = offset_arm(base=base)
    volume = _offset_arm_pappus()
    paving = reach(robot, delta=0.1)
    lo, hi = paving.measure_bounds
    assert paving.method == "critical" and paving.complete
    assert lo <= volume <= hi, (lo, volume, hi)
    assert (hi - lo) / hi < 0.6
    # Two proved brackets, each holding the reference: the boxes' and the section's by Pappus (a key added to
    # the JSON, measure_bounds their intersection).
    (blo, bhi), (vlo, vhi) = paving.box_measure_bounds, paving.volume_bounds
    assert blo <= volume <= bhi and vlo <= volume <= vhi
    assert (lo, hi) == (max(blo, vlo), min(bhi, vhi)) and vhi - vlo < bhi - blo
    out = paving.to_dict()
    assert out["volume_bounds"] == [vlo, vhi] and out["box_measure_bounds"] == [blo, bhi]
    assert out["measure_bounds"] == [lo, hi]
    check_sampled_and_reached(robot, paving, samples=30_000, seed=3)


@pytest.fixture(scope="module")
def wrist_paving():
    """The offset arm with a wrist paved at delta 0.25, every stage of its section to its end."""
    robot = offset_arm(wrist=True)
    return robot, reach(robot, delta=0.25)


def test_three_joint_section_is_paved_by_blocks(wrist_paving):
    """A section moved by three joints (the offset arm with a wrist) is paved by blocks of cells carrying
    joint boxes: sampled configurations never land in an outer box; inner points reached at 50 digits;
    the bracket holds Pappus's volume."""
    robot, paving = wrist_paving
    plan = structure_of(robot, ())
    assert isinstance(plan, Turned) and plan.section.k == 3
    lo, hi = paving.measure_bounds
    volume = _wrist_pappus(robot)
    assert lo <= volume <= hi, (lo, volume, hi)
    assert lo > 0 and len(paving.outer)
    model = ReachModel(robot)
    rng = np.random.default_rng(4)
    q = model.random_configurations(30_000, rng)
    pos = model.position_float(q)
    assert not in_any_box(pos, paving.outer).any()
    for box in paving.inner[rng.integers(len(paving.inner), size=3)]:
        assert reached_at_50_digits(model, rng.uniform(box[:, 0], box[:, 1]), q, pos), box


def test_a_budget_of_boxes_stops_the_section_at_the_same_cells_on_every_run(wrist_paving):
    """``StopAt(section_boxes=5000)``: the section of the offset arm with a wrist stops once 5000 of its boxes
    are evaluated (the stage under way ends its chunk), on the same cells every run (no clock: two runs give the
    same boxes), fewer than the 9220 of its stages run to their ends; what it decided is still sound: sampled
    configurations never in an outer box, inner points reached at 50 digits (independent numerics), the bracket
    holds Pappus's volume of the sampled section (second method).  A budget that is not a whole number of at
    least 1 is refused by name."""
    robot, free = wrist_paving
    cut = paved_alike_twice(robot, 0.25, StopAt(section_boxes=5000))
    assert cut.complete and 0 < len(cut.inner) < len(free.inner) and len(cut.outer)
    lo, hi = cut.measure_bounds
    assert lo < free.measure_bounds[0] and lo <= _wrist_pappus(robot) <= hi
    check_sampled_and_reached(robot, cut, samples=30_000, seed=12)
    for bad in (0, 2.5, True):
        with pytest.raises(InvalidParameterError, match="section_boxes"):
            StopAt(section_boxes=bad)


# The edges are pinned (an example's cost is mostly its arm's symbolic derivation and plan, not its paving, so each
# one counts): a full turn with a zero third link (the point on joint 3's axis), a full turn given as limits with an
# ordinary link (inner boxes), far less than a full turn with a tiny link (outer boxes only) and with a long one
# (inner boxes of the limited turn).  One draw on top; `make explore` hunts the rest of the grid (a hair short of a
# full turn among them).
@settings(max_examples=1, deadline=None, derandomize=True)
@given(first=st.sampled_from([None, (-sp.pi, sp.pi), (-R(314, 100), R(314, 100)), (-1, 2)]),
       a3=st.sampled_from([R(0), R(1, 100), R(2, 5), R(1, 2)]))
@example(first=None, a3=R(0))
@example(first=(-sp.pi, sp.pi), a3=R(2, 5))
@example(first=(-1, 2), a3=R(1, 100))
@example(first=(-1, 2), a3=R(1, 2))
def test_edges_never_give_a_wrong_box(first, a3):
    """Edges: a first joint turning a full turn, a hair short of it, or far less (a two-joint section turned less
    than a full turn proves no inner box: the arm, moved by three joints, is paved on 3-D cells instead, and by the
    section with outer boxes only where the point is on joint 3's axis); a zero or tiny third link (joints 2 and 3
    coaxial in effect, the point on joint 3's axis).  Property: sampled configurations never land in an outer box,
    inner points are reached."""
    robot = offset_arm(first=first, a3=a3)
    paving = reach(robot, delta=0.2)
    plan = structure_of(robot, ())
    model = ReachModel(robot)
    rng = np.random.default_rng(7)
    q = model.random_configurations(30_000, rng)
    pos = model.position_float(q)
    assert not in_any_box(pos, paving.outer).any()
    if isinstance(plan, Turned) and not plan.full and limited_turn(plan, model) is None:
        assert on_cells(robot, ()) is (model.k == 3) and paving.volume_bounds is None
        if model.k < 3:
            assert not len(paving.inner)                # the section proves outer boxes only
    for box in paving.inner[rng.integers(len(paving.inner), size=2)] if len(paving.inner) else []:
        assert reached_at_50_digits(model, rng.uniform(box[:, 0], box[:, 1]), q, pos), box


def test_unbounded_prismatic_joint_is_refused_by_name():
    """Bad input: a prismatic joint without limits after a turning first joint is named."""
    robot = DHRobot([DHJoint.revolute(1, d=R(3, 10), alpha=sp.pi / 2), DHJoint.prismatic(2, alpha=sp.pi / 2)])
    with pytest.raises(JointLimitError, match=r"joint 2 \(d2\) is prismatic"):
        reach(robot, delta=0.1)


def test_blocks_stage_keeps_to_its_share_of_the_time_left():
    """With no time left for it, the blocks stage is skipped and the section still ends normally: without the
    shoulder's distance bound (the map rebuilt without it), no cell is proved outside, whatever the machine's
    speed."""
    plan = structure_of(shell_arm(), ())
    image = RadialMap(plan.section.square, plan.section.lateral)
    grid, classes, _, stopped, _ = section_paving(image, 0.1, depth=1, seconds_left=lambda: 0.0)
    assert stopped == "" and not (classes == OUTER).any()


def test_turned_volume_holds_the_exact_spherical_shell():
    """Exact closed form: the section's Pappus bracket holds 4/3 pi (R^3 - r^3) of the shell arm (decided
    exactly by SymPy), and every cell and every piece of a cell agrees with the annulus in exact rationals
    (:func:`agrees_with_shell`).  The section's progress (share of cells decided) only grows."""
    plan = structure_of(shell_arm(), ())
    assert isinstance(plan, Turned) and plan.full and plan.section.k == 3
    shares = []
    # Cells in up to 16 pieces; a budget of boxes, not of seconds, so every machine classifies the same cells.
    grid, classes, _, stopped, pieces = section_paving(plan.section, 0.05, tuning=Tuning(section_pairs=4000), depth=2,
                                                       budget=lambda count, ahead=0.0: "enough" if count > 6000 else "",
                                                       show=lambda share, count: shares.append(share))
    assert stopped in ("", "enough") and shares == sorted(shares) and shares[-1] > 0
    lo, hi = turned_volume(grid, classes, pieces)
    r, big = R(3, 10), R(7, 10)
    assert sp.Rational(lo) <= 4 * sp.pi / 3 * (big ** 3 - r ** 3) <= sp.Rational(hi)
    assert (classes == INNER).any() and (classes == OUTER).any()
    e0, e1 = ([sp.Rational(float(v)) for v in e] for e in grid.edges)
    for (i, j), kind in np.ndenumerate(classes):
        if kind != UNDECIDED:
            assert agrees_with_shell(e0[i], e0[i + 1], e1[j], e1[j + 1], kind), (i, j, kind)
    for kind, rects in ((INNER, pieces.inner), (OUTER, pieces.outer)):
        for (r0, r1), (z0, z1) in rects:
            assert agrees_with_shell(*(sp.Rational(float(v)) for v in (r0, r1, z0, z1)), kind), (r0, r1, z0, z1)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3), st.sampled_from([INNER, OUTER, UNDECIDED])),
                max_size=12),
       st.sampled_from([1.0, 0.1, 1e-3, 3.0]), st.sampled_from([0.0, -0.05, 0.3, 1e6]))
def test_turned_volume_brackets_the_exact_solid(cells, width, shift):
    """Exact rationals: the bracket holds pi times the exact sum of (r1^2 - r0^2)(z1 - z0) over the inner
    cells (lower) and over the inner and undecided cells (upper), rho clipped at 0 (edges: cells across the
    axis, widths that are no binary fractions, far from the origin)."""
    grid = CellGrid(np.array([[shift, shift + 2 * width], [shift, shift + 2 * width]]), width)
    classes = np.full(grid.shape, OUTER, dtype=np.int8)
    for i, j, kind in cells:
        classes[i, j] = kind
    lo, hi = turned_volume(grid, classes)
    e0, e1 = ([sp.Rational(float(v)) for v in e] for e in grid.edges)

    def exact(kinds):
        return sp.pi * sum(((max(e0[i + 1], 0) ** 2 - max(e0[i], 0) ** 2) * (e1[j + 1] - e1[j])
                            for (i, j), k in np.ndenumerate(classes) if k in kinds), sp.Integer(0))

    assert sp.Rational(lo) <= exact({INNER}) and exact({INNER, UNDECIDED}) <= sp.Rational(hi)
    assert hi - lo <= float(exact({UNDECIDED})) * (1 + 1e-12) + 1e-9 * (1 + abs(hi))


def test_section_bar_draws_the_share_of_cells(capsys):
    """The section's progress bar (tqdm through workspace_sym.progress) shows the share of cells decided."""
    with section_bar(True) as show:
        show(0.25, 10)
        show(0.75, 30)
    err = capsys.readouterr().err
    assert "of the cells decided" in err and "75.0%" in err

