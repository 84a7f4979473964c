//! `dem bench`: speed figures (never timed tests). Each variant prints its figure as its last line.

use clap::{Args, Subcommand};
use clumpgen::batch::collect_inputs;
use clumpgen::{make_template, read_outline, ClumpParams, Outline, ReadOptions, Units};
use rayon::prelude::*;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Subcommand)]
pub enum BenchKind {
    /// Clump generation: grains per second at the given cover, on one thread and on all.
    Clump(ClumpBench),
    /// The dense 2D lattice of shared/bench/lammps-dense2d.in (46,000 discs, periodic, linear
    /// spring-dashpot with history, dt 1 µs): particle-steps per second.
    Dense(SolverBench),
    /// The same lattice with a parallel bond at every contact (≈138,000 bonds), automatic dt.
    Bonded(SolverBench),
    /// The cutting scene `dem test cutting` runs (specimen, slot walls, rigid tool, local
    /// damping, history rows, guard), timed once the tool is in the specimen.
    Cutting(CuttingBench),
    /// The Chung & Ooi (2011) impact benchmark (tests 1–8, `validation::chung_ooi`): a table
    /// of each figure against its closed form (and LAMMPS where the committed peer file has
    /// it); exit status 1 if an asserted figure is 1 % or more off. The last line is the
    /// worst asserted error.
    ChungOoi(ChungOoiBench),
}

/// `dem bench chung-ooi` flags.
#[derive(Args)]
pub struct ChungOoiBench {
    /// Write `chung_ooi.json` (schema dem.chung-ooi/1) and the SVG figures here.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Time step = t_c / this.
    #[arg(long, default_value_t = 2000)]
    steps_per_contact: u32,
    /// The LAMMPS results (`scripts/chung-ooi-lammps.sh`); skipped if absent.
    #[arg(long, default_value = "data/peers/chung-ooi-lammps.json")]
    peer: PathBuf,
}

/// `dem bench cutting` flags.
#[derive(Args)]
pub struct CuttingBench {
    /// Steps timed (default 20,000), after an untimed approach in which the tool travels to
    /// the specimen and a_p (1 mm) into it. A multiple of 100 (the guard's cadence) ends the
    /// timing right after the last step's checks; otherwise the run's closing writes (final
    /// checkpoint, summary) are timed too.
    #[arg(long, default_value_t = 20000)]
    steps: u64,
    /// Worker threads, at least 1; results are bit-identical for any count.
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Specimen generation: traditional | orc | improved.
    #[arg(long, default_value = "traditional")]
    method: String,
    /// Specimen generation: random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Specimen generation: the Table 2 size, 20 × 10 mm (default 10 × 5 mm, which starts in
    /// seconds); radii 0.175–0.285 mm, grains 0.86 mm, template r_min 0.08 mm either way.
    #[arg(long)]
    table2: bool,
    /// A specimen file written by `dem specimen` instead of generating one (the model is
    /// still --model).
    #[arg(long)]
    specimen: Option<PathBuf>,
    /// The LabModel the scene runs with (`dem calibrate` writes one).
    #[arg(long, default_value = "data/models/si3n4.model.json")]
    model: PathBuf,
    /// Specimen generation: the material file.
    #[arg(long, default_value = "data/materials/si3n4.json")]
    material: PathBuf,
    /// Cutting speed (m/s). Default 10: the approach takes a tenth of the steps it takes at
    /// Table 2's 1 m/s; the cost of a step hardly depends on it.
    #[arg(long, default_value_t = 10.0)]
    speed: f64,
    /// Frame of reference of the local damping: fragment (relative to each disc's bonded
    /// fragment; the cutting test's default) | lab (PFC; `dem test cutting --damping-frame`)
    #[arg(long, default_value = "fragment")]
    damping_frame: String,
}

