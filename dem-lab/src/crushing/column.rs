//! A crushable granular column under one-dimensional compression (`dem test column`; issue 25
//! item 5, after S3 in `shared/SOURCES.md`): 200+ lattice grains (docs/lattice.md) in a box of
//! rigid walls, compressed by a top platen moving down at a constant speed (an oedometer: the
//! side walls keep the lateral strain zero).
//!
//! The grains: outlines (e.g. `data/outlines`) scaled to `size_classes` equivalent diameters
//! spaced geometrically in `[d_min, d_max]`, each filled with a lattice of one absolute spacing
//! S (so a fragment's size means the same in every grain, and one fines cutoff serves all),
//! links with the springs of docs/lattice.md §2 and the chosen criterion, as `dem test crush`
//! ([`crate::crushing::grain`]). Placement (seeded): each grain draws an outline and a size class and is
//! deposited: of 12 random (angle, x) candidates, each dropped straight down until a node
//! disc meets a placed one or the floor (a gap of 0.1 S kept), the one resting lowest is taken
//! (a greedy geometric deposit, no dynamics). The top platen starts just above the highest
//! grain. No gravity. **Seating** (`<name>-seat.json`): the grains as rigid clumps (they cannot
//! break) and the top platen moving down at `seat_speed` until both platens carry
//! `seat_stress`; the loose deposit compacts there at a fraction of the cost (a rigid grain's
//! time step is several times a node's). **Loading** (`<name>.json`): the lattice grains at the
//! seated poses, at rest, the top platen from its seated height H0 down at the platen speed.
//!
//! Measured:
//!
//! - vertical stress σ_v = F/(W t) (W the box width) of the top and the bottom platen against
//!   the vertical strain ε_v = δ/H0 (δ the platen's travel, H0 the initial gap); frictionless
//!   side walls by default, so the two agree at equilibrium, and σ_v, where a level is asked,
//!   is the smaller of the two (the top platen alone also feels the impacts of compaction);
//! - the grading (fragment sizes: connected components of each grain's intact links,
//!   [`dem_core::fragments`], their equivalent diameters) the first time σ_v reaches each of
//!   `stress_levels`, as the fraction passing a set of sieve sizes, and Hardin's relative
//!   breakage B_r ([`relative_breakage`]); the run ends at the last level (or at `max_strain`);
//! - every broken link (`<name>.breaks.csv`), the energy balance, particle-steps/s;
//! - quasi-static checks: the inertial number at each level, `I = ε̇ d̄ √(ρ/σ_v)` (GDR MiDi
//!   2004, "On dense granular flows", Eur. Phys. J. E 14:341–365; I ≲ 1e-3 is the quasi-static
//!   regime), and the kinetic over the strain energy there.
//!
//! Platen speed: given, else from a target inertial number at the first stress level,
//! `v = I·H0·√(σ_1/ρ)/d̄` (d̄ the mean grain size).

use super::lattice::{self, EndEnergy, LatticeScene, Rows};
use crate::run::{run_scene, LabRun};
use crate::specimen::relax;
use crate::tests::harness::{self, DtFactor, RunFacts};
use crate::LabError;
use clumpgen::clump::LatticeParams;
use clumpgen::synth::SplitMix64;
use clumpgen::{make_template, ClumpParams, Length, Method, ReadOptions, Template};
use dem_core::fragments::{self, LatticeGrain};
use dem_core::output::driver::{RunOptions, StepHook};
use dem_core::output::history::Record;
use dem_core::scene::schema::{ClumpMode, ClumpSetSpec, PlacementSpec, SceneFile};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::grain::{extent, CrushTest, LinkCriterion};

const TEST: &str = "column";

/// Hardin's (1985) breakage potential of a grading given as pieces `(d, mass)`:
/// `B_p = ∫₀¹ b_p df`, with `b_p = log10(D/d_f)` for `D ≥ d_f` and 0 below (f the mass fraction
/// passing, D the size at f, d_f the fines cutoff; Hardin, B.O. 1985, "Crushing of soil
/// particles", J. Geotech. Eng. 111(10):1177–1192, where d_f = 0.074 mm, the No. 200 sieve).
/// On a plot of f against log10 D it is the area between the grading curve and the vertical
/// line at d_f. For discrete pieces the curve is a staircase and the integral is exact:
/// `B_p = Σ w_i max(0, log10(d_i/d_f))`, w_i the mass fractions. 0 for no mass.
pub fn breakage_potential(pieces: &[(f64, f64)], d_f: f64) -> f64 {
    let total: f64 = pieces.iter().map(|p| p.1).sum();
    if total.is_nan() || total <= 0.0 || d_f.is_nan() || d_f <= 0.0 {
        return 0.0;
    }
    pieces
        .iter()
        .map(|&(d, m)| m * (d / d_f).log10().max(0.0))
        .sum::<f64>()
        / total
}

/// Hardin's (1985) relative breakage `B_r = B_t/B_p`: `B_p` the breakage potential of the
/// initial grading, `B_t = B_p(initial) − B_p(current)` the total breakage, the area between
/// the initial and the current grading curves above the fines cutoff d_f (see
/// [`breakage_potential`]). 0 when the initial grading has no potential (all finer than d_f).
pub fn relative_breakage(initial: &[(f64, f64)], current: &[(f64, f64)], d_f: f64) -> f64 {
    let bp = breakage_potential(initial, d_f);
    if bp > 0.0 {
        let br = (bp - breakage_potential(current, d_f)) / bp;
        // The same pieces summed in another order differ in the last bits: no breakage.
        if br.abs() < 1e-12 {
            0.0
        } else {
            br
        }
    } else {
        0.0
    }
}

/// Mass fraction of `pieces` `(d, mass)` finer than or equal to each of `sieves`.
pub fn passing(pieces: &[(f64, f64)], sieves: &[f64]) -> Vec<f64> {
    let total: f64 = pieces.iter().map(|p| p.1).sum();
    sieves
        .iter()
        .map(|&s| {
            if total > 0.0 {
                pieces.iter().filter(|p| p.0 <= s).map(|p| p.1).sum::<f64>() / total
            } else {
                0.0
            }
        })
        .collect()
}

