"""Pairs of a section map proved unreachable by the wrist's ring (workspace_sym/serial/mapsection.py: WristRing,
wrist_ring, ring_unreachable; docs/methods.md section 9): the ring's constants against the DH tables, its bound
against sampled configurations, and every claim against the definition at cell corners and on the cone's rim,
then against sampled configurations of the UR5 and the Panda, aimed at their stretched arms where the claims are."""

from __future__ import annotations

import math

import numpy as np
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from reach_checks import industrial_arm, on_cone, sampled_pairs
from workspace_sym import robots
from workspace_sym.kinematics import numeric_function
from workspace_sym.serial.reachmap import sphere_directions
from workspace_sym.serial.ring import WristRing, ring_outer_cells, ring_unreachable, wrist_ring


def _ring_distance(ring, p, a):
    """``g``: the squared distance from ``S`` to the nearest point of the ring of ``(p, a)`` (floats)."""
    y = p - ring.centre[:, 0]
    t = (y * a).sum(axis=-1)
    side = np.sqrt(np.maximum((y * y).sum(axis=-1) - t * t, 0.0))
    return (t - ring.offset[0]) ** 2 + (side - ring.radius[0]) ** 2


def _limits(robot):
    """The joints' limits, a whole turn for a joint without any (the UR5's)."""
    return np.array([[float(v) for v in (j.limits or (-sp.pi, sp.pi))] for j in robot.joints])


def test_the_rings_constants_are_the_tables_and_its_bound_is_the_stretched_arm():
    # Reference: the DH tables (exact). UR5 (tests/data/dh/ur5.json, standard DH): w2 = o_4, p - o_4 = d5 z_4 +
    # d6 z_5 with z_4 normal to the approach z_5, so L = d6 and rho = d5; S = (0, 0, d1) on the first axis, and
    # |o_4 - S|^2 = |a2 + a3 turned|^2 + d4^2 is at most (a2 + a3)^2 + d4^2, attained with the elbow straight.
    # Panda (modified DH): w2 = o_5 (axes 5 and 6 meet), p - o_5 = 0.088 x + 0.21 a: L = 0.21, rho = 0.088;
    # S = (0, 0, 0.333). The Puma's tool point is its wrist centre (L = rho = 0): no ring.
    ur5 = industrial_arm("ur5")
    ring = wrist_ring(ur5, ())
    d = {k: float(ur5.joints[k].d) for k in range(6)}
    a = {k: abs(float(ur5.joints[k].a)) for k in range(6)}
    assert ring.offset[0] <= d[5] <= ring.offset[1] and ring.radius[0] <= d[4] <= ring.radius[1]
    assert np.allclose(ring.centre[:, 0], [0, 0, d[0]], atol=1e-300) and np.allclose(ring.centre[:, 1], [0, 0, d[0]])
    top = (a[1] + a[2]) ** 2 + d[3] ** 2
    assert top <= ring.reach <= top + 1e-5
    panda = industrial_arm("panda")
    ring = wrist_ring(panda, ())
    assert ring.offset[0] <= 0.21 <= ring.offset[1] and ring.radius[0] <= 0.088 <= ring.radius[1]
    assert np.allclose(ring.centre.T, [[0, 0, 0.333]] * 2)
    assert wrist_ring(robots.build("puma560"), ()) is None


def test_sampled_configurations_lie_within_the_rings_bound_and_come_near_it():
    # Reference: forward kinematics of 200,000 configurations within the limits (floats): g <= reach everywhere
    # (the theorem), and the largest g within 1e-3 of the bound (the bound is not loose)
    for name in ("ur5", "panda"):
        robot = industrial_arm(name)
        ring = wrist_ring(robot, ())
        lim = _limits(robot)
        q = np.random.default_rng(3).uniform(lim[:, 0], lim[:, 1], size=(200_000, robot.n))
        T = numeric_function(robot.fk(), robot.q)(q)
        g = _ring_distance(ring, T[:, :3, 3], T[:, :3, 2])
        assert g.max() <= ring.reach and g.max() >= ring.reach - 1e-3


@settings(max_examples=120, deadline=None)
@given(st.sampled_from([0.05, 0.1, 0.3]), st.floats(-1, 1), st.sampled_from([0.0, 0.0823, 0.21, -0.3]),
       st.sampled_from([0.0, 0.088, 0.3]), st.sampled_from([1.0, 30.0, 90.0, 180.0]),
       st.tuples(*[st.integers(0, 8)] * 3), st.tuples(*[st.integers(0, 1)] * 3), st.floats(0, 1),
       st.floats(0, 2 * math.pi), st.integers(0, 25), st.sampled_from([0.0, 1e-12, 1e-6]))
