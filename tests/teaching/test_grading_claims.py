"""What a student's answer claims (issue 37 item 4): a yes/no verdict with its reason, a hedge that leaves the
answer open, a contradiction, and a value with its uncertainty, ``1.40474 +- 0.01``.

Reference: the grade a careful teacher gives.  A verdict with a reason is graded by the verdict, with or without a
comma; a hedge (``not sure``, ``don't know``, ``didn't solve``, ``maybe``, ``I think``) or a contradiction
(``no, yes``, ``Yes, it is unreachable``) is *cannot read*, with the words; a plus-or-minus sign is never a
subtraction (``1.40474 +- 0.01`` is not ``1.39474``): a measure reads it as the uncertainty of its value, every other
reader of a number refuses it, naming the sign and its column.
"""

import pytest
import sympy as sp
from hypothesis import example, given
from hypothesis import strategies as st

from workspace_sym.answers import Notation, read_answer, read_yes_no, split_uncertainty
from workspace_sym.errors import ExpressionError
from workspace_sym.expressions import parse_expr, parse_math
from workspace_sym.grading import AnswerKey
from workspace_sym.verify import check_expression, check_measure

VALUE = [1.40474, 1.40474]        # a certified measure, 1 % tolerance


@pytest.fixture(scope="module")
def key():
    return AnswerKey.from_dict({"format": "workspace-sym key", "questions": [
        {"id": "no", "kind": "reachable", "answer": False, "evidence": "beyond the reach"},
        {"id": "yes", "kind": "reachable", "answer": True},
        {"id": "m", "kind": "measure", "answer": VALUE, "rel_tol": 0.01},
        {"id": "mu", "kind": "measure", "answer": [0.3268, 0.3272], "rel_tol": 0.01, "unit": "m^2"},
        {"id": "n", "kind": "integer", "answer": 8, "unit": "arcs"},
        {"id": "x", "kind": "expression", "answer": "a1 - a2", "symbols": ["a1", "a2"]}]})


def _grade(key, qid, text):
    v = key.grade(qid, text)
    return v.status, v.message


# ------------------------------------------------------------------------------ yes / no
@pytest.mark.parametrize(("qid", "text", "words"), [
    ("no", "No, not sure", "'not sure' leaves the answer open"),
    ("no", "no, I don't know", "\"don't know\" leaves the answer open"),
    ("no", "No, I didn't solve it", "\"didn't solve\" leaves the answer open"),
    ("no", "no, maybe", "'maybe' leaves the answer open"),
    ("no", "No, I think", "'I think' leaves the answer open"),
    ("no", "No?", "'?' leaves the answer open"),
    ("no", "no, yes", "it says both 'no' and 'yes'"),
    ("yes", "Yes, no", "it says both 'Yes' and 'no'"),
    ("yes", "Yes, it is unreachable", "it says both 'Yes' and no ('unreachable')"),
    ("no", "No, it can be reached", "it says both 'No' and yes ('can be reached')"),
])
def test_hedges_and_contradictions_cannot_be_read(key, qid, text, words):
    """Graded correct before (the first word was taken and the rest ignored)."""
    status, message = _grade(key, qid, text)
    assert status == "cannot read" and words in message, message


@pytest.mark.parametrize(("qid", "text"), [
    ("no", "No because it is too far"), ("no", "no it is too far"), ("no", "It is not reachable"),
    ("no", "No, it cannot reach"), ("no", "The point is out of reach."), ("no", "no configuration reaches it"),
    ("no", "NO - BEYOND THE REACH!"), ("yes", "Yes because theta1 = 0 reaches it"), ("yes", "It is reachable."),
    ("yes", "yes it can be reached"),
])
def test_a_verdict_with_its_reason_is_graded_by_the_verdict(key, qid, text):
    """'No because ...', 'no it is ...' and 'It is not reachable' were 'cannot read' (no comma after the word)."""
    status, message = _grade(key, qid, text)
    assert status == "correct", message


