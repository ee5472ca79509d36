"""Verification helpers for teaching: check a student's answer and say why it is right or wrong.

Every helper returns a :class:`Verdict` whose ``ok`` is True, False, or None
(undecided), with a sentence for the student and the evidence: an exact
identity, a counterexample configuration, a witness configuration, an interval
certificate, or a certified bracket.

One vocabulary, here, in grading (:mod:`workspace_sym.teaching.grading`) and in the
exercise keys (:mod:`workspace_sym.teaching.exercises`): a verdict's ``status`` is
*correct* or *wrong* only with a proof (``evidence["method"]`` names it:
``exact identity``, ``counterexample``, ``exact witness``, ``interval
existence proof``, ``reach bound``, ``interval exclusion``, ``certified
key``), else *undecided* (``within tolerance``: a numeric witness within
``t`` times the reach, "within tolerance t of the workspace, not decided";
``undecided``: nothing found), *cannot read*, *cannot check* (over its time
budget) or *not graded* (the batch ran out of time).  A key holds proved
answers only.  Two helpers judge otherwise: :func:`check_boundary_arc`
compares sampled points with the computed boundary in floats within a
tolerance (``"boundary test"``, the boundary's own standard), and
:func:`check_measure` places a number in a certified bracket (its evidence
is the bracket).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import sympy as sp

from ..errors import ExpressionError, InvalidParameterError
from ..expressions import as_sympy, parse_expr
from ..interval.driver import StopAt
from ..interval.graph import numpy_constant
from ..interval.image import ImageMap
from ..numbers import fmt_bracket
from ..planar.boundary import prove_unreachable, witness_near
from ..planar.chain import read_value
from ..planar.exact import is_zero, link_direction
from ..snap import exact_decimal
from ..symbolic import trig_polynomials
from .answers import Notation, read_answer, split_top_level
from .options import deprecated, refuse_stop

__all__ = ["Verdict", "cannot_read", "exact_parameters", "check_expression", "check_factors", "check_reachable",
           "check_boundary_arc", "check_measure",
           "assert_expression", "assert_factors", "assert_reachable", "assert_boundary_arc", "assert_measure",
           "REACH_TOLERANCE", "MAX_BOXES"]


#: Statuses of an answer without a verdict (``ok`` None), by the reason.
_UNGRADED = ("cannot read", "cannot check", "not graded", "no answer", "duplicate")


@dataclass
class Verdict:
    """A judgement with its evidence.

    ``ok`` is True (correct), False (wrong) or None: undecided, or the answer
    could not be read (``evidence["method"]`` is ``"cannot read"`` and
    ``evidence["position"]`` the column of the problem when known), or it was
    not checked within its time budget (``"cannot check"``), or a batch ran
    out of time before it (``"not graded"``), or it is blank (``"no answer"``)
    or a student's second answer to one question (``"duplicate"``).

    Parameters
    ----------
    ok : bool or None
        The judgement.
    message : str
        The sentence for the student.
    evidence : dict, optional
        What the judgement rests on: ``"method"`` and the method's data (a counterexample, a witness, a
        bracket...).
    """

    ok: bool | None
    message: str
    evidence: dict = field(default_factory=dict)

    def __bool__(self):
        return bool(self.ok)

    @property
    def status(self) -> str:
        """``"correct"``, ``"wrong"``, ``"cannot read"``, ``"cannot check"``, ``"not graded"``, ``"no answer"``,
        ``"duplicate"`` or ``"undecided"``.

        Returns
        -------
        str
            The status: from ``ok``, or for ``ok`` None from ``evidence["method"]`` when it names a reason.
        """
        if self.ok is None:
            method = self.evidence.get("method")
            return method if method in _UNGRADED else "undecided"
        return "correct" if self.ok else "wrong"

    def _repr_markdown_(self):
        return f"**{self.status}**: {self.message}"

    def __repr__(self):
        text = " ".join(self.message.split())
        return f"Verdict({self.status}: {text if len(text) <= 72 else text[:71] + '...'})"


def _number(value, name: str) -> float:
    """A student's number: text through parse_expr (``"pi/4"``, no symbols), anything else through float()."""
    if isinstance(value, str):
        value = parse_expr(value, name, new_symbols=False)
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"{name} must be a real number; got {value!r:.60}") from None


def cannot_read(exc: ExpressionError) -> Verdict:
    """The verdict on an answer that could not be read: the reason, and where.

    Parameters
    ----------
    exc : ExpressionError
        The reader's error.

    Returns
    -------
    Verdict
        ``ok`` None, the error's message on one line, ``evidence`` ``{"method": "cannot read", "position": ...}``
        (the 1-based column, or None).
    """
    message = " ".join(str(exc).split())
    return Verdict(None, message, {"method": "cannot read", "position": getattr(exc, "position", None)})


