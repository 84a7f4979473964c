//! Bonded-disc specimens of a brittle material, built three ways (S0, Ye & Xu 2010; the
//! generation procedure of S4, Tan et al., which is PFC's, Potyondy & Cundall 2004 §3.1):
//!
//! ```text
//! generator  random discs at half size in four frictionless walls (stiffer than the discs),
//!            radii grown to the target porosity, uniform radius change to the isotropic
//!            stress σ0 (read from the wall forces), floaters re-sized or removed, equilibrium
//! methods    traditional: one disc per grain, parallel bonds at every disc-disc contact
//!            orc:         discs grouped into grains (grains.rs), each grain one rigid clump
//!                         with the summed disc properties (`dem_core::clump::orc`),
//!                         grain-boundary bonds between clumps
//!            improved:    each grain's cell filled with a clumpgen template (≤ 9 discs, solved
//!                         masses), placed as a bonded clump (intra-grain bond group), packed
//!                         by servo-controlled walls to σ0, grain-boundary bonds between grains
//!            few:         (`GrainMode::Few`, few.rs) ORC and improved from the traditional
//!                         packing of the seed with a few synthetic irregular grains (S0:
//!                         "the irregular grains are few"), as many as S0's disc counts ask
//!            all three:   walls removed, relaxed with local damping until the kinetic energy
//!                         is below `ke_ratio` × the stored strain energy
//! summary    discs, grains, porosity, coordination, bonds, residual kinetic energy, stresses
//! io         the `dem.specimen/1` file any scene can load, and the summary beside it
//! ```
//!
//! Everything is deterministic per seed (own RNG, [`rng`]; the engine is bit-identical for any
//! thread count).

pub mod cache;
pub mod few;
pub mod generator;
pub mod grains;
pub mod groups;
pub mod improved;
pub mod io;
pub mod methods;
pub mod relax;
pub mod rng;
pub mod summary;

pub use methods::{generate, Specimen};
pub use summary::Summary;

use dem_core::bond::BondError;
use dem_core::pipeline::WorldError;
use serde::{Deserialize, Serialize};

/// Name of the bond group between grains (every bond of a traditional specimen).
pub const GRAIN_BOUNDARY: &str = "grain_boundary";
/// Name of the bond group inside improved-ORC grains.
pub const INTRA_GRAIN: &str = "intra_grain";
/// Material name the specimen file uses for its discs (a scene defines its properties).
pub const DEFAULT_MATERIAL: &str = "specimen";

/// The fewest mean disc diameters 2r̄ = r_min + r_max that a specimen, and each lab test's
/// resolving dimension (the compression specimen's width, the Brazilian disc's diameter, the
/// bending beam's height), must span. Below it the geometry is refused, not warned about.
///
/// Resolution, the number of particles across the specimen, is a parameter of a bonded-particle
/// model: Potyondy & Cundall (2004, A bonded-particle model for rock, IJRMMS 41:1329–1364)
/// treat particle size as a model property that changes the measured strengths, and their own
/// PFC2D specimens are tens of particles across; Ding, Zhang, Zhu & Zhang (2014, Effect of
/// model scale and particle size distribution on PFC3D simulation results, Rock Mech Rock Eng
/// 47, doi:10.1007/s00603-013-0533-1) find that the scatter (coefficient of variation) of the
/// simulated UCS, E and ν falls markedly as the specimen-to-particle size ratio L/d grows, and
/// is larger in 2D than in 3D. Neither gives a hard lower bound, so 5 is a floor for
/// *meaningless* geometry, not a recommendation for good results (aim for 20 and more, as
/// those studies do): at 5 diameters a compression specimen still has about 3 diameters of
/// interior between its default lateral gauges (2 mean radii reaching into each side), a beam
/// has 2 discs on either side of its neutral axis, and a Brazilian disc has a loaded diameter
/// of 5 discs; below it a test measures a few force chains. The project's own coarse
/// regression tests run at 5.8 (a 1.5 mm beam) to 11.5 (a 3 mm disc) diameters of
/// 0.10–0.16 mm discs and keep passing.
pub const MIN_DIAMETERS_ACROSS: f64 = 5.0;

