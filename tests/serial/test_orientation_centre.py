"""Issue 40: the cone of the LBR iiwa 14 (rtb-data URDF) through its wrist centre (docs/methods.md section 8, "A cone
through the wrist centre"): the tool point is the wrist centre plus 0.126 m along the approach, the wrist (joints 5
and 6, roll over 340 deg, pitch within +-120 deg) reaches every approach within 120 deg of its roll axis, so the
workspace of a cone about straight down is paved on the section of the chain to the wrist centre, its direction
proofs also proving the roll axis within 120 deg less the approach's tilt of straight down, and the tool's section
derived from it (turn.tool_section).

References: configurations sampled within the limits whose approach lies in the cone (the robot's own fk_numeric),
an inverse kinematics at 50 digits (mpmath), a least-squares wrist solution for the wrist's reach (scipy), and for
the tool's section a brute-force check of its claims on random wrist-centre sections.
"""

import dataclasses
import math
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from reach_checks import admissible_configurations, arcs_volume, arm_in_cone_at_50_digits, in_any_box, industrial_arm
from workspace_sym.interval.graph import numpy_constant
from workspace_sym.interval.image import CellGrid
from workspace_sym.interval.verdict import INSIDE as INNER
from workspace_sym.interval.verdict import OUTSIDE as OUTER
from workspace_sym.interval.verdict import UNDECIDED
from workspace_sym.kinematics import DHRobot
from workspace_sym.serial import Pose, reach
from workspace_sym.serial.pose import constraint_from, pose_structure, wrist_cap
from workspace_sym.serial.tuning import DEFAULT
from workspace_sym.serial.turn import tool_section

CONE = dict(approach=(0, 0, -1), cone=20)
# Coarse cells and few seeds: a bracket in seconds (about [0.58, 2.92] m^3; 300 s give [1.90, 2.39], BENCHMARKS.md)
TUNING = dataclasses.replace(DEFAULT, budget_cells=16, direction_samples=20_000)


@pytest.fixture(scope="module")
def iiwa():
    return industrial_arm("iiwa")


@pytest.fixture(scope="module")
def paving(iiwa):
    return reach(iiwa, delta=0.2, pose=Pose(**CONE), tuning=TUNING)


@pytest.mark.slow
def test_the_iiwa_cone_goes_through_its_wrist_centre(iiwa, paving):
    """The structure is recognised with the URDF's own numbers (flange 63/500 m, pitch limit 2.0942 rad) and the
    run proves boxes of both kinds."""
    structure = pose_structure(iiwa, (), constraint_from(**CONE), TUNING)        # the run's, cached
    centre = structure.centre
    assert centre is not None and structure.model is None
    assert centre.length == sp.Rational(63, 500) and centre.sign == -1
    assert float(centre.psi) == pytest.approx(2.0942, abs=1e-12)
    assert paving.method == "section" and paving.counts["inner"] > 0 and paving.counts["outer"] > 0


@pytest.mark.slow
def test_admissible_configurations_never_land_in_an_outer_box_and_the_bracket_holds_their_volume(iiwa, paving):
    """Sampled configurations within the limits with the approach in the cone: their tool points never lie in an
    outer box (narrowed by 1e-9 for float rounding), and their volume estimate (cells of 0.04 turned by Pappus,
    ``arcs_volume``: no bound, 2.19 m^3 at 0.01 with 4.7e5 points, session 24) lies in the bracket."""
    q, _, points = admissible_configurations(iiwa, 1_000_000, 7, **CONE)
    assert len(points) > 10_000
    assert not in_any_box(points, paving.outer, pad=-1e-9).any()
    lo, hi = paving.measure_bounds
    assert 0 < lo <= arcs_volume(iiwa, q[:, 0], points, 0.04) <= hi


@pytest.mark.slow
def test_points_of_inner_boxes_are_reached_in_the_cone_at_50_digits(iiwa, paving):
    """A point drawn in each of 5 inner boxes is the tool point of a configuration within the limits whose approach
    lies within 20 deg of straight down, found by least squares and refined at 50 digits (checked there)."""
    rng = np.random.default_rng(4)
    boxes = paving.inner[rng.choice(len(paving.inner), 5, replace=False)]
    for box in boxes:
        point = rng.uniform(box[:, 0], box[:, 1])
        assert arm_in_cone_at_50_digits(iiwa, point, (0, 0, -1), 20, rng) is not None, point


