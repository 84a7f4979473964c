//! The grinding wheel of S1 (a patent on 2D grinding-wheel modelling with DEM), its first
//! three steps (issue 52; calibration and grinding come later):
//!
//! ```text
//! geometry  (1) the annulus of walls: the outer a full circle (a closed polygon), the inner a
//!               ring of n1 rectangular grooves (depth h1, width b) joined by circular arcs,
//!               groove k's corners groove 1's rotated by θ_k = 2π(k − 1)/n1 (one closed
//!               polyline wall; the grooves key the wheel to the hub when it turns)
//! pack      (2) discs in the annulus at half size, radii × m = √((1 − n_target)/(1 − n_current))
//!               (S1) in small increments, cycled until tightly packed, rattlers removed and
//!               the rule applied again until n is within the tolerance of the target;
//!               contact bonds (Potyondy & Cundall 2004, §2.3: a bond at the contact point,
//!               normal and shear springs, strengths in force, no moment) between every two
//!               discs whose gap is at most the bond gap
//! grits     (3) the outer wall deleted; abrasive grits (clusters of overlapping discs:
//!               S1's triangle, square, round) on the rim, uniformly or randomly spaced with a
//!               minimum gap, protruding by `protrusion`; the wheel discs they overlap
//!               removed (and wheel discs left with no bond); each grit one rigid clump,
//!               bonded to the wheel discs within the grit bond gap by parallel bonds
//!               (Potyondy & Cundall 2004 §2.4), the second bond model
//! file      wheel.json (`dem.wheel/1`: parameters, groove corners, summary), beside it
//!           wheel.specimen.json (`dem.specimen/1`: discs, grits as rigid clumps, bonds per
//!           group) and wheel.scene.json (`dem.scene/1`: materials, both bond groups, the hub
//!           wall turning at `omega`), which `dem run` runs and `dem render` draws
//! ```
//!
//! Damping of the written scene: local damping α = 0.7 in the **fragment** frame
//! (`dem_core::damping`): PFC's lab-frame local damping, F_d = −α|F| sgn(v), is a one-signed
//! drag on a body in steady motion, and a spinning wheel's discs move steadily (each feels the
//! centripetal bond force, never changing the sign of its velocity in a quarter turn); the
//! fragment frame damps only the motion relative to the bonded wheel, so a free-spinning wheel
//! keeps its angular momentum (the test `free_wheel_keeps_its_spin` measures both frames).

pub mod geometry;
pub mod grits;
pub mod pack;

use crate::model::{material, pair};
use crate::specimen::rng::Rng;
use crate::LabError;
use dem_core::scene::schema::{
    BodiesSpec, BondGroupSpec, BondListSpec, BondModelName, ContactSpec, CriterionName,
    DampingSpec, DiscSetSpec, LawName, LengthUnit, RunSpec, SceneFile, SpecimenFile, SpecimenRef,
    WallSpec, SPECIMEN_SCHEMA,
};
use geometry::{GrooveRing, Walls};
use grits::GritParams;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// Schema identifier of the wheel file.
pub const WHEEL_SCHEMA: &str = "dem.wheel/1";
/// Bond groups and materials of the wheel scene.
pub const WHEEL_BOND: &str = "wheel_bond";
pub const GRIT_BOND: &str = "grit_bond";
pub const WHEEL_MATERIAL: &str = "wheel";
pub const GRIT_MATERIAL: &str = "grit";
pub const WALL_MATERIAL: &str = "wall";

/// Every parameter of a wheel (SI units).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct WheelParams {
    pub ring: GrooveRing,
    /// Wheel disc radii, uniform in [r_min, r_max] (m).
    pub r_min: f64,
    pub r_max: f64,
    /// Target porosity n of the wheel body and the accepted |n − n_target|.
    pub porosity: f64,
    pub porosity_tolerance: f64,
    pub seed: u64,
    /// Disc thickness t (m).
    pub thickness: f64,
    /// Wheel (bond) material: density (kg/m³), contact modulus E_c (k_n = 2tE_c, Pa),
    /// k_n/k_s, friction.
    pub density: f64,
    pub contact_modulus: f64,
    pub stiffness_ratio: f64,
    pub friction: f64,
    /// Contact bonds: k_n, k_s as the contact's; normal and shear strength σ·2r̄t with this
    /// σ (Pa).
    pub bond_strength: f64,
    /// Largest gap bonded between wheel discs (m).
    pub bond_gap: f64,
    pub grits: GritParams,
    /// Grit material: density (kg/m³) and contact modulus (Pa).
    pub grit_density: f64,
    pub grit_modulus: f64,
    /// Grit parallel bonds: modulus Ē_c (k̄_n = Ē_c/(2r̄), Pa), tensile and cohesive strength
    /// (Pa), λ̄ = 1; bonded when the gap is at most `grit_bond_gap` (m).
    pub grit_bond_modulus: f64,
    pub grit_bond_tensile: f64,
    pub grit_bond_cohesion: f64,
    pub grit_bond_gap: f64,
    /// The written scene: the hub's angular velocity (rad/s) and the steps it runs.
    pub omega: f64,
    pub steps: u64,
}

