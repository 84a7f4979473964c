//! `dem test ucs|biaxial|brazilian|bending|senb`: virtual lab tests on a specimen generated (or reused) with
//! the same parameters as `dem specimen`, each written as a plain scene file that `dem run` can
//! re-run, then run and analysed (`docs/lab-tests.md`).
//!
//! One clap variant per test; the specimen and model flags every test shares are
//! [`LabArgs`] (`#[command(flatten)]`, in `lab_args.rs`), so another test (cutting) adds only
//! its own variant. The quasi-static tests run through one handler, [`handle`]: each test's
//! flags say only what is its own ([`Handler`]: its size, its test, its printed lines).

use crate::lab_args::{strict_cover, LabArgs};
use crate::progress::Progress as Bar;
use crate::specimen::{parse_length, parse_speed, print_cover};
use clap::{Args, Subcommand};
use dem_lab::specimen::cache::{self, Shape, TestSpecimen};
use dem_lab::specimen::{Progress, SpecimenParams};
use dem_lab::tests::bending::BendingTest;
use dem_lab::tests::biaxial::BiaxialTest;
use dem_lab::tests::brazilian::BrazilianTest;
use dem_lab::tests::senb::SenbTest;
use dem_lab::tests::ucs::UcsTest;
use dem_lab::tests::QuasiStatic;
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

/// The size flags of the rectangular specimens (`dem test ucs`, `dem test biaxial`).
#[derive(Args)]
pub struct RectangleArgs {
    /// Specimen width with unit.
    #[arg(long, default_value = "10mm")]
    pub width: String,
    /// Specimen height with unit (2:1 tall by default).
    #[arg(long, default_value = "20mm")]
    pub height: String,
}

impl RectangleArgs {
    /// `--width` and `--height` (m).
    fn parse(&self) -> Result<[f64; 2], String> {
        Ok([
            parse_length(&self.width, "--width")?,
            parse_length(&self.height, "--height")?,
        ])
    }

    /// [`flag_message`] for the test's `<test>.width` and `<test>.height`.
    fn message(&self, e: LabError, test: &str) -> String {
        size_message(e, test, &self.width, &self.height)
    }
}

