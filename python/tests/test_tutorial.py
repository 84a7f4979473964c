"""The tutorial docs/python/tutorial.py runs and writes its pictures."""

import os
import subprocess
import sys

import pytest

from conftest import ROOT


def test_tutorial_runs(tmp_path):
    pytest.importorskip("matplotlib")
    env = dict(os.environ, TUTORIAL_OUT=str(tmp_path))
    p = subprocess.run([sys.executable, str(ROOT / "docs" / "python" / "tutorial.py")], env=env,
                       capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    for f in ("grain-01.json", "grain-01.png", "forces.png", "cut.png"):
        assert (tmp_path / f).stat().st_size > 0, f
    assert "mean main force" in p.stdout
