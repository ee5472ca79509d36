"""DH kinematics: exact identities (paper 004), an independent numpy DH product,
finite differences, and hypothesis properties."""

import functools

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dh_reference import fk_numpy
from workspace_sym import (
    DHJoint,
    DHRobot,
    DHTableError,
    ExpressionError,
    JointLimitError,
    UnknownNameError,
    characteristic_polynomial,
    eigenvalues_from_charpoly,
    robots,
)
from workspace_sym.symbolic import textbook

th = sp.symbols("theta1:7")
d1, a1, a2, a3, d5 = sp.symbols("d1 a1 a2 a3 d5")
c = {k: sp.cos(th[k - 1]) for k in range(1, 7)}
s = {k: sp.sin(th[k - 1]) for k in range(1, 7)}
c23, s23 = sp.cos(th[1] + th[2]), sp.sin(th[1] + th[2])
c234, s234 = sp.cos(th[1] + th[2] + th[3]), sp.sin(th[1] + th[2] + th[3])


# ---------------------------------------------------------------- paper 004, exact identities
def test_glass_position_is_exactly_the_papers(glass):
    """Paper 004, section 6: x = c1 (a1 + a2 c2 + a3 c23 + s234 d5), ... (structural equality, not just value)."""
    inner = a1 + a2 * c[2] + a3 * c23 + s234 * d5
    x, y, z = glass.position
    assert x == c[1] * inner
    assert y == s[1] * inner
    assert z == d1 + a2 * s[2] + a3 * s23 - c234 * d5


def test_glass_position_prints_as_textbook(glass):
    assert glass.to_str(glass.position[0]) == "c1*(a1 + a2*c2 + a3*c23 + d5*s234)"


def test_glass_rotation_is_the_corrected_form(glass):
    """Paper 004 with theta6 = 0; row 2 as corrected in docs/methods.md section 1 (c234, not s234)."""
    R = glass.rotation.subs(th[5], 0)
    expected = sp.Matrix([
        [s[1] * s[5] + c[1] * c234 * c[5], s[1] * c[5] - c[1] * c234 * s[5], c[1] * s234],
        [-c[1] * s[5] + s[1] * c234 * c[5], -c[1] * c[5] - s[1] * c234 * s[5], s[1] * s234],
        [s234 * c[5], -s234 * s[5], -c234],
    ])
    assert (R - expected).applyfunc(sp.expand) == sp.zeros(3, 3)


def test_glass_paper_misprint_is_not_reproduced(glass):
    """The paper's first printing has s234 in entry (2, 1); that is not an identity: the difference is nonzero at
    one configuration (exact angles, evaluated to 30 digits), which proves it without SymPy's simplify."""
    R = glass.rotation.subs(th[5], 0)
    misprint = -c[1] * s[5] + s[1] * s234 * c[5]
    point = dict(zip(th[:5], (sp.pi / 3, sp.pi / 5, sp.pi / 7, -sp.pi / 4, sp.pi / 6)))
    assert abs(sp.N((R[1, 0] - misprint).xreplace(point), 30)) > sp.Rational(1, 100)


def test_partial_transforms_chain(glass):
    """T_0^k = T_0^(k-1) A_k for every k (exact)."""
    for k in range(1, glass.n + 1):
        product = glass.fk(k - 1) * glass.row_matrix(k)
        assert sp.simplify(sp.expand_trig(product - glass.fk(k))) == sp.zeros(4, 4)


def test_glass_singular_factors(glass):
    """Elbow stretched (s3 = 0) is the only joint-space singularity of the 6 x 5 twist map."""
    assert glass.singular_factors("geometric") == [a2, a3, s[3]]
    assert glass.singular_factors("position") == [a1 + a2 * c[2] + a3 * c23 + d5 * s234]


def test_puma_det_factors(puma):
    """Textbook Puma 560 determinant: a2 s5 (a3 s3 + d4 c3)(a2 c2 + a3 c23 - d4 s23) up to sign."""
    A2, A3, D4 = sp.symbols("a2 a3 d4")
    expected = {A2, s[5], A3 * s[3] + D4 * c[3], A2 * c[2] + A3 * c23 - D4 * s23}
    got = puma.singular_factors()
    assert len(got) == 4
    for f in got:
        assert f in expected or -f in expected


