"""Pairs of a section map proved unreachable by the wrist point ``w = p - L a`` (workspace_sym/serial/mapsection.py:
wrist_offset, wrist_robot, cap_patches, wrist_unreachable; docs/methods.md section 9): the offset against the
tables, the cap's patches against vectors built on the cone's rim, and every claim against sampled configurations,
aimed where the claims are (a stretched arm, a wrist point whose whole workspace is a sphere)."""

from __future__ import annotations

import math
import warnings
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from reach_checks import in_any_box, industrial_arm, on_cone, sampled_pairs
from workspace_sym import reach, robots
from workspace_sym.interval.driver import RunOn
from workspace_sym.kinematics import DHJoint, DHRobot, numeric_function
from workspace_sym.serial.mapsection import cap_patches, wrist_offset, wrist_robot, wrist_unreachable
from workspace_sym.serial.reachmap import ReachMap, free_cells, reach_map, sphere_directions

R = sp.Rational


def _toy(last_a=0):
    """A turn, a shoulder of 0.4, a wrist pitch and a roll carrying the tool point 0.15 along the approach: the
    last two axes meet at the wrist point, whose workspace is the sphere of radius 0.4 about (0, 0, 0.2) (every
    point of it on its boundary).  ``last_a``: an offset of the roll axis from the pitch axis."""
    return DHRobot([DHJoint.revolute(1, d=R(1, 5), alpha=sp.pi / 2, limits=(-sp.pi, sp.pi)),
                    DHJoint.revolute(2, a=R(2, 5), limits=(-sp.pi, sp.pi)),
                    DHJoint.revolute(3, a=last_a, alpha=sp.pi / 2, limits=(-sp.pi, sp.pi)),
                    DHJoint.revolute(4, d=R(3, 20), limits=(-sp.pi, sp.pi))], name="toy wrist")


def test_the_wrist_offset_is_the_table_s_and_frees_w_of_the_last_joint():
    # Reference: the DH tables themselves (exact): the UR5's d6 (0.0823, tests/data/dh/ur5.json), the Panda's
    # d7 + tool z (0.107 + 0.103, modified DH, tests/data/dh/panda.json: the last axis is offset 0.088 from the
    # one before it, so w is the foot of their common normal), the toy's d4; the Puma's tool point is its wrist
    # centre (L = 0: nothing to gain); a toy whose last two axes are parallel has no common normal.
    ur5, panda, toy = industrial_arm("ur5"), industrial_arm("panda"), _toy()
    assert wrist_offset(ur5, ()) == ur5.joints[5].d == R(823, 10000)
    assert wrist_offset(panda, ()) == panda.joints[6].d + panda.tool[2, 3] == R(21, 100)
    assert wrist_offset(toy, ()) == R(3, 20)
    assert wrist_offset(robots.build("puma560"), ()) is None
    parallel = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=1), DHJoint.revolute(3, d=R(1, 10))])
    assert wrist_offset(parallel, ()) is None
    # w = p - L a at random configurations (floats of the two robots' own fk), and free of the last joint
    # (exactly: SymPy's derivative simplifies to zero)
    rng = np.random.default_rng(4)
    for robot in (ur5, toy):
        L = wrist_offset(robot, ())
        moved = wrist_robot(robot, L)
        assert all(sp.simplify(sp.diff(e, robot.q[-1])) == 0 for e in moved.position)
        q = rng.uniform(-math.pi, math.pi, size=(50, robot.n))
        T = numeric_function(robot.fk(), robot.q)(q)
        w = numeric_function(moved.position, robot.q)(q)[:, :, 0]
        assert np.allclose(w, T[:, :3, 3] - float(L) * T[:, :3, 2], atol=1e-12)


@settings(max_examples=300, deadline=None)
@given(st.one_of(st.sampled_from([(0, 0, 1), (0, 0, -1), (1, 0, 0), (1, 1, 1), (1e-9, 0, -1), (1, 1e-12, 0)]),
                 st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 1e-3)),
       st.one_of(st.sampled_from([1e-6, 30.0, 90.0, 179.999, 180.0]), st.floats(1e-3, 180)),
       st.sampled_from([0.0, 1 / 3, 0.5, 2 / 3, 1.0]) | st.floats(0, 1),
       st.floats(-4 * math.pi, 4 * math.pi))