#[derive(Args)]
pub struct SolverBench {
    /// Steps timed (after one untimed warm-up step that builds the neighbour list).
    #[arg(long, default_value_t = 2000)]
    steps: u64,
    /// Worker threads; results are bit-identical for any count.
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Lattice size `NX,NY` in hex cells of two discs (bonded only; default the full
    /// 200,115 = 46,000 discs). E.g. 30,25 = 1,500 discs, the size of a cutting specimen.
    #[arg(long, value_parser = parse_cells)]
    cells: Option<[usize; 2]>,
    /// Bonded only: flat joints of this many elements (1–8; Potyondy 2012) instead of parallel
    /// bonds, with the same stiffness and strengths.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=8))]
    flat_joint: Option<u8>,
}

fn parse_cells(s: &str) -> Result<[usize; 2], String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("expected NX,NY, got `{s}`"))?;
    let p = |t: &str| -> Result<usize, String> {
        match t.trim().parse::<usize>() {
            Ok(v) if v >= 3 => Ok(v),
            _ => Err(format!("lattice cells must be integers >= 3, got `{t}`")),
        }
    };
    Ok([p(a)?, p(b)?])
}

/// Builds the scene in memory, runs it, prints the stage times; the last line is the figure.
fn solver(name: &str, b: SolverBench, world: dem_core::World) -> Result<ExitCode, String> {
    if b.steps == 0 || b.threads == 0 {
        return Err("--steps and --threads must be at least 1".into());
    }
    let mut w = world;
    let rate = dem_core::bench::run_bench_timed(&mut w, b.steps, b.threads);
    w.check()
        .map_err(|e| format!("{name} benchmark stopped by the guard: {e}"))?;
    let bonds = w.bonds.as_ref().map_or(0, |x| x.n_intact());
    println!(
        "{name}: {} discs, {bonds} intact bonds, {} steps of dt {:.3e} s on {} thread(s)",
        w.state.discs.len(),
        b.steps,
        w.dt(),
        b.threads
    );
    print!("{}", w.counters.report());
    println!("state digest: {:016x}", digest(&w));
    if let Some(c) = rate.cpu {
        println!("particle-steps per CPU-second (all threads): {c:.4e}");
    }
    println!("particle-steps/s: {:.4e}", rate.wall);
    Ok(ExitCode::SUCCESS)
}

/// A 64-bit FNV-1a digest of the bits of the disc state and the bond forces: equal digests
/// across thread counts and builds show bit-identical runs.
fn digest(w: &dem_core::World) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |v: u64| {
        for b in v.to_le_bytes() {
            h = (h ^ b as u64).wrapping_mul(0x100_0000_01b3);
        }
    };
    let d = &w.state.discs;
    for a in [
        &d.x, &d.y, &d.theta, &d.vx, &d.vy, &d.omega, &d.fx, &d.fy, &d.torque,
    ] {
        a.iter().for_each(|v| eat(v.to_bits()));
    }
    if let Some(b) = &w.bonds {
        for v in b.iter() {
            eat(v.fn_.to_bits());
            eat(v.fs.to_bits());
            eat(v.m.to_bits());
        }
    }
    h
}

