//! Grain outlines from GIS polygons: GeoJSON (the `geojson` crate: Polygon, MultiPolygon,
//! Feature, FeatureCollection) and WKT (the `wkt` crate: POLYGON, MULTIPOLYGON; one geometry
//! per file, or one per line; an EWKT `SRID=n;` prefix is read).
//!
//! * One grain per polygon; a MultiPolygon gives one grain per part. A GeoJSON feature's grain
//!   is named by its `id`, else its `name` property, else `feature-<index>` (0-based, as in
//!   `.features[i]`); parts of a multi-polygon feature add `-<part>`. WKT polygons are
//!   `polygon-<k>`, k counting the polygons of the file from 0.
//! * Units: `ReadOptions::units` is required (GIS files carry no length unit; RFC 7946 even
//!   makes GeoJSON longitude/latitude). A `crs` member (GeoJSON) or SRID (EWKT) naming a
//!   geographic CRS (EPSG codes 4000-4999, the geographic 2D range holding WGS 84 = 4326, ETRS89
//!   = 4258, NAD83 = 4269; OGC CRS84/CRS83/CRS27) is refused, naming the file: degrees are not
//!   lengths, project the polygons first. Without units, the error says when every coordinate
//!   lies within ±180/±90 (probably degrees).
//! * Rings: the outer ring is the outline; an open ring (first point ≠ last) is closed with a
//!   warning (the CSV reader takes open outlines too; the warning says the file breaks the
//!   GeoJSON/WKT rule); inner rings (holes) are warned with their area fraction (`geo`'s
//!   `Area`), and the template fills the outer ring. Validity (self-intersection, too few
//!   points, zero area) is the one of every outline ([`super::finish`]), per grain, naming the
//!   points by their index in the ring. A third coordinate (z) is ignored.

use geo::{Area, BoundingRect, Coord, LineString, MultiPolygon, Polygon};
use serde_json::Value;

use super::grains::{file_safe, FileGrains, Grain};
use super::text::RawOutline;
use super::{finish, ReadOptions};
use crate::error::{OutlineError, Pos};

/// A polygon's rings (outer first) in file coordinates.
type Rings = Vec<Vec<[f64; 2]>>;

/// A polygon as read, or why it is no polygon.
struct Poly {
    name: String,
    label: String,
    rings: Result<Rings, String>,
}

/// Is `name` (a GeoJSON `crs` name, `EPSG:4326`, a URN or URL) a geographic CRS?
pub fn is_geographic_crs(name: &str) -> bool {
    let u = name.to_ascii_uppercase();
    if ["CRS84", "CRS83", "CRS27"].iter().any(|c| u.contains(c)) {
        return true;
    }
    let digits: String = u
        .chars()
        .rev()
        .take_while(|c| c.is_ascii_digit())
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    matches!(digits.parse::<u32>(), Ok(4000..=4999))
}

/// The name of a GeoJSON `crs` member: `{"type": "name", "properties": {"name": ...}}`,
/// `{"type": "EPSG", "properties": {"code": 4326}}` or a plain string.
fn crs_name(v: &Value) -> Option<String> {
    match v {
        Value::String(s) => Some(s.clone()),
        Value::Object(o) => {
            let p = o.get("properties")?;
            if let Some(Value::String(s)) = p.get("name") {
                return Some(s.clone());
            }
            p.get("code").map(|c| format!("EPSG:{c}"))
        }
        _ => None,
    }
}

fn ring(ps: &[geojson::Position]) -> Result<Vec<[f64; 2]>, String> {
    ps.iter()
        .enumerate()
        .map(|(k, p)| {
            let s = p.as_slice();
            if s.len() < 2 {
                Err(format!("point {k} has {} coordinates, need 2", s.len()))
            } else {
                Ok([s[0], s[1]])
            }
        })
        .collect()
}

fn polygons_of(value: &geojson::GeometryValue) -> Result<Vec<Result<Rings, String>>, String> {
    use geojson::GeometryValue as G;
    let poly = |rings: &Vec<Vec<geojson::Position>>| rings.iter().map(|r| ring(r)).collect();
    match value {
        G::Polygon { coordinates } => Ok(vec![poly(coordinates)]),
        G::MultiPolygon { coordinates } => Ok(coordinates.iter().map(poly).collect()),
        other => Err(format!(
            "a {} is not a grain outline (expected Polygon or MultiPolygon)",
            other.type_name()
        )),
    }
}

