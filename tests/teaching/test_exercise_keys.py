"""Every answer key of `workspace-sym exercises`, re-derived by a second, independent path (issue 23 item 4).

The keys of 200 seeds (``make_exercises(seed=s, count=2, max_joints=3)``: one 3-joint DH robot and one planar
chain each) are cached per seed in ``tests/data/exercise_keys.json.gz`` with the chain's boundary arcs: generating
them takes minutes (SymPy kinematics), checking them takes seconds.  Each arc is cached as centre, radius, polar
angles of its ends (in the direction of travel, the workspace on the left) and the joint values of its midpoint.
``test_cache_is_the_generators_output`` regenerates a spread of seeds and compares them entry by entry, so a change
of the generator fails here until the cache is written again with ``PYTHONPATH=tests/helpers python
tests/teaching/test_exercise_keys.py``.

The second path shares no code with the generator's derivations: the DH transforms are multiplied here in numpy
(complex numbers), derivatives by complex steps, the planar chain by its own sums of sines and cosines, and
reachability by sampling and Gauss-Newton, arc counts and areas by those, winding numbers and Green's theorem.
Key answers (text) are read with the students' reader, evaluated at random joint values and lengths.
"""

import gzip
import itertools
import json
import math
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from paths import DATA
from workspace_sym.answers import Notation, read_answer
from workspace_sym.expressions import parse_expr

CACHE = DATA / "exercise_keys.json.gz"
SEEDS = range(200)
OPTIONS = {"count": 2, "max_joints": 3}
REGENERATED = (0, 61, 199)          # seeds generated again on every run and compared with the cache
H = 1e-30                                   # complex step


def _entry(seed: int) -> dict:
    """What is cached for one seed: the key, and the boundary arcs of its chain (per loop, in order of travel)."""
    from workspace_sym.exercises import make_exercises
    from workspace_sym.planar import PlanarChain

    _, _, key = make_exercises(seed=seed, **OPTIONS)
    (spec,) = key["chains"].values()
    b = PlanarChain(spec["lengths"], spec["lower"], spec["upper"]).boundary()
    loops = [[[*b.arcs[k].center, b.arcs[k].radius, b.arcs[k].start_angle, b.arcs[k].end_angle,
               b.arcs[k].configuration(sum(b.arcs[k].theta_sets[b.arcs[k].free_joint - 1]) / 2).tolist()]
              for k in loop.arcs] for loop in b.loops]
    return json.loads(json.dumps({"key": key, "loops": loops}))


@lru_cache(maxsize=1)
def _cache() -> dict:
    with gzip.open(CACHE, "rt") as f:
        data = json.load(f)
    assert data["options"] == OPTIONS
    return {int(s): v for s, v in data["seeds"].items()}


def _questions(seed: int, kind: str):
    entry = _cache()[seed]
    return [q for q in entry["key"]["questions"] if q["kind"] == kind]


def _number(text) -> float:
    return float(parse_expr(str(text), "key", new_symbols=False))


# ------------------------------------------------------------------------------ the DH robot, in numpy
def _rz(t):
    M = np.zeros(np.shape(t) + (4, 4), dtype=complex)
    M[..., 0, 0] = M[..., 1, 1] = np.cos(t)
    M[..., 1, 0] = np.sin(t)
    M[..., 0, 1] = -M[..., 1, 0]
    M[..., 2, 2] = M[..., 3, 3] = 1
    return M


def _rx(t):
    M = np.zeros(np.shape(t) + (4, 4), dtype=complex)
    M[..., 1, 1] = M[..., 2, 2] = np.cos(t)
    M[..., 2, 1] = np.sin(t)
    M[..., 1, 2] = -M[..., 2, 1]
    M[..., 0, 0] = M[..., 3, 3] = 1
    return M


def _tr(x, z):
    x, z = np.broadcast_arrays(x, z)
    M = np.zeros(x.shape + (4, 4), dtype=complex)
    M[..., 0, 0] = M[..., 1, 1] = M[..., 2, 2] = M[..., 3, 3] = 1
    M[..., 0, 3], M[..., 2, 3] = x, z
    return M


