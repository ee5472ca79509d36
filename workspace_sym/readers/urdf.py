"""Serial chains of URDF files, read with yourdfpy and turned into exact DH robots.

A URDF joint is a constant transform (``origin``: ``xyz`` then
``Rz(yaw) Ry(pitch) Rx(roll)``) followed by a rotation about ``axis``
(revolute, continuous) or a translation along it (prismatic); fixed joints are
constant transforms only.  The chain from a base link to a tip link is the
product of these transforms, and it has a standard DH table once constant base
and tool transforms are allowed: :mod:`.chain` extracts it exactly.  So
:func:`read_urdf` returns a :class:`~workspace_sym.kinematics.DHRobot`
(standard convention, with ``base`` and ``tool``) whose ``fk()`` equals the
URDF product identically; everything a DH robot offers (textbook FK,
Jacobians, singular factors, certified reach) works on it.  What the
extraction needed is stated in ``robot.input_notes``; numbers are snapped as in
:mod:`workspace_sym.snap` (see :mod:`.chain`).

The file is untrusted XML: defusedxml parses it first
(:func:`workspace_sym.files.parse_xml`), refusing document type and entity
declarations in any encoding, and yourdfpy (whose lxml would expand entities)
reads only the document so checked.

**A URDF file is data, a xacro file is a program.**  Only a file whose name
ends in ``.xacro`` (``robot.urdf.xacro``) is expanded, by :mod:`.xacro`, which
runs the code the file holds; any other file is read as URDF and never
expanded, and one holding xacro markup is refused, with the way to expand it
knowingly.
"""

from __future__ import annotations

import io
import logging
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from ..errors import URDFError
from ..files import parse_xml, read_xml
from ..kinematics import DHRobot
from ..snap import DEFAULT_TOL, Snapper
from .chain import dh_robot
from .xacro import XACRO_SUFFIX, check_packages, check_xacro_args, expand_xacro, is_xacro, xacro_markup

__all__ = ["read_urdf", "MOVING", "UNSUPPORTED"]

#: URDF joint types that become a joint of the chain.
MOVING = ("revolute", "continuous", "prismatic")
#: Joint types refused on the chain (several degrees of freedom).
UNSUPPORTED = ("floating", "planar")


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

    Returns
    -------
    DHRobot
        Standard DH with ``base`` and ``tool``.  Joint ``k`` of the chain (fixed joints skipped) gets the variable
        ``theta{k}`` (revolute, continuous) or ``d{k}`` (prismatic), the URDF joint position itself; limits come
        from the file (none for continuous joints).

    Raises
    ------
    URDFError
        Unreadable file, a document type or entities, a URDF file holding xacro markup, xacro that cannot be
        expanded, ``packages`` or ``xacro_args`` for a file that is not ``.xacro``, an argument the file does not
        have, unknown or unconnected links, a branching tree
        without ``tip_link``, a mimic, floating or planar joint on the chain, a
        revolute or prismatic joint without ``<limit>``, a chain without joints, a number that is not finite.
    JointLimitError
        A lower limit above the upper one.
    InvalidParameterError
        ``tol`` not a finite number >= 0.

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
    packages, args = check_packages(packages), check_xacro_args(xacro_args)
    for parameter, given, use in (("packages", packages, "package directories serve only the $(find PKG)"),
                                  ("xacro_args", args, "arguments serve only the $(arg NAME)")):
        if given and not is_xacro(path):
            raise URDFError(f"{parameter}: {path.name} is read as URDF, not expanded as xacro (its name does not end "
                            f"in {XACRO_SUFFIX}); {use} of a xacro file", parameter=parameter)
    model = _load(path, packages, args)
    joints = model.robot.joints
    by_child = {j.child: j for j in joints}
    links = [link.name for link in model.robot.links]
    base_given = base_link is not None
    base_link = _base(links, by_child, base_link, path)
    tip_link = _tip(links, joints, by_child, base_link, tip_link, path, base_given)
    chain = _path(by_child, base_link, tip_link, path)
    snapper = Snapper(exact=exact, tol=tol, error=URDFError)
    return dh_robot(model.robot.name or path.stem, chain, snapper, base_link, tip_link)


# ---------------------------------------------------------------------------- reading the file
def _load(path: Path, packages: dict, args: dict):
    try:
        import yourdfpy
    except ImportError:
        raise URDFError("path: reading URDF files needs yourdfpy: pip install 'workspace_sym[urdf]'",
                        parameter="path") from None
    if is_xacro(path):       # named xacro by the user: expanded, and its expressions run
        root = parse_xml(expand_xacro(path, packages, args), path, "path", kind="URDF", error=URDFError)
    else:                    # data: never expanded
        root = read_xml(path, "path", kind="URDF", error=URDFError)
        markup = xacro_markup(root)
        if markup is not None:
            raise URDFError(f"path: {str(path)!r} looks like xacro, not URDF ({markup}); a URDF file is read as "
                            "data and never expanded. Expanding xacro runs the code the file holds: if you trust "
                            f"this file, give it a name ending in {XACRO_SUFFIX} to expand it here, or expand it "
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
