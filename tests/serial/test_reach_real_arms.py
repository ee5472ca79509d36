"""Certified workspaces of real arms against independent references (issue 24 item 3).

Every certifying path of ``reach`` for the industrial arms, one arm each, paved once with no time limit, so that
every machine decides the same boxes:
* a section turned through a full circle (``reach_section``): the UR5 (``tests/data/dh/ur5.json``, every joint a
  full turn, its lateral offset varying with the wrist), at a coarse delta;
* a section turned by a limited first joint (``reach_turn``): the LBR iiwa 14 (rtb-data's
  ``lbr_iiwa_14_r820.urdf``, 340 deg, its section moved by five joints once the last is dropped), at delta 0.1
  with a budget of 3000 boxes for the section
  (``StopAt(section_boxes=3000)``).  A coarser delta proves nothing inside: the Krawczyk test on their sections fails on
  the wider cells it gives (none of the iiwa's cells of 58 mm, at delta 0.4, is proved at any direction, after
  tens of seconds of failed proofs), while at delta 0.1 about two thirds of its cells of 14 mm are.  The budget, of
  boxes and never of seconds, ends the proofs at the four directions within the cells of the first direction
  (two chunks of proofs; the blocks of cells outside do not start), so that the paving takes seconds, not
  minutes; the outer boxes come from the distance from the shoulder.
The KUKA KR16 (rtb-data's ``kr16_2.urdf``, a first joint of 370 deg: full-turn path, delta 0.3) and the Panda
(``tests/data/dh/panda.json``, 332 deg: limited path, delta 0.1, 3000 boxes) took these same checks too (KR16 19.94
in [12.86, 21.28], Panda 3.42 in [0.45, 3.57], 156 inner and 4020 outer boxes, 4343 samples in inner boxes) for
another minute of the suite on paths the UR5 and the iiwa already take: ``ARMS`` keeps their settings (add them to
``PAVED`` to run them here), ``benchmarks/bench_reach_arms.py`` paves both against their reference volumes, and
tests/serial/test_reach_shoulder.py keeps the KR16's section paving and the Panda's shoulder distance.

References, each named in its test:
* independent numerics: 10^6 configurations of all joints sampled within the joint limits, placed by the robot's
  own numeric position (``DHRobot.numeric(robot.position)``, not the reach model, which drops joints), chunked,
  never lie in an outer box;
* a second method: the volume of the densely sampled section turned by the first joint (the same 10^6 points in
  (rho, z) about the first joint's axis, found from the points themselves; each cell of side h hit by a sample
  turned through the union of the arcs of the first joint's range from its samples: ``reach_checks.arcs_volume``,
  Pappus's theorem where the first joint turns a full circle), which the proved volume bracket must hold;
* inverse kinematics at 50 digits: corners and centres of random inner boxes are reached within the limits by
  Newton's method refined with mpmath (residual below 1e-40).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from reach_checks import arcs_volume, first_axis, industrial_arm, reached_at_50_digits, sampled_positions
from workspace_sym import StopAt
from workspace_sym.serial import ReachModel, reach, resolve_method
from workspace_sym.serial.model import reach_model
from workspace_sym.serial.plans import on_cells
from workspace_sym.serial.section import Turned
from workspace_sym.serial.structure import structure_of
from workspace_sym.serial.turn import limited_turn

pytestmark = pytest.mark.slow       # four industrial arms paved: a minute and more (make test-fast leaves them out)

# Deltas and budgets of boxes (never of seconds): the same boxes on every machine.  (delta, the run's budget, the
# section's budget: None for the full turns, whose sections end on their own at these deltas.)
ARMS = {"ur5": (0.2, 50_000, None), "kr16": (0.3, 50_000, None),
        "iiwa": (0.1, 200_000, 3000), "panda": (0.1, 200_000, 3000)}
SAMPLES, CHUNK = 1_000_000, 500_000
SECTION_CELL = 0.01            # side h of the (rho, z) cells of the reference volume


@functools.cache
def _arm(name):
    robot = industrial_arm(name)            # shared with test_reach_shoulder: one symbolic preparation
    delta, boxes, section = ARMS[name]
    return robot, reach(robot, delta=delta, stop=StopAt(max_boxes=boxes, section_boxes=section))


def _strictly_in_boxes(points, boxes, shrink=1e-9, g=0.25):
    """Mask of the points more than ``shrink`` inside some box (each face moved in by ``shrink``). The points
    are binned in cubes of side ``g``; a box looks only at the points of the columns of cubes (x, y) it meets,
    within the run of cubes along z it meets (contiguous in the binned order)."""
    key = np.floor(points / g).astype(np.int64)
    low = key.min(axis=0)
    dims = key.max(axis=0) - low + 1
    flat = np.ravel_multi_index((key - low).T, dims)
    order = np.argsort(flat)
    flat = flat[order]
    hit = np.zeros(len(points), dtype=bool)
    for box in boxes:
        lo, hi = box[:, 0] + shrink, box[:, 1] - shrink
        a = np.maximum(np.floor(lo / g).astype(np.int64) - low, 0)
        b = np.minimum(np.floor(hi / g).astype(np.int64) - low, dims - 1)
        if (a > b).any():
            continue
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                first, last = np.ravel_multi_index(([i, i], [j, j], [a[2], b[2]]), dims)
                rows = order[np.searchsorted(flat, first):np.searchsorted(flat, last, side="right")]
                hit[rows] |= ((points[rows] > lo) & (points[rows] < hi)).all(axis=1)
    return hit


PAVED = ["ur5", "iiwa"]             # one arm per path: see the module's docstring for the KR16 and the Panda


@pytest.fixture(scope="module", params=PAVED)
def arm(request):
    robot, paving = _arm(request.param)
    return request.param, robot, paving


def test_million_configurations_never_in_an_outer_box_and_the_sampled_volume_in_the_bracket(arm):
    """Independent numerics: 10^6 configurations within the limits (the robot's own numeric position) never lie in
    an outer box, while many lie in inner boxes (the check can see a point in a box). Float error: a point counts
    as in a box only if it is more than 1e-9 inside each face (the box shrunk by 1e-9), so a point within 1e-9 of
    a face is on the box's boundary; the float position errs by about 1e-15 here and the float limits by an ulp.
    Second method: the section sampled by the same points, (rho, z) about the first joint's axis (found from the
    points, and checked: turning the first joint keeps rho and z to 1e-12), cells of side h = 0.01 hit by a
    sample each turned through the union of the arcs ``psi - q1 + [lo, hi]`` of its samples (``arcs_volume``;
    a full circle for the UR5, whose first joint turns 360 deg: Pappus's theorem), extrapolated to cells of
    side zero, ``2 V(h) - V(2 h)`` (the hit cells overlap the boundary by about half a cell: iiwa V(h) 3.317 and
    V(2 h) 3.413, 3.222 extrapolated, against 3.230 at h = 5 mm). Tolerance: none, the estimate itself must lie in
    the proved bracket (iiwa 3.222 in [1.18, 3.311], whose upper bound the elbow's reach brought below V(h)).
    No check is vacuous: each paving has inner and outer boxes
    (iiwa 1124 inner and 3536 outer boxes in a fresh process; up to 1148 inner after other tests prepared the same
    robot object), and more than 1000 of the samples lie in inner boxes."""
    name, robot, paving = arm
    assert paving.method == "critical" and paving.complete and len(paving.outer) and len(paving.inner)
    rng = np.random.default_rng(0)
    centre, axis = first_axis(robot, rng)
    q = rng.uniform(-np.pi, np.pi, size=(200, robot.n))
    turned = q.copy()
    turned[:, 0] += 1.0
    moved = [robot.fk_numeric(c)[:, :3, 3] - centre for c in (q, turned)]
    along = [m @ axis for m in moved]
    across = [np.linalg.norm(m - a[:, None] * axis, axis=1) for m, a in zip(moved, along)]
    assert np.allclose(along[0], along[1], atol=1e-12) and np.allclose(across[0], across[1], atol=1e-12)
    first, points = [], []
    checked = in_inner = 0
    for q, p in sampled_positions(robot, SAMPLES, seed=1, chunk=CHUNK):
        assert not _strictly_in_boxes(p, paving.outer).any(), name
        in_inner += _strictly_in_boxes(p, paving.inner).sum()
        checked += len(p)
        first.append(q[:, 0])
        points.append(p)
    assert checked == SAMPLES and in_inner > 1000, in_inner
    first, points = np.concatenate(first), np.concatenate(points)
    coarse = [arcs_volume(robot, first, points, k * SECTION_CELL) for k in (1, 2)]
    reference = 2 * coarse[0] - coarse[1]           # the hit cells' overlap of the boundary, extrapolated away
    lo, hi = paving.measure_bounds
    assert lo <= reference <= hi, (name, lo, reference, hi, coarse)


def test_inner_box_points_are_reached_at_50_digits(arm):
    """Inverse kinematics at 50 digits: the centre and a corner of 5 random inner boxes (seeded) are reached
    within the joint limits by float Newton from the nearest of 20,000 sampled configurations, refined by mpmath
    ``findroot`` at 50 digits on the best-conditioned joints (the others fixed), residual below 1e-40."""
    name, robot, paving = arm
    assert len(paving.inner), name
    model = ReachModel(robot)
    rng = np.random.default_rng(2)
    q = model.random_configurations(20_000, rng)
    pos = model.position_float(q)
    for box in paving.inner[rng.integers(len(paving.inner), size=5)]:
        corner = box[np.arange(3), rng.integers(2, size=3)]
        for target in (box.mean(axis=1), corner):
            assert reached_at_50_digits(model, target, q, pos), (name, box, target)


# (the first joint turns a full circle, a limited turn proving inner boxes at every polar angle: reach_turn)
SECTION_PATHS = {"ur5": (True, False), "kr16": (True, False), "iiwa": (False, True), "panda": (False, True)}


def test_the_industrial_arms_keep_their_section_path(arm):
    """The 3-D cells take only the arms whose turned section proves no inner box (tests/serial/test_reach_turn3d.py):
    these
    arms keep the section path as before, the UR5 (and the KR16) turned a full circle, the iiwa (and the Panda) by a
    limited first joint of more than half a turn whose section moves with five joints (reach_turn).  Reference:
    their structure, read from the section (its sections prepared once, by the paving above), and the paving
    itself, whose volume bracket comes from the section's cells (the 3-D cells give none)."""
    name, robot, paving = arm
    plan, model = structure_of(robot, ()), reach_model(robot, ())
    full, limited = SECTION_PATHS[name]
    assert isinstance(plan, Turned) and plan.full is full and (limited_turn(plan, model) is not None) is limited
    assert resolve_method(robot) == "critical" and not on_cells(robot, ()) and model.k >= 5
    assert paving.volume_bounds is not None
