"""The command line of reachability maps: ``reach-map`` writes a map whose answers ``query`` reads back; bad input
is exit status 2 and one stderr line naming the option."""

import contextlib
import io
import json

import numpy as np
import pytest

from workspace_sym import robots
from workspace_sym.cli import main
from workspace_sym.display import to_html
from workspace_sym.plotting import plot_reach_map
from workspace_sym.serial.reachmap import ReachMap, map_problem

BUILD = ("reach-map", "scara", "--delta", "0.2", "--directions", "6", "--cone", "30")


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    where = tmp_path_factory.mktemp("map")
    path = where / "map.npz"
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([*BUILD, "--out", str(path), "--json"])
    assert code == 0
    (where / "points.csv").write_text("x,y,z\n0.3,0.0,0.1\n# a comment\n9,9,9\n")
    return path, where / "points.csv", json.loads(out.getvalue()), err.getvalue()


def test_reach_map_writes_a_map_of_its_problem_and_query_reads_it_back(built, capsys):
    # Reference: the map loaded in Python (ReachMap.load, expecting the problem the command was given).
    path, points = built[:2]
    made = ReachMap.load(path, expect=map_problem(robots.build("scara"), delta=0.2, directions=6, cone=30))
    code, out, err = run(capsys, "query", str(path), "--points", str(points), "--approach", "1,0,0", "--json")
    assert code == 0 and err == ""
    data = json.loads(out)
    p = np.array([[0.3, 0.0, 0.1], [9, 9, 9]])
    assert data["codes"] == made.query(p, approach=[[1, 0, 0]]).tolist() == [-1, -1]
    code, out, _ = run(capsys, "query", str(path), "--points", str(points), "--json")
    assert json.loads(out)["capability"] == made.query(p).tolist()
    code, out, _ = run(capsys, "query", str(path), "--points", str(points))
    assert out.splitlines()[0] == "x,y,z,capability_lower,capability_upper" and len(out.splitlines()) == 3


def test_reach_map_json_summary(built):
    _, _, data, err = built
    assert data["directions"] == 6 and data["pairs"] == data["reachable"] + data["unreachable"] + \
        data["undecided"]
    assert "do not cover the sphere" in err and "wrote" in err


@pytest.mark.parametrize("argv, flag", [
    (("--cone", "0"), "--cone"), (("--directions", "0"), "--directions"), (("--store", "x"), "--store"),
])
def test_bad_reach_map_input_is_one_line_and_exit_2(tmp_path, capsys, argv, flag):
    code, out, err = run(capsys, "reach-map", "scara", "--delta", "0.2", "--out", str(tmp_path / "m.npz"), *argv)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and f"error: {flag}:" in err
    assert not (tmp_path / "m.npz").exists()


def test_bad_query_input_is_one_line_and_exit_2(built, tmp_path, capsys):
    path, points = built[:2]
    (tmp_path / "bad.csv").write_text("1,2\n")
    for argv, word in [((str(path), "--points", str(points), "--approach", "0,0,0"), "--approach"),
                       ((str(path), "--points", str(tmp_path / "bad.csv")), "--points"),
                       ((str(points), "--points", str(points)), "map")]:
        code, out, err = run(capsys, "query", *argv)
        assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and f"error: {word}" in err


def test_a_map_displays_in_a_notebook_and_draws_a_slice(built):
    made = ReachMap.load(built[0])
    html = to_html(made)
    assert "approach directions" in html and "<img" in html and "proved unreachable" in html
    fig = plot_reach_map(made, axis="z", value=0.1, direction=0)
    image = fig.axes[0].images[0].get_array()
    assert image.shape == (made.shape[1], made.shape[0])
    assert set(np.unique(image)) <= {-1.0, 0.0, 1.0}


def test_reach_map_by_the_section_method_writes_a_map_of_its_problem(tmp_path, capsys):
    # Reference: the map loaded in Python against the fingerprint of the section method's problem; the SCARA's
    # approach is straight down at every configuration (its DH table), so no other direction is proved.
    path = tmp_path / "section.npz"
    code, out, _ = run(capsys, "reach-map", "scara", "--delta", "0.05", "--directions", "6", "--cone", "30",
                       "--method", "section", "--out", str(path), "--json")
    assert code == 0 and json.loads(out)["method"] == "section proofs and the position paving"
    scara = robots.build("scara")
    section = ReachMap.load(path, expect=map_problem(scara, delta=0.05, directions=6, cone=30, method="section"))
    down = int(np.argmax(section.directions @ [0.0, 0.0, -1.0]))
    assert set(np.argwhere(section.codes == 1)[:, 3]) == {down}


def test_the_section_method_refuses_a_checkpoint_with_status_2(tmp_path, capsys):
    code, out, err = run(capsys, "reach-map", "scara", "--delta", "0.2", "--method", "section",
                         "--resume", str(tmp_path / "c.npz"), "--out", str(tmp_path / "m.npz"))
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "error: --resume: method=" in err
    assert not (tmp_path / "m.npz").exists()
