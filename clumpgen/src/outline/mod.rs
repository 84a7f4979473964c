//! Reading, validating and normalizing grain outlines.
//!
//! Input formats: CSV / whitespace / tab text files of `x y` pairs (one per line, `#` comments
//! anywhere, an optional header line such as `x,y` before the first point, an optional
//! repeated closing point) and JSON `{"units": "mm", "points": [[x, y], ...]}` (chosen by a
//! `.json` extension). Text files declare units in a comment `units: m`, and a pixel size in
//! `metres_per_px: 1e-4`; JSON files in the `"units"` and `"metres_per_px"` keys. Units come from [`ReadOptions::units`] if given (it overrides the file), else
//! from the file (`# units: m` comment or JSON `"units"`), else millimetres.
//!
//! Multi-grain files ([`read_grains`]): binary masks and labelled images (PNG, TIFF; `raster`
//! module: one grain per 4-connected component or label value, outline along pixel edges) and
//! GIS polygons (GeoJSON, WKT; `gis` module: one grain per polygon). Each of their grains goes
//! through steps 2-7 below (`finish`) on its own, so a bad grain fails alone, named by
//! file and grain.
//!
//! Hand-written and `geo` code: `geo` (with `geo-types`, the common form of the `geojson` and
//! `wkt` crates) computes the bounding box of GIS files (the degrees check), the area of
//! their holes, and simplifies pixel outlines on request (Ramer-Douglas-Peucker). The hand-written [`crate::props::polygon_props`] stays for area, centroid and
//! polar moment J (geo has no J; its area and centroid agree to 1e-15 relative, tested in
//! `tests/geo_agreement.rs`, but sum in another order, which would change the last bits of
//! every template), and so does [`find_self_intersection`] (exact for the integer pixel
//! outlines; it names the two edges and the point, where geo's validation says only that a
//! ring intersects itself; both agree on the test shapes) and [`resample`] (equal arc steps;
//! geo's `Densify` only adds points). The pixel outline tracer is hand-written because it is
//! exact (area = pixel count) and imageproc's `find_contours` is not (pixel centres).
//!
//! Processing order, all in input units until step 7:
//! 1. parse (line-numbered errors for unparsable lines and non-finite numbers);
//! 2. drop consecutive exact duplicates (with a warning) and an exact repeated closing point
//!    (silently);
//! 3. require ≥ 3 distinct points;
//! 4. subtract the local origin, the bounding-box centre of the raw points (so UTM-sized
//!    coordinates keep their precision: subtracting nearby floats is exact, Sterbenz lemma);
//! 5. reject negligible area (|A| ≤ 1e-12 (w + h)², w×h the bounding box);
//! 6. reject self-intersection ([`find_self_intersection`]);
//! 7. make counter-clockwise, scale to metres, optionally [`resample`].

mod gis;
mod grains;
mod raster;
mod text;
mod validate;

use std::path::Path;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

pub use gis::is_geographic_crs;
pub use grains::{FileGrains, Grain, GrainOptions, MaskMode, MultiKind, MULTI_EXTENSIONS};
pub use raster::PINCH_CUT_PX;
pub use validate::{find_self_intersection, SelfHit};

use crate::error::{EdgeRef, OutlineError, Pos};
use crate::geom::bbox;
use crate::props::signed_area;
use crate::units::Units;
use text::RawOutline;

// (Here, not in `grains`, because it dispatches to `raster` and `gis`, which use `grains`.)
/// Read every grain of a multi-grain file. An error here concerns the whole file (unreadable,
/// not an image, an empty mask, degrees); a grain's own problem is in its [`Grain::outline`].
/// Files of no [`MultiKind`] are an error.
pub fn read_grains(
    path: &Path,
    opts: &ReadOptions,
    g: &GrainOptions,
) -> Result<FileGrains, OutlineError> {
    let file = path.display().to_string();
    let Some(kind) = MultiKind::of(path) else {
        return Err(OutlineError::BadOption {
            file,
            reason: format!(
                "not a multi-grain file (expected one of .{})",
                MULTI_EXTENSIONS.join(", .")
            ),
        });
    };
    let bytes = crate::io::read_input(path).map_err(|e| OutlineError::Io {
        file: file.clone(),
        source: e,
    })?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let sha = sha256_hex(&bytes);
    match kind {
        MultiKind::Image => raster::image_grains(&bytes, &file, &stem, &sha, opts, g),
        MultiKind::GeoJson | MultiKind::Wkt => {
            let text = String::from_utf8(bytes).map_err(|e| OutlineError::Io {
                file: file.clone(),
                source: std::io::Error::new(std::io::ErrorKind::InvalidData, e),
            })?;
            gis::gis_grains(&text, kind == MultiKind::Wkt, &file, &stem, &sha, opts)
        }
    }
}

