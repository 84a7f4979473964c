//! clumpgen: grain outlines to disc clumps whose mass, centroid and moment of inertia equal the
//! real grain's (the "improved ORC" method of Ye & Xu 2010), saved as JSON templates.
//!
//! The pipeline for one grain ([`clump::make_template`]):
//!
//! ```text
//! outline file ── outline::read_outline ──► Outline (SI, local origin, CCW, validated)
//!   (mask, label image, GeoJSON, WKT: outline::read_grains, one Outline per grain)
//!     │ props::polygon_props, descriptors::shape_descriptors   (exact, Green's theorem)
//!     ▼
//! fill::Filler::run          minimum-residual-area discs until the cover target (exact cover)
//!     ▼
//! massfit::fit_masses        Σm = m_p, Σm·x = 0, Σm·y = 0, ΣI = I_p, m_i > 0 (QP, active set)
//!     │ (infeasible → Filler::repair_disc near the boundary, then solve again)
//!     ▼
//! template::Template         versioned JSON, written atomically; Template::load reads it back
//! ```
//!
//! With `method: lattice` ([`lattice`], crushable grains, S3) the fill is a triangular node
//! lattice of spacing S instead, with its links; the mass solve is the same.
//! [`lattice_elastic()`] gives the lattice's equivalent E and ν and their inverse.
//!
//! [`batch::run_batch`] runs many grains in parallel (a clump library); [`export`] writes a
//! template for PFC2D, YADE, LAMMPS or MercuryDPM beside it.
//!
//! One grain, from an outline in memory to a template:
//!
//! ```
//! use clumpgen::clump::make_template;
//! use clumpgen::outline::{parse_outline, ReadOptions};
//! use clumpgen::ClumpParams;
//!
//! // An L-shaped grain, as a CSV outline file in millimetres would hold it.
//! let csv = "# units: mm\nx,y\n0,0\n2,0\n2,1\n1,1\n1,2\n0,2\n";
//! let outline = parse_outline(csv, "l-grain", "l-grain.csv", false, &ReadOptions::default())?;
//! let t = make_template(&outline, &ClumpParams::default())?;
//! // At least the cover target (95 % of the area by default) with a few discs ...
//! assert!(t.cover.value >= 0.95 && t.discs.len() <= 20);
//! // ... and the grain's exact mass, centroid and moment of inertia (improved ORC).
//! let (a, g) = (&t.achieved, &t.target);
//! assert!((a.mass - g.mass).abs() <= 1e-12 * g.mass);
//! assert!((a.inertia - g.inertia).abs() <= 1e-12 * g.inertia);
//! assert!(a.centroid[0].abs() < 1e-15 && a.centroid[1].abs() < 1e-15);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod batch;
pub mod clump;
pub mod cover;
pub mod descriptors;
pub mod error;
pub mod export;
pub mod fill;
pub mod geom;
pub mod hausdorff;
pub mod io;
pub mod lattice;
pub mod lattice_elastic;
pub mod massfit;
pub mod outline;
pub mod props;
pub mod synth;
pub mod template;
pub mod units;

pub use clump::{make_template, ClumpError, ClumpParams, Length, ParamError};
pub use descriptors::{convex_hull, shape_descriptors, ShapeDescriptors};
pub use error::OutlineError;
pub use lattice_elastic::{lattice_elastic, link_stiffness, Elastic, LinkStiffness};
pub use outline::{
    find_self_intersection, parse_outline, read_outline, resample, Outline, ReadOptions, SelfHit,
};
pub use props::{polygon_props, PolygonProps};
pub use synth::{scale_to_area, synth_grain, SynthParams};
pub use template::{Method, Template};
pub use units::Units;
