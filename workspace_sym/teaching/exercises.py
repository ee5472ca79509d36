"""Exercise sheets with answer keys derived and certified by the library.

:func:`make_exercises` draws, from one seed, random DH robots (3 to
``max_joints`` joints, revolute and prismatic, standard or modified
convention) and random planar chains (2 to 4 revolute joints with limits),
and asks:

- robots: an entry of the end-point position, a column of the geometric
  Jacobian, the singular factors of the position Jacobian (3-joint robots),
  whether a point is reachable — with a witness configuration (the point is
  the exact image of angles in multiples of 30 degrees) or a proof (it lies
  beyond the sum of the DH link lengths, compared in exact arithmetic);
- chains: whether a point is reachable (proved either way by
  :func:`~workspace_sym.teaching.checks.check_reachable`: an exact witness or a
  Krawczyk existence proof, an exact reach bound or an interval exclusion;
  a point it leaves undecided is drawn again), the number
  of arcs of the workspace boundary and its area (certified bracket).

Every answer is computed here, never typed in.  The same seed gives the same
sheet.  :func:`write_exercises` writes the student sheet and the answer key
(Markdown, HTML, LaTeX) and ``key.json``, which ``workspace-sym grade`` reads.
"""

from __future__ import annotations

import json
import math
import time
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import sympy as sp

from ..document import Document
from ..errors import InvalidParameterError, SymbolicBudgetError
from ..files import write_files
from ..interval.driver import RunOn, StopAt
from ..kinematics import DHRobot
from ..numbers import fmt_bracket
from ..planar import PlanarChain
from ..progress import progress_bar
from ..symbolic import symbolic_budget
from .checks import check_reachable, exact_parameters
from .grading import KEY_FORMAT, tolerance_rule
from .options import refuse_run, refuse_stop

__all__ = ["make_exercises", "write_exercises", "exact_parameters", "reach_bound", "reachability_point",
           "MAX_COUNT", "AREA_DIGITS", "POINT_BOXES"]

#: Most problems on one sheet.
MAX_COUNT = 20
_LENGTHS = [sp.Rational(k, 20) for k in range(2, 11)]          # 0.1 .. 0.5
_COORD = ("x", "y", "z")
#: Significant digits asked for an area, stated on the sheet and applied by the key.
AREA_DIGITS = 3
#: Boxes the interval exclusion may spend on one drawn point of a chain (a point it leaves undecided is drawn
#: again): fixed, so that a seed gives the same sheet on every machine.
POINT_BOXES = 20_000
# (the key's entry, the answer as the key document shows it: text, a list of text and SymPy objects set inline, or a
# SymPy object displayed)
_Question = tuple[dict[str, Any], Any]
_P = sp.Symbol("p")


def _dh_description(rng, name: str, n: int) -> dict:
    """A random DH table in the JSON format of :meth:`DHRobot.from_dict` (degrees), lengths symbolic."""
    rows, params = [], {}
    kinds = ["R"] + [("P" if rng.random() < 0.25 else "R") for _ in range(n - 1)]
    for k, kind in enumerate(kinds, start=1):
        alpha = int(rng.choice([0, 90, -90]))
        a = f"a{k}" if rng.random() < 0.6 else 0
        row: dict[str, Any] = {"type": kind, "a": a, "alpha": alpha}
        if kind == "R":
            d = f"d{k}" if rng.random() < 0.4 else 0
            span = int(rng.choice([90, 120, 150, 180]))
            row.update(d=d, limits=[-span, span])
            if d:
                params[d] = str(_LENGTHS[int(rng.integers(len(_LENGTHS)))])
        else:
            row.update(theta=int(rng.choice([0, 90])), limits=["0", "1/2"])
        if a:
            params[a] = str(_LENGTHS[int(rng.integers(len(_LENGTHS)))])
        rows.append(row)
    convention = str(rng.choice(["standard", "modified"]))
    return {"name": name, "convention": convention, "angles": "degrees", "joints": rows, "parameters": params}