/// Options of [`read_outline`] / [`parse_outline`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ReadOptions {
    /// Units of the file; overrides what the file declares. `None`: the file's declaration,
    /// else millimetres.
    pub units: Option<Units>,
    /// Resample the outline to this many points equally spaced along its perimeter.
    pub resample: Option<usize>,
}

/// A validated grain outline in SI units and a local frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outline {
    /// File stem, e.g. `"grain-007"`.
    pub name: String,
    /// The path as given.
    pub source: String,
    /// Hex SHA-256 of the file bytes.
    pub sha256: String,
    /// Units the file was read in.
    pub units: Units,
    /// Local origin in metres (bounding-box centre of the raw points), already subtracted from
    /// `points`: input point = (points + origin) / metres_per_unit.
    pub origin: [f64; 2],
    /// Vertices in metres, local frame, counter-clockwise, no repeated closing point, no
    /// consecutive duplicates.
    pub points: Vec<[f64; 2]>,
    /// Non-fatal remarks (dropped duplicates, overridden units; holes, a grain cut by the
    /// image border).
    pub warnings: Vec<String>,
    /// Which grain of a multi-grain file (image, GeoJSON, WKT) this is, e.g. `label 7`,
    /// `component 3`, `feature "g7"`; `None` for a one-outline file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grain: Option<String>,
}

/// The sizes, in metres, a grain outline's bounding box may span: 1 nm (below, a "grain" is a
/// few atoms) to 10 km (above, the file is in the wrong units; and the squares and products of
/// coordinates the area and inertia need would lose their digits or overflow far beyond).
/// Outside it an outline is refused with [`OutlineError::OutOfScale`] (issue 48: 1e200 mm
/// coordinates were a "degenerate outline" of area inf).
pub const SIZE_RANGE: [f64; 2] = [1e-9, 1e4];

/// Read an outline file (JSON if the extension is `.json`, case-insensitive; text otherwise).
pub fn read_outline(path: &Path, opts: &ReadOptions) -> Result<Outline, OutlineError> {
    let source = path.display().to_string();
    let bytes = crate::io::read_input(path).map_err(|e| OutlineError::Io {
        file: source.clone(),
        source: e,
    })?;
    let text = String::from_utf8(bytes.clone()).map_err(|e| OutlineError::Io {
        file: source.clone(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidData, e),
    })?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    parse_outline(&text, &name, &source, json, opts)
}

/// Parse outline text already in memory; `source` names it in errors, `json` picks the format.
/// `sha256` is that of the UTF-8 bytes of `text`.
pub fn parse_outline(
    text: &str,
    name: &str,
    source: &str,
    json: bool,
    opts: &ReadOptions,
) -> Result<Outline, OutlineError> {
    let raw = if json {
        text::parse_json(text)
    } else {
        text::parse_text(text)
    }
    .map_err(|e| e.with_file(source))?;
    let sha256 = sha256_hex(text.as_bytes());
    let mut warnings = Vec::new();
    let units = resolve_units(&raw, source, opts, &mut warnings)?;
    finish(&raw, units, name, source, source, sha256, opts, warnings)
}

