"""Planar serial chains with joint limits: Steps 0 and 1 of the alignment method of Bastien (2018).

Notation of docs/methods.md section 4, with 0-based indices in the code: segment
``k`` goes from ``P_k`` to ``P_{k+1}`` with length ``l_k``; ``theta_0`` is
measured from the +y axis and ``theta_k`` from segment ``k-1``;
``phi_k = theta_0 + ... + theta_k`` and ``P_p = sum_k l_k (-sin phi_k, cos phi_k)``.
Joint numbers shown to users are 1-based, as in the paper.

* Step 0 (:attr:`PlanarChain.step0`, :meth:`PlanarChain.candidate_arcs`) enumerates the arcs allowed by the
  alignment condition.  It is a breadth-first scan over the joints after the
  first free one, vectorised over all branches and pruned as soon as an
  alignment angle leaves its limits.
* Step 1 (:attr:`PlanarChain.step1`, :meth:`PlanarChain.kept_arcs`) keeps the parts of each arc that pass
  the scalar-product test of Lemma 3.1, vectorised over the candidates.
* Step 2 (:meth:`PlanarChain.boundary`) builds the arrangement of the kept arcs,
  proves which of its faces belong to the workspace and returns the boundary
  loops (:class:`~workspace_sym.planar.boundary.Boundary`).  It lives in
  :mod:`workspace_sym.planar.boundary`, which this module imports; the boundary
  reads the chain by its attributes and imports nothing from here.
"""

from __future__ import annotations

import math
from fractions import Fraction
from functools import cached_property
from numbers import Integral, Number

import numpy as np
import sympy as sp

from ..errors import ExpressionError, InvalidParameterError
from ..expressions import check_joint_limits, parse_expr
from ..interval.driver import RunOn, StopAt, deprecated, with_legacy_keywords
from ..numbers import fmt
from .arcs import RESOLUTION, Arc, degrees_text
from .boundary import Boundary, build_boundary

__all__ = ["PlanarChain", "read_value"]

_TOL = 1e-12          # angles (radians) and lengths relative to the chain's reach
_ZERO_B = 1e-9        # |B_j| <= _ZERO_B |u| |v_j| counts as B_j = 0 (Lemma 3.1)
_SAFE_LENGTHS = (1e-100, 1e100)   # the longest link: its square times the number of faces stays a normal float
_TWO_PI = 2 * math.pi


def _wrap(a):
    """Angle(s) in (-pi, pi]."""
    a = np.fmod(np.asarray(a, dtype=float) + np.pi, 2 * np.pi)
    a = np.where(a <= 0, a + 2 * np.pi, a)
    return a - np.pi


def read_value(value, name: str):
    """A user number as ``(float, exact SymPy number)``; decimals are read as the rationals they spell.

    Text goes through :func:`~workspace_sym.expressions.parse_expr` (no symbols allowed).

    Parameters
    ----------
    value : int, float, fractions.Fraction, str or SymPy number
        The number: an integer or fraction is exact, a float is the decimal it prints as (``0.186`` is
        ``93/500``), text such as ``"3/20"`` or ``"sqrt(2)/10"`` is read by the restricted grammar.
    name : str
        What the value is, for messages (``"length of joint 2"``).

    Returns
    -------
    tuple
        ``(float, sympy.Expr)``: the value as a float and as an exact real SymPy number.

    Raises
    ------
    InvalidParameterError
        When ``value`` is a bool, None, of another type, not finite or not real.
    ExpressionError
        When text cannot be read as a number (a symbol, a syntax error, a refused construct).
    """
    if isinstance(value, bool) or value is None:
        raise InvalidParameterError(f"{name} must be a finite number; got {value!r}")
    try:
        if isinstance(value, (Integral, Fraction)):
            exact = sp.Rational(value if isinstance(value, Fraction) else int(value))
        elif isinstance(value, (float, np.floating)):
            if not math.isfinite(value):
                raise InvalidParameterError(f"{name} must be a finite number; got {value!r}")
            exact = sp.Rational(repr(float(value)))
        elif isinstance(value, str):
            exact = parse_expr(value, name, new_symbols=False)
        elif isinstance(value, (sp.Basic, Number)):
            exact = sp.sympify(value)  # not text
        else:
            raise TypeError
    except ExpressionError:
        raise
    except (TypeError, ValueError, sp.SympifyError):
        raise InvalidParameterError(f"{name} must be a finite number; got {value!r}") from None
    if not (isinstance(exact, sp.Expr) and exact.is_number and exact.is_real is not False):
        raise InvalidParameterError(f"{name} must be a finite real number; got {value!r}")
    number = float(exact)
    if not math.isfinite(number):
        raise InvalidParameterError(f"{name} must be a finite number; got {value!r}")
    return number, exact


