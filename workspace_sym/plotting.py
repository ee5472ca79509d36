"""Figures (matplotlib).  Kernels never import this module; it imports matplotlib lazily.

Every function takes an optional ``ax`` and returns the artists it drew, so that
notebooks can compose figures and tests can check what was drawn.
"""

from __future__ import annotations

import numpy as np

__all__ = ["scatter_workspace_3d", "plot_reach", "plot_sweeps", "plot_paving", "plot_paving_slices", "save_figure",
           "plot_planar_step", "plot_boundary_loops"]


def _pyplot():
    # Imported here so that importing workspace_sym never loads matplotlib;
    # without a display matplotlib falls back to the Agg backend by itself.
    import matplotlib.pyplot as plt

    return plt


def _axes3d(ax):
    plt = _pyplot()
    if ax is None:
        fig = plt.figure(figsize=(6, 5))
        ax = fig.add_subplot(projection="3d")
    return ax


def scatter_workspace_3d(points, *, ax=None, color=None, size=1.0, title=None, units="m"):
    """3D scatter of reachable points (paper 004, figures 2-5).  Returns the ``PathCollection``."""
    points = np.asarray(points)
    ax = _axes3d(ax)
    artist = ax.scatter(points[:, 0], points[:, 1], points[:, 2], s=size,
                        c=color if color is not None else points[:, 2],
                        cmap=None if color is not None else "viridis", depthshade=False)
    ax.set_xlabel(f"x ({units})")
    ax.set_ylabel(f"y ({units})")
    ax.set_zlabel(f"z ({units})")
    if title:
        ax.set_title(title)
    _equal_3d(ax, points)
    return artist


def _equal_3d(ax, points):
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, 1e-9)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)


def plot_sweeps(robot, joints, *, n=200, ax=None, parameters=None):
    """Trajectories of the end-effector when each of ``joints`` sweeps its range alone
    (paper 004, figures 6-10).  Returns one ``Line3D`` per joint."""
    from .sampling import reach_points, sweep_joints

    ax = _axes3d(ax)
    lines = []
    q = sweep_joints(robot, joints, n)
    pts = reach_points(robot, q, parameters)
    for k, j in enumerate(joints):
        seg = pts[k * n:(k + 1) * n]
        (line,) = ax.plot(seg[:, 0], seg[:, 1], seg[:, 2], label=f"theta{j} sweep")
        lines.append(line)
    ax.legend(loc="upper left", fontsize="small")
    _equal_3d(ax, pts)
    return lines


def plot_reach(points, *, ax=None, units="m"):
    """Side view ``(r, z)`` with ``r = sqrt(x^2 + y^2)``: the reach and height of the workspace.

    Returns the scatter artist.
    """
    plt = _pyplot()
    points = np.asarray(points)
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 4))
    r = np.hypot(points[:, 0], points[:, 1])
    artist = ax.scatter(r, points[:, 2], s=0.5, alpha=0.4)
    ax.set_xlabel(f"r = sqrt(x² + y²) ({units})")
    ax.set_ylabel(f"z ({units})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(f"reach {np.linalg.norm(points, axis=1).max():.4g} {units}")
    return artist


def save_figure(artists, path, *, dpi=120):
    """Save the figure that holds ``artists`` (an artist, axes, list or dict of artists) and close it.

    The file is written under a temporary name and renamed, so a failure never
    leaves a half-written image.
    """
    import os
    from pathlib import Path

    plt = _pyplot()
    obj = artists
    if isinstance(obj, dict):
        obj = next(iter(obj.values()))
    if isinstance(obj, list):
        obj = obj[0]
    fig = obj.figure if hasattr(obj, "figure") and obj.figure is not None else obj
    path = Path(path)
    tmp = path.with_name(f".{path.name}.partial{path.suffix}")
    try:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight")
        os.replace(tmp, path)
    finally:
        plt.close(fig)
        if tmp.exists():
            tmp.unlink()
    return path


def plot_paving(paving, *, ax=None, show_outer=False, exact_boundary=None, title=None):
    """Inner (green) and boundary (yellow) boxes of a 2D or 3D paving (Rybak et al., figure 4).

    ``exact_boundary`` is a callable ``(x, y) -> array`` whose zero level set
    is drawn over a 2D paving (e.g. ``max_j g_j``).  Returns a dict of the
    artists drawn, keyed by box kind.
    """
    plt = _pyplot()
    n = len(paving.variables)
    if n == 3:
        return _plot_paving_3d(paving, ax=ax, title=title)
    if n != 2:
        raise ValueError(f"plot_paving draws 2D or 3D pavings; this one has {n} variables")
    from matplotlib.collections import PolyCollection

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 3.5))
    artists = {}
    kinds = [("inner", "#4caf50"), ("boundary", "#ffd54f")] + ([("outer", "#e0e0e0")] if show_outer else [])
    for kind, colour in kinds:
        boxes = getattr(paving, kind)
        verts = [[(b[0, 0], b[1, 0]), (b[0, 1], b[1, 0]), (b[0, 1], b[1, 1]), (b[0, 0], b[1, 1])] for b in boxes]
        coll = PolyCollection(verts, facecolors=colour, edgecolors="k", linewidths=0.2, label=f"{kind} ({len(boxes)})")
        ax.add_collection(coll)
        artists[kind] = coll
    lo, hi = paving.box.lower, paving.box.upper
    if exact_boundary is not None:
        xs, ys = np.meshgrid(np.linspace(lo[0], hi[0], 600), np.linspace(lo[1], hi[1], 300))
        artists["exact"] = ax.contour(xs, ys, exact_boundary(xs, ys), levels=[0.0], colors="r", linewidths=1.0)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel(str(paving.variables[0]))
    ax.set_ylabel(str(paving.variables[1]))
    m_lo, m_hi = paving.measure_bounds
    how = " with contraction" if paving.contract else ""
    ax.set_title(title or f"delta = {paving.delta}{how}: area in [{m_lo:.4f}, {m_hi:.4f}]")
    ax.legend(loc="upper right", fontsize="small")
    return artists


