"""Files named by the user: read as text, JSON or XML, and written whole or not at all.

Every reader of a user's file (DH tables, URDF, xacro and MJCF files, answer
keys and CSVs) and every writer of a user's output path (figures, reports,
grades, exercise sheets) goes through here, so that a missing file, a file
that is not UTF-8, JSON nested 100,000 deep, XML declaring entities, a
missing or unwritable output directory or an unknown figure format each
raise a :class:`~workspace_sym.errors.WorkspaceError` naming the parameter,
the path and what was expected, never a traceback.

XML is parsed with defusedxml, a parser built for untrusted XML (the ``urdf``
extra): a document type declaration, and with it any entity (internal ones
are how "billion laughs" bombs work, external ones read other files), is
refused on the parsed document, so in every encoding the parser reads.

Outputs are checked before the work starts (:func:`check_output_file`,
:func:`check_output_dir`) and written under a temporary name that is renamed
once complete (:func:`publish_dir`), so a failure leaves nothing half-written.
"""

from __future__ import annotations

import codecs
import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

from .errors import OutputError, WorkspaceError

if TYPE_CHECKING:
    from xml.etree.ElementTree import Element

__all__ = ["read_text", "read_json", "read_bytes", "read_xml", "parse_xml", "check_output_file", "check_output_dir",
           "publish_dir", "write_files", "figure_formats"]


def read_text(path, parameter: str, *, error: type[WorkspaceError] = WorkspaceError, encoding: str = "utf-8") -> str:
    """The text of the file ``path``; ``error`` (naming ``parameter``) when it cannot be read or is not UTF-8.

    Parameters
    ----------
    path : str or path
        The file.
    parameter : str
        What the file is (``"path"``, ``"answers"``): the message starts with it and the error carries it.
    error : type
        The :class:`~workspace_sym.errors.WorkspaceError` subclass raised (default ``WorkspaceError`` itself).
    encoding : str
        The codec (default ``"utf-8"``; ``"utf-8-sig"`` also drops a byte order mark).  A file it cannot decode is
        reported as not UTF-8 whatever the codec.

    Returns
    -------
    str
        The file's text.

    Raises
    ------
    WorkspaceError
        Of the class ``error``, when the file cannot be read or decoded.

    Examples
    --------
    >>> read_text("/no/such/file.json", "path")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.WorkspaceError: path: cannot read '/no/such/file.json': No such file or directory
    """
    path = Path(path)
    try:
        return path.read_text(encoding=encoding)
    except UnicodeDecodeError as exc:
        raise error(f"{parameter}: {str(path)!r} is not UTF-8 text (byte {exc.object[exc.start]:#04x} at offset "
                    f"{exc.start}); save it as UTF-8", parameter=parameter) from None
    except OSError as exc:
        raise error(f"{parameter}: cannot read {str(path)!r}: {exc.strerror or exc}", parameter=parameter) from None


def read_json(path, parameter: str, *, error: type[WorkspaceError] = WorkspaceError):
    """The JSON value of the file ``path`` (UTF-8); ``error`` for unreadable, invalid or too deeply nested JSON.

    Parameters
    ----------
    path : str or path
        The file.
    parameter : str
        What the file is (``"path"``, ``"answers"``): the message starts with it and the error carries it.
    error : type
        The :class:`~workspace_sym.errors.WorkspaceError` subclass raised (default ``WorkspaceError`` itself).

    Returns
    -------
    object
        The decoded JSON value (dict, list, str, number, bool or None).

    Raises
    ------
    WorkspaceError
        Of the class ``error``, when the file cannot be read, is not UTF-8 or is not valid JSON.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> deep = pathlib.Path(tempfile.mkdtemp()) / "deep.json"
    >>> _ = deep.write_text("[" * 100000 + "]" * 100000)
    >>> read_json(deep, "path")                              # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    workspace_sym.errors.WorkspaceError: path: '...deep.json' is not valid JSON (nested too deeply)
    """
    text = read_text(path, parameter, error=error)
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        reason = f"{exc.msg} at line {exc.lineno}"
    except RecursionError:
        reason = "nested too deeply"
    raise error(f"{parameter}: {str(path)!r} is not valid JSON ({reason})", parameter=parameter)


