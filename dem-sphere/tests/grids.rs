//! The single and multi-level grids give the brute-force pair set; whole runs with either
//! grid are bit-identical; results are bit-identical for 1 and 2 threads.

mod common;
use common::*;
use dem_sphere::pack::insert_rsi;
use dem_sphere::rng::SplitMix64;
use dem_sphere::{find_pairs, find_pairs_brute, GridKind, Periodic, World};
use nalgebra::Vector3;

fn bidisperse(n: usize, ratio: f64, phi: f64, seed: u64) -> (Vec<Vector3<f64>>, Vec<f64>) {
    // Equal volumes of small (r = 1) and large (r = ratio) spheres.
    let nl = ((n as f64) / (1.0 + ratio.powi(3))).round().max(1.0) as usize;
    let mut radii = vec![ratio; nl];
    radii.resize(n, 1.0);
    let vol: f64 = radii
        .iter()
        .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r * r * r)
        .sum();
    let l = (vol / phi).cbrt().max(2.5 * ratio);
    let p = insert_rsi(&radii, Vector3::zeros(), Vector3::repeat(l), seed, 100_000).unwrap();
    p.into_iter().unzip()
}

#[test]
fn both_grids_find_the_brute_force_pairs() {
    for (k, &ratio) in [1.0, 3.0, 10.0].iter().enumerate() {
        let (x, r) = bidisperse(1500, ratio, 0.3, k as u64);
        let margin = 0.3;
        let brute = find_pairs_brute(&Periodic::none(), &x, &r, margin);
        let (single, s1) = find_pairs(GridKind::Single, &Periodic::none(), &x, &r, margin);
        let (multi, s2) = find_pairs(
            GridKind::MultiLevel { ratio: 2.0 },
            &Periodic::none(),
            &x,
            &r,
            margin,
        );
        println!(
            "ratio {ratio}: {} pairs; tests single {} ({} level), multi-level {} ({} levels)",
            brute.len(),
            s1.tests,
            s1.levels,
            s2.tests,
            s2.levels
        );
        assert_eq!(single, brute);
        assert_eq!(multi, brute);
        assert!(!brute.is_empty());
    }
    // A continuous distribution, several level ratios.
    let mut rng = SplitMix64::new(9);
    let radii: Vec<f64> = (0..1200).map(|_| rng.range(0.1, 1.0)).collect();
    let (x, r): (Vec<_>, Vec<_>) =
        insert_rsi(&radii, Vector3::zeros(), Vector3::repeat(20.0), 1, 100_000)
            .unwrap()
            .into_iter()
            .unzip();
    let brute = find_pairs_brute(&Periodic::none(), &x, &r, 0.05);
    for q in [1.5, 2.0, 3.0] {
        assert_eq!(
            find_pairs(
                GridKind::MultiLevel { ratio: q },
                &Periodic::none(),
                &x,
                &r,
                0.05
            )
            .0,
            brute
        );
    }
}

#[test]
fn periodic_grids_find_the_minimum_image_pairs() {
    let mut rng = SplitMix64::new(4);
    for (k, &(ratio, l)) in [(1.0, 12.0), (10.0, 45.0), (4.0, 9.0)].iter().enumerate() {
        let n = 800;
        let radii: Vec<f64> = (0..n)
            .map(|i| if i % 97 == 0 { ratio } else { 1.0 })
            .collect();
        // Unwrapped positions: some far outside the cell.
        let x: Vec<Vector3<f64>> = (0..n)
            .map(|_| {
                let p = Vector3::new(rng.range(0.0, l), rng.range(0.0, l), rng.range(0.0, l));
                p + Vector3::new(
                    l * rng.range(-3.0, 3.0).round(),
                    0.0,
                    -l * rng.range(0.0, 2.0).round(),
                )
            })
            .collect();
        let per = Periodic {
            lo: Vector3::zeros(),
            len: [Some(l), if k == 2 { None } else { Some(l) }, Some(l)],
        };
        let brute = find_pairs_brute(&per, &x, &radii, 0.2);
        let (single, _) = find_pairs(GridKind::Single, &per, &x, &radii, 0.2);
        let (multi, st) = find_pairs(GridKind::MultiLevel { ratio: 2.0 }, &per, &x, &radii, 0.2);
        let plain = find_pairs_brute(&Periodic::none(), &x, &radii, 0.2).len();
        println!(
            "periodic, ratio {ratio}, L {l}: {} pairs ({plain} without periodicity), {} levels",
            brute.len(),
            st.levels
        );
        assert_eq!(single, brute);
        assert_eq!(multi, brute);
        assert!(brute.len() > plain);
    }
}

