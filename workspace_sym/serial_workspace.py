"""Certified position workspace of a serial robot: reachable boxes proved, unreachable boxes proved.

:func:`reach` paves the space of end-effector positions (``x, y`` for a
planar robot, ``x, y, z`` otherwise) into

* **outer** boxes: no configuration within the joint limits puts the
  end-effector in the box;
* **inner** boxes: every point of the box is the position of some
  configuration within the joint limits;
* **boundary** boxes: neither is proved and the box is at most ``delta``.

Two methods (``method=``):

``"critical"`` (the default where it applies).  A planar robot is the map
``q -> (x, y)`` of :func:`workspace_sym.interval.image.critical_paving`: the
critical set of every face of the joint box is covered by joint boxes, whose
enclosures mark a grid of cells of size ``delta``; every connected region of
unmarked cells misses the workspace boundary, so it is decided by one proof
for one of its cells (Krawczyk inside, exhausted joint boxes outside); marked
cells are tried one by one.  A spatial robot whose coordinates are moved
by disjoint sets of joints (a SCARA: ``x, y`` by two revolute joints, ``z``
by a prismatic one) has the product of their images as workspace: the plane
factor is paved that way, a single coordinate's image is an interval (outer:
its enclosure; inner: between two configurations whose values are proved).
Otherwise a spatial robot whose first joint is revolute with
``theta_1 = k q_1 + offset`` and ``q_1`` in no other entry of the table (its
own ``d_1``, ``a_1``, ``alpha_1`` included) nor in the tool (standard DH, no
base transform) has ``p = Rz(theta_1) (u, c, v)`` with
``(u, v)`` depending on the other joints and ``c`` constant (a lateral
offset): the section ``S`` of points ``(u, v)`` is paved that way (cells of
``SECTION_RATIO delta``), and a box of ``(x, y, z)`` is classified from the
intervals of ``s = sqrt(x^2 + y^2 - c^2)``, of its polar angle and of ``z``:
it is inner when one branch ``u = +s`` or ``u = -s`` lies in proved cells of
``S`` with the needed ``theta_1`` inside the limits for every point, outer
when for both branches the cells are proved outside ``S`` or the needed
``theta_1`` misses the limits.  Angles are float ``atan2`` of the box corners
widened by ``ANGLE_PAD`` (10^6 times their rounding error).  When ``c``
varies with the other joints, or a rigid base transform comes first (any
URDF robot), the section is ``(rho, z)`` in the first joint's frame
(:mod:`workspace_sym.reach_section`: inner boxes need ``q_1`` to turn a
full circle, or :mod:`workspace_sym.reach_turn` half a circle with a section
moved by three joints or more; outer boxes hold whatever its limits).  Such
an arm whose section proves no inner box (a two-joint section, or a turn
below half a circle) is paved on 3-D cells as below when at most
``CELLS_MAX_JOINTS`` joints move the position (the section path when its
boxes are stored, or when the 3-D cover is too large).  Any other spatial
robot (a prismatic first joint, a first joint whose variable enters later
rows, ...) is the map ``q -> (x, y, z)`` of the same
:func:`~workspace_sym.interval.image.critical_paving` in space: the critical
set of every face (the position Jacobian's rank below 3, or the tangent cone
of the joint box not mapped onto ``R^3``) is covered, its enclosures mark a
3-D grid of cells of size ``delta``, and every 6-connected region of unmarked
cells is decided by one proof; a cover too large falls back to ``"pairs"``.

``"pairs"`` (any robot).  Each task box carries joint boxes covering every
configuration whose position may lie in it; the root task box is the
enclosure of the position over the limits.  When a task box is split, a
joint box goes to each half its enclosure meets (refined by bisection while
wider than the half); a task box left without joint boxes is outer.  Inner
proofs: the Krawczyk test of :class:`~workspace_sym.interval.image.ImageMap`
around a Newton solution for the box centre.

Joint ranges: a joint's range is its limits.  The position is periodic in a
joint variable only when that variable appears in angles alone, each a
rational multiple of it plus a constant (a coupled ``theta_2 = q_2 + q_1/2``
makes ``q_1``'s period ``4 pi``); a joint whose range spans a period is then
paved over one period without limit faces.  An unlimited revolute joint is
paved over one period of the position (``theta_1 = q_1/2``: ``q_1`` in
``[-2 pi, 2 pi]``), or raises :class:`~workspace_sym.errors.JointLimitError`
when the position is not periodic in it.  ``time_limit`` bounds the whole call:
the model's symbolic preparation runs under a budget of the time limit
(:func:`~workspace_sym.symbolic.symbolic_budget`) and raises
:class:`~workspace_sym.errors.SymbolicBudgetError` naming ``time_limit`` when
it is not ready in time (no task box is known then: nothing is decided); a
chunk of work expected to end past it is not started, and what is left is
pending.

Every verdict rests on outward-rounded interval arithmetic (numpy engine):
the enclosures of the position and of the Jacobian's minors, the Krawczyk
operator, and the box classification.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
import os
import time
import zipfile
from contextlib import contextmanager
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import sympy as sp

from . import reach_section, reach_turn
from .errors import InvalidParameterError, JointLimitError, SymbolicBudgetError
from .interval import arith, image
from .interval.boxes import Box, Paving, StoredPaving, box_measure, box_sizes, check_delta, halves
from .interval.driver import (
    RunBudget,
    RunOn,
    StopAt,
    paving_of,
    read_checkpoint,
    refuse_storage,
    store_for,
    subdivide,
    write_checkpoint,
)
from .interval.executor import MIN_CHUNK, runner_for
from .interval.fingerprint import Fingerprint, check_fingerprint
from .interval.graph import numpy_constant
from .interval.image import CellGrid, CoverTooLarge, ImageMap, critical_cover, critical_paving, distribute
from .interval.search import split_every_axis
from .interval.store import BoxStore
from .interval.verdict import INSIDE, OUTSIDE, UNDECIDED, codes_from_masks
from .kinematics import DHRobot
from .reach_section import (
    SECTION_DEPTH,
    Pieces,
    RadialMap,
    Turned,
    TurnedTest,
    first_joint_turn,
    section_bar,
    section_paving,
    turned,
    turned_volume,
)
from .reach_turn import LimitedTurnTest, limited_turn, limited_volume, pave_limited
from .symbolic import symbolic_budget

__all__ = ["reach", "Pose", "resolve_method", "ReachModel", "METHODS", "CHUNK_PAIRS", "reach_problem"]

_TASK = (sp.Symbol("x"), sp.Symbol("y"), sp.Symbol("z"))
_MIN_PAIRS = 64                  # pairs a task box may always hold, however small its share of the root box
METHODS = ("auto", "critical", "pairs")
SECTION_RATIO = 0.25             # cell width of the section against the width of the task boxes
SECTION_RESERVE = 1.5            # margin on the expected time of a step of a turned section and on its (x, y, z) boxes
ANGLE_PAD = 1e-9                 # widening of float angles (rad)
CHUNK_PAIRS = 100_000            # (joint box, task box) pairs in one chunk of the pairs method
CELLS_MAX_JOINTS = 3             # a turned section proving no inner box gives way to the 3-D cells up to this many
                                 # moving joints (a square map: docs/methods.md section 5 has the measured costs)
_MARGIN = 1e-12                  # of angle comparisons after reduction modulo 2 pi
_TWO_PI = 2 * math.pi


@dataclass(frozen=True, slots=True)
class Pose:
    """A constraint on the tool frame for :func:`reach` (read by :func:`workspace_sym.orientation.reach_pose`):
    the approach axis (z of the tool frame) within ``cone`` degrees of ``approach`` (``every``: every
    direction of the cone), or the frame exactly ``orientation`` (a rotation matrix) or ``rpy`` (roll, pitch,
    yaw in degrees).

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


