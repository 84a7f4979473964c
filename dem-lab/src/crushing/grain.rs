//! Single-grain crushing between two platens (`dem test crush`; issue 25 item 5, after S3 in
//! `shared/SOURCES.md`): one lattice grain (a `clumpgen.template/2`, docs/lattice.md) between
//! two rigid frictionless platens closing at a constant speed v each, with local damping.
//!
//! The grain: its nodes are free discs with the template's masses, its links contact bonds
//! with the lattice springs `k_n = E t/(√3(1 − ν))`, `k_s = E t (1 − 3ν)/(√3(1 − ν²))`
//! (docs/lattice.md §2, strain-energy equivalence) and the chosen criterion. The node–node
//! and node–platen contacts are linear springs of the same k_n, k_s (fragments press on each
//! other and on the platens); with nodes smaller than S/2 (radius fraction f < 1) neighbours
//! do not touch, so an intact link acts alone until its compression closes the gap (1 − f)S.
//!
//! Measured:
//!
//! - the platen force F (mean of the two platens' forces, N) against the platen closure
//!   δ = 2vt (written to `<name>.force.csv`);
//! - the crushing strength `σ = F_peak/(d·t)` (the usual definition for single-particle
//!   crushing, e.g. McDowell & Bolton 1998, in 2D with the thickness t), with **d the platen gap
//!   at first contact**: the grain's extent along the loading axis, nodes' discs included;
//! - **stage 1** (the first major breakage): the run stops at the first history row where the
//!   grain's largest fragment holds less than `major` (default 0.9) of its mass (a step hook,
//!   [`dem_core::output::driver::StepHook::stop`]); F_peak is the largest platen force up to
//!   then. A load drop alone is not taken for the breakage: a node crushed off at a platen
//!   drops the load (on `concave-01` at R_eq/S = 5.6 one broken link halved it, and the grain
//!   then turned on its new seat), while the grain is still whole. The fragments then;
//! - **stage 2** (multi-level crushing, S3: fragments keep their lattice and break again):
//!   loading continues, restarted from stage 1's final checkpoint, until the platen closure
//!   is `stage2_travel` × stage 1's; the fragments then;
//! - fragments: connected components of each grain's intact links ([`dem_core::fragments`]),
//!   their equivalent diameters from their nodes' masses; single nodes as fines;
//! - every broken link (grain, link, criterion, mode, position, time): `<name>.breaks.csv`;
//! - quasi-static checks: at the peak, the kinetic energy over the stored strain energy
//!   (bonds + contacts), and the time to the peak in P-wave transit times `d √(ρ/E)`; the
//!   energy balance of the run (boundary work against strain + kinetic + damping + friction +
//!   released energy, `dem_core::energy`).
//!
//! Quasi-static rule (as the other lab tests, [`crate::tests::harness::Loading::speed_for`]): the
//! platens close the estimated failure displacement `u_f = d·ε_link` (ε_link the link's
//! failure strain under the criterion, in tension) in `quasi_static_factor` transit times.

use super::lattice::{self, EndEnergy, LatticeScene, Rows};
use crate::run::run_scene;
use crate::tests::harness::{self, DtFactor, RunFacts};
use crate::LabError;
use clumpgen::Template;
use dem_core::fragments::{self, FragmentSummary, LatticeGrain};
use dem_core::output::driver::RunOptions;
use dem_core::scene::schema::{
    BondGroupSpec, BondModelName, ClumpMode, ClumpSetSpec, CriterionName, RunSpec, SceneFile,
};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

const TEST: &str = "crush";

