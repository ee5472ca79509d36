"""Compile SymPy expressions into interval evaluators (numpy engine or mpmath reference).

The interval extension of an expression depends on how it is written: every
repeated occurrence of a variable can widen the enclosure (the dependency
problem).  :func:`best_form` picks, among the expression as given, its
factored form, its Horner form and the completed-square form of separable
quadratics, the one with the fewest repeated occurrences; when a variable is
still repeated, the evaluator also computes the centred (mean-value) form
``f(m) + grad f(X) . (X - m)`` and intersects the two enclosures.

Rewritings are exact: the constants are made exact first
(:func:`~workspace_sym.interval.graph.exact_constants`) and hidden behind
placeholder symbols while SymPy rewrites, and a candidate is kept only when
it expands back to the expression.  The preparation is bounded, and every
stage whose cost grows with the input looks at its budget before or while it
runs: an expression in which each variable occurs once is already its best
form (no search at all: ``(x + y + 1)**1000`` is evaluated as written, an
interval power of an interval sum); the size of the expanded polynomial is
bounded from the expression tree before anything is expanded, and the search
is skipped past ``MAX_EXPANDED_TERMS`` terms or total degree
``MAX_REWRITE_DEGREE`` (SymPy takes 30 s to factor ``(x + y)**100``); the
expansion itself (:func:`expand_bounded`) checks the number of terms and the
clock after every product; expressions larger than ``MAX_REWRITE_OPS``
operations, or a search that has run for ``REWRITE_SECONDS``, keep the forms
found so far (at least the natural one).

The evaluators are :class:`~workspace_sym.interval.graph.Graph` forward
sweeps; compiled evaluators are cached per (expression, variables, backend).
Expressions evaluated together over the same boxes (a Jacobian's entries, a
map's coordinates) are one :class:`CompiledBatch`: one sweep over the union of
their graphs, where what they share (the sines and cosines of the joints,
their products) is computed once, each enclosure the same floats as its own
evaluator gives.
"""

from __future__ import annotations

import math
import time
from functools import lru_cache

import sympy as sp

from ..errors import ExpressionError, OverBudget, check_choice
from ..expressions import as_sympy
from . import arith
from .graph import Graph, exact_constants

__all__ = ["best_form", "compile_expr", "CompiledExpr", "compile_batch", "CompiledBatch", "BACKENDS",
           "repeated_occurrences", "expansion_bound", "expand_bounded", "OverBudget"]

BACKENDS = ("numpy", "mpmath")
MAX_REWRITE_OPS = 400     # larger expressions are evaluated as written
REWRITE_SECONDS = 2.0     # no further candidate form is tried after this
MAX_EXPANDED_TERMS = 200  # polynomials that expand to more terms are evaluated as written
MAX_REWRITE_DEGREE = 40   # ... and so are those of higher total degree (factoring cost grows steeply with it)


# ----------------------------------------------------------------------------- forms
def repeated_occurrences(expr: sp.Expr, variables) -> int:
    """Sum over variables of (occurrences - 1): zero means the natural extension is exact.

    Parameters
    ----------
    expr : sympy.Expr
        The expression.
    variables : iterable of sympy.Symbol
        The variables counted.

    Returns
    -------
    int
        The number of repeated occurrences (0 or more).
    """
    counts = {v: 0 for v in variables}
    for node in sp.preorder_traversal(expr):
        if node in counts:
            counts[node] += 1
    return sum(max(0, c - 1) for c in counts.values())


def _complete_squares(expr: sp.Expr, variables) -> sp.Expr | None:
    """``a x^2 + b x + rest -> a (x + b/(2a))^2 + rest - b^2/(4a)`` for every variable
    that appears only in such a separable quadratic."""
    try:
        poly = sp.Poly(expr, *variables)
    except sp.PolynomialError:
        return None
    if poly.total_degree() > 2:
        return None
    rest, squares = sp.expand(expr), []
    for v in variables:
        p = sp.Poly(rest, v)
        if p.degree() != 2:
            continue
        a, b, c = p.all_coeffs()
        if (a.free_symbols | b.free_symbols) & set(variables):
            continue
        squares.append(a * (v + b / (2 * a)) ** 2)
        rest = sp.expand(c - b**2 / (4 * a))
    changed = any(sq.args[-1].is_Pow if sq.is_Mul else sq.is_Pow for sq in squares)
    out = sp.Add(*squares) + rest
    return out if changed else None


