"""Pictures of 3D pavings: the artists drawn, checked against counts made independently of the drawing code."""

import numpy as np
import pytest
import sympy as sp

import workspace_sym as ws
from workspace_sym import StopAt
from workspace_sym.errors import InvalidParameterError, UnknownNameError
from workspace_sym.interval import pave
from workspace_sym.interval.boxes import Box, Paving, box_measure
from workspace_sym.plotting import paving_voxels, plot_paving, plot_paving_slices, plot_reach, slice_heights

X, Y, Z = sp.symbols("x y z")
NONE = np.empty((0, 3, 2))


def _unit_cube(i):
    return [[i, i + 1.0], [0.0, 1.0], [0.0, 1.0]]


def _row_of_cubes(inner, boundary, pending=()):
    """A hand-made paving of unit cubes in a row along x (cube i spans [i, i + 1] x [0, 1] x [0, 1])."""
    boxes = {k: np.array([_unit_cube(i) for i in v]) if len(v) else NONE
             for k, v in (("inner", inner), ("boundary", boundary), ("pending", pending))}
    n = 1 + max([*inner, *boundary, *pending])
    return Paving(variables=(X, Y, Z), box=Box((X, Y, Z), (0.0, 0.0, 0.0), (float(n), 1.0, 1.0)), constraints=(),
                  delta=1.0, backend="numpy", size="diameter", outer=NONE, seconds=0.0, complete=not len(pending),
                  evaluated=n, **boxes)


def _drawn_faces(fig):
    """Face colours of the one box collection of a 3D paving figure, after drawing."""
    fig.canvas.draw()
    (boxes,) = fig.axes[0].collections
    return boxes.get_facecolor()


