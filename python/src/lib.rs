//! `brittle_dem._native`: the Python bindings of the workspace (issue 53). Thin: every call
//! goes to the library layer as `dem` does (dem-cli/src/clump.rs, specimen.rs,
//! test_cutting.rs, run.rs, render.rs), with typed values; the pure-Python package
//! (`brittle_dem/__init__.py`) adds the dict conveniences, the history as numpy arrays and the
//! optional pandas frames. SI units throughout (m, kg, s, N, Pa, rad).
//!
//! Long runs release the GIL: the work runs on a scoped thread (inside a rayon pool of the
//! asked size) while the calling thread waits with the GIL released, wakes every
//! [`POLL`] to check for Ctrl-C (`py.check_signals()`, which only the main thread can do) and
//! calls the user's callback on the calling thread when the work asks for it.

use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyType};
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Duration;

mod drive;
use drive::{drive, Ctl, Msg, Reply};

/// How often a waiting call checks for Ctrl-C.
const POLL: Duration = Duration::from_millis(100);

// ---------------------------------------------------------------------------------------
// Errors: `brittle_dem.errors.DemError` (a ValueError) and `DemIOError` (also an OSError),
// with the library's message, the one `dem` prints after `error: `.

/// Whether the error (or one of its sources) is a file's: an `std::io::Error` in its chain, or
/// one of the library's file errors that keep only the reason.
fn is_io(e: &(dyn std::error::Error + 'static)) -> bool {
    let mut cur: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(x) = cur {
        if x.is::<std::io::Error>()
            || matches!(
                x.downcast_ref::<dem_lab::specimen::SpecimenError>(),
                Some(dem_lab::specimen::SpecimenError::File { .. })
            )
            || matches!(
                x.downcast_ref::<dem_render::RenderError>(),
                Some(dem_render::RenderError::Read { .. })
            )
        {
            return true;
        }
        cur = x.source();
    }
    false
}

/// The package's exception class `name` (`DemError`, `DemIOError`, `DemStopped`), or the
/// builtin base when the package is not importable (the bare extension module).
fn exc(py: Python<'_>, name: &str, msg: String) -> PyErr {
    let cls = py
        .import("brittle_dem.errors")
        .and_then(|m| m.getattr(name))
        .and_then(|c| c.downcast_into::<PyType>().map_err(PyErr::from));
    match cls {
        Ok(c) => PyErr::from_type(c, msg),
        Err(_) if name == "DemIOError" => PyOSError::new_err(msg),
        Err(_) => PyValueError::new_err(msg),
    }
}

/// A library error as the package's exception.
fn dem_err<E: std::error::Error + 'static>(e: E) -> PyErr {
    let io = is_io(&e);
    Python::with_gil(|py| {
        exc(
            py,
            if io { "DemIOError" } else { "DemError" },
            e.to_string(),
        )
    })
}

/// A message (the CLI's own checks, which `dem` returns as strings) as a `DemError`.
fn msg_err(m: impl Into<String>) -> PyErr {
    Python::with_gil(|py| exc(py, "DemError", m.into()))
}

/// A file error with its message as a `DemIOError`.
fn io_err(m: impl Into<String>) -> PyErr {
    Python::with_gil(|py| exc(py, "DemIOError", m.into()))
}

fn to_py<'py, T: serde::Serialize>(py: Python<'py>, v: &T) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, v).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// A dict (or any Python value) as `T`, the error naming the field as the CLI's do
/// (`field a.b: reason`).
fn from_py<T: serde::de::DeserializeOwned>(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<T> {
    let mut de = pythonize::Depythonizer::from_object(obj);
    serde_path_to_error::deserialize(&mut de)
        .map_err(|e| msg_err(format!("{what}: field {}: {}", e.path(), e.inner())))
}

// ---------------------------------------------------------------------------------------
// Lengths with units, as the `dem` flags take them.

/// `0.5mm`, `20um`, `1e-3m` or a plain number in metres.
fn length_m(v: &Bound<'_, PyAny>, what: &str) -> PyResult<f64> {
    if let Ok(x) = v.extract::<f64>() {
        return Ok(x);
    }
    let s: String = v.extract().map_err(|_| {
        msg_err(format!(
            "{what}: a length in m (float) or with unit (\"0.5mm\")"
        ))
    })?;
    parse_length(&s, what).map_err(msg_err)
}

/// As dem-cli/src/specimen.rs `parse_length`: `10mm`, `0.5um`, `1e-3m`.
fn parse_length(s: &str, what: &str) -> Result<f64, String> {
    let t = s.trim();
    for (suffix, scale) in [("um", 1e-6), ("µm", 1e-6), ("mm", 1e-3), ("m", 1.0)] {
        if let Some(num) = t.strip_suffix(suffix) {
            return num
                .trim()
                .parse::<f64>()
                .map(|v| v * scale)
                .map_err(|_| format!("{what} {s:?}: not a number with unit"));
        }
    }
    Err(format!(
        "{what} {s:?}: give a unit: mm, um or m (e.g. 0.5mm)"
    ))
}

/// A template radius: a float is a fraction of the grain's equivalent radius, a string is
/// that or a length with unit (`dem clump --rmin`).
fn clump_length(v: &Bound<'_, PyAny>, what: &str) -> PyResult<clumpgen::Length> {
    if let Ok(x) = v.extract::<f64>() {
        return Ok(clumpgen::Length::OfReq(x));
    }
    let s: String = v.extract().map_err(|_| {
        msg_err(format!(
            "--{what}: a fraction of R_eq (float) or a length like \"0.1mm\""
        ))
    })?;
    let s = s.trim();
    for (suffix, scale) in [("um", 1e-6), ("µm", 1e-6), ("mm", 1e-3), ("m", 1.0)] {
        if let Some(num) = s.strip_suffix(suffix) {
            let v: f64 = num
                .trim()
                .parse()
                .map_err(|_| msg_err(format!("--{what} {s:?}: not a number with unit")))?;
            return Ok(clumpgen::Length::Metres(v * scale));
        }
    }
    s.parse::<f64>().map(clumpgen::Length::OfReq).map_err(|_| {
        msg_err(format!(
            "--{what} {s:?}: expected a fraction of R_eq or a length like 0.1mm"
        ))
    })
}

// ---------------------------------------------------------------------------------------
// Outlines and clump templates (`dem clump`).

/// A clump template (`clumpgen.template/1` or `/2`): the discs that stand for one grain, with
/// the grain's exact mass, centroid and inertia (improved method). Lengths m, masses kg,
/// inertia kg m² (for the disc thickness `thickness`).
#[pyclass(module = "brittle_dem._native", frozen)]
struct Template {
    t: clumpgen::Template,
}

#[pymethods]
impl Template {
    /// Reads a template file (`dem clump` writes them).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Template> {
        clumpgen::Template::load(&path)
            .map(|t| Template { t })
            .map_err(dem_err)
    }
    /// Writes the template file (JSON) as `dem clump` does.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        self.t.save(&path).map_err(dem_err)
    }
    /// The template as its JSON text.
    fn to_json(&self) -> PyResult<String> {
        self.t.to_json("template").map_err(dem_err)
    }
    /// The template as a dict (the file's fields).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.t)
    }
    /// Template id (the outline's name).
    #[getter]
    fn id(&self) -> String {
        self.t.id.clone()
    }
    /// `improved`, `orc` or `lattice`.
    #[getter]
    fn method(&self) -> String {
        self.t.method.name().to_string()
    }
    /// Density ρ (kg/m³).
    #[getter]
    fn density(&self) -> f64 {
        self.t.density
    }
    /// Disc thickness t (m).
    #[getter]
    fn thickness(&self) -> f64 {
        self.t.thickness
    }
    /// Mass of the clump (kg), Σ m_i.
    #[getter]
    fn mass(&self) -> f64 {
        self.t.achieved.mass
    }
    /// The clump's mass centre (m, shape (2,)) in the grain's frame (grain centroid at 0).
    #[getter]
    fn centroid<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.t.achieved.centroid)
    }
    /// Moment of inertia about the grain centroid (kg m²).
    #[getter]
    fn inertia(&self) -> f64 {
        self.t.achieved.inertia
    }
    /// Moment of inertia about the clump's own mass centre (kg m²).
    #[getter]
    fn inertia_own(&self) -> f64 {
        self.t.achieved.inertia_own
    }
    /// The grain's own (target) mass (kg), centroid (m), inertia (kg m²) and area (m²).
    #[getter]
    fn target<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.t.target)
    }
    /// The discs, shape (k, 4) float64: x (m), y (m), r (m), m (kg).
    #[getter]
    fn discs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = (self.t.discs.iter())
            .map(|d| vec![d.x, d.y, d.r, d.m])
            .collect();
        PyArray2::from_vec2(py, &rows).map_err(|e| PyValueError::new_err(e.to_string()))
    }
    /// Number of discs.
    #[getter]
    fn n_discs(&self) -> usize {
        self.t.discs.len()
    }
    /// Area cover A_r = area(union of discs ∩ grain) / area(grain), in [0, 1].
    #[getter]
    fn cover(&self) -> f64 {
        self.t.cover.value
    }
    /// Grain area (m²).
    #[getter]
    fn area(&self) -> f64 {
        self.t.shape.area
    }
    fn __repr__(&self) -> String {
        format!(
            "Template(id={:?}, method={}, discs={}, mass={:.6e} kg, cover={:.4})",
            self.t.id,
            self.t.method.name(),
            self.t.discs.len(),
            self.t.achieved.mass,
            self.t.cover.value
        )
    }
}

