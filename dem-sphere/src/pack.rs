//! Packing scenes: random sequential insertion (RSI) of N spheres with a size distribution
//! into a box, a gravity pour, settling to a kinetic-energy criterion, and the measures.
//!
//! * **Insertion** ([`insert_rsi`]): radii drawn from the distribution and sorted largest
//!   first; each sphere is tried at uniform random positions of the insertion region (its
//!   centre at least r from every face) until it overlaps no sphere placed before it
//!   (Widom 1966, J. Chem. Phys. 44:3888; RSI jams near φ ≈ 0.38 for monodisperse spheres,
//!   so the region should be filled to φ ≲ 0.3). Too many failures: an error, not a panic.
//! * **Pour and settle** ([`pack`]): the spheres, numbered cell by cell for memory
//!   locality, fall under gravity in the box of six walls;
//!   the run stops when the kinetic energy per sphere (translation + rotation) drops below
//!   `ke_per_sphere` after the free-fall time √(2H/g) of the insertion height, or at
//!   `max_time`.
//! * **Packing fraction** ([`packing_fraction`]): the solid fraction of the interior window
//!   — the box less 2 r_max from each side wall and from the floor, and less 2 r_max below
//!   the top of the bed (the highest sphere top) — by counting the points of a cubic
//!   lattice of spacing r_min/5 (at most ~4·10⁶ points) inside spheres; the lattice error
//!   is ~(spacing/window)·surface terms, < 10⁻³ here.
//! * **Coordination number** ([`coordination`]): mean number of sphere–sphere contacts
//!   (δ > 0) of the spheres whose centre is in the window (walls not counted, rattlers
//!   included).

use crate::error::{positive, SphereError};
use crate::rng::SplitMix64;
use crate::{box_walls, Config, GridKind, Laws, World};
use dem_laws::GranularLaw;
use nalgebra::Vector3;

/// Size distribution of the radii.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SizeDist {
    /// All spheres of radius r.
    Mono(f64),
    /// Radii uniform in [min, max].
    Uniform { min: f64, max: f64 },
    /// Two sizes, a number fraction `large_fraction` of the large ones.
    Bidisperse {
        small: f64,
        large: f64,
        large_fraction: f64,
    },
}

impl SizeDist {
    fn check(&self) -> Result<(f64, f64), SphereError> {
        match *self {
            SizeDist::Mono(r) => {
                positive("sizes.radius", r)?;
                Ok((r, r))
            }
            SizeDist::Uniform { min, max } => {
                positive("sizes.min", min)?;
                positive("sizes.max", max)?;
                if max < min {
                    return Err(SphereError::invalid(
                        "sizes.max",
                        format!("must be ≥ sizes.min = {min}, got {max}"),
                    ));
                }
                Ok((min, max))
            }
            SizeDist::Bidisperse {
                small,
                large,
                large_fraction,
            } => {
                positive("sizes.small", small)?;
                positive("sizes.large", large)?;
                if !(0.0..=1.0).contains(&large_fraction) {
                    return Err(SphereError::invalid(
                        "sizes.large_fraction",
                        format!("must be in [0, 1], got {large_fraction}"),
                    ));
                }
                Ok((small.min(large), small.max(large)))
            }
        }
    }

    fn sample(&self, n: usize, rng: &mut SplitMix64) -> Vec<f64> {
        match *self {
            SizeDist::Mono(r) => vec![r; n],
            SizeDist::Uniform { min, max } => (0..n).map(|_| rng.range(min, max)).collect(),
            SizeDist::Bidisperse {
                small,
                large,
                large_fraction,
            } => {
                let nl = (large_fraction * n as f64).round() as usize;
                (0..n).map(|i| if i < nl { large } else { small }).collect()
            }
        }
    }
}

/// Spheres stored in every cell of side `cell` they overlap (insertion checks, point
/// location).
struct CoverGrid {
    lo: Vector3<f64>,
    cell: f64,
    dims: [i64; 3],
    cells: Vec<Vec<u32>>,
}

