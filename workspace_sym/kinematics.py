"""Serial robots from Denavit-Hartenberg tables, derived symbolically.

Standard DH (docs/methods.md section 1): ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``.
Modified (Craig) DH: ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``, where
row ``i`` of the table holds ``alpha_{i-1}, a_{i-1}, theta_i, d_i``.

Every result is a SymPy expression in textbook form (see :mod:`workspace_sym.symbolic`);
the fast numeric evaluators are generated from those same expressions.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
import sympy as sp

from .charpoly import (
    characteristic_polynomial,
    eigenvalues_from_charpoly,
    gram_characteristic_polynomial,
    maximal_minor_factors,
)
from .errors import (
    DHTableError,
    ExpressionError,
    InvalidParameterError,
    check_choice,
)
from .expressions import as_matrix, as_sympy, check_joint_limits, is_finite_value, parse_expr
from .registry import declared, load
from .snap import DEFAULT_TOL, chop
from .symbolic import (
    algebraic_constants,
    check_budget,
    decimal_form,
    derivation,
    in_lengths,
    op_counts,
    shorthand,
    shorthand_latex,
    shorthand_str,
    textbook,
    textbook_form,
    textbook_matrix,
    trig_pair,
)
from .transforms import inverse_transform, matrix_product, rot_x, rot_z, translation, xyz_rpy

__all__ = [
    "DHJoint",
    "DHRobot",
    "AnalyticJacobian",
    "dh_matrix",
    "xyz_rpy",
    "characteristic_polynomial",
    "gram_characteristic_polynomial",
    "eigenvalues_from_charpoly",
    "maximal_minor_factors",
    "numeric_function",
    "CONVENTIONS",
    "EULER_CONVENTIONS",
    "READERS",
    "ENGINES",
]

CONVENTIONS = ("standard", "modified")
EULER_CONVENTIONS = ("zyz", "rpy")
JOINT_KINDS = ("R", "P")


def dh_matrix(theta, d, a, alpha, *, convention: str = "standard") -> sp.Matrix:
    """Homogeneous transform of one DH row.

    For ``convention="modified"`` the arguments are ``theta_i, d_i, a_{i-1}, alpha_{i-1}``.

    Parameters
    ----------
    theta, d, a, alpha : SymPy expression or number
        The row's fields: angles in radians, lengths in the table's unit.
    convention : {"standard", "modified"}
        Standard ``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` (the default) or modified ``Rx(alpha) Tx(a) Rz(theta)
        Tz(d)``.

    Returns
    -------
    sympy.Matrix
        The 4x4 homogeneous transform.

    Raises
    ------
    UnknownNameError
        When ``convention`` is not one of :data:`CONVENTIONS`.

    Examples
    --------
    >>> t = sp.Symbol("t")
    >>> dh_matrix(t, 0, 1, 0)
    Matrix([
    [cos(t), -sin(t), 0, cos(t)],
    [sin(t),  cos(t), 0, sin(t)],
    [     0,       0, 1,      0],
    [     0,       0, 0,      1]])
    """
    check_choice("convention", convention, CONVENTIONS)
    # Constant angles whose cosines SymPy writes as nested radicals (36 deg) or not at all (1 deg)
    # stay cos(c), sin(c) atoms (trig_pair): products of nested radicals grow without end.
    rz, rx = rot_z(theta, trig_pair(theta)), rot_x(alpha, trig_pair(alpha))
    if convention == "standard":
        return rz * translation(z=d) * translation(x=a) * rx
    return rx * translation(x=a) * rz * translation(z=d)


@dataclass(frozen=True, slots=True)
class DHJoint:
    """One row of a DH table.

    ``theta`` and ``d`` are full expressions: for a revolute joint ``theta``
    contains the joint variable (``theta_i`` plus any offset), for a prismatic
    joint ``d`` does.  ``limits`` are in radians (revolute) or length units
    (prismatic); ``None`` means unlimited.  ``name`` is the joint's name in
    the file it was read from (a URDF or MJCF joint), ``None`` for a DH
    table; it is a label, not part of the table (equal rows are equal joints).

    Parameters
    ----------
    kind : {"R", "P"}
        Revolute or prismatic.
    theta, d, a, alpha : sympy.Expr
        The row's fields (angles in radians).
    variable : sympy.Symbol
        The joint variable, which ``theta`` (revolute) or ``d`` (prismatic) must contain.
    limits : pair of SymPy numbers, optional
        ``(lower, upper)``; None (the default) for an unlimited joint.
    name : str, optional
        The joint's name in the file it was read from (default None).

    Raises
    ------
    UnknownNameError
        When ``kind`` is neither ``"R"`` nor ``"P"``.
    DHTableError
        When the moving field does not contain ``variable``.
    JointLimitError
        When a limit is not a finite real number or ``lower >= upper``.
    ExpressionError
        When a limit is text that cannot be read.
    """

    kind: str
    theta: sp.Expr
    d: sp.Expr
    a: sp.Expr
    alpha: sp.Expr
    variable: sp.Symbol
    limits: tuple[sp.Expr, sp.Expr] | None = None
    name: str | None = field(default=None, compare=False)

    def __post_init__(self):
        check_choice("joint type", self.kind, JOINT_KINDS)
        moving = self.theta if self.kind == "R" else self.d
        if not moving.has(self.variable):
            raise DHTableError(
                f"{'theta' if self.kind == 'R' else 'd'} of a {self.kind} joint must contain its variable "
                f"{self.variable}; got {moving}"
            )
        if self.limits is not None:
            check_joint_limits(self.variable, *self.limits)

    @classmethod
    def revolute(cls, index: int, *, d=0, a=0, alpha=0, offset=0, limits=None, variable=None) -> DHJoint:
        """Revolute joint ``index`` (1-based) with variable ``theta{index}``.

        Parameters
        ----------
        index : int
            The joint's place in the table, from 1: it names the variable and the messages.
        d, a, alpha : number, SymPy expression or str
            The constant fields (default 0; ``alpha`` in radians); text is read by
            :func:`~workspace_sym.expressions.parse_expr`, new symbols (``"a2"``) included.
        offset : number, SymPy expression or str
            Added to the variable: ``theta = variable + offset`` (default 0).
        limits : pair, optional
            ``(lower, upper)`` in radians, numbers or text without symbols; None (the default): unlimited.
        variable : sympy.Symbol, optional
            The joint variable; None (the default) is ``theta{index}``.

        Returns
        -------
        DHJoint
            The row.

        Raises
        ------
        ExpressionError
            When a field or a limit cannot be read (a limit may not hold a symbol).
        JointLimitError
            When a limit is not finite or ``lower >= upper``.
        """
        q = variable if variable is not None else sp.Symbol(f"theta{index}")
        d, a, alpha, offset = (_field(v, index, k) for k, v in (("d", d), ("a", a), ("alpha", alpha),
                                                                 ("offset", offset)))
        return cls("R", q + offset, d, a, alpha, q, _limits(limits, index))

    @classmethod
    def prismatic(cls, index: int, *, theta=0, a=0, alpha=0, offset=0, limits=None, variable=None) -> DHJoint:
        """Prismatic joint ``index`` (1-based) with variable ``d{index}``.

        Parameters
        ----------
        index : int
            The joint's place in the table, from 1: it names the variable and the messages.
        theta, a, alpha : number, SymPy expression or str
            The constant fields (default 0; ``theta`` and ``alpha`` in radians); text is read by
            :func:`~workspace_sym.expressions.parse_expr`, new symbols included.
        offset : number, SymPy expression or str
            Added to the variable: ``d = variable + offset`` (default 0).
        limits : pair, optional
            ``(lower, upper)`` in the length unit, numbers or text without symbols; None (the default): unlimited.
        variable : sympy.Symbol, optional
            The joint variable; None (the default) is ``d{index}``.

        Returns
        -------
        DHJoint
            The row.

        Raises
        ------
        ExpressionError
            When a field or a limit cannot be read (a limit may not hold a symbol).
        JointLimitError
            When a limit is not finite or ``lower >= upper``.
        """
        q = variable if variable is not None else sp.Symbol(f"d{index}")
        theta, a, alpha, offset = (_field(v, index, k) for k, v in (("theta", theta), ("a", a), ("alpha", alpha),
                                                                         ("offset", offset)))
        return cls("P", theta, q + offset, a, alpha, q, _limits(limits, index))

    def __repr__(self) -> str:
        lim = "" if self.limits is None else f", limits=[{self.limits[0]}, {self.limits[1]}]"
        return f"DHJoint({self.kind}: theta={self.theta}, d={self.d}, a={self.a}, alpha={self.alpha}{lim})"


def _homogeneous(M, parameter: str) -> sp.Matrix:
    """A constant 4 x 4 homogeneous transform, checked."""
    if not isinstance(M, sp.MatrixBase):
        try:
            M = sp.Matrix([[as_sympy(v, parameter) for v in row] for row in M])   # text only through the reader
        except TypeError as exc:
            raise DHTableError(f"{parameter}: expected a 4 x 4 matrix; got {M!r:.80}") from exc
    if M.shape != (4, 4):
        raise DHTableError(f"{parameter}: expected a 4 x 4 matrix; got shape {M.shape[0]} x {M.shape[1]}")
    if list(M[3, :]) != [0, 0, 0, 1]:
        raise DHTableError(f"{parameter}: last row must be [0, 0, 0, 1]; got {list(M[3, :])}")
    R = M[:3, :3]
    if R.free_symbols:
        raise DHTableError(f"{parameter}: the rotation must be numeric; got symbols {sorted(map(str, R.free_symbols))}")
    # In floats: evalf of the exact R R^T - I, whose entries are exactly 0, raised its precision until it gave up
    # (4 s for a tool turned by rpy angles in degrees).
    Rn = np.array(R.evalf(), dtype=float)
    err = np.abs(Rn @ Rn.T - np.eye(3)).max()
    det = float(np.linalg.det(Rn))
    if err > 1e-9 or det < 0:
        raise DHTableError(f"{parameter}: the 3 x 3 block must be a rotation (R R^T = I, det R = +1); "
                           f"got |R R^T - I| = {err:.3g}, det R = {det:.6g}")
    return M


def _field(value, index, field):
    """A field of joint ``index``: numbers and SymPy objects as given, text through parse_expr (never sympify)."""
    return parse_expr(value, f"joint {index} {field}")


def _limits(limits, index):
    if limits is None:
        return None
    lo, hi = limits
    return tuple(parse_expr(v, f"joint {index} {side} limit", new_symbols=False)
                 for side, v in (("lower", lo), ("upper", hi)))


def parameter_value(value, name: str) -> float:
    """A default parameter value: a finite real number (text read by parse_expr, without symbols)."""
    v = parse_expr(value, name, new_symbols=False)
    if not v.is_number or not is_finite_value(v):
        raise ExpressionError(f"{name}: expected a finite real number; got {value!r:.60}")
    return float(v)


@dataclass(frozen=True, slots=True)
class AnalyticJacobian:
    """Analytic Jacobian ``[v; d(angles)/dt] = J q_dot`` for one Euler convention.

    ``angles`` are the three Euler angles as functions of the joint variables,
    ``singular_when`` an expression whose zero set is the representation
    singularity (where the angle rates are undefined although the geometric
    Jacobian is fine).

    Parameters
    ----------
    convention : {"zyz", "rpy"}
        The Euler angles.
    J : sympy.Matrix
        The 6 x n Jacobian: the position rows, then the rates of the three angles.
    angles : tuple of three sympy.Expr
        The angles, as ``atan2`` of entries of the rotation.
    singular_when : sympy.Expr
        Zero exactly where the angles' rates are undefined.
    note : str
        That condition in words.
    """

    convention: str
    J: sp.Matrix
    angles: tuple[sp.Expr, sp.Expr, sp.Expr]
    singular_when: sp.Expr
    note: str


def _no_longer(T: sp.Matrix, raw: sp.Matrix) -> sp.Matrix:
    """``T`` with each entry that has more operations (``count_ops``) than the same entry of the raw product ``raw``
    replaced by that entry: each product is put in textbook form from the previous one, whose entries may be a
    little longer than the raw product's (issue 29: 3 of 16 entries of a 6-joint table, by up to 7 %)."""
    check_budget("comparing with the raw product")
    ours, theirs = op_counts(T), op_counts(raw)
    return sp.Matrix(T.rows, T.cols, [t if a <= b else r for t, r, a, b in zip(T, raw, ours, theirs)])


def _cross(u: sp.Matrix, v: sp.Matrix) -> sp.Matrix:
    """``u x v`` as SymPy's ``Matrix.cross`` writes it, with the products by a zero component left out: SymPy's
    ``0 * expr`` asks whether ``expr`` could be infinite (``0 * oo`` is nan), a walk of assumption queries over the
    whole of ``expr`` that took a quarter of a 6-joint table's fk + Jacobian for ``z_0 = (0, 0, 1)``."""
    def times(a, b):
        return sp.S.Zero if a == 0 or b == 0 else a * b

    return sp.Matrix([times(u[1], v[2]) - times(u[2], v[1]), times(u[2], v[0]) - times(u[0], v[2]),
                      times(u[0], v[1]) - times(u[1], v[0])])


MAX_JOINTS = 24
"""The most joints a :class:`DHRobot` takes: its symbolic kinematics grow with every joint (a planar chain of 20
joints takes seconds, one of 50 did not finish in a minute), so a larger table is refused at once, not left to run."""


def check_joint_count(n: int) -> None:
    if n > MAX_JOINTS:
        raise DHTableError(f"joints: a robot has at most {MAX_JOINTS} joints (the symbolic kinematics grow with every "
                           f"joint); got {n}", parameter="joints")


READERS: dict[str, Callable[..., DHRobot]] = {}
"""The readers of robot descriptions, by format: ``"dh"`` (a DH-file dictionary), ``"dh_file"`` (a DH JSON file),
``"urdf"``, ``"mjcf"``.  The readers build on this module, so it never imports them: :mod:`workspace_sym.readers`
registers them here when it is imported, and ``DHRobot.from_dict``, ``from_file``, ``from_urdf`` and
``from_mjcf`` look them up; an empty table is filled by the provider the package declares
(:mod:`workspace_sym.registry`)."""


ENGINES: dict[str, Callable] = {}
"""The engines a robot's convenience methods hand it to, by name: ``"reach"`` (the certified workspace,
:func:`workspace_sym.serial.reach`).  They build on this module, which never imports them: each registers itself
here when it is imported, and ``DHRobot.reach`` looks it up (an empty table is filled as :data:`READERS` is)."""


def _registered(table: dict, name: str, key: str, what: str) -> Callable:
    """``table[key]`` (``name`` is the table's), the provider the package declares for it imported first when it is
    not there; ``what`` names the entry in the error."""
    provider = {"READERS": "readers", "ENGINES": "engines"}[name]
    if key not in table:
        try:
            load(provider)
        except LookupError:
            pass
    found = table.get(key)
    if found is None:
        module = declared().get(provider, f"workspace_sym.{provider}")
        raise RuntimeError(f"no {what} is registered in workspace_sym.kinematics.{name}; import {module}, which "
                           "registers it")
    return found


def _reader(kind: str) -> Callable[..., DHRobot]:
    """The reader registered for ``kind`` in :data:`READERS`."""
    return _registered(READERS, "READERS", kind, f"reader of {kind!r} robot descriptions")


class DHRobot:
    """A serial robot described by a DH table.

    Parameters
    ----------
    joints : sequence of DHJoint
        The rows, from the base out: 1 to :data:`MAX_JOINTS` of them, with distinct variables.
    convention : {"standard", "modified"}
        The DH convention of the rows (default ``"standard"``).
    name : str
        The robot's name (default ``"robot"``).
    parameters : dict, optional
        Default numeric values for the symbolic lengths, used by the numeric
        evaluators and plots (``{Symbol("a2"): 0.25, ...}``); a key may be the symbol's name, a value text (read
        as a finite number).
    units : str
        Length unit of the table and the parameters (default ``"m"``).
    base, tool : 4 x 4 matrix, optional
        Constant transforms before the first row and after the last one:
        ``fk() = base T_0^n tool``.  The Jacobians are those of the tool point,
        expressed in the world (base) frame.
    input_notes : sequence of str
        What the reader changed in the input (floats made exact, URDF joints
        folded), kept as ``robot.input_notes``.
    chop_tol : float, optional
        Floats below it in each DH matrix are set to zero (float tables read
        with ``exact=False``).

    Raises
    ------
    DHTableError
        When ``joints`` is empty or longer than :data:`MAX_JOINTS`, two joints share a variable, a parameter is a
        joint variable, or ``base`` or ``tool`` is not a 4 x 4 transform with a numeric rotation and last row
        ``[0, 0, 0, 1]``.
    UnknownNameError
        When ``convention`` is not one of :data:`CONVENTIONS`.
    ExpressionError
        When an entry of ``base`` or ``tool`` given as text cannot be read, or a parameter value given as text is
        not a finite number.

    Examples
    --------
    >>> robot = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=1)])
    >>> robot.position
    Matrix([
    [cos(theta1) + cos(theta1 + theta2)],
    [sin(theta1) + sin(theta1 + theta2)],
    [                                 0]])
    """

    def __init__(self, joints, *, convention: str = "standard", name: str = "robot",
                 parameters: dict | None = None, units: str = "m", base=None, tool=None, input_notes=(),
                 chop_tol: float | None = None):
        check_choice("convention", convention, CONVENTIONS)
        self.input_notes = tuple(input_notes)
        self.chop_tol = chop_tol
        self.base = None if base is None else _homogeneous(base, "base")
        self.tool = None if tool is None else _homogeneous(tool, "tool")
        joints = tuple(joints)
        if not joints:
            raise DHTableError("joints: a robot needs at least one joint; got an empty table")
        check_joint_count(len(joints))
        variables = [j.variable for j in joints]
        if len(set(variables)) != len(variables):
            raise DHTableError(f"joint variables must be distinct; got {variables}")
        self.joints = joints
        self.convention = convention
        self.name = name
        self.units = units
        self.parameters = {sp.Symbol(str(k)) if isinstance(k, str) else k:
                           parameter_value(v, f"parameter {k}") if isinstance(v, str) else v
                           for k, v in (parameters or {}).items()}
        clash = set(self.parameters) & set(variables)
        if clash:
            raise DHTableError(f"parameters {sorted(map(str, clash))} are joint variables, not constants")

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_dict(cls, data: dict, *, name: str = "robot", exact: bool = True, tol: float = DEFAULT_TOL) -> DHRobot:
        """Build a robot from a DH-file dictionary: :func:`workspace_sym.readers.read_dh`.

        The format is that of ``docs/cli.md``, section "DH files".  Floats are made exact where they clearly are
        (``exact``, ``tol``; listed in ``robot.input_notes``).

        Parameters
        ----------
        data : dict
            The DH description.
        name, exact, tol
            As for :func:`workspace_sym.readers.read_dh`.

        Returns
        -------
        DHRobot
            The robot.

        Raises
        ------
        DHTableError, UnknownNameError, JointLimitError, ExpressionError, InvalidParameterError
            As for :func:`workspace_sym.readers.read_dh`.

        Examples
        --------
        >>> DHRobot.from_dict({"joints": [{"d": 0, "a": 0.4318, "alpha": 90.0}]}).joints[0]
        DHJoint(R: theta=theta1, d=0, a=2159/5000, alpha=pi/2)
        """
        return _reader("dh")(data, name=name, exact=exact, tol=tol)

    @classmethod
    def from_file(cls, path, *, exact: bool = True, tol: float = DEFAULT_TOL) -> DHRobot:
        """Read a DH JSON file: :func:`workspace_sym.readers.read_dh_file`.

        Parameters
        ----------
        path : str or path
            The JSON file.
        exact, tol
            As for :func:`workspace_sym.readers.read_dh`.

        Returns
        -------
        DHRobot
            The robot, named after the file unless the file gives a ``"name"``.

        Raises
        ------
        DHTableError, UnknownNameError, JointLimitError, ExpressionError, InvalidParameterError
            As for :func:`workspace_sym.readers.read_dh_file`.
        """
        return _reader("dh_file")(path, exact=exact, tol=tol)

    @classmethod
    def from_urdf(cls, path, *, base_link: str | None = None, tip_link: str | None = None, exact: bool = True,
                  tol: float = DEFAULT_TOL, packages: dict | None = None, xacro_args: dict | None = None) -> DHRobot:
        """The serial chain from ``base_link`` to ``tip_link`` of a URDF file, as a DH robot.

        Every chain of revolute and prismatic joints has a standard DH table
        once constant base and tool transforms are allowed; it is extracted
        exactly, and ``fk()`` equals the URDF's own forward kinematics.  See
        :func:`workspace_sym.readers.read_urdf` (needs the ``urdf`` extra, yourdfpy).
        The file is read as data; only a file named ``*.xacro`` is expanded (the
        ``xacro`` extra, ``packages`` naming the directories of its
        ``$(find pkg)``, ``xacro_args`` the values of its ``$(arg name)``),
        which runs the code it holds: expand only files you would run.

        Parameters
        ----------
        path, base_link, tip_link, exact, tol, packages, xacro_args
            As for :func:`workspace_sym.readers.read_urdf`.

        Returns
        -------
        DHRobot
            Standard DH with ``base`` and ``tool``.

        Raises
        ------
        URDFError, JointLimitError, InvalidParameterError
            As for :func:`workspace_sym.readers.read_urdf`.
        """
        return _reader("urdf")(path, base_link=base_link, tip_link=tip_link, exact=exact, tol=tol,
                               packages=packages, xacro_args=xacro_args)

    @classmethod
    def from_mjcf(cls, path, *, base_link: str | None = None, tip_link: str | None = None, exact: bool = True,
                  tol: float = DEFAULT_TOL) -> DHRobot:
        """The chain of bodies ``base_link -> tip_link`` of a MuJoCo file: :func:`workspace_sym.readers.read_mjcf`.

        Parameters
        ----------
        path, base_link, tip_link, exact, tol
            As for :func:`workspace_sym.readers.read_mjcf`.

        Returns
        -------
        DHRobot
            Standard DH with ``base`` and ``tool``.

        Raises
        ------
        MJCFError, JointLimitError, InvalidParameterError
            As for :func:`workspace_sym.readers.read_mjcf`.
        """
        return _reader("mjcf")(path, base_link=base_link, tip_link=tip_link, exact=exact, tol=tol)

    # ------------------------------------------------------------------ basics
    @property
    def n(self) -> int:
        """Number of joints.

        Returns
        -------
        int
            The number of rows of the table.
        """
        return len(self.joints)

    @property
    def q(self) -> tuple[sp.Symbol, ...]:
        """Joint variables in order.

        Returns
        -------
        tuple of sympy.Symbol
            The variable of each joint, from the base out.
        """
        return tuple(j.variable for j in self.joints)

    @property
    def symbols(self) -> set[sp.Symbol]:
        """Symbolic constants of the table (lengths, offsets).

        Returns
        -------
        set of sympy.Symbol
            The free symbols of the DH fields other than the joint variables (base and tool not included).
        """
        out = set()
        for j in self.joints:
            for e in (j.theta, j.d, j.a, j.alpha):
                out |= e.free_symbols
        return out - set(self.q)

    def __repr__(self) -> str:
        return f"DHRobot({self.name!r}, {self.n} joints, {self.convention} DH)"

    def problem_fields(self) -> dict:
        """Everything that decides this robot's kinematics and limits, by name, for the fingerprint of a stored
        or resumed run (:class:`~workspace_sym.interval.fingerprint.Fingerprint`): every DH entry and joint
        type (offsets are in ``theta`` and ``d``), the limits, the convention, base, tool, default parameter
        values, units and the chop tolerance.  The name is left out: it changes no box.

        Returns
        -------
        dict
            Each field by its name (``"robot table"``, ``"robot limits"``, ...): lists, tuples, SymPy objects,
            strings, numbers or None.

        Examples
        --------
        >>> a = DHRobot([DHJoint.revolute(1, a=1, limits=(-1, 1))])
        >>> b = DHRobot([DHJoint.revolute(1, a=1, limits=(-1, 2))])
        >>> [k for k in a.problem_fields() if a.problem_fields()[k] != b.problem_fields()[k]]
        ['robot limits']
        """
        return {"robot table": [(j.kind, j.variable, j.theta, j.d, j.a, j.alpha) for j in self.joints],
                "robot limits": [j.limits for j in self.joints],
                "robot convention": self.convention,
                "robot base": self.base, "robot tool": self.tool,
                "robot parameters": sorted(self.parameters.items(), key=lambda item: str(item[0])),
                "robot units": self.units, "robot chop_tol": self.chop_tol}

    def row_matrix(self, k: int) -> sp.Matrix:
        """``A_k``, the DH matrix of row ``k`` (1-based), so that ``T_0^k = T_0^(k-1) A_k`` (no base or tool).

        Parameters
        ----------
        k : int
            The row, 1 to :attr:`n`.

        Returns
        -------
        sympy.Matrix
            The 4x4 transform, its floats below ``chop_tol`` set to zero when the robot has one.

        Raises
        ------
        InvalidParameterError
            When ``k`` is outside 1 to :attr:`n`.
        """
        if not 1 <= k <= self.n:
            raise InvalidParameterError(f"k must be between 1 and {self.n}; got {k}", parameter="k")
        j = self.joints[k - 1]
        A = dh_matrix(j.theta, j.d, j.a, j.alpha, convention=self.convention)
        return A if self.chop_tol is None else chop(A, self.chop_tol)

    # ------------------------------------------------------------------ forward kinematics
    def raw_fk(self) -> sp.Matrix:
        """The product of base, ``A_1`` to ``A_n`` and tool, unsimplified (a reference for :meth:`fk`).

        Returns
        -------
        sympy.Matrix
            The 4x4 product.
        """
        T = self._raw_frames[-1]
        return matrix_product(T, self.tool) if self.tool is not None else T

    @cached_property
    def _raw_frames(self) -> tuple[sp.Matrix, ...]:
        """``base A_1 ... A_k`` for ``k = 0 .. n``, multiplied out with no simplification."""
        T = self.base if self.base is not None else sp.eye(4)
        out = [T]
        for k in range(1, self.n + 1):
            check_budget(f"the raw product up to joint {k}")
            T = matrix_product(T, self.row_matrix(k))
            out.append(T)
        return tuple(out)

    @cached_property
    def transforms(self) -> tuple[sp.Matrix, ...]:
        """The transforms ``T_0^1`` to ``T_0^n`` of the DH table alone (no base, no tool), in textbook form."""
        out = []
        T = sp.eye(4)
        with derivation(f"forward kinematics of {self.name}"):
            for k in range(self.n):
                check_budget(f"T_0^{k + 1}")
                T = textbook_matrix(matrix_product(T, self.row_matrix(k + 1)))
                out.append(T)
        return tuple(out)

    @cached_property
    def _frames(self) -> tuple[sp.Matrix, ...]:
        """Frames 0..n in the world frame: ``base T_0^k`` (the tool is not included)."""
        frames = (sp.eye(4),) + self.transforms
        with derivation(f"forward kinematics of {self.name} (base)"):
            if self.base is not None:
                frames = tuple(textbook_matrix(matrix_product(self.base, T)) for T in frames)
            return tuple(self._dusted(_no_longer(T, raw)) for T, raw in zip(frames, self._raw_frames))

    def _dusted(self, T: sp.Matrix) -> sp.Matrix:
        """``T`` without the float coefficients below ``chop_tol`` that products of floats leave (``1.7e-17``
        where two float terms should cancel); ``T`` itself for a robot without one."""
        return T if self.chop_tol is None else chop(T, self.chop_tol)

    @cached_property
    def _tip(self) -> sp.Matrix:
        T = self._frames[-1]
        if self.tool is None:
            return T
        with derivation(f"forward kinematics of {self.name} (tool)"):
            return self._dusted(_no_longer(textbook_matrix(matrix_product(T, self.tool)), self.raw_fk()))

    def fk(self, k=None, *, parameters: dict | None = None) -> sp.Matrix:
        """``base T_0^k``, with the tool transform appended for ``k = n`` (the default).

        ``k = 0`` is the base transform (the identity without one).  A list of
        ``n`` joint values instead of ``k`` gives the pose there:
        :meth:`fk_at`.

        Parameters
        ----------
        k : int, sequence or None
            The frame, 0 to :attr:`n` (None, the default: :attr:`n`, with the tool); or a configuration (list,
            tuple, array or matrix of :attr:`n` joint values).
        parameters : dict, optional
            With a configuration only: as for :meth:`fk_at`.

        Returns
        -------
        sympy.Matrix
            The 4x4 transform in textbook form; at a configuration, the pose there.

        Raises
        ------
        InvalidParameterError
            When ``k`` is neither a frame number from 0 to :attr:`n` nor a configuration, or ``parameters`` is
            given without a configuration (and as for :meth:`fk_at`).
        SymbolicError
            When the derivation fails, or runs out of its budget (:class:`~workspace_sym.errors.SymbolicBudgetError`).
        """
        if isinstance(k, (list, tuple, np.ndarray, sp.MatrixBase)):
            return self.fk_at(k, parameters=parameters)
        if parameters is not None:
            raise InvalidParameterError("parameters apply to a configuration: fk(q, parameters=...) with q a list of "
                                        f"{self.n} joint values", parameter="parameters")
        k = self.n if k is None else k
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
            raise InvalidParameterError(f"k must be a frame number from 0 to {self.n} or a configuration (a list of "
                                        f"{self.n} joint values); got {k!r:.60}", parameter="k")
        if not 0 <= k <= self.n:
            raise InvalidParameterError(f"k must be between 0 and {self.n}; got {k}")
        return self._tip if k == self.n else self._frames[k]

    @property
    def position(self) -> sp.Matrix:
        """Position of the end-effector (tool point), a 3x1 matrix.

        Returns
        -------
        sympy.Matrix
            The last column's first three entries of :meth:`fk`.
        """
        return self.fk()[:3, 3]

    @property
    def rotation(self) -> sp.Matrix:
        """Orientation of the end-effector (tool frame), a 3x3 matrix.

        Returns
        -------
        sympy.Matrix
            The rotation block of :meth:`fk`.
        """
        return self.fk()[:3, :3]

    # ------------------------------------------------------------------ Jacobians
    def _parameter_twists(self, i: int, frames=None) -> dict:
        """Unit twists of the four DH parameters of row ``i`` (0-based), in the world frame (or in the frame
        that ``frames``, the frames 0..n expressed in it, are given in).

        ``{"theta": ("R", axis, point), "d": ("P", axis), ...}``: the motion of
        the tool frame per unit increase of that parameter, all others fixed.
        Standard DH, ``T_i = T_(i-1) Rz(theta) Tz(d) Tx(a) Rx(alpha)``: theta and d act
        along ``z_(i-1)`` through ``o_(i-1)``, a and alpha along ``x_i`` through ``o_i``.
        Modified DH, ``T_i = T_(i-1) Rx(alpha) Tx(a) Rz(theta) Tz(d)``: alpha and a act
        along ``x_(i-1)`` through ``o_(i-1)``, theta and d along ``z_i`` through ``o_i``.
        """
        frames = self._frames if frames is None else frames
        F0, F1 = frames[i], frames[i + 1]
        x0, z0, o0 = F0[:3, 0], F0[:3, 2], F0[:3, 3]
        x1, z1, o1 = F1[:3, 0], F1[:3, 2], F1[:3, 3]
        if self.convention == "standard":
            return {"theta": ("R", z0, o0), "d": ("P", z0), "a": ("P", x1), "alpha": ("R", x1, o1)}
        return {"alpha": ("R", x0, o0), "a": ("P", x0), "theta": ("R", z1, o1), "d": ("P", z1)}

    @cached_property
    def geometric_jacobian(self) -> sp.Matrix:
        """6 x n geometric Jacobian ``[v; omega] = J q_dot`` of the tool point, column by column.

        Column ``k`` is the chain rule over every DH entry that depends on ``q_k``:
        ``sum d(entry)/d(q_k) * twist(entry)``, with the revolute twist
        ``[u x (p - o); u]`` and the prismatic one ``[u; 0]``
        (:meth:`_parameter_twists`).  For the usual ``theta_k = q_k + offset`` this is
        the textbook ``[z_(k-1) x (p - o_(k-1)); z_(k-1)]``; a reversed joint
        (``theta_k = -q_k``) or a scaled one (``d_k = 2 q_k``) gets the factor
        ``-1`` or ``2``, and any other dependence its derivative.
        """
        p = self.position
        twists = [self._parameter_twists(i) for i in range(self.n)]
        with derivation(f"geometric Jacobian of {self.name}"):
            return self._jacobian_columns(p, twists)

    def _jacobian_columns(self, p, twists) -> sp.Matrix:
        cols = []
        for q in self.q:
            check_budget(f"the Jacobian column of {q}")
            col = sp.zeros(6, 1)
            for joint, tw in zip(self.joints, twists):
                for name in ("theta", "d", "a", "alpha"):
                    rate = sp.diff(getattr(joint, name), q)
                    if rate == 0:
                        continue
                    kind, u, *o = tw[name]
                    if kind == "R":
                        unit = sp.Matrix.vstack(_cross(u, p - o[0]), u)
                    else:
                        unit = sp.Matrix.vstack(u, sp.zeros(3, 1))
                    col += rate * unit
            cols.append([textbook(e) for e in col])
        return sp.Matrix(cols).T

    @property
    def position_jacobian(self) -> sp.Matrix:
        """3 x n Jacobian of the end-effector position (top rows of the geometric one).

        Returns
        -------
        sympy.Matrix
            The first three rows of :attr:`geometric_jacobian`.
        """
        return self.geometric_jacobian[:3, :]

    def analytic_jacobian(self, convention: str = "zyz") -> AnalyticJacobian:
        """Analytic Jacobian for ZYZ Euler angles or roll-pitch-yaw (ZYX).

        The angle rows are obtained by differentiating the closed-form angles
        (``atan2`` of rotation entries), ``d atan2(Y, X) = (X dY - Y dX) / (X^2 + Y^2)``.

        ZYZ, ``R = Rz(phi) Ry(theta) Rz(psi)``: ``phi = atan2(r23, r13)``,
        ``theta = atan2(sqrt(r13^2 + r23^2), r33)``, ``psi = atan2(r32, -r31)``;
        singular where ``sin(theta) = 0`` (``r13 = r23 = 0``).
        Roll-pitch-yaw, ``R = Rz(phi) Ry(theta) Rx(psi)``: ``phi = atan2(r21, r11)``,
        ``theta = atan2(-r31, sqrt(r11^2 + r21^2))``, ``psi = atan2(r32, r33)``;
        singular where ``cos(theta) = 0`` (``r11 = r21 = 0``).  The angles of
        paper 004 (its section 6) are this set with the pitch of opposite sign.

        Parameters
        ----------
        convention : {"zyz", "rpy"}
            The Euler angles (default ``"zyz"``).

        Returns
        -------
        AnalyticJacobian
            The 6 x n Jacobian, the angles, and where the angles' rates are undefined.

        Raises
        ------
        UnknownNameError
            When ``convention`` is not one of :data:`EULER_CONVENTIONS`.
        SymbolicError
            When the derivation fails, or runs out of its budget (:class:`~workspace_sym.errors.SymbolicBudgetError`).
        """
        check_choice("convention", convention, EULER_CONVENTIONS)
        R = self.rotation
        with derivation(f"analytic ({convention}) Jacobian of {self.name}"):
            return self._analytic_jacobian(convention, R)

    def _analytic_jacobian(self, convention: str, R: sp.Matrix) -> AnalyticJacobian:
        if convention == "zyz":
            S = sp.sqrt(textbook(R[0, 2] ** 2 + R[1, 2] ** 2))
            pairs = [(R[1, 2], R[0, 2]), (S, R[2, 2]), (R[2, 1], -R[2, 0])]
            singular = textbook(R[0, 2] ** 2 + R[1, 2] ** 2)
            note = "ZYZ angles are undefined where sin(theta) = 0: r13 = r23 = 0 (z axes of base and tool parallel)."
        else:
            S = sp.sqrt(textbook(R[0, 0] ** 2 + R[1, 0] ** 2))
            pairs = [(R[1, 0], R[0, 0]), (-R[2, 0], S), (R[2, 1], R[2, 2])]
            singular = textbook(R[0, 0] ** 2 + R[1, 0] ** 2)
            note = "Roll-pitch-yaw angles are undefined where cos(pitch) = 0: r11 = r21 = 0 (gimbal lock)."
        angles = tuple(sp.atan2(Y, X) for Y, X in pairs)
        rows = []
        for Y, X in pairs:
            den = textbook(X ** 2 + Y ** 2)
            row = []
            for q in self.q:
                num = textbook(X * sp.diff(Y, q) - Y * sp.diff(X, q))
                row.append(_quotient(num, den))
            rows.append(row)
        J = sp.Matrix.vstack(self.position_jacobian, sp.Matrix(rows))
        return AnalyticJacobian(convention, J, angles, singular, note)

    def jacobian(self, kind: str = "geometric") -> sp.Matrix:
        """``"geometric"``, ``"position"`` or ``"analytic"`` (ZYZ) Jacobian.

        Parameters
        ----------
        kind : {"geometric", "position", "analytic"}
            Which Jacobian (default ``"geometric"``).

        Returns
        -------
        sympy.Matrix
            6 x n (geometric, analytic) or 3 x n (position).

        Raises
        ------
        UnknownNameError
            When ``kind`` is not one of the three.
        SymbolicError
            When the derivation fails, or runs out of its budget (:class:`~workspace_sym.errors.SymbolicBudgetError`).
        """
        check_choice("kind", kind, ("geometric", "position", "analytic"))
        if kind == "geometric":
            return self.geometric_jacobian
        if kind == "position":
            return self.position_jacobian
        return self.analytic_jacobian().J

    def singular_factors(self, kind: str = "geometric", *, multiplicity: bool = False) -> list:
        """Factors whose vanishing makes the Jacobian lose rank.

        For a square Jacobian of full generic rank, the factors of ``det J``;
        otherwise the factors common to every maximal (generic-rank) minor.
        The rows are first expressed in the frame of a middle link: rotating
        the rows changes neither the determinant nor the ideal of maximal
        minors, and the entries become much shorter (joint 1 drops out).

        Computed on the first call for each ``kind`` and kept (a 7-joint arm
        takes tens of seconds); nothing else computes it.  With ``multiplicity``
        the result is a list of ``(factor, m)`` pairs (see
        :func:`maximal_minor_factors`).

        Parameters
        ----------
        kind : {"geometric", "position", "analytic"}
            Which Jacobian (default ``"geometric"``).
        multiplicity : bool
            Return ``(factor, m)`` pairs (default False: the factors alone).

        Returns
        -------
        list
            The factors (SymPy expressions), shortest first, or ``(factor, m)`` pairs; ``[]`` when the rank never
            drops on a hypersurface.

        Raises
        ------
        UnknownNameError
            When ``kind`` is not one of the three.
        SymbolicError
            When the derivation fails, or runs out of its budget (:class:`~workspace_sym.errors.SymbolicBudgetError`).

        Examples
        --------
        >>> q3 = sp.Symbol("q3")
        >>> stanford = DHRobot([DHJoint.revolute(1, alpha=-sp.pi / 2),
        ...                     DHJoint.revolute(2, d=sp.Symbol("d2"), alpha=sp.pi / 2),
        ...                     DHJoint.prismatic(3, variable=q3), DHJoint.revolute(4, alpha=-sp.pi / 2),
        ...                     DHJoint.revolute(5, alpha=sp.pi / 2), DHJoint.revolute(6)])
        >>> stanford.singular_factors(multiplicity=True)
        [(q3, 2), (sin(theta2), 1), (sin(theta5), 1)]
        """
        check_choice("kind", kind, ("geometric", "position", "analytic"))
        cache = self.__dict__.setdefault("_singular_cache", {})
        if kind not in cache:
            J = self._middle_frame_jacobian(kind) if kind != "analytic" else self.jacobian(kind)
            with derivation(f"singular factors of the {kind} Jacobian of {self.name}"):
                cache[kind] = maximal_minor_factors(J, multiplicity=True)
        pairs = cache[kind]
        return list(pairs) if multiplicity else [f for f, _ in pairs]

    def _middle_frame_jacobian(self, kind: str) -> sp.Matrix:
        """The geometric or position Jacobian with its rows expressed in the frame of a middle link.

        Rotating the rows (``J -> diag(R, R) J``, ``R`` orthogonal) changes neither the
        rank, the maximal minors up to sign, nor the eigenvalues of ``J J^T``.  The reference
        point stays the tool point; only the axes turn.  The entries are derived in that frame
        from the start (:meth:`_frames_in`), products of the rows on either side of it, not by
        turning the world-frame Jacobian: joint 1 and the base drop out and no entry carries
        the whole chain (turning the world Jacobian of a 6-joint table with twists made its
        entries three times longer, and its minors cost 40 s).
        """
        J = self._middle_jacobian
        return J if kind == "geometric" else J[:3, :]

    @cached_property
    def _middle_jacobian(self) -> sp.Matrix:
        middle = self.n // 2
        with derivation(f"the geometric Jacobian of {self.name} in frame {middle}"):
            frames, tip = self._frames_in(middle)
            twists = [self._parameter_twists(i, frames) for i in range(self.n)]
            return self._jacobian_columns(tip[:3, 3], twists)

    def _frames_in(self, m: int) -> tuple[list, sp.Matrix]:
        """Frames 0..n of the table and the tool frame, expressed in frame ``m`` (``(T_0^m)^-1 T_0^k``), in
        textbook form: ``A_(m+1) ... A_k`` outward, ``A_m^-1 ... A_(k+1)^-1`` inward (no base: it drops out)."""
        frames: list = [None] * (self.n + 1)
        frames[m] = T = sp.eye(4)
        for k in range(m + 1, self.n + 1):
            check_budget(f"frame {k} in frame {m}")
            T = frames[k] = textbook_matrix(matrix_product(T, self.row_matrix(k)))
        T = frames[m]
        for k in range(m, 0, -1):
            check_budget(f"frame {k - 1} in frame {m}")
            T = frames[k - 1] = textbook_matrix(matrix_product(T, inverse_transform(self.row_matrix(k))))
        tip = frames[self.n] if self.tool is None else textbook_matrix(matrix_product(frames[self.n], self.tool))
        return frames, tip

    def characteristic_polynomial(self, kind: str = "geometric", lam: sp.Symbol | None = None) -> sp.Poly:
        """``det(lambda I - J J^T)`` of the geometric (6 x n) or position (3 x n) Jacobian.

        Coefficients are sums of squared minors of ``J`` in textbook form (see
        :func:`~workspace_sym.charpoly.gram_characteristic_polynomial`), computed on
        the Jacobian derived in a middle link's frame; print them with :meth:`to_str`
        or :meth:`to_latex`.  A minor not factored within its share of the budget
        stays the exact, unexpanded determinant of its submatrix
        (``sympy.Determinant``; :func:`eigenvalues_from_charpoly` evaluates it).  Kept
        after the first call for each ``kind``.

        Parameters
        ----------
        kind : {"geometric", "position"}
            Which Jacobian (default ``"geometric"``).
        lam : sympy.Symbol, optional
            The polynomial's variable; None (the default) is ``Symbol("lambda")``.

        Returns
        -------
        sympy.Poly
            The monic polynomial in ``lam`` of degree 6 (geometric) or 3 (position), over the domain ``EX``.

        Raises
        ------
        UnknownNameError
            When ``kind`` is neither ``"geometric"`` nor ``"position"``.
        SymbolicError
            When the derivation fails, or runs out of its budget (:class:`~workspace_sym.errors.SymbolicBudgetError`).

        Examples
        --------
        >>> arm = DHRobot([DHJoint.revolute(1, a=sp.Symbol("a1")), DHJoint.revolute(2, a=sp.Symbol("a2"))])
        >>> p = arm.characteristic_polynomial("position")
        >>> arm.to_str(p.all_coeffs()[2])
        'a1**2*a2**2*s2**2'
        """
        check_choice("kind", kind, ("geometric", "position"))
        cache = self.__dict__.setdefault("_charpoly_cache", {})
        if kind not in cache:
            J = self._middle_frame_jacobian(kind)
            with derivation(f"characteristic polynomial of J J^T ({kind} Jacobian of {self.name})"):
                cache[kind] = gram_characteristic_polynomial(J, sp.Symbol("lambda"))
        poly = cache[kind]
        return poly if lam is None else sp.Poly.from_list(poly.all_coeffs(), lam, domain="EX")

    # ------------------------------------------------------------------ printing
    def placement(self) -> dict:
        """The constant transforms around the DH table that :meth:`fk` multiplies in, those that are not the
        identity: ``fk() = base T_0^n tool``.

        Returns
        -------
        dict
            ``{"base": matrix, "tool": matrix}`` with only the transforms the robot has and that are not the
            identity (empty for a bare DH table), base first.
        """
        identity = sp.eye(4)
        return {name: M for name, M in (("base", self.base), ("tool", self.tool))
                if M is not None and M != identity}

    def lengths(self) -> tuple:
        """The robot's numeric lengths: the ``d`` and ``a`` of its table and the translations of its base and tool,
        without sign, zeros and repeats (what :meth:`in_lengths` scales a factor to).

        Returns
        -------
        tuple of sympy.Rational
            The distinct positive lengths, smallest first (symbolic ones left out).
        """
        values = [v for j in self.joints for v in (j.d, j.a)]
        values += [M[i, 3] for M in self.placement().values() for i in range(3)]
        return tuple(sorted({abs(v) for v in map(sp.sympify, values) if v.is_Rational and v != 0}))

    def in_lengths(self, factor):
        """A singular factor (defined up to a constant) printed in this robot's lengths: the UR5's
        ``8500*c2 + 7845*c23 - 1893*s234`` as ``0.425 c2 + 0.39225 c23 - 0.09465 s234``
        (:func:`~workspace_sym.symbolic.in_lengths` with :meth:`lengths`).  For printing; compute with the factor.

        Parameters
        ----------
        factor : SymPy expression
            A factor such as one of :meth:`singular_factors`.

        Returns
        -------
        SymPy expression
            A positive rational multiple of ``factor`` (``factor`` itself when no multiple reads in lengths).
        """
        return in_lengths(factor, self.lengths())

    def fk_name(self, *, latex: bool = False) -> str:
        """What :meth:`fk` is, as a label: ``T_0^6`` for a bare DH table, ``base · T_0^6 · tool`` (or the part
        of it the robot has) when a base or tool transform (:meth:`placement`) is multiplied in.

        Parameters
        ----------
        latex : bool, default False
            LaTeX (``\\mathrm{base}\\, T_0^{6}\\, \\mathrm{tool}``) instead of text.

        Returns
        -------
        str
            The label.
        """
        parts = self.placement()
        chain = f"T_0^{{{self.n}}}" if latex else f"T_0^{self.n}"
        words = (["base"] if "base" in parts else []) + [chain] + (["tool"] if "tool" in parts else [])
        if latex:
            return r"\,".join(w if w == chain else rf"\mathrm{{{w}}}" for w in words)
        return " · ".join(words)

    def shorthand(self, expr) -> sp.Expr:
        """``expr`` as printed: ``c_i``, ``s_ij`` symbols for this robot's joint variables, lengths given as
        decimals shown as decimals (:func:`~workspace_sym.symbolic.decimal_form`).

        Parameters
        ----------
        expr : SymPy expression or matrix
            A result of this robot (text is read by :func:`~workspace_sym.expressions.parse_expr`).

        Returns
        -------
        sympy.Basic or sympy.Matrix
            The expression for printing, in ``c_i``, ``s_ij`` symbols.

        Raises
        ------
        ExpressionError
            When ``expr`` is text that cannot be read, or of another type.
        """
        return decimal_form(shorthand(expr, self.q))

    def to_str(self, expr) -> str:
        """Textbook string with shorthand, e.g. ``c1*(a1 + a2*c2 + a3*c23 + d5*s234)``.

        Parameters
        ----------
        expr : SymPy expression or matrix
            A result of this robot (text is read by :func:`~workspace_sym.expressions.parse_expr`).

        Returns
        -------
        str
            The string (:func:`~workspace_sym.symbolic.shorthand_str`).

        Raises
        ------
        ExpressionError
            When ``expr`` is text that cannot be read, or of another type.
        """
        return shorthand_str(expr, self.q)

    def to_latex(self, expr, *, short: bool = True) -> str:
        """LaTeX of any result, with ``c_{23}`` shorthand when ``short``.

        Parameters
        ----------
        expr : SymPy expression or matrix
            A result of this robot (text is read by :func:`~workspace_sym.expressions.parse_expr`).
        short : bool
            Use the shorthand (default True).

        Returns
        -------
        str
            The LaTeX (:func:`~workspace_sym.symbolic.shorthand_latex`).

        Raises
        ------
        ExpressionError
            When ``expr`` is text that cannot be read, or of another type.
        """
        return shorthand_latex(expr, self.q, short=short)

    # ------------------------------------------------------------------ numbers
    def substitute(self, expr, parameters: dict | None = None):
        """``expr`` with the default (or given) numeric parameters substituted.

        Parameters
        ----------
        expr : SymPy expression or matrix
            The expression (text is read by :func:`~workspace_sym.expressions.parse_expr`).
        parameters : dict, optional
            Values by symbol or name, used instead of the robot's defaults (not merged with them); None (the
            default) uses :attr:`parameters`.  Python floats become SymPy floats; other values are substituted
            as given.

        Returns
        -------
        sympy.Basic or sympy.Matrix
            The expression with the values in place (matrices come back immutable).

        Raises
        ------
        ExpressionError
            When ``expr`` is text that cannot be read, or of another type.
        """
        params = self.parameters if parameters is None else {sp.Symbol(str(k)): v for k, v in parameters.items()}
        return as_sympy(expr).xreplace({k: sp.Float(v) if isinstance(v, float) else v for k, v in params.items()})

    def numeric(self, expr, parameters: dict | None = None):
        """Vectorised evaluator of ``expr`` over configurations (see :func:`numeric_function`).

        Parameters
        ----------
        expr : SymPy expression or matrix
            The expression, in the joint variables and the robot's symbols.
        parameters : dict, optional
            As for :meth:`substitute`.

        Returns
        -------
        callable
            ``f(q)``, as :func:`numeric_function` returns it, over the joint variables :attr:`q`.

        Raises
        ------
        InvalidParameterError
            When a symbol other than the joint variables has no value.
        """
        return numeric_function(self.substitute(expr, parameters), self.q)

    @cached_property
    def fk_numeric(self):
        """``f(q) -> (N, 4, 4)`` array of ``T_0^n`` for ``q`` of shape ``(N, n)``, default parameters."""
        return self.numeric(self.fk())

    @cached_property
    def jacobian_numeric(self):
        """``f(q) -> (N, 6, n)`` geometric Jacobians, default parameters."""
        return self.numeric(self.geometric_jacobian)

    def reach(self, *, delta: float, **options):
        """Certified position workspace within the joint limits: :func:`workspace_sym.serial.reach` (registered
        in :data:`ENGINES` by the engine, which builds on this module).

        Parameters
        ----------
        delta : float
            Undecided task boxes whose size is at most ``delta`` become boundary boxes.
        **options
            The keywords of :func:`workspace_sym.serial.reach`.

        Returns
        -------
        workspace_sym.serial.ReachResult
        """
        return _registered(ENGINES, "ENGINES", "reach", "reach engine")(self, delta=delta, **options)

    def codegen(self, *, out, lang: str = "c", prefix: str = "") -> list:
        """Write C for ``fk`` and ``jacobian`` into directory ``out``: :func:`workspace_sym.codegen.write_code`.

        Parameters
        ----------
        out, lang, prefix
            As for :func:`workspace_sym.codegen.write_code`.

        Returns
        -------
        list of pathlib.Path
            The paths written, header first.

        Raises
        ------
        UnknownNameError, WorkspaceError, InvalidParameterError
            As for :func:`workspace_sym.codegen.write_code`.
        """
        from .codegen import write_code  # one way: codegen builds on this module

        return write_code(self, out, lang=lang, prefix=prefix)

    def joint_limits(self, default: float = math.pi) -> np.ndarray:
        """``(n, 2)`` float array of limits; unlimited joints get ``[-default, default]``.

        Parameters
        ----------
        default : float
            Half the range given to an unlimited joint, revolute or prismatic (default ``pi``).

        Returns
        -------
        numpy.ndarray
            Lower and upper limit of each joint, radians or length units.
        """
        out = np.empty((self.n, 2))
        for k, j in enumerate(self.joints):
            out[k] = (-default, default) if j.limits is None else (float(j.limits[0]), float(j.limits[1]))
        return out

    # ------------------------------------------------------------------ display (Jupyter)
    def textbook(self, expr):
        """``expr`` (matrix, expression, polynomial, list) printing in textbook shorthand: ``c_{1}``, ``s_{234}``.

        Still a SymPy expression of the joint variables: it substitutes,
        differentiates and evaluates as before, and a notebook typesets it
        (:func:`workspace_sym.symbolic.textbook_form`).

        Parameters
        ----------
        expr : SymPy expression, matrix, polynomial, list or tuple
            The expression (SymPy objects and numbers, not text).

        Returns
        -------
        sympy.Basic or sympy.Matrix
            The same mathematics, printing in shorthand; a list or tuple becomes a SymPy ``Tuple``.

        Examples
        --------
        >>> robot = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=1)])
        >>> robot.textbook(robot.position)
        Matrix([
        [c1 + c12],
        [s1 + s12],
        [       0]])
        >>> robot.textbook(robot.singular_factors("position"))
        (s2,)
        """
        return textbook_form(expr, self.q)

    # ------------------------------------------------------------------ a configuration, the other convention
    def fk_at(self, q, *, parameters: dict | None = None) -> sp.Matrix:
        """``fk()`` at the configuration ``q`` (``n`` joint values: radians, or lengths for prismatic joints) with
        the default numeric parameters, or ``parameters``, substituted; exact values give an exact pose.

        Parameters
        ----------
        q : sequence
            :attr:`n` joint values: numbers, NumPy scalars, SymPy numbers or text (read by
            :func:`~workspace_sym.expressions.parse_expr`).
        parameters : dict, optional
            As for :meth:`substitute`.

        Returns
        -------
        sympy.Matrix
            The 4x4 pose.

        Raises
        ------
        InvalidParameterError
            When ``q`` does not hold :attr:`n` values, or a value is not a finite real number.
        ExpressionError
            When a value is text that cannot be read, or of another type.
        SymbolicError
            When the derivation of :meth:`fk` fails, or runs out of its budget.

        Examples
        --------
        >>> robot = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=1)])
        >>> robot.fk_at([0, sp.pi / 2])[:2, 3].T
        Matrix([[1, 1]])
        """
        values = list(q)
        if len(values) != self.n:
            raise InvalidParameterError(f"q must hold {self.n} joint values (one per joint); got {len(values)}",
                                        parameter="q")
        config = {}
        for variable, value in zip(self.q, values):
            value = as_sympy(value.item() if isinstance(value, np.generic) else value, "q")
            if not (isinstance(value, sp.Expr) and value.is_number and is_finite_value(value)):
                raise InvalidParameterError(f"q: the value of {variable} must be a finite real number; got "
                                            f"{value!r:.60}", parameter="q")
            config[variable] = value
        return self.substitute(self.fk().xreplace(config), parameters)

    def to_convention(self, convention: str) -> DHRobot:
        """The same robot in the other DH convention (``"standard"`` or ``"modified"``), FK identical.

        ``Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)`` rows regrouped as
        ``Rx(alpha_(i-1)) Tx(a_(i-1)) Rz(theta_i) Tz(d_i)`` (``Tx`` and ``Rx``
        commute): standard to modified moves ``a`` and ``alpha`` one row down,
        the last pair into the tool; modified to standard moves them one row
        up, the first pair into the base.  The robot itself when it is already
        in ``convention``.

        Parameters
        ----------
        convention : {"standard", "modified"}
            The convention wanted.

        Returns
        -------
        DHRobot
            A new robot (or this one), its input notes saying it was converted.

        Raises
        ------
        UnknownNameError
            When ``convention`` is not one of :data:`CONVENTIONS`.
        """
        check_choice("convention", convention, CONVENTIONS)
        if convention == self.convention:
            return self
        J = self.joints
        pairs = [(j.a, j.alpha) for j in J]
        if convention == "modified":
            moved, (a, alpha) = [(sp.Integer(0), sp.Integer(0)), *pairs[:-1]], pairs[-1]
            end = dh_matrix(0, 0, a, alpha)                       # Tx(a_n) Rx(alpha_n), before the tool
            base, tool = self.base, end if self.tool is None else end * self.tool
        else:
            moved, (a, alpha) = [*pairs[1:], (sp.Integer(0), sp.Integer(0))], pairs[0]
            start = dh_matrix(0, 0, a, alpha, convention="modified")   # Rx(alpha_0) Tx(a_0), after the base
            base, tool = start if self.base is None else self.base * start, self.tool
        joints = [replace(j, a=a, alpha=alpha) for j, (a, alpha) in zip(J, moved)]
        identity = sp.eye(4)
        return DHRobot(joints, convention=convention, name=self.name, parameters=self.parameters, units=self.units,
                       base=None if base == identity else base, tool=None if tool == identity else tool,
                       input_notes=(*self.input_notes, f"converted from {self.convention} to {convention} DH"),
                       chop_tol=self.chop_tol)


_THREADS = max(1, os.cpu_count() or 1)
_CHUNK_MIN = 50_000


def numeric_function(expr, variables):
    """Vectorised numpy function generated from a SymPy expression or matrix.

    The returned callable takes ``q`` of shape ``(N, n)`` (or ``(n,)``) and returns
    an array of shape ``(N, *expr.shape)`` (or ``expr.shape``).  Common
    subexpressions are shared, so a million configurations cost one pass.

    Parameters
    ----------
    expr : SymPy expression or matrix
        The expression; its only free symbols may be ``variables``.
    variables : sequence of sympy.Symbol
        The variables, in the order of the columns of ``q``.

    Returns
    -------
    callable
        ``f(q)`` as above; it raises :class:`~workspace_sym.errors.InvalidParameterError` when the last
        dimension of ``q`` is not ``len(variables)``.  Its attribute ``expr`` is the matrix it evaluates.

    Raises
    ------
    InvalidParameterError
        When ``expr`` has a free symbol that is not one of ``variables``.

    Examples
    --------
    >>> t = sp.symbols("t1 t2")
    >>> f = numeric_function(sp.Matrix([sp.cos(t[0]) + t[1]]), t)
    >>> f(np.array([[0.0, 1.0], [np.pi, 0.0]]))[:, 0, 0]
    array([ 2., -1.])
    """
    M = as_matrix(expr, "expr")
    free = M.free_symbols - set(variables)
    if free:
        raise InvalidParameterError(
            f"parameters: no numeric value for {sorted(map(str, free))}; pass parameters={{...}}"
        )
    shape = M.shape
    entries = list(M)
    fn = sp.lambdify(list(variables), entries, modules="numpy", cse=True)

    def evaluate(q):
        q = np.asarray(q, dtype=float)
        single = q.ndim == 1
        q2 = np.atleast_2d(q)
        if q2.shape[-1] != len(variables):
            raise InvalidParameterError(f"q: expected {len(variables)} joint values per row; got shape {q.shape}")
        # Contiguous joint columns in, contiguous entry rows out: strided access
        # costs as much as the arithmetic at a million configurations.
        cols = np.ascontiguousarray(q2.T)
        out = np.empty((len(entries), q2.shape[0]))

        def fill(lo, hi):
            for k, v in enumerate(fn(*cols[:, lo:hi])):
                out[k, lo:hi] = v

        n = q2.shape[0]
        workers = min(_THREADS, n // _CHUNK_MIN) if n >= 2 * _CHUNK_MIN else 1
        if workers > 1:
            # numpy ufuncs release the GIL: large batches run on every core.
            bounds = np.linspace(0, n, workers + 1).astype(int)
            with ThreadPoolExecutor(workers) as pool:
                list(pool.map(fill, bounds[:-1], bounds[1:]))
        else:
            fill(0, n)
        out = np.moveaxis(out.reshape(shape + (n,)), -1, 0)
        return out[0] if single else out

    evaluate.expr = M
    return evaluate


def _quotient(num: sp.Expr, den: sp.Expr) -> sp.Expr:
    """``num / den`` with common polynomial factors cancelled (trig functions as generators)."""
    if num == 0:
        return sp.Integer(0)
    # cancel() with sqrt(2), sqrt(3) coefficients (constant angles such as pi/12) or a
    # square root in the denominator can take minutes: keep the plain quotient there.
    if algebraic_constants([num, den]) or any(not p.exp.is_Integer for p in den.atoms(sp.Pow)):
        return num / den
    return sp.factor_terms(sp.cancel(num / den))

