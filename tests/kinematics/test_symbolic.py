"""Textbook simplification: exact SymPy identities."""


import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from paths import DATA
from simplify_reference import simplified_count
from workspace_sym import robots
from workspace_sym.kinematics import DHRobot
from workspace_sym.symbolic import factor_trig, group_terms, shorthand, shorthand_latex, textbook

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


# ---------------------------------------------------------------- compactness (issue 18, item 4)
DH = DATA / "dh"
RTB_TABLES = ["ur5", "kr5", "irb140", "stanford", "cobra600"]     # DH tables of roboticstoolbox-python's models
CATALOG_DH = ["glass-handling", "puma560", "scara", "planar-2r", "planar-3r"]


def _robot(name):
    return DHRobot.from_file(DH / f"{name}.json") if name in RTB_TABLES + ["panda"] else robots.build(name)


def _same_function(A, B, robot, points=4):
    """A == B at random joint values and parameter values (float check of an exact rewrite)."""
    rng = np.random.default_rng(7)
    symbols = sorted(set().union(*(e.free_symbols for e in list(A) + list(B))), key=str)
    for _ in range(points):
        values = {s: rng.uniform(-3, 3) for s in symbols}
        a = np.array(A.xreplace(values).evalf(), dtype=float)
        b = np.array(B.xreplace(values).evalf(), dtype=float)
        np.testing.assert_allclose(a, b, atol=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("name", CATALOG_DH + RTB_TABLES)
def test_textbook_fk_no_longer_than_simplify(name):
    """Every entry of T_0^n in textbook form has at most the count_ops of sympy.simplify of the raw DH product,
    and it is the same function.  The reference count is stored in tests/data/simplify_counts.json keyed by the raw
    entry and the SymPy version (tests/helpers/simplify_reference.py: computed here when either differs); fk()
    itself, the thing under test, is computed here."""
    robot = _robot(name)
    T, raw = robot.fk(), robot.raw_fk()
    _same_function(T, raw, robot)
    for i in range(3):
        for j in range(4):
            assert sp.count_ops(T[i, j]) <= simplified_count(raw[i, j]), (name, i, j, T[i, j])


@pytest.mark.slow
def test_textbook_panda_no_longer_than_simplify_on_the_approach_axis():
    """Panda (modified DH, tool): the whole T is shorter than the raw product, and the approach axis (third
    column; simplify of the full T takes over a minute, see benchmarks/bench_kinematics.py) is no longer than
    sympy.simplify's, entry by entry (the reference counts stored as in the test above)."""
    robot = _robot("panda")
    T, raw = robot.fk(), robot.raw_fk()
    _same_function(T, raw, robot, points=2)
    assert sum(sp.count_ops(e) for e in T) < sum(sp.count_ops(e) for e in raw)
    for i in range(3):
        assert sp.count_ops(T[i, 2]) <= simplified_count(raw[i, 2]), (i, T[i, 2])


def test_classic_groupings(puma, glass):
    """The textbook groupings (Craig, table 3.4 for the Puma's p_x; paper 004 for the glass arm's x)."""
    assert puma.to_str(puma.position[0]) == "c1*(a2*c2 + a3*c23 - d4*s23) + d3*s1"
    assert glass.to_str(glass.position[0]) == "c1*(a1 + a2*c2 + a3*c23 + d5*s234)"


_monomials = st.lists(
    st.tuples(st.integers(-3, 3).filter(bool), st.lists(st.sampled_from(sp.symbols("c1 c2 s1 s2 a1 a2")), max_size=4)),
    min_size=1, max_size=8)


@given(_monomials)
@settings(max_examples=150, deadline=None)
def test_group_terms_is_an_identity_and_never_longer(terms):
    """Property over random polynomials: grouping expands back to the same polynomial and never adds operations."""
    expr = sp.Add(*(c * sp.Mul(*f) for c, f in terms))
    grouped = group_terms(expr)
    assert sp.expand(grouped - expr) == 0
    assert sp.count_ops(grouped) <= sp.count_ops(sp.factor_terms(sp.expand(expr)))


def test_constant_with_square_roots_has_no_factor():
    """A constant such as sqrt(6) - sqrt(2) (it reached the factoriser through a drawn DH table) has no factor;
    SymPy cannot make a polynomial of it over QQ(sqrt 2, sqrt 3)."""
    from workspace_sym.symbolic import _factor_list

    assert _factor_list(sp.sqrt(6) - sp.sqrt(2), (sp.sqrt(2), sp.sqrt(3))) == []
    assert factor_trig(sp.sqrt(6) - sp.sqrt(2)) == []


def test_large_factorisation_with_square_roots_keeps_an_exact_product():
    """Above EXTENSION_FACTOR_TERMS the roots are symbols while factoring: the factors' product is still the
    polynomial (exact identity), and a planted factor is found when no product of roots was reduced
    (sqrt 2 sqrt 6 = 2 sqrt 3 would hide it: then the factors are only coarser)."""
    from workspace_sym.symbolic import EXTENSION_FACTOR_TERMS, _factor_list

    x, y, z = sp.symbols("x y z")
    f = sp.sqrt(2) * x + y - sp.sqrt(3) * z
    g = sp.expand((x + y + z + 1) ** 3 + 6 * x * y)
    poly = sp.expand(f * g)
    assert len(poly.args) > EXTENSION_FACTOR_TERMS
    factors = _factor_list(poly, (sp.sqrt(2), sp.sqrt(3), sp.sqrt(6)))
    product = sp.Mul(*(h**m for h, m in factors))
    ratio = sp.simplify(poly / product)
    assert ratio.is_number and ratio != 0
    assert any(sp.simplify(h / f).is_number for h, _ in factors)


def test_decimal_lengths_print_as_decimals():
    """UR5 lengths given as decimals (read as exact fractions) print as the decimals of the table, inside the
    textbook grouping, and the printed text reads back to the same exact expression."""
    from workspace_sym.expressions import parse_expr

    robot = _robot("ur5")
    x = robot.position[0]
    text = robot.to_str(x)
    assert text == "c1*(-0.425*c2 - 0.39225*c23 - 0.0823*c234*s5 + 0.09465*s234) + s1*(0.0823*c5 + 0.10915)"
    names = {f"{k}{''.join(map(str, i))}": f(sum(robot.q[j - 1] for j in i))
             for k, f in (("c", sp.cos), ("s", sp.sin)) for i in ((1,), (2,), (5,), (2, 3), (2, 3, 4))}
    assert sp.expand(parse_expr(text, "x", names=names) - x) == 0
    assert "0.425 c_{2}" in robot.to_latex(x)


# ---------------------------------------------------------------------- issue 29: the cheap counters and products
_x, _y, _z = sp.symbols("x y z")
_leaves = st.sampled_from([_x, _y, _z, sp.Integer(2), sp.Rational(-1, 3), sp.Integer(-1), sp.pi, sp.sqrt(2)])


def _combine(children):
    pair = st.tuples(children, children)
    return st.one_of(
        pair.map(lambda p: p[0] + p[1]), pair.map(lambda p: p[0] - p[1]), pair.map(lambda p: p[0] * p[1]),
        pair.map(lambda p: p[0] / p[1] if p[1] != 0 else p[0]), children.map(lambda e: -e),
        children.map(sp.sin), children.map(sp.cos), children.map(sp.exp),
        st.tuples(children, st.integers(-2, 3)).map(lambda p: p[0] ** p[1] if p[0] != 0 else p[0]))


_expressions = st.recursive(_leaves, _combine, max_leaves=12)


@settings(derandomize=True, max_examples=300, deadline=None)
@given(_expressions)
def test_op_count_is_sympys_count_ops(expr):
    """Reference: sympy.count_ops itself, on random expressions (signs, quotients, powers, functions, E)."""
    from workspace_sym.symbolic import op_count

    assert op_count(expr) == sp.count_ops(expr), expr


def test_op_count_is_sympys_count_ops_on_a_table_with_twists_and_a_tool():
    """Reference: sympy.count_ops on the raw product, the textbook fk and the Jacobian of a 3-joint table with
    offsets and twists in whole degrees and a tool (the entries textbook() compares)."""
    from workspace_sym.symbolic import op_count

    robot = DHRobot.from_dict({"joints": [{"type": "R", "theta": 120, "alpha": -25, "a": 0.425, "d": 0.2},
                                          {"type": "P", "theta": 75, "alpha": 97, "a": 0.1, "d": 0.0},
                                          {"type": "R", "theta": 60, "alpha": 150, "a": 0.25, "d": 0.05}],
                               "tool": {"xyz": [0.1, 0.0, 0.05], "rpy": [-31, 7, -78]}})
    for e in list(robot.raw_fk()) + list(robot.fk()) + list(robot.geometric_jacobian):
        assert op_count(e) == sp.count_ops(e)


@settings(derandomize=True, max_examples=200, deadline=None)
@given(_monomials)
@example([(-1, []), (-1, [sp.Symbol("c2")]), (2, sp.symbols("c1 c1 c1 c2")), (-3, sp.symbols("c1 c1 c1 c2"))])
def test_least_flat_ops_is_a_lower_bound(terms):
    """Reference: count_ops of sympy.factor_terms of the expanded sum, which group_terms no longer builds when the
    grouping is already within this bound."""
    from workspace_sym.symbolic import _least_flat_ops, _term_factors

    base = sp.Add(*(c * sp.Mul(*f) for c, f in terms))
    for expr in (sp.expand(base), sp.expand(base * sp.cos(t1 + sp.pi / 5)), sp.expand(base * sp.sin(2 * t1))):
        if expr.is_Add:
            assert _least_flat_ops([_term_factors(t) for t in expr.args]) <= sp.count_ops(sp.factor_terms(expr))


@settings(derandomize=True, max_examples=200, deadline=None)
@given(st.lists(st.one_of(st.just(sp.Integer(0)), _expressions), min_size=6, max_size=6))
def test_cross_is_sympys_cross(entries):
    """Reference: sympy's Matrix.cross, entry for entry the same expressions (zero components included)."""
    from workspace_sym.kinematics import _cross

    u, v = sp.Matrix(entries[:3]), sp.Matrix(entries[3:])
    assert _cross(u, v) == u.cross(v)


_P, _Q, _T1, _T2 = sp.symbols("x y theta1 theta2")
_ATOMS = st.sampled_from([_P, _Q, sp.cos(_T1), sp.sin(_T1 + _T2), sp.cos(_T1 - 2 * _T2), sp.Rational(3, 4),
                          sp.Rational(-17, 40), sp.Float("0.39225"), sp.Integer(-1), sp.Integer(2), sp.sqrt(2),
                          sp.pi, sp.I, sp.exp(_P), sp.Symbol("c23"), sp.Integer(10) ** 400])
_EXPRESSIONS = st.recursive(
    _ATOMS,
    lambda inner: st.one_of(st.lists(inner, min_size=2, max_size=5).map(lambda a: sp.Add(*a)),
                            st.lists(inner, min_size=2, max_size=4).map(lambda a: sp.Mul(*a)),
                            st.tuples(inner, st.sampled_from([2, 3, -1, -2, sp.Rational(1, 2)]))
                            .map(lambda p: p[0] ** p[1])),
    max_leaves=40)


@settings(max_examples=300, deadline=None)
@given(expr=_EXPRESSIONS)
@example(expr=1 - 2 * _P)                                   # SymPy's special case: a number first, then -2*x
@example(expr=_P + sp.O(_P**2))                             # an Order term: left to SymPy
@example(expr=sp.Symbol("A", commutative=False) * sp.Symbol("B", commutative=False) + _P)   # non-commutative
@example(expr=sp.Integer(10) ** 400 * _P + sp.Float("1e300") * _Q ** 2 + sp.I * _P * _Q)    # huge coefficients
@example(expr=sp.Matrix([[_P + 1, sp.cos(_T1) ** 2 * _Q - _P], [0, (_P + _Q) ** 2]]))
@example(expr=(sp.Float("0.39225") * _P + _Q) ** 2 * sp.cos(_T1) + (sp.Float("0.39225") * _P + _Q) ** 2
        + sp.Float("0.5"))                                # a repeated sum with a float, printed once
def test_canonical_sstr_is_sympys_string(expr):
    """The textbook printer keeps the order of each sum once found; reference: ``sympy.sstr`` itself, character
    for character, with and without ``full_prec``, over random nested sums, products and powers of symbols,
    sines and cosines of sums, rationals, floats, surds, pi, i and a 400-digit integer; and SymPy's
    ``default_sort_key`` of each of their nodes.  Repeated subexpressions are printed once: a float keeps the
    form of its depth."""
    from workspace_sym.symbolic import _CanonicalOrder, canonical_sstr

    # Python refuses to write an integer of more than 4,300 digits (products of powers of 10^400 reach it)
    assume(all(max(abs(r.p), r.q).bit_length() < 14_000 for r in expr.atoms(sp.Rational)))
    assert canonical_sstr(expr) == sp.sstr(expr)
    assert canonical_sstr(expr, full_prec=False) == sp.sstr(expr, full_prec=False)
    order = _CanonicalOrder()              # and the sort keys behind the order are SymPy's, at every node
    for node in sp.preorder_traversal(expr) if isinstance(expr, sp.Expr) else ():
        assert order.key(node) == sp.default_sort_key(node)


def test_the_textbook_strings_of_arms_are_sympys(glass):
    """The same on real results: the glass arm's forward kinematics and Jacobian and the UR5's fk, as textbook
    strings (shorthand and decimal lengths), against ``sympy.sstr`` of the same expressions."""
    from workspace_sym.symbolic import decimal_form

    ur5 = DHRobot.from_file(DATA / "dh" / "ur5.json")
    for robot, matrices in ((glass, (glass.fk(), glass.geometric_jacobian)), (ur5, (ur5.fk(),))):
        for matrix in matrices:
            for entry in matrix:
                assert robot.to_str(entry) == sp.sstr(decimal_form(shorthand(entry, robot.q)), full_prec=False)
