"""The ``workspace-sym`` command line (``docs/cli.md`` is the contract).

Every computing subcommand accepts ``--json``: stdout then holds exactly one JSON
object, progress and warnings go to stderr.  Bad input exits with status 2 and
one line on stderr; nothing is written to output paths in that case.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

from .errors import InvalidParameterError, SymbolicBudgetError, WorkspaceError
from .numbers import clean_json, fmt, fmt_bound, fmt_bracket, measure_text
from .version import __version__

if TYPE_CHECKING:
    from .kinematics import DHRobot

# The command line builds its parser and answers --help without SymPy or an engine (each command imports what
# it uses): `workspace-sym --help` starts in a fraction of a second.
SNAP_TOL = 1e-9                 # the default of --snap-tol: workspace_sym.snap.DEFAULT_TOL (test_cli checks it)

__all__ = ["main", "build_parser"]


# Options taking comma-separated lists whose first value may be negative (``--lower -60,0,-10``).
_LIST_OPTIONS = ("--lengths", "--lower", "--upper")


def _join_list_values(argv: list[str]) -> list[str]:
    """``--lower -60,0,-10`` as ``--lower=-60,0,-10``: argparse takes a value starting with '-' (other than a
    plain negative number) for an option name and refuses it."""
    out, k = [], 0
    while k < len(argv):
        token = argv[k]
        nxt = argv[k + 1] if k + 1 < len(argv) else None
        if token in _LIST_OPTIONS and nxt is not None and nxt.startswith("-") and not nxt.startswith("--") \
                and nxt != "-h":
            out.append(f"{token}={nxt}")
            k += 2
            continue
        out.append(token)
        k += 1
    return out


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error and exit status 2, like every other bad input."""

    commands: dict[str, _Parser]                     # the subcommands' parsers (build_parser)

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")

    def parse_known_args(self, args=None, namespace=None):
        args = sys.argv[1:] if args is None else list(args)
        return super().parse_known_args(_join_list_values(args), namespace)


def _emit_json(obj) -> None:
    sys.stdout.write(json.dumps(clean_json(obj), indent=2) + "\n")


def _wrote(*paths) -> None:
    """Name the files a command wrote, on stderr (stdout stays for the result, or the JSON object)."""
    print(f"workspace-sym: wrote {', '.join(str(p) for p in paths)}", file=sys.stderr)


def _wrote_report(path) -> None:
    """Name the files of a report directory (the report itself first, then its figures)."""
    path = Path(path)
    files = sorted((f for f in path.parent.iterdir() if f.is_file()),
                   key=lambda f: (f != path, f.suffix == ".png", f.name))
    _wrote(*files)


def _robot_from_args(args) -> DHRobot:
    from . import robots
    from .kinematics import DHRobot
    from .snap import summary

    catalog = getattr(args, "robot", None)
    given = [f"catalog robot {catalog!r}" if catalog is not None else None,
             "--dh FILE" if args.dh is not None else None, "--urdf FILE" if args.urdf is not None else None,
             "--mjcf FILE" if args.mjcf is not None else None]
    given = [g for g in given if g]
    if len(given) > 1:
        raise WorkspaceError(f"give one of a catalog robot, --dh FILE, --urdf FILE or --mjcf FILE; got "
                             f"{' and '.join(g for g in given if g)}")
    if (args.base or args.tip) and args.urdf is None and args.mjcf is None:
        raise WorkspaceError("--base and --tip name links of a URDF file or bodies of an MJCF file: give --urdf FILE "
                             "or --mjcf FILE")
    if args.package and args.urdf is None:
        raise WorkspaceError("--package names the directory of a package of a xacro file: give --urdf FILE")
    if args.xacro_arg and args.urdf is None:
        raise WorkspaceError("--xacro-arg names an argument of a xacro file: give --urdf FILE")
    if args.dh is not None or args.urdf is not None or args.mjcf is not None:
        exact = not args.keep_floats
        robot = (DHRobot.from_file(args.dh, exact=exact, tol=args.snap_tol) if args.dh is not None else
                 DHRobot.from_mjcf(args.mjcf, base_link=args.base, tip_link=args.tip, exact=exact, tol=args.snap_tol)
                 if args.mjcf is not None else
                 DHRobot.from_urdf(args.urdf, base_link=args.base, tip_link=args.tip, exact=exact, tol=args.snap_tol,
                                   packages=_pairs(args.package, "packages", "PKG=DIR (a package of "
                                                   "the xacro file and its directory)"),
                                   xacro_args=_pairs(args.xacro_arg, "xacro_args", "NAME=VALUE (an "
                                                     "argument of the xacro file and its value)", empty=True)))
        line = summary(robot.input_notes)
        if line:
            print(f"workspace-sym {args.command}: note: {line}", file=sys.stderr)
        return robot
    if catalog is None:
        raise WorkspaceError("robot: name a catalog robot (see 'workspace-sym robots') or pass --dh FILE or "
                             "--urdf FILE")
    model = robots.build(catalog)
    if not isinstance(model, DHRobot):
        raise WorkspaceError(f"robot {catalog!r} is not a serial DH robot; this command needs one")
    return model


# The options naming a robot file; a library error about its ``path`` is about the option given.
_ROBOT_FILES = ("dh", "urdf", "mjcf")


def _pairs(values, parameter: str, expected: str, *, empty: bool = False) -> dict:
    """Repeated ``option NAME=VALUE`` options (``--package PKG=DIR``, ``--xacro-arg NAME=VALUE``) as a dict;
    ``empty``: a value may be empty (a xacro argument, as ``name:=`` gives)."""
    out = {}
    for text in values or ():
        name, sep, value = text.partition("=")
        if not sep or not name.strip() or not (value.strip() or empty):
            # named as the library names it (parameter): the error line puts the option in its place
            raise InvalidParameterError(f"{parameter}: expected {expected}; got {text!r:.80}", parameter=parameter)
        out[name.strip()] = value.strip()
    return out


def _report_summary(path, start: float, **extra) -> dict:
    """The JSON of a command that wrote a report: its Markdown file, the three renderings, the figures."""
    path = Path(path)
    return {"report": str(path), **extra,
            "files": {kind: str(path.with_suffix(suffix)) for kind, suffix in
                      (("markdown", ".md"), ("html", ".html"), ("latex", ".tex"))},
            "figures": sorted(str(f) for f in path.parent.glob("*.png")),
            "seconds": time.perf_counter() - start}


def _matrix_strings(M) -> list:
    from .symbolic import canonical_sstr  # sympy.sstr's strings, each sum ordered once (long entries)

    return [[canonical_sstr(M[i, j]) for j in range(M.cols)] for i in range(M.rows)]


# ------------------------------------------------------------------------------ subcommands
def cmd_robots(args) -> int:
    from . import robots

    entries = robots.catalog()
    if args.json:
        _emit_json({"robots": [
            {"name": e.name, "kind": e.kind, "source": e.source, "units": e.units, "summary": e.summary,
             "parameters": {k: v for k, v in e.parameters.items()}, "limits": e.limits}
            for e in entries]})
        return 0
    width = max(len(e.name) for e in entries)
    for e in entries:
        print(f"{e.name:<{width}}  {e.kind}")
        print(f"{'':<{width}}  {e.summary}")
        print(f"{'':<{width}}  source: {e.source}")
        if e.parameters:
            params = ", ".join(f"{k} = {v}" for k, v in e.parameters.items())
            print(f"{'':<{width}}  parameters ({e.units}): {params}")
        if e.limits:
            print(f"{'':<{width}}  limits: {e.limits}")
    return 0


