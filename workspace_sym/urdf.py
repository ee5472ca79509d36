"""Serial chains of URDF files, read with yourdfpy and turned into exact DH robots.

A URDF joint is a constant transform (``origin``: ``xyz`` then
``Rz(yaw) Ry(pitch) Rx(roll)``) followed by a rotation about ``axis``
(revolute, continuous) or a translation along it (prismatic); fixed joints are
constant transforms only.  The chain from a base link to a tip link is the
product of these transforms.

**Every such chain has a standard DH table** once a constant base transform
(frame 0 must have its z axis on joint 1's axis) and a tool transform (from
the last DH frame to the tip link) are allowed: between two successive joint
axes the common normal gives ``a`` and ``alpha``, and the two other numbers of
a URDF origin (a rotation about, and a shift along, the next joint's axis) go
into that joint's ``theta`` offset and ``d`` (Denavit and Hartenberg 1955;
Spong, Hutchinson, Vidyasagar, *Robot Modeling and Control*, section 3.2).
Skew axes are no obstacle, a URDF simply spends six numbers where DH needs
four.  So :func:`read_urdf` returns a :class:`~workspace_sym.kinematics.DHRobot`
(standard convention, with ``base`` and ``tool``) whose ``fk()`` equals the
URDF product identically; everything a DH robot offers (textbook FK,
Jacobians, singular factors, certified reach) works on it.  What the
extraction needed is stated in ``robot.input_notes``: whether the table alone
starts at the URDF base (no base transform), and where successive axes are
parallel (the DH frame is then not unique: ``d = 0`` is chosen).

Numbers are snapped as in :mod:`workspace_sym.snap`: lengths become the
decimals of the file, ``rpy`` angles within ``tol`` of a multiple of ``pi/360``
become that multiple (``1.57079632679`` is ``pi/2`` at the default 1e-9, the
rounded ``1.5708`` is not), axis components within ``tol`` of ``cos(k pi/12)``
become it, and the axis is normalised exactly.

The file is untrusted XML: defusedxml parses it first
(:func:`workspace_sym.files.parse_xml`), refusing document type and entity
declarations in any encoding, and yourdfpy (whose lxml would expand entities)
reads only the document so checked.

**A URDF file is data, a xacro file is a program.**  Only a file whose name
ends in ``.xacro`` (``robot.urdf.xacro``) is expanded, with the ``xacro``
package (``pip install 'workspace_sym[xacro]'``; without it the file is
refused with the command that expands it).  Expanding runs the ``${...}``
expressions of the file with xacro's own evaluator, which reaches any class
Python has loaded (``subprocess.Popen`` included), as ROS's ``xacro`` command
does: give a ``.xacro`` name only to a file you would run, and let no one else
choose the name of a file you read.  Any other file is read as URDF and never
expanded; one holding xacro markup (an element of xacro's namespace, ``${`` or
``$(`` in an attribute or a text) is refused, with the way to expand it
knowingly.  None of the package's readers of others' input (answer keys,
students' answers) reads robot files.  ``$(find pkg)`` is the directory given
in ``packages`` (``--package pkg=DIR``), else a folder named ``pkg`` above the
file or beside one of the folders above it (the layout of rtb-data and of a ROS
workspace); ``$(arg name)`` is the value given in ``xacro_args``
(``--xacro-arg name=value``, xacro's own ``name:=value``), else the default of
the file's ``<xacro:arg>``.
"""

from __future__ import annotations

import io
import logging
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import sympy as sp

from .errors import URDFError
from .expressions import check_joint_limits
from .files import parse_xml, read_bytes, read_xml
from .kinematics import DHJoint, DHRobot, xyz_rpy
from .snap import DEFAULT_TOL, Snapper, chop

__all__ = ["read_urdf", "MOVING", "UNSUPPORTED"]

#: URDF joint types that become a joint of the chain.
MOVING = ("revolute", "continuous", "prismatic")
#: Joint types refused on the chain (several degrees of freedom).
UNSUPPORTED = ("floating", "planar")
_DUST = 1e-14


