//! The bond stage on several threads, by ranges of bonds: the bond store (sorted by the
//! smaller disc index, see `Bonds::remap`) is cut into contiguous ranges of whole blocks, one
//! per worker. Each worker updates its bonds block by block and adds their forces directly to
//! the discs that no other range touches, in bond order, exactly as the one-thread path does.
//! A disc touched by the bonds of more than one range ("shared": discs sit in space order, so
//! a thin layer at each range boundary) must receive its contributions in bond order across
//! the ranges, so the blocks that reach one store their bonds' outputs in per-bond slots, and a
//! short serial pass adds the slots of each shared disc in bond order ([`Incidence`]). Every
//! disc thus sees the additions of the one-thread path in the same order: the results are
//! bit-identical for any thread count (the same construction as the contact pass,
//! `contact::owned`).
//!
//! Compared with a two-pass form (all outputs to a per-bond array, then a gather over discs),
//! the forces of most bonds go straight to the discs: no 32-byte record per bond written and
//! read back every step.

use super::incidence::Incidence;
use super::kernel::{block_best, sub, BlockOut, BondsIn, BondsMut, Ctx, Work, INTACT};
use crate::lanes::BOND_BLOCK;
use crate::team::SyncPtr;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

/// The cut of the bonds into ranges for one bond list, disc count and range count.
#[derive(Clone, Debug, Default)]
pub(super) struct Split {
    /// (bonds, discs, ranges) it was made for (the store drops it when its bonds change).
    key: (usize, usize, usize),
    /// Range r holds bonds `bounds[r]..bounds[r + 1]` (multiples of [`BOND_BLOCK`] but the last).
    bounds: Vec<usize>,
    /// Whether disc d is touched by the bonds of more than one range.
    shared: Vec<bool>,
    /// The shared discs, increasing.
    shared_list: Vec<u32>,
    /// Per block of [`BOND_BLOCK`] bonds: whether one of its bonds has a shared disc.
    dirty: Vec<bool>,
}

impl Split {
    /// Whether it was made for `nb` bonds, `nd` discs and `ranges` ranges.
    pub fn fits(&self, nb: usize, nd: usize, ranges: usize) -> bool {
        self.key == (nb, nd, ranges)
    }

    /// Cut the bonds (i, j) of `nd` discs into `ranges` ranges of about equal length. Every
    /// index must be below `nd`.
    pub fn new(i: &[u32], j: &[u32], nd: usize, ranges: usize) -> Split {
        let nb = i.len();
        let ranges = ranges.max(1);
        let mut bounds = vec![0];
        for r in 1..ranges {
            let k = (nb * r / ranges) / BOND_BLOCK * BOND_BLOCK;
            bounds.push(k.max(bounds[r - 1]));
        }
        bounds.push(nb);
        // The first range touching each disc; touched by another one too: shared.
        const NONE: u32 = u32::MAX;
        let mut first = vec![NONE; nd];
        let mut shared = vec![false; nd];
        for r in 0..ranges {
            for q in bounds[r]..bounds[r + 1] {
                for d in [i[q] as usize, j[q] as usize] {
                    if first[d] == NONE {
                        first[d] = r as u32;
                    } else if first[d] != r as u32 {
                        shared[d] = true;
                    }
                }
            }
        }
        let shared_list = (0..nd as u32).filter(|&d| shared[d as usize]).collect();
        let dirty = (0..nb)
            .step_by(BOND_BLOCK)
            .map(|k| {
                (k..(k + BOND_BLOCK).min(nb))
                    .any(|q| shared[i[q] as usize] || shared[j[q] as usize])
            })
            .collect();
        Split {
            key: (nb, nd, ranges),
            bounds,
            shared,
            shared_list,
            dirty,
        }
    }

    /// Number of shared discs.
    #[cfg(test)]
    pub fn n_shared(&self) -> usize {
        self.shared_list.len()
    }
}

