//! The three specimen methods on a small Si3N4-like specimen (4 × 2 mm, radii 0.10-0.16 mm):
//! each method's invariants, the relaxation bound, determinism, and the file round trip
//! through a scene.

use dem_core::bond::BondStatus;
use dem_core::state::FREE;
use dem_lab::specimen::methods::{GB, INTRA};
use dem_lab::specimen::{generate, io, Method, Specimen, SpecimenParams};
use std::sync::OnceLock;

const RHO: f64 = 3200.0;

fn params(method: Method, seed: u64) -> SpecimenParams {
    SpecimenParams::new(
        method, 4e-3, 2e-3, 0.10e-3, 0.16e-3, RHO, 310e9, 800e6, seed,
    )
}

fn make(method: Method) -> Specimen {
    generate(&params(method, 3), &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn traditional() -> &'static Specimen {
    static S: OnceLock<Specimen> = OnceLock::new();
    S.get_or_init(|| make(Method::Traditional))
}

fn orc() -> &'static Specimen {
    static S: OnceLock<Specimen> = OnceLock::new();
    S.get_or_init(|| make(Method::Orc))
}

fn improved() -> &'static Specimen {
    static S: OnceLock<Specimen> = OnceLock::new();
    S.get_or_init(|| make(Method::Improved))
}

/// Relaxed: the kinetic energy is below the stated bound, now and in the summary.
fn assert_relaxed(s: &Specimen) {
    let e = s.world.energy();
    let (ke, u) = (e.kinetic(), e.strain_contact + e.strain_bond);
    assert!(u > 0.0);
    assert!(ke <= s.params.ke_ratio * u, "KE {ke:e} J, strain {u:e} J");
    assert_eq!(s.summary.kinetic_energy, ke);
    assert!(s.world.state.walls.is_empty());
    let b = s.world.bonds.as_ref().unwrap();
    assert_eq!(
        b.n_intact(),
        b.len(),
        "no bond may break while the specimen is built"
    );
}

#[test]
fn traditional_has_no_clumps_and_bonds_at_contacts() {
    let s = traditional();
    assert_relaxed(s);
    let w = &s.world;
    let d = &w.state.discs;
    assert!(w.state.clumps.is_empty());
    assert!(d.body.iter().all(|&b| b == FREE));
    assert!(d.len() > 100, "{} discs", d.len());
    // One disc per grain.
    let mut groups = d.group.clone();
    groups.sort_unstable();
    groups.dedup();
    assert_eq!(groups.len(), d.len());
    let b = w.bonds.as_ref().unwrap();
    let mut bonded = std::collections::HashSet::new();
    for v in b.iter() {
        assert_eq!(v.group, GB);
        // Installed at a contact: the gap at installation was ≤ the bond gap (0).
        assert!(v.g0 <= s.params.bond_gap, "g0 {}", v.g0);
        bonded.insert((v.i.min(v.j), v.i.max(v.j)));
    }
    // Every disc is bonded, and every overlapping pair of the relaxed specimen is bonded.
    let mut has = vec![false; d.len()];
    for &(i, j) in &bonded {
        has[i as usize] = true;
        has[j as usize] = true;
    }
    assert!(has.iter().all(|&h| h));
    for c in w.contacts() {
        assert!(bonded.contains(&(c.i.min(c.j), c.i.max(c.j))));
    }
    let sm = &s.summary;
    assert_eq!(sm.discs, d.len());
    assert_eq!(sm.bonds[GB as usize].intact, b.len());
    assert!(
        sm.porosity > 0.1 && sm.porosity < 0.3,
        "porosity {}",
        sm.porosity
    );
    let [sx, sy] = sm.wall_stress_at_bonding;
    let s0 = s.params.iso_stress;
    let tol = s.params.iso_tolerance;
    assert!(((sx + sy) / 2.0 - s0).abs() <= tol * s0, "{sx} {sy}");
}

