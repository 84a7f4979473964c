//! Bond breakage criteria, selectable per bond group.
//!
//! The four criteria are the ones the sources name: the lattice-element breakage criteria of the
//! crushing patent S3 ("maximum stress, maximum force, maximum strain, or energy release rate";
//! see `shared/SOURCES.md`), with the maximum-stress form being the parallel-bond strength model of
//! Potyondy & Cundall (2004), "A bonded-particle model for rock", Int. J. Rock Mech. Min. Sci.
//! 41:1329-1364 (also used by S4, Tan et al., for SiC). Each criterion decides *whether* a bond
//! breaks and in which *mode*: tension (opening, including bending) or shear.
//!
//! Quantities (bond forces as in [`super::potyondy2004`]; F̄n positive in compression):
//! - σ = −F̄n/Ā, normal stress, positive in tension;
//! - σ̄ = −F̄n/Ā + β̄|M̄|R̄/Ī, the largest tensile stress on the bond cross-section;
//! - τ̄ = |F̄s|/Ā, the mean shear stress;
//! - L = R1 + R2 + g0, the bond length (centre distance at installation).
//!
//! Tension is always checked first (as in PFC's linear parallel bond): a bond that satisfies both
//! conditions in the same step breaks in tension.

use super::BondError;
use serde::{Deserialize, Serialize};

/// How a bond broke.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BreakMode {
    Tension,
    Shear,
}

impl BreakMode {
    pub fn name(self) -> &'static str {
        match self {
            BreakMode::Tension => "tension",
            BreakMode::Shear => "shear",
        }
    }

    /// Index into per-mode counters (`[tension, shear]`).
    pub fn index(self) -> usize {
        match self {
            BreakMode::Tension => 0,
            BreakMode::Shear => 1,
        }
    }
}

/// A breakage criterion (strengths in SI units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Criterion {
    /// Maximum stress (Potyondy & Cundall 2004, parallel-bond strength; PFC linear parallel bond): tension
    /// when σ̄ ≥ σ̄c; shear when τ̄ ≥ τ̄c = c̄ − σ tan φ̄. Parallel bonds only (needs Ā, Ī).
    Stress {
        /// Tensile strength σ̄c (Pa).
        tensile: f64,
        /// Cohesion c̄ (Pa).
        cohesion: f64,
        /// Friction angle φ̄ (rad), in [0, π/2).
        #[serde(default)]
        friction_angle: f64,
    },
    /// Maximum force (S3's "maximum force"; PFC contact-bond strengths): tension when the tensile
    /// normal force −F̄n ≥ `tensile` or the bending moment |M̄| ≥ `moment`; shear when
    /// |F̄s| ≥ `shear`. Forces in N, moment in N·m (a contact bond carries no moment).
    Force {
        tensile: f64,
        shear: f64,
        /// Absent on disk when infinite (JSON has no infinity: it would be written `null`
        /// and a checkpoint holding it could not be read back).
        #[serde(default = "infinity", skip_serializing_if = "is_infinite")]
        moment: f64,
    },
    /// Maximum strain (S3's "maximum strain"): the elastic strains of the bond over its length L,
    /// tension when ε̄ = σ̄/(k̄n·L) ≥ `tensile` (normal opening plus β̄R̄ times the bending
    /// rotation, over L), shear when γ̄ = τ̄/(k̄s·L) ≥ `shear`. For a contact bond
    /// ε = −Fn/(kn·L), γ = |Fs|/(ks·L). Dimensionless.
    Strain { tensile: f64, shear: f64 },
    /// Energy (S3's "energy release rate"): the bond breaks when its opening strain energy
    /// U = U_open + U_shear reaches the fracture energy G_c·A, with
    /// U_open = F̄n²/(2k̄nĀ) (tensile F̄n only) + M̄²/(2k̄nĪ), U_shear = F̄s²/(2k̄sĀ), and A the
    /// bond area (Ā = 2R̄t; for a contact bond 2·min(R1,R2)·t). Compressive normal energy is
    /// left out: a bond is not broken by squeezing (compression is carried by the contact law).
    /// Mode: tension when U_open ≥ U_shear, else shear.
    Energy {
        /// Fracture energy per unit bond area G_c (J/m²).
        fracture_energy: f64,
    },
}