impl WheelParams {
    /// A small wheel: 5 mm outer, 2 mm hub radius, 6 grooves 0.6 × 0.5 mm, discs 0.1–0.15
    /// mm at porosity 0.18, 12 triangular grits of 5 rows of 0.06 mm discs, vitrified-bond-like
    /// wheel (2500 kg/m³, E_c 30 GPa) and diamond-like grits (3500 kg/m³, 300 GPa).
    pub fn small() -> WheelParams {
        WheelParams {
            ring: GrooveRing {
                r_outer: 5e-3,
                r_inner: 2e-3,
                grooves: 6,
                groove_depth: 0.5e-3,
                groove_width: 0.6e-3,
                outer_segments: 180,
            },
            r_min: 0.1e-3,
            r_max: 0.15e-3,
            porosity: 0.18,
            porosity_tolerance: 0.005,
            seed: 1,
            thickness: 1e-3,
            density: 2500.0,
            contact_modulus: 30e9,
            stiffness_ratio: 2.5,
            friction: 0.5,
            bond_strength: 50e6,
            bond_gap: 0.01e-3,
            grits: GritParams {
                shape: grits::GritShape::Triangle,
                rows: 5,
                radius: 0.06e-3,
                count: 12,
                spacing: grits::GritSpacing::Uniform,
                min_gap: 0.1e-3,
                protrusion: 0.1e-3,
            },
            grit_density: 3500.0,
            grit_modulus: 300e9,
            grit_bond_modulus: 30e9,
            grit_bond_tensile: 100e6,
            grit_bond_cohesion: 100e6,
            grit_bond_gap: 0.3e-3,
            omega: 0.0,
            steps: 1000,
        }
    }

    fn r_mean(&self) -> f64 {
        0.5 * (self.r_min + self.r_max)
    }

    /// Checks every field; errors name the field (and its `dem wheel` flag).
    pub fn validate(&self) -> Result<(), LabError> {
        let p = |f: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(LabError::Param {
                    field: f.into(),
                    reason: format!("{v}: must be positive"),
                })
            }
        };
        p("r_min (--r-min)", self.r_min)?;
        p("r_max (--r-max)", self.r_max)?;
        if self.r_max < self.r_min {
            return Err(LabError::Param {
                field: "r_max (--r-max)".into(),
                reason: format!("{} is below r_min {}", self.r_max, self.r_min),
            });
        }
        p("thickness (--thickness)", self.thickness)?;
        p("density (--density)", self.density)?;
        p("contact_modulus (--modulus)", self.contact_modulus)?;
        p("stiffness_ratio (--stiffness-ratio)", self.stiffness_ratio)?;
        p("bond_strength (--bond-strength)", self.bond_strength)?;
        p("grit_density (--grit-density)", self.grit_density)?;
        p("grit_modulus (--grit-modulus)", self.grit_modulus)?;
        p(
            "grit_bond_modulus (--grit-bond-modulus)",
            self.grit_bond_modulus,
        )?;
        p(
            "grit_bond_tensile (--grit-bond-tensile)",
            self.grit_bond_tensile,
        )?;
        p(
            "grit_bond_cohesion (--grit-bond-cohesion)",
            self.grit_bond_cohesion,
        )?;
        p(
            "porosity_tolerance (--porosity-tolerance)",
            self.porosity_tolerance,
        )?;
        for (f, v) in [
            ("friction (--friction)", self.friction),
            ("bond_gap (--bond-gap)", self.bond_gap),
            ("grit_bond_gap (--grit-bond-gap)", self.grit_bond_gap),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(LabError::Param {
                    field: f.into(),
                    reason: format!("{v}: must be >= 0"),
                });
            }
        }
        if !self.omega.is_finite() {
            return Err(LabError::Param {
                field: "omega (--omega)".into(),
                reason: "must be finite".into(),
            });
        }
        self.ring.validate(8.0 * self.r_max)?;
        self.grits.validate(self.ring.r_outer)
    }

    fn contact_kn(&self) -> f64 {
        2.0 * self.thickness * self.contact_modulus
    }
}

