"""The largest cube enclosed in the Orthoglide's dextrous workspace (Chablat, Wenger, Merlet 2002, section 5).

A numeric search on the diagonal, the binding points and, when they are the
two diagonal corners, the edge and centre in closed form from the model's
pencil; then two certificates that assume none of this, both budgeted box
searches (:func:`workspace_sym.interval.search.prove_all`) over the box
module of :mod:`.certificate`: the cube is inside, and no larger cube fits
anywhere.  The model (:class:`~workspace_sym.orthoglide.Orthoglide`) is passed
in and read for its pencil, symbols and eigenvalues; this module does not
import it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import partial

import numpy as np
import sympy as sp

from ..errors import InvalidParameterError
from ..interval import arith
from ..interval.driver import RunOn, StopAt, with_legacy_keywords
from ..interval.search import prove_all
from ..numbers import fmt, fmt_bound, fmt_bracket
from ..progress import stage_bar
from .certificate import box_module, check_sigma, numeric_dextrous

__all__ = ["CubeResult", "binding_points", "closed_form_cube", "cube_inside", "largest_cube", "no_enclosed_cube",
           "surface_points"]


@dataclass
class CubeResult:
    """Largest axis-aligned cube in the dextrous workspace, with certificates (paper section 5).

    A cube of edge ``edge_lower`` centred at ``center`` is proved inside; no
    cube of edge larger than ``edge_upper`` is enclosed anywhere (proved: for
    every possible centre, a point of such a cube is proved outside).

    Made by :func:`largest_cube`.

    Parameters
    ----------
    center : tuple of float
        The centre ``(x, y, z)`` of the cube proved inside.
    edge_lower : float
        The edge of the cube proved inside (0 when none was).
    edge_upper : float
        No enclosed cube has a larger edge.
    alpha : float
        The step of the search on the half-edge.
    sigma : tuple of float
        ``(sigma_min, sigma_max)``, the bounds on the eigenvalues of ``J J^T``.
    seconds : float
        Wall-clock time.
    boxes : dict
        Boxes evaluated by each certificate: ``{"inside_proof": ..., "upper_proof": ...}``.
    binding : list of dict, optional
        The binding points (:func:`binding_points`).
    exact : dict or None, optional
        The closed form (:func:`closed_form_cube`) when it was derived and lies in the certified bracket.
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
        return (f"edge = {e['edge']} = {float(e['edge']):.9f}, centre x = y = z = {e['center']} = "
                f"{float(e['center']):.9f} (binding: {self.binding_text()})")

    def binding_text(self) -> str:
        """The corners that bind the closed form and the bounds they meet (none without a closed form).

        Returns
        -------
        str
            ``"corner (+, +, +) on sigma_max; ..."``, or ``""`` without a closed form.
        """
        bounds = self.exact["bounds"] if self.exact is not None else {}
        return "; ".join(f"corner ({s}, {s}, {s}) on {', '.join(b)}" for s, b in bounds.items())

    def __repr__(self):
        return (f"CubeResult(edge in {fmt_bracket(self.edge_lower, self.edge_upper, 6)}, centre "
                f"({', '.join(fmt(v, 6) for v in self.center)}))")

    def _latex_lines(self) -> list[str]:
        """The closed form as LaTeX equations (empty when it was not derived)."""
        if self.exact is None:
            return []
        e = self.exact
        return [rf"\text{{edge}} = {sp.latex(e['edge'])} \approx {fmt(float(e['edge']), 9)}",
                rf"x = y = z = {sp.latex(e['center'])} \approx {fmt(float(e['center']), 9)}"]

    def _repr_latex_(self) -> str:
        lines = self._latex_lines() or [rf"\text{{edge}} \in {fmt_bracket(self.edge_lower, self.edge_upper, 9)}"]
        return "$\\displaystyle " + r", \quad ".join(lines) + "$"

    def _repr_markdown_(self) -> str:
        """The certified bracket, the centre and the closed form typeset (Jupyter)."""
        out = [f"**Largest cube in the dextrous workspace** ($\\sigma \\in [{self.sigma[0]:g}, {self.sigma[1]:g}]$, "
               f"$\\alpha = {self.alpha:g}$, {self.seconds:.1f} s)", "",
               f"- a cube of edge {fmt_bound(self.edge_lower, 9, up=False)} centred at "
               f"({', '.join(fmt(v, 6) for v in self.center)}) is proved inside;",
               f"- no cube of edge above {fmt_bound(self.edge_upper, 9, up=True)} fits anywhere (proved)."]
        lines = self._latex_lines()
        if lines:
            out += ["", f"Closed form (binding: {self.binding_text()}):", ""] + [f"$${line}$$" for line in lines]
        return "\n".join(out)

    def to_dict(self) -> dict:
        """The result as a JSON object (``workspace-sym cube --json``, docs/cli.md).

        Returns
        -------
        dict
            ``center``, ``edge_lower``, ``edge_upper``, ``alpha``, ``sigma``, ``seconds``, ``boxes`` and
            ``binding``; with ``closed_form``, ``edge_exact`` and ``center_exact`` (text) when the closed form
            was derived.
        """
        data = {"center": [float(v) for v in self.center], "edge_lower": self.edge_lower,
                "edge_upper": self.edge_upper, "alpha": self.alpha, "sigma": list(self.sigma),
                "seconds": self.seconds, "boxes": dict(self.boxes), "binding": self.binding}
        if self.exact is not None:
            data["closed_form"] = self.closed_form
            data["edge_exact"] = str(self.exact["edge"])
            data["center_exact"] = str(self.exact["center"])
        return data


