"""The DH file reader: JSON tables into exact :class:`~workspace_sym.kinematics.DHRobot` models.

The format is that of ``docs/cli.md``, section "DH files".  Beside :mod:`.urdf`
and :mod:`.mjcf`, the other readers of robot descriptions: this module owns
the file format (fields, angle units, the snapping of floats to exact numbers,
base and tool transforms); :mod:`workspace_sym.kinematics` owns the model and
its derivations.  ``DHRobot.from_dict`` and ``DHRobot.from_file`` delegate
here, through the registry :data:`workspace_sym.kinematics.READERS`.
"""

from __future__ import annotations

import math
from pathlib import Path

import sympy as sp

from ..errors import DHTableError, JointLimitError, check_choice
from ..expressions import check_joint_limits, parse_angle, parse_expr, read_symbol
from ..files import read_json
from ..kinematics import CONVENTIONS, JOINT_KINDS, DHJoint, DHRobot, check_joint_count, parameter_value
from ..snap import DEFAULT_TOL, Snapper
from ..transforms import xyz_rpy

__all__ = ["read_dh", "read_dh_file"]


def read_dh(data: dict, *, name: str = "robot", exact: bool = True, tol: float = DEFAULT_TOL) -> DHRobot:
    """Build a robot from the DH-file dictionary (``docs/cli.md``, section "DH files").

    ``{"convention": "standard" | "modified", "angles": "degrees" | "radians",
    "joints": [{"type": "R" | "P", "theta": ..., "d": ..., "a": ..., "alpha": ...,
    "limits": [lo, hi]}], "parameters": {"a2": 0.25}, "base": ..., "tool": ...}``.
    ``base`` and ``tool`` (optional) are ``{"xyz": [x, y, z], "rpy": [roll, pitch, yaw]}``
    (rotation ``Rz(yaw) Ry(pitch) Rx(roll)``, angles in the file's unit) or a 4 x 4 list;
    ``fk() = base T_0^n tool``.  Plain numbers for
    angles (theta offsets, alpha, revolute limits) are degrees unless
    ``"angles": "radians"``; expressions containing ``pi`` or symbols are radians.
    For a revolute joint ``theta`` is an offset added to ``theta{i}`` unless it
    already contains that variable; likewise ``d`` for a prismatic joint.

    Floats (JSON numbers with a decimal point) are made exact where they
    clearly are (:mod:`workspace_sym.snap`): an angle within ``tol`` radians of
    a multiple of ``pi/360`` becomes that multiple (``1.5707963267948966`` is
    ``pi/2``), a length the decimal it spells (``0.4318`` is ``2159/5000``);
    every replacement is listed in ``robot.input_notes``.  With ``exact=False``
    floats stay floats and the entries of each DH matrix below ``tol`` are
    chopped (``cos(1.5707963267948966) = 6e-17`` becomes 0).  Strings are read
    as written (``"0.4318"`` is already exact).

    Parameters
    ----------
    data : dict
        The DH description, as decoded from JSON.
    name : str
        The robot's name when ``data`` has no ``"name"`` (default ``"robot"``).
    exact : bool
        Make floats exact (default True); False keeps them and chops the DH matrices below ``tol``.
    tol : float
        The snapping (or chopping) tolerance, a finite number >= 0 (default
        :data:`~workspace_sym.snap.DEFAULT_TOL`).

    Returns
    -------
    DHRobot
        The robot, its input notes listing every float made exact.

    Raises
    ------
    DHTableError
        When ``data`` is not an object, ``joints`` is not a non-empty list of at most
        :data:`~workspace_sym.kinematics.MAX_JOINTS` rows, a row is not an object, has an unknown type, a
        missing or unknown field, ``parameters`` is not an object, ``base`` or ``tool`` is not a rigid transform,
        or the rows do not make a robot (a field without its variable, variables not distinct, a parameter that
        is a joint variable).
    UnknownNameError
        When ``convention`` or ``angles`` is not one of its values.
    JointLimitError
        When ``limits`` is not a pair, or a limit is not finite or not below the other.
    ExpressionError
        When a field's text cannot be read or a number is not finite, a ``variable`` is not a name, a parameter
        value is not a finite number, or, in degrees, a field adds a number without ``pi`` to a symbol.
    InvalidParameterError
        When ``tol`` is not a finite number >= 0.

    Examples
    --------
    >>> puma_alpha = {"angles": "radians", "joints": [{"d": 0, "a": 0, "alpha": 1.5707963267948966},
    ...                                               {"d": 0, "a": 0.4318, "alpha": 0.0}]}
    >>> robot = read_dh(puma_alpha)
    >>> [j.alpha for j in robot.joints], robot.joints[1].a
    ([pi/2, 0], 2159/5000)
    >>> robot.input_notes
    ('joint 1 alpha: 1.5707963267948966 -> pi/2', 'joint 2 a: 0.4318 -> 2159/5000')
    """
    snapper = Snapper(exact=exact, tol=tol)
    if not isinstance(data, dict):
        raise DHTableError(f"DH description must be a JSON object; got {type(data).__name__}")
    convention = data.get("convention", "standard")
    check_choice("convention", convention, CONVENTIONS)
    unit = data.get("angles", "degrees")
    check_choice("angles", unit, ("degrees", "radians"))
    degrees = unit == "degrees"
    rows = data.get("joints")
    if not isinstance(rows, list) or not rows:
        raise DHTableError(f"joints: expected a non-empty list of DH rows; got {rows!r}")
    check_joint_count(len(rows))                   # before reading 10,000 rows one by one
    joints = []
    for i, row in enumerate(rows, start=1):
        if not isinstance(row, dict):
            raise DHTableError(f"joint {i}: expected an object with type, theta, d, a, alpha; got {row!r}")
        kind = row.get("type", "R")
        if kind not in JOINT_KINDS:
            raise DHTableError(f"joint {i}: type must be 'R' or 'P'; got {kind!r}")
        required = ("d", "a", "alpha") if kind == "R" else ("theta", "a", "alpha")
        missing = [k for k in required if k not in row]
        if missing:
            raise DHTableError(f"joint {i}: missing field {missing[0]!r} (a DH row needs {', '.join(required)})")
        unknown = set(row) - {"type", "theta", "d", "a", "alpha", "limits", "variable"}
        if unknown:
            raise DHTableError(f"joint {i}: unknown field {sorted(unknown)[0]!r}")
        q = (read_symbol(row["variable"], f"joint {i} variable") if "variable" in row
             else sp.Symbol(f"theta{i}" if kind == "R" else f"d{i}"))
        a = _read_length(row["a"], f"joint {i} a", snapper)
        alpha = _read_angle(row["alpha"], f"joint {i} alpha", degrees, snapper)
        if kind == "R":
            theta = _read_angle(row.get("theta", 0), f"joint {i} theta", degrees, snapper)
            theta = theta if theta.has(q) else q + theta
            d = _read_length(row["d"], f"joint {i} d", snapper)
        else:
            theta = _read_angle(row["theta"], f"joint {i} theta", degrees, snapper)
            d = _read_length(row.get("d", 0), f"joint {i} d", snapper)
            d = d if d.has(q) else q + d
        limits = row.get("limits")
        if limits is not None:
            if not isinstance(limits, (list, tuple)) or len(limits) != 2:
                raise JointLimitError(f"joint {i} limits: expected [lower, upper]; got {limits!r}")
            if kind == "R":
                limits = tuple(_read_angle(v, f"joint {i} limits", degrees, snapper) for v in limits)
            else:
                limits = tuple(_read_length(v, f"joint {i} limits", snapper) for v in limits)
            check_joint_limits(i, *limits, shown=(row["limits"][0], row["limits"][1]))
        joints.append(DHJoint(kind, theta, d, a, alpha, q, limits))
    params = {}
    parameters = data.get("parameters") or {}
    if not isinstance(parameters, dict):
        raise DHTableError(f"parameters: expected an object such as {{\"a2\": 0.25}}; got {parameters!r:.60}")
    for k, v in parameters.items():
        params[read_symbol(k, "parameters")] = parameter_value(v, f"parameter {k}")
    base, tool = (_read_transform(data[key], key, degrees, snapper) if data.get(key) is not None else None
                  for key in ("base", "tool"))
    return DHRobot(joints, convention=convention, name=data.get("name", name), parameters=params,
               units=data.get("units", "m"), base=base, tool=tool, input_notes=snapper.notes,
               chop_tol=None if exact else snapper.tol)


