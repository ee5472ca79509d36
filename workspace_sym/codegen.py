"""C source for a robot's forward kinematics and geometric Jacobian, generated from its SymPy expressions.

The formulas are the robot's own: ``robot.fk()`` (base and tool included) and
``robot.geometric_jacobian``, with the numeric parameter values substituted.
Common subexpressions are shared with :func:`sympy.cse`, and every line is
printed by SymPy's C printer (:class:`sympy.printing.c.C99CodePrinter`) from a
:mod:`sympy.codegen.ast` tree; nothing here formats an expression by hand.  The
generated functions allocate nothing and keep no state::

    void fk(const double *q, double *T);        /* T: 4 x 4, row-major */
    void jacobian(const double *q, double *J);  /* J: 6 x n, row-major */

``q`` holds the joint values in the robot's order (radians for revolute
joints, the table's length unit for prismatic ones); the header's comment
says which variable each ``q[k]`` is and, for a robot read from a URDF or MJCF
file, which joint of the file (``q[0] = theta1 = joint 'shoulder'``).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import sympy as sp
from sympy.codegen.ast import (
    Assignment,
    CodeBlock,
    Declaration,
    FunctionDefinition,
    FunctionPrototype,
    Pointer,
    Type,
    Variable,
    float64,
    value_const,
)
from sympy.printing.c import C99CodePrinter, get_math_macros

from .errors import InvalidParameterError, WorkspaceError, check_choice

__all__ = ["LANGUAGES", "c_code", "write_code"]

LANGUAGES = ("c",)

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def _stem(name: str) -> str:
    """A file stem and C identifier from a robot name (untrusted text): letters, digits and underscores only."""
    stem = re.sub(r"[^A-Za-z0-9]+", "_", name)[:64].strip("_") or "robot"
    return stem if not stem[0].isdigit() else f"robot_{stem}"


def _comment(text) -> str:
    """``text`` safe inside a C block comment: printable ASCII, no ``*/`` (which would end it) and no ``/*`` (which
    -Wcomment reports, an error under -Werror)."""
    text = "".join(ch if " " <= ch <= "~" else "?" for ch in str(text))
    return text.replace("*/", "* /").replace("/*", "/ *")


def _numeric(robot, expr: sp.Matrix, what: str) -> sp.Matrix:
    """``expr`` with the robot's parameter values substituted; every other symbol but the joints is an error."""
    M = sp.Matrix(robot.substitute(expr))
    free = sorted(map(str, M.free_symbols - set(robot.q)))
    if free:
        raise InvalidParameterError(
            f"parameters: the {what} of {robot.name!r} needs numeric values for {', '.join(free)} to become C code; "
            f"give them in the DH file's \"parameters\" or in DHRobot(parameters={{...}})", parameter="parameters")
    return M


def _function(name: str, M: sp.Matrix, robot, output: str) -> FunctionDefinition:
    """``void name(const double *q, double *output)`` filling ``output`` row-major with the entries of ``M``."""
    q = sp.MatrixSymbol("q", robot.n, 1)
    M = M.xreplace({v: q[k, 0] for k, v in enumerate(robot.q)})
    out = sp.MatrixSymbol(output, M.rows, M.cols)
    temps, (reduced,) = sp.cse(M, symbols=sp.numbered_symbols("w"))
    body = [Declaration(Variable(w, type=float64, attrs={value_const}, value=e)) for w, e in temps]
    body += [Assignment(out[i, j], reduced[i, j]) for i in range(M.rows) for j in range(M.cols)]
    return FunctionDefinition(Type("void"), name, [Pointer("q", type=float64, attrs={value_const}),
                                                   Pointer(output, type=float64)], CodeBlock(*body))


def _macro_guards(code: str) -> str:
    """``#define`` fallbacks for the ``math.h`` constants (``M_PI``, ``M_SQRT2``) the code uses: they are POSIX,
    not ISO C, and a strict ``-std=c99`` leaves them undefined."""
    macros = {}
    for value, macro in get_math_macros().items():   # SymPy's own table of the macros its printer writes
        if macro not in macros and re.search(rf"\b{macro}\b", code):
            macros[macro] = sp.N(value, 21)
    return "\n".join(f"#ifndef {m}\n#define {m} {v}\n#endif" for m, v in macros.items())


def c_code(robot, *, prefix: str = "") -> dict[str, str]:
    """The C header and source of ``robot``'s forward kinematics and geometric Jacobian, in memory.

    The functions are ``<prefix>fk`` and ``<prefix>jacobian``
    (a ``prefix`` such as ``"ur5_"`` lets several robots share one program).
    Numeric parameter values (``robot.parameters``) are substituted; a symbolic
    length without a value raises :class:`InvalidParameterError` naming it.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    prefix : str
        Put in front of the function names: empty (the default) or a C identifier.

    Returns
    -------
    dict of str to str
        ``{"<stem>.h": header, "<stem>.c": source}``, the stem made from the robot's name (letters, digits and
        underscores only; ``"robot"`` when nothing is left).

    Raises
    ------
    InvalidParameterError
        When ``prefix`` is not empty or a C identifier, or when the forward kinematics or the Jacobian keeps a
        symbol other than the joint variables (a parameter without a value).

    Examples
    --------
    >>> from workspace_sym import DHJoint, DHRobot
    >>> arm = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=sp.Rational(1, 2))], name="arm")
    >>> files = c_code(arm)
    >>> sorted(files)
    ['arm.c', 'arm.h']
    >>> fk = files["arm.c"].split("void fk")[1].split("}")[0]
    >>> [line.strip() for line in fk.splitlines() if "w0 =" in line or "T[3]" in line]
    ['const double w0 = q[0] + q[1];', 'T[3] = (1.0/2.0)*w1 + cos(q[0]);']
    >>> c_code(DHRobot([DHJoint.revolute(1, a=sp.Symbol("l1"))], name="arm"))
    Traceback (most recent call last):
    ...
    workspace_sym.errors.InvalidParameterError: parameters: the forward kinematics of 'arm' needs numeric values \
for l1 to become C code; give them in the DH file's "parameters" or in DHRobot(parameters={...})
    """
    if not isinstance(prefix, str) or (prefix and not _IDENTIFIER.match(prefix)):
        raise InvalidParameterError(f"prefix must be empty or a C identifier (letters, digits, underscores, not "
                                    f"starting with a digit); got {prefix!r}", parameter="prefix")
    T = _numeric(robot, robot.fk(), "forward kinematics")
    J = _numeric(robot, robot.geometric_jacobian, "Jacobian")
    printer = C99CodePrinter()
    functions = [_function(f"{prefix}fk", T, robot, "T"), _function(f"{prefix}jacobian", J, robot, "J")]
    definitions = "\n\n".join(printer.doprint(f) for f in functions)
    prototypes = "\n".join(printer.doprint(FunctionPrototype.from_FunctionDefinition(f)) + ";" for f in functions)
    stem = _stem(robot.name)
    guard, count = f"WORKSPACE_SYM_{stem.upper()}_H", f"{stem.upper()}_N_JOINTS"
    from .version import __version__

    kinds = {"R": "revolute, rad", "P": f"prismatic, {_comment(robot.units)}"}
    # a robot read from a URDF or MJCF file: q[k] is also named by the file's joint, whose position it is
    variables = ", ".join(f"q[{k}] = {_comment(v)}" + (f" = joint '{_comment(j.name)}'" if j.name else "")
                          + f" ({kinds[j.kind]})" for k, (v, j) in enumerate(zip(robot.q, robot.joints)))
    params = ", ".join(f"{_comment(k)} = {v!r}" for k, v in robot.parameters.items()) or "none"
    about = (f"/* Generated by workspace_sym {__version__} for robot '{_comment(robot.name)}': {robot.n} joints, "
             f"{robot.convention} DH, lengths in {_comment(robot.units)}.\n"
             f" * Joint vector: {variables}.\n"
             f" * Parameters substituted: {params}.\n")
    header = (about +
              f" * {prefix}fk: T = base * A_1 * ... * A_n * tool, 4 x 4 row-major, T[4*i + j].\n"
              f" * {prefix}jacobian: geometric Jacobian of the tool point in the base frame, 6 x {robot.n} row-major,\n"
              f" *   J[{robot.n}*i + k]: rows 0-2 linear velocity, rows 3-5 angular velocity, column k joint k.\n"
              " * No allocation, no global state: safe to call from any thread. */\n"
              f"#ifndef {guard}\n#define {guard}\n\n"
              f"#define {count} {robot.n}\n\n"
              "#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n"
              f"{prototypes}\n\n"
              "#ifdef __cplusplus\n}\n#endif\n\n"
              f"#endif /* {guard} */\n")
    guards = _macro_guards(definitions)
    source = (about + " * The declarations are in " + stem + ".h. */\n"
              f"#include <math.h>\n#include \"{stem}.h\"\n\n"
              + (guards + "\n\n" if guards else "")
              + definitions + "\n")
    return {f"{stem}.h": header, f"{stem}.c": source}


