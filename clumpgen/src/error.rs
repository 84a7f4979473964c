//! Typed errors of the outline reader.
//!
//! Every message names the file (as given by the caller) and, where it applies, the line
//! (CSV / whitespace input) or the point index (JSON input) of the offending data.

use std::fmt;

/// Where in an input file a value came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pos {
    /// 1-based line number of a text (CSV / whitespace) file.
    Line(usize),
    /// 0-based index of a point in the `points` array of a JSON file.
    Point(usize),
}

impl fmt::Display for Pos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Pos::Line(l) => write!(f, "line {l}"),
            Pos::Point(p) => write!(f, "point {p}"),
        }
    }
}

/// `"file"` or `"file, line 7"`.
fn loc(file: &str, pos: &Option<Pos>) -> String {
    match pos {
        Some(p) => format!("{file}, {p}"),
        None => file.to_string(),
    }
}

/// One edge of an outline, as reported by a self-intersection error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeRef {
    /// Vertex indices (0-based, counting the data points of the file in file order,
    /// including dropped duplicates) of the edge's two end points.
    pub vertices: [usize; 2],
    /// Where in the file the two end points are.
    pub pos: [Pos; 2],
}

impl fmt::Display for EdgeRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "edge {}-{} ({} to {})",
            self.vertices[0], self.vertices[1], self.pos[0], self.pos[1]
        )
    }
}

/// Everything that can go wrong while reading an outline.
#[derive(Debug, thiserror::Error)]
pub enum OutlineError {
    /// The file could not be read.
    #[error("{file}: cannot read: {source}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
    /// A text line that is neither a comment, nor the header, nor an `x y` pair.
    #[error("{file}, line {line}: cannot parse {text:?}: {reason}")]
    Unparsable {
        file: String,
        line: usize,
        text: String,
        reason: String,
    },
    /// A JSON file that does not have the shape `{"units": "mm", "points": [[x, y], ...]}`.
    #[error("{file}, line {line} column {column}: bad JSON outline: {reason}")]
    Json {
        file: String,
        line: usize,
        column: usize,
        reason: String,
    },
    /// A coordinate that is NaN or infinite (in the file, or after the unit conversion).
    #[error("{}: non-finite coordinate in {text:?}", loc(.file, &Some(*.pos)))]
    NonFinite {
        file: String,
        pos: Pos,
        text: String,
    },
    /// Fewer than 3 distinct points after dropping duplicates.
    #[error("{file}: an outline needs at least 3 distinct points, found {distinct}")]
    TooFewPoints { file: String, distinct: usize },
    /// Zero, or numerically negligible, enclosed area (collinear points, or loops that cancel).
    #[error(
        "{file}: degenerate outline: signed area {area:e} {units}^2 is negligible against the \
         bounding box ({width:e} x {height:e} {units}); points collinear or loops cancel"
    )]
    ZeroArea {
        file: String,
        area: f64,
        width: f64,
        height: f64,
        units: String,
    },
    /// The outline's size in metres is outside `range`, what a grain can be here
    /// (`outline::SIZE_RANGE`): wrong units, a wrong pixel size, or coordinates that overflow.
    #[error(
        "{file}: the outline spans {w} x {h} {units} = {s} m, outside the {lo:e} to {hi:e} m a \
         grain can span here; check the units (--units) or the pixel size (--px-scale)",
        w = short(*.width), h = short(*.height), s = short(*.size),
        lo = .range[0], hi = .range[1]
    )]
    OutOfScale {
        file: String,
        /// The larger side of the bounding box, in metres (may be inf).
        size: f64,
        width: f64,
        height: f64,
        units: String,
        /// The sizes accepted (m).
        range: [f64; 2],
    },
    /// Two non-adjacent edges meet (cross, touch, or overlap), or two adjacent edges fold back
    /// onto each other.
    #[error(
        "{file}: outline intersects itself: {a} and {b} meet at ({x}, {y}) {units}",
        x = .point[0], y = .point[1]
    )]
    SelfIntersection {
        file: String,
        /// The lower-numbered edge (boxed to keep the error small).
        a: Box<EdgeRef>,
        /// The other edge.
        b: Box<EdgeRef>,
        /// A common point of the two edges, in input units and input (not local) coordinates.
        point: [f64; 2],
        units: String,
    },
    /// A units name that is not one of m, mm, um, µm, micron, px.
    #[error("{}: unknown units {text:?} (expected m, mm, um, µm, micron or px)", loc(.file, .pos))]
    UnknownUnits {
        file: String,
        pos: Option<Pos>,
        text: String,
    },
    /// Pixel units without a pixel size.
    #[error(
        "{}: units are px but no pixel size is known: give ReadOptions.units = \
         Units::Px {{ metres_per_px }} (or `metres_per_px` in the file)",
        loc(.file, .pos)
    )]
    PxWithoutScale { file: String, pos: Option<Pos> },
    /// A pixel size that is not finite and positive.
    #[error("{}: bad pixel size {value} (must be finite and > 0)", loc(.file, .pos))]
    BadScale {
        file: String,
        pos: Option<Pos>,
        value: f64,
    },
    /// An invalid reading option (e.g. resampling to fewer than 3 points).
    #[error("{file}: bad read option: {reason}")]
    BadOption { file: String, reason: String },
    /// An image that cannot be decoded, or is not an 8/16-bit greyscale mask.
    #[error("{file}: cannot read the image: {reason}")]
    Image { file: String, reason: String },
    /// An image read without its pixel size.
    #[error(
        "{file}: an image needs its pixel size: give --units px --px-scale M_PER_PX \
         (library: ReadOptions.units = Units::Px {{ metres_per_px }})"
    )]
    NeedPxScale { file: String },
    /// A mask or GIS file holding no grain (all background, or every grain skipped).
    #[error("{file}: no grain: {reason}")]
    NoGrain { file: String, reason: String },
    /// A GeoJSON or WKT file that cannot be read as polygons.
    #[error("{file}: {reason}")]
    Gis { file: String, reason: String },
    /// GIS coordinates without units, or in degrees of a geographic CRS.
    #[error("{file}: {reason}")]
    GisUnits { file: String, reason: String },
}

