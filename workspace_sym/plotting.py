"""Figures (matplotlib).  Kernels never import this module; it imports matplotlib lazily.

Every function takes an optional ``ax`` (draw there, or in a new figure) and
returns the :class:`~matplotlib.figure.Figure`, so that notebooks can compose
figures and save them; the artists drawn are on ``fig.axes``.  Axes carry their
units, and legends name the arc types and the box classes.
"""

from __future__ import annotations

import math

import numpy as np

from .numbers import fmt, fmt_bracket

__all__ = ["scatter_workspace_3d", "plot_reach", "plot_sweeps", "plot_paving", "plot_paving_slices", "save_figure",
           "plot_planar_step", "plot_boundary_loops", "arc_label_positions", "paving_voxels", "slice_heights",
           "plot_reach_map"]


def _pyplot():
    # Imported here so that importing workspace_sym never loads matplotlib;
    # without a display matplotlib falls back to the Agg backend by itself.
    import matplotlib.pyplot as plt

    return plt


def _axes3d(ax):
    plt = _pyplot()
    if ax is None:
        fig = plt.figure(figsize=(6, 5), layout="constrained")
        ax = fig.add_subplot(projection="3d")
    return ax


def _axes(ax, figsize):
    # constrained layout: a plain fig.savefig() keeps the legend beside the axes and the axis labels in the picture
    if ax is None:
        _, ax = _pyplot().subplots(figsize=figsize, layout="constrained")
    return ax


def _label(name, units) -> str:
    return f"{name} ({units})" if units else str(name)


def scatter_workspace_3d(points, *, ax=None, color=None, size=1.0, title=None, units="m"):
    """3D scatter of reachable points (paper 004, figures 2-5).  Returns the figure.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` points.
    ax : matplotlib.axes.Axes, optional
        3D axes to draw in; by default a new figure.
    color : color or array_like, optional
        One colour, or one value a point; by default the height ``z`` on the viridis map.
    size : float, default 1.0
        Marker size (points squared).
    title : str, optional
        The axes' title; none by default.
    units : str, default "m"
        The unit of length, for the axis labels.

    Returns
    -------
    matplotlib.figure.Figure
        The figure holding the axes, with equal scales on the three axes.
    """
    points = np.asarray(points)
    ax = _axes3d(ax)
    ax.scatter(points[:, 0], points[:, 1], points[:, 2], s=size,
                        c=color if color is not None else points[:, 2],
                        cmap=None if color is not None else "viridis", depthshade=False)
    ax.set_xlabel(f"x ({units})")
    ax.set_ylabel(f"y ({units})")
    ax.set_zlabel(f"z ({units})")
    if title:
        ax.set_title(title)
    _equal_3d(ax, points)
    return ax.figure


def _equal_3d(ax, points):
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, 1e-9)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)


def plot_sweeps(robot, joints, *, n=200, ax=None, parameters=None):
    """Trajectories of the end-effector when each of ``joints`` sweeps its range alone
    (paper 004, figures 6-10), one line per joint.  Returns the figure.

    Each joint sweeps from where the previous sweep left the arm (:func:`~workspace_sym.sampling.sweep_joints`,
    starting with every joint at its lower limit).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    joints : sequence of int
        The joints to sweep, 1-based, in order.
    n : int, default 200
        Samples per sweep.
    ax : matplotlib.axes.Axes, optional
        3D axes to draw in; by default a new figure.
    parameters : dict, optional
        Numeric values of the robot's symbolic parameters (:func:`~workspace_sym.sampling.reach_points`); by
        default its own.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, with a legend naming each joint's line.

    Raises
    ------
    InvalidParameterError
        When a joint index is out of range.
    """
    from .sampling import reach_points, sweep_joints

    ax = _axes3d(ax)
    q = sweep_joints(robot, joints, n)
    pts = reach_points(robot, q, parameters)
    for k, j in enumerate(joints):
        seg = pts[k * n:(k + 1) * n]
        ax.plot(seg[:, 0], seg[:, 1], seg[:, 2], label=f"θ{j} sweeps its range")
    units = getattr(robot, "units", "m")
    for setter, name in zip((ax.set_xlabel, ax.set_ylabel, ax.set_zlabel), "xyz"):
        setter(_label(name, units))
    ax.legend(fontsize="small", **_BESIDE)
    _equal_3d(ax, pts)
    return ax.figure


