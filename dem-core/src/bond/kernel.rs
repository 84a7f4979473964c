//! The per-step bond kernel: bonds are processed in blocks of [`BOND_BLOCK`]; per block, the pair
//! data are gathered, the geometry and kinematics computed branch-free over the block (the
//! compiler emits packed SIMD), then the bond laws and criteria are applied (also branch-free
//! for the common case of a block of intact parallel bonds with the stress criterion), and the
//! resulting forces scattered to the discs in bond order.
//!
//! Every path calls the same inline functions in the same order for a given bond, so the
//! fused single-thread path, the two-pass parallel path and the fast and general block loops
//! all produce identical bits.

use super::criteria::{stress_flags, BreakMode, Compiled, Criterion};
use super::flat_joint::{self, ElementStrength, FlatJointState, Motion};
use super::incidence::Incidence;
use super::potyondy2004::{Kinematics, ParallelBondParams};
use super::split::Split;
use super::{contact_bond, potyondy2004, BondGroup, BondModel};
#[cfg(target_arch = "x86_64")]
use crate::lanes::transpose4;
use crate::lanes::{Packed, BOND_BLOCK};
use crate::neighbors::MinImage;

/// `status` codes: intact, broken (tension/shear), and broken in the current step (not yet
/// logged).
pub(super) const INTACT: u8 = 0;
pub(super) const BROKEN: u8 = 1; // + mode index
pub(super) const NEW: u8 = 3; // + mode index

/// Use the parallel path (ranges of bonds, [`super::split`]) from this many bonds on (and with
/// more than one thread).
pub(super) const PAR_MIN_BONDS: usize = 8192;

/// Unit normal n̂ from i to j ((1, 0) for coincident centres), gap, and the arms
/// a_i = R_i + g/2, a_j = R_j + g/2 from the centres to the contact point.
#[inline(always)]
fn normal_gap(dx: f64, dy: f64, ri: f64, rj: f64) -> (f64, f64, f64, f64, f64) {
    let dist = (dx * dx + dy * dy).sqrt();
    let ok = dist > 0.0;
    let inv = 1.0 / if ok { dist } else { 1.0 };
    let nx = if ok { dx * inv } else { 1.0 };
    let ny = dy * inv;
    let gap = dist - ri - rj;
    (nx, ny, gap, ri + 0.5 * gap, rj + 0.5 * gap)
}

/// Read-only disc data the kernel needs.
pub(super) struct DiscView<'a> {
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub vx: &'a [f64],
    pub vy: &'a [f64],
    pub omega: &'a [f64],
    pub r: &'a [f64],
    /// The minimum image of the periodic axes (the contact pass's, [`MinImage`]).
    pub img: MinImage,
}

impl DiscView<'_> {
    /// Whether all disc arrays have the length of `x`.
    fn lengths_agree(&self) -> bool {
        let n = self.x.len();
        [
            self.y.len(),
            self.vx.len(),
            self.vy.len(),
            self.omega.len(),
            self.r.len(),
        ]
        .iter()
        .all(|&l| l == n)
    }

    /// (n̂, gap, a_i, a_j) of the pair (i, j), as the kernel computes them.
    pub fn geometry(&self, i: usize, j: usize) -> (f64, f64, f64, f64, f64) {
        let (dx, dy) = self
            .img
            .delta_select(self.x[j] - self.x[i], self.y[j] - self.y[i]);
        normal_gap(dx, dy, self.r[i], self.r[j])
    }
}

/// Per-step constants of the kernel.
pub(super) struct Ctx<'a> {
    pub v: DiscView<'a>,
    /// The contact pass's packed records of the same discs, or empty; not empty only when
    /// the CPU has AVX2; read (see [`gather_packed`]) only when there is one per disc.
    pub packed: &'a [Packed],
    pub groups: &'a [BondGroup],
    pub compiled: &'a [Compiled],
    /// Per-bond stress-criterion parameters of parallel bonds ([`StressParams`]).
    pub stress: &'a StressParams,
    pub t: f64,
    pub dt: f64,
}

/// Read-only bond arrays (whole store).
pub(super) struct BondsIn<'a> {
    pub i: &'a [u32],
    pub j: &'a [u32],
    pub group: &'a [u16],
    pub g0: &'a [f64],
    pub rbar: &'a [f64],
}

