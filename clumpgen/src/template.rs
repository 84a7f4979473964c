//! The clump template: a versioned JSON record of one grain's disc clump, everything in SI units
//! in the grain's centroid frame (not rotated; the principal angle is recorded). The schema is
//! documented field by field in `docs/template-schema.md`; [`Template::load`] reads it back and
//! checks it, naming the file and the field at fault.

use crate::massfit::Residuals;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Schema identifier written in every template without a lattice; bump on incompatible
/// change.
pub const SCHEMA: &str = "clumpgen.template/1";

/// Schema identifier of a lattice template (`method: lattice`): version 1 plus the `lattice`
/// record (spacing, node radius, links). Written only for lattice templates, so templates of the
/// other methods stay byte for byte what they were; readers accept both.
pub const SCHEMA_LATTICE: &str = "clumpgen.template/2";

/// Whether `schema` is one this version reads ([`SCHEMA`] or [`SCHEMA_LATTICE`]).
pub fn is_template_schema(schema: &str) -> bool {
    schema == SCHEMA || schema == SCHEMA_LATTICE
}

/// How the disc masses were assigned.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Improved ORC (Ye & Xu 2010): masses solved so that mass, centroid and inertia are exact.
    Improved,
    /// Classic ORC (Ashmawy et al. 2003): uniform-density discs summed, overlaps counted twice.
    Orc,
    /// Triangular node lattice (S3, crushable grains; `crate::lattice`): nodes as discs of one
    /// radius, masses solved as for `Improved`; the template has a `lattice` record with the
    /// links (schema `clumpgen.template/2`).
    Lattice,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Improved => "improved",
            Method::Orc => "orc",
            Method::Lattice => "lattice",
        }
    }
}

/// One disc of the clump (m, m, m, kg), centre in the grain's centroid frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Disc {
    pub x: f64,
    pub y: f64,
    pub r: f64,
    pub m: f64,
}

/// Where the outline came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Source {
    pub file: String,
    pub sha256: String,
    /// Units the outline file was read in (`m`, `mm`, `um`, `px`).
    pub units: String,
    /// Outline vertices after cleaning (and resampling, if asked).
    pub vertices: usize,
    /// Grain centroid in the file's own coordinates, converted to metres (SI), so a clump can be
    /// put back where the grain was.
    pub centroid_m: [f64; 2],
    /// The grain within a multi-grain file (`label 7`, `component 3`, `feature "g7"`); absent
    /// for a one-outline file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grain: Option<String>,
    pub warnings: Vec<String>,
}

/// Fill parameters as used (absolute lengths, m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct FillRecord {
    pub cover_target: f64,
    pub r_min: f64,
    pub r_max: f64,
    pub max_discs: usize,
    pub raster: usize,
    /// `cover_reached`, `max_discs` or `no_room`.
    pub stop: crate::fill::StopReason,
    /// Discs added after the fill to make the mass fit feasible.
    pub repair_discs: usize,
    /// Every disc satisfies `r ≤ distance(centre, outline) + inside_tolerance` (m).
    pub inside_tolerance: f64,
    /// Lower bound on solved masses, as a fraction of the prior (improved method).
    pub mass_floor: f64,
    /// The prior the improved method stays closest to.
    pub prior: String,
}

/// Mass properties: mass (kg), centroid (m, grain centroid frame), moment of inertia about the
/// z axis through the grain centroid (kg·m²), and area (m²).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct MassProps {
    pub mass: f64,
    pub centroid: [f64; 2],
    /// About the grain's centroid (what the consistency equation (3) of Ye & Xu constrains).
    pub inertia: f64,
    /// About the clump's own mass centre (= `inertia − mass·|centroid|²`).
    pub inertia_own: f64,
    /// Area the mass stands for: the grain area for the target; `Σπr²` for the clump (overlaps
    /// counted twice, as ORC does).
    pub area: f64,
}

impl MassProps {
    /// Mass properties of discs with masses `m`, about the grain centroid (the frame's
    /// origin): Σm, Σm·x/Σm, Σm(r²/2 + |x|²), and Σπr² as the area.
    pub fn of_discs(discs: &[Disc]) -> MassProps {
        let xyr: Vec<[f64; 3]> = discs.iter().map(|d| [d.x, d.y, d.r]).collect();
        let m: Vec<f64> = discs.iter().map(|d| d.m).collect();
        let mass: f64 = m.iter().sum();
        let cx = discs.iter().map(|d| d.m * d.x).sum::<f64>() / mass;
        let cy = discs.iter().map(|d| d.m * d.y).sum::<f64>() / mass;
        let inertia = crate::massfit::inertia_about_origin(&xyr, &m);
        MassProps {
            mass,
            centroid: [cx, cy],
            inertia,
            inertia_own: inertia - mass * (cx * cx + cy * cy),
            area: discs.iter().map(|d| std::f64::consts::PI * d.r * d.r).sum(),
        }
    }
}

