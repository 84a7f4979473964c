//! The specimen file (`dem.specimen/1`, see `docs/specimen.md` and
//! [`dem_core::scene::schema::SpecimenFile`]) and the summary beside it.
//!
//! A relaxed specimen is written as: one disc set (positions and radii in metres, shifted so
//! the discs' bounding box starts at the origin; per-disc grain ids; per-disc mass factors for
//! improved-ORC members, whose masses are the templates' solved ones), the rigid clumps (ORC) as
//! member lists, and the intact bonds per bond group as disc index pairs.
//!
//! **Stress-free hand-over.** Bonds are installed force-free when a scene loads them (the bond
//! store sets each bond's reference gap to the gap at installation), so the forces the relaxed
//! specimen holds in its bonds cannot be restored; the contacts of bonded pairs would then push
//! the specimen apart when it is loaded. So every bonded pair that overlaps is given its
//! current gap as contact reference gap (`contact_offsets`; for improved-ORC members that is
//! their designed overlap plus the small elastic one): the loaded specimen starts with no force
//! in any bonded contact and no bond force, i.e. at rest, with its locked-in stress (reported
//! in the summary) released. The reference gaps are of the order of σ0·r/E (~1e-5 r) except
//! for the members of improved grains.
//!
//! Disc indices are the discs' order in the file (the world's stable ids, in order). Materials
//! and bond groups are named; a scene defines them. Both files are written atomically
//! (temporary file, then rename).

use super::{Specimen, SpecimenError};
use dem_core::bond::BondStatus;
use dem_core::scene::schema::{
    BondListSpec, DiscSetSpec, LengthUnit, SceneFile, SpecimenFile, SPECIMEN_SCHEMA,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The file form of a specimen; its discs are made of the scene material `material`.
pub fn to_file(s: &Specimen, material: &str) -> SpecimenFile {
    let w = &s.world;
    let d = &w.state.discs;
    let mut order: Vec<usize> = (0..d.len()).collect();
    order.sort_by_key(|&k| d.id[k]);
    let mut file_of_id: HashMap<u32, u32> = HashMap::with_capacity(d.len());
    for (f, &k) in order.iter().enumerate() {
        file_of_id.insert(d.id[k], f as u32);
    }
    let x0 = order
        .iter()
        .map(|&k| d.x[k] - d.r[k])
        .fold(f64::INFINITY, f64::min);
    let y0 = order
        .iter()
        .map(|&k| d.y[k] - d.r[k])
        .fold(f64::INFINITY, f64::min);
    let (x0, y0) = if d.is_empty() { (0.0, 0.0) } else { (x0, y0) };
    let t = w.state.thickness;
    let rho = s.params.density;
    let factors: Vec<f64> = order
        .iter()
        .map(|&k| d.m[k] / (rho * t * std::f64::consts::PI * d.r[k] * d.r[k]))
        .collect();
    let uniform = factors.iter().all(|f| (f - 1.0).abs() <= 1e-12);
    let set = DiscSetSpec {
        material: material.to_string(),
        group: 0,
        velocity: [0.0; 2],
        omega: 0.0,
        random_speed: 0.0,
        fixed: false,
        discs: order
            .iter()
            .map(|&k| [d.x[k] - x0, d.y[k] - y0, d.r[k]])
            .collect(),
        groups: Some(order.iter().map(|&k| d.group[k]).collect()),
        mass_factors: (!uniform).then_some(factors),
    };
    let cl = &w.state.clumps;
    let rigid_clumps = (0..cl.len())
        .map(|c| {
            cl.members[cl.member_range(c)]
                .iter()
                .map(|id| file_of_id[id])
                .collect()
        })
        .collect();
    // Stress-free hand-over: every bonded pair that overlaps gets its current gap as contact
    // reference gap, and the loader installs the bonds force-free, so the loaded specimen
    // starts with no force in any bonded contact (see the module docs).
    let mut bonds = Vec::new();
    if let Some(b) = &w.bonds {
        for (g, name) in b.group_names().into_iter().enumerate() {
            let mut pairs = Vec::new();
            let mut gaps = Vec::new();
            for v in b.iter().filter(|v| v.group as usize == g) {
                if v.status != BondStatus::Intact {
                    continue;
                }
                let (i, j) = (v.i as usize, v.j as usize);
                pairs.push([file_of_id[&d.id[i]], file_of_id[&d.id[j]]]);
                gaps.push(dem_core::bond::install::gap(&w.state, i, j).min(0.0));
            }
            if pairs.is_empty() {
                continue;
            }
            let any = gaps.iter().any(|&g| g < 0.0);
            bonds.push(BondListSpec {
                bond_group: name,
                pairs,
                contact_offsets: any.then_some(gaps),
            });
        }
    }
    let p = &s.params;
    SpecimenFile {
        schema: SPECIMEN_SCHEMA.to_string(),
        description: format!(
            "{} specimen, {} x {} mm, radii {}-{} mm, seed {}; written by dem specimen",
            p.method.name(),
            p.width * 1e3,
            p.height * 1e3,
            p.r_min * 1e3,
            p.r_max * 1e3,
            p.seed
        ),
        units: LengthUnit::M,
        discs: vec![set],
        clumps: Vec::new(),
        rigid_clumps,
        bonds,
    }
}

/// `x.json` → `x.summary.json` (any other name gets `.summary.json` appended).
pub fn summary_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name.strip_suffix(".json").unwrap_or(&name);
    path.with_file_name(format!("{stem}.summary.json"))
}

