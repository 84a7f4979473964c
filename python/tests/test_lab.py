"""The quasi-static lab tests: Python equals `dem test brazilian` byte for byte; errors."""

import filecmp
import json
import subprocess

import numpy as np
import pytest

import brittle_dem as bd
from conftest import ROOT, dem_command

FLAGS = ["--diameter", "3mm", "--r-min", "0.1mm", "--r-max", "0.16mm", "--density", "3200",
         "--youngs", "300GPa", "--tensile", "500MPa", "--threads", "1", "--seed", "1"]


def params():
    return bd.SpecimenParams("traditional", "3mm", "3mm", "0.1mm", "0.16mm", 3200.0, 300e9,
                             500e6, seed=1)


def test_brazilian_equals_cli(tmp_path):
    r = bd.lab_test("brazilian", tmp_path / "py", params(), {"diameter": 3e-3}, threads=1)
    assert r.name == "brazilian"
    res = r.result
    assert res["tensile_strength"] > 0 and res["diameter"] == pytest.approx(3e-3, rel=1e-3)
    h = r.history
    assert h.rows > 10 and all(h[k].dtype == np.float64 for k in h)
    cmd = dem_command()
    if cmd is None:
        pytest.skip("no `dem` command and no cargo to build it")
    cli = tmp_path / "cli"
    p = subprocess.run(cmd + ["test", "brazilian", *FLAGS, "--out", str(cli)], cwd=ROOT,
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    for f in ("brazilian.out/history.csv", "brazilian.specimen.json"):
        assert filecmp.cmp(r.out_dir / f, cli / f, shallow=False), f"{f} differs from the CLI's"
    b = json.loads((cli / "brazilian.result.json").read_text())
    assert b["result"] == res


def test_lab_test_errors(tmp_path):
    with pytest.raises(bd.DemError, match="not a quasi-static lab test"):
        bd.lab_test("shear", tmp_path, params())
    with pytest.raises(bd.DemError, match="diameter"):
        bd.lab_test("brazilian", tmp_path, params(), {"diameter": -1.0})
    with pytest.raises(bd.DemError, match="unknown field"):
        bd.lab_test("ucs", tmp_path, params(), {"bogus": 1})
