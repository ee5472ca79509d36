"""Orthoglide (Chablat, Wenger, Merlet 2002): the pencil polynomial against numpy eigenvalues,
certified boxes checked with mpmath eigenvalues at 50 digits, the volume bracket against Monte Carlo."""

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from workspace_sym import InvalidParameterError
from workspace_sym.orthoglide import Orthoglide, e1, e2, e3, inverse_entries, lam, x, y, z
from workspace_sym.orthoglide.certificate import witnessed_module


@pytest.fixture(scope="module")
def ortho():
    return Orthoglide()


def _random_points(rng, n, radius=0.8):
    pts = []
    while len(pts) < n:
        p = rng.uniform(-radius, radius, 3)
        if p[1] ** 2 + p[2] ** 2 < 0.95 and p[0] ** 2 + p[2] ** 2 < 0.95 and p[0] ** 2 + p[1] ** 2 < 0.95:
            pts.append(p)
    return pts


def _mp_eigenvalues(p):
    with mpmath.workdps(50):
        px, py, pz = (mpmath.mpf(float(v)) for v in p)
        etas = [mpmath.sqrt(1 - py**2 - pz**2), mpmath.sqrt(1 - px**2 - pz**2), mpmath.sqrt(1 - px**2 - py**2)]
        A = mpmath.matrix([[etas[0], py, pz], [px, etas[1], pz], [px, py, etas[2]]])
        J = mpmath.inverse(A) * mpmath.diag(etas)
        ev, _ = mpmath.eigsy(J * J.T)
        return sorted(ev)


def test_isotropic_at_origin(ortho):
    """Paper section 3: J = I at the isotropic configuration."""
    np.testing.assert_allclose(ortho.eigenvalues([0, 0, 0]), [1, 1, 1], atol=1e-15)


def test_pencil_roots_are_the_eigenvalues(ortho):
    """det(lambda A A^T - B^2) has the eigenvalues of J J^T as roots (numpy eigvalsh as reference)."""
    rng = np.random.default_rng(4)
    for p in _random_points(rng, 8):
        subs = {x: p[0], y: p[1], z: p[2]}
        subs.update({e: float(v.subs(subs)) for e, v in ortho.eta.items()})
        coeffs = [float(c.subs(subs)) for c in ortho.pencil.all_coeffs()]
        roots = np.sort(np.roots(coeffs).real)
        np.testing.assert_allclose(roots, ortho.eigenvalues(p), rtol=1e-8)


def test_charpoly_is_pencil_over_det_squared(ortho):
    """det(lambda I - J J^T) = det(lambda A A^T - B^2) / det(A)^2, compared at 30 digits at a rational point."""
    pt = {x: sp.Rational(1, 5), y: sp.Rational(-1, 7), z: sp.Rational(1, 3)}
    etas = {e: sp.sqrt(v.subs(pt)) for e, v in ortho.eta_squared.items()}
    J = ortho.J.subs(pt).subs(etas).evalf(40)
    direct = sp.Poly((lam * sp.eye(3) - J * J.T).det(method="berkowitz"), lam).all_coeffs()
    via = [c.subs(pt).subs(etas).evalf(40) for c in ortho.charpoly.all_coeffs()]
    for a, b in zip(direct, via):
        assert abs(sp.N(a - b, 30)) < 1e-25


def test_inverse_entries_are_the_symbolic_inverse_and_its_derivatives(ortho):
    """Exact SymPy identity: the short formulas of the box module (with s_i = 1/eta_i^2, r_i = 1/eta_i) are
    A^T B^-2 A and its partial derivatives in x, y, z, as rational functions of x, y, z and the eta_i
    (d eta_i / dx = -x / eta_i and the like)."""
    etas = (e1, e2, e3)
    N, grads = inverse_entries(x, y, z, [1 / e**2 for e in etas], [1 / e for e in etas])
    exact = ortho.inverse
    chain = {v: [sp.diff(ortho.eta[e], v).subs({ortho.eta[k]: k for k in etas}) for e in etas] for v in (x, y, z)}
    for (i, j), v in N.items():
        assert sp.cancel(v - exact[i, j]) == 0
        for var, g in zip((x, y, z), grads):
            total = sp.diff(exact[i, j], var) + sum(sp.diff(exact[i, j], e) * d for e, d in zip(etas, chain[var]))
            assert sp.cancel(g[i, j] - total) == 0
    # and N is the inverse of J J^T (exact, as rational functions of x, y, z and the eta_i)
    assert (exact * ortho.J * ortho.J.T).applyfunc(sp.cancel) == sp.eye(3)


