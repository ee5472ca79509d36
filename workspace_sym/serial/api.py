"""Certified workspace of a serial robot: reachable boxes proved, unreachable boxes proved.

:func:`reach` paves the space of end-effector positions (``x, y`` for a planar robot, ``x, y, z`` otherwise) into

* **outer** boxes: no configuration within the joint limits puts the end-effector in the box;
* **inner** boxes: every point of the box is the position of some configuration within the joint limits;
* **boundary** boxes: neither is proved and the box is at most ``delta``;

and, with a constraint on the tool frame (``pose=Pose(...)``), the positions the tool reaches with its frame so
constrained (:mod:`workspace_sym.serial.pose`).  It validates its options, picks a plan (:mod:`.plans`: the
critical method on one grid of cells, the section of a turned arm, the pairs method, or the pose plans), runs its
three steps under one budget (:class:`~workspace_sym.interval.driver.StopAt`, whose clock starts before the
symbolic preparation), and returns a :class:`ReachResult`: the paving, the method, the volume bracket proved
another way when there is one, and the constraint.

Every verdict rests on outward-rounded interval arithmetic (numpy engine): the enclosures of the position and of
the Jacobian's minors, the Krawczyk operator, and the box classification (docs/methods.md sections 5 and 8).
"""

from __future__ import annotations

import dataclasses
import warnings
from contextlib import contextmanager
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..errors import CoverTooLarge, InvalidParameterError, SymbolicBudgetError
from ..interval import arith
from ..interval.boxes import Box, Paving, check_delta
from ..interval.driver import RunBudget, RunOn, StopAt
from ..kinematics import DHRobot
from ..numbers import fmt_bracket
from ..symbolic import symbolic_budget
from .model import check_root, parameter_values, reach_model
from .plans import choose_plans, pose_plan
from .pose import PoseConstraint, constraint_from, pose_structure
from .stored import reach_problem
from .tuning import DEFAULT, Tuning

__all__ = ["reach", "Pose", "ReachResult", "resolve_method", "METHODS"]

METHODS = ("auto", "critical", "pairs")


@dataclass(frozen=True, slots=True)
class Pose:
    """A constraint on the tool frame for :func:`reach` (:mod:`workspace_sym.serial.pose`): the approach axis (z of
    the tool frame) within ``cone`` degrees of ``approach`` (``every``: every direction of the cone), or the frame
    exactly ``orientation`` (a rotation matrix) or ``rpy`` (roll, pitch, yaw in degrees).

    Parameters
    ----------
    approach : sequence of three numbers, optional
        The cone's axis, in the base frame (any length but zero).
    cone : float, optional
        The cone's half-angle in degrees (0: the exact direction); given with ``approach``.
    every : bool
        Every direction of the cone rather than some (the dextrous workspace).
    orientation : 3 x 3 array_like, optional
        A constant rotation of the tool frame.
    rpy : sequence of three angles, optional
        The same as roll, pitch, yaw (``Rz(yaw) Ry(pitch) Rx(roll)``; numbers are degrees, text with ``pi``
        radians).

    Examples
    --------
    >>> Pose(approach=(0, 0, -1), cone=20)
    Pose(approach=(0, 0, -1), cone=20, every=False, orientation=None, rpy=None)
    """

    approach: Any = None
    cone: Any = None
    every: bool = False
    orientation: Any = None
    rpy: Any = None