def test_the_column_of_a_hedge_is_given(key):
    assert key.grade("no", "no, I am not sure.").evidence["position"] == 10          # the 'n' of 'not'
    with pytest.raises(ExpressionError) as caught:
        read_yes_no("  no, I am not sure.")
    assert caught.value.position == 12                  # counted in the text as written


def test_y_before_a_blank_is_not_a_verdict():
    """A single letter leads only before a punctuation mark: 'y = 0.5 ...' speaks of a coordinate."""
    assert read_yes_no("y") is True and read_yes_no("n: too far") is False
    with pytest.raises(ExpressionError, match="answer yes"):
        read_yes_no("y = 0.5 is reached")


_VERDICTS = [("yes", True), ("no", False), ("true", True), ("false", False), ("oui", True), ("non", False)]
_SIGNS = [("y", True), ("n", False), ("1", True), ("0", False)]
_SENTENCES = [("reachable", True), ("unreachable", False), ("not reachable", False), ("it is reachable", True),
              ("it is not reachable", False), ("the point is out of reach", False)]
_PUNCTUATION = [",", ", ", ":", " : ", ";", " - ", " \u2014 ", ". "]
# (text, what it claims: True yes, False no, None nothing; a hedge)
_NEUTRAL = ["because of the joint limits", "see the figure", "theta1 = 0 deg", "|p|^2 = 2 > 1.21",
            "because it is too far", "the arm folds back"]
_POLAR = [("it is beyond the reach", False), ("it cannot be reached", False), ("it is out of reach", False),
          ("it is not within reach", False), ("it can be reached", True), ("it is inside the workspace", True),
          ("it is reachable", True), ("it is unreachable", False)]
_HEDGES = ["not sure", "I don't know", "I didn't solve it", "maybe", "I think so", "probably", "no idea",
           "I did not finish", "perhaps not"]
_CASES = [str.lower, str.upper, str.capitalize, lambda s: s]


@st.composite
def _answers(draw):
    """(text, claims, hedged): a verdict x a separator x a reason, a hedge or a contradiction x case x final stop."""
    kind = draw(st.sampled_from(["word", "sign", "sentence"]))
    verdict, truth = draw(st.sampled_from({"word": _VERDICTS, "sign": _SIGNS, "sentence": _SENTENCES}[kind]))
    claims, hedged = {truth}, False
    tail = draw(st.sampled_from(["none", "neutral", "polar", "hedge", "contradiction"]))
    if tail == "none":
        text = verdict
    else:
        # a bare blank separates only a leading word from its reason
        separators = _PUNCTUATION + ([" "] if kind == "word" and tail != "contradiction" else [])
        separator = draw(st.sampled_from(separators))
        if tail == "neutral":
            reason = draw(st.sampled_from(_NEUTRAL))
        elif tail == "polar":
            reason, said = draw(st.sampled_from(_POLAR))
            claims.add(said)
        elif tail == "hedge":
            reason, hedged = draw(st.sampled_from(_HEDGES)), True
        else:
            reason = "no" if truth else "yes"
            claims.add(not truth)
        text = verdict + separator + reason
    text = draw(st.sampled_from(_CASES))(text) + draw(st.sampled_from(["", ".", "!", " ."]))
    return text, claims, hedged


@given(_answers(), st.booleans())
@example(("No, not sure", {False}, True), False)
@example(("no, yes", {False, True}, False), False)
@example(("No because it is too far", {False}, False), False)
@example(("It is not reachable", {False}, False), False)
def test_the_grade_a_careful_teacher_gives(key, answer, truth):
    """correct / wrong by the verdict when the answer says one thing; cannot read when it hedges or says both."""
    text, claims, hedged = answer
    status, message = _grade(key, "yes" if truth else "no", text)
    if hedged or len(claims) > 1:
        expected = "cannot read"
    else:
        expected = "correct" if claims == {truth} else "wrong"
    assert status == expected, (text, message)


