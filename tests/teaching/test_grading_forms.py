"""Answers written the way students write them (issue 27, teacher): trailing periods, units, number words, words after
a count, blank answers and answers given twice.  References: the key's own values (an integer, a certified bracket)
and unit conversions by their definition (1 cm = 1/100 m, 1 degree = pi/180 rad)."""

import csv
import json

import pytest

from workspace_sym.cli import main
from workspace_sym.errors import InvalidParameterError
from workspace_sym.grading import AnswerKey, grade_answers, write_grading

AREA = [0.3268, 0.3272]           # a certified bracket of an area in m^2


def _key(**extra) -> AnswerKey:
    questions = [{"id": "r", "kind": "reachable", "answer": False, "evidence": "beyond the reach"},
                 {"id": "y", "kind": "reachable", "answer": True},
                 {"id": "n", "kind": "integer", "answer": 4, "unit": "arcs"},
                 {"id": "k", "kind": "integer", "answer": 21},
                 {"id": "m", "kind": "measure", "answer": AREA, "rel_tol": 0.01, "unit": "m^2"},
                 {"id": "a", "kind": "measure", "answer": [0.7853, 0.7854], "rel_tol": 0.001, "unit": "rad"},
                 {"id": "u", "kind": "measure", "answer": AREA, "rel_tol": 0.01},
                 {"id": "x", "kind": "expression", "robot": "G", "answer": "c1 (a1 + a2 c2 + a3 c23 + d5 s234)"}]
    return AnswerKey.from_dict({"format": "workspace-sym key", "robots": {"G": "glass-handling"},
                                "questions": questions, **extra})


@pytest.fixture(scope="module")
def key():
    return _key()


def _status(key, qid, text):
    (g,) = grade_answers(key, [("ann", qid, text)])
    return g.verdict.status, g.verdict.message


@pytest.mark.parametrize(("qid", "text"), [
    ("r", "No."), ("r", "no"), ("r", "NO!"), ("r", "No, it is beyond the reach."), ("r", "unreachable."),
    ("y", "Yes."), ("y", "yes: theta = 0 reaches it"),
    ("n", "4"), ("n", "4."), ("n", "4 arcs"), ("n", "4 arcs."), ("n", "four"), ("n", "Four arcs."),
    ("n", "4 circular arcs"), ("k", "twenty-one"), ("k", "Twenty one"), ("k", "21 things"),
    ("m", "0.327"), ("m", "0.327 m^2"), ("m", "0.327 m²"), ("m", "0.327m2"), ("m", "0.327 m**2"),
    ("m", "3270 cm^2"), ("m", "3270 cm²."), ("m", "327000 mm^2"),
    ("a", "pi/4"), ("a", "pi/4 rad"), ("a", "45 deg"), ("a", "45°"), ("a", "45 degrees"),
    ("u", "0.327"), ("u", "0.327 m^2"),
])
def test_right_answers_as_students_write_them(key, qid, text):
    status, message = _status(key, qid, text)
    assert status == "correct", message


@pytest.mark.parametrize(("qid", "text", "status", "words"), [
    ("r", "Yes.", "wrong", "unreachable"),
    ("y", "no idea", "cannot read", "answer yes"),
    ("n", "5 arcs", "wrong", "derived count is 4"),
    ("n", "five", "wrong", "derived count is 4"),
    ("n", "4 lines", "wrong", "counts arcs, not lines"),
    ("n", "2 pi", "cannot read", "cannot read '2 pi'"),
    ("n", "4 <script>", "cannot read", ""),
    ("m", "0.327 m", "wrong", "m is a length, but the answer is an area (m^2)"),
    ("m", "0.327 m^3", "wrong", "m^3 is a volume, but the answer is an area (m^2)"),
    ("m", "0.327 rad", "wrong", "rad is an angle, but the answer is an area (m^2)"),
    ("m", "0.327 cm^2", "wrong", "is not within 1%"),
    ("m", "0.327 ft^2", "cannot read", "unknown unit 'ft^2'"),
    ("a", "45", "wrong", "not within"),
    ("a", "0.7854 m", "wrong", "m is a length, but the answer is an angle (rad)"),
])
def test_wrong_forms_get_a_reason(key, qid, text, status, words):
    got, message = _status(key, qid, text)
    assert got == status and words in message, message


