//! `dem specimen`: build a relaxed bonded specimen (traditional, ORC or improved ORC) and
//! write it as a `dem.specimen/1` file with a summary JSON beside it (`docs/specimen.md`).

use crate::progress::Progress as Bar;
use clap::Args;
use dem_lab::specimen::{
    self, io, FewGrains, GrainMode, IrregularCount, Method, Progress, RadiusDist, SpecimenParams,
};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct SpecimenArgs {
    /// traditional | orc | improved.
    #[arg(long, default_value = "traditional")]
    method: String,
    /// Specimen width with unit (`20mm`, `2e-2m`, `500um`).
    #[arg(long)]
    width: String,
    /// Specimen height with unit.
    #[arg(long)]
    height: String,
    /// Smallest disc radius with unit.
    #[arg(long)]
    r_min: String,
    /// Largest disc radius with unit.
    #[arg(long)]
    r_max: String,
    /// Radius distribution: normal (mean (r_min + r_max)/2, sd (r_max − r_min)/6, truncated)
    /// or uniform.
    #[arg(long, default_value = "normal")]
    dist: String,
    /// Random seed; a seed gives the same specimen on every machine and thread count.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Material file (data/materials/*.json): name, density, E and a tensile strength
    /// (Brazilian, else flexural) set the defaults below.
    #[arg(long)]
    material: Option<PathBuf>,
    /// Density (kg/m³), overriding the material file.
    #[arg(long)]
    density: Option<f64>,
    /// Young's modulus with unit (`310GPa`): contact and bond moduli E_c = Ē_c.
    #[arg(long)]
    youngs: Option<String>,
    /// Tensile strength with unit (`800MPa`): grain-boundary bond strengths σ̄c = c̄ (intra-grain
    /// twice that); σ0 defaults to 1 % of it.
    #[arg(long)]
    tensile: Option<String>,
    /// Isotropic stress installed before bonding, with unit (`8MPa`).
    #[arg(long)]
    iso_stress: Option<String>,
    /// Target 2D porosity of the initial packing.
    #[arg(long, default_value_t = 0.16)]
    porosity: f64,
    /// Mean equivalent grain diameter (ORC, improved), with unit; default 4 mean radii.
    #[arg(long)]
    grain_size: Option<String>,
    /// Smallest template disc radius (improved), with unit; default r_min/2.
    #[arg(long)]
    template_r_min: Option<String>,
    /// Which grains are irregular (orc, improved): `all` (every cell of a Voronoi
    /// tessellation of --grain-size) or `few` (S0: a few synthetic grains of --grain-size in
    /// the traditional packing of the seed, as many as give the improved specimen S0's
    /// 1576/989 discs per packing disc; docs/specimen.md, "Few irregular grains (S0)").
    #[arg(long, default_value = "all")]
    irregular: String,
    /// With `--irregular few`: this many irregular grains instead of S0's disc ratio.
    #[arg(long)]
    irregular_count: Option<usize>,
    /// With `--irregular few`: equivalent diameter of the irregular grains, with unit;
    /// default --grain-size.
    #[arg(long)]
    irregular_size: Option<String>,
    /// With `--irregular few`, improved ORC: how the specimen returns to σ0 after its
    /// templates are put in: `affine` (default; settle, then affine steps) or `servo`
    /// (stress-controlled walls; keeps more contacts on thin beams; docs/specimen.md).
    #[arg(long)]
    insertion: Option<String>,
    /// Largest number of discs per improved-ORC grain (9 in the paper).
    #[arg(long, default_value_t = 9)]
    max_discs: usize,
    /// Relaxed when kinetic energy ≤ this × stored strain energy.
    #[arg(long, default_value_t = 1e-6)]
    ke_ratio: f64,
    /// Name of the material the file's discs refer to (default: the material file's name,
    /// else "specimen").
    #[arg(long)]
    material_name: Option<String>,
    /// Output specimen file (JSON); the summary goes to `<stem>.summary.json` beside it, and a
    /// scene that loads the specimen with its generation micro-parameters to `<stem>.scene.json`.
    #[arg(long)]
    out: PathBuf,
    /// Worker threads, at least 1 (default: all cores); results do not depend on it.
    #[arg(long, value_parser = crate::parse_threads)]
    threads: Option<usize>,
    /// Replace an existing `--out` file (and its scene and summary beside it); without it an
    /// existing one is refused before anything is generated.
    #[arg(long)]
    force: bool,
    /// An improved-ORC grain whose template stops below its cover target is a failure (the
    /// specimen is not written; exit code 2) instead of a warning.
    #[arg(long)]
    strict: bool,
}

