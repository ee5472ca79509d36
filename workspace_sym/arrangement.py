"""Arrangements of circular arcs, under their earlier module name.

The code is in :mod:`workspace_sym.planar.arrangement`; this module keeps the names its users imported from here.
"""

from .planar.arrangement import Arrangement, arc_area_term, arc_distance, crossings, in_span, parity_inside

__all__ = ["Arrangement", "arc_area_term", "arc_distance", "crossings", "in_span", "parity_inside"]