def read_bytes(path, parameter: str, *, error: type[WorkspaceError] = WorkspaceError) -> bytes:
    """The bytes of the file ``path``; ``error`` (naming ``parameter``) when it cannot be read.

    Parameters
    ----------
    path : str or path
        The file.
    parameter : str
        What the file is (``"path"``, ``"answers"``): the message starts with it and the error carries it.
    error : type
        The :class:`~workspace_sym.errors.WorkspaceError` subclass raised (default ``WorkspaceError`` itself).

    Returns
    -------
    bytes
        The file's content.

    Raises
    ------
    WorkspaceError
        Of the class ``error``, when the file cannot be read.
    """
    try:
        return Path(path).read_bytes()
    except OSError as exc:
        raise error(f"{parameter}: cannot read {str(path)!r}: {exc.strerror or exc}", parameter=parameter) from None


def read_xml(path, parameter: str, *, kind: str, error: type[WorkspaceError] = WorkspaceError) -> Element:
    """The root element of the XML file ``path`` (a ``kind`` file: ``"URDF"``, ``"MJCF"``), parsed as untrusted data.

    See :func:`parse_xml`.

    Parameters
    ----------
    path : str or path
        The file.
    parameter : str
        What the file is (``"path"``, ``"answers"``): the message starts with it and the error carries it.
    kind : str
        The kind of file, for the messages.
    error : type
        The :class:`~workspace_sym.errors.WorkspaceError` subclass raised (default ``WorkspaceError`` itself).

    Returns
    -------
    xml.etree.ElementTree.Element
        The document's root element.

    Raises
    ------
    WorkspaceError
        Of the class ``error``, when the file cannot be read or parsed, as :func:`parse_xml` says.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> bomb = pathlib.Path(tempfile.mkdtemp()) / "bomb.xml"
    >>> _ = bomb.write_text('<!DOCTYPE m [<!ENTITY a "aaaaaaaa">]><mujoco>&a;</mujoco>', encoding="utf-16")
    >>> read_xml(bomb, "path", kind="MJCF")                          # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    workspace_sym.errors.WorkspaceError: path: '...bomb.xml' declares a document type or entities; MJCF needs neither
    """
    return parse_xml(read_bytes(path, parameter, error=error), path, parameter, kind=kind, error=error)


# Byte order marks (XML 1.0, appendix F): a file starting with one is decoded here, whatever its declaration says
# (expat reads UTF-16 but not under the name 'utf-16-be', and no UTF-32).  UTF-32's marks begin with UTF-16's: first.
_BOMS = ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"), (codecs.BOM_UTF8, "utf-8-sig"),
         (codecs.BOM_UTF16_LE, "utf-16"), (codecs.BOM_UTF16_BE, "utf-16"))


def parse_xml(data: bytes, path, parameter: str, *, kind: str, error: type[WorkspaceError] = WorkspaceError) -> Element:
    """The root element of the XML document ``data`` (the bytes of the file ``path``), parsed as untrusted data.

    defusedxml parses it and refuses any document type declaration (so any
    entity) wherever the parser meets it, in UTF-8, UTF-16 or UTF-32 (with
    its byte order mark) or a one-byte encoding its declaration names.  A
    document type, XML that is not well-formed or an encoding the parser does
    not read each raise ``error`` naming ``parameter``, the path and what was
    expected.

    Parameters
    ----------
    data : bytes
        The document.
    path : str or path
        The file it came from, for the messages.
    parameter : str
        What the file is (``"path"``, ``"answers"``): the message starts with it and the error carries it.
    kind : str
        The kind of file (``"URDF"``, ``"MJCF"``), for the messages.
    error : type
        The :class:`~workspace_sym.errors.WorkspaceError` subclass raised (default ``WorkspaceError`` itself).

    Returns
    -------
    xml.etree.ElementTree.Element
        The document's root element.

    Raises
    ------
    WorkspaceError
        Of the class ``error``: a document type or entity, XML that is not well-formed, a byte order mark the
        bytes do not follow, an encoding the parser does not read, or defusedxml not installed.
    """
    try:
        import defusedxml
        from defusedxml.ElementTree import ParseError, fromstring
    except ImportError:
        raise error(f"{parameter}: reading {kind} files needs defusedxml: pip install 'workspace_sym[urdf]'",
                    parameter=parameter) from None
    where = repr(str(path))
    source: bytes | str = data
    for bom, codec in _BOMS:
        if data.startswith(bom):
            try:
                source = data.decode(codec)
            except UnicodeDecodeError as exc:
                name = codec.removesuffix("-sig").upper()
                raise error(f"{parameter}: {where} starts with the byte order mark of {name} but is not {name} text "
                            f"({exc.reason} at byte {exc.start})", parameter=parameter) from None
            break
    try:
        return fromstring(source, forbid_dtd=True)
    except defusedxml.DefusedXmlException:      # before ValueError, which it derives from
        raise error(f"{parameter}: {where} declares a document type or entities; {kind} needs neither",
                    parameter=parameter) from None
    except ParseError as exc:
        raise error(f"{parameter}: {where} is not well-formed XML ({exc})", parameter=parameter) from None
    except ValueError as exc:                   # pyexpat: "multi-byte encodings are not supported"
        raise error(f"{parameter}: {where} is in an encoding the XML parser does not read ({exc}); save it as "
                    "UTF-8", parameter=parameter) from None


