//! Disc–disc force pass over the neighbour list.
//!
//! Pairs are computed in blocks ([`super::kernel`]): gather, branch-free evaluation of the law
//! (vectorised), then a scatter loop adds the forces to the discs in pair order. One thread:
//! forces are scattered pair by pair in list order. Several threads: each owns a contiguous
//! range of discs and scatters directly into it; the few discs at range boundaries get their
//! forces in a short second pass in the same order ([`super::owned`]) — the same sequence of
//! floating-point additions as the one-thread scatter, so results are bit-identical for any
//! thread count. Energies are summed in pair order within fixed chunks of [`CHUNK`] discs and
//! the chunk sums added in chunk order.

use super::kernel::{Acc4, Ctx, LinearGamma, LinearRatio, PairHook, PairLaw, Scratch};
use super::owned::{self, ListRef, Outs, Plan};
use super::{ContactLaws, ContactModel, NormalDamping};
use crate::lanes::Packed;
use crate::neighbors::{MinImage, Neighbors};
use crate::state::Discs;

/// Discs per energy chunk (fixed so that reductions do not depend on the thread count).
pub const CHUNK: usize = 512;
/// Split the pass between threads from this many listed pairs on.
pub const PAR_MIN_PAIRS: usize = 2048;

/// Energies of one force pass: strain (stored, at this step), dissipated by friction during
/// this step, and (walls only) the part F_d · v_wall Δt of the wall dashpots' dissipation; the
/// dashpot forces themselves are summed per disc into [`Dashpot`] for the integration pass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassEnergy {
    pub strain: f64,
    pub damp: f64,
    pub fric: f64,
}

impl PassEnergy {
    pub fn add(&mut self, o: &PassEnergy) {
        self.strain += o.strain;
        self.damp += o.damp;
        self.fric += o.fric;
    }
}

/// Per-disc sums of the contact dashpot forces and torques of this step (filled only when
/// energy is tracked and some law has a dashpot). The integration pass books their dissipation
/// as −(F_d · v̄ + T_d ω̄) Δt with v̄ the mean of the half-step velocities around t, the
/// velocity the kinetic energy uses: for central differences ½m(v₊² − v₋²) = F · v̄ Δt
/// exactly, so the balance closes to O(Δt²); F_d · v(t − Δt/2) Δt (the former bookkeeping) is
/// off by O(Δt).
///
/// Without dashpots (every law undamped, [`ContactLaws::has_dashpots`]) each dashpot force is
/// c·v = 0·v = ±0 for a finite state, so every dissipation term built from these sums is ±0
/// and the accumulated dashpot dissipation (which starts at +0 and only has ±0 subtracted or
/// added as +0 + (±0)) stays exactly +0: skipping the sums gives the same bits. (A non-finite
/// state would make the terms NaN; the guard stops such a run before any output row.)
#[derive(Clone, Debug, Default)]
pub struct Dashpot {
    pub fx: Vec<f64>,
    pub fy: Vec<f64>,
    pub t: Vec<f64>,
}

impl Dashpot {
    /// Zeroed sums for `n` discs.
    pub fn reset(&mut self, n: usize) {
        for v in [&mut self.fx, &mut self.fy, &mut self.t] {
            v.clear();
            v.resize(n, 0.0);
        }
    }
}