/// The breakage criterion of the lattice links, with its parameter(s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LinkCriterion {
    /// Maximum force (N): a link breaks in tension at `tensile`, in shear at `shear`.
    Force { tensile: f64, shear: f64 },
    /// Maximum stress (Pa; S3's "maximum stress": the element's force over its area): a
    /// link's area is that of the edge its two nodes' hexagonal cells share, A = (S/√3)·t
    /// (the crack its break opens, as for [`LinkCriterion::Energy`]); it breaks in tension
    /// when −F_n/A ≥ `tensile`, in shear when |F_s|/A ≥ `shear`: the force criterion with
    /// F = σ·A.
    Stress { tensile: f64, shear: f64 },
    /// Maximum strain: tension at `tensile` (opening over S), shear at `shear`.
    Strain { tensile: f64, shear: f64 },
    /// Energy release rate: the material's fracture energy G_c (J/m²). A broken link opens the
    /// edge its two nodes' hexagonal cells share, S/√3 long, so a link breaks when its strain
    /// energy reaches G_c·(S/√3)·t; the bond criterion's `fracture_energy` is G_c/(f√3) for
    /// node radius fraction f (its area is 2·min(R)·t = f·S·t; docs/lattice.md §3).
    Energy { fracture_energy: f64 },
}

impl LinkCriterion {
    /// The criterion's name (`force`, `strain`, `energy`).
    pub fn name(&self) -> &'static str {
        match self {
            LinkCriterion::Force { .. } => "force",
            LinkCriterion::Stress { .. } => "stress",
            LinkCriterion::Strain { .. } => "strain",
            LinkCriterion::Energy { .. } => "energy",
        }
    }

    fn validate(&self) -> Result<(), LabError> {
        self.validate_for(TEST)
    }

    /// Checks the parameters; errors name the field `<test>.criterion.<field>`.
    pub(crate) fn validate_for(&self, test: &str) -> Result<(), LabError> {
        let check = |f: &str, v: f64| harness::positive(test, f, v).map(|_| ());
        match *self {
            LinkCriterion::Force { tensile, shear }
            | LinkCriterion::Stress { tensile, shear }
            | LinkCriterion::Strain { tensile, shear } => {
                check("criterion.tensile", tensile)?;
                check("criterion.shear", shear)
            }
            LinkCriterion::Energy { fracture_energy } => {
                check("criterion.fracture_energy", fracture_energy)
            }
        }
    }

    /// A link's area A = (S/√3)·t (m²): the edge its two nodes' hexagonal cells share, for
    /// lattice spacing `s` and thickness `t` (m).
    pub fn link_area(s: f64, t: f64) -> f64 {
        s / 3f64.sqrt() * t
    }

    /// The bond criterion of a link between nodes of radius fraction `f` of a lattice of
    /// spacing `s` and thickness `t` (m; see [`LinkCriterion::Energy`] and
    /// [`LinkCriterion::Stress`]).
    pub fn bond_criterion(&self, f: f64, s: f64, t: f64) -> dem_core::bond::Criterion {
        use dem_core::bond::Criterion;
        match *self {
            LinkCriterion::Stress { tensile, shear } => Criterion::Force {
                tensile: tensile * Self::link_area(s, t),
                shear: shear * Self::link_area(s, t),
                moment: f64::INFINITY,
            },
            LinkCriterion::Force { tensile, shear } => Criterion::Force {
                tensile,
                shear,
                moment: f64::INFINITY,
            },
            LinkCriterion::Strain { tensile, shear } => Criterion::Strain { tensile, shear },
            LinkCriterion::Energy { fracture_energy } => Criterion::Energy {
                fracture_energy: fracture_energy / (f * 3f64.sqrt()),
            },
        }
    }

    /// The lattice's bond group `lattice`: contact bonds of stiffness (`k_n`, `k_s`) with the
    /// criterion of [`LinkCriterion::bond_criterion`].
    pub(crate) fn bond_group(&self, k_n: f64, k_s: f64, f: f64, s: f64, t: f64) -> BondGroupSpec {
        use dem_core::bond::Criterion;
        let group = |criterion| BondGroupSpec {
            kn: Some(k_n),
            ks: Some(k_s),
            ..BondGroupSpec::new("lattice", BondModelName::ContactBond, criterion)
        };
        match self.bond_criterion(f, s, t) {
            Criterion::Force { tensile, shear, .. } => BondGroupSpec {
                normal_strength: Some(tensile),
                shear_strength: Some(shear),
                ..group(CriterionName::Force)
            },
            Criterion::Strain { tensile, shear } => BondGroupSpec {
                normal_strain: Some(tensile),
                shear_strain: Some(shear),
                ..group(CriterionName::Strain)
            },
            Criterion::Energy { fracture_energy } => BondGroupSpec {
                fracture_energy: Some(fracture_energy),
                ..group(CriterionName::Energy)
            },
            // Never made by bond_criterion (a link is a contact bond).
            Criterion::Stress { .. } => group(CriterionName::Stress),
        }
    }

    /// A link's failure opening strain (opening over S) in pure tension: F_t/(k_n S),
    /// σ_t A/(k_n S), ε_t, or √(2 G_c (S/√3) t / k_n)/S.
    pub fn failure_strain(&self, k_n: f64, s: f64, t: f64) -> f64 {
        match *self {
            LinkCriterion::Force { tensile, .. } => tensile / (k_n * s),
            LinkCriterion::Stress { tensile, .. } => tensile * Self::link_area(s, t) / (k_n * s),
            LinkCriterion::Strain { tensile, .. } => tensile,
            LinkCriterion::Energy { fracture_energy } => {
                (2.0 * fracture_energy * s / 3f64.sqrt() * t / k_n).sqrt() / s
            }
        }
    }
}

