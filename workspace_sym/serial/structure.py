"""How a spatial robot's workspace reduces to a map into the plane: the structures the section plans pave.

* :class:`Product`: position coordinates moved by disjoint sets of joints (a SCARA: ``x, y`` by two revolute
  joints, ``z`` by a prismatic one); the workspace is the product of their images.
* :class:`Revolved`: a first joint that turns everything after it with a constant lateral offset ``c``
  (standard DH, no base transform): ``p = Rz(theta_1) (u, c, v)``, the section ``(u, v)`` of the other joints.
* :class:`~workspace_sym.serial.section.Turned`: the same turn with a lateral offset that varies, or a rigid base
  transform first: the section ``(rho, z)`` in the first joint's frame.

:func:`structure_of` finds the first that applies (cached per robot and parameter values).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..interval.graph import numpy_constant
from ..interval.image import ImageMap
from ..kinematics import DHRobot
from ..symbolic import simplified
from .model import ReachModel, reach_model
from .section import Turned, first_joint_turn, turned

__all__ = ["Revolved", "revolved", "Product", "product", "structure_of"]


@dataclass(frozen=True)
class Revolved:
    """``p = Rz(theta_1) (u, c, v)``: the section map ``(u, v)`` of the other joints, the offset ``c`` (two
    floats enclosing it) and ``theta_1``'s range (outward and inward floats; ``full`` for a whole turn).

    Parameters
    ----------
    section : ImageMap
        The map ``q' -> (u, v)`` of the other joints.
    c : tuple
        ``(lo, hi)`` floats enclosing the lateral offset ``c``.
    outer_range : tuple
        ``(a, b)`` floats enclosing ``theta_1``'s range, in radians.
    inner_range : tuple
        ``(a, b)`` floats within ``theta_1``'s range, in radians.
    full : bool
        ``q_1`` turns the position through a whole period.
    """

    section: ImageMap
    c: tuple
    outer_range: tuple
    inner_range: tuple
    full: bool


def revolved(model: ReachModel) -> Revolved | None:
    """The section of a spatial robot turned by its first joint, or None when the structure is not there.

    Parameters
    ----------
    model : ReachModel
        The robot's reach model.

    Returns
    -------
    Revolved or None
        The structure (standard DH, no base transform, a spatial position, ``q_1`` turning everything after it
        with a constant lateral offset), or None.
    """
    robot = model.robot
    if robot.convention != "standard" or robot.base is not None or model.m != 3 or model.joints[:1] != [0]:
        return None
    turn = first_joint_turn(model)        # theta_1 = slope q1 + offset turns everything after it, nothing else
    if turn is None:
        return None
    q1, theta, slope = turn
    offset = theta.subs(q1, 0)
    # Standard DH without base: T = Rz(theta_1) Tz(d_1) Tx(a_1) Rx(alpha_1) ..., so p = Rz(theta_1) p(theta_1 = 0).
    p1 = [simplified(e.subs(q1, -offset / slope)) for e in model.position]
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
    return Revolved(section, numpy_constant(p1[1]), (lo_f[0], hi_f[1]), (lo_f[1], hi_f[0]), full)


@dataclass(frozen=True)
class Product:
    """Position coordinates moved by disjoint sets of joints: the workspace is the product of their images.
    ``plane`` are the two task axes of a group of two coordinates (or ``()``), ``section`` its map;
    ``intervals`` hold, per single coordinate, its axis, an outer enclosure of its image and an inner one
    (or None).

    Parameters
    ----------
    plane : tuple
        The two task axes moved together (indices), or ``()``.
    section : ImageMap or None
        Their map into the plane, or None.
    intervals : tuple
        ``(axis, outer, inner)`` per coordinate moved alone: ``outer`` a ``(lo, hi)`` enclosure of its image,
        ``inner`` a ``(lo, hi)`` inside it, or None.
    """

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


def product(model: ReachModel) -> Product | None:
    """The product structure of a spatial robot's position (a SCARA: x, y by two joints, z by a third).

    Parameters
    ----------
    model : ReachModel
        The robot's reach model.

    Returns
    -------
    Product or None
        The structure when the coordinates fall into two groups or more moved by disjoint sets of joints, else
        None.
    """
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
    return Product(plane, section, tuple(intervals))


@lru_cache(maxsize=16)
def structure_of(robot: DHRobot, parameters: tuple) -> Revolved | Product | Turned | None:
    """How a spatial robot's workspace reduces to a map into the plane: a product of images, a section
    turned by the first joint (constant lateral offset, or any in cylindrical coordinates), or None.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    parameters : tuple
        Its parameter values as ``(name, value)`` pairs.

    Returns
    -------
    Revolved or Product or Turned or None
        The first structure found, in the order :class:`Product`, :class:`Revolved`,
        :class:`~workspace_sym.serial.section.Turned`.
    """
    model = reach_model(robot, parameters)
    return product(model) or revolved(model) or turned(model)