#[test]
fn a_cluster_across_a_periodic_boundary_moves_as_one_inside() {
    let run = |shift: f64, periodic: bool| {
        let l = hooke_friction(1000.0, 0.3, 0.5);
        let mut cfg = dem_sphere::Config {
            gravity: Vector3::zeros(),
            ..Default::default()
        };
        if periodic {
            cfg.periodic = Periodic {
                lo: Vector3::zeros(),
                len: [Some(0.02), Some(0.02), None],
            };
        }
        let mut w = World::new(cfg, dem_sphere::Laws::single(l, l)).unwrap();
        let mut rng = SplitMix64::new(8);
        let radii: Vec<f64> = (0..60).map(|_| rng.range(0.8e-3, 1.2e-3)).collect();
        let c = Vector3::new(0.01, 0.01, 0.0);
        let p = insert_rsi(
            &radii,
            c - Vector3::repeat(0.0045),
            c + Vector3::repeat(0.0045),
            2,
            10_000,
        )
        .unwrap();
        for (x, r) in p {
            // Converging velocities: the cluster collapses.
            let v =
                (c - x) * 20.0 + Vector3::new(rng.range(-0.02, 0.02), rng.range(-0.02, 0.02), 0.0);
            w.add_sphere(x + Vector3::new(shift, shift, 0.0), v, r, 2500.0, 0)
                .unwrap();
        }
        w.config.dt = w.critical_dt(0.1, 0.05);
        let mut most = 0;
        for _ in 0..30 {
            w.run(100);
            most = most.max(w.contacts().filter(|c| c.2 > 0.0).count());
        }
        (w, most)
    };
    let (a, most) = run(0.0, false);
    let (b, _) = run(0.01, true);
    let mut dx = 0.0f64;
    for i in 0..a.spheres.len() {
        let d = b.spheres.x[i] - Vector3::new(0.01, 0.01, 0.0) - a.spheres.x[i];
        dx = dx.max(d.norm());
    }
    let crossing = b
        .spheres
        .x
        .iter()
        .filter(|x| x.x > 0.02 || x.y > 0.02)
        .count();
    println!("60 spheres, {most} contacts at most, {crossing} centres past the periodic boundary: max |Δx| = {dx:.2e} m");
    assert!(most > 10 && crossing > 5 && dx < 1e-10);
}

fn digest(w: &World) -> Vec<u64> {
    let s = &w.spheres;
    let mut d = Vec::new();
    for i in 0..s.len() {
        for c in 0..3 {
            d.extend([
                s.x[i][c].to_bits(),
                s.v[i][c].to_bits(),
                s.w[i][c].to_bits(),
            ]);
        }
    }
    let e = w.energy();
    d.extend([
        e.damping.to_bits(),
        e.friction.to_bits(),
        e.strain.to_bits(),
    ]);
    d
}

#[test]
fn runs_are_bit_identical_for_1_and_2_threads_and_either_grid() {
    let run = |threads: usize, grid: GridKind| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut w = pour(300, 11, true);
            w.config.grid = grid;
            // Small parallel tasks, so that 2 threads split this small world.
            w.config.min_par_len = 16;
            w.run(8000);
            (
                digest(&w),
                w.counters.builds,
                w.contacts().filter(|c| c.2 > 0.0).count(),
            )
        })
    };
    let (a, builds, contacts) = run(1, GridKind::MultiLevel { ratio: 2.0 });
    let (b, _, _) = run(2, GridKind::MultiLevel { ratio: 2.0 });
    let (c, _, _) = run(2, GridKind::Single);
    println!("300 spheres, 8000 steps, {builds} list builds, {contacts} contacts at the end");
    assert!(contacts > 50, "{contacts}");
    assert_eq!(a, b, "1 vs 2 threads");
    assert_eq!(b, c, "single vs multi-level grid");
}

