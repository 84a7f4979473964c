//! What the single-grain and the column crushing tests share: lattice grains (their links the
//! bond group `lattice`, docs/lattice.md §2–3) in a scene of platens, the parameter checks of
//! the lattice material, the history read as platen forces, energies and break counts, the
//! energy at the end of a run, the checks before a result is written, and the written files.

use crate::run::{run_scene, LabRun};
use crate::tests::harness;
use crate::tests::harness::DtFactor;
use crate::LabError;
use dem_core::output::driver::{RunOptions, StepHook};
use dem_core::output::history::Record;
use dem_core::scene::schema::{
    BodiesSpec, BondGroupSpec, ClumpSetSpec, ContactSpec, DampingSpec, OutputSpec, RunSpec,
    SceneFile, WallSpec,
};
use std::path::Path;

pub use crate::tests::harness::param;

/// `<test>.poisson`: 0 ≤ ν < 1/3, the range of a triangular lattice (docs/lattice.md).
pub fn check_poisson(test: &str, nu: f64) -> Result<(), LabError> {
    if !(0.0..1.0 / 3.0).contains(&nu) {
        return Err(param(
            test,
            "poisson",
            format!(
                "{nu}: a triangular lattice of normal and shear springs reaches only 0 <= nu < 1/3 (docs/lattice.md)"
            ),
        ));
    }
    Ok(())
}

/// An I/O error naming `file`.
pub fn io_error(file: &Path, source: std::io::Error) -> LabError {
    LabError::Io {
        file: file.display().to_string(),
        source,
    }
}

/// Writes `text` to `<out>/<name>` atomically.
pub fn write_text(out: &Path, name: String, text: &str) -> Result<(), LabError> {
    dem_core::output::write_atomic(&out.join(name), text.as_bytes())?;
    Ok(())
}

/// A wall of `material` from `a` to `b` (m) moving at `vy` (m/s) along y.
pub fn wall(name: &str, a: [f64; 2], b: [f64; 2], material: &str, vy: f64) -> WallSpec {
    WallSpec {
        material: material.into(),
        ..harness::wall(name, a, b, [0.0, vy])
    }
}

/// A scene of lattice grains: materials `grain` (of `density`, friction `friction`), `platen`
/// and, with `side_friction`, `side`, all of the lattice springs `k` = (k_n, k_s); the grains'
/// link `bond_group` (none: rigid grains); local damping; a run of `duration` (s).
pub struct LatticeScene<'a> {
    /// The scene's name and description.
    pub name: &'a str,
    pub description: String,
    /// Disc thickness t (m) and the grains' density (kg/m³).
    pub thickness: f64,
    pub density: f64,
    /// The lattice springs (k_n, k_s) (N/m), of the links and of every contact.
    pub k: (f64, f64),
    /// Friction: node–node, node–platen, node–side wall (`None`: no side walls).
    pub friction: f64,
    pub platen_friction: f64,
    pub side_friction: Option<f64>,
    /// The links' bond group `lattice` (`None`: rigid grains).
    pub bond_group: Option<BondGroupSpec>,
    /// The grains and the walls.
    pub clumps: Vec<ClumpSetSpec>,
    pub walls: Vec<WallSpec>,
    /// Local damping α, the time-step factor, the history cadence (steps) and the run's
    /// duration (s).
    pub local_damping: f64,
    pub dt_factor: DtFactor,
    pub history_every: u64,
    pub duration: f64,
}

impl LatticeScene<'_> {
    /// The scene (`dem.scene/1`).
    pub fn build(self) -> SceneFile {
        let (kn, ks) = self.k;
        let mut materials = vec![
            crate::model::material("grain", Some(self.density), kn, ks, self.friction),
            crate::model::material("platen", None, kn, ks, self.platen_friction),
        ];
        let mut pairs = vec![crate::model::pair(
            "grain",
            "platen",
            kn,
            ks,
            self.platen_friction,
        )];
        if let Some(mu) = self.side_friction {
            materials.push(crate::model::material("side", None, kn, ks, mu));
            pairs.push(crate::model::pair("grain", "side", kn, ks, mu));
        }
        SceneFile {
            description: self.description,
            thickness: Some(self.thickness),
            materials,
            contact: ContactSpec {
                pairs,
                ..ContactSpec::default()
            },
            bond_groups: self.bond_group.into_iter().collect(),
            bodies: BodiesSpec {
                clumps: self.clumps,
                ..BodiesSpec::default()
            },
            walls: self.walls,
            damping: DampingSpec {
                local: self.local_damping,
                viscous: 0.0,
                ..Default::default()
            },
            run: RunSpec {
                duration: Some(self.duration),
                dt_factor: Some(self.dt_factor.get()),
                ..RunSpec::default()
            },
            outputs: OutputSpec {
                history_every: self.history_every,
                ..OutputSpec::default()
            },
            ..SceneFile::new(self.name)
        }
    }
}

