"""Closed-form reports: Markdown with image files, one self-contained HTML file, LaTeX.

A report is built once as a list of blocks (:class:`Document`) and rendered to
the three formats, so they always say the same thing.  Exact expressions are
LaTeX in Markdown and LaTeX, and MathML in HTML (read by every current browser
without a network connection).  Reports are written to a temporary directory
first and moved into place only when complete, so a failure never leaves a
half-written report.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import math
import platform
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import sympy as sp

from .errors import SymbolicBudgetError
from .files import publish_dir
from .numbers import fmt, fmt_bound, fmt_bracket, md_escape, measure_text

__all__ = ["Document", "dh_robot_report", "orthoglide_report", "paving_report", "planar_report", "reproducibility",
           "tex_escape", "md_escape", "number", "DEGREE", "Equations"]


def reproducibility(command: str | None = None) -> dict:
    """Versions, date and command that produced a result."""
    import matplotlib
    import mpmath
    import numpy

    from .version import __version__

    return {
        "workspace_sym": __version__,
        "python": platform.python_version(),
        "sympy": sp.__version__,
        "numpy": numpy.__version__,
        "mpmath": mpmath.__version__,
        "matplotlib": matplotlib.__version__,
        "date": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "command": command if command is not None else " ".join(["workspace-sym"] + sys.argv[1:]),
    }


def tex_escape(text: str, *, math: bool = True) -> str:
    r"""Escape LaTeX specials in text, leaving ``$...$`` math segments alone (``math=False``: escape ``$`` too,
    for text that came from a user or the command line).

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


def number(value, spec: str = ".6f") -> str:
    """``value`` formatted with ``spec`` (``".6f"``, ``".1f"``, ``"g"``), never as a negative zero.

    The one place where reports format numbers, through :func:`workspace_sym.numbers.fmt`.

    Examples
    --------
    >>> number(-1e-12), number(-2.5, ".1f"), number(-0.0, "g")
    ('0.000000', '-2.5', '0')
    """
    match = re.fullmatch(r"(?:\.(\d+))?([fge%])", spec)
    if match is None:
        raise ValueError(f"spec: expected a float format such as '.6f' or 'g'; got {spec!r}")
    return fmt(value, int(match.group(1)) if match.group(1) else 6, match.group(2))


# a symbol that prints as the degree sign (^{\circ} in LaTeX): 90 * DEGREE
DEGREE = sp.Symbol("°")

_WIDTH = 78          # characters of SymPy str that fit one line of the LaTeX page (a4, 2 cm margins, 10 pt)


def _breakable(tex: str) -> str:
    """Escaped text that LaTeX may break after ``/``, ``_``, ``=`` and ``,`` (paths, command lines)."""
    return re.sub(r"(/|\\_|=|,)", r"\1\\allowbreak{}", tex)


def _tex(x) -> str:
    if isinstance(x, sp.MatrixBase):
        return sp.latex(x, mat_str="pmatrix", mat_delim="").replace("°", "^{\\circ}")
    return sp.latex(x).replace("°", "^{\\circ}")


