"""Figures (matplotlib).  Kernels never import this module; it imports matplotlib lazily.

Every function takes an optional ``ax`` and returns the artists it drew, so that
notebooks can compose figures and tests can check what was drawn.
"""

from __future__ import annotations

import numpy as np

__all__ = ["scatter_workspace_3d", "plot_reach", "plot_sweeps", "save_figure"]


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
    artist = ax.scatter(points[:, 0], points[:, 1], points[:, 2], s=size, c=color if color is not None else points[:, 2],
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


def save_figure(artist_or_ax, path, *, dpi=120):
    """Save the figure that holds ``artist_or_ax`` and close it."""
    plt = _pyplot()
    fig = artist_or_ax.figure if hasattr(artist_or_ax, "figure") else artist_or_ax
    if isinstance(artist_or_ax, list):
        fig = artist_or_ax[0].figure
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return path
