//! The 2D flat-joint interface of Potyondy (2012), "A flat-jointed bonded-particle material for
//! hard rock", 46th US Rock Mechanics/Geomechanics Symposium, ARMA 12-501 (PFC's flat-joint
//! contact model; reviewed in Potyondy 2015, "The bonded-particle model as a tool for rock
//! mechanics research and application", Geosyst. Eng. 18:1-28).
//!
//! Two discs meet at a flat interface of half-width R̄ = λ̄·min(R1, R2) and thickness t, centred
//! at the contact point and normal to the line of centres, divided into N equal elements of
//! width w = 2R̄/N (element e spans s ∈ [−R̄ + e·w, −R̄ + (e+1)·w] along the tangent t̂). Each
//! element is **bonded** (it carries tension, compression, shear and bending: cement) or
//! **unbonded** (compression only, and shear up to Coulomb friction μ). Unlike a parallel bond
//! ([`super::potyondy2004`]), breaking an element leaves the rest of the interface working, and
//! a fully broken interface still resists rotation and sliding through its compressed
//! elements: the remedy for the parallel-bond model's too low UCS/σt ratio and friction angle.
//!
//! **Normal part** (total form, as the parallel bond's): with δ = g − g0 the change of the gap
//! at the contact point since installation (opening positive) and θ = Σ(ω2 − ω1)Δt the
//! relative rotation since installation, the gap at s along the interface changes by
//! δ(s) = δ − θ·s (disc 2 turning counter-clockwise closes the side s > 0). The normal
//! pressure is p(s) = −k̄n·δ(s) (positive in compression) on a bonded element and
//! max(0, −k̄n·δ(s)) on an unbonded one; an element's normal force and its moment about the
//! contact point on disc 2 are
//!
//! ```text
//! F_e = t ∫_e p(s) ds            M_e = −t ∫_e p(s)·s ds
//! ```
//!
//! (closed forms: p is linear on the element, or linear on its compressed part). With every
//! element bonded, ΣF_e = −k̄n·2R̄t·δ and ΣM_e = −k̄n·(2/3)R̄³t·θ for any N: exactly the parallel
//! bond's Ā and Ī, so an intact flat joint is as stiff as a parallel bond of the same k̄n, R̄.
//!
//! **Shear part** (incremental, per element): F_s,e −= k̄s·(w t)·Δδs with Δδs the shear
//! displacement increment at the contact point (the same for every element in 2D); on an
//! unbonded element |F_s,e| ≤ μ·F_e (zero when the element is open).
//!
//! **Strength of a bonded element** (PFC's flat joint): tension when the largest tensile stress
//! on the element, max over its two edges of k̄n·δ(s), reaches σc; otherwise shear when
//! τ_e = |F_s,e|/(w t) reaches c − σ_e tan φ_b, σ_e = −F_e/(w t) the element's mean normal stress
//! (tension positive). A broken element is unbonded from that step on (its forces are
//! recomputed under the unbonded rules in the same step).
//!
//! **Forces on the discs** as for the parallel bond: on disc 2, F = (ΣF_e) n̂ + (ΣF_s,e) t̂ at the
//! contact point plus the moment ΣM_e; the opposite on disc 1.
//!
//! **As a bond group** (`flat_joint_potyondy2012` in scenes; `bond_step`): the elements'
//! strengths are the group's stress criterion; the interface state ([`FlatJointState`]) is kept
//! per bond by the store and written to checkpoints. When its last bonded element breaks, the
//! bond counts as broken (one entry in the break log, with that element's mode; the bond
//! counts and `Bonds::n_intact` follow the cement); if the interface is still in contact it
//! stays, as in Potyondy (2012), a frictional flat contact (compression, friction and the moment
//! of its compressed part: it resists rolling) and leaves the bond stage when it opens, the
//! pair's contact law carrying what touches later.
//! One departure from PFC's flat-joint *contact*, which replaces the contact law of the pair:
//! here the disc–disc contact law acts beside the interface (as beside a parallel bond). Not
//! here yet: PFC's installation gap and slit (initially unbonded) elements: every element
//! starts bonded, at zero force.

use super::{potyondy2004, BondError};
use serde::{Deserialize, Serialize};

/// The most elements an interface may have (the element state is a fixed-size array).
pub const MAX_ELEMENTS: usize = 8;