def _mathml(x) -> str:
    return sp.mathml(x, printer="presentation")


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
    """

    def __init__(self, title: str):
        self.title = title
        self.blocks: list[tuple] = []

    def heading(self, text, level=2):
        self.blocks.append(("h", level, text))

    def para(self, text):
        """A paragraph: text, or a list of text and SymPy objects (set inline as mathematics: ``["no: ",
        sp.Abs(p)**2, " > 1"]``)."""
        self.blocks.append(("p", text if isinstance(text, str) else [
            t if isinstance(t, str) else sp.sympify(t, strict=True) for t in text]))

    def math(self, lhs, expr):
        """A displayed equation ``lhs = expr`` (SymPy objects; ``lhs`` may be a name such as ``"c_1"``)."""
        self.equations([(lhs, expr)])

    def equations(self, pairs):
        """Several equations ``lhs = expr`` aligned on their ``=`` signs."""
        self.blocks.append(("eqs", [(_label(lhs), sp.sympify(e, strict=True) if not isinstance(e, sp.MatrixBase) else e)
                                    for lhs, e in pairs]))

    def table(self, header, rows):
        """A table: each header and cell is text or a SymPy object (set as mathematics)."""
        self.blocks.append(("table", list(header), [list(r) for r in rows]))

    def figure(self, path: Path, caption: str):
        self.blocks.append(("fig", Path(path), caption))

    def items(self, pairs):
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

    def html(self, folder: Path) -> str:
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
                data = base64.b64encode((folder / b[1].name).read_bytes()).decode()
                body.append(f"<figure><img alt='{html.escape(b[2])}' src='data:image/png;base64,{data}'>"
                            f"<figcaption>Figure {figures}: {html.escape(b[2])}</figcaption></figure>")
            elif b[0] == "items":
                body.append("<ul>" + "".join(f"<li><b>{html.escape(str(k))}</b>: {html.escape(str(v))}</li>"
                                             for k, v in b[1]) + "</ul>")
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
        """Write ``stem.md``, ``stem.html`` and ``stem.tex`` into ``folder`` (figures must already be there)."""
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


def _publish(doc: Document, tmp: Path, out: Path, *, command: str | None = None, start: float | None = None) -> Path:
    """Close ``doc`` with the reproducibility block, render it into ``tmp`` and move everything to ``out``."""
    doc.heading("Reproducibility")
    info = reproducibility(command)
    if start is not None:
        info["seconds"] = number(time.perf_counter() - start, ".2f")
    doc.items(info.items())
    doc.write(tmp)
    _finalise(tmp, out)
    return out / "report.md"


def _measure_name(dimensions: int, units: str | None) -> tuple[str, str]:
    """``("area", "m²")`` for two dimensions in metres, ``("volume", "m³")`` for three; no unit without units."""
    name = {2: "area", 3: "volume"}.get(dimensions, "measure")
    power = {2: "²", 3: "³"}.get(dimensions, f"^{dimensions}")
    return name, f"{units}{power}" if units else ""


def _paving_section(doc: Document, paving, tmp: Path, *, units: str | None = None, stem: str = "paving") -> None:
    """Box counts, the certified measure bracket (rounded outward), whether the run completed and pictures of a
    paving: the boxes (2D or 3D) and, for a 3D paving, three slices.  ``units`` is the length unit of the
    variables; figures go to ``tmp/stem.png`` (and ``tmp/stem-slices.png``)."""
    from .plotting import plot_paving, plot_paving_slices, save_figure, slice_heights

    d = paving.to_dict()
    dims = len(paving.variables)
    name, unit = _measure_name(dims, units)
    kinds = ("inner", "boundary", "outer") + (("pending",) if d["pending"]["boxes"] else ())
    doc.table(["boxes", "count", f"{name} ({unit})" if unit else "measure"],
              [[k, str(d[k]["boxes"]), measure_text(k, d[k]["measure"])] for k in kinds])
    unit_text = f" {unit}" if unit else ""
    lo, hi = d["measure_bounds"]
    text = (f"delta {d['delta']}, backend {d['backend']}, {number(d['seconds'], '.3f')} s: the {name} lies in "
            f"{fmt_bracket(lo, hi, 6)}{unit_text} (inner boxes are proved inside, outer boxes proved "
            "outside, with outward-rounded interval arithmetic; the bracket is rounded outward).")
    if d.get("volume_bounds") is not None:
        b_lo, b_hi = d["box_measure_bounds"]
        text += (f" The first joint turns a full circle, so the workspace is the solid of revolution of its section: "
                 f"the section's cells turned about the axis (Pappus) bound the volume too, and the bracket is the "
                 f"intersection of theirs and the boxes' alone, {fmt_bracket(b_lo, b_hi, 6)}{unit_text}.")
    if d.get("exact_measure") is not None:
        text += f" Exact measure {number(float(d['exact_measure']))}."  # to_dict stores it as a float
    doc.para(text)
    if d["complete"]:
        doc.para("The run completed: every box is proved inside, proved outside, or undecided at size delta.")
    else:
        doc.para(f"The run did not complete ({d.get('stop_reason') or 'stopped'}): {d['pending']['boxes']} pending "
                 f"boxes were not examined; they count in the upper bound only.")
    save_figure(plot_paving(paving, units=units), tmp / f"{stem}.png")
    doc.figure(tmp / f"{stem}.png", "certified boxes: inner (green), boundary (yellow)"
               + (", pending (blue)" if d["pending"]["boxes"] else "") + ", outer (not drawn)")
    if dims == 3:
        heights = slice_heights(paving)
        save_figure(plot_paving_slices(paving, values=heights, units=units), tmp / f"{stem}-slices.png")
        doc.figure(tmp / f"{stem}-slices.png", f"the boxes met by the planes {paving.variables[2]} = "
                   + ", ".join(number(v, "g") for v in heights) + (f" {units}" if units else ""))


def _reach_section(doc: Document, robot, paving, tmp: Path) -> None:
    """The certified position workspace of a DH robot (:func:`workspace_sym.serial.reach`)."""
    coords = ", ".join(map(str, paving.variables))
    doc.heading("Certified workspace (proved boxes)")
    doc.para(f"The end-effector positions ({coords}) are covered by boxes down to size delta = {paving.delta} "
             f"({paving.size}). Inner boxes: every point of the box is the position of some configuration within "
             "the joint limits. Outer boxes: no point of the box is. Boundary boxes, of size at most delta, are "
             "undecided. Every verdict rests on outward-rounded interval arithmetic "
             "(workspace_sym.serial, whose docstrings give the proofs).")
    _paving_section(doc, paving, tmp, units=robot.units, stem="reach")


def _pose_section(doc: Document, robot, paving, constraint, tmp: Path) -> None:
    """The certified orientation workspace of a DH robot (:func:`workspace_sym.serial.reach` with a pose):
    ``constraint`` is its :class:`~workspace_sym.serial.pose.PoseConstraint`."""
    coords = ", ".join(map(str, paving.variables))
    doc.heading("Certified orientation workspace (proved boxes)")
    what = constraint.words()
    doc.para(f"Constraint: {what}. The tool positions ({coords}) are covered by boxes down to size delta = "
             f"{paving.delta} ({paving.size}). Inner boxes: every point of the box is the tool point of a "
             "configuration within the joint limits satisfying the constraint exactly. Outer boxes: no point of the "
             "box is. Boundary boxes, of size at most delta, are undecided. Every verdict rests on outward-rounded "
             f"interval arithmetic (method {paving.method}; workspace_sym.serial.pose and docs/methods.md section 8 "
             "give the proofs).")
    if paving.method == "section":
        lo, hi = paving.volume_bounds
        doc.para(f"The workspace is turned by the first joint: its volume is also bracketed from the section's "
                 f"cells by Pappus's theorem, {fmt_bracket(lo, hi, 6)} {robot.units}³; the bracket below is the "
                 "intersection of that one and the boxes' (both proved).")
    _paving_section(doc, paving, tmp, units=robot.units, stem="reach")


def _reach_not_started(doc: Document, time_limit: float) -> None:
    """The certified-workspace section of a run whose time limit passed while the model was being prepared."""
    doc.heading("Certified workspace (proved boxes)")
    doc.para(f"Not computed: the time limit of {time_limit:g} s (reach_time_limit) passed while the symbolic model "
             "(position, Jacobian, enclosures) was being prepared, so no box was decided. Allow more time.")


def _finalise(tmp: Path, out: Path) -> None:
    publish_dir(tmp, out)


def _degrees(angle, variables=()):
    """An angle of a DH table in degrees: ``theta2 + pi/2`` reads ``theta2 + 90 deg`` (the joint variable kept)."""
    const, rest = sp.sympify(angle).as_independent(*variables, as_Add=True)
    const = sp.nsimplify(const * 180 / sp.pi)
    return rest + const * DEGREE if const != 0 else (rest if rest != 0 else sp.Integer(0) * DEGREE)


def _limits_cell(joint):
    if joint.limits is None:
        return "free"
    lo, hi = joint.limits
    if joint.kind == "R":
        return f"[{sp.nsimplify(lo * 180 / sp.pi)}°, {sp.nsimplify(hi * 180 / sp.pi)}°]"
    return sp.Interval(lo, hi)


def dh_robot_report(robot, out, *, samples: int = 20000, command: str | None = None,
                    reach_delta: float | None = None, reach_time_limit: float = 60.0,
                    reach_constraint: dict | None = None) -> Path:
    """Report of a DH robot: DH table (angles in degrees), forward kinematics, the 6 x n geometric Jacobian and
    its singular factors in textbook form, a sampled workspace picture (Markdown, HTML, LaTeX; ``out/report.md``
    and siblings).  Returns the path of the Markdown file.

    With ``reach_delta`` a section "Certified workspace (proved boxes)" adds
    ``robot.reach(delta=reach_delta, stop=StopAt(time_limit=reach_time_limit))``: box counts
    and measures, the certified bracket of the area (planar robot) or volume,
    whether the run completed, the boxes (3D: also three slices in z).
    ``reach_constraint`` (the keywords ``approach``, ``cone``, ``every``,
    ``orientation``, ``rpy`` of ``reach``) makes it the certified orientation
    workspace under that constraint, with the constraint stated.
    """
    from .interval.boxes import check_delta
    from .interval.driver import RunOn, StopAt
    from .plotting import save_figure, scatter_workspace_3d
    from .sampling import reach_points, sample_joint_box
    from .serial import Pose

    constraint = None
    if reach_delta is not None:                  # checked before the long symbolic work
        check_delta(reach_delta, "reach_delta")
        check_delta(reach_time_limit, "reach_time_limit")
        if reach_constraint:
            from .serial.pose import constraint_from

            constraint = constraint_from(**reach_constraint)
    out = Path(out)
    start = time.perf_counter()
    T = robot.shorthand(robot.fk())
    J = robot.shorthand(robot.geometric_jacobian)
    singular = robot.singular_factors("geometric")
    pts = reach_points(robot, sample_joint_box(robot, samples, seed=1))
    doc = Document(f"{robot.name}: symbolic kinematics")
    q = robot.q
    doc.para("Textbook shorthand: c_i = cos(theta_i), s_ij = sin(theta_i + theta_j), and so on:")
    example = q[1] + q[2] if len(q) > 2 else q[0]
    doc.equations([(robot.shorthand(sp.cos(q[0])), sp.cos(q[0])), (robot.shorthand(sp.sin(example)), sp.sin(example))])
    doc.heading("DH table")
    doc.para(f"Convention: {robot.convention}; lengths in {robot.units}, angles in degrees.")
    doc.table(["i", "type", "theta", "d", "a", "alpha", "limits"],
              [[str(k), j.kind, _degrees(j.theta, q), robot.shorthand(j.d), robot.shorthand(j.a), _degrees(j.alpha),
                _limits_cell(j)]
               for k, j in enumerate(robot.joints, 1)])
    if robot.parameters:
        doc.para("Parameters (" + robot.units + "): "
                 + ", ".join(f"{k} = {v}" for k, v in robot.parameters.items()) + ".")
    doc.heading(f"Forward kinematics T_0^{robot.n}")
    names = sp.Matrix(4, 4, lambda i, j: sp.Symbol(f"r_{i + 1}{j + 1}") if i < 3 and j < 3 else
                      (sp.Symbol("p_" + "xyz"[i]) if i < 3 else sp.Integer(int(j == 3))))
    doc.math(sp.Symbol(f"T_0^{robot.n}"), names)
    doc.equations([(names[i, j], T[i, j]) for j in range(4) for i in range(3)])
    doc.heading("Geometric Jacobian")
    doc.para(f"J is {J.rows} x {J.cols}: rows 1-3 the linear velocity, rows 4-6 the angular velocity, "
             "column k the contribution of joint k.")
    doc.math(sp.Symbol("J"), J)
    if singular:
        doc.para("Rank is lost where one of these factors vanishes:")
        doc.equations([(sp.Symbol(f"f_{k}"), robot.shorthand(f)) for k, f in enumerate(singular, 1)])
    else:
        doc.para("No hypersurface of rank loss.")
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        save_figure(scatter_workspace_3d(pts, title=f"{robot.name}: {samples} sampled configurations",
                                         units=robot.units), tmp / "workspace.png")
        doc.heading("Workspace (sampled picture, not a proof)")
        doc.figure(tmp / "workspace.png", f"{samples} random configurations")
        if reach_delta is not None:
            try:
                pose = {"pose": Pose(**reach_constraint)} if reach_constraint else {}
                paving = robot.reach(delta=reach_delta, stop=StopAt(time_limit=reach_time_limit),
                                     run=RunOn(progress=False), **pose)
            except SymbolicBudgetError as error:
                if error.parameter != "time_limit":
                    raise
                _reach_not_started(doc, reach_time_limit)
            else:
                if constraint is None:
                    _reach_section(doc, robot, paving, tmp)
                else:
                    _pose_section(doc, robot, paving, constraint, tmp)
        return _publish(doc, tmp, out, command=command, start=start)


# ---------------------------------------------------------------------- planar chains
def _exact_set(values):
    values = [sp.nsimplify(v) if v.is_Rational else v for v in values]
    return sp.FiniteSet(values[0]) if len(values) == 1 else sp.Interval(values[0], values[1])


def planar_verification(boundary, exact_rows=None, *, samples: int = 20000, seed: int = 1) -> list[tuple[str, str]]:
    """Independent cross-checks of a boundary, as (check, result) pairs for a report.

    Exact against float values, random configurations (corners included) never
    outside the loops, every boundary arc's configurations inside the joint
    limits and on the arc, and how each face of the arrangement was decided.
    """
    from .planar.exact import exact_area

    chain = boundary.chain
    checks = []
    if exact_rows is not None:
        worst = 0.0
        for row, arc in zip(exact_rows, boundary.arcs):
            pairs = [(row["center"][0], arc.center[0]), (row["center"][1], arc.center[1]),
                     (row["radius"], arc.radius), (row["start_angle"], arc.start_angle),
                     (row["end_angle"], arc.end_angle)]
            worst = max(worst, max(abs(float(sp.N(e, 30)) - v) for e, v in pairs))
        area_err = abs(float(sp.N(exact_area(boundary, exact_rows), 30)) - boundary.area)
        checks.append(("closed forms vs floats", f"largest difference {number(worst, '.1e')} over centres, radii "
                                                 f"and angles; area {number(area_err, '.1e')}"))
    theta = chain.sample(samples, seed=seed)
    pts = chain.forward(theta)
    verdicts = list(boundary.classify(pts, tol=1e-9))
    outside = verdicts.count("outside")
    checks.append(("random configurations", f"{len(pts)} (with {min(2 ** chain.p, 4096)} corners of the joint box): "
                                            f"{verdicts.count('inside')} inside, {verdicts.count('boundary')} on the "
                                            f"boundary, {outside} outside (must be 0)"))
    worst_fk, worst_lim = 0.0, 0.0
    for arc in boundary.arcs:
        i = arc.free_joint - 1
        lo, hi = arc.theta_sets[i]
        for t in np.linspace(lo, hi, 5):
            th = [s[0] for s in arc.theta_sets]
            th[i] = t
            worst_lim = max(worst_lim, max(max(chain.lower[k] - th[k], th[k] - chain.upper[k], 0.0)
                                           for k in range(chain.p)))
            p = chain.forward(th)
            worst_fk = max(worst_fk, abs(math.dist(p, arc.center) - arc.radius))
    checks.append(("arc configurations", f"forward kinematics lies on its arc within {number(worst_fk, '.1e')}; "
                                         f"joint limits exceeded by at most {number(worst_lim, '.1e')} rad"))
    methods: dict[str, int] = {}
    for ev in boundary.evidence.values():
        methods[ev["method"]] = methods.get(ev["method"], 0) + 1
    checks.append(("faces of the arrangement", f"{len(boundary.faces)} bounded faces: " +
                   ", ".join(f"{n} by {m}" for m, n in sorted(methods.items())) +
                   "; the unbounded face is outside"))
    checks.append(("area", f"{number(boundary.area, '.12g')} from the loops (Green's theorem); "
                           f"undecided area {number(boundary.undecided_area, '.3g')}"))
    if boundary.merged:
        m = boundary.merged
        checks.append(("merged slivers", f"{m['faces']} faces narrower than {m['width_tolerance']:g} times the reach, "
                                         f"of total area {number(m['area'], '.3g')}, merged into their neighbours "
                                         f"({', '.join(f'{n} {k}' for k, n in m['into'].items() if n)})"))
    return checks


def planar_report(chain, out, *, command: str | None = None, title: str | None = None, exact: bool = True,
                  paving=None, paving_title: str | None = None) -> Path:
    """Full report of a planar chain's workspace boundary in ``out`` (report.md, report.html, report.tex, figures).

    With ``paving`` (a :class:`~workspace_sym.interval.Paving`) a section
    summarises that certified covering as well.  Returns the Markdown path.
    """
    from .planar.boundary import format_set
    from .planar.exact import area_terms
    from .plotting import plot_boundary_loops, plot_planar_step, save_figure

    out = Path(out)
    start = time.perf_counter()
    boundary = chain.boundary()
    rows = boundary.exact if exact else []
    doc = Document(title or f"Workspace boundary of a planar {chain.p}-joint chain")
    doc.para("Alignment method of Bastien (2018): Step 0 lists the circular arcs allowed by the alignment "
             "condition, Step 1 keeps the parts that pass the local test of Lemma 3.1 and marks the side of the "
             "workspace, Step 2 walks the arrangement of the kept arcs; every face of that arrangement is proved "
             "inside (Lemma 3.1 or a witness configuration) or outside (interval exclusion). "
             "Angles in degrees; theta_1 is measured from the +y axis, theta_k from segment k-1.")
    doc.heading("Chain")
    doc.table(["joint", "length", "lower (deg)", "upper (deg)"],
              [[str(k + 1), chain.exact_lengths[k], sp.nsimplify(chain.exact_lower[k] * 180 / sp.pi),
                sp.nsimplify(chain.exact_upper[k] * 180 / sp.pi)] for k in range(chain.p)])
    c = boundary.counts
    doc.para(f"Arcs after Step 0: {c['step0']}; after Step 1: {c['step1']}; on the boundary (Step 2): {c['step2']}.")
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        doc.heading("Steps 0, 1 and 2")
        for step in (0, 1, 2):
            save_figure(plot_planar_step(chain, step), tmp / f"step{step}.png")
            doc.figure(tmp / f"step{step}.png", f"Step {step} (blue: type I, red: type II, green: type III; "
                                                 f"ticks point into the workspace; gold: random configurations)")
        save_figure(plot_boundary_loops(boundary), tmp / "boundary.png")
        doc.heading("Boundary")
        for loop in boundary.loops:
            doc.para(f"{loop.kind} loop, travelled with the workspace on the left: arcs "
                     + ", ".join(str(k + 1) for k in loop.arcs) + f" (signed area {number(loop.area, '.10g')}).")
        doc.figure(tmp / "boundary.png", "Boundary arcs numbered as in the tables")
        doc.table(["#", "type"] + [f"Theta_{j + 1} (deg)" for j in range(chain.p)] + ["centre", "radius"],
                  [[str(k + 1), a.type] + [format_set([math.degrees(v) for v in s_]) for s_ in a.theta_sets]
                   + [f"({number(a.center[0], '.6f')}, {number(a.center[1], '.6f')})", f"{number(a.radius, '.6f')}"]
                   for k, a in enumerate(boundary.arcs)])
        if exact:
            doc.heading("Closed forms", 3)
            doc.para("The same table with exact expressions (degrees), from the exact inputs: every entry is "
                     "checked against the float value in the Verification section.")
            doc.table(["#", "type"] + [f"Theta_{j + 1} (deg)" for j in range(chain.p)],
                      [[str(k + 1), a.type] + [_exact_set(s_) for s_ in r["theta_sets"]]
                       for k, (a, r) in enumerate(zip(boundary.arcs, rows))])
            doc.para("Centres c_k and radii r_k of the boundary arcs:")
            doc.equations([pair for k, r in enumerate(rows, 1)
                           for pair in ((f"c_{k}", sp.Matrix([r["center"]])), (f"r_{k}", r["radius"]))])
        doc.heading("Area")
        doc.para(f"Area {number(boundary.area, '.12g')}, perimeter {number(boundary.perimeter, '.12g')}.")
        if exact:
            doc.para("Exact area, one term per boundary arc (Green's theorem: the sector swept about the arc's centre "
                     "plus the change of the centre's moment), and their sum:")
            terms = area_terms(boundary, rows)
            doc.equations([(f"A_{k}", t) for k, t in enumerate(terms, 1)]
                          + [("A", sp.Add(*[sp.Symbol(f"A_{k}") for k in range(1, len(terms) + 1)]))])
        doc.heading("Verification")
        doc.table(["check", "result"], [[k, v] for k, v in planar_verification(boundary, rows)])
        if paving is not None:
            doc.heading(paving_title or "Certified paving")
            _paving_section(doc, paving, tmp)
        return _publish(doc, tmp, out, command=command, start=start)


def paving_report(paving, out, *, title: str = "Certified paving", command: str | None = None) -> Path:
    """Report of a certified paving: box counts, the measure bracket, a picture, reproducibility."""
    doc = Document(title)
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        _paving_section(doc, paving, tmp)
        return _publish(doc, tmp, Path(out), command=command)


def orthoglide_report(model, out, *, eps: float = 0.125, alpha: float = 0.01, command: str | None = None) -> Path:
    """Report of the Orthoglide: J, the pencil polynomial, the certified dextrous volume and the largest cube."""
    from .plotting import plot_paving, plot_paving_slices, save_figure

    out = Path(out)
    start = time.perf_counter()
    dex = model.dextrous(eps=eps)
    cube = model.largest_cube(alpha=alpha)
    d, c = dex.to_dict(), cube.to_dict()
    doc = Document("Orthoglide: dextrous workspace and largest enclosed cube")
    doc.para("Chablat, Wenger, Merlet (2002). A point is dextrous when every eigenvalue of J J^T lies in "
             f"[{d['sigma'][0]}, {d['sigma'][1]}]. Boxes are proved inside or outside with outward-rounded interval "
             "arithmetic; undecided boxes make up the error index E.")
    doc.math("J", model.J)
    pencil = model.pencil
    term_counts = ", ".join(str(len(sp.Add.make_args(k))) for k in pencil.all_coeffs())
    doc.para(f"The eigenvalues of J J^T are the roots of the cubic q(lambda) = det(lambda A A^T - B^2) "
             f"(no division), whose coefficients have {term_counts} terms; its leading coefficient q_3 is")
    doc.math("q_3", pencil.all_coeffs()[0])
    doc.para("Boxes are certified with the inverse N = A^T B^-2 A = (J J^T)^-1 instead: enclosed in mean-value "
             "form, rotated by the eigenvectors at the box centre, N - I/sigma_max and I/sigma_min - N proved "
             "positive definite (inside) or a Rayleigh quotient out of range (outside).")
    doc.math("N", model.inverse)
    doc.heading("Dextrous workspace")
    doc.table(["eps", "inside volume (proved)", "E (undecided)", "boxes in / undecided / out", "seconds"],
              [[str(eps), fmt_bound(d["volume_inner"], 6, up=False), fmt_bound(d["volume_undecided"], 6, up=True),
                f"{d['boxes']['inner']} / {d['boxes']['undecided']} / {d['boxes']['outer']}",
                number(d["seconds"], ".1f")]])
    doc.para("Paper, eps = 0.05: 1.468 inside, E in [0, 0.48], about 5 hours.")
    doc.heading("Largest enclosed cube")
    doc.table(["centre", "edge proved inside", "no enclosed cube above", "alpha", "seconds"],
              [[", ".join(number(v) for v in c["center"]), fmt_bound(c["edge_lower"], 6, up=False),
                fmt_bound(c["edge_upper"], 6, up=True),
                str(alpha), number(c["seconds"], ".1f")]])
    if cube.exact is not None:
        doc.para("The binding points are the corners of the cube on the diagonal x = y = z: "
                 + "; ".join(f"corner ({k}, {k}, {k}) on {', '.join(v)}" for k, v in cube.exact["bounds"].items())
                 + ". Solving the pencil there exactly gives the edge and the centre (x = y = z) in closed form; the "
                 "certified bracket above contains them.")
        doc.equations([("edge", cube.exact["edge"]), ("centre", cube.exact["center"])])
    doc.para("Paper (alpha = 0.001): centre (0.085938, 0.085938, 0.085938), edge 0.643950, no cube above 0.643952. "
             "The paper's centre is 11/128, the point of a 1/128 grid next to the closed form.")
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        save_figure(plot_paving(dex.paving, title=f"dextrous workspace, eps = {eps}"), tmp / "dextrous.png")
        doc.figure(tmp / "dextrous.png", "inside boxes (green) and undecided boxes (yellow)")
        save_figure(plot_paving_slices(dex.paving, reference=lambda p: model.numeric_dextrous(p, dex.sigma)),
                    tmp / "slices.png")
        doc.figure(tmp / "slices.png", "slices of the boxes; red: the boundary from numeric eigenvalues")
        return _publish(doc, tmp, out, command=command, start=start)