/// `x.json` → `x.scene.json` beside it.
fn scene_path(out: &std::path::Path) -> PathBuf {
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name.strip_suffix(".json").unwrap_or(&name);
    out.with_file_name(format!("{stem}.scene.json"))
}

/// A speed, one rule for every speed flag (`--speed`, `--seat-speed`, `--speed-max`): a number
/// in m/s (`1`, `2.5`), or with a unit (`1m/s`, `50mm/s`, `500um/s`) → m/s; positive and finite.
pub fn parse_speed(s: &str, what: &str) -> Result<f64, String> {
    let units = [("mm/s", 1e-3), ("um/s", 1e-6), ("µm/s", 1e-6), ("m/s", 1.0)];
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        Ok(_) => Err(format!("{what}: {s:?} must be positive (m/s)")),
        Err(_) if units.iter().any(|(u, _)| s.trim().ends_with(u)) => parse_unit(s, what, &units),
        Err(_) => Err(format!(
            "{what}: {s:?} needs a unit (mm/s, um/s, µm/s, m/s), or a number in m/s"
        )),
    }
}

/// `20mm`, `0.2mm`, `500um`, `1e-3m` → metres.
pub fn parse_length(s: &str, what: &str) -> Result<f64, String> {
    parse_unit(
        s,
        what,
        &[("mm", 1e-3), ("um", 1e-6), ("µm", 1e-6), ("m", 1.0)],
    )
}

/// `8MPa`, `310GPa`, `1e5Pa` → pascals.
pub fn parse_stress(s: &str, what: &str) -> Result<f64, String> {
    parse_unit(
        s,
        what,
        &[("GPa", 1e9), ("MPa", 1e6), ("kPa", 1e3), ("Pa", 1.0)],
    )
}

fn parse_unit(s: &str, what: &str, units: &[(&str, f64)]) -> Result<f64, String> {
    let t = s.trim();
    for (u, f) in units {
        if let Some(num) = t.strip_suffix(u) {
            let v: f64 = num
                .trim()
                .parse()
                .map_err(|_| format!("{what}: cannot read the number in {s:?}"))?;
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{what}: {s:?} must be positive"));
            }
            return Ok(v * f);
        }
    }
    let names: Vec<&str> = units.iter().map(|u| u.0).collect();
    Err(format!("{what}: {s:?} needs a unit ({})", names.join(", ")))
}

/// Name, density (kg/m³), E (Pa), tensile strength (Pa) from a `data/materials` file.
pub type MaterialInfo = (String, Option<f64>, Option<f64>, Option<f64>);

pub fn read_material(path: &std::path::Path) -> Result<MaterialInfo, String> {
    // Typed, so a misspelled or mistyped key is an error naming the file and the key.
    let m = dem_lab::calibrate::MaterialFile::read_unchecked(path).map_err(|e| e.to_string())?;
    let e = m.measured.e_gpa.or(m.assumed.e_gpa).map(|g| g * 1e9);
    let tensile = m
        .measured
        .brazilian_mpa
        .or(m.measured.flexural_mpa)
        .map(|v| v * 1e6);
    Ok((m.material, Some(m.density_kg_m3), e, tensile))
}

/// `--method` and `--dist`.
pub fn method_and_dist(method: &str, dist: &str) -> Result<(Method, RadiusDist), String> {
    let m = Method::parse(method)
        .ok_or_else(|| format!("--method {method:?}: use traditional, orc or improved"))?;
    let d = match dist {
        "normal" => RadiusDist::Normal,
        "uniform" => RadiusDist::Uniform,
        d => return Err(format!("--dist {d:?}: use normal or uniform")),
    };
    Ok((m, d))
}

/// `--irregular`, `--irregular-count`, `--irregular-size` (the others need `few`).
pub fn grain_mode(
    p: &SpecimenParams,
    mode: &str,
    count: Option<usize>,
    size: Option<&str>,
    insertion: Option<&str>,
) -> Result<GrainMode, String> {
    match mode {
        "all" => {
            if count.is_some() || size.is_some() || insertion.is_some() {
                return Err(
                    "--irregular-count, --irregular-size and --insertion need --irregular few"
                        .to_string(),
                );
            }
            Ok(GrainMode::All)
        }
        "few" => {
            let mut f = FewGrains::s0(p);
            if let Some(n) = count {
                f.count = IrregularCount::Count(n);
            }
            if let Some(s) = size {
                f.diameter = parse_length(s, "--irregular-size")?;
            }
            if let Some(s) = insertion {
                f.insertion = specimen::Insertion::parse(s)
                    .ok_or_else(|| format!("--insertion {s:?}: use affine or servo"))?;
            }
            Ok(GrainMode::Few(f))
        }
        m => Err(format!("--irregular {m:?}: use all or few")),
    }
}

