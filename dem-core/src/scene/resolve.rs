//! Scene file → [`Scene`]: parse (unknown fields rejected, errors with the JSON path), convert
//! lengths to SI once, resolve names to indices, load templates and specimens, check every value.
//! Every error names the file, the field and the reason.

use super::check::{dir_of, parse_json, Ck};
use super::controls;
use super::mix::pair_laws;
use super::model::*;
use super::schema::*;
use super::SceneError;
use crate::bond::BondGroup;
use clumpgen::synth::SplitMix64;
use clumpgen::Template;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Reads, parses and checks a scene file.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text = clumpgen::io::read_input_string(path).map_err(|source| SceneError::Io {
        file: path.display().to_string(),
        source,
    })?;
    parse(&text, path)
}

/// Parses and checks scene text; `path` names it in errors and anchors relative paths.
pub fn parse(text: &str, path: &Path) -> Result<Scene, SceneError> {
    let file = path.display().to_string();
    let raw: SceneFile = parse_json(text, &file)?;
    resolve(raw, path)
}

/// Checks a scene held in memory as the file types, as [`parse`] checks its text: for
/// programs that build scenes as typed values (the lab tests) and write them for `dem run`
/// beside their results. `path` is where the scene is (or would be) written: it names the
/// scene in errors and anchors relative paths (specimen files, templates).
pub fn resolve(raw: SceneFile, path: &Path) -> Result<Scene, SceneError> {
    Resolver::new(path).scene(raw)
}

/// State of one scene load: material and group names, template cache, id counters.
struct Resolver {
    scene_path: PathBuf,
    ck: Ck,
    materials: HashMap<String, u16>,
    densities: Vec<Option<f64>>,
    thickness: f64,
    groups: HashMap<String, usize>,
    template_index: HashMap<PathBuf, usize>,
    templates: Vec<Template>,
    discs: Vec<DiscInit>,
    clumps: Vec<ClumpInit>,
    /// From specimen files: rigid clumps of listed discs and explicit bonds.
    rigid_clumps: Vec<Vec<usize>>,
    bonds: Vec<ExplicitBond>,
    /// The scene's random numbers (initial speeds): SplitMix64 seeded with `seed`.
    rng: SplitMix64,
}

fn v2(v: [f64; 2], u: f64) -> [f64; 2] {
    [v[0] * u, v[1] * u]
}

impl Resolver {
    fn new(path: &Path) -> Resolver {
        Resolver {
            scene_path: path.to_path_buf(),
            ck: Ck {
                file: path.display().to_string(),
            },
            materials: HashMap::new(),
            densities: Vec::new(),
            thickness: 1.0,
            groups: HashMap::new(),
            template_index: HashMap::new(),
            templates: Vec::new(),
            discs: Vec::new(),
            clumps: Vec::new(),
            rigid_clumps: Vec::new(),
            bonds: Vec::new(),
            rng: SplitMix64::new(0),
        }
    }

