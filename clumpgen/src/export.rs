//! Exports of a clump template to other DEM codes: PFC2D, YADE, LAMMPS and MercuryDPM.
//!
//! Every export is written beside its template (`g.json` → `g.pfc.p2dat`, `g.yade.py`,
//! `g.lammps.mol`, `g.mercury/`), atomically file by file ([`crate::io::write_atomic`]), and
//! carries the clump the template describes: the discs (x, y, r) and the mass properties of the
//! per-disc masses m (for the improved method: the grain's exact mass, centroid and moment of
//! inertia). What each code can take and what it does with it (the formats, their sources, and
//! what the peers computed when they loaded the exports) is in `docs/exports.md`:
//!
//! * **PFC2D** (`clump template create`, Itasca PFC 6+ command reference): pebbles (r, x, y),
//!   and the mass properties given explicitly (`volume`, `inertia`, `position`). PFC templates
//!   have unit density, so `volume` = M/ρ and `inertia` = I/ρ; replicated with `density ρ` the
//!   clump has the template's mass and inertia. Not loaded in PFC here (commercial).
//! * **YADE** (Python; `O.bodies.clump`): each disc becomes a sphere of radius r at (x, y, 0)
//!   for contacts. YADE sums sphere members from their material's density (ρ 4/3 π r³,
//!   0.4 m r²; `Clump::updateProperties`), so each member gets a material copy whose density
//!   makes its mass the disc's (mass and centroid exact), and the clump's principal inertia
//!   then gets what a disc has more than the sphere: exact.
//! * **LAMMPS** (`molecule` file: Coords, Types, Diameters, Masses; header `mass`, `com`,
//!   `inertia`, the latter in the order LAMMPS' `Molecule::read` takes it): per-atom masses are
//!   the disc masses, so the mass and centroid are exact; the body inertia is exact where
//!   LAMMPS takes it from the header (bodies inserted from the template by `fix deposit`/`fix
//!   pour` with `mol ... rigid`), and short by Σ 0.1 m r² where `fix rigid/small` builds a body
//!   from atoms (it counts each atom as a sphere, 0.4 m r²).
//! * **MercuryDPM** (the MClump folder read by `ClumpInput.h`: `Clump/Clump.txt` with
//!   `x,y,z,r` per pebble, `Inertia/Mass.txt`, `Inertia/TOI.txt`, `Inertia/PD.txt`): mass and
//!   inertia tensor given explicitly, pebbles about the mass centre in the principal frame (as
//!   MClump writes them); MercuryDPM reads them in single precision (`std::stof`).
//!
//! Everything is SI. The 3D tensors (YADE, LAMMPS header, MercuryDPM, PFC) take each disc as a
//! lamina (a thin disc): I_zz = m r²/2, I_xx = I_yy = m r²/4 about its centre, so that
//! I_xx + I_yy = I_zz for the clump (perpendicular axes). Only I_zz (rotation in the plane)
//! acts in 2D, and it is the template's. The thickness t is a mass-per-area convention (PFC2D's
//! unit thickness), not an extent: a slab's m t²/12 would make I_xx, I_yy ~6R²/t² ≈ 10⁵–10⁷ ×
//! I_zz for mm grains and t = 1 m, and LAMMPS (`Molecule::compute_inertia`, fix rigid/small)
//! sets a principal moment below 1e-7 of the largest to zero: I_zz of grains under ~0.1 mm.

use crate::template::Template;
use std::path::{Path, PathBuf};

/// An export format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Format {
    Pfc,
    Yade,
    Lammps,
    Mercury,
}

impl Format {
    /// All formats, in the order they are written.
    pub const ALL: [Format; 4] = [Format::Pfc, Format::Yade, Format::Lammps, Format::Mercury];