def test_planar_2r_position_singularity():
    robot = robots.build("planar-2r")
    assert robot.singular_factors("position") == [sp.Symbol("l1"), sp.Symbol("l2"), s[2]]


# ---------------------------------------------------------------- numeric cross-checks
CATALOG_DH = ["glass-handling", "puma560", "scara", "planar-3r"]


@functools.cache
def _cached_robot(name):
    """One robot per name for the numeric and characteristic-polynomial tests (its derivations are kept)."""
    return robots.build(name)


@pytest.mark.parametrize("name", CATALOG_DH)
def test_fk_matches_independent_numpy_product(name):
    robot = _cached_robot(name)
    rng = np.random.default_rng(7)
    lim = robot.joint_limits()
    q = lim[:, 0] + (lim[:, 1] - lim[:, 0]) * rng.random((25, robot.n))
    T = robot.fk_numeric(q)
    for k in range(len(q)):
        np.testing.assert_allclose(T[k], fk_numpy(robot, q[k]), atol=1e-12)


def test_modified_dh_matches_independent_product():
    """Craig convention: a planar 3R with a twisted base, compared with a plain numpy product."""
    L1, L2 = sp.symbols("L1 L2")
    data = {"convention": "modified", "angles": "degrees", "parameters": {"L1": 0.7, "L2": 0.4},
            "joints": [{"type": "R", "d": 0.1, "a": 0, "alpha": 0},
                       {"type": "R", "d": 0, "a": "L1", "alpha": 90},
                       {"type": "P", "theta": 30, "a": "L2", "alpha": -90, "limits": [0, 0.5]}]}
    robot = DHRobot.from_dict(data)
    assert robot.convention == "modified" and robot.joints[2].kind == "P"
    rng = np.random.default_rng(3)
    for _ in range(10):
        q = rng.uniform(-2, 2, 3)
        np.testing.assert_allclose(robot.fk_numeric(q), fk_numpy(robot, q), atol=1e-12)


def _numeric_twist_jacobian(robot, q, h=1e-6):
    """Central differences of the numeric FK: linear part from p, angular part from dR R^T."""
    J = np.zeros((6, robot.n))
    T0 = robot.fk_numeric(q)
    for k in range(robot.n):
        dq = np.zeros(robot.n)
        dq[k] = h
        Tp, Tm = robot.fk_numeric(q + dq), robot.fk_numeric(q - dq)
        J[:3, k] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T0[:3, :3].T
        J[3:, k] = [W[2, 1], W[0, 2], W[1, 0]]
    return J


@pytest.mark.parametrize("name", CATALOG_DH)
def test_geometric_jacobian_matches_finite_differences(name):
    robot = _cached_robot(name)
    rng = np.random.default_rng(11)
    for _ in range(8):
        q = rng.uniform(-2.5, 2.5, robot.n)
        np.testing.assert_allclose(robot.jacobian_numeric(q), _numeric_twist_jacobian(robot, q), atol=1e-7)


@pytest.mark.parametrize("convention", ["zyz", "rpy"])
def test_analytic_jacobian_matches_derivative_of_euler_angles(glass, convention):
    aj = glass.analytic_jacobian(convention)
    J = glass.numeric(aj.J)
    angles = glass.numeric(sp.Matrix(aj.angles))
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = rng.uniform(-1.2, 1.2, 6)
        q[1:4] = rng.uniform(0.2, 0.5, 3)  # away from the representation singularity
        h = 1e-6
        for k in range(6):
            dq = np.zeros(6)
            dq[k] = h
            fd = (angles(q + dq) - angles(q - dq))[:, 0] / (2 * h)
            np.testing.assert_allclose(J(q)[3:, k], fd, atol=1e-6)
    assert aj.singular_when.has(sp.cos(th[1] + th[2] + th[3])) or aj.singular_when.has(sp.sin(th[4] + th[5]))