/// Flat-joint parameters of a bond group. Strengths come from the group's stress criterion
/// (σc, c, φ_b), applied per element.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlatJointParams {
    /// Normal stiffness per unit area k̄n (Pa/m).
    pub kn: f64,
    /// Shear stiffness per unit area k̄s (Pa/m).
    pub ks: f64,
    /// Radius multiplier λ̄: R̄ = λ̄·min(R1, R2) (default 1).
    #[serde(default = "one")]
    pub lambda: f64,
    /// Number of elements N along the interface, 1..=8 (default 2: the fewest that let an
    /// interface be partly broken).
    #[serde(default = "two")]
    pub elements: u8,
    /// Friction coefficient μ of unbonded elements (default 0).
    #[serde(default)]
    pub friction: f64,
    /// Fraction φ_B of the elements bonded at installation, in [0, 1] (default 1). The others
    /// start unbonded (PFC's slit elements): in contact they carry compression and friction
    /// only. Which elements: a hash of the bond id and the element index (deterministic).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub bonded_fraction: f64,
}

fn is_one(v: &f64) -> bool {
    *v == 1.0
}

fn one() -> f64 {
    1.0
}

fn two() -> u8 {
    2
}

impl FlatJointParams {
    pub fn validate(&self, group: &str) -> Result<(), BondError> {
        let bad = |field: &str, value: f64| BondError::Parameter {
            group: group.to_string(),
            field: field.to_string(),
            value,
        };
        for (f, v) in [("kn", self.kn), ("ks", self.ks), ("lambda", self.lambda)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(bad(f, v));
            }
        }
        if !(self.friction >= 0.0 && self.friction.is_finite()) {
            return Err(bad("friction", self.friction));
        }
        if self.elements == 0 || self.elements as usize > MAX_ELEMENTS {
            return Err(bad("elements", self.elements as f64));
        }
        if !(0.0..=1.0).contains(&self.bonded_fraction) {
            return Err(bad("bonded_fraction", self.bonded_fraction));
        }
        Ok(())
    }
}

/// Strength of a bonded element: tensile strength σc (Pa), cohesion c (Pa) and tan φ_b.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementStrength {
    pub tensile: f64,
    pub cohesion: f64,
    pub tan_phi: f64,
}

/// The history of one flat joint.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FlatJointState {
    /// Relative rotation since installation θ = Σ(ω2 − ω1)Δt (rad).
    pub theta: f64,
    /// Gap change since installation δ = g − g0 at the last update (m): with θ it fixes the
    /// normal pressure, so the stored energy can be read without the discs.
    pub delta: f64,
    /// Bit e set: element e is bonded.
    pub bonded: u8,
    /// Shear force of each element along t̂ (N); entries from N on are zero.
    pub fs: [f64; MAX_ELEMENTS],
    /// Energy this interface has given up so far (J): the strain energy an element loses when
    /// it breaks (bonded → unbonded at the same motion) and the slip work of sliding unbonded
    /// elements, so the energy balance closes (`Bonds::released_energy` adds it).
    #[serde(default)]
    pub released: f64,
    /// How the last element broke: 0 none yet, 1 tension, 2 shear (the bond's break mode when
    /// the broken interface finally opens).
    #[serde(default)]
    pub last_break: u8,
    /// The interface's break (its last element's) is in the break log; it stays, in contact,
    /// as a frictional flat contact until it opens.
    #[serde(default)]
    pub logged: bool,
}

impl FlatJointState {
    /// A new interface of `n` elements, all bonded, force-free.
    pub fn new(n: u8) -> FlatJointState {
        let n = (n as usize).min(MAX_ELEMENTS);
        FlatJointState {
            theta: 0.0,
            delta: 0.0,
            bonded: ((1u16 << n) - 1) as u8,
            fs: [0.0; MAX_ELEMENTS],
            released: 0.0,
            last_break: 0,
            logged: false,
        }
    }

    /// The interface of bond `id` at installation: element e bonded when a hash of (`id`, e),
    /// uniform in [0, 1), is below `p.bonded_fraction` (so every element with the default 1).
    /// An interface with no bonded element is a plain frictional contact from the start: it
    /// never enters the break log and leaves the bond stage when it opens.
    pub fn installed(p: &FlatJointParams, id: u32) -> FlatJointState {
        let mut s = FlatJointState::new(p.elements);
        if p.bonded_fraction < 1.0 {
            for e in 0..p.elements.min(MAX_ELEMENTS as u8) {
                if unit_hash(((id as u64) << 8) | e as u64) >= p.bonded_fraction {
                    s.bonded &= !(1u8 << e);
                }
            }
            if s.bonded == 0 {
                s.logged = true;
                s.last_break = LAST_TENSION;
            }
        }
        s
    }

