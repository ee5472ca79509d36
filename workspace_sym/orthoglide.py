"""The Orthoglide (Chablat, Wenger, Merlet 2002): dextrous workspace and largest enclosed cube.

Model (METHODS.md section 3, leg length 1, the working mode of the isotropic
configuration): ``A = [[eta1, y, z], [x, eta2, z], [x, y, eta3]]``,
``B = diag(eta1, eta2, eta3)``, ``J = A^-1 B`` with
``eta1 = sqrt(1 - y^2 - z^2)``, ``eta2 = sqrt(1 - x^2 - z^2)``, ``eta3 = sqrt(1 - x^2 - y^2)``.

Certified box module ``M(B)`` (paper section 4.1, made rigorous):

* the eigenvalues of ``J J^T`` are the roots of
  ``q(lambda) = det(lambda A A^T - B^2) = det(A)^2 det(lambda I - J J^T)``.
  We certify with ``q`` rather than with the characteristic polynomial of
  ``J J^T`` or of its inverse ``A^T B^-2 A``: it has no division (those forms
  divide by ``det A`` or by ``eta_i^2``, whose enclosures blow up near the
  singular surfaces), and every ``eta_i`` enters only linearly or through
  ``eta_i^2``, which is replaced by its polynomial;
* a box is decided when it lies inside the three cylinders (``eta_i^2 > 0``),
  ``det A`` keeps its sign (no parallel singularity) and ``q(sigma_min)``,
  ``q(sigma_max)`` keep their signs on the whole box: then no eigenvalue equals
  ``sigma_min`` or ``sigma_max`` in the box and, by continuity, every point has
  the status of the centre;
* the status of the centre is itself certified: ``J J^T`` is symmetric, so ``q``
  has only real roots and Descartes' rule of signs on ``q(t + sigma)`` gives the
  exact number of eigenvalues above ``sigma`` from the signs of its
  coefficients, enclosed with intervals at the centre.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import sympy as sp

from .errors import InvalidParameterError
from .interval import arith
from .interval.compiler import compile_expr
from .interval.paving import Box, Paving, subdivide

__all__ = ["Orthoglide", "DextrousResult"]

x, y, z = sp.symbols("x y z", real=True)
e1, e2, e3 = sp.symbols("eta1 eta2 eta3", positive=True)
lam = sp.Symbol("lambda")


@dataclass(frozen=True, eq=False)
class DextrousResult:
    """Certified dextrous workspace: inside volume and the error index E (volume of undecided boxes)."""

    paving: Paving
    sigma: tuple[float, float]
    eps: float

    @property
    def volume_inner(self) -> float:
        return self.paving.measures["inner"]

    @property
    def volume_undecided(self) -> float:
        m = self.paving.measures
        return m["boundary"] + m["pending"]

    def to_dict(self) -> dict:
        p = self.paving
        return {
            "volume_inner": self.volume_inner,
            "volume_undecided": self.volume_undecided,
            "boxes": {"inner": len(p.inner), "undecided": len(p.boundary) + len(p.pending), "outer": len(p.outer)},
            "eps": self.eps,
            "sigma": list(self.sigma),
            "complete": p.complete,
            "boxes_evaluated": p.evaluated,
            "seconds": p.seconds,
        }


class Orthoglide:
    """Symbolic model and certified computations for the Orthoglide (leg length 1).

    Examples
    --------
    >>> o = Orthoglide()
    >>> np.round(o.eigenvalues([0.0, 0.0, 0.0]), 12)   # isotropic at the origin
    array([1., 1., 1.])
    """

    variables = (x, y, z)
    source = ("D. Chablat, P. Wenger, J.-P. Merlet, Workspace analysis of the Orthoglide using interval "
              "analysis, ARK 2002")

    # ------------------------------------------------------------------ symbolic model
    @cached_property
    def eta(self) -> dict:
        """``eta_i`` as functions of the position (defined inside the cylinders, paper eq. 6)."""
        return {e1: sp.sqrt(1 - y**2 - z**2), e2: sp.sqrt(1 - x**2 - z**2), e3: sp.sqrt(1 - x**2 - y**2)}

    @cached_property
    def eta_squared(self) -> dict:
        return {e1: 1 - y**2 - z**2, e2: 1 - x**2 - z**2, e3: 1 - x**2 - y**2}

    @cached_property
    def A(self) -> sp.Matrix:
        return sp.Matrix([[e1, y, z], [x, e2, z], [x, y, e3]])

    @cached_property
    def B(self) -> sp.Matrix:
        return sp.diag(e1, e2, e3)

    @cached_property
    def J(self) -> sp.Matrix:
        """``J = A^-1 B`` (in terms of x, y, z and the leg terms eta_i)."""
        return self.A.adjugate() * self.B / self.A.det()

    def _reduce(self, expr) -> sp.Expr:
        """Replace ``eta_i**2`` by its polynomial (every even power), keep odd powers linear."""
        expr = sp.expand(expr)
        poly = sp.Poly(expr, e1, e2, e3)
        out = sp.Integer(0)
        for (k1, k2, k3), c in poly.terms():
            term = c
            for e, k in ((e1, k1), (e2, k2), (e3, k3)):
                term *= self.eta_squared[e] ** (k // 2) * e ** (k % 2)
            out += term
        return sp.expand(out)

    @cached_property
    def pencil(self) -> sp.Poly:
        """``q(lambda) = det(lambda A A^T - B^2)``, a cubic in lambda whose roots are the eigenvalues of J J^T."""
        G = self.A * self.A.T
        D = self.B**2
        q = (lam * G - D).det(method="berkowitz")
        return sp.Poly(self._reduce(q), lam)

    @cached_property
    def charpoly(self) -> sp.Poly:
        """``det(lambda I - J J^T)`` as a polynomial in lambda (coefficients in x, y, z, eta_i).

        Equal to ``pencil / det(A)^2``; shown for reports, the certificates use the pencil.
        """
        detA = self._reduce(self.A.det())
        coeffs = [c / self._reduce(detA**2) for c in self.pencil.all_coeffs()]
        return sp.Poly.from_list(coeffs, lam)

    def shifted(self, sigma) -> list[sp.Expr]:
        """Coefficients of ``q(t + sigma)`` in t, highest first (Descartes' rule at sigma)."""
        t = sp.Symbol("t")
        q = sp.Poly(self.pencil.as_expr().subs(lam, t + sp.nsimplify(sigma)), t)
        return [self._reduce(c) for c in q.all_coeffs()]

    def latex(self) -> str:
        """LaTeX of the pencil polynomial, coefficient by coefficient."""
        return sp.latex(sp.collect(self.pencil.as_expr(), lam))

    # ------------------------------------------------------------------ numbers
    def jacobian(self, point) -> np.ndarray:
        px, py, pz = map(float, point)
        etas = [math.sqrt(1 - py**2 - pz**2), math.sqrt(1 - px**2 - pz**2), math.sqrt(1 - px**2 - py**2)]
        A = np.array([[etas[0], py, pz], [px, etas[1], pz], [px, py, etas[2]]])
        return np.linalg.solve(A, np.diag(etas))

    def eigenvalues(self, point) -> np.ndarray:
        """Eigenvalues of ``J J^T`` at a point (numpy, for pictures and checks)."""
        J = self.jacobian(point)
        return np.linalg.eigvalsh(J @ J.T)

    # ------------------------------------------------------------------ certified module M(B)
    def _compiled(self, sigma_min, sigma_max):
        """Interval evaluators over ``(x, y, z, eta1, eta2, eta3)``.

        The leg terms are separate interval variables enclosed by
        ``sqrt(max(eta_i^2, 0))`` over the box: the expressions stay polynomial
        (small trees, cheap centred forms), and the enclosures hold for every
        point of the box inside the cylinders.
        """
        key = (sigma_min, sigma_max)
        cache = self.__dict__.setdefault("_compiled_cache", {})
        if key not in cache:
            v6 = self.variables + (e1, e2, e3)
            detA = self._reduce(self.A.det())
            cache[key] = {
                "eta2": [compile_expr(self.eta_squared[e], self.variables) for e in (e1, e2, e3)],
                "detA": compile_expr(detA, v6),
                "legs": compile_expr(e1 * e2 * e3, v6),
                "shifted": {s_: [compile_expr(c, v6) for c in self.shifted(s_)] for s_ in (sigma_min, sigma_max)},
            }
        return cache[key]

    def box_module(self, boxes: np.ndarray, sigma=(0.25, 4.0)) -> np.ndarray:
        """``M(B)`` for an ``(N, 3, 2)`` array of boxes: 1 inside, -1 outside, 0 undecided (paper 4.1).

        Every 1 and -1 is proved with outward-rounded interval arithmetic (see
        the module docstring).  A box wholly outside a cylinder is -1; a box
        that straddles a cylinder can still be proved -1 through ``det(J J^T)``
        on its part inside the cylinders, never 1.
        """
        sigma_min, sigma_max = _check_sigma(sigma)
        f = self._compiled(sigma_min, sigma_max)
        n = len(boxes)
        X = [(boxes[:, k, 0], boxes[:, k, 1]) for k in range(3)]
        mid = 0.5 * boxes[:, :, 0] + 0.5 * boxes[:, :, 1]
        C = [(mid[:, k], mid[:, k]) for k in range(3)]
        with np.errstate(all="ignore"):
            eta2 = [tuple(np.broadcast_to(v, (n,)) for v in g(X)) for g in f["eta2"]]
            outside_cyl = np.any([hi < 0 for _, hi in eta2], axis=0)
            inside_cyl = np.all([lo > 0 for lo, _ in eta2], axis=0)
            E = [arith.sqrt((np.maximum(lo, 0.0), np.maximum(hi, 0.0))) for lo, hi in eta2]
            eta2_c = [tuple(np.broadcast_to(v, (n,)) for v in g(C)) for g in f["eta2"]]
            E_c = [arith.sqrt((np.maximum(lo, 0.0), np.maximum(hi, 0.0))) for lo, hi in eta2_c]
            XE, CE = X + E, C + E_c
            d_lo, d_hi = f["detA"](XE)
            regular = (d_lo > 0) | (d_hi < 0)
            # det(J J^T) = (eta1 eta2 eta3)^2 / det(A)^2 against sigma^3: below sigma_min^3 some
            # eigenvalue is below sigma_min, above sigma_max^3 one is above sigma_max.  Each factor is
            # enclosed on its own and squared with the tight square (an expanded quotient is far looser).
            P = arith.sqr(f["legs"](XE))
            D = arith.sqr((d_lo, d_hi))
            smin3, smax3 = (arith.const(*_enclose_cube(v)) for v in (sigma_min, sigma_max))
            surely_out = (arith.sub(P, arith.mul(smin3, D))[1] < 0) | (arith.sub(arith.mul(smax3, D), P)[1] < 0)
            status = {}
            for s_ in (sigma_min, sigma_max):
                coeffs = f["shifted"][s_]
                c0_lo, c0_hi = coeffs[-1](XE)
                no_cross = (c0_lo > 0) | (c0_hi < 0)
                sure = np.ones(n, dtype=bool)
                signs = []
                for g in coeffs:
                    lo, hi = (np.broadcast_to(v, (n,)) for v in g(CE))
                    sure &= (lo > 0) | (hi < 0)
                    signs.append(lo > 0)
                # All roots are real: Descartes' sign variations count the eigenvalues above sigma exactly.
                above = sum((a != b).astype(int) for a, b in zip(signs, signs[1:]))
                status[s_] = (no_cross & sure, above)
        ok = inside_cyl & regular & status[sigma_min][0] & status[sigma_max][0]
        all_in = (status[sigma_min][1] == 3) & (status[sigma_max][1] == 0)
        codes = np.where(ok, np.where(all_in, 1, -1), 0)
        return np.where(outside_cyl | surely_out, -1, codes)

    # ------------------------------------------------------------------ largest cube (paper section 5)
    def _numeric_dextrous(self, pts, sigma) -> np.ndarray:
        """Whether points are dextrous, by numpy eigenvalues (a guess for the search, never a certificate)."""
        pts = np.atleast_2d(pts)
        x, y, z = pts.T
        e2 = np.stack([1 - y**2 - z**2, 1 - x**2 - z**2, 1 - x**2 - y**2], axis=1)
        ok = (e2 > 0).all(axis=1)
        eta = np.sqrt(np.where(ok[:, None], e2, 1.0))
        A = np.empty((len(pts), 3, 3))
        A[:, 0] = np.stack([eta[:, 0], y, z], 1)
        A[:, 1] = np.stack([x, eta[:, 1], z], 1)
        A[:, 2] = np.stack([x, y, eta[:, 2]], 1)
        det = np.linalg.det(A)
        ok &= np.abs(det) > 1e-12
        A[~ok] = np.eye(3)
        J = np.linalg.solve(A, eta[:, :, None] * np.eye(3)[None])
        ev = np.linalg.eigvalsh(J @ np.swapaxes(J, 1, 2))
        return ok & (ev[:, 0] >= sigma[0]) & (ev[:, -1] <= sigma[1])

    def cube_inside(self, center, half: float, *, sigma=(0.25, 4.0), min_width: float = 1e-3,
                    max_boxes: int = 200_000):
        """Prove that the cube of half-edge ``half`` at ``center`` lies in the dextrous workspace.

        Returns True (every sub-box proved inside), False (a sub-box proved
        outside) or None (undecided boxes narrower than ``min_width``, or the
        budget ran out), and the number of boxes evaluated.
        """
        sigma = _check_sigma(sigma)
        c = np.asarray(center, dtype=float)
        work = np.stack([c - half, c + half], axis=1)[None]
        used = 0
        while len(work):
            used += len(work)
            if used > max_boxes:
                return None, used
            codes = self.box_module(work, sigma)
            if (codes == -1).any():
                return False, used
            work = work[codes == 0]
            if not len(work):
                return True, used
            if (work[:, :, 1] - work[:, :, 0]).max() < min_width:
                return None, used
            work = _octants(work)
        return True, used

    def no_enclosed_cube(self, half: float, *, sigma=(0.25, 4.0), grid: int = 5, min_width: float = 1e-4,
                         max_boxes: int = 400_000):
        """Prove that no cube of half-edge ``half`` lies in the dextrous workspace, wherever its centre.

        Centres are boxed in ``[-1, 1]^3`` (the workspace lies in the three
        cylinders).  Every cube centred in a box ``B`` of half-width ``u``
        contains the cube of half-edge ``half - u`` centred at the middle of
        ``B``; when a point of that smaller cube (a grid on its surface and its
        centre) is proved outside by the box module, ``B`` is discarded.
        Returns True, or None when boxes narrower than ``min_width`` remain or
        the budget ran out, and the number of centre boxes evaluated.
        """
        sigma = _check_sigma(sigma)
        shape = np.vstack([_surface_points(grid), np.zeros((1, 3))])
        work = np.array([[[-1.0, 1.0]] * 3])
        used = 0
        while len(work):
            used += len(work)
            if used > max_boxes:
                return None, used
            mid = 0.5 * (work[:, :, 0] + work[:, :, 1])
            u = 0.5 * (work[:, :, 1] - work[:, :, 0]).max(axis=1)
            shrunk = half - u
            alive = np.ones(len(work), dtype=bool)
            usable = shrunk > 0
            if usable.any():
                idx = np.flatnonzero(usable)
                pts = mid[idx, None, :] + shrunk[idx, None, None] * shape[None, :, :]       # (m, s, 3)
                pts = pts.reshape(-1, 3)
                codes = self.box_module(np.stack([pts, pts], axis=2), sigma).reshape(len(idx), len(shape))
                alive[idx] = ~(codes == -1).any(axis=1)
            work = work[alive]
            if not len(work):
                return True, used
            if (work[:, :, 1] - work[:, :, 0]).max() < min_width:
                return None, used
            work = _octants(work)
        return True, used

    def largest_cube(self, *, alpha: float = 0.001, sigma=(0.25, 4.0)) -> CubeResult:
        """The largest cube enclosed in the dextrous workspace, to ``alpha`` on the half-edge (paper section 5).

        The centre is searched numerically on the diagonal ``x = y = z`` (the
        mechanism's symmetry, where the paper finds it); the certificates do not
        assume it: ``cube_inside`` proves the returned cube, and
        ``no_enclosed_cube`` proves that no cube with half-edge ``alpha`` larger
        fits anywhere.
        """
        import time

        if not isinstance(alpha, (int, float)) or not math.isfinite(alpha) or alpha <= 0:
            raise InvalidParameterError(f"alpha must be a positive number; got {alpha!r}")
        sigma = _check_sigma(sigma)
        start = time.perf_counter()
        shape = np.vstack([_surface_points(9), np.zeros((1, 3))])

        def fits(t, half):
            return self._numeric_dextrous(np.full(3, t) + half * shape, sigma).all()

        def best_half(t):
            lo, hi = 0.0, 1.0
            if not fits(t, 0.0):
                return 0.0
            while hi - lo > alpha / 8:
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if fits(t, mid) else (lo, mid)
            return lo

        ts = np.linspace(-0.5, 0.5, 41)
        halves = [best_half(t) for t in ts]
        k = int(np.argmax(halves))
        a, b = ts[max(k - 1, 0)], ts[min(k + 1, len(ts) - 1)]
        for _ in range(30):                      # golden-section refinement of the centre
            m1, m2 = a + 0.382 * (b - a), a + 0.618 * (b - a)
            if best_half(m1) >= best_half(m2):
                b = m2
            else:
                a = m1
        t_best = 0.5 * (a + b)
        centre = np.full(3, t_best)
        half = best_half(t_best)
        boxes = {"inside_proof": 0, "upper_proof": 0}
        lower = half - alpha / 2
        while lower > 0:
            ok, used = self.cube_inside(centre, lower, sigma=sigma, min_width=alpha / 16)
            boxes["inside_proof"] += used
            if ok:
                break
            lower -= alpha / 2
        lower = max(lower, 0.0)
        upper = lower + alpha
        while upper <= 1.0:
            ok, used = self.no_enclosed_cube(upper, sigma=sigma, min_width=alpha / 16)
            boxes["upper_proof"] += used
            if ok:
                break
            upper += alpha / 2
        return CubeResult(tuple(centre), 2 * lower, 2 * upper, float(alpha), sigma, time.perf_counter() - start,
                          boxes)

    # ------------------------------------------------------------------ dextrous workspace
    def dextrous(self, *, eps: float = 0.05, sigma=(0.25, 4.0), box=None, progress=None, time_limit=None,
                 max_boxes=None) -> DextrousResult:
        """Certified dextrous workspace in ``[-1, 1]^3`` (paper section 4.2).

        Boxes are bisected while their largest edge is at least ``eps``;
        smaller undecided boxes make up the error index E.
        """
        if not isinstance(eps, (int, float)) or not math.isfinite(eps) or eps <= 0:
            raise InvalidParameterError(f"eps must be a positive number; got {eps!r}")
        sigma = _check_sigma(sigma)
        b = Box.from_bounds(box or {x: (-1, 1), y: (-1, 1), z: (-1, 1)})
        paving = subdivide(lambda boxes: self.box_module(boxes, sigma), b, delta=eps, size="width",
                           progress=progress, time_limit=time_limit, max_boxes=max_boxes, label="dextrous")
        return DextrousResult(paving, sigma, float(eps))


@dataclass
class CubeResult:
    """Largest axis-aligned cube in the dextrous workspace, with certificates (paper section 5).

    A cube of edge ``edge_lower`` centred at ``center`` is proved inside; no
    cube of edge larger than ``edge_upper`` is enclosed anywhere (proved: for
    every possible centre, a point of such a cube is proved outside).
    """

    center: tuple
    edge_lower: float
    edge_upper: float
    alpha: float
    sigma: tuple
    seconds: float
    boxes: dict

    def to_dict(self) -> dict:
        return {"center": [float(v) for v in self.center], "edge_lower": self.edge_lower,
                "edge_upper": self.edge_upper, "alpha": self.alpha, "sigma": list(self.sigma),
                "seconds": self.seconds, "boxes": dict(self.boxes)}


def _octants(boxes: np.ndarray) -> np.ndarray:
    """The eight halves-in-every-direction of each box of an ``(N, 3, 2)`` array."""
    mid = 0.5 * (boxes[:, :, 0] + boxes[:, :, 1])
    parts = []
    for corner in range(8):
        part = boxes.copy()
        for k in range(3):
            part[:, k, 1 - (corner >> k & 1)] = mid[:, k]
        parts.append(part)
    return np.concatenate(parts)


def _surface_points(n: int) -> np.ndarray:
    """Points of the surface of the cube [-1, 1]^3 on an n x n grid per face, (m, 3)."""
    g = np.linspace(-1, 1, n)
    a, b = np.meshgrid(g, g)
    a, b = a.ravel(), b.ravel()
    faces = []
    for axis in range(3):
        for side in (-1.0, 1.0):
            pts = np.empty((len(a), 3))
            pts[:, axis] = side
            others = [k for k in range(3) if k != axis]
            pts[:, others[0]], pts[:, others[1]] = a, b
            faces.append(pts)
    return np.unique(np.vstack(faces), axis=0)


def _enclose_cube(v: float) -> tuple[float, float]:
    """Outward enclosure of v**3 for a float v."""
    c = v * v * v
    return float(arith.down(arith.down(c))), float(arith.up(arith.up(c)))


def _check_sigma(sigma):
    try:
        lo, hi = (float(v) for v in sigma)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"sigma must be two numbers (sigma_min, sigma_max); got {sigma!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo <= 0:
        raise InvalidParameterError(f"sigma_min must be a positive finite number; got {lo!r}")
    if lo >= hi:
        raise InvalidParameterError(f"sigma_max ({hi}) must exceed sigma_min ({lo})")
    return lo, hi

