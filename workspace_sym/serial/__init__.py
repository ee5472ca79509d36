"""Certified workspaces of serial robots: the position workspace, and where the tool can point.

One entry point, :func:`reach` (:mod:`.api`), and one engine of plans (:mod:`.plans`), each with the same three
steps: pave a section or cells, decide the task boxes, prove the volume.  The rooms, from the bottom up:

* :mod:`.tuning`: every figure that changes which boxes are proved, in one frozen :class:`Tuning`;
* :mod:`.model`: the position map over the joints that move it (:class:`ReachModel`), joint ranges and periods;
* :mod:`.angles`: polar angles of task boxes and arcs of a first joint's range;
* :mod:`.section`: an arm turned by its first joint, its ``(rho, z)`` section and its stages of proofs;
* :mod:`.turn`: the same with a first joint limited to part of a turn;
* :mod:`.structure`: which structure a spatial arm has (a product, a revolved or a turned section);
* :mod:`.classify`: task boxes classified from a paved section, by the paving driver;
* :mod:`.cells`: the critical method on one grid of task cells (planar arms, arms without structure);
* :mod:`.pairs`: the pairs method, one loop for positions and poses;
* :mod:`.pose`: constraints on the tool frame (an approach cone, a constant orientation) and their models;
* :mod:`.stored`: the fingerprint of a run's whole problem, and the section kept beside a checkpoint;
* :mod:`.plans`: the plans, and which a robot gets;
* :mod:`.api`: :func:`reach`, :class:`Pose`, :class:`ReachResult`;
* :mod:`.reachmap`: certified reachability maps (:func:`reach_map`, :class:`ReachMap`), one pose run a direction.

The engine builds on :mod:`workspace_sym.kinematics`, which does not import it: importing this package registers
:func:`reach` in :data:`workspace_sym.kinematics.ENGINES`, where ``DHRobot.reach`` finds it.
"""

from ..kinematics import ENGINES
from .api import METHODS, Pose, ReachResult, reach, resolve_method
from .model import ReachModel
from .pose import PoseConstraint, approach_constraint, orientation_constraint
from .reachmap import ReachMap, reach_map
from .stored import reach_problem
from .tuning import DEFAULT, Tuning

__all__ = ["reach", "Pose", "ReachResult", "Tuning", "DEFAULT", "resolve_method", "METHODS", "ReachModel",
           "PoseConstraint", "approach_constraint", "orientation_constraint", "reach_problem",
           "reach_map", "ReachMap"]

ENGINES["reach"] = reach
