"""What the rooms of :mod:`workspace_sym.planar` share: the arc of a boundary, the finest detail resolved, angles
shown in degrees.

The chain (:mod:`.chain`, Steps 0 and 1) makes :class:`Arc` values and the boundary (:mod:`.boundary`, Step 2)
extends them; both read :data:`RESOLUTION`.  This room imports neither.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..numbers import clean, fmt

__all__ = ["Arc", "RESOLUTION", "degrees", "degrees_text"]

# The finest detail Step 2 resolves, relative to the reach: faces narrower than this are merged
# (boundary.SLIVER_WIDTH).  A joint whose range falls short of a full turn by at most twice this many radians
# is a full turn: each angle it leaves out lies within RESOLUTION of a limit, so the points only they reach
# lie within RESOLUTION * reach of the workspace of the limited joint.
RESOLUTION = 1e-7


@dataclass(frozen=True, slots=True)
class Arc:
    """A circular arc of the workspace boundary (or a candidate for it).

    ``theta_sets[k]`` is ``(value,)`` for a joint held at a limit or at an
    alignment angle, ``(low, high)`` for the free joint (radians).  ``center``,
    ``radius``; ``start_angle`` / ``end_angle`` are polar angles about the
    centre (radians, counter-clockwise from start to end as the free joint
    increases).  ``side`` is +1 when the workspace lies locally away from the
    centre, -1 towards it, 0 before Step 1.

    Parameters
    ----------
    type : str
        The paper's type of the set J of free joints (``free_joint`` and the joints held at alignment angles;
        the others are at limits): ``"I"`` when J holds every joint, ``"III"`` when it holds ``free_joint`` alone,
        ``"II"`` otherwise.
    free_joint : int
        The joint that turns along the arc, 1-based.
    theta_sets : tuple of tuple of float
        One entry per joint: ``(value,)`` for a held joint, ``(low, high)`` for the free joint (radians).
    center : tuple of float
        The centre ``(x, y)`` of the circle, in the unit of the chain's lengths.
    radius : float
        The radius of the circle, in the unit of the chain's lengths.
    start_angle, end_angle : float
        Polar angles about ``center`` where the arc starts and ends (radians).
    side : int, default 0
        +1, -1 or 0, as above.
    """

    type: str
    free_joint: int
    theta_sets: tuple
    center: tuple[float, float]
    radius: float
    start_angle: float
    end_angle: float
    side: int = 0

    def configuration(self, theta_free: float) -> np.ndarray:
        """The joint vector of the point of the arc where the free joint is ``theta_free``.

        Parameters
        ----------
        theta_free : float
            The value of the free joint (radians).

        Returns
        -------
        numpy.ndarray
            ``(p,)`` joint angles (radians): the held joints at their values, the free one at ``theta_free``.
        """
        theta = np.array([s[0] for s in self.theta_sets])
        theta[self.free_joint - 1] = theta_free
        return theta

    def point(self, angle: float) -> np.ndarray:
        """The point of the circle at polar angle ``angle``.

        Parameters
        ----------
        angle : float
            Polar angle about :attr:`center` (radians); any value, not only one on the arc.

        Returns
        -------
        numpy.ndarray
            ``(2,)``: the point ``center + radius (cos angle, sin angle)``.
        """
        return np.array([self.center[0] + self.radius * math.cos(angle),
                         self.center[1] + self.radius * math.sin(angle)])

    def __repr__(self):
        sets = ", ".join(f"{{{fmt(math.degrees(s[0]))}}}" if len(s) == 1 else
                         f"[{fmt(math.degrees(s[0]))}, {fmt(math.degrees(s[1]))}]" for s in self.theta_sets)
        return (f"Arc({self.type}, joint {self.free_joint}, centre ({fmt(self.center[0], 6, 'g')}, "
                f"{fmt(self.center[1], 6, 'g')}), r = {fmt(self.radius, 6, 'g')}, deg: {sets}, side {self.side:+d})")


def degrees(radians: float) -> float:
    """An angle of the float geometry in degrees, without float noise (-60.0, not -59.99999999999999).

    Parameters
    ----------
    radians : float
        The angle in radians.

    Returns
    -------
    float
        The angle in degrees (:func:`~workspace_sym.numbers.clean` on the scale of a full turn): the nearest
        decimal of at most 9 significant digits when within float noise of it, 0.0 within 3.6e-10 deg of zero.
    """
    return clean(math.degrees(radians), scale=360.0)


def degrees_text(radians: float) -> str:
    """A joint limit as given in degrees: ``-60``, not ``-59.99999999999999``.

    Parameters
    ----------
    radians : float
        The angle in radians.

    Returns
    -------
    str
        :func:`degrees` written with at most 10 significant digits, without a trailing ``.0``.

    Examples
    --------
    >>> degrees_text(math.radians(-60)), degrees(math.radians(130))
    ('-60', 130.0)
    """
    return fmt(degrees(radians), 10, "g")
