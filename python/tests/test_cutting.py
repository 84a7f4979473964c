"""The cutting test: Python equals `dem test cutting` byte for byte, histories as numpy
arrays, callbacks, stop and resume, errors."""

import filecmp
import json
import threading
import _thread

import numpy as np
import pytest

import brittle_dem as bd
from conftest import python_cut


def test_python_cut_equals_cli(py_cut, cli_cut):
    """The same inputs through Python and through `dem test cutting`: the same bytes."""
    py = py_cut.out_dir
    for f in ("history.csv", "cutting.forces.csv", "cutting.inputs.json", "specimen.json",
              "breaks.csv"):
        assert filecmp.cmp(py / f, cli_cut / f, shallow=False), f"{f} differs from the CLI's"
    # The specimen's summary: the same but for its generation's wall time.
    a, b = (json.loads((d / "specimen.summary.json").read_text()) for d in (py, cli_cut))
    a.pop("wall_time_s"), b.pop("wall_time_s")
    assert a == b
    # The scenes name the specimen file by its absolute path: equal but for the folder.
    for f in ("cutting.scene.json", "specimen.scene.json"):
        a = (py / f).read_text().replace(str(py), "OUT")
        b = (cli_cut / f).read_text().replace(str(cli_cut), "OUT")
        assert a == b, f"{f} differs from the CLI's"
    a = json.loads((py / "cutting.result.json").read_text())
    b = json.loads((cli_cut / "cutting.result.json").read_text())
    for k in ("main_force", "vertical_force", "chips", "broken_bonds", "window", "discs"):
        assert a[k] == b[k], k


def test_cut_result_and_history(py_cut):
    c = py_cut
    assert c.discs > 50 and c.steps > 1000
    assert np.isfinite(c.main_force_mean) and c.main_force_peak >= c.main_force_mean
    w0, w1 = c.window
    assert 0 <= w0 < w1
    d = c.to_dict()
    assert d["main_force"]["mean"] == c.main_force_mean
    h = c.history
    assert h.rows > 10 and h.names[:3] == ["time", "step", "dt"]
    for k in h:
        assert h[k].dtype == np.float64 and h[k].shape == (h.rows,)
    assert h.to_array().shape == (h.rows, len(h.names))
    f = c.forces
    assert f.names == ["travel_m", "time_s", "main_N", "vertical_N"]
    assert np.all(np.diff(f["time_s"]) > 0)
    assert "main force" in c.report()


def test_history_to_pandas(py_cut):
    pd = pytest.importorskip("pandas")
    df = py_cut.forces.to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == py_cut.forces.names
    assert len(df) == py_cut.forces.rows


def test_cut_deterministic(py_cut, tmp_path):
    """Again, with a progress callback and 2 threads: the same history."""
    calls = []
    c = python_cut_with(tmp_path, threads=2, callback=lambda d, t: calls.append((d, t)), every=2000)
    assert filecmp.cmp(c.out_dir / "history.csv", py_cut.out_dir / "history.csv", shallow=False)
    assert calls and calls[-1][0] == calls[-1][1]
    assert all(b[0] >= a[0] for a, b in zip(calls, calls[1:]))


def python_cut_with(out, **kw):
    model = bd.load_model(__import__("conftest").MODEL)
    params = bd.SpecimenParams.from_model(model, "6mm", "3mm", "0.175mm", "0.285mm", seed=1)
    model = model.with_r_mean(0.5 * (params.r_min + params.r_max))
    test = bd.cutting_test(depth=0.5e-3, length=1.5e-3, speed=2.0)
    return bd.cut(out, test, specimen=params, model=model, **kw)


