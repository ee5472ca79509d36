"""Joint axes to DH rows: a chain of URDF-shaped joints as an exact standard-DH robot.

A URDF-shaped joint is a constant transform (``origin``: ``xyz`` then
``Rz(yaw) Ry(pitch) Rx(roll)``) followed by a rotation about ``axis``
(revolute, continuous) or a translation along it (prismatic); fixed joints are
constant transforms only.  A chain is the product of these transforms.  The
URDF reader (:mod:`.urdf`) hands over yourdfpy's joints, the MJCF reader
(:mod:`.mjcf`) joints it builds from bodies: :func:`dh_robot` reads of a joint
its ``name``, ``type`` (``"revolute"``, ``"continuous"``, ``"prismatic"`` or
``"fixed"``), ``origin`` (a 4 x 4 array, or None), ``axis`` (three numbers, or
None for ``(1, 0, 0)``) and ``limit`` (``lower`` and ``upper``; None for a
continuous joint).

**Every such chain has a standard DH table** once a constant base transform
(frame 0 must have its z axis on joint 1's axis) and a tool transform (from
the last DH frame to the tip link) are allowed: between two successive joint
axes the common normal gives ``a`` and ``alpha``, and the two other numbers of
an origin (a rotation about, and a shift along, the next joint's axis) go
into that joint's ``theta`` offset and ``d`` (Denavit and Hartenberg 1955;
Spong, Hutchinson, Vidyasagar, *Robot Modeling and Control*, section 3.2).
Skew axes are no obstacle, a URDF simply spends six numbers where DH needs
four.  So :func:`dh_robot` returns a :class:`~workspace_sym.kinematics.DHRobot`
(standard convention, with ``base`` and ``tool``) whose ``fk()`` equals the
chain's product identically.  What the extraction needed is stated in
``robot.input_notes``: whether the table alone starts at the base link (no base
transform), and where successive axes are parallel (the DH frame is then not
unique: ``d = 0`` is chosen).

Numbers are snapped as in :mod:`workspace_sym.snap`: lengths become the
decimals of the file, ``rpy`` angles within ``tol`` of a multiple of ``pi/360``
become that multiple (``1.57079632679`` is ``pi/2`` at the default 1e-9, the
rounded ``1.5708`` is not), axis components within ``tol`` of ``cos(k pi/12)``
become it, and the axis is normalised exactly.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import sympy as sp

from ..errors import URDFError
from ..expressions import check_joint_limits
from ..kinematics import DHJoint, DHRobot
from ..snap import Snapper, chop, snap_angle
from ..transforms import xyz_rpy

__all__ = ["dh_robot"]

_DUST = 1e-14


# ---------------------------------------------------------------------------- exact transforms
def _origin(joint, snapper: Snapper) -> sp.Matrix:
    """The joint's origin as an exact 4 x 4 transform (snapped), checked against the parsed floats."""
    from trimesh import transformations  # yourdfpy builds its origins with these; same convention

    M = np.eye(4) if joint.origin is None else np.asarray(joint.origin, dtype=float)
    where = f"joint {joint.name!r} origin"
    xyz = [snapper.length(v, f"{where} xyz") for v in M[:3, 3]]
    angles = transformations.euler_from_matrix(M, "sxyz")
    rpy = [snapper.angle(v, f"{where} rpy") for v in angles]
    T = xyz_rpy(xyz, rpy)
    gap = float(np.abs(np.array(T[:3, :3].evalf(), dtype=float) - M[:3, :3]).max())
    # snapping moves an entry of the rotation by at most the sum of the angles' moves (a snap from the digits
    # written, 1.5707963 -> pi/2, may move an angle by more than tol); beyond that the angles were recovered badly
    moved = sum(abs(float(r) - a) for r, a in zip(rpy, angles))
    if gap > 10 * snapper.tol + moved + 1e-12:   # Euler angles recovered badly near pitch = +-pi/2: keep the matrix
        T[:3, :3] = sp.Matrix(3, 3, [snapper.cosine(v, f"{where} rotation") for v in M[:3, :3].ravel()])
    return snapper.chop(T)


def _frame(R: sp.Matrix, o: sp.Matrix) -> sp.Matrix:
    return sp.Matrix.vstack(sp.Matrix.hstack(R, o), sp.Matrix([[0, 0, 0, 1]]))


def _axis(joint, snapper: Snapper) -> tuple[sp.Matrix, sp.Expr]:
    """Unit axis (exact) and the length of the axis as written (a prismatic joint moves ``q * axis``)."""
    raw = np.asarray(joint.axis if joint.axis is not None else (1.0, 0.0, 0.0), dtype=float)
    u = sp.Matrix([snapper.cosine(v, f"joint {joint.name!r} axis") for v in raw])
    norm2 = _clean(u.dot(u))
    if norm2 == 0 or float(norm2) < 1e-24:
        raise URDFError(f"path: joint {joint.name!r} has a zero axis {raw.tolist()}", parameter="path")
    norm = _clean(sp.sqrt(norm2))
    return (u if norm == 1 else (u / norm).applyfunc(_clean)), norm


