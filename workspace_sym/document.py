"""Documents as blocks, rendered to Markdown, HTML and LaTeX: the one writer of formatted text.

A :class:`Document` is built once as a list of blocks (headings, paragraphs with inline mathematics, displayed
equations, tables, figures, key/value lists) and rendered to the three formats, so that they always say the same
thing.  Exact expressions are LaTeX in Markdown and LaTeX, and MathML in HTML (read by every current browser without a
network connection); every text is escaped for the format it goes into
(:func:`~workspace_sym.numbers.md_escape`, :func:`tex_escape`).
:class:`Equations` shows equations in a notebook the same way.

It imports nothing of the package but :mod:`workspace_sym.numbers` (``md_escape``): the reports
(:mod:`workspace_sym.report`), the exercise sheets and the grading report (:mod:`workspace_sym.teaching`) all build
their documents here.
"""

from __future__ import annotations

import base64
import html
import re
from pathlib import Path

import sympy as sp
from sympy.printing.latex import LatexPrinter
from sympy.printing.mathml import MathMLPresentationPrinter

from .numbers import md_escape

__all__ = ["Document", "Equations", "tex_escape", "latex_markup", "mathml_markup", "MINUS"]


# ------------------------------------------------------------------ the package's printers of SymPy objects
MINUS = "\u2212"     # the minus sign of typeset mathematics; a hyphen-minus "-" renders as a hyphen in MathML


class _LatexPrinter(LatexPrinter):
    """SymPy's LaTeX printer with ``atan2`` as the operator name, not ``\\operatorname{atan}_{2}``."""

    def _print_atan2(self, expr, exp=None):
        name = r"\operatorname{atan2}" + ("" if exp is None else f"^{{{exp}}}")
        return name + r"{\left(" + ", ".join(self._print(a) for a in expr.args) + r" \right)}"


class _MathMLPrinter(MathMLPresentationPrinter):
    """SymPy's presentation MathML with ``atan2`` named as such (SymPy writes ``arctan(y, x)``) and a true minus
    sign (U+2212) in every ``<mo>`` and before every negative ``<mn>``."""

    def mathml_tag(self, e):
        return "atan2" if isinstance(e, sp.atan2) else super().mathml_tag(e)

    def doprint(self, expr):
        text = super().doprint(expr)
        text = text.replace("<mo>-</mo>", f"<mo>{MINUS}</mo>")
        return re.sub(r"<mn>-([^<]*)</mn>", rf"<mrow><mo>{MINUS}</mo><mn>\1</mn></mrow>", text)


def latex_markup(x, **settings) -> str:
    r"""LaTeX of a SymPy object as the package prints it: :func:`sympy.latex` with ``atan2`` written
    ``\operatorname{atan2}``.

    Parameters
    ----------
    x : sympy.Basic or sympy.MatrixBase
        What to print.
    **settings
        Settings of SymPy's LaTeX printer (``mat_str``, ``mat_delim``, ...).

    Returns
    -------
    str
        The LaTeX, without math delimiters.

    Raises
    ------
    TypeError
        For a setting SymPy's printer does not know.

    Examples
    --------
    >>> latex_markup(sp.atan2(sp.Symbol("y"), 1))
    '\\operatorname{atan2}{\\left(y, 1 \\right)}'
    """
    return _LatexPrinter(settings).doprint(x)


def mathml_markup(x) -> str:
    """Presentation MathML of a SymPy object as the package prints it: :func:`sympy.mathml` with ``atan2`` named
    ``atan2`` and minus signs as U+2212 (MINUS SIGN), which a browser renders as a minus, not as a hyphen.

    Parameters
    ----------
    x : sympy.Basic or sympy.MatrixBase
        What to print.

    Returns
    -------
    str
        The MathML, without the enclosing ``<math>`` element.

    Raises
    ------
    TypeError
        When SymPy's MathML printer cannot print ``x``.

    Examples
    --------
    >>> mathml_markup(-sp.Symbol("x"))
    '<mrow><mo>\u2212</mo><mi>x</mi></mrow>'
    """
    return _MathMLPrinter().doprint(x)


