"""Programs some tests need beyond Python: headless Chromium with its driver, pdflatex and a C compiler.

The report tests open the HTML in headless Chromium and compile the LaTeX with pdflatex (Debian packages
chromium, chromium-driver, texlive-latex-base; .ci/run installs them); the generated-code tests compile C with
``cc`` (Debian package gcc).  Without them those tests are skipped
locally and the run ends with a banner naming them (tests/conftest.py); under CI (CI=true) a missing program
fails the test instead, so CI always runs both.
"""

import os
import re
import shutil
import subprocess

import pytest

TOOL_SKIP = "system tool missing:"


def require_tool(*names: str, install: str = "chromium chromium-driver texlive-latex-base") -> None:
    """Skip the calling test (fail it under CI) unless every program in ``names`` is on PATH; ``install`` names the
    Debian packages that provide them."""
    missing = [n for n in names if shutil.which(n) is None]
    if missing:
        message = f"{TOOL_SKIP} {', '.join(missing)} (Debian: apt-get install {install})"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(message)
        pytest.skip(message)


def assert_compiles(tex_path, *, min_pdf_bytes: int = 10_000) -> None:
    """pdflatex compiles ``tex_path`` (in its folder) with no error, no undefined control sequence and no overfull
    box wider than 10 pt."""
    subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", tex_path.name], cwd=tex_path.parent,
                   capture_output=True, timeout=120)
    log = tex_path.with_suffix(".log").read_text(errors="replace")
    assert tex_path.with_suffix(".pdf").stat().st_size > min_pdf_bytes
    assert not re.search(r"^! ", log, re.M), log[-2000:]
    assert "Undefined control sequence" not in log
    over = [float(x) for x in re.findall(r"Overfull \\[hv]box \(([\d.]+)pt too", log)]
    assert all(x <= 10 for x in over), over


def headless_chromium(*flags: str):
    """A selenium driver of the system's headless Chromium and chromedriver (call :func:`require_tool` first);
    ``flags`` are added to the usual ones (``--window-size=W,H``).  The caller quits it."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium")
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", *flags):
        options.add_argument(flag)
    return webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
