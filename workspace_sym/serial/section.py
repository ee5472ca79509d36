"""A spatial arm turned by its first joint: the certified section in cylindrical coordinates.

The structure (a plan of :func:`workspace_sym.serial.api.reach`, :mod:`workspace_sym.serial.plans`): the
first joint is revolute with ``theta_1 = k q_1 + offset`` and ``q_1`` in no
other entry of the table (its own ``d_1``, ``a_1``, ``alpha_1`` included),
nor in the base or tool transforms.  Then, standard or modified DH, with a
rigid base transform ``B`` (the robot's base, times ``Rx(alpha_0) Tx(a_0)``
of the first row in modified DH),

    p = B Rz(theta_1) w(q'),    w = (u, c, v) of the other joints q',

where the lateral offset ``c`` may vary with ``q'`` (UR5, KUKA KR16 with
its URDF base).  In the frame of the first joint (``B^-1 p``), a point of
cylindrical coordinates ``(rho, psi, z)`` is ``Rz(theta_1)`` of
``w = (rho cos psi', rho sin psi', z)`` with ``rho^2 = u^2 + c^2``: when
``q_1`` turns the position through a whole period, the workspace is the solid
of revolution of the section

    S = {(rho, z) = (sqrt(u^2 + c^2), v)(q')},

the image of a map into the plane that
:func:`~workspace_sym.interval.image.critical_paving` paves.  :class:`RadialMap`
is that map: its enclosures are those of ``(u^2 + c^2, v)`` with an
outward-rounded square root on the first coordinate; its critical set is
decided on the smooth map ``(u^2 + c^2, v)``, whose ``2 x 2`` minors are those
of ``(rho, v)`` times ``2 rho`` (the same signs off the axis, and zero on the
axis ``u = c = 0`` where ``rho`` is not smooth: those configurations count as
critical, so their image is marked and the connectedness argument holds); its
Krawczyk and outside proofs run on ``(u^2 + c^2, v)`` for the squared box
(outward-rounded), which holds the same points.

A box of world ``(x, y, z)`` is mapped to the frame of the first joint by
``B^-1`` in outward-rounded interval arithmetic (an enclosing box); the
interval of ``rho`` over it and its ``z`` interval form a rectangle of the
section's grid: the box is **inner** when the rectangle lies in cells proved
inside ``S`` (every point is reached: any ``theta_1`` is allowed), **outer**
when it lies in cells proved outside (no point of the box is on the solid of
revolution, which holds the workspace whatever the limits of ``q_1``).  With
``q_1`` limited to less than a period the outer verdicts still hold and no box
is declared inner here (the polar angle's interval is not modelled):
:mod:`workspace_sym.serial.turn` proves inner boxes for a turn of half a circle
or more and a section moved by three joints or more, and ``reach`` paves the
other such arms moved by three joints on 3-D cells instead.  With a whole turn, the cells also bound
the workspace's volume by Pappus's theorem (:func:`turned_volume`): the solid
of revolution of the inner cells lies in it, and it lies in the solid of the
cells not proved outside.
"""

from __future__ import annotations

import math
import time
from contextlib import contextmanager
from dataclasses import dataclass
from functools import lru_cache
from typing import cast

import numpy as np
import sympy as sp

from ..interval import arith
from ..interval.boxes import halves
from ..interval.graph import numpy_constant
from ..interval.image import CellGrid, ImageMap, distribute
from ..interval.search import split_every_axis
from ..interval.store import ExactSum
from ..interval.verdict import INSIDE as INNER
from ..interval.verdict import OUTSIDE as OUTER
from ..interval.verdict import UNDECIDED
from ..progress import progress_bar
from ..symbolic import simplified
from ..transforms import inverse_transform, matrix_product, rot_x, translation
from .model import parameter_values
from .tuning import DEFAULT, Tuning

__all__ = ["Pieces", "RadialMap", "SquareMap", "ShoulderReach", "Turned", "turned", "first_joint_turn",
           "shoulder_distance", "to_first_frame", "first_frame", "TurnedTest", "section_bar", "section_paving",
           "in_chunks", "blocks",
           "solid_volumes", "turned_volume", "REACH_SIMPLIFY_OPS", "ElbowReach", "elbow_reach", "squared_enclosures"]