/// A crushable column test (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ColumnTest {
    /// Scene `<name>.json`, outputs `<name>.out/`, result `<name>.result.json` (default
    /// "column").
    pub name: String,
    /// Number of grains (default 210).
    pub grains: usize,
    /// Box width as a multiple of d_max (default 20).
    pub width: f64,
    /// Grain sizes: equivalent diameters of `size_classes` classes spaced geometrically in
    /// [d_min, d_max] (m; defaults 1.2 and 2 mm, 3 classes). Each grain draws a class.
    pub d_min: f64,
    pub d_max: f64,
    pub size_classes: usize,
    /// Lattice spacing S (m, every grain; default 0.2 mm) and node radius fraction f.
    pub spacing: f64,
    pub node_radius: f64,
    /// Disc thickness t (m; default 1, as `dem test crush` with an outline).
    pub thickness: f64,
    /// Grain material: E (Pa), ν (0 ≤ ν < 1/3), ρ (kg/m³), link criterion.
    pub young: f64,
    pub poisson: f64,
    pub density: f64,
    pub criterion: LinkCriterion,
    /// Friction of node–node contacts (0.5), node–platen (0.5), node–side wall (0: smooth).
    pub friction: f64,
    pub platen_friction: f64,
    pub wall_friction: f64,
    /// Placement seed (outline, size class, angle of each grain).
    pub seed: u64,
    /// Vertical stresses (Pa, increasing) at which the grading is recorded; the run ends at the
    /// last one.
    pub stress_levels: Vec<f64>,
    /// Seating (before loading): rigid grains (they cannot break), the top platen moving down
    /// at `seat_speed` (m/s, default 1) until both platens carry `seat_stress` (Pa, below the
    /// first level; default 0.5 MPa).
    pub seat_stress: f64,
    pub seat_speed: f64,
    /// How the top platen loads the column (default [`Loading::Inertial`]).
    pub loading: Loading,
    /// [`Loading::Ramp`]: the platen speed (m/s); `None`: from `inertial_number` at the first
    /// level (module docs).
    pub speed: Option<f64>,
    /// The inertial number I = ε̇ d̄ √(ρ/σ_v) held throughout ([`Loading::Inertial`], default
    /// 1e-3) or at the first level ([`Loading::Ramp`] without `speed`).
    pub inertial_number: f64,
    /// The run's cap: platen travel over H0 (default 0.5).
    pub max_strain: f64,
    pub dt_factor: DtFactor,
    pub local_damping: f64,
    /// History row every this many steps (default 50).
    pub history_every: u64,
}

/// How the top platen loads the column.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Loading {
    /// The platen's speed follows the stress so that the inertial number stays at
    /// `inertial_number`: v = I (H0 − δ) √(σ/ρ) / d̄ each `history_every` steps, σ the bottom
    /// platen's stress (not below `seat_stress`). GDR MiDi (2004) find granular flows
    /// rate-independent (quasi-static) for I ≲ 1e-3; a constant speed at that I for the first
    /// level would load the last one at I √(σ_1/σ_n), far slower than needed.
    #[default]
    Inertial,
    /// A constant platen speed. Not quasi-static at the speeds affordable here: at I = 0.01
    /// at the first level the bottom platen carried a third of the top's stress in the
    /// first contact, and halving the speed changed B_r at 10 and 20 MPa by 20–25 %.
    Ramp,
}

impl Default for ColumnTest {
    fn default() -> ColumnTest {
        // The material of the single-grain study.
        let grain = CrushTest::default();
        ColumnTest {
            name: TEST.into(),
            grains: 210,
            width: 20.0,
            d_min: 1.2e-3,
            d_max: 2.0e-3,
            size_classes: 3,
            spacing: 0.2e-3,
            node_radius: 0.9,
            thickness: 1.0,
            young: grain.young,
            poisson: grain.poisson,
            density: grain.density,
            criterion: grain.criterion,
            friction: grain.friction,
            platen_friction: grain.platen_friction,
            wall_friction: 0.0,
            seed: 1,
            stress_levels: vec![2e6, 5e6, 10e6, 20e6, 40e6],
            seat_stress: 0.5e6,
            seat_speed: 1.0,
            speed: None,
            inertial_number: 1e-3,
            max_strain: 0.5,
            dt_factor: DtFactor::default(),
            local_damping: harness::LOCAL_DAMPING,
            history_every: 50,
            loading: Loading::Inertial,
        }
    }
}

fn param(field: &str, reason: impl Into<String>) -> LabError {
    lattice::param(TEST, field, reason)
}

impl ColumnTest {
    /// Checks every value; errors name the field (`column.<field>`).
    pub fn validate(&self) -> Result<(), LabError> {
        for (f, v) in [
            ("width", self.width),
            ("d_min", self.d_min),
            ("d_max", self.d_max),
            ("spacing", self.spacing),
            ("thickness", self.thickness),
            ("young", self.young),
            ("density", self.density),
            ("inertial_number", self.inertial_number),
        ] {
            harness::positive(TEST, f, v)?;
        }
        if self.grains == 0 {
            return Err(param("grains", "must be at least 1"));
        }
        if self.grains > 100_000 {
            return Err(param(
                "grains",
                format!("{}: more than 100000 grains", self.grains),
            ));
        }
        if self.d_max < self.d_min {
            return Err(param(
                "d_max",
                format!("{:e} m is below d_min ({:e} m)", self.d_max, self.d_min),
            ));
        }
        if self.size_classes == 0 || self.size_classes > 20 {
            return Err(param(
                "size_classes",
                format!("{}: must be 1 to 20", self.size_classes),
            ));
        }
        if self.spacing >= self.d_min {
            return Err(param(
                "spacing",
                format!(
                    "{:e} m is not below the smallest grain size d_min ({:e} m)",
                    self.spacing, self.d_min
                ),
            ));
        }
        if self.width < 2.0 {
            return Err(param(
                "width",
                format!("{}: the box must be at least 2 d_max wide", self.width),
            ));
        }
        if !(self.node_radius > 0.0 && self.node_radius <= 1.0) {
            return Err(param(
                "node_radius",
                format!("{}: a fraction of S/2 in (0, 1]", self.node_radius),
            ));
        }
        lattice::check_poisson(TEST, self.poisson)?;
        self.criterion.validate_for(TEST)?;
        for (f, v) in [
            ("friction", self.friction),
            ("platen_friction", self.platen_friction),
            ("wall_friction", self.wall_friction),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(param(f, format!("{v}: must be >= 0")));
            }
        }
        if self.stress_levels.is_empty() {
            return Err(param("stress_levels", "give at least one stress level"));
        }
        let mut last = 0.0;
        for &s in &self.stress_levels {
            if !(s.is_finite() && s > last) {
                return Err(param(
                    "stress_levels",
                    format!("{s:e} Pa: levels must be positive, finite and increasing"),
                ));
            }
            last = s;
        }
        if let Some(v) = self.speed {
            harness::positive(TEST, "speed", v)?;
        }
        harness::positive(TEST, "seat_speed", self.seat_speed)?;
        if !(self.seat_stress > 0.0 && self.seat_stress < self.stress_levels[0]) {
            return Err(param(
                "seat_stress",
                format!(
                    "{:e} Pa: must be positive and below the first stress level ({:e} Pa)",
                    self.seat_stress, self.stress_levels[0]
                ),
            ));
        }
        if !(self.max_strain > 0.0 && self.max_strain < 1.0) {
            return Err(param(
                "max_strain",
                format!("{}: a fraction of H0 in (0, 1)", self.max_strain),
            ));
        }
        self.dt_factor.check(&format!("{TEST}.dt_factor"))?;
        if !(self.local_damping >= 0.0 && self.local_damping < 1.0) {
            return Err(param(
                "local_damping",
                format!("{}: must lie in [0, 1)", self.local_damping),
            ));
        }
        if self.history_every == 0 {
            return Err(param("history_every", "must be at least 1"));
        }
        harness::plain_name(TEST, &self.name)
    }

    /// The equivalent diameters of the size classes (m), increasing.
    pub fn sizes(&self) -> Vec<f64> {
        let n = self.size_classes;
        (0..n)
            .map(|k| {
                if n == 1 {
                    self.d_min
                } else {
                    self.d_min * (self.d_max / self.d_min).powf(k as f64 / (n - 1) as f64)
                }
            })
            .collect()
    }

    /// The fines cutoff d_f of Hardin's breakage measures: the equivalent diameter of two
    /// lattice cells, `2√(2A_c/π)`, `A_c = (√3/2)S²` (≈ 1.49 S). A single node, the finest
    /// piece the lattice holds (fines, [`dem_core::fragments`]), is below it: its mass is that of
    /// 0.45–1.5 cells (docs/lattice.md §1).
    pub fn fines_cutoff(&self) -> f64 {
        let a_c = 0.5 * 3f64.sqrt() * self.spacing * self.spacing;
        2.0 * (2.0 * a_c / std::f64::consts::PI).sqrt()
    }
}

