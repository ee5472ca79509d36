"""Reports: each kind in Markdown, self-contained HTML and LaTeX, with the content checked."""

import re
import shutil
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from paths import DATA
from reports import report_with_document
from system_tools import assert_compiles, headless_chromium, require_tool
from workspace_sym import Pose, RunOn, StopAt, robots
from workspace_sym.interval import pave
from workspace_sym.numbers import fmt_bracket
from workspace_sym.planar import PlanarChain
from workspace_sym.report import dh_robot_report, number, paving_report, planar_report, tex_escape


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


HUMAN_ARM = (["0.186", "0.146", "0.108"], [-60, 0, -10], [120, 130, 25])     # Bastien 2018, Table 1 case iii


@pytest.fixture(scope="module")
def planar(tmp_path_factory):
    """The Table 1 iii report, written once for the tests below."""
    # a long command line with $ and ~ (it goes into the LaTeX verbatim-escaped and must break across lines)
    command = ("workspace-sym report chain --lengths=0.186,0.146,0.108 --lower=-60,0,-10 --upper=120,130,25 --out "
               + "/".join(["~/$HOME_long_directory_name"] * 6))
    return report_with_document(lambda f: planar_report(PlanarChain(*HUMAN_ARM), f, command=command),
                                 tmp_path_factory.mktemp("planar") / "r")


@pytest.fixture(scope="module")
def dh(tmp_path_factory):
    return report_with_document(lambda f: dh_robot_report(robots.build("glass-handling"), f, samples=2000),
                                 tmp_path_factory.mktemp("dh") / "d")


def test_planar_report(planar):
    md_path, _ = planar
    md = md_path.read_text()
    folder = md_path.parent
    # the Table-2-style table: eight arcs, decimals and exact expressions (LaTeX)
    assert md.count("| III |") + md.count("| II |") >= 16
    assert "[-60.0000, -55.1005]" in md and "\\operatorname{atan2}" in md and "\\frac{93}{500}" in md
    assert "## Verification" in md and "0 outside (must be 0)" in md and "## Reproducibility" in md
    for name in ("step0.png", "step1.png", "step2.png", "boundary.png"):
        assert f"]({name})" in md and (folder / name).stat().st_size > 1000
    assert "*Figure 4: Boundary arcs numbered as in the tables*" in md
    html = (folder / "report.html").read_text()
    check_html(html, figures=4)
    assert "<math" in html and "-55.1005" in html and "<code>" not in html      # labels are MathML, not code
    tex = (folder / "report.tex").read_text()
    assert latex_is_balanced(tex) and "\\includegraphics" in tex and "\\caption*" not in tex
    assert "\\begin{align*}" in tex and "\\begin{pmatrix}" in tex


def test_planar_report_math_has_minus_signs_and_atan2(planar):
    """Issue 39 (notebook user): the demo's HTML showed minus signs as hyphens (``<mo>-</mo>``), atan2 as
    ``arctan(y, x)``, and the LaTeX ``\\operatorname{atan}_{2}``; MathML's minus is U+2212 (MathML Core, section
    on operators) and the function is named atan2 in both."""
    md_path, _ = planar
    html = md_path.with_suffix(".html").read_text(encoding="utf-8")
    maths = re.findall(r"<math.*?</math>", html, flags=re.S)
    assert maths and "<mi>atan2</mi>" in html and "arctan" not in html
    assert not any("<mo>-</mo>" in m or "<mn>-" in m for m in maths)
    assert sum(m.count("<mo>\u2212</mo>") for m in maths) >= 8          # the -60 deg limits, the negative terms
    tex = md_path.with_suffix(".tex").read_text()
    assert "\\operatorname{atan2}" in tex and "atan}_{2}" not in tex and "atan_2" not in tex
    require_tool("pdflatex")
    assert_compiles(md_path.with_suffix(".tex"))


def _sympy_cells(doc):
    """Every SymPy object a report shows: table cells, equation sides (matrix entries one by one)."""
    for block in doc.blocks:
        if block[0] == "table":
            yield from (c for row in block[2] for c in row if not isinstance(c, str))
        elif block[0] == "eqs":
            for _, e in block[1]:
                yield from (e if hasattr(e, "shape") else [e])