def _fk(spec: dict, q, lengths: dict) -> np.ndarray:
    """T_0^n of the DH table ``spec`` (the key's JSON) at joint values ``q`` (``(..., n)``, complex allowed)."""
    def value(v):
        return lengths[v] if isinstance(v, str) else float(v)

    q = np.asarray(q)
    T = np.broadcast_to(np.eye(4, dtype=complex), q.shape[:-1] + (4, 4))
    for k, row in enumerate(spec["joints"]):
        alpha, a = math.radians(row["alpha"]), value(row["a"])
        theta, d = (q[..., k], value(row["d"])) if row["type"] == "R" else (math.radians(row["theta"]), q[..., k])
        zeros = np.zeros(q.shape[:-1])
        if spec["convention"] == "standard":        # Rz(theta) Tz(d) Tx(a) Rx(alpha)
            T = T @ _rz(theta + zeros) @ _tr(a + zeros, d + zeros) @ _rx(alpha + zeros)
        else:                                       # Craig: Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)
            T = T @ _rx(alpha + zeros) @ _tr(a + zeros, zeros) @ _rz(theta + zeros) @ _tr(zeros, d + zeros)
    return T


def _jacobian(spec, q, lengths) -> np.ndarray:
    """6 x n geometric Jacobian by complex steps: v = dp/dq_k, omega from dR/dq_k R^T."""
    n = len(q)
    steps = np.array(q, dtype=complex)[None].repeat(n + 1, axis=0)
    steps[np.arange(1, n + 1), np.arange(n)] += 1j * H
    T = _fk(spec, steps, lengths)
    R = T[0, :3, :3].real
    dT = T[1:].imag / H                                      # (n, 4, 4)
    W = dT[:, :3, :3] @ R.T
    return np.concatenate([dT[:, :3, 3], np.stack([W[:, 2, 1], W[:, 0, 2], W[:, 1, 0]], axis=1)], axis=1).T


def _notation(spec) -> Notation:
    joints = {k: (sp.Symbol(f"theta{k}" if r["type"] == "R" else f"d{k}"), r["type"])
              for k, r in enumerate(spec["joints"], start=1)}
    return Notation(joints, frozenset(sp.Symbol(n) for n in spec["parameters"]))


def _random_point(spec, rng):
    """Random joint values (any real: identities hold everywhere) and lengths; as floats and as SymPy values."""
    q = rng.uniform(-2.5, 2.5, len(spec["joints"]))
    lengths = {n: float(rng.uniform(0.1, 1.0)) for n in spec["parameters"]}
    names = _notation(spec)
    values = {v: sp.Float(x) for (v, _), x in zip(names.joints.values(), q)}
    values.update({sp.Symbol(n): sp.Float(x) for n, x in lengths.items()})
    return q, lengths, values


def _value(expr, values) -> np.ndarray:
    return np.array(expr.xreplace(values).evalf(15), dtype=float).ravel()


def _robot(seed):
    entry = _cache()[seed]
    (name, spec), = entry["key"]["robots"].items()
    return spec, _notation(spec), [q for q in entry["key"]["questions"] if q.get("robot") == name]