angles6 = arrays(np.float64, 6, elements=st.floats(-np.pi, np.pi, allow_nan=False))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(q=angles6)
def test_rotation_is_orthonormal(glass, q):
    """Property: R R^T = I and det R = 1 at any configuration (glass arm, default lengths)."""
    T = glass.fk_numeric(q)
    R = T[:3, :3]
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert abs(np.linalg.det(R) - 1) < 1e-12


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(q=arrays(np.float64, 4, elements=st.floats(-3, 3, allow_nan=False)))
def test_prismatic_column_is_axis_and_zero(scara, q):
    """Property: the prismatic column of the SCARA Jacobian is [z_2; 0] with |z_2| = 1."""
    J = scara.jacobian_numeric(q)
    T2 = scara.numeric(scara.fk(2))(q)
    np.testing.assert_allclose(J[:3, 2], T2[:3, 2], atol=1e-12)
    np.testing.assert_allclose(J[3:, 2], 0, atol=1e-15)


def test_numeric_fk_is_vectorised_over_many_configurations(glass):
    q = np.random.default_rng(0).uniform(-1, 1, (100_000, 6))
    T = glass.fk_numeric(q)
    assert T.shape == (100_000, 4, 4)
    np.testing.assert_allclose(T[123], fk_numpy(glass, q[123]), atol=1e-12)