fn infinity() -> f64 {
    f64::INFINITY
}

fn is_infinite(x: &f64) -> bool {
    x.is_infinite() && *x > 0.0
}

/// The loads of one bond, in the form every criterion can use. Built by the bond model.
///
/// The checks are written without divisions (they run for every bond every step): with the
/// bending lever ℓ = Ī/(R̄Ā) (= R̄/3 for the 2D parallel bond), σ̄Ā = −F̄n + β̄|M̄|/ℓ, so
/// σ̄ ≥ σ̄c ⇔ −F̄n·ℓ + β̄|M̄| ≥ σ̄c·Ā·ℓ.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Loads {
    /// F̄n, positive in compression (N).
    pub fn_: f64,
    /// |F̄s| (N).
    pub fs_abs: f64,
    /// |M̄| (N·m); 0 for a contact bond.
    pub m_abs: f64,
    /// Ā (m²).
    pub area: f64,
    /// Bending lever ℓ = Ī/(R̄Ā) (m); any positive value for a bond without moment.
    pub lever: f64,
    /// β̄ (0 for a contact bond).
    pub beta: f64,
    /// Normal and shear stiffness of the bond as springs: k̄nĀ, k̄sĀ (N/m), k̄nĪ (N·m/rad;
    /// 0 for a contact bond).
    pub kn_a: f64,
    pub ks_a: f64,
    pub kn_i: f64,
    /// Bond length L (m).
    pub length: f64,
}

impl Loads {
    /// σ̄Ā·ℓ = −F̄n·ℓ + β̄|M̄|: the largest tensile stress σ̄ = −F̄n/Ā + β̄|M̄|R̄/Ī times Āℓ.
    #[inline(always)]
    fn sigma_area_lever(&self) -> f64 {
        -self.fn_ * self.lever + self.beta * self.m_abs
    }

    /// (U_open, U_shear), see [`Criterion::Energy`].
    #[inline]
    fn energies(&self) -> (f64, f64) {
        let un = if self.fn_ < 0.0 {
            self.fn_ * self.fn_ / (2.0 * self.kn_a)
        } else {
            0.0
        };
        let ub = if self.kn_i > 0.0 {
            self.m_abs * self.m_abs / (2.0 * self.kn_i)
        } else {
            0.0
        };
        (un + ub, self.fs_abs * self.fs_abs / (2.0 * self.ks_a))
    }
}

impl Criterion {
    /// Check a criterion's parameters; `parallel` tells whether the bond model has an area and
    /// moment of inertia (the stress criterion needs them).
    pub fn validate(&self, group: &str, parallel: bool) -> Result<(), BondError> {
        let bad = |field: &str, value: f64| BondError::Parameter {
            group: group.to_string(),
            field: field.to_string(),
            value,
        };
        let pos = |field: &str, v: f64| {
            if v > 0.0 && !v.is_nan() {
                Ok(())
            } else {
                Err(bad(field, v))
            }
        };
        match *self {
            Criterion::Stress {
                tensile,
                cohesion,
                friction_angle,
            } => {
                if !parallel {
                    return Err(BondError::StressOnContactBond(group.to_string()));
                }
                pos("tensile", tensile)?;
                pos("cohesion", cohesion)?;
                if !(0.0..std::f64::consts::FRAC_PI_2).contains(&friction_angle) {
                    return Err(bad("friction_angle", friction_angle));
                }
            }
            Criterion::Force {
                tensile,
                shear,
                moment,
            } => {
                pos("tensile", tensile)?;
                pos("shear", shear)?;
                pos("moment", moment)?;
            }
            Criterion::Strain { tensile, shear } => {
                pos("tensile", tensile)?;
                pos("shear", shear)?;
            }
            Criterion::Energy { fracture_energy } => pos("fracture_energy", fracture_energy)?,
        }
        Ok(())
    }

    /// The criterion with its derived constants (tan φ̄), ready for the hot loop.
    pub(crate) fn compile(&self) -> Compiled {
        let tan_phi = match *self {
            Criterion::Stress { friction_angle, .. } => friction_angle.tan(),
            _ => 0.0,
        };
        Compiled {
            criterion: *self,
            tan_phi,
        }
    }
}