/// `x` to 4 significant digits: plain between 0.001 and 10^6 (`7`, `12.35`), else in
/// scientific notation with trailing zeros dropped (`1e201`, not `9.999999999999999e200`).
fn short(x: f64) -> String {
    if x != 0.0 && (1e-3..1e6).contains(&x.abs()) {
        let d = 3 - x.abs().log10().floor() as i32;
        let p = 10f64.powi(d);
        return format!("{}", (x * p).round() / p);
    }
    let s = format!("{x:.3e}");
    match s.split_once('e') {
        Some((m, e)) if m.contains('.') => {
            format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => s,
    }
}

impl OutlineError {
    /// Replace the file name of an error produced without one (e.g. by [`crate::Units::parse`]).
    pub fn with_file(mut self, name: &str) -> Self {
        match &mut self {
            OutlineError::Io { file, .. }
            | OutlineError::Unparsable { file, .. }
            | OutlineError::Json { file, .. }
            | OutlineError::NonFinite { file, .. }
            | OutlineError::TooFewPoints { file, .. }
            | OutlineError::ZeroArea { file, .. }
            | OutlineError::OutOfScale { file, .. }
            | OutlineError::SelfIntersection { file, .. }
            | OutlineError::UnknownUnits { file, .. }
            | OutlineError::PxWithoutScale { file, .. }
            | OutlineError::BadScale { file, .. }
            | OutlineError::BadOption { file, .. }
            | OutlineError::Image { file, .. }
            | OutlineError::NeedPxScale { file }
            | OutlineError::NoGrain { file, .. }
            | OutlineError::Gis { file, .. }
            | OutlineError::GisUnits { file, .. } => *file = name.to_string(),
        }
        self
    }

    /// Set the position of a units error (no-op for other variants).
    pub(crate) fn at(mut self, p: Pos) -> Self {
        match &mut self {
            OutlineError::UnknownUnits { pos, .. }
            | OutlineError::PxWithoutScale { pos, .. }
            | OutlineError::BadScale { pos, .. } => *pos = Some(p),
            _ => {}
        }
        self
    }
}
