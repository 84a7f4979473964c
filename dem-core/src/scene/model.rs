//! A scene after loading: every value in SI, every name resolved to an index, every template
//! loaded, every check passed. `super::build` turns it into a `World`.

use super::schema::{Between, ClumpMode, LawName};
use crate::bond::BondGroup;
use crate::state::Periodic;
use clumpgen::Template;
use serde::Serialize;
use std::path::PathBuf;

/// A loaded, checked scene (SI units).
#[derive(Debug, Clone, Serialize)]
pub struct Scene {
    /// The scene file as given and its folder (templates and outputs are relative to it).
    #[serde(skip)]
    pub file: PathBuf,
    pub name: String,
    pub thickness: f64,
    pub seed: u64,
    pub materials: Vec<Material>,
    /// One entry per unordered pair of materials that can touch (disc-disc, disc-wall),
    /// sorted by (a, b) with a ≤ b.
    pub pairs: Vec<PairLaw>,
    pub bond_groups: Vec<BondGroup>,
    /// Loaded templates, each file once; clumps refer to them by index.
    pub templates: Vec<Template>,
    pub discs: Vec<DiscInit>,
    pub clumps: Vec<ClumpInit>,
    /// Rigid clumps (ORC sums of the members) of specimen-file discs: indices into `discs`.
    pub rigid_clumps: Vec<Vec<usize>>,
    /// Explicit bonds of specimen files.
    pub bonds: Vec<ExplicitBond>,
    pub auto_bonds: Vec<AutoBond>,
    pub walls: Vec<WallInit>,
    pub loads: Vec<crate::pipeline::ExternalLoad>,
    pub periodic: Periodic,
    pub gravity: Option<[f64; 2]>,
    pub damping: Damping,
    /// Run control: the time-step and guard settings enter the physics hash, the stop and
    /// step cap do not (a restart may extend a run).
    pub run: Run,
    #[serde(skip)]
    pub outputs: Outputs,
}

#[derive(Debug, Clone, Serialize)]
pub struct Material {
    pub name: String,
    pub density: Option<f64>,
    pub kn: Option<f64>,
    pub ks: Option<f64>,
    pub youngs_modulus: Option<f64>,
    pub poisson: Option<f64>,
    pub friction: f64,
    pub restitution: Option<f64>,
    pub damping_ratio: Option<f64>,
    pub rolling_friction: f64,
}

/// Normal damping of a pair, as the user gave it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum NormalDamping {
    /// Coefficient of restitution e in (0, 1].
    Restitution(f64),
    /// Fraction of critical damping in [0, 1).
    Ratio(f64),
}

/// Stiffness parameters of a pair's law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum PairStiffness {
    /// Linear spring-dashpot: kn, ks (N/m).
    Linear { kn: f64, ks: f64 },
    /// Hertz-Mindlin: effective modulus E* and effective shear modulus G* (rules in
    /// `super::mix`).
    Hertz { e_star: f64, g_star: f64 },
    /// A catalogue law (`"law": "granular"`), checked for 2D discs.
    Granular(dem_laws::GranularLaw),
}

/// The contact law of one material pair with its mixed parameters.
#[derive(Debug, Clone, Serialize)]
pub struct PairLaw {
    pub a: u16,
    pub b: u16,
    pub law: LawName,
    pub stiffness: PairStiffness,
    pub friction: f64,
    pub damping: NormalDamping,
    /// Rolling-resistance coefficient, `Some` only when rolling resistance is switched on.
    pub rolling: Option<f64>,
}

/// A free disc (also the members of bonded clumps).
#[derive(Debug, Clone, Serialize)]
pub struct DiscInit {
    pub x: f64,
    pub y: f64,
    pub r: f64,
    pub vx: f64,
    pub vy: f64,
    pub omega: f64,
    pub material: u16,
    pub group: u32,
    pub fixed: bool,
    /// Mass and inertia when not those of a uniform disc of the material (bonded-clump
    /// members carry the template's masses).
    pub mass: Option<(f64, f64)>,
}

/// One placed clump.
#[derive(Debug, Clone, Serialize)]
pub struct ClumpInit {
    pub template: usize,
    pub material: u16,
    pub mode: ClumpMode,
    pub bond_group: Option<usize>,
    pub bond_tolerance: f64,
    /// Material density over the template's density (masses are scaled by it, and by the
    /// scene thickness over the template's).
    pub density_ratio: f64,
    pub x: f64,
    pub y: f64,
    pub angle: f64,
    pub vx: f64,
    pub vy: f64,
    pub omega: f64,
    /// Each clump gets its own group (grain id).
    pub group: u32,
}

