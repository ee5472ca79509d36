"""Untrusted text (issue 19): every entry point that reads a user string refuses Python code.

``sympy.sympify`` evaluates its input, so a DH file, a command-line option or a
student's answer could run a command on the machine that reads it.  Each
injection string below goes through every entry point of the Python API and of
the command line; each must raise the reader's :class:`ExpressionError` (the
command line: exit status 2 and exactly one line on stderr), and the marker
file that the payloads try to create must never appear.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from hostile import INJECTIONS, MARKER
from paths import ROOT
from workspace_sym import robots
from workspace_sym.cli import main
from workspace_sym.errors import ConstraintError, ExpressionError, WorkspaceError
from workspace_sym.expressions import MAX_LENGTH, as_sympy, parse_angle, parse_expr, read_symbol
from workspace_sym.interval import Box, certify_box, parse_constraints, pave
from workspace_sym.interval.compiler import compile_expr
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.parallel import rpr2
from workspace_sym.planar import PlanarChain
from workspace_sym.snap import chop
from workspace_sym.symbolic import roots_as_symbols, textbook
from workspace_sym.verify import check_boundary_arc, check_expression, check_measure, check_reachable

IDS = [s[:30] for s in INJECTIONS]


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    """Run in tmp_path (relative payload paths land there) and check afterwards that no marker was written."""
    monkeypatch.chdir(tmp_path)
    yield tmp_path
    assert not (tmp_path / MARKER).exists(), "a payload ran"


def _raises_reader_error(call, field):
    with pytest.raises(ExpressionError) as info:
        call()
    message = str(info.value)
    assert field in message, message
    assert "\n" not in message
    return message


# ------------------------------------------------------------------------------------------- Python API
@pytest.mark.parametrize("text", INJECTIONS, ids=IDS)
def test_reader_refuses(text, in_tmp):
    _raises_reader_error(lambda: parse_expr(text, "joint 2 d"), "joint 2 d: ")
    _raises_reader_error(lambda: parse_angle(text, "joint 2 theta", degrees=True), "joint 2 theta: ")
    _raises_reader_error(lambda: as_sympy(text, "expression"), "expression: ")
    _raises_reader_error(lambda: chop(text, 1e-9), "expr: ")                  # public helpers taking expressions
    _raises_reader_error(lambda: roots_as_symbols([text], []), "exprs: ")


@pytest.mark.parametrize("text", INJECTIONS, ids=IDS)
def test_constraints_refuse(text, in_tmp):
    x, y = sp.symbols("x y")
    for s in (text, f"{text} <= 0"):
        with pytest.raises(ConstraintError, match="constraint 1: "):
            parse_constraints([s], (x, y))
        with pytest.raises(ConstraintError, match="constraint 2: "):
            pave(["x <= 1", s], {"x": (0, 1), "y": (0, 1)}, delta=0.5)
        with pytest.raises(ConstraintError, match="constraint 1: "):
            certify_box(Box.from_bounds({"x": (0, 1)}), [s])
    _raises_reader_error(lambda: Box.from_bounds({"x": (text, 1)}), "lower bound of x")


@pytest.mark.parametrize("field", ["d", "a", "alpha", "theta"])
@pytest.mark.parametrize("text", INJECTIONS, ids=IDS)
def test_dh_fields_refuse(text, field, in_tmp):
    row = {"type": "R", "theta": 0, "d": 0, "a": 1, "alpha": 0}
    row[field] = text
    _raises_reader_error(lambda: DHRobot.from_dict({"joints": [{"d": 0, "a": 1, "alpha": 0}, row]}),
                         f"joint 2 {field}: ")
    kwargs = {"d": 0, "a": 1, "alpha": 0, "offset": 0}
    kwargs["offset" if field == "theta" else field] = text
    _raises_reader_error(lambda: DHJoint.revolute(2, **kwargs), "joint 2 ")


@pytest.mark.parametrize("text", INJECTIONS, ids=IDS)
def test_base_and_tool_transforms_refuse(text, in_tmp):
    """The base / tool fields of a DH file (xyz, rpy, 4 x 4) and the constructor's matrices read text by the reader."""
    joints = [{"d": 0, "a": 1, "alpha": 0}]
    matrix = [[1, 0, 0, text], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    robot = DHRobot.from_dict({"joints": joints})
    for key in ("base", "tool"):
        _raises_reader_error(lambda key=key: DHRobot.from_dict({"joints": joints, key: {"xyz": [text, 0, 0]}}),
                             f"{key} xyz: ")
        _raises_reader_error(lambda key=key: DHRobot.from_dict({"joints": joints, key: {"rpy": [0, text, 0]}}),
                             f"{key} rpy: ")
        _raises_reader_error(lambda key=key: DHRobot.from_dict({"joints": joints, key: matrix}), f"{key} matrix: ")
        _raises_reader_error(lambda key=key: DHRobot(robot.joints, **{key: matrix}), key)


@pytest.mark.parametrize("text", INJECTIONS, ids=IDS)
def test_dh_limits_parameters_and_names_refuse(text, in_tmp):
    base = {"d": 0, "a": "l1", "alpha": 0}
    for limits in ([text, 1], [-1, text]):
        _raises_reader_error(lambda limits=limits: DHRobot.from_dict({"joints": [dict(base, limits=limits)]}),
                             "joint 1 limits: ")
        _raises_reader_error(lambda limits=limits: DHRobot.from_dict({"angles": "radians", "joints": [
            {"type": "P", "theta": 0, "a": 0, "alpha": 0, "limits": limits}]}), "joint 1 limits: ")
        _raises_reader_error(lambda limits=limits: DHJoint.revolute(1, limits=limits), "joint 1 ")
    _raises_reader_error(lambda: DHRobot.from_dict({"joints": [base], "parameters": {"l1": text}}), "parameter l1: ")
    _raises_reader_error(lambda: DHRobot.from_dict({"joints": [dict(base, variable=text)]}), "joint 1 variable: ")
    _raises_reader_error(lambda: DHRobot.from_dict({"joints": [base], "parameters": {text: 1}}), "parameters: ")
    robot = DHRobot.from_dict({"joints": [base]})
    _raises_reader_error(lambda: DHRobot(robot.joints, parameters={"l1": text}), "parameter l1: ")
    _raises_reader_error(lambda: robot.substitute(text), "expression: ")


@pytest.mark.parametrize("text", INJECTIONS, ids=IDS)
def test_planar_chain_and_models_refuse(text, in_tmp):
    _raises_reader_error(lambda: PlanarChain([text, 1], [0, 0], [10, 10]), "length of joint 1")
    _raises_reader_error(lambda: PlanarChain([1, 1], [0, text], [10, 10]), "lower limit of joint 2")
    _raises_reader_error(lambda: PlanarChain([1, 1], [0, 0], [10, text]), "upper limit of joint 2")
    for name in ("l0", "lmin", "lmax", "lmin2", "lmax2"):
        _raises_reader_error(lambda name=name: rpr2(**{name: text}), f"{name}: ")
    _raises_reader_error(lambda: robots.build("rpr2", l0=text), "l0: ")


@pytest.mark.parametrize("text", INJECTIONS, ids=IDS)
def test_student_answers_refuse(text, in_tmp):
    # a student's text that cannot be read is a verdict (never an exception): cannot read, with the reason;
    # '[1][0]' alone is arithmetic for a student (brackets are parentheses, juxtaposition multiplies): 1*0, wrong
    for t in (text, "\\cos " + text):  # the plain reader and the LaTeX one
        verdict = check_expression(t, "cos(t1 + t2)")
        assert verdict.status == ("wrong" if text == "[1][0]" else "cannot read"), verdict
        assert verdict.ok is False or verdict.message.startswith("student answer: ")
        assert "\n" not in verdict.message
    _raises_reader_error(lambda: check_expression("cos(t1)", text), "derived: ")
    _raises_reader_error(lambda: check_measure(text, None), "claimed: ")
    _raises_reader_error(lambda: check_reachable(None, (text, 0)), "point: ")
    chain = PlanarChain([1], [0], [90])
    _raises_reader_error(lambda: check_boundary_arc(chain, (0, text), 1, 0, 1), "center: ")
    _raises_reader_error(lambda: check_boundary_arc(chain, (0, 0), text, 0, 1), "radius: ")
    _raises_reader_error(lambda: textbook(text), "expression: ")
    _raises_reader_error(lambda: compile_expr(text, (sp.Symbol("x"),)), "expression: ")


def test_containers_of_text_are_not_sympified(in_tmp):
    """sympify evaluates the strings inside a tuple or dict even with strict=True; as_sympy refuses them."""
    payload = f"__import__('os').system('touch {MARKER}')"
    for value in ((payload,), [payload], {"a": payload}):
        with pytest.raises(ExpressionError, match="expected a SymPy expression or a number"):
            as_sympy(value)


# ------------------------------------------------------------------------------------------- command line
def _cli(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _assert_cli_refuses(capsys, argv, needle):
    code, out, err = _cli(capsys, *argv)
    assert code == 2, (argv[:3], out, err)
    assert out == "" and err.count("\n") == 1 and "Traceback" not in err, err
    assert any(n in err for n in needle), err


def _cli_cases(text, tmp_path):
    """Every subcommand option that reads text, with ``text`` in it, and the field its error must name.

    The chain options are split at commas first, so a payload with a comma may be refused for giving
    the wrong number of values instead; either way nothing of it is evaluated.
    """
    dh = tmp_path / "robot.json"
    joint = ("joint 1", "one value per joint")
    cases = [
        (["pave", "--var", "x=0:1", f"--constraint={text}", "--delta", "0.5"], ("constraint 1",)),
        (["pave", "--var", "x=0:1", "--constraint", "x <= 1", f"--constraint={text} <= 0", "--delta", "0.5"],
         ("constraint 2",)),
        (["pave", f"--var=x={text}:1", "--constraint", "x <= 1", "--delta", "0.5"], ("--var",)),
        (["pave", f"--var=x=0:{text}", "--constraint", "x <= 1", "--delta", "0.5"], ("--var",)),
        (["pave", f"--var={text}=0:1", "--constraint", "x <= 1", "--delta", "0.5"], ("--var",)),
        (["boundary", f"--lengths={text}", "--lower=-60", "--upper=120"], joint),
        (["boundary", "--lengths=0.3", f"--lower={text}", "--upper=120"], joint),
        (["boundary", "--lengths=0.3", "--lower=-60", f"--upper={text}"], joint),
        (["report", "chain", f"--lengths={text}", "--lower=-60", "--upper=120", "--out", str(tmp_path / "r")],
         joint),
    ]
    rows = []
    for field in ("d", "a", "alpha", "theta", "limits"):
        row = {"type": "R", "d": 0, "a": 1, "alpha": 0}
        row[field] = [text, 1] if field == "limits" else text
        rows.append((field, {"joints": [row]}))
    rows.append(("parameter l1", {"joints": [{"d": 0, "a": "l1", "alpha": 0}], "parameters": {"l1": text}}))
    for k, (field, data) in enumerate(rows):
        path = dh.with_name(f"robot{k}.json")
        path.write_text(json.dumps(data))
        for command in ("fk", "jacobian"):
            cases.append(([command, "--dh", str(path)], (field,)))
    return cases


@pytest.mark.parametrize("text", INJECTIONS, ids=IDS)
def test_cli_refuses(text, in_tmp, capsys):
    for argv, needle in _cli_cases(text, in_tmp):
        _assert_cli_refuses(capsys, argv, needle)
    assert not (in_tmp / "r").exists()


@pytest.mark.parametrize("argv", [
    ["boundary", "--lengths=__import__('os').system('touch MARKER')", "--lower=-60", "--upper=120"],
    ["pave", "--var", "x=0:1", "--constraint=__import__('os').system('touch MARKER') <= 0", "--delta", "0.5"],
    ["fk", "--dh", "robot.json"],
])
def test_cli_subprocess_one_line_no_side_effect(argv, tmp_path):
    """The installed entry point end to end: exit status 2, one stderr line, no traceback, no marker."""
    (tmp_path / "robot.json").write_text(json.dumps(
        {"joints": [{"d": f"__import__('os').system('touch {MARKER}')", "a": 1, "alpha": 0}]}))
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-m", "workspace_sym", *argv], cwd=tmp_path, capture_output=True,
                          text=True, timeout=120, env=env)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr and "is not allowed" in proc.stderr
    assert not (tmp_path / MARKER).exists()


# ------------------------------------------------------------------------------------------- property
_TOKENS = ["x", "y", "q1", "(", ")", "+", "-", "*", "**", "^", "/", "1", "0.5", "1e3", "2", "9", "pi", "E", "sin",
           "sqrt", "atan2", ",", "<=", "<", ">", "==", ".", "_", "__class__", "[", "]", "'", '"', "lambda", ":",
           "if", "else", "j", " ", "oo", "nan", "open", "=", "@", "%", "//", "~", "&", "|", "!", "\\", "\x00"]
_MARKER_DIR = Path(__file__).resolve().parent


def _read_everywhere(text):
    x, y = sp.symbols("x y")
    for read in (lambda: parse_expr(text, "p"), lambda: parse_expr(text, "p", new_symbols=False),
                 lambda: parse_expr(text, "p", relational=True), lambda: parse_angle(text, "p", degrees=True),
                 lambda: parse_constraints([text], (x, y))):
        try:
            read()
        except ExpressionError:  # ConstraintError included
            pass


@settings(max_examples=300, deadline=5000, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(alphabet=st.characters(min_codepoint=0, max_codepoint=127), max_size=80))
@example("9**9**9**9")
@example("2^2^2^2^2")
@example("1e-99999999")
@example("1e99999")
@example("x\x00")
@example("(" * 300)
@example("-" * 1999 + "1")
@example("sin(1, 2)")
@example("Min()")
@example("0 < x < 1")
@example("x <= 1 <= y")
@example("atan2(0, 0)")
@example("log(0)")
@example("1/0")
@example("Float + 1")
@example("sqrt(" + "7" * 1990 + ")")  # crashed the size bound once (int too large for a float), then took 3 s
def test_random_ascii_raises_only_expression_error(text):
    _read_everywhere(text)
    assert not (_MARKER_DIR / MARKER).exists() and not Path(MARKER).exists()


@settings(max_examples=300, deadline=5000, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.sampled_from(_TOKENS), max_size=30).map("".join))
def test_token_soup_raises_only_expression_error(text):
    """Near-valid expressions reach deeper into the grammar than random characters do."""
    _read_everywhere(text)
    assert not Path(MARKER).exists()