/// A crushing run's history per row: time, the `top` and `bottom` platens' y forces (N),
/// kinetic (translation + rotation) and strain (bonds + contacts) energy (J), and the lattice
/// links broken (tension + shear).
pub struct Rows {
    pub time: Vec<f64>,
    pub top: Vec<f64>,
    pub bottom: Vec<f64>,
    pub kinetic: Vec<f64>,
    pub strain: Vec<f64>,
    pub broken: Vec<f64>,
}

impl Rows {
    /// The rows of history `t`; errors name `test`.
    pub fn of(t: &Record, test: &str) -> Result<Rows, LabError> {
        let e = &t.energy;
        let links = harness::group_series(t, "lattice", test)?;
        let (bt, bs) = (
            harness::counts(&links.tension),
            harness::counts(&links.shear),
        );
        Ok(Rows {
            time: t.time.clone(),
            top: harness::wall_series(t, "top", test)?.fy.clone(),
            bottom: harness::wall_series(t, "bottom", test)?.fy.clone(),
            kinetic: harness::sum2(&e.kinetic_translation, &e.kinetic_rotation),
            strain: harness::sum2(&e.strain_bond, &e.strain_contact),
            broken: harness::sum2(&bt, &bs),
        })
    }
}

/// The energy at the end of a run (J): boundary work, strain (bonds + contacts), kinetic,
/// damping, friction, released at breaks; the balance error relative to the work.
pub struct EndEnergy {
    pub balance_error: f64,
    pub damping: f64,
    pub friction: f64,
    pub kinetic_energy: f64,
    pub released: f64,
    pub strain_energy: f64,
    pub work: f64,
}

impl EndEnergy {
    /// From the last row of `history`'s energies and the kinetic energy of `world` (the run's
    /// final state).
    pub fn of(history: &Record, world: &dem_core::World) -> EndEnergy {
        let en = &history.energy;
        let last = |v: &[f64]| *v.last().unwrap_or(&f64::NAN);
        EndEnergy {
            balance_error: last(&en.balance_error),
            damping: last(&en.damping),
            friction: last(&en.friction),
            kinetic_energy: world.energy().kinetic(),
            released: last(&en.bond_break),
            strain_energy: last(&en.strain_bond) + last(&en.strain_contact),
            work: last(&en.boundary_work),
        }
    }

    /// The figures a result must have finite, by name.
    pub fn figures(&self) -> [(&'static str, f64); 6] {
        [
            ("work", self.work),
            ("strain_energy", self.strain_energy),
            ("damping", self.damping),
            ("friction", self.friction),
            ("released", self.released),
            ("balance_error", self.balance_error),
        ]
    }
}

/// Never write a NaN: an analysis error of `test` naming the first of `figures` that is not
/// finite.
pub fn all_finite(test: &str, figures: &[(&str, f64)]) -> Result<(), LabError> {
    match figures.iter().find(|(_, v)| !v.is_finite()) {
        Some((name, v)) => Err(harness::analysis_error(
            test,
            format!("{name} is not finite ({v}); the result is not written"),
        )),
        None => Ok(()),
    }
}

/// Links broken in `world` so far.
pub fn broken_links(world: &dem_core::World) -> usize {
    world.bonds.as_ref().map_or(0, |b| b.len() - b.n_intact())
}

/// Particle-steps per second: `nodes` × `steps` / `wall` (s; 0 without a wall time).
pub fn particle_steps_per_s(nodes: usize, steps: u64, wall: f64) -> f64 {
    if wall > 0.0 {
        nodes as f64 * steps as f64 / wall
    } else {
        0.0
    }
}

/// A run's stop condition, asked every few steps: stop now?
pub type Stop = Box<dyn Fn(&dem_core::World) -> bool>;

/// Runs `scene` written to `file`, checked every `every` steps by `stop`, until `stop`
/// says so: a run that ends otherwise (at its duration) is an analysis error of `test` saying
/// `why_not`.
pub fn run_until(
    test: &str,
    scene: &SceneFile,
    file: &Path,
    (every, stop): (u64, Stop),
    progress: &mut dyn FnMut(u64, u64),
    why_not: impl FnOnce() -> String,
) -> Result<LabRun, LabError> {
    let hook = StepHook {
        every,
        run: Box::new(|_| Ok(())),
        stop: Some(stop),
    };
    let r = run_scene(scene, file, &RunOptions::default(), progress, Some(hook))?;
    if r.summary.status != "failure" {
        return Err(harness::analysis_error(test, why_not()));
    }
    Ok(r)
}