def cmd_fk(args) -> int:
    import sympy as sp

    robot = _robot_from_args(args)
    start = time.perf_counter()
    T = robot.fk()
    placement = robot.placement()          # base and tool, when not the identity: T = base · T_0^n · tool
    chain = robot.transforms[-1]           # T_0^n of the DH table alone
    seconds = time.perf_counter() - start
    if args.json:
        # "T" is what fk() gives (base and tool included); "base", "tool" (null when absent or the identity) and
        # "dh_product" (T_0^n of the table alone) let a reader rebuild it: T = base · dh_product · tool
        _emit_json({
            "robot": robot.name,
            "T": _matrix_strings(T),
            "position": [sp.sstr(e) for e in robot.position],
            "T_is": "T = " + robot.fk_name(),
            "base": _matrix_strings(placement["base"]) if "base" in placement else None,
            "tool": _matrix_strings(placement["tool"]) if "tool" in placement else None,
            "dh_product": _matrix_strings(chain),
            "textbook": {"T": [[robot.to_str(T[i, j]) for j in range(4)] for i in range(4)],
                         "position": [robot.to_str(e) for e in robot.position],
                         **{k: [[robot.to_str(M[i, j]) for j in range(4)] for i in range(4)]
                            for k, M in placement.items()}},
            "latex": {"T": robot.to_latex(T), "position": [robot.to_latex(e) for e in robot.position],
                      **{k: robot.to_latex(M) for k, M in placement.items()}},
            "seconds": seconds,
        })
        return 0
    if args.latex:
        for name, M in placement.items():
            print(rf"\mathrm{{{name}}} = {robot.to_latex(M)}")
        if placement:
            print(rf"T_0^{{{robot.n}}} = {robot.to_latex(chain)}")
            print(rf"T = {robot.fk_name(latex=True)} = {robot.to_latex(T)}")
        else:
            print(f"T_0^{robot.n} = {robot.to_latex(T)}")
        return 0
    label = f"T = {robot.fk_name()}" if placement else f"T_0^{robot.n}"
    print(f"{robot.name}: {label} ({robot.convention} DH), c1 = cos(theta1), s23 = sin(theta2 + theta3)")
    for name, M in placement.items():
        print(f"  {name}: " + "; ".join(" | ".join(robot.to_str(M[i, j]) for j in range(4)) for i in range(3))
              + " (last row 0 | 0 | 0 | 1)")
    if placement:
        print(f"  T_0^{robot.n}: the DH table's product A_1 ... A_{robot.n} (--json: dh_product); T:")
    for i in range(3):
        print(f"  row {i + 1}: " + " | ".join(robot.to_str(T[i, j]) for j in range(4)))
    for name, e in zip("xyz", robot.position):
        print(f"  {name} = {robot.to_str(e)}")
    return 0


def cmd_jacobian(args) -> int:
    import sympy as sp

    from .symbolic import canonical_sstr

    robot = _robot_from_args(args)
    start = time.perf_counter()
    extra = {}
    if args.kind == "analytic":
        aj = robot.analytic_jacobian(args.euler)
        J = aj.J
        extra = {"euler": args.euler, "representation_singularity": sp.sstr(aj.singular_when) + " = 0",
                 "note": aj.note}
    else:
        J = robot.geometric_jacobian
    if not (args.json or args.latex):   # the Jacobian first: the factors can take far longer than J itself
        print(f"{robot.name}: {args.kind} Jacobian ({J.rows} x {J.cols})")
        for j in range(J.cols):
            print(f"  column {j + 1}: " + " | ".join(robot.to_str(J[i, j]) for i in range(J.rows)), flush=True)
    # Singular factors can cost far more than J itself (45 s for a 7-joint arm): --no-singular skips them, and
    # "singular" is then null in the JSON; past the symbolic budget they are null too, and "unfinished" says so.
    unfinished: dict[str, str] = {}
    pairs = None if args.no_singular else _within_budget(
        lambda: robot.singular_factors("geometric", multiplicity=True), "singular", unfinished)
    # each factor is defined up to a constant: printed (textbook, latex, text) in the robot's own lengths,
    # 0.425*c2 + 0.39225*c23 - ..., not as the gcd returns it, 8500*c2 + 7845*c23 - ...; "singular" and
    # "factor" keep the exact primitive factor that code compares
    singular: list | None = None
    shown: list | None = None
    if pairs is not None:
        singular = [f for f, _ in pairs]
        shown = [robot.in_lengths(f) for f in singular]
    charpoly = None if not args.charpoly else _within_budget(
        lambda: robot.characteristic_polynomial(args.charpoly).all_coeffs(), "charpoly", unfinished)
    seconds = time.perf_counter() - start
    if args.json:
        _emit_json({
            "robot": robot.name,
            "kind": args.kind,
            "J": _matrix_strings(J),
            "singular": None if singular is None else [sp.sstr(f) for f in singular],
            "singularities": None if pairs is None else [{"factor": sp.sstr(f), "multiplicity": m,
                                                          "textbook": robot.to_str(g)}
                                                         for (f, m), g in zip(pairs, shown or [])],
            "textbook": {"J": [[robot.to_str(J[i, j]) for j in range(J.cols)] for i in range(J.rows)],
                         "singular": None if shown is None else [robot.to_str(g) for g in shown]},
            "latex": {"J": robot.to_latex(J),
                      "singular": None if shown is None else [robot.to_latex(g) for g in shown]},
            "charpoly": None if charpoly is None else {
                "kind": args.charpoly, "variable": "lambda",
                "coefficients": [canonical_sstr(c) for c in charpoly],   # sympy.sstr's, each sum ordered once
                "textbook": [robot.to_str(c) for c in charpoly],
                "latex": [robot.to_latex(c) for c in charpoly]},
            "unfinished": unfinished,
            **extra,
            "seconds": seconds,
        })
        return 0
    if args.latex:
        print(f"J = {robot.to_latex(J)}")
        if charpoly is not None:
            print(f"det(lambda I - J J^T), coefficients of lambda^{len(charpoly) - 1} down to lambda^0: "
                  + ", ".join(robot.to_latex(c) for c in charpoly))
        if pairs is not None:
            print("singular: " + (f"{_product(robot, pairs, latex=True)} = 0" if pairs else NO_SINGULAR_FACTOR))
        for message in unfinished.values():
            print(message)
        return 0
    if pairs is not None:
        print(f"  singular where: {_product(robot, pairs)} = 0" if pairs else f"  singular: {NO_SINGULAR_FACTOR}")
    elif "singular" in unfinished:
        print(f"  singular: {unfinished['singular']}")
    if charpoly is not None:
        print(f"  det(lambda I - J J^T), {args.charpoly} Jacobian:")
        for k, c in enumerate(charpoly):
            print(f"    lambda^{len(charpoly) - 1 - k}: {robot.to_str(c)}")
    elif "charpoly" in unfinished:
        print(f"  det(lambda I - J J^T): {unfinished['charpoly']}")
    if extra:
        print(f"  {extra['note']}")
    return 0


def _within_budget(derive, key: str, unfinished: dict):
    """``derive()``, or None with ``unfinished[key]`` saying it was not found within the symbolic budget: the
    Jacobian printed before it stands, and the command ends with status 0 (a budget is an answer, not a fault)."""
    try:
        return derive()
    except SymbolicBudgetError as exc:
        what = "not factored" if key == "singular" else "not found"
        unfinished[key] = f"{what} within the budget ({exc})"
        return None


def cmd_codegen(args) -> int:
    """Write C for the forward kinematics and the geometric Jacobian of a robot."""
    robot = _robot_from_args(args)
    start = time.perf_counter()
    paths = robot.codegen(out=args.out, lang=args.lang, prefix=args.prefix)
    _wrote(*paths)
    functions = {"fk": f"void {args.prefix}fk(const double *q, double *T)",
                 "jacobian": f"void {args.prefix}jacobian(const double *q, double *J)"}
    if args.json:
        _emit_json({"robot": robot.name, "lang": args.lang, "joints": robot.n, "files": [str(p) for p in paths],
                    "functions": functions, "seconds": time.perf_counter() - start})
        return 0
    print(f"{robot.name}: {functions['fk']} (4 x 4 row-major) and {functions['jacobian']} (6 x {robot.n} "
          f"row-major) in {paths[1]}, declared in {paths[0]}")
    return 0


#: What the jacobian text says when the singular set is given by no single equation.
NO_SINGULAR_FACTOR = ("no single equation: no factor is common to every maximal minor, so the rank drops only "
                      "where several equations hold at once, if anywhere")