def test_table1_iii_closed_forms_are_short(planar):
    """Issue 12: every closed-form cell of the Table 1 iii report is at most 80 characters of SymPy str, with no
    unreduced atan(cos x / sin x) nor sin(x)**2 + cos(x)**2, and the exact area is one term per arc plus a sum."""
    _, doc = planar
    cells = list(_sympy_cells(doc))
    assert len(cells) > 40
    assert max(len(str(c)) for c in cells) <= 80, max(cells, key=lambda c: len(str(c)))
    text = " ".join(str(c) for c in cells)
    assert "atan(" not in text and "acos(" not in text and ")**2" not in text
    names = [str(lhs) for b in doc.blocks if b[0] == "eqs" for lhs, _ in b[1]]
    assert [n for n in names if n.startswith("A_")] == [f"A_{k}" for k in range(1, 9)] and "A" in names


def _reach_report(robot, folder, **options):
    """``dh_robot_report(robot, folder, reach_delta=...)`` with the Document it rendered, the Paving ``robot.reach``
    returned and the keywords it was called with (to hold the report's numbers against the paving's)."""
    from workspace_sym.kinematics import DHRobot

    calls = []
    reach = DHRobot.reach

    def keep(self, **kwargs):
        calls.append((kwargs, reach(self, **kwargs)))
        return calls[-1][1]

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(DHRobot, "reach", keep)
        path, doc = report_with_document(lambda f: dh_robot_report(robot, f, samples=500, **options), folder)
    assert len(calls) == 1
    return path, doc, calls[0][1], calls[0][0]


def test_scara_tool_down_report_states_the_constraint_and_the_pavings_numbers(tmp_path, scara):
    """An orientation workspace's section (``pose=Pose(...)``): the constraint stated, the numbers those of
    the Paving ``reach`` returned under it (reference: that Paving)."""
    path, _, paving, kwargs = _reach_report(scara, tmp_path / "r", reach_delta=0.1, pose=Pose(rpy=(180, 0, 0)))
    assert kwargs["pose"].rpy == (180, 0, 0) and kwargs["delta"] == 0.1
    md = path.read_text()
    text = md[md.index("## Certified orientation workspace (proved boxes)"):md.index("## Reproducibility")]
    assert "the tool frame can be exactly the rotation of roll, pitch, yaw (180, 0, 0) degrees" in text
    assert "satisfying the constraint exactly" in text and f"method {paving.method}" in text
    for kind in ("inner", "boundary", "outer"):
        count = re.search(rf"^\| {kind} \| (\d+) \|", text, re.M).group(1)
        assert int(count) == paving.counts[kind]
    lo, hi = paving.measure_bounds
    assert fmt_bracket(lo, hi, 6) in text


@pytest.fixture(scope="module")
def reach2d(tmp_path_factory):
    """The planar 2R arm (l1 = 1, l2 = 0.5, joints free) with its certified workspace at delta 0.2."""
    return _reach_report(robots.build("planar-2r"), tmp_path_factory.mktemp("reach2d") / "r", reach_delta=0.2)


@pytest.fixture(scope="module")
def reach3d(tmp_path_factory, scara):
    """The SCARA of the catalog with its certified workspace at delta 0.1 (about 2 s of reach)."""
    return _reach_report(scara, tmp_path_factory.mktemp("reach3d") / "r", reach_delta=0.1, stop=StopAt(time_limit=30))


def _section(md: str) -> str:
    start = md.index("## Certified workspace (proved boxes)")
    return md[start:md.index("## Reproducibility")]


def _assert_reach_section(md: str, paving, name: str, unit: str):
    """The section states what is proved and gives the paving's counts, measures, bracket and run."""
    text = _section(md)
    assert "every point of the box is the position of some configuration within the joint limits" in text
    assert "Outer boxes: no point of the box is" in text and "of size at most delta, are undecided" in text
    for kind in ("inner", "boundary", "outer"):
        count, measure = re.search(rf"^\| {kind} \| (\d+) \| ([\d.]+) \|$", text, re.M).groups()
        assert int(count) == paving.counts[kind] and abs(float(measure) - paving.measures[kind]) <= 1e-6
        if kind in ("inner", "outer"):          # proved lower bounds, printed rounded down (issue 23 item 5)
            assert float(measure) <= paving.measures[kind]
    assert f"| boxes | count | {name} ({unit}) |" in text
    lo, hi = map(float, re.search(rf"the {name} lies in \[([-\d.]+), ([-\d.]+)\] {unit} ", text).groups())
    # printed with six decimals rounded outward: still a bracket of the paving's, and as tight as six decimals allow
    p_lo, p_hi = paving.measure_bounds
    assert lo <= p_lo < lo + 1e-6 and hi - 1e-6 < p_hi <= hi
    assert f", {number(paving.seconds, '.3f')} s:" in text
    assert ("The run completed" in text) == paving.complete
    return lo, hi