@dataclass(frozen=True, eq=False)
class ReachResult:
    """What :func:`reach` proved: the :class:`~workspace_sym.interval.boxes.Paving` of the task space, the method
    that proved it (``"critical"``, ``"pairs"``, ``"section"``), a bracket of the workspace's measure proved
    another way when the plan has one (``volume_bounds``: a section turned by the first joint, by Pappus's
    theorem), and the tool constraint (``constraint``, with a pose).

    The paving's figures are read through it (``inner``, ``counts``, ``complete``, ...); :attr:`measure_bounds`
    is the intersection of the boxes' bracket and ``volume_bounds`` (both hold the measure).

    Parameters
    ----------
    paving : Paving
        The paving of the task space.
    method : str
        ``"critical"``, ``"pairs"`` or ``"section"``.
    volume_bounds : tuple, optional
        ``(lo, hi)``, the measure proved another way.
    constraint : PoseConstraint, optional
        The tool constraint, with a pose.
    """

    paving: Paving
    method: str
    volume_bounds: tuple | None = None
    constraint: PoseConstraint | None = None

    # the paving's figures ------------------------------------------------------------------------------------
    @property
    def inner(self) -> np.ndarray:
        """The inner boxes: every point is proved reachable.

        Returns
        -------
        numpy.ndarray
            ``(N, m, 2)`` boxes.
        """
        return self.paving.inner

    @property
    def boundary(self) -> np.ndarray:
        """The boundary boxes: undecided, each of size at most ``delta``.

        Returns
        -------
        numpy.ndarray
            ``(N, m, 2)`` boxes.
        """
        return self.paving.boundary

    @property
    def outer(self) -> np.ndarray:
        """The outer boxes: no point is reachable.

        Returns
        -------
        numpy.ndarray
            ``(N, m, 2)`` boxes.
        """
        return self.paving.outer

    @property
    def pending(self) -> np.ndarray:
        """The boxes a stopped run did not decide.

        Returns
        -------
        numpy.ndarray
            ``(N, m, 2)`` boxes.
        """
        return self.paving.pending

    @property
    def counts(self) -> dict:
        """The number of boxes of each kind.

        Returns
        -------
        dict
            ``inner``, ``boundary``, ``outer``, ``pending``.
        """
        return self.paving.counts

    @property
    def measures(self) -> dict:
        """The measure (area or volume) of the boxes of each kind.

        Returns
        -------
        dict
            ``inner``, ``boundary``, ``outer``, ``pending``.
        """
        return self.paving.measures

    @property
    def box(self) -> Box:
        """The root task box.

        Returns
        -------
        Box
            The box paved.
        """
        return self.paving.box

    @property
    def variables(self) -> tuple:
        """The task coordinates.

        Returns
        -------
        tuple
            Their SymPy symbols (``x, y`` or ``x, y, z``).
        """
        return self.paving.variables

    @property
    def delta(self) -> float:
        """The run's ``delta``.

        Returns
        -------
        float
            The largest size of a boundary box.
        """
        return self.paving.delta

    @property
    def size(self) -> str:
        """How a box's size is measured.

        Returns
        -------
        str
            ``"diameter"`` or ``"width"``.
        """
        return self.paving.size

    @property
    def seconds(self) -> float:
        """The run's duration.

        Returns
        -------
        float
            Seconds.
        """
        return self.paving.seconds

    @property
    def complete(self) -> bool:
        """Whether every box was decided.

        Returns
        -------
        bool
            False when a budget or Ctrl-C stopped the run.
        """
        return self.paving.complete

    @property
    def evaluated(self) -> int:
        """The boxes evaluated.

        Returns
        -------
        int
            Summed over the plan's steps.
        """
        return self.paving.evaluated

    @property
    def stop_reason(self) -> str:
        """Why the run stopped early.

        Returns
        -------
        str
            ``""`` when it did not.
        """
        return self.paving.stop_reason

    @property
    def units(self) -> str | None:
        """The robot's length units.

        Returns
        -------
        str or None
            As the robot gives them.
        """
        return self.paving.units

    @property
    def backend(self) -> str:
        """The interval engine.

        Returns
        -------
        str
            ``"numpy"``.
        """
        return self.paving.backend

    @property
    def contract(self) -> bool:
        """Whether the boxes were contracted (``pave(contract=True)``).

        Returns
        -------
        bool
            False for ``reach``.
        """
        return self.paving.contract

    @property
    def exact_measure(self):
        """The exact measure of the workspace, when one was attached.

        Returns
        -------
        object
            None unless attached.
        """
        return self.paving.exact_measure

    @property
    def tool_constraint(self) -> PoseConstraint | None:
        """The tool constraint (the name of earlier releases; :attr:`constraint`).

        Returns
        -------
        PoseConstraint or None
            :attr:`constraint`.
        """
        return self.constraint

    # the brackets -------------------------------------------------------------------------------------------
    @property
    def box_measure_bounds(self) -> tuple[float, float]:
        """The certified bracket of the boxes alone (the paving's).

        Returns
        -------
        tuple of float
            ``(lo, hi)``.
        """
        return self.paving.measure_bounds

    @cached_property
    def measure_bounds(self) -> tuple[float, float]:
        """The certified bracket of the workspace's measure: the boxes' bracket, intersected with
        :attr:`volume_bounds` when the plan proved one.

        Returns
        -------
        tuple of float
            ``(lo, hi)``.
        """
        lo, hi = self.paving.measure_bounds
        if self.volume_bounds is not None:
            lo, hi = max(lo, self.volume_bounds[0]), min(hi, self.volume_bounds[1])
        return lo, hi

    def to_dict(self) -> dict:
        """The JSON answer (docs/cli.md): the paving's, with the method, the brackets and the constraint.

        Returns
        -------
        dict
            The paving's keys, with ``measure_bounds`` (this result's bracket) and ``method``; with
            ``volume_bounds``, also ``box_measure_bounds`` and ``volume_bounds``; with a constraint,
            ``constraint`` and ``constraint_words``.
        """
        out = self.paving.to_dict()
        out["measure_bounds"] = list(self.measure_bounds)
        out["method"] = self.method
        if self.volume_bounds is not None:
            out["box_measure_bounds"] = list(self.box_measure_bounds)
            out["volume_bounds"] = list(self.volume_bounds)
        if self.constraint is not None:
            out["constraint"] = self.constraint.to_dict()
            out["constraint_words"] = self.constraint.words()
        return out

    def __repr__(self) -> str:
        lo, hi = self.measure_bounds
        c = self.counts
        return (f"ReachResult({c['inner']} inner, {c['boundary']} boundary, {c['outer']} outer, "
                f"{c['pending']} pending; measure in {fmt_bracket(lo, hi, 6, 'g')}, delta={self.delta}, "
                f"method {self.method})")


