"""Docstring examples run as tests."""

import doctest
import importlib

import pytest

MODULES = ["errors", "expressions", "symbolic", "kinematics", "robots", "sampling", "parallel", "interval.mp",
           "interval.compiler", "interval.contractor", "interval.paving", "interval.search", "planar", "arrangement", "boundary", "exact", "orthoglide.model",
           "report", "verify"]


@pytest.mark.parametrize("name", MODULES)
def test_doctests(name):
    module = importlib.import_module(f"workspace_sym.{name}")
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0
