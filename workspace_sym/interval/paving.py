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
import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp

from ..errors import BoxError, ConstraintError, ExpressionError, InvalidParameterError, check_choice
from ..expressions import parse_expr
from . import arith, verdict
from . import mp as mpi
from .boxes import SIZES, Box, Paving, bisect, box_measure, box_sizes, check_delta, halves
from .compiler import BACKENDS, best_form, compile_expr
from .contractor import Program
from .driver import RunBudget, RunOn, StopAt, expand, initial_boxes, subdivide
from .executor import thread_pool
from .graph import Graph
from .verdict import CODE, INSIDE, OUTSIDE, Decider, codes_from_masks

__all__ = ["Certificate", "Constraint", "parse_constraints", "certify_box", "pave", "threaded", "check_digits",
           "hausdorff",
           # the engine's lower layers, re-exported for the code that reads them from here
           "Box", "Paving", "SIZES", "bisect", "box_measure", "box_sizes", "check_delta", "halves", "RunBudget",
           "RunOn", "StopAt", "expand", "initial_boxes", "subdivide", "Decider"]

class Certificate(enum.Enum):
    """Outcome of a box test; only IN and OUT are proved statements (the codes of :mod:`.verdict`).

    ``bool(certificate)`` raises ``TypeError``: compare with the members instead.

    Parameters
    ----------
    value : int
        A verdict code: ``Certificate(1)`` is ``IN``, ``Certificate(-1)`` is ``OUT``, ``Certificate(0)`` is
        ``UNDECIDED``; any other value raises ``ValueError``.
    names, module, qualname, type, start, boundary
        The rest of the signature of :class:`enum.Enum`'s functional API; a Certificate takes none of them
        (an enumeration with members cannot be extended: ``TypeError``).
    """

    IN = INSIDE
    OUT = OUTSIDE
    UNDECIDED = verdict.UNDECIDED

    def __bool__(self):
        raise TypeError("a Certificate is not a boolean; compare with Certificate.IN / OUT / UNDECIDED")


