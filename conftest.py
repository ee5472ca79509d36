"""Set for every test and doctest the suite collects: figures use the Agg backend (no display in CI)."""

import gc
import os

import pytest
from hypothesis import settings

os.environ.setdefault("MPLBACKEND", "Agg")

# Property tests draw the same examples on every machine ("reproducible", the default), so a red CI run is a
# finding anyone can replay.  `make explore` draws fresh random examples on each run to hunt new ones: a case
# it finds is pinned with @example before it is fixed.
settings.register_profile("reproducible", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "reproducible"))

collect_ignore = ["workspace_sym/__main__.py"]

# SymPy's derivations allocate millions of short-lived objects and few cycles; at CPython's default threshold (700
# allocations) the cyclic collector ran so often that it took about a tenth of the suite's CPU (tests/kinematics/
# test_kinematics.py with tests/serial/test_orientation_arms.py: 41.0 s user at the default, 36.4 s here; with the
# collector off, 37.7 s: the rest is not the collector's).  Only when the collector runs changes, not what it frees.
gc.set_threshold(50_000, 20, 100)

# The test files that take longest, longest first (their summed test times in `make test` on 2 cores, from a JUnit
# report of the whole suite, 1,654 s of test time in 14:35 on a shared machine; the group of SAME_WORKER below
# counted as one): `make test` gives each pytest-xdist worker whole files (--dist=loadfile), in the order collected
# (--no-loadscope-reorder), so the long ones start at once and the short ones fill in around them; a long file
# handed out last would run alone at the end.  Files not listed keep their order after these.  Only the order
# changes: no test depends on another.
LONGEST_FIRST = [
    # the industrial arms' group (SAME_WORKER), about a quarter of the suite's test time, on one worker
    "test_serial_workspace.py", "test_reach_map_section.py", "test_reach_real_arms.py", "test_orientation_arms.py",
    "test_reach_shoulder.py", "test_reach_pieces.py", "test_orientation_centre.py", "test_orientation_spin.py",
    "test_orientation_offset.py", "test_orientation_offset_cone.py", "test_notebooks.py", "test_report.py",
    "test_kinematics.py", "test_cli.py", "test_executor.py",
    "test_grading_teacher.py", "test_kinematics_anytable.py", "test_boundary.py", "test_orthoglide.py",
    "test_charpoly.py", "test_docs_site.py", "test_reach_map_wrist.py", "test_reach_turn.py", "test_exercise_keys.py",
    "test_reach_section.py", "test_untrusted_input.py", "test_symbolic.py", "test_reach_critical3d.py",
    "test_typing.py", "test_reach_store.py", "test_orientation.py", "test_display.py", "test_hostile_robot_files.py",
    "test_mjcf.py", "test_urdf.py", "test_cli_report.py", "test_docstrings.py", "test_soundness.py",
    "test_fingerprint.py", "test_reach_turn3d.py", "test_codegen.py", "test_paving.py", "test_orientation_wrist.py",
    "test_reach_map.py",
]


# Test files that prepare the same robot objects (reach_checks.industrial_arm: the UR5, KR16, iiwa and Panda; the
# session's Puma and SCARA of tests/conftest.py): one worker runs them one after the other, so that each symbolic
# preparation (a few seconds an arm) is done once and not once on each worker.  Together they took 80 s of test
# time against 90 s one file per process.  The group is handed out where its first file comes in LONGEST_FIRST.
# test_orientation_spin.py's iiwa after the others had prepared it: its URDF read, structure and wrist centre done,
# 23 s for its tool-down paving and exact approach's structure against 38 s in a fresh process.
SAME_WORKER = {
    "industrial arms": ["test_serial_workspace.py", "test_reach_map_section.py", "test_reach_real_arms.py",
                        "test_orientation_arms.py", "test_reach_shoulder.py", "test_reach_pieces.py",
                        "test_orientation_centre.py", "test_orientation_spin.py"],
}
_GROUP_OF = {name: group for group, names in SAME_WORKER.items() for name in names}


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist=loadfile`` with the files of a SAME_WORKER group as one unit of work (pytest-xdist's own
    scheduler otherwise: each file is one unit)."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class LoadFileGroupScheduling(LoadFileScheduling):
        def _split_scope(self, nodeid):
            path = super()._split_scope(nodeid)
            return _GROUP_OF.get(path.rsplit("/", 1)[-1], path)

    return LoadFileGroupScheduling(config, log)


def pytest_collection_modifyitems(config, items):
    if settings().derandomize is False:
        # `make explore`: a test's own @settings(derandomize=True) would outrank the profile and draw the same
        # examples on every run; its settings are those of the decorator with fresh draws
        for item in items:
            test = getattr(item, "obj", None)
            if getattr(test, "is_hypothesis_test", False):
                test._hypothesis_internal_use_settings = settings(test._hypothesis_internal_use_settings,
                                                                  derandomize=False, database=None)
    rank = {name: k for k, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))   # stable: a file's tests keep their order