    /// Number of bonded elements.
    pub fn bonded_count(&self) -> u32 {
        self.bonded.count_ones()
    }
}

/// Elements that broke in one update (bit e: element e).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Broke {
    pub tension: u8,
    pub shear: u8,
}

/// Element e's extent [a, b] along t̂ for an interface of half-width `rbar` and `n` elements.
#[inline]
pub fn element_span(rbar: f64, n: usize, e: usize) -> (f64, f64) {
    let w = 2.0 * rbar / n as f64;
    (-rbar + e as f64 * w, -rbar + (e + 1) as f64 * w)
}

/// Normal force F_e and moment M_e (about the contact point, on disc 2) of the pressure
/// p(s) = −kn·(δ − θ s)·t on [a, b], clipped to p ≥ 0 when `unbonded` (closed forms).
fn normal(kn: f64, t: f64, delta: f64, theta: f64, a: f64, b: f64, unbonded: bool) -> (f64, f64) {
    // p(s) = q0 + q1 s per unit length along t̂ (N/m).
    let q0 = -kn * delta * t;
    let q1 = kn * theta * t;
    let Some((lo, hi)) = loaded(q0, q1, a, b, unbonded) else {
        return (0.0, 0.0);
    };
    let (d1, d2, d3) = (
        hi - lo,
        (hi * hi - lo * lo) / 2.0,
        (hi * hi * hi - lo * lo * lo) / 3.0,
    );
    (q0 * d1 + q1 * d2, -(q0 * d2 + q1 * d3))
}

/// The relative motion of a flat joint's two discs in one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Gap change since installation δ = g − g0 (m, opening positive).
    pub delta: f64,
    /// Shear displacement increment Δδs along t̂ at the contact point (m).
    pub dus: f64,
    /// Relative rotation increment Δθ = (ω2 − ω1)Δt (rad).
    pub dtheta: f64,
}

/// One step of a flat joint of half-width `rbar` and thickness `t`: update `state` with the
/// step's [`Motion`] and break the bonded elements that fail. Returns the forces
/// `[ΣF_e, ΣF_s,e, ΣM_e]` on disc 2 (normal positive in compression) and the elements that broke.
pub fn update(
    p: &FlatJointParams,
    strength: &ElementStrength,
    rbar: f64,
    t: f64,
    motion: Motion,
    state: &mut FlatJointState,
) -> ([f64; 3], Broke) {
    let Motion { delta, dus, dtheta } = motion;
    let n = p.elements as usize;
    state.theta += dtheta;
    state.delta = delta;
    let theta = state.theta;
    if let Some(f) = intact(p, strength, rbar, t, n, dus, state) {
        return (f, Broke::default());
    }
    let area = 2.0 * rbar * t / n as f64;
    let mut out = [0.0; 3];
    let mut broke = Broke::default();
    for e in 0..n {
        let bit = 1u8 << e;
        let (a, b) = element_span(rbar, n, e);
        let trial = state.fs[e] - p.ks * area * dus;
        let mut fs = trial;
        let was_bonded = state.bonded & bit != 0;
        let mut bonded = was_bonded;
        let (mut fe, mut me) = normal(p.kn, t, delta, theta, a, b, !bonded);
        if bonded {
            // Largest tensile stress on the element: at one of its edges (δ(s) is linear).
            let sigma_max = p.kn * (delta - theta * a).max(delta - theta * b);
            let sigma_mean = -fe / area;
            if sigma_max >= strength.tensile {
                broke.tension |= bit;
                bonded = false;
            } else if fs.abs() >= area * (strength.cohesion - sigma_mean * strength.tan_phi) {
                broke.shear |= bit;
                bonded = false;
            }
            if !bonded {
                state.bonded &= !bit;
                (fe, me) = normal(p.kn, t, delta, theta, a, b, true);
            }
        }
        if !bonded {
            let limit = p.friction * fe;
            if fs.abs() > limit {
                fs = limit.copysign(fs);
            }
            // What the element gives up. Breaking now: its bonded energy (normal, and shear at
            // the trial force) less the unbonded one. Sliding on: the slip work of the contact
            // law (linear_spring_dashpot): the mean of the old and new spring force times the
            // slip, (F_old + F)(F_trial − F)/(2k̄s w t), what the stored energy does not hold.
            let k = p.ks * area;
            state.released += if was_bonded {
                normal_energy(p.kn, t, delta, theta, a, b, false)
                    - normal_energy(p.kn, t, delta, theta, a, b, true)
                    + (trial * trial - fs * fs) / (2.0 * k)
            } else {
                (state.fs[e] + fs) * (trial - fs) / (2.0 * k)
            };
        }
        state.fs[e] = fs;
        out[0] += fe;
        out[1] += fs;
        out[2] += me;
    }
    (out, broke)
}

