"""Closed forms of a planar chain's boundary: every arc and the area as SymPy expressions.

Step 2 (:mod:`workspace_sym.planar.boundary`) decides the topology in floats; this
module rebuilds each arc from the chain's exact inputs (lengths, limits, the
alignment angles of Step 0) and matches every loop vertex to a closed form:
an end of the arc's own range, or an intersection of two circles (Bastien
2018, Table 2: the -55.1005 deg is such an intersection).  Rooms:
chain -> boundary -> arrangement, exact; this module reads a boundary and its
chain by their attributes and imports no other room.
"""

from __future__ import annotations

import math

import mpmath
import sympy as sp

from ..symbolic import attempt

__all__ = ["closed_forms", "exact_arcs", "exact_area", "area_terms", "shortest_form", "short_atan2", "short_sqrt",
           "polar_angle", "norm2", "link_direction", "is_zero"]


def link_direction(angle):
    """``u(angle) = (-sin angle, cos angle)``: the direction of a link at absolute angle ``angle`` from the +y axis,
    as a SymPy column (the end point of a chain is ``sum_k l_k u(phi_k)``, docs/methods.md section 4).

    Parameters
    ----------
    angle : sympy.Expr or number
        The absolute angle of the link (radians).

    Returns
    -------
    sympy.Matrix
        The 2 x 1 column ``(-sin angle, cos angle)``.

    Examples
    --------
    >>> link_direction(sp.pi / 2).T
    Matrix([[-1, 0]])
    """
    return sp.Matrix([-sp.sin(angle), sp.cos(angle)])


