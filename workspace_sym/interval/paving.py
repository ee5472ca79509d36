"""Certified boxes: non-uniform covering of ``X = {x in P : g_j(x) <= 0}`` (Rybak et al. 2016).

A box is **inner** when every ``g_j <= 0`` on the whole box (condition 8),
**outer** when some ``g_j > 0`` on the whole box (condition 7), **boundary**
when neither is proved and its size is at most ``delta`` (condition 9); larger
undecided boxes are bisected along their longest edge.  Every decision comes
from outward-rounded interval arithmetic; anything unproved stays undecided.

The numpy backend processes a whole generation of boxes per call; the mpmath
backend evaluates one box at a time at any precision and serves as reference.
"""

from __future__ import annotations

import enum
import html
import math
import time
from dataclasses import dataclass, field
from functools import cache, cached_property, lru_cache

import numpy as np
import sympy as sp

from ..errors import BoxError, ConstraintError, ExpressionError, InvalidParameterError, check_choice
from ..expressions import parse_expr
from ..numbers import fmt, fmt_bracket, measure_text
from ..progress import progress_bar
from . import arith, verdict
from . import mp as mpi
from .compiler import BACKENDS, best_form, compile_expr
from .contractor import Program, confirm
from .graph import Graph
from .store import ExactSum, measures_of
from .verdict import CODE, INSIDE, OUTSIDE, UNDECIDED, Decider, codes_from_masks

__all__ = ["Certificate", "Box", "Constraint", "parse_constraints", "certify_box", "pave", "subdivide", "threaded",
           "bisect", "box_sizes", "check_delta", "check_digits", "expand", "RunBudget",
           "Paving", "hausdorff", "box_measure", "SIZES"]

SIZES = ("diameter", "width")


class Certificate(enum.Enum):
    """Outcome of a box test; only IN and OUT are proved statements (the codes of :mod:`.verdict`)."""

    IN = INSIDE
    OUT = OUTSIDE
    UNDECIDED = verdict.UNDECIDED

    def __bool__(self):
        raise TypeError("a Certificate is not a boolean; compare with Certificate.IN / OUT / UNDECIDED")