/// `dem test ucs` flags.
#[derive(Args)]
pub struct UcsArgs {
    #[command(flatten)]
    pub lab: LabArgs,
    #[command(flatten)]
    pub size: RectangleArgs,
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
    #[command(flatten)]
    pub size: RectangleArgs,
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
        TestKind::Ucs(a) => handle(&a.lab, &a),
        TestKind::Biaxial(a) => handle(&a.lab, &a),
        TestKind::Brazilian(a) => handle(&a.lab, &a),
        TestKind::Bending(a) => handle(&a.lab, &a),
        TestKind::Senb(a) => handle(&a.lab, &a),
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
    mut l: lab::tests::harness::Loading,
) -> Result<lab::tests::harness::Loading, String> {
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
        let spec = cache::prepare(p, shape, &file, &mut |pr: Progress| {
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

/// A run's progress callback (steps done, steps in all).
type Steps<'a> = &'a mut dyn FnMut(u64, u64);

/// What a [`Handler`]'s run gives.
type Ran<H> = Result<<H as Handler>::Out, LabError>;

/// One quasi-static `dem test <test>` from its flags: what [`handle`] needs of it, the rest
/// (specimen, model, run lock, progress, the run) the same for all.
trait Handler: Sync {
    type Test: serde::Serialize + Sync;
    type Out: Send;
    /// The test's name (its file stem, the subcommand's name by default).
    fn name(test: &Self::Test) -> &str;
    /// The specimen's width and height (m) from the flags.
    fn size(&self) -> Result<[f64; 2], String>;
    /// The test from the flags, validated and checked against the nominal particle size of the
    /// specimen flags `p` before anything is generated; errors name the flags.
    fn test(&self, p: &SpecimenParams, size: [f64; 2]) -> Result<Self::Test, String>;
    fn shape(test: &Self::Test) -> Shape;
    /// The typed inputs the run lock is keyed on.
    fn inputs(
        &self,
        p: &SpecimenParams,
        model: &LabModel,
        test: &Self::Test,
    ) -> Result<serde_json::Value, String> {
        inputs(p, model, test)
    }
    /// Runs `test` of model `m` on specimen `s`, reporting to `progress`.
    fn run(&self, test: &Self::Test, m: &LabModel, s: &TestSpecimen, progress: Steps) -> Ran<Self>;
    /// The test's lines on the terminal (`lab`: the shared flags).
    fn print(&self, lab: &LabArgs, o: &Self::Out, model: &LabModel);
}

/// Runs the test `a` describes: specimen parameters and model from the shared flags `lab`, the
/// test from its own, then [`with_specimen`] and the test's lines.
fn handle<H: Handler>(lab: &LabArgs, a: &H) -> Result<ExitCode, String> {
    let [w, h] = a.size()?;
    let p = lab.specimen_params(w, h)?;
    let model = lab.lab_model(&p)?;
    let test = a.test(&p, [w, h])?;
    let o = with_specimen(
        lab,
        &p,
        H::shape(&test),
        (H::name(&test), a.inputs(&p, &model, &test)?),
        |spec, pr| a.run(&test, &model, spec, pr),
    )?;
    a.print(lab, &o, &model);
    Ok(ExitCode::SUCCESS)
}

/// A [`Handler`] of a test run once by [`lab::tests::run`] (all but biaxial): its result file
/// an [`lab::Outcome`], its lines those of [`Simple::print`] and the run's ([`print_run`]).
trait Simple: Sync {
    type Test: QuasiStatic + Send + Sync;
    fn size(&self) -> Result<[f64; 2], String>;
    fn test(&self, p: &SpecimenParams, size: [f64; 2]) -> Result<Self::Test, String>;
    /// The test's own lines (then the run's, [`print_run`]).
    fn print(&self, r: &Report<Self>, model: &LabModel);
}

/// What a [`Simple`] test measured.
type Report<S> = <<S as Simple>::Test as QuasiStatic>::Report;

impl<S: Simple> Handler for S
where
    Report<S>: Send,
{
    type Test = S::Test;
    type Out = lab::Outcome<S::Test, Report<S>>;
    fn name(test: &S::Test) -> &str {
        test.name()
    }
    fn size(&self) -> Result<[f64; 2], String> {
        Simple::size(self)
    }
    fn test(&self, p: &SpecimenParams, size: [f64; 2]) -> Result<S::Test, String> {
        Simple::test(self, p, size)
    }
    fn shape(test: &S::Test) -> Shape {
        test.shape()
    }
    fn run(&self, test: &S::Test, m: &LabModel, s: &TestSpecimen, progress: Steps) -> Ran<Self> {
        lab::tests::run(test, m, s, progress)
    }
    fn print(&self, lab: &LabArgs, o: &Self::Out, model: &LabModel) {
        Simple::print(self, &o.result, model);
        let name = o.test.name();
        print_run(&o.run, &lab.out.join(format!("{name}.result.json")));
    }
}

/// `test` validated (errors as `validate`'s) and passed by `check` (errors through `flags`).
fn checked<T>(
    test: T,
    validate: impl Fn(&T) -> Result<(), LabError>,
    check: impl Fn(&T) -> Result<(), LabError>,
    flags: impl Fn(LabError) -> String,
) -> Result<T, String> {
    validate(&test).map_err(|e| e.to_string())?;
    check(&test).map_err(flags)?;
    Ok(test)
}

impl Simple for UcsArgs {
    fn print(&self, r: &Report<Self>, _: &LabModel) {
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
    }
    fn size(&self) -> Result<[f64; 2], String> {
        self.size.parse()
    }
    fn test(&self, p: &SpecimenParams, [w, h]: [f64; 2]) -> Result<UcsTest, String> {
        let test = UcsTest {
            width: w,
            height: h,
            loading: loading(&self.lab, &self.speed, UcsTest::default().loading)?,
            ..UcsTest::default()
        };
        checked(
            test,
            UcsTest::validate,
            |t| t.check_geometry([w, h], nominal_r_mean(p)),
            |e| self.size.message(e, "ucs"),
        )
    }
    type Test = UcsTest;
}

/// [`flag_message`] for a rectangular specimen's `<test>.width` and `<test>.height`, given as
/// `--width` and `--height`.
fn size_message(e: LabError, test: &str, width: &str, height: &str) -> String {
    let (fw, fh) = (format!("{test}.width"), format!("{test}.height"));
    flag_message(e, &[(&fw, "--width", width), (&fh, "--height", height)])
}

impl Handler for BiaxialArgs {
    type Test = (BiaxialTest, Vec<f64>);
    type Out = lab::tests::biaxial::BiaxialSeries;
    fn name((test, _): &Self::Test) -> &str {
        &test.name
    }
    fn size(&self) -> Result<[f64; 2], String> {
        let size = self.size.parse()?;
        // Checked here too, before the specimen flags, as they always were.
        parse_confinements(&self.confining, "--confining")?;
        Ok(size)
    }
    fn test(&self, p: &SpecimenParams, [w, h]: [f64; 2]) -> Result<Self::Test, String> {
        let confinements = parse_confinements(&self.confining, "--confining")?;
        let test = BiaxialTest {
            width: w,
            height: h,
            loading: loading(&self.lab, &self.speed, BiaxialTest::default().loading)?,
            ..BiaxialTest::default()
        };
        let test = checked(
            test,
            BiaxialTest::validate,
            |t| t.check_geometry([w, h], nominal_r_mean(p)),
            |e| self.size.message(e, "biaxial"),
        )?;
        Ok((test, confinements))
    }
    fn shape((test, _): &Self::Test) -> Shape {
        test.shape()
    }
    fn inputs(
        &self,
        p: &SpecimenParams,
        model: &LabModel,
        (test, confinements): &Self::Test,
    ) -> Result<serde_json::Value, String> {
        inputs(p, model, &(test, confinements))
    }
    fn run(&self, (test, s3): &Self::Test, m: &LabModel, s: &TestSpecimen, pr: Steps) -> Ran<Self> {
        lab::tests::biaxial::run_series(test, s3, m, s, pr)
    }
    fn print(&self, lab: &LabArgs, s: &Self::Out, _: &LabModel) {
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
            lab.out.join("biaxial.result.json").display()
        );
    }
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

impl Simple for BrazilianArgs {
    fn print(&self, r: &Report<Self>, model: &LabModel) {
        let (sigma_t, d_mm, t) = (r.tensile_strength * 1e-6, r.diameter * 1e3, model.thickness);
        println!(
            "σ_t = 2F/(πDt) = {sigma_t:.1} MPa (peak load {:.4e} N, D = {d_mm:.3} mm, t = {t} m)",
            r.peak_load
        );
        println!(
            "platens {:.4e} m/s each; time to peak = {:.1} P-wave transit times",
            r.platen_speed, r.quasi_static_ratio
        );
    }
    fn size(&self) -> Result<[f64; 2], String> {
        let d = parse_length(&self.diameter, "--diameter")?;
        Ok([d, d])
    }
    fn test(&self, p: &SpecimenParams, [d, _]: [f64; 2]) -> Result<BrazilianTest, String> {
        let test = BrazilianTest {
            diameter: d,
            loading: loading(&self.lab, &self.speed, BrazilianTest::default().loading)?,
            ..BrazilianTest::default()
        };
        let flags = [("brazilian.diameter", "--diameter", self.diameter.as_str())];
        checked(
            test,
            BrazilianTest::validate,
            |t| t.check_geometry(d, nominal_r_mean(p)),
            |e| flag_message(e, &flags),
        )
    }
    type Test = BrazilianTest;
}

/// Nominal mean disc radius of the specimen flags (m): (r_min + r_max)/2.
fn nominal_r_mean(p: &SpecimenParams) -> f64 {
    0.5 * (p.r_min + p.r_max)
}

impl Simple for BendingArgs {
    fn print(&self, r: &Report<Self>, model: &LabModel) {
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
    }
    fn size(&self) -> Result<[f64; 2], String> {
        let size = [
            parse_length(&self.length, "--length")?,
            parse_length(&self.height, "--height")?,
        ];
        // Checked here too, before the specimen flags, as it always was.
        parse_length(&self.span, "--span")?;
        Ok(size)
    }
    fn test(&self, p: &SpecimenParams, [l, h]: [f64; 2]) -> Result<BendingTest, String> {
        let span = parse_length(&self.span, "--span")?;
        let test = BendingTest {
            length: l,
            height: h,
            span,
            loading: loading(&self.lab, &self.speed, BendingTest::default().loading)?,
            ..BendingTest::default()
        };
        let flags = [
            ("bending.height", "--height", self.height.as_str()),
            ("bending.span", "--span", self.span.as_str()),
        ];
        checked(
            test,
            BendingTest::validate,
            |t| t.check_geometry([l, h], nominal_r_mean(p)),
            |e| flag_message(e, &flags),
        )
    }
    type Test = BendingTest;
}

fn print_run(run: &lab::tests::harness::RunFacts, result: &std::path::Path) {
    println!(
        "run: {} after {} steps (dt {:.3e} s), {} of {} bonds broken, {:.1} s",
        run.status, run.steps, run.dt, run.bonds_broken, run.bonds, run.wall_time_s
    );
    println!("scene:   {} (dem run it again)", run.scene_file.display());
    println!("outputs: {}", run.out_dir.display());
    println!("result:  {}", result.display());
}

impl Simple for SenbArgs {
    fn print(&self, r: &Report<Self>, model: &LabModel) {
        let (span_mm, depth_mm) = (r.span * 1e3, r.height * 1e3);
        println!(
            "K_IC = P S f(a/W) / (B W^1.5) = {:.3} MPa·m^½ (ASTM E399 SE(B): peak load {:.4e} N, S = {span_mm:.3} mm, W = {depth_mm:.3} mm, a/W = {:.3}, f = {:.3}, B = t = {} m)",
            r.fracture_toughness * 1e-6,
            r.peak_load,
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
    }
    fn size(&self) -> Result<[f64; 2], String> {
        Ok([
            parse_length(&self.length, "--length")?,
            parse_length(&self.height, "--height")?,
        ])
    }
    fn test(&self, p: &SpecimenParams, [l, h]: [f64; 2]) -> Result<SenbTest, String> {
        let notch_width = match &self.notch_width {
            Some(w) => parse_length(w, "--notch-width")?,
            None => p.r_min + p.r_max,
        };
        let test = SenbTest {
            length: l,
            height: h,
            notch_ratio: self.notch_ratio,
            notch_width,
            loading: loading(&self.lab, &self.speed, SenbTest::default().loading)?,
            ..SenbTest::default()
        };
        let ratio = self.notch_ratio.to_string();
        let width = self.notch_width.clone().unwrap_or_default();
        let flags = [
            ("senb.length", "--length", self.length.as_str()),
            ("senb.height", "--height", self.height.as_str()),
            ("senb.notch_ratio", "--notch-ratio", ratio.as_str()),
            ("senb.notch_width", "--notch-width", width.as_str()),
        ];
        test.validate().map_err(|e| flag_message(e, &flags))?;
        test.check_geometry(nominal_r_mean(p))
            .map_err(|e| flag_message(e, &flags))?;
        Ok(test)
    }
    type Test = SenbTest;
}
