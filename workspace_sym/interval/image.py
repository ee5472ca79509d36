"""Certified image of a box of joints under a smooth map: which points are reached, which are not.

:class:`ImageMap` holds a map ``p = f(q)`` from a box of joint values ``Q``
(joints the map is periodic in may be marked so) to ``R^m``, with its interval enclosures
(outward-rounded numpy engine), float evaluators, and two proofs:

* **outer**, :meth:`ImageMap.prove_outside`: joint boxes covering every
  configuration whose position may lie in a task box are refined until their
  enclosures miss it; a task box left without joint boxes is unreachable.
* **inner**, :meth:`ImageMap.prove_inside`: Goldsztejn and Jaulin,
  "Inner approximation of the range of vector-valued functions" (Reliable
  Computing 14, 2010).  With ``m`` joints ``u`` chosen where the Jacobian is
  best conditioned and the others fixed at float values within their limits,
  for a joint box ``U`` inside the limits, a point ``u0`` in it and a float
  matrix ``C``, if ``K = u0 - C (f(u0) - T) + (I - C J(U)) (U - u0)`` lies in
  the interior of ``U`` (outward-rounded, ``J(U)`` an interval enclosure of
  the Jacobian), then for every ``y`` in the task box ``T`` the Krawczyk
  operator of ``f(u) - y`` maps ``U`` into its interior, so ``f(u) = y`` has
  a solution in ``U``: ``T`` is reached.

For a map into the plane or into space (``m = 2`` or ``3``), :func:`critical_paving` decides whole
regions at once from one theorem:

    If ``y`` is on the boundary of ``f(Q)``, every configuration ``q`` with
    ``f(q) = y`` lies in the critical set ``Sigma``: on the face ``F`` of
    ``Q`` whose relative interior holds ``q``, the derivative does not map
    the tangent cone of ``Q`` at ``q`` onto ``R^m``.

(Where the derivative maps the tangent cone onto ``R^m``, ``f`` maps a
neighbourhood of ``q`` in ``Q`` onto a neighbourhood of ``y``.)  So a
connected set ``K`` of task space that misses ``f(Sigma)`` misses the
boundary of ``f(Q)`` and lies either inside ``f(Q)`` or outside it: one proof
for one point of ``K`` decides all of ``K``.  ``Sigma`` is covered by joint
boxes of each face: a box is dropped when an ``m x m`` minor of its face's
free columns is proved non-zero on it (the face has ``m`` free joints or
more), or, on a face with ``m - 1`` free joints (an edge in the plane, a
2-face in space), when two limited joints are proved to push to opposite
sides of the hyperplane the free columns span; every other box is kept.
Their enclosures are marked on a grid of task cells; the unmarked cells are
split into components connected through the cells' faces (4-connected in the
plane, 6-connected in space); a component touching the grid's margin (outside
the enclosure of ``f(Q)``) is outside, any other is decided by proving one of
its cells inside (Krawczyk) or outside (joint boxes).  Marked cells are then
tried one by one with the Krawczyk test.
"""

from __future__ import annotations

import inspect
import itertools
import math
import time

import numpy as np
import sympy as sp

from ..errors import CoverStopped, CoverTooLarge
from ..expressions import as_sympy
from . import arith
from .boxes import halves
from .compiler import CompiledBatch, compile_batch, compile_expr
from .graph import numpy_constant
from .verdict import CODE, INSIDE, OUTSIDE, UNDECIDED

__all__ = ["ImageMap", "critical_paving", "CellGrid", "CoverTooLarge", "batch_enclosures"]
OUTSIDE_PAIRS = 20_000            # joint boxes a component's cell may hold while proved outside
MAX_COVER_BOXES = 4_000_000      # joint boxes of one face's cover in flight: more means a critical set of full
                                 # dimension (parallel joint axes, say); CoverTooLarge is raised
OUTSIDE_MIN_CELLS = 16            # smaller components are not proved outside
MINOR_SIMPLIFY_OPS = 300          # minors larger than this are compiled as expanded, not simplified


def _limit_floats(value) -> tuple[float, float]:
    """Two floats enclosing an exact joint limit (equal when it is a float)."""
    if isinstance(value, (int, float, np.floating)):
        return float(value), float(value)
    return numpy_constant(value)


