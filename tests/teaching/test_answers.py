"""Students' answers as they write them: shorthand, juxtaposition, LaTeX, matrices; wrong ones with a real
counterexample, unreadable ones with the place of the problem."""

import pytest
import sympy as sp

from workspace_sym.answers import Notation, read_answer
from workspace_sym.errors import WorkspaceError
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.verify import check_expression

GLASS_X = [  # the glass arm's x coordinate (Bastien's paper 004, printed c1 (a1 + a2 c2 + a3 c23 + d5 s234))
    "c1*(a1 + a2*c2 + a3*c23 + d5*s234)",
    "c1 (a1 + a2 c2 + a3 c23 + d5 s234)",
    "C1 (a1 + a2 C2 + a3 C23 + d5 S234)",
    "c_1 (a_1 + a_2 c_2 + a_3 c_{23} + d_5 s_{234})",
    "cos(q1)*(a1 + a2*cos(q2) + a3*cos(q2 + q3) + d5*sin(q2 + q3 + q4))",
    "cos(t1)(a1 + a2 cos t2 + a3 cos(t2 + t3) + d5 sin(t2 + t3 + t4))",
    "a1 c1 + a2 c1 c2 + a3 c1 (c2 c3 - s2 s3) + d5 c1 s234",
    "c1 · (a1 + a2 c2 + a3 c32 + d5 s423)",
    r"\cos\theta_1 \left(a_1 + a_2 \cos\theta_2 + a_3 \cos(\theta_2 + \theta_3) + d_5 \sin(\theta_2+\theta_3+\theta_4)"
    r"\right)",
    r"c_{1} \left(a_{1} + a_{2} c_{2} + a_{3} c_{23} + d_{5} s_{234}\right)",
    r"\cos{\theta_1} \cdot (a_1 + a_2 \cos \theta_2 + a_3 c_{23} + d_5 s_{234})",
]


@pytest.mark.parametrize("text", GLASS_X)
def test_glass_x_as_students_write_it(glass, text):
    v = check_expression(text, glass.position[0], robot=glass)
    assert v.status == "correct", v.message


def test_library_printers_read_back(glass, puma):
    """Cross-check with the library's own printers: every position entry and the second Jacobian column, as
    robot.to_str (c23 shorthand) and robot.to_latex (c_{23}, a_{2}, matrices in \\left[\\begin{matrix}), is
    read back equal to the derived result."""
    for robot in (glass, puma):
        column = robot.geometric_jacobian[:, 1]
        for e in robot.position:
            for text in (robot.to_str(e), robot.to_latex(e)):
                assert check_expression(text, e, robot=robot).ok is True, text
        assert check_expression(robot.to_latex(column), column, robot=robot).ok is True


def test_puma_answers(puma):
    """Puma 560 x and the Jacobian column 2 (Craig's form: -c1 (a2 s2 + a3 s23 + d4 c23), ...)."""
    x = puma.position[0]
    assert check_expression("c1 (a2 c2 + a3 c23 - d4 s23) + d3 s1", x, robot=puma).ok is True
    assert check_expression(r"c_1\left(a_2 c_2 + a_3 c_{23} - d_4 s_{23}\right) + d_3 s_1", x, robot=puma).ok
    column = puma.geometric_jacobian[:, 1]
    plain = "[-c1 (a2 s2 + a3 s23 + d4 c23), -s1 (a2 s2 + a3 s23 + d4 c23), a2 c2 + a3 c23 - d4 s23, s1, -c1, 0]"
    assert check_expression(plain, column, robot=puma).ok is True
    latex = (r"\begin{pmatrix} -c_1 (a_2 s_2 + a_3 s_{23} + d_4 c_{23}) \\ -s_1 (a_2 s_2 + a_3 s_{23} + d_4 c_{23})"
             r"\\ a_2 c_2 + a_3 c_{23} - d_4 s_{23} \\ s_1 \\ -c_1 \\ 0 \end{pmatrix}")
    assert check_expression(latex, column, robot=puma).ok is True
    flipped = plain.replace("s1, -c1", "s1, c1")
    v = check_expression(flipped, column, robot=puma)
    assert v.status == "wrong" and v.evidence["entry"] == [5, 1]


def test_whole_transform(glass):
    T = glass.fk(2)
    text = "[[c1 c2, -c1 s2, s1, c1 (a1 + a2 c2)], [s1 c2, -s1 s2, -c1, s1 (a1 + a2 c2)], [s2, c2, 0, d1 + a2 s2]," \
           " [0, 0, 0, 1]]"
    assert check_expression(text, T, robot=glass).ok is True
    v = check_expression(text.replace("-c1 s2", "c1 s2"), T, robot=glass)
    assert v.status == "wrong" and v.evidence["entry"] == [1, 2]
    assert check_expression("[c1, s1]", T, robot=glass).status == "wrong"          # shape