# ------------------------------------------------------------------------------------------- the legitimate side
q1, q2, x, y = sp.symbols("q1 q2 x y")


@pytest.mark.parametrize("text, expected", [
    ("pi/2", sp.pi / 2),
    ("2*pi/3", 2 * sp.pi / 3),
    ("sqrt(2)/2", sp.sqrt(2) / 2),
    ("-q1", -q1),
    ("q2 + pi/2", q2 + sp.pi / 2),
    ("(x-5)^2", (x - 5) ** 2),
    ("x^2 + y^2", x**2 + y**2),
    ("1e-3", sp.Rational(1, 1000)),
    ("1.5e10", sp.Integer(15_000_000_000)),
    ("0.186", sp.Rational(93, 500)),
    ("0.1", sp.Rational(1, 10)),
    ("3/20", sp.Rational(3, 20)),
    ("10**-3", sp.Rational(1, 1000)),
    ("atan2(1, 1)", sp.pi / 4),
    ("Abs(-2)", sp.Integer(2)),
    ("x**1000", x**1000),
    ("10**300", sp.Integer(10) ** 300),
    ("  x + 1  ", x + 1),
    ("gamma", sp.Symbol("gamma")),   # a DH angle name, not SymPy's gamma function
])
def test_legitimate_text_reads_as_before(text, expected):
    value = parse_expr(text, "p")
    assert value == expected and sp.simplify(value - expected) == 0


