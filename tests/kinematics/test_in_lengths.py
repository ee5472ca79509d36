"""``symbolic.in_lengths``: a factor defined up to a constant, rescaled so that it reads in the robot's lengths
(issue 39, Engineer item 2).  Reference: exact SymPy equality with the factor multiplied by hand, and the ratio
to the factor a positive constant."""

import pytest
import sympy as sp

from workspace_sym.symbolic import in_lengths


@pytest.mark.parametrize("factor, lengths, expected", [
    ("8500*c2 + 7845*c23 - 1893*s234", ["0.425", "0.39225", "0.09465"], "17*c2/40 + 1569*c23/4000 - 1893*s234/20000"),
    ("7*c3 + 134*s3", ["0.035", "0.67", "0.26"], "7*c3/200 + 67*s3/100"),
    ("c2 + c3", ["0.5"], "c2 + c3"),                       # unit coefficients: nothing says it holds a length
    ("4*c2 + 7*c3", ["0.1"], "c2/10 + 7*c3/40"),           # one length, the other a terminating decimal
    ("3*c2 + 7*c3", ["0.1"], "3*c2 + 7*c3"),               # 0.1/3: no scale gives terminating decimals
    ("3*c2 + 7*c3", [sp.sqrt(2)], "3*c2 + 7*c3"),           # no rational length: as it was
    ("s5", ["0.1"], "s5"),                                 # one term: as it was
])
def test_in_lengths_rescales_by_a_positive_constant(factor, lengths, expected):
    f = sp.sympify(factor)
    got = in_lengths(f, [sp.Rational(v) if isinstance(v, str) else v for v in lengths])
    assert got == sp.sympify(expected)
    ratio = sp.cancel(got / f)
    assert ratio.is_Rational and ratio > 0                # a positive constant multiple, sign kept
