//! `dem calibrate`: micro-parameters from a material's measured properties (the procedure of
//! Potyondy & Cundall 2004 used by S4): UCS, three-point bending and Brazilian tests on
//! specimens generated once with the specimen flags, run until E, ν and the strengths match
//! (`dem_lab::calibrate`). Writes the calibrated model (`model.json`, usable with
//! `dem test ... --model`), the calibration record and the table (target vs achieved).

use crate::lab_args::LabArgs;
use crate::progress::Progress;
use clap::Args;
use dem_lab as lab;
use dem_lab::calibrate::virtual_lab::{self, VirtualLab};
use dem_lab::calibrate::{self, MaterialFile, Options};
use dem_lab::specimen::SpecimenParams;
use dem_lab::tests::bending::BendingTest;
use dem_lab::tests::biaxial::BiaxialSeries;
use dem_lab::tests::biaxial::BiaxialTest;
use dem_lab::tests::brazilian::BrazilianTest;
use dem_lab::tests::senb::{SenbReport, SenbTest};
use dem_lab::tests::ucs::UcsTest;
use dem_lab::LabModel;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Args)]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub lab: LabArgs,
    /// Material file with the target properties (`measured`, else `assumed`: E_GPa, poisson,
    /// ucs_MPa, flexural_MPa, brazilian_MPa, kic_MPa_sqrt_m); default: --material.
    #[arg(long)]
    pub targets: Option<PathBuf>,
    /// Largest number of runs per search.
    #[arg(long, default_value_t = 8)]
    pub max_iter: usize,
    /// Relative tolerance on E and the fitted strengths.
    #[arg(long, default_value_t = 0.02)]
    pub tol: f64,
    /// β of K_IC = β σ̄c √(πR̄) (S4; not given there), for the reported toughness.
    #[arg(long, default_value_t = 1.0)]
    pub kic_beta: f64,
    /// Lower bound of the search in κ = k_n/k_s (ν falls with κ). Potyondy & Cundall (2004)
    /// keep κ ≥ 1; a random 2D packing then gives ν ≥ ~0.26, so a lower ν target (SiC: 0.14)
    /// needs a bound below 1 (shear springs stiffer than normal ones), e.g. 0.25.
    #[arg(long, default_value_t = 1.0)]
    pub kappa_min: f64,
    /// UCS specimen width and height, bending beam length, height and span, Brazilian disc
    /// diameter, all with units (defaults: 10mm,20mm 20mm,5mm,16mm 10mm).
    #[arg(long, default_value = "10mm,20mm")]
    pub ucs_size: String,
    #[arg(long, default_value = "20mm,5mm,16mm")]
    pub beam: String,
    #[arg(long, default_value = "10mm")]
    pub disc: String,
    /// After calibrating, measure K_IC with the calibrated model on a single-edge-notched beam
    /// of this length and depth W (`dem test senb`: span 4W, a/W = 0.5, slot one nominal mean
    /// diameter), e.g. `44mm,10mm`; the table gets a `K_IC (SENB)` row and the measured β. If
    /// the SENB fails, the calibration is still written, the table says why, exit code 2.
    #[arg(long)]
    pub senb: Option<String>,
    /// After calibrating, run biaxial tests (`dem test biaxial`) with the calibrated model on
    /// the UCS specimens at these confinements σ3 with unit, e.g. `0MPa,100MPa,200MPa`; the
    /// table gets the friction angle φ, the cohesion c (Mohr–Coulomb over all seeds' peaks)
    /// and UCS/σ_t. If a biaxial run fails, the calibration is still written, exit code 2.
    #[arg(long, value_delimiter = ',')]
    pub biaxial: Vec<String>,
    /// Specimens per test: seeds --seed, --seed + 1, …; every test's value is the mean over
    /// them, and the table states each property's mean ± SE and range (a seed whose specimen
    /// fails to generate is replaced by the next one, with a warning).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=20))]
    pub seeds: u32,
    /// Largest number of calibration passes: another stiffness and strength search from the
    /// last pass's model while its final E or ν is off the tolerance (ν moves with the
    /// strengths).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=5))]
    pub passes: u32,
}

