"""The characteristic polynomial of a matrix and of ``J J^T`` (Cauchy-Binet), numeric eigenvalues from it, and
the singular factors of a Jacobian (:func:`maximal_minor_factors`, the gcd of its maximal minors).

Split out of :mod:`workspace_sym.kinematics` (which keeps thin delegating methods on
:class:`~workspace_sym.kinematics.DHRobot`): this is generic algebra on SymPy matrices,
with no knowledge of DH tables.
"""

from __future__ import annotations

import time
from functools import cmp_to_key
from itertools import combinations

import numpy as np
import sympy as sp
from sympy.polys.polyerrors import ExactQuotientFailed

from .errors import InvalidParameterError
from .expressions import as_matrix, as_sympy
from .symbolic import (
    HalfAngleRing,
    algebraic_constants,
    attempt,
    check_budget,
    factor_half_angle,
    generic_constants,
    opaque_powers,
    remaining_budget,
    restore_constants,
    roots_as_symbols,
    symbolic_budget,
    textbook,
    textbook_polynomial,
    trig_ring_form,
)

__all__ = [
    "characteristic_polynomial",
    "gram_characteristic_polynomial",
    "eigenvalues_from_charpoly",
    "laplace_minor",
    "maximal_minor_factors",
    "EXTENSION_GCD_COLUMNS",
]


def characteristic_polynomial(M, lam: sp.Symbol | None = None, *, gram: bool = False,
                              simplify=textbook) -> sp.Poly:
    """``det(lambda I - M)`` (or of ``M M^T`` when ``gram``) as a polynomial in lambda.

    With ``gram`` the coefficients are sums of squared minors of ``M``
    (:func:`gram_characteristic_polynomial`), which finishes on 6 x 6
    Jacobians where the expanded determinant does not.  Coefficients are
    simplified with ``simplify`` (textbook form by default; pass
    ``sympy.factor`` for rational functions or ``None`` to keep them raw).

    Parameters
    ----------
    M : sympy.Matrix or sequence of rows
        The matrix; entries of a nested sequence are read by :func:`~workspace_sym.expressions.as_sympy` (text
        through the restricted reader).  Square unless ``gram``.
    lam : sympy.Symbol, optional
        The polynomial's variable; None (the default) is ``Symbol("lambda")``.
    gram : bool
        Take the characteristic polynomial of ``M M^T`` (default False: of ``M``).
    simplify : callable or None
        Applied to each coefficient (default :func:`~workspace_sym.symbolic.textbook`); None keeps them raw.

    Returns
    -------
    sympy.Poly
        The monic polynomial in ``lam``, of degree ``M.rows``.

    Raises
    ------
    InvalidParameterError
        When ``M`` is not square and ``gram`` is False.
    ExpressionError
        When an entry of a nested sequence cannot be read.
    SymbolicBudgetError
        With ``gram``, when the enclosing budget runs out (see :func:`gram_characteristic_polynomial`).

    Examples
    --------
    >>> lam = sp.Symbol("lambda")
    >>> characteristic_polynomial(sp.Matrix([[2, 0], [0, 3]]), lam).as_expr()
    lambda**2 - 5*lambda + 6
    """
    if not isinstance(M, sp.MatrixBase):
        M = sp.Matrix([[as_sympy(v, "M") for v in row] for row in M])      # text only through the reader
    if M.rows != M.cols and not gram:
        raise InvalidParameterError(f"M: the characteristic polynomial needs a square matrix; got {M.shape}",
                                    parameter="M")
    lam = lam if lam is not None else sp.Symbol("lambda")
    if gram:
        return gram_characteristic_polynomial(M, lam, simplify=simplify)
    # Matrix.charpoly runs sympy.simplify on every coefficient unless told otherwise:
    # far too slow on trigonometric entries, and not the form we want anyway.
    p = M.charpoly(lam, simplify=lambda e: e)
    if simplify is None:
        return p
    coeffs = [simplify(c) for c in p.all_coeffs()]
    return sp.Poly.from_list(coeffs, lam)


SHORT_SUM_TERMS = 24   # Cauchy-Binet coefficients with at most this many monomials are also tried reduced


