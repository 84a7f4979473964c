//! The scene file as written: `dem.scene/1` JSON, field by field as in `docs/scene-schema.md`.
//!
//! Every struct rejects unknown fields. Lengths (and velocities, accelerations) are in the file's
//! `units`; [`mod@super::resolve`] converts them to SI once and checks the values. Enums are plain
//! strings and bodies are arrays of plain objects (no tagged or untagged unions), so a parse error
//! always carries the exact JSON path of the offending value.

use serde::{Deserialize, Serialize};

/// Schema identifier every scene file carries.
pub const SCHEMA: &str = "dem.scene/1";
/// Schema identifier of a specimen file (bodies only, see [`SpecimenFile`]).
pub const SPECIMEN_SCHEMA: &str = "dem.specimen/1";

/// Length unit of a scene or specimen file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum LengthUnit {
    #[default]
    #[serde(rename = "m")]
    M,
    #[serde(rename = "mm")]
    Mm,
}

impl LengthUnit {
    /// Metres per unit.
    pub fn metres(self) -> f64 {
        match self {
            LengthUnit::M => 1.0,
            LengthUnit::Mm => 1e-3,
        }
    }
}

/// The whole scene file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Always `"dem.scene/1"`.
    #[cfg_attr(feature = "schema", schemars(extend("const" = "dem.scene/1")))]
    pub schema: String,
    #[serde(default)]
    pub name: String,
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub units: LengthUnit,
    /// Disc thickness t (length unit); default 1 m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
    #[serde(default)]
    pub seed: u64,
    pub materials: Vec<MaterialSpec>,
    #[serde(default)]
    pub contact: ContactSpec,
    #[serde(default)]
    pub bond_groups: Vec<BondGroupSpec>,
    #[serde(default)]
    pub bodies: BodiesSpec,
    #[serde(default)]
    pub auto_bonds: Vec<AutoBondSpec>,
    #[serde(default)]
    pub walls: Vec<WallSpec>,
    /// Constant external forces and torques on single discs.
    #[serde(default)]
    pub loads: Vec<LoadSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub periodic: Option<PeriodicSpec>,
    /// Gravitational acceleration (length unit / s²); absent = no gravity stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<[f64; 2]>,
    #[serde(default)]
    pub damping: DampingSpec,
    pub run: RunSpec,
    #[serde(default)]
    pub outputs: OutputSpec,
}

impl SceneFile {
    /// An empty scene `name` (`dem.scene/1`, units m, no materials, bodies or walls, the
    /// engine's run and output defaults), for programs that build scenes as values.
    pub fn new(name: &str) -> SceneFile {
        SceneFile {
            schema: SCHEMA.into(),
            name: name.into(),
            description: String::new(),
            units: LengthUnit::M,
            thickness: None,
            seed: 0,
            materials: Vec::new(),
            contact: ContactSpec::default(),
            bond_groups: Vec::new(),
            bodies: BodiesSpec::default(),
            auto_bonds: Vec::new(),
            walls: Vec::new(),
            loads: Vec::new(),
            periodic: None,
            gravity: None,
            damping: DampingSpec::default(),
            run: RunSpec::default(),
            outputs: OutputSpec::default(),
        }
    }
}

/// A material: density for discs, contact properties for the laws that use them.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub name: String,
    /// kg/m³; required for materials that discs use.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Linear law: normal and tangential contact stiffness (N/m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kn: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ks: Option<f64>,
    /// Hertz-Mindlin: Young's modulus (Pa) and Poisson's ratio.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub youngs_modulus: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson: Option<f64>,
    /// Coulomb friction coefficient μ.
    #[serde(default)]
    pub friction: f64,
    /// Normal coefficient of restitution e in (0, 1]; or give `damping_ratio`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// Normal dashpot as a fraction of critical damping, in [0, 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_ratio: Option<f64>,
    /// Rolling-resistance coefficient μ_r (used by pairs with `"rolling": true`).
    #[serde(default)]
    pub rolling_friction: f64,
}

/// Contact law choice: a default for every material pair plus per-pair overrides.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    #[serde(default)]
    pub law: LawName,
    #[serde(default)]
    pub rolling: bool,
    /// With `"law": "granular"`: the law by its sub-models (normal, damping, tangential;
    /// `docs/laws.md`), used by every pair without its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub granular: Option<dem_laws::GranularSpec>,
    #[serde(default)]
    pub pairs: Vec<PairSpec>,
}