def plot_reach(points, *, ax=None, units="m"):
    """Side view ``(r, z)`` with ``r = sqrt(x^2 + y^2)`` of sampled end points ``(N, 3)``: the reach and height
    of the workspace.

    Given the certified result of :func:`~workspace_sym.serial.api.reach` (or its
    :class:`~workspace_sym.interval.boxes.Paving`) instead, draws its boxes
    (:func:`plot_paving`).  Returns the figure.

    Parameters
    ----------
    points : array_like or Paving or ReachResult
        ``(N, 3)`` end points, or a certified result.
    ax : matplotlib.axes.Axes, optional
        Axes to draw in; by default a new figure.
    units : str, default "m"
        The unit of length, for the axis labels (a paving's own units come first).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, titled with the largest distance from the base.

    Raises
    ------
    InvalidParameterError
        When ``points`` is neither an ``(N, 3)`` array nor a paving, or the paving is neither 2D nor 3D.
    """
    from .interval.boxes import Paving

    if isinstance(getattr(points, "paving", points), Paving):
        return plot_paving(points, ax=ax, units=points.units or units)
    points = np.asarray(points)
    if points.ndim != 2 or points.shape[1] < 3:
        from .errors import InvalidParameterError

        raise InvalidParameterError(f"points must be an (N, 3) array of end points or a Paving; got shape "
                                    f"{points.shape}", parameter="points")
    ax = _axes(ax, (5, 4))
    r = np.hypot(points[:, 0], points[:, 1])
    ax.scatter(r, points[:, 2], s=0.5, alpha=0.4)
    ax.set_xlabel(f"r = sqrt(x² + y²) ({units})")
    ax.set_ylabel(f"z ({units})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(f"reach {np.linalg.norm(points, axis=1).max():.4g} {units}")
    return ax.figure


def save_figure(artists, path, *, dpi=120):
    """Save the figure ``artists`` (or the figure that holds an artist, axes, list or dict of artists) and
    close it.

    The file is written under a temporary name and renamed, so a failure never
    leaves a half-written image.

    Parameters
    ----------
    artists : Figure, Axes, artist, list or dict
        The figure, or something that holds it (the first item of a list or dict).
    path : str or os.PathLike
        The file; its suffix chooses the format (``.png``, ``.svg``, ``.pdf``...).
    dpi : int, default 120
        Resolution of raster formats.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    OutputError
        When the file cannot be written (missing or unwritable directory, unknown format); the figure is
        closed all the same.
    """
    import os
    from pathlib import Path

    plt = _pyplot()
    obj = artists
    if isinstance(obj, dict):
        obj = next(iter(obj.values()))
    if isinstance(obj, list):
        obj = obj[0]
    from matplotlib.figure import Figure

    fig = obj if isinstance(obj, Figure) else obj.figure
    from .errors import OutputError

    path = Path(path)
    tmp = path.with_name(f".{path.name}.partial{path.suffix}")
    try:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight")
        os.replace(tmp, path)
    except (OSError, ValueError) as exc:    # a missing directory, an unknown format (matplotlib's ValueError)
        reason = getattr(exc, "strerror", None) or " ".join(str(exc).split())[:160]
        raise OutputError(f"path: cannot write {str(path)!r}: {reason}", parameter="path") from None
    finally:
        plt.close(fig)
        if tmp.exists():
            tmp.unlink()
    return path


_BOX_COLOURS = {"inner": "#4caf50", "boundary": "#ffd54f", "outer": "#e0e0e0", "pending": "#90caf9"}
_BOX_NAMES = {"inner": "inner (proved inside)", "boundary": "boundary (undecided, size ≤ δ)",
              "outer": "outer (proved outside)", "pending": "pending (not examined)"}


_BELOW = {"loc": "upper center", "bbox_to_anchor": (0.5, -0.2)}     # under the axes and their x label
_BESIDE = {"loc": "upper left", "bbox_to_anchor": (1.02, 1.0), "borderaxespad": 0.0}   # right of the axes


def _box_legend(ax, counts, *, fontsize="small", where=None):
    """Legend of the box classes drawn, with their numbers of boxes (``where``: legend placement keywords)."""
    from matplotlib.patches import Patch

    handles = [Patch(facecolor=_BOX_COLOURS[k], edgecolor="k", linewidth=0.3, label=f"{_BOX_NAMES[k]}: {n}")
               for k, n in counts.items()]
    return ax.legend(handles=handles, fontsize=fontsize, **(where or _BESIDE))


def plot_paving(paving, *, ax=None, show_outer=False, exact_boundary=None, title=None, units=None):
    """Inner (green) and boundary (yellow) boxes of a 2D or 3D paving (Rybak et al., figure 4), pending boxes
    (a stopped run) in blue.

    ``exact_boundary`` is a callable ``(x, y) -> array`` whose zero level set
    is drawn over a 2D paving (e.g. ``max_j g_j``).  ``units`` labels the axes
    (``"x (m)"``; default: the paving's own ``units``).  Returns the figure; the legend, beside the axes so that
    it hides no box, names the box classes.

    A 3D paving is drawn as voxels (:func:`paving_voxels`): the inner boxes an opaque solid, the boundary and
    pending boxes a translucent shell.

    Parameters
    ----------
    paving : Paving
        A paving of 2 or 3 variables.
    ax : matplotlib.axes.Axes, optional
        Axes (3D axes for a 3D paving) to draw in; by default a new figure.
    show_outer : bool, default False
        Whether to draw the outer boxes too (2D only).
    exact_boundary : callable, optional
        ``(x, y) -> array``, as above (2D only).
    title : str, optional
        The title; by default ``delta`` and the certified bracket of the measure.
    units : str, optional
        The unit of the axes.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    Raises
    ------
    InvalidParameterError
        When the paving has neither 2 nor 3 variables.
    """
    units = paving.units if units is None else units
    n = len(paving.variables)
    if n == 3:
        return _plot_paving_3d(paving, ax=ax, title=title, units=units)
    if n != 2:
        from .errors import InvalidParameterError

        raise InvalidParameterError(f"plot_paving draws 2D or 3D pavings; this one has {n} variables")
    from matplotlib.collections import PolyCollection
    from matplotlib.lines import Line2D

    ax = _axes(ax, (7, 3.5))
    kinds = ["inner", "boundary"] + (["outer"] if show_outer else []) + (["pending"] if len(paving.pending) else [])
    for kind in kinds:
        boxes = getattr(paving, kind)
        verts = [[(b[0, 0], b[1, 0]), (b[0, 1], b[1, 0]), (b[0, 1], b[1, 1]), (b[0, 0], b[1, 1])] for b in boxes]
        ax.add_collection(PolyCollection(verts, facecolors=_BOX_COLOURS[kind], edgecolors="k", linewidths=0.2,
                                         label=kind))
    lo, hi = paving.box.lower, paving.box.upper
    legend = _box_legend(ax, {k: paving.counts[k] for k in kinds})
    if exact_boundary is not None:
        xs, ys = np.meshgrid(np.linspace(lo[0], hi[0], 600), np.linspace(lo[1], hi[1], 300))
        ax.contour(xs, ys, exact_boundary(xs, ys), levels=[0.0], colors="r", linewidths=1.0)
        handles = legend.legend_handles + [Line2D([], [], color="r", lw=1.0, label="exact boundary")]
        ax.legend(handles=handles, fontsize="small", **_BESIDE)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel(_label(paving.variables[0], units))
    ax.set_ylabel(_label(paving.variables[1], units))
    m_lo, m_hi = paving.measure_bounds
    how = " with contraction" if paving.contract else ""
    ax.set_title(title or f"δ = {paving.delta}{how}: area in {fmt_bracket(m_lo, m_hi)}")
    return ax.figure


# Faces of a voxel seen along +axis / -axis, counter-clockwise from outside (outward normals for shading).
_VOXEL_FACES = {
    0: (((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)), ((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0))),
    1: (((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)), ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1))),
    2: (((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)), ((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0))),
}


