//! Contact laws per material pair and the disc–disc / disc–wall force passes.
//!
//! Kinematics shared by every law (2D, normal n from disc i to disc j, tangent t = (−n_y, n_x)):
//! overlap δ = g₀ − gap with gap = |x_j − x_i| − r_i − r_j and g₀ ≤ 0 the registered reference
//! gap ([`crate::World::set_contact_offset`], 0 by default). The contact point lies on the
//! line of centres midway in the geometric overlap h₂ = r_i + r_j − d (d = |x_j − x_i|), at
//! a_i = r_i − h₂/2 from centre i and a_j = r_j − h₂/2 from centre j, so a_i + a_j = d (the
//! contact location of PFC's ball–ball contact, Potyondy & Cundall 2004, Int. J. Rock Mech.
//! Min. Sci. 41:1329, §2.1: "the contact point lies in the middle of the overlap region").
//! The geometric (not the offset) overlap is used: members of bonded clumps overlap deeply
//! and the arms must add up to d for the tangential force to conserve angular momentum
//! (d F_t − (a_i + a_j) F_t = 0). Relative velocity of j's contact point with respect to
//! i's: v = v_j − v_i − (ω_i a_i + ω_j a_j) t, split into v_n = v·n (positive when
//! separating) and v_t = v·t. A law returns the normal force F_n (positive = repulsive) and
//! tangential force F_t on disc j; disc i receives the opposite force, disc i the torque
//! −a_i F_t and disc j −a_j F_t (plus the rolling moment, + on i, − on j), consistent with
//! the velocity above so that the pair's power is F · v.
//!
//! The tangential history u_s is a scalar along t: in 2D the tangent plane is a line, so
//! carrying the scalar is the exact rotation of the shear vector with the contact normal
//! (Cundall & Strack 1979). It lives in the neighbour list (one slot per listed pair) and is
//! carried over at rebuilds and reorderings, keyed by the pair.

pub(crate) mod disc_disc;
pub(crate) mod disc_segment;
pub mod granular;
pub(crate) mod kernel;
pub(crate) mod linear4;
pub(crate) mod owned;

// The laws themselves are written once, for discs and spheres, in `dem-laws`; the 2D solver
// instantiates them with a scalar tangential history (`T = f64`).
pub use dem_laws::{
    eta_for_restitution, restitution_of_eta, HertzMindlin, LinearSpringDashpot, NormalDamping,
    RollingResistance,
};

use serde::{Deserialize, Serialize};

/// Kinematics of one touching disc pair, input to a law ([`dem_laws::Kin`] in 2D).
pub type PairKin = dem_laws::Kin<f64>;

/// Output of a law for one disc pair ([`dem_laws::Out`] in 2D; energies only when tracked).
pub type PairOut = dem_laws::Out<f64>;

/// The contact law of one material pair.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum ContactModel {
    Linear(LinearSpringDashpot),
    HertzMindlin(HertzMindlin),
    /// A catalogue law composed of named sub-models (`dem_laws::GranularLaw`, checked for
    /// 2D by [`granular::check_2d`]).
    Granular(dem_laws::GranularLaw),
}

impl ContactModel {
    #[inline(always)]
    pub fn force<const E: bool>(&self, k: &PairKin, us: &mut f64) -> PairOut {
        match self {
            ContactModel::Linear(l) => l.force::<E, f64>(k, us),
            ContactModel::HertzMindlin(h) => h.force::<E, f64>(k, us),
            ContactModel::Granular(g) => granular::force::<E>(g, k, us),
        }
    }

    /// Normal stiffness used by rolling resistance and the time step: k_n (linear) or the
    /// Hertz tangent stiffness at overlap `delta`.
    #[inline(always)]
    pub fn kn(&self, r_eff: f64, delta: f64) -> f64 {
        match self {
            ContactModel::Linear(l) => l.kn,
            ContactModel::HertzMindlin(h) => h.kn_tangent(r_eff, delta),
            ContactModel::Granular(g) => granular::kn(g, r_eff, delta),
        }
    }

