"""The characteristic polynomial of J J^T within a budget, the middle-frame Jacobian, and the jacobian command when
a derivation runs out of budget (issues 26 item 4, 28 item 1, 29).

References: numpy's eigenvalues of J J^T of the world-frame Jacobian at random configurations (an independent
float computation), the rotation identity J_m = diag(R^T, R^T) J with R the orientation of frame m (numpy), and
SymPy's own expanded determinant of a small submatrix.
"""

import json

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from dh_reference import GENERIC_6, dummies, fk_numpy_with_tool, tables
from workspace_sym import charpoly, kinematics
from workspace_sym.cli import main
from workspace_sym.errors import SymbolicBudgetError
from workspace_sym.kinematics import DHRobot, eigenvalues_from_charpoly


def _eigenvalues_agree(robot, p, kind, points=3, seed=4):
    """Roots of ``p`` at random configurations against numpy's eigenvalues of J J^T (world frame)."""
    Jf = robot.numeric(robot.jacobian(kind))
    rng = np.random.default_rng(seed)
    for _ in range(points):
        q = rng.uniform(-np.pi, np.pi, robot.n)
        J = Jf(q)
        expected = np.linalg.eigvalsh(J @ J.T)
        scale = max(1.0, expected.max())
        ours = eigenvalues_from_charpoly(p, dict(zip(robot.q, q)))
        assert np.allclose(ours, expected, atol=1e-9 * scale), (ours, expected)


def _roots_function(robot, p):
    """q -> the roots of ``p`` at the joint values q, ordered by real part (complex: a root off the real line
    fails a comparison with real eigenvalues).  The coefficients are lambdified once (numpy), each unexpanded
    determinant (kept when its minors run out of budget) by numpy's det of its lambdified matrix: substituting
    floats into the 22,000-operation coefficients of a generic 3 x 4 Jacobian (eigenvalues_from_charpoly) took
    3 s a point."""
    coeffs = [sp.sympify(c) for c in p.all_coeffs()]
    dets = sorted(set().union(*(c.atoms(sp.Determinant) for c in coeffs)), key=sp.default_sort_key)
    names = [sp.Dummy() for _ in dets]
    f = sp.lambdify([*robot.q, *names], [c.xreplace(dict(zip(dets, names))) for c in coeffs], "numpy")
    matrices = [sp.lambdify(robot.q, d.arg, "numpy") for d in dets]

    def roots(q):
        values = [np.linalg.det(np.array(m(*q), dtype=float)) for m in matrices]
        r = np.roots(np.array(f(*q, *values), dtype=float))
        return r[np.argsort(r.real)]
    return roots


@pytest.mark.slow
def test_generic_four_joint_charpoly_finishes_and_matches_numpy():
    """Issues 28-29: the 3 x 4 characteristic polynomial of a generic table (the first four rows of the generic
    6-joint table, its tool kept: no twist a multiple of 90 degrees, a prismatic joint, offsets everywhere; det J J^T
    sums four squared 3 x 3 minors) finishes within the library's default budget (its minors factored, or kept as
    exact determinants) and its roots (its coefficients lambdified) are numpy's eigenvalues of J J^T, J by central
    differences of the plain numpy DH product.  Five rows (ten minors) took 68 s of the suite's time and six about
    two minutes, on the same path: how long they take is a benchmark's figure (``benchmarks/bench_symbolic_tables.py``),
    not this test's."""
    robot = DHRobot.from_dict({"joints": GENERIC_6["joints"][:4], "tool": GENERIC_6["tool"]})
    p = robot.characteristic_polynomial("position")
    assert p.degree() == 3 and not dummies(p)
    roots = _roots_function(robot, p)
    rng = np.random.default_rng(4)
    h = 1e-6
    for _ in range(3):   # J of the plain numpy DH product by central differences: no symbolic world Jacobian
        q = rng.uniform(-np.pi, np.pi, robot.n)
        J = np.array([fk_numpy_with_tool(robot, q + h * e)[:3, 3] - fk_numpy_with_tool(robot, q - h * e)[:3, 3]
                      for e in np.eye(robot.n)]).T / (2 * h)
        expected = np.linalg.eigvalsh(J @ J.T)
        assert np.allclose(roots(q), expected, atol=1e-7 * expected.max())


