"""Serial chains of MuJoCo models (MJCF), turned into exact DH robots as URDF chains are.

An MJCF body sits at ``pos`` and an orientation (``quat``, ``euler``,
``axisangle``, ``xyaxes`` or ``zaxis``) in its parent body's frame; each of its
joints moves it, in document order, about (``hinge``) or along (``slide``)
``axis`` through ``pos``, both in the body's frame, by ``q - ref``.  So a body
is the constant transform ``Trans(pos) R`` followed, for each joint, by
``Trans(p) Motion(axis, q) Rot/Trans(axis, -ref) Trans(-p)``: a URDF chain of
fixed and moving joints, and :mod:`.chain` turns that into a
standard DH table with base and tool transforms, exactly as for a URDF file
(same snapping of floats, same notes).  A quaternion written to 6 decimals
or more that rounds an exact turn (``0.9659258 0.258819 0 0``: 30 degrees
about x) is read as that turn, with a note, and ``Rot(axis, -ref)`` and
``Trans(-p)`` stay two transforms, so that neither leaves float dust or a
16-digit decimal in the exact kinematics.  Angles are degrees unless
``<compiler angle="radian">``; ``eulerseq`` is honoured; joint attributes
come from ``<default>`` classes (``class``, ``childclass``) as in MuJoCo; a
joint is limited when ``limited="true"``, or ``"auto"`` (the default) with a
``range``.

The file is untrusted data: it is parsed with defusedxml
(:func:`workspace_sym.files.read_xml`), which refuses document type
declarations (entities) in every encoding; numbers are read strictly (a
decimal or exponent literal, finite, the expected count), and an error names
the parameter ``path``, the element and the attribute (the command line
shows ``path`` as ``--mjcf``).  ``<include>`` is refused.  Reading needs the
``urdf`` extra (defusedxml, and the transform helpers).
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import sympy as sp

from ..errors import MJCFError
from ..files import read_xml
from ..kinematics import DHRobot
from ..snap import DEFAULT_TOL, Snapper, snap_angle
from .chain import dh_robot

__all__ = ["read_mjcf"]

_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\Z")
_ORIENTATIONS = ("quat", "axisangle", "euler", "xyaxes", "zaxis")
_DEFAULT_CLASS = "main"


@dataclass(frozen=True, slots=True)
class _Limit:
    lower: float
    upper: float
    placeholder: bool = False     # an unlimited slide joint (URDF has no such joint): dropped after the extraction


@dataclass(frozen=True, slots=True)
class _Joint:
    """A URDF-shaped joint (what :func:`.chain.dh_robot` reads): a constant origin, then a motion."""

    name: str
    type: str
    origin: np.ndarray
    axis: tuple = (0.0, 0.0, 1.0)
    limit: _Limit | None = None


def read_mjcf(path, *, base_link: str | None = None, tip_link: str | None = None, exact: bool = True,
              tol: float = DEFAULT_TOL) -> DHRobot:
    """The serial chain ``base_link -> tip_link`` (body names) of an MJCF file as an exact DH robot.

    ``fk()`` is the pose of the tip body's frame in the base body's frame.

    Parameters
    ----------
    path : str or Path
        An MJCF file (read as untrusted data).
    base_link : str, optional
        The first body of the chain; default: the world body.
    tip_link : str, optional
        The last body; default: the one leaf body below ``base_link`` reached through a joint.
    exact, tol
        Snapping of floats, as for :func:`workspace_sym.readers.urdf.read_urdf`.

    Returns
    -------
    DHRobot
        Standard DH with ``base`` and ``tool``; hinge joints are revolute, slide joints prismatic.

    Raises
    ------
    MJCFError
        A file that cannot be read or is not a model this reader takes (``parameter="path"``; the message names
        the element and the attribute): a number that is not a plain literal, non-finite or of the wrong count,
        two orientations on one body, a zero axis, a ball or free joint on the chain, an unknown class,
        ``limited="true"`` without a range, ``<include>``, ``<frame>``, a document type; an unknown body or a
        chain that does not connect (``"base_link"``, ``"tip_link"``).
    JointLimitError
        A range whose lower end is not below its upper end.
    InvalidParameterError
        ``tol`` not a finite number >= 0.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> text = '''<mujoco model="arm"><worldbody>
    ...   <body name="upper"><joint type="hinge" axis="0 0 1" range="-150 150"/>
    ...     <body name="fore" pos="0.4 0 0"><joint axis="0 0 1"/>
    ...       <body name="tip" pos="0.3 0 0"/></body></body></worldbody></mujoco>'''
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "arm.xml"
    >>> _ = path.write_text(text)
    >>> robot = read_mjcf(path)
    >>> robot.joints[0]
    DHJoint(R: theta=theta1, d=0, a=2/5, alpha=0, limits=[-5*pi/6, 5*pi/6])
    >>> robot.to_str(robot.position[0])
    '0.4*c1 + 0.3*c12'
    """
    path = Path(path)
    root = _parse(path)
    compiler = {}
    for c in root.iter("compiler"):
        compiler.update(c.attrib)
    if compiler.get("coordinate", "local") != "local":
        raise MJCFError(f"path: <compiler coordinate={compiler['coordinate']!r}> is not supported (only "
                        "'local', the only value MuJoCo 2.3 and later accept)", parameter="path")
    angle = compiler.get("angle", "degree")
    if angle not in ("degree", "radian"):
        raise MJCFError(f"path: <compiler angle> must be 'degree' or 'radian'; got {angle!r}", parameter="path")
    seq = compiler.get("eulerseq", "xyz")
    if not re.fullmatch(r"[xyzXYZ]{3}", seq):
        raise MJCFError(f"path: <compiler eulerseq> must be three of x, y, z, X, Y, Z; got {seq!r}",
                        parameter="path")
    snapper = Snapper(exact=exact, tol=tol)
    model = _Model(root, degrees=angle == "degree", eulerseq=seq, snapper=snapper)
    base = model.body(base_link or "world", "base_link")
    tip = model.body(tip_link, "tip_link") if tip_link is not None else model.leaf(base)
    chain = model.chain(base, tip)
    robot = dh_robot(root.get("model") or path.stem, chain, snapper, model.name(base), model.name(tip))
    return _without_placeholder_limits(robot, chain)


# ---------------------------------------------------------------------------- reading the file
def _parse(path: Path) -> ET.Element:
    root = read_xml(path, "path", kind="MJCF", error=MJCFError)
    if root.tag == "robot":
        raise MJCFError(f"path: {str(path)!r} is a URDF file (root element <robot>), not an MJCF model; read it as "
                        "URDF (DHRobot.from_urdf, --urdf FILE)", parameter="path")
    if root.tag != "mujoco":
        raise MJCFError(f"path: {str(path)!r} is not an MJCF model (root element <{root.tag}>, expected <mujoco>)",
                        parameter="path")
    if root.find(".//include") is not None:
        raise MJCFError(f"path: {str(path)!r} uses <include>; merge the included files first", parameter="path")
    return root


def _where(element: ET.Element) -> str:
    name = element.get("name")
    return f"<{element.tag}{' name=' + repr(name) if name else ''}>"


def _numbers(element: ET.Element, attribute: str, count: int, attrs: dict | None = None) -> list[float] | None:
    """The attribute as exactly ``count`` finite numbers, or None when absent."""
    text = (attrs if attrs is not None else element.attrib).get(attribute)
    if text is None:
        return None
    tokens = text.split()
    if len(tokens) != count or not all(_NUMBER.match(t) for t in tokens):
        raise MJCFError(f"path: {_where(element)} {attribute}: expected {count} numbers; got {text[:60]!r}",
                        parameter="path")
    values = [float(t) for t in tokens]
    if not all(math.isfinite(v) for v in values):
        raise MJCFError(f"path: {_where(element)} {attribute}: numbers must be finite; got {text[:60]!r}",
                        parameter="path")
    return values


def _given(element: ET.Element, attribute: str, count: int) -> list[float]:
    """:func:`_numbers` of an attribute the caller found in ``element``."""
    values = _numbers(element, attribute, count)
    assert values is not None
    return values


def _rotation(axis, angle: float) -> np.ndarray:
    """Rodrigues' rotation about a unit ``axis`` by ``angle`` radians."""
    x, y, z = axis
    K = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def _unit(v, element, attribute) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(v))
    if n < 1e-12:
        raise MJCFError(f"path: {_where(element)} {attribute}: a zero vector {v.tolist()} has no direction",
                        parameter="path")
    return v / n


