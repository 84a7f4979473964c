//! The orthogonal cutting test (S0 Ye & Xu 2010; S4 Tan et al.): a bonded specimen in a slot of
//! three fixed frictionless walls, cut by a rigid tool (one polyline wall: clearance face,
//! edge, rake face; one contact per disc, PFC's series contact stiffness) much stiffer than
//! the discs, moving horizontally at speed v with its edge a depth a_p below
//! the specimen top, over a cut length L. `docs/cutting.md` describes the set-up, the outputs
//! and the measured figures.
//!
//! ```text
//! scene    CuttingTest + LabModel + specimen file → plain dem.scene/1 JSON (dem run runs it)
//! run      scene → run_built → analyze; writes cutting.result.json and cutting.forces.csv
//! analyze  history → main and vertical force against tool travel, peak/mean over the steady
//!          window; final world → chips (chips.rs), machined surface (surface.rs), residual
//!          cracks; broken bonds by group and mode
//! ```

pub mod chips;
pub mod debris;
pub mod removal;
pub mod surface;
pub mod tool;

use self::chips::{ChipReport, ResidualCracks};
use self::removal::{removal_mode, RemovalMode};
use self::surface::Surface;
use self::tool::{edge_arc, CutGeometry, Segment, ToolModel, CLEARANCE, RAKE, TOOL};
use super::model::series_wall_stiffness;
use super::model::{DISC_MATERIAL, WALL_MATERIAL};
use super::run::run_built;
use super::tests::harness::DtFactor;
use super::{analysis, LabError, LabModel};
use dem_core::output::driver::RunOptions;
use dem_core::output::history::Record;
use dem_core::output::write_atomic;
use dem_core::scene::schema::{OutputSpec, RunSpec, SceneFile, SpecimenFile, WallSpec};
use dem_core::{DampingFrame, State, World};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Name of the tool's material in the scene (its disc pair sets the tool stiffness).
pub const TOOL_MATERIAL: &str = "tool";
/// File names written in the output folder.
pub const SCENE_FILE: &str = "cutting.scene.json";
pub const RESULT_FILE: &str = "cutting.result.json";
pub const FORCES_FILE: &str = "cutting.forces.csv";
/// File name of [`Inputs`] in a cut's output folder.
pub const INPUTS_FILE: &str = "cutting.inputs.json";

/// The inputs of a cut, `<out>/cutting.inputs.json` ([`INPUTS_FILE`]): written before the
/// specimen is generated (and again once its model is known), so a sweep's case folder says
/// what it runs (validation matches cases to its own runs by it).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Inputs {
    /// The parameters of the generated specimen; `null` with `--specimen`.
    pub specimen: Option<crate::specimen::SpecimenParams>,
    /// The `--specimen` file, if given.
    pub specimen_file: Option<String>,
    /// The material model the cut runs with; `null` until a generated specimen's own is known
    /// (no `--model`).
    pub model: Option<LabModel>,
    /// The flat joints of `--flat-joint` (with `--joint-friction`, `--joint-bonded-fraction`), which
    /// the model gets whichever way it is found: recorded here too so a cut whose model is not
    /// known yet says (and its run lock's key holds) that it runs with flat joints. Absent
    /// without `--flat-joint`, so the inputs of parallel-bond cuts are as before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_joint: Option<crate::model::FlatJointOption>,
    pub test: CuttingTest,
}

/// A cutting test. SI units (m, m/s, rad); the `× a_p` fields are multiples of the depth of
/// cut. Defaults: [`CuttingTest::default`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(default, deny_unknown_fields)]
pub struct CuttingTest {
    /// Depth of cut a_p (m). Default 1 mm (S0).
    pub depth: f64,
    /// Cutting speed v (m/s). Default 1 m/s (S0).
    pub speed: f64,
    /// Cut length L (m): travel of the cutting edge past the specimen's left edge. Default
    /// 10 mm (S0).
    pub length: f64,
    /// Rake angle γ (rad) from the vertical, positive leaning back. Default 0: S0 does not
    /// state it; S4 varies it; 0° is the neutral choice.
    pub rake_angle: f64,
    /// Clearance angle α (rad) of the clearance face above the horizontal. Default 7° (a
    /// common value for ceramic cutting tools; not stated in S0).
    pub clearance_angle: f64,
    /// Rake face length (× a_p): long enough to hold the chip. Default 3.
    pub rake_face: f64,
    /// Clearance face length (× a_p). Default 1.
    pub clearance_face: f64,
    /// Gap between the tool's foremost point and the specimen at the start (× a_p). Default
    /// 0.1: long enough to show a zero force before contact, short because travel costs steps.
    pub approach: f64,
    /// Tool normal (and shear) stiffness as a multiple of the disc's ("much stiffer than the
    /// discs", S4). Default 10. With [`ToolModel::Rigid`] it is PFC's wall stiffness as a
    /// multiple of the ball stiffness, combined with the disc's in series (tool contact
    /// 2·f/(1+f) × the disc–disc k_n: 1.82× at 10, [`series_wall_stiffness`]); with
    /// [`ToolModel::Segments`] the tool contact is f × the disc–disc k_n directly. The
    /// automatic time step is bounded by the stiffest contact a disc can make, tool contacts
    /// included.
    pub tool_stiffness: f64,
    /// Tool-disc friction coefficient. Default 0 (frictionless walls, as PFC's default; S0 and
    /// S4 do not state it).
    pub tool_friction: f64,
    /// PFC local damping α (Cundall 1987). Default 0.7, PFC2D's default, which S0 and S4
    /// (PFC2D users who do not state a damping) most likely kept. Without damping the only
    /// dissipation is bond breakage: the tool's impacts fling discs ahead and the main force
    /// is a train of spikes (measured on the 20 × 10 mm Si3N4 specimen, 2.5 mm cut: mean/peak
    /// 0.02 undamped against 0.13 at 0.7, docs/cutting.md). Set 0 for an undamped run.
    pub local_damping: f64,
    /// The frame of reference of the local damping ([`dem_core::damping`]): `lab` (PFC: each
    /// disc's own velocity; drags debris and anything else in steady motion) or `fragment`
    /// (the motion relative to the disc's bonded fragment: no drag on rigid motion, the same
    /// forces in every frame of reference). Default `fragment`, chosen on issue 47's contracts
    /// and speed exponent (docs/cutting.md, "Damping and the frame of reference", decision log
    /// 2026-12-02). Left out of the serialised test (and so of the run keys) at `lab`, and a
    /// serialised test without it is `lab`, whatever the default: every run made before the
    /// switch keeps its key and meaning.
    #[serde(default, skip_serializing_if = "DampingFrame::is_lab")]
    pub damping_frame: DampingFrame,
    /// The frame of reference the cut is run in: `lab` (default: specimen and slot walls at
    /// rest, the tool moving at v) or `tool` (the tool at rest, the specimen and slot walls
    /// moving at −v): the Galilean contract of docs/cutting.md. The analyses (chips,
    /// surface, cracks) see the final state shifted back to the lab frame. Left out of the
    /// serialised test at `lab`.
    #[serde(default, skip_serializing_if = "CutFrame::is_lab")]
    pub frame: CutFrame,
    /// Safety factor of the automatic time step. Default 0.3 (the engine's 0.04 is chosen for
    /// energy conservation of an elastic gas over 1e5 steps; here stability and force
    /// statistics matter: see docs/cutting.md for the halving check). In (0, 1], the rule of
    /// every lab test.
    pub dt_factor: DtFactor,
    /// Target number of history rows over the run (one row every ⌈steps/rows⌉ steps, each
    /// with the tool forces). Default 4000: 2.5 µm of travel per row at L = 10 mm.
    pub history_rows: u64,
    /// Start of the steady window (× a_p of travel past entry); it ends at L. Default 2.
    pub window_start: f64,
    /// Surface profile bin width (× the mean disc diameter). Default 1.
    pub surface_bin: f64,
    /// VTK snapshots spread evenly over the run, the first at the start and the last at the
    /// end (0 = none).
    pub snapshots: u64,
    /// Blow-up guard: kinetic energy may not exceed this × the energy supplied (scene
    /// `run.max_energy_growth`). Default 2, the engine's. (A specimen is handed over
    /// stress-free, ~1e-24 J, and round-off in the undamped bonded assembly grows to ~1e-20 J
    /// before the tool touches it; the guard's rounding-energy floor, ~1e-17 J for the
    /// 20 × 10 mm specimen, keeps that from tripping it: measured, 40 000 undamped steps at
    /// dt factor 0.3 pass.)
    pub max_energy_growth: f64,
    /// Blow-up guard: deepest overlap allowed, as a fraction of the smaller radius (scene
    /// `run.max_overlap_fraction`). Default 0.5, above the engine's 0.3: with rigid ORC grains
    /// (which cannot break) a grain jammed between the rake face and the specimen reaches 0.3
    /// at a time step of 0.3 of the critical one (Table 2 run orc-d1-v1-s1, 2026-11-25), a
    /// physical limit of the unbreakable-grain model rather than a numerical blow-up, which
    /// passes any fixed limit within a few steps. PFC2D, the papers' code, has no such stop.
    /// The deepest overlap seen is reported ([`RunFigures::max_overlap_fraction`]). Left out
    /// of the serialised test (and so of the report's run keys) at its default: a run that
    /// stayed below 0.3 is the same bit for bit under either limit, the guard only reads.
    #[serde(
        default = "default_max_overlap",
        skip_serializing_if = "is_default_max_overlap"
    )]
    pub max_overlap_fraction: f64,
    /// How the tool is modelled: one rigid polyline body with PFC's series contact stiffness
    /// (default), or the earlier two segments with direct stiffness (`segments`). A test
    /// written without the field (results and run keys before 2026-11-26) is the earlier
    /// model, and `segments` is left out when serialised, so those keys stay as they were.
    #[serde(
        default = "ToolModel::legacy",
        skip_serializing_if = "ToolModel::is_legacy"
    )]
    pub tool: ToolModel,
    /// Cutting-edge radius r_e (× a_p) of the rigid tool; 0 (default) = a sharp edge. S0 does
    /// not state one.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub edge_radius: f64,
    /// Viscous contact damping of the disc–disc contacts: the critical damping ratio of the
    /// linear law's dashpots (PFC's `ball damping`; 0 = none, the default: PFC2D's default is
    /// local damping only). For the speed and damping study (docs/cutting.md).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub contact_damping: f64,
    /// Delete detached fragments once they are above the nominal surface and clear of the
    /// tool (rules in [`self::debris`], checked on every history row; docs/cutting.md,
    /// "Deleting fragments"). Default false. Left out of the serialised test (and so of the
    /// run keys) when false.
    #[serde(default, skip_serializing_if = "is_false")]
    pub delete_fragments: bool,
    /// Selective mass scaling before the cut (scene `run.mass_scaling`,
    /// [`dem_core::mass_scaling`]): the lightest discs are made heavier until none steps below the
    /// largest step whose added mass and added spin inertia stay within this fraction of the
    /// free discs' totals; 0 (default) = none. For the improved-ORC specimens, whose light
    /// template discs set a 3.5× smaller step (docs/cutting.md, "Mass scaling"). Left out of
    /// the serialised test (and so of the run keys) when 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub mass_scaling: f64,
}