/// The step of an interface whose elements are all bonded and stay so: the totals in closed
/// form (the parallel bond's −k̄nĀδ and −k̄nĪθ; every element carries the same shear force), or
/// `None` when an element is unbonded or one may break now (then [`update`] takes the
/// elements one by one). The elements that could break first are the extreme ones: the largest
/// edge tensile stress is k̄n(δ + |θ|R̄), and the least compressed element's mean normal stress
/// k̄n(δ + |θ|(R̄ − w/2)) sets the lowest shear strength.
#[inline]
fn intact(
    p: &FlatJointParams,
    strength: &ElementStrength,
    rbar: f64,
    t: f64,
    n: usize,
    dus: f64,
    state: &mut FlatJointState,
) -> Option<[f64; 3]> {
    let full = ((1u16 << n) - 1) as u8;
    if state.bonded != full {
        return None;
    }
    let (delta, theta) = (state.delta, state.theta);
    let area = 2.0 * rbar * t / n as f64;
    let w = 2.0 * rbar / n as f64;
    let fs = state.fs[0] - p.ks * area * dus;
    let sigma_edge = p.kn * (delta + theta.abs() * rbar);
    let sigma_weakest = p.kn * (delta + theta.abs() * (rbar - 0.5 * w));
    let tension = sigma_edge >= strength.tensile;
    let shear = fs.abs() >= area * (strength.cohesion - sigma_weakest * strength.tan_phi);
    if tension || shear {
        return None;
    }
    state.fs[..n].fill(fs);
    let (a, i) = (potyondy2004::area(rbar, t), potyondy2004::inertia(rbar, t));
    Some([-p.kn * a * delta, fs * n as f64, -p.kn * i * theta])
}

/// The part of the element [a, b] on which a pressure c0 + c1·s acts: all of it when bonded;
/// when unbonded, the part where it is compressive (on one side of its root −c0/c1); `None`
/// when nothing is loaded.
fn loaded(c0: f64, c1: f64, a: f64, b: f64, unbonded: bool) -> Option<(f64, f64)> {
    if !unbonded {
        return Some((a, b));
    }
    if c1 == 0.0 {
        return (c0 > 0.0).then_some((a, b));
    }
    let root = -c0 / c1;
    let (lo, hi) = if c1 > 0.0 {
        (a.max(root), b)
    } else {
        (a, b.min(root))
    };
    (lo < hi).then_some((lo, hi))
}

/// Strain energy t∫p²/(2k̄n) ds of the normal pressure on [a, b] (clipped to p ≥ 0 when
/// `unbonded`), p per unit area −k̄n(δ − θ s) (closed form).
fn normal_energy(kn: f64, t: f64, delta: f64, theta: f64, a: f64, b: f64, unbonded: bool) -> f64 {
    let (s0, s1) = (-kn * delta, kn * theta);
    let Some((lo, hi)) = loaded(s0, s1, a, b, unbonded) else {
        return 0.0;
    };
    // ∫ (s0 + s1 s)² ds = [(s0 + s1 s)³ / (3 s1)], or s0² (hi − lo) when s1 = 0.
    let int = if s1 == 0.0 {
        s0 * s0 * (hi - lo)
    } else {
        ((s0 + s1 * hi).powi(3) - (s0 + s1 * lo).powi(3)) / (3.0 * s1)
    };
    t * int / (2.0 * kn)
}

/// Strain energy of the interface (J): t∫p²/(2k̄n) ds over the loaded parts of the elements
/// plus ΣF_s,e²/(2k̄s w t), at the state's last δ and θ.
pub fn energy(p: &FlatJointParams, rbar: f64, t: f64, state: &FlatJointState) -> f64 {
    let n = p.elements as usize;
    let area = 2.0 * rbar * t / n as f64;
    (0..n)
        .map(|e| {
            let (a, b) = element_span(rbar, n, e);
            let unbonded = state.bonded & (1 << e) == 0;
            normal_energy(p.kn, t, state.delta, state.theta, a, b, unbonded)
                + state.fs[e] * state.fs[e] / (2.0 * p.ks * area)
        })
        .sum()
}

