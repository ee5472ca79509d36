"""Closed forms of a planar chain's boundary: every arc and the area as SymPy expressions.

Step 2 (:mod:`workspace_sym.boundary`) decides the topology in floats; this
module rebuilds each arc from the chain's exact inputs (lengths, limits, the
alignment angles of Step 0) and matches every loop vertex to a closed form:
an end of the arc's own range, or an intersection of two circles (Bastien
2018, Table 2: the -55.1005 deg is such an intersection).  Layers:
planar -> arrangement -> boundary -> exact; this module reads a boundary by
duck typing and imports none of them.
"""

from __future__ import annotations

import math

import sympy as sp

__all__ = ["closed_forms", "exact_arcs", "exact_area"]


def _u(angle):
    return sp.Matrix([-sp.sin(angle), sp.cos(angle)])


def _fit(expr, value: float, period, tol: float = 1e-9):
    """``expr + n * period`` equal to ``value`` within ``tol`` for some integer n, or None."""
    v = float(sp.N(expr, 30))
    per = float(period)
    n = round((value - v) / per)
    if abs(value - v - n * per) <= tol * max(1.0, abs(value)):
        return expr + n * period
    return None


def _exact_source(chain, arc) -> dict:
    """The exact configuration, centre, radius and start angle of a Step 1 arc."""
    p, i = chain.p, arc.free_joint - 1
    L, lo, hi = chain.exact_lengths, chain.exact_lower, chain.exact_upper
    theta, aligned = [None] * p, []
    for j in range(p):
        if j == i:
            continue
        v = arc.theta_sets[j][0]
        if abs(v - chain.lower[j]) <= 1e-12:
            theta[j] = lo[j]
        elif abs(v - chain.upper[j]) <= 1e-12:
            theta[j] = hi[j]
        else:
            aligned.append(j)
    J = [i] + aligned
    bodies = []
    for k, start in enumerate(J):
        end = J[k + 1] if k + 1 < len(J) else p
        deltas, delta = [], sp.Integer(0)
        for s_ in range(start, end):
            if s_ > start:
                delta = delta + theta[s_]
            deltas.append(delta)
        vx = sum(-L[s_] * sp.sin(d) for s_, d in zip(range(start, end), deltas))
        vy = sum(L[s_] * sp.cos(d) for s_, d in zip(range(start, end), deltas))
        segs = list(zip(range(start, end), deltas))
        length2 = sum(L[a] ** 2 for a, _ in segs) + sum(
            2 * L[a] * L[b] * sp.cos(db - da) for (a, da), (b, db) in zip_pairs(segs))
        bodies.append((sp.atan2(-vx, vy), sp.sqrt(length2), delta))
    signed, orient = bodies[0][1], 1
    for k in range(1, len(J)):
        gamma_prev, _, turn_prev = bodies[k - 1]
        e = gamma_prev - turn_prev - bodies[k][0]
        t = arc.theta_sets[J[k]][0]
        n = round((t - float(sp.N(e, 30))) / math.pi)
        theta[J[k]] = e + n * sp.pi
        orient = -orient if n % 2 else orient
        signed = signed + orient * bodies[k][1]
    positive = float(sp.N(signed, 30)) > 0
    radius = signed if positive else -signed
    phi, centre = sp.Integer(0), sp.Matrix([0, 0])
    for s_ in range(i):
        phi = phi + theta[s_]
        centre = centre + L[s_] * _u(phi)
    a0_float = arc.start_angle - (arc.theta_sets[i][0] - chain.lower[i])
    a0 = phi + lo[i] + bodies[0][0] + sp.pi / 2 + (0 if positive else sp.pi)
    a0 = _fit(a0, a0_float, 2 * sp.pi, 1e-7)
    return {"theta": theta, "i": i, "center": (centre[0], centre[1]), "radius": radius, "a0": a0,
            "a0_float": a0_float, "lo": lo[i], "hi": hi[i], "span": hi[i] - lo[i]}


def zip_pairs(items):
    """All pairs (a, b) with a before b."""
    for k, a in enumerate(items):
        for b in items[k + 1:]:
            yield a, b


def _intersection_angles(c1, r1, c2, r2):
    dx, dy = c2[0] - c1[0], c2[1] - c1[1]
    d2 = dx ** 2 + dy ** 2
    if float(sp.N(d2, 30)) <= 1e-24:
        return []
    beta = sp.atan2(dy, dx)
    gamma = sp.acos((r1 ** 2 + d2 - r2 ** 2) / (2 * r1 * sp.sqrt(d2)))
    return [beta + gamma, beta - gamma]


