//! Reading back the VTK files `dem run` writes (dem-core's `output::vtk`): a disc snapshot
//! `snap-*.vtp` (points, point arrays `radius`, `velocity`, `id`, `body`, `group`, `material`;
//! bonds as line cells with `bond_state`, `bond_group`), the walls beside it (`walls-*.vtp`,
//! one line cell per wall) and the `snapshots.pvd` collection, in either encoding the writer
//! has (`outputs.vtk_format`): ASCII, or binary in VTK's appended base64 layout (inline
//! `format="binary"` base64 arrays are read too). A small hand parser; compressed, raw-binary
//! or other VTK flavours are refused with a message.

use crate::error::RenderError;
use crate::picture::{
    counts, grain_keys, short_name, step_time, Bond, Disc, Kind, Picture, WallLine,
};
use base64::Engine as _;
use dem_core::state::FREE;
use std::path::{Path, PathBuf};

/// [`RenderError::File`] for `$file` with a `format!` reason.
macro_rules! ferr {
    ($file:expr, $($arg:tt)*) => {
        RenderError::file(&$file, format!($($arg)*))
    };
}

/// [`RenderError::Array`] for the array `$at` ([`ArrayAt`]) with a `format!` reason.
macro_rules! aerr {
    ($at:expr, $($arg:tt)*) => {
        $at.err(format!($($arg)*))
    };
}

/// Which `<DataArray>` of which file, for messages.
struct ArrayAt<'a> {
    file: &'a str,
    name: &'a str,
    section: &'a str,
}

impl ArrayAt<'_> {
    fn err(&self, reason: String) -> RenderError {
        RenderError::Array {
            file: self.file.to_string(),
            name: self.name.to_string(),
            section: self.section.to_string(),
            reason,
        }
    }
}

/// One `<DataArray>`: its section (`PointData`, `CellData`, `Points`, `Lines`, …), name,
/// components and values (as text tokens are parsed to f64: ids up to 2^53 stay exact).
struct Array {
    section: String,
    name: String,
    comps: usize,
    values: Vec<f64>,
}

/// The value of attribute `key` in the tag text `tag` (`key="value"`).
fn attr<'a>(tag: &'a str, key: &str) -> Option<&'a str> {
    let pat = format!(" {key}=\"");
    let i = tag.find(&pat)? + pat.len();
    let rest = &tag[i..];
    rest.find('"').map(|j| &rest[..j])
}

/// A parsed `.vtp`: its piece's counts and its arrays.
struct PolyData {
    points: usize,
    lines: usize,
    arrays: Vec<Array>,
}

impl PolyData {
    fn get(&self, section: &str, name: &str) -> Option<&Array> {
        self.arrays
            .iter()
            .find(|a| a.section == section && a.name == name)
    }
}

