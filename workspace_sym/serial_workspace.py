"""Certified position workspace of a serial robot: reachable boxes proved, unreachable boxes proved.

:func:`reach` paves the space of end-effector positions (``x, y`` for a
planar robot, ``x, y, z`` otherwise) into

* **outer** boxes: no configuration within the joint limits puts the
  end-effector in the box;
* **inner** boxes: every point of the box is the position of some
  configuration within the joint limits;
* **boundary** boxes: neither is proved and the box is at most ``delta``.

Outer proof.  Each task box carries joint boxes covering every configuration
whose position may lie in it.  The root task box is the enclosure of the
position over the joint limits, with the limits as its one joint box.  When
a task box is split, a joint box goes to each half its position enclosure
meets (the enclosure is refined by bisecting the joint box while it is
wider than the half); a joint box whose enclosure misses the half cannot
hold a configuration reaching it.  A task box left without joint boxes is
outer.  Enclosures come from the interval compiler on the symbolic forward
kinematics (outward-rounded numpy engine, centred form where a joint
repeats); only the joints the position depends on are subdivided.

Inner proof (Goldsztejn and Jaulin, "Inner approximation of the range of
vector-valued functions", Reliable Computing 14, 2010, whose test is a
Krawczyk operator over a box of right-hand sides).  With ``m`` task
coordinates, ``m`` joints ``u`` are chosen where the Jacobian is best
conditioned and the others are fixed at float values within their limits.
For a joint box ``U`` inside the limits, a point ``u0`` in it and a float
matrix ``C``, if

    ``K = u0 - C (p(u0) - T) + (I - C J(U)) (U - u0)``

lies in the interior of ``U`` (every operation outward-rounded, ``J(U)`` an
interval enclosure of the Jacobian over ``U``), then for every ``y`` in the
task box ``T`` the Krawczyk operator of ``p(u) - y`` maps ``U`` into its
interior, so ``p(u) = y`` has a solution in ``U``: ``T`` is reachable.
``U`` is built around a numerical solution for the centre of ``T`` (Newton
from a joint box of the cover), so only the final test needs to be
rigorous.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp

from .errors import InvalidParameterError, JointLimitError
from .interval import arith
from .interval.compiler import compile_expr
from .interval.executor import _MIN_CHUNK, _runner
from .interval.paving import Box, Paving, RunBudget, box_measure, box_sizes, check_delta
from .interval.search import split_every_axis
from .kinematics import DHRobot

__all__ = ["reach", "ReachModel"]

_TASK = (sp.Symbol("x"), sp.Symbol("y"), sp.Symbol("z"))
_MIN_PAIRS = 64                  # pairs a task box may always hold, however small its share of the root box


class ReachModel:
    """The position map of a robot as the interval and float functions :func:`reach` needs.

    ``coordinates`` are the indices of the position coordinates that depend
    on the joints (two for a planar robot); ``joints`` are the indices of
    the joints the position depends on, ``limits`` their ``(k, 2)`` limits.
    """

    def __init__(self, robot: DHRobot, parameters: dict | None = None):
        if not isinstance(robot, DHRobot):
            raise InvalidParameterError(f"robot: reach needs a serial DH robot; got {type(robot).__name__}")
        position = robot.substitute(robot.position, parameters)
        free = position.free_symbols - set(robot.q)
        if free:
            raise InvalidParameterError(f"parameters: give values for {', '.join(sorted(map(str, free)))} "
                                        "(the position must be numeric apart from the joints)")
        moving = position.free_symbols
        self.joints = [k for k, q in enumerate(robot.q) if q in moving]
        self.coordinates = [i for i in range(3) if position[i].free_symbols]
        if not self.joints:
            raise InvalidParameterError(f"robot: the position of {robot.name} does not depend on any joint")
        limits, periodic = [], []
        for k in self.joints:
            joint = robot.joints[k]
            if joint.limits is None and joint.kind == "P":
                raise JointLimitError(f"joint {k + 1} ({joint.variable}) is prismatic: reach needs its limits")
            lo, hi = (-np.pi, np.pi) if joint.limits is None else map(float, joint.limits)
            limits.append((lo, hi))
            # An unlimited revolute joint whose angle is +-q + const: the position is 2 pi periodic in q, so
            # a solution outside [-pi, pi] is a solution inside it.
            slope = sp.diff(joint.theta, joint.variable) if joint.kind == "R" else None
            periodic.append(joint.limits is None and slope in (1, -1))
        self.limits = np.array(limits, dtype=float)
        self.periodic = np.array(periodic, dtype=bool)
        self.variables = tuple(robot.q[k] for k in self.joints)
        self.task_variables = tuple(_TASK[i] for i in self.coordinates)
        p = [position[i] for i in self.coordinates]
        self.m, self.k = len(p), len(self.joints)
        self._position = [compile_expr(e, self.variables) for e in p]
        jac = [[sp.diff(e, q) for q in self.variables] for e in p]
        self._jacobian = [[compile_expr(entry, self.variables) for entry in row] for row in jac]
        self._p_float = sp.lambdify([self.variables], p, modules="numpy")
        self._j_float = sp.lambdify([self.variables], jac, modules="numpy")

    # -------------------------------------------------------------- interval enclosures
    def enclose(self, Q: np.ndarray) -> np.ndarray:
        """``(N, m, 2)`` enclosures of the position over joint boxes ``Q`` (``(N, k, 2)``)."""
        X = [(Q[:, j, 0], Q[:, j, 1]) for j in range(self.k)]
        out = np.empty((len(Q), self.m, 2))
        with np.errstate(all="ignore"):
            for i, f in enumerate(self._position):
                lo, hi = f(X)
                out[:, i, 0], out[:, i, 1] = lo, hi
        return out

    def jacobian_enclosure(self, Q: np.ndarray):
        """``J[i][j] = (lo, hi)`` arrays enclosing ``d p_i / d u_j`` over ``Q``."""
        X = [(Q[:, j, 0], Q[:, j, 1]) for j in range(self.k)]
        shape = (len(Q),)
        with np.errstate(all="ignore"):
            return [[tuple(np.broadcast_to(v, shape) for v in f(X)) for f in row] for row in self._jacobian]

    # -------------------------------------------------------------- floats
    def position_float(self, q: np.ndarray) -> np.ndarray:
        """``(N, m)`` positions at joint values ``q`` (``(N, k)``), in floats."""
        out = self._p_float(q.T)
        return np.stack([np.broadcast_to(np.asarray(v, dtype=float), (len(q),)) for v in out], axis=1)

    def jacobian_float(self, q: np.ndarray) -> np.ndarray:
        """``(N, m, k)`` Jacobians at ``q``, in floats."""
        rows = self._j_float(q.T)
        return np.stack([np.stack([np.broadcast_to(np.asarray(v, dtype=float), (len(q),)) for v in row], axis=1)
                         for row in rows], axis=1)

    # -------------------------------------------------------------- inner test
    def prove_inside(self, T: np.ndarray, seeds: np.ndarray, *, newton: int = 8) -> np.ndarray:
        """Mask of the task boxes ``T`` proved inside the image (see the module docstring).

        ``seeds`` are joint values (``(N, k)``) from which Newton's method
        looks for a configuration reaching the centre of each box.
        """
        N, m, k = len(T), self.m, self.k
        centre = 0.5 * (T[:, :, 0] + T[:, :, 1])
        q = seeds.copy()
        with np.errstate(all="ignore"):
            for _ in range(newton):
                r = self.position_float(q) - centre
                step = np.einsum("nij,nj->ni", np.linalg.pinv(self.jacobian_float(q)), r)
                q = q - step
                q = np.where(self.periodic, np.remainder(q + np.pi, 2 * np.pi) - np.pi,
                             np.clip(q, self.limits[:, 0], self.limits[:, 1]))
            J = self.jacobian_float(q)
        ok = np.isfinite(J).all(axis=(1, 2)) & np.isfinite(q).all(axis=1)
        # The m joints with the best-conditioned square Jacobian; the others stay fixed at q.
        combos = list(itertools.combinations(range(k), m))
        dets = np.stack([np.abs(np.linalg.det(J[:, :, list(c)])) for c in combos], axis=1)
        dets = np.where(np.isfinite(dets), dets, 0.0)
        choice = np.argmax(dets, axis=1)
        ok &= dets[np.arange(N), choice] > 1e-12
        proved = np.zeros(N, dtype=bool)
        for c_index, cols in enumerate(combos):
            for factor in (1.5,):                       # radius of U against the image of T (inflated on failure)
                rows = np.nonzero(ok & (choice == c_index) & ~proved)[0]
                if len(rows):
                    proved[rows] = self._krawczyk(T[rows], q[rows], list(cols), factor)
        return proved

    def _krawczyk(self, T, q, cols, factor, *, inflations: int = 2):
        """Mask of the boxes ``T`` for which the Krawczyk test succeeds on a box ``U`` around ``q``.

        ``U`` starts at ``factor`` times the image of ``T`` by ``C``; when
        the test fails, ``U`` is replaced by ``K`` widened by a fifth
        (epsilon-inflation) and tried again, ``inflations`` times.  Each try
        is a complete, independent test.
        """
        N = len(T)
        sub = np.array(cols)
        with np.errstate(all="ignore"):
            C = np.linalg.inv(self.jacobian_float(q)[:, :, sub])
        half = 0.5 * (T[:, :, 1] - T[:, :, 0])
        radius = factor * np.einsum("nij,nj->ni", np.abs(C), half) + 1e-12 * (1 + np.abs(q[:, sub]))
        usable = np.isfinite(C).all(axis=(1, 2)) & np.isfinite(radius).all(axis=1)
        proved = np.zeros(N, dtype=bool)
        rows = np.nonzero(usable)[0]
        for _ in range(inflations + 1):
            if not len(rows):
                break
            box = np.repeat(q[rows, :, None], 2, axis=2)          # fixed joints: point intervals
            box[:, sub, 0] = q[rows][:, sub] - radius[rows]
            box[:, sub, 1] = q[rows][:, sub] + radius[rows]
            within = (box[:, :, 0] >= self.limits[:, 0]) & (box[:, :, 1] <= self.limits[:, 1])
            allowed = (within | self.periodic).all(axis=1)
            K = self._krawczyk_image(T[rows], q[rows], C[rows], box, sub)
            ok = allowed & (K[:, :, 0] > box[:, sub, 0]).all(axis=1) & (K[:, :, 1] < box[:, sub, 1]).all(axis=1)
            proved[rows[ok]] = True
            grow = np.maximum(np.abs(K[:, :, 0] - q[rows][:, sub]), np.abs(K[:, :, 1] - q[rows][:, sub]))
            retry = ~ok & allowed & np.isfinite(grow).all(axis=1)
            radius[rows[retry]] = np.maximum(radius[rows[retry]], 1.2 * grow[retry])
            rows = rows[retry]
        return proved

    def _krawczyk_image(self, T, q, C, box, sub):
        """``K = q - C (p(q) - T) + (I - C J(U)) (U - q)`` over the joints ``sub``, outward-rounded: ``(N, m, 2)``."""
        m = self.m
        point = np.repeat(q[:, :, None], 2, axis=2)
        K = np.empty((len(T), m, 2))
        with np.errstate(all="ignore"):
            p0 = self.enclose(point)                              # p(q), outward-rounded
            JU = self.jacobian_enclosure(box)
            R = [arith.sub((p0[:, i, 0], p0[:, i, 1]), (T[:, i, 0], T[:, i, 1])) for i in range(m)]
            D = [arith.sub((box[:, j, 0], box[:, j, 1]), (q[:, j], q[:, j])) for j in sub]
            for a in range(m):
                c = [(C[:, a, i], C[:, a, i]) for i in range(m)]
                acc = arith.neg(_dot(c, R))
                for b, j in enumerate(sub):
                    cj = _dot(c, [JU[i][j] for i in range(m)])                  # (C J(U))[a, b]
                    identity = (1.0, 1.0) if a == b else (0.0, 0.0)
                    acc = arith.add(acc, arith.mul(arith.sub(identity, cj), D[b]))
                K[:, a, 0], K[:, a, 1] = arith.add(acc, (q[:, sub[a]], q[:, sub[a]]))
        return np.where(np.isnan(K), np.inf * np.array([-1.0, 1.0]), K)


def _dot(c, v):
    acc = arith.mul(c[0], v[0])
    for ci, vi in zip(c[1:], v[1:]):
        acc = arith.add(acc, arith.mul(ci, vi))
    return acc


def _meets(E: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Closed boxes ``E`` and ``T`` (same shape) share a point; NaN bounds count as meeting."""
    apart = (E[:, :, 0] > T[:, :, 1]) | (E[:, :, 1] < T[:, :, 0])
    return ~apart.any(axis=1)


