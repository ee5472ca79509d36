"""Exceptions of workspace_sym: every exception class of the package is defined here.

Every error a user can provoke with bad input derives from :class:`WorkspaceError`,
and its message names the parameter, the value received and what was expected.
The command line turns any of them into exit status 2 and one line on stderr.

Three classes are not bad input but a bounded stage giving up, which its caller
catches and answers otherwise: :class:`OverBudget` (an expansion would grow
past its budget), :class:`CoverTooLarge` (a critical set needs too many
joint boxes) and :class:`CoverStopped` (a budget ran out during a critical
cover).  Modules that raised them first still re-export them
(``workspace_sym.interval.image.CoverTooLarge`` is this class).

Two errors are also the standard exception of their kind, so that a caller
who catches that kind catches them: :class:`SymbolicBudgetError` is a
:class:`TimeoutError`, :class:`MissingExtraError` an :class:`ImportError`.
"""

from __future__ import annotations

__all__ = [
    "WorkspaceError",
    "InvalidParameterError",
    "DHTableError",
    "URDFError",
    "MJCFError",
    "ExpressionError",
    "JointLimitError",
    "UnknownNameError",
    "ConstraintError",
    "BoxError",
    "OutputError",
    "MissingExtraError",
    "WorkerResultError",
    "OverBudget",
    "CoverTooLarge",
    "CoverStopped",
    "Refused",
    "BudgetExpired",
    "BoundaryError",
    "SymbolicError",
    "SymbolicBudgetError",
]


class WorkspaceError(ValueError):
    """Root of every error raised by workspace_sym for bad input.

    ``parameter``, when the raiser knows it, is the name of the function
    argument that was bad (``"delta"``, ``"max_boxes"``): the message speaks
    of the API, and the command line uses ``parameter`` to name its option.

    Parameters
    ----------
    *args
        The arguments of :class:`ValueError`: in this package, one string, the message.
    parameter : str or None, optional
        The name of the bad argument; None (the default) when no one argument is to blame.

    Examples
    --------
    >>> err = WorkspaceError("delta must be a positive finite number; got -1", parameter="delta")
    >>> err.parameter, str(err)
    ('delta', 'delta must be a positive finite number; got -1')
    >>> WorkspaceError("no parameter to blame").parameter is None
    True
    """

    def __init__(self, *args, parameter: str | None = None):
        super().__init__(*args)
        self.parameter = parameter


class InvalidParameterError(WorkspaceError):
    """A scalar option is outside its allowed range or set.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class DHTableError(WorkspaceError):
    """A Denavit-Hartenberg row or file is malformed.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class URDFError(DHTableError):
    """A URDF file cannot be read as a serial chain (unreadable, xacro, branching, unsupported joint).

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class MJCFError(DHTableError):
    """A MuJoCo model cannot be read as a serial chain (malformed number, ball or free joint, unknown body).

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class ExpressionError(WorkspaceError):
    """A string could not be read as a SymPy expression.

    ``position``, when the reader knows it, is the 1-based column of the text
    where the problem is (a student's answer is told where it went wrong).

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    position : int or None, optional
        The 1-based column of the text where the problem is; None (the default) when unknown.
    """

    def __init__(self, *args, parameter: str | None = None, position: int | None = None):
        super().__init__(*args, parameter=parameter)
        self.position = position


class JointLimitError(WorkspaceError):
    """Joint limits are inverted, non-finite or outside their range.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class UnknownNameError(WorkspaceError):
    """A name (robot, convention, backend, ...) is not among the allowed ones.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class ConstraintError(ExpressionError):
    """A constraint is not an inequality or uses unknown symbols.

    A constraint is an expression read from user text like any other, so this
    is an :class:`ExpressionError`: ``except ExpressionError`` catches every
    unreadable input.

    Parameters
    ----------
    *args, parameter, position
        As for :class:`ExpressionError`: the message, the name of the bad argument and the 1-based column of the
        text where the problem is (each None when unknown).
    """


class BoxError(WorkspaceError):
    """A box has inverted or non-finite bounds.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class BoundaryError(WorkspaceError):
    """The exact boundary of a planar chain could not be computed reliably for these inputs (it would contradict
    a property every chain has): refused rather than answered wrongly.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class MissingExtraError(WorkspaceError, ImportError):
    """An optional dependency is not installed (distributed runs need dask.distributed:
    ``pip install 'workspace_sym[distributed]'``); also an :class:`ImportError`.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).

    Examples
    --------
    >>> issubclass(MissingExtraError, ImportError)
    True
    """


class WorkerResultError(WorkspaceError):
    """A worker of ``executor`` sent back something other than what its task can produce (wrong type, dtype or
    shape, non-finite bounds, boxes outside the chunk it was given): refused rather than stored as a proof.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class OverBudget(Exception):
    """A bounded stage gave up: its input would grow past its budget (terms, degree or time)."""


class CoverTooLarge(RuntimeError):
    """The critical sets need more than ``image.MAX_COVER_BOXES`` joint boxes at once."""


class CoverStopped(Exception):
    """A budget ran out between two generations of a critical cover (nothing is decided from it).

    Parameters
    ----------
    evaluated : int
        The number of joint boxes evaluated before the stop.
    reason : str
        Why it stopped; also the exception's message.
    """

    def __init__(self, evaluated: int, reason: str):
        super().__init__(reason)
        self.evaluated, self.reason = evaluated, reason


class Refused(Exception):
    """The expression reader met something its grammar does not take (a name, a function, an operator, a number
    out of range); it says what, and the reader turns it into an :class:`ExpressionError` naming the text."""


class BudgetExpired(BaseException):
    """Raised by the timer of :func:`~workspace_sym.symbolic.symbolic_budget` inside SymPy's own code; a
    ``BaseException``, so that no ``except Exception`` on the way swallows it (the budget's block turns it into
    :class:`SymbolicBudgetError`)."""


class OutputError(WorkspaceError):
    """An output path cannot be written (missing or unwritable directory, unknown figure format).

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class SymbolicError(WorkspaceError):
    """A symbolic derivation (forward kinematics, a Jacobian, its singular factors, a characteristic
    polynomial) could not be carried out on this input; the message names what could not be done.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).
    """


class SymbolicBudgetError(SymbolicError, TimeoutError):
    """A symbolic step did not finish within its budget (time, or the size of an expansion or a table); also a
    :class:`TimeoutError`, so ``except TimeoutError`` catches it.

    Parameters
    ----------
    *args, parameter
        As for :class:`WorkspaceError`: the message, and the name of the bad argument (None when unknown).

    Examples
    --------
    >>> issubclass(SymbolicBudgetError, TimeoutError) and issubclass(SymbolicBudgetError, WorkspaceError)
    True
    """


def check_choice(parameter: str, value, allowed) -> None:
    """Raise :class:`UnknownNameError` unless ``value`` is one of ``allowed``.

    Examples
    --------
    >>> check_choice("backend", "numpy", ("numpy", "mpmath"))
    >>> check_choice("backend", "gpu", ("numpy", "mpmath"))
    Traceback (most recent call last):
    ...
    workspace_sym.errors.UnknownNameError: backend must be one of 'numpy', 'mpmath'; got 'gpu'
    """
    if value not in allowed:
        choices = ", ".join(repr(a) for a in allowed)
        raise UnknownNameError(f"{parameter} must be one of {choices}; got {value!r}", parameter=parameter)