@contextmanager
def prepared_within(robot: DHRobot, budget: RunBudget):
    """The symbolic preparation of the reach model (kinematics, enclosures) within what is left of the run's time
    limit: past it, one :class:`SymbolicBudgetError` naming ``time_limit`` (no task box is known yet, so there
    is no paving to return: nothing was decided).

    The limit is checked twice: by the symbolic steps themselves while they run (their budget, with its timer),
    and once more when the block ends, so that a preparation found in a cache (no symbolic step run, nothing to
    interrupt) and finished after the limit is refused the same way whatever the machine's speed."""
    time_limit = budget.time_limit
    if time_limit is None:
        yield
        return
    try:
        with symbolic_budget(max(time_limit - budget.seconds, 0.0), f"the symbolic model of {robot.name}"):
            yield
        if budget.seconds > time_limit:
            raise SymbolicBudgetError(f"the symbolic model of {robot.name}: finished after the limit")
    except SymbolicBudgetError as exc:
        raise SymbolicBudgetError(f"time_limit: the symbolic model of {robot.name} (position, Jacobian, "
                                  f"enclosures) was not ready within the time limit of {time_limit:g} s, so no "
                                  "box was decided; allow more time", parameter="time_limit") from exc


def resolve_method(robot: DHRobot, method: str = "auto", parameters=()) -> str:
    """The method :func:`reach` uses for ``robot``: ``"critical"`` or ``"pairs"``.

    ``"auto"`` is ``"critical"`` for every robot whose position moves in two or three coordinates: planar
    arms, products and sections turned by a revolute first joint first, the critical method in space for any
    other map into ``R^3`` and for a turned section that proves no inner box moved by at most
    ``Tuning.cells_max_joints`` joints (:func:`~workspace_sym.serial.plans.on_cells` tells which); ``"pairs"`` for
    a position moving along one coordinate only.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    method : {"auto", "critical", "pairs"}
        The method asked for.
    parameters : dict or iterable of pairs
        Values of the robot's symbolic parameters (empty: its own).

    Returns
    -------
    str
        ``"critical"`` or ``"pairs"``.

    Raises
    ------
    InvalidParameterError
        ``method`` not one of :data:`METHODS`, ``"critical"`` for a position moving in one coordinate, or a
        robot the reach model refuses (:class:`~workspace_sym.serial.model.ReachModel`).
    JointLimitError
        A joint without a usable range.
    """
    if method not in METHODS:
        raise InvalidParameterError(f"method must be one of {', '.join(map(repr, METHODS))}; got {method!r}",
                                    parameter="method")
    parameters = tuple(parameters.items()) if isinstance(parameters, dict) else tuple(parameters)
    parameters = tuple(sorted(parameters, key=lambda item: str(item[0])))
    m = reach_model(robot, parameters).m
    fits = m in (2, 3)
    if method == "critical" and not fits:
        raise InvalidParameterError(f"method 'critical' needs a position moving in two or three coordinates (a "
                                    f"map into the plane or into space, whose critical set it covers); the "
                                    f"position of {robot.name} moves in {m}: use method='pairs'",
                                    parameter="method")
    return method if method != "auto" else ("critical" if fits else "pairs")


