"""Certified reachability maps: position cells times approach directions, each pair proved or undecided.

:func:`reach_map` runs the certified pose engine (:func:`~workspace_sym.serial.api.reach` with
``Pose(approach=d_k, cone=cone)``) once for each of ``K`` approach directions ``d_k`` and reads each run's paving
on one grid of cubic cells of side ``delta``.  A pair (cell, ``k``) is

* **proved reachable** (code 1) when the closed cell is a subset of the union of that run's inner boxes: every
  point of the cell is the tool point of a configuration within the limits whose approach axis lies within
  ``cone`` degrees of ``d_k``;
* **proved unreachable** (code -1) when the cell is a subset of the union of its outer boxes and of the outside of
  its root box: no point of the cell is reached with an approach axis within the cone;
* **undecided** (code 0) otherwise.

The subset tests compare floats only, never round (:func:`covered_cells`), so a cell covered by boxes "up to
rounding" is not proved.  docs/methods.md section 9 gives the argument.  A :class:`ReachMap` holds the codes
(``int8``, the verdict codes of :mod:`workspace_sym.interval.verdict`), the capability bracket of each cell, a
vectorised :meth:`ReachMap.query`, and is saved as one ``.npz`` naming its whole problem.
"""

from __future__ import annotations

import hashlib
import json
import math
import time
import warnings
import zipfile
from dataclasses import dataclass, field
from functools import lru_cache, partial
from pathlib import Path

import numpy as np

from ..errors import InvalidParameterError, WorkspaceError
from ..files import write_npz
from ..interval import arith
from ..interval.boxes import check_delta
from ..interval.driver import RunOn, StopAt
from ..interval.executor import Inline, refuse_result, runner_for
from ..interval.fingerprint import Fingerprint, check_fingerprint
from ..interval.verdict import CODE, INSIDE, OUTSIDE, UNDECIDED, codes_from_masks
from ..kinematics import DHRobot
from ..progress import progress_bar
from .api import Pose, reach
from .model import parameter_values, reach_model
from .stored import reach_problem
from .tuning import DEFAULT

__all__ = ["ReachMap", "reach_map", "sphere_directions", "covering_angle", "covered_cells", "free_cells",
           "map_problem", "MAP_FORMAT", "MAP_METHOD", "SECTION_METHOD", "METHODS"]

MAP_FORMAT = 1
"""The version of the files :meth:`ReachMap.save` writes (a file of another version is refused)."""

MAP_METHOD = "union of pose pavings"
"""How the pairs are proved: each direction's certified pose paving, its boxes' union tested cell by cell."""

SECTION_METHOD = "section proofs and the position paving"
"""The other way (``method="section"``): pairs proved reachable from certified solutions of the section of an arm
turned by its first joint (:mod:`workspace_sym.serial.mapsection`), cells proved unreachable from its position
paving, and pairs from the paving of its wrist point (:func:`~workspace_sym.serial.mapsection.wrist_unreachable`)."""

METHODS = {"pavings": MAP_METHOD, "section": SECTION_METHOD}
"""The values of ``reach_map(method=...)`` and what each records as the map's method."""

SECTION_OPTIONS: dict[str, int | bool | None] = {"cell": None, "local": 96, "samples": 10_000_000,
                                                 "branch_samples": 1_000_000, "split": 4, "retries": 32, "wrist": True}
"""The section method's defaults (``cell``: the section cells' side, None for ``delta / 10``; ``samples``: the random
configurations that seed Newton where it aims the approach, ``branch_samples`` where it cannot (the seeds are then
the solutions' branches: the Puma proves the same 4,577 pairs from 10^7 as from 10^6); ``wrist``: the pairs proved
unreachable from the wrist point's paving are tried)."""

WRIST_CELLS = 50_000_000
"""The most cells of the grid on which the section method reads the wrist point's paving (one byte each)."""

MAX_PIECES = 4096
"""The most pieces the exact union test splits one cell into before it leaves the cell undecided."""

_CHUNK = 1 << 16         # points a query handles at once (its arrays stay in the cache)
_RIM = 1e-12            # a query's approach must lie this far (relative) inside a cone to be read as held by it


def sphere_directions(count: int) -> np.ndarray:
    """A deterministic near-uniform set of ``count`` unit vectors.

    1: straight down; 2: up and down; 6: the cube's faces; 14: its faces and corners; 26: its faces, edges and
    corners (each normalised); any other count: the Fibonacci spiral (``z_i = 1 - (2 i + 1) / count``, longitudes
    by the golden angle).

    Parameters
    ----------
    count : int
        The number of directions, 1 or more.

    Returns
    -------
    numpy.ndarray
        ``(count, 3)`` unit vectors.

    Raises
    ------
    InvalidParameterError
        ``count`` not a whole number of at least 1.

    Examples
    --------
    >>> sphere_directions(2)
    array([[ 0.,  0.,  1.],
           [ 0.,  0., -1.]])
    >>> sphere_directions(26).shape
    (26, 3)
    """
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise InvalidParameterError(f"directions must be a whole number of at least 1 or a (K, 3) array of "
                                    f"nonzero vectors; got {count!r}", parameter="directions")
    count = int(count)
    if count == 1:
        return np.array([[0.0, 0.0, -1.0]])
    if count == 2:
        return np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
    cube = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1) if (i, j, k) != (0, 0, 0)],
                    dtype=float)
    ones = np.abs(cube).sum(axis=1)
    chosen = {6: ones == 1, 14: (ones == 1) | (ones == 3), 26: ones > 0}
    if count in chosen:
        pick = cube[chosen[count]]
        return pick / np.linalg.norm(pick, axis=1)[:, None]
    i = np.arange(count)
    z = 1.0 - (2.0 * i + 1.0) / count
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = i * math.pi * (3.0 - math.sqrt(5.0))
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def covering_angle(directions) -> float:
    """The largest angle, in degrees, from any unit vector to its nearest direction of ``directions``.

    For directions whose convex hull holds the origin inside, it is the largest angular radius of the caps
    through the vertices of a hull facet (the sphere's Voronoi vertices are the facets' poles); otherwise (fewer
    than four directions, all in a closed half-space) it is estimated from 20,000 spiral points, a value below
    the true one by at most their spacing (about 1.6 degrees).  It is a description of the cover, never used in a
    proof.

    Parameters
    ----------
    directions : array_like
        ``(K, 3)`` unit vectors.

    Returns
    -------
    float
        Degrees in ``[0, 180]``.

    Examples
    --------
    >>> round(covering_angle(sphere_directions(6)), 4)          # a cube's corner from its faces
    54.7356
    """
    d = np.asarray(directions, dtype=float)
    if len(d) >= 4:
        from scipy.spatial import ConvexHull, QhullError

        try:
            hull = ConvexHull(d)
            offsets = -hull.equations[:, 3]             # n . x = offset on each facet, n its outward unit normal
            if np.all(offsets > 1e-9):
                return float(np.degrees(np.arccos(np.clip(offsets.min(), -1.0, 1.0))))
        except (QhullError, ValueError):        # a degenerate hull (coplanar directions): the estimate below
            pass
    probe = sphere_directions(20_000)
    return float(np.degrees(np.arccos(np.clip((probe @ d.T).max(axis=1).min(), -1.0, 1.0))))


def _directions(directions) -> np.ndarray:
    """``directions`` as ``(K, 3)`` unit vectors (a count, or an array of nonzero vectors)."""
    if isinstance(directions, (int, np.integer)) and not isinstance(directions, bool):
        return sphere_directions(int(directions))
    try:
        d = np.array(directions, dtype=float)
    except (TypeError, ValueError):
        d = np.zeros((0,))
    if d.ndim != 2 or d.shape[1] != 3 or len(d) < 1 or not np.isfinite(d).all():
        raise InvalidParameterError(f"directions must be a whole number of at least 1 or a (K, 3) array of finite "
                                    f"vectors; got {directions!r}", parameter="directions")
    norms = np.linalg.norm(d, axis=1)
    if not (norms > 0).all():
        raise InvalidParameterError(f"directions: direction {int(np.argmin(norms))} is the zero vector; expected "
                                    "nonzero vectors", parameter="directions")
    return d / norms[:, None]


