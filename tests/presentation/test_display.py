"""Issue 12 part A: rich display of results, clean numbers, tqdm progress, plots that return their Figure.

Display methods are checked for their content (the numbers and symbols a reader
looks for), not only for existing.
"""

import math
import re

import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given
from hypothesis import strategies as st

import workspace_sym as ws
from workspace_sym import RunOn
from workspace_sym.display import plain, textbook_form, to_html
from workspace_sym.numbers import clean, clean_json, fmt, fmt_bound
from workspace_sym.progress import progress_bar

HUMAN_ARM = (["0.186", "0.146", "0.108"], [-60, 0, -10], [120, 130, 25])     # Bastien 2018, Table 1 case iii


@pytest.fixture(scope="module")
def arm_boundary():
    return ws.PlanarChain(*HUMAN_ARM).boundary()


def one_short_line(text: str) -> bool:
    return "\n" not in text and len(text) <= 100 and "np.float64" not in text and "array(" not in text


# ------------------------------------------------------------------ numbers
@given(st.floats(allow_nan=False, allow_infinity=False), st.integers(0, 12), st.sampled_from("fge"))
@example(-1e-9, 4, "f")
@example(-0.0, 2, "f")
def test_fmt_never_prints_a_negative_zero_and_keeps_the_value(x, digits, spec):
    text = fmt(x, digits, spec)
    assert not (text.startswith("-") and float(text) == 0)
    assert float(text) == float(format(x, f".{digits}{spec}"))     # the same number Python's format gives


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e12, max_value=1e12))
@example(-59.99999999999999)
@example(7.951386703658792e-15)
@example(-0.0)
def test_clean_moves_a_value_by_float_noise_only(x):
    y = clean(x)
    assert math.copysign(1.0, y) > 0 or y != 0                      # no negative zero
    assert abs(y - x) <= 1e-12 * max(abs(x), 1.0)


def test_clean_snaps_exact_values_and_json_keeps_bits():
    assert clean(-59.99999999999999) == -60.0 and clean(7.95e-15, scale=360) == 0.0
    assert clean(-0.09299999999999996) == -0.093                    # 0.186 sin(-30 deg): a short decimal
    assert clean(0.2684793913989452) == 0.2684793913989452           # not near a short decimal: unchanged
    bound = 0.1 + 0.2                                                # a certified bound must keep its bits
    assert clean_json({"m": [bound, -0.0]}) == {"m": [bound, 0.0]}
    assert math.copysign(1.0, clean_json([-0.0])[0]) == 1.0


def test_boundary_table_holds_round_values(arm_boundary):
    """Table 2 of Bastien (2018): -60, 0, -10, ... degrees exactly; before issue 12 the table held
    -59.99999999999999 and 7.95e-15."""
    values = [v for row in arm_boundary.table() for s in row["theta_sets"] for v in s]
    assert -60.0 in values and 0.0 in values and 25.0 in values
    assert all(v == round(v) for v in values if abs(v - round(v)) < 1e-6)
    assert not any(v == 0 and math.copysign(1.0, v) < 0 for v in values)
    # the one angle that is not a whole degree, -55.1005 (Table 2), kept to full precision:
    # -60 deg + 2 atan(l3 sin 10 deg / (l1 + l2 + l3 cos 10 deg)) (tests/planar/test_boundary.py derives it)
    l1, l2, l3 = 0.186, 0.146, 0.108
    closed = -60 + 2 * math.degrees(math.atan(l3 * math.sin(math.radians(10)) / (l1 + l2 + l3 * math.cos(
        math.radians(10)))))
    assert any(abs(v - closed) < 1e-9 for v in values)