# ---------------------------------------------------------------------- short forms
# A point of a planar chain is a sum of terms L u(a) with u(a) = (-sin a, cos a).  Its polar angle and squared
# norm are written from those terms directly, so that no atan(cos x / sin x) or sin(x)**2 + cos(x)**2 appears.
def _integer_form(*exprs):
    """``(k, [k * e for e in exprs])`` with ``k > 0`` rational such that every coefficient becomes a coprime
    integer (clears denominators and common factors: atan2 and ratios do not change)."""
    coeffs = [sp.Rational(t.as_coeff_Mul()[0]) for e in exprs for t in sp.Add.make_args(sp.expand(e)) if e != 0]
    if not coeffs:
        return sp.Integer(1), list(exprs)
    den = sp.ilcm(*[c.q for c in coeffs]) if len(coeffs) > 1 else coeffs[0].q
    num = sp.igcd(*[abs(c.p) * (den // c.q) for c in coeffs]) if len(coeffs) > 1 else abs(coeffs[0].p)
    k = sp.Rational(den, num)
    return k, [sp.expand(k * e) for e in exprs]


def short_atan2(y, x):
    """``atan2(y, x)`` as one short term: a known angle when SymPy evaluates it exactly, otherwise
    ``atan2`` (not ``atan`` of a quotient plus a multiple of pi) of integer-coefficient arguments, with the sign
    of ``y`` pulled out.

    Parameters
    ----------
    y, x : sympy.Expr
        The coordinates, exact expressions.

    Returns
    -------
    sympy.Expr
        An expression equal to ``atan2(y, x)``.

    Examples
    --------
    >>> short_atan2(sp.Rational(27, 250) * sp.sin(sp.pi / 18), sp.Rational(83, 250) + sp.Rational(27, 250)
    ...             * sp.cos(sp.pi / 18))
    atan2(27*sin(pi/18), 27*cos(pi/18) + 83)
    >>> short_atan2(sp.cos(7 * sp.pi / 18), sp.sin(7 * sp.pi / 18))
    pi/9
    """
    y, x = sp.expand(y), sp.expand(x)
    known = sp.atan2(y, x)
    if not known.has(sp.atan, sp.atan2, sp.acos, sp.asin):
        return known
    # cos(a)/sin(a) style quotients of one angle: the polar angle of (cos a, sin a) scaled
    ratio = sp.simplify(y / x) if len(sp.Add.make_args(y)) == len(sp.Add.make_args(x)) == 1 else None
    if ratio is not None:
        tan = sp.atan(ratio)
        if not tan.has(sp.atan):
            # atan gives (-pi/2, pi/2); the quadrant comes from the float signs
            return _fit_quadrant(tan, _value(sp.atan2(y, x)))
    if y.could_extract_minus_sign():
        return -short_atan2(-y, x)
    _, (y, x) = _integer_form(y, x)
    return sp.atan2(y, x, evaluate=False)


def _fit_quadrant(angle, value: float):
    n = round((value - _value(angle)) / math.pi)
    return angle + n * sp.pi


def _combine(terms):
    """Terms ``(L, a)`` with equal angles added, zero coefficients dropped."""
    out = {}
    for L, a in terms:
        key = sp.expand(a)
        out[key] = out.get(key, 0) + L
    return [(sp.expand(L), a) for a, L in out.items() if sp.expand(L) != 0]


def polar_angle(terms):
    """Polar angle of ``sum L u(a)`` over ``terms`` (pairs ``(L, a)``), as ``a_ref + pi/2 + atan2(...)`` with
    the arguments measured from the term of largest coefficient.  ``None`` for the zero vector.

    Parameters
    ----------
    terms : iterable of tuple
        Pairs ``(L, a)`` of SymPy expressions: a length and an absolute angle (radians); terms of equal angles
        are added first.

    Returns
    -------
    sympy.Expr or None
        The polar angle (radians, not reduced to a turn), or None when the terms cancel.
    """
    terms = _combine(terms)
    if not terms:
        return None
    L_ref, ref = max(terms, key=lambda t: abs(float(t[0])))
    if float(L_ref) < 0:
        ref = ref + sp.pi
    y = sum(L * sp.sin(a - ref) for L, a in terms)
    x = sum(L * sp.cos(a - ref) for L, a in terms)
    return ref + sp.pi / 2 + short_atan2(y, x)


def norm2(terms):
    """``|sum L u(a)|^2`` as ``sum L^2 + 2 sum L L' cos(a - a')`` (never a sin^2 + cos^2).

    Parameters
    ----------
    terms : iterable of tuple
        Pairs ``(L, a)`` of SymPy expressions: a length and an absolute angle (radians).

    Returns
    -------
    sympy.Expr
        The squared norm, expanded.
    """
    terms = _combine(terms)
    return sp.expand(sum(L ** 2 for L, _ in terms)
                     + sum(2 * L1 * L2 * sp.cos(a2 - a1) for (L1, a1), (L2, a2) in zip_pairs(terms)))


def short_sqrt(value):
    """``sqrt(value)`` written ``sqrt(N)/D`` with integer coefficients in ``N`` and ``D`` an integer.

    Parameters
    ----------
    value : sympy.Expr
        A non-negative exact expression.

    Returns
    -------
    sympy.Expr
        An expression equal to ``sqrt(value)``; a rational or a single term gives SymPy's own ``sqrt``.

    Examples
    --------
    >>> short_sqrt(sp.Rational(8447, 125000) - sp.Rational(6789, 125000) * sp.cos(5 * sp.pi / 18))
    sqrt(16894 - 13578*cos(5*pi/18))/500
    """
    value = sp.expand(value)
    if value.is_Rational or len(sp.Add.make_args(value)) == 1:
        return sp.sqrt(value)
    k, (n,) = _integer_form(value)          # value = n / k, n with coprime integer coefficients
    num, den = k.q, k.p                       # value = n * num / den
    # sqrt(n num / den) = sqrt(n num f) / sqrt(den f), f the square-free part of den: an integer denominator
    f = sp.Mul(*[b ** (e % 2) for b, e in sp.factorint(den).items()])
    return sp.sqrt(sp.expand(n * num * f)) / sp.sqrt(den * f)


_MP = {sp.sin: mpmath.sin, sp.cos: mpmath.cos, sp.tan: mpmath.tan, sp.atan: mpmath.atan, sp.acos: mpmath.acos,
       sp.asin: mpmath.asin, sp.atan2: mpmath.atan2}


def _mp(expr):
    """``expr`` in mpmath at the working precision, walking the tree once."""
    if expr.is_Rational:
        return mpmath.mpf(expr.p) / expr.q
    if expr.is_Float:
        return mpmath.mpf(expr)
    if expr is sp.pi:
        return +mpmath.pi
    args = [_mp(a) for a in expr.args]
    if expr.is_Add:
        return mpmath.fsum(args)
    if expr.is_Mul:
        return mpmath.fprod(args)
    if expr.is_Pow:
        return mpmath.power(*args)
    return _MP[expr.func](*args)


def _value(expr) -> float:
    """``expr`` at 50 digits (fixed precision: SymPy's adaptive evalf can loop for long on expressions that
    cancel exactly, such as an acos of exactly 1); a rounding-sized imaginary part (acos just past 1) is dropped."""
    with mpmath.workdps(50):
        return float(mpmath.re(_mp(sp.sympify(expr))))


def _fit(expr, value: float, period, tol: float = 1e-9):
    """``expr + n * period`` equal to ``value`` within ``tol`` for some integer n, or None."""
    v = _value(expr)
    per = float(period)
    n = round((value - v) / per)
    if abs(value - v - n * per) <= tol * max(1.0, abs(value)):
        return expr + n * period
    return None


def _segment_terms(L, theta, start, end, phi=0):
    """Terms ``(l_s, phi_s)`` of segments ``start..end-1``, ``phi_s`` the sum of ``phi`` and ``theta[start..s]``."""
    terms = []
    for s_ in range(start, end):
        phi = phi + theta[s_]
        terms.append((L[s_], phi))
    return terms


def _exact_source(chain, arc) -> dict:
    """The exact configuration, centre, radius and start angle of a Step 1 arc."""
    p, i = chain.p, arc.free_joint - 1
    L, lo, hi = chain.exact_lengths, chain.exact_lower, chain.exact_upper
    theta, aligned = [None] * p, []
    for j in range(p):
        if j == i:
            continue
        v = arc.theta_sets[j][0]
        if abs(v - chain.lower[j]) <= 1e-12:
            theta[j] = lo[j]
        elif abs(v - chain.upper[j]) <= 1e-12:
            theta[j] = hi[j]
        else:
            aligned.append(j)
    J = [i] + aligned
    bodies = []
    for k, start in enumerate(J):
        end = J[k + 1] if k + 1 < len(J) else p
        # the rigid body from joint `start` to the next aligned joint, in the frame of segment `start`
        terms = _segment_terms(L, [sp.Integer(0)] + theta[start + 1:end], 0, end - start)
        terms = [(L[start + s_], a) for s_, (_, a) in enumerate(terms)]
        bodies.append((polar_angle(terms) - sp.pi / 2, short_sqrt(norm2(terms)), terms[-1][1]))
    signed, orient = bodies[0][1], 1
    for k in range(1, len(J)):
        gamma_prev, _, turn_prev = bodies[k - 1]
        e = gamma_prev - turn_prev - bodies[k][0]
        t = arc.theta_sets[J[k]][0]
        n = round((t - _value(e)) / math.pi)
        theta[J[k]] = e + n * sp.pi
        orient = -orient if n % 2 else orient
        signed = signed + orient * bodies[k][1]
    positive = _value(signed) > 0
    radius = signed if positive else -signed
    centre_terms = _segment_terms(L, theta, 0, i)
    centre = sum((l_ * link_direction(a) for l_, a in centre_terms), sp.Matrix([0, 0]))
    a0_float = arc.start_angle - (arc.theta_sets[i][0] - chain.lower[i])
    at_lo = list(theta)
    at_lo[i] = lo[i]
    a0 = _fit(polar_angle(_segment_terms(L, at_lo, i, p, centre_terms[-1][1] if i else 0)), a0_float,
              2 * sp.pi, 1e-7)
    return {"theta": theta, "i": i, "center": (centre[0], centre[1]), "radius": radius, "a0": a0,
            "a0_float": a0_float, "lo": lo[i], "hi": hi[i], "span": hi[i] - lo[i], "centre_terms": centre_terms}


def zip_pairs(items):
    """All pairs (a, b) with a before b."""
    for k, a in enumerate(items):
        for b in items[k + 1:]:
            yield a, b


def _intersection_angles(src, other):
    """Polar angles about the centre of ``src`` of the points where its circle meets that of ``other``."""
    between = [(l_, a) for l_, a in other["centre_terms"]] + [(-l_, a) for l_, a in src["centre_terms"]]
    d2 = norm2(between)
    if _value(d2) <= 1e-24:
        return []
    beta = polar_angle(between)
    r1, r2 = src["radius"], other["radius"]
    gamma = sp.acos((r1 ** 2 + d2 - r2 ** 2) / (2 * r1 * short_sqrt(d2)))
    return [beta + gamma, beta - gamma]


def _vertex_angle(src, angle, neighbours, sources_all):
    """Closed form of the polar angle ``angle`` (float) of a loop vertex on the circle of ``src``."""
    own = [src["a0"], src["a0"] + src["span"]]
    for e in own:
        fitted = _fit(e, angle, 2 * sp.pi)
        if fitted is not None:
            return fitted
    for other in neighbours + sources_all:
        same = (abs(_value(other["radius"] - src["radius"])) < 1e-12 and
                all(abs(_value(other["center"][k] - src["center"][k])) < 1e-12 for k in (0, 1)))
        cands = [other["a0"], other["a0"] + other["span"]] if same else _intersection_angles(src, other)
        for e in cands:
            fitted = _fit(e, angle, 2 * sp.pi)
            if fitted is not None:
                return fitted
    # no closed form matched (e.g. a Step 1 cut where u is parallel to P_i - P_j): keep the float,
    # which exact_arcs reports through its "exact" flag
    return sp.Float(angle, 17)


def is_zero(expr, *, max_degree: int = 48) -> bool:
    """``expr == 0`` proved: zero after expansion, or its minimal polynomial is x.  False when not proved,
    including when the number field is too large for minimal_polynomial to finish quickly (cos(pi/180) has degree
    48 and one with a few of them can run for minutes): callers then keep the form they had.

    Parameters
    ----------
    expr : sympy.Expr
        An exact expression.
    max_degree : int, default 48
        The largest bound on the degree of the number field (sines and cosines of rational multiples of pi,
        square roots) for which the minimal polynomial is tried.

    Returns
    -------
    bool
        True when ``expr`` is proved zero; False when it is not, or not proved (its value exceeds 1e-30, it
        holds another kind of term, or the field is too large).

    Examples
    --------
    >>> is_zero(sp.cos(sp.pi / 12) - (sp.sqrt(6) + sp.sqrt(2)) / 4), is_zero(sp.cos(sp.pi / 12) - sp.Rational(1, 2))
    (True, False)
    """
    expr = sp.expand(expr)
    if expr == 0:
        return True
    if abs(_value(expr)) > 1e-30:
        return False
    # degree bound: every sin/cos(k pi/N) lies in Q(exp(i pi/N)), of degree phi(2N); each square root doubles it
    denominators = [sp.Rational(a.args[0] / sp.pi).q if (a.args[0] / sp.pi).is_Rational else None
                    for a in expr.atoms(sp.sin, sp.cos)]
    if None in denominators:
        return False
    roots = [a for a in expr.atoms(sp.Pow) if not a.exp.is_Integer]
    degree = sp.totient(2 * sp.ilcm(1, *denominators)) * 2 ** len(roots)
    if degree > max_degree:
        return False
    x = sp.Dummy("x")
    try:
        return sp.minimal_polynomial(expr, x) == x
    except (NotImplementedError, ValueError, sp.polys.polyerrors.PolynomialError):
        return False


def _is_plain(angle) -> bool:
    """An angle with no inverse trigonometric function and no float: a limit, an alignment of rational pi."""
    return not angle.has(sp.atan, sp.atan2, sp.acos, sp.asin, sp.Float)


def _free_value_at(chain, src, config):
    """The free joint value of ``src`` at which the chain reaches the end point of ``config``, written as
    the difference of two polar angles about the arc's centre, or None when that point is not proved to lie on
    the arc's circle (or is its centre)."""
    L, i, p = chain.exact_lengths, src["i"], chain.p
    rel = _segment_terms(L, config, 0, p) + [(-l_, a) for l_, a in src["centre_terms"]]
    if not is_zero(norm2(rel) - sp.expand(src["radius"] ** 2)):
        return None
    at_zero = list(src["theta"])
    at_zero[i] = sp.Integer(0)
    reach, body = polar_angle(rel), polar_angle(_segment_terms(L, at_zero, i, p, src["centre_terms"][-1][1]
                                                                 if i else 0))
    if reach is None or body is None:
        return None
    return sp.expand(reach - body)


def _shorter_vertices(chain, loops, arcs, sources, values):
    """Rewrite each free joint value at a loop vertex in a shorter form proved equal.

    ``values[k] = [t_start, t_end]`` of boundary arc ``k`` (radians).  At a vertex shared by arcs A and B,
    when B's value is plain (a joint limit, a rational multiple of pi) the vertex is B's configuration, and A's
    value is the angle that turns A's configuration onto that point: for Table 2's -55.1005 deg this gives
    -60 deg + 2 atan2(l3 sin 10 deg, l1 + l2 + l3 cos 10 deg).  The new form replaces the old one only when it
    is shorter and equal to it to 30 digits modulo 2 pi, the point being proved on A's circle
    (:func:`is_zero`)."""
    for _ in range(2):                      # a second pass lets rewritten values feed their neighbours
        for loop in loops:
            ids = list(loop.arcs)
            for pos, k in enumerate(ids):
                nxt = ids[(pos + 1) % len(ids)]
                for (a, end_a), (b, end_b) in (((k, 1), (nxt, 0)), ((nxt, 0), (k, 1))):
                    t_a, t_b = values[a][end_a], values[b][end_b]
                    if _is_plain(t_a) or not _is_plain(t_b):
                        continue
                    src_a, src_b = sources[arcs[a].source], sources[arcs[b].source]
                    config = list(src_b["theta"])
                    config[src_b["i"]] = t_b
                    candidate = _free_value_at(chain, src_a, config)
                    if candidate is None:
                        continue
                    fitted = _fit(candidate, _value(t_a), 2 * sp.pi, 1e-20)
                    if fitted is not None and len(str(fitted)) < len(str(t_a)):
                        values[a][end_a] = fitted


def closed_forms(boundary) -> list[dict]:
    """Closed forms of every boundary arc: ``center``, ``radius``, ``start_angle``, ``end_angle`` (radians),
    ``theta_sets`` (degrees) and ``free_values`` (the free joint at the start and end vertex, radians), as
    SymPy expressions built from the chain's exact inputs.

    ``boundary`` is a :class:`~workspace_sym.planar.boundary.Boundary` (read for its
    chain, arcs and loops; this module imports nothing from it).  The topology
    comes from the float computation; each closed form is matched to its float
    value (to 1e-9) and a vertex falls back to a 17-digit float only if no
    closed form matches (the row's ``"exact"`` flag is then False).  Polar
    angles are written as one ``atan2`` of integer-coefficient arguments,
    radii as ``sqrt(N)/D``, and a vertex shared with a plain neighbour is
    rewritten from the neighbour's configuration when that form is shorter and proved equal.
    Computed on every call; :attr:`Boundary.exact` holds the result once.

    Parameters
    ----------
    boundary : Boundary
        The boundary of a planar chain.

    Returns
    -------
    list of dict
        One dict per arc of ``boundary.arcs``: ``center`` (pair), ``radius``, ``start_angle``, ``end_angle``,
        ``theta_sets`` (one tuple per joint, degrees), ``free_values``, ``joint`` (0-based index of the free
        joint), ``configuration`` (the joint angles of the Step 1 arc, radians, None for the free joint) and
        ``exact`` (False when a vertex fell back to a float).
    """
    chain = boundary.chain
    kept = chain.kept_arcs()
    sources = {b.source: _exact_source(chain, kept[b.source]) for b in boundary.arcs}
    values, ends = {}, {}
    for loop in boundary.loops:
        ids = list(loop.arcs)
        for pos, k in enumerate(ids):
            a = boundary.arcs[k]
            src = sources[a.source]
            prev = boundary.arcs[ids[pos - 1]]
            nxt = boundary.arcs[ids[(pos + 1) % len(ids)]]
            others = [sources[b.source] for b in boundary.arcs if b.source != a.source]
            start = _vertex_angle(src, a.start_angle, [sources[prev.source]], others)
            end = _vertex_angle(src, a.end_angle, [sources[nxt.source]], others)
            ts = []
            for ang in (start, end):
                t = src["lo"] + ang - src["a0"]
                cands = [_fit(t, v, 2 * sp.pi) for v in a.theta_sets[src["i"]]]
                ts.append(next((c for c in cands if c is not None), t))
            sweep = (a.end_angle - a.start_angle) / (2 * math.pi)
            turns = int(math.copysign(math.floor(abs(sweep) + 1e-9), sweep))
            if turns > 0:       # a whole circle (a full-turn joint): its two ends are one vertex, a turn apart
                ts[1] = ts[0] + turns * 2 * sp.pi
            elif turns < 0:
                ts[0] = ts[1] - turns * 2 * sp.pi
            values[k], ends[k] = ts, (a.start_angle, a.end_angle)
    _shorter_vertices(chain, boundary.loops, boundary.arcs, sources, values)
    result = []
    for k, a in enumerate(boundary.arcs):
        src = sources[a.source]
        i, ts = src["i"], values[k]
        angles = [_fit(src["a0"] + t - src["lo"], v, 2 * sp.pi, 1e-7) for t, v in zip(ts, ends[k])]
        sets = [(src["theta"][j] * 180 / sp.pi,) if j != i else None for j in range(chain.p)]
        sets[i] = tuple(sp.expand(e * 180 / sp.pi) for e in sorted(ts, key=lambda e: _value(e)))
        result.append({"center": src["center"], "radius": src["radius"], "start_angle": angles[0],
                       "end_angle": angles[1], "theta_sets": sets, "free_values": tuple(ts),
                       "joint": i, "configuration": tuple(src["theta"]),
                       "exact": not any(t.has(sp.Float) for t in ts)})
    return result


def exact_arcs(boundary) -> list[dict]:
    """The closed forms of the arcs of ``boundary`` (:func:`closed_forms`), computed once per boundary.

    Parameters
    ----------
    boundary : Boundary
        The boundary of a planar chain.

    Returns
    -------
    list of dict
        :attr:`boundary.exact <workspace_sym.planar.boundary.Boundary.exact>`: the rows of :func:`closed_forms`,
        the same list on every call.

    Examples
    --------
    >>> from workspace_sym import PlanarChain
    >>> b = PlanarChain([1, 1], [-90, 0], [90, 90]).boundary()
    >>> rows = exact_arcs(b)
    >>> [r["radius"] for r in rows], all(r["exact"] for r in rows)
    ([2, 1, sqrt(2), 1], True)
    >>> sp.simplify(exact_area(b))
    pi
    """
    return boundary.exact


def _printed_length(e) -> int:
    # Printed length without ordering the terms: the str printer orders an Add by evaluating its terms numerically,
    # which for the nested radicals of a six-link chain costs minutes; the order changes no length.
    return len(sp.sstr(e, order="none"))


def _shortest(*forms):
    return min(forms, key=_printed_length)


def area_terms(boundary, rows=None) -> list[sp.Expr]:
    """One closed-form term per boundary arc whose sum is the enclosed area (Green's theorem).

    Along arc k the free joint i turns the distal segments rigidly about the centre ``C = sum_{a<i} l_a u(phi_a)``
    from ``t_s`` to ``t_e``, so ``(1/2) int (x dy - y dx)`` over the arc is

        A_k = (r_k^2 (t_e - t_s) + sum_{a<i<=b} l_a l_b (sin(phi_b(t_e) - phi_a) - sin(phi_b(t_s) - phi_a))) / 2

    (``cross(u(a), u(b)) = sin(b - a)``): the sector swept about ``C`` plus the change of ``cross(C, P)``.  Each term
    is written in the shortest of a few rearrangements SymPy proves equal (expanded, common factors out).

    Parameters
    ----------
    boundary : Boundary
        The boundary of a planar chain.
    rows : list of dict, optional
        Its closed forms (:func:`closed_forms`); by default ``boundary.exact``.

    Returns
    -------
    list of sympy.Expr
        One term per arc, in the order of ``rows``.

    Examples
    --------
    >>> from workspace_sym import PlanarChain
    >>> area_terms(PlanarChain([1, 1], [-90, 0], [90, 90]).boundary())
    [2*pi, 1/2 + pi/4, -pi, -pi/4 - 1/2]
    """
    rows = boundary.exact if rows is None else rows
    L, p = boundary.chain.exact_lengths, boundary.chain.p
    terms = []
    for r in rows:
        i, (t_s, t_e) = r["joint"], r["free_values"]
        config = list(r["configuration"])
        centre = _segment_terms(L, config, 0, i)
        ends = []
        for t in (t_s, t_e):
            config[i] = t
            ends.append(_segment_terms(L, config, i, p, centre[-1][1] if i else 0))
        cross = sum(la * lb * (sp.sin(be - aa) - sp.sin(bs - aa))
                    for la, aa in centre for (lb, bs), (_, be) in zip(*ends))
        term = sp.expand((sp.expand(r["radius"] ** 2) * (t_e - t_s) + cross) / 2)
        terms.append(_shortest(term, sp.factor_terms(term), sp.collect(term, sp.pi)))
    return terms


def exact_area(boundary, rows=None) -> sp.Expr:
    """The enclosed area as a closed form: the sum of :func:`area_terms` (over the exact arcs ``rows``, by
    default those of :func:`exact_arcs`).

    Parameters
    ----------
    boundary : Boundary
        The boundary of a planar chain.
    rows : list of dict, optional
        Its closed forms (:func:`closed_forms`); by default ``boundary.exact``.

    Returns
    -------
    sympy.Expr
        The area, written in the shortest of a few forms SymPy proves equal to the sum of the terms (see
        :func:`shortest_form`): ``2*sqrt(3)*pi``, not ``pi*(-2 + sqrt(3)) + pi*(sqrt(3) + 2)``.
    """
    return shortest_form(sp.Add(*area_terms(boundary, rows)))


SIMPLIFY_SECONDS = 2.0   # sympy.simplify of an area, tried on small sums only
SIMPLIFY_OPS = 80        # ... of at most this many operations (count_ops of the expanded sum)


def shortest_form(expr) -> sp.Expr:
    """``expr`` (one of this module's exact closed forms) in the shortest printed of a few equal forms.

    The candidates are the expression itself, its expansion, the expansion collected in ``pi`` and with its common
    factors out, :func:`sympy.together`, :func:`sympy.factor` and, for a small expression, :func:`sympy.simplify`
    within :data:`SIMPLIFY_SECONDS` (:func:`~workspace_sym.symbolic.attempt`); each is a rewriting SymPy proves
    equal, and one whose value differs from ``expr``'s at 40 digits is dropped all the same.  Meant for our own
    exact expressions (lengths and angles already read), never for user text.

    Parameters
    ----------
    expr : sympy.Expr
        A closed form without free symbols.

    Returns
    -------
    sympy.Expr
        The shortest candidate by printed length; ``expr`` itself when none is shorter.

    Raises
    ------
    SymbolicBudgetError
        When an enclosing :class:`~workspace_sym.symbolic.symbolic_budget` runs out during the attempts.

    Examples
    --------
    >>> shortest_form(sp.pi * (sp.sqrt(3) - 2) + sp.pi * (sp.sqrt(3) + 2))
    2*sqrt(3)*pi
    """
    expr = sp.sympify(expr)
    value = sp.N(expr, 40)
    if not (value.is_number and value.is_real):
        return expr
    expanded = sp.expand(expr)
    forms = [expr, expanded, sp.collect(expanded, sp.pi), sp.factor_terms(expanded)]
    for rewrite in (sp.together, sp.factor):
        done, form = attempt(lambda f=rewrite: f(expanded), SIMPLIFY_SECONDS / 4, "rewriting an area")
        if done:
            forms.append(form)
    if sp.count_ops(expanded) <= SIMPLIFY_OPS:
        done, form = attempt(lambda: sp.simplify(expr), SIMPLIFY_SECONDS, "simplifying an area")
        if done:
            forms.append(form)
    scale = max(1.0, abs(float(value)))
    # The shortest of the forms that pass the check, checking the shortest first (a stable sort keeps min's choice
    # among equal lengths): each check evaluates a form at 40 digits, as long as a rewriting for a sum of sines of
    # arctangents, and the longer forms need none once a shorter one passed.
    for form in sorted(forms, key=_printed_length):
        if form is expr or (form.is_number and abs(sp.N(form - value, 40)) <= 1e-30 * scale):
            return form
    return expr         # not reached: expr is among the forms
