//! One grain, outline to template: properties → fill → mass solve (→ repair) → template.

use crate::cover::Circle;
use crate::descriptors::{shape_descriptors, ShapeDescriptors};
use crate::fill::{FillParams, Filler, StopReason};
use crate::lattice::{lattice_fill, MAX_LATTICE_NODES};
use crate::massfit::{
    fit_masses, fit_masses_interior, fit_masses_plain, residuals, MassFitError, MassTargets,
};
use crate::outline::Outline;
use crate::props::{polygon_props, PolygonProps};
use crate::template::{
    CoverRecord, Disc, FillRecord, LatticeRecord, MassProps, Method, Shape, Source, Template,
    SCHEMA, SCHEMA_LATTICE,
};
use serde::{Deserialize, Serialize};

/// Discs are sized from the exact distance to the outline, so they are inside up to rounding;
/// this (relative to the equivalent radius) is the tolerance the template states and tests check.
pub const INSIDE_TOL: f64 = 1e-12;

/// The largest [`ClumpParams::raster`]: cells along a grain's longer side.
///
/// The filler keeps, per grain being filled, two flags and a squared distance per raster cell
/// (10 bytes) and sweeps every cell for every disc (distance transform, candidate search); it
/// refines the raster up to 4× where it is too coarse. At 1024 that is at most 4096 × 4096 =
/// 16.8 million cells, 168 MB, for a square grain (the default 64 needs 0.66 MB); the
/// `--raster 100000` of issue 20 asked for 9.4 GB at once and aborted.
pub const MAX_RASTER: usize = 1024;

/// The largest [`ClumpParams::max_discs`].
///
/// Every disc of the fill costs a sweep of the raster and the exact union area of all discs so
/// far (`O(k²)` for `k` discs, [`crate::cover::union_area`]), so a fill of `k` discs costs
/// `O(k·cells + k³)`; the mass fit's active-set methods are `O(k²)` to `O(k³)`. A thousand discs
/// is far beyond what a DEM clump uses (Ye & Xu 2010: up to 9 for cutting, the default 64).
pub const MAX_DISCS: usize = 1000;

/// A length given absolutely (m) or as a fraction of the grain's equivalent radius.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Length {
    Metres(f64),
    OfReq(f64),
}

/// `0.02 r_eq` or `0.1 mm` (as the `dem clump` flags take them; the report prints it).
impl std::fmt::Display for Length {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Length::Metres(v) => write!(f, "{} mm", v * 1e3),
            Length::OfReq(x) => write!(f, "{x} r_eq"),
        }
    }
}

impl Length {
    pub fn resolve(self, r_eq: f64) -> f64 {
        match self {
            Length::Metres(v) => v,
            Length::OfReq(f) => f * r_eq,
        }
    }
}

/// Everything that controls how a grain becomes a clump.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ClumpParams {
    pub method: Method,
    /// Grain density ρ (kg/m³).
    pub density: f64,
    /// Disc thickness t (m); 2D masses are ρ·t·area (PFC2D convention, default 1 m).
    pub thickness: f64,
    /// Target area cover (0.95 in Ye & Xu 2010).
    pub cover: f64,
    pub r_min: Length,
    pub r_max: Length,
    pub max_discs: usize,
    /// Raster cells along the grain's longer side for steering the fill.
    pub raster: usize,
    /// Lower bound of solved masses as a fraction of their prior (improved method).
    pub mass_floor: f64,
    /// Largest accepted relative residual of the mass fit.
    pub tolerance: f64,
    /// Largest number of discs added to make an infeasible mass fit feasible.
    pub max_repairs: usize,
    /// Rescue a mass fit the plain solve finds infeasible: refit with the inertia row centred
    /// and scaled ([`crate::massfit::fit_masses`]) and, if repair discs as far out as they fit
    /// do not help, put them on the ring that carries the inertia deficit (`ring_levels`).
    /// `false` keeps the fit of the versions before 2026-11-27 (which fails on circles of more
    /// than ~1,700 points): specimens use it, so that a seed builds the specimen its run keys
    /// were made with (a rescued grain template changes the specimen: Table 2's improved
    /// seeds 7 and 8 each have a grain whose template failed).
    #[serde(default = "rescue_default", skip_serializing_if = "is_rescue_default")]
    pub rescue: bool,
    /// The lattice of `method: lattice` ([`crate::lattice`]); `None` for the other methods.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lattice: Option<LatticeParams>,
}

