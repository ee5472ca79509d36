"""Certified workspaces of real arms against independent references (issue 24 item 3).

The UR5 (``tests/data/dh/ur5.json``, every joint a full turn) and the KUKA KR16 (rtb-data's ``kr16_2.urdf``, limits
from the file), each paved once by ``reach`` at a coarse delta with no time limit, so that every machine decides
the same boxes.

References, each named in its test:
* independent numerics: 10^6 configurations of all joints sampled within the joint limits, placed by the robot's
  own numeric position (``DHRobot.numeric(robot.position)``, not the reach model, which drops joints), chunked,
  never lie in an outer box;
* a second method: Pappus's theorem on the densely sampled section (the same 10^6 points in (rho, z) about the
  first joint's axis, found from the points themselves; each cell of side h hit by a sample turned through a
  full circle), which the proved volume bracket must hold;
* inverse kinematics at 50 digits: corners and centres of random inner boxes are reached within the limits by
  Newton's method refined with mpmath (residual below 1e-40).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from reach_checks import industrial_arm, reached_at_50_digits

from workspace_sym import StopAt
from workspace_sym.serial_workspace import ReachModel, reach

# Coarse deltas and a budget of boxes (never of seconds): the same boxes on every machine.
ARMS = {"ur5": 0.2, "kr16": 0.3}
SAMPLES, CHUNK = 1_000_000, 100_000
SECTION_CELL = 0.01            # side h of the (rho, z) cells of the Pappus reference


@functools.cache
def _arm(name):
    robot = industrial_arm(name)            # shared with test_reach_shoulder: one symbolic preparation
    return robot, reach(robot, delta=ARMS[name], stop=StopAt(max_boxes=50_000, progress=False))


def _first_axis(robot, rng):
    """The first joint's axis (a point and a unit direction), found from the points alone: the points of one
    configuration with the first joint turned by 0, 120 and 240 degrees lie on a circle about the axis (their
    centroid its centre, the normal of their plane its direction)."""
    q = rng.uniform(-1, 1, size=(1, robot.n)).repeat(3, axis=0)
    q[:, 0] += np.array([0, 2, 4]) * np.pi / 3
    p = robot.fk_numeric(q)[:, :3, 3]
    a = np.cross(p[1] - p[0], p[2] - p[0])
    return p.mean(axis=0), a / np.linalg.norm(a)


def _sampled_points(robot, seed):
    """``SAMPLES`` points of configurations uniform within the joint limits (``joint_limits``: the file's, or
    a full turn for a joint without limits), in chunks of ``CHUNK``, by the robot's own numeric position."""
    rng = np.random.default_rng(seed)
    limits = robot.joint_limits()
    position = robot.numeric(robot.position)
    for _ in range(SAMPLES // CHUNK):
        yield position(rng.uniform(limits[:, 0], limits[:, 1], size=(CHUNK, robot.n)))[:, :, 0]


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


@pytest.fixture(scope="module", params=list(ARMS))
def arm(request):
    robot, paving = _arm(request.param)
    return request.param, robot, paving


def test_million_configurations_never_in_an_outer_box_and_pappus_in_the_bracket(arm):
    """Independent numerics: 10^6 configurations within the limits (the robot's own numeric position) never lie in
    an outer box, while many lie in inner boxes (the check can see a point in a box). Float error: a point counts
    as in a box only if it is more than 1e-9 inside each face (the box shrunk by 1e-9), so a point within 1e-9 of
    a face is on the box's boundary; the float position errs by about 1e-15 here and the float limits by an ulp.
    Second method: Pappus's theorem on the section sampled by the same points, (rho, z) about the first joint's
    axis (found from the points, and checked: turning the first joint keeps rho and z to 1e-12), cells of side
    h = 0.01 hit by a sample each turned through a full circle (2 pi rho_cell h^2). Tolerance: none, the
    estimate itself must lie in the proved bracket; its own uncertainty, between the volume of the hit cells whose
    8 neighbours are all hit and that of the hit cells grown by one cell, is printed if it fails (UR5 [3.48,
    3.78] about 3.62 in the bracket [1.85, 3.83]; KR16 [19.40, 20.44] about 19.94 in [12.86, 21.28])."""
    name, robot, paving = arm
    assert paving.method == "critical" and paving.complete and len(paving.outer)
    rng = np.random.default_rng(0)
    centre, axis = _first_axis(robot, rng)
    q = rng.uniform(-np.pi, np.pi, size=(200, robot.n))
    turned = q.copy()
    turned[:, 0] += 1.0
    moved = [robot.fk_numeric(c)[:, :3, 3] - centre for c in (q, turned)]
    along = [m @ axis for m in moved]
    across = [np.linalg.norm(m - a[:, None] * axis, axis=1) for m, a in zip(moved, along)]
    assert np.allclose(along[0], along[1], atol=1e-12) and np.allclose(across[0], across[1], atol=1e-12)
    h = SECTION_CELL
    keys = []
    checked = in_inner = 0
    for p in _sampled_points(robot, seed=1):
        assert not _strictly_in_boxes(p, paving.outer).any(), name
        in_inner += _strictly_in_boxes(p, paving.inner).sum()
        checked += len(p)
        z = (p - centre) @ axis
        rho = np.linalg.norm(p - centre - z[:, None] * axis, axis=1)
        keys.append(np.unique(np.floor(rho / h).astype(np.int64) * 2**32 + np.floor(z / h).astype(np.int64)))
    assert checked == SAMPLES and in_inner > 10_000, in_inner
    key = np.unique(np.concatenate(keys))
    hit = np.stack([(key + 2**31) // 2**32, (key + 2**31) % 2**32 - 2**31], axis=1)     # (rho, z) cell indices
    cells = set(map(tuple, hit.tolist()))

    def volume(c):
        return float(np.sum(2 * np.pi * (c[:, 0] + 0.5) * h ** 3))

    around = [(i, j) for i in (-1, 0, 1) for j in (-1, 0, 1)]
    interior = np.array([c for c in hit if all((c[0] + i, c[1] + j) in cells for i, j in around)])
    grown = np.array(sorted({(c[0] + i, c[1] + j) for c in hit for i, j in around if c[0] + i >= 0}))
    reference = volume(hit)
    lo, hi = paving.measure_bounds
    assert lo <= reference <= hi, (name, lo, reference, hi, volume(interior), volume(grown))


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
