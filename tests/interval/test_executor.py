"""Pavings through the executor seam: other processes, a Dask cluster, boxes on disk, checkpoints.

The reference of every comparison is the local run of the same paving by
the driver :func:`workspace_sym.interval.driver.subdivide` with its in-line
runner (one chunk at a time in this thread, the boxes in memory, no
checkpoint): a distributed, streamed or resumed run must give exactly its
boxes (as sets), counts and measures.
"""

import importlib
import importlib.util
import json
import os
import sys
from concurrent.futures import ProcessPoolExecutor
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from workspace_sym import RunOn, StopAt, robots
from workspace_sym.cli import main
from workspace_sym.display import to_html
from workspace_sym.errors import InvalidParameterError, WorkspaceError
from workspace_sym.interval import pave
from workspace_sym.interval.boxes import StoredPaving
from workspace_sym.interval.executor import MissingExtraError, connect
from workspace_sym.interval.paving import _decider, _setup
from workspace_sym.interval.store import ExactSum, parse_memory
from workspace_sym.orthoglide import Orthoglide, cube


class _OnFirstUse:
    """A module imported when one of its names is first read: both pytest workers collect this file and only one
    runs it, so the other does not pay for importing Dask's distributed scheduler."""

    def __init__(self, name):
        self._name = name

    def __getattr__(self, attribute):
        if attribute.startswith("_"):        # pytest reads attributes such as _pytestfixturefunction at collection
            raise AttributeError(attribute)
        return getattr(importlib.import_module(self._name), attribute)


# [distributed] is part of the test extra; looked up here, imported by the first test that uses it
pytestmark = pytest.mark.skipif(importlib.util.find_spec("distributed") is None,
                                reason="the [distributed] extra is not installed")
distributed, dask = _OnFirstUse("distributed"), _OnFirstUse("dask")

BALL = (["x**2 + y**2 + z**2 <= 1"], {"x": (-1.2, 1.2), "y": (-1.2, 1.2), "z": (-1.2, 1.2)})


@pytest.fixture(scope="module")
def client():
    """One 2-process LocalCluster for the whole module (start-up costs seconds).

    A worker that dies is restarted by its nanny, but the cluster itself closes that nanny for good when no worker
    of the same name has registered within ``distributed.deploy.lost-worker-timeout`` (15 s by default): on a
    loaded machine a restarted worker process can take longer than that to start, and the cluster then stays at
    one worker.  The timeout is raised to the 300 s the tests wait for their workers.
    """
    with dask.config.set({"distributed.deploy.lost-worker-timeout": "300s"}), \
            distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                     silence_logs=40) as cluster, distributed.Client(cluster) as c:
        yield c


@pytest.fixture(scope="module")
def rpr2():
    m = robots.build("rpr2")
    return m.constraints, m.box


def as_set(boxes) -> set:
    return {tuple(b.ravel()) for b in np.asarray(boxes)}


def assert_same(a, b):
    """Same counts, same measures to the last bit, and the same boxes of every class."""
    assert a.counts == b.counts
    assert a.measures == b.measures
    assert a.complete and b.complete
    for kind in ("inner", "boundary", "outer"):
        assert as_set(getattr(a, kind)) == as_set(getattr(b, kind)), kind


