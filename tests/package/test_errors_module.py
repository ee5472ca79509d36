"""Every exception class of workspace_sym lives in :mod:`workspace_sym.errors` (issue 26 item 5).

Reference: the package itself, imported module by module -- any exception class a module defines is found by
walking the package, so a new error class defined elsewhere fails here.
"""

import importlib
import inspect
import pkgutil
import re

import pytest

import workspace_sym
from paths import ROOT
from workspace_sym import errors

ARCHITECTURE = ROOT / "docs" / "architecture.md"


def _modules():
    """Every module of the package (``__main__`` would run the command line, so it is left out)."""
    yield workspace_sym
    for info in pkgutil.walk_packages(workspace_sym.__path__, prefix="workspace_sym."):
        if info.name.rsplit(".", 1)[-1] != "__main__":
            yield importlib.import_module(info.name)


def _exception_classes():
    """``{(module name, attribute name): class}`` for every public exception class reachable from a module."""
    found = {}
    for module in _modules():
        for name, value in vars(module).items():
            if inspect.isclass(value) and issubclass(value, BaseException) and value.__module__.startswith(
                    "workspace_sym") and not name.startswith("_"):
                found[(module.__name__, name)] = value
    return found


def test_every_public_exception_class_is_defined_in_errors_and_exported():
    found = _exception_classes()
    assert found, "no exception class found: the walk over the package is broken"
    elsewhere = sorted(f"{module}.{name}" for (module, name), cls in found.items()
                       if cls.__module__ != "workspace_sym.errors")
    assert not elsewhere, f"exception classes defined outside workspace_sym/errors.py: {elsewhere}"
    missing = sorted({cls.__name__ for cls in found.values()} - set(errors.__all__))
    assert not missing, f"exception classes missing from errors.__all__: {missing}"


def test_every_workspace_error_subclass_is_importable_from_errors_and_documented():
    subclasses, queue = set(), [errors.WorkspaceError]
    while queue:                                    # the whole tree of subclasses, not just the direct children
        for sub in queue.pop().__subclasses__():
            if sub.__module__.startswith("workspace_sym") and not sub.__name__.startswith("_"):
                subclasses.add(sub)
                queue.append(sub)
    assert errors.MissingExtraError in subclasses
    table = ARCHITECTURE.read_text(encoding="utf-8")
    row = next(line for line in table.splitlines() if line.startswith("| `errors.py` |"))
    for cls in sorted(subclasses | {errors.WorkspaceError}, key=lambda c: c.__name__):
        assert getattr(errors, cls.__name__) is cls, cls
        assert cls.__name__ in errors.__all__, cls
        assert (cls.__doc__ or "").strip(), f"{cls.__name__} has no docstring"
        assert re.search(rf"`{cls.__name__}`", row), f"{cls.__name__} is not in docs/architecture.md's errors row"


@pytest.mark.parametrize(("module", "name"), [
    ("workspace_sym.interval.image", "CoverTooLarge"),
    ("workspace_sym.interval.executor", "MissingExtraError"),
    ("workspace_sym.interval.compiler", "OverBudget"),
])
def test_old_locations_reexport_the_same_class(module, name):
    """Code that imported an error from where it used to be defined still catches the same class."""
    assert getattr(importlib.import_module(module), name) is getattr(errors, name)
    assert name in importlib.import_module(module).__all__


def test_every_name_in_errors_all_is_documented():
    row = next(line for line in ARCHITECTURE.read_text(encoding="utf-8").splitlines()
               if line.startswith("| `errors.py` |"))
    for name in errors.__all__:
        obj = getattr(errors, name)
        assert (obj.__doc__ or "").strip(), name
        assert f"`{name}`" in row, name