/// Work arrays of the pass (see [`super::owned`]): partner-side force slots of pairs whose
/// partner is a shared disc (fx, fy on j, torque on j), own-pair sums of shared discs.
#[derive(Clone, Debug, Default)]
pub struct Slots {
    /// Per-disc dashpot sums of this step (energy tracking with dashpots only).
    pub dashpot: Dashpot,
    /// Partner-side dashpot slots (energy tracking with dashpots only).
    pub dfx: Vec<f64>,
    pub dfy: Vec<f64>,
    pub dtj: Vec<f64>,
    /// Block scratch of the one-thread pass (allocated once).
    pub scratch: Box<Scratch>,
    pub fx: Vec<f64>,
    pub fy: Vec<f64>,
    pub tj: Vec<f64>,
    /// Own-pair sums of shared discs: fx, fy, torque, and the dashpot parts.
    pub own: [Vec<f64>; 6],
    pub chunk_energy: Vec<PassEnergy>,
    /// The split of the discs between threads.
    pub plan: Plan,
    /// Packed disc records of the AVX2 gather and force accumulators of the AVX2 scatter
    /// (see [`super::owned`]), rebuilt at every pass.
    pub packed: Vec<Packed>,
    pub acc: Vec<Acc4>,
    /// The accumulators `acc` are all +0.0: the last AVX2 pass copied them out and cleared
    /// them (while in cache), so the next `pack` need not (saves a read of every record).
    pub acc_zero: bool,
    /// `packed` holds the discs' current records, written by the integrator at the end of
    /// the last step (only inside [`crate::World::run_while`], where nothing else can change
    /// the discs between two steps, and without rigid clumps, whose pass moves discs after
    /// the integrator); the next pass then skips `pack` and clears this. Any neighbour
    /// rebuild clears it too (discs may be reordered).
    pub packed_fresh: bool,
    /// `packed` holds the records of the discs as the last disc–disc pass saw them (its
    /// AVX2 path ran): the bond stage of the same step reads them (nothing moves the discs
    /// in between). Set by the pass, cleared by the pipeline when the discs move.
    pub packed_current: bool,
    /// Take the portable gather and scatter even when the CPU has AVX2 (tests).
    pub portable: bool,
}

/// Whether the list is consistent with `n` discs (checked before unchecked indexing).
fn valid(d: &Discs, nb: &Neighbors, minv: &[f64]) -> bool {
    let n = d.len();
    let np = nb.nbr.len();
    nb.start.len() == n + 1
        && nb.start[n] as usize == np
        && nb.us.len() == np
        && nb.mr.len() == np
        && (nb.g0.is_empty() || nb.g0.len() == np)
        && nb.rstart.len() == n + 1
        && nb.rpair.len() == np
        && minv.len() == n
        && [
            d.y.len(),
            d.vx.len(),
            d.vy.len(),
            d.omega.len(),
            d.r.len(),
            d.material.len(),
        ]
        .iter()
        .all(|&l| l == n)
        && [d.fx.len(), d.fy.len(), d.torque.len()]
            .iter()
            .all(|&l| l == n)
        && (nb.verified
            || ((nb.nbr.iter().fold(0u32, |m, &j| m.max(j)) as usize) < n.max(1)
                && (nb.rpair.iter().fold(0u32, |m, &p| m.max(p)) as usize) < np.max(1)
                && nb.start.windows(2).all(|w| w[0] <= w[1])))
}

/// Compute disc–disc contact forces into `d.fx, d.fy, d.torque` (their previous content is
/// replaced: the pass clears them or, on the AVX2 path, overwrites them with its
/// accumulators, which start at +0.0, so the caller need not clear them). Returns the pass energies (zero unless `track_energy`). `dashpots` (only with
/// `track_energy`): sum the dashpot forces per disc into `slots.dashpot` for the integration
/// pass; the caller passes `false` when no law has a dashpot
/// ([`ContactLaws::has_dashpots`]), and the sums are then neither reset nor filled. `hook`:
/// evaluated with the pairs ([`super::kernel::PairHook`]; the pipeline passes the fused
/// parallel bonds, `bond::fused`), or none. `ranges`: the step's thread count (the pass cuts
/// the discs into that many ranges when it has enough pairs; same results for any).
#[allow(clippy::too_many_arguments)]
pub(crate) fn compute<H: PairHook>(
    d: &mut Discs,
    nb: &mut Neighbors,
    minv: &[f64],
    laws: &ContactLaws,
    img: MinImage,
    dt: f64,
    track_energy: bool,
    dashpots: bool,
    slots: &mut Slots,
    ranges: usize,
    hook: Option<&H>,
) -> PassEnergy {
    assert!(valid(d, nb, minv), "neighbour list out of date");
    if !nb.verified || nb.owner.len() != nb.nbr.len() {
        nb.set_owner();
    }
    nb.verified = true;
    let dashpots = track_energy && dashpots;
    if dashpots {
        slots.dashpot.reset(d.len());
    }
    let model = uniform_model(d, laws);
    let a = (
        d,
        nb,
        minv,
        img,
        dt,
        (track_energy, dashpots),
        (slots, ranges),
        hook,
    );
    match model {
        Some(ContactModel::Linear(l)) => match l.damping {
            NormalDamping::Gamma(g) => run(a, &LinearGamma(l, g)),
            NormalDamping::Ratio(z) => run(a, &LinearRatio(l, z)),
        },
        Some(ContactModel::HertzMindlin(h)) => run(a, &h),
        // The catalogue law takes the table path (its match arm there).
        Some(ContactModel::Granular(_)) | None => run(a, laws),
    }
}