impl CoverGrid {
    fn new(lo: Vector3<f64>, hi: Vector3<f64>, cell: f64) -> CoverGrid {
        let mut cell = cell;
        let dims = loop {
            let span = (hi - lo).map(|e| if e.is_finite() { e.max(0.0) } else { 0.0 });
            let d = [0, 1, 2].map(|k| ((span[k] / cell).ceil() as i64).max(1));
            if (d[0] as f64) * (d[1] as f64) * (d[2] as f64) <= 8e6 {
                break d;
            }
            cell *= 1.25;
        };
        CoverGrid {
            lo,
            cell,
            dims,
            cells: vec![Vec::new(); (dims[0] * dims[1] * dims[2]) as usize],
        }
    }

    fn range(&self, a: &Vector3<f64>, b: &Vector3<f64>) -> ([i64; 3], [i64; 3]) {
        let c = |p: f64, k: usize| {
            (((p - self.lo[k]) / self.cell).floor() as i64).clamp(0, self.dims[k] - 1)
        };
        ([0, 1, 2].map(|k| c(a[k], k)), [0, 1, 2].map(|k| c(b[k], k)))
    }

    fn each(&self, a: [i64; 3], b: [i64; 3], mut f: impl FnMut(usize)) {
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    f(((z * self.dims[1] + y) * self.dims[0] + x) as usize);
                }
            }
        }
    }

    fn insert(&mut self, i: u32, x: &Vector3<f64>, r: f64) {
        let (a, b) = self.range(&(x - Vector3::repeat(r)), &(x + Vector3::repeat(r)));
        let mut ids = Vec::new();
        self.each(a, b, |c| ids.push(c));
        for c in ids {
            self.cells[c].push(i);
        }
    }
}

/// Random sequential insertion of the radii `radii` (placed largest first) into the box
/// [lo, hi]; returns (centre, radius) in placement order. Errors: a sphere larger than the
/// box, or `attempts` failed tries for one sphere.
pub fn insert_rsi(
    radii: &[f64],
    lo: Vector3<f64>,
    hi: Vector3<f64>,
    seed: u64,
    attempts: usize,
) -> Result<Vec<(Vector3<f64>, f64)>, SphereError> {
    let mut rs = radii.to_vec();
    for (k, &r) in rs.iter().enumerate() {
        positive(&format!("radii[{k}]"), r)?;
    }
    rs.sort_by(|a, b| b.total_cmp(a));
    let r_min = rs.last().copied().unwrap_or(1.0);
    for k in 0..3 {
        if let Some(&r) = rs.first() {
            if hi[k] - lo[k] < 2.0 * r {
                return Err(SphereError::invalid(
                    "box",
                    format!(
                        "extent {} on axis {k} is smaller than the largest diameter {}",
                        hi[k] - lo[k],
                        2.0 * r
                    ),
                ));
            }
        }
    }
    let mut rng = SplitMix64::new(seed);
    let mut grid = CoverGrid::new(lo, hi, 2.0 * r_min);
    let mut out: Vec<(Vector3<f64>, f64)> = Vec::with_capacity(rs.len());
    for (idx, &r) in rs.iter().enumerate() {
        let mut placed = false;
        for _ in 0..attempts {
            let x = Vector3::new(
                rng.range(lo.x + r, hi.x - r),
                rng.range(lo.y + r, hi.y - r),
                rng.range(lo.z + r, hi.z - r),
            );
            let (a, b) = grid.range(&(x - Vector3::repeat(r)), &(x + Vector3::repeat(r)));
            let mut free = true;
            grid.each(a, b, |c| {
                if free {
                    for &j in &grid.cells[c] {
                        let (y, rj) = out[j as usize];
                        if (y - x).norm_squared() < (r + rj) * (r + rj) {
                            free = false;
                            break;
                        }
                    }
                }
            });
            if free {
                grid.insert(out.len() as u32, &x, r);
                out.push((x, r));
                placed = true;
                break;
            }
        }
        if !placed {
            return Err(SphereError::InsertionFailed {
                field: "pack.n".into(),
                index: idx,
                radius: r,
                attempts,
                placed: out.len(),
            });
        }
    }
    Ok(out)
}