/// How grains are modelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// One disc per grain.
    Traditional,
    /// Overlapping rigid clusters (Ashmawy et al. 2003): one rigid clump per grain.
    Orc,
    /// Improved ORC (Ye & Xu 2010): template discs with solved masses, bonded inside the grain.
    Improved,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Traditional => "traditional",
            Method::Orc => "orc",
            Method::Improved => "improved",
        }
    }

    pub fn parse(s: &str) -> Option<Method> {
        match s.to_ascii_lowercase().as_str() {
            "traditional" => Some(Method::Traditional),
            "orc" => Some(Method::Orc),
            "improved" | "improved_orc" | "improved-orc" => Some(Method::Improved),
            _ => None,
        }
    }
}

/// Radius distribution between `r_min` and `r_max`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RadiusDist {
    Uniform,
    /// Normal with mean (r_min + r_max)/2 and standard deviation (r_max − r_min)/6, truncated
    /// to [r_min, r_max] by rejection (S4: "radii normally distributed").
    Normal,
}

/// Micro-parameters used while the specimen is built (contacts, walls, bonds). A scene that
/// loads the specimen sets its own; these are written to the summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MicroParams {
    /// Contact modulus E_c (Pa), defined by the linear contact stiffness k_n = 2 t E_c (set by
    /// [`crate::LabModel::contact_kn`]): Potyondy & Cundall's (2004, §2.3) 2D relation for the
    /// stiffness of one *ball*, used here for the contact itself. By P&C's contact relation
    /// k_n = A E / L (A = 2Rt, L = 2R: k_n = t E) this contact has the modulus 2 E_c, so a
    /// PFC2D model's contact stiffness is reproduced with half its E_c. The calibrations in
    /// `data/models` are made with this convention and absorb the factor of 2.
    pub contact_modulus: f64,
    /// k_n / k_s of contacts.
    pub stiffness_ratio: f64,
    /// Disc friction μ of the bonded specimen (packing is frictionless).
    pub friction: f64,
    /// Wall normal stiffness as a multiple of the disc k_n ("walls stiffer than discs", S4).
    /// Every disc's time step is bounded by its stiffest possible contact, so a large factor
    /// slows the whole packing down; 2 by default.
    pub wall_stiffness_factor: f64,
    /// Parallel-bond modulus Ē_c (Pa): k̄_n = Ē_c / (2 r̄) with r̄ the mean disc radius (PFC sets
    /// Ē_c/(R_A + R_B) per bond; one value per group here).
    pub bond_modulus: f64,
    /// k̄_n / k̄_s.
    pub bond_stiffness_ratio: f64,
    /// Bond radius multiplier λ̄.
    pub bond_radius_multiplier: f64,
    /// Grain-boundary bond tensile strength σ̄_c and cohesion c̄ (Pa).
    pub boundary_tensile: f64,
    pub boundary_cohesion: f64,
    /// Intra-grain bond tensile strength and cohesion (Pa), improved ORC.
    pub intra_tensile: f64,
    pub intra_cohesion: f64,
}

impl MicroParams {
    /// Defaults from a Young's modulus E (Pa) and a tensile strength σ_t (Pa): E_c = Ē_c = E,
    /// k_n/k_s = k̄_n/k̄_s = 2.5, μ = 0.5, λ̄ = 1 (Potyondy & Cundall 2004 Table 1 ratios);
    /// σ̄_c = c̄ = σ_t at grain boundaries and 2σ_t inside grains. Walls 2× stiffer.
    /// These are starting values, not a calibration.
    pub fn from_modulus(e: f64, tensile: f64) -> MicroParams {
        MicroParams {
            contact_modulus: e,
            stiffness_ratio: 2.5,
            friction: 0.5,
            wall_stiffness_factor: 2.0,
            bond_modulus: e,
            bond_stiffness_ratio: 2.5,
            bond_radius_multiplier: 1.0,
            boundary_tensile: tensile,
            boundary_cohesion: tensile,
            intra_tensile: 2.0 * tensile,
            intra_cohesion: 2.0 * tensile,
        }
    }
}