@dataclass(frozen=True, slots=True)
class Box:
    """An axis-aligned box ``[lower_k, upper_k]`` over named variables.

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
        return float(np.prod(np.subtract(self.upper, self.lower)))

    def __repr__(self):
        parts = ", ".join(f"{v} in [{lo!r}, {hi!r}]" for v, lo, hi in zip(self.variables, self.lower, self.upper))
        return f"Box({parts})"


@dataclass(frozen=True, slots=True)
class Constraint:
    """``g(x) <= 0`` (or ``< 0`` when ``strict``)."""

    g: sp.Expr
    strict: bool = False
    source: str = ""

    def __repr__(self):
        return f"Constraint({self.g} {'<' if self.strict else '<='} 0)"


def parse_constraints(constraints, variables) -> tuple[Constraint, ...]:
    """Read inequalities (SymPy relationals or strings) as ``g <= 0`` constraints.

    Strings are read by :func:`~workspace_sym.expressions.parse_expr` with the
    names of ``variables`` as the only symbols, one comparison (``<``, ``<=``,
    ``>``, ``>=``), ``^`` as power and decimals as exact rationals; anything
    else raises :class:`ConstraintError`.

    Examples
    --------
    >>> x = sp.Symbol("x")
    >>> parse_constraints(["x**2 <= 4", x > 1], (x,))
    (Constraint(x**2 - 4 <= 0), Constraint(1 - x < 0))
    >>> parse_constraints(["x**2 - 4"], (x,))
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ConstraintError: constraint 1 ('x**2 - 4') is not an inequality; write it as 'g <= 0'
    """
    if isinstance(constraints, (str, sp.Basic)):
        constraints = [constraints]
    out = []
    names = {str(v): v for v in variables}
    # text may name the variables (and pi, sqrt, ...) and nothing else
    readable = {n: v for n, v in names.items() if n.isidentifier() and not n.startswith("_")}
    for k, c in enumerate(constraints, start=1):
        text = c if isinstance(c, str) else ""
        if isinstance(c, str):
            try:
                c = parse_expr(c, f"constraint {k}", names=readable, new_symbols=False, relational=True)
            except ExpressionError as exc:
                raise ConstraintError(str(exc)) from None
        if c is sp.true or c is sp.false or isinstance(c, bool):
            # A constant inequality (SymPy evaluates "-6 <= 0" to True): always / never satisfied.
            out.append(Constraint(sp.Integer(-1 if bool(c) else 1), False, text))
            continue
        if not isinstance(c, sp.core.relational.Relational) or isinstance(c, (sp.Eq, sp.Ne)):
            raise ConstraintError(f"constraint {k} ({text or str(c)!r}) is not an inequality; write it as 'g <= 0'")
        # Match variables by name: Symbol("x1") and Symbol("x1", real=True) are the same variable here.
        same_name = {sym: names[str(sym)] for sym in c.free_symbols if str(sym) in names and sym not in variables}
        if same_name:
            c = c.xreplace(same_name)
        if isinstance(c, (sp.LessThan, sp.StrictLessThan)):
            g = c.lhs - c.rhs
        else:
            g = c.rhs - c.lhs
        unknown = g.free_symbols - set(variables)
        if unknown:
            raise ConstraintError(f"constraint {k} ({text or str(c)!r}) uses unknown symbol(s) "
                                  f"{', '.join(sorted(map(str, unknown)))}; variables are "
                                  f"{', '.join(map(str, variables))}")
        out.append(Constraint(g, isinstance(c, (sp.StrictLessThan, sp.StrictGreaterThan)), text))
    if not out:
        raise ConstraintError("constraints: at least one inequality is needed")
    return tuple(out)


# ----------------------------------------------------------------------------- deciding
def _split_constant(g: sp.Expr):
    """``g = sign * e + c`` with ``c`` a number and ``e`` free of a leading minus sign (shared by constraints)."""
    c, e = g.as_coeff_Add()
    sign = 1
    if e.could_extract_minus_sign():
        e, sign = -e, -1
    return e, sign, c


# A proof of ``g <= 0`` (or ``g > 0``) on a box, for ``g = sign * e + c`` with ``e`` enclosed in ``[lo, hi]`` and the
# constant ``c`` in ``[cl, ch]``, is one exact comparison of floats: ``e + c <= 0`` on the box when
# ``hi <= -ch`` (negating a float is exact), so the sum is never rounded.  Per sign and strictness: (end of e's
# enclosure, comparison, which end of c, negated) for "inside", then the same for "outside".
_TESTS = {
    (1, False): ((1, np.less_equal, 1, True), (0, np.greater, 0, True)),
    (1, True): ((1, np.less, 1, True), (0, np.greater_equal, 0, True)),
    (-1, False): ((0, np.greater_equal, 1, False), (1, np.less, 0, False)),
    (-1, True): ((0, np.greater, 1, False), (1, np.less_equal, 0, False)),
}


def _decide_numpy(decider, boxes: np.ndarray):
    """Codes per box: 1 inner, -1 outer, 0 undecided (numpy backend, vectorised).

    One forward sweep of ``decider.graph`` encloses the distinct non-constant
    parts of the constraints, sharing their common subexpressions
    (``64 <= x^2 + y^2 <= 144`` evaluates ``x^2 + y^2`` once, and
    ``(x - 5)^2 + y^2`` shares its ``y^2``); a part with a centred form is
    enclosed by its own evaluator.  Each constraint is then two exact
    comparisons against its constant (:data:`_TESTS`).
    """
    X = [(boxes[:, k, 0], boxes[:, k, 1]) for k in range(boxes.shape[1])]
    inside = outside = None
    with np.errstate(all="ignore"):
        vals = decider.graph.forward(X)
        values = [vals[r] if f is None else f(X) for r, f in decider.sources]
        # NaN compares False both ways: undecided for this constraint.
        for k, (end, test, bound), (end_out, test_out, bound_out) in decider.tests:
            v = values[k]
            i, o = test(v[end], bound), test_out(v[end_out], bound_out)
            inside = i if inside is None else inside & i
            outside = o if outside is None else outside | o
    if np.ndim(inside) == 0 or np.ndim(outside) == 0:       # only constant constraints
        shape = (len(boxes),)
        inside, outside = np.broadcast_to(inside, shape), np.broadcast_to(outside, shape)
    return codes_from_masks(inside, outside)


def _decide_mpmath(compiled, constraints, boxes: np.ndarray, digits: int):
    codes = np.zeros(len(boxes), dtype=CODE)
    with mpi.precision(digits):
        for i, b in enumerate(boxes):
            X = [mpi.from_float_bounds(lo, hi) for lo, hi in b]
            all_in, some_out = True, False
            for f, c in zip(compiled, constraints):
                v = f(X)
                if v is None:
                    all_in = False
                    continue
                lo, hi = v.a, v.b
                if c.strict:
                    all_in &= bool(hi < 0)
                    some_out |= bool(lo >= 0)
                else:
                    all_in &= bool(hi <= 0)
                    some_out |= bool(lo > 0)
            codes[i] = codes_from_masks(all_in, some_out)
    return codes


class _Decider:
    def __init__(self, constraints, variables, backend, digits):
        check_choice("backend", backend, BACKENDS)
        self.constraints = constraints
        self.variables = variables
        self.backend = backend
        self.digits = digits
        if backend == "mpmath":
            self.compiled = [compile_expr(c.g, variables, backend=backend) for c in constraints]
            return
        exprs, parts = [], []
        for c in constraints:
            e, sign, const = _split_constant(c.g)
            if e not in exprs:
                exprs.append(e)
            parts.append((exprs.index(e), sign, compile_expr(const, ())([]) if const else (0.0, 0.0), c.strict))
        shared = [compile_expr(e, variables) for e in exprs]
        # The parts enclosed by their chosen form alone are the roots of one graph; a centred one keeps its
        # evaluator (the intersection with its mean-value form).
        plain = [f for f in shared if not f.centred]
        self.graph = Graph([f.expr for f in plain], variables)
        self.sources = [(self.graph.roots[plain.index(f)], None) if not f.centred else (None, f) for f in shared]
        self.tests = []
        for k, sign, const, strict in parts:
            tests = []
            for end, test, which, negated in _TESTS[sign, strict]:
                bound = float(const[which])
                tests.append((end, test, -bound if negated else bound))
            self.tests.append((k, *tests))

    def __reduce__(self):
        # Another process rebuilds the decider from the SymPy constraints (compiled once there, then cached)
        # rather than receiving the generated code.
        return _decider, (self.constraints, self.variables, self.backend, self.digits)

    def __call__(self, boxes):
        if self.backend == "numpy":
            return _decide_numpy(self, boxes)
        return _decide_mpmath(self.compiled, self.constraints, boxes, self.digits)


def _setup(constraints, box, variables):
    if isinstance(box, Box):
        b = box
    elif isinstance(box, dict):
        b = Box.from_bounds(box)
    else:
        b = Box.from_bounds(box, variables)
    if variables is not None and tuple(map(str, variables)) != tuple(map(str, b.variables)):
        raise BoxError(f"box: variables {list(map(str, b.variables))} differ from {list(map(str, variables))}")
    if isinstance(constraints, (str, sp.Basic)):
        constraints = [constraints]
    try:
        return _parse_cached(tuple(constraints), b.variables), b
    except TypeError:                 # something unhashable: parse without the cache
        return parse_constraints(constraints, b.variables), b


@lru_cache(maxsize=256)
def _parse_cached(constraints: tuple, variables: tuple):
    return parse_constraints(constraints, variables)


MIN_DIGITS = 15      # below double precision the mpmath backend only loses to the numpy one


def check_digits(digits) -> None:
    if not isinstance(digits, int) or isinstance(digits, bool) or not MIN_DIGITS <= digits <= 100_000:
        raise InvalidParameterError(f"digits (precision of the mpmath backend) must be a whole number from "
                                    f"{MIN_DIGITS} (double precision) to 100000; got {digits!r}", parameter="digits")


@lru_cache(maxsize=256)
def _decider(constraints: tuple, variables: tuple, backend: str, digits: int):
    """The decider of a constraint set (cached: repeated pavings skip parsing and compiling)."""
    check_digits(digits)               # for any backend: a wrong option is refused, not ignored
    return _Decider(constraints, variables, backend, digits)


@lru_cache(maxsize=256)
def _program(constraints: tuple, variables: tuple) -> Program:
    """The contraction program of a constraint set (cached like the deciders)."""
    return Program([best_form(c.g, variables) for c in constraints], variables)


@dataclass(frozen=True)
class _Separate:
    """The contraction of a constraint set as a picklable callable: another process builds the program once."""

    constraints: tuple
    variables: tuple

    def __call__(self, boxes):
        return _program(self.constraints, self.variables).separate(boxes)


@arith.nearest_rounding
def certify_box(box, constraints, *, variables=None, backend: str = "numpy", digits: int = 30) -> Certificate:
    """IN if every constraint holds on the whole box, OUT if one fails on the whole box, else UNDECIDED.

    Examples
    --------
    >>> certify_box({"x": (0, 1), "y": (0, 1)}, ["x**2 + y**2 <= 4"])
    <Certificate.IN: 1>
    >>> certify_box({"x": (3, 4), "y": (0, 1)}, ["x**2 + y**2 <= 4"])
    <Certificate.OUT: -1>
    >>> certify_box({"x": (1, 3), "y": (0, 1)}, ["x**2 + y**2 <= 4"])
    <Certificate.UNDECIDED: 0>
    """
    cons, b = _setup(constraints, box, variables)
    code = _decider(cons, b.variables, backend, digits)(b.array[None, :, :])[0]
    return Certificate(int(code))


# ----------------------------------------------------------------------------- paving
def box_measure(boxes: np.ndarray) -> float:
    """Total measure (area, volume) of an ``(N, n, 2)`` array of boxes.

    The measures of the boxes (products of float edge widths) are summed
    exactly and rounded once (:class:`~workspace_sym.interval.store.ExactSum`):
    the total does not depend on the order of the boxes, so a distributed or
    resumed run gives the same figure as a local one.
    """
    if len(boxes) == 0:
        return 0.0
    return ExactSum.of(measures_of(np.asarray(boxes))).value


MAX_3D_BOXES_SHOWN = 20_000     # a notebook draws a 3D paving up to this many boxes (matplotlib 3D is slow)


@dataclass(frozen=True, eq=False)
class Paving:
    """Result of :func:`pave`: inner, boundary, outer and pending boxes, each an ``(N, n, 2)`` array.

    ``pending`` boxes are those a stopped run (budget, time limit, Ctrl-C)
    did not examine: they are neither proved nor classified.  ``units`` is the
    length unit of the variables when they are lengths (a robot's workspace
    from ``reach``), for the axes of its pictures.
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
    method: str = ""                # how the boxes were decided, when a caller chose among ways (reach)

    @property
    def counts(self) -> dict:
        """Number of boxes of each class."""
        return {k: len(getattr(self, k)) for k in ("inner", "boundary", "outer", "pending")}

    @cached_property
    def measures(self) -> dict:
        """Measure of each class (exact sums, computed once)."""
        return {k: box_measure(getattr(self, k)) for k in ("inner", "boundary", "outer", "pending")}

    @cached_property
    def measure_bounds(self) -> tuple[float, float]:
        """The certified bracket ``(measure(inner), measure(inner) + measure(boundary) + measure(pending))``,
        rounded outward: every box's measure and the sums are rounded down for the lower bound, up for the upper
        one (the figures of :attr:`measures` are rounded to nearest)."""
        low = ExactSum.of(measures_of(self.inner, "down"))
        high = ExactSum()
        for kind in ("inner", "boundary", "pending"):
            high.add(measures_of(getattr(self, kind), "up"))
        return low.value_down, high.value_up

    def to_dict(self) -> dict:
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
        if self.method:
            out["method"] = self.method
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

    def _repr_html_(self) -> str:
        """Summary (boxes and measure of each class, the certified bracket) and the picture (Jupyter)."""
        from ..display import figure_html, html_table
        from ..plotting import plot_paving

        m, c = self.measures, self.counts
        rows = [(kind, c[kind], measure_text(kind, m[kind], 6, "g"))
                for kind in ("inner", "boundary", "outer", "pending")]
        lo, hi = self.measure_bounds
        how = ", with contraction" if self.contract else ""
        lines = [f"over ({', '.join(map(str, self.variables))}), δ = {self.delta} ({self.size}), backend "
                 f"{self.backend}{how}: {self.evaluated} boxes evaluated in {self.seconds:.2f} s",
                 f"certified measure in {fmt_bracket(lo, hi, 6)}"]
        if self.exact_measure is not None:
            lines.append(f"exact measure {fmt(float(sp.N(self.exact_measure)), 6)} = {sp.sstr(self.exact_measure)}")
        if not self.complete:
            lines.append(f"stopped early: {self.stop_reason}; pending boxes are unclassified")
        drawn, n = len(self.inner) + len(self.boundary), len(self.variables)
        picture = ""
        if n == 2 or (n == 3 and drawn <= MAX_3D_BOXES_SHOWN):
            picture = figure_html(plot_paving(self), alt="paving")
        elif n == 3:
            picture = f"<p>(no picture of {drawn} boxes in 3D here: see plotting.plot_paving_slices)</p>"
        return ("<p>" + "<br/>".join(html.escape(t) for t in lines) + "</p>"
                + html_table(("boxes", "number", "measure"), rows) + picture)


