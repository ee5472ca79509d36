"""Boxes and what a paving returns: :class:`Box`, arrays of boxes (sizes, halves, measures), :class:`Paving` and
:class:`StoredPaving` (the same, its decided boxes on disk).

Every layer of the engine above the deciders works on ``(N, n, 2)`` float arrays of boxes; this module holds
what they share about them and the result objects, below the driver (:mod:`~workspace_sym.interval.driver`),
which builds them, and the constraint pavings (:mod:`~workspace_sym.interval.paving`), which return them.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import sympy as sp

from ..errors import BoxError, ExpressionError, InvalidParameterError
from ..expressions import parse_expr
from ..numbers import fmt_bracket
from .store import KINDS, ExactSum, measures_of

__all__ = ["Box", "SIZES", "check_delta", "box_sizes", "halves", "bisect", "box_measure", "Paving", "StoredPaving"]

SIZES = ("diameter", "width")


@dataclass(frozen=True, slots=True)
class Box:
    """An axis-aligned box ``[lower_k, upper_k]`` over named variables.

    Parameters
    ----------
    variables : tuple of sympy.Symbol
        The variables, one per edge.
    lower, upper : tuple of float
        The bounds of each edge.  The constructor takes the fields as given; :meth:`from_bounds` checks them.

    Raises
    ------
    BoxError
        From :meth:`from_bounds`, for bounds that do not make a box.

    Examples
    --------
    >>> Box.from_bounds({"x": (0, 1), "y": (-1, 2)})
    Box(x in [0.0, 1.0], y in [-1.0, 2.0])
    >>> Box.from_bounds({"x": (1, 0)})
    Traceback (most recent call last):
    ...
    workspace_sym.errors.BoxError: box: lower bound of x (1) must not exceed its upper bound (0)
    """

    variables: tuple
    lower: tuple
    upper: tuple

    @classmethod
    def from_bounds(cls, bounds, variables=None) -> Box:
        """From ``{var: (lo, hi)}`` or a sequence of pairs with ``variables``.

        Bounds are numbers or text read by :func:`~workspace_sym.expressions.parse_expr`
        (``"-pi/2"``), rounded to the nearest float.

        Parameters
        ----------
        bounds : dict, sequence of pairs or Box
            ``{variable: (lo, hi)}`` (a variable is a name or a SymPy symbol), or ``(lo, hi)`` pairs in the
            order of ``variables``; a Box is returned as it is.
        variables : sequence of str or sympy.Symbol, optional
            The variables of a sequence of pairs (needed then; ignored with a dict).

        Returns
        -------
        Box
            The box.

        Raises
        ------
        BoxError
            For a sequence without ``variables`` or of another length, no variable, a variable given twice, a
            bound that is not a number, an infinite bound or width, a lower bound above its upper bound, or a
            measure that overflows double precision.
        ExpressionError
            For text that is not a constant expression.
        """
        if isinstance(bounds, Box):
            return bounds
        if isinstance(bounds, dict):
            variables = tuple(sp.Symbol(v) if isinstance(v, str) else v for v in bounds)
            pairs = list(bounds.values())
        else:
            pairs = list(bounds)
            if variables is None:
                raise BoxError("box: a list of bounds needs variables=...; or pass {variable: (lo, hi)}")
            variables = tuple(sp.Symbol(v) if isinstance(v, str) else v for v in variables)
            if len(variables) != len(pairs):
                raise BoxError(f"box: {len(pairs)} bounds for {len(variables)} variables")
        if not pairs:
            raise BoxError("box: at least one variable is needed; got an empty box")
        repeated = sorted({str(v) for v in variables if list(map(str, variables)).count(str(v)) > 1})
        if repeated:
            raise BoxError(f"box: each variable needs one range; {', '.join(repeated)} is given more than once")
        lower, upper = [], []
        for v, pair in zip(variables, pairs):
            try:
                lo, hi = pair
                lo_f, hi_f = (float(parse_expr(b, f"box: {side} bound of {v}", new_symbols=False))
                              if isinstance(b, str) else float(b) for side, b in (("lower", lo), ("upper", hi)))
            except ExpressionError:
                raise
            except (TypeError, ValueError):
                raise BoxError(f"box: bounds of {v} must be two numbers; got {pair!r}") from None
            if not (math.isfinite(lo_f) and math.isfinite(hi_f)):
                raise BoxError(f"box: bounds of {v} must be finite; got [{lo}, {hi}]")
            if lo_f > hi_f:
                raise BoxError(f"box: lower bound of {v} ({lo}) must not exceed its upper bound ({hi})")
            if not math.isfinite(hi_f - lo_f):
                raise BoxError(f"box: bounds of {v} must be finite with a finite width; got [{lo}, {hi}], whose "
                               "width overflows double precision")
            lower.append(lo_f)
            upper.append(hi_f)
        if not math.isfinite(math.prod(h - lo_ for lo_, h in zip(lower, upper))):
            raise BoxError(f"box: the measure of the box overflows double precision; got "
                           f"{', '.join(f'{v} in [{a:g}, {b:g}]' for v, a, b in zip(variables, lower, upper))}")
        return cls(variables, tuple(lower), tuple(upper))

    @property
    def array(self) -> np.ndarray:
        """``(n, 2)`` array of bounds."""
        return np.array([self.lower, self.upper]).T

    @property
    def measure(self) -> float:
        """The product of the edge widths (area, volume), in floats (not rounded outward).

        Returns
        -------
        float
            The measure.
        """
        return float(np.prod(np.subtract(self.upper, self.lower)))

    def __repr__(self):
        parts = ", ".join(f"{v} in [{lo!r}, {hi!r}]" for v, lo, hi in zip(self.variables, self.lower, self.upper))
        return f"Box({parts})"



def box_measure(boxes: np.ndarray) -> float:
    """Total measure (area, volume) of an ``(N, n, 2)`` array of boxes.

    The measures of the boxes (products of float edge widths) are summed
    exactly and rounded once (:class:`~workspace_sym.interval.store.ExactSum`):
    the total does not depend on the order of the boxes, so a distributed or
    resumed run gives the same figure as a local one.

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.

    Returns
    -------
    float
        The sum of the float measures of the boxes, rounded to nearest once; 0.0 for no box.
    """
    if len(boxes) == 0:
        return 0.0
    return ExactSum.of(measures_of(np.asarray(boxes))).value


@dataclass(frozen=True, eq=False)
class Paving:
    """Result of :func:`pave`: inner, boundary, outer and pending boxes, each an ``(N, n, 2)`` array.

    ``pending`` boxes are those a stopped run (budget, time limit, Ctrl-C)
    did not examine: they are neither proved nor classified.  ``units`` is the
    length unit of the variables when they are lengths (a robot's workspace
    from ``reach``), for the axes of its pictures.

    Parameters
    ----------
    variables : tuple of sympy.Symbol
        The variables of the boxes' edges.
    box : Box
        The box that was paved.
    constraints : tuple
        The constraints paved (:class:`~workspace_sym.interval.paving.Constraint`); empty when the paving
        comes from another decider.
    delta : float
        Undecided boxes of size at most ``delta`` were not split further.
    backend : str
        ``"numpy"`` or ``"mpmath"``: the arithmetic that decided the boxes.
    size : str
        How a box's size was measured against ``delta``: ``"diameter"`` or ``"width"`` (:data:`SIZES`).
    inner, boundary, outer, pending : numpy.ndarray
        ``(N, n, 2)`` boxes: proved inside, undecided down to ``delta``, proved outside, not examined.
    seconds : float
        Wall-clock seconds of the run, with those of the earlier parts of a resumed one.
    complete : bool
        True when no box is pending.
    evaluated : int
        Number of boxes the decider evaluated.
    stop_reason : str
        Why a run stopped with boxes pending (``"time limit of 5 s reached"``, ``"budget of 1000 boxes reached"``,
        ``"interrupted"``); ``""`` for a complete one.
    exact_measure : sympy.Expr or None
        The exact measure of the set, when known (:meth:`with_exact_measure`).
    contract : bool
        Whether boxes were contracted as well as bisected.
    units : str or None
        The length unit of the variables, when they are lengths.
    """

    variables: tuple
    box: Box
    constraints: tuple
    delta: float
    backend: str
    size: str
    inner: np.ndarray
    boundary: np.ndarray
    outer: np.ndarray
    pending: np.ndarray
    seconds: float
    complete: bool
    evaluated: int
    stop_reason: str = ""
    exact_measure: object = field(default=None)
    contract: bool = False
    units: str | None = None

    @property
    def counts(self) -> dict:
        """Number of boxes of each class."""
        return {k: len(getattr(self, k)) for k in ("inner", "boundary", "outer", "pending")}

    @cached_property
    def measures(self) -> dict:
        """Measure of each class (exact sums, computed once)."""
        return {k: box_measure(getattr(self, k)) for k in ("inner", "boundary", "outer", "pending")}

    @property
    def measure_bounds(self) -> tuple[float, float]:
        """The certified bracket ``(measure(inner), measure(inner) + measure(boundary) + measure(pending))``,
        rounded outward: every box's measure and the sums are rounded down for the lower bound, up for the upper
        one (the figures of :attr:`measures` are rounded to nearest)."""
        return self.box_measure_bounds

    @cached_property
    def box_measure_bounds(self) -> tuple[float, float]:
        """The bracket of the boxes: ``(measure(inner), measure(inner) + measure(boundary) + measure(pending))``,
        rounded outward (:attr:`measure_bounds`)."""
        low = ExactSum.of(measures_of(self.inner, "down"))
        high = ExactSum()
        for kind in ("inner", "boundary", "pending"):
            high.add(measures_of(getattr(self, kind), "up"))
        return low.value_down, high.value_up

    def with_exact_measure(self, value) -> Paving:
        """This paving with the exact measure of the set it covers attached (shown beside the bracket by
        :meth:`to_dict`, the display and reports); the boxes are shared, not copied.

        Parameters
        ----------
        value : sympy.Expr
            The exact measure.

        Returns
        -------
        Paving
            A shallow copy (of the same class) with ``exact_measure`` set.
        """
        twin = copy.copy(self)
        object.__setattr__(twin, "exact_measure", value)
        return twin

    def to_dict(self) -> dict:
        """The JSON summary of the paving (``docs/cli.md``), without the boxes.

        Returns
        -------
        dict
            For each class its ``boxes`` (count) and ``measure``; ``measure_bounds``, ``delta``, ``size``,
            ``backend``, ``contract``, ``complete``, ``boxes_evaluated``, ``seconds``; and ``stop_reason``,
            ``units``, ``exact_measure`` (a float) with ``exact_measure_expr`` (text) when they are set.
        """
        m, c = self.measures, self.counts
        out = {
            "inner": {"boxes": c["inner"], "measure": m["inner"]},
            "boundary": {"boxes": c["boundary"], "measure": m["boundary"]},
            "outer": {"boxes": c["outer"], "measure": m["outer"]},
            "pending": {"boxes": c["pending"], "measure": m["pending"]},
            "measure_bounds": list(self.measure_bounds),
            "delta": self.delta,
            "size": self.size,
            "backend": self.backend,
            "contract": self.contract,
            "complete": self.complete,
            "boxes_evaluated": self.evaluated,
            "seconds": self.seconds,
        }
        if self.stop_reason:
            out["stop_reason"] = self.stop_reason
        if self.units:
            out["units"] = self.units
        if self.exact_measure is not None:
            out["exact_measure"] = float(sp.N(self.exact_measure, 17))
            out["exact_measure_expr"] = sp.sstr(self.exact_measure)
        return out

    def __repr__(self):
        lo, hi = self.measure_bounds
        c = self.counts
        return (f"Paving({c['inner']} inner, {c['boundary']} boundary, {c['outer']} outer, "
                f"{c['pending']} pending; measure in {fmt_bracket(lo, hi, 6, 'g')}, "
                f"delta={self.delta})")


_FEW = 7     # up to this many variables, a reduction across a box's edges is a loop over columns


def _across(op, a):
    """``op`` reduced across the columns of ``(N, n)`` array ``a``, left to right.

    numpy's ``op.reduce(a, axis=1)`` costs about 40 us on a thousand boxes of two edges (a generic loop per
    row); a loop over few columns costs one call each, and adds in the same order.
    """
    if a.shape[1] > _FEW:
        return op.reduce(a, axis=1)
    out = a[:, 0]
    for j in range(1, a.shape[1]):
        out = op(out, a[:, j])
    return out


def box_sizes(boxes: np.ndarray, size: str) -> np.ndarray:
    """The size of each box, as compared with ``delta``.

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.
    size : str
        ``"diameter"``: the length of the diagonal; anything else (``"width"``): the widest edge.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` sizes, computed in floats (not rounded outward).
    """
    w = boxes[:, :, 1] - boxes[:, :, 0]
    return np.sqrt(_across(np.add, w * w)) if size == "diameter" else _across(np.maximum, w)


def halves(boxes: np.ndarray, axis: np.ndarray | None = None):
    """Both halves of every box along ``axis`` (default: its longest edge), in order (``2i``, ``2i + 1``),
    and the mask of boxes that could be split (a box one float wide cannot; its two "halves" are itself).

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.
    axis : numpy.ndarray of int or None
        ``(N,)``: the edge to split in each box; None (default): its longest edge (the first of equals).

    Returns
    -------
    children : numpy.ndarray
        ``(2 N, n, 2)``: the lower half of box ``i`` at ``2i``, its upper half at ``2i + 1``.
    split : numpy.ndarray of bool
        ``(N,)``: True where the box was split.
    """
    N, n = boxes.shape[:2]
    lo, hi = boxes[:, :, 0], boxes[:, :, 1]
    k = np.argmax(hi - lo, axis=1) if axis is None else np.asarray(axis)
    mid = 0.5 * lo + 0.5 * hi                       # of every edge: whole-array operations, no gathering
    split = (np.arange(n) == k[:, None]) & (mid > lo) & (mid < hi)
    children = np.repeat(boxes, 2, axis=0)
    pairs = children.reshape(N, 2, n, 2)
    pairs[:, 0, :, 1] = np.where(split, mid, hi)
    pairs[:, 1, :, 0] = np.where(split, mid, lo)
    return children, _across(np.logical_or, split)


def bisect(boxes: np.ndarray):
    """Split every box along its longest edge; also returns boxes too thin to split.

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, n, 2)`` boxes.

    Returns
    -------
    halves : numpy.ndarray
        ``(2 M, n, 2)``: both halves of each of the ``M`` boxes that could be split, in order.
    unsplit : numpy.ndarray
        ``(N - M, n, 2)``: the boxes whose longest edge is one float wide.
    """
    children, ok = halves(boxes)
    return children.reshape(-1, 2, *boxes.shape[1:])[ok].reshape(-1, *boxes.shape[1:]), boxes[~ok]



def check_delta(delta, name="delta"):
    """Refuse a ``delta`` that is not a positive finite number.

    Parameters
    ----------
    delta : object
        The value to check.
    name : str
        The parameter's name for the error message (default ``"delta"``).

    Raises
    ------
    InvalidParameterError
        When ``delta`` is not an int or float (a bool is not), not finite, or not positive.
    """
    if not isinstance(delta, (int, float)) or isinstance(delta, bool) or not math.isfinite(delta) or delta <= 0:
        raise InvalidParameterError(f"{name} must be a positive finite number; got {delta!r}", parameter=name)



@dataclass(frozen=True, eq=False)
class StoredPaving(Paving):
    """A :class:`~workspace_sym.interval.paving.Paving` whose decided boxes are on disk.

    The boxes are in the ``.npy`` parts listed in ``files``: :meth:`parts`
    streams a class part by part, while ``inner``, ``boundary`` and ``outer``
    (and :meth:`load`) read the whole class into memory the first time they
    are asked for, so that everything that takes a Paving (pictures, the
    notebook display, reports) sees the same boxes as with an in-memory run.
    The counts and measures are those accumulated while the boxes were
    written (exact sums), without reading them back.

    Parameters
    ----------
    variables, box, constraints, delta, backend, size
        As for :class:`Paving`.
    inner, boundary, outer
        Given empty: these classes are read from ``files`` the first time they are asked for.
    pending, seconds, complete, evaluated, stop_reason, exact_measure, contract, units
        As for :class:`Paving`.
    store : str
        The directory of the box store.
    stored_counts : dict
        Number of boxes of each decided class, by class.
    stored_sums : dict
        The exact sum of each decided class's measures (text of an
        :class:`~workspace_sym.interval.store.ExactSum`), by class.
    stored_bounds : dict
        ``{"down": sums, "up": sums}``: the same sums of per-box measures rounded down and up.
    files : dict
        The ``.npy`` parts of each decided class, by class.
    _loaded : dict
        The classes read from disk so far (a cache); leave it empty.
    """

    store: str = ""
    stored_counts: dict = field(default_factory=dict)
    stored_sums: dict = field(default_factory=dict)
    stored_bounds: dict = field(default_factory=dict)        # {"down": sums, "up": sums}: outward measure sums
    files: dict = field(default_factory=dict)
    _loaded: dict = field(default_factory=dict, repr=False)

    def __getattribute__(self, name):
        # The decided classes are fields of Paving, empty in a stored one: read them from disk on demand.
        if name in KINDS:
            loaded = object.__getattribute__(self, "_loaded")
            if name not in loaded:
                loaded[name] = object.__getattribute__(self, "load")(name)
            return loaded[name]
        return object.__getattribute__(self, name)

    @property
    def counts(self) -> dict:
        """Number of boxes of each class, without reading the boxes.

        Returns
        -------
        dict
            ``{"inner": ..., "boundary": ..., "outer": ..., "pending": ...}``.
        """
        return {**self.stored_counts, "pending": len(self.pending)}

    @property
    def measures(self) -> dict:
        """Measure of each class, from the exact sums kept while the boxes were written.

        Returns
        -------
        dict
            ``{"inner": ..., "boundary": ..., "outer": ..., "pending": ...}``, floats rounded to nearest.
        """
        return {**{k: ExactSum.parse(v).value for k, v in self.stored_sums.items()},
                "pending": box_measure(self.pending)}

    @cached_property
    def box_measure_bounds(self) -> tuple[float, float]:
        """The certified bracket of the boxes from the outward sums kept while they were written (see Paving;
        :attr:`measure_bounds` intersects it with :attr:`volume_bounds` as there)."""
        down, up = ({k: ExactSum.parse(v) for k, v in self.stored_bounds[d].items()} for d in ("down", "up"))
        high = ExactSum.of(measures_of(self.pending, "up"))
        high.merge(up["inner"])
        high.merge(up["boundary"])
        return down["inner"].value_down, high.value_up

    def parts(self, kind: str):
        """The boxes of a class, part by part (memory-mapped ``(N, n, 2)`` arrays).

        Parameters
        ----------
        kind : str
            ``"inner"``, ``"boundary"`` or ``"outer"``.

        Yields
        ------
        numpy.memmap
            One part, read-only.
        """
        for path in self.files[kind]:
            yield np.load(path, mmap_mode="r")

    def load(self, kind: str) -> np.ndarray:
        """All the boxes of a class as one array (when they fit in memory).

        Parameters
        ----------
        kind : str
            ``"inner"``, ``"boundary"`` or ``"outer"``.

        Returns
        -------
        numpy.ndarray
            ``(N, n, 2)``: the parts concatenated in order.
        """
        parts = list(self.parts(kind))
        return np.concatenate(parts) if parts else np.empty((0, len(self.variables), 2))

    def to_dict(self) -> dict:
        """The JSON summary of :meth:`Paving.to_dict`, with where the boxes are.

        Returns
        -------
        dict
            As for a Paving, plus ``files`` (the parts' paths, as text) in each decided class and ``store``.
        """
        out = super().to_dict()
        for k in KINDS:
            out[k]["files"] = [str(p) for p in self.files[k]]
        out["store"] = self.store
        return out

    def __repr__(self):
        lo, hi = self.measure_bounds
        c = self.counts
        return (f"StoredPaving({c['inner']} inner, {c['boundary']} boundary, {c['outer']} outer, {c['pending']} "
                f"pending in {self.store}; measure in {fmt_bracket(lo, hi, 6, 'g')}, delta={self.delta})")