/// Polygons of a feature (or a bare geometry, `feature` = `None`) named `name`/`label`.
fn push_polys(out: &mut Vec<Poly>, geometry: Option<&geojson::Geometry>, name: &str, label: &str) {
    let Some(g) = geometry else {
        out.push(Poly {
            name: name.to_string(),
            label: label.to_string(),
            rings: Err("no geometry".into()),
        });
        return;
    };
    match polygons_of(&g.value) {
        Err(e) => out.push(Poly {
            name: name.to_string(),
            label: label.to_string(),
            rings: Err(e),
        }),
        Ok(ps) if ps.len() == 1 => out.push(Poly {
            name: name.to_string(),
            label: label.to_string(),
            rings: ps.into_iter().next().expect("one"),
        }),
        Ok(ps) => {
            for (j, r) in ps.into_iter().enumerate() {
                out.push(Poly {
                    name: format!("{name}-{j}"),
                    label: format!("{label} part {j}"),
                    rings: r,
                });
            }
        }
    }
}

fn feature_name(f: &geojson::Feature, i: usize) -> (String, String) {
    let given = match &f.id {
        Some(geojson::feature::Id::String(s)) => Some(s.clone()),
        Some(geojson::feature::Id::Number(n)) => Some(n.to_string()),
        None => f
            .properties
            .as_ref()
            .and_then(|p| p.get("name"))
            .and_then(|v| match v {
                Value::String(s) => Some(s.clone()),
                Value::Number(n) => Some(n.to_string()),
                _ => None,
            }),
    };
    let fallback = format!("feature-{i}");
    match given {
        Some(g) => (file_safe(&g, &fallback), format!("feature {i} ({g:?})")),
        None => (fallback, format!("feature {i}")),
    }
}

fn parse_geojson(text: &str, file: &str) -> Result<(Vec<Poly>, Option<String>), OutlineError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let gj: geojson::GeoJson = serde_json::from_str(text).map_err(|e| OutlineError::Json {
        file: file.to_string(),
        line: e.line(),
        column: e.column(),
        reason: format!("bad GeoJSON: {e}"),
    })?;
    let crs_of =
        |m: &Option<geojson::JsonObject>| m.as_ref().and_then(|m| m.get("crs")).and_then(crs_name);
    let mut out = Vec::new();
    let crs = match &gj {
        geojson::GeoJson::Geometry(g) => {
            match polygons_of(&g.value) {
                Err(e) => {
                    return Err(OutlineError::Gis {
                        file: file.to_string(),
                        reason: e,
                    })
                }
                Ok(ps) => {
                    for (k, r) in ps.into_iter().enumerate() {
                        out.push(Poly {
                            name: format!("polygon-{k}"),
                            label: format!("polygon {k}"),
                            rings: r,
                        });
                    }
                }
            }
            crs_of(&g.foreign_members)
        }
        geojson::GeoJson::Feature(f) => {
            let (n, l) = feature_name(f, 0);
            push_polys(&mut out, f.geometry.as_ref(), &n, &l);
            crs_of(&f.foreign_members)
        }
        geojson::GeoJson::FeatureCollection(fc) => {
            for (i, f) in fc.features.iter().enumerate() {
                let (n, l) = feature_name(f, i);
                push_polys(&mut out, f.geometry.as_ref(), &n, &l);
            }
            crs_of(&fc.foreign_members)
        }
    };
    Ok((out, crs))
}

fn wkt_rings(p: &wkt::types::Polygon<f64>) -> Rings {
    p.rings()
        .iter()
        .map(|r| r.coords().iter().map(|c| [c.x, c.y]).collect())
        .collect()
}

/// One WKT geometry (with an optional `SRID=n;` prefix) into `out`.
fn wkt_geometry(
    s: &str,
    where_: &str,
    out: &mut Vec<Poly>,
    srid: &mut Option<String>,
) -> Result<(), String> {
    let s = s.trim();
    let body = match s.get(..5) {
        Some(p) if p.eq_ignore_ascii_case("SRID=") => {
            let (head, rest) = s
                .split_once(';')
                .ok_or_else(|| "SRID= without the ';' before the geometry".to_string())?;
            srid.get_or_insert_with(|| format!("EPSG:{}", &head[5..]));
            rest
        }
        _ => s,
    };
    let g: wkt::Wkt<f64> = body
        .parse()
        .map_err(|e: &str| bad_coordinate(body).unwrap_or_else(|| e.to_string()))?;
    let mut add = |rings: Rings| {
        let k = out.len();
        out.push(Poly {
            name: format!("polygon-{k}"),
            label: format!("polygon {k}{where_}"),
            rings: if rings.is_empty() {
                Err("an empty polygon".into())
            } else {
                Ok(rings)
            },
        });
    };
    match g {
        wkt::Wkt::Polygon(p) => add(wkt_rings(&p)),
        wkt::Wkt::MultiPolygon(m) => {
            for p in m.polygons() {
                add(wkt_rings(p));
            }
        }
        _ => return Err("not a grain outline (expected POLYGON or MULTIPOLYGON)".to_string()),
    }
    Ok(())
}

