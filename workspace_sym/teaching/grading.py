"""Batch grading: a machine-readable answer key, a CSV of students' answers, a graded CSV and a report.

The key is JSON (``workspace-sym exercises`` writes one; a teacher may write
one by hand)::

    {"format": "workspace-sym key", "version": 1,
     "robots": {"R1": "glass-handling" | {DH description, see DHRobot.from_dict}},
     "chains": {"C1": {"lengths": [...], "lower": [...], "upper": [...]}},     # degrees
     "questions": [
       {"id": "1a", "kind": "expression", "robot": "R1", "answer": "c1*(a1 + a2*c2)", "prompt": "..."},
       {"id": "1b", "kind": "expression", "robot": "R1", "answer": "[-s1*a2, c1*a2, 0]"},   # a matrix
       {"id": "1c", "kind": "factors", "robot": "R1", "answer": ["s3", "a2*c2 + a3*c23"]},
       {"id": "1d", "kind": "reachable", "answer": true, "evidence": "witness theta = ..."},
       {"id": "2a", "kind": "integer", "answer": 8, "unit": "arcs"},
       {"id": "2b", "kind": "measure", "answer": [0.2681, 0.2682], "digits": 3, "unit": "m^2"}]}

A measure is accepted within its certified bracket widened by its tolerance: ``digits`` (the answer agrees with
the certified value to that many significant digits: within half a unit of its last one) or ``rel_tol`` (a
fraction of the value), not both; :func:`tolerance_rule` says it in words, on the sheet and in each verdict.
Every question may carry ``points`` (default 1) and ``angles``
(``"radians"`` or ``"degrees"``, how numbers inside sin and cos are read); an
expression question without a robot lists its ``symbols`` (``["theta1",
"a1"]``).  A count may name what it counts (``unit``, a word such as ``"arcs"``) and a measure
its unit (``"m"``, ``"m^2"``, ``"cm^3"``, ``"rad"``, ``"deg"``...): an answer then may carry a unit of the same
kind (converted: ``3270 cm^2`` is ``0.327 m^2``) and one of another kind is wrong, with the reason.
Students write ``No.``, ``no it is too far``, ``Four arcs.``, ``0.327 m²`` or ``1.40474 +- 0.01``: a
sentence's final full stop, a verdict with its reason, number words, units and an uncertainty (the value is
graded) are read (:func:`~workspace_sym.teaching.answers.read_yes_no`,
:func:`~workspace_sym.teaching.answers.read_count`, :func:`~workspace_sym.teaching.answers.split_unit`,
:func:`~workspace_sym.teaching.answers.split_uncertainty`); a yes/no answer that
hedges (``No, not sure``) or contradicts itself (``no, yes``) is *cannot read*, with the words.
The key is a file, so it is read like any user text: expressions through the
safe reader, with the robot's notation.

Answers are a CSV with columns ``student, question, answer`` (separated by commas, semicolons or tabs), at most
:data:`MAX_ROWS` rows; names that differ only in case or blanks are listed (:func:`similar_students`).
Each answer gets a :class:`~workspace_sym.teaching.checks.Verdict`: correct, wrong (with the
counterexample) or cannot read (with the column), never an exception; a
blank answer is *no answer*, and a student's second answer to a question is
*duplicate* (not graded: the first one is, and the report lists the rows).

Checking is bounded in time (:func:`grade_answers`): an answer still being
checked after ``answer_time_limit`` seconds (default :data:`ANSWER_SECONDS`) is
*cannot check*, with the reason; once the batch has spent the time limit of
``stop=StopAt(time_limit=...)`` (default :data:`TOTAL_SECONDS`) the remaining
rows are *not graded* (no points).  Both are counted in the report, which says
why.
"""

from __future__ import annotations

import csv
import io
import math
import re
import signal
import threading
import time
from collections import Counter
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import sympy as sp

from .. import robots as catalog
from ..document import Document
from ..errors import ExpressionError, InvalidParameterError, SymbolicBudgetError, UnknownNameError, WorkspaceError
from ..expressions import parse_expr, read_symbol
from ..files import read_json, read_text, write_files
from ..interval.driver import RunOn, StopAt
from ..kinematics import DHRobot
from ..numbers import fmt_bracket
from ..planar import PlanarChain
from ..progress import progress_bar
from ..symbolic import RETRY_SECONDS as RETRY_SECONDS  # re-exported: the retry of the budget below
from ..symbolic import symbolic_budget
from .answers import (
    ANGLE_UNITS,
    Notation,
    plain_sentence,
    read_answer,
    read_count,
    read_unit,
    read_yes_no,
    split_uncertainty,
    split_unit,
)
from .checks import Verdict, cannot_read, check_expression, check_factors
from .options import deprecated, refuse_run, refuse_stop

__all__ = ["KIND_NAMES", "KEY_FORMAT", "Question", "AnswerKey", "GradedAnswer", "grade_answers", "read_answers_csv",
           "write_grading", "duplicate_rows", "similar_students", "tolerance_rule", "accepted_range", "DELIMITERS",
           "MAX_ROWS", "ANSWER_SECONDS", "TOTAL_SECONDS", "BATCH"]

