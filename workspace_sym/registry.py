"""Providers a lower layer hands work to without importing them, declared by the package's face.

The symbolic core builds robots (:class:`~workspace_sym.kinematics.DHRobot`) that the readers and the reach engine
build on, so it must never import them; yet ``DHRobot.from_urdf`` needs a reader and ``DHRobot.reach`` the engine.
Each provider registers its functions in the core's own tables (``kinematics.READERS``, ``kinematics.ENGINES``)
when it is imported.  The package's face, the one module that knows every layer, declares here which module
provides what (:func:`declare`), so that a table still empty when it is first used is filled by importing the
declared module (:func:`load`), however the caller reached the core (``import workspace_sym``, or
``from workspace_sym.kinematics import DHRobot``).  This is a plugin table, like a package's entry points: the
core names no provider.

>>> declare("example", "json")
>>> load("example").__name__
'json'
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["declare", "load", "declared"]

_PROVIDERS: dict[str, str] = {}


def declare(name: str, module: str) -> None:
    """Declare that the module ``module`` (a dotted name) provides ``name``.

    Parameters
    ----------
    name : str
        What is provided (``"readers"``, ``"engines"``).
    module : str
        The dotted name of the module that registers it when imported.
    """
    _PROVIDERS[name] = module


def declared() -> dict[str, str]:
    """The providers declared so far, by name.

    Returns
    -------
    dict
        ``{name: dotted module name}``.
    """
    return dict(_PROVIDERS)


def load(name: str) -> ModuleType:
    """Import the module declared for ``name`` (it registers what it provides as it is imported).

    Parameters
    ----------
    name : str
        A name passed to :func:`declare`.

    Returns
    -------
    module
        The provider's module.

    Raises
    ------
    LookupError
        No provider was declared for ``name``.
    """
    try:
        module = _PROVIDERS[name]
    except KeyError:
        raise LookupError(f"no provider of {name!r} is declared (workspace_sym's __init__ declares them)") from None
    return importlib.import_module(module)
