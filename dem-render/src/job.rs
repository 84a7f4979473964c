//! One `dem render` call: an input file to a picture (PNG) or a series to an animation (GIF,
//! MP4), the output path chosen and checked (never an input file), with what was written and
//! how long it took for the caller's messages.

use crate::anim::{self, Format};
use crate::draw::{self, Frame, Options};
use crate::error::RenderError;
use crate::load;
use crate::vtk;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What to draw, from which file, into which.
#[derive(Clone, Debug)]
pub struct Job {
    /// A checkpoint, a `last-good-state.json`, a specimen file, a clump template, a VTK
    /// snapshot (`snap-*.vtp`) or a series of them (`snapshots.pvd`: an animation).
    pub input: PathBuf,
    /// The output: a PNG, or for a series a GIF (or an MP4 with ffmpeg on PATH); `None`: the
    /// input's name with .png (.gif for a series), beside it ([`default_out`]).
    pub out: Option<PathBuf>,
    /// A template's grain outline file (`None`: the file the template names).
    pub outline: Option<PathBuf>,
    /// Frames per second of an animation (1 to 100).
    pub fps: u32,
    /// How to draw.
    pub options: Options,
}

/// What [`run`] wrote.
#[derive(Clone, Debug)]
pub enum Written {
    /// One picture.
    Picture {
        /// The PNG written.
        out: PathBuf,
        /// Width (px).
        width: u32,
        /// Height (px).
        height: u32,
        /// Discs in the picture.
        discs: usize,
        /// Where model coordinates land in the image.
        frame: Frame,
        /// Time reading the input (s).
        read_s: f64,
        /// Time drawing (s).
        draw_s: f64,
        /// Time encoding the PNG (s).
        encode_s: f64,
    },
    /// An animation of a series.
    Animation {
        /// The GIF or MP4 written.
        out: PathBuf,
        /// Frames (one per disc snapshot).
        frames: usize,
        /// Width (px).
        width: u32,
        /// Height (px).
        height: u32,
        /// Frames per second.
        fps: u32,
        /// Time reading the snapshots (s).
        read_s: f64,
        /// Time drawing and encoding the frames (s).
        draw_s: f64,
    },
}

/// `x.json` → `x.png` beside it; a series `x.pvd` → `x.gif`.
pub fn default_out(input: &Path) -> PathBuf {
    if is_series(input) {
        input.with_extension("gif")
    } else {
        input.with_extension("png")
    }
}

fn has_ext(p: &Path, ext: &str) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

fn is_series(p: &Path) -> bool {
    has_ext(p, "pvd")
}

/// The path with its folder made absolute and canonical (the file itself need not exist), to
/// tell whether two names are one file.
fn canonical(p: &Path) -> PathBuf {
    if let Ok(c) = p.canonicalize() {
        return c;
    }
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    match (dir.canonicalize(), p.file_name()) {
        (Ok(d), Some(n)) => d.join(n),
        _ => p.to_path_buf(),
    }
}

/// Runs `dem render`: reads `job.input`, draws it and writes the picture or animation;
/// `note` gets each remark on the input (an outline not found, no velocities) as it comes.
pub fn run(job: &Job, note: &mut dyn FnMut(&str)) -> Result<Written, RenderError> {
    let out = job.out.clone().unwrap_or_else(|| default_out(&job.input));
    let out_c = canonical(&out);
    let mut inputs = vec![("the input", job.input.as_path())];
    if let Some(o) = &job.outline {
        inputs.push(("the outline (--outline)", o.as_path()));
    }
    for (what, p) in inputs {
        if canonical(p) == out_c {
            return Err(RenderError::output(
                &out,
                format!("is {what} {}; give another output file", p.display()),
            ));
        }
    }
    let format = if has_ext(&out, "gif") {
        Some(Format::Gif)
    } else if has_ext(&out, "mp4") {
        Some(Format::Mp4)
    } else {
        None
    };
    if is_series(&job.input) {
        let Some(format) = format else {
            return Err(RenderError::output(
                &out,
                format!(
                    "a series ({}) is an animation: give a .gif (or .mp4 with ffmpeg)",
                    job.input.display()
                ),
            ));
        };
        return animate(job, &out, format, note);
    }
    if format.is_some() {
        return Err(RenderError::output(
            &out,
            "animations are made from a series (snapshots.pvd); one picture is a .png",
        ));
    }
    let t0 = Instant::now();
    let picture = load::load(&job.input, job.outline.as_deref())?;
    let t1 = Instant::now();
    for n in &picture.notes {
        note(n);
    }
    let r = draw::render(&picture, &job.options).map_err(|e| e.inside(&job.input))?;
    let t2 = Instant::now();
    clumpgen::io::write_atomic(&out, &r.png)
        .map_err(|e| RenderError::output(&out, format!("cannot write: {e}")))?;
    Ok(Written::Picture {
        out,
        width: r.width,
        height: r.height,
        discs: picture.discs.len(),
        frame: r.frame,
        read_s: (t1 - t0).as_secs_f64(),
        draw_s: (t2 - t1).as_secs_f64() - r.encode_s,
        encode_s: r.encode_s,
    })
}

/// `dem render SERIES.pvd --out FILE.gif|mp4`: every disc snapshot a frame, one view and one
/// speed scale for all (the union of the frames' extents and their top speed, unless the
/// options give them).
fn animate(
    job: &Job,
    out: &Path,
    format: Format,
    note: &mut dyn FnMut(&str),
) -> Result<Written, RenderError> {
    if !(1..=100).contains(&job.fps) {
        return Err(RenderError::Fps { fps: job.fps });
    }
    if format == Format::Mp4 && anim::ffmpeg().is_none() {
        return Err(RenderError::output(
            out,
            "an MP4 is made by ffmpeg, which is not on PATH; install it or write a .gif",
        ));
    }
    let input = &job.input;
    let mut opts = job.options.clone();
    let t0 = Instant::now();
    let series = vtk::read_pvd(input)?;
    let out_c = canonical(out);
    let mut pics = Vec::with_capacity(series.len());
    for (t, file) in &series {
        if canonical(file) == out_c {
            return Err(RenderError::output(
                out,
                format!(
                    "is a file of the series {}; give another output file",
                    input.display()
                ),
            ));
        }
        if !file.is_file() {
            return Err(RenderError::file(
                input.display(),
                format!("names {}, which does not exist", file.display()),
            ));
        }
        let p = vtk::load_vtp(file, Some(*t)).map_err(|e| e.inside(input))?;
        pics.push(p);
    }
    if let Some(first) = pics.first() {
        for n in &first.notes {
            note(n);
        }
    }
    if opts.view.is_none() {
        opts.view = Some(anim::union_view(&pics).ok_or_else(|| {
            RenderError::file(
                input.display(),
                "nothing to draw: no disc or wall in any snapshot",
            )
        })?);
    }
    if opts.speed_max.is_none() {
        let top = pics
            .iter()
            .flat_map(|p| p.discs.iter().map(|d| d.speed))
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
        opts.speed_max = (top > 0.0).then_some(top);
    }
    let t1 = Instant::now();
    let (width, height) =
        anim::animate(&pics, &opts, job.fps, format, out).map_err(|e| e.inside(input))?;
    Ok(Written::Animation {
        out: out.to_path_buf(),
        frames: pics.len(),
        width,
        height,
        fps: job.fps,
        read_s: (t1 - t0).as_secs_f64(),
        draw_s: t1.elapsed().as_secs_f64(),
    })
}