def paving_voxels(paving, kinds=("inner", "boundary", "pending"), *, resolution: int = 64):
    """The boxes of a 3D paving on a grid, for drawing: ``(grid, lower, step)``.

    ``grid`` is an ``(n_x, n_y, n_z)`` int8 array holding ``k + 1`` where a
    cell's centre lies in a box of ``kinds[k]`` (0: none of them).  The
    cells are as small as the narrowest box along each axis, at most
    ``resolution`` per axis; a box holding no cell centre still marks the
    cell of its own centre, so nothing drawn disappears.  Later kinds paint
    over earlier ones (a picture leans towards the undecided).  A picture,
    not a proof: the certified boxes are the paving's.

    Parameters
    ----------
    paving : Paving
        A paving of 3 variables.
    kinds : sequence of str, default ("inner", "boundary", "pending")
        The box classes to put on the grid, in painting order.
    resolution : int, default 64
        The most cells along an axis.

    Returns
    -------
    tuple
        ``(grid, lower, step)``: the int8 grid, the ``(3,)`` corner of the paving's box where cell ``(0, 0, 0)``
        starts, and the ``(3,)`` cell size.
    """
    lower = np.asarray(paving.box.lower, dtype=float)
    upper = np.asarray(paving.box.upper, dtype=float)
    width = np.maximum(upper - lower, np.finfo(float).tiny)
    boxes = [np.asarray(getattr(paving, k), dtype=float).reshape(-1, 3, 2) for k in kinds]
    every = np.concatenate(boxes)
    narrowest = (every[:, :, 1] - every[:, :, 0]).min(axis=0) if len(every) else width
    n = np.clip(np.round(width / np.maximum(narrowest, width / resolution)), 1, resolution).astype(int)
    step = width / n
    grid = np.zeros(tuple(n), dtype=np.int8)
    for code, b in enumerate(boxes, 1):
        # cells whose centres lower + (i + 1/2) step lie in [lo, hi]
        first = np.ceil((b[:, :, 0] - lower) / step - 0.5).astype(int)
        last = np.floor((b[:, :, 1] - lower) / step - 0.5).astype(int)
        own = np.floor((0.5 * (b[:, :, 0] + b[:, :, 1]) - lower) / step).astype(int)
        empty = (last < first).any(axis=1)
        first[empty], last[empty] = own[empty], own[empty]
        first, last = np.clip(first, 0, n - 1), np.clip(last, 0, n - 1)
        for (i0, j0, k0), (i1, j1, k1) in zip(first, last):
            grid[i0:i1 + 1, j0:j1 + 1, k0:k1 + 1] = code
    return grid, lower, step


