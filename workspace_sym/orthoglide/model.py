"""The Orthoglide (Chablat, Wenger, Merlet 2002): dextrous workspace and largest enclosed cube.

Model (METHODS.md section 3, leg length 1, the working mode of the isotropic
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
  intersected with the natural form, then rotated by the eigenvectors ``Q`` of
  ``N(c)``: ``Q^T N Q`` is nearly diagonal and its diagonal varies like the
  eigenvalues themselves (first order);
* inside (1): ``N - I/sigma_max`` and ``I/sigma_min - N`` are proved positive
  definite on the whole box (Sylvester's criterion on the rotated enclosure,
  see :mod:`workspace_sym.interval.symmetric`); outside (-1): a Rayleigh
  quotient proves ``lambda_min(N) < 1/sigma_max`` or ``lambda_max(N) > 1/sigma_min``
  on the whole box, or the box lies outside a cylinder, or (for a box that
  straddles a cylinder) a diagonal entry of ``N`` exceeds ``1/sigma_min`` on its
  part inside the cylinders.

The characteristic polynomial of ``J J^T`` (and the pencil ``det(lambda A A^T - B^2)``)
is derived symbolically for reports; certifying with it was measured far
weaker: at eps = 0.05 the pencil form with Descartes' rule left E = 2.66 in
105 s, the matrix form leaves E = 0.53 in about 1 s (BENCHMARKS.md).  A
polynomial coefficient mixes every eigenvalue and its enclosure over a box
grows with all of them, where the rotated matrix separates them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import sympy as sp

from .errors import InvalidParameterError
from .interval import arith, symmetric
from .interval.arith import Interval
from .interval.paving import Box, Paving, subdivide, threaded

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

        Equal to ``pencil / det(A)^2``; shown for reports (the certificates use :attr:`inverse`).
        """
        detA = self._reduce(self.A.det())
        coeffs = [c / self._reduce(detA**2) for c in self.pencil.all_coeffs()]
        return sp.Poly.from_list(coeffs, lam)

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
    @cached_property
    def inverse(self) -> sp.Matrix:
        """``N = A^T B^-2 A = (J J^T)^-1``, the matrix the box module certifies."""
        return self.A.T * self.B**-2 * self.A

    def box_module(self, boxes: np.ndarray, sigma=(0.25, 4.0)) -> np.ndarray:
        """``M(B)`` for an ``(N, 3, 2)`` array of boxes: 1 inside, -1 outside, 0 undecided (paper 4.1).

        Every 1 and -1 is proved with outward-rounded interval arithmetic (see
        the module docstring).  A box wholly outside a cylinder is -1; a box
        that straddles a cylinder can be proved -1 on its part inside the
        cylinders, never 1.
        """
        sigma_min, sigma_max = _check_sigma(sigma)
        a_lo, a_hi = _reciprocal(sigma_max)
        b_lo, b_hi = _reciprocal(sigma_min)
        n = len(boxes)
        lo, hi = boxes[:, :, 0], boxes[:, :, 1]
        mid = 0.5 * lo + 0.5 * hi
        with np.errstate(all="ignore"):
            X = [Interval(lo[:, k], hi[:, k]) for k in range(3)]
            squares, eta2, s, r = _leg_terms(X)
            outside_cyl = np.any([e.hi <= 0 for e in eta2], axis=0)
            # Straddling boxes: on the part inside the cylinders 1/eta_i^2 >= 1/max(eta_i^2).
            s_low = [Interval(*arith.point(arith.down(1.0 / e.hi))) for e in eta2]
            diag_low = [1 + squares[0] * (s_low[1] + s_low[2]), 1 + squares[1] * (s_low[0] + s_low[2]),
                        1 + squares[2] * (s_low[0] + s_low[1])]
            too_large = np.any([d.lo > b_hi for d in diag_low], axis=0)

            natural, gradient = inverse_entries(*X, s, r)
            C = [Interval(mid[:, k], mid[:, k].copy()) for k in range(3)]
            centre, _ = inverse_entries(*C, *_leg_terms(C)[2:], gradients=False)
            N_nat, N_c = symmetric.from_entries(natural), symmetric.from_entries(centre)
            regular = (np.all([e.lo > 0 for e in eta2], axis=0) & np.isfinite(N_nat[0]).all(axis=(1, 2))
                       & np.isfinite(N_nat[1]).all(axis=(1, 2)))
            point = 0.5 * N_c[0] + 0.5 * N_c[1]
            point[~regular] = np.eye(3)
            _, Q = np.linalg.eigh(point)
            S = symmetric.congruence(Q, N_c)
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
        return np.where(outside, -1, np.where(inside, 1, 0))

    # ------------------------------------------------------------------ largest cube (paper section 5)
    def _numeric_dextrous(self, pts, sigma) -> np.ndarray:
        """Whether points are dextrous, by float Sylvester tests on ``N = (J J^T)^-1`` (a guess for the search,
        the pictures and the tests, never a certificate)."""
        pts = np.atleast_2d(np.asarray(pts, dtype=float))
        x_, y_, z_ = pts.T
        e2 = np.stack([1 - y_**2 - z_**2, 1 - x_**2 - z_**2, 1 - x_**2 - y_**2])
        ok = (e2 > 0).all(axis=0)
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

    def _witnessed_module(self, boxes: np.ndarray, sigma) -> np.ndarray:
        """:meth:`box_module`, skipping boxes that numerically have a dextrous and a non-dextrous point.

        Such a box can be neither proved inside nor outside, and leaving a box
        undecided needs no proof, so the verdicts are those of ``box_module``
        on every box it could decide.  The centre and the eight corners are
        tested (float Sylvester tests, about 4 us a box against about 25 us
        for the certificate); at fine eps most undecided boxes straddle the
        boundary this way.
        """
        pts = boxes[:, None, :, 0] + _CORNERS_AND_CENTRE[None] * (boxes[:, None, :, 1] - boxes[:, None, :, 0])
        ok = self._numeric_dextrous(pts.reshape(-1, 3), sigma).reshape(len(boxes), -1)
        decidable = ok.all(axis=1) | ~ok.any(axis=1)
        codes = np.zeros(len(boxes), dtype=int)
        if decidable.any():
            codes[decidable] = self.box_module(boxes[decidable], sigma)
        return codes

    def cube_inside(self, center, half: float, *, sigma=(0.25, 4.0), min_width: float = 1e-3,
                    max_boxes: int = 200_000):
        """Prove that the cube of half-edge ``half`` at ``center`` lies in the dextrous workspace.

        Returns True (every sub-box proved inside), False (a sub-box proved
        outside) or None (undecided boxes narrower than ``min_width``, or the
        budget ran out), and the number of boxes evaluated.
        """
        sigma = _check_sigma(sigma)
        c = np.asarray(center, dtype=float)
        work = np.stack([arith.down(c - half), arith.up(c + half)], axis=1)[None]     # holds the exact cube
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
        corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
        shapes = (np.vstack([corners, np.zeros((1, 3))]), np.vstack([_surface_points(grid), np.zeros((1, 3))]))
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
            for shape in shapes:                  # the corners and the centre first, then a grid on the faces
                idx = np.flatnonzero(alive & (shrunk > 0))
                if not len(idx):
                    break
                pts = (mid[idx, None, :] + shrunk[idx, None, None] * shape[None, :, :]).reshape(-1, 3)
                codes = self.box_module(np.stack([pts, pts], axis=2), sigma).reshape(len(idx), len(shape))
                alive[idx] = ~(codes == -1).any(axis=1)
            work = work[alive]
            if not len(work):
                return True, used
            if (work[:, :, 1] - work[:, :, 0]).max() < min_width:
                return None, used
            work = _octants(work)
        return True, used

    def largest_cube(self, *, alpha: float = 0.001, sigma=(0.25, 4.0), progress: bool | None = None) -> CubeResult:
        """The largest cube enclosed in the dextrous workspace, to ``alpha`` on the half-edge (paper section 5).

        1. The centre is searched numerically on the diagonal ``x = y = z`` (the
           mechanism's symmetry, where the paper finds it).
        2. The binding points (those that leave the workspace when the cube
           grows a little) are identified on a grid of the cube's surface.  When
           they are the two corners on the diagonal, the pencil restricted to
           ``x = y = z = u`` is solved exactly for each corner and its bound:
           the edge and the centre in closed form (SymPy), used from then on.
        3. Certificates, which assume none of this: ``cube_inside`` proves the
           cube of half-edge ``R - alpha/2``, ``no_enclosed_cube`` proves that no
           cube of half-edge ``R + alpha/2`` fits anywhere.
        """
        import time

        if not isinstance(alpha, (int, float)) or not math.isfinite(alpha) or alpha <= 0:
            raise InvalidParameterError(f"alpha must be a positive number; got {alpha!r}")
        sigma = _check_sigma(sigma)
        start = time.perf_counter()
        say = _stages(progress, "cube")
        say("numeric search on the diagonal")
        shape = np.vstack([_surface_points(9), np.zeros((1, 3))])
        tol = min(alpha / 8, 1e-6)              # the search is cheap; the binding points need it accurate

        def fits(t, half):
            return self._numeric_dextrous(np.full(3, t) + half * shape, sigma).all()

        def best_half(t):
            lo, hi = 0.0, 1.0
            if not fits(t, 0.0):
                return 0.0
            while hi - lo > tol:
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if fits(t, mid) else (lo, mid)
            return lo

        ts = np.linspace(-0.5, 0.5, 41)
        halves = [best_half(t) for t in ts]
        k = int(np.argmax(halves))
        a, b = ts[max(k - 1, 0)], ts[min(k + 1, len(ts) - 1)]
        g = (math.sqrt(5) - 1) / 2
        m1, m2 = b - g * (b - a), a + g * (b - a)
        h1, h2 = best_half(m1), best_half(m2)
        while b - a > tol:                       # golden-section refinement of the centre
            if h1 >= h2:
                b, m2, h2 = m2, m1, h1
                m1 = b - g * (b - a)
                h1 = best_half(m1)
            else:
                a, m1, h1 = m1, m2, h2
                m2 = a + g * (b - a)
                h2 = best_half(m2)
        t_num = 0.5 * (a + b)
        half = best_half(t_num)
        say("binding points")
        binding = self._binding(t_num, half, sigma, step=1e-4)
        closed = self._closed_form_cube(binding, t_num, half, sigma, tol=1e-3)
        if closed is not None:
            t_num, half = float(closed["center"]), float(closed["half"])
        centre = np.full(3, t_num)
        boxes = {"inside_proof": 0, "upper_proof": 0}
        say("certificate: the cube is inside")
        lower = half - alpha / 2
        while lower > 0:
            ok, used = self.cube_inside(centre, lower, sigma=sigma, min_width=alpha / 16)
            boxes["inside_proof"] += used
            if ok:
                break
            lower -= alpha / 2
        lower = max(lower, 0.0)
        say("certificate: no larger cube anywhere")
        upper = lower + alpha
        while upper <= 1.0:
            ok, used = self.no_enclosed_cube(upper, sigma=sigma, min_width=alpha / 16)
            boxes["upper_proof"] += used
            if ok:
                break
            upper += alpha / 2
        say(None)
        if closed is not None and not 2 * lower <= float(2 * closed["half"]) <= 2 * upper:
            closed = None                        # not what the certificates bracket: do not claim it
        return CubeResult(tuple(centre), 2 * lower, 2 * upper, float(alpha), sigma, time.perf_counter() - start,
                          boxes, binding, closed)

    def _binding(self, t: float, half: float, sigma, *, step: float) -> list[dict]:
        """Points of the cube's surface (9 x 9 grid per face) that leave the workspace when the half-edge grows by
        ``step``, with the bounds they cross: ``{"corner": signs, "point": [...], "bounds": [...]}``."""
        shape = _surface_points(9)
        pts = t + (half + step) * shape
        out = []
        for s_, p in zip(shape, pts):
            ev = self.eigenvalues(p) if min(1 - p[1]**2 - p[2]**2, 1 - p[0]**2 - p[2]**2,
                                            1 - p[0]**2 - p[1]**2) > 0 else None
            if ev is None:
                out.append({"signs": s_.tolist(), "point": p.tolist(), "bounds": ["cylinder"]})
                continue
            bounds = [name for name, hit in (("sigma_min", ev[0] < sigma[0]), ("sigma_max", ev[-1] > sigma[1])) if hit]
            if bounds:
                out.append({"signs": s_.tolist(), "point": p.tolist(), "bounds": bounds})
        return out

    def _closed_form_cube(self, binding, t: float, half: float, sigma, *, tol: float):
        """Edge and centre in closed form when the binding points are the corners ``c -+ R (1, 1, 1)``.

        On the diagonal the pencil ``det(lambda A A^T - B^2)`` is a polynomial in
        ``u`` and ``sqrt(1 - 2 u^2)``; every binding corner gives the equation
        ``q(sigma_bound; u) = 0``, solved exactly, and the root next to the
        numeric corner is kept.  None when the binding points are elsewhere,
        the roots disagree, or SymPy finds no root there.
        """
        corners = {}
        for b in binding:
            signs = tuple(int(v) for v in b["signs"])
            if signs not in ((1, 1, 1), (-1, -1, -1)) or "cylinder" in b["bounds"]:
                return None
            corners.setdefault(signs[0], set()).update(b["bounds"])
        if set(corners) != {1, -1}:
            return None
        u = sp.Symbol("u", real=True)
        q = self.pencil.as_expr().subs({x: u, y: u, z: u}).subs({e: sp.sqrt(1 - 2 * u**2) for e in (e1, e2, e3)})
        values = {}
        for sign, bounds in corners.items():
            guess = t + sign * half
            roots = set()
            for bound in bounds:
                level = sp.nsimplify(sigma[0] if bound == "sigma_min" else sigma[1])
                sols = [r for r in sp.solve(sp.expand(q.subs(lam, level)), u) if r.is_real]
                near = [r for r in sols if abs(float(r) - guess) < tol]
                if len(near) != 1:
                    return None
                roots.add(sp.radsimp(near[0]))
            if len(roots) != 1:
                return None
            values[sign] = roots.pop()
        half_exact = sp.radsimp((values[1] - values[-1]) / 2)
        centre_exact = sp.radsimp((values[1] + values[-1]) / 2)
        return {"half": half_exact, "center": centre_exact, "edge": sp.radsimp(2 * half_exact),
                "corners": {"+": values[1], "-": values[-1]},
                "bounds": {("+" if k > 0 else "-"): sorted(v) for k, v in corners.items()}}

    # ------------------------------------------------------------------ dextrous workspace
    def dextrous(self, *, eps: float = 0.05, sigma=(0.25, 4.0), box=None, progress=None, time_limit=None,
                 max_boxes=None) -> DextrousResult:
        """Certified dextrous workspace in ``[-1, 1]^3`` (paper section 4.2).

        Boxes are bisected while their largest edge exceeds ``eps``; smaller
        undecided boxes make up the error index E.  Each box goes through
        :meth:`box_module`, except boxes with a numerically dextrous and a
        numerically non-dextrous point among their corners and centre, which
        no certificate could decide: they are bisected (or counted in E)
        straight away (:meth:`_witnessed_module`).
        """
        if not isinstance(eps, (int, float)) or not math.isfinite(eps) or eps <= 0:
            raise InvalidParameterError(f"eps must be a positive number; got {eps!r}")
        sigma = _check_sigma(sigma)
        b = Box.from_bounds(box or {x: (-1, 1), y: (-1, 1), z: (-1, 1)})
        paving = subdivide(threaded(lambda boxes: self._witnessed_module(boxes, sigma)), b, delta=eps, size="width",
                           progress=progress, time_limit=time_limit, max_boxes=max_boxes, label="dextrous",
                           chunk=50_000)
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
    binding: list = field(default_factory=list)
    exact: dict | None = None

    @property
    def closed_form(self) -> str | None:
        """The edge and the centre in closed form, with the binding corners, when they were derived."""
        if self.exact is None:
            return None
        e = self.exact
        bounds = "; ".join(f"corner ({s}, {s}, {s}) on {', '.join(b)}" for s, b in e["bounds"].items())
        return (f"edge = {e['edge']} = {float(e['edge']):.9f}, centre x = y = z = {e['center']} = "
                f"{float(e['center']):.9f} (binding: {bounds})")

    def to_dict(self) -> dict:
        data = {"center": [float(v) for v in self.center], "edge_lower": self.edge_lower,
                "edge_upper": self.edge_upper, "alpha": self.alpha, "sigma": list(self.sigma),
                "seconds": self.seconds, "boxes": dict(self.boxes), "binding": self.binding}
        if self.exact is not None:
            data["closed_form"] = self.closed_form
            data["edge_exact"] = str(self.exact["edge"])
            data["center_exact"] = str(self.exact["center"])
        return data