@pytest.mark.parametrize("wrong", [
    "c1 (a1 + a2 c2 - a3 c23 + d5 s234)",                      # sign slip on the elbow
    "c1 (a1 + a2 c2 + a3 c23 + d5 c234)",                      # sine for cosine
    r"\cos\theta_1 (a_1 + a_2 \cos\theta_2 + a_3 c_{23})",     # a term forgotten
    "s1 (a1 + a2 c2 + a3 c23 + d5 s234)",
])
def test_wrong_answers_have_a_real_counterexample(glass, wrong):
    """The counterexample is re-checked here by exact substitution, independently of the checker: the student's
    and the derived expression differ there (at 30 digits), and the values the verdict reports are those."""
    derived = glass.position[0]
    v = check_expression(wrong, derived, robot=glass)
    assert v.status == "wrong"
    point = {sp.Symbol(k): sp.Rational(val) for k, val in v.evidence["counterexample"].items()}
    student = read_answer(wrong, Notation.from_robot(glass))
    mine, theirs = sp.N(student.subs(point), 30), sp.N(derived.subs(point), 30)
    assert abs(mine - theirs) > 1e-20
    assert abs(mine - sp.Float(v.evidence["student_value"], 30)) < 1e-25
    assert abs(theirs - sp.Float(v.evidence["derived_value"], 30)) < 1e-25


@pytest.mark.parametrize(("text", "column", "words"), [
    ("c1 (a1 + a2 c2", 4, "never closed"),
    ("c1 + * a2", 6, "nothing on its left"),
    ("c1 (a1 + x)", 10, "unknown name 'x'"),
    ("c7 a1", 1, "unknown name 'c7'"),
    ("a2c2", 1, "unknown name"),
    ("2 3 a1", 3, "two numbers"),
    ("c1 $ a2", 4, "unexpected character"),
    (r"\cos\theta_1 \foo{a_1}", 14, "command '\\foo' is not allowed"),
    (r"c_1 (a_1 + ", 10, "nothing on its right"),
    (r"a_1^{x} \cdot c_1", 5, "small integer"),
    ("import os", 1, "unknown name 'import'"),
])
def test_nonsense_cannot_be_read(glass, text, column, words):
    v = check_expression(text, glass.position[0], robot=glass)
    assert v.status == "cannot read" and v.ok is None
    assert v.evidence["position"] == column and words in v.message, v.message


def test_empty_and_huge_answers_cannot_be_read(glass):
    for text in ("", "   ", r"10^{10^{10}}", r"\frac{1}{0}", "x" * 5000, r"\sqrt[3]{a_1}", "9^9^9^9",
                 "(c1 + s1 + c2 + s2 + a1)^1000", r"(c_1 + s_1 + c_2 + s_2)^{999}", "(c1 + s2)^40 (a1 + a2)^40"):
        assert check_expression(text, glass.position[0], robot=glass).status == "cannot read", text


def test_ambiguous_names_are_refused_with_both_meanings():
    t1 = sp.Symbol("t1")
    robot = DHRobot([DHJoint.revolute(1, a=t1), DHJoint.revolute(2, a=1)])   # a length called t1
    v = check_expression("t1 c1", robot.position[0], robot=robot)
    assert v.status == "cannot read" and "'t1' is ambiguous" in v.message and "theta1" in v.message
    assert check_expression("t1 c1 + c12", robot.position[0], robot=robot).ok is None
    assert check_expression("theta1", sp.Symbol("theta1"), robot=robot).ok is True   # its own name is no alias
    slider = DHRobot([DHJoint.revolute(1, a=1), DHJoint.prismatic(2)])
    v = check_expression("c2", slider.position[0], robot=slider)
    assert v.status == "cannot read" and "joint 2 is prismatic" in v.message
    assert check_expression("q2", sp.Symbol("d2"), robot=slider).ok is True


def test_degrees_stated():
    t1 = sp.Symbol("theta1")
    assert check_expression("cos(q1 + 90)", -sp.sin(t1), angles="degrees").ok is True
    assert check_expression("cos(q1 + pi/2)", -sp.sin(t1), angles="degrees").ok is True   # pi: radians
    assert check_expression("cos(q1 + 90)", -sp.sin(t1)).status == "wrong"               # 90 radians
    assert check_expression(r"\cos\left(\theta_1 + \frac{\pi}{2}\right)", -sp.sin(t1)).ok is True
    assert check_expression("cos(θ1 + π/2)", -sp.sin(t1)).ok is True
    with pytest.raises(WorkspaceError, match="angles must be one of"):
        read_answer("c1", Notation.from_symbols([t1]), angles="grads")


def test_issue_13_reproduction_without_robot(glass):
    """The calls of issue 13, as written there (no robot= given): the shorthand is read from the symbols of the
    derived result, and the paper's juxtaposed notation is accepted instead of raising."""
    x = glass.position[0]
    assert check_expression("c1*(a1 + a2*c2 + a3*c23 + d5*s234)", x).ok is True
    assert check_expression("c1 (a1 + a2 c2 + a3 c23 + d5 s234)", x).ok is True
