"""Teaching: students' answers read, checked with a proof, graded in batches; exercise sheets with certified keys.

The rooms, from the bottom up (each imports only the rooms above it in this list, and the package's lower layers):

* :mod:`.options`: which fields of :class:`~workspace_sym.interval.driver.StopAt` and
  :class:`~workspace_sym.interval.driver.RunOn` each function honours (the others are refused), and the warning for
  the keywords of earlier releases;
* :mod:`.answers`: students' answers as they write them (textbook shorthand, juxtaposition, LaTeX, matrices, units,
  yes/no, counts in words): :class:`Notation`, :func:`read_answer`, :func:`read_latex`;
* :mod:`.checks`: one answer checked, with its evidence: :class:`Verdict` and the ``check_*`` functions (an exact
  identity or a counterexample, matching singular factors, a point proved reachable or unreachable, a claimed arc or
  measure), and their ``assert_*`` forms for autograders;
* :mod:`.grading`: answer keys (:class:`AnswerKey`, :class:`Question`), a CSV of answers graded under a time budget
  (:func:`grade_answers`), the graded CSV and the report (:func:`write_grading`);
* :mod:`.exercises`: exercise sheets drawn from a seed, with answer keys derived and certified here
  (:func:`make_exercises`, :func:`write_exercises`).

The functions that may run long take ``stop=StopAt(...)`` as the rest of the package does: ``max_boxes`` for the box
search of :func:`check_reachable`, ``time_limit`` for a batch of :func:`grade_answers` (its budget per answer is
``answer_time_limit``) and for a sheet of :func:`make_exercises`.  These two, which run long, take
``run=RunOn(progress=...)`` for their progress bar; they run in this process and keep no boxes, so the other fields
of a ``RunOn`` are refused.

The earlier module paths ``workspace_sym.answers``, ``workspace_sym.verify`` (now :mod:`.checks`),
``workspace_sym.grading`` and ``workspace_sym.exercises`` still hold their public names.
"""

from . import answers, checks, exercises, grading
from .answers import (
    ANGLE_UNITS,
    MAX_ENTRIES,
    MAX_EXPANSION,
    MAX_OPERATIONS,
    Notation,
    Unit,
    expansion_size,
    plain_sentence,
    read_answer,
    read_count,
    read_latex,
    read_unit,
    read_yes_no,
    split_top_level,
    split_uncertainty,
    split_unit,
)
from .checks import (
    MAX_BOXES,
    REACH_TOLERANCE,
    Verdict,
    assert_boundary_arc,
    assert_expression,
    assert_factors,
    assert_measure,
    assert_reachable,
    cannot_read,
    check_boundary_arc,
    check_expression,
    check_factors,
    check_measure,
    check_reachable,
    exact_parameters,
)
from .exercises import (
    AREA_DIGITS,
    MAX_COUNT,
    POINT_BOXES,
    make_exercises,
    reach_bound,
    reachability_point,
    write_exercises,
)
from .grading import (
    ANSWER_SECONDS,
    BATCH,
    DELIMITERS,
    KEY_FORMAT,
    KIND_NAMES,
    MAX_ROWS,
    TOTAL_SECONDS,
    AnswerKey,
    GradedAnswer,
    Question,
    accepted_range,
    duplicate_rows,
    grade_answers,
    read_answers_csv,
    similar_students,
    tolerance_rule,
    write_grading,
)

__all__ = [
    "answers", "checks", "grading", "exercises",
    # answers
    "Notation", "read_answer", "read_latex", "split_top_level", "expansion_size", "ANGLE_UNITS", "MAX_EXPANSION",
    "MAX_ENTRIES", "MAX_OPERATIONS", "Unit", "read_unit", "split_unit", "split_uncertainty", "read_count",
    "read_yes_no", "plain_sentence",
    # checks
    "Verdict", "cannot_read", "exact_parameters", "check_expression", "check_factors", "check_reachable",
    "check_boundary_arc", "check_measure", "assert_expression", "assert_factors", "assert_reachable",
    "assert_boundary_arc", "assert_measure", "REACH_TOLERANCE", "MAX_BOXES",
    # grading
    "KIND_NAMES", "KEY_FORMAT", "Question", "AnswerKey", "GradedAnswer", "grade_answers", "read_answers_csv",
    "write_grading", "duplicate_rows", "similar_students", "tolerance_rule", "accepted_range", "DELIMITERS",
    "MAX_ROWS", "ANSWER_SECONDS", "TOTAL_SECONDS", "BATCH",
    # exercises
    "make_exercises", "write_exercises", "reach_bound", "reachability_point", "MAX_COUNT", "AREA_DIGITS", "POINT_BOXES",
]