/// A single-grain crushing test (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CrushTest {
    /// Scene `<name>.json`, outputs `<name>.out/`, result `<name>.result.json` (default "crush").
    pub name: String,
    /// Young's modulus E (Pa), Poisson's ratio ν (0 ≤ ν < 1/3, the lattice's range), density ρ.
    pub young: f64,
    pub poisson: f64,
    pub density: f64,
    pub criterion: LinkCriterion,
    /// Friction coefficient of node–node contacts (fragments on fragments; default 0.5).
    pub friction: f64,
    /// Friction coefficient of node–platen contacts (default 0.5). Frictionless platens let
    /// an irregular grain turn and slip out sideways again and again before it is loaded
    /// (seen on `concave-01`: the load rose and fell to zero ten times in a closure of 2 % of
    /// d, no link broken).
    pub platen_friction: f64,
    /// Rotation of the grain (rad, CCW) before loading along y (default 0).
    pub angle: f64,
    /// Stage 1 ends when the largest fragment holds less than this fraction of the grain's
    /// mass (default 0.9; in (0, 1)).
    pub major: f64,
    /// Stage 2 loads on to this many times stage 1's platen closure (default 2; must be > 1).
    pub stage2_travel: f64,
    /// Platen speed (each, m/s); `None`: the quasi-static rule (module docs).
    pub speed: Option<f64>,
    /// Quasi-static rule: transit times to the estimated failure displacement (default 100;
    /// 20 gave a strength 7 % above the converged one on `concave-01`, 100 is within 0.5 %).
    pub quasi_static_factor: f64,
    /// Stage 1's cap: a platen closure of this fraction of d (default 0.2).
    pub max_closure: f64,
    pub dt_factor: DtFactor,
    pub local_damping: f64,
    /// History row every this many steps (default 20).
    pub history_every: u64,
}

impl Default for CrushTest {
    fn default() -> CrushTest {
        CrushTest {
            name: TEST.into(),
            young: 70e9,
            poisson: 0.2,
            density: 2650.0,
            criterion: LinkCriterion::Energy {
                fracture_energy: 30.0,
            },
            friction: 0.5,
            platen_friction: 0.5,
            angle: 0.0,
            major: 0.9,
            stage2_travel: 2.0,
            speed: None,
            quasi_static_factor: 100.0,
            max_closure: 0.2,
            dt_factor: DtFactor::default(),
            local_damping: harness::LOCAL_DAMPING,
            history_every: 20,
        }
    }
}

