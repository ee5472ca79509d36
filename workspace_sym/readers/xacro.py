"""xacro files expanded into URDF: a xacro file is a program, run only when its name says so.

**A URDF file is data, a xacro file is a program.**  :func:`workspace_sym.readers.urdf.read_urdf` expands only a
file whose name ends in ``.xacro`` (``robot.urdf.xacro``, :func:`is_xacro`), with the ``xacro`` package (``pip
install 'workspace_sym[xacro]'``; without it the file is refused with the command that expands it).  Expanding runs
the ``${...}`` expressions of the file with xacro's own evaluator, which reaches any class Python has loaded
(``subprocess.Popen`` included), as ROS's ``xacro`` command does: give a ``.xacro`` name only to a file you would
run, and let no one else choose the name of a file you read.  Any other file is read as URDF and never expanded;
one holding xacro markup (:func:`xacro_markup`: an element of xacro's namespace, ``${`` or ``$(`` in an attribute
or a text) is refused, with the way to expand it knowingly.  None of the package's readers of others' input
(answer keys, students' answers) reads robot files.

:func:`expand_xacro` checks every file xacro reads (the file and its ``<xacro:include>``) as untrusted XML first
(:func:`workspace_sym.files.parse_xml`: no document type, no entities).  ``$(find pkg)`` is the directory given in
``packages`` (``--package pkg=DIR``), else a folder named ``pkg`` above the file or beside one of the folders above
it (the layout of rtb-data and of a ROS workspace); ``$(arg name)`` is the value given in ``xacro_args``
(``--xacro-arg name=value``, xacro's own ``name:=value``), else the default of the file's ``<xacro:arg>``; a given
name the file neither declares nor uses is refused.
"""

from __future__ import annotations

import io
import xml.etree.ElementTree as ET
from pathlib import Path

from ..errors import URDFError
from ..files import parse_xml, read_bytes

__all__ = ["XACRO_SUFFIX", "is_xacro", "check_packages", "check_xacro_args", "expand_xacro", "xacro_markup"]

# The end of the name of a file that read_urdf expands with xacro (and so runs): the user's choice, not the file's.
XACRO_SUFFIX = ".xacro"
# xacro's namespace, in the two spellings ROS files use.
_XACRO_NAMESPACES = ("http://ros.org/wiki/xacro", "http://www.ros.org/wiki/xacro")


def is_xacro(path: Path) -> bool:
    """Whether ``path`` is to be expanded as xacro: its name ends in ``.xacro``, the user's choice, not the file's.

    Parameters
    ----------
    path : pathlib.Path
        The file named by the user.

    Returns
    -------
    bool
        True when its name ends in :data:`XACRO_SUFFIX`.

    Examples
    --------
    >>> is_xacro(Path("robot.urdf.xacro")), is_xacro(Path("robot.urdf"))
    (True, False)
    """
    return path.name.endswith(XACRO_SUFFIX)


def check_packages(packages) -> dict:
    """``packages`` checked: package names to existing directories.

    Parameters
    ----------
    packages : dict or None
        Package names (as in ``$(find pkg)``) to their directories.

    Returns
    -------
    dict
        The names without surrounding blanks, to :class:`~pathlib.Path` objects.

    Raises
    ------
    URDFError
        A name that is not text, or a directory that does not exist (``parameter="packages"``).
    """
    out = {}
    for name, folder in (packages or {}).items():
        if not isinstance(name, str) or not name.strip() or not Path(folder).is_dir():
            raise URDFError(f"packages: expected a package name and an existing directory; got {name!r} = "
                            f"{str(folder)!r}", parameter="packages")
        out[name.strip()] = Path(folder)
    return out


def check_xacro_args(values) -> dict:
    """``xacro_args`` checked: argument names to their values as text (what xacro's ``name:=value`` gives).

    Parameters
    ----------
    values : dict or None
        Argument names (as in ``$(arg name)``) to text or numbers.

    Returns
    -------
    dict
        The names to their values as text.

    Raises
    ------
    URDFError
        A name that is not text or has surrounding blanks, a value that is not one line of text or a number
        (``parameter="xacro_args"``).

    Examples
    --------
    >>> check_xacro_args({"robot_name": "px100", "scale": 2})
    {'robot_name': 'px100', 'scale': '2'}
    """
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


def expand_xacro(path: Path, packages: dict, args: dict) -> bytes:
    """The URDF a xacro file expands to (the ``xacro`` package, ``$(find pkg)`` through :func:`_find_package`).

    Every file xacro reads (``path`` and its ``<xacro:include>``) is first checked as untrusted XML
    (:func:`workspace_sym.files.parse_xml`: no document type, no entities), and xacro parses the bytes checked.
    Expanding runs the code the file holds: call it only on a file the user named ``*.xacro``.

    Parameters
    ----------
    path : Path
        The xacro file.
    packages : dict
        Directories of packages (:func:`check_packages`), for ``$(find pkg)``.
    args : dict
        Values of the file's arguments (:func:`check_xacro_args`), for ``$(arg name)``.

    Returns
    -------
    bytes
        The expanded document.

    Raises
    ------
    URDFError
        The ``xacro`` extra missing, a file that does not expand or is not safe XML (``parameter="path"``), a
        package not found (``"packages"``), an argument the file does not have (``"xacro_args"``).
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



def xacro_markup(root: ET.Element) -> str | None:
    """The first xacro markup of a parsed file, shown as ``<tag attribute='value'>``: an element or attribute of
    xacro's namespace, or an expression ``${`` or a substitution ``$(`` in an attribute or a text; None if none.

    (An expanded file may keep the ``xmlns:xacro`` declaration: that alone is not markup.)

    Parameters
    ----------
    root : xml.etree.ElementTree.Element
        The root of the parsed file.

    Returns
    -------
    str or None
        The markup found first (in document order), cut to 40 characters of its value; None when there is none.

    Examples
    --------
    >>> xacro_markup(ET.fromstring('<robot name="arm"><link name="${prefix}base"/></robot>'))
    "<link name='${prefix}base'>"
    >>> xacro_markup(ET.fromstring('<robot name="arm"><link name="base"/></robot>')) is None
    True
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

