"""The house holds its shape (issue 38 item 2): the package's module graph, imports inside functions counted,
has no circle, no import up the layers, and no private name taken from another module.

Layers, lowest first (docs/architecture.md draws them): base, reading text, the symbolic core and the interval
engine, the readers, the domain engines, teaching, presentation, and the package's face.  A module may import
modules of its own layer or of lower ones.  A lower layer that must reach a higher one at run time is reached
by registration (the presentation registers its notebook HTML with IPython; the readers fill the robot's
registry of readers), never by an import.  Reference: the module graph read from the sources with ``ast``
(``from . import``, ``from .x import``, ``import workspace_sym.x``, at any depth), resolved to files.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

import workspace_sym

PACKAGE = Path(workspace_sym.__file__).parent

# The layer of each module or package (its first dotted part, or the module itself); the modules kept at their
# earlier paths for one release (thin re-exports) sit on the layer of what they re-export.
LAYER = {
    "errors": 0, "numbers": 0, "progress": 0, "files": 0, "transforms": 0, "version": 0, "document": 0, "registry": 0,
    "expressions": 1, "snap": 1,
    "symbolic": 2, "charpoly": 2, "kinematics": 2, "codegen": 2, "interval": 2,
    "readers": 3, "dh_file": 3, "urdf": 3, "mjcf": 3,
    "serial": 4, "serial_workspace": 4, "reach_section": 4, "reach_turn": 4, "orientation": 4,
    "planar": 4, "arrangement": 4, "boundary": 4, "exact": 4, "parallel": 4, "orthoglide": 4, "sampling": 4,
    "robots": 4,
    "teaching": 5, "answers": 5, "verify": 5, "grading": 5, "exercises": 5,
    "display": 6, "plotting": 6, "report": 6, "cli": 6, "__main__": 6,
    "__init__": 7,
}


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE).with_suffix("")
    parts = list(rel.parts)
    return ".".join(parts)


@functools.cache
def _modules() -> dict[str, Path]:
    """The package's modules by dotted name (read once: ``_resolve`` asks at every import)."""
    return {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _resolve(importer: str, node: ast.ImportFrom) -> list[str]:
    """The package modules an ``ImportFrom`` reaches: ``from .x import y`` is module ``x`` (or ``x.y`` when that
    is a module)."""
    package = importer.split(".")[:-1]          # the package holding the importer (an __init__ is in its own)
    if node.level:
        base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
        target = [*base, *(node.module.split(".") if node.module else [])]
    elif node.module and node.module.split(".")[0] == "workspace_sym":
        target = node.module.split(".")[1:]
    else:
        return []
    modules = _modules()
    out = []
    for alias in node.names:
        candidate = ".".join([*target, alias.name])
        if candidate in modules or f"{candidate}.__init__" in modules:
            out.append(candidate if candidate in modules else f"{candidate}.__init__")
        else:
            name = ".".join(target) if target else "__init__"
            out.append(name if name in modules else f"{name}.__init__")
    return out


@functools.cache
def _edges() -> tuple:
    """``(importer, imported, names)`` for every import of a package module by another, at any depth (the sources
    parsed once for the three tests of the graph)."""
    return tuple(_each_edge())


def _each_edge():
    modules = _modules()
    for name, path in modules.items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                for target in _resolve(name, node):
                    if target != name:
                        yield name, target, [a.name for a in node.names]
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    parts = alias.name.split(".")
                    if parts[0] == "workspace_sym" and len(parts) > 1:
                        target = ".".join(parts[1:])
                        yield name, target if target in modules else f"{target}.__init__", []


def _layer(module: str) -> int:
    head = module.split(".")[0]
    return LAYER[head]


def test_every_module_has_a_layer():
    unplaced = sorted(m for m in _modules() if m.split(".")[0] not in LAYER)
    assert unplaced == [], f"modules with no layer (add them to LAYER and docs/architecture.md): {unplaced}"


def test_no_import_runs_up_the_layers():
    upward = sorted({(a, b) for a, b, _ in _edges() if _layer(a) < _layer(b)})
    assert upward == [], f"imports from a lower layer to a higher one: {upward}"


def test_no_private_name_is_taken_from_another_module():
    private = sorted({(a, b, n) for a, b, names in _edges() for n in names if n.startswith("_")
                      and not n.startswith("__")})
    assert private == [], f"private names imported across modules: {private}"


def test_the_module_graph_has_no_circle():
    graph: dict[str, set[str]] = {}
    for a, b, _ in _edges():
        graph.setdefault(a, set()).add(b)
    index, low, stack, on, circles, counter = {}, {}, [], set(), [], [0]

    def strong(v):                        # Tarjan's strongly connected components
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for v in list(graph):
        if v not in index:
            strong(v)
    assert circles == [], f"circles in the module graph: {circles}"


@pytest.mark.parametrize("module", ["scipy", "matplotlib", "IPython", "tqdm", "lark", "dask", "yourdfpy", "xacro",
                                    "mujoco", "defusedxml"])
def test_import_workspace_sym_loads_no_heavy_library(module):
    """``import workspace_sym`` stays cheap (issue 38 item 6): the heavy libraries are imported where used.
    Reference: a fresh interpreter's ``sys.modules`` after the import."""
    import subprocess
    import sys

    code = f"import sys, workspace_sym; print({module!r} in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "False"