    /// The name used on the command line (`--export pfc`).
    pub fn name(self) -> &'static str {
        match self {
            Format::Pfc => "pfc",
            Format::Yade => "yade",
            Format::Lammps => "lammps",
            Format::Mercury => "mercury",
        }
    }

    /// `pfc`, `yade`, `lammps` or `mercury` (case-insensitive); `None` for anything else.
    pub fn parse(s: &str) -> Option<Format> {
        let s = s.trim().to_ascii_lowercase();
        Format::ALL.into_iter().find(|f| f.name() == s)
    }

    /// The files this format writes for the template at `template` (`g.json`): one file beside
    /// it, or for MercuryDPM the files of the folder `g.mercury/`.
    pub fn paths(self, template: &Path) -> Vec<PathBuf> {
        let stem = template
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "clump".into());
        let beside = |ending: &str| template.with_file_name(format!("{stem}{ending}"));
        match self {
            Format::Pfc => vec![beside(".pfc.p2dat")],
            Format::Yade => vec![beside(".yade.py")],
            Format::Lammps => vec![beside(".lammps.mol")],
            Format::Mercury => {
                let dir = beside(".mercury");
                MERCURY_FILES.iter().map(|f| dir.join(f)).collect()
            }
        }
    }

    /// What this format cannot carry exactly, in general terms (the figures are per grain:
    /// [`Caveat`]); `None` when the export carries the template's mass properties exactly.
    pub fn limitation(self) -> Option<&'static str> {
        match self {
            Format::Pfc | Format::Yade => None,
            Format::Lammps => Some(
                "exact masses and centroid; I_z is exact only for bodies inserted from the \
                 molecule (fix deposit/pour mol ... rigid: the header's inertia); fix \
                 rigid/small building a body from atoms counts each atom as a sphere \
                 (0.4 m r^2, not the disc's m r^2/2), so its I_z is low",
            ),
            Format::Mercury => Some(
                "exact mass and inertia tensor in the files, but MercuryDPM's ClumpInput.h \
                 reads them with std::stof (single precision, ~6e-8 relative)",
            ),
        }
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The files of a MercuryDPM clump folder, as `ClumpInput.h` (`LoadPebbles`, `LoadMass`,
/// `LoadTOI`, `LoadPD`) reads them, plus a README with what the numbers are.
pub const MERCURY_FILES: [&str; 5] = [
    "Clump/Clump.txt",
    "Inertia/Mass.txt",
    "Inertia/TOI.txt",
    "Inertia/PD.txt",
    "README.txt",
];

/// Relative single-precision rounding of MercuryDPM's `std::stof` (2⁻²⁴).
pub const MERCURY_STOF_REL: f64 = 5.960_464_477_539_063e-8;

/// The clump's rigid-body properties as the exports state them, from the discs and their masses
/// (the template's `achieved` figures, and the 3D tensor of the discs as laminae).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidProps {
    /// Σ m (kg).
    pub mass: f64,
    /// Mass centre Σ m (x, y) / M (m, template frame).
    pub centroid: [f64; 2],
    /// About the mass centre: Σ m (r²/2 + d²) (kg m²), the in-plane rotation moment.
    pub izz: f64,
    /// Σ m (r²/4 + (y − y_c)²).
    pub ixx: f64,
    /// Σ m (r²/4 + (x − x_c)²).
    pub iyy: f64,
    /// The tensor's off-diagonal component −Σ m (x − x_c)(y − y_c).
    pub ixy: f64,
    /// What a code that takes each disc as a sphere (0.4 m r²) makes of I_zz: Σ m (0.4 r² + d²).
    pub izz_spheres: f64,
}

/// The rigid-body properties of the template's clump (see [`RigidProps`]).
pub fn rigid_props(t: &Template) -> RigidProps {
    let mass: f64 = t.discs.iter().map(|d| d.m).sum();
    let cx = t.discs.iter().map(|d| d.m * d.x).sum::<f64>() / mass;
    let cy = t.discs.iter().map(|d| d.m * d.y).sum::<f64>() / mass;
    let (mut izz, mut ixx, mut iyy, mut ixy, mut izz_spheres) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for d in &t.discs {
        let (dx, dy, r2) = (d.x - cx, d.y - cy, d.r * d.r);
        izz += d.m * (0.5 * r2 + dx * dx + dy * dy);
        izz_spheres += d.m * (0.4 * r2 + dx * dx + dy * dy);
        ixx += d.m * (0.25 * r2 + dy * dy);
        iyy += d.m * (0.25 * r2 + dx * dx);
        ixy -= d.m * dx * dy;
    }
    RigidProps {
        mass,
        centroid: [cx, cy],
        izz,
        ixx,
        iyy,
        ixy,
        izz_spheres,
    }
}

/// A per-grain figure of what a format does not carry exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Caveat {
    pub format: Format,
    /// Relative shortfall of the quantity the format loses (LAMMPS: I_z of a body built from
    /// atoms, (I − I_spheres)/I; MercuryDPM: the single-precision rounding bound).
    pub rel: f64,
}

/// The caveat of `f` for this template, if the format cannot carry it exactly.
pub fn caveat(t: &Template, f: Format) -> Option<Caveat> {
    match f {
        Format::Pfc | Format::Yade => None,
        Format::Lammps => {
            let p = rigid_props(t);
            Some(Caveat {
                format: f,
                rel: (p.izz - p.izz_spheres) / p.izz,
            })
        }
        Format::Mercury => Some(Caveat {
            format: f,
            rel: MERCURY_STOF_REL,
        }),
    }
}

/// An export that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{file}: cannot write the {format} export: {source}")]
pub struct ExportError {
    pub file: String,
    pub format: Format,
    pub source: std::io::Error,
}

/// The text of every file `f` writes for the template saved at `template` (paths as
/// [`Format::paths`]).
pub fn render(t: &Template, f: Format, template: &Path) -> Vec<(PathBuf, String)> {
    let name = template
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let texts = match f {
        Format::Pfc => vec![pfc(t, &name)],
        Format::Yade => vec![yade(t, &name)],
        Format::Lammps => vec![lammps(t, &name)],
        Format::Mercury => mercury(t, &name).to_vec(),
    };
    f.paths(template).into_iter().zip(texts).collect()
}

/// Writes the export `f` of the template saved at `template`, each file atomically; returns the
/// files written.
pub fn write(t: &Template, f: Format, template: &Path) -> Result<Vec<PathBuf>, ExportError> {
    let mut written = Vec::new();
    for (path, text) in render(t, f, template) {
        crate::io::write_atomic(&path, text.as_bytes()).map_err(|source| ExportError {
            file: path.display().to_string(),
            format: f,
            source,
        })?;
        written.push(path);
    }
    Ok(written)
}