fn lengths(s: &str, flag: &str, n: usize) -> Result<Vec<f64>, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| crate::specimen::parse_length(x.trim(), flag))
        .collect::<Result<_, _>>()?;
    if v.len() != n {
        return Err(format!(
            "{flag} {s:?}: give {n} lengths separated by commas"
        ));
    }
    Ok(v)
}

/// `dem calibrate`: the tests from the flags (checked before any specimen is generated), the
/// folder's lock, the calibration and the measurements after it ([`measure`]), the table with
/// what did not measure stated ([`tabulate`]), the files written atomically. Exit 2 when the
/// SENB or biaxial measurement failed; the calibration is written all the same.
pub fn run(a: CalibrateArgs) -> Result<ExitCode, String> {
    let t0 = Instant::now();
    let targets_file = a
        .targets
        .clone()
        .or_else(|| a.lab.material.clone())
        .ok_or("give --targets or --material: a material file with measured properties")?;
    let mat = MaterialFile::read(&targets_file).map_err(|e| e.to_string())?;
    let targets = mat
        .targets()
        .map_err(|e| format!("{}: {e}", targets_file.display()))?;
    let (tests, p) = Tests::from_flags(&a)?;
    let start = a.lab.lab_model(&p)?;
    let opts = options(&a)?;
    let out = a.lab.out.clone();
    // The folder's lock (`run_lock`), keyed on the material file and the typed inputs.
    let inputs = serde_json::to_value((
        &p,
        &start,
        (&tests.ucs, &tests.bending, &tests.brazilian),
        (a.tol, a.max_iter, a.kic_beta, a.kappa_min),
        &tests.senb,
        (a.seeds, a.passes),
    ))
    .map(|mut v| {
        // Only a calibration with biaxial tests adds them to its key.
        if let (false, Some(a)) = (tests.confinements.is_empty(), v.as_array_mut()) {
            a.push(serde_json::json!(tests.confinements));
        }
        v
    })
    .map_err(|e| e.to_string())?;
    let _lock = crate::run_lock::acquire_noted(
        &out,
        crate::run_lock::Claim {
            command: "dem calibrate",
            scene: &targets_file,
            hash: &crate::run_lock::inputs_hash(&inputs),
        },
        a.lab.force,
    )?;
    let m = measure(&a, &p, &tests, &start, &targets, &opts)?;
    let (table, failed) = tabulate(&a, &mat, p.method.name(), &tests, &m);
    let write = |name: &str, text: String| -> Result<PathBuf, String> {
        let f = out.join(name);
        dem_core::output::write_atomic(&f, text.as_bytes()).map_err(|e| e.to_string())?;
        Ok(f)
    };
    let files = [
        write(
            "model.json",
            pretty(serde_json::to_string_pretty(&m.cal.model))?,
        )?,
        write(
            "calibration.json",
            pretty(serde_json::to_string_pretty(&m.cal))?,
        )?,
        write(
            "calibration-table.json",
            pretty(serde_json::to_string_pretty(&table))?,
        )?,
        write("calibration-table.md", table.markdown())?,
    ];
    println!("{}", table.markdown());
    println!(
        "{} test runs ({:.1} s of runs), {:.1} s in all",
        m.runs,
        m.lab_time,
        t0.elapsed().as_secs_f64()
    );
    for f in files {
        println!("wrote {}", f.display());
    }
    if let Some(e) = &failed.biaxial {
        eprintln!("error: --biaxial: {e}; the calibration is written without the friction angle");
    }
    if let Some(e) = &failed.senb {
        eprintln!("error: --senb: {e}; the calibration is written without the K_IC (SENB) row");
    }
    if failed.senb.is_some() || failed.biaxial.is_some() {
        return Ok(ExitCode::from(2));
    }
    Ok(ExitCode::SUCCESS)
}

