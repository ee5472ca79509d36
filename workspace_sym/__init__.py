"""workspace_sym: robot workspaces computed exactly or with proofs.

The flat public API, so that a notebook writes ``ws.DHRobot(...)``::

    import workspace_sym as ws
    robot = ws.robots.build("glass-handling")
    robot.to_str(robot.position[0])   # 'c1*(a1 + a2*c2 + a3*c23 + d5*s234)'
"""

from . import readers, robots  # readers: fills kinematics.READERS
from .display import register_notebook_display as _register_notebook_display
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
from .planar import Arc, Boundary, PlanarChain
from .planar.exact import exact_arcs, exact_area
from .sampling import extent, reach_points, sample_joint_box, sweep_joints
from .serial_workspace import Pose, reach
from .symbolic import factor_trig, shorthand, textbook
from .teaching import answers, exercises, grading
from .teaching import checks as verify
from .version import __version__ as __version__

_register_notebook_display()          # inside IPython: SymPy results display as MathML (offline exports)

__all__ = [
    "robots",
    "readers",
    "WorkspaceError",
    "BoxError",
    "ConstraintError",
    "DHTableError",
    "ExpressionError",
    "InvalidParameterError",
    "JointLimitError",
    "UnknownNameError",
    "URDFError",
    "MJCFError",
    "AnalyticJacobian",
    "DHJoint",
    "DHRobot",
    "characteristic_polynomial",
    "dh_matrix",
    "eigenvalues_from_charpoly",
    "maximal_minor_factors",
    "numeric_function",
    "Boundary",
    "exact_arcs",
    "exact_area",
    "Box",
    "Certificate",
    "Paving",
    "certify_box",
    "hausdorff",
    "pave",
    "StopAt",
    "RunOn",
    "Orthoglide",
    "ConstraintModel",
    "rpr2",
    "Arc",
    "PlanarChain",
    "reach",
    "Pose",
    "verify",
    "answers",
    "grading",
    "exercises",
    "extent",
    "reach_points",
    "sample_joint_box",
    "sweep_joints",
    "factor_trig",
    "shorthand",
    "textbook",
]