def _colour_pixels(png: Path, colour: str) -> int:
    """Pixels of an image within a few levels of ``colour`` (the image must decode)."""
    import matplotlib.image
    from matplotlib.colors import to_rgb

    rgb = matplotlib.image.imread(png)[:, :, :3]
    assert rgb.shape[0] > 300 and rgb.shape[1] > 300
    return int((np.abs(rgb - np.array(to_rgb(colour))).max(axis=2) < 0.02).sum())


def _green_pixels(png: Path) -> int:
    """Pixels whose green exceeds red and blue by 0.15 (any shade of the inner boxes' green)."""
    import matplotlib.image

    rgb = matplotlib.image.imread(png)[:, :, :3]
    return int((rgb[:, :, 1] - np.maximum(rgb[:, :, 0], rgb[:, :, 2]) > 0.15).sum())


def test_reach_section_of_a_planar_robot(reach2d):
    """planar-2r: the section's numbers are those of the Paving reach returned; the annulus 1/2 <= r <= 3/2 of
    area 2 pi (exact, the arm's full joint range) lies in the printed bracket; the picture shows inner boxes."""
    md_path, _, paving, kwargs = reach2d
    assert kwargs == {"delta": 0.2, "stop": StopAt(time_limit=60.0), "run": RunOn(progress=False)}
    lo, hi = _assert_reach_section(md_path.read_text(), paving, "area", "m²")
    assert paving.complete and lo <= 2 * np.pi <= hi and paving.counts["inner"] > 0
    folder = md_path.parent
    assert _colour_pixels(folder / "reach.png", "#4caf50") > 1000 and _colour_pixels(folder / "reach.png", "#ffd54f")
    assert not (folder / "reach-slices.png").exists()               # slices only for a 3D workspace
    check_html((folder / "report.html").read_text(), figures=2)
    assert latex_is_balanced((folder / "report.tex").read_text())


def test_reach_section_of_a_spatial_robot(reach3d):
    """SCARA: volume in m³, the 3D picture and three slices spread over the z range of the boxes."""
    md_path, _, paving, kwargs = reach3d
    assert kwargs == {"delta": 0.1, "stop": StopAt(time_limit=30), "run": RunOn(progress=False)}
    md = md_path.read_text()
    _assert_reach_section(md, paving, "volume", "m³")
    assert paving.counts["inner"] > 0 and len(paving.variables) == 3
    heights = [float(v) for v in re.search(r"the planes z = ([\d.]+), ([\d.]+), ([\d.]+) m\*", md).groups()]
    z_lo, z_hi = paving.box.lower[2], paving.box.upper[2]
    assert z_lo < heights[0] < heights[1] < heights[2] < z_hi
    folder = md_path.parent
    assert _green_pixels(folder / "reach.png") > 2000               # the shaded inner solid, not only its legend
    assert _colour_pixels(folder / "reach-slices.png", "#4caf50") > 100
    assert _colour_pixels(folder / "reach-slices.png", "#ffd54f") > 1000
    check_html((folder / "report.html").read_text(), figures=3)
    assert latex_is_balanced((folder / "report.tex").read_text())


def test_reach_report_refuses_a_bad_delta(tmp_path):
    """Bad reach options fail at once, naming the parameter, and write nothing."""
    from workspace_sym.errors import WorkspaceError

    arm = robots.build("planar-2r")
    for options, name in (({"reach_delta": -0.1}, "reach_delta"), ({"reach_delta": float("nan")}, "reach_delta"),
                          ({"reach_delta": 0.2, "stop": 60}, "stop"), ({"reach_delta": 0.2, "run": None}, "run"),
                          ({"reach_delta": 0.2, "pose": {"rpy": (180, 0, 0)}}, "pose"),
                          ({"reach_delta": 0.2, "pose": Pose(cone=20)}, "cone")):
        with pytest.raises(WorkspaceError) as err:
            dh_robot_report(arm, tmp_path / "x", **options)
        assert err.value.parameter == name and name in str(err.value)
    with pytest.warns(DeprecationWarning, match="reach_time_limit= is deprecated"), \
            pytest.raises(WorkspaceError) as err:
        dh_robot_report(arm, tmp_path / "x", reach_delta=0.2, reach_time_limit=0)
    assert err.value.parameter == "reach_time_limit"
    with pytest.raises(TypeError, match="unexpected keyword argument 'reach_deltaa'"):
        dh_robot_report(arm, tmp_path / "x", reach_deltaa=0.2)
    assert not (tmp_path / "x").exists()