def test_student_numbers_may_be_expressions():
    """Numeric answers may be exact expressions, e.g. the closed-form area our own JSON prints."""
    chain = PlanarChain(["0.3", "0.15"], [-120, -30], [0, 30])
    boundary = chain.boundary()
    assert check_measure(boundary.to_dict(exact=True)["area_exact"], boundary).ok is True
    inside = chain.forward(np.radians([[-60.0, 20.0]]))[0]
    assert check_reachable(chain, tuple(repr(float(v)) for v in inside)).ok is check_reachable(chain, inside).ok is True
    assert check_reachable(chain, ("3/10", "-sqrt(4)/10")).ok is check_reachable(chain, (0.3, -0.2)).ok is False


def test_constraint_text_and_objects():
    (c,) = parse_constraints(["x**2 + y**2 <= 144"], (x, y))
    assert sp.expand(c.g - (x**2 + y**2 - 144)) == 0 and not c.strict
    (c,) = parse_constraints(["(x-5)^2 + y^2 > 0.25"], (x, y))
    assert sp.expand(c.g - (sp.Rational(1, 4) - (x - 5) ** 2 - y**2)) == 0 and c.strict
    (c,) = parse_constraints([x**2 <= 2], (x,))        # SymPy relationals pass as objects
    assert c.g == x**2 - 2
    xr = sp.Symbol("x", real=True)                      # text names the box variable, assumptions and all
    (c,) = parse_constraints(["x <= 1"], (xr,))
    assert c.g == xr - 1