/// The tests a calibration runs, read from the flags.
struct Tests {
    ucs: UcsTest,
    bending: BendingTest,
    brazilian: BrazilianTest,
    /// K_IC of the calibrated model (`--senb`), if asked for.
    senb: Option<SenbTest>,
    /// The biaxial confinements (`--biaxial`, Pa): none, or two and more.
    confinements: Vec<f64>,
    biaxial: BiaxialTest,
}

impl Tests {
    /// The tests and the specimens' parameters (the UCS specimen's size), every geometry
    /// checked against the particle size first (issue 20: geometry the particle size makes
    /// meaningless is refused before generating); errors name the flag.
    fn from_flags(a: &CalibrateArgs) -> Result<(Tests, SpecimenParams), String> {
        let u = lengths(&a.ucs_size, "--ucs-size", 2)?;
        let b = lengths(&a.beam, "--beam", 3)?;
        let d = lengths(&a.disc, "--disc", 1)?[0];
        let ucs = UcsTest {
            width: u[0],
            height: u[1],
            ..UcsTest::default()
        };
        let bending = BendingTest {
            length: b[0],
            height: b[1],
            span: b[2],
            ..BendingTest::default()
        };
        let brazilian = BrazilianTest {
            diameter: d,
            ..BrazilianTest::default()
        };
        let p = a.lab.specimen_params(ucs.width, ucs.height)?;
        let r_mean = 0.5 * (p.r_min + p.r_max);
        ucs.check_geometry([ucs.width, ucs.height], r_mean)
            .map_err(|e| format!("--ucs-size {}: {e}", a.ucs_size))?;
        bending
            .check_geometry([bending.length, bending.height], r_mean)
            .map_err(|e| format!("--beam {}: {e}", a.beam))?;
        brazilian
            .check_geometry(brazilian.diameter, r_mean)
            .map_err(|e| format!("--disc {}: {e}", a.disc))?;
        let senb = match &a.senb {
            Some(s) => {
                let v = lengths(s, "--senb", 2)?;
                let t = SenbTest {
                    name: "senb".into(),
                    length: v[0],
                    height: v[1],
                    notch_width: p.r_min + p.r_max,
                    ..SenbTest::default()
                };
                t.validate()
                    .and_then(|_| t.check_geometry(r_mean))
                    .map_err(|e| format!("--senb {s}: {e}"))?;
                Some(t)
            }
            None => None,
        };
        let confinements = crate::test::parse_confinements(&a.biaxial, "--biaxial")?;
        if confinements.len() == 1 {
            return Err(format!(
                "--biaxial {}: give two or more confinements (a friction angle needs two)",
                a.biaxial[0]
            ));
        }
        let biaxial = BiaxialTest {
            name: "biaxial".into(),
            width: ucs.width,
            height: ucs.height,
            ..BiaxialTest::default()
        };
        let tests = Tests {
            ucs,
            bending,
            brazilian,
            senb,
            confinements,
            biaxial,
        };
        Ok((tests, p))
    }
}

/// The search's options from the flags; `--kappa-min` checked against the upper bound.
fn options(a: &CalibrateArgs) -> Result<Options, String> {
    let opts = Options {
        rel_tol: a.tol,
        max_iter: a.max_iter,
        passes: a.passes as usize,
        kic_beta: a.kic_beta,
        kappa_bounds: [a.kappa_min, Options::default().kappa_bounds[1]],
        ..Options::default()
    };
    if !(a.kappa_min > 0.0 && a.kappa_min <= opts.kappa_bounds[1]) {
        return Err(format!(
            "--kappa-min {}: must be positive and at most the upper bound {}",
            a.kappa_min, opts.kappa_bounds[1]
        ));
    }
    Ok(opts)
}

/// The SENB reports of the seeds run, and those seeds.
type SenbSeeds = (Vec<SenbReport>, Vec<u64>);

/// What [`measure`] ran: the calibration, then the measurements made with its model (each
/// `None` when not asked for, `Some(Err)` when it failed), and the virtual lab's bookkeeping.
struct Measured {
    cal: calibrate::Calibration,
    /// K_IC per seed (`--senb`) and the seeds.
    senb: Option<Result<SenbSeeds, String>>,
    /// One biaxial series per UCS seed (`--biaxial`).
    biaxial: Option<Result<Vec<BiaxialSeries>, String>>,
    runs: usize,
    lab_time: f64,
    seeds: [Vec<u64>; 3],
    last: virtual_lab::LastRuns,
}

