//! [`RenderError`]: why a file could not be drawn or a picture not written. Every message names
//! the file (or the output, `--out FILE`) and says why, as `dem render` prints it.

use std::path::Path;

/// Why a file could not be read and drawn, or its picture or animation not written. The
/// messages are the ones `dem render` prints: each names the file (the output as `--out FILE`,
/// a field of a specimen file, an array of a VTK file) and the reason.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// A file could not be read (missing, a folder, too large, not UTF-8 text).
    #[error("{file}: cannot read: {source}")]
    Read {
        /// The file as given.
        file: String,
        /// Why not.
        source: std::io::Error,
    },
    /// A file that is not one `dem render` draws, or whose content is wrong (a VTK element or
    /// attribute, a count, a non-finite value, a series that lists a missing file).
    #[error("{file}: {reason}")]
    File {
        /// The file as given.
        file: String,
        /// What is wrong, and where in the file.
        reason: String,
    },
    /// A field of a specimen file: a disc or a template that does not exist, a count that does
    /// not match.
    #[error("{file}: field {field}: {reason}")]
    Field {
        /// The specimen file.
        file: String,
        /// The field's path (`bonds[0].pairs[3]`).
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A `<DataArray>` of a VTK file: its format, type, base64 data or values.
    #[error("{file}: array {name:?} ({section}): {reason}")]
    Array {
        /// The VTK file.
        file: String,
        /// The array's `Name` (empty where it has none).
        name: String,
        /// The section it is in (`PointData`, `CellData`, `Points`, `Lines`, …).
        section: String,
        /// What is wrong.
        reason: String,
    },
    /// A checkpoint that does not parse (the message names the file and the field).
    #[error(transparent)]
    Checkpoint(#[from] dem_core::checkpoint::CheckpointError),
    /// A clump template that does not parse (the message names the file and the field).
    #[error(transparent)]
    Template(#[from] clumpgen::template::TemplateError),
    /// A template's grain outline file that does not read (the message names the file).
    #[error(transparent)]
    Outline(#[from] clumpgen::OutlineError),
    /// The output file: the same file as an input, the wrong kind for the input, not
    /// writable, or its encoder (GIF, ffmpeg) failed.
    #[error("--out {file}: {reason}")]
    Output {
        /// The output file as given.
        file: String,
        /// What is wrong.
        reason: String,
    },
    /// An image width outside 1 to `max` pixels.
    #[error("--width: {width} px is not in 1..={max}")]
    Width {
        /// The width asked for (px).
        width: u32,
        /// The widest image drawn ([`crate::MAX_WIDTH`]).
        max: u32,
    },
    /// A frame rate outside 1 to 100 frames per second.
    #[error("{fps}: frames per second must be 1 to 100")]
    Fps {
        /// The frame rate asked for.
        fps: u32,
    },
    /// No disc, wall or outline to draw, and no view given.
    #[error("nothing to draw: no disc, wall or outline")]
    Empty,
    /// The image's pixels could not be allocated.
    #[error("cannot allocate a {width} x {height} px image")]
    Alloc {
        /// Width (px).
        width: u32,
        /// Height (px).
        height: u32,
    },
    /// The PNG encoder failed.
    #[error("PNG encoding: {0}")]
    Png(#[from] png::EncodingError),
    /// An animation frame could not be made (`empty frame`, `cannot make a frame`).
    #[error("{0}")]
    Frame(&'static str),
    /// A program (ffmpeg) that could not be started or waited for.
    #[error("{program}: {reason}")]
    Program {
        /// The program's path.
        program: String,
        /// What went wrong.
        reason: String,
    },
    /// An error drawing `file` (the input of a picture, or a series whose snapshot failed).
    #[error("{file}: {source}")]
    In {
        /// The input file as given.
        file: String,
        /// What went wrong.
        source: Box<RenderError>,
    },
}

impl RenderError {
    /// [`RenderError::File`] for `file` (a path or a name as given) and `reason`.
    pub(crate) fn file(file: impl ToString, reason: impl Into<String>) -> RenderError {
        RenderError::File {
            file: file.to_string(),
            reason: reason.into(),
        }
    }

    /// [`RenderError::Read`] for `file` and an I/O error (or another reason as one).
    pub(crate) fn read(file: impl ToString, source: std::io::Error) -> RenderError {
        RenderError::Read {
            file: file.to_string(),
            source,
        }
    }

    /// [`RenderError::Output`] for the output `file` and `reason`.
    pub(crate) fn output(file: &Path, reason: impl Into<String>) -> RenderError {
        RenderError::Output {
            file: file.display().to_string(),
            reason: reason.into(),
        }
    }

    /// This error as met drawing `file`: [`RenderError::In`].
    pub(crate) fn inside(self, file: &Path) -> RenderError {
        RenderError::In {
            file: file.display().to_string(),
            source: Box::new(self),
        }
    }
}
