"""Closed forms of a planar chain's boundary, under their earlier module name.

The code is in :mod:`workspace_sym.planar.exact`; this module keeps the names its users imported from here.
"""

from .planar.exact import area_terms, closed_forms, exact_arcs, exact_area, norm2, polar_angle, short_atan2, short_sqrt

__all__ = ["closed_forms", "exact_arcs", "exact_area", "area_terms", "short_atan2", "short_sqrt", "polar_angle",
           "norm2"]