def _exact(value) -> sp.Expr:
    """``value`` with its floats replaced by the rationals they are (a float is its binary value exactly)."""
    value = sp.sympify(value)
    return value.xreplace({f: sp.Rational(f) for f in value.atoms(sp.Float)})


def _period(robot: DHRobot, k: int, parameters: dict | None):
    """``(T, "")``, ``T`` the least period of the position in joint ``k``'s variable ``q``, or ``(None, why)``
    when it is not proved periodic.

    A DH matrix holds its angles only through their cosines and sines, so if ``q`` appears in angles alone
    (theta and alpha of any row), each ``c_i q + (terms free of q)`` with every ratio ``c_i / c_0`` rational
    (``n_i / D`` over a common denominator, ``g = gcd(n_i)``), the position is ``T`` periodic in ``q`` where
    ``c_i T`` is in ``2 pi Z`` for every ``i``: ``T = 2 pi D / (g |c_0|)``.
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
            angle = _exact(robot.substitute(angle, parameters))
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


def _joint_range(robot: DHRobot, k: int, parameters: dict | None):
    """Exact range of joint ``k`` in the reach model, and whether the position is periodic in it with that
    range as its period (a joint turning the position through whole periods has no limit faces).

    A joint whose range spans a period ``T`` of the position (:func:`_period`) is given ``[lo, lo + T]``
    (an unlimited one ``[-T/2, T/2]``): the image is the same.  Whether the limits span ``T`` is decided
    exactly; undecidable counts as not, which is always sound.
    """
    joint = robot.joints[k]
    period, why = _period(robot, k, parameters)
    if joint.limits is None:
        if joint.kind == "P":
            raise JointLimitError(f"joint {k + 1} ({joint.variable}) is prismatic: reach needs its limits")
        if period is None:
            raise JointLimitError(f"joint {k + 1} ({joint.variable}) has no limits and the position is not "
                                  f"periodic in it ({why}): reach needs its limits")
        return (-period / 2, period / 2), True
    lo, hi = joint.limits
    try:
        full = period is not None and bool(sp.simplify(_exact(hi - lo) - period) >= 0)
    except TypeError:
        full = False
    return ((lo, lo + period) if full else (lo, hi)), full


class ReachModel(ImageMap):
    """The position map of a robot over the joints that move it.

    ``coordinates`` are the indices of the position coordinates that depend
    on the joints (two for a planar robot); ``joints`` are the indices of
    the joints the position depends on, ``limits`` their ``(k, 2)`` limits
    (floats enclosing the exact ones).
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
        ranges = [_joint_range(robot, k, parameters) for k in self.joints]
        self.exact_limits = [r for r, _ in ranges]
        self.task_variables = tuple(_TASK[i] for i in self.coordinates)
        super().__init__([position[i] for i in self.coordinates], [robot.q[k] for k in self.joints],
                         [r for r, _ in ranges], [p for _, p in ranges])


@dataclass(frozen=True)
class _Revolved:
    """``p = Rz(theta_1) (u, c, v)``: the section map ``(u, v)`` of the other joints, the offset ``c`` (two
    floats enclosing it) and ``theta_1``'s range (outward and inward floats; ``full`` for a whole turn)."""

    section: ImageMap
    c: tuple
    outer_range: tuple
    inner_range: tuple
    full: bool


def _revolved(model: ReachModel) -> _Revolved | None:
    """The section of a spatial robot turned by its first joint, or None when the structure is not there."""
    robot = model.robot
    if robot.convention != "standard" or robot.base is not None or model.m != 3 or model.joints[:1] != [0]:
        return None
    turn = first_joint_turn(model)        # theta_1 = slope q1 + offset turns everything after it, nothing else
    if turn is None:
        return None
    q1, theta, slope = turn
    offset = theta.subs(q1, 0)
    # Standard DH without base: T = Rz(theta_1) Tz(d_1) Tx(a_1) Rx(alpha_1) ..., so p = Rz(theta_1) p(theta_1 = 0).
    p1 = [sp.simplify(e.subs(q1, -offset / slope)) for e in model.position]
    if p1[1].free_symbols & set(robot.q):
        return None
    variables = [q for q in robot.q[1:] if q in (p1[0].free_symbols | p1[2].free_symbols)]
    if not variables:
        return None
    rows = [model.variables.index(q) for q in variables]
    section = ImageMap([p1[0], p1[2]], variables, [model.exact_limits[r] for r in rows], model.periodic[rows])
    # theta_1's range is the image of q1's (one period of the position when q1 turns it fully: a whole turn).
    (lo, hi), full = model.exact_limits[0], bool(model.periodic[0])
    lo, hi = (slope * lo + offset, slope * hi + offset)[::1 if slope > 0 else -1]
    lo_f, hi_f = numpy_constant(lo), numpy_constant(hi)
    return _Revolved(section, numpy_constant(p1[1]), (lo_f[0], hi_f[1]), (lo_f[1], hi_f[0]), full)


@dataclass(frozen=True)
class _Product:
    """Position coordinates moved by disjoint sets of joints: the workspace is the product of their images.
    ``plane`` are the two task axes of a group of two coordinates (or ``()``), ``section`` its map;
    ``intervals`` hold, per single coordinate, its axis, an outer enclosure of its image and an inner one
    (or None)."""

    plane: tuple
    section: ImageMap | None
    intervals: tuple


def _interval_image(image: ImageMap, rng) -> tuple:
    """Outer and inner enclosures of the image of a real function over a joint box: the image of a
    connected box is an interval; two configurations within the limits whose values are proved at most
    ``a`` and at least ``b`` put ``[a, b]`` inside it (the segment between them lies in the box)."""
    outer = tuple(image.enclose(image.limits[None])[0, 0])
    corners = np.array(list(itertools.product(*image.inner_limits))) if image.k <= 10 else np.empty((0, image.k))
    q = np.concatenate([corners, image.random_configurations(2000, rng)])
    values = image.enclose(np.repeat(q[:, :, None], 2, axis=2))[:, 0]
    a, b = values[:, 1].min(), values[:, 0].max()
    return outer, ((a, b) if a <= b else None)


def _product(model: ReachModel) -> _Product | None:
    """The product structure of a spatial robot's position (a SCARA: x, y by two joints, z by a third)."""
    if model.m != 3:
        return None
    uses = [model.expressions[i].free_symbols & set(model.variables) for i in range(3)]
    groups: list[list[int]] = []
    for i in range(3):
        joined = [g for g in groups if any(uses[i] & uses[j] for j in g)]
        merged = sorted({i, *(j for g in joined for j in g)})
        groups = [g for g in groups if g not in joined] + [merged]
    if len(groups) < 2:
        return None
    plane: tuple = ()
    section, intervals = None, []
    rng = np.random.default_rng(0)
    for g in groups:
        variables = [q for q in model.variables if q in set().union(*(uses[i] for i in g))]
        rows = [model.variables.index(q) for q in variables]
        image = ImageMap([model.expressions[i] for i in g], variables, [model.exact_limits[r] for r in rows],
                         model.periodic[rows])
        if len(g) == 2:
            plane, section = tuple(g), image
        else:
            intervals.append((g[0], *_interval_image(image, rng)))
    return _Product(plane, section, tuple(intervals))