#[derive(Args)]
pub struct ClumpBench {
    /// Outline files or folders.
    #[arg(default_value = "data/outlines")]
    inputs: Vec<PathBuf>,
    #[arg(long, default_value_t = 0.95)]
    cover: f64,
    /// Repetitions; the median is reported.
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Units override for the outline files (e.g. px with --px-scale).
    #[arg(long)]
    units: Option<String>,
    #[arg(long)]
    px_scale: Option<f64>,
    /// Raster cells along a grain's longer side.
    #[arg(long, default_value_t = ClumpParams::default().raster)]
    raster: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn clump(b: ClumpBench) -> Result<ExitCode, String> {
    let units = b
        .units
        .as_deref()
        .map(|u| Units::parse(u, b.px_scale).map_err(|e| e.to_string()))
        .transpose()?;
    let read = ReadOptions {
        units,
        ..ReadOptions::default()
    };
    let inputs = collect_inputs(&b.inputs).map_err(|e| e.to_string())?;
    let outlines: Vec<Outline> = inputs
        .iter()
        .filter_map(|i| read_outline(&i.path, &read).ok())
        .collect();
    if outlines.is_empty() {
        return Err("no readable outlines".into());
    }
    let p = ClumpParams {
        cover: b.cover,
        raster: b.raster,
        ..ClumpParams::default()
    };
    p.check()
        .map_err(|e| format!("--{} {}: {}", e.name, e.value, e.reason))?;
    let run = |threads: usize| -> Result<(f64, usize), String> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| e.to_string())?;
        let mut rates = vec![];
        let mut ok = 0;
        for _ in 0..b.repeats.max(1) {
            let t0 = Instant::now();
            ok = pool.install(|| {
                outlines
                    .par_iter()
                    .filter(|o| make_template(o, &p).is_ok())
                    .count()
            });
            rates.push(outlines.len() as f64 / t0.elapsed().as_secs_f64());
        }
        Ok((median(rates), ok))
    };
    // Per-grain times on one thread (median over grains, best of the repeats per grain).
    let mut per_grain: Vec<f64> = outlines
        .iter()
        .map(|o| {
            (0..b.repeats.max(1))
                .map(|_| {
                    let t0 = Instant::now();
                    let _ = make_template(o, &p);
                    t0.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    per_grain.sort_by(f64::total_cmp);
    let all = rayon::current_num_threads();
    let (one, ok) = run(1)?;
    let (many, _) = run(all)?;
    println!(
        "grains: {} ({} succeeded), cover target {}, median of {} runs",
        outlines.len(),
        ok,
        b.cover,
        b.repeats
    );
    println!(
        "1 thread:  {one:.1} grains/s; per grain median {:.3} ms, 90th percentile {:.3} ms",
        per_grain[per_grain.len() / 2] * 1e3,
        per_grain[per_grain.len() * 9 / 10] * 1e3
    );
    println!("{all} threads: {many:.1} grains/s");
    println!("grains/s: {many:.1}");
    Ok(ExitCode::SUCCESS)
}

pub fn run(k: BenchKind) -> Result<ExitCode, String> {
    match k {
        BenchKind::Clump(b) => clump(b),
        BenchKind::Cutting(b) => cutting(b),
        BenchKind::ChungOoi(b) => chung_ooi(b),
        BenchKind::Dense(b) => {
            if b.cells.is_some() || b.flat_joint.is_some() {
                return Err("--cells and --flat-joint apply to `dem bench bonded` only".into());
            }
            solver("dense", b, dem_core::bench::dense_lattice_scene())
        }
        BenchKind::Bonded(b) => {
            use dem_core::bond::bench::{
                bonded_lattice_with, lattice_bond_group, lattice_flat_joint_group,
            };
            let w = match b.flat_joint {
                None => bonded_lattice_with(b.cells, &lattice_bond_group),
                Some(n) => bonded_lattice_with(b.cells, &|t| lattice_flat_joint_group(t, n)),
            };
            solver("bonded", b, w)
        }
    }
}

/// A temporary folder removed when dropped.
struct TempDir(PathBuf);

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `dem bench cutting`: builds the scene as `dem test cutting` does
/// ([`dem_lab::cutting::CuttingScene::build`]), runs it through the same driver
/// ([`dem_core::output::driver::Simulation`]) up to the engaged tool (untimed), then times
/// `--steps` more steps of the run.
fn cutting(b: CuttingBench) -> Result<ExitCode, String> {
    use dem_core::output::driver::{RunOptions, Simulation};
    use dem_lab::cutting::{CuttingScene, CuttingTest};
    if b.steps == 0 {
        return Err("--steps: must be at least 1".into());
    }
    if b.threads == 0 {
        return Err("--threads: must be at least 1".into());
    }
    if !(b.speed > 0.0 && b.speed.is_finite()) {
        return Err(format!(
            "--speed: {} must be a positive speed in m/s",
            b.speed
        ));
    }
    if !["traditional", "orc", "improved"].contains(&b.method.as_str()) {
        return Err(format!(
            "--method: `{}` is not traditional, orc or improved",
            b.method
        ));
    }
    let text = clumpgen::io::read_input_string(&b.model)
        .map_err(|e| format!("--model {}: {e}", b.model.display()))?;
    let model: dem_lab::LabModel =
        serde_json::from_str(&text).map_err(|e| format!("--model {}: {e}", b.model.display()))?;
    let dir =
        TempDir(std::env::temp_dir().join(format!("dem-bench-cutting-{}", std::process::id())));
    std::fs::create_dir_all(&dir.0).map_err(|e| format!("{}: {e}", dir.0.display()))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(b.threads)
        .build()
        .map_err(|e| e.to_string())?;
    let (w, h) = if b.table2 {
        (20e-3, 10e-3)
    } else {
        (10e-3, 5e-3)
    };
    let specimen = match &b.specimen {
        Some(p) => {
            if !p.is_file() {
                return Err(format!("--specimen {}: no such file", p.display()));
            }
            p.clone()
        }
        None => {
            // Table 2's specimen (docs/cutting.md): radii 0.175-0.285 mm, grains 0.86 mm,
            // template discs from 0.08 mm, the material file's density and moduli.
            let in_material = |e: String| format!("--material {}: {e}", b.material.display());
            let (method, _) =
                crate::specimen::method_and_dist(&b.method, "normal").map_err(in_material)?;
            let (_, density, e, tensile) =
                crate::specimen::material_values(Some(&b.material), None, None, None)
                    .map_err(in_material)?;
            let mut p = dem_lab::specimen::SpecimenParams::new(
                method, w, h, 0.175e-3, 0.285e-3, density, e, tensile, b.seed,
            );
            p.grain_size = 0.86e-3;
            p.template_r_min = 0.08e-3;
            p.validate().map_err(|e| in_material(e.to_string()))?;
            let name = crate::specimen::read_material(&b.material)
                .map_err(|e| format!("--material {}: {e}", b.material.display()))?
                .0;
            let s = pool
                .install(|| dem_lab::specimen::generate(&p, &mut |_| {}))
                .map_err(|e| format!("specimen generation: {e}"))?;
            let path = dir.0.join("specimen.json");
            dem_lab::specimen::io::save(&s, &name, &path).map_err(|e| e.to_string())?;
            path
        }
    };
    // Table 2's test (a_p 1 mm, L 10 mm, rigid tool, local damping 0.7 in --damping-frame)
    // at --speed; the cut
    // length is the specimen's width when that is shorter.
    // Errors about a given specimen name the flag.
    let named = |e: dem_lab::LabError| match &b.specimen {
        Some(p) => format!("--specimen {}: {e}", p.display()),
        None => e.to_string(),
    };
    let info = dem_lab::cutting::SpecimenInfo::read(&specimen).map_err(named)?;
    let width = info.extent[1] - info.extent[0];
    let test = CuttingTest {
        damping_frame: b
            .damping_frame
            .parse()
            .map_err(|e| format!("--damping-frame: {e}"))?,
        ..CuttingTest::new(1e-3, b.speed, width.min(10e-3))
    }
    .check()
    .map_err(|e| e.to_string())?;
    let scene_file = dir.0.join("cutting.scene.json");
    let mut cs = CuttingScene::build(&test, &model, &info, &scene_file, 0).map_err(named)?;
    let world = cs.take_world().ok_or("cutting scene: no world built")?;
    dem_lab::run::write_scene(&cs.scene, &scene_file).map_err(|e| e.to_string())?;
    let loaded =
        dem_core::scene::resolve(cs.scene.clone(), &scene_file).map_err(|e| e.to_string())?;
    let guard = loaded.outputs.guard_every.max(1);
    // The approach: to the specimen's edge and a_p into it, rounded up to the guard's cadence.
    let g = &cs.geometry;
    let travel = g.travel_entry + test.depth - g.travel_start;
    let approach = ((travel / (b.speed * cs.dt)).ceil() as u64).div_ceil(guard) * guard;
    let end = approach + b.steps;
    if end > cs.steps {
        return Err(format!(
            "--steps: {} steps after the {approach}-step approach pass the cut's end ({} steps)",
            b.steps, cs.steps
        ));
    }
    let opts = RunOptions {
        out_dir: Some(dir.0.clone()),
        restart: None,
        max_steps: Some(approach),
    };
    // (Built and run inside the pool, as `dem test cutting` does: a run's step hook is not
    // `Send`.)
    let timed = pool.install(|| -> Result<_, String> {
        let mut sim = Simulation::with_world(loaded, world, &opts).map_err(|e| e.to_string())?;
        if let Some(hk) = cs.hook() {
            sim.set_hook(hk);
        }
        sim.run(&mut |_, _| {})
            .map_err(|e| format!("approach: {e}"))?;
        sim.set_max_steps(Some(end));
        sim.world.counters.reset();
        let c0 = dem_core::bench::process_cpu_seconds();
        let t0 = Instant::now();
        let mut stop: Option<(f64, Option<f64>)> = None;
        sim.run(&mut |done, _| {
            if done >= end && stop.is_none() {
                stop = Some((
                    t0.elapsed().as_secs_f64(),
                    dem_core::bench::process_cpu_seconds(),
                ));
            }
        })
        .map_err(|e| format!("timed steps: {e}"))?;
        let (secs, c1) = stop.unwrap_or((t0.elapsed().as_secs_f64(), None));
        Ok((secs, c0, c1, sim.world))
    });
    let (secs, c0, c1, world) = timed?;
    let wo = &world;
    let discs = wo.state.discs.len();
    let bonds = wo.bonds.as_ref().map_or(0, |x| x.n_intact());
    let work = discs as f64 * b.steps as f64;
    let what = match &b.specimen {
        Some(p) => p.display().to_string(),
        None => format!(
            "{} specimen {} x {} mm, seed {}",
            b.method,
            w * 1e3,
            h * 1e3,
            b.seed
        ),
    };
    println!(
        "cutting ({what}; v {} m/s, a history row every {} steps): {discs} discs, {bonds} intact \
         bonds, {} walls, {} steps of dt {:.3e} s from step {approach} (tool edge {:.3} mm into \
         the specimen) on {} thread(s)",
        b.speed,
        cs.every,
        wo.state.walls.len(),
        b.steps,
        wo.dt(),
        (g.travel(wo.state.time) - g.travel_entry) * 1e3,
        b.threads
    );
    print!("{}", wo.counters.report());
    println!("state digest: {:016x}", digest(wo));
    println!("steps/s: {:.4e}", b.steps as f64 / secs);
    if let Some(c) = c0.zip(c1).map(|(a, z)| work / (z - a).max(1e-9)) {
        println!("particle-steps per CPU-second (all threads): {c:.4e}");
    }
    println!("particle-steps/s: {:.4e}", work / secs);
    Ok(ExitCode::SUCCESS)
}

/// `dem bench chung-ooi`: runs the eight tests, prints every figure, writes the results.
fn chung_ooi(b: ChungOoiBench) -> Result<ExitCode, String> {
    use validation::chung_ooi::{run_all, Peer, TOLERANCE_PCT};
    if b.steps_per_contact < 100 {
        return Err("--steps-per-contact must be at least 100".into());
    }
    let mut r = run_all(b.steps_per_contact);
    // The peer file as given, else relative to the repository the binary was built in.
    let peer_path = if b.peer.exists() {
        b.peer.clone()
    } else {
        std::path::Path::new(validation::REPOSITORY).join(&b.peer)
    };
    let peer = if peer_path.exists() {
        Some(Peer::read(&peer_path).map_err(|e| e.to_string())?)
    } else {
        None
    };
    println!(
        "{:>4}  {:<34} {:<24} {:>14} {:>14} {:>10} {:>14}  asserted",
        "test", "case", "figure", "ours", "closed form", "error %", "LAMMPS"
    );
    for c in &r.checks {
        let lmp = peer
            .as_ref()
            .and_then(|p| p.value(c))
            .map_or("—".to_string(), |v| format!("{v:.6e}"));
        println!(
            "{:>4}  {:<34} {:<24} {:>14.6e} {:>14.6e} {:>10.4} {:>14}  {}",
            c.test,
            c.case,
            c.figure,
            c.ours,
            c.closed_form,
            c.error_pct,
            lmp,
            if c.asserted { "yes" } else { "no" },
        );
    }
    if let Some(p) = &peer {
        println!("LAMMPS: {} {} ({})", p.code, p.version, p.how);
        for n in &p.not_run {
            println!("LAMMPS did not run: {n}");
        }
    }
    if let Some(p) = &peer {
        r.add_peer(p);
    }
    if let Some(dir) = &b.out {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let write = |name: &str, bytes: &[u8]| {
            let path = dir.join(name);
            clumpgen::io::write_atomic(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))
        };
        let json = serde_json::to_string_pretty(&r).map_err(|e| e.to_string())? + "\n";
        write("chung_ooi.json", json.as_bytes())?;
        for f in r.figures().map_err(|e| e.to_string())? {
            write(&f.file, f.svg.as_bytes())?;
        }
    }
    println!(
        "{} asserted figures, {} at {TOLERANCE_PCT} % or more; {} reported only; {:.2} s",
        r.asserted,
        r.failed,
        r.checks.len() - r.asserted,
        r.wall_time_s
    );
    println!("worst asserted error: {:.4} %", r.worst_asserted_pct);
    Ok(if r.failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