/// The `dem clump` parameters from the keywords.
#[allow(clippy::too_many_arguments)]
fn clump_params(
    method: &str,
    cover: f64,
    r_min: &Bound<'_, PyAny>,
    r_max: &Bound<'_, PyAny>,
    max_discs: usize,
    density: f64,
    thickness: f64,
    spacing: Option<&Bound<'_, PyAny>>,
    node_radius: f64,
) -> PyResult<clumpgen::ClumpParams> {
    let method = match method {
        "improved" => clumpgen::Method::Improved,
        "orc" => clumpgen::Method::Orc,
        "lattice" => clumpgen::Method::Lattice,
        m => {
            return Err(msg_err(format!(
                "--method {m:?}: use improved, orc or lattice"
            )))
        }
    };
    let lattice = match (method, spacing) {
        (clumpgen::Method::Lattice, Some(s)) => Some(clumpgen::clump::LatticeParams {
            spacing: clump_length(s, "spacing")?,
            node_radius,
        }),
        (clumpgen::Method::Lattice, None) => {
            return Err(msg_err("--method lattice needs --spacing"));
        }
        (_, Some(_)) => return Err(msg_err("--spacing needs --method lattice")),
        _ => None,
    };
    let p = clumpgen::ClumpParams {
        method,
        density,
        thickness,
        cover,
        r_min: clump_length(r_min, "rmin")?,
        r_max: clump_length(r_max, "rmax")?,
        max_discs,
        lattice,
        ..clumpgen::ClumpParams::default()
    };
    p.check().map_err(dem_err)?;
    Ok(p)
}

fn units(s: Option<&str>) -> PyResult<Option<clumpgen::Units>> {
    s.map(|u| clumpgen::Units::parse(u, None).map_err(dem_err))
        .transpose()
}

/// A template from an outline given as points: `points` of shape (n, 2) (x, y in `units`, no
/// repeated closing point needed), named `name`. The outline is read as `dem clump` reads an
/// outline file (validated, centred, counter-clockwise), then filled.
#[pyfunction]
#[pyo3(signature = (points, *, name="grain", units="m", method="improved", cover=0.95,
    r_min=None, r_max=None, max_discs=64, density=2650.0, thickness=1.0, resample=None,
    spacing=None, node_radius=1.0))]
#[allow(clippy::too_many_arguments)]
fn template_from_points(
    py: Python<'_>,
    points: numpy::PyReadonlyArray2<'_, f64>,
    name: &str,
    units: &str,
    method: &str,
    cover: f64,
    r_min: Option<&Bound<'_, PyAny>>,
    r_max: Option<&Bound<'_, PyAny>>,
    max_discs: usize,
    density: f64,
    thickness: f64,
    resample: Option<usize>,
    spacing: Option<&Bound<'_, PyAny>>,
    node_radius: f64,
) -> PyResult<Template> {
    let a = points.as_array();
    if a.ncols() != 2 {
        return Err(msg_err(format!(
            "points: shape ({}, {}): give an (n, 2) array of x, y",
            a.nrows(),
            a.ncols()
        )));
    }
    // The outline text as a file would hold it (shortest round-trip decimals: the same
    // numbers), so the points go through the one outline reader and its checks.
    let mut text = String::with_capacity(a.nrows() * 48);
    for row in a.rows() {
        text.push_str(&format!("{} {}\n", row[0], row[1]));
    }
    let dflt_min = 0.02f64.into_pyobject(py)?.into_any();
    let dflt_max = 1.0f64.into_pyobject(py)?.into_any();
    let p = clump_params(
        method,
        cover,
        r_min.unwrap_or(&dflt_min),
        r_max.unwrap_or(&dflt_max),
        max_discs,
        density,
        thickness,
        spacing,
        node_radius,
    )?;
    let opts = clumpgen::ReadOptions {
        units: self::units(Some(units))?,
        resample,
    };
    let source = format!("{name} (numpy array)");
    py.allow_threads(|| {
        let ol = clumpgen::parse_outline(&text, name, &source, false, &opts).map_err(dem_err)?;
        clumpgen::make_template(&ol, &p)
            .map(|t| Template { t })
            .map_err(dem_err)
    })
}

/// A template from an outline file (CSV/whitespace `x y` or JSON), as `dem clump FILE` makes
/// it. `units` overrides what the file declares (default: the file's, else mm).
#[pyfunction]
#[pyo3(signature = (path, *, units=None, method="improved", cover=0.95, r_min=None,
    r_max=None, max_discs=64, density=2650.0, thickness=1.0, resample=None, spacing=None,
    node_radius=1.0))]
