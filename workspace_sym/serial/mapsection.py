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
argument and its margins).

Pairs proved unreachable for one direction come from the wrist point ``w = p - L a`` (:func:`wrist_offset`: the
foot of the common normal of the last two axes, where they meet for the UR5 and a spherical wrist): a
configuration with its tool point in a cell and its approach in a cone has ``w`` in the cell moved by ``-L``
times the cone's cap, so a cell and cone whose moved boxes meet none of the boxes of ``w``'s own position paving
that may hold its points (inner, boundary, pending) are reached by none (:func:`wrist_unreachable`).
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

__all__ = ["SectionProver", "section_prover", "section_reachable", "wrist_offset", "wrist_robot", "cap_patches",
           "wrist_unreachable"]

BRANCHES = 8           # seeds per section cell when Newton cannot aim (fewer than four section joints)
NEAREST = 6            # local directions tried per map direction and piece: the nearest to it
SWINGS = (math.pi, 0.5 * math.pi, -0.5 * math.pi)   # beta's swings tried for a second proof, in turn
FEW = 32               # a failing direction's aims are tried again where it fails at this many section cells or fewer
MARGIN = 1e-9          # added to every float comparison of the cell test (far above its rounding, about 1e-15)
SOLVES_SHARE = 0.75    # the continuation's share of a section's time limit (the second proofs and retries: the rest)
SOLVED = 1e-13         # Newton's rows stop within this (relative) of their targets: floats, where a proof is tried


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


def local_directions(prover: SectionProver, directions: np.ndarray, count: int) -> np.ndarray:
    """About ``count`` local directions for Newton to aim at, on the circles where the map's directions are seen.

    A map direction ``d`` is seen from the frame that turns with the point as ``e(psi) = Rz(-psi) R^T d``: as
    ``psi`` runs, on the circle of the sphere at ``d``'s height in the first joint's frame.  So the local
    directions lie on those circles (the poles once), evenly in angle, as many on each as its length asks
    (at least three), about ``count`` in all: every ``e`` is then within half a step of one (the 26 cube
    directions, 96 asked: 95 local directions, every ``e`` within 7.95 degrees), where as many spread over the
    whole sphere leave 16 degrees.  Only Newton's aim: the proofs hold for any choice.

    Parameters
    ----------
    prover : SectionProver
        The robot's prover (its ``rotation`` into the first joint's frame).
    directions : numpy.ndarray
        ``(K, 3)`` unit vectors of the map.
    count : int
        About how many local directions.

    Returns
    -------
    numpy.ndarray
        ``(L, 3)`` unit vectors.
    """
    heights = np.clip((np.asarray(directions, dtype=float) @ prover.rotation.T)[:, 2], -1.0, 1.0)
    heights = np.unique(np.round(heights, 9))
    poles = np.abs(heights) > 1 - 1e-9
    radii = np.sqrt(1 - heights[~poles] ** 2)
    share = (count - int(poles.sum())) * radii / max(radii.sum(), 1e-300)
    out = [np.array([[0.0, 0.0, math.copysign(1.0, z)]]) for z in heights[poles]]
    for z, r, n in zip(heights[~poles], radii, np.maximum(3, np.round(share)).astype(int)):
        angle = 2 * math.pi * np.arange(n) / n
        out.append(np.stack([r * np.cos(angle), r * np.sin(angle), np.full(n, z)], 1))
    return np.concatenate(out)


def _columns(f, q: np.ndarray) -> np.ndarray:
    """``(N, r)`` floats of a column function (:func:`~workspace_sym.kinematics.numeric_function`) at ``q``."""
    return f(q)[:, :, 0]


