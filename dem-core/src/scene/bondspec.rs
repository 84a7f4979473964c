//! Bond group checks: the scene's flat bond-group object → [`crate::bond::BondGroup`]. Each model
//! and criterion requires its parameters and refuses the others (a parameter that would be
//! silently ignored is an error, so a misread scene cannot run); value ranges are the bond
//! module's own ([`crate::bond::BondGroup::validate`]), reported with the scene field name.

use super::check::Ck;
use super::schema::{BondGroupSpec, BondModelName, CriterionName};
use super::SceneError;
use crate::bond::{
    BondError, BondGroup, BondModel, ContactBondParams, Criterion, FlatJointParams,
    ParallelBondParams,
};

pub(crate) fn bond_group(ck: &Ck, i: usize, g: &BondGroupSpec) -> Result<BondGroup, SceneError> {
    let f = |k: &str| format!("bond_groups[{i}].{k}");
    let model = match g.model {
        BondModelName::ParallelPotyondy2004 => "parallel_potyondy2004",
        BondModelName::ContactBond => "contact_bond",
        BondModelName::FlatJointPotyondy2012 => "flat_joint_potyondy2012",
    };
    let crit = match g.criterion {
        CriterionName::Stress => "criterion stress",
        CriterionName::Force => "criterion force",
        CriterionName::Strain => "criterion strain",
        CriterionName::Energy => "criterion energy",
    };
    let required = |k: &str, v: Option<f64>, why: &str| -> Result<f64, SceneError> {
        match v {
            Some(v) => ck.finite(&f(k), v),
            None => Err(ck.err(f(k), format!("required by {why}"))),
        }
    };
    let refuse = |k: &str, v: Option<f64>, why: &str| -> Result<(), SceneError> {
        match v {
            Some(_) => Err(ck.err(f(k), format!("not used by {why}; remove it"))),
            None => Ok(()),
        }
    };
    let (kn, ks) = (required("kn", g.kn, model)?, required("ks", g.ks, model)?);
    if g.model != BondModelName::FlatJointPotyondy2012 {
        refuse("elements", g.elements.map(f64::from), model)?;
        refuse("friction", g.friction, model)?;
        refuse("bonded_fraction", g.bonded_fraction, model)?;
    }
    let bmodel = match g.model {
        BondModelName::FlatJointPotyondy2012 => {
            refuse("moment_factor", g.moment_factor, model)?;
            let elements = g.elements.unwrap_or(2);
            let max = crate::bond::flat_joint::MAX_ELEMENTS as u32;
            if !(1..=max).contains(&elements) {
                return Err(ck.err(
                    f("elements"),
                    format!("{elements} is out of range: a flat joint has 1 to {max} elements"),
                ));
            }
            BondModel::FlatJoint(FlatJointParams {
                kn,
                ks,
                lambda: g.radius_multiplier.unwrap_or(1.0),
                elements: elements as u8,
                friction: ck.finite(&f("friction"), g.friction.unwrap_or(0.0))?,
                bonded_fraction: ck
                    .finite(&f("bonded_fraction"), g.bonded_fraction.unwrap_or(1.0))?,
            })
        }
        BondModelName::ParallelPotyondy2004 => BondModel::Parallel(ParallelBondParams {
            kn,
            ks,
            lambda: g.radius_multiplier.unwrap_or(1.0),
            beta: g.moment_factor.unwrap_or(1.0),
        }),
        BondModelName::ContactBond => {
            refuse("radius_multiplier", g.radius_multiplier, model)?;
            refuse("moment_factor", g.moment_factor, model)?;
            BondModel::Contact(ContactBondParams { kn, ks })
        }
    };
    // (scene field, value, used by this criterion)
    let c = g.criterion;
    let fields: [(&str, Option<f64>, bool); 9] = [
        (
            "tensile_strength",
            g.tensile_strength,
            c == CriterionName::Stress,
        ),
        ("cohesion", g.cohesion, c == CriterionName::Stress),
        (
            "friction_angle",
            g.friction_angle,
            c == CriterionName::Stress,
        ),
        (
            "normal_strength",
            g.normal_strength,
            c == CriterionName::Force,
        ),
        (
            "shear_strength",
            g.shear_strength,
            c == CriterionName::Force,
        ),
        (
            "moment_strength",
            g.moment_strength,
            c == CriterionName::Force,
        ),
        ("normal_strain", g.normal_strain, c == CriterionName::Strain),
        ("shear_strain", g.shear_strain, c == CriterionName::Strain),
        (
            "fracture_energy",
            g.fracture_energy,
            c == CriterionName::Energy,
        ),
    ];
    for (name, v, used) in fields {
        if !used {
            refuse(name, v, crit)?;
        }
    }
    let criterion = match c {
        CriterionName::Stress => Criterion::Stress {
            tensile: required("tensile_strength", g.tensile_strength, crit)?,
            cohesion: required("cohesion", g.cohesion, crit)?,
            friction_angle: ck
                .finite(&f("friction_angle"), g.friction_angle.unwrap_or(0.0))?
                .to_radians(),
        },
        CriterionName::Force => Criterion::Force {
            tensile: required("normal_strength", g.normal_strength, crit)?,
            shear: required("shear_strength", g.shear_strength, crit)?,
            moment: g.moment_strength.unwrap_or(f64::INFINITY),
        },
        CriterionName::Strain => Criterion::Strain {
            tensile: required("normal_strain", g.normal_strain, crit)?,
            shear: required("shear_strain", g.shear_strain, crit)?,
        },
        CriterionName::Energy => Criterion::Energy {
            fracture_energy: required("fracture_energy", g.fracture_energy, crit)?,
        },
    };
    let out = BondGroup {
        name: g.name.clone(),
        model: bmodel,
        criterion,
    };
    out.validate().map_err(|e| match e {
        BondError::Parameter { field, value, .. } => {
            let scene_field = match (field.as_str(), c) {
                ("lambda", _) => "radius_multiplier",
                ("beta", _) => "moment_factor",
                ("tensile", CriterionName::Stress) => "tensile_strength",
                ("tensile", CriterionName::Force) => "normal_strength",
                ("shear", CriterionName::Force) => "shear_strength",
                ("moment", _) => "moment_strength",
                ("tensile", _) => "normal_strain",
                ("shear", _) => "shear_strain",
                (other, _) => other,
            };
            let shown = if scene_field == "friction_angle" { value.to_degrees() } else { value };
            ck.err(f(scene_field), format!("{shown} is out of range (see docs/scene-schema.md)"))
        }
        BondError::FlatJointNeedsStress(_) => ck.err(
            f("criterion"),
            "flat_joint_potyondy2012's elements break by criterion \"stress\" (tensile_strength, cohesion, friction_angle)",
        ),
        BondError::StressOnContactBond(_) => ck.err(
            f("criterion"),
            "contact_bond has no cross-section; use criterion \"force\" (strengths in N), \"strain\" or \"energy\"",
        ),
        other => ck.err(f("name"), other.to_string()),
    })?;
    Ok(out)
}