/// The grading recorded at one stress level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grading {
    /// The level asked (Pa; 0 for the initial grading) and σ_v when it was recorded (Pa).
    pub level: f64,
    pub stress: f64,
    /// Vertical strain δ/H0 and time (s) then.
    pub strain: f64,
    pub time: f64,
    /// Links broken so far.
    pub broken_links: usize,
    /// Pieces of two nodes or more, single-node fines, and the fines' mass fraction.
    pub fragments: usize,
    pub fines: usize,
    pub fines_mass_fraction: f64,
    /// Hardin's breakage potential of this grading and the relative breakage B_r against the
    /// initial one.
    pub breakage_potential: f64,
    pub relative_breakage: f64,
    /// Inertial number ε̇ d̄ √(ρ/σ_v) and the kinetic over the strain energy then.
    pub inertial_number: f64,
    pub kinetic_over_strain: f64,
    /// The unbalanced-force ratio then ([`crate::specimen::relax::unbalanced_ratio`]) and
    /// the platen's speed (m/s).
    #[serde(default)]
    pub unbalanced_ratio: f64,
    #[serde(default)]
    pub platen_speed: f64,
    /// Mass fraction passing each of [`ColumnReport::sieves`].
    pub passing: Vec<f64>,
}

/// What the test measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColumnReport {
    /// Grains, nodes, links; the templates (outline, size class) used.
    pub grains: usize,
    pub nodes: usize,
    pub links: usize,
    /// Lattice springs (N/m).
    pub k_n: f64,
    pub k_s: f64,
    /// Box width W and platen gap H0 (m) at the start of loading (after seating); solid
    /// fraction then, and of the deposit before seating (gap `deposit_height`).
    pub width: f64,
    pub height: f64,
    pub initial_solid_fraction: f64,
    pub deposit_height: f64,
    pub deposit_solid_fraction: f64,
    /// Mean grain size d̄ (mass-weighted d_eq, m), the fines cutoff d_f (m).
    pub mean_size: f64,
    pub fines_cutoff: f64,
    /// Platen speed (m/s): the ramp's, or the inertial loading's at the start.
    pub platen_speed: f64,
    /// Sieve sizes (m) of the gradings, increasing.
    pub sieves: Vec<f64>,
    /// The initial grading (level 0) and one a stress level reached, in order.
    pub gradings: Vec<Grading>,
    /// Levels asked but not reached within `max_strain`.
    pub levels_not_reached: Vec<f64>,
    /// Largest σ_v (the smaller of the platens' stresses; Pa) and the strain at it.
    pub peak_stress: f64,
    pub strain_at_peak: f64,
    /// Energy at the end (J): boundary work, strain, kinetic, damping, friction, released;
    /// the balance error relative to the work.
    pub work: f64,
    pub strain_energy: f64,
    pub kinetic_energy: f64,
    pub damping: f64,
    pub friction: f64,
    pub released: f64,
    pub balance_error: f64,
    /// Nodes × steps / wall time.
    pub particle_steps_per_s: f64,
}

/// The result file `<name>.result.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColumnOutcome {
    pub test: ColumnTest,
    /// The outline files the grains were made from.
    pub outlines: Vec<PathBuf>,
    pub result: ColumnReport,
    /// The seating run (rigid grains) and the loading run.
    pub seat: RunFacts,
    pub run: RunFacts,
}

/// One grain as drawn and placed.
struct Placed {
    template: usize,
    x: f64,
    y: f64,
    angle: f64,
}

/// The templates: every outline at every size class, template `o·classes + k`. Errors name the
/// outline file and the size.
pub fn templates(test: &ColumnTest, outlines: &[PathBuf]) -> Result<Vec<Template>, LabError> {
    let mut out = vec![];
    for file in outlines {
        let ol0 =
            clumpgen::read_outline(file, &ReadOptions::default()).map_err(|e| LabError::Param {
                field: "outlines".into(),
                reason: e.to_string(),
            })?;
        for d in test.sizes() {
            let mut ol = ol0.clone();
            ol.points = clumpgen::scale_to_area(&ol0.points, std::f64::consts::PI * 0.25 * d * d);
            let p = ClumpParams {
                method: Method::Lattice,
                density: test.density,
                thickness: test.thickness,
                lattice: Some(LatticeParams {
                    spacing: Length::Metres(test.spacing),
                    node_radius: test.node_radius,
                }),
                ..ClumpParams::default()
            };
            let t = make_template(&ol, &p).map_err(|e| LabError::Param {
                field: "outlines".into(),
                reason: format!(
                    "{} scaled to d_eq {:.4} mm with spacing {:.4} mm: {e}",
                    file.display(),
                    d * 1e3,
                    test.spacing * 1e3
                ),
            })?;
            out.push(t);
        }
    }
    if out.is_empty() {
        return Err(LabError::Param {
            field: "outlines".into(),
            reason: "no outline files given".into(),
        });
    }
    Ok(out)
}