def _chain_description(rng) -> dict:
    p = int(rng.integers(2, 5))
    lengths = [str(_LENGTHS[int(rng.integers(len(_LENGTHS)))]) for _ in range(p)]
    lower, upper = [], []
    for _ in range(p):
        lo = int(rng.integers(-15, 1)) * 10
        hi = min(180, lo + int(rng.integers(6, 25)) * 10)
        lower.append(lo)
        upper.append(hi)
    return {"lengths": lengths, "lower": lower, "upper": upper}


def _interesting(exprs, rng):
    """Index of a random entry that depends on a joint angle (falls back to any nonzero entry)."""
    moving = [k for k, e in enumerate(exprs) if e.has(sp.sin, sp.cos)]
    pool = moving or [k for k, e in enumerate(exprs) if e != 0] or list(range(len(exprs)))
    return int(rng.choice(pool))


def reach_bound(robot: DHRobot, values: dict) -> sp.Expr:
    """Sum over the rows of ``|a| + max |d|``: by the triangle inequality no end point is farther from the origin.

    Parameters
    ----------
    robot : DHRobot
        The robot; a prismatic joint's ``d`` is taken at both its limits.
    values : dict
        Exact values of the robot's symbolic lengths (:func:`~workspace_sym.teaching.checks.exact_parameters`).

    Returns
    -------
    sympy.Expr
        The bound, exact.
    """
    total = sp.Integer(0)
    for j in robot.joints:
        a = abs(sp.sympify(j.a).subs(values))
        if j.kind == "P":
            lo, hi = j.limits
            d = max(abs(j.d.subs(j.variable, lo).subs(values)), abs(j.d.subs(j.variable, hi).subs(values)))
        else:
            d = abs(sp.sympify(j.d).subs(values))
        total += a + d
    return sp.nsimplify(total)


def reachability_point(robot: DHRobot, rng) -> tuple[list, bool, str, list | None]:
    """A point for a reachability question, with its certified answer: ``(point, reachable, why, witness)``.

    Either the exact image of a configuration within the limits (``witness``
    lists it, exact text: joint angles in multiples of 30 degrees, prismatic
    joints in multiples of 1/10, each decided within its limits in exact
    arithmetic, or the lower limit itself where no multiple lies within them)
    or a point beyond :func:`reach_bound`, compared in exact rationals
    (``witness`` None).

    Parameters
    ----------
    robot : DHRobot
        The robot, with its numeric lengths.
    rng : numpy.random.Generator
        The source of the draws (about half the points are reachable).

    Returns
    -------
    tuple
        ``(point, reachable, why, witness)``: three exact SymPy coordinates, the answer, the reason in words and
        the witness joint values as text (None for an unreachable point).
    """
    values = exact_parameters(robot)
    position = robot.position.subs(values)
    if rng.random() < 0.5:
        config = {}
        shown = []
        for j in robot.joints:
            q = _witness_value(j, rng)
            shown.append(f"{j.variable} = {sp.nsimplify(q * 180 / sp.pi)} deg" if j.kind == "R" else
                         f"{j.variable} = {q}")
            config[j.variable] = q
        # sines and cosines of multiples of 30 degrees evaluate to radicals: expanding gives the canonical form
        point = [sp.expand(position[i].subs(config)) for i in range(3)]
        return point, True, "witness configuration " + ", ".join(shown), [sp.sstr(config[j.variable])
                                                                          for j in robot.joints]
    bound = reach_bound(robot, values)
    direction = [int(v) for v in rng.integers(-3, 4, size=3)]
    if not any(direction):
        direction = [1, 0, 0]
    norm2 = sum(v * v for v in direction)
    scale = sp.Rational(math.ceil(float(bound) * 1.3 / math.sqrt(norm2) * 100) + 1, 100)
    point = [scale * v for v in direction]
    if not sum(p * p for p in point) > bound**2:        # exact rationals: the proof itself
        raise RuntimeError(f"point {point} is not beyond the reach bound {bound}")  # pragma: no cover
    return point, False, (f"|p|^2 = {sum(p * p for p in point)} > {bound**2} = (sum of |a_k| + max |d_k|)^2, "
                          "and no end point is farther than that sum (triangle inequality over the DH rows)"), None