class ImageMap:
    """A map from a joint box to ``R^m`` with what :func:`critical_paving` and the paving of
    :func:`workspace_sym.serial.reach` need.

    Parameters
    ----------
    expressions : sequence of sympy.Expr
        The ``m`` coordinates of ``f`` as SymPy expressions of ``variables``.
    variables : sequence of sympy.Symbol
        The ``k`` joint symbols.
    limits : sequence of pairs
        ``k`` pairs ``(lo, hi)``, exact (SymPy) or floats.  Enclosures use the limits rounded outward, the
        boxes of inner proofs the limits rounded inward.
    periodic : sequence of bool
        ``k`` booleans: the map is periodic in that joint with period
        ``hi - lo`` (its limits span exactly one period, so it has no limit faces
        and any value of it is allowed).  A joint turning through a full circle
        is periodic only when the map is (a joint in a coupled angle such as
        ``q2 + q1/2`` is not ``2 pi`` periodic).

    Raises
    ------
    ExpressionError
        For an expression with an operation the interval compiler does not support, or a limit that is not a
        real constant.
    """

    COMBOS_TRIED = 3       # choices of the m joints of the inner test tried per box, best-conditioned first
    INFLATIONS = 2         # epsilon-inflations of the Krawczyk box after a failed test (each a new test)
    CONTRACTIONS = 1       # Krawczyk contractions of a proof's box after the box K(U) itself

    def __init__(self, expressions, variables, limits, periodic):
        expressions = [as_sympy(e) for e in expressions]    # text is read, never evaluated
        self.variables = tuple(variables)
        self.m, self.k = len(expressions), len(self.variables)
        pairs = [(_limit_floats(lo), _limit_floats(hi)) for lo, hi in limits]
        # Outward limits for enclosures and limit faces, inward ones for the boxes of inner proofs.
        self.limits = np.array([(lo[0], hi[1]) for lo, hi in pairs], dtype=float)
        self.face_limits = np.array([(lo, hi) for lo, hi in pairs], dtype=float)       # (k, 2, 2)
        self.inner_limits = np.array([(lo[1], hi[0]) for lo, hi in pairs], dtype=float)
        self.periodic = np.array(periodic, dtype=bool)
        self.expressions = expressions
        self._position = compile_batch(expressions, self.variables)
        jac = [[sp.diff(e, q) for q in self.variables] for e in expressions]
        self._jacobian = [[compile_expr(entry, self.variables) for entry in row] for row in jac]
        self._columns: dict = {}        # the batches of the Jacobian's entries, by the columns asked for
        # Floats with common subexpressions shared (SymPy's cse reads a flat list, not a nested one): the
        # Panda's section Jacobian in 0.05 s a chunk of 50,000 configurations instead of 0.24 s.
        self._p_float = sp.lambdify([self.variables], expressions, modules="numpy", cse=True)
        self._j_float = sp.lambdify([self.variables], [entry for row in jac for entry in row], modules="numpy",
                                    cse=True)
        self._jac_symbolic = jac
        self._minors = None

    # -------------------------------------------------------------- interval enclosures
    def enclose(self, Q: np.ndarray) -> np.ndarray:
        """``(N, m, 2)`` enclosures of ``f`` over joint boxes ``Q`` (``(N, k, 2)``).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            ``(N, m, 2)``, rounded outward; a coordinate with no enclosure (NaN) is ``[-inf, inf]``.
        """
        return batch_enclosures(self._position, Q, self.k, self.m)

    def jacobian_enclosure(self, Q: np.ndarray, columns=None):
        """``J[i][j] = (lo, hi)`` arrays enclosing ``d f_i / d q_j`` over ``Q``; with ``columns``, only those
        columns are computed (the others are None).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.
        columns : iterable of int or None
            The joints whose columns are wanted (None: all).

        Returns
        -------
        list of list
            ``m`` rows of ``k`` entries: a ``(lo, hi)`` pair of ``(N,)`` arrays (NaN: no enclosure), or None.
        """
        X = [(Q[:, j, 0], Q[:, j, 1]) for j in range(self.k)]
        shape = (len(Q),)
        wanted = tuple(range(self.k)) if columns is None else tuple(sorted(set(int(j) for j in columns)))
        batch = self._columns.get(wanted)
        if batch is None:       # the entries of those columns, row by row, in one sweep
            batch = self._columns[wanted] = CompiledBatch([self._jacobian[i][j] for i in range(self.m)
                                                           for j in wanted])
        with np.errstate(all="ignore"):
            values = iter(batch(X))
            out: list[list] = [[None] * self.k for _ in range(self.m)]
            for i in range(self.m):
                for j in wanted:
                    out[i][j] = tuple(np.broadcast_to(v, shape) for v in next(values))
            return out

    @property
    def minors(self) -> dict:
        """The ``m x m`` minors ``det [J_c1, ..., J_cm]`` (columns ascending) of the Jacobian, compiled: for a
        map into the plane the ``2 x 2`` minors ``det [J_i, J_j]``, into space the ``3 x 3`` ones."""
        if self._minors is None:
            J = self._jac_symbolic
            out = {}
            for cols in itertools.combinations(range(self.k), self.m):
                # Division-free expansion of the determinant (a d - b c for m = 2).
                det = sp.expand(sp.Matrix([[J[r][c] for c in cols] for r in range(self.m)]).det(method="berkowitz"))
                if sp.count_ops(det) <= MINOR_SIMPLIFY_OPS:
                    short = sp.expand(sp.fu(det))          # products of sines and cosines to sums of angles
                    det = short if sp.count_ops(short) < sp.count_ops(det) else det
                out[cols] = compile_expr(det, self.variables)
            self._minors = out
        return self._minors

    def minor_enclosure(self, Q: np.ndarray, *columns: int):
        """Enclosure of ``det [J_c1, ..., J_cm]`` over ``Q`` for ``m`` distinct columns in any order (the sign
        of the permutation that sorts them is applied).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.
        *columns : int
            ``m`` distinct joint indices.

        Returns
        -------
        tuple of numpy.ndarray
            ``(lo, hi)``, each ``(N,)``.
        """
        X = [(Q[:, v, 0], Q[:, v, 1]) for v in range(self.k)]
        order = tuple(sorted(columns))
        f = self.minors[order]
        with np.errstate(all="ignore"):
            lo, hi = (np.broadcast_to(v, (len(Q),)) for v in f(X))
        return (lo, hi) if _parity(columns) == 0 else (-hi, -lo)

    # -------------------------------------------------------------- floats
    def position_float(self, q: np.ndarray) -> np.ndarray:
        """``(N, m)`` values of ``f`` at joint values ``q`` (``(N, k)``), in floats.

        Parameters
        ----------
        q : numpy.ndarray
            ``(N, k)`` joint values.

        Returns
        -------
        numpy.ndarray
            ``(N, m)`` positions (no proof: rounded as numpy rounds).
        """
        out = self._p_float(q.T)
        return np.stack([np.broadcast_to(np.asarray(v, dtype=float), (len(q),)) for v in out], axis=1)

    def jacobian_float(self, q: np.ndarray) -> np.ndarray:
        """``(N, m, k)`` Jacobians at ``q``, in floats.

        Parameters
        ----------
        q : numpy.ndarray
            ``(N, k)`` joint values.

        Returns
        -------
        numpy.ndarray
            ``(N, m, k)``: ``d f_i / d q_j`` at each configuration.
        """
        entries = self._j_float(q.T)
        flat = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (len(q),)) for v in entries], axis=1)
        return flat.reshape(len(q), self.m, self.k)

    def random_configurations(self, n: int, rng) -> np.ndarray:
        """Joint values drawn uniformly within the limits (rounded inward).

        Parameters
        ----------
        n : int
            Number of configurations.
        rng : numpy.random.Generator
            The source of the draws.

        Returns
        -------
        numpy.ndarray
            ``(n, k)`` joint values.
        """
        return rng.uniform(self.inner_limits[:, 0], self.inner_limits[:, 1], size=(n, self.k))

    # -------------------------------------------------------------- inner test
    def newton(self, targets: np.ndarray, seeds: np.ndarray, *, steps: int = 8):
        """Joint values near a solution of ``f(q) = target`` from each seed (least-squares Newton steps kept
        within the limits), and the mask of those whose residual is below ``1e-9`` times the reach.

        Parameters
        ----------
        targets : numpy.ndarray
            ``(N, m)`` points.
        seeds : numpy.ndarray
            ``(N, k)`` starting joint values.
        steps : int
            Newton steps (default 8).

        Returns
        -------
        q : numpy.ndarray
            ``(N, k)`` joint values after the steps (periodic joints wrapped into their period, the others
            clipped to their limits rounded inward).
        converged : numpy.ndarray of bool
            ``(N,)``: ``q`` is finite and ``|f(q) - target| <= 1e-9 (1 + max_i |target_i|)``, in floats (a
            hint, not a proof).
        """
        q = seeds.copy()
        with np.errstate(all="ignore"):
            for _ in range(steps):
                r = self.position_float(q) - targets
                J = self.jacobian_float(q)
                # Least-squares step J^T (J J^T)^-1 r (J is m x k with m <= k), lightly damped.
                JJ = np.einsum("nik,njk->nij", J, J) + 1e-14 * np.eye(self.m)
                step = np.einsum("nik,ni->nk", J, np.linalg.solve(JJ, r[:, :, None])[:, :, 0])
                q = q - step
                lo, hi = self.limits[:, 0], self.limits[:, 1]
                q = np.where(self.periodic, lo + np.remainder(q - lo, hi - lo),
                             np.clip(q, self.inner_limits[:, 0], self.inner_limits[:, 1]))
            residual = np.linalg.norm(self.position_float(q) - targets, axis=1)
        return q, np.isfinite(q).all(axis=1) & (residual <= 1e-9 * (1 + np.abs(targets).max(axis=1)))

    def prove_inside(self, T: np.ndarray, seeds: np.ndarray, *, newton: int = 8) -> np.ndarray:
        """Mask of the task boxes ``T`` proved inside the image (module docstring).

        ``seeds`` are joint values (``(N, k)``) from which Newton's method
        looks for a configuration reaching the centre of each box.

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, m, 2)`` task boxes.
        seeds : numpy.ndarray
            ``(N, k)`` starting joint values.
        newton : int
            Newton steps (default 8).

        Returns
        -------
        numpy.ndarray of bool
            ``(N,)``: True where the box is proved inside; all False when the map has fewer joints than
            coordinates (``k < m``).
        """
        if self.k < self.m:
            return np.zeros(len(T), dtype=bool)
        q, _ = self.newton(0.5 * (T[:, :, 0] + T[:, :, 1]), seeds, steps=newton)
        return self.prove_inside_at(T, q)

    def prove_inside_at(self, T: np.ndarray, q: np.ndarray) -> np.ndarray:
        """The Krawczyk test of each box ``T`` around the configuration ``q`` (``(N, k)``).

        Up to :attr:`COMBOS_TRIED` choices of the ``m`` joints that vary are tried per box, the best
        conditioned first.

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, m, 2)`` task boxes.
        q : numpy.ndarray
            ``(N, k)`` configurations, one per box.

        Returns
        -------
        numpy.ndarray of bool
            ``(N,)``: True where the box is proved inside.
        """
        return self.prove_inside_boxes(T, q)[0]

    def prove_inside_boxes(self, T: np.ndarray, q: np.ndarray, *, inflations: int | None = None):
        """:meth:`prove_inside_at` with the joint box of each proof: for every ``y`` in ``T[i]`` the equation
        ``f(q) = y`` has a solution in ``U[i]`` (the joints that varied in their proved ranges, the others at
        ``q[i]``).

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, m, 2)`` task boxes.
        q : numpy.ndarray
            ``(N, k)`` configurations, one per box.
        inflations : int, optional
            Epsilon-inflations after a failed test (default :attr:`INFLATIONS`).

        Returns
        -------
        proved : numpy.ndarray of bool
            ``(N,)``.
        U : numpy.ndarray
            ``(N, k, 2)`` joint boxes, meaningful where ``proved``.
        """
        N, m, k = len(T), self.m, self.k
        inflations = self.INFLATIONS if inflations is None else inflations
        with np.errstate(all="ignore"):
            J = self.jacobian_float(q)
        ok = np.isfinite(J).all(axis=(1, 2)) & np.isfinite(q).all(axis=1)
        # m joints u with a regular square Jacobian, the best-conditioned first; the others stay fixed at q.
        # A box that fails with one choice is tried with the next (a choice whose joint sits at its limit
        # leaves no room for U).
        combos = list(itertools.combinations(range(k), m))
        dets = np.stack([np.abs(np.linalg.det(J[:, :, list(c)])) for c in combos], axis=1)
        dets = np.where(np.isfinite(dets) & ok[:, None], dets, 0.0)
        order = np.argsort(-dets, axis=1)
        proved = np.zeros(N, dtype=bool)
        U = np.repeat(np.asarray(q, dtype=float)[:, :, None], 2, axis=2)
        for rank in range(min(len(combos), self.COMBOS_TRIED)):
            choice = order[:, rank]
            usable = ~proved & (dets[np.arange(N), choice] > 1e-12)
            for c_index, cols in enumerate(combos):
                rows = np.nonzero(usable & (choice == c_index))[0]
                if len(rows):
                    proved[rows], U[rows] = self._krawczyk_boxes(T[rows], q[rows], list(cols), 1.5,
                                                                 inflations=inflations)
        return proved, U

    def prove_inside_multistart(self, T: np.ndarray, rng, *, starts: int = 6, seeds: np.ndarray | None = None,
                                reached: bool = False):
        """The inner test from ``seeds`` first (if given), then from random configurations, ``starts`` times
        in all, each time on the boxes not yet proved; the test runs where Newton's method converged.

        With ``reached``, also returns the mask of boxes whose centre Newton's method reached (in floats:
        no proof, a hint that a proof of the outside would fail).

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, m, 2)`` task boxes.
        rng : numpy.random.Generator
            The source of the random configurations.
        starts : int
            Attempts in all, the seeds included (default 6).
        seeds : numpy.ndarray or None
            ``(N, k)`` joint values for the first attempt (None: random ones).
        reached : bool
            Also return the mask of centres reached (default False).

        Returns
        -------
        numpy.ndarray of bool or tuple
            ``proved`` (``(N,)``: True where the box is proved inside), or ``(proved, reached)`` with
            ``reached``.  Nothing is proved when ``k < m``.
        """
        proved = np.zeros(len(T), dtype=bool)
        hit = np.zeros(len(T), dtype=bool)
        if self.k < self.m:
            return (proved, hit) if reached else proved
        centre = 0.5 * (T[:, :, 0] + T[:, :, 1])
        for attempt in range(starts):
            rows = np.nonzero(~proved)[0]
            if not len(rows):
                break
            q0 = seeds[rows] if (attempt == 0 and seeds is not None) else self.random_configurations(len(rows), rng)
            q, converged = self.newton(centre[rows], q0)
            rows, q = rows[converged], q[converged]
            hit[rows] = True
            proved[rows] = self.prove_inside_at(T[rows], q)
        return (proved, hit) if reached else proved

    def admissible(self, box: np.ndarray) -> np.ndarray:
        """Mask of the joint boxes ``box`` (``(N, k, 2)``, fixed joints as points) on which a side condition
        of the inner test is proved; a test around a box outside the mask fails.  The plain map has none: a
        constrained map (:mod:`workspace_sym.serial.pose`) proves its constraint over the Krawczyk box.

        Parameters
        ----------
        box : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray of bool
            ``(N,)``: all True here.
        """
        return np.ones(len(box), dtype=bool)

    def _krawczyk(self, T, q, cols, factor, *, inflations: int = 2):
        """Mask of the boxes ``T`` for which the Krawczyk test succeeds on a box ``U`` around ``q``.

        ``U`` starts at ``factor`` times the image of ``T`` by ``C``; when
        the test fails, ``U`` is replaced by ``K`` widened by a fifth
        (epsilon-inflation) and tried again, ``inflations`` times.  Each try
        is a complete, independent test.
        """
        return self._krawczyk_boxes(T, q, cols, factor, inflations=inflations)[0]

    def _krawczyk_boxes(self, T, q, cols, factor, *, inflations: int = 2):
        """:meth:`_krawczyk`, with the box ``U`` of each successful try (``(N, k, 2)``; ``q`` as points where
        the test failed)."""
        N = len(T)
        sub = np.array(cols)
        with np.errstate(all="ignore"):
            C = np.linalg.inv(self.jacobian_float(q)[:, :, sub])
        half = 0.5 * (T[:, :, 1] - T[:, :, 0])
        radius = factor * np.einsum("nij,nj->ni", np.abs(C), half) + 1e-12 * (1 + np.abs(q[:, sub]))
        usable = np.isfinite(C).all(axis=(1, 2)) & np.isfinite(radius).all(axis=1)
        proved = np.zeros(N, dtype=bool)
        proofs = np.repeat(np.asarray(q, dtype=float)[:, :, None], 2, axis=2)
        rows = np.nonzero(usable)[0]
        p0 = np.full((N, self.m, 2), np.nan)
        if len(rows):
            with np.errstate(all="ignore"):
                p0[rows] = self.enclose(np.repeat(q[rows, :, None], 2, axis=2))      # f(q), outward-rounded
        for _ in range(inflations + 1):
            if not len(rows):
                break
            box = np.repeat(q[rows, :, None], 2, axis=2)          # fixed joints: point intervals
            box[:, sub, 0] = q[rows][:, sub] - radius[rows]
            box[:, sub, 1] = q[rows][:, sub] + radius[rows]
            within = (box[:, :, 0] >= self.inner_limits[:, 0]) & (box[:, :, 1] <= self.inner_limits[:, 1])
            allowed = (within | self.periodic).all(axis=1) & self.admissible(box)
            K = self._krawczyk_image(T[rows], q[rows], C[rows], box, sub, p0[rows])
            ok = allowed & (K[:, :, 0] > box[:, sub, 0]).all(axis=1) & (K[:, :, 1] < box[:, sub, 1]).all(axis=1)
            proved[rows[ok]] = True
            # the solutions in U lie in K(U), so K(U) holds one for every y in T; and every solution in a box X
            # lies in K(X): each contraction X <- K(X) & X keeps them (a narrower box for its users)
            # (the mean-value form behind K(X) needs the segment from q to each point of X in X: only boxes
            # holding q are contracted)
            tight = box[ok]
            tight[:, sub] = K[ok]
            at_q = q[rows[ok]][:, sub]
            for _ in range(self.CONTRACTIONS):
                centred = ((tight[:, sub, 0] <= at_q) & (at_q <= tight[:, sub, 1])).all(axis=1)
                if not centred.any():
                    break
                at, inner = rows[ok][centred], tight[centred]
                K2 = self._krawczyk_image(T[at], q[at], C[at], inner, sub, p0[at])
                inner[:, sub, 0] = np.maximum(inner[:, sub, 0], K2[:, :, 0])
                inner[:, sub, 1] = np.minimum(inner[:, sub, 1], K2[:, :, 1])
                tight[centred] = inner
            proofs[rows[ok]] = tight
            grow = np.maximum(np.abs(K[:, :, 0] - q[rows][:, sub]), np.abs(K[:, :, 1] - q[rows][:, sub]))
            retry = ~ok & allowed & np.isfinite(grow).all(axis=1)
            radius[rows[retry]] = np.maximum(radius[rows[retry]], 1.2 * grow[retry])
            rows = rows[retry]
        return proved, proofs

    def _krawczyk_image(self, T, q, C, box, sub, p0):
        """``K = q - C (f(q) - T) + (I - C J(U)) (U - q)`` over the joints ``sub``, outward-rounded: ``(N, m, 2)``
        (``p0``: ``f(q)`` enclosed, :meth:`enclose` of the point boxes ``q``)."""
        m = self.m
        K = np.empty((len(T), m, 2))
        with np.errstate(all="ignore"):
            JU = self.jacobian_enclosure(box, columns=sub)          # the columns of the joints that vary
            R = [arith.sub((p0[:, i, 0], p0[:, i, 1]), (T[:, i, 0], T[:, i, 1])) for i in range(m)]
            D = [arith.sub((box[:, j, 0], box[:, j, 1]), (q[:, j], q[:, j])) for j in sub]
            for a in range(m):
                c = [(C[:, a, i], C[:, a, i]) for i in range(m)]
                acc = arith.neg(dot(c, R))
                for b, j in enumerate(sub):
                    cj = dot(c, [JU[i][j] for i in range(m)])                  # (C J(U))[a, b]
                    identity = (1.0, 1.0) if a == b else (0.0, 0.0)
                    acc = arith.add(acc, arith.mul(arith.sub(identity, cj), D[b]))
                K[:, a, 0], K[:, a, 1] = arith.add(acc, (q[:, sub[a]], q[:, sub[a]]))
        return np.where(np.isnan(K), np.inf * np.array([-1.0, 1.0]), K)

    # -------------------------------------------------------------- outer test
    def prove_outside(self, T: np.ndarray, *, max_pairs=200_000, rounds: int = 60) -> np.ndarray:
        """Mask of the task boxes ``T`` proved to hold no point of the image: every joint box whose enclosure
        meets a task box is halved (longest edge) until none is left, or the box holds ``max_pairs`` (one
        number, or one per box).

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, m, 2)`` task boxes.
        max_pairs : int or array_like of int
            The most joint boxes a task box may hold (default 200,000).
        rounds : int
            The most rounds of halving (default 60).

        Returns
        -------
        numpy.ndarray of bool
            ``(N,)``: True where no joint box is left, a proof that the box holds no point of the image.
        """
        Q = np.repeat(self.limits[None], len(T), axis=0)
        owner = np.arange(len(T))
        cap = np.broadcast_to(np.asarray(max_pairs), (len(T),))
        Q, owner = distribute(self, T, Q, owner, cap, rounds=rounds, ratio=0.0)
        return np.bincount(owner, minlength=len(T)) == 0