#[allow(clippy::too_many_arguments)]
fn template_from_file(
    py: Python<'_>,
    path: PathBuf,
    units: Option<&str>,
    method: &str,
    cover: f64,
    r_min: Option<&Bound<'_, PyAny>>,
    r_max: Option<&Bound<'_, PyAny>>,
    max_discs: usize,
    density: f64,
    thickness: f64,
    resample: Option<usize>,
    spacing: Option<&Bound<'_, PyAny>>,
    node_radius: f64,
) -> PyResult<Template> {
    let dflt_min = 0.02f64.into_pyobject(py)?.into_any();
    let dflt_max = 1.0f64.into_pyobject(py)?.into_any();
    let p = clump_params(
        method,
        cover,
        r_min.unwrap_or(&dflt_min),
        r_max.unwrap_or(&dflt_max),
        max_discs,
        density,
        thickness,
        spacing,
        node_radius,
    )?;
    let opts = clumpgen::ReadOptions {
        units: self::units(units)?,
        resample,
    };
    py.allow_threads(|| {
        let ol = clumpgen::read_outline(&path, &opts).map_err(dem_err)?;
        clumpgen::make_template(&ol, &p)
            .map(|t| Template { t })
            .map_err(dem_err)
    })
}

/// An outline's points ((n, 2), m) and origin ((2,), m).
type PointsAndOrigin<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// Reads an outline file: its points (m, local frame centred on the bounding box, shape
/// (n, 2)) and the origin (m) subtracted from them.
#[pyfunction]
#[pyo3(signature = (path, *, units=None))]
fn read_outline<'py>(
    py: Python<'py>,
    path: PathBuf,
    units: Option<&str>,
) -> PyResult<PointsAndOrigin<'py>> {
    let opts = clumpgen::ReadOptions {
        units: self::units(units)?,
        resample: None,
    };
    let ol = clumpgen::read_outline(&path, &opts).map_err(dem_err)?;
    let rows: Vec<Vec<f64>> = ol.points.iter().map(|p| p.to_vec()).collect();
    let pts = PyArray2::from_vec2(py, &rows).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((pts, PyArray1::from_slice(py, &ol.origin)))
}

// ---------------------------------------------------------------------------------------
// Material models, specimens (`dem specimen`).

/// A material model (`LabModel`: density, thickness, mean radius, micro-parameters, flat
/// joints), as `dem calibrate` writes it and `--model` reads it.
#[pyclass(module = "brittle_dem._native", frozen)]
#[derive(Clone)]
struct LabModel {
    m: dem_lab::LabModel,
}

#[pymethods]
impl LabModel {
    /// Reads a model file (the `--model` of every lab test).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<LabModel> {
        let text = clumpgen::io::read_input_string(&path)
            .map_err(|e| io_err(format!("--model {}: {e}", path.display())))?;
        let m: dem_lab::LabModel = serde_json::from_str(&text)
            .map_err(|e| msg_err(format!("--model {}: {e}", path.display())))?;
        if let Some(o) = &m.flat_joint {
            o.check().map_err(|(field, why)| {
                msg_err(format!(
                    "--model {}: flat_joint.{field} {why}",
                    path.display()
                ))
            })?;
        }
        Ok(LabModel { m })
    }
    /// A model from a dict (the file's fields).
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyAny>) -> PyResult<LabModel> {
        Ok(LabModel {
            m: from_py(d, "model")?,
        })
    }
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.m)
    }
    /// Density ρ (kg/m³).
    #[getter]
    fn density(&self) -> f64 {
        self.m.density
    }
    /// Mean disc radius r̄ (m).
    #[getter]
    fn r_mean(&self) -> f64 {
        self.m.r_mean
    }
    /// This model with the mean radius r̄ (m) (the bond stiffness k̄_n = Ē_c/(2r̄) follows).
    fn with_r_mean(&self, r_mean: f64) -> LabModel {
        let mut m = self.m.clone();
        m.r_mean = r_mean;
        LabModel { m }
    }
    fn __repr__(&self) -> String {
        format!(
            "LabModel(density={} kg/m3, r_mean={:.4e} m, E_c={:.4e} Pa)",
            self.m.density, self.m.r_mean, self.m.micro.contact_modulus
        )
    }
}

/// The parameters of a specimen (`SpecimenParams`; lengths m, stresses Pa): the method, box,
/// radii, seed, material and micro-parameters, and every generation setting.
#[pyclass(module = "brittle_dem._native", frozen)]
#[derive(Clone)]
struct SpecimenParams {
    p: dem_lab::specimen::SpecimenParams,
}

fn method_of(s: &str) -> PyResult<dem_lab::specimen::Method> {
    dem_lab::specimen::Method::parse(s)
        .ok_or_else(|| msg_err(format!("--method {s:?}: use traditional, orc or improved")))
}

#[pymethods]
impl SpecimenParams {
    /// The defaults of `dem specimen` for a `width` × `height` box (m, or strings with unit)
    /// and radii in [`r_min`, `r_max`]: density ρ (kg/m³), Young's modulus E (Pa) and tensile
    /// strength σ_t (Pa) give the micro-parameters. `overrides` (a dict of fields, as
    /// `to_dict` gives them) are applied last; the result is validated.
    #[new]
    #[pyo3(signature = (method, width, height, r_min, r_max, density, youngs, tensile, seed=1,
        overrides=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        method: &str,
        width: &Bound<'_, PyAny>,
        height: &Bound<'_, PyAny>,
        r_min: &Bound<'_, PyAny>,
        r_max: &Bound<'_, PyAny>,
        density: f64,
        youngs: f64,
        tensile: f64,
        seed: u64,
        overrides: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<SpecimenParams> {
        let p = dem_lab::specimen::SpecimenParams::new(
            method_of(method)?,
            length_m(width, "--width")?,
            length_m(height, "--height")?,
            length_m(r_min, "--r-min")?,
            length_m(r_max, "--r-max")?,
            density,
            youngs,
            tensile,
            seed,
        );
        SpecimenParams { p }.with(overrides)
    }
    /// `dem test … --specimen-from-model`: the model's density and micro-parameters (E = its
    /// contact modulus, σ_t = its grain-boundary tensile strength), as validation's Table 2.
    /// Run such a specimen with `model.with_r_mean((r_min + r_max) / 2)`.
    #[staticmethod]
    #[pyo3(signature = (model, width, height, r_min, r_max, method="traditional", seed=1,
        overrides=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_model(
        model: &LabModel,
        width: &Bound<'_, PyAny>,
        height: &Bound<'_, PyAny>,
        r_min: &Bound<'_, PyAny>,
        r_max: &Bound<'_, PyAny>,
        method: &str,
        seed: u64,
        overrides: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<SpecimenParams> {
        let m = &model.m;
        let mut p = dem_lab::specimen::SpecimenParams::new(
            method_of(method)?,
            length_m(width, "--width")?,
            length_m(height, "--height")?,
            length_m(r_min, "--r-min")?,
            length_m(r_max, "--r-max")?,
            m.density,
            m.micro.contact_modulus,
            m.micro.boundary_tensile,
            seed,
        );
        p.micro = m.micro.clone();
        SpecimenParams { p }.with(overrides)
    }
    /// Parameters from a dict (every field, as `to_dict` gives them).
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyAny>) -> PyResult<SpecimenParams> {
        let p: dem_lab::specimen::SpecimenParams = from_py(d, "specimen")?;
        p.validate().map_err(dem_err)?;
        Ok(SpecimenParams { p })
    }
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.p)
    }
    #[getter]
    fn method(&self) -> String {
        self.p.method.name().to_string()
    }
    #[getter]
    fn width(&self) -> f64 {
        self.p.width
    }
    #[getter]
    fn height(&self) -> f64 {
        self.p.height
    }
    #[getter]
    fn r_min(&self) -> f64 {
        self.p.r_min
    }
    #[getter]
    fn r_max(&self) -> f64 {
        self.p.r_max
    }
    #[getter]
    fn seed(&self) -> u64 {
        self.p.seed
    }
    fn __repr__(&self) -> String {
        format!(
            "SpecimenParams(method={}, {} x {} mm, r {}-{} mm, seed {})",
            self.p.method.name(),
            self.p.width * 1e3,
            self.p.height * 1e3,
            self.p.r_min * 1e3,
            self.p.r_max * 1e3,
            self.p.seed
        )
    }
}