@lru_cache(maxsize=16)
def _model(robot: DHRobot, parameters: tuple) -> ReachModel:
    """The reach model of a robot (cached: a worker compiles it once for all its chunks)."""
    return ReachModel(robot, dict(parameters) or None)


@lru_cache(maxsize=16)
def _section(robot: DHRobot, parameters: tuple) -> _Revolved | _Product | Turned | None:
    """How a spatial robot's workspace reduces to a map into the plane: a product of images, a section
    turned by the first joint (constant lateral offset, or any in cylindrical coordinates), or None."""
    model = _model(robot, parameters)
    return _product(model) or _revolved(model) or turned(model)


def _plane_map(robot: DHRobot, parameters: tuple, which: str) -> ImageMap | RadialMap:
    """The map whose critical set a cover step covers: the reach model itself (``"model"``: a planar arm, or a
    spatial one paved on cells in space) or the section of a spatial arm (``"section"``)."""
    if which == "model":
        return _model(robot, parameters)
    section = _section(robot, parameters)
    assert section is not None and section.section is not None     # asked only of a robot with a plane map
    return section.section


@dataclass(frozen=True)
class _CoverStep:
    """The critical cover of a group of faces of the planar map or of the section (picklable: the robot
    travels to the workers, the map is compiled there once)."""

    robot: DHRobot
    parameters: tuple
    which: str
    target: float
    clip: tuple

    def __call__(self, faces):
        return critical_cover(_plane_map(self.robot, self.parameters, self.which), faces, self.target,
                              np.array(self.clip))


def _cover_with(executor, robot, parameters, which):
    """The ``cover`` argument of :func:`critical_paving`: all faces here, or groups of faces, one task each."""
    if executor is None:
        return None

    def cover(faces, target, clip):
        spread = runner_for(executor, _CoverStep(robot, parameters, which, float(target), tuple(map(tuple, clip))))
        try:
            groups = [faces[i::spread.slots] for i in range(min(spread.slots, len(faces)))]
            return [f.result() for f in [spread.submit(group) for group in groups]]
        finally:
            spread.close()
    return cover


# ---------------------------------------------------------------------------------------------- revolved boxes
def _angles(X: np.ndarray):
    """Polar angle range ``(lo, hi)`` of the ``(x, y)`` rectangles of boxes ``X``, widened by ``ANGLE_PAD``;
    ``(-inf, inf)`` where the rectangle holds the axis ``x = y = 0``."""
    x0, x1, y0, y1 = (X[:, 0, 0] + 0.0, X[:, 0, 1] + 0.0, X[:, 1, 0] + 0.0, X[:, 1, 1] + 0.0)
    axis = (x0 <= 0) & (x1 >= 0) & (y0 <= 0) & (y1 >= 0)
    xs, ys = np.stack([x0, x1, x0, x1], axis=1), np.stack([y0, y0, y1, y1], axis=1)
    angle = np.arctan2(ys, xs)
    # A rectangle across the negative x axis: its angles are continuous over (pi/2, 3 pi/2).
    across = (x1 < 0) & (y0 < 0) & (y1 >= 0)
    angle = np.where(across[:, None] & (ys < 0), angle + _TWO_PI, angle)
    lo, hi = angle.min(axis=1) - ANGLE_PAD, angle.max(axis=1) + ANGLE_PAD
    return np.where(axis, -np.inf, lo), np.where(axis, np.inf, hi)


def _arc_within(lo, hi, a: float, b: float, full: bool):
    """``[lo, hi]`` lies in ``[a, b] + 2 pi k`` for some integer ``k``."""
    if full:
        return np.ones(len(lo), dtype=bool)
    with np.errstate(invalid="ignore"):
        t = a + np.remainder(lo - a, _TWO_PI)
        return (t >= a + _MARGIN) & (t + (hi - lo) <= b - _MARGIN)


def _arc_apart(lo, hi, a: float, b: float, full: bool):
    """``[lo, hi]`` meets no ``[a, b] + 2 pi k``."""
    if full or b - a >= _TWO_PI:
        return np.zeros(len(lo), dtype=bool)
    with np.errstate(invalid="ignore"):
        t = b + np.remainder(lo - b, _TWO_PI)
        return (t >= b + _MARGIN) & (t + (hi - lo) <= a + _TWO_PI - _MARGIN)


class _SectionTest:
    """Classify boxes of ``(x, y, z)`` from a paving of the section (module docstring)."""

    def __init__(self, revolved: _Revolved, grid, classes):
        self.r, self.grid = revolved, grid
        self.inside = grid.prefix(classes, INSIDE)
        self.outside = grid.prefix(classes, OUTSIDE)

    def _in(self, table, u, z, outside_counts):
        return self.grid.all_in_class(table, np.stack([np.stack(u, axis=1), z], axis=1), outside_counts=outside_counts)

    def __call__(self, X: np.ndarray):
        r = self.r
        with np.errstate(all="ignore"):
            r2 = arith.add(arith.sqr((X[:, 0, 0], X[:, 0, 1])), arith.sqr((X[:, 1, 0], X[:, 1, 1])))
            c_lo, c_hi = r.c
            s2 = arith.sub(r2, arith.sqr((np.float64(c_lo), np.float64(c_hi))))
            s = arith.sqrt((np.maximum(s2[0], 0.0), np.maximum(s2[1], 0.0)))
            phi_lo, phi_hi = _angles(X)
            c = 0.5 * (c_lo + c_hi)
            if c_lo == c_hi == 0.0:
                a_lo = a_hi = np.zeros(len(X))
                turn = math.pi
            else:
                ends = np.arctan2(c, np.stack([s[0], s[1]], axis=1))
                a_lo, a_hi = ends.min(axis=1) - ANGLE_PAD, ends.max(axis=1) + ANGLE_PAD
                turn = math.copysign(math.pi, c)
        z = X[:, 2]
        plus, minus = (s[0], s[1]), (-s[1], -s[0])
        # theta_1 = phi - atan2(c, u): u = +s gives phi - alpha, u = -s gives phi - turn + alpha.
        t_plus = (phi_lo - a_hi, phi_hi - a_lo)
        t_minus = (phi_lo - turn + a_lo - ANGLE_PAD, phi_hi - turn + a_hi + ANGLE_PAD)
        (a_in, b_in), (a_out, b_out) = r.inner_range, r.outer_range
        in_plus = self._in(self.inside, plus, z, False)
        in_minus = self._in(self.inside, minus, z, False)
        inner = (s2[0] >= 0) & ((in_plus & _arc_within(*t_plus, a_in, b_in, r.full))
                                | (in_minus & _arc_within(*t_minus, a_in, b_in, r.full)))
        if c_lo == c_hi == 0.0 and (r.full or b_in - a_in >= math.pi + _MARGIN):
            # theta_1's range and its half turn cover the circle: every angle is served by one branch.
            inner |= in_plus & in_minus
        out_plus = self._in(self.outside, plus, z, True) | _arc_apart(*t_plus, a_out, b_out, r.full)
        out_minus = self._in(self.outside, minus, z, True) | _arc_apart(*t_minus, a_out, b_out, r.full)
        outer = (s2[1] < 0) | (out_plus & out_minus)
        return inner, outer & ~inner


