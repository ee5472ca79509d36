"""Exercise sheets with certified answer keys, under their earlier module name.

The code is :mod:`workspace_sym.teaching.exercises`; this module keeps the names its users imported from here.
"""

from .teaching.exercises import (
    AREA_DIGITS,
    MAX_COUNT,
    POINT_BOXES,
    exact_parameters,
    make_exercises,
    reach_bound,
    reachability_point,
    write_exercises,
)

__all__ = ["make_exercises", "write_exercises", "exact_parameters", "reach_bound", "reachability_point", "MAX_COUNT",
           "AREA_DIGITS", "POINT_BOXES"]
