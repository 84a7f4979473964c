//! `dem test cutting`: orthogonal cutting of a specimen (`docs/cutting.md`). The specimen is a
//! file written by `dem specimen` (its summary and scene beside it give the micro-parameters),
//! the scene is written to the output folder as a plain file (`dem run` re-runs it), run, and
//! analysed: peak and mean main and vertical force over the steady window, chips, broken
//! bonds, machined surface, residual cracks.

use crate::lab_args::{read_model, Elastic, LabArgs};
use crate::progress::Progress;
use crate::specimen::{parse_length, read_material};
use clap::Args;
use dem_lab::cutting::tool::ToolModel;
use dem_lab::cutting::{self, CheckedTest, CuttingResult, CuttingTest, Inputs, INPUTS_FILE};
use dem_lab::specimen::{io, SpecimenParams};
use dem_lab::LabModel;
use std::path::PathBuf;
use std::process::ExitCode;

/// `dem test cutting` flags. Lengths take a unit suffix (`1mm`, `10mm`, `0.5um`, `1e-3m`);
/// the speed is in m/s (`1`, `2`, or `1m/s`); angles in degrees.
#[derive(Args, Clone, Debug)]
pub struct CuttingArgs {
    /// Specimen file written by `dem specimen` (`<stem>.summary.json` and `<stem>.scene.json`
    /// beside it give the model unless --model is given). Without it a specimen is generated
    /// from the specimen flags below into `<out>/specimen.json`.
    #[arg(long)]
    pub specimen: Option<PathBuf>,
    /// Generation: specimen width with unit.
    #[arg(long, default_value = "20mm")]
    pub width: String,
    /// Generation: specimen height with unit.
    #[arg(long, default_value = "10mm")]
    pub height: String,
    /// Generation: build the specimen with --model's density and micro-parameters (E = its
    /// contact modulus, σ_t = its grain-boundary tensile strength, σ0 = 1 % of σ_t) instead of
    /// a material's, and run with the model's r_mean set to the specimen's (r_min + r_max)/2
    /// (bond stiffness k̄_n = Ē_c/(2r̄) follows the radii), as validation's Table 2 does.
    /// Needs --model; --material, --density, --youngs and --tensile are refused with it.
    #[arg(long)]
    pub specimen_from_model: bool,
    /// A CuttingTest JSON (all fields optional, SI units, see docs/cutting.md); the flags
    /// below override it.
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Depth of cut a_p with unit (default 1mm).
    #[arg(long)]
    pub depth: Option<String>,
    /// Cutting speed in m/s (default 1).
    #[arg(long)]
    pub speed: Option<String>,
    /// Cut length L with unit (default 10mm).
    #[arg(long)]
    pub length: Option<String>,
    /// Rake angle in degrees (default 0; positive leans the rake face back).
    #[arg(long)]
    pub rake_angle: Option<f64>,
    /// Clearance angle in degrees (default 7).
    #[arg(long)]
    pub clearance_angle: Option<f64>,
    /// Tool model: rigid (default: one polyline body, one contact per disc, PFC's series
    /// stiffness for tool and slot walls) | segments (the earlier two separate faces, direct
    /// stiffness).
    #[arg(long)]
    pub tool: Option<String>,
    /// Cutting-edge radius of the rigid tool with unit (default 0: sharp).
    #[arg(long)]
    pub edge_radius: Option<String>,
    /// Tool stiffness as a multiple of the disc's (PFC's wall/ball ratio with the rigid tool,
    /// default 10).
    #[arg(long)]
    pub tool_stiffness: Option<f64>,
    /// Critical damping ratio of viscous disc-disc contact dashpots (default 0: none).
    #[arg(long)]
    pub contact_damping: Option<f64>,
    /// Tool-disc friction coefficient (default 0).
    #[arg(long)]
    pub tool_friction: Option<f64>,
    /// Selective mass scaling before the cut: make the lightest discs heavier until none sets
    /// a step below the largest one whose added mass and added spin inertia stay within this
    /// fraction of the discs' totals (e.g. 0.02; default 0: none). Reported in the result's
    /// `run.mass_scaling` (docs/cutting.md, "Mass scaling").
    #[arg(long)]
    pub mass_scaling: Option<f64>,
    /// PFC local damping α (default 0.7, PFC's default; 0 = undamped).
    #[arg(long)]
    pub local_damping: Option<f64>,
    /// Frame of reference of the local damping: fragment (default: the motion relative to the
    /// disc's bonded fragment, no drag on rigid motion; docs/cutting.md, "Damping and the frame
    /// of reference") | lab (PFC: each disc's own velocity; drags debris in steady motion)
    #[arg(long)]
    pub damping_frame: Option<String>,
    /// Frame of reference of the run: lab (default: the tool moves at v) | tool (the tool at
    /// rest, the specimen and slot walls moving at −v; the Galilean check)
    #[arg(long)]
    pub frame: Option<String>,
    /// Start of the steady window as a multiple of a_p (default 2).
    #[arg(long)]
    pub window_start: Option<f64>,
    /// Target number of history rows (default 4000).
    #[arg(long)]
    pub history_rows: Option<u64>,
    /// VTK snapshots spread evenly over the cut's duration, the first at the start and the
    /// last at the end (default 0: none).
    #[arg(long)]
    pub snapshots: Option<u64>,
    /// Delete detached fragments once they are above the nominal surface and clear of the
    /// tool and the workpiece (checked on every history row; docs/cutting.md, "Deleting
    /// fragments").
    #[arg(long)]
    pub delete_fragments: bool,
    /// Run the cut a `cutting.inputs.json` describes (the generated specimen's parameters, the
    /// model and the test, as a cut writes them into its folder) in place of the specimen,
    /// model and test flags: a cut run again from its folder, or planned as typed values (the
    /// report's runs are `dem sweep` cases of this flag). Its specimen is generated (not a
    /// `--specimen` file) and its model given.
    #[arg(long, value_name = "FILE", conflicts_with_all = [
        "specimen", "specimen_from_model", "params", "depth", "speed", "length", "rake_angle",
        "clearance_angle", "tool", "edge_radius", "tool_stiffness", "contact_damping",
        "tool_friction", "mass_scaling", "local_damping", "damping_frame", "frame",
        "window_start", "history_rows", "snapshots", "delete_fragments", "method", "r_min",
        "r_max", "seed", "model", "material", "dt_factor", "grain_size", "porosity",
        "flat_joint", "joint_friction", "joint_bonded_fraction",
    ])]
    pub inputs: Option<PathBuf>,
    /// Resolve the specimen parameters, model and test, write them to
    /// `<out>/cutting.inputs.json` and print them; generate and run nothing.
    #[arg(long)]
    pub dry_run: bool,
    /// Generation: reuse the specimen of the same parameters from this folder if one was
    /// generated there before (a sub-folder per parameter hash), and keep a newly generated one
    /// there. `dem sweep run` passes `DIR/specimens`, so a study's cases of one seed generate
    /// their specimen once (generation is deterministic: the files are the same bytes).
    #[arg(long)]
    pub specimen_cache: Option<PathBuf>,
    /// The specimen flags (used without --specimen), the material model (`--model`: a LabModel
    /// JSON, `dem calibrate` writes one, run with instead of the specimen's own
    /// micro-parameters; its `flat_joint` record is kept, --flat-joint wins over it), the
    /// safety factor of the time step (`--dt-factor`, default 0.3), and `--out` (the output
    /// folder: cutting.inputs.json, cutting.scene.json, the run's outputs, cutting.forces.csv,
    /// cutting.result.json), `--threads`, `--force`, `--strict`: those of every lab test.
    #[command(
        flatten,
        next_help_heading = "Specimen, model and run (every lab test's flags)"
    )]
    pub lab: LabArgs,
}

