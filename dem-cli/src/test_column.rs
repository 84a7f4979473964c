//! `dem test column`: a crushable granular column under one-dimensional compression
//! (docs/lattice.md §7, `dem_lab::crushing::column`): 200+ lattice grains from outline files in a
//! box of rigid walls, a top platen moving down; stress–strain, gradings at stress levels,
//! Hardin's relative breakage.

use crate::specimen::{parse_length, parse_speed, parse_stress};
use crate::test_crush::{criterion_of, CriterionFlags, GrainMaterialArgs, RunFolderArgs};
use clap::Args;
use dem_lab::crushing::column::{self, ColumnTest};
use dem_lab::LabError;
use std::path::PathBuf;
use std::process::ExitCode;

/// `dem test column` flags.
#[derive(Args)]
pub struct ColumnArgs {
    /// Outline files or folders (as `dem clump` reads them, e.g. `data/outlines`); each grain
    /// draws one.
    #[arg(long, required = true, num_args = 1..)]
    pub outlines: Vec<PathBuf>,
    /// Number of grains.
    #[arg(long, default_value_t = 210)]
    pub grains: usize,
    /// Box width in multiples of --d-max.
    #[arg(long, default_value_t = 20.0)]
    pub width: f64,
    /// Smallest and largest grain size (equivalent diameter), with unit.
    #[arg(long, default_value = "1.2mm")]
    pub d_min: String,
    #[arg(long, default_value = "2mm")]
    pub d_max: String,
    /// Size classes, geometrically spaced from --d-min to --d-max.
    #[arg(long, default_value_t = 3)]
    pub size_classes: usize,
    /// Lattice spacing S of every grain, with unit.
    #[arg(long, default_value = "0.2mm")]
    pub spacing: String,
    /// Node radius as a fraction of S/2, in (0, 1].
    #[arg(long, default_value_t = 0.9)]
    pub node_radius: f64,
    #[command(flatten)]
    pub material: GrainMaterialArgs,
    /// Link breakage criterion: force, stress, strain or energy (each needs its parameter
    /// flag).
    #[arg(long, default_value = "energy")]
    pub criterion: String,
    #[arg(long)]
    pub link_force: Option<f64>,
    #[arg(long)]
    pub link_stress: Option<String>,
    #[arg(long)]
    pub link_strain: Option<f64>,
    #[arg(long)]
    pub link_shear: Option<f64>,
    /// energy: the material's fracture energy G_c (J/m²).
    #[arg(long, default_value = "30")]
    pub fracture_energy: Option<f64>,
    /// Friction: node–node, node–platen, node–side wall.
    #[arg(long, default_value_t = 0.5)]
    pub friction: f64,
    #[arg(long, default_value_t = 0.5)]
    pub platen_friction: f64,
    #[arg(long, default_value_t = 0.0)]
    pub wall_friction: f64,
    /// Placement seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Vertical stresses at which the grading is recorded, comma-separated, with unit
    /// (`2MPa,5MPa,10MPa`); the run ends at the last.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "2MPa,5MPa,10MPa,20MPa,40MPa"
    )]
    pub stress_levels: Vec<String>,
    /// Seating before loading: rigid grains, the top platen moving down at --seat-speed until
    /// both platens carry this stress (below the first level).
    #[arg(long, default_value = "0.5MPa")]
    pub seat_stress: String,
    #[arg(long, default_value = "1m/s")]
    pub seat_speed: String,
    /// inertial: the platen's speed follows the stress so that the inertial number stays at
    /// --inertial-number (quasi-static at 1e-3, GDR MiDi 2004); ramp: a constant speed
    /// (--speed, or from --inertial-number at the first level).
    #[arg(long, default_value = "inertial", value_parser = ["inertial", "ramp"])]
    pub loading: String,
    /// Platen speed with unit (`1m/s`), --loading ramp only; default from --inertial-number.
    #[arg(long)]
    pub speed: Option<String>,
    /// Inertial number I = ε̇ d̄ √(ρ/σ) held throughout (--loading inertial) or at the first
    /// level (--loading ramp without --speed).
    #[arg(long, default_value_t = 1e-3)]
    pub inertial_number: f64,
    /// The run's cap: platen travel over the initial height.
    #[arg(long, default_value_t = 0.5)]
    pub max_strain: f64,
    #[command(flatten)]
    pub folder: RunFolderArgs,
}

fn message(e: LabError) -> String {
    match e {
        LabError::Param { field, reason } => {
            let flag = match field.strip_prefix("column.") {
                Some(f) if !f.starts_with("criterion") => format!("--{}", f.replace('_', "-")),
                _ => field,
            };
            format!("{flag}: {reason}")
        }
        e => e.to_string(),
    }
}