/// Figures of a built wheel.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct WheelSummary {
    pub porosity_target: f64,
    /// Porosity of the packed wheel body (before the grits), 1 − Σπr²/S.
    pub porosity_reached: f64,
    /// Area S of the annulus (m²).
    pub annulus_area: f64,
    pub pack: pack::PackStats,
    /// Wheel discs in the file, grit discs, grits.
    pub wheel_discs: usize,
    pub grit_discs: usize,
    pub grits: usize,
    /// Wheel discs removed where grits overlap them, and then left with no bond.
    pub removed_by_grits: usize,
    pub removed_unbonded: usize,
    /// Bonds per bond group.
    pub bonds: BTreeMap<String, usize>,
    /// Fewest parallel bonds of one grit.
    pub min_grit_bonds: usize,
}

impl WheelSummary {
    /// A few lines for people.
    pub fn text(&self) -> String {
        let bonds: Vec<String> = self.bonds.iter().map(|(k, v)| format!("{k} {v}")).collect();
        format!(
            "porosity {:.4} (target {:.4}; placed at {:.4}, m = {:?})\n\
             discs: {} wheel, {} in {} grits; removed: {} under grits, {} left unbonded, {} in \
             packing\nbonds: {} (fewest per grit {})\n",
            self.porosity_reached,
            self.porosity_target,
            self.pack.porosity_placed,
            self.pack
                .factors
                .iter()
                .map(|m| (m * 1e5).round() / 1e5)
                .collect::<Vec<_>>(),
            self.wheel_discs,
            self.grit_discs,
            self.grits,
            self.removed_by_grits,
            self.removed_unbonded,
            self.pack.removed,
            bonds.join(", "),
            self.min_grit_bonds
        )
    }
}

/// A built wheel.
#[derive(Clone, Debug)]
pub struct Wheel {
    pub params: WheelParams,
    pub walls: Walls,
    /// Wheel discs `[x, y, r]` (m), and as packed (before the grits).
    pub discs: Vec<[f64; 3]>,
    pub packed: Vec<[f64; 3]>,
    /// Each grit's discs `[x, y, r]`.
    pub grits: Vec<Vec<[f64; 3]>>,
    /// Contact bonds between wheel discs (indices into `discs`) and each pair's gap at
    /// installation when negative (else 0).
    pub wheel_bonds: Vec<([u32; 2], f64)>,
    /// Parallel bonds: (wheel disc index, grit index, disc index in the grit).
    pub grit_bonds: Vec<(u32, u32, u32)>,
    pub summary: WheelSummary,
}

fn gap(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1]) - a[2] - b[2]
}

/// Pairs (i < j) of `d` whose gap is at most `tol`, on a grid.
fn pairs_within(d: &[[f64; 3]], tol: f64) -> Vec<(usize, usize)> {
    let rmax = d.iter().map(|p| p[2]).fold(0.0, f64::max);
    let cell = 2.0 * rmax + tol;
    let mut grid: BTreeMap<(i64, i64), Vec<usize>> = BTreeMap::new();
    let key = |p: [f64; 3]| ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64);
    for (k, p) in d.iter().enumerate() {
        grid.entry(key(*p)).or_default().push(k);
    }
    let mut out = Vec::new();
    for (i, p) in d.iter().enumerate() {
        let (cx, cy) = key(*p);
        for gx in cx - 1..=cx + 1 {
            for gy in cy - 1..=cy + 1 {
                if let Some(v) = grid.get(&(gx, gy)) {
                    for &j in v {
                        if j > i && gap(*p, d[j]) <= tol {
                            out.push((i, j));
                        }
                    }
                }
            }
        }
    }
    out.sort_unstable();
    out
}

