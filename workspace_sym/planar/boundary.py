"""Step 2 of the alignment method: the workspace boundary of a planar chain as loops of arcs.

The kept arcs of Step 1 contain the boundary, so every face of their
arrangement lies wholly inside or wholly outside the workspace (a face meets
no boundary point, and is connected).  Each face is classified, and
``Boundary.evidence`` records how:

* **inside** when a kept arc has its side (Lemma 3.1) pointing into the face —
  the configurations on that arc cover a one-sided neighbourhood there — or
  when a witness configuration lands in the face;
* **outside** for the unbounded face, and for a bounded face when a point of
  it lies strictly outside the annulus ``2 l_max - R <= r <= R`` that holds
  every configuration whatever the limits (:func:`outside_every_turn`, exact
  rational arithmetic: the hole of joints a hair short of a full turn touches
  reachable points, so no finite exclusion covers it), or when interval
  exclusion shows that no configuration of the joint box reaches a point of it
  (:func:`prove_unreachable`, outward-rounded, within a budget of boxes), or
  else when the arc that the point describes in the frame of link 1 misses the
  workspace of the joints 2..p, computed by this same method
  (:func:`unreachable_via_subchain`, float geometry with explicit tolerances).

Only interval exclusion and the annulus are proofs; the other verdicts are float
geometry with explicit tolerances, the standard of the whole arrangement (the
topology of Step 2 is decided in floats).  The planar boundary is therefore an
exact-geometry result, not a certified-box result; a face that no argument
decides is reported as undecided.

The boundary is made of the edges between an inside and an outside face,
walked with the workspace on the left: outer loops turn counter-clockwise,
holes clockwise.  Area and perimeter come from the arcs (Green's theorem).
:attr:`Boundary.exact` holds every arc in closed form from the exact inputs
(computed by :mod:`workspace_sym.planar.exact` on first use).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import sympy as sp

from ..errors import BoundaryError, InvalidParameterError
from ..interval import arith
from ..interval.driver import RunOn, StopAt, deprecated, refuse_run, refuse_stop, with_legacy_keywords
from ..interval.search import prove_all
from ..numbers import clean, fmt, md_escape
from ..progress import stage_bar
from .arcs import RESOLUTION, Arc, degrees
from .arrangement import Arrangement, arc_area_term, arc_distance, in_span, parity_inside
from .exact import closed_forms, exact_area

__all__ = ["Boundary", "BoundaryArc", "Loop", "ArcTable", "build_boundary", "format_set", "prove_unreachable",
           "outside_every_turn", "unreachable_via_subchain", "witness_near", "SLIVER_WIDTH"]

_TWO_PI = 2 * math.pi


@dataclass(frozen=True, slots=True, repr=False)     # the one-line repr of Arc
class BoundaryArc(Arc):
    """One arc of a boundary loop: an :class:`~workspace_sym.planar.arcs.Arc` in the loop's direction of travel.

    The free joint's interval in ``theta_sets`` is restricted to this arc;
    ``start_angle`` and ``end_angle`` follow the direction of travel
    (``end < start`` when the loop runs clockwise on this circle).  ``source``
    indexes the Step 1 arc it comes from.

    Parameters
    ----------
    type : str
        ``"I"``, ``"II"`` or ``"III"``, as in :class:`~workspace_sym.planar.arcs.Arc`.
    free_joint : int
        The joint that turns along the arc, 1-based.
    theta_sets : tuple of tuple of float
        ``(value,)`` for a held joint, ``(low, high)`` for the free joint over this arc (radians).
    center : tuple of float
        The centre ``(x, y)`` of the circle.
    radius : float
        The radius of the circle.
    start_angle, end_angle : float
        Polar angles about ``center`` at the start and the end of the arc in the loop's direction of travel
        (radians).
    side : int, default 0
        The side of the Step 1 arc (+1 workspace away from the centre, -1 towards it).
    source : int, default -1
        The index of the Step 1 arc in :attr:`PlanarChain.step1 <workspace_sym.planar.chain.PlanarChain.step1>`.
    """

    source: int = -1

    @property
    def sweep(self) -> float:
        """The signed angle the arc turns through.

        Returns
        -------
        float
            ``end_angle - start_angle`` (radians): negative when the loop runs clockwise on this circle.
        """
        return self.end_angle - self.start_angle

    @property
    def start(self):
        """The point where the arc starts in the direction of travel.

        Returns
        -------
        numpy.ndarray
            ``(2,)``: the point at ``start_angle``.
        """
        return self.point(self.start_angle)

    @property
    def end(self):
        """The point where the arc ends in the direction of travel.

        Returns
        -------
        numpy.ndarray
            ``(2,)``: the point at ``end_angle``.
        """
        return self.point(self.end_angle)

    def area_term(self) -> float:
        """The arc's term of the enclosed area by Green's theorem, ``(1/2) int (x dy - y dx)`` along it.

        Returns
        -------
        float
            The term (:func:`~workspace_sym.planar.arrangement.arc_area_term`); the terms of a loop add up to
            its signed area.
        """
        return float(arc_area_term(*self.center, self.radius, self.start_angle, self.end_angle))


def format_set(values, digits: int = 4) -> str:
    """A joint's set of a boundary arc, in degrees: ``{-60.0000}`` (held) or ``[-60.0000, -55.1005]`` (free).

    Parameters
    ----------
    values : sequence of float
        ``(value,)`` or ``(low, high)``, already in degrees.
    digits : int, default 4
        Decimals shown.

    Returns
    -------
    str
        The set in braces (one value) or as an interval (two).
    """
    if len(values) == 1:
        return f"{{{fmt(values[0], digits)}}}"
    return f"[{fmt(values[0], digits)}, {fmt(values[1], digits)}]"


class ArcTable(list):
    """:meth:`Boundary.table`: a list of ``{"type", "free_joint", "theta_sets"}`` dicts, one per arc, that Jupyter
    displays as the table it is (HTML drawn by :func:`workspace_sym.display.arc_table_html`, or Markdown), held
    joints in braces and free ones as intervals.

    Parameters
    ----------
    rows : iterable of dict
        One dict per arc: ``"type"``, ``"free_joint"`` (1-based) and ``"theta_sets"`` (one tuple per joint, in
        degrees: floats, or SymPy expressions when ``exact``).
    joints : int
        The number of joints (columns of sets).
    exact : bool, default False
        Whether the sets are closed forms (shown as SymPy prints them) rather than floats (shown with 4
        decimals).
    """

    def __init__(self, rows, *, joints: int, exact: bool = False):
        super().__init__(rows)
        self.joints, self.exact = joints, exact

    def cells(self) -> tuple[list, list]:
        """The header and the rows of cells (text), one row per arc.

        Returns
        -------
        tuple
            ``(header, rows)``: the header ``["#", "type", "θ1 (deg)", ...]`` and one list per arc: its number
            from 1, its type and the set of each joint as text (:func:`format_set`, or the closed forms).
        """
        def shown(values):
            if not self.exact:
                return format_set(values)
            text = ", ".join(sp.sstr(v) for v in values)
            return f"{{{text}}}" if len(values) == 1 else f"[{text}]"

        header = ["#", "type"] + [f"θ{j + 1} (deg)" for j in range(self.joints)]
        return header, [[k, row["type"], *(shown(v) for v in row["theta_sets"])] for k, row in enumerate(self, 1)]

    def _repr_markdown_(self) -> str:
        header, rows = self.cells()
        return "\n".join(["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
                         + ["| " + " | ".join(md_escape(str(c)) for c in row) + " |" for row in rows]) + "\n"


@dataclass(frozen=True)
class Loop:
    """One closed loop of a boundary, the workspace on its left.

    Parameters
    ----------
    kind : str
        ``"outer"`` (counter-clockwise) or ``"hole"`` (clockwise).
    arcs : tuple of int
        Indices into :attr:`Boundary.arcs`, in order of travel.
    area : float
        The signed area it encloses: positive for an outer loop, negative for a hole.
    """

    kind: str                 # "outer" or "hole"
    arcs: tuple               # indices into Boundary.arcs, in order of travel
    area: float               # signed: positive for an outer loop


@dataclass
class Boundary:
    """The boundary of a planar chain's workspace (Step 2), with area, perimeter and point queries.

    Made by :func:`build_boundary` (:meth:`PlanarChain.boundary <workspace_sym.planar.chain.PlanarChain.boundary>`).

    Parameters
    ----------
    chain : PlanarChain
        The chain, read by its attributes.
    arcs : list of BoundaryArc
        Every arc of every loop.
    loops : list of Loop
        The loops, outer ones first, each kind by decreasing area.
    counts : dict
        The number of arcs after each step: ``{"step0": ..., "step1": ..., "step2": ...}``.
    faces : dict
        Face index of the arrangement -> ``"inside"``, ``"outside"`` or ``"undecided"``.
    evidence : dict
        Face index -> how its status was decided: ``{"method": ..., ...}`` with the arc, the witness
        configuration or the probe point.
    undecided_area : float
        The total area of the undecided faces (0 when every face was decided).
    seconds : float
        Wall-clock time of the computation.
    arrangement : Arrangement
        The arrangement of the kept arcs.
    merged : dict, optional
        The slivers merged into their neighbours: ``{"faces", "area", "width_tolerance", "into"}``; empty when
        there were none.
    """

    chain: Any                # the PlanarChain (planar.chain), read by its attributes: the chain imports this module
    arcs: list
    loops: list
    counts: dict
    faces: dict               # face index -> "inside" / "outside" / "undecided", with the evidence in `evidence`
    evidence: dict
    undecided_area: float
    seconds: float
    arrangement: Arrangement = field(repr=False)
    merged: dict = field(default_factory=dict)   # slivers merged into their neighbours (see _merge_slivers)

    @property
    def area(self) -> float:
        """Area enclosed by the loops (Green's theorem over the arcs).

        Returns
        -------
        float
            The sum of the loops' signed areas (holes subtract), in the square of the chain's unit of length.
        """
        return float(sum(loop.area for loop in self.loops))

    @property
    def perimeter(self) -> float:
        """The total length of the boundary.

        Returns
        -------
        float
            The sum of ``radius * |sweep|`` over every arc of every loop.
        """
        return float(sum(a.radius * abs(a.sweep) for a in self.arcs))

    @cached_property
    def exact(self) -> list[dict]:
        """Closed forms of the arcs (:func:`~workspace_sym.planar.exact.closed_forms`), one dict per arc, computed
        once.

        Returns
        -------
        list of dict
            One dict per arc of :attr:`arcs`, in the same order.
        """
        return closed_forms(self)

    def _arc_arrays(self):
        rows = [(a.center[0], a.center[1], a.radius, min(a.start_angle, a.end_angle), abs(a.sweep)) for a in self.arcs]
        return np.array(rows, dtype=float).reshape(-1, 5).T

    def contains(self, point, *, tol: float = 1e-9) -> str:
        """``"inside"``, ``"outside"`` or ``"boundary"`` (within ``tol`` times the reach) — ray parity (paper §5).

        Parameters
        ----------
        point : array_like
            ``(2,)``: the point ``(x, y)``.
        tol : float, default 1e-9
            Distance to the nearest arc, relative to the chain's reach, within which the point is on the
            boundary.

        Returns
        -------
        str
            ``"inside"``, ``"outside"`` or ``"boundary"``.  With one joint the workspace is an arc: every point
            off it is ``"outside"``.
        """
        return str(self.classify(np.asarray(point, dtype=float).reshape(1, 2), tol=tol)[0])

    def classify(self, points, *, tol: float = 1e-9) -> np.ndarray:
        """:meth:`contains` for many points at once: an array of ``"inside"`` / ``"outside"`` / ``"boundary"``.

        Parameters
        ----------
        points : array_like
            ``(n, 2)`` points (one point ``(2,)`` is taken as ``(1, 2)``).
        tol : float, default 1e-9
            As in :meth:`contains`.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` object array of the three strings.
        """
        q = np.atleast_2d(np.asarray(points, dtype=float))
        out = np.full(len(q), "outside", dtype=object)
        if not self.arcs:
            return out
        arr = self._arc_arrays()
        for k in range(0, len(q), 4096):
            chunk = q[k:k + 4096]
            near = arc_distance(chunk, *arr).min(axis=1) <= tol * self.chain.reach
            # one joint: the workspace is an open arc with no inside, and ray parity means nothing
            inside = parity_inside(chunk, *arr, tol=tol * self.chain.reach) if self.chain.p > 1 else False
            out[k:k + 4096] = np.where(near, "boundary", np.where(inside, "inside", "outside"))
        return out

    def configurations(self, point, *, tol: float = 1e-9) -> np.ndarray:
        """Every configuration on a kept arc (Step 1) that reaches the boundary point ``point`` (radians, (k, p)).

        Empty when the point is not on the boundary.

        Parameters
        ----------
        point : array_like
            ``(2,)``: the point ``(x, y)``.
        tol : float, default 1e-9
            Distance relative to the chain's reach within which the point is on the boundary and on a kept arc.

        Returns
        -------
        numpy.ndarray
            ``(k, p)`` joint angles (radians), rounded to 12 decimals and without repeats; ``(0, p)`` when the
            point is not on the boundary.
        """
        q = np.asarray(point, dtype=float)
        if self.contains(q, tol=tol) != "boundary":
            return np.zeros((0, self.chain.p))
        out = []
        for arc in self.chain.kept_arcs():
            i = arc.free_joint - 1
            d = q - np.array(arc.center)
            if abs(math.hypot(*d) - arc.radius) > tol * self.chain.reach:
                continue
            rel = (math.atan2(d[1], d[0]) - arc.start_angle + 1e-12) % _TWO_PI - 1e-12
            lo, hi = arc.theta_sets[i]
            if rel <= hi - lo + 1e-12:
                out.append(arc.configuration(lo + min(max(rel, 0.0), hi - lo)))
        if not out:
            return np.zeros((0, self.chain.p))
        return np.unique(np.round(np.array(out), 12), axis=0)

    def table(self, *, exact: bool = False) -> ArcTable:
        """Rows in the form of the paper's Table 2: type and the set of every joint, in degrees (a list of dicts
        that a notebook displays as a table).

        Parameters
        ----------
        exact : bool, default False
            Whether the sets are the closed forms of :attr:`exact` (SymPy expressions in degrees) rather than
            floats.

        Returns
        -------
        ArcTable
            One ``{"type", "free_joint", "theta_sets"}`` dict per arc.
        """
        rows = []
        ex = self.exact if exact else None
        for k, a in enumerate(self.arcs):
            sets = []
            for j, s in enumerate(a.theta_sets):
                if ex is not None:
                    sets.append(tuple(ex[k]["theta_sets"][j]))
                else:
                    sets.append(tuple(degrees(v) for v in s))
            rows.append({"type": a.type, "free_joint": a.free_joint, "theta_sets": sets})
        return ArcTable(rows, joints=self.chain.p, exact=exact)

    def to_dict(self, *, exact: bool = False) -> dict:
        """The JSON object of ``workspace-sym boundary`` (docs/cli.md).

        Parameters
        ----------
        exact : bool, default False
            Whether to add the closed forms: an ``"exact"`` object per arc (strings of SymPy expressions) and
            ``"area_exact"``.

        Returns
        -------
        dict
            ``arcs`` (type, free joint, sets in degrees, centre, radius, start and end angles in radians, side),
            ``loops``, ``area``, ``perimeter``, ``counts``, ``undecided_area``, ``seconds`` and ``merged``.
        """
        arcs = []
        ex = self.exact if exact else None
        reach = self.chain.reach
        for k, a in enumerate(self.arcs):
            d = {"type": a.type, "free_joint": a.free_joint,
                 "theta_sets": [[degrees(v) for v in s] for s in a.theta_sets],
                 "center": [clean(a.center[0], scale=reach), clean(a.center[1], scale=reach)],
                 "radius": clean(a.radius, scale=reach), "start_angle": clean(a.start_angle, scale=_TWO_PI),
                 "end_angle": clean(a.end_angle, scale=_TWO_PI), "side": a.side}
            if ex is not None:
                e = ex[k]
                d["exact"] = {"theta_sets": [[str(v) for v in s] for s in e["theta_sets"]],
                              "center": [str(v) for v in e["center"]], "radius": str(e["radius"]),
                              "start_angle": str(e["start_angle"]), "end_angle": str(e["end_angle"])}
            arcs.append(d)
        out = {"arcs": arcs, "loops": [{"kind": l.kind, "arcs": list(l.arcs)} for l in self.loops],
               "area": self.area, "perimeter": self.perimeter, "counts": dict(self.counts),
               "undecided_area": self.undecided_area, "seconds": self.seconds, "merged": dict(self.merged)}
        if ex is not None:
            out["area_exact"] = str(exact_area(self, ex))
        return out

    def __repr__(self):
        n = len(self.loops)
        return f"Boundary({len(self.arcs)} arcs, {n} loop{'' if n == 1 else 's'}, area {fmt(self.area, 6, 'g')})"

    def polygon(self, *, step: float = 0.01):
        """The loops as polylines (list of (n, 2) arrays) for drawing and polygon checks.

        Parameters
        ----------
        step : float, default 0.01
            The largest angle between two points of an arc (radians); each arc has at least its two ends.

        Returns
        -------
        list of numpy.ndarray
            One ``(n, 2)`` array per loop, in :attr:`loops` order; a point shared by two arcs appears twice.
        """
        polys = []
        for loop in self.loops:
            pts = []
            for k in loop.arcs:
                a = self.arcs[k]
                n = max(2, int(abs(a.sweep) / step) + 1)
                t = np.linspace(a.start_angle, a.end_angle, n)
                pts.append(np.stack([a.center[0] + a.radius * np.cos(t), a.center[1] + a.radius * np.sin(t)], 1))
            polys.append(np.vstack(pts))
        return polys


# ---------------------------------------------------------------------- classification
def _tail_levers(lengths, lo, hi):
    """Upper bounds of ``|P_p - P_j|`` over boxes of relative angles (natural interval extension), (n, m)."""
    n, m = lo.shape
    levers = np.zeros((n, m))
    for j in range(m):
        phi = (np.zeros(n), np.zeros(n))
        x = (np.zeros(n), np.zeros(n))
        y = (np.zeros(n), np.zeros(n))
        for k in range(j, m):
            if k > j:
                phi = arith.add(phi, (lo[:, k], hi[:, k]))
            lk = arith.point(np.full(n, lengths[k]))
            x = arith.sub(x, arith.mul(lk, arith.sin(phi)))
            y = arith.add(y, arith.mul(lk, arith.cos(phi)))
        levers[:, j] = arith.up(np.sqrt(arith.up(np.maximum(x[0] ** 2, x[1] ** 2) + np.maximum(y[0] ** 2, y[1] ** 2))))
    return levers


def prove_unreachable(chain, q, *, max_boxes: int = 200_000) -> bool | None:
    """Prove that no configuration of the joint box reaches the point ``q``; None when the budget ran out.

    The first joint is eliminated: ``P_p = R(theta_1) v`` with
    ``v = l_1 e_y + (the chain of joints 2..p)``, so ``q`` is reached only if
    ``v`` lies on the arc ``{R(-theta_1) q}``.  The joints 2..p are bisected;
    a box is discarded when the disc ``|v - v(m)| <= sum_j lever_j h_j``
    (outward-rounded mean-value bound, levers from an interval enclosure of
    ``|P_p - P_j|`` over the box) misses that arc by more than a 1e-9 margin.

    Parameters
    ----------
    chain : PlanarChain
        The chain, read by its attributes.
    q : array_like
        ``(2,)``: the point.
    max_boxes : int, default 200000
        Budget of the bisection (:func:`~workspace_sym.interval.search.prove_all`).

    Returns
    -------
    bool or None
        True when proved unreachable; None when the budget ran out first (never False: no box is proved to
        reach ``q``).  With one joint, True when ``|q|`` differs from the length by more than the margin.
    """
    return _exclusion(chain, q, max_boxes)[0]


def _exclusion(chain, q, max_boxes: int, time_limit: float | None = None) -> tuple[bool | None, int]:
    """:func:`prove_unreachable` within ``max_boxes`` boxes and ``time_limit`` seconds: ``(proved, boxes used)``."""
    L = np.array(chain.lengths)
    q = np.asarray(q, dtype=float)
    rq = math.hypot(*q)
    aq = math.atan2(q[1], q[0])
    arc_start, arc_span = aq - chain.upper[0], chain.upper[0] - chain.lower[0]
    margin = 1e-9 * chain.reach
    if chain.p == 1:
        return abs(rq - L[0]) > margin or None, 0
    boxes = np.stack([chain.lower[1:], chain.upper[1:]], axis=1)[None].astype(float)

    def test(boxes):
        """Code 1 for a box whose disc misses the arc; split the others along their largest ``lever * h``."""
        lo, hi = boxes[:, :, 0], boxes[:, :, 1]
        n = len(lo)
        m = 0.5 * (lo + hi)
        h = np.maximum(arith.up(hi - m), arith.up(m - lo))
        # v(m): l_1 e_y plus the tail at the box centre (theta_1 = 0)
        phi = arith.point(np.zeros(n))
        vx = arith.point(np.zeros(n))
        vy = arith.point(np.full(n, L[0]))
        for k in range(1, chain.p):
            phi = arith.add(phi, arith.point(m[:, k - 1]))
            lk = arith.point(np.full(n, L[k]))
            vx = arith.sub(vx, arith.mul(lk, arith.sin(phi)))
            vy = arith.add(vy, arith.mul(lk, arith.cos(phi)))
        levers = _tail_levers(L[1:], lo, hi)
        weights = arith.up(levers * h)
        rad = weights[:, 0]
        for j in range(1, weights.shape[1]):
            rad = arith.up(rad + weights[:, j])
        # distance from the enclosure of v(m) to the arc of radius |q| (float, less a margin)
        cx, cy = 0.5 * (vx[0] + vx[1]), 0.5 * (vy[0] + vy[1])
        slack = np.maximum(vx[1] - vx[0], vy[1] - vy[0])
        rho = np.hypot(cx, cy)
        on = in_span(np.arctan2(cy, cx), arc_start, arc_span)
        e0 = np.hypot(cx - rq * math.cos(arc_start), cy - rq * math.sin(arc_start))
        e1 = np.hypot(cx - rq * math.cos(arc_start + arc_span), cy - rq * math.sin(arc_start + arc_span))
        dist = np.where(on, np.abs(rho - rq), np.minimum(e0, e1)) - slack - margin
        return np.where(dist > rad, 1, 0), np.argmax(weights, axis=1)

    with np.errstate(all="ignore"):
        proved, used = prove_all(boxes, test, split="given", stop=StopAt(max_boxes=max_boxes, time_limit=time_limit))
    return proved, used


def _arc_arc_distance(a, b) -> float:
    """Smallest distance between two circular arcs ``(cx, cy, r, start, span)`` (counter-clockwise spans)."""
    (ax, ay, ar, a0, aw), (bx, by, br, b0, bw) = a, b
    ends_a = np.array([[ax + ar * math.cos(t), ay + ar * math.sin(t)] for t in (a0, a0 + aw)])
    ends_b = np.array([[bx + br * math.cos(t), by + br * math.sin(t)] for t in (b0, b0 + bw)])
    best = min(arc_distance(ends_a, *[np.array([v]) for v in b]).min(),
               arc_distance(ends_b, *[np.array([v]) for v in a]).min())
    d = math.hypot(bx - ax, by - ay)
    if d > 0:
        ex, ey = (bx - ax) / d, (by - ay) / d
        # the circles' intersection points, and the pairs of points on the line of centres
        along = (ar * ar - br * br + d * d) / (2 * d)
        h2 = ar * ar - along * along
        pts = []
        if h2 >= 0:
            h = math.sqrt(h2)
            pts += [(ax + along * ex - s * h * ey, ay + along * ey + s * h * ex) for s in (1, -1)]
        pts += [(ax + s * ar * ex, ay + s * ar * ey) for s in (1, -1)]
        for x, y in pts:
            if in_span(math.atan2(y - ay, x - ax), a0, aw):
                best = min(best, float(arc_distance(np.array([[x, y]]), *[np.array([v]) for v in b])[0, 0]))
    return float(best)


def outside_every_turn(chain, q) -> bool:
    """Whether ``q`` lies strictly outside the annulus ``2 l_max - R <= r <= R`` that holds every configuration
    whatever the limits (triangle inequality), decided in exact rational arithmetic.

    A face of the arrangement is reachable everywhere or nowhere, so one such point proves the whole face outside:
    the hole of a chain whose joints turn a hair short of a full turn is tangent to reachable points, and no finite
    interval exclusion can cover it.

    Parameters
    ----------
    chain : PlanarChain
        The chain, read by its exact lengths.
    q : array_like
        ``(2,)``: the point (floats, compared as the rationals they are).

    Returns
    -------
    bool
        True when ``q`` is proved outside the annulus; False otherwise, and always when a length is irrational
        (no claim is made).
    """
    from fractions import Fraction

    if not all(length.is_Rational for length in chain.exact_lengths):
        return False                            # irrational lengths: no exact comparison here, no claim
    r2 = sum(Fraction(float(v)) ** 2 for v in q)
    lengths = [Fraction(int(length.p), int(length.q)) for length in chain.exact_lengths]
    reach, longest = sum(lengths), max(lengths)
    inner = 2 * longest - reach
    return r2 > reach * reach or (inner > 0 and r2 < inner * inner)


def unreachable_via_subchain(chain, q, *, margin: float = 1e-9):
    """Decide whether ``q`` is reachable through the workspace ``W`` of the joints 2..p.

    ``P_p = R(theta_1) (l_1 e_y + w)`` with ``w`` in ``W``, so ``q`` is reached
    exactly when the arc ``{R(-theta_1) q - l_1 e_y}`` meets ``W``.  With
    ``W``'s boundary from this same method: when a point of the arc lies
    inside ``W``, a configuration of the subchain reaching it (least squares)
    completes a witness; when both ends are outside and the arc stays more than
    ``margin`` times the reach from every boundary arc of ``W``, ``q`` is
    unreachable.  Float geometry with explicit tolerances, like the rest of Step 2.

    Parameters
    ----------
    chain : PlanarChain
        The chain, read by its attributes.
    q : array_like
        ``(2,)``: the point.
    margin : float, default 1e-9
        The tolerance, relative to the chain's reach.

    Returns
    -------
    tuple
        ``(True, None)`` (unreachable), ``(False, theta)`` (reachable, ``theta`` a ``(p,)`` witness
        configuration in radians, or None when the least squares did not land within the tolerance) or
        ``(None, None)`` (undecided, also when the workspace of joints 2..p is itself unreliable or has
        undecided faces).
    """
    q = np.asarray(q, dtype=float)
    tol = margin * chain.reach
    rq = math.hypot(*q)
    aq = math.atan2(q[1], q[0])
    start, span = aq - chain.upper[0], chain.upper[0] - chain.lower[0]
    if chain.p == 1:
        if abs(rq - chain.lengths[0]) > tol:
            return True, None
        return None, None
    sub = chain.subchain
    l1 = chain.lengths[0]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            w = sub.boundary(run=RunOn(progress=False))
    except BoundaryError:                       # W itself is not reliable: no argument through it
        return None, None
    if w.undecided_area > 0 or not w.arcs:
        return None, None
    theta1 = np.linspace(chain.lower[0], chain.upper[0], 257)
    pts = np.stack([rq * np.cos(aq - theta1), rq * np.sin(aq - theta1) - l1], axis=1)
    verdict = w.classify(pts, tol=margin)
    inside = np.flatnonzero(verdict == "inside")
    if len(inside):
        k = inside[len(inside) // 2]
        th, _ = witness_near(sub, pts[k], samples=2048, seed=int(k), k=32, iterations=100)
        theta = np.concatenate([[theta1[k]], th[0]])
        return False, (theta if math.dist(chain.forward(theta), q) <= tol else None)
    if (verdict[[0, -1]] == "boundary").any():
        return None, None
    if rq <= tol:
        return True, None
    arc = (0.0, -l1, rq, start, span)
    for a in w.arcs:
        other = (a.center[0], a.center[1], a.radius, min(a.start_angle, a.end_angle), abs(a.sweep))
        if _arc_arc_distance(arc, other) <= tol:
            return None, None
    return True, None


def _local_witness(chain, targets, starts, iterations: int = 60):
    """Damped least squares projected on the joint box, from several starts per target.

    ``targets`` (m, 2), ``starts`` (m, k, p): returns the best configuration per
    target (m, p) and its distance to the target (m,).
    """
    lo, hi = np.array(chain.lower), np.array(chain.upper)
    theta = np.array(starts, dtype=float)
    target = np.broadcast_to(np.asarray(targets, dtype=float)[:, None, :], theta.shape[:2] + (2,))
    for _ in range(iterations):
        pts = chain.joints_positions(theta)
        r = target - pts[..., -1, :]
        v = pts[..., -1:, :] - pts[..., :-1, :]                   # dP/dtheta_j = sigma(P_p - P_j)
        J = np.stack([-v[..., 1], v[..., 0]], axis=-2)             # (m, k, 2, p)
        JJt = J @ np.swapaxes(J, -1, -2) + 1e-9 * np.eye(2)
        step = (np.swapaxes(J, -1, -2) @ np.linalg.solve(JJt, r[..., None]))[..., 0]
        theta = np.clip(theta + step, lo, hi)
    err = np.hypot(*np.moveaxis(chain.forward(theta) - target, -1, 0))
    k = np.argmin(err, axis=1)
    rows = np.arange(len(theta))
    return theta[rows, k], err[rows, k]



def witness_near(chain, targets, *, starts=None, points=None, samples: int = 4096, seed: int = 0, k: int = 16,
                 iterations: int = 60):
    """Configurations reaching ``targets`` (m, 2): least squares from the ``k`` sampled configurations whose
    end points are nearest each target.  ``starts`` (and their end ``points``) may be given to reuse a sample.

    Parameters
    ----------
    chain : PlanarChain
        The chain, read by its attributes.
    targets : array_like
        ``(m, 2)`` points (one point ``(2,)`` is taken as ``(1, 2)``).
    starts : numpy.ndarray, optional
        ``(n, p)`` configurations to start from (radians); by default ``chain.sample(samples, seed=seed)``.
    points : numpy.ndarray, optional
        ``(n, 2)`` end points of ``starts``; by default computed.
    samples : int, default 4096
        Size of the random sample drawn when ``starts`` is not given.
    seed : int, default 0
        Seed of that sample.
    k : int, default 16
        The number of starts per target.
    iterations : int, default 60
        Damped least-squares steps, projected on the joint box.

    Returns
    -------
    tuple of numpy.ndarray
        The best configuration per target ``(m, p)`` (radians, within the limits) and its distance to the
        target ``(m,)``.
    """
    targets = np.atleast_2d(np.asarray(targets, dtype=float))
    if starts is None:
        starts = chain.sample(samples, seed=seed)
    if points is None:
        points = chain.forward(starts)
    near = np.argsort(((points[None, :, :] - targets[:, None, :]) ** 2).sum(-1), axis=1)[:, :k]
    return _local_witness(chain, targets, starts[near], iterations)

SLIVER_WIDTH = RESOLUTION     # faces narrower than this times the reach are merged into their neighbours


def _slivers(chain, arr: Arrangement) -> dict:
    """Bounded faces whose mean width ``2 area / perimeter`` is at most ``SLIVER_WIDTH`` times the reach.

    Two arcs closer than that (circles nearly tangent or nearly coincident,
    as when joints span nearly a full turn) enclose such faces.  They are
    100 times the arrangement's tolerance across, too thin to hold a probe
    with clearance, so no witness or exclusion can decide them: they are
    merged instead (:func:`_merge_slivers`).  Returns ``{face: width}``.
    """
    out = {}
    for f in range(len(arr.face_cycles)):
        edges = arr.face_edges(f)
        perimeter = sum(arr.circles[arr.edges[k].circle, 2] * arr.edges[k].span for k in edges)
        width = 2 * abs(arr.face_area[f]) / perimeter if perimeter > 0 else 0.0
        if width <= SLIVER_WIDTH * chain.reach:
            out[f] = float(width)
    return out


def _merge_slivers(arr: Arrangement, status, evidence, slivers: dict) -> dict:
    """Give each group of adjacent slivers the status of the decided faces around it, so that the arcs
    between them (closer than the sliver width) become one: inside when every decided neighbour is inside,
    outside when every one is outside (the unbounded face is outside); between inside and outside, a sliver
    keeps a status proved for it and is outside otherwise; with no decided neighbour it stays undecided.
    Returns what was merged, for :attr:`Boundary.merged`."""
    parent = {f: f for f in slivers}

    def find(f):
        while parent[f] != f:
            parent[f] = parent[parent[f]]
            f = parent[f]
        return f

    sides = [(int(arr.half_face[2 * k]), int(arr.half_face[2 * k + 1])) for k in range(len(arr.edges))]
    for a, b in sides:
        if a in slivers and b in slivers:
            parent[find(a)] = find(b)
    around: dict[int, set[str]] = {}
    for a, b in sides:
        for f, g in ((a, b), (b, a)):
            if f in slivers and g not in slivers:
                around.setdefault(find(f), set()).add("outside" if g < 0 else status[g])
    into = {"inside": 0, "outside": 0, "undecided": 0}
    area = 0.0
    for f, width in slivers.items():
        near = around.get(find(f), set()) & {"inside", "outside"}
        if len(near) == 1:
            new = near.pop()
        elif not near:
            new = "undecided"
        else:
            new = status[f] if status[f] in ("inside", "outside") else "outside"
        status[f] = new
        evidence[f] = {"method": "merged sliver", "width": width, "into": new}
        into[new] += 1
        area += float(abs(arr.face_area[f]))
    if not slivers:
        return {}
    return {"faces": len(slivers), "area": area, "width_tolerance": SLIVER_WIDTH, "into": into}


@dataclass
class _Proofs:
    """The boxes and seconds the interval exclusions of one boundary may spend: ``per_proof`` boxes each
    (``proof_boxes``), ``boxes_left`` over them all and a ``deadline`` (``stop``); ``spent`` names the budget
    that ran out, when one did."""

    per_proof: int
    boxes_left: int | None
    deadline: float | None
    spent: str = ""

    def excluded(self, chain, q) -> bool:
        """Whether ``q`` is proved unreachable within what is left (False once a budget is spent)."""
        allowed = self.per_proof if self.boxes_left is None else min(self.per_proof, self.boxes_left)
        seconds = None if self.deadline is None else self.deadline - time.perf_counter()
        if allowed <= 0 or (seconds is not None and seconds <= 0):
            self.spent = self.spent or ("max_boxes" if allowed <= 0 else "time_limit")
            return False
        proved, used = _exclusion(chain, q, allowed, seconds)
        if self.boxes_left is not None:
            self.boxes_left -= used
        return bool(proved)


def _classify(chain, arr: Arrangement, kept, samples, seed, proofs: _Proofs, slivers=()):
    nf = len(arr.face_cycles)
    status = ["unknown"] * nf
    evidence = {}
    notes = []
    for k, e in enumerate(arr.edges):
        for s in e.sources:
            h = 2 * k if kept[s].side == -1 else 2 * k + 1     # the half-edge with the arc's side on its left
            f = arr.half_face[h]
            if f < 0:
                notes.append(f"Step 1 arc {s} points into the unbounded face")
            elif status[f] == "unknown":
                status[f], evidence[int(f)] = "inside", {"method": "Lemma 3.1", "arc": int(s)}
    todo = [f for f in range(nf) if status[f] == "unknown" and f not in slivers]
    if not todo:
        return status, evidence, notes
    theta = chain.sample(samples, seed=seed)
    pts = chain.forward(theta)
    probes = {}
    for f in todo:
        hit = np.flatnonzero(arr.in_face(pts, f))
        if len(hit):
            hit = hit[:64][arr.face_clearance(pts[hit[:64]], f) > 10 * arr.tol]
        if len(hit):
            status[f], evidence[f] = "inside", {"method": "witness", "configuration": theta[hit[0]].tolist()}
            continue
        q, clearance = arr.interior_point(f)
        if q is None:
            notes.append(f"face {f}: no interior point with clearance found")
            status[f] = "undecided"
            continue
        probes[f] = (q, clearance)
    if probes:
        faces = list(probes)
        qs = np.array([probes[f][0] for f in faces])
        found, err = witness_near(chain, qs, starts=theta, points=pts)
        for f, th, e in zip(faces, found, err):
            q, clearance = probes[f]
            if e < 0.5 * clearance:
                status[f], evidence[f] = "inside", {"method": "witness", "configuration": th.tolist()}
                continue
            if outside_every_turn(chain, q):
                status[f], evidence[f] = "outside", {"method": "annulus of full turns", "point": q.tolist()}
                continue
            decided, witness = unreachable_via_subchain(chain, q)
            if decided is False and witness is not None:
                status[f], evidence[f] = "inside", {"method": "witness through joints 2..p",
                                                    "configuration": witness.tolist()}
            elif decided is not False and proofs.excluded(chain, q):
                status[f], evidence[f] = "outside", {"method": "interval exclusion", "point": q.tolist()}
            elif decided:
                status[f], evidence[f] = "outside", {"method": "workspace of joints 2..p", "point": q.tolist()}
            else:
                status[f], evidence[f] = "undecided", {"method": "none conclusive", "point": q.tolist()}
    return status, evidence, notes


def build_boundary(chain, *, samples: int = 4096, seed: int = 0, proof_boxes: int = 4_000,
                   stop: StopAt = StopAt(), run: RunOn = RunOn(), max_boxes: int | None = None,
                   progress: bool | None = None) -> Boundary:
    """Step 2 for ``chain`` (see :meth:`workspace_sym.planar.chain.PlanarChain.boundary`).

    Parameters
    ----------
    chain : PlanarChain
        The chain, read by its attributes (its Steps 0 and 1).
    samples : int, default 4096
        The number of random configurations drawn to find witnesses.
    seed : int, default 0
        Seed of that sample.
    proof_boxes : int, default 4000
        Box budget of the interval exclusion of each face.
    stop : StopAt
        When the interval exclusions stop: ``max_boxes`` boxes over all of them, ``time_limit`` seconds for the
        call.  A face whose proof the budget cuts short stays undecided (a warning says which budget, and the
        area becomes a lower bound).  ``section_boxes`` does not apply and is refused.
    run : RunOn
        ``progress``: show the stages (True always, False never, None on an interactive output once the run
        has lasted a second).  The boundary is built in this process and keeps no boxes: the other fields are
        refused.
    max_boxes : int, optional
        Deprecated spelling of ``proof_boxes`` (a :class:`DeprecationWarning`).
    progress : bool, optional
        Deprecated spelling of ``run=RunOn(progress=...)`` (a :class:`DeprecationWarning`).

    Returns
    -------
    Boundary
        A new boundary (:meth:`PlanarChain.boundary <workspace_sym.planar.chain.PlanarChain.boundary>` keeps
        it; this function does not).

    Raises
    ------
    InvalidParameterError
        When ``proof_boxes`` is not a positive integer, or ``stop`` or ``run`` sets a field that does not apply.
    BoundaryError
        When the loops found contradict a property every chain has (an area larger than the annulus that holds
        every configuration, or a negative one).

    Warns
    -----
    UserWarning
        When faces stay undecided, and for each note of the classification.
    DeprecationWarning
        For ``max_boxes=`` and ``progress=``.
    """
    t0 = time.perf_counter()
    stop, run = with_legacy_keywords("build_boundary", stop, run, progress=progress)
    if max_boxes is not None:
        deprecated("build_boundary", "max_boxes", "proof_boxes=... (each face's proof; stop=StopAt(max_boxes=...) "
                   "bounds them all)")
        proof_boxes = max_boxes
    if isinstance(proof_boxes, bool) or not isinstance(proof_boxes, int) or proof_boxes < 1:
        raise InvalidParameterError(f"proof_boxes must be a positive integer; got {proof_boxes!r}",
                                    parameter="proof_boxes")
    refuse_stop("build_boundary", stop, ("max_boxes", "time_limit"), "stops on the boxes and seconds of its proofs")
    refuse_run("build_boundary", run)
    proofs = _Proofs(proof_boxes, stop.max_boxes, None if stop.time_limit is None else t0 + stop.time_limit)
    say = stage_bar(run.progress if run.progress is not None else stop.progress, "boundary", 4)
    say("steps 0 and 1")
    step0 = len(chain.step0["free"])
    kept = chain.step1
    rows = [(*a.center, a.radius, a.start_angle, a.end_angle - a.start_angle) for a in kept]
    say(f"arrangement of {len(kept)} arcs")
    arr = Arrangement(rows, scale=chain.reach)
    try:
        return _boundary_of(chain, kept, arr, step0, t0, say, samples=samples, seed=seed, proofs=proofs)
    finally:
        say(None)


def _boundary_of(chain, kept, arr, step0, t0, say, *, samples, seed, proofs: _Proofs) -> Boundary:
    """Classification of the faces of ``arr`` and the walk along the boundary (:func:`build_boundary`)."""
    if chain.p == 1:
        a = kept[0] if kept else None
        arcs = [] if a is None else [BoundaryArc(a.type, 1, a.theta_sets, a.center, a.radius, a.start_angle,
                                                 a.end_angle, a.side, 0)]
        loops = [Loop("outer", (0,), 0.0)] if arcs else []
        return Boundary(chain, arcs, loops, {"step0": step0, "step1": len(kept), "step2": len(arcs)}, {}, {}, 0.0,
                        time.perf_counter() - t0, arr)
    say(f"classifying {len(arr.face_cycles)} faces")
    slivers = _slivers(chain, arr)
    status, evidence, notes = _classify(chain, arr, kept, samples, seed, proofs, slivers)
    say("walking the loops")
    merged_slivers = _merge_slivers(arr, status, evidence, slivers)
    inside = np.array([s == "inside" for s in status] + [False])      # index -1: unbounded face
    left_in = inside[arr.half_face]
    right_in = inside[arr.half_face[np.arange(len(arr.half_face)) ^ 1]]
    is_boundary = left_in & ~right_in
    # walk: from the head of h, turn clockwise around the vertex to the next boundary half-edge
    pos = {h: (v, k) for v, hs in enumerate(arr.outgoing) for k, h in enumerate(hs)}
    seen = np.zeros(len(is_boundary), bool)
    loops_h = []
    for h0 in np.flatnonzero(is_boundary):
        if seen[h0]:
            continue
        loop, h = [], int(h0)
        while not seen[h]:
            seen[h] = True
            loop.append(h)
            v, k = pos[h ^ 1]
            hs = arr.outgoing[v]
            for step in range(1, len(hs) + 1):
                g = hs[(k - step) % len(hs)]
                if is_boundary[g]:
                    break
            h = g
        loops_h.append(loop)
    arcs, loops = [], []
    for loop in loops_h:
        pieces = [_piece(arr, kept, h) for h in loop]
        merged: list[dict] = []
        for pc in pieces:
            if merged and merged[-1]["circle"] == pc["circle"] and merged[-1]["source"] == pc["source"]:
                merged[-1]["a1"] += pc["a1"] - pc["a0"]
            else:
                merged.append(dict(pc))
        first, last = merged[0], merged[-1]
        if len(merged) > 1 and first["circle"] == last["circle"] and first["source"] == last["source"]:
            merged[0]["a0"] -= merged[-1]["a1"] - merged[-1]["a0"]
            merged.pop()
        area = float(sum(arc_area_term(*_circle(arr, m), m["a0"], m["a1"]) for m in merged))
        if area > 0:  # start the outer loop at its point farthest from the origin
            far = [np.hypot(*arr.circles[m["circle"], :2]) + arr.circles[m["circle"], 2] for m in merged]
            k = int(np.argmax(far))
            merged = merged[k:] + merged[:k]
        base = len(arcs)
        arcs.extend(_boundary_arc(chain, kept, arr, m) for m in merged)
        loops.append(Loop("outer" if area > 0 else "hole", tuple(range(base, len(arcs))), area))
    loops.sort(key=lambda l: (l.kind != "outer", -abs(l.area)))
    undecided = float(sum(arr.face_area[f] for f, s in enumerate(status) if s == "undecided"))
    _check_consistent(chain, sum(loop.area for loop in loops), undecided)
    if undecided > 0:
        cut = f"; the proofs stopped at stop.{proofs.spent}" if proofs.spent else ""
        warnings.warn(f"{sum(s == 'undecided' for s in status)} face(s) of total area {undecided:.3g} could not be "
                      f"classified (no witness, interval exclusion within proof_boxes={proofs.per_proof}{cut}, and "
                      f"the argument through joints 2..p inconclusive); the area is a lower bound", stacklevel=4)
    for note in notes:
        warnings.warn(note, stacklevel=4)
    counts = {"step0": step0, "step1": len(kept), "step2": len(arcs)}
    faces = {f: s for f, s in enumerate(status)}
    return Boundary(chain, arcs, loops, counts, faces, evidence, undecided, time.perf_counter() - t0, arr,
                    merged_slivers)


def _check_consistent(chain, area: float, undecided: float) -> None:
    """Refuse a boundary that contradicts what holds for every chain: the workspace lies in the annulus
    ``max(0, 2 l_max - R) <= r <= R`` its joints reach when they all turn fully, and no face has negative area.

    Arcs that are nearly tangent at clusters of vertices (limits a hair short of a full turn) can be ordered wrongly
    around a vertex, and a hole is then lost; this check turns such a silent wrong area into an error.
    """
    lengths = [float(v) for v in chain.lengths]
    reach = sum(lengths)
    inner = max(0.0, 2 * max(lengths) - reach)
    bound = math.pi * (reach - inner) * (reach + inner)
    slack = 1e-9 * math.pi * reach * reach
    if area > bound + slack or undecided < -slack or area < -slack:      # undecided faces are honest doubt
        raise BoundaryError(f"the boundary of this chain could not be computed reliably: it gives an area of "
                            f"{area:.10g} (undecided {undecided:.3g}) where every configuration lies in an annulus of "
                            f"area {bound:.10g}; limits a hair short of a full turn make nearly tangent arcs whose "
                            f"order the arrangement cannot tell (give such a joint a full turn, or limits further "
                            f"from one)", parameter="lower")


def _piece(arr, kept, h):
    e = arr.edges[h // 2]
    want = -1 if h % 2 == 0 else 1
    srcs = [s for s in e.sources if kept[s].side == want] or list(e.sources)
    cx, cy, r, a0, a1 = arr.half_edge_arc(h)
    return {"circle": e.circle, "source": min(srcs), "a0": a0, "a1": a1}


def _circle(arr, piece: dict) -> tuple[float, float, float]:
    """Centre and radius ``(cx, cy, r)`` of the circle a loop's piece runs on."""
    cx, cy, r = arr.circles[piece["circle"]]
    return cx, cy, r


def _boundary_arc(chain, kept, arr, m) -> BoundaryArc:
    src = kept[m["source"]]
    cx, cy, r = _circle(arr, m)
    i = src.free_joint - 1
    lo_src = src.theta_sets[i][0]

    def theta_at(angle):
        rel = (angle - src.start_angle + 1e-9) % _TWO_PI - 1e-9
        return lo_src + min(max(rel, 0.0), src.theta_sets[i][1] - lo_src)

    if src.end_angle - src.start_angle >= _TWO_PI - 1e-12:
        # a full-turn joint: the piece may cross the joint's -180/180 seam, so follow it from its start
        t_start = theta_at(m["a0"])
        t0, t1 = sorted((t_start, t_start + m["a1"] - m["a0"]))
        turns = math.ceil((lo_src - t0 - 1e-9) / _TWO_PI)       # from [lo, hi] on: -180..180, not -540..-180
        t0, t1 = t0 + turns * _TWO_PI, t1 + turns * _TWO_PI
    else:
        t0, t1 = sorted((theta_at(m["a0"]), theta_at(m["a1"])))
    sets = tuple((float(t0), float(t1)) if k == i else s for k, s in enumerate(src.theta_sets))
    return BoundaryArc(src.type, src.free_joint, sets, (float(src.center[0]), float(src.center[1])), float(src.radius),
                       float(m["a0"]), float(m["a1"]), src.side, m["source"])
