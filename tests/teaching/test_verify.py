"""Teaching helpers: right answers are accepted, wrong ones rejected with the evidence."""


import numpy as np
import pytest
import sympy as sp

from workspace_sym import InvalidParameterError, robots
from workspace_sym.interval import StopAt, pave
from workspace_sym.planar import PlanarChain
from workspace_sym.symbolic import factor_trig
from workspace_sym.verify import (
    assert_boundary_arc,
    assert_expression,
    assert_factors,
    assert_measure,
    assert_reachable,
    check_boundary_arc,
    check_expression,
    check_factors,
    check_measure,
    check_reachable,
)

ARM = PlanarChain(["0.186", "0.146", "0.108"], [-60, 0, -10], [120, 130, 25])   # Bastien 2018, Table 1 (iii)


def test_expression_right_and_wrong(glass):
    """The glass arm's x coordinate (paper 004): the textbook form is accepted, a sign slip is caught with a
    counterexample that really is one (re-evaluated here at 30 digits)."""
    derived = glass.position[0]
    c = {k: sp.Symbol(f"theta{k}") for k in range(1, 7)}
    a1, a2, a3, d5 = sp.symbols("a1 a2 a3 d5")
    right = sp.cos(c[1]) * (a1 + a2 * sp.cos(c[2]) + a3 * sp.cos(c[2] + c[3]) + d5 * sp.sin(c[2] + c[3] + c[4]))
    wrong = sp.cos(c[1]) * (a1 + a2 * sp.cos(c[2]) - a3 * sp.cos(c[2] + c[3]) + d5 * sp.sin(c[2] + c[3] + c[4]))
    assert set(derived.free_symbols) >= {c[1], c[2]}
    assert check_expression(right, derived).ok is True
    v = check_expression(wrong, derived)
    assert v.ok is False
    point = {sp.Symbol(k): sp.Rational(val) for k, val in v.evidence["counterexample"].items()}
    assert abs(sp.N((wrong - derived).subs(point), 30)) > 1e-20


def test_expression_identities():
    assert check_expression("sin(2*t)", "2*sin(t)*cos(t)").ok is True
    assert check_expression("sin(t)**2", "1 - cos(t)**2").ok is True
    assert check_expression("sin(t)", "cos(t)").ok is False


def test_reachable_witness_and_proof():
    v = check_reachable(ARM, (0.0, 0.30))
    assert v.ok is True and np.allclose(ARM.forward(v.evidence["configuration"]), [0.0, 0.30], atol=1e-10)
    theta = np.array(v.evidence["configuration"])
    assert (theta >= np.array(ARM.lower) - 1e-12).all() and (theta <= np.array(ARM.upper) + 1e-12).all()
    assert check_reachable(ARM, (0.0, -0.30)).ok is False          # behind the shoulder: proved unreachable
    assert check_reachable(ARM, (0.0, 0.45)).ok is False           # beyond the reach 0.44
    with pytest.raises(InvalidParameterError, match="point"):
        check_reachable(ARM, (float("nan"), 0.0))


def test_boundary_arc_right_and_wrong():
    b = ARM.boundary()
    outer = max(b.arcs, key=lambda a: a.radius)                    # the stretched arm, radius 0.44 about O
    lo, hi = sorted((outer.start_angle, outer.end_angle))
    assert check_boundary_arc(ARM, (0, 0), 0.44, lo, hi).ok is True
    assert check_boundary_arc(ARM, (0, 0), 0.44, lo - 0.3, hi).ok is False   # runs past theta_1 = 120 deg
    assert check_boundary_arc(ARM, (0, 0), 0.40, lo, hi).ok is False         # inside the workspace


def test_measure_against_brackets():
    b = ARM.boundary()
    assert check_measure(b.area, b).ok is True
    assert check_measure(0.27, b).ok is False and check_measure(0.27, b, rel_tol=0.01).ok is True
    model = robots.build("rpr2")
    paving = pave(model.constraints, model.box, delta=0.25)
    assert check_measure(float(model.exact_measure), paving).ok is True    # Rybak: 35.0533 inside the bracket
    assert check_measure(40.0, paving).ok is False
    with pytest.raises(InvalidParameterError, match="result"):
        check_measure(1.0, object())