/// A bond listed in a specimen file: discs `a`, `b` (indices into [`Scene::discs`]), bond
/// group index, and the pair's contact reference gap (m, ≤ 0; 0 = none).
#[derive(Debug, Clone, Serialize)]
pub struct ExplicitBond {
    pub a: usize,
    pub b: usize,
    pub group: usize,
    pub contact_offset: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct AutoBond {
    pub bond_group: usize,
    pub tolerance: f64,
    pub between: Between,
    /// Materials allowed (all when empty).
    pub materials: Vec<u16>,
}

#[derive(Debug, Clone, Serialize)]
pub struct WallInit {
    pub name: String,
    pub a: [f64; 2],
    pub b: [f64; 2],
    /// Inner vertices of a polyline wall (empty: a segment).
    pub via: Vec<[f64; 2]>,
    pub material: u16,
    pub velocity: [f64; 2],
    pub angular_velocity: f64,
    pub center: [f64; 2],
    pub servo: Option<crate::wall_servo::WallServo>,
}

#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Damping {
    pub local: f64,
    pub viscous: f64,
    /// The frame local damping acts in ([`crate::damping`]).
    pub frame: crate::damping::DampingFrame,
}

/// Run control.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Run {
    /// Stop when time ≥ duration (s), or after `steps`.
    #[serde(skip)]
    pub stop: Stop,
    pub dt_factor: Option<f64>,
    pub dt: Option<f64>,
    #[serde(skip)]
    pub max_steps: Option<u64>,
    /// Verlet skin (m).
    pub skin: Option<f64>,
    pub max_overlap_fraction: Option<f64>,
    pub max_energy_growth: Option<f64>,
    /// Budget of the selective mass scaling before the run (fraction; `None` = none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass_scaling: Option<f64>,
    /// Stop at failure (run control, not physics: a restart may change it).
    #[serde(skip)]
    pub stop_after_peak: Option<StopAfterPeak>,
}

/// `run.stop_after_peak`, resolved: wall indices, axis (0 = x, 1 = y), fraction, arming load (N).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StopAfterPeak {
    pub walls: Vec<usize>,
    pub axis: usize,
    pub below: f64,
    pub min_load: f64,
}

/// A position gauge: name and region [x0, y0, x1, y1] (m).
#[derive(Debug, Clone, PartialEq)]
pub struct Gauge {
    pub name: String,
    pub region: [f64; 4],
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stop {
    Duration(f64),
    Steps(u64),
}

impl Default for Stop {
    fn default() -> Self {
        Stop::Steps(0)
    }
}

/// Output control; the folder is absolute (resolved against the scene file). Run control, not
/// physics: none of it enters [`Scene::physics_hash`], so a restart may change any of it.
#[derive(Debug, Clone)]
pub struct Outputs {
    pub dir: PathBuf,
    pub history_every: u64,
    pub vtk_every: u64,
    /// Snapshots spread evenly over the run (`outputs.vtk_count`; 0: `vtk_every` applies).
    pub vtk_count: u64,
    /// Encoding of the VTK snapshots.
    pub vtk_format: crate::output::vtk::Format,
    pub checkpoint_every: u64,
    /// Numbered checkpoints kept (newest; 0 = all).
    pub checkpoint_keep: u32,
    /// Whether the run writes checkpoints at all; `false`: neither the periodic ones nor
    /// `ckpt-final.*`, and the run cannot be resumed.
    pub checkpoints: bool,
    /// File format of the checkpoints (`ckpt-<step>.json` or `.bin`).
    pub checkpoint_format: crate::checkpoint::Format,
    pub guard_every: u64,
    pub summary: bool,
    pub gauges: Vec<Gauge>,
}

impl Outputs {
    /// When snapshots are written, as the disk-estimate messages say it: "a snapshot every 10
    /// steps (outputs.vtk_every)", "3 snapshots over the run (outputs.vtk_count)" or "no
    /// snapshots".
    pub fn snapshot_plan(&self) -> String {
        match (self.vtk_every, self.vtk_count) {
            (0, 0) => "no snapshots".into(),
            (0, n) => format!("{n} snapshots over the run (outputs.vtk_count)"),
            (k, _) => format!("a snapshot every {k} steps (outputs.vtk_every)"),
        }
    }
}

impl Default for Outputs {
    fn default() -> Outputs {
        Outputs {
            dir: PathBuf::new(),
            history_every: 0,
            vtk_every: 0,
            vtk_count: 0,
            vtk_format: crate::output::vtk::Format::Ascii,
            checkpoint_every: 0,
            checkpoint_keep: 0,
            checkpoints: true,
            checkpoint_format: crate::checkpoint::Format::Json,
            guard_every: 0,
            summary: false,
            gauges: Vec::new(),
        }
    }
}

impl Scene {
    /// The law of material pair (a, b).
    pub fn pair(&self, a: u16, b: u16) -> Option<&PairLaw> {
        let key = (a.min(b), a.max(b));
        self.pairs
            .binary_search_by(|p| (p.a, p.b).cmp(&key))
            .ok()
            .map(|i| &self.pairs[i])
    }

    /// SHA-256 (hex) of everything that determines the physics (not run control or outputs):
    /// a checkpoint records it and a restart refuses a scene that differs.
    pub fn physics_hash(&self) -> String {
        use sha2::{Digest, Sha256};
        let text = serde_json::to_string(self).unwrap_or_default();
        let d = Sha256::digest(text.as_bytes());
        d.iter().map(|b| format!("{b:02x}")).collect()
    }

    /// Number of discs the built world will have.
    pub fn disc_count(&self) -> usize {
        self.discs.len()
            + self
                .clumps
                .iter()
                .map(|c| self.templates[c.template].discs.len())
                .sum::<usize>()
    }
}
