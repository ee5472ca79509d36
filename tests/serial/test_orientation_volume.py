"""The volume bracket of a solid turned by the first joint, from its section's cells (Pappus,
``orientation.section_volume_bracket``): against exact volumes of turned rectangles, a numerical integration at 20
digits."""

from __future__ import annotations

import math
from types import SimpleNamespace

import mpmath
import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from workspace_sym.interval.image import CellGrid
from workspace_sym.interval.verdict import INSIDE as INNER
from workspace_sym.interval.verdict import OUTSIDE as OUTER
from workspace_sym.interval.verdict import UNDECIDED
from workspace_sym.serial.pose import section_volume_bracket


def _turn(c: float, degrees: float):
    half = math.radians(degrees) / 2
    return SimpleNamespace(c=(c, c), inner_range=(-half, half), outer_range=(-half, half), full=degrees == 360)


def _grid(width: float, reach_u: float = 1.0):
    return CellGrid(np.array([[-reach_u, reach_u], [0.0, 1.0]]), width)


def _rectangle(grid, u0, u1, v0, v1, value=INNER):
    """Classes with the cells inside [u0, u1] x [v0, v1] set to ``value`` (the rest OUTER)."""
    classes = np.full(grid.shape, OUTER, dtype=np.int8)
    (e0, e1) = grid.edges
    rows = (e0[:-1] >= u0) & (e0[1:] <= u1)
    cols = (e1[:-1] >= v0) & (e1[1:] <= v1)
    classes[np.ix_(rows, cols)] = value
    return classes


@pytest.mark.parametrize("c, degrees, u, volume", [
    # Reference: exact volumes. One branch (u > 0), a whole turn: an annulus pi (u1^2 - u0^2) h, whatever c
    # (r^2 = u^2 + c^2, so r1^2 - r0^2 = u1^2 - u0^2).
    (0.15, 360, (0.25, 1.25), math.pi * (1.25**2 - 0.25**2) * 0.5),
    (0.0, 360, (0.25, 1.25), math.pi * (1.25**2 - 0.25**2) * 0.5),
    # A partial turn of 90 degrees, one branch: a quarter of it.
    (0.15, 90, (0.25, 1.25), math.pi / 4 * (1.25**2 - 0.25**2) * 0.5),
    # Both branches and c = 0: the arcs [a, b] and [a + pi, b + pi] are disjoint for a 90 degree range, so the
    # solid is twice the turned half: 2 (pi / 2) / 2 * 0.75^2 * h.
    (0.0, 90, (-0.75, 0.75), math.pi / 2 * 0.75**2 * 0.5),
    # Both branches, a whole turn: the cylinder of radius sqrt(0.75^2 + c^2) less the hole of radius c.
    (0.15, 360, (-0.75, 0.75), math.pi * 0.75**2 * 0.5),
])
def test_turned_rectangles_have_their_exact_volume(c, degrees, u, volume):
    grid = _grid(0.5, 1.5)
    lo, hi = section_volume_bracket(grid, _rectangle(grid, *u, 0.25, 0.75), _turn(c, degrees))
    assert lo <= volume <= hi
    assert hi - lo <= 1e-12 * volume


def _arcs_volume(c: float, degrees: float, s1: float, height: float) -> mpmath.mpf:
    """Reference: the volume of {Rz(theta) (u, c, v)}, |u| <= s1, |theta| <= degrees / 2, 0 <= v - v0 <= height,
    integrated at 20 digits over s = |u|: at each s the two arcs of polar angles, [a, b] + atan2(c, s) and
    [a, b] + atan2(c, -s), measured by inclusion-exclusion on the unrolled line (their overlaps with the other
    arc's copies shifted by whole turns)."""
    with mpmath.workdps(20):
        half = mpmath.radians(degrees) / 2

        def union(s):
            first = (-half + mpmath.atan2(c, s), half + mpmath.atan2(c, s))
            second = (-half + mpmath.atan2(c, -s), half + mpmath.atan2(c, -s))
            overlap = sum(max(0, min(first[1], second[1] + k * 2 * mpmath.pi)
                              - max(first[0], second[0] + k * 2 * mpmath.pi)) for k in (-2, -1, 0, 1, 2))
            return 4 * half - overlap

        return height * mpmath.quad(lambda s: union(s) * s, mpmath.linspace(0, s1, 9))


@pytest.mark.parametrize("c, degrees", [(0.15, 320), (-0.3, 200), (0.4, 45)])
def test_partial_turns_with_an_offset_hold_the_integrated_volume(c, degrees):
    # Reference: _arcs_volume (numerical integration at 20 digits); the bracket must hold it and narrow with the
    # cells (the arcs' offset varies across a cell, so it is not exact).
    widths = []
    for width in (2.0**-3, 2.0**-6):
        grid = _grid(width, 1.0)
        # |u| <= 0.75 - width / 2 on the grid's odd multiples of width / 2
        s1 = (math.floor(0.75 / width - 0.5) + 0.5) * width
        v0 = grid.edges[1][2]
        classes = _rectangle(grid, -s1, s1, v0, v0 + 8 * width)
        lo, hi = section_volume_bracket(grid, classes, _turn(c, degrees))
        exact = _arcs_volume(c, degrees, s1, 8 * width)
        assert lo <= exact <= hi
        widths.append((hi - lo) / float(exact))
    assert widths[1] < 0.05 and widths[1] < widths[0]


@settings(derandomize=True, max_examples=40, deadline=None)
@given(st.lists(st.sampled_from([INNER, UNDECIDED, OUTER]), min_size=7 * 5, max_size=7 * 5),
       st.sampled_from([0.0, 0.15, -0.4]), st.sampled_from([360, 320, 180, 30]))
@example([UNDECIDED] * 35, 0.15, 320)
@example([INNER] * 35, 0.0, 360)
def test_deciding_a_cell_only_narrows_the_bracket(cells, c, degrees):
    # Reference: monotonicity (a property of any sound bracket of a fixed set): proving an undecided cell
    # inner or outer never loses what was proved, and the bracket of the refined classes lies within the first.
    grid = _grid(0.5, 1.0)
    assert grid.shape == (7, 5)
    classes = np.array(cells, dtype=np.int8).reshape(7, 5)
    lo, hi = section_volume_bracket(grid, classes, _turn(c, degrees))
    assert 0 <= lo <= hi
    undecided = np.argwhere(classes == UNDECIDED)
    for value in (INNER, OUTER):
        refined = classes.copy()
        refined[tuple(undecided[: len(undecided) // 2].T)] = value
        r_lo, r_hi = section_volume_bracket(grid, refined, _turn(c, degrees))
        assert lo <= r_lo <= r_hi <= hi


def test_an_asymmetric_grid_is_refused():
    grid = CellGrid(np.array([[0.0, 1.0], [0.0, 1.0]]), 0.5)
    with pytest.raises(ValueError, match="symmetric"):
        section_volume_bracket(grid, np.zeros(grid.shape, dtype=np.int8), _turn(0.0, 360))