def test_factors_up_to_constants():
    """The planar 2R arm's Jacobian determinant in the plane is l1 l2 s2 (the classical identity): its factors in
    any scaling pass, a missing or an extra factor is named."""
    robot = robots.build("planar-2r")
    derived = factor_trig(robot.position_jacobian[:2, :2].det())
    assert {str(f) for f in derived} == {"l1", "l2", "sin(theta2)"}
    assert check_factors(", ".join(robot.to_str(f) for f in derived), derived, robot=robot).ok is True
    assert check_factors(["-2*" + robot.to_str(f) for f in derived], derived, robot=robot).ok is True
    v = check_factors(", ".join([robot.to_str(f) for f in derived] + ["c1"]), derived, robot=robot)
    assert v.status == "wrong" and v.evidence["extra"] == ["cos(theta1)"]
    v = check_factors("c2", derived, robot=robot)
    assert v.status == "wrong" and "sin(theta2)" in v.evidence["missing"]
    assert check_factors("s2 +", derived, robot=robot).status == "cannot read"


def test_assertions_for_autograders():
    """Each assert_* returns the verdict when the student is right and raises AssertionError carrying the
    verdict's explanation otherwise (nbgrader shows that message)."""
    glass = robots.build("glass-handling")
    x = glass.position[0]
    assert assert_expression("c1 (a1 + a2 c2 + a3 c23 + d5 s234)", x, robot=glass).ok is True
    with pytest.raises(AssertionError, match=r"^wrong: not equal: at .* the answer is .* but the derived value is"):
        assert_expression("c1 (a1 + a2 c2 - a3 c23 + d5 s234)", x, robot=glass)
    with pytest.raises(AssertionError, match=r"^cannot read: .*unknown name 'zz' at column 4"):
        assert_expression("c1 zz", x, robot=glass)
    robot = robots.build("planar-2r")
    with pytest.raises(AssertionError, match=r"missing .*sin\(theta2\); not a singular factor: cos\(theta2\)"):
        assert_factors("c2", factor_trig(robot.position_jacobian[:2, :2].det()), robot=robot)
    assert assert_reachable(ARM, (0.0, 0.30)).ok is True
    assert assert_reachable(ARM, (0.0, -0.30), claimed=False).ok is True
    with pytest.raises(AssertionError, match="claimed reachable, but it is unreachable: interval arithmetic"):
        assert_reachable(ARM, (0.0, -0.30))
    b = ARM.boundary()
    outer = max(b.arcs, key=lambda a: a.radius)
    lo, hi = sorted((outer.start_angle, outer.end_angle))
    assert assert_boundary_arc(ARM, (0, 0), 0.44, lo, hi).ok is True
    with pytest.raises(AssertionError, match=r"^wrong: the point at angle .* the workspace, not on its boundary"):
        assert_boundary_arc(ARM, (0, 0), 0.40, lo, hi)
    assert assert_measure(b.area, b).ok is True
    with pytest.raises(AssertionError, match="above the area"):
        assert_measure(0.5, b)


def test_reachable_only_with_a_proof():
    """Issue 31 item 1: no end point of two unit links is farther than 2 from the origin (triangle inequality), so
    (2 + 1e-10, 0) is unreachable, proved in exact arithmetic; (2, 0) is reached exactly at theta = (-90, 0) deg
    (a joint at its limit: the exact witness is checked in SymPy); an interior point is proved reached by the
    Krawczyk test, and the solution really is near the witness (re-solved here in closed form by the law of
    cosines); a point just beyond a corner of the workspace is 'within tolerance, not decided', never
    'reachable'."""
    arm = PlanarChain(["1", "1"], [-90, -90], [90, 90])
    v = check_reachable(arm, (2 + 1e-10, 0))
    assert v.status == "wrong" and v.evidence["method"] == "reach bound"
    v = check_reachable(arm, (2, 0))
    assert v.ok is True and v.evidence["method"] == "exact witness"
    assert [sp.sympify(t) for t in v.evidence["exact_configuration"]] == [-sp.pi / 2, 0]
    v = check_reachable(arm, (0.5, 1.5))
    assert v.ok is True and v.evidence["method"] == "interval existence proof"
    t2 = np.arccos((0.5**2 + 1.5**2 - 2) / 2)                            # law of cosines, elbow angle
    assert abs(abs(v.evidence["configuration"][1]) - t2) < 1e-8
    corner = (1 + 1e-10, 1)                                           # theta = (-90, 90) deg reaches (1, 1)
    v = check_reachable(arm, corner)
    assert v.ok is None and v.evidence["method"] == "within tolerance" and "not decided" in v.message
    with pytest.raises(AssertionError, match=r"^undecided: within tolerance 1e-10 x reach"):
        assert_reachable(arm, corner)
    with pytest.raises(AssertionError, match=r"claimed reachable, but it is unreachable: .*exact arithmetic"):
        assert_reachable(arm, (2 + 1e-10, 0))
    assert assert_reachable(arm, (2, 0)).evidence["method"] == "exact witness"



