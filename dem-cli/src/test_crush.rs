//! `dem test crush`: one lattice grain crushed between two platens (docs/lattice.md §4,
//! `dem_lab::crushing::grain`). The grain is a lattice template (`--template`) or an outline made
//! into one here (`--outline` with `--spacing`, as `dem clump --method lattice`).

use crate::progress::Progress;
use crate::specimen::{parse_length, parse_stress};
use clap::Args;
use clumpgen::clump::LatticeParams;
use clumpgen::{make_template, ClumpParams, Method, ReadOptions};
use dem_lab::crushing::grain::{self, CrushTest, LinkCriterion};
use dem_lab::LabError;
use std::path::PathBuf;
use std::process::ExitCode;

/// `dem test crush` flags.
#[derive(Args)]
pub struct CrushArgs {
    /// A lattice template (`clumpgen.template/2`, from `dem clump --method lattice`).
    #[arg(long)]
    pub template: Option<PathBuf>,
    /// An outline file (as `dem clump` reads them), filled with a lattice of --spacing.
    #[arg(long)]
    pub outline: Option<PathBuf>,
    /// Lattice spacing S for --outline: a fraction of the grain's equivalent radius (`0.18`)
    /// or a length (`0.2mm`).
    #[arg(long)]
    pub spacing: Option<String>,
    /// Node radius as a fraction of S/2 for --outline, in (0, 1]; below 1 neighbours do not
    /// touch, so an intact link acts alone (docs/lattice.md §4).
    #[arg(long, default_value_t = 0.9)]
    pub node_radius: f64,
    /// Disc thickness t for --outline, with unit (a template keeps its own).
    #[arg(long, default_value = "1m")]
    pub thickness: String,
    #[command(flatten)]
    pub material: GrainMaterialArgs,
    /// Link breakage criterion: force, stress, strain or energy (each needs its parameter
    /// flag).
    #[arg(long)]
    pub criterion: String,
    /// force: a link's tensile strength (N).
    #[arg(long)]
    pub link_force: Option<f64>,
    /// strain: a link's tensile strain at failure.
    #[arg(long)]
    pub link_strain: Option<f64>,
    /// stress: a link's tensile strength as a stress, with unit (`50MPa`), on the area of the
    /// cell edge it crosses, (S/√3)·t.
    #[arg(long)]
    pub link_stress: Option<String>,
    /// force, stress, strain: the shear strength (N), shear stress (Pa) or shear strain;
    /// default the tensile one.
    #[arg(long)]
    pub link_shear: Option<f64>,
    /// energy: the material's fracture energy G_c (J/m²).
    #[arg(long)]
    pub fracture_energy: Option<f64>,
    /// Node–node friction coefficient.
    #[arg(long, default_value_t = 0.5)]
    pub friction: f64,
    /// Node–platen friction coefficient.
    #[arg(long, default_value_t = 0.5)]
    pub platen_friction: f64,
    /// Rotation of the grain before loading along y, degrees CCW.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub angle: f64,
    /// Stage 1 (first major breakage) ends when the largest fragment holds less than this
    /// fraction of the grain's mass.
    #[arg(long, default_value_t = 0.9)]
    pub major: f64,
    /// Stage 1's cap: a platen closure of this fraction of the grain's size d.
    #[arg(long, default_value_t = 0.2)]
    pub max_closure: f64,
    /// Stage 2 loads on to this multiple of stage 1's platen closure.
    #[arg(long, default_value_t = 2.0)]
    pub stage2_travel: f64,
    /// Platen speed (each) with unit, e.g. `0.01m/s`; default the quasi-static rule.
    #[arg(long)]
    pub speed: Option<String>,
    /// Safety factor of the automatic time step, in (0, 1] (default 0.3).
    #[arg(long)]
    pub dt_factor: Option<dem_lab::tests::harness::DtFactor>,
    #[command(flatten)]
    pub folder: RunFolderArgs,
}