def figure_formats() -> tuple[str, ...]:
    """File name extensions matplotlib can write (``png``, ``pdf``, ``svg``, ...).

    Returns
    -------
    tuple of str
        The extensions, without the dot, in alphabetical order.
    """
    from matplotlib.backend_bases import FigureCanvasBase

    return tuple(sorted(FigureCanvasBase.get_supported_filetypes()))


def _writable_dir(directory: Path, parameter: str, path: Path) -> None:
    """Raise unless ``directory`` can hold new files, or can be created (its nearest existing ancestor can)."""
    probe = directory
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir():
        raise OutputError(f"{parameter}: cannot write {str(path)!r}: {str(probe)!r} is not a directory",
                          parameter=parameter)
    if not os.access(probe, os.W_OK | os.X_OK):
        raise OutputError(f"{parameter}: cannot write {str(path)!r}: directory {str(probe)!r} is not writable",
                          parameter=parameter)
    if probe != directory and not _can_create(probe):
        raise OutputError(f"{parameter}: cannot write {str(path)!r}: no directory can be created in {str(probe)!r}",
                          parameter=parameter)


def _can_create(directory: Path) -> bool:
    """Whether a directory can be made in ``directory`` (write bits are not enough: /proc, read-only mounts)."""
    try:
        tempfile.mkdtemp(prefix=".workspace-sym-probe-", dir=directory)
    except OSError:
        return False
    else:
        for probe in directory.glob(".workspace-sym-probe-*"):
            shutil.rmtree(probe, ignore_errors=True)
        return True


def write_npz(path, **arrays) -> Path:
    """Write ``arrays`` to ``path`` as one ``.npz`` (no pickle needed to read it), whole or not at all: under
    ``path.part`` first, then renamed over ``path``, so a reader never meets a half-written file (checkpoints,
    stored sections, reach maps).

    Parameters
    ----------
    path : str or path
        The file.
    **arrays : array_like
        The arrays, by name.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    import numpy as np

    path = Path(path)
    part = path.with_name(path.name + ".part")
    with open(part, "wb") as out:
        np.savez(out, **arrays)
    os.replace(part, path)
    return path


def check_output_file(path, parameter: str, *, formats=None) -> Path:
    """``path`` as a Path, once its directory exists and is writable and its extension is one of ``formats``.

    Called before a long computation, so that a typo in the output path is
    reported at once.  The directory must exist (a figure is not written into
    a directory that nobody created).

    Parameters
    ----------
    path : str or path
        The output file.
    parameter : str
        The argument that named it (``"plot"``), for the message and the error.
    formats : iterable of str, optional
        The extensions accepted, lowercase and without the dot (:func:`figure_formats`); None (the default)
        accepts any name.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    OutputError
        When the extension is not among ``formats``, the directory is missing, not a directory or not writable,
        or ``path`` is a directory.

    Examples
    --------
    >>> check_output_file("/missing/dir/x.png", "plot")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.OutputError: plot: cannot write '/missing/dir/x.png': directory '/missing/dir' does not \
exist
    >>> check_output_file("x.txt", "plot", formats=("pdf", "png"))
    Traceback (most recent call last):
    ...
    workspace_sym.errors.OutputError: plot: cannot write 'x.txt': unknown image format 'txt'; expected a file \