def _all_minors(entries, shape, ring) -> dict:
    """Every minor of a matrix of ring elements, keyed by ``(rows, cols)`` (:func:`laplace_minor`, each minor
    built once from those one size smaller)."""
    m, n = shape
    minors: dict = {}
    for k in range(1, min(m, n) + 1):
        for rows in combinations(range(m), k):
            for cols in combinations(range(n), k):
                minors[(rows, cols)] = laplace_minor(entries, rows, cols, minors, ring.zero)
    return minors


def laplace_minor(P: list, rows: tuple, cols: tuple, memo: dict, zero):
    """The minor ``(rows, cols)`` of a matrix of polynomial-ring elements, by Laplace expansion along its first
    row, every smaller minor kept in ``memo`` (shared by the maximal minors: they differ in one column) and the
    budget checked at each.  Products of short entries by minors, no division: Bareiss' exact divisions of
    long polynomials took 50 s of a 7-joint arm's 6 x 6 minors (and DomainMatrix.det, which cannot be
    interrupted, 14 minutes on a float AL5D).

    Parameters
    ----------
    P : list of lists
        The matrix, row by row, its entries elements of one polynomial ring.
    rows, cols : tuple of int
        The rows and columns of the minor, increasing, as many of each.
    memo : dict
        Minors already computed, by ``(rows, cols)``; the minors computed here are added to it.
    zero
        The ring's zero.

    Returns
    -------
    ring element
        The minor.

    Raises
    ------
    SymbolicBudgetError
        When the enclosing :func:`~workspace_sym.symbolic.symbolic_budget` is spent.
    """
    key = (rows, cols)
    if key in memo:
        return memo[key]
    if len(rows) == 1:
        return P[rows[0]][cols[0]]
    check_budget(f"the {len(rows)} x {len(rows)} minors")
    top, rest = rows[0], rows[1:]
    total = zero
    for pos, j in enumerate(cols):
        if P[top][j]:
            sub = laplace_minor(P, rest, cols[:pos] + cols[pos + 1:], memo, zero)
            if sub:
                total = total + P[top][j] * sub if pos % 2 == 0 else total - P[top][j] * sub
    memo[key] = total
    return total


def _factored(p, back: dict, simplify, cache: dict, pool: _FactorPool | None = None) -> sp.Expr:
    """A ring element as its numeric content times its factors, each simplified once: by
    :meth:`_FactorPool.factor` when a ``pool`` is given, else SymPy's ``factor_list`` (irreducible factors)."""
    check_budget("factoring a minor")
    content, factors = pool.factor(p) if pool is not None else p.factor_list()
    atoms = _textbook_atoms(p.ring, back) if simplify is textbook else None
    for f, _ in factors:
        if f not in cache:
            # a ring element's textbook form straight from the ring (as SymPy sums: two minutes of the Panda's)
            cache[f] = textbook_polynomial(f, atoms) if atoms is not None else simplify(f.as_expr().xreplace(back))
    return _product(p.ring.domain.to_sympy(content), [(cache[f], m) for f, m in factors])


def _textbook_atoms(ring, back: dict) -> list | None:
    """What the generators of ``ring`` stand for, when each is a sine or cosine of joint angles or a symbol
    (:func:`~workspace_sym.symbolic.textbook_polynomial` takes them), else None."""
    atoms = [back.get(g, g) for g in ring.symbols]
    fit = all(a.is_Symbol or (isinstance(a, (sp.sin, sp.cos)) and not a.args[0].is_number) for a in atoms)
    return atoms if fit else None