def _witness_value(joint, rng):
    """A value of ``joint`` within its limits, decided exactly: a multiple of 30 degrees (revolute) or of 1/10
    (prismatic) drawn among those the limits hold, else the lower limit itself (an unlimited revolute joint takes
    the whole turn; an unlimited prismatic one the multiples of 1/10 from 0 to 1/2)."""
    unit = sp.pi / 6 if joint.kind == "R" else sp.Rational(1, 10)
    if joint.limits is None:
        lo, hi = (-sp.pi, sp.pi) if joint.kind == "R" else (sp.S.Zero, sp.Rational(1, 2))
    else:
        lo, hi = joint.limits
    first, last = int(sp.ceiling(lo / unit)), int(sp.floor(hi / unit))
    steps = [k for k in range(max(first, -60), min(last, 60) + 1) if bool(lo <= k * unit) and bool(k * unit <= hi)]
    return int(rng.choice(steps)) * unit if steps else lo


def _chain_point(chain: PlanarChain, rng):
    for _ in range(20):
        r = float(rng.uniform(0, 1.1 * chain.reach))
        phi = float(rng.uniform(-math.pi, math.pi))
        point = [sp.Rational(round(r * math.cos(phi), 3)).limit_denominator(1000),
                 sp.Rational(round(r * math.sin(phi), 3)).limit_denominator(1000)]
        # the exact point (text of a rational), decided only with a proof: points within tolerance are drawn again
        verdict = check_reachable(chain, [sp.sstr(v) for v in point], stop=StopAt(max_boxes=POINT_BOXES))
        why = verdict.message.split(": ", 1)[-1]
        if verdict.ok is True:
            return point, True, why, [float(t) for t in verdict.evidence["configuration"]], verdict
        if verdict.ok is False:
            return point, False, why, None, verdict
    raise RuntimeError("no decidable point found in 20 draws")  # pragma: no cover - the disc is mostly decidable


def _position_jacobian_at_random(robot, rng) -> sp.Matrix:
    """The 3 x n position Jacobian at random values of the joints and lengths, 30 digits (from the product of
    the DH matrices, unsimplified: cheap for a robot that is drawn again)."""
    values = {x: sp.Float(sp.Rational(int(rng.integers(-2000, 2000)) + 7, 1000), 30)
              for x in sorted(robot.symbols | set(robot.q), key=str)}
    return robot.raw_fk()[:3, 3].jacobian(robot.q).xreplace(values).evalf(30)


def _can_answer(robot, rng) -> bool:
    """Can the robot answer every question?  The end point must move with the joints (a non-zero entry of the
    position Jacobian at a random point), and a 3-joint robot needs a position-Jacobian determinant that is not
    identically zero (a non-zero value at a random point proves it) with a factor that depends on a joint.

    Robots whose determinant vanishes identically (modified DH with a revolute last joint: the origin of the
    last frame does not move with it; coaxial joints; a planar arm) or is a constant are drawn again; a value
    too small to prove anything also draws again, never a wrong key.
    """
    J = _position_jacobian_at_random(robot, rng)
    if not any(abs(e) > 1e-12 for e in J):
        return False
    if robot.n != 3:
        return True
    if abs(J.det()) <= 1e-12:
        return False
    return any(f.free_symbols & set(robot.q) for f in robot.singular_factors("position"))