/// The maximum-stress conditions (tension: σ̄ ≥ σ̄c; shear: τ̄ ≥ c̄ − σ tan φ̄), evaluated
/// without branches; tension takes precedence when both hold.
#[inline(always)]
pub(crate) fn stress_flags(l: &Loads, tensile: f64, cohesion: f64, tan_phi: f64) -> (bool, bool) {
    (
        // σ̄ ≥ σ̄c.
        l.sigma_area_lever() >= tensile * l.area * l.lever,
        // τ̄ ≥ c̄ − σ tan φ̄ with σ = −F̄n/Ā, i.e. |F̄s| ≥ c̄Ā + F̄n tan φ̄.
        l.fs_abs >= cohesion * l.area + l.fn_ * tan_phi,
    )
}

/// A [`Criterion`] with tan φ̄ precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Compiled {
    pub criterion: Criterion,
    pub tan_phi: f64,
}

impl Compiled {
    /// (tension condition, shear condition) of a bond with these loads; tension takes
    /// precedence when both hold.
    #[inline]
    pub(crate) fn flags(&self, l: &Loads) -> (bool, bool) {
        match self.criterion {
            Criterion::Stress {
                tensile, cohesion, ..
            } => stress_flags(l, tensile, cohesion, self.tan_phi),
            Criterion::Force {
                tensile,
                shear,
                moment,
            } => (-l.fn_ >= tensile || l.m_abs >= moment, l.fs_abs >= shear),
            // ε̄ = σ̄/(k̄n L) = σ̄Ā/(k̄nĀ·L) ≥ ε̄c; γ̄ = τ̄/(k̄s L) = |F̄s|/(k̄sĀ·L) ≥ γ̄c.
            Criterion::Strain { tensile, shear } => (
                l.sigma_area_lever() >= tensile * l.kn_a * l.length * l.lever,
                l.fs_abs >= shear * l.ks_a * l.length,
            ),
            Criterion::Energy { fracture_energy } => {
                let (uo, us) = l.energies();
                let brk = uo + us >= fracture_energy * l.area;
                (brk && uo >= us, brk && uo < us)
            }
        }
    }