def _notation(robot, symbols) -> Notation:
    """The robot's names, or those of ``symbols`` when there is no robot."""
    if robot is not None:
        return Notation.from_robot(robot)
    return Notation.from_symbols(symbols)


def _read_student(student, notation, angles):
    """The student's answer as SymPy; text through :func:`~workspace_sym.teaching.answers.read_answer`."""
    if isinstance(student, str):
        return read_answer(student, notation, angles=angles, parameter="student answer")
    if isinstance(student, (list, tuple)):
        return sp.Matrix([_read_student(s, notation, angles) for s in student])
    return as_sympy(student, "student answer")


def _decimal(v: sp.Rational) -> str:
    """A rational as the decimal it is when it has one (``7/20`` is ``0.35``, as a sheet prints it), else as is."""
    q = int(v.q)
    while q % 2 == 0:
        q //= 2
    while q % 5 == 0:
        q //= 5
    if q != 1:
        return str(v)
    from decimal import Decimal

    return format(Decimal(int(v.p)) / Decimal(int(v.q)), "f")


def exact_parameters(robot) -> dict:
    """The robot's numeric lengths as the decimals they print as (``0.387`` is ``387/1000``): points stay exact.

    Parameters
    ----------
    robot : DHRobot
        The robot, read for its numeric ``parameters``.

    Returns
    -------
    dict
        Parameter -> exact SymPy number.
    """
    return {k: exact_decimal(v) if isinstance(v, float) else sp.nsimplify(v) for k, v in robot.parameters.items()}


def _question_data(robot) -> dict:
    """The data of a question on ``robot`` (keywords of :func:`_scalar_verdict`): its numeric lengths (exact), the
    range of each joint variable (its limits, else half a turn either way) and which variables are angles."""
    if robot is None:
        return {}
    ranges = {j.variable: (float(lo), float(hi)) for j, (lo, hi) in zip(robot.joints, robot.joint_limits())}
    return {"data": exact_parameters(robot), "ranges": ranges,
            "angles": frozenset(j.variable for j in robot.joints if j.kind == "R")}


def _scalar_verdict(s, d, *, samples, seed, where: str = "", data=None, ranges=None, angles=frozenset()):
    """Exact identity, or a counterexample where every symbol has a value: first the question's ``data`` (the
    robot's lengths) with joint values drawn within ``ranges``, then, if the two agree at the data, any values;
    ``angles`` are shown in radians."""
    diff = s - d
    (poly,), _ = trig_polynomials([diff])
    if sp.expand(poly) == 0:
        return Verdict(True, f"equal{where}: the difference reduces to 0 after expanding and sin^2 = 1 - cos^2",
                       {"method": "exact identity"})
    symbols = sorted(s.free_symbols | d.free_symbols, key=str)     # every symbol: both values are numbers
    data, ranges = data or {}, ranges or {}
    rng = np.random.default_rng(seed)

    def draw(x, at_data: bool):
        if at_data and x in data:
            return data[x]
        lo, hi = ranges.get(x, (-3.0, 3.0)) if at_data else (-3.0, 3.0)
        return sp.Rational(int(rng.integers(math.ceil(lo * 1000), math.floor(hi * 1000) + 1)), 1000)

    for k in range(samples):
        at_data = k < samples // 2 and bool(data or ranges)
        values = {x: draw(x, at_data) for x in symbols}
        value = sp.N(diff.subs(values), 30)
        if value.is_number and abs(value) > 1e-20:
            shown = {str(x): v for x, v in values.items()}
            mine, theirs = sp.N(s.subs(values), 30), sp.N(d.subs(values), 30)
            at = ", ".join(f"{x} = {_decimal(v)}{' rad' if x in angles else ''}" for x, v in values.items())
            return Verdict(False, f"not equal{where}: at {at} the answer is {sp.N(mine, 6)} but the derived "
                                  f"value is {sp.N(theirs, 6)}",
                           {"method": "counterexample", "counterexample": shown, "difference": float(value),
                            "student_value": str(mine), "derived_value": str(theirs)})
    return Verdict(None, f"no counterexample found{where}, but the expressions are not identical after expansion "
                         "(are some angles dependent?)", {"method": "undecided", "residual": str(poly)})


