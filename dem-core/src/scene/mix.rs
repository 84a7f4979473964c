//! The contact law of each material pair that can touch, with its parameters mixed from the two
//! materials (or taken from a `contact.pairs` override).
//!
//! Mixing rules (documented in `docs/scene-schema.md`):
//! - linear stiffness: a material's `kn`/`ks` is the stiffness of a contact between two bodies of
//!   that material; two materials combine as springs in series, each body contributing 2k:
//!   k = 2 k₁k₂/(k₁ + k₂) (the harmonic mean; PFC2D's series rule for ball stiffnesses);
//! - Hertz-Mindlin: E* = 1/((1−ν₁²)/E₁ + (1−ν₂²)/E₂) (Johnson 1985, Contact Mechanics, ch. 4)
//!   and G* = 1/((2−ν₁)/G₁ + (2−ν₂)/G₂) with G = E/(2(1+ν)) (Mindlin's tangential stiffness
//!   8G*a, Johnson ch. 7; as combined in Di Renzo & Di Maio 2004);
//! - friction and rolling friction: the smaller of the two (PFC's rule);
//! - normal damping: the smaller restitution, or the larger damping ratio; a material without
//!   either defers to the other; none at all means no dashpot. Hertz-Mindlin takes restitution
//!   only (its damping is calibrated for it).

use super::check::Ck;
use super::model::{NormalDamping, PairLaw, PairStiffness, Scene};
use super::schema::{ContactSpec, LawName, PairSpec};
use super::SceneError;
use std::collections::{BTreeSet, HashMap};

pub(crate) fn pair_laws(
    ck: &Ck,
    scene: &Scene,
    contact: &ContactSpec,
    names: &HashMap<String, u16>,
) -> Result<Vec<PairLaw>, SceneError> {
    // Overrides by (a, b), a ≤ b.
    let mut overrides: HashMap<(u16, u16), (usize, &PairSpec)> = HashMap::new();
    for (i, p) in contact.pairs.iter().enumerate() {
        let mut ids = [0u16; 2];
        for (k, id) in ids.iter_mut().enumerate() {
            *id = *names.get(&p.materials[k]).ok_or_else(|| {
                ck.err(
                    format!("contact.pairs[{i}].materials[{k}]"),
                    format!("no material named {:?}", p.materials[k]),
                )
            })?;
        }
        let key = (ids[0].min(ids[1]), ids[0].max(ids[1]));
        if let Some((j, _)) = overrides.insert(key, (i, p)) {
            return Err(ck.err(
                format!("contact.pairs[{i}].materials"),
                format!("the same pair is already given in contact.pairs[{j}]"),
            ));
        }
        if p.restitution.is_some() && p.damping_ratio.is_some() {
            return Err(ck.err(
                format!("contact.pairs[{i}].restitution"),
                "give restitution or damping_ratio, not both",
            ));
        }
    }
    let disc_mats: BTreeSet<u16> = scene
        .discs
        .iter()
        .map(|d| d.material)
        .chain(scene.clumps.iter().map(|c| c.material))
        .collect();
    let wall_mats: BTreeSet<u16> = scene.walls.iter().map(|w| w.material).collect();
    let mut used = BTreeSet::new();
    for &a in &disc_mats {
        for &b in disc_mats.iter().chain(wall_mats.iter()) {
            used.insert((a.min(b), a.max(b)));
        }
    }
    used.into_iter()
        .map(|(a, b)| pair(ck, scene, contact, overrides.get(&(a, b)).copied(), a, b))
        .collect()
}