def _plot_paving_3d(paving, *, ax=None, title=None):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    ax = _axes3d(ax)
    artists = {}
    for kind, colour, alpha in (("inner", "#4caf50", 0.5), ("boundary", "#ffd54f", 0.15)):
        faces = []
        for b in getattr(paving, kind):
            (x0, x1), (y0, y1), (z0, z1) = b
            corners = np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])
            for quad in ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)):
                faces.append(corners[list(quad)])
        coll = Poly3DCollection(faces, facecolors=colour, edgecolors="none", alpha=alpha)
        ax.add_collection3d(coll)
        artists[kind] = coll
    ax.set_xlim(paving.box.lower[0], paving.box.upper[0])
    ax.set_ylim(paving.box.lower[1], paving.box.upper[1])
    ax.set_zlim(paving.box.lower[2], paving.box.upper[2])
    for setter, v in zip((ax.set_xlabel, ax.set_ylabel, ax.set_zlabel), paving.variables):
        setter(str(v))
    if title:
        ax.set_title(title)
    return artists


def plot_paving_slices(paving, *, axis: int = 2, values=(-0.4, 0.0, 0.3), reference=None, title=None):
    """2D slices of a 3D paving: the boxes met by the plane ``variable[axis] = value``, one panel per value.

    ``reference`` is an optional callable ``(points (m, 3)) -> bool array`` (for
    instance numeric eigenvalues) whose boundary is drawn in red on each slice,
    an independent picture to hold the certified boxes against.  Returns the
    figure.
    """
    from matplotlib.collections import PolyCollection

    plt = _pyplot()
    if len(paving.variables) != 3:
        raise ValueError(f"plot_paving_slices draws 3D pavings; this one has {len(paving.variables)} variables")
    others = [k for k in range(3) if k != axis]
    lo, hi = paving.box.lower, paving.box.upper
    fig, axes = plt.subplots(1, len(values), figsize=(3.6 * len(values), 3.6), squeeze=False)
    for ax, v in zip(axes[0], values):
        for kind, colour in (("inner", "#4caf50"), ("boundary", "#ffd54f")):
            boxes = getattr(paving, kind)
            boxes = boxes[(boxes[:, axis, 0] <= v) & (v <= boxes[:, axis, 1])]
            a, b = others
            verts = [[(q[a, 0], q[b, 0]), (q[a, 1], q[b, 0]), (q[a, 1], q[b, 1]), (q[a, 0], q[b, 1])] for q in boxes]
            ax.add_collection(PolyCollection(verts, facecolors=colour, edgecolors="none",
                                             label=f"{kind} ({len(boxes)})"))
        if reference is not None:
            u, w = np.meshgrid(np.linspace(lo[others[0]], hi[others[0]], 400),
                               np.linspace(lo[others[1]], hi[others[1]], 400))
            pts = np.empty(u.shape + (3,))
            pts[..., axis], pts[..., others[0]], pts[..., others[1]] = v, u, w
            inside = np.asarray(reference(pts.reshape(-1, 3)), dtype=float).reshape(u.shape)
            ax.contour(u, w, inside, levels=[0.5], colors="r", linewidths=0.8)
        ax.set_xlim(lo[others[0]], hi[others[0]])
        ax.set_ylim(lo[others[1]], hi[others[1]])
        ax.set_aspect("equal")
        ax.set_xlabel(str(paving.variables[others[0]]))
        ax.set_ylabel(str(paving.variables[others[1]]))
        ax.set_title(f"{paving.variables[axis]} = {v}", fontsize="medium")
        ax.legend(loc="upper right", fontsize="x-small")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