class _ProductTest:
    """Classify boxes of ``(x, y, z)`` for a product structure: inner when every factor is proved inside,
    outer when one factor is proved outside."""

    def __init__(self, product: _Product, grid, classes):
        self.p, self.grid = product, grid
        if product.section is not None:
            self.inside = grid.prefix(classes, INSIDE)
            self.outside = grid.prefix(classes, OUTSIDE)

    def __call__(self, X: np.ndarray):
        inner = np.ones(len(X), dtype=bool)
        outer = np.zeros(len(X), dtype=bool)
        if self.p.section is not None:
            rect = X[:, list(self.p.plane)]
            inner &= self.grid.all_in_class(self.inside, rect, outside_counts=False)
            outer |= self.grid.all_in_class(self.outside, rect, outside_counts=True)
        for axis, (lo, hi), proved in self.p.intervals:
            inner &= False if proved is None else (X[:, axis, 0] >= proved[0]) & (X[:, axis, 1] <= proved[1])
            outer |= (X[:, axis, 1] < lo) | (X[:, axis, 0] > hi)
        return inner, outer & ~inner


def _prove_in_pieces(model, T, seeds, depth):
    """Mask of the boxes ``T`` proved inside the image, box ``i`` cut into up to ``2^(m depth[i])`` pieces
    (halved along every edge per level) of which every one must pass the test."""
    proved = np.ones(len(T), dtype=bool)
    pieces, owner = T, np.arange(len(T))
    for level in range(int(depth.max(initial=0)) + 1):
        ok = model.prove_inside(pieces, seeds[owner])
        failed = owner[~ok]
        final = depth[failed] <= level
        proved[failed[final]] = False
        again = ~ok
        again[np.nonzero(again)[0][final]] = False
        if not again.any():
            break
        pieces = split_every_axis(pieces[again])
        owner = np.tile(owner[again], 2 ** T.shape[1])
    return proved


def _volumes(T: np.ndarray) -> np.ndarray:
    return np.prod(T[:, :, 1] - T[:, :, 0], axis=1)


@dataclass(frozen=True)
class _ReachStep:
    """One generation of :func:`reach` on a chunk of task boxes with their pairs (picklable: the robot travels
    to the workers, the model is compiled there once).

    Called with ``(T, Q, owner)``, it returns the inner, boundary and outer
    task boxes, the children of the split ones and their pairs ``(Q, owner)``.
    Each task box is treated on its own (:func:`_distribute`), so chunks give
    together exactly what one call on all the boxes gives.
    """

    robot: DHRobot
    parameters: tuple
    delta: float
    size: str
    inner_depth: int
    max_pairs: int
    root_measure: float

    def __call__(self, part):
        T, Q, owner = part
        model = _model(self.robot, self.parameters)
        # A task box may hold pairs in proportion to its share of the root box, and at least _MIN_PAIRS.
        cap = np.maximum(_MIN_PAIRS, np.floor(self.max_pairs * (_volumes(T) / self.root_measure)))
        Q, owner = distribute(model, T, Q, owner, cap)
        count = np.bincount(owner, minlength=len(T))
        is_out = count == 0
        # One seed per task box: the centre of its first joint box.
        live, first = np.unique(owner, return_index=True)
        is_in = np.zeros(len(T), dtype=bool)
        if len(live):
            seeds = Q[first].mean(axis=2)
            # A box that would become a boundary box is also tried in pieces (every piece proved).
            last = box_sizes(T[live], self.size) <= self.delta
            is_in[live] = _prove_in_pieces(model, T[live], seeds, np.where(last, self.inner_depth, 0))
        return split_pairs(T, Q, owner, is_in, is_out, self.delta, self.size)


def split_pairs(T, Q, owner, is_in, is_out, delta: float, size: str):
    """One step of the pair method after its proofs: ``(inner, boundary, outer, children, Q, owner)``.

    Undecided task boxes of size at most ``delta`` (or too thin to halve in floats) are boundary boxes; the
    others are halved, and both halves inherit the joint boxes ``Q`` their parent owned."""
    und = ~is_out & ~is_in
    small = und & (box_sizes(T, size) <= delta)
    split = und & ~small
    children, ok = halves(T[split])
    boundary = np.concatenate([T[small], T[split][~ok]])     # too thin to split: delta below float resolution
    split[np.nonzero(split)[0][~ok]] = False
    children = children.reshape(-1, 2, *T.shape[1:])[ok].reshape(-1, *T.shape[1:])
    new_index = np.full(len(T), -1)
    new_index[split] = np.arange(split.sum())
    pair = new_index[owner] >= 0
    Q, base = Q[pair], new_index[owner[pair]]
    return T[is_in], boundary, T[is_out], children, np.concatenate([Q, Q]), np.concatenate([2 * base, 2 * base + 1])


def _parts(T, Q, owner, pieces: int):
    """The task boxes cut into ``pieces`` runs of consecutive boxes, each with its own pairs in their order."""
    order = np.argsort(owner, kind="stable")
    Q, owner = Q[order], owner[order]
    for rows in np.array_split(np.arange(len(T)), pieces):
        if len(rows):
            a, b = rows[0], rows[-1] + 1
            lo, hi = np.searchsorted(owner, [a, b])
            yield T[a:b], Q[lo:hi], owner[lo:hi] - a


def _pairs(robot, parameters, delta, size, run, *, max_pairs, inner_depth, executor, chunk_pairs, where, problem):
    """The ``"pairs"`` method: ``(paving, None)``, its decided boxes in a store (memory or disk, ``where``) and,
    with ``where.resume``, a checkpoint of the task boxes left with their joint boxes, named by ``problem``
    (:func:`reach_problem`) and the method's own options."""
    model = _model(robot, parameters)
    Q = model.limits[None].copy()
    root = model.enclose(Q)[0]
    box = Box(model.task_variables, tuple(root[:, 0]), tuple(root[:, 1]))
    T = root[None].copy()
    owner = np.zeros(1, dtype=int)
    evaluated, reason, seconds_before = 0, "", 0.0
    step = _ReachStep(robot, parameters, float(delta), size, inner_depth, int(max_pairs), float(_volumes(T)[0]))
    path = None if where.resume is None else Path(where.resume)
    fingerprint = Fingerprint({**problem, "method": "pairs", "lower": list(box.lower), "upper": list(box.upper),
                               "max_pairs": int(max_pairs), "inner_depth": int(inner_depth)})
    if path is not None and path.exists():
        meta, arrays = read_checkpoint(path, fingerprint)
        keeper = BoxStore.restore(len(root), meta["store"], arrays, problem=fingerprint.digest)
        T, Q, owner = arrays["pending"], arrays["joint_boxes"], arrays["owner"].astype(int)
        evaluated, seconds_before = int(meta["evaluated"]), float(meta["seconds"])
    else:
        keeper, _ = store_for(len(root), where, fingerprint.digest)
    spread = None if executor is None else runner_for(executor, step)
    rate = 0.0                                  # seconds per (task box, pair) of the last wave of chunks
    try:
        while len(T):
            pieces = max(1, math.ceil(len(Q) / chunk_pairs))
            if spread is not None:
                pieces = max(pieces, min(spread.slots, math.ceil(len(T) / MIN_CHUNK)))
            parts = list(_parts(T, Q, owner, pieces))
            # Waves of one chunk (here) or one per slot (executor); the budget is looked at before each wave,
            # and a wave expected to end past the time limit is not started: its task boxes stay pending,
            # with their joint boxes (a checkpoint goes on from them).
            width = 1 if spread is None else spread.slots
            results, left = [], []
            for w in range(0, len(parts), width):
                wave = parts[w:w + width]
                work = sum(len(t) + len(q) for t, q, _ in wave)
                reason = run.stop_reason(evaluated, ahead=rate * work)
                if reason:
                    left = parts[w:]
                    break
                start = time.perf_counter()
                if spread is None:
                    results.append(step(wave[0]))
                else:
                    results += [f.result() for f in [spread.submit(part) for part in wave]]
                rate = (time.perf_counter() - start) / max(1, work)
            children, pairs, owners, count = [], [], [], 0
            for i, b, o, c, q, w in [*results, *((t, None, None, t, q, w) for t, q, w in left)]:
                if b is not None:
                    keeper.add("inner", i)
                    keeper.add("boundary", b)
                    keeper.add("outer", o)
                owners.append(w + count)
                count += len(c)
                children.append(c)
                pairs.append(q)
            evaluated += len(T) - sum(len(t) for t, _, _ in left)
            T = np.concatenate(children) if children else T[:0]
            Q = np.concatenate(pairs) if pairs else Q[:0]
            owner = np.concatenate(owners) if owners else owner[:0]
            if left:
                break
            if run.showing:
                run.show(1.0 - box_measure(T) / box.measure, evaluated)
    except KeyboardInterrupt:
        reason = "interrupted"
    finally:
        if spread is not None:
            spread.close()
    if path is not None:
        write_checkpoint(path, {"fingerprint": fingerprint, "evaluated": evaluated,
                                "seconds": seconds_before + run.seconds}, T, keeper,
                         {"joint_boxes": Q, "owner": owner})
    keeper.flush()
    done = not len(T)
    return paving_of(keeper, variables=model.task_variables, box=box, constraints=(), delta=float(delta),
                     backend="numpy", size=size, pending=T, seconds=seconds_before + run.seconds, complete=done,
                     evaluated=evaluated, stop_reason="" if done else reason), None