# ------------------------------------------------------------------------------ the tests
def _differences(a, b, where="") -> list:
    """Where two JSON values differ: text, integers and booleans exactly, floats to 1e-9 (a last-bit difference of
    another machine's floating point is not a change of the generator)."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return [f"{where}: keys {sorted(set(a) ^ set(b))}"]
        return [d for k in a for d in _differences(a[k], b[k], f"{where}/{k}")]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: lengths {len(a)} != {len(b)}"]
        return [d for k, (x, y) in enumerate(zip(a, b)) for d in _differences(x, y, f"{where}/{k}")]
    if isinstance(a, float) or isinstance(b, float):
        same = isinstance(a, (int, float)) and isinstance(b, (int, float)) and math.isclose(a, b, rel_tol=1e-9,
                                                                                            abs_tol=1e-12)
        return [] if same else [f"{where}: {a!r} != {b!r}"]
    return [] if a == b and type(a) is type(b) else [f"{where}: {a!r} != {b!r}"]


@pytest.mark.parametrize("seed", REGENERATED)
def test_cache_is_the_generators_output(seed):
    """The cached keys are what make_exercises writes (regenerated here; floats compared to 1e-9)."""
    assert not _differences(_entry(seed), _cache()[seed]), (
        f"the generator changed: run 'PYTHONPATH=tests/helpers python {Path(__file__)}'")
    assert _differences({"a": [1.0, "x"]}, {"a": [1.0 + 1e-6, "x"]}) == ["/a/0: 1.0 != 1.000001"]


def test_the_cache_covers_200_seeds():
    assert set(_cache()) == set(SEEDS)
    kinds = {q["kind"] for s in SEEDS for q in _cache()[s]["key"]["questions"]}
    assert kinds == {"expression", "factors", "reachable", "integer", "measure"}


def test_fk_entries_and_jacobian_columns():
    """Expression keys: the end point's coordinate and a column of the geometric Jacobian equal, at random joint
    values and lengths, the numpy product of the DH matrices and its complex-step derivatives (1e-9)."""
    rng = np.random.default_rng(1)
    for seed in SEEDS:
        spec, names, questions = _robot(seed)
        for q in (q for q in questions if q["kind"] == "expression"):
            expr = read_answer(q["answer"], names)
            for _ in range(2 if q["prompt"].startswith("Give the ") else 1):
                joints, lengths, values = _random_point(spec, rng)
                if q["prompt"].startswith("Give the "):
                    i = "xyz".index(q["prompt"].split()[2])
                    expected = [_fk(spec, joints, lengths)[i, 3].real]
                else:
                    k = int(q["prompt"].split()[2]) - 1
                    expected = _jacobian(spec, joints, lengths)[:, k]
                got = _value(expr, values)
                assert np.allclose(got, expected, atol=1e-9), (seed, q["id"], got, expected)


def test_singular_factors():
    """Factor keys: the determinant of the 3 x 3 position Jacobian (complex steps of the numpy FK) is not
    identically zero, moves with the joints, and equals c * prod f_i^m_i for one constant c and multiplicities
    m_i in 1..3 at 6 random points (joint values and lengths): the key's factors are exactly its factors."""
    rng = np.random.default_rng(2)
    combos = np.array(list(itertools.product((1, 2, 3), repeat=6)))
    for seed in SEEDS:
        spec, names, questions = _robot(seed)
        (q,) = [q for q in questions if q["kind"] == "factors"]
        factors = [read_answer(f, names) for f in q["answer"]]
        assert factors, seed
        dets, values = [], []
        for _ in range(6):
            joints, lengths, point = _random_point(spec, rng)
            dets.append(np.linalg.det(_jacobian(spec, joints, lengths)[:3]))
            values.append([_value(f, point)[0] for f in factors])
        dets, values = np.array(dets), np.array(values)
        assert (np.abs(dets) > 1e-9).all(), (seed, dets)                  # det J is not identically 0
        joints, lengths, _ = _random_point(spec, rng)
        other = np.linalg.det(_jacobian(spec, joints + 0.7, lengths)[:3])
        assert abs(other - np.linalg.det(_jacobian(spec, joints, lengths)[:3])) > 1e-9, seed   # moves with q
        m = np.unique(combos[:, :len(factors)], axis=0)
        ratio = dets[None, :] / np.prod(values[None, :, :] ** m[:, None, :], axis=2)
        spread = np.abs(ratio / ratio[:, :1] - 1).max(axis=1)
        assert spread.min() < 1e-7, (seed, q["answer"], spread.min())


