"""The Orthoglide (Chablat, Wenger, Merlet 2002): the symbolic model, and the entry points to its computations.

Model (docs/methods.md section 3, leg length 1, the working mode of the isotropic
configuration): ``A = [[eta1, y, z], [x, eta2, z], [x, y, eta3]]``,
``B = diag(eta1, eta2, eta3)``, ``J = A^-1 B`` with
``eta1 = sqrt(1 - y^2 - z^2)``, ``eta2 = sqrt(1 - x^2 - z^2)``, ``eta3 = sqrt(1 - x^2 - y^2)``.

:class:`Orthoglide` holds the model (SymPy matrices, the pencil and the
characteristic polynomial of ``J J^T``, float Jacobian and eigenvalues) and
hands the certified work to two modules that do not import it, the way
SymPy's ``KanesMethod`` hands linearisation to ``Linearizer``:
:mod:`.certificate` (the box module ``M(B)`` and the dextrous workspace
paving) and :mod:`.cube` (the largest enclosed cube and its certificates).
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np
import sympy as sp

from ..interval.driver import RunOn, StopAt, with_legacy_keywords
from . import certificate, cube

__all__ = ["Orthoglide"]

x, y, z = sp.symbols("x y z", real=True)
e1, e2, e3 = sp.symbols("eta1 eta2 eta3", positive=True)
lam = sp.Symbol("lambda")


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
        """``eta_i^2`` as polynomials of the position."""
        return {e1: 1 - y**2 - z**2, e2: 1 - x**2 - z**2, e3: 1 - x**2 - y**2}

    @cached_property
    def A(self) -> sp.Matrix:
        """``A = [[eta1, y, z], [x, eta2, z], [x, y, eta3]]`` (in x, y, z and the symbols eta_i)."""
        return sp.Matrix([[e1, y, z], [x, e2, z], [x, y, e3]])

    @cached_property
    def B(self) -> sp.Matrix:
        """``B = diag(eta1, eta2, eta3)``."""
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
        """LaTeX of the pencil polynomial, coefficient by coefficient.

        Returns
        -------
        str
            The pencil :attr:`pencil` collected in powers of lambda, as LaTeX.
        """
        return sp.latex(sp.collect(self.pencil.as_expr(), lam))

    # ------------------------------------------------------------------ numbers
    def jacobian(self, point) -> np.ndarray:
        """``J = A^-1 B`` at a point, in floats.

        Parameters
        ----------
        point : sequence of float
            ``(x, y, z)``, inside the three cylinders (every ``eta_i^2 >= 0``).

        Returns
        -------
        numpy.ndarray
            The 3 x 3 Jacobian.

        Raises
        ------
        ValueError
            From :func:`math.sqrt` when the point lies outside a cylinder (a leg is undefined).
        numpy.linalg.LinAlgError
            When ``A`` is singular there (a parallel singularity).
        """
        px, py, pz = map(float, point)
        etas = [math.sqrt(1 - py**2 - pz**2), math.sqrt(1 - px**2 - pz**2), math.sqrt(1 - px**2 - py**2)]
        A = np.array([[etas[0], py, pz], [px, etas[1], pz], [px, py, etas[2]]])
        return np.linalg.solve(A, np.diag(etas))

    def eigenvalues(self, point) -> np.ndarray:
        """Eigenvalues of ``J J^T`` at a point (numpy, for pictures and checks).

        Parameters
        ----------
        point : sequence of float
            ``(x, y, z)``, inside the three cylinders.

        Returns
        -------
        numpy.ndarray
            The three eigenvalues, ascending.
        """
        J = self.jacobian(point)
        return np.linalg.eigvalsh(J @ J.T)

    @cached_property
    def inverse(self) -> sp.Matrix:
        """``N = A^T B^-2 A = (J J^T)^-1``, the matrix the box module certifies."""
        return self.A.T * self.B**-2 * self.A

    # ------------------------------------------------------------------ certified computations (delegated)
    def box_module(self, boxes: np.ndarray, sigma=(0.25, 4.0)) -> np.ndarray:
        """``M(B)`` for an ``(N, 3, 2)`` array of boxes: 1 inside, -1 outside, 0 undecided
        (:func:`.certificate.box_module`, paper 4.1).

        Parameters
        ----------
        boxes : numpy.ndarray
            ``(N, 3, 2)`` boxes of positions.
        sigma : pair of float, default (0.25, 4.0)
            ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` verdict codes, each 1 and -1 proved.
        """
        return certificate.box_module(boxes, sigma)

    def numeric_dextrous(self, pts, sigma) -> np.ndarray:
        """Whether points are dextrous, in floats (:func:`.certificate.numeric_dextrous`; never a certificate).

        Parameters
        ----------
        pts : array_like
            ``(n, 3)`` positions.
        sigma : pair of float
            ``(sigma_min, sigma_max)``.

        Returns
        -------
        numpy.ndarray
            ``(n,)`` bools.
        """
        return certificate.numeric_dextrous(pts, sigma)

    def dextrous(self, *, eps: float = 0.05, sigma=(0.25, 4.0), box=None, shave=certificate.SHAVE,
                 stop: StopAt = StopAt(), run: RunOn = RunOn()) -> certificate.DextrousResult:
        """Certified dextrous workspace in ``[-1, 1]^3`` (:func:`.certificate.dextrous`, paper section 4.2).

        ``shave`` contracts the boxes that would count in E (:func:`.certificate.shave_boxes`; ``()``
        for the paper's plain bisection).  ``stop`` and ``run`` say what to stop at and where to run
        (:class:`~workspace_sym.interval.driver.StopAt`, :class:`~workspace_sym.interval.driver.RunOn`).

        Parameters
        ----------
        eps : float, default 0.05
            Boxes are bisected while their largest edge exceeds ``eps``.
        sigma : pair of float, default (0.25, 4.0)
            ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.
        box : dict, optional
            ``{variable: (lo, hi)}`` over :attr:`variables`; by default ``[-1, 1]^3``.
        shave : sequence of float, default ``certificate.SHAVE``
            Slab fractions in (0, 1); ``()`` for plain bisection.
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
            When ``eps``, ``sigma`` or ``shave`` is out of range.
        """
        return certificate.dextrous(self.variables, eps=eps, sigma=sigma, box=box, shave=shave, stop=stop, run=run)

    def cube_inside(self, center, half: float, *, sigma=(0.25, 4.0), min_width: float = 1e-3,
                    stop: StopAt = StopAt(), run: RunOn = RunOn(), executor=None):
        """Prove that a cube lies in the dextrous workspace (:func:`.cube.cube_inside`).

        Parameters
        ----------
        center : array_like
            ``(3,)``: the centre of the cube.
        half : float
            Its half-edge.
        sigma : pair of float, default (0.25, 4.0)
            ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.
        min_width : float, default 1e-3
            Undecided sub-boxes narrower than this stop the search.
        stop : StopAt, optional
            Box budget (default 200,000) and time limit.
        run : RunOn, optional
            ``executor`` spreads the box evaluations.
        executor : optional
            Deprecated spelling of ``run=RunOn(executor=...)``.

        Returns
        -------
        tuple
            ``(verdict, used)``: True (proved inside), False (a sub-box proved outside) or None, and the number
            of boxes evaluated.

        Raises
        ------
        InvalidParameterError
            When ``sigma`` is out of range or two different executors are given.
        """
        stop, run = with_legacy_keywords("cube_inside", stop, run, executor=executor)
        return cube.cube_inside(center, half, sigma=sigma, min_width=min_width, stop=stop, run=run)

    def no_enclosed_cube(self, half: float, *, sigma=(0.25, 4.0), grid: int = 5, min_width: float = 1e-4,
                         stop: StopAt = StopAt(), run: RunOn = RunOn(), executor=None):
        """Prove that no cube of half-edge ``half`` fits anywhere (:func:`.cube.no_enclosed_cube`).

        Parameters
        ----------
        half : float
            The half-edge of the cubes.
        sigma : pair of float, default (0.25, 4.0)
            ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.
        grid : int, default 5
            Points per edge of the grid on each face of the shrunk cubes.
        min_width : float, default 1e-4
            Undecided centre boxes narrower than this stop the search.
        stop : StopAt, optional
            Box budget (default 400,000) and time limit.
        run : RunOn, optional
            ``executor`` spreads the box evaluations.
        executor : optional
            Deprecated spelling of ``run=RunOn(executor=...)``.

        Returns
        -------
        tuple
            ``(verdict, used)``: True (proved) or None, and the number of centre boxes evaluated.

        Raises
        ------
        InvalidParameterError
            When ``sigma`` is out of range or two different executors are given.
        """
        stop, run = with_legacy_keywords("no_enclosed_cube", stop, run, executor=executor)
        return cube.no_enclosed_cube(half, sigma=sigma, grid=grid, min_width=min_width, stop=stop, run=run)

    def largest_cube(self, *, alpha: float = 0.001, sigma=(0.25, 4.0), stop: StopAt = StopAt(),
                     run: RunOn = RunOn(), progress: bool | None = None, executor=None) -> cube.CubeResult:
        """The largest cube enclosed in the dextrous workspace, certified.

        See :func:`.cube.largest_cube` and the paper's section 5: ``run`` holds the progress bar, ``stop`` the
        budget of each certificate search, ``run=RunOn(executor=...)`` spreads their box evaluations
        (``progress=`` and ``executor=`` are deprecated spellings of these).

        Parameters
        ----------
        alpha : float, default 0.001
            The step on the half-edge.
        sigma : pair of float, default (0.25, 4.0)
            ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.
        stop : StopAt, optional
            Box budget and time limit of each certificate search.
        run : RunOn, optional
            ``executor`` and ``progress``.
        progress : bool or None, optional
            Deprecated spelling of ``run=RunOn(progress=...)``.
        executor : optional
            Deprecated spelling of ``run=RunOn(executor=...)``.

        Returns
        -------
        CubeResult
            The certified bracket of the edge, the centre, and the closed form when derived.

        Raises
        ------
        InvalidParameterError
            When ``alpha`` or ``sigma`` is out of range or two different executors are given.
        """
        stop, run = with_legacy_keywords("largest_cube", stop, run, executor=executor, progress=progress)
        return cube.largest_cube(self, alpha=alpha, sigma=sigma, stop=stop, run=run)