def read_dh_file(path, *, exact: bool = True, tol: float = DEFAULT_TOL) -> DHRobot:
    """Read a DH JSON file (see :func:`read_dh` for ``exact`` and ``tol``); the robot is named after the file.

    Parameters
    ----------
    path : str or path
        The JSON file (UTF-8).
    exact, tol
        As for :func:`read_dh`.

    Returns
    -------
    DHRobot
        The robot, named after the file's stem unless the file gives a ``"name"``.

    Raises
    ------
    DHTableError
        When the file cannot be read or is not valid JSON (``parameter="path"``), and as for :func:`read_dh`.
    UnknownNameError, JointLimitError, ExpressionError, InvalidParameterError
        As for :func:`read_dh`.
    """
    path = Path(path)
    return read_dh(read_json(path, "path", error=DHTableError), name=path.stem, exact=exact, tol=tol)


def _read_transform(value, key: str, degrees: bool, snapper: Snapper | None = None) -> sp.Matrix:
    """``{"xyz": [x, y, z], "rpy": [r, p, y]}`` (``Rz(y) Ry(p) Rx(r)``, angles in the file's unit) or a 4 x 4 list.

    Floats go through ``snapper`` (see :func:`_read_angle`); the 3 x 3 block of a
    4 x 4 list snaps to the exact cosines of :meth:`Snapper.cosine`.
    """
    snapper = snapper if snapper is not None else Snapper()
    if isinstance(value, dict):
        unknown = set(value) - {"xyz", "rpy"}
        if unknown:
            raise DHTableError(f"{key}: unknown field {sorted(unknown)[0]!r} (expected 'xyz' and/or 'rpy')")
        xyz, rpy = value.get("xyz", [0, 0, 0]), value.get("rpy", [0, 0, 0])
        for field_, v in (("xyz", xyz), ("rpy", rpy)):
            if not isinstance(v, (list, tuple)) or len(v) != 3:
                raise DHTableError(f"{key} {field_}: expected a list of 3 numbers; got {v!r}")
        x, y, z = (_read_length(v, f"{key} xyz", snapper) for v in xyz)
        r, p, w = (_read_angle(v, f"{key} rpy", degrees, snapper) for v in rpy)
        return snapper.chop(xyz_rpy((x, y, z), (r, p, w)))
    if isinstance(value, (list, tuple)) and len(value) == 4 and all(isinstance(r, (list, tuple)) and len(r) == 4
                                                                   for r in value):
        return snapper.chop(sp.Matrix([[_read_length(v, f"{key} matrix", snapper, rotation=i < 3 and j < 3)
                                        for j, v in enumerate(row)] for i, row in enumerate(value)]))
    raise DHTableError(f"{key}: expected {{\"xyz\": [..], \"rpy\": [..]}} or a 4 x 4 list; got {value!r}")


def _read_angle(value, where: str, degrees: bool, snapper: Snapper) -> sp.Expr:
    """An angle field: a float (a JSON number with a point) is snapped by ``snapper``, anything else read as given."""
    if type(value) is float and math.isfinite(value):
        return snapper.angle(value, where, degrees=degrees)
    return parse_angle(value, where, degrees=degrees)


def _read_length(value, where: str, snapper: Snapper, *, rotation: bool = False) -> sp.Expr:
    """A length field (or a rotation entry): a float becomes the decimal it spells, anything else is read as given."""
    if type(value) is float and math.isfinite(value):
        return snapper.cosine(value, where) if rotation else snapper.length(value, where)
    return parse_expr(value, where)