/// Parses the ASCII PolyData in `text` (from `file`, for messages).
fn parse_polydata(text: &str, file: &str) -> Result<PolyData, RenderError> {
    let head = text
        .find("<VTKFile")
        .map(|i| &text[i..i + text[i..].find('>').unwrap_or(text.len() - i)])
        .ok_or_else(|| ferr!(file, "not a VTK XML file (no <VTKFile> element)"))?;
    match attr(head, "type") {
        Some("PolyData") => {}
        Some(other) => {
            return Err(ferr!(
                file,
                "VTK type {other:?}; dem render reads the PolyData snapshots (snap-*.vtp) \
                 dem run writes"
            ))
        }
        None => return Err(ferr!(file, "<VTKFile> has no type attribute")),
    }
    if !text.contains("</VTKFile>") {
        return Err(ferr!(file, "truncated (no closing </VTKFile>)"));
    }
    if attr(head, "compressor").is_some() {
        return Err(ferr!(
            file,
            "compressed VTK data; dem render reads the uncompressed ASCII or base64 \
             snapshots dem run writes"
        ));
    }
    let header = match attr(head, "header_type").unwrap_or("UInt32") {
        "UInt32" => 4,
        "UInt64" => 8,
        h => return Err(ferr!(file, "<VTKFile> header_type={h:?}")),
    };
    let (arrays_end, appended) = appended_data(text, file)?;
    let piece = text
        .find("<Piece")
        .map(|i| &text[i..i + text[i..].find('>').unwrap_or(0)])
        .ok_or_else(|| ferr!(file, "no <Piece> element"))?;
    let count = |key: &str| -> Result<usize, RenderError> {
        match attr(piece, key) {
            None => Ok(0),
            Some(v) => v
                .trim()
                .parse()
                .map_err(|e| ferr!(file, "<Piece> {key}={v:?}: {e}")),
        }
    };
    let points = count("NumberOfPoints")?;
    let lines = count("NumberOfLines")?;
    for key in ["NumberOfVerts", "NumberOfStrips", "NumberOfPolys"] {
        if count(key)? != 0 {
            return Err(ferr!(
                file,
                "<Piece> {key} is not 0; dem render reads the disc and wall snapshots \
                 dem run writes (points and lines only)"
            ));
        }
    }
    let sections = [
        "<PointData",
        "<CellData",
        "<Points",
        "<Lines",
        "<Verts",
        "<Polys",
        "<Strips",
    ];
    let mut arrays = Vec::new();
    let mut pos = 0;
    while let Some(i) = text[pos..arrays_end].find("<DataArray") {
        let start = pos + i;
        let section = sections
            .iter()
            .filter_map(|s| text[..start].rfind(s).map(|k| (k, &s[1..])))
            .max_by_key(|(k, _)| *k)
            .map(|(_, s)| s.to_string())
            .unwrap_or_default();
        let tag_end = text[start..]
            .find('>')
            .map(|k| start + k)
            .ok_or_else(|| ferr!(file, "truncated inside a <DataArray> tag"))?;
        let tag = &text[start..tag_end];
        let name = attr(tag, "Name").unwrap_or("").to_string();
        let what = ArrayAt {
            file,
            name: &name,
            section: &section,
        };
        let format = attr(tag, "format").ok_or_else(|| aerr!(what, "no format attribute"))?;
        let comps = match attr(tag, "NumberOfComponents") {
            None => 1,
            Some(c) => c
                .parse::<usize>()
                .ok()
                .filter(|&c| c >= 1)
                .ok_or_else(|| aerr!(what, "NumberOfComponents={c:?}"))?,
        };
        let body_end = if tag.ends_with('/') {
            tag_end
        } else {
            text[tag_end..]
                .find("</DataArray>")
                .map(|k| tag_end + k)
                .ok_or_else(|| aerr!(what, "truncated (no closing </DataArray>)"))?
        };
        let ty = attr(tag, "type").unwrap_or("");
        let body = text.get(tag_end + 1..body_end).unwrap_or("");
        let values = match format {
            "ascii" => body
                .split_ascii_whitespace()
                .enumerate()
                .map(|(k, t)| {
                    t.parse::<f64>()
                        .map_err(|_| aerr!(what, "value {k} is {t:?}, not a number"))
                })
                .collect::<Result<Vec<f64>, RenderError>>()?,
            "binary" => {
                let bytes = decode_run(body.trim().as_bytes(), header, &what)?;
                binary_values(&bytes, ty, &what)?
            }
            "appended" => {
                let data = appended
                    .ok_or_else(|| aerr!(what, "format \"appended\" but no <AppendedData>"))?;
                let offset: usize = attr(tag, "offset")
                    .and_then(|o| o.trim().parse().ok())
                    .ok_or_else(|| aerr!(what, "appended array without a valid offset"))?;
                let run = data
                    .get(offset..)
                    .filter(|r| !r.is_empty())
                    .ok_or_else(|| {
                        aerr!(
                            what,
                            "offset {offset} is past the appended data ({} characters)",
                            data.len()
                        )
                    })?;
                let bytes = decode_run(run, header, &what)?;
                binary_values(&bytes, ty, &what)?
            }
            f => {
                return Err(aerr!(
                    what,
                    "format {f:?}; dem render reads ASCII, base64 binary and appended \
                     base64 VTK arrays"
                ))
            }
        };
        if values.len() % comps != 0 {
            return Err(aerr!(
                what,
                "{} values are not whole tuples of {comps}",
                values.len()
            ));
        }
        arrays.push(Array {
            section,
            name,
            comps,
            values,
        });
        pos = body_end;
    }
    Ok(PolyData {
        points,
        lines,
        arrays,
    })
}