# ---------------------------------------------------------------- characteristic polynomial
def test_charpoly_eigenvalues_match_numpy(glass):
    """Eigenvalues of J J^T (position Jacobian) from the characteristic polynomial vs eigvalsh."""
    Jp = glass.substitute(glass.position_jacobian)
    lam = sp.Symbol("lambda")
    poly = characteristic_polynomial(Jp, lam, gram=True, simplify=None)
    assert poly.degree() == 3
    rng = np.random.default_rng(2)
    for _ in range(5):
        q = rng.uniform(-1.5, 1.5, 6)
        values = dict(zip(glass.q, map(sp.Float, q)))
        Jn = glass.numeric(glass.position_jacobian)(q)
        np.testing.assert_allclose(eigenvalues_from_charpoly(poly, values), np.linalg.eigvalsh(Jn @ Jn.T),
                                   rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("name, kind", [("glass-handling", "position"), ("glass-handling", "geometric"),
                                        ("puma560", "position"), ("puma560", "geometric"),
                                        ("planar-3r", "geometric")])
def test_robot_charpoly_eigenvalues_match_numpy(name, kind):
    """Cross-check: roots of the Cauchy-Binet characteristic polynomial (computed on rows in a middle frame)
    are numpy's eigenvalues of J J^T of the unrotated Jacobian, at random configurations."""
    robot = _cached_robot(name)
    poly = robot.characteristic_polynomial(kind)
    J = robot.jacobian(kind)
    assert poly.degree() == J.rows
    Jf = robot.numeric(J)
    rng = np.random.default_rng(5)
    for _ in range(4):
        q = rng.uniform(-3, 3, robot.n)
        values = {**{k: sp.Float(v) for k, v in robot.parameters.items()}, **dict(zip(robot.q, map(sp.Float, q)))}
        Jn = Jf(q)
        np.testing.assert_allclose(eigenvalues_from_charpoly(poly, values), np.linalg.eigvalsh(Jn @ Jn.T),
                                   rtol=1e-9, atol=1e-12)


def test_robot_charpoly_is_the_expanded_determinant():
    """Exact identity: the sum-of-squared-minors coefficients equal those of det(lambda I - J J^T) expanded by
    SymPy's own charpoly (planar 3R, symbolic lengths), after reducing s^2 + c^2."""
    robot = robots.build("planar-3r")
    J = robot.position_jacobian
    lam = sp.Symbol("lambda")
    ours = robot.characteristic_polynomial("position", lam).all_coeffs()
    reference = (J * J.T).charpoly(lam, simplify=lambda e: e).all_coeffs()
    for a, b in zip(ours, reference, strict=True):
        assert textbook(sp.expand(sp.expand_trig(a - b))) == 0


@pytest.mark.parametrize("name", ["glass-handling", "puma560"])
def test_robot_charpoly_every_angle_in_shorthand(name):
    """No sine or cosine is left that the shorthand cannot name (no 2*theta3, no unshortened sums)."""
    robot = _cached_robot(name)
    for kind in ("position", "geometric"):
        for c in robot.characteristic_polynomial(kind).all_coeffs():
            text = robot.to_str(c)
            assert "sin(" not in text and "cos(" not in text, text


def test_charpoly_exact_identity():
    a, b = sp.symbols("a b")
    p = characteristic_polynomial(sp.Matrix([[a, 1], [0, b]]), sp.Symbol("x"))
    assert sp.expand(p.as_expr() - (sp.Symbol("x") - a) * (sp.Symbol("x") - b)) == 0


# ---------------------------------------------------------------- bad input
def test_missing_dh_field_names_the_field():
    with pytest.raises(DHTableError, match=r"joint 2: missing field 'alpha'"):
        DHRobot.from_dict({"joints": [{"d": 0, "a": 1, "alpha": 0}, {"d": 0, "a": 1}]})


def test_unparsable_expression_names_the_field():
    with pytest.raises(ExpressionError, match=r"joint 1 a: cannot read '2\*\(' "):
        DHRobot.from_dict({"joints": [{"d": 0, "a": "2*(", "alpha": 0}]})


def test_inverted_limits_name_joint_and_values():
    with pytest.raises(JointLimitError, match=r"upper limit of joint 1 \(-10\) must exceed its lower limit \(25\)"):
        DHRobot.from_dict({"joints": [{"d": 0, "a": 1, "alpha": 0, "limits": [25, -10]}]})


def test_unknown_convention_and_robot():
    with pytest.raises(UnknownNameError, match="convention must be one of 'standard', 'modified'; got 'craig'"):
        DHRobot.from_dict({"convention": "craig", "joints": [{"d": 0, "a": 1, "alpha": 0}]})
    with pytest.raises(UnknownNameError, match="robot 'r2d2' is not in the catalog"):
        robots.get("r2d2")


def test_nan_and_empty_table_refused():
    with pytest.raises(ExpressionError, match="finite"):
        DHRobot.from_dict({"joints": [{"d": float("nan"), "a": 1, "alpha": 0}]})
    with pytest.raises(DHTableError, match="non-empty list"):
        DHRobot.from_dict({"joints": []})


def test_exact_degrees_stay_exact():
    robot = DHRobot.from_dict({"joints": [{"d": 0, "a": "1/3", "alpha": 90, "limits": [-60, 45]}]})
    j = robot.joints[0]
    assert j.alpha == sp.pi / 2 and j.a == sp.Rational(1, 3)
    assert j.limits == (-sp.pi / 3, sp.pi / 4)


# ---------------------------------------------------------------- issue 18: any dependence of theta_i / d_i on q_i
def _twist_from_fk_derivative(robot):
    """Reference Jacobian by differentiating the symbolic FK: v = dp/dq_k, omega = vee(dR/dq_k R^T), the derivatives
    symbolic (SymPy's diff of each entry of T) and the product dR/dq_k R^T in floats (the symbolic product took a
    third of the test's time): ``f(q) -> (6, n)``."""
    T = robot.fk()
    n = len(robot.q)
    parts = robot.numeric(sp.Matrix.hstack(T[:3, :], *[sp.diff(T[:3, :], q) for q in robot.q]))

    def jacobian(q):
        M = np.asarray(parts(np.atleast_2d(q)), dtype=float).reshape(3, 4 * (n + 1))
        R = M[:, :3]
        cols = []
        for k in range(n):
            dT = M[:, 4 * (k + 1):4 * (k + 2)]
            W = dT[:, :3] @ R.T
            cols.append(np.r_[dT[:, 3], W[2, 1], W[0, 2], W[1, 0]])
        return np.array(cols).T
    return jacobian


def _fd_jacobian_numpy(robot, q, h=1e-6):
    """Central differences of the plain-numpy DH product (tests/helpers/dh_reference.py): independent of the
    symbolic FK."""
    J = np.zeros((6, robot.n))
    R0 = fk_numpy(robot, q)[:3, :3]
    for k in range(robot.n):
        dq = np.zeros(robot.n)
        dq[k] = h
        Tp, Tm = fk_numpy(robot, q + dq), fk_numpy(robot, q - dq)
        J[:3, k] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ R0.T
        J[3:, k] = [W[2, 1], W[0, 2], W[1, 0]]
    return J


REVERSED_RP = {"angles": "radians", "joints": [
    {"type": "R", "variable": "q1", "theta": "-q1", "d": 0, "a": 1, "alpha": 0},
    {"type": "P", "variable": "q2", "theta": 0, "d": "-q2", "a": 0, "alpha": 0}]}


def test_reversed_joints_issue_18_example():
    """Issue 18: p = (cos q1, -sin q1, -q2), so the exact columns are (-sin q1, -cos q1, 0) and (0, 0, -1)."""
    robot = DHRobot.from_dict(REVERSED_RP)
    q1, q2 = sp.symbols("q1 q2")
    assert robot.position == sp.Matrix([sp.cos(q1), -sp.sin(q1), -q2])
    expected = sp.Matrix([[-sp.sin(q1), 0], [-sp.cos(q1), 0], [0, -1], [0, 0], [0, 0], [-1, 0]])
    assert robot.geometric_jacobian == expected
    assert robot.analytic_jacobian("rpy").J[:3, :] == expected[:3, :]


def test_jaco_like_reversed_first_joint_matches_numpy_differences():
    """A Kinova-Jaco-style first joint (theta1 = -q1, d1 = 0.2755, alpha1 = pi/2) and a scaled prismatic joint."""
    data = {"angles": "radians", "joints": [
        {"type": "R", "variable": "q1", "theta": "-q1", "d": 0.2755, "a": 0, "alpha": "pi/2"},
        {"type": "R", "variable": "q2", "theta": "q2 - pi/2", "d": 0, "a": 0.41, "alpha": "pi"},
        {"type": "P", "variable": "q3", "theta": "pi/2", "d": "2*q3 + 1/10", "a": 0, "alpha": "pi/2"},
        {"type": "R", "variable": "q4", "theta": "q4/2 + pi/6", "d": 0.1, "a": 0.05, "alpha": "-pi/3"}]}
    robot = DHRobot.from_dict(data)
    rng = np.random.default_rng(18)
    for _ in range(5):
        q = rng.uniform(-2, 2, robot.n)
        np.testing.assert_allclose(robot.jacobian_numeric(q), _fd_jacobian_numpy(robot, q), atol=1e-7)


@pytest.mark.parametrize("convention", ["zyz", "rpy"])
def test_analytic_jacobian_of_reversed_joints_matches_euler_angle_differences(convention):
    """Reversed, scaled and nonlinear joints: position rows against numpy DH differences, angle rows
    against central differences of the Euler angles."""
    data = {"angles": "radians", "joints": [
        {"type": "R", "variable": "q1", "theta": "-q1", "d": 0.3, "a": 0, "alpha": "pi/2"},
        {"type": "R", "variable": "q2", "theta": "2*q2", "d": 0, "a": 0.4, "alpha": 0},
        {"type": "P", "variable": "q3", "theta": "pi/2", "d": "-q3/2", "a": 0, "alpha": "pi/2"},
        {"type": "R", "variable": "q4", "theta": "q4 + q4**2/4", "d": 0, "a": 0, "alpha": 0}]}
    robot = DHRobot.from_dict(data)
    aj = robot.analytic_jacobian(convention)
    J, angles = robot.numeric(aj.J), robot.numeric(sp.Matrix(aj.angles))
    rng, h = np.random.default_rng(9), 1e-6
    for _ in range(4):
        q = rng.uniform(-1, 1, robot.n)
        np.testing.assert_allclose(J(q)[:3], _fd_jacobian_numpy(robot, q)[:3], atol=1e-7)
        for k in range(robot.n):
            dq = np.zeros(robot.n)
            dq[k] = h
            fd = (angles(q + dq) - angles(q - dq))[:, 0] / (2 * h)
            np.testing.assert_allclose(J(q)[3:, k], fd, atol=1e-6)


_lengths = st.sampled_from([0, 1, sp.Rational(1, 2), sp.Rational(-3, 4), "L"])
_twelfths = st.integers(-11, 12).map(lambda k: sp.pi * k / 12)


@st.composite
def dh_tables(draw, *, rates=True, max_joints=4):
    """Random DH tables: R and P joints, alpha and offsets multiples of pi/12, lengths symbolic, rational
    or zero; with ``rates`` the joint entry is k q + c (k in {1, -1, 2, -1/2}) or the nonlinear q + q^2/4."""
    n = draw(st.integers(2, max_joints))
    convention = draw(st.sampled_from(["standard", "modified"]))
    joints, params = [], {}
    for i in range(1, n + 1):
        kind = draw(st.sampled_from(["R", "P"]))
        q = sp.Symbol(f"q{i}")

        def length(tag, i=i):
            v = draw(_lengths)
            if v == "L":
                sym = sp.Symbol(f"{tag}{i}")
                params[sym] = draw(st.sampled_from([0.3, 0.7, 1.1]))
                return sym
            return sp.sympify(v)

        if rates:
            k = draw(st.sampled_from([1, -1, 2, sp.Rational(-1, 2), "nonlinear"]))
            motion = q + q ** 2 / 4 if k == "nonlinear" else k * q
        else:
            motion = q
        a, d, alpha, offset = length("a"), length("d"), draw(_twelfths), draw(_twelfths)
        if kind == "R":
            joints.append(DHJoint("R", motion + offset, d, a, alpha, q))
        else:
            joints.append(DHJoint("P", offset, motion + length("e"), a, alpha, q))
    return DHRobot(joints, convention=convention, parameters=params)


@settings(max_examples=12, deadline=None)      # 12 random tables (30 before: a minute and a half of SymPy)
@given(robot=dh_tables(max_joints=3))
def test_jacobian_is_the_derivative_of_fk(robot):
    """Property (issue 18.1): linear rows = dp/dq and angular rows = vee(dR/dq R^T), reference by symbolic
    differentiation of FK, compared at random points; FK itself against the plain-numpy DH product."""
    J = robot.numeric(robot.geometric_jacobian)
    ref = _twist_from_fk_derivative(robot)
    rng = np.random.default_rng(0)
    for _ in range(3):
        q = rng.uniform(-2, 2, robot.n)
        np.testing.assert_allclose(robot.fk_numeric(q), fk_numpy(robot, q), atol=1e-12)
        np.testing.assert_allclose(J(q), ref(q), atol=1e-10)


@settings(max_examples=8, deadline=None)
@given(robot=dh_tables(max_joints=2))
def test_jacobian_matches_numpy_differences(robot):
    """Property: the same Jacobians against central differences of the independent numpy DH product."""
    rng = np.random.default_rng(1)
    q = rng.uniform(-2, 2, robot.n)
    np.testing.assert_allclose(robot.jacobian_numeric(q), _fd_jacobian_numpy(robot, q), atol=1e-6)


# ---------------------------------------------------------------- issue 18.2: singular factors on any DH table
def _rank_loss_at_zero_of(robot, kind, factor, seed=0):
    """Find a real point where ``factor`` vanishes (bisection along one variable from a random point) and
    return (r-th singular value / largest) of the Jacobian there, r its generic rank; None if no real zero
    was found (a factor without real zeros cannot report a false singularity)."""
    syms = list(robot.q) + sorted(robot.symbols, key=str)
    J = sp.lambdify(syms, robot.jacobian(kind), "numpy")
    f = sp.lambdify(syms, factor, "numpy")
    rng = np.random.default_rng(seed)
    x0 = np.concatenate([rng.uniform(-2, 2, robot.n), rng.uniform(0.3, 1.5, len(syms) - robot.n)])
    sv = np.linalg.svd(np.array(J(*x0), dtype=float), compute_uv=False)
    r = int(np.sum(sv > 1e-9 * sv[0]))
    for k in sorted(range(len(syms)), key=lambda k: syms[k] not in factor.free_symbols):
        if syms[k] not in factor.free_symbols:
            continue
        grid = np.linspace(-3.1, 3.1, 621)
        vals = []
        for g in grid:
            x = x0.copy()
            x[k] = g
            vals.append(float(f(*x)))
        vals = np.array(vals)
        hits = np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)[0]
        if not hits.size:
            continue
        lo, hi = grid[hits[0]], grid[hits[0] + 1]
        x = x0.copy()
        for _ in range(80):
            x[k] = (lo + hi) / 2
            x_lo = x0.copy()
            x_lo[k] = lo
            if np.sign(f(*x)) == np.sign(f(*x_lo)):
                lo = x[k]
            else:
                hi = x[k]
        x[k] = (lo + hi) / 2
        sv = np.linalg.svd(np.array(J(*x), dtype=float), compute_uv=False)
        return sv[r - 1] / max(1.0, sv[0])
    return None


