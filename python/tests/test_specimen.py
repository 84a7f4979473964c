"""Specimen parameters and generation: the three methods, summary, arrays, determinism,
errors."""

import numpy as np
import pytest

import brittle_dem as bd


def small(method="traditional", seed=1, **over):
    return bd.SpecimenParams(method, "3mm", "1.5mm", "0.175mm", "0.285mm",
                             3200.0, 300e9, 500e6, seed=seed, overrides=over or None)


def test_params_fields_and_dict_round_trip():
    p = small()
    assert p.method == "traditional"
    assert p.width == pytest.approx(3e-3) and p.r_min == pytest.approx(0.175e-3)
    d = p.to_dict()
    assert d["method"] == "traditional" and d["seed"] == 1
    q = bd.SpecimenParams.from_dict(d)
    assert q.to_dict() == d
    r = small(porosity=0.18)
    assert r.to_dict()["porosity"] == 0.18


def test_params_errors():
    with pytest.raises(bd.DemError, match="--method \"x\": use traditional, orc or improved"):
        small("x")
    with pytest.raises(bd.DemError, match="--width"):
        bd.SpecimenParams("traditional", "3 parsecs", "1mm", "0.1mm", "0.2mm", 1.0, 1.0, 1.0)
    with pytest.raises(bd.DemError, match="not a specimen parameter"):
        small(bogus=1)
    with pytest.raises(bd.DemError, match="field"):
        bd.SpecimenParams.from_dict({"method": "traditional"})


@pytest.fixture(scope="module")
def trad():
    return bd.generate_specimen(small(), threads=1)


def test_generate_traditional(trad):
    s = trad
    assert s.n_discs > 20 and s.n_bonds > s.n_discs
    summ = s.summary
    assert isinstance(summ, dict) and summ
    d = s.discs()
    for k in ("x", "y", "r", "m", "vx", "vy", "omega", "theta"):
        assert d[k].dtype == np.float64 and d[k].shape == (s.n_discs,)
    assert d["id"].dtype == np.uint32 and d["group"].shape == (s.n_discs,)
    # (The radii are scaled to the packing's porosity after placement.)
    assert (d["r"] > 0.1e-3).all() and (d["r"] < 0.5e-3).all()
    assert "disc" in s.summary_text().lower()


def test_generate_deterministic_and_thread_independent(trad):
    b = bd.generate_specimen(small(), threads=2)
    for k in ("x", "y", "r"):
        np.testing.assert_array_equal(trad.discs()[k], b.discs()[k])


@pytest.mark.parametrize("method", ["orc", "improved"])
def test_generate_grain_methods(method):
    stages = []
    s = bd.generate_specimen(small(method), threads=1, callback=lambda st, f: stages.append(st))
    assert s.params.method == method and s.n_discs > 0
    assert stages, "the callback hears the stages"


def test_specimen_save(trad, tmp_path):
    f = tmp_path / "spec.json"
    trad.save(f)
    assert f.is_file() and (tmp_path / "spec.summary.json").is_file()
    assert (tmp_path / "spec.scene.json").is_file()
    png = bd.render(f)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"


def test_generate_stopped_by_callback():
    with pytest.raises(bd.DemStopped):
        bd.generate_specimen(small(seed=2), threads=1, callback=lambda st, f: False)


def test_models(tmp_path):
    from conftest import MODEL

    m = bd.load_model(MODEL)
    assert m.density > 0 and m.r_mean > 0
    assert bd.load_model(m.to_dict()).to_dict() == m.to_dict()
    assert m.with_r_mean(1e-4).r_mean == 1e-4
    with pytest.raises(bd.DemIOError, match="--model"):
        bd.load_model(tmp_path / "none.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    with pytest.raises(bd.DemError, match="--model"):
        bd.load_model(bad)
