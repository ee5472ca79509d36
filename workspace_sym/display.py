"""Rich display of results in Jupyter (IPython's display protocol) and textbook-shorthand expressions.

The results a user holds (``DHRobot``, ``PlanarChain``, ``Boundary`` and its
table of arcs, ``Paving``, the Orthoglide's results) are drawn by functions of
this module, which :func:`register_notebook_display` registers with IPython by
name (the engines import no presentation; :func:`to_html` gives the same
HTML): HTML tables, a figure embedded as a PNG, numbers through
:mod:`workspace_sym.numbers`.

:func:`textbook_form` turns ``cos(theta2 + theta3)`` into a function that is
still the cosine of ``theta2 + theta3`` (it substitutes, differentiates and
evaluates like ``cos``) but prints as ``c23`` (``c_{23}`` in LaTeX), so that a
notebook cell ending with ``robot.textbook(robot.fk())`` shows the matrix as a
textbook prints it.

Examples
--------
>>> import sympy as sp
>>> t1, t2 = sp.symbols("theta1 theta2")
>>> e = textbook_form(sp.cos(t1) * sp.sin(t1 + t2), (t1, t2))
>>> e, sp.latex(e)
(c1*s12, 'c_{1} s_{12}')
>>> e.subs(t2, 0), e.diff(t2)
(c1*s1, c1*c12)
>>> plain(e.diff(t2)) == sp.cos(t1) * sp.cos(t1 + t2)
True
"""

from __future__ import annotations

import base64
import html
import io
import math
import re
import sys

import sympy as sp

from .document import mathml_markup
from .numbers import clean, fmt, fmt_bound, fmt_bracket, measure_text
from .planar.arcs import degrees_text
from .plotting import plot_boundary_loops, plot_paving, plot_paving_slices, plot_reach_map
from .report import Equations
from .symbolic import plain, textbook_form

__all__ = ["textbook_form", "plain", "html_table", "figure_html", "expr_text", "mathml", "typeset",
           "register_notebook_display",
           "to_html", "paving_html",
           "reach_map_html", "robot_html", "dextrous_html", "cube_html", "planar_chain_html", "boundary_html",
           "arc_table_html", "MAX_3D_BOXES_SHOWN"]


# ------------------------------------------------------------------ SymPy results in a notebook
def mathml(obj) -> str | None:
    """Block MathML of a SymPy expression or matrix, textbook shorthand included (``c_{1}`` as c with a
    subscript 1); ``None`` when SymPy's MathML printer cannot print ``obj``.

    Parameters
    ----------
    obj : sympy.Basic or sympy.MatrixBase
        The expression or matrix.

    Returns
    -------
    str or None
        ``<math display="block">...</math>`` (presentation MathML), or None.

    Examples
    --------
    >>> t1 = sp.Symbol("theta1")
    >>> "<msub><mi>c</mi><mi>1</mi></msub>" in mathml(textbook_form(sp.cos(t1), (t1,)))
    True
    """
    try:
        return f'<math display="block">{mathml_markup(obj)}</math>'
    except Exception:         # an object SymPy's printer does not know: let the notebook show it otherwise
        return None


def typeset(expr, lhs=None) -> Equations:
    """A SymPy result shown as mathematics in a notebook, MathML in its HTML form: ``typeset(robot.textbook(x),
    "x")`` shows ``x = c1 (a1 + ...)`` in the textbook shorthand, and an exported notebook shows it offline.

    ``robot.textbook`` itself returns a SymPy expression (to compute with); inside IPython it is shown as MathML
    too (:func:`register_notebook_display`), but without a left-hand side; this wrapper is the same
    :class:`~workspace_sym.document.Equations` the reports' equations use.

    Parameters
    ----------
    expr : sympy.Basic or sympy.MatrixBase or number
        What to show.
    lhs : str or sympy.Basic, optional
        The left-hand side (``"x"``, ``"T_0^3"``); none by default.

    Returns
    -------
    Equations
        An object with ``_repr_html_`` (MathML) and ``_repr_latex_``; its ``repr`` is the plain text.

    Raises
    ------
    sympy.SympifyError
        When ``expr`` is text or another object that is not mathematics.

    Examples
    --------
    >>> t1 = sp.Symbol("theta1")
    >>> shown = typeset(textbook_form(-sp.cos(t1), (t1,)), "x")
    >>> "<msub><mi>c</mi><mi>1</mi></msub>" in shown._repr_html_(), shown
    (True, x = -c1)
    """
    return Equations(expr) if lhs is None else Equations((lhs, expr))


