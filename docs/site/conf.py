"""Sphinx configuration of the documentation site (``make docs``; issue 39).

The site is built from the package's numpydoc docstrings (autodoc, autosummary, numpydoc) and from the Markdown
guides of docs/ and the README (MyST, through myst-nb), which each page of this folder includes, and from the
notebooks of notebooks/: copied into docs/site/notebooks/ (a generated folder, ignored by git) when the build starts,
executed by myst-nb (cached: a notebook whose code did not change is not run again) and shown with their outputs.
Warnings are errors (``sphinx-build -W``), and so is a notebook that fails (``nb_execution_raise_on_error``).
"""

import os
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))          # the worktree's package, before any installed copy
# the notebooks' kernels are other processes: they import the worktree's package too
os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p)

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
    "myst_nb",  # MyST Markdown (myst-parser) and the notebooks
]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "**/.ipynb_checkpoints"]

# myst-nb: the notebooks are executed when their code changed since the last build (a jupyter-cache next to the
# output folder), each within 300 s; an error in a cell fails the build.  The test suite builds with
# ``-D nb_execution_mode=off`` (the pages then show the code without outputs).
nb_execution_mode = "cache"
nb_execution_timeout = 300
nb_execution_raise_on_error = True
NOTEBOOKS = ROOT / "notebooks"
SITE_NOTEBOOKS = Path(__file__).resolve().parent / "notebooks"

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


def _copy_notebooks(app, config):
    """notebooks/*.ipynb into docs/site/notebooks/, where Sphinx reads its sources; an unchanged copy is left alone
    (its date would make Sphinx read it again) and a notebook no longer in notebooks/ is removed."""
    SITE_NOTEBOOKS.mkdir(exist_ok=True)
    sources = {path.name: path for path in NOTEBOOKS.glob("*.ipynb")}
    for stale in SITE_NOTEBOOKS.glob("*.ipynb"):
        if stale.name not in sources:
            stale.unlink()
    for name, source in sources.items():
        copy = SITE_NOTEBOOKS / name
        if not copy.exists() or copy.read_bytes() != source.read_bytes():
            shutil.copyfile(source, copy)


def _numpydoc_with_one_template(app):
    """numpydoc compiles its Jinja template again for every docstring it renders (``get_doc_object`` builds a new
    environment each call: a thousand compilations, a tenth of the build); the same template, loaded once per
    build through the builder's loader as numpydoc does it, renders the same text."""
    from numpydoc import docscrape, docscrape_sphinx, numpydoc

    template = None

    def get_doc_object(obj, what=None, doc=None, config=None, builder=None):
        nonlocal template
        if template is None:
            loader = docscrape_sphinx.BuiltinTemplateLoader()
            loader.init(app.builder, dirs=[str(Path(docscrape_sphinx.__file__).parent / "templates")])
            template = docscrape_sphinx.SandboxedEnvironment(loader=loader).get_template("numpydoc_docstring.rst")
        config = {} if config is None else config
        config["template"] = template
        return docscrape.get_doc_object(obj, what=what, doc=doc, config=config,
                                        class_doc=docscrape_sphinx.SphinxClassDoc,
                                        func_doc=docscrape_sphinx.SphinxFunctionDoc,
                                        obj_doc=docscrape_sphinx.SphinxObjDoc)

    numpydoc.get_doc_object = get_doc_object


def setup(app):
    app.connect("builder-inited", _numpydoc_with_one_template)
    app.connect("config-inited", _copy_notebooks)
    app.connect("include-read", _readme_links)