def _exposed_faces(grid, code, lower, step, *, against_empty_only: bool):
    """``(F, 4, 3)`` quadrilaterals of the cells ``grid == code`` that face a cell of another kind (or only an
    empty cell), outward."""
    mine = grid == code
    padded = np.pad(grid, 1)
    faces = []
    for axis in range(3):
        for side, shift in ((0, 1), (1, -1)):
            neighbour = np.roll(padded, -shift, axis=axis)[1:-1, 1:-1, 1:-1]
            show = mine & ((neighbour == 0) if against_empty_only else (neighbour != code))
            cells = np.argwhere(show)
            if len(cells):
                corners = np.array(_VOXEL_FACES[axis][side], dtype=float)
                faces.append(lower + (cells[:, None, :] + corners[None]) * step)
    return np.concatenate(faces) if faces else np.empty((0, 4, 3))


def _plot_paving_3d(paving, *, ax=None, title=None, units=None, resolution: int = 64):
    """Inner boxes as a shaded opaque solid, boundary (and pending) boxes as a translucent shell around it.

    Only the faces between a drawn kind and another kind are drawn (on a grid
    of at most ``resolution`` cells per axis, :func:`paving_voxels`), so tens
    of thousands of boxes draw in about a second and the inner solid stays
    visible through the shell.
    """
    from matplotlib.colors import to_rgba
    from matplotlib.ticker import MaxNLocator
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    ax = _axes3d(ax)
    kinds = ["inner", "boundary"] + (["pending"] if len(paving.pending) else [])
    grid, lower, step = paving_voxels(paving, kinds, resolution=resolution)
    faces, colours = [], []
    for code, kind in enumerate(kinds, 1):
        opaque = kind == "inner"
        quads = _exposed_faces(grid, code, lower, step, against_empty_only=not opaque)
        faces.append(quads)
        colours.append(np.tile(to_rgba(_BOX_COLOURS[kind], 1.0 if opaque else 0.18), (len(quads), 1)))
    # one collection, so that faces of every kind are sorted by depth together
    ax.add_collection3d(Poly3DCollection(np.concatenate(faces), facecolors=np.concatenate(colours), linewidths=0,
                                         shade=True, label="boxes"))
    lo, hi = paving.box.lower, paving.box.upper
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(np.maximum(np.subtract(hi, lo), 1e-3 * max(np.subtract(hi, lo))))   # true proportions
    for axis, v in zip((ax.xaxis, ax.yaxis, ax.zaxis), paving.variables):
        axis.set_major_locator(MaxNLocator(5))
        axis.set_label_text(_label(v, units))
    _box_legend(ax, {k: paving.counts[k] for k in kinds})
    m_lo, m_hi = paving.measure_bounds
    ax.set_title(title or f"δ = {paving.delta}: volume in {fmt_bracket(m_lo, m_hi)}")
    return ax.figure