_ARC_COLOURS = {"I": "tab:blue", "II": "tab:red", "III": "tab:green"}   # the paper's figures 4 to 6


def _draw_arc(ax, center, radius, a0, a1, *, color, lw=1.2, side=0, tick=None):
    t = np.linspace(a0, a1, max(8, int(abs(a1 - a0) / 0.01)))
    (line,) = ax.plot(center[0] + radius * np.cos(t), center[1] + radius * np.sin(t), color=color, lw=lw)
    if side and tick:
        m = 0.5 * (a0 + a1)
        r0, r1 = radius, radius + side * tick
        ax.plot([center[0] + r0 * np.cos(m), center[0] + r1 * np.cos(m)],
                [center[1] + r0 * np.sin(m), center[1] + r1 * np.sin(m)], color=color, lw=lw)
    return line


def plot_planar_step(chain, step: int, *, ax=None, samples: int = 20000, seed: int = 0, title=None):
    """One step of the alignment method, drawn like the paper's figures 4 to 6.

    Step 0: the candidate arcs; step 1: the kept arcs, with a tick on the side
    of the workspace; step 2: the boundary loops and the enclosed workspace.
    Arcs are blue (type I), red (type II) or green (type III); the gold dots
    are ``samples`` random configurations (the discrete swept area).
    """
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath

    plt = _pyplot()
    if step not in (0, 1, 2):
        from .errors import InvalidParameterError

        raise InvalidParameterError(f"step must be 0, 1 or 2; got {step!r}")
    if ax is None:
        _, ax = plt.subplots(figsize=(5.5, 5.5))
    artists = {}
    if samples:
        pts = chain.forward(chain.sample(samples, seed=seed, corners=False))
        artists["samples"] = ax.scatter(pts[:, 0], pts[:, 1], s=0.3, color="gold", alpha=0.5, lw=0)
    tick = 0.03 * chain.reach
    if step == 0:
        arcs = chain.candidate_arcs()
        artists["arcs"] = [_draw_arc(ax, a.center, a.radius, a.start_angle, a.end_angle,
                                     color=_ARC_COLOURS[a.type], lw=0.8) for a in arcs]
    elif step == 1:
        arcs = chain.kept_arcs()
        artists["arcs"] = [_draw_arc(ax, a.center, a.radius, a.start_angle, a.end_angle,
                                     color=_ARC_COLOURS[a.type], side=a.side, tick=tick) for a in arcs]
    else:
        b = chain.boundary()
        arcs = b.arcs
        polys = b.polygon(step=0.005)
        if polys:
            verts = np.vstack([np.vstack([p, p[:1]]) for p in polys])
            codes = np.concatenate([[MplPath.MOVETO] + [MplPath.LINETO] * (len(p) - 1) + [MplPath.CLOSEPOLY]
                                    for p in polys])
            artists["fill"] = ax.add_patch(PathPatch(MplPath(verts, codes), facecolor="khaki", alpha=0.6, lw=0))
        artists["arcs"] = [_draw_arc(ax, a.center, a.radius, a.start_angle, a.end_angle, color=_ARC_COLOURS[a.type],
                                     lw=1.8, side=a.side, tick=tick) for a in arcs]
    ax.plot([0], [0], "k+")
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(title or f"Step {step}: {len(arcs)} arcs")
    return artists


def plot_boundary_loops(boundary, *, ax=None, labels: bool = True, title=None):
    """The boundary loops with the arcs numbered as in the report's table."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(5.5, 5.5))
    lines = []
    for k, a in enumerate(boundary.arcs):
        lines.append(_draw_arc(ax, a.center, a.radius, a.start_angle, a.end_angle, color=_ARC_COLOURS[a.type], lw=2))
        if labels:
            m = 0.5 * (a.start_angle + a.end_angle)
            ax.annotate(str(k + 1), (a.center[0] + a.radius * np.cos(m), a.center[1] + a.radius * np.sin(m)),
                        fontsize=8, ha="center", va="center",
                        bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8))
    ax.set_aspect("equal")
    ax.set_title(title or f"boundary: {len(boundary.arcs)} arcs, area {boundary.area:.6g}")
    return lines