def _square_boxes(T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(rho, z)`` boxes as ``(rho^2, z)`` boxes holding the same points (outward-rounded), and the mask of
    those lying in ``rho >= 0`` (a box reaching ``rho < 0`` holds points no configuration reaches)."""
    T2 = T.copy()
    with np.errstate(all="ignore"):
        lo, hi = arith.sqr((np.maximum(T[:, 0, 0], 0.0), np.maximum(T[:, 0, 1], 0.0)))
    T2[:, 0, 0], T2[:, 0, 1] = lo, hi
    return T2, T[:, 0, 0] >= 0


def squared_enclosures(W: np.ndarray) -> np.ndarray:
    """Enclosures of ``(u^2 + c^2, v)`` from those of ``(u, c, v)`` (``(N, 3, 2)``), rounded outward: ``(N, 2, 2)``,
    the first coordinate clipped at 0, infinite where the arithmetic gives NaN; empty (``lo > hi``) where ``u`` or
    ``c`` is.

    Parameters
    ----------
    W : numpy.ndarray
        ``(N, 3, 2)`` enclosures of ``(u, c, v)``.

    Returns
    -------
    numpy.ndarray
        ``(N, 2, 2)``.
    """
    E = np.empty((len(W), 2, 2))
    with np.errstate(all="ignore"):
        lo, hi = arith.add(arith.sqr((W[:, 0, 0], W[:, 0, 1])), arith.sqr((W[:, 1, 0], W[:, 1, 1])))
    empty = (W[:, 0, 0] > W[:, 0, 1]) | (W[:, 1, 0] > W[:, 1, 1])
    E[:, 0, 0], E[:, 0, 1] = np.where(empty, np.inf, np.maximum(lo, 0.0)), np.where(empty, -np.inf, hi)
    E[:, 1] = W[:, 2]
    return np.where(np.isnan(E), np.inf * np.array([-1.0, 1.0]), E)


class SquareMap(ImageMap):
    """``q' -> (u^2 + c^2, v)`` whose interval enclosures (values and Jacobian, used by the Krawczyk test)
    come from those of ``(u, c, v)`` and their derivatives: ``sqr(u) + sqr(c)`` and ``2 (u u_j + c c_j)``,
    tighter than the expanded expression's (kept for the floats of Newton's method).

    Its Krawczyk test is not inflated: on 1500 sampled cells of the UR5's section (width 0.0144), one test per
    choice of joints, then four pieces for the cells left, proves 72.5 % of them in a quarter of the time that
    two inflations take to prove 76 %; the time saved goes to the later stages of :func:`section_paving`.

    Parameters
    ----------
    rho2 : sympy.Expr
        ``u^2 + c^2``, for the floats of Newton's method.
    w : sequence of sympy.Expr
        ``(u, c, v)``.
    variables : sequence of sympy.Symbol
        The joints ``q'``.
    limits : sequence of tuple
        Their ``(lo, hi)`` limits, exact or floats.
    periodic : sequence of bool
        As for :class:`~workspace_sym.interval.image.ImageMap`.
    lateral : ImageMap, optional
        The map ``q' -> (u, c, v)`` when it is built already (its own enclosures); None: compiled from ``w``.
    """

    INFLATIONS = 0

    def __init__(self, rho2, w, variables, limits, periodic, lateral: ImageMap | None = None):
        super().__init__([rho2, w[2]], variables, limits, periodic)
        self.lateral = ImageMap(w, variables, limits, periodic) if lateral is None else lateral

    def enclose(self, Q: np.ndarray) -> np.ndarray:
        """Enclosures of ``(u^2 + c^2, v)`` from those of ``u``, ``c`` and ``v``.

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            ``(N, 2, 2)`` outward-rounded enclosures (the first coordinate clipped at 0; infinite where the
            arithmetic gives NaN).
        """
        return squared_enclosures(self.lateral.enclose(Q))

    def jacobian_enclosure(self, Q: np.ndarray, columns=None):
        """Enclosures of the Jacobian of ``(u^2 + c^2, v)``: ``2 (u u_j + c c_j)`` and ``v_j``.

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.
        columns : iterable of int, optional
            The columns wanted; the others are None.  None: all.

        Returns
        -------
        list
            Two rows of ``k`` entries, each ``(lo, hi)`` arrays of length ``N`` or None.
        """
        W = self.lateral.enclose(Q)
        J = self.lateral.jacobian_enclosure(Q, columns)
        u, c = (W[:, 0, 0], W[:, 0, 1]), (W[:, 1, 0], W[:, 1, 1])
        two = (2.0, 2.0)
        with np.errstate(all="ignore"):
            top = [None if J[0][j] is None else arith.mul(two, arith.add(arith.mul(u, J[0][j]), arith.mul(c, J[1][j])))
                   for j in range(self.k)]
        return [top, [J[2][j] for j in range(self.k)]]


class RadialMap:
    """The section map ``q' -> (rho, v) = (sqrt(u^2 + c^2), v)`` (module docstring), with what
    :func:`~workspace_sym.interval.image.critical_paving` needs; the rest is the squared map's.

    Parameters
    ----------
    square : ImageMap
        The map ``q' -> (u^2 + c^2, v)`` (a :class:`SquareMap`).
    lateral : ImageMap
        The map ``q' -> (u, c, v)``.
    reach : ShoulderReach, optional
        The outer bound from the distance to the shoulder, when there is one.

    Raises
    ------
    ValueError
        ``square`` is not a map into the plane, or ``lateral`` not a map into space.
    """

    def __init__(self, square: ImageMap, lateral: ImageMap, reach: ShoulderReach | None = None):
        if square.m != 2 or lateral.m != 3:
            raise ValueError("RadialMap needs the maps (u^2 + c^2, v) and (u, c, v)")
        self.square, self.lateral, self.reach = square, lateral, reach
        self._last: tuple | None = None

    def __getattr__(self, name):
        if name in ("square", "lateral", "reach", "_last"):   # not set yet (unpickling): no recursion
            raise AttributeError(name)
        return getattr(self.square, name)

    def enclose(self, Q: np.ndarray) -> np.ndarray:
        """Enclosures of ``(rho, v)``, ``rho = sqrt(u^2 + c^2)`` from the enclosures of ``u`` and ``c``.

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            ``(N, 2, 2)`` outward-rounded enclosures (infinite where the arithmetic gives NaN; empty, ``[inf,
            -inf]``, where ``lateral`` proves broken over the box a side condition every configuration must meet:
            :meth:`~workspace_sym.serial.turn.SideMap.refused`, with its ``prune``).
        """
        W = getattr(self.lateral, "enclose_outer", self.lateral.enclose)(Q)     # (a cone's every approach)
        E = np.empty((len(Q), 2, 2))
        with np.errstate(all="ignore"):
            r2 = arith.add(arith.sqr((W[:, 0, 0], W[:, 0, 1])), arith.sqr((W[:, 1, 0], W[:, 1, 1])))
            E[:, 0, 0], E[:, 0, 1] = arith.sqrt((np.maximum(r2[0], 0.0), r2[1]))
        E[:, 1] = W[:, 2]
        E = np.where(np.isnan(E), np.inf * np.array([-1.0, 1.0]), E)
        # joint boxes proved to break a condition every configuration meets hold none of them: empty
        refused = getattr(self.lateral, "refused", None) if getattr(self.lateral, "prune", False) else None
        if refused is not None:
            E[refused(Q)] = np.array([np.inf, -np.inf])
        return E

    def _rows(self, Q: np.ndarray):
        """Interval Jacobian rows ``u u_j + c c_j`` (half the derivative of ``rho^2``) and ``v_j`` over ``Q``,
        from the enclosures of ``u, c`` and of their derivatives (the last ``Q`` is remembered)."""
        if self._last is not None and self._last[0] is Q:
            return self._last[1]
        W = self.lateral.enclose(Q)
        J = self.lateral.jacobian_enclosure(Q)
        u, c = (W[:, 0, 0], W[:, 0, 1]), (W[:, 1, 0], W[:, 1, 1])
        with np.errstate(all="ignore"):
            top = [arith.add(arith.mul(u, J[0][j]), arith.mul(c, J[1][j])) for j in range(self.k)]
        rows = (top, [J[2][j] for j in range(self.k)])
        self._last = (Q, rows)
        return rows

    def minor_enclosure(self, Q: np.ndarray, i: int, j: int):
        """An enclosure of ``det [J_i, J_j]`` of ``(u^2 + c^2, v) / 2`` (the sign of that of ``(rho, v)``
        off the axis; zero on it): the interval product of the entries, cut to one sign where the interval
        ``2 x 2`` matrix is proved regular (its product with the inverse ``C`` of its midpoint lies within
        distance 1 of the identity in the max-row-sum norm, so every matrix in it has the sign of ``det C``,
        itself enclosed).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.
        i, j : int
            Two distinct columns (joints), in either order (the sign follows the order).

        Returns
        -------
        lo : numpy.ndarray
            ``(N,)`` lower bounds of the minor.
        hi : numpy.ndarray
            ``(N,)`` upper bounds.
        """
        top, bottom = self._rows(Q)
        a, b, c, d = top[i], top[j], bottom[i], bottom[j]
        with np.errstate(all="ignore"):
            lo, hi = arith.sub(arith.mul(a, d), arith.mul(b, c))
            mid = [0.5 * (x[0] + x[1]) for x in (a, b, c, d)]
            det = mid[0] * mid[3] - mid[1] * mid[2]
            C = [mid[3] / det, -mid[1] / det, -mid[2] / det, mid[0] / det]      # inverse of [[a, b], [c, d]]
            point = [(x, x) for x in C]
            B = [arith.add(arith.mul(point[0], a), arith.mul(point[1], c)), arith.add(arith.mul(point[0], b),
                 arith.mul(point[1], d)), arith.add(arith.mul(point[2], a), arith.mul(point[3], c)),
                 arith.add(arith.mul(point[2], b), arith.mul(point[3], d))]
            gap = [arith.sub((1.0, 1.0) if k in (0, 3) else (0.0, 0.0), B[k]) for k in range(4)]
            size = [np.maximum(np.abs(g[0]), np.abs(g[1])) for g in gap]
            row0, row1 = arith.up(size[0] + size[1]), arith.up(size[2] + size[3])
            regular = np.isfinite(row0) & np.isfinite(row1) & (row0 < 1) & (row1 < 1)
            det_c = arith.sub(arith.mul(point[0], point[3]), arith.mul(point[1], point[2]))
        positive = regular & (det_c[0] > 0)
        negative = regular & (det_c[1] < 0)
        tiny = np.finfo(float).tiny
        lo = np.where(positive, np.maximum(lo, tiny), lo)
        hi = np.where(negative, np.minimum(hi, -tiny), hi)
        return (lo, hi) if i < j else (-hi, -lo)

    def position_float(self, q: np.ndarray) -> np.ndarray:
        """``(rho, v)`` at joint values, in floats.

        Parameters
        ----------
        q : numpy.ndarray
            ``(N, k)`` joint values.

        Returns
        -------
        numpy.ndarray
            ``(N, 2)`` values.
        """
        p = self.square.position_float(q)
        p[:, 0] = np.sqrt(np.maximum(p[:, 0], 0.0))
        return p

    def prove_inside_multistart(self, T: np.ndarray, rng, **options):
        """The squared map's multistart inner test on the ``(rho^2, v)`` boxes holding the same points.

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, 2, 2)`` boxes of ``(rho, v)``.
        rng : numpy.random.Generator
            Draws the random starts.
        **options
            Those of :meth:`~workspace_sym.interval.image.ImageMap.prove_inside_multistart` (``starts``,
            ``seeds``, ``reached``).

        Returns
        -------
        numpy.ndarray or tuple
            The ``(N,)`` mask of the boxes proved inside (none reaching ``rho < 0``); with ``reached=True``, also
            the mask of the boxes whose centre Newton's method reached.
        """
        T2, ok = _square_boxes(T)
        result = self.square.prove_inside_multistart(T2, rng, **options)
        if isinstance(result, tuple):
            return result[0] & ok, result[1]
        return result & ok

    def prove_inside(self, T: np.ndarray, seeds: np.ndarray, **options) -> np.ndarray:
        """The squared map's inner test on the ``(rho^2, v)`` boxes holding the same points.

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, 2, 2)`` boxes of ``(rho, v)``.
        seeds : numpy.ndarray
            ``(N, k)`` joint values from which Newton's method starts.
        **options
            Those of :meth:`~workspace_sym.interval.image.ImageMap.prove_inside` (``newton``).

        Returns
        -------
        numpy.ndarray
            ``(N,)`` mask of the boxes proved inside the section (none reaching ``rho < 0``).
        """
        T2, ok = _square_boxes(T)
        return self.square.prove_inside(T2, seeds, **options) & ok

    def prove_outside(self, T: np.ndarray, **options) -> np.ndarray:
        """Mask of the boxes of ``(rho, v)`` proved to hold no point of the section.

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, 2, 2)`` boxes of ``(rho, v)``.
        **options
            Those of :meth:`~workspace_sym.interval.image.ImageMap.prove_outside` (``max_pairs``, ``rounds``).

        Returns
        -------
        numpy.ndarray
            ``(N,)`` booleans.
        """
        # The outward enclosures of rho: a joint box is dropped only when they miss the box.  ImageMap's
        # method reads only what this class also provides (limits, enclose, the periodic joints).
        return ImageMap.prove_outside(cast(ImageMap, self), T, **options)


class ShoulderReach:
    """An outer bound of the section from the distance to a point ``S`` fixed in the turning frame (on the
    axis of the first joint that moves the section, where ``h`` below does not depend on that joint).

    ``h(q') = |w(q') - S|^2`` is the squared distance in space from the point ``S = (s_x, s_y, s_z)`` of the
    frame of the first joint; the first joint turns ``w`` and ``S`` together, so a configuration whose point
    has section coordinates ``(rho, z)`` has ``h >= (rho - |s_xy|)^2 + (z - s_z)^2`` (``w_xy . s_xy <= rho
    |s_xy|``).  With ``H`` an upper bound of ``h`` over the joint box (:meth:`bound`: branch and bound on
    outward-rounded enclosures), every cell of the section farther than ``sqrt(H)`` from ``(|s_xy|, s_z)``
    is outside the section (:meth:`far_cells`); likewise, with ``h <= (rho + |s_xy|)^2 + (z - s_z)^2`` and a
    lower bound ``L`` (:meth:`lowest`), every cell whose farthest point is nearer than ``sqrt(L)`` (the hole
    around the shoulder of an arm whose elbow cannot fold flat: :meth:`near_cells`).  ``h`` is written with
    the joints that change it only (:func:`shoulder_distance`: the LBR iiwa's and the Panda's joints 4 to 6),
    on which the branch and bound is tight and quick.

    Parameters
    ----------
    expression : sympy.Expr
        ``h``, in ``variables``.
    variables : sequence of sympy.Symbol
        The joints ``h`` depends on.
    limits : sequence of tuple
        Their ``(lo, hi)`` limits, exact or floats.
    periodic : sequence of bool
        As for :class:`~workspace_sym.interval.image.ImageMap`.
    centre : tuple
        ``(|s_xy|, s_z)``, exact.
    """

    def __init__(self, expression, variables, limits, periodic, centre):
        self.map = ImageMap([expression], variables, limits, periodic)
        self.centre = tuple(numpy_constant(c) for c in centre)          # (|s_xy|, s_z), enclosed
        self._bounds: dict = {}           # sign -> (tolerance, bound) of the last search

    def enclose(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(lo, hi)`` of ``h`` over the joint boxes ``Q`` of its variables: the natural enclosure
        intersected with the centred form ``h(c) + sum_j dh/dq_j(Q) (Q_j - c_j)`` (``c`` the centres).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        lo : numpy.ndarray
            ``(N,)`` lower bounds of ``h`` (-inf where the arithmetic gives NaN).
        hi : numpy.ndarray
            ``(N,)`` upper bounds (inf where it gives NaN).
        """
        natural = self.map.enclose(Q)[:, 0]
        centre = 0.5 * Q[:, :, 0] + 0.5 * Q[:, :, 1]
        acc = tuple(self.map.enclose(np.repeat(centre[:, :, None], 2, axis=2))[:, 0].T)
        J = self.map.jacobian_enclosure(Q)[0]
        with np.errstate(all="ignore"):
            for j in range(self.map.k):
                acc = arith.add(acc, arith.mul(J[j], arith.sub((Q[:, j, 0], Q[:, j, 1]), (centre[:, j], centre[:, j]))))
        lo, hi = np.maximum(natural[:, 0], acc[0]), np.minimum(natural[:, 1], acc[1])
        return np.where(np.isnan(lo), -np.inf, lo), np.where(np.isnan(hi), np.inf, hi)

    def bound(self, tolerance: float, *, max_boxes: int = 20_000, rounds: int = 60) -> float:
        """An upper bound of ``h`` over the joint box, within about ``tolerance`` of its maximum: boxes whose
        enclosure stays below a value of ``h`` proved attained (the lower end of the enclosure at a box's
        centre) are dropped, the others halved, until the bound is that close or the boxes that many.

        The last bound found is kept: a later call with a tolerance no finer returns it without a search.

        Parameters
        ----------
        tolerance : float
            How close to the maximum the bound is sought.
        max_boxes : int
            The search stops before it would hold more boxes.
        rounds : int
            Halvings at most.

        Returns
        -------
        float
            An upper bound of ``h`` over the joint box.
        """
        return self._extreme(tolerance, 1.0, max_boxes, rounds)

    def lowest(self, tolerance: float, *, max_boxes: int = 20_000, rounds: int = 60) -> float:
        """A lower bound of ``h`` over the joint box, within about ``tolerance`` of its minimum (the search of
        :meth:`bound` on ``-h``, whose enclosures are those of ``h`` negated, exactly).

        Parameters
        ----------
        tolerance : float
            How close to the minimum the bound is sought.
        max_boxes : int
            The search stops before it would hold more boxes.
        rounds : int
            Halvings at most.

        Returns
        -------
        float
            A lower bound of ``h`` over the joint box.
        """
        return -self._extreme(tolerance, -1.0, max_boxes, rounds)

    def _extreme(self, tolerance: float, sign: float, max_boxes: int, rounds: int) -> float:
        """An upper bound of ``sign h`` (``sign`` is 1 or -1) by the branch and bound of :meth:`bound`."""
        cached = self._bounds.get(sign)
        if cached is not None and cached[0] <= tolerance:
            return cached[1]

        def enclose(Q):
            lo, hi = self.enclose(Q)
            return (lo, hi) if sign > 0 else (-hi, -lo)

        Q = self.map.limits[None].copy()
        attained = -np.inf
        for _ in range(rounds):
            lo, hi = enclose(Q)
            centre = 0.5 * Q[:, :, 0] + 0.5 * Q[:, :, 1]
            at = self.map.enclose(np.repeat(centre[:, :, None], 2, axis=2))[:, 0]
            at = at[:, 0] if sign > 0 else -at[:, 1]
            attained = max(attained, float(np.max(at)))
            keep = hi > attained
            Q, hi = Q[keep], hi[keep]
            if not len(Q) or float(np.max(hi)) - attained <= tolerance or 2 * len(Q) > max_boxes:
                break
            children, ok = halves(Q)
            Q = np.concatenate([Q[~ok], children.reshape(-1, 2, *Q.shape[1:])[ok].reshape(-1, *Q.shape[1:])])
        top = max(attained, float(np.max(hi))) if len(Q) else attained
        self._bounds[sign] = (tolerance, top)
        return top

    def far_cells(self, grid: CellGrid, bound: float) -> np.ndarray:
        """Boolean grid of the cells every point of which is farther than ``sqrt(bound)`` from the centre
        (outward-rounded: the distance is bounded below).

        Parameters
        ----------
        grid : CellGrid
            A grid of the section ``(rho, z)``.
        bound : float
            An upper bound of ``h`` (:meth:`bound`).

        Returns
        -------
        numpy.ndarray
            Booleans of ``grid.shape``.
        """
        e0, e1 = grid.edges
        return self.far(e0[:-1, None], e0[1:, None], e1[None, :-1], e1[None, 1:], bound)

    def far(self, r0, r1, z0, z1, bound: float) -> np.ndarray:
        """:meth:`far_cells` of the rectangles ``[r0, r1] x [z0, z1]`` (arrays broadcast together).

        Parameters
        ----------
        r0, r1, z0, z1 : numpy.ndarray
            The rectangles' edges.
        bound : float
            An upper bound of ``h`` (:meth:`bound`).

        Returns
        -------
        numpy.ndarray
            Booleans of the broadcast shape.
        """
        (a, b), (c, d) = self.centre
        with np.errstate(all="ignore"):
            dr = np.maximum(0.0, np.maximum(arith.sub((r0, r0), (b, b))[0], arith.sub((a, a), (r1, r1))[0]))
            dz = np.maximum(0.0, np.maximum(arith.sub((z0, z0), (d, d))[0], arith.sub((c, c), (z1, z1))[0]))
            r2, z2 = arith.sqr((dr, dr))[0], arith.sqr((dz, dz))[0]
            return arith.add((r2, r2), (z2, z2))[0] > bound

    def near_cells(self, grid: CellGrid, lowest: float) -> np.ndarray:
        """Boolean grid of the cells every point of which, at every polar angle, is nearer than
        ``sqrt(lowest)`` to ``S`` (``lowest`` a lower bound of ``h``, :meth:`lowest`): the farthest a point of
        section coordinates ``(rho, z)`` can be from ``S`` is ``(rho + |s_xy|)^2 + (z - s_z)^2``, bounded above
        over the cell (outward-rounded).  No configuration reaches them: the hole around the shoulder.

        Parameters
        ----------
        grid : CellGrid
            A grid of the section ``(rho, z)``.
        lowest : float
            A lower bound of ``h`` (:meth:`lowest`).

        Returns
        -------
        numpy.ndarray
            Booleans of ``grid.shape``.
        """
        e0, e1 = grid.edges
        return self.near(e0[:-1, None], e0[1:, None], e1[None, :-1], e1[None, 1:], lowest)

    def near(self, r0, r1, z0, z1, lowest: float) -> np.ndarray:
        """:meth:`near_cells` of the rectangles ``[r0, r1] x [z0, z1]`` (arrays broadcast together).

        Parameters
        ----------
        r0, r1, z0, z1 : numpy.ndarray
            The rectangles' edges.
        lowest : float
            A lower bound of ``h`` (:meth:`lowest`).

        Returns
        -------
        numpy.ndarray
            Booleans of the broadcast shape.
        """
        (_, b), (c, d) = self.centre
        with np.errstate(all="ignore"):
            dr = arith.add((np.maximum(r1, 0.0), np.maximum(r1, 0.0)), (b, b))[1]
            dz = np.maximum(arith.sub((d, d), (z0, z0))[1], arith.sub((z1, z1), (c, c))[1])
            r2, z2 = arith.sqr((dr, dr))[1], arith.sqr((dz, dz))[1]
            return arith.add((r2, r2), (z2, z2))[1] < lowest

    def outside(self, r0, r1, z0, z1, width: float, tolerance: float = DEFAULT.reach_tolerance) -> np.ndarray:
        """Mask of the rectangles ``[r0, r1] x [z0, z1]`` (arrays broadcast together) proved outside the section
        by the distance from ``S``: far (:meth:`far`) or in the hole around it (:meth:`near`), both bounds of
        ``h`` sought within ``tolerance`` (:attr:`Tuning.reach_tolerance`) times ``width`` times the greatest
        distance (an upper bound of it).

        Parameters
        ----------
        r0, r1, z0, z1 : numpy.ndarray
            The rectangles' edges.
        width : float
            The width the tolerance is counted in (a cell's, or a piece's).
        tolerance : float
            The tolerance, in widths.

        Returns
        -------
        numpy.ndarray
            Booleans of the broadcast shape.
        """
        root = self.enclose(self.map.limits[None])[1][0]
        tolerance = tolerance * width * math.sqrt(max(root, 0.0))
        return self.far(r0, r1, z0, z1, self.bound(tolerance)) | self.near(r0, r1, z0, z1, self.lowest(tolerance))

    def outside_cells(self, grid: CellGrid, tolerance: float = DEFAULT.reach_tolerance) -> np.ndarray:
        """Boolean grid of the cells proved outside the section by the distance from ``S`` (:meth:`outside`,
        the far cells and the hole), the bounds of ``h`` sought within ``tolerance`` times the cell's width
        times the greatest distance (for the greatest distance, about half ``tolerance`` of a cell: a tenth by
        default).

        Parameters
        ----------
        grid : CellGrid
            A grid of the section ``(rho, z)``.
        tolerance : float
            The tolerance, in cell widths.

        Returns
        -------
        numpy.ndarray
            Booleans of ``grid.shape``.
        """
        e0, e1 = grid.edges
        return self.outside(e0[:-1, None], e0[1:, None], e1[None, :-1], e1[None, 1:], grid.width, tolerance)

    def far_boxes(self, T: np.ndarray, bound: float) -> np.ndarray:
        """Mask of the ``(rho, z)`` rectangles ``T`` (``(N, 2, 2)``) every point of which is farther than
        ``sqrt(bound)`` from the centre, as :meth:`far_cells` (the pieces of cells of :func:`section_paving`).

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, 2, 2)`` rectangles.
        bound : float
            An upper bound of ``h`` (:meth:`bound`).

        Returns
        -------
        numpy.ndarray
            ``(N,)`` booleans.
        """
        return self.far(T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1], bound)