def _cell_width(delta: float, size: str, m: int) -> float:
    """Width of cells whose size (diameter or width) is at most ``delta``."""
    return (delta / math.sqrt(m) if size == "diameter" else delta) * (1 - 1e-9)


CELL_CHUNK = 2_000                 # marked cells of the 3-D critical method proved between two looks at the budget


def _cells(robot, parameters, delta, size, run, *, executor):
    """The ``"critical"`` method on one grid of task cells (:func:`critical_paving`): a planar robot, or a
    spatial robot without a product or turned-section structure (cells in space).  Undecided cells are
    boundary boxes, or pending when a budget stopped the run."""
    model = _model(robot, parameters)
    grid, classes, evaluated, reason = critical_paving(model, _cell_width(delta, size, model.m),
                                                       budget=run.stop_reason,
                                                       cover=_cover_with(executor, robot, parameters, "model"),
                                                       show=run.show, chunk=None if model.m == 2 else CELL_CHUNK)
    extent = grid.extent
    box = Box(model.task_variables, tuple(extent[:, 0]), tuple(extent[:, 1]))
    undecided = grid.boxes(classes, UNDECIDED, merge=bool(reason))
    pending = undecided if reason else None
    boundary = [] if reason else [undecided]
    return box, [grid.boxes(classes, INSIDE)], boundary, [grid.boxes(classes, OUTSIDE)], pending, evaluated, reason


def _spatial(robot, parameters, delta, size, run, *, executor, where, problem):
    """The ``"critical"`` method for a spatial robot whose workspace is a product of images or a section
    turned by its first joint (module docstring): the section paved, then the task boxes classified from it by
    the driver (:func:`classify_task_boxes`, its boxes where ``where`` says; the section kept beside a
    checkpoint and the checkpoint named by ``problem``, :func:`reach_problem`).  Returns ``(paving, volume)``,
    or the tuple of a run stopped while the section was paved (every task box pending)."""
    model = _model(robot, parameters)
    plan = _section(robot, parameters)
    root = model.enclose(model.limits[None])[0]
    box = Box(model.task_variables, tuple(root[:, 0]), tuple(root[:, 1]))
    width = _cell_width(delta, size, 3)
    grid, classes, evaluated, reason = None, None, 0, ""
    volume, pieces, proved = None, None, None
    limited = limited_turn(plan, model)
    test = None
    # A resumed run takes the section its checkpoint was classified from (a time limit may refine it differently).
    problem = {**problem, "method": f"critical ({type(plan).__name__})", "section_boxes": run.section_boxes}
    named = Fingerprint({**problem, "section cell": SECTION_RATIO * width, "joint limits": model.limits})
    saved = _saved_section(where, named)
    if saved is not None:
        grid, classes, proved, pieces, evaluated = saved
    elif limited is not None:
        # A limited first joint of half a turn or more: cells proved at every polar angle (reach_turn).
        with section_bar(run.showing) as show:
            grid, classes, proved, evaluated, reason = pave_limited(limited, SECTION_RATIO * width, run, show=show,
                                                                    boxes=run.section_boxes)
    elif isinstance(plan, Turned) and plan.section.k > 2:
        # The section refines while its next step would end before the time limit less the time the (x, y, z)
        # boxes take, measured once on the first proved cells (a rehearsal: more cells decided, fewer boxes).
        reserve = [0.0]

        def rehearse(grid, classes):
            start = time.perf_counter()
            classify_task_boxes(TurnedTest(plan, grid, classes), box, delta, size)
            reserve[0] = SECTION_RESERVE * (time.perf_counter() - start)

        def seconds_left():
            return run.time_limit - run.seconds - reserve[0]

        def section_budget(count, ahead=0.0):
            late = run.time_limit is not None and run.seconds + SECTION_RESERVE * ahead + reserve[0] > run.time_limit
            spent = run.section_boxes is not None and count >= run.section_boxes
            return run.stop_reason(count) or ("section share" if late or spent else "")

        with section_bar(run.showing) as show:
            grid, classes, evaluated, reason, pieces = section_paving(
                plan.section, SECTION_RATIO * width, budget=section_budget, show=show,
                rehearse=rehearse if run.time_limit else None, depth=SECTION_DEPTH if run.time_limit else 1,
                seconds_left=seconds_left if run.time_limit else None)
        reason = "" if reason == "section share" else reason
    elif plan.section is not None:
        with section_bar(run.showing) as show:  # the section's bar, from the first generation of its cover
            grid, classes, evaluated, reason = critical_paving(plan.section, SECTION_RATIO * width,
                                                               budget=run.stop_reason, show=show,
                                                               cover=_cover_with(executor, robot, parameters,
                                                                                 "section"))
    if limited is not None:
        volume = limited_volume(limited, grid, classes, proved)
        test = LimitedTurnTest(limited, grid, classes, proved)
    if not reason and saved is None:
        _save_section(where, named, grid, classes, proved, pieces, evaluated)
    if isinstance(plan, Turned) and plan.full:
        volume = turned_volume(grid, classes, pieces)      # the solid of revolution of the section (Pappus)
    run.show(0.0, evaluated)
    if reason:
        return box, [], [], [], root[None].copy(), evaluated, reason, volume
    tests = {_Product: _ProductTest, _Revolved: _SectionTest, Turned: TurnedTest}
    test = test or tests[type(plan)](plan, grid, classes)
    # A checkpoint of the classification belongs to this robot, delta and section (a time-limited turned
    # section may refine differently on another run: its cells are part of what the checkpoint names).
    what = {**problem, "section cells": section_digest(grid, classes, None if limited is None else proved)}
    run.spent = evaluated
    paving = classify_task_boxes(test, box, delta, size, run, RunOn(max_memory=where.max_memory, store=where.store,
                                                                   resume=where.resume), describe=what)
    return paving, volume