/// The files of a generated specimen, as `<out>/` holds them and the cache keeps them.
const SPECIMEN_FILES: [&str; 3] = [
    "specimen.json",
    "specimen.summary.json",
    "specimen.scene.json",
];

impl CuttingArgs {
    /// The test: `--params` file (or the defaults), then the flags; validated once, here.
    pub fn test(&self) -> Result<CheckedTest, String> {
        let mut t = match &self.params {
            Some(p) => {
                let text = clumpgen::io::read_input_string(p)
                    .map_err(|e| format!("{}: {e}", p.display()))?;
                CuttingTest::from_params(&text).map_err(|e| format!("{}: {e}", p.display()))?
            }
            None => CuttingTest::default(),
        };
        if let Some(s) = &self.tool {
            t.tool = match s.as_str() {
                "rigid" => ToolModel::Rigid,
                "segments" => ToolModel::Segments,
                _ => return Err(format!("--tool: {s:?} is not rigid or segments")),
            };
        }
        if let Some(v) = self.contact_damping {
            t.contact_damping = v;
        }
        if let Some(v) = self.mass_scaling {
            t.mass_scaling = v;
        }
        if let Some(s) = &self.depth {
            t.depth = parse_length(s, "--depth")?;
        }
        if let Some(s) = &self.speed {
            t.speed = crate::specimen::parse_speed(s, "--speed")?;
        }
        if let Some(s) = &self.length {
            t.length = parse_length(s, "--length")?;
        }
        if let Some(a) = self.rake_angle {
            t.rake_angle = a.to_radians();
        }
        if let Some(a) = self.clearance_angle {
            t.clearance_angle = a.to_radians();
        }
        if let Some(v) = self.tool_stiffness {
            t.tool_stiffness = v;
        }
        if let Some(v) = self.tool_friction {
            t.tool_friction = v;
        }
        if let Some(v) = self.lab.dt_factor {
            t.dt_factor = v;
        }
        if let Some(v) = self.local_damping {
            t.local_damping = v;
        }
        if let Some(s) = &self.damping_frame {
            t.damping_frame = s.parse().map_err(|e| format!("--damping-frame: {e}"))?;
        }
        if let Some(s) = &self.frame {
            t.frame = match s.as_str() {
                "lab" => cutting::CutFrame::Lab,
                "tool" => cutting::CutFrame::Tool,
                _ => return Err(format!("--frame: {s:?} is not lab or tool")),
            };
        }
        if let Some(v) = self.window_start {
            t.window_start = v;
        }
        if let Some(v) = self.history_rows {
            t.history_rows = v;
        }
        if let Some(v) = self.snapshots {
            t.snapshots = v;
        }
        // After --depth: the test stores the radius as a multiple of a_p.
        if let Some(s) = &self.edge_radius {
            t.edge_radius = parse_length(s, "--edge-radius")? / t.depth;
        }
        if self.delete_fragments {
            t.delete_fragments = true;
        }
        t.check().map_err(|e| e.to_string())
    }

