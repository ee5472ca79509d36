"""The Orthoglide (Chablat, Wenger, Merlet 2002): dextrous workspace and largest enclosed cube.

* :mod:`.model`: :class:`Orthoglide`, the symbolic model and the entry points;
* :mod:`.certificate`: the certified box module ``M(B)`` and the dextrous workspace paving;
* :mod:`.cube`: the largest enclosed cube and its two certificates.
"""

from .certificate import DextrousResult, inverse_entries
from .cube import CubeResult
from .model import Orthoglide, e1, e2, e3, lam, x, y, z

__all__ = ["Orthoglide", "DextrousResult", "CubeResult", "inverse_entries", "x", "y", "z", "e1", "e2", "e3", "lam"]
