//! The specimen, material-model and output flags every lab test shares ([`LabArgs`], used with
//! `#[command(flatten)]` by `dem test ucs|brazilian|bending|senb|cutting` and `dem calibrate`).

use crate::specimen::{cover_lines, material_values, method_and_dist, parse_length, parse_stress};
use clap::Args;
use dem_lab::model::FlatJointOption;
use dem_lab::specimen::cache::TestSpecimen;
use dem_lab::specimen::{GrainMode, Method, SpecimenParams};
use dem_lab::{LabError, LabModel};
use std::path::{Path, PathBuf};

/// Specimen, material model and output flags shared by every test (the specimen flags are
/// those of `dem specimen`; the test sets the width and height).
#[derive(Args, Clone, Debug)]
pub struct LabArgs {
    /// traditional | orc | improved.
    #[arg(long, default_value = "traditional")]
    pub method: String,
    /// Smallest disc radius with unit (`0.175mm`; required to generate a specimen).
    #[arg(long)]
    pub r_min: Option<String>,
    /// Largest disc radius with unit (required to generate a specimen).
    #[arg(long)]
    pub r_max: Option<String>,
    /// Radius distribution: normal or uniform.
    #[arg(long, default_value = "normal")]
    pub dist: String,
    /// Random seed of the specimen.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Material file (data/materials/*.json): density, E and a tensile strength set the
    /// default micro-parameters (as `dem specimen`).
    #[arg(long)]
    pub material: Option<PathBuf>,
    /// Density (kg/m³), overriding the material file.
    #[arg(long)]
    pub density: Option<f64>,
    /// Young's modulus with unit (`310GPa`): E_c = Ē_c.
    #[arg(long)]
    pub youngs: Option<String>,
    /// Tensile strength with unit (`800MPa`): bond strengths σ̄c = c̄.
    #[arg(long)]
    pub tensile: Option<String>,
    /// Isotropic stress installed before bonding, with unit.
    #[arg(long)]
    pub iso_stress: Option<String>,
    /// Target 2D porosity of the initial packing.
    #[arg(long, default_value_t = 0.16)]
    pub porosity: f64,
    /// Mean equivalent grain diameter (ORC, improved), with unit.
    #[arg(long)]
    pub grain_size: Option<String>,
    /// Smallest template disc radius (improved), with unit.
    #[arg(long)]
    pub template_r_min: Option<String>,
    /// Largest number of discs per improved-ORC grain.
    #[arg(long, default_value_t = 9)]
    pub max_discs: usize,
    /// Which grains are irregular (orc, improved), as `dem specimen`: `all` (every cell of a
    /// Voronoi tessellation of --grain-size) or `few` (S0: a few synthetic grains in the
    /// traditional packing, as many as give S0's 1576/989 discs per packing disc).
    #[arg(long, default_value = "all")]
    pub irregular: String,
    /// With `--irregular few`: this many irregular grains instead of S0's disc ratio.
    #[arg(long)]
    pub irregular_count: Option<usize>,
    /// With `--irregular few`: equivalent diameter of the irregular grains, with unit;
    /// default --grain-size.
    #[arg(long)]
    pub irregular_size: Option<String>,
    /// With `--irregular few`, improved ORC: `affine` (default) or `servo`, as `dem specimen`.
    #[arg(long)]
    pub insertion: Option<String>,
    /// A LabModel JSON (density, thickness, r_mean, micro; `dem calibrate` writes one) whose
    /// micro-parameters the test runs with, instead of those of the specimen flags. The
    /// specimen geometry is still generated with the specimen flags.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Flat joints instead of parallel bonds: --flat-joint, --joint-friction,
    /// --joint-bonded-fraction.
    #[command(flatten)]
    pub joints: FlatJointArgs,
    /// Output folder: specimen file (reused when its parameters match), scene, run outputs
    /// and `<test>.result.json`.
    #[arg(long)]
    pub out: PathBuf,
    /// Worker threads, at least 1 (default: all cores); results do not depend on it.
    #[arg(long, value_parser = crate::parse_threads)]
    pub threads: Option<usize>,
    /// Safety factor of the automatic time step, in (0, 1] (default: the test's).
    #[arg(long)]
    pub dt_factor: Option<dem_lab::tests::harness::DtFactor>,
    /// Run even if the test's output folder is locked by a run of another scene or one still
    /// running (`run.lock`; a rerun of the same test is always allowed).
    #[arg(long)]
    pub force: bool,
    /// An improved-ORC grain whose template stops below its cover target is a failure (the
    /// test does not run; exit code 2) instead of a warning.
    #[arg(long)]
    pub strict: bool,
}