def read_urdf(path, *, base_link: str | None = None, tip_link: str | None = None, exact: bool = True,
              tol: float = DEFAULT_TOL, packages: dict | None = None, xacro_args: dict | None = None) -> DHRobot:
    """The serial chain ``base_link -> tip_link`` of a URDF file as an exact DH robot.

    Parameters
    ----------
    path : str or Path
        A URDF file (read as data), or a xacro file, named ``*.xacro``: expanded with the ``xacro`` extra, which
        runs the code the file holds (expand only files you would run).
    base_link : str, optional
        Default: the root of the link tree.
    tip_link : str, optional
        Default: the one leaf below ``base_link`` reached through a moving joint;
        a tree with several such leaves needs it.
    exact, tol
        Snapping of floats (see :mod:`workspace_sym.snap`); ``exact=False`` keeps
        floats and chops entries below ``tol``.
    packages : dict, optional
        Directories of the packages a xacro file names in ``$(find pkg)`` (a ``.xacro`` file only).
    xacro_args : dict, optional
        Values of the arguments of a xacro file, ``$(arg name)`` (a ``.xacro`` file only): text or numbers, as
        ``name:=value`` on xacro's command line; a name the file neither declares nor uses is refused.

    Joint ``k`` of the chain (fixed joints skipped) gets the variable
    ``theta{k}`` (revolute, continuous) or ``d{k}`` (prismatic), the URDF joint
    position itself; limits come from the file (none for continuous joints).

    Raises
    ------
    URDFError
        Unreadable file, a document type or entities, a URDF file holding xacro markup, xacro that cannot be
        expanded, ``packages`` or ``xacro_args`` for a file that is not ``.xacro``, an argument the file does not
        have, unknown or unconnected links, a branching tree
        without ``tip_link``, a mimic, floating or planar joint on the chain, a
        revolute or prismatic joint without ``<limit>``, a chain without joints.
    Examples
    --------
    A planar 2R arm (links 0.4 and 0.3), its limits written as floats:

    >>> import pathlib, tempfile
    >>> joint = ('<joint name="{0}" type="revolute"><parent link="{1}"/><child link="{2}"/>'
    ...          '<origin xyz="{3} 0 0"/><axis xyz="0 0 1"/>'
    ...          '<limit lower="-2.6179938779914944" upper="2.6179938779914944"/></joint>')
    >>> text = ('<robot name="arm"><link name="base"/><link name="upper"/><link name="fore"/><link name="tip"/>'
    ...         + joint.format("shoulder", "base", "upper", 0) + joint.format("elbow", "upper", "fore", 0.4)
    ...         + '<joint name="flange" type="fixed"><parent link="fore"/><child link="tip"/>'
    ...           '<origin xyz="0.3 0 0"/></joint></robot>')
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "arm.urdf"
    >>> _ = path.write_text(text)
    >>> robot = read_urdf(path)
    >>> robot.joints[0]
    DHJoint(R: theta=theta1, d=0, a=2/5, alpha=0, limits=[-5*pi/6, 5*pi/6])
    >>> robot.to_str(robot.position[0])
    '0.4*c1 + 0.3*c12'
    """
    path = Path(path)
    packages, args = _package_dirs(packages), _xacro_args(xacro_args)
    for parameter, given, use in (("packages", packages, "package directories serve only the $(find PKG)"),
                                  ("xacro_args", args, "arguments serve only the $(arg NAME)")):
        if given and not _is_xacro(path):
            raise URDFError(f"{parameter}: {path.name} is read as URDF, not expanded as xacro (its name does not end "
                            f"in {_XACRO_SUFFIX}); {use} of a xacro file", parameter=parameter)
    model = _load(path, packages, args)
    joints = model.robot.joints
    by_child = {j.child: j for j in joints}
    links = [link.name for link in model.robot.links]
    base_given = base_link is not None
    base_link = _base(links, by_child, base_link, path)
    tip_link = _tip(links, joints, by_child, base_link, tip_link, path, base_given)
    chain = _path(by_child, base_link, tip_link, path)
    snapper = Snapper(exact=exact, tol=tol, error=URDFError)
    return _dh_robot(model.robot.name or path.stem, chain, snapper, base_link, tip_link)


# ---------------------------------------------------------------------------- reading the file
# The end of the name of a file that read_urdf expands with xacro (and so runs): the user's choice, not the file's.
_XACRO_SUFFIX = ".xacro"
# xacro's namespace, in the two spellings ROS files use.
_XACRO_NAMESPACES = ("http://ros.org/wiki/xacro", "http://www.ros.org/wiki/xacro")


def _is_xacro(path: Path) -> bool:
    return path.name.endswith(_XACRO_SUFFIX)