PINNED_TABLES = [
    DHRobot([DHJoint.revolute(1, a=1, alpha=sp.pi / 4), DHJoint.revolute(2, a=1)]),  # crashed: sqrt(2)
    DHRobot([DHJoint.revolute(1, a=1, alpha=sp.pi / 3, offset=sp.pi / 4), DHJoint.revolute(2, a=1)]),
    DHRobot([DHJoint.revolute(1, a=1), DHJoint.prismatic(2)]),  # crashed: constant rotated Jacobian
]


@pytest.mark.parametrize("robot", PINNED_TABLES, ids=["alpha-pi/4", "alpha-pi/3-offset-pi/4", "R-then-P"])
def test_pinned_crashes_of_issue_18(robot):
    """These raised ValueError / AttributeError; now the factors are exact and vanish where the rank drops."""
    assert robot.singular_factors() == []  # twist maps of rank 2 everywhere: the two angular columns differ
    factors = robot.singular_factors("position")
    assert all(f.free_symbols for f in factors)
    for f in factors:
        ratio = _rank_loss_at_zero_of(robot, "position", f)
        assert ratio is None or ratio < 1e-8


def test_surd_table_folded_elbow_factor():
    """2R with alpha1 = pi/4 and equal links: the 3 x 2 position Jacobian loses rank only at theta2 = pi,
    where the tip folds back onto the first axis (column 1 = z0 x p = 0); stretched (theta2 = 0) it does not,
    the two axes being 45 degrees apart.  The gcd of the minors is cos(theta2/2), reported as 1 + c2."""
    robot = PINNED_TABLES[0]
    assert robot.singular_factors("position") == [sp.cos(th[1]) + 1]
    J = robot.numeric(robot.position_jacobian)
    assert np.linalg.svd(J([0.7, np.pi]), compute_uv=False)[1] < 1e-12
    assert np.linalg.svd(J([0.7, 0.0]), compute_uv=False)[1] > 0.1