def _section_file(where: RunOn) -> Path | None:
    """The file beside a checkpoint ``where.resume`` keeping the section its task boxes are classified from."""
    return None if where.resume is None else Path(f"{where.resume}.section.npz")


def _save_section(where: RunOn, named: Fingerprint, grid, classes, proved, pieces, evaluated: int) -> None:
    """Keep a paved section beside the checkpoint (written whole, then renamed: never half-written), with the
    fingerprint of its problem ``named``."""
    path = _section_file(where)
    if path is None or classes is None:
        return
    pieces = pieces or Pieces.none()
    part = path.with_name(path.name + ".part")
    with open(part, "wb") as out:
        np.savez(out, named=np.array(json.dumps(named.to_json())), box=grid.box, width=np.array(grid.width),
                 classes=classes,
                 proved=np.zeros(0, dtype=bool) if proved is None else proved, inner=pieces.inner,
                 outer=pieces.outer, evaluated=np.array(evaluated))
    os.replace(part, path)


def _saved_section(where: RunOn, named: Fingerprint):
    """``(grid, classes, proved, pieces, evaluated)`` of the section kept beside the checkpoint, or None (no
    checkpoint, or no file yet: the section is paved).  A file of another problem than ``named`` is refused,
    naming what differs, as a checkpoint is."""
    path = _section_file(where)
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
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
        raise InvalidParameterError(f"resume: {str(path)!r} beside the checkpoint is not a section kept by "
                                    f"reach ({exc})", parameter="resume") from None


def section_digest(grid, classes, proved=None) -> str:
    """What a checkpoint of the task boxes names of the section they were classified from: a digest of its
    cells' classes, the grid's box and (limited turns) the cells proved per direction; ``"none"`` without a
    section."""
    if classes is None:
        return "none"
    data = np.ascontiguousarray(classes).tobytes() + np.asarray(grid.box, dtype=float).tobytes()
    return hashlib.sha256(data + (b"" if proved is None else np.ascontiguousarray(proved).tobytes())).hexdigest()[:16]


@dataclass(frozen=True)
class _Classify:
    """The decider of :func:`classify_task_boxes`: the codes of a test's ``(is_in, is_out)`` masks; ``what``
    names its problem in a checkpoint's fingerprint (:func:`reach_problem` and the section's cells)."""

    test: Any
    what: Any = None

    def __call__(self, boxes: np.ndarray) -> np.ndarray:
        return codes_from_masks(*self.test(boxes))

    def describe(self) -> Any:
        return self.what or f"{type(self.test).__module__}.{type(self.test).__qualname__}"


def classify_task_boxes(test, box: Box, delta: float, size: str, stop: StopAt | RunBudget = StopAt(progress=False),
                        run: RunOn = RunOn(), *, describe: dict | None = None) -> Paving:
    """Pave the task box ``box`` with the driver (:func:`~workspace_sym.interval.driver.subdivide`), each box
    classified by ``test`` (``(is_in, is_out)`` masks from a paved section): proved boxes are inner/outer,
    undecided ones of size at most ``delta`` boundary.  No presplit: every box evaluated is a box of the
    breadth-first bisection from ``box``, so the counts are those of the classification alone.  ``stop``: a
    :class:`~workspace_sym.interval.driver.StopAt`, or ``reach``'s running budget (its clock, bar and the boxes
    the section took); ``run``: where the decided boxes go (``max_memory``, ``store``, ``resume``); ``describe``
    names the run's whole problem in a checkpoint (:func:`reach_problem`, the section's cells)."""
    return subdivide(_Classify(test, describe), box, delta=delta, size=size, stop=stop, run=run, label="reach",
                     presplit=0)


def check_root(root, delta: float, size: str, robot: DHRobot) -> None:
    """Refuse a task box ``root`` (the enclosure of the position over the limits) that is not finite, or a
    ``delta`` larger than it."""
    if not np.isfinite(root).all():
        raise InvalidParameterError("robot: the position has no finite enclosure over the joint limits",
                                    parameter="robot")
    extent = box_sizes(root[None], size)[0]
    if delta > extent:
        raise InvalidParameterError(f"delta must be at most the size of the workspace's enclosing box "
                                    f"({extent:.6g} {robot.units}); got {delta!r}", parameter="delta")


def resolve_method(robot: DHRobot, method: str = "auto", parameters=()) -> str:
    """The method :func:`reach` uses for ``robot``: ``"critical"`` or ``"pairs"``.

    ``"auto"`` is ``"critical"`` for every robot whose position moves in two or three coordinates: planar
    arms, products and sections turned by a revolute first joint first (:func:`_section`), the critical
    method in space (:func:`_cells`) for any other map into ``R^3`` and for a turned section that proves no
    inner box moved by at most ``CELLS_MAX_JOINTS`` joints (:func:`_on_cells` tells which); ``"pairs"`` for a
    position moving along one coordinate only."""
    if method not in METHODS:
        raise InvalidParameterError(f"method must be one of {', '.join(map(repr, METHODS))}; got {method!r}",
                                    parameter="method")
    parameters = tuple(parameters.items()) if isinstance(parameters, dict) else tuple(parameters)
    parameters = tuple(sorted(parameters, key=lambda item: str(item[0])))
    m = _model(robot, parameters).m
    fits = m in (2, 3)
    if method == "critical" and not fits:
        raise InvalidParameterError(f"method 'critical' needs a position moving in two or three coordinates (a "
                                    f"map into the plane or into space, whose critical set it covers); the "
                                    f"position of {robot.name} moves in {m}: use method='pairs'",
                                    parameter="method")
    return method if method != "auto" else ("critical" if fits else "pairs")


def _turn_without_inner(robot: DHRobot, parameters: tuple) -> bool:
    """``robot`` is a section turned by a first joint limited to less than a period (:class:`Turned`, not full)
    that proves no inner box: a section moved by two joints (``w`` sweeps a surface, no box of ``w`` lies in
    it) or a turn shorter than half a turn (no pair of directions covers the circle:
    :func:`~workspace_sym.reach_turn.limited_turn` is None)."""
    plan = _section(robot, parameters)
    return isinstance(plan, Turned) and not plan.full and limited_turn(plan, _model(robot, parameters)) is None


def _on_cells(robot: DHRobot, parameters: tuple, stored: bool = False) -> bool:
    """The critical method decides ``robot`` on one grid of task cells (:func:`_cells`): a planar arm, a
    spatial one without a product or turned-section structure, or one whose turned section proves no inner
    box (:func:`_turn_without_inner`) moved by at most ``CELLS_MAX_JOINTS`` joints (and by three at least: the
    image of fewer is a surface, with no inner box either way), unless its boxes are to be stored (``stored``: the
    section path, which stores them, is kept)."""
    model = _model(robot, parameters)
    if model.m == 2 or _section(robot, parameters) is None:
        return True
    return not stored and model.m <= model.k <= CELLS_MAX_JOINTS and _turn_without_inner(robot, parameters)


def _refuse_storage(robot: DHRobot, run: RunOn, m: int) -> None:
    """``max_memory``, ``store`` and ``resume`` apply where the task boxes are bisected (spatial arms with a
    section or a product, the pairs method); the critical method on one grid of cells (planar arms, spatial
    arms without structure) decides its cells in one pass."""
    space = "planar" if m == 2 else "3-D"
    refuse_storage(f"the {space} critical method on {robot.name}", run,
                   why="decides one grid of cells in one pass, in memory",
                   supported="method='pairs' on any arm, and the critical method on a spatial arm with a product "
                             "or a section turned by its first joint")