# ------------------------------------------------------------------ exact sums
@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(min_value=0, max_value=1e300, allow_subnormal=True), max_size=60), st.randoms())
def test_exact_sum_is_the_rounded_rational_sum_in_any_order(values, rnd):
    """Reference: Fraction arithmetic (exact); the sum of a shuffled copy fed in two parts is the same float."""
    exact = float(sum((Fraction(v) for v in values), Fraction(0)))
    assert ExactSum.of(values).value == exact
    shuffled = list(values)
    rnd.shuffle(shuffled)
    s = ExactSum()
    s.add(np.array(shuffled[: len(shuffled) // 2]))
    s.add(np.array(shuffled[len(shuffled) // 2:]))
    assert s.value == exact
    assert ExactSum.parse(str(s)).value == exact


def test_parse_memory_rejects_what_is_not_a_size():
    assert parse_memory("2GB") == 2 * 10**9 and parse_memory("512 MiB") == 512 * 2**20
    for bad in ("2 parsecs", "", "-1GB", "10", True, None):
        with pytest.raises(InvalidParameterError, match="max_memory"):
            parse_memory(bad)


# ------------------------------------------------------------------ same answer everywhere
def test_rybak_on_dask_equals_local(client, rpr2):
    local = pave(*rpr2, delta=0.08)
    spread = pave(*rpr2, delta=0.08, run=RunOn(executor=client))
    assert_same(local, spread)


def test_contraction_on_dask_equals_local(client, rpr2):
    local = pave(*rpr2, delta=0.08, contract=True)
    spread = pave(*rpr2, delta=0.08, contract=True, run=RunOn(executor=client))
    assert_same(local, spread)


def test_unit_ball_on_dask_equals_local_and_brackets_its_volume(client):
    local = pave(*BALL, delta=0.15)
    spread = pave(*BALL, delta=0.15, run=RunOn(executor=client))
    assert_same(local, spread)
    lo, hi = spread.measure_bounds
    assert lo <= 4 / 3 * np.pi <= hi                   # exact volume of the unit ball


def test_orthoglide_on_dask_equals_local(client):
    o = Orthoglide()
    local, spread = o.dextrous(eps=0.1), o.dextrous(eps=0.1, run=RunOn(executor=client))
    assert_same(local.paving, spread.paving)
    assert local.to_dict()["volume_inner"] == spread.to_dict()["volume_inner"] > 0


def test_cube_certificates_on_dask_give_the_same_verdicts(client):
    """Chablat, Wenger, Merlet 2002, section 5: the largest cube has edge 0.643950 (half 0.322) and centre
    0.085938 on the diagonal; a cube of half-edge 0.25 there is inside, none of half-edge 0.4 fits."""
    centre = (0.085938,) * 3
    local = cube.cube_inside(centre, 0.25, min_width=0.01)
    assert local[0] is True
    assert local == cube.cube_inside(centre, 0.25, min_width=0.01, run=RunOn(executor=client))
    local = cube.no_enclosed_cube(0.4, min_width=0.05)
    assert local[0] is True
    assert local == cube.no_enclosed_cube(0.4, min_width=0.05, run=RunOn(executor=client))
    with pytest.warns(DeprecationWarning, match="no_enclosed_cube: executor= is deprecated"):
        assert local == cube.no_enclosed_cube(0.4, min_width=0.05, executor=client)


def test_reach_of_the_2r_arm_on_dask_equals_local(client):
    """The serial-arm workspace, each generation cut into chunks of a few hundred pairs on two workers."""
    from workspace_sym.serial import reach

    arm = robots.build("planar-2r")
    local = reach(arm, delta=0.2)
    spread = reach(arm, delta=0.2, run=RunOn(executor=client, chunk=300))
    assert_same(local, spread)
    assert local.counts["inner"] > 0 and local.counts["outer"] > 0


def test_cli_reach_on_a_scheduler_equals_local(client, capsys):
    argv = ["reach", "planar-2r", "--delta", "0.3", "--json"]
    assert main(argv) == 0
    local = json.loads(capsys.readouterr().out)
    assert main([*argv, "--scheduler", client.scheduler.address]) == 0
    spread = json.loads(capsys.readouterr().out)
    for kind in ("inner", "boundary", "outer"):
        assert local[kind] == spread[kind]


def test_cli_section_map_on_a_scheduler_equals_local(client, tmp_path, capsys):
    """The section method's stages as Dask tasks: the pavings side by side, the section in two parts of its cells.
    Reference: the map built in this process; the SCARA's two parts prove the same 126 pairs reachable (its
    section cannot aim: the seeds are the solution branches) and its 4,140 unreachable pairs are the pavings'."""
    from workspace_sym.serial.reachmap import ReachMap

    argv = ["reach-map", "scara", "--delta", "0.05", "--directions", "6", "--method", "section", "--json"]
    assert main([*argv, "--out", str(tmp_path / "here.npz")]) == 0
    assert main([*argv, "--out", str(tmp_path / "there.npz"), "--scheduler", client.scheduler.address]) == 0
    capsys.readouterr()
    here, there = (ReachMap.load(tmp_path / name) for name in ("here.npz", "there.npz"))
    assert np.array_equal(here.codes, there.codes) and (here.codes == 1).sum() == 126
    assert here.info["section_parts"] == 1 and there.info["section_parts"] == 2


def test_process_pool_equals_local(rpr2):
    with ProcessPoolExecutor(2) as pool:
        spread = pave(*rpr2, delta=0.08, run=RunOn(executor=pool))
    assert_same(pave(*rpr2, delta=0.08), spread)


def test_the_decider_pickles_as_its_constraints(rpr2):
    """What travels to a worker is the SymPy recipe, rebuilt there through the same cache."""
    import pickle

    cons, box = _setup(*rpr2, None)
    decide = _decider(cons, box.variables, "numpy", 30)
    payload = pickle.dumps(decide)
    assert pickle.loads(payload) is decide              # same process: the cached decider itself
    assert len(payload) < 5000


# ------------------------------------------------------------------ faults
class KillOnce:
    """A decider that kills the worker process running it, the first time only.

    "First" is decided by the file system, which outlives the worker: the
    flag file is created atomically (``O_EXCL``), so of two workers starting
    their first chunks at the same moment exactly one dies, and a worker
    restarted by its nanny finds the flag.
    """

    def __init__(self, decide, flag):
        self.decide, self.flag = decide, flag

    def __call__(self, boxes):
        try:
            os.close(os.open(self.flag, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            return self.decide(boxes)
        os._exit(1)                                       # the worker dies in the middle of a chunk


def test_a_killed_worker_does_not_change_the_result(client, rpr2, tmp_path):
    from workspace_sym.interval.driver import RunOn, subdivide

    cons, box = _setup(*rpr2, None)
    decide = _decider(cons, box.variables, "numpy", 30)
    flag = tmp_path / "killed"
    local = subdivide(decide, box, delta=0.08, constraints=cons)
    spread = subdivide(KillOnce(decide, str(flag)), box, delta=0.08, constraints=cons, run=RunOn(executor=client))
    assert flag.exists()                                  # a worker did die during the run
    assert_same(local, spread)


def test_the_step_outlives_every_worker_that_held_it(client, rpr2):
    """Dask's memory manager keeps one replica of data no task waits for; when the workers holding the step
    die, the next chunk still runs (a scattered step would be lost: 'lost dependencies')."""
    import time

    from workspace_sym.interval.driver import initial_boxes
    from workspace_sym.interval.executor import Dask

    cons, box = _setup(*rpr2, None)
    decide = _decider(cons, box.variables, "numpy", 30)
    boxes = initial_boxes(box, 0.08, "diameter", 64)
    runner = Dask(client, decide)
    try:
        assert np.array_equal(runner.submit(boxes).result(timeout=300), decide(boxes))
        holders = set(client.who_has([runner.fn])[runner.fn.key])
        kills = [client.submit(os._exit, 1, workers=[w], allow_other_workers=False, pure=False) for w in holders]
        deadline = time.monotonic() + 300
        while holders & set(client.scheduler_info()["workers"]):
            assert time.monotonic() < deadline, "the workers holding the step did not die"
            time.sleep(0.2)
        client.cancel(kills)
        assert np.array_equal(runner.submit(boxes).result(timeout=300), decide(boxes))
    finally:
        runner.close()
        client.wait_for_workers(2, timeout=300)           # the nannies restart them for the next tests


class InterruptOnce:
    """A decider that raises KeyboardInterrupt (Ctrl-C) on its third call."""

    def __init__(self, decide):
        self.decide, self.calls = decide, 0
        self.constraints, self.backend = decide.constraints, decide.backend    # the checkpoint's fingerprint

    def __call__(self, boxes):
        self.calls += 1
        if self.calls == 3:
            raise KeyboardInterrupt
        return self.decide(boxes)


@pytest.mark.parametrize("stream", [False, True])
def test_a_stopped_run_resumes_to_the_uninterrupted_result(rpr2, tmp_path, stream):
    options = {"store": tmp_path / "boxes"} if stream else {}
    checkpoint = tmp_path / "run.npz"
    first = pave(*rpr2, delta=0.08, stop=StopAt(max_boxes=700), run=RunOn(resume=checkpoint, **options))
    assert not first.complete and first.counts["pending"] > 0 and checkpoint.exists()
    # every box is accounted for: decided or pending
    m = first.measures
    assert abs(sum(m.values()) - first.box.measure) <= 1e-12 * first.box.measure
    second = pave(*rpr2, delta=0.08, run=RunOn(resume=checkpoint, **options))
    assert_same(pave(*rpr2, delta=0.08), second)
    assert second.evaluated == pave(*rpr2, delta=0.08).evaluated
    again = pave(*rpr2, delta=0.08, run=RunOn(resume=checkpoint, **options))      # a finished checkpoint: nothing to do
    assert again.counts == second.counts and again.evaluated == second.evaluated


def test_ctrl_c_keeps_every_undecided_box_pending_and_resumes(rpr2, tmp_path):
    from workspace_sym.interval.driver import RunOn, subdivide

    cons, box = _setup(*rpr2, None)
    decide = _decider(cons, box.variables, "numpy", 30)
    checkpoint = tmp_path / "run.npz"
    stopped = subdivide(InterruptOnce(decide), box, delta=0.08, constraints=cons,
                         run=RunOn(resume=checkpoint, chunk=2048))
    assert stopped.stop_reason == "interrupted" and stopped.counts["pending"] > 0
    m = stopped.measures
    assert abs(sum(m.values()) - box.measure) <= 1e-12 * box.measure
    resumed = subdivide(decide, box, delta=0.08, constraints=cons, run=RunOn(resume=checkpoint))
    assert_same(subdivide(decide, box, delta=0.08, constraints=cons), resumed)


def test_a_checkpoint_of_another_run_is_refused(rpr2, tmp_path):
    checkpoint = tmp_path / "run.npz"
    pave(*rpr2, delta=0.08, stop=StopAt(max_boxes=100), run=RunOn(resume=checkpoint))
    with pytest.raises(InvalidParameterError, match="delta"):
        pave(*rpr2, delta=0.05, run=RunOn(resume=checkpoint))


# ------------------------------------------------------------------ bounded memory
def test_streamed_boxes_on_disk_equal_the_local_run(rpr2, tmp_path):
    stored = pave(*rpr2, delta=0.08, run=RunOn(max_memory="64MB", store=tmp_path / "boxes"))
    assert isinstance(stored, StoredPaving)
    assert stored._loaded == {}                           # nothing read back into memory while paving
    local = pave(*rpr2, delta=0.08)
    assert_same(local, stored)
    # The parent's contract (issue 26): its classes read back from disk, so pictures and the notebook display
    # draw the boxes (they drew nothing when the arrays were empty).
    assert len(stored.inner) == stored.counts["inner"] == len(local.inner)
    from workspace_sym.plotting import plot_paving

    drawn = [len(c.get_paths()) for c in plot_paving(stored).axes[0].collections]
    assert drawn == [len(local.inner), len(local.boundary)] and "<img" in to_html(stored)
    data = stored.to_dict()
    assert data["store"] == str(tmp_path / "boxes")
    assert all(os.path.exists(f) for k in ("inner", "boundary", "outer") for f in data[k]["files"])
    with pytest.raises(InvalidParameterError, match="already holds boxes"):
        pave(*rpr2, delta=0.08, run=RunOn(store=tmp_path / "boxes"))


def test_orthoglide_streamed_on_dask_equals_local(client, tmp_path):
    o = Orthoglide()
    local = o.dextrous(eps=0.1)
    spread = o.dextrous(eps=0.1, run=RunOn(executor=client, max_memory="256MB", store=tmp_path / "boxes"))
    assert_same(local.paving, spread.paving)
    assert spread.to_dict()["files"]["inner"]


# ------------------------------------------------------------------ command line and missing extra
def test_cli_scheduler_and_resume(client, tmp_path, capsys):
    argv = ["pave", "rpr2", "--delta", "0.1", "--json"]
    assert main(argv) == 0
    local = json.loads(capsys.readouterr().out)
    assert main([*argv, "--scheduler", client.scheduler.address]) == 0
    spread = json.loads(capsys.readouterr().out)
    checkpoint = str(tmp_path / "run.npz")
    assert main([*argv, "--max-boxes", "300", "--resume", checkpoint, "--max-memory", "64MB"]) == 0
    stopped = json.loads(capsys.readouterr().out)
    assert main([*argv, "--resume", checkpoint, "--max-memory", "64MB"]) == 0
    resumed = json.loads(capsys.readouterr().out)
    assert not stopped["complete"] and stopped["pending"]["boxes"] > 0
    for kind in ("inner", "boundary", "outer"):
        assert local[kind] == spread[kind]
        assert local[kind]["boxes"] == resumed[kind]["boxes"] and local[kind]["measure"] == resumed[kind]["measure"]
        assert resumed[kind]["files"]


def test_cli_bad_scheduler_is_one_line(capsys):
    assert main(["pave", "rpr2", "--delta", "0.1", "--scheduler", "local:zero"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--scheduler" in err and "local:N" in err


def test_without_dask_the_error_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)     # import distributed now raises ImportError
    with pytest.raises(MissingExtraError, match=r"workspace_sym\[distributed\]"), connect("local:2"):
        pass
    assert issubclass(MissingExtraError, WorkspaceError)
