"""What a reach run stores: the fingerprint of its whole problem, and the section kept beside its checkpoint.

:func:`reach_problem` names every field of a run's problem (the exact robot, the parameter values, ``delta``,
``size``, the tuning, the constraint and the method) for the
:class:`~workspace_sym.interval.fingerprint.Fingerprint` of its checkpoint; a section paved under a time limit
may refine differently on another run, so it is kept beside the checkpoint (:func:`save_section`, in
``FILE.section.npz``) and taken again on resuming (:func:`saved_section`), refused when it names another problem.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np

from ..errors import InvalidParameterError
from ..files import write_npz
from ..interval import image
from ..interval.driver import RunOn
from ..interval.fingerprint import Fingerprint, check_fingerprint
from ..interval.image import CellGrid
from ..kinematics import DHRobot
from . import angles, section, turn
from .section import Pieces
from .tuning import DEFAULT, Tuning

__all__ = ["reach_problem", "section_file", "save_section", "saved_section"]


def reach_problem(robot: DHRobot, parameters, delta: float, size: str, tuning: Tuning = DEFAULT, **more) -> dict:
    """The whole problem of a reach run, by named fields, for the fingerprint of everything it stores or resumes
    (:class:`~workspace_sym.interval.fingerprint.Fingerprint`): the exact robot
    (:meth:`~workspace_sym.kinematics.DHRobot.problem_fields`: every DH entry, type, offset, limit, base, tool,
    parameter), the parameter values given, ``delta``, ``size``, the tuning (:class:`Tuning`, with the constants
    of the engine that change which boxes are proved) and ``more`` (the constraint, the method and its options).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : dict or iterable of pairs
        The parameter values given (``(name, value)`` pairs, or a dict).
    delta : float
        The run's ``delta``.
    size : {"diameter", "width"}
        The run's ``size``.
    tuning : Tuning
        The run's tuning.
    **more
        Further fields, by name.

    Returns
    -------
    dict
        The fields by name: the robot's, then ``"parameters"`` (sorted pairs), ``"delta"`` (a float), ``"size"``,
        ``"tuning"`` (its fields and the engine's constants) and ``more``.

    Examples
    --------
    >>> from workspace_sym.kinematics import DHJoint
    >>> arm = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=1, limits=(-1, 1))])
    >>> sorted(reach_problem(arm, (), 0.1, "diameter"))[:4]
    ['delta', 'parameters', 'robot base', 'robot chop_tol']
    """
    values = sorted(dict(parameters).items(), key=lambda item: str(item[0]))
    engine = {"OUTSIDE_PAIRS": image.OUTSIDE_PAIRS, "MAX_COVER_BOXES": image.MAX_COVER_BOXES,
              "OUTSIDE_MIN_CELLS": image.OUTSIDE_MIN_CELLS, "MINOR_SIMPLIFY_OPS": image.MINOR_SIMPLIFY_OPS,
              "REACH_SIMPLIFY_OPS": section.REACH_SIMPLIFY_OPS, "ANGLE_PAD": angles.ANGLE_PAD,
              "DIRECTIONS": turn.DIRECTIONS}
    return {**robot.problem_fields(), "parameters": values, "delta": float(delta), "size": size,
            "tuning": {**tuning.to_dict(), **engine}, **more}


def section_file(where: RunOn) -> Path | None:
    """The file beside a checkpoint ``where.resume`` keeping the section its task boxes are classified from.

    Parameters
    ----------
    where : RunOn
        The run's options.

    Returns
    -------
    pathlib.Path or None
        ``RESUME.section.npz``; None without ``where.resume``.
    """
    return None if where.resume is None else Path(f"{where.resume}.section.npz")


def save_section(where: RunOn, named: Fingerprint, grid, classes, proved, pieces, evaluated: int) -> None:
    """Keep a paved section beside the checkpoint (written whole, then renamed: never half-written), with the
    fingerprint of its problem ``named``.

    Nothing is written without ``where.resume`` or without a section (``classes`` None).

    Parameters
    ----------
    where : RunOn
        The run's options (:func:`section_file`).
    named : Fingerprint
        The section's whole problem.
    grid : CellGrid
        The section's grid.
    classes : numpy.ndarray or None
        The verdict code of each cell.
    proved : numpy.ndarray or None
        The pieces proved at each direction of a limited turn, or None.
    pieces : Pieces or None
        The pieces of undecided cells proved inside or outside, or None.
    evaluated : int
        The boxes the section evaluated.
    """
    path = section_file(where)
    if path is None or classes is None:
        return
    pieces = pieces or Pieces.none()
    write_npz(path, named=np.array(json.dumps(named.to_json())), box=grid.box, width=np.array(grid.width),
              classes=classes, proved=np.zeros(0, dtype=bool) if proved is None else proved, inner=pieces.inner,
              outer=pieces.outer, evaluated=np.array(evaluated))


def saved_section(where: RunOn, named: Fingerprint):
    """``(grid, classes, proved, pieces, evaluated)`` of the section kept beside the checkpoint, or None (no
    checkpoint, or no file yet: the section is paved).  A file of another problem than ``named`` is refused,
    naming what differs, as a checkpoint is.

    Parameters
    ----------
    where : RunOn
        The run's options (:func:`section_file`).
    named : Fingerprint
        The whole problem the section must name.

    Returns
    -------
    tuple or None
        ``(grid, classes, proved, pieces, evaluated)``: the :class:`~workspace_sym.interval.image.CellGrid`, the
        verdict code of each cell, the pieces proved per direction (None when none were kept), the
        :class:`~workspace_sym.serial.section.Pieces` and the boxes evaluated; None when there is no such file.

    Raises
    ------
    InvalidParameterError
        The file cannot be read as a kept section, or it names another problem.
    """
    path = section_file(where)
    if path is None or not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            stored = json.loads(str(data["named"]))
            check_fingerprint(stored, named, what=f"{str(path)!r} is the section kept beside a checkpoint")
            grid = CellGrid(data["box"], float(data["width"]))
            classes, proved = data["classes"], data["proved"]
            if classes.shape != grid.shape:
                raise ValueError(f"{classes.shape} cells for a grid of {grid.shape}")
            return (grid, classes, proved if proved.size else None, Pieces(data["inner"], data["outer"]),
                    int(data["evaluated"]))
    except InvalidParameterError:
        raise                                     # another problem's section: check_fingerprint names what differs
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
        raise InvalidParameterError(f"resume: {str(path)!r} beside the checkpoint is not a section kept by "
                                    f"reach ({exc})", parameter="resume") from None
