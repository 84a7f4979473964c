//! The suite's cases as scene files. Lengths in the files are metres (`"units": "m"`), all other
//! quantities SI. Shared conventions (each case says where it departs from them):
//!
//! - Contact stiffness from a modulus E with the 2D deformability relation of Potyondy &
//!   Cundall (2004) §2.3: each disc contributes k = 2tE, two in series give the contact
//!   k_n = tE (a material's `kn` in the scene is the contact's, so `kn` = tE); k_n/k_s = 2.5
//!   (their calibrated granite).
//! - Parallel bonds (Potyondy & Cundall 2004): k̄n = E/(R₁ + R₂) at the case's typical radius
//!   sum, k̄n/k̄s = 2.5, radius multiplier λ̄ = 1.
//! - Si3N4 (the material of Ye & Xu 2010, S0): ρ = 3200 kg/m³ (as `validation::table1`),
//!   E = 300 GPa (dense silicon nitride, handbook range about 280–320 GPa; S0 gives no
//!   micro-parameters). SiC: S4 Table 1, E = 430 GPa, ρ = 3210 kg/m³.
//! - Thickness t = 1 mm (t cancels from every time step: masses and stiffnesses scale with it).

use super::{Expect, StabilityError};
use clumpgen::synth::SplitMix64;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// One case: its scene, the files beside it, how long and how it is judged.
#[derive(Debug, Clone)]
pub struct CaseSpec {
    pub name: String,
    pub stresses: String,
    /// The scene (JSON), with its `run.steps`.
    pub scene: Value,
    /// Files written beside the scene (name, text): templates, outlines.
    pub files: Vec<(String, String)>,
    pub steps: u64,
    /// Guard and samples every this many steps.
    pub sample_every: u64,
    /// Bound on the largest |balance error|.
    pub bound: f64,
    pub expect: Expect,
}

impl CaseSpec {
    /// Writes the scene (and its files) into `dir`; returns the scene file.
    pub fn write(&self, dir: &Path) -> Result<PathBuf, StabilityError> {
        for (name, text) in &self.files {
            write(&dir.join(name), text)?;
        }
        let file = dir.join(format!("{}.json", self.name));
        let text = serde_json::to_string_pretty(&self.scene).map_err(|e| StabilityError::Io {
            file: file.display().to_string(),
            source: std::io::Error::other(e),
        })?;
        write(&file, &(text + "\n"))?;
        Ok(file)
    }
}

fn write(path: &Path, text: &str) -> Result<(), StabilityError> {
    clumpgen::io::write_atomic(path, text.as_bytes()).map_err(|source| StabilityError::Io {
        file: path.display().to_string(),
        source,
    })
}

/// Bound on the largest |balance error| of every case (see the module docs of `stability`).
pub const BALANCE_BOUND: f64 = 1e-2;
/// Thickness of every scene (m).
pub const T: f64 = 1e-3;
/// Si3N4 (see the module docs).
pub const SI3N4: (f64, f64) = (3200.0, 300e9);
/// SiC, S4 Table 1: density, Young's modulus.
pub const SIC: (f64, f64) = (3210.0, 430e9);

/// A linear-contact material of modulus `e` (k_n = tE, k_s = k_n/2.5); `density` None for walls.
pub fn material(
    name: &str,
    density: Option<f64>,
    e: f64,
    friction: f64,
    restitution: Option<f64>,
) -> Value {
    let kn = T * e;
    let mut m = json!({"name": name, "kn": kn, "ks": kn / 2.5, "friction": friction});
    if let Some(rho) = density {
        m["density"] = json!(rho);
    }
    if let Some(e) = restitution {
        m["restitution"] = json!(e);
    }
    m
}

/// A parallel-bond group of modulus `e` at radius sum `rsum` with tensile strength and
/// cohesion `strength` (Pa).
pub fn bond_group(name: &str, e: f64, rsum: f64, strength: f64) -> Value {
    let kn = e / rsum;
    json!({"name": name, "model": "parallel_potyondy2004", "criterion": "stress",
           "kn": kn, "ks": kn / 2.5, "tensile_strength": strength, "cohesion": strength,
           "friction_angle": 30})
}

/// A wall.
pub fn wall(name: &str, a: [f64; 2], b: [f64; 2], material: &str, v: [f64; 2]) -> Value {
    json!({"name": name, "a": a, "b": b, "material": material, "velocity": v})
}

/// The scene skeleton; `run.steps` and outputs set from the step count.
pub fn scene(name: &str, description: &str, steps: u64) -> Value {
    json!({
        "schema": "dem.scene/1",
        "name": name,
        "description": description,
        "units": "m",
        "thickness": T,
        "run": {"steps": steps},
        "outputs": {"history_every": (steps / 200).max(1), "vtk_every": (steps / 20).max(1)}
    })
}

