"""Compile SymPy expressions into interval evaluators (numpy engine or mpmath reference).

The interval extension of an expression depends on how it is written: every
repeated occurrence of a variable can widen the enclosure (the dependency
problem).  :func:`best_form` picks, among the expression as given, its
factored form, its Horner form and the completed-square form of separable
quadratics, the one with the fewest repeated occurrences; when a variable is
still repeated, the evaluator also computes the centred (mean-value) form
``f(m) + grad f(X) . (X - m)`` and intersects the two enclosures.

Compiled evaluators are cached per (expression, variables, backend).
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

import sympy as sp

from ..errors import ExpressionError, check_choice
from ..expressions import as_sympy
from . import arith
from . import mp as mpi

__all__ = ["best_form", "compile_expr", "CompiledExpr", "BACKENDS", "repeated_occurrences"]

BACKENDS = ("numpy", "mpmath")
_EXACT_INT = 2**53


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


def best_form(expr, variables) -> sp.Expr:
    """The rewriting of ``expr`` whose interval extension overestimates least.

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> best_form(x**2 - 10*x + y**2 - 119, (x, y))
    y**2 + (x - 5)**2 - 144
    """
    expr = as_sympy(expr)
    variables = tuple(variables)
    candidates = [expr]
    if expr.is_polynomial(*variables):
        for make in (sp.factor, lambda e: sp.horner(e, *variables) if variables else e,
                     lambda e: _complete_squares(sp.expand(e), variables)):
            try:
                form = make(expr)
            except (sp.PolynomialError, ValueError, TypeError):
                continue
            if form is not None:
                candidates.append(form)
    return min(candidates, key=lambda e: (repeated_occurrences(e, variables), sp.count_ops(e)))


# ----------------------------------------------------------------------------- constants
def _numpy_const(value: sp.Expr):
    if value.is_Integer:
        n = int(value)
        if abs(n) <= _EXACT_INT:
            return (float(n), float(n))
        f = float(n)
        return (float(arith.down(f)), float(arith.up(f)))
    if value.is_Rational:
        p, q = int(value.p), int(value.q)
        f = p / q  # correctly rounded
        if Fraction(f) == Fraction(p, q):
            return (f, f)
        return (float(arith.down(f)), float(arith.up(f)))
    # Floats as typed (decimal), pi, sqrt(2), ...: enclose at 60 digits, then widen.
    with mpi.precision(60):
        enclosure = _compile_tree(value, (), "mpmath")([])
    if enclosure is None:
        raise ExpressionError(f"constant {value} is not a real number")
    return (float(arith.down(float(enclosure.a))), float(arith.up(float(enclosure.b))))


def _mp_const(value: sp.Expr):
    if value.is_Integer:
        return mpi.iv.mpf(int(value))
    if value.is_Rational:
        return mpi.const_rational(int(value.p), int(value.q))
    if value.is_Float:
        return mpi.const_float(str(value))
    if value == sp.pi:
        return +mpi.iv.pi
    return +mpi.iv.e


# ----------------------------------------------------------------------------- tree compilation
def _unsupported(node):
    raise ExpressionError(
        f"expression: {type(node).__name__} ({node}) is not supported by the interval compiler; "
        "supported: + - * /, integer powers, sqrt, sin, cos, Abs"
    )


def _lift(fn):
    """mpmath operations propagate a domain error (None) instead of raising."""

    def g(*vals):
        if any(v is None for v in vals):
            return None
        return fn(*vals)

    return g


def _mp_sqrt_recip(v):
    r = mpi.sqrt(v)
    return None if r is None else mpi.div(mpi.iv.mpf(1), r)


_ONE = (1.0, 1.0)

# One operation table per backend; the tree walk below is shared.  Constants:
# numpy encloses every number once at compile time; mpmath encloses the leaves
# at call time because its precision may change between calls.
_OPS = {
    "numpy": {
        "is_const": lambda node: node.is_number,
        "const": lambda node: (lambda c: lambda X: c)(_numpy_const(node)),
        "add": arith.add, "mul": arith.mul, "neg": arith.neg, "ipow": arith.ipow,
        "recip": lambda v: arith.div(_ONE, v), "sqrt": arith.sqrt,
        "recip_sqrt": lambda v: arith.div(_ONE, arith.sqrt(v)),
        sp.sin: arith.sin, sp.cos: arith.cos, sp.Abs: arith.iabs,
    },
    "mpmath": {
        "is_const": lambda node: node.is_Rational or node.is_Float or node in (sp.pi, sp.E),
        "const": lambda node: lambda X: _mp_const(node),
        "add": _lift(lambda a, b: a + b), "mul": _lift(lambda a, b: a * b), "neg": _lift(lambda a: -a),
        "ipow": _lift(mpi.ipow), "recip": _lift(lambda v: mpi.div(mpi.iv.mpf(1), v)), "sqrt": _lift(mpi.sqrt),
        "recip_sqrt": _lift(_mp_sqrt_recip),
        sp.sin: _lift(mpi.sin), sp.cos: _lift(mpi.cos), sp.Abs: _lift(mpi.iabs),
    },
}


def _compile_tree(expr: sp.Expr, variables, backend: str):
    """A closure tree evaluating ``expr`` with the interval operations of ``backend``."""
    ops = _OPS[backend]
    index = {v: k for k, v in enumerate(variables)}

    def fold(op, parts):
        def f(X):
            acc = parts[0](X)
            for p in parts[1:]:
                acc = op(acc, p(X))
            return acc

        return f

    def build(node):
        if node in index:
            k = index[node]
            return lambda X: X[k]
        if ops["is_const"](node):
            return ops["const"](node)
        if node.is_Add:
            return fold(ops["add"], [build(a) for a in node.args])
        if node.is_Mul:
            coeff, rest = node.as_coeff_Mul()
            if coeff == -1:
                inner, neg = build(rest), ops["neg"]
                return lambda X: neg(inner(X))
            return fold(ops["mul"], [build(a) for a in node.args])
        if node.is_Pow:
            base, e = node.args
            b = build(base)
            if e.is_Integer and int(e) >= 1:
                n, ipow = int(e), ops["ipow"]
                return lambda X: ipow(b(X), n)
            if e.is_Integer:
                n, ipow, recip = -int(e), ops["ipow"], ops["recip"]
                return lambda X: recip(ipow(b(X), n))
            if e in (sp.Rational(1, 2), sp.Rational(-1, 2)):
                fn = ops["sqrt"] if e > 0 else ops["recip_sqrt"]
                return lambda X: fn(b(X))
            _unsupported(node)
        fn = ops.get(type(node))
        if fn is not None:
            a = build(node.args[0])
            return lambda X: fn(a(X))
        _unsupported(node)

    return build(expr)


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
        self.expr = best_form(expr, self.variables)
        make = lambda e, v: _compile_tree(e, v, backend)  # noqa: E731
        self._natural = make(self.expr, self.variables)
        self.centred = repeated_occurrences(self.expr, self.variables) > 0 and backend == "numpy"
        if self.centred:
            self._f = make(as_sympy(expr), self.variables)
            self._grad = [make(best_form(sp.diff(expr, v), self.variables), self.variables)
                          for v in self.variables]

    def __repr__(self):
        return f"CompiledExpr({self.expr}, backend={self.backend!r}, centred={self.centred})"

    def __call__(self, X):
        value = self._natural(X)
        if not self.centred:
            return value
        return arith.intersect(value, self.mean_value(X))

    def mean_value(self, X):
        """Centred form ``f(m) + sum_i G_i(X) (X_i - m_i)`` (numpy backend)."""
        mids = [0.5 * lo + 0.5 * hi for lo, hi in X]
        M = [arith.point(m) for m in mids]
        acc = self._f(M)
        for grad, (lo, hi), m in zip(self._grad, X, mids):
            acc = arith.add(acc, arith.mul(grad(X), arith.sub((lo, hi), (m, m))))
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