def slice_heights(paving, axis: int = 2) -> tuple[float, ...]:
    """Three values spread over the range of ``variables[axis]`` of a paving's box (0.2, 0.45 and 0.7 of the
    way), rounded to about three significant digits of that range: where to slice a 3D paving
    (:func:`plot_paving_slices`) when nothing says where.

    Parameters
    ----------
    paving : Paving
        The paving, read for its box.
    axis : int, default 2
        The variable across which to slice (0-based).

    Returns
    -------
    tuple of float
        The three values.
    """
    lo, hi = paving.box.lower[axis], paving.box.upper[axis]
    width = hi - lo
    decimals = max(0, 2 - math.floor(math.log10(width))) if width > 0 else 3
    # not a quarter, half, three quarters: those are bisection planes, where boxes of both sides meet
    return tuple(float(np.round(lo + f * width, decimals)) for f in (0.2, 0.45, 0.7))


def plot_paving_slices(paving, *, axis: int = 2, values=(-0.4, 0.0, 0.3), reference=None, title=None, ax=None,
                       units=None):
    """2D slices of a 3D paving: the boxes met by the plane ``variable[axis] = value``, one panel per value.

    ``reference`` is an optional callable ``(points (m, 3)) -> bool array`` (for
    instance numeric eigenvalues) whose boundary is drawn in red on each slice,
    an independent picture to hold the certified boxes against.  ``ax`` is a
    sequence of axes, one per value (default: a new row of panels).  Returns
    the figure.

    Parameters
    ----------
    paving : Paving
        A paving of 3 variables; its inner and boundary boxes are drawn.
    axis : int, default 2
        The variable fixed on each slice (0-based).
    values : sequence of float, default (-0.4, 0.0, 0.3)
        The values of that variable, one panel each (:func:`slice_heights` suggests some for another box).
    reference : callable, optional
        ``(m, 3) points -> bool array``, as above.
    title : str, optional
        A title over the panels.
    ax : sequence of matplotlib.axes.Axes, optional
        One axes per value.
    units : str, optional
        The unit of the axes; by default the paving's.

    Returns
    -------
    matplotlib.figure.Figure
        The figure holding the panels.

    Raises
    ------
    InvalidParameterError
        When the paving does not have 3 variables, or ``ax`` does not hold one axes per value.
    """
    from matplotlib.collections import PolyCollection
    from matplotlib.lines import Line2D

    units = paving.units if units is None else units
    plt = _pyplot()
    if len(paving.variables) != 3:
        from .errors import InvalidParameterError

        raise InvalidParameterError(f"plot_paving_slices draws 3D pavings; this one has {len(paving.variables)} "
                                    "variables")
    others = [k for k in range(3) if k != axis]
    lo, hi = paving.box.lower, paving.box.upper
    if ax is None:
        fig, axes = plt.subplots(1, len(values), figsize=(3.6 * len(values), 3.6), squeeze=False, layout="constrained")
        axes = list(axes[0])
    else:
        axes = list(np.atleast_1d(ax))
        if len(axes) != len(values):
            from .errors import InvalidParameterError

            raise InvalidParameterError(f"ax: one axes per slice value; got {len(axes)} for {len(values)} values",
                                        parameter="ax")
        fig = axes[0].figure
    for a_, v in zip(axes, values):
        counts = {}
        for kind in ("inner", "boundary"):
            boxes = getattr(paving, kind)
            boxes = boxes[(boxes[:, axis, 0] <= v) & (v <= boxes[:, axis, 1])]
            a, b = others
            verts = [[(q[a, 0], q[b, 0]), (q[a, 1], q[b, 0]), (q[a, 1], q[b, 1]), (q[a, 0], q[b, 1])] for q in boxes]
            a_.add_collection(PolyCollection(verts, facecolors=_BOX_COLOURS[kind], edgecolors="none", label=kind))
            counts[kind] = len(boxes)
        legend = _box_legend(a_, counts, fontsize="x-small", where=_BELOW)   # the panel's boxes stay visible
        if reference is not None:
            u, w = np.meshgrid(np.linspace(lo[others[0]], hi[others[0]], 400),
                               np.linspace(lo[others[1]], hi[others[1]], 400))
            pts = np.empty(u.shape + (3,))
            pts[..., axis], pts[..., others[0]], pts[..., others[1]] = v, u, w
            inside = np.asarray(reference(pts.reshape(-1, 3)), dtype=float).reshape(u.shape)
            a_.contour(u, w, inside, levels=[0.5], colors="r", linewidths=0.8)
            handles = legend.legend_handles + [Line2D([], [], color="r", lw=0.8, label="reference boundary")]
            a_.legend(handles=handles, fontsize="x-small", **_BELOW)
        a_.set_xlim(lo[others[0]], hi[others[0]])
        a_.set_ylim(lo[others[1]], hi[others[1]])
        a_.set_aspect("equal")
        a_.set_xlabel(_label(paving.variables[others[0]], units))
        a_.set_ylabel(_label(paving.variables[others[1]], units))
        a_.set_title(f"{paving.variables[axis]} = {v}", fontsize="medium")
    if title:
        fig.suptitle(title)
    return fig