def reach_tuning() -> dict:
    """The tuning constants of the reach methods that change which boxes are proved (cell ratios, samples,
    depths, shares of a time limit, cover and pair budgets), read when a run starts: part of the fingerprint of
    every checkpoint and kept section (:func:`reach_problem`)."""
    names = {image: ("OUTSIDE_PAIRS", "MAX_COVER_BOXES", "OUTSIDE_MIN_CELLS"),
             reach_section: ("SECTION_PAIRS", "SECTION_SAMPLES", "SECTION_CHUNK", "BLOCKS_SHARE", "BLOCKS_WEIGHT",
                             "REACH_TOLERANCE", "SECTION_DEPTH"),
             reach_turn: ("DIRECTIONS", "DIRECTION_CHUNK", "DIRECTION_SAMPLES", "DIRECTION_DEPTH", "TIMED_DEPTH",
                          "DIRECTIONS_SHARE", "BLOCKS_END", "SHOULDER_PIECES")}
    own = {"SECTION_RATIO": SECTION_RATIO, "SECTION_RESERVE": SECTION_RESERVE, "ANGLE_PAD": ANGLE_PAD,
           "MIN_PAIRS": _MIN_PAIRS, "CELLS_MAX_JOINTS": CELLS_MAX_JOINTS, "CELL_CHUNK": CELL_CHUNK}
    return {**own, **{name: getattr(module, name) for module, group in names.items() for name in group}}


def reach_problem(robot: DHRobot, parameters, delta: float, size: str, **more) -> dict:
    """The whole problem of a reach run, by named fields, for the fingerprint of everything it stores or resumes
    (:class:`~workspace_sym.interval.fingerprint.Fingerprint`): the exact robot
    (:meth:`~workspace_sym.kinematics.DHRobot.problem_fields`: every DH entry, type, offset, limit, base, tool,
    parameter), the parameter values given, ``delta``, ``size``, the tuning (:func:`reach_tuning`) and ``more``
    (the constraint, the method and its options).

    >>> from workspace_sym.kinematics import DHJoint
    >>> arm = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=1, limits=(-1, 1))])
    >>> sorted(reach_problem(arm, (), 0.1, "diameter"))[:4]
    ['delta', 'parameters', 'robot base', 'robot chop_tol']
    """
    values = sorted(dict(parameters).items(), key=lambda item: str(item[0]))
    return {**robot.problem_fields(), "parameters": values, "delta": float(delta), "size": size,
            "tuning": reach_tuning(), **more}


@contextmanager
def _prepared_within(robot: DHRobot, time_limit: float | None, spent: float = 0.0):
    """The symbolic preparation of the reach model (kinematics, enclosures) within what is left of the time
    limit: past it, one :class:`SymbolicBudgetError` naming ``time_limit`` (no task box is known yet, so there
    is no paving to return: nothing was decided)."""
    if time_limit is None:
        yield
        return
    try:
        with symbolic_budget(max(time_limit - spent, 0.0), f"the symbolic model of {robot.name}"):
            yield
    except SymbolicBudgetError as exc:
        raise SymbolicBudgetError(f"time_limit: the symbolic model of {robot.name} (position, Jacobian, "
                                  f"enclosures) was not ready within the time limit of {time_limit:g} s, so no "
                                  "box was decided; allow more time", parameter="time_limit") from exc


