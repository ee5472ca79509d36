"""Every printed or serialised certified bound is rounded outward (issue 23 item 5).

Reference: the certified numbers themselves.  A lower bound printed with six
significant digits must not exceed the proved one, an upper bound must not be
below it; rounding to nearest broke this (the disk paving below has the upper
bound 3.42203125, which ``:.6g`` printed as 3.42203).  Each test reads the text
a user sees (repr, Jupyter HTML, Markdown, LaTeX, plot titles, the command line,
verification and grading messages) and checks every bracket and bound in it.
"""

from __future__ import annotations

import re
from decimal import Decimal

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import workspace_sym as ws
from workspace_sym import RunOn, cli
from workspace_sym.display import to_html
from workspace_sym.numbers import fmt_bound, fmt_bracket
from workspace_sym.orthoglide.certificate import DextrousResult
from workspace_sym.orthoglide.cube import CubeResult

_NUMBER = r"-?\d+(?:\.\d*)?(?:e[-+]?\d+)?"
_BRACKET = re.compile(rf"\[\s*({_NUMBER})\s*,\s*({_NUMBER})\s*\]")

DISK = (["x**2 + y**2 <= 1"], {"x": (-1.1, 1.1), "y": (-1.1, 1.1)})


def brackets(text: str) -> list[tuple[Decimal, Decimal]]:
    return [(Decimal(a), Decimal(b)) for a, b in _BRACKET.findall(text)]


def assert_holds(text: str, lo: float, hi: float) -> None:
    """``text`` prints the certified bracket ``[lo, hi]`` at least once, and every printing of it holds it."""
    near = [(a, b) for a, b in brackets(text) if abs(float(a) - lo) <= 1e-3 * (1 + abs(lo))]
    assert near, f"no bracket near [{lo!r}, {hi!r}] in {text!r}"
    for a, b in near:
        assert a <= Decimal(lo) and b >= Decimal(hi), f"printed [{a}, {b}] cuts the certified [{lo!r}, {hi!r}]"


@pytest.fixture(scope="module")
def disk():
    paving = ws.pave(*DISK, delta=0.1)
    lo, hi = paving.measure_bounds
    # The case that failed before: six significant digits to nearest print 3.42203 < hi
    assert float(f"{hi:.6g}") < hi
    return paving


@settings(derandomize=True, max_examples=300, deadline=None)
@given(st.floats(-1e12, 1e12, allow_nan=False), st.floats(0, 1e6, allow_nan=False),
       st.integers(1, 12), st.sampled_from(["f", "g"]))
@example(34.06668091, 1.98330688, 6, "g")       # the repr of the issue: [34.0667, 36.05] cut the lower bound
@example(9.9999999, 0.0, 3, "g")                # rounding up gains a digit
@example(-1e-300, 2e-300, 4, "f")               # tiny bounds around zero
def test_fmt_bracket_holds_the_bracket(lo, width, digits, spec):
    """Property over random brackets, checked in exact decimal arithmetic."""
    hi = lo + width
    (a, b), = brackets(fmt_bracket(lo, hi, digits, spec))
    assert a <= Decimal(lo) and b >= Decimal(hi)
    # ... and no looser than one unit of the last printed digit on each side
    unit = Decimal(10) ** -digits if spec == "f" else None
    if unit is not None:
        assert Decimal(lo) - a <= unit and b - Decimal(hi) <= unit     # (Decimal subtraction rounds to 28 digits)


def test_fmt_bound_directions():
    assert fmt_bound(1 / 3, 4, up=False) == "0.3333" and fmt_bound(1 / 3, 4, up=True) == "0.3334"
    assert fmt_bound(-1 / 3, 4, "g", up=False) == "-0.3334" and fmt_bound(-1 / 3, 4, "g", up=True) == "-0.3333"
    assert fmt_bound(2.0, 3, "g", up=True) == "2" and fmt_bound(-1e-9, 2, up=True) == "0.00"


