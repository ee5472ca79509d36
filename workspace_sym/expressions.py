"""The one reader of user text: numbers and SymPy expressions, validated before SymPy sees them.

Every string a user gives (DH fields, lengths, joint limits, parameters,
constraints, student answers, command-line options) is read by
:func:`parse_expr`.  :func:`sympy.sympify` evaluates its input as Python, so
a DH file holding ``"__import__('os').system(...)"`` would run the command;
here the text is first parsed with :mod:`ast` and only a small grammar of
arithmetic is accepted, then SymPy's parser evaluates it in a namespace that
holds nothing but the allowed names.  Both the user's text and the code SymPy
generates from it are checked.

Non-strings are not text: :func:`as_sympy` turns internal values (SymPy
objects, numbers) into SymPy without ever parsing a string.
"""

from __future__ import annotations

import ast
import keyword
import math
import re
import warnings
from collections.abc import Mapping
from numbers import Number

import sympy as sp
from sympy.parsing.sympy_parser import auto_number, eval_expr, rationalize, stringify_expr

from .errors import ExpressionError, JointLimitError, Refused

__all__ = ["parse_expr", "parse_math", "subscript_name", "parse_angle", "read_symbol", "as_sympy", "is_finite_value",
           "check_joint_limits", "refuse_plus_minus", "refuse_decimal_comma", "FUNCTIONS", "CONSTANTS", "MAX_LENGTH",
           "MAX_DEPTH", "PLUS_MINUS", "as_matrix"]

#: Longest text accepted (characters); ``max_length=`` changes it per call.
MAX_LENGTH = 2000
#: Deepest nesting of operations and parentheses accepted.
MAX_DEPTH = 100
#: Largest magnitude of a numeric exponent (``x**1000`` is fine, ``2**2**2**2**2`` is not).
MAX_EXPONENT = 1000
#: Most decimal digits of a power's value or of a function's numeric argument (``10**300`` is fine).
#: SymPy extracts roots of big integers by trial division: sqrt of a 2,000-digit integer takes seconds.
MAX_DIGITS = 300

#: Most arguments of all Min and Max calls of one text together.
MAX_SORTING_ARGUMENTS = 16
_SORTING = ("Min", "Max")

#: Functions a user may call, by name.
FUNCTIONS = {
    "sqrt": sp.sqrt, "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "asin": sp.asin, "acos": sp.acos,
    "atan": sp.atan, "atan2": sp.atan2, "exp": sp.exp, "log": sp.log, "Abs": sp.Abs, "Min": sp.Min, "Max": sp.Max,
}
#: Named constants.
CONSTANTS = {"pi": sp.pi, "E": sp.E}
# Names the generated code itself uses (auto_number writes ``Integer (2 )``, ``Rational ('0.1')``).
_MACHINERY = {"Integer": sp.Integer, "Float": sp.Float, "Rational": sp.Rational, "Symbol": sp.Symbol}
# Names a user may not take as symbols: the machinery, and SymPy's spellings of non-finite or complex values.
_RESERVED = frozenset(_MACHINERY) | {"oo", "zoo", "nan", "I"}

_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_UNARYOPS = (ast.UAdd, ast.USub)
_COMPARISONS = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">="}
_SHOWN = 60
_LOG2 = math.log10(2)
_DECIMAL = re.compile(r"(?P<int>[0-9_]*)(?:\.(?P<frac>[0-9_]*))?(?:[eE](?P<exp>[+-]?[0-9_]+))?")


#: A plus-or-minus sign as people type it: ``±``, ``∓``, ``+/-``, ``+-`` or ``+ -`` (Python's grammar reads
#: ``1.4 +- 0.01`` as ``1.4 + (-0.01)``), LaTeX's ``\\pm`` and ``\\mp``.
PLUS_MINUS = re.compile(r"\u00b1|\u2213|\+\s*/\s*-|\+\s*-|\\(?:pm|mp)(?![A-Za-z])")


def refuse_plus_minus(text: str, parameter: str, *, offset: int = 0) -> None:
    """Raise :class:`ExpressionError` when ``text`` holds a plus-or-minus sign (:data:`PLUS_MINUS`).

    A value read from text is one value: ``1.40474 +- 0.01`` is a value and its uncertainty, never the
    subtraction ``1.39474`` that Python's unary minus would make of it.  ``offset`` is added to the column.

    Parameters
    ----------
    text : str
        The text to check; anything that is not a string passes.
    parameter : str
        What the text is, for the message and the error's ``parameter``.
    offset : int
        Added to the column reported (the text is a piece of a longer one).

    Raises
    ------
    ExpressionError
        When a plus-or-minus sign is found; ``position`` is its 1-based column (plus ``offset``).

    Examples
    --------
    >>> refuse_plus_minus("0.2 + -0.1", "d")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: d: cannot read '0.2 + -0.1': '+ -' at column 5 is a plus-or-minus sign, \
which gives two values, not one; give one value (a subtraction is written a - b)
    """
    m = PLUS_MINUS.search(text) if isinstance(text, str) else None
    if m is None:
        return
    column = offset + m.start() + 1
    raise ExpressionError(f"{parameter}: cannot read {quoted(text)}: {m.group()!r} at column {column} is a "
                          "plus-or-minus sign, which gives two values, not one; give one value (a subtraction is "
                          "written a - b)", parameter=parameter, position=column)


_DECIMAL_COMMA = re.compile(r"\s*([-+]?[0-9]+),([0-9]+)\s*")


