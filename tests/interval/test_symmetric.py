"""Eigenvalue certificates for symmetric 3 x 3 interval matrices: every enclosure is checked against
exact rational arithmetic on members of the interval matrix (hypothesis)."""

from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from workspace_sym.interval import symmetric

UPPER = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


@st.composite
def interval_matrix(draw, scale=1e3):
    """A symmetric interval matrix (lo, hi) of shape (1, 3, 3) and a float matrix Q (1, 3, 3)."""
    lo, hi = np.empty((1, 3, 3)), np.empty((1, 3, 3))
    for i, j in UPPER:
        a = draw(st.floats(-scale, scale))
        w = draw(st.floats(0, scale / 10))
        lo[0, i, j] = lo[0, j, i] = a
        hi[0, i, j] = hi[0, j, i] = a + w
    Q = np.array(draw(st.lists(st.floats(-1, 1), min_size=9, max_size=9))).reshape(1, 3, 3)
    return (lo, hi), Q


def _member(S, t):
    """The symmetric member lo + t (hi - lo) of S, exactly, for t in [0, 1] given per upper entry."""
    lo, hi = S
    M = [[None] * 3 for _ in range(3)]
    for (i, j), tk in zip(UPPER, t):
        v = Fraction(lo[0, i, j]) + tk * (Fraction(hi[0, i, j]) - Fraction(lo[0, i, j]))
        M[i][j] = M[j][i] = v
    return M


def _congruence_exact(Q, M):
    q = [[Fraction(Q[0, i, j]) for j in range(3)] for i in range(3)]
    return [[sum(q[i][k] * M[i][j] * q[j][l] for i in range(3) for j in range(3)) for l in range(3)]
            for k in range(3)]


members = st.lists(st.sampled_from([Fraction(0), Fraction(1), Fraction(1, 2), Fraction(1, 3)]), min_size=6,
                   max_size=6)


@settings(max_examples=300, deadline=None)
@given(interval_matrix(), members)
def test_congruence_encloses_every_member_exactly(SQ, t):
    """Property: for a member M of S (vertices and interior points), Q^T M Q computed in exact rationals
    lies in the enclosure congruence(Q, S)."""
    S, Q = SQ
    lo, hi = symmetric.congruence(Q, S)
    C = _congruence_exact(Q, _member(S, t))
    for k in range(3):
        for m in range(3):
            assert Fraction(lo[0, k, m]) <= C[k][m] <= Fraction(hi[0, k, m])


def _positive_definite_exact(M):
    a, b, c = M[0][0], M[1][1], M[2][2]
    d, f, g = M[0][1], M[0][2], M[1][2]
    det = a * (b * c - g * g) - d * (d * c - g * f) + f * (d * g - b * f)
    return a > 0 and a * b - d * d > 0 and det > 0


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(0.1, 10), min_size=3, max_size=3), st.lists(st.floats(-1, 1), min_size=3, max_size=3),
       st.floats(0, 0.5), members)
def test_positive_definite_is_never_wrong(diag, off, width, t):
    """Property: when positive_definite says yes, every member checked is positive definite (exact
    Sylvester minors on vertices and interior points)."""
    lo = np.zeros((1, 3, 3))
    for k in range(3):
        lo[0, k, k] = diag[k]
    for (i, j), v in zip(((0, 1), (0, 2), (1, 2)), off):
        lo[0, i, j] = lo[0, j, i] = v
    hi = lo + width
    if symmetric.positive_definite((lo, hi))[0]:
        assert _positive_definite_exact(_member((lo, hi), t))


def test_positive_definite_decides_clear_cases():
    """Not vacuous: a diagonally dominant interval matrix is recognised, an indefinite one is not."""
    lo = np.array([[[2.0, 0.1, -0.2], [0.1, 3.0, 0.3], [-0.2, 0.3, 4.0]]])
    assert symmetric.positive_definite((lo, lo + 0.01))[0]
    lo[0, 2, 2] = -0.5
    assert not symmetric.positive_definite((lo, lo + 0.01))[0]
    assert not symmetric.positive_definite((lo * np.nan, lo))[0]       # NaN: no enclosure, no certificate
