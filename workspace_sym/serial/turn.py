"""A spatial arm turned by a LIMITED first joint: section cells proved reached at every polar angle.

The structure is that of :mod:`workspace_sym.serial.section`: ``p = B Rz(theta_1) w(q')`` with ``w = (u, c, v)``
of the other joints ``q'``, ``theta_1`` now in an interval ``[a, b]`` shorter than a period (LBR iiwa:
``340 deg``, Panda: ``332 deg``).  In the frame of the first joint a point of cylindrical coordinates
``(rho, psi, z)`` is reached if and only if some ``q'`` has ``(|w_xy|, w_z) = (rho, z)`` and
``psi - arg w_xy(q')`` in ``[a, b]`` modulo ``2 pi``.

**Every polar angle.**  Let ``A(rho, z)`` be the polar angles ``arg w_xy`` of the configurations ``q'`` reaching
``(rho, z)``.  If ``A`` holds two angles ``alpha`` and ``beta`` whose difference ``d`` (modulo ``2 pi``) lies in
``[2 pi - L, L]`` (``L = b - a``), the arcs ``alpha + [a, b]`` and ``beta + [a, b]`` cover the circle (the gap of
the first, of length ``2 pi - L``, lies in the second), so the point is reached at every polar angle.  Here
``alpha`` and ``beta`` are taken among the four axis directions ``k pi / 2`` of the first joint's frame, where
"``A(rho, z)`` holds ``k pi / 2`` for every ``(rho, z)`` of a cell ``[r0, r1] x [z0, z1]``" is exactly the box
inclusion

    ``[r0, r1] x {0} x [z0, z1]`` (``k = 0``), ``{0} x [r0, r1] x [z0, z1]`` (``k = 1``),
    ``[-r1, -r0] x {0} x [z0, z1]`` (``k = 2``), ``{0} x [-r1, -r0] x [z0, z1]`` (``k = 3``)  in  ``w(Q')``

(``r0`` clipped at 0), which the Krawczyk test of :meth:`~workspace_sym.interval.image.ImageMap.prove_inside`
proves on the map ``w`` itself (three outputs, its joints fixed but three at the Newton solution; the
degenerate coordinate is an interval of width zero): no polar angle is ever computed for a proof.  Two directions
``k pi / 2`` apart by ``d`` in ``{pi / 2, pi, 3 pi / 2}`` qualify when ``d`` lies in ``[2 pi - L, L]``, decided
on an outward enclosure of ``L``: opposite directions when ``L >= pi``, any two when ``L >= 3 pi / 2``.  A cell
with two qualifying directions proved is **inner** (the solid it turns into lies in the workspace); a cell with
one direction ``k`` proved holds the sector ``psi in k pi / 2 + [a, b]``.

**Outside.**  A cell proved outside the section (beyond the greatest distance from the shoulder or within the
least, :meth:`~workspace_sym.serial.section.ShoulderReach.outside_cells`; blocks of cells, stage 2 of
:func:`~workspace_sym.serial.section.section_paving`), or beyond the greatest distance from every place the
elbow can take (:class:`~workspace_sym.serial.section.ElbowReach`), is outside
the workspace at every polar angle, whatever the limits of ``theta_1``.

**Boxes and volume.**  A world box is mapped to the first joint's frame (``B^-1`` in interval arithmetic); it is
inner when its ``(rho, z)`` rectangle lies in inner cells, or in cells proved at one direction ``k`` while its
polar angle range (float ``atan2`` of its corners widened, as the constant-offset section does) lies in
``k pi / 2 + [a, b]``; outer when the rectangle lies in cells outside the section.  The volume is bracketed as
:func:`~workspace_sym.serial.section.turned_volume` does, on pieces of cells (a cell failing whole is tried in
``4^level`` pieces, and those proved count, a cell cut by the section's boundary included): the solids of the
pieces proved at both directions of a pair, plus a share ``L / 2 pi`` (rounded down) of the solids of the pieces
with one direction proved, lie in the workspace; the workspace lies in the solid of the cells not proved
outside, whose pieces beyond the greatest distance from the shoulder (or within the least) are dropped.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace

import numpy as np
import sympy as sp

from ..interval import arith
from ..interval.compiler import CompiledExpr, compile_batch, compile_expr
from ..interval.graph import numpy_constant
from ..interval.image import CellGrid, ImageMap, batch_enclosures
from ..interval.search import split_every_axis
from ..interval.store import ExactSum
from ..interval.verdict import INSIDE as INNER
from ..interval.verdict import OUTSIDE as OUTER
from ..interval.verdict import UNDECIDED
from .angles import arc_within, polar_angles
from .section import (
    ElbowReach,
    RadialMap,
    Turned,
    TurnedTest,
    blocks,
    elbow_reach,
    first_joint_turn,
    in_chunks,
    solid_volumes,
    to_first_frame,
    turned_volume,
)
from .tuning import DEFAULT, Tuning

__all__ = ["DIRECTIONS", "LimitedTurn", "limited_turn", "covering_pairs", "DirectionMap", "direction_seeds",
           "prove_directions", "full_turn_cells", "limited_volume", "pieces_upper", "cell_level", "LimitedTurnTest",
           "pave_limited", "budgeted_width", "SideMap", "constrained_turn", "tool_section", "shifted_section",
           "SpinSectors", "direction_maps", "turned_map", "spin_volume", "roots_volume", "ToolSectionTest"]

SPIN_SECTORS = 36                # sectors of the first joint's range for a constant orientation (SpinSectors)
SPIN_BINS = 720                  # bins of the circle their cover is read on
SPIN_TURNS = 4                   # M: a constant orientation's proofs at 4 M directions (direction_maps)
DIRECTIONS = 4                   # the axis directions k pi / 2 of the first joint's frame (not a tuning: the
                                 # covering pairs and the proofs are written for these four)


@dataclass(frozen=True)
class LimitedTurn:
    """A :class:`~workspace_sym.serial.section.Turned` arm whose first joint turns through ``[a, b]``, less than
    a period: ``inner_range`` (floats inside ``[a, b]``), ``pairs`` (the pairs of directions whose arcs cover
    the circle) and ``share`` (a float at most ``(b - a) / 2 pi``).

    Parameters
    ----------
    plan : Turned
        The turned section.
    inner_range : tuple
        ``(a, b)`` floats within ``theta_1``'s range, in radians.
    pairs : tuple
        The pairs ``(j, k)`` of axis directions whose arcs cover the circle (:func:`covering_pairs`).
    share : float
        At most ``(b - a) / 2 pi``.
    elbow : ElbowReach, optional
        The outer bound from the distance to the elbow (:func:`~workspace_sym.serial.section.elbow_reach`).
    """

    plan: Turned
    inner_range: tuple
    pairs: tuple
    share: float
    elbow: ElbowReach | None = None


def limited_turn(plan, model) -> LimitedTurn | None:
    """The structure of the module docstring when ``plan`` (of ``model``) is a turned section moved by three
    joints or more whose first joint is limited to less than a period but at least a half turn; None
    otherwise.

    Parameters
    ----------
    plan : Turned or other
        The robot's structure (:func:`~workspace_sym.serial.structure.structure_of`).
    model : ReachModel
        The robot's reach model.

    Returns
    -------
    LimitedTurn or None
        The structure, or None.
    """
    if not isinstance(plan, Turned) or plan.full or plan.section.k < 3:
        return None                     # two joints move w over a surface: no box of w is inside its image
    turn = first_joint_turn(model)
    if turn is None:
        return None
    q1, theta, slope = turn
    lo, hi = model.exact_limits[0]
    a, b = sorted((theta.subs(q1, lo), theta.subs(q1, hi)), key=lambda e: float(sp.N(e, 30)))
    length = sp.Abs(slope) * (hi - lo)
    pairs = covering_pairs(length)
    if not pairs:
        return None
    a_f, b_f = numpy_constant(a), numpy_constant(b)
    share = arith.div(numpy_constant(length), numpy_constant(2 * sp.pi))[0]
    return LimitedTurn(plan, (float(a_f[1]), float(b_f[0])), tuple(pairs), float(share), elbow_reach(model))


def covering_pairs(length) -> tuple:
    """The pairs ``(j, k)`` of axis directions whose arcs ``j pi / 2 + [a, b]`` and ``k pi / 2 + [a, b]`` cover the
    circle when ``b - a`` is the exact ``length``: ``d = (k - j) pi / 2`` in ``[2 pi - L, L]``, decided on outward
    enclosures of the exact differences (never a float guess).

    Parameters
    ----------
    length : sympy.Expr
        ``L = b - a``, exact, in radians.

    Returns
    -------
    tuple
        The pairs ``(j, k)``, ``0 <= j < k < 4``, in lexicographic order; empty below half a turn.

    Examples
    --------
    >>> covering_pairs(sp.pi), covering_pairs(3 * sp.pi / 2)[:3], covering_pairs(sp.pi - sp.Rational(1, 10**9))
    (((0, 2), (1, 3)), ((0, 1), (0, 2), (0, 3)), ())
    """
    pairs = []
    for j, k in itertools.combinations(range(DIRECTIONS), 2):
        d = (k - j) * sp.pi / 2
        if numpy_constant(length - d)[0] >= 0 and numpy_constant(d - 2 * sp.pi + length)[0] >= 0:
            pairs.append((j, k))
    return tuple(pairs)


class DirectionMap:
    """The inner test of ``(rho, z)`` cells at the direction ``k pi / 2``: each ``(N, 2, 2)`` cell becomes the box
    of ``w = (u, c, v)`` of the module docstring, proved inside ``w(Q')`` by ``lateral``'s Krawczyk test.

    Parameters
    ----------
    lateral : ImageMap
        The map ``q' -> (u, c, v)``.
    k : int
        The direction, 0 to 3.
    """

    def __init__(self, lateral: ImageMap, k: int):
        self.lateral, self.k = lateral, k

    def boxes(self, T: np.ndarray) -> np.ndarray:
        """The boxes of ``w`` at direction ``k pi / 2`` of the ``(rho, z)`` cells ``T`` (module docstring).

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, 2, 2)`` cells of ``(rho, z)``.

        Returns
        -------
        numpy.ndarray
            ``(N, 3, 2)`` boxes, ``rho`` clipped at 0, the coordinate across the direction a point interval
            ``[0, 0]``.
        """
        r0, r1 = np.maximum(T[:, 0, 0], 0.0), T[:, 0, 1]
        sign = 1.0 if self.k < 2 else -1.0
        radial = np.stack([r0, r1], axis=1) if sign > 0 else np.stack([-r1, -r0], axis=1)
        W = np.zeros((len(T), 3, 2))
        W[:, self.k % 2] = radial
        W[:, 2] = T[:, 1]
        return W

    def prove_inside(self, T: np.ndarray, seeds: np.ndarray) -> np.ndarray:
        """Mask of the cells proved reached at direction ``k pi / 2`` at every point.

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, 2, 2)`` cells of ``(rho, z)``.
        seeds : numpy.ndarray
            ``(N, k')`` joint values from which Newton's method starts.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` booleans (False for a cell wholly at ``rho < 0``).
        """
        return self.lateral.prove_inside(self.boxes(T), seeds) & (T[:, 0, 1] >= 0)

    def prove_sectors(self, T: np.ndarray, seeds: np.ndarray, spin: SpinSectors):
        """:meth:`prove_inside` with the sectors of the first joint's range at which the proof holds
        (:meth:`SpinSectors.masks` over each Krawczyk box); a cell counts as proved when one sector passes.

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, 2, 2)`` cells of ``(rho, z)``.
        seeds : numpy.ndarray
            ``(N, k')`` joint values from which Newton's method starts.
        spin : SpinSectors
            The sectors' test.

        Returns
        -------
        proved : numpy.ndarray
            ``(N,)`` booleans.
        masks : numpy.ndarray
            ``(N,)`` ``uint64``: bit ``i`` set where sector ``i`` passes (0 where not proved).
        """
        lateral = self.lateral
        masks = np.zeros(len(T), dtype=np.uint64)
        if lateral.k < lateral.m or not len(T):
            return np.zeros(len(T), dtype=bool), masks
        W = self.boxes(T)
        q, _ = lateral.newton(0.5 * (W[:, :, 0] + W[:, :, 1]), seeds, steps=8)
        proved, U = lateral.prove_inside_boxes(W, q)
        proved &= T[:, 0, 1] >= 0
        masks[proved] = spin.masks(U[proved])
        return proved & (masks != 0), masks


def direction_maps(lateral: ImageMap) -> list:
    """The inner tests of a section map's directions: the four axis directions ``k pi / 2``
    (:class:`DirectionMap`), or, when ``lateral`` carries ``M - 1`` copies turned by ``j pi / (2 M)`` (``turned``,
    :class:`SideMap` copies of :func:`constrained_turn` with a :class:`SpinSectors`), the ``4 M`` directions ``k
    pi / (2 M)``, direction ``k`` proved on the axes of copy ``k mod M`` (the map itself for 0).

    Parameters
    ----------
    lateral : ImageMap
        The map ``q' -> (u, c, v)``.

    Returns
    -------
    list of DirectionMap
        Direction ``k`` at the polar angle ``k 2 pi / len(list)``.
    """
    maps = [lateral] + list(getattr(lateral, "turned", None) or ())
    return [DirectionMap(maps[k % len(maps)], k // len(maps)) for k in range(DIRECTIONS * len(maps))]


def turned_map(lateral: ImageMap, angle) -> ImageMap:
    """``lateral`` with its outputs ``(u, c)`` turned by ``-angle`` about the first joint's axis: its direction
    ``k pi / 2`` is ``lateral``'s ``angle + k pi / 2`` (the same joints, limits and periodicity; the exact
    rotation compiled with the map, so its proofs are as sound as ``lateral``'s).

    Parameters
    ----------
    lateral : ImageMap
        The map ``q' -> (u, c, v)``.
    angle : sympy.Expr
        The angle, exact.

    Returns
    -------
    ImageMap
        The turned map.
    """
    c, s = sp.cos(angle), sp.sin(angle)
    u, v, z = lateral.expressions
    turned = ImageMap([c * u + s * v, -s * u + c * v, z], lateral.variables, [(0.0, 0.0)] * lateral.k,
                      lateral.periodic)
    turned.limits, turned.face_limits = lateral.limits.copy(), lateral.face_limits.copy()
    turned.inner_limits = lateral.inner_limits.copy()
    return turned


def direction_seeds(lateral: ImageMap, grid, n: int = DEFAULT.direction_samples, seed: int = 0,
                    directions: int = DIRECTIONS):
    """``(index, q)``: for each cell of ``grid`` and each direction ``k``, a sampled configuration reaching the
    cell with its polar angle nearest ``k 2 pi / directions`` (``k pi / 2`` for the four axis directions):
    ``index[k]`` the ``(M, 2)`` cells, ``q[k]`` the ``(M, k')`` configurations (floats: they only choose where a
    proof starts).

    Parameters
    ----------
    lateral : ImageMap
        The map ``q' -> (u, c, v)``.
    grid : CellGrid
        The grid of the section ``(rho, z)``.
    n : int
        Configurations sampled.
    seed : int
        The seed of the random generator.
    directions : int
        Directions, evenly spaced from the first joint's x axis (4, or the 4 M of :func:`direction_maps`).

    Returns
    -------
    index : list of numpy.ndarray
        Per direction, the cells reached.
    q : list of numpy.ndarray
        Per direction, a configuration per cell.
    """
    rng = np.random.default_rng(seed)
    q = lateral.random_configurations(n, rng)
    w = lateral.position_float(q)
    rz = np.stack([np.hypot(w[:, 0], w[:, 1]), w[:, 2]], axis=1)
    cell, _ = grid.span(np.repeat(rz[:, :, None], 2, axis=2))
    angle = np.arctan2(w[:, 1], w[:, 0])
    step = 2 * np.pi / directions
    direction = np.remainder(np.rint(angle / step).astype(int), directions)
    off = np.abs(np.remainder(angle - direction * step + np.pi, 2 * np.pi) - np.pi)
    index, seeds = [], []
    for k in range(directions):
        mine = np.nonzero(direction == k)[0]
        mine = mine[np.argsort(off[mine], kind="stable")]        # the nearest angle first: np.unique keeps it
        cells, first = np.unique(cell[mine], axis=0, return_index=True)
        index.append(cells)
        seeds.append(q[mine[first]])
    return index, seeds


def _split(cells: np.ndarray, level: int):
    """``(pieces, owner, offset)``: each ``(rho, z)`` cell halved along both axes ``level`` times
    (:func:`~workspace_sym.interval.search.split_every_axis`, the same floats as the proofs'), the cell of each
    piece and its position ``(a, b)`` among the ``2^level x 2^level`` pieces of its cell."""
    pieces, owner, offset = cells, np.arange(len(cells)), np.zeros((len(cells), 2), dtype=int)
    for _ in range(level):           # split_every_axis: children grouped by corner, bit k of it the upper half
        pieces, owner = split_every_axis(pieces), np.tile(owner, 4)
        offset = np.concatenate([2 * offset + np.array([c & 1, c >> 1 & 1]) for c in range(4)])
    return pieces, owner, offset


def cell_level(pieces: np.ndarray, grid) -> np.ndarray:
    """The masks over ``grid``'s cells of the cells whose pieces are all proved, from the piece masks of
    :func:`prove_directions` (``(..., n0 F, n1 F)``).

    Parameters
    ----------
    pieces : numpy.ndarray
        Boolean masks over the pieces, ``(..., n0 F, n1 F)`` with ``F`` pieces per cell along each axis.
    grid : CellGrid
        The grid of ``n0 x n1`` cells.

    Returns
    -------
    numpy.ndarray
        Booleans ``(..., n0, n1)``.
    """
    F = pieces.shape[-2] // grid.shape[0]
    return np.asarray(pieces.reshape(pieces.shape[:-2] + (grid.shape[0], F, grid.shape[1], F)).all(axis=(-3, -1)))


def prove_directions(lateral: ImageMap, grid, candidates: np.ndarray, *, budget=None,
                     depth: int = DEFAULT.direction_depth, sampled=None, evaluated: int = 0, state: dict | None = None,
                     chunk: int = DEFAULT.direction_chunk):
    """``(pieces, evaluated, stopped)``: ``pieces[k]`` the mask over the ``2^depth x 2^depth`` pieces of each
    cell of ``grid`` (shape ``(n0 2^depth, n1 2^depth)``) of those proved at direction ``k`` (module
    docstring), among the ``candidates`` (a mask over ``grid``) that hold a sampled configuration near that
    direction (``sampled``: :func:`direction_seeds`, drawn when not given); the cells failing whole are tried
    in ``4^level`` pieces up to ``depth`` (the pieces not within one proved already), each piece proved
    counting for the volume (a cell cut by the boundary of the section keeps its pieces inside).
    ``budget(evaluated, ahead=seconds)`` is asked before each chunk.  ``state`` (a dict, filled on the first
    call) lets a later call go on where a stopped one ended: the cells tried at each level are not tried
    again.

    Parameters
    ----------
    lateral : ImageMap
        The map ``q' -> (u, c, v)``.
    grid : CellGrid
        The grid of the section ``(rho, z)``.
    candidates : numpy.ndarray
        Booleans of ``grid.shape``: the cells that may be tried.
    budget : callable, optional
        ``budget(evaluated, ahead=seconds)``: a stop reason, or ``""`` to go on; None: no budget.
    depth : int
        The deepest level of pieces.
    sampled : tuple, optional
        ``(index, q)`` of :func:`direction_seeds`.
    evaluated : int
        Boxes evaluated before.
    state : dict, optional
        Kept between calls (see above); it fixes ``depth`` on its first call.
    chunk : int
        Cells proved between two looks at the budget (divided by ``4^level`` at each level).

    Returns
    -------
    pieces : numpy.ndarray
        Booleans ``(4, n0 2^depth, n1 2^depth)``.
    evaluated : int
        The count, with the proofs of this call.
    stopped : str
        Why ``budget`` stopped it (``""``: it did not).
    """
    budget = budget or (lambda evaluated, ahead=0.0: "")
    F = 2 ** depth
    maps = direction_maps(lateral)
    D = len(maps)
    if state is None or not state:
        state = {} if state is None else state
        state["pieces"] = np.zeros((D, grid.shape[0] * F, grid.shape[1] * F), dtype=bool)
        state["tried"] = np.zeros((depth + 1, D) + grid.shape, dtype=bool)
    pieces, tried = state["pieces"], state["tried"]
    spin = getattr(lateral, "spin", None)
    if spin is not None and "sectors" not in state:
        state["sectors"] = np.zeros(pieces.shape, dtype=np.uint64)
    index, seeds = sampled if sampled is not None else direction_seeds(lateral, grid, directions=D)
    count = [evaluated]
    pace = [0.0]

    def ask(ahead):
        return budget(count[0], ahead=ahead)

    stopped = ""
    for level in range(depth + 1):
        for k in range(D):
            image = maps[k]
            at = tuple(index[k].T)
            todo = np.nonzero(candidates[at] & ~cell_level(pieces[k], grid)[at] & ~tried[level, k][at])[0]

            def prove(part, k=k, image=image, level=level):
                cells = index[k][part]
                tried[level, k][tuple(cells.T)] = True
                boxes, owner, offset = _split(grid.cells(cells), level)
                size = F >> level
                rows = cells[owner, 0] * F + offset[:, 0] * size
                cols = cells[owner, 1] * F + offset[:, 1] * size
                done = np.ones(len(boxes), dtype=bool)
                for a, b in itertools.product(range(size), repeat=2):
                    done &= pieces[k][rows + a, cols + b]
                count[0] += int((~done).sum())
                inside = np.zeros(len(boxes), dtype=bool)
                if spin is None:
                    inside[~done] = image.prove_inside(boxes[~done], seeds[k][part][owner[~done]])
                else:
                    masks = np.zeros(len(boxes), dtype=np.uint64)
                    inside[~done], masks[~done] = image.prove_sectors(boxes[~done], seeds[k][part][owner[~done]],
                                                                      spin)
                for a, b in itertools.product(range(size), repeat=2):
                    pieces[k][rows[inside] + a, cols[inside] + b] = True
                    if spin is not None:
                        state["sectors"][k][rows[inside] + a, cols[inside] + b] = masks[inside]

            stopped = in_chunks(todo, max(1, chunk // 4 ** level), ask, prove, pace, 4 ** level)
            if stopped:
                return pieces, count[0], stopped
    return pieces, count[0], stopped


def full_turn_cells(limited: LimitedTurn, classes: np.ndarray, pieces: np.ndarray,
                    sectors: np.ndarray | None = None) -> np.ndarray:
    """Classes of the cells for every polar angle: inner where two directions of a qualifying pair are proved
    (every piece of the cell, ``pieces`` as :func:`prove_directions` gives them), or, with ``sectors``, where the
    sectors proved at the directions cover the circle (:meth:`SpinSectors.bins_covered`, every piece); outer
    where the section's cell is, undecided elsewhere.

    Parameters
    ----------
    limited : LimitedTurn
        The structure (its covering pairs).
    classes : numpy.ndarray
        The verdict code of each cell of the section (only its outer cells are read).
    pieces : numpy.ndarray
        The pieces proved at each direction.
    sectors : numpy.ndarray, optional
        The sectors' masks of each piece at each direction (``uint64``, :func:`prove_directions` with a
        :class:`SpinSectors` map), read with the map's ``spin``.

    Returns
    -------
    numpy.ndarray
        Verdict codes (``int8``) of the cells for every polar angle.
    """
    F = pieces.shape[-2] // classes.shape[0]

    def whole(mask):                    # cells all of whose pieces are in mask
        return mask.reshape(classes.shape[0], F, classes.shape[1], F).all(axis=(1, 3))

    spin = getattr(limited.plan.section.lateral, "spin", None)
    full = np.zeros(classes.shape, dtype=bool)
    if spin is None:
        for j, k in limited.pairs:
            full |= whole(pieces[j] & pieces[k])
    elif sectors is not None:
        covered = np.zeros(pieces.shape[1:], dtype=bool)
        some = np.nonzero(pieces.sum(axis=0) >= 2)             # one direction's arc is short of a turn
        covered[some] = spin.bins_covered(sectors[(slice(None),) + some]) == spin.bins
        full = whole(covered)
    out = np.full(classes.shape, UNDECIDED, dtype=np.int8)
    out[full & (classes != OUTER)] = INNER
    out[classes == OUTER] = OUTER
    return out


def limited_volume(limited: LimitedTurn, grid, full: np.ndarray, pieces: np.ndarray,
                   tuning: Tuning = DEFAULT) -> tuple[float, float]:
    """A proved bracket of the workspace's volume (module docstring) from the full-turn classes ``full`` and the
    pieces proved at each direction (:func:`prove_directions`): a piece proved at both directions of a pair
    turns into a solid in the workspace, a piece proved at one direction gives a share ``L / 2 pi`` (rounded
    down) of its solid.  The upper bound is that of the cells not outside, also sought on the pieces of the
    undecided cells (:func:`pieces_upper`), the lesser kept.

    Parameters
    ----------
    limited : LimitedTurn
        The structure.
    grid : CellGrid
        The grid of the section ``(rho, z)``.
    full : numpy.ndarray
        The full-turn verdict code of each cell (:func:`full_turn_cells`).
    pieces : numpy.ndarray
        The pieces proved at each direction.
    tuning : Tuning
        ``shoulder_pieces`` and ``reach_tolerance`` (:func:`pieces_upper`).

    Returns
    -------
    lo : float
        A lower bound of the workspace's volume.
    hi : float
        An upper bound.
    """
    high = turned_volume(grid, full)[1]
    if limited.plan.section.reach is not None:
        high = min(high, pieces_upper(limited.plan.section.reach, grid, full, tuning.shoulder_pieces,
                                       tuning.reach_tolerance, elbow=limited.elbow))
    F = pieces.shape[-2] // grid.shape[0]
    both = np.zeros(pieces.shape[1:], dtype=bool)
    for j, k in limited.pairs:
        both |= pieces[j] & pieces[k]
    outer = np.repeat(np.repeat(full == OUTER, F, axis=0), F, axis=1)
    both &= ~outer
    one = pieces.any(axis=0) & ~both & ~outer
    whole = both.reshape(grid.shape[0], F, grid.shape[1], F).all(axis=(1, 3))       # cells inner: whole solids
    cells = turned_volume(grid, np.where(whole, INNER, OUTER).astype(np.int8))[0]
    at = np.argwhere((both | one).reshape(grid.shape[0], F, grid.shape[1], F).any(axis=(1, 3)) & ~whole)
    boxes, owner, offset = _split(grid.cells(at), F.bit_length() - 1)
    rows, cols = at[owner, 0] * F + offset[:, 0], at[owner, 1] * F + offset[:, 1]
    volumes = solid_volumes(boxes[:, 0, 0], boxes[:, 0, 1], boxes[:, 1, 0], boxes[:, 1, 1])[0]
    low = ExactSum.of(volumes[both[rows, cols]]).value_down
    part = ExactSum.of(volumes[one[rows, cols]]).value_down
    with np.errstate(all="ignore"):
        extra = arith.mul((part, part), (limited.share, limited.share))[0]
        total = arith.add(arith.add((cells, cells), (low, low)), (extra, extra))[0]
    return float(total), high


def spin_volume(limited: LimitedTurn, grid, full: np.ndarray, pieces: np.ndarray, sectors: np.ndarray,
                tuning: Tuning = DEFAULT) -> tuple[float, float]:
    """A proved bracket of the volume swept by a constant orientation's section (:class:`SpinSectors` on
    ``limited``'s map): each piece not in an outer cell gives the share of its solid of the bins of polar angle
    its sectors cover (:meth:`SpinSectors.bins_covered`, rounded down), a cell inner at every polar angle its
    whole solid; the upper bound as :func:`limited_volume`'s.

    Parameters
    ----------
    limited : LimitedTurn
        The structure (its map's ``spin`` set, :func:`constrained_turn`).
    grid : CellGrid
        The grid of the section ``(rho, z)``.
    full : numpy.ndarray
        The full-turn verdict code of each cell (:func:`full_turn_cells`).
    pieces : numpy.ndarray
        The pieces proved at each direction.
    sectors : numpy.ndarray
        Their sectors' masks (``pave_limited``'s ``state["sectors"]``).
    tuning : Tuning
        As for :func:`limited_volume`.

    Returns
    -------
    lo : float
        A lower bound of the volume.
    hi : float
        An upper bound.
    """
    spin = getattr(limited.plan.section.lateral, "spin", None)
    if spin is None:
        raise ValueError("spin_volume needs a section map with sectors (constrained_turn with a spin condition)")
    high = turned_volume(grid, full)[1]
    if limited.plan.section.reach is not None:
        high = min(high, pieces_upper(limited.plan.section.reach, grid, full, tuning.shoulder_pieces,
                                       tuning.reach_tolerance, elbow=limited.elbow))
    F = pieces.shape[-2] // grid.shape[0]
    whole = full == INNER
    cells = turned_volume(grid, np.where(whole, INNER, OUTER).astype(np.int8))[0]
    cell_of = np.repeat(np.repeat(whole | (full == OUTER), F, axis=0), F, axis=1)
    some = np.nonzero((pieces.sum(axis=0) >= 2) & ~cell_of)
    counts = np.zeros(pieces.shape[1:], dtype=np.int64)
    counts[some] = spin.bins_covered(sectors[(slice(None),) + some])
    low = _binned_volume(grid, counts, spin.bins)
    if not low:
        return float(cells), high
    return float(arith.add((cells, cells), (low, low))[0]), high


def _binned_volume(grid, counts: np.ndarray, bins: int) -> float:
    """A lower bound (rounded down) of the solids of the pieces of ``grid``'s cells turned through the share
    ``counts / bins`` of the circle each covers (``counts`` over the pieces, ``(n0 F, n1 F)``); 0 when none."""
    F = counts.shape[-2] // grid.shape[0]
    at = np.argwhere((counts > 0).reshape(grid.shape[0], F, grid.shape[1], F).any(axis=(1, 3)))
    if not len(at):
        return 0.0
    boxes, owner, offset = _split(grid.cells(at), F.bit_length() - 1)
    rows, cols = at[owner, 0] * F + offset[:, 0], at[owner, 1] * F + offset[:, 1]
    volumes = solid_volumes(boxes[:, 0, 0], boxes[:, 0, 1], boxes[:, 1, 0], boxes[:, 1, 1])[0]
    got = counts[rows, cols].astype(float)
    with np.errstate(all="ignore"):
        share = arith.div((got, got), (float(bins), float(bins)))[0]
        parts = arith.mul((volumes, volumes), (share, share))[0]
    return float(ExactSum.of(np.maximum(parts[got > 0], 0.0)).value_down)


def roots_volume(parts, grid, chunk: int = 20_000, outer: np.ndarray | None = None):
    """``(codes, (lo, hi))``: the cells of one grid swept at every polar angle and a proved volume bracket, from
    the sections of a tool point's several maps (a wrist's solutions, :class:`~workspace_sym.serial.pose.
    OffsetFlange`), each paved on ``grid`` (:func:`pave_limited` with its ``box``) with its own sectors
    (:class:`SpinSectors`).  A point is swept at a polar angle when one map's proofs reach it there, so the bins a
    piece covers are the union of each map's (:meth:`SpinSectors.covered_bins`); a cell is inner when every piece
    of it covers every bin (or one map's cell is inner), outer when every map's cell is outer.  The lower bound
    takes each piece's share of its solid of the bins covered (rounded down), the upper bound Pappus's theorem on
    the cells not outer.

    Parameters
    ----------
    parts : sequence of tuple
        ``(limited, full, pieces, sectors)`` per map: its structure (the map's ``spin`` set), full-turn codes
        (:func:`full_turn_cells`), pieces proved at each direction and their sectors' masks (``state["sectors"]``).
    grid : CellGrid
        The grid of all of them.
    chunk : int
        Pieces per step (memory).
    outer : numpy.ndarray, optional
        The cells proved outside the whole set (a cone's, proved on its own map); None: those outer for every map.

    Returns
    -------
    codes : numpy.ndarray
        Verdict codes (``int8``) of the cells for every polar angle.
    bracket : tuple of float
        ``(lo, hi)`` of the volume swept.
    """
    F = parts[0][2].shape[-2] // grid.shape[0]
    if outer is None:
        outer = np.logical_and.reduce([full == OUTER for _, full, _, _ in parts])
    inner = np.logical_or.reduce([full == INNER for _, full, _, _ in parts]) & ~outer
    skip = np.repeat(np.repeat(outer | inner, F, axis=0), F, axis=1)
    some = np.nonzero(np.logical_or.reduce([pieces.any(axis=0) for _, _, pieces, _ in parts]) & ~skip)
    counts = np.zeros(parts[0][2].shape[1:], dtype=np.int64)
    bins = 0
    for start in range(0, len(some[0]), chunk):
        window = tuple(a[start:start + chunk] for a in some)
        covered = np.zeros((len(window[0]), 1), dtype=bool)
        for limited, _, _, sectors in parts:
            spin = limited.plan.section.lateral.spin
            covered = covered | spin.covered_bins(sectors[(slice(None),) + window])
            bins = spin.bins
        counts[window] = covered.sum(axis=1)
    if bins:
        inner |= (counts == bins).reshape(grid.shape[0], F, grid.shape[1], F).all(axis=(1, 3)) & ~outer
    codes = np.full(grid.shape, UNDECIDED, dtype=np.int8)
    codes[inner] = INNER
    codes[outer] = OUTER
    high = turned_volume(grid, codes)[1]
    cells = turned_volume(grid, np.where(inner, INNER, OUTER).astype(np.int8))[0]
    counts[np.repeat(np.repeat(inner | outer, F, axis=0), F, axis=1)] = 0
    low = _binned_volume(grid, counts, bins) if bins else 0.0
    if not low:
        return codes, (float(cells), high)
    return codes, (float(arith.add((cells, cells), (low, low))[0]), high)

def pieces_upper(reach, grid, classes: np.ndarray, pieces: int = DEFAULT.shoulder_pieces,
                 tolerance: float = DEFAULT.reach_tolerance, elbow: ElbowReach | None = None) -> float:
    """An upper bound of the volume of the solid of revolution of the section from its classes and the distance
    from the shoulder (:class:`~workspace_sym.serial.section.ShoulderReach`): the solids of the inner cells, plus
    those of the pieces of the undecided cells (each cut ``pieces`` times along both axes, the cell's own edges
    kept as the outer edges of its pieces, so that they cover it) not proved outside by that distance, summed
    rounded up.  The cells cut by the sphere of the greatest distance (or the least) weigh only their part
    within it, to a piece.

    Parameters
    ----------
    reach : ShoulderReach
        The distance from the shoulder.
    grid : CellGrid
        The grid of the section ``(rho, z)``.
    classes : numpy.ndarray
        The verdict code of each cell.
    pieces : int
        Cuts along each axis of an undecided cell.
    tolerance : float
        The tolerance of the distance bounds, in pieces' widths (:meth:`ShoulderReach.outside`).
    elbow : ElbowReach, optional
        The distance from the elbow: the pieces it proves outside are dropped too (those of the cells it
        proves outside whole first, then the pieces of the others).

    Returns
    -------
    float
        The bound, rounded up.
    """
    e0, e1 = grid.edges
    at = np.argwhere(classes == UNDECIDED)
    t = np.linspace(0.0, 1.0, pieces + 1)

    def cut(e, index):                          # (N, pieces + 1) edges, the ends exactly the cell's
        lo, hi = e[index][:, None], e[index + 1][:, None]
        edges = lo + (hi - lo) * t[None, :]
        edges[:, 0], edges[:, -1] = lo[:, 0], hi[:, 0]
        return edges

    r, z = cut(e0, at[:, 0]), cut(e1, at[:, 1])
    r0, r1 = r[:, :-1, None], r[:, 1:, None]
    z0, z1 = z[:, None, :-1], z[:, None, 1:]
    kept = ~reach.outside(r0, r1, z0, z1, grid.width / pieces, tolerance)
    if elbow is not None and len(at):
        edges = (e0[at[:, 0]], e0[at[:, 0] + 1], e1[at[:, 1]], e1[at[:, 1] + 1])
        whole = elbow.outside(*edges, grid.width, tolerance)
        kept[whole] = False
        rest = np.nonzero(kept.any(axis=(1, 2)) & ~elbow.within(*edges, grid.width))[0]
        if len(rest):
            shape = kept[rest].shape
            b0, b1, c0, c1 = (np.broadcast_to(x[rest], shape) for x in (r0, r1, z0, z1))
            far = elbow.outside(b0, b1, c0, c1, grid.width, tolerance)
            kept[rest] &= ~far
    shape = kept.shape
    vol = solid_volumes(*(np.broadcast_to(x, shape)[kept] for x in (r0, r1, z0, z1)))[1]
    inner = turned_volume(grid, np.where(classes == INNER, INNER, OUTER).astype(np.int8))[1]
    total = ExactSum.of(vol)
    total.add(np.array([inner]))
    return float(total.value_up)


class LimitedTurnTest(TurnedTest):
    """Classify world boxes of ``(x, y, z)`` from the full-turn classes and the directions proved (module
    docstring).

    Called with ``(N, 3, 2)`` boxes, it returns the masks ``(is_in, is_out)``: proved inner, proved outer (never
    both).

    Parameters
    ----------
    limited : LimitedTurn
        The structure.
    grid : CellGrid
        The grid of the section ``(rho, z)``.
    full : numpy.ndarray
        The full-turn verdict code of each cell (:func:`full_turn_cells`).
    pieces : numpy.ndarray
        The pieces proved at each direction (:func:`prove_directions`).
    """

    def __init__(self, limited: LimitedTurn, grid, full: np.ndarray, pieces: np.ndarray):
        super().__init__(limited.plan, grid, full)
        self.limited = limited
        self.sectors = [grid.prefix(np.where(p, INNER, UNDECIDED).astype(np.int8), INNER)
                        for p in cell_level(pieces, grid)]

    def __call__(self, X: np.ndarray):
        F = self.rectangles(X)
        finite = np.isfinite(F).all(axis=(1, 2))
        inner = finite & self.grid.all_in_class(self.inside, F, outside_counts=False)
        outer = finite & self.grid.all_in_class(self.outside, F, outside_counts=True)
        rest = np.nonzero(finite & ~inner & ~outer)[0]
        if len(rest):
            lo, hi = polar_angles(to_first_frame(self.plan.inverse, X[rest]))
            a, b = self.limited.inner_range
            for k, table in enumerate(self.sectors):
                turn = k * math.pi / 2
                within = arc_within(lo - turn, hi - turn, a, b, False)
                cells = self.grid.all_in_class(table, F[rest], outside_counts=False)
                inner[rest[within & cells]] = True
        return inner, outer & ~inner


def budgeted_width(limited: LimitedTurn, tuning: Tuning = DEFAULT) -> float:
    """The section cells' width of a run with a budget (a time limit or a budget of section boxes), whatever its
    ``delta``: the greatest distance from the shoulder (its bound within a hundredth of the root enclosure of
    the squared distance) over ``tuning.budget_cells``, or half the longest side of the section's enclosure over
    it without a shoulder.  A finer ``delta`` then paves the same section within the same budget (the proved
    volume bracket does not depend on the task boxes), where a section tied to ``delta`` would spend the same
    time on four times the cells.  Floats: the width only chooses where proofs are tried.

    Parameters
    ----------
    limited : LimitedTurn
        The structure.
    tuning : Tuning
        ``budget_cells``.

    Returns
    -------
    float
        The width.
    """
    section = limited.plan.section
    if section.reach is not None:
        root = float(section.reach.enclose(section.reach.map.limits[None])[1][0])
        radius = math.sqrt(max(section.reach.bound(0.01 * max(root, 0.0)), 0.0))
    else:
        box = section.enclose(section.limits[None])[0]
        radius = 0.5 * float(np.max(box[:, 1] - box[:, 0]))
    if not (radius > 0 and math.isfinite(radius)):
        box = section.enclose(section.limits[None])[0]
        radius = 0.5 * float(np.max(box[:, 1] - box[:, 0]))
    return radius / tuning.budget_cells


def pave_limited(limited: LimitedTurn, width: float, run, *, show=None, boxes: int | None = None,
                 tuning: Tuning = DEFAULT, state: dict | None = None, box: np.ndarray | None = None):
    """``(grid, full classes, pieces, evaluated, reason)`` over a grid of the given width on the section's
    enclosure: its cells tried at the four directions (:func:`prove_directions`, whose pieces are returned),
    then blocks of cells proved outside the section (stage 2 of
    :func:`~workspace_sym.serial.section.section_paving`; a cell holding a sampled position is never tried, a
    cell inner at every angle is skipped).  With a time limit, the directions
    take ``tuning.directions_share`` of the time left when called, the blocks run until ``tuning.blocks_end`` of it (the
    directions go on where they stopped when the blocks end before), the world boxes take the rest.  With a
    budget of ``boxes`` (evaluated here; the same cells on every machine), the stages stop at the same shares
    of it, the step under way ending first.

    Parameters
    ----------
    limited : LimitedTurn
        The structure.
    width : float
        The cells' width.
    run : RunBudget
        The run's budget (its clock, ``time_limit`` and ``stop_reason``).
    show : callable, optional
        ``show(share decided, evaluated)`` for the blocks.
    boxes : int, optional
        A budget of boxes for this section (``StopAt.section_boxes``).
    tuning : Tuning
        ``reach_tolerance``, ``direction_samples``, ``direction_depth`` (``timed_depth`` with a time limit),
        ``direction_chunk``, ``directions_share``, ``blocks_end``, ``section_pairs``.
    state : dict, optional
        An empty dict, filled with the direction proofs' state (:func:`prove_directions`: ``"sectors"`` for a
        constant orientation's map, read by :func:`spin_volume`).
    box : numpy.ndarray, optional
        The ``(2, 2)`` box of the grid, holding the section's enclosure (several sections on one grid,
        :func:`roots_volume`); None: the enclosure.

    Returns
    -------
    tuple
        ``(grid, classes, pieces, evaluated, reason)``: the :class:`~workspace_sym.interval.image.CellGrid`, the
        full-turn verdict codes, the pieces proved at each direction, the boxes evaluated, and why the run's
        budget stopped it (``""``: it did not, or only a share ran out).
    """
    section = limited.plan.section
    limit, begun = run.time_limit, run.seconds
    show = show or (lambda share, evaluated: None)

    def until(share, why):
        def budget(count, ahead=0.0):
            late = limit is not None and run.seconds + 1.5 * ahead > begun + share * (limit - begun)
            spent = boxes is not None and count >= share * boxes
            return run.stop_reason(count) or (why if late or spent else "")
        return budget

    grid = CellGrid(section.enclose(section.limits[None])[0] if box is None else box, width)
    # The cells beyond the greatest distance from the shoulder, or within the least: outside, in two proofs.
    outside = (np.zeros(grid.shape, dtype=bool) if section.reach is None
               else section.reach.outside_cells(grid, tuning.reach_tolerance))
    if limited.elbow is not None:       # the distance from the elbow, on the cells the shoulder left
        e0, e1 = grid.edges
        at = np.argwhere(~outside)
        outside[tuple(at.T)] = limited.elbow.outside(e0[at[:, 0]], e0[at[:, 0] + 1], e1[at[:, 1]],
                                                     e1[at[:, 1] + 1], grid.width, tuning.reach_tolerance)
    sampled = direction_seeds(section.lateral, grid, tuning.direction_samples,
                              directions=len(direction_maps(section.lateral)))
    reached = np.zeros(grid.shape, dtype=np.int8)
    for index in sampled[0]:
        reached[tuple(index.T)] = 1
    state = {} if state is None else state
    depth = tuning.direction_depth if limit is None else tuning.timed_depth
    proved, evaluated, reason = prove_directions(section.lateral, grid, ~outside,
                                                 budget=until(tuning.directions_share, "share"), sampled=sampled,
                                                 state=state, depth=depth, chunk=tuning.direction_chunk)
    classes = full_turn_cells(limited, np.where(outside, OUTER, UNDECIDED).astype(np.int8), proved,
                              state.get("sectors"))
    if reason != "share" and reason:
        return grid, classes, proved, evaluated, reason
    found = classes.copy()
    evaluated, reason = blocks(section, grid, found, grid.prefix(reached, 1), until(tuning.blocks_end, "share"),
                               show, tuning.section_pairs, evaluated)
    classes[found == OUTER] = OUTER             # (a block proved inside the section proves nothing here)
    if not reason:              # the blocks ended early: the directions go on with the time left until blocks_end
        proved, evaluated, reason = prove_directions(section.lateral, grid, classes != OUTER,
                                                     budget=until(tuning.blocks_end, "share"), sampled=sampled,
                                                     evaluated=evaluated, state=state, depth=depth,
                                                     chunk=tuning.direction_chunk)
        classes = full_turn_cells(limited, classes, proved, state.get("sectors"))
    return grid, classes, proved, evaluated, "" if reason == "share" else reason


# ----------------------------------------------------------------------------------------------- a tool along the
# approach from a wrist centre (docs/methods.md section 8, "A cone through the wrist centre")
class SideMap(ImageMap):
    """The section map ``q' -> (u, c, v)`` of a limited turn whose inner proofs also prove side conditions
    ``s_i(q') >= bound_i`` over each Krawczyk box (the hook :meth:`~workspace_sym.interval.image.ImageMap.admissible`);
    it shares the compiled map of ``lateral``.  Its random configurations satisfy the conditions in floats (they
    only choose where proofs start).

    Parameters
    ----------
    lateral : ImageMap
        The section map.
    sides : sequence of tuple
        ``(s_i, bound_i)`` pairs: ``s_i`` in ``lateral``'s variables, ``bound_i`` a float at least the exact
        bound (an outward enclosure's upper end): ``s_i >= bound_i`` proves the condition.
    prune : bool
        Every configuration the section stands for meets the conditions (a wrist solution's joints within their
        limits, :class:`~workspace_sym.serial.pose.OffsetFlange`), so the outer proofs leave the joint boxes
        that break one (:meth:`refused`); False (a cone's tilt, which only chooses the inner cells): they do
        not.
    slack : sequence of float, optional
        Per side, how far below its bound a configuration the outer proofs stand for may bring it (a cone's
        approaches other than the one proved, :class:`~workspace_sym.serial.pose.OffsetFlange`): :meth:`refused`
        leaves only the boxes below ``bound_i - slack_i``; None: 0 each.

    Attributes
    ----------
    spin : SpinSectors or None
        The sectors of the first joint's range at which a proof holds (:func:`prove_directions` reads it);
        None: every polar angle of the direction's arc.
    turned : list of SideMap
        The same map turned by ``j pi / (2 M)``, ``j = 1 .. M - 1`` (:func:`turned_map`): ``4 M`` directions
        (:func:`direction_maps`); empty: the four axis directions.
    """

    def __init__(self, lateral: ImageMap, sides, prune: bool = False, slack=None):
        self.__dict__.update(lateral.__dict__)        # the same compiled map: no second symbolic preparation
        self.prune = prune
        self._enclose = lateral.enclose               # and its own enclosures (a FlangeMap clips its unit vector)
        self._enclose_outer = getattr(lateral, "enclose_outer", lateral.enclose)
        self.spin: SpinSectors | None = None          # set by constrained_turn for a constant orientation
        self.turned: list = []
        self.sides = tuple((sp.sympify(side), float(bound)) for side, bound in sides)
        if not self.sides:
            raise ValueError("a side map needs at least one side condition")
        self.slack = tuple(float(x) for x in (slack or (0.0,) * len(self.sides)))
        if len(self.slack) != len(self.sides) or min(self.slack) < 0:
            raise ValueError(f"slack: one bound at least 0 per side condition; got {slack!r}")
        self._sides = [compile_expr(side, self.variables) for side, _ in self.sides]
        self._sides_float = [sp.lambdify([self.variables], side, modules="numpy") for side, _ in self.sides]

    def enclose(self, Q: np.ndarray) -> np.ndarray:
        """The enclosures of the map it was made from (:meth:`~workspace_sym.interval.image.ImageMap.enclose`).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            ``(N, 3, 2)`` outward-rounded enclosures.
        """
        return self._enclose(Q)

    def enclose_outer(self, Q: np.ndarray) -> np.ndarray:
        """The outer proofs' enclosures of the map it was made from (a cone's every approach,
        :meth:`~workspace_sym.serial.pose.FlangeMap.enclose_outer`; else :meth:`enclose`).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            ``(N, 3, 2)`` outward-rounded enclosures.
        """
        return self._enclose_outer(Q)

    def admissible(self, box: np.ndarray) -> np.ndarray:
        """Mask of the joint boxes on which every ``s_i >= bound_i`` is proved (outward-rounded; NaN: not proved).

        Parameters
        ----------
        box : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` booleans.
        """
        proved = np.ones(len(box), dtype=bool)
        for lo, _, bound in self._side_enclosures(box):
            proved &= lo >= bound
        return proved

    def refused(self, box: np.ndarray) -> np.ndarray:
        """Mask of the joint boxes on which some ``s_i < bound_i - slack_i`` is proved (outward-rounded, a margin
        of 1e-12 below ``bound_i`` for the exact bound it rounds up): no configuration of such a box meets the
        conditions, so the outer proofs may leave it (:meth:`~workspace_sym.serial.section.RadialMap.enclose`).

        Parameters
        ----------
        box : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` booleans.
        """
        out = np.zeros(len(box), dtype=bool)
        for (_, hi, bound), slack in zip(self._side_enclosures(box), self.slack):
            out |= hi < bound - slack - 1e-12
        return out

    def _side_enclosures(self, box: np.ndarray):
        """``(lo, hi, bound_i)`` per side: the outward enclosures of ``s_i`` over the boxes (NaN where none)."""
        X = [(box[:, j, 0], box[:, j, 1]) for j in range(box.shape[1])]
        with np.errstate(all="ignore"):
            for side, (_, bound) in zip(self._sides, self.sides):
                lo, hi = side(X)
                yield np.broadcast_to(lo, (len(box),)), np.broadcast_to(hi, (len(box),)), bound

    def random_configurations(self, n: int, rng) -> np.ndarray:
        """Up to ``n`` configurations uniform within the limits on which every ``s_i > bound_i`` in floats.

        Parameters
        ----------
        n : int
            Number of configurations wanted.
        rng : numpy.random.Generator
            The source of the draws.

        Returns
        -------
        numpy.ndarray
            ``(M, k)`` joint values, ``M <= n`` (fewer when the conditions are rarely met).
        """
        kept: list = []
        for _ in range(8):
            q = super().random_configurations(n, rng)
            good = np.ones(len(q), dtype=bool)
            with np.errstate(all="ignore"):
                for side, (_, bound) in zip(self._sides_float, self.sides):
                    good &= np.broadcast_to(np.asarray(side(q.T), dtype=float), (len(q),)) > bound
            kept.append(q[good])
            if sum(map(len, kept)) >= n:
                break
        return np.concatenate(kept)[:n]


class SpinSectors:
    """Where a direction proof of a constant orientation holds (docs/methods.md section 8, "A constant orientation
    through the wrist centre"): the first joint's range ``[a, b]`` (the floats of ``inner_range``) is cut into
    ``count`` sectors; over a sector and a Krawczyk box of the section's joints, one of the wrist's two solutions
    (the one the condition's ``root`` names, when it names one) is proved within the limits of the roll and of
    the last joint (:class:`~workspace_sym.serial.pose.SpinCondition`, every bound outward-rounded).  A proof at
    the direction ``k`` (polar angle ``beta_k``) then holds at the polar angles ``theta_1 + beta_k`` of the
    sectors that pass.

    Parameters
    ----------
    condition : SpinCondition or None
        The condition's expressions; None: no condition, every sector passes wherever a direction is proved (the
        arcs of several maps' proofs read together, :func:`roots_volume`; give ``count=1``).
    variables : sequence of sympy.Symbol
        The section's joints.
    inner_range : tuple of float
        ``(a, b)`` within the first joint's DH range.
    count : int
        Sectors (at most 64, one bit each).
    bins : int
        Bins of the circle for :meth:`covered_bins`.
    directions : int
        The directions' count, evenly spaced from the first joint's x axis (:func:`direction_maps`).

    Attributes
    ----------
    condition : SpinCondition
        The condition (its expressions, for the tests' second methods).
    root : int
        The condition's ``root``: 0 for either solution, else the one solution proved.
    """

    MARGIN = 1e-9                 # radians: far above the float error of a sum of angles

    def __init__(self, condition, variables, inner_range, count: int = SPIN_SECTORS, bins: int = SPIN_BINS,
                 directions: int = DIRECTIONS):
        if not 1 <= count <= 64:
            raise ValueError(f"count: 1 to 64 sectors; got {count}")
        variables = tuple(variables)
        self.count, self.bins, self.directions = count, bins, directions
        self.condition, self.root = condition, getattr(condition, "root", 0)
        # without a condition, the proofs' arcs only: every sector passes where a direction is proved
        self._X: CompiledExpr | None = None
        self._Y: CompiledExpr | None = None
        self._spin: CompiledExpr | None = None
        self._roll: CompiledExpr | None = None
        if condition is not None:
            self._X = compile_expr(condition.X, variables)
            self._Y = compile_expr(condition.Y, (condition.turn,) + variables)
            self._spin = compile_expr(condition.spin * condition.V2 - condition.Y ** 2, (condition.turn,) + variables)
            if condition.roll is not None:
                self._roll = compile_expr(condition.roll * condition.V2 - condition.X ** 2, variables)
        self._linear = None
        if condition is not None and getattr(condition, "linear", None) is not None:
            # Y = A cos(t) + B sin(t) + C: A, B, C and V^2 enclosed once per box, Y per sector from them
            self._linear = compile_batch(list(condition.linear) + [condition.V2], variables)
            self._cos2 = numpy_constant(condition.spin)
        a, b = inner_range
        edges = np.linspace(a, b, count + 1)
        edges[0], edges[-1] = a, b
        self.edges = edges
        # each sector's cosine and sine, and at its middle, with the offsets from the middle (outward)
        lo, hi = edges[:-1], edges[1:]
        middle = 0.5 * (lo + hi)
        with np.errstate(all="ignore"):
            self._trig = (arith.cos((lo, hi)), arith.sin((lo, hi)), arith.cos((middle, middle)),
                          arith.sin((middle, middle)), (arith.sub((lo, lo), (middle, middle))[0],
                                                        arith.sub((hi, hi), (middle, middle))[1]))
        # For each direction and bin of the circle: whether the bin lies in the direction's arc, and the first
        # and last sectors that may meet it (margins outward), read by covered().
        width = 2 * math.pi / bins
        start = np.arange(bins) * width
        self._inside, self._first, self._last = [], [], []
        for k in range(directions):
            rel = np.remainder(start - (a + k * 2 * math.pi / directions), 2 * math.pi)
            self._inside.append((rel >= self.MARGIN) & (rel + width <= (b - a) - self.MARGIN))
            scale = count / (b - a)
            self._first.append(np.clip(np.floor((rel - self.MARGIN) * scale), 0, count - 1).astype(int))
            self._last.append(np.clip(np.floor((rel + width + self.MARGIN) * scale), 0, count - 1).astype(int))
        # the bits a bin needs at each direction (its first and last sectors), read as one word
        one = np.uint64(1)
        self._need = [(one << first.astype(np.uint64)) | (one << last.astype(np.uint64))
                      for first, last in zip(self._first, self._last)]

    def masks(self, U: np.ndarray) -> np.ndarray:
        """The sectors at which one solution is proved within the limits over each joint box.

        Parameters
        ----------
        U : numpy.ndarray
            ``(N, k', 2)`` boxes of the section's joints (Krawczyk boxes).

        Returns
        -------
        numpy.ndarray
            ``(N,)`` ``uint64``, bit ``i`` for sector ``i``.
        """
        N = len(U)
        out = np.zeros(N, dtype=np.uint64)
        if not N:
            return out
        if self._X is None or self._Y is None or self._spin is None:         # no condition: every sector
            return np.full(N, np.uint64((1 << self.count) - 1), dtype=np.uint64)
        Q = [(U[:, j, 0], U[:, j, 1]) for j in range(U.shape[1])]
        with np.errstate(all="ignore"):
            x = self._X(Q)
            x = tuple(np.broadcast_to(v, (N,)) for v in x)
            if self._roll is None:
                plus_roll = minus_roll = np.ones(N, dtype=bool)
            else:
                roll = np.broadcast_to(self._roll(Q)[0], (N,)) >= 0
                plus_roll, minus_roll = (x[1] <= 0) | roll, (x[0] >= 0) | roll
            linear = None if self._linear is None else batch_enclosures(self._linear, U, U.shape[1], 4)
            for i in range(self.count):
                if linear is None:
                    T = [(np.full(N, self.edges[i]), np.full(N, self.edges[i + 1]))] + Q
                    y = tuple(np.broadcast_to(v, (N,)) for v in self._Y(T))
                    spin = np.broadcast_to(self._spin(T)[0], (N,)) >= 0
                else:
                    y, spin = self._linear_sector(linear, i)
                plus, minus = plus_roll & ((y[1] <= 0) | spin), minus_roll & ((y[0] >= 0) | spin)
                ok = plus if self.root > 0 else minus if self.root < 0 else plus | minus
                out[ok] |= np.uint64(1 << i)
        return out

    def _linear_sector(self, linear: np.ndarray, i: int):
        """``(y, spin)`` over sector ``i`` from the enclosures ``(N, 4, 2)`` of ``A, B, C, V^2``: ``Y = A cos(t) + B
        sin(t) + C`` enclosed as the intersection of its natural form and its mean-value form about the sector's
        middle ``m`` (``Y(m) + (B cos(t) - A sin(t)) (t - m)``), and whether ``cos(h_n)^2 V^2 - Y^2 >= 0`` is proved
        (every bound outward-rounded)."""
        A, B, C, V2 = ((linear[:, j, 0], linear[:, j, 1]) for j in range(4))
        cos_s, sin_s, cos_m, sin_m, offset = (tuple(np.full(len(linear), v[i]) for v in pair) for pair in self._trig)
        natural = arith.add(arith.add(arith.mul(A, cos_s), arith.mul(B, sin_s)), C)
        slope = arith.sub(arith.mul(B, cos_s), arith.mul(A, sin_s))
        middle = arith.add(arith.add(arith.mul(A, cos_m), arith.mul(B, sin_m)), C)
        mean = arith.add(middle, arith.mul(slope, offset))
        y = (np.maximum(natural[0], mean[0]), np.minimum(natural[1], mean[1]))
        spin = arith.sub(arith.mul(V2, self._cos2), arith.sqr(y))[0] >= 0
        return y, spin

    def bins_covered(self, masks: np.ndarray, chunk: int = 20_000) -> np.ndarray:
        """How many of the ``bins`` equal arcs of the circle the sectors passing at the directions cover
        (:meth:`covered_bins`, summed).

        Parameters
        ----------
        masks : numpy.ndarray
            ``(directions, N)`` ``uint64`` masks (:meth:`masks`; 0 where a direction is not proved).
        chunk : int
            Pieces per step (memory).

        Returns
        -------
        numpy.ndarray
            ``(N,)`` counts.
        """
        N = masks.shape[1]
        out = np.zeros(N, dtype=np.int64)
        for start in range(0, N, chunk):
            out[start:start + chunk] = self.covered_bins(masks[:, start:start + chunk]).sum(axis=1)
        return out

    def covered_bins(self, masks: np.ndarray) -> np.ndarray:
        """Which bins ``[b, b + 1] 2 pi / bins`` of polar angle the sectors passing at the directions cover: a bin
        is covered by a direction when it lies in the direction's arc and every sector that may meet it passes
        (margins outward), so every polar angle of a covered bin lies in a passing sector.

        Parameters
        ----------
        masks : numpy.ndarray
            ``(directions, N)`` ``uint64`` masks (:meth:`masks`; 0 where a direction is not proved).

        Returns
        -------
        numpy.ndarray
            ``(N, bins)`` booleans.
        """
        bins = np.zeros((masks.shape[1], self.bins), dtype=bool)
        for k in range(self.directions):
            rows = np.nonzero(masks[k])[0]          # the pieces proved at this direction
            if len(rows):
                need = self._need[k][None, :]
                bins[rows] |= ((masks[k][rows, None] & need) == need) & self._inside[k][None, :]
        return bins


def constrained_turn(limited: LimitedTurn, sides, spin=None, prune: bool = False, *,
                     arcs: bool = False, slack=None) -> LimitedTurn:
    """``limited`` whose direction proofs also prove ``s_i >= bound_i`` for each of ``sides`` (:class:`SideMap`);
    its outer proofs are unchanged (the distances from the shoulder and the elbow, the blocks: outside the section
    is outside any part of it), unless ``prune``.

    Parameters
    ----------
    limited : LimitedTurn
        The structure.
    sides : sequence of tuple
        ``(expression, bound)`` pairs, the expressions in the section's joints (see :class:`SideMap`).
    spin : SpinCondition, optional
        A constant orientation's condition on the wrist's solutions
        (:class:`~workspace_sym.serial.pose.SpinCondition`): the proofs then hold at the sectors of the first
        joint's range where it is proved (:class:`SpinSectors`).
    prune : bool
        As for :class:`SideMap`.
    arcs : bool
        Without ``spin``: keep where each piece's proofs hold (the arcs of the four directions, a
        :class:`SpinSectors` without a condition and with one sector), so that several maps' proofs can be read
        together (:func:`roots_volume`).
    slack : sequence of float, optional
        As for :class:`SideMap`.

    Returns
    -------
    LimitedTurn
        The same structure with the constrained section map.
    """
    section = limited.plan.section
    lateral = SideMap(section.lateral, sides, prune, slack)
    if spin is not None:        # 4 M directions: the turned copies prove those off the axes
        lateral.spin = SpinSectors(spin, section.lateral.variables, limited.inner_range,
                                   directions=DIRECTIONS * SPIN_TURNS)
        lateral.turned = [SideMap(turned_map(section.lateral, sp.pi * j / (2 * SPIN_TURNS)), sides)
                          for j in range(1, SPIN_TURNS)]
    elif arcs:
        lateral.spin = SpinSectors(None, section.lateral.variables, limited.inner_range, count=1)
    radial = RadialMap(section.square, lateral, section.reach)
    return replace(limited, plan=replace(limited.plan, section=radial))


def tool_section(sections, length, cone, sign: int, *, offsets: int = 8):
    """The ``(rho, z)`` section of the tool points ``p = w + L a`` of a wrist centre ``w`` and an approach ``a``
    within ``cone`` of ``d = (0, 0, sign)``, from full-turn classes of the wrist centre's section: ``sections``
    holds ``(grid, classes, tilt)`` triples, all on one grid, whose inner cells are wrist centres reached at every
    polar angle from which the wrist reaches every approach tilted by at most ``tilt`` from ``d``
    (``tilt <= cone``), and whose outer cells hold no wrist centre at all.  On a grid of the same width:

    * **outer**: every ``w = p - L a`` of the cell lies in outer cells or beyond the grid (``rho_w`` within
      ``|L| sin(cone)`` of ``rho_p``, ``|L|`` for a cone of a quarter turn or more, ``z_w = z_p - L a_z`` with
      ``sign a_z`` in ``[cos(cone), 1]``);
    * **inner**: for one triple and one of ``2 offsets + 1`` approaches ``a = s e_rho + sign sqrt(1 - s^2) e_z``
      in the plane of ``p`` and the axis (``|s| < sin(tilt)``; ``s = 0`` for a tilt of 0), every ``w = p - L a``
      of the cell lies in its inner cells at ``rho_w >= 0``: ``w`` is then a wrist centre at ``p``'s polar angle
      from which the wrist points the tool along ``a`` exactly, and the tool point is ``p``.

    Every bound is rounded outward (the exact ``L``, ``sin``, ``cos`` and ``sqrt`` enclosed).

    Parameters
    ----------
    sections : sequence of tuple
        ``(grid, classes, tilt)``: the wrist centre's section grid ``(rho, z)`` (the same for all), its full-turn
        verdict codes (:func:`full_turn_cells`) and the tilt (exact, radians).
    length : sympy.Expr
        ``L``, exact.
    cone : sympy.Expr
        The cone's half-angle, exact (radians, in ``(0, pi]``).
    sign : int
        ``d``'s vertical sign, 1 or -1.
    offsets : int
        Approaches tried on each side of ``d`` for the inner cells (default 8; the in-plane approaches tilt at
        most a quarter turn).

    Returns
    -------
    tool_grid : CellGrid
        The tool points' section grid.
    tool_classes : numpy.ndarray
        Their verdict codes.
    """
    grid, classes, _ = sections[0]
    L = numpy_constant(length)
    sin_c, cos_c = numpy_constant(sp.sin(cone)), numpy_constant(sp.cos(cone))
    # |L| sin(cone) sideways, rounded up; a cone of a quarter turn or more holds horizontal approaches: |L|
    wide_cone = bool(sp.sympify(cone) >= sp.pi / 2)
    reach = arith.mul(arith.iabs(L), (1.0, 1.0) if wide_cone else sin_c)[1]
    along = arith.mul(L, (cos_c[0], 1.0) if sign > 0 else (-1.0, -cos_c[0]))     # L a_z
    box = grid.box
    tool_box = np.array([[0.0, float(arith.up(box[0, 1] + reach))],
                         [float(arith.down(box[1, 0] + along[0])), float(arith.up(box[1, 1] + along[1]))]])
    tool = CellGrid(tool_box, grid.width)
    e0, e1 = tool.edges
    rows, cols = np.meshgrid(np.arange(tool.shape[0]), np.arange(tool.shape[1]), indexing="ij")
    i, j = rows.ravel(), cols.ravel()
    r = (e0[i], e0[i + 1])
    z = (e1[j], e1[j + 1])
    outside = grid.prefix(classes, OUTER)
    # outer: rho_w in [rho_p - reach, rho_p + reach] (clipped at 0), z_w = z_p - L a_z
    wide = arith.add(r, (-reach, reach))
    rect = np.stack([np.stack([np.maximum(wide[0], 0.0), wide[1]], axis=1),
                     np.stack(arith.sub(z, along), axis=1)], axis=1)
    outer = grid.all_in_class(outside, rect, outside_counts=True)
    inner = np.zeros(len(i), dtype=bool)
    for level, level_classes, tilt in sections:
        inside = level.prefix(level_classes, INNER)
        sin_t = float(numpy_constant(sp.sin(tilt))[0])
        for s in np.unique(np.linspace(-sin_t, sin_t, 2 * offsets + 1) * (1 - 1e-9)):
            k = arith.sqrt(arith.sub((1.0, 1.0), arith.sqr((s, s))))
            if not k[0] > cos_c[1] and s != 0:
                continue                               # a not strictly inside the cone: not used
            shift = arith.mul(L, (s, s))
            vertical = arith.mul(L, k if sign > 0 else (-k[1], -k[0]))
            rho_w = arith.sub(r, shift)
            rect = np.stack([np.stack(rho_w, axis=1), np.stack(arith.sub(z, vertical), axis=1)], axis=1)
            inner |= (rho_w[0] >= 0) & level.all_in_class(inside, rect, outside_counts=False)
    codes = np.full(len(i), UNDECIDED, dtype=np.int8)
    codes[outer] = OUTER
    codes[inner & ~outer] = INNER
    return tool, codes.reshape(tool.shape)


def shifted_section(length, sign: int) -> tuple[float, float]:
    """For an exact approach ``d = (0, 0, sign)``: the enclosure ``[s0, s1]`` of the tool point's height over
    the wrist centre's, ``L sign`` (``p = w + L d``), and the tool section is the wrist centre's translated by it
    (no new grid: a tool cell ``[z0, z1]`` is the wrist cell ``[z0 - s, z1 - s]``, which a grid of its own would
    straddle by the float rounding of the shift).  Its Pappus volume is the wrist centre's (a vertical
    translation); :class:`ToolSectionTest` with ``shift`` reads a world box on the wrist centre's grid.

    Parameters
    ----------
    length : sympy.Expr
        ``L``, exact.
    sign : int
        ``d``'s vertical sign, 1 or -1.

    Returns
    -------
    tuple of float
        ``(s0, s1)``, rounded outward.
    """
    L = numpy_constant(length)
    return (float(L[0]), float(L[1])) if sign > 0 else (float(-L[1]), float(-L[0]))


class ToolSectionTest(TurnedTest):
    """Classify world boxes of ``(x, y, z)`` from the tool's section cells (:func:`tool_section`), each proved at
    every polar angle (inner) or outside: a box is inner when its ``(rho, z)`` rectangle lies in inner cells, outer
    when in outer cells or beyond the grid.  With ``shift`` (:func:`shifted_section`), the cells are the wrist
    centre's and a box's heights are first lowered by the shift (outward).

    Parameters
    ----------
    plan : Turned
        The wrist centre's structure (for its base, the identity here).
    grid : CellGrid
        The tool's section grid (with ``shift``, the wrist centre's).
    classes : numpy.ndarray
        Its verdict codes.
    shift : tuple of float, optional
        The enclosure of the tool's height over the wrist centre's (None: the grid is the tool's own).
    """

    def __init__(self, plan, grid, classes, shift: tuple[float, float] | None = None):
        super().__init__(plan, grid, classes)
        self.shift = shift

    def rectangles(self, X: np.ndarray) -> np.ndarray:
        """``(N, 2, 2)`` rectangles of ``(rho, z)`` on the test's grid holding the points of the world boxes
        ``X`` (their heights lowered by ``shift`` when set), outward-rounded.

        Parameters
        ----------
        X : numpy.ndarray
            ``(N, 3, 2)`` world boxes.

        Returns
        -------
        numpy.ndarray
            ``(N, 2, 2)`` rectangles.
        """
        rect = super().rectangles(X)
        if self.shift is not None:
            rect[:, 1] = np.stack(arith.sub((rect[:, 1, 0], rect[:, 1, 1]), self.shift), axis=1)
        return rect

    def __call__(self, X: np.ndarray):
        rect = self.rectangles(X)
        finite = np.isfinite(rect).all(axis=(1, 2))
        inner = finite & self.grid.all_in_class(self.inside, rect, outside_counts=False)
        outer = finite & self.grid.all_in_class(self.outside, rect, outside_counts=True)
        return inner, outer & ~inner