/// The grain as loaded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GrainFacts {
    /// The template file as given.
    pub template: PathBuf,
    pub id: String,
    pub nodes: usize,
    pub links: usize,
    /// Lattice spacing S (m) and node radius fraction f.
    pub spacing: f64,
    pub node_radius_fraction: f64,
    /// Equivalent diameter 2√(A/π) of the outline (m).
    pub d_eq: f64,
    /// The size d of σ = F/(d t): the platen gap at first contact (m).
    pub d: f64,
    /// Thickness t (m, the template's).
    pub thickness: f64,
    /// Lattice springs k_n, k_s (N/m) from E, ν, t.
    pub k_n: f64,
    pub k_s: f64,
}

/// The fragments at the end of a stage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StageFacts {
    /// Simulation time (s) and platen closure δ = 2vt (m) at the end of the stage.
    pub time: f64,
    pub closure: f64,
    /// Links broken so far.
    pub broken_links: usize,
    pub fragments: FragmentSummary,
}

/// What the test measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CrushReport {
    pub grain: GrainFacts,
    /// Peak platen force of stage 1 (N), the closure at it (m), σ = F_peak/(d t) (Pa).
    pub peak_force: f64,
    pub closure_at_peak: f64,
    pub strength: f64,
    /// Platen speed (each, m/s).
    pub platen_speed: f64,
    /// Quasi-static checks at the peak: kinetic over strain energy, time to the peak over the
    /// transit time d √(ρ/E).
    pub kinetic_over_strain_at_peak: f64,
    pub time_to_peak: f64,
    pub transit_time: f64,
    /// Energy at the end of the run (J): boundary work, strain (bonds + contacts), kinetic,
    /// damping, friction, released at breaks; the balance error relative to the work.
    pub work: f64,
    pub strain_energy: f64,
    pub kinetic_energy: f64,
    pub damping: f64,
    pub friction: f64,
    pub released: f64,
    pub balance_error: f64,
    pub stage1: StageFacts,
    pub stage2: StageFacts,
    /// Particle-steps per second over both stages (nodes × steps / wall time).
    pub particle_steps_per_s: f64,
}

/// The result file `<name>.result.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CrushOutcome {
    pub test: CrushTest,
    pub result: CrushReport,
    pub runs: [RunFacts; 2],
}

fn param(field: &str, reason: impl Into<String>) -> LabError {
    lattice::param(TEST, field, reason)
}

impl CrushTest {
    /// Checks every value; errors name the field (`crush.<field>`).
    pub fn validate(&self) -> Result<(), LabError> {
        harness::positive(TEST, "young", self.young)?;
        harness::positive(TEST, "density", self.density)?;
        lattice::check_poisson(TEST, self.poisson)?;
        self.criterion.validate()?;
        if !(self.friction.is_finite() && self.friction >= 0.0) {
            return Err(param("friction", "must be >= 0"));
        }
        if !(self.platen_friction.is_finite() && self.platen_friction >= 0.0) {
            return Err(param("platen_friction", "must be >= 0"));
        }
        if !self.angle.is_finite() {
            return Err(param("angle", "must be finite"));
        }
        if !(self.major > 0.0 && self.major < 1.0) {
            return Err(param(
                "major",
                format!("{}: must lie in (0, 1)", self.major),
            ));
        }
        if !(self.max_closure > 0.0 && self.max_closure < 1.0) {
            return Err(param(
                "max_closure",
                format!("{}: a fraction of d in (0, 1)", self.max_closure),
            ));
        }
        if !(self.stage2_travel.is_finite() && self.stage2_travel > 1.0) {
            return Err(param(
                "stage2_travel",
                format!(
                    "{}: must be above 1 (a multiple of stage 1's closure)",
                    self.stage2_travel
                ),
            ));
        }
        harness::plain_name(TEST, &self.name)?;
        let l = harness::Loading {
            speed: self.speed,
            quasi_static_factor: self.quasi_static_factor,
            dt_factor: self.dt_factor,
            local_damping: self.local_damping,
            stop_below: 0.5,
            max_travel_factor: 2.0,
            history_every: self.history_every,
        };
        l.validate(TEST)
    }
}