class RunBudget:
    """Stopping rules and progress bar of a branch-and-bisect run (:func:`subdivide`, ``reach``).

    ``stop_reason(evaluated)`` is empty while the run may go on, else why it
    stops (the time limit or the box budget).  The bar shows the share of
    ``total`` (the initial measure) already decided; ``progress`` follows
    :mod:`workspace_sym.progress` (None: on an interactive output, after a second).
    """

    def __init__(self, *, max_boxes: int | None, time_limit: float | None, progress: bool | None,
                 total: float, label: str):
        if max_boxes is not None and max_boxes < 1:
            raise InvalidParameterError(f"max_boxes must be at least 1; got {max_boxes!r}", parameter="max_boxes")
        if time_limit is not None and not (isinstance(time_limit, int | float) and not isinstance(time_limit, bool)
                                           and math.isfinite(time_limit) and time_limit > 0):
            raise InvalidParameterError(f"time_limit must be a positive number of seconds; got {time_limit!r}",
                                        parameter="time_limit")
        self.max_boxes, self.time_limit = max_boxes, time_limit
        self.start = time.perf_counter()
        self.total = total
        self.bar = progress_bar(progress, total=100.0, desc=label, unit="%",
                                bar_format="{desc}: {percentage:5.1f}% of the box decided{postfix} |{bar}| "
                                           "[{elapsed}]")

    @property
    def seconds(self) -> float:
        return time.perf_counter() - self.start

    @property
    def showing(self) -> bool:
        """Whether the bar draws (callers skip computing what it would show otherwise)."""
        return not self.bar.disable

    def stop_reason(self, evaluated: int, *, ahead: float = 0.0) -> str:
        """``ahead``: seconds the next step is expected to take; the run stops before a step that would end
        past the time limit."""
        elapsed = self.seconds
        if self.time_limit is not None and elapsed + ahead > self.time_limit:
            return f"time limit of {self.time_limit} s reached"
        if self.max_boxes is not None and evaluated >= self.max_boxes:
            return f"budget of {self.max_boxes} boxes reached"
        return ""

    def show(self, decided: float, evaluated: int) -> None:
        if not self.showing:
            return
        share = min(1.0, decided / self.total) if self.total > 0 else 1.0
        self.bar.set_postfix_str(f"{evaluated} boxes", refresh=False)
        self.bar.update(100.0 * share - self.bar.n)

    def close(self) -> None:
        self.bar.close()


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
    w = boxes[:, :, 1] - boxes[:, :, 0]
    return np.sqrt(_across(np.add, w * w)) if size == "diameter" else _across(np.maximum, w)