@pytest.mark.slow
def test_the_wrist_reaches_every_approach_within_its_reach_of_the_roll_axis(iiwa):
    """Second method for the half-turn roll (wrist_cap's symbolic identity): at random arm configurations, random
    approaches within 119 deg of the roll axis are reached by joints 5 and 6 within their limits (least squares on
    the two wrist joints, the arm fixed; joint 7 does not turn the approach)."""
    from scipy.optimize import least_squares

    rng = np.random.default_rng(2)
    limits = iiwa.joint_limits()
    chain = DHRobot(list(iiwa.joints[:4]), convention=iiwa.convention)
    for _ in range(12):
        q = rng.uniform(limits[:, 0], limits[:, 1])
        z = chain.fk_numeric(q[None, :4])[0][:3, 2]                         # the roll joint's axis
        beta = math.radians(rng.uniform(0, 119))
        u = np.cross(z, rng.normal(size=3))
        u /= np.linalg.norm(u)
        target = math.cos(beta) * z + math.sin(beta) * u

        def residual(w, q=q, target=target):
            full = np.r_[q[:4], w, q[6]]
            return iiwa.fk_numeric(full[None])[0][:3, 2] - target

        best = min((least_squares(residual, rng.uniform(limits[4:6, 0], limits[4:6, 1]),
                                  bounds=(limits[4:6, 0], limits[4:6, 1]), xtol=1e-15, ftol=1e-15, gtol=1e-15)
                    for _ in range(8)), key=lambda fit: np.abs(fit.fun).max())
        assert np.abs(best.fun).max() < 1e-9, (q, target)


def test_a_roll_of_less_than_half_a_turn_is_no_wrist():
    """The half-turn reduction needs the roll to turn at least pi: the iiwa's chain with joint 5 limited to +-80
    deg is refused by name (reference: the condition itself)."""
    iiwa = industrial_arm("iiwa")
    joints = list(iiwa.joints)
    joints[4] = dataclasses.replace(joints[4], limits=(-sp.pi * 4 / 9, sp.pi * 4 / 9))
    tool = sp.Matrix(iiwa.tool) * sp.Matrix([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -sp.Rational(63, 500)],
                                             [0, 0, 0, 1]])
    moved = DHRobot(joints, convention=iiwa.convention, tool=tool)
    why = wrist_cap(moved, None, moved.substitute(moved.fk()), half_turn=True)
    assert isinstance(why, str) and "less than half a turn" in why


@st.composite
def centre_sections(draw):
    """A random wrist-centre section on a grid of cells 0.05 wide over [0, 1] x [-1, 1]: a blob of inner cells
    (a disc of random centre and radius), a ring of undecided cells around it, outer cells beyond; a tool length
    and a cone."""
    grid = CellGrid(np.array([[0.0, 1.0], [-1.0, 1.0]]), 0.05)
    e0, e1 = grid.edges
    rc = draw(st.floats(0.0, 0.8))
    zc = draw(st.floats(-0.6, 0.6))
    radius = draw(st.floats(0.05, 0.5))
    ring = draw(st.floats(0.0, 0.2))
    mid0, mid1 = np.meshgrid(0.5 * (e0[:-1] + e0[1:]), 0.5 * (e1[:-1] + e1[1:]), indexing="ij")
    distance = np.hypot(mid0 - rc, mid1 - zc)
    classes = np.full(grid.shape, OUTER, dtype=np.int8)
    classes[distance < radius + ring] = UNDECIDED
    classes[distance < radius] = INNER
    classes[e0[1:] <= 0.0, :] = OUTER                   # no wrist centre at rho < 0
    length = sp.Rational(draw(st.integers(-200, 200)), 1000)
    # up to 179 deg: a cone of a quarter turn or more holds horizontal approaches (a review found outer cells
    # claimed with the sideways reach |L| sin(cone) there, fewer than |L|)
    cone = sp.pi * sp.Rational(draw(st.one_of(st.integers(1, 40), st.integers(85, 179))), 180)
    sign = draw(st.sampled_from([-1, 1]))
    return grid, classes, length, cone, sign


def _cell_of(grid, rho, z):
    e0, e1 = grid.edges
    return np.searchsorted(e0, rho, side="right") - 1, np.searchsorted(e1, z, side="right") - 1