name ending in .pdf, .png
    """
    path = Path(path)
    if formats is not None:
        suffix = path.suffix.lower().lstrip(".")
        if suffix not in formats:
            got = f"unknown image format {suffix!r}" if suffix else "no extension"
            raise OutputError(f"{parameter}: cannot write {str(path)!r}: {got}; expected a file name ending in "
                              + ", ".join(f".{f}" for f in formats), parameter=parameter)
    directory = path.parent
    if not directory.is_dir():
        what = "is not a directory" if directory.exists() else "does not exist"
        raise OutputError(f"{parameter}: cannot write {str(path)!r}: directory {str(directory)!r} {what}",
                          parameter=parameter)
    if path.is_dir():
        raise OutputError(f"{parameter}: cannot write {str(path)!r}: it is a directory", parameter=parameter)
    _writable_dir(directory, parameter, path)
    return path


def check_output_dir(path, parameter: str) -> Path:
    """``path`` as a Path, once it is a writable directory or can be created (before any work is done).

    Parameters
    ----------
    path : str or path
        The output directory; it is not created here.
    parameter : str
        The argument that named it (``"out"``), for the message and the error.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    OutputError
        When ``path`` is a file, or it is missing and cannot be created, or it is not writable.

    Examples
    --------
    >>> check_output_dir("/proc/1/new-report", "out")          # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    workspace_sym.errors.OutputError: out: cannot write '/proc/1/new-report': ...
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{parameter}: cannot write into {str(path)!r}: it is a file, not a directory",
                          parameter=parameter)
    _writable_dir(path, parameter, path)
    return path


def publish_dir(files: Path, out, parameter: str = "out") -> Path:
    """Move the files of the directory ``files`` into ``out`` (created if needed) without leaving it half-filled.

    A new ``out`` is first filled as a hidden sibling and renamed in one step;
    into an existing ``out`` the files are copied as hidden siblings first
    and renamed only once all of them are there.  On failure the hidden
    copies are removed and :class:`OutputError` names ``parameter``.

    Parameters
    ----------
    files : pathlib.Path
        A directory holding the finished files (and directories); it is copied, not emptied.
    out : str or path
        The output directory.
    parameter : str
        The argument that named ``out`` (default ``"out"``), for the message and the error.

    Returns
    -------
    pathlib.Path
        ``out``.

    Raises
    ------
    OutputError
        When ``out`` fails :func:`check_output_dir` or a copy or rename fails.
    """
    out = Path(out)
    check_output_dir(out, parameter)
    staged = []
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        if not out.exists():
            partial = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
            staged.append(partial)
            for item in files.iterdir():
                _copy(item, partial / item.name)
            partial.chmod(0o777 & ~_umask())
            os.rename(partial, out)
            staged.clear()
            return out
        pairs = []
        for item in files.iterdir():
            hidden = out / f".{item.name}.partial"
            staged.append(hidden)
            _copy(item, hidden)
            pairs.append((hidden, out / item.name))
        for hidden, target in pairs:
            if target.is_dir() and not target.is_symlink():
                shutil.rmtree(target)
            os.replace(hidden, target)
        staged.clear()
        return out
    except OSError as exc:
        raise OutputError(f"{parameter}: cannot write into {str(out)!r}: {exc.strerror or exc}",
                          parameter=parameter) from None
    finally:
        for leftover in staged:
            shutil.rmtree(leftover, ignore_errors=True) if leftover.is_dir() else leftover.unlink(missing_ok=True)


def write_files(texts: dict, out, parameter: str = "out") -> dict:
    """Write ``{file name: text}`` into the directory ``out`` as :func:`publish_dir` does: all or nothing.

    Parameters
    ----------
    texts : dict of str to str
        The text of each file (UTF-8), by its name (a plain name, no directory).
    out : str or path
        The output directory (created if needed).
    parameter : str
        The argument that named ``out`` (default ``"out"``), for the message and the error.

    Returns
    -------
    dict of str to pathlib.Path
        ``{file name: path}`` of the files written.

    Raises
    ------
    OutputError
        When ``out`` cannot be written, as for :func:`publish_dir`.
    """
    out = check_output_dir(out, parameter)
    with tempfile.TemporaryDirectory() as tmp:
        for name, text in texts.items():
            (Path(tmp) / name).write_text(text, encoding="utf-8")
        publish_dir(Path(tmp), out, parameter)
    return {name: out / name for name in texts}


def _copy(source: Path, target: Path) -> None:
    if source.is_dir():
        shutil.copytree(source, target)
    else:
        shutil.copyfile(source, target)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