def test_robot_reachability():
    """Robot reachability keys: a witness is within the joint limits and the numpy FK maps it onto the point
    (1e-12); an unreachable point lies beyond sum_k sqrt(a_k^2 + max d_k^2) (each DH row translates by at most
    that: a second, tighter triangle inequality) and beyond 2000 sampled end points."""
    rng = np.random.default_rng(3)
    for seed in SEEDS:
        spec, _, questions = _robot(seed)
        (q,) = [q for q in questions if q["kind"] == "reachable"]
        lengths = {n: _number(v) for n, v in spec["parameters"].items()}
        point = np.array([_number(p) for p in q["point"]])
        lo = np.array([-math.radians(r["limits"][1]) if r["type"] == "R" else 0.0 for r in spec["joints"]])
        hi = np.array([math.radians(r["limits"][1]) if r["type"] == "R" else 0.5 for r in spec["joints"]])
        if q["answer"]:
            witness = np.array([_number(w) for w in q["witness"]])
            assert (lo - 1e-12 <= witness).all() and (witness <= hi + 1e-12).all(), seed
            assert np.allclose(_fk(spec, witness, lengths)[:3, 3].real, point, atol=1e-12), seed
        else:
            bound = 0.0
            for r in spec["joints"]:
                a = lengths[r["a"]] if isinstance(r["a"], str) else float(r["a"])
                d = 0.5 if r["type"] == "P" else (lengths[r["d"]] if isinstance(r["d"], str) else float(r["d"]))
                bound += math.hypot(a, d)
            assert np.linalg.norm(point) > bound, seed
            ends = np.linalg.norm(_fk(spec, rng.uniform(lo, hi, (2000, len(lo))), lengths)[:, :3, 3].real, axis=1)
            assert ends.max() < np.linalg.norm(point), seed


def _forward(L, theta):
    phi = np.cumsum(theta, axis=-1)
    return np.stack([-(np.sin(phi) * L).sum(-1), (np.cos(phi) * L).sum(-1)], axis=-1)


def _distance(L, lo, hi, targets, rng, samples: int = 8000, starts: int = 24):
    """Distance from each target to the workspace, found by sampling (the joint box and its faces) then
    Gauss-Newton from the ``starts``
    nearest samples, with the joints held at a limit that the step pushes against dropped (active set): 0 (to
    1e-12) for a reachable point, an upper bound of the distance otherwise."""
    theta = rng.uniform(lo, hi, (samples, len(L)))
    pick = rng.random(theta.shape)                    # faces of the joint box too: joints at a limit or at 0
    theta = np.where(pick < 0.25, lo, np.where(pick < 0.5, hi, np.where(pick < 0.6, np.clip(0, lo, hi), theta)))
    targets = np.atleast_2d(targets)
    near = np.argsort(((_forward(L, theta)[None] - targets[:, None]) ** 2).sum(-1), axis=1)[:, :starts]
    t = theta[near]                                            # (m, starts, p)
    goal = targets[:, None, :]
    best = np.linalg.norm(_forward(L, t) - goal, axis=-1)
    for _ in range(15):
        phi = np.cumsum(t, axis=-1)
        r = goal - _forward(L, t)
        # d end / d theta_j = sum_{k >= j} L_k (-cos phi_k, -sin phi_k)
        J = np.stack([-np.cumsum((np.cos(phi) * L)[..., ::-1], axis=-1)[..., ::-1],
                      -np.cumsum((np.sin(phi) * L)[..., ::-1], axis=-1)[..., ::-1]], axis=-2)
        free = np.ones_like(t)
        for _ in range(2):
            Jf = J * free[..., None, :]
            JJt = Jf @ np.swapaxes(Jf, -1, -2) + 1e-12 * np.eye(2)
            step = (np.swapaxes(Jf, -1, -2) @ np.linalg.solve(JJt, r[..., None]))[..., 0]
            free = free * ~(((t <= lo) & (step < 0)) | ((t >= hi) & (step > 0)))
        step *= np.minimum(1.0, 0.3 / (np.abs(step).max(axis=-1, keepdims=True) + 1e-300))   # near singular: short
        t = np.clip(t + step, lo, hi)
        best = np.minimum(best, np.linalg.norm(_forward(L, t) - goal, axis=-1))
    return best.min(axis=1)


def _chain(seed):
    entry = _cache()[seed]
    (spec,) = entry["key"]["chains"].values()
    L = np.array([_number(v) for v in spec["lengths"]])
    lo, hi = np.radians(spec["lower"]), np.radians(spec["upper"])
    return L, lo, hi, entry["loops"]


def test_chain_reachability():
    """Chain reachability keys: a witness lies within the limits and its end point (sums of sines and cosines
    here) is the point within 1e-9; an unreachable point is farther than 1e-6 from every end point found by
    sampling and Gauss-Newton."""
    rng = np.random.default_rng(4)
    for seed in SEEDS:
        L, lo, hi, _ = _chain(seed)
        (q,) = _questions(seed, "reachable")[1:]
        point = np.array([_number(p) for p in q["point"]])
        if q["answer"]:
            w = np.array(q["witness"])
            assert (lo - 1e-12 <= w).all() and (w <= hi + 1e-12).all(), seed
            assert np.allclose(_forward(L, w), point, atol=1e-9), seed
        else:
            assert _distance(L, lo, hi, point, rng)[0] > 1e-6, seed