/// Mutable bond arrays (whole store or one chunk).
pub(super) struct BondsMut<'a> {
    pub fn_: &'a mut [f64],
    pub fs: &'a mut [f64],
    pub m: &'a mut [f64],
    pub status: &'a mut [u8],
    /// Flat-joint interfaces, one per bond, or empty when no group is a flat joint.
    pub fj: &'a mut [FlatJointState],
}

/// Disc force accumulators.
pub(super) struct DiscOut<'a> {
    pub fx: &'a mut [f64],
    pub fy: &'a mut [f64],
    pub tq: &'a mut [f64],
}

/// Run the bond stage over all bonds: update forces and status, add the forces of intact
/// bonds to the discs. Returns the number of bonds broken now (marked [`NEW`] + mode).
/// `avx2`: use the AVX2 build of the block loop (pass [`crate::lanes::has_avx2`]; same results either way).
/// `index_bound`: [`index_bound`] of `b.i`, `b.j` (cached by the store). `serial`: the work
/// arrays of the one-thread path (kept by the store, so they are not re-zeroed every step).
/// The parallel path ([`super::split`]) uses `scratch` (per-bond slots, resized as needed),
/// `split` (the cut into ranges) and `incidence` (the bonds by disc, for the shared discs),
/// building the last two when missing or made for another size (the store resets them when
/// bonds change). `ranges`: the thread count (one: the one-thread path; more: that many
/// ranges; same results).
#[allow(clippy::too_many_arguments)]
pub(super) fn run(
    c: &Ctx,
    b: &BondsIn,
    mut m: BondsMut,
    out: DiscOut,
    scratch: &mut Vec<[f64; 4]>,
    serial: &mut SerialWork,
    incidence: &mut Option<Incidence>,
    split: &mut Option<Split>,
    avx2: bool,
    index_bound: usize,
    ranges: usize,
) -> usize {
    let nb = b.i.len();
    let nd = out.fx.len();
    let (fx, fy, tq) = (&mut out.fx[..nd], &mut out.fy[..nd], &mut out.tq[..nd]);
    // Whether every disc index is in range (then the gather and scatter skip the checks).
    let valid = c.v.x.len() == nd && c.v.lengths_agree() && index_bound <= nd;
    // (An index out of range, which cannot happen, takes the one-thread path's checks.)
    let parallel = valid && nb >= PAR_MIN_BONDS && ranges > 1;
    if !parallel {
        let SerialWork { w, o } = serial;
        let mut broke = 0;
        for k in (0..nb).step_by(BOND_BLOCK) {
            let e = (k + BOND_BLOCK).min(nb);
            let mut s = sub(&mut m, k..e);
            let (nbrk, all_intact) = block_best(c, b, k, &mut s, o, w, avx2, valid);
            broke += nbrk;
            if valid && all_intact && nbrk == 0 {
                // SAFETY: `valid`: all indices < nd = fx.len() = fy.len() = tq.len().
                unsafe { scatter_unchecked(fx, fy, tq, &b.i[k..e], &b.j[k..e], o) };
                continue;
            }
            for q in k..e {
                if m.status[q] == INTACT {
                    let o = [o[0][q - k], o[1][q - k], o[2][q - k], o[3][q - k]];
                    scatter(fx, fy, tq, b.i[q] as usize, b.j[q] as usize, &o);
                }
            }
        }
        return broke;
    }
    // Several threads: ranges of bonds, each adding directly to the discs only it touches
    // (same bits, see `split`).
    if !split.as_ref().is_some_and(|s| s.fits(nb, nd, ranges)) {
        *split = Some(Split::new(b.i, b.j, nd, ranges));
    }
    if incidence.as_ref().is_some_and(|inc| inc.discs() != nd) {
        *incidence = None;
    }
    let inc = incidence.get_or_insert_with(|| Incidence::new(b.i, b.j, nd));
    let split = split.as_ref().expect("made above");
    super::split::run(c, b, m, (fx, fy, tq), split, inc, scratch, avx2)
}

