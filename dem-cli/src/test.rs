//! `dem test ucs|biaxial|brazilian|bending|senb`: virtual lab tests on a specimen generated (or reused) with
//! the same parameters as `dem specimen`, each written as a plain scene file that `dem run` can
//! re-run, then run and analysed (`docs/lab-tests.md`).
//!
//! One clap variant per test; the specimen and model flags every test shares are
//! [`LabArgs`] (`#[command(flatten)]`, in `lab_args.rs`), so another test (cutting) adds only
//! its own variant.

use crate::lab_args::{strict_cover, LabArgs};
use crate::progress::Progress as Bar;
use crate::specimen::{parse_length, parse_speed, print_cover};
use clap::{Args, Subcommand};
use dem_lab::bending::BendingTest;
use dem_lab::biaxial::BiaxialTest;
use dem_lab::brazilian::BrazilianTest;
use dem_lab::senb::SenbTest;
use dem_lab::specimen::{Progress, SpecimenParams};
use dem_lab::specimens::{self, Shape, TestSpecimen};
use dem_lab::ucs::UcsTest;
use dem_lab::{self as lab, LabError, LabModel};
use std::process::ExitCode;

/// The lab tests.
// Parsed once per process: the size of the largest variant is of no account.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
pub enum TestKind {
    /// Uniaxial compression between two platens: E, ν (10–50 % pre-peak band) and UCS.
    Ucs(UcsArgs),
    /// Biaxial (confined) compression at one or more confinements held by servo side walls:
    /// peak σ1 at each σ3, friction angle and cohesion (Mohr–Coulomb).
    Biaxial(BiaxialArgs),
    /// Brazilian disc between two platens: σ_t = 2F/(πDt).
    Brazilian(BrazilianArgs),
    /// Three-point bending of a beam: σ_f = 3FL/(2bh²) and the elastic stiffness.
    Bending(BendingArgs),
    /// Single-edge-notched beam in three-point bending (ASTM E399 SE(B), span 4W): K_IC and
    /// the measured β of K_IC = β σ̄c √(πR̄).
    Senb(SenbArgs),
    /// Orthogonal cutting: peak and mean main and vertical force, chips, broken bonds,
    /// machined surface (docs/cutting.md).
    Cutting(crate::test_cutting::CuttingArgs),
    /// One lattice grain crushed between two platens: force–displacement, crushing strength
    /// σ = F/(d t), fragments after the first breakage and a second loading stage
    /// (docs/lattice.md).
    Crush(crate::test_crush::CrushArgs),
    /// A crushable column: 200+ lattice grains in a box under one-dimensional compression;
    /// stress–strain, gradings at stress levels, Hardin's relative breakage (docs/lattice.md).
    Column(crate::test_column::ColumnArgs),
}

/// [`flag_message`] for a rectangular specimen's `<test>.width` and `<test>.height`, given as
/// `--width` and `--height`.
fn size_message(e: LabError, test: &str, width: &str, height: &str) -> String {
    let (fw, fh) = (format!("{test}.width"), format!("{test}.height"));
    flag_message(e, &[(&fw, "--width", width), (&fh, "--height", height)])
}

/// A lab-test error as a message naming the flag: `flags` maps a field (`ucs.width`) to its
/// flag and the value as given; other fields keep their name.
fn flag_message(e: LabError, flags: &[(&str, &str, &str)]) -> String {
    match e {
        LabError::Param { field, reason } => match flags.iter().find(|f| f.0 == field) {
            Some((_, flag, given)) => format!("{flag} {given}: {reason}"),
            None => format!("{field}: {reason}"),
        },
        e => e.to_string(),
    }
}

/// Nominal mean disc radius of the specimen flags (m): (r_min + r_max)/2.
fn nominal_r_mean(p: &SpecimenParams) -> f64 {
    0.5 * (p.r_min + p.r_max)
}

/// `dem test ucs` flags.
#[derive(Args)]
pub struct UcsArgs {
    #[command(flatten)]
    pub lab: LabArgs,
    /// Specimen width with unit.
    #[arg(long, default_value = "10mm")]
    pub width: String,
    /// Specimen height with unit (2:1 tall by default).
    #[arg(long, default_value = "20mm")]
    pub height: String,
    /// Platen speed (each platen) with unit, e.g. `0.05m/s`; default from the quasi-static
    /// rule (docs/lab-tests.md).
    #[arg(long)]
    pub speed: Option<String>,
}

