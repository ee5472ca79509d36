"""The plans of a reach run: one object per method, each with the same three steps.

1. :meth:`Plan.pave` paves what the method decides first: the cells of the task space (the critical method on one
   grid), the section a turned arm reduces to, the constrained section of a pose, or nothing (the pairs
   methods start from the root task box);
2. :meth:`Plan.classify` decides the task boxes from it: read off the cells, classified from the section by the
   paving driver (:func:`~workspace_sym.serial.classify.classify_task_boxes`, with its store and checkpoints), or
   by the pairs loop (:func:`~workspace_sym.serial.pairs.pave_pairs`);
3. :meth:`Plan.volume` proves the workspace's volume another way when it can (a turned section by Pappus's
   theorem), or gives None.

:func:`choose_plans` picks the plans for a robot and a method, the first one to try followed by those that take
over when its cover is too large (:class:`~workspace_sym.errors.CoverTooLarge`); :func:`pose_plan` the plan of a
run with a tool constraint.  Every plan reads its figures from a :class:`~workspace_sym.serial.tuning.Tuning`.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..interval import arith
from ..interval.boxes import Box, Paving, StoredPaving
from ..interval.driver import RunBudget, RunOn, paving_of, read_checkpoint, refuse_storage, store_for, write_checkpoint
from ..interval.executor import runner_for
from ..interval.fingerprint import Fingerprint
from ..interval.image import CellGrid, critical_paving
from ..interval.store import BoxStore
from ..interval.verdict import INSIDE, OUTSIDE, UNDECIDED
from ..kinematics import DHRobot
from .cells import cover_with
from .classify import ProductTest, RevolvedTest, classify_task_boxes, section_digest
from .model import TASK, cell_width, check_root, reach_model
from .pairs import CHUNK_PAIRS, PositionStep, pave_pairs
from .pose import (
    PoseConstraint,
    PoseStep,
    PoseStructure,
    SquaredTest,
    section_classes,
    section_volume_bracket,
    squared_volume_bracket,
)
from .ring import ring_outer_cells
from .section import Turned, TurnedTest, section_bar, section_paving, turned_volume
from .stored import reach_problem, save_section, saved_section
from .structure import Product, Revolved, structure_of
from .tuning import DEFAULT, Tuning
from .turn import (
    DIRECTIONS,
    SPIN_TURNS,
    LimitedTurnTest,
    ToolSectionTest,
    budgeted_width,
    direction_maps,
    limited_turn,
    limited_volume,
    pave_limited,
    roots_volume,
    shifted_section,
    spin_volume,
    tool_section,
)

__all__ = ["Section", "Plan", "CellsPlan", "SectionPlan", "PairsPlan", "PoseSectionPlan", "PosePairsPlan",
           "SectionShare", "choose_plans", "pose_plan", "on_cells", "POSE_CHUNK_PAIRS"]

POSE_CHUNK_PAIRS = 200_000       # pairs in one chunk of the pose methods' pairs loop (RunOn.chunk is refused there)


@dataclass
class Section:
    """What a plan's first step paved: the grid of cells and their classes (None for the pairs methods), the
    boxes it evaluated, why it stopped (``""``: it did not), and what the next steps need (``test``: the task-box
    test; ``volume``: a bracket proved from the cells; ``box``: the root task box).

    Parameters
    ----------
    box : Box
        The root task box.
    grid : CellGrid, optional
        The grid of the cells paved (of the task space, or of the section).
    classes : numpy.ndarray, optional
        The verdict code of each cell of ``grid``.
    evaluated : int
        Boxes evaluated.
    reason : str
        Why a budget stopped the step (``""``: it did not).
    test : callable, optional
        ``test(X) -> (is_in, is_out)`` classifying task boxes from the cells.
    volume : tuple, optional
        ``(lo, hi)`` bracket of the workspace's measure proved from the cells.
    digest : str
        What a checkpoint names of the cells (:func:`~workspace_sym.serial.classify.section_digest`).
    """

    box: Box
    grid: CellGrid | None = None
    classes: np.ndarray | None = None
    evaluated: int = 0
    reason: str = ""
    test: Any = None
    volume: tuple | None = None
    digest: str = "none"


class Plan:
    """A way of paving a robot's workspace (module docstring): ``method`` names it in the result.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    values : tuple
        Its parameter values as ``(name, value)`` pairs.
    delta : float
        Undecided task boxes of size at most ``delta`` are boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured.
    tuning : Tuning
        The figures of every stage.
    problem : dict
        The run's whole problem (:func:`~workspace_sym.serial.stored.reach_problem`), named by its checkpoints.
    """

    method = ""

    def __init__(self, robot: DHRobot, values: tuple, delta: float, size: str, tuning: Tuning, problem: dict):
        self.robot, self.values, self.delta, self.size, self.tuning = robot, values, float(delta), size, tuning
        self.problem = problem

    def pave(self, budget: RunBudget, run: RunOn) -> Section:
        """Step 1: pave what the method decides first.

        Parameters
        ----------
        budget : RunBudget
            The run's budget (clock, box budget, bar).
        run : RunOn
            Where and how the run goes.

        Returns
        -------
        Section
            What was paved.
        """
        raise NotImplementedError

    def classify(self, section: Section, budget: RunBudget, run: RunOn) -> Paving:
        """Step 2: decide the task boxes from what :meth:`pave` paved.

        Parameters
        ----------
        section : Section
            What :meth:`pave` returned.
        budget : RunBudget
            The run's budget (clock, box budget, bar).
        run : RunOn
            Where and how the run goes (store, checkpoint).

        Returns
        -------
        Paving
            The paving of the task space.
        """
        raise NotImplementedError

    def volume(self, section: Section) -> tuple | None:
        """Step 3: the workspace's measure proved another way.

        Parameters
        ----------
        section : Section
            What :meth:`pave` returned.

        Returns
        -------
        tuple or None
            ``section.volume``: a ``(lo, hi)`` bracket, or None.
        """
        return section.volume

    # helpers shared by the plans ------------------------------------------------------------------------
    def paving(self, box: Box, inner, boundary, outer, pending, budget: RunBudget, evaluated: int, reason: str,
               units: str) -> Paving:
        """A paving of the boxes of a step that did not go through the driver (all in memory).

        Parameters
        ----------
        box : Box
            The root task box.
        inner, boundary, outer : list of numpy.ndarray
            The boxes of each kind, in parts (``(N, m, 2)`` arrays, concatenated).
        pending : numpy.ndarray or None
            The boxes left undecided when a budget stopped the step.
        budget : RunBudget
            The run's budget, whose clock gives the seconds.
        evaluated : int
            Boxes evaluated.
        reason : str
            Why a budget stopped the step; dropped when nothing is pending.
        units : str
            The robot's length units.

        Returns
        -------
        Paving
            Complete unless boxes are pending.
        """
        m = len(box.variables)
        empty = np.empty((0, m, 2))

        def stack(parts):
            parts = [p for p in parts if len(p)]
            return np.concatenate(parts) if parts else empty

        if pending is None or not len(pending):
            reason = ""                         # a budget that ran out after the last box: nothing is pending
        return Paving(variables=box.variables, box=box, constraints=(), delta=self.delta, backend="numpy",
                      size=self.size, inner=stack(inner), boundary=stack(boundary), outer=stack(outer),
                      pending=empty if pending is None else pending, seconds=budget.seconds, complete=not reason,
                      evaluated=evaluated, stop_reason=reason, units=units)


def _root_box(model) -> tuple[np.ndarray, Box]:
    root = model.enclose(model.limits[None])[0]
    return root, Box(model.task_variables, tuple(root[:, 0]), tuple(root[:, 1]))


class CellsPlan(Plan):
    """The critical method on one grid of task cells (:mod:`workspace_sym.serial.cells`): a planar arm, or a spatial
    one without a structure; its grid is decided in one pass, in memory (no store, no checkpoint).

    Parameters
    ----------
    *args
        Those of :class:`Plan`.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Where the critical cover runs (:func:`~workspace_sym.serial.cells.cover_with`); None: here.
    """

    method = "critical"

    def __init__(self, *args, executor=None):
        super().__init__(*args)
        self.executor = executor

    def pave(self, budget, run):
        """The cells of the task space (:func:`~workspace_sym.interval.image.critical_paving`).

        Parameters
        ----------
        budget : RunBudget
            The run's budget (clock, box budget, bar).
        run : RunOn
            Not read (the executor was given to the plan).

        Returns
        -------
        Section
            The grid's extent as the root box, the grid, its classes, the boxes evaluated and why it stopped.

        Raises
        ------
        CoverTooLarge
            The critical cover needs too many boxes (the next plan takes over).
        """
        model = reach_model(self.robot, self.values)
        grid, classes, evaluated, reason = critical_paving(
            model, cell_width(self.delta, self.size, model.m), budget=budget.stop_reason,
            cover=cover_with(self.executor, self.robot, self.values, "model"), show=budget.show,
            chunk=None if model.m == 2 else self.tuning.cell_chunk)
        extent = grid.extent
        box = Box(model.task_variables, tuple(extent[:, 0]), tuple(extent[:, 1]))
        return Section(box, grid, classes, evaluated, reason)

    def classify(self, section, budget, run):
        """The task boxes read off the cells: inner and outer cells, the undecided ones boundary boxes (or
        pending, runs of cells merged, when a budget stopped the cells).

        Parameters
        ----------
        section : Section
            What :meth:`pave` returned.
        budget : RunBudget
            The run's budget, whose clock gives the seconds.
        run : RunOn
            Not read (the boxes stay in memory).

        Returns
        -------
        Paving
            The cells as boxes.
        """
        grid, classes, reason = section.grid, section.classes, section.reason
        assert grid is not None and classes is not None
        undecided = grid.boxes(classes, UNDECIDED, merge=bool(reason))
        return self.paving(section.box, [grid.boxes(classes, INSIDE)], [] if reason else [undecided],
                           [grid.boxes(classes, OUTSIDE)], undecided if reason else None, budget, section.evaluated,
                           reason, self.robot.units)


class SectionPlan(Plan):
    """A spatial arm whose workspace is a product of images or a section turned by its first joint
    (:mod:`workspace_sym.serial.structure`): the section paved (critical cover, stages of
    :func:`~workspace_sym.serial.section.section_paving`, or the directions of a limited turn), then the task
    boxes classified from it by the driver, where ``run`` says (store, checkpoint: the section kept beside it).

    Parameters
    ----------
    *args
        Those of :class:`Plan`.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Where the critical cover of the section runs (:func:`~workspace_sym.serial.cells.cover_with`); None:
        here.
    """

    method = "critical"

    def __init__(self, *args, executor=None):
        super().__init__(*args)
        self.executor = executor
        self.model = reach_model(self.robot, self.values)
        self.structure = structure_of(self.robot, self.values)
        self.limited = limited_turn(self.structure, self.model)

    def pave(self, budget, run):
        """The section: taken from beside the checkpoint when ``run.resume`` has one, else paved (the directions
        of a limited turn, the stages of :func:`~workspace_sym.serial.section.section_paving` for a turned
        section moved by three joints or more, the critical cover otherwise) and kept beside the checkpoint
        when it was not stopped.  The plan's ``problem`` gains the method and ``budget.section_boxes``.

        Parameters
        ----------
        budget : RunBudget
            The run's budget (clock, box budget, ``section_boxes``, bar).
        run : RunOn
            ``resume``: the checkpoint beside which the section is kept.

        Returns
        -------
        Section
            The section's grid and classes, the test of the task boxes (None when the section was stopped, but
            for a limited turn's), the volume bracket (a :class:`~workspace_sym.serial.section.Turned` section
            turned fully, or a limited turn proved at its directions; else None) and the digest of the cells.

        Raises
        ------
        InvalidParameterError
            The section kept beside the checkpoint cannot be read or names another problem.
        CoverTooLarge
            The critical cover of the section needs too many boxes.
        """
        model, plan, tuning = self.model, self.structure, self.tuning
        _, box = _root_box(model)
        width = tuning.section_ratio * cell_width(self.delta, self.size, 3)
        if self.limited is not None and (budget.time_limit is not None or budget.section_boxes is not None):
            width = budgeted_width(self.limited, tuning)    # the same section whatever delta (reach.turn)
        grid, classes, evaluated, reason = None, None, 0, ""
        volume, pieces, proved = None, None, None
        self.problem = {**self.problem, "method": f"critical ({type(plan).__name__})",
                        "section_boxes": budget.section_boxes}
        # A resumed run takes the section its checkpoint was classified from (a time limit may refine it
        # differently).
        named = Fingerprint({**self.problem, "section cell": width, "joint limits": model.limits})
        saved = saved_section(run, named)
        if saved is not None:
            grid, classes, proved, pieces, evaluated = saved
        elif self.limited is not None:
            # A limited first joint of half a turn or more: cells proved at every polar angle (reach.turn).
            with section_bar(budget.showing) as show:
                grid, classes, proved, evaluated, reason = pave_limited(self.limited, width, budget, show=show,
                                                                        boxes=budget.section_boxes, tuning=tuning)
        elif isinstance(plan, Turned) and plan.section.k > 2:
            grid, classes, evaluated, reason, pieces = self._timed_section(plan, box, width, budget)
        elif plan is not None and plan.section is not None:
            with section_bar(budget.showing) as show:   # the section's bar, from the first generation of its cover
                grid, classes, evaluated, reason = critical_paving(
                    plan.section, width, budget=budget.stop_reason, show=show,
                    cover=cover_with(self.executor, self.robot, self.values, "section"))
        test: Any = None
        if self.limited is not None:
            volume = limited_volume(self.limited, grid, classes, proved, tuning)
            test = LimitedTurnTest(self.limited, grid, classes, proved)
        if not reason and saved is None:
            save_section(run, named, grid, classes, proved, pieces, evaluated)
        if isinstance(plan, Turned) and plan.full:
            volume = turned_volume(grid, classes, pieces)      # the solid of revolution of the section (Pappus)
        budget.show(0.0, evaluated)
        if not reason:
            tests = {Product: ProductTest, Revolved: RevolvedTest, Turned: TurnedTest}
            test = test or tests[type(plan)](plan, grid, classes)
        return Section(box, grid, classes, evaluated, reason, test, volume,
                       section_digest(grid, classes, None if self.limited is None else proved))

    def _timed_section(self, plan, box, width, budget):
        """A section moved by three joints or more: the stages of ``section_paving``.  It refines while its next
        step would end before the time limit less the time the (x, y, z) boxes take, measured once on the first
        proved cells (a rehearsal: more cells decided, fewer boxes)."""
        tuning = self.tuning
        reserve = [0.0]

        def rehearse(grid, classes):
            start = time.perf_counter()
            classify_task_boxes(TurnedTest(plan, grid, classes), box, self.delta, self.size)
            reserve[0] = tuning.section_reserve * (time.perf_counter() - start)

        def seconds_left():
            return budget.time_limit - budget.seconds - reserve[0]

        def section_budget(count, ahead=0.0):
            late = budget.time_limit is not None and \
                budget.seconds + tuning.section_reserve * ahead + reserve[0] > budget.time_limit
            spent = budget.section_boxes is not None and count >= budget.section_boxes
            return budget.stop_reason(count) or ("section share" if late or spent else "")

        timed = budget.time_limit is not None
        with section_bar(budget.showing) as show:
            grid, classes, evaluated, reason, pieces = section_paving(
                plan.section, width, budget=section_budget, show=show, tuning=tuning,
                rehearse=rehearse if timed else None, depth=tuning.section_depth if timed else 1,
                seconds_left=seconds_left if timed else None)
        return grid, classes, evaluated, ("" if reason == "section share" else reason), pieces

    def classify(self, section, budget, run):
        """The task boxes classified from the section by the driver, under what is left of the budget, with the
        store and checkpoint ``run`` asks for (the checkpoint names the section's cells); every task box pending
        when the section was stopped.

        Parameters
        ----------
        section : Section
            What :meth:`pave` returned.
        budget : RunBudget
            The run's budget; the boxes of the section count against it.
        run : RunOn
            ``max_memory``, ``store``, ``resume``, ``progress``.

        Returns
        -------
        Paving
            Its ``evaluated`` counts the section's boxes too.

        Raises
        ------
        InvalidParameterError
            ``run.resume`` names a checkpoint of another problem, or ``run.store`` holds another run's boxes.
        """
        if section.reason:                  # stopped while the section was paved: every task box pending
            root, box = _root_box(self.model)
            return self.paving(box, [], [], [], root[None].copy(), budget, section.evaluated, section.reason,
                               self.robot.units)
        # A checkpoint of the classification belongs to this problem and section (a time-limited turned section
        # may refine differently on another run: its cells are part of what the checkpoint names).
        what = {**self.problem, "section cells": section.digest}
        budget.spent = section.evaluated
        paving = classify_task_boxes(section.test, section.box, self.delta, self.size, budget,
                                     RunOn(max_memory=run.max_memory, store=run.store, resume=run.resume,
                                           progress=run.progress),
                                     describe=what)
        return _with(paving, evaluated=budget.spent + paving.evaluated, units=self.robot.units)


class PairsPlan(Plan):
    """The pairs method (:mod:`workspace_sym.serial.pairs`) on the position: its decided boxes in a store (memory
    or disk) and, with ``run.resume``, a checkpoint of the task boxes left with their joint boxes.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    values : tuple
        Its parameter values as ``(name, value)`` pairs.
    delta : float
        Undecided task boxes of size at most ``delta`` are boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured.
    tuning : Tuning
        ``max_pairs``, ``inner_depth``, ``min_pairs``.
    problem : dict
        The run's whole problem, named by its checkpoint.
    """

    method = "pairs"

    def pave(self, budget, run):
        """Nothing to pave: the root task box, the enclosure of the position over the limits.

        Parameters
        ----------
        budget : RunBudget
            Not read.
        run : RunOn
            Not read.

        Returns
        -------
        Section
            The root box alone.
        """
        model = reach_model(self.robot, self.values)
        _, box = _root_box(model)
        return Section(box)

    def classify(self, section, budget, run):
        """The pairs loop (:func:`~workspace_sym.serial.pairs.pave_pairs`) from the root, or from the checkpoint
        ``run.resume`` when it exists; the checkpoint is written at the end when ``run.resume`` is given.

        Parameters
        ----------
        section : Section
            What :meth:`pave` returned.
        budget : RunBudget
            The run's budget (clock, box budget, bar).
        run : RunOn
            ``executor``, ``chunk``, ``max_memory``, ``store``, ``resume``.

        Returns
        -------
        Paving
            A :class:`~workspace_sym.interval.boxes.StoredPaving` when the boxes are on disk.

        Raises
        ------
        InvalidParameterError
            ``run.resume`` names a file that is not a checkpoint of this problem, or ``run.store`` holds another
            run's boxes.
        """
        model, tuning = reach_model(self.robot, self.values), self.tuning
        box = section.box
        root = box.array
        Q = model.limits[None].copy()
        T = root[None].copy()
        owner = np.zeros(1, dtype=int)
        evaluated, seconds_before = 0, 0.0
        step = PositionStep(self.robot, self.values, self.delta, self.size, tuning.inner_depth, tuning.max_pairs,
                            tuning.min_pairs, float(np.prod(root[:, 1] - root[:, 0])))
        path = None if run.resume is None else Path(run.resume)
        fingerprint = Fingerprint({**self.problem, "method": "pairs", "lower": list(box.lower),
                                   "upper": list(box.upper), "max_pairs": tuning.max_pairs,
                                   "inner_depth": tuning.inner_depth})
        if path is not None and path.exists():
            meta, arrays = read_checkpoint(path, fingerprint)
            keeper = BoxStore.restore(len(root), meta["store"], arrays, problem=fingerprint.digest)
            T, Q, owner = arrays["pending"], arrays["joint_boxes"], arrays["owner"].astype(int)
            evaluated, seconds_before = int(meta["evaluated"]), float(meta["seconds"])
        else:
            keeper, _ = store_for(len(root), run, fingerprint.digest)
        spread = None if run.executor is None else runner_for(run.executor, step)
        try:
            T, Q, owner, done, reason = pave_pairs(step, T, Q, owner, budget=budget, keeper=keeper,
                                                   chunk=CHUNK_PAIRS if run.chunk is None else run.chunk,
                                                   spread=spread, show=budget.show if budget.showing else None)
        finally:
            if spread is not None:
                spread.close()
        evaluated += done
        if path is not None:
            write_checkpoint(path, {"fingerprint": fingerprint, "evaluated": evaluated,
                                           "seconds": seconds_before + budget.seconds}, T, keeper,
                             {"joint_boxes": Q, "owner": owner})
        keeper.flush()
        complete = not len(T)
        return paving_of(keeper, variables=model.task_variables, box=box, constraints=(), delta=self.delta,
                         backend="numpy", size=self.size, pending=T, seconds=seconds_before + budget.seconds,
                         complete=complete, evaluated=evaluated, stop_reason="" if complete else reason,
                         units=self.robot.units)


class PoseSectionPlan(Plan):
    """A cone about the vertical on an arm turned by its first joint (:mod:`workspace_sym.serial.pose`): the
    constrained section ``(u, v)`` paved by the pairs loop, the task boxes classified from it by the driver
    (store and checkpoint as for the position's section), the volume by Pappus's theorem.

    Parameters
    ----------
    *args
        Those of :class:`Plan`.
    structure : PoseStructure
        The constrained model over the section ``(u, v)`` and the position's
        :class:`~workspace_sym.serial.structure.Revolved` structure.
    """

    method = "section"

    def __init__(self, *args, structure: PoseStructure):
        super().__init__(*args)
        self.structure = structure

    def pave(self, budget, run):
        """The constrained section (:func:`~workspace_sym.serial.pose.section_classes`), its cells about
        ``tuning.section_ratio`` times as wide as the task cells (a power of two).

        Parameters
        ----------
        budget : RunBudget
            The run's budget (clock, box budget, bar).
        run : RunOn
            Not read.

        Returns
        -------
        Section
            The root task box, the section's grid and classes, their test, the volume bracket by Pappus's
            theorem (:func:`~workspace_sym.serial.pose.section_volume_bracket`) and the digest of the cells.

        Raises
        ------
        InvalidParameterError
            The position has no finite enclosure, or ``delta`` exceeds the size of the root task box.
        """
        position = reach_model(self.robot, self.values)
        root, _ = _root_box(position)
        check_root(root, self.delta, self.size, self.robot)
        box = Box(TASK, tuple(root[:, 0]), tuple(root[:, 1]))
        tuning, model = self.tuning, self.structure.model
        assert model is not None                    # a section plan has its model (pose_plan)
        width = tuning.section_ratio * cell_width(self.delta, self.size, 3)
        squared = self.structure.turned is not None         # the section (rho^2, z) of a varying offset
        saved, section_run, named = None, budget, None
        if budget.time_limit is not None:
            # Under a time limit the section is paved generation by generation (coarse cells first) toward cells
            # as fine as its enclosure over tuning.pose_timed_cells, whatever delta, until its share of the time
            # left: the Pappus bracket then depends on the time given, not on delta, and a finer delta never
            # costs it its cells (docs/methods.md section 8).  A resumed run takes the section kept beside its
            # checkpoint (the clock may refine it differently).
            # The cells along the longest side: pose_timed_cells for pose_timed_seconds left, as the square root
            # of the time below that (the grid's cells are counted, classified and summed after the paving: a
            # short limit must not pay for a grid it has no time to refine).
            left = max(budget.time_limit - budget.seconds, 0.0)
            cells = tuning.pose_timed_cells * min(1.0, (left / tuning.pose_timed_seconds) ** 0.5)
            enclosure = model.position.enclose(model.position.limits[None])[0]
            width = min(width, float(np.max(enclosure[:, 1] - enclosure[:, 0])) / max(cells, 1.0))
            end = budget.seconds + tuning.pose_section_share * left
            section_run = SectionShare(budget, end, tuning.section_reserve)
            named = Fingerprint({**self.problem, "method": self.method, "section cell": width})
            saved = saved_section(run, named)
        if saved is not None:
            grid, classes, _, _, evaluated = saved
            reason = ""
        else:
            grid, classes, evaluated, reason = section_classes(model, width, section_run, tuning=tuning,
                                                               chunk=POSE_CHUNK_PAIRS, symmetric=not squared)
            if reason == SectionShare.REASON:       # the section's share of the time is spent: not the run's
                reason = ""
            if not reason and named is not None:
                save_section(run, named, grid, classes, None, None, evaluated)
        if squared:
            test = SquaredTest(grid, classes, self.structure.turned.inverse)
            return Section(box, grid, classes, evaluated, reason, test, squared_volume_bracket(grid, classes),
                           section_digest(grid, classes))
        revolved = self.structure.revolved
        return Section(box, grid, classes, evaluated, reason, RevolvedTest(revolved, grid, classes),
                       section_volume_bracket(grid, classes, revolved), section_digest(grid, classes))

    def classify(self, section, budget, run):
        """The task boxes classified from the section by the driver, with the store and checkpoint ``run`` asks
        for; when the budget stopped the section, its cells still classify every task box (no checkpoint, the
        paving reported incomplete).

        Parameters
        ----------
        section : Section
            What :meth:`pave` returned.
        budget : RunBudget
            The run's budget; the boxes of the section count against it.
        run : RunOn
            ``max_memory``, ``store``, ``resume``, ``progress``.

        Returns
        -------
        Paving
            Its ``evaluated`` counts the section's boxes too.

        Raises
        ------
        InvalidParameterError
            ``run.resume`` names a checkpoint of another problem, or ``run.store`` holds another run's boxes.
        """
        if section.reason:
            # The budget ran out while the section was paved: its cells still classify every (x, y, z) box (its
            # undecided cells leave boundary boxes, so the bracket holds; the run is reported incomplete, with
            # the reason), and no checkpoint is written (a resumed run paves the section again and starts over).
            kept = RunOn(max_memory=run.max_memory, store=run.store, progress=False)
            paving = classify_task_boxes(section.test, section.box, self.delta, self.size, run=kept)
            return _with(paving, evaluated=section.evaluated + paving.evaluated, units=self.robot.units,
                         complete=False, stop_reason=section.reason, seconds=budget.seconds)
        # Then the task boxes go on within what is left of the budget; a checkpoint names the problem, the
        # constraint and the section's cells (a resumed run paves the section again and must find the same cells).
        what = {**self.problem, "method": self.method, "section cells": section.digest}
        budget.spent = section.evaluated
        paving = classify_task_boxes(section.test, section.box, self.delta, self.size, budget, run, describe=what)
        return _with(paving, evaluated=section.evaluated + paving.evaluated, units=self.robot.units)


CENTRE_SECONDS = 15.0      # seconds a tilt's section takes at Tuning.budget_cells on the LBR iiwa (session 24)


def timed_sections(budget, tuning: Tuning, count: int, seconds: float):
    """``(finer, tuning, ends)`` for ``count`` sections paved one after the other under a time limit: each gets an
    equal share of ``tuning.pose_section_share`` of the time left, its cells finer by the square root of that share
    over ``seconds`` (what a section takes at the default cells; at most 3x), its seeds in proportion to the cells,
    and ends at ``ends[i]`` seconds of the run; without a time limit ``(1.0, tuning, None)``.

    Parameters
    ----------
    budget : RunBudget
        The run's budget.
    tuning : Tuning
        The run's tuning.
    count : int
        The sections.
    seconds : float
        A section's seconds at the default cells.

    Returns
    -------
    tuple
        ``(finer, tuning, ends)``.
    """
    if budget.time_limit is None:
        return 1.0, tuning, None
    start = budget.seconds
    share = tuning.pose_section_share * max(budget.time_limit - start, 0.0) / count
    finer = min(3.0, max(1.0, (share / seconds) ** 0.5))
    tuning = dataclasses.replace(tuning, direction_samples=int(tuning.direction_samples * finer ** 2))
    return finer, tuning, [start + share * (i + 1) for i in range(count)]


def _pave_share(limited, width: float, budget, end, tuning: Tuning, box=None):
    """:func:`~workspace_sym.serial.turn.pave_limited` under the run's budget until ``end`` seconds of the run
    (None: the whole budget), with its bar: ``(grid, classes, pieces, evaluated, reason, state)``, the reason
    ``""`` when only its share of the time is spent (not a reason to stop the run)."""
    state: dict = {}
    level = budget if end is None else SectionShare(budget, end, tuning.section_reserve)
    with section_bar(budget.showing) as show:
        grid, classes, proved, count, reason = pave_limited(limited, width, level, show=show, tuning=tuning,
                                                            state=state, box=box)
    return grid, classes, proved, count, "" if reason == SectionShare.REASON else reason, state


class WristCentrePlan(PoseSectionPlan):
    """A cone about the vertical, or a constant orientation with a vertical approach, through the wrist centre
    (:class:`~workspace_sym.serial.pose.WristCentre`, the LBR iiwa): the section of the chain to the wrist centre
    paved as a limited turn (its directions proved with the roll axis within ``psi - c`` of ``d``; for an
    orientation, on the sectors of the first joint's turn where the wrist's spin is proved), the tool points'
    section derived from it (:func:`~workspace_sym.serial.turn.tool_section`; for an exact approach, the wrist
    centre's translated, :func:`~workspace_sym.serial.turn.shifted_section`), the task boxes classified from that
    by the driver and the volume by Pappus's theorem on the tool's section (for an exact approach, the wrist
    centre's pieces with the share of the polar angle proved, :func:`~workspace_sym.serial.turn.limited_volume`,
    :func:`~workspace_sym.serial.turn.spin_volume`) (docs/methods.md section 8).

    Parameters
    ----------
    *args
        Those of :class:`Plan`.
    structure : PoseStructure
        Its ``centre``.
    """

    def pave(self, budget, run):
        """The wrist centre's section (:func:`~workspace_sym.serial.turn.pave_limited`, its cells as wide as a
        time-limited position run's whatever delta), then the tool's.

        Parameters
        ----------
        budget : RunBudget
            The run's budget (clock, box budget, bar).
        run : RunOn
            Not read (storage options are refused by :func:`pose_plan`).

        Returns
        -------
        Section
            The root task box (the tool's section turned a full circle), the tool's grid and classes, their test,
            the volume bracket (:func:`~workspace_sym.serial.section.turned_volume`) and the digest of the cells.

        Raises
        ------
        InvalidParameterError
            ``delta`` exceeds the size of the root task box.
        """
        centre, tuning = self.structure.centre, self.tuning
        assert centre is not None                   # pose_plan chooses this plan for a centre only
        # The section's cells do not follow delta (as a time-limited position run's): budget_cells along the
        # shoulder's reach, finer when the time limit leaves each tilt's section more than its calibration
        # (CENTRE_SECONDS for budget_cells, the cost growing as the cells' count), with seeds in proportion.
        width = budgeted_width(centre.limited, tuning)
        levels = centre.levels()
        # a constant orientation proves 4 M directions (turn.SPIN_TURNS), each about as costly as one of four
        seconds = CENTRE_SECONDS * (1 if centre.spin is None else SPIN_TURNS)
        finer, tuning, ends = timed_sections(budget, tuning, len(levels), seconds)
        width /= finer
        sections, evaluated, reason = [], 0, ""
        for i, (tilt, limited) in enumerate(levels):      # each tilt's own proofs (the last one's read below)
            grid, classes, proved, count, reason, state = _pave_share(limited, width, budget,
                                                                      None if ends is None else ends[i], tuning)
            evaluated += count
            sections.append((grid, classes, tilt))
            if reason:
                break
        if centre.cone == 0:            # an exact approach: the wrist centre's section translated by L d
            tool, codes = sections[0][0], sections[0][1]
            shift = shifted_section(centre.length, centre.sign)
            rho, (z0, z1) = tool.box
            z = (float(arith.down(z0 + shift[0])), float(arith.up(z1 + shift[1])))
            # the volume (a translation keeps it) with the share of each piece's solid its proofs reach
            volume = (limited_volume(limited, tool, codes, proved, tuning) if centre.spin is None
                      else spin_volume(limited, tool, codes, proved, state["sectors"], tuning))
        else:
            tool, codes = tool_section(sections, centre.length, centre.cone, centre.sign)
            shift = None
            rho, z = tool.box
            volume = turned_volume(tool, codes)
        root = np.array([[-rho[1], rho[1]], [-rho[1], rho[1]], [z[0], z[1]]])
        check_root(root, self.delta, self.size, self.robot)
        box = Box(TASK, tuple(root[:, 0]), tuple(root[:, 1]))
        budget.show(0.0, evaluated)
        test = ToolSectionTest(centre.limited.plan, tool, codes, shift)
        return Section(box, tool, codes, evaluated, reason, test, volume,
                       section_digest(tool, codes) + ("" if shift is None else f" shifted {shift[0]!r} {shift[1]!r}"))


class FlangePlan(PoseSectionPlan):
    """A constant orientation with a vertical approach, or an exact vertical approach, on an arm whose flange is
    offset sideways from its last joint's axis (:class:`~workspace_sym.serial.pose.OffsetFlange`, the Panda): the
    section of each wrist solution's tool points paved as a limited turn on one grid (its directions proved with
    that solution's pitch and roll within the limits; for an orientation, on the sectors of the first joint's turn
    where its last joint is), the cells
    swept at every polar angle and the volume bracket from their union
    (:func:`~workspace_sym.serial.turn.roots_volume`), the task boxes classified from that by the driver
    (docs/methods.md section 8, "A flange offset sideways").

    Parameters
    ----------
    *args
        Those of :class:`Plan`.
    structure : PoseStructure
        Its ``flange``.
    """

    def pave(self, budget, run):
        """Each solution's section on one grid (:func:`~workspace_sym.serial.turn.pave_limited`, its cells as
        wide as a time-limited position run's whatever delta, finer under a longer time limit), then their union.

        Parameters
        ----------
        budget : RunBudget
            The run's budget (clock, box budget, bar).
        run : RunOn
            Not read (storage options are refused by :func:`pose_plan`).

        Returns
        -------
        Section
            The root task box (the tool's section turned a full circle), the grid and classes, their test, the
            volume bracket and the digest of the cells.

        Raises
        ------
        InvalidParameterError
            ``delta`` exceeds the size of the root task box.
        """
        flange, tuning = self.structure.flange, self.tuning
        assert flange is not None                   # pose_plan chooses this plan for a flange only
        roots = [limited for _, limited in flange.roots]
        # a cone adds the tool point's own section pruned by the cone (flange.outer): outer proofs, and inner ones
        maps = roots + ([] if flange.outer is None else [flange.outer])
        enclosures = [limited.plan.section.enclose(limited.plan.section.limits[None])[0] for limited in maps]
        box = np.stack([np.min([e[:, 0] for e in enclosures], axis=0), np.max([e[:, 1] for e in enclosures],
                                                                               axis=0)], axis=1)
        width = min(budgeted_width(limited, tuning) for limited in maps)
        # a constant orientation proves 4 M directions (turn.SPIN_TURNS), an exact approach the four axis ones
        turns = len(direction_maps(roots[0].plan.section.lateral)) // DIRECTIONS
        shared = dataclasses.replace(tuning, pose_section_share=tuning.flange_section_share)
        finer, tuning, ends = timed_sections(budget, shared, len(maps), CENTRE_SECONDS * turns)
        width /= finer
        # Each solution's section needs its blocks (the outer cells are those outer in both), but its directions
        # only where its conditions hold: their share of the time follows the share of sampled configurations
        # meeting the conditions (floats: they only share the time); a cone's own map mostly its blocks.
        rng = np.random.default_rng(0)
        met = [len(limited.plan.section.lateral.random_configurations(4_000, rng)) for limited in roots]
        parts, evaluated, reason, grid = [], 0, "", None
        for i, limited in enumerate(maps):
            share = (max(0.1, tuning.flange_directions * met[i] / max(max(met), 1)) if i < len(roots)
                     else tuning.cone_directions)
            mine = dataclasses.replace(tuning, directions_share=share, section_pairs=tuning.flange_pairs)
            grid, classes, proved, count, reason, state = _pave_share(limited, width, budget,
                                                                      None if ends is None else ends[i], mine, box)
            evaluated += count
            parts.append((limited, classes, proved, state.get("sectors", np.zeros(proved.shape, dtype=np.uint64))))
            if reason:
                break
        assert grid is not None
        if len(parts) < len(maps):      # stopped before every section was paved: no cell is outer
            parts = [(limited, np.where(classes == OUTSIDE, UNDECIDED, classes).astype(np.int8), proved, sectors)
                     for limited, classes, proved, sectors in parts]
        outer = None
        if flange.outer is not None and len(parts) == len(maps):
            # outside the cone's set: outside both solutions' sections widened to every approach, or outside the
            # tool point's section pruned where the approach leaves the cone (two proofs, either will do)
            outer = np.logical_and.reduce([classes == OUTSIDE for _, classes, _, _ in parts[:-1]])
            outer |= parts[-1][1] == OUTSIDE
        elif len(parts) == len(maps):
            outer = np.logical_and.reduce([classes == OUTSIDE for _, classes, _, _ in parts])
        if flange.ring is not None:
            # a third proof: the wrist's ring cannot come near enough to the shoulder (closed form, every cell)
            ring = ring_outer_cells(grid.edges, flange.ring, flange.sign, flange.cone)
            outer = ring if outer is None else outer | ring
        codes, volume = roots_volume(parts, grid, outer=outer)
        rho, z = grid.box
        root = np.array([[-rho[1], rho[1]], [-rho[1], rho[1]], [z[0], z[1]]])
        check_root(root, self.delta, self.size, self.robot)
        task = Box(TASK, tuple(root[:, 0]), tuple(root[:, 1]))
        budget.show(0.0, evaluated)
        test = ToolSectionTest(roots[0].plan, grid, codes)
        return Section(task, grid, codes, evaluated, reason, test, volume, section_digest(grid, codes))


class SectionShare:
    """The run's budget as a section paved under a time limit sees it: the run's own reasons to stop, and
    :attr:`REASON` once a step would end past ``end`` seconds of the run (its expected seconds times
    ``reserve``), so that the rest of the limit is left to the task boxes.

    Parameters
    ----------
    budget : RunBudget
        The run's budget.
    end : float
        The run's seconds at which the section's share ends.
    reserve : float
        The margin on a step's expected seconds.
    """

    REASON = "section share"

    def __init__(self, budget: RunBudget, end: float, reserve: float):
        self.budget, self.end, self.reserve = budget, end, reserve

    @property
    def time_limit(self) -> float:
        """The share's end, as a limit for the stages that divide the time left among themselves
        (:func:`~workspace_sym.serial.turn.pave_limited`).

        Returns
        -------
        float
            :attr:`end`, in seconds of the run.
        """
        return self.end

    @property
    def seconds(self) -> float:
        """Seconds since the run began.

        Returns
        -------
        float
            The run budget's :attr:`~workspace_sym.interval.driver.RunBudget.seconds`.
        """
        return self.budget.seconds

    @property
    def showing(self) -> bool:
        """Whether the run's bar draws.

        Returns
        -------
        bool
            The run budget's :attr:`~workspace_sym.interval.driver.RunBudget.showing`.
        """
        return self.budget.showing

    def stop_reason(self, evaluated: int, *, ahead: float = 0.0) -> str:
        """The run's reason to stop, else :attr:`REASON` past the share, else ``""``.

        Parameters
        ----------
        evaluated : int
            Boxes the section has evaluated.
        ahead : float
            Seconds the next step is expected to take.

        Returns
        -------
        str
            Why the section stops now (``""``: it goes on).
        """
        late = self.budget.seconds + self.reserve * ahead > self.end
        return self.budget.stop_reason(evaluated, ahead=ahead) or (self.REASON if late else "")


class PosePairsPlan(Plan):
    """The pairs method with a tool constraint, over ``(x, y, z)`` (:class:`~workspace_sym.serial.pose.PoseStep`
    in the one pairs loop); its boxes stay in memory.

    Parameters
    ----------
    *args
        Those of :class:`Plan`.
    structure : PoseStructure
        The constrained model over ``(x, y, z)``.
    """

    method = "pairs"

    def __init__(self, *args, structure: PoseStructure):
        super().__init__(*args)
        self.structure = structure

    def pave(self, budget, run):
        """Nothing to pave: the root task box, the enclosure of the position over the arm's limits.

        Parameters
        ----------
        budget : RunBudget
            Not read.
        run : RunOn
            Not read.

        Returns
        -------
        Section
            The root box alone.

        Raises
        ------
        InvalidParameterError
            The position has no finite enclosure, or ``delta`` exceeds the size of the root task box.
        """
        model = self.structure.model
        assert model is not None                    # a pairs plan has its model (pose_plan)
        root = model.position.enclose(model.position.limits[None])[0]
        check_root(root, self.delta, self.size, self.robot)
        return Section(Box(TASK, tuple(root[:, 0]), tuple(root[:, 1])))

    def classify(self, section, budget, run):
        """The pairs loop with the pose model's step (:class:`~workspace_sym.serial.pose.PoseStep`), its boxes in
        memory.

        Parameters
        ----------
        section : Section
            What :meth:`pave` returned.
        budget : RunBudget
            The run's budget (clock, box budget, bar).
        run : RunOn
            Not read (storage options are refused by :func:`pose_plan`).

        Returns
        -------
        Paving
            Its pending boxes are the task boxes left when the budget stopped the loop.
        """
        model, tuning = self.structure.model, self.tuning
        assert model is not None
        root = section.box.array
        step = PoseStep(model, self.delta, self.size, tuning.pose_inner_depth, tuning.pose_max_pairs,
                        tuning.min_pairs, float(np.prod(root[:, 1] - root[:, 0])))
        keeper = BoxStore(3)
        T, _, _, evaluated, reason = pave_pairs(step, root[None].copy(), model.root_pairs(), np.zeros(1, dtype=int),
                                                budget=budget, keeper=keeper, chunk=POSE_CHUNK_PAIRS,
                                                show=budget.show if budget.showing else None)
        return self.paving(section.box, [keeper.arrays("inner")], [keeper.arrays("boundary")],
                           [keeper.arrays("outer")], T if len(T) else None, budget, evaluated, reason,
                           self.robot.units)


def _with(paving: Paving, **changes) -> Paving:
    """``paving`` with ``changes``, its decided boxes not read back when they are on disk."""
    fields: dict[str, Any] = dict(changes)
    if isinstance(paving, StoredPaving):        # (replace() would read the stored boxes back)
        fields.update({k: np.empty((0, len(paving.variables), 2)) for k in ("inner", "boundary", "outer")})
    return dataclasses.replace(paving, **fields)


# ----------------------------------------------------------------------------------------------- choosing
def turn_without_inner(robot: DHRobot, values: tuple) -> bool:
    """``robot`` is a section turned by a first joint limited to less than a period (:class:`Turned`, not full)
    that proves no inner box: a section moved by two joints (``w`` sweeps a surface, no box of ``w`` lies in it)
    or a turn shorter than half a turn (no pair of directions covers the circle:
    :func:`~workspace_sym.serial.turn.limited_turn` is None)."""
    plan = structure_of(robot, values)
    return isinstance(plan, Turned) and not plan.full and limited_turn(plan, reach_model(robot, values)) is None


def on_cells(robot: DHRobot, values: tuple, stored: bool = False, tuning: Tuning = DEFAULT) -> bool:
    """The critical method decides ``robot`` on one grid of task cells (:class:`CellsPlan`): a planar arm, a
    spatial one without a product or turned-section structure, or one whose turned section proves no inner box
    (:func:`turn_without_inner`) moved by at most ``tuning.cells_max_joints`` joints (and by three at least: the
    image of fewer is a surface, with no inner box either way), unless its boxes are to be stored (``stored``: the
    section path, which stores them, is kept).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    values : tuple
        Its parameter values as ``(name, value)`` pairs.
    stored : bool
        The run stores its boxes (``max_memory``, ``store`` or ``resume``).
    tuning : Tuning
        ``cells_max_joints``.

    Returns
    -------
    bool
        Whether the critical method paves ``robot`` on one grid of task cells.
    """
    model = reach_model(robot, values)
    if model.m == 2 or structure_of(robot, values) is None:
        return True
    return not stored and model.m <= model.k <= tuning.cells_max_joints and turn_without_inner(robot, values)


def choose_plans(robot: DHRobot, values: tuple, kind: str, method: str, *, delta: float, size: str,
                 tuning: Tuning, problem: dict, run: RunOn) -> list[Plan]:
    """The plans for ``robot`` with the resolved method ``kind`` (``"critical"`` or ``"pairs"``, from
    ``method``): the first to try, then those that take over when its cover is too large
    (:class:`~workspace_sym.errors.CoverTooLarge`): a turned section after the 3-D cells, and the pairs method
    under ``"auto"``.  Storage options (``run.max_memory``, ``store``, ``resume``) keep a spatial arm off the
    one-grid cells (pairs under ``"auto"``, refused under ``"critical"``).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    values : tuple
        Its parameter values as ``(name, value)`` pairs.
    kind : {"critical", "pairs"}
        The resolved method (:func:`~workspace_sym.serial.api.resolve_method`).
    method : {"auto", "critical", "pairs"}
        The method asked for.
    delta : float
        Undecided task boxes of size at most ``delta`` are boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured.
    tuning : Tuning
        The figures of every stage.
    problem : dict
        The run's whole problem (:func:`~workspace_sym.serial.stored.reach_problem`).
    run : RunOn
        Where and how the run goes (storage options, executor).

    Returns
    -------
    list of Plan
        The plans in the order to try them.

    Raises
    ------
    InvalidParameterError
        Storage options with ``method="critical"`` on an arm paved on one grid of cells.
    """
    stored = run.max_memory is not None or run.store is not None or run.resume is not None
    model = reach_model(robot, values)
    args = (robot, values, delta, size, tuning, problem)
    pairs = PairsPlan(*args)
    if kind == "pairs":
        return [pairs]
    cells = on_cells(robot, values, stored, tuning)
    if cells and model.m == 3 and stored and method == "auto":
        return [pairs]              # the 3-D grid is decided in memory; the pairs method stores its boxes
    if cells and model.m == 3:
        _ = model.minors            # the 3 x 3 minors of the cover: symbolic, within the time limit
    if stored and cells:
        space = "planar" if model.m == 2 else "3-D"
        refuse_storage(f"the {space} critical method on {robot.name}", run,
                       why="decides one grid of cells in one pass, in memory",
                       supported="method='pairs' on any arm, and the critical method on a spatial arm with a "
                                 "product or a section turned by its first joint")
    plans: list[Plan] = []
    if cells:
        plans.append(CellsPlan(*args, executor=run.executor))
        if model.m == 3 and structure_of(robot, values) is not None:
            # a turned section proving no inner box: its own path (outer boxes), as before the 3-D cells
            plans.append(SectionPlan(*args, executor=run.executor))
    else:
        plans.append(SectionPlan(*args, executor=run.executor))
    if method == "auto":
        plans.append(pairs)         # also when the critical cover is too large
    return plans


def pose_plan(robot: DHRobot, values: tuple, constraint: PoseConstraint, structure: PoseStructure, *,
              delta: float, size: str, tuning: Tuning, run: RunOn) -> Plan:
    """The plan of a run with a tool constraint: the constrained section when the first joint turns it (a cone
    about the vertical), the pairs method otherwise (its boxes in memory: storage options refused).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    values : tuple
        Its parameter values as ``(name, value)`` pairs.
    constraint : PoseConstraint
        The tool constraint.
    structure : PoseStructure
        How the constrained workspace is paved (:func:`~workspace_sym.serial.pose.pose_structure`).
    delta : float
        Undecided task boxes of size at most ``delta`` are boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured.
    tuning : Tuning
        The figures of every stage.
    run : RunOn
        Where and how the run goes (its storage options).

    Returns
    -------
    Plan
        A :class:`PoseSectionPlan` when ``structure`` has a revolved section, else a :class:`PosePairsPlan`.

    Raises
    ------
    InvalidParameterError
        Storage options (``max_memory``, ``store``, ``resume``) for the pairs method.
    """
    problem = reach_problem(robot, values, delta, size, tuning, constraint=constraint.to_dict())
    args = (robot, values, delta, size, tuning, problem)
    if structure.centre is not None:
        refuse_storage(f"reach with {constraint} on {robot.name} (through the wrist centre)", run,
                       why="derives its section from the wrist centre's in memory",
                       supported="the section method of a cone about the vertical on an arm turned by a whole turn "
                                 "and reach without a pose")
        return WristCentrePlan(*args, structure=structure)
    if structure.flange is not None:
        refuse_storage(f"reach with {constraint} on {robot.name} (through the wrist's solutions)", run,
                       why="derives its section from the solutions' sections in memory",
                       supported="the section method of a cone about the vertical on an arm turned by a whole turn "
                                 "and reach without a pose")
        return FlangePlan(*args, structure=structure)
    if not structure.sectioned:
        refuse_storage(f"reach with {constraint} on {robot.name} (the pairs method)", run,
                       why="keeps its boxes in memory",
                       supported="the section method (a constraint whose section the first joint turns, "
                                 "such as a cone about the vertical on the Puma 560) and reach without a pose")
        return PosePairsPlan(*args, structure=structure)
    return PoseSectionPlan(*args, structure=structure)
