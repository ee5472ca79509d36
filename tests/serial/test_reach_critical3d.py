"""The critical-set method for any serial position map into space (issue 24 item 1).

A spatial arm that fits none of the structures of ``reach`` (planar, product, first revolute joint turning a
section) is paved by ``critical_paving`` with ``m = 3``: the critical set of every face of the joint box covered,
its enclosures marking a 3-D grid of cells, each 6-connected region of unmarked cells decided by one proof.
Coarse deltas and budgets of boxes (never of seconds): every machine decides the same cells.

References, each named in its test:
* exact: the oblique prism arm (a prismatic joint along z0, then a 2R chain of full turns in a plane tilted by
  ``alpha_1 = atan(3/4)``) reaches exactly the points with ``0 <= z - 3y/4 <= 1/2`` and
  ``1/4 <= x^2 + (5y/4)^2 <= 9/4``, of volume ``2 pi * 1/2 * 4/5 = 4 pi / 5``, checked in rationals;
* independent numerics: 10^5 configurations within the limits placed by the robot's own numeric position never
  lie in an outer box; corners and centres of inner boxes are reached within the limits by an inverse
  kinematics at 50 digits;
* a second method: on a 3R elbow arm (which the section method paves) the 3-D method forced and the section
  method never contradict each other, and their volume brackets meet;
* a property over random small prismatic-first arms (joints near full turns, zero lengths, coaxial joints).
"""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import workspace_sym.interval.image as image
from reach_checks import in_any_box, reached_at_50_digits
from workspace_sym import StopAt
from workspace_sym.errors import InvalidParameterError
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial import reach, resolve_method
from workspace_sym.serial.model import reach_model
from workspace_sym.serial.structure import structure_of

QUIET = StopAt()
HALF = sp.Rational(1, 2)

# A robot on a rail: P along z0, then alpha = 90 deg and two limited revolute joints, and one full turn.
RAIL = DHRobot([DHJoint.prismatic(1, alpha=sp.pi / 2, limits=(0, HALF)),
                DHJoint.revolute(2, a=sp.Rational(2, 5), alpha=sp.pi / 2, limits=(-sp.pi / 2, sp.pi / 2)),
                DHJoint.revolute(3, d=sp.Rational(1, 10), a=sp.Rational(3, 10), limits=(-sp.pi / 2, sp.pi / 2)),
                DHJoint.revolute(4, a=sp.Rational(1, 5))], name="rail")

# P along z0, then a 2R chain (1, 1/2) of full turns in the plane of normal z1 = (0, -3/5, 4/5).
OBLIQUE = DHRobot([DHJoint.prismatic(1, alpha=sp.atan(sp.Rational(3, 4)), limits=(0, HALF)),
                   DHJoint.revolute(2, a=1), DHJoint.revolute(3, a=HALF)], name="oblique prism")
OBLIQUE_VOLUME = 4 * sp.pi / 5


def _in_oblique(x, y, z) -> bool:
    """Exact membership (Fractions): the stroke ``q1 = z - 3y/4`` in ``[0, 1/2]`` and the in-plane point
    ``(x, 5y/4)`` in the annulus ``1/2 <= r <= 3/2``."""
    q1 = z - Fraction(3, 4) * y
    r2 = x * x + (Fraction(5, 4) * y) ** 2
    return 0 <= q1 <= Fraction(1, 2) and Fraction(1, 4) <= r2 <= Fraction(9, 4)


def _positions(robot, q):
    """The robot's own numeric position (not the reach model) at configurations ``q`` (``(N, n)``)."""
    return robot.numeric(robot.position)(q)[:, :, 0]


def _samples(robot, n, seed):
    rng = np.random.default_rng(seed)
    limits = robot.joint_limits()
    return rng.uniform(limits[:, 0], limits[:, 1], size=(n, robot.n))


@pytest.fixture(scope="module")
def rail():
    return reach(RAIL, delta=0.25, stop=QUIET)


@pytest.fixture(scope="module")
def oblique():
    return reach(OBLIQUE, delta=0.25, stop=QUIET)


def test_an_arm_without_structure_takes_the_critical_method(rail):
    """A prismatic first joint fits no structure (no plane, no product, no revolute first joint): 'auto' picks
    the critical method in space, which ends with inner and outer boxes and a complete paving."""
    assert reach_model(RAIL, ()).m == 3 and structure_of(RAIL, ()) is None
    assert resolve_method(RAIL) == "critical" and resolve_method(RAIL, "critical") == "critical"
    assert rail.method == "critical" and rail.complete and not len(rail.pending)
    assert len(rail.inner) > 0 and len(rail.outer) > 0
    lo, hi = rail.measure_bounds
    assert 0 < lo < hi