/// A packing scene.
#[derive(Clone, Debug, PartialEq)]
pub struct PackSpec {
    /// Number of spheres.
    pub n: usize,
    /// Radii.
    pub sizes: SizeDist,
    /// Density (kg/m³).
    pub density: f64,
    /// The box (walls), floor at `box_lo.z`.
    pub box_lo: Vector3<f64>,
    pub box_hi: Vector3<f64>,
    /// Top of the insertion region (≤ box_hi.z); the region is the box below it.
    pub fill_top: f64,
    /// Sphere–sphere and sphere–wall laws.
    pub law: GranularLaw,
    pub wall_law: GranularLaw,
    /// Gravity (m/s²).
    pub gravity: Vector3<f64>,
    /// Settled when the kinetic energy per sphere is below this (J).
    pub ke_per_sphere: f64,
    /// Give up settling after this time (s).
    pub max_time: f64,
    /// Δt = `dt_fraction` × √(m*/k) at overlap `delta_rel` × r_min ([`World::critical_dt`]).
    pub dt_fraction: f64,
    pub delta_rel: f64,
    /// Insertion seed and tries per sphere.
    pub seed: u64,
    pub attempts: usize,
    /// Broad phase.
    pub grid: GridKind,
}

/// The result of [`pack`].
#[derive(Clone, Debug)]
pub struct Packing {
    /// The settled world.
    pub world: World,
    /// Whether the kinetic-energy criterion was met (else `max_time` was reached).
    pub settled: bool,
    /// Solid fraction in the interior window and the window.
    pub fraction: f64,
    pub window: (Vector3<f64>, Vector3<f64>),
    /// Mean coordination number of the spheres in the window, and their number.
    pub coordination: f64,
    pub in_window: usize,
    /// Settling time (s), steps, and the final kinetic energy per sphere (J).
    pub time: f64,
    pub steps: u64,
    pub ke_per_sphere: f64,
}

/// Insert, pour and settle (module docs); returns the packing and its measures.
pub fn pack(spec: &PackSpec) -> Result<Packing, SphereError> {
    let (_, r_max) = spec.sizes.check()?;
    positive("pack.density", spec.density)?;
    positive("pack.ke_per_sphere", spec.ke_per_sphere)?;
    positive("pack.max_time", spec.max_time)?;
    positive("pack.dt_fraction", spec.dt_fraction)?;
    if spec.n == 0 {
        return Err(SphereError::invalid("pack.n", "must be ≥ 1, got 0"));
    }
    if !(spec.fill_top > spec.box_lo.z + 2.0 * r_max && spec.fill_top <= spec.box_hi.z) {
        return Err(SphereError::invalid(
            "pack.fill_top",
            format!(
                "must be in (box_lo.z + 2 r_max, box_hi.z] = ({}, {}], got {}",
                spec.box_lo.z + 2.0 * r_max,
                spec.box_hi.z,
                spec.fill_top
            ),
        ));
    }
    let walls = box_walls(spec.box_lo, spec.box_hi)?;
    let mut rng = SplitMix64::new(spec.seed ^ 0x5EED);
    let radii = spec.sizes.sample(spec.n, &mut rng);
    let top = Vector3::new(spec.box_hi.x, spec.box_hi.y, spec.fill_top);
    let mut placed = insert_rsi(&radii, spec.box_lo, top, spec.seed, spec.attempts)?;
    // Number the spheres cell by cell (cells of 2 r_max, z, then y, then x), so that
    // neighbours sit close in memory.
    let c = 2.0 * r_max;
    let cell = |x: &Vector3<f64>| {
        let q = (x - spec.box_lo) / c;
        (q.z.floor() as i64, q.y.floor() as i64, q.x.floor() as i64)
    };
    placed.sort_by(|a, b| cell(&a.0).cmp(&cell(&b.0)).then(a.0.x.total_cmp(&b.0.x)));
    let config = Config {
        gravity: spec.gravity,
        grid: spec.grid,
        ..Config::default()
    };
    let mut w = World::new(config, Laws::single(spec.law, spec.wall_law))?;
    for p in walls {
        w.add_wall(p)?;
    }
    for (x, r) in placed {
        w.add_sphere(x, Vector3::zeros(), r, spec.density, 0)?;
    }
    w.config.dt = w.critical_dt(spec.dt_fraction, spec.delta_rel);
    let g = spec.gravity.norm().max(1e-300);
    let t_fall = (2.0 * (spec.fill_top - spec.box_lo.z) / g).sqrt();
    let n = spec.n as f64;
    let check = 50;
    let mut settled = false;
    let mut ke = f64::INFINITY;
    while w.time < spec.max_time {
        w.run(check);
        let e = w.energy();
        ke = e.kinetic() / n;
        if w.time > t_fall && ke < spec.ke_per_sphere {
            settled = true;
            break;
        }
    }
    let window = interior_window(&w);
    let fraction = packing_fraction(&w, window.0, window.1);
    let (coordination, in_window) = coordination(&w, window.0, window.1);
    Ok(Packing {
        time: w.time,
        steps: w.counters.steps,
        world: w,
        settled,
        fraction,
        window,
        coordination,
        in_window,
        ke_per_sphere: ke,
    })
}

