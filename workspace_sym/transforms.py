"""Homogeneous transforms as exact SymPy matrices: rotations, translations, URDF origins, products, inverses.

The pieces every DH row, base, tool and file origin is made of (:mod:`workspace_sym.kinematics` multiplies
them; the readers and the reach sections use them too).

>>> translation(z=1) * rot_z(sp.pi / 2) == xyz_rpy((0, 0, 1), (0, 0, sp.pi / 2))
True
>>> inverse_transform(translation(x=2) * rot_x(sp.pi)) * translation(x=2) * rot_x(sp.pi) == sp.eye(4)
True
"""

from __future__ import annotations

import sympy as sp

__all__ = ["rot_x", "rot_y", "rot_z", "translation", "xyz_rpy", "matrix_product", "inverse_transform"]


def rot_z(t, trig=None) -> sp.Matrix:
    """Rotation by ``t`` about z (``trig``: its cosine and sine when already known).

    Parameters
    ----------
    t : SymPy expression or number
        The angle, in radians.
    trig : pair of SymPy expressions, optional
        ``(cos(t), sin(t))`` when already known (written into the matrix as given); None (the default) computes
        them.

    Returns
    -------
    sympy.Matrix
        The 4x4 homogeneous transform.
    """
    c, s = trig or (sp.cos(t), sp.sin(t))
    return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def rot_x(t, trig=None) -> sp.Matrix:
    """Rotation by ``t`` about x (``trig``: its cosine and sine when already known).

    Parameters
    ----------
    t : SymPy expression or number
        The angle, in radians.
    trig : pair of SymPy expressions, optional
        ``(cos(t), sin(t))`` when already known (written into the matrix as given); None (the default) computes
        them.

    Returns
    -------
    sympy.Matrix
        The 4x4 homogeneous transform.
    """
    c, s = trig or (sp.cos(t), sp.sin(t))
    return sp.Matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def rot_y(t) -> sp.Matrix:
    """Rotation by ``t`` about y.

    Parameters
    ----------
    t : SymPy expression or number
        The angle, in radians.

    Returns
    -------
    sympy.Matrix
        The 4x4 homogeneous transform.
    """
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]])


def translation(x=0, y=0, z=0) -> sp.Matrix:
    """Translation by ``(x, y, z)``.

    Parameters
    ----------
    x, y, z : SymPy expression or number, optional
        The offsets along each axis (default 0), in the model's length unit.

    Returns
    -------
    sympy.Matrix
        The 4x4 homogeneous transform.
    """
    return sp.Matrix([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]])


def xyz_rpy(xyz, rpy) -> sp.Matrix:
    """The homogeneous transform ``Trans(xyz) Rz(yaw) Ry(pitch) Rx(roll)`` of a URDF origin (``rpy`` in radians).

    Parameters
    ----------
    xyz : three SymPy expressions or numbers
        The translation ``(x, y, z)``.
    rpy : three SymPy expressions or numbers
        Roll, pitch and yaw, in radians: rotations about the fixed x, y and z axes, in that order.

    Returns
    -------
    sympy.Matrix
        The 4x4 homogeneous transform.
    """
    (x, y, z), (r, p, w) = xyz, rpy
    return translation(x, y, z) * rot_z(w) * rot_y(p) * rot_x(r)


def matrix_product(A: sp.Matrix, B: sp.Matrix) -> sp.Matrix:
    """``A * B`` with each entry one SymPy sum of its products: the same expressions as SymPy's product, which
    adds the products one at a time (a quarter of a 6-joint table's fk went into those partial sums).

    Parameters
    ----------
    A, B : sympy.Matrix
        The factors; ``A.cols`` must equal ``B.rows`` (not checked).

    Returns
    -------
    sympy.Matrix
        The ``A.rows`` by ``B.cols`` product; products with a zero factor are left out of each sum.
    """
    return sp.Matrix(A.rows, B.cols, lambda i, j: sp.Add(*(A[i, k] * B[k, j] for k in range(A.cols)
                                                           if A[i, k] != 0 and B[k, j] != 0)))


def inverse_transform(A: sp.Matrix) -> sp.Matrix:
    """The inverse ``[R^T, -R^T p; 0, 1]`` of a homogeneous transform.

    Parameters
    ----------
    A : sympy.Matrix
        A 4x4 homogeneous transform ``[R, p; 0, 1]``; ``R`` is taken to be a rotation (its transpose is used as
        its inverse, not checked).

    Returns
    -------
    sympy.Matrix
        The 4x4 inverse transform.
    """
    Rt = A[:3, :3].T
    return sp.Matrix.vstack(sp.Matrix.hstack(Rt, -matrix_product(Rt, A[:3, 3])), sp.Matrix([[0, 0, 0, 1]]))