/// Draws the grains and deposits them (module docs). Returns the placements, the box width
/// and the top of the highest grain.
fn place(test: &ColumnTest, tpls: &[Template]) -> (Vec<Placed>, f64, f64) {
    let mut rng = SplitMix64::new(test.seed);
    let w = test.width * test.d_max;
    let gap = 0.1 * test.spacing;
    // Placed node discs, binned by x in columns of width `cw` (at least one disc diameter plus
    // the gap, so a disc meets only discs of its own and the two next columns).
    let r_max = tpls
        .iter()
        .flat_map(|t| t.discs.iter().map(|d| d.r))
        .fold(0.0, f64::max);
    let cw = 2.0 * r_max + gap;
    let ncol = (w / cw).ceil() as usize + 1;
    let mut cols: Vec<Vec<[f64; 3]>> = vec![vec![]; ncol];
    let col_of = |x: f64| ((x / cw).floor().max(0.0) as usize).min(ncol - 1);
    let mut out = Vec::with_capacity(test.grains);
    let mut top = 0.0f64;
    for _ in 0..test.grains {
        let t = (rng.next_u64() % tpls.len() as u64) as usize;
        let tpl = &tpls[t];
        // Candidates: DEPOSIT_TRIES (angle, x) pairs; the grain drops straight down from each
        // until a node disc meets a placed one or the floor (a gap of 0.1 S kept), and the
        // candidate whose centroid comes to rest lowest is taken.
        let mut best: Option<(f64, Placed, Vec<[f64; 3]>)> = None;
        for _ in 0..DEPOSIT_TRIES {
            let angle = rng.range(0.0, std::f64::consts::TAU);
            let e = extent(tpl, angle);
            let lo = gap - e[0];
            let hi = w - gap - e[2];
            let x = if hi > lo {
                rng.range(lo, hi)
            } else {
                0.5 * (lo + hi)
            };
            let (sn, cs) = angle.sin_cos();
            let nodes: Vec<[f64; 3]> = tpl
                .discs
                .iter()
                .map(|d| [x + cs * d.x - sn * d.y, sn * d.x + cs * d.y, d.r])
                .collect();
            // The lowest centroid height y such that every node clears the floor and every
            // placed disc.
            let mut y = gap - e[1];
            for n in &nodes {
                let c = col_of(n[0]);
                for col in &cols[c.saturating_sub(1)..=(c + 1).min(ncol - 1)] {
                    for p in col {
                        let reach = n[2] + p[2] + gap;
                        let dx = n[0] - p[0];
                        if dx.abs() < reach {
                            y = y.max(p[1] + (reach * reach - dx * dx).sqrt() - n[1]);
                        }
                    }
                }
            }
            if best.as_ref().is_none_or(|b| y < b.0) {
                best = Some((
                    y,
                    Placed {
                        template: t,
                        x,
                        y,
                        angle,
                    },
                    nodes,
                ));
            }
        }
        let (y, p, nodes) = best.expect("DEPOSIT_TRIES > 0");
        for n in nodes {
            let placed = [n[0], n[1] + y, n[2]];
            top = top.max(placed[1] + placed[2]);
            cols[col_of(placed[0])].push(placed);
        }
        out.push(p);
    }
    (out, w, top)
}

/// Candidate (angle, x) pairs a grain's deposit tries.
const DEPOSIT_TRIES: usize = 12;

/// How the top platen moves in a scene.
enum Phase {
    /// Seating: rigid grains, the top platen moving down at `speed` for `duration` at most
    /// (the run stops earlier, once seated).
    Seat { speed: f64, duration: f64 },
    /// Loading: lattice grains, the top platen moving down at `speed`.
    /// The top platen down at `speed` (the hook may change it); the run's `duration` (s) a
    /// cap (the hook ends the run first).
    Load { speed: f64, duration: f64 },
}

/// The test's scene: the grains (template files `<name>.grains/<k>.json`, relative to the
/// scene, rigid for seating, bonded lattices for loading), bottom platen, two side walls, the
/// top platen at height `h`, moving as `phase` says.
#[allow(clippy::too_many_arguments)]
fn scene(
    test: &ColumnTest,
    placed: &[Placed],
    n_tpl: usize,
    k: &clumpgen::LinkStiffness,
    w: f64,
    h: f64,
    wall_top: f64,
    phase: &Phase,
) -> SceneFile {
    let seat = matches!(phase, Phase::Seat { .. });
    let mut sets = vec![];
    for t in 0..n_tpl {
        let ps: Vec<PlacementSpec> = placed
            .iter()
            .filter(|p| p.template == t)
            .map(|p| harness::placement(p.x, p.y, p.angle))
            .collect();
        if !ps.is_empty() {
            sets.push(ClumpSetSpec {
                template: format!("{}.grains/{t}.json", test.name),
                material: "grain".into(),
                mode: if seat {
                    ClumpMode::Rigid
                } else {
                    ClumpMode::Bonded
                },
                bond_group: (!seat).then(|| "lattice".into()),
                bond_tolerance: 0.0,
                placements: ps,
            });
        }
    }
    let top = wall_top;
    let (speed, duration, what) = match *phase {
        Phase::Seat { speed, duration } => (
            speed,
            duration,
            format!(
                "seating of rigid grains to {:.3} MPa at {speed:.4e} m/s",
                test.seat_stress * 1e-6
            ),
        ),
        Phase::Load { speed, duration } => (
            speed,
            duration,
            match test.loading {
                Loading::Ramp => format!("top platen down at {speed:.4e} m/s"),
                Loading::Inertial => format!(
                    "top platen down at the inertial number {} (from {speed:.4e} m/s)",
                    test.inertial_number
                ),
            },
        ),
    };
    let wall = lattice::wall;
    LatticeScene {
        name: &test.name,
        description: format!(
            "Crushable column (dem test column): {} lattice grains, box {:.3} mm wide, H0 {:.3} mm, {what}",
            test.grains,
            w * 1e3,
            h * 1e3
        ),
        thickness: test.thickness,
        density: test.density,
        k: (k.k_n, k.k_s),
        friction: test.friction,
        platen_friction: test.platen_friction,
        side_friction: Some(test.wall_friction),
        bond_group: (!seat).then(|| {
            test.criterion.bond_group(
                k.k_n,
                k.k_s,
                test.node_radius,
                test.spacing,
                test.thickness,
            )
        }),
        clumps: sets,
        walls: vec![
            wall("bottom", [0.0, 0.0], [w, 0.0], "platen", 0.0),
            wall("left", [0.0, 0.0], [0.0, top], "side", 0.0),
            wall("right", [w, 0.0], [w, top], "side", 0.0),
            wall("top", [0.0, h], [w, h], "platen", -speed),
        ],
        local_damping: test.local_damping,
        dt_factor: test.dt_factor,
        history_every: test.history_every,
        duration,
    }
    .build()
}