/// The one law of every listed pair when all discs share one material without rolling
/// resistance (walls and tools have their own materials but are not in this pass): then the
/// branch-free uniform path computes exactly what the table path would (same expressions, see
/// `kernel::PairLaw`), without the per-pair lookups.
fn uniform_model(d: &Discs, laws: &ContactLaws) -> Option<ContactModel> {
    let m0 = d.material.first().copied().unwrap_or(0);
    let one = d.material.iter().fold(0u16, |a, &m| a | (m ^ m0)) == 0;
    (one && laws.rolling(m0, m0).is_none()).then(|| *laws.model(m0, m0))
}

/// Whether the pass evaluates every pair with one linear spring-dashpot law without dashpot
/// sums (`dashpots`: energies tracked and some law has a dashpot): the case the four-lane
/// kernel (`super::linear4`, AVX2) takes, and the one in which parallel bonds are evaluated
/// with their pairs (`bond::fused`; on every CPU, so that results do not depend on it).
pub(crate) fn uniform_linear(d: &Discs, laws: &ContactLaws, dashpots: bool) -> bool {
    !dashpots && matches!(uniform_model(d, laws), Some(ContactModel::Linear(_)))
}

type Args<'a, H> = (
    &'a mut Discs,
    &'a mut Neighbors,
    &'a [f64],
    MinImage,
    f64,
    (bool, bool),
    (&'a mut Slots, usize),
    Option<&'a H>,
);

fn run<L: PairLaw, H: PairHook>(a: Args<H>, law: &L) -> PassEnergy {
    let (d, nb, minv, img, dt, track, (slots, threads), hook) = a;
    let ranges = if threads > 1 && nb.nbr.len() >= PAR_MIN_PAIRS {
        threads
    } else {
        1
    };
    let Discs {
        x,
        y,
        vx,
        vy,
        omega,
        r,
        material,
        fx,
        fy,
        torque,
        ..
    } = d;
    let c = Ctx {
        x,
        y,
        vx,
        vy,
        w: omega,
        r,
        mat: material,
        minv,
        start: &nb.start,
        nbr: &nb.nbr,
        owner: &nb.owner,
        g0: &nb.g0,
        law,
        img,
        dt,
        hook,
    };
    let (us, mr) = (&mut nb.us, &mut nb.mr);
    let list = ListRef {
        builds: nb.builds,
        start: &nb.start,
        nbr: &nb.nbr,
        rstart: &nb.rstart,
        rpair: &nb.rpair,
    };
    // The dashpot sums are lent to the pass (moved out and back: no copy).
    let mut dash = std::mem::take(&mut slots.dashpot);
    let outs = Outs {
        fx,
        fy,
        tq: torque,
        dash: [&mut dash.fx, &mut dash.fy, &mut dash.t],
    };
    let e = match track {
        (true, true) => owned::pass::<true, true, L, H>(&c, us, mr, &list, outs, slots, ranges),
        (true, false) => owned::pass::<true, false, L, H>(&c, us, mr, &list, outs, slots, ranges),
        (false, _) => owned::pass::<false, false, L, H>(&c, us, mr, &list, outs, slots, ranges),
    };
    slots.dashpot = dash;
    e
}

