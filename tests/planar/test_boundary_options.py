"""The boundary takes the package's one options spelling (issue 38 item 3): ``proof_boxes`` for each face's
interval exclusion, ``stop=StopAt(max_boxes=, time_limit=)`` over all of them, ``run=RunOn(progress=)`` for its
stages; the earlier ``max_boxes=`` and ``progress=`` still work with a DeprecationWarning naming the new spelling.

Reference: the p = 6 chain of Bastien (2018), figure 6, whose hole is proved outside by interval exclusion in
2,493 boxes (measured here by the exclusion itself): a budget above that proves it, one below does not, whichever
budget it is.  Where the exclusion is cut short the boundary's loops stay the same (the hole is decided by the
argument through joints 2..p, a second method), so the area does not change."""

import warnings

import numpy as np
import pytest

from workspace_sym import InvalidParameterError, RunOn, StopAt
from workspace_sym.planar import PlanarChain
from workspace_sym.planar.boundary import _exclusion

P6 = ([0.20, 0.20, 0.15, 0.35, 0.20, 0.20], [-120, -120, -30, -90, -45, -23], [60, 170, 30, 91, 23, 24])


def _chain():
    return PlanarChain(*P6)


def _methods(boundary):
    return sorted(e["method"] for e in boundary.evidence.values())


@pytest.fixture(scope="module")
def hole():
    """The boxes the hole's exclusion takes, from the exclusion itself, and the full boundary."""
    b = _chain().boundary()
    (point,) = [e["point"] for e in b.evidence.values() if e["method"] == "interval exclusion"]
    proved, used = _exclusion(_chain(), np.array(point), 10_000)
    assert proved is True and 100 < used < 10_000
    return used, b


def test_each_budget_cuts_the_hole_s_proof_where_it_says(hole):
    used, full = hole
    for options in ({"proof_boxes": used - 1}, {"stop": StopAt(max_boxes=used - 1)}):
        cut = _chain().boundary(**options)
        assert "interval exclusion" not in _methods(cut), options
        assert cut.area == pytest.approx(full.area, abs=1e-12)
    for options in ({"proof_boxes": used}, {"stop": StopAt(max_boxes=used)}):
        assert "interval exclusion" in _methods(_chain().boundary(**options)), options


def test_a_time_limit_already_spent_proves_nothing_by_exclusion_and_is_not_kept():
    chain = _chain()
    cut = chain.boundary(stop=StopAt(time_limit=1e-9))
    assert "interval exclusion" not in _methods(cut)
    assert chain.boundary() is not cut and "interval exclusion" in _methods(chain.boundary())
    assert chain.boundary() is chain.boundary()                       # kept when the budget is boxes only


def test_the_earlier_keywords_warn_and_give_the_same_boundary(hole):
    used, full = hole
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        old = _chain().boundary(max_boxes=4000, progress=False)
    messages = sorted(str(w.message) for w in caught if w.category is DeprecationWarning)
    assert messages == ["boundary: max_boxes= is deprecated; pass proof_boxes=... (each face's proof; "
                        "stop=StopAt(max_boxes=...) bounds them all)",
                        "boundary: progress= is deprecated; pass run=RunOn(progress=...)"]
    assert all(w.filename == __file__ for w in caught)                # the warnings point at the caller's line
    new = _chain().boundary(proof_boxes=4000, run=RunOn(progress=False))
    assert _methods(old) == _methods(new) == _methods(full) and old.area == new.area == full.area


@pytest.mark.parametrize(("options", "needle"), [
    ({"proof_boxes": 0}, "proof_boxes must be a positive integer; got 0"),
    ({"proof_boxes": 2.5}, "proof_boxes must be a positive integer; got 2.5"),
    ({"stop": StopAt(section_boxes=10)}, "stop: build_boundary stops on the boxes and seconds of its proofs; "
                                         "section_boxes does not apply"),
    ({"run": RunOn(chunk=10)}, "run: build_boundary runs in this process and keeps no boxes"),
    ({"stop": 5}, "stop must be a StopAt; got int"),
])
def test_options_that_do_not_apply_are_refused_by_name(options, needle):
    with pytest.raises(InvalidParameterError, match=needle.replace("(", r"\(").replace(")", r"\)")) as info:
        _chain().boundary(**options)
    assert info.value.parameter in ("proof_boxes", "stop", "run")