# Up to 3 joints: a 3-joint table with several pi/12 twists takes 1 to 10 s (gcds and factors with the
# square roots as symbols, long factors left ungathered).  Derandomized: the suite must finish, and 180
# random 3-joint draws checked by hand (under 10 s each) do not prove every future draw does.  10 draws (20
# before): each is a fresh table of twists and offsets at multiples of pi/12; `make explore` draws new ones.
@settings(max_examples=10, deadline=None, derandomize=True)
@given(robot=dh_tables(rates=False, max_joints=3))
def test_singular_factors_never_crash_and_vanish_where_rank_drops(robot):
    """Property (issue 18.2): fk, jacobian and singular_factors finish on random 2- and 3-joint tables (alpha, offsets
    multiples of pi/12, R and P, lengths symbolic / rational / zero), and at a numerically found zero of
    every reported factor the Jacobian's generic-rank singular value vanishes."""
    assert robot.fk().shape == (4, 4) and robot.jacobian().shape == (6, robot.n)
    for kind in ("geometric", "position"):
        for f, m in robot.singular_factors(kind, multiplicity=True):
            assert m >= 1
            if f == 0:
                continue  # Jacobian identically zero (all rows dropped)
            assert f.free_symbols
            ratio = _rank_loss_at_zero_of(robot, kind, f)
            assert ratio is None or ratio < 1e-7, (kind, f, ratio)