@dataclass(frozen=True)
class Turned:
    """``p = B Rz(theta_1) w(q')``: the section map, ``B^-1`` as interval rotation rows and translation
    (None for the identity), and whether ``q_1`` turns the position through a whole period.

    Parameters
    ----------
    section : RadialMap
        The section map ``q' -> (rho, v)``.
    inverse : tuple or None
        ``(rows, back)``: the 3 x 3 rotation ``R^T`` and the translation ``-R^T t`` of ``B^-1``, each entry a
        ``(lo, hi)`` pair of floats enclosing it; None when ``B`` is the identity.
    full : bool
        ``q_1`` turns the position through a whole period.
    """

    section: RadialMap
    inverse: tuple | None
    full: bool


def first_frame(robot, parameters) -> sp.Matrix:
    """``B``: the base transform, times ``Rx(alpha_0) Tx(a_0)`` of the first row in modified DH: the frame whose
    ``z`` axis is the first joint's.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : dict or None
        Values of its symbolic lengths.

    Returns
    -------
    sympy.Matrix
        The exact ``4 x 4`` transform.
    """
    B = robot.base if robot.base is not None else sp.eye(4)
    if robot.convention == "modified":
        joint = robot.joints[0]
        B = B * rot_x(robot.substitute(joint.alpha, parameters)) * translation(x=robot.substitute(joint.a, parameters))
    return B