def halves(boxes: np.ndarray, axis: np.ndarray | None = None):
    """Both halves of every box along ``axis`` (default: its longest edge), in order (``2i``, ``2i + 1``),
    and the mask of boxes that could be split (a box one float wide cannot; its two "halves" are itself)."""
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
    """Split every box along its longest edge; also returns boxes too thin to split."""
    children, ok = halves(boxes)
    return children.reshape(-1, 2, *boxes.shape[1:])[ok].reshape(-1, *boxes.shape[1:]), boxes[~ok]


def pave(constraints, box, *, delta: float, variables=None, backend: str = "numpy", size: str = "diameter",
         max_boxes: int | None = None, time_limit: float | None = None, progress: bool | None = None,
         digits: int = 30, chunk: int = 200_000, exact_measure=None, contract: bool = False,
         executor=None, max_memory=None, store=None, resume=None) -> Paving:
    """Non-uniform covering of ``{x in box : every constraint}`` (docs/methods.md section 2).

    Parameters
    ----------
    constraints : inequalities (SymPy relationals or strings such as ``"x**2 + y**2 <= 144"``)
    box : ``{variable: (lo, hi)}``, a :class:`Box`, or pairs with ``variables``
    delta : float
        Undecided boxes whose size is at most ``delta`` become boundary boxes.
    backend : {"numpy", "mpmath"}
    size : {"diameter", "width"}
        How a box is measured against ``delta``: its diameter (the paper's
        ``d(P)``, default) or its largest edge (codac's convention).
    max_boxes, time_limit : optional budget; when exhausted, the remaining
        boxes are returned as ``pending`` (never classified).
    progress : progress bar (``tqdm.auto``: a widget in Jupyter, a bar on a
        terminal); default: on an interactive output once the run has lasted
        a second; False: never.
    digits : precision of the mpmath backend.
    contract : bool
        Also cut inner and outer slices off every undecided box by
        forward-backward contraction of the constraints (numpy backend;
        :mod:`~workspace_sym.interval.contractor`).  The contraction only
        proposes where to cut: a slice is declared inner or outer when the
        same forward evaluation that decides every box proves it (on the
        whole slice or on each of its pieces).  Fewer,
        tighter boundary boxes at the same ``delta``; the boxes are no
        longer those of a plain bisection tree.
    executor, max_memory, store, resume : run on other processes or
        machines (a :class:`concurrent.futures.Executor` or a
        ``dask.distributed.Client``), stream the decided boxes to disk, and
        checkpoint the run to a file it can be resumed from
        (:func:`~workspace_sym.interval.executor.run_paving`).  The verdicts,
        box counts and measures are those of the local run.

    Returns
    -------
    Paving

    Examples
    --------
    >>> p = pave(["x**2 + y**2 <= 1"], {"x": (-1, 1), "y": (-1, 1)}, delta=0.1)
    >>> lo, hi = p.measure_bounds
    >>> bool(lo <= 3.141592653589793 <= hi)
    True
    """
    check_choice("backend", backend, BACKENDS)
    cons, b = _setup(constraints, box, variables)  # delta and size are checked by subdivide
    if contract and backend != "numpy":
        raise InvalidParameterError(f"contract=True needs the numpy backend; got backend={backend!r}")
    decide = _decider(cons, b.variables, backend, digits)
    separate = _Separate(cons, b.variables) if contract else None
    return subdivide(decide, b, delta=delta, size=size, max_boxes=max_boxes, time_limit=time_limit,
                     progress=progress, chunk=chunk, constraints=cons, backend=backend,
                     exact_measure=exact_measure, separate=separate,
                     presplit=0 if contract else 512,  # contraction changes the tree: start from the box
                     executor=executor, max_memory=max_memory, store=store, resume=resume)


