"""Shared fixtures (the Agg backend is set by the top-level conftest.py)."""

import pytest

from workspace_sym import robots


@pytest.fixture(scope="session")
def glass():
    """The symbolic glass-handling arm (derivations cached across tests)."""
    return robots.build("glass-handling")


@pytest.fixture(scope="session")
def puma():
    return robots.build("puma560")


@pytest.fixture(scope="session")
def scara():
    return robots.build("scara")


# ---------------------------------------------------------------------- system tools (browser, TeX)
def pytest_terminal_summary(terminalreporter):
    """A loud banner when the browser, TeX or C compiler tests were skipped for want of their programs."""
    from system_tools import TOOL_SKIP

    skipped = [r for r in terminalreporter.stats.get("skipped", [])
               if isinstance(r.longrepr, tuple) and TOOL_SKIP in str(r.longrepr[2])]
    if skipped:
        tr = terminalreporter
        tr.write_sep("!", "BROWSER / TEX / C COMPILER TESTS NOT RUN", red=True, bold=True)
        for r in skipped:
            tr.write_line(f"SKIPPED {r.nodeid}: {r.longrepr[2]}", red=True)
        tr.write_line("The HTML reports were not opened in a browser, the LaTeX reports or the generated C code "
                      "were not compiled. Install the packages above (as .ci/run does) to run them.",
                      red=True, bold=True)