/// A pair with `"law": "granular"`: the law built from its spec (the pair's, else
/// `contact.granular`) and checked for discs; the materials' contact values are not used.
fn granular_pair(
    ck: &Ck,
    contact: &ContactSpec,
    ov: Option<(usize, &PairSpec)>,
    (a, b): (u16, u16),
    what: &str,
    rolling: bool,
) -> Result<PairLaw, SceneError> {
    let (spec, field) = match ov {
        Some((i, p)) if p.granular.is_some() => {
            (p.granular.as_ref(), format!("contact.pairs[{i}].granular"))
        }
        _ => (contact.granular.as_ref(), "contact.granular".to_string()),
    };
    let spec = spec.ok_or_else(|| {
        ck.err(
            field.clone(),
            format!("{what} uses the granular law, which needs its sub-models here (docs/laws.md)"),
        )
    })?;
    let law = spec.build().map_err(|e| match e {
        dem_laws::LawError::Invalid { path, reason, .. } => {
            ck.err(format!("{field}.{path}"), reason)
        }
        other => ck.err(field.clone(), other.to_string()),
    })?;
    crate::contact::granular::check_2d(&law).map_err(|r| ck.err(field.clone(), r))?;
    if let Some((i, p)) = ov {
        let unused = [
            ("kn", p.kn.is_some()),
            ("ks", p.ks.is_some()),
            ("friction", p.friction.is_some()),
            ("restitution", p.restitution.is_some()),
            ("damping_ratio", p.damping_ratio.is_some()),
        ];
        if let Some((k, _)) = unused.iter().find(|(_, set)| *set) {
            return Err(ck.err(
                format!("contact.pairs[{i}].{k}"),
                "not used by the granular law (set it in its sub-models)",
            ));
        }
    }
    if rolling {
        return Err(ck.err(
            field,
            "rolling resistance with the granular law on discs is not supported yet",
        ));
    }
    let friction = match law.tangential {
        dem_laws::Tangential::LinearNoHistory { mu, .. }
        | dem_laws::Tangential::LinearHistory { mu, .. }
        | dem_laws::Tangential::Mindlin { mu, .. }
        | dem_laws::Tangential::MindlinDeresiewicz { mu, .. } => mu,
    };
    Ok(PairLaw {
        a,
        b,
        law: LawName::Granular,
        stiffness: PairStiffness::Granular(law),
        friction,
        damping: NormalDamping::Ratio(0.0),
        rolling: None,
    })
}