def test_the_earlier_reach_keywords_of_the_report_warn_and_call_reach_the_new_way(tmp_path, scara):
    """Issue 38 item 3: ``reach_time_limit=`` and ``reach_constraint=`` still work for one release, each with a
    DeprecationWarning naming its new spelling, and ``reach`` is called as ``stop=`` and ``pose=`` would call it
    (reference: the keywords reach received, recorded)."""
    with pytest.warns(DeprecationWarning) as caught:
        _, _, _, old = _reach_report(scara, tmp_path / "old", reach_delta=0.25, reach_time_limit=30,
                                     reach_constraint={"rpy": (180, 0, 0)})
    assert sorted(str(w.message) for w in caught if w.category is DeprecationWarning) == [
        "dh_robot_report: reach_constraint= is deprecated; pass pose=Pose(...)",
        "dh_robot_report: reach_time_limit= is deprecated; pass stop=StopAt(time_limit=...)"]
    _, _, _, new = _reach_report(scara, tmp_path / "new", reach_delta=0.25, stop=StopAt(time_limit=30),
                                 pose=Pose(rpy=(180, 0, 0)))
    assert old == new == {"delta": 0.25, "stop": StopAt(time_limit=30), "run": RunOn(progress=False),
                          "pose": Pose(rpy=(180, 0, 0))}


def test_dh_report(dh):
    md_path, doc = dh
    md = md_path.read_text()
    assert md_path.name == "report.md"                          # one naming scheme for every report
    assert "a_{1} + a_{2} c_{2} + a_{3} c_{23} + d_{5} s_{234}" in md and "Rank is lost" in md
    html = (md_path.parent / "report.html").read_text()
    check_html(html, figures=1)
    assert "<code>" not in html and html.count("<math") > 20
    assert latex_is_balanced((md_path.parent / "report.tex").read_text())
    # limits in degrees as the catalog gives them (glass-handling joint 1: -160 .. 160 deg), the Jacobian 6 x n
    table = next(b for b in doc.blocks if b[0] == "table")
    assert table[2][0][-1] == "[-160°, 160°]" and str(table[2][0][5]) == "90*°"
    J = next(e for b in doc.blocks if b[0] == "eqs" for lhs, e in b[1] if str(lhs) == "J")
    assert J.shape == (6, 6) and str(J[0, 0]) == "-s1*(a1 + a2*c2 + a3*c23 + d5*s234)"   # column 1: joint 1


def test_dh_report_from_a_file(tmp_path):
    """`workspace-sym report --dh FILE` writes the DH report of the README's example file."""
    from workspace_sym.cli import main

    dh_file = tmp_path / "arm$1_%~.json"          # the name goes into the title: escaped, not read as TeX
    dh_file.write_text('{"convention": "standard", "angles": "degrees", "parameters": {"l1": 0.5}, "joints": ['
                       '{"type": "R", "d": 0, "a": "l1", "alpha": 0, "limits": [-90, 90]}, '
                       '{"type": "P", "theta": 0, "a": 0, "alpha": 0, "limits": [0, 0.2]}]}')
    assert main(["report", "--dh", str(dh_file), "--out", str(tmp_path / "out")]) == 0
    md = (tmp_path / "out" / "report.md").read_text()
    assert "[-90°, 90°]" in md and "p_{x} = c_{1} l_{1}" in md
    tex = (tmp_path / "out" / "report.tex").read_text()
    assert "arm\\$1\\_\\%\\textasciitilde{}: symbolic kinematics" in tex
    assert "arm$1_%~: symbolic kinematics</h1>" in (tmp_path / "out" / "report.html").read_text()
    if shutil.which("pdflatex"):
        assert_compiles(tmp_path / "out" / "report.tex")
    assert main(["report", "glass-handling", "--dh", str(dh_file), "--out", str(tmp_path / "no")]) == 2
    assert not (tmp_path / "no").exists()


