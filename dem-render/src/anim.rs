//! Animations: every disc snapshot of a `.pvd` series drawn with one view and one speed scale,
//! written as an animated GIF (`image`'s GIF encoder) or, when `ffmpeg` is on PATH, an MP4
//! (PNG frames piped to it).

use crate::draw::{self, Options};
use crate::error::RenderError;
use crate::picture::Picture;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame as GifFrame, RgbaImage};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The container an animation is written in, from the output's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Animated GIF.
    Gif,
    /// H.264 MP4 through ffmpeg.
    Mp4,
}

/// `ffmpeg` on PATH, if there is one.
pub fn ffmpeg() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join("ffmpeg"))
        .find(|p| p.is_file())
}

/// Union of the pictures' content boxes (m).
pub fn union_view(pics: &[Picture]) -> Option<[f64; 4]> {
    pics.iter().filter_map(draw::content_box).reduce(|a, b| {
        [
            a[0].min(b[0]),
            a[1].max(b[1]),
            a[2].min(b[2]),
            a[3].max(b[3]),
        ]
    })
}

/// Draws every picture with `o` (its view and speed scale fixed by the caller) and encodes
/// the frames; returns the file's bytes (GIF) or writes the MP4 through ffmpeg to `out`
/// (atomically, via a temporary file beside it). Frames of different heights (a caption that
/// wraps) are padded with background at the bottom to the tallest.
pub fn animate(
    pics: &[Picture],
    o: &Options,
    fps: u32,
    format: Format,
    out: &Path,
) -> Result<(u32, u32), RenderError> {
    let mut frames = Vec::with_capacity(pics.len());
    for p in pics {
        let (pm, _) = draw::draw(p, o)?;
        frames.push(pm);
    }
    let w = o.width;
    let h = frames.iter().map(|f| f.height()).max().unwrap_or(1);
    let images: Vec<RgbaImage> = frames
        .iter()
        .map(|f| {
            let mut img = RgbaImage::from_pixel(w, h, image::Rgba([255, 255, 255, 255]));
            // Opaque background: premultiplied RGBA is plain RGBA.
            for (y, row) in f.data().chunks_exact(4 * w as usize).enumerate() {
                for (x, px) in row.chunks_exact(4).enumerate() {
                    img.put_pixel(x as u32, y as u32, image::Rgba([px[0], px[1], px[2], 255]));
                }
            }
            img
        })
        .collect();
    match format {
        Format::Gif => {
            let mut bytes = Vec::new();
            {
                let mut e = GifEncoder::new_with_speed(&mut bytes, 10);
                e.set_repeat(Repeat::Infinite)
                    .map_err(|e| RenderError::output(out, format!("GIF encoding: {e}")))?;
                let delay = Delay::from_numer_denom_ms(1000, fps);
                for img in images {
                    e.encode_frame(GifFrame::from_parts(img, 0, 0, delay))
                        .map_err(|e| RenderError::output(out, format!("GIF encoding: {e}")))?;
                }
            }
            clumpgen::io::write_atomic(out, &bytes)
                .map_err(|e| RenderError::output(out, format!("cannot write: {e}")))?;
        }
        Format::Mp4 => {
            let ff = ffmpeg().ok_or_else(|| {
                RenderError::output(out, "an MP4 needs ffmpeg on PATH (not found); write a .gif")
            })?;
            let tmp = out.with_extension(format!("tmp-{}.mp4", std::process::id()));
            let mut child = Command::new(&ff)
                .args(["-y", "-loglevel", "error", "-f", "image2pipe", "-framerate"])
                .arg(fps.to_string())
                .args([
                    "-c:v", "png", "-i", "-", "-c:v", "libx264", "-pix_fmt", "yuv420p",
                ])
                .args(["-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2:color=white"])
                .arg(&tmp)
                .stdin(Stdio::piped())
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .map_err(|e| RenderError::Program {
                    program: ff.display().to_string(),
                    reason: format!("cannot start: {e}"),
                })?;
            let mut fed = Ok(());
            if let Some(mut stdin) = child.stdin.take() {
                for img in &images {
                    let pm = tiny_skia::Pixmap::from_vec(
                        img.as_raw().clone(),
                        tiny_skia::IntSize::from_wh(w, h)
                            .ok_or(RenderError::Frame("empty frame"))?,
                    )
                    .ok_or(RenderError::Frame("cannot make a frame"))?;
                    let png = draw::encode_png(&pm, true)?;
                    if let Err(e) = stdin.write_all(&png) {
                        fed = Err(e);
                        break;
                    }
                }
            }
            let res = child.wait_with_output().map_err(|e| RenderError::Program {
                program: ff.display().to_string(),
                reason: e.to_string(),
            })?;
            if !res.status.success() || fed.is_err() {
                let _ = std::fs::remove_file(&tmp);
                return Err(RenderError::output(
                    out,
                    format!(
                        "ffmpeg failed ({}): {}",
                        res.status,
                        String::from_utf8_lossy(&res.stderr).trim()
                    ),
                ));
            }
            std::fs::rename(&tmp, out).map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                RenderError::output(out, format!("cannot write: {e}"))
            })?;
        }
    }
    Ok((w, h))
}