@arith.nearest_rounding
def reach(robot: DHRobot, *, delta: float, size: str = "diameter", parameters: dict | None = None,
          method: str = "auto", max_pairs: int | None = None, inner_depth: int | None = None,
          stop: StopAt = StopAt(), run: RunOn = RunOn(), pose: Pose | None = None) -> Paving:
    """Pave the position workspace of a serial robot within its joint limits (module docstring).

    Parameters
    ----------
    robot : DHRobot
    delta : float
        Undecided task boxes whose size is at most ``delta`` become boundary boxes.
    size : {"diameter", "width"}
    parameters : values of the symbolic lengths (default: the robot's own).
    method : {"auto", "critical", "pairs"}
        ``"auto"`` (the only choice with a ``pose``, which picks its own
        method): ``"critical"`` for every robot whose position moves in two
        or three coordinates, with the structure it has first: a planar
        robot, a spatial robot whose coordinates are moved by disjoint sets
        of joints, a spatial robot turned by a revolute first joint (a rigid
        base transform allowed), and otherwise the critical set of the whole
        map into space on a 3-D grid of cells (falling back to ``"pairs"``
        when its cover is too large); ``"pairs"`` for a position moving
        along one coordinate.  A first joint limited to less than a period
        whose section in cylindrical coordinates proves no inner box (a
        section moved by two joints, or a turn below half a circle: base
        transforms, modified DH, varying lateral offsets) gives way to the
        3-D cells when at most ``CELLS_MAX_JOINTS`` (3) joints move the
        position, under ``"auto"`` and ``"critical"`` alike; with
        ``max_memory``, ``store`` or ``resume``, or a 3-D cover too large,
        such an arm keeps the section path (outer boxes only).
    inner_depth, max_pairs : of the ``"pairs"`` method: a box about
        to become a boundary box is also proved inner piece by piece, halving it
        along every edge up to ``inner_depth`` times; a task box stops refining its
        joint boxes once it would hold more than ``max_pairs`` times its share of
        the root box's measure (64 pairs at least).  Default (None): 2 and
        200,000; with a ``pose``, :func:`~workspace_sym.orientation.reach_pose`'s
        defaults, and given values are passed on to its pairs method.
    stop : :class:`~workspace_sym.interval.driver.StopAt`
        A budget (``max_boxes``, ``time_limit``): what is left undecided is returned as ``pending``.  A
        symbolic model not ready within ``time_limit`` raises
        :class:`~workspace_sym.errors.SymbolicBudgetError`.  ``section_boxes``: a budget of boxes (cells,
        pieces of cells and blocks evaluated) for the section of an arm turned by its first joint and moved by
        three joints or more (:func:`~workspace_sym.reach_section.section_paving`,
        :func:`~workspace_sym.reach_turn.pave_limited`), the same cells on every machine where a time limit
        is not: its stages stop where they stop at their shares of a time limit (a full turn: every stage
        once the budget is spent, the cells decided kept; a limited first joint: at the shares of
        ``pave_limited``), then the task boxes are classified from the cells decided (within ``max_boxes``).
        Other sections (one cover of their critical set) have no stages and ignore it.  ``progress``: a
        progress bar (:mod:`workspace_sym.progress`; default: on an interactive output once the run has lasted
        a second).
    run : :class:`~workspace_sym.interval.driver.RunOn`
        ``executor``: None (this process), a :class:`concurrent.futures.Executor`
        or a ``dask.distributed.Client``
        (:func:`workspace_sym.interval.executor.connect`): the critical covers
        (one task per face) or the generations of task boxes (``"pairs"``) run
        there; the result has the same boxes, counts and measures.  ``chunk``:
        about this many (joint box, task box) pairs go in one chunk of work of the
        ``"pairs"`` method (default ``CHUNK_PAIRS``).  ``max_memory``, ``store``
        and ``resume`` (as for :func:`~workspace_sym.interval.driver.subdivide`:
        decided boxes streamed to disk, the result a
        :class:`~workspace_sym.interval.boxes.StoredPaving`; a checkpoint to go on
        from) apply to the spatial arms of the ``"critical"`` method, whose task
        boxes go through the driver: the section (or plane factor) is paved
        again on a resumed run and must be the same (the checkpoint names its
        cells; a time-limited turned section may differ, and is refused); and
        to ``"pairs"``, whose checkpoint holds the task boxes left with their
        joint boxes (its frontier stays in memory).  The critical method on
        one grid of cells refuses them (one grid of cells, in memory): for a
        planar robot, and for a spatial robot without structure asked for
        ``method="critical"`` (under ``"auto"`` such a robot is then paved by
        ``"pairs"``).  With a ``pose``
        they apply to its ``"section"`` method as to the spatial critical
        method (:func:`~workspace_sym.orientation.reach_pose`).
    pose : :class:`Pose`, optional
        A constraint on the tool frame (:func:`workspace_sym.orientation.reach_pose`).
        Then inner boxes are proved reached by configurations within the limits
        satisfying the constraint exactly, outer boxes proved reached by none
        (docs/methods.md section 8); a ``method`` other than ``"auto"``, and
        ``run.executor`` / ``run.chunk``, are refused.

    Returns
    -------
    Paving
        Over ``x, y`` (planar robot) or ``x, y, z``; ``inner`` boxes are
        proved reachable, ``outer`` boxes proved unreachable.

    Examples
    --------
    >>> from workspace_sym.kinematics import DHJoint
    >>> arm = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=sp.Rational(1, 2))])
    >>> p = reach(arm, delta=0.1)
    >>> lo, hi = p.measure_bounds           # the annulus 1/2 <= r <= 3/2: area 2 pi
    >>> bool(lo <= 2 * np.pi <= hi)
    True
    """
    stored = run.max_memory is not None or run.store is not None or run.resume is not None
    if pose is not None:
        if not isinstance(pose, Pose):
            raise InvalidParameterError(f"pose must be a serial_workspace.Pose; got {type(pose).__name__}",
                                        parameter="pose")
        if method != "auto":
            raise InvalidParameterError(f"method: reach with a tool constraint chooses its own method (the "
                                        f"section where the first joint turns it, pairs otherwise); got "
                                        f"{method!r}, expected 'auto'", parameter="method")
        if stop.section_boxes is not None:
            raise InvalidParameterError(f"section_boxes: reach with a tool constraint paves its own section (no "
                                        f"budget of boxes for it); got {stop.section_boxes!r}, expected None",
                                        parameter="section_boxes")
        from .orientation import reach_pose  # one way: orientation builds on this module

        given = {name: value for name, value in (("max_pairs", max_pairs), ("inner_depth", inner_depth))
                 if value is not None}
        return reach_pose(robot, delta=delta, approach=pose.approach, cone=pose.cone, every=pose.every,
                          orientation=pose.orientation, rpy=pose.rpy, size=size, parameters=parameters,
                          max_boxes=stop.max_boxes, time_limit=stop.time_limit, progress=stop.progress,
                          run=run, **given)
    max_pairs = 200_000 if max_pairs is None else max_pairs
    inner_depth = 2 if inner_depth is None else inner_depth
    chunk_pairs = CHUNK_PAIRS if run.chunk is None else run.chunk
    executor = run.executor
    check_delta(delta)
    if size not in ("diameter", "width"):
        raise InvalidParameterError(f"size must be one of 'diameter', 'width'; got {size!r}", parameter="size")
    for name, value, least in (("inner_depth", inner_depth, 0),):
        if not isinstance(value, int) or isinstance(value, bool) or value < least:
            raise InvalidParameterError(f"{name} must be a whole number, {least} or more; got {value!r}",
                                        parameter=name)
    values = tuple(sorted((parameters or {}).items(), key=lambda item: str(item[0])))  # hashable
    # The time limit bounds the whole call: the clock starts before the symbolic preparation of the model.
    time_limit = stop.time_limit
    budget = RunBudget(stop, "reach")
    model = root = None
    kind = method
    try:
        with _prepared_within(robot, time_limit, budget.seconds):
            model = _model(robot, values)
            root = model.enclose(model.limits[None])[0]
        check_root(root, delta, size, robot)
        with _prepared_within(robot, time_limit, budget.seconds):
            kind = resolve_method(robot, method, values)
            cells = kind == "critical" and _on_cells(robot, values, stored)
            if cells and model.m == 3 and stored and method == "auto":
                kind, cells = "pairs", False   # the 3-D grid is decided in memory; the pairs method stores its boxes
            if cells and model.m == 3:
                _ = model.minors           # the 3 x 3 minors of the cover: symbolic, within the time limit
        if stored and cells:
            _refuse_storage(robot, run, model.m)
        problem = reach_problem(robot, values, delta, size)
        result: Any = None                  # the driver's (paving, volume), or a method's tuple of boxes
        if kind == "critical":
            try:
                result = (_cells(robot, values, delta, size, budget, executor=executor) if cells else
                          _spatial(robot, values, delta, size, budget, executor=executor, where=run,
                                   problem=problem))
            except CoverTooLarge as error:
                too_large: CoverTooLarge | None = error
                if cells and model.m == 3 and _section(robot, values) is not None:
                    # a turned section proving no inner box: its own path (outer boxes), as before the 3-D cells
                    try:
                        cells, too_large = False, None
                        result = _spatial(robot, values, delta, size, budget, executor=executor, where=run,
                                          problem=problem)
                    except CoverTooLarge as again:
                        too_large = again
                if too_large is not None and method == "critical":
                    raise InvalidParameterError(f"method 'critical': {too_large} (joints with parallel axes?); use "
                                                "method='pairs'", parameter="method") from None
        if result is None:
            kind = "pairs"                      # also when the critical cover was too large (auto)
            result = _pairs(robot, values, delta, size, budget, max_pairs=max_pairs, inner_depth=inner_depth,
                            executor=executor, chunk_pairs=chunk_pairs, where=run, problem=problem)
    except KeyboardInterrupt:
        if model is None or root is None:
            raise
        whole = Box(model.task_variables, tuple(root[:, 0]), tuple(root[:, 1]))
        result = whole, [], [], [], root[None], 0, "interrupted"
    finally:
        budget.close()
    assert model is not None                    # set before anything that returns a result
    if isinstance(result[0], Paving):           # the task boxes went through the driver
        paving, volume = result
        emptied = {k: np.empty((0, len(model.task_variables), 2)) for k in ("inner", "boundary", "outer")} \
            if isinstance(paving, StoredPaving) else {}  # (replace() would read the stored boxes back)
        return dataclasses.replace(paving, **emptied, evaluated=budget.spent + paving.evaluated, units=robot.units,
                                   method=kind, volume_bounds=volume)
    box, inner, boundary, outer, pending, evaluated, reason, *volume = result
    if pending is None or not len(pending):
        reason = ""                             # a budget that ran out after the last box: nothing is pending
    m = len(model.task_variables)
    empty = np.empty((0, m, 2))

    def stack(parts):
        parts = [p for p in parts if len(p)]
        return np.concatenate(parts) if parts else empty

    return Paving(variables=model.task_variables, box=box, constraints=(), delta=float(delta), backend="numpy",
                  size=size, inner=stack(inner), boundary=stack(boundary), outer=stack(outer),
                  pending=empty if pending is None else pending, seconds=budget.seconds, complete=not reason,
                  evaluated=evaluated, stop_reason=reason, units=robot.units, method=kind,
                  volume_bounds=volume[0] if volume else None)