/// `dem test biaxial` flags.
#[derive(Args)]
pub struct BiaxialArgs {
    #[command(flatten)]
    pub lab: LabArgs,
    /// Specimen width with unit.
    #[arg(long, default_value = "10mm")]
    pub width: String,
    /// Specimen height with unit (2:1 tall by default).
    #[arg(long, default_value = "20mm")]
    pub height: String,
    /// Confining stresses σ3 with unit, comma-separated, one run each on the same specimen
    /// (e.g. `0MPa,100MPa,200MPa`); two or more give φ and c.
    #[arg(long, value_delimiter = ',', required = true)]
    pub confining: Vec<String>,
    /// Platen speed (each platen) with unit; default from the quasi-static rule.
    #[arg(long)]
    pub speed: Option<String>,
}

/// `dem test brazilian` flags.
#[derive(Args)]
pub struct BrazilianArgs {
    #[command(flatten)]
    pub lab: LabArgs,
    /// Disc diameter with unit.
    #[arg(long, default_value = "10mm")]
    pub diameter: String,
    /// Platen speed with unit (`0.05m/s`); default from the quasi-static rule.
    #[arg(long)]
    pub speed: Option<String>,
}

/// `dem test bending` flags.
#[derive(Args)]
pub struct BendingArgs {
    #[command(flatten)]
    pub lab: LabArgs,
    /// Beam length with unit.
    #[arg(long, default_value = "20mm")]
    pub length: String,
    /// Beam height with unit.
    #[arg(long, default_value = "5mm")]
    pub height: String,
    /// Support span with unit.
    #[arg(long, default_value = "16mm")]
    pub span: String,
    /// Loading-roller speed with unit (`0.05m/s`); default from the quasi-static rule.
    #[arg(long)]
    pub speed: Option<String>,
}

/// `dem test senb` flags.
#[derive(Args)]
pub struct SenbArgs {
    #[command(flatten)]
    pub lab: LabArgs,
    /// Beam length with unit (at least the span 4W plus a mean disc diameter each side).
    #[arg(long, default_value = "22mm")]
    pub length: String,
    /// Beam depth W with unit; the span is 4W.
    #[arg(long, default_value = "5mm")]
    pub height: String,
    /// Notch depth over beam depth a/W (ASTM E399: 0.45–0.55).
    #[arg(long, default_value_t = 0.5)]
    pub notch_ratio: f64,
    /// Notch (slot) width with unit; default one nominal mean disc diameter (r_min + r_max).
    #[arg(long)]
    pub notch_width: Option<String>,
    /// Loading-roller speed with unit (`0.05m/s`); default from the quasi-static rule.
    #[arg(long)]
    pub speed: Option<String>,
}

pub fn run(kind: TestKind) -> Result<ExitCode, String> {
    match kind {
        TestKind::Ucs(a) => ucs(a),
        TestKind::Biaxial(a) => biaxial(a),
        TestKind::Brazilian(a) => brazilian(a),
        TestKind::Bending(a) => bending(a),
        TestKind::Senb(a) => senb(a),
        TestKind::Cutting(a) => crate::test_cutting::run(a),
        TestKind::Crush(a) => crate::test_crush::run(a),
        TestKind::Column(a) => crate::test_column::run(a),
    }
}

/// Confining stresses with unit (`0MPa`, `100MPa`, …; zero allowed) → Pa.
pub fn parse_confinements(list: &[String], flag: &str) -> Result<Vec<f64>, String> {
    list.iter()
        .map(|s| {
            let num = s.trim().trim_end_matches(|c: char| c.is_alphabetic());
            if num.parse::<f64>() == Ok(0.0) {
                return Ok(0.0);
            }
            crate::specimen::parse_stress(s, flag)
                .map_err(|e| format!("{e} (a confinement is ≥ 0, compression positive)"))
        })
        .collect()
}

/// The loading settings from the shared flags and a test's `--speed`.
fn loading(
    lab: &LabArgs,
    speed: &Option<String>,
    mut l: lab::common::Loading,
) -> Result<lab::common::Loading, String> {
    if let Some(v) = speed {
        l.speed = Some(parse_speed(v, "--speed")?);
    }
    if let Some(f) = lab.dt_factor {
        l.dt_factor = f;
    }
    Ok(l)
}