def check_delta(delta, name="delta"):
    if not isinstance(delta, (int, float)) or isinstance(delta, bool) or not math.isfinite(delta) or delta <= 0:
        raise InvalidParameterError(f"{name} must be a positive finite number; got {delta!r}", parameter=name)


@cache
def _thread_pool(workers: int):
    """One pool per worker count for the whole process (its threads end with the interpreter)."""
    from concurrent.futures import ThreadPoolExecutor

    return ThreadPoolExecutor(workers, thread_name_prefix="workspace_sym")


def threaded(decide, workers: int | None = None, *, min_batch: int = 8192):
    """``decide`` run on parts of large batches in threads (numpy releases the GIL in its loops).

    The codes are those of ``decide`` on the whole batch; only the wall time
    changes.  ``workers`` defaults to the number of cores, at most 4; the
    threads come from one pool shared by every call.
    """
    import os

    workers = workers or min(os.cpu_count() or 1, 4)
    if workers < 2:
        return decide
    pool = _thread_pool(workers)

    guarded = arith.nearest_rounding(decide)       # a worker thread keeps the mode it was created with

    def run(boxes):
        if len(boxes) < min_batch:
            return decide(boxes)
        return np.concatenate(list(pool.map(guarded, np.array_split(boxes, workers))))

    return run