impl SpecimenParams {
    /// `overrides` applied through the fields' serde names, then validated.
    fn with(self, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<SpecimenParams> {
        let mut p = self.p;
        if let Some(o) = overrides.filter(|o| !o.is_empty()) {
            let mut v = serde_json::to_value(&p).map_err(|e| msg_err(e.to_string()))?;
            let extra: serde_json::Map<String, serde_json::Value> =
                from_py(o.as_any(), "overrides")?;
            let obj = v.as_object_mut().expect("a struct serializes to an object");
            for (k, x) in extra {
                if !obj.contains_key(&k) && k != "grains" {
                    return Err(msg_err(format!(
                        "overrides: {k:?} is not a specimen parameter"
                    )));
                }
                obj.insert(k, x);
            }
            let de = serde_json::Value::Object(obj.clone());
            p = serde_path_to_error::deserialize(de)
                .map_err(|e| msg_err(format!("overrides: field {}: {}", e.path(), e.inner())))?;
        }
        p.validate().map_err(dem_err)?;
        Ok(SpecimenParams { p })
    }
}

/// A generated specimen: the relaxed, bonded packing and its summary (porosity, stress,
/// bonds, grains; the numbers `dem specimen` prints).
#[pyclass(module = "brittle_dem._native", frozen)]
struct Specimen {
    s: dem_lab::specimen::Specimen,
}

#[pymethods]
impl Specimen {
    /// The summary as a dict (`<stem>.summary.json`).
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.s.summary)
    }
    /// The summary as `dem specimen` prints it.
    fn summary_text(&self) -> String {
        self.s.summary.text()
    }
    #[getter]
    fn params(&self) -> SpecimenParams {
        SpecimenParams {
            p: self.s.params.clone(),
        }
    }
    /// Number of discs.
    #[getter]
    fn n_discs(&self) -> usize {
        self.s.world.state.discs.len()
    }
    /// Number of bonds (intact at generation).
    #[getter]
    fn n_bonds(&self) -> usize {
        self.s.world.bonds.as_ref().map_or(0, |b| b.len())
    }
    /// The discs, a dict of float64/int arrays of shape (n,): x, y, r (m), m (kg), group
    /// (grain id), id.
    fn discs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        state_dict(py, &self.s.world.state)
    }
    /// Writes the specimen file, `<stem>.summary.json` and `<stem>.scene.json` beside it, as
    /// `dem specimen --out path` does; `material` is the name the discs refer to.
    #[pyo3(signature = (path, material=None))]
    fn save(&self, path: PathBuf, material: Option<&str>) -> PyResult<()> {
        save_specimen(
            &self.s,
            material.unwrap_or(dem_lab::specimen::DEFAULT_MATERIAL),
            &path,
        )
    }
    fn __repr__(&self) -> String {
        format!(
            "Specimen({}, {} discs, {} bonds)",
            self.s.params.method.name(),
            self.n_discs(),
            self.n_bonds()
        )
    }
}

/// As `dem specimen` writes a specimen: the file, its summary and scene beside it.
fn save_specimen(s: &dem_lab::specimen::Specimen, material: &str, path: &Path) -> PyResult<()> {
    use dem_lab::specimen::io;
    if let Some(d) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(d).map_err(|e| io_err(format!("{}: {e}", d.display())))?;
    }
    io::save(s, material, path).map_err(dem_err)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let scene = io::example_scene(s, material, &name, 1000);
    let text = serde_json::to_string_pretty(&scene).map_err(|e| msg_err(e.to_string()))?;
    let stem = path.with_extension("");
    let scene_file = PathBuf::from(format!("{}.scene.json", stem.display()));
    io::write_atomic(&scene_file, &text).map_err(dem_err)?;
    Ok(())
}

fn state_dict<'py>(py: Python<'py>, st: &dem_core::state::State) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let c = &st.discs;
    d.set_item("id", PyArray1::from_slice(py, &c.id))?;
    d.set_item("x", PyArray1::from_slice(py, &c.x))?;
    d.set_item("y", PyArray1::from_slice(py, &c.y))?;
    d.set_item("theta", PyArray1::from_slice(py, &c.theta))?;
    d.set_item("vx", PyArray1::from_slice(py, &c.vx))?;
    d.set_item("vy", PyArray1::from_slice(py, &c.vy))?;
    d.set_item("omega", PyArray1::from_slice(py, &c.omega))?;
    d.set_item("r", PyArray1::from_slice(py, &c.r))?;
    d.set_item("m", PyArray1::from_slice(py, &c.m))?;
    d.set_item("group", PyArray1::from_slice(py, &c.group))?;
    Ok(d)
}

/// Generates a specimen (`dem specimen`) on `threads` threads (None: all; the result does not
/// depend on it). `callback(stage, fraction)` is told the stages as they go; Ctrl-C stops.
#[pyfunction]
#[pyo3(signature = (params, *, threads=None, callback=None))]
fn generate_specimen(
    py: Python<'_>,
    params: &SpecimenParams,
    threads: Option<usize>,
    callback: Option<PyObject>,
) -> PyResult<Specimen> {
    let p = params.p.clone();
    // (No callback: no hand-off to the calling thread at all.)
    let asks = callback.is_some();
    let out = drive(
        py,
        threads,
        move |ctl: &Ctl| {
            let mut last = String::new();
            dem_lab::specimen::generate(&p, &mut |pr| {
                ctl.check();
                if asks && pr.stage != last {
                    last = pr.stage.to_string();
                    if ctl.ask(Msg::Stage(last.clone(), pr.fraction)) == Reply::Stop {
                        ctl.stop();
                    }
                }
            })
        },
        |py, m| on_msg(py, m, callback.as_ref()),
    )?;
    out.map(|s| Specimen { s }).map_err(dem_err)
}

