"""Textbook simplification: exact SymPy identities."""

import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from workspace_sym.symbolic import factor_trig, shorthand, shorthand_latex, textbook

t1, t2, t3, t4 = sp.symbols("theta1:5")
a, b = sp.symbols("a b")


def test_angle_addition_is_gathered():
    e = sp.cos(t1) * sp.cos(t2) - sp.sin(t1) * sp.sin(t2)
    assert textbook(e) == sp.cos(t1 + t2)


def test_three_angle_sum_is_gathered():
    e = sp.expand(sp.expand_trig(sp.sin(t2 + t3 + t4)))
    assert textbook(e) == sp.sin(t2 + t3 + t4)


def test_pythagorean_identity_removed():
    assert textbook(a * sp.sin(t1) ** 2 + a * sp.cos(t1) ** 2) == a


def test_never_product_to_sum():
    e = textbook(sp.cos(t1) * sp.sin(t2))
    assert e == sp.cos(t1) * sp.sin(t2)


def test_common_factor_pulled_out():
    e = sp.cos(t1) * a + sp.cos(t1) * b * sp.cos(t2)
    assert textbook(e) == sp.cos(t1) * (a + b * sp.cos(t2))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(-3, 3), min_size=4, max_size=4))
def test_textbook_is_an_identity(coeffs):
    """Property: textbook() never changes the value (exact check via expand_trig)."""
    e = (coeffs[0] * sp.cos(t1) * sp.cos(t2) + coeffs[1] * sp.sin(t1) * sp.sin(t2)
         + coeffs[2] * sp.sin(t1) ** 2 + coeffs[3] * sp.cos(t1 + t2) * sp.sin(t3))
    assert sp.simplify(sp.expand_trig(textbook(e) - e)) == 0


def test_factor_trig_finds_hidden_sine():
    # c2 s23 - s2 c23 = s3; in the reduced normal form s3 only shows as (1 - c3^2)-multiples.
    e = a * (sp.cos(t2) * sp.sin(t2 + t3) - sp.sin(t2) * sp.cos(t2 + t3)) * sp.sin(t3)
    assert factor_trig(e) == [a, sp.sin(t3)]


def test_factor_trig_zero_and_constant():
    assert factor_trig(sp.Integer(0)) == [0]
    assert factor_trig(sp.Integer(7)) == []


def test_shorthand_names_and_latex():
    e = sp.cos(t1) * sp.sin(t2 + t3)
    assert str(shorthand(e, (t1, t2, t3))) == "c1*s23"
    assert "c_{1}" in shorthand_latex(e, (t1, t2, t3)) and "s_{23}" in shorthand_latex(e, (t1, t2, t3))