/// The frame of reference a cut is run in ([`CuttingTest::frame`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum CutFrame {
    /// Specimen and slot at rest, tool moving at v.
    #[default]
    Lab,
    /// Tool at rest, specimen and slot moving at −v.
    Tool,
}

impl CutFrame {
    pub fn is_lab(&self) -> bool {
        *self == CutFrame::Lab
    }
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

fn is_false(v: &bool) -> bool {
    !*v
}

/// Default of [`CuttingTest::max_overlap_fraction`].
pub const DEFAULT_MAX_OVERLAP: f64 = 0.5;

fn default_max_overlap() -> f64 {
    DEFAULT_MAX_OVERLAP
}

fn is_default_max_overlap(v: &f64) -> bool {
    *v == DEFAULT_MAX_OVERLAP
}

impl Default for CuttingTest {
    fn default() -> CuttingTest {
        CuttingTest {
            depth: 1e-3,
            speed: 1.0,
            length: 10e-3,
            rake_angle: 0.0,
            clearance_angle: 7f64.to_radians(),
            rake_face: 3.0,
            clearance_face: 1.0,
            approach: 0.1,
            tool_stiffness: 10.0,
            tool_friction: 0.0,
            local_damping: 0.7,
            damping_frame: DampingFrame::Fragment,
            frame: CutFrame::Lab,
            dt_factor: DtFactor::default(),
            history_rows: 4000,
            window_start: 2.0,
            surface_bin: 1.0,
            snapshots: 0,
            max_energy_growth: 2.0,
            max_overlap_fraction: DEFAULT_MAX_OVERLAP,
            tool: ToolModel::Rigid,
            edge_radius: 0.0,
            contact_damping: 0.0,
            delete_fragments: false,
            mass_scaling: 0.0,
        }
    }
}

impl CuttingTest {
    /// The defaults with depth a_p (m), speed v (m/s) and cut length L (m).
    pub fn new(depth: f64, speed: f64, length: f64) -> CuttingTest {
        CuttingTest {
            depth,
            speed,
            length,
            ..Default::default()
        }
    }

    /// A test file a user wrote (`dem test cutting --params`): every field it leaves out is
    /// today's default ([`CuttingTest::default`]). Reading a stored test (a result, a run key)
    /// differs in two fields, whose absence there means the model of the runs made before they
    /// existed: `tool` (absent: `segments`) and `damping_frame` (absent: `lab`); here their
    /// absence means today's `rigid` and `fragment`. Unknown fields are an error naming them.
    pub fn from_params(text: &str) -> Result<CuttingTest, serde_json::Error> {
        /// Which of the two fields the file gives (any other field is read by `CuttingTest`).
        #[derive(Deserialize)]
        struct Given {
            tool: Option<serde::de::IgnoredAny>,
            damping_frame: Option<serde::de::IgnoredAny>,
        }
        let mut t: CuttingTest = serde_json::from_str(text)?;
        let given: Given = serde_json::from_str(text)?;
        let today = CuttingTest::default();
        if given.tool.is_none() {
            t.tool = today.tool;
        }
        if given.damping_frame.is_none() {
            t.damping_frame = today.damping_frame;
        }
        Ok(t)
    }

    /// [`CuttingTest::validate`]s the test and wraps it: the one way to a [`CheckedTest`].
    pub fn check(self) -> Result<CheckedTest, LabError> {
        self.validate()?;
        Ok(CheckedTest(self))
    }

    /// Check every value; the error names the field.
    pub fn validate(&self) -> Result<(), LabError> {
        let bad = |field: &str, reason: String| {
            Err(LabError::Param {
                field: field.into(),
                reason,
            })
        };
        for (f, v) in [
            ("depth", self.depth),
            ("speed", self.speed),
            ("length", self.length),
            ("rake_face", self.rake_face),
            ("clearance_face", self.clearance_face),
            ("approach", self.approach),
            ("tool_stiffness", self.tool_stiffness),
            ("surface_bin", self.surface_bin),
            ("max_energy_growth", self.max_energy_growth),
            ("max_overlap_fraction", self.max_overlap_fraction),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return bad(f, format!("{v} must be positive"));
            }
        }
        let deg = |r: f64| r.to_degrees();
        if self.rake_angle.is_nan() || self.rake_angle.abs() >= 45f64.to_radians() {
            return bad(
                "rake_angle",
                format!("{}° must lie in (−45°, 45°)", deg(self.rake_angle)),
            );
        }
        if !(self.clearance_angle > 0.0 && self.clearance_angle < 45f64.to_radians()) {
            return bad(
                "clearance_angle",
                format!("{}° must lie in (0°, 45°)", deg(self.clearance_angle)),
            );
        }
        if self.rake_angle + self.clearance_angle >= 85f64.to_radians() {
            return bad(
                "rake_angle",
                "rake + clearance angle must stay below 85° (wedge angle ≥ 5°)".into(),
            );
        }
        if self.rake_face * self.rake_angle.cos() <= 1.0 {
            return bad(
                "rake_face",
                "the rake face must reach above the specimen top (rake_face · cos γ > 1)".into(),
            );
        }
        // A snapshot at most every history row (issue 48 D4: `--snapshots 100000000` wrote one
        // every step, 25,546 files in 90 s); the disk estimate of the run layer bounds the rest.
        if self.snapshots > self.history_rows {
            return bad(
                "snapshots",
                format!(
                    "{} is more than the {} history rows (history_rows): snapshots are taken \
                     at most once a row; ask for at most {} (or more rows)",
                    self.snapshots, self.history_rows, self.history_rows
                ),
            );
        }
        if !(self.mass_scaling >= 0.0 && self.mass_scaling <= 0.5) {
            return bad(
                "mass_scaling",
                format!("{} must lie in [0, 0.5]", self.mass_scaling),
            );
        }
        if !(self.tool_friction >= 0.0 && self.tool_friction.is_finite()) {
            return bad("tool_friction", "must be ≥ 0".into());
        }
        if !(self.edge_radius >= 0.0 && self.edge_radius.is_finite()) {
            return bad("edge_radius", format!("{} must be ≥ 0", self.edge_radius));
        }
        if self.edge_radius > 0.0 && self.tool == ToolModel::Segments {
            return bad(
                "edge_radius",
                "an edge radius needs the rigid tool (tool = \"rigid\")".into(),
            );
        }
        if self.edge_radius >= self.clearance_face.min(self.rake_face) {
            return bad(
                "edge_radius",
                "the rounded edge must be shorter than both faces".into(),
            );
        }
        if !(0.0..=1.0).contains(&self.contact_damping) {
            return bad("contact_damping", "must lie in [0, 1]".into());
        }
        if !(0.0..1.0).contains(&self.local_damping) {
            return bad("local_damping", "must lie in [0, 1)".into());
        }
        if self.frame == CutFrame::Tool && self.delete_fragments {
            return bad(
                "frame",
                "the tool frame moves the specimen, and fragment deletion's rules are written \
                 for the lab frame: run delete_fragments with frame \"lab\""
                    .into(),
            );
        }
        self.dt_factor.check("dt_factor")?;
        if self.history_rows < 10 {
            return bad("history_rows", "at least 10".into());
        }
        if !(self.window_start >= 0.0 && self.window_start * self.depth < self.length) {
            // Issue 48 D9: the numbers and every flag that moves it, not only a flag the user
            // may not have given.
            return bad(
                "window_start",
                format!(
                    "the steady window from window_start × depth = {} × {:.4} mm = {:.4} mm to \
                     the cut length {:.4} mm is empty: lengthen the cut (--length), cut \
                     shallower (--depth) or start the window earlier (--window-start)",
                    self.window_start,
                    self.depth * 1e3,
                    self.window_start * self.depth * 1e3,
                    self.length * 1e3
                ),
            );
        }
        Ok(())
    }
}