def initial_boxes(box: Box, delta: float, size: str, presplit: int) -> np.ndarray:
    """The box bisected, unevaluated, into about ``presplit`` boxes larger than ``delta`` (see :func:`subdivide`).

    A fresh array each call, from a cache: the same box, delta and size give the same boxes, and bisecting them
    costs about as much as deciding them (nine generations of numpy calls for 512 boxes).
    """
    return _initial_boxes(box.lower, box.upper, float(delta), size, presplit).copy()


@lru_cache(maxsize=64)
def _initial_boxes(lower: tuple, upper: tuple, delta: float, size: str, presplit: int) -> np.ndarray:
    work = np.array([lower, upper], dtype=float).T[None, :, :].copy()
    while len(work) < presplit and (box_sizes(work, size) > delta).all():
        work, thin = bisect(work)
        if len(thin):
            return np.concatenate([work, thin])
    return work


def expand(batch: np.ndarray, decide: Decider, separate, delta: float, size: str):
    """One step of the branch and bisect on a batch: ``(inner, boundary, outer, children)`` arrays.

    Each box is decided on its own, so the union of the results does not
    depend on how the boxes are batched: this is the unit of work that
    :mod:`~workspace_sym.interval.executor` sends to other processes.
    """
    codes = decide(batch)
    und = batch[codes == UNDECIDED]
    inner, outer = [batch[codes == INSIDE]], [batch[codes == OUTSIDE]]
    if separate is not None:
        cut = separate(und)
        # The contraction proposes slices; each is declared only when the forward evaluation
        # that decides every other box proves it too, whole or piece by piece.  The rest stays undecided.
        proved_in, proved_out = confirm(decide, cut.inner, cut.outer)
        inner.append(cut.inner[proved_in])
        outer.append(cut.outer[proved_out])
        und = np.concatenate([cut.kept, cut.inner[~proved_in], cut.outer[~proved_out]])
    small = box_sizes(und, size) <= delta
    children, thin = bisect(und[~small])
    return np.concatenate(inner), np.concatenate([und[small], thin]), np.concatenate(outer), children