/// Pieces `(d_eq, mass)` of every grain's fragments.
fn pieces(w: &dem_core::World, density: f64) -> (Vec<(f64, f64)>, usize, usize, f64) {
    let f = fragments::fragments(&w.state, w.bonds.as_ref(), density, None);
    let total: f64 = f.iter().map(|p| p.mass).sum();
    let fines: Vec<&fragments::Fragment> = f.iter().filter(|p| p.is_fines()).collect();
    // fold from +0.0: an empty f64 sum is −0.0, which would print as "-0.0000".
    let fm = fines.iter().map(|p| p.mass).fold(0.0, |a, b| a + b);
    (
        f.iter().map(|p| (p.d_eq, p.mass)).collect(),
        f.len() - fines.len(),
        fines.len(),
        if total > 0.0 { fm / total } else { 0.0 },
    )
}

/// A grading as recorded by the hook (the rest is filled after the run).
struct Snap {
    level: f64,
    stress: f64,
    time: f64,
    travel: f64,
    speed: f64,
    broken: usize,
    pieces: Vec<(f64, f64)>,
    fragments: usize,
    fines: usize,
    fines_mass_fraction: f64,
    kinetic_over_strain: f64,
    unbalanced_ratio: f64,
}

/// The top platen: wall index in the scene (bottom, left, right, top).
const TOP: usize = 3;

/// The loading hook's state: the gradings taken and the platen travel sampled.
struct Loader {
    snaps: Vec<Snap>,
    travel: Vec<(f64, f64)>,
}

impl Loader {
    /// Called every `history_every` steps: samples the travel, takes a grading the first time
    /// both platens carry a level (the top one alone also feels the impacts of compaction),
    /// and with [`Loading::Inertial`] sets the platen's speed for the next steps. `area` =
    /// W t (m²), `h` = H0 (m), `d` = d̄ (m).
    fn observe(
        &mut self,
        world: &mut dem_core::World,
        test: &ColumnTest,
        area: f64,
        h: f64,
        d: f64,
    ) {
        let walls = &world.state.walls;
        let (top, bottom) = (walls[TOP].force[1] / area, -walls[0].force[1] / area);
        let travel = h - walls[TOP].a[1];
        let speed = -walls[TOP].v[1];
        self.travel.push((world.state.time, travel));
        let levels = &test.stress_levels;
        let sigma = top.min(bottom);
        while self.snaps.len() < levels.len() && sigma >= levels[self.snaps.len()] {
            let level = levels[self.snaps.len()];
            self.snaps
                .push(snap(world, test.density, level, sigma, travel, speed));
        }
        if test.loading == Loading::Inertial {
            let v = inertial_speed(test, h - travel, bottom, d);
            world.state.walls[TOP].v = [0.0, -v];
        }
    }

    /// The platen travel at `time`, linear between the samples (0 before the first).
    fn travel_at(&self, time: f64) -> f64 {
        let i = self.travel.partition_point(|p| p.0 < time);
        match (i.checked_sub(1).map(|j| self.travel[j]), self.travel.get(i)) {
            (_, Some(&(t1, x1))) if t1 == time => x1,
            (Some((t0, x0)), Some(&(t1, x1))) => x0 + (x1 - x0) * (time - t0) / (t1 - t0),
            (Some((_, x0)), None) => x0,
            (None, _) => 0.0,
        }
    }
}

/// The platen speed (m/s) that compresses a column `height` high (m) under the vertical
/// stress `sigma` (Pa; not below `seat_stress`) at the inertial number of `test`:
/// I = ε̇ d̄ √(ρ/σ) with ε̇ = v/height, so v = I height √(σ/ρ) / d̄.
fn inertial_speed(test: &ColumnTest, height: f64, sigma: f64, d: f64) -> f64 {
    test.inertial_number * height * (sigma.max(test.seat_stress) / test.density).sqrt() / d
}

/// The grading and the state of the column now, at `level` with the vertical stress `sigma`.
fn snap(
    world: &dem_core::World,
    density: f64,
    level: f64,
    sigma: f64,
    travel: f64,
    speed: f64,
) -> Snap {
    let (p, nf, nfines, fmf) = pieces(world, density);
    let e = world.energy();
    let strain = e.strain_bond + e.strain_contact;
    Snap {
        level,
        stress: sigma,
        time: world.state.time,
        travel,
        speed,
        broken: lattice::broken_links(world),
        pieces: p,
        fragments: nf,
        fines: nfines,
        fines_mass_fraction: fmf,
        kinetic_over_strain: if strain > 0.0 {
            e.kinetic() / strain
        } else {
            0.0
        },
        unbalanced_ratio: relax::unbalanced_ratio(world),
    }
}

/// The deposit: the grains placed (sorted by template: clumps are created set by set, one set a
/// template, so grain k is `placed[k]`), the box width `w`, the deposit's height `h_dep` and
/// the side walls' top, each grain's mass and the mean grain size.
struct Deposit {
    placed: Vec<Placed>,
    w: f64,
    h_dep: f64,
    wall_top: f64,
    mass: Vec<f64>,
    m_tot: f64,
    mean_size: f64,
}

impl Deposit {
    /// Draws and deposits the grains ([`place`]).
    fn new(test: &ColumnTest, tpls: &[Template]) -> Deposit {
        let (mut placed, w, top) = place(test, tpls);
        // Clumps are created set by set (one set a template), so sorted by template the
        // placements are in creation order: grain k is placed[k].
        placed.sort_by_key(|p| p.template);
        let h_dep = top + 0.1 * test.spacing;
        let wall_top = h_dep + 2.0 * test.d_max;
        // Mean grain size (mass-weighted).
        let mass: Vec<f64> = placed
            .iter()
            .map(|p| tpls[p.template].target.mass)
            .collect();
        let m_tot: f64 = mass.iter().sum();
        let mean_size = mass.iter().map(|&m| m * d_of(test, m)).sum::<f64>() / m_tot;
        Deposit {
            placed,
            w,
            h_dep,
            wall_top,
            mass,
            m_tot,
            mean_size,
        }
    }
}