def _winding(loops, points) -> np.ndarray:
    """Winding number of the arcs' loops about each point (polylines with a vertex every 0.05 rad: a point more
    than 0.0004 x radius from every circle is on the same side of the polyline as of the arc)."""
    w = np.zeros(len(points))
    for loop in loops:
        poly = np.concatenate([np.stack([cx + r * np.cos(t), cy + r * np.sin(t)], axis=1)
                               for cx, cy, r, a0, a1, _ in loop
                               for t in [np.linspace(a0, a1, max(2, math.ceil(abs(a1 - a0) / 0.05)),
                                                     endpoint=False)]])
        d = poly[None] - points[:, None]
        angle = np.arctan2(d[..., 1], d[..., 0])
        turn = np.diff(np.concatenate([angle, angle[:, :1]], axis=1), axis=1)
        w += ((turn + np.pi) % (2 * np.pi) - np.pi).sum(axis=1) / (2 * np.pi)
    return np.rint(w)


def test_chain_arc_counts_and_areas():
    """Arc-count keys: each cached boundary arc is made of end points (its midpoint is the end point, summed
    here, of its joint values, which lie within the limits) and lies on the boundary (no configuration is
    found reaching a point just outside it, up to 1e-3 x reach: sampling and Gauss-Newton); consecutive arcs of a
    loop lie on different circles (maximal arcs); every one of 400 sampled end points lies inside the loops
    (winding number); the count is the key's.  Area keys: the area enclosed by the loops (Green's theorem, one
    closed form per arc, written here) lies in the key's bracket, and the cells of a 100 x 100 grid hit by
    sampled end points cover no more than the bracket plus the cells along the boundary."""
    rng = np.random.default_rng(5)
    for seed in SEEDS:
        L, lo, hi, loops = _chain(seed)
        (count,) = _questions(seed, "integer")
        (area,) = _questions(seed, "measure")
        arcs = [a for loop in loops for a in loop]
        assert count["answer"] == len(arcs), seed
        geometry = np.array([a[:3] for a in arcs])
        outer, eps = [], []
        for k, (cx, cy, r, a0, a1, middle) in enumerate(arcs):
            mid = 0.5 * (a0 + a1)
            radial = np.array([math.cos(mid), math.sin(mid)])
            m = np.array([cx, cy]) + r * radial
            assert (lo - 1e-12 <= middle).all() and (middle <= hi + 1e-12).all(), seed
            assert np.allclose(_forward(L, np.array(middle)), m, atol=1e-9), seed
            # the probe stays nearer this arc than any other circle of the boundary (thin gaps)
            others = np.abs(np.linalg.norm(m - geometry[:, :2], axis=1) - geometry[:, 2])
            eps.append(float(np.clip(0.3 * np.delete(others, k).min(initial=1.0), 1e-7, 1e-3) * L.sum()))
            outer.append(m - eps[-1] * (-radial if a1 > a0 else radial))  # the workspace is on the left of travel
        far = _distance(L, lo, hi, np.array(outer), rng, samples=4000, starts=12)
        assert (far > 0.2 * np.array(eps)).all(), (seed, far, eps)
        for loop in loops:
            for a, b in zip(loop, loop[1:] + loop[:1]):
                if len(loop) > 1:
                    assert abs(a[2] - b[2]) > 1e-9 or math.dist(a[:2], b[:2]) > 1e-9, seed
        ends = _forward(L, rng.uniform(lo, hi, (400, len(L))))
        gap = np.abs(np.linalg.norm(ends[:, None] - geometry[None, :, :2], axis=2) - geometry[None, :, 2])
        clear = (gap > 2e-3 * L.sum()).all(axis=1)
        assert (_winding(loops, ends[clear]) != 0).all(), seed
        green = 0.5 * sum(r * r * (a1 - a0) + r * cx * (math.sin(a1) - math.sin(a0))
                          - r * cy * (math.cos(a1) - math.cos(a0)) for cx, cy, r, a0, a1, _ in arcs)
        lo_area, hi_area = area["answer"]
        assert lo_area - 1e-9 <= green <= hi_area + 1e-9, (seed, green, area["answer"])
        ends = _forward(L, rng.uniform(lo, hi, (20_000, len(L))))
        box_lo, box_hi = ends.min(axis=0), ends.max(axis=0)
        cells = 100
        size = (box_hi - box_lo) / cells + 1e-12
        index = np.minimum(((ends - box_lo) / size).astype(int), cells - 1)
        hit = np.count_nonzero(np.bincount(index[:, 0] * cells + index[:, 1], minlength=cells * cells))
        perimeter = sum(r * abs(a1 - a0) for _, _, r, a0, a1, _ in arcs)
        assert hit * size[0] * size[1] <= hi_area + 2 * perimeter * math.hypot(*size), seed


