"""Every public function, class and method says what it takes, gives and refuses (issue 38 item 7).

Public: a name in a module's ``__all__`` defined in that module, and the public methods and properties of its
classes.  Reference: numpydoc's own validator (``numpydoc.validate``, the checker of the field's docstring
standard), for the sections it can check: a docstring at all (GL08), every parameter documented (PR01) and no
parameter documented that is not one (PR02), a ``Returns`` section for a function that returns something (RT01);
and, written here, a ``Raises`` section for a function that raises one of the package's errors itself.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
import textwrap

import pytest
from numpydoc import validate as numpydoc_validate

import workspace_sym
from workspace_sym import errors

CHECKED = {"GL08", "PR01", "PR02", "RT01"}
ERRORS = set(errors.__all__)


def _public() -> dict[str, object]:
    found: dict[str, object] = {}
    for info in pkgutil.walk_packages(workspace_sym.__path__, "workspace_sym."):
        if info.name.endswith("__main__"):
            continue
        module = importlib.import_module(info.name)
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name, None)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)) or obj.__module__ != module.__name__:
                continue
            found[f"{module.__name__}.{name}"] = obj
            if inspect.isclass(obj):
                for key, value in vars(obj).items():
                    if not key.startswith("_") and (inspect.isfunction(value)
                                                   or isinstance(value, (classmethod, staticmethod, property))):
                        found[f"{module.__name__}.{name}.{key}"] = value
    return found


PUBLIC = _public()


def _own_nodes(node):
    """The nodes of a definition's own body: nested functions, lambdas and classes are not entered."""
    for child in ast.iter_child_nodes(node):
        if not isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            yield child
            yield from _own_nodes(child)


def _raises_own_error(obj) -> bool:
    """The function's own body (not a nested function's) raises one of the package's errors; for a class, the
    body of its ``__init__`` or ``__post_init__`` (what its constructor documents)."""
    if inspect.isclass(obj):
        return any(_raises_own_error(vars(obj)[name]) for name in ("__init__", "__post_init__") if name in vars(obj))
    function = obj.fget if isinstance(obj, property) else getattr(obj, "__func__", obj)
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(function)))
    except (OSError, TypeError):
        return False
    return any(isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call) and isinstance(node.exc.func, ast.Name)
               and node.exc.func.id in ERRORS for node in _own_nodes(tree.body[0]))


def test_the_public_api_is_large_enough_to_be_worth_counting():
    assert len(PUBLIC) > 500


@pytest.mark.parametrize("name", sorted(PUBLIC))
def test_every_public_definition_has_its_numpydoc_sections(name):
    report = numpydoc_validate.validate(name)
    missing = sorted((code, text) for code, text in report["errors"] if code in CHECKED)
    assert missing == [], f"{name}: {missing}"
    if _raises_own_error(PUBLIC[name]):
        assert "Raises\n" in (report.get("docstring") or inspect.getdoc(PUBLIC[name]) or ""), \
            f"{name} raises an error of workspace_sym.errors: its docstring needs a Raises section"
