"""The arrangement of circular arcs behind Step 2: faces and their areas against exact formulas."""

import math

import numpy as np
import pytest

from workspace_sym.arrangement import Arrangement, arc_area_term, parity_inside


def full_circle(cx, cy, r, cut=0.3):
    """A whole circle given as two arcs (spans below 2 pi, as Step 1 produces)."""
    return [(cx, cy, r, cut, math.pi), (cx, cy, r, cut + math.pi, math.pi)]


def test_two_overlapping_circles():
    """Unit circles at distance 1: a lens of area 2 pi / 3 - sqrt(3) / 2 and two crescents."""
    arr = Arrangement(full_circle(0, 0, 1) + full_circle(1, 0, 1), scale=2.0)
    lens = 2 * math.pi / 3 - math.sqrt(3) / 2
    assert len(arr.face_cycles) == 3
    assert sorted(arr.face_area) == pytest.approx(sorted([lens, math.pi - lens, math.pi - lens]), rel=1e-12)


def test_tangent_and_concentric_circles():
    """Externally tangent circles meet at one vertex; a concentric circle makes an annulus and a disc."""
    arcs = full_circle(0, 0, 1) + full_circle(2, 0, 1) + full_circle(0, 0, 0.5, cut=1.0)
    arr = Arrangement(arcs, scale=3.0)
    want = sorted([math.pi * (1 - 0.25), math.pi * 0.25, math.pi])
    assert sorted(arr.face_area) == pytest.approx(want, rel=1e-12)
    touching = [v for v in arr.vertices if abs(v[0] - 1) < 1e-9 and abs(v[1]) < 1e-9]
    assert len(touching) == 1


def test_duplicate_arcs_merge_and_green_term():
    """The same circle given twice is one circle; Green's term of a whole circle is pi r^2."""
    arr = Arrangement(full_circle(0.5, -0.2, 0.7) + full_circle(0.5, -0.2, 0.7, cut=2.0), scale=1.0)
    assert len(arr.circles) == 1 and arr.face_area == pytest.approx([math.pi * 0.49], rel=1e-12)
    assert arc_area_term(0.5, -0.2, 0.7, 0.0, 2 * math.pi) == pytest.approx(math.pi * 0.49, rel=1e-14)


def test_parity_ignores_rays_through_vertices():
    """A point level with a vertex of the loop still gets the right parity."""
    arcs = np.array(full_circle(0, 0, 1, cut=0.0)).T            # vertices at (1, 0) and (-1, 0)
    pts = np.array([[0.0, 0.0], [-2.0, 0.0], [0.5, 1e-17], [2.0, 0.0]])
    assert parity_inside(pts, *arcs).tolist() == [True, False, True, False]