def check_expression(student, derived, *, robot=None, angles: str = "radians", samples: int = 50,
                     seed: int = 0) -> Verdict:
    """Is the student's expression (or matrix) identically equal to the derived one?

    Exact test: the difference, with every sine and cosine of a sum expanded
    and ``sin^2 = 1 - cos^2`` applied, is a polynomial in ``c_u, s_u`` of
    degree at most one in each ``s_u``; for independent angle symbols it
    vanishes identically exactly when that polynomial is zero.  When it is not
    zero, a counterexample is searched among random rational values of the
    symbols (with a robot: at its numeric lengths, the joints within their
    limits, first) and confirmed at 30 digits; every symbol of both
    expressions gets a value, so the verdict gives both values as numbers.
    A matrix is checked entry by entry and the first wrong entry is named.

    Text is read by :func:`~workspace_sym.teaching.answers.read_answer` with the
    names of ``robot`` (or, without one, of the symbols of ``derived``):
    textbook shorthand ``c1``, ``s23``, ``c_{234}``, ``C1``; ``q1``, ``t1``
    for ``theta1``; juxtaposition ``c1 (a1 + a2 c2)``; LaTeX; ``[e1, e2,
    e3]`` for a column.  Nothing of it is evaluated as Python; text that
    cannot be read gets a *cannot read* verdict (``ok`` None) naming the
    problem and its column, never an exception.

    Parameters
    ----------
    student : str, SymPy expression or matrix, or sequence
        The student's answer (a sequence is a column).
    derived : str, sympy.Expr or sympy.Matrix
        The right answer; text is read by :func:`~workspace_sym.expressions.parse_expr`.
    robot : DHRobot, optional
        The robot the question is about: its names, numeric lengths and joint limits.
    angles : {"radians", "degrees"}, default "radians"
        How the student's numbers inside sin, cos and tan are read.
    samples : int, default 50
        Random points tried for a counterexample (per entry of a matrix).
    seed : int, default 0
        Seed of those points.

    Returns
    -------
    Verdict
        ``ok`` True (exact identity), False (a counterexample, or a wrong shape) or None (no counterexample
        found, or the answer cannot be read).

    Raises
    ------
    ExpressionError
        When ``derived`` (the teacher's text) cannot be read.
    UnknownNameError
        When ``angles`` is neither ``"radians"`` nor ``"degrees"``.

    Examples
    --------
    >>> check_expression("cos(t1)*cos(t2) - sin(t1)*sin(t2)", "cos(t1 + t2)").ok
    True
    >>> check_expression("c1 c2 - s1 s2", "cos(t1 + t2)").ok
    True
    >>> v = check_expression("cos(t1)*cos(t2) + sin(t1)*sin(t2)", "cos(t1 + t2)")
    >>> v.status, sorted(v.evidence["counterexample"])
    ('wrong', ['t1', 't2'])
    >>> v = check_expression("cos(t1)*cos(t3)", "cos(t1 + t2)")
    >>> v.status, v.evidence["position"]
    ('cannot read', 13)
    """
    d = parse_expr(derived, "derived") if not isinstance(derived, sp.MatrixBase) else derived
    notation = _notation(robot, d.free_symbols)
    data = _question_data(robot)
    try:
        s = _read_student(student, notation, angles)
    except ExpressionError as exc:
        return cannot_read(exc)
    if isinstance(d, sp.MatrixBase) or isinstance(s, sp.MatrixBase):
        if not (isinstance(d, sp.MatrixBase) and isinstance(s, sp.MatrixBase)):
            expected = f"a {d.rows} x {d.cols} matrix" if isinstance(d, sp.MatrixBase) else "one expression"
            return Verdict(False, f"expected {expected}", {"method": "shape"})
        if s.shape != d.shape and not (1 in s.shape and 1 in d.shape and len(s) == len(d)):
            return Verdict(False, f"expected a {d.rows} x {d.cols} matrix, got {s.rows} x {s.cols}",
                           {"method": "shape"})
        s = s.reshape(d.rows, d.cols)
        for i in range(d.rows):
            for j in range(d.cols):
                where = f" (entry {i + 1},{j + 1})" if d.cols > 1 else f" (entry {i + 1})"
                v = _scalar_verdict(s[i, j], d[i, j], samples=samples, seed=seed, where=where, **data)
                if v.ok is not True:
                    v.evidence["entry"] = [i + 1, j + 1]
                    return v
        return Verdict(True, f"all {len(d)} entries are equal (exact identities)", {"method": "exact identity"})
    return _scalar_verdict(s, d, samples=samples, seed=seed, **data)