#[test]
fn orc_grains_are_rigid_clumps_with_summed_properties() {
    let s = orc();
    assert_relaxed(s);
    let st = &s.world.state;
    let (d, cl) = (&st.discs, &st.clumps);
    assert!(cl.len() > 5, "{} clumps", cl.len());
    assert!(
        d.body.iter().all(|&b| b != FREE),
        "every disc is in a grain"
    );
    let mut members = 0;
    for c in 0..cl.len() {
        let idx: Vec<usize> = cl.members[cl.member_range(c)]
            .iter()
            .map(|&id| s.world.index_of_id(id).unwrap())
            .collect();
        members += idx.len();
        let m: f64 = idx.iter().map(|&k| d.m[k]).sum();
        assert!((cl.m[c] - m).abs() <= 1e-12 * m, "mass {} vs {m}", cl.m[c]);
        // Inertia about the clump centre = Σ (I_i + m_i d_i²) (overlaps counted as they are).
        let i: f64 = idx
            .iter()
            .map(|&k| {
                d.inertia[k] + d.m[k] * ((d.x[k] - cl.x[c]).powi(2) + (d.y[k] - cl.y[c]).powi(2))
            })
            .sum();
        assert!(
            (cl.inertia[c] - i).abs() <= 1e-9 * i,
            "inertia {} vs {i}",
            cl.inertia[c]
        );
        let cx: f64 = idx.iter().map(|&k| d.m[k] * d.x[k]).sum::<f64>() / m;
        assert!((cx - cl.x[c]).abs() <= 1e-12 * 4e-3, "centroid");
        // Rigid: members keep their body-frame distance to the centre.
        for (q, &k) in cl.member_range(c).zip(&idx) {
            let r2 = cl.offset_x[q].powi(2) + cl.offset_y[q].powi(2);
            let now = (d.x[k] - cl.x[c]).powi(2) + (d.y[k] - cl.y[c]).powi(2);
            assert!(
                (now - r2).abs() <= 1e-9 * d.r[k] * d.r[k],
                "member moved in its clump"
            );
            assert_eq!(d.group[k], d.group[idx[0]]);
        }
    }
    assert_eq!(members, d.len());
    // Bonds only between grains.
    let b = s.world.bonds.as_ref().unwrap();
    assert!(b.len() > 10);
    for v in b.iter() {
        assert_eq!(v.group, GB);
        assert_ne!(d.body[v.i as usize], d.body[v.j as usize]);
    }
    assert_eq!(s.summary.grains, cl.len());
}

#[test]
fn improved_grains_carry_template_masses_and_two_bond_groups() {
    let s = improved();
    assert_relaxed(s);
    let st = &s.world.state;
    let d = &st.discs;
    assert!(
        st.clumps.is_empty(),
        "improved grains are bonded, not rigid"
    );
    let grains = s.grains.as_ref().unwrap();
    let t = s.params.thickness;
    let mut n_grains = 0;
    let mut nonuniform = 0;
    for (g, cell) in grains.cells.iter().enumerate() {
        let k: Vec<usize> = (0..d.len()).filter(|&k| d.group[k] == g as u32).collect();
        if k.is_empty() {
            continue;
        }
        n_grains += 1;
        assert!(k.len() <= s.params.template_max_discs);
        let props = clumpgen::polygon_props(cell);
        // Mass: Σ m_i = ρ t A_grain exactly (consistency equation (1) of S0).
        let m: f64 = k.iter().map(|&i| d.m[i]).sum();
        let mp = RHO * t * props.area;
        assert!((m - mp).abs() <= 1e-9 * mp, "grain {g}: mass {m} vs {mp}");
        // Inertia about the grain's mass centre: ρ t J_grain (equation (3)), up to the elastic
        // strain of the grain since placement (σ/E ≲ 1e-3 at the pre-compaction stress).
        let cx = k.iter().map(|&i| d.m[i] * d.x[i]).sum::<f64>() / m;
        let cy = k.iter().map(|&i| d.m[i] * d.y[i]).sum::<f64>() / m;
        let inertia: f64 = k
            .iter()
            .map(|&i| d.inertia[i] + d.m[i] * ((d.x[i] - cx).powi(2) + (d.y[i] - cy).powi(2)))
            .sum();
        let ip = RHO * t * props.j;
        assert!(
            (inertia - ip).abs() <= 5e-3 * ip,
            "grain {g}: inertia {inertia} vs {ip}"
        );
        for &i in &k {
            let uniform = RHO * t * std::f64::consts::PI * d.r[i] * d.r[i];
            assert!((d.inertia[i] - 0.5 * d.m[i] * d.r[i] * d.r[i]).abs() <= 1e-12 * d.inertia[i]);
            if (d.m[i] / uniform - 1.0).abs() > 1e-6 {
                nonuniform += 1;
            }
        }
    }
    assert_eq!(n_grains, s.summary.grains);
    assert!(
        nonuniform > d.len() / 2,
        "{nonuniform} of {} discs carry solved masses",
        d.len()
    );
    let b = s.world.bonds.as_ref().unwrap();
    let (mut intra, mut gb) = (0, 0);
    let mut intra_pairs = std::collections::HashSet::new();
    for v in b.iter() {
        let same = d.group[v.i as usize] == d.group[v.j as usize];
        match v.group {
            g if g == INTRA => {
                assert!(same, "intra-grain bond between grains");
                intra += 1;
                intra_pairs.insert((
                    d.id[v.i as usize].min(d.id[v.j as usize]),
                    d.id[v.i as usize].max(d.id[v.j as usize]),
                ));
            }
            g if g == GB => {
                assert!(!same, "grain-boundary bond inside a grain");
                gb += 1;
            }
            g => panic!("unknown group {g}"),
        }
        assert_eq!(v.status, BondStatus::Intact);
    }
    assert!(intra > 0 && gb > 0, "{intra} intra, {gb} boundary bonds");
    // Overlapping members have registered reference gaps, each on a bonded member pair.
    assert!(!s.offsets.is_empty());
    for &(a, b2, g0) in &s.offsets {
        assert!(g0 < 0.0);
        assert!(intra_pairs.contains(&(a.min(b2), a.max(b2))));
    }
}