/// The area (m²) of a grain of mass `m` (kg).
fn area_of(test: &ColumnTest, m: f64) -> f64 {
    m / (test.density * test.thickness)
}

/// The equivalent diameter (m) of a grain of mass `m` (kg).
fn d_of(test: &ColumnTest, m: f64) -> f64 {
    2.0 * (area_of(test, m) / std::f64::consts::PI).sqrt()
}

/// Writes the templates `<name>.grains/<k>.json`.
fn write_templates(test: &ColumnTest, tpls: &[Template], out: &Path) -> Result<(), LabError> {
    let gdir = out.join(format!("{}.grains", test.name));
    std::fs::create_dir_all(&gdir).map_err(|e| lattice::io_error(&gdir, e))?;
    for (i, t) in tpls.iter().enumerate() {
        t.save(&gdir.join(format!("{i}.json")))
            .map_err(|e| LabError::Param {
                field: "outlines".into(),
                reason: e.to_string(),
            })?;
    }
    Ok(())
}

/// Seating: rigid grains, the top platen moving down at seat_speed; done when both platens
/// carry seat_stress (`<name>-seat.json`). Moves the placements to the seated poses (loading
/// starts from them at rest) and returns the run.
fn seat(
    test: &ColumnTest,
    dep: &mut Deposit,
    tpls: &[Template],
    k: &clumpgen::LinkStiffness,
    out: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<LabRun, LabError> {
    let seat = Phase::Seat {
        speed: test.seat_speed,
        duration: 2.0 * test.max_strain * dep.h_dep / test.seat_speed,
    };
    let (w, h_dep) = (dep.w, dep.h_dep);
    let s0 = scene(
        test,
        &dep.placed,
        tpls.len(),
        k,
        w,
        h_dep,
        dep.wall_top,
        &seat,
    );
    let (sigma_seat, t) = (test.seat_stress, test.thickness);
    let seated = move |world: &dem_core::World| {
        let walls = &world.state.walls;
        walls[TOP].force[1].min(-walls[0].force[1]) / (w * t) >= sigma_seat
    };
    let r0 = lattice::run_until(
        TEST,
        &s0,
        &out.join(format!("{}-seat.json", test.name)),
        (test.history_every, Box::new(seated)),
        progress,
        || {
            format!(
                "the rigid packing did not seat at {:.3} MPa (both platens) within a platen travel of {} H0; lower seat_stress or raise max_strain",
                test.seat_stress * 1e-6,
                2.0 * test.max_strain
            )
        },
    )?;
    let cl = &r0.world.state.clumps;
    if cl.len() != dep.placed.len() {
        return Err(harness::analysis_error(
            TEST,
            "the seated packing has another number of grains than was placed",
        ));
    }
    for (c, p) in dep.placed.iter_mut().enumerate() {
        let tp = &tpls[p.template];
        if (cl.m[c] - tp.achieved.mass).abs() > 1e-9 * tp.achieved.mass {
            return Err(harness::analysis_error(
                TEST,
                format!("seated grain {c} is not the grain placed there (mass)"),
            ));
        }
        let [gx, gy] = tp.achieved.centroid;
        let (sn, cs) = cl.theta[c].sin_cos();
        p.x = cl.x[c] - (cs * gx - sn * gy);
        p.y = cl.y[c] - (sn * gx + cs * gy);
        p.angle = cl.theta[c];
    }
    Ok(r0)
}

/// The loading run's duration cap (s) and starting platen speed (m/s) on a column `h` high.
fn loading_plan(test: &ColumnTest, h: f64, mean_size: f64) -> (f64, f64) {
    match test.loading {
        // The given speed, or I at the first level (above the seating stress, by validate).
        Loading::Ramp => {
            let v = test
                .speed
                .unwrap_or_else(|| inertial_speed(test, h, test.stress_levels[0], mean_size));
            (test.max_strain * h / v, v)
        }
        // A cap the hook ends first: the whole travel at the slowest speed.
        Loading::Inertial => {
            let v0 = inertial_speed(test, h, 0.0, mean_size);
            (test.max_strain * h / v0, v0)
        }
    }
}

/// Loading (`<name>.json`): the lattice grains at the seated poses, the top platen from `h`
/// down at `v0` (the hook: the grading the first time both platens carry each level; the
/// speed with [`Loading::Inertial`]; stop after the last level or at max_strain). Returns the
/// run and the hook's record.
#[allow(clippy::too_many_arguments)]
fn load(
    test: &ColumnTest,
    dep: &Deposit,
    tpls: &[Template],
    k: &clumpgen::LinkStiffness,
    h: f64,
    (duration, v0): (f64, f64),
    out: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<(LabRun, Loader), LabError> {
    let load = Phase::Load {
        speed: v0,
        duration,
    };
    let (w, mean_size) = (dep.w, dep.mean_size);
    let s = scene(test, &dep.placed, tpls.len(), k, w, h, dep.wall_top, &load);
    let state = Rc::new(RefCell::new(Loader {
        snaps: vec![],
        travel: vec![],
    }));
    let (state_run, state_stop) = (Rc::clone(&state), Rc::clone(&state));
    let t = test.thickness;
    let test_h = test.clone();
    let hook = StepHook {
        every: test.history_every,
        run: Box::new(move |world: &mut dem_core::World| {
            state_run
                .borrow_mut()
                .observe(world, &test_h, w * t, h, mean_size);
            Ok(())
        }),
        stop: {
            let (n, travel_max) = (test.stress_levels.len(), test.max_strain * h);
            Some(Box::new(move |world: &dem_core::World| {
                state_stop.borrow().snaps.len() >= n
                    || h - world.state.walls[TOP].a[1] >= travel_max
            }))
        },
    };
    let r = run_scene(
        &s,
        &out.join(format!("{}.json", test.name)),
        &RunOptions::default(),
        progress,
        Some(hook),
    )?;
    let loader = state.replace(Loader {
        snaps: vec![],
        travel: vec![],
    });
    Ok((r, loader))
}

/// The stress–strain curve `<name>.stress_strain.csv` of the loading run's history `hist` on a
/// column `w` wide and `h` high (the platen travel from the hook's samples), and the largest
/// σ_v (the smaller of the platens' stresses) with the strain at it.
fn stress_strain(
    test: &ColumnTest,
    hist: &Record,
    loader: &Loader,
    w: f64,
    h: f64,
) -> Result<(String, f64, f64), LabError> {
    let rows = Rows::of(hist, TEST)?;
    let t = test.thickness;
    let mut csv = String::from(
        "time,platen_travel,strain,stress_top,stress_bottom,kinetic,strain_energy,broken_links\n",
    );
    let (mut peak, mut strain_at_peak) = (0.0f64, 0.0);
    for i in 0..rows.time.len() {
        let (st, sb) = (rows.top[i] / (w * t), -rows.bottom[i] / (w * t));
        let travel = loader.travel_at(rows.time[i]);
        let eps = travel / h;
        if st.min(sb) > peak {
            (peak, strain_at_peak) = (st.min(sb), eps);
        }
        csv += &format!(
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{}\n",
            rows.time[i], travel, eps, st, sb, rows.kinetic[i], rows.strain[i], rows.broken[i]
        );
    }
    Ok((csv, peak, strain_at_peak))
}

/// The sieves and the gradings: the initial one (level 0), then one a level the hook reached;
/// the column `h` high at the start of loading.
fn gradings(test: &ColumnTest, dep: &Deposit, snaps: &[Snap], h: f64) -> (Vec<f64>, Vec<Grading>) {
    let d_f = test.fines_cutoff();
    let initial: Vec<(f64, f64)> = dep.mass.iter().map(|&m| (d_of(test, m), m)).collect();
    let lo = (0.5 * test.spacing).ln();
    let hi = (1.25 * test.d_max).ln();
    let sieves: Vec<f64> = (0..=40)
        .map(|i| (lo + (hi - lo) * i as f64 / 40.0).exp())
        .collect();
    let bp0 = breakage_potential(&initial, d_f);
    // I = ε̇ d̄ √(ρ/σ), ε̇ the platen speed over the column's current height.
    let inertial = |sn: &Snap| {
        if sn.stress > 0.0 {
            sn.speed / (h - sn.travel) * dep.mean_size * (test.density / sn.stress).sqrt()
        } else {
            0.0
        }
    };
    let mut gradings = vec![Grading {
        level: 0.0,
        stress: 0.0,
        strain: 0.0,
        time: 0.0,
        broken_links: 0,
        fragments: dep.placed.len(),
        fines: 0,
        fines_mass_fraction: 0.0,
        breakage_potential: bp0,
        relative_breakage: 0.0,
        inertial_number: 0.0,
        kinetic_over_strain: 0.0,
        unbalanced_ratio: 0.0,
        platen_speed: 0.0,
        passing: passing(&initial, &sieves),
    }];
    for sn in snaps {
        gradings.push(Grading {
            level: sn.level,
            stress: sn.stress,
            strain: sn.travel / h,
            time: sn.time,
            broken_links: sn.broken,
            fragments: sn.fragments,
            fines: sn.fines,
            fines_mass_fraction: sn.fines_mass_fraction,
            breakage_potential: breakage_potential(&sn.pieces, d_f),
            relative_breakage: relative_breakage(&initial, &sn.pieces, d_f),
            inertial_number: inertial(sn),
            kinetic_over_strain: sn.kinetic_over_strain,
            unbalanced_ratio: sn.unbalanced_ratio,
            platen_speed: sn.speed,
            passing: passing(&sn.pieces, &sieves),
        });
    }
    (sieves, gradings)
}

/// `<name>.gradings.csv`: a row per grading and sieve.
fn gradings_csv(sieves: &[f64], gradings: &[Grading]) -> String {
    let mut gcsv = String::from("level,stress,strain,relative_breakage,sieve,passing\n");
    for g in gradings {
        for (s, p) in sieves.iter().zip(&g.passing) {
            gcsv += &format!(
                "{:e},{:e},{:e},{:e},{:e},{:e}\n",
                g.level, g.stress, g.strain, g.relative_breakage, s, p
            );
        }
    }
    gcsv
}

/// The break log of the loading run's final `world`: grain k is `placed[k]` (creation
/// order), its group the k-th smallest.
fn break_log(
    world: &dem_core::World,
    placed: &[Placed],
    tpls: &[Template],
) -> Result<Vec<fragments::LinkBreak>, LabError> {
    let st = &world.state;
    let order: Vec<usize> = placed.iter().map(|p| p.template).collect();
    let mut groups: Vec<(u32, u32, usize)> = vec![]; // (group, first id, nodes)
    {
        let mut by: std::collections::BTreeMap<u32, (u32, usize)> = Default::default();
        for i in 0..st.discs.len() {
            let e = by.entry(st.discs.group[i]).or_insert((u32::MAX, 0));
            e.0 = e.0.min(st.discs.id[i]);
            e.1 += 1;
        }
        for (g, (id, n)) in by {
            groups.push((g, id, n));
        }
    }
    if groups.len() != order.len()
        || groups
            .iter()
            .zip(&order)
            .any(|(g, &tk)| g.2 != tpls[tk].discs.len())
    {
        return Err(harness::analysis_error(
            TEST,
            "the grains of the run do not match the placements (grain ids out of order)",
        ));
    }
    let lats: Vec<LatticeGrain> = groups
        .iter()
        .zip(&order)
        .map(|(g, &tk)| LatticeGrain {
            grain: g.0,
            first_id: g.1,
            links: &tpls[tk].lattice.as_ref().expect("a lattice template").links,
        })
        .collect();
    Ok(world
        .bonds
        .as_ref()
        .map_or(vec![], |b| fragments::lattice_breaks(b, &lats)))
}

/// Runs the test with grains from `outlines` in the folder `out`: writes the templates
/// (`<name>.grains/`), the scene `<name>.json` (outputs `<name>.out/`), runs it, and writes
/// `<name>.stress_strain.csv`, `<name>.gradings.csv`, `<name>.breaks.csv` and
/// `<name>.result.json` (each atomically).
pub fn run(
    test: &ColumnTest,
    outlines: &[PathBuf],
    out: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<ColumnOutcome, LabError> {
    test.validate()?;
    let k = clumpgen::link_stiffness(test.young, test.poisson, test.thickness)
        .map_err(|e| param("young", e.to_string()))?;
    let tpls = templates(test, outlines)?;
    write_templates(test, &tpls, out)?;
    let mut dep = Deposit::new(test, &tpls);
    let r0 = seat(test, &mut dep, &tpls, &k, out, progress)?;
    let (w, h_dep) = (dep.w, dep.h_dep);
    let h = r0.world.state.walls[TOP].a[1];
    let solid_deposit = area_of(test, dep.m_tot) / (w * h_dep);
    let solid = area_of(test, dep.m_tot) / (w * h);
    let plan = loading_plan(test, h, dep.mean_size);
    let v0 = plan.1;
    let (r, loader) = load(test, &dep, &tpls, &k, h, plan, out, progress)?;
    let (csv, peak, strain_at_peak) = stress_strain(test, &r.history, &loader, w, h)?;
    let (sieves, gradings) = gradings(test, &dep, &loader.snaps, h);
    let gcsv = gradings_csv(&sieves, &gradings);
    let breaks = break_log(&r.world, &dep.placed, &tpls)?;
    let nodes = r.world.state.discs.len();
    let links: usize = dep
        .placed
        .iter()
        .map(|p| {
            tpls[p.template]
                .lattice
                .as_ref()
                .map_or(0, |l| l.links.len())
        })
        .sum();
    let end = EndEnergy::of(&r.history, &r.world);
    let n_levels = loader.snaps.len();
    let report = ColumnReport {
        grains: dep.placed.len(),
        nodes,
        links,
        k_n: k.k_n,
        k_s: k.k_s,
        width: w,
        height: h,
        initial_solid_fraction: solid,
        deposit_height: h_dep,
        deposit_solid_fraction: solid_deposit,
        mean_size: dep.mean_size,
        fines_cutoff: test.fines_cutoff(),
        platen_speed: v0,
        sieves,
        gradings,
        levels_not_reached: test.stress_levels[n_levels..].to_vec(),
        peak_stress: peak,
        strain_at_peak,
        balance_error: end.balance_error,
        damping: end.damping,
        friction: end.friction,
        kinetic_energy: end.kinetic_energy,
        released: end.released,
        strain_energy: end.strain_energy,
        work: end.work,
        particle_steps_per_s: lattice::particle_steps_per_s(
            nodes,
            r.summary.steps,
            r.summary.wall_time_s,
        ),
    };
    let mut figures = vec![("peak_stress", report.peak_stress)];
    figures.extend(end.figures());
    figures.push(("platen_speed", report.platen_speed));
    for g in &report.gradings {
        figures.push(("gradings.relative_breakage", g.relative_breakage));
        figures.push(("gradings.stress", g.stress));
        figures.push(("gradings.kinetic_over_strain", g.kinetic_over_strain));
    }
    lattice::all_finite(TEST, &figures)?;
    let name = &test.name;
    lattice::write_text(out, format!("{name}.stress_strain.csv"), &csv)?;
    lattice::write_text(out, format!("{name}.gradings.csv"), &gcsv)?;
    lattice::write_text(
        out,
        format!("{name}.breaks.csv"),
        &fragments::breaks_csv(&breaks),
    )?;
    let o = ColumnOutcome {
        test: test.clone(),
        outlines: outlines.to_vec(),
        result: report,
        seat: RunFacts::of(&r0),
        run: RunFacts::of(&r),
    };
    harness::write_result(&out.join(format!("{name}.result.json")), &o)?;
    Ok(o)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One size d0 broken into halves (each piece d0/2): B_t = log10 2, so
    /// B_r = log10 2 / log10(d0/d_f) (Hardin 1985's definitions in closed form).
    #[test]
    fn hardin_relative_breakage_of_halved_pieces() {
        let (d0, d_f) = (2e-3, 1e-4);
        let initial = [(d0, 3.0), (d0, 1.0)];
        let halves = [(0.5 * d0, 2.0), (0.5 * d0, 2.0)];
        let bp = breakage_potential(&initial, d_f);
        assert!((bp - (d0 / d_f).log10()).abs() < 1e-12);
        let br = relative_breakage(&initial, &halves, d_f);
        assert!((br - 2f64.log10() / (d0 / d_f).log10()).abs() < 1e-12);
        // All below the cutoff: no potential left, B_r = 1.
        let fines = [(0.5 * d_f, 4.0)];
        assert!((relative_breakage(&initial, &fines, d_f) - 1.0).abs() < 1e-12);
        // Nothing broken: 0; no mass: 0, not NaN.
        assert_eq!(relative_breakage(&initial, &initial, d_f), 0.0);
        assert_eq!(breakage_potential(&[], d_f), 0.0);
        assert_eq!(relative_breakage(&[], &[], d_f), 0.0);
    }

    /// The platen travel between samples is linear in time; 0 before the first, the last after.
    #[test]
    fn travel_is_interpolated_between_samples() {
        let l = Loader {
            snaps: vec![],
            travel: vec![(1.0, 2.0), (2.0, 4.0), (4.0, 5.0)],
        };
        assert_eq!(l.travel_at(0.5), 0.0);
        assert_eq!(l.travel_at(1.0), 2.0);
        assert_eq!(l.travel_at(1.5), 3.0);
        assert_eq!(l.travel_at(3.0), 4.5);
        assert_eq!(l.travel_at(4.0), 5.0);
        assert_eq!(l.travel_at(9.0), 5.0);
    }

    #[test]
    fn passing_fractions() {
        let p = [(1.0, 1.0), (2.0, 1.0), (4.0, 2.0)];
        assert_eq!(
            passing(&p, &[0.5, 1.0, 3.0, 4.0]),
            vec![0.0, 0.25, 0.5, 1.0]
        );
    }

    #[test]
    fn bad_values_name_their_field() {
        let bad = |f: &dyn Fn(&mut ColumnTest), field: &str| {
            let mut t = ColumnTest::default();
            f(&mut t);
            match t.validate() {
                Err(LabError::Param { field: got, .. }) => assert_eq!(got, field),
                other => panic!("{field}: {other:?}"),
            }
        };
        bad(&|t| t.grains = 0, "column.grains");
        bad(&|t| t.d_min = f64::NAN, "column.d_min");
        bad(&|t| t.d_max = 1e-3, "column.d_max");
        bad(&|t| t.spacing = 2e-3, "column.spacing");
        bad(&|t| t.poisson = 0.4, "column.poisson");
        bad(
            &|t| t.stress_levels = vec![5e6, 2e6],
            "column.stress_levels",
        );
        bad(&|t| t.stress_levels = vec![], "column.stress_levels");
        bad(&|t| t.max_strain = 1.0, "column.max_strain");
        bad(&|t| t.size_classes = 0, "column.size_classes");
        bad(
            &|t| {
                t.criterion = LinkCriterion::Energy {
                    fracture_energy: -1.0,
                }
            },
            "column.criterion.fracture_energy",
        );
        assert!(ColumnTest::default().validate().is_ok());
    }
}
