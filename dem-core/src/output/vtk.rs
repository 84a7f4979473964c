//! VTK XML PolyData snapshots (`.vtp`, ASCII) that ParaView opens, and the `.pvd` collection
//! that strings them into a time series.
//!
//! A disc snapshot has one point per disc (no vertex cells: show it with ParaView's "Point
//! Gaussian" representation or a Glyph filter scaled by `radius`) with point data `radius`,
//! `velocity`, `omega`, `theta`, `force`, `id` (stable disc id), `body` (rigid clump index, −1
//! for free discs), `group`, `material`; bonds are line cells between their two discs with cell
//! data `bond_state` (1 intact, 0 broken), `bond_group`, `normal_force` (N, compression
//! positive), `shear_force` (N) and `moment` (N·m). Bonds that wrap around a periodic boundary
//! are left out of the picture (the line would cross the box). Walls go to a separate PolyData of
//! line cells with their `force` and `moment`.

use super::{finite, push_num, write_atomic, OutputError};
use crate::state::{State, Wall, FREE};
use std::path::{Path, PathBuf};

/// One bond as drawn: disc indices (current order, = point indices) and its state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BondLine {
    pub i: u32,
    pub j: u32,
    pub group: u32,
    pub intact: bool,
    pub normal_force: f64,
    pub shear_force: f64,
    pub moment: f64,
}

struct Xml {
    s: String,
    path: PathBuf,
}

impl Xml {
    fn floats(
        &mut self,
        name: &str,
        comps: usize,
        vals: impl Iterator<Item = f64>,
    ) -> Result<(), OutputError> {
        self.s.push_str(&format!(
            "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"ascii\">"
        ));
        for (k, v) in vals.enumerate() {
            let v = finite(&self.path, || format!("{name}[{}]", k / comps), v)?;
            self.s.push(if k.is_multiple_of(6 * comps) {
                '\n'
            } else {
                ' '
            });
            push_num(&mut self.s, v);
        }
        self.s.push_str("\n        </DataArray>\n");
        Ok(())
    }

    fn ints<T: std::fmt::Display>(&mut self, ty: &str, name: &str, vals: impl Iterator<Item = T>) {
        use std::fmt::Write;
        self.s.push_str(&format!(
            "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">"
        ));
        for (k, v) in vals.enumerate() {
            self.s.push(if k.is_multiple_of(16) { '\n' } else { ' ' });
            let _ = write!(self.s, "{v}");
        }
        self.s.push_str("\n        </DataArray>\n");
    }
}

const HEAD: &str = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <PolyData>\n";
const TAIL: &str = "    </Piece>\n  </PolyData>\n</VTKFile>\n";