/// The run-folder flags of `dem test crush` and `dem test column`.
#[derive(Args)]
pub struct RunFolderArgs {
    /// Output folder: the grain template(s), the scenes, run outputs, the CSVs (crush:
    /// `crush.force.csv`, `crush.breaks.csv`; column: `column.stress_strain.csv`,
    /// `column.gradings.csv`, `column.breaks.csv`) and `<name>.result.json`.
    #[arg(long)]
    pub out: PathBuf,
    /// Take the output folder even if another run holds it or held it for other inputs
    /// (`<out>/<name>.out/run.lock`).
    #[arg(long)]
    pub force: bool,
    /// Worker threads, at least 1 (default: all cores); results do not depend on it.
    #[arg(long, value_parser = crate::parse_threads)]
    pub threads: Option<usize>,
}

impl RunFolderArgs {
    /// The run of test `name` (`command`, e.g. `dem test crush`) in this folder, locked to the
    /// inputs of `hash`.
    pub(crate) fn locked<'a>(
        &'a self,
        name: &'a str,
        command: &'a str,
        hash: String,
    ) -> Locked<'a> {
        Locked {
            out: &self.out,
            name,
            command,
            hash,
            force: self.force,
            threads: self.threads,
        }
    }
}

/// The grain material's flags, `dem test crush` and `dem test column` alike.
#[derive(Args)]
pub struct GrainMaterialArgs {
    /// Young's modulus E of the grain material, with unit (`70GPa`).
    #[arg(long, default_value = "70GPa")]
    pub young: String,
    /// Poisson's ratio ν, 0 ≤ ν < 1/3 (the lattice's range).
    #[arg(long, default_value_t = 0.2)]
    pub poisson: f64,
    /// Density (kg/m³).
    #[arg(long, default_value_t = 2650.0)]
    pub density: f64,
}

impl GrainMaterialArgs {
    /// E (Pa) from `--young`.
    pub fn young(&self) -> Result<f64, String> {
        parse_stress(&self.young, "--young")
    }
}

/// The criterion from the flags; errors name the flag.
pub fn criterion(a: &CrushArgs) -> Result<LinkCriterion, String> {
    criterion_of(&CriterionFlags {
        criterion: &a.criterion,
        link_force: a.link_force,
        link_stress: a.link_stress.as_deref(),
        link_strain: a.link_strain,
        link_shear: a.link_shear,
        fracture_energy: a.fracture_energy,
    })
}

/// The criterion flags `dem test crush` and `dem test column` share.
pub struct CriterionFlags<'a> {
    pub criterion: &'a str,
    pub link_force: Option<f64>,
    pub link_stress: Option<&'a str>,
    pub link_strain: Option<f64>,
    pub link_shear: Option<f64>,
    pub fracture_energy: Option<f64>,
}

/// The criterion from its flags; errors name the flag.
pub fn criterion_of(a: &CriterionFlags) -> Result<LinkCriterion, String> {
    let given = |name: &str, present: bool, allowed: bool| -> Result<(), String> {
        if present && !allowed {
            return Err(format!(
                "{name} is not a parameter of --criterion {}",
                a.criterion
            ));
        }
        Ok(())
    };
    let need = |name: &str, v: Option<f64>, what: &str| -> Result<f64, String> {
        let v = v.ok_or_else(|| format!("--criterion {} needs {name} ({what})", a.criterion))?;
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("{name} {v}: must be positive and finite"));
        }
        Ok(v)
    };
    let c = a.criterion;
    given("--link-force", a.link_force.is_some(), c == "force")?;
    given("--link-strain", a.link_strain.is_some(), c == "strain")?;
    given("--link-stress", a.link_stress.is_some(), c == "stress")?;
    given(
        "--link-shear",
        a.link_shear.is_some(),
        c == "force" || c == "stress" || c == "strain",
    )?;
    given(
        "--fracture-energy",
        a.fracture_energy.is_some(),
        c == "energy",
    )?;
    let shear = |t: f64| match a.link_shear {
        Some(s) if !(s.is_finite() && s > 0.0) => {
            Err(format!("--link-shear {s}: must be positive and finite"))
        }
        Some(s) => Ok(s),
        None => Ok(t),
    };
    match c {
        "force" => {
            let t = need(
                "--link-force",
                a.link_force,
                "a link's tensile strength in N",
            )?;
            Ok(LinkCriterion::Force {
                tensile: t,
                shear: shear(t)?,
            })
        }
        "strain" => {
            let t = need(
                "--link-strain",
                a.link_strain,
                "a link's tensile failure strain",
            )?;
            Ok(LinkCriterion::Strain {
                tensile: t,
                shear: shear(t)?,
            })
        }
        "energy" => Ok(LinkCriterion::Energy {
            fracture_energy: need(
                "--fracture-energy",
                a.fracture_energy,
                "the material's fracture energy G_c in J/m²",
            )?,
        }),
        "stress" => {
            let parsed = a
                .link_stress
                .map(|v| crate::specimen::parse_stress(v, "--link-stress"))
                .transpose()?;
            let t = need(
                "--link-stress",
                parsed,
                "a link's tensile strength as a stress, e.g. 50MPa",
            )?;
            Ok(LinkCriterion::Stress {
                tensile: t,
                shear: shear(t)?,
            })
        }
        c => Err(format!(
            "--criterion {c:?}: expected force, stress, strain or energy"
        )),
    }
}