/// Hex SHA-256 of `bytes`.
pub(crate) fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Steps 2-7 of the module docs on raw points in `units`: the outline of `name`. `what` names
/// the outline in errors (the file, or `file, label 7` for one grain of a multi-grain file);
/// `source` is the file as given.
#[allow(clippy::too_many_arguments)]
pub(crate) fn finish(
    raw: &RawOutline,
    units: Units,
    name: &str,
    what: &str,
    source: &str,
    sha256: String,
    opts: &ReadOptions,
    mut warnings: Vec<String>,
) -> Result<Outline, OutlineError> {
    let (pts, pos, idx) = drop_duplicates(raw, &mut warnings);

    let mut distinct = pts.clone();
    distinct.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    distinct.dedup();
    if distinct.len() < 3 {
        return Err(OutlineError::TooFewPoints {
            file: what.to_string(),
            distinct: distinct.len(),
        });
    }

    let (lo, hi) = bbox(&pts);
    let origin = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let mut local: Vec<[f64; 2]> = pts
        .iter()
        .map(|p| [p[0] - origin[0], p[1] - origin[1]])
        .collect();
    let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
    let size = w.max(h) * units.metres_per_unit();
    if !(SIZE_RANGE[0]..=SIZE_RANGE[1]).contains(&size) {
        return Err(OutlineError::OutOfScale {
            file: what.to_string(),
            size,
            width: w,
            height: h,
            units: units.name(),
            range: SIZE_RANGE,
        });
    }
    let area = signed_area(&local);
    if area.is_nan() || area.abs() <= 1e-12 * (w + h) * (w + h) {
        return Err(OutlineError::ZeroArea {
            file: what.to_string(),
            area,
            width: w,
            height: h,
            units: units.name(),
        });
    }
    if let Some(hit) = find_self_intersection(&local) {
        let n = local.len();
        let edge = |e: usize| {
            Box::new(EdgeRef {
                vertices: [idx[e], idx[(e + 1) % n]],
                pos: [pos[e], pos[(e + 1) % n]],
            })
        };
        return Err(OutlineError::SelfIntersection {
            file: what.to_string(),
            a: edge(hit.edge_a),
            b: edge(hit.edge_b),
            point: [hit.point[0] + origin[0], hit.point[1] + origin[1]],
            units: units.name(),
        });
    }
    let mut pos = pos;
    if area < 0.0 {
        local.reverse();
        pos.reverse();
    }
    let s = units.metres_per_unit();
    let mut points = Vec::with_capacity(local.len());
    for (p, ps) in local.iter().zip(&pos) {
        let q = [p[0] * s, p[1] * s];
        if !(q[0].is_finite() && q[1].is_finite()) {
            return Err(OutlineError::NonFinite {
                file: what.to_string(),
                pos: *ps,
                text: format!("({}, {}) {} x {s} m", p[0], p[1], units.name()),
            });
        }
        points.push(q);
    }
    let origin_m = [origin[0] * s, origin[1] * s];
    if let Some(n) = opts.resample {
        points = resample_checked(&points, n, what)?;
    }
    Ok(Outline {
        name: name.to_string(),
        source: source.to_string(),
        grain: None,
        sha256,
        units,
        origin: origin_m,
        points,
        warnings,
    })
}

fn resolve_units(
    raw: &RawOutline,
    source: &str,
    opts: &ReadOptions,
    warnings: &mut Vec<String>,
) -> Result<Units, OutlineError> {
    let declared_scale = raw.metres_per_px.map(|(v, _)| v);
    if let Some(u) = opts.units {
        if let Units::Px { metres_per_px } = u {
            if !(metres_per_px.is_finite() && metres_per_px > 0.0) {
                return Err(OutlineError::BadScale {
                    file: source.to_string(),
                    pos: None,
                    value: metres_per_px,
                });
            }
        }
        if let Some((text, p)) = &raw.units {
            // Report a differing declaration; compare by name only (px scales are not declared
            // by name).
            let same = Units::parse(text, declared_scale.or(Some(1.0)))
                .map(|d| d.name() == u.name())
                .unwrap_or(false);
            if !same {
                warnings.push(format!(
                    "file declares units {text:?} ({p}); read as {} as requested",
                    u.name()
                ));
            }
        }
        return Ok(u);
    }
    match &raw.units {
        Some((text, p)) => {
            let scale_pos = raw.metres_per_px.map(|(_, sp)| sp).unwrap_or(*p);
            Units::parse(text, declared_scale).map_err(|e| {
                let at = if matches!(e, OutlineError::BadScale { .. }) {
                    scale_pos
                } else {
                    *p
                };
                e.with_file(source).at(at)
            })
        }
        None => Ok(Units::Mm),
    }
}