def _product(robot, pairs, *, latex: bool = False) -> str:
    """``f1 * (f2)**m * ...``: the singular factors with their multiplicities as one product that reads back as
    written (a sum is bracketed, so is a product raised to a power); LaTeX with ``\\cdot``."""
    def factor(f, m):
        f = robot.in_lengths(f)                  # in the robot's lengths, a positive multiple of the factor
        text = robot.to_latex(f) if latex else robot.to_str(f)
        if f.is_Add or (m > 1 and not (f.is_Symbol or f.is_Function)):
            text = f"\\left({text}\\right)" if latex else f"({text})"
        return text if m == 1 else f"{text}^{{{m}}}" if latex else f"{text}**{m}"

    return (r" \cdot " if latex else " * ").join(factor(f, m) for f, m in pairs)


def _parse_var(text: str):
    """``NAME=LOW:HIGH``; the name must be an identifier, the bounds numbers or constant expressions (``-pi/2``)."""
    from .expressions import is_finite_value, parse_expr, read_symbol

    name, sep, bounds = text.partition("=")
    lo, sep2, hi = bounds.partition(":")
    if not sep or not sep2 or not name.strip():
        raise InvalidParameterError(f"--var: expected NAME=LOW:HIGH; got {text!r}")
    symbol = read_symbol(name.strip(), "--var")
    values = []
    for side, v in (("lower", lo), ("upper", hi)):
        value = parse_expr(v, f"--var {symbol} {side} bound", new_symbols=False)
        if not value.is_number or not is_finite_value(value):
            raise InvalidParameterError(f"--var: bounds of {symbol} must be real numbers; got {bounds!r}")
        values.append(float(value))
    return symbol, tuple(values)


def cmd_pave(args) -> int:
    from . import robots
    from .interval import pave
    from .parallel import ConstraintModel

    if args.robot is not None:
        if args.var or args.constraint:
            raise WorkspaceError("pave: give either a catalog robot or --var/--constraint, not both")
        overrides = {k: v for k, v in (("l0", args.l0), ("lmin", args.lmin), ("lmax", args.lmax)) if v is not None}
        model = robots.build(args.robot, **overrides)
        if not isinstance(model, ConstraintModel):
            raise WorkspaceError(f"robot {args.robot!r} is not described by constraints; pave needs one (e.g. rpr2)")
        constraints, box, exact = model.constraints, model.box, model.exact_measure
    else:
        if not args.var or not args.constraint:
            raise WorkspaceError("pave: name a catalog robot (e.g. rpr2) or give --var NAME=LOW:HIGH and --constraint")
        pairs = [_parse_var(v) for v in args.var]
        names = [str(symbol) for symbol, _ in pairs]
        repeated = next((n for n in names if names.count(n) > 1), None)
        if repeated is not None:
            raise InvalidParameterError(f"--var: {repeated} is given {names.count(repeated)} times; give each "
                                        "variable once")
        box = dict(pairs)
        constraints, exact = args.constraint, None
    _check_plot_in_memory(args)
    with _distributed(args) as run:
        paving = pave(constraints, box, delta=args.delta, backend=args.backend, size=args.size, digits=args.digits,
                      contract=args.contract, stop=_stop_at(args), run=run).with_exact_measure(exact)
    if args.plot:
        from .plotting import plot_paving, save_figure

        _wrote(save_figure(plot_paving(paving), args.plot))
    _show_paving(paving, args.json)
    return _paving_status(args, paving)


def _paving_status(args, answer) -> int:
    """The exit status of a paving shown: 130, with one line on stderr, when Ctrl-C stopped the run.

    A budget or time limit reached is an answer (status 0); Ctrl-C is the user's stop, so the partial result is
    printed and the status says the command did not finish, as a shell expects of an interrupted program.
    """
    paving = getattr(answer, "paving", answer)
    if paving.complete or paving.stop_reason != "interrupted":
        return 0
    left = len(paving.pending)
    print(f"workspace-sym {args.command}: interrupted (Ctrl-C); the result above is partial, {left} "
          f"box{'' if left == 1 else 'es'} pending", file=sys.stderr)
    return 130


def _stop_at(args):
    """What a run stops at, from --max-boxes and --time-limit."""
    from .interval.driver import StopAt

    return StopAt(max_boxes=getattr(args, "max_boxes", None), time_limit=args.time_limit)


@contextmanager
def _distributed(args, options=("max_memory", "store", "resume")):
    """Where and how a run goes (a ``RunOn``), from --scheduler, --max-memory, --store, --resume and --progress (a
    local Dask cluster lives as long as the block)."""
    from .interval.driver import RunOn

    spread = {k: getattr(args, k) for k in options if getattr(args, k, None) is not None}
    spread["progress"] = getattr(args, "progress", None)
    if args.scheduler is None:
        yield RunOn(**spread)
        return
    from .interval.executor import connect

    with connect(args.scheduler) as client:
        yield RunOn(**spread, executor=client)


def _check_plot_in_memory(args) -> None:
    if (getattr(args, "plot", None) or getattr(args, "slices", None)) and (args.max_memory or args.store):
        raise WorkspaceError("--plot and --slices draw boxes held in memory; they cannot be combined with "
                             "--max-memory or --store (the boxes are on disk: load them in Python)")


def _show_paving(answer, as_json: bool, extra: dict | None = None) -> None:
    """A paving's (or a reach result's) JSON object, or its summary on the terminal."""
    import sympy as sp

    result = {**answer.to_dict(), **(extra or {})}
    if as_json:
        _emit_json(result)
        return
    lo, hi = answer.measure_bounds
    paving = getattr(answer, "paving", answer)
    how = ", with contraction" if paving.contract else ""
    print(f"delta = {paving.delta} ({paving.size}), backend {paving.backend}{how}: {paving.seconds:.3f} s, "
          f"{paving.evaluated} boxes evaluated")
    meaning = {"inner": "proved inside", "boundary": f"undecided, at most delta = {paving.delta}",
               "outer": "proved outside", "pending": "not examined: the run stopped"}
    for kind in ("inner", "boundary", "outer", "pending"):
        measure = measure_text(kind, result[kind]["measure"], 6)
        print(f"  {kind:<8} {result[kind]['boxes']:>8} boxes, measure {measure:<12} ({meaning[kind]})")
    volume = getattr(answer, "volume_bounds", None)
    if volume is not None:
        b_lo, b_hi = answer.box_measure_bounds
        print(f"  the boxes bound the measure to {fmt_bracket(b_lo, b_hi, 6)} (inner; inner + boundary + pending)")
        print(f"  the section's cells bound it to {fmt_bracket(volume[0], volume[1], 6)} (the section turned by the "
              "first joint, Pappus's theorem: proved)")
        print(f"  measure in {fmt_bracket(lo, hi, 6)} (the intersection of the two)")
    else:
        print(f"  measure in {fmt_bracket(lo, hi, 6)} (inner; inner + boundary + pending)")
    if paving.exact_measure is not None:
        print(f"  exact measure {fmt(float(paving.exact_measure), 6)} = {sp.sstr(paving.exact_measure)}")
    if not paving.complete:
        print(f"  stopped early: {paving.stop_reason}; pending boxes are unclassified")


def cmd_reach(args) -> int:
    from .serial import Pose, ReachModel, Tuning, reach

    robot = _robot_from_args(args)
    constraint = _pose_options(args)
    _check_plot_in_memory(args)
    if constraint:
        if args.scheduler is not None:
            raise InvalidParameterError(f"scheduler: reach with a tool constraint (approach, cone, every, "
                                        f"orientation) decides its boxes in this process, so a Dask scheduler does "
                                        f"not apply; got {args.scheduler!r}; it applies to reach without a tool "
                                        "constraint", parameter="scheduler")
        from .serial.pose import constraint_from

        described = constraint_from(**constraint)
        from .interval.driver import RunOn

        # boxes on disk and checkpoints for the section method (the pairs method with a pose refuses them)
        kept = RunOn(max_memory=args.max_memory, store=args.store, resume=args.resume, progress=args.progress)
        tuning = Tuning() if args.inner_depth is None else Tuning(pose_inner_depth=args.inner_depth)
        paving = reach(robot, delta=args.delta, size=args.size, stop=_stop_at(args), pose=Pose(**constraint),
                       run=kept, method=args.method, tuning=tuning)
    else:
        tuning = Tuning() if args.inner_depth is None else Tuning(inner_depth=args.inner_depth)
        with _distributed(args) as run:
            paving = reach(robot, delta=args.delta, size=args.size, tuning=tuning, method=args.method,
                           stop=_stop_at(args), run=run)
    if args.plot:
        from .plotting import plot_paving, save_figure

        _wrote(save_figure(plot_paving(paving, title=f"Certified position workspace of {robot.name}",
                                       units=robot.units), args.plot))
    model = ReachModel(robot)
    extra = {"robot": robot.name, "variables": [str(v) for v in paving.variables],
             "joints_subdivided": [str(q) for q in model.variables], "method": paving.method}
    if constraint and not args.json:         # (the JSON's "constraint" is the result's own, ReachResult.to_dict)
        print(f"{robot.name}: tool {described}")
    if not args.json:
        print(f"{robot.name}: position workspace over ({', '.join(extra['variables'])}); joints subdivided: "
              f"{', '.join(extra['joints_subdivided'])}; method {extra['method']}")
    _show_paving(paving, args.json, extra)
    return _paving_status(args, paving)