# ---------------------------------------------------------------------- a real browser and a real TeX
def test_html_report_renders_in_chromium(planar, dh, reach2d, reach3d):
    """Headless Chromium loads each HTML report: every figure decodes (naturalWidth > 0) and every MathML
    element is laid out with a non-zero size."""
    require_tool("chromium", "chromedriver")

    driver = headless_chromium()
    try:
        for md_path, figures in ((planar[0], 4), (dh[0], 1), (reach2d[0], 2), (reach3d[0], 3)):
            driver.get(md_path.with_suffix(".html").as_uri())
            widths = driver.execute_script("return [...document.images].map(i => i.complete ? i.naturalWidth : 0)")
            assert len(widths) == figures and all(w > 0 for w in widths)
            sizes = driver.execute_script("return [...document.getElementsByTagName('math')].map(m => {"
                                          "const r = m.getBoundingClientRect(); return [r.width, r.height]; })")
            assert len(sizes) > 10 and all(w > 0 and h > 0 for w, h in sizes)
            # laid out as mathematics, not as a line of plain text: a 6 x n or 4 x 4 matrix is several lines tall
            assert max(h for _, h in sizes) > 60
    finally:
        driver.quit()


def test_dh_report_of_a_decimal_table(tmp_path):
    """UR5 (roboticstoolbox's DH table, decimal lengths): lengths and formulas show the table's decimals, and a
    Jacobian column too wide for the page is set entry by entry, so pdflatex finds no overfull box."""
    from workspace_sym.cli import main

    table = DATA / "dh" / "ur5.json"
    assert main(["report", "--dh", str(table), "--out", str(tmp_path / "out")]) == 0
    tex = (tmp_path / "out" / "report.tex").read_text()
    assert "0.39225 c_{23}" in tex and "/20000" not in tex and "{20000}" not in tex
    assert "J_{1,1} &=" in tex
    if shutil.which("pdflatex"):
        assert_compiles(tmp_path / "out" / "report.tex")


def test_latex_report_compiles(planar, dh, reach2d, reach3d):
    """pdflatex compiles each LaTeX report with no error, no undefined control sequence and no overfull box
    wider than 10 pt (the closed-form table and the long formulas stay on the page; m² and m³ are set)."""
    require_tool("pdflatex")
    for md_path in (planar[0], dh[0], reach2d[0], reach3d[0]):
        assert_compiles(md_path.with_suffix(".tex"))


def test_paving_report(tmp_path):
    model = robots.build("rpr2")
    paving = pave(model.constraints, model.box, delta=0.25).with_exact_measure(model.exact_measure)
    md = paving_report(paving, tmp_path / "p").read_text()
    assert "| inner |" in md and "Exact measure 35.053350" in md
    check_html((tmp_path / "p" / "report.html").read_text(), figures=1)
    assert latex_is_balanced((tmp_path / "p" / "report.tex").read_text())
    if shutil.which("pdflatex"):
        assert_compiles(tmp_path / "p" / "report.tex")


def test_latex_escaping():
    assert tex_escape(r"a_b 50% $x_1$ {c} \ d") == r"a\_b 50\% $x_1$ \{c\} \textbackslash{} d"
    assert tex_escape("--var 'x=$HOME' ~a^b", math=False) == r"--var 'x=\$HOME' \textasciitilde{}a\textasciicircum{}b"
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
    if shutil.which("pdflatex"):                   # compiled here too when TeX is present (required: see above)
        assert_compiles(tmp_path / "o" / "report.tex")


def test_paving_section_names_a_pappus_bracket(tmp_path):
    """A paving with a second proved bracket (a turned section's, by Pappus): the printed bracket is the
    intersection (the one measure_bounds gives) and the text gives the boxes' own bracket and says why."""
    from workspace_sym.report import Document, _paving_section
    from workspace_sym.serial import ReachResult

    ball = pave(["x**2 + y**2 + z**2 - 1 <= 0"], {"x": (-1.5, 1.5), "y": (-1.5, 1.5), "z": (-1.5, 1.5)}, delta=0.8)
    b_lo, b_hi = ball.measure_bounds
    paving = ReachResult(ball, "critical", volume_bounds=(b_lo + 0.5, b_hi - 0.5))
    doc = Document("t")
    _paving_section(doc, paving, tmp_path, units="m")
    text = " ".join(b[1] for b in doc.blocks if b[0] == "p")
    lo, hi = map(float, re.search(r"the volume lies in \[([-\d.]+), ([-\d.]+)\] m³ ", text).groups())
    assert lo <= b_lo + 0.5 < lo + 1e-6 and hi - 1e-6 < b_hi - 0.5 <= hi
    assert "solid of revolution" in text and "the boxes' alone" in text