/// Generates the specimens, calibrates, then measures K_IC and the friction angle with the
/// calibrated model, on the lab's thread pool with a progress bar. A failed measurement after
/// the calibration (e.g. a notched beam that does not generate, or a drop the analysis
/// refuses) is returned in [`Measured`] and does not lose the calibration.
fn measure(
    a: &CalibrateArgs,
    p: &SpecimenParams,
    tests: &Tests,
    start: &LabModel,
    targets: &calibrate::Targets,
    opts: &Options,
) -> Result<Measured, String> {
    let out = &a.lab.out;
    let bar = Progress::stages();
    bar.set_prefix("calibrate");
    let pool = a.lab.pool()?;
    let m = pool.install(|| {
        let mut log = |l: &str| {
            bar.println(l);
            bar.set_message(l.to_string());
            if bar.is_hidden() {
                eprintln!("{l}");
            }
        };
        let n = a.seeds as usize;
        let (ucs, bending, brazilian) = (
            tests.ucs.clone(),
            tests.bending.clone(),
            tests.brazilian.clone(),
        );
        let mut lab = VirtualLab::prepare(p, out, ucs, bending, brazilian, n, &mut log)
            .map_err(|e| e.to_string())?;
        for s in (lab.ucs_specimen.iter())
            .chain(&lab.bending_specimen)
            .chain(&lab.brazilian_specimen)
        {
            crate::lab_args::strict_cover(&a.lab, s).map_err(|e| e.to_string())?;
            for l in crate::specimen::cover_lines(&s.file, &s.below_cover) {
                log(&format!("warning: {l}"));
            }
        }
        let c = calibrate::calibrate(&mut lab, start, targets, opts, &mut log)
            .map_err(|e| e.to_string())?;
        let senb = tests.senb.as_ref().map(|t| {
            let (specs, seeds) = virtual_lab::prepare_seeds(p, out, "senb", t.shape(), n, &mut log)
                .map_err(|e| e.to_string())?;
            log("senb: K_IC with the calibrated model");
            let mut all = Vec::new();
            for (k, (spec, &seed)) in specs.iter().zip(&seeds).enumerate() {
                let t = SenbTest {
                    name: virtual_lab::test_name(&t.name, k, seed),
                    ..t.clone()
                };
                let o = lab::tests::run(&t, &c.model, spec, &mut |_, _| {})
                    .map_err(|e| format!("seed {seed}: {e}"))?;
                all.push(o.result);
            }
            Ok::<_, String>((all, seeds))
        });
        // The biaxial tests, on the UCS specimens.
        let biaxial = (!tests.confinements.is_empty()).then(|| {
            log("biaxial: friction angle with the calibrated model");
            let mut all = Vec::new();
            for (k, (spec, &seed)) in lab.ucs_specimen.iter().zip(&lab.seeds[0]).enumerate() {
                let t = BiaxialTest {
                    name: virtual_lab::test_name(&tests.biaxial.name, k, seed),
                    ..tests.biaxial.clone()
                };
                let s = lab::tests::biaxial::run_series(
                    &t,
                    &tests.confinements,
                    &c.model,
                    spec,
                    &mut |_, _| {},
                )
                .map_err(|e| format!("seed {seed}: {e}"))?;
                all.push(s);
            }
            Ok::<_, String>(all)
        });
        Ok::<_, String>(Measured {
            cal: c,
            senb,
            biaxial,
            runs: lab.runs,
            lab_time: lab.wall_time_s,
            seeds: lab.seeds,
            last: lab.last,
        })
    })?;
    bar.finish_and_clear();
    Ok(m)
}

/// Why a measurement after the calibration is missing from the table.
#[derive(Default)]
struct Failed {
    senb: Option<String>,
    biaxial: Option<String>,
}