/// Where the `<DataArray>` elements end (the start of `<AppendedData>`, else the text's end)
/// and the appended base64 text after its `_` marker, if the file has one.
fn appended_data<'a>(text: &'a str, file: &str) -> Result<(usize, Option<&'a [u8]>), RenderError> {
    let Some(start) = text.find("<AppendedData") else {
        return Ok((text.len(), None));
    };
    let tag_end = text[start..]
        .find('>')
        .map(|k| start + k)
        .ok_or_else(|| ferr!(file, "truncated inside the <AppendedData> tag"))?;
    match attr(&text[start..tag_end], "encoding") {
        Some("base64") => {}
        e => {
            return Err(ferr!(
                file,
                "<AppendedData> encoding {e:?}; dem render reads the base64 appended data \
                 dem run writes, not raw"
            ))
        }
    }
    let end = text[tag_end..]
        .find("</AppendedData>")
        .map(|k| tag_end + k)
        .ok_or_else(|| ferr!(file, "truncated (no closing </AppendedData>)"))?;
    let body = text[tag_end + 1..end].trim();
    let data = body
        .strip_prefix('_')
        .ok_or_else(|| ferr!(file, "<AppendedData> does not start with the `_` marker"))?;
    Ok((start, Some(data.as_bytes())))
}

/// Decodes one base64 run that starts with its byte count (`header` bytes, little-endian) and
/// returns the data bytes after it. `b64` may run on past the run (appended data).
fn decode_run(b64: &[u8], header: usize, what: &ArrayAt) -> Result<Vec<u8>, RenderError> {
    let engine = &base64::engine::general_purpose::STANDARD;
    let chars = |bytes: usize| bytes.div_ceil(3) * 4;
    let bad = |e: base64::DecodeError| aerr!(what, "bad base64 data: {e}");
    let head = b64
        .get(..chars(header))
        .ok_or_else(|| aerr!(what, "base64 data ends inside its byte count"))?;
    let head = engine.decode(head).map_err(bad)?;
    let mut count = [0u8; 8];
    count[..header].copy_from_slice(&head[..header]);
    let count = u64::from_le_bytes(count);
    let n = usize::try_from(count)
        .ok()
        .filter(|&n| n <= b64.len())
        .ok_or_else(|| aerr!(what, "byte count {count} is larger than the data"))?;
    let run = b64.get(..chars(header + n)).ok_or_else(|| {
        aerr!(
            what,
            "the data ends before its {n} bytes (truncated base64)"
        )
    })?;
    let mut bytes = engine.decode(run).map_err(bad)?;
    bytes.drain(..header);
    bytes.truncate(n);
    Ok(bytes)
}

/// Little-endian values of VTK type `ty` as f64 (integers up to 2^53 exactly).
fn binary_values(bytes: &[u8], ty: &str, what: &ArrayAt) -> Result<Vec<f64>, RenderError> {
    macro_rules! each {
        ($t:ty) => {
            bytes
                .chunks_exact(std::mem::size_of::<$t>())
                .map(|c| <$t>::from_le_bytes(c.try_into().expect("chunk size")) as f64)
                .collect()
        };
    }
    let size = match ty {
        "Int8" | "UInt8" => 1,
        "Int16" | "UInt16" => 2,
        "Int32" | "UInt32" | "Float32" => 4,
        "Int64" | "UInt64" | "Float64" => 8,
        t => return Err(aerr!(what, "VTK type {t:?} is not read")),
    };
    if !bytes.len().is_multiple_of(size) {
        return Err(aerr!(
            what,
            "{} bytes are not whole {ty} values",
            bytes.len()
        ));
    }
    Ok(match ty {
        "Int8" => each!(i8),
        "UInt8" => each!(u8),
        "Int16" => each!(i16),
        "UInt16" => each!(u16),
        "Int32" => each!(i32),
        "UInt32" => each!(u32),
        "Float32" => each!(f32),
        "Int64" => each!(i64),
        "UInt64" => each!(u64),
        _ => each!(f64),
    })
}

