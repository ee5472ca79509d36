"""Exercise sheets with certified keys, and batch grading of a small class (library and command line)."""

import copy
import csv
import json

import numpy as np
import pytest
import sympy as sp

from system_tools import assert_compiles, require_tool
from workspace_sym.answers import Notation, read_answer
from workspace_sym.cli import main
from workspace_sym.exercises import exact_parameters, make_exercises, reach_bound, write_exercises
from workspace_sym.grading import AnswerKey, grade_answers
from workspace_sym.interval import RunOn, StopAt
from workspace_sym.kinematics import DHRobot
from workspace_sym.planar import PlanarChain

SEED, COUNT, JOINTS = 3, 2, 3          # one 3-joint robot, one chain: a small, fast sheet


@pytest.fixture(scope="module")
def generated():
    return make_exercises(seed=SEED, count=COUNT, max_joints=JOINTS)


def _right_answers(key: dict) -> dict:
    """The key's own answers, written as a student would type them."""
    out = {}
    for q in key["questions"]:
        a = q["answer"]
        out[q["id"]] = {"expression": lambda a=a: a, "factors": lambda a=a: ", ".join(a),
                        "reachable": lambda a=a: "yes" if a else "no", "integer": lambda a=a: str(a),
                        "measure": lambda a=a: f"{a[0]:.3g}"}[q["kind"]]()
    return out


def _sentence_answers(key: dict) -> dict:
    """Answers to the count, measure and yes/no questions written as sentences, with units (issue 27)."""
    forms = {"reachable": lambda a: "Yes." if a else "No.", "integer": lambda a: f"{a} arcs.",
             "measure": lambda a: f"{a[0] * 1e4:.4g} cm²"}
    return {q["id"]: forms[q["kind"]](q["answer"]) for q in key["questions"] if q["kind"] in forms}


def _latex_answers(key: dict, parsed: AnswerKey) -> dict:
    """Expression answers in the LaTeX the library prints (c_{23}, pmatrix-like \\left[\\begin{matrix}...)."""
    out = {}
    for q in parsed.questions:
        if q.kind == "expression":
            out[q.id] = parsed.robots[q.robot].to_latex(parsed.derived(q))
    return out


def test_same_seed_same_sheet(generated):
    sheet, key_doc, key = generated
    again = make_exercises(seed=SEED, count=COUNT, max_joints=JOINTS)
    assert again[2] == key and again[0].markdown() == sheet.markdown()
    assert make_exercises(seed=SEED + 1, count=COUNT, max_joints=JOINTS)[2] != key


def test_sheet_asks_every_kind(generated):
    _, _, key = generated
    kinds = [q["kind"] for q in key["questions"]]
    assert kinds.count("expression") == 2                     # an FK entry and a Jacobian column
    assert {"factors", "reachable", "integer", "measure"} <= set(kinds)
    (spec,) = key["robots"].values()
    assert 3 <= len(spec["joints"]) <= JOINTS and spec["convention"] in ("standard", "modified")


def test_key_answers_are_certified(generated):
    """Independent checks of the key: the FK entry is the robot's derived position (exact identity); a witness
    configuration maps exactly onto the point (robot, SymPy) or within 1e-9 (chain); an unreachable robot point
    lies beyond every sampled end point; the chain's area is near a Monte-Carlo estimate."""
    _, _, key = generated
    parsed = AnswerKey.from_dict(key)
    for q in key["questions"]:
        if q["kind"] != "reachable":
            continue
        point = [sp.Rational(p) if "sqrt" not in p else read_answer(p, Notation()) for p in q["point"]]
        if "robot" in q:
            robot = parsed.robots[q["robot"]]
            position = robot.position.subs(exact_parameters(robot))
            if q["answer"]:
                config = {v: read_answer(w, Notation()) for v, w in zip(robot.q, q["witness"])}
                assert all(sp.simplify(position[i].subs(config) - point[i]) == 0 for i in range(3))
            else:
                rng = np.random.default_rng(0)
                f = sp.lambdify(robot.q, position, "numpy")
                lo = [float(j.limits[0]) for j in robot.joints]
                hi = [float(j.limits[1]) for j in robot.joints]
                reach = max(np.linalg.norm(np.array(f(*rng.uniform(lo, hi)), dtype=float))
                            for _ in range(2000))
                assert reach <= float(reach_bound(robot, robot.parameters)) + 1e-12
                assert float(sum(p * p for p in point)) > reach**2
        else:
            chain = parsed.chains[q["chain"]]
            if q["answer"]:
                assert np.allclose(chain.forward(q["witness"]), [float(p) for p in point], atol=1e-9)
    (chain_name, spec), = key["chains"].items()
    chain = PlanarChain(spec["lengths"], spec["lower"], spec["upper"])
    (area,) = [q["answer"] for q in key["questions"] if q["kind"] == "measure"]
    ends = chain.forward(chain.sample(200_000, seed=1, corners=False))
    lo, hi = ends.min(axis=0) - 1e-3, ends.max(axis=0) + 1e-3
    grid = np.stack(np.meshgrid(np.linspace(lo[0], hi[0], 120), np.linspace(lo[1], hi[1], 120)), -1).reshape(-1, 2)
    b = chain.boundary()
    inside = np.mean(b.classify(grid, tol=1e-12) != "outside")
    estimate = inside * (hi[0] - lo[0]) * (hi[1] - lo[1])
    assert abs(estimate - area[0]) < 0.05 * area[0] + 0.002