#[test]
fn same_seed_same_specimen_for_any_thread_count() {
    let p = params(Method::Traditional, 3);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| generate(&p, &mut |_| {}).unwrap())
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.world.state.discs, b.world.state.discs);
    assert_eq!(a.world.bonds, b.world.bonds);
    let c = generate(&params(Method::Traditional, 4), &mut |_| {}).unwrap();
    assert_ne!(a.world.state.discs.x, c.world.state.discs.x);
}

/// Save, load through a scene, compare discs, masses, bonds, clumps and contact offsets; the
/// loaded specimen is at rest.
fn round_trip(s: &Specimen, name: &str) {
    let dir = std::env::temp_dir().join(format!("dem-specimen-rt-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("spec.json");
    let summary = io::save(s, "Si3N4", &file).unwrap();
    assert!(summary.ends_with("spec.summary.json") && summary.exists());
    let scene = io::example_scene(s, "Si3N4", "spec.json", 10);
    let scene_file = dir.join("spec.scene.json");
    std::fs::write(&scene_file, serde_json::to_string(&scene).unwrap()).unwrap();
    let sc = dem_core::scene::load(&scene_file).unwrap_or_else(|e| panic!("{e}"));
    let w = dem_core::scene::build(&sc).unwrap_or_else(|e| panic!("{e}"));
    let f = io::to_file(s, "Si3N4");
    let (d0, d1) = (&s.world.state.discs, &w.state.discs);
    assert_eq!(d1.len(), d0.len());
    // File order = the specimen's ids in order; the loaded world's ids are file indices.
    let mut order: Vec<usize> = (0..d0.len()).collect();
    order.sort_by_key(|&k| d0.id[k]);
    for (fi, &k) in order.iter().enumerate() {
        let j = w.index_of_id(fi as u32).unwrap();
        assert_eq!([d1.x[j], d1.y[j], d1.r[j]], f.discs[0].discs[fi]);
        assert!(
            (d1.m[j] - d0.m[k]).abs() <= 1e-12 * d0.m[k],
            "mass of disc {fi}"
        );
        assert_eq!(d1.group[j], d0.group[k]);
    }
    // Bonds: the same (file index pair, group name) set.
    let names = |w: &dem_core::World| w.bonds.as_ref().unwrap().group_names();
    let set = |w: &dem_core::World, file_of: &dyn Fn(u32) -> u32| {
        let n = names(w);
        let mut v: Vec<(u32, u32, String)> = w
            .bonds
            .as_ref()
            .unwrap()
            .iter()
            .filter(|b| b.status == BondStatus::Intact)
            .map(|b| {
                let (a, c) = (file_of(b.i), file_of(b.j));
                (a.min(c), a.max(c), n[b.group as usize].clone())
            })
            .collect();
        v.sort();
        v
    };
    let mut file_of_id = vec![0u32; d0.len()];
    for (fi, &k) in order.iter().enumerate() {
        file_of_id[d0.id[k] as usize] = fi as u32;
    }
    let before = set(&s.world, &|i| file_of_id[d0.id[i as usize] as usize]);
    let after = set(&w, &|i| d1.id[i as usize]);
    assert!(!before.is_empty());
    assert_eq!(before, after);
    // Rigid clumps: same count, same mass and inertia.
    let (c0, c1) = (&s.world.state.clumps, &w.state.clumps);
    assert_eq!(c0.len(), c1.len());
    let mut m0: Vec<(f64, f64)> = (0..c0.len()).map(|c| (c0.m[c], c0.inertia[c])).collect();
    let mut m1: Vec<(f64, f64)> = (0..c1.len()).map(|c| (c1.m[c], c1.inertia[c])).collect();
    m0.sort_by(|a, b| a.0.total_cmp(&b.0));
    m1.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (a, b) in m0.iter().zip(&m1) {
        assert!((a.0 - b.0).abs() <= 1e-12 * a.0 && (a.1 - b.1).abs() <= 1e-9 * a.1);
    }
    // Contact offsets: overlapping bonded members do not push each other apart.
    for &(a, b, g0) in &s.offsets {
        let (fa, fb) = (file_of_id[a as usize], file_of_id[b as usize]);
        if let Some(c) = w
            .contacts()
            .find(|c| (c.id_i, c.id_j) == (fa, fb) || (c.id_i, c.id_j) == (fb, fa))
        {
            assert!(c.overlap < 0.01 * g0.abs(), "offset of pair {fa}-{fb} lost");
        }
    }
    // Stress-free hand-over: the loaded specimen stays at rest (KE within the relaxation
    // bound of the specimen it came from) over 300 steps.
    let mut w = w;
    w.run(300);
    let u = s.summary.strain_energy;
    let ke = w.energy().kinetic();
    assert!(
        ke <= s.params.ke_ratio * u,
        "loaded specimen moves: KE {ke:e} J, U {u:e} J"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn file_round_trip_through_a_scene_orc() {
    round_trip(orc(), "orc");
}

#[test]
fn file_round_trip_through_a_scene_improved() {
    round_trip(improved(), "improved");
}
