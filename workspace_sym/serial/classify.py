"""Task boxes classified from a paved section: the tests of the section plans, and the driver that applies them.

A plan that paves a section (or the plane factor of a product) classifies the boxes of ``(x, y, z)`` with a test
``test(X) -> (is_in, is_out)`` built on the section's cells: :class:`RevolvedTest` (a constant lateral offset:
intervals of ``s = sqrt(x^2 + y^2 - c^2)``, of the polar angle and of ``z``), :class:`ProductTest` (a product
of images), :class:`~workspace_sym.serial.section.TurnedTest` and
:class:`~workspace_sym.serial.turn.LimitedTurnTest` (the ``(rho, z)`` section).  :func:`classify_task_boxes`
hands the test, as a decider, to the one paving driver (:func:`~workspace_sym.interval.driver.subdivide`), so
stores, checkpoints and budgets work as for any paving.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..interval import arith
from ..interval.boxes import Box, Paving
from ..interval.driver import RunBudget, RunOn, StopAt, subdivide
from ..interval.verdict import INSIDE, OUTSIDE, codes_from_masks
from .angles import ANGLE_PAD, ARC_MARGIN, arc_apart, arc_within, polar_angles
from .structure import Product, Revolved

__all__ = ["RevolvedTest", "ProductTest", "section_digest", "Classify", "classify_task_boxes"]


class RevolvedTest:
    """Classify boxes of ``(x, y, z)`` from a paving of the section (module docstring).

    Called with ``(N, 3, 2)`` boxes, it returns the masks ``(is_in, is_out)``: proved inner, proved outer
    (never both).

    Parameters
    ----------
    revolved : Revolved
        The structure: the section map, the offset ``c`` and the first joint's range.
    grid : CellGrid
        The grid of the section ``(u, v)``.
    classes : numpy.ndarray
        The verdict code of each cell of ``grid``.
    """

    def __init__(self, revolved: Revolved, grid, classes):
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
            phi_lo, phi_hi = polar_angles(X)
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
        inner = (s2[0] >= 0) & ((in_plus & arc_within(*t_plus, a_in, b_in, r.full))
                                | (in_minus & arc_within(*t_minus, a_in, b_in, r.full)))
        if c_lo == c_hi == 0.0 and (r.full or b_in - a_in >= math.pi + ARC_MARGIN):
            # theta_1's range and its half turn cover the circle: every angle is served by one branch.
            inner |= in_plus & in_minus
        out_plus = self._in(self.outside, plus, z, True) | arc_apart(*t_plus, a_out, b_out, r.full)
        out_minus = self._in(self.outside, minus, z, True) | arc_apart(*t_minus, a_out, b_out, r.full)
        outer = (s2[1] < 0) | (out_plus & out_minus)
        return inner, outer & ~inner


class ProductTest:
    """Classify boxes of ``(x, y, z)`` for a product structure: inner when every factor is proved inside,
    outer when one factor is proved outside.

    Called with ``(N, 3, 2)`` boxes, it returns the masks ``(is_in, is_out)``: proved inner, proved outer
    (never both).

    Parameters
    ----------
    product : Product
        The structure: the plane factor and the single coordinates.
    grid : CellGrid or None
        The grid of the plane factor (None without one).
    classes : numpy.ndarray or None
        The verdict code of each cell of ``grid`` (None without a plane factor).
    """

    def __init__(self, product: Product, grid, classes):
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


def section_digest(grid, classes, proved=None) -> str:
    """What a checkpoint of the task boxes names of the section they were classified from: a digest of its
    cells' classes, the grid's box and (limited turns) the cells proved per direction; ``"none"`` without a
    section.

    Parameters
    ----------
    grid : CellGrid or None
        The section's grid.
    classes : numpy.ndarray or None
        The verdict code of each cell; None without a section.
    proved : numpy.ndarray, optional
        The pieces proved at each direction of a limited turn
        (:func:`~workspace_sym.serial.turn.prove_directions`).

    Returns
    -------
    str
        16 hexadecimal digits of a SHA-256 digest, or ``"none"``.
    """
    if classes is None:
        return "none"
    data = np.ascontiguousarray(classes).tobytes() + np.asarray(grid.box, dtype=float).tobytes()
    return hashlib.sha256(data + (b"" if proved is None else np.ascontiguousarray(proved).tobytes())).hexdigest()[:16]


@dataclass(frozen=True)
class Classify:
    """The decider of :func:`classify_task_boxes`: the codes of a test's ``(is_in, is_out)`` masks; ``what``
    names its problem in a checkpoint's fingerprint (:func:`reach_problem` and the section's cells).

    Parameters
    ----------
    test : callable
        ``test(X) -> (is_in, is_out)`` on ``(N, m, 2)`` boxes.
    what : object, optional
        What a checkpoint names (a dict of the problem's fields); None: the test's type.
    """

    test: Any
    what: Any = None

    def __call__(self, boxes: np.ndarray) -> np.ndarray:
        return codes_from_masks(*self.test(boxes))

    def describe(self) -> Any:
        """What a checkpoint of this decider names.

        Returns
        -------
        object
            ``what``, or the qualified name of the test's type when ``what`` is None or empty.
        """
        return self.what or f"{type(self.test).__module__}.{type(self.test).__qualname__}"


def classify_task_boxes(test, box: Box, delta: float, size: str, stop: StopAt | RunBudget = StopAt(),
                        run: RunOn = RunOn(progress=False), *, describe: dict | None = None) -> Paving:
    """Pave the task box ``box`` with the driver (:func:`~workspace_sym.interval.driver.subdivide`), each box
    classified by ``test`` (``(is_in, is_out)`` masks from a paved section): proved boxes are inner/outer,
    undecided ones of size at most ``delta`` boundary.  No presplit: every box evaluated is a box of the
    breadth-first bisection from ``box``, so the counts are those of the classification alone.  ``stop``: a
    :class:`~workspace_sym.interval.driver.StopAt`, or ``reach``'s running budget (its clock, bar and the boxes
    the section took); ``run``: where the decided boxes go (``max_memory``, ``store``, ``resume``); ``describe``
    names the run's whole problem in a checkpoint (:func:`reach_problem`, the section's cells).

    Parameters
    ----------
    test : callable
        ``test(X) -> (is_in, is_out)`` on ``(N, m, 2)`` boxes.
    box : Box
        The root task box.
    delta : float
        Undecided boxes of size at most ``delta`` are boundary boxes.
    size : {"diameter", "width"}
        How a box's size is measured.
    stop : StopAt or RunBudget
        When to stop.
    run : RunOn
        Where the decided boxes go, and the progress bar (off by default).
    describe : dict, optional
        The problem a checkpoint names (None: the test's type).

    Returns
    -------
    Paving
        The paving of ``box`` (a :class:`~workspace_sym.interval.boxes.StoredPaving` when ``run`` stores its
        boxes).

    Raises
    ------
    InvalidParameterError
        A bad ``delta``, a ``run.store`` holding the boxes of another run, or a ``run.resume`` naming a file that
        is not a checkpoint of this problem.
    """
    return subdivide(Classify(test, describe), box, delta=delta, size=size, stop=stop, run=run, label="reach",
                     presplit=0)