/// The user's callback for a message of the work (on the calling thread, with the GIL).
fn on_msg(py: Python<'_>, m: Msg, cb: Option<&PyObject>) -> PyResult<Reply> {
    let Some(cb) = cb else {
        return Ok(Reply::Go);
    };
    let r = match m {
        Msg::Stage(s, f) => cb.call1(py, (s, f))?,
        Msg::Progress(done, total) => cb.call1(py, (done, total))?,
        Msg::State(s) => {
            let d = state_dict(py, &s)?;
            d.set_item("step", s.step)?;
            d.set_item("time", s.time)?;
            cb.call1(py, (d,))?
        }
    };
    // `False` stops; anything else (None, True) goes on.
    Ok(match r.extract::<bool>(py) {
        Ok(false) => Reply::Stop,
        _ => Reply::Go,
    })
}

// ---------------------------------------------------------------------------------------
// The cutting test (`dem test cutting`).

/// A cutting test (`CuttingTest`, SI: depth, length m; speed m/s; angles rad). Built from a
/// dict of the fields to change (the `--params` file's form; the others are the defaults)
/// and checked.
#[pyclass(module = "brittle_dem._native", frozen)]
#[derive(Clone)]
struct CuttingTest {
    t: dem_lab::cutting::CheckedTest,
}

#[pymethods]
impl CuttingTest {
    /// A test from the `--params` JSON text (all fields optional).
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<CuttingTest> {
        let t = dem_lab::cutting::CuttingTest::from_params(text)
            .map_err(|e| msg_err(format!("params: {e}")))?;
        Ok(CuttingTest {
            t: t.check().map_err(dem_err)?,
        })
    }
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, self.t.test())
    }
    /// Depth of cut a_p (m).
    #[getter]
    fn depth(&self) -> f64 {
        self.t.test().depth
    }
    /// Cutting speed v (m/s).
    #[getter]
    fn speed(&self) -> f64 {
        self.t.test().speed
    }
    /// Cut length L (m).
    #[getter]
    fn length(&self) -> f64 {
        self.t.test().length
    }
    fn __repr__(&self) -> String {
        let t = self.t.test();
        format!(
            "CuttingTest(depth={} mm, speed={} m/s, length={} mm)",
            t.depth * 1e3,
            t.speed,
            t.length * 1e3
        )
    }
}

/// The result of a cut (`cutting.result.json`): forces (N, for the disc thickness), chips,
/// broken bonds, surface, cracks and the run's figures.
#[pyclass(module = "brittle_dem._native", frozen)]
struct CuttingResult {
    r: dem_lab::cutting::CuttingResult,
    out: PathBuf,
}

#[pymethods]
impl CuttingResult {
    /// The whole result as a dict (`cutting.result.json`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.r)
    }
    /// The summary `dem test cutting` prints (the same lines).
    fn report(&self) -> String {
        cut_report(&self.r)
    }
    /// The output folder.
    #[getter]
    fn out_dir(&self) -> PathBuf {
        self.out.clone()
    }
    /// Mean main (cutting) force over the steady window (N).
    #[getter]
    fn main_force_mean(&self) -> f64 {
        self.r.main_force.mean
    }
    /// Peak main force (N).
    #[getter]
    fn main_force_peak(&self) -> f64 {
        self.r.main_force.peak
    }
    /// Mean vertical (thrust) force over the steady window (N).
    #[getter]
    fn vertical_force_mean(&self) -> f64 {
        self.r.vertical_force.mean
    }
    /// Peak vertical force (N).
    #[getter]
    fn vertical_force_peak(&self) -> f64 {
        self.r.vertical_force.peak
    }
    /// Number of discs of the specimen.
    #[getter]
    fn discs(&self) -> usize {
        self.r.discs
    }
    /// Steps run.
    #[getter]
    fn steps(&self) -> u64 {
        self.r.run.steps
    }
    /// Wall time of the run (s).
    #[getter]
    fn wall_time_s(&self) -> f64 {
        self.r.run.wall_time_s
    }
    /// The steady window [start, end] of tool travel (m).
    #[getter]
    fn window(&self) -> (f64, f64) {
        (self.r.window[0], self.r.window[1])
    }
    fn __repr__(&self) -> String {
        format!(
            "CuttingResult({} discs, {} steps, main force mean {:.4} N, peak {:.4} N)",
            self.r.discs, self.r.run.steps, self.r.main_force.mean, self.r.main_force.peak
        )
    }
}

/// The summary lines of a cut (a shorter form of `dem test cutting`'s printout).
fn cut_report(r: &dem_lab::cutting::CuttingResult) -> String {
    let kn = 1e-3;
    let (m, v) = (&r.main_force, &r.vertical_force);
    let mut s = format!(
        "  discs {}, thickness {} m (forces for this thickness)\n",
        r.discs, r.thickness
    );
    s += &format!(
        "  steady window      travel {:.3}-{:.3} mm ({} rows)\n",
        r.window[0] * 1e3,
        r.window[1] * 1e3,
        m.samples
    );
    s += &format!(
        "  main force (kN)    peak {:.4}  mean {:.4}  sd {:.4}\n",
        m.peak * kn,
        m.mean * kn,
        m.sd * kn
    );
    s += &format!(
        "  vertical force (kN) peak {:.4}  mean {:.4}  sd {:.4}\n",
        v.peak * kn,
        v.mean * kn,
        v.sd * kn
    );
    s += &format!(
        "  run                {} steps, dt {:.4e} s, {:.1} s wall, {} threads\n",
        r.run.steps, r.run.dt, r.run.wall_time_s, r.run.threads
    );
    s
}

/// Writes `<out>/cutting.inputs.json` as `dem test cutting` does.
fn write_inputs(out: &Path, i: &dem_lab::cutting::Inputs) -> PyResult<()> {
    let text = serde_json::to_string_pretty(i).map_err(|e| msg_err(e.to_string()))? + "\n";
    std::fs::create_dir_all(out).map_err(|e| io_err(format!("{}: {e}", out.display())))?;
    dem_lab::specimen::io::write_atomic(&out.join(dem_lab::cutting::INPUTS_FILE), &text)
        .map_err(dem_err)
}

/// Runs a cutting test into the folder `out`, as `dem test cutting` does (the same files:
/// cutting.inputs.json, specimen.json (generated), cutting.scene.json, history.csv,
/// cutting.forces.csv, cutting.result.json …). The specimen is `specimen` (parameters: it is
/// generated into `<out>/specimen.json`) or `specimen_file` (a file of `dem specimen`);
/// `model` the material model (None: the specimen file's own). `callback(done, total)` (step
/// counts) is called every `every` steps or more (0: on every history row); returning False
/// stops the run (`DemStopped`; calling again with the same folder resumes it from its last
/// checkpoint), as does Ctrl-C (`KeyboardInterrupt`).
#[pyfunction]
#[pyo3(signature = (out, test, *, specimen=None, specimen_file=None, model=None, threads=None,
    callback=None, every=0, checkpoints=20, resume=true))]