/// The density (kg/m³), Young's modulus and tensile strength (Pa) a specimen is built from,
/// when they come from somewhere other than the material flags (`dem test cutting
/// --specimen-from-model`: the model's), as numbers.
#[derive(Clone, Copy, Debug)]
pub struct Elastic {
    pub density: f64,
    pub youngs: f64,
    pub tensile: f64,
}

impl LabArgs {
    /// Specimen parameters for a `width × height` (m) box from the flags.
    pub fn specimen_params(&self, width: f64, height: f64) -> Result<SpecimenParams, String> {
        self.specimen_params_of(width, height, None)
    }

    /// [`LabArgs::specimen_params`] with the density and moduli of `elastic` instead of the
    /// material flags when it is given.
    pub fn specimen_params_of(
        &self,
        width: f64,
        height: f64,
        elastic: Option<Elastic>,
    ) -> Result<SpecimenParams, String> {
        let (method, dist) = method_and_dist(&self.method, &self.dist)?;
        let (density, e, tensile) = match elastic {
            Some(v) => (v.density, v.youngs, v.tensile),
            None => {
                let (_, density, e, tensile) = material_values(
                    self.material.as_ref(),
                    self.density,
                    self.youngs.as_deref(),
                    self.tensile.as_deref(),
                )?;
                (density, e, tensile)
            }
        };
        let radius = |v: &Option<String>, flag: &str| match v {
            Some(s) => parse_length(s, flag),
            None => Err(format!(
                "{flag} is required: the {} disc radius with unit (`0.175mm`)",
                if flag == "--r-min" {
                    "smallest"
                } else {
                    "largest"
                }
            )),
        };
        let mut p = SpecimenParams::new(
            method,
            width,
            height,
            radius(&self.r_min, "--r-min")?,
            radius(&self.r_max, "--r-max")?,
            density,
            e,
            tensile,
            self.seed,
        );
        p.distribution = dist;
        p.porosity = self.porosity;
        p.template_max_discs = self.max_discs;
        if let Some(s) = &self.iso_stress {
            p.iso_stress = parse_stress(s, "--iso-stress")?;
        }
        if let Some(s) = &self.grain_size {
            p.grain_size = parse_length(s, "--grain-size")?;
        }
        if let Some(s) = &self.template_r_min {
            p.template_r_min = parse_length(s, "--template-r-min")?;
        }
        p.grains = crate::specimen::grain_mode(
            &p,
            &self.irregular,
            self.irregular_count,
            self.irregular_size.as_deref(),
            self.insertion.as_deref(),
        )?;
        if p.method == Method::Traditional {
            // No irregular grains: the default mode keeps the parameters' JSON (and the keys
            // of cached specimens) as before.
            p.grains = GrainMode::All;
        }
        p.validate().map_err(|e| e.to_string())?;
        Ok(p)
    }

    /// The material model: `--model` if given, else the specimen's own; with --flat-joint,
    /// flat joints of those flags ([`FlatJointArgs::apply`]).
    pub fn lab_model(&self, p: &SpecimenParams) -> Result<LabModel, String> {
        let mut m = match &self.model {
            Some(path) => read_model(path)?,
            None => LabModel::from_params(p),
        };
        self.joints.apply(&mut m)?;
        Ok(m)
    }

