//! What `dem render` draws, read from a file: a checkpoint (`dem.checkpoint/1`), a
//! `last-good-state.json` (a bare solver state, no schema), a specimen file (`dem.specimen/1`)
//! or a clump template (`clumpgen.template/1`, or `/2` with a lattice), told apart by the file's
//! `schema` field. Every kind becomes one [`Picture`]: discs, bonds, walls, an outline, caption lines, in metres.

use crate::error::RenderError;
use crate::picture::{
    counts, grain_keys, short_name, sig, step_time, Bond, Disc, Kind, Picture, WallLine,
};
use clumpgen::template::Template;
use dem_core::bond::BondStatus;
use dem_core::scene::schema::{SpecimenFile, SPECIMEN_SCHEMA};
use dem_core::state::{State, FREE};
use serde::de::IgnoredAny;
use serde::Deserialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The kinds of file `dem render` reads, for messages.
pub const KINDS: &str = "a checkpoint (dem.checkpoint/1, ckpt-*.json), a last-good-state.json, \
                         a specimen file (dem.specimen/1), a clump template \
                         (clumpgen.template/1 or /2), a VTK snapshot (snap-*.vtp) or a series \
                         (snapshots.pvd)";

/// Reads `path` and turns it into a [`Picture`]; `outline` overrides a template's outline file.
/// Errors name the file and say why.
pub fn load(path: &Path, outline: Option<&Path>) -> Result<Picture, RenderError> {
    let file = path.display().to_string();
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("vtp"))
    {
        return crate::vtk::load_vtp(path, None);
    }
    let bytes = clumpgen::io::read_input(path).map_err(|e| RenderError::read(&file, e))?;
    if bytes.starts_with(&dem_core::checkpoint::MAGIC) {
        let c = dem_core::checkpoint::parse_bytes(&bytes, &file)?;
        return Ok(from_checkpoint(c, path));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        RenderError::read(
            &file,
            std::io::Error::new(std::io::ErrorKind::InvalidData, e),
        )
    })?;
    if text.trim_start().starts_with('<') {
        return Err(RenderError::file(
            &file,
            format!(
                "an XML file; dem render reads VTK snapshots by their name (snap-*.vtp, or a \
                 .pvd series), else {KINDS}"
            ),
        ));
    }
    /// Only the fields that tell the kinds apart (the rest is skipped, not stored).
    #[derive(Deserialize)]
    struct Peek {
        schema: Option<String>,
        discs: Option<IgnoredAny>,
        walls: Option<IgnoredAny>,
        step: Option<IgnoredAny>,
    }
    let peek: Peek = serde_json::from_str(&text).map_err(|e| {
        RenderError::file(
            &file,
            format!("not a JSON object ({e}); dem render reads {KINDS}"),
        )
    })?;
    let label = short_name(path);
    match peek.schema.as_deref() {
        Some(dem_core::checkpoint::SCHEMA) => {
            let c = dem_core::checkpoint::parse(&text, &file)?;
            Ok(from_checkpoint(c, path))
        }
        Some(SPECIMEN_SCHEMA) => {
            let s: SpecimenFile = serde_json::from_str(&text)
                .map_err(|e| RenderError::file(&file, format!("not a specimen file: {e}")))?;
            from_specimen(&s, path)
        }
        Some(clumpgen::template::SCHEMA | clumpgen::template::SCHEMA_LATTICE) => {
            let t = Template::from_json(&text, &file)?;
            Ok(from_template(&t, path, outline))
        }
        Some(dem_core::scene::schema::SCHEMA) => Err(RenderError::file(
            &file,
            format!(
                "a scene file (dem.scene/1): run it (`dem run {file}`) and render one of its \
                 checkpoints (ckpt-*.json in the output folder); dem render reads {KINDS}"
            ),
        )),
        Some(other) => Err(RenderError::file(
            &file,
            format!("schema {other:?} is not one dem render draws; it reads {KINDS}"),
        )),
        None if peek.discs.is_some() && peek.walls.is_some() && peek.step.is_some() => {
            let st: State = serde_json::from_str(&text).map_err(|e| {
                RenderError::file(
                    &file,
                    format!("not a solver state (last-good-state.json): {e}"),
                )
            })?;
            let mut p = from_state(&st, Kind::State);
            p.caption = vec![
                format!(
                    "{label}   {}   (last good state; no bonds)",
                    step_time(st.step, st.time)
                ),
                counts(&p),
            ];
            Ok(p)
        }
        None => Err(RenderError::file(
            &file,
            format!(
                "no `schema` field, and not a last-good-state.json either; dem render reads \
                 {KINDS}"
            ),
        )),
    }
}