impl Default for ContactSpec {
    fn default() -> Self {
        ContactSpec {
            law: LawName::LinearSpringDashpot,
            rolling: false,
            granular: None,
            pairs: Vec::new(),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum LawName {
    #[default]
    LinearSpringDashpot,
    HertzMindlin,
    /// A law composed of named sub-models (LAMMPS `pair_style granular`-like), given in
    /// `granular` (`docs/laws.md`); its parameters are its own, not mixed from the materials.
    Granular,
}

/// The law of one material pair (order of the two names does not matter).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct PairSpec {
    pub materials: [String; 2],
    pub law: LawName,
    #[serde(default)]
    pub rolling: bool,
    /// With `"law": "granular"`: this pair's law by its sub-models (else `contact.granular`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub granular: Option<dem_laws::GranularSpec>,
    /// Overrides of the mixed values, same meaning and units as in a material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kn: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ks: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_ratio: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_friction: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum BondModelName {
    ParallelPotyondy2004,
    ContactBond,
    /// The flat joint of Potyondy 2012: an interface of `elements` elements that break one by
    /// one (strengths from criterion `stress`), unbonded ones with `friction`.
    FlatJointPotyondy2012,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum CriterionName {
    Stress,
    Force,
    Strain,
    Energy,
}

/// A bond group: model, breakage criterion and the parameters they use. Which parameters are
/// required (and which are refused as unused) depends on the model and criterion; see the docs.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct BondGroupSpec {
    pub name: String,
    pub model: BondModelName,
    pub criterion: CriterionName,
    /// Parallel bond: normal and shear stiffness per area (Pa/m); contact bond: N/m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kn: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ks: Option<f64>,
    /// Parallel bond radius multiplier λ̄ (R̄ = λ̄·min(R1, R2)); default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_multiplier: Option<f64>,
    /// Moment contribution factor β̄ in σ̄ = −F̄n/Ā + β̄|M̄|R̄/Ī; default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moment_factor: Option<f64>,
    /// Flat joint: number of elements along the interface, 1–8; default 2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elements: Option<u32>,
    /// Flat joint: friction coefficient μ of unbonded elements; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// Flat joint: fraction of the elements bonded at installation (the others are slit:
    /// unbonded from the start), in [0, 1]; default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bonded_fraction: Option<f64>,
    /// Stress criterion: tensile strength σ̄c (Pa), cohesion c̄ (Pa), friction angle φ̄ (degrees).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tensile_strength: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cohesion: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_angle: Option<f64>,
    /// Force criterion: normal (tensile) and shear strength (N), and optionally the bending
    /// moment (N·m) at which a parallel bond breaks in tension.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_strength: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_strength: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moment_strength: Option<f64>,
    /// Strain criterion: limits of normal (opening) and shear strain (dimensionless).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_strain: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_strain: Option<f64>,
    /// Energy criterion: fracture energy per unit bond area G_c (J/m²); the bond breaks when its
    /// opening plus shear strain energy reaches G_c·Ā.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture_energy: Option<f64>,
}

impl BondGroupSpec {
    /// A group `name` of `model` with `criterion` and every optional field absent (the
    /// loader's defaults); set the stiffnesses and strengths the model needs.
    pub fn new(name: &str, model: BondModelName, criterion: CriterionName) -> BondGroupSpec {
        BondGroupSpec {
            name: name.into(),
            model,
            criterion,
            kn: None,
            ks: None,
            radius_multiplier: None,
            moment_factor: None,
            elements: None,
            friction: None,
            bonded_fraction: None,
            tensile_strength: None,
            cohesion: None,
            friction_angle: None,
            normal_strength: None,
            shear_strength: None,
            moment_strength: None,
            normal_strain: None,
            shear_strain: None,
            fracture_energy: None,
        }
    }
}

/// All bodies of the scene. Discs are created in this order: disc sets, clump sets, specimens.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct BodiesSpec {
    #[serde(default)]
    pub discs: Vec<DiscSetSpec>,
    #[serde(default)]
    pub clumps: Vec<ClumpSetSpec>,
    #[serde(default)]
    pub specimens: Vec<SpecimenRef>,
}

/// A set of free discs sharing material, group and initial motion.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct DiscSetSpec {
    pub material: String,
    #[serde(default)]
    pub group: u32,
    /// Initial velocity (length unit / s) and angular velocity (rad/s) of every disc.
    #[serde(default)]
    pub velocity: [f64; 2],
    #[serde(default)]
    pub omega: f64,
    /// Adds a velocity of this magnitude (length unit / s) in a random direction per disc,
    /// drawn from the scene seed.
    #[serde(default)]
    pub random_speed: f64,
    /// Fixed discs are not integrated; they keep their initial velocity.
    #[serde(default)]
    pub fixed: bool,
    /// `[x, y, r]` per disc (length unit).
    pub discs: Vec<[f64; 3]>,
    /// Per-disc group (e.g. grain id), replacing `group`; one per disc when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub groups: Option<Vec<u32>>,
    /// Per-disc mass as a multiple of the uniform disc's ρ·t·π·r² (improved-ORC grain members
    /// carry their template's solved masses); the inertia is then m·r²/2. One per disc when
    /// given; dimensionless, so independent of the scene's density and thickness.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_factors: Option<Vec<f64>>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum ClumpMode {
    /// ORC: one rigid body with the template's mass, centroid and inertia.
    Rigid,
    /// Improved ORC: free discs with the template's masses joined by intra-clump bonds.
    Bonded,
}

