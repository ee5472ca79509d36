"""One verdict code for every decider (issue 26 item 1): int8, INSIDE 1, OUTSIDE -1, UNDECIDED 0.

References: an elementwise definition of the code through :class:`Certificate` (property over random masks),
and the mpmath backend as an independent second decider of the same constraints (never the opposite verdict).
"""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from workspace_sym.interval import Certificate, certify_box
from workspace_sym.interval.paving import _decider, _setup
from workspace_sym.interval.verdict import CODE, INSIDE, OUTSIDE, UNDECIDED, VERDICTS, Decider, codes_from_masks
from workspace_sym.orthoglide.certificate import box_module

DISK = (["x**2 + y**2 <= 1"], {"x": (-1.5, 1.5), "y": (-1.5, 1.5)})


@settings(derandomize=True, max_examples=200, deadline=None)
@given(st.integers(0, 40).flatmap(lambda n: st.tuples(hnp.arrays(bool, n), hnp.arrays(bool, n))))
def test_codes_from_masks_is_the_certificate_of_each_box(masks):
    inside, outside = masks
    codes = codes_from_masks(inside, outside)
    assert codes.dtype == CODE == np.int8 and codes.shape == inside.shape
    for i, o, c in zip(inside, outside, codes):
        expected = Certificate.IN if i and not o else Certificate.OUT if o and not i else Certificate.UNDECIDED
        assert Certificate(int(c)) is expected                  # both proofs at once is a contradiction: doubt


def test_the_certificate_is_the_code():
    assert (Certificate.IN.value, Certificate.OUT.value, Certificate.UNDECIDED.value) == (INSIDE, OUTSIDE, UNDECIDED)
    assert set(VERDICTS) == {1, -1, 0}


def _boxes(rng, n, dim, scale):
    lo = rng.uniform(-1.3, 1.3, (n, dim))
    return np.stack([lo, lo + rng.uniform(0, scale, (n, dim))], axis=2)


def test_the_paving_deciders_speak_the_code_and_never_contradict_each_other():
    cons, box = _setup(*DISK, None)
    numeric, reference = _decider(cons, box.variables, "numpy", 30), _decider(cons, box.variables, "mpmath", 30)
    assert isinstance(numeric, Decider) and isinstance(reference, Decider)
    boxes = _boxes(np.random.default_rng(26), 400, 2, 0.4)
    a, b = numeric(boxes), reference(boxes)
    for codes in (a, b):
        assert codes.dtype == np.int8 and codes.shape == (len(boxes),) and np.isin(codes, VERDICTS).all()
    assert not ((a * b) == -1).any(), "one backend proved inside what the other proved outside"
    assert {INSIDE, OUTSIDE, UNDECIDED} <= set(a.tolist())        # the sample reaches every verdict
    for k in range(0, len(boxes), 40):
        bounds = {"x": tuple(boxes[k, 0]), "y": tuple(boxes[k, 1])}
        assert certify_box(bounds, DISK[0]) is Certificate(int(a[k]))


def test_the_orthoglide_box_module_speaks_the_code():
    boxes = _boxes(np.random.default_rng(31), 300, 3, 0.1) * 0.6
    codes = box_module(boxes)
    assert codes.dtype == np.int8 and np.isin(codes, VERDICTS).all()
    assert {INSIDE, UNDECIDED} <= set(codes.tolist())