def _check_cone(cone) -> float:
    if isinstance(cone, bool) or not isinstance(cone, (int, float, np.integer, np.floating)) or not (
            math.isfinite(cone) and 0 < cone <= 180):
        raise InvalidParameterError(f"cone must be a half-angle in degrees in (0, 180]; got {cone!r}",
                                    parameter="cone")
    return float(cone)


# ---------------------------------------------------------------------------------------------------------------
# the exact covering test


def covered_cells(edges, boxes: np.ndarray, exterior: np.ndarray | None = None) -> np.ndarray:
    """Which cells of the grid ``edges`` are subsets of the union of the closed ``boxes`` (and, with
    ``exterior``, of the open outside of that box), decided exactly.

    The test compares floats and never computes one: a cell inside one box (``lo <= e_i``, ``e_{i+1} <= hi``
    on every axis) is covered; a cell overlapped by several boxes is split at the boxes' faces that cross it
    (the pieces' union is the cell) until each piece lies inside one box (covered) or some piece meets no box
    (not covered, or not proved: more than :data:`MAX_PIECES` pieces).  A cell whose float sum of overlaps falls
    short of its volume is not tried.

    Parameters
    ----------
    edges : sequence of three numpy.ndarray
        The increasing cell edges on each axis (``n_a + 1`` floats).
    boxes : numpy.ndarray
        ``(N, 3, 2)`` closed boxes (infinite bounds allowed).
    exterior : numpy.ndarray, optional
        A closed ``(3, 2)`` box whose open outside counts as covered too (a point on its faces does not: a piece
        touching a face is covered only when that face is, by the closed boxes).

    Returns
    -------
    numpy.ndarray
        ``bool`` of the grid's shape ``(n_0, n_1, n_2)``.

    Examples
    --------
    >>> e = [np.array([0.0, 1.0, 2.0])] * 3
    >>> halves = np.array([[[0, 1.5], [0, 2], [0, 2]], [[1.5, 2], [0, 2], [0, 2]]], dtype=float)
    >>> int(covered_cells(e, halves).sum())      # the union is the whole grid, no single box holds a cell x = 1..2
    8
    """
    shape = tuple(len(e) - 1 for e in edges)
    out = np.zeros(shape, dtype=bool)
    if exterior is not None:                 # cells strictly outside the closed box: e_{i+1} < lo or e_i > hi
        away = [(e[1:] < exterior[a, 0]) | (e[:-1] > exterior[a, 1]) for a, e in enumerate(edges)]
        out |= away[0][:, None, None] | away[1][None, :, None] | away[2][None, None, :]
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 3, 2)
    if not len(boxes):
        return out
    lo_in, hi_in, lo_any, hi_any = [], [], [], []
    for a, e in enumerate(edges):
        lo, hi = boxes[:, a, 0], boxes[:, a, 1]
        n = len(e) - 1
        lo_in.append(np.searchsorted(e, lo, side="left"))                       # first i with lo <= e_i
        hi_in.append(np.searchsorted(e, hi, side="right") - 1)                  # i < this: e_{i+1} <= hi
        lo_any.append(np.clip(np.searchsorted(e, lo, side="right") - 1, 0, n))  # e_{i+1} > lo
        hi_any.append(np.clip(np.searchsorted(e, hi, side="left"), 0, n))       # e_i < hi
    # cells inside one box: a difference array over the index ranges
    i0, i1 = np.stack(lo_in, 1), np.stack(hi_in, 1)
    i0 = np.clip(i0, 0, np.array(shape))
    i1 = np.clip(i1, 0, np.array(shape))
    ok = (i1 > i0).all(axis=1)
    diff = np.zeros(tuple(s + 1 for s in shape), dtype=np.int64)
    for corner in range(8):
        bits = [(corner >> a) & 1 for a in range(3)]
        idx = tuple(np.where(bits[a], i1[ok, a], i0[ok, a]) for a in range(3))
        np.add.at(diff, idx, (-1) ** sum(bits))
    out |= diff.cumsum(0).cumsum(1).cumsum(2)[:shape[0], :shape[1], :shape[2]] > 0
    # cells overlapped by several boxes: the pairs (box, cell) that overlap, then the exact split
    a0, a1 = np.stack(lo_any, 1), np.stack(hi_any, 1)
    counts = np.prod(np.maximum(a1 - a0, 0), axis=1)
    if counts.sum() == 0:
        return out
    owner = np.repeat(np.arange(len(boxes)), counts)
    start = np.repeat(np.cumsum(counts) - counts, counts)
    local = np.arange(counts.sum()) - start
    span = np.maximum(a1 - a0, 0)[owner]
    ix = a0[owner, 0] + local // (span[:, 1] * span[:, 2])
    iy = a0[owner, 1] + (local // span[:, 2]) % span[:, 1]
    iz = a0[owner, 2] + local % span[:, 2]
    flat = np.ravel_multi_index((ix, iy, iz), shape)
    todo = ~out.ravel()[flat]
    owner, flat, ix, iy, iz = owner[todo], flat[todo], ix[todo], iy[todo], iz[todo]
    if not len(flat):
        return out
    cells = np.stack([np.stack([edges[a][i], edges[a][i + 1]], 1) for a, i in enumerate((ix, iy, iz))], 1)
    overlap = np.prod(np.clip(np.minimum(cells[:, :, 1], boxes[owner, :, 1])
                              - np.maximum(cells[:, :, 0], boxes[owner, :, 0]), 0, None), axis=1)
    volume = np.prod(cells[:, :, 1] - cells[:, :, 0], axis=1)
    if exterior is not None:                 # the part of the cell outside the box counts in the filter
        overlap = overlap + (volume - np.prod(np.clip(np.minimum(cells[:, :, 1], exterior[:, 1])
                                                      - np.maximum(cells[:, :, 0], exterior[:, 0]), 0, None), axis=1))
    order = np.argsort(flat, kind="stable")
    flat, owner, overlap, volume, cells = flat[order], owner[order], overlap[order], volume[order], cells[order]
    firsts = np.flatnonzero(np.r_[True, flat[1:] != flat[:-1]])
    sums = np.add.reduceat(overlap, firsts)
    ends = np.r_[firsts[1:], len(flat)]
    for begin, end, total in zip(firsts, ends, sums):
        if total < volume[begin] * (1 - 1e-9):      # the boxes miss a part of the cell (floats: only a filter)
            continue
        if _split_covered(cells[begin], boxes[owner[begin:end]], exterior):
            out.ravel()[flat[begin]] = True
    return out


def free_cells(edges, boxes: np.ndarray) -> np.ndarray:
    """Which closed cells of the grid ``edges`` meet none of the closed ``boxes``, decided by comparisons.

    A paving's inner, boundary and pending boxes hold every point of the set it paves (its outer boxes and the
    outside of its root hold none), so a cell meeting none of them holds no point of the set.  The cells a box
    meets are a range on each axis (``e_{i+1} >= lo`` and ``e_i <= hi``, by ``searchsorted``); a NaN bound
    counts as the whole axis.

    Parameters
    ----------
    edges : sequence of three numpy.ndarray
        The increasing cell edges on each axis.
    boxes : numpy.ndarray
        ``(N, 3, 2)`` closed boxes.

    Returns
    -------
    numpy.ndarray
        ``bool`` of the grid's shape.

    Examples
    --------
    >>> e = [np.array([0.0, 1.0, 2.0, 3.0])] * 3
    >>> int(free_cells(e, np.array([[[1.0, 1.5], [0.5, 0.5], [0.0, 3.0]]])).sum())   # x cells 0, 1; y cell 0
    21
    """
    shape = tuple(len(e) - 1 for e in edges)
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 3, 2)
    boxes = np.where(np.isnan(boxes), np.array([-np.inf, np.inf]), boxes)     # no bound: the whole axis
    first = np.stack([np.clip(np.searchsorted(e, boxes[:, a, 0], side="left") - 1, 0, shape[a])
                      for a, e in enumerate(edges)], 1)
    last = np.stack([np.clip(np.searchsorted(e, boxes[:, a, 1], side="right"), 0, shape[a])
                     for a, e in enumerate(edges)], 1)
    met = np.zeros(shape, dtype=bool)
    for (i0, j0, k0), (i1, j1, k1) in zip(first.tolist(), last.tolist()):
        met[i0:i1, j0:j1, k0:k1] = True
    return ~met