def _read_list(student, notation, angles) -> list:
    """A list of expressions: text split at top-level commas (``"s3, a2 c2 + a3 c23"``) or a sequence."""
    if not isinstance(student, str):
        return [_read_student(x, notation, angles) for x in student]
    pieces = [p for p, _ in split_top_level(student)]
    if all(not p.strip() for p in pieces):
        raise ExpressionError("student answer: expected a list of factors separated by commas, got nothing",
                              parameter="student answer")
    return [_read_student(p, notation, angles) for p in pieces if p.strip()]


def _proportional(g, f, *, seed: int = 0) -> bool:
    """Is ``g`` a nonzero constant times ``f``?  The constant is guessed at a random point, then proved exact."""
    symbols = sorted(f.free_symbols | g.free_symbols, key=str)
    rng = np.random.default_rng(seed)
    for _ in range(5):
        point = {x: sp.Rational(int(rng.integers(-3000, 3000)), 1000) for x in symbols}
        fv = sp.N(f.subs(point), 40)
        if fv.is_number and abs(fv) > 1e-12:
            ratio = sp.nsimplify(sp.N(g.subs(point), 40) / fv, tolerance=1e-25, rational=False)
            return ratio != 0 and _scalar_verdict(g, ratio * f, samples=5, seed=seed).ok is True
    return False


def check_factors(student, derived, *, robot=None, angles: str = "radians", seed: int = 0) -> Verdict:
    """Are the student's singular factors those derived, each up to a nonzero constant factor?

    ``student`` is text (factors separated by commas, in any notation that
    :func:`check_expression` reads) or a sequence; ``derived`` the list of
    factors (e.g. ``robot.singular_factors()``).  Each derived factor must
    match one of the student's (``g = k f`` for a constant ``k``, proved as
    an exact identity) and each of the student's factors one derived.

    Parameters
    ----------
    student : str or sequence
        The student's factors.
    derived : sequence
        The derived factors (SymPy expressions, or text read by :func:`~workspace_sym.expressions.as_sympy`).
    robot : DHRobot, optional
        The robot, for its names; by default the names of the derived factors' symbols.
    angles : {"radians", "degrees"}, default "radians"
        How the student's numbers inside sin, cos and tan are read.
    seed : int, default 0
        Seed of the point where each constant ratio is guessed.

    Returns
    -------
    Verdict
        ``ok`` True when the factors match both ways, False with ``evidence["missing"]`` and
        ``evidence["extra"]`` otherwise, None when the answer cannot be read.

    Examples
    --------
    >>> t2, t3, a2, a3 = sp.symbols("theta2 theta3 a2 a3")
    >>> derived = [sp.sin(t3), a2*sp.cos(t2) + a3*sp.cos(t2 + t3)]
    >>> check_factors("s3, -(a2 c2 + a3 c23)", derived).ok
    True
    >>> v = check_factors("s3", derived)
    >>> v.status, v.evidence["missing"]
    ('wrong', ['a2*cos(theta2) + a3*cos(theta2 + theta3)'])
    """
    derived = [as_sympy(f, "derived factor") for f in derived]
    symbols = set().union(*(f.free_symbols for f in derived)) if derived else set()
    notation = _notation(robot, symbols)
    try:
        given = _read_list(student, notation, angles)
    except ExpressionError as exc:
        return cannot_read(exc)
    matched = [[_proportional(g, f, seed=seed) for f in derived] for g in given]
    missing = [str(f) for j, f in enumerate(derived) if not any(row[j] for row in matched)]
    extra = [str(g) for g, row in zip(given, matched) if not any(row)]
    if not missing and not extra:
        match = ("the factor matches (up to a constant, an exact identity)" if len(derived) == 1 else
                 f"the {len(derived)} factors match (each up to a constant, exact identities)")
        return Verdict(True, match, {"method": "exact identity"})
    parts = ([f"missing {', '.join(missing)}"] if missing else []) + (
        [f"not a singular factor: {', '.join(extra)}"] if extra else [])
    return Verdict(False, "; ".join(parts), {"method": "factor match", "missing": missing, "extra": extra})


#: Points whose nearest numeric witness is within this times the reach, and which nothing proves either way,
#: are "within tolerance" (undecided), never reachable.
REACH_TOLERANCE = 1e-10
#: Boxes the interval exclusion of :func:`check_reachable` may evaluate when ``stop`` gives no ``max_boxes``.
MAX_BOXES = 500_000
_SNAP = 1e-3            # radians: a witness angle this close to a limit or a multiple of 15 deg is tried exactly
                        # (near a stretched or folded chain an end point 1e-10 away leaves the angles ~1e-5 off)