pub fn run(a: ColumnArgs) -> Result<ExitCode, String> {
    let crit = criterion_of(&CriterionFlags {
        criterion: &a.criterion,
        link_force: a.link_force,
        link_stress: a.link_stress.as_deref(),
        link_strain: a.link_strain,
        link_shear: a.link_shear,
        fracture_energy: if a.criterion == "energy" {
            a.fracture_energy
        } else {
            None
        },
    })?;
    let levels = a
        .stress_levels
        .iter()
        .map(|s| parse_stress(s, "--stress-levels"))
        .collect::<Result<Vec<f64>, String>>()?;
    let mut test = ColumnTest {
        grains: a.grains,
        width: a.width,
        d_min: parse_length(&a.d_min, "--d-min")?,
        d_max: parse_length(&a.d_max, "--d-max")?,
        size_classes: a.size_classes,
        spacing: parse_length(&a.spacing, "--spacing")?,
        node_radius: a.node_radius,
        young: a.material.young()?,
        poisson: a.material.poisson,
        density: a.material.density,
        friction: a.friction,
        platen_friction: a.platen_friction,
        wall_friction: a.wall_friction,
        criterion: crit,
        seed: a.seed,
        stress_levels: levels,
        inertial_number: a.inertial_number,
        seat_stress: parse_stress(&a.seat_stress, "--seat-stress")?,
        seat_speed: parse_speed(&a.seat_speed, "--seat-speed")?,
        max_strain: a.max_strain,
        loading: if a.loading == "ramp" {
            column::Loading::Ramp
        } else {
            column::Loading::Inertial
        },
        ..ColumnTest::default()
    };
    if let Some(v) = &a.speed {
        if test.loading != column::Loading::Ramp {
            return Err("--speed: only with --loading ramp (inertial loading sets the speed from --inertial-number)".into());
        }
        test.speed = Some(parse_speed(v, "--speed")?);
    }
    test.validate().map_err(message)?;
    let outlines: Vec<PathBuf> = clumpgen::batch::collect_inputs(&a.outlines)
        .map_err(|e| format!("--outlines: {e}"))?
        .into_iter()
        .map(|i| i.path)
        .collect();
    if outlines.is_empty() {
        return Err("--outlines: no outline files (csv, txt, xy, dat, json) found".into());
    }
    let hash = crate::run_lock::inputs_hash(&(&test, &outlines));
    let locked = a.folder.locked(&test.name, "dem test column", hash);
    let o = locked.run("column", |pr| {
        column::run(&test, &outlines, &a.folder.out, pr).map_err(message)
    })?;
    let r = &o.result;
    println!(
        "{} grains ({} outlines x {} sizes), {} nodes, {} links; box {:.3} mm wide; deposit {:.3} mm high (solid fraction {:.3}), seated (rigid, {} steps, {:.1} s) {:.3} mm ({:.3}); platen {:.4e} m/s{}",
        r.grains,
        outlines.len(),
        test.size_classes,
        r.nodes,
        r.links,
        r.width * 1e3,
        r.deposit_height * 1e3,
        r.deposit_solid_fraction,
        o.seat.steps,
        o.seat.wall_time_s,
        r.height * 1e3,
        r.initial_solid_fraction,
        r.platen_speed,
        if test.loading == column::Loading::Inertial {
            " at the start"
        } else {
            ""
        }
    );
    println!(
        "level (MPa)  σ_v (MPa)  strain   broken links  B_r     fines mass  I         unbalanced"
    );
    for g in &r.gradings {
        println!(
            "{:>10.2}  {:>9.2}  {:.4}  {:>12}  {:.4}  {:.4}      {:.2e}  {:.2e}",
            g.level * 1e-6,
            g.stress * 1e-6,
            g.strain,
            g.broken_links,
            g.relative_breakage,
            g.fines_mass_fraction,
            g.inertial_number,
            g.unbalanced_ratio
        );
    }
    if !r.levels_not_reached.is_empty() {
        println!(
            "not reached within a strain of {}: {:?} MPa",
            test.max_strain,
            r.levels_not_reached
                .iter()
                .map(|s| s * 1e-6)
                .collect::<Vec<_>>()
        );
    }
    println!(
        "energy: work {:.4e} J, balance error {:.2e}; {} steps in {:.1} s, {:.3e} particle-steps/s",
        r.work, r.balance_error, o.run.steps, o.run.wall_time_s, r.particle_steps_per_s
    );
    Ok(locked.print_result())
}