@example((0, 0, 1), 180.0, 1.0, 0.0)                         # the whole sphere: -d itself
@example((1, 1, 1), 30.0, 1.0, 2 * math.pi)                  # the rim at the seam of the arcs
def test_the_cap_patches_hold_every_vector_of_the_cone(d, cone, t_frac, phi):
    # Reference: vectors built on the cone, its rim and its axis included, in another frame than the patches'
    # (cross products with another vector), so that no shared arithmetic hides an error.
    a = on_cone(d, cone, t_frac, phi)
    boxes = cap_patches(np.array([d], dtype=float), cone)[0]
    inside = ((boxes[:, :, 0] <= a) & (a <= boxes[:, :, 1])).all(axis=1)
    assert inside.any(), (d, cone, t_frac, phi, a)


def test_sampled_configurations_never_fall_in_a_wrist_proved_pair_of_the_ur5():
    # Reference: forward kinematics of 240,000 configurations (floats), a third of them stretched (the elbow
    # within 0.1 rad of straight, where the tool point is farthest and the claims are), the rest uniform: none
    # may land in a pair proved unreachable, on the UR5's grid of 0.1 with 26 directions of 30 deg.
    ur5 = industrial_arm("ur5")
    L = wrist_offset(ur5, ())
    moved = wrist_robot(ur5, L)                 # one object: its symbolic position is derived once
    W = reach(moved, delta=0.05, run=RunOn(progress=False))
    edges = tuple(np.arange(-1.0, 1.0 + 1e-9, 0.1) + (0.0 if a < 2 else 0.05) for a in range(3))
    pad = float(L) + 0.1
    w_edges = tuple(np.arange(e[0] - pad, e[-1] + pad + 0.02, 0.0125) for e in edges)
    outside = free_cells(w_edges, np.concatenate([b.reshape(-1, 3, 2) for b in (W.inner, W.boundary, W.pending)]))
    directions = sphere_directions(26)
    shape = tuple(len(e) - 1 for e in edges) + (26,)
    proved = wrist_unreachable(edges, np.ones(shape, dtype=bool), directions, 30.0, L, outside, w_edges)
    assert proved.sum() > 20_000 and (proved.any(axis=-1) & ~proved.all(axis=-1)).sum() > 100
    rng = np.random.default_rng(11)
    q = rng.uniform(-math.pi, math.pi, size=(240_000, 6))
    q[:80_000, 2] = rng.uniform(-0.1, 0.1, size=80_000)
    index, ks = sampled_pairs(ur5, edges, directions, 30.0, q)
    assert len(ks) > 400_000
    assert not proved[index[:, 0], index[:, 1], index[:, 2], ks].any()
    # the premise itself: every sampled wrist point lies in a kept box of its paving (widened by 1e-9)
    w = numeric_function(moved.position, ur5.q)(q[::8])[:, :, 0]
    kept = np.concatenate([b.reshape(-1, 3, 2) for b in (W.inner, W.boundary, W.pending)])
    assert in_any_box(w, kept, pad=1e-9).all()


def test_a_section_map_proves_pairs_unreachable_for_some_directions_and_samples_agree(tmp_path):
    # Reference: 400,000 sampled configurations of the toy arm, whose wrist point lies on a sphere (every point of
    # its workspace on its boundary: the wrist paving's outer boxes come as close to it as they can); none in a
    # pair proved unreachable, and cells with both kinds of pairs exist (before the wrist stage a cell was -1
    # for every direction or for none).
    toy = _toy()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)           # 14 cones of 30 deg do not cover the sphere
        made = reach_map(toy, delta=0.1, directions=14, cone=30, method="section")
    codes = made.codes
    mixed = (codes == -1).any(-1) & (codes != -1).any(-1)
    assert mixed.sum() > 100 and made.info["wrist_offset"] == 0.15 and made.info["wrist_pairs"] > 400
    saved = made.save(tmp_path / "toy.npz")                 # the stage's figures travel with the file
    again = ReachMap.load(saved)
    assert again.summary()["wrist_pairs"] == made.info["wrist_pairs"] and np.array_equal(again.codes, codes)
    q = np.random.default_rng(2).uniform(-math.pi, math.pi, size=(400_000, 4))
    index, ks = sampled_pairs(toy, made.edges, made.directions, made.cone, q)
    assert len(ks) > 300_000
    assert not (codes[index[:, 0], index[:, 1], index[:, 2], ks] == -1).any()