def _aimed_newton(prover: SectionProver, targets, ell, q, steps: int = 10):
    """Least-squares Newton steps towards ``(t, v) = targets`` with ``b`` along ``ell`` (when the prover aims);
    the mask of the converged rows (floats: a hint where a proof is tried, not a proof).

    ``b . e_1 = b . e_2 = 0`` holds at ``b = -ell`` as well as at ``ell``, and an aim may not be met at all: the
    rows left without ``b . ell > 0.99`` take damped least-squares steps towards ``b = ell``
    (:func:`_nearest_aim`), then Newton's again; where that still misses, four steps on the position alone from
    the nearest ``b`` found (their proof is kept too: its ``b`` serves the directions it is near)."""
    square = prover.square
    seeds, q = q, _aim_steps(prover, targets, ell, q, steps)
    with np.errstate(all="ignore"):
        tolerance = 1e-9 * (1 + np.abs(targets).max(axis=1))
        residual = np.abs(square.position_float(q) - targets).max(axis=1)
        if prover.aims:
            along = np.einsum("ni,ni->n", _columns(prover.b_float, q), ell)
            off = np.nonzero(~(residual < tolerance) | ~(along > 0.99))[0]
            if len(off):
                # from the seeds (b = -ell, where Newton may have gone, is a critical point of |b - ell|^2)
                near = _nearest_aim(prover, targets[off], ell[off], seeds[off])
                q[off] = _aim_steps(prover, targets[off], ell[off], near, steps // 2)
                residual[off] = np.abs(square.position_float(q[off]) - targets[off]).max(axis=1)
                along = np.einsum("ni,ni->n", _columns(prover.b_float, q[off]), ell[off])
                missed = ~(residual[off] < tolerance[off]) | ~(along > 0.99)
                # the aim not met (or met at -ell): the position alone from the nearest b to ell
                still = off[missed]
                if len(still):
                    q[still], _ = square.newton(targets[still], near[missed], steps=4)
                    residual[still] = np.abs(square.position_float(q[still]) - targets[still]).max(axis=1)
        converged = np.isfinite(q).all(axis=1) & (residual < tolerance)
        aimed = converged.copy()
        if prover.aims:
            aimed &= np.einsum("ni,ni->n", _columns(prover.b_float, q), ell) > 0.99
    return q, converged, aimed


def _aim_steps(prover: SectionProver, targets, ell, q, steps: int):
    """Newton's least-norm steps on the position and, when the prover aims, ``b . e_1 = b . e_2 = 0`` (``e_1,
    e_2`` normal to ``ell``).  A row leaves the iteration once its residuals are within ``SOLVED`` of its
    targets (one more step would move it by about the rounding): most rows start from a neighbouring square's
    solution and need two or three of the steps."""
    square = prover.square
    lo, hi = square.inner_limits[:, 0], square.inner_limits[:, 1]
    q = np.array(q, dtype=float)
    if prover.aims:
        e1 = np.cross(ell, np.where(np.abs(ell[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]]))
        e1 /= np.linalg.norm(e1, axis=1)[:, None]
        e2 = np.cross(ell, e1)
    solved = SOLVED * (1 + np.abs(targets).max(axis=1))
    active = np.arange(len(q))
    with np.errstate(all="ignore"):
        for _ in range(steps):
            qa = q[active]
            f = square.position_float(qa) - targets[active]
            if prover.aims:
                b = _columns(prover.b_float, qa)
                f = np.concatenate([f, np.einsum("ni,ni->n", b, e1[active])[:, None],
                                    np.einsum("ni,ni->n", b, e2[active])[:, None]], axis=1)
            going = ~(np.abs(f).max(axis=1) <= solved[active])
            active, qa, f = active[going], qa[going], f[going]
            if not len(active):
                break
            J = square.jacobian_float(qa)
            if prover.aims:
                Jb = prover.b_jacobian(qa)
                J = np.concatenate([J, np.einsum("ni,nik->nk", e1[active], Jb)[:, None],
                                    np.einsum("ni,nik->nk", e2[active], Jb)[:, None]], axis=1)
            step = _least_norm_step(J, f, 1e-12)
            # a joint held at its limit that the step would push beyond it is left out of the step (its column
            # dropped), so that the others move instead of the iteration stalling at the limit
            held = ~square.periodic & (((qa <= lo) & (step > 0)) | ((qa >= hi) & (step < 0)))
            if held.any():
                step = np.where(held.any(axis=1)[:, None],
                                _least_norm_step(np.where(held[:, None, :], 0.0, J), f, 1e-12), step)
            qa = qa - step
            q[active] = np.where(square.periodic, lo + np.remainder(qa - lo, hi - lo), np.clip(qa, lo, hi))
    return q


def _nearest_aim(prover: SectionProver, targets, ell, q, steps: int = 8, weight: float = 0.1, damping: float = 1e-3):
    """Damped least-squares steps (Levenberg-Marquardt) on the position and ``weight (b - ell)``: where the aim
    cannot be met, a configuration whose ``b`` is near the nearest it can be to ``ell`` (floats, a seed)."""
    square = prover.square
    lo, hi = square.inner_limits[:, 0], square.inner_limits[:, 1]
    with np.errstate(all="ignore"):
        for _ in range(steps):
            b, Jb = _columns(prover.b_float, q), prover.b_jacobian(q)
            f = np.concatenate([square.position_float(q) - targets, weight * (b - ell)], axis=1)
            J = np.concatenate([square.jacobian_float(q), weight * Jb], axis=1)
            # (J^T J + damping I)^-1 J^T f = J^T (J J^T + damping I)^-1 f: the least-norm step with the damping
            step = _least_norm_step(J, f, damping)
            q = np.where(np.isfinite(step), q - step, q)             # rows without a step are left as they are
            q = np.where(square.periodic, lo + np.remainder(q - lo, hi - lo), np.clip(q, lo, hi))
    return q


def _least_norm_step(J: np.ndarray, f: np.ndarray, damping: float) -> np.ndarray:
    """``J^T (J J^T + damping I)^-1 f`` per row (``J``: ``(N, m, k)``, ``f``: ``(N, m)``), Newton's least-norm step.

    A batch holding an exactly singular matrix (a joint column dropped from a square system, with entries whose
    rounding swallows the damping: the KR16's section) is solved by the pseudo-inverse instead of raising."""
    JJ = np.einsum("nik,njk->nij", J, J) + damping * np.eye(J.shape[1])
    try:
        y = np.linalg.solve(JJ, f[:, :, None])[:, :, 0]
    except np.linalg.LinAlgError:
        bad = ~(np.isfinite(JJ).all(axis=(1, 2)) & np.isfinite(f).all(axis=1))     # NaN rows stay NaN, as solve's
        JJ[bad] = np.eye(J.shape[1])
        y = np.einsum("nij,nj->ni", np.linalg.pinv(JJ), np.where(bad[:, None], 0.0, f))
        y[bad] = np.nan
    return np.einsum("nik,ni->nk", J, y)


def _steered_newton(prover: SectionProver, targets, ell, beta, q, steps: int = 12, largest: float = 0.4):
    """Least-squares Newton steps towards ``(t, v) = targets``, ``b`` along ``ell`` and the polar angle of
    ``(u, c)`` at ``beta`` (its residual wrapped into ``(-pi, pi]``, each step at most ``largest`` radians):
    the self-motion of a redundant section swung to another ``beta``.  Floats, no proof (a seed)."""
    square = prover.square
    lo, hi = square.inner_limits[:, 0], square.inner_limits[:, 1]
    e1 = np.cross(ell, np.where(np.abs(ell[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]]))
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = np.cross(ell, e1)
    with np.errstate(all="ignore"):
        for _ in range(steps):
            w, Jw = square.lateral.position_float(q), square.lateral.jacobian_float(q)
            b, Jb = _columns(prover.b_float, q), prover.b_jacobian(q)
            r2 = w[:, 0] ** 2 + w[:, 1] ** 2
            turn = np.angle(np.exp(1j * (np.arctan2(w[:, 1], w[:, 0]) - beta)))
            d_beta = (w[:, 0, None] * Jw[:, 1] - w[:, 1, None] * Jw[:, 0]) / r2[:, None]
            f = np.concatenate([square.position_float(q) - targets, np.einsum("ni,ni->n", b, e1)[:, None],
                                np.einsum("ni,ni->n", b, e2)[:, None], turn[:, None]], axis=1)
            J = np.concatenate([square.jacobian_float(q), np.einsum("ni,nik->nk", e1, Jb)[:, None],
                                np.einsum("ni,nik->nk", e2, Jb)[:, None], d_beta[:, None]], axis=1)
            step = _least_norm_step(J, f, 1e-9)
            size = np.abs(step).max(axis=1, keepdims=True)
            q = q - step * np.minimum(1.0, largest / np.maximum(size, 1e-300))
            q = np.where(square.periodic, lo + np.remainder(q - lo, hi - lo), np.clip(q, lo, hi))
    return q


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
        # columns l and, for a limited first joint, L + l: the proof aimed at local direction l, and a second one
        # whose beta lies far from the first's (_SectionCells.second)
        width = 2 * L if prover.theta_range is not None and prover.aims else L
        self.b_mid = np.full((S, width, 3), np.nan)
        self.b_half = np.full((S, width, 3), np.inf)
        self.uc_mid = np.full((S, width, 2), np.nan)
        self.uc_half = np.full((S, width, 2), np.inf)
        self.solution = np.full((S, L, prover.square.k), np.nan)
        self.converged = np.zeros((S, L), dtype=bool)
        self.aimed = np.zeros((S, L), dtype=bool)        # the kept proof's b was aimed at the local direction
        self.tries = np.zeros((S, L), dtype=np.int8)
        self.swung = np.zeros((S, L), dtype=bool)        # a second proof was tried (_SectionCells.second)

    def bounds(self, s):
        """The rectangles of section cells ``s``: ``(rho0, rho1, z0, z1)``, neighbours sharing their edges."""
        i, j = self.index[s, 0], self.index[s, 1]
        return i * self.h, (i + 1) * self.h, self.z0 + j * self.h, self.z0 + (j + 1) * self.h

    def tasks(self, s):
        """The task boxes ``[down(rho_0^2), up(rho_1^2)] x [z_0, z_1]`` of section cells ``s``: ``(N, 2, 2)``."""
        r0, r1, z0, z1 = self.bounds(s)
        return np.stack([np.stack([arith.down(r0 * r0), arith.up(r1 * r1)], 1), np.stack([z0, z1], 1)], 1)

    def solve(self, s, l, seeds, aim=None):
        """Newton aimed at the local directions ``l`` from ``seeds``, then the Krawczyk test of the cells ``s``;
        the enclosures of the proofs are kept.  Returns the rows that converged.

        With ``aim`` (``(N, 3)``), Newton aims there instead and each proof replaces the one kept in column
        ``l`` (a retry for the directions near ``aim``: :func:`_retry_aims`); returns the rows proved."""
        prover = self.prover
        T = self.tasks(s)
        ell = self.local[l] if aim is None else aim
        q, converged, aimed = _aimed_newton(prover, 0.5 * (T[:, :, 0] + T[:, :, 1]), ell, seeds.copy())
        if aim is not None:
            return self._prove(s, l, T, q, np.nonzero(converged)[0])
        # a proof kept: the first, replaced once by one whose b was aimed (either serves the directions it is near);
        # only those are tried
        rows = np.nonzero(converged & ~self.aimed[s, l] & (aimed | ~np.isfinite(self.b_mid[s, l, 0])))[0]
        rows = self._prove(s, l, T, q, rows)
        self.aimed[s[rows], l[rows]] |= aimed[rows]
        ok = np.nonzero(aimed)[0]
        self.solution[s[ok], l[ok]] = q[ok]
        self.converged[s[ok], l[ok]] = True
        return ok

    def second(self, s, l):
        """For a limited first joint (``theta_1 = psi - beta`` must lie in its range): a second proof of the pairs
        ``(s, l)`` holding an aimed one, Newton steered to ``beta`` half a turn from the first proof's (then a
        quarter either way, ``SWINGS``, for the pairs still without), kept in column ``L + l`` where its
        ``beta`` lies more than the forbidden arc's width (plus 0.2) from the first's, so that no polar angle
        ``psi`` forbids both.  Returns the rows kept."""
        prover, square, L = self.prover, self.prover.square, len(self.local)
        lo, hi = prover.theta_range
        self.swung[s, l] = True
        T = self.tasks(s)
        targets = 0.5 * (T[:, :, 0] + T[:, :, 1])
        first = np.arctan2(self.uc_mid[s, l, 1], self.uc_mid[s, l, 0])
        stored = []
        todo = np.arange(len(s))
        for swing in SWINGS:
            q = _steered_newton(prover, targets[todo], self.local[l[todo]], first[todo] + swing,
                                self.solution[s[todo], l[todo]].copy())
            q, _converged, aimed = _aimed_newton(prover, targets[todo], self.local[l[todo]], q)
            with np.errstate(all="ignore"):
                w = square.lateral.position_float(q)
            apart = np.abs(np.angle(np.exp(1j * (np.arctan2(w[:, 1], w[:, 0]) - first[todo]))))
            rows = np.nonzero(aimed & (apart > 2 * math.pi - (hi - lo) + 0.2))[0]
            kept = self._prove(s[todo], l[todo] + L, T[todo], q, rows)
            stored.append(todo[kept])
            todo = np.setdiff1d(todo, todo[kept])
            if not len(todo):
                break
        return np.concatenate(stored)

    def _prove(self, s, col, T, q, rows):
        """The Krawczyk test of ``rows`` (of the cells ``s`` at ``q``); where it succeeds, the enclosures of ``b``
        and ``(u, c) / rho`` over the proof's box go to column ``col``.  Returns the rows stored."""
        prover, square = self.prover, self.prover.square
        r0, r1 = self.bounds(s)[:2]
        proved, U = square.prove_inside_boxes(T[rows], q[rows], inflations=2)
        rows, U = rows[proved], U[proved]
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
            self.b_mid[s[rows], col[rows]], self.b_half[s[rows], col[rows]] = mid[:, :3], half[:, :3]
            self.uc_mid[s[rows], col[rows]], self.uc_half[s[rows], col[rows]] = mid[:, 3:], half[:, 3:]
        return rows


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


def _turning(D: np.ndarray) -> np.ndarray:
    """Per direction ``d`` (rows of ``D``), an upper bound of the angle ``e(psi) = Rz(-psi) d`` turns through per
    radian of ``psi``: ``sin`` of ``d``'s angle from the axis, rounded up (``e(psi)`` runs on the circle of the
    unit sphere at ``d``'s height, of radius ``r``; the angle between two of its points ``t`` apart in ``psi`` is
    ``2 asin(r sin(t / 2)) <= r t``).  0 for the axis, 1 for a direction normal to it."""
    return np.minimum(np.hypot(D[:, 0], D[:, 1]) / np.linalg.norm(D, axis=1) * (1 + 1e-12), 1.0)


def section_reachable(prover: SectionProver, edges: tuple, candidates: np.ndarray, directions: np.ndarray, *,  # noqa: C901
                      cell: float, local: np.ndarray, samples: int = 1_000_000, split: int = 2, retries: int = 0,
                      seed: int = 0, deadline: float | None = None) -> np.ndarray:
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
        ``(L, 3)`` unit vectors: the local directions Newton aims at in each section cell (:func:`local_directions`).
    samples : int
        Random configurations whose section points seed Newton.
    split : int
        Each map cell is tested as ``split x split`` pieces in ``xy`` (a smaller polar spread each).
    retries : int
        Random starts per aim tried again: where a direction of a cell fails at ``FEW`` section cells or fewer,
        Newton aims at its ``e(psi)`` there from ``retries`` random configurations, the proofs replace those of
        the nearest local direction, and the cells that failed are tested again (0: no second try).
    seed : int
        The random draws' seed.
    deadline : float, optional
        ``time.perf_counter()`` value after which no more section cells are solved.  The first solves (the
        continuation) stop at ``SOLVES_SHARE`` of the time left, so that the second proofs and the retries,
        which come after the first cell test, keep the rest.

    Returns
    -------
    numpy.ndarray
        ``bool`` of shape ``(*grid, K)``.
    """
    solves_by = None if deadline is None else time.perf_counter() + SOLVES_SHARE * (deadline - time.perf_counter())
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

    D = np.asarray(directions, dtype=float) @ prover.rotation.T        # the directions in the first joint's frame
    turning = _turning(D)
    spans = []
    needed = np.zeros((n_rho, n_z), dtype=bool)
    for rmin, rmax, _psi, gamma, zs in pieces:
        i0, i1, rok = span(rmin, rmax, rho_edges)
        j0, j1, zok = span(zs[:, 0], zs[:, 1], z_edges)
        usable = rok & zok & np.isfinite(gamma) & (rmin > 1e-3 * h) & (gamma * turning.min() + MARGIN < prover.cone)
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
            if solves_by is not None and time.perf_counter() > solves_by:
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
    # a filter, not a proof: the cells where every section cell met by every piece holds some proof at all
    # (block sums of a prefix table of the solved section cells)
    solved = np.zeros((n_rho + 1, n_z + 1), dtype=np.int64)
    np.add.at(solved, (grid.index[:, 0] + 1, grid.index[:, 1] + 1), np.isfinite(grid.b_mid[:, :, 0]).any(axis=1))
    solved = solved.cumsum(axis=0).cumsum(axis=1)
    worth = np.ones(len(idx), dtype=bool)
    for i0, i1, j0, j1, usable in spans:
        count = solved[i1 + 1, j1 + 1] - solved[i0, j1 + 1] - solved[i1 + 1, j0] + solved[i0, j0]
        worth &= usable & (count == (i1 - i0 + 1) * (j1 - j0 + 1))
    cells = np.nonzero(worth)[0]
    test = _CellTest(grid, pieces, spans, D, turning)
    limited = grid.b_mid.shape[1] > L
    seconds: list = []
    good = test(cells, seconds=seconds if limited else None)
    if seconds and (deadline is None or time.perf_counter() < deadline):
        # a limited first joint: second proofs, beta swung half a turn, where a first proof serves a failing
        # direction but for the first joint's range; then the failing directions tested again
        s_t, l_t = seconds[0]
        for start in range(0, len(s_t), chunk):
            if deadline is not None and time.perf_counter() > deadline:
                break
            grid.second(s_t[start:start + chunk], l_t[start:start + chunk])
        failing = ~good.all(axis=1)
        good[failing] |= test(cells[failing], ~good[failing])
    if prover.aims and retries and (deadline is None or time.perf_counter() < deadline):
        # a direction failing at few section cells (FEW), where its local directions' proofs serve it not:
        # Newton aimed at its E itself there, from random starts, then the failing directions tested again
        failing = ~good.all(axis=1)
        wanted = test.wanted(cells[failing], good[failing])
        if len(wanted[0]):
            _retry_aims(grid, wanted, retries, rng, chunk, deadline)
            # a proof replaced by a retried one was a proof all the same: what the first test proved stays
            good[failing] |= test(cells[failing], ~good[failing])
    for n, row in zip(cells, good):
        out[tuple(idx[n])] = row
    return out


class _CellTest:
    """The test of map cells against the section's proofs: every piece, every section cell it meets, some proof
    serving the direction (of the local directions nearest ``e = Rz(-psi) d``, the others being too far to pass:
    choosing fewer only proves less).  Each pass reads only the directions it is given (a cell's failing ones
    when it is tested again) and leaves a cell at its first piece that proves none of them."""

    def __init__(self, grid: _SectionCells, pieces: list, spans: list, D: np.ndarray, turning: np.ndarray):
        self.grid, self.pieces, self.spans, self.D, self.turning = grid, pieces, spans, D, turning
        prover = grid.prover
        self.tried = min(NEAREST, len(grid.local)) if prover.aims else len(grid.local)
        self.limited = prover.theta_range
        if self.limited is not None:
            lo, hi = self.limited
            self.centre, self.cos_h = 0.5 * (lo + hi) + math.pi, math.cos(math.pi - 0.5 * (hi - lo))

    def _pieces(self, n: int, ks: np.ndarray):
        """Per usable piece of cell ``n``, for the directions ``ks``: its section cells, the local directions
        nearest each ``E``, the mask ``(S, len(ks))`` of the section cells and directions some of their proofs
        serve, ``E`` itself, and the mask ``(S, len(ks), columns)`` of the proofs whose ``b`` serves ``E`` but
        whose ``beta`` the first joint's range refuses; None for a piece that is not usable."""
        grid, D, L = self.grid, self.D[ks], len(self.grid.local)
        prover = grid.prover
        turning = self.turning[ks]
        for (_rmin, _rmax, psi, gamma, _zs), (i0, i1, j0, j1, usable) in zip(self.pieces, self.spans):
            if not usable[n]:
                yield None
                return
            ss = grid.lookup[i0[n]:i1[n] + 1, j0[n]:j1[n] + 1].ravel()
            c, s_ = math.cos(psi[n]), math.sin(psi[n])
            E = np.stack([c * D[:, 0] + s_ * D[:, 1], -s_ * D[:, 0] + c * D[:, 1], D[:, 2]], 1)    # Rz(-psi) d, (K, 3)
            if prover.aims:
                near = np.argsort(-(E @ grid.local.T), axis=1)[:, :self.tried]
            else:
                near = np.tile(np.arange(L), (len(D), 1))
            columns = np.concatenate([near, near + L], axis=1) if grid.b_mid.shape[1] > L else near
            mid, half = grid.b_mid[ss][:, columns], grid.b_half[ss][:, columns]                  # (S, K, n, 3)
            # angle(b, E) <= c - spread and angle(E, e(psi)) <= spread at every psi of the piece
            spread = gamma[n] * turning + MARGIN
            least = np.where(spread < prover.cone, np.cos(np.minimum(prover.cone - spread, math.pi)) + MARGIN, np.inf)
            with np.errstate(invalid="ignore"):
                value = np.einsum("sknc,kc->skn", mid, E) - np.einsum("sknc,kc->skn", half, np.abs(E))
            aimed = np.where(np.isnan(value), False, value >= least[None, :, None])
            passes = aimed
            if self.limited is not None:
                phi = psi[n] - self.centre
                f = np.array([math.cos(phi), math.sin(phi)])
                with np.errstate(invalid="ignore"):
                    top = grid.uc_mid[ss] @ f + grid.uc_half[ss] @ np.abs(f) + gamma[n]           # (S, 2 L)
                passes = aimed & np.where(np.isnan(top), False, top <= self.cos_h - MARGIN)[:, columns]
            yield ss, near, passes.any(axis=2), E, aimed & ~passes

    def __call__(self, cells: np.ndarray, todo: np.ndarray | None = None, seconds: list | None = None) -> np.ndarray:
        """``(len(cells), K)``: the directions proved reachable over every point of each cell, of those ``todo``
        (``(len(cells), K)``, default all).  With ``seconds`` (a limited first joint), the section cells and local
        directions whose first proof serves a direction left unproved but for the first joint's range, and that
        hold no second proof tried yet, are appended to it as ``(s, l)`` arrays."""
        grid, K = self.grid, len(self.D)
        out = np.zeros((len(cells), K), dtype=bool)
        for row, n in enumerate(cells):
            ks = np.arange(K) if todo is None else np.nonzero(todo[row])[0]
            if not len(ks):
                continue
            good = np.ones(len(ks), dtype=bool)
            # the directions a second proof may still prove: at every section cell where no proof serves them, a
            # first proof refused by the first joint's range alone
            mended = np.full(len(ks), seconds is not None)
            asked = []
            for piece in self._pieces(n, ks):
                if piece is None:
                    good[:] = mended[:] = False
                    break
                ss, near, served, _E, refused = piece
                if mended.any():
                    first = refused[:, :, :near.shape[1]] & ~served[:, :, None]
                    mended &= (served | first.any(axis=2)).all(axis=0)
                    s_i, k_i, j_i = np.nonzero(first)
                    asked.append((ss[s_i], near[k_i, j_i], k_i))
                good &= served.all(axis=0)
                if not (good | mended).any():
                    break
            out[row, ks] = good
            if seconds is not None:
                for s_i, l_i, k_i in asked:
                    keep = ~good[k_i]
                    seconds.append((s_i[keep], l_i[keep]))
        if seconds:
            ss, ls = (np.concatenate(v) for v in zip(*seconds))
            keep = grid.aimed[ss, ls] & ~grid.swung[ss, ls]
            _, first_at = np.unique(ss[keep] * len(grid.local) + ls[keep], return_index=True)
            seconds[:] = [(ss[keep][first_at], ls[keep][first_at])]
        return out

    def wanted(self, cells: np.ndarray, good: np.ndarray):
        """Where a direction of ``cells`` not proved (``good`` False) finds no proof serving it at ``FEW`` section
        cells of its pieces or fewer: those section cells, the local direction nearest ``E`` and ``E`` itself, once
        per (section cell, local direction): ``(W,)``, ``(W,)`` and ``(W, 3)``.  (A direction failing at many is
        most often out of reach there: not worth the solves.)"""
        ss_all, l_all, e_all = [], [], []
        for n, row in zip(cells, good):
            ks = np.nonzero(~row)[0]
            if not len(ks):
                continue
            found = []
            for piece in self._pieces(n, ks):
                if piece is None:
                    break
                ss, near, served, E, _ = piece
                s_i, k_i = np.nonzero(~served)
                found.append((ss[s_i], near[k_i, 0], E[k_i], k_i))
            if not found:
                continue
            k_all = np.concatenate([f[3] for f in found])
            few = np.bincount(k_all, minlength=len(ks)) <= FEW
            for ss_i, l_i, E_i, k_i in found:
                keep = few[k_i]
                ss_all.append(ss_i[keep])
                l_all.append(l_i[keep])
                e_all.append(E_i[keep])
        if not ss_all:
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros((0, 3))
        ss, ls, es = np.concatenate(ss_all), np.concatenate(l_all), np.concatenate(e_all)
        _, first = np.unique(ss * len(self.grid.local) + ls, return_index=True)
        return ss[first], ls[first], es[first]


def _retry_aims(grid: _SectionCells, wanted: tuple, starts: int, rng, chunk: int, deadline) -> None:
    """Newton aimed at ``E`` itself (not its nearest local direction) for the ``wanted`` section cells, from
    ``starts`` random configurations each; the start whose ``b`` comes nearest ``E`` seeds a proof that replaces
    the one kept for that local direction (:meth:`_SectionCells.solve`)."""
    prover, square = grid.prover, grid.prover.square
    s_all, l_all, e_all = wanted
    per = max(1, chunk // starts)
    for begin in range(0, len(s_all), per):
        if deadline is not None and time.perf_counter() > deadline:
            return
        s, l, E = s_all[begin:begin + per], l_all[begin:begin + per], e_all[begin:begin + per]
        T = grid.tasks(s)
        targets = 0.5 * (T[:, :, 0] + T[:, :, 1])                                 # the centres solve aims at
        rows = np.repeat(np.arange(len(s)), starts)
        starts_q = square.random_configurations(len(rows), rng)
        q, converged, _aimed = _aimed_newton(prover, targets[rows], E[rows], starts_q)
        with np.errstate(invalid="ignore"):
            along = np.where(converged, np.einsum("ni,ni->n", _columns(prover.b_float, q), E[rows]), -np.inf)
        best = np.full(len(s), -np.inf)
        np.maximum.at(best, rows, along)
        pick = np.nonzero(np.isfinite(along) & (along == best[rows]))[0]
        pair, first = np.unique(rows[pick], return_index=True)
        if len(pair):
            grid.solve(s[pair], l[pair], q[pick[first]], aim=E[pair])


# ------------------------------------------------------------------ unreachable pairs: the wrist point
def wrist_offset(robot: DHRobot, values: tuple, *, probes: int = 6) -> sp.Rational | None:
    """``L`` such that the point ``w = p - L a`` (``p`` the tool point, ``a`` the approach) is the foot of the
    common normal of the last joint's axis on the one before it, or None when the arm has no such point.

    Any ``L`` is sound for :func:`wrist_unreachable` (``w`` is then a point of the arm, and its workspace is
    paved over all the joints); this one makes ``w`` independent of the last joint and, where the last two axes
    meet (the UR5's ``o_5``, a spherical wrist's centre), of the one before it: its workspace is then the
    smallest.  Found from floats of the geometric Jacobian at ``probes`` random configurations (the last joint
    revolute about the approach through the tool point; the one before it revolute and not parallel), the same
    ``L`` at each within ``1e-9``; read as the rational of its decimal rounded to 10 digits.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    values : tuple
        Its parameter values as ``(name, value)`` pairs.
    probes : int
        Random configurations checked.

    Returns
    -------
    sympy.Rational or None
        ``L`` (lengths of the robot's unit), None when the structure is missing or ``L`` is 0 (``w`` would be
        the tool point itself, already paved).
    """
    if robot.n < 2 or any(j.kind != "R" for j in robot.joints[-2:]):
        return None
    params = dict(values) or None
    T = robot.substitute(robot.fk(), params)
    J = robot.substitute(robot.jacobian("geometric"), params)
    zero = [0, 0, 0]
    f = numeric_function(sp.Matrix([list(T[:3, 2]) + zero, list(T[:3, 3]) + zero, list(J[:, -2]), list(J[:, -1])]),
                         robot.q)
    q = np.random.default_rng(7).uniform(-math.pi, math.pi, size=(probes, robot.n))
    with np.errstate(all="ignore"):
        rows = f(q)                                 # (probes, 4, 6): a, p (first 3 of rows 0, 1), then J columns
    a, p = rows[:, 0, :3], rows[:, 1, :3]
    v_last, w_last = rows[:, 3, :3], rows[:, 3, 3:]
    v, omega = rows[:, 2, :3], rows[:, 2, 3:]
    if not (np.isfinite(rows[:, :, :3]).all() and np.isfinite(rows[:, 2:, 3:]).all()):
        return None
    # the last joint turns about the approach, through the tool point (it moves neither)
    if np.abs(v_last).max() > 1e-9 or np.abs(np.abs(np.einsum("ni,ni->n", w_last, a)) - 1).max() > 1e-9:
        return None
    r = p - (p + np.cross(omega, v))                 # p + omega x v: a point of the axis before it
    b = np.einsum("ni,ni->n", a, omega)
    if (1 - b * b).min() < 1e-6:
        return None
    s = (b * np.einsum("ni,ni->n", omega, r) - np.einsum("ni,ni->n", a, r)) / (1 - b * b)
    if np.ptp(s) > 1e-9 * (1 + np.abs(s).max()):
        return None
    offset = sp.nsimplify(round(-float(s.mean()), 10), rational=True)
    return None if offset == 0 else offset


def wrist_robot(robot: DHRobot, offset) -> DHRobot:
    """``robot`` with its tool point moved by ``-offset`` along the approach: the point ``w = p - offset a``.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    offset : sympy.Rational
        ``L`` (:func:`wrist_offset`).

    Returns
    -------
    DHRobot
        The same table, limits, base and parameters; the tool ``tool Trans(0, 0, -L)``.
    """
    shift = sp.eye(4)
    shift[2, 3] = -offset
    tool = shift if robot.tool is None else sp.Matrix(robot.tool) * shift
    return DHRobot(robot.joints, convention=robot.convention, name=f"{robot.name} (wrist point)",
                   parameters=robot.parameters, units=robot.units, base=robot.base, tool=tool)


def cap_patches(directions: np.ndarray, cone: float, bands: int = 3) -> np.ndarray:
    """Outward boxes ``(K, P, 3, 2)`` whose union holds the unit vectors within ``cone`` degrees of each
    direction: ``P = 1 + 6 + ... + 6 (bands - 1)`` patches of the cap.

    A unit vector within ``c`` of ``d`` is ``cos t d + sin t (cos f u + sin f v)`` with ``t`` in ``[0, c]`` and
    ``f`` in ``[0, 2 pi]`` (``u, v`` completing ``d`` to an orthonormal frame): band ``j`` of ``t``
    (``[j c / bands, (j + 1) c / bands]``) is cut into ``max(1, 6 j)`` arcs of ``f``, every interval widened by
    ``1e-12`` (the floats of ``c``, ``2 pi`` and the frame, errors of about ``1e-16``), and each patch's box is
    the outward interval evaluation of that formula, widened by ``1e-12`` too.

    Parameters
    ----------
    directions : numpy.ndarray
        ``(K, 3)`` nonzero vectors.
    cone : float
        The half-angle, degrees, in ``(0, 180]``.
    bands : int
        Bands of the polar angle.

    Returns
    -------
    numpy.ndarray
        ``(K, P, 3, 2)``.

    Examples
    --------
    >>> box = cap_patches(np.array([[0.0, 0.0, 1.0]]), 30.0, bands=1)[0, 0]
    >>> bool(np.allclose(box, [[-0.5, 0.5], [-0.5, 0.5], [np.cos(np.radians(30)), 1.0]]))
    True
    """
    d = np.asarray(directions, dtype=float)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    u = np.cross(d, np.where(np.abs(d[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]]))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    v = np.cross(d, u)
    c = math.radians(cone)
    t_lo, t_hi, f_lo, f_hi = [], [], [], []
    for j in range(bands):
        arcs = max(1, 6 * j)
        for i in range(arcs):
            t_lo.append(c * j / bands - 1e-12)
            t_hi.append(c * (j + 1) / bands + 1e-12)
            f_lo.append(2 * math.pi * i / arcs - 1e-12)
            f_hi.append(2 * math.pi * (i + 1) / arcs + 1e-12)
    t = (np.array(t_lo), np.array(t_hi))
    f = (np.array(f_lo), np.array(f_hi))
    ct, st, cf, sf = arith.cos(t), arith.sin(t), arith.cos(f), arith.sin(f)
    out = np.empty((len(d), len(t_lo), 3, 2))
    for a in range(3):
        for k in range(len(d)):
            side = arith.add(arith.mul(cf, (u[k, a], u[k, a])), arith.mul(sf, (v[k, a], v[k, a])))
            lo, hi = arith.add(arith.mul(ct, (d[k, a], d[k, a])), arith.mul(st, side))
            out[k, :, a, 0] = np.maximum(lo - 1e-12, -1.0)
            out[k, :, a, 1] = np.minimum(hi + 1e-12, 1.0)
    return out


def wrist_unreachable(edges: tuple, candidates: np.ndarray, directions: np.ndarray, cone: float, offset,
                      outside: np.ndarray, outside_edges: tuple, *, split: int = 2) -> np.ndarray:
    """The pairs (map cell, direction) proved unreachable by the wrist point (docs/methods.md section 9).

    A configuration putting the tool point ``p`` in the cell with its approach ``a`` in the cone puts its point
    ``w = p - L a`` in the box ``piece - L patch`` for some piece of the cell (``split^3`` pieces) and patch of
    the cap (:func:`cap_patches`), products and sums rounded outward.  No configuration puts ``w`` in a cell of
    ``outside`` (cells of the grid ``outside_edges`` proved out of ``w``'s workspace): a pair is proved
    unreachable when every such box lies in the union of those cells (the run of cells from the edge at or
    below its lower end to the edge at or above its upper end, at least one, found by comparisons and counted in
    a prefix table).

    Parameters
    ----------
    edges : tuple of numpy.ndarray
        The map's cell edges.
    candidates : numpy.ndarray
        ``bool`` of shape ``(*grid, K)``: the pairs to try.
    directions : numpy.ndarray
        ``(K, 3)`` the map's directions.
    cone : float
        The cones' half-angle, degrees.
    offset : sympy.Rational
        ``L``.
    outside : numpy.ndarray
        ``bool`` cells of the grid ``outside_edges`` proved free of ``w``.
    outside_edges : tuple of numpy.ndarray
        That grid's edges.
    split : int
        Pieces per axis of each map cell.

    Returns
    -------
    numpy.ndarray
        ``bool`` of the shape of ``candidates``.
    """
    out = np.zeros(candidates.shape, dtype=bool)
    caps = cap_patches(directions, cone)
    L = float(offset)
    L_iv = (np.array(float(np.nextafter(L, -np.inf))), np.array(float(np.nextafter(L, np.inf))))
    table = np.zeros(tuple(s + 1 for s in outside.shape), dtype=np.int64)
    table[1:, 1:, 1:] = outside.cumsum(0).cumsum(1).cumsum(2)

    def span(lo, hi, e):        # cells i0 .. i1 - 1 of one axis: e_i0 <= lo, hi <= e_i1, at least one; ok: in e
        i0 = np.searchsorted(e, lo, side="right") - 1
        i1 = np.maximum(np.searchsorted(e, hi, side="left"), i0 + 1)
        ok = (i0 >= 0) & (i1 <= len(e) - 1)
        return np.clip(i0, 0, len(e) - 1), np.clip(i1, 0, len(e) - 1), ok

    for k in range(candidates.shape[-1]):
        idx = np.argwhere(candidates[..., k])
        if not len(idx):
            continue
        minus = [arith.mul(L_iv, (caps[k, :, a, 0], caps[k, :, a, 1])) for a in range(3)]     # L a, (P,) each
        alive = np.arange(len(idx))
        for piece in itertools.product(range(split), repeat=3):
            bounds = []
            for a in range(3):
                lo, hi = edges[a][idx[alive, a]], edges[a][idx[alive, a] + 1]
                # the pieces share their split points (one float each), so their union is the cell
                p_lo = lo if piece[a] == 0 else lo + (hi - lo) * (piece[a] / split)
                p_hi = hi if piece[a] == split - 1 else lo + (hi - lo) * ((piece[a] + 1) / split)
                bounds.append((p_lo, p_hi))
            for patch in range(caps.shape[1]):
                if not len(alive):
                    break
                i0, i1, ok = [], [], np.ones(len(alive), dtype=bool)
                for a, (p_lo, p_hi) in enumerate(bounds):
                    # w = p - L a over the piece and the patch, rounded outward
                    w_lo = arith.down(p_lo - minus[a][1][patch])
                    w_hi = arith.up(p_hi - minus[a][0][patch])
                    j0, j1, inside = span(w_lo, w_hi, outside_edges[a])
                    i0.append(j0)
                    i1.append(j1)
                    ok &= inside
                count = (table[i1[0], i1[1], i1[2]] - table[i0[0], i1[1], i1[2]] - table[i1[0], i0[1], i1[2]]
                         - table[i1[0], i1[1], i0[2]] + table[i0[0], i0[1], i1[2]] + table[i0[0], i1[1], i0[2]]
                         + table[i1[0], i0[1], i0[2]] - table[i0[0], i0[1], i0[2]])
                keep = ok & (count == (i1[0] - i0[0]) * (i1[1] - i0[1]) * (i1[2] - i0[2]))
                alive = alive[keep]
                bounds = [(p_lo[keep], p_hi[keep]) for p_lo, p_hi in bounds]
        out[tuple(idx[alive].T) + (k,)] = True
    return out
