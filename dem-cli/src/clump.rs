//! `dem clump`: a batch of outlines to templates, in parallel, one failure never stopping the rest.

use crate::progress::Progress;
use clap::Args;
use clumpgen::batch::{
    collect_inputs_except, plan, plan_clashes, run_plan, BatchItem, BatchOptions, SUMMARY_FILE,
};
use clumpgen::clump::LatticeParams;
use clumpgen::export::Format;
use clumpgen::outline::{
    GrainOptions, MaskMode, MultiKind, MAX_RESAMPLE, MAX_RESAMPLE_WHY, MULTI_EXTENSIONS,
};
use clumpgen::{ClumpParams, Length, Method, ReadOptions, Units};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct ClumpArgs {
    /// Outline files (CSV/whitespace `x y` or JSON), masks and labelled images (PNG, TIFF),
    /// GeoJSON or WKT polygons, or folders searched recursively.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Output folder; templates mirror the input folders below their common folder, one
    /// `<name>.json` per grain (`<file stem>/<grain>.json` for an image, GeoJSON or WKT file).
    /// Refused if two grains would share a template or a template would overwrite an input.
    #[arg(long)]
    out: PathBuf,
    /// Target area cover A_r.
    #[arg(long, default_value_t = 0.95)]
    cover: f64,
    /// Smallest disc radius: a fraction of the grain's equivalent radius (`0.05`) or a length
    /// with unit (`20um`, `0.1mm`, `1e-4m`).
    #[arg(long, default_value = "0.02")]
    rmin: String,
    /// Largest disc radius, same forms as --rmin.
    #[arg(long, default_value = "1.0")]
    rmax: String,
    /// Largest number of discs per clump, at most 1000 (the paper's cutting specimens use 9).
    #[arg(long, default_value_t = ClumpParams::default().max_discs)]
    max_discs: usize,
    /// `improved` (exact mass, centroid, inertia), `orc` (summed uniform discs) or `lattice`
    /// (triangular node lattice of spacing --spacing with its links, exact mass, centroid,
    /// inertia; docs/lattice.md).
    #[arg(long, default_value = "improved")]
    method: String,
    /// Lattice node spacing S for --method lattice: a fraction of the grain's equivalent
    /// radius (`0.1`) or a length with unit (`50um`, `0.2mm`).
    #[arg(long)]
    spacing: Option<String>,
    /// Lattice node disc radius as a fraction of S/2, in (0, 1] (1: neighbours touch).
    #[arg(long, default_value_t = 1.0)]
    node_radius: f64,
    /// Grain density (kg/m^3).
    #[arg(long, default_value_t = 2650.0)]
    density: f64,
    /// Disc thickness t (m).
    #[arg(long, default_value_t = 1.0)]
    thickness: f64,
    /// Units of the outline files, overriding what they declare (m, mm, um, px). Required for
    /// GeoJSON and WKT; images need `--units px --px-scale`.
    #[arg(long)]
    units: Option<String>,
    /// Metres per pixel, for `--units px` (and so for images: the side of one pixel).
    #[arg(long)]
    px_scale: Option<f64>,
    /// Images: `binary` (one grain per 4-connected component of nonzero pixels), `labels` (one
    /// grain per nonzero value) or `auto` (labels when the image has more than 2 values).
    #[arg(long, default_value = "auto", value_parser = parse_mask)]
    mask: MaskMode,
    /// Binary masks: the grains are the zero pixels.
    #[arg(long)]
    invert: bool,
    /// Images: skip grains of fewer pixels (counted in a note).
    #[arg(long, default_value_t = GrainOptions::default().min_pixels)]
    min_pixels: usize,
    /// Images: simplify each pixel outline (Ramer-Douglas-Peucker) at this tolerance in pixels,
    /// e.g. 0.5; 0 (default) keeps the exact pixel outline.
    #[arg(long, default_value_t = 0.0)]
    simplify: f64,
    /// Resample each outline to this many equally spaced points first (3 to 1000000).
    #[arg(long)]
    resample: Option<usize>,
    /// Raster cells along a grain's longer side (steers the fill only; refined ×2, ×4 where it
    /// is too coarse to reach the cover), 1 to 1024.
    #[arg(long, default_value_t = ClumpParams::default().raster)]
    raster: usize,
    /// A grain whose discs stop below the --cover target is a failure (not written, exit 1)
    /// instead of a template written with a warning.
    #[arg(long)]
    strict: bool,
    /// Worker threads, at least 1 (default: all cores).
    #[arg(long, value_parser = crate::parse_threads)]
    threads: Option<usize>,
    /// Also write each template for other DEM codes, beside it: `pfc` (PFC2D clump template,
    /// `<name>.pfc.p2dat`), `yade` (Python, `<name>.yade.py`), `lammps` (molecule file,
    /// `<name>.lammps.mol`), `mercury` (MercuryDPM clump folder, `<name>.mercury/`). Several:
    /// `--export pfc,yade` or the flag repeated. See docs/exports.md.
    #[arg(long, value_delimiter = ',', value_parser = parse_export, value_name = "FORMAT")]
    export: Vec<Format>,
}