/// Cost per particle-step of the broad phase (one list build) and of a step (with a list
/// build every step, and without), single vs multi-level grid, size ratio 1 and 10 (equal
/// volumes of the two sizes), N spheres at φ = 0.3, best of 5 repetitions.
/// `cargo test --release -p dem-sphere --test grids -- --ignored --nocapture`
/// (`BENCH_N` sets N, default 20 000).
#[test]
#[ignore]
fn bench_grids() {
    use std::time::Instant;
    let n: usize = std::env::var("BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_000);
    let threads = rayon::current_num_threads();
    println!("N = {n}, {threads} threads; µs per particle(-step), best of 5");
    let best = |f: &mut dyn FnMut()| {
        (0..5)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut base = [[0.0; 3]; 2];
    for &ratio in &[1.0, 10.0] {
        let (x, r) = bidisperse(n, ratio, 0.3, 5);
        for (g, kind) in [GridKind::Single, GridKind::MultiLevel { ratio: 2.0 }]
            .into_iter()
            .enumerate()
        {
            // The world's margin: skin 0.2 r_min, hooke (no reach).
            let margin = 0.2;
            let (_, stats) = find_pairs(kind, &Periodic::none(), &x, &r, margin);
            let reps = 5;
            let build = best(&mut || {
                for _ in 0..reps {
                    std::hint::black_box(find_pairs(kind, &Periodic::none(), &x, &r, margin));
                }
            }) / (reps * n) as f64;
            let l = hooke_friction(1000.0, 0.5, 0.5);
            let cfg = dem_sphere::Config {
                gravity: Vector3::zeros(),
                grid: kind,
                skin: 0.2,
                dt: 1e-7,
                energy: false,
                ..dem_sphere::Config::default()
            };
            let mut w = World::new(cfg, dem_sphere::Laws::single(l, l)).unwrap();
            for (p, &ri) in x.iter().zip(&r) {
                w.add_sphere(p * 1e-3, Vector3::zeros(), ri * 1e-3, 2500.0, 0)
                    .unwrap();
            }
            w.step();
            let steps = 5;
            let rebuild = best(&mut || {
                for _ in 0..steps {
                    w.invalidate_list();
                    w.step();
                }
            }) / (steps * n) as f64;
            let plain = best(&mut || w.run(steps as u64)) / (steps * n) as f64;
            let c = [build, rebuild, plain];
            if ratio == 1.0 {
                base[g] = c;
            }
            println!(
                "ratio {ratio:>4}, {:<11}: {} levels, {:>6.1} tests/sphere | build {:.3} µs ({:.2}× ratio 1) | step + build {:.3} µs = {:.2e} particle-steps/s ({:.2}×) | step {:.3} µs = {:.2e} particle-steps/s ({:.2}×)",
                if g == 0 { "single" } else { "multi-level" },
                stats.levels,
                stats.tests as f64 / n as f64,
                build * 1e6,
                build / base[g][0],
                rebuild * 1e6,
                1.0 / rebuild,
                rebuild / base[g][1],
                plain * 1e6,
                1.0 / plain,
                plain / base[g][2],
            );
        }
    }
}

#[test]
fn histories_survive_neighbour_list_rebuilds() {
    // The same frictional pour with the list rebuilt every step, and with a zero skin (a
    // rebuild whenever anything moves): the shear springs follow their (i, j) key, so the
    // motion is bit-identical to the run that rebuilds only when the skin is used up. (With a
    // zero skin an opening contact leaves the list before the law sees it open: its spring
    // energy is booked at the build, so the friction total differs in the last bits.)
    let run = |mode: u8| {
        let mut w = pour(150, 21, true);
        if mode == 2 {
            w.config.skin = 0.0;
        }
        for _ in 0..6000 {
            if mode == 1 {
                w.invalidate_list();
            }
            w.step();
        }
        (digest(&w), w.counters.builds)
    };
    let (a, na) = run(0);
    let (b, nb) = run(1);
    let (c, nc) = run(2);
    println!("builds: {na} (skin 0.2 r_min), {nb} (every step), {nc} (skin 0)");
    assert!(nb > 10 * na && nc > 10 * na);
    let differ = |x: &[u64], y: &[u64]| (0..x.len()).filter(|&i| x[i] != y[i]).collect::<Vec<_>>();
    println!(
        "differing digest entries (of {}): {:?} {:?}",
        a.len(),
        differ(&a, &b),
        differ(&a, &c)
    );
    assert_eq!(a, b);
    let n = a.len();
    assert_eq!(a[..n - 2], c[..n - 2]);
    assert_eq!(a[n - 1], c[n - 1]);
    let (fa, fc) = (f64::from_bits(a[n - 2]), f64::from_bits(c[n - 2]));
    println!("friction {fa:.15e} vs {fc:.15e} (skin 0)");
    assert!((fa / fc - 1.0).abs() < 1e-12);
}
