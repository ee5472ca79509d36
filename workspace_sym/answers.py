"""Students' answers as they write them, under their earlier module name.

The code is :mod:`workspace_sym.teaching.answers`; this module keeps the names its users imported from here.
"""

from .teaching.answers import (
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

__all__ = ["Notation", "read_answer", "read_latex", "split_top_level", "expansion_size", "ANGLE_UNITS", "MAX_EXPANSION",
           "Unit", "read_unit", "split_unit", "split_uncertainty", "read_count", "read_yes_no", "plain_sentence",
           "MAX_ENTRIES", "MAX_OPERATIONS"]