    /// [`cutting::check_geometry`] with the error naming the flag and its value (or where
    /// the value came from: `--params` or the default) and the specimen `what`.
    fn check_geometry(
        &self,
        test: &CuttingTest,
        extent: [f64; 4],
        what: &str,
    ) -> Result<(), String> {
        cutting::check_geometry(test, extent).map_err(|e| match e {
            dem_lab::LabError::Param { field, reason } => {
                let (given, value) = match field.as_str() {
                    "length" => (&self.length, test.length),
                    "depth" => (&self.depth, test.depth),
                    _ => return format!("{what}: {reason}"),
                };
                let flag = match (given, &self.params) {
                    (Some(v), _) => format!("--{field} {v}"),
                    (None, Some(p)) => format!(
                        "--{field} ({} mm, from --params {} or the default)",
                        cutting::mm(value),
                        p.display()
                    ),
                    (None, None) => format!("--{field} (default {}mm)", cutting::mm(value)),
                };
                format!("{flag}: {reason} ({what})")
            }
            e => e.to_string(),
        })
    }

    /// The `--model` file, if given, as it is (its `flat_joint` record checked, not yet
    /// overridden by --flat-joint: see [`CuttingArgs::with_joints`]).
    pub fn model_file(&self) -> Result<Option<LabModel>, String> {
        self.lab.model.as_deref().map(read_model).transpose()
    }

    /// `m` with the flat-joint flags applied ([`crate::lab_args::FlatJointArgs::apply`]):
    /// with --flat-joint the cut runs with those flat joints whatever the model said (a
    /// `flat_joint` record of --model, or of the specimen's scene:
    /// [`cutting::model_from_specimen`]); without it the model's own choice stays. Every path
    /// to the cut's model goes through here.
    pub fn with_joints(&self, mut m: LabModel) -> Result<LabModel, String> {
        self.lab.joints.apply(&mut m)?;
        Ok(m)
    }

    /// The parameters of the specimen to generate (without --specimen): the specimen flags,
    /// `--irregular` (a traditional specimen keeps the default grain mode: it has no irregular
    /// grains) and, with --specimen-from-model, the model's micro-parameters.
    pub fn specimen_params(&self, model: Option<&LabModel>) -> Result<SpecimenParams, String> {
        let lab = &self.lab;
        for (v, f) in [(&lab.r_min, "--r-min"), (&lab.r_max, "--r-max")] {
            if v.is_none() {
                return Err(format!(
                    "give --specimen, or {f} (and the other specimen flags)"
                ));
            }
        }
        // With --specimen-from-model, the model's density and moduli, as typed values.
        let from_model = match (self.specimen_from_model, model) {
            (false, _) => None,
            (true, None) => return Err("--specimen-from-model needs --model".to_string()),
            (true, Some(m)) => {
                for (given, flag) in [
                    (lab.material.is_some(), "--material"),
                    (lab.density.is_some(), "--density"),
                    (lab.youngs.is_some(), "--youngs"),
                    (lab.tensile.is_some(), "--tensile"),
                ] {
                    if given {
                        return Err(format!(
                            "{flag}: --specimen-from-model takes the density and moduli from \
                             --model; leave {flag} out"
                        ));
                    }
                }
                Some(Elastic {
                    density: m.density,
                    youngs: m.micro.contact_modulus,
                    tensile: m.micro.boundary_tensile,
                })
            }
        };
        let w = parse_length(&self.width, "--width")?;
        let h = parse_length(&self.height, "--height")?;
        let mut p = lab.specimen_params_of(w, h, from_model)?;
        if let (true, Some(m)) = (self.specimen_from_model, model) {
            p.micro = m.micro.clone();
        }
        p.validate().map_err(|e| e.to_string())?;
        crate::specimen::check_resolution(&p, &self.width, &self.height)?;
        Ok(p)
    }