@pytest.mark.parametrize("last_a", [0, R(1, 20)])
def test_the_wrist_point_is_exact_for_any_offset(last_a):
    # Reference: a property of the construction, checked at random configurations: whatever L (here the toy's
    # and the toy with its roll axis moved 0.05 from the pitch axis, where w depends on every joint), the wrist
    # robot's tool point is p - L a, so its paving holds every w (the soundness of the stage needs no more).
    toy = _toy(last_a)
    assert wrist_offset(toy, ()) == R(3, 20)          # the foot of the common normal is o_3 either way
    q = np.random.default_rng(6).uniform(-math.pi, math.pi, size=(200, 4))
    T = numeric_function(toy.fk(), toy.q)(q)
    for L in (R(3, 20), R(1, 7), R(-2, 5)):
        w = numeric_function(wrist_robot(toy, L).position, toy.q)(q)[:, :, 0]
        assert np.allclose(w, T[:, :3, 3] - float(L) * T[:, :3, 2], atol=1e-12)


@settings(max_examples=120, deadline=None)
@given(st.sampled_from([0.05, 0.1, 0.3]), st.floats(-1, 1), st.sampled_from([1e-9, 1e-4, 0.02, 0.2]),
       st.sampled_from([-0.3, -0.05, 0.0823, 0.21, 1.0]), st.sampled_from([1.0, 30.0, 90.0, 180.0]),
       st.tuples(*[st.integers(0, 8)] * 3), st.tuples(*[st.integers(0, 1)] * 3), st.floats(0, 1),
       st.floats(0, 2 * math.pi), st.integers(0, 25))
@example(0.1, 0.0, 1e-9, 0.21, 30.0, (4, 4, 4), (0, 0, 0), 1.0, 0.0, 12)   # a corner of four cells, the rim
def test_a_tool_point_whose_wrist_point_lies_in_a_kept_box_is_never_claimed(h, shift, r, L, cone, at, face,
                                                                           t_frac, phi, k):
    # Reference: the definition, point by point: a tool point p put on a map cell's corner or face (the pieces'
    # and the cells' edges), an approach a on the cone of direction k (its rim included), and a kept box of
    # half-width r >= 1e-9 about w = p - L a (floats: the box holds the exact p - L a by far); the pair
    # (any closed cell holding p, k) must not be claimed unreachable.
    edges = tuple(shift + np.arange(10) * h for _ in range(3))
    directions = sphere_directions(26)
    a = on_cone(directions[k], cone, t_frac, phi)
    p = np.array([edges[i][at[i]] + (h / 2 if face[i] else 0.0) for i in range(3)])
    w = p - L * a
    kept = np.array([[[w[i] - r, w[i] + r] for i in range(3)]])
    pad = abs(L) + h
    w_edges = tuple(np.arange(e[0] - pad, e[-1] + pad + h, h / 2) for e in edges)
    outside = free_cells(w_edges, kept)
    shape = (9, 9, 9, 1)
    proved = wrist_unreachable(edges, np.ones(shape, dtype=bool), directions[k:k + 1], cone, sp.nsimplify(L),
                               outside, w_edges)
    cells = [[j for j in (at[i] - 1, at[i]) if 0 <= j < 9 and edges[i][j] <= p[i] <= edges[i][j + 1]]
             for i in range(3)]
    assert not any(proved[i, j, l, 0] for i in cells[0] for j in cells[1] for l in cells[2])
    if abs(L) <= 0.21 and cone <= 30:                  # short offsets and narrow cones: claims elsewhere
        assert proved.sum() > 0


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(*[st.floats(-1, 1)] * 3, st.sampled_from([0.0, 1e-12, 0.1, 0.5])), min_size=1,
                max_size=5), st.integers(0, 4), st.floats(0, 1), st.floats(0, 1), st.floats(0, 1))
def test_free_cells_never_hold_a_point_of_a_box(boxes, which, u, v, w):
    # Reference: points of the boxes (their corners and faces included: u, v, w of 0 or 1), located on the grid by
    # comparisons: no closed cell holding one is free.
    B = np.array([[[c - s, c + s] for c in centre] for *centre, s in boxes])
    edges = tuple(np.linspace(-1.2, 1.2, 13) for _ in range(3))
    free = free_cells(edges, B)
    box = B[which % len(B)]
    point = box[:, 0] + np.array([u, v, w]) * (box[:, 1] - box[:, 0])
    point = np.clip(point, box[:, 0], box[:, 1])
    cells = [[j for j in range(12) if e[j] <= x <= e[j + 1]] for e, x in zip(edges, point)]
    assume(all(cells))                                   # a point beyond the grid is in no cell
    assert not any(free[i, j, l] for i in cells[0] for j in cells[1] for l in cells[2])