/// A [`CuttingTest`] that passed [`CuttingTest::validate`]; made only by
/// [`CuttingTest::check`]. The scene, the geometry, the run and the analysis take this type, so
/// a cut is validated once, where its values enter (a flag, a study, a job), and not again on
/// the way to the integrator. Reads as the test it holds (`Deref`).
#[derive(Clone, Debug, PartialEq)]
pub struct CheckedTest(CuttingTest);

impl CheckedTest {
    /// The test it holds.
    pub fn test(&self) -> &CuttingTest {
        &self.0
    }

    /// Gives the test back (to change it, then [`CuttingTest::check`] it again).
    pub fn into_inner(self) -> CuttingTest {
        self.0
    }
}

impl std::ops::Deref for CheckedTest {
    type Target = CuttingTest;
    fn deref(&self) -> &CuttingTest {
        &self.0
    }
}

/// Metres as millimetres for messages: up to 4 decimals, trailing zeros dropped (`3`, `1.5`,
/// `0.125`).
pub fn mm(v: f64) -> String {
    let t = format!("{:.4}", v * 1e3);
    let t = t.trim_end_matches('0').trim_end_matches('.');
    if t == "-0" {
        "0".into()
    } else {
        t.into()
    }
}

/// Checks the test's geometry against the specimen's bounding box `extent` = `[x0, x1, y0,
/// y1]` (m), before any run: the cut length L must stay on the specimen (L ≤ its width; the
/// steady window ends at L, so a longer cut reports forces of the tool in the air), and the
/// depth must leave room for the cut and the slot's side walls (1.5 a_p < its height, as
/// [`CutGeometry::new`] needs). The error names the field (`length`, `depth`) and gives the
/// value and the specimen's extent. Run-time only: the test's serialised form is unchanged.
pub fn check_geometry(test: &CuttingTest, extent: [f64; 4]) -> Result<(), LabError> {
    let [x0, x1, y0, y1] = extent;
    let (w, h) = (x1 - x0, y1 - y0);
    if !(w > 0.0 && h > 0.0 && extent.iter().all(|v| v.is_finite())) {
        return Err(LabError::Param {
            field: "specimen".into(),
            reason: format!("its extent {extent:?} (m) is not a box"),
        });
    }
    let span = format!(
        "x from {} to {} mm, y from {} to {} mm",
        mm(x0),
        mm(x1),
        mm(y0),
        mm(y1)
    );
    // (A relative allowance of rounding: L equal to the width, written in other units.)
    if test.length > w * (1.0 + 1e-9) {
        return Err(LabError::Param {
            field: "length".into(),
            reason: format!(
                "the cut length L = {} mm runs past the specimen, which is {} mm wide ({span}); \
                 the tool would cut air and the steady window would end outside the specimen: \
                 L must be at most {} mm",
                mm(test.length),
                mm(w),
                mm(w)
            ),
        });
    }
    if 1.5 * test.depth >= h {
        return Err(LabError::Param {
            field: "depth".into(),
            reason: format!(
                "the depth of cut a_p = {} mm is too deep for the specimen, which is {} mm high \
                 ({span}); the cut and the slot's side walls below it need 1.5 a_p below the \
                 height: a_p must be below {} mm",
                mm(test.depth),
                mm(h),
                mm(h / 1.5)
            ),
        });
    }
    Ok(())
}

/// What the cutting test needs to know about a specimen file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpecimenInfo {
    /// The file (absolute when it could be resolved).
    pub file: PathBuf,
    /// Material name its discs refer to.
    pub material: String,
    /// Bounding box of its discs `[x0, x1, y0, y1]` (m, as loaded with offset 0).
    pub extent: [f64; 4],
    pub discs: usize,
}

impl SpecimenInfo {
    /// Reads a `dem.specimen/1` file (as `dem specimen` writes it: disc sets, no template
    /// clump sets).
    pub fn read(path: &Path) -> Result<SpecimenInfo, LabError> {
        let file = path.display().to_string();
        let text = clumpgen::io::read_input_string(path).map_err(|source| LabError::Io {
            file: file.clone(),
            source,
        })?;
        let spec: SpecimenFile = serde_json::from_str(&text).map_err(|e| LabError::Param {
            field: file.clone(),
            reason: format!("not a specimen file: {e}"),
        })?;
        let bad = |reason: &str| LabError::Param {
            field: file.clone(),
            reason: reason.into(),
        };
        if !spec.clumps.is_empty() {
            return Err(bad(
                "template clump sets are not supported by the cutting test",
            ));
        }
        let u = spec.units.metres();
        let mut ext = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut material: Option<String> = None;
        let mut n = 0;
        for set in &spec.discs {
            match &material {
                None => material = Some(set.material.clone()),
                Some(m) if *m != set.material => {
                    return Err(bad("disc sets of different materials are not supported"))
                }
                _ => {}
            }
            for [x, y, r] in &set.discs {
                let (x, y, r) = (x * u, y * u, r * u);
                ext = [
                    ext[0].min(x - r),
                    ext[1].max(x + r),
                    ext[2].min(y - r),
                    ext[3].max(y + r),
                ];
                n += 1;
            }
        }
        let Some(material) = material.filter(|_| n > 0) else {
            return Err(bad("the specimen has no discs"));
        };
        Ok(SpecimenInfo {
            file: std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
            material,
            extent: ext,
            discs: n,
        })
    }
}

/// The model a specimen written by `dem specimen` was generated with: thickness and
/// micro-parameters from `<stem>.summary.json`, density and the bond stiffness from
/// `<stem>.scene.json` (r̄ = Ē_c / (2 k̄_n), so the bond stiffness is reproduced exactly).
///
/// The bond model: flat joints ([`LabModel::flat_joint`], Potyondy 2012) when the scene's
/// bond groups are `flat_joint_potyondy2012` groups with one choice of elements, friction and
/// bonded fraction (a scene edited to flat joints, or written from a flat-joint model);
/// parallel bonds otherwise. `dem specimen` writes parallel bonds, and the summary has no
/// bond model, so a specimen's own files say "parallel bonds" unless the scene was changed:
/// `dem test cutting --flat-joint` puts its option on the model read here (the command line
/// wins, `CuttingArgs::with_joints` in dem-cli).
pub fn model_from_specimen(path: &Path) -> Result<LabModel, LabError> {
    let sp = crate::specimen::io::summary_path(path);
    let summary: crate::specimen::Summary = crate::read_json(&sp)?;
    let name = sp.to_string_lossy().replace(".summary.json", ".scene.json");
    let scene_path = PathBuf::from(name);
    let scene: SceneFile = crate::read_json(&scene_path)?;
    let field = |what: &str| LabError::Param {
        field: format!("{}: {what}", scene_path.display()),
        reason: "missing: the scene `dem specimen` writes has it".to_string(),
    };
    let density = scene
        .materials
        .first()
        .and_then(|m| m.density)
        .ok_or_else(|| field("materials[0].density"))?;
    let bond_kn = scene
        .bond_groups
        .first()
        .and_then(|g| g.kn)
        .ok_or_else(|| field("bond_groups[0].kn"))?;
    Ok(LabModel {
        density,
        thickness: summary.thickness,
        r_mean: summary.micro.bond_modulus / (2.0 * bond_kn),
        micro: summary.micro,
        flat_joint: scene_flat_joint(&scene, &scene_path)?,
    })
}