/// A grain test's run (crush, column): the folder `<out>/<name>.out` its scene runs into locked
/// to its inputs (`hash`; run_lock.rs), so two runs never mix their outputs there, the work in
/// a pool of `threads`, with a progress bar.
pub(crate) struct Locked<'a> {
    pub out: &'a std::path::Path,
    pub name: &'a str,
    pub command: &'a str,
    pub hash: String,
    pub force: bool,
    pub threads: Option<usize>,
}

impl Locked<'_> {
    /// Runs `body` (given a progress callback: steps done, steps in all) under the lock, with
    /// the bar's prefix `what`.
    pub fn run<T: Send>(
        &self,
        what: &str,
        body: impl FnOnce(&mut dyn FnMut(u64, u64)) -> Result<T, String> + Send,
    ) -> Result<T, String> {
        std::fs::create_dir_all(self.out).map_err(|e| format!("{}: {e}", self.out.display()))?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.unwrap_or(0))
            .build()
            .map_err(|e| e.to_string())?;
        let _lock = crate::run_lock::acquire_noted(
            &self.out.join(format!("{}.out", self.name)),
            crate::run_lock::Claim {
                command: self.command,
                scene: &self.out.join(format!("{}.json", self.name)),
                hash: &self.hash,
            },
            self.force,
        )?;
        let bar = Progress::stages();
        bar.set_prefix(what.to_string());
        let o = pool.install(|| {
            body(&mut |done, total| {
                bar.set_position((done * 1000).checked_div(total).unwrap_or(0));
            })
        });
        bar.finish_and_clear();
        o
    }

    /// Prints where the result file `<out>/<name>.result.json` is.
    pub fn print_result(&self) -> ExitCode {
        println!(
            "result:  {}",
            self.out
                .join(format!("{}.result.json", self.name))
                .display()
        );
        ExitCode::SUCCESS
    }
}

fn message(e: LabError) -> String {
    match e {
        LabError::Param { field, reason } => {
            let flag = match field.as_str() {
                "crush.young" => "--young",
                "crush.poisson" => "--poisson",
                "crush.density" => "--density",
                "crush.friction" => "--friction",
                "crush.platen_friction" => "--platen-friction",
                "crush.major" => "--major",
                "crush.max_closure" => "--max-closure",
                "crush.stage2_travel" => "--stage2-travel",
                "crush.speed" => "--speed",
                "crush.dt_factor" => "--dt-factor",
                "template" => return format!("--template: {reason}"),
                _ => return format!("{field}: {reason}"),
            };
            format!("{flag}: {reason}")
        }
        e => e.to_string(),
    }
}

