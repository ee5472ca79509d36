"""The pairs method: task boxes carried with the joint boxes that may reach them; one loop for positions and poses.

Each task box carries joint boxes covering every configuration whose position may lie in it; the root task box is
the enclosure of the position over the limits.  When a task box is split, a joint box goes to each half its
enclosure meets (refined by bisection while wider than the half,
:func:`~workspace_sym.interval.image.distribute`); a task box left without joint boxes is outer.  Inner proofs:
the Krawczyk test of :class:`~workspace_sym.interval.image.ImageMap` around a Newton solution for the box centre,
the last boxes before the boundary tried in pieces (:func:`prove_in_pieces`).  With a tool constraint the joint
boxes carry wrist values and an admissibility status, and the step is the pose model's
(:class:`~workspace_sym.serial.pose.PoseStep`); the loop is the same.

:func:`pave_pairs` is that loop.  Its unit of work is a task box together with a variable number of joint boxes
(``Q``, and ``owner``, the task box each belongs to), not a box, so it is not the paving driver's loop: a task box
is decided from its joint boxes (which are refined on the way), its children inherit them (:func:`split_pairs`),
and chunks are cut by number of pairs (:func:`parts`).  It stores its decided boxes in the driver's
:class:`~workspace_sym.interval.store.BoxStore` and its caller writes the driver's checkpoints, with the task boxes
left and their joint boxes as extra arrays.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..interval.boxes import box_sizes, halves
from ..interval.executor import MIN_CHUNK
from ..interval.image import distribute
from ..interval.search import split_every_axis
from ..interval.store import BoxStore, measures_of
from ..kinematics import DHRobot
from .model import reach_model

__all__ = ["CHUNK_PAIRS", "prove_in_pieces", "split_pairs", "parts", "caps", "PositionStep", "pave_pairs"]

CHUNK_PAIRS = 100_000            # (joint box, task box) pairs in one chunk of work (RunOn.chunk): boxes unchanged


def prove_in_pieces(model, T, seeds, depth):
    """Mask of the boxes ``T`` proved inside the image, box ``i`` cut into up to ``2^(m depth[i])`` pieces
    (halved along every edge per level) of which every one must pass the test.

    Parameters
    ----------
    model : ImageMap
        The map whose ``prove_inside(T, seeds)`` tests the pieces.
    T : numpy.ndarray
        ``(N, m, 2)`` task boxes.
    seeds : numpy.ndarray
        ``(N, k)`` configurations, one per box, from which each of its pieces is tried.
    depth : numpy.ndarray
        ``(N,)`` whole numbers: how many levels of pieces each box may be cut into (0: the box whole only).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` booleans: the boxes proved inside.
    """
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


def split_pairs(T, Q, owner, is_in, is_out, delta: float, size: str):
    """One step of the pair method after its proofs: ``(inner, boundary, outer, children, Q, owner)``.

    Undecided task boxes of size at most ``delta`` (or too thin to halve in floats) are boundary boxes; the
    others are halved, and both halves inherit the joint boxes ``Q`` their parent owned.

    Parameters
    ----------
    T : numpy.ndarray
        ``(N, m, 2)`` task boxes.
    Q : numpy.ndarray
        The joint boxes of the pairs, ``(P, k, 2)``.
    owner : numpy.ndarray
        ``(P,)`` the index in ``T`` of each pair's task box.
    is_in, is_out : numpy.ndarray
        ``(N,)`` masks of the task boxes proved inner and outer.
    delta : float
        Undecided task boxes of size at most ``delta`` are boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured.

    Returns
    -------
    tuple
        ``(inner, boundary, outer, children, Q, owner)``: the decided task boxes of each kind, the halves of the
        others, and their pairs (each joint box of a halved box twice, ``owner`` indexing ``children``).
    """
    und = ~is_out & ~is_in
    small = und & (box_sizes(T, size) <= delta)
    split = und & ~small
    children, ok = halves(T[split])
    boundary = np.concatenate([T[small], T[split][~ok]])     # too thin to split: delta below float resolution
    split[np.nonzero(split)[0][~ok]] = False
    children = children.reshape(-1, 2, *T.shape[1:])[ok].reshape(-1, *T.shape[1:])
    new_index = np.full(len(T), -1)
    new_index[split] = np.arange(split.sum())
    pair = new_index[owner] >= 0
    Q, base = Q[pair], new_index[owner[pair]]
    return T[is_in], boundary, T[is_out], children, np.concatenate([Q, Q]), np.concatenate([2 * base, 2 * base + 1])


def parts(T, Q, owner, pieces: int):
    """The task boxes cut into ``pieces`` runs of consecutive boxes, each with its own pairs in their order.

    Parameters
    ----------
    T : numpy.ndarray
        ``(N, m, 2)`` task boxes.
    Q : numpy.ndarray
        The joint boxes of the pairs.
    owner : numpy.ndarray
        The index in ``T`` of each pair's task box.
    pieces : int
        How many runs (``numpy.array_split`` of the task boxes; empty runs are skipped).

    Yields
    ------
    tuple
        ``(T, Q, owner)`` of one run, ``owner`` counted from the run's first task box.
    """
    order = np.argsort(owner, kind="stable")
    Q, owner = Q[order], owner[order]
    for rows in np.array_split(np.arange(len(T)), pieces):
        if len(rows):
            a, b = rows[0], rows[-1] + 1
            lo, hi = np.searchsorted(owner, [a, b])
            yield T[a:b], Q[lo:hi], owner[lo:hi] - a


def caps(T: np.ndarray, max_pairs: int, min_pairs: int, root_measure: float) -> np.ndarray:
    """The pairs each task box may hold: in proportion to its share of the root box, and at least ``min_pairs``.

    Parameters
    ----------
    T : numpy.ndarray
        ``(N, m, 2)`` task boxes.
    max_pairs : int
        The pairs the whole root box may hold.
    min_pairs : int
        The pairs any box may hold.
    root_measure : float
        The measure of the root box.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` whole numbers (as floats): ``max(min_pairs, floor(max_pairs measure / root_measure))``.
    """
    return np.maximum(min_pairs, np.floor(max_pairs * (measures_of(T) / root_measure)))


@dataclass(frozen=True)
class PositionStep:
    """One generation of the pairs method on a chunk of task boxes with their pairs, for the position alone
    (picklable: the robot travels to the workers, the model is compiled there once).

    Called with ``(T, Q, owner)``, it returns the inner, boundary and outer
    task boxes, the children of the split ones and their pairs ``(Q, owner)``.
    Each task box is treated on its own (:func:`~workspace_sym.interval.image.distribute`), so chunks give
    together exactly what one call on all the boxes gives.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    delta : float
        Undecided task boxes of size at most ``delta`` are boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured.
    inner_depth : int
        Levels of pieces a task box about to become a boundary box is tried in (:func:`prove_in_pieces`).
    max_pairs, min_pairs : int
        The caps of pairs per task box (:func:`caps`).
    root_measure : float
        The measure of the root task box.
    """

    robot: DHRobot
    parameters: tuple
    delta: float
    size: str
    inner_depth: int
    max_pairs: int
    min_pairs: int
    root_measure: float

    def __call__(self, part):
        T, Q, owner = part
        model = reach_model(self.robot, self.parameters)
        Q, owner = distribute(model, T, Q, owner, caps(T, self.max_pairs, self.min_pairs, self.root_measure))
        count = np.bincount(owner, minlength=len(T))
        is_out = count == 0
        # One seed per task box: the centre of its first joint box.
        live, first = np.unique(owner, return_index=True)
        is_in = np.zeros(len(T), dtype=bool)
        if len(live):
            seeds = Q[first].mean(axis=2)
            # A box that would become a boundary box is also tried in pieces (every piece proved).
            last = box_sizes(T[live], self.size) <= self.delta
            is_in[live] = prove_in_pieces(model, T[live], seeds, np.where(last, self.inner_depth, 0))
        return split_pairs(T, Q, owner, is_in, is_out, self.delta, self.size)


def pave_pairs(step, T, Q, owner, *, budget, keeper: BoxStore, chunk: int, spread=None, show=None):
    """The pairs loop from task boxes ``T`` with their pairs ``(Q, owner)``: ``(T, Q, owner, evaluated,
    reason)``, the task boxes left (none when complete) with their pairs, the task boxes evaluated, and why the
    loop stopped (``""`` when complete).

    Generation after generation, the task boxes are cut into chunks of about ``chunk`` pairs (at least one per
    slot of ``spread``, a :class:`~workspace_sym.interval.executor.Runner`, when given), handed to ``step`` in
    waves (one chunk here, one per slot there); the budget (a
    :class:`~workspace_sym.interval.driver.RunBudget`) is asked before each wave, with the seconds the wave is
    expected to take (the last wave's seconds per task box and pair), and a wave expected to end past the time
    limit is not started: its task boxes stay pending with their joint boxes, as do those of a wave Ctrl-C
    stops.  The decided boxes go to ``keeper`` wave by wave; ``show(share decided, evaluated)`` after each.

    Parameters
    ----------
    step : callable
        One generation on ``(T, Q, owner)``, returning what :func:`split_pairs` returns
        (:class:`PositionStep`, :class:`~workspace_sym.serial.pose.PoseStep`).
    T : numpy.ndarray
        ``(N, m, 2)`` task boxes to start from.
    Q : numpy.ndarray
        Their pairs' joint boxes.
    owner : numpy.ndarray
        The index in ``T`` of each pair's task box.
    budget : RunBudget
        Asked before each wave.
    keeper : BoxStore
        Where the decided boxes go.
    chunk : int
        About this many pairs in one chunk.
    spread : Runner, optional
        Where the chunks run, one per slot; None: here, one at a time.
    show : callable, optional
        ``show(share decided, evaluated)``, the share of the first task box's measure.

    Returns
    -------
    tuple
        ``(T, Q, owner, evaluated, reason)``: the task boxes left with their pairs, the number of task boxes
        handed to ``step`` in this call, and why the loop stopped (``""`` when no task box is left).
    """
    whole = float(measures_of(T[:1])[0]) if len(T) else 0.0
    evaluated, reason, rate, decided = 0, "", 0.0, 0.0
    while len(T):
        pieces = max(1, math.ceil(len(Q) / chunk))
        if spread is not None:
            pieces = max(pieces, min(spread.slots, math.ceil(len(T) / MIN_CHUNK)))
        cut = list(parts(T, Q, owner, pieces))
        width = 1 if spread is None else spread.slots
        children, pairs, owners, count, left = [], [], [], 0, []
        for w in range(0, len(cut), width):
            wave = cut[w:w + width]
            work = sum(len(t) + len(q) for t, q, _ in wave)
            reason = budget.stop_reason(evaluated, ahead=rate * work)
            if not reason:
                try:
                    start = time.perf_counter()
                    results = ([step(wave[0])] if spread is None else
                               [f.result() for f in [spread.submit(part) for part in wave]])
                    rate = (time.perf_counter() - start) / max(1, work)
                except KeyboardInterrupt:
                    reason = "interrupted"
            if reason:
                left = cut[w:]
                break
            for i, b, o, c, q, o_c in results:
                for kind, boxes in (("inner", i), ("boundary", b), ("outer", o)):
                    keeper.add(kind, boxes)
                    decided += float(measures_of(boxes).sum()) if len(boxes) else 0.0
                owners.append(o_c + count)
                count += len(c)
                children.append(c)
                pairs.append(q)
            evaluated += sum(len(t) for t, _, _ in wave)
            if show is not None:
                show(decided / whole if whole > 0 else 1.0, evaluated)
        for t, q, o in left:                     # pending, with their joint boxes
            owners.append(o + count)
            count += len(t)
            children.append(t)
            pairs.append(q)
        T = np.concatenate(children) if children else T[:0]
        Q = np.concatenate(pairs) if pairs else Q[:0]
        owner = np.concatenate(owners) if owners else owner[:0]
        if left:
            break
    return T, Q, owner, evaluated, reason if len(T) else ""
