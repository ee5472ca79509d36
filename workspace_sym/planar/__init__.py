"""Planar chains with joint limits: the exact workspace boundary by the alignment method of Bastien (2018).

``PlanarChain(lengths, lower, upper).boundary()`` gives the boundary as loops of arcs, its area and its closed
forms.  The rooms, from the bottom up:

* :mod:`.arcs`: what the others share: :class:`Arc`, :data:`RESOLUTION` (the finest detail resolved), angles in
  degrees;
* :mod:`.arrangement`: the arrangement of circular arcs (:class:`Arrangement`): vertices, edges, faces, point
  location, float arithmetic with explicit tolerances; it knows nothing of chains;
* :mod:`.exact`: closed forms of a boundary's arcs and area (:func:`closed_forms`, :func:`exact_arcs`,
  :func:`exact_area`, :func:`area_terms`), read from a boundary and its chain by their attributes;
* :mod:`.boundary`: Step 2: the faces of the kept arcs classified, the boundary loops walked
  (:func:`build_boundary`, :class:`Boundary`, :class:`BoundaryArc`, :class:`Loop`), the proofs that a point is
  out of reach (:func:`prove_unreachable`, :func:`outside_every_turn`, :func:`unreachable_via_subchain`) and
  witnesses (:func:`witness_near`); it reads the chain by its attributes and does not import it;
* :mod:`.chain`: :class:`PlanarChain`, Steps 0 and 1 (candidate arcs, arcs kept by Lemma 3.1), and
  :meth:`PlanarChain.boundary`, which hands the chain to :func:`build_boundary`.

Arrows: ``chain -> boundary -> arrangement, exact``; ``chain, boundary -> arcs``.  What a notebook shows of a
chain, a boundary or its table of arcs is drawn by :mod:`workspace_sym.display`, which registers itself; nothing
here imports the presentation layer.
"""

from .arcs import RESOLUTION, Arc
from .arrangement import Arrangement
from .boundary import Boundary, BoundaryArc, Loop, build_boundary, format_set, prove_unreachable, witness_near
from .chain import PlanarChain
from .exact import area_terms, closed_forms, exact_arcs, exact_area

__all__ = ["PlanarChain", "Arc", "RESOLUTION", "Boundary", "BoundaryArc", "Loop", "build_boundary", "format_set",
           "prove_unreachable", "witness_near", "Arrangement", "closed_forms", "exact_arcs", "exact_area",
           "area_terms"]