def test_decimals_one_rule_and_floats_stay_floats():
    """Text: a decimal is the rational it spells, at every entry point.  Python floats stay floats."""
    assert parse_expr("0.1", "a") == sp.Rational(1, 10)
    assert PlanarChain(["0.1"], [0], [90]).exact_lengths[0] == sp.Rational(1, 10)
    assert DHRobot.from_dict({"joints": [{"d": "0.1", "a": 1, "alpha": 0}]}).joints[0].d == sp.Rational(1, 10)
    value = parse_expr(0.1, "a")
    assert isinstance(value, sp.Float) and value == sp.Float(0.1) and float(value) == 0.1


def test_degrees_table_refuses_symbol_plus_degrees():
    """Issue 18 item 6: "q1 + 90" in a degrees table used to mean 90 radians."""
    joint = {"type": "R", "variable": "q1", "d": 0, "a": 1, "alpha": 0}
    with pytest.raises(ExpressionError, match=r'joint 1 theta: .*"theta": 90.*"q1 \+ pi/2"'):
        DHRobot.from_dict({"joints": [dict(joint, theta="q1 + 90")]})
    for theta, expected in (("q1 + pi/2", q1 + sp.pi / 2), (90, q1 + sp.pi / 2), ("-q1", -q1), ("2*q1", 2 * q1)):
        assert DHRobot.from_dict({"joints": [dict(joint, theta=theta)]}).joints[0].theta == expected
    radians = DHRobot.from_dict({"angles": "radians", "joints": [dict(joint, theta="q1 + 1")]})
    assert radians.joints[0].theta == q1 + 1
    with pytest.raises(ExpressionError, match=r"joint 1 alpha: .*write it in radians"):
        DHRobot.from_dict({"joints": [dict(joint, alpha="a1 + 90")]})