def cmd_reach_map(args) -> int:
    from .files import check_output_file
    from .interval.driver import StopAt
    from .serial.reachmap import reach_map

    robot = _robot_from_args(args)
    out = check_output_file(args.map_out, "map_out")
    stop = StopAt(max_boxes=args.max_boxes, time_limit=args.time_limit)
    with _distributed(args) as run:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", UserWarning)
            made = reach_map(robot, delta=args.delta, directions=args.directions, cone=args.cone,
                             reach_delta=args.reach_delta, method=args.method, stop=stop, run=run)
    for warning in caught:
        print(f"workspace-sym reach-map: warning: {warning.message}", file=sys.stderr)
    made.save(out)
    summary = {**made.summary(), "out": str(out)}
    if args.json:
        _emit_json(summary)
    else:
        print(f"{robot.name}: {' x '.join(map(str, made.shape))} cells of side {made.delta:g} x "
              f"{summary['directions']} directions (cones of {made.cone:g} deg, covering angle "
              f"{summary['covering_angle']:.4g} deg) in {summary['seconds']:.1f} s")
        print(f"pairs: {summary['reachable']} proved reachable, {summary['unreachable']} proved unreachable, "
              f"{summary['undecided']} undecided; decided {100 * summary['decided_fraction']:.1f} % "
              f"({100 * summary['decided_fraction_in_box']:.1f} % inside the bounding box)")
    _wrote(out)
    return 0


def _vectors_csv(text_or_path: str, parameter: str):
    """An (N, 3) array from a CSV file (x,y,z a line; a header line and # comments allowed) or one "X,Y,Z"."""
    import numpy as np

    from .files import read_text

    if Path(text_or_path).is_file():
        text = read_text(text_or_path, parameter, error=InvalidParameterError)
    elif parameter == "approach":
        text = text_or_path
    else:
        raise InvalidParameterError(f"{parameter}: {text_or_path!r} is not a file", parameter=parameter)
    rows = []
    for number, line in enumerate(text.splitlines(), 1):
        line = line.split("#")[0].strip()
        if not line:
            continue
        try:
            rows.append([float(v) for v in line.split(",")])
        except ValueError:
            if rows or number > 1:
                raise InvalidParameterError(f"{parameter}: line {number} ({line[:40]!r}) is not three numbers",
                                            parameter=parameter) from None
    if not rows or any(len(r) != 3 for r in rows):
        raise InvalidParameterError(f"{parameter} must hold three numbers a line (x,y,z); got "
                                    f"{len(rows)} lines", parameter=parameter)
    return np.array(rows, dtype=float)


def cmd_query(args) -> int:
    from .serial.reachmap import ReachMap

    try:
        made = ReachMap.load(args.map)
    except InvalidParameterError as exc:          # the file named by the positional argument, not a robot file
        raise InvalidParameterError(str(exc).replace("path: ", "map: ", 1), parameter="map") from None
    points = _vectors_csv(args.points, "points")
    approach = None if args.approach is None else _vectors_csv(args.approach, "approach")
    answer = made.query(points, approach=approach)
    if args.json:
        key = "codes" if approach is not None else "capability"
        _emit_json({"map": str(args.map), "robot": made.info.get("robot"), "points": len(points),
                    key: answer.tolist()})
    elif approach is not None:
        print("x,y,z,code")
        for p, code in zip(points, answer):
            print(f"{float(p[0])!r},{float(p[1])!r},{float(p[2])!r},{int(code)}")
    else:
        print("x,y,z,capability_lower,capability_upper")
        for p, (lo, hi) in zip(points, answer):
            print(f"{float(p[0])!r},{float(p[1])!r},{float(p[2])!r},{float(lo)!r},{float(hi)!r}")
    return 0


def _numbers(text: str, parameter: str, count: int, what: str) -> list:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != count:
        raise InvalidParameterError(f"{parameter} must be {what}; got {text!r}", parameter=parameter)
    return values


def _pose_options(args) -> dict:
    """The keywords of reach's tool constraint from --approach/--cone/--every/--orientation."""
    out: dict[str, object] = {}
    if args.orientation is not None:
        text = args.orientation.strip()
        if text.lower().startswith("rpy:"):
            return {"rpy": _numbers(text[4:], "rpy", 3, "three angles in degrees such as rpy:0,180,0")}
        values = _numbers(text, "orientation", 9, "rpy:R,P,Y (degrees) or nine numbers, the rotation matrix by rows")
        out["orientation"] = [values[0:3], values[3:6], values[6:9]]
    if args.approach is not None:
        out["approach"] = _numbers(args.approach, "approach", 3, "three numbers such as 0,0,-1")
    if args.cone is not None:
        out["cone"] = args.cone
    if args.every:
        out["every"] = True
    return out


def _parse_sigma(text: str):
    lo, sep, hi = text.partition(":")
    try:
        if not sep:
            raise ValueError
        return float(lo), float(hi)
    except ValueError:
        raise InvalidParameterError(f"--sigma: expected MIN:MAX such as 0.25:4; got {text!r}") from None


def _parse_shave(text: str | None):
    from .orthoglide.certificate import SHAVE

    if text is None:
        return SHAVE
    if text.strip().lower() == "none":
        return ()
    try:
        return tuple(float(f) for f in text.split(","))
    except ValueError:
        raise InvalidParameterError(f"--shave: expected fractions such as 0.5,0.25 or 'none'; got {text!r}",
                                    parameter="shave") from None


def cmd_dextrous(args) -> int:
    from . import robots
    from .orthoglide import Orthoglide

    model = robots.build(args.robot)
    if not isinstance(model, Orthoglide):
        raise WorkspaceError(f"robot {args.robot!r}: the dextrous workspace is implemented for the orthoglide")
    _check_plot_in_memory(args)
    with _distributed(args) as run:
        result = model.dextrous(eps=args.eps, sigma=_parse_sigma(args.sigma), shave=_parse_shave(args.shave),
                                stop=_stop_at(args), run=run)
    if args.plot or args.slices:
        from .plotting import plot_paving, plot_paving_slices, save_figure

        if args.plot:
            _wrote(save_figure(plot_paving(result.paving, title=f"dextrous workspace, eps = {args.eps}"), args.plot))
        if args.slices:
            _wrote(save_figure(plot_paving_slices(result.paving,
                                                  reference=lambda p: model.numeric_dextrous(p, result.sigma),
                                                  title=f"dextrous workspace, eps = {args.eps}: slices (red: numeric "
                                                        "eigenvalues)"), args.slices))
    data = result.to_dict()
    if args.json:
        _emit_json(data)
        return 0
    print(f"orthoglide dextrous workspace, sigma in [{data['sigma'][0]}, {data['sigma'][1]}], eps = {args.eps}: "
          f"{data['seconds']:.1f} s, {data['boxes_evaluated']} boxes")
    print(f"  certified inside volume {fmt_bound(data['volume_inner'], 6, up=False)} ({data['boxes']['inner']} boxes)")
    print(f"  error index E (undecided) {fmt_bound(data['volume_undecided'], 6, up=True)} "
          f"({data['boxes']['undecided']} boxes)")
    if not data["complete"]:
        print("  stopped early: the rest is counted in E")
    return 0