/// Parameters of the lattice fill (`dem clump --method lattice --spacing S`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LatticeParams {
    /// Node spacing S: metres or a fraction of the grain's equivalent radius.
    pub spacing: Length,
    /// Node disc radius as a fraction of S/2, in (0, 1] (1: neighbours touch).
    pub node_radius: f64,
}

fn rescue_default() -> bool {
    true
}

fn is_rescue_default(b: &bool) -> bool {
    *b
}

impl Default for ClumpParams {
    fn default() -> Self {
        ClumpParams {
            method: Method::Improved,
            density: 2650.0,
            thickness: 1.0,
            cover: 0.95,
            r_min: Length::OfReq(0.02),
            r_max: Length::OfReq(1.0),
            max_discs: 64,
            raster: 64,
            mass_floor: 1e-3,
            tolerance: 1e-10,
            max_repairs: 8,
            rescue: true,
            lattice: None,
        }
    }
}

/// Why a grain could not be turned into a template.
#[derive(Debug, thiserror::Error)]
pub enum ClumpError {
    #[error(transparent)]
    Outline(Box<crate::error::OutlineError>),
    #[error("{file}: invalid parameter: {reason}")]
    Params { file: String, reason: String },
    #[error("{file}: no disc of radius >= r_min = {r_min:.3e} m fits inside the outline")]
    NoDisc { file: String, r_min: f64 },
    #[error("{file}: mass fit failed with {discs} discs after {repairs} repair discs: {source}")]
    MassFit {
        file: String,
        discs: usize,
        repairs: usize,
        source: MassFitError,
    },
    #[error(transparent)]
    Template(#[from] crate::template::TemplateError),
    /// The lattice cannot be built for this grain (`field`: `spacing` or `node-radius`).
    #[error("{file}: {field}: {reason}")]
    Lattice {
        file: String,
        field: &'static str,
        reason: String,
    },
}

impl From<crate::error::OutlineError> for ClumpError {
    fn from(e: crate::error::OutlineError) -> Self {
        ClumpError::Outline(Box::new(e))
    }
}

/// A parameter of [`ClumpParams`] out of its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{name} {value}: {reason}")]
pub struct ParamError {
    /// The parameter, named as the `dem clump` flag (`cover`, `density`, `thickness`,
    /// `max-discs`, `raster`, `rmin`, `rmax`, `spacing`, `node-radius`) or the field
    /// (`mass_floor`, `tolerance`).
    pub name: &'static str,
    pub value: String,
    pub reason: String,
}

impl ClumpParams {
    /// Checks the values that do not depend on the grain, so a batch can refuse bad
    /// parameters once instead of failing every grain.
    pub fn check(&self) -> Result<(), ParamError> {
        let bad = |name, value: &dyn std::fmt::Display, reason: &str| {
            Err(ParamError {
                name,
                value: value.to_string(),
                reason: reason.to_string(),
            })
        };
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(self.density) {
            return bad("density", &self.density, "must be positive");
        }
        if !positive(self.thickness) {
            return bad("thickness", &self.thickness, "must be positive");
        }
        if !(self.cover > 0.0 && self.cover < 1.0) {
            return bad("cover", &self.cover, "must be in (0, 1)");
        }
        if self.max_discs == 0 {
            return bad("max-discs", &self.max_discs, "must be at least 1");
        }
        if self.max_discs > MAX_DISCS {
            return bad(
                "max-discs",
                &self.max_discs,
                &format!(
                    "at most {MAX_DISCS} discs per clump: every disc sweeps the fill's raster \
                     and recomputes the exact union of all discs so far, so the work grows as \
                     the cube of the disc count"
                ),
            );
        }
        if self.raster == 0 {
            return bad("raster", &self.raster, "must be at least 1");
        }
        if self.raster > MAX_RASTER {
            // Up to (4·raster)² cells of 10 bytes for a square grain (the fill refines ×2, ×4).
            let bytes = (4.0 * self.raster as f64).powi(2) * 10.0;
            return bad(
                "raster",
                &self.raster,
                &format!(
                    "at most {MAX_RASTER} cells along a grain's longer side: the fill refines the \
                     raster up to 4x and keeps 10 bytes per cell, {} per grain at this value \
                     ({} at {MAX_RASTER}), and sweeps every cell for every disc",
                    human_bytes(bytes),
                    human_bytes((4.0 * MAX_RASTER as f64).powi(2) * 10.0)
                ),
            );
        }
        if !(self.mass_floor > 0.0 && self.mass_floor < 1.0) {
            return bad("mass_floor", &self.mass_floor, "must be in (0, 1)");
        }
        if !positive(self.tolerance) {
            return bad("tolerance", &self.tolerance, "must be positive");
        }
        for (name, l) in [("rmin", self.r_min), ("rmax", self.r_max)] {
            let (Length::Metres(v) | Length::OfReq(v)) = l;
            if !positive(v) {
                return bad(name, &v, "must be positive");
            }
        }
        match (self.method, self.lattice) {
            (Method::Lattice, None) => {
                return bad(
                    "spacing",
                    &"(none)",
                    "the lattice method needs a node spacing",
                )
            }
            (Method::Lattice, Some(l)) => {
                let (Length::Metres(s) | Length::OfReq(s)) = l.spacing;
                if !positive(s) {
                    return bad("spacing", &s, "must be positive and finite");
                }
                let f = l.node_radius;
                if !(f.is_finite() && f > 0.0 && f <= 1.0) {
                    return bad("node-radius", &f, "a fraction of S/2 in (0, 1]");
                }
            }
            (_, Some(_)) => {
                return bad(
                    "spacing",
                    &self.method.name(),
                    "a spacing is for the lattice method only",
                )
            }
            (_, None) => {}
        }
        // Of one kind the two radii compare for every grain; mixed, per grain.
        match (self.r_min, self.r_max) {
            (Length::Metres(a), Length::Metres(b)) | (Length::OfReq(a), Length::OfReq(b))
                if a > b =>
            {
                bad("rmin", &a, &format!("larger than rmax {b}"))
            }
            _ => Ok(()),
        }
    }
}

/// `1.6 TB`, `168 MB`: a byte count in decimal units, three significant digits.
fn human_bytes(b: f64) -> String {
    let units = ["B", "kB", "MB", "GB", "TB", "PB"];
    let mut v = b;
    let mut k = 0;
    while v >= 1000.0 && k + 1 < units.len() {
        v /= 1000.0;
        k += 1;
    }
    format!("{} {}", format_sig3(v), units[k])
}

/// Three significant digits, no trailing zeros: 168, 16.8, 1.68, 1.6.
fn format_sig3(v: f64) -> String {
    let decimals = if v >= 100.0 {
        0
    } else if v >= 10.0 {
        1
    } else {
        2
    };
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn check_params(p: &ClumpParams, file: &str) -> Result<(), ClumpError> {
    p.check().map_err(|e| ClumpError::Params {
        file: file.to_string(),
        reason: e.to_string(),
    })
}

/// The improved method's mass solve for one grain.
struct Solve<'a> {
    p: &'a ClumpParams,
    t: &'a MassTargets,
    r_min: f64,
    r_max: f64,
    /// The grain's squared radius of gyration J/A (m²).
    k2: f64,
    file: &'a str,
}

impl Solve<'_> {
    /// Fits the masses of the filler's discs; while that is infeasible, adds a repair disc and
    /// fits again (at most `max_repairs` of them, never beyond `max_discs` discs). Repair discs
    /// go as far out as they can ([`Filler::repair_disc`]), or with `ring = Some(s)` onto the
    /// ring `r²/2 + d² = s` ([`Filler::ring_repair_disc`]). Returns the discs with their
    /// masses and the number of repair discs.
    fn run(
        &self,
        filler: &mut Filler,
        ring: Option<f64>,
    ) -> Result<(Vec<Disc>, usize), ClumpError> {
        let p = self.p;
        let uniform = |d: &Circle| p.density * p.thickness * std::f64::consts::PI * d.r * d.r;
        let mut repairs = 0;
        loop {
            let xyr: Vec<[f64; 3]> = filler.discs.iter().map(|d| [d.x, d.y, d.r]).collect();
            let prior: Vec<f64> = filler.discs.iter().map(uniform).collect();
            let fit = if p.rescue {
                fit_masses
            } else {
                fit_masses_plain
            };
            match fit(&xyr, &prior, self.t, p.mass_floor, p.tolerance) {
                Ok((m, _)) => {
                    let discs = filler
                        .discs
                        .iter()
                        .zip(m)
                        .map(|(d, m)| Disc {
                            x: d.x,
                            y: d.y,
                            r: d.r,
                            m,
                        })
                        .collect();
                    return Ok((discs, repairs));
                }
                Err(e) => {
                    let fail = |e| ClumpError::MassFit {
                        file: self.file.to_string(),
                        discs: filler.discs.len(),
                        repairs,
                        source: e,
                    };
                    if repairs >= p.max_repairs || filler.discs.len() >= p.max_discs {
                        return Err(fail(e));
                    }
                    let d = match ring {
                        None => filler.repair_disc(self.r_min, self.r_max, self.k2),
                        Some(s) => filler.ring_repair_disc(self.r_min, self.k2, s),
                    };
                    match d {
                        Some(d) => filler.place(d),
                        None => return Err(fail(e)),
                    }
                    repairs += 1;
                }
            }
        }
    }
}