@arith.nearest_rounding
def subdivide(decide: Decider, box: Box, *, delta: float, size: str = "diameter", max_boxes: int | None = None,
              time_limit: float | None = None, progress: bool | None = None, chunk: int = 200_000,
              constraints=(), backend: str = "numpy", exact_measure=None, label: str = "paving",
              presplit: int = 512, separate=None, executor=None, max_memory=None, store=None,
              resume=None) -> Paving:
    """Branch and bisect with any box classifier: the loop behind :func:`pave`.

    ``decide(boxes)`` takes an ``(N, n, 2)`` array and returns codes: 1 for a
    box proved inside, -1 proved outside, 0 undecided.  Undecided boxes larger
    than ``delta`` are bisected along their longest edge; the others become
    boundary boxes.  A budget, time limit or Ctrl-C returns the unexamined
    boxes as pending.

    The first generations are bisected without being evaluated until there are
    ``presplit`` boxes (none smaller than ``delta``): one numpy call costs about
    the same for one box or five hundred, and a box decided at a coarse level
    has its children decided too, so only the number of boxes changes (the
    measures of the Rybak benchmark are identical with and without; 1.3x to
    1.8x faster).  ``presplit=0`` evaluates from the initial box.

    ``separate(boxes)``, optional, runs on the undecided boxes and returns a
    :class:`~workspace_sym.interval.contractor.Separation`: inner and outer
    slices and the undecided remainder.  A slice is declared inner (outer)
    only when ``decide`` also proves it so, on the whole slice or on each of
    its pieces (:func:`~workspace_sym.interval.contractor.confirm`: near a
    corner of the set, different constraints fail on different parts of a
    slice); the remainder and the slices ``decide`` does not confirm go on
    to the size test and the bisection.  So every verdict of the paving
    comes from ``decide``.

    With ``executor``, ``max_memory``, ``store`` or ``resume`` the boxes are processed
    by :func:`~workspace_sym.interval.executor.run_paving` (chunks on other
    processes, decided boxes on disk, checkpoints): same boxes, in another
    order.
    """
    check_delta(delta)
    check_choice("size", size, SIZES)
    if executor is not None or max_memory is not None or store is not None or resume is not None:
        from .executor import run_paving

        return run_paving(decide, box, delta=delta, size=size, max_boxes=max_boxes, time_limit=time_limit,
                          progress=progress, chunk=chunk, constraints=constraints, backend=backend,
                          exact_measure=exact_measure, label=label, presplit=presplit, separate=separate,
                          executor=executor, max_memory=max_memory, store=store, resume=resume)
    run = RunBudget(max_boxes=max_boxes, time_limit=time_limit, progress=progress, total=box.measure, label=label)
    inner, boundary, outer = [], [], []
    work = initial_boxes(box, delta, size, presplit)
    evaluated, reason = 0, ""
    try:
        while len(work):
            reason = run.stop_reason(evaluated)
            if reason:
                break
            take = len(work) if max_boxes is None else min(len(work), max_boxes - evaluated)
            take = min(take, chunk)
            batch = work[:take]
            # an interrupt in expand leaves the batch in work: pending
            step_inner, step_boundary, step_outer, children = expand(batch, decide, separate, delta, size)
            work = work[take:]
            evaluated += len(batch)
            inner.append(step_inner)
            outer.append(step_outer)
            boundary.append(step_boundary)
            work = np.concatenate([work, children]) if len(work) else children
            if run.showing:                  # everything not in work is decided
                run.show(box.measure - box_measure(work), evaluated)
    except KeyboardInterrupt:
        reason = "interrupted"
    finally:
        run.close()
    n = len(box.variables)
    empty = np.empty((0, n, 2))

    def stack(parts):
        return np.concatenate(parts) if parts else empty

    return Paving(box.variables, box, tuple(constraints), float(delta), backend, size, stack(inner),
                  stack(boundary), stack(outer), work if len(work) else empty, run.seconds,
                  not reason, evaluated, reason, exact_measure, separate is not None)