pub(super) fn sub<'a>(m: &'a mut BondsMut, r: std::ops::Range<usize>) -> BondsMut<'a> {
    BondsMut {
        fn_: &mut m.fn_[r.clone()],
        fs: &mut m.fs[r.clone()],
        m: &mut m.m[r.clone()],
        status: &mut m.status[r.clone()],
        fj: if m.fj.is_empty() {
            &mut []
        } else {
            &mut m.fj[r]
        },
    }
}

/// Add one bond's contribution to its discs (the only place disc sums are formed). The three
/// slices have one length (so one bounds check covers them).
#[inline(always)]
pub(super) fn scatter(
    fx: &mut [f64],
    fy: &mut [f64],
    tq: &mut [f64],
    i: usize,
    j: usize,
    o: &[f64; 4],
) {
    let n = fx.len();
    let (fx, fy, tq) = (&mut fx[..n], &mut fy[..n], &mut tq[..n]);
    fx[i] -= o[0];
    fy[i] -= o[1];
    tq[i] += o[2];
    fx[j] += o[0];
    fy[j] += o[1];
    tq[j] += o[3];
}

/// 1 + the largest index in `i` and `j` (0 when empty): every index is below `n` exactly when
/// this is at most `n` (branch-free reduction).
pub(super) fn index_bound(i: &[u32], j: &[u32]) -> usize {
    let m = i.iter().chain(j).fold(0u32, |m, &k| m.max(k));
    if i.is_empty() {
        0
    } else {
        m as usize + 1
    }
}

/// [`scatter`] for a block of intact bonds, without bounds checks.
///
/// # Safety
/// Every index in `i` and `j` must be below the common length of `fx`, `fy` and `tq`, and
/// `i` and `j` must have one length, at most [`BOND_BLOCK`].
#[inline(always)]
unsafe fn scatter_unchecked(
    fx: &mut [f64],
    fy: &mut [f64],
    tq: &mut [f64],
    i: &[u32],
    j: &[u32],
    o: &BlockOut,
) {
    let [ox, oy, oti, otj] = o;
    for k in 0..i.len().min(BOND_BLOCK) {
        let (i, j) = (*i.get_unchecked(k) as usize, *j.get_unchecked(k) as usize);
        let (f0, f1, f2, f3) = (ox[k], oy[k], oti[k], otj[k]);
        *fx.get_unchecked_mut(i) -= f0;
        *fy.get_unchecked_mut(i) -= f1;
        *tq.get_unchecked_mut(i) += f2;
        *fx.get_unchecked_mut(j) += f0;
        *fy.get_unchecked_mut(j) += f1;
        *tq.get_unchecked_mut(j) += f3;
    }
}