def _package_dirs(packages) -> dict:
    """``packages`` checked: package names to existing directories."""
    out = {}
    for name, folder in (packages or {}).items():
        if not isinstance(name, str) or not name.strip() or not Path(folder).is_dir():
            raise URDFError(f"packages: expected a package name and an existing directory; got {name!r} = "
                            f"{str(folder)!r}", parameter="packages")
        out[name.strip()] = Path(folder)
    return out


def _xacro_args(values) -> dict:
    """``xacro_args`` checked: argument names to their values as text (what xacro's ``name:=value`` gives)."""
    out = {}
    for name, value in (values or {}).items():
        if (not isinstance(name, str) or not name or name != name.strip() or type(value) not in (str, int, float)
                or "\n" in str(value)):
            raise URDFError(f"xacro_args: expected an argument name and its value (text or a number, one line); got "
                            f"{name!r:.40} = {value!r:.60}", parameter="xacro_args")
        out[name] = str(value)
    return out


class _ArgsAsked(dict):
    """The arguments handed to xacro, noting the names the file asks about (declares with ``<xacro:arg>``, or
    reads in ``$(arg name)``): xacro itself ignores a given name the file never asks for, a typo included."""

    def __init__(self, values: dict):
        super().__init__(values)
        self.asked: set = set()

    def __contains__(self, name) -> bool:
        self.asked.add(name)
        return super().__contains__(name)

    def __getitem__(self, name):
        self.asked.add(name)
        return super().__getitem__(name)


def _find_package(name: str, path: Path, packages: dict) -> str:
    """``$(find name)`` for the xacro file ``path``: a given directory, a folder ``name`` above the file, or beside
    one of the folders above it."""
    if name in packages:
        return str(packages[name])
    for folder in path.resolve().parents:
        if folder.name == name:
            return str(folder)
        if (folder / name).is_dir():
            return str(folder / name)
    raise URDFError(f"packages: {path.name} needs $(find {name}), and no folder {name!r} is above it or beside "
                    f"the folders above it; give its directory (packages={{{name!r}: DIR}}, --package {name}=DIR)",
                    parameter="packages")


def _expand_xacro(path: Path, packages: dict, args: dict) -> bytes:
    """The URDF a xacro file expands to (the ``xacro`` package, ``$(find pkg)`` through :func:`_find_package`).

    Every file xacro reads (``path`` and its ``<xacro:include>``) is first checked as untrusted XML
    (:func:`workspace_sym.files.parse_xml`: no document type, no entities), and xacro parses the bytes checked.
    """
    try:
        import xacro
        from xacro import substitution_args
    except ImportError:
        raise URDFError(f"path: {str(path)!r} is a xacro file; install the xacro extra to expand it here (pip "
                        "install 'workspace_sym[xacro]'), or expand it first (xacro FILE > robot.urdf) and pass the "
                        ".urdf", parameter="path") from None
    parse = xacro.parse

    def checked_parse(inp, filename=None):
        if inp is None:         # a file to open (xacro's own rule: relative to its root_dir)
            name = Path(xacro.root_dir) / filename
            data = read_bytes(name, "path", error=URDFError)
            parse_xml(data, name, "path", kind="xacro", error=URDFError)
            inp = io.BytesIO(data)
        return parse(inp, filename)

    mappings = _ArgsAsked(args)
    saved = substitution_args._eval_find
    substitution_args._eval_find = lambda name: _find_package(name, path, packages)
    xacro.parse = checked_parse
    try:
        expanded = xacro.process_file(str(path), mappings=mappings).toxml().encode()
    except Exception as exc:  # broad on purpose: xacro raises its own and Python's exceptions on a bad file
        cause: BaseException | None = exc
        seen = set()
        while cause is not None and id(cause) not in seen:      # our own error about a package, wrapped by xacro
            if isinstance(cause, URDFError):
                raise cause from None
            seen.add(id(cause))
            cause = getattr(cause, "exc", None) or cause.__cause__ or cause.__context__
        reason = " ".join(str(exc).split())[:160] or type(exc).__name__
        raise URDFError(f"path: {str(path)!r} is a xacro file that could not be expanded ({reason})",
                        parameter="path") from None
    finally:
        substitution_args._eval_find = saved
        xacro.parse = parse
    unknown = sorted(set(args) - mappings.asked)
    if unknown:
        has = ", ".join(map(repr, sorted(mappings.asked))) or "none"
        raise URDFError(f"xacro_args: {path.name} has no argument {unknown[0]!r}; its arguments: {has}",
                        parameter="xacro_args")
    return expanded


