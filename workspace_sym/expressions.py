"""Reading numbers and SymPy expressions from user input, with clear errors."""

from __future__ import annotations

import math
from numbers import Number
from tokenize import TokenError

import sympy as sp

from .errors import ExpressionError

__all__ = ["parse_expr", "parse_angle", "is_finite_value"]


def parse_expr(value, parameter: str) -> sp.Expr:
    """Read ``value`` (number, SymPy object or string) as an exact-where-possible expression.

    Integers and rationals stay exact, floats are used as given, strings are read
    with :func:`sympy.sympify`.  NaN and infinities are refused.

    Examples
    --------
    >>> parse_expr("pi/2", "alpha")
    pi/2
    >>> parse_expr(3, "d")
    3
    >>> parse_expr("2*(", "a")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: a: cannot read '2*(' as an expression
    """
    if isinstance(value, bool) or value is None:
        raise ExpressionError(f"{parameter}: expected a number or an expression, got {value!r}")
    if isinstance(value, sp.Basic):
        expr = value
    elif isinstance(value, Number):
        if isinstance(value, float) and not math.isfinite(value):
            raise ExpressionError(f"{parameter}: expected a finite number, got {value!r}")
        expr = sp.sympify(value)
    elif isinstance(value, str):
        text = value.strip()
        if not text:
            raise ExpressionError(f"{parameter}: expected an expression, got an empty string")
        try:
            expr = sp.sympify(text, rational=False)
        except (sp.SympifyError, SyntaxError, TypeError, AttributeError, TokenError) as exc:
            raise ExpressionError(f"{parameter}: cannot read {value!r} as an expression") from exc
    else:
        raise ExpressionError(f"{parameter}: expected a number or an expression, got {value!r}")
    if not isinstance(expr, sp.Expr):
        raise ExpressionError(f"{parameter}: expected an expression, got {value!r}")
    if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise ExpressionError(f"{parameter}: expected a finite value, got {value!r}")
    return expr


def parse_angle(value, parameter: str, *, degrees: bool) -> sp.Expr:
    """Read an angle; plain numbers are degrees when ``degrees`` is true.

    An expression that contains ``pi`` or a symbol is taken as radians whatever
    ``degrees`` says, so ``"pi/2"`` and ``90`` mean the same in a degree table.
    Integer degrees stay exact: ``90`` becomes ``pi/2``.

    Examples
    --------
    >>> parse_angle(90, "alpha", degrees=True)
    pi/2
    >>> parse_angle("pi/2", "alpha", degrees=True)
    pi/2
    >>> parse_angle("alpha1", "alpha", degrees=True)
    alpha1
    """
    expr = parse_expr(value, parameter)
    if degrees and expr.is_number and not expr.has(sp.pi):
        return expr * sp.pi / 180
    return expr


def is_finite_value(expr: sp.Expr) -> bool:
    """True when ``expr`` is a number that evaluates to a finite real."""
    if not expr.is_number:
        return True
    value = complex(expr.evalf())
    return math.isfinite(value.real) and value.imag == 0
