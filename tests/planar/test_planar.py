"""Alignment method, Steps 0 and 1 (Bastien 2018): the paper's counts, and geometric checks
of every arc against forward kinematics."""

import math

import numpy as np
import pytest
import sympy as sp

from workspace_sym import InvalidParameterError, JointLimitError
from workspace_sym.planar import PlanarChain

HUMAN_ARM = ([0.186, 0.146, 0.108], [-60, 0, -10], [120, 130, 25])  # Table 1, case iii
P2 = ([0.30, 0.15], [-120, -30], [0, 30])
P6 = ([0.20, 0.20, 0.15, 0.35, 0.20, 0.20], [-120, -120, -30, -90, -45, -23], [60, 170, 30, 91, 23, 24])


@pytest.mark.parametrize("chain, step0, step1", [(HUMAN_ARM, 16, 11), (P2, 5, 7), (P6, 506, 75)],
                         ids=["table1-iii", "p2", "p6"])
def test_paper_counts(chain, step0, step1):
    """Bastien 2018: figure 4 (16 and 11 arcs), figure 5 (7 arcs after Step 1), section 7 (506 and 75)."""
    c = PlanarChain(*chain)
    assert len(c.candidate_arcs()) == step0
    assert len(c.kept_arcs()) == step1


def test_candidate_bound():
    """At most 2^(2p-1) - 2^(p-1) candidates (docs/methods.md section 4)."""
    for chain in (HUMAN_ARM, P2, P6):
        p = len(chain[0])
        assert len(PlanarChain(*chain).candidate_arcs()) <= 2 ** (2 * p - 1) - 2 ** (p - 1)


@pytest.mark.parametrize("chain", [HUMAN_ARM, P2, P6], ids=["table1-iii", "p2", "p6"])
def test_every_arc_configuration_is_in_limits_and_on_its_circle(chain):
    """Independent check: forward kinematics of each arc's configurations lies on the arc."""
    c = PlanarChain(*chain)
    for arc in c.candidate_arcs() + c.kept_arcs():
        i = arc.free_joint - 1
        lo, hi = arc.theta_sets[i]
        for t in np.linspace(lo, hi, 7):
            theta = [s[0] for s in arc.theta_sets]
            theta[i] = t
            assert all(c.lower[k] - 1e-12 <= theta[k] <= c.upper[k] + 1e-12 for k in range(c.p))
            p = c.forward(theta)
            assert math.isclose(math.dist(p, arc.center), arc.radius, rel_tol=1e-9, abs_tol=1e-12)
            angle = arc.start_angle + (t - lo)
            expected = (arc.center[0] + arc.radius * math.cos(angle), arc.center[1] + arc.radius * math.sin(angle))
            assert math.dist(p, expected) < 1e-9


def test_outermost_kept_arc_is_the_reach_with_workspace_inside():
    """Independent check with 50 000 random configurations: the largest kept radius about O equals the
    sampled reach (0.44, the stretched arm), and its side is -1 (workspace towards the centre)."""
    c = PlanarChain(*HUMAN_ARM)
    rng = np.random.default_rng(0)
    theta = np.array(c.lower) + (np.array(c.upper) - np.array(c.lower)) * rng.random((50000, 3))
    reach = np.hypot(*c.forward(theta).T).max()
    outer = max((a for a in c.kept_arcs() if a.center == (0.0, 0.0)), key=lambda a: a.radius)
    assert math.isclose(outer.radius, sum(c.lengths)) and outer.side == -1
    assert reach <= outer.radius + 1e-12 and outer.radius - reach < 1e-3


@pytest.mark.parametrize("args, error, match", [
    (([0.1, 0.2], [-10, 20], [10, 10]), JointLimitError, r"upper limit of joint 2 \(10 deg\) must exceed"),
    (([0.1], [float("-inf")], [10]), InvalidParameterError, "lower limit of joint 1 must be a finite number"),
    (([1e160, 1e160], [-10, -10], [10, 10]), InvalidParameterError, r"lengths: the longest link \(1e\+160\)"),
    (([1e154, 1e154], [-10, -10], [10, 10]), InvalidParameterError, r"lengths: the longest link \(1e\+154\)"),
    (([1, 1e-8], [-10, -10], [10, 10]), InvalidParameterError, r"lengths: the shortest link \(1e-08\) must be at "),
    (([0.1, -1], [0, 0], [1, 1]), InvalidParameterError, "length of joint 2 must be positive; got -1"),
    (([], [], []), InvalidParameterError, "at least one joint"),
    (([float("nan")], [0], [1]), InvalidParameterError, "length of joint 1 must be a finite number"),
])
def test_bad_input(args, error, match):
    with pytest.raises(error, match=match):
        PlanarChain(*args)


@pytest.mark.parametrize("lower, upper", [(-180, 180), (-360, 360), (-179.999999, 180), (-180, 179.9999999),
                                          (-179.99999999, 179.99999999), (0, 360), (-180, 179.99999)])
def test_full_turn_is_a_joint_without_limits(lower, upper):
    """Issue 23 item 2: a range of 360 deg or more (datasheets write +-180 or +-360) is accepted and is a full
    turn, and so is one within 2 RESOLUTION rad (1.1e-5 deg) of it; the joint runs over [-pi, pi]."""
    c = PlanarChain([0.3, 0.2], [lower, -90], [upper, 90])
    assert c.full == (True, False)
    assert (c.lower[0], c.upper[0]) == (-math.pi, math.pi)
    assert c.exact_lower[0] == -sp.pi and c.exact_upper[0] == sp.pi


def test_a_range_short_of_a_full_turn_keeps_its_limits():
    """2e-5 deg short of a full turn (above RESOLUTION rad) keeps its limits; ranges outside (-180, 180] are
    accepted as they are."""
    c = PlanarChain([0.3, 0.2], [-179.99998, 170], [180, 300])
    assert c.full == (False, False)
    assert c.lower[1] == pytest.approx(math.radians(170)) and c.upper[1] == pytest.approx(math.radians(300))