def test_cut_stopped_then_resumed(py_cut, tmp_path):
    """A callback returning False stops the cut; the same call again resumes it from its
    checkpoint and ends with the same history as the uninterrupted cut."""
    seen = []

    def stop_half(done, total):
        seen.append(done)
        return done < total // 2

    with pytest.raises(bd.DemStopped, match="stopped by the callback"):
        python_cut_with(tmp_path, threads=1, callback=stop_half)
    assert seen[-1] >= seen[-2]
    c = python_cut_with(tmp_path, threads=1)
    assert filecmp.cmp(c.out_dir / "history.csv", py_cut.out_dir / "history.csv", shallow=False)


@pytest.mark.parametrize("with_callback", [True, False])
def test_cut_ctrl_c(tmp_path, with_callback):
    """Ctrl-C (SIGINT on the main thread) stops a running cut with KeyboardInterrupt, with a
    callback (raised in it) or without (seen by the waiting thread's poll)."""
    import time

    calls = []

    def cb(done, total):
        calls.append(done)
        time.sleep(0.002)  # a slower cut: the interrupt lands inside it

    def interrupt():
        if with_callback:
            while len(calls) < 10:
                time.sleep(0.01)
        else:
            time.sleep(0.3)
        _thread.interrupt_main()

    # Python's own SIGINT handler (a shell's background job starts with SIGINT ignored, and
    # then interrupt_main does nothing).
    import signal

    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        threading.Thread(target=interrupt, daemon=True).start()
        completed = []
        with pytest.raises(KeyboardInterrupt):
            python_cut_with(tmp_path, threads=1, callback=cb if with_callback else None)
            completed.append(True)
            time.sleep(10)  # an interrupt that came after the cut lands here
    finally:
        signal.signal(signal.SIGINT, old)
    assert not completed, "the interrupt came after the cut had ended"


def test_callback_exception_propagates(tmp_path):
    def cb(done, total):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        python_cut_with(tmp_path, threads=1, callback=cb)


def test_cut_errors(tmp_path):
    with pytest.raises(bd.DemError, match="depth"):
        bd.cutting_test(depth=-1.0)
    with pytest.raises(bd.DemError, match="unknown field"):
        bd.cutting_test(bogus=1)
    with pytest.raises(bd.DemError, match="give specimen"):
        bd.cut(tmp_path, bd.cutting_test())
    with pytest.raises(bd.DemIOError):
        bd.cut(tmp_path, bd.cutting_test(), specimen_file=tmp_path / "missing.json")
    p = bd.SpecimenParams("traditional", "2mm", "1mm", "0.175mm", "0.285mm", 3200.0, 300e9, 5e8)
    with pytest.raises(bd.DemError, match="length"):
        bd.cut(tmp_path, bd.cutting_test(depth=0.3e-3, length=10e-3), specimen=p)


def test_gil_released_during_a_cut(tmp_path):
    """Another Python thread runs while a cut runs (the GIL is released)."""
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.01)

    th = threading.Thread(target=count)
    th.start()
    try:
        c = python_cut_with(tmp_path, threads=1)
    finally:
        done.set()
        th.join()
    # The cut takes about a second or more: the counter ticks every 10 ms meanwhile.
    assert len(ticks) >= 0.2 * c.wall_time_s / 0.01


def test_cut_of_a_specimen_file(py_cut, tmp_path):
    """A cut of the specimen file the first cut generated, with the same model: the same
    history (the specimen file is the same bytes, so the run is the same)."""
    import shutil

    for f in ("specimen.json", "specimen.summary.json", "specimen.scene.json"):
        shutil.copy(py_cut.out_dir / f, tmp_path / f)
    model = bd.LabModel.from_dict(json.loads((py_cut.out_dir / "cutting.inputs.json").read_text())["model"])
    c = bd.cut(tmp_path / "cut", py_cut.to_dict()["test"], specimen_file=tmp_path / "specimen.json",
               model=model, threads=1)
    assert filecmp.cmp(c.out_dir / "history.csv", py_cut.out_dir / "history.csv", shallow=False)
    inputs = json.loads((c.out_dir / "cutting.inputs.json").read_text())
    assert inputs["specimen"] is None and inputs["specimen_file"].endswith("specimen.json")