pub fn run(a: CrushArgs) -> Result<ExitCode, String> {
    let out = &a.folder.out;
    let crit = criterion(&a)?;
    let mut test = CrushTest {
        young: a.material.young()?,
        poisson: a.material.poisson,
        density: a.material.density,
        criterion: crit,
        friction: a.friction,
        platen_friction: a.platen_friction,
        angle: a.angle.to_radians(),
        major: a.major,
        max_closure: a.max_closure,
        stage2_travel: a.stage2_travel,
        ..CrushTest::default()
    };
    if let Some(v) = &a.speed {
        test.speed = Some(parse_length(
            v.trim().strip_suffix("/s").unwrap_or(v.trim()),
            "--speed",
        )?);
    }
    if let Some(f) = a.dt_factor {
        test.dt_factor = f;
    }
    test.validate().map_err(message)?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let template = match (&a.template, &a.outline) {
        (Some(_), Some(_)) => return Err("give --template or --outline, not both".into()),
        (None, None) => return Err(
            "give the grain: --template T.json (a lattice template) or --outline O.csv --spacing S"
                .into(),
        ),
        (Some(t), None) => {
            if a.spacing.is_some() {
                return Err("--spacing is for --outline (a template has its lattice)".into());
            }
            t.clone()
        }
        (None, Some(o)) => {
            let s = a.spacing.as_deref().ok_or(
                "--outline needs --spacing S (a fraction of R_eq like 0.18, or a length like 0.2mm)",
            )?;
            let spacing = crate::clump::parse_length(s, "spacing")?;
            let thickness = parse_length(&a.thickness, "--thickness")?;
            let p = ClumpParams {
                method: Method::Lattice,
                density: a.material.density,
                thickness,
                lattice: Some(LatticeParams {
                    spacing,
                    node_radius: a.node_radius,
                }),
                ..ClumpParams::default()
            };
            p.check().map_err(|e| {
                let value = match e.name {
                    "spacing" => s.to_string(),
                    _ => e.value.clone(),
                };
                format!("--{} {value}: {}", e.name.replace('_', "-"), e.reason)
            })?;
            let ol =
                clumpgen::read_outline(o, &ReadOptions::default()).map_err(|e| e.to_string())?;
            let tpl = make_template(&ol, &p).map_err(|e| e.to_string())?;
            let file = out.join(format!("{}.grain.json", test.name));
            tpl.save(&file).map_err(|e| e.to_string())?;
            file
        }
    };
    // The grain is part of the inputs the run lock is keyed on.
    let grain =
        clumpgen::io::read_input(&template).map_err(|e| format!("{}: {e}", template.display()))?;
    let hash = crate::run_lock::inputs_hash(&(&test, crate::run_lock::inputs_hash(&grain)));
    let locked = a.folder.locked(&test.name, "dem test crush", hash);
    let o = locked.run("crush", |pr| {
        grain::run(&test, &template, out, pr).map_err(message)
    })?;
    let r = &o.result;
    let g = &r.grain;
    println!(
        "grain {}: {} nodes, {} links, S = {:.4} mm (R_eq/S = {:.2}), d = {:.4} mm (platen gap), d_eq = {:.4} mm",
        g.id,
        g.nodes,
        g.links,
        g.spacing * 1e3,
        0.5 * g.d_eq / g.spacing,
        g.d * 1e3,
        g.d_eq * 1e3
    );
    println!(
        "σ = F/(d t) = {:.2} MPa (peak force {:.4e} N at closure {:.4e} m); criterion {}",
        r.strength * 1e-6,
        r.peak_force,
        r.closure_at_peak,
        o.test.criterion.name()
    );
    println!(
        "quasi-static: platens {:.4e} m/s each, time to peak {:.1} transit times, kinetic/strain energy at the peak {:.2e}",
        r.platen_speed,
        r.time_to_peak / r.transit_time,
        r.kinetic_over_strain_at_peak
    );
    for (k, s) in [(1, &r.stage1), (2, &r.stage2)] {
        println!(
            "stage {k}: closure {:.4e} m, {} links broken, {} fragments (≥ 2 nodes) + {} fines; largest {:.1} % of the mass",
            s.closure,
            s.broken_links,
            s.fragments.fragments,
            s.fragments.fines,
            100.0 * s.fragments.largest_mass_fraction
        );
    }
    println!(
        "energy: work {:.4e} J = strain {:.4e} + kinetic {:.4e} + damping {:.4e} + friction {:.4e} + released {:.4e} (balance error {:.2e}); {:.3e} particle-steps/s",
        r.work, r.strain_energy, r.kinetic_energy, r.damping, r.friction, r.released, r.balance_error, r.particle_steps_per_s
    );
    Ok(locked.print_result())
}