    fn scene(mut self, raw: SceneFile) -> Result<Scene, SceneError> {
        let ck = Ck {
            file: self.ck.file.clone(),
        };
        if raw.schema != SCHEMA {
            return Err(ck.err(
                "schema",
                format!("is {:?}, expected {SCHEMA:?}", raw.schema),
            ));
        }
        let u = raw.units.metres();
        self.thickness = match raw.thickness {
            Some(t) => ck.positive("thickness", t)? * u,
            None => 1.0,
        };
        self.rng = SplitMix64::new(raw.seed);
        let materials = self.materials(&raw.materials)?;
        let bond_groups = self.bond_groups(&raw.bond_groups)?;
        let scene_dir = dir_of(&self.scene_path);
        for (i, set) in raw.bodies.discs.iter().enumerate() {
            self.disc_set(&ck, &format!("bodies.discs[{i}]"), set, u, [0.0; 2])?;
        }
        let mut clump_sets = Vec::new();
        for (i, set) in raw.bodies.clumps.iter().enumerate() {
            clump_sets.push((
                format!("bodies.clumps[{i}]"),
                set.clone(),
                u,
                [0.0; 2],
                scene_dir.clone(),
                ck.file.clone(),
            ));
        }
        for (i, sp) in raw.bodies.specimens.iter().enumerate() {
            let field = format!("bodies.specimens[{i}]");
            let path = scene_dir.join(&sp.file);
            let off = v2(
                [
                    ck.finite(&format!("{field}.offset[0]"), sp.offset[0])?,
                    ck.finite(&format!("{field}.offset[1]"), sp.offset[1])?,
                ],
                u,
            );
            let text = clumpgen::io::read_input_string(&path).map_err(|e| {
                ck.err(
                    format!("{field}.file"),
                    format!("cannot read {}: {e}", path.display()),
                )
            })?;
            let sfile = path.display().to_string();
            let spec: SpecimenFile = parse_json(&text, &sfile)?;
            let sck = Ck {
                file: sfile.clone(),
            };
            if spec.schema != SPECIMEN_SCHEMA {
                return Err(sck.err(
                    "schema",
                    format!("is {:?}, expected {SPECIMEN_SCHEMA:?}", spec.schema),
                ));
            }
            let su = spec.units.metres();
            let sv = v2(
                [
                    ck.finite(&format!("{field}.velocity[0]"), sp.velocity[0])?,
                    ck.finite(&format!("{field}.velocity[1]"), sp.velocity[1])?,
                ],
                u,
            );
            let base = self.discs.len();
            for (k, set) in spec.discs.iter().enumerate() {
                self.disc_set(&sck, &format!("discs[{k}]"), set, su, off)?;
            }
            let n = self.discs.len() - base;
            for d in &mut self.discs[base..] {
                d.vx += sv[0];
                d.vy += sv[1];
            }
            let links = resolve_links(&sfile, &spec, base, n, su, |f, g| self.group(&sck, f, g))?;
            self.rigid_clumps.extend(links.0);
            self.bonds.extend(links.1);
            for (k, set) in spec.clumps.iter().enumerate() {
                // (Placement velocities are in the specimen's unit.)
                let mut set = set.clone();
                for p in &mut set.placements {
                    p.velocity[0] += sv[0] / su;
                    p.velocity[1] += sv[1] / su;
                }
                clump_sets.push((
                    format!("clumps[{k}]"),
                    set,
                    su,
                    off,
                    dir_of(&path),
                    sfile.clone(),
                ));
            }
        }
        // Clumps get groups after every disc set's: one new group per placed clump.
        let mut next_group = self
            .discs
            .iter()
            .map(|d| d.group as u64 + 1)
            .max()
            .unwrap_or(0);
        for (field, set, su, off, dir, file) in clump_sets {
            let cck = Ck { file };
            self.clump_set(&cck, &field, &set, su, off, &dir, &mut next_group)?;
        }
        let auto_bonds = self.auto_bonds(&raw.auto_bonds, u)?;
        let walls = self.walls(&raw.walls, u)?;
        let loads = self.loads(&raw.loads)?;
        let periodic = controls::periodic(&ck, raw.periodic.as_ref(), u)?;
        let gravity = match raw.gravity {
            Some(g) => Some([
                ck.finite("gravity[0]", g[0])? * u,
                ck.finite("gravity[1]", g[1])? * u,
            ]),
            None => None,
        };
        let damping = Damping {
            local: ck.range("damping.local", raw.damping.local, 0.0, 1.0, false)?,
            viscous: ck.range("damping.viscous", raw.damping.viscous, 0.0, 1.0, false)?,
            frame: raw.damping.frame,
        };
        let run = controls::run(&ck, &raw.run, u, &walls, &raw.outputs)?;
        let outputs = controls::outputs(&ck, &self.scene_path, &raw.outputs, u)?;
        if self.discs.is_empty() && self.clumps.is_empty() {
            return Err(ck.err("bodies", "the scene has no discs"));
        }
        let mut scene = Scene {
            file: self.scene_path.clone(),
            name: raw.name,
            thickness: self.thickness,
            seed: raw.seed,
            materials,
            pairs: Vec::new(),
            bond_groups,
            templates: std::mem::take(&mut self.templates),
            discs: std::mem::take(&mut self.discs),
            clumps: std::mem::take(&mut self.clumps),
            rigid_clumps: std::mem::take(&mut self.rigid_clumps),
            bonds: std::mem::take(&mut self.bonds),
            auto_bonds,
            walls,
            loads,
            periodic,
            gravity,
            damping,
            run,
            outputs,
        };
        scene.pairs = pair_laws(&ck, &scene, &raw.contact, &self.materials)?;
        Ok(scene)
    }