def _robot_problem(rng, number: int, n: int) -> tuple[dict, DHRobot, list[_Question]]:
    """A DH robot and its questions (prompt, key entry, key display).

    Robots that cannot answer a question are drawn again: the end point must
    move with the joints, and a 3-joint robot must have a position Jacobian
    whose determinant is not identically zero and depends on the joints.
    """
    name = f"R{number}"
    for _ in range(100):
        spec = _dh_description(rng, name, n)
        robot = DHRobot.from_dict(spec, name=name)
        if _can_answer(robot, rng):
            break
    else:  # pragma: no cover - about half of the random robots qualify
        raise RuntimeError("no robot able to answer every question in 100 draws")
    questions: list[_Question] = []
    i = _interesting(list(robot.position), rng)
    entry = robot.position[i]
    questions.append(({"kind": "expression", "answer": robot.to_str(entry),
                       "prompt": f"Give the {_COORD[i]} coordinate of the end point (origin of the last frame) "
                                 f"as a function of the joint variables and the symbolic lengths."},
                      robot.shorthand(entry)))
    J = robot.geometric_jacobian
    k = int(rng.integers(robot.n))
    column = J[:, k]
    questions.append(({"kind": "expression", "answer": "[" + ", ".join(robot.to_str(e) for e in column) + "]",
                       "prompt": f"Give column {k + 1} of the geometric Jacobian [v; omega] "
                                 f"(6 entries, as a list [e1, ..., e6])."},
                      robot.shorthand(column)))
    if robot.n == 3:
        factors = robot.singular_factors("position")
        questions.append(({"kind": "factors", "answer": [robot.to_str(f) for f in factors],
                           "prompt": "List the factors of the determinant of the 3 x 3 position Jacobian "
                                     "(comma-separated; constant multiples do not matter)."},
                          [part for f in factors for part in (", ", robot.shorthand(f))][1:]))
    point, reachable, why, witness = reachability_point(robot, rng)
    shown = "(" + ", ".join(sp.sstr(p) for p in point) + ")"
    if reachable:
        answer: Any = "yes: " + why
    else:   # the proof of reachability_point, typeset
        bound = reach_bound(robot, exact_parameters(robot))
        answer = ["no: ", sp.Eq(sp.Abs(_P) ** 2, sum(p * p for p in point), evaluate=False), " > ", bound**2,
                  ", the square of the sum over the DH rows of ", sp.Abs(sp.Symbol("a_k")), " + max ",
                  sp.Abs(sp.Symbol("d_k")), ", and no end point is farther than that sum (triangle inequality)"]
    questions.append(({"kind": "reachable", "answer": reachable, "evidence": why,
                       "point": [sp.sstr(p) for p in point], "witness": witness,
                       "prompt": f"With the numeric lengths and the joint limits, can the end point reach "
                                 f"{shown}? Answer yes or no."}, answer))
    return spec, robot, questions


def _split_circles(boundary) -> bool:
    """Do two consecutive arcs of a loop lie on one circle (centre and radius within 1e-9 x reach)?  Such arcs
    (mirror configurations tracing the same circle) are one arc to the eye and two to the alignment method."""
    tol = 1e-9 * boundary.chain.reach
    for loop in boundary.loops:
        arcs = [boundary.arcs[k] for k in loop.arcs]
        for a, b in zip(arcs, arcs[1:] + arcs[:1]):
            if a is not b and abs(a.radius - b.radius) <= tol and math.dist(a.center, b.center) <= tol:
                return True
    return False