#[allow(clippy::too_many_arguments)]
fn cut(
    py: Python<'_>,
    out: PathBuf,
    test: &CuttingTest,
    specimen: Option<&SpecimenParams>,
    specimen_file: Option<PathBuf>,
    model: Option<&LabModel>,
    threads: Option<usize>,
    callback: Option<PyObject>,
    every: u64,
    checkpoints: u64,
    resume: bool,
) -> PyResult<CuttingResult> {
    use dem_lab::cutting;
    let test = test.t.clone();
    let mut inputs = cutting::Inputs {
        specimen: specimen.map(|s| s.p.clone()),
        specimen_file: specimen_file.as_ref().map(|p| p.display().to_string()),
        model: model.map(|m| m.m.clone()),
        flat_joint: None,
        test: test.test().clone(),
    };
    let path = match (&inputs.specimen, &specimen_file) {
        (Some(_), Some(_)) => {
            return Err(msg_err(
                "give specimen (parameters) or specimen_file, not both",
            ))
        }
        (None, None) => return Err(msg_err("give specimen (parameters) or specimen_file")),
        (Some(p), None) => {
            cutting::check_geometry(test.test(), [0.0, p.width, 0.0, p.height]).map_err(|e| {
                msg_err(format!(
                    "{e} (the specimen to be generated, width {} mm, height {} mm)",
                    p.width * 1e3,
                    p.height * 1e3
                ))
            })?;
            out.join("specimen.json")
        }
        (None, Some(f)) => f.clone(),
    };
    write_inputs(&out, &inputs)?;
    let ro = cutting::CuttingRunOptions {
        checkpoints,
        resume,
        ..cutting::CuttingRunOptions::default()
    };
    let out2 = out.clone();
    // (No callback: no hand-off to the calling thread at all.)
    let asks = callback.is_some();
    let r = drive(
        py,
        threads,
        move |ctl: &Ctl| -> PyResult<Result<cutting::CuttingResult, String>> {
            if let Some(p) = &inputs.specimen {
                let s = dem_lab::specimen::generate(p, &mut |_| ctl.check());
                let s = match s {
                    Ok(s) => s,
                    Err(e) => return Ok(Err(e.to_string())),
                };
                save_specimen(&s, dem_lab::specimen::DEFAULT_MATERIAL, &path)?;
            }
            let info = match cutting::SpecimenInfo::read(&path) {
                Ok(i) => i,
                Err(e) => return Err(dem_err(e)),
            };
            cutting::check_geometry(&test, info.extent)
                .map_err(|e| msg_err(format!("{e} (specimen {})", path.display())))?;
            let model = match inputs.model.clone() {
                Some(m) => m,
                None => {
                    let m = cutting::model_from_specimen(&path).map_err(dem_err)?;
                    inputs.model = Some(m.clone());
                    write_inputs(&out2, &inputs)?;
                    m
                }
            };
            let mut next = 0u64;
            let r = cutting::run_with(&test, &model, &info, &out2, &ro, &mut |done, total| {
                ctl.check();
                if asks && (done >= next || done == total) {
                    next = done + every;
                    if ctl.ask(Msg::Progress(done, total)) == Reply::Stop {
                        ctl.stop();
                    }
                }
            });
            r.map(Ok).map_err(dem_err)
        },
        |py, m| on_msg(py, m, callback.as_ref()),
    )??;
    let r = r.map_err(msg_err)?;
    Ok(CuttingResult { r, out })
}

// ---------------------------------------------------------------------------------------
// The quasi-static lab tests (`dem test ucs | brazilian | bending | senb`).

/// The result of a quasi-static lab test (`<name>.result.json`: the test, model, specimen,
/// what the analysis measured, the run's facts) and where its outputs are.
#[pyclass(module = "brittle_dem._native", frozen)]
struct LabResult {
    outcome: serde_json::Value,
    name: String,
    out: PathBuf,
}

#[pymethods]
impl LabResult {
    /// The whole result as a dict (`<name>.result.json`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.outcome)
    }
    /// What the analysis measured (the result's `result`: strengths in Pa, moduli in Pa ...).
    #[getter]
    fn result<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.outcome["result"])
    }
    /// The test's name (its files' stem).
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }
    /// The run's output folder (`<out>/<name>.out`: history.csv, summary.json, ...).
    #[getter]
    fn run_dir(&self) -> PathBuf {
        self.out.join(format!("{}.out", self.name))
    }
    /// The folder of the test's files.
    #[getter]
    fn out_dir(&self) -> PathBuf {
        self.out.clone()
    }
    fn __repr__(&self) -> String {
        format!("LabResult({}: {})", self.name, self.outcome["result"])
    }
}

/// `T::default()` with the fields of `d` (the test's JSON form), as the typed test.
fn test_of<T: serde::Serialize + serde::de::DeserializeOwned + Default>(
    d: Option<&Bound<'_, PyDict>>,
    what: &str,
) -> PyResult<T> {
    let Some(d) = d.filter(|d| !d.is_empty()) else {
        return Ok(T::default());
    };
    let v: serde_json::Value = from_py(d.as_any(), what)?;
    serde_path_to_error::deserialize(v)
        .map_err(|e| msg_err(format!("{what}: field {}: {}", e.path(), e.inner())))
}

/// Runs the quasi-static test `test` as `dem test <kind>` does: the specimen of `p` in the
/// test's shape (generated into `<out>/<name>.specimen.json`, or reused when the same
/// parameters made it there before), then the test beside it.
#[allow(clippy::too_many_arguments)]
fn quasi_static<T>(
    py: Python<'_>,
    out: PathBuf,
    test: T,
    p: dem_lab::specimen::SpecimenParams,
    model: Option<dem_lab::LabModel>,
    threads: Option<usize>,
    callback: Option<PyObject>,
    every: u64,
) -> PyResult<LabResult>
where
    T: dem_lab::tests::QuasiStatic + Send + Sync,
{
    let model = model.unwrap_or_else(|| dem_lab::LabModel::from_params(&p));
    let name = test.name().to_string();
    let file = out.join(format!("{name}.specimen.json"));
    std::fs::create_dir_all(&out).map_err(|e| io_err(format!("{}: {e}", out.display())))?;
    // (No callback: no hand-off to the calling thread at all.)
    let asks = callback.is_some();
    let v = drive(
        py,
        threads,
        move |ctl: &Ctl| -> PyResult<serde_json::Value> {
            let spec =
                dem_lab::specimen::cache::prepare(&p, test.shape(), &file, &mut |_| ctl.check())
                    .map_err(dem_err)?;
            let mut next = 0u64;
            let o = dem_lab::tests::run(&test, &model, &spec, &mut |done, total| {
                ctl.check();
                if asks && (done >= next || done == total) {
                    next = done + every;
                    if ctl.ask(Msg::Progress(done, total)) == Reply::Stop {
                        ctl.stop();
                    }
                }
            })
            .map_err(dem_err)?;
            serde_json::to_value(&o).map_err(|e| msg_err(e.to_string()))
        },
        |py, m| on_msg(py, m, callback.as_ref()),
    )??;
    Ok(LabResult {
        outcome: v,
        name,
        out,
    })
}

