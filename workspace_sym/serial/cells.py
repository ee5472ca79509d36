"""The critical method's cover of faces, spread over an executor.

The critical method (:func:`workspace_sym.interval.image.critical_paving`, run by the plans of
:mod:`workspace_sym.serial.plans` on the cells of the task space and by the section plans on a section) covers
the critical set of every face of the joint box by joint boxes.  That cover may be spread over an executor:
:func:`cover_with` gives one task per group of faces (:class:`CoverStep`, picklable), and :func:`plane_map`
names the map a task rebuilds where it runs (the reach model itself, or the section of a spatial arm).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..interval.executor import runner_for
from ..interval.image import ImageMap, critical_cover
from ..kinematics import DHRobot
from .model import reach_model
from .section import RadialMap
from .structure import structure_of

__all__ = ["plane_map", "CoverStep", "cover_with"]


def plane_map(robot: DHRobot, parameters: tuple, which: str) -> ImageMap | RadialMap:
    """The map whose critical set a cover step covers: the reach model itself (``"model"``: a planar arm, or a
    spatial one paved on cells in space) or the section of a spatial arm (``"section"``).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    which : {"model", "section"}
        Which map.

    Returns
    -------
    ImageMap or RadialMap
        The reach model (:func:`~workspace_sym.serial.model.reach_model`), or the section map of the robot's
        structure (:func:`~workspace_sym.serial.structure.structure_of`; asked only of a robot that has one).
    """
    if which == "model":
        return reach_model(robot, parameters)
    section = structure_of(robot, parameters)
    assert section is not None and section.section is not None     # asked only of a robot with a plane map
    return section.section


@dataclass(frozen=True)
class CoverStep:
    """The critical cover of a group of faces of the planar map or of the section (picklable: the robot
    travels to the workers, the map is compiled there once).

    Called with a list of faces, it returns what :func:`~workspace_sym.interval.image.critical_cover` returns
    for them.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    which : {"model", "section"}
        The map covered (:func:`plane_map`).
    target : float
        The width the joint boxes of the cover are cut to.
    clip : tuple
        An enclosure of the whole image, as nested tuples of ``(lo, hi)`` per coordinate.
    """

    robot: DHRobot
    parameters: tuple
    which: str
    target: float
    clip: tuple

    def __call__(self, faces):
        return critical_cover(plane_map(self.robot, self.parameters, self.which), faces, self.target,
                              np.array(self.clip))


def cover_with(executor, robot, parameters, which):
    """The ``cover`` argument of :func:`critical_paving`: all faces here, or groups of faces, one task each.

    Parameters
    ----------
    executor : concurrent.futures.Executor or dask.distributed.Client or None
        Where the groups run; None: here.
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    which : {"model", "section"}
        The map covered (:func:`plane_map`).

    Returns
    -------
    callable or None
        ``cover(faces, target, clip)``, the list of the covers of the groups of ``faces`` (one group per slot of
        the executor, each a :class:`CoverStep` task); None without an executor (:func:`critical_paving` then
        covers every face here).
    """
    if executor is None:
        return None

    def cover(faces, target, clip):
        spread = runner_for(executor, CoverStep(robot, parameters, which, float(target), tuple(map(tuple, clip))))
        try:
            groups = [faces[i::spread.slots] for i in range(min(spread.slots, len(faces)))]
            return [f.result() for f in [spread.submit(group) for group in groups]]
        finally:
            spread.close()
    return cover
