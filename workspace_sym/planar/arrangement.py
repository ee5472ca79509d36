"""Arrangements of circular arcs: vertices, edges, faces and point location.

The arcs cut the plane into faces.  Circles closer than the tolerance are
merged, points closer than the tolerance are one vertex, and two circles
closer to tangency than the tangency tolerance meet in one point.  Everything
is float arithmetic with these explicit tolerances (relative to ``scale``).

A half-edge runs along an edge with its face on the left; ``next`` turns as
far clockwise as possible at each vertex, so each face is traced once.  The
orientation of outgoing half-edges at a vertex is read one short arc length
along all of them (a quarter of the shortest edge there), so that circles
tangent at a vertex are ordered by their curvature.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Arrangement", "arc_area_term", "arc_distance", "crossings", "in_span", "parity_inside"]

_TWO_PI = 2 * math.pi


def arc_area_term(cx, cy, r, a0, a1):
    """Green's theorem term ``(1/2) int (x dy - y dx)`` of the arc of centre ``c``, radius ``r``, angles a0 -> a1.

    Parameters
    ----------
    cx, cy : float or numpy.ndarray
        The centre.
    r : float or numpy.ndarray
        The radius.
    a0, a1 : float or numpy.ndarray
        Polar angles about the centre where the arc starts and ends (radians); ``a1 < a0`` runs clockwise.

    Returns
    -------
    float or numpy.ndarray
        The term (broadcast over array arguments); the terms of a closed loop add up to its signed area.
    """
    return 0.5 * (r * r * (a1 - a0) + r * cx * (np.sin(a1) - np.sin(a0)) - r * cy * (np.cos(a1) - np.cos(a0)))


def in_span(angle, start, span, tol=0.0):
    """Whether ``angle`` lies on the counter-clockwise span ``[start, start + span]`` (vectorised).

    Parameters
    ----------
    angle : float or numpy.ndarray
        The angle(s) (radians), any turn.
    start : float or numpy.ndarray
        Where the span starts (radians).
    span : float or numpy.ndarray
        Its counter-clockwise length (radians, 0 to 2 pi).
    tol : float, default 0.0
        Slack in radians at both ends.

    Returns
    -------
    bool or numpy.ndarray
        True where the angle lies on the span, within ``tol`` (broadcast over array arguments).
    """
    rel = np.mod(angle - start + tol, _TWO_PI) - tol
    return (rel >= -tol) & (rel <= span + tol)


def arc_distance(points, cx, cy, r, start, span):
    """Distance from each point (n, 2) to each arc (m) -> (n, m).

    Parameters
    ----------
    points : array_like
        ``(n, 2)`` points (one point ``(2,)`` is taken as ``(1, 2)``).
    cx, cy, r, start, span : numpy.ndarray
        ``(m,)`` arcs: centre, radius, start angle and counter-clockwise span (radians).

    Returns
    -------
    numpy.ndarray
        ``(n, m)``: the distance from each point to the nearest point of each arc (to the circle when the
        point's polar angle lies on the span, else to the nearer end).
    """
    points = np.atleast_2d(points)
    dx = points[:, 0:1] - cx
    dy = points[:, 1:2] - cy
    rho = np.hypot(dx, dy)
    on = in_span(np.arctan2(dy, dx), start, span)
    e0 = np.hypot(points[:, 0:1] - (cx + r * np.cos(start)), points[:, 1:2] - (cy + r * np.sin(start)))
    e1 = np.hypot(points[:, 0:1] - (cx + r * np.cos(start + span)), points[:, 1:2] - (cy + r * np.sin(start + span)))
    return np.where(on, np.abs(rho - r), np.minimum(e0, e1))


def crossings(points, cx, cy, r, start, span, direction: float = 0.0):
    """Number of crossings of the ray from each point in ``direction`` (radians) with each arc -> (n, m) ints.

    Parameters
    ----------
    points : array_like
        ``(n, 2)`` points (one point ``(2,)`` is taken as ``(1, 2)``).
    cx, cy, r, start, span : numpy.ndarray
        ``(m,)`` arcs: centre, radius, start angle and counter-clockwise span (radians).
    direction : float, default 0.0
        The direction of the rays (radians, 0 along +x).

    Returns
    -------
    numpy.ndarray
        ``(n, m)`` integers, 0 to 2: the crossings strictly ahead of each point; a tangent ray counts none.
    """
    points = np.atleast_2d(points)
    cb, sb = math.cos(direction), math.sin(direction)
    # rotate everything by -direction so that the ray runs along +x
    px, py = cb * points[:, 0:1] + sb * points[:, 1:2], -sb * points[:, 0:1] + cb * points[:, 1:2]
    qx, qy = cb * cx + sb * cy, -sb * cx + cb * cy
    start = start - direction
    dy = py - qy
    h2 = r * r - dy * dy
    h = np.sqrt(np.maximum(h2, 0.0))
    count = np.zeros(h2.shape, dtype=int)
    for sgn in (1.0, -1.0):
        x = qx + sgn * h
        ang = np.arctan2(dy, sgn * h)
        count += ((h2 > 0) & (x > px) & in_span(ang, start, span)).astype(int)
    return count


def parity_inside(points, cx, cy, r, start, span, *, tol: float = 1e-12):
    """Ray parity of each point against closed loops of arcs, choosing for each point a ray that passes
    no arc end point and touches no circle within ``tol`` (so vertices and tangencies never decide).

    Six fixed directions are tried in turn; a point for which every one passes within ``tol`` of an end or a
    tangency gets the parity of the ray along +x.

    Parameters
    ----------
    points : array_like
        ``(n, 2)`` points (one point ``(2,)`` is taken as ``(1, 2)``).
    cx, cy, r, start, span : numpy.ndarray
        ``(m,)`` arcs forming closed loops: centre, radius, start angle and counter-clockwise span (radians).
    tol : float, default 1e-12
        Distance (in the unit of the points) within which a ray is taken to pass an end point or touch a
        circle.

    Returns
    -------
    numpy.ndarray
        ``(n,)`` bools: True where the ray crosses the arcs an odd number of times (inside).
    """
    points = np.atleast_2d(points)
    ends = np.concatenate([np.stack([cx + r * np.cos(start), cy + r * np.sin(start)], 1),
                           np.stack([cx + r * np.cos(start + span), cy + r * np.sin(start + span)], 1)])
    result = np.zeros(len(points), bool)
    todo = np.arange(len(points))
    for direction in (0.0, 0.7377, 1.9311, 2.8913, 4.0127, 5.3311):
        if not len(todo):
            break
        d = np.array([math.cos(direction), math.sin(direction)])
        rel = ends[None, :, :] - points[todo, None, :]
        across = rel[..., 0] * d[1] - rel[..., 1] * d[0]
        ahead = rel[..., 0] * d[0] + rel[..., 1] * d[1]
        bad = ((np.abs(across) <= tol) & (ahead > -tol)).any(1)
        cen = np.stack([cx, cy], 1)[None, :, :] - points[todo, None, :]
        dist_line = np.abs(cen[..., 0] * d[1] - cen[..., 1] * d[0])
        bad |= (np.abs(dist_line - r) <= tol).any(1)
        ok = todo[~bad]
        result[ok] = crossings(points[ok], cx, cy, r, start, span, direction).sum(1) % 2 == 1
        todo = todo[bad]
    if len(todo):
        result[todo] = crossings(points[todo], cx, cy, r, start, span).sum(1) % 2 == 1
    return result


@dataclass
class Edge:
    tail: int
    head: int
    circle: int
    t0: float           # polar angle at the tail; the edge runs counter-clockwise to t0 + span
    span: float
    sources: list = field(default_factory=list)   # indices of the input arcs that cover this edge


class Arrangement:
    """The arrangement of circular arcs ``(cx, cy, r, start, span)`` (counter-clockwise spans, ``0 < span <= 2 pi``).

    Attributes after construction: ``circles`` (k, 3), ``vertices`` (v, 2),
    ``edges`` (list of :class:`Edge`), half-edge arrays ``tail``, ``head``,
    ``next`` and ``half_face`` (the face on the left of each half-edge, -1 for
    the unbounded face), the cycles of half-edges ``cycles`` and their signed
    areas ``cycle_area``, and for each bounded face ``f`` its outer cycle
    ``face_cycles[f]``, its holes ``face_holes[f]`` and its area ``face_area[f]``.

    Parameters
    ----------
    arcs : array_like
        ``(n, 5)`` rows ``(cx, cy, r, start, span)``.
    scale : float, default 1.0
        The size of the figure (the chain's reach): the tolerances are relative to it.
    tol : float, default 1e-9
        Circles, and points, closer than ``tol * scale`` are merged.
    tangent_tol : float, default 1e-7
        Two circles within ``tangent_tol * scale`` of tangency meet in one point.
    """

    def __init__(self, arcs, *, scale: float = 1.0, tol: float = 1e-9, tangent_tol: float = 1e-7):
        self.scale = float(scale)
        self.tol = tol * self.scale
        self.tangent_tol = tangent_tol * self.scale
        arcs = np.asarray(arcs, dtype=float).reshape(-1, 5)
        self.input = arcs
        self._circles(arcs)
        self._vertices()
        self._edges()
        self._half_edges()
        self._faces()

    # ------------------------------------------------------------------ circles and their covered spans
    def _circles(self, arcs):
        tol = self.tol
        ids = -np.ones(len(arcs), dtype=int)
        circles = []
        for k, (cx, cy, r, _, _) in enumerate(arcs):
            for c, (x, y, rr) in enumerate(circles):
                if abs(cx - x) <= tol and abs(cy - y) <= tol and abs(r - rr) <= tol:
                    ids[k] = c
                    break
            else:
                ids[k] = len(circles)
                circles.append((cx, cy, r))
        self.circles = np.array(circles).reshape(-1, 3)
        self.arc_circle = ids
        # union of the spans on each circle: list of (start, span) or a full circle (start, 2 pi)
        self.covered = []
        for c, (_, _, r) in enumerate(self.circles):
            spans = sorted((float(np.mod(a[3], _TWO_PI)), float(a[4])) for a in arcs[ids == c])
            ang_tol = tol / r
            merged = []
            for s, w in spans:
                if merged and s <= merged[-1][0] + merged[-1][1] + ang_tol:
                    merged[-1][1] = max(merged[-1][1], s + w - merged[-1][0])
                else:
                    merged.append([s, w])
            if len(merged) > 1 and merged[-1][0] + merged[-1][1] >= merged[0][0] + _TWO_PI - ang_tol:
                last = merged.pop()
                merged[0] = [last[0], max(last[1], merged[0][0] + merged[0][1] + _TWO_PI - last[0])]
            merged = [(s, min(w, _TWO_PI)) for s, w in merged]
            if merged and merged[0][1] >= _TWO_PI - ang_tol:
                merged = [(merged[0][0], _TWO_PI)]      # cut where an input arc starts: a vertex with a closed form
            self.covered.append(merged)

    def _on_circle(self, c, pts):
        """Parameters (polar angles) of the points lying on the covered part of circle ``c``."""
        cx, cy, r = self.circles[c]
        d = np.hypot(pts[:, 0] - cx, pts[:, 1] - cy)
        ang = np.arctan2(pts[:, 1] - cy, pts[:, 0] - cx)
        near = np.abs(d - r) <= 4 * self.tol
        on = np.zeros(len(pts), bool)
        for s, w in self.covered[c]:
            on |= near & in_span(ang, s, w, 4 * self.tol / r)
        return on, ang

    # ------------------------------------------------------------------ vertices
    def _vertices(self):
        pts = []
        for c, (cx, cy, r) in enumerate(self.circles):
            for s, w in self.covered[c]:
                if w < _TWO_PI:
                    pts.append((cx + r * math.cos(s), cy + r * math.sin(s)))
                    pts.append((cx + r * math.cos(s + w), cy + r * math.sin(s + w)))
        n = len(self.circles)
        if n > 1:
            a, b = np.triu_indices(n, 1)
            c1, c2 = self.circles[a], self.circles[b]
            dx, dy = c2[:, 0] - c1[:, 0], c2[:, 1] - c1[:, 1]
            d = np.hypot(dx, dy)
            r1, r2 = c1[:, 2], c2[:, 2]
            meet = (d > self.tol) & (d <= r1 + r2 + self.tangent_tol) & (d >= np.abs(r1 - r2) - self.tangent_tol)
            a, b, dx, dy, d, r1, r2, c1 = a[meet], b[meet], dx[meet], dy[meet], d[meet], r1[meet], r2[meet], c1[meet]
            along = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
            h = np.sqrt(np.maximum(r1 * r1 - along * along, 0.0))
            h = np.where(h <= self.tangent_tol, 0.0, h)
            ex, ey = dx / d, dy / d
            for sgn in (1.0, -1.0):
                x = c1[:, 0] + along * ex - sgn * h * ey
                y = c1[:, 1] + along * ey + sgn * h * ex
                cand = np.stack([x, y], axis=1)
                keep = np.ones(len(cand), bool)
                for circ in (a, b):
                    for c in np.unique(circ):
                        rows = np.flatnonzero(circ == c)
                        keep[rows] &= self._on_circle(c, cand[rows])[0]
                pts.extend(map(tuple, cand[keep]))
        pts = np.array(pts, dtype=float).reshape(-1, 2)
        # cluster points closer than the tolerance (union-find over close pairs)
        parent = np.arange(len(pts))

        def find(k):
            while parent[k] != k:
                parent[k] = parent[parent[k]]
                k = parent[k]
            return k

        if len(pts) > 1:
            order = np.argsort(pts[:, 0])
            xs = pts[order, 0]
            for idx, k in enumerate(order):
                j = idx + 1
                while j < len(order) and xs[j] - xs[idx] <= 4 * self.tol:
                    m = order[j]
                    if abs(pts[m, 1] - pts[k, 1]) <= 4 * self.tol:
                        parent[find(m)] = find(k)
                    j += 1
        roots = np.array([find(k) for k in range(len(pts))], dtype=int)
        uniq, label = np.unique(roots, return_inverse=True)
        verts = np.zeros((len(uniq), 2))
        np.add.at(verts, label, pts)
        verts /= np.bincount(label, minlength=len(uniq))[:, None]
        self.vertices = verts

    # ------------------------------------------------------------------ edges
    def _edges(self):
        self.edges = []
        for c, (cx, cy, r) in enumerate(self.circles):
            on, ang = self._on_circle(c, self.vertices)
            vids = np.flatnonzero(on)
            for s, w in self.covered[c]:
                inside = vids[in_span(ang[vids], s, w, 4 * self.tol / r)]
                rel = np.mod(ang[inside] - s + 4 * self.tol / r, _TWO_PI) - 4 * self.tol / r
                rel = np.clip(rel, 0.0, w)
                order = np.argsort(rel)
                vs, ts = list(inside[order]), list(rel[order])
                full = w >= _TWO_PI
                if full:
                    if not vs:  # a whole circle that meets nothing: one vertex of its own
                        self.vertices = np.vstack([self.vertices, [cx + r * math.cos(s), cy + r * math.sin(s)]])
                        vs, ts = [len(self.vertices) - 1], [0.0]
                    vs, ts = vs + [vs[0]], ts + [ts[0] + _TWO_PI]
                for k in range(len(vs) - 1):
                    span = ts[k + 1] - ts[k]
                    if vs[k] == vs[k + 1] and not (full and len(vs) == 2):
                        continue
                    if r * span <= self.tol and vs[k] != vs[k + 1]:
                        continue
                    self.edges.append(Edge(int(vs[k]), int(vs[k + 1]), c, s + ts[k], span))
        # which input arcs cover each edge (by the edge's middle)
        for e in self.edges:
            mid = e.t0 + 0.5 * e.span
            for k in np.flatnonzero(self.arc_circle == e.circle):
                if in_span(mid, self.input[k, 3], self.input[k, 4]):
                    e.sources.append(int(k))

    def edge_point(self, e: Edge, t: float):
        """The point of edge ``e``'s circle at polar angle ``t``.

        Parameters
        ----------
        e : Edge
            An edge of :attr:`edges`.
        t : float
            Polar angle about the circle's centre (radians).

        Returns
        -------
        numpy.ndarray
            ``(2,)``: the point.
        """
        cx, cy, r = self.circles[e.circle]
        return np.array([cx + r * math.cos(t), cy + r * math.sin(t)])

    # ------------------------------------------------------------------ half-edges and faces
    def _half_edges(self):
        """Half-edge 2e runs counter-clockwise along edge e (tail -> head), 2e + 1 back."""
        ne = len(self.edges)
        self.tail = np.zeros(2 * ne, int)
        self.head = np.zeros(2 * ne, int)
        key = np.zeros(2 * ne)
        outgoing = [[] for _ in range(len(self.vertices))]
        # Every half-edge leaving a vertex is read at one arc length from it, the shortest quarter edge there:
        # chords of different lengths compared different amounts of curvature, and a long edge's chord turned
        # past a nearly tangent short one (circles 7e-5 rad apart: a 2R chain at +-179.99 deg lost its hole).
        quarter = [min(0.25 * self.circles[e.circle, 2] * e.span, 1e-3 * self.scale) for e in self.edges]
        read_at = np.full(len(self.vertices), np.inf)
        for k, e in enumerate(self.edges):
            read_at[[e.tail, e.head]] = np.minimum(read_at[[e.tail, e.head]], quarter[k])
        for k, e in enumerate(self.edges):
            r = self.circles[e.circle, 2]
            for h, (v, t) in ((2 * k, (e.tail, e.t0 + read_at[e.tail] / r)),
                              (2 * k + 1, (e.head, e.t0 + e.span - read_at[e.head] / r))):
                self.tail[h], self.head[h] = v, (e.head if h % 2 == 0 else e.tail)
                q = self.edge_point(e, t) - self.vertices[v]
                key[h] = math.atan2(q[1], q[0])
                outgoing[v].append(h)
        self.next = np.zeros(2 * ne, int)
        for hs in outgoing:
            hs.sort(key=lambda h: key[h])
            pos = {h: k for k, h in enumerate(hs)}
            for h in hs:
                twin_of_incoming = h  # h is outgoing; the incoming half-edge is h ^ 1
                k = pos[twin_of_incoming]
                self.next[h ^ 1] = hs[(k - 1) % len(hs)]
        self.outgoing = outgoing

    def half_edge_arc(self, h):
        """``(cx, cy, r, a_from, a_to)`` of half-edge ``h`` in its direction of travel.

        Parameters
        ----------
        h : int
            Half-edge index: ``2e`` runs counter-clockwise along edge ``e``, ``2e + 1`` back.

        Returns
        -------
        tuple of float
            Centre, radius, and the polar angles where the half-edge starts and ends (radians).
        """
        e = self.edges[h // 2]
        cx, cy, r = self.circles[e.circle]
        if h % 2 == 0:
            return cx, cy, r, e.t0, e.t0 + e.span
        return cx, cy, r, e.t0 + e.span, e.t0

    def _faces(self):
        nh = len(self.next)
        cycle = -np.ones(nh, int)
        cycles = []
        for h in range(nh):
            if cycle[h] >= 0:
                continue
            cyc, g = [], h
            while cycle[g] < 0:
                cycle[g] = len(cycles)
                cyc.append(g)
                g = self.next[g]
            cycles.append(cyc)
        self.cycles = cycles
        self.half_cycle = cycle
        self.cycle_area = np.array([sum(arc_area_term(*self.half_edge_arc(h)) for h in cyc) for cyc in cycles])
        # connected components of the edge graph
        parent = list(range(len(self.vertices)))

        def find(k):
            while parent[k] != k:
                parent[k] = parent[parent[k]]
                k = parent[k]
            return k

        for e in self.edges:
            parent[find(e.tail)] = find(e.head)
        comp_of_cycle = [find(self.tail[c[0]]) for c in cycles]
        # the outer cycle of each component has the smallest signed area; the others bound faces
        outer_of = {}
        for k, comp in enumerate(comp_of_cycle):
            if comp not in outer_of or self.cycle_area[k] < self.cycle_area[outer_of[comp]]:
                outer_of[comp] = k
        bounded = [k for k in range(len(cycles)) if k not in outer_of.values()]
        self.face_cycles = bounded                     # face f is bounded by cycle face_cycles[f]
        self.face_holes = [[] for _ in bounded]
        face_of_cycle = {c: f for f, c in enumerate(bounded)}
        # the face around each component: the smallest bounded face of another component containing it
        comps = list(outer_of)
        probes = np.array([self._cycle_probe(outer_of[c]) for c in comps]).reshape(-1, 2)
        best = -np.ones(len(comps), int)
        best_area = np.full(len(comps), np.inf)
        comp_ids = np.array(comps)
        for f, k in enumerate(bounded):
            cand = (comp_ids != comp_of_cycle[k]) & (self.cycle_area[k] < best_area)
            if not cand.any():
                continue
            idx = np.flatnonzero(cand)
            hit = idx[self.inside_cycle(probes[idx], k)]
            best[hit], best_area[hit] = f, self.cycle_area[k]
        for comp, f in zip(comps, best):
            k = outer_of[comp]
            face_of_cycle[k] = int(f)
            if f >= 0:
                self.face_holes[f].append(k)
        self.half_face = np.array([face_of_cycle[cycle[h]] for h in range(nh)], dtype=int)
        self.face_area = np.array([self.cycle_area[c] + sum(self.cycle_area[k] for k in self.face_holes[f])
                                   for f, c in enumerate(bounded)])

    def _cycle_probe(self, k):
        """A point of cycle ``k`` (the middle of its first half-edge)."""
        cx, cy, r, a, b = self.half_edge_arc(self.cycles[k][0])
        m = 0.5 * (a + b)
        return np.array([cx + r * math.cos(m), cy + r * math.sin(m)])

    def cycle_arrays(self, k):
        """The arcs of cycle ``k`` as arrays ``cx, cy, r, start, span`` (counter-clockwise spans).

        Parameters
        ----------
        k : int
            Index into :attr:`cycles`.

        Returns
        -------
        numpy.ndarray
            ``(5, m)``: one column per edge of the cycle (cached per cycle).
        """
        cache = self.__dict__.setdefault("_cycle_cache", {})
        if k not in cache:
            edges = self._edge_table()
            cache[k] = edges[:, [h // 2 for h in self.cycles[k]]]
        return cache[k]

    def _edge_table(self):
        if getattr(self, "_edge_arr", None) is None or self._edge_arr.shape[1] != len(self.edges):
            self._edge_arr = np.array([(*self.circles[e.circle], e.t0, e.span) for e in self.edges]).T.reshape(5, -1)
        return self._edge_arr

    def inside_cycle(self, points, k):
        """Whether each point lies inside cycle ``k`` (ray parity).

        Parameters
        ----------
        points : array_like
            ``(n, 2)`` points.
        k : int
            Index into :attr:`cycles`.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` bools (:func:`parity_inside` with the arrangement's tolerance).
        """
        return parity_inside(points, *self.cycle_arrays(k), tol=self.tol)

    def in_face(self, points, f):
        """Whether each point lies in bounded face ``f``: inside its outer cycle and inside none of its holes.

        Parameters
        ----------
        points : array_like
            ``(n, 2)`` points (one point ``(2,)`` is taken as ``(1, 2)``).
        f : int
            A bounded face, index into :attr:`face_cycles`.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` bools.
        """
        points = np.atleast_2d(points)
        cx, cy, r, _, _ = self.cycle_arrays(self.face_cycles[f])
        box = ((points[:, 0] >= (cx - r).min()) & (points[:, 0] <= (cx + r).max()) &
               (points[:, 1] >= (cy - r).min()) & (points[:, 1] <= (cy + r).max()))
        out = np.zeros(len(points), bool)
        idx = np.flatnonzero(box)
        if len(idx):
            ok = self.inside_cycle(points[idx], self.face_cycles[f])
            for k in self.face_holes[f]:
                ok &= ~self.inside_cycle(points[idx], k)
            out[idx] = ok
        return out

    def face_edges(self, f):
        """Indices of the edges around bounded face ``f`` (outer cycle and holes).

        Parameters
        ----------
        f : int
            A bounded face, index into :attr:`face_cycles`.

        Returns
        -------
        list of int
            Indices into :attr:`edges`, sorted, each once.
        """
        hs = list(self.cycles[self.face_cycles[f]]) + [h for k in self.face_holes[f] for h in self.cycles[k]]
        return sorted({h // 2 for h in hs})

    def face_clearance(self, points, f):
        """Distance from points inside face ``f`` to the nearest edge (only the face's own edges can be nearest).

        Parameters
        ----------
        points : array_like
            ``(n, 2)`` points inside face ``f``.
        f : int
            A bounded face, index into :attr:`face_cycles`.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` distances to the nearest edge of the face.
        """
        return arc_distance(points, *self._edge_table()[:, self.face_edges(f)]).min(axis=1)

    def interior_point(self, f):
        """A point inside face ``f``, away from its edges, and its clearance (None, -1 if none is found).

        Probes step off the middle (and quarters) of the face's longest edges
        into the face, from a third of the edge length down to 1e-5 of it, and
        keep the probe with the largest clearance.

        Parameters
        ----------
        f : int
            A bounded face, index into :attr:`face_cycles`.

        Returns
        -------
        tuple
            ``(point, clearance)``: a ``(2,)`` array and its distance to the nearest edge (more than 10 times the
            tolerance), or ``(None, -1.0)``.
        """
        best, best_clear = None, -1.0
        hs = list(self.cycles[self.face_cycles[f]])
        hs.sort(key=lambda h: -self.circles[self.edges[h // 2].circle, 2] * self.edges[h // 2].span)
        perimeter = sum(self.circles[self.edges[k].circle, 2] * self.edges[k].span for k in self.face_edges(f))
        width = 2 * abs(self.face_area[f]) / perimeter if perimeter > 0 else 0.0
        for h in hs[:24]:
            cx, cy, r, a, b = self.half_edge_arc(h)
            length = r * self.edges[h // 2].span
            toward_centre = h % 2 == 0       # the left of a counter-clockwise arc is the centre side
            # steps from the edge's length, then from the face's mean width (a long thin face, such as the
            # lens between circles 1e-6 apart of a joint 1e-4 deg short of a full turn, is narrower than them)
            distances = [step * min(length, 0.2 * self.scale) for step in (0.3, 0.1, 0.03, 0.01, 3e-3, 1e-3, 1e-4,
                                                                             1e-5)] + [0.5 * width, 0.25 * width]
            for frac in (0.5, 0.25, 0.75):
                m = a + frac * (b - a)
                for d in distances:
                    rr = r - d if toward_centre else r + d
                    if rr <= 0 or d <= 20 * self.tol:
                        continue
                    q = np.array([cx + rr * math.cos(m), cy + rr * math.sin(m)])
                    if not self.in_face(q[None], f)[0]:
                        continue
                    clear = float(self.face_clearance(q[None], f)[0])
                    if clear > best_clear and clear > 10 * self.tol:
                        best, best_clear = q, clear
                    break
            if best_clear > 0.05 * self.scale:
                break
        return best, best_clear