def _chain_image(chain):
    """The chain's end point as an :class:`~workspace_sym.interval.image.ImageMap` of its joints (exact lengths
    and limits), built once per chain."""
    if "_image_map" not in chain.__dict__:
        theta = sp.symbols(f"theta1:{chain.p + 1}")
        phi = np.cumsum(np.array(theta, dtype=object))
        end = sum((L * link_direction(a) for L, a in zip(chain.exact_lengths, phi)), sp.zeros(2, 1))
        chain._image_map = ImageMap(list(end), theta, list(zip(chain.exact_lower, chain.exact_upper)),
                                    [False] * chain.p)
    return chain._image_map


def _exact_witness(chain, theta, target) -> list | None:
    """Exact joint values near ``theta`` (each a limit or a multiple of 15 degrees) whose end point is exactly
    ``target``, proved in exact arithmetic; None when there are none."""
    config = []
    for t, lo, hi in zip(theta, chain.exact_lower, chain.exact_upper):
        k = round(t / (math.pi / 12))
        best = min((lo, hi, k * sp.pi / 12), key=lambda c: abs(float(c) - t))
        if abs(float(best) - t) > _SNAP or not (bool(lo <= best) and bool(best <= hi)):
            return None
        config.append(best)
    phi = np.cumsum(np.array(config, dtype=object))
    end = sum((L * link_direction(a) for L, a in zip(chain.exact_lengths, phi)), sp.zeros(2, 1))
    return config if all(is_zero(end[i] - target[i]) for i in range(2)) else None


def _proved_inside(chain, theta, target):
    """Krawczyk's test (:meth:`ImageMap.prove_inside_at`) around ``theta`` refined by Newton's method: the
    refined configuration when some configuration within the joint limits near it provably reaches every point
    of a box of floats enclosing the exact ``target``, else None."""
    image = _chain_image(chain)
    T = np.array([[numpy_constant(v) for v in target]], dtype=float)
    q, _ = image.newton(0.5 * (T[:, :, 0] + T[:, :, 1]), np.asarray(theta, dtype=float)[None])
    return q[0] if image.prove_inside_at(T, q)[0] else None