def refuse_decimal_comma(text: str, parameter: str) -> None:
    """Raise :class:`ExpressionError` when ``text`` is a number written with a decimal comma (``1,40``), saying how
    to write it.

    Parameters
    ----------
    text : str
        The text to check: the whole of it, spaces aside, must be the number (``"1,40"``, ``"-2,5"``); anything
        else, and anything that is not a string, passes.
    parameter : str
        What the text is, for the message and the error's ``parameter``.

    Raises
    ------
    ExpressionError
        When ``text`` is such a number; ``position`` is the 1-based column of the comma.

    Examples
    --------
    >>> refuse_decimal_comma("1,40", "answer")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: answer: cannot read '1,40': a comma is not a decimal point; write 1.40
    """
    m = _DECIMAL_COMMA.fullmatch(text) if isinstance(text, str) else None
    if m is None:
        return
    thousands = f", or {m[1]}{m[2]} without the thousands separator" if len(m[2]) == 3 else ""
    raise ExpressionError(f"{parameter}: cannot read {quoted(text)}: a comma is not a decimal point; write "
                          f"{m[1]}.{m[2]}{thousands}", parameter=parameter, position=text.index(",") + 1)


def quoted(text: str) -> str:
    """``text`` for a message: quoted, and cut when long."""
    if len(text) <= _SHOWN:
        return repr(text)
    return f"{text[:_SHOWN - 3]!r}... ({len(text)} characters)"


class _Checker:
    """Walks an :mod:`ast` tree and accepts only arithmetic over the allowed names.

    ``visit`` returns a bound on ``log10`` of the size of the node's value when
    it is a number (numerator and denominator together), ``None`` when it holds
    a symbol.  On the code SymPy generates (``generated``, where every number
    is spelled out as ``Integer (2 )`` or ``Rational ('1e-3')``) the bounds are
    enforced, so ``9**9**9**9`` or ``1e-99999999`` is refused before SymPy
    tries to compute it.
    """

    def __init__(self, *, names, functions, new_symbols, relational, max_depth, generated=False):
        self.names = names
        self.functions = functions
        self.new_symbols = new_symbols
        self.relational = relational
        self.max_depth = max_depth
        self.generated = generated
        self.symbols: set[str] = set()
        self.sorting_arguments = 0

    def visit(self, node, depth: int = 0):
        if depth > self.max_depth:
            raise Refused(f"nested more than {self.max_depth} levels deep")
        if isinstance(node, ast.Expression):
            return self.visit(node.body, depth)
        if isinstance(node, ast.Constant):
            value = node.value
            if type(value) not in (int, float):  # bool, None, str, bytes, complex, Ellipsis
                raise Refused(f"{value!r} is not a real number")
            if type(value) is float and not math.isfinite(value):  # 1e999; an int of any length is fine
                raise Refused("a number is out of range (beyond 1.8e308, the largest float)")
            assert isinstance(value, (int, float))          # for mypy: the type test above is exact
            return math.log10(abs(value)) if abs(value) > 1 else 0.0
        if isinstance(node, ast.Name):
            return self._name(node.id)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, _UNARYOPS):
            return self.visit(node.operand, depth + 1)
        if _is_chain(node):
            # a + b - c*d + ... is long, not deep: walk its left spine without recursion
            rights = []
            while _is_chain(node):
                rights.append(node.right)
                node = node.left
            size = self.visit(node, depth + 1)
            for right in reversed(rights):
                s = self.visit(right, depth + 1)
                size = None if size is None or s is None else size + s + _LOG2
            return size
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            return self._power(self.visit(node.left, depth + 1), self.visit(node.right, depth + 1))
        if isinstance(node, ast.Call):
            return self._call(node, depth)
        if isinstance(node, ast.Compare):
            return self._compare(node, depth)
        raise Refused(_describe(node))

    def _power(self, base, exponent):
        if exponent is None or not self.generated:
            return None if exponent is None or base is None else base * 10.0 ** min(exponent, 300.0)
        magnitude = 10.0 ** exponent if exponent < 300 else math.inf
        if magnitude > MAX_EXPONENT * (1 + 1e-9):
            raise Refused(f"a numeric exponent may be at most {MAX_EXPONENT} in magnitude")
        if base is None:
            return None
        digits = base * magnitude
        if digits > MAX_DIGITS * (1 + 1e-9):
            raise Refused(f"a number in it would have more than {MAX_DIGITS} digits")
        return digits

    def _name(self, name: str):
        if name.startswith("_"):
            raise Refused(f"name {name!r} is not allowed")
        if name in self.names:
            value = self.names[name]
            return None if not isinstance(value, sp.Basic) or value.free_symbols else 0.5
        if name in self.functions:
            raise Refused(f"function {name!r} must be called, as in {name}(x)")
        if name in _RESERVED:
            raise Refused(f"name {name!r} is not allowed")
        if not self.new_symbols:
            raise Refused(f"unknown symbol {name!r}")
        self.symbols.add(name)
        return None

    def _machinery(self, name: str, node: ast.Call):
        """auto_number's own wrapping of a number: ``Integer (2 )``, ``Rational ('0.1')``, ``Float ('1e-3')``."""
        if node.keywords or len(node.args) != 1 or not isinstance(node.args[0], ast.Constant):
            raise Refused(f"unexpected call of {name}")
        value = node.args[0].value
        if type(value) is int and name != "Symbol":
            return self.visit(node.args[0])
        if isinstance(value, str) and name == "Symbol":
            return self._name(value)
        match = _DECIMAL.fullmatch(value) if isinstance(value, str) and name != "Symbol" else None
        if match is None:
            raise Refused(f"unexpected call of {name}")
        digits = len(match["int"].replace("_", "").lstrip("0")) + len((match["frac"] or "").replace("_", ""))
        exponent = match["exp"].replace("_", "") if match["exp"] else "0"
        if len(exponent) > 6:
            raise Refused(f"the number {match.group()} is out of range")
        return digits + abs(int(exponent)) + 1.0

    def _call(self, node: ast.Call, depth: int):
        func = node.func
        if isinstance(func, ast.Constant):          # "8 (eight)", "2(x + 1)"
            raise Refused(f"a number followed by '(' is not a product here: write {func.value!r}*(...)")
        if not isinstance(func, ast.Name):
            raise Refused(_describe(func))
        name = func.id
        if name.startswith("_"):
            raise Refused(f"name {name!r} is not allowed")
        if self.generated and name in _MACHINERY:
            return self._machinery(name, node)
        if name not in self.functions:
            raise Refused(f"function {name!r} is not allowed")
        if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
            raise Refused(f"{name}() takes plain arguments only")
        if name in _SORTING:
            # SymPy compares the arguments of Min/Max pairwise: 300 symbols take minutes
            self.sorting_arguments += len(node.args)
            if self.sorting_arguments > MAX_SORTING_ARGUMENTS:
                raise Refused(f"Min and Max take at most {MAX_SORTING_ARGUMENTS} arguments in all")
        sizes = [self.visit(a, depth + 1) for a in node.args]
        if self.generated and any(s is not None and s > MAX_DIGITS for s in sizes):
            raise Refused(f"a number given to {name}() may have at most {MAX_DIGITS} digits")
        if any(s is None for s in sizes):
            return None
        return sum(sizes)

    def _compare(self, node: ast.Compare, depth: int):
        if not self.relational:
            raise Refused("a comparison is not allowed here")
        if len(node.ops) != 1:
            raise Refused("one comparison only (write 'a <= x' and 'x <= b' as two inequalities)")
        if type(node.ops[0]) not in _COMPARISONS:
            raise Refused("not an inequality (use <=, <, >= or >)")
        self.visit(node.left, depth + 1)
        self.visit(node.comparators[0], depth + 1)
        return None