    /// Generates the specimen of `p` into `<out>/specimen.json`, with its summary and scene
    /// beside it as `dem specimen` writes them.
    fn generate(&self, p: &SpecimenParams) -> Result<PathBuf, String> {
        let name = match (&self.lab.material, self.specimen_from_model) {
            (Some(m), false) => read_material(m)?.0,
            _ => dem_lab::specimen::DEFAULT_MATERIAL.to_string(),
        };
        std::fs::create_dir_all(&self.lab.out)
            .map_err(|e| format!("{}: {e}", self.lab.out.display()))?;
        let path = self.lab.out.join("specimen.json");
        let cached = self.specimen_cache.as_ref().map(|c| {
            let key = crate::run_lock::inputs_hash(&(p, &name));
            c.join(&key[..24])
        });
        if let Some(c) = cached
            .as_ref()
            .filter(|c| c.join(SPECIMEN_FILES[2]).is_file())
        {
            return self.copy_from_cache(c, &path);
        }
        println!(
            "generating a {} specimen {} x {} mm into {}",
            p.method.name(),
            p.width * 1e3,
            p.height * 1e3,
            path.display()
        );
        let bar = Progress::stages();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.lab.threads.unwrap_or(0))
            .build()
            .map_err(|e| e.to_string())?;
        let s = pool.install(|| {
            dem_lab::specimen::generate(p, &mut |pr| {
                bar.set_prefix(pr.stage);
                bar.set_fraction(pr.fraction);
            })
        });
        bar.finish_and_clear();
        let s = s.map_err(|e| e.to_string())?;
        self.check_cover(
            &path,
            crate::specimen::below_cover(&s.summary),
            "the specimen was not written and the cut did not run",
        )?;
        io::save(&s, &name, &path).map_err(|e| e.to_string())?;
        let scene = io::example_scene(&s, &name, "specimen.json", 1000);
        let text = serde_json::to_string_pretty(&scene).map_err(|e| e.to_string())?;
        io::write_atomic(&self.lab.out.join("specimen.scene.json"), &text)
            .map_err(|e| e.to_string())?;
        if let Some(c) = &cached {
            self.keep_in_cache(c)?;
        }
        Ok(path)
    }

    /// Copies the specimen files kept in the cache folder `c` into `<out>`; the grains below
    /// their cover target are read from the summary and reported (or refused with --strict) as
    /// for a generated specimen.
    fn copy_from_cache(
        &self,
        c: &std::path::Path,
        path: &std::path::Path,
    ) -> Result<PathBuf, String> {
        println!("specimen {} from the cache {}", path.display(), c.display());
        let mut summary = None;
        for f in SPECIMEN_FILES {
            let src = c.join(f);
            let text = clumpgen::io::read_input_string(&src)
                .map_err(|e| format!("{}: {e}", src.display()))?;
            io::write_atomic(&self.lab.out.join(f), &text).map_err(|e| e.to_string())?;
            if f == SPECIMEN_FILES[1] {
                let s: dem_lab::specimen::Summary =
                    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", src.display()))?;
                summary = Some(s);
            }
        }
        let below = summary
            .as_ref()
            .map_or(&[][..], crate::specimen::below_cover);
        self.check_cover(path, below, "the cut did not run")?;
        Ok(path.to_path_buf())
    }

    /// The grains of the specimen `path` below their cover target: refused with --strict (the
    /// error says what was `not_done`), else printed as warnings.
    fn check_cover(
        &self,
        path: &std::path::Path,
        below: &[dem_lab::specimen::improved::GrainCover],
        not_done: &str,
    ) -> Result<(), String> {
        if self.lab.strict && !below.is_empty() {
            return Err(format!(
                "--strict: {} grains of the specimen are below their cover target; {not_done} \
                 (leave out --strict to run it with a warning):\n  {}",
                below.len(),
                crate::specimen::cover_lines(path, below).join("\n  ")
            ));
        }
        crate::specimen::print_cover(path, below);
        Ok(())
    }

    /// Keeps the specimen files of `<out>` in the cache folder `c`: written into a private
    /// folder beside it, then renamed into place, so a reader never sees a partial entry; when
    /// another process put the same entry there first, its copy (the same bytes) stays.
    fn keep_in_cache(&self, c: &std::path::Path) -> Result<(), String> {
        let parent = c
            .parent()
            .ok_or("the specimen cache has no parent folder")?;
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
        let tmp = parent.join(format!(
            ".tmp-{}-{}",
            c.file_name().and_then(|n| n.to_str()).unwrap_or("entry"),
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&tmp);
        std::fs::create_dir_all(&tmp).map_err(|e| format!("{}: {e}", tmp.display()))?;
        for f in SPECIMEN_FILES {
            std::fs::copy(self.lab.out.join(f), tmp.join(f))
                .map_err(|e| format!("{}: {e}", tmp.join(f).display()))?;
        }
        if std::fs::rename(&tmp, c).is_err() {
            // Another process kept the same specimen first (or the entry is in place).
            let _ = std::fs::remove_dir_all(&tmp);
        }
        Ok(())
    }

    /// The inputs alone (the tests read them).
    #[cfg(test)]
    fn inputs(&self) -> Result<Inputs, String> {
        self.resolve().map(|(inputs, _)| inputs)
    }

    /// What the cut runs: the specimen (parameters, or the file), the model (`None` until a
    /// generated specimen's own model is known: no --model), the flat-joint flags and the
    /// test; and the test checked (what the run takes). The model is --model with the
    /// flat-joint flags applied ([`Self::with_joints`]).
    fn resolve(&self) -> Result<(Inputs, CheckedTest), String> {
        if let Some(f) = &self.inputs {
            return read_inputs(f);
        }
        let test = self.test()?;
        let flat_joint = self.lab.joints.option()?;
        let mut model = self
            .model_file()?
            .map(|m| self.with_joints(m))
            .transpose()?;
        let specimen = match &self.specimen {
            Some(_) if self.specimen_from_model => {
                return Err(
                    "--specimen-from-model builds the specimen: leave out --specimen".to_string(),
                )
            }
            Some(_) => None,
            None => Some(self.specimen_params(model.as_ref())?),
        };
        if let (true, Some(m), Some(p)) = (self.specimen_from_model, model.as_mut(), &specimen) {
            m.r_mean = 0.5 * (p.r_min + p.r_max);
        }
        let inputs = Inputs {
            specimen,
            specimen_file: self.specimen.as_ref().map(|p| p.display().to_string()),
            model,
            flat_joint,
            test: test.test().clone(),
        };
        Ok((inputs, test))
    }
}