# keyword of earlier releases -> (option object, field)
_LEGACY = {"max_boxes": ("stop", "max_boxes"), "time_limit": ("stop", "time_limit"), "progress": ("run", "progress"),
           "section_boxes": ("stop", "section_boxes"), "executor": ("run", "executor"), "chunk": ("run", "chunk"),
           "max_memory": ("run", "max_memory"), "store": ("run", "store"), "resume": ("run", "resume"),
           "approach": ("pose", "approach"), "cone": ("pose", "cone"), "every": ("pose", "every"),
           "orientation": ("pose", "orientation"), "rpy": ("pose", "rpy"), "max_pairs": ("tuning", "max_pairs"),
           "inner_depth": ("tuning", "inner_depth")}
_OBJECTS = {"stop": "StopAt", "run": "RunOn", "pose": "Pose", "tuning": "Tuning"}


def _fold_legacy(legacy: dict, stop: StopAt, run: RunOn, pose: Pose | None, tuning: Tuning):
    """``(stop, run, pose, tuning)`` with the keywords of earlier releases folded in, each with a
    :class:`DeprecationWarning` naming its new spelling; an unknown keyword is a ``TypeError`` as Python's."""
    unknown = sorted(set(legacy) - set(_LEGACY))
    if unknown:
        raise TypeError(f"reach() got an unexpected keyword argument {unknown[0]!r}")
    options: dict[str, dict] = {"stop": {}, "run": {}, "pose": {}, "tuning": {}}
    for name, value in legacy.items():
        where, field = _LEGACY[name]
        if where == "tuning" and (pose is not None or legacy.keys() & {"approach", "orientation", "rpy"}):
            field = f"pose_{field}"             # the pairs method of a pose has its own figures
        options[where][field] = value
        warnings.warn(f"reach: {name}= is deprecated; pass {where}={_OBJECTS[where]}({field}=...)",
                      DeprecationWarning, stacklevel=3)
    if options["stop"]:
        stop = dataclasses.replace(stop, **options["stop"])
    if options["run"]:
        run = dataclasses.replace(run, **options["run"])
    if options["pose"]:
        pose = dataclasses.replace(pose or Pose(), **options["pose"])
    if options["tuning"]:
        tuning = tuning.replace(**options["tuning"])
    return stop, run, pose, tuning