@settings(max_examples=40, deadline=None)
@given(centre_sections(), st.integers(0, 2**32 - 1))
def test_the_tool_section_claims_only_what_its_wrist_centres_give(section, seed):
    """Brute force on random sections: a point of an inner tool cell is ``w + L a`` for a wrist centre ``w`` in an
    inner cell and some ``a`` within the cone (searched among 2001 in-plane approaches, with a margin of 1e-9 for
    float rounding); a point of an outer tool cell is ``w + L a`` for no ``a`` of 400 random approaches of the cone
    (any azimuth) with ``w`` in a cell that is not outer."""
    grid, classes, length, cone, sign = section
    tilt = min(cone, sp.pi / 2)                     # the in-plane approaches of the inner cells
    tool, codes = tool_section([(grid, classes, tilt)], length, cone, sign, offsets=4)
    rng = np.random.default_rng(seed)
    L, c = float(length), float(cone)
    e0, e1 = tool.edges
    for code in (INNER, OUTER):
        cells = np.argwhere(codes == code)
        for i, j in cells[rng.choice(len(cells), min(len(cells), 15), replace=False)] if len(cells) else []:
            rho = rng.uniform(max(e0[i], 0.0), max(e0[i + 1], 0.0))
            z = rng.uniform(e1[j], e1[j + 1])
            if code == INNER:
                # the offsets tool_section tries (offsets=4), and 2001 more between them
                t = min(c, math.pi / 2)
                s = np.r_[np.linspace(-math.sin(t), math.sin(t), 9) * (1 - 1e-9),
                          np.linspace(-math.sin(t), math.sin(t), 2001)]
                rw, zw = rho - L * s, z - L * sign * np.sqrt(1 - s * s)
                a, b = _cell_of(grid, rw, zw)
                ok = (rw >= 0) & (a >= 0) & (a < grid.shape[0]) & (b >= 0) & (b < grid.shape[1])
                inner = np.zeros(len(s), dtype=bool)
                inner[ok] = classes[a[ok], b[ok]] == INNER
                assert inner.any(), (rho, z)
            else:
                tilt = np.arccos(rng.uniform(math.cos(c), 1.0, 400))
                turn = rng.uniform(0, 2 * math.pi, 400)
                a3 = np.stack([np.sin(tilt) * np.cos(turn), np.sin(tilt) * np.sin(turn), sign * np.cos(tilt)], 1)
                w = np.array([rho, 0.0, z]) - L * a3
                rw, zw = np.hypot(w[:, 0], w[:, 1]), w[:, 2]
                a, b = _cell_of(grid, rw, zw)
                on = (a >= 0) & (a < grid.shape[0]) & (b >= 0) & (b < grid.shape[1])
                assert (classes[a[on], b[on]] == OUTER).all(), (rho, z)


def _closed_cells(edges, at_least, at_most):
    """Indices ``i`` of the closed cells ``[e_i, e_(i+1)]`` holding a point, given the exact tests ``at_least(e)``
    (point >= e) and ``at_most(e)`` (point <= e) against float edges read as exact rationals."""
    return [i for i in range(len(edges) - 1)
            if at_least(Fraction(float(edges[i]))) and at_most(Fraction(float(edges[i + 1])))]


def _ge_root(x, m, r):
    """``x >= m sqrt(r)`` exactly (``x``, ``m``, ``r >= 0`` rationals)."""
    if m == 0 or r == 0:
        return x >= 0
    if m > 0:
        return x >= 0 and x * x >= m * m * r
    return x >= 0 or x * x <= m * m * r