def register_notebook_display(shell=None) -> bool:
    """Have IPython show SymPy expressions and matrices as MathML in their HTML form.

    A notebook cell ending with ``robot.fk()`` or ``robot.textbook(expr)``
    otherwise shows SymPy's LaTeX, which needs MathJax and a network: an
    exported notebook opened offline shows raw ``$\\displaystyle ...$``.
    MathML is rendered by the browser itself.  Called on import of
    :mod:`workspace_sym` inside IPython; ``shell`` defaults to the running one.
    Returns whether a shell was found.

    The results of the engines (``DHRobot``, ``Paving``, ``ReachResult``, the
    Orthoglide's results, ``PlanarChain``, ``Boundary``, ``ArcTable``) are
    registered by name with the HTML formatter as well, drawn by the functions
    of this module.

    Parameters
    ----------
    shell : IPython.core.interactiveshell.InteractiveShell, optional
        The shell to register with; by default the running one, if IPython has been imported.

    Returns
    -------
    bool
        True when a shell was found and the formatters registered, False otherwise (nothing is changed).
    """
    if shell is None:
        ipython = sys.modules.get("IPython")        # a kernel has imported it; importing it here costs a second
        shell = None if ipython is None else ipython.get_ipython()
    if shell is None:
        return False
    formatter = shell.display_formatter.formatters["text/html"]
    for kind in (sp.Basic, sp.MatrixBase):
        formatter.for_type(kind, mathml)
    # The results of the engines, drawn by this layer (the engines import no presentation).
    for module, name, draw in _RESULTS:
        formatter.for_type_by_name(module, name, draw)
    return True


# ------------------------------------------------------------------ HTML pieces
_GREEK = {"theta": "\u03b8", "alpha": "\u03b1", "pi": "\u03c0", "lambda": "\u03bb", "sigma": "\u03c3",
          "eta": "\u03b7"}
_GREEK_NAME = re.compile(r"\b(" + "|".join(_GREEK) + r")(?=\d|_|\b)")      # theta2, pi; not "pitch"


def expr_text(expr) -> str:
    """One line of text for a SymPy value in an HTML cell: ``θ1 + π/2`` (escaped).

    Parameters
    ----------
    expr : sympy.Basic or object
        The value (anything :func:`sympy.sstr` prints).

    Returns
    -------
    str
        SymPy's string form with Greek names as letters and ``**`` as ``^``, HTML-escaped.

    Examples
    --------
    >>> expr_text(sp.Symbol("theta2") + sp.pi / 2 + sp.Symbol("pitch"))
    'pitch + θ2 + π/2'
    """
    text = _GREEK_NAME.sub(lambda m: _GREEK[m.group(1)], sp.sstr(expr))
    return html.escape(text.replace("**", "^"))


def html_table(header, rows, *, caption: str | None = None) -> str:
    """A small HTML table; cells are escaped unless they are already HTML (``markupsafe``-like ``__html__``).

    Parameters
    ----------
    header : iterable
        The column headings.
    rows : iterable of iterable
        The cells, row by row.
    caption : str or None, optional
        A caption (escaped); none by default.

    Returns
    -------
    str
        ``<table>`` with a ``<thead>`` and a ``<tbody>``.
    """
    def cell(v):
        return v.__html__() if hasattr(v, "__html__") else html.escape(str(v))

    head = "".join(f"<th>{cell(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{cell(v)}</td>" for v in row) + "</tr>" for row in rows)
    cap = f"<caption>{html.escape(caption)}</caption>" if caption else ""
    return f"<table>{cap}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


class Markup(str):
    """Text that :func:`html_table` inserts as HTML, not escaped."""

    def __html__(self):
        return str(self)