def cmd_cube(args) -> int:
    from . import robots
    from .orthoglide import Orthoglide

    model = robots.build(args.robot)
    if not isinstance(model, Orthoglide):
        raise WorkspaceError(f"robot {args.robot!r}: the largest cube is implemented for the orthoglide")
    with _distributed(args, ()) as run:         # the cube's certificates take the executor alone
        result = model.largest_cube(alpha=args.alpha, sigma=_parse_sigma(args.sigma),
                                    run=run)
    if args.json:
        _emit_json(result.to_dict())
    else:
        _print_cube(result.to_dict(), args.alpha)
    return 0


def _print_cube(data: dict, alpha: float) -> None:
    x, y, z = data["center"]
    print(f"orthoglide, largest cube in the dextrous workspace (sigma in {data['sigma']}), alpha = {alpha}: "
          f"{data['seconds']:.1f} s")
    print(f"  centre ({fmt(x, 6)}, {fmt(y, 6)}, {fmt(z, 6)})")
    print(f"  a cube of edge {fmt_bound(data['edge_lower'], 9, up=False)} there is proved inside; no cube of edge "
          f"above {fmt_bound(data['edge_upper'], 9, up=True)} fits anywhere (proved)")
    if "closed_form" in data:
        print(f"  closed form: {data['closed_form']}")


def _parse_list(text: str, option: str) -> list[str]:
    items = [t.strip() for t in str(text).split(",")]
    if not items or any(not t for t in items):
        raise InvalidParameterError(f"{option}: expected comma-separated numbers such as 0.3,0.15; got {text!r}")
    return items


def _chain_from_args(args):
    from .planar import PlanarChain

    lengths = _parse_list(args.lengths, "--lengths")
    lower = _parse_list(args.lower, "--lower")
    upper = _parse_list(args.upper, "--upper")
    return PlanarChain(lengths, lower, upper, degrees=not args.radians)


def cmd_boundary(args) -> int:
    from .planar.boundary import format_set

    chain = _chain_from_args(args)
    boundary = chain.boundary()
    data = boundary.to_dict(exact=args.exact)
    if args.plot:
        from .plotting import plot_planar_step, save_figure

        _wrote(save_figure(plot_planar_step(chain, 2), args.plot))
    if args.report:
        from .report import planar_report

        _wrote_report(planar_report(chain, args.report, command=" ".join(["workspace-sym"] + sys.argv[1:])))
    if args.json:
        _emit_json(data)
        return 0
    c = data["counts"]
    print(f"planar chain, p = {chain.p}: arcs step 0 / 1 / 2 = {c['step0']} / {c['step1']} / {c['step2']}, "
          f"{data['seconds']:.3f} s")
    for loop in data["loops"]:
        print(f"  {loop['kind']} loop: arcs {', '.join(str(k + 1) for k in loop['arcs'])}")
    print(f"  {'#':>3} {'type':<4} " + " ".join(f"{'theta_' + str(j + 1) + ' (deg)':>20}" for j in range(chain.p)))
    for k, arc in enumerate(data["arcs"], start=1):
        print(f"  {k:>3} {arc['type']:<4} " + " ".join(f"{format_set(s):>20}" for s in arc["theta_sets"]))
    print(f"  area {fmt(data['area'], 10, 'g')}, perimeter {fmt(data['perimeter'], 10, 'g')}")
    if args.exact:
        print(f"  exact area = {data['area_exact']}")
    if data["undecided_area"]:
        print(f"  undecided faces of area {fmt(data['undecided_area'], 6, 'g')}: the area is a lower bound")
    if data["merged"]:
        m = data["merged"]
        print(f"  {m['faces']} sliver faces (area {m['area']:.3g}) merged into their neighbours")
    if args.report:
        print(f"report: {Path(args.report) / 'report.md'}")
    return 0


def cmd_demo(args) -> int:
    from . import robots
    from .planar import PlanarChain
    from .report import planar_report

    start = time.perf_counter()
    # Bastien (2018), Table 1, case iii: the human arm (arm, forearm, hand)
    chain = PlanarChain(["0.186", "0.146", "0.108"], [-60, 0, -10], [120, 130, 25])
    model = robots.build("rpr2")
    paving = model.pave(delta=0.07)
    path = planar_report(chain, args.out, command=" ".join(["workspace-sym"] + sys.argv[1:]),
                         title="Human arm of Bastien (2018), Table 1 case iii: exact workspace boundary",
                         paving=paving, paving_title="Certified paving of Rybak's 2-RPR robot (delta 0.07)")
    b = chain.boundary()
    lo, hi = paving.measure_bounds
    _wrote_report(path)
    if args.json:
        _emit_json(_report_summary(path, start,
                                   boundary={"counts": dict(b.counts), "area": b.area, "arcs": len(b.arcs)},
                                   paving={"measure_bounds": [lo, hi], "exact_measure": float(model.exact_measure),
                                           "delta": 0.07}))
        return 0
    print(f"human arm (Bastien 2018, Table 1 iii): {b.counts['step0']} / {b.counts['step1']} / {b.counts['step2']} "
          f"arcs after steps 0 / 1 / 2, area {fmt(b.area, 10)}")
    print(f"2-RPR paving (Rybak et al. 2016), delta 0.07: area in {fmt_bracket(lo, hi)}, "
          f"exact {fmt(float(model.exact_measure))}")
    print(f"{time.perf_counter() - start:.1f} s; report: {path} (also {path.with_suffix('.html').name}, "
          f"{path.with_suffix('.tex').name})")
    return 0


def cmd_report(args) -> int:
    from . import robots
    from .kinematics import DHRobot
    from .report import dh_robot_report, planar_report

    start = time.perf_counter()
    command = " ".join(["workspace-sym"] + sys.argv[1:])
    from .interval.boxes import check_delta
    from .interval.driver import StopAt

    check_delta(args.reach_time_limit, "reach_time_limit")       # named by its flag, before StopAt names time_limit
    if args.reach_max_boxes is not None and args.reach_max_boxes < 1:     # likewise before StopAt names max_boxes
        raise InvalidParameterError(f"reach_max_boxes must be at least 1; got {args.reach_max_boxes}",
                                    parameter="reach_max_boxes")
    reach = {"reach_delta": args.reach_delta,
             "stop": StopAt(time_limit=args.reach_time_limit, max_boxes=args.reach_max_boxes)}
    constraint = _pose_options(args)
    if constraint:
        if args.reach_delta is None:
            raise InvalidParameterError("a tool constraint (approach, cone, every, orientation) is a constraint on "
                                        "the certified workspace section: give reach_delta too",
                                        parameter="reach_delta")
        from .serial import Pose
        from .serial.pose import constraint_from

        constraint_from(**constraint)     # a bad constraint is refused before any section is written
        reach["pose"] = Pose(**constraint)
    files = [f"--{dest} FILE" for dest in _ROBOT_FILES if getattr(args, dest) is not None]
    extra = {}

    def no_reach():
        if args.reach_delta is not None:
            raise InvalidParameterError(f"the certified workspace section needs a DH robot (catalog or --dh FILE); "
                                        f"{args.what!r} is not one", parameter="reach_delta")

    if (args.base or args.tip or args.package or args.xacro_arg) and not (args.urdf or args.mjcf):
        _robot_from_args(args)            # says which file --base, --tip, --package or --xacro-arg needs
    if args.what is not None and files:
        raise WorkspaceError(f"report: give either {args.what!r} or a robot file ({' and '.join(files)}), not both")
    if args.what == "chain":
        no_reach()
        if not (args.lengths and args.lower and args.upper):
            raise WorkspaceError("report chain: give --lengths, --lower and --upper")
        path = planar_report(_chain_from_args(args), args.out, command=command)
    elif files or args.what is None:
        if not files:
            raise WorkspaceError("report: name 'chain', a catalog robot, rpr2 or orthoglide, or pass --dh FILE, "
                                 "--urdf FILE or --mjcf FILE")
        robot = _robot_from_args(args)
        extra = {"robot": robot.name, "joints": robot.n}
        path = dh_robot_report(robot, args.out, command=command, **reach)
    else:
        from .orthoglide import Orthoglide
        from .parallel import ConstraintModel

        model = robots.build(args.what)
        extra = {"robot": args.what}
        if isinstance(model, DHRobot):
            extra["joints"] = model.n
            path = dh_robot_report(model, args.out, command=command, **reach)
        elif isinstance(model, ConstraintModel):
            no_reach()
            from .report import paving_report

            paving = model.pave(delta=args.delta)
            path = paving_report(paving, args.out, title=f"Certified paving of {args.what}", command=command)
        elif isinstance(model, Orthoglide):
            no_reach()
            from .report import orthoglide_report

            path = orthoglide_report(model, args.out, eps=args.eps, alpha=args.alpha, command=command)
        else:
            raise WorkspaceError(f"report: no report for {args.what!r}; use 'chain', a DH robot, rpr2 or orthoglide")
    _wrote_report(path)
    if args.json:
        _emit_json(_report_summary(path, start, **extra))
    else:
        print(f"report: {path}")
    return 0