/// Area cover of the clump.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct CoverRecord {
    /// `A_r = area(union of discs ∩ grain) / area(grain)`.
    pub value: f64,
    /// Bound on the absolute error of `value` (floating-point rounding; the union is exact).
    pub bound: f64,
    /// Area of the union of the discs (m²).
    pub union_area: f64,
}

/// Grain geometry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Shape {
    pub area: f64,
    pub perimeter: f64,
    /// Polar second moment of area about the centroid (m⁴).
    pub j: f64,
    /// Angle of the long (minimum second moment) axis from +x (rad).
    pub principal_angle: f64,
    pub r_eq: f64,
    pub aspect_ratio: f64,
    pub circularity: f64,
    pub solidity: f64,
}

/// The lattice of a `lattice` template (schema `clumpgen.template/2`): the nodes are the
/// template's `discs`, in the same order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct LatticeRecord {
    /// Node spacing S (m): lattice neighbours are S apart.
    pub spacing: f64,
    /// Node disc radius as a fraction of S/2 (1: neighbours touch).
    pub node_radius_fraction: f64,
    /// Lattice offset o (m, centroid frame): nodes at o + i·(S, 0) + j·(S/2, S√3/2).
    pub offset: [f64; 2],
    /// Links between lattice neighbours (nodes `i < j`, indices into `discs`).
    pub links: Vec<crate::lattice::Link>,
}

/// A clump template (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Template {
    /// `"clumpgen.template/1"`, or `"clumpgen.template/2"` for a lattice template (version 1
    /// plus `lattice`); readers reject anything else.
    #[cfg_attr(
        feature = "schema",
        schemars(extend("enum" = ["clumpgen.template/1", "clumpgen.template/2"]))
    )]
    pub schema: String,
    pub id: String,
    pub generator: String,
    pub source: Source,
    /// Always `{"length": "m", "mass": "kg", "inertia": "kg m^2"}`.
    pub units: std::collections::BTreeMap<String, String>,
    /// kg/m³.
    pub density: f64,
    /// Disc thickness t (m); masses are `ρ·t·area`.
    pub thickness: f64,
    pub method: Method,
    pub fill: FillRecord,
    pub discs: Vec<Disc>,
    pub target: MassProps,
    pub achieved: MassProps,
    pub residuals: Residuals,
    pub cover: CoverRecord,
    pub shape: Shape,
    /// Lattice templates only (schema `clumpgen.template/2`): spacing and links.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lattice: Option<LatticeRecord>,
}

/// Errors reading or writing a template.
#[derive(Debug, thiserror::Error)]
pub enum TemplateError {
    #[error("{file}: cannot read: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    /// Saving failed (a read-only or full disk, a missing permission).
    #[error("{file}: cannot write: {source}")]
    Write {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}: not a clump template: {source}")]
    Json {
        file: String,
        source: serde_json::Error,
    },
    #[error("{file}: schema is {found:?}, expected {SCHEMA:?} or {SCHEMA_LATTICE:?}")]
    Schema { file: String, found: String },
    #[error("{file}: field {field}: {reason}")]
    Field {
        file: String,
        field: String,
        reason: String,
    },
}

/// A template whose discs stop below the requested area cover. A warning, not an error: the
/// template still has exactly the grain's mass, centroid and inertia; only its shape is coarser
/// than asked for. Its message names the grain's file, the cover reached, the target and the
/// `dem clump` flags that change it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: cover {} below the target {target}: {}", below(*.cover, *.target), advice(.stop, *.max_discs, *.r_min, *.raster))]
pub struct CoverShortfall {
    /// The outline file, as given.
    pub file: String,
    /// The area cover reached.
    pub cover: f64,
    /// The cover asked for (`--cover`).
    pub target: f64,
    /// Why the fill stopped: `max_discs` or `no_room`.
    pub stop: crate::fill::StopReason,
    pub max_discs: usize,
    /// Smallest disc radius (m).
    pub r_min: f64,
    /// Raster cells along the longer side, after refinement.
    pub raster: usize,
}

