"""Outlines to clump templates: numpy arrays and files, dtypes and shapes, errors."""

import math

import numpy as np
import pytest

import brittle_dem as bd


def ellipse(a=1.0e-3, b=0.6e-3, n=80):
    t = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    return np.column_stack([a * np.cos(t), b * np.sin(t)])


def test_template_from_points_mass_and_arrays():
    pts = ellipse()
    t = bd.template_from_points(pts, name="ell", max_discs=9, density=3200.0, thickness=1.0)
    assert isinstance(t, bd.Template)
    area = 0.5 * abs(np.dot(pts[:, 0], np.roll(pts[:, 1], -1)) - np.dot(pts[:, 1], np.roll(pts[:, 0], -1)))
    # Improved method: the clump has the grain's exact mass.
    assert t.mass == pytest.approx(3200.0 * area, rel=1e-9)
    assert t.area == pytest.approx(area, rel=1e-9)
    assert t.centroid.dtype == np.float64 and t.centroid.shape == (2,)
    d = t.discs
    assert d.dtype == np.float64 and d.ndim == 2 and d.shape[1] == 4
    assert d.shape[0] == t.n_discs and 1 <= t.n_discs <= 9
    assert d[:, 3].sum() == pytest.approx(t.mass, rel=1e-9)
    assert 0.0 < t.cover <= 1.0
    assert t.inertia > 0 and t.inertia_own > 0
    assert t.method == "improved" and t.id == "ell"
    assert t.to_dict()["schema"].startswith("clumpgen.template/")


def test_template_orc_and_radius_units():
    t = bd.template_from_points(ellipse(), method="orc", r_min="0.05mm", r_max=0.8, max_discs=12)
    assert t.method == "orc"
    assert t.discs[:, 2].min() >= 0.05e-3 * (1 - 1e-12)


def test_template_file_round_trip(tmp_path):
    t = bd.template_from_points(ellipse(), max_discs=9)
    f = tmp_path / "t.json"
    t.save(f)
    u = bd.Template.load(f)
    np.testing.assert_array_equal(t.discs, u.discs)
    assert u.mass == t.mass


def test_template_from_file_equals_points(tmp_path):
    pts = ellipse()
    f = tmp_path / "grain.csv"
    f.write_text("".join(f"{float(x)!r} {float(y)!r}\n" for x, y in pts))
    a = bd.template_from_file(f, units="m", max_discs=9)
    b = bd.template_from_points(pts, max_discs=9)
    np.testing.assert_array_equal(a.discs, b.discs)
    assert a.id == "grain"
    p, origin = bd.read_outline(f, units="m")
    assert p.shape == (len(pts), 2) and p.dtype == np.float64 and origin.shape == (2,)


def test_template_deterministic():
    a = bd.template_from_points(ellipse(), max_discs=9)
    b = bd.template_from_points(ellipse(), max_discs=9)
    assert a.to_json() == b.to_json()


def test_template_errors():
    with pytest.raises(bd.DemError, match="shape"):
        bd.template_from_points(np.zeros((5, 3)))
    with pytest.raises(bd.DemError, match="distinct"):
        bd.template_from_points(np.array([[0.0, 0.0], [1e-3, 0.0], [0.0, 0.0]]))
    with pytest.raises(ValueError, match="--method"):
        bd.template_from_points(ellipse(), method="bogus")
    with pytest.raises(bd.DemError, match="--rmin"):
        bd.template_from_points(ellipse(), r_min="abcmm")
    with pytest.raises(bd.DemIOError) as e:
        bd.template_from_file("/nonexistent/grain.csv")
    assert isinstance(e.value, OSError) and isinstance(e.value, ValueError)
    assert "/nonexistent/grain.csv" in str(e.value)
    with pytest.raises(bd.DemIOError):
        bd.Template.load("/nonexistent/t.json")
