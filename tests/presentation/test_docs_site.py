"""The documentation site (issue 39, `make docs`): Sphinx builds docs/site with warnings as errors, and a reader
opening the API page of ``reach`` in a browser sees its signature and its Parameters section.

The site's sources (docs/site, the guides of docs/ it includes and the README) are copied into ``tmp_path`` first,
so that autosummary's generated pages and the build stay out of the checkout (and two runs cannot collide).

Reference: the page as headless Chromium lays it out (selenium), against the signature of ``reach`` itself."""

import inspect
import os
import re
import shutil
import subprocess
import sys

import pytest

from paths import ROOT
from system_tools import require_tool


def _copy_sources(into):
    """docs/site, docs/*.md and README.md at the same relative places under ``into``."""
    shutil.copytree(ROOT / "docs" / "site", into / "docs" / "site", ignore=shutil.ignore_patterns("generated"))
    for page in (ROOT / "docs").glob("*.md"):
        shutil.copy(page, into / "docs" / page.name)
    shutil.copy(ROOT / "README.md", into / "README.md")


def _build(tmp_path):
    sources = tmp_path / "src"
    _copy_sources(sources)
    html = tmp_path / "html"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                          str(sources / "docs" / "site"), str(html)],
                         capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    return html


@pytest.mark.slow      # about 30 s: the build (20-25 s on two cores), then Chromium
def test_site_builds_and_shows_the_api_of_reach(tmp_path):
    """The build passes with warnings as errors; the index says the docstring examples are doctests; every guide
    of docs/ is a page of the site; in Chromium, the page of ``workspace_sym.reach`` shows the signature (the function's
    name and each parameter's name, as ``inspect.signature`` gives them) and a Parameters section that lists them."""
    require_tool("chromium", "chromedriver")
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
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
    page = html / "api" / "generated" / "workspace_sym.reach.html"
    names = list(inspect.signature(reach).parameters)

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium")
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
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