/// The rings `s = k2 + Δ` (m²) tried for repair discs when the far-out ones fail.
///
/// With uniform-density masses `m0_i ∝ r_i²` the fill discs reach `s̄ = Σ r_i² s_i / Σ r_i²`;
/// the deficit `D = k2 − s̄` must be carried by repair discs with `s > k2`. A repair disc of
/// radius `r_min` has the prior share `q = r_min² / (Σ r_i² + r_min²)`; on the ring `Δ = D/q` it
/// carries the deficit with about its prior mass (two of them, balancing the centroid, with
/// half each), 500 times its floor at the default `mass_floor`. `Δ` is tried at 1, 1/8, 8, 1/64
/// and 64 times that. None when the discs do not fall short of the inertia (`D ≤ 0`).
fn ring_levels(discs: &[Circle], r_min: f64, k2: f64) -> Vec<f64> {
    let w: f64 = discs.iter().map(|d| d.r * d.r).sum();
    let s_bar = discs
        .iter()
        .map(|d| d.r * d.r * (0.5 * d.r * d.r + d.x * d.x + d.y * d.y))
        .sum::<f64>()
        / w;
    let deficit = k2 - s_bar;
    if !(deficit > 0.0 && deficit.is_finite()) {
        return Vec::new();
    }
    let delta = deficit * (w + r_min * r_min) / (r_min * r_min);
    [1.0, 0.125, 8.0, 1.0 / 64.0, 64.0]
        .iter()
        .map(|f| k2 + f * delta)
        .collect()
}