def _load(path: Path, packages: dict, args: dict):
    try:
        import yourdfpy
    except ImportError:
        raise URDFError("path: reading URDF files needs yourdfpy: pip install 'workspace_sym[urdf]'",
                        parameter="path") from None
    if _is_xacro(path):      # named xacro by the user: expanded, and its expressions run
        root = parse_xml(_expand_xacro(path, packages, args), path, "path", kind="URDF", error=URDFError)
    else:                    # data: never expanded
        root = read_xml(path, "path", kind="URDF", error=URDFError)
        markup = _xacro_markup(root)
        if markup is not None:
            raise URDFError(f"path: {str(path)!r} looks like xacro, not URDF ({markup}); a URDF file is read as "
                            "data and never expanded. Expanding xacro runs the code the file holds: if you trust "
                            f"this file, give it a name ending in {_XACRO_SUFFIX} to expand it here, or expand it "
                            "yourself (xacro FILE > robot.urdf)", parameter="path")
    if root.tag == "mujoco":
        raise URDFError(f"path: {str(path)!r} is an MJCF model (root element <mujoco>), not URDF; read it as MJCF "
                        "(DHRobot.from_mjcf, --mjcf FILE)", parameter="path")
    if root.tag != "robot":
        raise URDFError(f"path: {str(path)!r} is not a URDF file (root element <{root.tag}>, expected <robot>)",
                        parameter="path")
    # yourdfpy parses with lxml, which would expand entities: it gets the document defusedxml parsed and checked
    try:
        source = io.BytesIO(ET.tostring(root))
    except RecursionError:
        raise URDFError(f"path: {str(path)!r} is nested too deeply for a URDF file", parameter="path") from None
    # yourdfpy logs a parse error (lxml's limits, a depth of 256) and then reads what lxml can recover: a failure.
    logger = logging.getLogger("yourdfpy")
    errors = _Collect()
    logger.addHandler(errors)
    propagate, logger.propagate = logger.propagate, False
    model, failure = None, None
    try:
        # nan or inf in an origin: numpy warns while building the matrix; the value is refused when read
        with np.errstate(all="ignore"):
            model = yourdfpy.URDF.load(source, build_scene_graph=False, build_collision_scene_graph=False,
                                       load_meshes=False, load_collision_meshes=False)
    except Exception as exc:  # broad on purpose: lxml, KeyError on a missing attribute, float('abc'), ...
        failure = " ".join(str(exc).split())[:120] or type(exc).__name__
    finally:
        logger.removeHandler(errors)
        logger.propagate = propagate
    if errors.messages:
        raise URDFError(f"path: {str(path)!r} cannot be parsed as URDF ({errors.messages[0][:120]})",
                        parameter="path")
    if failure is not None:
        raise URDFError(f"path: cannot read {str(path)!r} as URDF ({failure})", parameter="path")
    return model


def _xacro_markup(root: ET.Element) -> str | None:
    """The first xacro markup of a parsed file, shown as ``<tag attribute='value'>``: an element or attribute of
    xacro's namespace, or an expression ``${`` or a substitution ``$(`` in an attribute or a text; None if none.

    (An expanded file may keep the ``xmlns:xacro`` declaration: that alone is not markup.)
    """
    def local(name: str) -> str:
        return name.rpartition("}")[2]

    def in_xacro(name: str) -> bool:
        return name.startswith("{") and name[1:].partition("}")[0].rstrip("/") in _XACRO_NAMESPACES

    def marked(text: str) -> bool:
        return "${" in text or "$(" in text

    for element in root.iter():
        tag = local(element.tag)
        if in_xacro(element.tag):
            return f"<xacro:{tag}>"
        for key, value in element.attrib.items():
            if in_xacro(key) or marked(value):
                return f"<{tag} {local(key)}={value[:40]!r}>"
        for text in (element.text or "", element.tail or ""):
            if marked(text):
                return f"<{tag}> with the text {' '.join(text.split())[:40]!r}"
    return None


class _Collect(logging.Handler):
    def __init__(self):
        super().__init__(logging.ERROR)
        self.messages = []

    def emit(self, record):
        self.messages.append(" ".join(record.getMessage().split()))


