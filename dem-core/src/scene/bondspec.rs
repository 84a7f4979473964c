//! Bond group checks: each model and criterion requires its parameters and refuses the others
//! (a parameter that would be silently ignored is an error, so a misread scene cannot run).

use super::model::BondGroup;
use super::resolve::Ck;
use super::schema::{BondGroupSpec, BondModelName, CriterionName};
use super::SceneError;

pub(crate) fn bond_group(ck: &Ck, i: usize, g: &BondGroupSpec) -> Result<BondGroup, SceneError> {
    let f = |k: &str| format!("bond_groups[{i}].{k}");
    let model = match g.model {
        BondModelName::ParallelPotyondy2004 => "parallel_potyondy2004",
        BondModelName::ContactBond => "contact_bond",
    };
    let crit = match g.criterion {
        CriterionName::Stress => "stress",
        CriterionName::Force => "force",
        CriterionName::Strain => "strain",
        CriterionName::Energy => "energy",
    };
    let required = |k: &str, v: Option<f64>, why: &str| -> Result<f64, SceneError> {
        match v {
            Some(v) => ck.positive(&f(k), v),
            None => Err(ck.err(f(k), format!("required by {why}"))),
        }
    };
    let refuse = |k: &str, v: Option<f64>, why: &str| -> Result<(), SceneError> {
        match v {
            Some(_) => Err(ck.err(f(k), format!("not used by {why}; remove it"))),
            None => Ok(()),
        }
    };
    let parallel = g.model == BondModelName::ParallelPotyondy2004;
    let kn = required("kn", g.kn, model)?;
    let ks = required("ks", g.ks, model)?;
    let (radius_multiplier, moment_factor) = if parallel {
        (
            g.radius_multiplier
                .map(|v| ck.positive(&f("radius_multiplier"), v))
                .transpose()?
                .unwrap_or(1.0),
            g.moment_factor
                .map(|v| ck.range(&f("moment_factor"), v, 0.0, 1.0, true))
                .transpose()?
                .unwrap_or(1.0),
        )
    } else {
        refuse("radius_multiplier", g.radius_multiplier, model)?;
        refuse("moment_factor", g.moment_factor, model)?;
        (1.0, 0.0)
    };
    if !parallel && g.criterion == CriterionName::Stress {
        return Err(ck.err(
            f("criterion"),
            "contact_bond has no cross-section; use criterion \"force\" (strengths in N), \"strain\" or \"energy\"",
        ));
    }
    let mut out = BondGroup {
        name: g.name.clone(),
        model: g.model,
        criterion: g.criterion,
        kn,
        ks,
        radius_multiplier,
        moment_factor,
        tensile_strength: None,
        cohesion: None,
        friction_angle: None,
        normal_strength: None,
        shear_strength: None,
        normal_strain: None,
        shear_strain: None,
        fracture_energy: None,
    };
    let why = format!("criterion {crit}");
    let stress = g.criterion == CriterionName::Stress;
    let force = g.criterion == CriterionName::Force;
    let strain = g.criterion == CriterionName::Strain;
    let energy = g.criterion == CriterionName::Energy;
    let fields: [(&str, Option<f64>, bool); 7] = [
        ("tensile_strength", g.tensile_strength, stress),
        ("cohesion", g.cohesion, stress),
        ("normal_strength", g.normal_strength, force),
        ("shear_strength", g.shear_strength, force),
        ("normal_strain", g.normal_strain, strain),
        ("shear_strain", g.shear_strain, strain),
        ("fracture_energy", g.fracture_energy, energy),
    ];
    let mut vals = [None; 7];
    for (k, (name, v, used)) in fields.into_iter().enumerate() {
        if used {
            vals[k] = Some(required(name, v, &why)?);
        } else {
            refuse(name, v, &why)?;
        }
    }
    [
        out.tensile_strength,
        out.cohesion,
        out.normal_strength,
        out.shear_strength,
        out.normal_strain,
        out.shear_strain,
        out.fracture_energy,
    ] = vals;
    if stress {
        let phi = g.friction_angle.unwrap_or(0.0);
        out.friction_angle = Some(
            ck.range(&f("friction_angle"), phi, 0.0, 90.0, false)?
                .to_radians(),
        );
    } else {
        refuse("friction_angle", g.friction_angle, &why)?;
    }
    Ok(out)
}
