//! Specimens of the lab tests: generated with the user's [`SpecimenParams`] (method, radii,
//! grain size, seed, micro-parameters) but the test's own shape, saved as `dem.specimen/1`
//! files beside the test scene, and reused when a key file beside them records the same
//! parameters. Generation takes tens of seconds for 1000 discs; a calibration generates each
//! test's specimen once and runs its scene with many [`crate::LabModel`]s.
//!
//! The Brazilian disc is carved from a D × D square specimen: discs whose centre lies outside
//! the circle of diameter D are dropped, with the bonds touching them; a rigid ORC grain goes
//! whole if any member goes, and so do the members of an improved-ORC grain (same grain id).
//! The single-edge-notched beam (SENB) has its notch cut the same way: the discs in a slot up
//! from the bottom edge at mid-length dropped, and every bond crossing the slot's mid-line below
//! its tip.

use crate::specimen::improved::GrainCover;
use crate::specimen::{self, io, Method, Progress, SpecimenParams, DEFAULT_MATERIAL};
use crate::LabError;
use dem_core::scene::schema::{LengthUnit, SpecimenFile};
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Shape of a test specimen (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum Shape {
    Rectangle {
        width: f64,
        height: f64,
    },
    /// Carved from a `diameter` × `diameter` square.
    Disc {
        diameter: f64,
    },
    /// A `width` × `height` beam with a notch `notch_depth` deep and `notch_width` wide cut
    /// up from the bottom at mid-length ([`carve_notch`]; the SENB test).
    NotchedBeam {
        width: f64,
        height: f64,
        notch_depth: f64,
        notch_width: f64,
    },
}

/// A specimen file ready for a lab scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TestSpecimen {
    pub file: PathBuf,
    /// Bounding box of the discs (discs' edges) in the file's coordinates (m): [x0, y0, x1, y1].
    pub extent: [f64; 4],
    pub discs: usize,
    pub bonds: usize,
    /// Mean disc radius (m).
    pub r_mean: f64,
    /// Whether an existing file was reused instead of generated.
    pub reused: bool,
    /// Grains whose improved-ORC template stops below its cover target (from the generator's
    /// summary beside the file; empty for other methods, and for a specimen whose summary
    /// predates this list). Reported, not acted on; left out of the JSON when empty.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub below_cover: Vec<GrainCover>,
}

/// What the key file beside a specimen records.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Key {
    schema: String,
    shape: Shape,
    params: SpecimenParams,
}

const KEY_SCHEMA: &str = "dem.lab-specimen-key/1";

/// What `x.failed.json` beside a specimen that failed to generate records: its key and the
/// error. Generation is deterministic (the same bits for any thread count), so the same key
/// fails again the same way; [`prepare`] returns the recorded error at once instead of
/// spending the failed run's steps again (a stress servo that does not converge costs up to
/// 12 M steps). Deleting the file, or any change of the inputs, tries again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Failed {
    key: Key,
    error: String,
}

/// `x.json` → `x.failed.json`.
pub fn failed_path(file: &Path) -> PathBuf {
    let k = key_path(file);
    let name = k.file_name().map(|n| n.to_string_lossy().into_owned());
    let name = name
        .unwrap_or_default()
        .replace(".key.json", ".failed.json");
    file.with_file_name(name)
}

/// `x.json` → `x.key.json`.
pub fn key_path(file: &Path) -> PathBuf {
    let name = file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name.strip_suffix(".json").unwrap_or(&name);
    file.with_file_name(format!("{stem}.key.json"))
}

/// The generation parameters of a test specimen: `base` with the shape's width and height
/// (the disc is generated as its bounding square).
pub fn shape_params(base: &SpecimenParams, shape: Shape) -> SpecimenParams {
    let mut p = base.clone();
    match shape {
        Shape::Rectangle { width, height } | Shape::NotchedBeam { width, height, .. } => {
            p.width = width;
            p.height = height;
        }
        Shape::Disc { diameter } => {
            p.width = diameter;
            p.height = diameter;
        }
    }
    p
}

