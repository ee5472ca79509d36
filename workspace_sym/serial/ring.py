"""The wrist's ring: where the tool point and its approach put the point of the arm before its last two joints.

``w2``, the point where the axis of the last joint but one meets the common normal of that axis and the one before
it, moves with the joints before those two only; its distance from a point ``S`` of the first joint's axis is
bounded over the joint limits (the shoulder distance of the arm cut before its last two rows,
:class:`~workspace_sym.serial.section.ShoulderReach`).  In any configuration ``p - w2 = L a + rho v`` with
constants ``L``, ``rho`` and ``v`` a unit vector normal to the approach ``a``: ``w2`` lies on a ring of radius
``rho`` about ``p - L a``.  So a tool point ``p`` with an approach ``a`` is reached only where that ring comes
within the bound of ``S``: an outer proof for every pair of a reach map (:func:`ring_unreachable`) and for every
cell of a pose section whose cone is about the first joint's axis (:func:`ring_outer_cells`), both in closed
form (docs/methods.md sections 8 and 9, "the wrist's ring").
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..interval import arith
from ..interval.graph import numpy_constant
from ..kinematics import DHRobot
from ..symbolic import simplified
from ..transforms import inverse_transform, rot_x, translation
from .model import reach_model
from .section import first_frame, turned

__all__ = ["WristRing", "wrist_ring", "ring_unreachable", "ring_outer_cells"]

MARGIN = 1e-9          # added to every angle computed in doubles (their errors are about 1e-15)


@dataclass(frozen=True)
class WristRing:
    """The ring on which a configuration's tool point and approach put a point of the arm's elbow side
    (docs/methods.md section 9, "the wrist's ring").

    ``w2`` is the point where the axis of the last joint but one meets the common normal of that axis and the
    one before it; it moves with the joints before those two only.  In any configuration ``p - w2 = L a + rho
    v``, ``v`` a unit vector perpendicular to the approach ``a``, with constants ``L`` and ``rho`` (checked
    exactly when the ring is built): ``w2`` lies on the circle of radius ``rho`` about ``p - L a`` in the plane
    normal to ``a``.  Its distance from the point ``S`` of the first joint's axis is at most ``sqrt(reach)``.

    Parameters
    ----------
    offset : tuple of float
        ``L``, enclosed (``(lo, hi)``).
    radius : tuple of float
        ``rho``, enclosed.
    centre : numpy.ndarray
        ``(3, 2)``: ``S`` in the world frame, enclosed.
    height : tuple of float
        ``S``'s coordinate along the first joint's axis in that joint's frame (:func:`~workspace_sym.serial.
        section.first_frame`), enclosed: the centre of a pose section's test.
    reach : float
        An upper bound of ``|w2 - S|^2`` over the joint limits.
    """

    offset: tuple
    radius: tuple
    centre: np.ndarray
    height: tuple
    reach: float

    def bound(self, r0_sq: np.ndarray, gap: np.ndarray) -> np.ndarray:
        """Lower bounds of ``g`` (the squared distance from ``S`` to the nearest point of the ring) over the
        points at ``|y| >= sqrt(r0_sq)`` whose angle from ``y = p - S`` to the approach is at least ``gap`` from
        ``theta_0 = atan2(rho, L)``: ``r_0^2 - 2 r_0 K cos(gap) + K^2``, rounded down, where ``r_0 >= K``
        (``g = |r e^(i theta) - K e^(i theta_0)|^2`` grows with ``r`` from ``K`` and with ``|theta -
        theta_0|``); NaN elsewhere.

        Parameters
        ----------
        r0_sq : numpy.ndarray
            Lower bounds of ``|y|^2`` (``(N, 1)`` or broadcasting with ``gap``).
        gap : numpy.ndarray
            Lower bounds of ``|theta - theta_0|``, radians, at most ``pi``.

        Returns
        -------
        numpy.ndarray
            The lower bounds of ``g`` (NaN where ``r_0 < K``).
        """
        L, rho = self.offset, self.radius
        K = arith.sqrt(arith.add(arith.sqr((np.array(L[0]), np.array(L[1]))),
                                 arith.sqr((np.array(rho[0]), np.array(rho[1])))))
        with np.errstate(all="ignore"):
            r0 = arith.sqrt((r0_sq, r0_sq))[0]
            two_r0K = arith.up(2 * arith.up(r0 * K[1]))
            g = arith.down(arith.down(r0_sq - arith.up(two_r0K * arith.up(np.cos(gap)))) + arith.down(K[0] * K[0]))
        return np.where(r0 >= K[1], g, np.nan)

    def gap(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Lower bounds of the distance from ``theta_0`` to the angles ``[lo, hi]`` (radians, doubles: each end
        and ``theta_0`` widened by :data:`MARGIN`).

        Parameters
        ----------
        lo, hi : numpy.ndarray
            The range of the angle from ``y`` to the approach.

        Returns
        -------
        numpy.ndarray
            ``max(lo - theta_0, theta_0 - hi, 0)`` rounded down, within ``[0, pi]``.
        """
        t_lo = math.atan2(self.radius[0], self.offset[1]) - 2 * MARGIN     # rho >= 0: theta_0 in [0, pi]
        t_hi = math.atan2(self.radius[1], self.offset[0]) + 2 * MARGIN
        with np.errstate(invalid="ignore"):
            gap = np.maximum(np.maximum(lo - MARGIN - t_hi, t_lo - hi - MARGIN), 0.0)
        return np.where(np.isfinite(gap), np.minimum(gap, math.pi), 0.0)


def wrist_ring(robot: DHRobot, values: tuple, *, tolerance: float = 1e-6) -> WristRing | None:
    """The arm's :class:`WristRing`, or None when it has none that helps.

    ``w2`` is the tool point of the arm cut before its last two rows (standard DH: the origin of frame
    ``n - 2``, on the axis of joint ``n - 1`` at the foot of its common normal with the axis before; modified
    DH: that frame moved by ``Rx(alpha) Tx(a)`` of row ``n - 1``).  ``L = (p - w2) . a`` and ``rho^2 = |p -
    w2|^2 - L^2`` are read in that frame, where they depend on the last two joints only, and must simplify to
    constants (else None).  ``S`` and the bound come from the cut arm's shoulder distance
    (:func:`~workspace_sym.serial.section.turned`: ``S`` on the axis of its first joint that moves the section;
    a point of it off the first joint's axis at ``|s_xy|`` is replaced by its foot on that axis, the bound
    growing by ``|s_xy|``).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    values : tuple
        Its parameter values as ``(name, value)`` pairs.
    tolerance : float
        How close to the maximum of ``|w2 - S|^2`` its bound is sought.

    Returns
    -------
    WristRing or None
        None when the last two joints are not revolute, the constants are not constant, ``L`` and ``rho`` are
        both 0 (the ring is the tool point: the position paving has it), or the cut arm is not turned by its
        first joint.
    """
    n = robot.n
    if n < 4 or any(j.kind != "R" for j in robot.joints[-2:]):
        return None
    params = dict(values) or None
    cut = robot.joints[:n - 2]
    if robot.convention == "modified":
        row = robot.joints[n - 2]
        step = rot_x(robot.substitute(row.alpha, params)) * translation(x=robot.substitute(row.a, params))
    else:
        step = sp.eye(4)
    tool = robot.tool if robot.tool is not None else sp.eye(4)
    tail = inverse_transform(step) * robot.row_matrix(n - 1) * robot.row_matrix(n) * tool
    tail = robot.substitute(tail, params)
    point, approach = tail[:3, 3], tail[:3, 2]
    offset = simplified(sp.expand((point.T * approach)[0]))
    square = simplified(sp.expand((point.T * point)[0] - offset ** 2))
    if offset.free_symbols or square.free_symbols or (offset == 0 and square == 0):
        return None
    arm = DHRobot(cut, convention=robot.convention, name=f"{robot.name} (wrist ring)", parameters=robot.parameters,
                  units=robot.units, base=robot.base, tool=None if step == sp.eye(4) else step)
    plan = turned(reach_model(arm, tuple(values)))
    if plan is None or plan.section.reach is None:
        return None
    shoulder = plan.section.reach
    B = first_frame(arm, params)
    s_xy, s_z = shoulder.centre
    axis = [numpy_constant(B[i, 2]) for i in range(3)]
    origin = [numpy_constant(B[i, 3]) for i in range(3)]
    centre = np.array([arith.add(origin[i], arith.mul(axis[i], s_z)) for i in range(3)], dtype=float)
    top = shoulder.bound(tolerance)
    if not math.isfinite(top):
        return None
    reach = float(arith.sqr(arith.add(arith.sqrt((top, top)), (s_xy[1], s_xy[1])))[1])
    return WristRing(numpy_constant(offset), numpy_constant(sp.sqrt(square)), centre, s_z, reach)


def ring_unreachable(edges: tuple, candidates: np.ndarray, directions: np.ndarray, cone: float, ring: WristRing,
                     *, split: int = 2) -> np.ndarray:
    """The pairs (map cell, direction) proved unreachable by the wrist's ring (docs/methods.md section 9).

    With ``y = p - S``, ``r = |y|`` and ``theta`` the angle from ``y`` to the approach ``a``, the ring's nearest
    point to ``S`` is at the squared distance ``g = (r cos theta - L)^2 + (r sin theta - rho)^2 = r^2 - 2 r K
    cos(theta - theta_0) + K^2`` (``K = sqrt(L^2 + rho^2)``, ``theta_0 = atan2(rho, L)``); a configuration has
    ``g <= reach``.  ``g`` grows with ``r`` from ``r >= K``, and with ``|theta - theta_0|``.  Over a piece of the
    cell (``split^3`` of them), ``r >= r_0`` (its nearest point to ``S``, rounded down) and ``theta`` lies
    within ``beta + c`` of the angle from the piece's centre to ``d`` (``beta`` the angle the piece subtends
    from ``S``, ``c`` the cone), so ``g >= r_0^2 - 2 r_0 K cos(Delta) + K^2`` with ``Delta`` the distance from
    ``theta_0`` to that range.  A pair is proved unreachable when that bound exceeds ``reach`` for every piece.
    The angles are doubles from ``atan2`` (errors of about ``1e-15``) and the range is widened by ``1e-9``; the
    lengths are rounded outward.

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
    ring : WristRing
        The arm's ring.
    split : int
        Pieces per axis of each map cell.

    Returns
    -------
    numpy.ndarray
        ``bool`` of the shape of ``candidates``.
    """
    out = np.zeros(candidates.shape, dtype=bool)
    d = np.asarray(directions, dtype=float)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    c = math.radians(cone)
    cells = np.argwhere(candidates.any(axis=-1))
    alive = candidates[tuple(cells.T)]                      # (N, K): the pairs of each cell still claimable
    for piece in itertools.product(range(split), repeat=3):
        y, centre = [], []
        for a in range(3):
            lo, hi = edges[a][cells[:, a]], edges[a][cells[:, a] + 1]
            # the pieces share their split points (one float each), so their union is the cell
            p_lo = lo if piece[a] == 0 else lo + (hi - lo) * (piece[a] / split)
            p_hi = hi if piece[a] == split - 1 else lo + (hi - lo) * ((piece[a] + 1) / split)
            y.append(arith.sub((p_lo, p_hi), (ring.centre[a, 0], ring.centre[a, 1])))
            centre.append(0.5 * (y[-1][0] + y[-1][1]))
        r0_sq = np.maximum(arith.add(arith.add(arith.sqr(y[0]), arith.sqr(y[1])), arith.sqr(y[2]))[0], 0.0)
        yc = np.stack(centre, axis=1)
        half = arith.up(0.5 * np.sqrt(sum((y[a][1] - y[a][0]) ** 2 for a in range(3))))      # half-diagonal
        norm = np.linalg.norm(yc, axis=1)
        with np.errstate(all="ignore"):
            beta = np.where(norm > half, np.arcsin(np.minimum(half / norm * (1 + 1e-12), 1.0)), np.inf)
            # the angle from the piece's centre to each direction, by atan2 (accurate at 0 and pi)
            angle = np.arctan2(np.linalg.norm(np.cross(yc[:, None, :], d[None, :, :]), axis=-1), yc @ d.T)
            spread = beta[:, None] + c
            g = ring.bound(r0_sq[:, None], ring.gap(angle - spread, angle + spread))
        alive &= np.where(np.isnan(g), False, g > ring.reach)
        if not alive.any():
            break
    rows, ks = np.nonzero(alive)
    out[tuple(cells[rows].T) + (ks,)] = True
    return out


def ring_outer_cells(edges: tuple, ring: WristRing, sign: float, cone: float) -> np.ndarray:
    """Cells of a pose section (``rho`` and ``z`` in the first joint's frame) that no configuration reaches with
    its approach within ``cone`` of the first joint's axis, ``sign`` times it: the ring's test of
    :func:`ring_unreachable` on the solid of revolution of each cell.

    A point of the solid of cell ``[rho_0, rho_1] x [z_0, z_1]`` is ``y = (rho cos psi, rho sin psi, z - s_z)``
    from ``S``; its angle from the axis, ``atan2(rho, sign (z - s_z))``, does not depend on ``psi``, and over the
    cell it lies between the angles of the cell's corners when the cell does not hold ``(0, s_z)`` (the polar
    angle of a convex set missing the origin is extreme at its vertices).  The approach lies within ``cone`` of
    the axis, so the angle from ``y`` to it lies within ``cone`` of that range.

    Parameters
    ----------
    edges : tuple of numpy.ndarray
        The section grid's edges (``rho``, then ``z``).
    ring : WristRing
        The arm's ring.
    sign : float
        1 for an approach about the axis, -1 about its opposite (straight down for an upright arm).
    cone : float
        The cone's half-angle, radians (0: an exact approach).

    Returns
    -------
    numpy.ndarray
        ``bool`` of the grid's shape: the cells proved outside.
    """
    r_lo, r_hi = np.maximum(edges[0][:-1], 0.0)[:, None], np.maximum(edges[0][1:], 0.0)[:, None]
    dz = (arith.sub((edges[1][:-1], edges[1][:-1]), (ring.height[1], ring.height[1]))[0][None, :],
          arith.sub((edges[1][1:], edges[1][1:]), (ring.height[0], ring.height[0]))[1][None, :])
    r0_sq = arith.add(arith.sqr((r_lo, r_hi)), arith.sqr(dz))[0]                      # nearest point, below
    corners = [np.arctan2(r + 0 * z, sign * z) for r in (r_lo, r_hi) for z in dz]
    with np.errstate(invalid="ignore"):
        lo, hi = np.minimum.reduce(corners) - MARGIN, np.maximum.reduce(corners) + MARGIN
        holds = (r_lo <= 0) & (dz[0] <= 0) & (dz[1] >= 0)                              # the cell holds S
        g = ring.bound(r0_sq, ring.gap(lo - cone, hi + cone))
        return ~holds & np.where(np.isnan(g), False, g > ring.reach)
