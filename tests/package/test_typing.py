"""The package type-checks clean under mypy, configured in pyproject.toml (issue 26 item 7).

Reference: mypy itself.  The second test plants a type error in a snippet and checks that the same configuration
reports it, so a configuration that silently checks nothing (say, a wrong ``files`` entry) fails here too.
"""

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import workspace_sym
from paths import ROOT

PYPROJECT = ROOT / "pyproject.toml"


def _mypy(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "mypy", "--config-file", str(PYPROJECT), *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)


@pytest.mark.slow                    # mypy on the whole package: half a minute (not in make test-fast)
def test_mypy_is_clean_on_the_package():
    run = _mypy()
    assert run.returncode == 0, f"mypy found problems in workspace_sym:\n{run.stdout}{run.stderr}"
    assert "Success: no issues found" in run.stdout
    checked = int(run.stdout.split("in ")[-1].split()[0])
    modules = list(Path(workspace_sym.__file__).parent.rglob("*.py"))
    assert checked == len(modules), f"mypy checked {checked} files; the package has {len(modules)}"


def test_the_configuration_reports_a_planted_error(tmp_path):
    planted = tmp_path / "planted.py"
    planted.write_text("from workspace_sym.errors import WorkspaceError\n\nx: int = WorkspaceError('a')\n")
    run = _mypy(str(planted))
    assert run.returncode == 1, run.stdout + run.stderr
    assert "Incompatible types in assignment" in run.stdout



def test_the_package_ships_its_type_marker():
    """PEP 561: without ``py.typed`` a user's mypy ignores the package's annotations."""
    assert (Path(workspace_sym.__file__).parent / "py.typed").is_file()
    with PYPROJECT.open("rb") as f:
        package_data = tomllib.load(f)["tool"]["setuptools"]["package-data"]["workspace_sym"]
    assert "py.typed" in package_data, "py.typed is not in the wheel unless package-data names it"
