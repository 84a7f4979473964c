//! Grain outlines from images: binary masks (one grain per connected component) and labelled
//! images (one grain per label value), 8- or 16-bit greyscale PNG or TIFF.
//!
//! * Decoding: the `image` crate (PNG, TIFF; greyscale `L8`/`L16` only: a colour or alpha image
//!   is refused, since turning colours into labels would merge or split grains silently).
//! * Mode ([`MaskMode`]): `binary` (foreground = nonzero, or zero with `invert`), `labels`
//!   (every nonzero value is a grain, 0 is background), `auto` (labels when the image holds more
//!   than 2 distinct values).
//! * Components: [`connected_components`] with 4-connectivity (pixels sharing an edge; pixels
//!   of different values are different components; labels in the raster order of each
//!   component's first pixel, as `imageproc::region_labelling` numbers them; written here, 30
//!   lines, because imageproc 0.27 brings a second nalgebra (0.35, Rust 1.89) into the build). Grains touching
//!   only at a pixel corner are therefore two grains, and grains separated by a one-pixel
//!   8-connected line (watershed lines) stay apart. Grains sharing an edge in a *binary* mask
//!   are one component: a binary mask cannot tell them apart (use a labelled image).
//! * Outline: the *crack* boundary, along pixel edges (not through pixel centres). Pixel
//!   (col i, row j) of an image of height H covers x ∈ [i, i+1], y ∈ [H−j−1, H−j] in pixel
//!   units (y up, origin at the image's bottom-left corner), so a region of N pixels without
//!   holes has area exactly N·px² (integer vertices: the shoelace sum is exact). The tracer
//!   keeps the region on its right and, where two pixels of one grain touch only at a corner
//!   (a pinch, visited twice), turns so as to keep them apart (4-connectivity) and cuts both
//!   corners by δ = 1/16 px (area −δ² = −1/256 px² per pinch) so the outline stays simple.
//!   Contour tracers such as `imageproc::contours::find_contours` (Suzuki & Abe 1985) are not
//!   used for the outline: their borders run through the centres of the border pixels, so a
//!   filled w×h rectangle gets (w−1)(h−1) px², short by (w+h−1) px² (half its perimeter times a
//!   pixel), and they follow 8-connected regions (checked with imageproc 0.27 on 2026-11-27: a
//!   10 × 6 rectangle enclosed 45 px², not 60).
//! * Optional simplification (`GrainOptions::simplify`, pixels): Ramer-Douglas-Peucker from
//!   `geo` drops staircase corners within the tolerance (area change at most tolerance ×
//!   perimeter); off by default, so that the outline is exact to the mask.
//! * Holes (pixels of the background or of other labels enclosed by a grain): counted with
//!   [`connected_components`] (8-connected background, the dual of 4-connected grains) and
//!   reported as a warning with their area; the template fills the outer outline.
//! * A grain touching the image border is warned (a grain cut off by the image edge); a label
//!   in several pieces keeps its largest (warned); grains below `min_pixels` are skipped and
//!   counted in a note; an image without any grain is an error naming the file.

use image::DynamicImage;
use rayon::prelude::*;

use super::grains::{FileGrains, Grain, GrainOptions, MaskMode};
use super::text::RawOutline;
use super::{finish, ReadOptions};
use crate::error::{OutlineError, Pos};
use crate::units::Units;

/// Corner cut at a pinch, in pixels (exact in binary floating point).
pub const PINCH_CUT_PX: f64 = 1.0 / 16.0;

#[derive(Debug, Clone, Copy)]
struct Comp {
    count: usize,
    value: u16,
    first: usize,
    lo: [usize; 2],
    hi: [usize; 2],
}

/// A grain to trace: component id, its figures, name, label, warnings so far.
type Picked = (u32, Comp, String, String, Vec<String>);