/// An array of `section` with `n` tuples of `comps` (the count checked), or `None` if absent.
fn sized<'a>(
    pd: &'a PolyData,
    file: &str,
    section: &str,
    name: &str,
    comps: usize,
    n: usize,
) -> Result<Option<&'a [f64]>, RenderError> {
    let Some(a) = pd.get(section, name) else {
        return Ok(None);
    };
    if a.comps != comps || a.values.len() != n * comps {
        return Err(ferr!(
            file,
            "array {name:?} ({section}) has {} values in tuples of {}; expected {n} \
             tuples of {comps}",
            a.values.len(),
            a.comps
        ));
    }
    Ok(Some(&a.values))
}

/// Line cells as index lists (connectivity split at the offsets), checked against `points`.
fn line_cells(pd: &PolyData, file: &str) -> Result<Vec<Vec<usize>>, RenderError> {
    if pd.lines == 0 {
        return Ok(Vec::new());
    }
    let missing = |n: &str| ferr!(file, "{} lines but no {n:?} array in <Lines>", pd.lines);
    let conn = pd
        .get("Lines", "connectivity")
        .ok_or_else(|| missing("connectivity"))?;
    let offs = pd
        .get("Lines", "offsets")
        .ok_or_else(|| missing("offsets"))?;
    if offs.values.len() != pd.lines {
        return Err(ferr!(
            file,
            "{} line offsets for {} lines",
            offs.values.len(),
            pd.lines
        ));
    }
    let mut cells = Vec::with_capacity(pd.lines);
    let mut from = 0usize;
    for (k, &end) in offs.values.iter().enumerate() {
        let end = end as usize;
        if end < from || end > conn.values.len() {
            return Err(ferr!(
                file,
                "line {k}: offset {end} is outside the connectivity (0..={})",
                conn.values.len()
            ));
        }
        let cell: Vec<usize> = conn.values[from..end].iter().map(|&v| v as usize).collect();
        if let Some(&bad) = cell.iter().find(|&&v| v >= pd.points) {
            return Err(ferr!(
                file,
                "line {k} names point {bad}; the file has {} points",
                pd.points
            ));
        }
        cells.push(cell);
        from = end;
    }
    Ok(cells)
}

/// The step of a `snap-000000100.vtp` name.
fn step_of(path: &Path) -> Option<u64> {
    let name = path.file_name()?.to_str()?;
    name.strip_prefix("snap-")?
        .strip_suffix(".vtp")?
        .parse()
        .ok()
}

/// The time of `path` as `snapshots.pvd` beside it lists it, if it does.
fn time_beside(path: &Path) -> Option<f64> {
    let pvd = path.parent()?.join("snapshots.pvd");
    let name = path.file_name()?.to_str()?;
    read_pvd(&pvd)
        .ok()?
        .into_iter()
        .find(|(_, f)| f.file_name().and_then(|n| n.to_str()) == Some(name))
        .map(|(t, _)| t)
}