def test_own_key_gives_full_marks_and_a_flipped_sign_the_expected_wrong_answers(generated):
    _, _, key = generated
    parsed = AnswerKey.from_dict(key)
    right, latex = _right_answers(key), _latex_answers(key, parsed)
    rows = [("ann", qid, text) for qid, text in right.items()]
    rows += [("cat", qid, latex.get(qid, text)) for qid, text in right.items()]
    rows += [("dee", qid, text) for qid, text in _sentence_answers(key).items()]
    graded = grade_answers(parsed, rows)
    assert all(g.verdict.status == "correct" for g in graded), [(g.question, g.verdict.message) for g in graded]
    assert sum(g.points for g in graded if g.student == "ann") == len(key["questions"])
    flipped = copy.deepcopy(key)
    target = next(q for q in flipped["questions"] if q["kind"] == "expression")
    target["answer"] = f"-({target['answer']})"
    graded = grade_answers(AnswerKey.from_dict(flipped), rows)
    wrong = {(g.student, g.question) for g in graded if g.verdict.status == "wrong"}
    assert wrong == {("ann", target["id"]), ("cat", target["id"])}
    g = next(g for g in graded if g.question == target["id"] and g.student == "ann")
    point = {sp.Symbol(k): sp.Rational(v) for k, v in g.verdict.evidence["counterexample"].items()}
    notation = Notation.from_robot(parsed.robots[target["robot"]])
    student, flipped_value = read_answer(g.answer, notation), read_answer(target["answer"], notation)
    assert sp.N((student - flipped_value).subs(point), 30) != 0       # re-checked by exact substitution


def test_wrong_and_unreadable_answers_in_a_class(generated):
    _, _, key = generated
    parsed = AnswerKey.from_dict(key)
    expression = next(q for q in key["questions"] if q["kind"] == "expression")
    integer = next(q for q in key["questions"] if q["kind"] == "integer")
    reach = next(q for q in key["questions"] if q["kind"] == "reachable")
    rows = [("bob", expression["id"], "c1 + * s2"), ("bob", integer["id"], str(integer["answer"] + 1)),
            ("bob", reach["id"], "no" if reach["answer"] else "yes"), ("bea", reach["id"], "perhaps"),
            ("bob", "9z", "1"), ("bea", expression["id"], "__import__('os')")]
    status = [g.verdict.status for g in grade_answers(parsed, rows)]
    assert status == ["cannot read", "wrong", "wrong", "cannot read", "cannot read", "cannot read"]


