"""Closed-form reports (Markdown with figures, LaTeX).

Reports are written to a temporary directory first and moved into place only
when complete, so a failure never leaves a half-written report.
"""

from __future__ import annotations

import datetime as _dt
import platform
import shutil
import sys
import tempfile
from pathlib import Path

import sympy as sp

__all__ = ["dh_robot_report", "reproducibility"]


def reproducibility(command: str | None = None) -> dict:
    """Versions, date and command that produced a result."""
    import matplotlib
    import mpmath
    import numpy

    from . import __version__

    return {
        "workspace_sym": __version__,
        "python": platform.python_version(),
        "sympy": sp.__version__,
        "numpy": numpy.__version__,
        "mpmath": mpmath.__version__,
        "matplotlib": matplotlib.__version__,
        "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "command": command if command is not None else " ".join(["workspace-sym"] + sys.argv[1:]),
    }


def _finalise(tmp: Path, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    for item in tmp.iterdir():
        target = out / item.name
        if target.exists():
            if target.is_dir():
                shutil.rmtree(target)
            else:
                target.unlink()
        shutil.move(str(item), str(target))


def dh_robot_report(robot, out, *, samples: int = 20000) -> Path:
    """Markdown + LaTeX report of a DH robot: FK, Jacobian, singular factors, a workspace picture.

    Returns the path of the Markdown file.
    """
    from .plotting import save_figure, scatter_workspace_3d
    from .sampling import reach_points, sample_joint_box

    out = Path(out)
    T = robot.fk()
    J = robot.geometric_jacobian
    singular = robot.singular_factors("geometric")
    pts = reach_points(robot, sample_joint_box(robot, samples, seed=1))
    stem = robot.name
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        save_figure(scatter_workspace_3d(pts, title=f"{robot.name}: {samples} sampled configurations",
                                         units=robot.units), tmp / f"{stem}-workspace.png")
        lines = [f"# {robot.name}: symbolic kinematics", ""]
        lines += ["Shorthand: `c1 = cos(theta1)`, `s23 = sin(theta2 + theta3)`.", ""]
        lines += ["## DH table", "", "| i | type | theta | d | a | alpha | limits |", "|---|---|---|---|---|---|---|"]
        for k, j in enumerate(robot.joints, 1):
            lim = "free" if j.limits is None else f"[{j.limits[0]}, {j.limits[1]}]"
            lines.append(f"| {k} | {j.kind} | {j.theta} | {j.d} | {j.a} | {j.alpha} | {lim} |")
        lines += ["", f"## Forward kinematics T_0^{robot.n}", ""]
        for name, e in zip("xyz", robot.position):
            lines.append(f"- `{name} = {robot.to_str(e)}`")
        lines += ["", "Rotation:", ""]
        for i in range(3):
            lines.append("- `" + " | ".join(robot.to_str(T[i, j]) for j in range(3)) + "`")
        lines += ["", f"$$T_0^{{{robot.n}}} = {robot.to_latex(T)}$$", "", "## Geometric Jacobian", ""]
        for k in range(J.cols):
            lines.append(f"- column {k + 1}: `" + " | ".join(robot.to_str(J[i, k]) for i in range(J.rows)) + "`")
        shown = " * ".join(robot.to_str(f) for f in singular) if singular else "no hypersurface of rank loss"
        lines += ["", f"Singular where `{shown} = 0`.", "", "## Workspace (sampled picture, not a proof)", "",
                  f"![workspace]({stem}-workspace.png)", "", "## Reproducibility", ""]
        lines += [f"- {k}: {v}" for k, v in reproducibility().items()]
        (tmp / f"{stem}.md").write_text("\n".join(lines) + "\n")
        (tmp / f"{stem}.tex").write_text(
            "\\documentclass{article}\n\\usepackage{amsmath}\n\\usepackage[landscape,margin=1cm]{geometry}\n"
            "\\begin{document}\n\\tiny\n"
            f"\\section*{{{robot.name}}}\n\\[ T_0^{{{robot.n}}} = {robot.to_latex(T)} \\]\n"
            f"\\[ J = {robot.to_latex(J)} \\]\n\\end{{document}}\n")
        _finalise(tmp, out)
    return out / f"{stem}.md"