def figure_html(fig, *, width: int = 420, alt: str = "figure") -> str:
    """The matplotlib figure ``fig`` as an ``<img>`` with an embedded PNG; the figure is closed.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, saved at 90 dpi and closed even when saving fails.
    width : int, default 420
        The width of the image on the page (pixels).
    alt : str, default "figure"
        The image's alternative text.

    Returns
    -------
    str
        ``<img src="data:image/png;base64,..." ...>``.
    """
    import matplotlib.pyplot as plt

    buffer = io.BytesIO()
    try:
        fig.savefig(buffer, format="png", dpi=90, bbox_inches="tight")
    finally:
        plt.close(fig)
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    return f'<img src="data:image/png;base64,{data}" width="{width}" alt="{html.escape(alt)}"/>'


# ------------------------------------------------------------------ results of the engines
MAX_3D_BOXES_SHOWN = 20_000     # a notebook draws a 3D paving up to this many boxes (matplotlib 3D is slow)


def paving_html(result) -> str:
    """Summary (boxes and measure of each class, the certified bracket) and the picture of a
    :class:`~workspace_sym.interval.boxes.Paving` or of a :class:`~workspace_sym.serial.api.ReachResult` (its
    method, tool constraint and bracket with the volume proved another way): what a notebook shows of it.

    Parameters
    ----------
    result : Paving or ReachResult
        The paving, or a result holding one in ``paving``.

    Returns
    -------
    str
        HTML: the summary lines, the table of box classes and, in 2D or in 3D up to
        :data:`MAX_3D_BOXES_SHOWN` boxes, the picture.
    """
    paving = getattr(result, "paving", result)
    m, c = paving.measures, paving.counts
    rows = [(kind, c[kind], measure_text(kind, m[kind], 6, "g")) for kind in ("inner", "boundary", "outer", "pending")]
    lo, hi = result.measure_bounds
    how = ", with contraction" if paving.contract else ""
    lines = [f"over ({', '.join(map(str, paving.variables))}), δ = {paving.delta} ({paving.size}), backend "
             f"{paving.backend}{how}: {paving.evaluated} boxes evaluated in {paving.seconds:.2f} s",
             f"certified measure in {fmt_bracket(lo, hi, 6)}"]
    constraint = getattr(result, "constraint", None)
    if constraint is not None:
        lines.append(f"tool constraint: {constraint.words()}")
    if getattr(result, "method", ""):
        lines.append(f"method {result.method}")
    if paving.exact_measure is not None:
        lines.append(f"exact measure {fmt(float(sp.N(paving.exact_measure)), 6)} = {sp.sstr(paving.exact_measure)}")
    if not paving.complete:
        lines.append(f"stopped early: {paving.stop_reason}; pending boxes are unclassified")
    drawn, n = len(paving.inner) + len(paving.boundary), len(paving.variables)
    picture = ""
    if n == 2 or (n == 3 and drawn <= MAX_3D_BOXES_SHOWN):
        picture = figure_html(plot_paving(paving), alt="paving")
    elif n == 3:
        picture = f"<p>(no picture of {drawn} boxes in 3D here: see plotting.plot_paving_slices)</p>"
    return ("<p>" + "<br/>".join(html.escape(t) for t in lines) + "</p>"
            + html_table(("boxes", "number", "measure"), rows) + picture)


def reach_map_html(reach_map) -> str:
    """What a notebook shows of a :class:`~workspace_sym.serial.reachmap.ReachMap`: its figures (pairs of each
    verdict, the decided fractions, the cover of the sphere) and the capability's lower bound on the layer
    ``z = 0`` (or the middle layer when 0 is outside the grid).

    Parameters
    ----------
    reach_map : ReachMap
        The map.

    Returns
    -------
    str
        HTML: the summary lines, the table of pairs, the picture.
    """
    s = reach_map.summary()
    rows = [("proved reachable", s["reachable"]), ("proved unreachable", s["unreachable"]),
            ("undecided", s["undecided"])]
    lines = [f"{s['robot']}: {' x '.join(map(str, s['grid']['shape']))} cells of side {s['delta']} {s['units'] or ''}"
             f" x {s['directions']} approach directions, cones of {s['cone']} deg (covering angle "
             f"{fmt(s['covering_angle'] or 0, 4)} deg), built in {fmt(s['seconds'] or 0, 3)} s",
             f"decided: {100 * s['decided_fraction']:.1f} % of the pairs, {100 * s['decided_fraction_in_box']:.1f} % "
             f"inside the arm's bounding box; method {s['method']}"]
    e = reach_map.edges[2]
    z = 0.0 if e[0] <= 0.0 <= e[-1] else float((e[0] + e[-1]) / 2)
    picture = figure_html(plot_reach_map(reach_map, axis="z", value=z), alt="reach map")
    return ("<p>" + "<br/>".join(html.escape(t) for t in lines) + "</p>" + html_table(("pairs", "number"), rows)
            + picture)


