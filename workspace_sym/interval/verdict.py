"""One encoding of a box's verdict, shared by every decider: an ``int8`` code a box.

``INSIDE`` (1) and ``OUTSIDE`` (-1) are proved statements about the whole box
(outward-rounded interval arithmetic); ``UNDECIDED`` (0) is everything else,
including a box that two tests would claim both ways (a contradiction is doubt,
never a verdict).  A :class:`Decider` maps an ``(N, n, 2)`` array of boxes to
``N`` codes; :func:`codes_from_masks` is the one place where masks of proofs
become codes.  :class:`~workspace_sym.interval.paving.Certificate` is the same
code as an enum, for one box.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

__all__ = ["CODE", "INSIDE", "OUTSIDE", "UNDECIDED", "VERDICTS", "Decider", "codes_from_masks"]

CODE = np.int8
INSIDE, OUTSIDE, UNDECIDED = 1, -1, 0
VERDICTS = (INSIDE, OUTSIDE, UNDECIDED)


@runtime_checkable
class Decider(Protocol):
    """Boxes in, verdicts out: ``decide(boxes)`` with ``boxes`` an ``(N, n, 2)`` float array returns ``N``
    codes (:data:`INSIDE`, :data:`OUTSIDE`, :data:`UNDECIDED`).  Each box is decided on its own, so any
    batching of the boxes gives the same codes; a decider sent to other processes must pickle.

    Any callable of that shape is a decider (``isinstance(f, Decider)`` checks only that it is callable); the
    protocol itself is never instantiated.

    Parameters
    ----------
    *args, **kwargs
        Not taken: calling ``Decider(...)`` raises ``TypeError`` (a protocol cannot be instantiated).
    """

    def __call__(self, boxes: np.ndarray, /) -> np.ndarray: ...


def codes_from_masks(inside, outside) -> np.ndarray:
    """``int8`` codes from a mask of boxes proved inside and one of boxes proved outside.

    A box in both masks gets :data:`UNDECIDED`: two proofs that contradict
    each other prove nothing.

    Parameters
    ----------
    inside : array_like of bool
        True where the box is proved inside.
    outside : array_like of bool
        True where the box is proved outside; broadcast against ``inside`` when the shapes differ.

    Returns
    -------
    numpy.ndarray of int8
        One code a box: :data:`INSIDE`, :data:`OUTSIDE` or :data:`UNDECIDED`.

    Examples
    --------
    >>> codes_from_masks([True, False, False, True], [False, True, False, True])
    array([ 1, -1,  0,  0], dtype=int8)
    """
    inside, outside = np.asarray(inside, dtype=bool), np.asarray(outside, dtype=bool)
    if inside.shape != outside.shape:
        inside, outside = np.broadcast_arrays(inside, outside)
    codes = inside.astype(CODE)       # 1 inside, then minus 1 outside: both is 0
    codes -= outside
    return codes