/// Builds the wheel: walls, packing, contact bonds, grits, removals, parallel bonds.
pub fn build(p: &WheelParams, progress: &mut dyn FnMut(&str)) -> Result<Wheel, LabError> {
    p.validate()?;
    let walls = p.ring.walls();
    let input = pack::PackInput {
        r_min: p.r_min,
        r_max: p.r_max,
        porosity: p.porosity,
        tolerance: p.porosity_tolerance,
        density: p.density,
        thickness: p.thickness,
        kn: p.contact_kn(),
        stiffness_ratio: p.stiffness_ratio,
        bond_gap: p.bond_gap,
        seed: p.seed,
        max_stage_steps: 20_000,
    };
    let (mut discs, stats) = pack::pack(&walls, &input, progress)?;
    let mut summary = WheelSummary {
        porosity_target: p.porosity,
        porosity_reached: stats.porosity_reached,
        annulus_area: walls.area,
        pack: stats,
        ..WheelSummary::default()
    };
    // Grits (the outer wall is not carried over: deleted).
    let mut rng = Rng::new(p.seed ^ 0x9e37_79b9_7f4a_7c15);
    let grits: Vec<Vec<[f64; 3]>> = p
        .grits
        .place(p.ring.r_outer, &mut rng)
        .into_iter()
        .map(|g| {
            g.into_iter()
                .map(|c| [c[0], c[1], p.grits.radius])
                .collect()
        })
        .collect();
    let packed = discs.clone();
    let under = |d: [f64; 3]| grits.iter().flatten().any(|g| gap(d, *g) < 0.0);
    let before = discs.len();
    discs.retain(|d| !under(*d));
    summary.removed_by_grits = before - discs.len();
    // Contact bonds, then the wheel discs no bond holds (repeat: a removal can strand others).
    let mut bonds;
    loop {
        bonds = pairs_within(&discs, p.bond_gap);
        let mut held = vec![false; discs.len()];
        for &(i, j) in &bonds {
            held[i] = true;
            held[j] = true;
        }
        let n = discs.len();
        let mut k = 0;
        discs.retain(|_| {
            k += 1;
            held[k - 1]
        });
        summary.removed_unbonded += n - discs.len();
        if discs.len() == n {
            break;
        }
    }
    let wheel_bonds: Vec<([u32; 2], f64)> = bonds
        .iter()
        .map(|&(i, j)| ([i as u32, j as u32], gap(discs[i], discs[j]).min(0.0)))
        .collect();
    let mut grit_bonds = Vec::new();
    let mut min_grit = usize::MAX;
    for (g, grit) in grits.iter().enumerate() {
        let mut n = 0;
        for (k, d) in discs.iter().enumerate() {
            for (m, c) in grit.iter().enumerate() {
                if gap(*d, *c) <= p.grit_bond_gap {
                    grit_bonds.push((k as u32, g as u32, m as u32));
                    n += 1;
                }
            }
        }
        if n == 0 {
            let near = discs
                .iter()
                .flat_map(|d| grit.iter().map(move |c| gap(*d, *c)))
                .fold(f64::INFINITY, f64::min);
            return Err(LabError::Param {
                field: "grit protrusion (--protrusion)".into(),
                reason: format!(
                    "grit {} has no wheel disc within the grit bond gap {:.4} mm (the nearest \
                     is {:.4} mm away): embed the grits deeper (a smaller --protrusion) or \
                     widen --grit-bond-gap",
                    g + 1,
                    p.grit_bond_gap * 1e3,
                    near * 1e3
                ),
            });
        }
        min_grit = min_grit.min(n);
    }
    summary.min_grit_bonds = if grits.is_empty() { 0 } else { min_grit };
    summary.wheel_discs = discs.len();
    summary.grits = grits.len();
    summary.grit_discs = grits.iter().map(|g| g.len()).sum();
    summary.bonds.insert(WHEEL_BOND.into(), wheel_bonds.len());
    summary.bonds.insert(GRIT_BOND.into(), grit_bonds.len());
    progress(&format!(
        "{} wheel discs, {} grits, {} contact bonds, {} parallel bonds",
        discs.len(),
        grits.len(),
        wheel_bonds.len(),
        grit_bonds.len()
    ));
    Ok(Wheel {
        params: p.clone(),
        walls,
        discs,
        packed,
        grits,
        wheel_bonds,
        grit_bonds,
        summary,
    })
}

/// The wheel file (`dem.wheel/1`).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct WheelFile {
    /// Always `"dem.wheel/1"`.
    pub schema: String,
    pub params: WheelParams,
    /// Groove corners c1..c4 of each groove (m).
    pub groove_corners: Vec<[[f64; 2]; 4]>,
    pub summary: WheelSummary,
    /// The specimen and scene files beside it (relative names).
    pub specimen: String,
    pub scene: String,
}

