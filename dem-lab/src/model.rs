//! The material model a lab test runs with: density, thickness and the micro-parameters
//! ([`MicroParams`], the same struct the specimen generator uses), turned into the `materials`
//! and `bond_groups` of a scene (`docs/scene-schema.md`). Calibration changes only this; the
//! specimen geometry stays.

use crate::specimen::{MicroParams, SpecimenParams, GRAIN_BOUNDARY, INTRA_GRAIN};
use dem_core::scene::schema::{
    BodiesSpec, BondGroupSpec, BondModelName, ContactSpec, CriterionName, LawName, MaterialSpec,
    PairSpec, SceneFile, SpecimenRef,
};
use serde::{Deserialize, Serialize};

/// Name of the specimen's disc material in lab scenes (the specimen files use it).
pub const DISC_MATERIAL: &str = crate::specimen::DEFAULT_MATERIAL;
/// Name of the material of loading walls (platens, supports, tool, slot).
pub const WALL_MATERIAL: &str = "wall";

/// Everything a lab-test scene needs to know about the material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LabModel {
    /// Density ρ (kg/m³).
    pub density: f64,
    /// Disc thickness t (m).
    pub thickness: f64,
    /// Mean disc radius r̄ (m): parallel-bond stiffness k̄_n = Ē_c/(2r̄) (as the generator,
    /// [`crate::specimen::methods::bond_groups`]).
    pub r_mean: f64,
    pub micro: MicroParams,
    /// Flat joints (Potyondy 2012, [`dem_core::bond::flat_joint`]) instead of parallel bonds in
    /// both bond groups: the same k̄n, k̄s, λ̄ and strengths (an intact flat joint is as stiff
    /// as the parallel bond), the interface split into `elements`. Absent (the default, and in
    /// every file written before it): parallel bonds, as S0 and S4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_joint: Option<FlatJointOption>,
}

/// The flat-joint choice of a [`LabModel`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlatJointOption {
    /// Elements per interface, 1–8.
    pub elements: u8,
    /// Friction coefficient of unbonded elements.
    #[serde(default)]
    pub friction: f64,
    /// Fraction of the elements bonded at installation (the rest slit); 1 when absent.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub bonded_fraction: f64,
}

fn one() -> f64 {
    1.0
}

impl FlatJointOption {
    /// Checks the option against the flat joint's limits (Potyondy 2012 as built here,
    /// [`dem_core::bond::flat_joint::FlatJointParams::validate`]): 1–8 elements, a finite friction
    /// coefficient ≥ 0, a bonded fraction in [0, 1]. The error is the field at fault
    /// (`elements`, `friction` or `bonded_fraction`) and why, so a caller names it as its
    /// user gave it (a command-line flag, or a `flat_joint` record of a model file).
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        let max = dem_core::bond::flat_joint::MAX_ELEMENTS;
        if self.elements == 0 || self.elements as usize > max {
            return Err(("elements", format!("{}: must be 1 to {max}", self.elements)));
        }
        if !(self.friction >= 0.0 && self.friction.is_finite()) {
            return Err((
                "friction",
                format!("{}: must be a finite number >= 0", self.friction),
            ));
        }
        if !(0.0..=1.0).contains(&self.bonded_fraction) {
            return Err((
                "bonded_fraction",
                format!("{}: must lie in [0, 1]", self.bonded_fraction),
            ));
        }
        Ok(())
    }
}

fn is_one(v: &f64) -> bool {
    *v == 1.0
}

impl LabModel {
    /// The model a specimen was generated with.
    pub fn from_params(p: &SpecimenParams) -> LabModel {
        LabModel {
            density: p.density,
            thickness: p.thickness,
            r_mean: 0.5 * (p.r_min + p.r_max),
            micro: p.micro.clone(),
            flat_joint: None,
        }
    }

    /// Linear contact normal stiffness of two discs, k_n = 2 t E_c: Potyondy & Cundall's
    /// (2004, §2.3) 2D relation E_c = k_n/(2t) for one ball's stiffness, applied here to the
    /// contact (no second ball spring in series). Their contact relation k_n = A E/L with
    /// A = 2Rt and L = 2R gives k_n = t E, so the modulus of this contact in that sense is
    /// 2 E_c; what E_c means is set by this line, and the calibrated models (`data/models`)
    /// absorb the factor (see [`crate::specimen::MicroParams::contact_modulus`]).
    pub fn contact_kn(&self) -> f64 {
        2.0 * self.thickness * self.micro.contact_modulus
    }

    /// Parallel-bond normal stiffness per area k̄_n = Ē_c / (2 r̄) (Pa/m).
    pub fn bond_kn(&self) -> f64 {
        self.micro.bond_modulus / (2.0 * self.r_mean)
    }

