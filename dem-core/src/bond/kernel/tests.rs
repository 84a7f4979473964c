//! Tests of the bond kernel: AVX2 against baseline, straight-line against general paths.

use super::super::bench::{bonded_lattice_state, lattice_bond_group, shaken_hex_lattice, RADIUS};
use super::super::BondStatus;
use super::super::Bonds;
use super::*;
use crate::lanes::has_avx2;

/// The AVX2 and baseline builds of the block loop give the same bits (on CPUs with AVX2;
/// elsewhere both runs take the baseline path).
#[test]
fn avx2_and_baseline_agree_bitwise() {
    let (_, bonds) = bonded_lattice_state([12, 8]);
    let st = shaken_state(1);
    let go = |avx2: bool| {
        let mut b = bonds.clone();
        let mut st = st.clone();
        for _ in 0..3 {
            st.discs.clear_forces();
            b.compute_with(&mut st, 1e-7, avx2, &[]);
        }
        (st, b)
    };
    let a = go(false);
    let b = go(has_avx2());
    assert!(a.0.discs.fx.iter().any(|&f| f != 0.0));
    assert_eq!(a, b);
}

/// The gather from the contact pass's packed records (AVX2) gives the bits of the gather
/// from the disc arrays, and the records are really read: records of other positions give
/// other forces. (On CPUs without AVX2 there are no records.)
#[cfg(target_arch = "x86_64")]
#[test]
fn packed_records_give_the_array_bits() {
    use crate::lanes::Packed;
    if !has_avx2() {
        return;
    }
    let st = shaken_state(5);
    // Some pairs left out, so that the bonds fill no whole number of blocks and of fours:
    // the partial block and the scalar tail of the gather run too.
    let mut bonds = Bonds::new(vec![lattice_bond_group(st.thickness)]).unwrap();
    bonds
        .install_within_gap(&st, 0.1 * RADIUS, |i, j| {
            (!(i + j).is_multiple_of(7)).then_some(0)
        })
        .unwrap();
    assert!(
        !bonds.len().is_multiple_of(4) && !bonds.len().is_multiple_of(BOND_BLOCK),
        "{}",
        bonds.len()
    );
    let go = |pk: &[Packed]| {
        let mut b = bonds.clone();
        let mut st = st.clone();
        for _ in 0..3 {
            st.discs.clear_forces();
            b.compute_with(&mut st, 1e-7, true, pk);
        }
        (st, b)
    };
    let from_arrays = go(&[]);
    assert!(from_arrays.0.discs.fx.iter().any(|&f| f != 0.0));
    assert_eq!(go(&records(&st)), from_arrays);
    let mut other = st.clone();
    other.discs.x[7] += 1e-6;
    other.discs.omega[3] += 1.0;
    assert_ne!(go(&records(&other)).0.discs.fx, from_arrays.0.discs.fx);
}

/// The packed disc records of `st`, as the contact pass builds them (the contact masses,
/// which the bond kernel does not read, set to 1).
///
/// # Panics
/// Without AVX2.
#[cfg(target_arch = "x86_64")]
fn records(st: &crate::state::State) -> Vec<crate::lanes::Packed> {
    use crate::contact::kernel::{pack_records, PackSrc};
    use crate::lanes::Packed;
    assert!(has_avx2());
    let d = &st.discs;
    let minv = vec![1.0; d.len()];
    let src = PackSrc {
        x: &d.x,
        y: &d.y,
        vx: &d.vx,
        vy: &d.vy,
        w: &d.omega,
        r: &d.r,
        minv: &minv,
    };
    let mut pk = vec![Packed::default(); d.len()];
    // SAFETY: the CPU has AVX2 (asserted above).
    unsafe { pack_records(&src, 0, &mut pk, &mut [], false) };
    pk
}