/// The calibration table: the calibrated rows, K_IC and the friction angle where they
/// measured (a note where not), and with more than one seed the seeds' scatter of each
/// property.
fn tabulate(
    a: &CalibrateArgs,
    mat: &MaterialFile,
    method: &str,
    tests: &Tests,
    m: &Measured,
) -> (calibrate::Table, Failed) {
    let mut table = calibrate::table(mat, method, &m.cal);
    let mut failed = Failed::default();
    let senb = match &m.senb {
        Some(Ok(s)) => {
            table.add_senb(&mean_senb(&s.0));
            Some(s)
        }
        Some(Err(e)) => {
            table.notes.push(format!("K_IC (SENB) not measured: {e}"));
            failed.senb = Some(e.clone());
            None
        }
        None => None,
    };
    match &m.biaxial {
        Some(Ok(all)) => {
            let pts: Vec<(f64, f64)> = (all.iter().flat_map(|s| &s.results))
                .map(|r| (r.sigma3, r.sigma1))
                .collect();
            match lab::analysis::mohr_coulomb(&pts) {
                Some(fit) => {
                    table.add_biaxial(&fit, &tests.confinements);
                    if all.len() > 1 {
                        let phi: Vec<f64> = (all.iter())
                            .map(|s| s.mohr_coulomb.map_or(f64::NAN, |m| m.friction_angle_deg))
                            .collect();
                        if phi.iter().all(|x| x.is_finite()) {
                            table.notes.push(calibrate::seed_scatter(
                                "friction angle φ (each seed's own fit)",
                                "°",
                                1.0,
                                &m.seeds[0],
                                &phi,
                            ));
                        }
                    }
                }
                None => {
                    let e =
                        "the peak strength does not rise with the confinement: no friction angle";
                    table.notes.push(format!("biaxial: {e}"));
                    failed.biaxial = Some(e.to_string());
                }
            }
        }
        Some(Err(e)) => {
            table
                .notes
                .push(format!("friction angle not measured: {e}"));
            failed.biaxial = Some(e.clone());
        }
        None => {}
    }
    if a.seeds > 1 {
        let [s_ucs, s_bend, s_braz] = &m.seeds;
        let last = &m.last;
        let ucs_of = |f: fn(&dem_lab::analysis::UcsResult) -> f64| -> Vec<f64> {
            last.ucs.iter().map(f).collect()
        };
        let mut notes = vec![
            calibrate::seed_scatter("E", "GPa", 1e9, s_ucs, &ucs_of(|r| r.young)),
            calibrate::seed_scatter("ν", "", 1.0, s_ucs, &ucs_of(|r| r.poisson)),
            calibrate::seed_scatter("UCS", "MPa", 1e6, s_ucs, &ucs_of(|r| r.ucs)),
            calibrate::seed_scatter("σ_f", "MPa", 1e6, s_bend, &last.bending),
            calibrate::seed_scatter("Brazilian σ_t", "MPa", 1e6, s_braz, &last.brazilian),
        ];
        if let Some((all, s)) = senb {
            let k: Vec<f64> = all.iter().map(|r| r.fracture_toughness).collect();
            notes.push(calibrate::seed_scatter(
                "K_IC (SENB)",
                "MPa·m^½",
                1e6,
                s,
                &k,
            ));
        }
        table.notes.extend(notes);
    }
    (table, failed)
}

fn pretty(r: Result<String, serde_json::Error>) -> Result<String, String> {
    r.map(|s| s + "\n").map_err(|e| e.to_string())
}

/// The SENB report whose toughness, peak load, β and crack-mouth opening are the means over
/// the seeds' reports (the geometry is the same beam on every seed).
fn mean_senb(all: &[SenbReport]) -> SenbReport {
    let n = all.len() as f64;
    let m = |f: fn(&lab::tests::senb::SenbReport) -> f64| all.iter().map(f).sum::<f64>() / n;
    lab::tests::senb::SenbReport {
        fracture_toughness: m(|r| r.fracture_toughness),
        peak_load: m(|r| r.peak_load),
        beta: m(|r| r.beta),
        cmod_at_peak: m(|r| r.cmod_at_peak),
        ..all[0].clone()
    }
}