INSIDE_BOXES = 200_000     # the budget of cube_inside when stop gives none
NO_CUBE_BOXES = 400_000    # the budget of no_enclosed_cube when stop gives none


def _budget(stop: StopAt, default: int) -> StopAt:
    """``stop`` with the certificate's own box budget when it gives none."""
    return stop if stop.max_boxes is not None else StopAt(default, stop.time_limit)


def cube_inside(center, half: float, *, sigma=(0.25, 4.0), min_width: float = 1e-3, stop: StopAt = StopAt(),
                run: RunOn = RunOn(), executor=None):
    """Prove that the cube of half-edge ``half`` at ``center`` lies in the dextrous workspace.

    Returns True (every sub-box proved inside), False (a sub-box proved
    outside) or None (undecided boxes narrower than ``min_width``, or the
    budget ran out), and the number of boxes evaluated.  ``stop``: the box
    budget (default ``INSIDE_BOXES``) and time limit of the search;
    ``run=RunOn(executor=...)`` spreads the evaluation
    (:func:`~workspace_sym.interval.search.prove_all`; ``executor=`` is its
    deprecated spelling).

    Parameters
    ----------
    center : array_like
        ``(3,)``: the centre of the cube.
    half : float
        Its half-edge.
    sigma : pair of float, default (0.25, 4.0)
        ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.
    min_width : float, default 1e-3
        Undecided sub-boxes narrower than this on every edge stop the search (verdict None).
    stop : StopAt, optional
        The box budget (``max_boxes``, default ``INSIDE_BOXES``) and ``time_limit`` of the search.
    run : RunOn, optional
        ``executor`` spreads the box evaluations; the search keeps no boxes.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Deprecated spelling of ``run=RunOn(executor=...)`` (a :class:`DeprecationWarning`).

    Returns
    -------
    tuple
        ``(verdict, used)``: True, False or None as above, and the number of boxes evaluated.

    Raises
    ------
    InvalidParameterError
        When ``sigma`` is not two numbers with ``0 < sigma_min < sigma_max``, or two different executors are
        given.
    """
    stop, run = with_legacy_keywords("cube_inside", stop, run, executor=executor)
    sigma = check_sigma(sigma)
    c = np.asarray(center, dtype=float)
    cube = np.stack([arith.down(c - half), arith.up(c + half)], axis=1)[None]     # holds the exact cube
    return prove_all(cube, partial(box_module, sigma=sigma), min_width=min_width, split="every",
                     stop=_budget(stop, INSIDE_BOXES), run=run)


