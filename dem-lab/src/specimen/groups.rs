//! The specimen's two bond groups, grain boundary and intra-grain (parallel bonds with the
//! maximum-stress criterion; Potyondy & Cundall 2004), built from the micro-parameters. Used
//! by every method's bonding stage (`methods`, `few`, `improved`) and by the specimen files
//! (`io`).

use super::{SpecimenParams, GRAIN_BOUNDARY, INTRA_GRAIN};
use dem_core::bond::{BondGroup, BondModel, Criterion, ParallelBondParams};

/// Index of the grain-boundary and intra-grain groups in the specimen's [`dem_core::bond::Bonds`].
pub const GB: u16 = 0;
pub const INTRA: u16 = 1;

/// The two bond groups (parallel bonds, maximum-stress criterion), k̄_n = Ē_c/(2 r̄).
pub fn bond_groups(p: &SpecimenParams) -> Vec<BondGroup> {
    bond_groups_with(p, false)
}

/// The bond groups; `unbreakable` gives them strengths of f64::MAX (grains are packed as
/// unbreakable clumps, as PFC packs clumps; the real strengths apply from bonding on).
pub fn bond_groups_with(p: &SpecimenParams, unbreakable: bool) -> Vec<BondGroup> {
    let m = &p.micro;
    let r_mean = 0.5 * (p.r_min + p.r_max);
    let kn = m.bond_modulus / (2.0 * r_mean);
    let model = BondModel::Parallel(ParallelBondParams {
        kn,
        ks: kn / m.bond_stiffness_ratio,
        lambda: m.bond_radius_multiplier,
        beta: 1.0,
    });
    let strength = |v: f64| if unbreakable { f64::MAX } else { v };
    let group = |name: &str, tensile: f64, cohesion: f64| BondGroup {
        name: name.to_string(),
        model,
        criterion: Criterion::Stress {
            tensile: strength(tensile),
            cohesion: strength(cohesion),
            friction_angle: 0.0,
        },
    };
    vec![
        group(GRAIN_BOUNDARY, m.boundary_tensile, m.boundary_cohesion),
        group(INTRA_GRAIN, m.intra_tensile, m.intra_cohesion),
    ]
}