def test_messages_name_field_value_and_what_is_allowed():
    message = _raises_reader_error(lambda: parse_expr("__import__('os')", "joint 2 d", names={"q2": q2},
                                                      new_symbols=False), "joint 2 d: ")
    assert "name '__import__' is not allowed" in message and "allowed: numbers" in message and "q2, pi" in message
    long = "x + " * 1000 + "1"
    message = _raises_reader_error(lambda: parse_expr(long, "a"), "a: ")
    assert f"({len(long)} characters) is too long; at most {MAX_LENGTH}" in message and len(message) < 200
    message = _raises_reader_error(lambda: parse_expr("(" * 150 + "1" + ")" * 150, "a"), "a: ")
    assert "nested more than 100 levels deep" in message
    assert parse_expr("x + " * 1000 + "1", "a", max_length=5000) == 1000 * x + 1
    verdict = check_expression("cos(t1 + z)", "cos(t1 + t2)")
    assert verdict.status == "cannot read" and "unknown name 'z' at column 10" in verdict.message
    assert verdict.evidence["position"] == 10
    with pytest.raises(ExpressionError, match="expected a name"):
        read_symbol("lambda", "joint 1 variable")


def test_reader_is_extensible():
    """Later callers (teaching) can add names and restrict functions without touching the reader."""
    theta = sp.Symbol("theta", real=True)
    assert parse_expr("cos(theta)", "p", names={"theta": theta}, new_symbols=False) == sp.cos(theta)
    with pytest.raises(ExpressionError, match="function 'sin' is not allowed"):
        parse_expr("sin(x)", "p", functions={"cos"})
    from sympy.parsing.sympy_parser import split_symbols
    assert parse_expr("x*y", "p", transformations=(split_symbols,)) == x * y