# ------------------------------------------------------------------ textbook expressions
def test_textbook_form_prints_shorthand_and_is_still_the_same_maths(glass):
    T = glass.textbook(glass.fk())
    latex = T._repr_latex_()
    assert "c_{1}" in latex and "s_{234}" in latex and "c_{23}" in latex and r"\cos" not in latex
    assert sp.sstr(T[0, 3]) == "c1*(a1 + a2*c2 + a3*c23 + d5*s234)"          # the README's textbook string
    # exact identity with the unprinted matrix, and the derivative is still the derivative
    assert sp.simplify(plain(T) - glass.fk()) == sp.zeros(4, 4)
    t2 = glass.q[1]
    assert sp.simplify(plain(T[0, 3].diff(t2)) - glass.fk()[0, 3].diff(t2)) == 0
    # substitution and numbers: theta = 0.1 everywhere, lambdified against the plain expression
    values = dict(zip(glass.q, [0.1] * 6)) | {k: v for k, v in glass.parameters.items()}
    assert float(T[0, 3].subs(values)) == pytest.approx(float(glass.fk()[0, 3].subs(values)), abs=1e-14)
    f = sp.lambdify(glass.q, T[0, 3].subs(glass.parameters))
    g = sp.lambdify(glass.q, glass.fk()[0, 3].subs(glass.parameters))
    q = np.random.default_rng(0).uniform(-3, 3, (6, 50))
    assert np.allclose(f(*q), g(*q), atol=1e-14)


def test_textbook_of_jacobian_factors_and_charpoly():
    arm = ws.DHRobot([ws.DHJoint.revolute(1, a=1), ws.DHJoint.revolute(2, a=1)])
    J = arm.textbook(arm.position_jacobian)
    assert "s_{12}" in J._repr_latex_() and "c_{12}" in J._repr_latex_()
    factors = arm.textbook(arm.singular_factors("position"))
    assert sp.latex(factors) == r"\left( s_{2},\right)"                    # det = s2 for the 2R arm
    lam = sp.Symbol("lambda")
    poly = ws.characteristic_polynomial(arm.position_jacobian[:2, :], lam, gram=True)
    shown = arm.textbook(poly)
    assert "c_{2}" in sp.latex(shown) and r"\lambda^{2}" in sp.latex(shown)
    assert sp.simplify(plain(shown) - poly.as_expr()) == 0


def test_textbook_charpoly_of_a_3r_arm_prints():
    """Regression: powers of shorthand functions beside powers of symbols (l3**2*s3**2) once broke SymPy's
    ordering of factors (a tuple compared with a str)."""
    arm = ws.robots.build("planar-3r")
    poly = arm.characteristic_polynomial("position")
    shown = arm.textbook(poly)
    text = sp.latex(shown)
    assert "l_{3}^{2} s_{3}^{2}" in text and "c_{23}" in text
    assert sp.expand(plain(shown) - poly.as_expr()) == 0                  # the same polynomial, exactly


def test_textbook_form_leaves_other_angles_alone():
    t1, t2, u = sp.symbols("theta1 theta2 u")
    e = textbook_form(sp.cos(2 * t1) + sp.sin(u) + sp.cos(t1 - t2), (t1, t2))
    assert sp.latex(e) == sp.latex(sp.cos(2 * t1) + sp.sin(u) + sp.cos(t1 - t2))


# ------------------------------------------------------------------ rich display of every result
def test_dh_robot_html_table_has_limits_in_degrees(glass):
    page = to_html(glass)
    # paper 004, section 7: theta1 in [-160, 160] deg, theta2 in [-30, 120] deg (robots.GLASS_LIMITS_DEG)
    assert "[-160°, 160°]" in page and "[-30°, 120°]" in page
    assert "<th>θ</th>" in page and "90°" in page                         # alpha_1 = pi/2 shown as 90 degrees
    assert "a2 = 0.25" in page and one_short_line(repr(glass))


def test_planar_chain_html(arm_boundary):
    chain = arm_boundary.chain
    page = to_html(chain)
    assert "93/500" in page and "<td>-60</td>" in page and "<td>130</td>" in page and "reach 0.44" in page
    assert one_short_line(repr(chain))


def test_boundary_repr_and_html(arm_boundary):
    assert repr(arm_boundary) == "Boundary(8 arcs, 1 loop, area 0.268479)"
    page = to_html(arm_boundary)
    assert "16 → 11 → 8 arcs" in page                                     # Bastien 2018, Table 1 iii
    assert "outer loop: arcs 1, 2, 3, 4, 5, 6, 7, 8" in page
    assert "[-60.0000, -55.1005]" in page and "{-10.0000}" in page         # Table 2, arc 8
    assert "area 0.2684793914" in page and '<img src="data:image/png;base64,' in page
    assert not re.search(r"-0\.0+\b(?![0-9]*[1-9])", page.split("<img")[0])