/// The flat-joint choice of a scene's bond groups (`None`: none is a flat joint). Each
/// flat-joint group is read as the scene loader reads it (defaults, ranges); the model has one
/// choice for both groups, so groups of flat joints that differ in elements, friction or bonded
/// fraction, or flat joints beside other bonds, are an error naming the scene's `bond_groups`.
fn scene_flat_joint(
    scene: &SceneFile,
    file: &Path,
) -> Result<Option<super::model::FlatJointOption>, LabError> {
    use dem_core::bond::BondModel;
    use dem_core::scene::schema::BondModelName;
    let name = file.display().to_string();
    let err = |reason: String| LabError::Param {
        field: format!("{name}: bond_groups"),
        reason,
    };
    let mut found: Vec<Option<super::model::FlatJointOption>> = Vec::new();
    for (k, spec) in scene.bond_groups.iter().enumerate() {
        if spec.model != BondModelName::FlatJointPotyondy2012 {
            // (Other bonds are not read: the scene as the specimen wrote it.)
            found.push(None);
            continue;
        }
        let group = dem_core::scene::bond_group(&name, k, spec)?;
        found.push(match group.model {
            BondModel::FlatJoint(p) => Some(super::model::FlatJointOption {
                elements: p.elements,
                friction: p.friction,
                bonded_fraction: p.bonded_fraction,
            }),
            _ => None,
        });
    }
    match found.split_first() {
        None => Ok(None),
        Some((first, rest)) if rest.iter().all(|o| o == first) => Ok(*first),
        Some(_) => Err(err(format!(
            "the groups' bond models differ ({}); the cutting test's model has one choice \
             (parallel bonds, or flat joints of one kind) for all of them",
            found
                .iter()
                .map(|o| match o {
                    None => "parallel or contact".to_string(),
                    Some(f) => format!(
                        "flat joint N {} μ {} φ_B {}",
                        f.elements, f.friction, f.bonded_fraction
                    ),
                })
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

/// The cutting scene (plain `dem.scene/1` JSON): the model's materials (disc material renamed
/// to the specimen's), a `tool` material with its disc pair (stiffness from `tool_stiffness`
/// by the test's [`ToolModel`], friction `tool_friction`), the specimen at offset 0, the slot
/// walls (frictionless `wall` material; with the rigid tool their disc pair is PFC's series
/// stiffness of the model's `wall_stiffness_factor`), the tool — one polyline wall `tool`, or
/// the walls `rake` and `clearance` — moving at (v, 0), duration, time-step factor, local
/// damping, contact damping, and outputs in the scene's folder with a history row every
/// `history_every` steps.
pub fn scene(
    test: &CheckedTest,
    model: &LabModel,
    spec: &SpecimenInfo,
    history_every: u64,
) -> Result<SceneFile, LabError> {
    let g = CutGeometry::new(test, spec.extent)?;
    let file = spec.file.display().to_string();
    let mut s = model.scene_file("cutting", &file, [0.0, 0.0]);
    let walls_named = match test.tool {
        ToolModel::Rigid => "one rigid tool wall `tool`",
        ToolModel::Segments => "tool walls `rake` and `clearance`",
    };
    s.description = format!(
        "Orthogonal cutting (dem test cutting): a_p = {} mm, v = {} m/s, L = {} mm, rake {}°, \
         clearance {}°; {walls_named}, slot walls `slot_*`.",
        test.depth * 1e3,
        test.speed,
        test.length * 1e3,
        test.rake_angle.to_degrees(),
        test.clearance_angle.to_degrees()
    );
    let kn = model.contact_kn();
    let ks = kn / model.micro.stiffness_ratio;
    let (ft, fw) = (test.tool_stiffness, model.micro.wall_stiffness_factor);
    let ((ktool, kstool), slot) = match test.tool {
        ToolModel::Rigid => (
            (series_wall_stiffness(kn, ft), series_wall_stiffness(ks, ft)),
            Some((series_wall_stiffness(kn, fw), series_wall_stiffness(ks, fw))),
        ),
        ToolModel::Segments => ((ft * kn, ft * ks), None),
    };
    let mat = spec.material.as_str();
    for m in s.materials.iter_mut().filter(|m| m.name == DISC_MATERIAL) {
        m.name = mat.into();
        if test.contact_damping > 0.0 {
            m.damping_ratio = Some(test.contact_damping);
        }
    }
    s.materials.push(super::model::material(
        TOOL_MATERIAL,
        None,
        ktool,
        kstool,
        test.tool_friction,
    ));
    for p in s.contact.pairs.iter_mut() {
        p.materials = [mat.into(), WALL_MATERIAL.into()];
        if let Some((kw, ksw)) = slot {
            p.kn = Some(kw);
            p.ks = Some(ksw);
        }
    }
    s.contact.pairs.push(super::model::pair(
        mat,
        TOOL_MATERIAL,
        ktool,
        kstool,
        test.tool_friction,
    ));
    // Lab frame: the slot walls at rest, the tool's at (v, 0) about its edge. Tool frame: every
    // body and wall given −(v, 0): the tool at rest, the specimen and the slot moving.
    let frame_v = match test.frame {
        CutFrame::Lab => [0.0, 0.0],
        CutFrame::Tool => [-g.velocity[0], -g.velocity[1]],
    };
    let wall = |w: &Segment| WallSpec {
        via: w.via.clone(),
        ..crate::tests::harness::wall(&w.name, w.a, w.b, frame_v)
    };
    s.walls = g.slot.iter().map(wall).collect();
    for w in &g.tool {
        s.walls.push(WallSpec {
            material: TOOL_MATERIAL.into(),
            velocity: [g.velocity[0] + frame_v[0], g.velocity[1] + frame_v[1]],
            center: Some(g.edge_start),
            ..wall(w)
        });
    }
    for sp in &mut s.bodies.specimens {
        sp.velocity = frame_v;
    }
    s.damping.local = test.local_damping;
    s.damping.frame = test.damping_frame;
    s.run = RunSpec {
        duration: Some(g.duration),
        dt_factor: Some(test.dt_factor.get()),
        max_energy_growth: Some(test.max_energy_growth),
        max_overlap_fraction: Some(test.max_overlap_fraction),
        mass_scaling: (test.mass_scaling > 0.0).then_some(test.mass_scaling),
        ..RunSpec::default()
    };
    let every = history_every.max(1);
    s.outputs = OutputSpec {
        dir: Some(".".into()),
        history_every: every,
        // `snapshots` spread evenly over the cut's duration, the first at the start and the
        // last at the end (issue 48: an interval of the planned steps wrote 4 for 3).
        vtk_count: test.snapshots,
        ..OutputSpec::default()
    };
    Ok(s)
}

/// A copy of `st` with every disc, clump and wall moved by `d` (m): a cut run in the tool's
/// frame, seen in the lab frame (velocities are left as they are: the analyses read
/// positions).
fn shift_state(st: &State, d: [f64; 2]) -> State {
    let mut s = st.clone();
    for x in s.discs.x.iter_mut().chain(s.clumps.x.iter_mut()) {
        *x += d[0];
    }
    for y in s.discs.y.iter_mut().chain(s.clumps.y.iter_mut()) {
        *y += d[1];
    }
    for w in &mut s.walls {
        w.translate(d);
    }
    s
}

/// Tool forces against travel, one entry per history row.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ForceHistory {
    /// Tool travel s = edge x − x0 (m).
    pub travel: Vec<f64>,
    pub time: Vec<f64>,
    /// Main (cutting) force: the force of the discs on the tool opposing its motion (N, for
    /// the scene thickness); positive while cutting.
    pub main: Vec<f64>,
    /// Vertical (thrust) force: the discs' force on the tool along +y, i.e. pushing the tool
    /// away from the workpiece when positive (N).
    pub vertical: Vec<f64>,
}

impl ForceHistory {
    /// From a run's history: the tool walls' reactions.
    pub fn from_record(h: &Record, g: &CutGeometry) -> Result<ForceHistory, LabError> {
        let time = h.time.clone();
        let wall = |w: &str| crate::tests::harness::wall_series(h, w, "cutting");
        // The tool's force: the one rigid tool wall, or the two faces of the earlier model.
        let (fx, fy) = if g.tool.len() == 1 {
            let t = wall(TOOL)?;
            (t.fx.clone(), t.fy.clone())
        } else {
            let (r, c) = (wall(RAKE)?, wall(CLEARANCE)?);
            (
                crate::tests::harness::sum2(&r.fx, &c.fx),
                crate::tests::harness::sum2(&r.fy, &c.fy),
            )
        };
        let v = g.velocity;
        let speed = (v[0] * v[0] + v[1] * v[1]).sqrt();
        let (ux, uy) = (v[0] / speed, v[1] / speed);
        let n = time.len();
        Ok(ForceHistory {
            travel: time.iter().map(|&t| g.travel(t)).collect(),
            main: (0..n).map(|k| -(fx[k] * ux + fy[k] * uy)).collect(),
            vertical: fy,
            time,
        })
    }

    /// CSV `travel_m,time_s,main_N,vertical_N`.
    pub fn to_csv(&self) -> String {
        let mut s = String::from("travel_m,time_s,main_N,vertical_N\n");
        for k in 0..self.time.len() {
            let _ = writeln!(
                s,
                "{:e},{:e},{:e},{:e}",
                self.travel[k], self.time[k], self.main[k], self.vertical[k]
            );
        }
        s
    }
}

/// Broken bonds of one group.
///
/// With flat joints (Potyondy 2012; [`LabModel::flat_joint`]) a bond is an interface of N
/// elements that break one by one. `tension` and `shear` are then, as the store counts them
/// (`Bonds::broken_counts`), the interfaces whose last bonded element broke (their cement is
/// all gone), by that element's mode: an interface with some cement left is not broken (it
/// still joins its discs, see [`chips`]). `total` counts the interfaces that had cement at
/// installation: one installed with every element slit (bonded fraction φ_B < 1) can never
/// break and is counted in `slit` instead. The element-level figures are beside them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BrokenBonds {
    pub group: String,
    pub tension: u64,
    pub shear: u64,
    /// Bonds of the group at the start (with flat joints: those with cement, see above;
    /// bonds that went with deleted fragments included).
    pub total: usize,
    /// Flat joints only (absent for parallel bonds): interfaces installed with every element
    /// slit, never cemented (not in `total`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slit: Option<usize>,
    /// Flat joints only: interfaces that lost some but not all of their bonded elements (not
    /// broken: cement left).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub partly_broken: Option<usize>,
    /// Flat joints only: bonded elements broken over the run, those of broken interfaces
    /// included (of `elements_bonded` at installation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elements_broken: Option<u64>,
    /// Flat joints only: bonded elements at installation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elements_bonded: Option<u64>,
}

/// [`BrokenBonds`] of every group of `b` (see there for flat joints; the element figures of
/// interfaces that went with deleted fragments are not known and left out).
pub fn broken_bonds(b: &dem_core::bond::Bonds) -> Vec<BrokenBonds> {
    let groups = b.groups();
    let mut total = vec![0usize; groups.len()];
    // Flat-joint groups: [slit, partly broken, elements broken, elements bonded].
    let mut fj: Vec<Option<[u64; 4]>> = groups
        .iter()
        .map(|g| matches!(g.model, dem_core::bond::BondModel::FlatJoint(_)).then_some([0; 4]))
        .collect();
    for k in 0..b.len() {
        let g = b.get(k).group as usize;
        match (chips::flat_joint_elements(b, k), fj[g].as_mut()) {
            (Some((0, _)), Some(c)) => c[0] += 1,
            (Some((installed, now)), Some(c)) => {
                total[g] += 1;
                c[1] += u64::from(now > 0 && now < installed);
                c[2] += u64::from(installed - now);
                c[3] += u64::from(installed);
            }
            _ => total[g] += 1,
        }
    }
    // (Bonds that went with deleted fragments, see `CuttingTest::delete_fragments`.)
    for (t, d) in total.iter_mut().zip(b.dropped_counts()) {
        *t += d as usize;
    }
    groups
        .iter()
        .zip(b.broken_counts())
        .zip(total)
        .zip(fj)
        .map(|(((grp, c), n), f)| BrokenBonds {
            group: grp.name.clone(),
            tension: c[0],
            shear: c[1],
            total: n,
            slit: f.map(|f| f[0] as usize),
            partly_broken: f.map(|f| f[1] as usize),
            elements_broken: f.map(|f| f[2]),
            elements_bonded: f.map(|f| f[3]),
        })
        .collect()
}

/// How the run went (filled from the history and the world; wall time by [`run`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunFigures {
    pub steps: u64,
    /// Time step at the end and its range over the run (s).
    pub dt: f64,
    pub dt_min: f64,
    pub dt_max: f64,
    pub history_rows: usize,
    pub history_every: u64,
    /// Relative energy balance error (history column `balance_error`, relative to the largest
    /// of initial, current, dissipated energy and boundary work): last row, and largest
    /// magnitude over the rows of the steady window (before the tool has done work the
    /// relative error is round-off over ~1e-24 J and means nothing).
    pub balance_error_final: f64,
    pub balance_error_max_abs: f64,
    pub wall_time_s: f64,
    pub threads: usize,
    /// Deepest overlap seen at the guard checks (fraction of the smaller radius for disc
    /// pairs, of the disc radius for the tool and slot walls); `None` in results written
    /// before it was recorded.
    #[serde(default)]
    pub max_overlap_fraction: Option<f64>,
    /// CPU time of the thread that drove the run (s; all of its CPU on a one-thread pool),
    /// over all invocations; `None` where unknown and in results written before it was
    /// recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cpu_time_s: Option<f64>,
    /// Invocations the run took (1, or more when it was resumed from a checkpoint; wall and
    /// CPU time, dt range and deepest overlap are over all of them).
    #[serde(default = "one")]
    pub invocations: u32,
    /// What the selective mass scaling did ([`CuttingTest::mass_scaling`]); absent without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_scaling: Option<dem_core::mass_scaling::MassScaling>,
}

fn one() -> u32 {
    1
}

/// Everything the cutting test reports (SI: m, N for the scene thickness, kg, s).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CuttingResult {
    pub schema: String,
    pub test: CuttingTest,
    pub specimen: String,
    pub discs: usize,
    /// Disc thickness t (m); forces are for this thickness.
    pub thickness: f64,
    pub geometry: CutGeometry,
    /// Steady window of tool travel `[window_start · a_p, L]` (m).
    pub window: [f64; 2],
    /// Main and vertical force over the window (N).
    pub main_force: analysis::ForceStats,
    pub vertical_force: analysis::ForceStats,
    /// Largest |main force| while the tool's foremost point was still outside the specimen
    /// (N); 0 when nothing touched it before entry.
    pub main_force_before_entry: f64,
    /// First travel at which the main force is positive (m).
    pub contact_travel: Option<f64>,
    /// Share of the steady window's force rows with the tool touching anything (a positive
    /// main force): under damping that leaves flying debris alone a brittle cut is a train of
    /// strikes, and a window mean over few of them says little (docs/cutting.md, "Damping and
    /// the frame of reference"). `None` in results written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub touching: Option<f64>,
    pub chips: ChipReport,
    pub broken_bonds: Vec<BrokenBonds>,
    pub broken_total: u64,
    pub surface: Option<Surface>,
    pub residual_cracks: ResidualCracks,
    pub run: RunFigures,
    /// Files written (scene, history, result, forces, breaks, summary).
    pub files: Vec<String>,
    /// How the material left (S0's terms: single grains or chunks, chip speeds); `None` in
    /// results written before it was recorded. (Fragments deleted during the run, see
    /// `deleted`, are not in it.)
    #[serde(default)]
    pub removal: Option<RemovalMode>,
    /// Fragments deleted during the run ([`CuttingTest::delete_fragments`]); absent when
    /// deletion was off.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub deleted: Option<self::debris::DeletedFragments>,
}

/// Schema tag of [`CuttingResult`].
pub const RESULT_SCHEMA: &str = "dem.cutting-result/1";

fn stats_or_err(
    f: &ForceHistory,
    v: &[f64],
    w: [f64; 2],
) -> Result<analysis::ForceStats, LabError> {
    analysis::force_stats(&f.travel, v, w[0], w[1]).ok_or_else(|| LabError::Analysis {
        test: "cutting".into(),
        reason: format!(
            "no history row in the steady window {:?} m of travel (history reaches {:?} m)",
            w,
            f.travel.last()
        ),
    })
}

/// Share of the rows with travel in `window` whose main force is positive; `None` when the
/// window holds no row ([`CuttingResult::touching`]; also read back from the forces file of a
/// run written before the field).
pub fn touching_share(travel: &[f64], main: &[f64], window: [f64; 2]) -> Option<f64> {
    let (mut rows, mut on) = (0usize, 0usize);
    for (s, m) in travel.iter().zip(main) {
        if *s >= window[0] && *s <= window[1] {
            rows += 1;
            on += usize::from(*m > 0.0);
        }
    }
    (rows > 0).then(|| on as f64 / rows as f64)
}

/// Analyses a finished cut: tool forces from `history`, chips, broken bonds, surface and
/// residual cracks from the final `world`.
pub fn analyze(
    test: &CheckedTest,
    spec: &SpecimenInfo,
    history: &Record,
    world: &World,
) -> Result<(CuttingResult, ForceHistory), LabError> {
    let g = CutGeometry::new(test, spec.extent)?;
    let f = ForceHistory::from_record(history, &g)?;
    let window = [test.window_start * test.depth, test.length];
    let main_force = stats_or_err(&f, &f.main, window)?;
    let vertical_force = stats_or_err(&f, &f.vertical, window)?;
    let main_force_before_entry = f
        .travel
        .iter()
        .zip(&f.main)
        .filter(|(s, _)| **s < g.travel_entry)
        .map(|(_, m)| m.abs())
        .fold(0.0, f64::max);
    let contact_travel = f
        .travel
        .iter()
        .zip(&f.main)
        .find(|(_, m)| **m > 0.0)
        .map(|(s, _)| *s);
    let touching = touching_share(&f.travel, &f.main, window);

    // A cut run in the tool's frame is analysed in the lab frame: its final state shifted by
    // the distance the specimen travelled (v t).
    let shifted;
    let st = match test.frame {
        CutFrame::Lab => &world.state,
        CutFrame::Tool => {
            let t = world.state.time;
            shifted = shift_state(&world.state, [g.velocity[0] * t, g.velocity[1] * t]);
            &shifted
        }
    };
    let bonds = world.bonds.as_ref();
    let frags = chips::fragments(st, bonds);
    let chips = chips::classify(&frags, g.nominal_y);
    let removal = removal_mode(st, &frags, g.nominal_y, test.speed);
    let [x0, _, y0, _] = spec.extent;
    let cracks = frags.first().map_or_else(ResidualCracks::default, |w| {
        chips::residual_cracks(st, bonds, w, g.nominal_y, x0, x0 + test.length)
    });
    let d = &st.discs;
    let r_mean = d.r.iter().sum::<f64>() / d.len().max(1) as f64;
    let bin = test.surface_bin * 2.0 * r_mean;
    let surface = frags.first().and_then(|w| {
        let discs = w.discs.iter().map(|&k| [d.x[k], d.y[k], d.r[k]]);
        surface::measure(
            discs,
            x0 + bin,
            x0 + test.length - bin,
            bin,
            g.nominal_y,
            y0,
        )
    });
    let broken_bonds = bonds.map(broken_bonds).unwrap_or_default();
    let broken_total = broken_bonds.iter().map(|b| b.tension + b.shear).sum();
    let bal = &history.energy.balance_error;
    let dts = &history.dt;
    let run = RunFigures {
        steps: st.step,
        dt: world.dt(),
        dt_min: dts.iter().copied().fold(f64::INFINITY, f64::min),
        dt_max: dts.iter().copied().fold(0.0, f64::max),
        history_rows: history.len(),
        history_every: 0,
        balance_error_final: bal.last().copied().unwrap_or(0.0),
        balance_error_max_abs: bal
            .iter()
            .zip(&f.travel)
            .filter(|(_, s)| **s >= window[0])
            .map(|(v, _)| v.abs())
            .fold(0.0, f64::max),
        wall_time_s: 0.0,
        threads: rayon::current_num_threads(),
        max_overlap_fraction: None,
        cpu_time_s: None,
        invocations: 1,
        mass_scaling: world.mass_scaling().cloned(),
    };
    let result = CuttingResult {
        schema: RESULT_SCHEMA.into(),
        test: test.test().clone(),
        specimen: spec.file.display().to_string(),
        discs: d.len(),
        thickness: st.thickness,
        geometry: g,
        window,
        main_force,
        vertical_force,
        main_force_before_entry,
        contact_travel,
        touching,
        chips,
        broken_bonds,
        broken_total,
        surface,
        residual_cracks: cracks,
        run,
        files: Vec::new(),
        removal: Some(removal),
        deleted: test
            .delete_fragments
            .then(|| self::debris::DeletedFragments::from_totals(world.removal_totals(), 0)),
    };
    Ok((result, f))
}

/// A cutting run's scene as [`run_with`] builds and runs it (and `dem bench cutting` times it):
/// the test checked against the specimen, the world built (its time step sets the history
/// cadence; the run then starts from this world rather than building it again), the history
/// cadence set for about `history_rows` rows, the fragment-deletion note, and numbered
/// checkpoints (about `checkpoints` over the run, 0 = none) on history rows.
pub struct CuttingScene {
    pub spec: SpecimenInfo,
    pub geometry: CutGeometry,
    /// The `dem.scene/1` scene to run (what `cutting.scene.json` holds).
    pub scene: SceneFile,
    /// Time step of the built world (s) and the steps of the whole cut.
    pub dt: f64,
    pub steps: u64,
    /// A history row every `every` steps.
    pub every: u64,
    debris: Option<self::debris::DebrisRule>,
    /// The world built from `scene` (until [`CuttingScene::take_world`] takes it).
    world: Option<World>,
}

impl CuttingScene {
    /// Checks the cut's geometry on the specimen (read once by the caller,
    /// [`SpecimenInfo::read`]) and builds the scene, whose file will be `scene_file` (relative
    /// paths resolve from there, as `dem run` resolves them), and its world, from the scene
    /// checked in memory.
    pub fn build(
        test: &CheckedTest,
        model: &LabModel,
        spec: &SpecimenInfo,
        scene_file: &Path,
        checkpoints: u64,
    ) -> Result<CuttingScene, LabError> {
        let spec = spec.clone();
        check_geometry(test, spec.extent)?;
        // Build the world, whose time step sets the history cadence (about `history_rows`
        // rows). The cadence and the other outputs do not enter the build: the run starts from
        // this world.
        let probe = scene(test, model, &spec, 1)?;
        let world = dem_core::scene::build(&dem_core::scene::resolve(probe, scene_file)?)?;
        let dt = world.dt();
        let g = CutGeometry::new(test, spec.extent)?;
        let steps = (g.duration / dt).ceil().max(1.0) as u64;
        let every = steps.div_ceil(test.history_rows).max(1);
        let mut s = scene(test, model, &spec, every)?;
        let debris = test.delete_fragments.then_some(self::debris::DebrisRule {
            nominal_y: g.nominal_y,
            top_y: spec.extent[3],
        });
        if debris.is_some() {
            // (So a run with deletion never resumes one without, nor the other way round.)
            s.description += " Detached fragments deleted on every history row (dem test \
                 cutting --delete-fragments; dem run does not delete them).";
        }
        if checkpoints > 0 {
            // On history rows, about `checkpoints` over the run.
            let n = steps.div_ceil(every).div_ceil(checkpoints).max(1) * every;
            s.outputs.checkpoint_every = n;
            s.outputs.checkpoint_keep = 1;
        }
        Ok(CuttingScene {
            spec,
            geometry: g,
            scene: s,
            dt,
            steps,
            every,
            debris,
            world: Some(world),
        })
    }

    /// The world built from the scene (once; `None` after).
    pub fn take_world(&mut self) -> Option<World> {
        self.world.take()
    }

    /// The step hook the run sets: fragment deletion on every history row when the test asks
    /// for it.
    pub fn hook(&self) -> Option<dem_core::output::driver::StepHook> {
        self.debris.map(|r| self::debris::hook(self.every, r))
    }
}

/// How [`run_with`] runs: checkpoints to resume from, and an optional stop.
#[derive(Clone, Debug)]
pub struct CuttingRunOptions {
    /// About this many numbered checkpoints over the run (0 = none): only the newest is kept,
    /// and it is deleted when the run completes (`ckpt-final.json` stays).
    pub checkpoints: u64,
    /// Continue from the newest numbered checkpoint in the output folder if the folder holds a
    /// run of the same scene (`cutting.scene.json` equal to the one this test writes): a run
    /// that was killed goes on from its last checkpoint instead of starting again, with the
    /// same results bit for bit (checkpoints restore the whole world). A checkpoint that does
    /// not load starts the run afresh.
    pub resume: bool,
    /// Stop when the world reaches this step, before the end (the run then returns
    /// [`LabError::Stopped`] and can be resumed).
    pub max_steps: Option<u64>,
    /// Told the checkpoint and its step when the run resumes from one (issue 48: a rerun after
    /// kill -9 said only that it took over a stale lock), and again with `None` when that
    /// checkpoint does not load and the run starts afresh.
    pub on_resume: Option<OnResume>,
}

/// [`CuttingRunOptions::on_resume`]: the checkpoint and its step, or `None` for a fresh start
/// after a checkpoint that did not load.
pub type OnResume = fn(Option<(&Path, u64)>);

impl Default for CuttingRunOptions {
    fn default() -> CuttingRunOptions {
        CuttingRunOptions {
            checkpoints: 20,
            resume: true,
            max_steps: None,
            on_resume: None,
        }
    }
}

/// Runs a cutting test with the default [`CuttingRunOptions`] (20 checkpoints, resuming an
/// interrupted run of the same scene); see [`run_with`].
pub fn run(
    test: &CheckedTest,
    model: &LabModel,
    specimen: &SpecimenInfo,
    out_dir: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<CuttingResult, LabError> {
    run_with(
        test,
        model,
        specimen,
        out_dir,
        &CuttingRunOptions::default(),
        progress,
    )
}

/// Runs a cutting test on the specimen `specimen` (its file, read once by
/// [`SpecimenInfo::read`]) with `model`, writing everything to
/// `out_dir`: `cutting.scene.json` (plain scene; `dem run` re-runs it into the same folder),
/// the run's outputs (`history.csv`, `breaks.csv`, `summary.json`, `ckpt-final.json`),
/// `cutting.forces.csv` and `cutting.result.json`. `progress(done, total)` is called now and
/// then with step counts (of this invocation). Runs on the current rayon pool (results do
/// not depend on its size).
pub fn run_with(
    test: &CheckedTest,
    model: &LabModel,
    specimen: &SpecimenInfo,
    out_dir: &Path,
    ro: &CuttingRunOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<CuttingResult, LabError> {
    let scene_file = out_dir.join(SCENE_FILE);
    // The scene of an earlier run in this folder (read before the probe overwrites it).
    let earlier: Option<Value> = std::fs::read_to_string(&scene_file)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let mut cs = CuttingScene::build(test, model, specimen, &scene_file, ro.checkpoints)?;
    let mut built = cs.take_world();
    let (spec, s) = (&cs.spec, &cs.scene);
    let every = cs.every;
    let hook = || cs.hook();
    let now = serde_json::to_value(s).map_err(|e| LabError::Io {
        file: scene_file.display().to_string(),
        source: std::io::Error::other(e),
    })?;
    let restart = if ro.resume && earlier.as_ref() == Some(&now) {
        dem_core::output::driver::numbered_checkpoints(out_dir)
            .ok()
            .and_then(|mut c| c.pop())
    } else {
        None
    };
    if let (Some(tell), Some((step, p))) = (ro.on_resume, &restart) {
        tell(Some((p, *step)));
    }
    let restart = restart.map(|(_, p)| p);
    let mut opts = RunOptions {
        out_dir: Some(out_dir.to_path_buf()),
        restart,
        max_steps: ro.max_steps,
    };
    // (A resumed run starts from its checkpoint's world: the built one waits for a checkpoint
    // that does not load.)
    let fresh = if opts.restart.is_none() {
        built.take()
    } else {
        None
    };
    let mut lab = match run_built(s, &scene_file, fresh, &opts, progress, hook()) {
        Err(LabError::Run(dem_core::output::driver::RunError::Checkpoint(_)))
            if opts.restart.is_some() =>
        {
            opts.restart = None;
            if let Some(tell) = ro.on_resume {
                tell(None);
            }
            run_built(s, &scene_file, built, &opts, progress, hook())?
        }
        r => r?,
    };
    if lab.summary.status == "max_steps" {
        return Err(LabError::Stopped {
            dir: out_dir.display().to_string(),
            step: lab.summary.final_step,
        });
    }
    if ro.checkpoints > 0 {
        let gone = dem_core::output::driver::prune_checkpoints(&lab.out_dir, 0)?;
        // The summary, written before, listed them: it lists what is left.
        let names: Vec<String> = (gone.iter())
            .filter_map(|p| p.strip_prefix(&lab.out_dir).ok())
            .map(|p| p.display().to_string())
            .collect();
        if !names.is_empty() {
            lab.summary.files.retain(|f| !names.contains(f));
            lab.summary.save(&lab.out_dir.join("summary.json"))?;
        }
    }
    let (mut result, forces) = analyze(test, spec, &lab.history, &lab.world)?;
    result.run.history_every = every;
    if let Some(d) = result.deleted.as_mut() {
        d.check_every = every;
    }
    result.run.threads = lab.summary.threads;
    let sm = &lab.summary;
    // (The driver always records the totals; a summary without them is this invocation.)
    let whole = sm.whole_run.unwrap_or_else(|| {
        dem_core::output::summary::RunTotals::then(
            None,
            sm.wall_time_s,
            sm.cpu_time_s,
            [sm.dt_min, sm.dt_max],
            sm.max_overlap_fraction,
        )
    });
    result.run.wall_time_s = whole.wall_time_s;
    result.run.cpu_time_s = whole.cpu_time_s;
    result.run.invocations = whole.invocations;
    result.run.dt_min = whole.dt_min;
    result.run.dt_max = whole.dt_max;
    result.run.max_overlap_fraction = Some(whole.max_overlap_fraction);
    let forces_file = out_dir.join(FORCES_FILE);
    write_atomic(&forces_file, forces.to_csv().as_bytes())?;
    let result_file = out_dir.join(RESULT_FILE);
    result.files = vec![
        lab.scene_file.display().to_string(),
        lab.out_dir.join("history.csv").display().to_string(),
    ];
    for f in lab.summary.files.iter() {
        let p = out_dir.join(f);
        let p = p.display().to_string();
        if !result.files.contains(&p) {
            result.files.push(p);
        }
    }
    result.files.push(forces_file.display().to_string());
    result.files.push(result_file.display().to_string());
    let text = serde_json::to_string_pretty(&result).map_err(|e| LabError::Io {
        file: result_file.display().to_string(),
        source: std::io::Error::other(e),
    })?;
    write_atomic(&result_file, text.as_bytes())?;
    Ok(result)
}

impl CutGeometry {
    /// The geometry of `test` on a specimen whose discs span `extent`.
    pub fn new(test: &CheckedTest, extent: [f64; 4]) -> Result<CutGeometry, LabError> {
        let [x0, x1, y0, y1] = extent;
        if !(x1 > x0 && y1 > y0 && extent.iter().all(|v| v.is_finite())) {
            return Err(LabError::Param {
                field: "extent".into(),
                reason: format!("{extent:?} is not a box"),
            });
        }
        let ap = test.depth;
        let yn = y1 - ap;
        let side_top = yn - 0.5 * ap;
        if side_top <= y0 {
            return Err(LabError::Param {
                field: "depth".into(),
                reason: format!(
                    "a_p = {ap} m leaves no room for the slot's side walls below 1.5 a_p in a \
                     specimen {} m high",
                    y1 - y0
                ),
            });
        }
        let (sg, cg) = test.rake_angle.sin_cos();
        let (sa, ca) = test.clearance_angle.sin_cos();
        let lr = test.rake_face * ap;
        let lc = test.clearance_face * ap;
        // Foremost point ahead of the edge: the rake face's top when it leans forward (γ < 0).
        let overhang = (-sg * lr).max(0.0);
        let ex = x0 - test.approach * ap - overhang;
        let edge = [ex, yn];
        let ur = [-sg, cg];
        let uc = [-ca, sa];
        let rake_end = [ex + ur[0] * lr, yn + ur[1] * lr];
        let clear_end = [ex + uc[0] * lc, yn + uc[1] * lc];
        let tool = match test.tool {
            ToolModel::Segments => vec![
                Segment::new(RAKE, edge, rake_end),
                Segment::new(CLEARANCE, edge, clear_end),
            ],
            ToolModel::Rigid if test.edge_radius > 0.0 => {
                let (arc, low) = edge_arc(edge, uc, ur, test.edge_radius * ap);
                // Lower the whole tool so the arc's lowest point cuts at y_n.
                let dy = yn - low;
                let sh = |p: [f64; 2]| [p[0], p[1] + dy];
                vec![Segment {
                    name: TOOL.into(),
                    a: sh(clear_end),
                    b: sh(rake_end),
                    via: arc.into_iter().map(sh).collect(),
                }]
            }
            ToolModel::Rigid => vec![Segment {
                name: TOOL.into(),
                a: clear_end,
                b: rake_end,
                via: vec![edge],
            }],
        };
        let travel_end = test.length;
        let front_end = x0 + travel_end + overhang;
        let right_top = if front_end + 0.5 * ap < x1 {
            y1
        } else {
            side_top
        };
        let pad = 0.5 * ap;
        let slot = [
            Segment::new("slot_bottom", [x0 - pad, y0], [x1 + pad, y0]),
            Segment::new("slot_left", [x0, y0], [x0, side_top]),
            Segment::new("slot_right", [x1, y0], [x1, right_top]),
        ];
        let travel_start = ex - x0;
        Ok(CutGeometry {
            extent,
            nominal_y: yn,
            edge_start: edge,
            tool,
            slot,
            travel_start,
            travel_end,
            travel_entry: -overhang,
            duration: (travel_end - travel_start) / test.speed,
            velocity: [test.speed, 0.0],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{check_geometry, model_from_specimen, CuttingTest};
    use crate::model::FlatJointOption;
    use crate::LabError;

    fn field(r: Result<(), LabError>) -> Option<(String, String)> {
        match r {
            Ok(()) => None,
            Err(LabError::Param { field, reason }) => Some((field, reason)),
            Err(e) => panic!("{e}"),
        }
    }

    /// Issue 48 D9: an empty steady window names the numbers and the flags that move it.
    #[test]
    fn an_empty_window_names_depth_length_and_start() {
        let t = CuttingTest::new(5e-3, 1.0, 10e-3);
        let (f, reason) = field(t.validate()).unwrap();
        assert_eq!(f, "window_start");
        for s in [
            "2 × 5.0000 mm = 10.0000 mm",
            "10.0000 mm is empty",
            "--length",
            "--depth",
        ] {
            assert!(reason.contains(s), "{s}: {reason}");
        }
    }

    /// Issue 48 D4: more snapshots than history rows (a snapshot every step of the run) is
    /// refused naming the field and the most allowed; as many as rows is fine.
    #[test]
    fn more_snapshots_than_rows_are_refused() {
        let t = CuttingTest::default();
        let ok = CuttingTest {
            snapshots: t.history_rows,
            ..t.clone()
        };
        assert!(field(ok.validate()).is_none());
        let bad = CuttingTest {
            snapshots: 100_000_000,
            ..t
        };
        let (f, reason) = field(bad.validate()).unwrap();
        assert_eq!(f, "snapshots");
        assert!(
            reason.contains("100000000") && reason.contains("at most 4000"),
            "{reason}"
        );
    }

    #[test]
    fn cut_geometry_must_fit_the_specimen() {
        // A 5 × 2 mm specimen whose box starts at x = 1 mm.
        let ext = [1e-3, 6e-3, 0.0, 2e-3];
        assert!(field(check_geometry(&CuttingTest::new(0.5e-3, 1.0, 5e-3), ext)).is_none());
        let (f, r) = field(check_geometry(&CuttingTest::new(0.5e-3, 1.0, 100e-3), ext)).unwrap();
        assert_eq!(f, "length");
        assert!(
            r.contains("L = 100 mm") && r.contains("5 mm wide") && r.contains("x from 1 to 6 mm"),
            "{r}"
        );
        // 1.5 a_p must stay below the height: 1.3 mm passes, 1.4 mm does not.
        assert!(field(check_geometry(&CuttingTest::new(1.3e-3, 1.0, 5e-3), ext)).is_none());
        let (f, r) = field(check_geometry(&CuttingTest::new(1.4e-3, 1.0, 5e-3), ext)).unwrap();
        assert_eq!(f, "depth");
        assert!(
            r.contains("2 mm high") && r.contains("below 1.3333 mm"),
            "{r}"
        );
        let (f, _) = field(check_geometry(
            &CuttingTest::default(),
            [0.0, 0.0, 0.0, 1.0],
        ))
        .unwrap();
        assert_eq!(f, "specimen");
    }

    /// Mass scaling is off by default and then absent from the serialised test (the run keys
    /// of earlier cuts stay as they were); a budget outside [0, 0.5] is refused by name.
    #[test]
    fn mass_scaling_is_off_by_default_and_checked() {
        let t = CuttingTest::default();
        let j = serde_json::to_value(&t).unwrap();
        assert!(j.get("mass_scaling").is_none(), "{j}");
        let on = CuttingTest {
            mass_scaling: 0.02,
            ..t.clone()
        };
        assert_eq!(serde_json::to_value(&on).unwrap()["mass_scaling"], 0.02);
        assert!(field(on.validate()).is_none());
        for bad in [-0.1, 0.6, f64::NAN] {
            let t = CuttingTest {
                mass_scaling: bad,
                ..t.clone()
            };
            assert_eq!(field(t.validate()).unwrap().0, "mass_scaling", "{bad}");
        }
    }

    /// The damping frame is absent from a serialised test at `lab` (the run keys of every cut
    /// before the option stay as they were) and named at `fragment`, the default; a
    /// serialised test without it reads as `lab`; both round-trip.
    #[test]
    fn the_damping_frame_is_named_only_when_not_lab() {
        let t = CuttingTest::default();
        assert_eq!(t.damping_frame, dem_core::DampingFrame::Fragment);
        let j = serde_json::to_value(&t).unwrap();
        assert_eq!(j["damping_frame"], "fragment", "{j}");
        let back: CuttingTest = serde_json::from_value(j).unwrap();
        assert_eq!(back, t);
        let lab = CuttingTest {
            damping_frame: dem_core::DampingFrame::Lab,
            ..t
        };
        let mut j = serde_json::to_value(&lab).unwrap();
        assert!(j.get("damping_frame").is_none(), "{j}");
        let back: CuttingTest = serde_json::from_value(j.clone()).unwrap();
        assert_eq!(back, lab);
        // A test written before the option (no field) is the lab frame, not today's default.
        j.as_object_mut().unwrap().remove("damping_frame");
        let old: CuttingTest = serde_json::from_value(j).unwrap();
        assert!(old.damping_frame.is_lab());
    }

    /// The model read back from a specimen's files keeps a flat joint its scene names (both
    /// groups alike), is parallel bonds for the scene `dem specimen` writes, and refuses
    /// groups of different bond models by the scene's `bond_groups`.
    #[test]
    fn a_specimens_model_keeps_the_flat_joints_of_its_scene() {
        use crate::specimen::{self, Method, SpecimenParams};
        // The small specimen of dem-cli's cutting tests (3 × 1.5 mm, Si3N4, seed 2).
        let dir = std::env::temp_dir().join(format!("dem-fj-model-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let p = SpecimenParams::new(
            Method::Traditional,
            3e-3,
            1.5e-3,
            0.1e-3,
            0.16e-3,
            3200.0,
            310e9,
            800e6,
            2,
        );
        let s = specimen::generate(&p, &mut |_| {}).unwrap();
        let path = dir.join("s.json");
        specimen::io::save(&s, "si3n4", &path).unwrap();
        let mut scene =
            serde_json::to_value(specimen::io::example_scene(&s, "si3n4", "s.json", 10)).unwrap();
        let write = |v: &serde_json::Value| {
            std::fs::write(dir.join("s.scene.json"), v.to_string()).unwrap();
        };
        write(&scene);
        let pb = model_from_specimen(&path).unwrap();
        assert_eq!(pb.flat_joint, None);
        assert!(!serde_json::to_string(&pb).unwrap().contains("flat_joint"));
        let fj = FlatJointOption {
            elements: 3,
            friction: 0.4,
            bonded_fraction: 0.75,
        };
        let with = crate::LabModel {
            flat_joint: Some(fj),
            ..pb.clone()
        };
        scene["bond_groups"] = serde_json::to_value(with.bond_groups()).unwrap();
        write(&scene);
        let back = model_from_specimen(&path).unwrap();
        assert_eq!(back.flat_joint, Some(fj));
        assert_eq!(back, with);
        // One group a flat joint, the other a parallel bond: refused, naming the groups.
        scene["bond_groups"][1] = serde_json::to_value(&pb.bond_groups()[1]).unwrap();
        write(&scene);
        match model_from_specimen(&path) {
            Err(LabError::Param { field, reason }) => {
                assert!(field.ends_with("bond_groups"), "{field}");
                assert!(reason.contains("flat joint N 3"), "{reason}");
            }
            other => panic!("{other:?}"),
        }
        // A flat-joint group the scene loader refuses is refused here too (by its field).
        scene["bond_groups"] = serde_json::to_value(with.bond_groups()).unwrap();
        scene["bond_groups"][0]["elements"] = serde_json::json!(9);
        write(&scene);
        let e = model_from_specimen(&path).unwrap_err().to_string();
        assert!(e.contains("elements"), "{e}");
        // The scene is read as a typed scene file (issue 49: it was read field by field from
        // untyped JSON, so a misspelt key was ignored): the error names the file and the key.
        let mut typo =
            serde_json::to_value(specimen::io::example_scene(&s, "si3n4", "s.json", 10)).unwrap();
        let kn = typo["bond_groups"][0]["kn"].take();
        typo["bond_groups"][0].as_object_mut().unwrap().remove("kn");
        typo["bond_groups"][0]["k_n"] = kn;
        write(&typo);
        let e = model_from_specimen(&path).unwrap_err().to_string();
        assert!(
            e.contains("s.scene.json: bond_groups[0]") && e.contains("k_n"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