def check_reachable(chain, point, *, stop: StopAt = StopAt(), seed: int = 0, tol: float = REACH_TOLERANCE,
                    max_boxes: int | None = None) -> Verdict:
    """Can the planar ``chain`` reach ``point``?  Decided only by a proof, else said to be undecided.

    The point is read exactly (a float as the decimal it prints as, text
    such as ``"1/3"`` exactly, as :class:`~workspace_sym.planar.PlanarChain`
    reads lengths).  Verdicts (``evidence["method"]``):

    - reachable (``ok`` True): ``"exact witness"``, joint values within the
      limits (limits, multiples of 15 degrees) whose end point equals the
      point in exact arithmetic; or ``"interval existence proof"``, Krawczyk's
      test (outward-rounded) proving that a configuration within the limits
      near the numeric witness reaches the point exactly;
    - unreachable (``ok`` False): ``"reach bound"``, ``|point|`` exceeds the
      sum of the lengths in exact arithmetic; or ``"interval exclusion"``
      (:func:`~workspace_sym.planar.boundary.prove_unreachable`);
    - undecided (``ok`` None): ``"within tolerance"``, a configuration
      reaches a point within ``tol`` times the reach but nothing proves the
      point reached or not (a numeric witness is never a proof); or
      ``"undecided"``, no witness and no proof within ``stop.max_boxes``.

    Parameters
    ----------
    chain : PlanarChain
        The planar chain, with its joint limits.
    point : pair of numbers or text
        ``(x, y)``, each a number or text such as ``"1/3"``, read exactly.
    stop : :class:`~workspace_sym.interval.driver.StopAt`
        ``max_boxes``: the boxes the interval exclusion may evaluate, the one box search of the call (None:
        :data:`MAX_BOXES`).  ``time_limit`` and ``section_boxes`` do not apply and are refused; ``progress`` shows
        nothing (the search has no bar).
    seed : int
        Seed of the numeric search for a witness configuration.
    tol : float
        Points a configuration reaches within ``tol`` times the reach, and which nothing proves either way, are
        *within tolerance* (undecided).
    max_boxes : int, optional
        Deprecated: ``stop=StopAt(max_boxes=...)`` (taken with a :class:`DeprecationWarning`).

    Returns
    -------
    Verdict
        ``ok`` True (proved reachable), False (proved unreachable) or None, with the method and its evidence.

    Raises
    ------
    InvalidParameterError
        A point that is not two finite real numbers; a ``stop`` that is not a ``StopAt`` or sets a time limit.
    ExpressionError
        Text of the point outside the expression grammar.

    Examples
    --------
    >>> from workspace_sym.planar import PlanarChain
    >>> arm = PlanarChain(["1", "1"], [-90, -90], [90, 90])
    >>> [check_reachable(arm, p).evidence["method"] for p in [(2, 0), (2 + 1e-10, 0), (0.5, 1.5), (0.5, 1.2)]]
    ['exact witness', 'reach bound', 'interval existence proof', 'interval exclusion']
    """
    if max_boxes is not None:
        deprecated("check_reachable", "max_boxes", "stop=StopAt(max_boxes=...)")
        stop = replace(stop, max_boxes=max_boxes)
    refuse_stop("check_reachable", stop, ("max_boxes",), "stops on boxes only (its interval exclusion)")
    boxes = MAX_BOXES if stop.max_boxes is None else stop.max_boxes
    flat = list(np.ravel(np.asarray(point, dtype=object)))
    if len(flat) != 2:
        raise InvalidParameterError(f"point must be two numbers (x, y); got {point!r:.60}", parameter="point")
    read = [read_value(v, "point") for v in flat]
    q, target = np.array([f for f, _ in read]), [e for _, e in read]
    reach = sum(chain.exact_lengths)
    if sp.expand(target[0] ** 2 + target[1] ** 2 - reach**2).is_positive:
        return Verdict(False, f"unreachable: |p|^2 = {sp.sstr(target[0] ** 2 + target[1] ** 2)} exceeds the square "
                              f"of the reach {sp.sstr(reach)} (the sum of the lengths), in exact arithmetic",
                       {"method": "reach bound"})
    theta, err = witness_near(chain, q, seed=seed, k=64, iterations=100)
    theta, err = theta[0], float(err[0])
    deg = [round(math.degrees(t), 6) for t in theta]
    found = {"configuration": theta.tolist(), "distance": err}
    if err <= 1e-6 * chain.reach:
        config = _exact_witness(chain, theta, target)
        if config is not None:
            shown = ", ".join(sp.sstr(c * 180 / sp.pi) for c in config)
            return Verdict(True, f"reachable: theta = ({shown}) deg, within the limits, reaches it exactly "
                                 "(exact arithmetic)",
                           {"method": "exact witness", "configuration": [float(c) for c in config], "distance": 0.0,
                            "exact_configuration": [sp.sstr(c) for c in config]})
        refined = _proved_inside(chain, theta, target)
        if refined is not None:
            deg = [round(math.degrees(t), 6) for t in refined]
            return Verdict(True, f"reachable: an interval Newton (Krawczyk) test proves that a configuration "
                                 f"within the limits near theta = {deg} deg reaches it exactly",
                           {"method": "interval existence proof", "configuration": refined.tolist(),
                            "distance": float(np.hypot(*(chain.forward(refined) - q)))})
    if prove_unreachable(chain, q, max_boxes=boxes):
        return Verdict(False, "unreachable: interval arithmetic shows that no configuration within the joint "
                              "limits reaches this point", {"method": "interval exclusion"})
    if err <= tol * chain.reach:
        return Verdict(None, f"within tolerance {tol:g} x reach of the workspace, not decided: theta = {deg} deg "
                             f"reaches a point {err:.1e} away, but neither an exact witness, an interval existence "
                             "proof nor a proof of the contrary was found",
                       {"method": "within tolerance", "tolerance": tol, **found})
    return Verdict(None, f"undecided: no witness found and no proof within {boxes} boxes "
                         "(the point may be very close to the boundary)", {"method": "undecided"})