/// Everything that defines a specimen. Lengths in m, stresses in Pa.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpecimenParams {
    pub method: Method,
    pub width: f64,
    pub height: f64,
    pub r_min: f64,
    pub r_max: f64,
    pub distribution: RadiusDist,
    /// Target 2D porosity n = 1 − Σπr²/A of the initial packing (before the stress servo).
    pub porosity: f64,
    pub seed: u64,
    /// Disc thickness t (m); the geometry does not depend on it (masses and stiffnesses
    /// both scale with t).
    pub thickness: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
    pub micro: MicroParams,
    /// Isotropic stress σ0 installed before bonding (Pa, compression positive).
    pub iso_stress: f64,
    /// Relative tolerance on σ0.
    pub iso_tolerance: f64,
    /// Pairs with gap ≤ this are bonded (m); 0 = touching pairs only.
    pub bond_gap: f64,
    /// Mean equivalent grain diameter (m), ORC and improved.
    pub grain_size: f64,
    /// Template fill of improved grains: largest disc count (9 in S0), area cover (0.95 in S0),
    /// disc radius range (m).
    pub template_max_discs: usize,
    pub template_cover: f64,
    pub template_r_min: f64,
    pub template_r_max: f64,
    /// Relaxed when kinetic energy ≤ `ke_ratio` × strain energy (contacts + bonds).
    pub ke_ratio: f64,
    /// Cap on the steps of any one stage.
    pub max_stage_steps: u64,
    /// Which grains are irregular (ORC, improved): every grain cell (the default, and what a
    /// parameter set without this key means) or a few grains in the traditional packing
    /// ([`few`]). Left out of the JSON when `All`, so existing parameter sets keep their JSON
    /// (and the hashes that name cached specimens).
    #[serde(default, skip_serializing_if = "GrainMode::is_all")]
    pub grains: GrainMode,
}

/// Which grains of an ORC or improved-ORC specimen are irregular.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GrainMode {
    /// Every cell of a Voronoi grain tessellation ([`grains`], grain size `grain_size`) is an
    /// irregular grain: the whole specimen is clumps.
    #[default]
    All,
    /// A few irregular grains in the traditional packing of the same seed (S0, Ye & Xu 2010:
    /// in Si3N4 "the irregular grains are few"; Fig. 4a): see [`few`].
    Few(FewGrains),
}

impl GrainMode {
    pub fn is_all(&self) -> bool {
        matches!(self, GrainMode::All)
    }
}

/// How many irregular grains a [`GrainMode::Few`] specimen gets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IrregularCount {
    /// This many.
    Count(usize),
    /// As many as it takes for the improved-ORC specimen to have this many times the discs of
    /// the packing (Σ over the grains of template discs − replaced packing discs ≥
    /// (ratio − 1) × packing discs). S0's Si3N4 specimens: 1576 / 989
    /// ([`FewGrains::S0_DISC_RATIO`]).
    DiscRatio(f64),
}

/// The irregular grains of a [`GrainMode::Few`] specimen: synthetic outlines
/// (`clumpgen::synth::synth_grain`) of one size and shape family; see [`few`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FewGrains {
    pub count: IrregularCount,
    /// Equivalent diameter of every outline (m): area π d²/4.
    pub diameter: f64,
    /// Inertia aspect ratio √(I_max/I_min) of each outline, uniform in [min, max].
    pub aspect_min: f64,
    pub aspect_max: f64,
    /// RMS relative amplitude of the outline's Fourier roughness and depth of its dents
    /// (`SynthParams::roughness`, `SynthParams::concavity`).
    pub roughness: f64,
    pub concavity: f64,
    /// Vertices per outline.
    pub vertices: usize,
    /// Largest template disc radius (m) of these grains (the template fill's r_max; the
    /// smallest is `template_r_min`, the cover and disc cap `template_cover`,
    /// `template_max_discs`).
    pub template_r_max: f64,
    /// How an improved-ORC specimen is brought back to σ0 after its templates are put in
    /// ([`few`], "Insertion"); ORC specimens do not use it. Left out of the JSON when
    /// [`Insertion::Affine`] (the default, so the keys of earlier specimens stay valid).
    #[serde(default, skip_serializing_if = "Insertion::is_affine")]
    pub insertion: Insertion,
}

