"""Reports: each kind in Markdown, self-contained HTML and LaTeX, with the content checked."""

import re
from html.parser import HTMLParser

import pytest

from workspace_sym import robots
from workspace_sym.interval import pave
from workspace_sym.planar import PlanarChain
from workspace_sym.report import dh_robot_report, paving_report, planar_report, tex_escape


def latex_is_balanced(tex: str) -> bool:
    """Environments nest properly and braces balance (outside escaped \\{ \\})."""
    stack = []
    for kind, name in re.findall(r"\\(begin|end)\{([^}]*)\}", tex):
        if kind == "begin":
            stack.append(name)
        elif not stack or stack.pop() != name:
            return False
    depth = 0
    for ch in re.sub(r"\\[{}]", "", tex):
        depth += {"{": 1, "}": -1}.get(ch, 0)
        if depth < 0:
            return False
    return not stack and depth == 0 and tex.lstrip().startswith("\\documentclass") and "\\end{document}" in tex


class _Tags(HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags, self.srcs = [], []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        self.srcs += [v for k, v in attrs if k == "src"]


def check_html(text: str, figures: int):
    p = _Tags()
    p.feed(text)
    assert p.tags.count("img") == figures
    assert all(s.startswith("data:image/png;base64,") for s in p.srcs)     # self-contained


def test_planar_report(tmp_path):
    chain = PlanarChain(["0.186", "0.146", "0.108"], [-60, 0, -10], [120, 130, 25])
    md_path = planar_report(chain, tmp_path / "r")
    md = md_path.read_text()
    # the Table-2-style table: eight arcs, decimals and exact expressions (LaTeX)
    assert md.count("| III |") + md.count("| II |") >= 16
    assert "[-60.0000, -55.1005]" in md and "\\operatorname{acos}" in md and "\\frac{93}{500}" in md
    assert "## Verification" in md and "0 outside (must be 0)" in md and "## Reproducibility" in md
    for name in ("step0.png", "step1.png", "step2.png", "boundary.png"):
        assert f"]({name})" in md and (tmp_path / "r" / name).stat().st_size > 1000
    html = (tmp_path / "r" / "report.html").read_text()
    check_html(html, figures=4)
    assert "<math" in html and "-55.1005" in html
    tex = (tmp_path / "r" / "report.tex").read_text()
    assert latex_is_balanced(tex) and "\\includegraphics" in tex and "acos" in tex


def test_paving_report(tmp_path):
    model = robots.build("rpr2")
    paving = pave(model.constraints, model.box, delta=0.25, exact_measure=model.exact_measure)
    md = paving_report(paving, tmp_path / "p").read_text()
    assert "| inner |" in md and "Exact measure 35.053350" in md
    check_html((tmp_path / "p" / "report.html").read_text(), figures=1)
    assert latex_is_balanced((tmp_path / "p" / "report.tex").read_text())


def test_dh_report(tmp_path):
    md = dh_robot_report(robots.build("glass-handling"), tmp_path / "d").read_text()
    assert "c1*(a1 + a2*c2 + a3*c23 + d5*s234)" in md and "Singular where" in md
    check_html((tmp_path / "d" / "glass-handling.html").read_text(), figures=1)
    assert latex_is_balanced((tmp_path / "d" / "glass-handling.tex").read_text())


def test_latex_escaping():
    assert tex_escape(r"a_b 50% $x_1$ {c} \ d") == r"a\_b 50\% $x_1$ \{c\} \textbackslash{} d"
    assert not latex_is_balanced("\\documentclass{article}\\begin{document}{\\end{document}")


def test_failed_report_leaves_nothing(tmp_path, monkeypatch):
    """A failure while writing leaves no half-written report."""
    import workspace_sym.report as report

    def boom(*a, **k):
        raise RuntimeError("disk full")

    monkeypatch.setattr(report.Document, "write", boom)
    with pytest.raises(RuntimeError):
        planar_report(PlanarChain([0.3, 0.15], [-120, -30], [0, 30]), tmp_path / "x")
    assert not (tmp_path / "x").exists()


def test_orthoglide_report(tmp_path):
    from workspace_sym.orthoglide import Orthoglide
    from workspace_sym.report import orthoglide_report

    md = orthoglide_report(Orthoglide(), tmp_path / "o", eps=0.125, alpha=0.05).read_text()
    assert "## Largest enclosed cube" in md and "0.643950" in md and "inside volume (proved)" in md
    assert "\\sqrt{2}" in md and "corner (+, +, +)" in md          # the closed form and its binding corners
    check_html((tmp_path / "o" / "report.html").read_text(), figures=2)
    assert latex_is_balanced((tmp_path / "o" / "report.tex").read_text())