def _is_chain(node) -> bool:
    return isinstance(node, ast.BinOp) and type(node.op) in _BINOPS and not isinstance(node.op, ast.Pow)


def _describe(node) -> str:
    """What a refused piece of syntax is, in words."""
    kinds = {
        ast.Attribute: "attribute access ('.')", ast.Subscript: "indexing ('[...]')", ast.Lambda: "lambda",
        ast.IfExp: "'if ... else'", ast.BoolOp: "'and' / 'or'", ast.List: "a list",
        ast.Tuple: "a comma outside a function's arguments (a decimal point is written '.')",
        ast.Dict: "a dict", ast.Set: "a set", ast.ListComp: "a comprehension", ast.SetComp: "a comprehension",
        ast.DictComp: "a comprehension", ast.GeneratorExp: "a generator", ast.JoinedStr: "an f-string",
        ast.Starred: "'*' unpacking", ast.NamedExpr: "':='", ast.Await: "'await'", ast.Yield: "'yield'",
        ast.Slice: "a slice",
    }
    if isinstance(node, ast.BinOp):
        return f"operator {type(node.op).__name__} is not allowed (use + - * / ** ^)"
    if isinstance(node, ast.UnaryOp):
        return f"operator {type(node.op).__name__} is not allowed"
    if isinstance(node, ast.Compare):
        return "a comparison is not allowed here"
    return f"{kinds.get(type(node), type(node).__name__)} is not allowed"


def _allowed(names, functions, new_symbols: bool, relational: bool) -> str:
    """The 'expected ...' half of a message."""
    parts = [n for n in names if not n.startswith("_")]
    if new_symbols:
        parts.append("symbol names")
    parts += list(functions)
    ops = "+ - * / ** ^" + (", one of < <= > >=" if relational else "")
    return f"allowed: numbers, {ops}, {', '.join(parts)}"


