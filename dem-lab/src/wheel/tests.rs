//! Issue 52's "Done when" points of the wheel's first part, on a small wheel (about 400 discs).

use super::*;
use dem_core::damping::DampingFrame;
use dem_core::state::FREE;
use dem_core::World;
use std::sync::OnceLock;

/// 3 mm wheel on a 1.2 mm hub, 4 grooves 0.5 mm wide and 0.4 mm deep; 8 triangular grits.
pub fn tiny() -> WheelParams {
    let mut p = WheelParams::small();
    p.ring.r_outer = 3e-3;
    p.ring.r_inner = 1.2e-3;
    p.ring.grooves = 4;
    p.ring.groove_width = 0.5e-3;
    p.ring.groove_depth = 0.4e-3;
    p.ring.outer_segments = 120;
    p.grits.count = 8;
    p.porosity = 0.18;
    // Grits as stiff as the wheel: a longer time step for the spin test.
    p.grit_modulus = p.contact_modulus;
    p
}

fn wheel() -> &'static Wheel {
    static W: OnceLock<Wheel> = OnceLock::new();
    W.get_or_init(|| build(&tiny(), &mut |m| eprintln!("{m}")).unwrap())
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-wheel-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Done when: the porosity reached within 0.005 of its target.
#[test]
fn porosity_reaches_its_target() {
    let w = wheel();
    let s = &w.summary;
    eprintln!("{}", s.text());
    let direct = 1.0 - disc_area(&w.packed) / w.walls.area;
    assert!((s.porosity_reached - direct).abs() < 1e-12);
    assert!(
        (s.porosity_reached - s.porosity_target).abs() <= 0.005,
        "porosity {} target {}",
        s.porosity_reached,
        s.porosity_target
    );
    assert!(s.pack.mean_overlap_ratio < pack::MAX_MEAN_OVERLAP);
}

/// Done when: no grit disc overlaps a wheel disc after removal; each grit as S1 lays it out;
/// bonds per group counted (and written).
#[test]
fn grits_clear_the_wheel_and_bonds_are_counted() {
    let w = wheel();
    let mut worst = f64::INFINITY;
    for g in &w.grits {
        assert_eq!(g.len(), 15);
        for c in g {
            for d in &w.discs {
                worst = worst.min(gap(*c, *d));
            }
        }
        // The grit's discs are the triangle layout moved rigidly: pairwise distances kept.
        let v = grits::layout(grits::GritShape::Triangle, 5, w.params.grits.radius);
        for i in 0..g.len() {
            for j in 0..g.len() {
                let a = (g[i][0] - g[j][0]).hypot(g[i][1] - g[j][1]);
                let b = (v[i][0] - v[j][0]).hypot(v[i][1] - v[j][1]);
                assert!((a - b).abs() < 1e-15, "grit layout");
            }
        }
    }
    eprintln!("smallest grit-wheel gap {worst:.3e} m");
    assert!(worst >= 0.0);
    let s = &w.summary;
    assert_eq!(s.bonds[WHEEL_BOND], w.wheel_bonds.len());
    assert_eq!(s.bonds[GRIT_BOND], w.grit_bonds.len());
    assert!(s.bonds[WHEEL_BOND] > w.discs.len() && s.min_grit_bonds >= 1);
    let f = w.specimen_file();
    assert_eq!(f.rigid_clumps.len(), w.grits.len());
    let counted: Vec<(String, usize)> = f
        .bonds
        .iter()
        .map(|b| (b.bond_group.clone(), b.pairs.len()))
        .collect();
    assert_eq!(
        counted,
        vec![
            (WHEEL_BOND.to_string(), s.bonds[WHEEL_BOND]),
            (GRIT_BOND.to_string(), s.bonds[GRIT_BOND])
        ]
    );
}

/// Centre of mass of the free discs and clumps.
fn centre(w: &World) -> [f64; 2] {
    let (mut m, mut x, mut y) = (0.0, 0.0, 0.0);
    let d = &w.state.discs;
    for k in 0..d.len() {
        if d.body[k] == FREE {
            m += d.m[k];
            x += d.m[k] * d.x[k];
            y += d.m[k] * d.y[k];
        }
    }
    let c = &w.state.clumps;
    for k in 0..c.len() {
        m += c.m[k];
        x += c.m[k] * c.x[k];
        y += c.m[k] * c.y[k];
    }
    [x / m, y / m]
}

/// Angular momentum over polar inertia about the centre of mass, of the free discs and the
/// clumps.
fn spin(w: &World) -> f64 {
    let g = centre(w);
    let (mut l, mut j) = (0.0, 0.0);
    let d = &w.state.discs;
    for k in 0..d.len() {
        if d.body[k] == FREE {
            let (x, y) = (d.x[k] - g[0], d.y[k] - g[1]);
            l += d.m[k] * (x * d.vy[k] - y * d.vx[k]) + d.inertia[k] * d.omega[k];
            j += d.m[k] * (x * x + y * y) + d.inertia[k];
        }
    }
    let c = &w.state.clumps;
    for k in 0..c.len() {
        let (x, y) = (c.x[k] - g[0], c.y[k] - g[1]);
        l += c.m[k] * (x * c.vy[k] - y * c.vx[k]) + c.inertia[k] * c.omega[k];
        j += c.m[k] * (x * x + y * y) + c.inertia[k];
    }
    l / j
}

