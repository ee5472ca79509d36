"""The budgeted box search shared by the Orthoglide cube certificates and the planar interval exclusion."""

import numpy as np
import pytest

from workspace_sym import InvalidParameterError, WorkspaceError
from workspace_sym.interval.search import prove_all, split_every_axis, split_widest

UNIT = np.array([[[0.0, 1.0], [0.0, 1.0]]])


def test_children_tile_their_parent():
    for split, count in ((split_widest, 2), (split_every_axis, 4)):
        kids = split(UNIT)
        assert len(kids) == count
        assert np.prod(kids[:, :, 1] - kids[:, :, 0], axis=1).sum() == 1.0
        assert (kids[:, :, 0] >= 0).all() and (kids[:, :, 1] <= 1).all()


def test_an_undecided_box_is_never_a_verdict():
    """Budget and width limits give None, never True: only the test proves."""

    def never(b):
        return np.zeros(len(b), int)

    def fine(b):
        """Proves only boxes narrower than 0.3: True at the third generation of halving every edge."""
        return np.where((b[:, :, 1] - b[:, :, 0]).max(1) < 0.3, 1, 0)

    assert prove_all(UNIT, never, max_boxes=100)[0] is None
    assert prove_all(UNIT, never, max_boxes=10**6, min_width=0.1)[0] is None
    assert prove_all(UNIT, fine, max_boxes=100, split="every") == (True, 1 + 4 + 16)
    assert prove_all(UNIT, lambda b: np.where(b[:, 0, 0] > 0.9, -1, 0), max_boxes=1000)[0] is False


def test_bad_options_name_the_parameter():
    with pytest.raises(WorkspaceError, match="split must be one of 'widest', 'every', 'given'; got 'thirds'"):
        prove_all(UNIT, lambda b: np.ones(len(b)), max_boxes=10, split="thirds")
    with pytest.raises(InvalidParameterError, match="max_boxes must be at least 1; got 0"):
        prove_all(UNIT, lambda b: np.ones(len(b)), max_boxes=0)