def _split_covered(cell: np.ndarray, boxes: np.ndarray, exterior: np.ndarray | None = None) -> bool:
    """Whether the closed ``cell`` is a subset of the union of the closed ``boxes`` and of the open outside of
    ``exterior``: split at faces, no rounding.  A piece may be degenerate (a face, ``lo == hi`` on an axis)."""
    stack, pieces = [cell], 0
    while stack:
        c = stack.pop()
        pieces += 1
        if pieces > MAX_PIECES:
            return False
        if exterior is not None:
            face: int | None = None
            away = False
            for a in range(3):
                if c[a, 1] < exterior[a, 0] or c[a, 0] > exterior[a, 1]:
                    away = True                  # strictly outside: covered
                    break
                if c[a, 1] == exterior[a, 0] or c[a, 0] == exterior[a, 1]:
                    face = a                     # in the closed outside, touching the face: the face must be covered
            if away:
                continue
            if face is not None:
                c = c.copy()
                c[face] = exterior[face, 0] if c[face, 1] == exterior[face, 0] else exterior[face, 1]
        flat = c[:, 0] == c[:, 1]
        meet = (np.where(flat, boxes[:, :, 0] <= c[:, 1], boxes[:, :, 0] < c[:, 1])
                & np.where(flat, boxes[:, :, 1] >= c[:, 0], boxes[:, :, 1] > c[:, 0])).all(axis=1)
        if not meet.any():
            return False            # a piece in no box (of positive volume, or a face outside every box)
        near = boxes[meet]
        if ((near[:, :, 0] <= c[:, 0]) & (near[:, :, 1] >= c[:, 1])).all(axis=1).any():
            continue
        b = near[0]
        for a in range(3):
            for cut in (b[a, 0], b[a, 1]):
                if c[a, 0] < cut < c[a, 1]:
                    left, right = c.copy(), c.copy()
                    left[a, 1] = cut
                    right[a, 0] = cut
                    stack += [left, right]
                    break
            else:
                continue
            break
    return True


# ---------------------------------------------------------------------------------------------------------------
# one direction


def direction_codes(task, *, robot: DHRobot, parameters: tuple, cone: float, reach_delta: float,
                    edges: tuple, max_boxes: int | None):
    """The codes of every cell for the directions of ``task``, from a certified pose paving each (a worker's job).

    Parameters
    ----------
    task : numpy.ndarray
        ``(1, 4)``: a direction's index and its unit vector; ``(1, 5)``: also the paving's time limit.
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    cone : float
        The cone's half-angle in degrees.
    reach_delta : float
        The pose paving's ``delta``.
    edges : tuple of numpy.ndarray
        The grid's cell edges on each axis.
    max_boxes : int or None
        ``StopAt(max_boxes=)`` of the paving.

    Returns
    -------
    dict
        ``index``, ``codes`` (``int8`` of the grid's shape), ``inside_root`` (the paving's root box inside the
        grid's box), ``seconds``, ``method`` and ``complete``.
    """
    index, d = int(task[0, 0]), tuple(float(v) for v in task[0, 1:4])
    started = time.perf_counter()
    stop = StopAt(max_boxes=max_boxes, time_limit=None if task.shape[1] < 5 else float(task[0, 4]))
    result = reach(robot, delta=reach_delta, parameters=dict(parameters), pose=Pose(approach=d, cone=cone),
                   stop=stop, run=RunOn(progress=False))
    root = np.array([result.box.lower, result.box.upper], dtype=float).T
    inner = covered_cells(edges, result.inner)
    outer = covered_cells(edges, result.outer.reshape(-1, 3, 2), exterior=root)
    codes = codes_from_masks(inner.ravel(), outer.ravel()).reshape(inner.shape)
    inside = bool(all(edges[a][0] <= root[a, 0] and root[a, 1] <= edges[a][-1] for a in range(3)))
    return {"index": index, "codes": codes, "inside_root": inside, "seconds": time.perf_counter() - started,
            "method": result.method, "complete": bool(result.complete)}


def _checked(value, task, shape):
    """A worker's answer for ``task``, refused unless it is the codes of the grid for that direction."""
    if type(value) is not dict or not {"index", "codes", "inside_root"} <= set(value):
        refuse_result("something other than a direction's codes", type(value).__name__)
    codes = value["codes"]
    if type(codes) is not np.ndarray or codes.shape != shape or codes.dtype != CODE:
        refuse_result(f"codes that are not int8 of shape {shape}", f"{getattr(codes, 'dtype', '?')} "
                      f"{getattr(codes, 'shape', '?')}")
    if not np.isin(codes, (INSIDE, OUTSIDE, UNDECIDED)).all() or value["index"] != int(task[0, 0]):
        refuse_result("codes other than 1, 0 and -1, or another direction's", f"direction {value['index']!r}")
    return value


# ---------------------------------------------------------------------------------------------------------------
# the map