impl Wheel {
    /// The discs and bonds as a `dem.specimen/1` file: wheel discs first (group 0), then the
    /// grit discs (group = grit number), each grit a rigid clump.
    pub fn specimen_file(&self) -> SpecimenFile {
        let nw = self.discs.len() as u32;
        let mut start = Vec::new();
        let mut s = nw;
        for g in &self.grits {
            start.push(s);
            s += g.len() as u32;
        }
        let wheel = DiscSetSpec {
            material: WHEEL_MATERIAL.into(),
            group: 0,
            velocity: [0.0; 2],
            omega: 0.0,
            random_speed: 0.0,
            fixed: false,
            discs: self.discs.clone(),
            groups: None,
            mass_factors: None,
        };
        let grit = DiscSetSpec {
            material: GRIT_MATERIAL.into(),
            discs: self.grits.iter().flatten().copied().collect(),
            groups: Some(
                self.grits
                    .iter()
                    .enumerate()
                    .flat_map(|(g, v)| std::iter::repeat_n(g as u32 + 1, v.len()))
                    .collect(),
            ),
            ..wheel.clone()
        };
        let rigid_clumps = self
            .grits
            .iter()
            .zip(&start)
            .map(|(g, &s)| (s..s + g.len() as u32).collect())
            .collect();
        let offsets: Vec<f64> = self.wheel_bonds.iter().map(|b| b.1).collect();
        let mut bonds = vec![BondListSpec {
            bond_group: WHEEL_BOND.into(),
            pairs: self.wheel_bonds.iter().map(|b| b.0).collect(),
            contact_offsets: offsets.iter().any(|&g| g < 0.0).then_some(offsets),
        }];
        if !self.grit_bonds.is_empty() {
            bonds.push(BondListSpec {
                bond_group: GRIT_BOND.into(),
                pairs: self
                    .grit_bonds
                    .iter()
                    .map(|&(k, g, m)| [k, start[g as usize] + m])
                    .collect(),
                contact_offsets: None,
            });
        }
        let mut discs = vec![wheel];
        if !self.grits.is_empty() {
            discs.push(grit);
        }
        SpecimenFile {
            schema: SPECIMEN_SCHEMA.into(),
            description: format!(
                "S1 grinding wheel, r {:.3}-{:.3} mm, {} grooves, porosity {:.4}, {} grits; \
                 written by dem wheel",
                self.params.ring.r_inner * 1e3,
                self.params.ring.r_outer * 1e3,
                self.params.ring.grooves,
                self.summary.porosity_reached,
                self.grits.len()
            ),
            units: LengthUnit::M,
            discs,
            clumps: Vec::new(),
            rigid_clumps,
            bonds,
        }
    }