def test_sampled_configurations_of_the_rail_miss_every_outer_box(rail):
    """Independent numerics: 10^5 configurations of all four joints within the limits (the full turn over
    [-pi, pi]), placed by the robot's own numeric position, never lie in a closed outer box."""
    pos = _positions(RAIL, _samples(RAIL, 100_000, seed=11))
    assert len(rail.outer) > 0
    assert not in_any_box(pos, rail.outer).any()


def test_inner_boxes_of_the_rail_are_reached_at_50_digits(rail):
    """Inverse kinematics at 50 digits: the corners and the centre of 8 inner boxes (spread over the list) are
    reached within the limits, the residual below 1e-40."""
    model = reach_model(RAIL, ())
    rng = np.random.default_rng(5)
    q = model.random_configurations(40_000, rng)
    pos = model.position_float(q)
    inner = rail.inner
    assert len(inner) >= 8
    for box in inner[np.linspace(0, len(inner) - 1, 8).astype(int)]:
        for point in [*itertools.product(*box), box.mean(axis=1)]:
            assert reached_at_50_digits(model, np.array(point), q, pos), (box.tolist(), point)


def test_the_oblique_prism_reference_is_the_forward_kinematics():
    """The closed form of the exact tests is the robot's: every sampled position (floats) recovers its stroke
    ``q1 = z - 3y/4`` and lies in the annulus of the plane, to rounding."""
    q = _samples(OBLIQUE, 2000, seed=3)
    x, y, z = _positions(OBLIQUE, q).T
    assert np.allclose(z - 0.75 * y, q[:, 0], atol=1e-12)
    r = np.hypot(x, 1.25 * y)
    assert (r >= 0.5 - 1e-12).all() and (r <= 1.5 + 1e-12).all()


def test_the_oblique_prism_bracket_holds_its_exact_volume(oblique):
    """Exact reference: the volume 4 pi / 5 lies in the proved bracket (compared exactly: each float bound is a
    rational), and the paving went through the critical method in space."""
    assert structure_of(OBLIQUE, ()) is None and oblique.method == "critical" and oblique.complete
    lo, hi = oblique.measure_bounds
    assert sp.Rational(lo) <= OBLIQUE_VOLUME <= sp.Rational(hi)
    assert 0 < lo and hi < oblique.box.measure


def _range_in(values, lo, hi) -> bool:
    return lo <= min(values) and max(values) <= hi


def test_inner_boxes_of_the_oblique_prism_lie_in_its_exact_set(oblique):
    """Exact reference, a proof per box: in rationals, the stroke ``z - 3y/4`` (linear: its range over the box is
    that of the corners) lies in [0, 1/2], and ``x^2 + (5y/4)^2`` over the box (each square's least value 0
    where its interval holds 0) lies in [1/4, 9/4]."""
    assert len(oblique.inner) > 20
    for box in oblique.inner:
        (x0, x1), (y0, y1), (z0, z1) = [(Fraction(lo), Fraction(hi)) for lo, hi in box]
        strokes = [z - Fraction(3, 4) * y for y in (y0, y1) for z in (z0, z1)]
        assert _range_in(strokes, 0, Fraction(1, 2)), box.tolist()

        def squares(a, b):
            return (0 if a <= 0 <= b else min(a * a, b * b)), max(a * a, b * b)
        (sx0, sx1), (sy0, sy1) = squares(x0, x1), squares(Fraction(5, 4) * y0, Fraction(5, 4) * y1)
        assert _range_in([sx0 + sy0, sx1 + sy1], Fraction(1, 4), Fraction(9, 4)), box.tolist()


def test_outer_boxes_of_the_oblique_prism_miss_its_exact_set(oblique):
    """Exact reference on dense samples: the 27 points of each outer box at the fractions 0, 1/2, 1 of its edges
    (corners, centres of faces and edges, centre) and 2 random rational points are outside the set."""
    rng = np.random.default_rng(2)
    assert len(oblique.outer) > 20
    for box in oblique.outer:
        ts = [*itertools.product((0, Fraction(1, 2), 1), repeat=3),
              *(tuple(Fraction(int(v), 997) for v in rng.integers(0, 998, 3)) for _ in range(2))]
        for t in ts:
            point = [Fraction(lo) + ti * (Fraction(hi) - Fraction(lo)) for (lo, hi), ti in zip(box, t)]
            assert not _in_oblique(*point), (box.tolist(), point)