# ---------------------------------------------------------------- issue 18.3: multiplicities, float lengths
def test_stanford_multiplicities_divide_det():
    """Stanford arm (Spong et al., table 3.5): det J = +-q3^2 s2 s5; factors with exponents."""
    q3, d2 = sp.Symbol("q3"), sp.Symbol("d2")
    robot = DHRobot([DHJoint.revolute(1, alpha=-sp.pi / 2), DHJoint.revolute(2, d=d2, alpha=sp.pi / 2),
                     DHJoint.prismatic(3, variable=q3), DHJoint.revolute(4, alpha=-sp.pi / 2),
                     DHJoint.revolute(5, alpha=sp.pi / 2), DHJoint.revolute(6)])
    pairs = robot.singular_factors(multiplicity=True)
    assert pairs == [(q3, 2), (s[2], 1), (s[5], 1)]
    # det J / (q3^2 s2 s5) is the same constant of modulus 1 at random points (numeric, independent of factoring).
    J = robot.numeric(robot.geometric_jacobian, {d2: 0.3})
    rng = np.random.default_rng(6)
    ratios = []
    for _ in range(4):
        q = rng.uniform(-2, 2, 6)
        ratios.append(np.linalg.det(J(q)) / (q[2] ** 2 * np.sin(q[1]) * np.sin(q[4])))
    np.testing.assert_allclose(np.abs(ratios), 1, rtol=1e-9)
    assert len({np.sign(r) for r in ratios}) == 1
    assert robot.singular_factors() == [q3, s[2], s[5]]


