"""The position map of a serial robot over the joints that move it: the model every reach plan proves on.

:class:`ReachModel` keeps the joints the position depends on, their exact ranges (:func:`joint_range`) as
floats enclosing them (inward floats for inner proofs), and compiles each coordinate and each Jacobian entry
(:class:`~workspace_sym.interval.image.ImageMap`).

Joint ranges: a joint's range is its limits.  The position is periodic in a joint variable only when that
variable appears in angles alone, each a rational multiple of it plus a constant (a coupled
``theta_2 = q_2 + q_1/2`` makes ``q_1``'s period ``4 pi``, :func:`period`); a joint whose range spans a period is
then paved over one period without limit faces.  An unlimited revolute joint is paved over one period of the
position (``theta_1 = q_1/2``: ``q_1`` in ``[-2 pi, 2 pi]``), or raises
:class:`~workspace_sym.errors.JointLimitError` when the position is not periodic in it.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import sympy as sp

from ..errors import InvalidParameterError, JointLimitError
from ..interval.boxes import box_sizes
from ..interval.graph import exact_constants
from ..interval.image import ImageMap
from ..kinematics import DHRobot

__all__ = ["TASK", "period", "joint_range", "ReachModel", "reach_model", "cell_width", "check_root", "parameter_values"]

TASK = (sp.Symbol("x"), sp.Symbol("y"), sp.Symbol("z"))


def period(robot: DHRobot, k: int, parameters: dict | None):
    """``(T, "")``, ``T`` the least period of the position in joint ``k``'s variable ``q``, or ``(None, why)``
    when it is not proved periodic.

    A DH matrix holds its angles only through their cosines and sines, so if ``q`` appears in angles alone
    (theta and alpha of any row), each ``c_i q + (terms free of q)`` with every ratio ``c_i / c_0`` rational
    (``n_i / D`` over a common denominator, ``g = gcd(n_i)``), the position is ``T`` periodic in ``q`` where
    ``c_i T`` is in ``2 pi Z`` for every ``i``: ``T = 2 pi D / (g |c_0|)``.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    k : int
        The joint's index (0-based).
    parameters : dict or None
        Values of the robot's symbolic parameters (None: the robot's own).

    Returns
    -------
    T : sympy.Expr or None
        The least period, exact; None when the position is not proved periodic in ``q``.
    why : str
        ``""`` with a period, else why there is none (``q`` sets a length, enters the base or tool transform,
        or turns the angles at rates that are not constants of rational ratio).
    """
    q = robot.q[k]
    lengths = [e for j in robot.joints for e in (j.d, j.a)]
    if any(q in sp.sympify(e).free_symbols for e in lengths):
        return None, f"{q} sets a length of the table"
    if any(M is not None and q in M.free_symbols for M in (robot.base, robot.tool)):
        return None, f"{q} enters the base or tool transform"
    slopes = []
    for joint in robot.joints:
        for angle in (joint.theta, joint.alpha):
            angle = exact_constants(sp.sympify(robot.substitute(angle, parameters)))
            if q in angle.free_symbols:
                slope = sp.diff(angle, q)
                if slope.free_symbols or slope == 0:
                    return None, f"the angle {angle} is not c {q} + terms free of {q} with a constant c"
                slopes.append(slope)
    ratios = [sp.simplify(c / slopes[0]) for c in slopes]
    if not all(r.is_Rational for r in ratios):
        return None, f"its angles turn with {q} at rates {', '.join(map(str, slopes))} of irrational ratio"
    common = math.lcm(*(int(r.q) for r in ratios))
    turns = math.gcd(*(int(r * common) for r in ratios))
    return 2 * sp.pi * common / (turns * abs(slopes[0])), ""


def joint_range(robot: DHRobot, k: int, parameters: dict | None):
    """Exact range of joint ``k`` in the reach model, and whether the position is periodic in it with that
    range as its period (a joint turning the position through whole periods has no limit faces).

    A joint whose range spans a period ``T`` of the position (:func:`period`) is given ``[lo, lo + T]``
    (an unlimited one ``[-T/2, T/2]``): the image is the same.  Whether the limits span ``T`` is decided
    exactly; undecidable counts as not, which is always sound.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    k : int
        The joint's index (0-based).
    parameters : dict or None
        Values of the robot's symbolic parameters (None: the robot's own).

    Returns
    -------
    range : tuple
        ``(lo, hi)``, exact (SymPy): the joint's limits; ``(lo, lo + T)`` when they span a period ``T``;
        ``(-T/2, T/2)`` for a joint without limits.
    periodic : bool
        Whether the range is one period of the position.

    Raises
    ------
    JointLimitError
        The joint has no limits and is prismatic, or the position is not periodic in it.
    """
    joint = robot.joints[k]
    turn, why = period(robot, k, parameters)
    if joint.limits is None:
        if joint.kind == "P":
            raise JointLimitError(f"joint {k + 1} ({joint.variable}) is prismatic: reach needs its limits")
        if turn is None:
            raise JointLimitError(f"joint {k + 1} ({joint.variable}) has no limits and the position is not "
                                  f"periodic in it ({why}): reach needs its limits")
        return (-turn / 2, turn / 2), True
    lo, hi = joint.limits
    try:
        full = turn is not None and bool(sp.simplify(exact_constants(sp.sympify(hi - lo)) - turn) >= 0)
    except TypeError:
        full = False
    return ((lo, lo + turn) if full else (lo, hi)), full


class ReachModel(ImageMap):
    """The position map of a robot over the joints that move it.

    ``coordinates`` are the indices of the position coordinates that depend
    on the joints (two for a planar robot); ``joints`` are the indices of
    the joints the position depends on, ``limits`` their ``(k, 2)`` limits
    (floats enclosing the exact ones).

    Parameters
    ----------
    robot : DHRobot
        The serial robot.
    parameters : dict, optional
        Values of the robot's symbolic parameters (None: the robot's own).

    Raises
    ------
    InvalidParameterError
        ``robot`` is not a :class:`~workspace_sym.kinematics.DHRobot`, its position keeps a symbol other than
        the joints once ``parameters`` are substituted, or it depends on no joint.
    JointLimitError
        A joint the position depends on has no usable range (:func:`joint_range`).
    """

    def __init__(self, robot: DHRobot, parameters: dict | None = None):
        if not isinstance(robot, DHRobot):
            raise InvalidParameterError(f"robot: reach needs a serial DH robot; got {type(robot).__name__}")
        position = robot.substitute(robot.position, parameters)
        free = position.free_symbols - set(robot.q)
        if free:
            raise InvalidParameterError(f"parameters: give values for {', '.join(sorted(map(str, free)))} "
                                        "(the position must be numeric apart from the joints)")
        moving = position.free_symbols
        self.robot = robot
        self.parameters = parameters
        self.position = position
        self.joints = [k for k, q in enumerate(robot.q) if q in moving]
        self.coordinates = [i for i in range(3) if position[i].free_symbols]
        if not self.joints:
            raise InvalidParameterError(f"robot: the position of {robot.name} does not depend on any joint")
        ranges = [joint_range(robot, k, parameters) for k in self.joints]
        self.exact_limits = [r for r, _ in ranges]
        self.task_variables = tuple(TASK[i] for i in self.coordinates)
        super().__init__([position[i] for i in self.coordinates], [robot.q[k] for k in self.joints],
                         [r for r, _ in ranges], [p for _, p in ranges])


def parameter_values(parameters) -> tuple:
    """Parameter values as the hashable key the cached models and structures take: ``(name, value)`` pairs
    sorted by name.

    Parameters
    ----------
    parameters : dict or None
        Values of a robot's symbolic parameters (None or empty: the robot's own).

    Returns
    -------
    tuple
        The pairs; empty for None.
    """
    return tuple(sorted((parameters or {}).items(), key=lambda item: str(item[0])))


@lru_cache(maxsize=16)
def reach_model(robot: DHRobot, parameters: tuple) -> ReachModel:
    """The reach model of a robot (cached: a worker compiles it once for all its chunks).

    Parameters
    ----------
    robot : DHRobot
        The serial robot.
    parameters : tuple
        The parameter values as ``(name, value)`` pairs (hashable); empty for the robot's own.

    Returns
    -------
    ReachModel
        The model, shared by every call with the same robot and values.
    """
    return ReachModel(robot, dict(parameters) or None)


def cell_width(delta: float, size: str, m: int) -> float:
    """Width of cells whose size (diameter or width) is at most ``delta``.

    Parameters
    ----------
    delta : float
        The largest size allowed.
    size : {"diameter", "width"}
        How a cell's size is measured: its diagonal (``sqrt(m)`` times its width) or its width.
    m : int
        The number of task coordinates.

    Returns
    -------
    float
        ``delta / sqrt(m)`` (diameter) or ``delta`` (width), less a relative margin of ``1e-9``.
    """
    return (delta / math.sqrt(m) if size == "diameter" else delta) * (1 - 1e-9)


def check_root(root, delta: float, size: str, robot: DHRobot) -> None:
    """Refuse a task box ``root`` (the enclosure of the position over the limits) that is not finite, or a
    ``delta`` larger than it.

    Parameters
    ----------
    root : numpy.ndarray
        ``(m, 2)`` task box.
    delta : float
        The run's ``delta``.
    size : {"diameter", "width"}
        How the box's size is measured.
    robot : DHRobot
        The robot, whose units the message names.

    Raises
    ------
    InvalidParameterError
        ``root`` is not finite, or ``delta`` exceeds its size.
    """
    if not np.isfinite(root).all():
        raise InvalidParameterError("robot: the position has no finite enclosure over the joint limits",
                                    parameter="robot")
    extent = box_sizes(root[None], size)[0]
    if delta > extent:
        raise InvalidParameterError(f"delta must be at most the size of the workspace's enclosing box "
                                    f"({extent:.6g} {robot.units}); got {delta!r}", parameter="delta")