    /// Tangential stiffness at overlap `delta`.
    #[inline(always)]
    pub fn ks(&self, r_eff: f64, delta: f64) -> f64 {
        match self {
            ContactModel::Linear(l) => l.ks,
            ContactModel::HertzMindlin(h) => h.kt(r_eff, delta),
            ContactModel::Granular(g) => granular::ks(g, r_eff, delta),
        }
    }

    /// Elastic energy held by the tangential spring with history `us` at overlap `delta`
    /// (½ k_s u_s², with the Hertz–Mindlin k_t(δ) for that law): the energy that is released
    /// when the contact opens and the history is reset (see `contact::kernel`).
    #[inline(always)]
    pub fn shear_energy(&self, r_eff: f64, delta: f64, us: f64) -> f64 {
        0.5 * self.ks(r_eff, delta.max(0.0)) * us * us
    }

    /// Elastic normal and tangential forces for views (no dashpot).
    pub fn spring_forces(&self, r_eff: f64, delta: f64, us: f64) -> (f64, f64) {
        match self {
            ContactModel::Linear(l) => (l.spring_normal(delta), -l.ks * us),
            ContactModel::HertzMindlin(h) => {
                (h.spring_normal(r_eff, delta), -h.kt(r_eff, delta) * us)
            }
            ContactModel::Granular(g) => (
                granular::spring_normal(g, r_eff, delta).0,
                -granular::ks(g, r_eff, delta.max(0.0)) * us,
            ),
        }
    }
}

/// Contact laws for every material pair (symmetric table) and optional rolling resistance.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ContactLaws {
    n: usize,
    models: Vec<ContactModel>,
    rolling: Vec<Option<RollingResistance>>,
}

impl ContactLaws {
    /// `n_materials` materials, every pair using `model`, no rolling resistance.
    pub fn new(n_materials: usize, model: ContactModel) -> ContactLaws {
        let n = n_materials.max(1);
        ContactLaws {
            n,
            models: vec![model; n * n],
            rolling: vec![None; n * n],
        }
    }

    /// One material, one law.
    pub fn uniform(model: ContactModel) -> ContactLaws {
        ContactLaws::new(1, model)
    }

    pub fn n_materials(&self) -> usize {
        self.n
    }

    /// Set the law of material pair (a, b) (and (b, a)). Out-of-range materials are ignored
    /// and reported as `false`.
    pub fn set(&mut self, a: u16, b: u16, model: ContactModel) -> bool {
        let (a, b) = (a as usize, b as usize);
        if a >= self.n || b >= self.n {
            return false;
        }
        self.models[a * self.n + b] = model;
        self.models[b * self.n + a] = model;
        true
    }

    /// Set the rolling resistance of material pair (a, b).
    pub fn set_rolling(&mut self, a: u16, b: u16, r: Option<RollingResistance>) -> bool {
        let (a, b) = (a as usize, b as usize);
        if a >= self.n || b >= self.n {
            return false;
        }
        self.rolling[a * self.n + b] = r;
        self.rolling[b * self.n + a] = r;
        true
    }

