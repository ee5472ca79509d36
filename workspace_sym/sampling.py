"""Sampling the joint box of a serial robot (vectorised), for workspace pictures.

These are pictures, not proofs: a scatter of reachable points like figures 2-10
of paper 004.  Certified statements come from :mod:`workspace_sym.interval`.
"""

from __future__ import annotations

import numpy as np

from .errors import InvalidParameterError, check_choice

__all__ = ["sample_joint_box", "sweep_joints", "reach_points", "extent"]


def _limits(robot) -> np.ndarray:
    return robot.joint_limits()


def sample_joint_box(robot, n: int, *, method: str = "uniform", seed: int | None = 0) -> np.ndarray:
    """``(n, dof)`` configurations drawn from the joint box.

    ``method="uniform"`` draws at random; ``"grid"`` takes a regular grid with
    about ``n`` points (``ceil(n ** (1/dof))`` per joint, limits included).

    Parameters
    ----------
    robot : DHRobot
        The robot, read for its joint limits (radians, or metres for a prismatic joint; an unlimited joint
        spans ``[-pi, pi]``).
    n : int
        The number of configurations (``"uniform"``), or the least number of grid points (``"grid"``).
    method : {"uniform", "grid"}, default "uniform"
        Random draws or a regular grid.
    seed : int or None, default 0
        Seed of :func:`numpy.random.default_rng` for ``"uniform"``; None draws a fresh one.

    Returns
    -------
    numpy.ndarray
        ``(n, dof)`` configurations for ``"uniform"``; ``(k ** dof, dof)`` for ``"grid"``, with
        ``k = max(2, ceil(n ** (1/dof)))`` values per joint, so at least ``n`` rows.

    Raises
    ------
    UnknownNameError
        When ``method`` is neither ``"uniform"`` nor ``"grid"``.
    InvalidParameterError
        When ``n`` is not a positive integer.

    Examples
    --------
    >>> from workspace_sym.robots import planar_2r
    >>> sample_joint_box(planar_2r(), 4, method="grid").shape
    (4, 2)
    """
    check_choice("method", method, ("uniform", "grid"))
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise InvalidParameterError(f"n must be a positive integer; got {n!r}")
    lim = _limits(robot)
    if method == "uniform":
        rng = np.random.default_rng(seed)
        return lim[:, 0] + (lim[:, 1] - lim[:, 0]) * rng.random((n, len(lim)))
    per_joint = max(2, int(np.ceil(n ** (1.0 / len(lim)))))
    axes = [np.linspace(lo, hi, per_joint) for lo, hi in lim]
    mesh = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(lim))
    return mesh


def sweep_joints(robot, joints, n: int = 200, *, base=None) -> np.ndarray:
    """Configurations that move ``joints`` (1-based) one after the other over their range.

    The others stay at ``base`` (default: every joint at its lower limit, as in
    paper 004, figures 6-9).  Each listed joint runs from its lower to its upper
    limit with ``n`` samples, starting from where the previous sweep left it
    (figure 10 of the paper).

    Parameters
    ----------
    robot : DHRobot
        The robot, read for its joint limits and number of joints.
    joints : iterable of int
        The joints to sweep, 1-based, in order; a joint may come more than once.
    n : int, default 200
        Samples per sweep, limits included.
    base : array_like, optional
        ``(dof,)``: the configuration the sweeps start from; by default every joint at its lower limit.

    Returns
    -------
    numpy.ndarray
        ``(n * len(joints), dof)`` configurations, the sweeps one after the other.

    Raises
    ------
    InvalidParameterError
        When ``base`` does not have one value per joint or a joint index is out of range.
    """
    lim = _limits(robot)
    q = lim[:, 0].copy() if base is None else np.asarray(base, dtype=float).copy()
    if q.shape != (robot.n,):
        raise InvalidParameterError(f"base must have {robot.n} values; got shape {q.shape}")
    out = []
    for j in joints:
        if not 1 <= j <= robot.n:
            raise InvalidParameterError(f"joint index must be between 1 and {robot.n}; got {j}")
        block = np.repeat(q[None, :], n, axis=0)
        block[:, j - 1] = np.linspace(lim[j - 1, 0], lim[j - 1, 1], n)
        out.append(block)
        q = block[-1].copy()
    return np.concatenate(out, axis=0)


def reach_points(robot, q: np.ndarray, parameters: dict | None = None) -> np.ndarray:
    """End-effector positions ``(N, 3)`` of configurations ``q`` (one vectorised call).

    Parameters
    ----------
    robot : DHRobot
        The robot.
    q : numpy.ndarray
        ``(N, dof)`` configurations.
    parameters : dict, optional
        Numeric values of the robot's symbolic parameters, replacing its defaults (not merged with them: give
        every one); by default the robot's own.

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` positions of the end effector.

    Raises
    ------
    InvalidParameterError
        When ``parameters`` leaves a symbol of the position without a value.
    """
    if parameters is None:
        return robot.fk_numeric(q)[..., :3, 3]
    return robot.numeric(robot.position, parameters)(q)[..., :, 0]


def extent(points: np.ndarray) -> dict:
    """Bounding box and reach (largest distance from the base) of a point cloud.

    Parameters
    ----------
    points : array_like
        ``(N, d)`` points, ``N >= 1``.

    Returns
    -------
    dict
        ``{"min": [...], "max": [...], "reach": float}``: the per-coordinate minimum and maximum and the
        largest distance from the origin.
    """
    points = np.asarray(points)
    return {
        "min": points.min(axis=0).tolist(),
        "max": points.max(axis=0).tolist(),
        "reach": float(np.linalg.norm(points, axis=1).max()),
    }