def _clean(e):
    """Exact constants in their simplest radical form; a constant holding a float evaluated to one float."""
    e = sp.sympify(e)
    if e.is_Rational or not e.is_number:
        return e
    if e.has(sp.Float):   # exactness is lost already: one float, not a tree of sqrt(2) times floats
        return e.evalf(17)
    return _simplest(e)


@lru_cache(maxsize=4096)
def _simplest(e: sp.Expr) -> sp.Expr:
    """``radsimp(simplify(e))`` of an exact constant, once per constant (the entries of a chain's frames repeat
    the same few: sines and cosines of the snapped angles and their products)."""
    return sp.radsimp(sp.simplify(e))


def _is_zero(e, tol: float) -> bool:
    e = sp.sympify(e)
    if e.has(sp.Float):
        return abs(float(e)) <= tol
    return _clean(e) == 0


# ---------------------------------------------------------------------------- DH extraction
def dh_robot(name: str, chain, snapper: Snapper, base_link: str, tip_link: str) -> DHRobot:
    """The chain of joints ``chain`` (URDF-shaped, from ``base_link`` to ``tip_link``) as an exact DH robot.

    Parameters
    ----------
    name : str
        The robot's name.
    chain : sequence of joints
        The joints in order, each with ``name``, ``type``, ``origin``, ``axis`` and ``limit`` (see the module's
        description); fixed joints fold into the next transform.
    snapper : Snapper
        How floats are made exact (:class:`workspace_sym.snap.Snapper`); its notes join the robot's.
    base_link, tip_link : str
        The names of the chain's ends, for the notes.

    Returns
    -------
    DHRobot
        Standard DH with ``base`` and ``tool``; moving joint ``k`` gets the variable ``theta{k}`` (revolute,
        continuous) or ``d{k}`` (prismatic), the joint's position itself, and its limits (none when continuous).

    Raises
    ------
    URDFError
        A zero axis.
    JointLimitError
        A lower limit above the upper one.
    """
    lines, pending = [], sp.eye(4)
    notes: list[str] = []
    moving = []
    for j in chain:
        pending = pending * _origin(j, snapper)
        if j.type == "fixed":
            continue
        u, scale = _axis(j, snapper)
        lines.append((pending[:3, 3].applyfunc(_clean), (pending[:3, :3] * u).applyfunc(_clean)))
        moving.append((j, scale))
    T_tip = pending   # the tip link at q = 0, in the base link's frame
    # Float axes 1e-17 from parallel are parallel: their common normal would be 1e17 away.
    frames, rows = _dh_frames(lines, max(snapper.tol, 1e-12), notes, [j.name for j, _ in moving])
    joints, names = [], []
    for k, ((j, scale), (theta0, d0, a, alpha)) in enumerate(zip(moving, rows), start=1):
        if j.type == "prismatic":
            q = sp.Symbol(f"d{k}")
            theta, d, read = theta0, scale * q + d0, snapper.length
        else:
            q = sp.Symbol(f"theta{k}")
            theta, d, read = q + theta0, d0, snapper.angle
        limits = None
        if j.type != "continuous":
            raw = (j.limit.lower or 0.0, j.limit.upper or 0.0)
            limits = tuple(read(v, f"joint {j.name!r} limit") for v in raw)
            check_joint_limits(f"{j.name!r}", *limits, shown=raw)
        joints.append(DHJoint("P" if j.type == "prismatic" else "R", theta, d, a, alpha, q, limits, name=j.name))
        names.append(f"{q} = {j.name}")
    base = frames[0]
    tool = _rigid_inverse(frames[-1]) * T_tip
    # Floats (angles that did not snap) leave rounding dust of 1e-17 in exact zeros: dropped at 1e-14.
    base, tool = (snapper.chop(chop(M.applyfunc(_clean), _DUST)) for M in (base, tool))
    # Identity entry by entry: with floats kept, Float(1.0) != Integer(1) although it is the identity.
    base, tool = (None if all(e.is_zero for e in M - sp.eye(4)) else M for M in (base, tool))
    if base is None:
        notes.insert(0, f"DH table (standard) from {base_link!r}: frame 0 is the base link's frame")
    else:
        notes.insert(0, f"DH table (standard) from {base_link!r} with a base transform: joint 1's axis is not "
                        "the base link's z axis through its origin")
    notes.insert(1, f"joints {', '.join(names)}; tool transform to {tip_link!r}")
    chop_tol = None if snapper.exact else snapper.tol
    if chop_tol is None and snapper.tol > 0 and _has_floats(joints, base, tool):
        # angles off the grid stay floats even when reading exactly, and their products leave 1e-17 dust
        chop_tol = snapper.tol
        notes.append(f"floats kept (angles that snap to no exact value): float coefficients below {snapper.tol:g} "
                     "that their products leave are dropped")
    return DHRobot(joints, name=name, units="m", base=base, tool=tool, input_notes=notes + snapper.notes,
                   chop_tol=chop_tol)