/// Writes the disc snapshot with its bonds to `path` (atomically).
pub fn write_discs(path: &Path, st: &State, bonds: &[BondLine]) -> Result<(), OutputError> {
    let d = &st.discs;
    let n = d.len();
    let wraps = |b: &BondLine| {
        (0..2).any(|axis| match st.periodic.length[axis] {
            Some(l) => {
                let (a, c) = if axis == 0 {
                    (d.x[b.i as usize], d.x[b.j as usize])
                } else {
                    (d.y[b.i as usize], d.y[b.j as usize])
                };
                (c - a).abs() > 0.5 * l
            }
            None => false,
        })
    };
    let lines: Vec<&BondLine> = bonds
        .iter()
        .filter(|b| (b.i as usize) < n && (b.j as usize) < n && !wraps(b))
        .collect();
    let mut x = Xml {
        s: String::with_capacity(200 * n + 100 * lines.len() + 1024),
        path: path.to_path_buf(),
    };
    x.s.push_str(HEAD);
    x.s.push_str(&format!(
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"0\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n",
        lines.len()
    ));
    x.s.push_str("      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n");
    x.floats("radius", 1, d.r.iter().copied())?;
    x.floats("velocity", 3, (0..n).flat_map(|i| [d.vx[i], d.vy[i], 0.0]))?;
    x.floats("omega", 1, d.omega.iter().copied())?;
    x.floats("theta", 1, d.theta.iter().copied())?;
    x.floats("force", 3, (0..n).flat_map(|i| [d.fx[i], d.fy[i], 0.0]))?;
    x.ints("UInt32", "id", d.id.iter());
    x.ints(
        "Int64",
        "body",
        d.body
            .iter()
            .map(|&b| if b == FREE { -1 } else { b as i64 }),
    );
    x.ints("UInt32", "group", d.group.iter());
    x.ints("UInt16", "material", d.material.iter());
    x.s.push_str("      </PointData>\n");
    if !lines.is_empty() {
        x.s.push_str("      <CellData Scalars=\"bond_state\">\n");
        x.ints("UInt8", "bond_state", lines.iter().map(|b| b.intact as u8));
        x.ints("UInt32", "bond_group", lines.iter().map(|b| b.group));
        x.floats("normal_force", 1, lines.iter().map(|b| b.normal_force))?;
        x.floats("shear_force", 1, lines.iter().map(|b| b.shear_force))?;
        x.floats("moment", 1, lines.iter().map(|b| b.moment))?;
        x.s.push_str("      </CellData>\n");
    }
    x.s.push_str("      <Points>\n");
    x.floats("points", 3, (0..n).flat_map(|i| [d.x[i], d.y[i], 0.0]))?;
    x.s.push_str("      </Points>\n");
    if !lines.is_empty() {
        x.s.push_str("      <Lines>\n");
        x.ints(
            "Int64",
            "connectivity",
            lines.iter().flat_map(|b| [b.i, b.j]),
        );
        x.ints("Int64", "offsets", (1..=lines.len()).map(|k| 2 * k));
        x.s.push_str("      </Lines>\n");
    }
    x.s.push_str(TAIL);
    write_atomic(path, x.s.as_bytes())
}

/// Writes the walls as line cells with their reaction `force` and `moment` (atomically).
pub fn write_walls(path: &Path, walls: &[Wall]) -> Result<(), OutputError> {
    let n = walls.len();
    let mut x = Xml {
        s: String::with_capacity(300 * n + 1024),
        path: path.to_path_buf(),
    };
    x.s.push_str(HEAD);
    let points: usize = walls.iter().map(|w| w.via.len() + 2).sum();
    x.s.push_str(&format!(
        "    <Piece NumberOfPoints=\"{points}\" NumberOfVerts=\"0\" NumberOfLines=\"{n}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
    ));
    x.s.push_str("      <CellData Vectors=\"force\">\n");
    x.floats(
        "force",
        3,
        walls.iter().flat_map(|w| [w.force[0], w.force[1], 0.0]),
    )?;
    x.floats("moment", 1, walls.iter().map(|w| w.moment))?;
    x.floats("work", 1, walls.iter().map(|w| w.work))?;
    x.floats(
        "velocity",
        3,
        walls.iter().flat_map(|w| [w.v[0], w.v[1], 0.0]),
    )?;
    x.s.push_str("      </CellData>\n      <Points>\n");
    x.floats(
        "points",
        3,
        walls
            .iter()
            .flat_map(|w| w.vertices().flat_map(|p| [p[0], p[1], 0.0])),
    )?;
    // One line cell per wall: a polyline wall is one cell through all its vertices.
    x.s.push_str("      </Points>\n      <Lines>\n");
    let ends: Vec<usize> = walls
        .iter()
        .scan(0, |end, w| {
            *end += w.via.len() + 2;
            Some(*end)
        })
        .collect();
    x.ints(
        "Int64",
        "connectivity",
        0..ends.last().copied().unwrap_or(0),
    );
    x.ints("Int64", "offsets", ends.iter().copied());
    x.s.push_str("      </Lines>\n");
    x.s.push_str(TAIL);
    write_atomic(path, x.s.as_bytes())
}

/// One dataset of a `.pvd` collection.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Entry {
    pub time: f64,
    pub step: u64,
    pub part: u32,
    /// Relative to the collection file.
    pub file: String,
}

