"""Students' answers as they write them: textbook shorthand, juxtaposition, LaTeX, matrices.

A student answering "x of the glass-handling arm" writes ``c1 (a1 + a2 c2 + a3
c23 + d5 s234)``, ``C1*(...)``, ``cos(q1)*(...)`` or
``\\cos\\theta_1 \\left(a_1 + a_2 \\cos\\theta_2 + \\dots\\right)``.  A
:class:`Notation` knows what the names of a robot mean (``c23`` is
``cos(theta2 + theta3)``, ``q1`` and ``t1`` are ``theta1``) and
:func:`read_answer` turns the text into SymPy:

- plain text goes through :func:`~workspace_sym.expressions.parse_math`, the
  project's allowlist reader with juxtaposition;
- LaTeX (any backslash) is tokenised here against a small vocabulary (Greek
  letters, ``\\sin \\cos \\tan \\sqrt \\frac \\cdot \\times \\left \\right``,
  ``pmatrix`` / ``bmatrix``), rewritten with explicit products and
  parentheses, and parsed by SymPy's LaTeX parser (Lark backend); its result
  is vetted (only the allowed functions and the robot's names, bounded size)
  before it is used;
- a matrix is ``[e1, e2, e3]`` (a column), ``[[a, b], [c, d]]`` (rows) or a
  LaTeX ``pmatrix``.

Nothing of the text is evaluated as Python.  Unreadable text raises
:class:`~workspace_sym.errors.ExpressionError` with ``position`` (1-based
column) when the reader knows where the problem is.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from string import ascii_lowercase

import sympy as sp

from ..errors import ExpressionError, check_choice
from ..expressions import (
    CONSTANTS,
    FUNCTIONS,
    MAX_DEPTH,
    MAX_LENGTH,
    PLUS_MINUS,
    nesting_depth,
    parse_math,
    quoted,
    refuse_plus_minus,
    subscript_name,
)

__all__ = ["Notation", "read_answer", "read_latex", "split_top_level", "expansion_size", "ANGLE_UNITS",
           "MAX_EXPANSION", "Unit", "read_unit", "split_unit", "split_uncertainty", "read_count", "read_yes_no",
           "plain_sentence", "MAX_ENTRIES", "MAX_OPERATIONS"]

#: How numbers inside sin, cos and tan are read.
ANGLE_UNITS = ("radians", "degrees")
#: Most entries of a matrix answer.
MAX_ENTRIES = 64
#: Most operations of one read answer (after parsing).
MAX_OPERATIONS = 4000

_JOINT_ALIAS = re.compile(r"(theta|θ|th|q|t)([0-9]+)")
_SHORTHAND = re.compile(r"([cCsS])([0-9]+)")


@dataclass(frozen=True)
class Notation:
    """The names a student may use for one robot.

    ``joints`` maps a joint number (1-based) to ``(variable, kind)`` with kind
    ``"R"`` or ``"P"``; ``constants`` are the other symbols (lengths).  A name
    means, in this order of lookup, all of:

    - a symbol of the robot spelled exactly (``a2``, ``theta1``, ``d3``);
    - ``theta<k>``, ``θ<k>``, ``th<k>``, ``q<k>``, ``t<k>``: the variable of
      joint ``k`` (``q<k>`` only for a prismatic joint);
    - ``c<ij..>``, ``s<ij..>``, ``C<ij..>``, ``S<ij..>``: cosine or sine of the
      sum of the revolute joint variables ``i, j, ...`` (one digit each).

    When these meanings differ (a robot with a length called ``t1``, or ``c1``
    as a parameter) the name is ambiguous and refused with both meanings.

    Parameters
    ----------
    joints : dict, optional
        ``{k: (variable, kind)}``, as above; empty by default.
    constants : frozenset, optional
        The other symbols of the robot; empty by default.

    Raises
    ------
    ExpressionError
        From :meth:`resolve` (the constructor checks nothing): a name that is ambiguous, or that asks for the
        angle of a prismatic joint.

    Examples
    --------
    >>> from workspace_sym import robots
    >>> names = Notation.from_robot(robots.build("glass-handling"))
    >>> names.resolve("s234"), names.resolve("q1"), names.resolve("a2"), names.resolve("x")
    (sin(theta2 + theta3 + theta4), theta1, a2, None)
    """

    joints: dict = field(default_factory=dict)
    constants: frozenset = frozenset()

    @classmethod
    def from_robot(cls, robot) -> Notation:
        """The notation of a :class:`~workspace_sym.kinematics.DHRobot`.

        Parameters
        ----------
        robot : DHRobot
            The robot: its joint variables and kinds, and its other symbols as constants.

        Returns
        -------
        Notation
            The robot's names.
        """
        joints = {k: (j.variable, j.kind) for k, j in enumerate(robot.joints, start=1)}
        return cls(joints, frozenset(robot.symbols))

    @classmethod
    def from_symbols(cls, symbols) -> Notation:
        """Guess the joints from symbol names ``theta<k>``, ``q<k>``, ``t<k>`` (revolute); the rest are constants.

        Parameters
        ----------
        symbols : iterable of sympy.Symbol
            The symbols; the first of them (by name) to name joint ``k`` is its variable.

        Returns
        -------
        Notation
            The guessed names.
        """
        joints, constants = {}, set()
        for s in sorted(symbols, key=str):
            m = _JOINT_ALIAS.fullmatch(str(s))
            k = int(m[2]) if m else 0
            if k and k not in joints:
                joints[k] = (s, "R")
            else:
                constants.add(s)
        return cls(joints, frozenset(constants))

    def _own(self) -> dict:
        own = {str(s): s for s in self.constants}
        own.update({str(v): v for v, _ in self.joints.values()})
        return own

    def resolve(self, name: str):
        """SymPy value of ``name``, ``None`` when unknown; :class:`ExpressionError` when ambiguous.

        Parameters
        ----------
        name : str
            A name as the student wrote it (``"s234"``, ``"q1"``, ``"a2"``).

        Returns
        -------
        sympy.Expr or None
            The symbol, the joint variable, or the sine or cosine of a sum of joint variables; None when the
            name means nothing for this robot.

        Raises
        ------
        ExpressionError
            When the name has two meanings, or names the angle of a prismatic joint (``theta2``, ``t2`` or
            ``c2`` when joint 2 is prismatic and no symbol is spelled so).
        """
        meanings = []
        own = self._own().get(name)
        if own is not None:
            meanings.append(own)
        m = _JOINT_ALIAS.fullmatch(name)
        if m and int(m[2]) in self.joints:
            k = int(m[2])
            variable, kind = self.joints[k]
            if kind == "P" and m[1] != "q" and own is None:
                raise ExpressionError(f"{name!r} names joint {k}, which is prismatic: its variable is {variable}")
            if kind == "R" or m[1] == "q":
                meanings.append(variable)
        m = _SHORTHAND.fullmatch(name)
        if m and len(self.joints) <= 9:
            digits = [int(c) for c in m[2]]
            if len(set(digits)) == len(digits) and all(d in self.joints for d in digits):
                prismatic = [d for d in digits if self.joints[d][1] == "P"]
                if prismatic and own is None:
                    raise ExpressionError(f"{name!r}: joint {prismatic[0]} is prismatic, it has no angle")
                if not prismatic:
                    angle = sp.Add(*(self.joints[d][0] for d in digits))
                    meanings.append((sp.cos if m[1] in "cC" else sp.sin)(angle))
        distinct = list(dict.fromkeys(meanings))
        if len(distinct) > 1:
            raise ExpressionError(f"{name!r} is ambiguous for this robot: it could be {distinct[0]} or "
                                  f"{distinct[1]}; write the other one in full")
        return distinct[0] if distinct else None

    def resolver(self, parameter: str):
        """``resolve`` with ``parameter`` prefixed to its ambiguity errors.

        Parameters
        ----------
        parameter : str
            The name of the answer, put before the message and set as the error's ``parameter``.

        Returns
        -------
        callable
            ``resolve(name)``, as :meth:`resolve`.

        Raises
        ------
        ExpressionError
            From the returned function, where :meth:`resolve` raises it, with ``parameter`` named (this method
            itself raises nothing).
        """
        def resolve(name):
            try:
                return self.resolve(name)
            except ExpressionError as exc:
                raise ExpressionError(f"{parameter}: {exc}", parameter=parameter) from None
        return resolve


# ------------------------------------------------------------------------------ plain text and matrices
def split_top_level(text: str, offset: int = 0) -> list[tuple[str, int]]:
    """Pieces of ``text`` between commas outside brackets, each with its column offset.

    Parameters
    ----------
    text : str
        The text.
    offset : int, default 0
        Added to every column (the place of ``text`` in a longer text).

    Returns
    -------
    list of tuple
        ``(piece, column)`` pairs, pieces unstripped; one piece when there is no comma at depth 0.

    Examples
    --------
    >>> split_top_level("s3, atan2(y, x), [a, b]")
    [('s3', 0), (' atan2(y, x)', 3), (' [a, b]', 16)]
    """
    pieces, depth, start = [], 0, 0
    for k, ch in enumerate(text):
        depth += ch in "([{"
        depth -= ch in ")]}"
        if ch == "," and depth == 0:
            pieces.append((text[start:k], offset + start))
            start = k + 1
    pieces.append((text[start:], offset + start))
    return pieces


def _plain_matrix(text: str, parameter: str, read) -> sp.Matrix:
    """``[e1, e2]`` as a column, ``[[a, b], [c, d]]`` as rows; ``read(piece, column)`` reads one entry."""
    stripped = text.strip()
    lead = text.index("[")
    inner = stripped[1:-1]
    pieces = split_top_level(inner, lead + 1)
    nested = [p.strip().startswith("[") and p.strip().endswith("]") for p, _ in pieces]
    if all(nested):
        rows = []
        for piece, column in pieces:
            start = column + piece.index("[") + 1
            rows.append([read(p, c) for p, c in split_top_level(piece.strip()[1:-1], start)])
        if len({len(r) for r in rows}) != 1:
            raise ExpressionError(f"{parameter}: cannot read {quoted(text)}: rows of different lengths",
                                  parameter=parameter)
        return sp.Matrix(rows)
    if any(nested):
        raise ExpressionError(f"{parameter}: cannot read {quoted(text)}: mix of rows and entries",
                              parameter=parameter)
    return sp.Matrix([read(p, c) for p, c in pieces])


def _is_bracketed(text: str) -> bool:
    """True when the whole text is one ``[...]`` (a matrix, not ``[a + b] c``)."""
    text = text.strip()
    if not (text.startswith("[") and text.endswith("]")):
        return False
    depth = 0
    for k, ch in enumerate(text):
        depth += ch in "(["
        depth -= ch in ")]"
        if depth == 0 and k < len(text) - 1:
            return False
    return True


# ------------------------------------------------------------------------------ LaTeX
_GREEK = {"alpha", "beta", "gamma", "delta", "epsilon", "varepsilon", "zeta", "eta", "theta", "vartheta", "iota",
          "kappa", "lambda", "mu", "nu", "xi", "rho", "sigma", "tau", "upsilon", "phi", "varphi", "chi", "psi",
          "omega"}
_LATEX_TOKEN = re.compile(r"""
    (?P<space>\s+|\\[,;:!\ ]|\\quad(?![A-Za-z])|\\qquad(?![A-Za-z])|~|\\left(?![A-Za-z])|\\right(?![A-Za-z])
              |\\displaystyle(?![A-Za-z]))
  | (?P<begin>\\begin\{[pbv]?matrix\})
  | (?P<end>\\end\{[pbv]?matrix\})
  | (?P<rowsep>\\\\)
  | (?P<colsep>&)
  | (?P<func>\\(?:sin|cos|tan)(?![A-Za-z]))
  | (?P<frac>\\[dt]?frac(?![A-Za-z]))
  | (?P<sqrt>\\sqrt(?![A-Za-z]))
  | (?P<mul>\\cdot(?![A-Za-z])|\\times(?![A-Za-z])|\*)
  | (?P<name>(?:\\[A-Za-z]+|[A-Za-z]+)(?:_(?:\{[^{}]*\}|[0-9A-Za-z])|[0-9]+)?)
  | (?P<number>[0-9]+(?:\.[0-9]+)?|\.[0-9]+)
  | (?P<power>\^)
  | (?P<op>[-+/])
  | (?P<open>[(\[])
  | (?P<close>[)\]])
  | (?P<lbrace>\{)
  | (?P<rbrace>\})