/// A number as the shortest text that reads back to the same f64 (`1.5e-3`): every format here
/// (PFC, Python, LAMMPS' and MercuryDPM's C parsers) reads this form.
fn num(v: f64) -> String {
    format!("{v:e}")
}

/// Text safe inside a one-line comment (no line breaks or other control characters).
fn one_line(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// A name PFC and LAMMPS accept (letters, digits, underscores).
fn plain_name(s: &str) -> String {
    let n: String = s
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if n.is_empty() || n.starts_with(|c: char| c.is_ascii_digit()) {
        format!("g_{n}")
    } else {
        n
    }
}

/// The comment lines every export starts with: where it came from and what the grain is.
fn provenance(t: &Template, template_name: &str, format: &str) -> Vec<String> {
    let p = rigid_props(t);
    let exactness = match t.method {
        crate::template::Method::Improved => {
            "improved ORC (Ye & Xu 2010): disc masses solved so that the clump's mass, centroid \
             and moment of inertia are the grain's"
        }
        crate::template::Method::Orc => {
            "classic ORC: disc masses rho t pi r^2 (overlaps counted twice); the clump's mass \
             properties are not the grain's"
        }
        crate::template::Method::Lattice => {
            "lattice (S3): nodes of a triangular lattice, masses solved so that the clump's \
             mass, centroid and moment of inertia are the grain's; the lattice links are not \
             exported (the clump is rigid here)"
        }
    };
    vec![
        format!(
            "{format} export of clump template {} ({}, schema {}) by {}",
            one_line(template_name),
            one_line(&t.id),
            one_line(&t.schema),
            one_line(&t.generator)
        ),
        format!(
            "outline {} (sha256 {})",
            one_line(&t.source.file),
            one_line(&t.source.sha256)
        ),
        format!("method: {exactness}"),
        format!(
            "units SI (m, kg, kg m^2); density {} kg/m^3, disc thickness t = {} m; {} discs",
            num(t.density),
            num(t.thickness),
            t.discs.len()
        ),
        format!(
            "grain: area {} m^2, mass {} kg, I_z {} kg m^2 about its centroid (the origin)",
            num(t.shape.area),
            num(t.target.mass),
            num(t.target.inertia)
        ),
        format!(
            "clump: mass M = {} kg, mass centre ({}, {}) m, I_z = {} kg m^2 about it",
            num(p.mass),
            num(p.centroid[0]),
            num(p.centroid[1]),
            num(p.izz)
        ),
        format!(
            "coordinates in the grain's centroid frame, not rotated (principal angle {} rad); \
             the grain sat at ({}, {}) m in its outline file",
            num(t.shape.principal_angle),
            num(t.source.centroid_m[0]),
            num(t.source.centroid_m[1])
        ),
    ]
}

fn comment_block(prefix: &str, lines: &[String]) -> String {
    lines.iter().map(|l| format!("{prefix}{l}\n")).collect()
}

/// PFC2D: a data file of one `clump template create` command (PFC 6+ syntax, `...` continues a
/// line, `;` starts a comment).
pub fn pfc(t: &Template, template_name: &str) -> String {
    let p = rigid_props(t);
    let name = plain_name(&t.id);
    let mut lines = provenance(t, template_name, "PFC2D");
    lines.extend([
        String::new(),
        "PFC clump templates have unit density: volume = M/rho and inertia = I/rho below, so"
            .into(),
        format!(
            "  clump replicate name '{name}' density {} ...",
            num(t.density)
        ),
        format!(
            "gives mass {} kg and I_z {} kg m^2 about the mass centre: the template's (exact).",
            num(p.mass),
            num(p.izz)
        ),
        "PFC2D counts 2D volumes per unit thickness (1 m): volume = M/rho is the area times t."
            .into(),
        "inertia: the tensor I11 I22 I33 I12 I13 I23 about the mass centre per unit density,"
            .into(),
        "I33 = sum m (r^2/2 + d^2) the in-plane moment; I11, I22, I12 take each disc as a".into(),
        "lamina (m r^2/4; only I33 acts in 2D). Pebbles: radius, x, y.".into(),
        "position: the mass centre, where PFC puts the template's origin.".into(),
        "Written from the PFC command reference (clump template create); not loaded in PFC".into(),
        "by the exporter's tests (PFC is commercial): see docs/exports.md.".into(),
    ]);
    let mut s = comment_block("; ", &lines);
    s.push_str(&format!("clump template create name '{name}' ...\n"));
    s.push_str(&format!("    pebbles {} ...\n", t.discs.len()));
    for d in &t.discs {
        s.push_str(&format!(
            "        {} {} {} ...\n",
            num(d.r),
            num(d.x),
            num(d.y)
        ));
    }
    let rho = t.density;
    s.push_str(&format!("    volume {} ...\n", num(p.mass / rho)));
    s.push_str(&format!(
        "    inertia {} {} {} {} 0 0 ...\n",
        num(p.ixx / rho),
        num(p.iyy / rho),
        num(p.izz / rho),
        num(p.ixy / rho)
    ));
    s.push_str(&format!(
        "    position {} {}\n",
        num(p.centroid[0]),
        num(p.centroid[1])
    ));
    s
}

/// YADE: a Python file with the clump's data and `add_clump(position, material)`, which builds
/// the clump with the template's masses (see the module docs).
pub fn yade(t: &Template, template_name: &str) -> String {
    let p = rigid_props(t);
    let mut lines = provenance(t, template_name, "YADE");
    lines.extend([
        String::new(),
        "YADE is 3D: each disc (x, y, r) of the 2D clump becomes a sphere of radius r at".into(),
        "(x, y, 0), the contact shape. O.bodies.clump sums its members as spheres of their".into(),
        "material's density (rho 4/3 pi r^3, 0.4 m r^2, parallel axes), so add_clump gives".into(),
        "each member a copy of the material whose density makes its mass the template's disc"
            .into(),
        "mass m (the clump's mass and mass centre are then the template's), and afterwards adds"
            .into(),
        "to the clump's principal inertia what a disc (lamina) has more than a sphere".into(),
        "(m r^2/2 vs 0.4 m r^2 about z; m r^2/4 vs 0.4 m r^2 about x and y): I_z is".into(),
        "the template's exactly. Contacts use the copied material (only density differs).".into(),
        "For a 2D run block the out-of-plane motion (O.bodies[cid].state.blockedDOFs = 'zXY')."
            .into(),
        String::new(),
        "Use, in a YADE script:".into(),
        format!(
            "  exec(open('{}').read())",
            one_line(&yade_name(template_name))
        ),
        "  cid = add_clump(position=(0, 0, 0), material=-1)".into(),
        "position: where the template's origin (the grain centroid) goes.".into(),
    ]);
    let mut s = comment_block("# ", &lines);
    let id = serde_json::to_string(&t.id).unwrap_or_else(|_| "\"clump\"".into());
    s.push_str(&format!("\nCLUMP_ID = {id}\n"));
    s.push_str(&format!("DENSITY = {}  # kg/m^3\n", num(t.density)));
    s.push_str(&format!("THICKNESS = {}  # m\n", num(t.thickness)));
    s.push_str(&format!(
        "MASS = {}  # kg, sum of the disc masses\n",
        num(p.mass)
    ));
    s.push_str(&format!(
        "CENTROID = ({}, {})  # m, mass centre in the template frame\n",
        num(p.centroid[0]),
        num(p.centroid[1])
    ));
    s.push_str(&format!(
        "INERTIA_Z = {}  # kg m^2, about the mass centre\n",
        num(p.izz)
    ));
    s.push_str("DISCS = [  # x (m), y (m), r (m), m (kg)\n");
    for d in &t.discs {
        s.push_str(&format!(
            "    ({}, {}, {}, {}),\n",
            num(d.x),
            num(d.y),
            num(d.r),
            num(d.m)
        ));
    }
    s.push_str("]\n\n");
    s.push_str(YADE_ADD_CLUMP);
    s
}

fn yade_name(template_name: &str) -> String {
    let stem = template_name.strip_suffix(".json").unwrap_or(template_name);
    format!("{stem}.yade.py")
}

const YADE_ADD_CLUMP: &str = r#"
def add_clump(position=(0.0, 0.0, 0.0), material=-1, exact_inertia=True):
    """Adds the clump to O.bodies with its origin at `position` and returns the clump's id.

    material: a Material, or an id in O.materials (-1: the last one, or YADE's default
    material when there is none); each member gets a copy of it whose density makes the
    sphere's mass the disc's. exact_inertia=False leaves YADE's own sum over the spheres
    (0.4 m r^2 each), for comparison. Raises RuntimeError if the inertia cannot be set.
    """
    import copy
    import math
    from yade import utils, Vector3, Matrix3
    from yade.wrapper import Omega
    omega = Omega()
    if isinstance(material, int):
        base = omega.materials[material] if len(omega.materials) else utils.defaultMaterial()
    else:
        base = material
    d_plane = 0.0  # sum m (r^2/4 - 0.4 r^2): disc (lamina) minus sphere, about x and y
    d_z = 0.0  # sum m (r^2/2 - 0.4 r^2): disc minus sphere, about z
    ids = []
    for x, y, r, m in DISCS:
        mat = copy.deepcopy(base)
        mat.label = ""
        mat.density = m / (4.0 / 3.0 * math.pi * r ** 3)
        omega.materials.append(mat)
        b = utils.sphere((position[0] + x, position[1] + y, position[2]), r, material=mat)
        ids.append(omega.bodies.append(b))
        d_plane += m * (r * r / 4.0 - 0.4 * r * r)
        d_z += m * (r * r / 2.0 - 0.4 * r * r)
    cid = omega.bodies.clump(ids)
    if not exact_inertia:
        return cid
    # YADE summed spheres (0.4 m r^2); add the difference to discs, in the clump's frame.
    state = omega.bodies[cid].state
    rot = state.ori.toRotationMatrix()
    local = rot.transpose() * Matrix3(d_plane, 0, 0, 0, d_plane, 0, 0, 0, d_z) * rot
    off = max(abs(local[i, j]) for i in range(3) for j in range(3) if i != j)
    if off > 1e-9 * max(state.inertia):
        raise RuntimeError("%s: clump axes are not principal for the discs" % CLUMP_ID)
    state.inertia = Vector3(*[state.inertia[k] + local[k, k] for k in range(3)])
    return cid
"#;

/// LAMMPS: a molecule file (`molecule` command) for atom_style sphere, with per-atom masses and
/// the body's mass, centre and inertia in the header.
pub fn lammps(t: &Template, template_name: &str) -> String {
    let p = rigid_props(t);
    let short = 100.0 * (p.izz - p.izz_spheres) / p.izz;
    let mut lines = provenance(t, template_name, "LAMMPS");
    lines.extend([
        String::new(),
        "A molecule file (LAMMPS `molecule` command) for dimension 2, atom_style sphere and".into(),
        "fix rigid/small: one atom per disc (z = 0), diameter 2r, mass m = the disc's mass".into(),
        "(exact: not LAMMPS' density-based mass). Header: the body's mass, mass centre and".into(),
        "inertia tensor about it (discs as laminae, m r^2/4 in plane; Izz = sum m (r^2/2 + d^2),"
            .into(),
        "the template's), in the order LAMMPS reads it: Ixx Iyy Izz Iyz Ixz Ixy (Molecule::read"
            .into(),
        "stores the six values as itensor[0..5] and compute_inertia takes itensor[3] as yz,".into(),
        "[5] as xy; the molecule doc page lists Ixy Ixz Iyz). A planar clump has Iyz = Ixz = 0."
            .into(),
        "What LAMMPS computes: mass and mass centre exact from the atoms. The body inertia is"
            .into(),
        "the header's (exact) for bodies inserted from this molecule (fix deposit or fix pour"
            .into(),
        "with mol ... rigid). fix rigid/small building a body from atoms (create_atoms mol,".into(),
        "read_data) counts each atom as a sphere, 0.4 m r^2 instead of the disc's m r^2/2:".into(),
        format!(
            "there Izz = {} kg m^2, {short:.3} % below the template's. NOT CARRIED EXACTLY.",
            num(p.izz_spheres)
        ),
        "Use: molecule g <file>; create_atoms 0 single x y 0 mol g <seed>;".into(),
        "     fix 1 all rigid/small molecule  (atom types: all 1; offset with `molecule ... toff`)"
            .into(),
    ]);
    let mut s = comment_block("# ", &lines);
    s.push('\n');
    s.push_str(&format!("{} atoms\n", t.discs.len()));
    s.push_str(&format!("{} mass\n", num(p.mass)));
    s.push_str(&format!(
        "{} {} 0 com\n",
        num(p.centroid[0]),
        num(p.centroid[1])
    ));
    s.push_str(&format!(
        "{} {} {} 0 0 {} inertia\n",
        num(p.ixx),
        num(p.iyy),
        num(p.izz),
        num(p.ixy)
    ));
    let section = |title: &str, row: &dyn Fn(usize) -> String| -> String {
        let mut b = format!("\n{title}\n\n");
        for i in 0..t.discs.len() {
            b.push_str(&format!("{} {}\n", i + 1, row(i)));
        }
        b
    };
    let d = &t.discs;
    s.push_str(&section("Coords", &|i| {
        format!("{} {} 0", num(d[i].x), num(d[i].y))
    }));
    s.push_str(&section("Types", &|_| "1".into()));
    s.push_str(&section("Diameters", &|i| num(2.0 * d[i].r)));
    s.push_str(&section("Masses", &|i| num(d[i].m)));
    s
}

/// The principal angle θ of the clump's in-plane mass distribution: rotating the pebbles by −θ
/// makes the tensor diagonal (θ = ½ atan2(2 Σ m dx dy, Σ m dx² − Σ m dy²)).
pub fn principal_angle(t: &Template) -> f64 {
    let p = rigid_props(t);
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for d in &t.discs {
        let (dx, dy) = (d.x - p.centroid[0], d.y - p.centroid[1]);
        sxx += d.m * dx * dx;
        syy += d.m * dy * dy;
        sxy += d.m * dx * dy;
    }
    0.5 * (2.0 * sxy).atan2(sxx - syy)
}

/// MercuryDPM: the five files of [`MERCURY_FILES`], in that order. Pebbles are about the mass
/// centre and rotated by −θ ([`principal_angle`]) into the principal frame, so the tensor of
/// inertia is diagonal (up to rounding) and the principal directions are the axes, as MClump
/// writes its clumps (`rotateToPD`).
pub fn mercury(t: &Template, template_name: &str) -> [String; 5] {
    let p = rigid_props(t);
    let th = principal_angle(t);
    let (c, s) = (th.cos(), th.sin());
    let rotated: Vec<(f64, f64, f64, f64)> = t
        .discs
        .iter()
        .map(|d| {
            let (dx, dy) = (d.x - p.centroid[0], d.y - p.centroid[1]);
            (c * dx + s * dy, -s * dx + c * dy, d.r, d.m)
        })
        .collect();
    // The tensor in the rotated frame, from the rotated pebbles (so file and pebbles agree).
    let (mut ixx, mut iyy, mut izz, mut ixy) = (0.0, 0.0, 0.0, 0.0);
    for &(x, y, r, m) in &rotated {
        ixx += m * (0.25 * r * r + y * y);
        iyy += m * (0.25 * r * r + x * x);
        izz += m * (0.5 * r * r + x * x + y * y);
        ixy -= m * x * y;
    }
    let clump: String = rotated
        .iter()
        .map(|&(x, y, r, _)| format!("{},{},0,{}\n", num(x), num(y), num(r)))
        .collect();
    let mass = format!("{}\n", num(p.mass));
    let toi = format!(
        "{},{},0\n{},{},0\n0,0,{}\n",
        num(ixx),
        num(ixy),
        num(ixy),
        num(iyy),
        num(izz)
    );
    let pd = "1,0,0\n0,1,0\n0,0,1\n".to_string();
    let mut lines = provenance(t, template_name, "MercuryDPM");
    lines.extend([
        String::new(),
        "A MercuryDPM clump folder as MClump writes it and ClumpInput.h reads it (copy it to"
            .into(),
        "Tools/MClump/Clumps/; the folder name is the clump's name):".into(),
        "  Clump/Clump.txt  one pebble per line: x,y,z,r (m; z = 0)".into(),
        "  Inertia/Mass.txt the clump mass M (kg)".into(),
        "  Inertia/TOI.txt  tensor of inertia about the mass centre, 3 rows of 3 (kg m^2)".into(),
        "  Inertia/PD.txt   principal directions, one per row".into(),
        "The files carry no comments (the reader takes every line as numbers).".into(),
        format!(
            "Pebbles are about the mass centre, rotated by -theta, theta = {} rad, into the",
            num(th)
        ),
        "clump's principal frame (as MClump's rotateToPD): rotate the clump by +theta about z"
            .into(),
        "and move it to the mass centre to put the grain where the template has it.".into(),
        "TOI: Izz = sum m (r^2/2 + d^2), the template's; Ixx, Iyy, Ixy take each disc as a".into(),
        "lamina (m r^2/4). Mass and TOI are exact in the files; MercuryDPM reads them".into(),
        "with std::stof (single precision: ~6e-8 relative). NOT CARRIED EXACTLY to ~6e-8.".into(),
        "Pebbles are spheres in MercuryDPM (contacts); their own volumes do not enter the".into(),
        "clump's mass, which setClumpMass sets from Mass.txt.".into(),
    ]);
    let readme: String = lines.iter().map(|l| format!("{l}\n")).collect();
    [clump, mass, toi, pd, readme]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outline::parse_outline;
    use crate::{make_template, ClumpParams, ReadOptions};

    fn template(method: crate::Method) -> Template {
        // An L-shaped grain (mm): not symmetric, so centroid and tensor are non-trivial.
        let text = "x y\n0 0\n30 0\n30 10\n10 10\n10 30\n0 30\n";
        let ol = parse_outline(text, "ell", "ell.csv", false, &ReadOptions::default()).unwrap();
        let p = ClumpParams {
            method,
            thickness: 0.5,
            ..ClumpParams::default()
        };
        make_template(&ol, &p).unwrap()
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
    }

    /// Numbers of a whitespace- or comma-separated line.
    fn nums(line: &str) -> Vec<f64> {
        line.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| {
                s.parse::<f64>()
                    .unwrap_or_else(|_| panic!("{s:?} in {line:?}"))
            })
            .collect()
    }

    #[test]
    fn rigid_props_are_the_templates_achieved_figures() {
        for m in [crate::Method::Improved, crate::Method::Orc] {
            let t = template(m);
            let p = rigid_props(&t);
            assert!(rel(p.mass, t.achieved.mass) < 1e-14);
            assert!((p.centroid[0] - t.achieved.centroid[0]).abs() < 1e-15);
            assert!((p.centroid[1] - t.achieved.centroid[1]).abs() < 1e-15);
            assert!(rel(p.izz, t.achieved.inertia_own) < 1e-12, "{m:?}");
            // Laminae: Ixx + Iyy = Izz (perpendicular axes).
            assert!(rel(p.ixx + p.iyy, p.izz) < 1e-12);
            assert!(p.izz_spheres < p.izz);
        }
        // Improved: the clump is the grain.
        let t = template(crate::Method::Improved);
        let p = rigid_props(&t);
        assert!(rel(p.mass, t.target.mass) < 1e-10);
        assert!(rel(p.izz, t.target.inertia) < 1e-10);
        assert!(p.centroid[0].hypot(p.centroid[1]) < 1e-10 * t.shape.r_eq);
    }

    #[test]
    fn formats_parse_and_name_their_files() {
        assert_eq!(Format::parse("PFC"), Some(Format::Pfc));
        assert_eq!(Format::parse(" lammps"), Some(Format::Lammps));
        assert_eq!(Format::parse("foo"), None);
        for f in Format::ALL {
            assert_eq!(Format::parse(f.name()), Some(f));
        }
        let t = Path::new("out/sub/g.json");
        assert_eq!(Format::Pfc.paths(t), [Path::new("out/sub/g.pfc.p2dat")]);
        assert_eq!(Format::Yade.paths(t), [Path::new("out/sub/g.yade.py")]);
        assert_eq!(Format::Lammps.paths(t), [Path::new("out/sub/g.lammps.mol")]);
        let m = Format::Mercury.paths(t);
        assert_eq!(m[0], Path::new("out/sub/g.mercury/Clump/Clump.txt"));
        assert_eq!(m.len(), 5);
    }

    #[test]
    fn lammps_molecule_file_parses_back() {
        let t = template(crate::Method::Improved);
        let p = rigid_props(&t);
        let text = lammps(&t, "ell.json");
        // LAMMPS reads the first line as a title and strips `#` comments; the header follows.
        assert!(text.starts_with("# LAMMPS export of clump template ell.json"));
        assert!(text.contains("NOT CARRIED EXACTLY"));
        let body: Vec<&str> = text
            .lines()
            .map(|l| l.split('#').next().unwrap_or("").trim())
            .filter(|l| !l.is_empty())
            .collect();
        let n = t.discs.len();
        assert_eq!(body[0], format!("{n} atoms"));
        assert!(
            body[1].ends_with(" mass")
                && rel(nums(&body[1][..body[1].len() - 5])[0], p.mass) == 0.0
        );
        let com = nums(body[2].strip_suffix(" com").unwrap());
        assert_eq!(com, [p.centroid[0], p.centroid[1], 0.0]);
        let inertia = nums(body[3].strip_suffix(" inertia").unwrap());
        // LAMMPS' order: Ixx Iyy Izz Iyz Ixz Ixy (see `lammps`).
        assert_eq!(inertia, [p.ixx, p.iyy, p.izz, 0.0, 0.0, p.ixy]);
        // Sections in order, each with n numbered rows.
        let mut sections = std::collections::BTreeMap::new();
        let mut k = 4;
        while k < body.len() {
            let title = body[k];
            let rows: Vec<Vec<f64>> = body[k + 1..k + 1 + n].iter().map(|l| nums(l)).collect();
            for (i, r) in rows.iter().enumerate() {
                assert_eq!(r[0], (i + 1) as f64, "{title} row {i}");
            }
            sections.insert(title, rows);
            k += 1 + n;
        }
        let keys: Vec<&&str> = sections.keys().collect();
        assert_eq!(keys, [&"Coords", &"Diameters", &"Masses", &"Types"]);
        for (i, d) in t.discs.iter().enumerate() {
            assert_eq!(sections["Coords"][i][1..], [d.x, d.y, 0.0]);
            assert_eq!(sections["Diameters"][i][1], 2.0 * d.r);
            assert_eq!(sections["Masses"][i][1], d.m);
            assert_eq!(sections["Types"][i][1], 1.0);
        }
        let sum: f64 = sections["Masses"].iter().map(|r| r[1]).sum();
        assert!(
            rel(sum, t.target.mass) < 1e-10,
            "{sum} vs {}",
            t.target.mass
        );
        // The stated shortfall of a body built from atoms as spheres is Σ 0.1 m r² / I.
        let c = caveat(&t, Format::Lammps).unwrap();
        let expect = t.discs.iter().map(|d| 0.1 * d.m * d.r * d.r).sum::<f64>() / p.izz;
        assert!(rel(c.rel, expect) < 1e-9, "{} vs {expect}", c.rel);
        assert!(text.contains(&format!("{:.3} % below", 100.0 * c.rel)));
    }

    #[test]
    fn yade_script_parses_back() {
        let t = template(crate::Method::Improved);
        let p = rigid_props(&t);
        let text = yade(&t, "ell.json");
        assert!(text.contains("exec(open('ell.yade.py').read())"));
        assert!(text
            .contains("def add_clump(position=(0.0, 0.0, 0.0), material=-1, exact_inertia=True):"));
        let value = |name: &str| -> String {
            let l = text
                .lines()
                .find(|l| l.starts_with(&format!("{name} = ")))
                .unwrap_or_else(|| panic!("{name} missing"));
            l[name.len() + 3..]
                .split('#')
                .next()
                .unwrap()
                .trim()
                .to_string()
        };
        assert_eq!(value("CLUMP_ID"), "\"ell\"");
        assert_eq!(nums(&value("DENSITY")), [t.density]);
        assert_eq!(nums(&value("THICKNESS")), [t.thickness]);
        assert_eq!(nums(&value("MASS")), [p.mass]);
        assert_eq!(nums(&value("CENTROID").replace(['(', ')'], "")), p.centroid);
        assert_eq!(nums(&value("INERTIA_Z")), [p.izz]);
        let rows: Vec<Vec<f64>> = text
            .lines()
            .skip_while(|l| !l.starts_with("DISCS = ["))
            .skip(1)
            .take_while(|l| *l != "]")
            .map(|l| nums(&l.replace(['(', ')'], "")))
            .collect();
        assert_eq!(rows.len(), t.discs.len());
        for (r, d) in rows.iter().zip(&t.discs) {
            assert_eq!(r[..], [d.x, d.y, d.r, d.m]);
        }
        let sum: f64 = rows.iter().map(|r| r[3]).sum();
        assert!(rel(sum, t.target.mass) < 1e-10);
        // A hostile id stays one string literal and one comment line.
        let mut odd = t.clone();
        odd.id = "a\"b\nc".into();
        let text = yade(&odd, "x.json");
        assert!(text.contains("CLUMP_ID = \"a\\\"b\\nc\""));
        assert!(text.lines().all(|l| !l.starts_with('c')));
    }

    #[test]
    fn pfc_data_file_parses_back() {
        let t = template(crate::Method::Orc);
        let p = rigid_props(&t);
        let text = pfc(&t, "ell.json");
        let cmd: Vec<&str> = text
            .lines()
            .map(|l| l.split(';').next().unwrap_or("").trim())
            .filter(|l| !l.is_empty())
            .map(|l| l.trim_end_matches("...").trim())
            .collect();
        assert_eq!(cmd[0], "clump template create name 'ell'");
        assert_eq!(cmd[1], format!("pebbles {}", t.discs.len()));
        let n = t.discs.len();
        for (i, d) in t.discs.iter().enumerate() {
            assert_eq!(nums(cmd[2 + i]), [d.r, d.x, d.y]);
        }
        let kw = |k: &str| {
            nums(
                cmd[2 + n..]
                    .iter()
                    .find(|l| l.starts_with(k))
                    .unwrap()
                    .strip_prefix(k)
                    .unwrap(),
            )
        };
        // Unit density: volume·ρ and inertia·ρ are the clump's mass and moments.
        assert!(rel(kw("volume")[0] * t.density, p.mass) < 1e-15);
        let i = kw("inertia");
        assert_eq!(i.len(), 6);
        assert!(rel(i[2] * t.density, p.izz) < 1e-15);
        assert!(rel(i[0] * t.density, p.ixx) < 1e-15 && rel(i[1] * t.density, p.iyy) < 1e-15);
        assert_eq!(kw("position"), p.centroid);
        // ORC: the clump is not the grain, and the comment says so.
        assert!(text.contains("not the grain's"));
        assert!(rel(p.mass, t.target.mass) > 1e-6);
    }

    #[test]
    fn mercury_folder_parses_back_in_the_principal_frame() {
        let t = template(crate::Method::Improved);
        let p = rigid_props(&t);
        let [clump, mass, toi, pd, readme] = mercury(&t, "ell.json");
        let pebbles: Vec<Vec<f64>> = clump.lines().map(nums).collect();
        assert_eq!(pebbles.len(), t.discs.len());
        assert!(pebbles.iter().all(|r| r.len() == 4 && r[2] == 0.0));
        assert_eq!(nums(&mass), [p.mass]);
        assert!(rel(nums(&mass)[0], t.target.mass) < 1e-10);
        let m: Vec<Vec<f64>> = toi.lines().map(nums).collect();
        assert_eq!(m.len(), 3);
        assert!(m.iter().all(|r| r.len() == 3));
        // Symmetric, diagonal in the principal frame, Izz the template's.
        assert_eq!(m[0][1], m[1][0]);
        assert!(m[0][1].abs() < 1e-12 * p.izz, "{m:?}");
        assert!(rel(m[2][2], p.izz) < 1e-12);
        // Rotation keeps distances to the mass centre and the radii; the pebbles' mass centre
        // (with the template's masses, in disc order) is the origin.
        let (mut sx, mut sy) = (0.0, 0.0);
        for (r, d) in pebbles.iter().zip(&t.discs) {
            let d0 = (d.x - p.centroid[0]).hypot(d.y - p.centroid[1]);
            assert!((r[0].hypot(r[1]) - d0).abs() < 1e-15 + 1e-12 * d0);
            assert_eq!(r[3], d.r);
            sx += d.m * r[0];
            sy += d.m * r[1];
        }
        assert!(sx.hypot(sy) / p.mass < 1e-12 * t.shape.r_eq);
        // Eigenvalues are kept: trace and determinant of the in-plane block.
        assert!(rel(m[0][0] + m[1][1], p.ixx + p.iyy) < 1e-12);
        assert!(
            rel(
                m[0][0] * m[1][1] - m[0][1] * m[1][0],
                p.ixx * p.iyy - p.ixy * p.ixy
            ) < 1e-9
        );
        assert_eq!(pd, "1,0,0\n0,1,0\n0,0,1\n");
        assert!(readme.contains("std::stof") && readme.contains("NOT CARRIED EXACTLY"));
        // The data files hold numbers only: the reader has no comment syntax.
        for f in [&clump, &mass, &toi, &pd] {
            assert!(f
                .lines()
                .all(|l| !l.is_empty() && l.split(',').all(|v| v.parse::<f64>().is_ok())));
        }
    }

    #[test]
    fn write_puts_every_file_beside_the_template() {
        let dir = std::env::temp_dir().join(format!("clumpgen-export-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let t = template(crate::Method::Improved);
        let path = dir.join("sub/ell.json");
        t.save(&path).unwrap();
        let mut all = Vec::new();
        for f in Format::ALL {
            let w = write(&t, f, &path).unwrap();
            assert_eq!(w, f.paths(&path));
            for p in &w {
                assert!(p.starts_with(dir.join("sub")), "{p:?}");
                let text = std::fs::read_to_string(p).unwrap();
                let expect = render(&t, f, &path)
                    .into_iter()
                    .find(|(q, _)| q == p)
                    .unwrap()
                    .1;
                assert_eq!(text, expect);
            }
            all.extend(w);
        }
        assert_eq!(all.len(), 8);
        // No temporary file is left behind.
        let left: Vec<_> = walk(&dir)
            .into_iter()
            .filter(|p| p.to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(left.is_empty(), "{left:?}");
        // A folder where a file must go: the error names the file and the format.
        std::fs::remove_file(dir.join("sub/ell.yade.py")).unwrap();
        std::fs::create_dir_all(dir.join("sub/ell.yade.py/x")).unwrap();
        let e = write(&t, Format::Yade, &path).unwrap_err().to_string();
        assert!(
            e.contains("ell.yade.py") && e.contains("yade export"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn walk(d: &Path) -> Vec<PathBuf> {
        let mut out = Vec::new();
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                out.extend(walk(&p));
            } else {
                out.push(p);
            }
        }
        out
    }
}
