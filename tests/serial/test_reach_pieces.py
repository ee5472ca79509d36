"""Pieces of the undecided cells of a turned section (workspace_sym.reach_section, stage 4 of section_paving).

The cells a whole proof cannot decide (near the section's boundary, near singular curves) are halved along both
axes, level after level; each piece is proved inside (Krawczyk) or outside (the shoulder's distance bound) on its
own, and the Pappus bracket counts the proved pieces.

References, each named in its test:
* exact closed form: the shell arm's section is an annulus of radii 3/10 and 7/10 (SymPy rationals): every piece
  agrees with it, and the bracket holds 4/3 pi (R^3 - r^3);
* independent numerics: 10^5 configurations of the UR5 never land in an outer piece, and random points of inner
  pieces are reached within the limits by an inverse kinematics refined at 50 digits;
* a second method: Pappus's theorem on the UR5's section sampled at 10^6 configurations;
* exact rationals: the volume bracket with pieces against pi times the exact sums of the rectangles.
"""

from __future__ import annotations

import functools

import numpy as np
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from reach_checks import agrees_with_shell, in_any_box, industrial_arm, reached_at_50_digits, shell_arm
from workspace_sym.interval.image import CellGrid
from workspace_sym.interval.search import split_every_axis
from workspace_sym.interval.verdict import INSIDE as INNER
from workspace_sym.interval.verdict import OUTSIDE as OUTER
from workspace_sym.interval.verdict import UNDECIDED
from workspace_sym.serial import ReachModel
from workspace_sym.serial.section import Pieces, section_paving, turned_volume
from workspace_sym.serial.structure import structure_of
from workspace_sym.serial.tuning import Tuning

R = sp.Rational


@functools.cache
def _shell_plan():
    return structure_of(shell_arm(), ())


def _owners(grid, rects):
    """Cell index of each rectangle (its centre's cell) and whether it lies in that cell."""
    centre = rects.mean(axis=2)
    first, _ = grid.span(np.repeat(centre[:, :, None], 2, axis=2))
    cells = grid.cells(first)
    inside = (rects[:, :, 0] >= cells[:, :, 0]).all(axis=1) & (rects[:, :, 1] <= cells[:, :, 1]).all(axis=1)
    return first, inside


def _disjoint(rects):
    """No two rectangles share an interior point (pieces of one quadtree: nested or disjoint, never nested)."""
    for k in range(len(rects)):
        lo = np.maximum(rects[k, :, 0], rects[k + 1:, :, 0])
        hi = np.minimum(rects[k, :, 1], rects[k + 1:, :, 1])
        if ((hi > lo).all(axis=1)).any():
            return False
    return True


def test_pieces_of_the_shell_lie_in_the_exact_annulus():
    """Exact closed form: with cells too wide for whole proofs near the circles, the pieces decide part of the
    undecided cells; every piece agrees with the annulus in exact rationals, lies in an undecided cell, no two
    overlap, and the bracket with them is narrower and still holds 4/3 pi (R^3 - r^3)."""
    plan = _shell_plan()
    grid, classes, _, stopped, pieces = section_paving(plan.section, 0.08, tuning=Tuning(section_pairs=4000), depth=2)
    assert stopped == "" and len(pieces.inner) and len(pieces.outer)
    for kind, rects in ((INNER, pieces.inner), (OUTER, pieces.outer)):
        for (r0, r1), (z0, z1) in rects:
            assert agrees_with_shell(*(R(float(v)) for v in (r0, r1, z0, z1)), kind), (kind, r0, r1, z0, z1)
    both = np.concatenate([pieces.inner, pieces.outer])
    cells, within = _owners(grid, both)
    assert within.all() and np.all(classes[tuple(cells.T)] == UNDECIDED)
    assert _disjoint(both)
    lo, hi = turned_volume(grid, classes, pieces)
    whole_lo, whole_hi = turned_volume(grid, classes)
    exact = 4 * sp.pi / 3 * (R(7, 10) ** 3 - R(3, 10) ** 3)
    assert R(lo) <= exact <= R(hi)
    assert whole_lo < lo and hi < whole_hi


def test_pieces_of_the_ur5_are_sound():
    """Independent numerics on the UR5 (every joint +-180 deg; cells of width 0.08 halved twice): 10^5 sampled
    configurations never land in an outer piece (nor an outer cell), random points of six inner pieces (a random
    polar angle) are reached at 50 digits; second method: the bracket, narrower with the pieces, holds Pappus's
    volume of the section sampled at 10^6 configurations (cells of side 0.008)."""
    robot = industrial_arm("ur5")
    image = structure_of(robot, ()).section
    # No blocks of cells (no time left for them): the cells and pieces proved from samples and the shoulder bound.
    grid, classes, _, stopped, pieces = section_paving(image, 0.08, depth=2, seconds_left=lambda: 0.0)
    assert stopped == "" and len(pieces.inner) > 100 and len(pieces.outer) > 10
    rng = np.random.default_rng(11)
    p = image.position_float(image.random_configurations(100_000, rng))
    first, _ = grid.span(np.repeat(p[:, :, None], 2, axis=2))
    assert not np.any(classes[tuple(first.T)] == OUTER)
    for k in range(0, len(pieces.outer), 64):
        assert not in_any_box(p, pieces.outer[k:k + 64]).any()
    model = ReachModel(robot)
    q = model.random_configurations(30_000, rng)
    pos = model.position_float(q)
    for (r0, r1), (z0, z1) in pieces.inner[rng.choice(len(pieces.inner), size=6, replace=False)]:
        rho, z, psi = rng.uniform(r0, r1), rng.uniform(z0, z1), rng.uniform(-np.pi, np.pi)
        assert reached_at_50_digits(model, np.array([rho * np.cos(psi), rho * np.sin(psi), z]), q, pos)
    h = 0.008
    sampled = image.position_float(image.random_configurations(1_000_000, np.random.default_rng(3)))
    # the hit cells (i, j) as one integer each (a 1-D unique is several times cheaper than the rows' unique)
    i, j = np.floor(sampled / h).astype(np.int64).T
    span = j.max() - j.min() + 1
    rows = np.unique((i - i.min()) * span + (j - j.min())) // span + i.min()
    volume = float(np.sum(2 * np.pi * (rows + 0.5) * h ** 3))
    lo, hi = turned_volume(grid, classes, pieces)
    whole_lo, whole_hi = turned_volume(grid, classes)
    assert lo <= volume <= hi, (lo, volume, hi)
    assert whole_lo < lo and hi < whole_hi