    /// Does a bond with these loads break, and how? Tension is checked first.
    #[cfg(test)]
    pub(crate) fn check(&self, l: &Loads) -> Option<BreakMode> {
        match self.flags(l) {
            (true, _) => Some(BreakMode::Tension),
            (false, true) => Some(BreakMode::Shear),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A force criterion without a moment strength round-trips through JSON: the infinite
    /// moment is left out (not written as `null`, which would not read back).
    #[test]
    fn an_infinite_moment_strength_round_trips_through_json() {
        let c = Criterion::Force {
            tensile: 2e3,
            shear: 1e3,
            moment: f64::INFINITY,
        };
        let text = serde_json::to_string(&c).unwrap();
        assert!(!text.contains("null") && !text.contains("moment"), "{text}");
        assert_eq!(serde_json::from_str::<Criterion>(&text).unwrap(), c);
        let finite = Criterion::Force {
            tensile: 2e3,
            shear: 1e3,
            moment: 5.0,
        };
        let text = serde_json::to_string(&finite).unwrap();
        assert_eq!(serde_json::from_str::<Criterion>(&text).unwrap(), finite);
    }

    fn loads(fn_: f64, fs: f64, m: f64) -> Loads {
        // R̄ = 0.5, t = 2: Ā = 2, Ī = 2/3·0.125·2 = 1/6, ℓ = Ī/(R̄Ā) = 1/6.
        Loads {
            fn_,
            fs_abs: fs.abs(),
            m_abs: m.abs(),
            area: 2.0,
            lever: 1.0 / 6.0,
            beta: 1.0,
            kn_a: 10.0,
            ks_a: 5.0,
            kn_i: 10.0 / 12.0,
            length: 1.0,
        }
    }

    #[test]
    fn stress_tension_bending_and_mohr_coulomb_shear() {
        let c = Criterion::Stress {
            tensile: 3.0,
            cohesion: 4.0,
            friction_angle: 0.5,
        };
        // Pure tension: −F̄n/Ā = 3 at F̄n = −6.
        assert_eq!(c.compile().check(&loads(-5.99, 0.0, 0.0)), None);
        assert_eq!(
            c.compile().check(&loads(-6.0, 0.0, 0.0)),
            Some(BreakMode::Tension)
        );
        // Pure bending: |M̄|R̄/Ī = 3 at |M̄| = 1.
        assert_eq!(c.compile().check(&loads(0.0, 0.0, 0.999)), None);
        assert_eq!(
            c.compile().check(&loads(0.0, 0.0, -1.0)),
            Some(BreakMode::Tension)
        );
        // Shear at zero normal force: τ̄ = 4 at |F̄s| = 8; compression raises the limit by
        // σ tan φ̄: F̄n = 2 → σ = −1 → τ̄c = 4 + tan 0.5.
        assert_eq!(c.compile().check(&loads(0.0, 7.99, 0.0)), None);
        assert_eq!(
            c.compile().check(&loads(0.0, -8.0, 0.0)),
            Some(BreakMode::Shear)
        );
        let lim = 2.0 * (4.0 + 0.5f64.tan());
        assert_eq!(c.compile().check(&loads(2.0, lim * 0.999, 0.0)), None);
        assert_eq!(
            c.compile().check(&loads(2.0, lim * 1.001, 0.0)),
            Some(BreakMode::Shear)
        );
        // Tension wins when both hold.
        assert_eq!(
            c.compile().check(&loads(-7.0, 100.0, 0.0)),
            Some(BreakMode::Tension)
        );
    }

    #[test]
    fn force_strain_energy() {
        let f = Criterion::Force {
            tensile: 1.0,
            shear: 2.0,
            moment: 0.5,
        };
        assert_eq!(f.compile().check(&loads(-0.99, 1.99, 0.49)), None);
        assert_eq!(
            f.compile().check(&loads(-1.0, 0.0, 0.0)),
            Some(BreakMode::Tension)
        );
        assert_eq!(
            f.compile().check(&loads(0.0, 0.0, 0.5)),
            Some(BreakMode::Tension)
        );
        assert_eq!(
            f.compile().check(&loads(5.0, 2.0, 0.0)),
            Some(BreakMode::Shear)
        );
        // Strain: ε = (−F̄n/k̄nĀ)/L; at F̄n = −1, ε = 0.1.
        let s = Criterion::Strain {
            tensile: 0.1,
            shear: 0.2,
        };
        assert_eq!(s.compile().check(&loads(-0.99, 0.0, 0.0)), None);
        assert_eq!(
            s.compile().check(&loads(-1.0, 0.0, 0.0)),
            Some(BreakMode::Tension)
        );
        assert_eq!(
            s.compile().check(&loads(0.0, 1.0, 0.0)),
            Some(BreakMode::Shear)
        );
        // Energy: G_c·Ā = 0.1·2 = 0.2 J; F̄n = −2 stores 4/20 = 0.2 J; compression stores
        // nothing that counts.
        let e = Criterion::Energy {
            fracture_energy: 0.1,
        };
        assert_eq!(e.compile().check(&loads(-1.99, 0.0, 0.0)), None);
        assert_eq!(
            e.compile().check(&loads(-2.0, 0.0, 0.0)),
            Some(BreakMode::Tension)
        );
        assert_eq!(e.compile().check(&loads(100.0, 0.0, 0.0)), None);
        // F̄s² /(2·5) = 0.2 at |F̄s| = √2.
        assert_eq!(
            e.compile().check(&loads(0.0, 2f64.sqrt() * 1.0001, 0.0)),
            Some(BreakMode::Shear)
        );
    }

    #[test]
    fn validation_rejects_bad_values_and_stress_on_contact_bonds() {
        let c = Criterion::Stress {
            tensile: 1.0,
            cohesion: 1.0,
            friction_angle: 0.0,
        };
        assert!(c.validate("g", true).is_ok());
        assert!(matches!(
            c.validate("g", false),
            Err(BondError::StressOnContactBond(_))
        ));
        let bad = Criterion::Force {
            tensile: f64::NAN,
            shear: 1.0,
            moment: f64::INFINITY,
        };
        assert!(matches!(
            bad.validate("g", true),
            Err(BondError::Parameter { .. })
        ));
        let phi = Criterion::Stress {
            tensile: 1.0,
            cohesion: 1.0,
            friction_angle: 2.0,
        };
        assert!(phi.validate("g", true).is_err());
    }
}