/// Reads a disc snapshot `snap-*.vtp` (with `walls-*.vtp` beside it when present); `time`
/// (s) from the collection, else looked up in `snapshots.pvd` beside the file.
pub fn load_vtp(path: &Path, time: Option<f64>) -> Result<Picture, RenderError> {
    let file = path.display().to_string();
    let text = clumpgen::io::read_input_string(path).map_err(|e| RenderError::read(&file, e))?;
    let pd = parse_polydata(&text, &file)?;
    let n = pd.points;
    let pts = sized(&pd, &file, "Points", "points", 3, n)?
        .ok_or_else(|| ferr!(file, "no <Points> array (the disc centres)"))?;
    let r = sized(&pd, &file, "PointData", "radius", 1, n)?.ok_or_else(|| {
        ferr!(
            file,
            "no point array \"radius\"; dem render reads the disc snapshots dem run \
             writes (snap-*.vtp)"
        )
    })?;
    finite_points(pts, &file, "disc centre")?;
    if let Some(k) = r.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(ferr!(
            file,
            "point array \"radius\", value {k}: {}; a disc radius is a positive finite \
             number",
            r[k]
        ));
    }
    let vel = sized(&pd, &file, "PointData", "velocity", 3, n)?;
    if let Some(k) = vel.and_then(|v| v.iter().position(|x| !x.is_finite())) {
        return Err(ferr!(
            file,
            "point array \"velocity\", component {k} (disc {}): not finite",
            k / 3
        ));
    }
    let int = |name: &str| -> Result<Option<Vec<u32>>, RenderError> {
        Ok(sized(&pd, &file, "PointData", name, 1, n)?.map(|v| {
            v.iter()
                .map(|&x| if x < 0.0 { FREE } else { x as u32 })
                .collect()
        }))
    };
    let body = int("body")?.unwrap_or_else(|| vec![FREE; n]);
    let group = int("group")?.unwrap_or_else(|| vec![0; n]);
    let id = int("id")?.unwrap_or_else(|| (0..n as u32).collect());
    let material = int("material")?;
    let keys = grain_keys(&body, &group, &id);
    let discs = (0..n)
        .map(|k| Disc {
            x: pts[3 * k],
            y: pts[3 * k + 1],
            r: r[k],
            speed: vel.map_or(0.0, |v| v[3 * k].hypot(v[3 * k + 1])),
            material: material.as_ref().map_or(0, |m| m[k] as u16),
            grain: keys[k],
        })
        .collect();
    let cells = line_cells(&pd, &file)?;
    let state = sized(&pd, &file, "CellData", "bond_state", 1, cells.len())?;
    let bgroup = sized(&pd, &file, "CellData", "bond_group", 1, cells.len())?;
    let mut bonds = Vec::with_capacity(cells.len());
    for (k, c) in cells.iter().enumerate() {
        let [i, j] = c[..] else {
            return Err(ferr!(
                file,
                "line {k} has {} points; a bond joins two discs",
                c.len()
            ));
        };
        bonds.push(Bond {
            i,
            j,
            group: bgroup.map_or(0, |g| g[k] as u16),
            intact: state.is_none_or(|s| s[k] != 0.0),
            broke_at: None,
            width: 0.0,
        });
    }
    let ngroups = bonds
        .iter()
        .map(|b| b.group as usize + 1)
        .max()
        .unwrap_or(0);
    let mut notes = Vec::new();
    let walls = match walls_beside(path) {
        Some(w) if w.is_file() => load_walls(&w)?,
        _ => Vec::new(),
    };
    if vel.is_none() {
        notes.push(format!("{file}: no \"velocity\" array; speeds drawn as 0"));
    }
    let mut p = Picture {
        kind: Kind::Snapshot,
        discs,
        bonds,
        bond_groups: (0..ngroups).map(|g| format!("bond group {g}")).collect(),
        materials: Vec::new(),
        walls,
        outline: None,
        centroid: None,
        clump_centroid: None,
        caption: Vec::new(),
        notes,
    };
    let time = time.or_else(|| time_beside(path));
    let when = match (step_of(path), time) {
        (Some(s), Some(t)) => step_time(s, t),
        (Some(s), None) => step_time(s, f64::NAN)
            .split("   t =")
            .next()
            .unwrap_or("")
            .to_string(),
        (None, Some(t)) => step_time(0, t)
            .split("   ")
            .nth(1)
            .unwrap_or("")
            .to_string(),
        (None, None) => String::new(),
    };
    p.caption = vec![
        format!("{}   {when}", short_name(path))
            .trim_end()
            .to_string(),
        counts(&p),
    ];
    Ok(p)
}