def tex_escape(text: str, *, math: bool = True) -> str:
    r"""Escape LaTeX specials in text, leaving ``$...$`` math segments alone (``math=False``: escape ``$`` too,
    for text that came from a user or the command line).

    Parameters
    ----------
    text : str
        The text.
    math : bool
        True (the default): the text may hold ``$...$`` mathematics, which is left as it is.  False: all of it is
        text, put on one line (runs of whitespace become one space), with ``$``, ``|``, ``<`` and ``>`` escaped
        too.

    Returns
    -------
    str
        The escaped text.

    Examples
    --------
    >>> print(tex_escape(r"a_b 50% $x_1$ {c} \ d"))
    a\_b 50\% $x_1$ \{c\} \textbackslash{} d
    >>> print(tex_escape("cost $5 ~ 90°", math=False))
    cost \$5 \textasciitilde{} 90\ensuremath{^\circ}
    >>> tex_escape("")
    ''
    """
    parts = text.split("$") if math else [" ".join(text.split())]      # user text: one line (a table cell)
    for k in range(0, len(parts), 2):
        part = parts[k].replace("\\", "\0")
        for ch in "_%&#{}" + ("" if math else "$"):
            part = part.replace(ch, "\\" + ch)
        part = part.replace("^", "\\textasciicircum{}").replace("~", "\\textasciitilde{}")
        if not math:        # the OT1 font prints these three as other glyphs
            part = part.replace("|", "\\textbar{}").replace("<", "\\textless{}").replace(">", "\\textgreater{}")
        parts[k] = part.replace("\0", "\\textbackslash{}").replace("°", "\\ensuremath{^\\circ}")
    return "$".join(parts)


_WIDTH = 78          # characters of SymPy str that fit one line of the LaTeX page (a4, 2 cm margins, 10 pt)


def _breakable(tex: str) -> str:
    """Escaped text that LaTeX may break after ``/``, ``_``, ``=`` and ``,`` (paths, command lines)."""
    return re.sub(r"(/|\\_|=|,)", r"\1\\allowbreak{}", tex)


def _tex(x) -> str:
    if isinstance(x, sp.MatrixBase):
        return latex_markup(x, mat_str="pmatrix", mat_delim="").replace("°", "^{\\circ}")
    return latex_markup(x).replace("°", "^{\\circ}")


def _mathml(x) -> str:
    return mathml_markup(x)


class _Word(sp.Symbol):
    """A word naming a left-hand side (``answer``, ``edge``), set upright as text: ``\\text{answer}`` in LaTeX,
    ``<mtext>`` in MathML (a Symbol's name would be printed as it is written); ``answer_2`` has a subscript."""

    def _parts(self):
        word, _, sub = self.name.partition("_")
        return word, sub

    def _latex(self, printer):
        word, sub = self._parts()
        return f"\\text{{{word}}}" + (f"_{{{sub}}}" if sub else "")

    def _mathml_presentation(self, printer):
        word, sub = self._parts()
        text = printer.dom.createElement("mtext")
        text.appendChild(printer.dom.createTextNode(word))
        if not sub:
            return text
        node = printer.dom.createElement("msub")
        index = printer.dom.createElement("mn")
        index.appendChild(printer.dom.createTextNode(sub))
        node.appendChild(text)
        node.appendChild(index)
        return node


_WORD = re.compile(r"\\text\{([A-Za-z][A-Za-z ]*)\}|([A-Za-z]{2,})")


def _label(name):
    """A left-hand side: SymPy object; a word (``"answer"``, ``"\\text{answer}"``: upright text), or a name such
    as ``"c_1"``, ``"T^0_6"`` or ``"theta"`` made a Symbol."""
    if not isinstance(name, str):
        return name
    word = _WORD.fullmatch(name)
    if word and (word[1] or sp.latex(sp.Symbol(word[2])) == word[2]):      # not a Greek letter such as theta
        return _Word(word[1] or word[2])
    return sp.Symbol(name)


def _subscripted(label, index: str):
    """``label`` with the subscript ``index`` (``J`` -> ``J_{1,2}``; a word stays a word)."""
    return (_Word if isinstance(label, _Word) else sp.Symbol)(f"{label}_{index}")