def first_joint_turn(model):
    """``(q1, theta_1, slope)`` when the first joint is revolute with ``theta_1 = slope q1 + offset`` and ``q1``
    appears in no other entry of the table (its own row's ``d``, ``a``, ``alpha`` included), nor in the base or
    the tool: then it turns everything after it and nothing else.  None otherwise.

    Parameters
    ----------
    model : ReachModel
        The robot's reach model.

    Returns
    -------
    tuple or None
        ``(q1, theta_1, slope)``: the joint's symbol, its angle ``theta_1`` with the parameters substituted, and
        the constant ``d theta_1 / d q1`` (SymPy); None when the joint is not such a turn.
    """
    robot = model.robot
    joint = robot.joints[0]
    if joint.kind != "R":
        return None
    q1 = joint.variable
    others = [joint.d, joint.a, joint.alpha] + [e for j in robot.joints[1:] for e in (j.theta, j.d, j.a, j.alpha)]
    others += [e for M in (robot.base, robot.tool) if M is not None for e in M]
    if any(q1 in sp.sympify(e).free_symbols for e in others):
        return None
    theta = robot.substitute(joint.theta, model.parameters)
    slope = sp.diff(theta, q1)
    if slope.free_symbols or slope == 0:
        return None
    return q1, theta, slope


@lru_cache(maxsize=16)
def turned(model) -> Turned | None:
    """The structure of the module docstring in a :class:`~workspace_sym.serial.model.ReachModel`, or None
    (cached per model, as :func:`~workspace_sym.serial.model.reach_model` caches the models: a pose structure
    and the position plans of one robot share it; every user only reads it).

    Parameters
    ----------
    model : ReachModel
        The robot's reach model.

    Returns
    -------
    Turned or None
        The structure (a spatial position, a revolute first joint turning everything after it, a rigid ``B``,
        a section moved by at least one joint), or None.
    """
    robot = model.robot
    if model.m != 3 or model.joints[:1] != [0] or robot.joints[0].kind != "R":
        return None
    turn = first_joint_turn(model)
    if turn is None:
        return None
    q1, theta, slope = turn
    B = first_frame(robot, model.parameters)
    R, t = B[:3, :3], B[:3, 3]
    if B[3, :] != sp.Matrix([[0, 0, 0, 1]]) or sp.simplify(R.T * R - sp.eye(3)) != sp.zeros(3, 3):
        return None                                     # not rigid: the structure is not there
    # w = Rz(-theta_1) B^-1 p, read at theta_1 = 0.
    at_zero = {q1: -theta.subs(q1, 0) / slope}
    w = [simplified(e) for e in (R.T * (model.position - t)).subs(at_zero)]
    if any(q1 in e.free_symbols for e in w):
        return None
    rho2 = w[0] ** 2 + w[1] ** 2        # its floats only (enclosures come from u, c, v: SquareMap)
    # Joints that move the section: decided on the exact expressions (a joint absent from them is dropped).
    variables = [q for q in model.variables[1:] if q in (rho2.free_symbols | w[2].free_symbols)]
    if not variables:
        return None
    rows = [model.variables.index(q) for q in variables]
    limits, periodic = [model.exact_limits[r] for r in rows], model.periodic[rows]
    square = SquareMap(rho2, w, variables, limits, periodic)
    inverse = None
    if B != sp.eye(4):
        Rt = R.T
        back = -Rt * t
        inverse = (tuple(tuple(numpy_constant(Rt[i, j]) for j in range(3)) for i in range(3)),
                   tuple(numpy_constant(back[i]) for i in range(3)))
    reach = _shoulder_reach(model, B, at_zero, model.joints[rows[0]])
    return Turned(RadialMap(square, square.lateral, reach), inverse, bool(model.periodic[0]))


REACH_SIMPLIFY_OPS = 300         # a larger squared distance is compiled expanded, not simplified


def shoulder_distance(robot, parameters, joint: int):
    """``(h, variables)``: the squared distance ``h`` from the origin ``S`` of the frame whose ``z`` axis is
    the axis of ``joint`` (0-based; that frame is ``joint`` in standard DH, ``joint + 1`` in modified DH) to the
    tool point, written with the joints that change that distance only, and its free joint variables.

    The distance is the same in every frame: in frame ``k`` it is ``|r_k - s_k|`` with ``r_k`` the tool point
    (a product of the rows after ``k`` and the tool) and ``s_k`` the coordinates of ``S``.  While ``s_k`` is a
    constant point (it is ``0`` in the joint's frame), the next row's inverse maps it to ``s_(k+1)``; when that
    is a constant too, the row's joint turns about an axis through ``S`` (``|Rz(q) r - s| = |r - s|`` for ``s``
    on the axis): it is dropped, and so on.  The first row whose joint moves ``s`` ends the walk; ``h`` is
    ``|r_k - s_k|^2`` there (expanded: the rotations dropped cannot leave a ``cos^2 + sin^2`` behind).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : dict or None
        Values of its symbolic parameters (None: the robot's own).
    joint : int
        The joint whose axis holds ``S`` (0-based).

    Returns
    -------
    h : sympy.Expr
        The squared distance (its shorter form by ``sympy.fu`` when that is shorter and ``h`` has at most
        ``REACH_SIMPLIFY_OPS`` operations).
    variables : list of sympy.Symbol
        The joints ``h`` depends on, in the robot's order.
    """
    h, variables = _shoulder_distance(robot, parameter_values(parameters), joint)
    return h, list(variables)


@lru_cache(maxsize=64)
def _shoulder_distance(robot, values: tuple, joint: int) -> tuple:
    """:func:`shoulder_distance` with hashable parameter values, cached: the turned structure, the elbow's reach
    and an offset flange's planes ask for the same distances (the Panda's at its second joint: 2 to 3 s each)."""
    parameters = dict(values) if values else None
    frame = joint + (robot.convention == "modified")
    joints = set(robot.q)
    s = sp.zeros(3, 1)
    while frame < robot.n:
        inverse = inverse_transform(robot.substitute(robot.row_matrix(frame + 1), parameters))
        moved = (inverse[:3, :3] * s + inverse[:3, 3]).applyfunc(sp.simplify)
        if any(e.free_symbols & joints for e in moved):
            break
        s, frame = moved, frame + 1
    T = sp.eye(4)
    for row in range(frame + 1, robot.n + 1):
        T = matrix_product(T, robot.substitute(robot.row_matrix(row), parameters))
    if robot.tool is not None:
        T = matrix_product(T, robot.substitute(robot.tool, parameters))
    h = sp.expand(sum((T[i, 3] - s[i]) ** 2 for i in range(3)))
    if sp.count_ops(h) <= REACH_SIMPLIFY_OPS:
        short = sp.expand(sp.fu(h))                # products of sines and cosines to sums of angles
        h = short if sp.count_ops(short) < sp.count_ops(h) else h
    return h, tuple(q for q in robot.q if q in h.free_symbols)


def _shoulder_reach(model, B, at_zero, joint: int) -> ShoulderReach | None:
    """:class:`ShoulderReach` with ``S`` on the axis of ``joint`` (the first that moves the section; its
    squared distance :func:`shoulder_distance`), ``S`` in the frame of the first joint at ``theta_1 = 0``;
    None when that point moves with ``q_1`` there (it cannot for the structure of :func:`turned`, checked all
    the same) or the distance moves with no joint."""
    robot = model.robot
    R, t = B[:3, :3], B[:3, 3]
    origin = robot.substitute(robot._parameter_twists(joint)["theta"][2], model.parameters)
    S = [simplified(e) for e in (R.T * (sp.Matrix(origin) - t)).subs(at_zero)]
    if any(e.free_symbols for e in S):
        return None
    h, variables = shoulder_distance(robot, model.parameters, joint)
    if not variables or any(q not in model.variables for q in variables):
        return None
    rows = [model.variables.index(q) for q in variables]
    return ShoulderReach(h, variables, [model.exact_limits[r] for r in rows], model.periodic[rows],
                         (sp.sqrt(S[0] ** 2 + S[1] ** 2), S[2]))