# ------------------------------------------------------------------------------ plus or minus
@pytest.mark.parametrize(("text", "status", "words"), [
    ("1.40474 +- 0.01", "correct", "1.40474 +- 0.01 is within 1%"),
    ("1.40474 ± 0.01", "correct", "1.40474 +- 0.01 is within 1%"),
    ("1.40474 +/- 0.01", "correct", "the value is graded, not its stated uncertainty"),
    ("(1.40474 + - 0.01)", "correct", "1.40474 +- 0.01"),
    ("1.40474 +- 0.1", "correct", "1.40474 +- 0.1"),         # was 1.30474: wrong
    ("1.5 +- 0.1", "wrong", "1.5 +- 0.1 is not within 1%"),  # was 1.4: correct
    ("1.40474 +- x", "cannot read", "uncertainty"),
    ("1.40474 +- -0.01", "cannot read", "a number >= 0"),
    ("1.4 +- 0.01 +- 0.02", "cannot read", "plus-or-minus sign"),
])
def test_a_measure_reads_plus_minus_as_an_uncertainty(key, text, status, words):
    got, message = _grade(key, "m", text)
    assert got == status and words in message, message
    assert "1.39474" not in message and "1.30474" not in message


@pytest.mark.parametrize("text", ["(0.327 ± 0.002) m^2", "0.327 +- 0.002 m^2", "0.327 m^2 +- 0.002", "3270 cm² ± 20"])
def test_a_unit_belongs_to_the_value_and_its_uncertainty(key, text):
    status, message = _grade(key, "mu", text)
    assert status == "correct", message


def test_split_uncertainty():
    assert split_uncertainty("(0.327 ± 0.002) m^2") == ("0.327 m^2", "0.002 m^2")
    assert split_uncertainty("45 deg +/- 1") == ("45 deg", "1 deg")
    assert split_uncertainty("2 - 1") == ("2 - 1", None)


@pytest.mark.parametrize(("qid", "text", "column"), [
    ("n", "8 +- 1", 3),          # was 7: wrong
    ("n", "8 ± 0", 3),
    ("x", "a1 + -a2", 4),        # was a1 - a2: correct
    ("x", "a1 +- a2", 4),
    ("x", r"a_1 \pm a_2", 5),
])
def test_other_kinds_refuse_plus_minus_with_its_column(key, qid, text, column):
    v = key.grade(qid, text)
    assert v.status == "cannot read" and "plus-or-minus sign" in v.message, v.message
    assert v.evidence["position"] == column


def test_every_reader_of_a_number_refuses_plus_minus():
    """The root: parse_expr (DH fields, limits, options, numeric answers) and parse_math / read_answer (students'
    expressions) read Python's grammar, where '+-' is '+ (-...)'.  Each refuses it now; a double minus stays a
    subtraction of a negative."""
    with pytest.raises(ExpressionError, match="'\\+-' at column 5 is a plus-or-minus sign"):
        parse_expr("0.1 +- 0.01", "joint 1 d")
    with pytest.raises(ExpressionError, match="plus-or-minus"):
        parse_math("a1 +- 1", "answer", resolve={"a1": sp.Symbol("a1")}.get)
    with pytest.raises(ExpressionError, match="plus-or-minus"):
        read_answer("[a1, a1 +- 1]", Notation.from_symbols([sp.Symbol("a1")]))
    with pytest.raises(ExpressionError, match="plus-or-minus"):
        check_measure("1.40474 +- 0.01", type("R", (), {"measure_bounds": (1.4, 1.41)})())
    assert parse_expr("2 - -1", "d") == 3
    assert check_expression("a1 - (-a2)", "a1 + a2").ok is True


def test_the_column_of_a_contradiction_is_the_second_claim(key):
    assert key.grade("no", "no, yes").evidence["position"] == 5
    assert key.grade("yes", "Yes, it is unreachable").evidence["position"] == 12
