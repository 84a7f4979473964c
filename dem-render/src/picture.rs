//! What `dem render` draws, whatever file it came from: discs, bonds, walls, an outline and
//! caption lines, in metres ([`Picture`]), and the caption helpers. `load` reads the solver's
//! and clumpgen's files into it, `vtk` the VTK snapshots; both import this leaf module.

use dem_core::state::FREE;
use std::path::Path;

/// One disc to draw (metres, m/s).
#[derive(Clone, Debug)]
pub struct Disc {
    /// Centre x (m).
    pub x: f64,
    /// Centre y (m).
    pub y: f64,
    /// Radius (m).
    pub r: f64,
    /// Speed |v| (m/s); 0 where the file has no velocities.
    pub speed: f64,
    /// Material index (into [`Picture::materials`] where names are known).
    pub material: u16,
    /// Grain key: discs of one grain (rigid clump, bonded clump, specimen grain) share it.
    pub grain: u64,
}

/// One bond between two discs (indices into [`Picture::discs`]).
#[derive(Clone, Copy, Debug)]
pub struct Bond {
    /// First disc.
    pub i: usize,
    /// Second disc.
    pub j: usize,
    /// Bond group index (into [`Picture::bond_groups`]).
    pub group: u16,
    /// Intact (true) or broken.
    pub intact: bool,
    /// Where a broken bond broke (m; the break log's bond centre), where known.
    pub broke_at: Option<[f64; 2]>,
    /// Bond width 2R̄ (m); 0 where unknown.
    pub width: f64,
}

/// A wall or tool: a polyline (m).
#[derive(Clone, Debug)]
pub struct WallLine {
    /// The wall's name in the scene (`tool`, `slot_left`, …).
    pub name: String,
    /// Vertices in order (at least two).
    pub points: Vec<[f64; 2]>,
}

/// What kind of file the picture came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A checkpoint of a run.
    Checkpoint,
    /// A `last-good-state.json` written when a run stopped.
    State,
    /// A specimen file.
    Specimen,
    /// A clump template.
    Template,
    /// A VTK disc snapshot (`snap-*.vtp`).
    Snapshot,
}

/// Everything `dem render` draws, in metres.
#[derive(Clone, Debug)]
pub struct Picture {
    /// Which kind of file it was.
    pub kind: Kind,
    /// The discs.
    pub discs: Vec<Disc>,
    /// Bonds, intact and broken (a specimen file lists only intact ones).
    pub bonds: Vec<Bond>,
    /// Bond group names by index.
    pub bond_groups: Vec<String>,
    /// Material names by index (empty where the file does not name them).
    pub materials: Vec<String>,
    /// Walls and the tool.
    pub walls: Vec<WallLine>,
    /// A grain outline (template), closed implicitly.
    pub outline: Option<Vec<[f64; 2]>>,
    /// The grain centroid (template): drawn as a `+`.
    pub centroid: Option<[f64; 2]>,
    /// The clump's own mass centre where it differs from the grain's (ORC template): an `x`.
    pub clump_centroid: Option<[f64; 2]>,
    /// Caption lines (file, step and time, counts).
    pub caption: Vec<String>,
    /// Remarks for stderr (an outline not found, discs skipped).
    pub notes: Vec<String>,
}

/// `folder/file.json`: the file name with its folder, which tells checkpoints of runs apart.
pub fn short_name(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    match path
        .parent()
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
    {
        Some(dir) if !dir.is_empty() => format!("{dir}/{name}"),
        _ => name,
    }
}

/// `step 13,884,535   t = 10.100 ms`.
pub fn step_time(step: u64, t: f64) -> String {
    let digits = step.to_string();
    let grouped: Vec<&str> = digits
        .as_bytes()
        .rchunks(3)
        .rev()
        .map(|c| std::str::from_utf8(c).unwrap_or("?"))
        .collect();
    let grouped = grouped.join(",");
    format!("step {grouped}   t = {}", seconds(t))
}

/// A time in s, ms or us with four significant digits.
fn seconds(t: f64) -> String {
    let a = t.abs();
    if a == 0.0 || a >= 1.0 {
        format!("{} s", sig(t))
    } else if a >= 1e-3 {
        format!("{} ms", sig(t * 1e3))
    } else {
        format!("{} us", sig(t * 1e6))
    }
}

/// `1583 discs, 3175 bonds (412 broken), 4 walls`.
pub fn counts(p: &Picture) -> String {
    let mut s = format!("{} discs", p.discs.len());
    if !p.bonds.is_empty() {
        let broken = p.bonds.iter().filter(|b| !b.intact).count();
        s += &format!(", {} intact bonds", p.bonds.len() - broken);
        if broken > 0 {
            s += &format!(" ({broken} broken)");
        }
    }
    if !p.walls.is_empty() {
        s += &format!(", {} walls", p.walls.len());
    }
    s
}

/// Grain keys of discs given their rigid-clump index (or `FREE`), their group and their id:
/// a clump's discs share their clump; other discs share their group where the groups tell
/// grains apart (not all equal), else each disc is its own grain.
pub fn grain_keys(body: &[u32], group: &[u32], id: &[u32]) -> Vec<u64> {
    let groups_vary = group.windows(2).any(|w| w[0] != w[1]);
    (0..body.len())
        .map(|k| {
            if body[k] != FREE {
                (1 << 40) | body[k] as u64
            } else if groups_vary {
                group[k] as u64
            } else {
                (2 << 40) | id[k] as u64
            }
        })
        .collect()
}

/// Four significant digits, without trailing zeros (`0.4312`, `12.5`, `1234`).
pub fn sig(v: f64) -> String {
    if !v.is_finite() || v == 0.0 {
        return format!("{v}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).clamp(0, 8) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}