def test_reachable_takes_its_box_budget_from_stop():
    """Issue 38 (one options spelling): the budget of check_reachable's one box search is stop=StopAt(max_boxes=);
    max_boxes= still works for one release, with a DeprecationWarning naming the new spelling, shown at the caller;
    a time limit, which the search cannot honour, is refused.  Reference: (0.5, 1.2) is unreachable by the 2R arm
    with limits [-90, 90] (law of cosines: cos theta2 = (1.69 - 2) / 2 < 0, beyond the elbow's limit), proved
    under the default budget and not within 1 box."""
    arm = PlanarChain(["1", "1"], [-90, -90], [90, 90])
    assert check_reachable(arm, (0.5, 1.2)).evidence["method"] == "interval exclusion"
    new = check_reachable(arm, (0.5, 1.2), stop=StopAt(max_boxes=1))
    assert new.status == "undecided" and "no proof within 1 boxes" in new.message
    with pytest.warns(DeprecationWarning) as caught:
        old = check_reachable(arm, (0.5, 1.2), max_boxes=1)
    assert [str(w.message) for w in caught] == [
        "check_reachable: max_boxes= is deprecated; pass stop=StopAt(max_boxes=...)"]
    assert caught[0].filename == __file__
    assert (old.status, old.message) == (new.status, new.message)
    with pytest.raises(InvalidParameterError, match="time_limit does not apply; got time_limit=5") as error:
        check_reachable(arm, (0.5, 1.2), stop=StopAt(time_limit=5))
    assert error.value.parameter == "stop"


def test_reachable_verdicts_agree_with_the_law_of_cosines():
    """Random points near the outer circle and the elbow limit of a 2R arm with limits [-90, 90]: every decided
    verdict agrees with the closed-form answer (the elbow angle from the law of cosines within its limit, then
    theta_1 within its own), and 'reachable' comes only with a proof."""
    arm = PlanarChain(["1", "1"], [-90, -90], [90, 90])
    rng = np.random.default_rng(5)
    decided = 0
    for _ in range(12):
        r = float(rng.choice([2 - 1e-9, 2 + 1e-9, np.sqrt(2) * (1 + 1e-9), np.sqrt(2) * (1 - 1e-9)]))
        a = float(rng.uniform(-np.pi, np.pi))
        x, y = r * np.cos(a), r * np.sin(a)
        v = check_reachable(arm, (x, y), stop=StopAt(max_boxes=20_000))
        c2 = (x * x + y * y - 2) / 2
        truth = None
        if c2 > 1 or c2 < 0:                                        # |theta_2| > 90 deg or beyond the reach
            truth = False
        else:
            t2 = np.arccos(c2)
            polar = np.arctan2(y, x)                                  # theta_1 = polar - 90 deg - theta_2 / 2
            firsts = [polar - np.pi / 2 - s * t2 / 2 for s in (1, -1)]
            ok = [abs((t + np.pi) % (2 * np.pi) - np.pi) < np.pi / 2 - 1e-6 for t in firsts]
            near = [abs(abs((t + np.pi) % (2 * np.pi) - np.pi) - np.pi / 2) < 1e-6 for t in firsts]
            truth = True if any(ok) else (None if any(near) else False)
        if v.ok is not None:
            decided += 1
            assert truth is None or v.ok is truth, (x, y, v)
            assert v.evidence["method"] in ("exact witness", "interval existence proof", "reach bound",
                                            "interval exclusion")
    assert decided >= 8


def test_a_certified_bracket_has_no_hidden_slack():
    """check_measure widened every bracket by 1e-12 even with rel_tol=0: a value just above a certified upper bound
    was accepted.  Reference: the paving's own bracket, and the next float beyond each end."""
    paving = pave(["x**2 + y**2 <= 1"], {"x": (-1.1, 1.1), "y": (-1.1, 1.1)}, delta=0.2)
    lo, hi = paving.measure_bounds
    assert check_measure(lo, paving).ok and check_measure(hi, paving).ok
    assert check_measure(float(np.nextafter(hi, 10)), paving).ok is False
    assert check_measure(float(np.nextafter(lo, -10)), paving).ok is False