_ARC_COLOURS = {"I": "tab:blue", "II": "tab:red", "III": "tab:green"}   # the paper's figures 4 to 6
_ARC_NAMES = {"I": "type I", "II": "type II", "III": "type III"}


def _draw_arc(ax, center, radius, a0, a1, *, color, lw=1.2, side=0, tick=None):
    t = np.linspace(a0, a1, max(8, int(abs(a1 - a0) / 0.01)))
    (line,) = ax.plot(center[0] + radius * np.cos(t), center[1] + radius * np.sin(t), color=color, lw=lw)
    if side and tick:
        m = 0.5 * (a0 + a1)
        r0, r1 = radius, radius + side * tick
        ax.plot([center[0] + r0 * np.cos(m), center[0] + r1 * np.cos(m)],
                [center[1] + r0 * np.sin(m), center[1] + r1 * np.sin(m)], color=color, lw=lw)
    return line


def _arc_legend(ax, types, *, extra=()):
    """Legend of the arc types drawn (the paper's colours) and of ``extra`` handles."""
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=_ARC_COLOURS[t], lw=1.8, label=_ARC_NAMES[t]) for t in ("I", "II", "III")
               if t in types]
    return ax.legend(handles=handles + list(extra), fontsize="small", **_BESIDE)   # beside: it hides no arc


def _planar_axes(ax, units):
    ax.set_aspect("equal")
    ax.set_xlabel(_label("x", units))
    ax.set_ylabel(_label("y", units))