/// A quasi-static lab test (`dem test ucs | brazilian | bending | senb`) into the folder `out`:
/// `test` the fields to change from the test's defaults (SI units: its JSON form, e.g.
/// `{"width": 0.01, "height": 0.02}` for ucs, `{"diameter": 0.01}` for brazilian), on a
/// specimen of the parameters `specimen` (the box is the test's shape), with `model` (None:
/// the specimen parameters' own, as without `--model`). `callback(done, total)` as for
/// `cut`.
#[pyfunction]
#[pyo3(signature = (kind, out, specimen, *, test=None, model=None, threads=None, callback=None,
    every=0))]
#[allow(clippy::too_many_arguments)]
fn lab_test(
    py: Python<'_>,
    kind: &str,
    out: PathBuf,
    specimen: &SpecimenParams,
    test: Option<&Bound<'_, PyDict>>,
    model: Option<&LabModel>,
    threads: Option<usize>,
    callback: Option<PyObject>,
    every: u64,
) -> PyResult<LabResult> {
    use dem_lab::tests::ucs::UcsTest;
    use dem_lab::tests::{bending::BendingTest, brazilian::BrazilianTest, senb::SenbTest};
    let p = specimen.p.clone();
    let m = model.map(|m| m.m.clone());
    let r_mean = 0.5 * (p.r_min + p.r_max);
    match kind {
        "ucs" => {
            let t: UcsTest = test_of(test, "ucs")?;
            t.validate().map_err(dem_err)?;
            t.check_geometry([t.width, t.height], r_mean)
                .map_err(dem_err)?;
            quasi_static(py, out, t, p, m, threads, callback, every)
        }
        "brazilian" => {
            let t: BrazilianTest = test_of(test, "brazilian")?;
            t.validate().map_err(dem_err)?;
            t.check_geometry(t.diameter, r_mean).map_err(dem_err)?;
            quasi_static(py, out, t, p, m, threads, callback, every)
        }
        "bending" => {
            let t: BendingTest = test_of(test, "bending")?;
            t.validate().map_err(dem_err)?;
            t.check_geometry([t.length, t.height], r_mean)
                .map_err(dem_err)?;
            quasi_static(py, out, t, p, m, threads, callback, every)
        }
        "senb" => {
            let t: SenbTest = test_of(test, "senb")?;
            t.validate().map_err(dem_err)?;
            t.check_geometry(r_mean).map_err(dem_err)?;
            quasi_static(py, out, t, p, m, threads, callback, every)
        }
        k => Err(msg_err(format!(
            "{k:?} is not a quasi-static lab test: ucs, brazilian, bending or senb (cuts: cut)"
        ))),
    }
}

// ---------------------------------------------------------------------------------------
// Scenes (`dem run`).

/// How a scene run ended, with its summary (`summary.json`).
#[pyclass(module = "brittle_dem._native", frozen)]
struct RunResult {
    summary: dem_core::output::summary::RunSummary,
    ending: &'static str,
    out: PathBuf,
}

#[pymethods]
impl RunResult {
    /// `completed`, `max_steps`, `failure` (run.stop_after_peak) or `stopped` (the callback
    /// returned False).
    #[getter]
    fn ending(&self) -> &'static str {
        self.ending
    }
    /// The summary as a dict (`summary.json`).
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.summary)
    }
    /// The output folder.
    #[getter]
    fn out_dir(&self) -> PathBuf {
        self.out.clone()
    }
    /// Steps of this run.
    #[getter]
    fn steps(&self) -> u64 {
        self.summary.steps
    }
    fn __repr__(&self) -> String {
        format!(
            "RunResult({}, {} steps, {:.2} s)",
            self.ending, self.summary.steps, self.summary.wall_time_s
        )
    }
}

/// Runs a scene (`dem run`): `scene_json` the `dem.scene/1` text, `scene_file` where it stands
/// (relative paths in it resolve from there; the file itself is not read), output to `out`
/// (None: the scene's `outputs.dir`). `callback(state)` gets a dict of numpy copies of the
/// discs (x, y, vx, … of shape (n,)) with `step` and `time` every `every` steps; returning
/// False ends the run there (its outputs written). Ctrl-C raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (scene_json, scene_file, *, out=None, max_steps=None, threads=None,
    callback=None, every=0, restart=None))]
#[allow(clippy::too_many_arguments)]
fn run_scene(
    py: Python<'_>,
    scene_json: String,
    scene_file: PathBuf,
    out: Option<PathBuf>,
    max_steps: Option<u64>,
    threads: Option<usize>,
    callback: Option<PyObject>,
    every: u64,
    restart: Option<PathBuf>,
) -> PyResult<RunResult> {
    use dem_core::output::driver::{Ending, RunOptions, Simulation, StepHook};
    let scene = dem_core::scene::parse(&scene_json, &scene_file).map_err(dem_err)?;
    let out = out.unwrap_or_else(|| scene.outputs.dir.clone());
    let opts = RunOptions {
        out_dir: Some(out.clone()),
        restart,
        max_steps,
    };
    let want_state = callback.is_some() && every > 0;
    let r = drive(
        py,
        threads,
        move |ctl: &Ctl| -> PyResult<(dem_core::output::summary::RunSummary, &'static str)> {
            let mut sim = Simulation::new(scene, &opts).map_err(dem_err)?;
            let steps = sim.total_steps();
            if steps > dem_lab::run::STEP_LIMIT {
                return Err(msg_err(format!(
                    "{}: {steps} steps, more than {} (dem run refuses them without --yes)",
                    sim.scene.file.display(),
                    dem_lab::run::STEP_LIMIT
                )));
            }
            let stopped = std::rc::Rc::new(std::cell::Cell::new(false));
            if want_state {
                let (s1, s2) = (stopped.clone(), stopped.clone());
                let ctl = ctl.clone();
                sim.set_hook(StepHook {
                    every,
                    run: Box::new(move |w| {
                        if ctl.ask(Msg::State(Box::new(w.state.clone()))) == Reply::Stop {
                            s1.set(true);
                        }
                        Ok(())
                    }),
                    stop: Some(Box::new(move |_| s2.get())),
                });
            }
            let (summary, ending) = sim.run(&mut |_, _| ctl.check()).map_err(dem_err)?;
            let e = match ending {
                Ending::Completed => "completed",
                Ending::MaxSteps => "max_steps",
                Ending::Failure if stopped.get() => "stopped",
                Ending::Failure => "failure",
            };
            Ok((summary, e))
        },
        |py, m| on_msg(py, m, callback.as_ref()),
    )??;
    Ok(RunResult {
        summary: r.0,
        ending: r.1,
        out,
    })
}