@pytest.mark.parametrize("shares", [(0.0, 0.6), (0.5, 0.0)], ids=["determinants", "unfactored minors"])
def test_unexpanded_forms_are_exact(monkeypatch, shares):
    """When the exact minors (first case) or their factoring (second) get no time, the coefficients are sums of
    squared determinants of submatrices: still the characteristic polynomial (numpy's eigenvalues; a 3-joint
    table with offsets of 97 and 20 degrees and a 45 degree twist, the 6 x 3 geometric Jacobian), no
    placeholder, and each determinant expands to SymPy's own det of its submatrix."""
    monkeypatch.setattr(charpoly, "MINORS_SHARE", shares[0])
    monkeypatch.setattr(charpoly, "FACTOR_SHARE", shares[1])
    robot = DHRobot.from_dict({"joints": [{"type": "R", "theta": 97, "alpha": 90, "a": 0.3, "d": 0.4},
                                          {"type": "P", "theta": 20, "alpha": -90, "a": 0.25, "d": 0.1},
                                          {"type": "R", "theta": 0, "alpha": 45, "a": 0.425, "d": 0.05}]})
    p = robot.characteristic_polynomial("geometric")
    dets = p.as_expr().atoms(sp.Determinant)
    assert dets and not dummies(p)
    _eigenvalues_agree(robot, p, "geometric")
    d = min(dets, key=lambda d: d.arg.shape[0])
    q = dict(zip(robot.q, (0.4, -1.1, 0.3)))
    assert abs(sp.N((d.doit() - d.arg.as_mutable().det(method="berkowitz")).xreplace(q))) < 1e-12


