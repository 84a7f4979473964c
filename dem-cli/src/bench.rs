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
        BenchKind::Dense(b) => {
            if b.cells.is_some() {
                return Err("--cells applies to `dem bench bonded` only".into());
            }
            solver("dense", b, dem_core::bench::dense_lattice_scene())
        }
        BenchKind::Bonded(b) => {
            let w = match b.cells {
                None => dem_core::bond::bench::bonded_lattice_scene(),
                Some(c) => dem_core::bond::bench::bonded_lattice_world(c),
            };
            solver("bonded", b, w)
        }
    }
}