@settings(max_examples=25, deadline=None, derandomize=True)
@given(centre=st.tuples(st.sampled_from([0.0, 0.3, -0.25]), st.sampled_from([0.0, 0.1, 1e-9])),
       bound=st.sampled_from([0.0, 0.01, 0.09, 0.5, 4.0]), width=st.sampled_from([0.1, 0.07, 0.25]))
def test_far_pieces_are_the_far_cells_and_their_pieces(centre, bound, width):
    """Edges (a bound of zero, centres on cell edges): the far test on rectangles agrees with the far test of a
    grid's cells, and a piece of a far cell is far (its points are points of the cell)."""
    reach = _shell_plan().section.reach
    saved = reach.centre
    try:
        reach.centre = tuple((c, c) for c in centre)
        grid = CellGrid(np.array([[-0.2, 0.8], [-0.6, 0.6]]), width)
        cells = np.argwhere(np.ones(grid.shape, dtype=bool))
        rects = grid.cells(cells)
        far = reach.far_cells(grid, bound)
        assert np.array_equal(reach.far_boxes(rects, bound), far[tuple(cells.T)])
        quarters = split_every_axis(rects)
        assert np.all(reach.far_boxes(quarters, bound)[np.tile(far[tuple(cells.T)], 4)])
    finally:
        reach.centre = saved


@settings(max_examples=30, deadline=None, derandomize=True)
@given(st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3), st.sampled_from([INNER, UNDECIDED]), st.integers(0, 3),
                          st.sampled_from([INNER, OUTER, UNDECIDED])), max_size=10, unique_by=lambda t: t[:2]),
       st.sampled_from([1.0, 0.1, 1e-3, 3.0]), st.sampled_from([0.0, -0.05, 0.3, 1e6]))
def test_volume_with_pieces_brackets_the_exact_solid(cells, width, shift):
    """Exact rationals: inner cells, and undecided cells with one quarter proved (inner or outer) or none; the
    bracket holds pi times the exact sum of (r1^2 - r0^2)(z1 - z0) over the inner cells and pieces (lower) and over
    the undecided cells less the outer pieces (upper), rho clipped at 0, and is no wider than the rest of the
    undecided cells plus the outward rounding (a few units in the last place of each pi r1^2 (z1 - z0)).  Edges:
    cells across the axis, widths that are no binary fractions, far from the origin."""
    grid = CellGrid(np.array([[shift, shift + 2 * width], [shift, shift + 2 * width]]), width)
    classes = np.full(grid.shape, OUTER, dtype=np.int8)
    chosen = {INNER: [], OUTER: []}
    for i, j, cell, quarter, kind in cells:
        classes[i, j] = cell
        if cell == UNDECIDED and kind != UNDECIDED:
            chosen[kind].append(split_every_axis(grid.cells(np.array([[i, j]])))[quarter])
    pieces = Pieces(*(np.array(chosen[k]).reshape(-1, 2, 2) for k in (INNER, OUTER)))
    lo, hi = turned_volume(grid, classes, pieces)
    e0, e1 = ([R(float(v)) for v in e] for e in grid.edges)

    def solid(r0, r1, z0, z1, outer=False):
        r0, r1, z0, z1 = (R(float(v)) for v in (r0, r1, z0, z1))
        return sp.pi * (max(r1, 0) ** 2 - (0 if outer else max(r0, 0) ** 2)) * (z1 - z0)

    def total(kinds, outer=False):
        return sum((solid(e0[i], e0[i + 1], e1[j], e1[j + 1], outer) for (i, j), k in np.ndenumerate(classes)
                    if k in kinds), sp.Integer(0))

    def of(rects):
        return sum((solid(r0, r1, z0, z1) for (r0, r1), (z0, z1) in rects), sp.Integer(0))

    assert R(lo) <= total({INNER}) + of(pieces.inner)
    assert total({INNER, UNDECIDED}) - of(pieces.outer) <= R(hi)
    rounding = 1e-14 * float(total({INNER, UNDECIDED}, outer=True))
    assert hi - lo <= float(total({UNDECIDED}) - of(pieces.inner) - of(pieces.outer)) + rounding + 1e-300
