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
        """The joint vector of the point of the arc where the free joint is ``theta_free``."""
        theta = np.array([s[0] for s in self.theta_sets])
        theta[self.free_joint - 1] = theta_free
        return theta

    def point(self, angle: float) -> np.ndarray:
        """The point of the circle at polar angle ``angle``."""
        return np.array([self.center[0] + self.radius * math.cos(angle),
                         self.center[1] + self.radius * math.sin(angle)])

    def __repr__(self):
        sets = ", ".join(f"{{{fmt(math.degrees(s[0]))}}}" if len(s) == 1 else
                         f"[{fmt(math.degrees(s[0]))}, {fmt(math.degrees(s[1]))}]" for s in self.theta_sets)
        return (f"Arc({self.type}, joint {self.free_joint}, centre ({fmt(self.center[0], 6, 'g')}, "
                f"{fmt(self.center[1], 6, 'g')}), r = {fmt(self.radius, 6, 'g')}, deg: {sets}, side {self.side:+d})")


def degrees(radians: float) -> float:
    """An angle of the float geometry in degrees, without float noise (-60.0, not -59.99999999999999)."""
    return clean(math.degrees(radians), scale=360.0)


def degrees_text(radians: float) -> str:
    """A joint limit as given in degrees: ``-60``, not ``-59.99999999999999``.

    >>> degrees_text(math.radians(-60)), degrees(math.radians(130))
    ('-60', 130.0)
    """
    return fmt(degrees(radians), 10, "g")
