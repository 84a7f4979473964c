//! One grain, outline to template: properties → fill → mass solve (→ repair) → template.

use crate::cover::Circle;
use crate::descriptors::shape_descriptors;
use crate::fill::{FillParams, Filler, StopReason};
use crate::massfit::{fit_masses, inertia_about_origin, residuals, MassFitError, MassTargets};
use crate::outline::Outline;
use crate::props::polygon_props;
use crate::template::{
    CoverRecord, Disc, FillRecord, MassProps, Method, Shape, Source, Template, SCHEMA,
};
use serde::{Deserialize, Serialize};

/// Discs are sized from the exact distance to the outline, so they are inside up to rounding;
/// this (relative to the equivalent radius) is the tolerance the template states and tests check.
pub const INSIDE_TOL: f64 = 1e-12;

/// A length given absolutely (m) or as a fraction of the grain's equivalent radius.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Length {
    Metres(f64),
    OfReq(f64),
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
    /// `max-discs`, `rmin`, `rmax`) or the field (`mass_floor`, `tolerance`).
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

fn check_params(p: &ClumpParams, file: &str) -> Result<(), ClumpError> {
    p.check().map_err(|e| ClumpError::Params {
        file: file.to_string(),
        reason: e.to_string(),
    })
}

/// Mass properties of discs with masses `m`, about the grain centroid (the frame's origin).
fn mass_props(discs: &[Disc]) -> MassProps {
    let xyr: Vec<[f64; 3]> = discs.iter().map(|d| [d.x, d.y, d.r]).collect();
    let m: Vec<f64> = discs.iter().map(|d| d.m).collect();
    let mass: f64 = m.iter().sum();
    let cx = discs.iter().map(|d| d.m * d.x).sum::<f64>() / mass;
    let cy = discs.iter().map(|d| d.m * d.y).sum::<f64>() / mass;
    let inertia = inertia_about_origin(&xyr, &m);
    MassProps {
        mass,
        centroid: [cx, cy],
        inertia,
        inertia_own: inertia - mass * (cx * cx + cy * cy),
        area: discs.iter().map(|d| std::f64::consts::PI * d.r * d.r).sum(),
    }
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
            loop {
                let xyr: Vec<[f64; 3]> = filler.discs.iter().map(|d| [d.x, d.y, d.r]).collect();
                let prior: Vec<f64> = filler.discs.iter().map(uniform).collect();
                match fit_masses(&xyr, &prior, &t, p.mass_floor, p.tolerance) {
                    Ok((m, _)) => {
                        break filler
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
                    }
                    Err(e) => {
                        let fail = |e| ClumpError::MassFit {
                            file: file.clone(),
                            discs: filler.discs.len(),
                            repairs,
                            source: e,
                        };
                        if repairs >= p.max_repairs || filler.discs.len() >= p.max_discs {
                            return Err(fail(e));
                        }
                        match filler.repair_disc(r_min, r_max, props.j / props.area) {
                            Some(d) => filler.place(d),
                            None => return Err(fail(e)),
                        }
                        repairs += 1;
                    }
                }
            }
        }
    };
    let (cover, cover_bound) = filler.cover();
    let achieved = mass_props(&discs);
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
        source: Source {
            file: outline.source.clone(),
            sha256: outline.sha256.clone(),
            units: outline.units.name(),
            vertices: outline.points.len(),
            centroid_m: [outline.origin[0] + c[0], outline.origin[1] + c[1]],
            warnings: outline.warnings.clone(),
        },
        units: [("length", "m"), ("mass", "kg"), ("inertia", "kg m^2")]
            .into_iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect(),
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
        shape: Shape {
            area: props.area,
            perimeter: props.perimeter,
            j: props.j,
            principal_angle: props.principal_angle,
            r_eq,
            aspect_ratio: shape.aspect_ratio,
            circularity: shape.circularity,
            solidity: shape.solidity,
        },
    })
}