def dot(c, v):
    acc = arith.mul(c[0], v[0])
    for ci, vi in zip(c[1:], v[1:]):
        acc = arith.add(acc, arith.mul(ci, vi))
    return acc


def batch_enclosures(batch: CompiledBatch, Q: np.ndarray, k: int, m: int) -> np.ndarray:
    """``(N, m, 2)`` enclosures of the ``m`` expressions of a compiled batch over the first ``k`` columns of the joint
    boxes ``Q`` (``(N, >= k, 2)``), rounded outward; a coordinate with no enclosure (NaN) is ``[-inf, inf]``.

    Parameters
    ----------
    batch : CompiledBatch
        The expressions, compiled (:func:`~workspace_sym.interval.compiler.compile_batch`).
    Q : numpy.ndarray
        Joint boxes.
    k, m : int
        The number of joints read and of expressions.

    Returns
    -------
    numpy.ndarray
        ``(N, m, 2)``.
    """
    X = [(Q[:, j, 0], Q[:, j, 1]) for j in range(k)]
    out = np.empty((len(Q), m, 2))
    with np.errstate(all="ignore"):
        for i, (lo, hi) in enumerate(batch(X)):
            out[:, i, 0], out[:, i, 1] = lo, hi
    return np.where(np.isnan(out), np.inf * np.array([-1.0, 1.0]), out)


