"""Forward-backward contraction (HC4-revise) of a constraint set, on arrays of boxes.

The constraints ``g_j(x) <= 0`` are written once as a straight-line program
over their expression DAG (common subexpressions shared: Rybak's four
constraints share ``x^2 + y^2`` and ``(x - 5)^2 + y^2``).  A forward sweep
encloses every node over a box; a backward sweep intersects each root with a
target (``[-inf, 0]`` for the constraint, ``[0, inf]`` for its negation) and
projects it back onto the children through the inverse of each operation,
outward-rounded, down to the variables.  The result encloses every point of
the box where the targets are met, so what it cuts off is proved:

* contracting with all constraints at ``[-inf, 0]`` gives ``C_out``: the points
  of ``B \\ C_out`` violate some constraint (outer);
* contracting with each ``g_j`` at ``[0, inf]`` and taking the hull gives
  ``C_in``: the points of ``C_out \\ C_in`` satisfy every constraint (inner).

This is the separator of Jaulin's set inversion (``codac.SepInverse``) on the
program of the constraints (:class:`~workspace_sym.interval.graph.Graph`).
:func:`~workspace_sym.interval.paving.pave` takes the slices as proposals
only: it declares a slice inner or outer when its forward evaluation, the
test of every other box, proves it too, whole or piece by piece
(:func:`confirm`), so that a slip in an inverse
operation or in a rewriting cannot become a false certificate.  A box is contracted only where its whole
forward sweep is finite: there every function in it is defined and
continuous, so a point cut off really satisfies, or violates, the
constraints; a domain error or a divisor containing zero leaves the box as
it is (undecided).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import arith
from .boxes import halves
from .graph import Graph
from .verdict import CODE, INSIDE, OUTSIDE, UNDECIDED

__all__ = ["Program", "Separation", "confirm", "CONFIRM_DEPTH"]

_INF = np.inf
_ONE = (1.0, 1.0)
_ROOT_REL = 1e-12   # covers pow(x, 1/n) with 1/n rounded: |ln x| 2^-53 / n < 1e-13 for finite x
CONFIRM_DEPTH = 6   # a proposed slice is checked in at most 2^6 pieces
_CONFIRM_STEP = 3   # ... decided after every third bisection (numpy's cost per call dominates on a few boxes)


@dataclass(frozen=True, slots=True, eq=False)
class Separation:
    """Result of :meth:`Program.separate` on ``N`` boxes.

    ``inner`` and ``outer`` are ``(M, n, 2)`` arrays of proved slices;
    ``kept`` is ``(N', n, 2)``, the undecided remainder of each box that was
    not wholly decided.  Together they tile the input boxes.  ``inner_from``,
    ``outer_from`` and ``kept_from``, when given, are the indices of the
    input box each of them was cut from.

    Parameters
    ----------
    inner, outer : numpy.ndarray
        ``(M, n, 2)`` slices proposed inside and outside.
    kept : numpy.ndarray
        ``(N', n, 2)`` undecided remainders.
    inner_from, outer_from, kept_from : numpy.ndarray of int or None
        The index of the input box each slice or remainder comes from (None: not given;
        :meth:`Program.separate` gives them).
    """

    inner: np.ndarray
    outer: np.ndarray
    kept: np.ndarray
    inner_from: np.ndarray | None = None
    outer_from: np.ndarray | None = None
    kept_from: np.ndarray | None = None


def _root(x, n: int, upward: bool):
    """An outward bound of the real ``n``-th root of ``x`` (odd ``n``: sign kept; even: ``x >= 0``)."""
    if n == 2:
        r = np.sqrt(x)
        return arith.up(r) if upward else np.maximum(arith.down(r), 0.0)
    r = np.sign(x) * np.power(np.abs(x), 1.0 / n)
    step = np.abs(r) * _ROOT_REL + 2.0**-1074
    return r + step if upward else r - step


def _square_inverse(z):
    """``{a : sqrt(a) in z}``, outward."""
    lo, hi = np.maximum(z[0], 0.0), z[1]
    return np.maximum(arith.down(lo * lo), 0.0), arith.up(hi * hi)


def _intersect(old, new):
    """``old`` cut by ``new``; a NaN bound of ``new`` (a failed inverse) cuts nothing."""
    return np.fmax(old[0], new[0]), np.fmin(old[1], new[1])


def _columns(boxes):
    return [(boxes[:, k, 0], boxes[:, k, 1]) for k in range(boxes.shape[1])]


def _peel(outer_box, inner_box):
    """Boxes tiling ``outer_box \\ inner_box`` (``inner_box`` inside it): at most two slabs a dimension; also the
    index of the box each slab comes from."""
    n = outer_box.shape[1]
    slabs, sources = [outer_box[:0]], [np.empty(0, dtype=np.intp)]
    current = outer_box.copy()
    for k in range(n):
        below = inner_box[:, k, 0] > current[:, k, 0]
        if below.any():
            s = current[below].copy()
            s[:, k, 1] = inner_box[below, k, 0]
            slabs.append(s)
            sources.append(np.nonzero(below)[0])
        above = inner_box[:, k, 1] < current[:, k, 1]
        if above.any():
            s = current[above].copy()
            s[:, k, 0] = inner_box[above, k, 1]
            slabs.append(s)
            sources.append(np.nonzero(above)[0])
        current[:, k, :] = inner_box[:, k, :]
    return np.concatenate(slabs), np.concatenate(sources)


def confirm(decide, inner: np.ndarray, outer: np.ndarray, *, depth: int = CONFIRM_DEPTH):
    """Masks of the proposed ``inner`` and ``outer`` slices that ``decide`` proves so, whole or piece by piece.

    A proposed slice that the forward evaluation leaves undecided may still
    be outer (inner) everywhere with no single constraint proving it: near
    a corner of Rybak's workspace one part of a slice violates
    ``x1^2 + x2^2 <= 144`` and the rest ``(x1 - 5)^2 + x2^2 >= 64``.  Such a
    box is bisected, up to ``depth`` times, and counts when ``decide`` proves
    every piece (the pieces tile it: closed halves sharing their middle face).
    A piece proved the other way, or too thin to split and unproved, fails
    its box.  Only ``decide`` proves, so a slip in an inverse operation of the
    contraction cannot become a verdict.  Both kinds share each call of
    ``decide``, made after every third bisection of the undecided pieces.

    Parameters
    ----------
    decide : Decider
        The verdicts of the paving.
    inner, outer : numpy.ndarray
        ``(M, n, 2)`` slices proposed inside and outside.
    depth : int
        The most bisections of a slice (default :data:`CONFIRM_DEPTH`: up to ``2^6`` pieces).

    Returns
    -------
    tuple of numpy.ndarray of bool
        ``(proved_inner, proved_outer)``: one flag a slice of ``inner`` and of ``outer``.
    """

    boxes = np.concatenate([inner, outer])
    want = np.repeat(np.array([INSIDE, OUTSIDE], dtype=CODE), [len(inner), len(outer)])
    codes = decide(boxes)
    tried = codes == UNDECIDED
    owner = np.nonzero(tried)[0]
    pieces, failed = boxes[owner], np.zeros(len(boxes), dtype=bool)
    shape = boxes.shape[1:]
    for level in range(0, depth, _CONFIRM_STEP):
        if not len(pieces):
            break
        for _ in range(min(_CONFIRM_STEP, depth - level)):      # bisected a few times between two decisions
            children, split = halves(pieces)
            failed[owner[~split]] = True
            pieces = children.reshape(-1, 2, *shape)[split].reshape(-1, *shape)
            owner = np.repeat(owner[split], 2)
        piece_codes = decide(pieces)
        failed[owner[(piece_codes != want[owner]) & (piece_codes != UNDECIDED)]] = True
        still = (piece_codes == UNDECIDED) & ~failed[owner]
        pieces, owner = pieces[still], owner[still]
    failed[owner] = True                     # pieces still undecided after the last split
    proved = (codes == want) | (tried & ~failed)
    return proved[:len(inner)], proved[len(inner):]


class Program:
    """The constraints ``g_j <= 0`` as one straight-line program, with forward and backward sweeps.

    Parameters
    ----------
    expressions : iterable of sympy.Expr
        The ``g_j``.
    variables : iterable of sympy.Symbol
        The box's variables, in order.
    min_gain : float
        A contraction by less than this fraction of a box's edge is not applied (the slab it would cut off is
        not worth a box); default ``1e-3``.
    passes : int
        Forward-backward sweeps per cut, each on the box the previous one left (stops early at a fixed
        point).  One is the default: on Rybak's robot a second pass shrinks the final boundary by 0.2 % and
        changes the bisection tree more than it gains.

    Raises
    ------
    ExpressionError
        For an operation the interval compiler does not support, or a symbol that is not a variable
        (:class:`~workspace_sym.interval.graph.Graph`).

    Examples
    --------
    >>> import sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> prog = Program([x**2 + y**2 - 1], (x, y))
    >>> s = prog.separate(np.array([[[0.0, 2.0], [0.0, 0.5]]]))
    >>> float(s.kept[0, 0, 1]) <= 1.0000001      # x <= 1 wherever x^2 + y^2 <= 1
    True
    """

    def __init__(self, expressions, variables, *, min_gain: float = 1e-3, passes: int = 1):
        self.graph = Graph(expressions, variables)
        self.variables = self.graph.variables
        self.nodes = self.graph.nodes
        self.roots = self.graph.roots
        self.passes = int(passes)
        self.min_gain = float(min_gain)
        self._order = self._reachable(self.roots)

    def _reachable(self, roots):
        """Indices of the nodes under ``roots``, parents before children (the backward order)."""
        seen, stack = set(), list(roots)
        while stack:
            i = stack.pop()
            if i not in seen:
                seen.add(i)
                stack.extend(self.nodes[i][1])
        return sorted(seen, reverse=True)      # a child is always built before its parents

    # -------------------------------------------------------------- sweeps
    def forward(self, X):
        """Enclosures ``(lo, hi)`` of every node over the boxes ``X`` (a list of ``(lo, hi)`` arrays).

        Parameters
        ----------
        X : list of pair of numpy.ndarray
            One ``(lo, hi)`` interval per variable.

        Returns
        -------
        list of tuple
            The enclosure of every node of the graph, NaN meaning none.
        """
        return self.graph.forward(X)

    def _backward(self, forward, targets, order, shape):
        """Variables' enclosures after cutting ``targets`` (root index -> interval); also the empty mask."""
        vals = list(forward)
        empty = np.zeros(shape, dtype=bool)
        for r, t in targets.items():
            vals[r] = _intersect(vals[r], t)
        for i in order:
            kind, ch, p = self.nodes[i]
            z = vals[i]
            empty |= z[0] > z[1]
            if kind in ("var", "const", "sin", "cos"):
                continue
            for pos, c in enumerate(ch):
                if self.nodes[c][0] != "const":
                    vals[c] = _intersect(vals[c], self._inverse(kind, pos, [vals[k] for k in ch], z, p))
        n = len(self.variables)
        for k in range(n):
            empty |= vals[k][0] > vals[k][1]
        return vals[:n], empty

    @classmethod
    def _inverse(cls, kind, pos, args, z, p):
        """Enclosure of the values of argument ``pos`` of a node that are consistent with its value ``z``."""
        if kind == "add":
            return arith.sub(z, args[1 - pos])
        if kind == "mul":
            return arith.div(z, args[1 - pos])        # the whole line when the other factor contains 0
        if kind == "neg":
            return arith.neg(z)
        if kind == "recip":
            return arith.div(_ONE, z)
        if kind == "sqrt":
            return _square_inverse(z)
        if kind == "abs":
            return -z[1], z[1]
        return cls._pow_inverse(args[0], z, p)

    @staticmethod
    def _pow_inverse(a, z, n):
        """Enclosure of ``{x in a : x^n in z}``."""
        if n % 2:
            return _root(z[0], n, False), _root(z[1], n, True)
        top = _root(np.maximum(z[1], 0.0), n, True)
        low = _root(np.maximum(z[0], 0.0), n, False)
        # x in [-top, -low] or [low, top]; a branch is out when ``a`` misses it (a.lo > -low: no negative
        # solution in ``a``; a.hi < low: no positive one).  Both out: lo > hi, an empty result.
        lo = np.where((a[0] >= 0) | (a[0] > -low), low, -top)
        hi = np.where((a[1] <= 0) | (a[1] < low), -low, top)
        return lo, hi

    # -------------------------------------------------------------- separation
    def _defined(self, vals, shape):
        ok = np.ones(shape, dtype=bool)
        for (kind, _, _), (lo, hi) in zip(self.nodes, vals):
            if kind != "const":
                ok &= np.isfinite(lo) & np.isfinite(hi)
        return ok

    def _relax(self, boxes, contracted, empty):
        """The contracted boxes, one float wider each way, with contractions below ``min_gain`` of an edge undone.

        The extra float matters on the faces: a slice cut off is a closed box
        sharing a face with the contracted box, and a contraction can be
        exact (``x1 <= 0`` cuts at 0 itself), so the face must lie strictly
        beyond every point the contraction kept.
        """
        out = np.stack([np.stack([np.nextafter(lo, -_INF), np.nextafter(hi, _INF)], axis=-1)
                        for lo, hi in contracted], axis=1)
        out = np.clip(out, boxes[:, :, :1], boxes[:, :, 1:])
        tol = self.min_gain * (boxes[:, :, 1] - boxes[:, :, 0])
        small_lo = out[:, :, 0] - boxes[:, :, 0] < tol
        small_hi = boxes[:, :, 1] - out[:, :, 1] < tol
        out[:, :, 0] = np.where(small_lo, boxes[:, :, 0], out[:, :, 0])
        out[:, :, 1] = np.where(small_hi, boxes[:, :, 1], out[:, :, 1])
        bad = np.isnan(out).any(axis=(1, 2)) & ~empty
        out[bad] = boxes[bad]
        return out

    def _contract(self, boxes, vals, targets, order, passes):
        """``boxes`` cut to the points meeting ``targets``, and the mask of boxes with no such point.

        ``vals`` is the forward sweep over ``boxes``; each further pass sweeps
        the contracted boxes again (tighter enclosures, further cuts) until
        nothing changes or ``passes`` is reached.
        """
        shape = (len(boxes),)
        empty = np.zeros(shape, dtype=bool)
        current = boxes
        for k in range(passes):
            if k:
                vals = self.forward(_columns(current))
            c, e = self._backward(vals, targets, order, shape)
            empty |= e
            new = self._relax(current, c, empty)
            if np.array_equal(new, current):
                break
            current = new
        return current, empty

    def separate(self, boxes: np.ndarray) -> Separation:
        """Split each box into proved outer slices, proved inner slices and an undecided remainder.

        One backward sweep serves all cuts: the boxes are stacked ``m + 1``
        times, the first copy cut by every constraint (``g_j <= 0``), copy
        ``j + 1`` by the negation of constraint ``j`` alone (``g_j >= 0``).

        Parameters
        ----------
        boxes : numpy.ndarray
            ``(N, n, 2)`` boxes.

        Returns
        -------
        Separation
            The slices and remainders, with the index of the box each comes from.  A box whose forward sweep
            is not finite everywhere is not cut: it is kept whole.
        """
        boxes = np.asarray(boxes, dtype=float)
        N, n = boxes.shape[:2]
        if N == 0:
            none = np.empty(0, dtype=np.intp)
            return Separation(boxes, boxes, boxes, none, none, none)
        m = len(self.roots)
        stacked = np.concatenate([boxes] * (m + 1))
        with np.errstate(all="ignore"):
            vals = self.forward(_columns(stacked))
            defined = self._defined(vals, ((m + 1) * N,))[:N]
            targets: dict = {}
            for j, r in enumerate(self.roots):
                lo, hi = np.full((m + 1, N), -_INF), np.full((m + 1, N), _INF)
                hi[0] = 0.0
                lo[j + 1] = 0.0
                t = (lo.ravel(), hi.ravel())
                targets[r] = _intersect(targets[r], t) if r in targets else t
            cut, empty = self._contract(stacked, vals, targets, self._order, self.passes)
        cut, empty = cut.reshape(m + 1, N, n, 2), empty.reshape(m + 1, N)
        c_out, out_empty = cut[0], empty[0] & defined
        # The cut by "some g_j > 0" is the hull of the cuts by each g_j >= 0 (an empty cut adds nothing),
        # taken within c_out.
        lo = np.where(empty[1:, :, None], _INF, cut[1:, :, :, 0]).min(axis=0)
        hi = np.where(empty[1:, :, None], -_INF, cut[1:, :, :, 1]).max(axis=0)
        c_in = np.stack([np.maximum(lo, c_out[:, :, 0]), np.minimum(hi, c_out[:, :, 1])], axis=-1)
        # No point violating a constraint in the box, or none within c_out: all of c_out is inner.
        in_empty = (empty[1:].all(axis=0) | (c_in[:, :, 0] > c_in[:, :, 1]).any(axis=1)) & defined & ~out_empty
        c_out[~defined] = boxes[~defined]
        c_in[~defined] = boxes[~defined]
        live = ~out_empty
        index = np.nonzero(live)[0]
        outer_slabs, outer_from = _peel(boxes[live], c_out[live])
        live &= ~in_empty
        kept_from = np.nonzero(live)[0]
        inner_slabs, inner_from = _peel(c_out[live], c_in[live])
        return Separation(np.concatenate([c_out[in_empty], inner_slabs]),
                          np.concatenate([boxes[out_empty], outer_slabs]),
                          c_in[live], inner_from=np.concatenate([np.nonzero(in_empty)[0], kept_from[inner_from]]),
                          outer_from=np.concatenate([np.nonzero(out_empty)[0], index[outer_from]]),
                          kept_from=kept_from)