/// Material name, density, E and tensile strength: the flags, else the `--material` file.
pub fn material_values(
    material: Option<&PathBuf>,
    density: Option<f64>,
    youngs: Option<&str>,
    tensile: Option<&str>,
) -> Result<(String, f64, f64, f64), String> {
    let (name, mat_rho, mat_e, mat_t) = match material {
        Some(p) => read_material(p)?,
        None => ("specimen".to_string(), None, None, None),
    };
    let need = |v: Option<f64>, what: &str| {
        v.ok_or_else(|| format!("{what} is not set: give it or a --material file that has it"))
    };
    let density = need(density.or(mat_rho), "--density")?;
    let e = need(
        youngs
            .map(|s| parse_stress(s, "--youngs"))
            .transpose()?
            .or(mat_e),
        "--youngs",
    )?;
    let tensile = need(
        tensile
            .map(|s| parse_stress(s, "--tensile"))
            .transpose()?
            .or(mat_t),
        "--tensile",
    )?;
    Ok((name, density, e, tensile))
}

pub fn run(a: SpecimenArgs) -> Result<ExitCode, String> {
    let (method, dist) = method_and_dist(&a.method, &a.dist)?;
    let (mat_name, density, e, tensile) = material_values(
        a.material.as_ref(),
        a.density,
        a.youngs.as_deref(),
        a.tensile.as_deref(),
    )?;
    let mut p = SpecimenParams::new(
        method,
        parse_length(&a.width, "--width")?,
        parse_length(&a.height, "--height")?,
        parse_length(&a.r_min, "--r-min")?,
        parse_length(&a.r_max, "--r-max")?,
        density,
        e,
        tensile,
        a.seed,
    );
    p.distribution = dist;
    p.porosity = a.porosity;
    p.template_max_discs = a.max_discs;
    p.ke_ratio = a.ke_ratio;
    if let Some(s) = &a.iso_stress {
        p.iso_stress = parse_stress(s, "--iso-stress")?;
    }
    if let Some(s) = &a.grain_size {
        p.grain_size = parse_length(s, "--grain-size")?;
    }
    if let Some(s) = &a.template_r_min {
        p.template_r_min = parse_length(s, "--template-r-min")?;
    }
    p.grains = grain_mode(
        &p,
        &a.irregular,
        a.irregular_count,
        a.irregular_size.as_deref(),
        a.insertion.as_deref(),
    )?;
    p.validate().map_err(|e| e.to_string())?;
    check_resolution(&p, &a.width, &a.height)?;
    // An output never replaces an input (issue 48 D2), --force or not: the material file read
    // is not one of the three files written, under any spelling of its path.
    if let Some(m) = &a.material {
        let outs = [a.out.clone(), scene_path(&a.out), io::summary_path(&a.out)];
        if let Some(f) = outs
            .iter()
            .find(|f| dem_core::output::driver::same_file(m, f))
        {
            return Err(format!(
                "--out {}: would write {}, which is the --material file {}; give another --out \
                 (--force does not replace an input)",
                a.out.display(),
                f.display(),
                m.display()
            ));
        }
    }
    // Never a silent overwrite (issue 20): the specimen file and the scene beside it (which
    // the user may have edited) are refused before the minutes of generation, unless --force.
    if !a.force {
        for f in [a.out.clone(), scene_path(&a.out)] {
            if f.exists() {
                return Err(format!(
                    "{}: exists; give another --out, or --force to replace it",
                    f.display()
                ));
            }
        }
    }
    let material = a.material_name.unwrap_or(mat_name);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| e.to_string())?;
    println!(
        "{} specimen {:.4} x {:.4} mm, radii {:.4}-{:.4} mm, seed {}, σ0 {:.3} MPa",
        method.name(),
        p.width * 1e3,
        p.height * 1e3,
        p.r_min * 1e3,
        p.r_max * 1e3,
        p.seed,
        p.iso_stress * 1e-6
    );
    let bar = Bar::stages();
    let spec = pool.install(|| {
        specimen::generate(&p, &mut |pr: Progress| {
            bar.set_prefix(pr.stage);
            bar.set_fraction(pr.fraction);
            bar.set_message(pr.message);
        })
    });
    bar.finish_and_clear();
    let spec = spec.map_err(|e| e.to_string())?;
    let below = below_cover(&spec.summary);
    let lines = cover_lines(&a.out, below);
    if a.strict && !below.is_empty() {
        return Err(format!(
            "--strict: {} grains are below their cover target; {} not written (leave out \
             --strict to write it with a warning):\n  {}",
            below.len(),
            a.out.display(),
            lines.join("\n  ")
        ));
    }
    for l in &lines {
        eprintln!("warning: {l}");
    }
    let summary_file = io::save(&spec, &material, &a.out).map_err(|e| e.to_string())?;
    let name = a
        .out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let scene_file = scene_path(&a.out);
    let scene = io::example_scene(&spec, &material, &name, 1000);
    let text = serde_json::to_string_pretty(&scene).map_err(|e| e.to_string())?;
    io::write_atomic(&scene_file, &text).map_err(|e| e.to_string())?;
    print!("{}", spec.summary.text());
    println!("specimen: {} (material {material:?})", a.out.display());
    println!("summary:  {}", summary_file.display());
    println!(
        "scene:    {} (dem run it to load the specimen)",
        scene_file.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// The improved-ORC grains of a specimen (its summary) whose templates stopped below their
/// cover target (none for other methods).
pub fn below_cover(s: &dem_lab::specimen::Summary) -> &[dem_lab::specimen::improved::GrainCover] {
    s.templates
        .as_ref()
        .map(|t| t.below_cover.as_slice())
        .unwrap_or_default()
}

/// The warnings (one line per grain, naming `file`) and the count of the grains below their
/// cover target, as the lab tests print them (none: nothing printed).
pub fn print_cover(file: &std::path::Path, below: &[dem_lab::specimen::improved::GrainCover]) {
    if below.is_empty() {
        return;
    }
    for l in cover_lines(file, below) {
        eprintln!("warning: {l}");
    }
    println!(
        "templates: {} grains below their cover target (warnings above; --strict makes them a failure)",
        below.len()
    );
}

/// Grains below their cover target listed at most this many at a time ("and N more").
const COVER_LIST: usize = 10;

/// One line per grain below its cover target (at most [`COVER_LIST`], then "and N more"),
/// each naming the specimen file.
pub fn cover_lines(
    file: &std::path::Path,
    below: &[dem_lab::specimen::improved::GrainCover],
) -> Vec<String> {
    let mut v: Vec<String> = below
        .iter()
        .take(COVER_LIST)
        .map(|g| format!("{}: {g}", file.display()))
        .collect();
    if below.len() > COVER_LIST {
        v.push(format!("and {} more", below.len() - COVER_LIST));
    }
    v
}

/// [`specimen::SpecimenParams::check_resolution`] with the refusal naming the flag and the value
/// given (`--height 2mm: ...`); `dem specimen` and the generating lab tests (`dem test cutting`,
/// issue 48 D8) share it.
pub(crate) fn check_resolution(
    p: &specimen::SpecimenParams,
    width: &str,
    height: &str,
) -> Result<(), String> {
    p.check_resolution().map_err(|e| match e {
        specimen::SpecimenError::Geometry { field, reason } => {
            let given = if field == "width" { width } else { height };
            format!("--{field} {given}: {reason}")
        }
        e => e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::parse_speed;

    /// One rule for every speed flag (issue 49): a number is m/s, a unit converts; the error
    /// names the flag. Before, `dem test cutting --speed` took `1` and refused `50mm/s`,
    /// while `dem test ucs --speed` refused `1` and took `50mm/s`.
    #[test]
    fn speeds_have_one_rule() {
        for (s, v) in [
            ("1", 1.0),
            ("2.5", 2.5),
            ("1m/s", 1.0),
            ("1 m/s", 1.0),
            ("50mm/s", 0.05),
            ("500um/s", 5e-4),
            ("2e3mm/s", 2.0),
        ] {
            let got = parse_speed(s, "--speed").unwrap();
            assert!((got - v).abs() <= 1e-15 * v, "{s}: {got}");
        }
        let e = parse_speed("0", "--speed").unwrap_err();
        assert!(e.starts_with("--speed: \"0\" must be positive"), "{e}");
        let e = parse_speed("-1mm/s", "--seat-speed").unwrap_err();
        assert!(
            e.starts_with("--seat-speed: \"-1mm/s\" must be positive"),
            "{e}"
        );
        let e = parse_speed("fast", "--speed").unwrap_err();
        assert!(
            e.contains("needs a unit") && e.ends_with("or a number in m/s"),
            "{e}"
        );
        assert!(
            parse_speed("1m", "--speed").is_err(),
            "a length is not a speed"
        );
        assert!(parse_speed("inf", "--speed").is_err() && parse_speed("NaN", "--speed").is_err());
    }
}
