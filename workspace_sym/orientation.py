"""Certified orientation workspaces, under their earlier module name: :mod:`workspace_sym.serial.pose`.

``reach_pose`` is the entry point of earlier releases: ``reach(robot, pose=Pose(...), stop=StopAt(...),
run=RunOn(...), tuning=Tuning(...))`` is its spelling now.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

from .interval.driver import RunOn, StopAt
from .serial.api import Pose, ReachResult, reach
from .serial.pose import (
    ORTHOGONAL_TOL,
    PoseConstraint,
    PoseModel,
    approach_constraint,
    constraint_from,
    orientation_constraint,
    section_volume_bracket,
)
from .serial.tuning import DEFAULT

__all__ = ["PoseConstraint", "approach_constraint", "orientation_constraint", "constraint_from", "reach_pose",
           "PoseModel", "section_volume_bracket", "ORTHOGONAL_TOL"]


def reach_pose(robot, *, delta: float, approach=None, cone=None, every: bool = False, orientation=None,  # noqa: PLR0913
               rpy=None, size: str = "diameter", parameters: dict | None = None, max_boxes: int | None = None,
               time_limit: float | None = None, progress: bool | None = None, max_pairs: int | None = None,
               inner_depth: int | None = None, chunk_pairs: int | None = None, section_ratio: float | None = None,
               run: RunOn = RunOn()) -> ReachResult:
    """Deprecated: ``reach(robot, delta=..., pose=Pose(approach=, cone=, every=, orientation=, rpy=),
    stop=StopAt(max_boxes=, time_limit=), run=RunOn(progress=), tuning=Tuning(pose_max_pairs=, pose_inner_depth=,
    section_ratio=))``, which this calls.  ``chunk_pairs`` no longer applies (the pose methods cut their chunks
    themselves; the boxes never depended on it).

    Parameters
    ----------
    robot : DHRobot
        The serial robot (``reach``'s ``robot``).
    delta : float
        Undecided task boxes whose size is at most ``delta`` become boundary boxes (``reach``'s ``delta``).
    approach : sequence of three numbers, optional
        The axis of the cone (``Pose.approach``).
    cone : float, optional
        The cone's half-angle in degrees, 0 for the exact direction (``Pose.cone``).
    every : bool
        Every direction of the cone rather than some (``Pose.every``).
    orientation : 3 x 3 array_like, optional
        A constant tool rotation (``Pose.orientation``).
    rpy : sequence of three angles, optional
        A constant tool rotation as roll, pitch, yaw in degrees (``Pose.rpy``).
    size : {"diameter", "width"}
        How a box's size is measured (``reach``'s ``size``).
    parameters : dict, optional
        Values of the symbolic lengths (``reach``'s ``parameters``).
    max_boxes : int, optional
        ``StopAt.max_boxes``.
    time_limit : float, optional
        ``StopAt.time_limit``, in seconds.
    progress : bool, optional
        ``RunOn.progress``; None keeps ``run.progress``.
    max_pairs : int, optional
        ``Tuning.pose_max_pairs``; None keeps the default.
    inner_depth : int, optional
        ``Tuning.pose_inner_depth``; None keeps the default.
    chunk_pairs : int, optional
        Ignored (see above).
    section_ratio : float, optional
        ``Tuning.section_ratio``; None keeps the default.
    run : RunOn
        Where and how the run goes (``reach``'s ``run``).

    Returns
    -------
    ReachResult
        What ``reach`` returns with this ``pose``.

    Raises
    ------
    InvalidParameterError
        As :func:`~workspace_sym.serial.api.reach` with a pose: a bad constraint, ``delta``, ``size`` or option.
    JointLimitError
        A prismatic joint without limits, or an unlimited revolute joint the position is not periodic in.

    Warns
    -----
    DeprecationWarning
        Always: this spelling is deprecated.
    """
    warnings.warn("reach_pose is deprecated; pass reach(robot, delta=..., pose=Pose(...), stop=StopAt(...), "
                  "run=RunOn(...), tuning=Tuning(...))", DeprecationWarning, stacklevel=2)
    changes = {name: value for name, value in (("pose_max_pairs", max_pairs), ("pose_inner_depth", inner_depth),
                                               ("section_ratio", section_ratio)) if value is not None}
    return reach(robot, delta=delta, size=size, parameters=parameters,
                 stop=StopAt(max_boxes=max_boxes, time_limit=time_limit),
                 run=run if progress is None else replace(run, progress=progress),
                 pose=Pose(approach=approach, cone=cone, every=every, orientation=orientation, rpy=rpy),
                 tuning=DEFAULT.replace(**changes))