def check_boundary_arc(chain, center, radius, start_angle, end_angle, *, tol: float = 1e-6,
                       points: int = 9) -> Verdict:
    """Does the claimed arc (centre, radius, polar angles in radians, counter-clockwise) lie on the boundary?

    Sample points of the claim are tested against the computed boundary within
    ``tol`` times the reach; the verdict names the first point that is not.
    The test is float geometry with that tolerance (the standard of the
    boundary itself, :mod:`workspace_sym.planar.boundary`), not a proof:
    ``evidence["method"]`` is ``"boundary test"``.

    Parameters
    ----------
    chain : PlanarChain
        The chain; its boundary is computed (or reused).
    center : pair of numbers or text
        The claimed centre ``(x, y)``; text such as ``"1/2"`` is read by the restricted grammar.
    radius : number or text
        The claimed radius, positive.
    start_angle, end_angle : number or text
        Polar angles about the centre where the arc starts and ends (radians).
    tol : float, default 1e-6
        Distance from the boundary, relative to the reach, within which a point is on it.
    points : int, default 9
        Points sampled along the claim, ends included.

    Returns
    -------
    Verdict
        ``ok`` True when every sampled point is on the boundary, False naming the first that is not.

    Raises
    ------
    InvalidParameterError
        When a number is not real, or ``radius`` is not positive.
    ExpressionError
        When a number given as text cannot be read.
    BoundaryError
        When the chain's boundary cannot be computed reliably.
    """
    b = chain.boundary()
    c = np.array([_number(v, "center") for v in np.ravel(np.asarray(center, dtype=object))]).reshape(2)
    radius, start_angle, end_angle = (_number(v, n) for v, n in ((radius, "radius"), (start_angle, "start_angle"),
                                                                  (end_angle, "end_angle")))
    if not radius > 0:
        raise InvalidParameterError(f"radius must be positive; got {radius!r}")
    angles = np.linspace(start_angle, end_angle, points)
    pts = c + radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    verdicts = b.classify(pts, tol=tol)
    bad = np.flatnonzero(verdicts != "boundary")
    if not len(bad):
        return Verdict(True, f"all {points} sampled points of the arc lie on the boundary (within {tol:g} x reach)",
                       {"method": "boundary test", "points": pts.tolist()})
    k = int(bad[0])
    return Verdict(False, f"the point at angle {angles[k]:.6f} rad, {pts[k].round(6).tolist()}, is {verdicts[k]} "
                          "the workspace, not on its boundary", {"method": "boundary test", "point": pts[k].tolist(),
                                                                 "where": str(verdicts[k])})


def check_measure(claimed: float, result, *, rel_tol: float = 0.0) -> Verdict:
    """Does a claimed area or volume fall inside the certified bracket of ``result``?

    ``result`` is a :class:`~workspace_sym.boundary.Boundary` (bracket: the
    area, widened by undecided faces), a :class:`~workspace_sym.interval.Paving`
    (``measure_bounds``) or an Orthoglide ``DextrousResult`` (inside volume,
    inside + E).  ``rel_tol`` widens the bracket for rounded answers.

    Parameters
    ----------
    claimed : number or text
        The student's area or volume; text such as ``"pi/4"`` is read by the restricted grammar.
    result : Boundary, Paving or DextrousResult
        What the claim is checked against.
    rel_tol : float, default 0.0
        The bracket is widened on both sides by ``rel_tol`` times its larger end (in absolute value).

    Returns
    -------
    Verdict
        ``ok`` True when the claim lies in the (widened) bracket, False otherwise; ``evidence["bracket"]`` is
        ``[lo, hi]``.

    Raises
    ------
    InvalidParameterError
        When ``claimed`` is not a finite real number or ``result`` is of another type.
    ExpressionError
        When ``claimed`` is text that cannot be read.
    """
    claimed = _number(claimed, "claimed")
    if not math.isfinite(claimed):
        raise InvalidParameterError(f"claimed must be a finite number; got {claimed!r}")
    float_error = 0.0               # a certified bracket is taken as it is; a float area gets 1e-12 either side
    if hasattr(result, "loops"):
        lo, hi = result.area, result.area + result.undecided_area
        what = "area from the exact boundary"
        float_error = 1e-12 * max(1.0, abs(hi))
    elif hasattr(result, "measure_bounds"):
        lo, hi = result.measure_bounds
        what = "certified paving bracket"
    elif hasattr(result, "volume_inner"):
        lo, hi = result.paving.measure_bounds
        what = "certified dextrous-volume bracket"
    else:
        raise InvalidParameterError(f"result must be a Boundary, a Paving or a DextrousResult; "
                                    f"got {type(result).__name__}")
    slack = rel_tol * max(abs(lo), abs(hi)) + float_error
    if lo - slack <= claimed <= hi + slack:
        return Verdict(True, f"{claimed:g} lies in the {what} {fmt_bracket(lo, hi, 6, 'g')}", {"bracket": [lo, hi]})
    side = "below" if claimed < lo else "above"
    return Verdict(False, f"{claimed:g} is {side} the {what} {fmt_bracket(lo, hi, 6, 'g')}", {"bracket": [lo, hi]})


# ------------------------------------------------------------------------------ assertions for autograders
def _assert(verdict: Verdict) -> Verdict:
    if verdict.ok is not True:
        raise AssertionError(f"{verdict.status}: {verdict.message}")
    return verdict