/// Pass 1a of [`block`] from the packed disc records (AVX2): for four bonds at a time the
/// records of j and i are loaded as vectors, [x, y, v_x, v_y]_j − [..]_i is one lane-wise
/// subtraction (the IEEE operations of the scalar x_j − x_i, ...), and 4×4 transposes turn
/// the rows into the columns d_x, d_y, Δv_x, Δv_y (`dv`) and ω_i, r_i, ω_j, r_j (`ws`, plain
/// copies); the last bonds mod 4 are read from the records one by one. The same bits as
/// the gather from the disc arrays, from one cache line per disc instead of six (the
/// approach of the contact pass, `contact::kernel::gather_aos`).
///
/// # Safety
/// The CPU must support AVX2; every index in `i_` and `j_` must be below `pk.len()`, and
/// they must have one length, at most [`BOND_BLOCK`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn gather_packed(
    pk: &[Packed],
    i_: &[u32],
    j_: &[u32],
    dv: [&mut [f64; BOND_BLOCK]; 4],
    ws: [&mut [f64; BOND_BLOCK]; 4],
) {
    use std::arch::x86_64::*;
    let n = i_.len().min(j_.len()).min(BOND_BLOCK);
    let base = pk.as_ptr();
    // SAFETY (record loads): indices below pk.len() (the contract); records are 64-byte
    // aligned, so both 32-byte halves are aligned.
    let ld_a = |k: u32| _mm256_load_pd((*base.add(k as usize)).a.as_ptr());
    let ld_b = |k: u32| _mm256_load_pd((*base.add(k as usize)).b.as_ptr());
    let [dxs, dys, dvx, dvy] = dv;
    let [wis, ris, wjs, rjs] = ws;
    let mut k = 0;
    while k + 4 <= n {
        let (i, j) = (i_.get_unchecked(k..k + 4), j_.get_unchecked(k..k + 4));
        let d = |l: usize| _mm256_sub_pd(ld_a(j[l]), ld_a(i[l]));
        let [dx, dy, dvxv, dvyv] = transpose4([d(0), d(1), d(2), d(3)]);
        // SAFETY (stores): k + 4 <= n <= BOND_BLOCK.
        let st = |a: &mut [f64; BOND_BLOCK], v| _mm256_storeu_pd(a.as_mut_ptr().add(k), v);
        st(dxs, dx);
        st(dys, dy);
        st(dvx, dvxv);
        st(dvy, dvyv);
        // [ω, r, 1/m, 0] rows of four discs → the columns ω and r.
        let [wi, ri, _, _] = transpose4([ld_b(i[0]), ld_b(i[1]), ld_b(i[2]), ld_b(i[3])]);
        let [wj, rj, _, _] = transpose4([ld_b(j[0]), ld_b(j[1]), ld_b(j[2]), ld_b(j[3])]);
        st(wis, wi);
        st(ris, ri);
        st(wjs, wj);
        st(rjs, rj);
        k += 4;
    }
    for k in k..n {
        let (pi, pj) = (
            &*base.add(*i_.get_unchecked(k) as usize),
            &*base.add(*j_.get_unchecked(k) as usize),
        );
        dxs[k] = pj.a[0] - pi.a[0];
        dys[k] = pj.a[1] - pi.a[1];
        dvx[k] = pj.a[2] - pi.a[2];
        dvy[k] = pj.a[3] - pi.a[3];
        wis[k] = pi.b[0];
        ris[k] = pi.b[1];
        wjs[k] = pj.b[0];
        rjs[k] = pj.b[1];
    }
}

/// [`block`] compiled for AVX2 (4 lanes). Only selects, +, −, ×, ÷ and √ are used, all
/// correctly rounded in IEEE 754, and Rust never contracts to FMA, so the results are the
/// same bits as the baseline build (the approach of `contact::disc_disc`).
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn block_avx2(
    c: &Ctx,
    b: &BondsIn,
    base: usize,
    m: &mut BondsMut,
    out: &mut BlockOut,
    w: &mut Work,
    valid: bool,
) -> (usize, bool) {
    if valid {
        block::<true>(c, b, base, m, out, w)
    } else {
        block::<false>(c, b, base, m, out, w)
    }
}

