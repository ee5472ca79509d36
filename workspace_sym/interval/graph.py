"""SymPy expressions as one straight-line program over their DAG: the single translator to interval code.

Every interval evaluation of the package starts here.  :class:`Graph` turns a
list of SymPy expressions into nodes (variables, constants and the supported
operations), sharing common subexpressions; its forward sweep encloses every
node over boxes with the numpy engine (arrays of boxes) or the mpmath
reference (one box, any precision).  :mod:`~workspace_sym.interval.compiler`
evaluates the roots, :mod:`~workspace_sym.interval.contractor` adds a
backward sweep on the same nodes.  An operation is added in one place: the
``_build`` dispatch and the two operation tables below.

Constants are exact.  A SymPy ``Float`` is the binary number it holds (not
the decimal it was printed from), so :func:`exact_constants` replaces it by
the equal ``Rational`` before any rewriting: a rewriting of a float
expression by SymPy (``factor``, ``horner``) would otherwise round its
coefficients to 15 digits.  The numpy engine encloses each constant
subexpression (``pi/2``, ``sqrt(3)``, ``8/7``) once, at 60 digits, widened to
floats; the mpmath reference encloses the constant leaves at call time, at
the precision in force.
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction

import numpy as np
import sympy as sp

from ..errors import ExpressionError
from ..expressions import as_sympy
from . import arith
from . import mp as mpi

__all__ = ["Graph", "exact_constants", "SUPPORTED", "numpy_constant"]

SUPPORTED = "+ - * /, integer and half-integer powers, sqrt, sin, cos, Abs"
_ONE = (1.0, 1.0)
_FUNCTIONS = {sp.sin: "sin", sp.cos: "cos", sp.Abs: "abs"}


def exact_constants(expr: sp.Expr) -> sp.Expr:
    """``expr`` with every ``Float`` replaced by the ``Rational`` of the same value (exact).

    Parameters
    ----------
    expr : sympy.Expr
        The expression.

    Returns
    -------
    sympy.Expr
        The expression with exact constants (``expr`` itself when it holds no float).

    Examples
    --------
    >>> x = sp.Symbol("x")
    >>> exact_constants(0.5 * x + sp.Rational(8, 7))
    x/2 + 8/7
    >>> exact_constants(0.1 * x)                     # 0.1 as a float is a binary fraction
    3602879701896397*x/36028797018963968
    """
    floats = expr.atoms(sp.Float)
    if not floats:
        return expr
    return expr.xreplace({f: sp.Rational(f) for f in floats})


def _unsupported(node, what="is not supported by the interval compiler"):
    raise ExpressionError(f"expression: {type(node).__name__} ({node}) {what}; supported: {SUPPORTED}")


# ----------------------------------------------------------------------------- constants
def numpy_constant(value: sp.Expr) -> tuple[float, float]:
    """Two floats enclosing the real constant ``value`` (equal when it is a float exactly).

    Parameters
    ----------
    value : sympy.Expr, number or str
        A constant expression (no symbol).

    Returns
    -------
    tuple of float
        ``(lo, hi)``; a rational beyond the float range gives ``(largest float, inf)`` or its negative.  Other
        constants are enclosed at 60 digits and widened by a float spacing each way.

    Raises
    ------
    ExpressionError
        For a constant that is not real (``sqrt(1 - pi)``), or one the interval compiler does not support
        (``sqrt(-2)``, which SymPy writes with ``I``).
    """
    value = exact_constants(as_sympy(value))
    if value.is_Rational:
        p, q = int(value.p), int(value.q)
        try:
            f = p / q  # correctly rounded (Python's int true division)
        except OverflowError:
            return (float(np.finfo(float).max), np.inf) if p > 0 else (-np.inf, -float(np.finfo(float).max))
        if Fraction(f) == Fraction(p, q):
            return (f, f)
        return (float(arith.down(f)), float(arith.up(f)))
    # pi, sqrt(2), pi/2 + 1/3, ...: enclosed at 60 digits by the mpmath reference, then widened.
    with mpi.precision(60):
        (enclosure,) = Graph([value], (), fold=False).evaluate([], "mpmath")
    if enclosure is None:
        raise ExpressionError(f"constant {value} is not a real number")
    return (float(arith.down(float(enclosure.a))), float(arith.up(float(enclosure.b))))


def _mp_leaf(value: sp.Expr):
    if value.is_Integer:
        return mpi.iv.mpf(int(value))
    if value.is_Rational:
        return mpi.const_rational(int(value.p), int(value.q))
    if value == sp.pi:
        return +mpi.iv.pi
    return +mpi.iv.e


# ----------------------------------------------------------------------------- operations
def _lift(fn):
    """mpmath operations propagate a domain error (None) instead of raising."""

    def g(*args):                       # child values..., then the node's parameter
        if any(v is None for v in args[:-1]):
            return None
        return fn(*args)

    return g


# kind -> function of (child values..., parameter)
_NUMPY: dict[str, Callable] = {
    "add": lambda a, b, p: arith.add(a, b),
    "mul": lambda a, b, p: arith.mul(a, b),
    "neg": lambda a, p: arith.neg(a),
    "pow": lambda a, p: arith.ipow(a, p),
    "recip": lambda a, p: arith.div(_ONE, a),
    "sqrt": lambda a, p: arith.sqrt(a),
    "sin": lambda a, p: arith.sin(a),
    "cos": lambda a, p: arith.cos(a),
    "abs": lambda a, p: arith.iabs(a),
}
_MPMATH: dict[str, Callable] = {
    "add": _lift(lambda a, b, p: a + b),
    "mul": _lift(lambda a, b, p: a * b),
    "neg": _lift(lambda a, p: -a),
    "pow": _lift(lambda a, p: mpi.ipow(a, p)),
    "recip": _lift(lambda a, p: mpi.div(mpi.iv.mpf(1), a)),
    "sqrt": _lift(lambda a, p: mpi.sqrt(a)),
    "sin": _lift(lambda a, p: mpi.sin(a)),
    "cos": _lift(lambda a, p: mpi.cos(a)),
    "abs": _lift(lambda a, p: mpi.iabs(a)),
}


class Graph:
    """Expressions over ``variables`` as a list of nodes ``(kind, children, parameter)``.

    Kinds: ``var`` (parameter: the variable's index), ``const`` (parameter:
    the SymPy constant), ``add``, ``mul`` (binary), ``neg``, ``pow``
    (parameter: a positive integer exponent), ``recip``, ``sqrt``, ``sin``,
    ``cos``, ``abs``.  A child always comes before its parents.  Equal
    subexpressions are one node, so a forward sweep evaluates them once.

    ``fold=False`` keeps constant subexpressions as operations over constant
    leaves (rationals, ``pi``, ``E``): used to enclose a constant itself.

    Parameters
    ----------
    expressions : iterable
        The expressions (SymPy, numbers or text); their roots are :attr:`roots`, in order.
    variables : iterable of sympy.Symbol
        The variables, in the order of the intervals a sweep takes.
    fold : bool
        Enclose each constant subexpression once, as a leaf (default True).

    Raises
    ------
    ExpressionError
        For an operation outside :data:`SUPPORTED`, a symbol that is not a variable, or a constant that is not
        real.

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> g = Graph([x**2 + y**2 - 1, x**2 + y**2 - 4], (x, y))
    >>> len(g.nodes), g.roots          # x, y, x^2, y^2, their sum, two constants, two sums
    (9, [6, 8])
    >>> lo, hi = g.evaluate([(np.array([0.0]), np.array([1.0])), (np.array([0.0]), np.array([1.0]))])[0]
    >>> bool(-1 - 1e-12 < lo[0] <= -1 and 1 <= hi[0] < 1 + 1e-12)      # [-1, 1], rounded outward
    True
    """

    def __init__(self, expressions, variables, *, fold: bool = True):
        self.variables = tuple(variables)
        self.fold = fold
        self.nodes: list[tuple] = []
        self._memo: dict = {}
        for k, v in enumerate(self.variables):
            self._add(("var", (), k), v)
        self.roots = [self._build(exact_constants(as_sympy(e))) for e in expressions]
        self._numpy_consts = {i: numpy_constant(p) for i, (kind, _, p) in enumerate(self.nodes)
                              if kind == "const" and fold}
        self._mp_graphs: dict = {}

    # -------------------------------------------------------------- building
    def _add(self, node, key=None):
        if key is not None and key in self._memo:
            return self._memo[key]
        self.nodes.append(node)
        i = len(self.nodes) - 1
        if key is not None:
            self._memo[key] = i
        return i

    def _const(self, value):
        return self._add(("const", (), value), ("const", value))

    def _leaf_constant(self, expr) -> bool:
        if self.fold:
            return expr.is_number
        return expr.is_Rational or expr in (sp.pi, sp.E)

    def _build(self, expr):
        if expr in self._memo:               # variables and shared subexpressions
            return self._memo[expr]
        if self._leaf_constant(expr):
            return self._const(expr)
        if expr.is_Symbol:
            raise ExpressionError(f"expression: unknown symbol {expr}; variables are "
                                  f"{', '.join(map(str, self.variables)) or 'none'}")
        if expr.is_Add:
            # Non-constant terms first, in a fixed order, then the constant: g = e + c shares e.
            const, rest = expr.as_coeff_Add() if self.fold else (sp.Integer(0), expr)
            terms = sorted(sp.Add.make_args(rest), key=sp.default_sort_key)
            if rest in self._memo:
                acc = self._memo[rest]
            elif len(terms) > 1 and all(t.could_extract_minus_sign() for t in terms):
                acc = self._add(("neg", (self._build(-rest),), None), rest)
            else:
                acc = self._build(terms[0])
                for t in terms[1:]:
                    acc = self._add(("add", (acc, self._build(t)), None))
                self._memo[rest] = acc
            if const != 0:
                acc = self._add(("add", (acc, self._const(const)), None))
            self._memo[expr] = acc
            return acc
        if expr.is_Mul:
            coeff, rest = expr.as_coeff_Mul()
            if coeff == -1:
                return self._add(("neg", (self._build(rest),), None), expr)
            factors = sorted(sp.Mul.make_args(expr), key=sp.default_sort_key)
            acc = self._build(factors[0])
            for f in factors[1:]:
                acc = self._add(("mul", (acc, self._build(f)), None))
            self._memo[expr] = acc
            return acc
        if expr.is_Pow:
            base, e = expr.args
            if e.is_Integer and int(e) >= 1:
                return self._add(("pow", (self._build(base),), int(e)), expr)
            if e.is_Integer:
                b = self._build(base)
                p = b if int(e) == -1 else self._add(("pow", (b,), -int(e)), base ** (-e))
                return self._add(("recip", (p,), None), expr)
            if e.is_Rational and e.q == 2:     # sqrt(x)**3 is x**(3/2) in SymPy
                if e < 0:
                    return self._add(("recip", (self._build(base ** -e),), None), expr)
                if e.p == 1:
                    return self._add(("sqrt", (self._build(base),), None), expr)
                return self._add(("pow", (self._build(sp.sqrt(base)),), int(e.p)), expr)
        kind = _FUNCTIONS.get(type(expr))
        if kind is not None:
            return self._add((kind, (self._build(expr.args[0]),), None), expr)
        _unsupported(expr)

    # -------------------------------------------------------------- forward sweep
    def forward(self, X, backend: str = "numpy") -> list:
        """Enclosures of every node over the box(es) ``X``.

        numpy: ``X`` is a list of ``(lo, hi)`` arrays, one per variable; a
        value is a ``(lo, hi)`` pair, NaN meaning no enclosure.  mpmath:
        ``X`` is a list of ``iv.mpf``; ``None`` means no enclosure (a domain
        error).

        Parameters
        ----------
        X : list
            One interval per variable.
        backend : str
            ``"numpy"`` (default); anything else is the mpmath reference.

        Returns
        -------
        list
            The enclosure of every node, in the order of :attr:`nodes`.
        """
        numpy = backend == "numpy"
        ops = _NUMPY if numpy else _MPMATH
        vals = []
        for i, (kind, ch, p) in enumerate(self.nodes):
            if kind == "var":
                vals.append(X[p])
            elif kind == "const":
                vals.append(self._numpy_consts[i] if numpy else self._mp_constant(i, p))
            else:
                vals.append(ops[kind](*(vals[c] for c in ch), p))
        return vals

    def _mp_constant(self, i, value):
        """A constant enclosed at the precision in force (a folded one through its own graph)."""
        if value.is_Rational or value in (sp.pi, sp.E):
            return _mp_leaf(value)
        if i not in self._mp_graphs:
            self._mp_graphs[i] = Graph([value], (), fold=False)
        return self._mp_graphs[i].evaluate([], "mpmath")[0]

    def evaluate(self, X, backend: str = "numpy") -> list:
        """Enclosures of the roots (the expressions, in order) over ``X``.

        Parameters
        ----------
        X : list
            One interval per variable, as for :meth:`forward`.
        backend : str
            ``"numpy"`` (default) or ``"mpmath"``.

        Returns
        -------
        list
            One enclosure per expression.
        """
        vals = self.forward(X, backend)
        return [vals[r] for r in self.roots]