/// Loads and checks a lattice template; errors name the file.
pub fn load_template(path: &Path) -> Result<Template, LabError> {
    let t = Template::load(path).map_err(|e| LabError::Param {
        field: "template".into(),
        reason: e.to_string(),
    })?;
    if t.lattice.is_none() {
        return Err(LabError::Param {
            field: "template".into(),
            reason: format!(
                "{}: not a lattice template (clumpgen.template/2; make one with `dem clump --method lattice --spacing S`)",
                path.display()
            ),
        });
    }
    Ok(t)
}

/// The grain's facts and the nodes' extent [x0, y0, x1, y1] (m, discs included) after the
/// rotation `angle`.
fn grain_facts(
    test: &CrushTest,
    tpl: &Template,
    file: &Path,
) -> Result<(GrainFacts, [f64; 4]), LabError> {
    let lat = tpl.lattice.as_ref().expect("checked by load_template");
    let k = clumpgen::link_stiffness(test.young, test.poisson, tpl.thickness)
        .map_err(|e| param("young", e.to_string()))?;
    let ext = extent(tpl, test.angle);
    let area = tpl.target.mass / (tpl.density * tpl.thickness);
    Ok((
        GrainFacts {
            template: file.to_path_buf(),
            id: tpl.id.clone(),
            nodes: tpl.discs.len(),
            links: lat.links.len(),
            spacing: lat.spacing,
            node_radius_fraction: lat.node_radius_fraction,
            d_eq: 2.0 * (area / std::f64::consts::PI).sqrt(),
            d: ext[3] - ext[1],
            thickness: tpl.thickness,
            k_n: k.k_n,
            k_s: k.k_s,
        },
        ext,
    ))
}

/// The platen speed (each, m/s) the test runs `tpl` at: the given one, else the quasi-static
/// rule (module docs).
pub fn speed_of(test: &CrushTest, tpl: &Template) -> Result<f64, LabError> {
    if tpl.lattice.is_none() {
        return Err(LabError::Param {
            field: "template".into(),
            reason: format!("{}: not a lattice template", tpl.id),
        });
    }
    let (g, _) = grain_facts(test, tpl, Path::new(""))?;
    Ok(platen_speed(test, &g).0)
}

/// Platen speed (each, m/s): the given one, else the quasi-static rule (module docs).
fn platen_speed(test: &CrushTest, g: &GrainFacts) -> (f64, f64) {
    let u_fail = g.d * test.criterion.failure_strain(g.k_n, g.spacing, g.thickness);
    let transit = g.d * (test.density / test.young).sqrt();
    let v = test
        .speed
        .unwrap_or(u_fail / (test.quasi_static_factor * transit));
    (v, u_fail)
}

/// The test's stage-1 scene (`dem.scene/1`): the grain (template file `tpl_name`, relative to
/// the scene), two platens, the lattice bond group, local damping, a closure of `max_closure`
/// × d at most (the run stops earlier, at the first major breakage, by [`run`]'s hook).
pub fn scene(test: &CrushTest, g: &GrainFacts, ext: [f64; 4], tpl_name: &str) -> SceneFile {
    let (v, _) = platen_speed(test, g);
    let [x0, y0, x1, y1] = ext;
    let ov = g.d;
    let platen =
        |name: &str, y: f64, vy: f64| lattice::wall(name, [x0 - ov, y], [x1 + ov, y], "platen", vy);
    let clumps = vec![ClumpSetSpec {
        template: tpl_name.into(),
        material: "grain".into(),
        mode: ClumpMode::Bonded,
        bond_group: Some("lattice".into()),
        bond_tolerance: 0.0,
        placements: vec![harness::placement(0.0, 0.0, test.angle)],
    }];
    LatticeScene {
        name: &test.name,
        description: format!(
            "Single-grain crushing (dem test crush): {} between platens at {v:.4e} m/s each; d = {:.4} mm",
            g.id,
            g.d * 1e3
        ),
        thickness: g.thickness,
        density: test.density,
        k: (g.k_n, g.k_s),
        friction: test.friction,
        platen_friction: test.platen_friction,
        side_friction: None,
        bond_group: Some(test.criterion.bond_group(
            g.k_n,
            g.k_s,
            g.node_radius_fraction,
            g.spacing,
            g.thickness,
        )),
        clumps,
        walls: vec![platen("bottom", y0, v), platen("top", y1, -v)],
        local_damping: test.local_damping,
        dt_factor: test.dt_factor,
        history_every: test.history_every,
        duration: test.max_closure * g.d / (2.0 * v),
    }
    .build()
}