@dataclass(frozen=True, eq=False)
class ReachMap:
    """A certified reachability map: cubic cells of side ``delta`` (``origin``, ``shape``) times ``K`` approach
    directions, each pair's verdict code in ``codes`` (1 proved reachable with the approach axis within ``cone``
    degrees of the direction at every point of the cell, -1 proved unreachable with it at every point, 0
    undecided).

    Parameters
    ----------
    directions : numpy.ndarray
        ``(K, 3)`` unit vectors.
    cone : float
        The cones' half-angle, degrees.
    delta : float
        The cells' side.
    origin : numpy.ndarray
        The grid's lowest corner (3 floats).
    shape : tuple of int
        Cells on each axis.
    codes : numpy.ndarray
        ``int8`` of shape ``(*shape, K)``.
    outside_proved : bool
        Every point outside the grid proved unreachable (the grid holds every direction's certified root box).
    fingerprint : Fingerprint
        The whole problem (:func:`map_problem`).
    info : dict
        ``robot``, ``units``, ``method``, ``seconds``, ``reach_delta``, ``covering_angle``, per-direction
        ``direction_seconds`` and ``direction_methods``, ``complete``.
    """

    directions: np.ndarray
    cone: float
    delta: float
    origin: np.ndarray
    shape: tuple
    codes: np.ndarray
    outside_proved: bool
    fingerprint: Fingerprint
    info: dict = field(default_factory=dict)

    @property
    def edges(self) -> tuple:
        """The cell edges on each axis, ``origin + i * delta`` computed once in floats (the cells' definition).

        Returns
        -------
        tuple of numpy.ndarray
            Three increasing arrays of ``n_a + 1`` floats.
        """
        return tuple(self.origin[a] + np.arange(self.shape[a] + 1) * self.delta for a in range(3))

    @property
    def method(self) -> str:
        """How the pairs were proved (:data:`MAP_METHOD`).

        Returns
        -------
        str
            The method.
        """
        return str(self.info.get("method", MAP_METHOD))

    @property
    def units(self) -> str | None:
        """The robot's length units.

        Returns
        -------
        str or None
            As the robot gives them.
        """
        return self.info.get("units")

    @property
    def capability(self) -> np.ndarray:
        """The certified capability bracket of each cell, ``[proved / K, (K - unreachable) / K]``: the fraction of
        the directions with which every point of the cell is reached lies in it.

        Returns
        -------
        numpy.ndarray
            ``(*shape, 2)`` floats.
        """
        k = self.codes.shape[-1]
        return np.stack([(self.codes == INSIDE).sum(-1) / k, (k - (self.codes == OUTSIDE).sum(-1)) / k], -1)

    def cells_of(self, points) -> tuple[np.ndarray, np.ndarray]:
        """The cell holding each point (the closed cell, its edges as :attr:`edges`), and whether it is in the
        grid.

        Parameters
        ----------
        points : array_like
            ``(N, 3)`` finite points.

        Returns
        -------
        tuple
            ``(index, inside)``: ``(N, 3)`` cell indices (meaningful where ``inside``) and ``(N,)`` bools.

        Raises
        ------
        InvalidParameterError
            Points that are not an ``(N, 3)`` array of finite numbers.
        """
        p = _points(points, "points")
        edges = self.edges
        index = np.empty(p.shape, dtype=np.int64)
        inside = np.ones(len(p), dtype=bool)
        for a in range(3):
            e = edges[a]
            i = np.floor((p[:, a] - self.origin[a]) / self.delta).astype(np.int64)
            i = np.clip(i, 0, self.shape[a] - 1)
            i = np.where(p[:, a] < e[i], i - 1, i)              # the division rounds: read the edges themselves
            i = np.where(p[:, a] > e[np.clip(i + 1, 0, self.shape[a])], i + 1, i)
            inside &= (p[:, a] >= e[0]) & (p[:, a] <= e[-1])
            index[:, a] = np.clip(i, 0, self.shape[a] - 1)
        return index, inside

    def query(self, points, approach=None) -> np.ndarray:
        """What the map proved at each point: with ``approach``, a verdict code; without, the capability bracket.

        With ``approach`` (``(N, 3)``, any nonzero lengths): the code of the pair (the point's cell, the map
        direction nearest the approach vector) when that direction's cone holds the vector (with a margin of
        ``1e-12``), else 0.  A -1 then proves the point is not reached with that approach axis (nor any other of
        the cone); a 1 proves it is reached with an approach axis within ``cone`` of the map direction, so within
        ``2 cone`` of the vector given, not with the vector itself.  Without ``approach``: ``(N, 2)``, the
        capability bracket of the point's cell.  A point outside the grid is -1 (bracket ``[0, 0]``) when the map
        proved the outside of its grid unreachable (:attr:`outside_proved`), else 0 (``[0, 1]``).

        Parameters
        ----------
        points : array_like
            ``(N, 3)`` finite points, in the robot's units.
        approach : array_like, optional
            ``(N, 3)`` (or one ``(3,)``) nonzero approach vectors.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` ``int8`` codes with ``approach``, ``(N, 2)`` floats without.

        Raises
        ------
        InvalidParameterError
            Points or approach vectors that are not finite ``(N, 3)`` arrays, a zero approach vector.

        Examples
        --------
        >>> m = ReachMap(sphere_directions(2), 90.0, 1.0, np.zeros(3), (1, 1, 1), np.array([[[[1, -1]]]], np.int8),
        ...              True, Fingerprint({}))
        >>> m.query([[0.5, 0.5, 0.5], [3, 0, 0]], approach=[[0, 0, 2], [0, 0, 1]]).tolist()
        [1, -1]
        """
        p = _points(points, "points")
        if approach is None:
            out = np.empty((len(p), 2))
            capability = self.capability
            for at in range(0, len(p), _CHUNK):
                index, inside = self.cells_of(p[at:at + _CHUNK])
                bracket = capability[index[:, 0], index[:, 1], index[:, 2]]
                bracket[~inside] = (0.0, 0.0) if self.outside_proved else (0.0, 1.0)
                out[at:at + _CHUNK] = bracket
            return out
        v = _points(approach, "approach")
        if len(v) == 1 and len(p) != 1:
            v = np.repeat(v, len(p), axis=0)
        if len(v) != len(p):
            raise InvalidParameterError(f"approach must hold one vector a point ({len(p)}); got {len(v)}",
                                        parameter="approach")
        norms = np.sqrt(np.einsum("ij,ij->i", v, v))
        if not (norms > 0).all():
            raise InvalidParameterError(f"approach: vector {int(np.argmin(norms))} is the zero vector; expected "
                                        "nonzero approach vectors", parameter="approach")
        answer = np.empty(len(p), dtype=CODE)
        cos_c = math.cos(math.radians(self.cone))
        d32 = self.directions.astype(np.float32)
        outside_code = OUTSIDE if self.outside_proved else UNDECIDED
        for at in range(0, len(p), _CHUNK):
            vs, ns = v[at:at + _CHUNK], norms[at:at + _CHUNK]
            # the nearest direction in single precision (any choice is sound), then whether its cone holds the
            # vector in double precision with a margin far above the rounding of a 3-term dot product
            v32 = vs.astype(np.float32)
            k = np.argmax(v32[:, 0:1] * d32[:, 0] + v32[:, 1:2] * d32[:, 1] + v32[:, 2:3] * d32[:, 2], axis=1)
            best = np.einsum("ij,ij->i", vs, self.directions[k])
            held = best - ns * cos_c >= _RIM * ns
            index, inside = self.cells_of(p[at:at + _CHUNK])
            codes = self.codes[index[:, 0], index[:, 1], index[:, 2], k]
            answer[at:at + _CHUNK] = np.where(held, np.where(inside, codes, outside_code), UNDECIDED)
        return answer

    def bounding_mask(self, box=None) -> np.ndarray:
        """The cells inside ``box`` (default: the arm's certified bounding box, ``info['root']``).

        Parameters
        ----------
        box : array_like, optional
            ``(3, 2)``.

        Returns
        -------
        numpy.ndarray
            ``bool`` of the grid's shape: cells whose centre lies in the box.
        """
        box = np.asarray(self.info.get("root") if box is None else box, dtype=float)
        centres = [(e[:-1] + e[1:]) / 2 for e in self.edges]
        masks = [(c >= box[a, 0]) & (c <= box[a, 1]) for a, c in enumerate(centres)]
        return masks[0][:, None, None] & masks[1][None, :, None] & masks[2][None, None, :]

    def summary(self) -> dict:
        """The map in figures, JSON-able: counts of pairs, decided fractions (all, inside the bounding box), build
        seconds, method.

        Returns
        -------
        dict
            ``robot``, ``units``, ``delta``, ``cone``, ``directions``, ``covering_angle``, ``grid`` (``origin``,
            ``shape``), ``pairs``, ``reachable``, ``unreachable``, ``undecided``, ``decided_fraction``,
            ``decided_fraction_in_box``, ``outside_proved``, ``seconds``, ``method``, ``reach_delta``,
            ``complete``; with ``method="section"``, ``wrist_offset`` (``L``, None without the stage),
            ``wrist_pairs`` (the pairs it proved unreachable) and ``ring_pairs`` (those the wrist's ring proved
            unreachable besides).
        """
        c = self.codes
        inbox = c[self.bounding_mask()] if "root" in self.info else c
        return {"robot": self.info.get("robot"), "units": self.units, "delta": self.delta, "cone": self.cone,
                "directions": int(c.shape[-1]), "covering_angle": self.info.get("covering_angle"),
                "grid": {"origin": [float(v) for v in self.origin], "shape": [int(s) for s in self.shape]},
                "pairs": int(c.size), "reachable": int((c == INSIDE).sum()), "unreachable": int((c == OUTSIDE).sum()),
                "undecided": int((c == UNDECIDED).sum()),
                "decided_fraction": float((c != UNDECIDED).mean()) if c.size else 0.0,
                "decided_fraction_in_box": float((inbox != UNDECIDED).mean()) if inbox.size else 0.0,
                "outside_proved": bool(self.outside_proved), "seconds": self.info.get("seconds"),
                "method": self.method, "reach_delta": self.info.get("reach_delta"),
                "complete": self.info.get("complete"),
                **{key: self.info[key] for key in ("wrist_offset", "wrist_pairs", "ring_pairs") if key in self.info}}

    def slice(self, axis: str = "z", value: float = 0.0, direction: int | None = None) -> np.ndarray:
        """The grid's layer of cells holding ``axis = value``: a direction's codes, or the lower capability bound.

        Parameters
        ----------
        axis : {"x", "y", "z"}
            The axis cut.
        value : float
            Where.
        direction : int, optional
            A direction's index (its codes); None: the lower capability bound of each cell.

        Returns
        -------
        numpy.ndarray
            A 2-D array over the two other axes.

        Raises
        ------
        InvalidParameterError
            An axis not ``x``, ``y``, ``z``, a value outside the grid, a direction out of range.
        """
        if axis not in ("x", "y", "z"):
            raise InvalidParameterError(f"axis must be one of 'x', 'y', 'z'; got {axis!r}", parameter="axis")
        a = "xyz".index(axis)
        e = self.edges[a]
        if not (math.isfinite(value) and e[0] <= value <= e[-1]):
            raise InvalidParameterError(f"value must lie in the grid, [{e[0]:g}, {e[-1]:g}] on {axis}; got "
                                        f"{value!r}", parameter="value")
        i = int(min(max(np.searchsorted(e, value, side="right") - 1, 0), self.shape[a] - 1))
        if direction is None:
            layer = self.capability[..., 0]
        else:
            if not (isinstance(direction, (int, np.integer)) and 0 <= direction < self.codes.shape[-1]):
                raise InvalidParameterError(f"direction must be an index in [0, {self.codes.shape[-1]}); got "
                                            f"{direction!r}", parameter="direction")
            layer = self.codes[..., direction]
        return np.take(layer, i, axis=a)

    # files ------------------------------------------------------------------------------------------------------
    def save(self, path) -> Path:
        """Write the map to ``path`` (``.npz``, no pickle), whole or not at all (a ``.part`` file renamed).

        Parameters
        ----------
        path : str or path
            The file.

        Returns
        -------
        pathlib.Path
            ``path``.

        Raises
        ------
        OutputError
            A directory that cannot hold the file.
        """
        from ..files import check_output_file, write_npz

        return write_npz(check_output_file(path, "path"), **_arrays(self))

    @classmethod
    def load(cls, path, *, expect: Fingerprint | None = None) -> ReachMap:
        """A map written by :meth:`save`, checked whole before it is returned.

        Parameters
        ----------
        path : str or path
            The file.
        expect : Fingerprint, optional
            The problem the map must be of (:func:`map_problem`, or another map's :attr:`fingerprint`); None
            accepts any problem.

        Returns
        -------
        ReachMap
            The map.

        Raises
        ------
        InvalidParameterError
            ``path``: not a map (unreadable, truncated, corrupted: its content digest differs, or a field missing),
            or of another format version; ``expect``: a map of another problem, naming the fields that differ.
        """
        try:
            with np.load(path, allow_pickle=False) as data:
                arrays = {name: data[name] for name in data.files}
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
            raise InvalidParameterError(f"path: {str(path)!r} is not a reach map ({exc})", parameter="path") from None
        try:
            version = int(arrays["format"])
        except (KeyError, TypeError, ValueError):
            version = -1
        if version != MAP_FORMAT:
            raise InvalidParameterError(f"path: {str(path)!r} is a reach map of format version {version}; this "
                                        f"workspace_sym reads version {MAP_FORMAT}: build the map again",
                                        parameter="path")
        try:
            if str(arrays["content"]) != _content_digest(arrays):
                raise ValueError("its content digest differs from the one it was saved with")
            meta = json.loads(str(arrays["meta"]))
            named = Fingerprint.from_json(json.loads(str(arrays["fingerprint"])))
            codes = arrays["codes"]
            shape = tuple(int(s) for s in arrays["shape"])
            directions = arrays["directions"]
            if codes.dtype != CODE or codes.shape != (*shape, len(directions)) or directions.shape[1:] != (3,):
                raise ValueError(f"codes {codes.dtype} {codes.shape} for a grid {shape} and {len(directions)} "
                                 "directions")
            if not np.isin(codes, (INSIDE, OUTSIDE, UNDECIDED)).all():
                raise ValueError("codes other than 1, 0 and -1")
            made = cls(directions=directions, cone=float(arrays["cone"]), delta=float(arrays["delta"]),
                       origin=arrays["origin"], shape=shape, codes=codes, outside_proved=bool(arrays["outside_proved"]),
                       fingerprint=named, info=meta)
        except (KeyError, TypeError, ValueError, IndexError) as exc:
            raise InvalidParameterError(f"path: {str(path)!r} is not a whole reach map ({exc}); refused",
                                        parameter="path") from None
        if expect is not None:
            check_fingerprint(named.to_json(), expect, what=f"{str(path)!r} is a reach map", parameter="expect")
        return made

    def __repr__(self) -> str:
        s = self.summary()
        return (f"ReachMap({s['robot']}: {self.shape} cells x {s['directions']} "
                f"directions, cone {self.cone:g} deg, delta {self.delta:g}; {s['reachable']} reachable, "
                f"{s['unreachable']} unreachable, {s['undecided']} undecided pairs)")


