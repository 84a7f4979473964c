//! Table 1 of Ye & Xu (2010): one grain's area, centroid deviation and mass moment of inertia as
//! the real grain, as an ORC clump (uniform discs summed, overlaps counted twice) and as an
//! improved-ORC clump (masses solved for exact mass, centroid and inertia).
//!
//! The paper's grain outline, density and thickness are not published. We use the project's
//! stand-in `data/outlines/table1-grain.csv` (area exactly 2246.63 mm²) and choose ρ·t so that the
//! real grain's inertia equals the paper's 7.57×10⁵ g·mm²; with ρ = 3200 kg/m³ (Si3N4) that fixes
//! t. The ORC and improved columns are then computed, not fitted.

use crate::error::{Error, Result};
use clumpgen::{make_template, read_outline, ClumpParams, Method, ReadOptions, Template};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The paper's real-grain inertia (g·mm²), Table 1.
pub const PAPER_REAL_INERTIA_G_MM2: f64 = 7.57e5;
/// Density used (kg/m³): silicon nitride, about 3.2 g/cm³.
pub const DENSITY: f64 = 3200.0;

/// One column of Table 1 (a method), in the paper's units.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Row {
    pub method: String,
    pub area_mm2: f64,
    pub centroid_dx_mm: f64,
    pub centroid_dy_mm: f64,
    /// About the body's own mass centre (g·mm²).
    pub inertia_g_mm2: f64,
    pub discs: usize,
    pub cover: f64,
    pub paper_area_mm2: f64,
    pub paper_centroid_dx_mm: f64,
    pub paper_centroid_dy_mm: f64,
    pub paper_inertia_g_mm2: f64,
}

/// Table 1 with the settings used.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Table1 {
    pub grain: String,
    pub density_kg_m3: f64,
    pub thickness_m: f64,
    pub params: ClumpParams,
    pub rows: Vec<Row>,
    pub note: String,
}

#[derive(Deserialize)]
struct PaperRow {
    method: String,
    area: f64,
    centroid_dx: f64,
    centroid_dy: f64,
    inertia: f64,
}
#[derive(Deserialize)]
struct PaperTable {
    rows: Vec<PaperRow>,
}

/// Computes Table 1 from the grain outline and the paper's reference JSON.
pub fn table1(outline: &Path, reference: &Path, base: &ClumpParams) -> Result<Table1> {
    let ol = read_outline(outline, &ReadOptions::default())?;
    let paper: PaperTable =
        serde_json::from_str(&std::fs::read_to_string(reference).map_err(Error::io(reference))?)
            .map_err(Error::json(reference))?;
    let props = clumpgen::props::polygon_props(&ol.points);
    // ρ·t from the paper's real inertia: I = ρ t J  (J in m⁴, I in kg·m²; 1 g·mm² = 1e-9 kg·m²).
    let rho_t = PAPER_REAL_INERTIA_G_MM2 * 1e-9 / props.j;
    let thickness = rho_t / DENSITY;
    let params = ClumpParams {
        density: DENSITY,
        thickness,
        ..*base
    };
    let make = |m: Method| -> Result<Template> {
        make_template(
            &ol,
            &ClumpParams {
                method: m,
                ..params
            },
        )
        .map_err(Error::from)
    };
    let orc = make(Method::Orc)?;
    let imp = make(Method::Improved)?;
    let find = |name: &str| paper.rows.iter().find(|r| r.method == name);
    let row = |name: &str, t: Option<&Template>| -> Row {
        let p = find(name);
        let (area, dx, dy, inertia, discs, cover) = match t {
            None => (props.area * 1e6, 0.0, 0.0, rho_t * props.j * 1e9, 0, 1.0),
            Some(t) => (
                t.achieved.mass / rho_t * 1e6,
                t.achieved.centroid[0] * 1e3,
                t.achieved.centroid[1] * 1e3,
                t.achieved.inertia_own * 1e9,
                t.discs.len(),
                t.cover.value,
            ),
        };
        Row {
            method: name.to_string(),
            area_mm2: area,
            centroid_dx_mm: dx,
            centroid_dy_mm: dy,
            inertia_g_mm2: inertia,
            discs,
            cover,
            paper_area_mm2: p.map_or(f64::NAN, |p| p.area),
            paper_centroid_dx_mm: p.map_or(f64::NAN, |p| p.centroid_dx),
            paper_centroid_dy_mm: p.map_or(f64::NAN, |p| p.centroid_dy),
            paper_inertia_g_mm2: p.map_or(f64::NAN, |p| p.inertia),
        }
    };
    Ok(Table1 {
        grain: outline.display().to_string(),
        density_kg_m3: DENSITY,
        thickness_m: thickness,
        params,
        rows: vec![
            row("real", None),
            row("orc", Some(&orc)),
            row("improved", Some(&imp)),
        ],
        note:
            "Area of a clump = its mass / (rho t): for ORC the sum of disc areas (overlaps counted \
               twice), for improved ORC the grain area. Centroid deviation = clump mass centre \
               minus grain centroid. Inertia about the body's own mass centre. rho t chosen so the \
               real grain's inertia equals the paper's; the paper's outline is not published, so \
               the grain is a stand-in of the same area."
                .into(),
    })
}

impl Table1 {
    /// Markdown table, ours beside the paper's.
    pub fn markdown(&self) -> String {
        let mut s = String::from("# Table 1 (Ye & Xu 2010): one grain by method\n\n");
        s.push_str(&format!(
            "Grain `{}`; density {} kg/m³, thickness {:.6e} m (ρ·t set so the real grain's \
             inertia equals the paper's); cover target {}, r_min {}, r_max {}.\n\n",
            self.grain,
            self.density_kg_m3,
            self.thickness_m,
            self.params.cover,
            self.params.r_min,
            self.params.r_max
        ));
        s.push_str("| property | real (ours) | real (paper) | ORC (ours) | ORC (paper) | improved ORC (ours) | improved ORC (paper) |\n|---|---|---|---|---|---|---|\n");
        let r = &self.rows;
        let line = |name: &str, f: &dyn Fn(&Row) -> (f64, f64), fmt: &dyn Fn(f64) -> String| {
            let mut l = format!("| {name} |");
            for row in r {
                let (o, p) = f(row);
                l.push_str(&format!(" {} | {} |", fmt(o), fmt(p)));
            }
            l.push('\n');
            l
        };
        let f2 = |v: f64| format!("{v:.2}");
        let e3 = |v: f64| {
            if v == 0.0 {
                "0".to_string()
            } else {
                format!("{v:.3e}")
            }
        };
        s.push_str(&line(
            "area (mm²)",
            &|w| (w.area_mm2, w.paper_area_mm2),
            &f2,
        ));
        s.push_str(&line(
            "centroid X deviation (mm)",
            &|w| (w.centroid_dx_mm, w.paper_centroid_dx_mm),
            &e3,
        ));
        s.push_str(&line(
            "centroid Y deviation (mm)",
            &|w| (w.centroid_dy_mm, w.paper_centroid_dy_mm),
            &e3,
        ));
        s.push_str(&line(
            "mass moment of inertia (g·mm²)",
            &|w| (w.inertia_g_mm2, w.paper_inertia_g_mm2),
            &e3,
        ));
        s.push_str(&format!(
            "\nDiscs: ORC {}, improved {} (cover {:.4}).\n\n{}\n",
            r[1].discs, r[2].discs, r[2].cover, self.note
        ));
        s
    }
}