def parse_expr(value, parameter: str, *, names: Mapping | None = None, functions=None, new_symbols: bool = True,
               relational: bool = False, max_length: int = MAX_LENGTH, max_depth: int = MAX_DEPTH,
               transformations: tuple = ()) -> sp.Basic:
    """Read ``value`` (number, SymPy object or text) as an exact-where-possible expression.

    Numbers: integers and fractions stay exact, Python floats stay floats
    (``sp.Float`` of the exact binary value).  SymPy objects pass through.
    Text is untrusted and read by one rule:

    - it is at most ``max_length`` characters and parses as a Python
      expression (:func:`ast.parse`) made only of numbers, names, ``+ - * /
      **``, unary signs, parentheses and calls of the allowed ``functions``
      (default :data:`FUNCTIONS`: sqrt, sin, cos, tan, asin, acos, atan,
      atan2, exp, log, Abs, Min, Max) without keywords; with ``relational``
      also one comparison ``<``, ``<=``, ``>``, ``>=``.  Attributes,
      subscripts, strings, lambdas, comprehensions, ``if``/``else`` and
      names starting with ``_`` are refused, as is nesting deeper than
      ``max_depth`` and a numeric exponent above 1000 in magnitude;
    - ``^`` means power, as in textbooks: ``"(x - 5)^2"`` is ``(x - 5)**2``;
    - a decimal is the rational it spells: ``"0.1"`` is ``1/10``, ``"1e-3"``
      is ``1/1000`` (so results stay exact);
    - a plus-or-minus sign (``+-``, ``+ -``, ``+/-``, ``±``) is refused
      (:func:`refuse_plus_minus`): Python's grammar reads ``0.1 +- 0.01`` as
      ``0.1 + (-0.01)``;
    - names: those of ``names`` (a mapping ``name -> SymPy object``, e.g. the
      variables of a box), then ``pi`` and ``E``; any other identifier becomes
      a plain ``Symbol`` when ``new_symbols`` is true and is refused
      otherwise.  ``oo``, ``zoo``, ``nan``, ``I`` are never symbols.
      There is no implicit multiplication: ``2x`` is refused, write ``2*x``.

    ``transformations`` are extra :mod:`sympy.parsing.sympy_parser`
    transformations run after the built-in ones (the text must still pass the
    checks above, and so must the code they produce).  NaN and infinities are
    refused.

    Parameters
    ----------
    value : str, number or SymPy object
        What to read; ``bool`` and ``None`` are refused.
    parameter : str
        What the value is (``"joint 2 d"``), for the message.
    names : mapping of str to SymPy object, optional
        Names the text may use, and their values; they take precedence over ``pi`` and ``E``.
    functions : mapping or iterable of str, optional
        The functions the text may call: a mapping ``name -> SymPy function``, or names among
        :data:`FUNCTIONS`; None (the default) is all of :data:`FUNCTIONS`.
    new_symbols : bool
        Whether an unknown identifier becomes a new ``Symbol`` (default) or is refused.
    relational : bool
        Whether one comparison ``<``, ``<=``, ``>``, ``>=`` is allowed (default False).
    max_length : int
        Longest text read, in characters (default :data:`MAX_LENGTH`).
    max_depth : int
        Deepest nesting accepted (default :data:`MAX_DEPTH`).
    transformations : tuple
        Extra SymPy parser transformations (default none).

    Returns
    -------
    sympy.Basic
        A SymPy expression; with ``relational``, possibly an inequality, or ``true`` / ``false`` when the
        comparison is between numbers.

    Raises
    ------
    ExpressionError
        Naming ``parameter``, the text (cut when long) and what is allowed.
    TypeError
        When a key of ``names`` is not an identifier (a programming error, not bad input).

    Examples
    --------
    >>> parse_expr("pi/2", "alpha")
    pi/2
    >>> parse_expr(3, "d")
    3
    >>> parse_expr("0.1 + 1e-3", "a")
    101/1000
    >>> parse_expr("(x - 5)^2 + y^2 <= 144", "constraint", relational=True)
    y**2 + (x - 5)**2 <= 144
    >>> parse_expr("2*(", "a")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: a: cannot read '2*(' as an expression (invalid syntax)
    >>> parse_expr("__import__('os')", "joint 2 d", names={"q2": sp.Symbol("q2")}, new_symbols=False)
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: joint 2 d: cannot read "__import__('os')": name '__import__' is not \
allowed; allowed: numbers, + - * / ** ^, q2, pi, E, sqrt, sin, cos, ..., Abs, Min, Max
    """
    if isinstance(value, bool) or value is None:
        raise ExpressionError(f"{parameter}: expected a number or an expression, got {value!r}")
    if isinstance(value, str):
        expr = _read_text(value, parameter, names=names, functions=functions, new_symbols=new_symbols,
                          relational=relational, max_length=max_length, max_depth=max_depth,
                          transformations=transformations)
    elif isinstance(value, sp.Basic):
        expr = value
    elif isinstance(value, Number):
        if isinstance(value, float) and not math.isfinite(value):
            raise ExpressionError(f"{parameter}: expected a finite number, got {value!r}")
        expr = sp.sympify(value)  # a number, never text
    else:
        raise ExpressionError(f"{parameter}: expected a number or an expression, got {type(value).__name__} "
                              f"{quoted(repr(value))}")
    if isinstance(expr, sp.Expr):
        parts: tuple = (expr,)
    elif relational and isinstance(expr, sp.core.relational.Relational):
        parts = expr.args
    elif relational and isinstance(expr, sp.logic.boolalg.BooleanAtom):
        parts = ()
    else:
        raise ExpressionError(f"{parameter}: expected an expression, got {quoted(str(value))}")
    if any(p.has(sp.nan, sp.zoo, sp.oo, -sp.oo) for p in parts):
        raise ExpressionError(f"{parameter}: expected a finite value, got {quoted(str(value))}")
    return expr


