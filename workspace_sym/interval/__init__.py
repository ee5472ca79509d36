"""Certified interval computations: arithmetic (numpy engine, mpmath reference),
the SymPy expression compiler, and the non-uniform covering."""

from .compiler import BACKENDS, CompiledExpr, best_form, compile_expr
from .mp import precision
from .paving import Box, Certificate, Constraint, Paving, box_measure, certify_box, hausdorff, parse_constraints, pave

__all__ = ["BACKENDS", "CompiledExpr", "best_form", "compile_expr", "precision", "Box", "Certificate", "Constraint",
           "Paving", "box_measure", "certify_box", "hausdorff", "parse_constraints", "pave"]