/// Takes the lock of the folder test `test`'s scene `<out>/<test>.json` runs into,
/// `<out>/<test>.out` (`run_lock`), before anything is written; `inputs` (the test's typed
/// inputs) say whether an earlier run there was the same test.
fn lock_test(
    lab: &LabArgs,
    test: &str,
    inputs: &serde_json::Value,
) -> Result<crate::run_lock::RunLock, String> {
    let command = format!("dem test {test}");
    crate::run_lock::acquire_noted(
        &lab.out.join(format!("{test}.out")),
        crate::run_lock::Claim {
            command: &command,
            scene: &lab.out.join(format!("{test}.json")),
            hash: &crate::run_lock::inputs_hash(inputs),
        },
        lab.force,
    )
}

/// Generates (or reuses) the test's specimen `<out>/<test>.specimen.json` and runs `body` on it
/// in the thread pool, with a progress bar for both, holding the test's run lock
/// ([`lock_test`], keyed on `inputs`); with --strict a specimen with grains below their cover
/// target stops before the test ([`strict_cover`]), else they are printed as warnings.
fn with_specimen<T>(
    lab: &LabArgs,
    p: &SpecimenParams,
    shape: Shape,
    (test, inputs): (&str, serde_json::Value),
    body: impl FnOnce(&TestSpecimen, &mut dyn FnMut(u64, u64)) -> Result<T, LabError> + Send,
) -> Result<T, String>
where
    T: Send,
{
    let pool = lab.pool()?;
    let _lock = lock_test(lab, test, &inputs)?;
    let file = lab.out.join(format!("{test}.specimen.json"));
    println!(
        "{test}: {} specimen, radii {:.4}-{:.4} mm, seed {} -> {}",
        p.method.name(),
        p.r_min * 1e3,
        p.r_max * 1e3,
        p.seed,
        file.display()
    );
    let bar = Bar::stages();
    let out = pool.install(|| -> Result<(TestSpecimen, T), LabError> {
        let spec = specimens::prepare(p, shape, &file, &mut |pr: Progress| {
            bar.set_prefix(pr.stage);
            bar.set_fraction(pr.fraction);
            bar.set_message(pr.message);
        })?;
        bar.set_prefix(test.to_string());
        bar.set_message(format!("{} discs", spec.discs));
        strict_cover(lab, &spec)?;
        let r = body(&spec, &mut |done, total| {
            bar.set_position((done * 1000).checked_div(total).unwrap_or(0));
        })?;
        Ok((spec, r))
    });
    bar.finish_and_clear();
    let (spec, r) = out.map_err(|e| e.to_string())?;
    println!(
        "specimen: {} discs, {} bonds{}",
        spec.discs,
        spec.bonds,
        if spec.reused {
            " (reused: same parameters)"
        } else {
            ""
        }
    );
    print_cover(&spec.file, &spec.below_cover);
    Ok(r)
}

/// A quasi-static test's typed inputs as one JSON value (their hash keys its run lock).
fn inputs<T: serde::Serialize>(
    p: &SpecimenParams,
    model: &LabModel,
    test: &T,
) -> Result<serde_json::Value, String> {
    serde_json::to_value((p, model, test)).map_err(|e| e.to_string())
}

fn print_run(run: &lab::common::RunFacts, result: &std::path::Path) {
    println!(
        "run: {} after {} steps (dt {:.3e} s), {} of {} bonds broken, {:.1} s",
        run.status, run.steps, run.dt, run.bonds_broken, run.bonds, run.wall_time_s
    );
    println!("scene:   {} (dem run it again)", run.scene_file.display());
    println!("outputs: {}", run.out_dir.display());
    println!("result:  {}", result.display());
}

fn ucs(a: UcsArgs) -> Result<ExitCode, String> {
    let w = parse_length(&a.width, "--width")?;
    let h = parse_length(&a.height, "--height")?;
    let p = a.lab.specimen_params(w, h)?;
    let model = a.lab.lab_model(&p)?;
    let test = UcsTest {
        width: w,
        height: h,
        loading: loading(&a.lab, &a.speed, UcsTest::default().loading)?,
        ..UcsTest::default()
    };
    test.validate().map_err(|e| e.to_string())?;
    test.check_geometry([w, h], nominal_r_mean(&p))
        .map_err(|e| size_message(e, "ucs", &a.width, &a.height))?;
    let o = with_specimen(
        &a.lab,
        &p,
        test.shape(),
        ("ucs", inputs(&p, &model, &test)?),
        |spec, pr| lab::ucs::run(&test, &model, spec, pr),
    )?;
    let r = &o.result;
    println!(
        "E = {:.2} GPa, ν = {:.3} ({:.0}-{:.0} % pre-peak band, {} rows), UCS = {:.1} MPa at axial strain {:.3e}",
        r.young * 1e-9,
        r.poisson,
        r.band[0] * 100.0,
        r.band[1] * 100.0,
        r.band_rows,
        r.ucs * 1e-6,
        r.peak_strain
    );
    println!(
        "platens {:.4e} m/s each (strain rate {:.3e} 1/s); time to peak = {:.1} P-wave transit times",
        r.platen_speed, r.strain_rate, r.quasi_static_ratio
    );
    print_run(&o.run, &a.lab.out.join("ucs.result.json"));
    Ok(ExitCode::SUCCESS)
}