def _hide_constants(expr: sp.Expr):
    """``expr`` with its non-integer rationals replaced by placeholder symbols, and the way back.

    SymPy's rewritings then see no coefficient they could round or expand
    into huge integers (a float such as 1e-300 is a rational with a
    1,000-bit denominator); every rewriting is an identity in the
    placeholders, so putting the rationals back gives an equal expression.
    """
    numbers = sorted((r for r in expr.atoms(sp.Rational) if not r.is_Integer), key=sp.default_sort_key)
    hide = {r: sp.Dummy(f"k{i}") for i, r in enumerate(numbers)}
    return expr.xreplace(hide), {d: r for r, d in hide.items()}


# ----------------------------------------------------------------------------- budgets
def expansion_bound(expr: sp.Expr) -> tuple[int, int]:
    """``(terms, degree)``: upper bounds on the number of terms and the total degree of ``expand(expr)``.

    Computed on the expression tree, without expanding (linear in the size
    of the tree): a sum adds the terms of its parts, a product multiplies
    them, a power ``b**n`` has at most ``C(n + t - 1, t - 1)`` terms when
    ``b`` has ``t``.  Every symbol has degree 1; a subexpression that is not
    a sum, product or positive integer power counts as one term of degree 1
    when it holds a symbol, 0 otherwise.

    Parameters
    ----------
    expr : sympy.Expr
        The expression.

    Returns
    -------
    tuple of int
        ``(terms, degree)``; ``terms`` is ``2**64`` (past any budget) where the binomial is too costly to
        compute.

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> expansion_bound((x + y + 1)**1000)
    (501501, 1000)
    >>> expansion_bound(x**2 - 10*x + y**2 - 119)
    (4, 2)
    """
    seen: dict = {}

    def walk(e):
        if e in seen:
            return seen[e]
        if e.is_Add or e.is_Mul:
            parts = [walk(a) for a in e.args]
            if e.is_Add:
                out = (sum(t for t, _ in parts), max(d for _, d in parts))
            else:
                out = (math.prod(t for t, _ in parts), sum(d for _, d in parts))
        elif e.is_Pow and e.exp.is_Integer and e.exp > 0:
            t, d = walk(e.base)
            n = int(e.exp)
            # C(n + t - 1, t - 1) grows fast: stop computing it once it is past any budget
            out = (math.comb(n + t - 1, t - 1) if min(n, t - 1) < 64 else 2**64, n * d)
        else:
            out = (1, 1 if e.free_symbols else 0)
        seen[e] = out
        return out

    return walk(expr)


def expand_bounded(expr: sp.Expr, gens, *, max_terms: int, deadline: float | None = None):
    """``expr`` expanded as a polynomial in ``gens`` (a SymPy ring element), or :class:`OverBudget`.

    The expansion is done by ring arithmetic (sums, products and powers by
    repeated squaring) and the number of terms and the clock are checked
    after every operation, so no step runs far past ``max_terms`` or
    ``deadline`` (a :func:`time.perf_counter` value).  Constants other than
    rationals (``sqrt(2)``, ``pi``) are coefficients of the expression
    domain.  Raises :class:`OverBudget`, or ``ValueError`` when ``expr`` is
    not a polynomial in ``gens``.

    Parameters
    ----------
    expr : sympy.Expr
        The expression.
    gens : iterable of sympy.Symbol
        The polynomial's variables.
    max_terms : int
        The most terms any intermediate result may have.
    deadline : float or None
        A :func:`time.perf_counter` value past which the expansion stops (None: no deadline).

    Returns
    -------
    sympy.polys.rings.PolyElement
        The polynomial, in a ring over ``QQ`` (rational constants only) or ``EX``.

    Raises
    ------
    OverBudget
        When a result has more than ``max_terms`` terms or the deadline has passed.

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> expand_bounded((x + y)**2 - x**2, (x, y), max_terms=10).as_expr()
    2*x*y + y**2
    >>> expand_bounded((x + y)**50, (x, y), max_terms=10)
    Traceback (most recent call last):
    ...
    workspace_sym.errors.OverBudget: more than 10 terms
    """
    gens = tuple(gens)
    numbers = all(a.is_Rational for a in expr.atoms(sp.Number)) and not (
        expr.atoms(sp.NumberSymbol) or any(not a.free_symbols for a in expr.atoms(sp.Function)))
    R = sp.polys.rings.PolyRing(gens, sp.QQ if numbers else sp.EX, sp.polys.orderings.lex)
    where = {g: R.gens[k] for k, g in enumerate(gens)}

    def check(p):
        if len(p) > max_terms:
            raise OverBudget(f"more than {max_terms} terms")
        if deadline is not None and time.perf_counter() > deadline:
            raise OverBudget("out of time")
        return p

    def walk(e):
        if e in where:
            return where[e]
        if not (e.free_symbols & set(gens)):
            return R(R.domain.from_sympy(e))
        if e.is_Add or e.is_Mul:
            out = walk(e.args[0])
            for a in e.args[1:]:
                out = check(out + walk(a) if e.is_Add else out * walk(a))
            return out
        if e.is_Pow and e.exp.is_Integer and e.exp > 0:
            base, n, out = walk(e.base), int(e.exp), R.one
            while n:                      # square and multiply, checked at every step
                if n & 1:
                    out = check(out * base)
                n >>= 1
                if n:
                    base = check(base * base)
            return out
        raise ValueError(f"{e} is not a polynomial in {gens}")

    return walk(expr)


