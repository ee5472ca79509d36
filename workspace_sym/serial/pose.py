"""Certified orientation workspaces of a serial robot: where the tool can be *and point where it must*.

``reach(robot, pose=Pose(...))`` (the pose plans of :mod:`workspace_sym.serial.plans`)
paves the space of tool positions ``(x, y, z)`` under one of two constraints
on the tool frame (its rotation ``R(q)``, the tool transform included; the
approach axis ``a(q)`` is its third column):

* **cone** (``approach=d, cone=c``): ``a(q) . d >= |d| cos c`` (the approach
  axis within ``c`` degrees of ``d``; ``c = 0`` is the exact direction);
* **orientation** (``orientation=R`` or ``rpy=(r, p, y)``): ``R(q) = R``.

It returns the same three kinds of boxes as
:func:`workspace_sym.serial.api.reach` without a pose:

* **outer**: no configuration within the joint limits that satisfies the
  constraint puts the tool point in the box;
* **inner**: every point of the box is the tool point of some configuration
  within the limits that satisfies the constraint;
* **boundary**: neither is proved and the box is at most ``delta``.

The method is the ``"pairs"`` method of ``reach`` with the constraint as a
filter (docs/methods.md section 8).  The joints are split into *arm* joints,
which move the position, and *wrist* joints, which move only the constrained
quantity (``a(q) . d``, or ``R(q)``).  Each task box carries arm boxes
covering every *admissible* configuration whose position may lie in it; an
arm box is dropped when its position enclosure misses the task box, or when
the constraint is proved violated over it times every box of a cover of the
wrist limits (cone: the upper bound of ``a . d`` below the lower bound of
``|d| cos c``, and for ``c = 0`` also ``a . e1`` or ``a . e2`` excluding 0;
orientation: some entry of ``R(q)`` whose enclosure misses that entry of
``R``).  A task box left without arm boxes is outer.  An arm box proved
admissible for every arm value (a wrist value satisfying the cone over the
whole box; for the exact direction, a parametric Krawczyk test on the wrist)
keeps that status in its halves.

A constant orientation is reduced to the exact direction ``R z`` when the
last joint spins the tool about its approach axis through a full turn (the
Puma, the UR5, a SCARA); a cone about the vertical on a robot turned by its
first joint (``reach``'s section structure) is paved on the section
``(u, v)`` and turned by the first joint: ``method`` is then ``"section"``,
and the volume bracket is also proved from the section's cells by Pappus's
theorem (:func:`section_volume_bracket`, kept as the paving's ``volume_bounds``).

Inner proofs: the Krawczyk test of
:class:`~workspace_sym.interval.image.ImageMap` on a square system around a
Newton solution for the box centre, with a side condition proved over the
Krawczyk box ``U`` (:meth:`ImageMap.admissible`):

* cone with ``c > 0``: the position equations ``p(q) = y`` in three joints
  (the others fixed at the Newton solution), and ``a . d >= |d| cos c`` proved
  over ``U``: every point of the box is reached by a configuration in ``U``,
  all of which satisfy the constraint;
* cone with ``c = 0``: ``p(q) = y``, ``a . e1 = a . e2 = 0`` (``e1, e2`` an
  exact orthogonal basis of ``d``'s normal plane) in as many joints, and
  ``a . d > 0`` over ``U`` (so ``a`` is ``d / |d|``, not its opposite);
* orientation: ``p(q) = y`` and the skew part of ``R^T R(q)`` zero in six
  joints, and ``trace(R^T R(q)) > -1`` over ``U``: ``R^T R(q)`` is then a
  symmetric rotation other than a half turn, the identity, so ``R(q) = R``.

So an inner box is proved with the constraint *exactly* (no tolerance):
the solution the Krawczyk operator proves lies in ``U``, inside the limits.

A cone on an arm with a roll-pitch wrist (two joints moving the approach
and not the position, the first turning fully, ``a . z = cos(q_k + phi)``
about its axis ``z``) is paved as a cone on ``z`` over the arm joints alone
(:func:`wrist_reduction`, docs/methods.md section 8).  With a tool point at a
length ``L`` along the approach from such a wrist (a half turn of roll suffices
there, :func:`wrist_cap`) on an arm turned by a limited first joint (the LBR
iiwa), a cone about the vertical is paved through the wrist centre: its section
with the roll axis proved within ``psi - t`` of ``d``, the tool's section derived
from it (:class:`WristCentre`, :func:`~workspace_sym.serial.turn.tool_section`);
so is a constant orientation whose approach is vertical, when the last joint
spins the tool about its approach through half a turn or more: the direction
proofs then hold on sectors of the first joint's turn where one of the wrist's
two solutions is within the limits (:class:`SpinCondition`,
:class:`~workspace_sym.serial.turn.SpinSectors`).
For a cone through a tool point along the approach, outer proofs also drop
pairs on the enclosure of the admissible positions (:class:`_OffsetEnclosure`).

``every=True`` (positions from which every direction of the cone is
reachable, the dextrous workspace of Kumar and Waldron) is proved with a
roll-pitch wrist (inner: one arm configuration whose wrist reaches the whole
cone; outer: ``d`` itself unreachable) and raises otherwise for ``c > 0``; for
``c = 0`` it is the same as ``every=False``.

The target rotation is made exact: ``rpy`` angles are read like the angles
of a DH file (numbers are degrees, ``pi`` makes radians); a matrix must be a
rotation within ``ORTHOGONAL_TOL``; it is read as its roll, pitch and yaw,
each snapped to a multiple of ``pi/360`` within that tolerance
(:func:`workspace_sym.snap.snap_angle`) or else taken as the exact binary
value of its float, and the workspace is that of the rotation those angles
define (within ``ORTHOGONAL_TOL`` of the matrix given; ``constraint.rotation``).
Every verdict rests on outward-rounded interval arithmetic (numpy engine).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
import sympy as sp

from ..errors import InvalidParameterError
from ..expressions import parse_angle
from ..interval import arith
from ..interval.boxes import box_sizes, halves
from ..interval.compiler import compile_batch, compile_expr
from ..interval.graph import exact_constants, numpy_constant
from ..interval.image import CellGrid, ImageMap, batch_enclosures, dot, meets
from ..interval.store import BoxStore, ExactSum
from ..interval.verdict import INSIDE as INNER
from ..interval.verdict import OUTSIDE as OUTER
from ..interval.verdict import UNDECIDED
from ..kinematics import DHRobot
from ..numbers import fmt
from ..snap import snap_angle
from ..transforms import rot_x, rot_y, rot_z, translation
from .angles import ANGLE_PAD
from .model import TASK, joint_range, reach_model
from .pairs import caps, pave_pairs, prove_in_pieces, split_pairs
from .ring import WristRing, wrist_ring
from .section import (
    RadialMap,
    SquareMap,
    Turned,
    first_frame,
    section_bar,
    squared_enclosures,
    to_first_frame,
    turned,
)
from .structure import Revolved, revolved, structure_of
from .tuning import DEFAULT, Tuning
from .turn import LimitedTurn, constrained_turn, limited_turn

__all__ = ["PoseConstraint", "approach_constraint", "orientation_constraint", "constraint_from", "PoseModel",
           "PoseStructure", "pose_structure", "wrist_reduction", "PoseStep", "section_classes",
           "section_volume_bracket", "SquaredTest", "squared_volume_bracket",
           "ORTHOGONAL_TOL"]

ORTHOGONAL_TOL = 1e-9            # a matrix farther than this from a rotation (entrywise) is refused


def _exact(value) -> sp.Expr:
    """``value`` (a number) with its floats replaced by the rationals they are."""
    return exact_constants(sp.sympify(value))


def _real(value, parameter: str, what: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"{parameter} must be {what}; got {value!r}", parameter=parameter) from None
    if not math.isfinite(number):
        raise InvalidParameterError(f"{parameter} must be {what}; got {value!r}", parameter=parameter)
    return number


def _rotation(roll, pitch, yaw) -> sp.Matrix:
    """``Rz(yaw) Ry(pitch) Rx(roll)`` (the URDF convention), exact."""
    return sp.ImmutableMatrix((rot_z(yaw) * rot_y(pitch) * rot_x(roll))[:3, :3])


@dataclass(frozen=True)
class PoseConstraint:
    """A constraint on the tool frame: ``kind`` is ``"cone"`` (``direction`` an exact 3-vector, ``cone`` the
    exact half-angle in radians, ``degrees`` as given, ``every``) or ``"orientation"`` (``rotation`` an exact
    rotation matrix, ``rpy`` its exact roll, pitch, yaw in radians).

    Parameters
    ----------
    kind : {"cone", "orientation"}
        Which constraint.
    direction : tuple
        The cone's axis: three exact numbers, not all zero.
    cone : sympy.Expr
        The cone's half-angle in radians, exact (0: the exact direction).
    degrees : float
        The half-angle as given, in degrees.
    every : bool
        Every direction of the cone, rather than some.
    rotation : sympy.Matrix, optional
        The exact rotation of an orientation constraint.
    rpy : tuple
        Its exact roll, pitch, yaw in radians.
    """

    kind: str
    direction: tuple = ()
    cone: sp.Expr = sp.S.Zero
    degrees: float = 0.0
    every: bool = False
    rotation: sp.Matrix | None = None
    rpy: tuple = ()

    def to_dict(self) -> dict:
        """The constraint for a JSON answer (floats; the exact values as text).

        Returns
        -------
        dict
            A cone: ``approach``, ``cone_deg``, ``every``.  An orientation: ``orientation`` (the matrix),
            ``rpy_deg``, ``rpy_exact`` (SymPy text).
        """
        if self.kind == "cone":
            return {"approach": [float(c) for c in self.direction], "cone_deg": self.degrees, "every": self.every}
        return {"orientation": [[float(self.matrix[i, j]) for j in range(3)] for i in range(3)],
                "rpy_deg": [float(a * 180 / sp.pi) for a in self.rpy],
                "rpy_exact": [sp.sstr(a) for a in self.rpy]}

    @property
    def matrix(self) -> sp.Matrix:
        """The exact rotation of an orientation constraint.

        Returns
        -------
        sympy.Matrix
            ``rotation``.

        Raises
        ------
        ValueError
            The constraint has no rotation (a cone).
        """
        if self.rotation is None:
            raise ValueError(f"{self} has no rotation matrix")
        return self.rotation

    def words(self) -> str:
        """The constraint in words, as a report or a notebook states it.

        Returns
        -------
        str
            One sentence without its full stop.

        Examples
        --------
        >>> approach_constraint((0, 0, -1), 20, every=True).words()
        "the tool's approach axis (z of the tool frame) can reach every direction within 20 degrees of (0, 0, -1)"
        """
        if self.kind == "cone":
            what = ("the tool's approach axis (z of the tool frame) can reach every direction within "
                    if self.every else "the tool's approach axis (z of the tool frame) can lie within ")
            direction = ", ".join(fmt(float(c), 6, "g") for c in self.direction)
            return what + f"{fmt(self.degrees, 6, 'g')} degrees of ({direction})"
        return ("the tool frame can be exactly the rotation of roll, pitch, yaw ("
                + ", ".join(fmt(float(a * 180 / sp.pi), 6, "g") for a in self.rpy) + ") degrees")

    def __str__(self) -> str:
        if self.kind == "cone":
            d = ", ".join(f"{float(c):g}" for c in self.direction)
            return f"approach within {self.degrees:g} deg of ({d})" + (" (every direction)" if self.every else "")
        return "orientation rpy = (" + ", ".join(f"{float(a * 180 / sp.pi):g}" for a in self.rpy) + ") deg"


def approach_constraint(approach, cone, every: bool = False) -> PoseConstraint:
    """The cone constraint, checked: ``approach`` three finite numbers not all zero, ``cone`` in [0, 180]
    degrees.

    Parameters
    ----------
    approach : sequence of three numbers
        The cone's axis (any length but zero).
    cone : float
        The half-angle in degrees, 0 for the exact direction.
    every : bool
        Every direction of the cone rather than some.

    Returns
    -------
    PoseConstraint
        A cone, its numbers made exact (a float is the rational it is).

    Raises
    ------
    InvalidParameterError
        ``approach`` not three finite numbers or all zero, ``cone`` missing or outside [0, 180], ``every`` not
        a bool.

    Examples
    --------
    >>> str(approach_constraint((0, 0, -2), 20))
    'approach within 20 deg of (0, 0, -2)'
    >>> approach_constraint((0, 0, 0), 20)
    Traceback (most recent call last):
    ...
    workspace_sym.errors.InvalidParameterError: approach must be a non-zero vector (ax, ay, az); got (0, 0, 0)
    """
    try:
        values = tuple(approach)
    except TypeError:
        values = ()
    if len(values) != 3:
        raise InvalidParameterError(f"approach must be three numbers (ax, ay, az); got {approach!r}",
                                    parameter="approach")
    numbers = [_real(v, "approach", "three finite numbers (ax, ay, az)") for v in values]
    if not any(numbers):
        raise InvalidParameterError(f"approach must be a non-zero vector (ax, ay, az); got {approach!r}",
                                    parameter="approach")
    if cone is None:
        raise InvalidParameterError("cone must be given with approach (degrees, 0 for the exact direction); got "
                                    "None", parameter="cone")
    degrees = _real(cone, "cone", "an angle in degrees between 0 and 180")
    if not 0 <= degrees <= 180:
        raise InvalidParameterError(f"cone must be an angle in degrees between 0 and 180; got {cone!r}",
                                    parameter="cone")
    if not isinstance(every, bool):
        raise InvalidParameterError(f"every must be True or False; got {every!r}", parameter="every")
    direction = tuple(_exact(v) for v in numbers)
    return PoseConstraint("cone", direction, _exact(degrees) * sp.pi / 180, degrees, every)


def orientation_constraint(orientation=None, rpy=None) -> PoseConstraint:
    """The constant-orientation constraint from a 3 x 3 rotation matrix or from roll, pitch, yaw angles
    (``Rz(yaw) Ry(pitch) Rx(roll)``; numbers are degrees, text with ``pi`` radians), made exact (module
    docstring).

    Parameters
    ----------
    orientation : 3 x 3 array_like, optional
        A rotation matrix (within ``ORTHOGONAL_TOL`` entrywise).
    rpy : sequence of three angles, optional
        Roll, pitch, yaw: numbers are degrees, and so is text without ``pi`` (``"90"``); text with ``pi`` is
        radians (``"pi/2"``).  Exactly one of ``orientation`` and ``rpy`` is given.

    Returns
    -------
    PoseConstraint
        An orientation, its rotation exact.

    Raises
    ------
    InvalidParameterError
        Both or neither given, ``rpy`` not three finite numeric angles, ``orientation`` not a 3 x 3 rotation
        matrix (or none of the roll, pitch, yaw read from it reproduces it).
    ExpressionError
        An angle given as text that the expression reader refuses.

    Examples
    --------
    >>> c = orientation_constraint(rpy=(180, 0, 0))
    >>> c.rotation
    Matrix([
    [1,  0,  0],
    [0, -1,  0],
    [0,  0, -1]])
    >>> orientation_constraint([[1, 0, 0], [0, 1, 0], [0, 0, 2]])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    workspace_sym.errors.InvalidParameterError: orientation must be a rotation matrix ...
    """
    if (orientation is None) == (rpy is None):
        raise InvalidParameterError("give one of orientation (a 3 x 3 rotation matrix) and rpy (roll, pitch, yaw); "
                                    f"got orientation={orientation!r}, rpy={rpy!r}", parameter="orientation")
    if rpy is not None:
        try:
            values = tuple(rpy)
        except TypeError:
            values = ()
        if len(values) != 3:
            raise InvalidParameterError(f"rpy must be three angles (roll, pitch, yaw); got {rpy!r}", parameter="rpy")
        angles = []
        for v in values:
            angle = parse_angle(v if isinstance(v, str) else _exact(_real(v, "rpy", "three finite angles")),
                                "rpy", degrees=True)
            if angle.free_symbols or not angle.is_real:
                raise InvalidParameterError(f"rpy must be three numeric angles; got {rpy!r}", parameter="rpy")
            angles.append(angle)
        return PoseConstraint("orientation", rotation=_rotation(*angles), rpy=tuple(angles))
    expected = "a rotation matrix (3 x 3, orthonormal rows, determinant +1, within 1e-09)"
    try:
        M = np.array(orientation, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"orientation must be {expected}; got {orientation!r}",
                                    parameter="orientation") from None
    if M.shape != (3, 3) or not np.isfinite(M).all():
        raise InvalidParameterError(f"orientation must be {expected}; got {orientation!r}", parameter="orientation")
    error = np.abs(M.T @ M - np.eye(3)).max()
    if error > ORTHOGONAL_TOL or np.linalg.det(M) < 0:
        why = f"M^T M - I is {error:.3g} away from zero" if error > ORTHOGONAL_TOL else "its determinant is -1"
        raise InvalidParameterError(f"orientation must be {expected}; got {M.tolist()} ({why})",
                                    parameter="orientation")
    # Roll, pitch, yaw of Rz(y) Ry(p) Rx(r), each snapped to a multiple of pi/360 or kept as its float.
    pitch = math.atan2(-M[2, 0], math.hypot(M[0, 0], M[1, 0]))
    if math.hypot(M[0, 0], M[1, 0]) > 1e-6:
        roll, yaw = math.atan2(M[2, 1], M[2, 2]), math.atan2(M[1, 0], M[0, 0])
    else:                                   # gimbal lock: yaw = 0
        roll, yaw = math.atan2(-M[1, 2], M[1, 1]), 0.0
    snapped = tuple(snap_angle(a, ORTHOGONAL_TOL) or sp.Rational(a) for a in (roll, pitch, yaw))
    R = _rotation(*snapped)
    if np.abs(np.array(R.evalf(20).tolist(), dtype=float) - M).max() > ORTHOGONAL_TOL:
        raise InvalidParameterError(f"orientation must be {expected}; got {M.tolist()} (no roll, pitch, yaw "
                                    "reproduces it)", parameter="orientation")
    return PoseConstraint("orientation", rotation=R, rpy=snapped)


def _orthonormal_pair(d):
    """Two exact vectors spanning the plane normal to ``d`` (orthogonal to it and to each other)."""
    d = sp.Matrix(d)
    k = min(range(3), key=lambda i: abs(float(d[i])))
    e = sp.Matrix([1 if i == k else 0 for i in range(3)])
    e1 = e - d * (d.dot(e) / d.dot(d))
    return e1, d.cross(e1)


class _ConstrainedMap(ImageMap):
    """The square system of the inner test (module docstring): ``p(q) = y`` and ``g(q) = 0``, with the side
    condition ``s(q) > bound`` (``>=`` when ``closed``) proved over the Krawczyk box."""

    def __init__(self, position, equations, side, bound, closed, variables, limits, periodic, aim=None):
        # An equation that is identically zero holds everywhere: it is not part of the square system.
        equations = [e for e in equations if sp.simplify(e) != 0]
        super().__init__(list(position) + list(equations), variables, limits, periodic)
        self.extra = len(equations)
        self._side = compile_expr(side, self.variables)
        self.bound, self.closed = bound, closed
        self.aim = aim                      # a map whose Newton solutions are tried first (cone: a = d)

    def side(self, Q: np.ndarray):
        X = [(Q[:, j, 0], Q[:, j, 1]) for j in range(self.k)]
        with np.errstate(all="ignore"):
            lo, hi = self._side(X)
        return np.broadcast_to(lo, (len(Q),)), np.broadcast_to(hi, (len(Q),))

    def admissible(self, box):
        lo, _ = self.side(box)
        return (lo >= self.bound) if self.closed else (lo > self.bound)

    def prove_inside(self, T, seeds, *, newton: int = 8):
        """Inner test of position boxes ``T`` (``(N, 3, 2)``): the equations ``g = 0`` get the target 0."""
        if self.k < self.m:
            return np.zeros(len(T), dtype=bool)
        padded = np.concatenate([T, np.zeros((len(T), self.extra, 2))], axis=1)
        centre = 0.5 * (padded[:, :, 0] + padded[:, :, 1])
        proved = np.zeros(len(T), dtype=bool)
        if self.aim is not None:
            aim_centre = np.concatenate([centre, np.zeros((len(T), self.aim.m - self.m))], axis=1)
            q, ok = self.aim.newton(aim_centre, seeds, steps=newton)
            rows = np.nonzero(ok)[0]
            proved[rows] = self.prove_inside_at(padded[rows], q[rows])
        rows = np.nonzero(~proved)[0]
        if len(rows):
            q, _ = self.newton(centre[rows], seeds[rows], steps=newton)
            proved[rows] = self.prove_inside_at(padded[rows], q)
        return proved


class _WristSolver:
    """A parametric Krawczyk test on the wrist: for an arm box ``A``, a wrist box ``W`` around a Newton
    solution ``w0`` for the arm box's centre and a float matrix ``C``, if
    ``K = w0 - C g(A, w0) + (I - C J_w(A, W)) (W - w0)`` lies in the interior of ``W`` (outward-rounded), then
    for every arm value in ``A`` the equations ``g(arm, w) = 0`` have a solution ``w`` in ``W`` (the Krawczyk
    operator of ``g(arm, .)`` maps ``W`` into its interior); with ``W`` within the wrist limits and the side
    condition ``s > 0`` proved over ``A x W``, the arm box is admissible everywhere."""

    def __init__(self, equations, side, variables, ka):
        self.ka = ka
        wrist = variables[ka:]
        self.g = [compile_expr(e, variables) for e in equations]
        self.dg = [[compile_expr(sp.diff(e, w), variables) for w in wrist] for e in equations]
        self.side = compile_expr(side, variables)
        self.side_float = sp.lambdify([variables], side, modules="numpy")
        self.g_float = sp.lambdify([variables], equations, modules="numpy")
        self.dg_float = sp.lambdify([variables], [[sp.diff(e, w) for w in wrist] for e in equations],
                                    modules="numpy")

    def _floats(self, f, q, shape):
        with np.errstate(all="ignore"):
            out = f(q.T)
        return np.moveaxis(np.array([[np.broadcast_to(np.asarray(v, dtype=float), (len(q),)) for v in row]
                                     for row in out] if len(shape) == 2 else
                                    [np.broadcast_to(np.asarray(v, dtype=float), (len(q),)) for v in out]), -1, 0)

    @staticmethod
    def _eval(f, Q):
        X = [(Q[:, j, 0], Q[:, j, 1]) for j in range(Q.shape[1])]
        with np.errstate(all="ignore"):
            lo, hi = f(X)
        return np.broadcast_to(lo, (len(Q),)), np.broadcast_to(hi, (len(Q),))

    def solves(self, arm, w, wrist: ImageMap) -> np.ndarray:
        """Mask of the float wrist values ``w`` solving the equations at ``arm`` to 1e-9, within the limits,
        with the side condition (no proof: it only spares the search for a proof of violation)."""
        q = np.concatenate([arm, w], axis=1)
        g = self._floats(self.g_float, q, (wrist.k,))
        with np.errstate(all="ignore"):
            side = np.broadcast_to(np.asarray(self.side_float(q.T), dtype=float), (len(q),))
        within = ((w >= wrist.inner_limits[:, 0]) & (w <= wrist.inner_limits[:, 1])).all(axis=1)
        return within & (np.abs(g).max(axis=1) <= 1e-9) & (side > 0)

    def prove(self, A, w, wrist: ImageMap, *, steps: int = 6):
        """Mask of the arm boxes ``A`` proved admissible everywhere, and the wrist value of each."""
        n, k = len(A), wrist.k
        centre = 0.5 * (A[:, :, 0] + A[:, :, 1])
        for _ in range(steps):                           # Newton on the wrist at the arm box's centre
            q = np.concatenate([centre, w], axis=1)
            g = self._floats(self.g_float, q, (k,))
            J = self._floats(self.dg_float, q, (k, k))
            with np.errstate(all="ignore"):
                try:
                    step = np.linalg.solve(J + 1e-12 * np.eye(k), g[:, :, None])[:, :, 0]
                except np.linalg.LinAlgError:
                    break
                w = np.where(np.isfinite(step), w - step, w)
        w = np.clip(w, wrist.inner_limits[:, 0], wrist.inner_limits[:, 1])
        q = np.concatenate([centre, w], axis=1)
        J = self._floats(self.dg_float, q, (k, k))
        with np.errstate(all="ignore"):
            det = np.linalg.det(np.where(np.isfinite(J), J, 0.0))
        singular = ~(np.abs(det) > 1e-12) | ~np.isfinite(J).all(axis=(1, 2))
        J[singular] = np.eye(k)
        C = np.linalg.inv(J)
        usable = ~singular & np.isfinite(C).all(axis=(1, 2)) & np.isfinite(w).all(axis=1)
        C = np.where(usable[:, None, None], C, 0.0)
        point = np.concatenate([A, np.repeat(w[:, :, None], 2, axis=2)], axis=1)
        g0 = [self._eval(f, point) for f in self.g]
        # W: a box around w0 of the size by which the arm box moves the solution, widened.
        spread = np.stack([np.maximum(np.abs(lo), np.abs(hi)) for lo, hi in g0], axis=1)
        radius = 2.0 * np.einsum("nij,nj->ni", np.abs(C), spread) + 1e-12
        proved = np.zeros(n, dtype=bool)
        for _ in range(3):
            W = np.stack([w - radius, w + radius], axis=2)
            within = ((W[:, :, 0] >= wrist.inner_limits[:, 0]) & (W[:, :, 1] <= wrist.inner_limits[:, 1])
                      | wrist.periodic).all(axis=1)
            full = np.concatenate([A, W], axis=1)
            JW = [[self._eval(f, full) for f in row] for row in self.dg]
            K = np.empty((n, k, 2))
            for a in range(k):
                c = [(C[:, a, i], C[:, a, i]) for i in range(k)]
                acc = arith.neg(dot(c, g0))
                for b in range(k):
                    cj = dot(c, [JW[i][b] for i in range(k)])
                    identity = (1.0, 1.0) if a == b else (0.0, 0.0)
                    offset = arith.sub((W[:, b, 0], W[:, b, 1]), (w[:, b], w[:, b]))
                    acc = arith.add(acc, arith.mul(arith.sub(identity, cj), offset))
                K[:, a, 0], K[:, a, 1] = arith.add(acc, (w[:, a], w[:, a]))
            side_lo, _ = self._eval(self.side, full)
            inside = (K[:, :, 0] > W[:, :, 0]).all(axis=1) & (K[:, :, 1] < W[:, :, 1]).all(axis=1)
            proved |= usable & within & inside & (side_lo > 0)
            grow = np.maximum(np.abs(K[:, :, 0] - w), np.abs(K[:, :, 1] - w))
            radius = np.where(np.isfinite(grow), np.maximum(radius, 1.2 * grow), radius)
        return proved, w


class _OffsetEnclosure:
    """Enclosures of the position over the configurations that satisfy a cone, for a tool point at a constant
    length ``L`` along the approach from a point ``o`` that the last joints do not move (``p = o + L a``: a flange
    or tool offset along the approach, the KR16's 0.158 m).

    For any constant ``L`` and any rotation ``M``, ``w = (w - L M a) + L M a`` is an identity; on a configuration
    whose approach lies in the cone, ``M a`` lies in the cap of unit vectors within the cone's half-angle of
    ``M d``, hence in the cap's bounding box ``C``.  So ``enclosure(w - L M a) + L (enclosure(M a) & C)`` encloses
    the position of every admissible configuration of a joint box: intersected with the plain enclosure, it
    drops (arm box, task box) pairs sooner, which is only ever used to drop a pair (an outer proof), never to
    prove a box inner.  ``L`` and ``M`` only decide how tight it is: ``M`` is the candidate (the identity, or a
    base's rotation transposed, which takes the approach into the frame of ``w``) for which ``w - L M a`` expands
    free of the most joints.

    Parameters
    ----------
    w : sequence of sympy.Expr
        The three coordinates the task coordinates are built from (``(u, c, v)`` of a squared section, or
        ``(x, y, z)``).
    approach : sequence of sympy.Expr
        The approach axis, in the same variables.
    direction : sequence of sympy.Expr
        The cone's axis ``d``.
    cone : sympy.Expr
        The half-angle (radians).
    length : sympy.Expr
        ``L``.
    turns : sequence of sympy.Matrix
        The candidate rotations ``M``.
    variables : sequence of sympy.Symbol
        The model's joints (arm, then wrist).
    """

    MARGIN = 1e-12          # the cap's box is widened by this each way (its float bounds err by about 1e-16)

    def __init__(self, w, approach, direction, cone, length, turns, variables):
        best = None
        moving = set().union(*(sp.sympify(e).free_symbols for e in w))
        for M in turns:
            turned_axis = list(sp.Matrix(M) * sp.Matrix(approach))
            base = [sp.expand(wi - length * ai) for wi, ai in zip(w, turned_axis)]
            free = set().union(*(e.free_symbols for e in base)) & moving
            if best is None or len(free) < len(best[0]):
                best = (free, base, turned_axis, sp.Matrix(M) * sp.Matrix(direction))
        free, base, turned_axis, axis = best
        self.useful = len(free) < len(moving)
        self.k = len(variables)
        self._batch = compile_batch(base + turned_axis, tuple(variables))   # o, then M a
        self.length = numpy_constant(length)
        d = np.array([float(e) for e in axis])
        d /= np.linalg.norm(d)
        c = float(cone)
        angles = np.arccos(np.clip(d, -1.0, 1.0))
        lo = np.cos(np.minimum(angles + c, np.pi)) - self.MARGIN
        hi = np.cos(np.maximum(angles - c, 0.0)) + self.MARGIN
        self.cap = (np.maximum(lo, -1.0), np.minimum(hi, 1.0))

    def enclose(self, Q: np.ndarray) -> np.ndarray:
        """``(N, 3, 2)`` enclosures of ``w`` over the admissible configurations of the joint boxes ``Q`` (all the
        model's joints), rounded outward; a coordinate whose cap and axis enclosures do not meet is returned empty
        (``lo > hi``): no configuration of the box satisfies the cone.

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            ``(N, 3, 2)``.
        """
        E = batch_enclosures(self._batch, Q, self.k, 6)
        a = np.maximum(E[:, 3:, 0], self.cap[0]), np.minimum(E[:, 3:, 1], self.cap[1])
        empty = a[0] > a[1]
        with np.errstate(all="ignore"):
            lo, hi = arith.add((E[:, :3, 0], E[:, :3, 1]), arith.mul(self.length, a))
        return np.stack([np.where(empty, np.inf, lo), np.where(empty, -np.inf, hi)], axis=2)


class PoseModel:
    """A position map (``m`` task coordinates) over the joints that move the position or the constrained
    quantity, the constraint's enclosures, and the square system of the inner test (module docstring).

    ``approach`` is the tool's approach axis (three expressions) and ``rotation`` its frame (3 x 3, for a
    constant orientation); ``limits`` are exact, ``periodic`` as for :class:`ImageMap`.

    Parameters
    ----------
    position : sequence of sympy.Expr
        The ``m`` task coordinates.
    approach : sequence of sympy.Expr
        The approach axis.
    rotation : sympy.Matrix or None
        The tool frame's rotation (read for an orientation constraint only).
    constraint : PoseConstraint
        The constraint.
    variables : sequence of sympy.Symbol
        The joints that move the position or the constrained quantity.
    limits : sequence of tuple
        Their exact ``(lo, hi)`` ranges.
    periodic : sequence of bool
        Whether each range is a period.
    task_variables : sequence of sympy.Symbol
        The names of the task coordinates.
    proof_cone : sympy.Expr, optional
        The half-angle the inner proof must show, when narrower than the constraint's (after the wrist
        reduction with ``every``); None: the constraint's.
    tuning : Tuning
        ``wrist_cells``, ``wrist_grid``.
    square : sequence of sympy.Expr, optional
        ``w = (u, c, v)`` when ``position`` is ``(u^2 + c^2, v)``: its enclosures then come from those of ``u``,
        ``c``, ``v`` (:class:`~workspace_sym.serial.section.SquareMap`, tighter than the expanded square's).
    offset : tuple, optional
        ``(L, turns)`` for a cone with a tool point at the length ``L`` along the approach from a point the last
        joints do not move: pairs are dropped on the enclosure of the admissible positions too
        (:class:`_OffsetEnclosure`, ``turns`` its candidate rotations).
    """

    def __init__(self, position, approach, rotation, constraint: PoseConstraint, variables, limits, periodic,
                 task_variables, *, proof_cone: sp.Expr | None = None, tuning: Tuning = DEFAULT,
                 square=None, offset=None):
        self.constraint = constraint
        self.wrist_cells, self.wrist_grid = tuning.wrist_cells, tuning.wrist_grid
        variables, limits, periodic = list(variables), list(limits), list(periodic)
        position = [sp.sympify(e) for e in position]
        approach = sp.Matrix(approach)
        if constraint.kind == "cone":
            d = sp.Matrix(constraint.direction)
            e1, e2 = _orthonormal_pair(d)
            # The exact direction is also a . e1 = a . e2 = 0: enclosures of these exclude 0 at a distance of
            # the order of the box, where a . d only falls quadratically short of |d|.
            quantities = [approach.dot(d)] + ([approach.dot(e1), approach.dot(e2)] if constraint.cone == 0 else [])
        else:
            quantities = list(rotation)
        # Arm joints move the position; wrist joints only the constrained quantity (docs/methods.md section 8).
        moving = set().union(*(e.free_symbols for e in position))
        order = sorted(range(len(variables)), key=lambda j: variables[j] not in moving)
        variables, limits, periodic = ([seq[j] for j in order] for seq in (variables, limits, periodic))
        self.ka = sum(q in moving for q in variables)
        if square is None:
            self.position = ImageMap(position, variables[:self.ka], limits[:self.ka], periodic[:self.ka])
        else:
            self.position = SquareMap(position[0], square, variables[:self.ka], limits[:self.ka], periodic[:self.ka])
        self.wrist = ImageMap([], variables[self.ka:], limits[self.ka:], periodic[self.ka:])
        self.variables = tuple(variables)
        self.task_variables = tuple(task_variables)
        self._quantities = [compile_expr(e, self.variables) for e in quantities]
        self.solver = None
        self.lead = quantities[0]           # a . d for a cone (the first entry of R(q) for an orientation)
        self._lead_float = sp.lambdify([self.variables], self.lead, modules="numpy")
        if constraint.kind == "cone":
            norm = sp.sqrt(d.dot(d))
            self.bound = numpy_constant(norm * sp.cos(constraint.cone))
            if constraint.cone == 0:
                self.proof = _ConstrainedMap(position, [approach.dot(e1), approach.dot(e2)], approach.dot(d), 0.0,
                                             False, variables, limits, periodic)
                if self.wrist.k == 2:
                    self.solver = _WristSolver([approach.dot(e1), approach.dot(e2)], approach.dot(d), self.variables,
                                               self.ka)
            else:
                # The inner proof may need a narrower cone than the one whose violation drops a box (every=True
                # after the wrist reduction); Newton first aims the axis at d when that leaves a square system.
                proof_bound = self.bound if proof_cone is None else numpy_constant(norm * sp.cos(proof_cone))
                aim = (ImageMap(position + [approach.dot(e1), approach.dot(e2)], variables, limits, periodic)
                       if len(variables) >= len(position) + 2 else None)
                self.proof = _ConstrainedMap(position, [], approach.dot(d), proof_bound[1], True, variables, limits,
                                             periodic, aim=aim)
        else:
            self.entries = np.array([numpy_constant(e) for e in constraint.matrix], dtype=np.float64)   # (9, 2)
            M = constraint.matrix.T * rotation
            skew = [M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]]
            self.proof = _ConstrainedMap(position, skew, M.trace(), -1.0, False, variables, limits, periodic)
        self.offset: _OffsetEnclosure | None = None
        w = list(square) if square is not None else position
        if offset is not None and constraint.kind == "cone" and proof_cone is None and len(w) == 3:
            tightened = _OffsetEnclosure(w, list(approach), list(constraint.direction), constraint.cone, offset[0],
                                         offset[1], self.variables)
            self.offset = tightened if tightened.useful else None
        root = self.position.enclose(self.position.limits[None])[0]
        length = 0.5 * float(np.max(root[:, 1] - root[:, 0]))
        # How much a joint moves the position (largest Jacobian entry over the limits) and the constrained
        # quantity (an angle of at most the joint's turn, as a length: times half the root box).
        J = self.position.jacobian_enclosure(self.position.limits[None])
        m = self.position.m
        scale = np.array([max(max(abs(float(J[i][j][0][0])), abs(float(J[i][j][1][0]))) for i in range(m))
                          for j in range(self.position.k)])
        self.position_scale = np.where(np.isfinite(scale), scale, length)

    def _enclosures(self, Q: np.ndarray) -> list:
        X = [(Q[:, j, 0], Q[:, j, 1]) for j in range(Q.shape[1])]
        with np.errstate(all="ignore"):
            return [tuple(np.broadcast_to(v, (len(Q),)) for v in f(X)) for f in self._quantities]

    def constraint_status(self, Q: np.ndarray):
        """Masks of the boxes ``Q`` over all joints (arm, then wrist) on which the constraint is proved
        violated everywhere, and proved satisfied everywhere (NaN: neither).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, ka + kw, 2)`` boxes (fixed joints as point intervals).

        Returns
        -------
        violated : numpy.ndarray
            ``(N,)`` booleans.
        satisfied : numpy.ndarray
            ``(N,)`` booleans (only for a cone with a positive half-angle; all False otherwise).
        """
        E = self._enclosures(Q)
        if self.constraint.kind == "cone":
            lo, hi = E[0]
            violated = hi < self.bound[0]
            for lo_e, hi_e in E[1:]:                 # the exact direction: a . e = 0
                violated |= (lo_e > 0) | (hi_e < 0)
            return violated, (lo >= self.bound[1]) & (len(E) == 1)
        violated = np.zeros(len(Q), dtype=bool)
        for (lo, hi), (r_lo, r_hi) in zip(E, self.entries):
            violated |= (hi < r_lo) | (lo > r_hi)
        return violated, np.zeros(len(Q), dtype=bool)

    def admissibility(self, A: np.ndarray):
        """For arm boxes ``A`` (``(N, ka, 2)``): the mask of those on which no wrist within its limits
        satisfies the constraint (proved), the mask of those on which one wrist value satisfies it for every
        arm value (proved), and a wrist value per box (that value, or the centre of a wrist box not proved
        violated).

        Wrist boxes are halved (widest first) while wider than the arm box, at most ``wrist_cells`` per arm
        box; a wrist box is dropped when the constraint is proved violated over it times the arm box.  This
        search for a proof of violation is skipped where a float search finds a wrist value satisfying the
        constraint at the arm box's centre (a box is only dropped on a proof, so skipping is always sound).

        Parameters
        ----------
        A : numpy.ndarray
            ``(N, ka, 2)`` arm boxes.

        Returns
        -------
        dead : numpy.ndarray
            ``(N,)`` booleans: no wrist value satisfies the constraint (proved).
        sure : numpy.ndarray
            ``(N,)`` booleans: one wrist value satisfies it for every arm value (proved).
        witness : numpy.ndarray
            ``(N, kw)`` wrist values.
        """
        n, kw = len(A), self.wrist.k
        if kw == 0:
            dead, sure = self.constraint_status(A)
            return dead, sure, np.zeros((n, 0))
        witness = np.repeat(0.5 * (self.wrist.inner_limits[:, 0] + self.wrist.inner_limits[:, 1])[None], n, axis=0)
        sure, alive = np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
        centre = 0.5 * (A[:, :, 0] + A[:, :, 1])
        if self.constraint.kind == "cone" and self.constraint.cone != 0:
            # First the wrist value of a small grid that best aims the axis at the arm box's centre (floats),
            # then the proof that it satisfies the cone over the whole arm box.
            best = self._best_wrist(centre)
            point = np.repeat(best[:, :, None], 2, axis=2)
            _, holds = self.constraint_status(np.concatenate([A, point], axis=1))
            sure[holds], witness[holds] = True, best[holds]
            with np.errstate(all="ignore"):
                value = self._lead_float(np.concatenate([centre, best], axis=1).T)
            plausible = np.broadcast_to(np.asarray(value, dtype=float), (n,)) >= self.bound[1]
        elif self.solver is not None:
            best = self._best_wrist(centre)
            holds, value = self.solver.prove(A, best, self.wrist)
            sure[holds], witness[holds] = True, value[holds]
            plausible = self.solver.solves(centre, value, self.wrist)
        elif self.constraint.kind == "cone" and self.constraint.cone == 0:
            best, plausible = self._best_wrist(centre), np.zeros(n, dtype=bool)
        else:
            best, plausible = witness, np.zeros(n, dtype=bool)
        keep = plausible & ~sure
        alive[keep], witness[keep] = True, (best if self.solver is None else value)[keep]
        W = np.repeat(self.wrist.limits[None], n, axis=0)[~sure & ~plausible]
        row = np.nonzero(~sure & ~plausible)[0]
        target = np.max(A[:, :, 1] - A[:, :, 0], axis=1)
        survives = np.zeros(n, dtype=bool)          # a wrist box not proved violated is left at the end
        seen = np.zeros(n, dtype=bool)
        while len(W):
            violated, _ = self.constraint_status(np.concatenate([A[row], W], axis=1))
            W, row = W[~violated], row[~violated]
            centre = np.clip(0.5 * (W[:, :, 0] + W[:, :, 1]), self.wrist.inner_limits[:, 0],
                             self.wrist.inner_limits[:, 1])
            if self.constraint.kind == "cone":
                point = np.repeat(centre[:, :, None], 2, axis=2)
                _, holds = self.constraint_status(np.concatenate([A[row], point], axis=1))
                sure[row[holds]] = True
                witness[row[holds]] = centre[holds]
            fresh = ~seen[row] & ~sure[row]
            witness[row[fresh]] = centre[fresh]
            seen[row] = True
            keep = ~sure[row]
            W, row = W[keep], row[keep]
            width = W[:, :, 1] - W[:, :, 0]
            split = np.max(width, axis=1) > target[row]
            count = np.bincount(row, minlength=n) + np.bincount(row[split], minlength=n)
            split &= (count <= self.wrist_cells)[row]
            children, ok = halves(W[split])
            # Boxes not split, or one float wide, are final: their arm box is not proved violated.
            survives[row[~split]] = True
            survives[row[split][~ok]] = True
            W = children.reshape(-1, 2, kw, 2)[ok].reshape(-1, kw, 2)
            row = np.repeat(row[split][ok], 2)
        if self.solver is None and self.constraint.kind == "cone" and self.constraint.cone == 0:
            # The seed of the inner test: the wrist value of a grid aiming the axis nearest d (floats), not a
            # box centre, which may sit where the constraint's equations are singular (cos q5 at q5 = 0).
            witness[~sure] = best[~sure]
        return ~alive & ~sure & ~survives, sure, witness

    def _best_wrist(self, arm: np.ndarray) -> np.ndarray:
        """Per arm value (``(N, ka)``), the wrist value of a grid over the wrist limits (``wrist_grid`` per joint)
        where the first constrained quantity (``a . d``) is largest, in floats."""
        axes = [np.linspace(lo, hi, self.wrist_grid) for lo, hi in self.wrist.inner_limits]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, self.wrist.k)
        best = np.empty((len(arm), self.wrist.k))
        for start in range(0, len(arm), 4096):
            a = arm[start:start + 4096]
            q = np.concatenate([np.repeat(a, len(grid), axis=0), np.tile(grid, (len(a), 1))], axis=1)
            with np.errstate(all="ignore"):
                value = np.broadcast_to(np.asarray(self._lead_float(q.T), dtype=float), (len(q),))
            value = np.where(np.isfinite(value), value, -np.inf).reshape(len(a), len(grid))
            best[start:start + 4096] = grid[np.argmax(value, axis=1)]
        return best

    def distribute(self, T, Q, owner, cap, *, rounds: int = 4):
        """Keep the (joint box, task box) pairs whose arm box may hold an admissible configuration with its
        position in the task box, halving arm boxes along the joint that widens the position most while
        their position is wider than the task box, while a task box holds at most ``cap`` pairs.

        ``Q`` holds per pair the arm box, then a wrist value per wrist joint and a status (0: not examined,
        1: not proved either way, 2: admissible for every arm value) as point intervals.

        Parameters
        ----------
        T : numpy.ndarray
            ``(N, m, 2)`` task boxes.
        Q : numpy.ndarray
            ``(P, ka + kw + 1, 2)`` pairs, as above.
        owner : numpy.ndarray
            ``(P,)`` the index in ``T`` of each pair's task box.
        cap : numpy.ndarray
            ``(N,)`` the pairs each task box may hold.
        rounds : int
            Halvings at most.

        Returns
        -------
        Q : numpy.ndarray
            The pairs kept, halved arm boxes included.
        owner : numpy.ndarray
            The index in ``T`` of each pair's task box.
        """
        ka, kw = self.ka, self.wrist.k
        for r in range(rounds + 1):
            fresh = Q[:, -1, 0] == 0
            if fresh.any():
                dead, sure, witness = self.admissibility(Q[fresh, :ka])
                rows = np.nonzero(fresh)[0]
                Q[rows, ka:ka + kw] = witness[:, :, None]
                Q[rows, -1] = np.where(sure, 2.0, np.where(dead, -1.0, 1.0))[:, None]
            E = self.position.enclose(Q[:, :ka])
            if self.offset is not None:
                E = self._admissible(E, Q[:, :ka])
            keep = meets(E, T[owner]) & (E[:, :, 0] <= E[:, :, 1]).all(axis=1) & (Q[:, -1, 0] > 0)
            Q, owner, E = Q[keep], owner[keep], E[keep]
            if r == rounds:
                break
            width = Q[:, :ka, 1] - Q[:, :ka, 0]
            task = np.max(T[owner, :, 1] - T[owner, :, 0], axis=1)
            split = np.max(E[:, :, 1] - E[:, :, 0], axis=1) > task
            after = np.bincount(owner, minlength=len(T)) + np.bincount(owner[split], minlength=len(T))
            split &= (after <= cap)[owner]
            if not split.any():
                break
            children, ok = halves(Q[split], np.argmax(width * self.position_scale, axis=1)[split])
            children = children.reshape(-1, 2, *Q.shape[1:])[ok].reshape(-1, *Q.shape[1:])
            children[:, -1] = np.where(children[:, -1] == 2.0, 2.0, 0.0)      # admissible stays admissible
            Q = np.concatenate([Q[~split], Q[split][~ok], children])
            owner = np.concatenate([owner[~split], owner[split][~ok], np.repeat(owner[split][ok], 2)])
        return Q, owner

    def _admissible(self, E: np.ndarray, A: np.ndarray) -> np.ndarray:
        """``E`` (the position's enclosures over the arm boxes ``A``) intersected with the enclosures of the
        admissible positions (:class:`_OffsetEnclosure`, the wrist joints over their limits); an empty result
        (``lo > hi``) means no admissible configuration in the box."""
        assert self.offset is not None
        wrist = np.repeat(np.reshape(self.wrist.limits, (-1, 2))[None], len(A), axis=0)
        W = self.offset.enclose(np.concatenate([A, wrist], axis=1))
        if isinstance(self.position, SquareMap):
            W = squared_enclosures(W)
        # fmax / fmin: a NaN bound (no enclosure) leaves E's; an empty coordinate stays empty.
        return np.stack([np.fmax(E[:, :, 0], W[:, :, 0]), np.fmin(E[:, :, 1], W[:, :, 1])], axis=2)

    def root_pairs(self) -> np.ndarray:
        """The one pair of the root: the arm limits, a wrist value, status 0.

        Returns
        -------
        numpy.ndarray
            ``(1, ka + kw + 1, 2)``: the arm's outward limits, then zeros.
        """
        return np.concatenate([self.position.limits, np.zeros((self.wrist.k + 1, 2))])[None]

    def seeds(self, Q: np.ndarray) -> np.ndarray:
        """Configurations (arm, then wrist) from pairs: the arm box's centre and the pair's wrist value.

        Parameters
        ----------
        Q : numpy.ndarray
            ``(P, ka + kw + 1, 2)`` pairs.

        Returns
        -------
        numpy.ndarray
            ``(P, ka + kw)`` joint values.
        """
        return np.concatenate([Q[:, :self.ka].mean(axis=2), Q[:, self.ka:-1, 0]], axis=1)


def _free_of(expressions, q) -> bool:
    return all(q not in sp.sympify(e).free_symbols for e in expressions)


def _spin_reduction(robot: DHRobot, params, constraint: PoseConstraint, T) -> PoseConstraint:
    """A constant orientation ``R`` as the exact direction ``R z`` when the last joint spins the tool about its
    approach axis through a full turn (:func:`_spin_range`, docs/methods.md section 8), else the constraint
    itself: every frame with the approach ``R z`` at that position is reached, ``R`` among them.
    """
    if constraint.kind != "orientation":
        return constraint
    spin = _spin_range(robot, params, T)
    if spin is None or not spin[1]:
        return constraint
    return PoseConstraint("cone", tuple(constraint.matrix[:, 2]), sp.S.Zero, 0.0, False)


def wrist_reduction(robot: DHRobot, params, constraint: PoseConstraint, T):
    """A cone on the approach axis as a cone on the roll axis of a roll-pitch wrist, or why there is none.

    The wrist is the two joints ``j < k`` that move the approach ``a`` and not the position (standard DH, both
    revolute).  When ``q_j`` enters only ``theta_j`` and its range spans a period, ``a = Rot(z, theta_j) b`` with
    ``z`` the axis of joint ``j`` (``z_{j-1}``, free of the wrist), so a full turn of ``q_j`` sweeps every direction
    at the angle of ``b`` from ``z``.  When moreover ``a . z = cos(q_k + phi)`` (checked symbolically) and ``q_k``'s
    range holds an angle ``t`` with ``t + phi = 0 (mod 2 pi)``, the directions the wrist reaches from an arm
    configuration are exactly the cap ``angle(a, z) <= psi`` with ``psi = min(pi, largest |q_k + phi|)``.  Then
    (theorem) some direction within ``c`` of ``d`` is reached iff ``angle(z, d) <= psi + c``; every direction of the
    cone (one arm configuration) iff ``angle(z, d) <= psi - c``; ``d`` itself iff ``angle(z, d) <= psi``.

    Returns ``(z, constraint on z, proof_cone)``: the cone ``psi + c`` (``psi`` with ``every``, whose drops are
    then proved for the axis ``d`` alone, a direction of the cone) and the cone the inner proof must show
    (``psi - c`` with ``every``, else None).  The wrist joints then leave the model: its inner proof no longer
    meets the wrist's singularity (``q_k + phi = 0``, where ``q_j`` is undetermined), nor its violation proofs a
    cover of wrist boxes.  Otherwise a string: why the robot has no such wrist, in its joints' terms (the
    refusal of ``every=True`` quotes it).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    params : dict or None
        Values of its symbolic parameters.
    constraint : PoseConstraint
        The constraint (a cone, or there is no reduction).
    T : sympy.Matrix
        The robot's forward kinematics with ``params`` substituted (4 x 4).

    Returns
    -------
    tuple or str
        ``(z, constraint on z, proof_cone)``, or why there is none.
    """
    if constraint.kind != "cone":
        return "the constraint is not a cone"
    cap = wrist_cap(robot, params, T)
    if isinstance(cap, str):
        return cap
    axis, psi, wrist = cap
    c = constraint.cone
    if constraint.every and c != 0:
        if not bool(psi - c >= 0):
            names = ", ".join(f"joint {i + 1} ({robot.q[i]})" for i in wrist)
            return (f"its wrist ({names}) reaches directions up to {fmt(float(psi * 180 / sp.pi), 6, 'g')} "
                    f"degrees from its roll axis, less than the cone's {fmt(constraint.degrees, 6, 'g')}")
        reduced = PoseConstraint("cone", constraint.direction, psi, float(psi * 180 / sp.pi), True)
        return axis, reduced, psi - c
    angle = sp.Min(sp.pi, psi + c)
    return axis, PoseConstraint("cone", constraint.direction, angle, float(angle * 180 / sp.pi)), None


def wrist_cap(robot: DHRobot, params, T, *, half_turn: bool = False):
    """The roll axis ``z`` of a roll-pitch wrist and the angle ``psi`` such that, from any arm configuration, the
    wrist reaches exactly (or, with ``half_turn``, at least) the directions within ``psi`` of ``z``; or why there is
    none (:func:`wrist_reduction`'s conditions).

    With ``half_turn``, a roll joint turning at least half a turn (not a whole one) qualifies when the wrist's two
    solutions are checked symbolically, ``a(q_j + pi, -q_k - 2 phi) = a(q_j, q_k)``: the directions at the angle
    ``beta`` from ``z`` reached with the pitch at ``-phi + beta`` form an arc of azimuths as long as the roll's
    range, those reached at ``-phi - beta`` the same arc turned by ``pi``, and the two cover the circle.  ``psi``
    is then the smaller of the pitch's reaches on either side of ``-phi`` (both signs are needed), at most ``pi``.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    params : dict or None
        Values of its symbolic parameters.
    T : sympy.Matrix
        The robot's forward kinematics with ``params`` substituted (4 x 4).
    half_turn : bool
        Accept a roll joint turning half a turn or more (default False: a whole turn).

    Returns
    -------
    tuple or str
        ``(z, psi, (j, k))``: the roll axis (three expressions in the arm joints), ``psi`` (exact, radians) and
        the roll and pitch joints' indices; or why there is no such wrist.
    """
    if robot.convention != "standard":
        return f"its table is in {robot.convention} DH (the wrist is recognised in standard DH only)"
    approach, position = list(T[:3, 2]), list(T[:3, 3])
    in_position = set().union(*(sp.sympify(e).free_symbols for e in position))
    in_approach = set().union(*(sp.sympify(e).free_symbols for e in approach))

    def named(indices):
        return ", ".join(f"joint {i + 1} ({robot.q[i]})" for i in indices) or "none"

    wrist = [i for i, q in enumerate(robot.q) if q in in_approach and q not in in_position]
    if len(wrist) != 2:
        moving = [i for i, q in enumerate(robot.q) if q in in_approach and q in in_position]
        if not wrist and not moving:
            return "no joint turns the approach axis (it is the same in every configuration)"
        return (f"the joints that turn the approach axis without moving the tool point are {named(wrist)}, not "
                f"two" + (f" (the tool point moves with {named(moving)}, which also turn the approach axis)"
                          if moving else ""))
    if any(robot.joints[i].kind != "R" for i in wrist):
        return f"its wrist joints {named(wrist)} are not both revolute"
    j, k = wrist
    roll, pitch = robot.q[j], robot.q[k]
    others = [e for i, joint in enumerate(robot.joints) for e in (joint.d, joint.a, joint.alpha)
              + (() if i == j else (joint.theta,))]
    others += [e for M in (robot.base, robot.tool) if M is not None for e in M]
    if not _free_of(others, roll):
        return f"the roll joint {named([j])} enters the table other than through its angle theta"
    full = joint_range(robot, j, params)[1]
    if not full and not half_turn:
        return f"the roll joint {named([j])} does not turn through a full turn within its limits"
    axis = list(robot.substitute(robot.fk(j), params)[:3, 2])
    if not _free_of(axis, roll) or not _free_of(axis, pitch):
        return f"the axis of the roll joint {named([j])} moves with the wrist"
    # a = R_0^j (A_(j+1) ... A_n tool) z and z = R_0^j e_z, the rotation R_0^j free of the wrist: a . z is the
    # tail's own z component (a small expression; the whole chain's took 26 s to simplify on the LBR iiwa)
    tail = sp.eye(4) if robot.tool is None else sp.Matrix(robot.tool)
    for row in range(robot.n, j, -1):
        tail = robot.substitute(robot.row_matrix(row), params) * tail
    cosine = sp.simplify(tail[2, 2])
    phi = sp.atan2(-sp.diff(cosine, pitch).subs(pitch, 0), cosine.subs(pitch, 0))
    if cosine.free_symbols != {pitch} or sp.simplify(sp.expand_trig(cosine - sp.cos(pitch + phi))) != 0:
        return (f"the angle of the approach axis from the roll axis of {named([j])} is not set by {named([k])} "
                "alone as a pitch (cos(angle) = cos(q + phi))")
    (lo, hi), _ = joint_range(robot, k, params)
    turns = sp.ceiling((lo + phi) / (2 * sp.pi))
    if not bool(2 * sp.pi * turns <= hi + phi):
        # the cap's centre is not reached: an annulus, not a cap
        return (f"the pitch joint {named([k])} cannot bring the approach axis onto the roll axis within its "
                "limits (the wrist reaches a ring of directions, not a cap)")
    below, above = 2 * sp.pi * turns - lo - phi, hi + phi - 2 * sp.pi * turns    # the pitch's reach either side
    if full:
        return axis, sp.Min(sp.pi, sp.Max(below, above)), (j, k)
    (r_lo, r_hi), _ = joint_range(robot, j, params)
    slope = sp.diff(robot.substitute(sp.Matrix([robot.joints[j].theta]), params)[0], roll)
    if slope.free_symbols or abs(slope) != 1 or not bool(r_hi - r_lo >= sp.pi):
        return f"the roll joint {named([j])} turns less than half a turn within its limits"
    direction = list(tail[:3, 2])
    flipped = [sp.sympify(e).subs({roll: roll + sp.pi, pitch: -pitch - 2 * phi}, simultaneous=True)
               for e in direction]
    if any(sp.simplify(sp.expand_trig(f - e)) != 0 for f, e in zip(flipped, direction)):
        return (f"the roll joint {named([j])} turns less than a full turn and the wrist's second solution "
                f"(roll + pi, pitch mirrored) does not give the same approach axis")
    return axis, sp.Min(sp.pi, below, above), (j, k)


def _tool_offset(robot: DHRobot, params, constraint: PoseConstraint, T):
    """For a constant orientation ``R``: ``(k, o_k + R t)`` with ``k`` the first frame whose origin ``o_k`` holds
    the tool point at a constant offset in the tool frame, ``t = R(q)^T (p(q) - o_k(q))`` free of the joints (a
    spherical wrist: ``k`` its centre's frame, ``t = (0, 0, d6)`` for the Puma), or None.

    On the configurations with ``R(q) = R`` the tool point is ``o_k(q) + R t`` (theorem), so the workspace is paved
    with that position, which the wrist joints do not move; its configurations are those of the constraint, so
    inner and outer proofs hold for the real tool point.  After the spin reduction (a configuration with
    ``a(q) = R z``, spun by the last joint to ``R(q) = R``) the tool point is still ``o_k + R t``: ``o_k`` does not
    depend on the last joint."""
    if constraint.kind != "orientation":
        return None
    found = _tail_offset(robot, params)
    if found is None:
        return None
    k, t = found
    origin = robot.substitute(robot.fk(k), params)[:3, 3]
    return k, [sp.sympify(e) for e in origin + constraint.matrix * t]


def _tail_offset(robot: DHRobot, params):
    """``(k, t)``: the first frame ``k`` whose origin ``o_k`` holds the tool point at a constant offset ``t`` in
    the tool frame (``t = R(q)^T (p(q) - o_k(q))`` free of the joints), or None."""
    # R(q)^T (p - o_k) = (R_k^n)^T p_k^n: the offset from the tail of the chain alone (frames k..n, tool).
    tails = [sp.eye(4) if robot.tool is None else sp.Matrix(robot.tool)]
    for i in range(robot.n, 0, -1):
        tails.append(robot.substitute(robot.row_matrix(i), params) * tails[-1])
    tails = tails[::-1]                     # tails[k] = T_k^n (tool included)
    probes = np.random.default_rng(0).uniform(-3, 3, size=(robot.n, 4))
    found = None
    for k in range(robot.n - 1, 0, -1):     # the shortest tail first; a float probe rejects before SymPy
        offset = tails[k][:3, :3].T * tails[k][:3, 3]
        with np.errstate(all="ignore"):
            values = np.array([np.broadcast_to(np.asarray(v, dtype=float), (4,))
                               for v in sp.lambdify([robot.q], list(offset), modules="numpy")(probes)])
        if not np.isfinite(values).all() or np.ptp(values, axis=1).max() > 1e-9:
            break
        t = sp.simplify(offset)
        if t.free_symbols & set(robot.q):
            break
        found = k, t
    return found


def _approach_offset(robot: DHRobot, params, constraint: PoseConstraint):
    """For a cone: ``(L, turns)`` when the tool point is ``o_k + L a`` (a tail offset ``(0, 0, L)``, ``L != 0``),
    ``turns`` the rotations that may take the approach into the frame of a section (:class:`_OffsetEnclosure`);
    else None."""
    if constraint.kind != "cone":
        return None
    found = _tail_offset(robot, params)
    if found is None or found[1][0] != 0 or found[1][1] != 0 or found[1][2] == 0:
        return None
    turns = [sp.eye(3)] + ([] if robot.base is None else [sp.Matrix(robot.base)[:3, :3].T])
    return found[1][2], turns


def _joints_of(robot, expressions, params):
    moving = set().union(*(sp.sympify(e).free_symbols for e in expressions))
    joints = [k for k, q in enumerate(robot.q) if q in moving]
    ranges = [joint_range(robot, k, params) for k in joints]
    return [robot.q[k] for k in joints], [r for r, _ in ranges], [p for _, p in ranges]



def joints_of(robot, expressions, params):
    """The joints moving ``expressions``, their exact limits and periodicity (``(variables, limits, periodic)``).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    expressions : sequence of sympy.Expr
        The expressions.
    params : dict or None
        Parameter values.

    Returns
    -------
    tuple
        ``(variables, limits, periodic)``.
    """
    return _joints_of(robot, expressions, params)


def _turns_freely(robot: DHRobot, k: int, params, limits, periodic) -> bool:
    """Joint ``k`` is revolute with ``theta_k = q_k + constant``, ``q_k`` in no other entry of the table (nor the
    base or tool), and its range is one whole turn: every expression of the kinematics is then ``2 pi``-periodic
    in ``q_k`` and every angle is reached."""
    joint = robot.joints[k]
    q = joint.variable
    if joint.kind != "R" or not periodic:
        return False
    theta = robot.substitute(joint.theta, params)
    if sp.diff(theta, q) != 1 or q in sp.diff(theta, q).free_symbols:
        return False
    others = [joint.d, joint.a, joint.alpha] + [e for i, j in enumerate(robot.joints) if i != k
                                                for e in (j.theta, j.d, j.a, j.alpha)]
    others += [e for M in (robot.base, robot.tool) if M is not None for e in M]
    if not _free_of(others, q):
        return False
    lo, hi = limits
    return bool(sp.simplify(hi - lo - 2 * sp.pi) == 0)


def _summed_angles(robot: DHRobot, params, expressions, variables, limits, periodic):
    """The expressions in the partial sums of the longest chain of joints whose angles enter them summed
    (``sin(q2 + q3 + q4)``: parallel axes, the UR5's joints 2, 3, 4), or the inputs unchanged.

    With the chain ``q_a, q_b, ...`` (robot order) and ``phi_1 = q_a``, ``phi_k = phi_(k-1) + q_k``, the map
    ``(q_a, q_b, ...) -> (phi_1, phi_2, ...)`` is a bijection modulo ``2 pi`` when every joint of the chain but the
    first turns freely (:func:`_turns_freely`): ``phi_1`` keeps ``q_a``'s range, each later ``phi_k`` ranges over
    one whole turn (periodic), and the expressions, ``2 pi``-periodic in each joint, take the same values on the
    new box as on the old one.  So the image, and the admissible set, are the same: inner and outer proofs in the
    new variables hold for the robot.  It matters for the inner proofs: a Krawczyk box in ``(q2, q3, q4)`` is wide
    in ``q2 + q3 + q4`` (the widths add) where the solutions keep the sum nearly constant (the tool down), so the
    enclosures of ``sin(q2 + q3 + q4)`` over it are loose and the test fails at all but the smallest boxes.

    Returns ``(expressions, variables, limits, periodic)``."""
    index = {q: i for i, q in enumerate(variables)}
    sums = set()
    for e in expressions:
        for node in sp.preorder_traversal(sp.sympify(e)):
            if isinstance(node, (sp.sin, sp.cos)) and isinstance(node.args[0], sp.Add):
                terms = node.args[0].args
                if all(t in index for t in terms):
                    sums.add(frozenset(terms))
    if not sums:
        return expressions, variables, limits, periodic
    longest = max(sums, key=lambda s: (len(s), sorted(index[t] for t in s)))
    chain = sorted(longest, key=lambda t: robot.q.index(t))
    ks = [robot.q.index(t) for t in chain]
    if len(chain) < 2 or not all(_turns_freely(robot, k, params, limits[index[q]], periodic[index[q]])
                                 for k, q in zip(ks[1:], chain[1:])):
        return expressions, variables, limits, periodic
    partial = [chain[0]] + [sp.Symbol("+".join(str(t) for t in chain[:i + 1])) for i in range(1, len(chain))]
    back = {chain[i]: partial[i] - partial[i - 1] for i in range(1, len(chain))}
    out = [sp.sympify(e).subs(back, simultaneous=True) for e in expressions]
    variables, limits, periodic = list(variables), list(limits), list(periodic)
    for i in range(1, len(chain)):
        j = index[chain[i]]
        variables[j], limits[j], periodic[j] = partial[i], (-sp.pi, sp.pi), True
    return out, variables, limits, periodic


@dataclass(frozen=True)
class WristCentre:
    """A cone about the vertical, or a constant orientation whose approach is vertical, for a tool point at the
    length ``L`` along the approach from a wrist centre ``o_k`` (the LBR iiwa: 0.126 m), with a roll-pitch wrist at
    ``o_k`` reaching every direction within ``psi`` of its roll axis (:func:`wrist_cap`, a half turn of roll or
    more), on an arm turned by a limited first joint (docs/methods.md section 8, "A cone through the wrist
    centre" and "A constant orientation through the wrist centre").

    Parameters
    ----------
    robot : DHRobot
        The chain to the wrist centre (its tool point ``o_k``).
    limited : LimitedTurn
        Its section (a limited turn).
    side : sympy.Expr
        ``z . d``, the roll axis's component along ``d``, in the section's joints.
    length : sympy.Expr
        ``L``: the tool point is ``o_k + L a``.
    cone : sympy.Expr
        The cone's half-angle (radians; 0 for an exact direction or an orientation).
    sign : int
        ``d = (0, 0, sign)``.
    psi : sympy.Expr
        The wrist's reach from its roll axis (radians).
    spin : SpinCondition, optional
        For an orientation: what the wrist's two solutions ask of the roll and the last joint (the direction
        proofs then hold at the polar angles of the first joint's sectors where one solution is within the
        limits, :class:`~workspace_sym.serial.turn.SpinSectors`); None for a cone.
    """

    robot: DHRobot
    limited: LimitedTurn
    side: sp.Expr
    length: sp.Expr
    cone: sp.Expr
    sign: int
    psi: sp.Expr
    spin: SpinCondition | None = None

    def levels(self, count: int = 3) -> list:
        """``(tilt, LimitedTurn)`` pairs: the tilts ``0, c / (count - 1), ..., c`` of the approach from ``d``
        (the tilt 0 alone for a cone of 0) and the section whose direction proofs also prove the roll axis within
        ``psi - tilt`` of ``d`` (:func:`~workspace_sym.serial.turn.constrained_turn`): from its wrist centres
        the wrist reaches every approach tilted by at most ``tilt`` from ``d``; with ``spin``, the proofs hold at
        the polar angles where one of the wrist's solutions is within the limits.

        Parameters
        ----------
        count : int
            Number of tilts (default 3).

        Returns
        -------
        list
            The pairs, the tilt exact.
        """
        tilts = [self.cone * sp.Rational(i, count - 1) for i in range(count)] if self.cone != 0 else [sp.S.Zero]
        return [(tilt, constrained_turn(self.limited, [(self.side, numpy_constant(sp.cos(self.psi - tilt))[1])],
                                        self.spin))
                for tilt in tilts]


def _spin_range(robot: DHRobot, params, T):
    """The last joint's range ``((lo, hi), full)`` when it spins the tool frame about its approach axis at a
    fixed position, else None.

    The tool frame is ``R_pre Rz(theta_n) C`` with ``R_pre`` and ``C`` free of ``q_n`` when ``q_n`` enters only
    ``theta_n``; an approach axis ``R_pre Rz(theta_n) C z`` free of ``q_n`` makes ``C z = +-z``, so turning
    ``theta_n`` by ``phi`` turns the frame about its own ``z`` by ``+-phi`` at a fixed position (the position
    being free of ``q_n``)."""
    k = robot.n - 1
    joint = robot.joints[k]
    q = joint.variable
    others = [joint.d, joint.a, joint.alpha] + [e for j in robot.joints[:k] for e in (j.theta, j.d, j.a, j.alpha)]
    others += [e for M in (robot.base, robot.tool) if M is not None for e in M]
    if joint.kind != "R" or not _free_of(others, q) or not _free_of(list(T[:3, 2]) + list(T[:3, 3]), q):
        return None
    return joint_range(robot, k, params)


@dataclass(frozen=True)
class SpinCondition:
    """What a constant orientation ``R`` with a vertical approach ``d`` asks of the wrist at a wrist centre
    reached with the roll axis within ``psi`` of ``d`` (docs/methods.md section 8, "A constant orientation through
    the wrist centre"): the wrist has two solutions, labelled by the pitch axis ``+-(z x d) / V`` (``z`` the roll
    axis, ``V = |z x d|``); the ``+`` one lies within the roll's and the last joint's limits iff ``-X >= cos(h_r) V``
    and ``-Y >= cos(h_n) V``, the ``-`` one iff ``X >= cos(h_r) V`` and ``Y >= cos(h_n) V`` (:func:`_spin_condition`).

    Parameters
    ----------
    turn : sympy.Symbol
        The first joint's DH angle ``theta_1``, the variable of ``Y`` besides the section's joints.
    X : sympy.Expr
        In the section's joints.
    Y : sympy.Expr
        In ``turn`` and the section's joints.
    V2 : sympy.Expr
        ``V^2 = 1 - (z . d)^2``, in the section's joints.
    roll : sympy.Expr or None
        ``cos(h_r)^2`` (the roll's half range ``h_r`` at least a quarter turn); None: the roll turns fully.
    spin : sympy.Expr
        ``cos(h_n)^2``, the last joint's.
    root : int
        0: either solution will do; ``+1`` or ``-1``: only that one (a map of one root's tool points,
        :class:`OffsetFlange`).
    linear : tuple, optional
        ``(A, B, C)`` in the section's joints with ``Y = A cos(turn) + B sin(turn) + C`` by construction
        (:func:`_turned_linear`): the sectors then read ``Y`` from three enclosures (:class:`~workspace_sym.serial.
        turn.SpinSectors`); None: ``Y`` is evaluated over each sector.
    """

    turn: sp.Symbol
    X: sp.Expr
    Y: sp.Expr
    V2: sp.Expr
    roll: sp.Expr | None
    spin: sp.Expr
    root: int = 0
    linear: tuple | None = None


def _turned_linear(robot: DHRobot, z0, vector):
    """``(A, B, C)`` with ``(Rz(turn) z0) . vector = A cos(turn) + B sin(turn) + C`` (``z0`` an axis in the first
    joint's frame at ``theta_1 = 0``, ``vector`` constant), when the robot's frames after the first joint are
    ``Rz(theta_1)`` times frames free of it (no base; standard DH, or modified DH with ``alpha_0 = 0``; the first
    joint's variable in its ``theta`` only): the world axis is then ``Rz(turn) z0`` exactly; else None."""
    q1 = robot.q[0]
    if robot.base is not None:
        return None
    first = robot.joints[0]
    if robot.convention == "modified" and sp.simplify(sp.cos(first.alpha) - 1) != 0:
        return None
    others = [first.d, first.a, first.alpha] + [e for j in robot.joints[1:] for e in (j.theta, j.d, j.a, j.alpha)]
    if not _free_of(others, q1):
        return None
    e = [sp.sympify(v) for v in vector]
    z = [sp.sympify(v) for v in z0]
    return (z[0] * e[0] + z[1] * e[1], z[0] * e[1] - z[1] * e[0], z[2] * e[2])


def _range_centre(robot: DHRobot, params, i: int):
    """``(mu, h, full)`` of joint ``i``: ``theta_i = s q_i + c`` with ``s = +-1`` (None otherwise), its limits
    ``m +- h`` (exact: a float limit as the binary fraction the engine uses), ``mu = c + s m``."""
    q = robot.q[i]
    theta = robot.substitute(sp.Matrix([robot.joints[i].theta]), params)[0]
    slope = sp.diff(theta, q)
    if slope.free_symbols or abs(slope) != 1:
        return None
    (lo, hi), full = joint_range(robot, i, params)
    lo, hi = exact_constants(sp.sympify(lo)), exact_constants(sp.sympify(hi))
    m, h = (lo + hi) / 2, (hi - lo) / 2
    return exact_constants(theta.subs(q, 0)) + slope * m, h, full


def _spin_condition(robot: DHRobot, params, wrist: tuple, rotation: sp.Matrix, sign: int):
    """The :class:`SpinCondition` of a constant orientation ``rotation`` whose approach is ``d = (0, 0, sign)``
    on a roll-pitch wrist (:func:`wrist_cap`: roll ``j``, pitch ``k = j + 1``) followed by the last joint
    ``n = k + 1``, which spins the tool about its approach through half a turn or more; None when the structure is
    not there.

    Theorem (docs/methods.md section 8).  With ``cos(alpha) = 0`` on the roll's and the pitch's DH rows (checked),
    the pitch axis ``p = R_j (sin(alpha_r) sin(theta_j), -sin(alpha_r) cos(theta_j), 0)`` is normal to the roll
    axis ``z`` and to the last joint's axis ``z' = R_(n-1) e_z``, which is ``e_C d`` (``C e_z = e_C e_z``,
    checked, ``C`` the rotation after ``Rz(theta_n)``): pointing the tool along ``d`` needs ``p = +-(z x d) /
    V``.  For the ``+`` solution, ``(cos, sin)(theta_j) = -sin(alpha_r) (v_x, v_y) / V`` (``v = R_j^T d``), so
    ``cos(theta_j - mu_r) = -X / V`` with ``X = sin(alpha_r) (v_x cos(mu_r) + v_y sin(mu_r))``, and the roll lies
    in ``m_r +- h_r`` iff that cosine is at least ``cos(h_r)``.  The last frame's x axis is ``sin(alpha_p) (p x
    z')`` (``alpha_p`` the pitch row's), that is ``-sin(alpha_p) e_C h / V`` with ``h`` the horizontal part of
    ``z``; the tool frame is ``R`` iff ``R_(n-1) Rz(theta_n) e_x = x_t = R C^T e_x``, so ``cos(theta_n - mu_n) =
    -Y / V`` with ``Y = sin(alpha_p) e_C (z . e_n)``, ``e_n = x_t cos(mu_n) + sin(mu_n) (x_t x z')``.  The ``-``
    solution flips both signs.  Both solutions' pitches lie within the limits when ``angle(z, d) <= psi``."""
    j, k = wrist
    n = robot.n
    if k != j + 1 or n - 1 != k + 1:
        return None
    T = robot.substitute(robot.fk(), params)
    spin = _spin_range(robot, params, T)
    roll_range, spin_range = _range_centre(robot, params, j), _range_centre(robot, params, n - 1)
    if spin is None or spin[1] or roll_range is None or spin_range is None:
        return None
    mu_r, h_r, roll_full = roll_range
    mu_n, h_n, _ = spin_range
    if not bool(2 * h_n >= sp.pi) or not (roll_full or bool(2 * h_r >= sp.pi)):
        return None
    roll_row = robot.substitute(robot.row_matrix(j + 1), params)
    pitch_row = robot.substitute(robot.row_matrix(k + 1), params)
    if sp.simplify(roll_row[2, 2]) != 0 or sp.simplify(pitch_row[2, 2]) != 0:
        return None
    s_r, s_p = sp.simplify(roll_row[2, 1]), sp.simplify(pitch_row[2, 1])       # sin(alpha), +-1
    tail = robot.substitute(robot.row_matrix(n), params) * (sp.eye(4) if robot.tool is None
                                                              else sp.Matrix(robot.tool))
    last = robot.q[n - 1]
    e_c = sp.simplify(tail[2, 2])
    if [sp.simplify(tail[0, 2]), sp.simplify(tail[1, 2])] != [0, 0] or e_c not in (1, -1):
        return None
    theta_n = robot.substitute(sp.Matrix([robot.joints[n - 1].theta]), params)[0]
    C = (rot_z(-theta_n)[:3, :3] * tail[:3, :3]).applyfunc(lambda e: sp.simplify(sp.expand_trig(e)))
    if last in C.free_symbols:
        return None
    d = sp.Matrix([0, 0, sign])
    x_t = sp.Matrix(rotation) * C.T * sp.Matrix([1, 0, 0])
    z_last = e_c * d
    e_n = x_t * sp.cos(mu_n) + sp.sin(mu_n) * x_t.cross(z_last)
    axis = robot.substitute(robot.fk(j), params)
    z = axis[:3, 2]
    turn = sp.Symbol("theta_turn")
    theta_1 = robot.substitute(sp.Matrix([robot.joints[0].theta]), params)[0]
    q1 = robot.q[0]
    s1 = sp.diff(theta_1, q1)
    if s1.free_symbols or abs(s1) != 1:
        return None
    X = s_r * sign * (axis[2, 0] * sp.cos(mu_r) + axis[2, 1] * sp.sin(mu_r))
    V2 = 1 - (sign * z[2]) ** 2
    linear = _turned_linear(robot, z.subs(q1, -theta_1.subs(q1, 0) / s1), s_p * e_c * e_n)
    if linear is None:
        Y = (s_p * e_c * (z.T * e_n)[0]).subs(q1, s1 * (turn - theta_1.subs(q1, 0)))
    else:
        Y = linear[0] * sp.cos(turn) + linear[1] * sp.sin(turn) + linear[2]
    return SpinCondition(turn, X, Y, V2, None if roll_full else sp.cos(h_r) ** 2, sp.cos(h_n) ** 2, linear=linear)


def wrist_centre(robot: DHRobot, parameters: tuple, constraint: PoseConstraint) -> WristCentre | None:
    """The structure of :class:`WristCentre` when ``robot`` and ``constraint`` have it, else None (the pairs
    method then paves the constraint).

    Conditions, each checked (symbolically where it matters): a cone of half-angle ``c >= 0`` about ``(0, 0,
    +-1)`` (not ``every``), or a constant orientation whose approach is ``(0, 0, +-1)``; standard DH without a
    base; the tool point at ``o_k + L a`` (tail offset ``(0, 0, L)``, :func:`_tail_offset`); with the tool point
    moved to ``o_k``, a roll-pitch wrist (:func:`wrist_cap` with ``half_turn``) reaching ``psi > c`` from its roll
    axis ``z``; ``z . d`` free of the first joint and of every joint outside the section of the chain to ``o_k``,
    which is a turn of a limited first joint (:func:`~workspace_sym.serial.turn.limited_turn`); for an orientation,
    the structure of :func:`_spin_condition`, its ``X`` and ``Y`` in the same joints.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    constraint : PoseConstraint
        The constraint.

    Returns
    -------
    WristCentre or None
        The structure, or None.
    """
    if constraint.kind == "cone":
        if constraint.every:
            return None
        d, c = [sp.sympify(e) for e in constraint.direction], constraint.cone
    else:
        d, c = list(constraint.matrix[:, 2]), sp.S.Zero
    if d[0] != 0 or d[1] != 0 or robot.base is not None or robot.convention != "standard":
        return None
    params = dict(parameters) or None
    found = _tail_offset(robot, params)
    if found is None or found[1][0] != 0 or found[1][1] != 0 or found[1][2] == 0:
        return None
    k, t = found
    tool = (sp.eye(4) if robot.tool is None else sp.Matrix(robot.tool)) * translation(0, 0, -t[2])
    moved = DHRobot(list(robot.joints), convention=robot.convention, name=robot.name, parameters=robot.parameters,
                    units=robot.units, tool=tool)
    cap = wrist_cap(moved, params, moved.substitute(moved.fk(), params), half_turn=True)
    if isinstance(cap, str):
        return None
    axis, psi, wrist = cap
    if not bool(psi - c > 0):
        return None
    sign = 1 if d[2] > 0 else -1
    spin = None
    if constraint.kind == "orientation":
        spin = _spin_condition(robot, params, wrist, constraint.matrix, sign)
        if spin is None:
            return None
    chain = DHRobot(list(robot.joints[:k]), convention=robot.convention, name=f"{robot.name} (wrist centre)",
                    parameters=robot.parameters, units=robot.units)
    limited = limited_turn(structure_of(chain, parameters), reach_model(chain, parameters))
    if limited is None or limited.plan.inverse is not None:
        return None
    side = sp.simplify(sign * axis[2])                 # z . d / |d|, which the first joint's turn leaves alone
    joints = set(limited.plan.section.lateral.variables)
    if not side.free_symbols <= joints or (spin is not None and not (spin.X.free_symbols <= joints and
                                                                     spin.Y.free_symbols <= joints | {spin.turn})):
        return None
    return WristCentre(chain, limited, side, t[2], c, sign, psi, spin)


class FlangeMap(ImageMap):
    """``q' -> p = b(q') - f (u_x, u_y, 0)``: the tool point of one wrist solution on an arm whose flange is offset
    sideways from its last joint's axis (:class:`OffsetFlange`), with ``b = w + L d`` and ``u = h / |h|`` the
    horizontal unit of the roll axis.  Its enclosures clip each component of ``u`` to ``[-1, 1]`` (where the roll
    axis is near the vertical, ``u``'s own enclosure is unbounded, but ``u`` is a unit vector); its Jacobian and
    floats are those of the whole expression.

    With a ``cone`` (an approach ``a`` within ``c`` of ``d``, docs/methods.md section 8), :meth:`enclose_outer`
    holds the tool point ``w + L a - f u_a`` of every such approach (``u_a`` the unit of ``z - (z . a) a``), for
    the outer proofs; :meth:`enclose` stays that of ``a = d`` (the inner proofs are made at ``d``).

    Parameters
    ----------
    base : sequence of sympy.Expr
        ``b``, three expressions.
    unit : sequence of sympy.Expr
        ``(u_x, u_y)``.
    factor : sympy.Expr
        ``f``, exact.
    variables, limits, periodic
        As for :class:`~workspace_sym.interval.image.ImageMap`.
    axis : sequence of sympy.Expr, optional
        The roll axis ``z`` (three expressions), with ``cone``.
    cone : sympy.Expr, optional
        The cone's half-angle ``c`` (exact, radians, below a quarter turn).
    length : sympy.Expr, optional
        ``L``, exact, with ``cone``.
    sign : int
        ``d = (0, 0, sign)``.
    """

    def __init__(self, base, unit, factor, variables, limits, periodic, *, axis=None, cone=None, length=None,
                 sign: int = -1):
        expressions = [base[0] - factor * unit[0], base[1] - factor * unit[1], base[2]]
        super().__init__(expressions, variables, limits, periodic)
        self._base = compile_batch(list(base), self.variables)
        self._unit = compile_batch(list(unit), self.variables)
        self.factor = numpy_constant(factor)
        self.cone = None
        if cone is not None and cone != 0:
            self.cone = cone
            self._axis = compile_batch(list(axis), self.variables)
            c = sp.sympify(cone)
            # the constants of enclose_outer, each an outward enclosure of the exact value
            self._c, self._sin, self._cos = numpy_constant(c), numpy_constant(sp.sin(c)), numpy_constant(sp.cos(c))
            self._chord = numpy_constant(2 * sp.sin(c / 2))
            self._length = numpy_constant(length)
            self._lift = numpy_constant(sign * length * (sp.cos(c) - 1))

    def enclose(self, Q: np.ndarray) -> np.ndarray:
        """``(N, 3, 2)`` enclosures of ``p`` over joint boxes ``Q``, ``u`` clipped to ``[-1, 1]`` (outward-rounded).

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            The enclosures; a coordinate with no enclosure is ``[-inf, inf]``.
        """
        E = batch_enclosures(self._base, Q, self.k, 3)
        U = self._clipped_unit(Q)
        with np.errstate(all="ignore"):
            for i in range(2):
                side = arith.mul((U[:, i, 0], U[:, i, 1]), self.factor)
                E[:, i, 0], E[:, i, 1] = arith.sub((E[:, i, 0], E[:, i, 1]), side)
        return np.where(np.isnan(E), np.inf * np.array([-1.0, 1.0]), E)

    def _clipped_unit(self, Q: np.ndarray) -> np.ndarray:
        U = batch_enclosures(self._unit, Q, self.k, 2)
        return np.clip(np.where(np.isnan(U), np.array([-1.0, 1.0]), U), -1.0, 1.0)

    def enclose_outer(self, Q: np.ndarray) -> np.ndarray:
        """``(N, 3, 2)`` enclosures of the tool point ``w + L a - f u_a`` over joint boxes ``Q`` and every
        approach ``a`` of the cone (outward-rounded); without a cone, :meth:`enclose`.

        ``L a`` lies in ``L d + L ([-sin c, sin c]^2 x sign [cos c - 1, 0])``.  Along the arc from ``d`` to ``a``
        (at most ``c`` long) ``u_a`` moves by at most ``|da| / sin(phi)``, ``phi`` the angle from ``z`` to the
        approach, at least ``s = V cos c - |z_z| sin c`` in sine (``V = |z x d|``), and its horizontal part by at
        most ``|da| sqrt(sin(c)^2 + cot(phi)^2)``, ``|cos(phi)| <= min(1, |z_z| + V sin c)``: so each horizontal
        component of ``u_a`` lies within the lesser of ``c / s`` and ``c sqrt(sin(c)^2 + cot^2)`` of ``u_d``'s
        (where ``s > 0``; else anywhere in ``[-1, 1]``), and ``|u_z| = |u_a . (d - a)| <= 2 sin(c / 2)``.

        Parameters
        ----------
        Q : numpy.ndarray
            ``(N, k, 2)`` joint boxes.

        Returns
        -------
        numpy.ndarray
            The enclosures; a coordinate with no enclosure is ``[-inf, inf]``.
        """
        if self.cone is None:
            return self.enclose(Q)
        N = len(Q)
        E = batch_enclosures(self._base, Q, self.k, 3)
        U = self._clipped_unit(Q)
        Z = batch_enclosures(self._axis, Q, self.k, 3)
        with np.errstate(all="ignore"):
            horizontal = arith.sqrt(arith.add(arith.sqr((Z[:, 0, 0], Z[:, 0, 1])),
                                              arith.sqr((Z[:, 1, 0], Z[:, 1, 1]))))
            vertical = arith.iabs((Z[:, 2, 0], Z[:, 2, 1]))
            low = arith.sub(arith.mul(horizontal, self._cos), arith.mul(vertical, self._sin))[0]
            # |du| <= c / sin(phi); its horizontal part <= c sqrt(sin(c)^2 + cot(phi)^2), |cos(phi)| at most
            # min(1, |z_z| + V sin c) along the arc
            cosine = np.minimum(arith.add(vertical, arith.mul(horizontal, self._sin))[1], 1.0)
            cot = arith.div((cosine, cosine), (low, low))[1]
            level = arith.sqrt(arith.add(arith.sqr(self._sin), arith.sqr((cot, cot))))[1]
            radius = np.minimum(arith.div(self._c, (low, low))[1], arith.mul(self._c, (level, level))[1])
            radius = np.where(np.isnan(low) | ~(low > 0) | np.isnan(radius), np.inf, radius)
            sideways = arith.mul(arith.mul(arith.const(-1.0, 1.0, (N,)), self._sin), self._length)   # L a_x, a_y
            for i in range(2):
                lo = np.clip(np.nan_to_num(arith.sub((U[:, i, 0], U[:, i, 0]), (radius, radius))[0], nan=-1.0),
                             -1.0, 1.0)
                hi = np.clip(np.nan_to_num(arith.add((U[:, i, 1], U[:, i, 1]), (radius, radius))[1], nan=1.0),
                             -1.0, 1.0)
                E[:, i, 0], E[:, i, 1] = arith.sub(arith.add((E[:, i, 0], E[:, i, 1]), sideways),
                                                   arith.mul((lo, hi), self.factor))
            lift = (np.full(N, min(self._lift[0], 0.0)), np.full(N, max(self._lift[1], 0.0)))      # L (a_z - d_z)
            chord = arith.mul(arith.const(-1.0, 1.0, (N,)), self._chord)                           # u_z
            E[:, 2, 0], E[:, 2, 1] = arith.sub(arith.add((E[:, 2, 0], E[:, 2, 1]), lift),
                                               arith.mul(chord, self.factor))
        return np.where(np.isnan(E), np.inf * np.array([-1.0, 1.0]), E)


def _same_limits(image: ImageMap, like: ImageMap) -> ImageMap:
    """``image`` with the limits of ``like`` (the same joints): outward for enclosures, inward for proofs."""
    image.limits, image.face_limits = like.limits.copy(), like.face_limits.copy()
    image.inner_limits = like.inner_limits.copy()
    return image


@dataclass(frozen=True)
class OffsetFlange:
    """A constant orientation with a vertical approach ``d`` on an arm in modified DH whose flange is offset
    sideways by ``e`` from its last joint's axis (the Panda: ``e = 0.088`` m), after a roll-pitch wrist and a last
    joint that spins the tool about its approach (docs/methods.md section 8, "A flange offset sideways").

    With the approach fixed, the wrist has two solutions ``sigma = +-1`` (the pitch axis ``sigma (z x d) / V``,
    ``z`` the roll axis, ``V = |z x d|``), and the tool point of each is ``p_sigma = w + L d - sigma s_n e h / V``
    (``w`` the roll frame's origin, ``h`` the horizontal part of ``z``, ``s_n`` the sine of the last row's twist):
    a map of the arm's joints before the roll, turned by the first.  Each root is paved as a limited turn of its
    own map, its direction proofs also proving its pitch within the limits (a side condition) and, per sector of
    the first joint's turn, its roll and last joint within theirs (:class:`SpinCondition` with its ``root``).

    Parameters
    ----------
    roots : tuple
        ``(sigma, LimitedTurn)`` pairs, each turn's map a :class:`FlangeMap` with its conditions
        (:func:`~workspace_sym.serial.turn.constrained_turn`).
    sign : int
        ``d = (0, 0, sign)``.
    outer : LimitedTurn, optional
        A cone's: the tool point's own section, pruned where the approach leaves the cone.
    cone : float
        The cone's half-angle, radians (0: an exact approach or a constant orientation).
    ring : WristRing, optional
        The arm's :class:`~workspace_sym.serial.ring.WristRing`: its outer proofs of the section's cells
        (:func:`~workspace_sym.serial.ring.ring_outer_cells`).
    """

    roots: tuple
    sign: int
    outer: LimitedTurn | None = None
    cone: float = 0.0
    ring: WristRing | None = None


def _offset_rows(robot: DHRobot, params):
    """``(j, e_factor, L, s_k, s_n)`` of a modified-DH wrist whose flange is offset sideways
    (:class:`OffsetFlange`): the roll ``j = n - 3``, then a pitch row with ``a = d = 0`` and ``cos(alpha) = 0``,
    then the last row with ``a = e != 0`` and ``cos(alpha) = 0``, a tool rotated about its ``z`` and translated
    along it by ``t``: ``L = d_n + t``, ``e_factor = s_n e``, ``s_k`` and ``s_n`` the pitch row's and the last
    row's ``sin(alpha)``; None when a condition fails."""
    n = robot.n
    if n < 5 or robot.convention != "modified" or robot.base is not None:
        return None
    pitch, last = robot.joints[n - 2], robot.joints[n - 1]
    if any(joint.kind != "R" for joint in robot.joints[n - 3:]):
        return None
    row = [robot.substitute(sp.Matrix([e]), params)[0] for e in (pitch.a, pitch.d, pitch.alpha, last.a,
                                                                  last.alpha, last.d)]
    if any(e.free_symbols for e in row) or row[0] != 0 or row[1] != 0 or row[3] == 0:
        return None
    if sp.simplify(sp.cos(row[2])) != 0 or sp.simplify(sp.cos(row[4])) != 0:
        return None
    tool = sp.eye(4) if robot.tool is None else sp.Matrix(robot.tool)
    if list(tool[:3, 2]) != [0, 0, 1] or tool[0, 3] != 0 or tool[1, 3] != 0:
        return None
    s_k, s_n = sp.simplify(sp.sin(row[2])), sp.simplify(sp.sin(row[4]))
    return n - 3, s_n * row[3], row[5] + tool[2, 3], s_k, s_n


def offset_flange(robot: DHRobot, parameters: tuple, constraint: PoseConstraint) -> OffsetFlange | None:
    """The structure of :class:`OffsetFlange` when ``robot`` and ``constraint`` have it, else None.

    Conditions, each checked: a constant orientation whose approach is ``(0, 0, +-1)``; the rows of
    :func:`_offset_rows`; the roll, the pitch and the last joint each ``theta = +-q + c`` with a range of at
    least half a turn, the last joint spinning the tool about its approach (:func:`_spin_range`); the chain to the
    roll frame's origin a limited turn of its first joint (:func:`~workspace_sym.serial.turn.limited_turn`) whose
    section moves with the joints before the roll, and the roll axis free of the roll.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    constraint : PoseConstraint
        The constraint.

    Returns
    -------
    OffsetFlange or None
        The structure, or None.
    """
    oriented = constraint.kind == "orientation"
    cone = sp.S.Zero if oriented else sp.sympify(constraint.cone)
    if oriented:
        d = list(constraint.matrix[:, 2])
    elif cone == 0 or (not constraint.every and bool(2 * cone < sp.pi)):
        d = list(constraint.direction)
    else:                       # every direction of a cone, or a cone of a quarter turn or more: not this structure
        return None
    if d[0] != 0 or d[1] != 0:
        return None
    params = dict(parameters) or None
    rows = _offset_rows(robot, params)
    if rows is None:
        return None
    j, factor, length, s_k, s_n = rows
    T = robot.substitute(robot.fk(), params)
    spin = _spin_range(robot, params, T)
    ranges = [_range_centre(robot, params, i) for i in ((j, j + 1, j + 2) if oriented else (j, j + 1))]
    # (an exact approach leaves the spin free: the last joint's range does not matter)
    if spin is None or (oriented and spin[1]) or any(r is None for r in ranges):
        return None
    (mu_r, h_r, roll_full), (mu_p, h_p, _) = ranges[:2]
    if not (roll_full or bool(2 * h_r >= sp.pi)):
        return None
    if oriented:
        mu_n, h_n, _ = ranges[2]
        if not bool(2 * h_n >= sp.pi):
            return None
    sign = 1 if d[2] > 0 else -1
    chain = DHRobot(list(robot.joints[:j + 1]), convention=robot.convention, name=f"{robot.name} (roll frame)",
                    parameters=robot.parameters, units=robot.units)
    limited = limited_turn(structure_of(chain, parameters), reach_model(chain, parameters))
    if limited is None or limited.plan.inverse is not None:
        return None
    F = chain.substitute(chain.fk(), params)
    q1, roll = robot.q[0], robot.q[j]
    theta_1 = robot.substitute(sp.Matrix([robot.joints[0].theta]), params)[0]
    s1 = sp.diff(theta_1, q1)
    if s1.free_symbols or abs(s1) != 1 or roll in F[:3, 2].free_symbols:
        return None
    variables = list(limited.plan.section.lateral.variables)
    at_zero = {q1: -theta_1.subs(q1, 0) / s1}
    w = [sp.sympify(e).subs(at_zero) for e in F[:3, 3]]
    z = [sp.sympify(e).subs(at_zero) for e in F[:3, 2]]
    if not set().union(*(e.free_symbols for e in w + z)) <= set(variables):
        return None
    # the roll frame before its turn (theta_j = 0): v = R^T d in it
    theta_j = robot.substitute(sp.Matrix([robot.joints[j].theta]), params)[0]
    before = F[:3, :3].subs(roll, sp.solve(theta_j, roll)[0])
    v_x, v_y = sign * before[2, 0], sign * before[2, 1]
    X = s_k * (v_x * sp.cos(mu_r) + v_y * sp.sin(mu_r))
    v_z = sign * z[2]
    V2 = 1 - v_z ** 2
    V = sp.sqrt(z[0] ** 2 + z[1] ** 2)
    condition = None
    if oriented:
        # the last joint: x_r the frame's x axis before the tool's turn about z; Y in the first joint's turn
        tool = sp.eye(4) if robot.tool is None else sp.Matrix(robot.tool)
        x_r = sp.Matrix(constraint.matrix) * tool[:3, :3].T * sp.Matrix([1, 0, 0])
        turn = sp.Symbol("theta_turn")
        dv = sp.Matrix([0, 0, sign])
        # (z x d) . x_r = z . (d x x_r): Y = s_n z . (x_r cos(mu_n) - (d x x_r) sin(mu_n)), z the world roll axis
        linear = _turned_linear(robot, z, s_n * (x_r * sp.cos(mu_n) - dv.cross(x_r) * sp.sin(mu_n)))
        if linear is None:
            world = sp.Matrix([sp.sympify(e) for e in F[:3, 2]]).subs(q1, s1 * (turn - theta_1.subs(q1, 0)))
            Y = s_n * ((world.T * x_r)[0] * sp.cos(mu_n) - (world.cross(dv).T * x_r)[0] * sp.sin(mu_n))
        else:
            Y = linear[0] * sp.cos(turn) + linear[1] * sp.sin(turn) + linear[2]
    base = [w[0], w[1], w[2] + length * sign]
    unit = [z[0] / V, z[1] / V]
    cos_p = numpy_constant(sp.cos(h_p))[1]
    section = limited.plan.section.lateral
    zero, periodic = [(0.0, 0.0)] * len(variables), section.periodic
    roots = []
    # A cone's outer proofs hold every approach a within c of d: the map's outer enclosures (FlangeMap.enclose_outer)
    # and its conditions, which move by at most c (the pitch: the angle from z to the approach moves by c) and 2 c
    # (the roll: X and V are 1-Lipschitz in the approach) when a leaves d (docs/methods.md section 8)
    slack = None if cone == 0 else (numpy_constant(cone)[1], numpy_constant(2 * cone)[1])
    for sigma in (1, -1):
        lateral = _same_limits(FlangeMap(base, unit, sigma * factor, variables, zero, periodic, axis=z, cone=cone,
                                         length=length, sign=sign), section)
        p = lateral.expressions
        square = _same_limits(SquareMap(p[0] ** 2 + p[1] ** 2, p, variables, zero, periodic, lateral=lateral),
                              section)
        plan = Turned(RadialMap(square, lateral, None), None, False)
        turned_root = replace(limited, plan=plan, elbow=None)
        # the pitch within its limits, and the roll within its own (both free of the first joint's turn): every
        # configuration of this solution meets them, so its outer proofs leave the joint boxes that break one
        sides = [(-s_k * s_n * (v_z * sp.cos(mu_p) + sigma * V * sp.sin(mu_p)), cos_p)]
        if not roll_full:
            sides.append((-sigma * X - sp.cos(h_r) * V, 0.0))
        if oriented:
            condition = SpinCondition(turn, X, Y, V2, None if roll_full else sp.cos(h_r) ** 2, sp.cos(h_n) ** 2,
                                      root=sigma, linear=linear)
        # an exact approach: the conditions are free of the first joint's turn, each proof holds on its arc
        roots.append((sigma, constrained_turn(turned_root, sides, condition, prune=True, arcs=not oriented,
                                              slack=None if slack is None else slack[:len(sides)])))
    outer = None
    if cone != 0:
        # The cone's outer proofs: the tool point's own section (the joints before the last), its joint boxes
        # left where the approach is proved outside the cone (a_z, free of the first joint's turn); its direction
        # proofs are inner proofs of the cone too (the approach proved within it over each Krawczyk box)
        whole = limited_turn(structure_of(robot, parameters), reach_model(robot, parameters))
        if whole is None or whole.plan.inverse is not None:
            return None
        a_z = sign * sp.sympify(T[2, 2]).subs(at_zero)
        if not a_z.free_symbols <= set(whole.plan.section.lateral.variables):
            return None
        outer = constrained_turn(whole, [(a_z, numpy_constant(sp.cos(cone))[1])], prune=True, arcs=True)
    # the ring's cells are read about the first joint's axis: its frame must not be turned from the world's
    upright = first_frame(robot, dict(parameters) or None)[:3, :3] == sp.eye(3)
    return OffsetFlange(tuple(roots), sign, outer, float(cone), wrist_ring(robot, parameters) if upright else None)


@dataclass(frozen=True)
class PoseStructure:
    """How the constrained workspace is paved: ``model`` over ``(x, y, z)``, or over the section ``(u, v)`` of
    a robot turned by its first joint (``revolved``, the position's section structure) when the constraint is
    invariant under that turn (a cone about the vertical).

    Parameters
    ----------
    model : PoseModel
        The model paved.
    revolved : Revolved, optional
        The position's section structure; None: ``model`` is over ``(x, y, z)``.
    turned : Turned, optional
        The position's section structure when the lateral offset varies (the UR5): ``model`` is then over
        ``(t, z) = (rho^2, z)`` (:func:`squared_volume_bracket`, :class:`SquaredTest`).
    centre : WristCentre, optional
        A cone about the vertical through the wrist centre's section (:class:`WristCentre`); ``model`` is then
        None.
    flange : OffsetFlange, optional
        A constant orientation with a vertical approach through the sections of the wrist's solutions
        (:class:`OffsetFlange`); ``model`` is then None.
    """

    model: PoseModel | None
    revolved: Revolved | None = None
    turned: Turned | None = None
    centre: WristCentre | None = None
    flange: OffsetFlange | None = None

    @property
    def sectioned(self) -> bool:
        """Whether ``model`` is over a section turned by the first joint (either structure).

        Returns
        -------
        bool
            ``revolved`` or ``turned`` is set.
        """
        return self.revolved is not None or self.turned is not None


def _section_structure(robot: DHRobot, parameters: tuple, constraint: PoseConstraint, axis, proof_cone,
                       section_robot: DHRobot, tuning: Tuning, offset=None) -> PoseStructure | None:
    """The section structure when the robot is turned by its first joint (the position's
    :class:`~workspace_sym.serial.structure.Revolved`: standard DH, no base, ``q_1`` only in ``theta_1``) and the
    cone's axis is vertical:
    then ``p = Rz(theta_1) p'`` and ``a = Rz(theta_1) a'`` with ``p', a'`` the pose at ``theta_1 = 0``, and
    ``a . d = a' . d``, so the admissible configurations of the other joints do not depend on ``theta_1``.
    ``section_robot`` has the position paved (the robot, or the wrist centre's chain shifted by a tool offset)."""
    if constraint.kind != "cone" or constraint.direction[0] != 0 or constraint.direction[1] != 0:
        return None
    turn = revolved(reach_model(section_robot, parameters))
    if turn is None:
        return _squared_structure(robot, parameters, constraint, axis, proof_cone, section_robot, tuning, offset)
    params = dict(parameters) or None
    q1 = robot.q[0]
    theta = robot.substitute(robot.joints[0].theta, params)
    zero = {q1: -theta.subs(q1, 0) / sp.diff(theta, q1)}
    approach = [e.subs(zero) for e in axis]
    position = list(turn.section.expressions)
    variables, limits, periodic = _joints_of(robot, position + approach, params)
    if q1 in variables:
        return None
    exprs, variables, limits, periodic = _summed_angles(robot, params, position + approach, variables, limits,
                                                        periodic)
    position, approach = exprs[:len(position)], exprs[len(position):]
    model = PoseModel(position, approach, None, constraint, variables, limits, periodic, (sp.Symbol("u"),
                                                                                         sp.Symbol("v")),
                      proof_cone=proof_cone, tuning=tuning)
    return PoseStructure(model, turn)



def _squared_structure(robot: DHRobot, parameters: tuple, constraint: PoseConstraint, axis, proof_cone,
                       section_robot: DHRobot, tuning: Tuning, offset=None) -> PoseStructure | None:
    """The section ``(t, z) = (rho^2, z)`` of an arm turned by its first joint with a lateral offset that varies
    (:func:`~workspace_sym.serial.section.turned`: ``p = Rz(theta_1) w(q')``, ``w = (u, c, v)``, no base
    transform, a whole turn), for a cone about the vertical: ``a = Rz(theta_1) a'`` and ``a . d = a' . d``, so a
    point of cylindrical coordinates ``(rho, psi, z)`` is reached with the constraint iff some admissible ``q'``
    has ``u^2 + c^2 = rho^2`` and ``v = z`` (then ``theta_1`` turns ``(u, c)`` to the point's polar angle).  The
    section is paved in ``t = rho^2``, where the solid's volume is ``pi`` times the area
    (:func:`squared_volume_bracket`).  None when the structure is not there."""
    params = dict(parameters) or None
    turn = turned(reach_model(section_robot, parameters))
    if turn is None or not turn.full:
        return None
    if section_robot.base is not None:
        # The first joint's axis is B's z: the cone's (vertical) axis must be along it, so that turning the
        # first joint keeps a . d (then a . d = a(theta_1 = 0) . d, as without a base).
        z_axis = sp.Matrix(section_robot.base)[:3, 2]
        if z_axis[0] != 0 or z_axis[1] != 0:
            return None
    w = list(turn.section.lateral.expressions)
    q1 = robot.q[0]
    theta = robot.substitute(robot.joints[0].theta, params)
    zero = {q1: -theta.subs(q1, 0) / sp.diff(theta, q1)}
    approach = [e.subs(zero) for e in axis]
    variables, limits, periodic = _joints_of(robot, w + approach, params)
    if q1 in variables:
        return None
    exprs, variables, limits, periodic = _summed_angles(robot, params, w + approach, variables, limits, periodic)
    w, approach = exprs[:3], exprs[3:]
    position = [w[0] ** 2 + w[1] ** 2, w[2]]
    model = PoseModel(position, approach, None, constraint, variables, limits, periodic,
                      (sp.Symbol("t"), sp.Symbol("v")), proof_cone=proof_cone, tuning=tuning, square=w,
                      offset=offset)
    return PoseStructure(model, turned=turn)


class SquaredTest:
    """Classify boxes of ``(x, y, z)`` from a paving of the section ``(t, z) = (rho^2, z)``
    (:func:`_squared_structure`): the box in the first joint's frame (``B^-1``, outward-rounded), then the
    rectangle of ``(x^2 + y^2, z)`` over it (outward-rounded): in cells proved inside it makes the box inner (the
    first joint turns a whole turn), in cells proved outside (or beyond the grid, which covers the section's
    enclosure) outer.

    Called with ``(N, 3, 2)`` boxes, it returns the masks ``(is_in, is_out)`` (never both).

    Parameters
    ----------
    grid : CellGrid
        The grid of the section ``(t, z)``.
    classes : numpy.ndarray
        The verdict code of each cell of ``grid``.
    inverse : tuple, optional
        ``B^-1`` as :attr:`~workspace_sym.serial.section.Turned.inverse` holds it; None for no base transform.
    """

    def __init__(self, grid: CellGrid, classes: np.ndarray, inverse=None):
        self.grid, self.inverse = grid, inverse
        self.inside = grid.prefix(classes, INNER)
        self.outside = grid.prefix(classes, OUTER)

    def __call__(self, X: np.ndarray):
        X = to_first_frame(self.inverse, X)
        with np.errstate(all="ignore"):
            t = arith.add(arith.sqr((X[:, 0, 0], X[:, 0, 1])), arith.sqr((X[:, 1, 0], X[:, 1, 1])))
        t = (np.maximum(t[0], 0.0), t[1])      # x^2 + y^2 >= 0 (exact): a box touching the axis rounds 0 down
        rect = np.stack([np.stack(t, axis=1), X[:, 2]], axis=1)
        finite = np.isfinite(rect).all(axis=(1, 2))
        inner = finite & self.grid.all_in_class(self.inside, rect, outside_counts=False)
        outer = finite & self.grid.all_in_class(self.outside, rect, outside_counts=True)
        return inner, outer & ~inner


def squared_volume_bracket(grid: CellGrid, classes: np.ndarray) -> tuple[float, float]:
    """Certified bracket of the volume of the solid of revolution (a whole turn) of a section paved in
    ``(t, z) = (rho^2, z)``: ``dV = 2 pi rho drho dz = pi dt dz``, so a cell ``[t0, t1] x [z0, z1]`` (``t``
    clipped at 0) turns into ``pi (t1 - t0) (z1 - z0)``; the cells proved inside give the lower bound, those not
    proved outside the upper one (outward-rounded, summed exactly).

    Parameters
    ----------
    grid : CellGrid
        The grid of the section ``(t, z)``.
    classes : numpy.ndarray
        The verdict code of each cell.

    Returns
    -------
    lo : float
        A lower bound of the volume.
    hi : float
        An upper bound.

    Examples
    --------
    >>> grid = CellGrid(np.array([[0.5, 1.5], [0.5, 1.5]]), 1.0)      # edges -1, 0, 1, 2, 3
    >>> classes = np.full(grid.shape, OUTER, dtype=np.int8)
    >>> classes[1, 1], classes[2, 1] = INNER, UNDECIDED       # t in [0, 1] and [1, 2], z in [0, 1]
    >>> lo, hi = squared_volume_bracket(grid, classes)        # a cylinder of radius 1, then of radius sqrt(2)
    >>> bool(lo <= math.pi <= lo + 1e-14), bool(2 * math.pi <= hi <= 2 * math.pi + 1e-13)
    (True, True)
    """
    e0, e1 = grid.edges
    pi_lo, pi_hi = numpy_constant(sp.pi)
    t0, t1 = np.maximum(e0[:-1], 0.0), np.maximum(e0[1:], 0.0)
    dt = arith.sub((t1, t1), (t0, t0))
    dz = arith.sub((e1[1:], e1[1:]), (e1[:-1], e1[:-1]))
    area = arith.mul((dt[0][:, None], dt[1][:, None]), (dz[0][None, :], dz[1][None, :]))
    volume = arith.mul((np.float64(pi_lo), np.float64(pi_hi)), area)
    low, high = volume[0][classes == INNER], volume[1][classes != OUTER]
    return ExactSum.of(low[low > 0]).value_down, ExactSum.of(high[high > 0]).value_up


@lru_cache(maxsize=8)
def pose_structure(robot: DHRobot, parameters: tuple, constraint: PoseConstraint,
                   tuning: Tuning = DEFAULT) -> PoseStructure:
    """How ``robot``'s workspace under ``constraint`` is paved (cached per robot, parameter values, constraint
    and tuning): the constrained section of a robot turned by its first joint when the constraint is a cone
    about the vertical, else the pose model over ``(x, y, z)``; a constant orientation reduced to an exact
    direction, and a cone on a roll-pitch wrist to a cone on its roll axis (module docstring).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.
    constraint : PoseConstraint
        The constraint.
    tuning : Tuning
        The tuning of the pose model.

    Returns
    -------
    PoseStructure
        The model and, for the section, the position's section structure.

    Raises
    ------
    InvalidParameterError
        ``robot`` not a DH robot, a parameter without a value, a position not moving in all three coordinates,
        or ``every=True`` with a positive cone on a robot without a roll-pitch wrist.
    JointLimitError
        A joint without a usable range (:func:`~workspace_sym.serial.model.joint_range`).
    """
    if not isinstance(robot, DHRobot):
        raise InvalidParameterError(f"robot: reach needs a serial DH robot; got {type(robot).__name__}",
                                    parameter="robot")
    params = dict(parameters) or None
    T = robot.substitute(robot.fk(), params)
    free = T.free_symbols - set(robot.q)
    if free:
        raise InvalidParameterError(f"parameters: give values for {', '.join(sorted(map(str, free)))} "
                                    "(the pose must be numeric apart from the joints)", parameter="parameters")
    position = list(T[:3, 3])
    if not all(e.free_symbols for e in position):
        raise InvalidParameterError(f"robot: an approach or orientation constraint needs a spatial robot whose "
                                    f"three position coordinates move; {robot.name}'s position is {position}",
                                    parameter="robot")
    section_robot: DHRobot | None = robot
    offset = _tool_offset(robot, params, constraint, T)
    if offset is not None:
        k, position = offset
        T = sp.Matrix(T)
        T[:3, 3] = sp.Matrix(position)
        # The chain to o_k with the offset's vertical part in d_1 (a translation along z_0, the turn's axis):
        # its section is that of o_k + R t when R t is vertical, the only case a vertical cone's section needs.
        lift = sp.Matrix(position) - robot.substitute(robot.fk(k), params)[:3, 3]
        # With a base transform B, d_1 translates along B's z: the lift in B's frame (B's rotation transposed).
        if robot.base is not None and robot.convention == "standard":
            lift = (sp.Matrix(robot.base)[:3, :3].T * lift).applyfunc(sp.simplify)
        if lift[0] == 0 and lift[1] == 0 and (robot.base is None or robot.convention == "standard"):
            joints = list(robot.joints[:k])
            joints[0] = replace(joints[0], d=joints[0].d + lift[2])
            section_robot = DHRobot(joints, convention=robot.convention, name=f"{robot.name} (wrist centre)",
                                    parameters=robot.parameters, units=robot.units, base=robot.base)
        else:
            section_robot = None
    reduced = _spin_reduction(robot, params, constraint, T)
    axis, proof_cone = list(T[:3, 2]), None
    wrist = wrist_reduction(robot, params, reduced, T)
    if not isinstance(wrist, str):
        axis, reduced, proof_cone = wrist
    elif reduced.every and reduced.cone != 0:
        raise InvalidParameterError(
            f"every=True (every direction of a {reduced.degrees:g} degree cone, the dextrous workspace) is not "
            f"implemented for {robot.name}: it is proved only for arms with a roll-pitch wrist, two revolute joints "
            "that turn the approach axis without moving the tool point, the first (roll) through a full turn, the "
            "second (pitch) tilting the approach from the roll axis, such as joints 4 and 5 of the Puma 560 "
            f"(docs/methods.md section 8), and {robot.name} has none: {wrist}; no certified answer is given: use "
            "every=False (some direction of the cone) or cone=0", parameter="every")
    # A tool point at a length along the approach: pairs dropped on the admissible positions too (_OffsetEnclosure)
    along = _approach_offset(robot, params, reduced) if offset is None else None
    structure = None if section_robot is None else _section_structure(robot, parameters, reduced, axis, proof_cone,
                                                                       section_robot, tuning, along)
    if structure is not None:
        return structure
    # A tool along the approach from a wrist centre (a cone) or a constant orientation the last joint cannot spin
    # through a full turn: through the wrist centre's section when the structure is there
    centre = wrist_centre(robot, parameters, reduced) if along is not None or reduced.kind == "orientation" else None
    if centre is not None:
        return PoseStructure(None, centre=centre)
    flange = offset_flange(robot, parameters, reduced)
    if flange is not None:
        return PoseStructure(None, flange=flange)
    rotation = T[:3, :3]
    quantities = axis if reduced.kind == "cone" else list(rotation)
    variables, limits, periodic = _joints_of(robot, position + quantities, params)
    return PoseStructure(PoseModel(position, axis, rotation, reduced, variables, limits, periodic, TASK,
                                   proof_cone=proof_cone, tuning=tuning, offset=along))


@dataclass(frozen=True)
class PoseStep:
    """One generation of the pairs method with a tool constraint, on a chunk of task boxes with their pairs
    (:func:`~workspace_sym.serial.pairs.pave_pairs`): the inner, boundary and outer boxes, the children of the
    split boxes and their pairs.  Each pair carries an arm box, a wrist value per wrist joint and an admissibility
    status (:meth:`PoseModel.distribute`); a task box is tried from two seeds (its first and last pair: often two
    branches of the inverse kinematics).

    Called with ``(T, Q, owner)``, it returns what :func:`~workspace_sym.serial.pairs.split_pairs` returns.

    Parameters
    ----------
    model : PoseModel
        The constrained model.
    delta : float
        Undecided task boxes of size at most ``delta`` are boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured.
    inner_depth : int
        Levels of pieces a task box about to become a boundary box is tried in.
    max_pairs, min_pairs : int
        The caps of pairs per task box (:func:`~workspace_sym.serial.pairs.caps`).
    root_measure : float
        The measure of the root task box.
    """

    model: PoseModel
    delta: float
    size: str
    inner_depth: int
    max_pairs: int
    min_pairs: int
    root_measure: float

    def __call__(self, part):
        T, Q, owner = part
        model = self.model
        Q, owner = model.distribute(T, Q, owner, caps(T, self.max_pairs, self.min_pairs, self.root_measure))
        is_out = np.bincount(owner, minlength=len(T)) == 0
        live, first = np.unique(owner, return_index=True)
        is_in = np.zeros(len(T), dtype=bool)
        if len(live):
            last = box_sizes(T[live], self.size) <= self.delta
            depth = np.where(last, self.inner_depth, 0)
            is_in[live] = prove_in_pieces(model.proof, T[live], model.seeds(Q[first]), depth)
            # A second seed: the last joint box of each task box (another branch of the inverse kinematics).
            again = np.nonzero(~is_in[live])[0]
            if len(again):
                ends = np.searchsorted(owner, live[again], side="right") - 1
                is_in[live[again]] = prove_in_pieces(model.proof, T[live[again]], model.seeds(Q[ends]),
                                                      depth[again])
        return split_pairs(T, Q, owner, is_in, is_out, self.delta, self.size)


def constraint_from(approach=None, cone=None, every: bool = False, orientation=None, rpy=None) -> PoseConstraint:
    """The constraint of a :class:`~workspace_sym.serial.api.Pose`'s fields (exactly one of ``approach`` and
    ``orientation`` / ``rpy``).

    Parameters
    ----------
    approach : sequence of three numbers, optional
        The cone's axis (:func:`approach_constraint`).
    cone : float, optional
        The cone's half-angle in degrees; only with ``approach``.
    every : bool
        Every direction of the cone; only with ``approach``.
    orientation : 3 x 3 array_like, optional
        A constant rotation (:func:`orientation_constraint`).
    rpy : sequence of three angles, optional
        A constant rotation as roll, pitch, yaw.

    Returns
    -------
    PoseConstraint
        The constraint, checked.

    Raises
    ------
    InvalidParameterError
        Both kinds or neither given, ``cone`` or ``every`` without ``approach``, or a value refused by
        :func:`approach_constraint` or :func:`orientation_constraint`.
    ExpressionError
        An ``rpy`` angle given as text that the expression reader refuses.
    """
    if approach is not None and (orientation is not None or rpy is not None):
        raise InvalidParameterError("give either approach (with cone) or orientation / rpy, not both; got "
                                    f"approach={approach!r} and orientation={orientation!r}, rpy={rpy!r}",
                                    parameter="approach")
    if approach is not None:
        return approach_constraint(approach, cone, every)
    if cone is not None or every:
        raise InvalidParameterError(f"cone and every need approach (the axis of the cone); got cone={cone!r}",
                                    parameter="cone")
    return orientation_constraint(orientation, rpy)



def section_classes(model: PoseModel, width: float, run, *, tuning: Tuning = DEFAULT, chunk: int = 200_000,
                    symmetric: bool = True):
    """A :class:`CellGrid` over the constrained section and the class of each cell, from a pairs paving whose
    boxes are unions of cells (cells of a power-of-two width on a grid of its multiples: every edge and every
    midpoint is a float exactly); ``(grid, classes, evaluated, reason)``.  ``run`` is the run's budget.

    Parameters
    ----------
    model : PoseModel
        The constrained model over the section ``(u, v)``.
    width : float
        The cells' width asked for (rounded to the nearest power of two).
    run : RunBudget
        The run's budget.
    tuning : Tuning
        ``pose_inner_depth``, ``pose_max_pairs``, ``min_pairs``.
    chunk : int
        About this many pairs in one chunk of the pairs loop.
    symmetric : bool
        The first axis's range symmetric about 0 (the section ``(u, v)``, :func:`section_volume_bracket`);
        False: from the enclosure's lower end (the section ``(t, z)``, :func:`squared_volume_bracket`).

    Returns
    -------
    tuple
        ``(grid, classes, evaluated, reason)``: the :class:`~workspace_sym.interval.image.CellGrid`, the verdict
        code of each cell (the cells of a stopped run not proved stay undecided), the task boxes evaluated,
        and why the budget stopped it (``""``: it did not).
    """
    w = 2.0 ** round(math.log2(width))
    root = model.position.enclose(model.position.limits[None])[0]
    # The u range is made symmetric about 0 (edges at odd multiples of w / 2 both ways) so that each cell's
    # mirror, the other branch of the turn, is a cell (section_volume_bracket).
    reach_u = math.ceil(max(-root[0, 0], root[0, 1]) / w) * w
    first = [-reach_u, reach_u] if symmetric else [math.floor(root[0, 0] / w) * w, root[0, 1]]
    corner = np.array([first, [math.floor(root[1, 0] / w) * w, root[1, 1]]])
    grid = CellGrid(corner, w)
    lo = np.array([e[0] for e in grid.edges])
    side = w * 2 ** math.ceil(math.log2(max(len(e) - 1 for e in grid.edges)))
    square = np.stack([lo, lo + side], axis=1)
    step = PoseStep(model, w, "width", tuning.pose_inner_depth, tuning.pose_max_pairs, tuning.min_pairs,
                    float(np.prod(square[:, 1] - square[:, 0])))
    keeper = BoxStore(2)
    with section_bar(run.showing) as show:      # the section's bar, as for the arms without a constraint
        _, _, _, evaluated, reason = pave_pairs(step, square[None].copy(), model.root_pairs(), np.zeros(1, dtype=int),
                                                budget=run, keeper=keeper, chunk=chunk, show=show)
    inner, outer = [keeper.arrays("inner")], [keeper.arrays("outer")]
    classes = np.full(grid.shape, UNDECIDED, dtype=np.int8)
    # A run stopped by the budget keeps what it proved: its pending boxes stay undecided.
    for value, parts in ((INNER, inner), (OUTER, outer)):
        boxes = np.concatenate([p for p in parts if len(p)] or [np.empty((0, 2, 2))])
        first = np.rint((boxes[:, :, 0] - lo) / w).astype(np.int64)
        last = np.rint((boxes[:, :, 1] - lo) / w).astype(np.int64)
        exact = np.all((lo + first * w == boxes[:, :, 0]) & (lo + last * w == boxes[:, :, 1]), axis=1)
        first, last = first[exact], last[exact]
        shape = np.array(grid.shape)
        first, last = np.minimum(first, shape), np.minimum(last, shape)
        counts = np.zeros((grid.shape[0] + 1, grid.shape[1] + 1), dtype=np.int64)
        np.add.at(counts, (first[:, 0], first[:, 1]), 1)
        np.add.at(counts, (first[:, 0], last[:, 1]), -1)
        np.add.at(counts, (last[:, 0], first[:, 1]), -1)
        np.add.at(counts, (last[:, 0], last[:, 1]), 1)
        classes[np.cumsum(np.cumsum(counts, axis=0), axis=1)[:-1, :-1] > 0] = value
    return grid, classes, evaluated, reason



def section_volume_bracket(grid: CellGrid, classes: np.ndarray, revolved) -> tuple[float, float]:
    """Certified bracket of the volume of the solid ``{Rz(theta) (u, c, v)}``, ``theta`` over the first joint's
    range and ``(u, v)`` over a section set ``S`` whose cells ``classes`` classify (Pappus), rounded outward.

    In cylindrical coordinates the point ``(u, c, v)`` turned by ``theta`` has height ``v``, ``r^2 = s^2 + c^2``
    with ``s = |u|`` (so ``r dr = s ds``) and polar angle ``theta + alpha`` (``u >= 0``) or
    ``theta + pi - alpha`` (``u < 0``), ``alpha = atan(c / s)``.  The volume is the integral over ``(s, v)`` of
    ``A(s, v) s ds dv`` where ``A`` is the measure of the angles reached: ``L`` (the range's length) when one of
    ``(s, v)`` and ``(-s, v)`` is in ``S``, the union of the two arcs, ``min(2 pi, L + min(d, L))`` with
    ``d = pi - 2 |alpha|`` their offset, when both are (``2 pi`` for a whole turn).  A folded cell
    ``[s0, s1] x [v0, v1]`` adds ``A (s1^2 - s0^2) (v1 - v0) / 2``: to the lower bound with ``A`` of its proved
    inner cells (``u`` and its mirror ``-u``), to the upper bound with ``A`` of those not proved outer.  The grid's
    first axis must be symmetric about ``u = 0``; ``revolved`` is the position's section structure
    (:class:`~workspace_sym.serial.structure.Revolved`: ``c``, ``inner_range``, ``outer_range``, ``full``).

    Parameters
    ----------
    grid : CellGrid
        The grid of the section ``(u, v)``, symmetric about ``u = 0``.
    classes : numpy.ndarray
        The verdict code of each cell.
    revolved : Revolved
        The position's section structure.

    Returns
    -------
    lo : float
        A lower bound of the volume.
    hi : float
        An upper bound of the volume.

    Raises
    ------
    ValueError
        The grid is not symmetric about ``u = 0``.

    Examples
    --------
    >>> grid = CellGrid(np.array([[-1.0, 1.0], [0.0, 1.0]]), 0.5)     # edges -1.75, -1.25, ..., 1.75 along u
    >>> classes = np.full(grid.shape, OUTER, dtype=np.int8)
    >>> classes[2:5, 2:4] = INNER                                        # |u| <= 0.75, 0.25 <= v <= 1.25
    >>> from types import SimpleNamespace
    >>> turn = SimpleNamespace(c=(0.0, 0.0), inner_range=(-np.pi, np.pi), outer_range=(-np.pi, np.pi), full=True)
    >>> lo, hi = section_volume_bracket(grid, classes, turn)
    >>> lo <= math.pi * 0.75 ** 2 * 1.0 <= hi and hi - lo < 1e-12      # a cylinder of radius 0.75, height 1
    True
    """
    e0, e1 = grid.edges
    n = len(e0) - 1
    if not np.array_equal(e0, -e0[::-1]):
        raise ValueError("section_volume_bracket needs a grid symmetric about u = 0")
    half = np.arange(n // 2, n)                 # the cells with u > 0 somewhere, and their mirrors
    s0, s1 = np.maximum(e0[half], 0.0), e0[half + 1]
    plus, minus = classes[half], classes[n - 1 - half]
    ring = arith.mul(arith.sub(arith.sqr((s1, s1)), arith.sqr((s0, s0))), (0.5, 0.5))
    ring = arith.mul((ring[0][:, None], ring[1][:, None]), arith.sub((e1[None, 1:], e1[None, 1:]),
                                                                   (e1[None, :-1], e1[None, :-1])))
    pi_lo, pi_hi = numpy_constant(sp.pi)
    shape = plus.shape
    if revolved.full:
        one = both = (np.full(shape, 2 * pi_lo), np.full(shape, 2 * pi_hi))
        length = (2 * pi_lo, 2 * pi_hi)
    else:
        (a_in, b_in), (a_out, b_out) = revolved.inner_range, revolved.outer_range
        length = (max(float(arith.down(np.float64(b_in - a_in))), 0.0), float(arith.up(np.float64(b_out - a_out))))
        # The offset d = pi - 2 atan(|c| / s) of the two arcs grows with s: its least over the cell at s0, its
        # greatest at s1 (ANGLE_PAD covers atan's rounding).
        c_lo, c_hi = revolved.c
        c_small = 0.0 if c_lo <= 0 <= c_hi else min(abs(c_lo), abs(c_hi))
        c_large = max(abs(c_lo), abs(c_hi))
        with np.errstate(divide="ignore", invalid="ignore"):      # s0 = 0: c / 0 is inf (0 / 0 is c = 0)
            near = np.arctan(arith.up(c_large / s0)) + ANGLE_PAD
            far = np.arctan(arith.down(c_small / s1)) - ANGLE_PAD
        d_lo = np.where(c_large == 0.0, pi_lo, np.maximum(arith.down(pi_lo - 2 * near), 0.0))
        d_hi = np.minimum(arith.up(pi_hi - 2 * np.maximum(far, 0.0)), pi_hi)
        union_lo = np.minimum(arith.down(length[0] + np.minimum(d_lo, length[0])), 2 * pi_lo)
        union_hi = np.minimum(arith.up(length[1] + np.minimum(d_hi, length[1])), 2 * pi_hi)
        one = (np.full(shape, length[0]), np.full(shape, min(length[1], 2 * pi_hi)))
        both = (np.repeat(union_lo[:, None], shape[1], axis=1), np.repeat(union_hi[:, None], shape[1], axis=1))
    low = np.where((plus == INNER) & (minus == INNER), both[0], np.where((plus == INNER) | (minus == INNER),
                                                                           one[0], 0.0))
    high = np.where((plus != OUTER) & (minus != OUTER), both[1], np.where((plus != OUTER) | (minus != OUTER),
                                                                            one[1], 0.0))
    lower = arith.mul((low, low), ring)[0]
    upper = arith.mul((high, high), ring)[1]
    return ExactSum.of(lower[low > 0]).value_down, ExactSum.of(upper[high > 0]).value_up