def _chain_problem(rng, number: int) -> tuple[str, dict, PlanarChain, list[_Question]]:
    name = f"C{number}"
    for _ in range(50):
        spec = _chain_description(rng)
        chain = PlanarChain(spec["lengths"], spec["lower"], spec["upper"])
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            boundary = chain.boundary()
        # a key holds certified answers only: a chain whose boundary comes with any doubt is drawn again, and so
        # is one whose arc count depends on how arcs are counted (two arcs in a row on one circle)
        if not caught and boundary.undecided_area == 0 and boundary.arcs and not _split_circles(boundary):
            break
    else:  # pragma: no cover - most random chains are clean
        raise RuntimeError("no chain with a fully certified boundary in 50 draws")
    point, reachable, why, witness, verdict = _chain_point(chain, rng)
    answer: Any = ("yes: " if reachable else "no: ") + why
    if verdict.evidence["method"] == "reach bound":      # check_reachable's proof, typeset
        answer = ["no: ", sp.Eq(sp.Abs(_P) ** 2, point[0] ** 2 + point[1] ** 2, evaluate=False),
                  " exceeds the square of the reach ", sum(chain.exact_lengths),
                  " (the sum of the lengths), in exact arithmetic"]
    lo, hi = boundary.area, boundary.area + boundary.undecided_area
    questions: list[_Question] = [
        ({"kind": "reachable", "answer": reachable, "evidence": why, "point": [sp.sstr(p) for p in point],
          "witness": witness,
          "prompt": f"Can the end point reach ({point[0]}, {point[1]})? Answer yes or no."}, answer),
        ({"kind": "integer", "answer": len(boundary.arcs), "unit": "arcs",
          "prompt": "How many circular arcs make up the boundary of the workspace?"}, f"{len(boundary.arcs)} arcs"),
        ({"kind": "measure", "answer": [lo, hi], "digits": AREA_DIGITS, "unit": "m^2",
          "prompt": f"What is the area of the workspace, in m²? Give {AREA_DIGITS} significant digits: an answer is "
                    f"accepted when it {tolerance_rule(digits=AREA_DIGITS).replace('value', 'area')}."},
         f"{lo:.6g} m²" if hi == lo else f"in {fmt_bracket(lo, hi, 6, 'g')} m²"),
    ]
    return name, spec, chain, questions


def make_exercises(*, seed: int, count: int, max_joints: int = 6, stop: StopAt = StopAt(), run: RunOn = RunOn()):
    """The sheet, the key (both :class:`~workspace_sym.document.Document`) and the machine-readable key (a dict).

    Problems alternate between DH robots (3 to ``max_joints`` joints) and
    planar chains.  Deterministic in ``seed``: a time limit never changes a
    sheet, which is made whole or not at all.

    Parameters
    ----------
    seed : int
        The seed (0 or more) every drawing is made from.
    count : int
        Number of problems, 1 to :data:`MAX_COUNT`.
    max_joints : int
        Most joints of a DH robot, 3 to 6.
    stop : :class:`~workspace_sym.interval.driver.StopAt`
        ``time_limit``: seconds for the whole sheet (None: no limit).  In the main thread of a POSIX process a
        timer also interrupts SymPy's own calls; elsewhere the derivations stop at their own checks of the
        deadline.  ``max_boxes`` and ``section_boxes`` do not apply and are refused: each proof of a drawn point
        has its fixed budget of :data:`POINT_BOXES` boxes, so that a seed gives the same sheet on every machine.
    run : :class:`~workspace_sym.interval.driver.RunOn`
        ``progress``: a bar over the problems (None: on an interactive output once the sheet has taken a second).
        The sheet is made in this process: the other fields are refused.

    Returns
    -------
    tuple
        ``(sheet, key_document, key)``: the student sheet, the answer key as a document, and the key as a
        dictionary (the JSON that ``workspace-sym grade`` reads).

    Raises
    ------
    InvalidParameterError
        A bad ``seed``, ``count``, ``max_joints``, ``stop`` or ``run``.
    SymbolicBudgetError
        The sheet not made within ``stop.time_limit`` (``parameter`` ``"time_limit"``).
    """
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise InvalidParameterError(f"seed must be a whole number >= 0; got {seed!r}", parameter="seed")
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= MAX_COUNT:
        raise InvalidParameterError(f"count must be a whole number from 1 to {MAX_COUNT}; got {count!r}",
                                    parameter="count")
    if isinstance(max_joints, bool) or not isinstance(max_joints, int) or not 3 <= max_joints <= 6:
        raise InvalidParameterError(f"max_joints must be 3 to 6; got {max_joints!r}", parameter="max_joints")
    refuse_stop("make_exercises", stop, ("time_limit",), f"stops on time only (the proof of a drawn point has its "
                                                         f"own budget of {POINT_BOXES} boxes)")
    refuse_run("make_exercises", run)
    shown = run.progress if run.progress is not None else stop.progress        # RunOn's, else the earlier spelling's
    with (progress_bar(shown, total=count, desc="exercise sheet", unit="problem") as bar,
          _within(stop.time_limit, f"the exercise sheet (seed {seed}, {count} problems)")):
        return _sheet(seed, count, max_joints, bar.update)


