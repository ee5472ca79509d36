"""Sphinx configuration of the documentation site (``make docs``; issue 39).

The site is built from the package's numpydoc docstrings (autodoc, autosummary, numpydoc) and from the Markdown
guides of docs/ and the README (myst-parser), which each page of this folder includes.  Notebooks are left out:
they are executed and exported by ``make notebooks`` instead.  Warnings are errors (``sphinx-build -W``).
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))          # the worktree's package, before any installed copy

from workspace_sym.version import __version__  # noqa: E402

project = "workspace_sym"
author = "workspace_sym contributors"
copyright = "workspace_sym contributors"
release = version = __version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build"]

# autodoc and autosummary: one page per name of the flat API (api/index), members in source order
autosummary_generate = True
autosummary_imported_members = False
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
# defaults as written in the source (``tuning=DEFAULT``), not the repr of a frozen dataclass with 25 fields
autodoc_preserve_defaults = True
autodoc_default_options = {"members": True, "show-inheritance": False}

# numpydoc renders the Parameters / Returns / Raises sections; class members are listed by autodoc itself
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# MyST: the guides' headings get anchors; $...$ and $$...$$ are maths
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

html_theme = "alabaster"
html_title = f"workspace_sym {release}"
html_static_path: list[str] = []
# signatures run long (keyword-only options): a wider page than alabaster's 940 px
html_theme_options = {"page_width": "1240px", "sidebar_width": "280px"}


def _readme_links(app, relative_path, parent_docname, content):
    """The README links the guides as ``docs/NAME.md`` (right on GitHub); on the site they are pages beside it."""
    if relative_path.name == "README.md":
        content[0] = content[0].replace("](docs/", "](")


def setup(app):
    app.connect("include-read", _readme_links)
