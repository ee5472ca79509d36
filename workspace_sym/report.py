"""Closed-form reports: Markdown with image files, one self-contained HTML file, LaTeX.

A report is built once as a list of blocks (:class:`~workspace_sym.document.Document`, re-exported here) and rendered
to the three formats, so they always say the same thing.  Exact expressions are
LaTeX in Markdown and LaTeX, and MathML in HTML (read by every current browser
without a network connection).  Reports are written to a temporary directory
first and moved into place only when complete, so a failure never leaves a
half-written report.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import math
import platform
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import sympy as sp

from .document import Document, Equations, tex_escape
from .errors import InvalidParameterError, SymbolicBudgetError
from .files import publish_dir
from .interval.boxes import check_delta
from .interval.driver import RunOn, StopAt, deprecated
from .numbers import fmt, fmt_bound, fmt_bracket, md_escape, measure_text
from .serial.api import Pose

__all__ = ["Document", "dh_robot_report", "orthoglide_report", "paving_report", "planar_report", "reproducibility",
           "tex_escape", "md_escape", "number", "DEGREE", "Equations"]


def reproducibility(command: str | None = None) -> dict:
    """Versions, date and command that produced a result.

    Parameters
    ----------
    command : str or None, optional
        The command to record; by default ``workspace-sym`` followed by this process's arguments.

    Returns
    -------
    dict
        ``workspace_sym``, ``python``, ``sympy``, ``numpy``, ``mpmath`` and ``matplotlib`` versions, ``date``
        (UTC, to the minute) and ``command``, all strings.
    """
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


def number(value, spec: str = ".6f") -> str:
    """``value`` formatted with ``spec`` (``".6f"``, ``".1f"``, ``"g"``), never as a negative zero.

    The one place where reports format numbers, through :func:`workspace_sym.numbers.fmt`.

    Parameters
    ----------
    value : float
        The number.
    spec : str, default ".6f"
        ``[.digits]type`` with type ``f``, ``g``, ``e`` or ``%``; 6 digits when none are given.

    Returns
    -------
    str
        The formatted number.

    Raises
    ------
    ValueError
        When ``spec`` is not of that form.

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