/// A checkpoint (either format) as a picture: discs, bonds (broken ones where they broke).
fn from_checkpoint(c: dem_core::checkpoint::Checkpoint, path: &Path) -> Picture {
    let label = short_name(path);
    let w = &c.world;
    let mut p = from_state(&w.state, Kind::Checkpoint);
    if let Some(b) = &w.bonds {
        p.bond_groups = b.group_names();
        let at: HashMap<u32, [f64; 2]> = b
            .log()
            .events
            .iter()
            .map(|e| (e.bond, [e.x, e.y]))
            .collect();
        p.bonds = b
            .iter()
            .map(|v| Bond {
                i: v.i as usize,
                j: v.j as usize,
                group: v.group,
                intact: v.status == BondStatus::Intact,
                broke_at: at.get(&v.id).copied(),
                width: 2.0 * v.rbar,
            })
            .filter(|b| b.i < p.discs.len() && b.j < p.discs.len())
            .collect();
    }
    p.caption = vec![
        format!("{label}   {}", step_time(w.state.step, w.state.time)),
        counts(&p),
    ];
    p
}

/// Discs and walls of a solver state (no bonds, no caption).
fn from_state(st: &State, kind: Kind) -> Picture {
    let d = &st.discs;
    let keys = grain_keys(&d.body, &d.group, &d.id);
    let discs = (0..d.len())
        .map(|k| Disc {
            x: d.x[k],
            y: d.y[k],
            r: d.r[k],
            speed: d.vx[k].hypot(d.vy[k]),
            material: d.material[k],
            grain: keys[k],
        })
        .collect();
    let walls = st
        .walls
        .iter()
        .map(|w| WallLine {
            name: w.name.clone(),
            points: w.vertices().collect(),
        })
        .collect();
    Picture {
        kind,
        discs,
        bonds: Vec::new(),
        bond_groups: Vec::new(),
        materials: Vec::new(),
        walls,
        outline: None,
        centroid: None,
        clump_centroid: None,
        caption: Vec::new(),
        notes: Vec::new(),
    }
}