def no_enclosed_cube(half: float, *, sigma=(0.25, 4.0), grid: int = 5, min_width: float = 1e-4,
                     stop: StopAt = StopAt(), run: RunOn = RunOn(), executor=None):
    """Prove that no cube of half-edge ``half`` lies in the dextrous workspace, wherever its centre.

    Centres are boxed in ``[-1, 1]^3`` (the workspace lies in the three
    cylinders).  Every cube centred in a box ``B`` of half-width ``u``
    contains the cube of half-edge ``half - u`` centred at the middle of
    ``B``; when a point of that smaller cube (a grid on its surface and its
    centre) is proved outside by the box module, ``B`` is discarded.
    Returns True, or None when boxes narrower than ``min_width`` remain or
    the budget ran out, and the number of centre boxes evaluated.  ``stop``
    and ``run`` as for :func:`cube_inside` (default budget ``NO_CUBE_BOXES``).

    Parameters
    ----------
    half : float
        The half-edge of the cubes.
    sigma : pair of float, default (0.25, 4.0)
        ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.
    grid : int, default 5
        Points per edge of the grid on each face of the shrunk cube (after its corners and centre).
    min_width : float, default 1e-4
        Undecided centre boxes narrower than this on every edge stop the search (verdict None).
    stop : StopAt, optional
        The box budget (``max_boxes``, default ``NO_CUBE_BOXES``) and ``time_limit`` of the search.
    run : RunOn, optional
        ``executor`` spreads the box evaluations; the search keeps no boxes.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Deprecated spelling of ``run=RunOn(executor=...)`` (a :class:`DeprecationWarning`).

    Returns
    -------
    tuple
        ``(verdict, used)``: True (proved) or None, and the number of centre boxes evaluated.

    Raises
    ------
    InvalidParameterError
        When ``sigma`` is not two numbers with ``0 < sigma_min < sigma_max``, or two different executors are
        given.
    """
    stop, run = with_legacy_keywords("no_enclosed_cube", stop, run, executor=executor)
    sigma = check_sigma(sigma)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    shapes = (np.vstack([corners, np.zeros((1, 3))]), np.vstack([surface_points(grid), np.zeros((1, 3))]))

    test = partial(_shrunk_cube_outside, half=half, shapes=shapes, sigma=sigma)     # picklable for executors
    return prove_all(np.array([[[-1.0, 1.0]] * 3]), test, min_width=min_width, split="every",
                     stop=_budget(stop, NO_CUBE_BOXES), run=run)


def _shrunk_cube_outside(centres, *, half, shapes, sigma):
    """Code 1 for a box of centres where a point of the shrunk cube is proved outside, 0 otherwise."""
    mid = 0.5 * (centres[:, :, 0] + centres[:, :, 1])
    u = 0.5 * (centres[:, :, 1] - centres[:, :, 0]).max(axis=1)
    shrunk = half - u
    alive = np.ones(len(centres), dtype=bool)
    for shape in shapes:                  # the corners and the centre first, then a grid on the faces
        idx = np.flatnonzero(alive & (shrunk > 0))
        if not len(idx):
            break
        pts = (mid[idx, None, :] + shrunk[idx, None, None] * shape[None, :, :]).reshape(-1, 3)
        codes = box_module(np.stack([pts, pts], axis=2), sigma).reshape(len(idx), len(shape))
        alive[idx] = ~(codes == -1).any(axis=1)
    return np.where(alive, 0, 1)


