"""workspace_sym: robot workspaces computed exactly or with proofs.

The flat public API, so that a notebook writes ``ws.DHRobot(...)``::

    import workspace_sym as ws
    robot = ws.robots.build("glass-handling")
    robot.to_str(robot.position[0])   # 'c1*(a1 + a2*c2 + a3*c23 + d5*s234)'

Each name is imported from its module the first time it is used (``import workspace_sym`` itself imports no
SymPy and no engine: the command line's ``--help`` and a script that needs one engine start fast); the names are
the same objects as in their modules.  This module is the package's face, the one that knows every layer: it
also declares which modules provide the readers and the reach engine to the robot class built below them
(:mod:`workspace_sym.registry`), and inside IPython it has the presentation layer register the notebook displays.
"""

from __future__ import annotations

import importlib
import sys
from typing import TYPE_CHECKING

from . import errors, registry
from .errors import (
    BoxError,
    ConstraintError,
    DHTableError,
    ExpressionError,
    InvalidParameterError,
    JointLimitError,
    MJCFError,
    UnknownNameError,
    URDFError,
    WorkspaceError,
)
from .version import __version__ as __version__

registry.declare("readers", "workspace_sym.readers")
registry.declare("engines", "workspace_sym.serial")

# name -> (module, attribute): the flat API, loaded on first use; a module alone is (module, None)
_API: dict[str, tuple[str, str | None]] = {
    "robots": ("robots", None), "readers": ("readers", None), "answers": ("teaching.answers", None),
    "exercises": ("teaching.exercises", None), "grading": ("teaching.grading", None),
    "verify": ("teaching.checks", None),
    **{name: ("kinematics", name) for name in ("AnalyticJacobian", "DHJoint", "DHRobot", "characteristic_polynomial",
                                               "dh_matrix", "eigenvalues_from_charpoly", "maximal_minor_factors",
                                               "numeric_function")},
    **{name: ("interval", name) for name in ("Box", "Certificate", "Paving", "certify_box", "hausdorff", "pave",
                                             "StopAt", "RunOn")},
    **{name: ("serial", name) for name in ("reach", "Pose", "ReachResult", "Tuning", "reach_map", "ReachMap")},
    **{name: ("planar", name) for name in ("Arc", "Boundary", "PlanarChain", "exact_arcs", "exact_area")},
    "Orthoglide": ("orthoglide", "Orthoglide"),
    "ConstraintModel": ("parallel", "ConstraintModel"), "rpr2": ("parallel", "rpr2"),
    **{name: ("sampling", name) for name in ("extent", "reach_points", "sample_joint_box", "sweep_joints")},
    **{name: ("symbolic", name) for name in ("factor_trig", "shorthand", "textbook")},
}


def __getattr__(name: str):
    """A name of the flat API, imported from its module on first use (PEP 562); then any submodule."""
    if name in _API:
        module, attribute = _API[name]
        value = importlib.import_module(f"{__name__}.{module}")
        if attribute is not None:
            value = getattr(value, attribute)
        globals()[name] = value
        return value
    try:
        return importlib.import_module(f"{__name__}.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__name__}.{name}":
            raise
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_API))


if TYPE_CHECKING:                       # what the names are, for type checkers and editors
    from . import readers, robots
    from .interval import Box, Certificate, Paving, RunOn, StopAt, certify_box, hausdorff, pave
    from .kinematics import (
        AnalyticJacobian,
        DHJoint,
        DHRobot,
        characteristic_polynomial,
        dh_matrix,
        eigenvalues_from_charpoly,
        maximal_minor_factors,
        numeric_function,
    )
    from .orthoglide import Orthoglide
    from .parallel import ConstraintModel, rpr2
    from .planar import Arc, Boundary, PlanarChain, exact_arcs, exact_area
    from .sampling import extent, reach_points, sample_joint_box, sweep_joints
    from .serial import Pose, ReachMap, ReachResult, Tuning, reach, reach_map
    from .symbolic import factor_trig, shorthand, textbook
    from .teaching import answers, exercises, grading
    from .teaching import checks as verify

if "IPython" in sys.modules:            # inside IPython: results display as HTML, SymPy's as MathML (offline exports)
    from .display import register_notebook_display

    register_notebook_display()

__all__ = [
    "robots", "readers", "errors", "registry",
    "WorkspaceError", "BoxError", "ConstraintError", "DHTableError", "ExpressionError", "InvalidParameterError",
    "JointLimitError", "UnknownNameError", "URDFError", "MJCFError",
    "AnalyticJacobian", "DHJoint", "DHRobot", "characteristic_polynomial", "dh_matrix", "eigenvalues_from_charpoly",
    "maximal_minor_factors", "numeric_function",
    "Boundary", "exact_arcs", "exact_area", "Arc", "PlanarChain",
    "Box", "Certificate", "Paving", "certify_box", "hausdorff", "pave", "StopAt", "RunOn",
    "Orthoglide", "ConstraintModel", "rpr2",
    "reach", "Pose", "ReachResult", "Tuning", "reach_map", "ReachMap",
    "verify", "answers", "grading", "exercises",
    "extent", "reach_points", "sample_joint_box", "sweep_joints",
    "factor_trig", "shorthand", "textbook",
]