/// The interior window of a bed in a box of walls (module docs): the walls' box (the
/// spheres' extent where there are no walls) less 2 r_max from the sides and floor, and less
/// 2 r_max below the highest sphere top.
pub fn interior_window(w: &World) -> (Vector3<f64>, Vector3<f64>) {
    let s = &w.spheres;
    let (_, r_max) = s.radius_range();
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
    for (x, &r) in s.x.iter().zip(&s.r) {
        lo = lo.inf(&(x - Vector3::repeat(r)));
        hi = hi.sup(&(x + Vector3::repeat(r)));
    }
    // Side walls and the floor, where they are axis planes.
    for p in &w.walls {
        for k in 0..3 {
            if p.normal[k] == 1.0 {
                lo[k] = p.point[k];
            }
            if p.normal[k] == -1.0 && k < 2 {
                hi[k] = p.point[k];
            }
        }
    }
    let e = Vector3::repeat(2.0 * r_max);
    (lo + e, hi - e)
}

/// Solid fraction of the box [lo, hi] by lattice counting (module docs).
pub fn packing_fraction(w: &World, lo: Vector3<f64>, hi: Vector3<f64>) -> f64 {
    let s = &w.spheres;
    let ext = hi - lo;
    if s.is_empty() || ext.min() <= 0.0 {
        return 0.0;
    }
    let (r_min, _) = s.radius_range();
    let vol = ext.x * ext.y * ext.z;
    let h = (r_min / 5.0).max((vol / 4e6).cbrt());
    let mut grid = CoverGrid::new(lo, hi, 2.0 * r_min);
    for (i, (x, &r)) in s.x.iter().zip(&s.r).enumerate() {
        grid.insert(i as u32, x, r);
    }
    let nk = [0, 1, 2].map(|k| ((ext[k] / h).floor() as usize).max(1));
    let (mut inside, mut total) = (0u64, 0u64);
    for a in 0..nk[2] {
        for b in 0..nk[1] {
            for c in 0..nk[0] {
                let p = lo
                    + Vector3::new(
                        (c as f64 + 0.5) * ext.x / nk[0] as f64,
                        (b as f64 + 0.5) * ext.y / nk[1] as f64,
                        (a as f64 + 0.5) * ext.z / nk[2] as f64,
                    );
                total += 1;
                let (q, _) = grid.range(&p, &p);
                let cell = ((q[2] * grid.dims[1] + q[1]) * grid.dims[0] + q[0]) as usize;
                if grid.cells[cell].iter().any(|&j| {
                    (s.x[j as usize] - p).norm_squared() < s.r[j as usize] * s.r[j as usize]
                }) {
                    inside += 1;
                }
            }
        }
    }
    inside as f64 / total as f64
}

/// Mean number of sphere–sphere contacts (δ > 0) of the spheres with centres in [lo, hi],
/// and their number.
pub fn coordination(w: &World, lo: Vector3<f64>, hi: Vector3<f64>) -> (f64, usize) {
    let s = &w.spheres;
    let inside = |i: usize| (0..3).all(|k| s.x[i][k] >= lo[k] && s.x[i][k] <= hi[k]);
    let mut z = vec![0u32; s.len()];
    for (i, j, d) in w.contacts() {
        if d > 0.0 {
            z[i] += 1;
            z[j] += 1;
        }
    }
    let (mut sum, mut cnt) = (0u64, 0usize);
    for (i, &zi) in z.iter().enumerate() {
        if inside(i) {
            sum += zi as u64;
            cnt += 1;
        }
    }
    (
        if cnt > 0 {
            sum as f64 / cnt as f64
        } else {
            0.0
        },
        cnt,
    )
}