#: Kinds of question a key may hold.
KIND_NAMES = ("expression", "factors", "reachable", "integer", "measure")
KEY_FORMAT = "workspace-sym key"
#: Most rows of an answers file (a class of 500 students answering 20 questions).
MAX_ROWS = 10_000
#: Default seconds one answer may take to check before it is "cannot check".
ANSWER_SECONDS = 10.0
#: Default seconds a whole batch may take; the rows left then are "not graded".
TOTAL_SECONDS = 1800.0
#: The default ``stop`` of :func:`grade_answers`: a batch stops after :data:`TOTAL_SECONDS`.
BATCH = StopAt(time_limit=TOTAL_SECONDS)


@dataclass(frozen=True)
class Question:
    """One question of a key: what is asked, of which robot or chain, and the derived answer.

    Made by :meth:`AnswerKey.from_dict`, which checks every field.

    Parameters
    ----------
    id : str
        The question's id (``"1a"``), at most 40 characters.
    kind : str
        One of :data:`KIND_NAMES`.
    answer : object
        By kind: the expression as text, a list of factors as text, a bool (reachable), an int (a count) or a
        certified bracket ``[lo, hi]`` (a measure).
    prompt : str, default ""
        The question as the sheet asks it.
    robot : str or None, optional
        The name of the key's robot the question is about.
    chain : str or None, optional
        The name of the key's chain the question is about.
    points : float, default 1.0
        The points of a correct answer.
    angles : {"radians", "degrees"}, default "radians"
        How numbers inside sin and cos are read.
    rel_tol : float, default 0.0
        A measure's tolerance, as a fraction of the value.
    evidence : str, default ""
        Why the key's answer holds (a reachability question), shown in the verdict.
    symbols : tuple of str, optional
        The names an expression question without a robot may use.
    unit : str, default ""
        What a count counts (one word), or a measure's unit.
    digits : int, default 0
        A measure's tolerance in significant digits (0: ``rel_tol`` applies).
    """

    id: str
    kind: str
    answer: Any                 # by kind: text, a bool, a count, a [lo, hi] bracket, a list of factors
    prompt: str = ""
    robot: str | None = None
    chain: str | None = None
    points: float = 1.0
    angles: str = "radians"
    rel_tol: float = 0.0
    evidence: str = ""
    symbols: tuple = ()
    unit: str = ""
    digits: int = 0             # a measure: significant digits the answer must agree to (0: rel_tol applies)