#[cfg(test)]
mod tests {
    use crate::bond::bench::shaken_hex_lattice;
    use crate::contact::{HertzMindlin, LinearSpringDashpot, NormalDamping};
    use crate::{ContactLaws, ContactModel, Params, World};

    /// All discs of one material take the uniform (branch-free, no lookup) path even when the
    /// table has other materials (walls, tools); it gives the bits of the table path, which
    /// runs when one disc has another material with the same law.
    #[test]
    fn uniform_path_gives_the_table_bits() {
        let st = shaken_hex_lattice([16, 8], 11, 0.02, 20.0);
        let lin = |damping| LinearSpringDashpot {
            kn: 1e5,
            ks: 3e4,
            damping,
            shear_damping: 0.5,
            mu: 0.3,
        };
        let models = [
            ContactModel::Linear(lin(NormalDamping::Ratio(0.0))),
            ContactModel::Linear(lin(NormalDamping::Ratio(0.2))),
            ContactModel::Linear(lin(NormalDamping::Gamma(100.0))),
            ContactModel::HertzMindlin(HertzMindlin::from_materials(
                1e8, 0.25, 1e8, 0.25, 0.8, 0.3,
            )),
        ];
        for model in models {
            let run = |odd: bool| {
                let mut st = st.clone();
                if odd {
                    st.discs.material[7] = 1;
                }
                // Three materials, one law (material 2 stands for a tool).
                let laws = ContactLaws::new(3, model);
                let params = Params {
                    dt_fixed: Some(2e-7),
                    skin: Some(1e-4),
                    ..Params::default()
                };
                let mut w = World::new(st, params, laws);
                w.run(30);
                let d = &w.state.discs;
                let bits: Vec<u64> = [&d.x, &d.y, &d.theta, &d.vx, &d.vy, &d.omega]
                    .iter()
                    .chain([&d.fx, &d.fy, &d.torque].iter())
                    .flat_map(|v| v.iter().map(|x| x.to_bits()))
                    .collect();
                (bits, format!("{:?}", w.energy()))
            };
            let (a, b) = (run(false), run(true));
            assert!(a.0 == b.0, "{model:?}: state differs");
            assert_eq!(a.1, b.1, "{model:?}: energy");
        }
    }

    /// Without dashpots the per-disc dashpot sums are skipped; that gives the bits (state and
    /// energies) of the pass with the sums, which a damped law of an unused material turns on.
    #[test]
    fn undamped_laws_skip_the_dashpot_sums_with_the_same_bits() {
        let st = shaken_hex_lattice([16, 8], 3, 0.02, 20.0);
        let law = LinearSpringDashpot {
            kn: 1e5,
            ks: 3e4,
            damping: NormalDamping::Ratio(0.0),
            shear_damping: 0.5,
            mu: 0.3,
        };
        let run = |damped_other: bool| {
            let mut laws = ContactLaws::new(2, ContactModel::Linear(law));
            if damped_other {
                let damped = LinearSpringDashpot {
                    damping: NormalDamping::Ratio(0.3),
                    ..law
                };
                laws.set(1, 1, ContactModel::Linear(damped));
            }
            assert_eq!(laws.has_dashpots(), damped_other);
            let params = Params {
                dt_fixed: Some(2e-7),
                skin: Some(1e-4),
                local_damping: 0.7,
                ..Params::default()
            };
            let mut w = World::new(st.clone(), params, laws);
            w.run(30);
            let d = &w.state.discs;
            let bits: Vec<u64> = [&d.x, &d.y, &d.theta, &d.vx, &d.vy, &d.omega]
                .iter()
                .flat_map(|v| v.iter().map(|x| x.to_bits()))
                .collect();
            (bits, format!("{:?}", w.energy()))
        };
        let (a, b) = (run(false), run(true));
        assert!(a.0 == b.0, "state differs");
        assert_eq!(a.1, b.1, "energy");
    }
}