    fn material(&self, ck: &Ck, field: &str, name: &str) -> Result<u16, SceneError> {
        self.materials
            .get(name)
            .copied()
            .ok_or_else(|| ck.err(field, format!("no material named {name:?}")))
    }

    /// A material discs are made of: it must have a density.
    fn disc_material(&self, ck: &Ck, field: &str, name: &str) -> Result<(u16, f64), SceneError> {
        let m = self.material(ck, field, name)?;
        match self.densities[m as usize] {
            Some(rho) => Ok((m, rho)),
            None => Err(ck.err(
                field,
                format!("material {name:?} has no density; discs need one"),
            )),
        }
    }

    fn materials(&mut self, raw: &[MaterialSpec]) -> Result<Vec<Material>, SceneError> {
        let ck = &self.ck;
        if raw.is_empty() {
            return Err(ck.err("materials", "at least one material is needed"));
        }
        if raw.len() > u16::MAX as usize {
            return Err(ck.err("materials", "too many materials"));
        }
        let mut out = Vec::new();
        for (i, m) in raw.iter().enumerate() {
            let f = |k: &str| format!("materials[{i}].{k}");
            if m.name.is_empty() {
                return Err(ck.err(f("name"), "must not be empty"));
            }
            if self.materials.insert(m.name.clone(), i as u16).is_some() {
                return Err(ck.err(f("name"), format!("material {:?} is defined twice", m.name)));
            }
            let opt_pos = |k: &str, v: Option<f64>| v.map(|v| ck.positive(&f(k), v)).transpose();
            let density = opt_pos("density", m.density)?;
            let kn = opt_pos("kn", m.kn)?;
            let ks = opt_pos("ks", m.ks)?;
            let youngs_modulus = opt_pos("youngs_modulus", m.youngs_modulus)?;
            let poisson = m
                .poisson
                .map(|v| ck.range(&f("poisson"), v, -1.0, 0.5, false))
                .transpose()?;
            if m.restitution.is_some() && m.damping_ratio.is_some() {
                return Err(ck.err(
                    f("restitution"),
                    "give restitution or damping_ratio, not both",
                ));
            }
            let restitution = m
                .restitution
                .map(|v| ck.range(&f("restitution"), v, 0.0, 1.0, true))
                .transpose()?;
            if restitution == Some(0.0) {
                return Err(ck.err(f("restitution"), "must be above 0"));
            }
            out.push(Material {
                name: m.name.clone(),
                density,
                kn,
                ks,
                youngs_modulus,
                poisson,
                friction: ck.non_negative(&f("friction"), m.friction)?,
                restitution,
                damping_ratio: m
                    .damping_ratio
                    .map(|v| ck.range(&f("damping_ratio"), v, 0.0, 1.0, false))
                    .transpose()?,
                rolling_friction: ck.non_negative(&f("rolling_friction"), m.rolling_friction)?,
            });
            self.densities.push(density);
        }
        Ok(out)
    }

    fn bond_groups(&mut self, raw: &[BondGroupSpec]) -> Result<Vec<BondGroup>, SceneError> {
        let mut out = Vec::new();
        for (i, g) in raw.iter().enumerate() {
            let f = |k: &str| format!("bond_groups[{i}].{k}");
            if g.name.is_empty() {
                return Err(self.ck.err(f("name"), "must not be empty"));
            }
            if self.groups.insert(g.name.clone(), i).is_some() {
                return Err(self.ck.err(
                    f("name"),
                    format!("bond group {:?} is defined twice", g.name),
                ));
            }
            out.push(super::bondspec::bond_group(&self.ck, i, g)?);
        }
        Ok(out)
    }

    fn group(&self, ck: &Ck, field: &str, name: &str) -> Result<usize, SceneError> {
        self.groups
            .get(name)
            .copied()
            .ok_or_else(|| ck.err(field, format!("no bond group named {name:?}")))
    }

