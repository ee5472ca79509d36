"""Certified interval computations: arithmetic (numpy engine, mpmath reference),
the SymPy expression compiler, the deciders, the one paving driver and where it runs.

Layers, each importing only those above it: ``arith`` / ``mp`` (kernels) <- ``graph`` / ``compiler``
(expressions to intervals) <- ``verdict`` (the ``Decider`` protocol and its codes) <- ``store`` / ``boxes``
(boxes, exact measures, results) <- ``executor`` (the ``Runner`` seam: in line, threads, futures, Dask) <-
``driver`` (the one loop, ``StopAt`` / ``RunOn`` options) <- ``paving`` (constraint deciders, with
``contractor``'s contraction, and ``pave``); ``image`` and ``search`` build on the same lower layers."""

from .boxes import Box, Paving, StoredPaving, box_measure
from .compiler import BACKENDS, CompiledExpr, best_form, compile_expr
from .driver import RunOn, StopAt, subdivide
from .mp import precision
from .paving import Certificate, Constraint, certify_box, hausdorff, parse_constraints, pave

__all__ = ["BACKENDS", "CompiledExpr", "best_form", "compile_expr", "precision", "Box", "Certificate", "Constraint",
           "Paving", "StoredPaving", "box_measure", "certify_box", "hausdorff", "parse_constraints", "pave", "StopAt",
           "RunOn", "subdivide"]