/// `--mask` values.
fn parse_mask(s: &str) -> Result<MaskMode, String> {
    match s {
        "auto" => Ok(MaskMode::Auto),
        "binary" => Ok(MaskMode::Binary),
        "labels" => Ok(MaskMode::Labels),
        _ => Err("expected auto, binary or labels".into()),
    }
}

/// `--export` values: one of the formats of [`Format::ALL`].
fn parse_export(s: &str) -> Result<Format, String> {
    Format::parse(s).ok_or_else(|| {
        let names: Vec<&str> = Format::ALL.iter().map(|f| f.name()).collect();
        format!("expected one of {}", names.join(", "))
    })
}

/// `0.05` → fraction of R_eq; `20um`, `0.1mm`, `1e-4m` → metres.
pub(crate) fn parse_length(s: &str, what: &str) -> Result<Length, String> {
    let s = s.trim();
    for (suffix, scale) in [("um", 1e-6), ("µm", 1e-6), ("mm", 1e-3), ("m", 1.0)] {
        if let Some(num) = s.strip_suffix(suffix) {
            let v: f64 = num
                .trim()
                .parse()
                .map_err(|_| format!("--{what} {s:?}: not a number with unit"))?;
            return Ok(Length::Metres(v * scale));
        }
    }
    s.parse::<f64>()
        .map(Length::OfReq)
        .map_err(|_| format!("--{what} {s:?}: expected a fraction of R_eq or a length like 0.1mm"))
}

pub fn run(a: ClumpArgs) -> Result<ExitCode, String> {
    let method = match a.method.as_str() {
        "improved" => Method::Improved,
        "orc" => Method::Orc,
        "lattice" => Method::Lattice,
        m => return Err(format!("--method {m:?}: expected improved, orc or lattice")),
    };
    let lattice = match (method, a.spacing.as_deref()) {
        (Method::Lattice, None) => {
            return Err("--method lattice needs --spacing S (e.g. 0.1 or 50um)".into())
        }
        (Method::Lattice, Some(s)) => Some(LatticeParams {
            spacing: parse_length(s, "spacing")?,
            node_radius: a.node_radius,
        }),
        (_, Some(_)) => return Err("--spacing is for --method lattice".into()),
        (_, None) => None,
    };
    let units = match (a.units.as_deref(), a.px_scale) {
        (None, Some(_)) => return Err("--px-scale is for --units px; give --units px".into()),
        (Some(u), s) => Some(Units::parse(u, s).map_err(|e| units_message(u, &e))?),
        (None, None) => None,
    };
    let params = ClumpParams {
        method,
        density: a.density,
        thickness: a.thickness,
        cover: a.cover,
        r_min: parse_length(&a.rmin, "rmin")?,
        r_max: parse_length(&a.rmax, "rmax")?,
        max_discs: a.max_discs,
        raster: a.raster,
        lattice,
        ..ClumpParams::default()
    };
    // Errors of the batch's own flags are one usage error, not one failure per grain.
    params.check().map_err(|e| {
        let value = match e.name {
            "rmin" => a.rmin.clone(),
            "rmax" => a.rmax.clone(),
            "spacing" => a.spacing.clone().unwrap_or_default(),
            _ => e.value.clone(),
        };
        format!("--{} {value}: {}", e.name, e.reason)
    })?;
    if let Some(n) = a.resample.filter(|&n| n < 3) {
        return Err(format!(
            "--resample {n}: an outline needs at least 3 points"
        ));
    }
    if let Some(n) = a.resample.filter(|&n| n > MAX_RESAMPLE) {
        return Err(format!(
            "--resample {n}: at most {MAX_RESAMPLE} points: {MAX_RESAMPLE_WHY}"
        ));
    }
    let opts = BatchOptions {
        read: ReadOptions {
            units,
            resample: a.resample,
        },
        params,
        out: a.out.clone(),
        exports: {
            let mut e = a.export.clone();
            e.sort();
            e.dedup();
            e
        },
        strict: a.strict,
        grains: GrainOptions {
            mask: a.mask,
            invert: a.invert,
            min_pixels: a.min_pixels,
            simplify: a.simplify,
        },
    };
    let inputs = collect_inputs_except(&a.inputs, Some(&a.out)).map_err(|e| e.to_string())?;
    if inputs.is_empty() {
        // Only folders can come back empty (a file given by name is read whatever its
        // extension), so name them: a folder called `x.csv` is otherwise a puzzle.
        let folders: Vec<String> = a.inputs.iter().map(|p| p.display().to_string()).collect();
        return Err(format!(
            "no outline files found in the folder{} {} (looked for .csv, .txt, .xy, .dat, .json, \
             .{} inside)",
            if folders.len() == 1 { "" } else { "s" },
            folders.join(", "),
            MULTI_EXTENSIONS.join(", .")
        ));
    }
    // Flags an input kind needs are usage errors, said once.
    let kind_of = |k: MultiKind| inputs.iter().find(|i| MultiKind::of(&i.path) == Some(k));
    if let Some(i) = kind_of(MultiKind::Image).filter(|_| !matches!(units, Some(Units::Px { .. })))
    {
        return Err(format!(
            "{} is an image: give its pixel size with --units px --px-scale M_PER_PX",
            i.path.display()
        ));
    }
    if units.is_none() {
        if let Some(i) = kind_of(MultiKind::GeoJson).or_else(|| kind_of(MultiKind::Wkt)) {
            return Err(format!(
                "{}: GIS coordinates carry no length unit: give --units m|mm|um (coordinates in \
                 degrees must be projected first)",
                i.path.display()
            ));
        }
    }
    if !(a.simplify.is_finite() && a.simplify >= 0.0) {
        return Err(format!(
            "--simplify {}: a tolerance in pixels, finite and >= 0",
            a.simplify
        ));
    }
    if a.invert && a.mask == MaskMode::Labels {
        return Err("--invert is for binary masks, not --mask labels".into());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| e.to_string())?;
    // Multi-grain files are read first: their grains are known only then.
    let plan = pool.install(|| plan(&inputs, &opts));
    // Outputs never collide: two grains for one template, or a template (or the summary)
    // over an input, refuse the batch before anything is written.
    let clash = plan_clashes(&inputs, &plan, &a.out, &opts.exports);
    if !clash.is_empty() {
        let list: Vec<String> = clash.iter().map(|c| format!("  {}", c.message)).collect();
        return Err(format!(
            "{} of {} grains cannot be written into {} (nothing written):\n{}",
            clash.iter().map(|c| c.inputs.len()).sum::<usize>(),
            plan.jobs.len(),
            a.out.display(),
            list.join("\n")
        ));
    }
    let bar = Progress::counted(plan.jobs.len() as u64, "grains");
    let report = pool.install(|| run_plan(&inputs, plan, &opts, &|| bar.inc(1)));
    bar.finish_and_clear();
    let failed: Vec<&BatchItem> = report.items.iter().filter(|i| i.error.is_some()).collect();
    println!("{}", report.summary_table());
    for line in export_lines(&opts.exports, &report.items) {
        println!("{line}");
    }
    if let Err(e) = report.save(&a.out.join(SUMMARY_FILE)) {
        eprintln!("error: {e}");
    }
    for n in &report.notes {
        eprintln!("note: {n}");
    }
    for i in &report.items {
        let g = i.grain.as_deref().unwrap_or("");
        for n in &i.notes {
            if n.starts_with(g) {
                eprintln!("warning: {}, {n}", i.input);
            } else {
                eprintln!("warning: {}, {g}: {n}", i.input);
            }
        }
    }
    for (_, w) in report.warnings() {
        eprintln!("warning: {w}");
    }
    if failed.is_empty() {
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!("{} of {} grains failed:", failed.len(), report.items.len());
        for f in failed {
            eprintln!("  {}", f.error.as_deref().unwrap_or(""));
        }
        Ok(ExitCode::from(1))
    }
}

