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
it expands back to the expression.  The preparation is bounded: expressions
larger than ``MAX_REWRITE_OPS`` operations, or a search that has run for
``REWRITE_SECONDS``, keep the forms found so far (at least the natural one).

The evaluators are :class:`~workspace_sym.interval.graph.Graph` forward
sweeps; compiled evaluators are cached per (expression, variables, backend).
"""

from __future__ import annotations

import time
from functools import lru_cache

import sympy as sp

from ..errors import ExpressionError, check_choice
from ..expressions import as_sympy
from . import arith
from .graph import Graph, exact_constants

__all__ = ["best_form", "compile_expr", "CompiledExpr", "BACKENDS", "repeated_occurrences"]

BACKENDS = ("numpy", "mpmath")
MAX_REWRITE_OPS = 400     # larger expressions are evaluated as written
REWRITE_SECONDS = 2.0     # no further candidate form is tried after this


# ----------------------------------------------------------------------------- forms
def repeated_occurrences(expr: sp.Expr, variables) -> int:
    """Sum over variables of (occurrences - 1): zero means the natural extension is exact."""
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


def best_form(expr, variables, *, seconds: float = REWRITE_SECONDS) -> sp.Expr:
    """The rewriting of ``expr`` whose interval extension overestimates least (an exact identity).

    Candidates: the expression as given, its factored form, its Horner form
    and the completed squares of separable quadratics (polynomials only);
    each is kept only when it expands back to ``expr``.  Floats become the
    equal rationals.

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
    candidates = [expr]
    if variables and expr.is_polynomial(*variables) and sp.count_ops(expr) <= MAX_REWRITE_OPS:
        hidden, back = _hide_constants(expr)
        reference = sp.expand(hidden)
        start = time.perf_counter()
        for make in (sp.factor, lambda e: sp.horner(e, *variables),
                     lambda e: _complete_squares(sp.expand(e), variables)):
            if time.perf_counter() - start >= seconds:
                break
            try:
                form = make(hidden)
            except (sp.polys.polyerrors.BasePolynomialError, ValueError, TypeError):
                continue
            if form is not None and sp.expand(form - reference) == 0:
                candidates.append(form.xreplace(back))
    return min(candidates, key=lambda e: (repeated_occurrences(e, variables), sp.count_ops(e)))


# ----------------------------------------------------------------------------- public
class CompiledExpr:
    """Interval evaluator of one expression for one backend.

    numpy backend: call with ``X`` a list of ``(lo, hi)`` arrays (one per
    variable), get ``(lo, hi)`` arrays; NaN means no enclosure.
    mpmath backend: call with a list of ``iv.mpf``; ``None`` means no enclosure.
    """

    def __init__(self, expr, variables, backend):
        self.variables = tuple(variables)
        self.backend = backend
        expr = exact_constants(as_sympy(expr))
        self.expr = best_form(expr, self.variables)
        self.centred = repeated_occurrences(self.expr, self.variables) > 0 and backend == "numpy"
        roots = [self.expr]
        if self.centred:
            roots += [best_form(sp.diff(expr, v), self.variables) for v in self.variables]
            self._at_point = Graph([expr], self.variables)
        self._graph = Graph(roots, self.variables)

    def __repr__(self):
        return f"CompiledExpr({self.expr}, backend={self.backend!r}, centred={self.centred})"

    def __call__(self, X):
        values = self._graph.evaluate(X, self.backend)
        if not self.centred:
            return values[0]
        return arith.intersect(values[0], self._mean_value(X, values[1:]))

    def natural(self, X):
        """The natural interval extension of the chosen form alone."""
        return self._graph.evaluate(X, self.backend)[0]

    def mean_value(self, X):
        """Centred form ``f(m) + sum_i G_i(X) (X_i - m_i)`` (numpy backend)."""
        return self._mean_value(X, self._graph.evaluate(X, self.backend)[1:])

    def _mean_value(self, X, gradients):
        mids = [0.5 * lo + 0.5 * hi for lo, hi in X]
        (acc,) = self._at_point.evaluate([arith.point(m) for m in mids])
        for grad, (lo, hi), m in zip(gradients, X, mids):
            acc = arith.add(acc, arith.mul(grad, arith.sub((lo, hi), (m, m))))
        return acc


@lru_cache(maxsize=512)
def _compile_cached(expr, variables, backend):
    return CompiledExpr(expr, variables, backend)


def compile_expr(expr, variables, *, backend: str = "numpy") -> CompiledExpr:
    """Interval evaluator of ``expr`` over ``variables`` (cached).

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