/// The grains of an image file (`bytes`), `file` as given, `stem` its file stem.
pub(crate) fn image_grains(
    bytes: &[u8],
    file: &str,
    stem: &str,
    sha256: &str,
    opts: &ReadOptions,
    g: &GrainOptions,
) -> Result<FileGrains, OutlineError> {
    let scale = match opts.units {
        Some(Units::Px { metres_per_px }) => metres_per_px,
        _ => {
            return Err(OutlineError::NeedPxScale {
                file: file.to_string(),
            })
        }
    };
    if !(scale.is_finite() && scale > 0.0) {
        return Err(OutlineError::BadScale {
            file: file.to_string(),
            pos: None,
            value: scale,
        });
    }
    let bad = |reason: String| OutlineError::Image {
        file: file.to_string(),
        reason,
    };
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| bad(e.to_string()))
    };
    // The header's size first: the decoded image is an input too, bounded by the same limit as
    // the file (`dem --max-input-mib`), and a refusal names the size (issue 48: a 100000 ×
    // 100000 header ended in the decoder's bare "Memory limit exceeded").
    let (w, h) = reader()?
        .into_dimensions()
        .map_err(|e| bad(e.to_string()))?;
    let limit = crate::io::input_limit();
    let decoded = 2 * u64::from(w) * u64::from(h);
    if decoded > limit {
        return Err(bad(format!(
            "{w} × {h} pixels take up to {} MiB decoded, more than the input limit of {} MiB; \
             crop or downscale the image, or raise the limit with `dem --max-input-mib N`",
            decoded.div_ceil(1 << 20),
            limit.div_ceil(1 << 20)
        )));
    }
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(limit);
    let mut decoder = reader()?;
    decoder.limits(limits);
    let img = decoder.decode().map_err(|e| bad(e.to_string()))?;
    let (w, h) = (img.width() as usize, img.height() as usize);
    let values: Vec<u16> = match img {
        DynamicImage::ImageLuma8(b) => b.into_raw().into_iter().map(u16::from).collect(),
        DynamicImage::ImageLuma16(b) => b.into_raw(),
        other => {
            return Err(bad(format!(
                "{:?} pixels: expected an 8- or 16-bit greyscale mask or label image (one \
                 channel, no alpha); convert it first",
                other.color()
            )))
        }
    };
    let mut seen = vec![false; 1 << 16];
    let mut distinct = 0usize;
    for &v in &values {
        if !seen[v as usize] {
            seen[v as usize] = true;
            distinct += 1;
        }
    }
    let mode = match g.mask {
        MaskMode::Auto if distinct > 2 => MaskMode::Labels,
        MaskMode::Auto => MaskMode::Binary,
        m => m,
    };
    if mode == MaskMode::Labels && g.invert {
        return Err(OutlineError::BadOption {
            file: file.to_string(),
            reason: format!(
                "--invert is for binary masks; this image is read as labels ({distinct} \
                 distinct values)"
            ),
        });
    }
    let cells: Vec<u16> = match mode {
        MaskMode::Labels => values,
        _ => values
            .iter()
            .map(|&v| u16::from((v != 0) != g.invert))
            .collect(),
    };
    if cells.iter().all(|&v| v == 0) {
        let why = if g.invert {
            "every pixel is nonzero, and with --invert the grains are the 0 pixels"
        } else {
            "every pixel is 0 (background)"
        };
        return Err(OutlineError::NoGrain {
            file: file.to_string(),
            reason: format!("an empty mask ({w} x {h} pixels): {why}"),
        });
    }
    let ids = connected_components(&cells, w, 0, false);
    let n = ids.iter().copied().max().unwrap_or(0) as usize;
    let mut comps: Vec<Option<Comp>> = vec![None; n + 1];
    for (k, &id) in ids.iter().enumerate() {
        if id == 0 {
            continue;
        }
        let (x, y) = (k % w, k / w);
        let c = comps[id as usize].get_or_insert(Comp {
            count: 0,
            value: cells[k],
            first: k,
            lo: [x, y],
            hi: [x, y],
        });
        c.count += 1;
        c.lo = [c.lo[0].min(x), c.lo[1].min(y)];
        c.hi = [c.hi[0].max(x), c.hi[1].max(y)];
    }
    // Components in raster order of their first pixels.
    let mut order: Vec<(u32, Comp)> = comps
        .iter()
        .enumerate()
        .filter_map(|(id, c)| c.map(|c| (id as u32, c)))
        .collect();
    order.sort_by_key(|(_, c)| c.first);
    // (id, component, name, label, warnings) of each grain to trace.
    let mut picked: Vec<Picked> = Vec::new();
    let mut small: Vec<usize> = Vec::new();
    let kind;
    if mode == MaskMode::Labels {
        kind = "labels";
        let mut by_value: std::collections::BTreeMap<u16, Vec<(u32, Comp)>> = Default::default();
        for (id, c) in &order {
            by_value.entry(c.value).or_default().push((*id, *c));
        }
        for (v, mut pieces) in by_value {
            pieces.sort_by(|a, b| b.1.count.cmp(&a.1.count).then(a.1.first.cmp(&b.1.first)));
            let (id, c) = pieces[0];
            if c.count < g.min_pixels {
                small.push(c.count);
                continue;
            }
            let mut warn = Vec::new();
            if pieces.len() > 1 {
                let rest: usize = pieces[1..].iter().map(|p| p.1.count).sum();
                warn.push(format!(
                    "label {v} is in {} pieces (pixels sharing an edge): kept the largest \
                     ({} px), left out {} px",
                    pieces.len(),
                    c.count,
                    rest
                ));
            }
            picked.push((id, c, format!("label-{v}"), format!("label {v}"), warn));
        }
    } else {
        kind = "components";
        for (k, (id, c)) in order.iter().enumerate() {
            if c.count < g.min_pixels {
                small.push(c.count);
                continue;
            }
            picked.push((
                *id,
                *c,
                format!("component-{}", k + 1),
                format!("component {}", k + 1),
                Vec::new(),
            ));
        }
    }
    let mut notes = Vec::new();
    let total = picked.len() + small.len();
    if !small.is_empty() {
        let (lo, hi) = (
            small.iter().min().copied().unwrap_or(0),
            small.iter().max().copied().unwrap_or(0),
        );
        notes.push(format!(
            "{file}: skipped {} of {total} {kind} below --min-pixels {} ({lo}-{hi} px)",
            small.len(),
            g.min_pixels
        ));
    }
    if picked.is_empty() {
        return Err(OutlineError::NoGrain {
            file: file.to_string(),
            reason: format!(
                "all {total} {kind} are below --min-pixels {} (largest {} px)",
                g.min_pixels,
                small.iter().max().copied().unwrap_or(0)
            ),
        });
    }
    let px = Units::Px {
        metres_per_px: scale,
    };
    let grains = picked
        .into_par_iter()
        .map(|(id, c, name, label, mut warnings)| {
            let what = format!("{file}, {label}");
            let traced = trace(&ids, w, id, &c);
            if c.lo[0] == 0 || c.lo[1] == 0 || c.hi[0] + 1 == w || c.hi[1] + 1 == h {
                warnings.push(format!(
                    "{label} touches the image border: possibly a grain cut off by the edge \
                     of the image"
                ));
            }
            let holes = traced.filled - c.count;
            if holes > 0 {
                let n_holes = count_holes(&ids, w, id, &c);
                warnings.push(format!(
                    "{label} has {n_holes} hole{} ({holes} px, {:.2} % of the area inside its \
                     outline; pixels of the background or of other labels): the template fills \
                     the outer outline, so its mass includes them",
                    if n_holes == 1 { "" } else { "s" },
                    100.0 * holes as f64 / traced.filled as f64
                ));
            }
            if traced.pinches > 0 {
                warnings.push(format!(
                    "{label} touches itself at {} pixel corner{} (pixels meeting only at a \
                     corner): each corner cut by {PINCH_CUT_PX} px to keep the outline simple",
                    traced.pinches,
                    if traced.pinches == 1 { "" } else { "s" }
                ));
            }
            let mut points: Vec<[f64; 2]> = traced
                .points
                .iter()
                .map(|p| [p[0], h as f64 - p[1]])
                .collect();
            if g.simplify > 0.0 {
                points = simplify(&points, g.simplify);
            }
            let npts = points.len();
            let raw = RawOutline {
                points,
                pos: (0..npts).map(Pos::Point).collect(),
                units: None,
                metres_per_px: None,
            };
            let outline = finish(
                &raw,
                px,
                &format!("{stem}/{name}"),
                &what,
                file,
                sha256.to_string(),
                opts,
                warnings,
            )
            .map(|mut o| {
                o.grain = Some(label.clone());
                o
            });
            Grain {
                name,
                label,
                outline,
            }
        })
        .collect();
    Ok(FileGrains { grains, notes })
}