/// The specimen of `shape` at `file` (with its key file and the generator's summary beside
/// it): reused if the key file records the same parameters and shape, else generated (which
/// reports `progress`) and saved. The discs are made of [`DEFAULT_MATERIAL`] (the lab model's
/// disc material).
pub fn prepare(
    base: &SpecimenParams,
    shape: Shape,
    file: &Path,
    progress: &mut dyn FnMut(Progress),
) -> Result<TestSpecimen, LabError> {
    let p = shape_params(base, shape);
    p.validate()?;
    let key = Key {
        schema: KEY_SCHEMA.into(),
        shape,
        params: p.clone(),
    };
    let kp = key_path(file);
    if file.exists() {
        if let Ok(text) = std::fs::read_to_string(&kp) {
            if serde_json::from_str::<Key>(&text).is_ok_and(|k| k == key) {
                let mut t = TestSpecimen::read(file)?;
                t.reused = true;
                return Ok(t);
            }
        }
    }
    if let Some(dir) = file.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| LabError::Io {
            file: dir.display().to_string(),
            source,
        })?;
    }
    let fp = failed_path(file);
    if let Ok(text) = std::fs::read_to_string(&fp) {
        if let Ok(f) = serde_json::from_str::<Failed>(&text) {
            if f.key == key {
                return Err(LabError::Param {
                    field: file.display().to_string(),
                    reason: format!(
                        "{} (recorded in {} by an earlier run of the same inputs; delete it to \
                         try again)",
                        f.error,
                        fp.display()
                    ),
                });
            }
        }
    }
    let spec = match specimen::generate(&p, progress) {
        Ok(s) => s,
        Err(e) => {
            let f = Failed {
                key,
                error: e.to_string(),
            };
            if let Ok(text) = serde_json::to_string_pretty(&f) {
                // Best effort: the generation error is what the caller must see.
                let _ = io::write_atomic(&fp, &text);
            }
            return Err(e.into());
        }
    };
    let _ = std::fs::remove_file(&fp);
    let mut sf = io::to_file(&spec, DEFAULT_MATERIAL);
    match shape {
        Shape::Disc { diameter } => sf = carve_disc(&sf, diameter, p.method),
        Shape::NotchedBeam {
            notch_depth,
            notch_width,
            ..
        } => sf = carve_notch(&sf, notch_depth, notch_width, p.method),
        Shape::Rectangle { .. } => {}
    }
    let ser = |e: serde_json::Error| LabError::Io {
        file: file.display().to_string(),
        source: std::io::Error::other(e),
    };
    io::write_atomic(file, &serde_json::to_string(&sf).map_err(ser)?)?;
    io::write_atomic(
        &io::summary_path(file),
        &serde_json::to_string_pretty(&spec.summary).map_err(ser)?,
    )?;
    io::write_atomic(&kp, &serde_json::to_string_pretty(&key).map_err(ser)?)?;
    TestSpecimen::read(file)
}

impl TestSpecimen {
    /// Reads a specimen file's geometry (any `dem.specimen/1` file of disc sets).
    pub fn read(file: &Path) -> Result<TestSpecimen, LabError> {
        let (sf, discs) = read_file(file)?;
        let mut ext = [f64::INFINITY, f64::INFINITY, -f64::INFINITY, -f64::INFINITY];
        let mut rsum = 0.0;
        for &[x, y, r] in &discs {
            ext[0] = ext[0].min(x - r);
            ext[1] = ext[1].min(y - r);
            ext[2] = ext[2].max(x + r);
            ext[3] = ext[3].max(y + r);
            rsum += r;
        }
        Ok(TestSpecimen {
            file: file.to_path_buf(),
            extent: ext,
            discs: discs.len(),
            bonds: sf.bonds.iter().map(|b| b.pairs.len()).sum(),
            r_mean: rsum / discs.len() as f64,
            reused: false,
            below_cover: below_cover(file, &sf),
        })
    }

    /// The discs `[x, y, r]` (m) of the specimen file, in file order.
    pub fn discs(&self) -> Result<Vec<[f64; 3]>, LabError> {
        Ok(read_file(&self.file)?.1)
    }

    /// Width and height of the extent (m).
    pub fn size(&self) -> [f64; 2] {
        [
            self.extent[2] - self.extent[0],
            self.extent[3] - self.extent[1],
        ]
    }

    /// The file name, as a scene beside the specimen refers to it.
    pub fn file_name(&self) -> String {
        self.file
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    }
}