/// The stress stage after improved-ORC templates are inserted ([`few`], "Insertion").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Insertion {
    /// Settle in the fixed box, then affine steps of the box and mass centres to σ0 (the
    /// first method; Table 2's specimens).
    #[default]
    Affine,
    /// Stress-controlled walls (PFC's servo) from the ramp's stress down to σ0.
    Servo,
}

impl Insertion {
    pub fn is_affine(&self) -> bool {
        *self == Insertion::Affine
    }

    /// `affine` or `servo`.
    pub fn parse(s: &str) -> Option<Insertion> {
        match s {
            "affine" => Some(Insertion::Affine),
            "servo" => Some(Insertion::Servo),
            _ => None,
        }
    }
}

impl FewGrains {
    /// Improved-ORC discs over traditional discs in S0's Si3N4 specimens: 1576 / 989.
    pub const S0_DISC_RATIO: f64 = 1576.0 / 989.0;

    /// S0's specimens for parameters `p` (the choices are explained in [`few`]): as many
    /// grains as S0's disc ratio asks; outlines of equivalent diameter `p.grain_size` from
    /// clumpgen's "rough" family (roughness 0.10, concavity 0.2, aspect 1.2–1.8, 64 vertices;
    /// `data/outlines/README.md`); template discs no larger than the packing's smallest disc
    /// (`p.r_min`).
    pub fn s0(p: &SpecimenParams) -> FewGrains {
        FewGrains {
            count: IrregularCount::DiscRatio(Self::S0_DISC_RATIO),
            diameter: p.grain_size,
            aspect_min: 1.2,
            aspect_max: 1.8,
            roughness: 0.10,
            concavity: 0.2,
            vertices: 64,
            template_r_max: p.r_min,
            insertion: Insertion::Affine,
        }
    }

    /// Check every value; errors name the field.
    pub fn validate(&self) -> Result<(), SpecimenError> {
        let bad = |name: &str, v: f64, what: &str| {
            Err(SpecimenError::Param(format!(
                "grains.few.{name} = {v} {what}"
            )))
        };
        if !(self.diameter > 0.0 && self.diameter.is_finite()) {
            return bad("diameter", self.diameter, "must be positive");
        }
        if !(self.template_r_max > 0.0 && self.template_r_max.is_finite()) {
            return bad("template_r_max", self.template_r_max, "must be positive");
        }
        if !(self.aspect_min >= 1.0 && self.aspect_min.is_finite()) {
            return bad("aspect_min", self.aspect_min, "must be at least 1");
        }
        if !(self.aspect_max >= self.aspect_min && self.aspect_max.is_finite()) {
            return bad("aspect_max", self.aspect_max, "must be at least aspect_min");
        }
        if !(0.0..1.0).contains(&self.roughness) {
            return bad("roughness", self.roughness, "must lie in [0, 1)");
        }
        if !(0.0..1.0).contains(&self.concavity) {
            return bad("concavity", self.concavity, "must lie in [0, 1)");
        }
        if !(8..=4096).contains(&self.vertices) {
            return bad("vertices", self.vertices as f64, "must lie in [8, 4096]");
        }
        if let IrregularCount::DiscRatio(r) = self.count {
            if !(1.0..10.0).contains(&r) {
                return bad("count.disc_ratio", r, "must lie in [1, 10)");
            }
        }
        Ok(())
    }
}