def plot_planar_step(chain, step: int, *, ax=None, samples: int = 20000, seed: int = 0, title=None, units="m"):
    """One step of the alignment method, drawn like the paper's figures 4 to 6.

    Step 0: the candidate arcs; step 1: the kept arcs, with a tick on the side
    of the workspace; step 2: the boundary loops and the enclosed workspace.
    Arcs are blue (type I), red (type II) or green (type III); the gold dots
    are ``samples`` random configurations (the discrete swept area).
    ``units`` is the length unit of the chain, for the axis labels.  Returns
    the figure.

    Parameters
    ----------
    chain : PlanarChain
        The chain.
    step : {0, 1, 2}
        The step to draw.
    ax : matplotlib.axes.Axes, optional
        Axes to draw in; by default a new figure.
    samples : int, default 20000
        Random configurations drawn as dots; 0 draws none.
    seed : int, default 0
        Seed of those configurations.
    title : str, optional
        The title; by default the step and its number of arcs.
    units : str, default "m"
        The unit of length, for the axis labels.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, with a legend of the arc types and of what else is drawn.

    Raises
    ------
    InvalidParameterError
        When ``step`` is not 0, 1 or 2.
    BoundaryError
        Step 2, when the chain's boundary cannot be computed reliably
        (:meth:`~workspace_sym.planar.chain.PlanarChain.boundary`).
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, PathPatch
    from matplotlib.path import Path as MplPath

    if step not in (0, 1, 2):
        from .errors import InvalidParameterError

        raise InvalidParameterError(f"step must be 0, 1 or 2; got {step!r}", parameter="step")
    ax = _axes(ax, (5.5, 5.5))
    extra: list = []      # legend handles of what is drawn beside the arcs
    if samples:
        pts = chain.forward(chain.sample(samples, seed=seed, corners=False))
        ax.scatter(pts[:, 0], pts[:, 1], s=0.3, color="gold", alpha=0.5, lw=0)
        extra.append(Line2D([], [], marker="o", ls="", color="gold", label=f"{samples} random configurations"))
    tick = 0.03 * chain.reach
    if step == 0:
        arcs = chain.candidate_arcs()
        for a in arcs:
            _draw_arc(ax, a.center, a.radius, a.start_angle, a.end_angle, color=_ARC_COLOURS[a.type], lw=0.8)
    elif step == 1:
        arcs = chain.kept_arcs()
        for a in arcs:
            _draw_arc(ax, a.center, a.radius, a.start_angle, a.end_angle, color=_ARC_COLOURS[a.type], side=a.side,
                      tick=tick)
        extra.append(Line2D([], [], color="k", lw=0, label="tick: side of the workspace"))
    else:
        b = chain.boundary()
        arcs = b.arcs
        polys = b.polygon(step=0.005)
        if polys:
            verts = np.vstack([np.vstack([p, p[:1]]) for p in polys])
            codes = np.concatenate([[MplPath.MOVETO] + [MplPath.LINETO] * (len(p) - 1) + [MplPath.CLOSEPOLY]
                                    for p in polys])
            ax.add_patch(PathPatch(MplPath(verts, codes), facecolor="khaki", alpha=0.6, lw=0))
            extra.append(Patch(facecolor="khaki", alpha=0.6, label="workspace"))
        for a in arcs:
            _draw_arc(ax, a.center, a.radius, a.start_angle, a.end_angle, color=_ARC_COLOURS[a.type], lw=1.8,
                      side=a.side, tick=tick)
    ax.plot([0], [0], "k+")
    _planar_axes(ax, units)
    _arc_legend(ax, {a.type for a in arcs}, extra=extra)
    ax.set_title(title or f"Step {step}: {len(arcs)} arcs")
    return ax.figure


def arc_label_positions(boundary, *, separation: float = 0.07) -> np.ndarray:
    """Where :func:`plot_boundary_loops` writes the arc numbers, ``(n, 2)``: on each arc, just outside the
    workspace, at the first of several points along the arc that stays ``separation`` times the reach away
    from the labels already placed (else the farthest one).

    Parameters
    ----------
    boundary : Boundary
        The boundary.
    separation : float, default 0.07
        The distance wanted between labels, relative to the chain's reach.

    Returns
    -------
    numpy.ndarray
        ``(n, 2)``: one position per arc of ``boundary.arcs``, in order.
    """
    reach = boundary.chain.reach
    offset, gap = 0.035 * reach, separation * reach
    placed: list[np.ndarray] = []
    for a in boundary.arcs:
        normal = -a.side if a.side else 1          # outward: away from the workspace side
        points = []
        for f in (0.5, 0.3, 0.7, 0.15, 0.85, 0.05, 0.95):
            t = a.start_angle + f * (a.end_angle - a.start_angle)
            for r in (a.radius + normal * offset, a.radius + normal * 2.2 * offset, a.radius - normal * offset):
                points.append((a.center[0] + r * np.cos(t), a.center[1] + r * np.sin(t)))
        candidates = np.array(points)
        if not placed:
            placed.append(candidates[0])
            continue
        dist = np.linalg.norm(candidates[:, None, :] - np.array(placed)[None], axis=2).min(axis=1)
        ok = np.flatnonzero(dist >= gap)
        placed.append(candidates[ok[0]] if len(ok) else candidates[int(np.argmax(dist))])
    return np.array(placed).reshape(-1, 2)


def plot_boundary_loops(boundary, *, ax=None, labels: bool = True, title=None, units="m"):
    """The boundary loops with the arcs numbered as in the report's table (numbers placed apart,
    :func:`arc_label_positions`), coloured by arc type.  Returns the figure.

    Parameters
    ----------
    boundary : Boundary
        The boundary.
    ax : matplotlib.axes.Axes, optional
        Axes to draw in; by default a new figure.
    labels : bool, default True
        Whether to number the arcs.
    title : str, optional
        The title; by default the number of arcs and the area.
    units : str, default "m"
        The unit of length, for the axis labels.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    ax = _axes(ax, (5.5, 5.5))
    for a in boundary.arcs:
        _draw_arc(ax, a.center, a.radius, a.start_angle, a.end_angle, color=_ARC_COLOURS[a.type], lw=2)
    if labels and boundary.arcs:
        for k, (x, y) in enumerate(arc_label_positions(boundary)):
            ax.annotate(str(k + 1), (x, y), fontsize=8, ha="center", va="center", color=_ARC_COLOURS[
                boundary.arcs[k].type], bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8))
    _planar_axes(ax, units)
    _arc_legend(ax, {a.type for a in boundary.arcs})
    ax.set_title(title or f"boundary: {len(boundary.arcs)} arcs, area {fmt(boundary.area, 6, 'g')}")
    return ax.figure