def best_form(expr, variables, *, seconds: float = REWRITE_SECONDS) -> sp.Expr:
    """The rewriting of ``expr`` whose interval extension overestimates least (an exact identity).

    Candidates: the expression as given, its factored form, its Horner form
    and the completed squares of separable quadratics (polynomials only);
    each is kept only when it expands back to ``expr``.  Floats become the
    equal rationals.

    Parameters
    ----------
    expr : sympy.Expr, number or str
        The expression (text is read by :func:`~workspace_sym.expressions.parse_expr`).
    variables : iterable of sympy.Symbol
        The variables whose repeated occurrences are counted.
    seconds : float
        The time after which no further candidate is tried (default :data:`REWRITE_SECONDS`).

    Returns
    -------
    sympy.Expr
        The candidate with the fewest repeated occurrences of the variables, then the fewest operations;
        ``expr`` (its floats made exact) when no rewriting is tried or none is better.

    Raises
    ------
    ExpressionError
        For text that is not an expression, or an object that is neither text, a number nor SymPy's.

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> best_form(x**2 - 10*x + y**2 - 119, (x, y))
    y**2 + (x - 5)**2 - 144
    >>> best_form(1e10*x**2*y + 8*x/7, (x, y))      # 8/7 stays exact
    x*(10000000000*x*y + 8/7)
    """
    expr = exact_constants(as_sympy(expr))
    variables = tuple(variables)
    if not _worth_rewriting(expr, variables):
        return expr
    candidates = [expr]
    hidden, back = _hide_constants(expr)
    terms, degree = expansion_bound(hidden)     # the placeholders count as symbols for SymPy's factoring
    if terms > MAX_EXPANDED_TERMS or degree > MAX_REWRITE_DEGREE:
        return expr
    gens = variables + tuple(sorted(hidden.free_symbols - set(variables), key=sp.default_sort_key))
    start = time.perf_counter()
    deadline = start + seconds
    try:
        reference = expand_bounded(hidden, gens, max_terms=MAX_EXPANDED_TERMS, deadline=deadline)
    except (OverBudget, ValueError, sp.polys.polyerrors.BasePolynomialError):
        return expr
    for make in (sp.factor, lambda e: sp.horner(e, *variables),
                 lambda e: _complete_squares(reference.as_expr(), variables)):
        if time.perf_counter() >= deadline:
            break
        try:
            form = make(hidden)
            if form is None:
                continue
            # the candidate is kept when it is the same polynomial (checked within the same budget)
            same = expand_bounded(form, gens, max_terms=4 * MAX_EXPANDED_TERMS) == reference
        except (OverBudget, sp.polys.polyerrors.BasePolynomialError, ValueError, TypeError):
            continue
        if same:
            candidates.append(form.xreplace(back))
    return min(candidates, key=lambda e: (repeated_occurrences(e, variables), sp.count_ops(e)))


def _worth_rewriting(expr: sp.Expr, variables) -> bool:
    """Whether a form with fewer repeated variables may exist and the search fits the budgets (cheap checks)."""
    if not variables or repeated_occurrences(expr, variables) == 0:
        return False              # each variable once: the natural extension is already the tightest
    return expr.is_polynomial(*variables) and sp.count_ops(expr) <= MAX_REWRITE_OPS