/// The inputs of `--inputs FILE`, checked: a generated specimen's parameters, a model and the
/// test (the errors name the file and field).
fn read_inputs(f: &std::path::Path) -> Result<(Inputs, CheckedTest), String> {
    let text =
        clumpgen::io::read_input_string(f).map_err(|e| format!("--inputs {}: {e}", f.display()))?;
    let de = &mut serde_json::Deserializer::from_str(&text);
    let i: Inputs = serde_path_to_error::deserialize(de).map_err(|e| {
        format!(
            "--inputs {}: field {}: {}",
            f.display(),
            e.path(),
            e.inner()
        )
    })?;
    let missing = |what: &str| format!("--inputs {}: field {what} is null: give it", f.display());
    let p = i.specimen.as_ref().ok_or_else(|| missing("specimen"))?;
    if i.specimen_file.is_some() {
        return Err(format!(
            "--inputs {}: field specimen_file: a cut of a given specimen file runs with              --specimen; --inputs generates its specimen from field specimen",
            f.display()
        ));
    }
    i.model.as_ref().ok_or_else(|| missing("model"))?;
    p.validate()
        .map_err(|e| format!("--inputs {}: field specimen: {e}", f.display()))?;
    let test = i
        .test
        .clone()
        .check()
        .map_err(|e| format!("--inputs {}: field test: {e}", f.display()))?;
    Ok((i, test))
}

fn write_inputs(out: &std::path::Path, i: &Inputs) -> Result<String, String> {
    let text = serde_json::to_string_pretty(i).map_err(|e| e.to_string())? + "\n";
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    io::write_atomic(&out.join(INPUTS_FILE), &text).map_err(|e| e.to_string())?;
    Ok(text)
}