@pytest.mark.parametrize(("inner", "boundary", "opaque", "translucent"), [
    ([0], [], 6, 0),                  # one cube: its six faces
    ([0, 1], [], 10, 0),              # two cubes side by side: the shared face is hidden from both
    ([0, 1], [2], 10, 5),             # the inner solid shows its face against the boundary cube; the shell its 5 outer
    ([1], [0, 2], 6, 10),             # an inner cube between two boundary cubes: the shell skips the faces inside
])
def test_3d_paving_draws_the_faces_between_kinds(inner, boundary, opaque, translucent):
    """Counted by hand for cubes in a row: inner faces facing another kind (opaque), boundary faces facing nothing
    (translucent); the legend still counts the boxes, and the title's bracket is the paving's."""
    from matplotlib.figure import Figure

    fig = plot_paving(_row_of_cubes(inner, boundary), units="m")
    assert isinstance(fig, Figure)
    alpha = _drawn_faces(fig)[:, 3]
    assert (alpha == 1).sum() == opaque and ((alpha > 0) & (alpha < 0.5)).sum() == translucent
    ax = fig.axes[0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == [f"inner (proved inside): {len(inner)}", f"boundary (undecided, size ≤ δ): {len(boundary)}"]
    assert ax.get_title() == f"δ = 1.0: volume in [{len(inner)}.0000, {len(inner) + len(boundary)}.0000]"
    assert ax.get_zlabel() == "z (m)"


def test_3d_paving_shows_pending_boxes():
    p = _row_of_cubes([0], [1], pending=[2])
    fig = plot_paving(p)
    # inner: 6; boundary, between two other kinds: its 4 faces towards nothing; pending at the end: 5
    assert len(_drawn_faces(fig)) == 6 + 4 + 5
    assert fig.axes[0].get_legend().get_texts()[-1].get_text() == "pending (not examined): 1"


def test_3d_paving_of_nothing():
    """Every box outer: nothing to draw, a figure all the same."""
    p = _row_of_cubes([0], [])
    p = Paving(**{**{f: getattr(p, f) for f in p.__dataclass_fields__}, "inner": NONE, "outer": p.inner})
    assert len(_drawn_faces(plot_paving(p))) == 0


@pytest.fixture(scope="module")
def shell():
    """A spherical shell 1/2 <= r <= 1 paved at delta 0.3 (a few thousand boxes of a bisection tree)."""
    return pave(["x**2 + y**2 + z**2 <= 1", "x**2 + y**2 + z**2 >= 0.25"],
                {"x": (-1.1, 1.1), "y": (-1.1, 1.1), "z": (-1.1, 1.1)}, delta=0.3, stop=StopAt())


def test_voxels_hold_the_boxes_exactly(shell):
    """Bisection boxes on a grid as fine as the narrowest box: each class covers exactly its own volume (cells
    counted here, boxes summed by box_measure)."""
    grid, lower, step = paving_voxels(shell)
    every = np.concatenate([shell.inner, shell.boundary])
    assert grid.shape == tuple(np.round(2.2 / (every[:, :, 1] - every[:, :, 0]).min(axis=0)).astype(int))
    assert np.allclose(lower, -1.1) and grid.shape[0] >= 16
    cell = float(np.prod(step))
    for code, kind in enumerate(("inner", "boundary"), 1):
        assert (grid == code).sum() * cell == pytest.approx(box_measure(getattr(shell, kind)), rel=1e-12)
    # a coarser grid still marks every box somewhere, and never more than its resolution per axis
    coarse, _, _ = paving_voxels(shell, resolution=8)
    assert coarse.shape == (8, 8, 8) and (coarse == 1).any() and (coarse == 2).any()


def test_slices_are_off_the_bisection_planes(shell):
    """slice_heights lies inside the z range and on no box face (where the boxes of both sides would meet); each
    panel draws exactly the boxes its plane crosses."""
    heights = slice_heights(shell)
    faces = np.concatenate([shell.inner[:, 2].ravel(), shell.boundary[:, 2].ravel()])
    assert -1.1 < heights[0] < heights[1] < heights[2] < 1.1 and not np.isin(heights, faces).any()
    fig = plot_paving_slices(shell, values=heights, units="m")
    for ax, v in zip(fig.axes, heights):
        drawn = {c.get_label(): len(c.get_paths()) for c in ax.collections}
        for kind in ("inner", "boundary"):
            z = getattr(shell, kind)[:, 2]
            assert drawn[kind] == int(((z[:, 0] < v) & (v < z[:, 1])).sum()) > 0
        assert ax.get_title() == f"z = {v}" and ax.get_xlabel() == "x (m)"


# ---------------------------------------------------------------------- notebook user (issue 27)
def test_plot_reach_accepts_the_paving_of_reach_with_its_units():
    """plot_reach(reach(...)) raised IndexError; now it draws the boxes, axes labelled in the robot's units."""
    paving = ws.robots.build("planar-2r").reach(delta=0.3)
    assert paving.units == "m" and paving.to_dict()["units"] == "m"
    fig = plot_reach(paving)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "y (m)"
    assert len(ax.collections) >= 2                    # inner and boundary boxes drawn
    with pytest.raises(InvalidParameterError, match="points must be an"):
        plot_reach(np.zeros((4, 2)))


def test_paving_legend_hides_no_box():
    """The legend sits beside the axes: its drawn extent does not meet the axes' extent."""
    paving = ws.pave(["x**2 + y**2 <= 1"], {"x": (-1, 1), "y": (-1, 1)}, delta=0.2)
    fig = plot_paving(paving, exact_boundary=lambda x, y: x ** 2 + y ** 2 - 1)
    fig.canvas.draw()
    ax = fig.axes[0]
    legend, frame = ax.get_legend().get_window_extent(), ax.get_window_extent()
    assert legend.x0 >= frame.x1 and "exact boundary" in [t.get_text() for t in ax.get_legend().get_texts()]


def test_catalog_refuses_unknown_parameters():
    expected = r"'planar-3r' has no parameter 'banana' \(value 2\); its parameters are: l1, l2, l3"
    with pytest.raises(UnknownNameError, match=expected):
        ws.robots.build("planar-3r", banana=2)
    assert 2.0 in ws.robots.build("planar-3r", l1=2.0).parameters.values()


# ---------------------------------------------------------------------- what a plain fig.savefig() keeps
def _outside_the_figure(fig):
    """The legends, axis labels and titles drawn outside the figure's extent after ``fig.savefig`` to PNG
    (matplotlib's renderer gives each artist's window extent; 0.5 px of slack)."""
    import io

    fig.savefig(io.BytesIO(), format="png")                 # a plain savefig: no bbox_inches="tight"
    renderer, frame = fig.canvas.get_renderer(), fig.bbox
    out = []
    for ax in fig.axes:
        for name, artist in (("legend", ax.get_legend()), ("x label", ax.xaxis.label), ("y label", ax.yaxis.label),
                             ("title", ax.title)):
            if artist is None or (hasattr(artist, "get_text") and not artist.get_text()):
                continue
            e = artist.get_window_extent(renderer)
            if e.x0 < frame.x0 - 0.5 or e.y0 < frame.y0 - 0.5 or e.x1 > frame.x1 + 0.5 or e.y1 > frame.y1 + 0.5:
                out.append(name)
    return out


def test_plot_reach_savefig_keeps_its_legend_and_labels():
    """Issue 39 (notebook user): plot_reach(p).savefig() clipped the legend (beside the axes) and the x label."""
    import matplotlib.pyplot as plt

    result = ws.reach(ws.robots.build("planar-2r"), delta=0.3)
    fig = plot_reach(result)
    try:
        assert fig.axes[0].get_legend() is not None and fig.axes[0].get_xlabel()
        assert _outside_the_figure(fig) == []
    finally:
        plt.close(fig)


def test_planar_figures_keep_their_legend_beside_the_arcs():
    """Issue 39: the arc legend (loc="best") sat over the arcs; beside the axes it meets none, and a plain savefig
    keeps it (Bastien 2018, Table 1 iii)."""
    import matplotlib.pyplot as plt

    from workspace_sym.plotting import plot_boundary_loops, plot_planar_step

    chain = ws.PlanarChain(["0.186", "0.146", "0.108"], [-60, 0, -10], [120, 130, 25])
    for fig in (plot_boundary_loops(chain.boundary()), plot_planar_step(chain, 1)):
        try:
            assert _outside_the_figure(fig) == []
            ax = fig.axes[0]
            legend, frame = ax.get_legend().get_window_extent(), ax.get_window_extent()
            assert legend.x0 >= frame.x1                    # right of the axes: over no arc
        finally:
            plt.close(fig)


def test_slices_savefig_keeps_every_panel_legend():
    import matplotlib.pyplot as plt

    fig = plot_paving_slices(_row_of_cubes([0, 1], [2]), axis=2, values=[0.5, 0.9])
    try:
        assert len(fig.axes) == 2 and _outside_the_figure(fig) == []
    finally:
        plt.close(fig)