def _mp_inside(p):
    """None outside the cylinders, else whether every eigenvalue of J J^T is in [1/4, 4] at 50 digits."""
    if max(p[1]**2 + p[2]**2, p[0]**2 + p[2]**2, p[0]**2 + p[1]**2) >= 1:
        return None
    ev = _mp_eigenvalues(p)
    return bool(ev[0] >= mpmath.mpf(1) / 4 and ev[-1] <= 4)


@settings(max_examples=150, deadline=None)
@given(centre=st.tuples(*[st.floats(-0.95, 0.95)] * 3), half=st.floats(1e-4, 0.08),
       corner=st.tuples(*[st.floats(0, 1)] * 3))
def test_box_module_never_certifies_falsely(centre, half, corner):
    """Hypothesis: a random box (many straddle the boundary or a cylinder) is never decided against the
    50-digit eigenvalues of one of its points (its centre and a random point are checked)."""
    ortho = Orthoglide()
    c = np.array(centre)
    box = np.stack([c - half, c + half], axis=1)
    code = int(ortho.box_module(box[None])[0])
    if code == 0:
        return
    for p in (c, box[:, 0] + np.array(corner) * (box[:, 1] - box[:, 0])):
        status = _mp_inside(p)
        if code == 1:
            assert status is True
        elif status is not None:
            assert status is False


def test_numeric_dextrous_agrees_with_eigvalsh(ortho):
    """The float Sylvester test against numpy eigenvalues of J J^T at random points of the cylinders
    (a cross-check of a guess: agreement away from the boundary, where float error cannot flip it)."""
    rng = np.random.default_rng(4)
    pts = rng.uniform(-0.7, 0.7, (3000, 3))
    ev = np.array([ortho.eigenvalues(p) for p in pts])
    margin = np.minimum(np.abs(ev[:, 0] - 0.25), np.abs(ev[:, -1] - 4)) > 1e-9
    expected = (ev[:, 0] >= 0.25) & (ev[:, -1] <= 4)
    got = ortho.numeric_dextrous(pts, (0.25, 4.0))
    assert 0.2 < expected.mean() < 0.9 and margin.mean() > 0.99
    assert np.array_equal(got[margin], expected[margin])


def test_witnessed_module_skips_only_undecidable_boxes(ortho):
    """Independent cross-check of both: boxes the witness filter skips (a numerically dextrous and a
    numerically non-dextrous point among the corners and the centre) are never decided by the
    certificate, and on the others the verdicts are the certificate's."""
    rng = np.random.default_rng(5)
    centres = rng.uniform(-0.8, 0.8, (20000, 3))
    half = rng.uniform(0.001, 0.03, (20000, 1))
    boxes = np.stack([centres - half, centres + half], axis=2)
    full = ortho.box_module(boxes)
    witnessed = witnessed_module(boxes, (0.25, 4.0))
    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=float)
    pts = boxes[:, None, :, 0] + corners[None] * (boxes[:, None, :, 1] - boxes[:, None, :, 0])
    ok = ortho.numeric_dextrous(pts.reshape(-1, 3), (0.25, 4.0)).reshape(len(boxes), -1)
    mixed = ok.any(axis=1) & ~ok.all(axis=1)
    assert mixed.sum() > 500                      # the filter has boxes to skip
    assert not full[mixed].any()                  # and the certificate decides none of them
    assert np.array_equal(witnessed, full)
    assert (full == 1).sum() > 1000 and (full == -1).sum() > 1000


@pytest.mark.slow
def test_certified_boxes_agree_with_50_digit_eigenvalues(ortho):
    """Points drawn from boxes certified inside have every eigenvalue in [1/4, 4] (mpmath, 50 digits);
    points from boxes certified outside (inside the cylinders) have one outside.  Six points in each of 150
    outer boxes (about 600 inside the cylinders, 20 a box before: 2,600 eigenvalue problems at 50 digits, most
    of the test's time): a box falsely certified outside is one whose points mostly meet the bound (its
    interval test failed, not an ulp at a corner), so a handful of its points shows it; every box is still
    visited."""
    r = ortho.dextrous(eps=0.125)
    rng = np.random.default_rng(9)
    inner, outer = r.paving.inner, r.paving.outer
    assert len(inner) > 50 and len(outer) > 50
    for b in inner[rng.choice(len(inner), 40, replace=False)]:
        p = b[:, 0] + rng.random(3) * (b[:, 1] - b[:, 0])
        ev = _mp_eigenvalues(p)
        assert ev[0] >= mpmath.mpf(1) / 4 and ev[-1] <= 4
    checked = 0
    for b in outer[rng.choice(len(outer), min(len(outer), 150), replace=False)]:
        for p in b[:, 0] + rng.random((6, 3)) * (b[:, 1] - b[:, 0]):
            if max(p[1]**2 + p[2]**2, p[0]**2 + p[2]**2, p[0]**2 + p[1]**2) >= 1:
                continue  # outside the cylinders: not part of the workspace at all
            ev = _mp_eigenvalues(p)
            assert ev[0] < mpmath.mpf(1) / 4 or ev[-1] > 4
            checked += 1
    assert checked >= 500  # most certified-outside boxes at eps = 0.125 lie inside the cylinders