class ElbowReach:
    """An outer bound of the section from the distance to the elbow ``E``, a point that moves with the joints
    before it (docs/methods.md section 5, "the elbow's reach").

    ``E(q_E)`` is the origin of the frame on the axis of the elbow joint (the first joint after the shoulder
    whose axis misses ``S``), in the frame of the first joint at ``theta_1 = 0``, a function of the joints
    ``q_E`` before the elbow; ``h_E = |w - E|^2`` is the squared distance from it to the tool point, a function
    of the joints after it (:func:`shoulder_distance` at the elbow joint), bounded above by ``H_E``
    (:meth:`ShoulderReach.bound`).  A configuration whose point has section coordinates ``(rho, z)`` has
    ``(rho - rho_E)^2 + (z - z_E)^2 <= |w - E|^2 <= H_E`` with ``rho_E = |E_xy|`` (the triangle inequality in
    the plane ``xy``: ``|w_xy - E_xy| >= | |w_xy| - |E_xy| |``).  So a rectangle of ``(rho, z)`` farther than
    ``sqrt(H_E)`` from every rectangle enclosing ``(rho_E, z_E)`` over the boxes of a cover of the joint box of
    ``q_E`` (:meth:`cover`: outward-rounded enclosures) holds no point of the section.

    Parameters
    ----------
    point : sequence of sympy.Expr
        ``E = (E_x, E_y, E_z)`` in ``point_variables``.
    point_variables : sequence of sympy.Symbol
        The joints ``E`` depends on.
    point_limits, point_periodic : sequence
        Their limits and periodicity (as for :class:`~workspace_sym.interval.image.ImageMap`).
    distance : ShoulderReach
        ``h_E`` (only its :meth:`~ShoulderReach.bound` is used).
    """

    def __init__(self, point, point_variables, point_limits, point_periodic, distance: ShoulderReach):
        self.map = ImageMap(list(point), point_variables, point_limits, point_periodic)
        self.distance = distance
        self._cover: dict = {}

    def rectangles(self, Q: np.ndarray) -> np.ndarray:
        """``(N, 2, 2)`` rectangles enclosing ``(rho_E, z_E)`` over the joint boxes ``Q`` (outward-rounded).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` boxes of the joints ``E`` depends on.

        Returns
        -------
        numpy.ndarray
            ``(N, 2, 2)``: ``rho_E`` then ``z_E`` (``[-inf, inf]``, or ``[0, inf]`` for ``rho_E``, where an
            enclosure fails).
        """
        E = self.map.enclose(Q)
        with np.errstate(all="ignore"):
            x2, y2 = arith.sqr((E[:, 0, 0], E[:, 0, 1])), arith.sqr((E[:, 1, 0], E[:, 1, 1]))
            r2 = arith.add(x2, y2)
            rho = arith.sqrt((np.maximum(r2[0], 0.0), r2[1]))      # rho_E^2 >= 0: clipping is exact
        out = np.empty((len(Q), 2, 2))
        out[:, 0, 0] = np.where(np.isnan(rho[0]), 0.0, rho[0])
        out[:, 0, 1] = np.where(np.isnan(rho[1]), np.inf, rho[1])
        out[:, 1] = E[:, 2]
        return out

    def cover(self, width: float, max_boxes: int = 512) -> np.ndarray:
        """Rectangles of ``(rho_E, z_E)`` over a cover of the joint box of ``q_E`` by boxes halved (along the
        joint that moves ``E`` most, from the Jacobian's enclosure) until each rectangle is at most ``width``
        wide or the boxes would be more than ``max_boxes``; kept per width.  Any cover of the joint box keeps
        the bound sound; a finer one makes it tighter.

        Parameters
        ----------
        width : float
            The widest rectangle sought.
        max_boxes : int
            Boxes at most.

        Returns
        -------
        numpy.ndarray
            ``(N, 2, 2)`` rectangles.
        """
        if width in self._cover:
            return self._cover[width]
        Q = self.map.limits[None].copy()
        done = np.empty((0,) + Q.shape[1:])
        while len(Q):
            R = self.rectangles(Q)
            wide = np.max(R[:, :, 1] - R[:, :, 0], axis=1) > width
            done, Q = np.concatenate([done, Q[~wide]]), Q[wide]
            if not len(Q) or len(done) + 2 * len(Q) > max_boxes:
                break
            J = self.map.jacobian_enclosure(Q)
            effect = np.zeros(Q.shape[:2])
            for row in J:
                for j, (lo, hi) in enumerate(row):
                    slope = np.nan_to_num(np.maximum(np.abs(lo), np.abs(hi)), nan=np.inf)
                    effect[:, j] += slope * (Q[:, j, 1] - Q[:, j, 0])
            children, ok = halves(Q, np.argmax(effect, axis=1))
            done = np.concatenate([done, Q[~ok]])
            Q = children.reshape(-1, 2, *Q.shape[1:])[ok].reshape(-1, *Q.shape[1:])
        self._cover[width] = self.rectangles(np.concatenate([done, Q]))
        return self._cover[width]

    def outside(self, r0, r1, z0, z1, width: float, tolerance: float = DEFAULT.reach_tolerance,
                chunk: int = 2_000_000) -> np.ndarray:
        """Mask of the rectangles ``[r0, r1] x [z0, z1]`` (arrays broadcast together) proved outside the section
        by the distance from the elbow (class docstring): the squared distance from each to every rectangle of
        :meth:`cover` (at ``width``), bounded below with outward rounding, exceeds ``H_E`` (sought within
        ``tolerance`` times ``width`` times the greatest distance, as :meth:`ShoulderReach.outside`).

        Parameters
        ----------
        r0, r1, z0, z1 : numpy.ndarray
            The rectangles' edges.
        width : float
            The width the tolerance and the cover are counted in (a cell's, or a piece's).
        tolerance : float
            The tolerance, in widths.
        chunk : int
            Rectangle-and-cover pairs compared at once.

        Returns
        -------
        numpy.ndarray
            Booleans of the broadcast shape.
        """
        root = self.distance.enclose(self.distance.map.limits[None])[1][0]
        bound = self.distance.bound(tolerance * width * math.sqrt(max(root, 0.0)))
        shape = np.broadcast_shapes(*(np.shape(x) for x in (r0, r1, z0, z1)))
        r0, r1, z0, z1 = (np.broadcast_to(x, shape).ravel() for x in (r0, r1, z0, z1))
        E = self.cover(width)
        out = np.zeros(len(r0), dtype=bool)
        step = max(1, chunk // max(1, len(E)))
        a, b, c, d = E[None, :, 0, 0], E[None, :, 0, 1], E[None, :, 1, 0], E[None, :, 1, 1]
        with np.errstate(all="ignore"):
            for s in range(0, len(r0), step):
                R0, R1, Z0, Z1 = (x[s:s + step, None] for x in (r0, r1, z0, z1))
                # Lower bounds only (the lower ends of arith.sub and arith.add, without their upper ends)
                dr = np.maximum(0.0, np.maximum(arith.down(R0 - b), arith.down(a - R1)))
                dz = np.maximum(0.0, np.maximum(arith.down(Z0 - d), arith.down(c - Z1)))
                near = arith.down(arith.sqr((dr, dr))[0] + arith.sqr((dz, dz))[0])
                out[s:s + step] = np.min(np.where(np.isnan(near), -np.inf, near), axis=1) > bound
        return out.reshape(shape)


    def within(self, r0, r1, z0, z1, width: float) -> np.ndarray:
        """Mask of the rectangles (arrays of one shape) every piece of which :meth:`outside` would leave: some
        rectangle of the cover lies within ``sqrt(H_E)`` of all of it (the farthest pair of points, floats).
        Only a filter of where the proofs are tried (a rectangle it passes is kept undecided).

        Parameters
        ----------
        r0, r1, z0, z1 : numpy.ndarray
            The rectangles' edges, ``(N,)``.
        width : float
            As for :meth:`outside`.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` booleans.
        """
        bound = self.distance.bound(DEFAULT.reach_tolerance * width * math.sqrt(max(
            self.distance.enclose(self.distance.map.limits[None])[1][0], 0.0)))
        E = self.cover(width)
        a, b, c, d = E[None, :, 0, 0], E[None, :, 0, 1], E[None, :, 1, 0], E[None, :, 1, 1]
        out = np.zeros(len(r0), dtype=bool)
        step = max(1, 2_000_000 // max(1, len(E)))
        with np.errstate(all="ignore"):
            for s in range(0, len(r0), step):
                R0, R1, Z0, Z1 = (np.asarray(x)[s:s + step, None] for x in (r0, r1, z0, z1))
                dr, dz = np.maximum(R1 - a, b - R0), np.maximum(Z1 - c, d - Z0)
                out[s:s + step] = np.min(dr * dr + dz * dz, axis=1) < bound
        return out


def elbow_reach(model) -> ElbowReach | None:
    """The :class:`ElbowReach` of a turned arm (:func:`turned`), or None: no shoulder, no joint after it whose
    axis misses the shoulder, an elbow that moves with ``q_1`` at ``theta_1 = 0`` (impossible for the structure
    of :func:`turned`, checked all the same), or a distance that moves with no joint.

    Parameters
    ----------
    model : ReachModel
        The robot's reach model (its first joint a turn, :func:`first_joint_turn`).

    Returns
    -------
    ElbowReach or None
        The bound, or None.
    """
    turn = first_joint_turn(model)
    if turn is None or len(model.joints) < 3:
        return None
    robot = model.robot
    q1, theta, slope = turn
    at_zero = {q1: -theta.subs(q1, 0) / slope}
    B = first_frame(robot, model.parameters)
    R, t = B[:3, :3], B[:3, 3]
    shoulder = model.joints[1]
    # The walk of shoulder_distance from the shoulder: the first row whose joint moves S is the elbow's.
    frame = shoulder + (robot.convention == "modified")
    joints = set(robot.q)
    s = sp.zeros(3, 1)
    while frame < robot.n:
        inverse = inverse_transform(robot.substitute(robot.row_matrix(frame + 1), model.parameters))
        moved = (inverse[:3, :3] * s + inverse[:3, 3]).applyfunc(sp.simplify)
        if any(e.free_symbols & joints for e in moved):
            break
        s, frame = moved, frame + 1
    elbow = frame - (robot.convention == "modified")
    if frame >= robot.n or elbow <= shoulder:
        return None
    origin = robot.substitute(robot._parameter_twists(elbow)["theta"][2], model.parameters)
    E = [simplified(e) for e in (R.T * (sp.Matrix(origin) - t)).subs(at_zero)]
    point_vars = [q for q in model.variables[1:] if any(q in e.free_symbols for e in E)]
    if q1 in set().union(*(e.free_symbols for e in E)) or not point_vars:
        return None
    h, variables = shoulder_distance(robot, model.parameters, elbow)
    if not variables or any(q not in model.variables for q in variables):
        return None
    rows = [model.variables.index(q) for q in variables]
    distance = ShoulderReach(h, variables, [model.exact_limits[r] for r in rows], model.periodic[rows], (0, 0))
    prow = [model.variables.index(q) for q in point_vars]
    return ElbowReach(E, point_vars, [model.exact_limits[r] for r in prow], model.periodic[prow], distance)


def to_first_frame(inverse, X: np.ndarray) -> np.ndarray:
    """Boxes enclosing ``B^-1`` of the world boxes ``X`` (outward-rounded; ``X`` itself without ``B``).

    Parameters
    ----------
    inverse : tuple or None
        ``B^-1`` as :attr:`Turned.inverse` holds it; None for the identity.
    X : numpy.ndarray
        ``(N, 3, 2)`` world boxes.

    Returns
    -------
    numpy.ndarray
        ``(N, 3, 2)`` boxes in the frame of the first joint (``X`` itself when ``inverse`` is None).
    """
    if inverse is None:
        return X
    rows, back = inverse
    out = np.empty_like(X)
    with np.errstate(all="ignore"):
        for i in range(3):
            acc = (np.full(len(X), back[i][0]), np.full(len(X), back[i][1]))
            for j in range(3):
                if rows[i][j] != (0.0, 0.0):
                    acc = arith.add(acc, arith.mul(rows[i][j], (X[:, j, 0], X[:, j, 1])))
            out[:, i, 0], out[:, i, 1] = acc
    return out


class TurnedTest:
    """Classify world boxes of ``(x, y, z)`` from a paving of the section (module docstring).

    Called with ``(N, 3, 2)`` boxes, it returns the masks ``(is_in, is_out)``: proved inner (only when ``q_1``
    turns fully), proved outer (never both).

    Parameters
    ----------
    plan : Turned
        The structure.
    grid : CellGrid
        The grid of the section ``(rho, z)``.
    classes : numpy.ndarray
        The verdict code of each cell of ``grid``.
    """

    def __init__(self, plan: Turned, grid, classes):
        self.plan, self.grid = plan, grid
        self.inside = grid.prefix(classes, INNER)
        self.outside = grid.prefix(classes, OUTER)

    def rectangles(self, X: np.ndarray) -> np.ndarray:
        """``(N, 2, 2)`` rectangles of ``(rho, z)`` holding the points of the world boxes ``X``.

        Parameters
        ----------
        X : numpy.ndarray
            ``(N, 3, 2)`` world boxes.

        Returns
        -------
        numpy.ndarray
            ``(N, 2, 2)`` rectangles, outward-rounded.
        """
        F = to_first_frame(self.plan.inverse, X)
        with np.errstate(all="ignore"):
            r2 = arith.add(arith.sqr((F[:, 0, 0], F[:, 0, 1])), arith.sqr((F[:, 1, 0], F[:, 1, 1])))
            # x^2 + y^2 >= 0: clipping the lower bound is exact (a box touching the axis rounds 0 + 0 down to
            # -5e-324, whose root would be NaN and the box never classified)
            rho = arith.sqrt((np.maximum(r2[0], 0.0), r2[1]))
        return np.stack([np.stack(rho, axis=1), F[:, 2]], axis=1)

    def __call__(self, X: np.ndarray):
        rect = self.rectangles(X)
        finite = np.isfinite(rect).all(axis=(1, 2))
        inner = finite & self.grid.all_in_class(self.inside, rect, outside_counts=False)
        if not self.plan.full:
            inner[:] = False
        outer = finite & self.grid.all_in_class(self.outside, rect, outside_counts=True)
        return inner, outer & ~inner


@dataclass(frozen=True)
class Pieces:
    """Pieces of undecided cells of a section's grid proved inside (``inner``) or outside (``outer``) the
    section: ``(N, 2, 2)`` rectangles of ``(rho, z)``, each a quarter of a cell or of a piece (halved along both
    axes at float midpoints), so that they overlap on edges only and lie in cells left undecided.

    Parameters
    ----------
    inner : numpy.ndarray
        ``(N, 2, 2)`` pieces proved inside.
    outer : numpy.ndarray
        ``(M, 2, 2)`` pieces proved outside.
    """

    inner: np.ndarray
    outer: np.ndarray

    @classmethod
    def none(cls) -> Pieces:
        """No piece.

        Returns
        -------
        Pieces
            Two empty ``(0, 2, 2)`` arrays.
        """
        return cls(np.empty((0, 2, 2)), np.empty((0, 2, 2)))


def in_chunks(items: np.ndarray, size: int, budget, work, pace: list, weight: int = 1) -> str:
    """``work(chunk)`` on ``items`` in chunks of about ``size``; before each chunk ``budget(ahead)`` is asked
    with the seconds it is expected to take: ``weight`` (tests per item) times the chunk's length times
    ``pace[0]``, the seconds per test of the last chunk (shared by every call of one run, so that a first
    chunk is expected to take its time too).  Returns why it stopped.

    Parameters
    ----------
    items : numpy.ndarray
        What ``work`` is called on, in order.
    size : int
        About this many items in one chunk (``numpy.array_split`` into ``ceil(len(items) / size)`` chunks).
    budget : callable
        ``budget(ahead)``: a stop reason, or ``""`` to go on.
    work : callable
        ``work(chunk)``.
    pace : list
        ``[seconds per test]``, updated after each chunk.
    weight : int
        Tests per item.

    Returns
    -------
    str
        ``budget``'s reason, or ``""`` when every chunk ran.
    """
    for part in np.array_split(items, max(1, math.ceil(len(items) / size))):
        stopped = budget(pace[0] * weight * len(part))
        if stopped:
            return stopped
        start = time.perf_counter()
        work(part)
        pace[0] = (time.perf_counter() - start) / max(1, weight * len(part))
    return ""


@contextmanager
def section_bar(progress: bool | None):
    """``show(share decided, evaluated)`` for :func:`section_paving` on a progress bar of its own
    (:mod:`workspace_sym.progress`): the share of the section's cells decided.

    Parameters
    ----------
    progress : bool or None
        Draw the bar (None: on an interactive output, once the section has lasted a moment).

    Yields
    ------
    callable
        ``show(share, evaluated)``.
    """
    with progress_bar(progress, total=100.0, desc="reach: section", unit="%",
                      bar_format="{desc}: {percentage:5.1f}% of the cells decided{postfix} |{bar}| "
                                 "[{elapsed}]") as bar:
        def show(share, evaluated):
            bar.set_postfix_str(f"{evaluated} boxes", refresh=False)
            bar.update(100.0 * share - bar.n)

        yield show


def section_paving(image: RadialMap, width: float, *, budget=None, show=None, tuning: Tuning = DEFAULT,
                   rehearse=None, depth: int = 1, seconds_left=None):
    """Classify the cells of a grid of the given width over the section, for sections moved by three joints
    or more (whose critical sets are too costly to cover), in four stages, each proof standing alone:

    1. the cells hit by sampled configurations are each proved inside from their sample (Krawczyk), the
       farthest from the axis first (they weigh the most in the volume); then, when the map has a
       :class:`ShoulderReach`, the cells beyond the greatest distance from the shoulder are outside;
    2. blocks of cells, from the whole grid down to single cells (halved along their longer side), carry the
       joint boxes whose enclosures meet them (:func:`~workspace_sym.interval.image.distribute`); a block
       left without joint boxes is outside the section, a block proved by the Krawczyk test from its first
       joint box's centre is inside (with ``seconds_left``, a callable giving the seconds the section has
       left, this stage takes ``tuning.blocks_weight`` times the share of the undecided volume in cells no sample
       reached, the others being never outside, and ``tuning.blocks_share`` at most);
    3. the sampled cells still undecided are proved from a second sample of theirs;
    4. every cell still undecided is refined into pieces (:func:`_refine`): halved along both axes, each piece
       proved on its own, inside by the Krawczyk test from the cell's sample (the sample nearest the cell's
       centre for a cell no sample reached) or outside by the shoulder's bound, and only the pieces left
       undecided halved again, level after level up to ``depth`` (the Krawczyk test of a whole cell fails
       where the Jacobian varies too much over the joint box it needs: near the section's boundary, a fold
       of the map, the undecided band is as thin as the pieces there).  A cell all of whose pieces are
       proved inside (outside) is inner (outer); the proved pieces of the other cells are returned apart.

    Returns ``(grid, classes, evaluated, stopped, pieces)``: the first four as
    :func:`~workspace_sym.interval.image.critical_paving`, except that the cells classified when a budget stops
    the run keep their (proved) class; ``pieces`` the :class:`Pieces` of stage 4, for :func:`turned_volume`.
    ``budget(evaluated, ahead=seconds)`` is asked before each step with the time the step is expected to
    take; ``show(share decided, evaluated)`` after each; ``rehearse(grid, classes)`` is called once after
    stage 1 (the caller measures there what it must keep time for).

    Parameters
    ----------
    image : RadialMap
        The section map.
    width : float
        The cells' width.
    budget : callable, optional
        ``budget(evaluated, ahead=seconds)``: a stop reason, or ``""`` to go on; None: no budget.
    show : callable, optional
        ``show(share decided, evaluated)``.
    tuning : Tuning
        ``section_samples``, ``section_chunk``, ``section_pairs``, ``reach_tolerance``, ``blocks_share``,
        ``blocks_weight``.
    rehearse : callable, optional
        ``rehearse(grid, classes)``, called once after stage 1.
    depth : int
        The levels of pieces of stage 4 (1: halved once).
    seconds_left : callable, optional
        The seconds the section has left; with it, stage 2 takes its share of them.

    Returns
    -------
    tuple
        ``(grid, classes, evaluated, stopped, pieces)``, as above.
    """
    budget = budget or (lambda evaluated, ahead=0.0: "")
    show = show or (lambda share, evaluated: None)
    root = image.enclose(image.limits[None])[0]
    grid = CellGrid(root, width)
    classes = np.full(grid.shape, UNDECIDED, dtype=np.int8)
    count = [0]                 # boxes evaluated

    def ask(ahead):
        return budget(count[0], ahead=ahead)

    def decided():
        return float(np.mean(classes != UNDECIDED))

    # Stage 1: cells hit by sampled configurations, each proved inside from its sample (Krawczyk).
    rng = np.random.default_rng(0)
    q = image.random_configurations(min(tuning.section_samples, 20 * classes.size), rng)
    p = image.position_float(q)
    first, _ = grid.span(np.repeat(p[:, :, None], 2, axis=2))
    index, row = np.unique(first, axis=0, return_index=True)
    seeds = q[row]
    # A second seed per cell, its last sample (often on another branch of the inverse kinematics, where the
    # Krawczyk test may succeed when it failed from the first: a test for one, where pieces cost four).
    last = len(first) - 1 - np.unique(first[::-1], axis=0, return_index=True)[1]
    others = q[last]

    def prove(part, seeds=seeds):
        count[0] += len(part)
        inside = _prove_cells(image, grid.cells(index[part]), seeds[part], 0)
        classes[tuple(index[part][inside].T)] = INNER
        show(decided(), count[0])

    def undecided():            # the farthest from the axis first: they weigh the most in the volume (Pappus)
        return np.nonzero(classes[tuple(index.T)] == UNDECIDED)[0][::-1]

    pace = [0.0]                # seconds per Krawczyk test of the last chunk
    stopped = in_chunks(np.arange(len(index))[::-1], tuning.section_chunk, ask, prove, pace)
    if stopped:
        return grid, classes, count[0], stopped, Pieces.none()
    reach = getattr(image, "reach", None)
    if reach is not None:       # the cells beyond the greatest distance from the shoulder, in one proof
        top = math.sqrt(max(reach.enclose(reach.map.limits[None])[1][0], 0.0))
        far = reach.far_cells(grid, reach.bound(tuning.reach_tolerance * width * top))
        classes[far & (classes == UNDECIDED)] = OUTER
        show(decided(), count[0])
    if rehearse is not None:
        rehearse(grid, classes)
    # Stage 2: blocks of cells, with a share of the time left (their last generations cost the most and decide
    # the least: the cells near the section's boundary, whose joint boxes are many).
    # That share is blocks_weight times the part of the undecided volume (Pappus) that blocks can decide, at
    # most blocks_share: the cells no sample reached (the others are proved inside by the later stages, or never
    # outside).
    hit = np.zeros(grid.shape, dtype=np.int8)
    hit[tuple(index.T)] = 1
    blocks_budget = budget
    if seconds_left is not None:
        e0 = np.maximum(grid.edges[0], 0.0)
        open_cells = (classes == UNDECIDED) * (e0[1:] ** 2 - e0[:-1] ** 2)[:, None]
        total = float(open_cells.sum())
        share = min(tuning.blocks_share,
                    tuning.blocks_weight * (float(open_cells[hit == 0].sum()) / total if total > 0 else 1.0))
        end = time.perf_counter() + share * seconds_left()

        def blocks_budget(evaluated, ahead=0.0):
            late = time.perf_counter() + ahead > end
            return budget(evaluated, ahead=ahead) or ("blocks share" if late else "")

    count[0], stopped = blocks(image, grid, classes, grid.prefix(hit, 1), blocks_budget, show, tuning.section_pairs,
                                count[0])
    stopped = "" if stopped == "blocks share" else stopped
    # Then the sampled cells still undecided, from their second seed; then every undecided cell in pieces.
    if not stopped:
        stopped = in_chunks(undecided(), tuning.section_chunk, ask, lambda part: prove(part, others), pace)
    pieces = Pieces.none()
    if not stopped:
        # The seed of a piece: its cell's first sample (the cell's own test, in pieces), or for a cell no sample
        # reached, the sample whose point is nearest the cell's centre.
        from scipy.spatial import cKDTree  # scipy is imported where it is used: not with the package

        seed_of = q[cKDTree(p).query(grid.cells(np.argwhere(np.ones(grid.shape, dtype=bool))).mean(axis=2))[1]]
        seed_of = seed_of.reshape(grid.shape + (q.shape[1],))
        seed_of[tuple(index.T)] = seeds
        far_pieces = None
        if reach is not None:
            def far_pieces(T, level):   # the bound sought within a tenth of a piece in distance, as for cells
                return reach.far_boxes(T, reach.bound(tuning.reach_tolerance * width / 2 ** level * top))
        pieces, stopped = _refine(image, grid, classes, seed_of, far_pieces, depth, ask, pace, count,
                                  tuning.section_chunk)
        show(decided(), count[0])
    return grid, classes, count[0], stopped, pieces


def _refine(image, grid, classes, seed_of, far, depth: int, ask, pace, count, chunk: int):
    """Stage 4 of :func:`section_paving`: ``(pieces, stopped)``.  Every undecided cell is halved along both
    axes, level after level up to ``depth``; a piece is outside when ``far(pieces, level)`` says so (the
    shoulder's distance bound), inside when the Krawczyk test from its cell's seed ``seed_of[i, j]`` proves it;
    only the pieces left undecided are halved again, the farthest from the axis first.  A cell whose pieces are all
    inside (outside) becomes inner (outer) in ``classes``; the proved pieces of the others are returned
    (:class:`Pieces`).  ``count[0]`` counts the tests."""
    cells = np.argwhere(classes == UNDECIDED)
    P, owner = grid.cells(cells), np.arange(len(cells))
    share = np.zeros((2, len(cells)))                   # share of each cell's area proved inside, outside
    found: list[list] = [[], []]                        # pieces proved inside, outside: (rectangles, owners)
    stopped = ""
    for level in range(1, depth + 1):
        if not len(P) or stopped:
            break
        P, owner = split_every_axis(P), np.tile(owner, 4)
        order = np.argsort(-P[:, 0, 1], kind="stable")
        P, owner = P[order], owner[order]
        open_ = np.ones(len(P), dtype=bool)

        def work(part, P=P, owner=owner, open_=open_, level=level):
            count[0] += len(part)
            T = P[part]
            out = far(T, level) if far is not None else np.zeros(len(T), dtype=bool)
            inside = np.zeros(len(T), dtype=bool)
            rest = np.nonzero(~out)[0]
            if len(rest):
                inside[rest] = image.prove_inside(T[rest], seed_of[tuple(cells[owner[part[rest]]].T)])
            for k, mask in enumerate((inside, out)):
                found[k].append((T[mask], owner[part[mask]]))
                np.add.at(share[k], owner[part[mask]], 0.25 ** level)
            open_[part[inside | out]] = False

        stopped = in_chunks(np.arange(len(P)), chunk, ask, work, pace)
        P, owner = P[open_], owner[open_]
    whole = [share[k] == 1.0 for k in range(2)]         # sums of powers of 1/4 below 2^-52 apart: exact
    classes[tuple(cells[whole[0]].T)] = INNER
    classes[tuple(cells[whole[1]].T)] = OUTER
    kept = []
    for k in range(2):
        rects = np.concatenate([r for r, _ in found[k]]) if found[k] else np.empty((0, 2, 2))
        owners = np.concatenate([o for _, o in found[k]]) if found[k] else np.empty(0, dtype=int)
        kept.append(rects[~(whole[0] | whole[1])[owners]])
    return Pieces(*kept), stopped


def _prove_cells(image, cells: np.ndarray, seeds: np.ndarray, level: int) -> np.ndarray:
    """Mask of the cells proved inside the image, each cut into ``4^level`` pieces (halved along both axes
    ``level`` times), every one of which is proved by the Krawczyk test from the cell's seed."""
    pieces, owner = cells, np.arange(len(cells))
    for _ in range(level):
        pieces, owner = split_every_axis(pieces), np.tile(owner, 4)
    proved = image.prove_inside(pieces, seeds[owner])
    return np.bincount(owner[~proved], minlength=len(cells)) == 0


def blocks(image, grid, classes, reached, budget, show, max_pairs, evaluated):
    """Stage 2 of :func:`section_paving`: ``(evaluated, stopped)``; ``classes`` is updated in place;
    ``reached`` is the summed-area table of the cells holding the position of a sampled configuration.

    Blocks of cells, from the whole grid down to single cells, carry the joint boxes whose enclosures meet them; a
    block that holds no sampled position and is left without joint boxes is outside, a block proved by the
    Krawczyk test from its first joint box's centre is inside.

    Parameters
    ----------
    image : ImageMap or RadialMap
        The section map.
    grid : CellGrid
        The section's grid.
    classes : numpy.ndarray
        The verdict code of each cell, updated in place (blocks already decided are skipped).
    reached : numpy.ndarray
        The summed-area table (:meth:`~workspace_sym.interval.image.CellGrid.prefix`).
    budget : callable
        ``budget(evaluated, ahead=seconds)``, asked before each generation of blocks.
    show : callable
        ``show(share decided, evaluated)``, after each generation.
    max_pairs : int
        About this many (block, joint box) pairs in one generation (64 per block at least).
    evaluated : int
        Boxes evaluated before.

    Returns
    -------
    evaluated : int
        The count, with the blocks of this call.
    stopped : str
        Why ``budget`` stopped it (``""``: every block decided or cut down to single cells).
    """
    proved = grid.prefix(classes, INNER) + grid.prefix(classes, OUTER)        # decided already
    blocks = np.array([[0, grid.shape[0], 0, grid.shape[1]]])
    Q = image.limits[None].copy()
    owner = np.zeros(1, dtype=int)
    stopped = ""
    e0, e1 = grid.edges
    last = 0.0                  # seconds of the last generation; the next is expected to take about twice
    while len(blocks):
        stopped = budget(evaluated, ahead=2 * last)
        if stopped:
            break
        start = time.perf_counter()
        evaluated += len(blocks)
        T = np.stack([np.stack([e0[blocks[:, 0]], e0[blocks[:, 1]]], axis=1),
                      np.stack([e1[blocks[:, 2]], e1[blocks[:, 3]]], axis=1)], axis=1)
        # A block whose cells are all decided already is left.
        i0, i1, j0, j1 = blocks.T
        done = proved[i1, j1] - proved[i0, j1] - proved[i1, j0] + proved[i0, j0] == (i1 - i0) * (j1 - j0)
        if done.any():
            keep = ~done[owner]
            new_index = np.cumsum(~done) - 1
            blocks, T, Q, owner = blocks[~done], T[~done], Q[keep], new_index[owner[keep]]
            if not len(blocks):
                break
        # A block holding the position of a sampled configuration is not outside: its joint boxes go to its
        # halves unrefined (refining them cannot prove anything there and costs the most).
        i0, i1, j0, j1 = blocks.T
        test = reached[i1, j1] - reached[i0, j1] - reached[i1, j0] + reached[i0, j0] == 0
        mine = test[owner]
        index = np.cumsum(test) - 1
        cap = np.full(int(test.sum()), max(64, max_pairs // max(1, int(test.sum()))))
        Qt, ot = distribute(image, T[test], Q[mine], index[owner[mine]], cap)
        Q, owner = np.concatenate([Q[~mine], Qt]), np.concatenate([owner[~mine], np.nonzero(test)[0][ot]])
        count = np.bincount(owner, minlength=len(T))
        verdict = np.full(len(T), UNDECIDED, dtype=np.int8)
        verdict[test & (count == 0)] = OUTER
        live, first = np.unique(owner, return_index=True)
        if len(live):
            inside = image.prove_inside(T[live], Q[first].mean(axis=2))
            verdict[live[inside]] = INNER
        for b in np.nonzero(verdict != UNDECIDED)[0]:
            i0, i1, j0, j1 = blocks[b]
            classes[i0:i1, j0:j1] = verdict[b]
        cells = (blocks[:, 1] - blocks[:, 0]) * (blocks[:, 3] - blocks[:, 2])
        split = (verdict == UNDECIDED) & (cells > 1)
        # Children: halve the longer side in index space.
        rows = blocks[split]
        wide = (rows[:, 1] - rows[:, 0]) >= (rows[:, 3] - rows[:, 2])
        mid_i = (rows[:, 0] + rows[:, 1]) // 2
        mid_j = (rows[:, 2] + rows[:, 3]) // 2
        left, right = rows.copy(), rows.copy()
        left[wide, 1], right[wide, 0] = mid_i[wide], mid_i[wide]
        left[~wide, 3], right[~wide, 2] = mid_j[~wide], mid_j[~wide]
        new_index = np.full(len(T), -1)
        new_index[split] = np.arange(split.sum())
        keep = new_index[owner] >= 0
        Q, base = Q[keep], new_index[owner[keep]]
        blocks = np.stack([left, right], axis=1).reshape(-1, 4)
        Q, owner = np.concatenate([Q, Q]), np.concatenate([2 * base, 2 * base + 1])
        show(float(np.mean(classes != UNDECIDED)), evaluated)
        last = time.perf_counter() - start
    return evaluated, stopped


def solid_volumes(r0, r1, z0, z1) -> tuple[np.ndarray, np.ndarray]:
    """Enclosures ``(lo, hi)`` of the volumes ``pi (r1^2 - r0^2) (z1 - z0)`` of the rectangles ``[r0, r1] x
    [z0, z1]`` of ``(rho, z)`` turned through a full circle (``rho`` clipped at 0; outward-rounded).

    Parameters
    ----------
    r0, r1, z0, z1 : numpy.ndarray
        The rectangles' edges.

    Returns
    -------
    lo : numpy.ndarray
        Lower bounds of the volumes.
    hi : numpy.ndarray
        Upper bounds.
    """
    pi = numpy_constant(sp.pi)
    r0, r1 = np.maximum(r0, 0.0), np.maximum(r1, 0.0)
    with np.errstate(all="ignore"):
        ring = arith.sub(arith.sqr((r1, r1)), arith.sqr((r0, r0)))
        return arith.mul(arith.mul(pi, ring), arith.sub((z1, z1), (z0, z0)))


def turned_volume(grid: CellGrid, classes: np.ndarray, pieces: Pieces | None = None) -> tuple[float, float]:
    """A proved bracket of the volume of the solid of revolution of the section ``S`` from its paving
    (Pappus): the cell ``[r0, r1] x [z0, z1]`` (``rho`` clipped at 0) turns into ``pi (r1^2 - r0^2)
    (z1 - z0)``, enclosed in outward-rounded interval arithmetic; the solid of the cells proved inside
    lies in it (lower bound: their volumes rounded down, summed exactly, rounded down once), and it lies
    in the solid of the cells not proved outside (upper bound: rounded up), since the cells cover the
    enclosure of ``S`` and overlap on edges only.  With ``pieces`` (:class:`Pieces` of undecided cells), the
    solids of the inner pieces add to the lower bound (rounded down) and those of the outer pieces are taken
    from the upper bound (rounded down, so the difference is rounded up): the volume is additive over
    rectangles overlapping on edges only.

    Example: one cell ``[0, 1] x [0, 1]`` proved inside, one ``[1, 2] x [0, 1]`` undecided: ``[pi, 4 pi]``;
    with the piece ``[1, 1.5] x [0, 0.5]`` of the second proved inside and ``[1.5, 2] x [0.5, 1]`` outside:
    ``[pi + 5 pi / 8, 4 pi - 7 pi / 8]``.

    Parameters
    ----------
    grid : CellGrid
        The section's grid.
    classes : numpy.ndarray
        The verdict code of each cell.
    pieces : Pieces, optional
        Pieces of undecided cells proved inside or outside.

    Returns
    -------
    lo : float
        A lower bound of the volume.
    hi : float
        An upper bound of the volume.

    Examples
    --------
    >>> g = CellGrid(np.array([[0.5, 1.5], [0.5, 1.5]]), 1.0)          # cell edges -1, 0, 1, 2, 3
    >>> c = np.full(g.shape, OUTER, dtype=np.int8)
    >>> c[1, 1], c[2, 1] = INNER, UNDECIDED                   # cells [0, 1] and [1, 2] of rho, [0, 1] of z
    >>> lo, hi = turned_volume(g, c)
    >>> bool(lo <= np.pi <= lo + 1e-14), bool(4 * np.pi <= hi <= 4 * np.pi + 1e-13)
    (True, True)
    >>> lo, hi = turned_volume(g, c, Pieces(np.array([[[1, 1.5], [0, 0.5]]]), np.array([[[1.5, 2], [0.5, 1]]])))
    >>> bool(lo <= 13 * np.pi / 8 <= lo + 1e-14), bool(25 * np.pi / 8 <= hi <= 25 * np.pi / 8 + 1e-13)
    (True, True)
    """
    e0, e1 = grid.edges

    def cells(value):
        at = np.argwhere(classes == value)
        return np.stack([np.stack([e0[at[:, 0]], e0[at[:, 0] + 1]], axis=1),
                         np.stack([e1[at[:, 1]], e1[at[:, 1] + 1]], axis=1)], axis=1)

    pieces = pieces or Pieces.none()
    inner, undecided = _ring_volumes(cells(INNER)), _ring_volumes(cells(UNDECIDED))
    low = ExactSum.of(inner[0])
    low.add(_ring_volumes(pieces.inner)[0])
    high = ExactSum.of(inner[1])
    high.add(undecided[1])
    high.add(-_ring_volumes(pieces.outer)[0])
    return low.value_down, high.value_up


def _ring_volumes(T: np.ndarray):
    """:func:`solid_volumes` of the rectangles ``T`` of ``(rho, z)`` (``(N, 2, 2)``)."""
    return solid_volumes(T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1])