class _FactorPool:
    """The factors of the minors met so far, shortest minors first, and the factoring of the next minor by exact
    division by them.

    A minor of ``J`` is divided by the generators in its monomial content, then by every factor of the pool
    (with its multiplicity); the cofactor left, when not a number, is one new factor and joins the pool (SymPy's
    ``factor_list`` on it, even on those of at most ten terms, was two thirds of the factoring time).  Each division is
    exact (``exquo``), so the product is the minor whatever happens; a division is only tried when the pool
    factor's support and degrees fit in the cofactor's and its values at two random integer points divide the
    cofactor's (``f | q`` implies ``f(a) | q(a)`` for primitive integer polynomials, Gauss' lemma).  The new
    factor is not proven irreducible: on the Panda's 6 x 7 Jacobian every one of the 1,150 minors SymPy factors
    within minutes has at most one irreducible factor not met in a shorter minor, and this gives exactly its
    factorisation, in 2.4 s for all 1,375 distinct minors where ``factor_list`` spends minutes (Wang's algorithm
    in ten generators proving large minors irreducible).
    """

    def __init__(self, ring, seed: int = 0):
        rng = np.random.default_rng(seed)
        self.ring = ring
        self.points = [[int(v) * (1 if rng.random() < 0.5 else -1) for v in rng.integers(2**30, 2**31, ring.ngens)]
                       for _ in range(2)]
        self.factors: list = []   # (f, support, degrees, values at the points)
        self.index: dict = {}

    def _values(self, q) -> list:
        out = []
        for point in self.points:
            total = 0
            for monom, c in q.iterterms():
                v = int(c)
                for a, e in zip(point, monom):
                    if e:
                        v *= a**e
                total += v
            out.append(total)
        return out

    def _add(self, f) -> None:
        if f not in self.index:   # the list first: a budget cut between the two leaves no index without entry
            support = frozenset(i for i in range(self.ring.ngens) if f.degree(i) > 0)
            self.factors.append((f, support, tuple(max(f.degree(i), 0) for i in range(self.ring.ngens)),
                                 self._values(f)))
            self.index[f] = len(self.factors) - 1

    def factor(self, p) -> tuple:
        """``(content, [(f, m), ...])`` with ``p == content * prod(f**m)``, each ``f`` primitive with integer
        coefficients and a positive leading coefficient; the new factors join the pool."""
        R = self.ring
        content, q = p.primitive()
        if q.LC < 0:
            content, q = -content, -q
        found: dict = {}
        low = tuple(min(m[i] for m in q.itermonoms()) for i in range(R.ngens))
        if any(low):
            q = R.from_dict({tuple(a - b for a, b in zip(m, low)): c for m, c in q.iterterms()})
            for i, e in enumerate(low):
                if e:
                    found[R.gens[i]] = e
        if len(q) > 1:
            support = {i for i in range(R.ngens) if q.degree(i) > 0}
            degrees = [max(q.degree(i), 0) for i in range(R.ngens)]
            values = self._values(q)
            for f, f_support, f_degrees, f_values in list(self.factors):
                if len(q) == 1:
                    break
                if len(f) == 1 or len(f) > len(q) or not f_support <= support or \
                        any(a > b for a, b in zip(f_degrees, degrees)):
                    continue
                while all(w and v % w == 0 for v, w in zip(values, f_values)):
                    check_budget("dividing a minor by known factors")
                    try:
                        q = q.exquo(f)
                    except ExactQuotientFailed:
                        break
                    found[f] = found.get(f, 0) + 1
                    values = [v // w for v, w in zip(values, f_values)]
                    degrees = [a - b for a, b in zip(degrees, f_degrees)]
            if len(q) > 1:
                found[q] = found.get(q, 0) + 1
                self._add(q)
            else:
                content *= q.LC
        elif q:
            content *= q.LC
        return content, sorted(found.items(), key=lambda fm: len(fm[0]))


def gram_characteristic_polynomial(J, lam: sp.Symbol | None = None, *, simplify=textbook) -> sp.Poly:
    """``det(lambda I - J J^T)`` with each coefficient a sum of squared minors of ``J`` (Cauchy-Binet).

    The coefficient of ``lambda^(m-k)`` is ``(-1)^k`` times the sum of the
    principal ``k x k`` minors of ``J J^T``, which by the Cauchy-Binet formula
    is the sum of the squares of all ``k x k`` minors of ``J``.  The minors are
    computed exactly (sines, cosines and constants as generators of a
    polynomial ring, each minor built once by Laplace expansion from the
    smaller ones), factored in that ring (shortest first, by exact division by
    the factors of the shorter minors: ``_FactorPool``), each factor brought to
    textbook form by ``simplify`` (straight from the ring,
    :func:`~workspace_sym.symbolic.textbook_polynomial`, for the default), and equal minors (up to sign) are
    counted once: ``c_k = (-1)^k sum_i n_i m_i^2``.  The
    coefficients keep that structure (the polynomial's domain is ``EX``);
    ``sympy.expand`` gives the monomial form.

    Each step has its share of the enclosing :func:`~workspace_sym.symbolic.symbolic_budget`
    (120 s without one): the exact minors :data:`MINORS_SHARE` of it, their factoring and
    textbook forms, shortest first, until :data:`FACTOR_SHARE` of what is left is spent (a
    minor not factored by then stays the determinant of its submatrix).  When the exact minors
    themselves do not finish in their share, the coefficients are returned unexpanded,
    ``c_k = (-1)^k sum det(J_(S,T))^2`` over the ``k x k`` submatrices of ``J`` as
    :class:`sympy.Determinant` objects: still exact
    (``.doit()`` expands them; :func:`eigenvalues_from_charpoly` evaluates them), only not
    multiplied out.

    ``J`` may be rotated first by any orthogonal matrix: ``(Q J)(Q J)^T`` has
    the same characteristic polynomial, which :meth:`DHRobot.characteristic_polynomial`
    uses to shorten the entries.

    Parameters
    ----------
    J : sympy.Matrix
        The ``m x n`` matrix (a Jacobian).  Not text: anything else is passed to ``sympy.Matrix``.
    lam : sympy.Symbol, optional
        The polynomial's variable; None (the default) is ``Symbol("lambda")``.
    simplify : callable or None
        Applied to each irreducible factor of a minor, and to short coefficients (default
        :func:`~workspace_sym.symbolic.textbook`); None keeps them raw.

    Returns
    -------
    sympy.Poly
        The monic polynomial of degree ``m`` in ``lam``, over the domain ``EX``.

    Raises
    ------
    SymbolicBudgetError
        When the enclosing budget (or the 120 s of its own) runs out before the coefficients are built.

    Examples
    --------
    >>> t, a = sp.symbols("t a")
    >>> gram_characteristic_polynomial(sp.Matrix([[a * sp.cos(t), a * sp.sin(t), 1]]), sp.Symbol("x"))
    Poly(x - a**2 - 1, x, domain='EX')
    """
    J = as_matrix(J, "J")
    lam = lam if lam is not None else sp.Symbol("lambda")
    with symbolic_budget(None, f"the characteristic polynomial of J J^T ({J.rows} x {J.cols})"):
        done, ring_minors = attempt(lambda: _ring_minors(J), MINORS_SHARE * (remaining_budget() or 0.0),
                                    "the exact minors")
        if not done:
            coeffs = _determinant_sums(J)
        else:
            minors, back = ring_minors
            coeffs = _squared_minor_sums(J, minors, back, simplify or (lambda e: e),
                                         time.monotonic() + FACTOR_SHARE * (remaining_budget() or 0.0))
    return sp.Poly.from_list(coeffs, lam, domain="EX")


MINORS_SHARE = 0.5    # of the budget left: the exact minors in the polynomial ring (else the Determinant sums)
FACTOR_SHARE = 0.35   # of the budget left after them: factoring the minors and their textbook forms (a 7-joint
                      # arm's 6 x 7 then ends in 60 s under the default budget, the 6-joint ones all factored)
RING_TOTAL_PRODUCTS = 20_000   # a coefficient is also tried multiplied out when its squares cost at most this


def _ring_minors(J: sp.Matrix) -> tuple:
    """Every minor of ``J`` as an element of a polynomial ring over QQ whose generators are the sines, cosines and
    constants of the entries; returns the minors (:func:`_all_minors`) and the substitution back to SymPy."""
    (entries, opaque), atoms = opaque_powers([as_sympy(e) for e in J]), set()
    for e in entries:
        atoms |= e.atoms(sp.sin, sp.cos) | set(algebraic_constants([e]))
    # Sines and cosines become generators before the constants become symbols: the other way round,
    # cos(theta2 + pi/6) turned into cos(theta2 + _k0/6) and that placeholder reached the output.
    forward = {a: sp.Dummy() for a in sorted(atoms, key=sp.default_sort_key)}
    entries, back = generic_constants([e.xreplace(forward) for e in entries])
    back.update({v: k for k, v in forward.items()})
    back.update(opaque)
    gens = sorted(set().union(*(e.free_symbols for e in entries)) or {sp.Dummy()}, key=sp.default_sort_key)
    R, *_ = sp.ring(gens, sp.QQ)
    rows = []
    for i in range(J.rows):
        check_budget("the entries as polynomials")
        rows.append([R.from_expr(entries[i * J.cols + j]) for j in range(J.cols)])
    return _all_minors(rows, J.shape, R), back


def _squared_minor_sums(J: sp.Matrix, minors: dict, back: dict, simplify, factor_until: float) -> list:
    """``[1, -c_1, c_2, ...]``: ``c_k`` the sum of the squared ``k x k`` minors, equal minors (up to sign) counted
    once, each factored and simplified, shortest first, while ``factor_until`` (a ``time.monotonic()``) is ahead;
    those left then are kept as the determinants of their submatrices (a 1 x 1 one as the entry).  (Slicing the
    time among the minors instead wasted it: a factorisation cut short gives nothing.)"""
    m = J.rows
    by_size: list = [{} for _ in range(m + 1)]   # minors up to sign, with how often they occur
    where: dict = {}                              # one submatrix of each
    for (r, c), minor in minors.items():
        if minor:
            minor = -minor if minor.LC < 0 else minor
            by_size[len(r)][minor] = by_size[len(r)].get(minor, 0) + 1
            where.setdefault(minor, (r, c))
    forms: dict = {}
    cache: dict = {}                # factors already simplified (_factored)
    pool = _FactorPool(next(iter(where)).ring) if where else None
    for minor in sorted(where, key=len):
        left = factor_until - time.monotonic()
        done, form = (attempt(lambda p=minor: _factored(p, back, simplify, cache, pool), left, "factoring a minor")
                      if left > 0 else (False, None))
        if not done:   # exact all the same, and as short as J
            check_budget("the determinants")
            form = _determinant(J, *where[minor])
        forms[minor] = form
    coeffs = [sp.Integer(1)]
    for k in range(1, m + 1):
        distinct = by_size[k]
        # Each form is that of a minor whose sign is already fixed (positive leading coefficient), so equal
        # minors were counted in the ring; nothing here walks the long forms again (could_extract_minus_sign and
        # count_ops on them cost seconds past the factoring deadline).
        sign = (-1) ** k
        total = _sum([_product(sign * n, [(forms[minor], 2)]) for minor, n in distinct.items()])
        if distinct and sum(len(p) ** 2 for p in distinct) <= RING_TOTAL_PRODUCTS:
            ring_total = sum((n * minor**2 for minor, n in distinct.items()), next(iter(distinct)).ring.zero)
            if len(ring_total) <= SHORT_SUM_TERMS:   # a^2 c^2 + a^2 s^2 + 1 is a^2 + 1
                reduced = sign * simplify(ring_total.as_expr().xreplace(back))
                total = reduced if sp.count_ops(reduced) < sp.count_ops(total) else total
        coeffs.append(total)
    return coeffs


_ORDER = cmp_to_key(sp.Basic.compare)   # the order of the arguments of SymPy's sums and products


def _plain(base: sp.Expr) -> bool:
    """Whether SymPy leaves every positive integer power of ``base`` as the plain ``Pow``: a symbol, a sine or
    cosine of a symbolic argument, or a sum of symbolic terms holding no infinity (:func:`_power`)."""
    if base.is_Symbol:
        return True
    if isinstance(base, (sp.sin, sp.cos)):
        return not base.args[0].is_number
    return bool(base.is_Add and base.free_symbols and not base.has(*_INFINITIES))


def _product(coeff, powers: list) -> sp.Expr:
    """``coeff * prod(f**m for f, m in powers)``, the object SymPy's ``Mul`` builds.

    SymPy's product takes every power apart and builds it again, asking of each sum of two terms whether one of
    them is infinite: a walk of the assumptions of its long terms (a third of the Panda's 6 x 7 polynomial).  When
    each ``f`` is a plain base (:func:`_plain`) or a product of plain bases and a rational, all bases distinct,
    ``coeff`` rational and each ``m`` a positive integer, the product is the sorted powers behind the coefficient,
    built here without the question; anything else goes to SymPy."""
    given = coeff = sp.sympify(coeff)
    pieces: dict = {}
    for f, m in powers:
        c, rest = f.as_coeff_Mul() if f.is_Mul else (sp.S.One, f)
        if not (int(m) == m and m > 0 and c.is_Rational and coeff.is_Rational):
            return _sympy_product(given, powers)
        coeff *= c ** m
        for b, e in (a.as_base_exp() for a in sp.Mul.make_args(rest)):
            if not (e.is_Integer and e > 0 and _plain(b)) or b in pieces:
                return _sympy_product(given, powers)
            pieces[b] = e * m
    if coeff.is_zero:
        return _sympy_product(given, powers)
    args = sorted((b if e == 1 else sp.Pow(b, e, evaluate=False) for b, e in pieces.items()), key=_ORDER)
    if coeff is not sp.S.One:
        if len(args) == 1 and args[0].is_Add:   # SymPy distributes a number over a sum: 2 (a + b) = 2 a + 2 b
            return _sympy_product(given, powers)
        args.insert(0, coeff)
    return args[0] if len(args) == 1 else sp.Mul(*args, evaluate=False) if args else coeff


def _sympy_product(coeff, powers: list) -> sp.Expr:
    """SymPy's own ``coeff * prod(f**m)`` (:func:`_product` when its shortcut does not apply)."""
    return sp.Mul(coeff, *(_power(f, m) for f, m in powers))


def _sum(terms: list) -> sp.Expr:
    """``Add(*terms)``, the object SymPy builds.  SymPy collects the terms by what multiplies their rational
    coefficient and multiplies each sum of coefficients back in, which for a number times one power is a whole
    product again (:func:`_product`).  When every such rest is a product, a plain base or a positive integer power
    of one, and no term is a number or a sum, the collected terms are put back here without that, in SymPy's
    order."""
    collected: dict = {}
    for t in terms:
        c, rest = t.as_coeff_Mul()
        if t.is_Number or t.is_Add or not c.is_Rational or not (rest.is_Mul or _plain_power(rest)):
            return sp.Add(*terms)
        collected[rest] = collected.get(rest, 0) + c
    out = [rest if c == 1 else sp.Mul(c, *sp.Mul.make_args(rest), evaluate=False)
           for rest, c in collected.items() if c != 0]
    return sp.Add(*sorted(out, key=_ORDER), evaluate=False) if len(out) > 1 else sp.Add(*out)


def _plain_power(f: sp.Expr) -> bool:
    """A plain base (:func:`_plain`) or a positive integer power of one."""
    base, e = f.as_base_exp()
    return bool(e.is_Integer and e > 0 and _plain(base))


_INFINITIES = (sp.S.Infinity, sp.S.NegativeInfinity, sp.S.ComplexInfinity)


def _power(base: sp.Expr, exp) -> sp.Expr:
    """``base**exp``, the same object SymPy builds.  For a sum of symbolic terms SymPy's evaluation ends in the
    plain ``Pow(base, exp)`` after asking whether a sum of two terms holds an infinite one, which walks the
    assumptions of each long term (seconds on the Panda's minors); here that sum is built without the question
    when a walk of its tree (no assumptions) shows no infinity.  A number or an infinity goes to SymPy."""
    if base.is_Add and _plain(base):
        return sp.Pow(base, exp, evaluate=False)
    return base**exp


def _determinant(J: sp.Matrix, rows, cols) -> sp.Expr:
    """The unexpanded determinant of a submatrix of ``J`` (a 1 x 1 one is its entry)."""
    if len(rows) == 1:
        return J[rows[0], cols[0]]
    return sp.Determinant(sp.ImmutableMatrix(J.extract(list(rows), list(cols))))


def _determinant_sums(J: sp.Matrix) -> list:
    """``[1, -c_1, c_2, ...]`` with ``c_k`` the sum of ``Determinant(J_(S,T))**2`` over the ``k x k``
    submatrices without a zero row or column (``c_1`` the sum of the squared entries): exact, not multiplied out."""
    coeffs = [sp.Integer(1)]
    for k in range(1, J.rows + 1):
        terms = []
        for rows in combinations(range(J.rows), k):
            for cols in combinations(range(J.cols), k):
                check_budget(f"the {k} x {k} submatrices")
                sub = J.extract(list(rows), list(cols))
                if any(all(e == 0 for e in sub.row(i)) for i in range(k)) or \
                        any(all(e == 0 for e in sub.col(j)) for j in range(k)):
                    continue
                terms.append(_determinant(J, rows, cols) ** 2)
        coeffs.append((-1) ** k * sp.Add(*terms))
    return coeffs


def eigenvalues_from_charpoly(poly: sp.Poly, values: dict | None = None) -> np.ndarray:
    """Numeric eigenvalues: roots of the characteristic polynomial at ``values``.

    Parameters
    ----------
    poly : sympy.Poly
        A characteristic polynomial, such as :func:`gram_characteristic_polynomial` returns (its unexpanded
        determinants are evaluated).
    values : dict, optional
        Values of the symbols of the coefficients (joint variables and lengths), by symbol; None (the default)
        when the coefficients are numbers already.

    Returns
    -------
    numpy.ndarray
        The roots: real and in increasing order when every imaginary part is below 1e-9 relative to the largest
        root (as for the symmetric ``J J^T``), else complex, ordered by real part.

    Raises
    ------
    TypeError
        When a coefficient keeps a symbol that ``values`` does not give.
    """
    values = values or {}
    coeffs = [complex(_evaluated(sp.sympify(c).xreplace(values))) for c in poly.all_coeffs()]
    roots = np.roots(coeffs)
    scale = max(1.0, float(np.max(np.abs(roots)))) if roots.size else 1.0
    if np.all(np.abs(roots.imag) <= 1e-9 * scale):
        return np.sort(roots.real)
    return roots[np.argsort(roots.real)]

def _evaluated(c: sp.Expr):
    """A coefficient's value at a point; unexpanded determinants (:func:`_determinant_sums`) are computed."""
    # sines, cosines and constants at a point as floats first: evalf's adaptive precision on a long exact sum
    # with cos(97*pi/180) in it took 14 s a point
    c = c.xreplace({a: sp.Float(sp.N(a, 20)) for a in c.atoms(sp.Function, sp.NumberSymbol) if a.is_number})
    if not c.has(sp.Determinant):
        return c.evalf()
    # the entries first (a float matrix's determinant is quick; an exact one with cos(97*pi/180) is not)
    return c.xreplace({d: sp.Determinant(sp.ImmutableMatrix(d.arg.evalf())).doit() for d in c.atoms(sp.Determinant)}
                      ).evalf()


EXTENSION_GCD_COLUMNS = 2   # wider Jacobians with square roots take their minors' gcd with the roots as symbols


def maximal_minor_factors(J: sp.Matrix, *, seed: int = 0, multiplicity: bool = False) -> list:
    """Factors common to every maximal non-vanishing minor of ``J``.

    The generic rank ``r`` is found numerically at a random point (joint
    variables and symbolic constants drawn at random); identically zero and
    repeated columns are dropped first (they change no rank).  The minors are
    computed exactly as polynomials in the sines and cosines of the joint
    angles (fraction-free elimination over a polynomial ring), so a square
    full-rank ``J`` gives the factorisation of ``det J``.  An empty list means
    that the rank never drops on a hypersurface of the joint space (a redundant
    chain, for instance).

    Coefficients: square roots from constant angles (``alpha = pi/4``) are
    adjoined to the rationals; floats and ``pi`` are replaced by symbols for
    the computation and put back in the factors (see
    :func:`~workspace_sym.symbolic.generic_constants`), so a float table gives
    ``0.425*c2 + 0.39225*c23``, not 30-digit integers.  With more than
    :data:`EXTENSION_GCD_COLUMNS` columns the square roots too are symbols
    during the gcd (over the algebraic field it can run for many minutes):
    every factor found still divides every minor, but a factor that appears
    only through ``sqrt(2)**2 = 2`` may be missed.

    With ``multiplicity`` the result is a list of ``(factor, m)``: ``m`` is the
    exponent of the factor in the gcd of the minors (in ``det J`` for a square
    ``J``), e.g. ``[(s2, 1), (s5, 1), (q3, 2)]`` for the Stanford arm.

    Parameters
    ----------
    J : sympy.Matrix
        The Jacobian.  Not text: anything else is passed to ``sympy.Matrix``.
    seed : int
        Seed of the random point at which the generic rank is found (default 0).
    multiplicity : bool
        Return ``(factor, m)`` pairs (default False: the factors alone).

    Returns
    -------
    list
        The factors (SymPy expressions), shortest first, or ``(factor, m)`` pairs; ``[0]`` (``[(0, 1)]``) when
        ``J`` is zero at the random point (its generic rank is 0); ``[]`` when no factor is common to the minors.

    Raises
    ------
    SymbolicBudgetError
        When the enclosing :func:`~workspace_sym.symbolic.symbolic_budget` is spent.

    Examples
    --------
    >>> t = sp.Symbol("t")
    >>> maximal_minor_factors(sp.Matrix([[sp.sqrt(2) * sp.sin(t), 0], [0, 1]]))
    [sin(t)]
    >>> maximal_minor_factors(sp.Matrix([[0, 1], [1, 0]]))
    []
    """
    J = as_matrix(J, "J")
    rng = np.random.default_rng(seed)
    point = {s: sp.Float(rng.uniform(0.3, 1.7)) for s in J.free_symbols}
    cols, seen = [], set()
    for k in range(J.cols):
        col = tuple(J[:, k])
        if all(e == 0 for e in col) or col in seen:
            continue
        seen.add(col)
        cols.append(k)
    rows = [i for i in range(J.rows) if any(J[i, k] != 0 for k in cols)]
    if not rows:
        return [(sp.Integer(0), 1)] if multiplicity else [sp.Integer(0)]
    J = J.extract(rows, cols)
    values = J.xreplace(point).evalf()
    # Each column scaled by its largest entry (SymPy floats have no overflow): a length (l1 + 1)**1000 is
    # 1e431 at the sample point, an infinity in numpy that made the rank 0 (every configuration singular).
    scales = [max((abs(v) for v in values[:, k]), default=1) or 1 for k in range(values.cols)]
    numeric = np.array([[values[i, k] / scales[k] for k in range(values.cols)] for i in range(values.rows)],
                       dtype=float).reshape(values.shape)
    r = int(np.linalg.matrix_rank(numeric))
    if r == 0:
        return [(sp.Integer(0), 1)] if multiplicity else [sp.Integer(0)]
    entries, pairs, angles = trig_ring_form(list(J))
    entries, back = generic_constants(entries)
    back.update(angles)
    extension = algebraic_constants(entries)
    if extension and J.cols > EXTENSION_GCD_COLUMNS:
        # gcds over QQ(sqrt 2, sqrt 3) in many variables run for many minutes (subresultants of
        # algebraic-number coefficients): the roots become symbols and the gcd is taken over QQ.
        entries, roots = roots_as_symbols(entries, extension)
        back.update(roots)
        extension = ()
    ring = HalfAngleRing(pairs, set().union(*(e.free_symbols for e in entries)), extension=extension)
    # Sparse, short rows first: Laplace expansion multiplies the first row's entries by the largest minors
    # (a permutation of rows changes a minor's sign only).
    order = sorted(range(J.rows), key=lambda i: (sum(J[i, j] != 0 for j in range(J.cols)),
                                                 sum(sp.count_ops(J[i, j]) for j in range(J.cols))))
    P = [[ring.element(entries[i * J.cols + j]) for j in range(J.cols)] for i in order]
    numeric = numeric[order, :]
    memo: dict = {}
    common = None
    for rr in combinations(range(J.rows), r):
        for cc in combinations(range(J.cols), r):
            if abs(np.linalg.det(numeric[np.ix_(rr, cc)])) < 1e-9:
                continue  # vanishes at a generic point: identically zero, no information
            det = ring.convert(laplace_minor(P, rr, cc, memo, ring.domain.zero))
            check_budget("the maximal minors' gcd")
            common = det if common is None else common.gcd(det)
            if common.is_ground:
                return []
    if common is None:  # every minor tiny at the sample point: no factor can be certified
        return []
    factors = factor_half_angle(ring.to_expr(common), ring.half, extension=extension, multiplicity=True)
    factors = [(f, m) for f, m in restore_constants(factors, back) if f != 0]
    return factors if multiplicity else [f for f, _ in factors]
