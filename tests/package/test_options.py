"""One options spelling (issue 38 item 3): ``stop=StopAt(...)`` says when a run stops, ``run=RunOn(...)`` where and
how it runs (its progress bar included), ``tuning=Tuning(...)`` how much work reach's stages may do; the keywords of
earlier releases still work for one release, each with a DeprecationWarning naming its new spelling.

References: the same call spelt the new way (the boxes, counts and brackets must be equal), and the text of the
warnings (what a user reads)."""

from __future__ import annotations

import warnings

import pytest
import sympy as sp

import workspace_sym as ws
from workspace_sym import RunOn, StopAt
from workspace_sym.interval.driver import RunBudget
from workspace_sym.kinematics import DHJoint, DHRobot
from workspace_sym.serial import Pose, Tuning, reach

ARM = DHRobot([DHJoint.revolute(1, a=1), DHJoint.revolute(2, a=sp.Rational(1, 2))], name="2R")


def _same(a, b):
    assert a.counts == b.counts and a.measure_bounds == b.measure_bounds and a.method == b.method


def test_the_readme_spelling_of_earlier_releases_still_runs_with_a_warning():
    """``reach(robot, delta=0.1, time_limit=60, progress=False)`` raised TypeError (issue 38): it runs again, and
    each old keyword names its replacement."""
    with pytest.warns(DeprecationWarning) as caught:
        old = reach(ARM, delta=0.1, time_limit=60, progress=False)
    messages = {str(w.message) for w in caught}
    assert messages == {"reach: time_limit= is deprecated; pass stop=StopAt(time_limit=...)",
                        "reach: progress= is deprecated; pass run=RunOn(progress=...)"}
    _same(old, reach(ARM, delta=0.1, stop=StopAt(time_limit=60), run=RunOn(progress=False)))


@pytest.mark.parametrize("old, new", [
    (dict(max_boxes=50), dict(stop=StopAt(max_boxes=50))),
    (dict(max_pairs=5_000, inner_depth=1, method="pairs"), dict(tuning=Tuning(max_pairs=5_000, inner_depth=1),
                                                               method="pairs")),
    (dict(chunk=500, method="pairs"), dict(run=RunOn(chunk=500), method="pairs")),
])
def test_old_keywords_give_the_boxes_of_the_new_spelling(old, new):
    """Each old keyword warns and gives the counts and bounds of its new spelling.  delta=0.3 (0.2 before: the
    chunk= case took 3 s a call) still leaves the 2R with inner, boundary and outer boxes to compare, and the
    max_boxes=50 budget still stops both runs with boxes pending."""
    with pytest.warns(DeprecationWarning, match="is deprecated; pass"):
        before = reach(ARM, delta=0.3, **old)
    _same(before, reach(ARM, delta=0.3, **new))


def test_the_tool_constraint_keywords_become_a_pose():
    puma = ws.robots.build("puma560")
    with pytest.warns(DeprecationWarning) as caught:
        old = reach(puma, delta=0.5, approach=(0, 0, -1), cone=20)
    assert {str(w.message) for w in caught} == {"reach: approach= is deprecated; pass pose=Pose(approach=...)",
                                                "reach: cone= is deprecated; pass pose=Pose(cone=...)"}
    new = reach(puma, delta=0.5, pose=Pose(approach=(0, 0, -1), cone=20))
    _same(old, new)
    assert old.constraint == new.constraint and old.method == "section"


def test_an_unknown_keyword_is_a_type_error_as_python_says_it():
    with pytest.raises(TypeError, match="reach\\(\\) got an unexpected keyword argument 'tolerance'"):
        reach(ARM, delta=0.1, tolerance=3)


def test_progress_is_how_a_run_is_shown_not_when_it_stops():
    """``RunOn(progress=)`` drives the bar; ``StopAt(progress=)`` (its earlier place) still does, with a warning."""
    assert RunBudget(StopAt(), "t", False).showing is False and RunBudget(StopAt(), "t", True).showing is True
    with pytest.warns(DeprecationWarning, match=r"StopAt\(progress=...\) is deprecated; pass run=RunOn\(progress="):
        old = StopAt(progress=True)
    assert RunBudget(old, "t").showing is True
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # the new spelling warns about nothing
        StopAt(max_boxes=3, time_limit=1.0)
        RunOn(progress=False, chunk=10)


def test_tuning_is_checked_and_named_in_its_errors():
    with pytest.raises(ws.errors.InvalidParameterError, match="inner_depth must be a whole number, 0 or more") as e:
        Tuning(inner_depth=-1)
    assert e.value.parameter == "inner_depth"
    with pytest.raises(ws.errors.InvalidParameterError, match=r"tuning must be a serial\.Tuning"):
        reach(ARM, delta=0.1, tuning={"inner_depth": 1})