/// Copies of one clump template.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ClumpSetSpec {
    /// Template file (`clumpgen.template/1`), relative to the file that names it.
    pub template: String,
    pub material: String,
    pub mode: ClumpMode,
    /// Bond group of the intra-clump bonds (bonded mode only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bond_group: Option<String>,
    /// Members of a bonded clump are bonded when their gap is at most this (length unit);
    /// overlapping members always are. Default 0.
    #[serde(default)]
    pub bond_tolerance: f64,
    pub placements: Vec<PlacementSpec>,
}

/// One copy of a template: centroid position, rotation and initial motion.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct PlacementSpec {
    pub x: f64,
    pub y: f64,
    /// Rotation of the template frame (rad, counter-clockwise).
    #[serde(default)]
    pub angle: f64,
    #[serde(default)]
    pub velocity: [f64; 2],
    #[serde(default)]
    pub omega: f64,
}

/// A specimen file (`dem.specimen/1`) to include, shifted by `offset`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SpecimenRef {
    /// Relative to the scene file.
    pub file: String,
    /// Shift (scene length unit).
    #[serde(default)]
    pub offset: [f64; 2],
    /// Initial velocity added to every body of the specimen (scene length unit / s): the
    /// specimen moving as a whole, e.g. a cut run in the tool's frame of reference.
    #[serde(default, skip_serializing_if = "is_zero2")]
    pub velocity: [f64; 2],
}

fn is_zero2(v: &[f64; 2]) -> bool {
    *v == [0.0, 0.0]
}

/// A specimen file: bodies in their own length unit; materials and bond groups refer to the
/// scene's by name, templates are relative to the specimen file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SpecimenFile {
    /// Always `"dem.specimen/1"`.
    #[cfg_attr(feature = "schema", schemars(extend("const" = "dem.specimen/1")))]
    pub schema: String,
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub units: LengthUnit,
    #[serde(default)]
    pub discs: Vec<DiscSetSpec>,
    #[serde(default)]
    pub clumps: Vec<ClumpSetSpec>,
    /// Rigid clumps (ORC) made of the specimen's own discs: member indices in the order the
    /// `discs` sets list them. Mass, centroid and inertia are the ORC sums of the members
    /// (`specimen::orc`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rigid_clumps: Vec<Vec<u32>>,
    /// Explicit bonds between the specimen's own discs (indices as in `rigid_clumps`),
    /// installed force-free at the loaded positions.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bonds: Vec<BondListSpec>,
}

/// Bonds of one group between listed disc pairs of a specimen file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct BondListSpec {
    /// A bond group of the scene.
    pub bond_group: String,
    /// Disc index pairs.
    pub pairs: Vec<[u32; 2]>,
    /// Contact reference gap of each pair (length unit): a negative value is an overlap the
    /// contact law ignores (bonded-clump members overlap by design, see
    /// `World::set_contact_offset`); 0 = none. One per pair when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_offsets: Option<Vec<f64>>,
}