def write_code(robot, out, *, lang: str = "c", prefix: str = "") -> list[Path]:
    """Write the generated code of ``robot`` (``lang="c"``: :func:`c_code`) into directory ``out``.

    Everything is generated in memory first, then each file is written under a
    temporary name and renamed: an error leaves no file half-written.

    Parameters
    ----------
    robot : DHRobot
        The robot.
    out : str or path
        The output directory, created when missing.
    lang : str
        The language, one of :data:`LANGUAGES` (default ``"c"``).
    prefix : str
        As for :func:`c_code`.

    Returns
    -------
    list of pathlib.Path
        The paths written, header first.

    Raises
    ------
    UnknownNameError
        When ``lang`` is not one of :data:`LANGUAGES`.
    WorkspaceError
        When ``out`` is a file, cannot be created or cannot be written into (``parameter="out"``).
    InvalidParameterError
        As for :func:`c_code`.
    """
    check_choice("lang", lang, LANGUAGES)
    out = Path(out)
    if out.exists() and not out.is_dir():   # before the derivation, which takes seconds
        raise WorkspaceError(f"out: expected a directory; {str(out)!r} is a file", parameter="out")
    files = c_code(robot, prefix=prefix)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise WorkspaceError(f"out: cannot create the directory {str(out)!r}: {exc.strerror}",
                             parameter="out") from exc
    paths, partial = [out / name for name in files], []
    try:
        for path, text in zip(paths, files.values()):
            tmp = path.with_name(f".{path.name}.partial")
            partial.append(tmp)
            tmp.write_text(text)
        for tmp, path in zip(partial, paths):
            os.replace(tmp, path)
    except OSError as exc:
        raise WorkspaceError(f"out: cannot write into {str(out)!r}: {exc.strerror}", parameter="out") from exc
    finally:
        for tmp in partial:
            tmp.unlink(missing_ok=True)
    return paths