fn biaxial(a: BiaxialArgs) -> Result<ExitCode, String> {
    let w = parse_length(&a.width, "--width")?;
    let h = parse_length(&a.height, "--height")?;
    let confinements = parse_confinements(&a.confining, "--confining")?;
    let p = a.lab.specimen_params(w, h)?;
    let model = a.lab.lab_model(&p)?;
    let test = BiaxialTest {
        width: w,
        height: h,
        loading: loading(&a.lab, &a.speed, BiaxialTest::default().loading)?,
        ..BiaxialTest::default()
    };
    test.validate().map_err(|e| e.to_string())?;
    test.check_geometry([w, h], nominal_r_mean(&p))
        .map_err(|e| size_message(e, "biaxial", &a.width, &a.height))?;
    let s = with_specimen(
        &a.lab,
        &p,
        test.shape(),
        ("biaxial", inputs(&p, &model, &(&test, &confinements))?),
        |spec, pr| lab::biaxial::run_series(&test, &confinements, &model, spec, pr),
    )?;
    for (k, r) in s.results.iter().enumerate() {
        println!(
            "biaxial-{k}: σ3 = {:.1} MPa (asked {:.1}, held within {:.1} %), peak σ1 = {:.1} MPa, deviator {:.1} MPa, E = {:.2} GPa, ν = {:.3}, {:.1} transit times to peak",
            r.sigma3 * 1e-6,
            r.confining * 1e-6,
            100.0 * r.confining_error,
            r.sigma1 * 1e-6,
            r.deviator * 1e-6,
            r.young * 1e-9,
            r.poisson,
            r.quasi_static_ratio
        );
    }
    match &s.mohr_coulomb {
        Some(m) => println!(
            "Mohr–Coulomb: φ = {:.1}°, c = {:.1} MPa (σ1 = {:.1} MPa + {:.3} σ3, R² {:.4})",
            m.friction_angle_deg,
            m.cohesion * 1e-6,
            m.intercept * 1e-6,
            m.slope,
            m.r2
        ),
        None if s.results.len() < 2 => {
            println!("Mohr–Coulomb: give two or more confinements for φ and c")
        }
        None => println!("Mohr–Coulomb: no envelope (the strength does not rise with σ3)"),
    }
    println!(
        "runs: {} steps, {:.1} s; result: {}",
        s.steps,
        s.wall_time_s,
        a.lab.out.join("biaxial.result.json").display()
    );
    Ok(ExitCode::SUCCESS)
}

fn brazilian(a: BrazilianArgs) -> Result<ExitCode, String> {
    let d = parse_length(&a.diameter, "--diameter")?;
    let p = a.lab.specimen_params(d, d)?;
    let model = a.lab.lab_model(&p)?;
    let test = BrazilianTest {
        diameter: d,
        loading: loading(&a.lab, &a.speed, BrazilianTest::default().loading)?,
        ..BrazilianTest::default()
    };
    test.validate().map_err(|e| e.to_string())?;
    test.check_geometry(d, nominal_r_mean(&p))
        .map_err(|e| flag_message(e, &[("brazilian.diameter", "--diameter", &a.diameter)]))?;
    let o = with_specimen(
        &a.lab,
        &p,
        test.shape(),
        ("brazilian", inputs(&p, &model, &test)?),
        |spec, pr| lab::brazilian::run(&test, &model, spec, pr),
    )?;
    let r = &o.result;
    println!(
        "σ_t = 2F/(πDt) = {:.1} MPa (peak load {:.4e} N, D = {:.3} mm, t = {} m)",
        r.tensile_strength * 1e-6,
        r.peak_load,
        r.diameter * 1e3,
        model.thickness
    );
    println!(
        "platens {:.4e} m/s each; time to peak = {:.1} P-wave transit times",
        r.platen_speed, r.quasi_static_ratio
    );
    print_run(&o.run, &a.lab.out.join("brazilian.result.json"));
    Ok(ExitCode::SUCCESS)
}