def test_generated_code_is_checked_too(in_tmp):
    """A transformation that smuggles code in is caught: the code SymPy would evaluate is validated as well."""
    from tokenize import NAME, OP, STRING

    def smuggle(tokens, local_dict, global_dict):
        return [(NAME, "open"), (OP, "("), (STRING, repr(MARKER)), (OP, ","), (STRING, "'w'"), (OP, ")")]

    with pytest.raises(ExpressionError, match="function 'open' is not allowed"):
        parse_expr("x", "p", transformations=(smuggle,))


def test_every_catalog_entry_still_builds():
    for entry in robots.catalog():
        assert robots.build(entry.name) is not None


def test_workspace_error_root():
    assert issubclass(ConstraintError, ExpressionError) and issubclass(ExpressionError, WorkspaceError)


# The public helpers of the symbolic core, the characteristic polynomial, the float evaluators and the interval
# images take SymPy objects; text given to them once went to sympy.sympify (or sympy.Matrix, which calls it), and
# ran (found by the docstring review of issue 38).  Now each reads it through the safe reader.
def _symbolic_helpers():
    from workspace_sym import symbolic
    from workspace_sym.charpoly import gram_characteristic_polynomial, maximal_minor_factors
    from workspace_sym.interval.image import ImageMap
    from workspace_sym.kinematics import numeric_function

    t = sp.Symbol("t")
    return [lambda text: symbolic.textbook_form(text, (t,)), lambda text: symbolic.op_counts([text]),
            lambda text: symbolic.expansion_size(text, 10**6), lambda text: symbolic.numeric_atoms([text]),
            lambda text: gram_characteristic_polynomial([[text, 1]]), lambda text: maximal_minor_factors([[text]]),
            lambda text: numeric_function([text], (t,)), lambda text: ImageMap([text], [t], [(0, 1)], [False]),
            lambda text: DHRobot([DHJoint.revolute(1, a=1)]).textbook(text)]


@pytest.mark.parametrize("text", INJECTIONS[:8], ids=IDS[:8])
def test_the_symbolic_helpers_read_text_and_never_run_it(text, in_tmp):
    for call in _symbolic_helpers():
        with pytest.raises(ExpressionError):
            call(text)
