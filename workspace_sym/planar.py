"""Planar serial chains with joint limits: the alignment method of Bastien (2018), Steps 0 and 1.

Notation of METHODS.md section 4: segment ``i`` goes from ``A_{i-1}`` to ``A_i``
with length ``l_i``; ``theta_1`` is measured from the +y axis, ``theta_i`` from
segment ``i-1``; ``phi_i = theta_1 + ... + theta_i`` and
``A_p = sum_i l_i (-sin phi_i, cos phi_i)``.

Step 0 enumerates the candidate circular arcs (alignment of ``A_{j-1}``, j free,
with ``A_p``); Step 1 keeps the parts of each arc that pass the scalar-product
test of Lemma 3.1.  Step 2 (the global traversal), exact closed forms and the
boundary object are not implemented yet.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from .errors import InvalidParameterError, JointLimitError

__all__ = ["PlanarChain", "Arc"]

_TOL = 1e-12


def _u(phi):
    """Unit vector of direction ``phi`` measured from +y: ``(-sin phi, cos phi)``."""
    return np.array([-math.sin(phi), math.cos(phi)])


def _angle_of(v) -> float:
    """Inverse of :func:`_u`: the direction of ``v`` measured from +y."""
    return math.atan2(-v[0], v[1])


def _wrap(a: float) -> float:
    """Angle in (-pi, pi]."""
    a = math.fmod(a + math.pi, 2 * math.pi)
    if a <= 0:
        a += 2 * math.pi
    return a - math.pi


def _sigma(v):
    """Rotation by +pi/2."""
    return np.array([-v[1], v[0]])


@dataclass(frozen=True, slots=True)
class Arc:
    """A circular arc of the workspace boundary (or a candidate for it).

    ``theta_sets[k]`` is ``(value,)`` for a joint held at a limit or at an
    alignment angle, ``(low, high)`` for the free joint (radians).  ``center``,
    ``radius``; ``start_angle`` / ``end_angle`` are polar angles about the
    centre (radians, counter-clockwise from start to end as the free joint
    increases).  ``side`` is +1 when the workspace lies locally away from the
    centre, -1 towards it, 0 before Step 1.
    """

    type: str
    free_joint: int
    theta_sets: tuple
    center: tuple
    radius: float
    start_angle: float
    end_angle: float
    side: int = 0

    def __repr__(self):
        sets = ", ".join("{%.4f}" % math.degrees(s[0]) if len(s) == 1 else
                         "[%.4f, %.4f]" % (math.degrees(s[0]), math.degrees(s[1])) for s in self.theta_sets)
        return (f"Arc({self.type}, joint {self.free_joint}, centre ({self.center[0]:.6g}, {self.center[1]:.6g}), "
                f"r = {self.radius:.6g}, deg: {sets}, side {self.side:+d})")


class PlanarChain:
    """A planar chain of revolute joints with limits.

    Parameters
    ----------
    lengths : sequence of positive numbers
    lower, upper : joint limits, ``-180 < lower < upper <= 180`` (degrees by default)
    degrees : bool

    Examples
    --------
    >>> arm = PlanarChain([0.186, 0.146, 0.108], [-60, 0, -10], [120, 130, 25])   # Bastien, Table 1 (iii)
    >>> len(arm.candidate_arcs()), len(arm.kept_arcs())
    (16, 11)
    """

    def __init__(self, lengths, lower, upper, *, degrees: bool = True):
        lengths, lower, upper = list(lengths), list(lower), list(upper)
        if not lengths:
            raise InvalidParameterError("lengths: a chain needs at least one joint; got none")
        if not len(lengths) == len(lower) == len(upper):
            raise InvalidParameterError(f"lengths, lower and upper must have one value per joint; got "
                                        f"{len(lengths)}, {len(lower)}, {len(upper)}")
        unit = "deg" if degrees else "rad"
        half_turn = 180.0 if degrees else math.pi
        for k, (l, lo, hi) in enumerate(zip(lengths, lower, upper), start=1):
            for name, v in (("length", l), ("lower limit", lo), ("upper limit", hi)):
                if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(float(v)):
                    raise InvalidParameterError(f"{name} of joint {k} must be a finite number; got {v!r}")
            if l <= 0:
                raise InvalidParameterError(f"length of joint {k} must be positive; got {l}")
            if not (-half_turn < lo and hi <= half_turn):
                raise JointLimitError(f"limits of joint {k} must lie in (-{half_turn:g}, {half_turn:g}] {unit}; "
                                      f"got [{lo}, {hi}]")
            if not lo < hi:
                raise JointLimitError(f"upper limit of joint {k} ({hi} {unit}) must exceed its lower limit "
                                      f"({lo} {unit})")
        scale = math.pi / 180 if degrees else 1.0
        self.lengths = tuple(float(l) for l in lengths)
        self.lower = tuple(float(v) * scale for v in lower)
        self.upper = tuple(float(v) * scale for v in upper)
        self.p = len(self.lengths)

    def __repr__(self):
        return f"PlanarChain(p={self.p}, lengths={self.lengths})"

    # ------------------------------------------------------------------ kinematics
    def joints_positions(self, theta) -> np.ndarray:
        """``(p + 1, 2)`` array of ``A_0 = O, A_1, ..., A_p``."""
        pts = [np.zeros(2)]
        phi = 0.0
        for l, t in zip(self.lengths, theta):
            phi += t
            pts.append(pts[-1] + l * _u(phi))
        return np.array(pts)

    def forward(self, theta) -> np.ndarray:
        """End point ``A_p`` (vectorised over a leading axis of ``theta``)."""
        theta = np.asarray(theta, dtype=float)
        phi = np.cumsum(theta, axis=-1)
        return np.stack([-(np.sin(phi) * self.lengths).sum(-1), (np.cos(phi) * self.lengths).sum(-1)], axis=-1)

    # ------------------------------------------------------------------ Step 0
    def _limit(self, j: int, s: int) -> float:
        return self.lower[j] if s == 0 else self.upper[j]

    def candidate_arcs(self) -> list[Arc]:
        """Step 0: every arc allowed by the alignment condition (types I, II, III).

        For each non-empty set J of free joints, each choice of limits for the
        others and each sign pattern of the chords of the rigid bodies between
        free joints, the angles of the free joints after ``i = min J`` are fixed
        (kept when strictly inside their limits), and ``A_p`` describes an arc
        of the circle centred at ``A_{i-1}`` as ``theta_i`` runs over its range.
        """
        p = self.p
        arcs = []
        for m in range(1, p + 1):
            for J in itertools.combinations(range(p), m):
                others = [j for j in range(p) if j not in J]
                for limits in itertools.product((0, 1), repeat=len(others)):
                    fixed = dict(zip(others, limits))
                    for signs in itertools.product((0, 1), repeat=m - 1):
                        arc = self._alignment_arc(J, fixed, signs)
                        if arc is not None:
                            arcs.append(arc)
        return arcs

    def _alignment_arc(self, J, fixed, signs):
        p = self.p
        theta = [None] * p
        for j, s in fixed.items():
            theta[j] = self._limit(j, s)
        i = J[0]
        # Rigid bodies between free joints: body k covers segments J[k] .. J[k+1]-1.
        ends = list(J[1:]) + [p]
        chords = []  # (local chord angle gamma, length, internal turn of the body's last segment)
        for start, end in zip(J, ends):
            delta, vec = 0.0, np.zeros(2)
            for s in range(start, end):
                if s > start:
                    delta += theta[s]
                vec = vec + self.lengths[s] * _u(delta)
            length = float(np.hypot(*vec))
            if length <= _TOL:
                return None
            chords.append((_angle_of(vec), length, delta))
        signed, orient = chords[0][1], 1
        for k in range(1, len(J)):
            gamma_prev, _, turn_prev = chords[k - 1]
            gamma, length, _ = chords[k]
            t = _wrap(gamma_prev - gamma - turn_prev + signs[k - 1] * math.pi)
            j = J[k]
            if not (self.lower[j] + _TOL < t < self.upper[j] - _TOL):
                return None
            theta[j] = t
            orient = -orient if signs[k - 1] else orient  # relative to the first chord, not the previous one
            signed += orient * length
        radius = abs(signed)
        if radius <= _TOL:
            return None
        theta_lo, theta_hi = list(theta), list(theta)
        theta_lo[i], theta_hi[i] = self.lower[i], self.upper[i]
        pts = self.joints_positions(theta_lo)
        centre = pts[i]
        v = pts[-1] - centre
        a0 = math.atan2(v[1], v[0])
        a1 = a0 + (self.upper[i] - self.lower[i])
        kind = "III" if len(J) == 1 else ("I" if len(J) == p else "II")
        sets = tuple((self.lower[k], self.upper[k]) if k == i else (theta[k],) for k in range(p))
        return Arc(kind, i + 1, sets, (float(centre[0]), float(centre[1])), radius, a0, a1)

    # ------------------------------------------------------------------ Step 1
    def _epsilon(self, arc: Arc, j: int) -> int:
        s = arc.theta_sets[j]
        if len(s) == 2:
            return 0
        if abs(s[0] - self.lower[j]) <= _TOL:
            return 1
        if abs(s[0] - self.upper[j]) <= _TOL:
            return -1
        return 0  # an alignment angle strictly inside the limits: a free joint

    def _side(self, arc: Arc, theta_i: float):
        """epsilon_0 of Lemma 3.1 at one point of the arc, or None when the point is eliminated."""
        i = arc.free_joint - 1
        theta = [s[0] for s in arc.theta_sets]
        theta[i] = theta_i
        pts = self.joints_positions(theta)
        u = pts[-1] - pts[i]
        scale = max(1e-300, float(u @ u))
        for eps0 in (1, -1):
            ok = True
            for j in range(self.p):
                if j == i:
                    continue
                v = pts[-1] - pts[j]
                B = 2 * float(u @ _sigma(v))
                if abs(B) <= 1e-12 * scale:
                    C = float(v @ v - u @ v)
                    ok = eps0 * C > 0
                else:
                    ok = eps0 * self._epsilon(arc, j) * B > 0
                if not ok:
                    break
            if ok:
                return eps0
        return None

    def _split_points(self, arc: Arc) -> list[float]:
        """Values of the free joint where some ``B_j`` (j before the free joint) changes sign."""
        i = arc.free_joint - 1
        lo, hi = arc.theta_sets[i]
        theta = [s[0] for s in arc.theta_sets]
        theta[i] = lo
        pts = self.joints_positions(theta)
        u0 = pts[-1] - pts[i]
        cuts = []
        for j in range(i):
            w = pts[i] - pts[j]  # B_j = 2 u . sigma(w): zero where u is parallel to w
            if float(np.hypot(*w)) <= _TOL:
                continue
            base = math.atan2(w[1], w[0]) - math.atan2(u0[1], u0[0])
            for k in range(-3, 4):
                for shift in (0.0, math.pi):
                    t = lo + base + shift + 2 * math.pi * k
                    if lo + _TOL < t < hi - _TOL:
                        cuts.append(t)
        return sorted(set(cuts))

    def kept_arcs(self) -> list[Arc]:
        """Step 1: the parts of the candidate arcs kept by Lemma 3.1, with their side."""
        kept = []
        for arc in self.candidate_arcs():
            i = arc.free_joint - 1
            lo, hi = arc.theta_sets[i]
            bounds = [lo] + self._split_points(arc) + [hi]
            pieces = []
            for a, b in zip(bounds, bounds[1:]):
                side = self._side(arc, 0.5 * (a + b))
                if side is None:
                    continue
                if pieces and pieces[-1][2] == side and abs(pieces[-1][1] - a) <= _TOL:
                    pieces[-1] = (pieces[-1][0], b, side)
                else:
                    pieces.append((a, b, side))
            for a, b, side in pieces:
                sets = tuple((a, b) if k == i else s for k, s in enumerate(arc.theta_sets))
                start = arc.start_angle + (a - lo)
                kept.append(Arc(arc.type, arc.free_joint, sets, arc.center, arc.radius, start, start + (b - a), side))
        return kept