/// A `--units`/`--px-scale` error as a flag message (the library's names no file here).
fn units_message(u: &str, e: &clumpgen::OutlineError) -> String {
    match e {
        clumpgen::OutlineError::PxWithoutScale { .. } => {
            format!("--units {u}: give the pixel size with --px-scale M_PER_PX")
        }
        clumpgen::OutlineError::BadScale { value, .. } => {
            format!("--px-scale {value}: must be finite and > 0")
        }
        clumpgen::OutlineError::UnknownUnits { text, .. } => {
            format!("--units {text:?}: expected m, mm, um, µm, micron or px")
        }
        e => format!("--units {u}: {e}"),
    }
}

/// One line per export format: what was written and, where the format cannot carry the
/// template's mass properties exactly, what is lost (with the range of the figure over the
/// grains: the LAMMPS inertia shortfall of bodies built from atoms).
fn export_lines(formats: &[Format], items: &[BatchItem]) -> Vec<String> {
    let ok: Vec<&BatchItem> = items.iter().filter(|i| i.error.is_none()).collect();
    formats
        .iter()
        .map(|&f| {
            let head = format!("export {:<8} {} grains", f.name(), ok.len());
            let Some(limit) = f.limitation() else {
                return format!("{head}: exact mass, centroid and inertia");
            };
            let rel: Vec<f64> = ok
                .iter()
                .flat_map(|i| &i.caveats)
                .filter(|c| c.format == f.name())
                .map(|c| c.rel)
                .collect();
            let range = match (
                rel.iter().copied().reduce(f64::min),
                rel.iter().copied().reduce(f64::max),
            ) {
                (Some(lo), Some(hi)) if f == Format::Lammps => {
                    format!(" by {:.2}-{:.2} %", 100.0 * lo, 100.0 * hi)
                }
                _ => String::new(),
            };
            format!("{head}: NOT EXACT: {limit}{range}; see docs/exports.md")
        })
        .collect()
}
