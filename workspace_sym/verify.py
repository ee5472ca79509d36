"""Checks of a student's answer with their evidence, under their earlier module name.

The code is :mod:`workspace_sym.teaching.checks` (``Verdict``, the ``check_*`` functions and their ``assert_*``
forms); this module keeps the names its users imported from here.
"""

from .teaching.checks import (
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

__all__ = ["Verdict", "cannot_read", "exact_parameters", "check_expression", "check_factors", "check_reachable",
           "check_boundary_arc", "check_measure", "assert_expression", "assert_factors", "assert_reachable",
           "assert_boundary_arc", "assert_measure", "REACH_TOLERANCE", "MAX_BOXES"]