/// A specimen file: its disc sets (grain ids from `groups`), rigid clumps, bonds and any clump
/// placements (templates relative to the file).
fn from_specimen(s: &SpecimenFile, path: &Path) -> Result<Picture, RenderError> {
    let file = path.display().to_string();
    let u = s.units.metres();
    let mut materials: Vec<String> = Vec::new();
    let mut material_index = |name: &str| -> u16 {
        match materials.iter().position(|m| m == name) {
            Some(k) => k as u16,
            None => {
                materials.push(name.to_string());
                (materials.len() - 1) as u16
            }
        }
    };
    let (mut x, mut y, mut r, mut speed, mut mat, mut group) =
        (vec![], vec![], vec![], vec![], vec![], vec![]);
    for (k, set) in s.discs.iter().enumerate() {
        if let Some(g) = &set.groups {
            if g.len() != set.discs.len() {
                return Err(RenderError::Field {
                    file,
                    field: format!("discs[{k}].groups"),
                    reason: format!("{} entries for {} discs", g.len(), set.discs.len()),
                });
            }
        }
        let m = material_index(&set.material);
        let v = set.velocity[0].hypot(set.velocity[1]) * u;
        for (q, d) in set.discs.iter().enumerate() {
            x.push(d[0] * u);
            y.push(d[1] * u);
            r.push(d[2] * u);
            speed.push(v);
            mat.push(m);
            group.push(set.groups.as_ref().map_or(set.group, |g| g[q]));
        }
    }
    let n = x.len();
    let mut body = vec![FREE; n];
    for (c, members) in s.rigid_clumps.iter().enumerate() {
        for (q, &i) in members.iter().enumerate() {
            let slot = body.get_mut(i as usize).ok_or_else(|| RenderError::Field {
                file: file.clone(),
                field: format!("rigid_clumps[{c}][{q}]"),
                reason: format!("disc {i} does not exist (the file has {n})"),
            })?;
            *slot = c as u32;
        }
    }
    let id: Vec<u32> = (0..n as u32).collect();
    let keys = grain_keys(&body, &group, &id);
    let mut discs: Vec<Disc> = (0..n)
        .map(|k| Disc {
            x: x[k],
            y: y[k],
            r: r[k],
            speed: speed[k],
            material: mat[k],
            grain: keys[k],
        })
        .collect();
    // Clump placements: each placement is one grain.
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut cache: HashMap<String, Template> = HashMap::new();
    let mut placement = 0u64;
    for (k, set) in s.clumps.iter().enumerate() {
        if !cache.contains_key(&set.template) {
            let t = Template::load(&dir.join(&set.template)).map_err(|e| RenderError::Field {
                file: file.clone(),
                field: format!("clumps[{k}].template"),
                reason: e.to_string(),
            })?;
            cache.insert(set.template.clone(), t);
        }
        let t = &cache[&set.template];
        let m = material_index(&set.material);
        for p in &set.placements {
            let (sn, cs) = p.angle.sin_cos();
            let v = p.velocity[0].hypot(p.velocity[1]) * u;
            for d in &t.discs {
                discs.push(Disc {
                    x: p.x * u + cs * d.x - sn * d.y,
                    y: p.y * u + sn * d.x + cs * d.y,
                    r: d.r,
                    speed: v,
                    material: m,
                    grain: (3 << 40) | placement,
                });
            }
            placement += 1;
        }
    }
    let mut bond_groups = Vec::new();
    let mut bonds = Vec::new();
    for (k, list) in s.bonds.iter().enumerate() {
        let g = match bond_groups.iter().position(|b| b == &list.bond_group) {
            Some(g) => g,
            None => {
                bond_groups.push(list.bond_group.clone());
                bond_groups.len() - 1
            }
        };
        for (q, &[a, b]) in list.pairs.iter().enumerate() {
            if a as usize >= n || b as usize >= n {
                return Err(RenderError::Field {
                    file,
                    field: format!("bonds[{k}].pairs[{q}]"),
                    reason: format!("disc {} does not exist (the file has {n})", a.max(b)),
                });
            }
            bonds.push(Bond {
                i: a as usize,
                j: b as usize,
                group: g as u16,
                intact: true,
                broke_at: None,
                width: 0.0,
            });
        }
    }
    let mut p = Picture {
        kind: Kind::Specimen,
        discs,
        bonds,
        bond_groups,
        materials,
        walls: Vec::new(),
        outline: None,
        centroid: None,
        clump_centroid: None,
        caption: Vec::new(),
        notes: Vec::new(),
    };
    let mut first = short_name(path);
    if !s.description.is_empty() {
        first += &format!(": {}", s.description);
    }
    p.caption = vec![first, counts(&p)];
    Ok(p)
}

