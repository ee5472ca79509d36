"""docs/architecture.md is true to the code (issue 38 item 7): every module of the package is listed on the page,
every module the page lists exists, and no docstring or comment of the package cites a file the repository does
not ship (the readers once cited an ``INTERFACE.md`` that is not in it).

References: the files of the package on disk, and the repository's own files."""

from __future__ import annotations

import re
from pathlib import Path

import workspace_sym

PACKAGE = Path(workspace_sym.__file__).parent
ROOT = PACKAGE.parent
PAGE = ROOT / "docs" / "architecture.md"


def _modules_on_disk() -> set[str]:
    return {p.relative_to(PACKAGE).as_posix() for p in PACKAGE.rglob("*.py")}


def _modules_on_the_page() -> set[str]:
    """The modules named in the first cell of the page's tables, under the section of their package."""
    listed: set[str] = set()
    package = None
    for line in PAGE.read_text(encoding="utf-8").splitlines():
        header = re.match(r"### `workspace_sym/(.*)`", line)
        if header:
            package = header.group(1)
            continue
        if line.startswith("## "):
            package = None
        if package is None or not line.startswith("| `"):
            continue
        first = line.split("|")[1]
        for name in re.findall(r"`([\w/]+\.py)`", first):
            listed.add(f"{package}{name}")
    return listed


def test_every_module_is_on_the_page():
    missing = sorted(_modules_on_disk() - _modules_on_the_page())
    assert missing == [], f"modules the architecture page does not list: {missing}"


def test_every_module_on_the_page_exists():
    stale = sorted(_modules_on_the_page() - _modules_on_disk())
    assert stale == [], f"modules the architecture page lists that are not in the package: {stale}"


CITED = re.compile(r"(?<![\w./-])((?:[\w-]+/)+[\w.-]+\.(?:md|py|json|ipynb|toml)|[A-Z][A-Z_]+\.md)\b")


# Paths that are not the repository's: where a report is written (its ``out`` argument), SymPy's own source.
ELSEWHERE = ("out/", "sympy/")


def test_no_docstring_cites_a_file_the_repository_does_not_ship():
    absent = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for cited in CITED.findall(path.read_text(encoding="utf-8")):
            candidates = [ROOT / cited, ROOT / "docs" / cited, PACKAGE / cited, path.parent / cited]
            if not cited.startswith(ELSEWHERE) and not any(c.exists() for c in candidates):
                absent.append(f"{path.relative_to(ROOT)}: {cited}")
    assert absent == [], f"files cited that the repository does not ship: {absent}"