def robot_html(robot) -> str:
    """A DH robot's table, limits in degrees, and its parameters (what a notebook shows of a ``DHRobot``).

    Parameters
    ----------
    robot : DHRobot
        The robot.

    Returns
    -------
    str
        HTML: one row per joint (type, theta, d, a, alpha, limits in degrees or in the robot's unit of length),
        and the numeric parameters.
    """
    def degrees(v) -> str:
        return f"{clean(float(v) * 180 / math.pi, scale=360.0):.10g}°"

    def limits(j) -> str:
        if j.limits is None:
            return "none"
        if j.kind == "R":
            return f"[{degrees(j.limits[0])}, {degrees(j.limits[1])}]"
        return f"[{clean(float(j.limits[0])):.10g}, {clean(float(j.limits[1])):.10g}] {robot.units}"

    rows = [(k, j.kind, Markup(expr_text(j.theta)), Markup(expr_text(j.d)), Markup(expr_text(j.a)),
             degrees(j.alpha) if j.alpha.is_number else Markup(expr_text(j.alpha)), limits(j))
            for k, j in enumerate(robot.joints, start=1)]
    table = html_table(("joint", "type", "\u03b8", "d", "a", "\u03b1", "limits"), rows,
                       caption=f"{robot.name}: {robot.n} joints, {robot.convention} DH, lengths in {robot.units}")
    params = ", ".join(f"{k} = {v}" for k, v in robot.parameters.items())
    extra = f"<p>parameters: {expr_text(params)}</p>" if params else ""
    return table + extra


def dextrous_html(result) -> str:
    """The Orthoglide's dextrous workspace (``DextrousResult``): its definition, volumes, box counts and slices of
    its boxes.

    Parameters
    ----------
    result : DextrousResult
        The result.

    Returns
    -------
    str
        HTML: the definition, a table of volumes and box counts, and a figure of slices.
    """
    data = result.to_dict()
    lo, hi = result.sigma
    rows = [("certified inside", fmt_bound(result.volume_inner, 6, up=False), data["boxes"]["inner"]),
            ("error index E (undecided)", fmt_bound(result.volume_undecided, 6, up=True), data["boxes"]["undecided"]),
            ("outside", "", data["boxes"]["outer"])]
    stopped = "" if result.paving.complete else " (stopped early: the rest counts in E)"
    head = (f"<p>Dextrous workspace: the points of [-1, 1]³ where every eigenvalue of J Jᵀ lies in "
            f"[{lo:g}, {hi:g}]; eps = {result.eps}, {data['boxes_evaluated']} boxes in {result.paving.seconds:.2f} s"
            f"{stopped}</p>")
    picture = figure_html(plot_paving_slices(result.paving), width=640, alt="slices")
    return head + html_table(("boxes", "volume", "number"), rows) + picture


def cube_html(result) -> str:
    """The Orthoglide's largest enclosed cube (``CubeResult``): the certified bracket, the centre and the closed
    form in MathML (an exported notebook needs no MathJax).

    Parameters
    ----------
    result : CubeResult
        The result.

    Returns
    -------
    str
        HTML.
    """
    out = [f"<p><b>Largest cube in the dextrous workspace</b> (&sigma; &isin; [{result.sigma[0]:g}, "
           f"{result.sigma[1]:g}], &alpha; = {result.alpha:g}, {result.seconds:.1f} s)</p>",
           "<ul><li>a cube of edge " + html.escape(fmt_bound(result.edge_lower, 9, up=False)) + " centred at ("
           + ", ".join(fmt(v, 6) for v in result.center) + ") is proved inside;</li>"
           f"<li>no cube of edge above {fmt_bound(result.edge_upper, 9, up=True)} fits anywhere (proved).</li></ul>"]
    if result.exact is not None:
        out.append(f"<p>Closed form (binding: {html.escape(result.binding_text())}):</p>")
        out.append(Equations(("edge", result.exact["edge"]), ("centre", result.exact["center"]))._repr_html_())
    return "".join(out)


