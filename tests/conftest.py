"""Shared fixtures (the Agg backend is set by the top-level conftest.py)."""

import numpy as np
import pytest
import sympy as sp

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


def dh_numpy(theta, d, a, alpha):
    """Independent plain-numpy standard DH matrix (docs/methods.md section 1)."""
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct],
                     [st, ct * ca, -ct * sa, a * st],
                     [0, sa, ca, d],
                     [0, 0, 0, 1.0]])


def dh_numpy_modified(theta, d, a_prev, alpha_prev):
    """Independent plain-numpy modified (Craig) DH matrix."""
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha_prev), np.sin(alpha_prev)
    return np.array([[ct, -st, 0, a_prev],
                     [st * ca, ct * ca, -sa, -sa * d],
                     [st * sa, ct * sa, ca, ca * d],
                     [0, 0, 0, 1.0]])


def fk_numpy(robot, q):
    """Product of numeric DH matrices, built from the table rows only (no symbolic FK)."""
    T = np.eye(4)
    subs = {k: float(v) for k, v in robot.parameters.items()}
    for joint, qk in zip(robot.joints, q):
        vals = {joint.variable: qk, **{sp.Symbol(str(k)): v for k, v in subs.items()}}
        row = [float(sp.sympify(e).subs(vals)) for e in (joint.theta, joint.d, joint.a, joint.alpha)]
        T = T @ (dh_numpy(*row) if robot.convention == "standard" else dh_numpy_modified(*row))
    return T


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