def _lines(expr, width: int = _WIDTH) -> list:
    """``expr`` cut into sums of consecutive terms, each at most ``width`` characters of SymPy str."""
    if not isinstance(expr, sp.Add) or len(str(expr)) <= width:
        return [expr]
    lines: list = []
    chunk: list = []
    for term in expr.as_ordered_terms():
        if chunk and len(str(sp.Add(*chunk, term, evaluate=False))) > width:
            lines.append(sp.Add(*chunk, evaluate=False))
            chunk = []
        chunk.append(term)
    return lines + [sp.Add(*chunk, evaluate=False)]


def _tex_pieces(expr, width: int = _WIDTH) -> list[str]:
    """The TeX of ``expr`` in lines of at most ``width`` characters of SymPy str: a sum cut between its terms
    (:func:`_lines`), and a term still too wide cut inside its widest factor in parentheses, each line's
    parentheses balanced with ``\\right.`` / ``\\left.``.  Lines after the first start with their sign."""
    if len(str(expr)) <= width:
        return [_tex(expr)]
    if isinstance(expr, sp.Add):
        pieces: list[str] = []
        for part in _lines(expr, width):
            terms = part.args if isinstance(part, sp.Add) else (part,)
            if len(terms) > 1 or len(str(part)) <= width:
                tex = _tex(part)
                pieces.append(tex if not pieces or tex.startswith("-") else "+ " + tex)
                continue
            negative = part.could_extract_minus_sign()
            inner = _tex_pieces(-part if negative else part, width)
            pieces += ["- " * negative + ("+ " if pieces and not negative else "") + inner[0], *inner[1:]]
        return pieces
    if isinstance(expr, sp.Mul):
        factors = list(expr.as_ordered_factors())
        wide = max(factors, key=lambda f: len(str(f)))
        inner = _tex_pieces(wide, width - 4) if isinstance(wide, sp.Add) else []
        if len(inner) > 1:
            factors.remove(wide)
            rest = sp.Mul(*factors)
            head = "" if rest == 1 else "-" if rest == -1 else _tex(rest) + " "
            # continued lines indented one more step per level; '{}' keeps a leading sign binary (spaced)
            cont = ["\\quad \\left. " + "{}" * (p[:1] in "+-") + p for p in inner[1:]]
            return ([head + "\\left(" + inner[0] + " \\right."] + [c + " \\right." for c in cont[:-1]]
                    + [cont[-1] + " \\right)"])
    return [_tex(expr)]


def _column_width(M, j: int) -> int:
    """Characters of SymPy str of column ``j``'s widest entry, plus its label and the space between."""
    return max(len(str(M[i, j])) for i in range(M.rows)) + 12


def _column_groups(M, width: int = _WIDTH) -> list:
    """Column indices of ``M`` in consecutive groups whose widest entries fit ``width`` together."""
    groups: list[list[int]] = []
    current: list[int] = []
    used = 0
    for j in range(M.cols):
        w = _column_width(M, j)
        if current and used + w > width:
            groups.append(current)
            current, used = [], 0
        current.append(j)
        used += w
    return groups + [current]


def _inline(parts, text, maths) -> str:
    """A paragraph of text and inline mathematics: each text run through ``text`` on one line (a blank at its ends
    is kept), each SymPy object through ``maths``."""
    if isinstance(parts, str):
        return text(parts)
    out = []
    for p in parts:
        if not isinstance(p, str):
            out.append(maths(p))
        else:
            words = " ".join(p.split())
            out.append(" " * p[:1].isspace() + (text(words) + " " * p[-1:].isspace() if words else ""))
    return "".join(out).strip()