/// The mean platen force F = 0.5 (F_top − F_bottom) (N) per row of `r`: discs push the top
/// platen up (+y) and the bottom one down.
fn platen_force(r: &Rows) -> Vec<f64> {
    r.top
        .iter()
        .zip(&r.bottom)
        .map(|(a, b)| 0.5 * (a - b))
        .collect()
}

/// Runs the test on the template `template` in the folder `out`: copies the template there as
/// `<name>.grain.json`, writes and runs stage 1 (`<name>.json`, outputs `<name>.out/`) and
/// stage 2 (`<name>-stage2.json`, restarted from stage 1's final checkpoint, outputs
/// `<name>-stage2.out/`), and writes `<name>.force.csv`, `<name>.breaks.csv` and
/// `<name>.result.json` (each atomically).
pub fn run(
    test: &CrushTest,
    template: &Path,
    out: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<CrushOutcome, LabError> {
    test.validate()?;
    let tpl = load_template(template)?;
    let (g, ext) = grain_facts(test, &tpl, template)?;
    std::fs::create_dir_all(out).map_err(|e| lattice::io_error(out, e))?;
    let tpl_name = format!("{}.grain.json", test.name);
    tpl.save(&out.join(&tpl_name))
        .map_err(|e| LabError::Param {
            field: "template".into(),
            reason: e.to_string(),
        })?;
    let s1 = scene(test, &g, ext, &tpl_name);
    let major = test.major;
    let density = test.density;
    let why_not = format!(
        "no major breakage (largest fragment below {} of the mass) within a platen closure of {} d; raise max_closure or check the criterion",
        test.major, test.max_closure
    );
    let file1 = out.join(format!("{}.json", test.name));
    let major_breakage = move |w: &dem_core::World| {
        let f = fragments::fragments(&w.state, w.bonds.as_ref(), density, None);
        FragmentSummary::of(&f).largest_mass_fraction < major
    };
    let stop = (test.history_every, Box::new(major_breakage) as _);
    let r1 = lattice::run_until(TEST, &s1, &file1, stop, progress, || why_not)?;
    let (v, _) = platen_speed(test, &g);
    let h1 = Rows::of(&r1.history, TEST)?;
    let force1 = platen_force(&h1);
    let (ip, peak) = crate::analysis::peak(&force1)
        .ok_or_else(|| harness::analysis_error(TEST, "no platen force"))?;
    if peak.is_nan() || peak <= 0.0 {
        return Err(harness::analysis_error(
            TEST,
            "the platens never loaded the grain",
        ));
    }
    let lat = tpl.lattice.as_ref().expect("a lattice template");
    let stage = |w: &dem_core::World| -> StageFacts {
        let st = &w.state;
        let frags = fragments::fragments(st, w.bonds.as_ref(), test.density, None);
        StageFacts {
            time: st.time,
            closure: 2.0 * v * st.time,
            broken_links: lattice::broken_links(w),
            fragments: FragmentSummary::of(&frags),
        }
    };
    let stage1 = stage(&r1.world);
    // Stage 2: the same physics, no stop, to stage2_travel × stage 1's closure.
    let mut s2 = s1.clone();
    s2.run = RunSpec {
        duration: Some(test.stage2_travel * r1.world.state.time),
        dt_factor: Some(test.dt_factor.get()),
        ..RunSpec::default()
    };
    let restart = r1.out_dir.join("ckpt-final.json");
    let r2 = run_scene(
        &s2,
        &out.join(format!("{}-stage2.json", test.name)),
        &RunOptions {
            restart: Some(restart),
            ..RunOptions::default()
        },
        progress,
        None,
    )?;
    let stage2 = stage(&r2.world);
    let h = Rows::of(&r2.history, TEST)?;
    let force = platen_force(&h);
    // The force–displacement curve of both stages (stage 2's history continues stage 1's).
    let mut csv = String::from("time,closure,force,kinetic,strain_energy,broken_links\n");
    for (k, f) in force.iter().enumerate() {
        csv += &format!(
            "{:e},{:e},{:e},{:e},{:e},{}\n",
            h.time[k],
            2.0 * v * h.time[k],
            f,
            h.kinetic[k],
            h.strain[k],
            h.broken[k]
        );
    }
    lattice::write_text(out, format!("{}.force.csv", test.name), &csv)?;
    let grain_id = r2.world.state.discs.group.first().copied().unwrap_or(0);
    let first_id = r2.world.state.discs.id.iter().copied().min().unwrap_or(0);
    let breaks = r2.world.bonds.as_ref().map_or(vec![], |b| {
        fragments::lattice_breaks(
            b,
            &[LatticeGrain {
                grain: grain_id,
                first_id,
                links: &lat.links,
            }],
        )
    });
    lattice::write_text(
        out,
        format!("{}.breaks.csv", test.name),
        &fragments::breaks_csv(&breaks),
    )?;
    let end = EndEnergy::of(&r2.history, &r2.world);
    let transit = g.d * (test.density / test.young).sqrt();
    let steps = r1.summary.steps + r2.summary.steps;
    let wall = r1.summary.wall_time_s + r2.summary.wall_time_s;
    let report = CrushReport {
        peak_force: peak,
        closure_at_peak: 2.0 * v * h1.time[ip],
        strength: peak / (g.d * g.thickness),
        platen_speed: v,
        kinetic_over_strain_at_peak: if h1.strain[ip] > 0.0 {
            h1.kinetic[ip] / h1.strain[ip]
        } else {
            0.0
        },
        time_to_peak: h1.time[ip],
        transit_time: transit,
        work: end.work,
        strain_energy: end.strain_energy,
        kinetic_energy: end.kinetic_energy,
        damping: end.damping,
        friction: end.friction,
        released: end.released,
        balance_error: end.balance_error,
        stage1,
        stage2,
        particle_steps_per_s: lattice::particle_steps_per_s(g.nodes, steps, wall),
        grain: g,
    };
    let mut figures = vec![
        ("peak_force", report.peak_force),
        ("strength", report.strength),
        (
            "kinetic_over_strain_at_peak",
            report.kinetic_over_strain_at_peak,
        ),
    ];
    figures.extend(end.figures());
    lattice::all_finite(TEST, &figures)?;
    let o = CrushOutcome {
        test: test.clone(),
        result: report,
        runs: [RunFacts::of(&r1), RunFacts::of(&r2)],
    };
    harness::write_result(&out.join(format!("{}.result.json", test.name)), &o)?;
    Ok(o)
}

/// Rotated extent [x0, y0, x1, y1] of a template's node discs about its origin.
pub(super) fn extent(t: &Template, angle: f64) -> [f64; 4] {
    let (s, c) = angle.sin_cos();
    let mut e = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for d in &t.discs {
        let (x, y) = (c * d.x - s * d.y, s * d.x + c * d.y);
        e = [
            e[0].min(x - d.r),
            e[1].min(y - d.r),
            e[2].max(x + d.r),
            e[3].max(y + d.r),
        ];
    }
    e
}