    /// The thread pool of `--threads`.
    pub fn pool(&self) -> Result<rayon::ThreadPool, String> {
        rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.unwrap_or(0))
            .build()
            .map_err(|e| e.to_string())
    }
}

/// The flat-joint flags (Potyondy 2012, [`dem_core::bond::flat_joint`]) of every lab test
/// (through [`LabArgs`]), `dem calibrate` and `dem test cutting` (flattened into both), so
/// all of them read and check them in one place.
#[derive(Args, Clone, Debug, Default)]
pub struct FlatJointArgs {
    /// Flat joints of this many elements (1–8; Potyondy 2012) instead of parallel bonds in both
    /// bond groups, with the model's stiffness and strengths (docs/scene-schema.md).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=8))]
    pub flat_joint: Option<u8>,
    /// With --flat-joint: friction coefficient of the unbonded elements (default 0).
    #[arg(long, requires = "flat_joint")]
    pub joint_friction: Option<f64>,
    /// With --flat-joint: fraction of the elements bonded at installation, the rest slit
    /// (unbonded from the start), in [0, 1] (default 1).
    #[arg(long, requires = "flat_joint")]
    pub joint_bonded_fraction: Option<f64>,
}

impl FlatJointArgs {
    /// The option the flags give (`None` without --flat-joint): N elements, friction μ
    /// (default 0), bonded fraction φ_B (default 1), checked by
    /// [`FlatJointOption::check`] with the error naming the flag.
    pub fn option(&self) -> Result<Option<FlatJointOption>, String> {
        let Some(elements) = self.flat_joint else {
            return Ok(None);
        };
        let o = FlatJointOption {
            elements,
            friction: self.joint_friction.unwrap_or(0.0),
            bonded_fraction: self.joint_bonded_fraction.unwrap_or(1.0),
        };
        o.check().map_err(|(field, why)| {
            let flag = match field {
                "elements" => "--flat-joint",
                "friction" => "--joint-friction",
                _ => "--joint-bonded-fraction",
            };
            format!("{flag} {why}")
        })?;
        Ok(Some(o))
    }

    /// Puts the flags' option on `m`: the command line wins over a `flat_joint` record the
    /// model already has (from `--model`); without --flat-joint `m` is left as it is.
    pub fn apply(&self, m: &mut LabModel) -> Result<(), String> {
        if let Some(o) = self.option()? {
            m.flat_joint = Some(o);
        }
        Ok(())
    }
}

/// A `--model` file (a [`LabModel`] JSON, as `dem calibrate` writes it), its `flat_joint`
/// record checked ([`FlatJointOption::check`]); errors name `--model`, the file and the field.
pub fn read_model(path: &Path) -> Result<LabModel, String> {
    let text = clumpgen::io::read_input_string(path)
        .map_err(|e| format!("--model {}: {e}", path.display()))?;
    let m: LabModel =
        serde_json::from_str(&text).map_err(|e| format!("--model {}: {e}", path.display()))?;
    if let Some(o) = &m.flat_joint {
        o.check().map_err(|(field, why)| {
            format!("--model {}: flat_joint.{field} {why}", path.display())
        })?;
    }
    Ok(m)
}

/// With `--strict`, a specimen with grains below their cover target is an error naming them.
pub fn strict_cover(lab: &LabArgs, spec: &TestSpecimen) -> Result<(), LabError> {
    if !lab.strict || spec.below_cover.is_empty() {
        return Ok(());
    }
    Err(LabError::Param {
        field: "--strict".into(),
        reason: format!(
            "{} grains of the specimen are below their cover target; the test did not run \
             (leave out --strict to run it with a warning):\n  {}",
            spec.below_cover.len(),
            cover_lines(&spec.file, &spec.below_cover).join("\n  ")
        ),
    })
}
