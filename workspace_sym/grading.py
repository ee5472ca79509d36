"""Answer keys and batch grading, under their earlier module name.

The code is :mod:`workspace_sym.teaching.grading`; this module keeps the names its users imported from here.
"""

from .teaching.grading import (
    ANSWER_SECONDS,
    BATCH,
    DELIMITERS,
    KEY_FORMAT,
    KIND_NAMES,
    MAX_ROWS,
    RETRY_SECONDS,
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

__all__ = ["KIND_NAMES", "KEY_FORMAT", "Question", "AnswerKey", "GradedAnswer", "grade_answers", "read_answers_csv",
           "write_grading", "duplicate_rows", "similar_students", "tolerance_rule", "accepted_range", "DELIMITERS",
           "MAX_ROWS", "ANSWER_SECONDS", "TOTAL_SECONDS", "RETRY_SECONDS", "BATCH"]