/// Turns one outline into a clump template.
pub fn make_template(outline: &Outline, p: &ClumpParams) -> Result<Template, ClumpError> {
    let file = outline.source.clone();
    check_params(p, &file)?;
    let props = polygon_props(&outline.points);
    let shape = shape_descriptors(&outline.points, &props);
    let c = props.centroid;
    let pts: Vec<[f64; 2]> = outline
        .points
        .iter()
        .map(|q| [q[0] - c[0], q[1] - c[1]])
        .collect();
    let r_eq = shape.r_eq;
    if p.method == Method::Lattice {
        return lattice_template(outline, p, &pts, &props, &shape);
    }
    let (r_min, r_max) = (p.r_min.resolve(r_eq), p.r_max.resolve(r_eq));
    if !(r_min > 0.0 && r_max >= r_min) {
        return Err(ClumpError::Params {
            file,
            reason: format!(
                "need 0 < r_min <= r_max, got r_min = {r_min:e} m, r_max = {r_max:e} m"
            ),
        });
    }
    let fp = FillParams {
        cover: p.cover,
        r_min,
        r_max,
        max_discs: p.max_discs,
    };
    // The raster steers the fill; where it is too coarse to see the last uncovered slivers
    // (stop = no_room below the target), refine it twice (×2, ×4) and carry on with the same discs.
    let mut raster = p.raster;
    let mut filler = Filler::new(&pts, props.area, raster);
    let mut fill = filler.run(&fp);
    for _ in 0..2 {
        if fill.stop != StopReason::NoRoom {
            break;
        }
        raster *= 2;
        let mut finer = Filler::new(&pts, props.area, raster);
        for d in &fill.discs {
            finer.place(*d);
        }
        filler = finer;
        fill = filler.run(&fp);
    }
    if fill.discs.is_empty() {
        return Err(ClumpError::NoDisc { file, r_min });
    }
    let target = MassProps {
        mass: p.density * p.thickness * props.area,
        centroid: [0.0, 0.0],
        inertia: p.density * p.thickness * props.j,
        inertia_own: p.density * p.thickness * props.j,
        area: props.area,
    };
    let uniform = |d: &Circle| p.density * p.thickness * std::f64::consts::PI * d.r * d.r;
    let mut repairs = 0;
    let discs: Vec<Disc> = match p.method {
        // Returned above, before the fill.
        Method::Lattice => return lattice_template(outline, p, &pts, &props, &shape),
        Method::Orc => filler
            .discs
            .iter()
            .map(|d| Disc {
                x: d.x,
                y: d.y,
                r: d.r,
                m: uniform(d),
            })
            .collect(),
        Method::Improved => {
            let t = MassTargets {
                mass: target.mass,
                inertia: target.inertia,
                length: r_eq,
            };
            let k2 = props.j / props.area;
            let fill_discs = filler.discs.len();
            let solve = Solve {
                p,
                t: &t,
                r_min,
                r_max,
                k2,
                file: &file,
            };
            match solve.run(&mut filler, None) {
                Ok((d, k)) => {
                    repairs = k;
                    d
                }
                Err(first) if !p.rescue => return Err(first),
                Err(first) => {
                    // Second attempt, from the fill discs again: repair discs on a ring
                    // chosen from the deficit (see `ring_levels`).
                    let rings = ring_levels(&filler.discs[..fill_discs], r_min, k2);
                    let mut found = None;
                    for ring in rings {
                        // Only the disc list is cut back; the raster's covered cells are no
                        // longer used (repair discs are chosen from the inside cells).
                        filler.discs.truncate(fill_discs);
                        if let Ok(fit) = solve.run(&mut filler, Some(ring)) {
                            found = Some(fit);
                            break;
                        }
                    }
                    let Some((d, k)) = found else {
                        return Err(first);
                    };
                    repairs = k;
                    d
                }
            }
        }
    };
    let (cover, cover_bound) = filler.cover();
    let achieved = MassProps::of_discs(&discs);
    let xyr: Vec<[f64; 3]> = discs.iter().map(|d| [d.x, d.y, d.r]).collect();
    let m: Vec<f64> = discs.iter().map(|d| d.m).collect();
    let res = residuals(
        &xyr,
        &m,
        &MassTargets {
            mass: target.mass,
            inertia: target.inertia,
            length: r_eq,
        },
    );
    Ok(Template {
        schema: SCHEMA.to_string(),
        id: outline.name.clone(),
        generator: format!("clumpgen {}", env!("CARGO_PKG_VERSION")),
        source: source_record(outline, c),
        units: units_record(),
        density: p.density,
        thickness: p.thickness,
        method: p.method,
        fill: FillRecord {
            cover_target: p.cover,
            r_min,
            r_max,
            max_discs: p.max_discs,
            raster,
            stop: fill.stop,
            repair_discs: repairs,
            inside_tolerance: INSIDE_TOL * r_eq,
            mass_floor: p.mass_floor,
            prior: "uniform density: rho * t * pi * r^2 per disc, scaled to the grain mass".into(),
        },
        discs,
        target,
        achieved,
        residuals: res,
        cover: CoverRecord {
            value: cover,
            bound: cover_bound,
            union_area: cover * props.area,
        },
        shape: shape_record(&props, &shape),
        lattice: None,
    })
}