/// The grains below their cover target that the generator's summary beside `file` lists
/// (`templates.below_cover`) and that are still in the specimen `sf` (a carved disc drops
/// grains); empty when there is no summary or no such list.
fn below_cover(file: &Path, sf: &SpecimenFile) -> Vec<GrainCover> {
    let listed: Vec<GrainCover> = std::fs::read_to_string(io::summary_path(file))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| serde_json::from_value(v.get("templates")?.get("below_cover")?.clone()).ok())
        .unwrap_or_default();
    if listed.is_empty() {
        return listed;
    }
    let present: HashSet<u32> = sf
        .discs
        .iter()
        .filter_map(|s| s.groups.as_ref())
        .flatten()
        .copied()
        .collect();
    listed
        .into_iter()
        .filter(|g| present.contains(&g.grain))
        .collect()
}

/// A specimen file and its discs in metres; it must hold discs and no template clumps.
fn read_file(file: &Path) -> Result<(SpecimenFile, Vec<[f64; 3]>), LabError> {
    let name = file.display().to_string();
    let text = clumpgen::io::read_input_string(file).map_err(|source| LabError::Io {
        file: name.clone(),
        source,
    })?;
    let sf: SpecimenFile = serde_json::from_str(&text).map_err(|e| LabError::Io {
        file: name.clone(),
        source: std::io::Error::other(e),
    })?;
    let u = match sf.units {
        LengthUnit::M => 1.0,
        LengthUnit::Mm => 1e-3,
    };
    let discs: Vec<[f64; 3]> = sf
        .discs
        .iter()
        .flat_map(|s| s.discs.iter().map(|d| [d[0] * u, d[1] * u, d[2] * u]))
        .collect();
    if discs.is_empty() || !sf.clumps.is_empty() {
        return Err(LabError::Param {
            field: name,
            reason: "a lab specimen needs discs (and no template clumps)".into(),
        });
    }
    Ok((sf, discs))
}

/// The disc of diameter `d` carved from a square specimen file (one disc set, as
/// [`io::to_file`] writes): centred on the discs' bounding box; discs whose centre is farther
/// than d/2 from the centre are dropped, with whole ORC rigid grains and whole improved-ORC
/// grains (same grain id) when one member is dropped; bonds touching a dropped disc go too.
/// The result is shifted so its bounding box starts at the origin.
pub fn carve_disc(sf: &SpecimenFile, d: f64, method: Method) -> SpecimenFile {
    let Some(set) = sf.discs.first() else {
        return sf.clone();
    };
    let [x0, y0, x1, y1] = bbox(&set.discs);
    let (cx, cy, rc) = (0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * d / unit(sf));
    let mut out = carve(
        sf,
        method,
        |&[x, y, _]| (x - cx).hypot(y - cy) > rc,
        |_, _| false,
    );
    let [nx0, ny0, _, _] = bbox(&out.discs[0].discs);
    for v in &mut out.discs[0].discs {
        v[0] -= nx0;
        v[1] -= ny0;
    }
    out.description = format!("{} (disc of diameter {} m carved out)", sf.description, d);
    out
}

/// The notch of a single-edge-notched beam (ASTM E399 SE(B)) cut into a rectangular specimen
/// file (one disc set): a slot of width `width` (m) from the bottom edge of the discs' bounding
/// box up to `depth` (m), centred at mid-length. Discs whose centre lies in the slot are
/// dropped (with whole grains, as [`carve_disc`]), and so is every bond, and every ORC rigid
/// grain, that crosses the slot's mid-line below its tip: the flanks touch but hold no tension
/// across the notch, which ends in a crack-like cut one slot width wide. Coordinates unchanged.
pub fn carve_notch(sf: &SpecimenFile, depth: f64, width: f64, method: Method) -> SpecimenFile {
    let Some(set) = sf.discs.first() else {
        return sf.clone();
    };
    let u = unit(sf);
    let [x0, y0, x1, _] = bbox(&set.discs);
    let (xc, tip, half) = (0.5 * (x0 + x1), y0 + depth / u, 0.5 * width / u);
    let crosses = |p: &[f64; 3], q: &[f64; 3]| {
        let (a, b) = (p[0] - xc, q[0] - xc);
        // On opposite sides of the mid-line, crossing it below the tip.
        a * b < 0.0 && p[1] + (q[1] - p[1]) * a / (a - b) < tip
    };
    let mut out = carve(
        sf,
        method,
        |&[x, y, _]| (x - xc).abs() < half && y < tip,
        crosses,
    );
    out.description = format!(
        "{} (notch {} m deep, {} m wide cut in at mid-length)",
        sf.description, depth, width
    );
    out
}