/// Which disc pairs automatic bonding may join.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Between {
    /// Any two discs (not members of the same rigid clump).
    #[default]
    All,
    /// Only discs of different groups (e.g. grain-boundary bonds between grains).
    DifferentGroups,
    /// Only discs of the same group.
    SameGroup,
}

/// Install bonds of `bond_group` between every pair of discs whose gap is at most `tolerance`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct AutoBondSpec {
    pub bond_group: String,
    /// Largest gap bonded (length unit); ≥ 0.
    #[serde(default)]
    pub tolerance: f64,
    #[serde(default)]
    pub between: Between,
    /// Only discs of these materials (all when empty).
    #[serde(default)]
    pub materials: Vec<String>,
}

/// A wall with prescribed motion: a straight segment from `a` to `b`, or a polyline
/// a → `via` → b moving as one rigid body (a disc gets one contact with it, at its nearest
/// point).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    pub name: String,
    pub a: [f64; 2],
    pub b: [f64; 2],
    /// Inner vertices of a polyline wall, in order from `a` to `b`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub via: Vec<[f64; 2]>,
    pub material: String,
    /// Translation velocity (length unit / s).
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Angular velocity (rad/s, counter-clockwise) about `center`.
    #[serde(default)]
    pub angular_velocity: f64,
    /// Centre of rotation and of the recorded moment; default the segment's midpoint.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f64; 2]>,
    /// Stress control instead of a prescribed velocity (`velocity` and `angular_velocity`
    /// must then be zero).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub servo: Option<ServoSpec>,
}

/// A wall's servo (PFC's biaxial-test servo, `dem_core::wall_servo`): each step the wall
/// moves along `direction` at G (σ_req − σ), G = α L t / (K Δt), σ = F/(L t) its measured
/// normal stress, K its contacts' normal stiffness.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ServoSpec {
    /// Target normal stress σ_req (Pa, compression positive; ≥ 0).
    pub stress: f64,
    /// Loaded length L the stress is measured over (length unit).
    pub length: f64,
    /// Direction of the wall's approach to the specimen (normalised on reading).
    pub direction: [f64; 2],
    /// Relaxation factor α in (0, 1] (default 0.5, as PFC).
    #[serde(default = "half")]
    pub alpha: f64,
    /// Speed limit (length unit / s).
    pub max_speed: f64,
}

fn half() -> f64 {
    0.5
}

/// A constant external force (N) and torque (N·m) on the disc with creation index `disc` (on
/// a rigid-clump member it acts on the whole clump).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    pub disc: u32,
    #[serde(default)]
    pub force: [f64; 2],
    #[serde(default)]
    pub torque: f64,
}

/// Periodic axes: `[lo, hi]` per periodic axis.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct PeriodicSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<[f64; 2]>,
}

/// Damping: PFC local damping α (in the lab frame or each body's bonded fragment) and global
/// viscous damping ζ.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// Local damping α in [0, 1): F_d = −α|F| sign(v) per component.
    #[serde(default)]
    pub local: f64,
    /// Global viscous damping as a fraction ζ of each body's critical damping, in [0, 1):
    /// F_v = −2ζ√(m K) v, T_v = −2ζ√(I K_rot) ω.
    #[serde(default)]
    pub viscous: f64,
    /// The frame local damping acts in: `"lab"` (default; PFC: F_d = −α|F| sign(v), which
    /// drags bodies in steady motion) or `"fragment"` (the motion relative to the body's bonded
    /// fragment, with the net force and moment removed per fragment: no drag on any rigid
    /// motion, the same forces in every frame of reference; `dem_core::damping`).
    #[serde(default, skip_serializing_if = "crate::damping::DampingFrame::is_lab")]
    pub frame: crate::damping::DampingFrame,
}