class PlanarChain:
    """A planar chain of revolute joints with limits.

    Inputs are kept exact as well: a float is read as the decimal it prints as
    (``0.186`` is ``93/500``), so that :meth:`boundary` can give closed forms.

    Parameters
    ----------
    lengths : sequence of numbers
        The link lengths, positive: floats, integers, fractions or strings such as ``"3/20"`` or
        ``"sqrt(2)/10"`` (:func:`read_value`).  The longest lies between 1e-100 and 1e100 and the shortest is at
        least :data:`RESOLUTION` times the longest.
    lower, upper : sequence of numbers
        Joint limits, one per joint, ``lower < upper`` (degrees by default), any values: a range of a full turn
        (360 degrees) or more, such as ``[-180, 180]`` or a datasheet's ``[-360, 360]``, is a joint without
        limits, and so is one that falls short of a full turn by at most ``2 *`` :data:`RESOLUTION` radians
        (1.1e-5 deg: the angles it leaves out move the end point by less than the detail the boundary resolves).
    degrees : bool, default True
        Whether ``lower`` and ``upper`` are in degrees; False reads them as radians.

    Raises
    ------
    InvalidParameterError
        When the three are not sequences of one value per joint, there is no joint, a value is not a finite real
        number or a length is not positive or out of the ranges above.
    ExpressionError
        When a value given as text cannot be read as a number.
    JointLimitError
        When a lower limit is not below its upper limit.

    Examples
    --------
    >>> arm = PlanarChain([0.186, 0.146, 0.108], [-60, 0, -10], [120, 130, 25])   # Bastien, Table 1 (iii)
    >>> len(arm.candidate_arcs()), len(arm.kept_arcs()), len(arm.boundary().arcs)
    (16, 11, 8)
    """

    def __init__(self, lengths, lower, upper, *, degrees: bool = True):
        try:
            lengths, lower, upper = list(lengths), list(lower), list(upper)
        except TypeError:
            raise InvalidParameterError("lengths, lower and upper must be sequences of numbers") from None
        if not lengths:
            raise InvalidParameterError("lengths: a chain needs at least one joint; got none")
        if not len(lengths) == len(lower) == len(upper):
            raise InvalidParameterError(f"lengths, lower and upper must have one value per joint; got "
                                        f"{len(lengths)}, {len(lower)}, {len(upper)}")
        unit = "deg" if degrees else "rad"
        floats, exact = [], []
        for k, (l, lo, hi) in enumerate(zip(lengths, lower, upper), start=1):
            row = [read_value(v, f"{name} of joint {k}")
                   for name, v in (("length", l), ("lower limit", lo), ("upper limit", hi))]
            (l, _), (lo, _), (hi, _) = row
            if l <= 0:
                raise InvalidParameterError(f"length of joint {k} must be positive; got {lengths[k - 1]}")
            check_joint_limits(k, lo, hi, shown=(lower[k - 1], upper[k - 1]), unit=unit)
            floats.append((l, lo, hi))
            exact.append(tuple(e for _, e in row))
        longest = max(l for l, _, _ in floats)
        if not _SAFE_LENGTHS[0] <= longest <= _SAFE_LENGTHS[1]:
            raise InvalidParameterError(f"lengths: the longest link ({fmt(longest, 6, 'g')}) must lie between "
                                        f"{_SAFE_LENGTHS[0]:g} and {_SAFE_LENGTHS[1]:g} (areas and squared radii "
                                        f"stay finite floats); express the lengths in another unit")
        shortest = min(l for l, _, _ in floats)
        if shortest < RESOLUTION * longest:
            raise InvalidParameterError(f"lengths: the shortest link ({fmt(shortest, 6, 'g')}) must be at least "
                                        f"{RESOLUTION:g} times the longest ({fmt(longest, 6, 'g')}): the boundary "
                                        f"resolves no detail finer than {RESOLUTION:g} of the reach")
        scale = math.pi / 180 if degrees else 1.0
        exact_scale = sp.pi / 180 if degrees else sp.Integer(1)
        self.lengths = tuple(l for l, _, _ in floats)
        # a full turn has no limits: it is held nowhere, any alignment angle is allowed, and it runs over
        # [-pi, pi] (exactly, for the closed forms)
        self.full = tuple((hi - lo) * scale >= _TWO_PI - 2 * RESOLUTION for _, lo, hi in floats)
        self.lower = tuple(-math.pi if f else lo * scale for f, (_, lo, _) in zip(self.full, floats))
        self.upper = tuple(math.pi if f else hi * scale for f, (_, _, hi) in zip(self.full, floats))
        self.exact_lengths = tuple(e[0] for e in exact)
        self.exact_lower = tuple(-sp.pi if f else e[1] * exact_scale for f, e in zip(self.full, exact))
        self.exact_upper = tuple(sp.pi if f else e[2] * exact_scale for f, e in zip(self.full, exact))
        self.p = len(self.lengths)
        self.reach = float(sum(self.lengths))
        self._boundaries: dict[tuple, Boundary] = {}

    def __repr__(self):
        def deg(v):
            return ", ".join(degrees_text(x) for x in v)

        return (f"PlanarChain(lengths={list(self.lengths)}, lower=[{deg(self.lower)}], "
                f"upper=[{deg(self.upper)}])")

    # ------------------------------------------------------------------ kinematics
    def joints_positions(self, theta) -> np.ndarray:
        """``(..., p + 1, 2)`` array of ``P_0 = O, P_1, ..., P_p`` (vectorised over leading axes).

        Parameters
        ----------
        theta : array_like
            ``(..., p)`` joint angles (radians).

        Returns
        -------
        numpy.ndarray
            ``(..., p + 1, 2)``: the origin, then the end of each link.
        """
        theta = np.asarray(theta, dtype=float)
        phi = np.cumsum(theta, axis=-1)
        steps = np.stack([-np.sin(phi), np.cos(phi)], axis=-1) * np.asarray(self.lengths)[:, None]
        zero = np.zeros(theta.shape[:-1] + (1, 2))
        return np.concatenate([zero, np.cumsum(steps, axis=-2)], axis=-2)

    def forward(self, theta) -> np.ndarray:
        """End point ``P_p`` (vectorised over leading axes of ``theta``).

        Parameters
        ----------
        theta : array_like
            ``(..., p)`` joint angles (radians).

        Returns
        -------
        numpy.ndarray
            ``(..., 2)``: the end point of each configuration.
        """
        theta = np.asarray(theta, dtype=float)
        phi = np.cumsum(theta, axis=-1)
        return np.stack([-(np.sin(phi) * self.lengths).sum(-1), (np.cos(phi) * self.lengths).sum(-1)], axis=-1)

    def sample(self, n: int, *, seed=0, corners: bool = True) -> np.ndarray:
        """``n`` random configurations (uniform in the joint box), plus up to 4096 corners of the box.

        Parameters
        ----------
        n : int
            The number of random configurations.
        seed : int, numpy.random.Generator or None, default 0
            Seed of :func:`numpy.random.default_rng`; None draws a fresh one.
        corners : bool, default True
            Whether to put the ``2**min(p, 12)`` corners of the box first: the first 12 joints at either limit,
            any further joints at their lower limit.

        Returns
        -------
        numpy.ndarray
            ``(n + 2**min(p, 12), p)`` joint angles (radians), corners first; ``(n, p)`` without corners.
        """
        rng = np.random.default_rng(seed)
        lo, hi = np.array(self.lower), np.array(self.upper)
        theta = lo + (hi - lo) * rng.random((n, self.p))
        if corners:
            m = min(self.p, 12)
            bits = (np.arange(2 ** m)[:, None] >> np.arange(m)) & 1
            c = np.tile(lo, (len(bits), 1))
            c[:, :m] = np.where(bits, hi[:m], lo[:m])
            theta = np.vstack([c, theta])
        return theta

    # ------------------------------------------------------------------ Step 0
    @cached_property
    def step0(self) -> dict:
        """Step 0 as arrays (computed once): ``theta`` (n, p) with NaN at the free joint, ``aligned`` (n, p),
        ``free`` (n,), ``center`` (n, 2), ``radius`` (n,), ``start`` (n,) polar angle at the lower limit."""
        p, L = self.p, np.array(self.lengths)
        lo, hi = np.array(self.lower), np.array(self.upper)
        full = np.array(self.full)
        tol_len = _TOL * self.reach
        out = []
        for i in range(p):
            if full[:i].any():     # a joint before the free one is held at a limit, and a full turn has none
                break
            st = _Scan(p, i, L[i])
            for j in range(i + 1, p):
                st = st.branch(j, L[j], lo[j], hi[j], lo, hi, full, tol_len)
                if st.n == 0:
                    break
            if st.n == 0:
                continue
            st = st.close(lo, hi, full, tol_len)
            keep = np.abs(st.radius) > tol_len
            theta_s, aligned_s = st.theta[keep], st.aligned[keep]
            if not len(theta_s):
                continue
            # end point relative to P_i, in the frame where segment i has direction 0
            local = np.where(np.isnan(theta_s), 0.0, theta_s)
            local[:, : i + 1] = 0.0
            phi = np.cumsum(local[:, i:], axis=1)
            ex = -(np.sin(phi) * L[i:]).sum(1)
            ey = (np.cos(phi) * L[i:]).sum(1)
            # prefix: joints before i at their limits
            bits = (np.arange(2 ** i)[:, None] >> np.arange(i)) & 1
            pre = np.where(bits, hi[:i], lo[:i]) if i else np.zeros((1, 0))
            pphi = np.cumsum(pre, axis=1)
            cx = -(np.sin(pphi) * L[:i]).sum(1)
            cy = (np.cos(pphi) * L[:i]).sum(1)
            base = pphi[:, -1] if i else np.zeros(1)
            ns, npre = len(theta_s), len(pre)
            theta = np.repeat(theta_s, npre, axis=0)
            theta[:, :i] = np.tile(pre, (ns, 1))
            theta[:, i] = np.nan
            start = (np.arctan2(ey, ex)[:, None] + base[None, :] + lo[i]).ravel()
            out.append(dict(theta=theta, aligned=np.repeat(aligned_s, npre, axis=0),
                            free=np.full(ns * npre, i),
                            center=np.stack([np.tile(cx, ns), np.tile(cy, ns)], axis=1),
                            radius=np.repeat(np.hypot(ex, ey), npre), start=_wrap(start)))
        if out:
            cand = {k: np.concatenate([o[k] for o in out]) for k in out[0]}
        else:
            cand = dict(theta=np.zeros((0, p)), aligned=np.zeros((0, p), bool), free=np.zeros(0, int),
                        center=np.zeros((0, 2)), radius=np.zeros(0), start=np.zeros(0))
        return cand

    def _make_arc(self, cand, k, a, b, side=0) -> Arc:
        i = int(cand["free"][k])
        n_free = int(cand["aligned"][k].sum()) + 1
        kind = "III" if n_free == 1 else ("I" if n_free == self.p else "II")
        sets = tuple((float(a), float(b)) if j == i else (float(cand["theta"][k, j]),) for j in range(self.p))
        start = float(cand["start"][k]) + (a - self.lower[i])
        return Arc(kind, i + 1, sets, (float(cand["center"][k, 0]), float(cand["center"][k, 1])),
                   float(cand["radius"][k]), start, start + (b - a), side)

    def candidate_arcs(self) -> list[Arc]:
        """Step 0: every arc allowed by the alignment condition (types I, II, III).

        For each non-empty set J of free joints, each choice of limits for the
        others and each sign pattern of the chords of the rigid bodies between
        free joints, the angles of the free joints after ``i = min J`` are fixed
        (kept when strictly inside their limits), and ``P_p`` describes an arc
        of the circle centred at ``P_i`` as ``theta_i`` runs over its range.

        Returns
        -------
        list of Arc
            The candidate arcs, a new list on each call (the arrays behind it, :attr:`step0`, are computed
            once); ``side`` is 0.
        """
        cand = self.step0
        return [self._make_arc(cand, k, self.lower[i], self.upper[i]) for k, i in enumerate(cand["free"])]

    # ------------------------------------------------------------------ Step 1
    @cached_property
    def step1(self) -> tuple[Arc, ...]:
        """Step 1 (computed once): the kept arcs, in the order the boundary's ``source`` indices refer to."""
        cand = self.step0
        lo, hi = np.array(self.lower), np.array(self.upper)
        kept: list[Arc] = []
        for i in range(self.p):
            idx = np.flatnonzero(cand["free"] == i)
            if not len(idx):
                continue
            theta = cand["theta"][idx].copy()
            theta[:, i] = lo[i]
            pts = self.joints_positions(theta)                        # (n, p+1, 2)
            u = pts[:, -1] - pts[:, i]                                 # (n, 2)
            v = pts[:, -1:, :] - pts[:, :-1, :]                        # (n, p, 2): v_j = P_p - P_j
            B = 2 * (u[:, None, 1] * v[..., 0] - u[:, None, 0] * v[..., 1])
            C = (v * v).sum(-1) - (u[:, None, :] * v).sum(-1)
            size = np.hypot(*u.T)[:, None] * np.hypot(v[..., 0], v[..., 1])
            aligned = cand["aligned"][idx]
            eps = np.where(aligned, 0,
                           np.where(np.abs(theta - lo) <= _TOL, 1, np.where(np.abs(theta - hi) <= _TOL, -1, 0)))
            zero = aligned | (np.abs(B) <= _ZERO_B * size)
            after = np.arange(self.p) > i
            ok = {}
            for e0 in (1, -1):
                good = np.where(zero, e0 * C > 0, e0 * eps * B > 0)
                ok[e0] = np.all(good | ~after, axis=1)
            # joints before i (none when i = 0): B_j = 2 |w||u| sin(arg u - arg w), w = P_i - P_j, zero twice per turn
            w = pts[:, i:i + 1, :] - pts[:, :i, :]                 # (n, i, 2)
            wnorm = np.hypot(w[..., 0], w[..., 1])
            arg_u0 = np.arctan2(u[:, 1], u[:, 0])
            arg_w = np.arctan2(w[..., 1], w[..., 0])
            rel = np.mod(arg_w - arg_u0[:, None], np.pi)                 # in [0, pi)
            cuts = lo[i] + np.concatenate([rel, rel + np.pi], axis=1)
            cuts = np.where((cuts > lo[i] + _TOL) & (cuts < hi[i] - _TOL), cuts, hi[i])
            bounds = np.concatenate([np.full((len(idx), 1), lo[i]), np.sort(cuts, axis=1),
                                     np.full((len(idx), 1), hi[i])], axis=1)
            mid = 0.5 * (bounds[:, 1:] + bounds[:, :-1])                        # (n, m)
            ang = arg_u0[:, None, None] + (mid - lo[i])[:, :, None] - arg_w[:, None, :]
            s = np.sign(np.sin(ang)) * eps[:, None, :i]                      # (n, m, i)
            plus = np.all(s > 0, axis=2) & ok[1][:, None]
            minus = np.all(s < 0, axis=2) & ok[-1][:, None]
            side = np.where(plus, 1, np.where(minus, -1, 0))
            side[(wnorm <= _TOL * self.reach).any(1)] = 0
            for r in np.flatnonzero((side != 0).any(axis=1)):
                pieces: list[tuple[float, float, int]] = []
                for m in range(side.shape[1]):
                    a, b, sd = bounds[r, m], bounds[r, m + 1], side[r, m]
                    if sd == 0 or b - a <= _TOL:
                        continue
                    if pieces and pieces[-1][2] == sd and abs(pieces[-1][1] - a) <= _TOL:
                        pieces[-1] = (pieces[-1][0], b, sd)
                    else:
                        pieces.append((a, b, sd))
                kept.extend(self._make_arc(cand, idx[r], a, b, int(sd)) for a, b, sd in pieces)
        return tuple(kept)

    def kept_arcs(self) -> list[Arc]:
        """Step 1: the parts of the candidate arcs kept by Lemma 3.1, with their side.

        Returns
        -------
        list of Arc
            A new list of :attr:`step1` (computed once), ``side`` +1 or -1.
        """
        return list(self.step1)

    @cached_property
    def subchain(self) -> PlanarChain | None:
        """The chain of joints 2..p in the frame of link 1 (None for one joint), built once."""
        if self.p == 1:
            return None
        return PlanarChain(self.lengths[1:], self.lower[1:], self.upper[1:], degrees=False)

    # ------------------------------------------------------------------ Step 2
    def boundary(self, *, samples: int = 4096, seed: int = 0, proof_boxes: int = 4_000, stop: StopAt = StopAt(),
                 run: RunOn = RunOn(), max_boxes: int | None = None, progress: bool | None = None) -> Boundary:
        """Step 2: the workspace boundary as loops of arcs (:class:`~workspace_sym.planar.boundary.Boundary`).

        The kept arcs cut the plane into faces; every face lies wholly inside or
        wholly outside the workspace.  A face is proved inside by Lemma 3.1 (a
        kept arc whose side points into it) or by a witness configuration that
        lands in it; a bounded face is proved outside by interval exclusion (no
        configuration of the joint box reaches a point of it).  A face that
        resists both within ``proof_boxes`` boxes, or whose proof ``stop`` cuts
        short, is reported as undecided, with a warning, and the area becomes a
        bracket.

        The result is kept: a second call with the same ``samples``, ``seed``, ``proof_boxes`` and a ``stop``
        of boxes only returns the same object (one with a time limit is built anew: where it stops depends on
        the machine).

        Parameters
        ----------
        samples : int, default 4096
            The number of random configurations drawn (with the corners of the joint box) to find witnesses.
        seed : int, default 0
            Seed of that sample.
        proof_boxes : int, default 4000
            Box budget of the interval exclusion of each face.
        stop : StopAt
            ``max_boxes`` boxes over all the exclusions, ``time_limit`` seconds for the call; ``section_boxes``
            is refused.
        run : RunOn
            ``progress``: True shows the stages, False never; None (the default) shows them on an interactive
            output once the run has lasted a second (:mod:`workspace_sym.progress`).  The other fields are
            refused: the boundary is built in this process and keeps no boxes.
        max_boxes : int, optional
            Deprecated spelling of ``proof_boxes`` (a :class:`DeprecationWarning`).
        progress : bool, optional
            Deprecated spelling of ``run=RunOn(progress=...)`` (a :class:`DeprecationWarning`).

        Returns
        -------
        Boundary
            The loops of arcs, their area and perimeter, and how each face was decided.

        Raises
        ------
        InvalidParameterError
            When ``proof_boxes`` is not a positive integer, or ``stop`` or ``run`` sets a field that does not
            apply.
        BoundaryError
            When the loops found contradict a property every chain has (an area larger than the annulus that
            holds every configuration, or a negative one): limits a hair short of a full turn.

        Warns
        -----
        UserWarning
            When faces stay undecided (the area is then a lower bound, :attr:`Boundary.undecided_area` the
            rest), and for each note of the classification.
        DeprecationWarning
            For ``max_boxes=`` and ``progress=``.
        """
        stop, run = with_legacy_keywords("boundary", stop, run, progress=progress)
        if max_boxes is not None:
            deprecated("boundary", "max_boxes", "proof_boxes=... (each face's proof; stop=StopAt(max_boxes=...) "
                       "bounds them all)")
            proof_boxes = max_boxes
        if not isinstance(stop, StopAt) or stop.time_limit is not None:      # refused, or not to be kept
            return build_boundary(self, samples=samples, seed=seed, proof_boxes=proof_boxes, stop=stop, run=run)
        key = (samples, seed, proof_boxes, stop.max_boxes)
        if key not in self._boundaries:
            self._boundaries[key] = build_boundary(self, samples=samples, seed=seed, proof_boxes=proof_boxes,
                                                    stop=stop, run=run)
        return self._boundaries[key]


