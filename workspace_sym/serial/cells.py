"""The critical method on one grid of task cells: a planar arm, or a spatial one without a structure to reduce it.

A planar robot is the map ``q -> (x, y)`` of :func:`workspace_sym.interval.image.critical_paving`: the critical
set of every face of the joint box is covered by joint boxes, whose enclosures mark a grid of cells of size
``delta``; every connected region of unmarked cells misses the workspace boundary, so it is decided by one proof
for one of its cells (Krawczyk inside, exhausted joint boxes outside); marked cells are tried one by one.  Any
other spatial robot (a prismatic first joint, a first joint whose variable enters later rows, ...) is the map
``q -> (x, y, z)`` of the same method in space: the critical set of every face (the position Jacobian's rank below
3, or the tangent cone of the joint box not mapped onto ``R^3``) is covered, its enclosures mark a 3-D grid of
cells, and every 6-connected region of unmarked cells is decided by one proof.  The cover of the faces may be
spread over an executor (:func:`cover_with`, one task per group of faces); the sections of the section plans use
the same cover (:func:`plane_map` names which map).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..interval.boxes import Box
from ..interval.executor import runner_for
from ..interval.image import ImageMap, critical_cover, critical_paving
from ..interval.verdict import INSIDE, OUTSIDE, UNDECIDED
from ..kinematics import DHRobot
from .model import cell_width, reach_model
from .section import RadialMap
from .structure import structure_of
from .tuning import DEFAULT, Tuning

__all__ = ["plane_map", "CoverStep", "cover_with", "pave_cells"]


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


def pave_cells(robot, parameters, delta, size, run, *, executor, tuning: Tuning = DEFAULT):
    """The ``"critical"`` method on one grid of task cells (:func:`critical_paving`): a planar robot, or a
    spatial robot without a product or turned-section structure (cells in space).  Undecided cells are
    boundary boxes, or pending when a budget stopped the run.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    delta : float
        The largest size of a cell (:func:`~workspace_sym.serial.model.cell_width`).
    size : {"diameter", "width"}
        How a cell's size is measured.
    run : RunBudget
        The run's budget: its ``stop_reason`` and ``show``.
    executor : concurrent.futures.Executor or dask.distributed.Client or None
        Where the critical cover runs (:func:`cover_with`).
    tuning : Tuning
        ``cell_chunk``: marked cells proved between two looks at the budget (cells in space).

    Returns
    -------
    tuple
        ``(box, inner, boundary, outer, pending, evaluated, reason)``: the grid's extent as a
        :class:`~workspace_sym.interval.boxes.Box`; lists of ``(N, m, 2)`` arrays of inner, boundary (empty when
        stopped) and outer cells; the undecided cells when stopped, else None; the boxes evaluated; why the
        budget stopped it (``""``: it did not).
    """
    model = reach_model(robot, parameters)
    grid, classes, evaluated, reason = critical_paving(model, cell_width(delta, size, model.m),
                                                       budget=run.stop_reason,
                                                       cover=cover_with(executor, robot, parameters, "model"),
                                                       show=run.show, chunk=None if model.m == 2 else tuning.cell_chunk)
    extent = grid.extent
    box = Box(model.task_variables, tuple(extent[:, 0]), tuple(extent[:, 1]))
    undecided = grid.boxes(classes, UNDECIDED, merge=bool(reason))
    pending = undecided if reason else None
    boundary = [] if reason else [undecided]
    return box, [grid.boxes(classes, INSIDE)], boundary, [grid.boxes(classes, OUTSIDE)], pending, evaluated, reason