impl SpecimenParams {
    /// Defaults for a `width × height` box and radii in [r_min, r_max]: normal radii,
    /// porosity 0.16, σ0 = 1 % of the tensile strength (tolerance 25 %), touching pairs bonded,
    /// grain size 4 mean disc radii, templates of ≤ 9 discs with radii from r_min/2 to 4 r_max
    /// at 95 % cover, relaxed to KE ≤ 1e-6 × strain energy, t = 1 m; micro-parameters from E
    /// and σ_t ([`MicroParams::from_modulus`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        method: Method,
        width: f64,
        height: f64,
        r_min: f64,
        r_max: f64,
        density: f64,
        youngs_modulus: f64,
        tensile_strength: f64,
        seed: u64,
    ) -> SpecimenParams {
        let r_mean = 0.5 * (r_min + r_max);
        SpecimenParams {
            method,
            width,
            height,
            r_min,
            r_max,
            distribution: RadiusDist::Normal,
            porosity: 0.16,
            seed,
            thickness: 1.0,
            density,
            micro: MicroParams::from_modulus(youngs_modulus, tensile_strength),
            iso_stress: 0.01 * tensile_strength,
            iso_tolerance: 0.25,
            bond_gap: 0.0,
            grain_size: 4.0 * r_mean,
            template_max_discs: 9,
            template_cover: 0.95,
            template_r_min: 0.5 * r_min,
            template_r_max: 4.0 * r_max,
            ke_ratio: 1e-6,
            max_stage_steps: 2_000_000,
            grains: GrainMode::All,
        }
    }

    /// Check every value.
    pub fn validate(&self) -> Result<(), SpecimenError> {
        let pos = |name: &str, v: f64| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(SpecimenError::Param(format!(
                    "{name} = {v} must be positive"
                )))
            }
        };
        pos("width", self.width)?;
        pos("height", self.height)?;
        pos("r_min", self.r_min)?;
        pos("r_max", self.r_max)?;
        pos("thickness", self.thickness)?;
        pos("density", self.density)?;
        pos("iso_stress", self.iso_stress)?;
        pos("iso_tolerance", self.iso_tolerance)?;
        pos("grain_size", self.grain_size)?;
        pos("template_cover", self.template_cover)?;
        pos("template_r_min", self.template_r_min)?;
        pos("template_r_max", self.template_r_max)?;
        pos("ke_ratio", self.ke_ratio)?;
        let m = &self.micro;
        for (n, v) in [
            ("contact_modulus", m.contact_modulus),
            ("stiffness_ratio", m.stiffness_ratio),
            ("wall_stiffness_factor", m.wall_stiffness_factor),
            ("bond_modulus", m.bond_modulus),
            ("bond_stiffness_ratio", m.bond_stiffness_ratio),
            ("bond_radius_multiplier", m.bond_radius_multiplier),
            ("boundary_tensile", m.boundary_tensile),
            ("boundary_cohesion", m.boundary_cohesion),
            ("intra_tensile", m.intra_tensile),
            ("intra_cohesion", m.intra_cohesion),
        ] {
            pos(n, v)?;
        }
        if !(m.friction >= 0.0 && m.friction.is_finite()) {
            return Err(SpecimenError::Param("friction must be ≥ 0".into()));
        }
        if self.r_max < self.r_min {
            return Err(SpecimenError::Param(format!(
                "r_max = {} m is below r_min = {} m",
                self.r_max, self.r_min
            )));
        }
        if self.template_r_max < self.template_r_min {
            return Err(SpecimenError::Param(
                "template_r_max is below template_r_min".into(),
            ));
        }
        if 2.0 * self.r_max >= self.width.min(self.height) {
            return Err(SpecimenError::Param(format!(
                "the largest disc (diameter {} m) does not fit in the {} × {} m box",
                2.0 * self.r_max,
                self.width,
                self.height
            )));
        }
        if !(self.porosity > 0.05 && self.porosity < 0.6) {
            return Err(SpecimenError::Param(format!(
                "porosity {} must lie in (0.05, 0.6)",
                self.porosity
            )));
        }
        if !(self.bond_gap >= 0.0 && self.bond_gap.is_finite()) {
            return Err(SpecimenError::Param("bond_gap must be ≥ 0".into()));
        }
        if self.template_cover >= 1.0 || self.template_max_discs == 0 {
            return Err(SpecimenError::Param(
                "template cover must be below 1 and max discs at least 1".into(),
            ));
        }
        let n_est = self.width * self.height * (1.0 - self.porosity)
            / (std::f64::consts::PI * self.r_min * self.r_min);
        if n_est > 5e6 {
            return Err(SpecimenError::Param(format!(
                "about {n_est:.0} discs: too many for the generator"
            )));
        }
        if self.max_stage_steps == 0 {
            return Err(SpecimenError::Param("max_stage_steps must be ≥ 1".into()));
        }
        if let GrainMode::Few(f) = &self.grains {
            f.validate()?;
            if f.template_r_max < self.template_r_min {
                return Err(SpecimenError::Param(format!(
                    "grains.few.template_r_max = {} m is below template_r_min = {} m",
                    f.template_r_max, self.template_r_min
                )));
            }
            if f.diameter >= self.width.min(self.height) {
                return Err(SpecimenError::Param(format!(
                    "grains.few.diameter = {} m does not fit in the {} × {} m box",
                    f.diameter, self.width, self.height
                )));
            }
        }
        Ok(())
    }
}