    /// The scene's `materials`: the disc material (density, linear contact k_n, k_s = k_n/κ,
    /// friction μ, no dashpot: bonded-particle tests dissipate by local damping and friction)
    /// and the frictionless wall material (its disc-wall stiffness is set by the pair entry of
    /// [`LabModel::contact`], not by mixing).
    pub fn materials(&self) -> Vec<MaterialSpec> {
        let kn = self.contact_kn();
        let ks = kn / self.micro.stiffness_ratio;
        let f = self.micro.wall_stiffness_factor;
        vec![
            material(
                DISC_MATERIAL,
                Some(self.density),
                kn,
                ks,
                self.micro.friction,
            ),
            material(WALL_MATERIAL, None, f * kn, f * ks, 0.0),
        ]
    }

    /// The scene's `contact`: linear law; the disc-wall pair set explicitly to
    /// k_n,wall = `wall_stiffness_factor` × k_n, frictionless.
    pub fn contact(&self) -> ContactSpec {
        let kn = self.contact_kn();
        let f = self.micro.wall_stiffness_factor;
        ContactSpec {
            law: LawName::LinearSpringDashpot,
            rolling: false,
            granular: None,
            pairs: vec![pair(
                DISC_MATERIAL,
                WALL_MATERIAL,
                f * kn,
                f * kn / self.micro.stiffness_ratio,
                0.0,
            )],
        }
    }

    /// The scene's `bond_groups`: grain-boundary and intra-grain parallel bonds (Potyondy &
    /// Cundall 2004), maximum-stress criterion, k̄_s = k̄_n/κ̄, λ̄, β̄ = 1, φ̄ = 0; or, with
    /// [`LabModel::flat_joint`], flat joints of the same stiffness and strengths.
    pub fn bond_groups(&self) -> Vec<BondGroupSpec> {
        let m = &self.micro;
        let kn = self.bond_kn();
        let fj = self.flat_joint;
        let model = match fj {
            None => BondModelName::ParallelPotyondy2004,
            Some(_) => BondModelName::FlatJointPotyondy2012,
        };
        let group = |name: &str, tensile: f64, cohesion: f64| BondGroupSpec {
            kn: Some(kn),
            ks: Some(kn / m.bond_stiffness_ratio),
            radius_multiplier: Some(m.bond_radius_multiplier),
            moment_factor: fj.is_none().then_some(1.0),
            elements: fj.map(|f| u32::from(f.elements)),
            friction: fj.map(|f| f.friction),
            bonded_fraction: fj.map(|f| f.bonded_fraction),
            tensile_strength: Some(tensile),
            cohesion: Some(cohesion),
            friction_angle: Some(0.0),
            ..BondGroupSpec::new(name, model, CriterionName::Stress)
        };
        vec![
            group(GRAIN_BOUNDARY, m.boundary_tensile, m.boundary_cohesion),
            group(INTRA_GRAIN, m.intra_tensile, m.intra_cohesion),
        ]
    }

    /// A scene with this model: schema, units m, thickness, materials, contact, bond groups,
    /// one specimen file (path relative to the scene), no walls, the engine's run and output
    /// defaults. Tests add walls, run and outputs.
    pub fn scene_file(&self, name: &str, specimen_file: &str, offset: [f64; 2]) -> SceneFile {
        SceneFile {
            thickness: Some(self.thickness),
            materials: self.materials(),
            contact: self.contact(),
            bond_groups: self.bond_groups(),
            bodies: BodiesSpec {
                specimens: vec![SpecimenRef {
                    file: specimen_file.into(),
                    offset,
                    velocity: [0.0, 0.0],
                }],
                ..BodiesSpec::default()
            },
            ..SceneFile::new(name)
        }
    }
}

/// A material of linear contact stiffnesses (`kn`, `ks`), friction `mu`, no dashpot, and
/// `density` (kg/m³; `None` for a wall material).
pub fn material(name: &str, density: Option<f64>, kn: f64, ks: f64, mu: f64) -> MaterialSpec {
    MaterialSpec {
        name: name.into(),
        density,
        kn: Some(kn),
        ks: Some(ks),
        friction: mu,
        damping_ratio: Some(0.0),
        ..MaterialSpec::default()
    }
}

/// The linear contact of materials `a` and `b`: stiffnesses (`kn`, `ks`), friction `mu`, no
/// dashpot.
pub fn pair(a: &str, b: &str, kn: f64, ks: f64, mu: f64) -> PairSpec {
    PairSpec {
        materials: [a.into(), b.into()],
        law: LawName::LinearSpringDashpot,
        kn: Some(kn),
        ks: Some(ks),
        friction: Some(mu),
        damping_ratio: Some(0.0),
        ..PairSpec::default()
    }
}