def test_paving_repr_and_html():
    p = ws.robots.build("rpr2").pave(delta=0.5)
    assert one_short_line(repr(p)) and repr(p).startswith(f"Paving({len(p.inner)} inner")
    page = to_html(p)
    lo, hi = p.measure_bounds
    # Rounded outward (issue 23 item 5): 42.8203125 to nearest printed 42.820312, below the proved upper bound
    assert (lo, hi) == (27.1875, 42.8203125) and "certified measure in [27.187500, 42.820313]" in page
    assert f"<td>inner</td><td>{len(p.inner)}</td>" in page and "exact measure 35.053350" in page    # Rybak
    assert "<img" in page


def test_dextrous_and_cube_results_display():
    from workspace_sym.orthoglide.cube import CubeResult

    dex = ws.robots.build("orthoglide").dextrous(eps=0.25)
    assert one_short_line(repr(dex)) and f"inside volume {fmt_bound(dex.volume_inner, 6, up=False)}" in repr(dex)
    page = to_html(dex)
    assert "eigenvalue of J Jᵀ lies in [0.25, 4]" in page and "error index E" in page and "<img" in page
    # Paper section 5: the edge (sqrt(2) + sqrt(6))/6, centre on the diagonal (README); numpy scalars inside
    edge = (sp.sqrt(2) + sp.sqrt(6)) / 6
    cube = CubeResult(tuple(np.full(3, np.float64(-0.1))), np.float64(0.6435), np.float64(0.6445), 1e-3,
                      (0.25, 4.0), 4.0, {}, [], {"edge": edge, "center": -sp.Rational(1, 10), "half": edge / 2,
                                              "bounds": {"+": ["sigma_max"], "-": ["sigma_min"]}})
    # the float 0.6435 is 0.64349999...: its bracket is rounded outward (issue 23 item 5)
    assert repr(cube) == "CubeResult(edge in [0.643499, 0.644500], centre (-0.100000, -0.100000, -0.100000))"
    latex = cube._repr_latex_()
    assert sp.latex(edge) in latex and r"\approx 0.643950551" in latex
    assert f"$$\\text{{edge}} = {sp.latex(edge)}" in cube._repr_markdown_()


def test_verdict_repr_is_one_line():
    t = sp.Symbol("theta1")
    v = ws.verify.check_expression("1", sp.cos(t) ** 2 + sp.sin(t) ** 2)
    assert repr(v).startswith("Verdict(correct: ") and one_short_line(repr(v))


# ------------------------------------------------------------------ progress
def test_progress_bars_follow_the_progress_option(capsys, monkeypatch):
    with progress_bar(False, total=2, desc="quiet") as bar:
        assert bar.disable
        bar.update(2)
    assert capsys.readouterr().err == ""
    with progress_bar(None, total=2, desc="auto") as bar:           # pytest's stderr is not a terminal
        assert bar.disable
    monkeypatch.setattr("workspace_sym.progress._in_kernel", lambda: True)
    with progress_bar(None, total=2, desc="kernel") as bar:         # in Jupyter: shown (after DELAY seconds)
        shown = not bar.disable
    assert shown
    ws.pave(["x**2 + y**2 <= 1"], {"x": (-1, 1), "y": (-1, 1)}, delta=0.05, run=RunOn(progress=True))
    err = capsys.readouterr().err
    assert "paving: 100.0% of the box decided" in err and "boxes" in err


def test_no_hand_written_progress_bar_left():
    from pathlib import Path

    root = Path(ws.__file__).parent
    for path in root.rglob("*.py"):
        assert 'write(f"\\r' not in path.read_text(), path


# ------------------------------------------------------------------ plots
def test_boundary_plot_returns_figure_with_legend_and_apart_labels(arm_boundary):
    from matplotlib.figure import Figure

    from workspace_sym.plotting import arc_label_positions, plot_boundary_loops

    fig = plot_boundary_loops(arm_boundary)
    ax = fig.axes[0]
    assert isinstance(fig, Figure) and ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "y (m)"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["type II", "type III"]
    numbers = sorted(int(t.get_text()) for t in ax.texts)
    assert numbers == list(range(1, 9))
    pos = arc_label_positions(arm_boundary)
    gaps = np.linalg.norm(pos[:, None] - pos[None], axis=2) + np.eye(len(pos)) * 1e9
    assert gaps.min() >= 0.07 * arm_boundary.chain.reach                # no two arc numbers collide