def _homogeneous(R=None, p=(0.0, 0.0, 0.0)) -> np.ndarray:
    T = np.eye(4)
    if R is not None:
        T[:3, :3] = R
    T[:3, 3] = p
    return T


class _Model:
    """The body tree, the default classes and the compiler settings of one MJCF file."""

    def __init__(self, root: ET.Element, *, degrees: bool, eulerseq: str, snapper: Snapper | None = None):
        self.degrees, self.eulerseq, self.snapper = degrees, eulerseq, snapper
        self.defaults: dict[str, dict] = {}
        for d in root.findall("default"):
            self._read_defaults(d, {}, top=True)
        world = root.find("worldbody")
        if world is None:
            raise MJCFError("path: the model has no <worldbody>", parameter="path")
        self.parent: dict[ET.Element, ET.Element | None] = {world: None}
        self.childclass: dict[ET.Element, str] = {world: _DEFAULT_CLASS}
        self.bodies: dict[str, ET.Element] = {"world": world}
        self._walk(world)

    def _read_defaults(self, element: ET.Element, inherited: dict, top: bool = False) -> None:
        name = element.get("class", _DEFAULT_CLASS if top else None)
        if name is None:
            raise MJCFError("path: a nested <default> needs a class attribute", parameter="path")
        joint = dict(inherited)
        for j in element.findall("joint"):
            joint.update(j.attrib)
        self.defaults[name] = joint
        for child in element.findall("default"):
            self._read_defaults(child, joint)

    def _walk(self, body: ET.Element) -> None:
        for child in body:
            if child.tag == "frame":
                raise MJCFError("path: <frame> elements are not supported; write their pose into the bodies",
                                parameter="path")
            if child.tag != "body":
                continue
            self.parent[child] = body
            self.childclass[child] = child.get("childclass", self.childclass[body])
            name = child.get("name")
            if name is not None:
                if name in self.bodies:
                    raise MJCFError(f"path: two bodies are named {name!r}", parameter="path")
                self.bodies[name] = child
            self._walk(child)

    def name(self, body: ET.Element) -> str:
        return next((k for k, v in self.bodies.items() if v is body), "unnamed body")

    def body(self, name: str, parameter: str) -> ET.Element:
        if name not in self.bodies:
            shown = ", ".join(map(repr, list(self.bodies)[:12]))
            raise MJCFError(f"{parameter}: no body {name!r} in the model; bodies: {shown}", parameter=parameter)
        return self.bodies[name]

    def _joints(self, body: ET.Element) -> list[ET.Element]:
        return [e for e in body if e.tag in ("joint", "freejoint")]

    def leaf(self, base: ET.Element) -> ET.Element:
        """The one leaf body below ``base`` reached through a joint."""
        leaves, stack = [], [(base, False)]
        while stack:
            body, moved = stack.pop()
            below = [c for c in body if c.tag == "body"]
            if not below and moved:
                leaves.append(body)
            stack.extend((c, moved or bool(self._joints(c))) for c in below)
        if len(leaves) != 1:
            found = f"{len(leaves)} leaf bodies moved by joints" if leaves else "no body moved by a joint"
            raise MJCFError(f"tip_link: the model has {found} below {self.name(base)!r}; name the tip body",
                            parameter="tip_link")
        return leaves[0]

    def chain(self, base: ET.Element, tip: ET.Element) -> list[_Joint]:
        """URDF-shaped joints from ``base`` to ``tip``: each body's pose, then its joints."""
        bodies: list[ET.Element] = []
        body: ET.Element | None = tip
        while body is not base:
            if body is None:
                raise MJCFError(f"tip_link: body {self.name(tip)!r} is not below {self.name(base)!r}",
                                parameter="tip_link")
            bodies.append(body)
            body = self.parent[body]
        out = []
        for body in reversed(bodies):
            out.append(_Joint(f"body {self.name(body)}", "fixed", self._pose(body)))
            for k, j in enumerate(self._joints(body), start=1):
                out.extend(self._joint(body, j, k))
        return out

    def _angle(self, value: float) -> float:
        return math.radians(value) if self.degrees else value

    def _pose(self, body: ET.Element) -> np.ndarray:
        given = [a for a in _ORIENTATIONS if a in body.attrib]
        if len(given) > 1:
            raise MJCFError(f"path: {_where(body)} gives the orientation twice ({' and '.join(given)})",
                            parameter="path")
        R = np.eye(3)
        if given == ["quat"]:
            w, x, y, z = self._quaternion(body, _unit(_given(body, "quat", 4), body, "quat"))
            R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                          [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                          [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        elif given == ["axisangle"]:
            *axis, a = _given(body, "axisangle", 4)
            R = _rotation(_unit(axis, body, "axisangle"), self._angle(a))
        elif given == ["euler"]:
            for ch, a in zip(self.eulerseq, _given(body, "euler", 3)):
                step = _rotation(np.eye(3)["xyz".index(ch.lower())], self._angle(a))
                R = R @ step if ch.islower() else step @ R     # lower case: axes moving with the frame
        elif given == ["xyaxes"]:
            v = _given(body, "xyaxes", 6)
            x = _unit(v[:3], body, "xyaxes")
            y = _unit(np.asarray(v[3:]) - np.dot(v[3:], x) * x, body, "xyaxes")
            R = np.column_stack([x, y, np.cross(x, y)])
        elif given == ["zaxis"]:
            z = _unit(_given(body, "zaxis", 3), body, "zaxis")
            c = np.cross([0.0, 0.0, 1.0], z)     # the smallest rotation taking the z axis to z
            s = float(np.linalg.norm(c))
            R = (_rotation(c / s, math.atan2(s, z[2])) if s > 1e-12 else
                 (np.eye(3) if z[2] > 0 else _rotation((1.0, 0.0, 0.0), math.pi)))
        return _homogeneous(R, _numbers(body, "pos", 3) or (0.0, 0.0, 0.0))

    def _quaternion(self, body: ET.Element, q: np.ndarray) -> np.ndarray:
        """The unit quaternion ``q`` of ``body``, replaced by the exact turn it was clearly written from.

        A file writes ``cos 15 deg`` as ``0.9659258``: to 7 decimals, so its
        angle is known to about 1e-7 only, far beyond the 1e-9 at which the
        chain's Euler angles snap, and the rounding would leave ``4e-17*s1``
        and ``8e-35*c4`` terms in every product.  When the turn's angle lies,
        within what the digits written allow (``8 * 0.5e-d`` for ``d``
        decimals), on the ``pi/360`` grid, and each component of its axis on
        ``0, 1/2, sqrt(2)/2, sqrt(3)/2, sqrt(3)/3, 1`` (or a 15-degree cosine)
        with an exactly unit axis, the quaternion of that exact turn (in full
        double precision, which the chain snaps) replaces the written one, and
        a note says so; otherwise ``q`` is kept.  Only a quaternion written to
        6 decimals or more is read so (``0.9 0.1 -0.3 0.2`` is what it says),
        and ``exact=False`` or ``tol = 0`` keeps every quaternion as written.
        """
        eps = _written_precision(body.get("quat", ""))
        if self.snapper is None or not self.snapper.exact or self.snapper.tol == 0 or not 0 < eps <= _ROUNDED:
            return q            # 0.9 0.1 -0.3 0.2 says nothing of a rounded value: it is what is meant
        w, v = float(q[0]), np.asarray(q[1:], dtype=float)
        if w < 0:                                   # q and -q are the same turn
            w, v = -w, -v
        s = float(np.linalg.norm(v))
        tol = 8 * eps
        angle = snap_angle(2 * math.atan2(s, w), tol)
        if angle is None:
            return q
        if angle == 0:
            exact, words = np.array([1.0, 0.0, 0.0, 0.0]), "no turn"
        else:
            axis = [_exact_cosine(c, tol / max(s, 1e-300)) for c in v / s]
            if any(c is None for c in axis) or sp.nsimplify(sum(c ** 2 for c in axis)) != 1:
                return q
            half = float(angle) / 2
            exact = np.array([math.cos(half)] + [math.sin(half) * float(c) for c in axis])
            words = f"a turn of {sp.sstr(angle * 180 / sp.pi)} deg about ({', '.join(map(sp.sstr, axis))})"
        if float(np.abs(exact - np.concatenate([[w], v])).max()) > 0:
            self.snapper.notes.append(f"{_where(body)} quat {body.get('quat')!r} (its digits within {eps:.0e}): "
                                      f"read as {words}")
        return exact

    def _joint(self, body: ET.Element, element: ET.Element, k: int) -> list[_Joint]:
        cls = element.get("class", self.childclass[body])
        if cls not in self.defaults and cls != _DEFAULT_CLASS:
            raise MJCFError(f"path: {_where(element)} class: no default class {cls!r}", parameter="path")
        attrs = {**self.defaults.get(cls, {}), **element.attrib}
        name = element.get("name") or f"joint {k} of body {self.name(body)}"
        kind = "free" if element.tag == "freejoint" else attrs.get("type", "hinge")
        if kind not in ("hinge", "slide"):
            raise MJCFError(f"path: joint {name!r} is {kind}; a serial chain takes hinge and slide joints only",
                            parameter="path")
        p = np.asarray(_numbers(element, "pos", 3, attrs) or (0.0, 0.0, 0.0))
        axis = _unit(_numbers(element, "axis", 3, attrs) or (0.0, 0.0, 1.0), element, "axis")
        ref = (_numbers(element, "ref", 1, attrs) or [0.0])[0]
        limited = attrs.get("limited", "auto")
        if limited not in ("true", "false", "auto"):
            raise MJCFError(f"path: {_where(element)} limited: expected true, false or auto; got {limited[:20]!r}",
                            parameter="path")
        span = _numbers(element, "range", 2, attrs)
        limit = None
        if limited == "true" or (limited == "auto" and span is not None):
            if span is None:
                raise MJCFError(f"path: {_where(element)} is limited but has no range", parameter="path")
            lo, hi = (self._angle(v) for v in span) if kind == "hinge" else span
            limit = _Limit(lo, hi)
        if kind == "hinge":
            # URDF's continuous joints have no limits; an unlimited slide gets a placeholder, removed afterwards.
            motion, undo = ("revolute" if limit else "continuous"), _homogeneous(_rotation(axis, -self._angle(ref)))
        else:
            motion, undo = "prismatic", _homogeneous(p=-ref * axis)
            limit = limit or _Limit(-1.0, 1.0, placeholder=True)
        # the turn by -ref and the shift back by -p are two transforms: multiplied here in floats, p - R p would
        # snap to a 16-digit decimal (3472963553338607/10^18) beside the exact cos(pi/18) of the next origin
        return [_Joint(name, motion, _homogeneous(p=p), tuple(axis), limit),
                _Joint(f"{name} (ref)", "fixed", undo), _Joint(f"{name} (anchor)", "fixed", _homogeneous(p=-p))]


def _written_precision(text: str) -> float:
    """Half a unit of the last decimal written among numbers with decimals (``"0.9659258 0.258819 0 0"``: 5e-8);
    0 when every number is written whole."""
    exponents = []
    for token in text.split():
        mantissa, _, power = token.lower().partition("e")
        decimals = len(mantissa.partition(".")[2]) if "." in mantissa else 0
        if decimals:
            exponents.append(int(power or 0) - decimals)
    return 0.5 * 10.0 ** max(exponents) if exponents else 0.0


def _exact_cosine(value: float, tol: float):
    """The value among ``0, +-1/2, +-sqrt(2)/2, +-sqrt(3)/2, +-sqrt(3)/3, +-1`` and the 15-degree cosines within
    ``tol`` of ``value``, or None."""
    for candidate in _AXIS_VALUES:
        if abs(float(candidate) - value) <= tol:
            return candidate
    return None


# a quaternion whose coarsest component is written to 6 decimals or more may be a rounded exact turn
_ROUNDED = 5e-7
_AXIS_VALUES = [sign * c for c in (sp.Integer(0), sp.Rational(1, 2), sp.sqrt(2) / 2, sp.sqrt(3) / 2,
                                   sp.sqrt(3) / 3, sp.Integer(1), (sp.sqrt(6) + sp.sqrt(2)) / 4,
                                   (sp.sqrt(6) - sp.sqrt(2)) / 4) for sign in (1, -1)]


def _without_placeholder_limits(robot, chain):
    """Unlimited slide joints: the placeholder limits of :meth:`_Model._joint` removed."""
    from dataclasses import replace

    moving = [j for j in chain if j.type != "fixed"]
    if not any(j.limit is not None and j.limit.placeholder for j in moving):
        return robot
    joints = [replace(dh, limits=None) if j.limit is not None and j.limit.placeholder else dh
              for dh, j in zip(robot.joints, moving)]
    return type(robot)(joints, convention=robot.convention, name=robot.name, units=robot.units, base=robot.base,
                       tool=robot.tool, input_notes=robot.input_notes, chop_tol=robot.chop_tol)