/// Drop consecutive exact duplicates (warned) and an exact repeated closing point (silent).
/// Returns the kept points, their positions and their indices among the file's points.
fn drop_duplicates(
    raw: &RawOutline,
    warnings: &mut Vec<String>,
) -> (Vec<[f64; 2]>, Vec<Pos>, Vec<usize>) {
    let mut pts: Vec<[f64; 2]> = Vec::with_capacity(raw.points.len());
    let mut pos = Vec::with_capacity(raw.points.len());
    let mut idx = Vec::with_capacity(raw.points.len());
    let mut dropped: Vec<Pos> = Vec::new();
    for (k, (p, ps)) in raw.points.iter().zip(&raw.pos).enumerate() {
        if pts.last() == Some(p) {
            dropped.push(*ps);
        } else {
            pts.push(*p);
            pos.push(*ps);
            idx.push(k);
        }
    }
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
        pos.pop();
        idx.pop();
    }
    if !dropped.is_empty() {
        // "dropped 3 consecutive duplicate points (lines 17, 40, 41)"
        const SHOW: usize = 10;
        let nums: Vec<String> = dropped
            .iter()
            .take(SHOW)
            .map(|p| match p {
                Pos::Line(l) => l.to_string(),
                Pos::Point(k) => k.to_string(),
            })
            .collect();
        let kind = match (dropped[0], dropped.len()) {
            (Pos::Line(_), 1) => "line",
            (Pos::Line(_), _) => "lines",
            (Pos::Point(_), 1) => "point",
            (Pos::Point(_), _) => "points",
        };
        let more = if dropped.len() > SHOW {
            format!(", ... and {} more", dropped.len() - SHOW)
        } else {
            String::new()
        };
        warnings.push(format!(
            "dropped {} consecutive duplicate point{} ({kind} {}{more})",
            dropped.len(),
            if dropped.len() == 1 { "" } else { "s" },
            nums.join(", ")
        ));
    }
    (pts, pos, idx)
}

/// The most points [`ReadOptions::resample`] may ask for.
pub const MAX_RESAMPLE: usize = 1_000_000;

/// Why resampling is bounded by [`MAX_RESAMPLE`] (said by the reader and by `dem clump`).
pub const MAX_RESAMPLE_WHY: &str = "the work per grain grows with the points (the \
     self-intersection check, the fill's scanlines and its inside tests visit every edge: about \
     2 s of CPU per grain at 1,000,000 points in an optimised build, minutes at 10,000,000), \
     while more points change a smooth outline's area by less than 1e-12 (n equally spaced \
     points converge as 1/n²)";

fn resample_checked(
    points: &[[f64; 2]],
    n: usize,
    source: &str,
) -> Result<Vec<[f64; 2]>, OutlineError> {
    if n < 3 {
        return Err(OutlineError::BadOption {
            file: source.to_string(),
            reason: format!("resample to {n} points: need at least 3"),
        });
    }
    if n > MAX_RESAMPLE {
        return Err(OutlineError::BadOption {
            file: source.to_string(),
            reason: format!("resample to {n} points: at most {MAX_RESAMPLE}: {MAX_RESAMPLE_WHY}"),
        });
    }
    let r = resample(points, n);
    if let Some(hit) = find_self_intersection(&r) {
        return Err(OutlineError::BadOption {
            file: source.to_string(),
            reason: format!(
                "resampling to {n} points makes the outline intersect itself (resampled edges \
                 {} and {}); use more points",
                hit.edge_a, hit.edge_b
            ),
        });
    }
    if signed_area(&r) <= 0.0 {
        return Err(OutlineError::BadOption {
            file: source.to_string(),
            reason: format!("resampling to {n} points leaves no area; use more points"),
        });
    }
    Ok(r)
}

/// `n` points equally spaced along the perimeter of the closed polygon `points`, starting at
/// `points[0]` and keeping its orientation: output point k lies on the polygon at arc length
/// k·P/n from `points[0]` (P the perimeter). Ye & Xu (2010) resample each grain outline into
/// equally spaced points before filling it. Corners between samples are cut, so the area
/// converges to the polygon's as O(1/n²). Returns an empty vector for `n == 0` or no points,
/// and `n` copies of the point for a zero-length outline.
pub fn resample(points: &[[f64; 2]], n: usize) -> Vec<[f64; 2]> {
    let m = points.len();
    if n == 0 || m == 0 {
        return Vec::new();
    }
    let mut cum = Vec::with_capacity(m + 1);
    cum.push(0.0);
    for i in 0..m {
        let (a, b) = (points[i], points[(i + 1) % m]);
        cum.push(cum[i] + (b[0] - a[0]).hypot(b[1] - a[1]));
    }
    let total = cum[m];
    if total == 0.0 {
        return vec![points[0]; n];
    }
    let mut out = Vec::with_capacity(n);
    let mut e = 0;
    for k in 0..n {
        let s = total * k as f64 / n as f64;
        while e + 1 < m && cum[e + 1] <= s {
            e += 1;
        }
        let len = cum[e + 1] - cum[e];
        let (a, b) = (points[e], points[(e + 1) % m]);
        let t = if len > 0.0 { (s - cum[e]) / len } else { 0.0 };
        out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
    }
    out
}