def test_grade_and_exercises_on_the_command_line(tmp_path, capsys):
    """Both commands end to end; --progress draws their bars on stderr (the JSON on stdout untouched)."""
    out = tmp_path / "sheet"
    assert main(["exercises", "--seed", str(SEED), "--count", str(COUNT), "--max-joints", str(JOINTS),
                 "--out", str(out), "--json", "--progress"]) == 0
    printed = capsys.readouterr()
    files = json.loads(printed.out)["files"]
    assert "exercise sheet" in printed.err and f"{COUNT}/{COUNT}" in printed.err
    assert {"sheet.md", "sheet.html", "sheet.tex", "key.md", "key.html", "key.tex", "key.json"} <= set(files)
    key = json.loads((out / "key.json").read_text())
    assert key == make_exercises(seed=SEED, count=COUNT, max_joints=JOINTS)[2]      # same seed, same key
    answers = tmp_path / "answers.csv"
    with answers.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["student", "question", "answer"])
        for qid, text in _right_answers(key).items():
            w.writerow(["ann", qid, text])
            w.writerow(["bob", qid, "c1 (a1"])
    assert main(["grade", str(out / "key.json"), str(answers), "--out", str(tmp_path / "graded"), "--json",
                 "--progress"]) == 0
    printed = capsys.readouterr()
    summary = json.loads(printed.out)
    rows_graded = 2 * len(key["questions"])
    assert "grading" in printed.err and f"{rows_graded}/{rows_graded}" in printed.err
    assert summary["students"] == {"ann": len(key["questions"]), "bob": 0.0}
    with (tmp_path / "graded" / "graded.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert {r["status"] for r in rows if r["student"] == "ann"} == {"correct"}
    assert any(r["status"] == "cannot read" and r["position"] for r in rows if r["student"] == "bob")
    html = (tmp_path / "graded" / "grades.html").read_text()
    assert "<math" in html and "Student bob" in html and "cannot read" in html


@pytest.mark.parametrize(("argv", "words"), [
    (["grade", "{tmp}/missing.json", "{tmp}/a.csv", "--out", "{tmp}/o"], "key: cannot read"),
    (["grade", "{tmp}/key.json", "{tmp}/bad.csv", "--out", "{tmp}/o"], "needs the columns student, question"),
    (["exercises", "--count", "0", "--out", "{tmp}/o"], "--count: count must be"),
    (["exercises", "--max-joints", "9", "--out", "{tmp}/o"], "--max-joints: max_joints must be 3 to 6"),
])
def test_bad_input_is_one_line_and_writes_nothing(tmp_path, capsys, argv, words):
    (tmp_path / "key.json").write_text(json.dumps({"format": "workspace-sym key", "robots": {"G": "glass-handling"},
                                                   "questions": [{"id": "1", "kind": "expression", "robot": "G",
                                                                  "answer": "c1"}]}))
    (tmp_path / "bad.csv").write_text("name,answer\nann,1\n")
    assert main([a.format(tmp=tmp_path) for a in argv]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_key_is_read_as_untrusted_text(tmp_path):
    bad = {"format": "workspace-sym key", "robots": {"G": "glass-handling"},
           "questions": [{"id": "1", "kind": "expression", "robot": "G", "answer": "__import__('os')"}]}
    with pytest.raises(Exception, match="key question 1: cannot read"):
        AnswerKey.from_dict(bad)
    with pytest.raises(Exception, match="kind of question '1' must be one of"):
        AnswerKey.from_dict({**bad, "questions": [{"id": "1", "kind": "essay", "answer": "x"}]})
    robot = AnswerKey.from_dict({**bad, "questions": [{"id": "1", "kind": "expression", "robot": "G",
                                                       "answer": "c1 (a1 + a2 c2)"}]}).robots["G"]
    assert isinstance(robot, DHRobot)


def test_write_exercises_writes_everything(tmp_path):
    paths = write_exercises(tmp_path, seed=SEED, count=1, max_joints=JOINTS)
    assert "\\begin{document}" in paths["sheet.tex"].read_text()
    assert "answer" in paths["key.md"].read_text() and "Answer key" in paths["key.html"].read_text()
    header, *rows = paths["answers-template.csv"].read_text().splitlines()
    assert header == "student,question,answer" and len(rows) == len(json.loads(paths["key.json"].read_text())
                                                                      ["questions"])


def test_answer_key_typesets_its_answers(tmp_path):
    """Issue 27: key.html showed a literal \\text{answer} (the label went into MathML as a symbol's name) and
    key.tex an overfull box 163 pt wide (the entries of a Jacobian column, set side by side in alignment columns,
    were pushed right by the wide row naming them).  Reference: pdflatex's own log."""
    paths = write_exercises(tmp_path, seed=0, count=1, max_joints=JOINTS)
    page = paths["key.html"].read_text()
    assert "\\text" not in page and page.count("<mtext>answer</mtext>") >= 2
    assert "<mi>answer</mi>" not in page
    tex = paths["key.tex"].read_text()
    # issue 39: the Jacobian column is set as a column (entry by entry only when too wide:
    # tests/teaching/test_grading_teacher)
    assert "\\text{answer} &= \\begin{pmatrix}" in tex
    require_tool("pdflatex")
    assert_compiles(paths["key.tex"])


def test_robot_points_both_ways():
    """Reachable points are the exact image of their witness (SymPy identity); unreachable ones lie beyond the
    triangle-inequality bound, and no sampled configuration comes near them."""
    from workspace_sym import robots
    from workspace_sym.exercises import reachability_point

    robot = robots.build("scara")
    position = robot.position.subs(exact_parameters(robot))
    seen = set()
    for seed in range(8):
        point, reachable, why, witness = reachability_point(robot, np.random.default_rng(seed))
        seen.add(reachable)
        if reachable:
            config = {v: read_answer(w, Notation()) for v, w in zip(robot.q, witness)}
            assert all(sp.simplify(position[i].subs(config) - point[i]) == 0 for i in range(3)), why
        else:
            bound = reach_bound(robot, robot.parameters)
            assert sum(p * p for p in point) > bound**2 and "triangle inequality" in why
            f = sp.lambdify(robot.q, position, "numpy")
            lo, hi = robot.joint_limits().T
            samples = np.random.default_rng(seed).uniform(lo, hi, size=(500, robot.n))
            assert max(np.linalg.norm(np.array(f(*s), dtype=float)) for s in samples) < float(bound) + 1e-12
    assert seen == {True, False}


# ------------------------------------------------------------------------------ reports escape what students write
HOSTILE = ["<img src=x onerror=alert(1)> |p|^2 *b* _i_ `c` [l](http://x) $x$ ~~s~~ & \\", "line one\nline two | x"]


def _md_cells(line: str) -> list[str]:
    """Cells of a GitHub table row: split at the pipes that are not backslash-escaped."""
    import re

    return re.split(r"(?<!\\)\|", line.strip())[1:-1]


def test_reports_escape_every_cell(generated, tmp_path):
    """Issue 30 item 5 / issue 27: a student's name and answer go into grades.md and grades.html as text.  In the
    Markdown every table row keeps the column count of its header (an unescaped '|', as in |p|^2, adds cells; a
    newline ends the row), no '<' of the student reaches the file (inline HTML), no link is made; in the LaTeX
    of a Document the same cells are escaped too."""
    from workspace_sym.grading import write_grading
    from workspace_sym.report import Document

    _, _, key = generated
    parsed = AnswerKey.from_dict(key)
    rows = [(name, q.id, answer) for name in HOSTILE for q, answer in zip(parsed.questions, HOSTILE * 9)]
    paths = write_grading(parsed, grade_answers(parsed, rows), tmp_path)
    md = paths["markdown"].read_text()
    header = None
    for line in md.splitlines():
        if line.startswith("|"):
            if line.startswith("|---") or header is None:
                header = header if line.startswith("|---") else len(_md_cells(line))
                continue
            assert len(_md_cells(line)) == header, line
        else:
            header = None
    assert "<img" not in md and "](http" not in md and "line one\n" not in md
    assert "&lt;img src=x onerror=alert(1)> \\|p\\|^2" in md            # shown, not rendered
    html_text = paths["html"].read_text()
    assert "<img" not in html_text and "&lt;img src=x onerror=alert(1)&gt;" in html_text
    doc = Document("t")
    doc.table(["who", "answer"], [[HOSTILE[0], HOSTILE[1]]])
    tex = doc.latex()
    row = next(line for line in tex.splitlines() if "onerror" in line)
    assert row.count(" & ") == 1 and "\\textbar{}p\\textbar{}" in row and "\\textless{}img" in row  # two cells
    assert "line one line two" in row and "\\&" in row and "\\$x\\$" in row


# ------------------------------------------------------------------------------ time and size budgets
def _long_latex_answer(robot, pairs: int = 20) -> str:
    """A correct answer padded with ``pairs`` cancelling cosines: x of the glass arm plus sum_k (cos(k theta_1) -
    cos(k theta_1)) (20 pairs: about 800 characters of LaTeX, 7 s to check on the machine this was written on)."""
    x = robot.to_latex(robot.position[0])
    pad = " + ".join(f"\\cos({k}\\theta_1) - \\cos({k}\\theta_1)" for k in range(2, 2 + pairs))
    return f"{x} + {pad}"


def test_grading_budgets(tmp_path):
    """Issue 30 item 6: one answer that takes seconds to check is stopped at its budget and marked 'cannot check'
    with the reason (not a wrong answer, no points); once the batch budget is spent the remaining rows are 'not
    graded'; the report says so.  The same answer with a generous budget is accepted (reference: it is the
    derived x plus terms that cancel)."""
    import time

    from workspace_sym.grading import write_grading

    key = AnswerKey.from_dict({"format": "workspace-sym key", "robots": {"G": "glass-handling"},
                               "questions": [{"id": "x", "kind": "expression", "robot": "G",
                                              "answer": "c1 (a1 + a2 c2 + a3 c23 + d5 s234)"}]})
    slow = _long_latex_answer(key.robots["G"])
    assert 700 <= len(slow) <= 1000
    grade_answers(key, [("ann", "x", "c1")])      # the key's derivation (seconds on a cold process) is not the answer's
    began = time.perf_counter()
    (g,) = grade_answers(key, [("ann", "x", slow)], answer_time_limit=0.05)
    assert time.perf_counter() - began < 1.0
    assert g.verdict.status == "cannot check" and g.points == 0 and "0.05 s" in g.verdict.message
    short = _long_latex_answer(key.robots["G"], pairs=1)          # the same answer, one cancelling pair
    assert grade_answers(key, [("ann", "x", short)], answer_time_limit=60)[0].verdict.status == "correct"
    rows = [("ann", "x", slow)] + [(f"bob{k}", "x", "c1") for k in range(5)]
    graded = grade_answers(key, rows, answer_time_limit=0.05, stop=StopAt(time_limit=0.05))
    assert [g.verdict.status for g in graded] == ["cannot check"] + ["not graded"] * 5
    began = time.perf_counter()
    md = write_grading(key, graded, tmp_path)["markdown"].read_text()
    assert time.perf_counter() - began < 1.0                # the report does not read the refused answer again
    assert "1 answer(s) could not be checked within their time budget" in md and "5 were not graded" in md
    with pytest.raises(Exception, match="answer_time_limit must be a positive number"):
        grade_answers(key, rows, answer_time_limit=0)
    # the spelling of earlier releases: the same budgets, each keyword with a DeprecationWarning naming the new one
    with pytest.warns(DeprecationWarning) as caught:
        again = grade_answers(key, rows, answer_seconds=0.05, total_seconds=0.05)
    assert [g.verdict.status for g in again] == ["cannot check"] + ["not graded"] * 5
    assert [str(w.message) for w in caught] == [
        "grade_answers: answer_seconds= is deprecated; pass answer_time_limit=...",
        "grade_answers: total_seconds= is deprecated; pass stop=StopAt(time_limit=...)"]
    assert {w.filename for w in caught} == {__file__}
    with pytest.raises(Exception, match="answer_seconds must be a positive number"), pytest.warns(DeprecationWarning):
        grade_answers(key, rows, answer_seconds=0)


def test_grading_and_sheets_take_stop(generated, tmp_path, capsys):
    """Issue 38 (one options spelling): grade_answers and make_exercises / write_exercises take stop=StopAt(...)
    and honour its time limit, and run=RunOn(progress=) (its bar: tested on the command line); a budget of boxes,
    or a field of RunOn but progress, which they cannot honour, is refused with the field named.  A
    sheet not made within its time limit is one SymbolicBudgetError naming time_limit, and nothing is written;
    under a generous limit it is the same sheet (reference: the key made without a limit from the same seed).
    Without a batch limit (StopAt()) a batch is graded as usual."""
    from workspace_sym.errors import InvalidParameterError, SymbolicBudgetError

    key = AnswerKey.from_dict({"format": "workspace-sym key", "questions": [
        {"id": "n", "kind": "integer", "answer": 4}]})
    assert [g.verdict.status for g in grade_answers(key, [("ann", "n", "4"), ("bob", "n", "5")], stop=StopAt())] == [
        "correct", "wrong"]
    with pytest.warns(DeprecationWarning, match=r"StopAt\(progress=...\) is deprecated"):
        earlier = StopAt(progress=True)                 # the bar's earlier place still draws it
    grade_answers(key, [("ann", "n", "4")], stop=earlier)
    assert "grading" in capsys.readouterr().err
    for call in (lambda: grade_answers(key, [], stop=StopAt(max_boxes=3)),
                 lambda: make_exercises(seed=SEED, count=COUNT, stop=StopAt(section_boxes=3))):
        with pytest.raises(InvalidParameterError, match=r"on time only.*; (max_boxes|section_boxes) does not") as error:
            call()
        assert error.value.parameter == "stop"
    for call in (lambda: grade_answers(key, [], run=RunOn(chunk=10)),
                 lambda: write_exercises(tmp_path / "kept", seed=SEED, count=COUNT, run=RunOn(store=tmp_path))):
        with pytest.raises(InvalidParameterError, match="in this process and keeps no boxes: only progress") as error:
            call()
        assert error.value.parameter == "run"
    assert not (tmp_path / "kept").exists()
    with pytest.raises(SymbolicBudgetError, match=r"time_limit: the exercise sheet .* not made within") as error:
        make_exercises(seed=SEED, count=COUNT, max_joints=JOINTS, stop=StopAt(time_limit=0.001))
    assert error.value.parameter == "time_limit"
    with pytest.raises(SymbolicBudgetError):
        write_exercises(tmp_path / "sheet", seed=SEED, count=COUNT, max_joints=JOINTS, stop=StopAt(time_limit=0.001))
    assert not (tmp_path / "sheet").exists()
    assert make_exercises(seed=SEED, count=COUNT, max_joints=JOINTS, stop=StopAt(time_limit=600))[2] == generated[2]


def test_answers_file_has_a_row_limit(tmp_path, capsys):
    """More rows than MAX_ROWS: refused at once with the limit named, nothing graded or written, on the command
    line too (exit 2, one line) (issue 30 item 6)."""
    from workspace_sym.grading import MAX_ROWS, read_answers_csv

    assert MAX_ROWS <= 20_000
    path = tmp_path / "answers.csv"
    path.write_text("student,question,answer\n" + "ann,1,c1\n" * (MAX_ROWS + 1))
    with pytest.raises(Exception, match=rf"more than {MAX_ROWS} rows, the most one run grades"):
        read_answers_csv(path)
    (tmp_path / "key.json").write_text(json.dumps({"format": "workspace-sym key", "robots": {"G": "glass-handling"},
                                                   "questions": [{"id": "1", "kind": "expression", "robot": "G",
                                                                  "answer": "c1"}]}))
    assert main(["grade", str(tmp_path / "key.json"), str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert f"more than {MAX_ROWS} rows" in err and err.count("\n") == 1 and not (tmp_path / "o").exists()
    path.write_text("student,question,answer\n" + "ann,1,c1\n" * MAX_ROWS)
    assert len(read_answers_csv(path)) == MAX_ROWS


def test_a_budget_swallowed_once_still_stops_the_check():
    """The timer's exception lands wherever the interpreter is; in a gc callback it is only printed (a suite run
    graded a 0.05 s answer for 3 s).  The timer fires again until the block ends, so a check that swallows the
    first interruption is still stopped, within a few retries (reference: the 2 s the loop would run)."""
    import time

    from workspace_sym.errors import SymbolicBudgetError
    from workspace_sym.teaching.grading import RETRY_SECONDS, _time_budget

    swallowed = 0
    began = time.perf_counter()
    with pytest.raises(SymbolicBudgetError):
        with _time_budget(0.02) as interruptible:
            assert interruptible
            while time.perf_counter() - began < 2.0:
                try:
                    time.sleep(0.001)
                except BaseException:         # the timer's interruption (only the timer raises here)
                    if swallowed:
                        raise
                    swallowed += 1
    assert swallowed == 1 and time.perf_counter() - began < 2.0 - 50 * RETRY_SECONDS
    time.sleep(3 * RETRY_SECONDS)           # the timer is disarmed with the block: nothing fires after it
