"""The Orthoglide's certified box module M(B) and the dextrous workspace paving (Chablat, Wenger, Merlet 2002).

Model (docs/methods.md section 3, leg length 1, the working mode of the isotropic
configuration): ``A = [[eta1, y, z], [x, eta2, z], [x, y, eta3]]``,
``B = diag(eta1, eta2, eta3)``, ``J = A^-1 B`` with
``eta1 = sqrt(1 - y^2 - z^2)``, ``eta2 = sqrt(1 - x^2 - z^2)``, ``eta3 = sqrt(1 - x^2 - y^2)``.

Certified box module ``M(B)`` (paper section 4.1, made rigorous).  The
eigenvalues of ``J J^T`` lie in ``[sigma_min, sigma_max]`` exactly when those of
its inverse

    ``N = A^T B^-2 A``,  ``N_jk = sum_i A_ij A_ik / eta_i^2``

lie in ``[1 / sigma_max, 1 / sigma_min]``.  We certify with ``N`` as a matrix
rather than with any characteristic polynomial:

* ``N`` is defined wherever the legs are (no division by ``det A``), is
  positive semi-definite everywhere, and tends to a singular matrix at the
  parallel singularity, so boxes there are simply outside; its entries are
  short (``1 + x^2 (s2 + s3)``, ``y r1 + x r2 + x y s3``, ... with
  ``s_i = 1/eta_i^2``, ``r_i = 1/eta_i``) and their gradients too;
* over a box, ``N`` is enclosed in mean-value form ``N(c) + sum_k dN/dx_k (X_k - c_k)``
  (Hansen's sequential form: ``dN/dx`` over ``(X, c_y, c_z)``, ``dN/dy`` over
  ``(X, Y, c_z)``, ``dN/dz`` over the box) intersected with the natural form,
  then rotated by the eigenvectors ``Q`` of
  ``N(c)``: ``Q^T N Q`` is nearly diagonal and its diagonal varies like the
  eigenvalues themselves (first order);
* inside (1): ``N - I/sigma_max`` and ``I/sigma_min - N`` are proved positive
  definite on the whole box (Sylvester's criterion on the rotated enclosure,
  see :mod:`workspace_sym.interval.symmetric`); outside (-1): a Rayleigh
  quotient proves ``lambda_min(N) < 1/sigma_max`` or ``lambda_max(N) > 1/sigma_min``
  on the whole box, or the box lies outside a cylinder, or (for a box that
  straddles a cylinder) a diagonal entry of ``N`` exceeds ``1/sigma_min`` on its
  part inside the cylinders.

The paving (:func:`dextrous`) bisects like the paper's section 4.2, and
contracts each box that would count in the error index E by shaving
(:func:`shave_boxes`): half-edge slabs next to its faces are cut off when
``M(B)`` proves them inside or outside.  At eps = 0.05 this takes E from
0.50 to 0.30 (the paper: 0.48) for about three times the box tests.

The characteristic polynomial of ``J J^T`` (and the pencil ``det(lambda A A^T - B^2)``)
is derived symbolically for reports; certifying with it was measured far
weaker: at eps = 0.05 the pencil form with Descartes' rule left E = 2.66 in
105 s, the matrix form leaves E = 0.53 in about 1 s (BENCHMARKS.md).  A
polynomial coefficient mixes every eigenvalue and its enclosure over a box
grows with all of them, where the rotated matrix separates them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from ..errors import InvalidParameterError
from ..interval import arith, symmetric
from ..interval.arith import Interval
from ..interval.boxes import Box, Paving, StoredPaving
from ..interval.contractor import Separation
from ..interval.driver import RunOn, StopAt, subdivide
from ..interval.paving import threaded
from ..interval.verdict import CODE, INSIDE, OUTSIDE, UNDECIDED, codes_from_masks
from ..numbers import fmt_bound

__all__ = ["DextrousResult", "box_module", "check_sigma", "dextrous", "inverse_entries", "leg_terms",
           "numeric_dextrous", "reciprocal", "shave_boxes", "witnessed_module"]


@dataclass(frozen=True, eq=False)
class DextrousResult:
    """Certified dextrous workspace: inside volume and the error index E (volume of undecided boxes).

    Made by :func:`dextrous`.

    Parameters
    ----------
    paving : Paving
        The paving of ``[-1, 1]^3`` (or of the box given), a
        :class:`~workspace_sym.interval.boxes.StoredPaving` when its boxes were streamed to disk.
    sigma : tuple of float
        ``(sigma_min, sigma_max)``, the bounds on the eigenvalues of ``J J^T``.
    eps : float
        The largest edge of an undecided box.
    shave : tuple of float, default ()
        The slab fractions of the shaving; empty for plain bisection.
    """

    paving: Paving
    sigma: tuple[float, float]
    eps: float
    shave: tuple[float, ...] = ()

    @property
    def volume_inner(self) -> float:
        """The volume of the boxes proved inside.

        Returns
        -------
        float
            A proved lower bound of the dextrous volume (the paving's measure of inner boxes, rounded down).
        """
        return self.paving.measure_bounds[0]          # the proved lower bound (rounded down)

    @property
    def volume_undecided(self) -> float:
        """The error index E: the volume of the boxes neither proved inside nor outside.

        Returns
        -------
        float
            The measure of the boundary and pending boxes (each rounded to nearest).
        """
        m = self.paving.measures
        return m["boundary"] + m["pending"]

    def __repr__(self):
        return (f"DextrousResult(inside volume {fmt_bound(self.volume_inner, 6, up=False)}, "
                f"E {fmt_bound(self.volume_undecided, 6, up=True)}, "
                f"eps {self.eps})")

    def to_dict(self) -> dict:
        """The result as a JSON object (``workspace-sym dextrous --json``, docs/cli.md).

        Returns
        -------
        dict
            ``volume_inner``, ``volume_undecided``, ``boxes`` (counts of inner, undecided and outer boxes),
            ``eps``, ``sigma``, ``shave``, ``complete``, ``boxes_evaluated`` and ``seconds``; with ``store`` and
            ``files`` when the boxes were streamed to disk.
        """
        p = self.paving
        data = {
            "volume_inner": self.volume_inner,
            "volume_undecided": self.volume_undecided,
            "boxes": {"inner": p.counts["inner"], "undecided": p.counts["boundary"] + p.counts["pending"],
                      "outer": p.counts["outer"]},
            "eps": self.eps,
            "sigma": list(self.sigma),
            "shave": list(self.shave),
            "complete": p.complete,
            "boxes_evaluated": p.evaluated,
            "seconds": p.seconds,
        }
        if isinstance(p, StoredPaving):            # boxes streamed to disk (max_memory=, store=)
            data["store"] = p.store
            data["files"] = {k: [str(f) for f in v] for k, v in p.files.items()}
        return data


def box_module(boxes: np.ndarray, sigma=(0.25, 4.0)) -> np.ndarray:
    """``M(B)`` for an ``(N, 3, 2)`` array of boxes: 1 inside, -1 outside, 0 undecided (paper 4.1).

    Every 1 and -1 is proved with outward-rounded interval arithmetic (see
    the module docstring).  A box wholly outside a cylinder is -1; a box
    that straddles a cylinder can be proved -1 on its part inside the
    cylinders, never 1.

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, 3, 2)`` boxes of positions ``(x, y, z)``, ``[..., 0]`` lower and ``[..., 1]`` upper bounds.
    sigma : pair of float, default (0.25, 4.0)
        ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` verdict codes (:mod:`workspace_sym.interval.verdict`): 1 inside, -1 outside, 0 undecided.

    Raises
    ------
    InvalidParameterError
        When ``sigma`` is not two finite numbers with ``0 < sigma_min < sigma_max``.
    """
    sigma_min, sigma_max = check_sigma(sigma)
    a_lo, a_hi = reciprocal(sigma_max)
    b_lo, b_hi = reciprocal(sigma_min)
    n = len(boxes)
    lo, hi = boxes[:, :, 0], boxes[:, :, 1]
    mid = 0.5 * lo + 0.5 * hi
    with np.errstate(all="ignore"):
        X = [Interval(lo[:, k], hi[:, k]) for k in range(3)]
        squares, eta2, s, r = leg_terms(X)
        outside_cyl = np.any([e.hi <= 0 for e in eta2], axis=0)
        # Straddling boxes: on the part inside the cylinders 1/eta_i^2 >= 1/max(eta_i^2).
        s_low = [Interval(*arith.point(arith.down(1.0 / e.hi))) for e in eta2]
        diag_low = [1 + squares[0] * (s_low[1] + s_low[2]), 1 + squares[1] * (s_low[0] + s_low[2]),
                    1 + squares[2] * (s_low[0] + s_low[1])]
        too_large = np.any([d.lo > b_hi for d in diag_low], axis=0)

        natural, gradient = _inverse_over(X, s, r, axes=(2,))
        C = [Interval(mid[:, k], mid[:, k].copy()) for k in range(3)]
        centre, _ = _inverse_over(C, *leg_terms(C)[2:], gradients=False)
        N_nat, N_c = symmetric.from_entries(natural), symmetric.from_entries(centre)
        regular = (np.all([e.lo > 0 for e in eta2], axis=0) & np.isfinite(N_nat[0]).all(axis=(1, 2))
                   & np.isfinite(N_nat[1]).all(axis=(1, 2)))
        point = 0.5 * N_c[0] + 0.5 * N_c[1]
        point[~regular] = np.eye(3)
        _, Q = np.linalg.eigh(point)
        S = symmetric.congruence(Q, N_c)
        # Hansen's sequential mean-value form: N(x) - N(c) is the sum over k of dN/dx_k at a point of
        # (X_1, ..., X_k, c_k+1, ...) times (x_k - c_k), so dN/dx is enclosed over (X, c_y, c_z) and dN/dy
        # over (X, Y, c_z), narrower than over the box.
        partial_boxes = ([X[0], C[1], C[2]], [X[0], X[1], C[2]])
        gradient = [_inverse_over(b, *leg_terms(b)[2:], axes=(k,))[1][k]
                    for k, b in enumerate(partial_boxes)] + [gradient[2]]
        for k in range(3):
            D = symmetric.congruence(Q, symmetric.from_entries(gradient[k]))
            h = (arith.down(lo[:, k] - mid[:, k])[:, None, None], arith.up(hi[:, k] - mid[:, k])[:, None, None])
            S = arith.add(S, arith.mul(D, h))
        S = arith.intersect(S, symmetric.congruence(Q, N_nat))
        eye = np.broadcast_to(np.eye(3), (n, 3, 3))
        G = symmetric.congruence(Q, (eye, eye))
        inside = (regular & symmetric.positive_definite(arith.sub(S, symmetric.scale(a_hi, G)))
                  & symmetric.positive_definite(arith.sub(symmetric.scale(b_lo, G), S)))
        small = arith.sub(S, symmetric.scale(a_lo, G))[1][:, 0, 0] < 0         # lambda_min(N) < 1/sigma_max
        large = arith.sub(S, symmetric.scale(b_hi, G))[0][:, 2, 2] > 0         # lambda_max(N) > 1/sigma_min
        outside = outside_cyl | too_large | (regular & (small | large))
    return codes_from_masks(inside, outside)


def numeric_dextrous(pts, sigma) -> np.ndarray:
    """Whether points are dextrous, by float Sylvester tests on ``N = (J J^T)^-1`` (a guess for the search,
    the pictures and the tests, never a certificate).

    Parameters
    ----------
    pts : array_like
        ``(n, 3)`` positions (one position ``(3,)`` is taken as ``(1, 3)``).
    sigma : pair of float
        ``(sigma_min, sigma_max)``, not checked.

    Returns
    -------
    numpy.ndarray
        ``(n,)`` bools: True where every leg is defined and the eigenvalues of ``J J^T`` lie strictly between
        ``sigma_min`` and ``sigma_max`` in floats.
    """
    pts = np.atleast_2d(np.asarray(pts, dtype=float))
    x_, y_, z_ = pts.T
    e2 = np.stack([1 - y_**2 - z_**2, 1 - x_**2 - z_**2, 1 - x_**2 - y_**2])
    ok = np.asarray((e2 > 0).all(axis=0))
    s = 1 / np.where(ok, e2, 1.0)
    N, _ = inverse_entries(x_, y_, z_, s, np.sqrt(s), gradients=False)
    # 1/sigma_max <= every eigenvalue of N <= 1/sigma_min, by Sylvester's criterion on N - I/sigma_max
    # and I/sigma_min - N (a few flops a point, where a batched eigvalsh costs microseconds).
    for sign, shift in ((1.0, -1.0 / sigma[1]), (-1.0, 1.0 / sigma[0])):
        a, b, c = (sign * N[k, k] + shift for k in range(3))
        d, f, g = sign * N[0, 1], sign * N[0, 2], sign * N[1, 2]
        det = a * (b * c - g * g) - d * (d * c - g * f) + f * (d * g - b * f)
        ok = ok & (a > 0) & (a * b - d * d > 0) & (det > 0)
    return ok


def witnessed_module(boxes: np.ndarray, sigma) -> np.ndarray:
    """:func:`box_module`, skipping boxes that numerically have a dextrous and a non-dextrous point.

    Such a box can be neither proved inside nor outside, and leaving a box
    undecided needs no proof, so the verdicts are those of ``box_module``
    on every box it could decide.  The centre and the eight corners are
    tested (float Sylvester tests, about 4 us a box against about 25 us
    for the certificate); at fine eps most undecided boxes straddle the
    boundary this way.

    Parameters
    ----------
    boxes : numpy.ndarray
        ``(N, 3, 2)`` boxes of positions.
    sigma : pair of float
        ``(sigma_min, sigma_max)``.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` verdict codes: those of :func:`box_module`, and 0 for the skipped boxes.
    """
    pts = boxes[:, None, :, 0] + _CORNERS_AND_CENTRE[None] * (boxes[:, None, :, 1] - boxes[:, None, :, 0])
    ok = numeric_dextrous(pts.reshape(-1, 3), sigma).reshape(len(boxes), len(_CORNERS_AND_CENTRE))
    decidable = ok.all(axis=1) | ~ok.any(axis=1)
    codes = np.zeros(len(boxes), dtype=CODE)
    if decidable.any():
        codes[decidable] = box_module(boxes[decidable], sigma)
    return codes


SHAVE = (0.5,)
CHUNK = 50_000                  # boxes in one chunk of the dextrous paving (RunOn.chunk by default)
"""Default slab fractions of :func:`dextrous`'s shaving: half of each edge, tried from every face
(BENCHMARKS.md: at eps = 0.05, inside 1.4125 -> 1.4961 and E 0.497 -> 0.298 for 2.7 times the box tests)."""


def shave_boxes(boxes: np.ndarray, *, sigma, delta: float, fractions=SHAVE, decide=None) -> Separation:
    """Contract the undecided boxes of the last level (largest edge at most ``delta``) by shaving slabs.

    For each fraction ``f`` in turn, and for each axis and each of its two
    faces, the slab of a box made of the ``f`` of its current edge next to
    that face goes through ``decide`` (default :func:`witnessed_module`); a
    slab proved inside or outside is cut off the box, and the next slab is
    taken from what is left (3B-style shaving of ``M(B)``).  Larger boxes
    are returned whole: bisection splits them anyway.

    Returns a :class:`~workspace_sym.interval.contractor.Separation`: the
    proved slabs and what is left of every box, which tile the input boxes
    (every cut is at one float, shared by the slab and the rest).  The
    paving confirms each slab with its own decider before declaring it
    (:func:`~workspace_sym.interval.paving.subdivide`).

    Parameters
    ----------
    boxes : array_like
        ``(N, 3, 2)`` undecided boxes.
    sigma : pair of float
        ``(sigma_min, sigma_max)``, for the default ``decide``.
    delta : float
        Only boxes whose largest edge is at most ``delta`` are shaved.
    fractions : sequence of float, default ``SHAVE``
        The slab fractions, in (0, 1), tried in turn.
    decide : callable, optional
        ``decide(boxes) -> codes`` for an ``(M, 3, 2)`` array; by default :func:`witnessed_module` with
        ``sigma``.

    Returns
    -------
    Separation
        ``inner`` and ``outer``, the slabs proved inside and outside, and ``kept``, one box per input box (what
        is left of it).
    """
    if decide is None:
        decide = partial(witnessed_module, sigma=sigma)
    kept = np.array(boxes, dtype=float)
    last = np.nonzero((kept[:, :, 1] - kept[:, :, 0]).max(axis=1) <= delta)[0]
    inner, outer = [np.empty((0, 3, 2))], [np.empty((0, 3, 2))]
    for f in fractions:
        for k in range(3):
            for side in (0, 1):
                if not len(last):
                    break
                slab = kept[last]
                lo, hi = slab[:, k, 0], slab[:, k, 1]
                cut = lo + f * (hi - lo) if side == 0 else hi - f * (hi - lo)
                ok = (cut > lo) & (cut < hi)                    # a slab one float thick is not cut
                slab[:, k, 1 - side] = cut
                codes = np.where(ok, decide(slab), UNDECIDED)
                inner.append(slab[codes == INSIDE])
                outer.append(slab[codes == OUTSIDE])
                kept[last[codes != UNDECIDED], k, side] = cut[codes != UNDECIDED]
    return Separation(np.concatenate(inner), np.concatenate(outer), kept)


def dextrous(variables, *, eps: float = 0.05, sigma=(0.25, 4.0), box=None, shave=SHAVE, stop: StopAt = StopAt(),
             run: RunOn = RunOn()) -> DextrousResult:
    """Certified dextrous workspace in ``[-1, 1]^3`` (paper section 4.2), ``variables`` naming x, y, z.

    Boxes are bisected while their largest edge exceeds ``eps``; smaller
    undecided boxes make up the error index E.  Each box goes through
    :func:`box_module`, except boxes with a numerically dextrous and a
    numerically non-dextrous point among their corners and centre, which
    no certificate could decide: they are bisected (or counted in E)
    straight away (:func:`witnessed_module`).

    ``shave`` (fractions in (0, 1), default ``SHAVE``) contracts each box
    that would be counted in E: slabs of these fractions of its edges, next
    to its faces, are cut off when proved inside or outside
    (:func:`shave_boxes`); ``()`` keeps the paper's plain bisection.

    ``stop`` (:class:`~workspace_sym.interval.driver.StopAt`) bounds the
    boxes and seconds; ``run``
    (:class:`~workspace_sym.interval.driver.RunOn`: an ``executor``, a
    ``concurrent.futures.Executor`` or a ``dask.distributed.Client``,
    ``max_memory``, ``store``, ``resume``; chunks of ``CHUNK`` boxes by default;
    ``progress``) spreads the chunks, streams the boxes to disk, checkpoints
    the run and shows its progress; the result is the same.

    Parameters
    ----------
    variables : sequence of sympy.Symbol
        The three symbols naming x, y and z (the box's variables).
    eps : float, default 0.05
        Boxes are bisected while their largest edge exceeds ``eps``.
    sigma : pair of float, default (0.25, 4.0)
        ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.
    box : dict, optional
        ``{variable: (lo, hi)}`` (:meth:`Box.from_bounds <workspace_sym.interval.boxes.Box.from_bounds>`), by
        default ``[-1, 1]`` for each of ``variables``.
    shave : sequence of float, default ``SHAVE``
        Slab fractions in (0, 1), as above; ``()`` for plain bisection.
    stop : StopAt, optional
        What to stop at (boxes evaluated, seconds); by default no limit.
    run : RunOn, optional
        Where to run (executor, chunk, max_memory, store, resume) and the progress bar.

    Returns
    -------
    DextrousResult
        The paving, with the inside volume and E.

    Raises
    ------
    InvalidParameterError
        When ``eps`` is not a positive finite number, ``sigma`` is not two numbers with
        ``0 < sigma_min < sigma_max``, or ``shave`` is not a sequence of fractions in (0, 1).
    BoxError
        When ``box`` is malformed.
    """
    if not isinstance(eps, (int, float)) or not math.isfinite(eps) or eps <= 0:
        raise InvalidParameterError(f"eps must be a positive number; got {eps!r}", parameter="eps")
    sigma = check_sigma(sigma)
    fractions = _check_shave(shave)
    b = Box.from_bounds(box or {v: (-1, 1) for v in variables})
    decide = partial(witnessed_module, sigma=sigma)          # picklable: it travels to other processes
    if run.chunk is None:
        run = replace(run, chunk=CHUNK)
    local = run.here
    if local:
        decide = threaded(decide)
    separate = partial(shave_boxes, sigma=sigma, delta=float(eps), fractions=fractions,
                       decide=decide if local else None) if fractions else None
    paving = subdivide(decide, b, delta=eps, size="width", stop=stop, run=run, label="dextrous", separate=separate)
    return DextrousResult(paving, sigma, float(eps), fractions)


def _check_shave(shave) -> tuple[float, ...]:
    try:
        fractions = tuple(float(f) for f in shave)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"shave must be a sequence of fractions in (0, 1); got {shave!r}",
                                    parameter="shave") from None
    if not all(0 < f < 1 for f in fractions):
        raise InvalidParameterError(f"shave must be a sequence of fractions in (0, 1); got {shave!r}",
                                    parameter="shave")
    return fractions


_CORNERS_AND_CENTRE = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)] + [[0.5, 0.5, 0.5]],
                               dtype=float)


def _square(v):
    return v.sq() if isinstance(v, Interval) else v**2


def _inverse_over(box: list[Interval], s: list[Interval], r: list[Interval], **options):
    """:func:`inverse_entries` over a box ``[X, Y, Z]`` given its leg terms ``s`` and ``r`` (:func:`leg_terms`)."""
    x, y, z = box
    return inverse_entries(x, y, z, s, r, **options)


def inverse_entries(x, y, z, s, r, *, gradients: bool = True, axes=(0, 1, 2)):
    """Upper triangle of ``N = A^T B^-2 A`` and of its three partial derivatives.

    ``s_i = 1/eta_i^2`` and ``r_i = 1/eta_i`` are passed in with the position,
    so one formula serves SymPy symbols (checked against ``Orthoglide.inverse``
    in the tests), floats and interval arrays.  Returns ``N`` and ``(dN/dx,
    dN/dy, dN/dz)`` (``None`` unless ``gradients``; only those in ``axes``,
    ``None`` for the others) as dicts ``{(i, j): entry}``
    for ``i <= j``; the chain rule used is ``ds1/dy = 2 y s1^2``,
    ``dr1/dy = y s1 r1`` and the like.

    Parameters
    ----------
    x, y, z : sympy.Expr, float, numpy.ndarray or Interval
        The position (all of one kind).
    s : sequence of three
        ``s_i = 1/eta_i^2`` of the same kind.
    r : sequence of three
        ``r_i = 1/eta_i`` of the same kind.
    gradients : bool, default True
        Whether to compute the partial derivatives.
    axes : tuple of int, default (0, 1, 2)
        The derivatives to compute: 0 for x, 1 for y, 2 for z.

    Returns
    -------
    tuple
        ``(N, gradients)``: ``N`` a dict ``{(i, j): entry}`` for ``i <= j``, ``gradients`` None or the triple
        ``(dN/dx, dN/dy, dN/dz)`` of such dicts, None for an axis not in ``axes``.
    """
    s1, s2, s3 = s
    r1, r2, r3 = r
    x2, y2, z2 = _square(x), _square(y), _square(z)
    N = {(0, 0): 1 + x2 * (s2 + s3), (1, 1): 1 + y2 * (s1 + s3), (2, 2): 1 + z2 * (s1 + s2),
         (0, 1): y * r1 + x * r2 + x * y * s3, (0, 2): z * r1 + x * z * s2 + x * r3,
         (1, 2): y * z * s1 + z * r2 + y * r3}
    if not gradients:
        return N, None
    dx = dy = dz = None
    if 0 in axes:
        dx = {(0, 0): 2 * x * (s2 + s3 + x2 * (_square(s2) + _square(s3))),
              (1, 1): 2 * x * y2 * _square(s3), (2, 2): 2 * x * z2 * _square(s2),
              (0, 1): r2 * (1 + x2 * s2) + y * s3 * (1 + 2 * x2 * s3),
              (0, 2): z * s2 * (1 + 2 * x2 * s2) + r3 * (1 + x2 * s3),
              (1, 2): x * (z * r2 * s2 + y * r3 * s3)}
    if 1 in axes:
        dy = {(0, 0): 2 * y * x2 * _square(s3), (1, 1): 2 * y * (s1 + s3 + y2 * (_square(s1) + _square(s3))),
              (2, 2): 2 * y * z2 * _square(s1),
              (0, 1): r1 * (1 + y2 * s1) + x * s3 * (1 + 2 * y2 * s3),
              (0, 2): y * (z * r1 * s1 + x * r3 * s3),
              (1, 2): z * s1 * (1 + 2 * y2 * s1) + r3 * (1 + y2 * s3)}
    if 2 in axes:
        dz = {(0, 0): 2 * z * x2 * _square(s2), (1, 1): 2 * z * y2 * _square(s1),
              (2, 2): 2 * z * (s1 + s2 + z2 * (_square(s1) + _square(s2))),
              (0, 1): z * (y * r1 * s1 + x * r2 * s2),
              (0, 2): r1 * (1 + z2 * s1) + x * s2 * (1 + 2 * z2 * s2),
              (1, 2): y * s1 * (1 + 2 * z2 * s1) + r2 * (1 + z2 * s2)}
    return N, (dx, dy, dz)


def leg_terms(X) -> tuple[list[Interval], list[Interval], list[Interval], list[Interval]]:
    """Squares, ``eta_i^2``, ``s_i = 1/eta_i^2`` and ``r_i = 1/eta_i`` as intervals.

    ``s_i`` and ``r_i`` are NaN (no enclosure) where ``eta_i^2`` may be <= 0.

    Parameters
    ----------
    X : sequence of Interval
        ``[X, Y, Z]``: interval arrays of the boxes' coordinates.

    Returns
    -------
    tuple of list of Interval
        ``(squares, eta2, s, r)``, three intervals each: ``[X^2, Y^2, Z^2]``, ``eta_i^2``, ``1/eta_i^2`` and
        ``1/eta_i``, outward-rounded.
    """
    squares = [v.sq() for v in X]
    eta2 = [1 - (squares[1] + squares[2]), 1 - (squares[0] + squares[2]), 1 - (squares[0] + squares[1])]
    s = [Interval(*arith.div((1.0, 1.0), (np.where(e.lo > 0, e.lo, np.nan), e.hi))) for e in eta2]
    r = [Interval(*arith.sqrt(v.pair)) for v in s]
    return squares, eta2, s, r


def reciprocal(v: float) -> tuple[float, float]:
    """Outward enclosure of 1/v for a float v > 0.

    Parameters
    ----------
    v : float
        A positive float.

    Returns
    -------
    tuple of float
        ``(lo, hi)`` with ``lo <= 1/v <= hi``.
    """
    q = 1.0 / v
    return float(arith.down(q)), float(arith.up(q))


def check_sigma(sigma):
    """``sigma`` read as ``(sigma_min, sigma_max)``, checked.

    Parameters
    ----------
    sigma : pair of numbers
        The bounds on the eigenvalues of ``J J^T``.

    Returns
    -------
    tuple of float
        ``(sigma_min, sigma_max)`` as floats.

    Raises
    ------
    InvalidParameterError
        When ``sigma`` is not two numbers, ``sigma_min`` is not positive and finite, ``sigma_max`` is not finite,
        or ``sigma_max <= sigma_min``.
    """
    try:
        lo, hi = (float(v) for v in sigma)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"sigma must be two numbers (sigma_min, sigma_max); got {sigma!r}",
                                    parameter="sigma") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo <= 0:
        raise InvalidParameterError(f"sigma_min must be a positive finite number; got {lo!r}", parameter="sigma")
    if lo >= hi:
        raise InvalidParameterError(f"sigma_max ({hi}) must exceed sigma_min ({lo})", parameter="sigma")
    return lo, hi