class Document:
    """A report as blocks, rendered to Markdown, HTML and LaTeX.

    Blocks: headings, paragraphs (plain text), displayed equations whose sides
    are SymPy objects (:meth:`math`, :meth:`equations`: MathML in HTML, ``align*``
    with long sums broken across lines, a term still too wide cut inside its
    parentheses, and ``pmatrix`` in LaTeX), paragraphs with inline mathematics
    (a list of text and SymPy objects), tables whose headers and cells are
    strings or SymPy expressions, figures (PNG files, numbered), and key/value
    lists.  Every text is escaped for the format it goes into.

    Parameters
    ----------
    title : str
        The document's title (its first heading).
    """

    def __init__(self, title: str):
        self.title = title
        self.blocks: list[tuple] = []

    def heading(self, text, level=2):
        """A heading.

        Parameters
        ----------
        text : str
            The heading's text.
        level : int
            2 (the default) for a section, 3 or more below it (the title is level 1); LaTeX has one level below
            sections.
        """
        self.blocks.append(("h", level, text))

    def para(self, text):
        """A paragraph: text, or a list of text and SymPy objects (set inline as mathematics: ``["no: ",
        sp.Abs(p)**2, " > 1"]``).

        Parameters
        ----------
        text : str or list
            The text, or a list of text and SymPy objects (or numbers).

        Raises
        ------
        sympy.SympifyError
            When a part of the list is neither text, a SymPy object nor a number.
        """
        self.blocks.append(("p", text if isinstance(text, str) else [
            t if isinstance(t, str) else sp.sympify(t, strict=True) for t in text]))

    def math(self, lhs, expr):
        """A displayed equation ``lhs = expr`` (SymPy objects; ``lhs`` may be a name such as ``"c_1"``).

        Parameters
        ----------
        lhs : SymPy object or str
            The left-hand side, as for :meth:`equations`.
        expr : SymPy object, number or SymPy matrix
            The right-hand side.

        Raises
        ------
        sympy.SympifyError
            When ``expr`` is neither a SymPy object, a matrix nor a number (text is refused).
        """
        self.equations([(lhs, expr)])

    def equations(self, pairs):
        """Several equations ``lhs = expr`` aligned on their ``=`` signs.

        Parameters
        ----------
        pairs : iterable of (lhs, expr)
            Each ``lhs`` a SymPy object or a str: a word (``"answer"``, ``"\\text{answer}"``) is set upright as
            text, any other name (``"c_1"``, ``"theta"``) is made a Symbol; each ``expr`` a SymPy object, a number
            or a SymPy matrix.

        Raises
        ------
        sympy.SympifyError
            When an ``expr`` is neither a SymPy object, a matrix nor a number (text is refused).
        """
        self.blocks.append(("eqs", [(_label(lhs), sp.sympify(e, strict=True) if not isinstance(e, sp.MatrixBase) else e)
                                    for lhs, e in pairs]))

    def table(self, header, rows):
        """A table: each header and cell is text or a SymPy object (set as mathematics).

        Parameters
        ----------
        header : iterable
            The column headers.
        rows : iterable of iterables
            The rows, each as long as ``header``.
        """
        self.blocks.append(("table", list(header), [list(r) for r in rows]))

    def figure(self, path: Path, caption: str):
        """A figure, numbered in the order the figures are added.

        Parameters
        ----------
        path : path
            The PNG file.  Only its name is kept: the Markdown and LaTeX refer to it by name, and :meth:`html`
            reads it from its ``folder``.
        caption : str
            The caption (plain text).
        """
        self.blocks.append(("fig", Path(path), caption))

    def items(self, pairs):
        """A list of key/value items.

        Parameters
        ----------
        pairs : iterable of (key, value)
            The items; each key and value is shown as ``str`` of it, as plain text.
        """
        self.blocks.append(("items", list(pairs)))

    # ---------------------------------------------------------------- renderers
    @staticmethod
    def _cell_md(x) -> str:
        # text escaped; in math a '|' (\left| of an absolute value) would still end the table cell
        return md_escape(x) if isinstance(x, str) else "$" + _tex(x).replace("|", "\\vert ") + "$"

    @staticmethod
    def _cell_html(x) -> str:
        if isinstance(x, str):
            return html.escape(x)
        return f'<math display="inline">{_mathml(x)}</math>'

    def markdown(self) -> str:
        """The document in Markdown, mathematics as ``$...$`` LaTeX.

        Returns
        -------
        str
            The Markdown text; figures are referred to by file name.
        """
        esc = md_escape
        lines = [f"# {esc(self.title)}", ""]
        figures = 0
        for b in self.blocks:
            if b[0] == "h":
                lines += ["#" * b[1] + " " + esc(b[2]), ""]
            elif b[0] == "p":
                lines += [_inline(b[1], lambda t: esc(t, block=True), lambda x: self._cell_md(x)), ""]
            elif b[0] == "eqs":
                lines += [f"$$ {_tex(lhs)} = {_tex(e)} $$" for lhs, e in b[1]] + [""]
            elif b[0] == "table":
                lines.append("| " + " | ".join(self._cell_md(h) for h in b[1]) + " |")
                lines.append("|" + "---|" * len(b[1]))
                lines += ["| " + " | ".join(self._cell_md(c) for c in r) + " |" for r in b[2]]
                lines.append("")
            elif b[0] == "fig":
                figures += 1
                caption = esc(b[2]).replace("[", "\\[").replace("]", "\\]")
                lines += [f"![{caption}]({b[1].name})", "", f"*Figure {figures}: {esc(b[2])}*", ""]
            elif b[0] == "items":
                lines += [f"- **{esc(k)}**: {esc(v)}" for k, v in b[1]] + [""]
        return "\n".join(lines)

    @staticmethod
    def _html_equations(pairs) -> str:
        rows = []
        for lhs, e in pairs:
            parts = [e] if isinstance(e, sp.MatrixBase) else _lines(e)
            for k, part in enumerate(parts):
                sign = "<mo>=</mo>" if k == 0 else ("" if _tex(part).startswith("-") else "<mo>+</mo>")
                left = _mathml(lhs) if k == 0 else ""
                # Chromium's MathML Core ignores columnalign: align the columns with CSS as well
                rows.append(f"<mtr><mtd style='text-align:right'>{left}</mtd>"
                            f"<mtd style='text-align:left'>{sign}{_mathml(part)}</mtd></mtr>")
        return ('<math display="block"><mtable columnalign="right left" columnspacing="0.3em">'
                + "".join(rows) + "</mtable></math>")

    def _body(self, folder) -> list[str]:
        """The blocks as HTML elements; figures read from ``folder`` (None: from their own paths, if there)."""
        body = [f"<h1>{html.escape(self.title)}</h1>"]
        figures = 0
        for b in self.blocks:
            if b[0] == "h":
                body.append(f"<h{b[1]}>{html.escape(b[2])}</h{b[1]}>")
            elif b[0] == "p":
                body.append(f"<p>{_inline(b[1], html.escape, self._cell_html)}</p>")
            elif b[0] == "eqs":
                body.append(f"<div class='eq'>{self._html_equations(b[1])}</div>")
            elif b[0] == "table":
                head = "".join(f"<th>{self._cell_html(h)}</th>" for h in b[1])
                rows = "".join("<tr>" + "".join(f"<td>{self._cell_html(c)}</td>" for c in r) + "</tr>" for r in b[2])
                body.append(f"<div class='tab'><table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody>"
                            "</table></div>")
            elif b[0] == "fig":
                figures += 1
                image = Path(b[1]) if folder is None else folder / b[1].name
                if folder is None and not image.is_file():       # a notebook's view of a document not written
                    body.append(f"<p><i>Figure {figures}: {html.escape(b[2])}</i></p>")
                    continue
                data = base64.b64encode(image.read_bytes()).decode()
                body.append(f"<figure><img alt='{html.escape(b[2])}' src='data:image/png;base64,{data}'>"
                            f"<figcaption>Figure {figures}: {html.escape(b[2])}</figcaption></figure>")
            elif b[0] == "items":
                body.append("<ul>" + "".join(f"<li><b>{html.escape(str(k))}</b>: {html.escape(str(v))}</li>"
                                             for k, v in b[1]) + "</ul>")
        return body

    def _repr_html_(self) -> str:
        """The document in a notebook: its HTML body, mathematics as MathML (an exported notebook shows it
        without a network or MathJax; the Markdown form's ``$...$`` would stay plain text offline).

        Returns
        -------
        str
            The document's elements, without the page's head and style.
        """
        return "<div class='workspace-sym-document'>\n" + "\n".join(self._body(None)) + "\n</div>"

    def html(self, folder: Path) -> str:
        """The document as one HTML page, mathematics as MathML.

        Parameters
        ----------
        folder : pathlib.Path
            The directory holding the figures' files.

        Returns
        -------
        str
            The page, with its style and every figure embedded (it needs no other file).

        Raises
        ------
        OSError
            When a figure's file cannot be read from ``folder``.
        """
        body = self._body(folder)
        style = ("body{font-family:system-ui,sans-serif;max-width:70em;margin:2em auto;padding:0 1em;line-height:1.45}"
                 "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:.25em .5em;"
                 "text-align:left;vertical-align:top}img{max-width:100%}.eq,.tab{overflow-x:auto;margin:.8em 0}"
                 "math{font-size:110%}figcaption{font-style:italic;color:#444}")
        return ("<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
                f"<title>{html.escape(self.title)}</title><style>{style}</style></head><body>\n"
                + "\n".join(body) + "\n</body></html>\n")

    @staticmethod
    def _tex_equations(pairs) -> str:
        return "\\begin{align*}\n" + " \\\\\n".join(Document._tex_lines(pairs)) + "\n\\end{align*}"

    @staticmethod
    def _tex_lines(pairs) -> list:
        """The ``align*`` lines of ``lhs = e`` pairs: long sums broken, wide matrices by columns."""
        lines = []
        for lhs, e in pairs:
            left = _tex(lhs)
            if isinstance(e, sp.MatrixBase):
                if sum(_column_width(e, j) for j in range(e.cols)) <= _WIDTH:
                    lines.append(f"{left} &= {_tex(e)}")
                    continue
                base = lhs if isinstance(lhs, sp.Symbol) else sp.Symbol("c")
                if e.cols == 1:
                    # a column too wide for the page (a Jacobian column): its entries one by one
                    names = [_subscripted(base, str(i + 1)) for i in range(e.rows)]
                    lines.append(f"{left} &= {_tex(sp.Matrix(names))}")
                    lines += Document._tex_lines(list(zip(names, e)))
                    continue
                # the matrix by columns, as many side by side as fit (entries of a row: scalars, not 1 x 1)
                names = [_subscripted(base, str(j + 1)) for j in range(e.cols)]
                lines.append(f"{left} &= {_tex(sp.Matrix([names]))}")
                for g in _column_groups(e):
                    if len(g) == 1 and _column_width(e, g[0]) > _WIDTH:
                        # one column still too wide: its entries one by one, each broken like a sum
                        lines += Document._tex_lines([(_subscripted(base, f"{i + 1},{g[0] + 1}") if e.rows > 1
                                                       else names[g[0]], e[i, g[0]]) for i in range(e.rows)])
                        continue
                    # one alignment column pair per line: more pairs would line up with the (wider) names row
                    # above and run off the page
                    lines.append(f"{_tex(names[g[0]])} &= " + " \\quad ".join(
                        (f"{_tex(names[j])} = " if j != g[0] else "") + _tex(e[0, j] if e.rows == 1 else e[:, j])
                        for j in g))
                continue
            pieces = _tex_pieces(e)
            lines.append(f"{left} &= {pieces[0]}")
            lines += ["&\\quad " + p for p in pieces[1:]]
        return lines

    def latex(self) -> str:
        """The document as a LaTeX ``article`` (amsmath, graphicx, geometry).

        Returns
        -------
        str
            The complete ``.tex`` source; figures are included by file name.
        """
        out = ["\\documentclass[a4paper,10pt]{article}", "\\usepackage{amsmath,amssymb,graphicx}",
               "\\usepackage[margin=2cm]{geometry}", "\\allowdisplaybreaks", "\\begin{document}",
               f"\\section*{{{tex_escape(self.title, math=False)}}}"]
        for b in self.blocks:
            if b[0] == "h":
                out.append(("\\subsection*{" if b[1] <= 2 else "\\subsubsection*{") + tex_escape(b[2], math=False)
                           + "}")
            elif b[0] == "p":
                out.append(_inline(b[1], lambda t: tex_escape(t, math=False), lambda x: f"${_tex(x)}$") + "\n")
            elif b[0] == "eqs":
                out.append(self._tex_equations(b[1]))
            elif b[0] == "table":
                cols = "l" * len(b[1])
                # never wider than the page: scaled down only when it would run off
                out.append("\\par\\noindent\\resizebox{\\ifdim\\width>\\linewidth\\linewidth\\else\\width\\fi}{!}{"
                           "\\small\\begin{tabular}{" + cols + "}")
                for r in (b[1], *b[2]):             # the header row may hold mathematics too
                    out.append(" & ".join(tex_escape(c, math=False) if isinstance(c, str) else f"${_tex(c)}$"
                                          for c in r) + (" \\\\ \\hline" if r is b[1] else " \\\\"))
                out.append("\\end{tabular}}\n")
            elif b[0] == "fig":
                out.append("\\begin{figure}[htbp]\\centering\\includegraphics[width=0.7\\linewidth]{" + b[1].name + "}"
                           "\\caption{" + tex_escape(b[2], math=False) + "}\\end{figure}")
            elif b[0] == "items":
                # values such as the command line are long words: ragged lines that may break after / _ = ,
                out.append("\\begin{itemize}\\raggedright")
                out += [f"\\item \\textbf{{{tex_escape(str(k), math=False)}}}: "
                        + _breakable(tex_escape(str(v), math=False)) for k, v in b[1]]
                out.append("\\end{itemize}")
        out.append("\\end{document}")
        return "\n".join(out) + "\n"

    def write(self, folder: Path, stem: str = "report") -> dict:
        """Write ``stem.md``, ``stem.html`` and ``stem.tex`` into ``folder`` (figures must already be there).

        The files are written in place, one after the other (not all or nothing): the reports write them into a
        temporary directory and publish it whole.

        Parameters
        ----------
        folder : pathlib.Path
            An existing directory.
        stem : str
            The files' name without extension (default ``"report"``).

        Returns
        -------
        dict of str to pathlib.Path
            The path written for each of ``"markdown"``, ``"html"`` and ``"latex"``.

        Raises
        ------
        OSError
            When a file cannot be written, or a figure cannot be read.
        """
        folder = Path(folder)
        paths = {"markdown": folder / f"{stem}.md", "html": folder / f"{stem}.html", "latex": folder / f"{stem}.tex"}
        paths["markdown"].write_text(self.markdown())
        paths["html"].write_text(self.html(folder))
        paths["latex"].write_text(self.latex())
        return paths