def _read_text(text: str, parameter: str, *, names, functions, new_symbols, relational, max_length, max_depth,
               transformations):
    shown = quoted(text)
    if len(text) > max_length:
        raise ExpressionError(f"{parameter}: {shown} is too long; at most {max_length} characters are read")
    text = text.strip()
    if not text:
        raise ExpressionError(f"{parameter}: expected an expression, got an empty string")
    refuse_plus_minus(text, parameter)
    refuse_decimal_comma(text, parameter)
    names = {**(names or {}), **{k: v for k, v in CONSTANTS.items() if k not in (names or {})}}
    bad = [n for n in names if not (isinstance(n, str) and n.isidentifier())]
    if bad:
        raise TypeError(f"names must be identifiers; got {bad!r}")  # a programming error, not user input
    if functions is None:
        functions = FUNCTIONS
    elif not isinstance(functions, Mapping):
        functions = {f: FUNCTIONS[f] for f in functions}
    allowed = _allowed(names, functions, new_symbols, relational)
    if nesting_depth(text) > max_depth:
        raise ExpressionError(f"{parameter}: cannot read {shown}: nested more than {max_depth} levels deep; "
                              f"{allowed}")
    # '^' is power (textbook spelling).  A plain replace is exact: the grammar has no strings where '^' could hide.
    source = text.replace("^", "**")
    try:
        with warnings.catch_warnings():  # "invalid decimal literal" in '1if x' must not reach stderr
            warnings.simplefilter("ignore")
            tree = ast.parse(source, mode="eval")
    except (SyntaxError, ValueError, OverflowError):  # ValueError: null bytes
        raise ExpressionError(f"{parameter}: cannot read {shown} as an expression (invalid syntax)") from None
    except (RecursionError, MemoryError):  # Python's own parser on very deep or long input
        raise ExpressionError(f"{parameter}: cannot read {shown}: nested too deeply; {allowed}") from None
    checker = _Checker(names=names, functions=functions, new_symbols=new_symbols, relational=relational,
                       max_depth=max_depth)
    try:
        checker.visit(tree)
    except Refused as exc:
        raise ExpressionError(f"{parameter}: cannot read {shown}: {exc}; {allowed}") from None
    local_dict = {n: sp.Symbol(n) for n in checker.symbols}
    local_dict.update(names)
    global_dict = {"__builtins__": {}, **_MACHINERY, **functions}
    steps = (auto_number, rationalize) + tuple(transformations)
    try:
        # Check the code SymPy will evaluate as well: the built-in transformations only wrap numbers.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            code = stringify_expr(source, local_dict, global_dict, steps)
            generated = ast.parse(code, mode="eval")
            _Checker(names={**local_dict, **functions}, functions=functions, new_symbols=False,
                     relational=relational, max_depth=2 * max_depth + 2, generated=True).visit(generated)
            # sympy's parse_expr is stringify_expr + eval_expr; evaluating the checked code itself leaves no gap
            return eval_expr(code, local_dict, global_dict)
    except Refused as exc:
        raise ExpressionError(f"{parameter}: cannot read {shown}: {exc}; {allowed}") from None
    except Exception as exc:  # broad on purpose: SymPy's own errors on validated arithmetic, e.g. sin(1, 2)
        reason = " ".join(str(exc).split())[:120] or type(exc).__name__
        raise ExpressionError(f"{parameter}: cannot read {shown} as an expression ({reason})") from None


# Textbook spellings of operators, each one character for one (column numbers stay those of the student's text).
_UNICODE = {"\u00b7": "*", "\u22c5": "*", "\u00d7": "*", "\u2219": "*", "\u2212": "-", "\u2013": "-",
            "\u03c0": "pi", "\u00b2": "^2", "\u00b3": "^3"}
_MATH_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<number>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)
  | (?P<name>[^\W\d]\w*(?:\{[0-9, ]*\}\w*)*)
  | (?P<op>\*\*|[-+*/^,])
  | (?P<open>[(\[])
  | (?P<close>[)\]])