pub fn run(a: CuttingArgs) -> Result<ExitCode, String> {
    let (mut inputs, test) = a.resolve()?;
    if let Some(p) = &inputs.specimen {
        // The specimen to be generated: check the cut fits before generating it.
        let what = match &a.inputs {
            Some(f) => format!("the specimen of --inputs {}", f.display()),
            None => format!(
                "the specimen to be generated, --width {} --height {}",
                a.width, a.height
            ),
        };
        a.check_geometry(&test, [0.0, p.width, 0.0, p.height], &what)?;
    }
    // The folder's lock (`run_lock`), before anything is written into it: keyed on the
    // inputs as resolved from the flags, so a rerun (or the run after a --dry-run) of the same
    // cut is the same run.
    let _lock = crate::run_lock::acquire_noted(
        &a.lab.out,
        crate::run_lock::Claim {
            command: "dem test cutting",
            scene: &a.lab.out.join(cutting::SCENE_FILE),
            hash: &crate::run_lock::inputs_hash(&inputs),
        },
        a.lab.force,
    )?;
    let text = write_inputs(&a.lab.out, &inputs)?;
    if a.dry_run {
        print!("{text}");
        return Ok(ExitCode::SUCCESS);
    }
    let specimen = match (&inputs.specimen, &a.specimen) {
        (_, Some(f)) => f.clone(),
        (Some(p), None) => a.generate(p)?,
        (None, None) => return Err("give --specimen, or the specimen flags".into()),
    };
    let info = cutting::SpecimenInfo::read(&specimen).map_err(|e| e.to_string())?;
    a.check_geometry(
        &test,
        info.extent,
        &format!("specimen {}", specimen.display()),
    )?;
    let model = match inputs.model.clone() {
        Some(m) => m,
        None => {
            // The specimen's own model (its files carry a flat joint only if its scene names
            // one; `dem specimen` writes parallel bonds): --flat-joint wins over it.
            let m = cutting::model_from_specimen(&specimen).map_err(|e| e.to_string())?;
            let m = a.with_joints(m)?;
            inputs.model = Some(m.clone());
            write_inputs(&a.lab.out, &inputs)?;
            m
        }
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.lab.threads.unwrap_or(0))
        .build()
        .map_err(|e| e.to_string())?;
    println!(
        "cutting {}: a_p {} mm, v {} m/s, L {} mm, rake {}°, clearance {}°, tool {} ({}), local damping {} ({} frame), contact damping {}, dt factor {}{}",
        specimen.display(),
        test.depth * 1e3,
        test.speed,
        test.length * 1e3,
        test.rake_angle.to_degrees(),
        test.clearance_angle.to_degrees(),
        match test.tool {
            ToolModel::Rigid => "rigid",
            ToolModel::Segments => "segments",
        },
        match test.tool {
            ToolModel::Rigid => format!(
                "{}× the ball stiffness in series: contact {:.3}× k_n",
                test.tool_stiffness,
                2.0 * test.tool_stiffness / (1.0 + test.tool_stiffness)
            ),
            ToolModel::Segments => format!("{}× k_n", test.tool_stiffness),
        },
        test.local_damping,
        test.damping_frame.name(),
        test.contact_damping,
        test.dt_factor,
        match test.frame {
            cutting::CutFrame::Lab => "",
            cutting::CutFrame::Tool => ", run in the tool's frame",
        }
    );
    if let Some(f) = &model.flat_joint {
        println!(
            "bonds: flat joints (Potyondy 2012) of {} elements, friction {}, bonded fraction {}",
            f.elements, f.friction, f.bonded_fraction
        );
    }
    let bar = Progress::counted(1, "steps");
    bar.set_prefix("cutting");
    let r = pool.install(|| {
        let ro = cutting::CuttingRunOptions {
            on_resume: Some(|at| match at {
                Some((ckpt, step)) => println!(
                    "resuming the interrupted run of this cut from {} (step {step})",
                    ckpt.display()
                ),
                None => println!("that checkpoint does not load: starting the cut afresh"),
            }),
            ..cutting::CuttingRunOptions::default()
        };
        cutting::run_with(&test, &model, &info, &a.lab.out, &ro, &mut |done, total| {
            bar.set_length(total.max(1));
            bar.set_position(done);
        })
    });
    bar.finish_and_clear();
    let r = r.map_err(|e| e.to_string())?;
    print!("{}", report(&r));
    Ok(ExitCode::SUCCESS)
}