def _base(links, by_child, base_link, path) -> str:
    if base_link is not None:
        if base_link not in links:
            raise URDFError(f"base_link: no link {base_link!r} in {path.name}; links: {_listed(links)}",
                            parameter="base_link")
        return base_link
    roots = _roots(links, by_child)
    if len(roots) != 1:
        raise URDFError(f"base_link: {path.name} has {len(roots)} root links ({_listed(roots)}); expected the "
                        "base link to be named", parameter="base_link")
    return roots[0]


def _roots(links, by_child) -> list:
    return [name for name in links if name not in by_child]


def _tip(links, joints, by_child, base_link, tip_link, path, base_given: bool = False) -> str:
    if tip_link is not None:
        if tip_link not in links:
            raise URDFError(f"tip_link: no link {tip_link!r} in {path.name}; links: {_listed(links)}",
                            parameter="tip_link")
        return tip_link
    children: dict[str, list] = {}           # parent link -> its joints (yourdfpy's Joint objects)
    for j in joints:
        children.setdefault(j.parent, []).append(j)
    leaves, stack = [], [(base_link, False)]
    while stack:   # leaves below base_link, and whether a moving joint leads there
        link, moved = stack.pop()
        below = children.get(link, [])
        if not below and moved:
            leaves.append(link)
        stack.extend((j.child, moved or j.type in MOVING) for j in below)
    if not leaves and base_given:      # the base chosen is the problem, not the tip left to its default
        raise URDFError(f"base_link: no joint moves a link below {base_link!r} in {path.name}; expected a link "
                        f"above the chain's joints (root links: {_listed(_roots(links, by_child))})",
                        parameter="base_link")
    if len(leaves) != 1:
        found = f"leaves {_listed(sorted(leaves))}" if leaves else "no link moved by a joint"
        raise URDFError(f"tip_link: {path.name} has {found} below {base_link!r}; expected the tip link to be "
                        "named", parameter="tip_link")
    return leaves[0]


def _path(by_child, base_link, tip_link, path) -> list:
    """The joints from ``base_link`` to ``tip_link``, in order."""
    chain, link = [], tip_link
    while link != base_link:
        joint = by_child.get(link)
        if joint is None:
            raise URDFError(f"tip_link: link {tip_link!r} is not connected below base link {base_link!r} in "
                            f"{path.name}", parameter="tip_link")
        chain.append(joint)
        link = joint.parent
        if len(chain) > len(by_child):
            raise URDFError(f"path: the joints of {path.name} form a loop", parameter="path")
    chain.reverse()
    for j in chain:
        if j.type not in (*MOVING, "fixed"):
            raise URDFError(f"path: joint {j.name!r} is {j.type}; a serial chain takes revolute, continuous, "
                            "prismatic and fixed joints only", parameter="path")
        if j.mimic is not None:
            raise URDFError(f"path: joint {j.name!r} mimics {j.mimic.joint!r}; mimic joints are not supported",
                            parameter="path")
        if j.type in ("revolute", "prismatic") and j.limit is None:
            raise URDFError(f"path: joint {j.name!r} ({j.type}) has no <limit>; URDF requires lower and upper "
                            "limits for it (or make it continuous)", parameter="path")
    if not any(j.type in MOVING for j in chain):
        raise URDFError(f"path: no moving joint between {base_link!r} and {tip_link!r}", parameter="path")
    return chain


def _listed(names, most: int = 12) -> str:
    names = list(names)
    shown = ", ".join(map(repr, names[:most]))
    return shown + (f", ... ({len(names)} in all)" if len(names) > most else "")