impl SpecimenParams {
    /// The specimen's resolution: its smaller side must span at least
    /// [`MIN_DIAMETERS_ACROSS`] mean disc diameters r_min + r_max. Not part of
    /// [`SpecimenParams::validate`] (which [`generate`] runs), so parameter sets of existing
    /// specimens still generate; `dem specimen` and the lab tests call it. The error names the
    /// side (`width` or `height`), its value and the bound.
    pub fn check_resolution(&self) -> Result<(), SpecimenError> {
        let d = self.r_min + self.r_max;
        let (field, side) = if self.width <= self.height {
            ("width", self.width)
        } else {
            ("height", self.height)
        };
        let n = side / d;
        if n.is_finite() && n >= MIN_DIAMETERS_ACROSS {
            return Ok(());
        }
        Err(SpecimenError::Geometry {
            field: field.into(),
            reason: format!(
                "{} mm is {n:.1} mean disc diameters ({:.4} mm); at least \
                 {MIN_DIAMETERS_ACROSS} are needed for a bonded specimen with an interior \
                 (resolution floor, docs/specimen.md; Potyondy & Cundall 2004, Ding et al. 2014)",
                side * 1e3,
                d * 1e3
            ),
        })
    }
}

/// Progress of a long stage, for progress bars.
#[derive(Clone, Debug)]
pub struct Progress {
    /// Stage name ("place", "grow", "stress", "floaters", "bond", "relax", ...).
    pub stage: &'static str,
    /// Completion of the stage in [0, 1] (estimated for convergence loops).
    pub fraction: f64,
    /// A short status line.
    pub message: String,
}

/// Why a specimen could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SpecimenError {
    #[error("specimen parameter: {0}")]
    Param(String),
    #[error("cannot place disc {index} of {count} without overlap after {attempts} attempts; raise the porosity or enlarge the box")]
    Placement {
        index: usize,
        count: usize,
        attempts: usize,
    },
    #[error("stage `{stage}` did not converge in {steps} steps: {detail}")]
    NoConvergence {
        stage: &'static str,
        steps: u64,
        detail: String,
    },
    /// Geometry that the particle size makes meaningless ([`SpecimenParams::check_resolution`]).
    #[error("{field}: {reason}")]
    Geometry { field: String, reason: String },
    #[error("irregular grains: {0}")]
    Irregular(String),
    #[error("grain {grain}: clump template: {source}")]
    Template {
        grain: usize,
        source: clumpgen::ClumpError,
    },
    #[error(transparent)]
    World(#[from] WorldError),
    #[error(transparent)]
    Bond(#[from] BondError),
    #[error("specimen file {file}: {reason}")]
    File { file: String, reason: String },
}