@arith.nearest_rounding
def reach(robot: DHRobot, *, delta: float, size: str = "diameter", parameters: dict | None = None,
          method: str = "auto", stop: StopAt = StopAt(), run: RunOn = RunOn(), pose: Pose | None = None,
          tuning: Tuning = DEFAULT, **legacy) -> ReachResult:
    """Pave the position workspace of a serial robot within its joint limits (module docstring).

    Parameters
    ----------
    robot : DHRobot
        A serial robot (a DH table, read from a file, a URDF or an MJCF model, or the catalog).
    delta : float
        Undecided task boxes whose size is at most ``delta`` become boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured: its diagonal, or its longest edge.
    parameters : dict, optional
        Values of the symbolic lengths (default: the robot's own).
    method : {"auto", "critical", "pairs"}
        ``"auto"`` (the only choice with a ``pose``, which picks its own method): ``"critical"`` for every robot
        whose position moves in two or three coordinates, with the structure it has first: a planar robot, a
        spatial robot whose coordinates are moved by disjoint sets of joints, a spatial robot turned by a
        revolute first joint (a rigid base transform allowed), and otherwise the critical set of the whole map
        into space on a 3-D grid of cells (falling back to ``"pairs"`` when its cover is too large);
        ``"pairs"`` for a position moving along one coordinate.  A first joint limited to less than a period
        whose section in cylindrical coordinates proves no inner box (a section moved by two joints, or a turn
        below half a circle) gives way to the 3-D cells when at most ``tuning.cells_max_joints`` (3) joints move
        the position, under ``"auto"`` and ``"critical"`` alike; with ``max_memory``, ``store`` or ``resume``,
        or a 3-D cover too large, such an arm keeps the section path (outer boxes only).
    stop : :class:`~workspace_sym.interval.driver.StopAt`
        When to stop: ``max_boxes`` boxes evaluated, ``time_limit`` seconds for the whole call (what is left
        undecided is returned as ``pending``; a symbolic model, or with a pose its wrist reduction and plan, not
        ready within ``time_limit`` raises :class:`~workspace_sym.errors.SymbolicBudgetError`), and
        ``section_boxes``, a budget of boxes for the section of an arm turned by its first joint and moved by
        three joints or more (the same cells on every machine where a time limit is not: its stages stop where
        they stop at their shares of a time limit).
    run : :class:`~workspace_sym.interval.driver.RunOn`
        Where and how: ``executor`` (None: this process; a :class:`concurrent.futures.Executor` or a
        ``dask.distributed.Client``): the critical covers (one task per group of faces) or the generations of
        task boxes (``"pairs"``) run there, with the same boxes; ``chunk``: about this many (joint box, task box)
        pairs in one chunk of the pairs method (default ``CHUNK_PAIRS``); ``max_memory``, ``store`` and
        ``resume``: decided boxes streamed to disk (the paving a
        :class:`~workspace_sym.interval.boxes.StoredPaving`) and a checkpoint to go on from, for the spatial arms
        of the critical method with a structure (the section kept beside the checkpoint), the pairs method, and
        a pose's section method; the critical method on one grid of cells and a pose's pairs method keep their
        boxes in memory and refuse them (under ``"auto"`` a spatial arm without structure is then paved by
        ``"pairs"``).  Every stored or resumed file names its whole problem: one of another problem is refused.
        ``progress``: a progress bar (None: on an interactive output once the run has lasted a second).
    pose : :class:`Pose`, optional
        A constraint on the tool frame (:mod:`workspace_sym.serial.pose`): inner boxes are then proved reached by
        configurations within the limits satisfying the constraint exactly, outer boxes by none
        (docs/methods.md section 8); a ``method`` other than ``"auto"``, ``stop.section_boxes``, and
        ``run.executor`` / ``run.chunk`` are refused.
    tuning : :class:`~workspace_sym.serial.tuning.Tuning`
        How much work each stage may do (samples, pairs, depths, shares of a time limit); part of every
        checkpoint's fingerprint.
    **legacy
        The keywords of earlier releases (``time_limit``, ``max_boxes``, ``progress``, ``executor``, ``chunk``,
        ``max_memory``, ``store``, ``resume``, ``approach``, ``cone``, ``every``, ``orientation``, ``rpy``,
        ``max_pairs``, ``inner_depth``), still taken with a :class:`DeprecationWarning` naming the new spelling.

    Returns
    -------
    ReachResult
        Over ``x, y`` (planar robot) or ``x, y, z``: its ``inner`` boxes are proved reachable, its ``outer``
        boxes proved unreachable (with the constraint, when given).

    Raises
    ------
    InvalidParameterError
        A bad ``delta``, ``size``, ``method``, option or combination of options, a robot whose position has no
        finite enclosure, a checkpoint of another problem.
    JointLimitError
        A prismatic joint without limits, or an unlimited revolute joint the position is not periodic in.
    SymbolicBudgetError
        The symbolic model not ready within ``stop.time_limit`` (without a pose).

    Examples
    --------
    >>> from workspace_sym.kinematics import DHJoint
    >>> arm = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a="1/2")])
    >>> p = reach(arm, delta=0.1)
    >>> lo, hi = p.measure_bounds           # the annulus 1/2 <= r <= 3/2: area 2 pi
    >>> bool(lo <= 2 * np.pi <= hi), p.method
    (True, 'critical')
    """
    if legacy:
        stop, run, pose, tuning = _fold_legacy(legacy, stop, run, pose, tuning)
    if not isinstance(tuning, Tuning):
        raise InvalidParameterError(f"tuning must be a serial.Tuning; got {type(tuning).__name__}",
                                    parameter="tuning")
    if pose is not None:
        return _reach_pose(robot, delta=delta, size=size, parameters=parameters, method=method, stop=stop, run=run,
                           pose=pose, tuning=tuning)
    check_delta(delta)
    if size not in ("diameter", "width"):
        raise InvalidParameterError(f"size must be one of 'diameter', 'width'; got {size!r}", parameter="size")
    values = parameter_values(parameters)
    # The time limit bounds the whole call: the clock starts before the symbolic preparation of the model.
    budget = RunBudget(stop, "reach", run.progress)
    model = root = None
    try:
        with prepared_within(robot, budget):
            model = reach_model(robot, values)
            root = model.enclose(model.limits[None])[0]
        check_root(root, delta, size, robot)
        problem = reach_problem(robot, values, delta, size, tuning)
        with prepared_within(robot, budget):
            kind = resolve_method(robot, method, values)
            plans = choose_plans(robot, values, kind, method, delta=delta, size=size, tuning=tuning,
                                 problem=problem, run=run)
        too_large: CoverTooLarge | None = None
        for plan in plans:
            try:
                section = plan.pave(budget, run)
            except CoverTooLarge as error:
                too_large = error
                continue
            paving = plan.classify(section, budget, run)
            return ReachResult(paving, plan.method, plan.volume(section))
        raise InvalidParameterError(f"method 'critical': {too_large} (joints with parallel axes?); use "
                                    "method='pairs'", parameter="method")
    except KeyboardInterrupt:
        if model is None or root is None:
            raise
        whole = Box(model.task_variables, tuple(root[:, 0]), tuple(root[:, 1]))
        empty = np.empty((0, len(model.task_variables), 2))
        return ReachResult(Paving(variables=model.task_variables, box=whole, constraints=(), delta=float(delta),
                                  backend="numpy", size=size, inner=empty, boundary=empty, outer=empty,
                                  pending=root[None], seconds=budget.seconds, complete=False, evaluated=0,
                                  stop_reason="interrupted", units=robot.units), method)
    finally:
        budget.close()