# ----------------------------------------------------------------------------- public
class CompiledExpr:
    """Interval evaluator of one expression for one backend.

    numpy backend: call with ``X`` a list of ``(lo, hi)`` arrays (one per
    variable), get ``(lo, hi)`` arrays; NaN means no enclosure.
    mpmath backend: call with a list of ``iv.mpf``; ``None`` means no enclosure.
    With the numpy backend an expression that still repeats a variable (and holds no ``Abs``) is
    ``centred``: its value is the intersection of the natural and the mean-value enclosures.

    Parameters
    ----------
    expr : sympy.Expr, number or str
        The expression; its :func:`best_form` is evaluated.
    variables : iterable of sympy.Symbol
        The variables, in the order of ``X``.
    backend : str
        ``"numpy"``; anything else is the mpmath reference (:func:`compile_expr` checks the name).

    Raises
    ------
    ExpressionError
        For an operation the interval compiler does not support, or a symbol that is not a variable.
    """

    def __init__(self, expr, variables, backend):
        self.variables = tuple(variables)
        self.backend = backend
        expr = exact_constants(as_sympy(expr))
        self.expr = best_form(expr, self.variables)
        # The mean-value form needs a derivative: Abs has none at 0 (SymPy writes it with re(x) and im(x)),
        # so an expression holding Abs is enclosed by its natural extension alone.
        self.centred = (repeated_occurrences(self.expr, self.variables) > 0 and backend == "numpy"
                        and not self.expr.has(sp.Abs))
        roots = [self.expr]
        if self.centred:
            roots += [best_form(sp.diff(expr, v), self.variables) for v in self.variables]
            self._at_point = Graph([expr], self.variables)
        self._graph = Graph(roots, self.variables)
        # what a batch needs to evaluate this one inside its own sweep (the same nodes, so the same floats)
        self.roots, self.point = tuple(roots), expr

    def __repr__(self):
        return f"CompiledExpr({self.expr}, backend={self.backend!r}, centred={self.centred})"

    def __call__(self, X):
        values = self._graph.evaluate(X, self.backend)
        if not self.centred:
            return values[0]
        return arith.intersect(values[0], self._mean_value(X, values[1:]))

    def natural(self, X):
        """The natural interval extension of the chosen form alone.

        Parameters
        ----------
        X : list
            One interval per variable, as for a call.

        Returns
        -------
        tuple or mpmath.iv.mpf or None
            The enclosure, as for a call, without the mean-value form.
        """
        return self._graph.evaluate(X, self.backend)[0]

    def mean_value(self, X):
        """Centred form ``f(m) + sum_i G_i(X) (X_i - m_i)`` (numpy backend).

        Parameters
        ----------
        X : list of pair of numpy.ndarray
            One ``(lo, hi)`` interval per variable.

        Returns
        -------
        tuple of numpy.ndarray
            ``(lo, hi)``, the mean-value enclosure alone.  Only a ``centred`` evaluator has one; another
            raises ``AttributeError``.
        """
        return self._mean_value(X, self._graph.evaluate(X, self.backend)[1:])

    def _mean_value(self, X, gradients):
        mids = [0.5 * lo + 0.5 * hi for lo, hi in X]
        (acc,) = self._at_point.evaluate([arith.point(m) for m in mids])
        return _centred(acc, gradients, X, mids)


def _centred(acc, gradients, X, mids):
    """``acc + sum_i G_i (X_i - m_i)``: the mean-value form from the value at the midpoint ``acc``."""
    for grad, (lo, hi), m in zip(gradients, X, mids):
        acc = arith.add(acc, arith.mul(grad, arith.sub((lo, hi), (m, m))))
    return acc