/// A `.pvd` collection file (ParaView's time series of snapshots).
#[derive(Debug, Clone)]
pub struct Collection {
    pub path: PathBuf,
    pub entries: Vec<Entry>,
}

impl Collection {
    pub fn new(path: &Path) -> Collection {
        Collection {
            path: path.to_path_buf(),
            entries: Vec::new(),
        }
    }

    /// Rewrites the collection atomically.
    pub fn flush(&self) -> Result<(), OutputError> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for e in &self.entries {
            let mut t = String::new();
            push_num(
                &mut t,
                finite(&self.path, || format!("time of {}", e.file), e.time)?,
            );
            s.push_str(&format!(
                "    <DataSet timestep=\"{t}\" group=\"\" part=\"{}\" file=\"{}\"/>\n",
                e.part,
                xml_escape(&e.file)
            ));
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        write_atomic(&self.path, s.as_bytes())
    }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapshot_has_points_bonds_and_refuses_nan() {
        let dir = std::env::temp_dir().join(format!("dem-vtk-{}", std::process::id()));
        let mut st = State::default();
        for k in 0..3 {
            st.discs.push_uniform(k as f64, 0.0, 0.5, 1000.0, 1.0, 0);
        }
        st.discs.vx[1] = 2.0;
        let bonds = [BondLine {
            i: 0,
            j: 1,
            group: 0,
            intact: true,
            normal_force: 10.0,
            shear_force: -1.0,
            moment: 0.25,
        }];
        let p = dir.join("s.vtp");
        write_discs(&p, &st, &bonds).unwrap();
        let t = std::fs::read_to_string(&p).unwrap();
        assert!(t.contains("NumberOfPoints=\"3\"") && t.contains("NumberOfLines=\"1\""));
        assert!(
            t.contains("Name=\"connectivity\" format=\"ascii\">\n0 1\n"),
            "{t}"
        );
        assert!(t.contains(
            "Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n0 0 0 2 0 0 0 0 0\n"
        ));
        st.discs.vy[2] = f64::INFINITY;
        let e = write_discs(&p, &st, &bonds).unwrap_err().to_string();
        assert!(e.contains("velocity[2]"), "{e}");
        // The good file is left as it was.
        assert_eq!(std::fs::read_to_string(&p).unwrap(), t);
        let mut c = Collection::new(&dir.join("run.pvd"));
        c.entries.push(Entry {
            time: 0.5,
            step: 10,
            part: 0,
            file: "s.vtp".into(),
        });
        c.flush().unwrap();
        let pvd = std::fs::read_to_string(dir.join("run.pvd")).unwrap();
        assert!(pvd.contains("timestep=\"0.5\" group=\"\" part=\"0\" file=\"s.vtp\""));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bonds_across_a_periodic_boundary_are_left_out() {
        let dir = std::env::temp_dir().join(format!("dem-vtk-per-{}", std::process::id()));
        let mut st = State::default();
        st.periodic.length = [Some(10.0), None];
        for x in [0.2, 9.8, 5.0] {
            st.discs.push_uniform(x, 0.0, 0.3, 1000.0, 1.0, 0);
        }
        let bond = |i, j| BondLine {
            i,
            j,
            group: 0,
            intact: false,
            normal_force: 0.0,
            shear_force: 0.0,
            moment: 0.0,
        };
        let p = dir.join("p.vtp");
        write_discs(&p, &st, &[bond(0, 1), bond(1, 2), bond(0, 7)]).unwrap();
        let t = std::fs::read_to_string(&p).unwrap();
        // Only 1-2 is drawn (0-1 wraps, 0-7 names no disc); its state is "broken" (0).
        assert!(t.contains("NumberOfLines=\"1\""), "{t}");
        assert!(
            t.contains("Name=\"connectivity\" format=\"ascii\">\n1 2\n"),
            "{t}"
        );
        assert!(
            t.contains("Name=\"bond_state\" format=\"ascii\">\n0\n"),
            "{t}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
