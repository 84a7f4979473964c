"""Shared fixtures of the brittle_dem tests: the repository, the `dem` command, and one short
cut run through Python and through `dem test cutting` (the CLI-equal test's inputs)."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "data" / "models" / "si3n4.model.json"

# The cut of the CLI-equal test: `dem test cutting` with these flags, and the same in Python.
CUT_FLAGS = [
    "--width", "6mm", "--height", "3mm", "--r-min", "0.175mm", "--r-max", "0.285mm",
    "--model", str(MODEL), "--specimen-from-model", "--depth", "0.5mm", "--length", "1.5mm",
    "--speed", "2", "--threads", "1", "--seed", "1",
]


def dem_command():
    """How to run `dem`: $DEM_CLI, `dem` on PATH, the workspace's release build, else
    `cargo run --release -p dem-cli --` (None without cargo)."""
    if os.environ.get("DEM_CLI"):
        return [os.environ["DEM_CLI"]]
    for p in (ROOT / "target" / "release" / "dem",):
        if p.is_file() and os.access(p, os.X_OK):
            return [str(p)]
    if shutil.which("dem"):
        return [shutil.which("dem")]
    if shutil.which("cargo"):
        return ["cargo", "run", "--quiet", "--release", "-p", "dem-cli", "--"]
    return None


def python_cut(out):
    import brittle_dem as bd

    model = bd.load_model(MODEL)
    params = bd.SpecimenParams.from_model(model, "6mm", "3mm", "0.175mm", "0.285mm", seed=1)
    model = model.with_r_mean(0.5 * (params.r_min + params.r_max))
    test = bd.cutting_test(depth=0.5e-3, length=1.5e-3, speed=2.0)
    return bd.cut(out, test, specimen=params, model=model, threads=1)


@pytest.fixture(scope="session")
def py_cut(tmp_path_factory):
    """The short cut through Python (about 10 s)."""
    return python_cut(tmp_path_factory.mktemp("py-cut"))


@pytest.fixture(scope="session")
def cli_cut(tmp_path_factory):
    """The same cut through `dem test cutting`: its output folder."""
    cmd = dem_command()
    if cmd is None:
        pytest.skip("no `dem` command and no cargo to build it: the CLI-equal test needs one")
    out = tmp_path_factory.mktemp("cli-cut")
    r = subprocess.run(cmd + ["test", "cutting", *CUT_FLAGS, "--out", str(out)],
                       cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return out