def largest_cube(model, *, alpha: float = 0.001, sigma=(0.25, 4.0), stop: StopAt = StopAt(),
                 run: RunOn = RunOn(), progress: bool | None = None, executor=None) -> CubeResult:
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

    ``stop`` (:class:`~workspace_sym.interval.driver.StopAt`): ``max_boxes``
    and ``time_limit`` bound each certificate search (default: :data:`INSIDE_BOXES` and
    :data:`NO_CUBE_BOXES` boxes, no time limit); a search that runs out proves
    nothing, so the bracket widens, never wrongly.  ``run``
    (:class:`~workspace_sym.interval.driver.RunOn`): ``executor`` spreads the
    certificates' box evaluations (a ``concurrent.futures.Executor`` or a
    ``dask.distributed.Client``); ``progress`` for the bar of the four
    stages.  ``progress=`` and ``executor=`` are the deprecated spellings of
    ``run=RunOn(progress=...)`` and ``run=RunOn(executor=...)``.

    Parameters
    ----------
    model : Orthoglide
        The model, read for its pencil, variables, leg terms and eigenvalues.
    alpha : float, default 0.001
        The step on the half-edge: the certified bracket of the half-edge is ``alpha`` wide (that of the edge
        ``2 alpha``) when both certificates succeed at the first try, wider by ``alpha / 2`` for each retry.
    sigma : pair of float, default (0.25, 4.0)
        ``(sigma_min, sigma_max)``: the bounds on the eigenvalues of ``J J^T``, ``0 < sigma_min < sigma_max``.
    stop : StopAt, optional
        ``max_boxes`` and ``time_limit`` of each certificate search, as above.
    run : RunOn, optional
        ``executor`` and ``progress``, as above.
    progress : bool or None, optional
        Deprecated spelling of ``run=RunOn(progress=...)``.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Deprecated spelling of ``run=RunOn(executor=...)``.

    Returns
    -------
    CubeResult
        The certified bracket of the edge, the centre, the binding points and the closed form when derived.

    Raises
    ------
    InvalidParameterError
        When ``alpha`` is not a positive finite number, ``sigma`` is not two numbers with
        ``0 < sigma_min < sigma_max``, or two different executors are given.
    """
    stop, run = with_legacy_keywords("largest_cube", stop, run, executor=executor, progress=progress)
    if not isinstance(alpha, (int, float)) or not math.isfinite(alpha) or alpha <= 0:
        raise InvalidParameterError(f"alpha must be a positive number; got {alpha!r}", parameter="alpha")
    sigma = check_sigma(sigma)
    start = time.perf_counter()
    say = stage_bar(run.progress if run.progress is not None else stop.progress, "cube", 4)
    search = StopAt(stop.max_boxes, stop.time_limit)     # of each certificate; the stage bar is the only bar
    say("numeric search on the diagonal")
    shape = np.vstack([surface_points(9), np.zeros((1, 3))])
    tol = min(alpha / 8, 1e-6)              # the search is cheap; the binding points need it accurate

    def fits(t, half):
        return numeric_dextrous(np.full(3, t) + half * shape, sigma).all()

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
    binding = binding_points(model, t_num, half, sigma, step=1e-4)
    closed = closed_form_cube(model, binding, t_num, half, sigma, tol=1e-3)
    if closed is not None:
        t_num, half = float(closed["center"]), float(closed["half"])
    centre = np.full(3, t_num)
    boxes = {"inside_proof": 0, "upper_proof": 0}
    say("certificate: the cube is inside")
    lower = half - alpha / 2
    while lower > 0:
        ok, used = cube_inside(centre, lower, sigma=sigma, min_width=alpha / 16, stop=search, run=run)
        boxes["inside_proof"] += used
        if ok:
            break
        lower -= alpha / 2
    lower = max(lower, 0.0)
    say("certificate: no larger cube anywhere")
    upper = lower + alpha
    while upper <= 1.0:
        ok, used = no_enclosed_cube(upper, sigma=sigma, min_width=alpha / 16, stop=search, run=run)
        boxes["upper_proof"] += used
        if ok:
            break
        upper += alpha / 2
    say(None)
    if closed is not None and not 2 * lower <= float(2 * closed["half"]) <= 2 * upper:
        closed = None                        # not what the certificates bracket: do not claim it
    return CubeResult(tuple(centre), 2 * lower, 2 * upper, float(alpha), sigma, time.perf_counter() - start,
                      boxes, binding, closed)


def binding_points(model, t: float, half: float, sigma, *, step: float) -> list[dict]:
    """Points of the cube's surface (9 x 9 grid per face) that leave the workspace when the half-edge grows by
    ``step``, with the bounds they cross: ``{"signs": [...], "point": [...], "bounds": [...]}``.

    Float eigenvalues (:meth:`Orthoglide.eigenvalues <workspace_sym.orthoglide.model.Orthoglide.eigenvalues>`):
    a guide for the closed form, not a proof.

    Parameters
    ----------
    model : Orthoglide
        The model, read for its eigenvalues.
    t : float
        The centre of the cube is ``(t, t, t)``.
    half : float
        Its half-edge.
    sigma : pair of float
        ``(sigma_min, sigma_max)``.
    step : float
        How much the half-edge grows.

    Returns
    -------
    list of dict
        One dict per point that leaves: ``signs`` (the point on the cube ``[-1, 1]^3``), ``point`` (its
        position on the grown cube) and ``bounds`` (``"sigma_min"``, ``"sigma_max"``, or ``"cylinder"`` when a
        leg is undefined there).
    """
    shape = surface_points(9)
    pts = t + (half + step) * shape
    out = []
    for s_, p in zip(shape, pts):
        ev = model.eigenvalues(p) if min(1 - p[1]**2 - p[2]**2, 1 - p[0]**2 - p[2]**2,
                                        1 - p[0]**2 - p[1]**2) > 0 else None
        if ev is None:
            out.append({"signs": s_.tolist(), "point": p.tolist(), "bounds": ["cylinder"]})
            continue
        bounds = [name for name, hit in (("sigma_min", ev[0] < sigma[0]), ("sigma_max", ev[-1] > sigma[1])) if hit]
        if bounds:
            out.append({"signs": s_.tolist(), "point": p.tolist(), "bounds": bounds})
    return out


def closed_form_cube(model, binding, t: float, half: float, sigma, *, tol: float):
    """Edge and centre in closed form when the binding points are the corners ``c -+ R (1, 1, 1)``.

    On the diagonal the pencil ``det(lambda A A^T - B^2)`` is a polynomial in
    ``u`` and ``sqrt(1 - 2 u^2)``; every binding corner gives the equation
    ``q(sigma_bound; u) = 0``, solved exactly, and the root next to the
    numeric corner is kept.  None when the binding points are elsewhere,
    the roots disagree, or SymPy finds no root there.

    Parameters
    ----------
    model : Orthoglide
        The model, read for its pencil, variables and leg terms.
    binding : list of dict
        The binding points (:func:`binding_points`).
    t : float
        The numeric centre ``(t, t, t)``.
    half : float
        The numeric half-edge.
    sigma : pair of float
        ``(sigma_min, sigma_max)``, read as the rationals they spell.
    tol : float
        A root is kept when it lies within ``tol`` of the numeric corner coordinate (exactly one must).

    Returns
    -------
    dict or None
        ``{"half", "center", "edge", "corners", "bounds"}``: SymPy numbers for the half-edge, the centre
        coordinate and the edge, the corner coordinates ``{"+": ..., "-": ...}`` and the bounds each corner
        meets; or None.
    """
    corners: dict[int, set[str]] = {}
    for b in binding:
        signs = tuple(int(v) for v in b["signs"])
        if signs not in ((1, 1, 1), (-1, -1, -1)) or "cylinder" in b["bounds"]:
            return None
        corners.setdefault(signs[0], set()).update(b["bounds"])
    if set(corners) != {1, -1}:
        return None
    u = sp.Symbol("u", real=True)
    lam = model.pencil.gens[0]
    q = (model.pencil.as_expr().subs({v: u for v in model.variables})
         .subs({e: sp.sqrt(1 - 2 * u**2) for e in model.eta}))
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


def surface_points(n: int) -> np.ndarray:
    """Points of the surface of the cube [-1, 1]^3 on an n x n grid per face, (m, 3).

    Parameters
    ----------
    n : int
        Points per edge of each face's grid.

    Returns
    -------
    numpy.ndarray
        ``(m, 3)`` points, sorted, each once (edges and corners are shared by faces): ``6 n^2 - 12 n + 8`` for
        ``n >= 2``.
    """
    g = np.linspace(-1, 1, n)
    a, b = (m.ravel() for m in np.meshgrid(g, g))
    faces = []
    for axis in range(3):
        for side in (-1.0, 1.0):
            pts = np.empty((len(a), 3))
            pts[:, axis] = side
            others = [k for k in range(3) if k != axis]
            pts[:, others[0]], pts[:, others[1]] = a, b
            faces.append(pts)
    return np.unique(np.vstack(faces), axis=0)
