//! Error against run time for clump generation: for every outline in a folder and each cover
//! target, the cover reached, the boundary deviation (Hausdorff distance outline ↔ clump boundary
//! over the equivalent radius), the mass-property residual, the disc count and the time per grain
//! (one thread).

use crate::error::{Error, Result};
use clumpgen::batch::{collect_inputs, median};
use clumpgen::cover::Circle;
use clumpgen::hausdorff::boundary_deviation;
use clumpgen::{make_template, read_outline, ClumpParams, Outline, ReadOptions};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// One cover setting, over all grains.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SweepRow {
    pub cover_target: f64,
    pub grains: usize,
    pub failures: usize,
    pub median_cover: f64,
    pub worst_cover: f64,
    pub median_hausdorff_over_req: f64,
    pub worst_hausdorff_over_req: f64,
    pub worst_residual: f64,
    pub median_discs: f64,
    pub max_discs: usize,
    /// Median over grains of the best of `repeats` timings of one grain (ms, one thread).
    pub median_ms_per_grain: f64,
}

/// The sweep and how it was run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Sweep {
    pub folder: String,
    pub method: String,
    pub repeats: usize,
    pub hausdorff_sampling_over_req: f64,
    pub rows: Vec<SweepRow>,
}

/// Runs the sweep over `covers` for all outlines in `folder` (serially, so times are per core).
pub fn sweep(folder: &Path, covers: &[f64], base: &ClumpParams, repeats: usize) -> Result<Sweep> {
    let inputs = collect_inputs(&[folder.to_path_buf()]).map_err(Error::BareIo)?;
    let outlines: Vec<Outline> = inputs
        .iter()
        .map(|i| read_outline(&i.path, &ReadOptions::default()))
        .collect::<std::result::Result<_, _>>()?;
    let h_rel = 1e-3;
    let mut rows = Vec::new();
    for &cover in covers {
        let p = ClumpParams { cover, ..*base };
        let (mut covs, mut hd, mut discs, mut ms) = (vec![], vec![], vec![], vec![]);
        let (mut worst_res, mut failures) = (0.0f64, 0);
        for ol in &outlines {
            let mut best = f64::INFINITY;
            let mut tpl = None;
            for _ in 0..repeats.max(1) {
                let t0 = Instant::now();
                let r = make_template(ol, &p);
                best = best.min(t0.elapsed().as_secs_f64());
                tpl = Some(r);
            }
            match tpl.expect("at least one run") {
                Ok(t) => {
                    let c = t.source.centroid_m;
                    let o = ol.origin;
                    let poly: Vec<[f64; 2]> = ol
                        .points
                        .iter()
                        .map(|q| [q[0] + o[0] - c[0], q[1] + o[1] - c[1]])
                        .collect();
                    let circles: Vec<Circle> = t
                        .discs
                        .iter()
                        .map(|d| Circle {
                            x: d.x,
                            y: d.y,
                            r: d.r,
                        })
                        .collect();
                    let r_eq = t.shape.r_eq;
                    let dev = boundary_deviation(&poly, &circles, h_rel * r_eq);
                    covs.push(t.cover.value);
                    hd.push(dev.hausdorff / r_eq);
                    discs.push(t.discs.len() as f64);
                    ms.push(best * 1e3);
                    worst_res = worst_res.max(t.residuals.max());
                }
                Err(_) => failures += 1,
            }
        }
        rows.push(SweepRow {
            cover_target: cover,
            grains: outlines.len(),
            failures,
            median_cover: median(covs.clone()),
            worst_cover: covs.iter().copied().fold(f64::INFINITY, f64::min).min(1.0),
            median_hausdorff_over_req: median(hd.clone()),
            worst_hausdorff_over_req: hd.iter().copied().fold(0.0, f64::max),
            worst_residual: worst_res,
            median_discs: median(discs.clone()),
            max_discs: discs.iter().copied().fold(0.0, f64::max) as usize,
            median_ms_per_grain: median(ms),
        });
    }
    Ok(Sweep {
        folder: folder.display().to_string(),
        method: base.method.name().to_string(),
        repeats,
        hausdorff_sampling_over_req: h_rel,
        rows,
    })
}

impl Sweep {
    /// Markdown table.
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "# Clump generation: error against run time\n\nOutlines: `{}`; method {}; time = \
             median over grains of the best of {} runs, one thread. Hausdorff distance sampled at \
             {} R_eq (bound half that).\n\n",
            self.folder, self.method, self.repeats, self.hausdorff_sampling_over_req
        );
        s.push_str("| cover target | grains | failed | median cover | lowest cover | median Hausdorff/R_eq | worst Hausdorff/R_eq | worst residual | median discs | most discs | median ms/grain |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        for r in &self.rows {
            s.push_str(&format!(
                "| {:.2} | {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.1e} | {} | {} | {:.3} |\n",
                r.cover_target,
                r.grains,
                r.failures,
                r.median_cover,
                r.worst_cover,
                r.median_hausdorff_over_req,
                r.worst_hausdorff_over_req,
                r.worst_residual,
                r.median_discs,
                r.max_discs,
                r.median_ms_per_grain
            ));
        }
        s
    }
}
