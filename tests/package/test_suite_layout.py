"""The suite mirrors the package (issue 38 item 8): every test file sits in a folder named on
docs/architecture.md's table of tests, each package of workspace_sym has its folder, and no test file imports
another (what files share is a module of tests/helpers).

Reference: the file tree itself and the page's table, read here."""

import ast
import re

from paths import ROOT

TESTS = ROOT / "tests"
PAGE = (ROOT / "docs" / "architecture.md").read_text()


def _folders_on_the_page():
    section = PAGE.split("## Tests\n", 1)[1].split("\n## ", 1)[0]
    return set(re.findall(r"^\| `tests/(\w+)/` \|", section, re.M))


def test_every_test_file_sits_in_a_folder_the_page_names():
    named = _folders_on_the_page()
    files = sorted(TESTS.rglob("test_*.py"))
    assert len(files) > 50
    assert not [f for f in files if f.parent == TESTS], "a test file at the top of tests/"
    assert {f.parent.name for f in files} == named      # every folder on the page holds tests, and only those


def test_each_package_of_workspace_sym_has_its_test_folder():
    packages = {p.parent.name for p in (ROOT / "workspace_sym").glob("*/__init__.py")}
    assert packages and packages <= _folders_on_the_page(), packages - _folders_on_the_page()


def test_no_test_file_imports_another():
    imported = []
    for path in sorted(TESTS.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            imported += [(path.name, n) for n in names if n.split(".")[0].startswith(("test_", "conftest"))]
    assert not imported