    fn disc_set(
        &mut self,
        ck: &Ck,
        field: &str,
        set: &DiscSetSpec,
        u: f64,
        off: [f64; 2],
    ) -> Result<(), SceneError> {
        let (material, rho) =
            self.disc_material(ck, &format!("{field}.material"), &set.material)?;
        let n = set.discs.len();
        if set.groups.as_ref().is_some_and(|g| g.len() != n) {
            return Err(ck.err(
                format!("{field}.groups"),
                format!("needs {n} entries, one per disc"),
            ));
        }
        if let Some(f) = &set.mass_factors {
            if f.len() != n {
                return Err(ck.err(
                    format!("{field}.mass_factors"),
                    format!("needs {n} entries, one per disc"),
                ));
            }
            for (k, &v) in f.iter().enumerate() {
                ck.positive(&format!("{field}.mass_factors[{k}]"), v)?;
            }
        }
        let vel = [
            ck.finite(&format!("{field}.velocity[0]"), set.velocity[0])? * u,
            ck.finite(&format!("{field}.velocity[1]"), set.velocity[1])? * u,
        ];
        let omega = ck.finite(&format!("{field}.omega"), set.omega)?;
        let speed = ck.non_negative(&format!("{field}.random_speed"), set.random_speed)? * u;
        for (k, d) in set.discs.iter().enumerate() {
            let x = ck.finite(&format!("{field}.discs[{k}][0]"), d[0])?;
            let y = ck.finite(&format!("{field}.discs[{k}][1]"), d[1])?;
            let r = d[2];
            if !(r.is_finite() && r > 0.0) {
                return Err(ck.err(
                    format!("{field}.discs[{k}][2]"),
                    format!("radius must be positive (got {r})"),
                ));
            }
            let (mut vx, mut vy) = (vel[0], vel[1]);
            if speed > 0.0 {
                let a = std::f64::consts::TAU * self.rng.uniform();
                vx += speed * a.cos();
                vy += speed * a.sin();
            }
            self.discs.push(DiscInit {
                x: x * u + off[0],
                y: y * u + off[1],
                r: r * u,
                vx,
                vy,
                omega,
                material,
                group: set.groups.as_ref().map_or(set.group, |g| g[k]),
                fixed: set.fixed,
                mass: set.mass_factors.as_ref().map(|f| {
                    let r = r * u;
                    let m = f[k] * rho * self.thickness * std::f64::consts::PI * r * r;
                    (m, 0.5 * m * r * r)
                }),
            });
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn clump_set(
        &mut self,
        ck: &Ck,
        field: &str,
        set: &ClumpSetSpec,
        u: f64,
        off: [f64; 2],
        dir: &Path,
        next_group: &mut u64,
    ) -> Result<(), SceneError> {
        let (material, rho) =
            self.disc_material(ck, &format!("{field}.material"), &set.material)?;
        let path = dir.join(&set.template);
        let ti = match self.template_index.get(&path) {
            Some(&t) => t,
            None => {
                let t = Template::load(&path)
                    .map_err(|e| ck.err(format!("{field}.template"), e.to_string()))?;
                self.templates.push(t);
                self.template_index
                    .insert(path.clone(), self.templates.len() - 1);
                self.templates.len() - 1
            }
        };
        let t = &self.templates[ti];
        let density_ratio = rho / t.density;
        let bond_group = match (set.mode, &set.bond_group) {
            (ClumpMode::Bonded, Some(g)) => {
                Some(self.group(ck, &format!("{field}.bond_group"), g)?)
            }
            (ClumpMode::Bonded, None) => {
                return Err(ck.err(
                    format!("{field}.bond_group"),
                    "a bonded clump needs the bond group of its intra-clump bonds",
                ))
            }
            (ClumpMode::Rigid, Some(_)) => {
                return Err(ck.err(
                    format!("{field}.bond_group"),
                    "a rigid clump has no bonds; remove bond_group or use mode \"bonded\"",
                ))
            }
            (ClumpMode::Rigid, None) => None,
        };
        let bond_tolerance =
            ck.non_negative(&format!("{field}.bond_tolerance"), set.bond_tolerance)? * u;
        for (k, p) in set.placements.iter().enumerate() {
            let f = |s: &str| format!("{field}.placements[{k}].{s}");
            if *next_group > u32::MAX as u64 {
                return Err(ck.err(f("x"), "too many groups"));
            }
            self.clumps.push(ClumpInit {
                template: ti,
                material,
                mode: set.mode,
                bond_group,
                bond_tolerance,
                density_ratio,
                x: ck.finite(&f("x"), p.x)? * u + off[0],
                y: ck.finite(&f("y"), p.y)? * u + off[1],
                angle: ck.finite(&f("angle"), p.angle)?,
                vx: ck.finite(&f("velocity[0]"), p.velocity[0])? * u,
                vy: ck.finite(&f("velocity[1]"), p.velocity[1])? * u,
                omega: ck.finite(&f("omega"), p.omega)?,
                group: *next_group as u32,
            });
            *next_group += 1;
        }
        Ok(())
    }

    fn auto_bonds(&self, raw: &[AutoBondSpec], u: f64) -> Result<Vec<AutoBond>, SceneError> {
        let ck = &self.ck;
        raw.iter()
            .enumerate()
            .map(|(i, a)| {
                let f = |k: &str| format!("auto_bonds[{i}].{k}");
                let materials = a
                    .materials
                    .iter()
                    .enumerate()
                    .map(|(k, m)| self.material(ck, &f(&format!("materials[{k}]")), m))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(AutoBond {
                    bond_group: self.group(ck, &f("bond_group"), &a.bond_group)?,
                    tolerance: ck.non_negative(&f("tolerance"), a.tolerance)? * u,
                    between: a.between,
                    materials,
                })
            })
            .collect()
    }

    fn walls(&self, raw: &[WallSpec], u: f64) -> Result<Vec<WallInit>, SceneError> {
        let ck = &self.ck;
        let mut names = std::collections::HashSet::new();
        raw.iter()
            .enumerate()
            .map(|(i, w)| {
                let f = |k: &str| format!("walls[{i}].{k}");
                if !names.insert(w.name.clone()) {
                    return Err(ck.err(f("name"), format!("wall {:?} is defined twice", w.name)));
                }
                let p = |k: &str, v: [f64; 2]| -> Result<[f64; 2], SceneError> {
                    Ok([
                        ck.finite(&format!("{}[0]", f(k)), v[0])? * u,
                        ck.finite(&format!("{}[1]", f(k)), v[1])? * u,
                    ])
                };
                let (a, b) = (p("a", w.a)?, p("b", w.b)?);
                let via = (w.via.iter().enumerate())
                    .map(|(k, &q)| p(&format!("via[{k}]"), q))
                    .collect::<Result<Vec<_>, _>>()?;
                // Consecutive vertices must differ (a zero-length face has no direction).
                let mut prev = ("a".to_string(), a);
                for (k, &q) in via.iter().enumerate() {
                    if q == prev.1 {
                        return Err(ck.err(
                            f(&format!("via[{k}]")),
                            format!("the vertex repeats {}", prev.0),
                        ));
                    }
                    prev = (format!("via[{k}]"), q);
                }
                if a == b && via.is_empty() {
                    return Err(ck.err(f("b"), "the wall's end points coincide"));
                }
                if b == prev.1 {
                    return Err(ck.err(f("b"), format!("the vertex repeats {}", prev.0)));
                }
                let center = match w.center {
                    Some(c) => p("center", c)?,
                    None => [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])],
                };
                Ok(WallInit {
                    name: w.name.clone(),
                    a,
                    b,
                    via,
                    material: self.material(ck, &f("material"), &w.material)?,
                    velocity: p("velocity", w.velocity)?,
                    angular_velocity: ck.finite(&f("angular_velocity"), w.angular_velocity)?,
                    center,
                    servo: w
                        .servo
                        .as_ref()
                        .map(|s| self.servo(s, w, &f("servo"), u))
                        .transpose()?,
                })
            })
            .collect()
    }