def test_volume_bracket_contains_monte_carlo(ortho):
    """Independent estimate: uniform points in [-1, 1]^3, numpy eigenvalues."""
    r = ortho.dextrous(eps=0.125)
    rng = np.random.default_rng(1)
    n, hits = 20000, 0
    pts = rng.uniform(-1, 1, (n, 3))
    for p in pts:
        if max(p[1]**2 + p[2]**2, p[0]**2 + p[2]**2, p[0]**2 + p[1]**2) >= 1:
            continue
        ev = ortho.eigenvalues(p)
        hits += bool(ev[0] >= 0.25 and ev[-1] <= 4)
    mc = 8 * hits / n
    sigma = 8 * np.sqrt(hits / n * (1 - hits / n) / n)
    assert r.volume_inner - 4 * sigma <= mc <= r.volume_inner + r.volume_undecided + 4 * sigma
    assert r.volume_inner > 0


def test_beats_the_papers_figures_at_its_eps(ortho):
    """Chablat, Wenger, Merlet 2002, section 4.3: eps = 0.05 gives a volume of 1.468 with an error bound E of
    0.48.  With the last-level boxes shaved we prove more inside and leave less undecided, and the bracket
    [inside, inside + E] meets the one certified at eps = 0.0025 without shaving, [1.6264, 1.6264 + 0.0224]
    (BENCHMARKS.md), which holds the true volume."""
    r = ortho.dextrous(eps=0.05)
    assert r.volume_inner >= 1.468 and r.volume_undecided <= 0.48
    assert r.volume_inner <= 1.6264 + 0.0225 and r.volume_inner + r.volume_undecided >= 1.6264
    total = sum(r.paving.measures[k] for k in ("inner", "boundary", "outer", "pending"))
    assert abs(total - 8) <= 1e-9                                  # the pieces tile [-1, 1]^3


def test_shaving_only_adds_proved_volume(ortho):
    """Shaving the last-level boxes keeps every box the plain bisection proves: at eps = 0.125 the shaved
    paving proves at least as much inside and outside, and its E is smaller."""
    plain, shaved = ortho.dextrous(eps=0.125, shave=()), ortho.dextrous(eps=0.125, shave=(0.5, 0.25))
    assert shaved.volume_inner >= plain.volume_inner + 0.1
    assert shaved.paving.measures["outer"] >= plain.paving.measures["outer"]
    assert shaved.volume_undecided < plain.volume_undecided - 0.1


def test_bad_sigma_and_eps(ortho):
    with pytest.raises(InvalidParameterError, match=r"sigma_max \(0.25\) must exceed sigma_min \(4.0\)"):
        ortho.dextrous(sigma=(4, 0.25))
    with pytest.raises(InvalidParameterError, match="sigma_min must be a positive"):
        ortho.dextrous(sigma=(0, 4))
    with pytest.raises(InvalidParameterError, match="eps must be a positive number; got 0"):
        ortho.dextrous(eps=0)
    with pytest.raises(InvalidParameterError, match=r"shave must be a sequence of fractions in \(0, 1\); got \(1.0,\)"):
        ortho.dextrous(shave=(1.0,))
    with pytest.raises(InvalidParameterError, match="shave must be a sequence of fractions"):
        ortho.dextrous(shave=0.5)


def test_boxes_outside_cylinders_never_crash(ortho):
    """Points outside the legs' cylinders: outside or undecided, never NaN or a crash."""
    boxes = np.array([[[0.9, 1.0], [0.9, 1.0], [-0.1, 0.1]], [[0.6, 0.8], [0.6, 0.8], [0.0, 0.1]]])
    codes = ortho.box_module(boxes)
    assert codes[0] == -1 and codes[1] in (-1, 0)


