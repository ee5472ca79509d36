"""False certificates of the Orthoglide box module (issue 19 item 1): boxes drawn adversarially across the
boundary of the dextrous workspace, every verdict checked at every corner and at random points with the
eigenvalues of J J^T at 100 digits (mpmath), an independent computation from the defining matrices."""

import mpmath
import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from workspace_sym.orthoglide.certificate import box_module, numeric_dextrous, shave_boxes

SIGMA = (0.25, 4.0)
CORNERS = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=float)


def _status_100_digits(p):
    """None outside the cylinders (no leg), else whether every eigenvalue of J J^T lies in [1/4, 4]."""
    with mpmath.workdps(100):
        px, py, pz = (mpmath.mpf(float(v)) for v in p)
        e2 = [1 - py**2 - pz**2, 1 - px**2 - pz**2, 1 - px**2 - py**2]
        if min(e2) <= 0:
            return None
        etas = [mpmath.sqrt(v) for v in e2]
        A = mpmath.matrix([[etas[0], py, pz], [px, etas[1], pz], [px, py, etas[2]]])
        J = mpmath.inverse(A) * mpmath.diag(etas)
        ev, _ = mpmath.eigsy(J * J.T)
        ev = sorted(ev)
        return bool(ev[0] >= mpmath.mpf(1) / 4 and ev[-1] <= 4)


def _boundary_along(direction):
    """The first float parameter t in [0, 1] where the ray t * direction leaves the dextrous set (bisection)."""
    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if numeric_dextrous(mid * direction, SIGMA)[0] else (lo, mid)
    return lo


def _box_across_boundary(direction, shift, log_half):
    d = np.array(direction, dtype=float)
    d /= np.linalg.norm(d)
    half = 10.0 ** log_half
    centre = (_boundary_along(d) + shift * half) * d
    return np.stack([centre - half, centre + half], axis=1)


directions = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1)


@settings(max_examples=50, deadline=None, derandomize=True)
@given(direction=directions, shift=st.floats(-3, 3), log_half=st.floats(-6, -1.5),
       samples=st.lists(st.tuples(*[st.floats(0, 1)] * 3), min_size=4, max_size=4))
@example(direction=(1.0, 1.0, 1.0), shift=-1.5, log_half=-3.0, samples=[(0.5, 0.5, 0.5)] * 4)
@example(direction=(1.0, 1.0, 1.0), shift=1.5, log_half=-3.0, samples=[(0.5, 0.5, 0.5)] * 4)
@example(direction=(1.0, 0.0, 0.0), shift=0.0, log_half=-6.0, samples=[(0.0, 1.0, 0.5)] * 4)
def test_box_module_verdicts_hold_at_corners_and_points_at_100_digits(direction, shift, log_half, samples):
    """A box proved inside has every corner and every sampled point dextrous at 100 digits; a box proved
    outside has none (a point outside the cylinders has no leg and counts as outside)."""
    box = _box_across_boundary(direction, shift, log_half)
    code = int(box_module(box[None], SIGMA)[0])
    if code == 0:
        return
    points = np.vstack([box[:, 0] + CORNERS * (box[:, 1] - box[:, 0]),
                        box[:, 0] + np.array(samples) * (box[:, 1] - box[:, 0])])
    for p in points:
        status = _status_100_digits(p)
        if code == 1:
            assert status is True, (box, p)
        else:
            assert status is not True, (box, p)


def test_boxes_across_the_boundary_are_decided_both_ways():
    """The property above is not vacuous: boxes of half-width 1e-3 just inside and just outside the boundary
    along 20 rays are proved inside and outside respectively, and boxes straddling it never are."""
    rng = np.random.default_rng(3)
    codes = {-3: [], 0: [], 3: []}
    for d in rng.normal(size=(20, 3)):
        for shift in codes:
            codes[shift].append(int(box_module(_box_across_boundary(d, shift, -3)[None], SIGMA)[0]))
    assert codes[-3].count(1) >= 15 and codes[3].count(-1) >= 15
    assert set(codes[-3]) <= {0, 1} and set(codes[3]) <= {0, -1} and set(codes[0]) == {0}