def _points(values, parameter: str) -> np.ndarray:
    try:
        p = np.array(values, dtype=float)
    except (TypeError, ValueError):
        p = np.zeros((0,))
    if p.ndim == 1 and p.shape == (3,):
        p = p[None]
    if p.ndim != 2 or p.shape[1] != 3 or not np.isfinite(p).all():
        raise InvalidParameterError(f"{parameter} must be an (N, 3) array of finite numbers; got "
                                    f"{'shape ' + str(p.shape) if p.size else repr(values)[:60]}"
                                    f"{' with a non-finite value' if p.size and not np.isfinite(p).all() else ''}",
                                    parameter=parameter)
    return p


def _arrays(m: ReachMap) -> dict:
    arrays = {"format": np.array(MAP_FORMAT), "directions": np.asarray(m.directions, dtype=float),
              "cone": np.array(m.cone), "delta": np.array(m.delta), "origin": np.asarray(m.origin, dtype=float),
              "shape": np.array(m.shape, dtype=np.int64), "codes": np.asarray(m.codes, dtype=CODE),
              "outside_proved": np.array(bool(m.outside_proved)),
              "fingerprint": np.array(json.dumps(m.fingerprint.to_json(), sort_keys=True)),
              "meta": np.array(json.dumps(m.info, sort_keys=True)), "units": np.array(str(m.units))}
    arrays["content"] = np.array(_content_digest(arrays))
    return arrays