def _halves(boxes: np.ndarray):
    """Both halves of every box along its longest edge, in order (``2i``, ``2i + 1``), and the mask of
    boxes that could be split (a box one float wide cannot; its two "halves" are then itself)."""
    rows = np.arange(len(boxes))
    k = np.argmax(boxes[:, :, 1] - boxes[:, :, 0], axis=1)
    lo, hi = boxes[rows, k, 0], boxes[rows, k, 1]
    mid = 0.5 * lo + 0.5 * hi
    ok = (mid > lo) & (mid < hi)
    children = np.repeat(boxes, 2, axis=0)
    children[2 * rows[ok], k[ok], 1] = mid[ok]
    children[2 * rows[ok] + 1, k[ok], 0] = mid[ok]
    return children, ok


def _distribute(model, T, Q, owner, cap, *, rounds: int = 4, ratio: float = 1.0):
    """Keep the (joint box, task box) pairs whose position enclosure meets the task box, refining wide ones.

    Task box ``i`` refines its wide joint boxes in a round only if it then
    holds at most ``cap[i]`` pairs.  What happens to a task box depends on it
    and its own pairs only (kept in their order), so any cut of the task
    boxes into chunks gives the same pairs.
    """
    for _ in range(rounds):
        E = model.enclose(Q)
        keep = _meets(E, T[owner])
        Q, owner, E = Q[keep], owner[keep], E[keep]
        wide = np.max(E[:, :, 1] - E[:, :, 0], axis=1) > ratio * np.max(T[owner, :, 1] - T[owner, :, 0], axis=1)
        after = np.bincount(owner, minlength=len(T)) + np.bincount(owner[wide], minlength=len(T))
        wide &= (after <= cap)[owner]
        if not wide.any():
            break
        children, ok = _halves(Q[wide])
        children = children.reshape(-1, 2, *Q.shape[1:])[ok].reshape(-1, *Q.shape[1:])
        Q = np.concatenate([Q[~wide], Q[wide][~ok], children])
        owner = np.concatenate([owner[~wide], owner[wide][~ok], np.repeat(owner[wide][ok], 2)])
    E = model.enclose(Q)
    keep = _meets(E, T[owner])
    return Q[keep], owner[keep]