/// The first coordinate of a WKT geometry that is not a finite number, as a reason: the `wkt`
/// crate reads `nan` as the end of a list and says "Missing closing parenthesis"
/// (issue 48).
fn bad_coordinate(body: &str) -> Option<String> {
    let (_, coords) = body.split_once('(')?;
    coords
        .split(|c: char| c == '(' || c == ')' || c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty() && !t.eq_ignore_ascii_case("EMPTY"))
        .find(|t| !t.parse::<f64>().is_ok_and(f64::is_finite))
        .map(|t| format!("coordinate `{t}` is not a finite number"))
}

fn parse_wkt(text: &str, file: &str) -> Result<(Vec<Poly>, Option<String>), OutlineError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut out = Vec::new();
    let mut srid = None;
    // Geometries start on lines that begin with a letter (`POLYGON`, `SRID=`) and run to the
    // next such line: one geometry per line, or one over many lines. `#` lines are skipped.
    let mut chunks: Vec<(usize, String)> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        match chunks.last_mut() {
            Some(c) if !t.starts_with(|c: char| c.is_ascii_alphabetic()) => {
                c.1.push(' ');
                c.1.push_str(t);
            }
            _ => chunks.push((i + 1, t.to_string())),
        }
    }
    for (line, t) in chunks {
        let bad = |reason: String| OutlineError::Unparsable {
            file: file.to_string(),
            line,
            text: match t.char_indices().nth(80) {
                Some((k, _)) => format!("{}...", &t[..k]),
                None => t.clone(),
            },
            reason: format!("bad WKT: {reason}"),
        };
        let end = t.trim_end();
        if !(end.ends_with(')') || end.to_ascii_uppercase().ends_with("EMPTY")) {
            return Err(bad("a geometry ends with ')' or EMPTY".into()));
        }
        wkt_geometry(&t, &format!(" (line {line})"), &mut out, &mut srid).map_err(bad)?;
    }
    Ok((out, srid))
}