fn bending(a: BendingArgs) -> Result<ExitCode, String> {
    let l = parse_length(&a.length, "--length")?;
    let h = parse_length(&a.height, "--height")?;
    let span = parse_length(&a.span, "--span")?;
    let p = a.lab.specimen_params(l, h)?;
    let model = a.lab.lab_model(&p)?;
    let test = BendingTest {
        length: l,
        height: h,
        span,
        loading: loading(&a.lab, &a.speed, BendingTest::default().loading)?,
        ..BendingTest::default()
    };
    test.validate().map_err(|e| e.to_string())?;
    test.check_geometry([l, h], nominal_r_mean(&p))
        .map_err(|e| {
            flag_message(
                e,
                &[
                    ("bending.height", "--height", &a.height),
                    ("bending.span", "--span", &a.span),
                ],
            )
        })?;
    let o = with_specimen(
        &a.lab,
        &p,
        test.shape(),
        ("bending", inputs(&p, &model, &test)?),
        |spec, pr| lab::bending::run(&test, &model, spec, pr),
    )?;
    let r = &o.result;
    println!(
        "σ_f = 3FL/(2bh²) = {:.1} MPa (peak load {:.4e} N, L = {:.3} mm, h = {:.3} mm, b = t = {} m)",
        r.flexural_strength * 1e-6,
        r.peak_load,
        r.span * 1e3,
        r.height * 1e3,
        model.thickness
    );
    println!(
        "elastic stiffness dF/dδ = {:.4e} N/m; roller {:.4e} m/s; time to peak = {:.1} beam periods",
        r.stiffness, r.roller_speed, r.quasi_static_ratio
    );
    print_run(&o.run, &a.lab.out.join("bending.result.json"));
    Ok(ExitCode::SUCCESS)
}

fn senb(a: SenbArgs) -> Result<ExitCode, String> {
    let l = parse_length(&a.length, "--length")?;
    let h = parse_length(&a.height, "--height")?;
    let p = a.lab.specimen_params(l, h)?;
    let model = a.lab.lab_model(&p)?;
    let notch_width = match &a.notch_width {
        Some(w) => parse_length(w, "--notch-width")?,
        None => p.r_min + p.r_max,
    };
    let test = SenbTest {
        length: l,
        height: h,
        notch_ratio: a.notch_ratio,
        notch_width,
        loading: loading(&a.lab, &a.speed, SenbTest::default().loading)?,
        ..SenbTest::default()
    };
    let ratio = a.notch_ratio.to_string();
    let width = a.notch_width.clone().unwrap_or_default();
    let flags = [
        ("senb.length", "--length", a.length.as_str()),
        ("senb.height", "--height", a.height.as_str()),
        ("senb.notch_ratio", "--notch-ratio", ratio.as_str()),
        ("senb.notch_width", "--notch-width", width.as_str()),
    ];
    test.validate().map_err(|e| flag_message(e, &flags))?;
    test.check_geometry(nominal_r_mean(&p))
        .map_err(|e| flag_message(e, &flags))?;
    let o = with_specimen(
        &a.lab,
        &p,
        test.shape(),
        ("senb", inputs(&p, &model, &test)?),
        |spec, pr| lab::senb::run(&test, &model, spec, pr),
    )?;
    let r = &o.result;
    println!(
        "K_IC = P S f(a/W) / (B W^1.5) = {:.3} MPa·m^½ (ASTM E399 SE(B): peak load {:.4e} N, S = {:.3} mm, W = {:.3} mm, a/W = {:.3}, f = {:.3}, B = t = {} m)",
        r.fracture_toughness * 1e-6,
        r.peak_load,
        r.span * 1e3,
        r.height * 1e3,
        r.notch_ratio,
        r.geometry_factor,
        model.thickness
    );
    println!(
        "bond scale σ̄c √(πR̄) = {:.3} MPa·m^½ -> measured β = {:.3}; notch slot {:.3} mm, ligament {:.1} mean disc diameters; CMOD at peak {:.3e} m",
        r.bond_estimate * 1e-6,
        r.beta,
        r.notch_width * 1e3,
        r.ligament_diameters,
        r.cmod_at_peak
    );
    println!(
        "roller {:.4e} m/s; time to peak = {:.1} periods of the un-notched beam",
        r.roller_speed, r.quasi_static_ratio
    );
    print_run(&o.run, &a.lab.out.join("senb.result.json"));
    Ok(ExitCode::SUCCESS)
}