def _stages(progress, label):
    """``say(text)`` writes the stage of a long run on stderr (by default when stderr is a terminal)."""
    import sys

    enabled = sys.stderr.isatty() if progress is None else bool(progress)
    shown = [False]

    def say(text):
        if not enabled:
            return
        if text is None:
            if shown[0]:
                sys.stderr.write("\n")
            return
        sys.stderr.write(f"\r{label}: {text:<45}")
        sys.stderr.flush()
        shown[0] = True

    return say


_CORNERS_AND_CENTRE = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)] + [[0.5, 0.5, 0.5]],
                               dtype=float)


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


def _square(v):
    return v.sq() if isinstance(v, Interval) else v**2


def inverse_entries(x, y, z, s, r, *, gradients: bool = True):
    """Upper triangle of ``N = A^T B^-2 A`` and of its three partial derivatives.

    ``s_i = 1/eta_i^2`` and ``r_i = 1/eta_i`` are passed in with the position,
    so one formula serves SymPy symbols (checked against ``Orthoglide.inverse``
    in the tests), floats and interval arrays.  Returns ``N`` and ``(dN/dx,
    dN/dy, dN/dz)`` (``None`` unless ``gradients``) as dicts ``{(i, j): entry}``
    for ``i <= j``; the chain rule used is ``ds1/dy = 2 y s1^2``,
    ``dr1/dy = y s1 r1`` and the like.
    """
    s1, s2, s3 = s
    r1, r2, r3 = r
    x2, y2, z2 = _square(x), _square(y), _square(z)
    N = {(0, 0): 1 + x2 * (s2 + s3), (1, 1): 1 + y2 * (s1 + s3), (2, 2): 1 + z2 * (s1 + s2),
         (0, 1): y * r1 + x * r2 + x * y * s3, (0, 2): z * r1 + x * z * s2 + x * r3,
         (1, 2): y * z * s1 + z * r2 + y * r3}
    if not gradients:
        return N, None
    dx = {(0, 0): 2 * x * (s2 + s3 + x2 * (_square(s2) + _square(s3))),
          (1, 1): 2 * x * y2 * _square(s3), (2, 2): 2 * x * z2 * _square(s2),
          (0, 1): r2 * (1 + x2 * s2) + y * s3 * (1 + 2 * x2 * s3),
          (0, 2): z * s2 * (1 + 2 * x2 * s2) + r3 * (1 + x2 * s3),
          (1, 2): x * (z * r2 * s2 + y * r3 * s3)}
    dy = {(0, 0): 2 * y * x2 * _square(s3), (1, 1): 2 * y * (s1 + s3 + y2 * (_square(s1) + _square(s3))),
          (2, 2): 2 * y * z2 * _square(s1),
          (0, 1): r1 * (1 + y2 * s1) + x * s3 * (1 + 2 * y2 * s3),
          (0, 2): y * (z * r1 * s1 + x * r3 * s3),
          (1, 2): z * s1 * (1 + 2 * y2 * s1) + r3 * (1 + y2 * s3)}
    dz = {(0, 0): 2 * z * x2 * _square(s2), (1, 1): 2 * z * y2 * _square(s1),
          (2, 2): 2 * z * (s1 + s2 + z2 * (_square(s1) + _square(s2))),
          (0, 1): z * (y * r1 * s1 + x * r2 * s2),
          (0, 2): r1 * (1 + z2 * s1) + x * s2 * (1 + 2 * z2 * s2),
          (1, 2): y * s1 * (1 + 2 * z2 * s1) + r2 * (1 + z2 * s2)}
    return N, (dx, dy, dz)


def _leg_terms(X):
    """Squares, ``eta_i^2``, ``s_i = 1/eta_i^2`` and ``r_i = 1/eta_i`` as intervals.

    ``s_i`` and ``r_i`` are NaN (no enclosure) where ``eta_i^2`` may be <= 0.
    """
    squares = [v.sq() for v in X]
    eta2 = [1 - (squares[1] + squares[2]), 1 - (squares[0] + squares[2]), 1 - (squares[0] + squares[1])]
    s = [Interval(*arith.div((1.0, 1.0), (np.where(e.lo > 0, e.lo, np.nan), e.hi))) for e in eta2]
    r = [Interval(*arith.sqrt(v.pair)) for v in s]
    return squares, eta2, s, r


def _reciprocal(v: float) -> tuple[float, float]:
    """Outward enclosure of 1/v for a float v > 0."""
    q = 1.0 / v
    return float(arith.down(q)), float(arith.up(q))


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