/// [`block`] with the best instruction set available.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn block_best(
    c: &Ctx,
    b: &BondsIn,
    base: usize,
    m: &mut BondsMut,
    out: &mut BlockOut,
    w: &mut Work,
    avx2: bool,
    valid: bool,
) -> (usize, bool) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` is true only when the CPU reports AVX2 (see `has_avx2`).
        return unsafe { block_avx2(c, b, base, m, out, w, valid) };
    }
    let _ = avx2;
    if valid {
        block::<true>(c, b, base, m, out, w)
    } else {
        block::<false>(c, b, base, m, out, w)
    }
}

/// Work arrays of the one-thread path: [`Work`] and the block's outputs.
#[derive(Clone, Debug)]
pub(super) struct SerialWork {
    w: Work,
    o: BlockOut,
}

/// Outputs of one block, by component (force on j along x, y, torques on i, j) and bond: the
/// vectorised pass stores whole vectors.
pub(super) type BlockOut = [[f64; BOND_BLOCK]; 4];

impl Default for SerialWork {
    fn default() -> SerialWork {
        SerialWork {
            w: Work::new(),
            o: [[0.0; BOND_BLOCK]; 4],
        }
    }
}

/// Per-block work arrays, reused from block to block (not re-zeroed).
#[derive(Clone, Debug)]
pub(super) struct Work {
    dxs: [f64; BOND_BLOCK],
    dys: [f64; BOND_BLOCK],
    ris: [f64; BOND_BLOCK],
    rjs: [f64; BOND_BLOCK],
    dvx: [f64; BOND_BLOCK],
    dvy: [f64; BOND_BLOCK],
    wis: [f64; BOND_BLOCK],
    wjs: [f64; BOND_BLOCK],
    /// n̂x, n̂y, gap, a_i, a_j, v_t, Δω.
    geo: [[f64; BOND_BLOCK]; 7],
}

impl Work {
    pub(super) fn new() -> Work {
        Work {
            dxs: [1.0; BOND_BLOCK],
            dys: [0.0; BOND_BLOCK],
            ris: [0.0; BOND_BLOCK],
            rjs: [0.0; BOND_BLOCK],
            dvx: [0.0; BOND_BLOCK],
            dvy: [0.0; BOND_BLOCK],
            wis: [0.0; BOND_BLOCK],
            wjs: [0.0; BOND_BLOCK],
            geo: [[0.0; BOND_BLOCK]; 7],
        }
    }
}

/// Per-bond parameters of parallel bonds with the stress criterion (k̄n, k̄s, λ̄, β̄, σ̄c, c̄,
/// tan φ̄; zeros for other bonds), and per block of [`BOND_BLOCK`] bonds (blocks start at multiples
/// of BOND_BLOCK) whether all its bonds are such bonds. Built from the groups once (the store
/// rebuilds it when bonds are added or reordered), so that a block whose bonds interleave
/// several such groups (improved ORC: intra-grain and grain-boundary bonds) reads them as
/// arrays instead of looking up each bond's group every step.
#[derive(Clone, Debug, Default)]
pub(super) struct StressParams {
    par: [Vec<f64>; 7],
    block_ok: Vec<bool>,
}

impl StressParams {
    pub(super) fn new(groups: &[BondGroup], compiled: &[Compiled], grp: &[u16]) -> StressParams {
        let mut s = StressParams::default();
        for v in s.par.iter_mut() {
            v.resize(grp.len(), 0.0);
        }
        let mut ok = vec![false; grp.len()];
        for (k, &g) in grp.iter().enumerate() {
            let g = g as usize;
            if let (
                BondModel::Parallel(p),
                Criterion::Stress {
                    tensile, cohesion, ..
                },
            ) = (&groups[g].model, compiled[g].criterion)
            {
                for (v, x) in s.par.iter_mut().zip([
                    p.kn,
                    p.ks,
                    p.lambda,
                    p.beta,
                    tensile,
                    cohesion,
                    compiled[g].tan_phi,
                ]) {
                    v[k] = x;
                }
                ok[k] = true;
            }
        }
        s.block_ok = ok
            .chunks(BOND_BLOCK)
            .map(|c| c.iter().all(|&o| o))
            .collect();
        s
    }

    /// Whether the store had `n` bonds when this was built.
    pub(super) fn fits(&self, n: usize) -> bool {
        self.par[0].len() == n && self.block_ok.len() == n.div_ceil(BOND_BLOCK)
    }

    /// The parameters of the full block starting at `base` (a multiple of [`BOND_BLOCK`]) when all
    /// its bonds are parallel bonds with the stress criterion.
    #[inline(always)]
    fn block(&self, base: usize) -> Option<[&[f64; BOND_BLOCK]; 7]> {
        if !base.is_multiple_of(BOND_BLOCK)
            || !self
                .block_ok
                .get(base / BOND_BLOCK)
                .copied()
                .unwrap_or(false)
        {
            return None;
        }
        let r = base..base + BOND_BLOCK;
        fn a(v: &[f64], r: std::ops::Range<usize>) -> Option<&[f64; BOND_BLOCK]> {
            v.get(r)?.try_into().ok()
        }
        Some([
            a(&self.par[0], r.clone())?,
            a(&self.par[1], r.clone())?,
            a(&self.par[2], r.clone())?,
            a(&self.par[3], r.clone())?,
            a(&self.par[4], r.clone())?,
            a(&self.par[5], r.clone())?,
            a(&self.par[6], r.clone())?,
        ])
    }
}

/// The parameters (p, σ̄c, c̄, tan φ̄) of a block's bonds (groups `grp`, not empty) when they
/// are all in one group of parallel bonds with the stress criterion.
#[inline(always)]
fn uniform_stress(c: &Ctx, grp: &[u16]) -> Option<(ParallelBondParams, f64, f64, f64)> {
    let g = *grp.first()?;
    if grp.iter().fold(0, |a, &h| a | (h ^ g)) != 0 {
        return None;
    }
    let g = g as usize;
    match (&c.groups[g].model, c.compiled[g].criterion) {
        (
            BondModel::Parallel(p),
            Criterion::Stress {
                tensile, cohesion, ..
            },
        ) => Some((*p, tensile, cohesion, c.compiled[g].tan_phi)),
        _ => None,
    }
}

/// Update the block of bonds `base..base + m.status.len()`: new forces and status, and for each
/// bond still intact the force on disc j and the torques on i and j (`[fx, fy, ti, tj]`) in
/// `out` (entries of bonds that are not intact are not to be scattered). Returns the number of
/// bonds broken now and whether all bonds of the block were intact before. `VALID`: every
/// disc index of the bonds is known to be in range (checked by the caller).
#[inline(always)]
fn block<const VALID: bool>(
    c: &Ctx,
    b: &BondsIn,
    base: usize,
    m: &mut BondsMut,
    out: &mut BlockOut,
    w: &mut Work,
) -> (usize, bool) {
    let n = m.status.len();
    let broken_any = m.status.iter().fold(INTACT, |a, &s| a | s) != INTACT;
    // A full block of intact parallel bonds with the stress criterion, with the packed
    // records: the four-lane kernel (the same bits).
    #[cfg(target_arch = "x86_64")]
    if VALID && n == BOND_BLOCK && !broken_any && c.packed.len() == c.v.x.len() {
        use super::parallel4::{block as four, Par};
        let par = match uniform_stress(c, &b.group[base..base + n]) {
            Some((p, tensile, cohesion, tan_phi)) => Some(Par::Uniform([
                p.kn, p.ks, p.lambda, p.beta, tensile, cohesion, tan_phi,
            ])),
            None => c.stress.block(base).map(Par::PerBond),
        };
        if let Some(par) = par {
            // SAFETY: `packed` is not empty only with AVX2 (see `Ctx::packed`); VALID:
            // every index of the block is below the number of discs = its length.
            let broke = unsafe { four(c, b, base, par, m, out) };
            return (broke, true);
        }
    }
    let r = base..base + n;
    let (i_, j_, grp) = (&b.i[r.clone()], &b.j[r.clone()], &b.group[r.clone()]);
    let (g0_, rbar_) = (&b.g0[r.clone()], &b.rbar[r]);
    let (f_n, f_s, f_m) = (&mut m.fn_[..n], &mut m.fs[..n], &mut m.m[..n]);
    let status = &mut m.status[..n];
    let fjs = &mut *m.fj;
    let [ox, oy, oti, otj] = out;
    // Pass 1a: gather the pair data (all disc slices re-cut to one length so the bounds checks
    // fold into one). Entries past `n` keep finite values of an earlier block or the padding
    // (their results are not used).
    let v = &c.v;
    let nd = v.x.len();
    let (x, y, vx, vy) = (&v.x[..nd], &v.y[..nd], &v.vx[..nd], &v.vy[..nd]);
    let (omega, rad) = (&v.omega[..nd], &v.r[..nd]);
    let Work {
        dxs,
        dys,
        ris,
        rjs,
        dvx,
        dvy,
        wis,
        wjs,
        geo,
    } = w;
    #[cfg(target_arch = "x86_64")]
    let from_records = VALID && c.packed.len() == nd;
    #[cfg(not(target_arch = "x86_64"))]
    let from_records = false;
    #[cfg(target_arch = "x86_64")]
    if from_records {
        let dv = [&mut *dxs, &mut *dys, &mut *dvx, &mut *dvy];
        let ws = [&mut *wis, &mut *ris, &mut *wjs, &mut *rjs];
        // SAFETY: `packed` is not empty only with AVX2 (see `Ctx::packed`); VALID: every
        // index of the block is below nd = its length.
        unsafe { gather_packed(c.packed, i_, j_, dv, ws) };
    }
    if VALID && !from_records {
        for k in 0..n {
            // SAFETY: VALID: the caller checked i, j < nd for every bond; k < n = len of all.
            unsafe {
                let (i, j) = (*i_.get_unchecked(k) as usize, *j_.get_unchecked(k) as usize);
                dxs[k] = x.get_unchecked(j) - x.get_unchecked(i);
                dys[k] = y.get_unchecked(j) - y.get_unchecked(i);
                ris[k] = *rad.get_unchecked(i);
                rjs[k] = *rad.get_unchecked(j);
                dvx[k] = vx.get_unchecked(j) - vx.get_unchecked(i);
                dvy[k] = vy.get_unchecked(j) - vy.get_unchecked(i);
                wis[k] = *omega.get_unchecked(i);
                wjs[k] = *omega.get_unchecked(j);
            }
        }
    }
    for k in 0..if VALID { 0 } else { n } {
        let (i, j) = (i_[k] as usize, j_[k] as usize);
        if i >= nd || j >= nd {
            // Cannot happen (indices are checked when bonds are added or remapped).
            status[k] = BROKEN;
            continue;
        }
        dxs[k] = x[j] - x[i];
        dys[k] = y[j] - y[i];
        ris[k] = rad[i];
        rjs[k] = rad[j];
        dvx[k] = vx[j] - vx[i];
        dvy[k] = vy[j] - vy[i];
        wis[k] = omega[i];
        wjs[k] = omega[j];
    }
    // Pass 1b: geometry and kinematics, branch-free over the whole block. Tangential relative
    // velocity of j's and i's material points at the contact point,
    // ((v_j − ω_j a_j t̂) − (v_i + ω_i a_i t̂))·t̂ with t̂ = (−n_y, n_x), and relative spin.
    {
        let [gnx, gny, ggap, gai, gaj, gvt, gdw] = geo;
        for k in 0..BOND_BLOCK {
            let (dx, dy) = v.img.delta_select(dxs[k], dys[k]);
            let (nx, ny, gap, ai, aj) = normal_gap(dx, dy, ris[k], rjs[k]);
            gnx[k] = nx;
            gny[k] = ny;
            ggap[k] = gap;
            gai[k] = ai;
            gaj[k] = aj;
            gvt[k] = dvx[k] * -ny + dvy[k] * nx - (wjs[k] * aj + wis[k] * ai);
            gdw[k] = wjs[k] - wis[k];
        }
    }
    let [gnx, gny, ggap, gai, gaj, gvt, gdw] = &*geo;
    let dt = c.dt;
    // One bond of pass 2: returns (new forces, output, break code 0 | 1 + mode index).
    #[inline(always)]
    fn finish(
        nx: f64,
        ny: f64,
        ai: f64,
        aj: f64,
        f: [f64; 3],
        flags: (bool, bool),
    ) -> ([f64; 4], u8) {
        let (fn_, fs, m) = (f[0], f[1], f[2]);
        let (tx, ty) = (-ny, nx);
        let o = [
            fn_ * nx + fs * tx,
            fn_ * ny + fs * ty,
            -ai * fs - m,
            -aj * fs + m,
        ];
        let code = if flags.0 {
            1 + BreakMode::Tension.index() as u8
        } else if flags.1 {
            1 + BreakMode::Shear.index() as u8
        } else {
            0
        };
        (o, code)
    }
    let kin = |k: usize| Kinematics {
        gap: ggap[k],
        dus: gvt[k] * dt,
        dtheta: gdw[k] * dt,
    };
    // Bond length R_i + R_j + g0 (only the strain criterion reads it).
    let length = |k: usize| gai[k] + gaj[k] - ggap[k] + g0_[k];
    // Blocks with a few broken bonds take the straight-line loops too, masked: a broken
    // bond's lane is computed but its forces are kept and it reports no break (the general
    // path skips it; its outputs are not scattered, see `run`). Blocks with many broken bonds
    // take the general path, which skips them.
    let broken = if broken_any {
        status.iter().filter(|&&s| s != INTACT).count()
    } else {
        0
    };
    let straight_ok = n == BOND_BLOCK && broken <= BOND_BLOCK / 4;
    let fast = if straight_ok {
        uniform_stress(c, grp)
    } else {
        None
    };
    let mut codes = [0u8; BOND_BLOCK];
    // Several groups, all parallel bonds with the stress criterion (improved ORC: intra-grain
    // and grain-boundary bonds interleave in store order): their parameters are read per
    // bond and the straight-line loop below evaluates the same expressions as the general
    // path, with the same values: same bits.
    let mixed = if fast.is_none() && straight_ok {
        c.stress.block(base)
    } else {
        None
    };
    let all_intact = (fast.is_some() || mixed.is_some()) && !broken_any;
    // Pass 2, straight-line code over a full block of parallel bonds with the stress
    // criterion; `$par(k)` gives bond k's parameters, `$masked` whether broken bonds are
    // to be left as they are.
    macro_rules! straight {
        ($masked:expr, $par:expr) => {
            for k in 0..BOND_BLOCK {
                let (p, tensile, cohesion, tan_phi) = $par(k);
                let (f, l) = potyondy2004::update(
                    &p,
                    rbar_[k],
                    c.t,
                    g0_[k],
                    length(k),
                    &kin(k),
                    [f_n[k], f_s[k], f_m[k]],
                );
                let (o, code) = finish(
                    gnx[k],
                    gny[k],
                    gai[k],
                    gaj[k],
                    f,
                    stress_flags(&l, tensile, cohesion, tan_phi),
                );
                let keep = !$masked || status[k] == INTACT;
                f_n[k] = if keep { f[0] } else { f_n[k] };
                f_s[k] = if keep { f[1] } else { f_s[k] };
                f_m[k] = if keep { f[2] } else { f_m[k] };
                ox[k] = o[0];
                oy[k] = o[1];
                oti[k] = o[2];
                otj[k] = o[3];
                codes[k] = if keep { code } else { 0 };
            }
        };
    }
    if let Some([kn, ks, lambda, beta, tensile, cohesion, tan_phi]) = mixed {
        let par = |k: usize| {
            let p = ParallelBondParams {
                kn: kn[k],
                ks: ks[k],
                lambda: lambda[k],
                beta: beta[k],
            };
            (p, tensile[k], cohesion[k], tan_phi[k])
        };
        if broken_any {
            straight!(true, par);
        } else {
            straight!(false, par);
        }
    } else if let Some(q) = fast {
        // One group: the parameters are the same for every bond.
        let par = |_: usize| q;
        if broken_any {
            straight!(true, par);
        } else {
            straight!(false, par);
        }
    } else {
        // Pass 2, general: any model and criterion per bond, skipping broken bonds.
        for k in 0..n {
            if status[k] != INTACT {
                continue;
            }
            let g = grp[k] as usize;
            let f0 = [f_n[k], f_s[k], f_m[k]];
            let (rb, g0, len, kn) = (rbar_[k], g0_[k], length(k), kin(k));
            let (f, flags) = match &c.groups[g].model {
                BondModel::Parallel(p) => {
                    let (f, l) = potyondy2004::update(p, rb, c.t, g0, len, &kn, f0);
                    (f, c.compiled[g].flags(&l))
                }
                BondModel::Contact(p) => {
                    let (f, l) = contact_bond::update(p, rb, c.t, g0, len, &kn, f0);
                    (f, c.compiled[g].flags(&l))
                }
                BondModel::FlatJoint(p) => {
                    let strength = match c.compiled[g].criterion {
                        Criterion::Stress {
                            tensile, cohesion, ..
                        } => ElementStrength {
                            tensile,
                            cohesion,
                            tan_phi: c.compiled[g].tan_phi,
                        },
                        // (A flat-joint group has the stress criterion: BondGroup::validate.)
                        _ => ElementStrength {
                            tensile: f64::INFINITY,
                            cohesion: f64::INFINITY,
                            tan_phi: 0.0,
                        },
                    };
                    let motion = Motion {
                        delta: kn.gap - g0,
                        dus: kn.dus,
                        dtheta: kn.dtheta,
                    };
                    flat_joint::bond_step(p, &strength, rb, c.t, motion, &mut fjs[k])
                }
            };
            f_n[k] = f[0];
            f_s[k] = f[1];
            f_m[k] = f[2];
            let (o, code) = finish(gnx[k], gny[k], gai[k], gaj[k], f, flags);
            ox[k] = o[0];
            oy[k] = o[1];
            oti[k] = o[2];
            otj[k] = o[3];
            codes[k] = code;
        }
    }
    let mut broke = 0;
    if codes.iter().fold(0, |a, &c| a | c) != 0 {
        for k in 0..n {
            if codes[k] != 0 {
                status[k] = NEW + codes[k] - 1;
                broke += 1;
            }
        }
    }
    (broke, all_intact)
}

#[cfg(test)]
mod tests;