# A 3R elbow arm: the section method paves it (first joint revolute about z0); the 3-D method is forced.
ELBOW = DHRobot([DHJoint.revolute(1, alpha=sp.pi / 2, limits=(-2 * sp.pi / 3, 2 * sp.pi / 3)),
                 DHJoint.revolute(2, a=HALF, limits=(-sp.pi / 2, sp.pi / 2)),
                 DHJoint.revolute(3, a=sp.Rational(2, 5), limits=(-2 * sp.pi / 3, 2 * sp.pi / 3))], name="elbow")


def _forced_3d(robot, **options):
    """``reach`` with every structure hidden: the critical method in space."""
    from workspace_sym.serial import plans

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(plans, "structure_of", lambda robot, parameters: None)
        return reach(robot, stop=QUIET, **options)


def _inside_points(boxes, rng, n=4):
    """The centre and ``n`` random interior points of each box: ``(N (n + 1), m)``."""
    t = rng.uniform(0.01, 0.99, size=(len(boxes), n, boxes.shape[1]))
    t = np.concatenate([np.full((len(boxes), 1, boxes.shape[1]), 0.5), t], axis=1)
    return (boxes[:, None, :, 0] + t * (boxes[:, None, :, 1] - boxes[:, None, :, 0])).reshape(-1, boxes.shape[1])


def test_the_3d_method_and_the_section_method_agree_on_an_elbow_arm():
    """Second method: on the elbow arm, the section method (auto) and the 3-D method (forced) never call a point
    inner by one and outer by the other (sampled interior points of every inner box of each miss the outer
    boxes of the other), and their proved volume brackets meet."""
    assert structure_of(ELBOW, ()) is not None
    section = reach(ELBOW, delta=0.25, stop=QUIET)
    cells = _forced_3d(ELBOW, delta=0.25)
    assert cells.method == section.method == "critical" and cells.complete and section.complete
    assert section.volume_bounds is None and len(cells.inner) and len(section.inner)
    rng = np.random.default_rng(4)
    for a, b in ((section, cells), (cells, section)):
        assert not in_any_box(_inside_points(a.inner, rng), b.outer).any()
    (lo1, hi1), (lo2, hi2) = section.measure_bounds, cells.measure_bounds
    assert max(lo1, lo2) <= min(hi1, hi2)


def test_a_cover_too_large_falls_back_to_the_pair_method(monkeypatch):
    """As on a planar arm: past MAX_COVER_BOXES joint boxes in flight, 'auto' runs the pair method (the same
    boxes as method='pairs' with the same budget) and method='critical' is a clear error naming the method."""
    monkeypatch.setattr(image, "MAX_COVER_BOXES", 200)
    stop = StopAt(max_boxes=800)
    auto = reach(OBLIQUE, delta=0.25, stop=stop)
    pairs = reach(OBLIQUE, delta=0.25, method="pairs", stop=stop)
    assert auto.method == "pairs" and auto.counts == pairs.counts and auto.measure_bounds == pairs.measure_bounds
    with pytest.raises(InvalidParameterError, match=r"method 'critical'.*parallel axes") as caught:
        reach(OBLIQUE, delta=0.25, method="critical", stop=stop)
    assert caught.value.parameter == "method"


def test_the_3d_method_refuses_storage_and_a_line_is_refused_clearly():
    """Bad input: the 3-D grid is decided in memory (max_memory refused with method='critical', naming the option
    and its value; under 'auto' the pairs method, which takes it, paves the arm), and
    'critical' on a position moving along one coordinate names the method and what it needs."""
    from workspace_sym import RunOn

    with pytest.raises(InvalidParameterError, match=r"3-D critical method on oblique prism.*max_memory='2GB'"):
        reach(OBLIQUE, delta=0.25, method="critical", stop=QUIET, run=RunOn(max_memory="2GB"))
    # under "auto" the arm goes to the pairs method, which stores its boxes (as before the 3-D method existed); the
    # method is chosen before the first box, so a budget of 300 boxes shows it as 3000 did (0.4 s of CPU, not 2.5 s)
    stored = reach(OBLIQUE, delta=0.25, stop=StopAt(max_boxes=300), run=RunOn(max_memory="2GB"))
    assert stored.method == "pairs"
    line = DHRobot([DHJoint.prismatic(1, limits=(0, 1))], name="line")
    with pytest.raises(InvalidParameterError, match="method 'critical' needs a position moving in two or three"):
        reach(line, delta=0.25, method="critical", stop=QUIET)
    assert resolve_method(line) == "pairs"


def test_a_budget_stops_the_3d_cover_cleanly():
    """A budget of boxes that runs out during the cover: nothing is decided from an unfinished cover, the boxes
    left are pending and tile the grid's box with the others (a box budget: the same on every machine)."""
    paving = reach(RAIL, delta=0.25, stop=StopAt(max_boxes=2000))
    assert not paving.complete and "budget of 2000 boxes" in paving.stop_reason
    assert len(paving.pending) > 0 and not len(paving.inner) and not len(paving.outer)
    assert abs(paving.measures["pending"] - paving.box.measure) <= 1e-9 * paving.box.measure


