"""What a worker sends back is checked on the driver before it is stored (issue 31 item 4).

A worker's result is unpickled by the client and then becomes part of a proof; the driver accepts only what its
task can produce: a tuple of four plain float64 ``(N, n, 2)`` arrays of finite, ordered boxes inside the chunk it
sent (a decider's codes: one 1, 0 or -1 a box).  The workers here are an executor that runs the real step and
then forges its result.  Reference: the honest run through the same executor gives the local paving exactly.
"""

import concurrent.futures

import numpy as np
import pytest

from workspace_sym import RunOn
from workspace_sym.errors import WorkerResultError, WorkspaceError
from workspace_sym.interval import pave
from workspace_sym.interval.executor import map_codes

DISK = (["x**2 + y**2 <= 1"], {"x": (-1.2, 1.2), "y": (-1.2, 1.2)})


class Forging(concurrent.futures.Executor):
    """Workers that compute the true result of each task, then send back ``forge(result, chunk)`` instead."""

    def __init__(self, forge):
        self.forge = forge

    def submit(self, fn, /, *args, **kwargs):
        future = concurrent.futures.Future()
        future.set_result(self.forge(fn(*args, **kwargs), args[-1]))
        return future


def _outside(result, chunk):
    inner, boundary, outer, children = result
    far = np.array([[[5.0, 6.0], [5.0, 6.0]]])          # not in the disk's box, so not in any chunk
    return inner, boundary, np.concatenate([outer, far]), children


def _nan(result, chunk):
    inner, boundary, outer, children = (a.copy() for a in result)
    children[:1, 0, 0] = np.nan
    return inner, boundary, outer, children


def _inverted(result, chunk):
    return (result[0], result[1], result[2], result[3][:, :, ::-1])


FORGERIES = {
    "a dict": (lambda result, chunk: {"inner": result[0]}, "not 4 arrays|other than 4 arrays"),
    "three arrays": (lambda result, chunk: result[:3], "other than 4 arrays"),
    "a list of boxes": (lambda result, chunk: (result[0].tolist(), *result[1:]), "not a numpy array"),
    "float32 boxes": (lambda result, chunk: (result[0].astype(np.float32), *result[1:]), "float64"),
    "object boxes": (lambda result, chunk: (result[0].astype(object), *result[1:]), "float64"),
    "boxes of another dimension": (lambda result, chunk: (np.zeros((1, 3, 2)), *result[1:]), r"shape \(N, 2, 2\)"),
    "a NaN bound": (_nan, "non-finite"),
    "inverted bounds": (_inverted, "inverted"),
    "a box outside the chunk": (_outside, "outside the boxes it was sent"),
}


def test_an_honest_executor_gives_the_local_paving():
    """The checks refuse nothing a real step produces (reference: the local run, box for box)."""
    local = pave(*DISK, delta=0.1)
    spread = pave(*DISK, delta=0.1, run=RunOn(executor=Forging(lambda result, chunk: result)))
    assert spread.counts == local.counts and spread.measures == local.measures
    for kind in ("inner", "boundary", "outer"):
        assert {b.tobytes() for b in getattr(spread, kind)} == {b.tobytes() for b in getattr(local, kind)}


@pytest.mark.parametrize("name", FORGERIES)
def test_a_forged_step_result_is_refused(name):
    forge, message = FORGERIES[name]
    with pytest.raises(WorkerResultError, match=message) as caught:
        pave(*DISK, delta=0.1, run=RunOn(executor=Forging(forge)))
    assert isinstance(caught.value, WorkspaceError)          # the command line prints one line, exit 2
    assert caught.value.parameter == "executor"
    assert str(caught.value).startswith("executor: a worker returned ")


def _codes(boxes):
    return np.where(boxes[:, 0, 1] < 0.5, 1, 0)


@pytest.mark.parametrize(("forge", "message"), [
    (lambda codes, chunk: codes.tolist(), "not a numpy array"),
    (lambda codes, chunk: codes[:-1], "not 2000 numbers|not 2001 numbers|numbers"),
    (lambda codes, chunk: codes.astype(str), "numbers"),
    (lambda codes, chunk: codes * 2, "other than 1, 0 and -1"),
])
def test_forged_codes_are_refused(forge, message):
    lows = np.linspace(0, 1, 4001)
    boxes = np.stack([lows, lows + 1e-3], axis=1)[:, None, :]
    assert np.array_equal(map_codes(_codes, boxes, Forging(lambda codes, chunk: codes)), _codes(boxes))
    with pytest.raises(WorkerResultError, match=message):
        map_codes(_codes, boxes, Forging(forge))