// ---------------------------------------------------------------------------------------
// Pictures (`dem render`).

#[allow(clippy::too_many_arguments)]
fn render_job(
    input: PathBuf,
    out: PathBuf,
    width: u32,
    color: &str,
    bonds: bool,
    broken: bool,
    view: Option<[f64; 4]>,
    speed_max: Option<f64>,
    outline: Option<PathBuf>,
) -> PyResult<dem_render::Job> {
    use dem_render::ColorBy;
    if !(1..=dem_render::MAX_WIDTH).contains(&width) {
        return Err(msg_err(format!(
            "{width} px: the width must be 1 to {} pixels",
            dem_render::MAX_WIDTH
        )));
    }
    let color = match color.trim() {
        "grain" => ColorBy::Grain,
        "group" => ColorBy::Group,
        "speed" => ColorBy::Speed,
        "material" => ColorBy::Material,
        other => {
            return Err(msg_err(format!(
                "{other:?} is not a colouring: grain, group, speed or material"
            )))
        }
    };
    if let Some([x0, x1, y0, y1]) = view {
        if !(x0 < x1 && y0 < y1 && [x0, x1, y0, y1].iter().all(|v| v.is_finite())) {
            return Err(msg_err("need finite XMIN < XMAX and YMIN < YMAX (m)"));
        }
    }
    Ok(dem_render::Job {
        input,
        out: Some(out),
        outline,
        fps: 10,
        options: dem_render::Options {
            width,
            color,
            bonds,
            broken,
            view,
            speed_max,
            rgb: false,
        },
    })
}

/// Draws a checkpoint, specimen, template or VTK snapshot to the PNG `out` (`dem render`);
/// returns the picture's size and frame: width, height (px), discs, px_per_m, c0, r0 (a model
/// point (x, y) in m lands at column c0 + px_per_m·x, row r0 − px_per_m·y). `view` is
/// [xmin, xmax, ymin, ymax] in m.
#[pyfunction]
#[pyo3(signature = (input, out, *, width=1200, color="grain", bonds=false, broken=false,
    view=None, speed_max=None, outline=None))]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
    py: Python<'py>,
    input: PathBuf,
    out: PathBuf,
    width: u32,
    color: &str,
    bonds: bool,
    broken: bool,
    view: Option<[f64; 4]>,
    speed_max: Option<f64>,
    outline: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    if out
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case("png"))
    {
        return Err(msg_err(format!(
            "{}: give a .png file (animations: dem render)",
            out.display()
        )));
    }
    let job = render_job(
        input, out, width, color, bonds, broken, view, speed_max, outline,
    )?;
    let mut notes = Vec::new();
    let w = py
        .allow_threads(|| dem_render::run(&job, &mut |n| notes.push(n.to_string())))
        .map_err(dem_err)?;
    let d = PyDict::new(py);
    if let dem_render::Written::Picture {
        out,
        width,
        height,
        discs,
        frame,
        ..
    } = w
    {
        d.set_item("out", out)?;
        d.set_item("width", width)?;
        d.set_item("height", height)?;
        d.set_item("discs", discs)?;
        d.set_item("px_per_m", frame.s)?;
        d.set_item("c0", frame.c0)?;
        d.set_item("r0", frame.r0)?;
    }
    d.set_item("notes", notes)?;
    Ok(d)
}

/// As [`render`], the PNG's bytes instead of a file.
#[pyfunction]
#[pyo3(signature = (input, *, width=1200, color="grain", bonds=false, broken=false,
    view=None, speed_max=None, outline=None))]
#[allow(clippy::too_many_arguments)]
fn render_png<'py>(
    py: Python<'py>,
    input: PathBuf,
    width: u32,
    color: &str,
    bonds: bool,
    broken: bool,
    view: Option<[f64; 4]>,
    speed_max: Option<f64>,
    outline: Option<PathBuf>,
) -> PyResult<Bound<'py, PyBytes>> {
    let dir = std::env::temp_dir().join(format!(
        "brittle-dem-render-{}-{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).map_err(|e| io_err(format!("{}: {e}", dir.display())))?;
    let out = dir.join("picture.png");
    let job = render_job(
        input,
        out.clone(),
        width,
        color,
        bonds,
        broken,
        view,
        speed_max,
        outline,
    )?;
    let r = py.allow_threads(|| dem_render::run(&job, &mut |_| {}));
    let bytes = r
        .map_err(dem_err)
        .and_then(|_| std::fs::read(&out).map_err(|e| io_err(format!("{}: {e}", out.display()))));
    let _ = std::fs::remove_dir_all(&dir);
    Ok(PyBytes::new(py, &bytes?))
}

static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

// ---------------------------------------------------------------------------------------
// Studies (`dem sweep`): the table and status of a sweep folder.

/// A dem-run error as the package's exception (its file errors as `DemIOError`).
fn run_err(e: dem_run::Error) -> PyErr {
    let io = e.kind() == dem_run::ErrorKind::Io;
    Python::with_gil(|py| {
        exc(
            py,
            if io { "DemIOError" } else { "DemError" },
            e.to_string(),
        )
    })
}

/// The table of the sweep folder `dir` (`dem sweep collect --out table.json`): one row per
/// case (axis values, collected outputs, status, times) and aggregates over seeds.
/// `timing=False` leaves out the wall and CPU times (`--no-timing`).
#[pyfunction]
#[pyo3(signature = (dir, *, timing=true))]
fn sweep_table<'py>(py: Python<'py>, dir: PathBuf, timing: bool) -> PyResult<Bound<'py, PyAny>> {
    let v = py
        .allow_threads(|| dem_run::collect::table(&dir, timing))
        .map_err(run_err)?;
    to_py(py, &v)
}

/// The lines `dem sweep status DIR` prints: the counts, a line per case, the time taken.
#[pyfunction]
fn sweep_status(dir: PathBuf) -> PyResult<Vec<String>> {
    dem_run::collect::status(&dir).map_err(run_err)
}

/// The library's version and the schema names it writes.
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Template>()?;
    m.add_class::<LabModel>()?;
    m.add_class::<SpecimenParams>()?;
    m.add_class::<Specimen>()?;
    m.add_class::<CuttingTest>()?;
    m.add_class::<CuttingResult>()?;
    m.add_class::<RunResult>()?;
    m.add_function(wrap_pyfunction!(template_from_points, m)?)?;
    m.add_function(wrap_pyfunction!(template_from_file, m)?)?;
    m.add_function(wrap_pyfunction!(read_outline, m)?)?;
    m.add_function(wrap_pyfunction!(generate_specimen, m)?)?;
    m.add_function(wrap_pyfunction!(cut, m)?)?;
    m.add_function(wrap_pyfunction!(lab_test, m)?)?;
    m.add_class::<LabResult>()?;
    m.add_function(wrap_pyfunction!(run_scene, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(render_png, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_table, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_status, m)?)?;
    Ok(())
}