# ---------------------------------------------------------------------------- exact transforms
def _origin(joint, snapper: Snapper) -> sp.Matrix:
    """The joint's origin as an exact 4 x 4 transform (snapped), checked against the parsed floats."""
    from trimesh import transformations  # yourdfpy builds its origins with these; same convention

    M = np.eye(4) if joint.origin is None else np.asarray(joint.origin, dtype=float)
    where = f"joint {joint.name!r} origin"
    xyz = [snapper.length(v, f"{where} xyz") for v in M[:3, 3]]
    angles = transformations.euler_from_matrix(M, "sxyz")
    rpy = [snapper.angle(v, f"{where} rpy") for v in angles]
    T = xyz_rpy(xyz, rpy)
    gap = float(np.abs(np.array(T[:3, :3].evalf(), dtype=float) - M[:3, :3]).max())
    # snapping moves an entry of the rotation by at most the sum of the angles' moves (a snap from the digits
    # written, 1.5707963 -> pi/2, may move an angle by more than tol); beyond that the angles were recovered badly
    moved = sum(abs(float(r) - a) for r, a in zip(rpy, angles))
    if gap > 10 * snapper.tol + moved + 1e-12:   # Euler angles recovered badly near pitch = +-pi/2: keep the matrix
        T[:3, :3] = sp.Matrix(3, 3, [snapper.cosine(v, f"{where} rotation") for v in M[:3, :3].ravel()])
    return snapper.chop(T)


def _frame(R: sp.Matrix, o: sp.Matrix) -> sp.Matrix:
    return sp.Matrix.vstack(sp.Matrix.hstack(R, o), sp.Matrix([[0, 0, 0, 1]]))


def _axis(joint, snapper: Snapper) -> tuple[sp.Matrix, sp.Expr]:
    """Unit axis (exact) and the length of the axis as written (a prismatic joint moves ``q * axis``)."""
    raw = np.asarray(joint.axis if joint.axis is not None else (1.0, 0.0, 0.0), dtype=float)
    u = sp.Matrix([snapper.cosine(v, f"joint {joint.name!r} axis") for v in raw])
    norm2 = _clean(u.dot(u))
    if norm2 == 0 or float(norm2) < 1e-24:
        raise URDFError(f"path: joint {joint.name!r} has a zero axis {raw.tolist()}", parameter="path")
    norm = _clean(sp.sqrt(norm2))
    return (u if norm == 1 else (u / norm).applyfunc(_clean)), norm


def _clean(e):
    """Exact constants in their simplest radical form; a constant holding a float evaluated to one float."""
    e = sp.sympify(e)
    if e.is_Rational or not e.is_number:
        return e
    if e.has(sp.Float):   # exactness is lost already: one float, not a tree of sqrt(2) times floats
        return e.evalf(17)
    return sp.radsimp(sp.simplify(e))


def _is_zero(e, tol: float) -> bool:
    e = sp.sympify(e)
    if e.has(sp.Float):
        return abs(float(e)) <= tol
    return _clean(e) == 0


# ---------------------------------------------------------------------------- DH extraction
def _dh_robot(name, chain, snapper: Snapper, base_link, tip_link) -> DHRobot:
    lines, pending = [], sp.eye(4)
    notes: list[str] = []
    moving = []
    for j in chain:
        pending = pending * _origin(j, snapper)
        if j.type == "fixed":
            continue
        u, scale = _axis(j, snapper)
        lines.append((pending[:3, 3].applyfunc(_clean), (pending[:3, :3] * u).applyfunc(_clean)))
        moving.append((j, scale))
    T_tip = pending   # the tip link at q = 0, in the base link's frame
    # Float axes 1e-17 from parallel are parallel: their common normal would be 1e17 away.
    frames, rows = _dh_frames(lines, max(snapper.tol, 1e-12), notes, [j.name for j, _ in moving])
    joints, names = [], []
    for k, ((j, scale), (theta0, d0, a, alpha)) in enumerate(zip(moving, rows), start=1):
        if j.type == "prismatic":
            q = sp.Symbol(f"d{k}")
            theta, d, read = theta0, scale * q + d0, snapper.length
        else:
            q = sp.Symbol(f"theta{k}")
            theta, d, read = q + theta0, d0, snapper.angle
        limits = None
        if j.type != "continuous":
            raw = (j.limit.lower or 0.0, j.limit.upper or 0.0)
            limits = tuple(read(v, f"joint {j.name!r} limit") for v in raw)
            check_joint_limits(f"{j.name!r}", *limits, shown=raw)
        joints.append(DHJoint("P" if j.type == "prismatic" else "R", theta, d, a, alpha, q, limits, name=j.name))
        names.append(f"{q} = {j.name}")
    base = frames[0]
    tool = _rigid_inverse(frames[-1]) * T_tip
    # Floats (angles that did not snap) leave rounding dust of 1e-17 in exact zeros: dropped at 1e-14.
    base, tool = (snapper.chop(chop(M.applyfunc(_clean), _DUST)) for M in (base, tool))
    # Identity entry by entry: with floats kept, Float(1.0) != Integer(1) although it is the identity.
    base, tool = (None if all(e.is_zero for e in M - sp.eye(4)) else M for M in (base, tool))
    if base is None:
        notes.insert(0, f"DH table (standard) from {base_link!r}: frame 0 is the base link's frame")
    else:
        notes.insert(0, f"DH table (standard) from {base_link!r} with a base transform: joint 1's axis is not "
                        "the base link's z axis through its origin")
    notes.insert(1, f"joints {', '.join(names)}; tool transform to {tip_link!r}")
    return DHRobot(joints, name=name, units="m", base=base, tool=tool, input_notes=notes + snapper.notes,
                   chop_tol=None if snapper.exact else snapper.tol)