/// The wheel of `dir`'s scene without its hub, turning rigidly at `omega`, run one turn (or
/// `turns`); returns Ω after / Ω before, the largest change of a disc's distance from the
/// centre over r_min, and the bonds broken.
fn free_turn(dir: &Path, frame: DampingFrame, omega: f64, turns: f64) -> (f64, f64, u64) {
    let w = wheel();
    w.save(dir).unwrap();
    let mut scene = w.scene_file("spin", "wheel.specimen.json", false);
    scene.damping.frame = frame;
    // The engine's accurate default step (f = 0.1) is not needed for a rigid spin.
    scene.run.dt_factor = Some(0.3);
    let text = serde_json::to_string_pretty(&scene).unwrap();
    let path = dir.join("spin.json");
    std::fs::write(&path, text).unwrap();
    let mut world = dem_core::scene::build(&dem_core::scene::load(&path).unwrap()).unwrap();
    world.params.max_energy_growth = f64::INFINITY;
    // Rigid rotation about the centre of mass (which then stays put).
    let g = centre(&world);
    let d = &mut world.state.discs;
    for k in 0..d.len() {
        d.vx[k] = -omega * (d.y[k] - g[1]);
        d.vy[k] = omega * (d.x[k] - g[0]);
        d.omega[k] = omega;
    }
    let c = &mut world.state.clumps;
    for k in 0..c.len() {
        c.vx[k] = -omega * (c.y[k] - g[1]);
        c.vy[k] = omega * (c.x[k] - g[0]);
        c.omega[k] = omega;
    }
    let rho = |w: &World| {
        let d = &w.state.discs;
        let mut v = vec![0.0; d.len()];
        for k in 0..d.len() {
            v[d.id[k] as usize] = (d.x[k] - g[0]).hypot(d.y[k] - g[1]);
        }
        v
    };
    let r0 = rho(&world);
    let s0 = spin(&world);
    let period = turns * 2.0 * PI / omega;
    let (mut t, mut steps) = (0.0, 0);
    while t < period {
        let n = (((period - t) / world.dt()).ceil() as u64).clamp(1, 500);
        t += n as f64 * world.dt();
        steps += n;
        world.run(n);
        world.check().unwrap();
    }
    eprintln!("{steps} steps of {:.3e} s", world.dt());
    let r1 = rho(&world);
    let shape = r0
        .iter()
        .zip(&r1)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / w.params.r_min;
    let broken = world.bonds.as_ref().map_or(0, |b| {
        b.iter()
            .filter(|v| v.status != dem_core::bond::BondStatus::Intact)
            .count() as u64
    });
    (spin(&world) / s0, shape, broken)
}

/// Done when: a wheel turned with no workpiece keeps its shape and its spin (angular velocity
/// within 1 % after one turn) under the scene's fragment-frame local damping; lab-frame local
/// damping brakes it (measured on a quarter turn, printed).
#[test]
fn free_wheel_keeps_its_spin() {
    let d = dir("spin");
    // Rim speed 60 m/s (grinding wheels run at 30-120 m/s).
    let omega = 60.0 / tiny().ring.r_outer;
    let (ratio, shape, broken) = free_turn(&d, DampingFrame::Fragment, omega, 1.0);
    eprintln!(
        "fragment frame, one turn: Ω/Ω0 = {ratio:.6}, largest radial shift {:.4} r_min, {broken} \
         bonds broken",
        shape
    );
    let (lab, lab_shape, _) = free_turn(&d, DampingFrame::Lab, omega, 0.25);
    eprintln!("lab frame, quarter turn: Ω/Ω0 = {lab:.6}, radial shift {lab_shape:.4} r_min");
    assert!((ratio - 1.0).abs() < 0.01, "{ratio}");
    assert!(shape < 0.05, "{shape}");
    assert_eq!(broken, 0);
    std::fs::remove_dir_all(&d).ok();
}

/// The three files are written and the scene loads as the solver reads it.
#[test]
fn files_load() {
    let d = dir("files");
    let files = wheel().save(&d).unwrap();
    let f = read(&files[0]).unwrap();
    assert_eq!(f.summary, wheel().summary);
    let scene = dem_core::scene::load(&files[2]).unwrap();
    let world = dem_core::scene::build(&scene).unwrap();
    assert_eq!(
        world.state.discs.len(),
        wheel().discs.len() + wheel().summary.grit_discs
    );
    assert_eq!(world.state.clumps.len(), wheel().grits.len());
    std::fs::remove_dir_all(&d).ok();
}

/// Bad input: a porosity that cannot be reached names the field.
#[test]
fn unreachable_porosity_is_refused() {
    for n in [0.05, 0.6] {
        let p = WheelParams {
            porosity: n,
            ..tiny()
        };
        match build(&p, &mut |_| {}) {
            Err(LabError::Param { field, reason }) => {
                assert!(field.starts_with("porosity"), "{field}: {reason}")
            }
            other => panic!("{n}: {:?}", other.err()),
        }
    }
}