UR5_FLOAT = [dict(d=0.089159, alpha=sp.pi / 2), dict(a=-0.425), dict(a=-0.39225),
             dict(d=0.10915, alpha=sp.pi / 2), dict(d=0.09465, alpha=-sp.pi / 2), dict(d=0.0823)]


def test_float_lengths_give_readable_factors():
    """UR5 with the float lengths of roboticstoolbox-python's models/DH/UR5.py: the factors keep the decimals
    (they were 28-digit integers) and equal those of the symbolic-length UR5 with the values put back."""
    robot = DHRobot([DHJoint.revolute(k + 1, **row) for k, row in enumerate(UR5_FLOAT)])
    factors = robot.singular_factors()
    assert all(abs(n) < 10 for f in factors for n in f.atoms(sp.Number))
    assert s[3] in factors and s[5] in factors
    wrist = [f for f in factors if f not in (s[3], s[5])]
    assert len(wrist) == 1
    expected = 0.425 * c[2] + 0.39225 * c23 - 0.09465 * s234  # a2 c2 + a3 c23 - d5 s234 with a2 = 0.425 ...
    g = sp.lambdify(th[:6], wrist[0] / expected)
    ratios = [g(*np.random.default_rng(k).uniform(-2, 2, 6)) for k in range(4)]
    np.testing.assert_allclose(ratios, ratios[0], rtol=1e-12)  # the same factor up to a constant


# ---------------------------------------------------------------- issue 18.4: base and tool transforms
def _rpy_numpy(xyz, rpy):
    """Independent homogeneous transform Trans(xyz) Rz(yaw) Ry(pitch) Rx(roll), radians."""
    r, p, y = rpy
    Rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    Ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    Rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = Rz @ Ry @ Rx, xyz
    return T


def test_base_and_tool_match_numpy_product_and_differences():
    """fk = base T_0^n tool against a plain numpy product; the Jacobian of the tool point against central
    differences of that product (the tool offset moves the reference point)."""
    base = {"xyz": [0.1, -0.2, 0.5], "rpy": [10, -20, 30]}
    data = {"angles": "degrees", "base": base, "tool": [[0, -1, 0, 0.05], [1, 0, 0, 0], [0, 0, 1, 0.12], [0, 0, 0, 1]],
            "joints": [{"type": "R", "d": 0.3, "a": 0, "alpha": 90}, {"type": "R", "d": 0, "a": 0.4, "alpha": 0},
                       {"type": "R", "variable": "q3", "theta": "-q3", "d": 0, "a": 0.3, "alpha": -90}]}
    robot = DHRobot.from_dict(data)
    B = _rpy_numpy(base["xyz"], np.radians(base["rpy"]))
    Tt = np.array(data["tool"], dtype=float)

    def world(q):
        return B @ fk_numpy(robot, q) @ Tt

    rng, h = np.random.default_rng(4), 1e-6
    for _ in range(5):
        q = rng.uniform(-2, 2, 3)
        np.testing.assert_allclose(robot.fk_numeric(q), world(q), atol=1e-12)
        J = np.zeros((6, 3))
        for k in range(3):
            dq = np.zeros(3)
            dq[k] = h
            Tp, Tm = world(q + dq), world(q - dq)
            J[:3, k] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
            W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ world(q)[:3, :3].T
            J[3:, k] = [W[2, 1], W[0, 2], W[1, 0]]
        np.testing.assert_allclose(robot.jacobian_numeric(q), J, atol=1e-7)


def test_bad_base_and_tool_are_refused():
    row = [{"type": "R", "d": 0, "a": 1, "alpha": 0}]
    with pytest.raises(DHTableError, match=r"tool: the 3 x 3 block must be a rotation"):
        DHRobot.from_dict({"joints": row, "tool": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]})
    with pytest.raises(DHTableError, match=r"base xyz: expected a list of 3 numbers; got \[1, 2\]"):
        DHRobot.from_dict({"joints": row, "base": {"xyz": [1, 2]}})
    with pytest.raises(DHTableError, match=r"base: expected .* or a 4 x 4 list; got 7"):
        DHRobot.from_dict({"joints": row, "base": 7})
