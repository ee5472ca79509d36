"""The budgeted box search shared by the Orthoglide cube certificates and the planar interval exclusion."""

import numpy as np
import pytest

from workspace_sym import InvalidParameterError, RunOn, StopAt, WorkspaceError
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

    assert prove_all(UNIT, never, stop=StopAt(max_boxes=100))[0] is None
    assert prove_all(UNIT, never, stop=StopAt(max_boxes=10**6), min_width=0.1)[0] is None
    assert prove_all(UNIT, never, min_width=0.1)[0] is None                  # the width alone bounds it
    assert prove_all(UNIT, never, stop=StopAt(time_limit=1e-9))[0] is None   # so does a time limit
    assert prove_all(UNIT, fine, stop=StopAt(max_boxes=100), split="every") == (True, 1 + 4 + 16)
    assert prove_all(UNIT, lambda b: np.where(b[:, 0, 0] > 0.9, -1, 0), stop=StopAt(max_boxes=1000))[0] is False


def test_used_counts_the_boxes_the_test_saw():
    """``used`` is the number of boxes handed to the test, also when the box budget stops the search (it once
    counted the generation that was refused, never evaluated).  Reference: a test that counts its own calls."""
    seen = []

    def never(b):
        seen.append(len(b))
        return np.zeros(len(b), int)

    for budget in (1, 2, 10, 100):
        seen.clear()
        verdict, used = prove_all(UNIT, never, stop=StopAt(max_boxes=budget), split="every")
        assert verdict is None and used == sum(seen) <= budget


def test_bad_options_name_the_parameter():
    with pytest.raises(WorkspaceError, match="split must be one of 'widest', 'every', 'given'; got 'thirds'"):
        prove_all(UNIT, lambda b: np.ones(len(b)), stop=StopAt(max_boxes=10), split="thirds")
    with pytest.raises(InvalidParameterError, match="max_boxes must be at least 1; got 0"):
        prove_all(UNIT, lambda b: np.ones(len(b)), stop=StopAt(max_boxes=0))
    with pytest.raises(InvalidParameterError, match="stop: prove_all needs a bound") as caught:
        prove_all(UNIT, lambda b: np.ones(len(b)))       # nothing would stop a search that never decides
    assert caught.value.parameter == "stop"
    with pytest.raises(InvalidParameterError, match="run: prove_all keeps no boxes") as caught:
        prove_all(UNIT, lambda b: np.ones(len(b)), stop=StopAt(max_boxes=10), run=RunOn(resume="x.npz"))
    assert caught.value.parameter == "run"


def test_old_keywords_warn_and_give_the_same_search():
    """Issue 26: executor= (documented in docs/distributed.md) still works, with a DeprecationWarning naming
    run=RunOn(executor=...); the verdict and count are those of the new spelling (a second call as reference)."""
    from concurrent.futures import ThreadPoolExecutor

    def fine(b):
        return np.where((b[:, :, 1] - b[:, :, 0]).max(1) < 0.3, 1, 0)

    with ThreadPoolExecutor(2) as pool:
        new = prove_all(UNIT, fine, stop=StopAt(max_boxes=100), split="every", run=RunOn(executor=pool))
        with pytest.warns(DeprecationWarning, match=r"executor= is deprecated; pass run=RunOn\(executor=\.\.\.\)"):
            old = prove_all(UNIT, fine, stop=StopAt(max_boxes=100), split="every", executor=pool)
        with pytest.raises(InvalidParameterError, match="two executors"), pytest.warns(DeprecationWarning):
            prove_all(UNIT, fine, stop=StopAt(max_boxes=100), executor=pool, run=RunOn(executor=object()))
    assert old == new == (True, 1 + 4 + 16)