/// A template: its discs (each its own colour), the grain outline read back from the file the
/// template names (or `outline`), the grain centroid and, where it differs, the clump's; a
/// lattice template's links as bonds (drawn with `--bonds`; `--color group` colours them by
/// direction: d0, d60, d120).
fn from_template(t: &Template, path: &Path, outline: Option<&Path>) -> Picture {
    let discs = t
        .discs
        .iter()
        .enumerate()
        .map(|(k, d)| Disc {
            x: d.x,
            y: d.y,
            r: d.r,
            speed: 0.0,
            material: 0,
            grain: k as u64,
        })
        .collect();
    let mut notes = Vec::new();
    let drawn = match template_outline(t, path, outline) {
        Ok((pts, note)) => {
            notes.extend(note);
            Some(pts)
        }
        Err(e) => {
            notes.push(format!("{e}; drawn without the outline"));
            None
        }
    };
    let (bonds, bond_groups) = match &t.lattice {
        Some(l) => {
            let width = 2.0 * 0.5 * l.spacing * l.node_radius_fraction;
            let bonds = l
                .links
                .iter()
                .filter(|k| k.i < t.discs.len() && k.j < t.discs.len())
                .map(|k| Bond {
                    i: k.i,
                    j: k.j,
                    group: match k.kind {
                        clumpgen::lattice::LinkKind::D0 => 0,
                        clumpgen::lattice::LinkKind::D60 => 1,
                        clumpgen::lattice::LinkKind::D120 => 2,
                    },
                    intact: true,
                    broke_at: None,
                    width,
                })
                .collect();
            let groups = ["link d0", "link d60", "link d120"]
                .map(String::from)
                .to_vec();
            (bonds, groups)
        }
        None => (Vec::new(), Vec::new()),
    };
    let c = t.achieved.centroid;
    let off = c[0].hypot(c[1]) > 1e-3 * t.shape.r_eq;
    let mut caption = vec![format!(
        "{} ({}): {} discs, cover {:.1} %, R_eq {} mm",
        t.id,
        t.method.name(),
        t.discs.len(),
        100.0 * t.cover.value,
        sig(t.shape.r_eq * 1e3)
    )];
    let mut second = format!("{}; + grain centroid", short_name(path));
    if off {
        second += ", x clump mass centre";
    }
    if drawn.is_none() {
        second += "; outline not found";
    }
    caption.push(second);
    Picture {
        kind: Kind::Template,
        discs,
        bonds,
        bond_groups,
        materials: Vec::new(),
        walls: Vec::new(),
        outline: drawn,
        centroid: Some([0.0, 0.0]),
        clump_centroid: off.then_some(c),
        caption,
        notes,
    }
}