@contextmanager
def _within(time_limit: float | None, what: str):
    """The block within ``time_limit`` seconds (None: no limit): past it, one
    :class:`~workspace_sym.errors.SymbolicBudgetError` naming ``time_limit``.  A derivation's own budget spent
    earlier is its own error, as without a time limit."""
    if time_limit is None:
        yield
        return
    began = time.monotonic()
    try:
        with symbolic_budget(time_limit, what):
            yield
    except SymbolicBudgetError as exc:
        if time.monotonic() - began < time_limit:
            raise
        raise SymbolicBudgetError(f"time_limit: {what} was not made within the time limit of {time_limit:g} s (a "
                                  "sheet is made whole or not at all); allow more time or ask for fewer problems",
                                  parameter="time_limit") from exc


def _sheet(seed: int, count: int, max_joints: int, done):
    """:func:`make_exercises` once its options are checked; ``done(1)`` after each problem."""
    rng = np.random.default_rng(seed)
    title = f"Workspace exercises (seed {seed})"
    sheet, key_doc = Document(title), Document(f"Answer key: {title}")
    key: dict[str, Any] = {"format": KEY_FORMAT, "version": 1, "title": title, "seed": seed, "robots": {}, "chains": {},
           "questions": []}
    for number in range(1, count + 1):
        if number % 2:
            n = int(rng.integers(3, max_joints + 1))
            spec, robot, questions = _robot_problem(rng, number, n)
            key["robots"][robot.name] = spec
            subject = {"robot": robot.name}
            link = [_A_PREV, _ALPHA_PREV] if robot.convention == "modified" else [_A, _ALPHA]
            for doc in (sheet, key_doc):
                doc.heading(f"Problem {number}: a {robot.n}-joint robot ({robot.convention} DH)")
                doc.para(_CONVENTION_NOTE[robot.convention])
                doc.table(["joint i", "type", _THETA, _D, *link, "limits"],
                          [[str(k), j.kind, j.theta, j.d, j.a, j.alpha, _limits_text(j)]
                           for k, j in enumerate(robot.joints, start=1)])
                lengths = ", ".join(f"{s} = {v}" for s, v in spec["parameters"].items()) or "none"
                doc.para(f"Numeric values of the lengths: {lengths}. Write c23 for cos(theta2 + theta3), s1 for "
                         "sin(theta1), and so on.")
        else:
            name, spec, chain, questions = _chain_problem(rng, number)
            key["chains"][name] = spec
            subject = {"chain": name}
            for doc in (sheet, key_doc):
                doc.heading(f"Problem {number}: a planar chain of {chain.p} revolute joints")
                doc.para(f"Lengths (metres) {', '.join(spec['lengths'])}; joint limits (degrees, each angle "
                         f"measured from the previous segment, the first from +y): "
                         + ", ".join(f"[{lo}, {hi}]" for lo, hi in zip(spec["lower"], spec["upper"])) + ".")
        for letter, (entry, shown) in zip("abcdefg", questions):
            qid = f"{number}{letter}"
            key["questions"].append({"id": qid, **subject, **entry})
            sheet.para(f"({qid}) {entry['prompt']}")
            key_doc.para(f"({qid}) {entry['prompt']}")
            if isinstance(shown, str):
                key_doc.para(f"Answer: {shown}")
            elif isinstance(shown, list):
                key_doc.para(["Answer: ", *shown])
            else:
                key_doc.math("\\text{answer}", shown)
        done(1)
    return sheet, key_doc, key