/// The bond stage over the ranges of `split` in parallel (see the module doc): bond forces and
/// status in `m`, the forces of intact bonds added to `fx, fy, tq` (length `nd`). `slot`:
/// per-bond outputs of the blocks that reach shared discs (resized to the bond count).
/// Returns the number of bonds broken now. Every disc index must be below `nd` and the disc
/// views of `c` must have `nd` entries (the caller's `valid`).
#[allow(clippy::too_many_arguments)]
pub(super) fn run(
    c: &Ctx,
    b: &BondsIn,
    m: BondsMut,
    (fx, fy, tq): (&mut [f64], &mut [f64], &mut [f64]),
    split: &Split,
    incidence: &Incidence,
    slot: &mut Vec<[f64; 4]>,
    avx2: bool,
) -> usize {
    let nb = b.i.len();
    let nd = fx.len();
    assert!(fy.len() == nd && tq.len() == nd && split.key.0 == nb && split.key.1 == nd);
    assert!(m.fn_.len() == nb && m.fs.len() == nb && m.m.len() == nb && m.status.len() == nb);
    assert!(b.i.len() == nb && b.j.len() == nb && incidence.discs() == nd);
    if slot.len() != nb {
        slot.resize(nb, [0.0; 4]);
    }
    let ranges = split.bounds.len() - 1;
    let (pf, ps, pm, pst, psl) = (
        SyncPtr::of(&mut *m.fn_),
        SyncPtr::of(&mut *m.fs),
        SyncPtr::of(&mut *m.m),
        SyncPtr::of(&mut *m.status),
        SyncPtr::of(&mut slot[..]),
    );
    // Flat-joint interfaces: one per bond, or none.
    let fj_all = !m.fj.is_empty();
    assert!(!fj_all || m.fj.len() == nb);
    let pfj = SyncPtr::of(&mut *m.fj);
    let (px, py, pt) = (
        SyncPtr::of(&mut *fx),
        SyncPtr::of(&mut *fy),
        SyncPtr::of(&mut *tq),
    );
    // (An integer sum: the same for any order of the ranges.)
    let broke = AtomicUsize::new(0);
    // Range r on worker r of the step's team at every step (as the contact pass's ranges).
    crate::team::run(ranges, &|r| {
        let (lo, hi) = (split.bounds[r], split.bounds[r + 1]);
        // SAFETY: the bond ranges [lo, hi) are disjoint and within the nb entries of
        // every bond array (the flat-joint states too when there are any: asserted above).
        let (mut mr, slot) = unsafe {
            let n = hi - lo;
            let mr = BondsMut {
                fn_: pf.slice(lo, n),
                fs: ps.slice(lo, n),
                m: pm.slice(lo, n),
                status: pst.slice(lo, n),
                fj: if fj_all { pfj.slice(lo, n) } else { &mut [] },
            };
            (mr, psl.slice(lo, n))
        };
        let mut w = Work::new();
        let mut o: BlockOut = [[0.0; BOND_BLOCK]; 4];
        let mut n_broke = 0;
        for k in (lo..hi).step_by(BOND_BLOCK) {
            let e = (k + BOND_BLOCK).min(hi);
            let mut s = sub(&mut mr, k - lo..e - lo);
            let (nbrk, all_intact) = block_best(c, b, k, &mut s, &mut o, &mut w, avx2, true);
            n_broke += nbrk;
            let all = all_intact && nbrk == 0;
            let dirty = split.dirty[k / BOND_BLOCK];
            for q in k..e {
                if !all && s.status[q - k] != INTACT {
                    continue;
                }
                let v = [o[0][q - k], o[1][q - k], o[2][q - k], o[3][q - k]];
                let (i, j) = (b.i[q] as usize, b.j[q] as usize);
                if dirty {
                    slot[q - lo] = v;
                }
                // SAFETY: i, j < nd (the contract); a disc that is not shared is touched
                // by this range's bonds only, so no other thread accesses it; shared
                // discs are not written here.
                unsafe {
                    if !dirty || !split.shared[i] {
                        *px.ptr().add(i) -= v[0];
                        *py.ptr().add(i) -= v[1];
                        *pt.ptr().add(i) += v[2];
                    }
                    if !dirty || !split.shared[j] {
                        *px.ptr().add(j) += v[0];
                        *py.ptr().add(j) += v[1];
                        *pt.ptr().add(j) += v[3];
                    }
                }
            }
        }
        broke.fetch_add(n_broke, Relaxed);
    });
    let broke = broke.into_inner();
    // Shared discs: all their bonds' contributions, in bond order.
    incidence.add(&split.shared_list, slot, m.status, fx, fy, tq);
    broke
}