def cmd_grade(args) -> int:
    """Grade a CSV of students' answers against a key; write the graded CSV and the report."""
    from .interval.driver import RunOn
    from .teaching import AnswerKey, duplicate_rows, grade_answers, read_answers_csv, similar_students, write_grading

    key = AnswerKey.from_file(args.key)
    graded = grade_answers(key, read_answers_csv(args.answers), run=RunOn(progress=args.progress))
    paths = write_grading(key, graded, args.out)
    total = sum(q.points for q in key.questions)
    scores: dict[str, float] = {}
    for g in graded:
        scores[g.student] = scores.get(g.student, 0.0) + g.points
    repeated, similar = duplicate_rows(graded), similar_students(graded)
    if args.json:
        _emit_json({"students": scores, "total": total, "answers": len(graded),
                    "files": {k: str(v) for k, v in paths.items()}, "duplicates": repeated,
                    "similar_students": similar})
    else:
        for student, score in scores.items():
            print(f"{student}: {score:g} / {total:g}")
        if repeated:
            print(f"{sum(len(d['rows']) - 1 for d in repeated)} duplicate row(s), not graded (only a student's "
                  "first answer to a question is): listed in the report")
        for names in similar:
            print(f"warning: {' and '.join(repr(n) for n in names)} differ only in case or blanks and are graded as "
                  "different students: check them")
        print(f"wrote {paths['csv']}, {paths['html']} and {paths['markdown']}")
    return 0


def cmd_exercises(args) -> int:
    """Write an exercise sheet, its answer key and the machine-readable key."""
    from .interval.driver import RunOn
    from .teaching import write_exercises

    paths = write_exercises(args.out, seed=args.seed, count=args.count, max_joints=args.max_joints,
                            run=RunOn(progress=args.progress))
    if args.json:
        _emit_json({"seed": args.seed, "count": args.count, "files": {k: str(v) for k, v in paths.items()}})
    else:
        print(f"wrote {', '.join(sorted(paths))} to {args.out}")
    return 0


# ------------------------------------------------------------------------------ parser
# Options shared by several subcommands, declared once as parent parsers.
DOCS = Path(__file__).resolve().parent / "docs"     # docs/ ships inside the package (pyproject package-data)
_DH_HELP = "DH table as JSON instead of a catalog robot (format: docs/cli.md, 'DH files')"


def _parent(*options) -> _Parser:
    """A parent parser holding ``options``, each ``(names, keyword arguments of add_argument)``."""
    p = _Parser(add_help=False)
    for names, kwargs in options:
        p.add_argument(*names, **kwargs)
    return p


_JSON = (("--json",), {"action": "store_true",
                       "help": "print one JSON object on stdout instead of text (keys: docs/cli.md)"})
_PROGRESS = (("--progress",), {"action": argparse.BooleanOptionalAction, "default": None,
                               "help": "progress bar on stderr (default: on a terminal, once a run has lasted a "
                                       "second)"})
_MAX_BOXES = (("--max-boxes",), {"type": int, "help": "stop after this many boxes (the rest is pending)"})
_TIME_LIMIT = (("--time-limit",), {"type": float, "help": "stop after this many seconds (the rest is pending)"})
_ROBOT = (("robot",), {"nargs": "?", "help": "catalog DH robot (see 'workspace-sym robots'), or none with --dh"})
_DH = (("--dh",), {"metavar": "FILE", "help": _DH_HELP})
_URDF = (("--urdf",), {"metavar": "FILE", "help": "a URDF file, read as data: its serial chain as a DH robot. A FILE "
                                                   "named *.xacro is expanded with xacro (the xacro extra), which runs "
                                                   "the code it holds: only files you would run"})
_PACKAGE = (("--package",), {"action": "append", "default": [], "metavar": "PKG=DIR",
                             "help": "with --urdf FILE.xacro: the directory of package PKG, for $(find PKG) (default: "
                                     "a folder PKG above the file or beside the folders above it); repeatable"})
_XACRO_ARG = (("--xacro-arg",), {"action": "append", "default": [], "metavar": "NAME=VALUE",
                                 "help": "with --urdf FILE.xacro: the value of the file's argument NAME, for $(arg "
                                         "NAME) (xacro's NAME:=VALUE); repeatable"})
_MJCF = (("--mjcf",), {"metavar": "FILE",
                       "help": "a MuJoCo model (MJCF XML): its serial chain of bodies as a DH robot"})
_BASE = (("--base",), {"metavar": "LINK", "help": "with --urdf/--mjcf: first link or body of the chain (default: the "
                       "root link, the world body)"})
_TIP = (("--tip",), {"metavar": "LINK", "help": "with --urdf/--mjcf: last link or body (default: the only leaf moved "
                     "by a joint)"})
_SNAP_TOL = (("--snap-tol",), {"type": float, "default": SNAP_TOL, "metavar": "RAD",
                               "help": "float angles of --dh/--urdf this close to a multiple of pi/360 become it "
                                       f"(default {SNAP_TOL:g})"})
_KEEP_FLOATS = (("--keep-floats",), {"action": "store_true",
                                     "help": "keep float inputs as floats; chop entries below --snap-tol instead"})
_SIGMA = (("--sigma",), {"default": "0.25:4", "help": "range of the eigenvalues of J J^T, MIN:MAX (default 0.25:4)"})
_DELTA = (("--delta",), {"type": float, "required": True, "help": "size below which undecided boxes stop splitting"})
_SCHEDULER = (("--scheduler",), {"metavar": "ADDRESS", "help": "decide the boxes on a Dask cluster: tcp://host:8786 "
                                 "(a running scheduler) or local:N (N local worker processes, started and stopped "
                                 "here); needs workspace_sym[distributed]"})
_MAX_MEMORY = (("--max-memory",), {"metavar": "SIZE", "help": "bound the memory (e.g. 2GB): decided boxes are "
                                   "streamed to disk (--store) and the frontier is processed depth-first"})
_STORE = (("--store",), {"metavar": "DIR", "help": "directory for the decided boxes (.npy parts; named in the JSON)"})
_RESUME = (("--resume",), {"metavar": "FILE", "help": "checkpoint: go on from FILE if it exists; written when the run "
                           "ends or stops (time limit, Ctrl-C), every minute with --max-memory"})
_SIZE = (("--size",), {"choices": ("diameter", "width"), "default": "diameter",
                       "help": "box size compared with delta: diameter (default, as in the paper) or largest edge"})


def _chain_parent(*, required: bool) -> _Parser:
    p = _Parser(add_help=False)
    p.add_argument("--lengths", required=required,
                   help="segment lengths, comma-separated (e.g. 0.186,0.146,0.108)")
    p.add_argument("--lower", required=required,
                   help="lower joint limits, comma-separated, degrees unless --radians (e.g. --lower -60,0,-10)")
    p.add_argument("--upper", required=required,
                   help="upper joint limits, comma-separated, degrees unless --radians (e.g. --upper 120,130,25)")
    p.add_argument("--radians", action="store_true", help="limits are in radians (default: degrees)")
    return p


def _pose_parent() -> _Parser:
    """--approach, --cone, --every, --orientation: a constraint on the tool frame (reach, report)."""
    p = _Parser(add_help=False)
    p.add_argument("--approach", metavar="AX,AY,AZ",
                   help="tool constraint: the approach axis (z of the tool frame) within --cone degrees of this "
                        "direction")
    p.add_argument("--cone", type=float, metavar="DEG", help="with --approach: half-angle of the cone (0: exact)")
    p.add_argument("--every", action="store_true",
                   help="with --approach: every direction of the cone (proved for arms with a roll-pitch wrist; "
                        "refused with the reason for other arms)")
    p.add_argument("--orientation", metavar="rpy:R,P,Y|R11,...,R33",
                   help="tool constraint: the tool frame exactly this rotation (roll, pitch, yaw in degrees, or "
                        "the matrix by rows)")
    return p