""", re.VERBOSE)
_SUBSCRIPT = re.compile(r"_\{([0-9, ]*)\}|_([0-9]+)")


def subscript_name(name: str) -> str:
    """``c_{23}`` and ``theta_1`` as the plain names ``c23`` and ``theta1`` (digit subscripts only).

    Parameters
    ----------
    name : str
        A name as written; commas and spaces inside braces are dropped (``c_{2, 3}`` is ``c23``).

    Returns
    -------
    str
        The name with its digit subscripts written plainly; other names unchanged.

    Examples
    --------
    >>> subscript_name("c_{234}"), subscript_name("theta_1"), subscript_name("joint_a")
    ('c234', 'theta1', 'joint_a')
    """
    return _SUBSCRIPT.sub(lambda m: (m[1] if m[1] is not None else m[2]).replace(",", "").replace(" ", ""), name)


def _math_error(parameter: str, text: str, column: int, reason: str) -> ExpressionError:
    return ExpressionError(f"{parameter}: cannot read {quoted(text)}: {reason} at column {column}",
                           parameter=parameter, position=column)


def _math_tokens(text: str, parameter: str, offset: int = 0):
    """``(kind, text, column)`` tokens of ``text``, with the textbook operators of :data:`_UNICODE` read."""
    tokens, pos = [], 0
    while pos < len(text):
        ch = text[pos]
        if ch in _UNICODE:
            spelled = _UNICODE[ch]
            if spelled == "pi":
                tokens.append(("name", "pi", offset + pos + 1))
            elif spelled.startswith("^"):
                tokens += [("op", "**", offset + pos + 1), ("number", spelled[1:], offset + pos + 1)]
            else:
                tokens.append(("op", spelled, offset + pos + 1))
            pos += 1
            continue
        match = _MATH_TOKEN.match(text, pos)
        if match is None:
            raise _math_error(parameter, text, offset + pos + 1, f"unexpected character {ch!r}")
        if match.lastgroup != "space":
            kind = match.lastgroup
            assert kind is not None                         # every alternative of _MATH_TOKEN is a named group
            word = match.group()
            if kind == "open":
                word = "("
            elif kind == "close":
                word = ")"
            elif kind == "op" and word == "^":
                word = "**"
            tokens.append((kind, word, offset + pos + 1))
        pos = match.end()
    return tokens


def parse_math(value, parameter: str, *, resolve, functions=None, max_length: int = MAX_LENGTH,  # noqa: C901
               offset: int = 0) -> sp.Expr:
    # (one reading loop over the tokens whose branches are the grammar's cases, in the order a reader meets them)
    """Read mathematics the way students and textbooks write it.

    On top of :func:`parse_expr`'s grammar (which checks the result again):

    - juxtaposition is multiplication: ``c1 (a1 + a2 c2)``, ``2 a2``,
      ``(a + b)(a - b)``; two numbers side by side are refused;
    - subscripts of digits are part of a name: ``c_{23}``, ``theta_1``, ``a_2``
      are looked up as ``c23``, ``theta1``, ``a2`` when the name as written is
      unknown;
    - a function may take one name or number without parentheses and carry a
      power: ``cos q1``, ``sin^2(theta1)`` (``= sin(theta1)^2``);
    - the middle dot and the multiplication sign are ``*``, the minus sign
      and the en dash ``-``, the letter pi is ``pi``, superscript two and three
      are ``^2`` and ``^3``; square brackets are parentheses.

    Every name goes through ``resolve(name)``, which returns its SymPy value
    (a symbol, or ``cos(theta2 + theta3)`` for the shorthand ``c23``), ``None``
    for an unknown name, or raises :class:`~workspace_sym.errors.ExpressionError`
    (an ambiguous name); ``pi`` and ``E`` are constants unless ``resolve``
    knows them.  Nothing of the text is evaluated as Python.

    ``offset`` is added to every column reported (the text is a piece of a
    longer answer, such as one entry of a matrix).

    Parameters
    ----------
    value : str
        The text; anything else is refused.
    parameter : str
        What the text is (``"answer"``), for the message.
    resolve : callable
        ``resolve(name)`` returns the SymPy value of a name, or None when the name is unknown.
    functions : mapping or iterable of str, optional
        The functions the text may call, as for :func:`parse_expr` (default :data:`FUNCTIONS`).
    max_length : int
        Longest text read, in characters (default :data:`MAX_LENGTH`).
    offset : int
        Added to every column reported (default 0).

    Returns
    -------
    sympy.Expr
        The expression, with each name replaced by the value ``resolve`` gave it.

    Raises
    ------
    ExpressionError
        Naming the text and, in ``position``, the column of the problem (no ``position`` when the text is not a
        string, is too long or empty, or when :func:`parse_expr` refuses the rewritten text).

    Examples
    --------
    >>> t1, a1, a2 = sp.symbols("theta1 a1 a2")
    >>> known = {"c1": sp.cos(t1), "a1": a1, "a2": a2, "theta1": t1}
    >>> parse_math("c_1 (a1 + a2 cos theta1)", "answer", resolve=known.get)
    (a1 + a2*cos(theta1))*cos(theta1)
    >>> parse_math("2 a2 sin^2(theta1)", "answer", resolve=known.get)
    2*a2*sin(theta1)**2
    >>> parse_math("c1 (a1 + x)", "answer", resolve=known.get)
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: answer: cannot read 'c1 (a1 + x)': unknown name 'x' at column 10
    """
    if not isinstance(value, str):
        raise ExpressionError(f"{parameter}: expected text, got {type(value).__name__}", parameter=parameter)
    text = value
    if len(text) > max_length:
        raise ExpressionError(f"{parameter}: {quoted(text)} is too long; at most {max_length} characters are read",
                              parameter=parameter)
    if not text.strip():
        raise ExpressionError(f"{parameter}: expected an expression, got an empty string", parameter=parameter)
    if functions is None:
        functions = FUNCTIONS
    refuse_plus_minus(text, parameter, offset=offset)
    refuse_decimal_comma(text, parameter)
    tokens = _math_tokens(text, parameter, offset)
    out: list[str] = []
    values: dict[str, sp.Basic] = {}
    known: dict[str, str] = {}
    opened: list[tuple[int, str | None]] = []     # column of each open parenthesis, power to append at its close
    previous = None                               # kind of the last token emitted: 'operand', 'op', 'open', 'func'
    i = 0

    def operand_name(word: str, column: int) -> str:
        for candidate in dict.fromkeys((word, subscript_name(word))):
            if candidate in known:
                return known[candidate]
            found = resolve(candidate)
            if found is not None:
                values[f"ans{len(values)}"] = found
                known[candidate] = f"ans{len(values) - 1}"
                return known[candidate]
        if word in CONSTANTS:
            return word
        raise _math_error(parameter, text, column, f"unknown name {word!r}")

    while i < len(tokens):
        kind, word, column = tokens[i]
        starts_operand = kind in ("number", "name", "open")
        if starts_operand and previous == "operand":
            if kind == "number" and out and tokens[i - 1][0] == "number":
                raise _math_error(parameter, text, column, "two numbers side by side (write * between them)")
            out.append("*")
        if kind == "name" and word in functions:
            power = None
            j = i + 1
            if j + 1 < len(tokens) and tokens[j][1] == "**" and tokens[j + 1][0] == "number":
                power, j = tokens[j + 1][1], j + 2
            nxt = tokens[j] if j < len(tokens) else None
            if nxt is not None and nxt[0] == "open":
                out += [word, "("]
                opened.append((nxt[2], power))
                previous, i = "open", j + 1
                continue
            if nxt is not None and (nxt[0] == "number" or (nxt[0] == "name" and nxt[1] not in functions)):
                arg = nxt[1] if nxt[0] == "number" else operand_name(nxt[1], nxt[2])
                out += [word, "(", arg, ")"] + (["**", power] if power else [])
                previous, i = "operand", j + 1
                continue
            raise _math_error(parameter, text, column, f"function {word!r} needs an argument, as in {word}(x)")
        if kind == "name":
            out.append(operand_name(word, column))
            previous = "operand"
        elif kind == "number":
            out.append(word)
            previous = "operand"
        elif kind == "open":
            out.append("(")
            opened.append((column, None))
            previous = "open"
        elif kind == "close":
            if not opened:
                raise _math_error(parameter, text, column, "unmatched ')'")
            if previous == "open" or previous == "op":
                raise _math_error(parameter, text, column, "nothing before ')'")
            _, power = opened.pop()
            out += [")"] + (["**", power] if power else [])
            previous = "operand"
        else:  # an operator
            unary = word in "+-"
            if previous in (None, "open", "op") and not unary:
                raise _math_error(parameter, text, column, f"operator {word!r} has nothing on its left")
            out.append(word)
            previous = "op"
        i += 1
    if previous == "op":
        raise _math_error(parameter, text, tokens[-1][2], f"operator {tokens[-1][1]!r} has nothing on its right")
    if opened:
        raise _math_error(parameter, text, opened[-1][0], "'(' is never closed")
    source = " ".join(out)
    try:
        return parse_expr(source, parameter, names=values, functions=functions, new_symbols=False,
                          max_length=max(4 * max_length, 200))
    except ExpressionError as exc:
        # say it about the student's text, not about the rewritten one
        reason = str(exc).split("; allowed:")[0].replace(quoted(source), quoted(text))
        for placeholder, obj in values.items():
            reason = reason.replace(f"'{placeholder}'", repr(sp.sstr(obj)))
        raise ExpressionError(reason, parameter=parameter) from None


def nesting_depth(text: str) -> int:
    """Deepest nesting of brackets ``([{`` in ``text`` (checked before any parser sees it)."""
    depth = deepest = 0
    for ch in text:
        if ch in "([{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in ")]}":
            depth -= 1
    return deepest


def parse_angle(value, parameter: str, *, degrees: bool) -> sp.Expr:
    """Read an angle; plain numbers are degrees when ``degrees`` is true.

    Rule for a degrees table:

    - a number (no symbol, no ``pi``) is degrees: ``90`` and ``"90"`` become
      ``pi/2``, integer degrees stay exact;
    - an expression containing ``pi`` is radians: ``"pi/2"``, ``"q1 + pi/2"``;
    - a symbol alone or times numbers (``"alpha1"``, ``"-q1"``) is radians;
    - a symbol plus a number without ``pi`` (``"q1 + 90"``) is refused: it
      used to mean 90 radians silently.  Give the offset alone as a number of
      degrees (``"theta": 90`` is added to the joint variable) or write it in
      radians (``"q1 + pi/2"``).

    With ``degrees`` false every value is radians.

    Parameters
    ----------
    value : str, number or SymPy object
        The angle, read by :func:`parse_expr`.
    parameter : str
        What the value is (``"joint 1 theta"``), for the message; its last word names the field in the hint.
    degrees : bool
        Whether the table is in degrees.

    Returns
    -------
    sympy.Expr
        The angle in radians.

    Raises
    ------
    ExpressionError
        When ``value`` cannot be read, or, in a degrees table, adds a number without ``pi`` to a symbol.

    Examples
    --------
    >>> parse_angle(90, "alpha", degrees=True)
    pi/2
    >>> parse_angle("pi/2", "alpha", degrees=True)
    pi/2
    >>> parse_angle("alpha1", "alpha", degrees=True)
    alpha1
    >>> parse_angle("q1 + 90", "joint 1 theta", degrees=True)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: joint 1 theta: 'q1 + 90' adds a number without pi to a symbol ... \
give the offset alone in degrees ("theta": 90) or write it in radians: "q1 + pi/2"
    """
    expr = parse_expr(value, parameter)
    if not degrees or expr.has(sp.pi):
        return expr
    if expr.is_number:
        return expr * sp.pi / 180
    constant, rest = expr.as_coeff_Add()
    if constant != 0:
        field = parameter.rsplit(" ", 1)[-1]
        hint = sp.sstr(rest + constant * sp.pi / 180)
        raise ExpressionError(
            f"{parameter}: {quoted(str(value))} adds a number without pi to a symbol in a degrees table, which is "
            f"ambiguous; give the offset alone in degrees (\"{field}\": {constant}) or write it in radians: "
            f"\"{hint}\"")
    return expr


def read_symbol(name, parameter: str) -> sp.Symbol:
    """A symbol named by user text: an identifier that text read by :func:`parse_expr` can refer to.

    Parameters
    ----------
    name : str
        The name.
    parameter : str
        What the name is (``"joint 1 variable"``), for the message.

    Returns
    -------
    sympy.Symbol
        The symbol of that name.

    Raises
    ------
    ExpressionError
        When ``name`` is not a string, not an identifier, a Python keyword, longer than 100 characters, starts
        with ``_``, or is a name the reader keeps for itself (a function, ``pi``, ``E``, ``oo``, ``zoo``,
        ``nan``, ``I``, ``Integer``, ``Float``, ``Rational``, ``Symbol``).

    Examples
    --------
    >>> read_symbol("q1", "joint 1 variable")
    q1
    >>> read_symbol("__class__", "joint 1 variable")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: joint 1 variable: expected a name such as q1, got '__class__'
    """
    if (not isinstance(name, str) or not name.isidentifier() or keyword.iskeyword(name) or name.startswith("_")
            or name in _RESERVED
            or name in FUNCTIONS or name in CONSTANTS or len(name) > 100):
        raise ExpressionError(f"{parameter}: expected a name such as q1, got {quoted(str(name))}")
    return sp.Symbol(name)


def as_sympy(value, parameter: str = "expression"):
    """A SymPy object for an internal value; text goes through :func:`parse_expr`, never :func:`sympy.sympify`.

    SymPy objects and matrices pass through, numbers are converted; any other
    object (a list or dict could hold strings that ``sympify`` would evaluate)
    is refused.

    Parameters
    ----------
    value : str, number, SymPy object or SymPy matrix
        The value.
    parameter : str
        What the value is, for the message (default ``"expression"``).

    Returns
    -------
    sympy.Basic
        The SymPy object: a matrix comes back immutable.

    Raises
    ------
    ExpressionError
        When ``value`` is text that :func:`parse_expr` refuses, or of another type.

    Examples
    --------
    >>> as_sympy(sp.Symbol("x") + 1)
    x + 1
    >>> as_sympy("x^2")
    x**2
    >>> as_sympy(["x"])
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: expression: expected a SymPy expression or a number, got list
    """
    if isinstance(value, str):
        return parse_expr(value, parameter)
    if isinstance(value, (sp.Basic, sp.MatrixBase, Number)):
        return sp.sympify(value)  # not text: no parsing happens
    raise ExpressionError(f"{parameter}: expected a SymPy expression or a number, got {type(value).__name__}")


def check_joint_limits(joint, lower, upper, *, shown=None, unit: str = "") -> None:
    """Raise :class:`JointLimitError` unless ``lower < upper``, both finite real numbers.

    ``shown`` are the limits as the user wrote them (for the message),
    ``unit`` follows them ("deg").  The one check behind every joint table.

    Parameters
    ----------
    joint : int or str
        The joint, as the message names it (``joint 3``).
    lower, upper : number, SymPy number or str
        The limits (text is read by :func:`parse_expr`).
    shown : pair, optional
        The limits as the user wrote them; None (the default) shows ``lower`` and ``upper``.
    unit : str
        The unit written after each limit in the message (default none).

    Raises
    ------
    JointLimitError
        When a limit is not a finite real number or ``lower >= upper``.
    ExpressionError
        When a limit is text that cannot be read, or of another type.

    Examples
    --------
    >>> check_joint_limits(3, sp.Integer(25), sp.Integer(-10), unit="deg")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.JointLimitError: upper limit of joint 3 (-10 deg) must exceed its lower limit (25 deg)
    """
    shown_lo, shown_hi = shown if shown is not None else (lower, upper)
    suffix = f" {unit}" if unit else ""
    values = []
    for name, value, text in (("lower", lower, shown_lo), ("upper", upper, shown_hi)):
        value = as_sympy(value, f"{name} limit of joint {joint}")
        if not value.is_number or not is_finite_value(value):
            raise JointLimitError(f"{name} limit of joint {joint} must be a finite number; got {text}")
        values.append(value)
    if not bool(values[0] < values[1]):
        raise JointLimitError(f"upper limit of joint {joint} ({shown_hi}{suffix}) must exceed its lower limit "
                              f"({shown_lo}{suffix})")


def is_finite_value(expr: sp.Expr) -> bool:
    """False when ``expr`` is a number that does not evaluate to a finite real (infinite, NaN, complex).

    Parameters
    ----------
    expr : sympy.Expr
        The expression.

    Returns
    -------
    bool
        False for a number whose value is infinite, NaN or not real; True for a finite real number, and for any
        expression that is not a number (one with free symbols).
    """
    if not expr.is_number:
        return True
    value = complex(expr.evalf())
    return math.isfinite(value.real) and value.imag == 0


def as_matrix(value, parameter: str = "matrix") -> sp.MatrixBase:
    """A SymPy matrix for an internal value: a matrix passes through; a list of rows, a flat list (a column) or
    one value is read entry by entry with :func:`as_sympy` (text through :func:`parse_expr`, never
    :func:`sympy.sympify`, which ``sympy.Matrix`` would call on text).

    Parameters
    ----------
    value : SymPy matrix, sequence of sequences, sequence, or one value
        The matrix, its rows, a column, or a 1 x 1 matrix's entry.
    parameter : str
        What the value is, for the message (default ``"matrix"``).

    Returns
    -------
    sympy.MatrixBase
        The matrix.

    Raises
    ------
    ExpressionError
        An entry that :func:`as_sympy` refuses.

    Examples
    --------
    >>> as_matrix([["x", 1], [0, "y^2"]])
    Matrix([
    [x,    1],
    [0, y**2]])
    >>> as_matrix(["__import__('os')"])
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: matrix: ...
    """
    if isinstance(value, sp.MatrixBase):
        return value
    if isinstance(value, (list, tuple)):
        if value and all(isinstance(row, (list, tuple)) for row in value):
            return sp.Matrix([[as_sympy(v, parameter) for v in row] for row in value])
        return sp.Matrix([as_sympy(v, parameter) for v in value])
    return sp.Matrix([as_sympy(value, parameter)])