/// Disc–wall contact stiffness in PFC's linear contact model, where the contact stiffness is
/// that of the two entities' springs in series, K = k_A k_B/(k_A + k_B) (Potyondy & Cundall
/// 2004, §2.2, eq. 4; Itasca PFC2D manual, linear contact model; a wall is an entity with its
/// own stiffness). Two equal discs of stiffness k_ball touch with K_dd = k_ball/2, so a disc
/// has k_ball = 2 K_dd; a wall of stiffness f·k_ball (PFC users give walls as a multiple of
/// the ball stiffness) touches a disc with
///
/// K_w = k_ball · f k_ball / (k_ball + f k_ball) = 2 K_dd · f / (1 + f),
///
/// e.g. 1.818 K_dd for f = 10 and 1.333 K_dd for f = 2 (→ 2 K_dd as f → ∞: a rigid wall
/// meets the disc's own spring only). `k_pair` is the disc–disc contact stiffness K_dd (normal
/// or shear: both combine the same way).
pub fn series_wall_stiffness(k_pair: f64, factor: f64) -> f64 {
    let k_ball = 2.0 * k_pair;
    k_ball * (factor * k_ball) / (k_ball + factor * k_ball)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::specimen::Method;

    fn model() -> LabModel {
        let p = SpecimenParams::new(
            Method::Traditional,
            4e-3,
            2e-3,
            1e-4,
            1.5e-4,
            3200.0,
            300e9,
            500e6,
            1,
        );
        LabModel::from_params(&p)
    }

    #[test]
    fn stiffnesses_follow_the_2d_relations() {
        let m = model();
        assert_eq!(m.contact_kn(), 2.0 * 1.0 * 300e9);
        assert!((m.bond_kn() - 300e9 / (2.0 * 1.25e-4)).abs() < 1e-3);
        let g = m.bond_groups();
        assert_eq!(g[0].name, GRAIN_BOUNDARY);
        assert_eq!(g[1].tensile_strength, Some(1000e6));
        let c = m.contact();
        assert_eq!(c.pairs[0].kn, Some(2.0 * 2.0 * 300e9));
    }

    /// The flat-joint groups are valid scene bond groups with the parallel bonds' stiffness
    /// and strengths; the model's JSON without the option is as before (no new key).
    #[test]
    fn flat_joint_groups_replace_the_parallel_bonds() {
        let mut m = model();
        assert!(!serde_json::to_string(&m).unwrap().contains("flat_joint"));
        let pb = m.bond_groups();
        m.flat_joint = Some(FlatJointOption {
            elements: 3,
            friction: 0.6,
            bonded_fraction: 0.8,
        });
        let fj = m.bond_groups();
        for k in 0..2 {
            let g = dem_core::scene::bond_group("model", k, &fj[k]).unwrap();
            match g.model {
                dem_core::bond::BondModel::FlatJoint(p) => {
                    assert_eq!((p.elements, p.friction, p.bonded_fraction), (3, 0.6, 0.8));
                    assert_eq!(Some(p.kn), pb[k].kn);
                    assert_eq!(Some(p.ks), pb[k].ks);
                }
                other => panic!("{other:?}"),
            }
            assert_eq!(fj[k].tensile_strength, pb[k].tensile_strength);
            assert_eq!(fj[k].cohesion, pb[k].cohesion);
            assert_eq!(fj[k].name, pb[k].name);
        }
        let back: LabModel = serde_json::from_str(&serde_json::to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
    }

    /// The option's check names the field at fault and lets the limits through.
    #[test]
    fn flat_joint_option_is_checked_by_field() {
        let ok = FlatJointOption {
            elements: 8,
            friction: 0.0,
            bonded_fraction: 0.0,
        };
        assert_eq!(ok.check(), Ok(()));
        for (bad, field) in [
            (FlatJointOption { elements: 0, ..ok }, "elements"),
            (FlatJointOption { elements: 9, ..ok }, "elements"),
            (
                FlatJointOption {
                    friction: -0.1,
                    ..ok
                },
                "friction",
            ),
            (
                FlatJointOption {
                    friction: f64::INFINITY,
                    ..ok
                },
                "friction",
            ),
            (
                FlatJointOption {
                    bonded_fraction: 1.5,
                    ..ok
                },
                "bonded_fraction",
            ),
            (
                FlatJointOption {
                    bonded_fraction: f64::NAN,
                    ..ok
                },
                "bonded_fraction",
            ),
        ] {
            assert_eq!(bad.check().unwrap_err().0, field, "{bad:?}");
        }
    }

    #[test]
    fn wall_and_disc_springs_combine_in_series() {
        let k = 6e11;
        // A wall as stiff as a disc: k_ball k_ball/(2 k_ball) = k_ball/2 = the disc-disc K.
        assert!((series_wall_stiffness(k, 1.0) - k).abs() <= 1e-15 * k);
        // The audit's figure: a wall 10× the ball gives 2·10/11 = 1.818 K_dd.
        assert!((series_wall_stiffness(k, 10.0) - k * 20.0 / 11.0).abs() <= 1e-15 * k);
        assert!((series_wall_stiffness(k, 2.0) - k * 4.0 / 3.0).abs() <= 1e-15 * k);
        // Series springs: softer than either spring, approaching the disc's own 2K when rigid.
        for f in [0.1, 1.0, 10.0, 1e6] {
            let kw = series_wall_stiffness(k, f);
            assert!(kw < 2.0 * k && kw < f * 2.0 * k, "{f}");
        }
        assert!((series_wall_stiffness(k, 1e12) - 2.0 * k).abs() < 1e-9 * k);
    }
}