@dataclass
class AnswerKey:
    """A parsed key: robots and chains by name, questions in order.

    Read from a file with :meth:`from_file` or from its JSON value with :meth:`from_dict` (the module docstring
    gives the format).

    Parameters
    ----------
    questions : list of Question
        The questions, in order.
    robots : dict, optional
        Name -> :class:`~workspace_sym.kinematics.DHRobot`.
    chains : dict, optional
        Name -> :class:`~workspace_sym.planar.PlanarChain`.
    title : str, default "Exercises"
        The title of the sheet and of the grading report.

    Raises
    ------
    InvalidParameterError
        From :meth:`from_dict` and :meth:`from_file`, for a malformed key (the constructor checks nothing).
    """

    questions: list
    robots: dict = field(default_factory=dict)
    chains: dict = field(default_factory=dict)
    title: str = "Exercises"
    _read: dict = field(default_factory=dict, init=False, repr=False, compare=False)   # key answers read, by id

    @classmethod
    def from_dict(cls, data) -> AnswerKey:
        """Check and read a key dictionary (see the module docstring).

        Parameters
        ----------
        data : dict
            The key's JSON value.

        Returns
        -------
        AnswerKey
            The key, its robots built and its chains made; every expression and factor of its answers has been
            read once to check it.

        Raises
        ------
        InvalidParameterError
            When the key is not a ``workspace-sym key`` object, a robot, chain or question is malformed (an id
            missing, repeated or longer than 40 characters; an answer of the wrong type; a bad ``points``,
            ``rel_tol``, ``digits``, ``unit`` or ``symbols``), or a question names a robot or chain the key does not
            define.
        UnknownNameError
            When a question's ``kind`` or ``angles`` is not one of those allowed, or a robot names no catalog entry.
        DHTableError
            When a robot's DH description is malformed.
        ExpressionError
            When an expression or factor of the key cannot be read with its robot's names.
        JointLimitError
            When a chain's limits are inverted.
        """
        if not isinstance(data, dict) or data.get("format") != KEY_FORMAT:
            raise InvalidParameterError(f"key: expected a JSON object with \"format\": \"{KEY_FORMAT}\"",
                                        parameter="key")
        built = {}
        for name, spec in _mapping(data, "robots").items():
            model = catalog.build(spec) if isinstance(spec, str) else DHRobot.from_dict(spec, name=name)
            if not isinstance(model, DHRobot):
                raise InvalidParameterError(f"key: robot {name!r} is not a serial DH robot", parameter="key")
            built[name] = model
        chains = {}
        for name, spec in _mapping(data, "chains").items():
            if not isinstance(spec, dict) or not {"lengths", "lower", "upper"} <= set(spec):
                raise InvalidParameterError(f"key: chain {name!r} needs lengths, lower and upper", parameter="key")
            chains[name] = PlanarChain(spec["lengths"], spec["lower"], spec["upper"])
        rows = data.get("questions")
        if not isinstance(rows, list) or not rows:
            raise InvalidParameterError("key: expected a non-empty list of questions", parameter="key")
        questions, seen = [], set()
        for k, row in enumerate(rows, start=1):
            q = _question(row, k, built, chains)
            if q.id in seen:
                raise InvalidParameterError(f"key: question id {q.id!r} appears twice", parameter="key")
            seen.add(q.id)
            questions.append(q)
        return cls(questions, built, chains, str(data.get("title", "Exercises")))

    @classmethod
    def from_file(cls, path) -> AnswerKey:
        """Read a key file (JSON).

        Parameters
        ----------
        path : str or os.PathLike
            The file (UTF-8 JSON).

        Returns
        -------
        AnswerKey
            The key (:meth:`from_dict`).

        Raises
        ------
        InvalidParameterError
            When the file cannot be read or is not valid JSON, and as :meth:`from_dict`.
        """
        return cls.from_dict(read_json(path, "key", error=InvalidParameterError))

    def question(self, qid: str) -> Question | None:
        """The question of id ``qid``.

        Parameters
        ----------
        qid : str
            The id, exactly.

        Returns
        -------
        Question or None
            The question, or None when the key has none of that id.
        """
        return next((q for q in self.questions if q.id == qid), None)

    def notation(self, q: Question) -> Notation:
        """The names of the question's robot, or of its ``symbols`` (joints ``theta<k>``, ``q<k>``, ``t<k>``).

        Parameters
        ----------
        q : Question
            A question of this key.

        Returns
        -------
        Notation
            The names a student may use in the answer.
        """
        if q.robot:
            return Notation.from_robot(self.robots[q.robot])
        return Notation.from_symbols([read_symbol(n, f"key question {q.id} symbols") for n in q.symbols])

    def derived(self, q: Question):
        """The key's answer as SymPy (expressions, factors) or as a plain value (read once per question).

        Parameters
        ----------
        q : Question
            A question of this key.

        Returns
        -------
        object
            A SymPy expression or matrix (a copy), a list of them (factors), or ``q.answer`` for the other kinds.
        """
        if q.kind not in ("expression", "factors"):
            return q.answer
        texts = (q.answer,) if q.kind == "expression" else tuple(q.answer)
        if (q.id, texts) not in self._read:
            self._read[q.id, texts] = [read_answer(t, self.notation(q), parameter=f"key question {q.id}")
                                       for t in texts]
        values = [v.copy() if isinstance(v, sp.MatrixBase) else v for v in self._read[q.id, texts]]
        return values[0] if q.kind == "expression" else values

    def grade(self, qid: str, text) -> Verdict:
        """The verdict on one answer to question ``qid``.

        Parameters
        ----------
        qid : str
            The question's id.
        text : str
            The student's answer.

        Returns
        -------
        Verdict
            Correct or wrong with the evidence, or ``ok`` None: *cannot read* (also for an unknown question id),
            *no answer* (blank or not text) or undecided.  Not bounded in time: :func:`grade_answers` is.
        """
        q = self.question(qid)
        if q is None:
            known = ", ".join(x.id for x in self.questions)
            return Verdict(None, f"unknown question {qid!r}; the key has {known}", {"method": "cannot read"})
        if not isinstance(text, str) or not text.strip():
            return Verdict(None, "no answer", {"method": "no answer"})
        text = plain_sentence(text)
        robot = self.robots.get(q.robot) if q.robot else None
        if q.kind == "expression":
            return check_expression(text, self.derived(q), robot=robot, angles=q.angles)
        if q.kind == "factors":
            return check_factors(text, self.derived(q), robot=robot, angles=q.angles)
        if q.kind == "reachable":
            return _grade_yes_no(text, bool(q.answer), q.evidence)
        if q.kind == "integer":
            return _grade_integer(text, int(q.answer), q.unit)
        return _grade_measure(text, q)


def _mapping(data: dict, key: str) -> dict:
    value = data.get(key) or {}
    if not isinstance(value, dict):
        raise InvalidParameterError(f"key: {key} must be an object of names", parameter="key")
    return value