def meets(E: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Closed boxes ``E`` and ``T`` (same shape) share a point; NaN bounds count as meeting."""
    apart = (E[:, :, 0] > T[:, :, 1]) | (E[:, :, 1] < T[:, :, 0])
    return ~np.asarray(apart.any(axis=1))


def distribute(model, T, Q, owner, cap, *, rounds: int = 4, ratio: float = 1.0):
    """Keep the (joint box, task box) pairs whose enclosure meets the task box, refining wide ones.

    Task box ``i`` refines its joint boxes whose enclosure is wider than
    ``ratio`` times the task box in a round only if it then holds at most
    ``cap[i]`` pairs.  What happens to a task box depends on it and its own
    pairs only (kept in their order), so any cut of the task boxes into
    chunks gives the same pairs.
    """
    for _ in range(rounds):
        E = model.enclose(Q)
        keep = meets(E, T[owner])
        Q, owner, E = Q[keep], owner[keep], E[keep]
        wide = np.max(E[:, :, 1] - E[:, :, 0], axis=1) > ratio * np.max(T[owner, :, 1] - T[owner, :, 0], axis=1)
        after = np.bincount(owner, minlength=len(T)) + np.bincount(owner[wide], minlength=len(T))
        wide &= (after <= cap)[owner]
        if not wide.any():
            break
        children, ok = halves(Q[wide])
        children = children.reshape(-1, 2, *Q.shape[1:])[ok].reshape(-1, *Q.shape[1:])
        Q = np.concatenate([Q[~wide], Q[wide][~ok], children])
        owner = np.concatenate([owner[~wide], owner[wide][~ok], np.repeat(owner[wide][ok], 2)])
    E = model.enclose(Q)
    keep = meets(E, T[owner])
    return Q[keep], owner[keep]


# ---------------------------------------------------------------------------------------------- critical set
def faces(image: ImageMap):
    """Every face of the joint box: per joint ``None`` (free), ``0`` (at its lower limit) or ``1`` (upper);
    periodic joints are always free."""
    choices = [(None,) if p else (None, 0, 1) for p in image.periodic]
    return list(itertools.product(*choices))


def face_box(image: ImageMap, face) -> np.ndarray:
    """The face as a ``(1, k, 2)`` joint box; a limited coordinate is the two floats enclosing the limit."""
    box = image.limits.copy()
    for j, side in enumerate(face):
        if side is not None:
            box[j] = image.face_limits[j, side]
    return box[None]


def _certain_sign(lo, hi):
    return np.where(lo > 0, 1, np.where(hi < 0, -1, 0))


def _parity(columns) -> int:
    """``0`` when sorting ``columns`` is an even permutation, ``1`` when odd."""
    columns = list(columns)
    return sum(a > b for i, a in enumerate(columns) for b in columns[i + 1:]) % 2


def _regular(image: ImageMap, Q: np.ndarray, free: np.ndarray, inward: np.ndarray) -> np.ndarray:
    """Mask of the joint boxes ``Q`` proved to hold no critical point of their face (module docstring).

    ``free[n, j]`` says joint ``j`` is free on the face of box ``n``; ``inward[n, j]`` is ``+1`` at a
    lower limit, ``-1`` at an upper one.  On a face with ``m`` free joints or more, an ``m x m`` minor of free
    columns proved non-zero makes the face's Jacobian onto ``R^m``.  On a face with ``m - 1`` free joints
    (an edge of a map into the plane, a 2-face of a map into space), the tangent cone is the span ``H`` of
    the free columns and the rays ``inward_c J_c`` of the limited joints; ``det [J_free, inward_c J_c]``
    proved non-zero says ``H`` is a hyperplane and on which side of it the ray lies: two rays proved on
    opposite sides make the cone ``R^m``.  Any other box (fewer free joints, nothing proved) is critical.
    """
    m = image.m
    count = free.sum(axis=1)
    regular = np.zeros(len(Q), dtype=bool)
    short = (count == m - 1) & (count < image.k)          # one free joint short of m: the rays decide
    left, right = np.zeros(len(Q), dtype=bool), np.zeros(len(Q), dtype=bool)
    for cols in itertools.combinations(range(image.k), m):
        # In space, a minor is evaluated only on the boxes it may still prove (the radial section map of a
        # plane caches its rows per array of boxes: every minor there sees all of them).
        rows = slice(None) if m == 2 else np.nonzero(~regular & ~(left & right) & (count >= m - 1))[0]
        lo, hi = image.minor_enclosure(Q[rows], *cols)
        at_rows = (count >= m)[rows] & free[rows][:, cols].all(axis=1) & ((lo > 0) | (hi < 0))
        regular[rows] |= at_rows
        if short.any():
            sign = _certain_sign(lo, hi)                        # of det [J_cols]
            for at, c in enumerate(cols):
                # the free columns, then the limited c: det [J_others, J_c] = (-1)^(m - 1 - at) det [J_cols]
                others = [j for j in cols if j != c]
                s = sign if (m - 1 - at) % 2 == 0 else -sign
                side = np.where(short[rows] & free[rows][:, others].all(axis=1) & ~free[rows][:, c],
                                s * inward[rows][:, c], 0)
                left[rows] |= side > 0
                right[rows] |= side < 0
    return regular | (left & right)


def critical_cover(image: ImageMap, face_list, target: float, clip: np.ndarray, *, show=None):
    """Enclosures ``(N, m, 2)`` of joint boxes covering the critical sets of the faces ``face_list``, each
    at most ``target`` wide (or a box that cannot be split further), clipped to ``clip`` (an enclosure of
    the whole image), and the number of joint boxes examined.  All faces go through one loop of arrays;
    what happens to a box depends on it alone, so any grouping of the faces gives the same enclosures.
    ``show(evaluated)``, optional, is called after each generation of joint boxes with the count so far."""
    face_list = list(face_list)
    if not face_list:
        return np.empty((0, image.m, 2)), 0
    free_of = np.array([[side is None for side in f] for f in face_list], dtype=bool)
    inward_of = np.array([[0 if side is None else (1 if side == 0 else -1) for side in f] for f in face_list])
    Q = np.concatenate([face_box(image, f) for f in face_list])
    which = np.arange(len(face_list))
    # Split where a joint moves the image most: joint width times the largest Jacobian entry over the limits.
    J = image.jacobian_enclosure(image.limits[None])
    scale = np.array([max(max(abs(float(J[i][j][0][0])), abs(float(J[i][j][1][0]))) for i in range(image.m))
                      for j in range(image.k)])
    scale = np.where(np.isfinite(scale), scale, 1.0)
    kept, evaluated = [], 0
    while len(Q):
        if len(Q) > MAX_COVER_BOXES:
            raise CoverTooLarge(f"the critical sets of {len(face_list)} faces need more than {MAX_COVER_BOXES} "
                                "joint boxes")
        evaluated += len(Q)
        free = free_of[which]
        E = image.enclose(Q)
        E[:, :, 0] = np.maximum(E[:, :, 0], clip[:, 0])
        E[:, :, 1] = np.minimum(E[:, :, 1], clip[:, 1])
        live = ~_regular(image, Q, free, inward_of[which]) & (E[:, :, 0] <= E[:, :, 1]).all(axis=1)
        Q, E, which, free = Q[live], E[live], which[live], free[live]
        vertex = ~free.any(axis=1)                      # a vertex: its enclosure is kept as it is
        small = vertex | (np.max(E[:, :, 1] - E[:, :, 0], axis=1) <= target)
        weight = np.where(free, (Q[:, :, 1] - Q[:, :, 0]) * scale, -np.inf)
        axis = np.argmax(weight, axis=1)
        children, ok = halves(Q[~small], axis[~small])
        kept.append(E[small])
        kept.append(E[~small][~ok])                     # one float wide: kept as it is
        Q = children.reshape(-1, 2, *Q.shape[1:])[ok].reshape(-1, *Q.shape[1:])
        which = np.repeat(which[~small][ok], 2)
        if show is not None:
            show(evaluated)
    return np.concatenate(kept), evaluated


# ---------------------------------------------------------------------------------------------- grid of cells
class CellGrid:
    """A grid of closed cells of equal width over a box with a margin of at least one cell outside it.

    ``edges[a]`` are the float cell edges along axis ``a``; cell ``(i, j, ...)`` is
    ``[edges[0][i], edges[0][i + 1]] x ...``.  The margin cells lie strictly outside
    ``box``.

    Parameters
    ----------
    box : array_like
        ``(m, 2)``: the box to cover.
    width : float
        The cells' width, positive.
    """

    def __init__(self, box: np.ndarray, width: float):
        self.box = np.asarray(box, dtype=float)
        self.width = float(width)
        self.edges = []
        for lo, hi in self.box:
            n = math.ceil((hi - lo) / width + 3)
            self.edges.append(lo - 1.5 * width + width * np.arange(n + 1))
        self.shape = tuple(len(e) - 1 for e in self.edges)

    @property
    def extent(self) -> np.ndarray:
        """The grid's own box, margin included.

        Returns
        -------
        numpy.ndarray
            ``(m, 2)``: the first and last cell edge along each axis.
        """
        return np.array([(e[0], e[-1]) for e in self.edges])

    def span(self, E: np.ndarray):
        """First and last cell index along each axis of the cells each closed box ``E`` meets: ``(N, m)`` twice.

        Parameters
        ----------
        E : numpy.ndarray
            ``(N, m, 2)`` closed boxes.

        Returns
        -------
        first : numpy.ndarray of int
            ``(N, m)``, clipped to the grid (a box beyond it gets the cells at its edge).
        last : numpy.ndarray of int
            ``(N, m)``, clipped likewise.
        """
        first = np.stack([np.searchsorted(e, E[:, a, 0], side="left") - 1 for a, e in enumerate(self.edges)], axis=1)
        last = np.stack([np.searchsorted(e, E[:, a, 1], side="right") - 1 for a, e in enumerate(self.edges)], axis=1)
        top = np.array(self.shape) - 1
        return np.clip(first, 0, top), np.clip(last, 0, top)

    def _corners(self, first: np.ndarray, last: np.ndarray):
        """``(index, sign)`` per corner of the blocks of cells ``first..last`` (inclusive, ``(N, m)``) in a table
        one longer along each axis: ``index`` a tuple of ``N`` positions (``first`` or ``last + 1`` per axis),
        ``sign`` ``(-1)^j``, ``j`` the number of axes at ``last + 1`` (the difference array of the block; a
        sum over the block from a summed-area table takes ``(-1)^m sign``)."""
        m = len(self.shape)
        for corner in itertools.product((0, 1), repeat=m):
            yield (tuple(last[:, a] + 1 if c else first[:, a] for a, c in enumerate(corner)),
                   -1 if sum(corner) % 2 else 1)

    def _summed(self, counts: np.ndarray) -> np.ndarray:
        for axis in range(counts.ndim):
            counts = np.cumsum(counts, axis=axis)
        return counts

    def mark(self, E: np.ndarray) -> np.ndarray:
        """Boolean grid of the cells meeting at least one box of ``E`` (a difference array: ``+-1`` at the
        corners of each block of cells, summed along every axis).

        Parameters
        ----------
        E : numpy.ndarray
            ``(N, m, 2)`` closed boxes.

        Returns
        -------
        numpy.ndarray of bool
            Of the grid's shape: True for a cell that meets a box.
        """
        counts = np.zeros(tuple(n + 1 for n in self.shape), dtype=np.int64)
        if len(E):
            first, last = self.span(E)
            for index, sign in self._corners(first, last):
                np.add.at(counts, index, sign)
        return self._summed(counts)[tuple(slice(None, -1) for _ in self.shape)] > 0

    def cells(self, index: np.ndarray) -> np.ndarray:
        """``(N, m, 2)`` boxes of the cells at integer positions ``index`` (``(N, m)``).

        Parameters
        ----------
        index : numpy.ndarray of int
            ``(N, m)`` cell positions.

        Returns
        -------
        numpy.ndarray
            ``(N, m, 2)`` closed cells.
        """
        return np.stack([np.stack([e[index[:, a]], e[index[:, a] + 1]], axis=1) for a, e in enumerate(self.edges)],
                        axis=1)

    def boxes(self, classes: np.ndarray, value: int, *, merge: bool = True) -> np.ndarray:
        """The cells of one class as ``(N, m, 2)`` boxes, runs along the last axis merged into one box.

        Parameters
        ----------
        classes : numpy.ndarray
            A code per cell, of the grid's shape.
        value : int
            The class wanted.
        merge : bool
            Merge runs of cells along the last axis (default True); False: one box a cell.

        Returns
        -------
        numpy.ndarray
            ``(N, m, 2)`` boxes whose union is the class's cells.
        """
        hit = classes == value
        if not merge:
            return self.cells(np.argwhere(hit))
        padded = np.pad(hit, [(0, 0)] * (hit.ndim - 1) + [(1, 1)])
        step = np.diff(padded.astype(np.int8), axis=-1)
        starts = np.argwhere(step == 1)
        ends = np.argwhere(step == -1)          # same rows, in the same order
        out = self.cells(starts)
        out[:, -1, 1] = self.edges[-1][ends[:, -1]]
        return out

    def prefix(self, classes: np.ndarray, value: int) -> np.ndarray:
        """Summed-area table of the cells of one class, for :meth:`all_in_class`.

        Parameters
        ----------
        classes : numpy.ndarray
            A code per cell, of the grid's shape.
        value : int
            The class counted.

        Returns
        -------
        numpy.ndarray of int64
            One longer than the grid along each axis: entry ``(i, j, ...)`` counts the class's cells below
            ``i``, ``j``, ....
        """
        table = np.zeros(tuple(n + 1 for n in self.shape), dtype=np.int64)
        table[tuple(slice(1, None) for _ in self.shape)] = self._summed((classes == value).astype(np.int64))
        return table

    def all_in_class(self, table: np.ndarray, E: np.ndarray, *, outside_counts: bool) -> np.ndarray:
        """Mask of the closed boxes ``E`` (``(N, m, 2)``) whose every point lies in cells of the class of
        ``table``; a part of ``E`` beyond the grid counts as in the class when ``outside_counts``.

        Parameters
        ----------
        table : numpy.ndarray
            A summed-area table of :meth:`prefix`.
        E : numpy.ndarray
            ``(N, m, 2)`` closed boxes.
        outside_counts : bool
            Whether the space beyond the grid belongs to the class.

        Returns
        -------
        numpy.ndarray of bool
            ``(N,)``: True where every cell the box meets is of the class (and it stays on the grid, unless
            ``outside_counts``).
        """
        first, last = self.span(E)
        ext = self.extent
        beyond = ((E[:, :, 0] < ext[:, 0]) | (E[:, :, 1] > ext[:, 1])).any(axis=1)
        flip = -1 if len(self.shape) % 2 else 1
        total = sum(flip * sign * table[index] for index, sign in self._corners(first, last))
        full = total == np.prod(last + 1 - first, axis=1)
        return full & (outside_counts | ~beyond)


# ---------------------------------------------------------------------------------------------- the paving
def critical_paving(image: ImageMap, width: float, *, rng=None, budget=None, cover_ratio: float = 0.7,
                    cover=None, show=None, chunk: int | None = None):
    """Classify the cells of a grid of the given width over the image of a map into the plane or into space
    (``m = 2`` or ``3``).

    Returns ``(grid, classes, evaluated, stopped)``: ``classes`` holds
    the verdict code (:mod:`.verdict`) OUTSIDE, INSIDE or UNDECIDED per cell (see the module
    docstring for the proofs); ``stopped`` is the reason a budget stopped the
    run (then every cell not yet decided is :data:`UNDECIDED`, and nothing
    rests on an unfinished step).  ``budget`` is a callable of the number of
    boxes evaluated returning a stop reason or ``""``, looked at after each generation of the cover here
    (with ``ahead=`` twice the seconds of the last generation when it takes that keyword, as
    :meth:`~workspace_sym.interval.driver.RunBudget.stop_reason` does: the next generation holds at most
    twice its boxes), each round of proofs of the components and each chunk of marked cells; ``cover`` computes the
    covers of a list of faces, ``cover(faces, target, clip)``, as a list of
    :func:`critical_cover` results (default: here, all faces in one call).  ``show`` is
    called as ``show(share decided, boxes evaluated)`` after each step: each generation of the cover here
    (nothing decided yet), each round of proofs of the components, the marked cells (``chunk`` of them at a
    time; default: all at once).  Unmarked cells are connected through their faces (4-connected in the plane,
    6-connected in space).

    Parameters
    ----------
    image : ImageMap
        The map, with ``m`` 2 or 3.
    width : float
        The cells' width.
    rng : numpy.random.Generator or None
        The source of random cells and configurations (None: ``numpy.random.default_rng(0)``).
    budget : callable or None
        ``budget(evaluated)`` (optionally with ``ahead=``) returns a stop reason or ``""``, as above (None:
        never stops).
    cover_ratio : float
        The critical cover's boxes are refined until their enclosures are at most ``cover_ratio * width``
        wide (default 0.7).
    cover : callable or None
        ``cover(faces, target, clip)``, as above (None: here).
    show : callable or None
        ``show(share, evaluated)``, as above (None: nothing shown).
    chunk : int or None
        Marked cells tried at a time (None: all at once).

    Returns
    -------
    grid : CellGrid
        The grid.
    classes : numpy.ndarray of int8
        A verdict code per cell.
    evaluated : int
        Boxes examined: the cover's joint boxes, and each point or cell tested.
    stopped : str
        The budget's stop reason, ``""`` for a complete run.

    Raises
    ------
    ValueError
        For a map into neither the plane nor space.
    CoverTooLarge
        When a generation of the critical cover holds more than :data:`MAX_COVER_BOXES` joint boxes.
    """
    from scipy import ndimage

    if image.m not in (2, 3):
        raise ValueError("critical_paving needs a map into the plane or into space")
    rng = np.random.default_rng(0) if rng is None else rng
    budget = budget or (lambda evaluated: "")
    show = show or (lambda share, evaluated: None)
    root = image.enclose(image.limits[None])[0]
    grid = CellGrid(root, width)
    classes = np.full(grid.shape, UNDECIDED, dtype=CODE)
    target = cover_ratio * width

    # The next generation of the cover holds at most twice the boxes of the last one: with a budget that takes
    # the seconds ``ahead`` of a step, a generation expected to end past its time limit is not started.
    foresees = "ahead" in inspect.signature(budget).parameters
    clock = [time.perf_counter()]

    def generation(evaluated):
        show(0.0, evaluated)
        now = time.perf_counter()
        reason = budget(evaluated, ahead=2.0 * (now - clock[0])) if foresees else budget(evaluated)
        clock[0] = now
        if reason:
            raise CoverStopped(evaluated, reason)

    try:
        if cover is None:
            covers = [critical_cover(image, faces(image), target, root, show=generation)]
        else:
            covers = cover(faces(image), target, root)
    except CoverStopped as stop:
        return grid, classes, stop.evaluated, stop.reason
    evaluated = sum(n for _, n in covers)
    stopped = budget(evaluated)
    if stopped:
        return grid, classes, evaluated, stopped
    marked = grid.mark(np.concatenate([E for E, _ in covers]))
    show(0.0, evaluated)
    labels, count = ndimage.label(~marked)
    ring = np.ones(grid.shape, dtype=bool)
    ring[tuple(slice(1, -1) for _ in grid.shape)] = False
    verdict = np.full(count + 1, UNDECIDED, dtype=CODE)
    verdict[np.unique(labels[ring & ~marked])] = OUTSIDE
    # Every other component: prove one of its cells, the deepest first, then a few others.
    depth = ndimage.distance_transform_cdt(~marked, metric="taxicab")
    todo = [c for c in range(1, count + 1) if verdict[c] == UNDECIDED]
    size = np.bincount(labels.ravel(), minlength=count + 1)
    if todo:
        deepest = np.array(ndimage.maximum_position(depth, labels, todo))
        candidates = [deepest]
        for _ in range(2):
            candidates.append(_random_cells(labels, todo, rng))
        for cells in candidates:
            open_ = np.array([verdict[c] == UNDECIDED for c in todo])
            if not open_.any():
                break
            # One point decides a component: the centre of the cell, as a degenerate box (easier to prove
            # than the whole cell).
            centre = grid.cells(cells[open_]).mean(axis=2)
            boxes = np.repeat(centre[:, :, None], 2, axis=2)
            ids = np.array(todo)[open_]
            evaluated += len(boxes)
            inside, reached = image.prove_inside_multistart(boxes, rng, reached=True)
            verdict[ids[inside]] = INSIDE
            # Outside proofs where Newton's method reached no centre, for components of at least
            # OUTSIDE_MIN_CELLS cells (a few pinched cells between marks are left undecided: their measure is
            # small and joint boxes near the boundary are many).
            rest = ~inside & ~reached & (size[ids] >= OUTSIDE_MIN_CELLS)
            if rest.any():
                evaluated += int(rest.sum())
                outside = image.prove_outside(boxes[rest], max_pairs=OUTSIDE_PAIRS)
                verdict[ids[rest][outside]] = OUTSIDE
            # the share of the unmarked cells decided so far (the marked ones are label 0, undecided)
            show(float(np.mean(verdict[labels] != UNDECIDED)), evaluated)
            stopped = budget(evaluated)
            if stopped:
                break
    classes[~marked] = verdict[labels[~marked]]
    show(float(np.mean(classes != UNDECIDED)), evaluated)
    if stopped:
        return grid, classes, evaluated, stopped
    # Marked cells, one by one (in chunks, the budget looked at between them).
    index = np.argwhere(marked)
    step = len(index) if chunk is None else chunk
    for start in range(0, len(index), max(step, 1)):
        part = index[start:start + step]
        boxes = grid.cells(part)
        evaluated += len(boxes)
        inside = image.prove_inside_multistart(boxes, rng, starts=4)
        classes[tuple(part[inside].T)] = INSIDE
        show(float(np.mean(classes != UNDECIDED)), evaluated)
        stopped = budget(evaluated)
        if stopped:
            break
    return grid, classes, evaluated, stopped or budget(evaluated)


def _random_cells(labels, components, rng):
    """One random cell of each component (``components`` ascending), as ``(N, m)`` indices."""
    flat = np.flatnonzero(np.isin(labels, components))
    flat = flat[rng.permutation(len(flat))]
    _, first = np.unique(labels.flat[flat], return_index=True)
    return np.stack(np.unravel_index(flat[first], labels.shape), axis=1)