""", re.VERBOSE)
_WRAPPED_MATRIX = re.compile(r"^(\s*(?:\\left)?\s*[\[(]\s*)(\\begin\{([pbv]?)matrix\}.*\\end\{\3matrix\})"
                             r"(\s*(?:\\right)?\s*[\])]\s*)$", re.DOTALL)
_MAX_DIGITS = 30
_MAX_POWER_PRODUCT = 1000


def _placeholder(k: int) -> str:
    """``Z_{aaa}``, ``Z_{aab}``, ...: names the Lark grammar reads as one symbol (subscripts of letters)."""
    letters = "".join(ascii_lowercase[k // 26**e % 26] for e in (2, 1, 0))
    return "Z_{" + letters + "}"


class _LatexRewriter:
    """LaTeX tokens to an unambiguous LaTeX string: names as placeholders, products and function calls explicit.

    SymPy's Lark grammar reads ``\\cos\\theta_1 (a_1 + a_2)`` four ways and
    has no ``c_{23}`` or ``\\pi``; written as ``(\\cos(Z_{aaa})) \\cdot (Z_{aab} +
    Z_{aac})`` it has one reading.
    """

    def __init__(self, text: str, parameter: str, resolve):
        self.text, self.parameter, self.resolve = text, parameter, resolve
        self.tokens = []
        self.values: dict[sp.Symbol, sp.Basic] = {}
        self._known: dict[str, str] = {}
        self.power_product = 1
        pos = 0
        while pos < len(text):
            match = _LATEX_TOKEN.match(text, pos)
            if match is None:
                raise self.error(pos + 1, f"unexpected character {text[pos]!r}")
            if match.lastgroup != "space":
                self.tokens.append((match.lastgroup, match.group(), pos + 1))
            pos = match.end()
        self.i = 0

    def error(self, column, reason) -> ExpressionError:
        where = f" at column {column}" if column else ""
        return ExpressionError(f"{self.parameter}: cannot read {quoted(self.text)}: {reason}{where}",
                               parameter=self.parameter, position=column)

    def peek(self):
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def take(self):
        tok = self.peek()
        self.i += 1
        return tok

    def column_at_end(self) -> int:
        return len(self.text)

    # names and numbers -------------------------------------------------------
    def name(self, word: str, column: int) -> str:
        m = re.fullmatch(r"(\\?)([A-Za-z]+)(?:_(?:\{([^{}]*)\}|([0-9A-Za-z]))|([0-9]+))?", word)
        assert m is not None                    # the tokenizer made ``word`` a name of this form
        backslash, base, braced, single, digits = m.groups()
        sub = braced if braced is not None else single if single is not None else digits or ""
        if backslash and base not in _GREEK and base != "pi":
            raise self.error(column, f"command '\\{base}' is not allowed (allowed: Greek letters, \\pi, \\sin, "
                                     f"\\cos, \\tan, \\sqrt, \\frac, \\cdot, \\times, \\left, \\right, pmatrix)")
        if base == "pi" and backslash and not sub:
            return self.name_constant("pi")   # the Lark grammar has no \pi
        plain = subscript_name(f"{base}_{{{sub}}}") if sub else base
        candidates = [plain] if not sub else [plain, f"{base}_{sub}"]
        for candidate in candidates:
            if candidate in self._known:
                return self._known[candidate]
            found = self.resolve(candidate)
            if found is not None:
                holder = _placeholder(len(self.values))
                self.values[sp.Symbol(holder)] = found
                self._known[candidate] = holder
                return holder
        if not sub and plain in CONSTANTS:
            return self.name_constant(plain)
        raise self.error(column, f"unknown name {word!r}")

    def name_constant(self, plain: str) -> str:
        holder = _placeholder(len(self.values))
        self.values[sp.Symbol(holder)] = CONSTANTS[plain]
        return holder

    def number(self, word: str, column: int) -> str:
        digits = word.replace(".", "")
        if len(digits) > _MAX_DIGITS:
            raise self.error(column, f"a number may have at most {_MAX_DIGITS} digits")
        if "." in word:
            whole, frac = word.split(".")
            return r"\frac{" + (whole + frac).lstrip("0").rjust(1, "0") + "}{1" + "0" * len(frac) + "}"
        return word

    def exponent(self) -> str:
        """After '^': a small integer, bare (``^2``) or braced (``^{-1}``)."""
        tok = self.take()
        if tok is None:
            raise self.error(self.column_at_end(), "'^' needs an exponent")
        kind, word, column = tok
        if kind == "number" and "." not in word:
            value = word[0]               # TeX reads one digit: x^23 is x^2 times 3
            if len(word) > 1:
                self.tokens.insert(self.i, ("number", word[1:], column + 1))
        elif kind == "lbrace":
            parts = []
            while (tok := self.take()) is not None and tok[0] != "rbrace":
                parts.append(tok[1])
            value = "".join(parts)
            if tok is None or not re.fullmatch(r"-?[0-9]{1,3}", value):
                raise self.error(column, "an exponent must be a small integer such as ^2 or ^{-1}")
        else:
            raise self.error(column, "an exponent must be a small integer such as ^2 or ^{-1}")
        self.power_product *= max(1, abs(int(value)))
        if self.power_product > _MAX_POWER_PRODUCT:
            raise self.error(column, "exponents too large")
        return "^{" + value + "}"

    # expressions -------------------------------------------------------------
    def group(self, closing: str, column: int) -> str:
        """Tokens up to the matching ``closing`` kind, rewritten."""
        inner = self.sequence(stop=closing)
        tok = self.take()
        if tok is None or tok[0] != closing:
            raise self.error(column, "this bracket is never closed")
        return inner

    def argument(self, column: int) -> str:
        """One argument of \\frac, \\sqrt or a function: a braced or parenthesised group, or one atom."""
        tok = self.take()
        if tok is None:
            raise self.error(column, "missing argument")
        kind, word, col = tok
        if kind == "lbrace":
            return "(" + self.group("rbrace", col) + ")"
        if kind == "open":
            return "(" + self.group("close", col) + ")"
        if kind == "name":
            return self.name(word, col)
        if kind == "number":
            if len(word) > 1 and "." not in word:     # \frac12: TeX takes one digit per argument
                self.tokens.insert(self.i, ("number", word[1:], col + 1))
                word = word[0]
            return self.number(word, col)
        raise self.error(col, f"{word!r} cannot be an argument")

    def operand(self, tok) -> str:
        kind, word, column = tok
        if kind == "name":
            return self.name(word, column)
        if kind == "number":
            return self.number(word, column)
        if kind == "open":
            return "(" + self.group("close", column) + ")"
        if kind == "lbrace":
            return "(" + self.group("rbrace", column) + ")"
        if kind == "frac":
            num = self.argument(column)
            den = self.argument(column)
            return r"(\frac{" + num + "}{" + den + "})"
        if kind == "sqrt":
            nxt = self.peek()
            if nxt is not None and nxt[1] == "[":
                raise self.error(nxt[2], "only square roots are allowed")
            return r"(\sqrt{" + self.argument(column) + "})"
        if kind == "func":
            power = ""
            nxt = self.peek()
            if nxt is not None and nxt[0] == "power":
                self.take()
                power = self.exponent()
            return "((" + word + "(" + self.argument(column) + "))" + power + ")"
        raise self.error(column, f"{word!r} cannot start a term")

    def sequence(self, stop: str | None = None) -> str:
        out, previous = [], None
        while (tok := self.peek()) is not None and tok[0] != stop:
            kind, word, column = tok
            if kind in ("close", "rbrace", "begin", "end", "rowsep", "colsep"):
                raise self.error(column, f"unexpected {word!r}")
            self.take()
            if kind == "power":
                if previous != "operand":
                    raise self.error(column, "'^' has nothing on its left")
                out.append(self.exponent())
                continue
            if kind in ("op", "mul"):
                if kind == "mul" or word == "/":
                    if previous != "operand":
                        raise self.error(column, f"{word!r} has nothing on its left")
                    out.append(r" \cdot " if kind == "mul" else " / ")
                else:
                    out.append(f" {word} ")
                previous = "op"
                continue
            if previous == "operand":
                out.append(r" \cdot ")
            out.append(self.operand(tok))
            previous = "operand"
        if previous == "op":
            raise self.error(self.tokens[self.i - 1][2], "an operator has nothing on its right")
        if previous is None:
            tok = self.peek()
            raise self.error(tok[2] if tok else self.column_at_end(), "empty expression")
        return "".join(out)

    def cells(self) -> list[list[str]] | str:
        """The rewritten text, or the rewritten cells of a matrix environment."""
        first = self.peek()
        if first is None:
            raise self.error(1, "empty expression")
        if first[0] != "begin":
            text = self.sequence()
            if self.peek() is not None:
                raise self.error(self.peek()[2], f"unexpected {self.peek()[1]!r}")
            return text
        self.take()
        rows: list[list] = []
        row: list = []
        while True:
            tok = self.peek()
            if tok is None:
                raise self.error(first[2], "matrix environment is never closed")
            if tok[0] == "end":
                self.take()
                if row or not rows:
                    rows.append(row)
                break
            row.append(self._cell())
            tok = self.take()
            if tok is None:
                raise self.error(first[2], "matrix environment is never closed")
            if tok[0] == "rowsep":
                rows.append(row)
                row = []
            elif tok[0] == "end":
                rows.append(row)
                break
        if self.peek() is not None:
            raise self.error(self.peek()[2], "text after the matrix")
        rows = [r for r in rows if r]
        if len({len(r) for r in rows}) != 1:
            raise self.error(first[2], "rows of different lengths")
        return rows

    def _cell(self) -> str:
        """One cell of a matrix: the tokens up to the next top-level ``&``, ``\\\\`` or ``\\end``, rewritten."""
        start, depth = self.i, 0
        while (tok := self.peek()) is not None and not (depth == 0 and tok[0] in ("colsep", "rowsep", "end")):
            depth += tok[0] in ("open", "lbrace")
            depth -= tok[0] in ("close", "rbrace")
            self.i += 1
        tokens, end = self.tokens, self.i
        self.tokens, self.i = tokens[start:end], 0       # sequence() reads to the end of its tokens
        try:
            return self.sequence()
        finally:
            self.tokens, self.i = tokens, end


_ALLOWED_FUNCTIONS = (sp.sin, sp.cos, sp.tan)


def _vet(expr, allowed_symbols: set) -> bool:
    """True when ``expr`` is arithmetic over ``allowed_symbols`` with sin, cos, tan and square roots only."""
    if not isinstance(expr, sp.Expr) or expr.has(sp.zoo, sp.nan, sp.oo, -sp.oo, sp.I):
        return False
    if sp.count_ops(expr) > MAX_OPERATIONS:
        return False
    for node in sp.preorder_traversal(expr):
        if isinstance(node, sp.Symbol):
            if node not in allowed_symbols:
                return False
        elif isinstance(node, sp.Pow):
            if not node.exp.is_Rational or abs(node.exp) > _MAX_POWER_PRODUCT:
                return False
        elif not isinstance(node, (sp.Add, sp.Mul, sp.Number, sp.NumberSymbol, *_ALLOWED_FUNCTIONS)):
            return False
    return True


def _alternatives(tree) -> list:
    """Every reading in a result of the Lark parser (a SymPy object, or a ``Tree('_ambig', ...)``)."""
    children = getattr(tree, "children", None)
    if children is None or getattr(tree, "data", None) != "_ambig":
        return [tree]
    return [alt for child in children for alt in _alternatives(child)]


def _parse_latex_cell(rewritten: str, rewriter: _LatexRewriter):
    from sympy.parsing.latex import parse_latex

    try:
        result = parse_latex(rewritten, backend="lark")
    except Exception as exc:  # broad on purpose: the parser's own errors on text already checked
        reason = " ".join(str(exc).split())[:80] or type(exc).__name__
        raise rewriter.error(None, f"the LaTeX parser refused it ({reason})") from None
    allowed = set(rewriter.values)
    readings = list(dict.fromkeys(r for r in _alternatives(result) if _vet(r, allowed)))
    if not readings:
        raise rewriter.error(None, "it uses something other than arithmetic, \\sin, \\cos, \\tan and \\sqrt "
                                   "of the robot's names")
    if len(readings) > 1 and any(sp.expand(r - readings[0]) != 0 for r in readings[1:]):
        raise rewriter.error(None, f"it can be read as {readings[0]} or as {readings[1]}; add \\cdot or "
                                   "parentheses")
    return readings[0].xreplace(rewriter.values)


def read_latex(text: str, notation: Notation, *, parameter: str = "answer", max_length: int = 1000):
    """A LaTeX answer as SymPy (a matrix for ``pmatrix`` / ``bmatrix``), read with the names of ``notation``.

    Parameters
    ----------
    text : str
        The LaTeX.
    notation : Notation
        The names the answer may use.
    parameter : str, default "answer"
        The answer's name in messages.
    max_length : int, default 1000
        The most characters read.

    Returns
    -------
    sympy.Expr or sympy.Matrix
        The expression, or the matrix of a matrix environment.

    Raises
    ------
    ExpressionError
        When the text is too long, nested too deep, holds a plus-or-minus sign, or cannot be read (an unknown
        command or name, a syntax error, two readings that differ, too many matrix entries); ``position`` is
        the column of the problem when known.

    Examples
    --------
    >>> t1, t2, a1, a2 = sp.symbols("theta1 theta2 a1 a2")
    >>> read_latex(r"\\cos\\theta_1 \\left(a_1 + a_2 \\cos\\theta_2\\right)", Notation.from_symbols([t1, t2, a1, a2]))
    (a1 + a2*cos(theta2))*cos(theta1)
    >>> read_latex(r"c_{12} + \\frac{1}{2}", Notation.from_symbols([t1, t2]))
    cos(theta1 + theta2) + 1/2
    """
    if len(text) > max_length:
        raise ExpressionError(f"{parameter}: {quoted(text)} is too long; at most {max_length} characters are read",
                              parameter=parameter)
    if nesting_depth(text) > MAX_DEPTH:
        raise ExpressionError(f"{parameter}: cannot read {quoted(text)}: nested more than {MAX_DEPTH} levels deep",
                              parameter=parameter)
    refuse_plus_minus(text, parameter)
    # SymPy's own printer wraps a matrix environment in \left[ ... \right]: blank them (columns stay)
    text = _WRAPPED_MATRIX.sub(lambda m: " " * len(m[1]) + m[2] + " " * len(m[4]), text)
    rewriter = _LatexRewriter(text, parameter, notation.resolver(parameter))
    cells = rewriter.cells()
    if isinstance(cells, str):
        return _parse_latex_cell(cells, rewriter)
    if sum(len(r) for r in cells) > MAX_ENTRIES:
        raise rewriter.error(None, f"a matrix may have at most {MAX_ENTRIES} entries")
    return sp.Matrix([[_parse_latex_cell(c, rewriter) for c in row] for row in cells])


# ------------------------------------------------------------------------------ the entry point
def expansion_size(expr, cap: int = 10**9) -> int:
    """An upper estimate of the number of terms of ``expr`` once sines and cosines of sums and products are
    expanded (what checking an answer does), stopped at ``cap``.

    ``(c1 + s1 + c2 + s2)^1000`` is a short text whose expansion would not finish: its estimate is the cap.

    Parameters
    ----------
    expr : sympy.Expr
        The expression.
    cap : int, default 10**9
        The largest value returned.

    Returns
    -------
    int
        The estimate, between 1 and ``cap``.

    Examples
    --------
    >>> t1, t2, a = sp.symbols("theta1 theta2 a")
    >>> expansion_size(a * sp.cos(t1 + t2) + 1), expansion_size((sp.cos(t1) + sp.sin(t1) + a) ** 100, cap=10**6)
    (3, 1000000)
    """
    def size(e) -> int:
        if isinstance(e, sp.Add):
            return min(cap, sum(size(a) for a in e.args))
        if isinstance(e, sp.Mul):
            out = 1
            for a in e.args:
                out = min(cap, out * size(a))
            return out
        if isinstance(e, sp.Pow) and e.exp.is_Integer and e.exp > 1 and e.base.free_symbols:
            base = size(e.base)
            return cap if base > 1 and int(e.exp) * math.log(base) > math.log(cap) else min(cap, base ** int(e.exp))
        if isinstance(e, (*_ALLOWED_FUNCTIONS,)) and isinstance(e.args[0], sp.Add):
            return min(cap, 2 ** min(60, len(e.args[0].args) - 1))
        return 1
    return size(expr)


#: Largest :func:`expansion_size` of an answer that is checked (bigger ones are refused as too large).
MAX_EXPANSION = 20_000



def _degrees(expr):
    """Numbers added to an angle inside sin, cos, tan are degrees: ``cos(theta1 + 90)`` is ``cos(theta1 + pi/2)``."""
    def convert(f):
        constant, rest = f.args[0].as_coeff_Add()
        if constant == 0 or f.args[0].has(sp.pi):
            return f
        return f.func(rest + constant * sp.pi / 180)
    return expr.replace(lambda e: isinstance(e, _ALLOWED_FUNCTIONS), convert)


def read_answer(text, notation: Notation, *, angles: str = "radians", parameter: str = "answer"):
    """A student's answer as SymPy, read with the names of ``notation``.

    ``text`` is plain text (``c1 (a1 + a2 c2)``, ``cos(q1)*a1``), LaTeX (it
    holds a backslash) or a matrix (``[e1, e2, e3]``, ``[[...], [...]]``,
    ``\\begin{pmatrix} ... \\end{pmatrix}``).  With ``angles="degrees"``
    numbers added to angles inside sin, cos and tan are degrees.

    Parameters
    ----------
    text : str
        The answer.
    notation : Notation
        The names the answer may use.
    angles : {"radians", "degrees"}, default "radians"
        How numbers inside sin, cos and tan are read.
    parameter : str, default "answer"
        The answer's name in messages.

    Returns
    -------
    sympy.Expr or sympy.Matrix
        The answer; a matrix for a matrix answer.

    Raises
    ------
    ExpressionError
        The text cannot be read (or is not text, is longer than
        :data:`~workspace_sym.expressions.MAX_LENGTH`, has more than
        :data:`MAX_ENTRIES` entries or would expand past
        :data:`MAX_EXPANSION` terms); ``position`` is the column of the
        problem when known.
    UnknownNameError
        When ``angles`` is neither ``"radians"`` nor ``"degrees"``.

    Examples
    --------
    >>> t = sp.symbols("theta1:4")
    >>> names = Notation.from_symbols(t)
    >>> read_answer("[c1 c2, s1 c2, s2]", names)
    Matrix([
    [cos(theta1)*cos(theta2)],
    [sin(theta1)*cos(theta2)],
    [            sin(theta2)]])
    >>> read_answer("cos(q1 + 90)", names, angles="degrees")
    -sin(theta1)
    """
    check_choice("angles", angles, ANGLE_UNITS)
    if not isinstance(text, str):
        raise ExpressionError(f"{parameter}: expected text, got {type(text).__name__}", parameter=parameter)
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"{parameter}: {quoted(text)} is too long; at most {MAX_LENGTH} characters are read",
                              parameter=parameter)
    if "\\" in text:
        result = read_latex(text, notation, parameter=parameter)
    else:
        resolve = notation.resolver(parameter)

        def read(piece, column=0):
            return parse_math(piece, parameter, resolve=resolve, offset=column)

        result = _plain_matrix(text, parameter, read) if _is_bracketed(text) else read(text)
        if isinstance(result, sp.MatrixBase) and len(result) > MAX_ENTRIES:
            raise ExpressionError(f"{parameter}: a matrix may have at most {MAX_ENTRIES} entries",
                                  parameter=parameter)
    if angles == "degrees":
        result = result.applyfunc(_degrees) if isinstance(result, sp.MatrixBase) else _degrees(result)
    entries = list(result) if isinstance(result, sp.MatrixBase) else [result]
    if any(expansion_size(e, MAX_EXPANSION + 1) > MAX_EXPANSION for e in entries):
        raise ExpressionError(f"{parameter}: cannot check {quoted(text)}: expanded it would have more than "
                              f"{MAX_EXPANSION} terms", parameter=parameter)
    return result


# ------------------------------------------------------------------------------ yes/no, counts, quantities
_FORMULA_WORDS = {w.lower() for w in (*CONSTANTS, *FUNCTIONS)}
_ONES = {w: k for k, w in enumerate("zero one two three four five six seven eight nine ten eleven twelve thirteen "
                                    "fourteen fifteen sixteen seventeen eighteen nineteen".split())}
_TENS = {w: 10 * k for k, w in enumerate("twenty thirty forty fifty sixty seventy eighty ninety".split(), start=2)}
#: Length units (metres per unit) and angle units (radians per unit) an answer may carry.
_LENGTH_UNITS = {"m": 1.0, "metre": 1.0, "metres": 1.0, "meter": 1.0, "meters": 1.0, "dm": 0.1, "cm": 0.01,
                 "mm": 0.001, "km": 1000.0}
_ANGLE_UNITS = {"rad": 1.0, "radian": 1.0, "radians": 1.0, "deg": math.pi / 180, "degree": math.pi / 180,
                "degrees": math.pi / 180, "°": math.pi / 180}
_UNIT = (r"(?<![A-Za-z_])(?P<base>metres?|meters?|radians?|degrees?|rad|deg|km|dm|cm|mm|m|°)"
         r"(?:\s*(?:\^|\*\*)\s*(?P<power>[123])|(?P<digit>[123])|(?P<sup>[²³]))?")
_QUANTITY = re.compile(r"(?P<number>.*?)\s*" + _UNIT + r"\s*", re.DOTALL)
_DIMENSIONS = {("length", 1): "a length", ("length", 2): "an area", ("length", 3): "a volume",
               ("angle", 1): "an angle"}


def plain_sentence(text: str) -> str:
    """``text`` without surrounding blanks and the full stop or exclamation marks ending a sentence (``"No."``,
    ``"4 arcs."``): nothing a formula ends with.

    Parameters
    ----------
    text : str
        The answer.

    Returns
    -------
    str
        The text stripped of blanks and of final ``.`` and ``!``; the stripped text when nothing else is left.
    """
    stripped = text.strip()
    return stripped.rstrip(".!").rstrip() or stripped


# A yes/no answer is a verdict word (or a sentence that says reachable / not reachable) and, after it, a reason.
# Words that may lead a sentence with only a blank after them ("no it is too far"); the single letters and digits
# need a punctuation mark or the end ("y = 0.5 ..." is not a yes).
_YES_WORDS = {"yes", "yep", "yeah", "true", "oui"}
_NO_WORDS = {"no", "nope", "false", "non"}
_YES_SIGNS = {"y", "1"}
_NO_SIGNS = {"n", "0"}
_LEAD = re.compile(r"\s*(?P<word>[^\W_]+)(?P<sep>\s*[,;:!\u2013\u2014]|\s*-(?![0-9])|\.(?=\s|$)|\s+|$)")
# A bare verdict word making a clause of the reason: "no, yes", "yes and no", "no; no".
_BARE = re.compile(r"(?:^|[,;:.!\u2013\u2014]|\s-|\b(?:and|or|but|then|so)\b)\s*(?P<word>yes|no|y|n|true|false|oui|non)"
                   r"\s*(?=$|[,;:.!\u2013\u2014]|\s-|\s(?:and|or|but)\b)", re.IGNORECASE)
_APOSTROPHE = "['\u2019]"
_NOT = rf"(?:not|never|no\s+longer|(?:is|are)n{_APOSTROPHE}?t)"
# Statements about the point: "it is not reachable", "out of reach", "it can be reached", "inside the workspace".
_NO_PHRASE = re.compile(
    rf"\bunreachable\b|\b{_NOT}\s+(?:\w+\s+)?(?:reachable|within\s+(?:the\s+|its\s+)?reach|in\s+reach|(?:inside|in|"
    rf"within)\s+the\s+workspace)\b|\b(?:cannot|can{_APOSTROPHE}?t|can\s+not|could\s*not|couldn{_APOSTROPHE}?t)\s+"
    rf"(?:be\s+)?reach(?:ed)?\b|\b(?:out\s+of|beyond)\s+(?:the\s+|its\s+)?reach\b|\boutside\s+(?:of\s+)?the\s+"
    rf"workspace\b", re.IGNORECASE)
_YES_PHRASE = re.compile(r"\breachable\b|\b(?:can|could)\s+(?:be\s+)?reach(?:ed)?\b|\b(?:within|in)\s+"
                         r"(?:the\s+|its\s+)?reach\b|\b(?:inside|in|within)\s+the\s+workspace\b", re.IGNORECASE)
# Words that leave the answer open: a careful teacher reads "No, not sure" as no answer, not as a no.
_HEDGE = re.compile(
    rf"\?|\b(?:not\s+(?:sure|certain)|unsure|uncertain|no\s+(?:idea|clue)|dunno|idk|maybe|perhaps|probably|"
    rf"possibly|might|i\s+(?:think|guess|believe|suppose|assume)|(?:do|does|did|could|can|have|has|had|am|was|were)"
    rf"(?:n{_APOSTROPHE}?t|\s*not)\s+(?:\w+\s+)?(?:know|solve[ds]?|finish(?:ed)?|tell|say|decide[ds]?|answer(?:ed)?|"
    rf"check(?:ed)?|compute[ds]?|do\s+it|manage[ds]?|get\s+it|work\s+it\s+out))\b", re.IGNORECASE)
_ASK = "answer yes (reachable) or no (unreachable), a reason may follow"


def _said(claims: list[tuple[bool, str]]) -> str:
    """``'no' and yes ('it is reachable')``: each claim once, its words when they are not the verdict itself."""
    words = _YES_WORDS | _NO_WORDS | _YES_SIGNS | _NO_SIGNS
    return " and ".join(dict.fromkeys(repr(w) if w.lower() in words else f"{'yes' if c else 'no'} ({w!r})"
                                      for c, w in claims))


def read_yes_no(text: str, *, parameter: str = "answer") -> bool:
    """``True`` for yes, ``False`` for no: a verdict with its reason, as a student writes it.

    The verdict is a leading word (``yes``, ``no``, ``true``, ``false``, ``oui``, ``non``; ``y``, ``n``, ``1``,
    ``0`` only before a punctuation mark or alone) or a statement about the point (``reachable``, ``It is not
    reachable``, ``out of reach``, ``it cannot be reached``, ``outside the workspace``).  A reason may follow, after
    a comma, colon, semicolon, dash, full stop or just a blank (``"No because it is too far"``); it is not graded,
    but what it says is read.  Case and a final full stop do not matter.

    Parameters
    ----------
    text : str
        The answer.
    parameter : str, default "answer"
        The answer's name in messages.

    Returns
    -------
    bool
        True for yes (reachable), False for no.

    Raises
    ------
    ExpressionError
        Neither yes nor no; a hedge (``not sure``, ``don't know``, ``didn't solve``, ``maybe``, ``I think``, a
        question mark), which leaves the answer open; or a contradiction (``"no, yes"``, ``"Yes, it is
        unreachable"``).  The message names the words; ``position`` is their column.

    Examples
    --------
    >>> read_yes_no("No."), read_yes_no("yes: theta = 0"), read_yes_no("no it is beyond the reach")
    (False, True, False)
    >>> read_yes_no("It is not reachable"), read_yes_no("Reachable, with theta1 = 0")
    (False, True)
    >>> read_yes_no("No, not sure")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.ExpressionError: answer: cannot read 'No, not sure': 'not sure' leaves the answer open; \
answer yes (reachable) or no (unreachable), a reason may follow
    """
    said = plain_sentence(text)
    shift = len(text) - len(text.lstrip())

    def refuse(reason: str, column: int | None = None) -> ExpressionError:
        return ExpressionError(f"{parameter}: cannot read {quoted(text)}: {reason}", parameter=parameter,
                               position=None if column is None else column + shift + 1)

    claims: list[tuple[int, bool, str]] = []          # (column, yes, the words), each claim the answer makes
    rest, start = said, 0
    lead = _LEAD.match(said)
    if lead:
        word = lead["word"].lower()
        if word in _YES_WORDS | _NO_WORDS or (word in _YES_SIGNS | _NO_SIGNS and not lead["sep"].isspace()):
            claims.append((lead.start("word"), word in _YES_WORDS | _YES_SIGNS, lead["word"]))
            rest, start = said[lead.end():], lead.end()
    hedge = _HEDGE.search(said)
    if hedge:
        raise refuse(f"{hedge.group()!r} leaves the answer open; {_ASK}", hedge.start())
    for m in _BARE.finditer(rest):
        claims.append((start + m.start("word"), m["word"].lower() in _YES_WORDS | _YES_SIGNS, m["word"]))
    blanked = _NO_PHRASE.sub(lambda m: " " * len(m.group()), said)
    for phrase, yes in ((_NO_PHRASE, False), (_YES_PHRASE, True)):
        for m in phrase.finditer(said if phrase is _NO_PHRASE else blanked):
            claims.append((m.start(), yes, " ".join(m.group().split())))
    claims.sort()
    verdicts = {yes for _, yes, _ in claims}
    if len(verdicts) > 1:                 # the column of the first claim that contradicts the one before it
        column = next(c for c, yes, _ in claims if yes != claims[0][1])
        raise refuse(f"it says both {_said([(yes, w) for _, yes, w in claims])}; {_ASK}", column)
    if not verdicts:
        raise refuse(_ASK)
    return verdicts.pop()


def read_count(text: str) -> tuple[int, str] | None:
    """A whole number written in digits or in words (``4``, ``four``, ``twenty-one``) with the words that follow it
    (``"4 circular arcs"`` is ``(4, "circular arcs")``); ``None`` when ``text`` is not of that form, or when a
    word after the number means something in a formula (``"2 pi"``, ``"3 sqrt"``).

    Parameters
    ----------
    text : str
        The answer.

    Returns
    -------
    tuple or None
        ``(number, words)``: the words after the number joined by single blanks (lower-cased when the number
        is in words); or None.

    Examples
    --------
    >>> read_count("Four arcs"), read_count("twenty-one"), read_count("4 <b>")
    ((4, 'arcs'), (21, ''), None)

    The number may be said twice, in digits and in words between parentheses, when both agree:

    >>> read_count("8 (eight) arcs"), read_count("8 (seven)")
    ((8, 'arcs'), None)
    """
    twice = re.fullmatch(r"\s*([0-9]{1,9})\s*\(([A-Za-z\s-]{1,40})\)(.*)", text, re.DOTALL)
    if twice:
        said = read_count(twice[2])
        return read_count(f"{twice[1]} {twice[3]}") if said == (int(twice[1]), "") else None
    m = re.fullmatch(r"\s*([0-9]{1,9})\s*([A-Za-z][A-Za-z\s-]*)?", text)
    if m:
        rest = (m[2] or "").split()
        return None if _FORMULA_WORDS & {w.lower() for w in rest} else (int(m[1]), " ".join(rest))
    words = [w for w in re.split(r"[\s-]+", text.strip().lower()) if w]
    if not words:
        return None
    value, used = _TENS.get(words[0]), 1
    if value is not None and len(words) > 1 and 0 < _ONES.get(words[1], 0) < 10:
        value, used = value + _ONES[words[1]], 2
    elif value is None:
        value = _ONES.get(words[0])
    rest = words[used:]
    if value is None or not all(w.isalpha() and w.isascii() for w in rest) or _FORMULA_WORDS & set(rest):
        return None
    return value, " ".join(rest)


@dataclass(frozen=True)
class Unit:
    """A unit of length, area, volume or angle as written (``"cm^2"``, ``"m²"``, ``"°"``): its dimension
    (``"length"`` with ``power`` 1 to 3, or ``"angle"``) and ``scale``, the value of one unit in metres to the
    power, or in radians.

    Parameters
    ----------
    text : str
        The unit as written.
    dimension : str
        ``"length"`` or ``"angle"``.
    power : int
        1, 2 or 3 for a length (1 for an angle).
    scale : float
        One unit in metres to ``power``, or in radians.
    """

    text: str
    dimension: str
    power: int
    scale: float

    @property
    def kind(self) -> str:
        """``"a length"``, ``"an area"``, ``"a volume"`` or ``"an angle"``.

        Returns
        -------
        str
            The quantity the unit measures, with its article.
        """
        return _DIMENSIONS[self.dimension, self.power]


def _unit(m) -> Unit | None:
    power = int(m["power"] or m["digit"] or {"²": 2, "³": 3}.get(m["sup"] or "", 1))
    written = m.string[m.start("base"):m.end()].strip()
    if m["base"] in _ANGLE_UNITS:
        return Unit(written, "angle", 1, _ANGLE_UNITS[m["base"]]) if power == 1 else None
    return Unit(written, "length", power, _LENGTH_UNITS[m["base"]] ** power)


def read_unit(text: str) -> Unit | None:
    """The unit ``text`` spells (``"m^2"``, ``"cm²"``, ``"rad"``, ``"degrees"``), ``None`` when it is none of them.

    Parameters
    ----------
    text : str
        The unit, blanks around it allowed; anything that is not a string gives None.

    Returns
    -------
    Unit or None
        The unit; None also for a power of an angle unit.

    Examples
    --------
    >>> read_unit("cm^2").scale, read_unit("m³").kind, read_unit("ft")
    (0.0001, 'a volume', None)
    """
    m = re.fullmatch(r"\s*" + _UNIT + r"\s*", text) if isinstance(text, str) else None
    return _unit(m) if m else None


def split_unit(text: str) -> tuple[str, Unit | None]:
    """``text`` as the number it starts with and the unit it ends with (``"0.327 m^2"``, ``"45°"``), or as it is
    with ``None`` when it ends with no unit.

    Parameters
    ----------
    text : str
        The answer.

    Returns
    -------
    tuple
        ``(number, unit)``: the text before the unit, stripped, and the :class:`Unit`; or ``(text, None)``.

    Examples
    --------
    >>> split_unit("3270 cm²")[0], split_unit("pi/4 rad")[1].scale, split_unit("2*pi")
    ('3270', 1.0, ('2*pi', None))
    """
    m = _QUANTITY.fullmatch(text)
    unit = _unit(m) if m and m["number"].strip() else None
    return (m["number"].strip(), unit) if m and unit else (text, None)


def split_uncertainty(text: str) -> tuple[str, str | None]:
    """``text`` as a value and the uncertainty after its plus-or-minus sign (``+-``, ``+/-``, ``±``), each with
    the unit written for both, or as it is with ``None`` when it has no such sign (or more than one).

    A unit after the uncertainty, or after the parentheses around both, is the unit of both; a unit after the
    value alone is the uncertainty's too.

    Parameters
    ----------
    text : str
        The answer.

    Returns
    -------
    tuple
        ``(value, uncertainty)`` as text, or ``(text, None)``.

    Examples
    --------
    >>> split_uncertainty("1.40474 +- 0.01"), split_uncertainty("(0.327 ± 0.002) m^2")
    (('1.40474', '0.01'), ('0.327 m^2', '0.002 m^2'))
    >>> split_uncertainty("45 deg +/- 1"), split_uncertainty("0.3")
    (('45 deg', '1 deg'), ('0.3', None))
    """
    signs = list(PLUS_MINUS.finditer(text))
    if len(signs) != 1:
        return text, None
    value, spread = text[:signs[0].start()].strip(), text[signs[0].end():].strip()
    after = ""
    if value.startswith("(") and ")" in spread:
        spread, after = spread.rsplit(")", 1)
        value, spread, after = value[1:].strip(), spread.strip(), after.strip()
    if not after:
        value_unit, spread_unit = split_unit(value)[1], split_unit(spread)[1]
        if value_unit is not None and spread_unit is None:
            spread = f"{spread} {value_unit.text}"
        elif spread_unit is not None and value_unit is None:
            value = f"{value} {spread_unit.text}"
    return (f"{value} {after}".strip(), f"{spread} {after}".strip())
