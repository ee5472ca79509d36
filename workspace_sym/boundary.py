"""Step 2 of the alignment method (the boundary of a planar chain's workspace), under its earlier module name.

The code is in :mod:`workspace_sym.planar.boundary`; this module keeps the names its users imported from here.
"""

from .planar.boundary import (
    SLIVER_WIDTH,
    ArcTable,
    Boundary,
    BoundaryArc,
    Loop,
    build_boundary,
    format_set,
    outside_every_turn,
    prove_unreachable,
    unreachable_via_subchain,
    witness_near,
)

__all__ = ["Boundary", "BoundaryArc", "Loop", "ArcTable", "build_boundary", "format_set", "prove_unreachable",
           "outside_every_turn", "unreachable_via_subchain", "witness_near", "SLIVER_WIDTH"]