def test_issue_seed_7():
    """The sheet of the issue (seed 7, 4 problems, 3 joints): its factor question is answerable now: the
    determinant is not identically zero (numpy FK) and '0' is not the answer."""
    from workspace_sym.exercises import make_exercises
    from workspace_sym.grading import AnswerKey

    _, _, key = make_exercises(seed=7, count=4, max_joints=3)
    parsed = AnswerKey.from_dict(key)
    rng = np.random.default_rng(7)
    for q in (q for q in key["questions"] if q["kind"] == "factors"):
        spec = key["robots"][q["robot"]]
        joints, lengths, _ = _random_point(spec, rng)
        assert abs(np.linalg.det(_jacobian(spec, joints, lengths)[:3])) > 1e-9
        assert parsed.grade(q["id"], ", ".join(q["answer"])).ok is True
        assert parsed.grade(q["id"], "0").ok is False


def _write_cache() -> None:  # pragma: no cover - run by hand when the generator changes
    data = {"options": OPTIONS, "seeds": {str(s): _entry(s) for s in SEEDS}}
    with open(CACHE, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0) as f:
        f.write(json.dumps(data, separators=(",", ":"), sort_keys=True).encode())


if __name__ == "__main__":  # pragma: no cover
    _write_cache()
    sys.exit(0)


def test_a_reachable_key_is_reached_within_every_limit():
    """A key's "reachable" is a certificate: its witness configuration must lie within the joint limits and put
    the end effector exactly at the point (the docstring review found prismatic values drawn from 0 to 1/2
    whatever the limits: on the catalog SCARA, d3 limited to [0, 0.21], 7 of 40 seeds gave d3 = 3/10 or 1/2).
    Reference: the limits and the robot's own exact position, for every seed that draws a reachable point, on a
    SCARA, an arm whose joint range holds no multiple of 30 deg, and an arm with an unlimited joint."""
    import numpy as np
    import sympy as sp

    from workspace_sym import robots
    from workspace_sym.kinematics import DHJoint, DHRobot
    from workspace_sym.teaching.exercises import exact_parameters, reachability_point

    narrow = DHRobot([DHJoint.revolute(1, a=1, limits=(sp.pi / 36, sp.pi / 9)),      # 5 to 20 deg: no 30 deg step
                      DHJoint.prismatic(2, alpha=sp.pi / 2, limits=(sp.Rational(1, 20), sp.Rational(2, 25))),
                      DHJoint.revolute(3, a=sp.Rational(1, 2))], name="narrow")     # unlimited
    for robot in (robots.build("scara"), narrow):
        reached = 0
        for seed in range(40):
            point, reachable, _, witness = reachability_point(robot, np.random.default_rng(seed))
            if not reachable:
                continue
            reached += 1
            config = {j.variable: sp.sympify(w) for j, w in zip(robot.joints, witness)}
            for j in robot.joints:
                if j.limits is not None:
                    lo, hi = j.limits
                    assert bool(lo <= config[j.variable] <= hi), (robot.name, seed, j.variable, config[j.variable])
            exact = robot.position.subs(exact_parameters(robot)).subs(config)
            assert all(sp.simplify(sp.expand(exact[i]) - point[i]) == 0 for i in range(3)), (robot.name, seed)
        assert reached >= 10