def test_planar_step_and_slices_plot_into_given_axes():
    import matplotlib.pyplot as plt

    from workspace_sym.plotting import plot_paving_slices, plot_planar_step

    chain = ws.PlanarChain(*HUMAN_ARM)
    fig, axes = plt.subplots(1, 2)
    assert plot_planar_step(chain, 1, ax=axes[1], samples=100) is fig
    legend = [t.get_text() for t in axes[1].get_legend().get_texts()]
    assert "type I" not in legend and "type III" in legend and "100 random configurations" in legend
    dex = ws.robots.build("orthoglide").dextrous(eps=0.25)
    fig, axes = plt.subplots(1, 2)
    assert plot_paving_slices(dex.paving, values=(0.0, 0.3), ax=axes) is fig
    assert axes[0].get_title() == "z = 0.0" and axes[0].get_legend() is not None
    plt.close("all")


def test_a_jupyter_kernel_gets_a_progress_widget_and_rich_outputs():
    """In a real kernel (as tests/presentation/test_notebooks.py runs them): tqdm.auto draws an ipywidgets bar, results
    come with their HTML / LaTeX representations."""
    nbformat = pytest.importorskip("nbformat")
    from nbclient import NotebookClient

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("import workspace_sym as ws\n"
                                          "p = ws.pave(['x**2 + y**2 <= 1'], {'x': (-1, 1), 'y': (-1, 1)}, "
                                          "delta=0.01, run=ws.RunOn(progress=True))\np"),
                nbformat.v4.new_code_cell("r = ws.robots.build('glass-handling')\nr.textbook(r.position)"),
                nbformat.v4.new_code_cell("r")]
    NotebookClient(nb, timeout=300, kernel_name="python3").execute()
    kinds = [[sorted(o.get("data", {})) for o in cell.outputs] for cell in nb.cells]
    assert ["application/vnd.jupyter.widget-view+json", "text/plain"] in kinds[0]
    assert ["text/html", "text/plain"] in kinds[0]                                 # the paving itself
    latex = nb.cells[1].outputs[-1]["data"]["text/latex"]
    assert r"c_{1} \left(a_{1} + a_{2} c_{2} + a_{3} c_{23} + d_{5} s_{234}\right)" in latex
    assert "[-160°, 160°]" in nb.cells[2].outputs[-1]["data"]["text/html"]


def test_notebook_shows_sympy_results_as_mathml():
    """Issue 27: robot.fk() and robot.textbook(expr) showed raw $\\displaystyle ...$ in a notebook exported and
    opened offline; inside IPython they now carry MathML in their HTML form, textbook shorthand included."""
    from IPython.core.interactiveshell import InteractiveShell

    from workspace_sym.display import register_notebook_display

    shell = InteractiveShell.instance()
    assert register_notebook_display(shell)
    robot = ws.robots.build("planar-2r")
    for result, needle in ((robot.textbook(robot.position), "<msub><mi>c</mi><mi>12</mi></msub>"),
                           (robot.fk(), "<mi>cos</mi>")):
        data, _ = shell.display_formatter.format(result)
        assert data["text/html"].startswith('<math display="block">') and needle in data["text/html"]
        assert "text/plain" in data                      # the plain form stays for consoles


def test_notebook_shows_planar_results_through_display(arm_boundary):
    """Issue 38: a planar chain, its boundary and the boundary's table of arcs no longer draw themselves (the planar
    engine imports no presentation module); display registers their HTML with IPython by module and class name, so
    a notebook shows the page of to_html: the counts of Bastien 2018, Table 1 (iii), and the picture."""
    from IPython.core.interactiveshell import InteractiveShell

    from workspace_sym.display import register_notebook_display

    shell = InteractiveShell.instance()
    assert register_notebook_display(shell)
    for result, needle in ((arm_boundary.chain, "reach 0.44"), (arm_boundary, "16 → 11 → 8 arcs"),
                           (arm_boundary.table(), "[-60.0000, -55.1005]")):
        assert not hasattr(result, "_repr_html_")
        data, _ = shell.display_formatter.format(result)
        page = data["text/html"]
        assert needle in page and page.split("<img")[0] == to_html(result).split("<img")[0]
    assert '<img src="data:image/png;base64,' in shell.display_formatter.format(arm_boundary)[0]["text/html"]