/// `walls-N.vtp` beside `snap-N.vtp`.
fn walls_beside(path: &Path) -> Option<PathBuf> {
    let name = path.file_name()?.to_str()?;
    let rest = name.strip_prefix("snap-")?;
    Some(path.with_file_name(format!("walls-{rest}")))
}

/// The walls of a `walls-*.vtp` (one polyline per line cell; the file does not keep names).
fn load_walls(path: &Path) -> Result<Vec<WallLine>, RenderError> {
    let file = path.display().to_string();
    let text = clumpgen::io::read_input_string(path).map_err(|e| RenderError::read(&file, e))?;
    let pd = parse_polydata(&text, &file)?;
    let pts = sized(&pd, &file, "Points", "points", 3, pd.points)?
        .ok_or_else(|| ferr!(file, "no <Points> array (the wall vertices)"))?;
    finite_points(pts, &file, "wall vertex")?;
    Ok(line_cells(&pd, &file)?
        .into_iter()
        .enumerate()
        .filter(|(_, c)| c.len() >= 2)
        .map(|(k, c)| WallLine {
            name: format!("wall {k}"),
            points: c.iter().map(|&v| [pts[3 * v], pts[3 * v + 1]]).collect(),
        })
        .collect())
}

/// Refuses a NaN or infinite coordinate of `<Points>` (issue 48 D17: a snapshot with a NaN
/// coordinate drew with exit 0), naming the point.
fn finite_points(pts: &[f64], file: &str, what: &str) -> Result<(), RenderError> {
    match pts.iter().position(|v| !v.is_finite()) {
        Some(k) => Err(ferr!(
            file,
            "<Points>, point {} ({what}): coordinate {} is {}; not a finite number",
            k / 3,
            ["x", "y", "z"][k % 3],
            pts[k]
        )),
        None => Ok(()),
    }
}