_LENGTHS = st.sampled_from([sp.Integer(0), sp.Rational(1, 4), HALF])
_TWISTS = st.sampled_from([sp.Integer(0), sp.pi / 2, sp.atan(sp.Rational(3, 4))])
_LIMITS = st.sampled_from([None, (-sp.pi + sp.Rational(1, 100), sp.pi - sp.Rational(1, 100)), (-1, 2)])


@settings(max_examples=6, deadline=None, derandomize=True)
@given(twist=_TWISTS, rows=st.lists(st.tuples(_LENGTHS, _LENGTHS, st.sampled_from([sp.Integer(0), sp.pi / 2]),
                                              _LIMITS), min_size=2, max_size=2))
def test_random_prismatic_first_arms_keep_samples_out_of_outer_boxes(twist, rows):
    """Property over random small prismatic-first arms (zero lengths, coaxial revolute joints, joints 1/100 short
    of a full turn or a full turn), the 3-D method forced: 20,000 sampled configurations within the limits, by
    the robot's own position, never lie in a closed outer box."""
    from hypothesis import assume

    robot = DHRobot([DHJoint.prismatic(1, alpha=twist, limits=(0, HALF)),
                     *(DHJoint.revolute(k, d=d, a=a, alpha=alpha, limits=limits)
                       for k, (d, a, alpha, limits) in enumerate(rows, start=2))], name="random rail")
    assume(reach_model(robot, ()).m == 3)
    paving = _forced_3d(robot, delta=0.3)
    pos = _positions(robot, _samples(robot, 20_000, seed=1))
    assert paving.complete
    assert not in_any_box(pos, paving.outer).any()


def test_a_joint_that_does_not_move_the_point_is_dropped_before_the_cover():
    """A last joint turning the tool about its own axis through the point (a = d = 0) leaves the position as it
    is: the reach model (the map whose critical set is covered) holds the four joints of the rail only, with the
    same position map (exact SymPy identity)."""
    wrist = DHRobot([*RAIL.joints, DHJoint.revolute(5, limits=(-1, 1))], name="rail with a wrist")
    model, bare = reach_model(wrist, ()), reach_model(RAIL, ())
    assert model.joints == [0, 1, 2, 3] and model.variables == bare.variables and model.k == 4
    assert all(sp.simplify(a - b) == 0 for a, b in zip(model.expressions, bare.expressions))
    assert resolve_method(wrist) == "critical" and structure_of(wrist, ()) is None


def test_the_cover_looks_at_the_budget_after_every_generation():
    """The cover in space can take minutes: a budget is asked after each generation of joint boxes (with the
    seconds expected of the next one when it takes ``ahead``), the progress bar shown the count each time, and a
    stop there decides no cell (nothing rests on an unfinished cover).  Reference: the counts handed to the
    budget grow from the 3 faces of the first generation, and the run stops with the reason it returned."""
    model = reach_model(OBLIQUE, ())
    asked = []

    def budget(evaluated, ahead=0.0):
        asked.append((evaluated, ahead))
        return "enough" if len(asked) == 4 else ""

    shown = []
    grid, classes, evaluated, reason = image.critical_paving(model, 0.1, budget=budget,
                                                             show=lambda share, count: shown.append((share, count)))
    assert reason == "enough" and evaluated == asked[-1][0] and len(asked) == 4
    assert shown == [(0.0, n) for n, _ in asked]          # the bar moves with every generation of the cover
    assert (classes == image.UNDECIDED).all()
    counts = [n for n, _ in asked]
    assert counts[0] == 3 and all(b > a for a, b in itertools.pairwise(counts))
    assert all(ahead >= 0 for _, ahead in asked)


def test_the_3d_cover_spread_over_an_executor_gives_the_same_paving(oblique):
    """The faces' covers go to an executor one group of faces per task (as for a planar arm): a box's fate depends
    on it alone, so the paving is the local one, box for box (a second run of the same method, split)."""
    from concurrent.futures import ThreadPoolExecutor

    from workspace_sym import RunOn

    with ThreadPoolExecutor(2) as pool:
        spread = reach(OBLIQUE, delta=0.25, stop=QUIET, run=RunOn(executor=pool))
    assert spread.method == "critical" and spread.counts == oblique.counts
    for kind in ("inner", "boundary", "outer"):
        assert np.array_equal(getattr(spread, kind), getattr(oblique, kind)), kind
    assert spread.measure_bounds == oblique.measure_bounds