/// The closed polygon `p` simplified by Ramer-Douglas-Peucker at `eps` (geo's `Simplify`);
/// the repeated closing point is dropped again. A simplified outline that intersects itself
/// fails with the usual validity error, naming the grain.
fn simplify(p: &[[f64; 2]], eps: f64) -> Vec<[f64; 2]> {
    use geo::{Coord, LineString, Polygon, Simplify};
    let ring: LineString<f64> = p.iter().map(|&[x, y]| Coord { x, y }).collect();
    let s = Polygon::new(ring, vec![]).simplify(eps);
    let mut out: Vec<[f64; 2]> = s.exterior().coords().map(|c| [c.x, c.y]).collect();
    if out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

/// A traced outer boundary in pixel-corner coordinates (image orientation: y down).
struct Traced {
    points: Vec<[f64; 2]>,
    /// Pixels inside the outline (the grain's and its holes').
    filled: usize,
    pinches: usize,
}

/// Unit steps east, south, west, north (image coordinates, y down).
const STEP: [[i64; 2]; 4] = [[1, 0], [0, 1], [-1, 0], [0, -1]];

/// The crack boundary of component `id` around its first pixel, the region on the right
/// (clockwise on screen, counter-clockwise once y points up). Vertices only where it turns.
fn trace(ids: &[u32], w: usize, id: u32, c: &Comp) -> Traced {
    let h = ids.len() / w;
    let inside = |x: i64, y: i64| {
        x >= 0
            && y >= 0
            && (x as usize) < w
            && (y as usize) < h
            && ids[y as usize * w + x as usize] == id
    };
    let start = [(c.first % w) as i64, (c.first / w) as i64];
    let mut p = start;
    let mut d = 0usize;
    let mut corners: Vec<[i64; 2]> = vec![start];
    // At most 4 edges per pixel of the bounding box: a guard, never reached.
    let guard = 4 * (c.hi[0] - c.lo[0] + 2) * (c.hi[1] - c.lo[1] + 2);
    for _ in 0..guard {
        p = [p[0] + STEP[d][0], p[1] + STEP[d][1]];
        let (cx, cy) = (p[0], p[1]);
        // Pixels ahead-left and ahead-right of the corner, for the direction of travel.
        let (al, ar) = match d {
            0 => ((cx, cy - 1), (cx, cy)),
            1 => ((cx, cy), (cx - 1, cy)),
            2 => ((cx - 1, cy), (cx - 1, cy - 1)),
            _ => ((cx - 1, cy - 1), (cx, cy - 1)),
        };
        let nd = if !inside(ar.0, ar.1) {
            (d + 1) % 4
        } else if inside(al.0, al.1) {
            (d + 3) % 4
        } else {
            d
        };
        if p == start && nd == 0 {
            break;
        }
        if nd != d {
            corners.push(p);
        }
        d = nd;
    }
    // Filled area (exact: integer shoelace), then the pinch cuts.
    let m = corners.len();
    let mut twice: i64 = 0;
    for i in 0..m {
        let (a, b) = (corners[i], corners[(i + 1) % m]);
        twice += a[0] * b[1] - b[0] * a[1];
    }
    let filled = (twice.unsigned_abs() / 2) as usize;
    let mut count = std::collections::HashMap::new();
    for q in &corners {
        *count.entry(*q).or_insert(0usize) += 1;
    }
    let mut pinches = 0;
    let mut points = Vec::with_capacity(m + 4);
    for i in 0..m {
        let q = corners[i];
        let qf = [q[0] as f64, q[1] as f64];
        if count[&q] < 2 {
            points.push(qf);
            continue;
        }
        pinches += 1;
        let (a, b) = (corners[(i + m - 1) % m], corners[(i + 1) % m]);
        let unit = |u: [i64; 2], v: [i64; 2]| {
            [(v[0] - u[0]).signum() as f64, (v[1] - u[1]).signum() as f64]
        };
        let (ui, uo) = (unit(a, q), unit(q, b));
        points.push([qf[0] - PINCH_CUT_PX * ui[0], qf[1] - PINCH_CUT_PX * ui[1]]);
        points.push([qf[0] + PINCH_CUT_PX * uo[0], qf[1] + PINCH_CUT_PX * uo[1]]);
    }
    Traced {
        points,
        filled,
        pinches: pinches / 2,
    }
}

/// Holes of component `id`: 8-connected regions of other pixels inside its bounding box that
/// do not reach the box's (padded) frame.
fn count_holes(ids: &[u32], w: usize, id: u32, c: &Comp) -> usize {
    let (bw, bh) = (c.hi[0] - c.lo[0] + 3, c.hi[1] - c.lo[1] + 3);
    let crop: Vec<u8> = (0..bw * bh)
        .map(|k| {
            let (x, y) = (k % bw, k / bw);
            let inside = x >= 1
                && y >= 1
                && x + 1 < bw
                && y + 1 < bh
                && ids[(c.lo[1] + y - 1) * w + c.lo[0] + x - 1] == id;
            u8::from(!inside)
        })
        .collect();
    let l = connected_components(&crop, bw, 0, true);
    // The padded frame is one region (label of pixel 0); every other region is a hole.
    let outside = l[0];
    let mut set = std::collections::BTreeSet::new();
    for &p in &l {
        if p != 0 && p != outside {
            set.insert(p);
        }
    }
    set.len()
}

/// Connected components of an image of `width` columns (row-major `cells`): pixels of equal
/// value other than `background` that share an edge (or, with `eight`, also a corner) are one
/// component. Returns a label per pixel, 0 for the background, 1, 2, ... in the raster order
/// of each component's first pixel. A flood fill with an explicit stack (no recursion).
pub fn connected_components<T: Copy + PartialEq>(
    cells: &[T],
    width: usize,
    background: T,
    eight: bool,
) -> Vec<u32> {
    let height = cells.len().checked_div(width).unwrap_or(0);
    let mut label = vec![0u32; cells.len()];
    let mut next = 0u32;
    let mut stack = Vec::new();
    for start in 0..cells.len() {
        if label[start] != 0 || cells[start] == background {
            continue;
        }
        next += 1;
        let v = cells[start];
        label[start] = next;
        stack.push(start);
        while let Some(k) = stack.pop() {
            let (x, y) = ((k % width) as isize, (k / width) as isize);
            for (dx, dy) in [
                (1, 0),
                (-1, 0),
                (0, 1),
                (0, -1),
                (1, 1),
                (1, -1),
                (-1, 1),
                (-1, -1),
            ]
            .into_iter()
            .take(if eight { 8 } else { 4 })
            {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= width as isize || ny >= height as isize {
                    continue;
                }
                let n = ny as usize * width + nx as usize;
                if label[n] == 0 && cells[n] == v {
                    label[n] = next;
                    stack.push(n);
                }
            }
        }
    }
    label
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ids_of(rows: &[&str]) -> (Vec<u32>, usize) {
        let w = rows[0].len();
        let ids = rows
            .iter()
            .flat_map(|r| r.bytes().map(|b| u32::from(b == b'#')))
            .collect();
        (ids, w)
    }

    fn comp(ids: &[u32], w: usize) -> Comp {
        let first = ids.iter().position(|&v| v == 1).unwrap();
        let mut c = Comp {
            count: 0,
            value: 1,
            first,
            lo: [usize::MAX; 2],
            hi: [0; 2],
        };
        for (k, _) in ids.iter().enumerate().filter(|(_, &v)| v == 1) {
            let (x, y) = (k % w, k / w);
            c.count += 1;
            c.lo = [c.lo[0].min(x), c.lo[1].min(y)];
            c.hi = [c.hi[0].max(x), c.hi[1].max(y)];
        }
        c
    }

    /// A PNG of `w` × `h` 8-bit greyscale pixels whose image data is empty: a header only.
    fn png_header(w: u32, h: u32) -> Vec<u8> {
        fn crc32(bytes: &[u8]) -> u32 {
            let mut c = !0u32;
            for &b in bytes {
                c ^= u32::from(b);
                for _ in 0..8 {
                    c = if c & 1 == 1 {
                        0xEDB8_8320 ^ (c >> 1)
                    } else {
                        c >> 1
                    };
                }
            }
            !c
        }
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut ihdr = w.to_be_bytes().to_vec();
        ihdr.extend_from_slice(&h.to_be_bytes());
        ihdr.extend_from_slice(&[8, 0, 0, 0, 0]);
        for (kind, data) in [(&b"IHDR"[..], &ihdr[..]), (b"IDAT", &[]), (b"IEND", &[])] {
            let chunk = [kind, data].concat();
            png.extend_from_slice(&(data.len() as u32).to_be_bytes());
            png.extend_from_slice(&chunk);
            png.extend_from_slice(&crc32(&chunk).to_be_bytes());
        }
        png
    }

    /// Issue 48: a 100000 × 100000 header is refused by its size and the limit, before any
    /// decoding (before: the decoder's "Memory limit exceeded", no size).
    #[test]
    fn an_image_too_large_to_decode_is_refused_with_its_size() {
        let opts = ReadOptions {
            units: Some(Units::Px {
                metres_per_px: 1e-6,
            }),
            resample: None,
        };
        let bytes = png_header(100_000, 100_000);
        let e = image_grains(
            &bytes,
            "huge.png",
            "huge",
            "",
            &opts,
            &GrainOptions::default(),
        )
        .expect_err("10^10 pixels");
        let msg = e.to_string();
        assert!(
            msg.starts_with("huge.png: ") && msg.contains("100000 × 100000 pixels"),
            "{msg}"
        );
        assert!(msg.contains("input limit of 1024 MiB") && msg.contains("--max-input-mib"));
    }

    #[test]
    fn crack_boundary_of_an_l_and_a_ring() {
        let (ids, w) = ids_of(&["....", ".##.", ".#..", "...."]);
        let t = trace(&ids, w, 1, &comp(&ids, w));
        assert_eq!(
            t.points,
            vec![[1., 1.], [3., 1.], [3., 2.], [2., 2.], [2., 3.], [1., 3.]]
        );
        assert_eq!((t.filled, t.pinches), (3, 0));
        let (ids, w) = ids_of(&["#####", "#...#", "#.#.#", "#...#", "#####"]);
        let c = comp(&ids, w);
        let t = trace(&ids, w, 1, &c);
        assert_eq!((t.filled, t.points.len()), (25, 4));
        // The inner pixel is a pixel of another value: one hole of 9 px with it.
        assert_eq!(count_holes(&ids, w, 1, &c), 1);
    }

    #[test]
    fn a_pinch_is_cut_so_the_outline_stays_simple() {
        // A U whose arms meet at one corner: (1,1)-(2,2) touch diagonally.
        let (ids, w) = ids_of(&["......", ".#....", "..###.", ".##.#.", ".####.", "......"]);
        let c = comp(&ids, w);
        let t = trace(&ids, w, 1, &c);
        assert_eq!(
            t.pinches, 0,
            "separate: (1,1) is its own 4-component in real use"
        );
        let (ids, w) = ids_of(&["......", ".##...", ".#.##.", ".####.", "......"]);
        let c = comp(&ids, w);
        let t = trace(&ids, w, 1, &c);
        assert_eq!(t.pinches, 1);
        assert!(crate::outline::find_self_intersection(&t.points).is_none());
        let area = crate::props::signed_area(&t.points).abs();
        let want = c.count as f64 - PINCH_CUT_PX * PINCH_CUT_PX;
        assert!((area - want).abs() < 1e-12, "{area} vs {want}");
    }

    #[test]
    fn components_are_numbered_in_raster_order_with_four_or_eight_neighbours() {
        // 1 1 0 2
        // 0 1 0 2
        // 1 0 2 0
        let v = [1u8, 1, 0, 2, 0, 1, 0, 2, 1, 0, 2, 0];
        assert_eq!(
            connected_components(&v, 4, 0, false),
            [1, 1, 0, 2, 0, 1, 0, 2, 3, 0, 4, 0]
        );
        // With corners too, the 1 at (0, 2) joins the 1 at (1, 1) and the 2 at (2, 2) the 2 at
        // (3, 1).
        assert_eq!(
            connected_components(&v, 4, 0, true),
            [1, 1, 0, 2, 0, 1, 0, 2, 1, 0, 2, 0]
        );
        // Different values never join; an empty image has no components.
        assert_eq!(
            connected_components(&[1u16, 2, 2, 1], 2, 0, false),
            [1, 2, 3, 4]
        );
        assert!(connected_components::<u8>(&[], 0, 0, false).is_empty());
    }
}