@dataclass(frozen=True, slots=True)
class Constraint:
    """``g(x) <= 0`` (or ``< 0`` when ``strict``).

    Parameters
    ----------
    g : sympy.Expr
        The constraint's function.
    strict : bool
        ``g < 0`` rather than ``g <= 0`` (default False).
    source : str
        The text the constraint was read from (default ``""``: given as SymPy).
    """

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

    Parameters
    ----------
    constraints : str, sympy relational or bool, or a sequence of them
        The inequalities; ``True`` (or a comparison SymPy evaluates to it, ``-6 <= 0``) always holds, ``False``
        never.
    variables : sequence of sympy.Symbol
        The variables; a symbol of a SymPy inequality with a variable's name is that variable, whatever its
        assumptions.

    Returns
    -------
    tuple of Constraint
        One ``g <= 0`` (or ``g < 0``) a given inequality, in order: ``a <= b`` gives ``g = a - b``, ``a >= b``
        gives ``g = b - a``.

    Raises
    ------
    ConstraintError
        For text that is not one inequality in the variables, an equation or anything that is not an
        inequality, a symbol that is not a variable, or no inequality at all.

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
    inside: Any = None
    outside: Any = None
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
    """Refuse a precision for the mpmath backend outside 15 to 100000 digits.

    Parameters
    ----------
    digits : object
        The value to check.

    Raises
    ------
    InvalidParameterError
        ``parameter="digits"``, unless ``digits`` is an int (not a bool) from :data:`MIN_DIGITS` to 100000.
    """
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

    Parameters
    ----------
    box : dict, Box or sequence of pairs
        ``{variable: (lo, hi)}``, a :class:`Box`, or ``(lo, hi)`` pairs in the order of ``variables``.
    constraints : str, sympy relational, or a sequence of them
        The inequalities (:func:`parse_constraints`).
    variables : sequence of str or sympy.Symbol, optional
        The variables of a box given as pairs; when given with a dict or a Box, they must be the box's, by
        name and in order.
    backend : str
        ``"numpy"`` (default) or ``"mpmath"``.
    digits : int
        Precision of the mpmath backend in decimal digits, 15 to 100000 (default 30); checked for either
        backend.

    Returns
    -------
    Certificate
        The verdict on the whole box.

    Raises
    ------
    BoxError
        For bounds that do not make a box, or variables that are not the box's.
    ConstraintError
        For constraints that cannot be read (:func:`parse_constraints`).
    UnknownNameError
        For a backend other than ``"numpy"`` and ``"mpmath"``.
    InvalidParameterError
        For ``digits`` outside 15 to 100000.

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
def pave(constraints, box, *, delta: float, variables=None, backend: str = "numpy", size: str = "diameter",
         digits: int = 30, contract: bool = False, stop: StopAt = StopAt(), run: RunOn = RunOn()) -> Paving:
    """Non-uniform covering of ``{x in box : every constraint}`` (docs/methods.md section 2).

    Parameters
    ----------
    constraints : str, sympy relational, or a sequence of them
        The inequalities, SymPy relationals or strings such as ``"x**2 + y**2 <= 144"``
        (:func:`parse_constraints`).
    box : dict, Box or sequence of pairs
        ``{variable: (lo, hi)}``, a :class:`Box`, or ``(lo, hi)`` pairs with ``variables``.
    delta : float
        Undecided boxes whose size is at most ``delta`` become boundary boxes
        (with ``contract``, their size before the contraction).
    variables : sequence of str or sympy.Symbol, optional
        The variables of a box given as pairs; when given with a dict or a Box, they must be the box's, by
        name and in order.
    backend : {"numpy", "mpmath"}
        The arithmetic: numpy (default; whole generations of boxes, floats rounded outward) or the mpmath
        reference (one box at a time, at ``digits``).
    size : {"diameter", "width"}
        How a box is measured against ``delta``: its diameter (the paper's
        ``d(P)``, default) or its largest edge (codac's convention).
    digits : int
        Precision of the mpmath backend in decimal digits, 15 to 100000 (default 30); checked for either
        backend.
    contract : bool
        Also cut inner and outer slices off every undecided box by
        forward-backward contraction of the constraints (numpy backend;
        :mod:`~workspace_sym.interval.contractor`).  The contraction only
        proposes where to cut: a slice is declared inner or outer when the
        same forward evaluation that decides every box proves it (on the
        whole slice or on each of its pieces).  A box larger than ``delta``
        is bisected after its contraction even when what is left of it is
        no longer larger: the size test is the plain paving's, on the box
        the bisection made, so every boundary box is the contracted part
        of a box at most ``delta`` (``codac.pave`` tests what is left: on
        Rybak's robot, about 1.2 times its boundary boxes for 0.8 times its
        boundary area at every ``delta``, benchmarks/bench_paving.py).  Tighter boundary
        boxes at the same ``delta``; the boxes are no longer those of a
        plain bisection tree.
    stop : :class:`~workspace_sym.interval.driver.StopAt`
        A budget of boxes (``max_boxes``) or seconds (``time_limit``): when
        exhausted, the remaining boxes are returned as ``pending`` (never
        classified).
    run : :class:`~workspace_sym.interval.driver.RunOn`
        ``progress``: a progress bar (``tqdm.auto``: a widget in Jupyter, a
        bar on a terminal; default: on an interactive output once the run has
        lasted a second; False: never).
        Run on other processes or machines (``executor``: a
        :class:`concurrent.futures.Executor` or a ``dask.distributed.Client``),
        stream the decided boxes to disk (``max_memory``, ``store``), and
        checkpoint the run to a file it can be resumed from (``resume``).  The
        verdicts, box counts and measures are those of the local run.

    Returns
    -------
    Paving
        The inner, boundary, outer and pending boxes with their measures; a
        :class:`~workspace_sym.interval.boxes.StoredPaving` when the boxes are on disk.

    Raises
    ------
    BoxError
        For bounds that do not make a box, or variables that are not the box's.
    ConstraintError
        For constraints that cannot be read (:func:`parse_constraints`).
    UnknownNameError
        For a ``backend`` or ``size`` outside its set.
    InvalidParameterError
        For ``contract=True`` with the mpmath backend, a ``delta`` that is not a positive finite number,
        ``digits`` outside 15 to 100000, or a ``run`` whose checkpoint or store is not this run's.
    ExpressionError
        For a constraint with an operation the interval compiler does not support.
    WorkerResultError
        When a worker of another process sends back something other than a step's result.

    Examples
    --------
    >>> p = pave(["x**2 + y**2 <= 1"], {"x": (-1, 1), "y": (-1, 1)}, delta=0.1)
    >>> lo, hi = p.measure_bounds
    >>> bool(lo <= 3.141592653589793 <= hi)
    True
    >>> pave(["x**2 + y**2 <= 1"], {"x": (-1, 1), "y": (-1, 1)}, delta=0.01, stop=StopAt(max_boxes=100)).complete
    False
    """
    check_choice("backend", backend, BACKENDS)
    cons, b = _setup(constraints, box, variables)  # delta and size are checked by subdivide
    if contract and backend != "numpy":
        raise InvalidParameterError(f"contract=True needs the numpy backend; got backend={backend!r}")
    decide = _decider(cons, b.variables, backend, digits)
    separate = _Separate(cons, b.variables) if contract else None
    return subdivide(decide, b, delta=delta, size=size, stop=stop, run=run, constraints=cons, backend=backend,
                     separate=separate, presplit=0 if contract else 512,  # contraction: start from the box
                     sized_before_cut=contract)


def threaded(decide, workers: int | None = None, *, min_batch: int = 8192):
    """``decide`` run on parts of large batches in threads (numpy releases the GIL in its loops).

    The codes are those of ``decide`` on the whole batch; only the wall time
    changes.  ``workers`` defaults to the number of cores, at most 4; the
    threads come from one pool shared by every call.

    Parameters
    ----------
    decide : Decider
        The verdicts; each thread runs it in round-to-nearest.
    workers : int or None
        Threads (None or 0: the number of cores, at most 4).  Below 2, ``decide`` itself is returned.
    min_batch : int
        Batches of fewer boxes run in the caller's thread, whole (default 8192).

    Returns
    -------
    callable
        A decider giving the same codes as ``decide``.
    """
    import os

    workers = workers or min(os.cpu_count() or 1, 4)
    if workers < 2:
        return decide
    pool = thread_pool(workers)

    guarded = arith.nearest_rounding(decide)       # a worker thread keeps the mode it was created with

    def run(boxes):
        if len(boxes) < min_batch:
            return decide(boxes)
        return np.concatenate(list(pool.map(guarded, np.array_split(boxes, workers))))

    return run


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

    Parameters
    ----------
    A, B : numpy.ndarray
        ``(N, n, 2)`` and ``(M, n, 2)`` boxes.
    block : int
        Boxes of each union taken at a time (default 2048; memory only, not the result).

    Returns
    -------
    tuple of float
        ``(lower, upper)``, computed in floats (not rounded outward); ``(0, 0)`` when ``A`` is empty,
        ``(inf, inf)`` when only ``B`` is.
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