def _frame(*moves) -> list:
    """The moves from frame i-1 to frame i, in words with inline mathematics (``Rz(theta_i) Tz(d_i) ...``)."""
    out: list = ["frame i follows frame i-1 by "]
    for k, (what, value, axis) in enumerate(moves):
        out += [", " if 0 < k < len(moves) - 1 else " and " if k else "", f"a {what} of ", value, f" about {axis}"
                if what == "turn" else f" along {axis}"]
    return out


_THETA, _D, _A, _ALPHA = sp.symbols("theta_i d_i a_i alpha_i")
_A_PREV, _ALPHA_PREV = sp.Symbol("a_i-1"), sp.Symbol("alpha_i-1")        # print as a_{i-1}, alpha_{i-1}
#: What a row of the DH table holds, said on the sheet (kinematics.dh_matrix; Craig 2005, section 3.4 for modified).
_CONVENTION_NOTE = {
    "standard": ["Standard DH: row i holds ", _THETA, ", ", _D, ", ", _A, " and ", _ALPHA, " of joint i; ",
                 *_frame(("turn", _THETA, "z"), ("move", _D, "z"), ("move", _A, "x"), ("turn", _ALPHA, "x")), "."],
    "modified": ["Modified (Craig) DH: row i holds ", _ALPHA_PREV, " and ", _A_PREV, ", the twist and length of the "
                 "link before joint i, then ", _THETA, " and ", _D, " of joint i; ",
                 *_frame(("turn", _ALPHA_PREV, "x"), ("move", _A_PREV, "x"), ("turn", _THETA, "z"), ("move", _D, "z")),
                 "."],
}


def _limits_text(joint) -> str:
    lo, hi = joint.limits
    if joint.kind == "R":
        return f"[{sp.sstr(lo * 180 / sp.pi)}, {sp.sstr(hi * 180 / sp.pi)}] deg"
    return f"[{lo}, {hi}]"


def write_exercises(out, *, seed: int, count: int, max_joints: int = 6, stop: StopAt = StopAt(),
                    run: RunOn = RunOn()) -> dict:
    """Write ``sheet.{md,html,tex}``, ``key.{md,html,tex}``, ``key.json`` and ``answers-template.csv`` into
    ``out``; return the paths.  Everything is computed before the first file is written.

    Parameters
    ----------
    out : path
        The output directory (made when missing).
    seed, count, max_joints, stop, run
        As for :func:`make_exercises`.

    Returns
    -------
    dict
        The path of each file written, by its name.

    Raises
    ------
    InvalidParameterError
        As :func:`make_exercises`.
    SymbolicBudgetError
        The sheet not made within ``stop.time_limit``: nothing is written.
    OutputError
        ``out`` cannot be written.
    """
    sheet, key_doc, key = make_exercises(seed=seed, count=count, max_joints=max_joints, stop=stop, run=run)
    texts = {}
    for stem, doc in (("sheet", sheet), ("key", key_doc)):
        texts[f"{stem}.md"] = doc.markdown()
        texts[f"{stem}.html"] = doc.html(Path("."))
        texts[f"{stem}.tex"] = doc.latex()
    texts["key.json"] = json.dumps(key, indent=2) + "\n"
    texts["answers-template.csv"] = "student,question,answer\n" + "".join(
        f",{q['id']},\n" for q in key["questions"])
    return write_files(texts, out)
