"""DH tables and an independent reference for their kinematics, shared by the kinematics tests.

The reference multiplies the DH matrices of each row in plain numpy (docs/methods.md section 1), sharing no code
with the package's symbolic or numeric kinematics; ``tables`` draws random tables for the property tests and
``GENERIC_6`` is the generic six-joint table of issue 29."""

import numpy as np
import sympy as sp
from hypothesis.strategies import composite, integers, sampled_from


def dh_numpy(theta, d, a, alpha):
    """Independent plain-numpy standard DH matrix (docs/methods.md section 1)."""
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct],
                     [st, ct * ca, -ct * sa, a * st],
                     [0, sa, ca, d],
                     [0, 0, 0, 1.0]])


def dh_numpy_modified(theta, d, a_prev, alpha_prev):
    """Independent plain-numpy modified (Craig) DH matrix."""
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha_prev), np.sin(alpha_prev)
    return np.array([[ct, -st, 0, a_prev],
                     [st * ca, ct * ca, -sa, -sa * d],
                     [st * sa, ct * sa, ca, ca * d],
                     [0, 0, 0, 1.0]])


def fk_numpy(robot, q):
    """Product of numeric DH matrices, built from the table rows only (no symbolic FK)."""
    T = np.eye(4)
    subs = {k: float(v) for k, v in robot.parameters.items()}
    for joint, qk in zip(robot.joints, q):
        vals = {joint.variable: qk, **{sp.Symbol(str(k)): v for k, v in subs.items()}}
        row = [float(sp.sympify(e).subs(vals)) for e in (joint.theta, joint.d, joint.a, joint.alpha)]
        T = T @ (dh_numpy(*row) if robot.convention == "standard" else dh_numpy_modified(*row))
    return T


def fk_numpy_with_tool(robot, q):
    """The plain numpy DH product followed by the robot's tool transform."""
    T = fk_numpy(robot, q)
    return T if robot.tool is None else T @ np.array(robot.tool.evalf(), dtype=float)


def dummies(obj) -> set:
    """Every placeholder symbol in a result (expressions, matrices, polynomials, lists of pairs)."""
    if isinstance(obj, (list, tuple)):
        return set().union(*(dummies(o) for o in obj)) if obj else set()
    if isinstance(obj, sp.Poly):
        return dummies(obj.all_coeffs())
    return sp.sympify(obj).atoms(sp.Dummy)


# A generic 6-joint table of the kind: R and P joints, offsets and twists in whole degrees that are
# multiples of neither 15 nor 18, decimal lengths, a tool turned by whole degrees.
GENERIC_6 = {"joints": [{"type": "R", "theta": 97, "alpha": -41, "a": 0.3, "d": 0.4},
                        {"type": "R", "theta": -25, "alpha": 73, "a": 0.25, "d": 0.1},
                        {"type": "P", "theta": 11, "alpha": -60, "a": 0.425, "d": 0.0},
                        {"type": "R", "theta": 0, "alpha": 135, "a": 0.1, "d": 0.39225},
                        {"type": "R", "theta": 33, "alpha": 17, "a": 0.05, "d": 0.2},
                        {"type": "R", "theta": 0, "alpha": -105, "a": 0.0, "d": 0.0823}],
             "tool": {"xyz": [0.0, 0.0, 0.1], "rpy": [-31, 7, -78]}}


@composite
def tables(draw, n_max=3, tool=False):
    """A random DH table as ``DHRobot.from_dict`` reads it: 2 to ``n_max`` joints, R and P, twists and offsets in
    whole degrees, lengths among values of real arms; with ``tool``, a tool turned by whole degrees."""
    n = draw(integers(2, n_max))
    joints = []
    for i in range(n):
        kind = draw(sampled_from("RRP")) if i else "R"
        joints.append({"type": kind, "theta": draw(integers(-179, 180)), "alpha": draw(integers(-179, 180)),
                       "a": draw(sampled_from([0.0, 0.1, 0.25, 0.425, 0.5, 1.0])),
                       "d": draw(sampled_from([0.0, 0.05, 0.2, 0.39225]))})
    data = {"joints": joints}
    if tool:
        data["tool"] = {"xyz": [0.1, 0.0, 0.05], "rpy": [draw(integers(-90, 90)) for _ in range(3)]}
    return data


def unshorthand(expr, q):
    """A printed textbook expression read back: ``c23`` -> ``cos(q2 + q3)``, ``s1`` -> ``sin(q1)``, and each
    decimal to the exact fraction it prints (``0.425`` -> ``17/40``); ``q`` the joint variables, from joint 1."""
    import re

    expr = sp.nsimplify(expr, rational=True)
    subs = {}
    for s in expr.free_symbols:
        m = re.fullmatch(r"([cs])(\d+)", s.name)
        if m:
            subs[s] = (sp.cos if m.group(1) == "c" else sp.sin)(sum(q[int(k) - 1] for k in m.group(2)))
    return expr.xreplace(subs)
