"""Programs some tests need beyond Python: headless Chromium with its driver, and pdflatex.

The report tests open the HTML in headless Chromium and compile the LaTeX with pdflatex (Debian packages
chromium, chromium-driver, texlive-latex-base; .ci/run installs them).  Without them those tests are skipped
locally and the run ends with a banner naming them (tests/conftest.py); under CI (CI=true) a missing program
fails the test instead, so CI always runs both.
"""

import os
import shutil

import pytest

TOOL_SKIP = "system tool missing:"


def require_tool(*names: str) -> None:
    """Skip the calling test (fail it under CI) unless every program in ``names`` is on PATH."""
    missing = [n for n in names if shutil.which(n) is None]
    if missing:
        message = (f"{TOOL_SKIP} {', '.join(missing)} "
                   "(Debian: apt-get install chromium chromium-driver texlive-latex-base)")
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(message)
        pytest.skip(message)
