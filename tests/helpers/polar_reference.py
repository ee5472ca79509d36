"""Independent area reference for planar chains: the sweep of the first joint, in polar coordinates.

P_p = R(theta_1) (l_1 e_y + w) with w in W, the workspace of the joints 2..p.  On the
circle of radius rho about O, the workspace is the angular set of S = l_1 e_y + W on that
circle, widened by the range of theta_1 (a rotation adds theta_1 to the polar angle).  The
area is the integral of rho times that angular measure.  Angular sets are exact for a
polygon S (circle-segment intersections); S is the union of the two-link sheets (p <= 3,
images of the joint rectangle's boundary, split where theta_p = 0) or, for p >= 4, the
boundary of W computed one level down (checked itself by the same test at p - 1).
"""

import math
from itertools import pairwise

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.ops import unary_union


def two_link_region(l1, l2, lo1, hi1, lo2, hi2, n=400):
    """The workspace of a two-link chain (theta_1 from +y) as a shapely geometry."""
    cuts = [lo2] + ([0.0] if lo2 < 0 < hi2 else []) + [hi2]
    s = np.linspace(0, 1, n)
    polys = []
    for c0, c1 in pairwise(cuts):
        ta, tb = lo1 + (hi1 - lo1) * s, c0 + (c1 - c0) * s
        edge = np.concatenate([np.stack([ta, np.full(n, c0)], 1), np.stack([np.full(n, hi1), tb], 1),
                               np.stack([ta[::-1], np.full(n, c1)], 1), np.stack([np.full(n, lo1), tb[::-1]], 1)])
        phi1, phi2 = edge[:, 0], edge[:, 0] + edge[:, 1]
        pts = np.stack([-l1 * np.sin(phi1) - l2 * np.sin(phi2), l1 * np.cos(phi1) + l2 * np.cos(phi2)], 1)
        polys.append(Polygon(pts).buffer(0))
    return unary_union(polys)


def _segments(geom):
    rings = []
    for g in getattr(geom, "geoms", [geom]):
        rings.append(np.asarray(g.exterior.coords))
        rings += [np.asarray(r.coords) for r in g.interiors]
    return np.vstack([np.stack([r[:-1], r[1:]], 1) for r in rings])      # (m, 2, 2)


def polar_sweep_area(region, lo, hi, n_rho=3000):
    """Area of the union over theta in [lo, hi] of R(theta) region (region: shapely geometry)."""
    seg = _segments(region)
    seg = seg[(np.diff(seg, axis=1) ** 2).sum(-1)[:, 0] > 0]          # drop repeated vertices
    shapely.prepare(region)
    rmax = np.hypot(seg[..., 0], seg[..., 1]).max()
    edges = np.linspace(0.0, rmax, n_rho + 1)
    total = 0.0
    p0, d = seg[:, 0], seg[:, 1] - seg[:, 0]
    a = (d * d).sum(1)
    b = 2 * (p0 * d).sum(1)
    c0 = (p0 * p0).sum(1)
    for k in range(n_rho):
        rho = 0.5 * (edges[k] + edges[k + 1])
        disc = b * b - 4 * a * (c0 - rho * rho)
        ok = disc >= 0
        sq = np.sqrt(np.where(ok, disc, 0.0))
        angles = []
        for t in ((-b - sq) / (2 * a), (-b + sq) / (2 * a)):
            good = ok & (t >= 0) & (t <= 1)
            pts = p0[good] + t[good, None] * d[good]
            angles.append(np.arctan2(pts[:, 1], pts[:, 0]))
        ang = np.sort(np.concatenate(angles))
        if not len(ang):
            inside = region.contains(shapely.Point(rho, 0.0))
            intervals = [(0.0, 2 * math.pi)] if inside else []
        else:
            ends = np.concatenate([ang, [ang[0] + 2 * math.pi]])
            mids = 0.5 * (ends[:-1] + ends[1:])
            inside = shapely.contains_xy(region, rho * np.cos(mids), rho * np.sin(mids))
            intervals = [(ends[j], ends[j + 1]) for j in np.flatnonzero(inside)]
        if not intervals:
            continue
        widened = sorted((s + lo, e + hi) for s, e in intervals)
        # union on the circle: unwrap by sorting, merge, and cap the total at 2 pi
        merged = []
        for s, e in widened:
            if merged and s <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], e)
            else:
                merged.append([s, e])
        if len(merged) > 1 and merged[-1][1] - 2 * math.pi >= merged[0][0]:
            last = merged.pop()
            merged[0][0] = min(merged[0][0], last[0] - 2 * math.pi)
            merged[0][1] = max(merged[0][1], last[1] - 2 * math.pi)
        measure = min(2 * math.pi, sum(e - s for s, e in merged))
        total += rho * measure * (edges[k + 1] - edges[k])
    return total


def reference_area(chain, sub_boundary_polygons=None):
    """Area of a chain's workspace by the sweep of its first joint (see the module docstring).

    ``sub_boundary_polygons``: for p >= 4, ``[(polyline, "outer" | "hole"), ...]`` of the
    workspace of the joints 2..p.
    """
    L, lo, hi = chain.lengths, chain.lower, chain.upper
    if chain.p == 2:
        return two_link_region(L[0], L[1], lo[0], hi[0], lo[1], hi[1]).area
    if chain.p == 3:
        W = two_link_region(L[1], L[2], lo[1], hi[1], lo[2], hi[2])
    else:
        W = None
        for poly, kind in sub_boundary_polygons:
            pg = Polygon(poly).buffer(0)
            W = pg if W is None else (W.union(pg) if kind == "outer" else W.difference(pg))
    S = shapely.affinity.translate(W, 0.0, L[0])
    return polar_sweep_area(S, lo[0], hi[0])