def assert_expression(student, derived, **options) -> Verdict:
    """:func:`check_expression` for an autograder cell: return the verdict if correct, else raise
    :class:`AssertionError` whose message is the explanation (the counterexample, or what could not be read).

    Parameters
    ----------
    student : str, SymPy expression or matrix, or sequence
        The student's answer.
    derived : str, sympy.Expr or sympy.Matrix
        The right answer.
    **options
        Keywords of :func:`check_expression`.

    Returns
    -------
    Verdict
        The verdict, when correct.

    Raises
    ------
    AssertionError
        Unless the verdict is correct: its status and message.

    Examples
    --------
    >>> assert_expression("c1 c2 - s1 s2", "cos(t1 + t2)").status
    'correct'
    >>> assert_expression("c1 c2 + s1 s2", "cos(t1 + t2)")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    AssertionError: wrong: not equal: at t1 = ..., t2 = ... the answer is ... but the derived value is ...
    """
    return _assert(check_expression(student, derived, **options))


def assert_factors(student, derived, **options) -> Verdict:
    """:func:`check_factors` raising :class:`AssertionError` with the explanation unless correct.

    Parameters
    ----------
    student : str or sequence
        The student's factors.
    derived : sequence
        The derived factors.
    **options
        Keywords of :func:`check_factors`.

    Returns
    -------
    Verdict
        The verdict, when correct.

    Raises
    ------
    AssertionError
        Unless the verdict is correct: its status and message.
    """
    return _assert(check_factors(student, derived, **options))


def assert_reachable(chain, point, claimed: bool = True, **options) -> Verdict:
    """Assert the student's claim that ``point`` is (``claimed=True``) or is not reachable by ``chain``.

    Passes only when the library proves the claim (an exact witness or an
    interval existence proof; an exact reach bound or an interval proof of
    unreachability: :func:`check_reachable`); raises :class:`AssertionError`
    with the evidence otherwise, also when it cannot decide (a point within
    tolerance of the workspace is neither).

    Parameters
    ----------
    chain : PlanarChain
        The chain.
    point : pair of numbers or text
        The point ``(x, y)``.
    claimed : bool, default True
        The student's claim: True for reachable.
    **options
        Keywords of :func:`check_reachable`.

    Returns
    -------
    Verdict
        ``ok`` True, with the message and evidence of the proof, when the claim is proved.

    Raises
    ------
    AssertionError
        When the claim is proved wrong or nothing is proved.

    Examples
    --------
    >>> from workspace_sym.planar import PlanarChain
    >>> arm = PlanarChain([1, 1], [-90, 0], [90, 90])
    >>> assert_reachable(arm, (0, 2)).status
    'correct'
    >>> assert_reachable(arm, (0, 2), claimed=False)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    AssertionError: wrong: claimed unreachable, but it is reachable: theta = (0, 0) deg, ... reaches it exactly ...
    >>> assert_reachable(arm, (0, 2 + 1e-10))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    AssertionError: wrong: claimed reachable, but it is unreachable: |p|^2 = ... exceeds the square of the reach 2 ...
    """
    verdict = check_reachable(chain, point, **options)
    if verdict.ok is None:
        raise AssertionError(f"undecided: {verdict.message}")
    word = "reachable" if claimed else "unreachable"
    if verdict.ok is bool(claimed):
        return Verdict(True, verdict.message, verdict.evidence)      # the message starts with the word proved
    raise AssertionError(f"wrong: claimed {word}, but it is {verdict.message}")


def assert_boundary_arc(chain, center, radius, start_angle, end_angle, **options) -> Verdict:
    """:func:`check_boundary_arc` raising :class:`AssertionError` with the explanation unless correct.

    Parameters
    ----------
    chain : PlanarChain
        The chain.
    center : pair of numbers or text
        The claimed centre.
    radius : number or text
        The claimed radius.
    start_angle, end_angle : number or text
        The claimed polar angles (radians).
    **options
        Keywords of :func:`check_boundary_arc`.

    Returns
    -------
    Verdict
        The verdict, when correct.

    Raises
    ------
    AssertionError
        Unless the verdict is correct: its status and message.
    """
    return _assert(check_boundary_arc(chain, center, radius, start_angle, end_angle, **options))


def assert_measure(claimed, result, **options) -> Verdict:
    """:func:`check_measure` raising :class:`AssertionError` with the explanation unless correct.

    Parameters
    ----------
    claimed : number or text
        The student's area or volume.
    result : Boundary, Paving or DextrousResult
        What the claim is checked against.
    **options
        Keywords of :func:`check_measure`.

    Returns
    -------
    Verdict
        The verdict, when correct.

    Raises
    ------
    AssertionError
        Unless the verdict is correct: its status and message.
    """
    return _assert(check_measure(claimed, result, **options))