/// Length unit of a specimen file in metres.
fn unit(sf: &SpecimenFile) -> f64 {
    match sf.units {
        LengthUnit::M => 1.0,
        LengthUnit::Mm => 1e-3,
    }
}

/// Bounding box [x0, y0, x1, y1] of discs [x, y, r] (their edges).
fn bbox(discs: &[[f64; 3]]) -> [f64; 4] {
    discs.iter().fold(
        [f64::INFINITY, f64::INFINITY, -f64::INFINITY, -f64::INFINITY],
        |b, &[x, y, r]| {
            [
                b[0].min(x - r),
                b[1].min(y - r),
                b[2].max(x + r),
                b[3].max(y + r),
            ]
        },
    )
}

/// The specimen file `sf` (one disc set) without the discs `drop` selects (in the file's
/// units) and the bonds `cut` selects: an ORC rigid grain goes whole if one member goes or two
/// of its members are `cut` apart, an improved-ORC grain (same grain id) whole if one member
/// goes; bonds touching a dropped disc go too. Discs are renumbered in order.
fn carve(
    sf: &SpecimenFile,
    method: Method,
    drop: impl Fn(&[f64; 3]) -> bool,
    cut: impl Fn(&[f64; 3], &[f64; 3]) -> bool,
) -> SpecimenFile {
    let mut out = sf.clone();
    let Some(set) = sf.discs.first() else {
        return out;
    };
    let n = set.discs.len();
    let mut keep: Vec<bool> = set.discs.iter().map(|d| !drop(d)).collect();
    match method {
        Method::Orc => {
            for members in &sf.rigid_clumps {
                let m: Vec<usize> = members.iter().map(|&i| i as usize).collect();
                let split = m.iter().enumerate().any(|(k, &i)| {
                    m[k + 1..]
                        .iter()
                        .any(|&j| cut(&set.discs[i], &set.discs[j]))
                });
                if split || m.iter().any(|&i| !keep[i]) {
                    for &i in &m {
                        keep[i] = false;
                    }
                }
            }
        }
        Method::Improved => {
            if let Some(g) = &set.groups {
                let dropped: HashSet<u32> = (0..n).filter(|&i| !keep[i]).map(|i| g[i]).collect();
                for i in 0..n {
                    if dropped.contains(&g[i]) {
                        keep[i] = false;
                    }
                }
            }
        }
        Method::Traditional => {}
    }
    let mut new_index = vec![u32::MAX; n];
    let mut k = 0u32;
    for i in 0..n {
        if keep[i] {
            new_index[i] = k;
            k += 1;
        }
    }
    fn kept<T: Copy>(v: &[T], keep: &[bool]) -> Vec<T> {
        v.iter().zip(keep).filter(|p| *p.1).map(|p| *p.0).collect()
    }
    let o = &mut out.discs[0];
    o.discs = kept(&set.discs, &keep);
    o.groups = set.groups.as_deref().map(|g| kept(g, &keep));
    o.mass_factors = set.mass_factors.as_deref().map(|m| kept(m, &keep));
    out.rigid_clumps = sf
        .rigid_clumps
        .iter()
        .filter(|m| m.iter().all(|&i| keep[i as usize]))
        .map(|m| m.iter().map(|&i| new_index[i as usize]).collect())
        .collect();
    out.bonds = sf
        .bonds
        .iter()
        .map(|b| {
            let idx: Vec<usize> = (0..b.pairs.len())
                .filter(|&q| {
                    let [i, j] = b.pairs[q].map(|i| i as usize);
                    keep[i] && keep[j] && !cut(&set.discs[i], &set.discs[j])
                })
                .collect();
            let mut nb = b.clone();
            nb.pairs = idx
                .iter()
                .map(|&q| b.pairs[q].map(|i| new_index[i as usize]))
                .collect();
            nb.contact_offsets = b
                .contact_offsets
                .as_ref()
                .map(|o| idx.iter().map(|&q| o[q]).collect());
            nb
        })
        .filter(|b| !b.pairs.is_empty())
        .collect();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use dem_core::scene::schema::{BondListSpec, DiscSetSpec};

    fn square() -> SpecimenFile {
        // 5 × 5 grid of discs r = 0.5 at unit spacing over [0, 5]²; grain id = row.
        let mut discs = vec![];
        let mut groups = vec![];
        for j in 0..5 {
            for i in 0..5 {
                discs.push([0.5 + i as f64, 0.5 + j as f64, 0.5]);
                groups.push(j as u32);
            }
        }
        let pairs: Vec<[u32; 2]> = (0..24).map(|k| [k as u32, k as u32 + 1]).collect();
        SpecimenFile {
            schema: dem_core::scene::schema::SPECIMEN_SCHEMA.into(),
            description: String::new(),
            units: LengthUnit::M,
            discs: vec![DiscSetSpec {
                material: "specimen".into(),
                group: 0,
                velocity: [0.0; 2],
                omega: 0.0,
                random_speed: 0.0,
                fixed: false,
                discs,
                groups: Some(groups),
                mass_factors: None,
            }],
            clumps: vec![],
            rigid_clumps: vec![vec![0, 1], vec![12, 13]],
            bonds: vec![BondListSpec {
                bond_group: "grain_boundary".into(),
                pairs,
                contact_offsets: Some((0..24).map(|k| -(k as f64)).collect()),
            }],
        }
    }

    #[test]
    fn a_failed_generation_is_recorded_and_not_run_again() {
        let dir = std::env::temp_dir().join(format!("dem-failed-spec-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut p = SpecimenParams::new(
            crate::specimen::Method::Traditional,
            2e-3,
            2e-3,
            0.1e-3,
            0.15e-3,
            3100.0,
            430e9,
            214e6,
            1,
        );
        let default_steps = p.max_stage_steps;
        p.max_stage_steps = 3; // no stage reaches equilibrium in 3 steps
        let shape = Shape::Rectangle {
            width: 2e-3,
            height: 2e-3,
        };
        let file = dir.join("s.json");
        let first = prepare(&p, shape, &file, &mut |_| {})
            .unwrap_err()
            .to_string();
        let fp = failed_path(&file);
        assert_eq!(fp, dir.join("s.failed.json"));
        assert!(fp.exists(), "{first}");
        let t0 = std::time::Instant::now();
        let again = prepare(&p, shape, &file, &mut |_| {})
            .unwrap_err()
            .to_string();
        assert!(again.contains("recorded in"), "{again}");
        assert!(again.contains(&first), "{again} / {first}");
        assert!(t0.elapsed().as_secs_f64() < 1.0);
        // Other inputs are another specimen: generated, and the record of the failure goes.
        p.max_stage_steps = default_steps;
        let ok = prepare(&p, shape, &file, &mut |_| {}).unwrap();
        assert!(ok.discs > 0 && !ok.reused);
        assert!(!fp.exists());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn carving_keeps_centres_inside_and_consistent_links() {
        let sf = square();
        // Circle of diameter 5 about (2.5, 2.5): the four corner discs (distance 2.83) go.
        let t = carve_disc(&sf, 5.0, Method::Traditional);
        assert_eq!(t.discs[0].discs.len(), 21);
        assert_eq!(t.rigid_clumps.len(), 1, "clump {{0, 1}} loses disc 0");
        assert_eq!(t.rigid_clumps[0], vec![10, 11], "discs 12, 13 renumbered");
        let b = &t.bonds[0];
        assert_eq!(b.pairs.len(), b.contact_offsets.as_ref().unwrap().len());
        // Bonds touching discs 0, 4, 20, 24 go: (0,1), (3,4), (4,5), (19,20), (20,21), (23,24).
        assert_eq!(b.pairs.len(), 24 - 6);
        assert!(b.pairs.iter().flatten().all(|&i| i < 21));
        // ORC: clump {0, 1} goes whole.
        let o = carve_disc(&sf, 5.0, Method::Orc);
        assert_eq!(o.discs[0].discs.len(), 20);
        // Improved: rows 0 and 4 (grains holding a corner) go whole.
        let m = carve_disc(&sf, 5.0, Method::Improved);
        assert_eq!(m.discs[0].discs.len(), 15);
        assert!(m.discs[0]
            .groups
            .as_ref()
            .unwrap()
            .iter()
            .all(|&g| (1..=3).contains(&g)));
        // Shifted to the origin.
        let minx = m.discs[0]
            .discs
            .iter()
            .map(|d| d[0] - d[2])
            .fold(f64::INFINITY, f64::min);
        let miny = m.discs[0]
            .discs
            .iter()
            .map(|d| d[1] - d[2])
            .fold(f64::INFINITY, f64::min);
        assert_eq!((minx, miny), (0.0, 0.0));
    }

    #[test]
    fn notch_drops_the_slot_and_the_bonds_across_it() {
        // Grid over [0, 5]²: mid-line x = 2.5 (column 2), notch 2.5 deep, 1 wide: discs 2 and
        // 7 (rows 0, 1 of column 2) sit in the slot; disc 12 (y = 2.5) is at the tip, kept.
        let mut sf = square();
        sf.rigid_clumps.push(vec![5, 9]); // (0.5, 1.5)–(4.5, 1.5): spans the notch
        let t = carve_notch(&sf, 2.5, 1.0, Method::Traditional);
        assert_eq!(t.discs[0].discs.len(), 23);
        assert_eq!(
            t.discs[0].discs[2], sf.discs[0].discs[3],
            "renumbered, not moved"
        );
        // Bonds touching 2 or 7 go ((1,2), (2,3), (6,7), (7,8)), and the row wrap-arounds
        // (4,5) and (9,10) cross x = 2.5 at y = 1.0 and 2.0, below the tip; (14,15) crosses at
        // 3.0 and stays.
        let b = &t.bonds[0];
        assert_eq!(b.pairs.len(), 24 - 6);
        assert_eq!(b.pairs.len(), b.contact_offsets.as_ref().unwrap().len());
        let old = |i: u32| {
            if i >= 7 {
                i + 2
            } else if i >= 2 {
                i + 1
            } else {
                i
            }
        };
        let pairs: Vec<[u32; 2]> = b.pairs.iter().map(|p| p.map(old)).collect();
        assert!(!pairs.contains(&[4, 5]) && !pairs.contains(&[9, 10]));
        assert!(pairs.contains(&[14, 15]) && pairs.contains(&[11, 12]));
        // ORC: the clump {5, 9} across the notch goes whole; {0, 1} and {12, 13} stay.
        let o = carve_notch(&sf, 2.5, 1.0, Method::Orc);
        assert_eq!(o.discs[0].discs.len(), 21);
        assert_eq!(o.rigid_clumps.len(), 2);
        // Improved: rows 0 and 1 (grains holding a slot disc) go whole.
        let m = carve_notch(&sf, 2.5, 1.0, Method::Improved);
        assert_eq!(m.discs[0].discs.len(), 15);
        // A notch 0.4 deep ends below every centre and below where (4,5) crosses (y = 1.0):
        // nothing is cut.
        let shallow = carve_notch(&sf, 0.4, 1.0, Method::Traditional);
        assert_eq!(shallow.discs[0].discs.len(), 25);
        assert_eq!(shallow.bonds[0].pairs.len(), 24);
    }

    #[test]
    fn grains_below_cover_come_from_the_summary_and_only_those_still_in_the_file() {
        // Issue 20: a reused (or carved) specimen reports the grains below their cover target
        // that its generator's summary lists, less those carved away (grain ids = rows 0..4).
        let dir = std::env::temp_dir().join(format!("dem-below-cover-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("s.json");
        std::fs::write(&file, serde_json::to_string(&square()).unwrap()).unwrap();
        assert!(TestSpecimen::read(&file).unwrap().below_cover.is_empty());
        let g = |grain: u32| GrainCover {
            grain,
            cover: 0.8,
            target: 0.95,
            discs: 4,
            stop: clumpgen::fill::StopReason::NoRoom,
            max_discs: 9,
            r_min: 0.05e-3,
        };
        let summary = serde_json::json!({"templates": {"below_cover": [g(2), g(7)]}});
        std::fs::write(io::summary_path(&file), summary.to_string()).unwrap();
        let t = TestSpecimen::read(&file).unwrap();
        assert_eq!(t.below_cover, vec![g(2)]);
        // In the result JSON only when there are any.
        let v = serde_json::to_value(&t).unwrap();
        assert_eq!(v["below_cover"][0]["grain"], 2);
        std::fs::remove_dir_all(&dir).ok();
    }
}