/// A hexagonal block of `cols` × `rows` touching discs of radius `r`, lower-left disc centre
/// at (x0 + r, y0 + r); odd rows shifted by r.
pub fn hex_block(cols: usize, rows: usize, r: f64, x0: f64, y0: f64) -> Vec<[f64; 3]> {
    let h = 3f64.sqrt() * r;
    let mut v = Vec::with_capacity(cols * rows);
    for row in 0..rows {
        for col in 0..cols {
            let x = x0 + r + (2 * col + row % 2) as f64 * r;
            v.push([x, y0 + r + row as f64 * h, r]);
        }
    }
    v
}

fn spec(name: &str, stresses: &str, scene: Value, steps: u64, every: u64) -> CaseSpec {
    CaseSpec {
        name: name.into(),
        stresses: stresses.into(),
        scene,
        files: Vec::new(),
        steps,
        sample_every: every,
        bound: BALANCE_BOUND,
        expect: Expect::Stable,
    }
}

/// Quick or full step count.
fn n(quick: bool, q: u64, f: u64) -> u64 {
    if quick {
        q
    } else {
        f
    }
}

/// Case 1, SiC stiffness: a 20 × 10 hexagonal block of discs of radius 2.5 µm (5 µm grains,
/// S4: "typical ceramic disc size is a few micrometres, comparable to the grain size"), SiC
/// E = 430 GPa, ρ = 3210 kg/m³ (S4 Table 1), bonded at every contact (k̄n = E/(2r)), standing
/// on a fixed floor and compressed by a platen wall (touching the top row at the start) at 0.1 m/s (full run: about 0.2 % strain,
/// below the UCS of 2 GPa, S4). Frictional (μ = 0.5), undamped contacts; bond strengths 2 GPa
/// (of the order of S4's UCS). Checks: the stiffest material of the project at the automatic
/// step, loaded through a wall.
pub fn sic_block(quick: bool) -> CaseSpec {
    let steps = n(quick, 20_000, 200_000);
    let (rho, e) = SIC;
    let r = 2.5e-6;
    let (cols, rows) = (20, 10);
    let discs = hex_block(cols, rows, r, 0.0, 0.0);
    let top = discs.iter().map(|d| d[1] + d[2]).fold(0.0, f64::max);
    let width = (2 * cols + 1) as f64 * r;
    let mut s = scene(
        "sic_block",
        "SiC (E = 430 GPa, S4 Table 1) bonded block of 5 um discs on a floor, compressed by a \
         platen wall at 0.1 m/s; stability suite case 1",
        steps,
    );
    s["materials"] = json!([
        material("sic", Some(rho), e, 0.5, None),
        material("platen", None, e, 0.0, None)
    ]);
    s["bond_groups"] = json!([bond_group("sic_bonds", e, 2.0 * r, 2e9)]);
    s["bodies"] = json!({"discs": [{"material": "sic", "discs": discs}]});
    s["auto_bonds"] = json!([{"bond_group": "sic_bonds", "tolerance": 1e-3 * r}]);
    s["walls"] = json!([
        wall(
            "floor",
            [-2.0 * r, 0.0],
            [width + 2.0 * r, 0.0],
            "platen",
            [0.0, 0.0]
        ),
        wall(
            "platen",
            [width + 2.0 * r, top],
            [-2.0 * r, top],
            "platen",
            [0.0, -0.1]
        )
    ]);
    spec(
        "sic_block",
        "SiC E = 430 GPa, 5 µm discs, bonded, platen 0.1 m/s",
        s,
        steps,
        50,
    )
}

/// Case 4, a tool at 50 m/s: a 24 × 8 hexagonal Si3N4 block of discs of radius 0.25 mm (S0's
/// specimen, 20 × 10 mm with 989 discs, has discs of about that size) in a slot of three fixed
/// walls (S4's cutting set-up), bonded (k̄n = E/(2r), strengths 600 MPa so that bonds break
/// ahead of the tool), cut at depth a_p = 1 mm (S0) by a vertical tool wall moving at 50 m/s
/// (25× S0's fastest 2 m/s). The tool is 10× stiffer than the discs (S4: "a moving wall much
/// stiffer than the discs"); contacts have restitution 0.5 and friction 0.5. Checks: a fast
/// stiff boundary, bond breaking and flying chips at the automatic step.
pub fn tool_50(quick: bool) -> CaseSpec {
    let steps = n(quick, 30_000, 300_000);
    let (rho, e) = SI3N4;
    let r = 2.5e-4;
    let (cols, rows) = (24, 8);
    let discs = hex_block(cols, rows, r, 0.0, 0.0);
    let top = discs.iter().map(|d| d[1] + d[2]).fold(0.0, f64::max);
    let width = (2 * cols + 1) as f64 * r;
    let cut = top - 1e-3;
    let mut s = scene(
        "tool_50ms",
        "Bonded Si3N4 block (24 x 8 discs of r 0.25 mm) in a slot, cut 1 mm deep by a tool \
         wall at 50 m/s; stability suite case 4",
        steps,
    );
    s["materials"] = json!([
        material("si3n4", Some(rho), e, 0.5, Some(0.5)),
        material("slot", None, e, 0.0, Some(0.5)),
        material("tool", None, 10.0 * e, 0.5, Some(0.5))
    ]);
    s["bond_groups"] = json!([bond_group("si3n4_bonds", e, 2.0 * r, 600e6)]);
    s["bodies"] = json!({"discs": [{"material": "si3n4", "discs": discs}]});
    s["auto_bonds"] = json!([{"bond_group": "si3n4_bonds", "tolerance": 1e-3 * r}]);
    let low = cut - 0.5 * r;
    s["walls"] = json!([
        wall("floor", [-r, 0.0], [width + r, 0.0], "slot", [0.0, 0.0]),
        wall("left", [0.0, low], [0.0, 0.0], "slot", [0.0, 0.0]),
        wall("right", [width, 0.0], [width, low], "slot", [0.0, 0.0]),
        wall(
            "tool",
            [-0.01 * r, cut],
            [-0.01 * r, top + 2e-3],
            "tool",
            [50.0, 0.0]
        )
    ]);
    spec(
        "tool_50ms",
        "tool wall at 50 m/s into a bonded Si3N4 block in a slot",
        s,
        steps,
        50,
    )
}