/// `cover` with enough decimals to show it below `target` (0.9499996 is not "0.9500").
fn below(cover: f64, target: f64) -> String {
    (4..=12)
        .map(|d| format!("{cover:.d$}"))
        .find(|s| s.parse::<f64>().is_ok_and(|v| v < target))
        .unwrap_or_else(|| format!("{cover:e}"))
}

fn advice(stop: &crate::fill::StopReason, max_discs: usize, r_min: f64, raster: usize) -> String {
    match stop {
        crate::fill::StopReason::MaxDiscs => format!(
            "the fill stopped at --max-discs {max_discs}; raise --max-discs or lower --cover"
        ),
        _ => format!(
            "no room is left for a disc of radius r_min = {r_min:.3e} m (seen on a raster of \
             {raster} cells); lower --rmin, raise --raster or lower --cover"
        ),
    }
}

impl Template {
    /// The cover shortfall of this template: `Some` when its cover is below the target it was
    /// made for.
    pub fn cover_shortfall(&self) -> Option<CoverShortfall> {
        (self.cover.value < self.fill.cover_target).then(|| CoverShortfall {
            file: self.source.file.clone(),
            cover: self.cover.value,
            target: self.fill.cover_target,
            stop: self.fill.stop,
            max_discs: self.fill.max_discs,
            r_min: self.fill.r_min,
            raster: self.fill.raster,
        })
    }