/// Write `text` to `path` atomically (a temporary file beside it, then rename).
pub fn write_atomic(path: &Path, text: &str) -> Result<(), SpecimenError> {
    let fail = |e: std::io::Error| SpecimenError::File {
        file: path.display().to_string(),
        reason: e.to_string(),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "specimen".into());
    let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
    std::fs::write(&tmp, text).map_err(fail)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        fail(e)
    })
}

/// Save the specimen file and its summary (`summary_path(path)`); returns the summary's path.
pub fn save(s: &Specimen, material: &str, path: &Path) -> Result<PathBuf, SpecimenError> {
    let ser = |e: serde_json::Error| SpecimenError::File {
        file: path.display().to_string(),
        reason: e.to_string(),
    };
    let text = serde_json::to_string(&to_file(s, material)).map_err(ser)?;
    write_atomic(path, &text)?;
    let sp = summary_path(path);
    let summary = serde_json::to_string_pretty(&s.summary).map_err(ser)?;
    write_atomic(&sp, &summary)?;
    Ok(sp)
}

/// A scene (`dem.scene/1`) that loads the specimen file `specimen_file` (relative to the
/// scene) with the micro-parameters it was generated with: material `material` (density,
/// linear contact k_n = 2tE_c, k_s, friction), the two bond groups (parallel bonds, stress
/// criterion), local damping 0.7, `steps` steps. A starting point for lab-test scenes.
pub fn example_scene(s: &Specimen, material: &str, specimen_file: &str, steps: u64) -> SceneFile {
    use dem_core::scene::schema::{
        BodiesSpec, BondGroupSpec, BondModelName, CriterionName, MaterialSpec, OutputSpec, RunSpec,
        SpecimenRef,
    };
    let p = &s.params;
    let m = &p.micro;
    let kn = 2.0 * p.thickness * m.contact_modulus;
    // The specimen's groups are parallel bonds with the stress criterion (groups::bond_groups).
    let bond_groups = super::groups::bond_groups(p)
        .iter()
        .filter_map(|g| match (&g.model, &g.criterion) {
            (
                dem_core::bond::BondModel::Parallel(pb),
                dem_core::bond::Criterion::Stress {
                    tensile,
                    cohesion,
                    friction_angle,
                },
            ) => Some(BondGroupSpec {
                kn: Some(pb.kn),
                ks: Some(pb.ks),
                radius_multiplier: Some(pb.lambda),
                moment_factor: Some(pb.beta),
                tensile_strength: Some(*tensile),
                cohesion: Some(*cohesion),
                friction_angle: Some(friction_angle.to_degrees()),
                ..BondGroupSpec::new(
                    &g.name,
                    BondModelName::ParallelPotyondy2004,
                    CriterionName::Stress,
                )
            }),
            _ => None,
        })
        .collect();
    SceneFile {
        schema: dem_core::scene::schema::SCHEMA.into(),
        name: format!("{} specimen, seed {}", p.method.name(), p.seed),
        description: "Loads the specimen with the micro-parameters it was generated with \
                      (dem specimen)."
            .into(),
        units: LengthUnit::M,
        thickness: Some(p.thickness),
        seed: 0,
        materials: vec![MaterialSpec {
            name: material.into(),
            density: Some(p.density),
            kn: Some(kn),
            ks: Some(kn / m.stiffness_ratio),
            friction: m.friction,
            damping_ratio: Some(0.0),
            ..MaterialSpec::default()
        }],
        contact: Default::default(),
        bond_groups,
        bodies: BodiesSpec {
            specimens: vec![SpecimenRef {
                file: specimen_file.into(),
                offset: [0.0, 0.0],
                velocity: [0.0, 0.0],
            }],
            ..BodiesSpec::default()
        },
        auto_bonds: vec![],
        walls: vec![],
        loads: vec![],
        periodic: None,
        gravity: None,
        damping: dem_core::scene::schema::DampingSpec {
            local: super::relax::LOCAL_DAMPING,
            viscous: 0.0,
            ..Default::default()
        },
        run: RunSpec {
            steps: Some(steps),
            ..RunSpec::default()
        },
        outputs: OutputSpec {
            history_every: 100,
            ..OutputSpec::default()
        },
    }
}