/// The disc snapshots of a `.pvd` collection in time order: (time in s, path). Wall files
/// (part 1) are skipped: each snapshot finds its own beside it.
pub fn read_pvd(path: &Path) -> Result<Vec<(f64, PathBuf)>, RenderError> {
    let file = path.display().to_string();
    let text = clumpgen::io::read_input_string(path).map_err(|e| RenderError::read(&file, e))?;
    if !text.contains("type=\"Collection\"") {
        return Err(ferr!(
            file,
            "not a VTK collection (no <VTKFile type=\"Collection\">)"
        ));
    }
    if !text.contains("</VTKFile>") {
        return Err(ferr!(file, "truncated (no closing </VTKFile>)"));
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut out = Vec::new();
    let mut pos = 0;
    while let Some(i) = text[pos..].find("<DataSet") {
        let start = pos + i;
        let end = text[start..]
            .find('>')
            .map(|k| start + k)
            .ok_or_else(|| ferr!(file, "truncated inside a <DataSet> tag"))?;
        let tag = &text[start..end];
        let f = attr(tag, "file")
            .ok_or_else(|| ferr!(file, "a <DataSet> has no file attribute"))?
            .replace("&quot;", "\"")
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&");
        let t: f64 = attr(tag, "timestep")
            .unwrap_or("0")
            .parse()
            .map_err(|e| ferr!(file, "<DataSet file=\"{f}\"> timestep: {e}"))?;
        pos = end;
        let part = attr(tag, "part").unwrap_or("0");
        let is_walls = Path::new(&f)
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| n.starts_with("walls-"));
        if part != "0" || is_walls {
            continue;
        }
        out.push((t, dir.join(&f)));
    }
    if out.is_empty() {
        return Err(ferr!(file, "the collection lists no disc snapshot"));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_and_arrays_are_read_and_bad_binary_refused() {
        let t = "<VTKFile type=\"PolyData\">\n<PolyData><Piece NumberOfPoints=\"2\" NumberOfLines=\"0\">\n\
                 <PointData><DataArray type=\"Float64\" Name=\"radius\" format=\"ascii\">\n0.5 0.25\n</DataArray></PointData>\n\
                 <Points><DataArray type=\"Float64\" Name=\"points\" NumberOfComponents=\"3\" format=\"ascii\">\n0 0 0 1 2 0\n</DataArray></Points>\n\
                 </Piece></PolyData></VTKFile>\n";
        let pd = parse_polydata(t, "f.vtp").unwrap();
        assert_eq!(pd.points, 2);
        assert_eq!(pd.get("PointData", "radius").unwrap().values, [0.5, 0.25]);
        assert_eq!(pd.get("Points", "points").unwrap().comps, 3);
        let b = t.replace("format=\"ascii\"", "format=\"binary\"");
        let e = parse_polydata(&b, "f.vtp").err().unwrap().to_string();
        assert!(
            e.contains("f.vtp") && e.contains("\"radius\"") && e.contains("base64"),
            "{e}"
        );
        let c = t.replace(
            "type=\"PolyData\">",
            "type=\"PolyData\" compressor=\"vtkZLibDataCompressor\">",
        );
        let e = parse_polydata(&c, "f.vtp").err().unwrap().to_string();
        assert!(e.contains("compressed"), "{e}");
        let e = parse_polydata(&t[..t.len() / 2], "f.vtp")
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("truncated"), "{e}");
    }

    /// Issue 48 D17: a snapshot with a NaN or infinite centre, a NaN, zero or negative
    /// radius, or a NaN velocity is refused naming the array and the disc; walls likewise.
    #[test]
    fn non_finite_snapshots_are_refused() {
        let dir = std::env::temp_dir().join(format!("dem-vtk-nan-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let snap = |pts: &str, r: &str, v: &str| {
            format!(
                "<VTKFile type=\"PolyData\">\n<PolyData><Piece NumberOfPoints=\"2\" NumberOfLines=\"0\">\n\
                 <PointData><DataArray type=\"Float64\" Name=\"radius\" format=\"ascii\">\n{r}\n</DataArray>\n\
                 <DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n{v}\n</DataArray></PointData>\n\
                 <Points><DataArray type=\"Float64\" Name=\"points\" NumberOfComponents=\"3\" format=\"ascii\">\n{pts}\n</DataArray></Points>\n\
                 </Piece></PolyData></VTKFile>\n"
            )
        };
        let f = dir.join("snap-000000000.vtp");
        let load = |text: String| {
            std::fs::write(&f, text).unwrap();
            load_vtp(&f, Some(0.0))
        };
        let (p, r, v) = ("0 0 0 1 2 0", "0.5 0.25", "0 0 0 1 0 0");
        assert!(load(snap(p, r, v)).is_ok());
        for (bad, want) in [
            (
                snap("0 0 0 nan 2 0", r, v),
                "point 1 (disc centre): coordinate x is NaN",
            ),
            (
                snap("0 inf 0 1 2 0", r, v),
                "point 0 (disc centre): coordinate y is inf",
            ),
            (snap(p, "0.5 NaN", v), "\"radius\", value 1: NaN"),
            (snap(p, "0 0.25", v), "\"radius\", value 0: 0"),
            (snap(p, "0.5 -1", v), "\"radius\", value 1: -1"),
            (
                snap(p, r, "0 0 0 1 nan 0"),
                "\"velocity\", component 4 (disc 1)",
            ),
        ] {
            let e = load(bad).err().unwrap().to_string();
            assert!(e.contains("snap-000000000.vtp") && e.contains(want), "{e}");
        }
        // The walls file beside it: a NaN vertex is refused naming that file.
        std::fs::write(
            dir.join("walls-000000000.vtp"),
            "<VTKFile type=\"PolyData\">\n<PolyData><Piece NumberOfPoints=\"2\" NumberOfLines=\"1\">\n\
             <Points><DataArray type=\"Float64\" Name=\"points\" NumberOfComponents=\"3\" format=\"ascii\">\n0 0 0 nan 1 0\n</DataArray></Points>\n\
             <Lines><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n0 1\n</DataArray>\n\
             <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n2\n</DataArray></Lines>\n\
             </Piece></PolyData></VTKFile>\n",
        )
        .unwrap();
        let e = load(snap(p, r, v)).err().unwrap().to_string();
        assert!(
            e.contains("walls-000000000.vtp") && e.contains("point 1 (wall vertex)"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A binary (appended base64) snapshot and walls, as dem run writes them, draw the same
    /// picture as the ASCII ones; a truncated appended block is refused naming the array.
    #[test]
    fn binary_snapshots_read_like_ascii() {
        use dem_core::output::vtk::{write_discs, write_walls, BondLine, Format};
        use dem_core::state::{State, Wall};
        let dir = std::env::temp_dir().join(format!("dem-render-vtkbin-{}", std::process::id()));
        let mut st = State::default();
        for k in 0..4 {
            st.discs
                .push_uniform(k as f64 / 3.0, 0.2, 0.1 + 0.01 * k as f64, 2500.0, 1.0, 0);
        }
        st.discs.vx[2] = 1.0 / 7.0;
        st.discs.body[3] = 1;
        st.walls
            .push(Wall::new("floor", [-1.0, 0.0], [2.0, 0.0], 0));
        let bond = |i, j, intact| BondLine {
            i,
            j,
            group: 1,
            intact,
            normal_force: 1.5,
            shear_force: 0.0,
            moment: 0.0,
            bonded_elements: None,
        };
        let bonds = [bond(0, 1, true), bond(2, 3, false)];
        let load = |format: Format| {
            let sub = dir.join(format!("{format:?}"));
            write_discs(&sub.join("snap-000000010.vtp"), &st, &bonds, format).unwrap();
            write_walls(&sub.join("walls-000000010.vtp"), &st.walls, format).unwrap();
            load_vtp(&sub.join("snap-000000010.vtp"), Some(0.5)).unwrap()
        };
        let (a, b) = (load(Format::Ascii), load(Format::Binary));
        let discs = |p: &Picture| -> Vec<[f64; 4]> {
            p.discs.iter().map(|d| [d.x, d.y, d.r, d.speed]).collect()
        };
        assert_eq!(discs(&a), discs(&b));
        assert_eq!(discs(&b)[2][3], 1.0 / 7.0);
        let grains = |p: &Picture| p.discs.iter().map(|d| d.grain).collect::<Vec<_>>();
        assert_eq!(grains(&a), grains(&b));
        let bonds = |p: &Picture| -> Vec<(usize, usize, u16, bool)> {
            p.bonds
                .iter()
                .map(|b| (b.i, b.j, b.group, b.intact))
                .collect()
        };
        assert_eq!(bonds(&b), [(0, 1, 1, true), (2, 3, 1, false)]);
        assert_eq!(bonds(&a), bonds(&b));
        assert_eq!(b.walls.len(), 1);
        assert_eq!(b.walls[0].points, a.walls[0].points);
        assert_eq!(a.caption[1], b.caption[1]);
        // Cut the appended block short: the array whose data is missing is named.
        let f = dir.join("Binary").join("snap-000000010.vtp");
        let text = std::fs::read_to_string(&f).unwrap();
        let end = text.find("\n  </AppendedData>").unwrap();
        let short = format!("{}{}", &text[..end - 10], &text[end..]);
        let e = parse_polydata(&short, "s.vtp").err().unwrap().to_string();
        assert!(
            e.contains("s.vtp: array \"offsets\"") && e.contains("truncated"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
