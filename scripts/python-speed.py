"""The speed of a Python-driven cut against the CLI's (docs/python.md, "Speed"): the cut of
the CLI-equal test (python/tests/conftest.py) through `dem test cutting` and through
`brittle_dem.cut`, alternately, `N` times each (default 3), into fresh folders; prints the
wall time of each (the whole command or call: specimen generation, run, analysis) and the
medians. Usage: python scripts/python-speed.py [N]   ($DEM_CLI: the dem binary, default
target/release/dem; brittle_dem must be installed)."""

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python" / "tests"))
from conftest import CUT_FLAGS, python_cut  # noqa: E402

n = int(sys.argv[1]) if len(sys.argv) > 1 else 3
dem = os.environ.get("DEM_CLI", str(ROOT / "target" / "release" / "dem"))
cli, py = [], []
with tempfile.TemporaryDirectory() as tmp:
    for k in range(n):
        out = Path(tmp) / f"cli-{k}"
        t0 = time.perf_counter()
        subprocess.run([dem, "test", "cutting", *CUT_FLAGS, "--out", str(out)], check=True,
                       cwd=ROOT, stdout=subprocess.DEVNULL)
        cli.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        c = python_cut(Path(tmp) / f"py-{k}")
        py.append(time.perf_counter() - t0)
        same = (out / "history.csv").read_bytes() == (c.out_dir / "history.csv").read_bytes()
        print(f"run {k + 1}: CLI {cli[-1]:.2f} s, Python {py[-1]:.2f} s, same history: {same}")
print(f"median of {n}: CLI {statistics.median(cli):.2f} s, Python {statistics.median(py):.2f} s "
      f"({c.steps} steps, {c.discs} discs, 1 thread)")