fn pair(
    ck: &Ck,
    scene: &Scene,
    contact: &ContactSpec,
    ov: Option<(usize, &PairSpec)>,
    a: u16,
    b: u16,
) -> Result<PairLaw, SceneError> {
    let (ma, mb) = (&scene.materials[a as usize], &scene.materials[b as usize]);
    let what = format!("pair ({:?}, {:?})", ma.name, mb.name);
    let (law, rolling) = match ov {
        Some((_, p)) => (p.law, p.rolling),
        None => (contact.law, contact.rolling),
    };
    let of = |k: &str| ov.map(|(i, _)| format!("contact.pairs[{i}].{k}"));
    // A material value, or an error naming the material field to set.
    let need = |m: u16, v: Option<f64>, k: &str, law: &str| {
        v.ok_or_else(|| {
            ck.err(
                format!("materials[{m}].{k}"),
                format!("{what} uses {law}, which needs {k} (or set it in a contact.pairs entry)"),
            )
        })
    };
    if let Some((i, p)) = ov {
        if p.granular.is_some() && law != LawName::Granular {
            return Err(ck.err(
                format!("contact.pairs[{i}].granular"),
                "given but the pair's law is not \"granular\"",
            ));
        }
    }
    let stiffness = match law {
        LawName::Granular => return granular_pair(ck, contact, ov, (a, b), &what, rolling),
        LawName::LinearSpringDashpot => {
            let get = |k: &str,
                       o: Option<f64>,
                       va: Option<f64>,
                       vb: Option<f64>|
             -> Result<f64, SceneError> {
                if let Some(v) = o {
                    return ck.positive(&of(k).unwrap_or_default(), v);
                }
                let (x, y) = (
                    need(a, va, k, "linear_spring_dashpot")?,
                    need(b, vb, k, "linear_spring_dashpot")?,
                );
                Ok(2.0 * x * y / (x + y))
            };
            let p = ov.map(|(_, p)| p);
            PairStiffness::Linear {
                kn: get("kn", p.and_then(|p| p.kn), ma.kn, mb.kn)?,
                ks: get("ks", p.and_then(|p| p.ks), ma.ks, mb.ks)?,
            }
        }
        LawName::HertzMindlin => {
            if let Some((i, p)) = ov {
                if p.kn.is_some() || p.ks.is_some() {
                    return Err(ck.err(
                        format!("contact.pairs[{i}].kn"),
                        "kn/ks are not used by hertz_mindlin (set youngs_modulus and poisson of the materials)",
                    ));
                }
            }
            let h = "hertz_mindlin";
            let (ea, eb) = (
                need(a, ma.youngs_modulus, "youngs_modulus", h)?,
                need(b, mb.youngs_modulus, "youngs_modulus", h)?,
            );
            let (na, nb) = (
                need(a, ma.poisson, "poisson", h)?,
                need(b, mb.poisson, "poisson", h)?,
            );
            let (ga, gb) = (ea / (2.0 * (1.0 + na)), eb / (2.0 * (1.0 + nb)));
            PairStiffness::Hertz {
                e_star: 1.0 / ((1.0 - na * na) / ea + (1.0 - nb * nb) / eb),
                g_star: 1.0 / ((2.0 - na) / ga + (2.0 - nb) / gb),
            }
        }
    };
    let p = ov.map(|(_, p)| p);
    let friction = match p.and_then(|p| p.friction) {
        Some(f) => ck.non_negative(&of("friction").unwrap_or_default(), f)?,
        None => ma.friction.min(mb.friction),
    };
    let damping = if let Some(e) = p.and_then(|p| p.restitution) {
        let e = ck.range(&of("restitution").unwrap_or_default(), e, 0.0, 1.0, true)?;
        if e == 0.0 {
            return Err(ck.err(of("restitution").unwrap_or_default(), "must be above 0"));
        }
        NormalDamping::Restitution(e)
    } else if let Some(z) = p.and_then(|p| p.damping_ratio) {
        NormalDamping::Ratio(ck.range(
            &of("damping_ratio").unwrap_or_default(),
            z,
            0.0,
            1.0,
            false,
        )?)
    } else {
        let da = ma
            .restitution
            .map(NormalDamping::Restitution)
            .or(ma.damping_ratio.map(NormalDamping::Ratio));
        let db = mb
            .restitution
            .map(NormalDamping::Restitution)
            .or(mb.damping_ratio.map(NormalDamping::Ratio));
        match (da, db) {
            (None, None) => NormalDamping::Ratio(0.0),
            (Some(d), None) | (None, Some(d)) => d,
            (Some(NormalDamping::Restitution(x)), Some(NormalDamping::Restitution(y))) => NormalDamping::Restitution(x.min(y)),
            (Some(NormalDamping::Ratio(x)), Some(NormalDamping::Ratio(y))) => NormalDamping::Ratio(x.max(y)),
            _ => {
                return Err(ck.err(
                    "contact.pairs",
                    format!("{what}: one material gives restitution, the other damping_ratio; add a contact.pairs entry with one of them"),
                ))
            }
        }
    };
    let damping = match (law, damping) {
        (LawName::HertzMindlin, NormalDamping::Ratio(0.0)) => NormalDamping::Restitution(1.0),
        (LawName::HertzMindlin, NormalDamping::Ratio(_)) => {
            return Err(ck.err(
                ov.map(|(i, _)| format!("contact.pairs[{i}].damping_ratio"))
                    .unwrap_or_else(|| "contact.law".into()),
                format!(
                "{what} uses hertz_mindlin, whose damping is set by restitution, not damping_ratio"
            ),
            ))
        }
        (_, d) => d,
    };
    let rolling = if rolling {
        Some(match p.and_then(|p| p.rolling_friction) {
            Some(r) => ck.non_negative(&of("rolling_friction").unwrap_or_default(), r)?,
            None => ma.rolling_friction.min(mb.rolling_friction),
        })
    } else {
        if let Some((i, p)) = ov {
            if p.rolling_friction.is_some() {
                return Err(ck.err(
                    format!("contact.pairs[{i}].rolling_friction"),
                    "given but rolling is off for this pair (set \"rolling\": true)",
                ));
            }
        }
        None
    };
    Ok(PairLaw {
        a,
        b,
        law,
        stiffness,
        friction,
        damping,
        rolling,
    })
}
