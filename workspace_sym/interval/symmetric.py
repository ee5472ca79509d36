"""Eigenvalue certificates for arrays of symmetric 3 x 3 interval matrices (numpy engine).

A symmetric interval matrix ``S`` is a pair ``(lo, hi)`` of ``(N, 3, 3)`` arrays
standing for every symmetric matrix between them.  The tests here are
statements about *every* member:

* :func:`congruence` encloses ``Q^T S Q`` for a float matrix ``Q`` (outward
  rounded).  With ``Q`` the eigenvectors of a midpoint matrix, the enclosure is
  nearly diagonal, and by Sylvester's law of inertia ``Q^T S Q`` is positive
  definite exactly when ``S`` is (``Q`` is then necessarily non-singular).
* :func:`positive_definite` applies Sylvester's criterion (leading principal
  minors positive) to the enclosure.  Off-diagonal entries enter the minors
  only through products, so once rotated the test is sharp to second order,
  where Gershgorin's discs would lose the first-order sum of the off-diagonal
  widths.
* The diagonal entries of ``Q^T S Q`` against those of ``Q^T Q`` are Rayleigh
  quotients: ``v^T S v > b v^T v`` proves ``lambda_max > b`` and
  ``v^T S v < a v^T v`` proves ``lambda_min < a`` for every member.
"""

from __future__ import annotations

import numpy as np

from . import arith

__all__ = ["from_entries", "congruence", "positive_definite", "scale"]

_UPPER = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


def from_entries(entries) -> tuple[np.ndarray, np.ndarray]:
    """Stack the upper triangle ``{(i, j): interval}`` (``i <= j``; ``(lo, hi)`` pairs or
    :class:`~workspace_sym.interval.arith.Interval`) into a symmetric pair of ``(N, 3, 3)`` arrays.

    Parameters
    ----------
    entries : dict
        The six entries of the upper triangle, keyed ``(i, j)`` with ``0 <= i <= j <= 2``; each an ``(lo, hi)``
        pair of arrays (or floats) or an :class:`~workspace_sym.interval.arith.Interval`.  The shape of entry
        ``(0, 0)`` sets ``N``; the others broadcast to it.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, each of shape ``(N, 3, 3)``, with ``lo[..., j, i] = lo[..., i, j]`` (likewise ``hi``).
    """
    pairs = {k: (v.pair if isinstance(v, arith.Interval) else v) for k, v in entries.items()}
    shape = np.broadcast(*pairs[0, 0]).shape + (3, 3)
    lo, hi = np.empty(shape), np.empty(shape)
    for i, j in _UPPER:
        a, b = pairs[i, j]
        lo[..., i, j] = lo[..., j, i] = a
        hi[..., i, j] = hi[..., j, i] = b
    return lo, hi


def _point_times(q, a):
    """The float array ``q`` times the interval ``a``, outward."""
    p1, p2 = q * a[0], q * a[1]
    return arith.down(np.minimum(p1, p2)), arith.up(np.maximum(p1, p2))


def scale(c: float, a):
    """``c * a`` for a float ``c``, outward.

    Parameters
    ----------
    c : float or numpy.ndarray
        The point factor (an array multiplies element by element).
    a : pair of numpy.ndarray
        The interval ``(lo, hi)``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``: an enclosure of ``c * a``, rounded outward.
    """
    return _point_times(c, a)


def congruence(Q: np.ndarray, S) -> tuple[np.ndarray, np.ndarray]:
    """Enclosure of ``Q^T S Q`` for ``(N, 3, 3)`` float ``Q`` and interval ``S``.

    Parameters
    ----------
    Q : numpy.ndarray
        ``(N, 3, 3)`` float matrices, taken as exact.
    S : pair of numpy.ndarray
        The interval matrix ``(lo, hi)``, each ``(N, 3, 3)``, as :func:`from_entries` gives it.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``, each ``(N, 3, 3)``: an outward-rounded enclosure of ``Q^T M Q`` for every ``M`` in ``S``.
    """
    lo, hi = S
    T = _point_times(Q[:, None, 0, :], (lo[:, :, 0, None], hi[:, :, 0, None]))   # T = S Q: T[i, l] = sum_j ...
    for j in (1, 2):
        T = arith.add(T, _point_times(Q[:, None, j, :], (lo[:, :, j, None], hi[:, :, j, None])))
    C = _point_times(Q[:, 0, :, None], (T[0][:, 0, None, :], T[1][:, 0, None, :]))  # C = Q^T T: sum_i Q[i, k] T[i, l]
    for i in (1, 2):
        C = arith.add(C, _point_times(Q[:, i, :, None], (T[0][:, i, None, :], T[1][:, i, None, :])))
    return C


def _entry(S, i, j):
    return S[0][:, i, j], S[1][:, i, j]


def positive_definite(S) -> np.ndarray:
    """Whether every symmetric member of the ``(N, 3, 3)`` interval matrix ``S`` is positive definite.

    Sylvester's criterion on enclosures of the three leading minors; an entry
    that is NaN gives False.

    Parameters
    ----------
    S : pair of numpy.ndarray
        The interval matrix ``(lo, hi)``, each ``(N, 3, 3)``, symmetric.

    Returns
    -------
    numpy.ndarray of bool
        ``(N,)``: True where every member is proved positive definite; False means not proved (it may still be).
    """
    a, b, c = _entry(S, 0, 0), _entry(S, 1, 1), _entry(S, 2, 2)
    d, f, g = _entry(S, 0, 1), _entry(S, 0, 2), _entry(S, 1, 2)
    ab = arith.mul(a, b)
    minor2 = arith.sub(ab, arith.sqr(d))
    dfg = arith.mul(arith.mul(d, f), g)
    det = arith.sub(arith.add(arith.mul(ab, c), arith.add(dfg, dfg)),
                    arith.add(arith.add(arith.mul(a, arith.sqr(g)), arith.mul(b, arith.sqr(f))),
                              arith.mul(c, arith.sqr(d))))
    return (a[0] > 0) & (minor2[0] > 0) & (det[0] > 0)
