//! `dem render`: a PNG picture of a checkpoint, a `last-good-state.json`, a specimen file, a
//! clump template (the kind is read from the file's `schema` field) or a VTK snapshot
//! (`snap-*.vtp`), and animations of a `.pvd` series. The flags and the messages are here; the
//! loading, drawing and writing are the `dem-render` crate's ([`dem_render::run`]).

use clap::Args;
use dem_render::{ColorBy, Job, Options, Written};
use std::path::PathBuf;
use std::process::ExitCode;

/// Flags of `dem render`.
#[derive(Args)]
#[command(after_help = "\
The picture: discs as filled circles, walls and the tool as thick grey lines, a scale bar in \
mm, a legend (speed: a colour bar) and a caption (file, step and time, counts). A template is \
drawn over its grain outline (read from the outline file the template names, found as given \
or beside the template; or --outline), with the grain centroid (+) and, where it differs, the \
clump's mass centre (x).

A VTK snapshot (snap-*.vtp, from a scene with outputs.vtk_every) gives discs (points and their \
`radius`), speed (`velocity`), grains (`body`, `group`), materials (by index) and bonds (its \
line cells, `bond_state` 1 intact, 0 broken; bond groups by index); the walls come from \
walls-*.vtp beside it, without names (the tool is drawn as a wall). A snapshot cannot carry \
where a bond broke (--broken marks it midway between the two centres), nor material or \
bond-group names: use a checkpoint for those. The VTK that dem run writes is read, ASCII or \
binary (outputs.vtk_format: base64, inline or appended; not compressed).

A series (snapshots.pvd) is drawn as an animation, one frame per disc snapshot in time order, \
all with one view (the union of the frames' extents, or --view) and one speed scale, the \
step and time in each frame's caption: an animated GIF (default: the .pvd's name with .gif), \
or an MP4 with --out FILE.mp4 when ffmpeg is on PATH.

After writing, one line gives the image size and where model coordinates land: column = c0 + \
s*x, row = r0 - s*y (x, y in mm; s in px/mm).

Examples:
  dem render out/ckpt-final.json --bonds
  dem render si3n4-improved.json --color group --out specimen.png
  dem render out/templates/equant-01.json --width 600
  dem render run/ckpt-final.json --view 4,16,4,11 --color speed
  dem render run/snap-000020000.vtp --color speed
  dem render run/snapshots.pvd --out cut.gif --fps 12 --width 600")]
pub struct RenderArgs {
    /// Input: a checkpoint (ckpt-*.json or ckpt-*.bin), a last-good-state.json, a specimen file
    /// (`dem specimen`), a clump template (`dem clump`), a VTK snapshot (snap-*.vtp) or a
    /// series of them (snapshots.pvd: an animation).
    input: PathBuf,
    /// Output PNG, or for a .pvd series a .gif (or .mp4 with ffmpeg on PATH); default: the
    /// input's name with .png (.gif for a series), beside it. Never an input file.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Frames per second of an animation (1 to 100; a GIF keeps 1/100 s delays).
    #[arg(long, value_name = "N", default_value_t = 10, value_parser = parse_fps)]
    fps: u32,
    /// Image width in pixels (1 to 6000); the height follows from the drawn region's aspect
    /// ratio (at most twice the width) plus the caption.
    #[arg(
        long,
        value_name = "PX",
        default_value_t = 1200,
        value_parser = parse_width
    )]
    width: u32,
    /// Disc colours: grain (rigid or bonded clump, specimen grain; touching grains differ;
    /// where some grains have several discs, one-disc grains are plain beige-grey),
    /// group (bonds coloured by bond group over grey discs; darker grey: no intact bond),
    /// speed (|v| on a colour scale, with a colour bar) or material.
    #[arg(long, value_name = "KIND", default_value = "grain", value_parser = parse_color)]
    color: ColorBy,
    /// Draw intact bonds as thin lines between disc centres.
    #[arg(long)]
    bonds: bool,
    /// Draw broken bonds (checkpoints keep them) as red crack marks where they broke, across
    /// the line of the two discs' centres, as long as the bond was wide.
    #[arg(long)]
    broken: bool,
    /// Draw only this region, in mm: XMIN,XMAX,YMIN,YMAX (default: everything, e.g. chips
    /// that flew far included).
    #[arg(
        long,
        value_name = "XMIN,XMAX,YMIN,YMAX",
        value_parser = parse_view
    )]
    view: Option<[f64; 4]>,
    /// Top of the speed scale in m/s (default: the largest speed in the file).
    #[arg(long, value_name = "M/S", value_parser = |s: &str| crate::specimen::parse_speed(s, "--speed-max"))]
    speed_max: Option<f64>,
    /// Write 24-bit RGB; by default the PNG has 256 palette colours (the flat colours exact,
    /// anti-aliased edges to the nearest kept colour), about a third of the size.
    #[arg(long)]
    rgb: bool,
    /// Grain outline file of a template (default: the file the template names).
    #[arg(long, value_name = "FILE")]
    outline: Option<PathBuf>,
}