@settings(max_examples=12, deadline=None)
@given(centre_sections(), st.integers(0, 2**32 - 1))
def test_the_tool_section_claims_hold_in_exact_rationals(section, seed):
    """The same claims decided exactly (rationals, square roots by squaring; the cone's cosine at 50 digits, a
    margin of 1e-30): a rational point of an inner tool cell is ``w + L a`` for one of the in-plane approaches
    tool_section tries (``s`` its floats read exactly, ``a = (s, 0, sign sqrt(1 - s^2))`` within the cone) with
    ``w`` in a closed inner cell at ``rho_w >= 0``; for 60 rational unit approaches of the cone (any azimuth,
    ``(2u, 2v, sign (1 - u^2 - v^2)) / (1 + u^2 + v^2)``) a rational point of an outer tool cell minus ``L a`` lies
    in a closed outer cell or beyond the grid.  (It fails when tool_section reads its inner cells wrongly; the float
    test above, with more approaches, is the one that catches a too narrow outer widening.)"""
    import mpmath

    grid, classes, length, cone, sign = section
    tilt = min(cone, sp.pi / 2)
    tool, codes = tool_section([(grid, classes, tilt)], length, cone, sign, offsets=4)
    rng = np.random.default_rng(seed)
    L = Fraction(int(length.p), int(length.q))
    g0, g1 = grid.edges
    e0, e1 = tool.edges
    with mpmath.workdps(50):
        cos_c = mpmath.cos(mpmath.pi * mpmath.mpf(int((cone / sp.pi).p)) / int((cone / sp.pi).q))
        half_tan = Fraction(float(mpmath.tan(mpmath.pi * mpmath.mpf(int((cone / sp.pi).p))
                                              / (2 * int((cone / sp.pi).q))))) * Fraction(999_999, 1_000_000)
    sin_t = float(numpy_constant(sp.sin(tilt))[0])
    offsets = [Fraction(float(v)) for v in np.unique(np.linspace(-sin_t, sin_t, 9) * (1 - 1e-9))]
    for code in (INNER, OUTER):
        cells = np.argwhere((codes == code) & (e0[1:, None] > 0))     # cells holding points at rho >= 0
        for i, j in cells[rng.choice(len(cells), min(len(cells), 15), replace=False)] if len(cells) else []:
            rho = Fraction(float(rng.uniform(max(e0[i], 0.0), max(e0[i + 1], 0.0))))
            z = Fraction(float(rng.uniform(e1[j], e1[j + 1])))
            if code == INNER:
                found = False
                for s_ in offsets:
                    k2 = 1 - s_ * s_
                    with mpmath.workdps(50):
                        if mpmath.sqrt(mpmath.mpf(k2.numerator) / k2.denominator) < cos_c + mpmath.mpf("1e-30"):
                            continue
                    rw = rho - L * s_
                    if rw < 0:
                        continue
                    rows = _closed_cells(g0, lambda e, x=rw: x >= e, lambda e, x=rw: x <= e)
                    # z_w = z - L sign sqrt(k2): z_w >= e iff z - e >= L sign sqrt(k2)
                    cols = _closed_cells(g1, lambda e, r=k2, y=z: _ge_root(y - e, L * sign, r),
                                         lambda e, r=k2, y=z: _ge_root(e - y, -L * sign, r))
                    found |= any(classes[a, b] == INNER for a in rows for b in cols)
                assert found, (rho, z)
            else:
                for _ in range(60):            # toward the cap's rim, where the widest reach sideways is
                    r, turn = 1 - rng.uniform(0, 1) ** 3, rng.uniform(0, 2 * math.pi)
                    u, v = (Fraction(float(x)) * half_tan for x in (r * math.cos(turn), r * math.sin(turn)))
                    n = 1 + u * u + v * v
                    approach = (2 * u / n, 2 * v / n, sign * (1 - u * u - v * v) / n)
                    wx, wy, wz = rho - L * approach[0], -L * approach[1], z - L * approach[2]
                    r2 = wx * wx + wy * wy
                    rows = _closed_cells(g0, lambda e, x=r2: e <= 0 or x >= e * e,
                                         lambda e, x=r2: e >= 0 and x <= e * e)
                    cols = _closed_cells(g1, lambda e, x=wz: x >= e, lambda e, x=wz: x <= e)
                    # a point on an edge is in both closed cells: one proved empty of wrist centres is enough
                    assert not rows or not cols or any(classes[a, b] == OUTER for a in rows for b in cols), \
                        (rho, z, approach)


def test_an_asymmetric_pitch_reaches_the_smaller_of_its_two_sides():
    """With half a turn of roll, both signs of the pitch are needed: the iiwa's chain with joint 6 limited to [-60,
    120] deg reaches 60 deg from the roll axis, not 120 (reference: the two wrist solutions of the docstring)."""
    iiwa = industrial_arm("iiwa")
    joints = list(iiwa.joints)
    joints[5] = dataclasses.replace(joints[5], limits=(-sp.pi / 3, 2 * sp.pi / 3))
    tool = sp.Matrix(iiwa.tool) * sp.Matrix([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -sp.Rational(63, 500)],
                                             [0, 0, 0, 1]])
    moved = DHRobot(joints, convention=iiwa.convention, tool=tool)
    _, psi, wrist = wrist_cap(moved, None, moved.substitute(moved.fk()), half_turn=True)
    assert wrist == (4, 5) and sp.simplify(psi - sp.pi / 3) == 0


def test_a_side_map_proves_its_condition_or_nothing():
    """SideMap's hook: a joint box on which the side condition holds everywhere is admissible, one reaching below
    the bound is not, and its seeds satisfy the condition (reference: the condition q1 >= 1/2 itself)."""
    from workspace_sym.interval.image import ImageMap
    from workspace_sym.serial.turn import SideMap

    q = sp.symbols("q1:4")
    lateral = ImageMap([q[0] + q[1], q[1] * q[2], q[2]], q, [(-1, 1)] * 3, [False] * 3)
    side = SideMap(lateral, [(q[0], 0.5)])
    boxes = np.array([[[0.6, 0.7], [0, 0], [0, 0]], [[0.4, 0.7], [0, 0], [0, 0]], [[0.5, 0.5], [-1, 1], [0, 1]]])
    assert side.admissible(boxes).tolist() == [True, False, True]
    seeds = side.random_configurations(500, np.random.default_rng(0))
    assert len(seeds) > 100 and (seeds[:, 0] > 0.5).all()
    assert side.position_float(seeds).shape == (len(seeds), 3)          # the same compiled map