@settings(max_examples=2, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(tables(n_max=2, tool=True))
@example({"convention": "modified", "joints": [{"type": "R", "theta": 0, "alpha": 0, "a": 0.0, "d": 0.333},
                                               {"type": "R", "theta": 0, "alpha": -90, "a": 0.0, "d": 0.0},
                                               {"type": "P", "theta": 20, "alpha": 90, "a": 0.0825, "d": 0.316}],
          "base": {"xyz": [0.1, 0.2, 0.0], "rpy": [0, 30, 45]}, "tool": {"xyz": [0, 0, 0.103], "rpy": [0, 0, -45]}})
def test_middle_frame_jacobian_is_the_turned_world_jacobian(data):
    """The Jacobian derived in frame m = n // 2 equals diag(R^T, R^T) J, R the orientation of frame m in the world
    (numpy, random configurations; both conventions, base and tool): the same reference point, axes turned."""
    robot = DHRobot.from_dict(data)
    m = robot.n // 2
    Jm, J, Fm = (robot.numeric(e) for e in (robot._middle_frame_jacobian("geometric"), robot.geometric_jacobian,
                                            robot.fk(m)))
    rng = np.random.default_rng(2)
    for _ in range(3):
        q = rng.uniform(-np.pi, np.pi, robot.n)
        Rt = Fm(q)[:3, :3].T
        assert np.allclose(Jm(q), np.vstack([Rt @ J(q)[:3], Rt @ J(q)[3:]]), atol=1e-10)


def test_jacobian_command_prints_j_then_the_unfinished_factors(monkeypatch, capsys):
    """The jacobian command with singular factors past the budget: the Jacobian is printed first, then one line
    saying they were not factored within the budget, exit status 0; the JSON has singular null and the message
    under "unfinished" (and an empty "unfinished" when everything was found)."""
    def spent(self, *args, **kwargs):
        raise SymbolicBudgetError("singular factors of the geometric Jacobian of planar-3r: a maximal minor not "
                                  "finished within the budget of 120 s")

    assert main(["jacobian", "planar-3r", "--json", "--no-singular"]) == 0
    assert json.loads(capsys.readouterr().out)["unfinished"] == {}
    monkeypatch.setattr(kinematics.DHRobot, "singular_factors", spent)
    assert main(["jacobian", "planar-3r"]) == 0
    out, err = capsys.readouterr()
    lines = out.splitlines()
    assert lines[1].startswith("  column 1:") and lines[3].startswith("  column 3:")
    assert lines[4].startswith("  singular: not factored within the budget (") and "120 s" in lines[4]
    assert len(lines) == 5 and err == ""
    assert main(["jacobian", "planar-3r", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["singular"] is None and data["singularities"] is None and len(data["J"]) == 6
    assert data["unfinished"]["singular"].startswith("not factored within the budget")


def test_singular_factors_live_in_charpoly_without_a_cycle():
    """Issue 26 item 4: the maximal minors' gcd is charpoly's (kinematics re-exports the same function), and
    charpoly imports nothing of kinematics (checked in the module's import lines).  Reference: the 2R arm's
    det J = l1 l2 sin(q2), an exact SymPy identity."""
    import ast
    import inspect

    assert kinematics.maximal_minor_factors is charpoly.maximal_minor_factors
    tree = ast.parse(inspect.getsource(charpoly))
    imported = {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    assert "kinematics" not in imported and "workspace_sym.kinematics" not in imported
    q1, q2 = sp.symbols("q1 q2")
    J = sp.Matrix([[-sp.sin(q1) - sp.sin(q1 + q2), -sp.sin(q1 + q2)], [sp.cos(q1) + sp.cos(q1 + q2), sp.cos(q1 + q2)]])
    assert sp.simplify(J.det() - sp.sin(q2)) == 0
    assert charpoly.maximal_minor_factors(J) == [sp.sin(q2)]


PANDA_4 = {"convention": "modified", "joints": [
    {"type": "R", "theta": 0, "alpha": 0, "a": 0, "d": "0.333"},
    {"type": "R", "theta": 0, "alpha": "-pi/2", "a": 0, "d": 0},
    {"type": "R", "theta": 0, "alpha": "pi/2", "a": 0, "d": "0.316"},
    {"type": "R", "theta": 0, "alpha": "pi/2", "a": "0.0825", "d": 0}],
    "angles": "radians", "tool": {"xyz": [0, 0, "0.107"], "rpy": [0, 0, 0]}}


def test_minors_factored_by_the_pool_are_sympys_factorisations_and_the_charpoly_is_exact():
    """Issue 41 item 3: the minors of J are factored by exact division by the factors of shorter minors
    (``charpoly._FactorPool``) instead of SymPy's ``factor_list``.  On the first four rows of the Panda's table (6 x 4
    geometric Jacobian, middle frame) each minor is the product of its pool factors (exact ring identity) and
    the factors are SymPy's own ``factor_list`` ones; the polynomial's roots are numpy's eigenvalues of J J^T, and
    each coefficient equals the sum of the principal minors of J J^T exactly (SymPy, sines and cosines at rational
    points of the unit circle)."""
    robot = DHRobot.from_dict(PANDA_4)
    J = robot._middle_frame_jacobian("geometric")
    minors, _ = charpoly._ring_minors(J)
    distinct = {-m if m.LC < 0 else m for m in minors.values() if m}
    pool = charpoly._FactorPool(next(iter(distinct)).ring)
    for m in sorted(distinct, key=len):
        content, factors = pool.factor(m)
        product = m.ring.ground_new(content)
        for f, e in factors:
            product *= f**e
        assert product == m
        ours = sorted((str(f.monic()), e) for f, e in factors)
        assert ours == sorted((str(f.monic()), e) for f, e in m.factor_list()[1])
    p = robot.characteristic_polynomial("geometric")
    assert not p.as_expr().has(sp.Determinant) and not dummies(p)
    _eigenvalues_agree(robot, p, "geometric")
    t = {q: sp.Rational(k + 2, 7) for k, q in enumerate(robot.q)}     # sin, cos at (2t, 1 - t^2) / (1 + t^2)
    circle = {f(q): v for q, u in t.items()
              for f, v in ((sp.sin, 2 * u / (1 + u**2)), (sp.cos, (1 - u**2) / (1 + u**2)))}
    Jq = sp.expand_trig(J).xreplace(circle)
    G = Jq * Jq.T
    lam = sp.Symbol("lambda")
    expected = G.charpoly(lam).all_coeffs()
    for c, e in zip(p.all_coeffs(), expected):
        assert sp.expand(sp.expand_trig(c).xreplace(circle)) == e


_x, _y, _t = sp.symbols("x y theta1")
_TERMS = st.sampled_from([_x, _y, sp.cos(_t), sp.sin(_t), _x * sp.cos(_t), sp.sin(_t) ** 2, sp.I * _y, sp.pi,
                          sp.sqrt(2), sp.I, sp.Integer(1), sp.oo, -sp.oo, sp.zoo,
                          sp.Integer(0)])


@settings(max_examples=150, deadline=None)
@given(terms=st.lists(_TERMS, min_size=1, max_size=4),
       coefficients=st.lists(st.fractions(min_value=-3, max_value=3, max_denominator=4), min_size=4, max_size=4),
       exp=st.sampled_from([2, 4, -1, -2, sp.Rational(1, 2)]))
@example(terms=[_x, sp.oo], coefficients=[1, 1, 1, 1], exp=2)          # a sum of two terms, one infinite
@example(terms=[sp.sqrt(2), sp.Integer(1)], coefficients=[1, 1, 1, 1], exp=2)   # a number: SymPy expands it
@example(terms=[_x, _y], coefficients=[-1, -1, 1, 1], exp=2)           # a sum whose sign could be taken out
@example(terms=[sp.Integer(1), sp.I], coefficients=[3, 4, 1, 1], exp=-1)     # 1/(3 + 4i) = (3 - 4i)/25
@example(terms=[sp.Integer(1), sp.I], coefficients=[3, 4, 1, 1], exp=sp.Rational(1, 2))   # sqrt(3 + 4i) = 2 + i
def test_the_squared_minors_are_the_powers_sympy_builds(terms, coefficients, exp):
    """The powers, products and sums of the squared-minor sums are built without SymPy's question whether a
    two-term sum holds an infinite term (seconds on the Panda); reference: SymPy's own ``base**exp``,
    ``Mul(c, *(f**m))`` and ``Add(*terms)``, compared by ``srepr`` (the same object, not only an equal value), over
    sums with numbers, infinities and imaginary terms, equal bases, and terms equal up to a rational factor."""
    rationals = [sp.Rational(c.numerator, c.denominator) for c in coefficients]
    base = sp.Add(*(c * t for c, t in zip(rationals, terms)))
    assert sp.srepr(charpoly._power(base, exp)) == sp.srepr(base**exp)
    if not (sp.sympify(exp).is_Integer and exp > 0):
        return
    for coeff in (sp.Integer(1), rationals[0], -rationals[1]):
        for powers in ([(base, exp)], [(base * _x**3 * sp.cos(_t), exp), (_y, 1)], [(base, 1), (_x, exp)],
                       [(base, exp), (base, 1)], [(rationals[2] * _x * base, exp), (sp.sin(_t), 3)]):
            built = charpoly._product(coeff, powers)
            assert sp.srepr(built) == sp.srepr(sp.Mul(coeff, *(f**m for f, m in powers)))
    products = [charpoly._product(c, [(base, exp), (_y, 2)]) for c in rationals] + [
        charpoly._product(rationals[3], [(t, exp)]) for t in terms]
    assert sp.srepr(charpoly._sum(products)) == sp.srepr(sp.Add(*products))