def test_paving_repr_html_and_plot_title(disk):
    lo, hi = disk.measure_bounds
    assert_holds(repr(disk), lo, hi)
    assert_holds(to_html(disk), lo, hi)
    from workspace_sym.plotting import plot_paving

    assert_holds(plot_paving(disk).axes[0].get_title(), lo, hi)


def test_stored_paving_repr(tmp_path):
    paving = ws.pave(*DISK, delta=0.1, run=RunOn(store=tmp_path / "boxes"))
    lo, hi = paving.measure_bounds
    assert type(paving).__name__ == "StoredPaving"
    assert_holds(repr(paving), lo, hi)


def test_paving_report_and_cli_text(disk, tmp_path, capsys):
    lo, hi = disk.measure_bounds
    out = ws.report.paving_report(disk, tmp_path / "report").parent
    for name in ("report.md", "report.html", "report.tex"):
        assert_holds((out / name).read_text(), lo, hi)
    code = cli.main(["pave", "--constraint", DISK[0][0], "--var", "x=-1.1:1.1", "--var", "y=-1.1:1.1",
                     "--delta", "0.1"])
    assert code == 0
    assert_holds(capsys.readouterr().out, lo, hi)


def test_verify_and_grading_messages(disk):
    lo, hi = disk.measure_bounds
    for claimed in (3.1, 10.0):
        assert_holds(ws.verify.check_measure(claimed, disk).message, lo, hi)
    from workspace_sym.teaching.grading import Question, _grade_measure

    question = Question("q", "measure", [lo, hi], rel_tol=0.01)
    for text in ("3.1", "10"):
        assert_holds(_grade_measure(text, question).message, lo, hi)


def test_orthoglide_results_round_outward(capsys):
    """Dextrous volume: inside is a lower bound (down), E an upper one (up); the cube: edge_lower down, upper up."""
    ball = ws.pave(["x**2 + y**2 + z**2 <= 1"], {"x": (-1.1, 1.1), "y": (-1.1, 1.1), "z": (-1.1, 1.1)}, delta=0.3)
    dextrous = DextrousResult(ball, (0.5, 2.0), 0.3)
    inner, undecided = dextrous.volume_inner, dextrous.volume_undecided
    for text in (repr(dextrous), to_html(dextrous)):
        numbers = [Decimal(v) for v in re.findall(_NUMBER, text)]
        assert any(v <= Decimal(inner) and Decimal(inner) - v < Decimal("1e-5") for v in numbers)
        assert not any(Decimal(inner) < v < Decimal(inner) + Decimal("1e-5") for v in numbers)
        assert any(v >= Decimal(undecided) and v - Decimal(undecided) < Decimal("1e-5") for v in numbers)
    cube = CubeResult(center=(0.1, 0.1, 0.1), edge_lower=0.64395049999, edge_upper=0.6439521111111,
                      alpha=0.001, sigma=(0.5, 2.0), seconds=1.0, boxes={})
    assert_holds(repr(cube), cube.edge_lower, cube.edge_upper)
    assert_holds(cube._repr_latex_(), cube.edge_lower, cube.edge_upper)
    markdown = cube._repr_markdown_()
    assert "0.643950499 centred" in markdown and "above 0.643952112" in markdown
    cli._print_cube(cube.to_dict(), cube.alpha)
    out = capsys.readouterr().out
    assert "edge 0.643950499 there" in out and "above 0.643952112 fits" in out


def test_cube_html_rounds_outward_and_typesets_in_mathml():
    cube = CubeResult(center=(0.1, 0.1, 0.1), edge_lower=0.64395049999, edge_upper=0.6439521111111,
                      alpha=0.001, sigma=(0.5, 2.0), seconds=1.0, boxes={})
    page = to_html(cube)
    assert "edge 0.643950499 centred" in page and "above 0.643952112 fits" in page