def _prove_in_pieces(model, T, seeds, depth):
    """Mask of the boxes ``T`` proved inside the image, box ``i`` cut into up to ``2^(m depth[i])`` pieces
    (halved along every edge per level) of which every one must pass the test."""
    proved = np.ones(len(T), dtype=bool)
    pieces, owner = T, np.arange(len(T))
    for level in range(int(depth.max(initial=0)) + 1):
        ok = model.prove_inside(pieces, seeds[owner])
        failed = owner[~ok]
        final = depth[failed] <= level
        proved[failed[final]] = False
        again = ~ok
        again[np.nonzero(again)[0][final]] = False
        if not again.any():
            break
        pieces = split_every_axis(pieces[again])
        owner = np.tile(owner[again], 2 ** T.shape[1])
    return proved


@lru_cache(maxsize=16)
def _model(robot: DHRobot, parameters: tuple) -> ReachModel:
    """The reach model of a robot (cached: a worker compiles it once for all its chunks)."""
    return ReachModel(robot, dict(parameters) or None)


def _volumes(T: np.ndarray) -> np.ndarray:
    return np.prod(T[:, :, 1] - T[:, :, 0], axis=1)


@dataclass(frozen=True)
class _ReachStep:
    """One generation of :func:`reach` on a chunk of task boxes with their pairs (picklable: the robot travels
    to the workers, the model is compiled there once).

    Called with ``(T, Q, owner)``, it returns the inner, boundary and outer
    task boxes, the children of the split ones and their pairs ``(Q, owner)``.
    Each task box is treated on its own (:func:`_distribute`), so chunks give
    together exactly what one call on all the boxes gives.
    """

    robot: DHRobot
    parameters: tuple
    delta: float
    size: str
    inner_depth: int
    max_pairs: int
    root_measure: float

    def __call__(self, part):
        T, Q, owner = part
        model = _model(self.robot, self.parameters)
        # A task box may hold pairs in proportion to its share of the root box, and at least _MIN_PAIRS.
        cap = np.maximum(_MIN_PAIRS, np.floor(self.max_pairs * (_volumes(T) / self.root_measure)))
        Q, owner = _distribute(model, T, Q, owner, cap)
        count = np.bincount(owner, minlength=len(T))
        is_out = count == 0
        # One seed per task box: the centre of its first joint box.
        live, first = np.unique(owner, return_index=True)
        is_in = np.zeros(len(T), dtype=bool)
        if len(live):
            seeds = Q[first].mean(axis=2)
            # A box that would become a boundary box is also tried in pieces (every piece proved).
            last = box_sizes(T[live], self.size) <= self.delta
            is_in[live] = _prove_in_pieces(model, T[live], seeds, np.where(last, self.inner_depth, 0))
        und = ~is_out & ~is_in
        small = und & (box_sizes(T, self.size) <= self.delta)
        split = und & ~small
        # Children of every split box, and the pairs of each child (both halves inherit the joint boxes).
        children, ok = _halves(T[split])
        boundary = np.concatenate([T[small], T[split][~ok]])     # too thin to split: delta below float resolution
        split[np.nonzero(split)[0][~ok]] = False
        children = children.reshape(-1, 2, *T.shape[1:])[ok].reshape(-1, *T.shape[1:])
        new_index = np.full(len(T), -1)
        new_index[split] = np.arange(split.sum())
        pair = new_index[owner] >= 0
        Q, base = Q[pair], new_index[owner[pair]]
        return T[is_in], boundary, T[is_out], children, np.concatenate([Q, Q]), np.concatenate([2 * base, 2 * base + 1])