def _reach_not_started(doc: Document, time_limit: float | None) -> None:
    """The certified-workspace section of a run whose time limit passed while the model was being prepared."""
    doc.heading("Certified workspace (proved boxes)")
    limit = "the time limit" if time_limit is None else f"the time limit of {time_limit:g} s"
    doc.para(f"Not computed: {limit} (stop.time_limit) passed while the symbolic model "
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


def _report_legacy(legacy: dict, stop: StopAt, pose: Pose | None) -> tuple[StopAt, Pose | None]:
    """``(stop, pose)`` with the keywords of earlier releases of :func:`dh_robot_report` folded in, each with a
    :class:`DeprecationWarning` naming its new spelling; an unknown keyword is a ``TypeError`` as Python's."""
    unknown = sorted(set(legacy) - {"reach_time_limit", "reach_constraint"})
    if unknown:
        raise TypeError(f"dh_robot_report() got an unexpected keyword argument {unknown[0]!r}")
    if "reach_time_limit" in legacy:
        deprecated("dh_robot_report", "reach_time_limit", "stop=StopAt(time_limit=...)", stacklevel=4)
        check_delta(legacy["reach_time_limit"], "reach_time_limit")
        stop = dataclasses.replace(stop, time_limit=legacy["reach_time_limit"])
    if "reach_constraint" in legacy:
        deprecated("dh_robot_report", "reach_constraint", "pose=Pose(...)", stacklevel=4)
        if legacy["reach_constraint"]:
            pose = Pose(**legacy["reach_constraint"])
    return stop, pose


def dh_robot_report(robot, out, *, samples: int = 20000, command: str | None = None,
                    reach_delta: float | None = None, stop: StopAt = StopAt(time_limit=60.0),
                    run: RunOn = RunOn(progress=False), pose: Pose | None = None, **legacy) -> Path:
    """Report of a DH robot: DH table (angles in degrees), forward kinematics, the 6 x n geometric Jacobian and
    its singular factors in textbook form, a sampled workspace picture (Markdown, HTML, LaTeX; ``out/report.md``
    and siblings).  Returns the path of the Markdown file.

    With ``reach_delta`` a section "Certified workspace (proved boxes)" adds
    ``robot.reach(delta=reach_delta, stop=stop, run=run, pose=pose)``: box counts
    and measures, the certified bracket of the area (planar robot) or volume,
    whether the run completed, the boxes (3D: also three slices in z).
    A ``pose`` makes it the certified orientation workspace under that tool
    constraint, with the constraint stated.  A symbolic stage of ``reach``
    that does not finish within the time limit leaves a note in that section
    instead.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    out : str or os.PathLike
        The directory of the report, created if needed; files of the same names in it are replaced.
    samples : int, default 20000
        Random configurations of the sampled picture (seed 1).
    command : str or None, optional
        The command line recorded in the Reproducibility section; by default this process's arguments.
    reach_delta : float or None, optional
        The ``delta`` of the certified section; None (default) leaves the section out.
    stop : StopAt, default StopAt(time_limit=60.0)
        When ``reach`` stops (its ``stop``).
    run : RunOn, default RunOn(progress=False)
        Where and how ``reach`` runs (its ``run``); no progress bar by default.
    pose : Pose or None, optional
        A tool constraint (:class:`~workspace_sym.serial.api.Pose`), as above.
    **legacy
        The keywords of earlier releases, each with a :class:`DeprecationWarning` naming its new spelling:
        ``reach_time_limit=T`` (``stop=StopAt(time_limit=T)``) and ``reach_constraint={...}``
        (``pose=Pose(...)``).  Any other keyword is a ``TypeError``.

    Returns
    -------
    pathlib.Path
        ``out / "report.md"``; ``report.html``, ``report.tex`` and the figures are beside it.

    Raises
    ------
    InvalidParameterError
        When ``reach_delta`` or the time limit is not a positive finite number, ``stop``, ``run`` or ``pose`` is
        not of its type, or ``pose`` is not a valid constraint (checked before the symbolic work).
    OutputError
        When ``out`` cannot be written.
    """
    from .plotting import save_figure, scatter_workspace_3d
    from .sampling import reach_points, sample_joint_box

    stop, pose = _report_legacy(legacy, stop, pose)
    constraint = None
    if reach_delta is not None:                  # checked before the long symbolic work
        check_delta(reach_delta, "reach_delta")
        for value, name, kind in ((stop, "stop", StopAt), (run, "run", RunOn), (pose, "pose", Pose)):
            if not isinstance(value, kind) and not (name == "pose" and value is None):
                raise InvalidParameterError(f"{name} must be a {kind.__name__}; got {type(value).__name__}",
                                            parameter=name)
        if pose is not None:
            from .serial.pose import constraint_from

            constraint = constraint_from(pose.approach, pose.cone, pose.every, pose.orientation, pose.rpy)
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
    names = sp.Matrix(4, 4, lambda i, j: sp.Symbol(f"r_{i + 1}{j + 1}") if i < 3 and j < 3 else
                      (sp.Symbol("p_" + "xyz"[i]) if i < 3 else sp.Integer(int(j == 3))))
    placement = robot.placement()
    if placement:                                 # T = base · T_0^n · tool: each factor shown, T rebuilt from them
        doc.heading(f"Forward kinematics T = {robot.fk_name()}")
        parts = " and ".join(f"the constant {w} transform" for w in placement)
        doc.para(f"T = {robot.fk_name()}: the pose of the tool frame in the world frame is the product of "
                 f"{parts} with the DH table's T_0^{robot.n} = A_1 ... A_{robot.n} (A_i from row i of the table "
                 "above), in that order:")
        doc.equations([(name, robot.shorthand(M)) for name, M in placement.items()])
        doc.para("Multiplied out:")
        doc.math(sp.Symbol("T"), names)
    else:
        doc.heading(f"Forward kinematics T_0^{robot.n}")
        doc.para(f"T_0^{robot.n} = A_1 ... A_{robot.n}, each A_i from row i of the table above (no base or tool "
                 "transform):")
        doc.math(sp.Symbol(f"T_0^{robot.n}"), names)
    doc.equations([(names[i, j], T[i, j]) for j in range(4) for i in range(3)])
    doc.heading("Geometric Jacobian")
    doc.para(f"J is {J.rows} x {J.cols}: rows 1-3 the linear velocity, rows 4-6 the angular velocity, "
             "column k the contribution of joint k.")
    doc.math(sp.Symbol("J"), J)
    if singular:
        doc.para("Rank is lost where one of these factors vanishes:")
        doc.equations([(sp.Symbol(f"f_{k}"), robot.shorthand(robot.in_lengths(f))) for k, f in enumerate(singular, 1)])
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
                paving = robot.reach(delta=reach_delta, stop=stop, run=run, **({} if pose is None else {"pose": pose}))
            except SymbolicBudgetError as error:
                if error.parameter != "time_limit":
                    raise
                _reach_not_started(doc, stop.time_limit)
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

    Parameters
    ----------
    chain : PlanarChain
        The chain; its boundary is computed (or reused) with the default options.
    out : str or os.PathLike
        The directory of the report, created if needed; files of the same names in it are replaced.
    command : str or None, optional
        The command line recorded in the Reproducibility section; by default this process's arguments.
    title : str or None, optional
        The report's title; by default "Workspace boundary of a planar p-joint chain".
    exact : bool, default True
        Whether to add the closed forms of the arcs and of the area.
    paving : Paving, optional
        A certified paving of the same workspace to summarise.
    paving_title : str or None, optional
        The heading of that section; by default "Certified paving".

    Returns
    -------
    pathlib.Path
        ``out / "report.md"``; ``report.html``, ``report.tex`` and the figures are beside it.

    Raises
    ------
    BoundaryError
        When the chain's boundary cannot be computed reliably.
    OutputError
        When ``out`` cannot be written.
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
    """Report of a certified paving: box counts, the measure bracket, a picture, reproducibility.

    Parameters
    ----------
    paving : Paving
        The paving (2D or 3D for the pictures).
    out : str or os.PathLike
        The directory of the report, created if needed; files of the same names in it are replaced.
    title : str, default "Certified paving"
        The report's title.
    command : str or None, optional
        The command line recorded in the Reproducibility section; by default this process's arguments.

    Returns
    -------
    pathlib.Path
        ``out / "report.md"``; ``report.html``, ``report.tex`` and the figures are beside it.

    Raises
    ------
    OutputError
        When ``out`` cannot be written.
    """
    doc = Document(title)
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        _paving_section(doc, paving, tmp)
        return _publish(doc, tmp, Path(out), command=command)


def orthoglide_report(model, out, *, eps: float = 0.125, alpha: float = 0.01, command: str | None = None) -> Path:
    """Report of the Orthoglide: J, the pencil polynomial, the certified dextrous volume and the largest cube.

    Parameters
    ----------
    model : Orthoglide
        The model.
    out : str or os.PathLike
        The directory of the report, created if needed; files of the same names in it are replaced.
    eps : float, default 0.125
        The ``eps`` of the dextrous workspace (:meth:`Orthoglide.dextrous
        <workspace_sym.orthoglide.model.Orthoglide.dextrous>`).
    alpha : float, default 0.01
        The ``alpha`` of the largest cube (:meth:`Orthoglide.largest_cube
        <workspace_sym.orthoglide.model.Orthoglide.largest_cube>`).
    command : str or None, optional
        The command line recorded in the Reproducibility section; by default this process's arguments.

    Returns
    -------
    pathlib.Path
        ``out / "report.md"``; ``report.html``, ``report.tex`` and the figures are beside it.

    Raises
    ------
    InvalidParameterError
        When ``eps`` or ``alpha`` is not a positive finite number.
    OutputError
        When ``out`` cannot be written.
    """
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