fn source_record(outline: &Outline, c: [f64; 2]) -> Source {
    Source {
        file: outline.source.clone(),
        sha256: outline.sha256.clone(),
        units: outline.units.name(),
        vertices: outline.points.len(),
        centroid_m: [outline.origin[0] + c[0], outline.origin[1] + c[1]],
        grain: outline.grain.clone(),
        warnings: outline.warnings.clone(),
    }
}

fn units_record() -> std::collections::BTreeMap<String, String> {
    [("length", "m"), ("mass", "kg"), ("inertia", "kg m^2")]
        .into_iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}

fn shape_record(props: &PolygonProps, shape: &ShapeDescriptors) -> Shape {
    Shape {
        area: props.area,
        perimeter: props.perimeter,
        j: props.j,
        principal_angle: props.principal_angle,
        r_eq: shape.r_eq,
        aspect_ratio: shape.aspect_ratio,
        circularity: shape.circularity,
        solidity: shape.solidity,
    }
}

/// The lattice method for one grain: [`crate::lattice::lattice_fill`] places the nodes and
/// links, then the improved method's mass solve gives every node a positive mass such that
/// mass, centroid and inertia are the grain's, closest to the prior of one lattice cell's mass
/// per node, `ρ·t·(√3/2)·S²` (scaled to the grain mass by the solve): its closed form without
/// active bounds ([`fit_masses_interior`]) when every mass stays above its floor, else the
/// active-set solve ([`fit_masses`]). No repair discs: the nodes are the lattice.
fn lattice_template(
    outline: &Outline,
    p: &ClumpParams,
    pts: &[[f64; 2]],
    props: &PolygonProps,
    shape: &ShapeDescriptors,
) -> Result<Template, ClumpError> {
    let file = outline.source.clone();
    let lp = p.lattice.ok_or_else(|| ClumpError::Lattice {
        file: file.clone(),
        field: "spacing",
        reason: "the lattice method needs a node spacing".into(),
    })?;
    let r_eq = shape.r_eq;
    let s = lp.spacing.resolve(r_eq);
    let fill = lattice_fill(pts, s, lp.node_radius).map_err(|e| ClumpError::Lattice {
        file: file.clone(),
        field: e.field,
        reason: e.reason,
    })?;
    let r = fill.radius;
    let n = fill.nodes.len();
    let xyr: Vec<[f64; 3]> = fill.nodes.iter().map(|q| [q[0], q[1], r]).collect();
    let cell = 3f64.sqrt() / 2.0 * s * s;
    let prior = vec![p.density * p.thickness * cell; n];
    let t = MassTargets {
        mass: p.density * p.thickness * props.area,
        inertia: p.density * p.thickness * props.j,
        length: r_eq,
    };
    // The bounds are usually inactive on a lattice: the closed form first, the active-set
    // solve with the bounds when a mass would fall below its floor.
    let (m, res) = match fit_masses_interior(&xyr, &prior, &t, p.mass_floor, p.tolerance) {
        Some(fit) => fit,
        None => fit_masses(&xyr, &prior, &t, p.mass_floor, p.tolerance).map_err(|e| {
            ClumpError::MassFit {
                file: file.clone(),
                discs: n,
                repairs: 0,
                source: e,
            }
        })?,
    };
    let discs: Vec<Disc> = fill
        .nodes
        .iter()
        .zip(&m)
        .map(|(q, &m)| Disc {
            x: q[0],
            y: q[1],
            r,
            m,
        })
        .collect();
    let target = MassProps {
        mass: t.mass,
        centroid: [0.0, 0.0],
        inertia: t.inertia,
        inertia_own: t.inertia,
        area: props.area,
    };
    // Node discs do not overlap (centres at least S apart, radii at most S/2), so their union
    // is the sum of their areas.
    let union = n as f64 * std::f64::consts::PI * r * r;
    Ok(Template {
        schema: SCHEMA_LATTICE.to_string(),
        id: outline.name.clone(),
        generator: format!("clumpgen {}", env!("CARGO_PKG_VERSION")),
        source: source_record(outline, props.centroid),
        units: units_record(),
        density: p.density,
        thickness: p.thickness,
        method: Method::Lattice,
        fill: FillRecord {
            cover_target: 0.0,
            r_min: r,
            r_max: r,
            max_discs: MAX_LATTICE_NODES,
            raster: 0,
            stop: StopReason::Lattice,
            repair_discs: 0,
            inside_tolerance: 0.0,
            mass_floor: p.mass_floor,
            prior: "one lattice cell per node: rho * t * (sqrt(3)/2) * S^2, scaled to the grain \
                    mass"
                .into(),
        },
        achieved: MassProps::of_discs(&discs),
        discs,
        target,
        residuals: res,
        cover: CoverRecord {
            value: union / props.area,
            bound: 16.0 * f64::EPSILON * n as f64 * union / props.area,
            union_area: union,
        },
        shape: shape_record(props, shape),
        lattice: Some(LatticeRecord {
            spacing: s,
            node_radius_fraction: lp.node_radius,
            offset: fill.offset,
            links: fill.links,
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raster_and_disc_limits_name_the_flag_the_limit_and_why() {
        let ok = ClumpParams::default();
        let at_limits = ClumpParams {
            raster: MAX_RASTER,
            max_discs: MAX_DISCS,
            ..ok
        };
        assert!(at_limits.check().is_ok());
        let e = ClumpParams {
            raster: 100_000,
            ..ok
        }
        .check()
        .unwrap_err();
        assert_eq!((e.name, e.value.as_str()), ("raster", "100000"));
        assert!(e.reason.starts_with("at most 1024 cells"), "{e}");
        assert!(
            e.reason.contains("1.6 TB per grain") && e.reason.contains("168 MB"),
            "{e}"
        );
        let e = ClumpParams { raster: 0, ..ok }.check().unwrap_err();
        assert_eq!(
            (e.name, e.reason.as_str()),
            ("raster", "must be at least 1")
        );
        let e = ClumpParams {
            max_discs: MAX_DISCS + 1,
            ..ok
        }
        .check()
        .unwrap_err();
        assert_eq!((e.name, e.value.as_str()), ("max-discs", "1001"));
        assert!(e.reason.starts_with("at most 1000 discs"), "{e}");
        // The library refuses too, before rasterising anything.
        let ol = crate::outline::parse_outline(
            "0 0\n10 0\n10 10\n0 10\n",
            "g",
            "g.csv",
            false,
            &crate::ReadOptions::default(),
        )
        .unwrap();
        let e = make_template(
            &ol,
            &ClumpParams {
                raster: 100_000,
                ..ok
            },
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("g.csv: invalid parameter: raster 100000"),
            "{e}"
        );
    }

    #[test]
    fn byte_counts_read_well() {
        assert_eq!(human_bytes(1.6e12), "1.6 TB");
        assert_eq!(human_bytes(167_772_160.0), "168 MB");
        assert_eq!(human_bytes(655_360.0), "655 kB");
        assert_eq!(human_bytes(12.0), "12 B");
    }
}