/// How long to run and with which time step.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Simulated time (s); or give `steps`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<u64>,
    /// Safety factor f of the automatic time step; default the engine's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt_factor: Option<f64>,
    /// Fixed time step (s) instead of the automatic one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Cap on the world's step count: the run stops there (and can be continued by a restart).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<u64>,
    /// Verlet skin (length unit); default 0.2 × the smallest radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skin: Option<f64>,
    /// Guard: largest overlap allowed, as a fraction of the smaller radius (default 0.3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_overlap_fraction: Option<f64>,
    /// Guard: kinetic energy may not exceed this multiple of the energy supplied (default 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_energy_growth: Option<f64>,
    /// Selective mass scaling before the run (`dem_core::mass_scaling`): the lightest discs
    /// are made heavier until their time-step bound reaches the largest step whose added mass
    /// and added spin inertia stay within this fraction of the free discs' totals (e.g. 0.02).
    /// Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_scaling: Option<f64>,
    /// Stop at failure: end the run once the load on some walls has fallen below a fraction
    /// of its peak (checked at history rows).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_after_peak: Option<StopAfterPeakSpec>,
}

/// `run.stop_after_peak`: the load is |Σ force component `axis` of `walls`|; the run ends
/// (status `failure`) at the first history row where the load is below `below` × its peak so
/// far, once that peak has reached `min_load` (N).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct StopAfterPeakSpec {
    pub walls: Vec<String>,
    pub axis: AxisName,
    pub below: f64,
    #[serde(default)]
    pub min_load: f64,
}

/// A coordinate axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum AxisName {
    X,
    Y,
}

/// `outputs.gauges[]`: the discs whose centre lies in `region` ([x0, y0, x1, y1], length
/// unit) when the scene is built; the history gets their mean position `<name>_x,<name>_y`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct GaugeSpec {
    pub name: String,
    pub region: [f64; 4],
}

/// What to write and how often (every N steps; 0 = never).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Output folder, relative to the scene file; default `<scene stem>.out`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dir: Option<String>,
    #[serde(default = "default_history")]
    pub history_every: u64,
    #[serde(default)]
    pub vtk_every: u64,
    /// This many snapshots spread evenly over the run instead of `vtk_every`: at the fractions
    /// k/(N − 1) of its duration (or step count), k = 0 … N − 1, the first at the start and the
    /// last at the end (1: the start only). 0 (default): `vtk_every` applies.
    #[serde(default, skip_serializing_if = "is_zero_u64")]
    pub vtk_count: u64,
    /// Snapshot encoding: `"ascii"` (default) or `"binary"` (VTK's appended base64 layout,
    /// exact values, a fixed size per value; see `dem_core::output::vtk`).
    #[serde(default, skip_serializing_if = "crate::output::vtk::Format::is_ascii")]
    pub vtk_format: crate::output::vtk::Format,
    #[serde(default)]
    pub checkpoint_every: u64,
    /// Keep only the newest N numbered checkpoints (`ckpt-<step>.json`), deleting older ones
    /// as new ones are written; 0 = keep all.
    #[serde(default, skip_serializing_if = "is_zero_u32")]
    pub checkpoint_keep: u32,
    /// Write checkpoints at all (default `true`); `false`: neither the periodic ones nor
    /// `ckpt-final.*`, so the run cannot be resumed (for runs too large or too short to need
    /// them). Wins over `checkpoint_every`.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub checkpoints: bool,
    /// Checkpoint file format: `"json"` (default; `ckpt-<step>.json`) or `"binary"`
    /// (`ckpt-<step>.bin`, about half the size, documented in `dem_core::checkpoint`).
    #[serde(default, skip_serializing_if = "crate::checkpoint::Format::is_json")]
    pub checkpoint_format: crate::checkpoint::Format,
    /// Blow-up guard interval (the guard also runs at every output).
    #[serde(default = "default_guard")]
    pub guard_every: u64,
    #[serde(default = "yes")]
    pub summary: bool,
    /// Position gauges (mean position of the discs in a region).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub gauges: Vec<GaugeSpec>,
}

fn is_zero_u32(v: &u32) -> bool {
    *v == 0
}

fn is_zero_u64(v: &u64) -> bool {
    *v == 0
}

fn is_true(v: &bool) -> bool {
    *v
}

fn default_history() -> u64 {
    100
}

fn default_guard() -> u64 {
    100
}

fn yes() -> bool {
    true
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            dir: None,
            history_every: default_history(),
            vtk_every: 0,
            vtk_count: 0,
            vtk_format: crate::output::vtk::Format::Ascii,
            checkpoint_every: 0,
            checkpoint_keep: 0,
            checkpoints: true,
            checkpoint_format: crate::checkpoint::Format::Json,
            guard_every: default_guard(),
            summary: true,
            gauges: Vec::new(),
        }
    }
}