def _vertex_angle(src, angle, neighbours, sources_all):
    """Closed form of the polar angle ``angle`` (float) of a loop vertex on the circle of ``src``."""
    own = [src["a0"], src["a0"] + src["span"]]
    for e in own:
        fitted = _fit(e, angle, 2 * sp.pi)
        if fitted is not None:
            return fitted
    for other in neighbours + sources_all:
        same = (abs(float(sp.N(other["radius"] - src["radius"], 30))) < 1e-12 and
                all(abs(float(sp.N(other["center"][k] - src["center"][k], 30))) < 1e-12 for k in (0, 1)))
        cands = ([other["a0"], other["a0"] + other["span"]] if same else
                 _intersection_angles(src["center"], src["radius"], other["center"], other["radius"]))
        for e in cands:
            fitted = _fit(e, angle, 2 * sp.pi)
            if fitted is not None:
                return fitted
    # no closed form matched (e.g. a Step 1 cut where u is parallel to P_i - P_j): keep the float,
    # which exact_arcs reports through its "exact" flag
    return sp.Float(angle, 17)


def closed_forms(boundary) -> list[dict]:
    """Closed forms of every boundary arc: ``center``, ``radius``, ``start_angle``, ``end_angle`` (radians)
    and ``theta_sets`` (degrees), as SymPy expressions built from the chain's exact inputs.

    ``boundary`` is a :class:`~workspace_sym.boundary.Boundary` (read for its
    chain, arcs and loops; this module imports nothing from it).  The topology
    comes from the float computation; each closed form is matched to its float
    value (to 1e-9) and a vertex falls back to a 17-digit float only if no
    closed form matches (the row's ``"exact"`` flag is then False).
    Computed on every call; :attr:`Boundary.exact` holds the result once.
    """
    chain = boundary.chain
    kept = chain.kept_arcs()
    cache = {}

    def source(k):
        if k not in cache:
            cache[k] = _exact_source(chain, kept[k])
        return cache[k]

    out = []
    for loop in boundary.loops:
        ids = list(loop.arcs)
        for pos, k in enumerate(ids):
            a = boundary.arcs[k]
            src = source(a.source)
            prev = boundary.arcs[ids[pos - 1]]
            nxt = boundary.arcs[ids[(pos + 1) % len(ids)]]
            others = [source(b.source) for b in boundary.arcs if b.source != a.source]
            start = _vertex_angle(src, a.start_angle, [source(prev.source)], others)
            end = _vertex_angle(src, a.end_angle, [source(nxt.source)], others)
            i = src["i"]
            sets = []
            for j in range(chain.p):
                if j == i:
                    ts = []
                    for ang in (start, end):
                        t = src["lo"] + ang - src["a0"]
                        cands = [_fit(t, v, 2 * sp.pi) for v in a.theta_sets[i]]
                        ts.append(next((c for c in cands if c is not None), t))
                    ts.sort(key=lambda e: float(sp.N(e, 30)))
                    sets.append(tuple(e * 180 / sp.pi for e in ts))
                else:
                    sets.append((src["theta"][j] * 180 / sp.pi,))
            out.append({"center": src["center"], "radius": src["radius"], "start_angle": start, "end_angle": end,
                        "theta_sets": sets, "exact": not (start.has(sp.Float) or end.has(sp.Float))})
    order = [k for loop in boundary.loops for k in loop.arcs]
    result = [None] * len(out)
    for k, row in zip(order, out):
        result[k] = row
    return result


def exact_arcs(boundary) -> list[dict]:
    """The closed forms of the arcs of ``boundary`` (:func:`closed_forms`), computed once per boundary.

    Examples
    --------
    >>> from workspace_sym import PlanarChain
    >>> b = PlanarChain([1, 1], [-90, 0], [90, 90]).boundary()
    >>> rows = exact_arcs(b)
    >>> [r["radius"] for r in rows], all(r["exact"] for r in rows)
    ([2, 1, sqrt(2), 1], True)
    >>> sp.simplify(exact_area(b))
    pi
    """
    return boundary.exact


def exact_area(boundary, rows=None) -> sp.Expr:
    """The enclosed area as a closed form (Green's theorem over the exact arcs ``rows``, by default those of
    :func:`exact_arcs`)."""
    rows = boundary.exact if rows is None else rows
    total = sp.Integer(0)
    for r in rows:
        (cx, cy), rad, a0, a1 = r["center"], r["radius"], r["start_angle"], r["end_angle"]
        total += (rad ** 2 * (a1 - a0) + rad * cx * (sp.sin(a1) - sp.sin(a0))
                  - rad * cy * (sp.cos(a1) - sp.cos(a0))) / 2
    return total