@example(0.1, 0.0, 0.0823, 0.09465, 30.0, (4, 4, 4), (0, 0, 0), 1.0, 0.0, 12, 0.0)   # a corner, the rim, g = reach
@example(0.1, 0.0, 0.21, 0.088, 30.0, (8, 0, 8), (1, 1, 0), 0.0, 1.0, 5, 0.0)       # the axis of the cone
def test_a_tool_point_whose_ring_reaches_the_bound_is_never_claimed(h, shift, L, rho, cone, at, face, t_frac, phi,
                                                                    k, slack):
    # Reference: the definition, point by point: a tool point p on a map cell's corner or face, an approach a on
    # the cone of direction k (its rim included) and a ring whose bound is g(p, a) itself (up to slack): a
    # configuration may sit there, so the pair (any closed cell holding p, k) must not be claimed unreachable.
    edges = tuple(shift + np.arange(10) * h for _ in range(3))
    directions = sphere_directions(26)
    a = on_cone(directions[k], cone, t_frac, phi)
    p = np.array([edges[i][at[i]] + (h / 2 if face[i] else 0.0) for i in range(3)])
    centre = np.array([[0.1, 0.1], [-0.05, -0.05], [shift, shift]])
    probe = WristRing((L, L), (rho, rho), centre, (shift, shift), 0.0)
    g = float(_ring_distance(probe, p, a)) * (1 + 1e-12) + slack
    ring = WristRing((L, L), (rho, rho), centre, (shift, shift), g)
    proved = ring_unreachable(edges, np.ones((9, 9, 9, 1), dtype=bool), directions[k:k + 1], cone, ring)
    cells = [[j for j in (at[i] - 1, at[i]) if 0 <= j < 9 and edges[i][j] <= p[i] <= edges[i][j + 1]]
             for i in range(3)]
    assert not any(proved[i, j, m, 0] for i in cells[0] for j in cells[1] for m in cells[2])


def test_sampled_configurations_never_fall_in_a_ring_proved_pair():
    # Reference: forward kinematics of 300,000 configurations per arm (floats) within the limits, half of them
    # with the elbow near straight (the UR5's third joint within 0.1 rad of 0, the Panda's fourth within 0.1 of
    # its upper limit), where the tool point is farthest and the claims are: none may land in a pair the ring
    # proves unreachable (grid of 0.05 over the arm's reach, 26 directions of 30 deg).  The claims are many and
    # depend on the direction (a cell is claimed for some directions, not all).
    directions = sphere_directions(26)
    for name, elbow, stretched in (("ur5", 2, 0.0), ("panda", 3, -0.0698)):
        robot = industrial_arm(name)
        ring = wrist_ring(robot, ())
        R = math.sqrt(ring.reach) + ring.offset[1] + ring.radius[1]
        edges = tuple(ring.centre[a, 0] + np.arange(-R, R + 0.05, 0.05) for a in range(3))
        # the shell of cells whose centres lie from 0.7 to 1.05 times the reach from S, where the claims are
        mid = np.stack(np.meshgrid(*[0.5 * (e[1:] + e[:-1]) - ring.centre[a, 0] for a, e in enumerate(edges)],
                                   indexing="ij"), -1)
        r = np.linalg.norm(mid, axis=-1)
        shell = np.repeat(((r > 0.7 * R) & (r < 1.05 * R))[..., None], 26, axis=-1)
        proved = ring_unreachable(edges, shell, directions, 30.0, ring)
        assert (proved.any(axis=-1) & ~proved.all(axis=-1)).sum() > 1_000
        lim = _limits(robot)
        q = np.random.default_rng(5).uniform(lim[:, 0], lim[:, 1], size=(300_000, robot.n))
        q[:150_000, elbow] = np.clip(stretched + np.random.default_rng(6).uniform(-0.1, 0.1, 150_000),
                                     lim[elbow, 0], lim[elbow, 1])
        index, ks = sampled_pairs(robot, edges, directions, 30.0, q)
        assert len(ks) > 300_000
        assert not proved[index[:, 0], index[:, 1], index[:, 2], ks].any()


def test_the_rings_bound_holds_at_50_digits_where_the_arm_is_stretched():
    # Reference: mpmath at 50 digits on SymPy's own forward kinematics of the UR5 at configurations with the
    # elbow straight (the bound's maximum) and random others: g <= reach, with L and rho the table's d6 and d5
    import mpmath

    ur5 = industrial_arm("ur5")
    ring = wrist_ring(ur5, ())
    T = ur5.fk()
    rng = np.random.default_rng(8)
    with mpmath.workdps(50):
        for row in range(12):
            q = rng.uniform(-math.pi, math.pi, 6)
            if row < 6:
                q[2] = 0.0
            M = T.subs(dict(zip(ur5.q, [sp.Float(v, 50) for v in q]))).evalf(50)
            p = [mpmath.mpf(str(M[i, 3])) for i in range(3)]
            a = [mpmath.mpf(str(M[i, 2])) for i in range(3)]
            y = [p[0], p[1], p[2] - mpmath.mpf(str(ur5.joints[0].d))]
            t = sum(y[i] * a[i] for i in range(3))
            side = mpmath.sqrt(max(sum(v * v for v in y) - t * t, 0))
            g = (t - mpmath.mpf("0.0823")) ** 2 + (side - mpmath.mpf("0.09465")) ** 2
            assert g <= ring.reach


