"""Joint-box sampling and workspace pictures (artists checked, not pixels)."""

import numpy as np
import pytest

from workspace_sym import InvalidParameterError, robots
from workspace_sym.sampling import extent, reach_points, sample_joint_box, sweep_joints


def test_samples_stay_in_the_joint_box(glass):
    q = sample_joint_box(glass, 5000, seed=1)
    lim = glass.joint_limits()
    assert q.shape == (5000, 6)
    assert np.all(q >= lim[:, 0]) and np.all(q <= lim[:, 1])


def test_reach_never_exceeds_the_sum_of_lengths(glass):
    """Independent bound: |p| <= d1 + a1 + a2 + a3 + d5 (triangle inequality)."""
    pts = reach_points(glass, sample_joint_box(glass, 20000, seed=2))
    bound = sum(glass.parameters.values())
    assert extent(pts)["reach"] <= bound + 1e-12


def test_sweep_moves_one_joint_at_a_time(glass):
    q = sweep_joints(glass, [4, 3, 2, 1], n=50)
    assert q.shape == (200, 6)
    assert np.ptp(q[:50, [0, 1, 2, 4, 5]], axis=0).max() == 0
    lim = glass.joint_limits()
    assert q[0, 3] == lim[3, 0] and q[49, 3] == lim[3, 1]


def test_bad_sampling_input():
    robot = robots.build("planar-2r")
    with pytest.raises(InvalidParameterError, match="n must be a positive integer; got 0"):
        sample_joint_box(robot, 0)
    with pytest.raises(InvalidParameterError, match="joint index must be between 1 and 2; got 3"):
        sweep_joints(robot, [3])


def test_plots_return_the_figure(glass):
    """Every plot returns its Figure; the artists drawn are on its axes, with units on the axes."""
    from matplotlib.figure import Figure

    from workspace_sym.plotting import plot_reach, plot_sweeps, scatter_workspace_3d

    pts = reach_points(glass, sample_joint_box(glass, 500, seed=3))
    fig = scatter_workspace_3d(pts)
    assert isinstance(fig, Figure) and len(fig.axes[0].collections[0].get_offsets()) == 500
    assert fig.axes[0].get_xlabel() == "x (m)"
    fig = plot_sweeps(glass, [1, 2])
    lines = fig.axes[0].get_lines()
    assert len(lines) == 2 and len(lines[0].get_data_3d()[0]) == 200
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert legend == ["θ1 sweeps its range", "θ2 sweeps its range"]
    fig = plot_reach(pts)
    assert isinstance(fig, Figure) and len(fig.axes[0].collections[0].get_offsets()) == 500


def test_paving_plot_draws_every_box_with_a_legend():
    from matplotlib.figure import Figure

    from workspace_sym.plotting import plot_paving

    p = robots.build("rpr2").pave(delta=0.5)
    fig = plot_paving(p, exact_boundary=lambda a, b: np.maximum(a**2 + b**2 - 144, 64 - a**2 - b**2), units="m")
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    drawn = {c.get_label(): c for c in ax.collections}
    assert len(drawn["inner"].get_paths()) == len(p.inner)
    assert len(drawn["boundary"].get_paths()) == len(p.boundary)
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == [f"inner (proved inside): {len(p.inner)}", f"boundary (undecided, size ≤ δ): {len(p.boundary)}",
                      "exact boundary"]
    assert ax.get_xlabel() == "x1 (m)" and ax.get_ylabel() == "x2 (m)"