/// One step of a flat-joint *bond* of the bond stage: [`update`] with the group's stress
/// criterion as the elements' strength (σc, c, tan φ_b). Returns the forces and the bond's
/// break flags `(tension, shear)` (the mode of the last element break), set twice at most:
/// when the last bonded element breaks (the store logs the crack then) and, if the interface
/// was still in contact then, again when it opens (ΣF_e = 0: unbonded elements carry no
/// tension), when the store removes it. As in Potyondy (2012), a fully broken interface in
/// contact stays a frictional flat contact meanwhile: compression, Coulomb friction and the
/// moment of its compressed part (it resists rolling).
#[inline]
pub(crate) fn bond_step(
    p: &FlatJointParams,
    strength: &ElementStrength,
    rbar: f64,
    t: f64,
    motion: Motion,
    state: &mut FlatJointState,
) -> ([f64; 3], (bool, bool)) {
    let (f, broke) = update(p, strength, rbar, t, motion, state);
    if broke.tension != 0 {
        state.last_break = LAST_TENSION;
    } else if broke.shear != 0 {
        state.last_break = LAST_SHEAR;
    }
    let cement_gone = state.bonded == 0 && state.last_break != 0;
    let signal = cement_gone && (!state.logged || f[0] == 0.0);
    (
        f,
        (
            signal && state.last_break == LAST_TENSION,
            signal && state.last_break == LAST_SHEAR,
        ),
    )
}

/// A number in [0, 1) from `x` (splitmix64's finaliser; the top 53 bits).
fn unit_hash(x: u64) -> f64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// [`FlatJointState::last_break`]: no element broke yet, the last broke in tension, in shear.
const LAST_TENSION: u8 = 1;
const LAST_SHEAR: u8 = 2;