    /// Checks a table read back from a checkpoint (deserialisation takes any sizes): at least
    /// one material, n² laws and n² rolling entries, finite parameters. Found by fuzzing the
    /// checkpoint reader (issue 20): `n` larger than the table indexed past its end.
    pub fn check_table(&self) -> Result<(), crate::WorldError> {
        let n = self.n;
        if n == 0 || self.models.len() != n * n || self.rolling.len() != n * n {
            return Err(crate::WorldError::Restored(format!(
                "contact laws: {} laws and {} rolling entries for {n} materials (need {n}²)",
                self.models.len(),
                self.rolling.len()
            )));
        }
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        for m in &self.models {
            let ok = match m {
                ContactModel::Linear(l) => {
                    let d = match l.damping {
                        NormalDamping::Ratio(z) => z,
                        NormalDamping::Gamma(g) => g,
                    };
                    finite(&[l.kn, l.ks, l.shear_damping, l.mu, d])
                }
                ContactModel::HertzMindlin(h) => {
                    finite(&[h.e_star, h.g_star, h.eta, h.restitution, h.mu])
                }
                ContactModel::Granular(g) => {
                    granular::is_finite(g) && granular::check_2d(g).is_ok()
                }
            };
            if !ok {
                return Err(crate::WorldError::Restored(
                    "contact laws: a law has a non-finite parameter".into(),
                ));
            }
        }
        if !self
            .rolling
            .iter()
            .flatten()
            .all(|r| finite(&[r.mu_r, r.stiffness_factor]))
        {
            return Err(crate::WorldError::Restored(
                "contact laws: a rolling resistance is not finite".into(),
            ));
        }
        Ok(())
    }

    /// Index of material pair (a, b); materials beyond the table use the last row.
    #[inline(always)]
    pub fn index(&self, a: u16, b: u16) -> usize {
        let a = (a as usize).min(self.n - 1);
        let b = (b as usize).min(self.n - 1);
        a * self.n + b
    }

    #[inline(always)]
    pub fn model(&self, a: u16, b: u16) -> &ContactModel {
        &self.models[self.index(a, b)]
    }

    #[inline(always)]
    pub fn rolling(&self, a: u16, b: u16) -> Option<&RollingResistance> {
        self.rolling[self.index(a, b)].as_ref()
    }

    /// Whether some pair's law may have a nonzero dashpot force. `false` only when every law
    /// is linear with a zero dashpot coefficient (`Ratio(0)` or `Gamma(0)`), a finite k_n ≥ 0
    /// and a finite shear-damping factor, so that c_n = 0 and c_t = 0 · c_n = 0 exactly and
    /// every dashpot force is ±0 (see `disc_disc::Dashpot`).
    pub fn has_dashpots(&self) -> bool {
        !self.models.iter().all(|m| match m {
            ContactModel::Linear(l) => {
                let zero = match l.damping {
                    NormalDamping::Ratio(z) => z == 0.0,
                    NormalDamping::Gamma(g) => g == 0.0,
                };
                zero && l.kn >= 0.0 && l.kn.is_finite() && l.shear_damping.is_finite()
            }
            ContactModel::HertzMindlin(_) => false,
            ContactModel::Granular(g) => !granular::has_dashpot(g),
        })
    }

    /// Whether any pair has rolling resistance.
    pub fn any_rolling(&self) -> bool {
        self.rolling.iter().any(|r| r.is_some())
    }

    pub fn models(&self) -> &[ContactModel] {
        &self.models
    }

    /// Whether material indices up to `max_material` are covered by the table.
    pub fn covers(&self, max_material: u16) -> bool {
        (max_material as usize) < self.n
    }
}

/// One listed pair as seen from outside (outputs, bond installation). Forces are the elastic
/// (spring) parts at the current positions; dashpot forces are not stored.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactView {
    /// Current indices of the two discs (change at reordering) and their stable ids.
    pub i: u32,
    pub j: u32,
    pub id_i: u32,
    pub id_j: u32,
    /// Gap |x_j − x_i| − r_i − r_j (m, opening positive) and overlap beyond the reference
    /// gap δ = g₀ − gap (m).
    pub gap: f64,
    pub overlap: f64,
    /// Unit normal from i to j and the contact point (midway in the geometric overlap
    /// r_i + r_j − |x_j − x_i|, see the module notes).
    pub normal: [f64; 2],
    pub point: [f64; 2],
    /// Elastic normal force (N, positive = compression) and tangential spring force on j (N).
    pub f_n: f64,
    pub f_t: f64,
}