/// The four-lane kernel (full blocks of intact parallel bonds with the stress criterion, from
/// the packed records) gives the bits of the baseline build (its straight-line and general
/// paths): the forces on the discs at every step, the bond forces and the status, for one
/// group and for two interleaved groups (uniform and per-bond parameters), strong bonds and
/// weak ones that break in tension and shear (blocks with broken bonds then leave the
/// four-lane kernel), in a periodic and a bounded box.
#[cfg(target_arch = "x86_64")]
#[test]
fn four_lane_kernel_gives_the_baseline_bits() {
    use super::super::parallel4::BLOCKS;
    if !has_avx2() {
        return;
    }
    let mut modes = [0usize; 2];
    for periodic in [true, false] {
        let cases = [
            (1e8, 1e8, false),
            (5e3, 1e8, false),
            (1e8, 3e4, false),
            (1e8, 1e8, true),
            (3e4, 3e4, true),
        ];
        for (tensile, cohesion, two) in cases {
            let mut st = shaken_state(11);
            if !periodic {
                st.periodic.length = [None, None];
            }
            // One group: the second group of `two_groups`, with these strengths; two groups:
            // the strong lattice group and that one, alternating.
            let mut groups = two_groups(tensile, cohesion);
            if !two {
                groups.swap(0, 1);
            }
            let mut bonds = Bonds::new(groups).unwrap();
            let assign = |i: usize, j: usize| Some(if two { ((i + j) % 2) as u16 } else { 0 });
            bonds.install_within_gap(&st, 0.1 * RADIUS, assign).unwrap();
            assert!(bonds.len() >= 8 * BOND_BLOCK);
            let pk = records(&st);
            let go = |avx2: bool, pk: &[crate::lanes::Packed]| {
                let (mut b, mut s) = (bonds.clone(), st.clone());
                let mut forces = Vec::new();
                for _ in 0..40 {
                    s.discs.clear_forces();
                    b.compute_with(&mut s, 1e-7, avx2, pk);
                    let d = &s.discs;
                    forces.extend(
                        d.fx.iter()
                            .chain(&d.fy)
                            .chain(&d.torque)
                            .map(|f| f.to_bits()),
                    );
                }
                (s, b, forces)
            };
            let before = BLOCKS.with(|b| b.get());
            let four = go(true, &pk);
            assert!(
                BLOCKS.with(|b| b.get()) > before,
                "four-lane kernel not used"
            );
            let want = go(false, &[]);
            assert!(four.0.discs.fx.iter().any(|&f| f != 0.0));
            assert!(
                four == want,
                "periodic {periodic} {tensile} {cohesion} two {two}"
            );
            for v in four.1.iter() {
                if let BondStatus::Broken(m) = v.status {
                    modes[m.index()] += 1;
                }
            }
        }
    }
    assert!(modes[0] > 0 && modes[1] > 0, "breaks by mode: {modes:?}");
}

/// The bonded 12 × 8 lattice shaken: random displacements and velocities from a seeded LCG.
fn shaken_state(seed: u64) -> crate::state::State {
    let (mut st, _) = bonded_lattice_state([12, 8]);
    let mut s = seed;
    for k in 0..st.discs.len() {
        let mut r = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        st.discs.x[k] += 2e-6 * r();
        st.discs.y[k] += 2e-6 * r();
        st.discs.vx[k] = 0.1 * r();
        st.discs.vy[k] = 0.1 * r();
        st.discs.omega[k] = 50.0 * r();
    }
    st
}

/// Run `steps` steps of the store built with `groups` (bond group `assign(i, j)`) whole and
/// split into stores of fewer than BOND_BLOCK bonds (the general per-bond path); assert equal bits
/// and return whether some full block of the whole store had between 1 and BOND_BLOCK/4 broken
/// bonds before a step (the masked straight-line path).
fn whole_against_split(
    groups: Vec<super::super::BondGroup>,
    assign: impl Fn(usize, usize) -> u16,
    steps: usize,
) -> bool {
    let st = shaken_state(7);
    let mut all = Bonds::new(groups.clone()).unwrap();
    all.install_within_gap(&st, 0.1 * RADIUS, |i, j| Some(assign(i, j)))
        .unwrap();
    let views: Vec<_> = all.iter().collect();
    assert!(views.len() >= 4 * BOND_BLOCK);
    // The same bonds in stores of fewer than BOND_BLOCK bonds: the general path.
    let mut parts: Vec<Bonds> = views
        .chunks(BOND_BLOCK - 1)
        .map(|c| {
            let mut b = Bonds::new(groups.clone()).unwrap();
            b.install_pairs(&st, c.iter().map(|v| (v.i as usize, v.j as usize, v.group)))
                .unwrap();
            b
        })
        .collect();
    let avx2 = has_avx2();
    let mut masked = false;
    for _ in 0..steps {
        let v: Vec<_> = all.iter().collect();
        masked |= v.chunks_exact(BOND_BLOCK).any(|c| {
            let b = c.iter().filter(|v| v.status != BondStatus::Intact).count();
            (1..=BOND_BLOCK / 4).contains(&b)
        });
        let mut a = st.clone();
        a.discs.clear_forces();
        all.compute_with(&mut a, 1e-7, avx2, &[]);
        for b in parts.iter_mut() {
            let mut a = st.clone();
            a.discs.clear_forces();
            b.compute_with(&mut a, 1e-7, avx2, &[]);
        }
    }
    let bits = |v: super::super::BondView| {
        (
            v.i,
            v.j,
            v.group,
            v.status,
            [v.fn_, v.fs, v.m].map(f64::to_bits),
        )
    };
    let whole: Vec<_> = all.iter().map(bits).collect();
    let split: Vec<_> = parts.iter().flat_map(|b| b.iter()).map(bits).collect();
    assert!(all.iter().any(|v| v.fs != 0.0));
    assert_eq!(whole, split);
    masked
}

/// The bench's two groups (`bench::two_groups`) for the lattice's thickness.
fn two_groups(tensile: f64, cohesion: f64) -> Vec<super::super::BondGroup> {
    let t = bonded_lattice_state([3, 3]).0.thickness;
    super::super::bench::two_groups(t, tensile, cohesion)
}