def _volume(boxes):
    return float(np.prod(boxes[:, :, 1] - boxes[:, :, 0], axis=1).sum())


def _assert_tiling(box, pieces):
    """The pieces lie in the box, their interiors are pairwise disjoint, and their volumes add up to the box's."""
    assert (pieces[:, :, 0] >= box[:, 0]).all() and (pieces[:, :, 1] <= box[:, 1]).all()
    assert (pieces[:, :, 1] > pieces[:, :, 0]).all()
    lo = np.maximum(pieces[:, None, :, 0], pieces[None, :, :, 0])
    hi = np.minimum(pieces[:, None, :, 1], pieces[None, :, :, 1])
    overlap = (hi > lo).all(axis=2)
    np.fill_diagonal(overlap, False)
    assert not overlap.any()
    assert abs(_volume(pieces) - _volume(box[None])) <= 1e-12 * _volume(box[None])


@settings(max_examples=40, deadline=None, derandomize=True)
@given(direction=directions, shift=st.floats(-1.5, 1.5), log_half=st.floats(-2.5, -1.5),
       samples=st.lists(st.tuples(*[st.floats(0, 1)] * 3), min_size=3, max_size=3))
@example(direction=(1.0, 1.0, 1.0), shift=0.0, log_half=-2.0, samples=[(0.5, 0.5, 0.5)] * 3)
@example(direction=(1.0, 0.0, 0.0), shift=0.5, log_half=-1.8, samples=[(0.0, 1.0, 0.5)] * 3)
def test_shaved_slabs_tile_the_box_and_hold_at_100_digits(direction, shift, log_half, samples):
    """Shaving a box across the boundary (the last-level boxes of eps = 0.05 have half-widths 10^-1.8):
    the slabs and the rest tile the box, every corner and sampled point of a slab proved inside is dextrous
    at 100 digits, and none of a slab proved outside is."""
    box = _box_across_boundary(direction, shift, log_half)
    cut = shave_boxes(box[None], sigma=SIGMA, delta=1.0, fractions=(0.5, 0.25))
    assert len(cut.kept) == 1
    _assert_tiling(box, np.concatenate([cut.inner, cut.outer, cut.kept]))
    for slabs, expected in ((cut.inner, True), (cut.outer, False)):
        for slab in slabs:
            points = np.vstack([slab[:, 0] + CORNERS * (slab[:, 1] - slab[:, 0]),
                                slab[:, 0] + np.array(samples) * (slab[:, 1] - slab[:, 0])])
            for p in points:
                status = _status_100_digits(p)
                assert (status is True) == expected, (box, slab, p)


def test_shaving_cuts_slabs_both_ways_across_the_boundary():
    """The property above is not vacuous: on boxes of half-width 0.01 across the boundary (0.007 from their
    centre, on either side) along 40 rays, shaving proves slabs inside and slabs outside, and leaves less
    than 80 % of the volume undecided."""
    rng = np.random.default_rng(5)
    boxes = np.array([_box_across_boundary(d, s, -2)
                      for d, s in zip(rng.normal(size=(40, 3)), np.tile([-0.7, 0.7], 20))])
    cut = shave_boxes(boxes, sigma=SIGMA, delta=1.0, fractions=(0.5, 0.25))
    assert len(cut.inner) >= 10 and len(cut.outer) >= 10
    assert _volume(cut.kept) < 0.8 * _volume(boxes)
    assert abs(_volume(np.concatenate([cut.inner, cut.outer, cut.kept])) - _volume(boxes)) <= 1e-12


def test_shaving_leaves_boxes_above_delta_whole():
    """Boxes larger than delta are bisected by the paving, not shaved: they come back unchanged."""
    boxes = np.array([_box_across_boundary((1.0, 0.3, -0.2), 0.0, -1)])
    cut = shave_boxes(boxes, sigma=SIGMA, delta=0.05)
    assert len(cut.inner) == len(cut.outer) == 0
    assert np.array_equal(cut.kept, boxes)