/// The printed summary of a cut.
pub fn report(r: &CuttingResult) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let kn = 1e-3;
    let (m, v) = (&r.main_force, &r.vertical_force);
    let _ = writeln!(
        s,
        "  discs {}, thickness {} m (forces for this thickness)",
        r.discs, r.thickness
    );
    let _ = writeln!(
        s,
        "  steady window      travel {:.3}-{:.3} mm ({} rows)",
        r.window[0] * 1e3,
        r.window[1] * 1e3,
        m.samples
    );
    let _ = writeln!(
        s,
        "  main force (kN)    peak {:.4}  mean {:.4}  sd {:.4}",
        m.peak * kn,
        m.mean * kn,
        m.sd * kn
    );
    if let Some(t) = r.touching {
        let _ = writeln!(
            s,
            "  tool touching      {:.0} % of the window's rows{}",
            100.0 * t,
            if t < 0.2 {
                " (a train of strikes: the mean rests on few of them; a longer cut averages more)"
            } else {
                ""
            }
        );
    }
    let _ = writeln!(
        s,
        "  vertical force (kN) peak {:.4}  mean {:.4}  sd {:.4}",
        v.peak * kn,
        v.mean * kn,
        v.sd * kn
    );
    let c = &r.chips;
    let _ = writeln!(
        s,
        "  chips              {} ({} discs, {:.4e} kg; largest {} discs); loose below surface {} ({} discs)",
        c.chips.count,
        c.chips.discs,
        c.chips.mass,
        c.chips.largest_discs,
        c.loose_below_surface.count,
        c.loose_below_surface.discs
    );
    if let Some(m) = &r.removal {
        let _ = writeln!(
            s,
            "  removal mode       {:.0} % of chip discs in single-grain chips, {:.0} % in chips of ≤ {} grains (largest {}); chip speed mean {:.3} m/s, max {:.3} m/s (tool {} m/s)",
            100.0 * m.single_grain_share,
            100.0 * m.small_chip_share,
            dem_lab::cutting::removal::SMALL_CHIP_GRAINS,
            m.largest_chip_grains,
            m.chip_speed_mean,
            m.chip_speed_max,
            m.tool_speed
        );
    }
    for b in &r.broken_bonds {
        let _ = write!(
            s,
            "  broken {:<12} {} tension, {} shear (of {})",
            b.group, b.tension, b.shear, b.total
        );
        // Flat joints: an interface is broken when its cement is all gone.
        if let (Some(p), Some(e), Some(eb)) = (
            b.partly_broken,
            b.elements_broken,
            b.elements_bonded.filter(|&n| n > 0),
        ) {
            let _ = write!(
                s,
                " flat-joint interfaces; {p} partly broken, {e} of {eb} bonded elements broken"
            );
            if let Some(n) = b.slit.filter(|&n| n > 0) {
                let _ = write!(s, ", {n} interfaces slit from the start");
            }
        }
        s.push('\n');
    }
    if let Some(f) = &r.surface {
        // Depth and roughness apart (issue 48: Ra was measured from the nominal line, so a
        // uniform undercut read as roughness): the depth against the cut line, then Ra and Rz
        // on the profile's mean line (ISO 4287; dem-lab/src/cutting/surface.rs).
        let _ = write!(
            s,
            "  surface            {:+.1} µm from the nominal cut line (mean; {:+.1} to {:+.1})",
            f.mean_deviation * 1e6,
            f.min_deviation * 1e6,
            f.max_deviation * 1e6,
        );
        if let Some(m) = f.roughness() {
            let _ = write!(
                s,
                "; on its mean line Ra {:.1} µm, Rz {:.1} µm",
                m.ra * 1e6,
                m.rz * 1e6
            );
        }
        let _ = writeln!(
            s,
            " ({} bins of {:.4} mm)",
            f.profile.len(),
            f.bin_width * 1e3
        );
    }
    if let Some(d) = &r.deleted {
        let _ = writeln!(
            s,
            "  deleted fragments  {} ({} discs, {} bonds, {:.4e} kg; kinetic {:.4e} J, all {:.4e} J; checked every {} steps)",
            d.fragments, d.discs, d.bonds, d.mass, d.kinetic_energy, d.energy, d.check_every
        );
    }
    let k = &r.residual_cracks;
    let _ = writeln!(
        s,
        "  residual cracks    {} below the surface ({} within the cut), deepest {:.4} mm",
        k.count,
        k.within_cut,
        k.deepest * 1e3
    );
    let u = &r.run;
    let _ = writeln!(
        s,
        "  run                {} steps, dt {:.4e} s ({:.4e}-{:.4e}), {:.1} s wall, {} threads, energy balance {:.2e} (max in window {:.2e})",
        u.steps, u.dt, u.dt_min, u.dt_max, u.wall_time_s, u.threads, u.balance_error_final,
        u.balance_error_max_abs
    );
    if let Some(ms) = &u.mass_scaling {
        let _ = writeln!(
            s,
            "  mass scaling       budget {}: critical dt {:.4e} -> {:.4e} s; {} discs heavier (+{:.3} % mass), {} with more inertia (+{:.3} % spin inertia)",
            ms.budget,
            ms.critical_dt_before,
            ms.critical_dt_after,
            ms.discs_mass,
            100.0 * ms.added_mass_fraction,
            ms.discs_inertia,
            100.0 * ms.added_inertia_fraction
        );
    }
    for f in &r.files {
        let _ = writeln!(s, "  file {f}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;
    use dem_lab::model::FlatJointOption;

    #[derive(Parser)]
    struct Cmd {
        #[command(flatten)]
        a: CuttingArgs,
    }

    fn args(extra: &[&str]) -> Result<CuttingArgs, clap::Error> {
        let material = concat!(env!("CARGO_MANIFEST_DIR"), "/../data/materials/si3n4.json");
        let mut v = vec!["cutting", "--out", "unused-out", "--r-min", "0.1mm"];
        v.extend_from_slice(&["--r-max", "0.16mm"]);
        if !extra.contains(&"--specimen-from-model") {
            // (--specimen-from-model takes the density and moduli from --model.)
            v.extend_from_slice(&["--material", material]);
        }
        v.extend_from_slice(extra);
        Cmd::try_parse_from(v).map(|c| c.a)
    }

    fn model_file(dir: &std::path::Path, fj: Option<FlatJointOption>) -> String {
        let p = SpecimenParams::new(
            dem_lab::specimen::Method::Traditional,
            20e-3,
            10e-3,
            0.175e-3,
            0.285e-3,
            3200.0,
            310e9,
            800e6,
            1,
        );
        let m = LabModel {
            flat_joint: fj,
            ..LabModel::from_params(&p)
        };
        let name = format!("model-{}.json", fj.map_or(0, |f| f.elements));
        let f = dir.join(name);
        std::fs::write(&f, serde_json::to_string(&m).unwrap()).unwrap();
        f.display().to_string()
    }

    /// The flat-joint option reaches the cut's model on every path: the flags alone (the
    /// inputs carry them until the specimen's own model is read, which `with_joints` then
    /// changes), a --model's `flat_joint` record (kept, also with --specimen-from-model), and
    /// the flags over such a record. Without them nothing changes (no `flat_joint` key).
    #[test]
    fn the_flat_joint_option_survives_every_model_path() {
        let dir = std::env::temp_dir().join(format!("dem-cut-fj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let four = FlatJointOption {
            elements: 4,
            friction: 0.5,
            bonded_fraction: 1.0,
        };
        let record = model_file(&dir, Some(four));
        let plain = model_file(&dir, None);

        // No flags, no model: nothing about flat joints in the inputs.
        let a = args(&[]).unwrap();
        let i = a.inputs().unwrap();
        assert!(i.flat_joint.is_none() && i.model.is_none());
        assert!(!serde_json::to_string(&i).unwrap().contains("flat_joint"));

        // The flags alone: in the inputs, and put on the specimen's own model when read.
        let a = args(&["--flat-joint", "2", "--joint-friction", "0.3"]).unwrap();
        let i = a.inputs().unwrap();
        let two = FlatJointOption {
            elements: 2,
            friction: 0.3,
            bonded_fraction: 1.0,
        };
        assert_eq!(i.flat_joint, Some(two));
        let own = LabModel::from_params(i.specimen.as_ref().unwrap());
        assert_eq!(own.flat_joint, None);
        assert_eq!(a.with_joints(own).unwrap().flat_joint, Some(two));

        // A --model with a flat_joint record, also with --specimen-from-model.
        for extra in [&[][..], &["--specimen-from-model"][..]] {
            let mut v = vec!["--model", record.as_str()];
            v.extend_from_slice(extra);
            let i = args(&v).unwrap().inputs().unwrap();
            assert_eq!(i.model.unwrap().flat_joint, Some(four), "{extra:?}");
            assert_eq!(i.flat_joint, None);
        }
        // The flags win over the record, and put flat joints on a model without one.
        for m in [&record, &plain] {
            let i = args(&[
                "--model",
                m.as_str(),
                "--flat-joint",
                "2",
                "--joint-friction",
                "0.3",
            ])
            .unwrap()
            .inputs()
            .unwrap();
            assert_eq!(i.model.unwrap().flat_joint, Some(two), "{m}");
        }
        // A --model without a record stays parallel bonds.
        let i = args(&["--model", &plain]).unwrap().inputs().unwrap();
        assert_eq!(i.model.unwrap().flat_joint, None);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// `--damping-frame` and `--frame` reach the test (the damping frame's default is
    /// `fragment`, the run frame's `lab`); bad values name the flag, and the tool frame refuses
    /// fragment deletion (its rules are the lab frame's).
    #[test]
    fn damping_and_run_frames_reach_the_test() {
        let t = args(&["--damping-frame", "fragment", "--frame", "tool"])
            .unwrap()
            .test()
            .unwrap();
        assert_eq!(t.damping_frame, dem_core::DampingFrame::Fragment);
        assert_eq!(t.frame, cutting::CutFrame::Tool);
        let d = args(&[]).unwrap().test().unwrap();
        assert!(d.damping_frame == dem_core::DampingFrame::Fragment && d.frame.is_lab());
        let l = args(&["--damping-frame", "lab"]).unwrap().test().unwrap();
        assert!(l.damping_frame.is_lab());
        let e = args(&["--damping-frame", "relative"])
            .unwrap()
            .test()
            .unwrap_err();
        assert!(e.starts_with("--damping-frame: \"relative\""), "{e}");
        let e = args(&["--frame", "wheel"]).unwrap().test().unwrap_err();
        assert!(e.starts_with("--frame: \"wheel\""), "{e}");
        let e = args(&["--frame", "tool", "--delete-fragments"])
            .unwrap()
            .test()
            .unwrap_err();
        assert!(e.starts_with("frame: the tool frame"), "{e}");
    }

    /// Bad flat-joint values are errors naming the flag (or the model file's field), checked
    /// as the other lab tests check them.
    #[test]
    fn bad_flat_joint_values_name_the_flag() {
        let e = |v: &[&str]| args(v).unwrap().inputs().unwrap_err();
        let t = e(&["--flat-joint", "2", "--joint-friction=-1"]);
        assert!(t.starts_with("--joint-friction -1"), "{t}");
        let t = e(&["--flat-joint", "2", "--joint-bonded-fraction", "1.5"]);
        assert!(t.starts_with("--joint-bonded-fraction 1.5"), "{t}");
        for bad in [&["--flat-joint", "9"][..], &["--joint-friction", "0.5"][..]] {
            assert!(args(bad).is_err(), "{bad:?}");
        }
        let dir = std::env::temp_dir().join(format!("dem-cut-fj-bad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = model_file(
            &dir,
            Some(FlatJointOption {
                elements: 2,
                friction: -0.5,
                bonded_fraction: 1.0,
            }),
        );
        let t = e(&["--model", &f]);
        assert!(
            t.contains("--model") && t.contains("flat_joint.friction -0.5"),
            "{t}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