def test_largest_cube_brackets_the_papers_cube(capsys):
    """Chablat, Wenger, Merlet 2002, section 5: the largest cube has edge 0.643950 and centre
    (0.085938, 0.085938, 0.085938).  At alpha = 0.02 our certified bracket must contain that edge, and
    an independent numeric check (numpy eigenvalues) agrees with both certificates."""
    import json

    import numpy as np

    from workspace_sym.cli import main

    assert main(["cube", "orthoglide", "--alpha", "0.02", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["edge_lower"] <= 0.643950 <= data["edge_upper"]
    assert data["edge_exact"] == "(sqrt(2) + sqrt(6))/6" and "closed_form" in data
    assert data["edge_upper"] - data["edge_lower"] <= 2 * 0.02 + 1e-12
    assert np.allclose(data["center"], 0.085938, atol=0.02)
    ortho = Orthoglide()
    rng = np.random.default_rng(0)
    half = data["edge_lower"] / 2
    pts = np.array(data["center"]) + rng.uniform(-half, half, (2000, 3))
    assert ortho.numeric_dextrous(pts, (0.25, 4.0)).all()
    big = np.array(data["center"]) + data["edge_upper"] / 2 * np.vstack([np.eye(3), -np.eye(3), np.ones((1, 3)),
                                                                         -np.ones((1, 3))])
    assert not ortho.numeric_dextrous(big, (0.25, 4.0)).all()


def test_largest_cube_closed_form_is_exact_and_certified():
    """The binding points are the two corners on the diagonal; the closed form edge (sqrt(2) + sqrt(6))/6 and
    centre (sqrt(6) - sqrt(2))/12 are checked as exact SymPy identities (the pencil vanishes at both corners for
    the bounds found), and the certified bracket at alpha = 1e-5 contains them.  Paper: edge 0.643950."""
    ortho = Orthoglide()
    r = ortho.largest_cube(alpha=1e-5)
    edge, centre = r.exact["edge"], r.exact["center"]
    assert sp.simplify(edge - (sp.sqrt(2) + sp.sqrt(6)) / 6) == 0
    assert sp.simplify(centre - (sp.sqrt(6) - sp.sqrt(2)) / 12) == 0
    assert abs(float(edge) - 0.643950) < 1e-6                  # the paper's edge, to its six digits
    assert r.edge_lower <= float(edge) <= r.edge_upper and r.edge_upper - r.edge_lower <= 2e-5 + 1e-12
    u = sp.Symbol("u")
    q = ortho.pencil.as_expr().subs({x: u, y: u, z: u}).subs({e: sp.sqrt(1 - 2 * u**2) for e in (e1, e2, e3)})
    plus, minus = centre + edge / 2, centre - edge / 2
    for corner, bound in ((plus, sp.Rational(1, 4)), (plus, 4), (minus, 4)):
        assert sp.simplify(q.subs(lam, bound).subs(u, corner)) == 0
    assert r.exact["bounds"] == {"+": ["sigma_max", "sigma_min"], "-": ["sigma_max"]}
    # independent: numpy eigenvalues at the exact corners are on the bounds
    ev_plus, ev_minus = ortho.eigenvalues([float(plus)] * 3), ortho.eigenvalues([float(minus)] * 3)
    assert abs(ev_plus[0] - 0.25) < 1e-12 and abs(ev_plus[-1] - 4) < 1e-11 and abs(ev_minus[-1] - 4) < 1e-11


def test_cube_bad_alpha(capsys):
    from workspace_sym.cli import main

    assert main(["cube", "orthoglide", "--alpha", "-1"]) == 2
    assert "--alpha" in capsys.readouterr().err


def test_largest_cube_takes_the_option_objects():
    """Issue 26: largest_cube takes stop= and run= like pave and dextrous; progress= and executor= (README,
    docs/distributed.md) still work with a DeprecationWarning and give the same certified bracket (reference:
    the new spelling's result).  A budget of one box a search proves only cubes decided in one box: the bracket
    widens on both sides and still holds the paper's edge 0.643950 (a budget never makes a wrong claim)."""
    from concurrent.futures import ThreadPoolExecutor

    from workspace_sym import RunOn, StopAt

    ortho = Orthoglide()
    with ThreadPoolExecutor(2) as pool:
        new = ortho.largest_cube(alpha=0.02, run=RunOn(executor=pool, progress=False))
        with pytest.warns(DeprecationWarning) as caught:
            old = ortho.largest_cube(alpha=0.02, progress=False, executor=pool)
    assert {str(w.message) for w in caught} == {
        "largest_cube: executor= is deprecated; pass run=RunOn(executor=...)",
        "largest_cube: progress= is deprecated; pass run=RunOn(progress=...)"}
    assert caught[0].filename == __file__                     # the warning points at the caller's line
    assert (old.edge_lower, old.edge_upper, old.boxes) == (new.edge_lower, new.edge_upper, new.boxes)
    assert new.edge_lower <= 0.643950 <= new.edge_upper
    starved = ortho.largest_cube(alpha=0.02, stop=StopAt(max_boxes=1))
    assert starved.edge_lower < new.edge_lower and starved.edge_upper > 1.0
    assert starved.edge_lower <= 0.643950 <= starved.edge_upper