def _parts(T, Q, owner, pieces: int):
    """The task boxes cut into ``pieces`` runs of consecutive boxes, each with its own pairs in their order."""
    order = np.argsort(owner, kind="stable")
    Q, owner = Q[order], owner[order]
    for rows in np.array_split(np.arange(len(T)), pieces):
        if len(rows):
            a, b = rows[0], rows[-1] + 1
            lo, hi = np.searchsorted(owner, [a, b])
            yield T[a:b], Q[lo:hi], owner[lo:hi] - a


@arith.nearest_rounding
def reach(robot: DHRobot, *, delta: float, size: str = "diameter", parameters: dict | None = None,
          max_boxes: int | None = None, time_limit: float | None = None, progress: bool | None = None,
          max_pairs: int = 200_000, inner_depth: int = 2, executor=None, chunk_pairs: int = 100_000) -> Paving:
    """Pave the position workspace of a serial robot within its joint limits (module docstring).

    Parameters
    ----------
    robot : DHRobot
    delta : float
        Undecided task boxes whose size is at most ``delta`` become boundary boxes.
    size : {"diameter", "width"}
    parameters : values of the symbolic lengths (default: the robot's own).
    max_boxes, time_limit : budget; the task boxes left are returned as ``pending``.
    progress : progress bar (:mod:`workspace_sym.progress`; default: on an
        interactive output once the run has lasted a second).
    inner_depth : a box about to become a boundary box is also proved inner
        piece by piece, halving it along every edge up to this many times.
    max_pairs : budget of (joint box, task box) pairs: a task box stops
        refining its joint boxes once it would hold more than ``max_pairs``
        times its share of the root box's measure (64 pairs at least).  Past
        it the proofs stay sound, fewer boxes are decided.  The cap of a box
        depends on that box alone, so a chunked run decides the same boxes.
    executor : None (this process), a :class:`concurrent.futures.Executor`
        or a ``dask.distributed.Client``
        (:func:`workspace_sym.interval.executor.connect`): each generation of
        task boxes is cut into chunks, each with its joint boxes, decided
        there; the result has the same boxes, counts and measures.
    chunk_pairs : about this many (joint box, task box) pairs per chunk.

    Returns
    -------
    Paving
        Over ``x, y`` (planar robot) or ``x, y, z``; ``inner`` boxes are
        proved reachable, ``outer`` boxes proved unreachable.

    Examples
    --------
    >>> from workspace_sym.kinematics import DHJoint
    >>> arm = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=sp.Rational(1, 2))])
    >>> p = reach(arm, delta=0.1)
    >>> lo, hi = p.measure_bounds           # the annulus 1/2 <= r <= 3/2: area 2 pi
    >>> bool(lo <= 2 * np.pi <= hi)
    True
    """
    check_delta(delta)
    if size not in ("diameter", "width"):
        raise InvalidParameterError(f"size must be one of 'diameter', 'width'; got {size!r}", parameter="size")
    if not isinstance(inner_depth, int) or isinstance(inner_depth, bool) or inner_depth < 0:
        raise InvalidParameterError(f"inner_depth must be a whole number of halvings, 0 or more; got {inner_depth!r}",
                                    parameter="inner_depth")
    if not isinstance(chunk_pairs, int) or isinstance(chunk_pairs, bool) or chunk_pairs < 1:
        raise InvalidParameterError(f"chunk_pairs must be a whole number of pairs, 1 or more; got {chunk_pairs!r}",
                                    parameter="chunk_pairs")
    run = RunBudget(max_boxes=max_boxes, time_limit=time_limit, progress=progress, total=0.0, label="reach")
    parameters = tuple(sorted((parameters or {}).items(), key=lambda item: str(item[0])))
    model = _model(robot, parameters)
    Q = model.limits[None].copy()
    root = model.enclose(Q)[0]
    if not np.isfinite(root).all():
        raise InvalidParameterError("robot: the position has no finite enclosure over the joint limits")
    box = Box(model.task_variables, tuple(root[:, 0]), tuple(root[:, 1]))
    T = root[None].copy()
    owner = np.zeros(1, dtype=int)
    inner, boundary, outer = [], [], []
    evaluated, reason = 0, ""
    run.total = box.measure
    step = _ReachStep(robot, parameters, float(delta), size, inner_depth, int(max_pairs), float(_volumes(T)[0]))
    spread = None if executor is None else _runner(executor, step)
    try:
        while len(T):
            reason = run.stop_reason(evaluated)
            if reason:
                break
            pieces = max(1, math.ceil(len(Q) / chunk_pairs))
            if spread is None:
                results = [step(part) for part in _parts(T, Q, owner, pieces)]
            else:
                pieces = max(pieces, min(spread.slots, math.ceil(len(T) / _MIN_CHUNK)))
                results = [f.result() for f in [spread.submit(part) for part in _parts(T, Q, owner, pieces)]]
            evaluated += len(T)
            children, pairs, owners = [], [], []
            for i, b, o, c, q, w in results:
                inner.append(i)
                boundary.append(b)
                outer.append(o)
                owners.append(w + sum(map(len, children)))
                children.append(c)
                pairs.append(q)
            T, Q, owner = np.concatenate(children), np.concatenate(pairs), np.concatenate(owners)
            if run.showing:
                run.show(box.measure - box_measure(T), evaluated)
    except KeyboardInterrupt:
        reason = "interrupted"
    finally:
        if spread is not None:
            spread.close()
        run.close()
    m = len(model.task_variables)
    empty = np.empty((0, m, 2))

    def stack(parts):
        return np.concatenate(parts) if parts else empty

    return Paving(model.task_variables, box, (), float(delta), "numpy", size, stack(inner), stack(boundary),
                  stack(outer), T if len(T) and reason else empty, run.seconds, not reason,
                  evaluated, reason)