def _content_digest(arrays: dict) -> str:
    """SHA-256 of every array but the digest itself: a flipped byte anywhere is refused."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        if name == "content":
            continue
        value = np.asarray(arrays[name])
        h.update(name.encode() + str(value.dtype).encode() + str(value.shape).encode())
        h.update(np.ascontiguousarray(value).tobytes() if value.dtype.kind != "U" else str(value).encode())
    return h.hexdigest()


def map_problem(robot: DHRobot, *, delta: float, directions=26, cone: float = 30.0, parameters=None,
                reach_delta: float | None = None, method: str = "pavings") -> Fingerprint:
    """The fingerprint of a map's whole problem: the robot (DH table, limits, base, tool, parameters), ``delta``,
    the directions, the cone, the pose paving's ``delta``, the engine's tuning, the method and the file format.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    delta : float
        The cells' side.
    directions : int or array_like
        As for :func:`reach_map`.
    cone : float
        Degrees.
    parameters : dict, optional
        Values of the robot's symbolic lengths.
    reach_delta : float, optional
        The pose pavings' ``delta`` (default ``delta / 2``).
    method : str
        ``"pavings"`` or ``"section"`` (:data:`METHODS`).

    Returns
    -------
    Fingerprint
        Named fields, compared by :meth:`ReachMap.load` (``expect=``) and by a resumed build.

    Raises
    ------
    InvalidParameterError
        A bad ``delta``, ``directions``, ``cone`` or ``method``.
    """
    check_delta(delta)
    _check_method(method)
    d = _directions(directions)
    cone = _check_cone(cone)
    reach_delta = float(delta) / 2 if reach_delta is None else float(reach_delta)
    check_delta(reach_delta)
    values = parameter_values(parameters)
    fields = reach_problem(robot, values, float(delta), "diameter", DEFAULT,
                           directions=[[float(v) for v in row] for row in d], cone=cone, reach_delta=reach_delta,
                           method=METHODS[method], map_format=MAP_FORMAT)
    if method == "section":
        fields["section"] = {**SECTION_OPTIONS, "cell": float(delta) / 10}
    return Fingerprint(fields)


def _check_method(method) -> str:
    if method not in METHODS:
        raise InvalidParameterError(f"method must be one of {', '.join(map(repr, METHODS))}; got {method!r}",
                                    parameter="method")
    return method


def _grid(robot: DHRobot, values: tuple, delta: float):
    """The grid's origin and shape: cells of side ``delta`` on multiples of ``delta``, holding the certified
    enclosure of every tool position over the joint limits (the reach model's root box)."""
    model = reach_model(robot, values)
    root = np.asarray(model.enclose(model.limits[None])[0], dtype=float)
    if root.shape != (3, 2) or not np.isfinite(root).all():
        raise InvalidParameterError(f"robot: a reach map needs a spatial robot whose tool position has a finite "
                                    f"enclosure; {robot.name} gives {root.tolist()}", parameter="robot")
    return (*_grid_of(root, delta), root)


def _grid_of(root: np.ndarray, delta: float):
    """The origin and shape of the cells of side ``delta`` on multiples of ``delta`` holding the box ``root``."""
    origin = np.floor(root[:, 0] / delta) * delta
    origin = np.where(origin > root[:, 0], origin - delta, origin)
    shape = np.maximum(np.ceil((root[:, 1] - origin) / delta).astype(int), 1)
    while (origin + shape * delta < root[:, 1]).any():      # the last float edge must hold the root box
        shape = shape + (origin + shape * delta < root[:, 1])
    return origin, tuple(int(s) for s in shape)


@arith.nearest_rounding
def reach_map(robot: DHRobot, *, delta: float, directions=26, cone: float = 30.0, parameters: dict | None = None,
              reach_delta: float | None = None, method: str = "pavings", stop: StopAt = StopAt(),
              run: RunOn = RunOn()) -> ReachMap:
    """The certified reachability map of ``robot`` (module docstring; docs/methods.md section 9).

    Parameters
    ----------
    robot : DHRobot
        A spatial serial robot.
    delta : float
        The cells' side, in the robot's units.
    directions : int or array_like
        ``K`` (:func:`sphere_directions`) or a ``(K, 3)`` array of nonzero vectors.
    cone : float
        The cones' half-angle in degrees, in ``(0, 180]``; a cone below the directions' covering angle leaves
        approach vectors no cone holds (a :class:`UserWarning` says so; :meth:`ReachMap.query` answers 0 there).
    parameters : dict, optional
        Values of the symbolic lengths.
    reach_delta : float, optional
        The ``delta`` of each direction's pose paving (default ``delta / 2``: its boundary boxes smaller than a
        cell); with ``method="section"``, of the position paving.
    method : {"pavings", "section"}
        ``"pavings"`` (default): one certified pose paving per direction, reachable and unreachable pairs from its
        boxes.  ``"section"``, for an arm turned by its first joint (the Puma 560, the UR5, the KR16, the
        iiwa 14, the Panda): reachable pairs from certified solutions of the arm's section, solved once for all the
        directions (:mod:`~workspace_sym.serial.mapsection`), unreachable cells from the position paving (no
        point of the cell is reached at all) and unreachable pairs of one direction from the paving of the wrist
        point ``p - L a`` (where the last two axes have a common normal); faster and far more pairs proved
        reachable on such arms (docs/methods.md section 9).
    stop : StopAt
        ``time_limit``: seconds for the whole map, shared among the directions not yet built (each gets what is
        left divided by their number); ``max_boxes``: a budget of each direction's paving.  What a stopped paving
        leaves pending is undecided.
    run : RunOn
        ``executor``: directions sent to a ``concurrent.futures`` executor or a Dask client (a task a direction,
        each answer checked); ``resume``: a checkpoint file of the finished directions, written after each one and
        taken again (refused when it names another problem); ``progress``: a bar over the directions;
        ``max_memory``, ``store``, ``chunk`` are refused (a map keeps one byte a pair in memory).  With
        ``method="section"``, ``executor`` runs the position and the wrist pavings side by side, then the section
        in as many parts as the executor has workers (a task each, each answer checked), and ``resume`` is refused.

    Returns
    -------
    ReachMap
        The map.

    Raises
    ------
    InvalidParameterError
        A bad ``delta``, ``directions``, ``cone``, ``reach_delta``, ``method`` or option, a planar robot, a
        checkpoint of another problem, ``method="section"`` for an arm without the structure (the reason named).

    Examples
    --------
    >>> from workspace_sym import robots
    >>> import warnings
    >>> with warnings.catch_warnings():                 # one cone of 30 deg does not cover the sphere
    ...     warnings.simplefilter("ignore")
    ...     m = reach_map(robots.build("scara"), delta=0.2, directions=[[1, 0, 0]], cone=30)
    >>> bool((m.codes == -1).all())                    # the SCARA's tool always points straight down
    True
    """
    check_delta(delta)
    d = _directions(directions)
    cone = _check_cone(cone)
    _check_method(method)
    if not isinstance(stop, StopAt) or not isinstance(run, RunOn):
        raise InvalidParameterError("stop and run must be a StopAt and a RunOn", parameter="run")
    for name in ("max_memory", "store", "chunk"):
        if getattr(run, name) is not None:
            raise InvalidParameterError(f"run: a reach map keeps its codes in memory (one byte a pair) and builds "
                                        f"each direction in one task, so {name} does not apply; got "
                                        f"{name}={getattr(run, name)!r}; use resume= for a checkpoint per direction",
                                        parameter=name)
    angle = covering_angle(d)
    if cone < angle:
        warnings.warn(f"reach_map: the cones of {cone:g} deg do not cover the sphere (the {len(d)} directions' "
                      f"covering angle is {angle:.4g} deg): approach vectors farther than {cone:g} deg from every "
                      "direction are held by no cone and queried as undecided", UserWarning, stacklevel=3)
    values = parameter_values(parameters)
    named = map_problem(robot, delta=delta, directions=d, cone=cone, parameters=parameters, reach_delta=reach_delta,
                        method=method)
    reach_delta = float(delta) / 2 if reach_delta is None else float(reach_delta)
    started = time.perf_counter()
    origin, shape, root = _grid(robot, values, float(delta))     # a spatial robot with a finite enclosure
    if method == "section":         # its own grid, from the position paving
        return _section_map(robot, values, d, cone, float(delta), reach_delta, named, angle, stop, run, started)
    edges = tuple(origin[a] + np.arange(shape[a] + 1) * float(delta) for a in range(3))
    codes = np.zeros((*shape, len(d)), dtype=CODE)
    done: dict[int, dict] = _resumed(run.resume, named, shape, len(d))
    for k, answer in done.items():
        codes[..., k] = answer["codes"]
    job = partial(direction_codes, robot=robot, parameters=values, cone=cone, reach_delta=reach_delta, edges=edges,
                  max_boxes=stop.max_boxes)
    todo = [k for k in range(len(d)) if k not in done]

    def task(k):
        row = [k, *d[k]]
        if stop.time_limit is not None:
            left = stop.time_limit - (time.perf_counter() - started)
            row.append(max(left, 1e-3) / max(1, len(todo) - len([j for j in todo if j in done])))
        return np.array([row], dtype=float)

    with progress_bar(run.progress, total=len(d), desc=f"reach map of {robot.name}", unit="direction",
                      initial=len(done)) as bar:
        if run.executor is None:
            for k in todo:
                answer = job(task(k))
                _finish(answer, codes, done, run.resume, named, bar)
        else:
            runner = runner_for(run.executor, job)
            try:
                pending = {}
                for k in todo:
                    t = task(k)
                    pending[runner.submit(t)] = t
                while pending:
                    for future in runner.wait(list(pending), 1.0):
                        t = pending.pop(future)
                        answer = runner.result(future, t, lambda value, tk: _checked(value, tk, shape))
                        _finish(answer, codes, done, run.resume, named, bar)
            finally:
                runner.close()
    info = {"robot": robot.name, "units": robot.units, "method": MAP_METHOD, "seconds": time.perf_counter() - started,
            "reach_delta": reach_delta, "covering_angle": angle, "root": root.tolist(),
            "direction_seconds": [done[k].get("seconds") for k in range(len(d))],
            "direction_methods": [done[k].get("method") for k in range(len(d))],
            "complete": all(done[k].get("complete", False) for k in range(len(d)))}
    outside = all(done[k].get("inside_root", False) for k in range(len(d)))
    return ReachMap(directions=d, cone=cone, delta=float(delta), origin=origin, shape=shape, codes=codes,
                    outside_proved=outside, fingerprint=named, info=info)


def _section_map(robot, values, d, cone, delta, reach_delta, named, angle, stop, run,
                 started) -> ReachMap:
    """``reach_map(method="section")``: the position paving's outer cells for every direction, the section's
    proofs for the reachable pairs (:mod:`~workspace_sym.serial.mapsection`).  The grid holds the bounding box
    of the paving's boxes not proved outer (inner, boundary, pending): every reachable point is in them, often
    a far smaller box than the enclosure over the joint limits (the Panda's: 0.9 m against 4.25 m).

    With ``run.executor`` the stages run as tasks there: the position and the wrist pavings side by side, then
    the section's candidate cells in as many parts as the executor has workers (whole layers of cells along the
    first joint's axis, about as many cells each), every part solved and tested on its own until the deadline.
    Without one they run in this process, one after the other."""
    from .mapsection import wrist_offset, wrist_unreachable
    from .ring import ring_unreachable, wrist_ring

    if run.resume is not None:
        raise InvalidParameterError(f"method='section' builds the map in one piece, so resume does not apply; got "
                                    f"resume={run.resume!r}; use method='pavings' for a checkpoint per direction",
                                    parameter="resume")
    prover = _section_prover(robot, values, cone)      # kept for the section in this process
    if isinstance(prover, str):
        raise InvalidParameterError(f"method: 'section' needs an arm turned by its first joint; {robot.name} is "
                                    f"not: {prover}; use method='pavings'", parameter="method")
    deadline = None if stop.time_limit is None else started + stop.time_limit
    offset = wrist_offset(robot, values)
    pavings = _runner(run.executor, partial(_paving_stage, robot=robot, values=values, reach_delta=reach_delta,
                                            offset=offset, max_boxes=stop.max_boxes))
    sections = None
    # the two pavings first, side by side on an executor
    shares = {POSITION: 0.3, WRIST: 0.2}
    tasks = {which: np.array([[which, math.nan if deadline is None else max(1e-3, share * stop.time_limit)]])
             for which, share in shares.items() if which == POSITION or offset is not None}
    futures: dict = {which: pavings.submit(task) for which, task in tasks.items()}
    try:
        with progress_bar(run.progress, total=4, desc=f"reach map of {robot.name}", unit="stage") as bar:
            position = pavings.result(futures[POSITION], tasks[POSITION], _checked_paving)
            bar.update(1)
            root = _kept_root(position)
            origin, shape = _grid_of(root, delta)
            edges = tuple(origin[a] + np.arange(shape[a] + 1) * delta for a in range(3))
            outer = covered_cells(edges, position["outer"], exterior=root)
            options = {**SECTION_OPTIONS, "cell": delta / 10}
            part_of = _section_parts(~outer, prover, 1 if run.executor is None else max(1, pavings.slots // 2))
            check = partial(_checked_section, part_of=part_of, count=len(d))
            sections = _runner(run.executor, partial(_section_stage, robot=robot, values=values,
                                                     cone=cone, directions=d, edges=edges, part_of=part_of,
                                                     options=options))
            ends = math.nan if deadline is None else time.time() + (deadline - time.perf_counter())
            parts = {part: np.array([[part, ends]]) for part in range(int(part_of.max()) + 1)}
            futures.update({("part", part): sections.submit(task) for part, task in parts.items()})
            # in this process the wrist's paving comes before the section (its share of the limit is its own)
            wrist = None if offset is None else pavings.result(futures[WRIST], tasks[WRIST], _checked_paving)
            bar.update(1)
            inner = np.zeros((*shape, len(d)), dtype=bool)
            section_seconds = 0.0
            for part, task in parts.items():
                answer = sections.result(futures.pop(("part", part)), task, check)
                inner |= answer["inner"]
                section_seconds = max(section_seconds, answer["seconds"])
            bar.update(1)
            stages = {"position": position["seconds"], "wrist": 0.0 if wrist is None else wrist["seconds"],
                      "section": section_seconds}
            finding = time.perf_counter()
            unreachable = np.repeat(outer[..., None], len(d), axis=-1)
            by_wrist = np.zeros_like(unreachable)
            if wrist is not None and offset is not None:
                # the cells meeting none of w's kept boxes, on a grid holding every w = p - L a of the map: cells
                # of delta / 8 (the boxes' size, reach_delta / 2 = delta / 4 across), at most WRIST_CELLS of them
                pad = abs(float(offset)) + delta
                extent = [edges[a][-1] - edges[a][0] + 2 * pad for a in range(3)]
                fine = max(delta / 8, (math.prod(extent) / WRIST_CELLS) ** (1 / 3))
                w_edges = tuple(edges[a][0] - pad + np.arange(math.ceil(extent[a] / fine) + 1) * fine
                                for a in range(3))
                w_out = free_cells(w_edges, wrist["kept"])
                by_wrist = wrist_unreachable(edges, ~inner & ~unreachable, d, cone, offset, w_out, w_edges)
                unreachable |= by_wrist
            ring = wrist_ring(robot, values)
            by_ring = np.zeros_like(unreachable)
            if ring is not None:
                by_ring = ring_unreachable(edges, ~inner & ~unreachable, d, cone, ring)
                unreachable |= by_ring
            stages["unreachable"] = time.perf_counter() - finding
            bar.update(1)
    finally:
        for runner in (pavings, sections):
            if runner is not None:
                runner.cancel(list(futures.values()))
                runner.close()
    codes = codes_from_masks(inner.ravel(), unreachable.ravel()).reshape(inner.shape)
    complete = (bool(position["complete"]) and (wrist is None or bool(wrist["complete"]))
                and (deadline is None or time.perf_counter() <= deadline))
    info = {"robot": robot.name, "units": robot.units, "method": SECTION_METHOD,
            "seconds": time.perf_counter() - started,
            "reach_delta": reach_delta, "covering_angle": angle, "root": root.tolist(),
            "direction_seconds": [None] * len(d), "direction_methods": [position["method"]] * len(d),
            "complete": complete, "section": options, "proved_axis": prover.axis,
            "wrist_offset": None if offset is None else float(offset),
            "wrist_pairs": int(by_wrist.sum()),
            "ring_pairs": int(by_ring.sum()),
            "wrist_complete": None if wrist is None else bool(wrist["complete"]),
            "section_parts": len(parts),
            "stage_seconds": {name: round(seconds, 1) for name, seconds in stages.items()}}
    inside = bool(all(edges[a][0] <= root[a, 0] and root[a, 1] <= edges[a][-1] for a in range(3)))
    return ReachMap(directions=d, cone=cone, delta=delta, origin=origin, shape=shape, codes=codes,
                    outside_proved=inside, fingerprint=named, info=info)


POSITION, WRIST = 0, 1       # the pavings of the section method's first stage: the tool point's, the wrist point's


def _runner(executor, fn):
    """Where the section method's stages run: this process, when asked for (no executor), or the executor."""
    return Inline(fn) if executor is None else runner_for(executor, fn)


@lru_cache(maxsize=4)
def _section_prover(robot: DHRobot, values: tuple, cone: float):
    """:func:`~workspace_sym.serial.mapsection.section_prover`, cached as :func:`~workspace_sym.serial.model.
    reach_model` caches the models: made once in each process (the map's own and each worker that solves a part
    of its section)."""
    from .mapsection import section_prover

    return section_prover(robot, values, cone)


def _paving_stage(task: np.ndarray, *, robot, values, reach_delta, offset, max_boxes) -> dict:
    """The position paving (``task[0, 0] == POSITION``) or the wrist point's (``WRIST``), within ``task[0, 1]``
    seconds (NaN: no limit), as the arrays the map reads of it."""
    from .mapsection import wrist_robot

    which, seconds = int(task[0, 0]), float(task[0, 1])
    began = time.perf_counter()
    stop = StopAt(max_boxes=max_boxes, time_limit=None if math.isnan(seconds) else seconds)
    if which == POSITION:
        paving = reach(robot, delta=reach_delta, parameters=dict(values), stop=stop, run=RunOn(progress=False))
    else:
        paving = reach(wrist_robot(robot, offset), delta=reach_delta / 2, parameters=dict(values), stop=stop,
                       run=RunOn(progress=False))
    return {"which": which, "outer": np.ascontiguousarray(paving.outer.reshape(-1, 3, 2), dtype=float),
            "kept": _kept(paving), "box": np.array([paving.box.lower, paving.box.upper], dtype=float).T,
            "complete": bool(paving.complete), "method": str(paving.method),
            "seconds": time.perf_counter() - began}


def _checked_paving(value, task):
    """A worker's paving for ``task``, refused unless it has the arrays the map reads, of their shapes."""
    if type(value) is not dict or value.get("which") != int(task[0, 0]):
        refuse_result("something other than the paving asked for", type(value).__name__)
    for name in ("outer", "kept", "box"):
        array = value.get(name)
        if (type(array) is not np.ndarray or array.dtype != np.float64 or array.shape[-2:] != (3, 2)
                or array.ndim != (2 if name == "box" else 3)):
            refuse_result(f"a paving whose {name} are not float boxes", f"{getattr(array, 'dtype', '?')} "
                          f"{getattr(array, 'shape', '?')}")
    if (type(value.get("complete")) is not bool or type(value.get("method")) is not str
            or not isinstance(value.get("seconds"), float)):
        refuse_result("a paving without its completeness, method and seconds", repr(value.get("method")))
    return value


def _section_parts(candidates: np.ndarray, prover, parts: int) -> np.ndarray:
    """``int`` of the grid's shape: the part of each candidate cell (-1: not a candidate).  Whole layers of cells
    across the map axis nearest the first joint's, about as many candidates a part: a part's section cells are
    then a band of heights of their own, and the continuation goes on within it."""
    part_of = np.full(candidates.shape, -1, dtype=np.int64)
    axis = int(np.argmax(np.abs(np.asarray(prover.rotation)[2])))
    layers = np.moveaxis(candidates, axis, 0).reshape(candidates.shape[axis], -1).sum(axis=1)
    total = int(layers.sum())
    if not total:
        return part_of
    before = np.concatenate([[0], np.cumsum(layers)[:-1]])
    layer_part = np.minimum((before + layers / 2) * parts // total, parts - 1).astype(np.int64)
    across = np.moveaxis(candidates, axis, 0)
    np.moveaxis(part_of, axis, 0)[across] = np.broadcast_to(layer_part[:, None, None], across.shape)[across]
    return part_of


def _section_stage(task: np.ndarray, *, robot, values, cone, directions, edges, part_of, options) -> dict:
    """The pairs of the cells of part ``task[0, 0]`` proved reachable by the section method, solved until the
    wall-clock time ``task[0, 1]`` (NaN: no limit)."""
    from .mapsection import local_directions, section_reachable

    part, ends = int(task[0, 0]), float(task[0, 1])
    began = time.perf_counter()
    prover = _section_prover(robot, values, cone)
    deadline = None if math.isnan(ends) else time.perf_counter() + (ends - time.time())
    inner = section_reachable(prover, edges, part_of == part, directions, cell=options["cell"],
                              local=local_directions(prover, directions, options["local"]),
                              samples=options["samples" if prover.aims else "branch_samples"],
                              split=options["split"], retries=options["retries"],
                              deadline=deadline)
    return {"part": part, "inner": inner, "seconds": time.perf_counter() - began}


def _checked_section(value, task, *, part_of, count):
    """A worker's section part for ``task``, refused unless its pairs are of the grid and of that part's cells."""
    if type(value) is not dict or value.get("part") != int(task[0, 0]):
        refuse_result("something other than the section part asked for", type(value).__name__)
    inner = value.get("inner")
    if type(inner) is not np.ndarray or inner.dtype != np.bool_ or inner.shape != (*part_of.shape, count):
        refuse_result(f"pairs that are not booleans of shape {(*part_of.shape, count)}",
                      f"{getattr(inner, 'dtype', '?')} {getattr(inner, 'shape', '?')}")
    if (inner & (part_of != value["part"])[..., None]).any():
        refuse_result("pairs of cells outside its part", f"part {value['part']}")
    if not isinstance(value.get("seconds"), float):
        refuse_result("a part without its seconds", repr(value.get("seconds")))
    return value


def _kept(paving) -> np.ndarray:
    """A paving's boxes not proved outer (inner, boundary, pending), ``(N, 3, 2)``: they hold every point of the
    set it paves."""
    return np.concatenate([b.reshape(-1, 3, 2) for b in (paving.inner, paving.boundary, paving.pending)])


def _kept_root(position: dict) -> np.ndarray:
    """The bounding box ``(3, 2)`` of a paving's boxes not proved outer (inner, boundary, pending), within its
    root box (:func:`_paving_stage`'s arrays): every point of the workspace lies in it."""
    box, kept = position["box"], position["kept"]
    if not len(kept):
        return box
    return np.stack([np.maximum(kept[:, :, 0].min(axis=0), box[:, 0]),
                     np.minimum(kept[:, :, 1].max(axis=0), box[:, 1])], 1)


def _finish(answer: dict, codes: np.ndarray, done: dict, resume, named: Fingerprint, bar) -> None:
    """One direction's codes into the map, and the checkpoint written again (whole, then renamed)."""
    k = answer["index"]
    codes[..., k] = answer["codes"]
    done[k] = answer
    bar.update(1)
    if resume is None:
        return
    finished = sorted(done)
    meta = {str(j): {key: done[j][key] for key in ("inside_root", "seconds", "method", "complete")} for j in finished}
    write_npz(resume, format=np.array(MAP_FORMAT), fingerprint=np.array(json.dumps(named.to_json(), sort_keys=True)),
              finished=np.array(finished, dtype=np.int64), codes=np.stack([done[j]["codes"] for j in finished], -1),
              meta=np.array(json.dumps(meta)))


def _resumed(resume, named: Fingerprint, shape: tuple, count: int) -> dict:
    """The finished directions of the checkpoint ``resume`` (none when there is no file yet); a checkpoint of
    another problem or format is refused, naming what differs."""
    if resume is None or not Path(resume).is_file():
        return {}
    try:
        with np.load(resume, allow_pickle=False) as data:
            if int(data["format"]) != MAP_FORMAT:
                raise InvalidParameterError(f"resume: {str(resume)!r} is a reach-map checkpoint of format "
                                            f"{int(data['format'])}, not {MAP_FORMAT}; start again",
                                            parameter="resume")
            check_fingerprint(json.loads(str(data["fingerprint"])), named,
                              what=f"{str(resume)!r} is the reach-map checkpoint")
            finished, codes = data["finished"], data["codes"]
            meta = json.loads(str(data["meta"]))
            if codes.shape != (*shape, len(finished)) or codes.dtype != CODE or not (
                    (finished >= 0) & (finished < count)).all():
                raise ValueError(f"codes {codes.shape} for a grid {shape}")
            return {int(k): {"index": int(k), "codes": codes[..., i], **meta[str(int(k))]}
                    for i, k in enumerate(finished)}
    except WorkspaceError:
        raise
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
        raise InvalidParameterError(f"resume: {str(resume)!r} is not a reach-map checkpoint ({exc})",
                                    parameter="resume") from None