    /// A wall's servo in SI; `field` names it (`walls[i].servo`).
    fn servo(
        &self,
        s: &ServoSpec,
        w: &WallSpec,
        field: &str,
        u: f64,
    ) -> Result<crate::wall_servo::WallServo, SceneError> {
        let ck = &self.ck;
        let f = |k: &str| format!("{field}.{k}");
        if w.velocity != [0.0; 2] || w.angular_velocity != 0.0 {
            return Err(ck.err(
                field.to_string(),
                "a servo wall's velocity is the servo's: give velocity [0, 0] and no angular_velocity",
            ));
        }
        let d = [
            ck.finite(&f("direction[0]"), s.direction[0])?,
            ck.finite(&f("direction[1]"), s.direction[1])?,
        ];
        let n = d[0].hypot(d[1]);
        if n == 0.0 {
            return Err(ck.err(f("direction"), "must not be [0, 0]"));
        }
        Ok(crate::wall_servo::WallServo {
            stress: ck.non_negative(&f("stress"), s.stress)?,
            length: ck.positive(&f("length"), s.length)? * u,
            direction: [d[0] / n, d[1] / n],
            alpha: ck.range(
                &f("alpha"),
                ck.positive(&f("alpha"), s.alpha)?,
                0.0,
                1.0,
                true,
            )?,
            max_speed: ck.positive(&f("max_speed"), s.max_speed)? * u,
        })
    }

