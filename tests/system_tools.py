"""Programs some tests need beyond Python: headless Chromium with its driver, pdflatex and a C compiler.

The report tests open the HTML in headless Chromium and compile the LaTeX with pdflatex (Debian packages
chromium, chromium-driver, texlive-latex-base; .ci/run installs them); the generated-code tests compile C with
``cc`` (Debian package gcc).  Without them those tests are skipped
locally and the run ends with a banner naming them (tests/conftest.py); under CI (CI=true) a missing program
fails the test instead, so CI always runs both.
"""

import os
import shutil

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