def _rigid_inverse(F: sp.Matrix) -> sp.Matrix:
    R, o = F[:3, :3], F[:3, 3]
    return _frame(R.T, -R.T * o)


def _unit(v: sp.Matrix) -> sp.Matrix:
    n = _clean(sp.sqrt(_clean(v.dot(v))))
    return (v / n).applyfunc(_clean)


def _angle(sin_, cos_) -> sp.Expr:
    """``atan2(sin, cos)`` exactly (``pi/2``, ``atan(4/3)``), as a float when either is one."""
    sin_, cos_ = _clean(sin_), _clean(cos_)
    if sin_.has(sp.Float) or cos_.has(sp.Float):
        return sp.Float(math.atan2(float(sin_), float(cos_)))
    return _clean(sp.atan2(sin_, cos_))


def _dh_frames(lines, tol, notes, names):
    """Standard DH frames 0..n (world 4 x 4 at q = 0) and rows ``(theta offset, d, a, alpha)``.

    ``lines[k] = (point, unit direction)`` of joint ``k + 1``'s axis at q = 0.
    Frame ``i`` has z on axis ``i + 1`` and x along the common normal of axes
    ``i`` and ``i + 1``; the last frame is frame ``n - 1`` turned by joint ``n``.
    """
    ex, ez = sp.Matrix([1, 0, 0]), sp.Matrix([0, 0, 1])
    o1, z = lines[0]
    origin = (o1 - o1.dot(z) * z).applyfunc(_clean)     # foot of the perpendicular from the base origin
    x = ex if _is_zero(z.cross(ez).norm() ** 2, tol ** 2) else _unit(ez.cross(z))
    x = _unit(x - x.dot(z) * z)
    frames = [_frame(sp.Matrix.hstack(x, z.cross(x), z), origin)]
    rows = []
    for i in range(1, len(lines)):
        p, w = lines[i]
        c = z.cross(w).applyfunc(_clean)
        if not _is_zero(c.dot(c), tol ** 2):
            x_new = _unit(c)
            a = _clean((p - origin).dot(x_new))
            if float(a) < 0:    # x along the normal from axis i to axis i + 1: a >= 0, as textbooks print it
                x_new, a = -x_new, -a
            k = _clean(z.dot(w))
            r = p - origin - a * x_new
            d = _clean((r.dot(z) - k * r.dot(w)) / (1 - k ** 2))
        else:
            r = p - origin
            perp = (r - r.dot(z) * z).applyfunc(_clean)
            d = sp.Integer(0)
            if _is_zero(perp.dot(perp), tol ** 2):
                x_new, a = x, sp.Integer(0)
                notes.append(f"axes of {names[i - 1]} and {names[i]} coincide: their common normal is chosen "
                             "as the previous one")
            else:
                a = _clean(sp.sqrt(_clean(perp.dot(perp))))
                x_new = (perp / a).applyfunc(_clean)
                notes.append(f"axes of {names[i - 1]} and {names[i]} are parallel: d = 0 is chosen for the "
                             "common normal")
        alpha = _angle(z.cross(w).dot(x_new), z.dot(w))
        theta = _angle(x.cross(x_new).dot(z), x.dot(x_new))
        rows.append((theta, d, a, alpha))
        origin = (origin + d * z + a * x_new).applyfunc(_clean)
        x, z = x_new, w
        frames.append(_frame(sp.Matrix.hstack(x, z.cross(x), z), origin))
    rows.append((sp.Integer(0), sp.Integer(0), sp.Integer(0), sp.Integer(0)))
    frames.append(frames[-1])
    return frames, rows