fn parse_width(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(w) if (1..=dem_render::MAX_WIDTH).contains(&w) => Ok(w),
        Ok(w) => Err(format!(
            "{w} px: the width must be 1 to {} pixels",
            dem_render::MAX_WIDTH
        )),
        Err(e) => Err(format!("{e} (a width in pixels, e.g. 1200)")),
    }
}

fn parse_fps(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(f) if (1..=100).contains(&f) => Ok(f),
        Ok(f) => Err(format!("{f}: frames per second must be 1 to 100")),
        Err(e) => Err(format!("{e} (frames per second, e.g. 10)")),
    }
}

fn parse_color(s: &str) -> Result<ColorBy, String> {
    match s.trim() {
        "grain" => Ok(ColorBy::Grain),
        "group" => Ok(ColorBy::Group),
        "speed" => Ok(ColorBy::Speed),
        "material" => Ok(ColorBy::Material),
        other => Err(format!(
            "{other:?} is not a colouring: grain, group, speed or material"
        )),
    }
}

fn parse_view(s: &str) -> Result<[f64; 4], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{e}: four numbers in mm, XMIN,XMAX,YMIN,YMAX"))?;
    let [x0, x1, y0, y1] = v[..] else {
        return Err(format!(
            "{} numbers: four in mm are needed, XMIN,XMAX,YMIN,YMAX",
            v.len()
        ));
    };
    if !v.iter().all(|x| x.is_finite()) || x0 >= x1 || y0 >= y1 {
        return Err("need finite XMIN < XMAX and YMIN < YMAX (mm)".into());
    }
    Ok([x0 * 1e-3, x1 * 1e-3, y0 * 1e-3, y1 * 1e-3])
}

/// Runs `dem render`.
pub fn run(a: RenderArgs) -> Result<ExitCode, String> {
    let job = Job {
        input: a.input,
        out: a.out,
        outline: a.outline,
        fps: a.fps,
        options: Options {
            width: a.width,
            color: a.color,
            bonds: a.bonds,
            broken: a.broken,
            view: a.view,
            speed_max: a.speed_max,
            rgb: a.rgb,
        },
    };
    let written =
        dem_render::run(&job, &mut |n| eprintln!("note: {n}")).map_err(|e| e.to_string())?;
    match written {
        Written::Picture {
            out,
            width,
            height,
            discs,
            frame: f,
            read_s,
            draw_s,
            encode_s,
        } => {
            println!(
                "wrote {}: {} x {} px, {} discs; {:.4} px/mm, (0, 0) mm at column {:.2}, row {:.2}",
                out.display(),
                width,
                height,
                discs,
                f.s * 1e-3,
                f.c0,
                f.r0
            );
            println!(
                "read in {:.0} ms, drawn in {:.0} ms, PNG encoded in {:.0} ms",
                read_s * 1e3,
                draw_s * 1e3,
                encode_s * 1e3
            );
        }
        Written::Animation {
            out,
            frames,
            width,
            height,
            fps,
            read_s,
            draw_s,
        } => {
            println!(
                "wrote {}: {} frames of {} x {} px at {} fps ({:.2} s)",
                out.display(),
                frames,
                width,
                height,
                fps,
                frames as f64 / fps as f64
            );
            println!(
                "read in {:.0} ms, drawn and encoded in {:.0} ms",
                read_s * 1e3,
                draw_s * 1e3
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