def test_boundary_table_displays_as_a_table(arm_boundary):
    """Issue 27: b.table() showed as a raw list of dicts in Jupyter.  It is still that list of dicts, and displays as
    a table: one row per arc (8 for case iii, Table 2 of Bastien 2018), a held joint in braces, a free one as an
    interval, -55.1005 among them; the exact table too."""
    rows = arm_boundary.table()
    assert isinstance(rows, list) and rows == [dict(r) for r in rows] and len(rows) == 8
    page = to_html(rows)
    assert page.count("<tr>") == 1 + 8 and "θ3 (deg)" in page and "[-60.0000, -55.1005]" in page
    lines = rows._repr_markdown_().strip().splitlines()
    assert len(lines) == 2 + 8 and lines[0] == "| # | type | θ1 (deg) | θ2 (deg) | θ3 (deg) |"
    assert lines[2].startswith(f"| 1 | {rows[0]['type']} | ")
    exact = arm_boundary.table(exact=True)
    assert len(exact) == 8 and to_html(exact).count("<tr>") == 1 + 8
    assert "-60" in exact._repr_markdown_() and "atan" in exact._repr_markdown_()


def test_mathml_writes_a_minus_sign_and_names_atan2():
    """Issue 39 (notebook user): MathML minus signs rendered as hyphens and atan2(y, x) as arctan(y, x).  MathML
    Core: the minus of an operator is U+2212 MINUS SIGN; "-" (U+002D) is a hyphen."""
    from workspace_sym.display import mathml

    x, y = sp.symbols("x y")
    out = mathml(sp.atan2(y, x) - 2 * x + sp.Matrix([[-1, sp.Rational(-1, 2)]])[0] * y)
    assert "<mi>atan2</mi>" in out and "arctan" not in out
    assert "<mo>-</mo>" not in out and "<mn>-" not in out and "<mo>\u2212</mo>" in out
    matrix = mathml(sp.Matrix([[-1, 2], [sp.Float(-0.5), x]]))
    assert matrix.count("<mrow><mo>\u2212</mo><mn>1</mn></mrow>") == 1 and "<mn>0.5</mn>" in matrix


def test_latex_names_atan2_as_one_operator():
    """sympy.latex writes \\operatorname{atan}_{2}; the package's printer \\operatorname{atan2}, powers included."""
    from workspace_sym.document import latex_markup
    from workspace_sym.symbolic import shorthand_latex

    x, y = sp.symbols("x y")
    assert latex_markup(sp.atan2(y, x)) == r"\operatorname{atan2}{\left(y, x \right)}"
    assert latex_markup(sp.atan2(y, x) ** 2).startswith(r"\operatorname{atan2}^{2}{\left(")
    assert "atan}_{2}" not in shorthand_latex(sp.atan2(y, x), [x, y])


def test_a_sheet_displays_as_mathml_not_tex():
    """Issue 39 (notebook user): teaching.ipynb showed the sheet through IPython's Markdown, whose $\\theta_{1}$ and
    $$ ... $$ an exported page shows as text offline; a Document's own HTML form is MathML, with no $ left."""
    from workspace_sym.exercises import make_exercises

    sheet, key_doc, _ = make_exercises(seed=3, count=2, max_joints=3)   # as in notebooks/teaching.ipynb
    for doc in (sheet, key_doc):
        assert "$" in doc.markdown()                         # the Markdown form has TeX for MathJax ...
        shown = doc._repr_html_()
        assert "<math" in shown and "$" not in shown         # ... the notebook's form none
        assert "<html" not in shown and "<style" not in shown    # a fragment: it restyles nothing of the notebook


def test_typeset_shows_a_textbook_result_as_mathml():
    # robot.textbook(expr) stays a SymPy expression; typeset gives it a left-hand side and MathML
    from workspace_sym.display import typeset

    robot = ws.robots.build("planar-2r")
    x = robot.textbook(robot.position[0])
    assert isinstance(x, sp.Expr)
    shown = typeset(x, "x")
    html = shown._repr_html_()
    assert "<mtext>x</mtext>" in html or "<mi>x</mi>" in html
    assert "<msub><mi>c</mi><mi>12</mi></msub>" in html and "$" not in html
    assert repr(shown).startswith("x = ")