def test_a_unit_the_key_does_not_give_is_read_but_said_unchecked(key):
    status, message = _status(key, "u", "0.327 m")
    assert status == "correct" and "unit m is not checked: the key gives none" in message


def test_blank_answers_are_no_answer(key, tmp_path):
    rows = [("ann", "x", ""), ("ann", "m", "   "), ("ann", "n", "4")]
    graded = grade_answers(key, rows)
    assert [g.verdict.status for g in graded] == ["no answer", "no answer", "correct"]
    assert [g.points for g in graded] == [0, 0, 1]
    md = write_grading(key, graded, tmp_path)["markdown"].read_text()
    assert "| student | score | correct | wrong | cannot read | no answer |" in md
    assert "| ann | 1 / 8 | 1 | 0 | 0 | 2 |" in md


def test_duplicate_rows_are_reported_and_graded_once(key, tmp_path):
    """A student answering one question twice: the first answer is graded, the later one is 'duplicate' (no points)
    and the report lists it with its CSV row (the header is row 1)."""
    rows = [("ann", "n", "4"), ("bob", "n", "3"), ("ann", "n", "4"), ("ann", "m", "0.327"), ("bob", "n", "4")]
    graded = grade_answers(key, rows)
    assert [g.verdict.status for g in graded] == ["correct", "wrong", "duplicate", "correct", "duplicate"]
    assert sum(g.points for g in graded if g.student == "ann") == 2 and sum(g.points for g in graded
                                                                            if g.student == "bob") == 0
    assert "row 4 repeats row 2" in graded[2].verdict.message and "row 6 repeats row 3" in graded[4].verdict.message
    md = write_grading(key, graded, tmp_path)["markdown"].read_text()
    assert "2 duplicate row(s)" in md and "ann, question n: rows 2, 4" in md


def test_key_units_are_checked(key):
    """A key's unit is read like any user text: an unknown one is refused when the key is read, naming it."""
    bad = {"format": "workspace-sym key", "questions": [{"id": "m", "kind": "measure", "answer": AREA,
                                                          "unit": "__import__('os')"}]}
    with pytest.raises(InvalidParameterError, match="unit of question 'm'"):
        AnswerKey.from_dict(bad)
    with pytest.raises(InvalidParameterError, match="unit of question 'm'"):
        AnswerKey.from_dict({**bad, "questions": [{**bad["questions"][0], "unit": 3}]})


def test_grade_command_reports_duplicates_and_blanks(key, tmp_path, capsys):
    path = tmp_path / "answers.csv"
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["student", "question", "answer"])
        w.writerows([["ann", "n", "Four arcs."], ["ann", "n", "4"], ["ann", "m", ""], ["ann", "m", "0.327 m²"]])
    (tmp_path / "key.json").write_text(json.dumps({
        "format": "workspace-sym key", "questions": [{"id": "n", "kind": "integer", "answer": 4, "unit": "arcs"},
                                                     {"id": "m", "kind": "measure", "answer": AREA,
                                                      "rel_tol": 0.01, "unit": "m^2"}]}))
    assert main(["grade", str(tmp_path / "key.json"), str(path), "--out", str(tmp_path / "o"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["students"] == {"ann": 1.0} and summary["answers"] == 4
    assert summary["duplicates"] == [{"student": "ann", "question": "n", "rows": [2, 3]},
                                     {"student": "ann", "question": "m", "rows": [4, 5]}]
    with (tmp_path / "o" / "graded.csv").open() as f:
        assert [r["status"] for r in csv.DictReader(f)] == ["correct", "duplicate", "no answer", "duplicate"]
