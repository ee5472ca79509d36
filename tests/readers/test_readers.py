"""The readers package and the registry of kinematics it fills (issue 38).

``kinematics`` sits below the readers, which build on ``DHRobot``: it imports none of them, and
``DHRobot.from_dict / from_file / from_urdf / from_mjcf`` look their reader up in ``kinematics.READERS``, which
``workspace_sym.readers`` fills when it is imported (``import workspace_sym`` imports it).  Reference: the
identity of the functions registered with those of the readers' modules, and of the old module paths' names with
the new ones.
"""

from __future__ import annotations

import pytest

import workspace_sym
from workspace_sym import DHRobot, kinematics, readers
from workspace_sym.readers import dh_file, mjcf, urdf


def test_importing_the_package_registers_every_reader():
    assert kinematics.READERS == {"dh": dh_file.read_dh, "dh_file": dh_file.read_dh_file, "urdf": urdf.read_urdf,
                                  "mjcf": mjcf.read_mjcf}
    assert workspace_sym.readers is readers


def test_the_classmethods_go_through_the_registry(monkeypatch, tmp_path):
    """A reader registered under a format is the one the classmethod calls, with the classmethod's arguments."""
    calls = []

    def reader(*args, **kwargs):
        calls.append((args, kwargs))
        return "read"

    for kind in ("dh", "dh_file", "urdf", "mjcf"):
        monkeypatch.setitem(kinematics.READERS, kind, reader)
    assert DHRobot.from_dict({"joints": []}, name="r") == "read"
    assert DHRobot.from_file(tmp_path / "r.json", exact=False) == "read"
    assert DHRobot.from_urdf(tmp_path / "r.urdf", tip_link="tool0") == "read"
    assert DHRobot.from_mjcf(tmp_path / "r.xml", base_link="b") == "read"
    assert [c[0][0] for c in calls] == [{"joints": []}, tmp_path / "r.json", tmp_path / "r.urdf", tmp_path / "r.xml"]
    assert calls[0][1]["name"] == "r" and calls[1][1]["exact"] is False
    assert calls[2][1]["tip_link"] == "tool0" and calls[2][1]["xacro_args"] is None
    assert calls[3][1]["base_link"] == "b"


@pytest.mark.parametrize("method, kind, argument", [(DHRobot.from_dict, "dh", {"joints": []}),
                                                    (DHRobot.from_file, "dh_file", "r.json"),
                                                    (DHRobot.from_urdf, "urdf", "r.urdf"),
                                                    (DHRobot.from_mjcf, "mjcf", "r.xml")])
def test_a_missing_reader_is_named(monkeypatch, method, kind, argument):
    """Without its reader a classmethod says which reader is missing and how to register it, not a KeyError."""
    monkeypatch.delitem(kinematics.READERS, kind)
    with pytest.raises(RuntimeError, match=f"no reader of '{kind}' robot descriptions is registered in "
                                           r"workspace_sym.kinematics.READERS; import workspace_sym.readers"):
        method(argument)


def test_the_old_module_paths_keep_their_names():
    from workspace_sym import dh_file as old_dh_file
    from workspace_sym import mjcf as old_mjcf
    from workspace_sym import urdf as old_urdf

    assert old_dh_file.read_dh is dh_file.read_dh and old_dh_file.read_dh_file is dh_file.read_dh_file
    assert old_urdf.read_urdf is urdf.read_urdf and old_urdf.MOVING is urdf.MOVING
    assert old_urdf.UNSUPPORTED is urdf.UNSUPPORTED
    assert old_mjcf.read_mjcf is mjcf.read_mjcf