class _Scan:
    """Branches of the Step 0 scan after the first free joint ``i``.

    Each branch holds the chord of the rigid body being built (in the frame of
    its first segment), the pending alignment check of the last free joint, and
    the signed radius accumulated so far.
    """

    def __init__(self, p, i, length):
        self.theta = np.full((1, p), np.nan)
        self.aligned = np.zeros((1, p), bool)
        self.vx, self.vy, self.turn = np.zeros(1), np.full(1, float(length)), np.zeros(1)
        self.pend, self.pend_joint = np.zeros(1), np.full(1, -1)
        self.orient, self.radius = np.ones(1), np.zeros(1)

    @property
    def n(self):
        return len(self.vx)

    def _take(self, rows):
        new = object.__new__(_Scan)
        for k, v in vars(self).items():
            setattr(new, k, v[rows])
        return new

    def _close_body(self, lo, hi, full, tol_len):
        """Close the current body: check the pending alignment angle, add the chord to the radius."""
        gamma = np.arctan2(-self.vx, self.vy)
        length = np.hypot(self.vx, self.vy)
        good = length > tol_len
        has = self.pend_joint >= 0
        pj = np.where(has, self.pend_joint, 0)
        t = np.where(full[pj], _wrap(self.pend - gamma), lo[pj] + np.mod(self.pend - gamma - lo[pj], _TWO_PI))
        good &= ~has | full[pj] | ((t > lo[pj] + _TOL) & (t < hi[pj] - _TOL))
        rows = np.flatnonzero(good)
        self.theta[rows[has[rows]], pj[rows[has[rows]]]] = t[rows[has[rows]]]
        self.radius = self.radius + self.orient * length
        return rows, gamma

    def branch(self, j, length, lo_j, hi_j, lo, hi, full, tol_len):
        """Joint ``j`` at its lower limit, at its upper limit (not for a full turn), or free with the next chord
        parallel or anti-parallel."""
        parts = []
        for value in () if full[j] else (lo_j, hi_j):
            s = self._take(slice(None))
            s.theta = self.theta.copy()
            s.theta[:, j] = value
            s.turn = self.turn + value
            s.vx = self.vx - length * np.sin(s.turn)
            s.vy = self.vy + length * np.cos(s.turn)
            parts.append(s)
        base = self._take(slice(None))
        base.theta = self.theta.copy()
        rows, gamma = base._close_body(lo, hi, full, tol_len)
        for sign in (0, 1):
            s = base._take(rows)
            s.theta = s.theta.copy()
            s.aligned = s.aligned.copy()
            s.aligned[:, j] = True
            s.pend = gamma[rows] - self.turn[rows] + sign * np.pi
            s.pend_joint = np.full(len(rows), j)
            s.orient = -s.orient if sign else s.orient
            s.vx, s.vy, s.turn = np.zeros(len(rows)), np.full(len(rows), float(length)), np.zeros(len(rows))
            parts.append(s)
        out = object.__new__(_Scan)
        for k in vars(self):
            setattr(out, k, np.concatenate([getattr(s, k) for s in parts]))
        return out

    def close(self, lo, hi, full, tol_len):
        rows, _ = self._close_body(lo, hi, full, tol_len)
        return self._take(rows)