/// Stiffness of an intact flat joint seen by one of its discs, for the time-step estimate: the
/// parallel bond's (same Ā and Ī, see the module doc).
#[inline]
pub fn stiffness(p: &FlatJointParams, rbar: f64, t: f64, arm: f64) -> (f64, f64) {
    let (a, i) = (potyondy2004::area(rbar, t), potyondy2004::inertia(rbar, t));
    (p.kn.max(p.ks) * a, p.kn * i + p.ks * a * arm * arm)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const T: f64 = 0.5;
    const R: f64 = 1e-3;

    fn params(n: u8) -> FlatJointParams {
        FlatJointParams {
            kn: 2e13,
            ks: 1e13,
            lambda: 1.0,
            elements: n,
            friction: 0.5,
            bonded_fraction: 1.0,
        }
    }

    fn mv(delta: f64, dus: f64, dtheta: f64) -> Motion {
        Motion { delta, dus, dtheta }
    }

    const STRONG: ElementStrength = ElementStrength {
        tensile: f64::INFINITY,
        cohesion: f64::INFINITY,
        tan_phi: 0.0,
    };

    /// An intact interface is a parallel bond: k̄nĀ, k̄sĀ and k̄nĪ for every N.
    #[test]
    fn intact_stiffness_equals_the_parallel_bond_for_any_element_count() {
        for n in 1..=MAX_ELEMENTS as u8 {
            let p = params(n);
            let a = 2.0 * R * T;
            let i = 2.0 / 3.0 * R * R * R * T;
            for delta in [-1e-7, 3e-8] {
                let mut s = FlatJointState::new(n);
                let (f, broke) = update(&p, &STRONG, R, T, mv(delta, 0.0, 0.0), &mut s);
                assert_relative_eq!(f[0], -p.kn * a * delta, max_relative = 1e-12);
                assert_eq!((f[1], broke), (0.0, Broke::default()));
                // The elements' moments cancel (to rounding: they are summed one by one).
                assert!(f[2].abs() <= 1e-14 * f[0].abs() * R, "n = {n}: M {}", f[2]);
            }
            let mut s = FlatJointState::new(n);
            let (f, _) = update(&p, &STRONG, R, T, mv(0.0, 2e-8, 0.0), &mut s);
            assert_relative_eq!(f[1], -p.ks * a * 2e-8, max_relative = 1e-12);
            let mut s = FlatJointState::new(n);
            let (f, _) = update(&p, &STRONG, R, T, mv(0.0, 0.0, 1e-5), &mut s);
            assert!(
                f[0].abs() < 1e-9 * p.kn * i * 1e-5 / R,
                "n = {n}: Fn {}",
                f[0]
            );
            assert_relative_eq!(f[2], -p.kn * i * 1e-5, max_relative = 1e-12);
        }
    }

    /// A fully unbonded interface under pure rotation: only the closing half presses, so it
    /// carries half the intact moment, −k̄n t θ R̄³/3, and the normal force k̄n t θ R̄²/2.
    #[test]
    fn unbonded_interface_under_rotation_carries_half_the_moment() {
        for n in [1u8, 2, 3, 8] {
            let p = params(n);
            let mut s = FlatJointState::new(n);
            s.bonded = 0;
            let th = 2e-5;
            let (f, _) = update(&p, &STRONG, R, T, mv(0.0, 0.0, th), &mut s);
            assert_relative_eq!(f[2], -p.kn * T * th * R.powi(3) / 3.0, max_relative = 1e-12);
            assert_relative_eq!(f[0], p.kn * T * th * R * R / 2.0, max_relative = 1e-12);
            // Opened (δ > θR̄): nothing touches.
            let mut s2 = FlatJointState::new(n);
            s2.bonded = 0;
            let (f, _) = update(&p, &STRONG, R, T, mv(th * R * 1.01, 0.0, th), &mut s2);
            assert_eq!(f, [0.0; 3]);
        }
    }

    /// Rotation that puts the edge s = −R̄ in tension beyond σc breaks the first element only,
    /// in tension; the moment then comes from the bonded elements alone (element 0 is open
    /// since θ s < 0 there): M = −k̄n t θ (R̄³ − (w − R̄)³)/3.
    #[test]
    fn one_element_breaks_in_tension_and_the_rest_carries_the_moment() {
        let n = 4u8;
        let p = params(n);
        let w = 2.0 * R / n as f64;
        let sigma_c = 1e8;
        let strength = ElementStrength {
            tensile: sigma_c,
            cohesion: f64::INFINITY,
            tan_phi: 0.0,
        };
        // Edge stress at s = −R̄ is k̄n θ R̄; at the next element's outer edge k̄n θ (R̄ − w).
        let th = sigma_c / (p.kn * R) * 1.01;
        assert!(p.kn * th * (R - w) < sigma_c);
        let mut s = FlatJointState::new(n);
        let (f, broke) = update(&p, &strength, R, T, mv(0.0, 0.0, th), &mut s);
        assert_eq!(
            broke,
            Broke {
                tension: 1,
                shear: 0
            }
        );
        assert_eq!(s.bonded, 0b1110);
        let m = -p.kn * T * th * (R.powi(3) - (w - R).powi(3)) / 3.0;
        assert_relative_eq!(f[2], m, max_relative = 1e-12);
        // Just below the strength nothing breaks.
        let mut s = FlatJointState::new(n);
        let (_, broke) = update(&p, &strength, R, T, mv(0.0, 0.0, th / 1.02), &mut s);
        assert_eq!(broke, Broke::default());
        assert_eq!(s.bonded, 0b1111);
    }

    /// Shear under a tilted normal stress: the least-compressed element reaches c − σ tan φ_b
    /// first and breaks in shear; its shear force drops to μ F_e, the other keeps k̄s w t Δδs.
    #[test]
    fn the_least_compressed_element_breaks_in_shear_first() {
        let n = 2u8;
        let p = params(n);
        let area = R * T; // w t with w = R̄
        let (c, tan_phi) = (5e7, 0.6);
        let strength = ElementStrength {
            tensile: f64::INFINITY,
            cohesion: c,
            tan_phi,
        };
        // Compression δ < 0 with a tilt: element 1 (s > 0) more compressed than element 0.
        let (delta, th) = (-2e-6, 1e-3);
        let mut probe = FlatJointState::new(n);
        let (f0, _) = update(&p, &STRONG, R, T, mv(delta, 0.0, th), &mut probe);
        let (fe0, _) = normal(p.kn, T, delta, th, -R, 0.0, false);
        let (fe1, _) = normal(p.kn, T, delta, th, 0.0, R, false);
        assert_relative_eq!(f0[0], fe0 + fe1, max_relative = 1e-12);
        assert!(0.0 < fe0 && fe0 < fe1);
        // Shear strengths c + σ_n tan φ_b (σ_n compressive = F_e/A).
        let (tau0, tau1) = (c + fe0 / area * tan_phi, c + fe1 / area * tan_phi);
        let dus = -(tau0 + tau1) / 2.0 / p.ks; // F_s,e = −ks A dus = A (τ0 + τ1)/2
        let mut s = FlatJointState::new(n);
        let (f, broke) = update(&p, &strength, R, T, mv(delta, dus, th), &mut s);
        assert_eq!(
            broke,
            Broke {
                tension: 0,
                shear: 1
            }
        );
        assert_relative_eq!(s.fs[0], p.friction * fe0, max_relative = 1e-12);
        assert_relative_eq!(s.fs[1], -p.ks * area * dus, max_relative = 1e-12);
        assert_relative_eq!(f[1], s.fs[0] + s.fs[1], max_relative = 1e-12);
    }

    /// After full breakage a compressed interface slides at |ΣF_s| = μ ΣF_n.
    #[test]
    fn a_fully_broken_interface_slides_with_coulomb_friction() {
        let n = 3u8;
        let p = params(n);
        let weak = ElementStrength {
            tensile: 1.0,
            cohesion: 1.0,
            tan_phi: 0.0,
        };
        let mut s = FlatJointState::new(n);
        let delta = -1e-6;
        // First step: a little shear breaks every element in shear (compressed, so not tension).
        let (_, broke) = update(&p, &weak, R, T, mv(delta, 1e-9, 0.0), &mut s);
        assert_eq!(
            broke,
            Broke {
                tension: 0,
                shear: 0b111
            }
        );
        assert_eq!(s.bonded, 0);
        let mut f = [0.0; 3];
        for _ in 0..50 {
            (f, _) = update(&p, &weak, R, T, mv(delta, 1e-7, 0.0), &mut s);
        }
        assert_relative_eq!(f[0], p.kn * 2.0 * R * T * 1e-6, max_relative = 1e-12);
        assert_relative_eq!(f[1], -p.friction * f[0], max_relative = 1e-12);
        // Reversing the slip unloads elastically first.
        let (g, _) = update(&p, &weak, R, T, mv(delta, -1e-9, 0.0), &mut s);
        assert_relative_eq!(g[1], f[1] + p.ks * 2.0 * R * T * 1e-9, max_relative = 1e-12);
    }

    /// Energy balance on an intact and on an unbonded interface: the work done along a
    /// loading path (trapezoid rule, exact for forces linear in the path) equals the strain
    /// energy stored. Work done on the joint, with the forces on disc 2 as in the module doc:
    /// dW = −F_n dδ − F_s dδs − M dθ.
    #[test]
    fn work_along_a_path_equals_the_stored_energy() {
        for bonded in [true, false] {
            let n = 4u8;
            let p = params(n);
            let mut s = FlatJointState::new(n);
            if !bonded {
                s.bonded = 0;
            }
            let steps = 200;
            // Closing and turning at once keeps every unbonded element's loaded part linear in
            // the path only if the compressed region does not move: use δ and θ in proportion
            // with δ < −θR̄ (the whole interface compressed).
            let (d_end, th_end, us_end) = (-2e-6, 1e-3, 3e-7);
            let (mut delta, mut w) = (0.0, 0.0);
            let mut f_old = [0.0; 3];
            for k in 1..=steps {
                let x = k as f64 / steps as f64;
                let d_new = d_end * x;
                let (f, _) = update(
                    &p,
                    &STRONG,
                    R,
                    T,
                    mv(d_new, us_end / steps as f64, th_end / steps as f64),
                    &mut s,
                );
                w += -(f[0] + f_old[0]) / 2.0 * (d_new - delta)
                    - (f[1] + f_old[1]) / 2.0 * (us_end / steps as f64)
                    - (f[2] + f_old[2]) / 2.0 * (th_end / steps as f64);
                delta = d_new;
                f_old = f;
            }
            assert!(d_end < -th_end * R);
            let u = energy(&p, R, T, &s);
            // Unbonded shear stays below the friction limit on this path (checked: the path is
            // elastic and the balance exact).
            for e in 0..n as usize {
                let (a, b) = element_span(R, n as usize, e);
                let (fe, _) = normal(p.kn, T, delta, s.theta, a, b, !bonded);
                assert!(s.fs[e].abs() < p.friction * fe, "element {e}");
            }
            assert_relative_eq!(w, u, max_relative = 1e-9);
        }
    }

    /// Breaking and sliding: at every update, the work done on the interface in that update
    /// (trapezoid) equals the change of stored energy plus what it released, to the
    /// trapezoid's error on the loading path (checked at 1e-6 of the energy moved).
    #[test]
    fn stored_plus_released_energy_follows_the_work_through_breaks_and_sliding() {
        let n = 4u8;
        let p = params(n);
        let strength = ElementStrength {
            tensile: 2e6,
            cohesion: 3e6,
            tan_phi: 0.5,
        };
        let mut s = FlatJointState::new(n);
        let mut f_old = [0.0; 3];
        let (mut delta, mut work) = (0.0, 0.0);
        let steps = 20000;
        let mut broke_any = Broke::default();
        for k in 1..=steps {
            let x = k as f64 / steps as f64;
            // Close, then bend and shear, then open: every element breaks, some slide.
            let d_new = -1e-7 * (std::f64::consts::PI * x).sin() + 2e-7 * x * x;
            let (dus, dth) = (2e-7 / steps as f64, 5e-4 * (6.0 * x).cos() / steps as f64);
            let (f, b) = update(&p, &strength, R, T, mv(d_new, dus, dth), &mut s);
            broke_any.tension |= b.tension;
            broke_any.shear |= b.shear;
            work += -(f[0] + f_old[0]) / 2.0 * (d_new - delta)
                - (f[1] + f_old[1]) / 2.0 * dus
                - (f[2] + f_old[2]) / 2.0 * dth;
            delta = d_new;
            f_old = f;
        }
        assert_eq!(s.bonded, 0, "every element broke");
        assert!(broke_any.tension != 0);
        let u = energy(&p, R, T, &s);
        assert!(s.released > 0.0);
        let scale = work.abs().max(s.released);
        assert!(
            (work - (u + s.released)).abs() <= 2e-3 * scale,
            "work {work} vs stored {u} + released {}",
            s.released
        );
    }

    /// Slit elements: the fraction bonded at installation follows φ_B (binomial spread over
    /// 4,000 elements: ±3 % is > 3.8 standard deviations), is the same for the same bond id,
    /// and an interface with none bonded starts as a logged, unbonded contact.
    #[test]
    fn the_bonded_fraction_sets_the_slit_elements() {
        let mut p = params(4);
        let all = FlatJointState::installed(&p, 7);
        assert_eq!(all.bonded, 0b1111);
        assert!(!all.logged);
        for phi in [0.3, 0.5, 0.9] {
            p.bonded_fraction = phi;
            let n: u32 = (0..1000)
                .map(|id| FlatJointState::installed(&p, id).bonded_count())
                .sum();
            let f = n as f64 / 4000.0;
            assert!((f - phi).abs() < 0.03, "φ_B {phi}: {f}");
            assert_eq!(
                FlatJointState::installed(&p, 42),
                FlatJointState::installed(&p, 42)
            );
        }
        p.bonded_fraction = 0.0;
        let none = FlatJointState::installed(&p, 3);
        assert_eq!(none.bonded, 0);
        assert!(none.logged);
        // It presses and rubs like an unbonded interface, and never breaks.
        let mut s = none;
        let strength = ElementStrength {
            tensile: 1.0,
            cohesion: 1.0,
            tan_phi: 0.0,
        };
        let (f, b) = bond_step(&p, &strength, R, T, mv(-1e-7, 1e-9, 0.0), &mut s);
        assert!(f[0] > 0.0);
        assert_eq!(b, (false, false));
        let (f, b) = bond_step(&p, &strength, R, T, mv(1e-7, 0.0, 0.0), &mut s);
        assert_eq!(f[0], 0.0);
        assert_eq!(b, (true, false), "leaves when open");
    }

    #[test]
    fn bad_parameters_name_the_field() {
        let mut p = params(2);
        p.elements = 9;
        assert_eq!(
            p.validate("g"),
            Err(BondError::Parameter {
                group: "g".into(),
                field: "elements".into(),
                value: 9.0
            })
        );
        p.elements = 2;
        p.friction = -0.1;
        assert!(
            matches!(p.validate("g"), Err(BondError::Parameter { field, .. }) if field == "friction")
        );
        p.friction = 0.5;
        p.ks = f64::NAN;
        assert!(
            matches!(p.validate("g"), Err(BondError::Parameter { field, .. }) if field == "ks")
        );
    }
}