class Equations:
    r"""Equations ``lhs = expr`` for a notebook: MathML in HTML (rendered by the browser itself, so an exported
    notebook needs no network and no MathJax) and LaTeX for front ends that prefer it; long sums are broken
    across lines as in the reports.

    ``Equations(expr)`` shows one expression, ``Equations(("x", e1), ("y", e2))`` several aligned on ``=``.

    Parameters
    ----------
    *items
        One expression (SymPy object, number or matrix) that is not a tuple, or ``(lhs, expr)`` pairs as for
        :meth:`Document.equations`.

    Raises
    ------
    sympy.SympifyError
        When an expression is neither a SymPy object, a matrix nor a number (text is refused).

    Examples
    --------
    >>> eq = Equations(("r_1", sp.sqrt(2) / 2))
    >>> "r_{1} &= \\frac{\\sqrt{2}}{2}" in eq._repr_latex_(), "<msqrt><mn>2</mn></msqrt>" in eq._repr_html_()
    (True, True)
    >>> eq
    r_1 = sqrt(2)/2
    """

    def __init__(self, *items):
        def value(e):                 # numbers and SymPy objects only, never text
            return e if isinstance(e, sp.MatrixBase) else sp.sympify(e, strict=True)

        if len(items) == 1 and not isinstance(items[0], tuple):
            self.pairs = [(None, value(items[0]))]
        else:
            self.pairs = [(_label(lhs), value(e)) for lhs, e in items]

    def _repr_html_(self) -> str:
        if self.pairs[0][0] is None:
            return f'<math display="block">{_mathml(self.pairs[0][1])}</math>'
        return Document._html_equations(self.pairs)

    def _repr_latex_(self) -> str:
        if self.pairs[0][0] is None:
            return f"$\\displaystyle {_tex(self.pairs[0][1])}$"
        body = Document._tex_equations(self.pairs)
        return "$\\displaystyle " + body.replace("align*", "aligned") + "$"

    def __repr__(self) -> str:
        return "\n".join(str(e) if lhs is None else f"{lhs} = {e}" for lhs, e in self.pairs)