/// The grain outline of template `t` in its centroid frame (metres): the outline file it names
/// (as given, else beside the template), or `over`. The file's units are not needed: the
/// polygon is scaled to the template's area (a check when the units are known). Returns the
/// points and a note when the file differs from the one the template was made from.
fn template_outline(
    t: &Template,
    path: &Path,
    over: Option<&Path>,
) -> Result<(Vec<[f64; 2]>, Option<String>), RenderError> {
    let tfile = path.display().to_string();
    let src = PathBuf::from(&t.source.file);
    let candidates: Vec<PathBuf> = match over {
        Some(o) => vec![o.to_path_buf()],
        None => {
            let dir = path.parent().unwrap_or(Path::new("."));
            let mut c = vec![src.clone()];
            if src.is_relative() {
                c.push(dir.join(&src));
            }
            if let Some(name) = src.file_name() {
                c.push(dir.join(name));
            }
            c
        }
    };
    let Some(found) = candidates.iter().find(|p| p.is_file()) else {
        let looked: Vec<String> = candidates.iter().map(|p| p.display().to_string()).collect();
        return Err(RenderError::file(
            &tfile,
            format!(
                "the grain outline {} is not found (looked at {}); give it with --outline FILE",
                t.source.file,
                looked.join(", ")
            ),
        ));
    };
    let opts = clumpgen::ReadOptions {
        units: Some(clumpgen::Units::M),
        resample: None,
    };
    let o = match (clumpgen::outline::MultiKind::of(found), &t.source.grain) {
        // A grain of an image or GIS file: that grain (any pixel size or units will do).
        (Some(kind), Some(grain)) => {
            let units = match kind {
                clumpgen::outline::MultiKind::Image => clumpgen::Units::Px { metres_per_px: 1.0 },
                _ => clumpgen::Units::M,
            };
            let mask = if grain.starts_with("component") {
                clumpgen::outline::MaskMode::Binary
            } else {
                clumpgen::outline::MaskMode::Labels
            };
            let g = clumpgen::outline::GrainOptions {
                mask,
                invert: false,
                min_pixels: 0,
                simplify: 0.0,
            };
            let all = clumpgen::outline::read_grains(
                found,
                &clumpgen::ReadOptions {
                    units: Some(units),
                    resample: None,
                },
                &g,
            )?;
            all.grains
                .into_iter()
                .find(|x| &x.label == grain)
                .ok_or_else(|| RenderError::file(found.display(), format!("no grain {grain}")))?
                .outline?
        }
        _ => clumpgen::read_outline(found, &opts)?,
    };
    let props = clumpgen::polygon_props(&o.points);
    if !(props.area > 0.0 && t.shape.area > 0.0) {
        return Err(RenderError::file(
            found.display(),
            "the outline has no area to scale to the template's",
        ));
    }
    let f = (t.shape.area / props.area).sqrt();
    let pts = o
        .points
        .iter()
        .map(|q| {
            [
                (q[0] - props.centroid[0]) * f,
                (q[1] - props.centroid[1]) * f,
            ]
        })
        .collect();
    let mut note = None;
    let expected = clumpgen::Units::parse(&t.source.units, None)
        .ok()
        .map(|u| u.metres_per_unit());
    if let Some(e) = expected {
        if (f / e - 1.0).abs() > 1e-6 {
            note = Some(format!(
                "{}: the outline's area does not match template {tfile} (scale {f:e} m per unit, \
                 the template says {} = {e:e}); drawn scaled to the template's area",
                found.display(),
                t.source.units
            ));
        }
    }
    if note.is_none() && o.sha256 != t.source.sha256 {
        note = Some(format!(
            "{}: not the file template {tfile} was made from (its SHA-256 differs)",
            found.display()
        ));
    }
    Ok((pts, note))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lattice template's links become the picture's bonds, grouped by direction, between
    /// the right discs; a fill template has none.
    #[test]
    fn lattice_links_are_drawn_as_bonds() {
        use clumpgen::clump::{make_template, LatticeParams, Length};
        use clumpgen::outline::{parse_outline, ReadOptions};
        use clumpgen::template::Method;
        let csv = "# units: mm\nx,y\n0,0\n3,0\n3,2\n0,2\n";
        let o = parse_outline(csv, "box", "box.csv", false, &ReadOptions::default()).unwrap();
        let p = clumpgen::ClumpParams {
            method: Method::Lattice,
            lattice: Some(LatticeParams {
                spacing: Length::Metres(0.5e-3),
                node_radius: 1.0,
            }),
            ..clumpgen::ClumpParams::default()
        };
        let t = make_template(&o, &p).unwrap();
        let links = &t.lattice.as_ref().unwrap().links;
        let pic = from_template(&t, Path::new("box.json"), None);
        assert!(!links.is_empty());
        assert_eq!(pic.bonds.len(), links.len());
        assert_eq!(pic.bond_groups, ["link d0", "link d60", "link d120"]);
        for (b, l) in pic.bonds.iter().zip(links) {
            let (di, dj) = (&t.discs[b.i], &t.discs[b.j]);
            assert_eq!((b.i, b.j), (l.i, l.j));
            assert!(((dj.x - di.x).hypot(dj.y - di.y) - 0.5e-3).abs() < 1e-12);
        }
        assert!((0..3).all(|g| pic.bonds.iter().any(|b| b.group == g)));
        let fill = make_template(&o, &clumpgen::ClumpParams::default()).unwrap();
        assert!(from_template(&fill, Path::new("f.json"), None)
            .bonds
            .is_empty());
    }

    #[test]
    fn captions_format_steps_times_and_figures() {
        assert_eq!(
            step_time(13_884_535, 0.0101),
            "step 13,884,535   t = 10.1 ms"
        );
        assert_eq!(step_time(999, 2.5e-5), "step 999   t = 25 us");
        assert_eq!(step_time(1000, 0.0), "step 1,000   t = 0 s");
        assert_eq!(sig(0.43125), "0.4313");
        assert_eq!(sig(1234.4), "1234");
        assert_eq!(sig(12.5), "12.5");
        assert_eq!(sig(f64::NAN), "NaN");
    }

    #[test]
    fn grains_are_clumps_then_groups_then_discs() {
        // A clump (body 0) and two free discs: groups that vary tell the free discs' grains.
        let k = grain_keys(&[0, 0, FREE, FREE], &[7, 7, 3, 3], &[0, 1, 2, 3]);
        assert_eq!(k[0], k[1]);
        assert_eq!(k[2], k[3]);
        assert_ne!(k[1], k[2]);
        // All groups equal: each free disc is its own grain.
        let k = grain_keys(&[FREE, FREE], &[0, 0], &[0, 1]);
        assert_ne!(k[0], k[1]);
    }
}