def _has_floats(joints, base, tool) -> bool:
    """Whether a float is left in the table, the base or the tool."""
    values = [v for j in joints for v in (j.theta, j.d, j.a, j.alpha)]
    values += [e for M in (base, tool) if M is not None for e in M]
    return any(sp.sympify(v).has(sp.Float) for v in values)


def _rigid_inverse(F: sp.Matrix) -> sp.Matrix:
    R, o = F[:3, :3], F[:3, 3]
    return _frame(R.T, -R.T * o)


def _unit(v: sp.Matrix) -> sp.Matrix:
    n = _clean(sp.sqrt(_clean(v.dot(v))))
    return (v / n).applyfunc(_clean)


def _angle(sin_, cos_) -> sp.Expr:
    """``atan2(sin, cos)`` exactly (``pi/2``, ``atan(4/3)``), as a float when either is one."""
    sin_, cos_ = _clean(sin_), _clean(cos_)
    if sin_.has(sp.Float) or cos_.has(sp.Float):
        value = math.atan2(float(sin_), float(cos_))
        # float dust: atan2(1e-17, -1) is pi to the last bit, and printed as theta2 + 3.14159265358979
        exact = snap_angle(value, _DUST)
        return exact if exact is not None else sp.Float(value)
    return _clean(sp.atan2(sin_, cos_))


def _dh_frames(lines, tol, notes, names):
    """Standard DH frames 0..n (world 4 x 4 at q = 0) and rows ``(theta offset, d, a, alpha)``.

    ``lines[k] = (point, unit direction)`` of joint ``k + 1``'s axis at q = 0.
    Frame ``i`` has z on axis ``i + 1`` and x along the common normal of axes
    ``i`` and ``i + 1``; the last frame is frame ``n - 1`` turned by joint ``n``.
    """
    ex, ez = sp.Matrix([1, 0, 0]), sp.Matrix([0, 0, 1])
    o1, z = lines[0]
    origin = (o1 - o1.dot(z) * z).applyfunc(_clean)     # foot of the perpendicular from the base origin
    x = ex if _is_zero(z.cross(ez).norm() ** 2, tol ** 2) else _unit(ez.cross(z))
    x = _unit(x - x.dot(z) * z)
    frames = [_frame(sp.Matrix.hstack(x, z.cross(x), z), origin)]
    rows = []
    for i in range(1, len(lines)):
        p, w = lines[i]
        c = z.cross(w).applyfunc(_clean)
        if not _is_zero(c.dot(c), tol ** 2):
            x_new = _unit(c)
            a = _clean((p - origin).dot(x_new))
            if float(a) < 0:    # x along the normal from axis i to axis i + 1: a >= 0, as textbooks print it
                x_new, a = -x_new, -a
            k = _clean(z.dot(w))
            r = p - origin - a * x_new
            d = _clean((r.dot(z) - k * r.dot(w)) / (1 - k ** 2))
        else:
            r = p - origin
            perp = (r - r.dot(z) * z).applyfunc(_clean)
            d = sp.Integer(0)
            if _is_zero(perp.dot(perp), tol ** 2):
                x_new, a = x, sp.Integer(0)
                notes.append(f"axes of {names[i - 1]} and {names[i]} coincide: their common normal is chosen "
                             "as the previous one")
            else:
                a = _clean(sp.sqrt(_clean(perp.dot(perp))))
                x_new = (perp / a).applyfunc(_clean)
                notes.append(f"axes of {names[i - 1]} and {names[i]} are parallel: d = 0 is chosen for the "
                             "common normal")
        alpha = _angle(z.cross(w).dot(x_new), z.dot(w))
        theta = _angle(x.cross(x_new).dot(z), x.dot(x_new))
        rows.append((theta, d, a, alpha))
        origin = (origin + d * z + a * x_new).applyfunc(_clean)
        x, z = x_new, w
        frames.append(_frame(sp.Matrix.hstack(x, z.cross(x), z), origin))
    rows.append((sp.Integer(0), sp.Integer(0), sp.Integer(0), sp.Integer(0)))
    frames.append(frames[-1])
    return frames, rows
