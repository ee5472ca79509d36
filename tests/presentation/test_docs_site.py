"""The documentation site (issue 39, `make docs`): Sphinx builds docs/site with warnings as errors, and a reader
opening the API page of ``reach`` in a browser sees its signature and its Parameters section; each notebook of
notebooks/ is a page of the site (myst-nb) with its title and its code.

The site's sources (docs/site, the guides of docs/ it includes, the README and the notebooks) are copied into
``tmp_path`` first, so that autosummary's generated pages and the build stay out of the checkout (and two runs cannot
collide).  The build does not execute the notebooks (``-D nb_execution_mode=off``: about a minute more with it);
``make docs`` does.

Reference: the page as headless Chromium lays it out (selenium), against the signature of ``reach`` itself."""

import html as html_text
import inspect
import json
import os
import re
import shutil
import subprocess
import sys

import pytest

from paths import ROOT
from system_tools import headless_chromium, require_tool


def _copy_sources(into):
    """docs/site, docs/*.md, README.md and notebooks/*.ipynb at the same relative places under ``into`` (conf.py copies
    the notebooks from there into docs/site/notebooks/, which a build of the checkout may have left: not copied)."""
    shutil.copytree(ROOT / "docs" / "site", into / "docs" / "site",
                    ignore=shutil.ignore_patterns("generated", "notebooks"))
    for page in (ROOT / "docs").glob("*.md"):
        shutil.copy(page, into / "docs" / page.name)
    shutil.copy(ROOT / "README.md", into / "README.md")
    (into / "notebooks").mkdir()
    for notebook in (ROOT / "notebooks").glob("*.ipynb"):
        shutil.copy(notebook, into / "notebooks" / notebook.name)


def _build(tmp_path):
    sources = tmp_path / "src"
    _copy_sources(sources)
    html = tmp_path / "html"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                          "-D", "nb_execution_mode=off", str(sources / "docs" / "site"), str(html)],
                         capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    return html


def _text(markup):
    """What a reader reads of an HTML fragment: no tags, entities decoded, Sphinx's curly apostrophes straight."""
    return html_text.unescape(re.sub(r"<[^>]+>", "", markup)).replace("\u2019", "'")


def _check_notebook_pages(html):
    """Each notebook of notebooks/ has a page whose title is its first Markdown heading and which shows the source of
    every code cell."""
    notebooks = sorted((ROOT / "notebooks").glob("*.ipynb"))
    assert notebooks
    for path in notebooks:
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        heading = next(line[2:].strip() for cell in cells if cell["cell_type"] == "markdown"
                       for line in "".join(cell["source"]).splitlines() if line.startswith("# "))
        page = (html / "notebooks" / f"{path.stem}.html").read_text(encoding="utf-8")
        title = re.search(r"<h1>(.*?)</h1>", page, re.S)
        assert title and _text(re.sub(r"<a class=\"headerlink\".*?</a>", "", title.group(1))) == heading, path.name
        shown = _text(page)
        codes = ["".join(cell["source"]).strip() for cell in cells if cell["cell_type"] == "code"]
        assert codes, path.name
        for code in codes:
            assert code in shown, (path.name, code[:200])


@pytest.mark.slow      # about 30 s: the build (notebooks not executed), then Chromium
def test_site_builds_and_shows_the_api_of_reach(tmp_path):
    """The build passes with warnings as errors; the index says the docstring examples are doctests; every guide
    of docs/ is a page of the site, and every notebook of notebooks/ (its title and its code); in Chromium, the page
    of ``workspace_sym.reach`` shows the signature (the function's name and each parameter's name, as
    ``inspect.signature`` gives them) and a Parameters section that lists them."""
    require_tool("chromium", "chromedriver")
    from selenium.webdriver.common.by import By

    from workspace_sym import reach

    html = _build(tmp_path)
    index = re.sub(r"<[^>]+>", "", (html / "index.html").read_text(encoding="utf-8"))
    assert "make test runs them" in index and "pytest --doctest-modules" in index
    # every guide of docs/ is a page of the site (a new one must be added to docs/site), and the README too
    for guide in ["readme", *(page.stem for page in (ROOT / "docs").glob("*.md"))]:
        assert (html / f"{guide}.html").stat().st_size > 10_000, guide
    for module in ("serial", "interval", "planar", "readers", "teaching", "orthoglide", "kinematics", "symbolic",
                   "report"):
        assert (html / "api" / f"{module}.html").exists(), module
    _check_notebook_pages(html)
    page = html / "api" / "generated" / "workspace_sym.reach.html"
    names = list(inspect.signature(reach).parameters)

    driver = headless_chromium()
    try:
        driver.get(page.as_uri())
        signature = driver.find_element(By.CSS_SELECTOR, "dl.py.function > dt.sig")
        assert signature.is_displayed() and signature.size["height"] > 0
        shown = signature.text
        assert "reach(" in shown
        assert all(name in shown for name in names), (names, shown)
        # numpydoc's Parameters section: a visible heading, then one bold name per parameter
        heading = driver.find_element(By.XPATH, "//dl[contains(@class, 'function')]/dd/dl[contains(@class, "
                                                "'field-list')]/dt[starts-with(normalize-space(.), 'Parameters')]")
        assert heading.is_displayed()
        listed = [e.text for e in heading.find_elements(By.XPATH, "following-sibling::dd[1]/dl/dt/strong")]
        assert all(e.is_displayed() for e in heading.find_elements(By.XPATH, "following-sibling::dd[1]/dl/dt"))
        keyword = {n for n, p in inspect.signature(reach).parameters.items() if p.kind is p.VAR_KEYWORD}
        assert [n for n in listed if n in names] == [n for n in names if n not in keyword], (names, listed)
    finally:
        driver.quit()