# ----------------------------------------------------------------------------- Hausdorff
def _corners(boxes: np.ndarray) -> np.ndarray:
    n = boxes.shape[1]
    grid = np.array(np.meshgrid(*[[0, 1]] * n, indexing="ij")).reshape(n, -1).T  # (2^n, n)
    return boxes[:, np.arange(n)[None, :], grid]  # (N, 2^n, n)


def _point_box_distance(points: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Euclidean distances ``(P, Q)`` from points ``(P, n)`` to boxes ``(Q, n, 2)``."""
    lo, hi = boxes[None, :, :, 0], boxes[None, :, :, 1]
    x = points[:, None, :]
    gap = np.maximum(np.maximum(lo - x, x - hi), 0.0)
    return np.sqrt(np.sum(gap * gap, axis=2))


def hausdorff(A: np.ndarray, B: np.ndarray, *, block: int = 2048) -> tuple[float, float]:
    """Bracket of the deviation ``Delta(A, B) = max_{a in A} min_{b in B} |a - b|`` of two box unions.

    The paper's closing formulas replace ``max_a min_j`` by ``min_j max_a``
    box by box; that exchange gives an upper bound, not an equality (a box of
    A may be covered by two boxes of B without lying in either).  We return
    ``(lower, upper)``: the upper bound is the paper's
    ``max_i min_j rho(P_i, Q_j)``, with ``rho(P, Q)`` exact (the largest
    distance from a corner of P to Q, distance to a box being convex);
    the lower bound is ``max_i min_j`` of the distance from the corners and
    centre of ``P_i`` to ``Q_j``.  Both are equal when A's boxes are small
    against B's.  The symmetric Hausdorff distance is the max of both
    directions.
    """
    A, B = np.asarray(A, dtype=float), np.asarray(B, dtype=float)
    if len(A) == 0:
        return 0.0, 0.0
    if len(B) == 0:
        return math.inf, math.inf
    corners = _corners(A)
    centres = A.mean(axis=2)
    lower, upper = 0.0, 0.0
    for i in range(0, len(A), block):
        c = corners[i:i + block]  # (m, 2^n, n)
        m, k, n = c.shape
        dist = np.full((m, k), np.inf)
        best_rho = np.full(m, np.inf)
        dcen = np.full(m, np.inf)
        for j in range(0, len(B), block):
            d = _point_box_distance(c.reshape(-1, n), B[j:j + block]).reshape(m, k, -1)
            dist = np.minimum(dist, d.min(axis=2))
            best_rho = np.minimum(best_rho, d.max(axis=1).min(axis=1))
            dcen = np.minimum(dcen, _point_box_distance(centres[i:i + block], B[j:j + block]).min(axis=1))
        lower = max(lower, float(np.max(np.maximum(dist.max(axis=1), dcen))))
        upper = max(upper, float(best_rho.max()))
    return lower, upper