def _reach_pose(robot: DHRobot, *, delta, size, parameters, method, stop: StopAt, run: RunOn, pose: Pose,
                tuning: Tuning) -> ReachResult:
    """:func:`reach` with a constraint on the tool frame: the pose plans (:func:`~.plans.pose_plan`)."""
    if not isinstance(pose, Pose):
        raise InvalidParameterError(f"pose must be a serial.Pose; got {type(pose).__name__}", parameter="pose")
    if method != "auto":
        raise InvalidParameterError(f"method: reach with a tool constraint chooses its own method (the section "
                                    f"where the first joint turns it, pairs otherwise); got {method!r}, expected "
                                    "'auto'", parameter="method")
    if stop.section_boxes is not None:
        raise InvalidParameterError(f"section_boxes: reach with a tool constraint paves its own section (no budget "
                                    f"of boxes for it); got {stop.section_boxes!r}, expected None",
                                    parameter="section_boxes")
    constraint = constraint_from(pose.approach, pose.cone, pose.every, pose.orientation, pose.rpy)
    check_delta(delta)
    if size not in ("diameter", "width"):
        raise InvalidParameterError(f"size must be one of 'diameter', 'width'; got {size!r}", parameter="size")
    if run.executor is not None or run.chunk is not None:
        given = ", ".join(f"{name}={getattr(run, name)!r}" for name in ("executor", "chunk")
                          if getattr(run, name) is not None)
        raise InvalidParameterError(f"run: reach with a tool constraint decides its boxes in this process; executor "
                                    f"and chunk do not apply; got {given}; they apply to reach without a pose",
                                    parameter="run")
    values = parameter_values(parameters)
    budget = RunBudget(stop, "reach", run.progress)
    try:
        with prepared_within(robot, budget):
            structure = pose_structure(robot, values, constraint, tuning)
            plan = pose_plan(robot, values, constraint, structure, delta=delta, size=size, tuning=tuning, run=run)
        section = plan.pave(budget, run)
        paving = plan.classify(section, budget, run)
        return ReachResult(paving, plan.method, plan.volume(section), constraint)
    finally:
        budget.close()
