//! Files holding many grains: images (masks and labelled images, [`super::raster`]) and GIS
//! polygons (GeoJSON and WKT, [`super::gis`]). [`read_grains`] gives one [`Grain`] per grain,
//! each with its own outline or its own error, so that one bad grain fails alone.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::Outline;
use crate::error::OutlineError;

/// The kinds of multi-grain files, chosen by extension (case-insensitive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MultiKind {
    /// `.png`, `.tif`, `.tiff`: a binary mask or a labelled image.
    Image,
    /// `.geojson`: Polygon, MultiPolygon, Feature or FeatureCollection.
    GeoJson,
    /// `.wkt`: POLYGON or MULTIPOLYGON (one geometry, or one per line).
    Wkt,
}

/// File endings of multi-grain files.
pub const MULTI_EXTENSIONS: [&str; 5] = ["png", "tif", "tiff", "geojson", "wkt"];

impl MultiKind {
    /// The kind of `path` by its extension, `None` for a one-outline file (CSV, JSON, ...).
    pub fn of(path: &Path) -> Option<MultiKind> {
        let e = path.extension()?.to_str()?.to_ascii_lowercase();
        match e.as_str() {
            "png" | "tif" | "tiff" => Some(MultiKind::Image),
            "geojson" => Some(MultiKind::GeoJson),
            "wkt" => Some(MultiKind::Wkt),
            _ => None,
        }
    }
}

/// How an image is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MaskMode {
    /// Labels if the image holds more than 2 distinct values, else binary.
    Auto,
    /// One grain per 4-connected component of the nonzero pixels (zero pixels with `invert`).
    Binary,
    /// One grain per nonzero value (0 is background).
    Labels,
}

/// Options for multi-grain files.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GrainOptions {
    pub mask: MaskMode,
    /// Binary masks: the grains are the zero pixels.
    pub invert: bool,
    /// Images: grains of fewer pixels are skipped (counted in a note).
    pub min_pixels: usize,
    /// Images: simplify the pixel outline (Ramer-Douglas-Peucker, `geo::Simplify`) so that no
    /// corner of it lies farther than this many pixels from the simplified outline; 0 keeps
    /// the exact pixel outline (area = pixel count).
    #[serde(default)]
    pub simplify: f64,
}

impl Default for GrainOptions {
    fn default() -> Self {
        GrainOptions {
            mask: MaskMode::Auto,
            invert: false,
            min_pixels: 20,
            simplify: 0.0,
        }
    }
}

/// One grain of a multi-grain file.
#[derive(Debug)]
pub struct Grain {
    /// File-safe name, unique within the file unless the file repeats a feature name:
    /// `component-3`, `label-7`, a feature's `id` or `name`, `feature-4`, `polygon-0`.
    pub name: String,
    /// How errors and templates name it: `component 3`, `label 7`, `feature "g7"`.
    pub label: String,
    /// Its outline (name `<file stem>/<name>`, [`Outline::grain`] = `label`), or why not.
    pub outline: Result<Outline, OutlineError>,
}

/// The grains of one file, and remarks on the file as a whole (grains skipped as too small).
#[derive(Debug)]
pub struct FileGrains {
    pub grains: Vec<Grain>,
    pub notes: Vec<String>,
}

/// A name safe as a file name: letters, digits, `-`, `_`, `.` kept (not leading dots), others
/// `_`; at most 100 characters; `fallback` when nothing is left.
pub(crate) fn file_safe(name: &str, fallback: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .take(100)
        .collect();
    let s = s.trim_start_matches('.').to_string();
    if s.is_empty() || s.chars().all(|c| c == '_') {
        fallback.to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_file_safe() {
        assert_eq!(file_safe("g7", "x"), "g7");
        assert_eq!(file_safe("../etc/passwd", "x"), "_etc_passwd");
        assert_eq!(file_safe("grain 7/a", "x"), "grain_7_a");
        assert_eq!(file_safe("", "feature-3"), "feature-3");
        assert_eq!(file_safe("///", "feature-3"), "feature-3");
        assert_eq!(MultiKind::of(Path::new("a/B.TIF")), Some(MultiKind::Image));
        assert_eq!(MultiKind::of(Path::new("a.json")), None);
    }
}
