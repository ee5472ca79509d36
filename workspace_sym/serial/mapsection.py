"""Reach-map pairs proved reachable from the section of an arm turned by its first joint.

For an arm whose first joint turns everything after it (``p = B Rz(theta_1) w(q')``, ``w = (u, c, v)``,
:func:`~workspace_sym.serial.section.turned`), the approach axis turns with it, ``a = R Rz(theta_1) a'(q')``
(``R`` the rotation of ``B``); in the first joint's frame (world boxes enter it as outward boxes, directions
as ``R^T d``), at a point of cylindrical coordinates ``(rho, psi, z)`` reached by ``q'`` (``u^2 + c^2 =
rho^2``, ``v = z``) with ``theta_1 = psi - beta``, ``beta = atan2(c, u)``,

    ``a . d = b(q') . e(psi)``,  ``b = ((u a'_x + c a'_y) / rho, (u a'_y - c a'_x) / rho, a'_z)``,
    ``e(psi) = Rz(-psi) d``:

the approach seen in the frame that turns with the point.  So one certified solution of the section
``(rho^2, z)`` over a small cell ``s`` (Krawczyk, :meth:`~workspace_sym.interval.image.ImageMap.prove_inside_boxes`),
with the enclosure of ``b`` over its box, serves every map cell whose ``(rho, z)`` meets ``s``, for every map
direction whose ``e(psi)`` it is near.  The section cells are solved for ``L`` local directions (Newton aims
``b`` at each), the map cells tested by comparisons of those enclosures (docs/methods.md section 9 gives the
argument and its margins).  Nothing here proves a pair unreachable.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..interval import arith
from ..interval.compiler import compile_expr
from ..kinematics import DHRobot, numeric_function
from .model import reach_model
from .pose import constraint_from, joints_of, wrist_reduction
from .section import SquareMap, first_frame, first_joint_turn, to_first_frame, turned

__all__ = ["SectionProver", "section_prover", "section_reachable"]

BRANCHES = 8           # seeds per section cell when Newton cannot aim (fewer than four section joints)
NEAREST = 6            # local directions tried per map direction and piece: the nearest to it
MARGIN = 1e-9          # added to every float comparison of the cell test (far above its rounding, about 1e-15)


@dataclass(frozen=True, eq=False)
class SectionProver:
    """What the section method needs of one robot and one cone (module docstring).

    Parameters
    ----------
    square : SquareMap
        ``q' -> (u^2 + c^2, v)`` over the joints ``q'`` that move the section or the approach.
    quantities : list
        Interval evaluators of ``u``, ``c``, ``u a'_x + c a'_y``, ``u a'_y - c a'_x``, ``a'_z`` over ``q'``.
    b_float, b_jacobian : callable
        Floats of ``b`` and of its Jacobian at ``(N, k)`` configurations, ``(N, 3, 1)`` and ``(N, 3, k)``
        (:func:`~workspace_sym.kinematics.numeric_function`; Newton's aim, no proof).
    cone : float
        The half-angle proved, radians (the roll axis's cone after a roll-pitch wrist's reduction).
    theta_range : tuple or None
        Floats within ``theta_1``'s range; None when the first joint turns fully.
    axis : str
        What ``a'`` is: ``"approach"`` or the roll axis of the wrist.
    inverse : tuple or None
        ``B^-1`` (:attr:`~workspace_sym.serial.section.Turned.inverse`): world boxes to the first joint's frame,
        where ``u, c, v`` and ``a'`` are written; None when ``B`` is the identity.
    rotation : numpy.ndarray
        Floats of ``R^T`` (``3 x 3``): world directions to that frame.
    """

    square: SquareMap
    quantities: list
    b_float: Callable[[np.ndarray], np.ndarray]
    b_jacobian: Callable[[np.ndarray], np.ndarray]
    cone: float
    theta_range: tuple | None
    axis: str
    inverse: tuple | None = None
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))

    @property
    def aims(self) -> bool:
        """Whether the section joints leave two degrees of freedom for Newton to aim ``b`` (``k >= 4``).

        Returns
        -------
        bool
            True for four section joints or more.
        """
        return self.square.k >= 4


def section_prover(robot: DHRobot, values: tuple, cone_degrees: float) -> SectionProver | str:
    """The section prover of ``robot`` for cones of ``cone_degrees``, or why the method does not apply.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    values : tuple
        Its parameter values as ``(name, value)`` pairs.
    cone_degrees : float
        The cones' half-angle.

    Returns
    -------
    SectionProver or str
        The prover, or the reason (no turned structure, a joint turning ``q_1``'s axis).
    """
    params = dict(values) or None
    model = reach_model(robot, values)
    turn = turned(model)
    if turn is None:
        return "its first joint does not turn the rest of the arm about a fixed axis"
    q1, theta, slope = first_joint_turn(model)
    at_zero = {q1: -theta.subs(q1, 0) / slope}
    u, c, v = turn.section.lateral.expressions
    T = robot.substitute(robot.fk(), params)
    wrist = wrist_reduction(robot, params, constraint_from(approach=(1.0, 0.0, 0.0), cone=cone_degrees), T)
    if isinstance(wrist, str):
        axis, cone, what = list(T[:3, 2]), math.radians(cone_degrees), "approach"
    else:
        axis, reduced, _ = wrist
        cone, what = float(reduced.cone), "roll axis of the wrist"
    R = first_frame(robot, params)[:3, :3]
    a = [sp.sympify(e).subs(at_zero) for e in R.T * sp.Matrix(axis)]       # a' in the first joint's frame
    variables, limits, periodic = joints_of(robot, [u, c, v] + a, params)
    if q1 in variables:
        return "its approach axis depends on the first joint other than by the turn"
    rho2 = u ** 2 + c ** 2
    square = SquareMap(rho2, [u, c, v], variables, limits, periodic)
    bx, by, bz = u * a[0] + c * a[1], u * a[1] - c * a[0], a[2]
    quantities = [compile_expr(e, variables) for e in (u, c, bx, by, bz)]
    b = sp.Matrix([bx / sp.sqrt(rho2), by / sp.sqrt(rho2), bz])
    # common subexpressions shared (numeric_function): the Panda's Jacobian of b in 0.03 s a chunk, not 1.8 s
    b_float = numeric_function(b, variables)
    b_jacobian = numeric_function(b.jacobian(variables), variables)
    theta_range = None
    if not model.periodic[0]:
        lo, hi = (robot.substitute(e, params) for e in robot.joints[0].limits)
        ends = sorted(float(sp.N(slope * x + theta.subs(q1, 0), 30)) for x in (lo, hi))
        theta_range = (float(np.nextafter(np.nextafter(ends[0], np.inf), np.inf)),
                       float(np.nextafter(np.nextafter(ends[1], -np.inf), -np.inf)))
    rotation = np.eye(3) if turn.inverse is None else np.array([[0.5 * (lo + hi) for lo, hi in row]
                                                                 for row in turn.inverse[0]])
    return SectionProver(square, quantities, b_float, b_jacobian, cone, theta_range, what, turn.inverse, rotation)


def _columns(f, q: np.ndarray) -> np.ndarray:
    """``(N, r)`` floats of a column function (:func:`~workspace_sym.kinematics.numeric_function`) at ``q``."""
    return f(q)[:, :, 0]


def _aimed_newton(prover: SectionProver, targets, ell, q, steps: int = 10):
    """Least-squares Newton steps towards ``(t, v) = targets`` with ``b`` along ``ell`` (when the prover aims);
    the mask of the converged rows (floats: a hint where a proof is tried, not a proof)."""
    square = prover.square
    lo, hi = square.inner_limits[:, 0], square.inner_limits[:, 1]
    if prover.aims:
        e1 = np.cross(ell, np.where(np.abs(ell[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]]))
        e1 /= np.linalg.norm(e1, axis=1)[:, None]
        e2 = np.cross(ell, e1)
    with np.errstate(all="ignore"):
        for _ in range(steps):
            f = square.position_float(q) - targets
            J = square.jacobian_float(q)
            if prover.aims:
                b, Jb = _columns(prover.b_float, q), prover.b_jacobian(q)
                f = np.concatenate([f, np.einsum("ni,ni->n", b, e1)[:, None], np.einsum("ni,ni->n", b, e2)[:, None]],
                                   axis=1)
                J = np.concatenate([J, np.einsum("ni,nik->nk", e1, Jb)[:, None], np.einsum("ni,nik->nk", e2, Jb)[:, None]],  # noqa: E501
                                   axis=1)
            JJ = np.einsum("nik,njk->nij", J, J) + 1e-12 * np.eye(J.shape[1])
            q = q - np.einsum("nik,ni->nk", J, np.linalg.solve(JJ, f[:, :, None])[:, :, 0])
            q = np.where(square.periodic, lo + np.remainder(q - lo, hi - lo), np.clip(q, lo, hi))
        residual = np.abs(square.position_float(q) - targets).max(axis=1)
        converged = np.isfinite(q).all(axis=1) & (residual < 1e-9 * (1 + np.abs(targets).max(axis=1)))
        if prover.aims:
            converged &= np.einsum("ni,ni->n", _columns(prover.b_float, q), ell) > 0.99
    return q, converged


class _SectionCells:
    """The section grid ``[i h, (i + 1) h] x [z_0 + j h, z_0 + (j + 1) h]`` of ``(rho, z)`` and, per cell and
    local direction, the enclosures a proof left (``nan`` where none)."""

    def __init__(self, prover: SectionProver, h: float, z0: float, needed: np.ndarray, local: np.ndarray):
        self.prover, self.h, self.z0 = prover, h, z0
        self.index = np.argwhere(needed)                     # (S, 2) section cells to solve
        self.lookup = np.full(needed.shape, -1, dtype=np.int64)
        self.lookup[self.index[:, 0], self.index[:, 1]] = np.arange(len(self.index))
        self.local = local
        S, L = len(self.index), len(local)
        self.b_mid = np.full((S, L, 3), np.nan)
        self.b_half = np.full((S, L, 3), np.inf)
        self.uc_mid = np.full((S, L, 2), np.nan)
        self.uc_half = np.full((S, L, 2), np.inf)
        self.solution = np.full((S, L, prover.square.k), np.nan)
        self.converged = np.zeros((S, L), dtype=bool)
        self.tries = np.zeros((S, L), dtype=np.int8)

    def bounds(self, s):
        """The rectangles of section cells ``s``: ``(rho0, rho1, z0, z1)``, neighbours sharing their edges."""
        i, j = self.index[s, 0], self.index[s, 1]
        return i * self.h, (i + 1) * self.h, self.z0 + j * self.h, self.z0 + (j + 1) * self.h

    def solve(self, s, l, seeds):
        """Newton aimed at the local directions ``l`` from ``seeds``, then the Krawczyk test of the cells ``s``;
        the enclosures of the proofs are kept.  Returns the rows that converged."""
        prover, square = self.prover, self.prover.square
        r0, r1, z0, z1 = self.bounds(s)
        T = np.stack([np.stack([arith.down(r0 * r0), arith.up(r1 * r1)], 1), np.stack([z0, z1], 1)], 1)
        q, converged = _aimed_newton(prover, 0.5 * (T[:, :, 0] + T[:, :, 1]), self.local[l], seeds.copy())
        rows = np.nonzero(converged)[0]
        proved, U = square.prove_inside_boxes(T[rows], q[rows], inflations=2)
        rows, U = rows[proved], U[proved]
        new = ~np.isfinite(self.b_mid[s[rows], l[rows], 0])
        rows, U = rows[new], U[new]
        if len(rows):
            X = [(U[:, j, 0], U[:, j, 1]) for j in range(square.k)]
            with np.errstate(all="ignore"):
                u, c, bx, by, bz = ([np.broadcast_to(x, (len(rows),)) for x in f(X)] for f in prover.quantities)
            inverse = (arith.down(1.0 / r1[rows]), arith.up(1.0 / r0[rows]))     # 1 / rho over the cell
            parts = [arith.mul(bx, inverse), arith.mul(by, inverse), bz, arith.mul(u, inverse), arith.mul(c, inverse)]
            mid = np.stack([0.5 * (p[0] + p[1]) for p in parts], 1)
            half = np.stack([arith.up(np.maximum(arith.up(p[1] - mid[:, i]), arith.up(mid[:, i] - p[0])))
                             for i, p in enumerate(parts)], 1)
            good = np.isfinite(mid).all(axis=1) & np.isfinite(half).all(axis=1)
            rows, mid, half = rows[good], mid[good], half[good]
            self.b_mid[s[rows], l[rows]], self.b_half[s[rows], l[rows]] = mid[:, :3], half[:, :3]
            self.uc_mid[s[rows], l[rows]], self.uc_half[s[rows], l[rows]] = mid[:, 3:], half[:, 3:]
        ok = np.nonzero(converged)[0]
        self.solution[s[ok], l[ok]] = q[ok]
        self.converged[s[ok], l[ok]] = True
        return ok


def _cell_geometry(X: np.ndarray, Y: np.ndarray):
    """Per ``xy`` rectangle (not holding the axis): ``rho`` range (outward), polar centre, half-spread ``gamma``
    (an upper bound of the angle from the centre to any point's polar angle)."""
    def away(A):
        return np.where((A[:, 0] <= 0) & (A[:, 1] >= 0), 0.0, np.minimum(np.abs(A[:, 0]), np.abs(A[:, 1])))

    # hypot within an ulp, the factor for its relative error; two floats more each way for subnormal radii,
    # where the factor rounds back to the same float
    rmin = np.nextafter(np.nextafter(np.hypot(away(X), away(Y)) * (1 - 1e-12), 0.0), 0.0)
    rmax = np.nextafter(np.nextafter(np.hypot(np.abs(X).max(axis=1), np.abs(Y).max(axis=1)) * (1 + 1e-12), np.inf),
                        np.inf)
    xc, yc = X.mean(axis=1), Y.mean(axis=1)
    psi = np.arctan2(yc, xc)
    cx = np.stack([X[:, 0], X[:, 1], X[:, 0], X[:, 1]], 1)
    cy = np.stack([Y[:, 0], Y[:, 0], Y[:, 1], Y[:, 1]], 1)
    # the polar angle along a segment that misses the origin is monotone: its extremes are at the corners
    rel = np.arctan2(cx * yc[:, None] - cy * xc[:, None], cx * xc[:, None] + cy * yc[:, None])
    return rmin, rmax, psi, np.abs(rel).max(axis=1) + MARGIN


def section_reachable(prover: SectionProver, edges: tuple, candidates: np.ndarray, directions: np.ndarray, *,  # noqa: C901
                      cell: float, local: np.ndarray, samples: int = 400_000, split: int = 2, seed: int = 0,
                      deadline: float | None = None) -> np.ndarray:
    """The pairs (map cell, direction) proved reachable by the section method (module docstring).

    Parameters
    ----------
    prover : SectionProver
        The robot's prover.
    edges : tuple of numpy.ndarray
        The map's cell edges.
    candidates : numpy.ndarray
        ``bool`` of the grid's shape: the cells to try.
    directions : numpy.ndarray
        ``(K, 3)`` unit vectors.
    cell : float
        The section cells' side.
    local : numpy.ndarray
        ``(L, 3)`` unit vectors: the local directions Newton aims at in each section cell.
    samples : int
        Random configurations whose section points seed Newton.
    split : int
        Each map cell is tested as ``split x split`` pieces in ``xy`` (a smaller polar spread each).
    seed : int
        The random draws' seed.
    deadline : float, optional
        ``time.perf_counter()`` value after which no more section cells are solved.

    Returns
    -------
    numpy.ndarray
        ``bool`` of shape ``(*grid, K)``.
    """
    shape = tuple(len(e) - 1 for e in edges)
    out = np.zeros((*shape, len(directions)), dtype=bool)
    idx = np.argwhere(candidates)
    if not len(idx):
        return out
    X, Y, Z = (np.stack([edges[a][idx[:, a]], edges[a][idx[:, a] + 1]], 1) for a in range(3))
    # the pieces: split points computed once, so that neighbouring pieces share their edge (one float)
    xe = [X[:, 0]] + [X[:, 0] + (X[:, 1] - X[:, 0]) * (i / split) for i in range(1, split)] + [X[:, 1]]
    ye = [Y[:, 0]] + [Y[:, 0] + (Y[:, 1] - Y[:, 0]) * (j / split) for j in range(1, split)] + [Y[:, 1]]
    # each piece in the frame of the first joint (an outward box: B^-1 of the world piece), its polar geometry
    # there and its z range
    pieces = []
    for i, j in itertools.product(range(split), repeat=2):
        F = to_first_frame(prover.inverse, np.stack([np.stack([xe[i], xe[i + 1]], 1),
                                                     np.stack([ye[j], ye[j + 1]], 1), Z], 1))
        pieces.append((*_cell_geometry(F[:, 0], F[:, 1]), F[:, 2]))
    h = float(cell)
    z0 = float(min(piece[4][:, 0].min() for piece in pieces))
    z1 = float(max(piece[4][:, 1].max() for piece in pieces))
    n_rho = math.ceil(float(max(piece[1].max() for piece in pieces)) / h) + 2
    n_z = math.ceil((z1 - z0) / h) + 2
    rho_edges = np.arange(n_rho + 1) * h
    z_edges = z0 + np.arange(n_z + 1) * h

    def span(lo, hi, e):        # section cells [e_i, e_{i+1}] covering [lo, hi], read on the edges themselves
        i0 = np.clip(np.searchsorted(e, lo, side="right") - 1, 0, len(e) - 2)
        i1 = np.clip(np.searchsorted(e, hi, side="left") - 1, 0, len(e) - 2)
        ok = (e[i0] <= lo) & (e[i1 + 1] >= hi)
        return i0, i1, ok

    spans = []
    needed = np.zeros((n_rho, n_z), dtype=bool)
    for rmin, rmax, _psi, gamma, zs in pieces:
        i0, i1, rok = span(rmin, rmax, rho_edges)
        j0, j1, zok = span(zs[:, 0], zs[:, 1], z_edges)
        usable = rok & zok & np.isfinite(gamma) & (rmin > 1e-3 * h) & (gamma < prover.cone)
        spans.append((i0, i1, j0, j1, usable))
        for piece in np.nonzero(usable)[0]:
            needed[i0[piece]:i1[piece] + 1, j0[piece]:j1[piece] + 1] = True
    ells = np.asarray(local, dtype=float) if prover.aims else np.zeros((BRANCHES, 3))
    grid = _SectionCells(prover, h, z0, needed, ells)
    S, L = len(grid.index), len(ells)
    # seeds: random configurations binned by their section point
    rng = np.random.default_rng(seed)
    square = prover.square
    q = square.random_configurations(samples, rng)
    w = square.lateral.position_float(q)
    bi = np.floor(np.hypot(w[:, 0], w[:, 1]) / h).astype(np.int64)
    bj = np.floor((w[:, 2] - z0) / h).astype(np.int64)
    inside = (bi >= 0) & (bi < n_rho) & (bj >= 0) & (bj < n_z)
    owner = np.where(inside, grid.lookup[np.clip(bi, 0, n_rho - 1), np.clip(bj, 0, n_z - 1)], -1)
    keep = owner >= 0
    q, owner = q[keep], owner[keep]
    order = np.argsort(owner, kind="stable")
    q, owner = q[order], owner[order]
    b = _columns(prover.b_float, q)
    if not prover.aims:     # b and (cos beta, sin beta) = (u, c) / rho, a unit vector of R^5
        w = square.lateral.position_float(q)
        feature = np.concatenate([b, w[:, :2] / np.hypot(w[:, 0], w[:, 1])[:, None]], axis=1) / math.sqrt(2)
    firsts = np.searchsorted(owner, np.arange(S), side="left")
    lasts = np.searchsorted(owner, np.arange(S), side="right")
    seeds = np.full((S, L, square.k), np.nan)
    for s in np.nonzero(lasts > firsts)[0]:
        rows = np.arange(firsts[s], lasts[s])
        if prover.aims:
            seeds[s] = q[rows[np.argmax(b[rows] @ ells.T, axis=0)]]
        else:           # the samples farthest apart in (b, beta), one after the other: the solutions' branches
            pick = [rows[0]]
            closest = feature[rows] @ feature[rows[0]]
            for _ in range(min(L, len(rows)) - 1):
                far = int(np.argmin(closest))
                if closest[far] > 0.999:
                    break
                pick.append(rows[far])
                closest = np.maximum(closest, feature[rows] @ feature[rows[far]])
            seeds[s, :len(pick)] = q[pick]
    s_all, l_all = np.nonzero(np.isfinite(seeds[:, :, 0]))
    todo = (s_all, l_all, seeds[s_all, l_all])
    neighbours = np.argsort(-(ells @ ells.T), axis=1)[:, 1:7] if prover.aims else None
    chunk = 50_000
    while len(todo[0]):
        s_t, l_t, q_t = todo
        grid.tries[s_t, l_t] += 1
        reached = []
        for start in range(0, len(s_t), chunk):
            if deadline is not None and time.perf_counter() > deadline:
                break
            part = slice(start, start + chunk)
            reached.append(start + grid.solve(s_t[part], l_t[part], q_t[part]))
        if not reached:
            break
        src = np.concatenate(reached)
        # continuation: a solution seeds the same local direction in the four neighbouring section cells, and the
        # nearest local directions in its own cell, where no solution is known yet (at most three tries each)
        sol = grid.solution[s_t[src], l_t[src]]
        ns: list[np.ndarray] = []
        nl: list[np.ndarray] = []
        nq: list[np.ndarray] = []
        for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            ii, jj = grid.index[s_t[src], 0] + di, grid.index[s_t[src], 1] + dj
            valid = (ii >= 0) & (ii < n_rho) & (jj >= 0) & (jj < n_z)
            target = np.where(valid, grid.lookup[np.clip(ii, 0, n_rho - 1), np.clip(jj, 0, n_z - 1)], -1)
            ns.append(target)
            nl.append(l_t[src])
            nq.append(sol)
        if neighbours is not None:
            for k in range(neighbours.shape[1]):
                ns.append(s_t[src])
                nl.append(neighbours[l_t[src], k])
                nq.append(sol)
        cs, cl, cq = np.concatenate(ns), np.concatenate(nl), np.concatenate(nq)
        fresh = cs >= 0
        fresh[fresh] = ~grid.converged[cs[fresh], cl[fresh]] & (grid.tries[cs[fresh], cl[fresh]] < 3)
        cs, cl, cq = cs[fresh], cl[fresh], cq[fresh]
        _, first = np.unique(cs * L + cl, return_index=True)
        todo = (cs[first], cl[first], cq[first])
    # the map cells: every piece, every section cell it meets, some proof serving the direction (of the local
    # directions nearest e = Rz(-psi) d, the others being too far to pass: choosing fewer only proves less)
    D = np.asarray(directions, dtype=float) @ prover.rotation.T        # the directions in the first joint's frame
    tried = min(NEAREST, L)
    limited = prover.theta_range
    if limited is not None:
        lo, hi = limited
        centre, cos_h = 0.5 * (lo + hi) + math.pi, math.cos(math.pi - 0.5 * (hi - lo))
    # a filter, not a proof: the cells where every section cell met by every piece holds some proof at all
    # (block sums of a prefix table of the solved section cells)
    solved = np.zeros((n_rho + 1, n_z + 1), dtype=np.int64)
    np.add.at(solved, (grid.index[:, 0] + 1, grid.index[:, 1] + 1), np.isfinite(grid.b_mid[:, :, 0]).any(axis=1))
    solved = solved.cumsum(axis=0).cumsum(axis=1)
    worth = np.ones(len(idx), dtype=bool)
    for i0, i1, j0, j1, usable in spans:
        count = solved[i1 + 1, j1 + 1] - solved[i0, j1 + 1] - solved[i1 + 1, j0] + solved[i0, j0]
        worth &= usable & (count == (i1 - i0 + 1) * (j1 - j0 + 1))
    for n in np.nonzero(worth)[0]:
        good = np.ones(len(D), dtype=bool)
        for (_rmin, _rmax, psi, gamma, _zs), (i0, i1, j0, j1, usable) in zip(pieces, spans):
            if not usable[n]:
                good[:] = False
                break
            ss = grid.lookup[i0[n]:i1[n] + 1, j0[n]:j1[n] + 1].ravel()
            c, s_ = math.cos(psi[n]), math.sin(psi[n])
            E = np.stack([c * D[:, 0] + s_ * D[:, 1], -s_ * D[:, 0] + c * D[:, 1], D[:, 2]], 1)    # Rz(-psi) d, (K, 3)
            near = np.argsort(-(E @ ells.T), axis=1)[:, :tried] if prover.aims else np.tile(np.arange(L), (len(D), 1))
            mid, half = grid.b_mid[ss][:, near], grid.b_half[ss][:, near]                        # (S, K, n, 3)
            with np.errstate(invalid="ignore"):
                value = np.einsum("sknc,kc->skn", mid, E) - np.einsum("sknc,kc->skn", half, np.abs(E))
            passes = np.where(np.isnan(value), False, value >= math.cos(prover.cone - gamma[n]) + MARGIN)
            if limited is not None:
                phi = psi[n] - centre
                f = np.array([math.cos(phi), math.sin(phi)])
                with np.errstate(invalid="ignore"):
                    top = grid.uc_mid[ss] @ f + grid.uc_half[ss] @ np.abs(f) + gamma[n]           # (S, L)
                passes &= np.where(np.isnan(top), False, top <= cos_h - MARGIN)[:, near]
            good &= passes.any(axis=2).all(axis=0)
            if not good.any():
                break
        out[tuple(idx[n])] = good
    return out
