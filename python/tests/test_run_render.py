"""Scenes (`dem run`) from files and dicts with a state callback, and pictures."""

import json
import shutil

import numpy as np
import pytest

import brittle_dem as bd


@pytest.fixture()
def scene_dir(py_cut, tmp_path):
    """The specimen of the short cut with the scene `dem specimen` writes beside it."""
    for f in ("specimen.json", "specimen.summary.json", "specimen.scene.json"):
        shutil.copy(py_cut.out_dir / f, tmp_path / f)
    return tmp_path


def test_run_scene_file(scene_dir):
    r = bd.run(scene_dir / "specimen.scene.json", scene_dir / "out", threads=1, max_steps=200)
    assert r.ending == "max_steps" and r.result.steps == 200
    assert r.summary["final_step"] == 200
    h = r.history
    assert h.rows >= 1 and h["step"].dtype == np.float64


def test_run_scene_dict_with_state_callback(scene_dir):
    scene = json.loads((scene_dir / "specimen.scene.json").read_text())
    states = []

    def cb(s):
        states.append(s)
        return len(states) < 3  # stop at the third call

    r = bd.run(scene, scene_dir / "out2", base_dir=scene_dir, threads=1, callback=cb, every=50)
    assert r.ending == "stopped"
    assert [s["step"] for s in states] == [50, 100, 150]
    s = states[-1]
    n = len(s["x"])
    for k in ("x", "y", "vx", "vy", "r", "m", "omega", "theta"):
        assert s[k].dtype == np.float64 and s[k].shape == (n,)
    assert s["time"] > 0
    # Copies: the arrays of one call do not change later.
    assert not np.shares_memory(states[0]["x"], states[1]["x"])


def test_run_scene_deterministic(scene_dir):
    a = bd.run(scene_dir / "specimen.scene.json", scene_dir / "a", threads=1, max_steps=300)
    b = bd.run(scene_dir / "specimen.scene.json", scene_dir / "b", threads=2, max_steps=300)
    assert (a.out_dir / "history.csv").read_bytes() == (b.out_dir / "history.csv").read_bytes()


def test_run_scene_errors(scene_dir, tmp_path):
    with pytest.raises(bd.DemIOError):
        bd.run(tmp_path / "missing.scene.json")
    with pytest.raises(bd.DemError):
        bd.run({"schema": "dem.scene/1"}, base_dir=tmp_path)


def test_render_file_and_bytes(py_cut, tmp_path):
    ck = py_cut.out_dir / "ckpt-final.json"
    info = bd.render(ck, tmp_path / "cut.png", width=400, bonds=True, color="speed")
    assert info["width"] == 400 and info["height"] > 0 and info["discs"] > 0
    data = (tmp_path / "cut.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    b = bd.render(ck, width=400, bonds=True, color="speed")
    assert b == data


def test_render_errors(py_cut, tmp_path):
    ck = py_cut.out_dir / "ckpt-final.json"
    with pytest.raises(bd.DemError, match="not a colouring"):
        bd.render(ck, color="rainbow")
    with pytest.raises(bd.DemError, match="width"):
        bd.render(ck, width=0)
    with pytest.raises(bd.DemIOError):
        bd.render(tmp_path / "missing.json")
    with pytest.raises(bd.DemError, match=".png"):
        bd.render(ck, tmp_path / "x.gif")
