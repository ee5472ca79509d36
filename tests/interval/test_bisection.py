"""Bisection helpers of the paving loop (issue 28 item 3: rewritten without gathers and row reductions).

Reference: a plain Python loop over the boxes, one box at a time (the definition: split the first longest edge at
``0.5 lo + 0.5 hi`` unless that is not strictly inside it; the size is the largest edge or the Euclidean norm
of the edges, summed as numpy sums one box's squared edges).
"""

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from workspace_sym.interval.paving import Box, box_sizes, halves, initial_boxes

_BOUND = st.one_of(st.floats(-1e6, 1e6, allow_nan=False, allow_subnormal=True), st.sampled_from([0.0, 1.0, -1.0]))


@st.composite
def box_arrays(draw):
    n = draw(st.integers(1, 9))
    count = draw(st.integers(0, 12))
    lows = draw(hnp.arrays(float, (count, n), elements=_BOUND))
    kind = draw(st.sampled_from(["random", "float-thin", "ties"]))
    if kind == "random":
        highs = lows + draw(hnp.arrays(float, (count, n), elements=st.floats(0, 1e3)))
    elif kind == "float-thin":                   # one float wide or degenerate: cannot be split
        highs = np.nextafter(lows, np.inf) if draw(st.booleans()) else lows.copy()
    else:                                        # equal edges: the first one is split
        highs = lows + 1.0
    return np.stack([lows, np.maximum(highs, lows)], axis=2)


def _reference(box):
    widths = [hi - lo for lo, hi in box]
    k = widths.index(max(widths))
    lo, hi = box[k]
    mid = 0.5 * lo + 0.5 * hi
    ok = lo < mid < hi
    first, second = box.copy(), box.copy()
    if ok:
        first[k, 1] = mid
        second[k, 0] = mid
    return first, second, ok, max(widths), math.sqrt(float(np.sum(np.square(widths))))


@settings(derandomize=True, max_examples=200, deadline=None)
@given(box_arrays())
@example(np.array([[[0.0, 5e-324], [0.0, 0.0]]]))
@example(np.array([[[1.0, 1.0000000000000002], [-3.0, -2.0]], [[0.0, 2.0], [0.0, 2.0]]]))
def test_halves_and_sizes_match_the_box_by_box_definition(boxes):
    children, ok = halves(boxes)
    assert children.shape == (2 * len(boxes), *boxes.shape[1:]) and ok.shape == (len(boxes),)
    widths, diameters = box_sizes(boxes, "width"), box_sizes(boxes, "diameter")
    for i, box in enumerate(boxes):
        first, second, split, size_w, size_d = _reference(box)
        assert bool(ok[i]) == split
        assert np.array_equal(children[2 * i], first) and np.array_equal(children[2 * i + 1], second)
        assert widths[i] == size_w and diameters[i] == size_d


@settings(derandomize=True, max_examples=50, deadline=None)
@given(box_arrays(), st.data())
def test_halves_along_a_given_axis(boxes, data):
    """Callers (orientation, image) choose the axis: the edge split is that one, whatever the widths."""
    axis = np.array(data.draw(st.lists(st.integers(0, boxes.shape[1] - 1), min_size=len(boxes),
                                       max_size=len(boxes))), dtype=np.intp)
    children, ok = halves(boxes, axis)
    for i, (box, k) in enumerate(zip(boxes, axis)):
        lo, hi = box[k]
        mid = 0.5 * lo + 0.5 * hi
        assert bool(ok[i]) == (lo < mid < hi)
        expected = box.copy()
        if ok[i]:
            expected[k, 1] = mid
        assert np.array_equal(children[2 * i], expected)


def test_initial_boxes_are_a_fresh_array_each_call():
    """The presplit is cached; a caller that writes into its boxes must not change the next run's."""
    box = Box.from_bounds({"x": (-12, 17), "y": (0, 12)})
    first = initial_boxes(box, 0.07, "width", 512)
    reference = first.copy()
    first[:] = 0.0
    again = initial_boxes(box, 0.07, "width", 512)
    assert np.array_equal(again, reference) and len(again) == 512
    assert np.isclose(np.prod(again[:, :, 1] - again[:, :, 0], axis=1).sum(), 29 * 12)