    /// Checks invariants every consumer relies on: finite numbers, positive radii and masses,
    /// positive density and thickness. `file` names the template in the error.
    pub fn check(&self, file: &str) -> Result<(), TemplateError> {
        let bad = |field: String, reason: &str| TemplateError::Field {
            file: file.to_string(),
            field,
            reason: reason.to_string(),
        };
        if !is_template_schema(&self.schema) {
            return Err(TemplateError::Schema {
                file: file.to_string(),
                found: self.schema.clone(),
            });
        }
        let v2 = self.schema == SCHEMA_LATTICE;
        if v2 != (self.method == Method::Lattice) {
            return Err(bad(
                "method".into(),
                &format!(
                    "method {} needs schema {:?}",
                    self.method.name(),
                    if v2 { SCHEMA } else { SCHEMA_LATTICE }
                ),
            ));
        }
        if v2 != self.lattice.is_some() {
            return Err(bad(
                "lattice".into(),
                if v2 {
                    "a lattice template (clumpgen.template/2) needs its lattice record"
                } else {
                    "only lattice templates (clumpgen.template/2) have a lattice record"
                },
            ));
        }
        for (name, v) in [("density", self.density), ("thickness", self.thickness)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(name.into(), "must be a positive finite number"));
            }
        }
        if self.discs.is_empty() {
            return Err(bad("discs".into(), "no discs"));
        }
        for (i, d) in self.discs.iter().enumerate() {
            for (k, v) in [("x", d.x), ("y", d.y), ("r", d.r), ("m", d.m)] {
                if !v.is_finite() {
                    return Err(bad(format!("discs[{i}].{k}"), "not a finite number"));
                }
            }
            if d.r <= 0.0 {
                return Err(bad(format!("discs[{i}].r"), "radius must be positive"));
            }
            if d.m <= 0.0 {
                return Err(bad(format!("discs[{i}].m"), "mass must be positive"));
            }
        }
        for (name, p) in [("target", &self.target), ("achieved", &self.achieved)] {
            let vals = [
                p.mass,
                p.centroid[0],
                p.centroid[1],
                p.inertia,
                p.inertia_own,
                p.area,
            ];
            if vals.iter().any(|v| !v.is_finite()) {
                return Err(bad(name.into(), "contains a non-finite number"));
            }
        }
        // The lattice's own geometry first: a moved node is a broken link before it is a
        // moved centroid.
        if let Some(l) = &self.lattice {
            self.check_lattice(l, file)?;
        }
        self.check_achieved(file)
    }

    /// The stated clump properties (`achieved`, what a rigid clump of the template moves
    /// with) are the discs' own: Σm, Σm·x/Σm and Σm(r²/2 + |x|²) to 1e-9 (relative; the
    /// centroid relative to the radius of gyration; every number is finite here, checked
    /// before). Issue 48 D16: a template with one disc's
    /// mass edited ran with the old clump mass, silently.
    fn check_achieved(&self, file: &str) -> Result<(), TemplateError> {
        let own = MassProps::of_discs(&self.discs);
        let a = &self.achieved;
        let tol = 1e-9;
        let gyr = (a.inertia / a.mass).abs().sqrt();
        let off = (own.centroid[0] - a.centroid[0]).hypot(own.centroid[1] - a.centroid[1]);
        let bad = |field: &str, what: &str, discs: String, stated: String| TemplateError::Field {
            file: file.to_string(),
            field: format!("achieved.{field}"),
            reason: format!(
                "the discs give {what} {discs}, the template states {stated} (a disc edited?); \
                 regenerate the template (dem clump) or make the two agree"
            ),
        };
        if (own.mass - a.mass).abs() > tol * a.mass.abs() {
            return Err(bad(
                "mass",
                "a mass of",
                format!("{:.6e} kg", own.mass),
                format!("{:.6e} kg", a.mass),
            ));
        }
        if off > tol * gyr {
            return Err(bad(
                "centroid",
                "a centroid of",
                format!("({:.6e}, {:.6e}) m", own.centroid[0], own.centroid[1]),
                format!("({:.6e}, {:.6e}) m", a.centroid[0], a.centroid[1]),
            ));
        }
        if (own.inertia - a.inertia).abs() > tol * a.inertia.abs() {
            return Err(bad(
                "inertia",
                "an inertia of",
                format!("{:.6e} kg m²", own.inertia),
                format!("{:.6e} kg m²", a.inertia),
            ));
        }
        Ok(())
    }

    /// The lattice record: positive spacing, fraction in (0, 1], links between existing nodes
    /// `i < j` at distance `spacing` (1e-9 relative), none twice.
    fn check_lattice(&self, l: &LatticeRecord, file: &str) -> Result<(), TemplateError> {
        let bad = |field: String, reason: String| TemplateError::Field {
            file: file.to_string(),
            field,
            reason,
        };
        if !(l.spacing.is_finite() && l.spacing > 0.0) {
            return Err(bad(
                "lattice.spacing".into(),
                "must be a positive finite number".into(),
            ));
        }
        let f = l.node_radius_fraction;
        if !(f.is_finite() && f > 0.0 && f <= 1.0) {
            return Err(bad(
                "lattice.node_radius_fraction".into(),
                "must be in (0, 1]".into(),
            ));
        }
        if !(l.offset[0].is_finite() && l.offset[1].is_finite()) {
            return Err(bad("lattice.offset".into(), "not finite".into()));
        }
        let n = self.discs.len();
        let mut seen = std::collections::HashSet::new();
        for (k, link) in l.links.iter().enumerate() {
            if !(link.i < link.j && link.j < n) {
                return Err(bad(
                    format!("lattice.links[{k}]"),
                    format!(
                        "nodes {} and {} must satisfy i < j < {n} (the number of discs)",
                        link.i, link.j
                    ),
                ));
            }
            if !seen.insert((link.i, link.j)) {
                return Err(bad(format!("lattice.links[{k}]"), "repeated link".into()));
            }
            let (a, b) = (&self.discs[link.i], &self.discs[link.j]);
            let d = (a.x - b.x).hypot(a.y - b.y);
            if (d - l.spacing).abs() > 1e-9 * l.spacing {
                return Err(bad(
                    format!("lattice.links[{k}]"),
                    format!(
                        "nodes {} and {} are {d:e} m apart, not the spacing {:e} m",
                        link.i, link.j, l.spacing
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Reads and checks a template.
    pub fn load(path: &Path) -> Result<Template, TemplateError> {
        let file = path.display().to_string();
        let text = crate::io::read_input_string(path).map_err(|source| TemplateError::Io {
            file: file.clone(),
            source,
        })?;
        Self::from_json(&text, &file)
    }

    /// Parses and checks a template from JSON text; `file` names it in errors.
    pub fn from_json(text: &str, file: &str) -> Result<Template, TemplateError> {
        let t: Template = serde_json::from_str(text).map_err(|source| TemplateError::Json {
            file: file.to_string(),
            source,
        })?;
        t.check(file)?;
        Ok(t)
    }

    /// Pretty JSON text, after [`Template::check`] (so no NaN is ever written).
    pub fn to_json(&self, file: &str) -> Result<String, TemplateError> {
        self.check(file)?;
        let mut s = serde_json::to_string_pretty(self).expect("template serialises");
        s.push('\n');
        Ok(s)
    }

    /// Writes the template atomically (temporary file in the same folder, then rename).
    pub fn save(&self, path: &Path) -> Result<(), TemplateError> {
        let file = path.display().to_string();
        let text = self.to_json(&file)?;
        crate::io::write_atomic(path, text.as_bytes())
            .map_err(|source| TemplateError::Write { file, source })
    }
}