def build_parser() -> _Parser:
    """The argument parser of ``workspace-sym``, one subparser per subcommand (docs/cli.md).

    Returns
    -------
    argparse.ArgumentParser
        The parser; its errors are one line on stderr and exit status 2, and ``parser.commands`` maps each
        subcommand's name to its own parser.
    """
    parser = _Parser(prog="workspace-sym", description="Robot workspaces, exactly or with proofs.",
                     epilog=f"Exit status: 0 on success, 2 for bad input, 130 when interrupted (Ctrl-C; reach and pave "
                            f"print their partial result first). The options, the DH file format and the JSON keys "
                            f"are described in docs/cli.md, installed with the package as {DOCS / 'cli.md'}.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    json_, progress, budget = _parent(_JSON), _parent(_PROGRESS), _parent(_MAX_BOXES, _TIME_LIMIT)
    dh_robot = _parent(_ROBOT, _DH, _URDF, _MJCF, _BASE, _TIP, _PACKAGE, _XACRO_ARG, _SNAP_TOL, _KEEP_FLOATS)
    # report: the same without the positional robot
    robot_files = _parent(_DH, _URDF, _MJCF, _BASE, _TIP, _PACKAGE, _XACRO_ARG, _SNAP_TOL, _KEEP_FLOATS)
    sigma, resolution = _parent(_SIGMA), _parent(_DELTA, _SIZE)
    spread, scheduler = _parent(_SCHEDULER, _MAX_MEMORY, _STORE, _RESUME), _parent(_SCHEDULER)

    p = sub.add_parser("robots", help="list the catalog", parents=[json_])
    p.set_defaults(func=cmd_robots)

    for name, func, help_ in (("fk", cmd_fk, "forward kinematics T_0^n in textbook form"),
                              ("jacobian", cmd_jacobian, "Jacobian and singular factors")):
        p = sub.add_parser(name, help=help_, parents=[dh_robot, json_])
        p.add_argument("--latex", action="store_true", help="print LaTeX")
        if name == "jacobian":
            p.add_argument("--kind", choices=("geometric", "analytic"), default="geometric",
                           help="geometric (default: linear and angular velocity) "
                                "or analytic (position and Euler-angle rates)")
            p.add_argument("--euler", choices=("zyz", "rpy"), default="zyz",
                           help="Euler convention of the analytic Jacobian (default zyz)")
            p.add_argument("--no-singular", action="store_true",
                           help="skip the singular factors (slow for 7-joint arms); JSON 'singular' is null")
            p.add_argument("--charpoly", choices=("geometric", "position"),
                           help="also give det(lambda I - J J^T) of the 6 x n geometric or 3 x n position "
                                "Jacobian, coefficients as sums of squared minors (tens of seconds for a 6R arm)")
        p.set_defaults(func=func)

    p = sub.add_parser("codegen", help="C code of the forward kinematics and the geometric Jacobian",
                       parents=[dh_robot, json_])
    p.add_argument("--lang", choices=("c",), default="c", help="language of the generated code (default c)")
    p.add_argument("--prefix", default="", help="prefix of the function names (e.g. ur5_ for ur5_fk)")
    p.add_argument("--out", required=True, help="output directory (<robot>.h and <robot>.c)")
    p.set_defaults(func=cmd_codegen)

    p = sub.add_parser("pave", help="certified non-uniform covering of a constraint set",
                       parents=[resolution, budget, progress, json_, spread])
    p.add_argument("robot", nargs="?", help="catalog model described by constraints (e.g. rpr2)")
    p.add_argument("--l0", type=float, help="rpr2: distance between the base joints")
    p.add_argument("--lmin", type=float, help="rpr2: shortest leg")
    p.add_argument("--lmax", type=float, help="rpr2: longest leg")
    p.add_argument("--var", action="append", default=[], metavar="NAME=LOW:HIGH", help="a variable and its range")
    p.add_argument("--constraint", action="append", default=[], metavar="INEQUALITY",
                   help='e.g. "x1**2 + x2**2 - 144 <= 0"')
    p.add_argument("--backend", choices=("numpy", "mpmath"), default="numpy",
                   help="interval arithmetic: numpy (default, outward-rounded floats) or mpmath")
    p.add_argument("--digits", type=int, default=30, help="precision of the mpmath backend")
    p.add_argument("--contract", action="store_true",
                   help="also cut proved slices off undecided boxes (forward-backward contraction; numpy backend)")
    p.add_argument("--plot", metavar="FILE", help="draw the boxes to an image file")
    p.set_defaults(func=cmd_pave)

    p = sub.add_parser("reach", help="certified position workspace of a serial robot (reachable / unreachable boxes)",
                       parents=[dh_robot, resolution, budget, progress, json_, spread, _pose_parent()])
    p.add_argument("--method", choices=("auto", "critical", "pairs"), default="auto",
                   help="critical: regions decided from the critical set (planar robots; spatial ones whose "
                        "coordinates are moved by disjoint joints, as a SCARA, or turned by a revolute first joint); "
                        "pairs: joint boxes carried by task boxes (any robot); auto (default): critical where it "
                        "applies")
    p.add_argument("--inner-depth", type=int, default=None,
                   help="pairs method: halvings of a last-level box when proving it reachable piece by piece "
                        "(default 2; with a tool constraint 1)")
    p.add_argument("--plot", metavar="FILE", help="draw the boxes to an image file")
    p.set_defaults(func=cmd_reach)

    p = sub.add_parser("reach-map", help="certified reachability map: cells x approach directions, each pair proved "
                                         "reachable, proved unreachable or undecided",
                       parents=[dh_robot, budget, progress, json_, spread])
    p.add_argument("--delta", type=float, required=True, help="the cells' side, in the robot's units")
    p.add_argument("--directions", type=int, default=26,
                   help="number of approach directions (26: the cube's faces, edges and corners; default 26)")
    p.add_argument("--cone", type=float, default=30.0, help="half-angle of each direction's cone, degrees (default 30)")
    p.add_argument("--reach-delta", type=float, default=None, metavar="D",
                   help="the delta of each direction's pose paving (default delta / 2); with --method section, "
                        "of the position paving")
    p.add_argument("--method", choices=("pavings", "section"), default="pavings",
                   help="pavings: one pose paving a direction (default); section: reachable pairs from certified "
                        "solutions of the section of an arm turned by its first joint, for all the directions at "
                        "once (no base transform; docs/methods.md section 9)")
    p.add_argument("--out", dest="map_out", required=True, metavar="FILE", help="the map's file (.npz)")
    p.set_defaults(func=cmd_reach_map)

    p = sub.add_parser("query", help="what a reachability map proved at points (with approach vectors or not)",
                       parents=[json_])
    p.add_argument("map", help="a map written by reach-map (.npz)")
    p.add_argument("--points", required=True, metavar="FILE", help="CSV of points, x,y,z a line")
    p.add_argument("--approach", metavar="FILE|AX,AY,AZ",
                   help="CSV of approach vectors (one a point) or one vector for all: the code of each point's "
                        "pair; without: the capability bracket")
    p.set_defaults(func=cmd_query)

    p = sub.add_parser("dextrous", help="certified dextrous workspace (Orthoglide)",
                       parents=[sigma, progress, json_, spread])
    p.add_argument("robot", help="catalog model (orthoglide)")
    p.add_argument("--eps", type=float, default=0.05, help="boxes narrower than this stay undecided")
    p.add_argument("--time-limit", type=float, help="stop after this many seconds (the rest counts in E)")
    p.add_argument("--plot", metavar="FILE", help="draw the boxes (3D) to an image file")
    p.add_argument("--slices", metavar="FILE", help="draw slices z = -0.4, 0, 0.3 with the numeric boundary")
    p.add_argument("--shave", metavar="F,F", default=None,
                   help="slab fractions shaved off the last-level boxes (default 0.5; 'none': plain bisection)")
    p.set_defaults(func=cmd_dextrous)

    p = sub.add_parser("cube", help="largest cube in the dextrous workspace (Orthoglide), certified both ways",
                       parents=[sigma, progress, json_, scheduler])
    p.add_argument("robot", help="catalog model (orthoglide)")
    p.add_argument("--alpha", type=float, default=0.001, help="accuracy on the half-edge (paper: 0.001)")
    p.set_defaults(func=cmd_cube)

    p = sub.add_parser("boundary", help="exact workspace boundary of a planar chain (alignment method)",
                       parents=[_chain_parent(required=True), json_])
    p.add_argument("--exact", action="store_true", help="closed forms of every arc and of the area")
    p.add_argument("--plot", metavar="FILE", help="draw the boundary (Step 2) to an image file")
    p.add_argument("--report", metavar="DIR", help="write the full report (Markdown, HTML, LaTeX) to DIR")
    p.set_defaults(func=cmd_boundary)

    p = sub.add_parser("report", help="write a report (Markdown, HTML, LaTeX) for a chain or a catalog robot",
                       parents=[_chain_parent(required=False), robot_files, json_, _pose_parent()])
    p.add_argument("what", nargs="?",
                   help="'chain' (with --lengths/--lower/--upper), a DH robot, rpr2 or orthoglide; none with "
                        "--dh, --urdf or --mjcf")
    p.add_argument("--delta", type=float, default=0.07, help="paving resolution (rpr2)")
    p.add_argument("--eps", type=float, default=0.125, help="dextrous workspace resolution (orthoglide)")
    p.add_argument("--alpha", type=float, default=0.01, help="largest-cube accuracy (orthoglide)")
    p.add_argument("--reach-delta", type=float, metavar="D",
                   help="DH robot: add a certified workspace section (reach with boxes down to size D)")
    p.add_argument("--reach-time-limit", type=float, default=60.0, metavar="SECONDS",
                   help="with --reach-delta: stop reach after this many seconds (default 60; the rest is pending)")
    p.add_argument("--reach-max-boxes", type=int, default=None, metavar="N",
                   help="with --reach-delta: stop reach after this many boxes evaluated (default: no budget; the rest "
                        "is pending)")
    p.add_argument("--out", required=True, help="output directory")
    p.set_defaults(func=cmd_report)

    p = sub.add_parser("grade", help="grade students' answers (CSV: student, question, answer) against a key",
                       parents=[json_, progress])
    p.add_argument("key", help="answer key (JSON, as written by 'workspace-sym exercises')")
    p.add_argument("answers", help="CSV with columns student, question, answer (separated by ',', ';' or a tab)")
    p.add_argument("--out", required=True, help="output directory (graded.csv, grades.html, grades.md)")
    p.set_defaults(func=cmd_grade)

    p = sub.add_parser("exercises", help="exercise sheet with a certified answer key (Markdown, HTML, LaTeX, JSON)",
                       parents=[json_, progress])
    p.add_argument("--seed", type=int, default=0, help="random seed: the same seed gives the same sheet")
    p.add_argument("--count", type=int, default=4, help="number of problems (robots and chains alternate)")
    p.add_argument("--max-joints", type=int, default=6, help="largest DH robot drawn, 3 to 6 joints (default 6)")
    p.add_argument("--out", required=True, help="output directory")
    p.set_defaults(func=cmd_exercises)

    p = sub.add_parser("demo", help="the main job: write the demo report and print its path", parents=[json_])
    p.add_argument("--out", default="demo-report", help="output directory (default: demo-report)")
    p.set_defaults(func=cmd_demo)
    parser.commands = sub.choices
    return parser


# Library errors name the API parameter (WorkspaceError.parameter); the command line adds its option when the
# running subcommand has one of that name (argparse's dest is the parameter name).
_FLAGS: dict[str | None, str] = {
    "delta": "--delta", "size": "--size", "max_boxes": "--max-boxes", "time_limit": "--time-limit",
    "backend": "--backend", "digits": "--digits", "inner_depth": "--inner-depth",
    "l0": "--l0", "lmin": "--lmin", "lmax": "--lmax",
    "eps": "--eps", "sigma": "--sigma", "alpha": "--alpha",
    "seed": "--seed", "count": "--count", "max_joints": "--max-joints",
    "scheduler": "--scheduler", "max_memory": "--max-memory", "store": "--store", "resume": "--resume",
    "reach_delta": "--reach-delta", "reach_time_limit": "--reach-time-limit", "reach_max_boxes": "--reach-max-boxes",
    "approach": "--approach", "cone": "--cone", "every": "--every", "orientation": "--orientation",
    "rpy": "--orientation",
    "base_link": "--base", "tip_link": "--tip", "out": "--out", "plot": "--plot", "slices": "--slices",
    "report": "--report", "prefix": "--prefix", "packages": "--package", "xacro_args": "--xacro-arg",
    "directions": "--directions", "points": "--points", "map_out": "--out",
}
# Options naming a file to write (a figure) and a directory to fill (a report); checked before any work.
_FIGURE_OPTIONS = ("plot", "slices")
_DIRECTORY_OPTIONS = ("out", "report")


def _error_line(args, exc: WorkspaceError) -> str:
    """The one stderr line of a bad input, with the option to blame when it is known."""
    message = " ".join(str(exc).split())
    flag = _FLAGS.get(exc.parameter)
    if exc.parameter == "path":         # a DH, URDF or MJCF file: the option that named it (one at most is given)
        flag = next((f"--{dest}" for dest in _ROBOT_FILES if getattr(args, dest, None) is not None), None)
    if flag is not None and (flag[2:].replace("-", "_") in vars(args) or exc.parameter in vars(args)):
        # "path: 'x.json' is not valid JSON" becomes "--dh: 'x.json' is not valid JSON"
        message = f"{flag}: {message.removeprefix(f'{exc.parameter}: ')}"
    return f"workspace-sym {args.command}: error: {message}"


def _check_outputs(args) -> None:
    """Refuse an output path that cannot be written before any work is done (one line, exit 2, nothing written)."""
    from .files import check_output_dir, check_output_file, figure_formats

    for dest in _FIGURE_OPTIONS:
        if getattr(args, dest, None) is not None:
            check_output_file(getattr(args, dest), dest, formats=figure_formats())
    for dest in _DIRECTORY_OPTIONS:
        if getattr(args, dest, None) is not None:
            check_output_dir(getattr(args, dest), dest)


def main(argv=None) -> int:
    """Run ``workspace-sym`` with the arguments ``argv``.

    The result goes to stdout (one JSON object with ``--json``), files written are named on stderr.  Bad input
    (any :class:`~workspace_sym.errors.WorkspaceError`) prints one line on stderr naming the option to blame;
    an unforeseen failure prints one line too (the traceback with ``WORKSPACE_SYM_DEBUG=1``).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; by default ``sys.argv[1:]``.

    Returns
    -------
    int
        The exit status: 0 on success (also when the reader of stdout went away), 2 for bad input or an
        unforeseen failure, 130 when interrupted.

    Raises
    ------
    SystemExit
        From argparse: status 2 for arguments it cannot parse (one line on stderr), 0 after ``--help`` or
        ``--version``.
    """
    parser = build_parser()
    args, unknown = parser.parse_known_args(argv)
    if unknown:     # said by the subcommand's parser, so the message names the command
        parser.commands[args.command].error(f"unrecognized arguments: {' '.join(unknown)}")
    try:
        _check_outputs(args)
        return args.func(args)
    except WorkspaceError as exc:
        print(_error_line(args, exc), file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"workspace-sym {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader of stdout went away (e.g. `| head`): stop quietly, as Unix tools do
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except Exception as exc:
        # A failure the library did not foresee (SymPy refusing a number field, say) is still one line and exit 2;
        # WORKSPACE_SYM_DEBUG=1 shows the traceback for a bug report.
        if os.environ.get("WORKSPACE_SYM_DEBUG"):
            raise
        first = (str(exc).splitlines() or [""])[0][:200]
        print(f"workspace-sym {args.command}: error: could not complete this command ({type(exc).__name__}: "
              f"{first}); please report it, with WORKSPACE_SYM_DEBUG=1 for the traceback", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