class CompiledBatch:
    """Interval evaluator of several expressions over the same boxes (numpy backend), in one sweep.

    Each expression is compiled as :func:`compile_expr` does (its best form, centred when a variable repeats);
    their graphs are then one :class:`~workspace_sym.interval.graph.Graph`, and the values at the midpoints of
    the centred ones another, so that a subexpression they share (``sin(q2)``, ``cos(q2 + q3)``, their
    products) is enclosed once per call instead of once per expression.  A node's value depends only on the
    subexpression it stands for, so each result is, float for float, what the expression's own evaluator
    returns (``tests/interval/test_interval.py`` checks it).

    Parameters
    ----------
    compiled : iterable of CompiledExpr
        The evaluators of the expressions (numpy backend), all over the same variables.

    Raises
    ------
    ValueError
        An evaluator of another backend, or over other variables.

    Examples
    --------
    >>> import numpy as np
    >>> x, y = sp.symbols("x y")
    >>> batch = compile_batch([sp.sin(x) * y, sp.sin(x) + y**2], (x, y))
    >>> X = [(np.array([0.0]), np.array([0.5])), (np.array([1.0]), np.array([2.0]))]
    >>> alone = [f(X) for f in batch.compiled]           # each expression's own evaluator
    >>> [bool(np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])) for a, b in zip(batch(X), alone)]
    [True, True]
    """

    def __init__(self, compiled):
        self.compiled = tuple(compiled)
        self.variables = self.compiled[0].variables if self.compiled else ()
        if any(f.backend != "numpy" or f.variables != self.variables for f in self.compiled):
            raise ValueError("a batch holds evaluators of the numpy backend over the same variables")
        roots, self._slices, points = [], [], []
        for f in self.compiled:
            self._slices.append((len(roots), len(f.roots), len(points) if f.centred else None))
            roots += f.roots
            if f.centred:
                points.append(f.point)
        self._graph = Graph(roots, self.variables)
        self._at_point = Graph(points, self.variables) if points else None

    def __len__(self) -> int:
        return len(self.compiled)

    def __call__(self, X) -> list:
        """The enclosures of the expressions over ``X`` (a list of ``(lo, hi)`` arrays, one per variable): a
        list of ``(lo, hi)`` pairs, NaN meaning no enclosure, as each expression's own evaluator gives them."""
        values = self._graph.evaluate(X)
        mids: list = []
        at_mids: list = []
        if self._at_point is not None:
            mids = [0.5 * lo + 0.5 * hi for lo, hi in X]
            at_mids = self._at_point.evaluate([arith.point(m) for m in mids])
        out = []
        for start, count, point in self._slices:
            if point is None:
                out.append(values[start])
            else:
                centred = _centred(at_mids[point], values[start + 1:start + count], X, mids)
                out.append(arith.intersect(values[start], centred))
        return out


def compile_batch(expressions, variables) -> CompiledBatch:
    """One evaluator of several expressions over the same variables (numpy backend), each result the
    floats :func:`compile_expr`'s evaluator of that expression gives (:class:`CompiledBatch`).

    Parameters
    ----------
    expressions : iterable
        The expressions (SymPy, numbers or text).
    variables : iterable of sympy.Symbol
        The variables; every symbol of each expression must be one.

    Returns
    -------
    CompiledBatch
        The evaluator.

    Raises
    ------
    ExpressionError
        As :func:`compile_expr`.
    """
    variables = tuple(variables)
    return CompiledBatch([compile_expr(e, variables) for e in expressions])


@lru_cache(maxsize=512)
def _compile_cached(expr, variables, backend):
    return CompiledExpr(expr, variables, backend)


def compile_expr(expr, variables, *, backend: str = "numpy") -> CompiledExpr:
    """Interval evaluator of ``expr`` over ``variables`` (cached).

    Parameters
    ----------
    expr : sympy.Expr, number or str
        The expression (text is read by :func:`~workspace_sym.expressions.parse_expr`).
    variables : iterable of sympy.Symbol
        The variables, in the order the evaluator takes their intervals; every symbol of ``expr`` must be one.
    backend : str
        ``"numpy"`` (default: arrays of boxes, floats rounded outward) or ``"mpmath"`` (one box, at the
        precision in force).

    Returns
    -------
    CompiledExpr
        The evaluator; the same object for the same expression, variables and backend while it stays among
        the 512 last compiled.

    Raises
    ------
    UnknownNameError
        For a backend not in :data:`BACKENDS`.
    ExpressionError
        For an expression that cannot be read, a symbol that is not among ``variables``, or an operation the
        interval compiler does not support.

    Examples
    --------
    >>> import numpy as np
    >>> x = sp.Symbol("x")
    >>> f = compile_expr(x**2 - 2*x, (x,))
    >>> lo, hi = f([(np.array([0.0]), np.array([2.0]))])
    >>> bool(lo[0] >= -1.0000001 and hi[0] <= 0.0000001)
    True
    """
    check_choice("backend", backend, BACKENDS)
    expr = as_sympy(expr)
    unknown = expr.free_symbols - set(variables)
    if unknown:
        names = ", ".join(sorted(map(str, unknown)))
        raise ExpressionError(f"expression {expr}: unknown symbol(s) {names}; variables are "
                              f"{', '.join(map(str, variables))}")
    return _compile_cached(expr, tuple(variables), backend)

