"""Polar angles of task boxes and arcs of a first joint's range, in floats widened by a pad.

A box of ``(x, y, z)`` is classified from the polar angles of its ``(x, y)`` rectangle
(:func:`polar_angles`: float ``atan2`` of its corners, widened by :data:`ANGLE_PAD`, 10^6 times their rounding
error) and the range ``[a, b]`` the first joint turns through (:func:`arc_within`, :func:`arc_apart`, modulo
``2 pi``, with a margin after the reduction).  This is the one place where a verdict rests on floats widened by
hand rather than on outward-rounded interval arithmetic (docs/methods.md section 5).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["ANGLE_PAD", "ARC_MARGIN", "polar_angles", "arc_within", "arc_apart"]

ANGLE_PAD = 1e-9                 # widening of float angles (rad): a soundness margin, not a tuning
ARC_MARGIN = 1e-12               # of angle comparisons after reduction modulo 2 pi
_TWO_PI = 2 * math.pi


def polar_angles(X: np.ndarray):
    """Polar angle range ``(lo, hi)`` of the ``(x, y)`` rectangles of boxes ``X``, widened by ``ANGLE_PAD``;
    ``(-inf, inf)`` where the rectangle holds the axis ``x = y = 0``.

    Parameters
    ----------
    X : numpy.ndarray
        ``(N, m, 2)`` boxes, ``m >= 2``, whose first two axes are ``x`` and ``y``.

    Returns
    -------
    lo : numpy.ndarray
        ``(N,)`` lower ends, in radians.
    hi : numpy.ndarray
        ``(N,)`` upper ends: every point of the rectangle has a polar angle in ``[lo, hi]`` (taken in
        ``(pi / 2, 3 pi / 2)``, before the pad, for a rectangle across the negative ``x`` axis).
    """
    x0, x1, y0, y1 = (X[:, 0, 0] + 0.0, X[:, 0, 1] + 0.0, X[:, 1, 0] + 0.0, X[:, 1, 1] + 0.0)
    axis = (x0 <= 0) & (x1 >= 0) & (y0 <= 0) & (y1 >= 0)
    xs, ys = np.stack([x0, x1, x0, x1], axis=1), np.stack([y0, y0, y1, y1], axis=1)
    angle = np.arctan2(ys, xs)
    # A rectangle across the negative x axis: its angles are continuous over (pi/2, 3 pi/2).
    across = (x1 < 0) & (y0 < 0) & (y1 >= 0)
    angle = np.where(across[:, None] & (ys < 0), angle + _TWO_PI, angle)
    lo, hi = angle.min(axis=1) - ANGLE_PAD, angle.max(axis=1) + ANGLE_PAD
    return np.where(axis, -np.inf, lo), np.where(axis, np.inf, hi)


def arc_within(lo, hi, a: float, b: float, full: bool):
    """``[lo, hi]`` lies in ``[a, b] + 2 pi k`` for some integer ``k``.

    Parameters
    ----------
    lo, hi : numpy.ndarray
        ``(N,)`` angle ranges in radians (:func:`polar_angles`).
    a, b : float
        The range the first joint turns through, in radians.
    full : bool
        The joint turns through a whole turn: every range lies in it.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` booleans, with a margin of ``ARC_MARGIN`` at both ends of ``[a, b]``; False for an infinite
        range.
    """
    if full:
        return np.ones(len(lo), dtype=bool)
    with np.errstate(invalid="ignore"):
        t = a + np.remainder(lo - a, _TWO_PI)
        return (t >= a + ARC_MARGIN) & (t + (hi - lo) <= b - ARC_MARGIN)


def arc_apart(lo, hi, a: float, b: float, full: bool):
    """``[lo, hi]`` meets no ``[a, b] + 2 pi k``.

    Parameters
    ----------
    lo, hi : numpy.ndarray
        ``(N,)`` angle ranges in radians (:func:`polar_angles`).
    a, b : float
        The range the first joint turns through, in radians.
    full : bool
        The joint turns through a whole turn: every range meets it.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` booleans, with a margin of ``ARC_MARGIN`` at both ends of the gap; all False when ``full`` or
        ``b - a >= 2 pi``, and False for an infinite range.
    """
    if full or b - a >= _TWO_PI:
        return np.zeros(len(lo), dtype=bool)
    with np.errstate(invalid="ignore"):
        t = b + np.remainder(lo - b, _TWO_PI)
        return (t >= b + ARC_MARGIN) & (t + (hi - lo) <= a + _TWO_PI - ARC_MARGIN)