/// Case 5, a very soft material under gravity: 12 × 14 discs of radius 20–25 mm (random, seed
/// 5), E = 1 MPa (the "very soft", about a soft rubber; ρ = 1100 kg/m³, rubber), in a
/// box of three walls, falling from a loose grid and settling under gravity; restitution 0.3,
/// friction 0.5. Impacts at up to ~1 m/s make overlaps of several per cent of the radius.
/// Checks: a step set by a soft material over a long settling with gravity work, damping and
/// friction in the balance.
pub fn soft_pile(quick: bool) -> CaseSpec {
    let steps = n(quick, 30_000, 300_000);
    let (cols, rows) = (12, 14);
    let pitch = 0.055;
    let mut rng = SplitMix64::new(5);
    let mut discs = Vec::with_capacity(cols * rows);
    for row in 0..rows {
        for col in 0..cols {
            let r = rng.range(0.020, 0.025);
            let x = (col as f64 + 0.5) * pitch + rng.range(-0.002, 0.002);
            discs.push([x, (row as f64 + 0.5) * pitch, r]);
        }
    }
    let width = cols as f64 * pitch;
    let mut s = scene(
        "soft_pile",
        "Soft discs (E = 1 MPa) falling into a box and settling under gravity; stability \
         suite case 5",
        steps,
    );
    s["materials"] = json!([
        material("soft", Some(1100.0), 1e6, 0.5, Some(0.3)),
        material("box", None, 1e6, 0.5, Some(0.3))
    ]);
    s["bodies"] = json!({"discs": [{"material": "soft", "discs": discs}]});
    let h = rows as f64 * pitch * 1.5;
    s["walls"] = json!([
        wall("floor", [0.0, 0.0], [width, 0.0], "box", [0.0, 0.0]),
        wall("left", [0.0, h], [0.0, 0.0], "box", [0.0, 0.0]),
        wall("right", [width, 0.0], [width, h], "box", [0.0, 0.0])
    ]);
    s["gravity"] = json!([0.0, -9.81]);
    spec(
        "soft_pile",
        "E = 1 MPa discs settling under gravity",
        s,
        steps,
        50,
    )
}

/// Case 8, forced unstable: case 5's scene (the soft pile) with a fixed step of 2× its
/// critical step. For discs that are not yet touching, the critical step is √(m/k) of the
/// stiffest single contact, and a disc on one contact (a wall) is unstable above 2/ω = 2√(m/k):
/// at 2× the pile is at that limit, and with several contacts above it. The guard must stop it
/// (it does, within a few tens of steps, by the energy-growth check). Case 1 (SiC) is not used:
/// at 2× its critical step its spurious energy goes into frictional sliding, so the guard
/// stays silent (see the 2× probe of every case in the report).
pub(super) fn forced(pile: &CaseSpec, dir: &Path) -> Result<CaseSpec, StabilityError> {
    let mut c = pile.clone();
    c.name = "forced_unstable".into();
    c.stresses = "case 5 at a fixed dt = 2 × critical dt (must be caught by the guard)".into();
    c.expect = Expect::Caught;
    c.sample_every = 10;
    c.scene["name"] = json!("forced_unstable");
    c.scene["description"] = json!(
        "Case 5 (soft pile) at a fixed time step of twice the critical step: the blow-up \
         guard must stop it; stability suite case 8"
    );
    c.scene["outputs"] = json!({"history_every": 10, "guard_every": 10});
    c.scene["run"]["dt"] = json!(2.0 * critical_dt(&c.scene, &dir.join("forced_unstable.json"))?);
    Ok(c)
}

/// The critical step of a scene as built (with its bonds and contacts).
pub fn critical_dt(scene: &Value, file: &Path) -> Result<f64, StabilityError> {
    let text = serde_json::to_string(scene).map_err(|e| StabilityError::Setup {
        case: file.display().to_string(),
        reason: e.to_string(),
    })?;
    let scene = dem_core::scene::parse(&text, file)?;
    Ok(dem_core::scene::build(&scene)?.critical_dt())
}