/// Blocks of intact parallel bonds in two stress-criterion groups (the improved-ORC case)
/// take the straight-line path with per-bond parameters; it gives the bits of the general
/// per-bond path, which every block of a store with fewer than BOND_BLOCK bonds takes.
#[test]
fn mixed_group_blocks_give_the_general_path_bits() {
    let st = shaken_state(7);
    let groups = two_groups(2e8, 3e8);
    let mut b = Bonds::new(groups.clone()).unwrap();
    b.install_within_gap(&st, 0.1 * RADIUS, |i, j| Some(((i + j) % 2) as u16))
        .unwrap();
    let v: Vec<_> = b.iter().collect();
    assert!(v[..BOND_BLOCK].iter().any(|x| x.group != v[0].group));
    whole_against_split(groups, |i, j| ((i + j) % 2) as u16, 3);
}

/// Blocks with a few broken bonds take the straight-line path masked (the broken bonds keep
/// their state, bonds breaking in it are reported as by the general path): the general
/// path's bits, for one group (weakened until bonds break step by step) and for two.
#[test]
fn blocks_with_a_few_broken_bonds_give_the_general_path_bits() {
    let mut masked = [false; 2];
    // Strengths at which some of the 576 bonds break over the 40 steps (measured: 120 and
    // 72, 26 and 18, 1 and 1 broken).
    for strength in [2e4, 3e4, 4e4] {
        // One group: the second group is unused.
        let mut groups = two_groups(strength, strength);
        groups.swap(0, 1);
        masked[0] |= whole_against_split(groups, |_, _| 0, 40);
        let groups = two_groups(strength, strength);
        masked[1] |= whole_against_split(groups, |i, j| ((i + j) % 2) as u16, 40);
    }
    assert_eq!(masked, [true, true], "no block took the masked path");
}

/// The parallel path (ranges of bonds, shared discs through slots: `split`) gives the bits
/// of the one-thread path on pools of 2, 3 and 4 threads — disc state, bond forces, status
/// and break log after 150 leapfrog steps of a shaken lattice whose weak bonds break in both
/// modes — with the four-lane kernel (packed records) and without; the split really has
/// shared discs and blocks that reach them.
#[test]
fn split_ranges_give_the_one_thread_bits() {
    use super::super::split::Split;
    // 60 × 30 cells: 3,600 discs, 10,800 bonds, above the parallel threshold; velocities
    // within ±0.02 m/s, spins within ±40 rad/s.
    let st0 = shaken_hex_lattice([60, 30], 99, 0.04, 80.0);
    let mut bonds0 = Bonds::new(two_groups(1.5e4, 1e4)).unwrap();
    bonds0
        .install_within_gap(&st0, 1e-5, |i, j| Some(((i + j) % 2) as u16))
        .unwrap();
    assert!(bonds0.len() >= PAR_MIN_BONDS);
    let (bi, bj): (Vec<u32>, Vec<u32>) = bonds0.iter().map(|v| (v.i, v.j)).unzip();
    for ranges in [2, 3, 4] {
        let sp = Split::new(&bi, &bj, st0.discs.len(), ranges);
        assert!(sp.n_shared() > 0);
    }
    let with_records = cfg!(target_arch = "x86_64") && has_avx2();
    for packed in [false, with_records] {
        let go = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let (mut st, mut b) = (st0.clone(), bonds0.clone());
                let dt = 2e-7;
                for _ in 0..150 {
                    st.discs.clear_forces();
                    #[cfg(target_arch = "x86_64")]
                    let pk = if packed { records(&st) } else { Vec::new() };
                    #[cfg(not(target_arch = "x86_64"))]
                    let pk: Vec<crate::lanes::Packed> = Vec::new();
                    b.compute_with(&mut st, dt, has_avx2(), &pk);
                    let d = &mut st.discs;
                    for k in 0..d.len() {
                        d.vx[k] += d.fx[k] / d.m[k] * dt;
                        d.vy[k] += d.fy[k] / d.m[k] * dt;
                        d.omega[k] += d.torque[k] / d.inertia[k] * dt;
                        d.x[k] += d.vx[k] * dt;
                        d.y[k] += d.vy[k] * dt;
                    }
                    st.step += 1;
                }
                let modes = b.log().events.iter().fold([0, 0], |mut m, e| {
                    m[e.mode.index()] += 1;
                    m
                });
                (serde_json::to_string(&st).unwrap(), b, modes)
            })
        };
        let one = go(1);
        // (Measured: 93 in tension and 3 in shear of 10,800.)
        assert!(one.2[0] > 0 && one.2[1] > 0, "breaks by mode {:?}", one.2);
        eprintln!("packed {packed}: breaks by mode {:?}", one.2);
        assert!(one.1.log().len() < bonds0.len() / 2);
        for threads in [2, 3, 4] {
            let many = go(threads);
            assert!(many.0 == one.0, "state, {threads} threads, packed {packed}");
            assert!(many.1 == one.1, "bonds, {threads} threads, packed {packed}");
        }
    }
}