def _question(row, k: int, robots: dict, chains: dict) -> Question:
    if not isinstance(row, dict):
        raise InvalidParameterError(f"key: question {k} must be an object", parameter="key")
    qid = row.get("id")
    if not isinstance(qid, str) or not qid.strip() or len(qid) > 40:
        raise InvalidParameterError(f"key: question {k} needs an id (text, at most 40 characters)", parameter="key")
    kind = row.get("kind")
    if kind not in KIND_NAMES:
        raise UnknownNameError(f"key: kind of question {qid!r} must be one of {', '.join(KIND_NAMES)}; got {kind!r}",
                               parameter="key")
    robot, chain = row.get("robot"), row.get("chain")
    if robot is not None and robot not in robots:
        raise InvalidParameterError(f"key: question {qid!r} names robot {robot!r}, which the key does not define",
                                    parameter="key")
    if chain is not None and chain not in chains:
        raise InvalidParameterError(f"key: question {qid!r} names chain {chain!r}, which the key does not define",
                                    parameter="key")
    answer: Any = row.get("answer")
    expected: Any = {"expression": str, "factors": list, "reachable": bool, "integer": int, "measure": list}[kind]
    if not isinstance(answer, expected) or (kind == "integer" and isinstance(answer, bool)):
        raise InvalidParameterError(f"key: answer of question {qid!r} ({kind}) must be a JSON {expected.__name__}",
                                    parameter="key")
    if kind == "measure" and not (len(answer) == 2 and all(isinstance(v, (int, float)) for v in answer)
                                  and answer[0] <= answer[1]):
        raise InvalidParameterError(f"key: answer of question {qid!r} must be a bracket [low, high]", parameter="key")
    if kind == "factors" and not all(isinstance(f, str) for f in answer):
        raise InvalidParameterError(f"key: factors of question {qid!r} must be strings", parameter="key")
    angles = row.get("angles", "radians")
    if angles not in ANGLE_UNITS:
        raise UnknownNameError(f"key: angles of question {qid!r} must be radians or degrees; got {angles!r}",
                               parameter="key")
    points, rel_tol = row.get("points", 1), row.get("rel_tol", 0.0)
    for name, value in (("points", points), ("rel_tol", rel_tol)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
            raise InvalidParameterError(f"key: {name} of question {qid!r} must be a number >= 0; got {value!r}",
                                        parameter="key")
    digits = row.get("digits", 0)
    if isinstance(digits, bool) or not isinstance(digits, int) or not 0 <= digits <= 15:
        raise InvalidParameterError(f"key: digits of question {qid!r} must be a whole number of significant digits "
                                    f"from 1 to 15; got {digits!r:.60}", parameter="key")
    if digits and (kind != "measure" or rel_tol):
        raise InvalidParameterError(f"key: digits of question {qid!r}: only a measure has them, and not with rel_tol "
                                    "(give one tolerance)", parameter="key")
    symbols = row.get("symbols", [])
    if not isinstance(symbols, list) or not all(isinstance(n, str) for n in symbols):
        raise InvalidParameterError(f"key: symbols of question {qid!r} must be a list of names", parameter="key")
    unit = row.get("unit", "")
    if kind == "measure" and unit != "" and (not isinstance(unit, str) or read_unit(unit) is None):
        raise InvalidParameterError(f"key: unit of question {qid!r} must be a unit of length, area, volume or angle "
                                    f"such as m, m^2, cm^3, rad, deg; got {unit!r:.60}", parameter="key")
    if kind == "integer" and not (isinstance(unit, str) and re.fullmatch(r"[A-Za-z]{0,40}", unit)):
        raise InvalidParameterError(f"key: unit of question {qid!r} must be one word (what is counted, such as "
                                    f"arcs); got {unit!r:.60}", parameter="key")
    if kind not in ("integer", "measure") and unit != "":
        raise InvalidParameterError(f"key: unit of question {qid!r}: only a count or a measure has one",
                                    parameter="key")
    question = Question(qid, kind, answer, str(row.get("prompt", "")), robot, chain, float(points), angles,
                        float(rel_tol), str(row.get("evidence", "")), tuple(symbols), unit, digits)
    if kind in ("expression", "factors"):  # the key's own expressions must read: fail now, not per student
        AnswerKey([question], robots, chains).derived(question)
    return question


def _grade_yes_no(text: str, truth: bool, evidence: str) -> Verdict:
    try:
        claimed = read_yes_no(text)
    except ExpressionError as exc:
        return cannot_read(exc)
    said = "reachable" if truth else "unreachable"
    if claimed is truth:
        return Verdict(True, f"{said}: {evidence}".rstrip(": "), {"method": "certified key"})
    return Verdict(False, f"the point is {said}: {evidence}".rstrip(": "), {"method": "certified key"})


def _singular(word: str) -> str:
    word = word.lower()
    return word[:-1] if len(word) > 1 and word.endswith("s") else word


def _grade_integer(text: str, truth: int, unit: str = "") -> Verdict:
    words = ""
    try:
        value = parse_expr(text, "answer", new_symbols=False, max_length=40)
    except ExpressionError as exc:
        counted = read_count(text) if len(text) <= 80 else None      # "4 arcs", "four", "twenty-one"
        if counted is None:
            return cannot_read(exc)
        value, words = sp.Integer(counted[0]), counted[1]
    if not value.is_Integer:
        return Verdict(None, f"cannot read {text[:60]!r}: expected a whole number", {"method": "cannot read"})
    note = ""
    if words and unit and _singular(words.split()[-1]) != _singular(unit):
        return Verdict(False, f"{text[:60]!r}: the question counts {unit}, not {words.split()[-1]}",
                       {"method": "unit"})
    if words and not unit:
        note = f" (the words {words!r} are not checked: the key names nothing counted)"
    if int(value) == truth:
        return Verdict(True, f"{truth}{note}", {"method": "certified key"})
    return Verdict(False, f"{int(value)}, but the derived count is {truth}{note}", {"method": "certified key"})


def _read_measure(text: str, q: Question):
    """``(value in the key's unit, as shown, note)`` of a number with an optional unit, or the verdict when it
    cannot be read or its unit is of another kind."""
    number, unit = split_unit(text)
    try:
        value = parse_expr(number, "answer", new_symbols=False, max_length=200)
        claimed = float(value)
    except ExpressionError as exc:
        # the number taken whole (atomic group): "1e400" is a number out of range, not 1 and a unit "e400"
        loose = re.fullmatch(r"(?>[-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*([A-Za-z].{0,20})", text.strip())
        if unit is None and loose:                        # "0.327 ft^2": a number and a unit not known here
            return Verdict(None, f"cannot read {text[:60]!r}: unknown unit {loose[1]!r}; write the number alone or "
                                 f"with a unit such as {q.unit or 'm, m^2, rad or deg'}", {"method": "cannot read"})
        return cannot_read(exc)
    except (TypeError, ValueError):
        return Verdict(None, f"cannot read {text[:60]!r}: expected a number", {"method": "cannot read"})
    expected = read_unit(q.unit) if q.unit else None
    # the number as written when it is a decimal ("1.40", not "1.4": its digits are what is graded)
    shown, note = number if re.fullmatch(r"[-+]?[0-9]*\.?[0-9]+", number) else f"{claimed:g}", ""
    if unit is not None and expected is None:
        note = f" (the unit {unit.text} is not checked: the key gives none)"
    elif unit is not None and expected is not None:
        if (unit.dimension, unit.power) != (expected.dimension, expected.power):
            return Verdict(False, f"{text[:60]!r}: {unit.text} is {unit.kind}, but the answer is {expected.kind} "
                                  f"({q.unit})", {"method": "unit", "bracket": list(q.answer)})
        if unit.scale != expected.scale:
            claimed = claimed * unit.scale / expected.scale
            shown = f"{number} {unit.text} = {claimed:g} {q.unit}"
    return claimed, shown, note


def _ordinal(n: int) -> str:
    return f"{n}{'th' if 10 <= n % 100 <= 20 else {1: 'st', 2: 'nd', 3: 'rd'}.get(n % 10, 'th')}"


def tolerance_rule(*, digits: int = 0, rel_tol: float = 0.0) -> str:
    """How a measure answer is accepted, in words: what an exercise sheet states and what the grader applies
    (:func:`accepted_range`).

    Parameters
    ----------
    digits : int, default 0
        Significant digits the answer must agree to.
    rel_tol : float, default 0.0
        The tolerance as a fraction of the value, when ``digits`` is 0.

    Returns
    -------
    str
        The rule in words.

    Examples
    --------
    >>> tolerance_rule(digits=3)
    'agrees with the certified value to 3 significant digits (within half a unit of its 3rd significant digit)'
    >>> tolerance_rule(rel_tol=0.001), tolerance_rule()
    ('within 0.1% of the certified value', 'within the certified bracket')
    """
    if digits:
        return (f"agrees with the certified value to {digits} significant digits (within half a unit of its "
                f"{_ordinal(digits)} significant digit)")
    if rel_tol:
        return f"within {rel_tol * 100:g}% of the certified value"
    return "within the certified bracket"


def accepted_range(lo: float, hi: float, *, digits: int = 0, rel_tol: float = 0.0) -> tuple[float, float]:
    """The answers :func:`tolerance_rule` accepts for the certified bracket ``[lo, hi]``: widened by half a unit of
    the last of ``digits`` significant digits of each end, or by ``rel_tol`` times the larger end.

    Parameters
    ----------
    lo, hi : float
        The certified bracket.
    digits : int, default 0
        Significant digits the answer must agree to (takes precedence over ``rel_tol``).
    rel_tol : float, default 0.0
        The tolerance as a fraction of the larger end, in absolute value.

    Returns
    -------
    tuple of float
        ``(low, high)``: the answers accepted.

    Examples
    --------
    >>> [round(v, 9) for v in accepted_range(1.40474, 1.40474, digits=3)]   # 1.40 is right, 1.39 and 1.391 are not
    [1.39974, 1.40974]
    >>> accepted_range(0.5, 0.5, rel_tol=0.01)
    (0.495, 0.505)
    """
    from decimal import Decimal

    def half_unit(v: float) -> float:
        if v == 0 or not math.isfinite(v):
            return 0.0
        return 0.5 * 10.0 ** (Decimal(v).adjusted() - digits + 1) * (1 + 1e-12)    # 1e-12: float rounding of a tie
    if digits:
        return lo - half_unit(lo), hi + half_unit(hi)
    slack = rel_tol * max(abs(lo), abs(hi))
    return lo - slack, hi + slack


def _grade_measure(text: str, q: Question) -> Verdict:
    value_text, spread_text = split_uncertainty(text)     # "1.40474 +- 0.01": a value and its uncertainty
    read = _read_measure(value_text, q)
    if isinstance(read, Verdict):
        return read
    claimed, shown, note = read
    if spread_text is not None:
        spread = _read_measure(spread_text, q)
        if isinstance(spread, Verdict) or not (math.isfinite(spread[0]) and spread[0] >= 0):
            reason = spread.message if isinstance(spread, Verdict) else "it must be a number >= 0"
            return Verdict(None, f"cannot read the uncertainty of {text[:60]!r} ({spread_text[:30]!r}): {reason}",
                           {"method": "cannot read"})
        shown, note = f"{shown} +- {spread[0]:g}", f"{note} (the value is graded, not its stated uncertainty)"
    lo, hi = q.answer
    in_unit = f" {q.unit}" if q.unit else ""
    low, high = accepted_range(lo, hi, digits=q.digits, rel_tol=q.rel_tol)
    bracket = fmt_bracket(lo, hi, 6, "g") + in_unit
    evidence = {"bracket": [lo, hi], "accepted": [low, high]}
    if q.digits:
        if math.isfinite(claimed) and low <= claimed <= high:
            return Verdict(True, f"{shown} agrees with the certified {bracket} to {q.digits} significant digits"
                                 f"{note}", evidence)
        return Verdict(False, f"{shown} does not agree with the certified value {bracket} to {q.digits} significant "
                              f"digits (accepted: {fmt_bracket(low, high, 6, 'g')}){note}", evidence)
    within = f"within {q.rel_tol * 100:g}% of"
    if math.isfinite(claimed) and low <= claimed <= high:
        return Verdict(True, f"{shown} is {within} the certified {bracket}{note}", evidence)
    return Verdict(False, f"{shown} is not {within} the certified value {bracket}{note}", evidence)


# ------------------------------------------------------------------------------ batch
@dataclass(frozen=True)
class GradedAnswer:
    """One row of a batch, graded.

    Parameters
    ----------
    student : str
        The student's name as written.
    question : str
        The question's id.
    answer : str
        The answer as written.
    verdict : Verdict
        The verdict.
    points : float
        The points given: the question's points when correct, else 0.
    max_points : float
        The question's points (0 for an unknown question).
    """

    student: str
    question: str
    answer: str
    verdict: Verdict
    points: float
    max_points: float


_COLUMNS = ("student", "question", "answer")
#: Column separators of an answers file, told apart by its header: a spreadsheet in a locale whose decimal mark is a
#: comma writes ';'.
DELIMITERS = (",", ";", "\t")


def _delimiter(text: str) -> str:
    """The separator with which the first line names the three columns (',' when none does)."""
    first = text.split("\n", 1)[0]
    for delimiter in DELIMITERS:
        header = {h.strip().lower() for h in next(csv.reader([first], delimiter=delimiter), [])}
        if set(_COLUMNS) <= header:
            return delimiter
    return ","


def read_answers_csv(path) -> list[tuple[str, str, str]]:
    """``(student, question, answer)`` rows of a CSV with those three columns (any order, header required),
    separated by commas, semicolons or tabs (:data:`DELIMITERS`, the header tells which).

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file (UTF-8, a byte-order mark allowed); column names are read without case or blanks.

    Returns
    -------
    list of tuple
        ``(student, question, answer)`` per row, each stripped, empty for a missing cell.

    Raises
    ------
    InvalidParameterError
        When the file cannot be read, is not a valid CSV, lacks one of the three columns or has more than
        :data:`MAX_ROWS` rows.
    """
    path = Path(path)
    text = read_text(path, "answers", error=InvalidParameterError, encoding="utf-8-sig")
    try:
        reader = csv.DictReader(io.StringIO(text), delimiter=_delimiter(text))
        header = [h.strip().lower() for h in (reader.fieldnames or [])]
        missing = [c for c in _COLUMNS if c not in header]
        if missing:
            first = text.split("\n", 1)[0].strip()
            raise InvalidParameterError(f"answers: {str(path)!r} needs the columns student, question, answer, "
                                        "separated by ',', ';' or a tab; missing "
                                        f"{', '.join(missing)} (its first line is {first[:60]!r})",
                                        parameter="answers")
        reader.fieldnames = header
        rows: list = []
        for row in reader:
            if len(rows) >= MAX_ROWS:
                raise InvalidParameterError(f"answers: {str(path)!r} has more than {MAX_ROWS} rows, the most one "
                                            "run grades (grading.MAX_ROWS); split it into several files",
                                            parameter="answers")
            rows.append(tuple((row.get(c) or "").strip() for c in _COLUMNS))
    except csv.Error as exc:
        raise InvalidParameterError(f"answers: {str(path)!r} is not a valid CSV ({exc})",
                                    parameter="answers") from None
    return rows


@contextmanager
def _time_budget(seconds: float):
    """Interrupt the block after ``seconds``: :func:`~workspace_sym.symbolic.symbolic_budget`, whose timer fires
    again if its interruption is swallowed on the way and which nested derivations cannot extend, raises
    :class:`~workspace_sym.errors.SymbolicBudgetError` when the block is over its time (or a derivation inside it
    over its own budget).  Yields whether a timer can interrupt SymPy's own calls (the main thread of a POSIX
    process: elsewhere only the deadline checks of our loops stop the block, and the caller compares the time it
    took)."""
    interruptible = hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
    with symbolic_budget(seconds, "checking this answer"):
        yield interruptible


def _check_budget(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise InvalidParameterError(f"{name} must be a positive number of seconds; got {value!r}", parameter=name)
    return float(value)


def grade_answers(key: AnswerKey, rows, *, stop: StopAt = BATCH, answer_time_limit: float = ANSWER_SECONDS,
                  run: RunOn = RunOn(), answer_seconds: float | None = None,
                  total_seconds: float | None = None) -> list[GradedAnswer]:
    """Grade ``(student, question, answer)`` rows against ``key``; never raises on an answer.

    An answer whose check takes more than ``answer_time_limit`` seconds is
    stopped and gets *cannot check* (``ok`` None, no points) with the reason;
    after ``stop.time_limit`` seconds for the whole batch, every remaining row
    gets *not graded*.  Where the check cannot be interrupted (not the main
    thread, or no POSIX timer) an answer runs to its end and is *cannot check*
    when it took longer than its budget.

    A student's first row for a question is graded; a later one is
    *duplicate* (no points), naming both rows as numbered in the CSV (the
    header is row 1: the first answer is row 2).

    Parameters
    ----------
    key : AnswerKey
        The answer key.
    rows : iterable of (str, str, str)
        ``(student, question, answer)`` rows, as :func:`read_answers_csv` returns them.
    stop : :class:`~workspace_sym.interval.driver.StopAt`
        ``time_limit``: seconds for the whole batch (default :data:`BATCH`, :data:`TOTAL_SECONDS`; None: no limit).
        ``max_boxes`` and ``section_boxes`` do not apply and are refused; ``progress`` shows nothing (no bar).
    answer_time_limit : float
        Seconds one answer may take to check (default :data:`ANSWER_SECONDS`): a budget per answer, within
        what is left of the batch's.
    run : :class:`~workspace_sym.interval.driver.RunOn`
        ``progress``: a bar over the rows (None: on an interactive output once the batch has lasted a second).
        The answers are checked in this process: the other fields are refused.
    answer_seconds, total_seconds : float, optional
        Deprecated: ``answer_time_limit=`` and ``stop=StopAt(time_limit=...)`` (taken with a
        :class:`DeprecationWarning`).

    Returns
    -------
    list of GradedAnswer
        One a row, in the order of the rows.

    Raises
    ------
    InvalidParameterError
        A time limit that is not a positive number of seconds, a ``stop`` setting a budget of boxes, or a ``run``
        setting anything but ``progress``.
    """
    if answer_seconds is not None:
        deprecated("grade_answers", "answer_seconds", "answer_time_limit=...")
        answer_time_limit = _check_budget(answer_seconds, "answer_seconds")
    if total_seconds is not None:
        deprecated("grade_answers", "total_seconds", "stop=StopAt(time_limit=...)")
        stop = replace(stop, time_limit=_check_budget(total_seconds, "total_seconds"))
    refuse_stop("grade_answers", stop, ("time_limit",), "stops on time only")
    refuse_run("grade_answers", run)
    answer_time_limit = _check_budget(answer_time_limit, "answer_time_limit")
    total = math.inf if stop.time_limit is None else float(stop.time_limit)
    rows = list(rows)
    out = []
    first_row: dict = {}
    start = time.perf_counter()
    shown = run.progress if run.progress is not None else stop.progress        # RunOn's, else the earlier spelling's
    with progress_bar(shown, total=len(rows), desc="grading", unit="answer") as bar:
        for row, (student, qid, text) in enumerate(rows, start=2):
            earlier = first_row.setdefault((student, qid), row)
            left = total - (time.perf_counter() - start)
            out.append(_grade_row(key, row, student, qid, text, earlier=earlier, left=left, total=total,
                                  answer_time_limit=answer_time_limit))
            bar.update(1)
    return out


def _grade_row(key: AnswerKey, row: int, student: str, qid: str, text: str, *, earlier: int, left: float,
               total: float, answer_time_limit: float) -> GradedAnswer:
    """One row of :func:`grade_answers`: a duplicate (``earlier`` is the row that answered first), not graded
    (``left`` seconds of the batch's ``total``), or checked within its budget."""
    q = key.question(qid)
    full = q.points if q is not None else 0.0
    verdict: Verdict | None                                  # None: stopped by its time budget
    if earlier != row:
        verdict = Verdict(None, f"duplicate: row {row} repeats row {earlier}, which answered question {qid} "
                                f"for student {student}; only the first answer is graded",
                          {"method": "duplicate", "rows": [earlier, row]})
        return GradedAnswer(student, qid, text, verdict, 0.0, full)
    if left <= 0:
        verdict = Verdict(None, f"not graded: the batch used its time budget of {total:g} s before "
                                "this answer", {"method": "not graded", "budget": total})
        return GradedAnswer(student, qid, text, verdict, 0.0, full)
    budget = min(answer_time_limit, left)
    began = time.perf_counter()
    try:
        with _time_budget(budget):
            verdict = key.grade(qid, text)
    except SymbolicBudgetError:     # over its time budget (a WorkspaceError: caught first)
        verdict = None
    except WorkspaceError as exc:   # an answer must never stop the batch
        verdict = Verdict(None, " ".join(str(exc).split()), {"method": "cannot read"})
    if verdict is None or time.perf_counter() - began > budget:
        verdict = Verdict(None, f"cannot check: checking this answer was stopped after {budget:g} s, its time "
                                "budget (a very long or deeply nested expression); it gets no points, check "
                                "it by hand", {"method": "cannot check", "budget": budget})
    return GradedAnswer(student, qid, text, verdict, full if verdict.ok is True else 0.0, full)


def similar_students(graded: list[GradedAnswer]) -> list[list[str]]:
    """Names graded as different students that differ only in case or blanks (``"Alice "``, ``"alice"``), each
    group in order of first appearance: probably one student, graded twice, which the teacher should check.

    Parameters
    ----------
    graded : list of GradedAnswer
        The graded rows.

    Returns
    -------
    list of list of str
        The groups of names, each of two names or more.
    """
    groups: dict[str, list[str]] = {}
    for g in graded:
        names = groups.setdefault(" ".join(g.student.split()).casefold(), [])
        if g.student not in names:
            names.append(g.student)
    return [names for names in groups.values() if len(names) > 1]


def duplicate_rows(graded: list[GradedAnswer]) -> list[dict]:
    """Each student and question answered more than once, with its rows as numbered in the CSV (the header being
    row 1), in the order of first appearance.

    Parameters
    ----------
    graded : list of GradedAnswer
        The graded rows (the duplicates are those whose status is ``"duplicate"``).

    Returns
    -------
    list of dict
        ``{"student", "question", "rows"}`` per student and question answered more than once.
    """
    seen: dict = {}
    for g in graded:
        if g.verdict.status == "duplicate":
            first, row = g.verdict.evidence["rows"]
            seen.setdefault((g.student, g.question), [first]).append(row)
    return [{"student": s, "question": q, "rows": rows} for (s, q), rows in seen.items()]


def _student_form(key: AnswerKey, g: GradedAnswer):
    """The answer as read (SymPy, shorthand for the robot) for the report, or the text when unreadable or not
    checked (reading it again would spend the time its budget refused)."""
    q = key.question(g.question)
    if q is None or q.kind != "expression" or g.verdict.status not in ("correct", "wrong") or not g.answer:
        return g.answer
    try:
        value = read_answer(g.answer, key.notation(q), angles=q.angles)
    except WorkspaceError:
        return g.answer
    return key.robots[q.robot].shorthand(value) if q.robot else value


def _expected_form(key: AnswerKey, q: Question):
    if q.kind == "expression":
        value = key.derived(q)
        return key.robots[q.robot].shorthand(value) if q.robot else value
    if q.kind == "factors":
        return ", ".join(q.answer)
    if q.kind == "reachable":
        return "yes" if q.answer else "no"
    if q.kind == "measure":
        rule = tolerance_rule(digits=q.digits, rel_tol=q.rel_tol).replace("the certified value", "it")
        return f"{fmt_bracket(q.answer[0], q.answer[1], 6, 'g')} {q.unit}".rstrip() + f"; accepted: {rule}"
    return str(q.answer)


def write_grading(key: AnswerKey, graded: list[GradedAnswer], out) -> dict:
    """Write ``graded.csv`` and the report ``grades.html`` / ``grades.md`` into ``out``; return their paths.

    Everything is rendered in memory first: nothing is written when rendering fails.

    Parameters
    ----------
    key : AnswerKey
        The key the answers were graded with.
    graded : list of GradedAnswer
        The graded rows (:func:`grade_answers`).
    out : str or os.PathLike
        The directory, created if needed; files of the same names in it are replaced.

    Returns
    -------
    dict
        ``{"csv": ..., "html": ..., "markdown": ...}``: the paths written.

    Raises
    ------
    OutputError
        When ``out`` cannot be written.
    """
    buffer = io.StringIO()
    writer = csv.writer(buffer)
    writer.writerow(["student", "question", "answer", "status", "points", "max_points", "explanation", "position"])
    for g in graded:
        position = g.verdict.evidence.get("position")
        writer.writerow([g.student, g.question, g.answer, g.verdict.status, f"{g.points:g}", f"{g.max_points:g}",
                         g.verdict.message, "" if position is None else position])
    students: dict[str, float] = {}                           # one pass over the rows
    by_student: dict = {}
    tally: Counter = Counter()
    for g in graded:
        students[g.student] = students.get(g.student, 0.0) + g.points
        by_student.setdefault(g.student, []).append(g)
        tally["student", g.student, g.verdict.status] += 1
        tally["question", g.question, g.verdict.status] += 1
    unchecked = [g for g in graded if g.verdict.status in ("cannot check", "not graded")]
    statuses = ("correct", "wrong", "cannot read") + tuple(
        st for st in ("no answer", "duplicate") if any(g.verdict.status == st for g in graded)) + (
        ("cannot check", "not graded") if unchecked else ())
    total = sum(q.points for q in key.questions)
    doc = Document(f"Grades: {key.title}")
    repeated = duplicate_rows(graded)
    similar = similar_students(graded)
    if similar:
        doc.para("Names: " + "; ".join(" and ".join(repr(n) for n in names) for names in similar)
                 + " differ only in case or blanks and are graded as different students: check them.")
    if repeated:
        doc.para(f"Duplicates: {sum(len(d['rows']) - 1 for d in repeated)} duplicate row(s): only the first answer "
                 "of a student to a question is graded, the later ones get no points (rows numbered as in the CSV, "
                 "the header being row 1). "
                 + "; ".join(f"{d['student']}, question {d['question']}: rows {', '.join(map(str, d['rows']))}"
                             for d in repeated) + ".")
    if unchecked:
        over = sum(g.verdict.status == "cannot check" for g in graded)
        doc.para(f"Time budget: {over} answer(s) could not be checked within their time budget (cannot check) and "
                 f"{len(unchecked) - over} were not graded because the batch ran out of time (not graded); they "
                 "get no points and are listed below: check them by hand.")
    doc.heading("Per student")
    doc.table(["student", "score", *statuses],
              [[s, f"{score:g} / {total:g}", *(str(tally["student", s, st]) for st in statuses)]
               for s, score in students.items()])
    doc.heading("Per question")
    doc.table(["question", "expected", *statuses],
              [[q.id, _expected_form(key, q), *(str(tally["question", q.id, st]) for st in statuses)]
               for q in key.questions])
    for s, rows in by_student.items():
        doc.heading(f"Student {s}", level=3)
        doc.table(["question", "answer as read", "verdict", "explanation"],
                  [[g.question, _student_form(key, g), g.verdict.status, g.verdict.message] for g in rows])
    html, markdown = doc.html(Path(".")), doc.markdown()
    written = write_files({"graded.csv": buffer.getvalue(), "grades.html": html, "grades.md": markdown}, out)
    return {"csv": written["graded.csv"], "html": written["grades.html"], "markdown": written["grades.md"]}