def _rational_unit(t):
    """A unit vector of rational coordinates near the float unit vector ``t``: the inverse stereographic image
    of a rational point near ``t``'s projection (from the pole farther from ``t``)."""
    t = np.asarray(t, dtype=float) / np.linalg.norm(t)
    pole = 1 if t[2] < 0 else -1                     # project from (0, 0, pole)
    s = Fraction(float(t[0] / (1 - pole * t[2]))).limit_denominator(10**7)
    u = Fraction(float(t[1] / (1 - pole * t[2]))).limit_denominator(10**7)
    n = s * s + u * u
    return (2 * s / (n + 1), 2 * u / (n + 1), pole * (n - 1) / (n + 1))


def test_wrist_claims_hold_in_exact_rationals_at_cell_corners_and_the_cone_s_rim():
    # Reference: exact rational arithmetic (fractions), not the floats of the stage.  For claims of the toy arm
    # (its wrist point on a sphere: every kept box on the boundary), tool points p at the corners, the face
    # centres and random rational points of claimed cells, approaches a with rational coordinates and a . a = 1
    # exactly, within the cone (a . d >= |d| c, c a rational above cos 30 deg) and near its rim: w = p - L a,
    # computed exactly, lies in none of the kept boxes (each bound read as the rational it is).
    toy = _toy()
    L = wrist_offset(toy, ())
    W = reach(wrist_robot(toy, L), delta=0.05, run=RunOn(progress=False))
    kept = np.concatenate([b.reshape(-1, 3, 2) for b in (W.inner, W.boundary, W.pending)])
    edges = tuple(np.arange(-0.7, 0.75, 0.1) + (0.2 if a == 2 else 0.0) for a in range(3))
    pad = float(L) + 0.1
    w_edges = tuple(np.arange(e[0] - pad, e[-1] + pad + 0.02, 0.0125) for e in edges)
    directions = sphere_directions(14)
    shape = tuple(len(e) - 1 for e in edges) + (14,)
    proved = wrist_unreachable(edges, np.ones(shape, dtype=bool), directions, 30.0, L, free_cells(w_edges, kept),
                               w_edges)
    pairs = np.argwhere(proved)
    assert len(pairs) > 2000
    cos_c = Fraction(math.cos(math.radians(30))) + Fraction(1, 10**12)        # above cos 30 deg
    rng = np.random.default_rng(8)
    lo_kept, hi_kept = kept[:, :, 0], kept[:, :, 1]
    checked = 0
    for i, j, l, k in pairs[rng.choice(len(pairs), size=150, replace=False)]:
        cell = [(Fraction(edges[a][c]), Fraction(edges[a][c + 1])) for a, c in enumerate((i, j, l))]
        points = [tuple(cell[a][b] for a, b in enumerate(bits)) for bits in ((0, 0, 0), (1, 1, 1), (0, 1, 0))]
        points.append(tuple((x0 + x1) / 2 for x0, x1 in cell))
        points.append(tuple(x0 + (x1 - x0) * Fraction(int(rng.integers(0, 1000)), 1000) for x0, x1 in cell))
        d = [Fraction(float(x)) for x in directions[k]]
        norm2 = sum(x * x for x in d)
        for t_frac, phi in ((0.0, 0.0), (0.999, rng.uniform(0, 2 * math.pi)), (0.999, rng.uniform(0, 2 * math.pi))):
            a = _rational_unit(on_cone(directions[k], 30.0, t_frac, phi))
            assert sum(x * x for x in a) == 1
            dot = sum(x * y for x, y in zip(a, d))
            if not (dot > 0 and dot * dot >= norm2 * cos_c * cos_c):
                continue                                # rounded out of the cone: not a point of the claim
            for p in points:
                w = [p[m] - L * a[m] for m in range(3)]
                wf = np.array([float(x) for x in w])
                near = np.nonzero(((lo_kept <= wf + 1e-9) & (wf - 1e-9 <= hi_kept)).all(axis=1))[0]
                for b in near:                          # exact: w is in no kept box
                    assert not all(Fraction(lo_kept[b, m]) <= w[m] <= Fraction(hi_kept[b, m]) for m in range(3))
                checked += 1
    assert checked > 1000