def plot_reach_map(reach_map, *, axis: str = "z", value: float = 0.0, direction: int | None = None, ax=None,
                   title=None):
    """A layer of a :class:`~workspace_sym.serial.reachmap.ReachMap`: one direction's verdicts (green proved
    reachable, grey undecided, white proved unreachable), or the lower bound of the certified capability index.

    Parameters
    ----------
    reach_map : ReachMap
        The map.
    axis : {"x", "y", "z"}
        The axis cut.
    value : float
        Where (within the grid).
    direction : int, optional
        A direction's index; None: the capability's lower bound (proved directions / K).
    ax : matplotlib.axes.Axes, optional
        Where to draw.
    title : str, optional
        The title (default: what is drawn).

    Returns
    -------
    matplotlib.figure.Figure
        The figure; its image is ``fig.axes[0].images[0]``.
    """
    layer = reach_map.slice(axis, value, direction)
    a = "xyz".index(axis)
    others = [i for i in range(3) if i != a]
    edges = reach_map.edges
    ax = _axes(ax, (5.5, 4.5))
    extent = (edges[others[0]][0], edges[others[0]][-1], edges[others[1]][0], edges[others[1]][-1])
    units = reach_map.units
    if direction is None:
        image = ax.imshow(layer.T, origin="lower", extent=extent, vmin=0, vmax=1, cmap="viridis",
                          interpolation="nearest")
        ax.figure.colorbar(image, ax=ax, label="proved directions / K")
        what = "certified capability (lower bound)"
    else:
        from matplotlib.colors import ListedColormap

        ax.imshow(layer.T.astype(float), origin="lower", extent=extent, vmin=-1, vmax=1, interpolation="nearest",
                  cmap=ListedColormap(["#ffffff", "#bbbbbb", "#2ca02c"]))
        d = reach_map.directions[direction]
        what = f"approach within {fmt(reach_map.cone, 3)} deg of ({', '.join(fmt(v, 3) for v in d)})"
    ax.set_xlabel(_label("xyz"[others[0]], units))
    ax.set_ylabel(_label("xyz"[others[1]], units))
    ax.set_title(title or f"{what}, {axis} = {fmt(value, 4)}", fontsize="medium")
    return ax.figure