/// The grains of a GeoJSON (`wkt` false) or WKT file.
pub(crate) fn gis_grains(
    text: &str,
    wkt: bool,
    file: &str,
    stem: &str,
    sha256: &str,
    opts: &ReadOptions,
) -> Result<FileGrains, OutlineError> {
    let (polys, crs) = if wkt {
        parse_wkt(text, file)?
    } else {
        parse_geojson(text, file)?
    };
    let what_kind = if wkt { "WKT" } else { "GeoJSON" };
    if polys.is_empty() {
        return Err(OutlineError::NoGrain {
            file: file.to_string(),
            reason: format!("the {what_kind} holds no polygon"),
        });
    }
    if let Some(c) = crs.as_deref().filter(|c| is_geographic_crs(c)) {
        return Err(OutlineError::GisUnits {
            file: file.to_string(),
            reason: format!(
                "its CRS {c:?} is geographic: coordinates in degrees of longitude and latitude \
                 are not lengths; project the polygons to a metric CRS (e.g. UTM) first"
            ),
        });
    }
    let Some(units) = opts.units else {
        // Where every coordinate lies within ±180/±90, say that they look like degrees.
        let all: MultiPolygon<f64> = polys
            .iter()
            .filter_map(|p| p.rings.as_ref().ok())
            .filter_map(|r| r.first())
            .map(|r| Polygon::new(r.iter().map(|&[x, y]| Coord { x, y }).collect(), vec![]))
            .collect();
        let degrees = all.bounding_rect().is_some_and(|b| {
            b.min().x >= -180.0 && b.max().x <= 180.0 && b.min().y >= -90.0 && b.max().y <= 90.0
        });
        let hint = if degrees {
            ": every coordinate lies within ±180/±90, so they may be degrees of longitude and \
             latitude, which must be projected to a metric CRS first"
        } else {
            ""
        };
        return Err(OutlineError::GisUnits {
            file: file.to_string(),
            reason: format!(
                "{what_kind} coordinates carry no length unit: give --units m|mm|um{hint}"
            ),
        });
    };
    let grains = polys
        .into_iter()
        .map(|p| {
            let what = format!("{file}, {}", p.label);
            let outline = p
                .rings
                .map_err(|reason| OutlineError::Gis {
                    file: what.clone(),
                    reason,
                })
                .and_then(|rings| {
                    if rings.is_empty() {
                        return Err(OutlineError::Gis {
                            file: what.clone(),
                            reason: "an empty polygon".into(),
                        });
                    }
                    let mut warnings = Vec::new();
                    let outer = &rings[0];
                    for (k, q) in outer.iter().enumerate() {
                        if !(q[0].is_finite() && q[1].is_finite()) {
                            return Err(OutlineError::NonFinite {
                                file: what.clone(),
                                pos: Pos::Point(k),
                                text: format!("[{}, {}]", q[0], q[1]),
                            });
                        }
                    }
                    if outer.len() > 1 && outer.first() != outer.last() {
                        warnings.push(format!(
                            "{}: ring not closed (first point != last, against the {what_kind} \
                             rule): closed by joining them",
                            p.label
                        ));
                    }
                    if rings.len() > 1 {
                        let ls = |r: &Vec<[f64; 2]>| -> LineString<f64> {
                            r.iter().map(|&[x, y]| Coord { x, y }).collect()
                        };
                        let poly = Polygon::new(ls(outer), rings[1..].iter().map(ls).collect());
                        let outer_area = Polygon::new(ls(outer), vec![]).unsigned_area();
                        let holes = outer_area - poly.unsigned_area();
                        warnings.push(format!(
                            "{} has {} hole{} (inner rings, {:.2} % of the area inside its \
                             outer ring): the template fills the outer ring, so its mass \
                             includes them",
                            p.label,
                            rings.len() - 1,
                            if rings.len() == 2 { "" } else { "s" },
                            100.0 * holes / outer_area
                        ));
                    }
                    let n = outer.len();
                    let raw = RawOutline {
                        points: outer.clone(),
                        pos: (0..n).map(Pos::Point).collect(),
                        units: None,
                        metres_per_px: None,
                    };
                    finish(
                        &raw,
                        units,
                        &format!("{stem}/{}", p.name),
                        &what,
                        file,
                        sha256.to_string(),
                        opts,
                        warnings,
                    )
                })
                .map(|mut o| {
                    o.grain = Some(p.label.clone());
                    o
                });
            Grain {
                name: p.name,
                label: p.label,
                outline,
            }
        })
        .collect();
    Ok(FileGrains {
        grains,
        notes: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geographic_names() {
        for n in [
            "EPSG:4326",
            "urn:ogc:def:crs:OGC:1.3:CRS84",
            "urn:ogc:def:crs:EPSG::4258",
            "http://www.opengis.net/def/crs/EPSG/0/4269",
        ] {
            assert!(is_geographic_crs(n), "{n}");
        }
        for n in [
            "EPSG:32633",
            "urn:ogc:def:crs:EPSG::3857",
            "EPSG:2056",
            "local",
        ] {
            assert!(!is_geographic_crs(n), "{n}");
        }
    }

    /// Issue 48: a `nan` coordinate is named as such (before: "Missing
    /// closing parenthesis"); a well-formed polygon still reads.
    #[test]
    fn a_non_finite_wkt_coordinate_is_named() {
        for (text, token) in [
            ("POLYGON ((0 0, 1 0, nan 1, 0 0))", "nan"),
            ("POLYGON ((0 0, 1 0, 1 NaN, 0 0))", "NaN"),
        ] {
            let Err(e) = parse_wkt(text, "g.wkt") else {
                panic!("{text} was read");
            };
            let e = e.to_string();
            assert!(
                e.contains(&format!("coordinate `{token}` is not a finite number")),
                "{e}"
            );
            assert!(e.starts_with("g.wkt") && e.contains("line 1"), "{e}");
        }
        let (polys, _) = parse_wkt("POLYGON ((0 0, 1 0, 1 1, 0 0))", "g.wkt").unwrap();
        assert_eq!(polys.len(), 1);
    }
}