    /// The scene: materials (wheel, grit, frictionless wall), the two bond groups, the
    /// specimen `specimen` (relative to the scene), the grooved hub wall turning at `omega`
    /// about the centre (`with_hub`), local damping 0.7 in the fragment frame.
    pub fn scene_file(&self, name: &str, specimen: &str, with_hub: bool) -> SceneFile {
        let p = &self.params;
        let kn = p.contact_kn();
        let ks = kn / p.stiffness_ratio;
        let kg = 2.0 * p.thickness * p.grit_modulus;
        let r_bar = 0.5 * (p.r_mean() + p.grits.radius);
        let strength = p.bond_strength * 2.0 * p.r_mean() * p.thickness;
        let contact_bond = BondGroupSpec {
            kn: Some(kn),
            ks: Some(ks),
            normal_strength: Some(strength),
            shear_strength: Some(strength),
            ..BondGroupSpec::new(WHEEL_BOND, BondModelName::ContactBond, CriterionName::Force)
        };
        let kb = p.grit_bond_modulus / (2.0 * r_bar);
        let parallel = BondGroupSpec {
            kn: Some(kb),
            ks: Some(kb / p.stiffness_ratio),
            radius_multiplier: Some(1.0),
            moment_factor: Some(1.0),
            tensile_strength: Some(p.grit_bond_tensile),
            cohesion: Some(p.grit_bond_cohesion),
            friction_angle: Some(0.0),
            ..BondGroupSpec::new(
                GRIT_BOND,
                BondModelName::ParallelPotyondy2004,
                CriterionName::Stress,
            )
        };
        let inner = &self.walls.inner;
        let walls = if with_hub {
            vec![WallSpec {
                name: "hub".into(),
                a: inner[0],
                b: inner[inner.len() - 1],
                via: inner[1..inner.len() - 1].to_vec(),
                material: WALL_MATERIAL.into(),
                velocity: [0.0; 2],
                angular_velocity: p.omega,
                center: Some([0.0, 0.0]),
                servo: None,
            }]
        } else {
            Vec::new()
        };
        SceneFile {
            description: format!(
                "S1 grinding wheel ({} wheel discs, {} grits) on its grooved hub; written by \
                 dem wheel",
                self.discs.len(),
                self.grits.len()
            ),
            thickness: Some(p.thickness),
            seed: p.seed,
            materials: vec![
                material(WHEEL_MATERIAL, Some(p.density), kn, ks, p.friction),
                material(
                    GRIT_MATERIAL,
                    Some(p.grit_density),
                    kg,
                    kg / p.stiffness_ratio,
                    p.friction,
                ),
                material(WALL_MATERIAL, None, kn, ks, 0.0),
            ],
            contact: ContactSpec {
                law: LawName::LinearSpringDashpot,
                rolling: false,
                granular: None,
                pairs: vec![
                    pair(WHEEL_MATERIAL, WALL_MATERIAL, kn, ks, 0.0),
                    pair(GRIT_MATERIAL, WALL_MATERIAL, kn, ks, 0.0),
                ],
            },
            bond_groups: vec![contact_bond, parallel],
            bodies: BodiesSpec {
                specimens: vec![SpecimenRef {
                    file: specimen.into(),
                    offset: [0.0, 0.0],
                    velocity: [0.0, 0.0],
                }],
                ..BodiesSpec::default()
            },
            walls,
            damping: DampingSpec {
                local: 0.7,
                viscous: 0.0,
                frame: dem_core::damping::DampingFrame::Fragment,
            },
            run: RunSpec {
                steps: Some(p.steps),
                ..RunSpec::default()
            },
            ..SceneFile::new(name)
        }
    }

    /// Writes `dir`/wheel.json, wheel.specimen.json and wheel.scene.json, each atomically;
    /// returns their paths.
    pub fn save(&self, dir: &Path) -> Result<[PathBuf; 3], LabError> {
        std::fs::create_dir_all(dir).map_err(|source| LabError::Io {
            file: dir.display().to_string(),
            source,
        })?;
        let files = [
            dir.join("wheel.json"),
            dir.join("wheel.specimen.json"),
            dir.join("wheel.scene.json"),
        ];
        let file = WheelFile {
            schema: WHEEL_SCHEMA.into(),
            params: self.params.clone(),
            groove_corners: self.walls.corners.clone(),
            summary: self.summary.clone(),
            specimen: "wheel.specimen.json".into(),
            scene: "wheel.scene.json".into(),
        };
        let json = |v: &dyn erased::Ser| v.text();
        let texts = [
            json(&file),
            json(&self.specimen_file()),
            json(&self.scene_file("wheel", "wheel.specimen.json", true)),
        ];
        for (f, t) in files.iter().zip(texts) {
            crate::specimen::io::write_atomic(f, &t?)?;
        }
        Ok(files)
    }
}

mod erased {
    /// Pretty JSON of any of the three file types.
    pub trait Ser {
        fn text(&self) -> Result<String, crate::LabError>;
    }
    impl<T: serde::Serialize> Ser for T {
        fn text(&self) -> Result<String, crate::LabError> {
            serde_json::to_string_pretty(self).map_err(|e| crate::LabError::Param {
                field: "wheel file".into(),
                reason: e.to_string(),
            })
        }
    }
}

/// Reads a wheel file.
pub fn read(path: &Path) -> Result<WheelFile, LabError> {
    let f: WheelFile = crate::read_json(path)?;
    if f.schema != WHEEL_SCHEMA {
        return Err(LabError::Param {
            field: format!("{}: schema", path.display()),
            reason: format!("{:?}: expected {WHEEL_SCHEMA:?}", f.schema),
        });
    }
    Ok(f)
}

/// Area of the discs' union is not needed: S1's porosity counts Σπr² (overlaps included).
pub fn disc_area(d: &[[f64; 3]]) -> f64 {
    d.iter().map(|p| PI * p[2] * p[2]).sum()
}

#[cfg(test)]
mod tests;