@settings(max_examples=150, deadline=None)
@given(st.sampled_from([0.01, 0.05, 0.2]), st.floats(-0.3, 0.3), st.sampled_from([0.0, 0.21, -0.1]),
       st.sampled_from([0.0, 0.088, 0.3]), st.sampled_from([0.0, 1e-9, math.radians(20), math.pi / 2]),
       st.sampled_from([1.0, -1.0]), st.integers(0, 7), st.integers(0, 7), st.tuples(st.integers(0, 1),
                                                                                      st.integers(0, 1)),
       st.floats(0, 1), st.floats(0, 2 * math.pi), st.floats(0, 2 * math.pi), st.sampled_from([0.0, 1e-12]))
@example(0.05, 0.0, 0.21, 0.088, 0.0, -1.0, 7, 0, (0, 0), 0.0, 0.0, 0.0, 0.0)          # an exact approach, a corner
@example(0.05, 0.1, 0.21, 0.088, math.radians(20), -1.0, 0, 3, (1, 1), 1.0, 1.0, 2.0, 0.0)  # the axis, the rim
def test_a_section_point_whose_ring_reaches_the_bound_is_never_claimed_outer(h, s_z, L, rho, cone, sign, i, j,
                                                                            face, t_frac, phi, psi, slack):
    # Reference: the definition on the solid of revolution: a point at section coordinates (rho, z) on a cell's
    # corner or face (any polar angle psi), an approach within the cone about sign * z (its rim included), and a
    # ring whose bound is g at that point and approach: the cells holding (rho, z) must not be proved outer.
    edges = (np.arange(9) * h - h, s_z - 4 * h + np.arange(9) * h)          # rho from -h (a padded grid), z about S
    point = (max(edges[0][i] + (h / 2 if face[0] else 0.0), 0.0), edges[1][j] + (h / 2 if face[1] else 0.0))
    p = np.array([point[0] * math.cos(psi), point[0] * math.sin(psi), point[1]])
    a = on_cone((0.0, 0.0, sign), math.degrees(cone), t_frac, phi) if cone else np.array([0.0, 0.0, sign])
    centre = np.array([[0.0, 0.0], [0.0, 0.0], [s_z, s_z]])
    probe = WristRing((L, L), (rho, rho), centre, (s_z, s_z), 0.0)
    g = float(_ring_distance(probe, p, a)) * (1 + 1e-12) + slack
    proved = ring_outer_cells(edges, WristRing((L, L), (rho, rho), centre, (s_z, s_z), g), sign, cone)
    cells = [[k for k in (at - 1, at) if 0 <= k < 8 and edges[ax][k] <= point[ax] <= edges[ax][k + 1]]
             for ax, at in ((0, i), (1, j))]
    assert cells[0] and cells[1]
    assert not any(proved[k, m] for k in cells[0] for m in cells[1])


def test_the_panda_section_cells_outer_by_the_ring_hold_no_sampled_tool_down_point():
    # Reference: forward kinematics of 2 x 10^6 configurations within the limits (floats), those whose approach is
    # within 20 deg of straight down, and those within 0.05 rad of it (near tool down): no section point
    # (rho, z) in a cell the ring proves outer for that cone (20 deg) or for the exact approach (0). The claims
    # are many (the stretched arm's shell).
    panda = industrial_arm("panda")
    ring = wrist_ring(panda, ())
    edges = (np.arange(-0.01, 1.0, 0.01), np.arange(-0.6, 1.4, 0.01))
    lim = _limits(panda)
    q = np.random.default_rng(9).uniform(lim[:, 0], lim[:, 1], size=(2_000_000, 7))
    T = numeric_function(panda.fk(), panda.q)(q)
    p, a_z = T[:, :3, 3], T[:, 2, 2]
    rho, z = np.hypot(p[:, 0], p[:, 1]), p[:, 2]
    for cone, pad in ((math.radians(20), 1e-9), (0.0, 0.05)):
        proved = ring_outer_cells(edges, ring, -1.0, cone + pad)
        assert proved.sum() > 1_000
        near = a_z <= -math.cos(cone + pad)
        i = np.searchsorted(edges[0], rho[near], side="right") - 1
        j = np.searchsorted(edges[1], z[near], side="right") - 1
        assert near.sum() > 1_000 and not proved[i, j].any()
