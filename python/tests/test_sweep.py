"""Studies: the table of a `dem sweep` folder read from Python equals `dem sweep collect`'s."""

import json
import subprocess

import numpy as np
import pytest

import brittle_dem as bd
from conftest import ROOT, dem_command

STUDY = {
    "name": "py-brazilian",
    "base": {"test": "brazilian", "flags": {"diameter": "3mm", "r-min": "0.1mm", "r-max": "0.16mm",
                                            "density": 3200, "youngs": "300GPa", "tensile": "500MPa"}},
    "axes": [{"seeds": {"from": 1, "to": 2}}],
    "collect": ["/result/tensile_strength"],
}


def test_sweep_table_equals_collect(tmp_path):
    cmd = dem_command()
    if cmd is None:
        pytest.skip("no `dem` command and no cargo to build it: the sweep is run with it")
    study = tmp_path / "study.sweep.json"
    study.write_text(json.dumps(STUDY))
    d = tmp_path / "sweep"
    for args in (["plan", str(study), "--out", str(d)], ["run", str(d)],
                 ["collect", str(d), "--out", str(tmp_path / "table.json"), "--no-timing"]):
        p = subprocess.run(cmd + ["sweep", *args], cwd=ROOT, capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
    t = bd.sweep_table(d, timing=False)
    assert t.to_dict() == json.loads((tmp_path / "table.json").read_text())
    assert t.axes == ["seed"] and [c["status"] for c in t.cases] == ["done", "done"]
    s = t.outputs("result.tensile_strength")
    assert s.dtype == np.float64 and s.shape == (2,) and (s > 0).all()
    pd = pytest.importorskip("pandas")
    df = t.to_pandas()
    assert list(df["seed"]) == ["1", "2"] and len(df) == 2
    lines = bd.sweep_status(d)
    assert any("2 done" in ln for ln in lines)


def test_sweep_errors(tmp_path):
    with pytest.raises(bd.DemError):
        bd.sweep_table(tmp_path / "none")