def planar_chain_html(chain) -> str:
    """The joints (exact lengths, limits in degrees) and the reach of a
    :class:`~workspace_sym.planar.chain.PlanarChain`: what a notebook shows of it.

    Parameters
    ----------
    chain : PlanarChain
        The chain.

    Returns
    -------
    str
        An HTML table, one row per joint.
    """
    rows = [(k + 1, sp.sstr(chain.exact_lengths[k]), degrees_text(chain.lower[k]), degrees_text(chain.upper[k]))
            for k in range(chain.p)]
    return html_table(("joint", "length", "lower (deg)", "upper (deg)"), rows,
                      caption=f"planar chain of {chain.p} revolute joints, reach {fmt(chain.reach, 10, 'g')}")


def arc_table_html(table) -> str:
    """A boundary's arcs in the form of Bastien's Table 2 (:meth:`~workspace_sym.planar.boundary.Boundary.table`,
    an :class:`~workspace_sym.planar.boundary.ArcTable`) as an HTML table.

    Parameters
    ----------
    table : ArcTable
        The table of arcs.

    Returns
    -------
    str
        An HTML table, one row per arc.
    """
    header, rows = table.cells()
    return html_table(header, rows, caption="Boundary arcs (Table 2 form)")


def boundary_html(boundary) -> str:
    """Counts per step, loops, area, the table of arcs and the picture of a
    :class:`~workspace_sym.planar.boundary.Boundary`: what a notebook shows of it.

    Parameters
    ----------
    boundary : Boundary
        The boundary.

    Returns
    -------
    str
        HTML: the summary lines, the table of arcs (:func:`arc_table_html`) and, when there are arcs, the
        picture of the loops.
    """
    c = boundary.counts
    lines = [f"{c['step0']} → {c['step1']} → {c['step2']} arcs after Steps 0 / 1 / 2, {boundary.seconds:.2f} s",
             f"area {fmt(boundary.area, 10, 'g')}, perimeter {fmt(boundary.perimeter, 10, 'g')}"]
    lines += [f"{loop.kind} loop: arcs {', '.join(str(k + 1) for k in loop.arcs)}" for loop in boundary.loops]
    if boundary.undecided_area:
        lines.append(f"undecided faces of area {fmt(boundary.undecided_area, 3, 'g')}: the area is a lower bound")
    picture = figure_html(plot_boundary_loops(boundary), alt="boundary loops") if boundary.arcs else ""
    return ("<p>" + "<br/>".join(html.escape(t) for t in lines) + "</p>" + arc_table_html(boundary.table())
            + picture)


_RESULTS = [("workspace_sym.kinematics", "DHRobot", robot_html),
            ("workspace_sym.orthoglide.certificate", "DextrousResult", dextrous_html),
            ("workspace_sym.orthoglide.cube", "CubeResult", cube_html),
            ("workspace_sym.interval.boxes", "Paving", paving_html),
            ("workspace_sym.interval.boxes", "StoredPaving", paving_html),
            ("workspace_sym.serial.api", "ReachResult", paving_html),
            ("workspace_sym.serial.reachmap", "ReachMap", reach_map_html),
            ("workspace_sym.planar.chain", "PlanarChain", planar_chain_html),
            ("workspace_sym.planar.boundary", "Boundary", boundary_html),
            ("workspace_sym.planar.boundary", "ArcTable", arc_table_html)]


def to_html(obj) -> str:
    """The HTML a notebook shows of a result of the package (the function registered for its type with IPython
    by :func:`register_notebook_display`, or the object's own ``_repr_html_``).

    Parameters
    ----------
    obj : object
        A result of the package, or any object with ``_repr_html_``.

    Returns
    -------
    str
        The HTML.

    Raises
    ------
    AttributeError
        When ``obj`` is none of the registered types and has no ``_repr_html_``.

    Examples
    --------
    >>> from workspace_sym.interval import pave
    >>> "certified measure in" in to_html(pave(["x**2 <= 1"], {"x": (-2, 2)}, delta=0.5))
    True
    """
    for klass in type(obj).__mro__:
        for module, name, draw in _RESULTS:
            if klass.__module__ == module and klass.__qualname__ == name:
                return draw(obj)
    return obj._repr_html_()
