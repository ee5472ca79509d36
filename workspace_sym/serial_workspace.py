"""The certified position workspace of a serial robot, under its earlier module name.

The engine is the package :mod:`workspace_sym.serial` (:func:`~workspace_sym.serial.api.reach` and its plans);
this module keeps the names its users imported from here.
"""

from .serial.api import METHODS, Pose, ReachResult, reach, resolve_method
from .serial.model import ReachModel
from .serial.pairs import CHUNK_PAIRS
from .serial.stored import reach_problem

__all__ = ["reach", "Pose", "ReachResult", "resolve_method", "ReachModel", "METHODS", "CHUNK_PAIRS", "reach_problem"]