    fn loads(&self, raw: &[LoadSpec]) -> Result<Vec<crate::pipeline::ExternalLoad>, SceneError> {
        let n = self.discs.len()
            + self
                .clumps
                .iter()
                .map(|c| self.templates[c.template].discs.len())
                .sum::<usize>();
        raw.iter()
            .enumerate()
            .map(|(i, l)| {
                let f = |k: &str| format!("loads[{i}].{k}");
                if l.disc as usize >= n {
                    return Err(self.ck.err(
                        f("disc"),
                        format!(
                            "no disc {} (the scene has {n}; ids count from 0 in creation order)",
                            l.disc
                        ),
                    ));
                }
                Ok(crate::pipeline::ExternalLoad {
                    id: l.disc,
                    force: [
                        self.ck.finite(&f("force[0]"), l.force[0])?,
                        self.ck.finite(&f("force[1]"), l.force[1])?,
                    ],
                    torque: self.ck.finite(&f("torque"), l.torque)?,
                })
            })
            .collect()
    }
}

/// The rigid clumps and explicit bonds of specimen file `spec` (read from `file`), whose `n`
/// discs were loaded as scene discs `base..base + n`: indices checked and shifted, bond groups
/// resolved by `group(field, name)`, contact offsets converted with `u` (m per file unit).
/// Used by the scene loader.
#[allow(clippy::type_complexity)]
fn resolve_links(
    file: &str,
    spec: &SpecimenFile,
    base: usize,
    n: usize,
    u: f64,
    group: impl Fn(&str, &str) -> Result<usize, SceneError>,
) -> Result<(Vec<Vec<usize>>, Vec<ExplicitBond>), SceneError> {
    let err = |field: String, reason: String| SceneError::Field {
        file: file.to_string(),
        field,
        reason,
    };
    let index = |field: String, i: u32| -> Result<usize, SceneError> {
        if (i as usize) < n {
            Ok(base + i as usize)
        } else {
            Err(err(
                field,
                format!("disc {i} does not exist (the specimen has {n})"),
            ))
        }
    };
    let mut in_clump = vec![false; n];
    let mut clumps = Vec::with_capacity(spec.rigid_clumps.len());
    for (k, members) in spec.rigid_clumps.iter().enumerate() {
        if members.is_empty() {
            return Err(err(format!("rigid_clumps[{k}]"), "has no members".into()));
        }
        let mut m = Vec::with_capacity(members.len());
        for (q, &i) in members.iter().enumerate() {
            let d = index(format!("rigid_clumps[{k}][{q}]"), i)?;
            if std::mem::replace(&mut in_clump[d - base], true) {
                return Err(err(
                    format!("rigid_clumps[{k}][{q}]"),
                    format!("disc {i} is already in a rigid clump"),
                ));
            }
            m.push(d);
        }
        clumps.push(m);
    }
    let mut bonds = Vec::new();
    for (k, list) in spec.bonds.iter().enumerate() {
        let g = group(&format!("bonds[{k}].bond_group"), &list.bond_group)?;
        if let Some(o) = &list.contact_offsets {
            if o.len() != list.pairs.len() {
                return Err(err(
                    format!("bonds[{k}].contact_offsets"),
                    format!("needs {} entries, one per pair", list.pairs.len()),
                ));
            }
        }
        for (q, &[a, b]) in list.pairs.iter().enumerate() {
            let a = index(format!("bonds[{k}].pairs[{q}][0]"), a)?;
            let b = index(format!("bonds[{k}].pairs[{q}][1]"), b)?;
            if a == b {
                return Err(err(
                    format!("bonds[{k}].pairs[{q}]"),
                    "a disc cannot be bonded to itself".into(),
                ));
            }
            let g0 = match &list.contact_offsets {
                Some(o) if o[q].is_finite() => o[q] * u,
                Some(_) => {
                    return Err(err(
                        format!("bonds[{k}].contact_offsets[{q}]"),
                        "must be a finite number".into(),
                    ))
                }
                None => 0.0,
            };
            bonds.push(ExplicitBond {
                a,
                b,
                group: g,
                contact_offset: g0.min(0.0),
            });
        }
    }
    Ok((clumps, bonds))
}
