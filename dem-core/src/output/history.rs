//! History CSV: one row every N steps with time, step, dt, the reaction force and moment of every
//! wall, the energy terms and balance ([`EnergyReport`]: kinetic, strain in contacts and bonds,
//! gravity potential, boundary work, damping, friction, released at breaks, total, initial,
//! relative balance error), and the broken bonds per group and mode (cumulative).
//!
//! Rows are kept as text and the file is rewritten atomically at each flush (checkpoints, the end
//! of the run, and at most every few seconds), so it is always complete and a restart continues
//! it exactly (the rows travel in the checkpoint).

use super::{finite, push_num, write_atomic, OutputError};
use crate::energy::EnergyReport;
use crate::state::Wall;
use std::path::{Path, PathBuf};

const ENERGY_COLUMNS: [&str; 12] = [
    "ek_trans",
    "ek_rot",
    "e_contact",
    "e_bond",
    "e_gravity",
    "w_boundary",
    "e_damping",
    "e_friction",
    "e_released",
    "e_total",
    "e_initial",
    "balance_error",
];

/// The energy columns of a report, in [`ENERGY_COLUMNS`] order.
fn energy_values(e: &EnergyReport) -> [f64; 12] {
    [
        e.kinetic_translation,
        e.kinetic_rotation,
        e.strain_contact,
        e.strain_bond,
        e.gravity_potential,
        e.boundary_work,
        e.damping,
        e.friction,
        e.bond_break,
        e.total,
        e.initial,
        e.balance_error,
    ]
}

/// Column-name safe text: letters, digits, `_`, `-`, `.`; anything else becomes `_`.
pub fn column_name(s: &str) -> String {
    let t: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "_-.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if t.is_empty() {
        "_".into()
    } else {
        t
    }
}

/// The history file of a run.
#[derive(Debug, Clone)]
pub struct History {
    path: PathBuf,
    header: String,
    rows: String,
    walls: usize,
    gauges: usize,
    groups: usize,
    /// Flat-joint groups with a `broken_<group>_elements` column (none: the column is absent).
    element_groups: usize,
}

impl History {
    /// Columns: `time,step,dt`, `<wall>_fx,<wall>_fy,<wall>_moment` per wall, the energy terms,
    /// `broken_<group>_tension,broken_<group>_shear` per bond group.
    pub fn new(path: &Path, walls: &[&str], bond_groups: &[&str]) -> History {
        History::with_gauges(path, walls, &[], bond_groups)
    }

    /// As [`History::new`], with `<gauge>_x,<gauge>_y` per position gauge after the walls.
    pub fn with_gauges(
        path: &Path,
        walls: &[&str],
        gauges: &[&str],
        bond_groups: &[&str],
    ) -> History {
        let mut h = String::from("time,step,dt");
        for w in walls {
            let w = column_name(w);
            h.push_str(&format!(",{w}_fx,{w}_fy,{w}_moment"));
        }
        for g in gauges {
            let g = column_name(g);
            h.push_str(&format!(",{g}_x,{g}_y"));
        }
        for e in ENERGY_COLUMNS {
            h.push(',');
            h.push_str(e);
        }
        for g in bond_groups {
            let g = column_name(g);
            h.push_str(&format!(",broken_{g}_tension,broken_{g}_shear"));
        }
        h.push('\n');
        History {
            path: path.to_path_buf(),
            header: h,
            rows: String::new(),
            walls: walls.len(),
            gauges: gauges.len(),
            groups: bond_groups.len(),
            element_groups: 0,
        }
    }

    /// Adds a `broken_<group>_elements` column (flat-joint elements broken so far) per group of
    /// `flat_joint_groups`, after the broken-bond columns; their values are the `elements` of
    /// [`History::push`]. Histories without flat joints are unchanged.
    pub fn with_element_columns(mut self, flat_joint_groups: &[&str]) -> History {
        self.header.pop();
        for g in flat_joint_groups {
            let g = column_name(g);
            self.header.push_str(&format!(",broken_{g}_elements"));
        }
        self.header.push('\n');
        self.element_groups = flat_joint_groups.len();
        self
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends a row (not yet written); refuses non-finite values. `gauges`: the mean position
    /// of each gauge's discs, in the order given to [`History::with_gauges`].
    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        time: f64,
        step: u64,
        dt: f64,
        walls: &[Wall],
        gauges: &[[f64; 2]],
        e: &EnergyReport,
        broken: &[[u64; 2]],
        elements: &[u64],
    ) -> Result<(), OutputError> {
        debug_assert_eq!(walls.len(), self.walls);
        debug_assert_eq!(gauges.len(), self.gauges);
        debug_assert_eq!(broken.len(), self.groups);
        debug_assert_eq!(elements.len(), self.element_groups);
        let p = &self.path;
        let mut row = String::with_capacity(256);
        push_num(
            &mut row,
            finite(p, || format!("time at step {step}"), time)?,
        );
        row.push_str(&format!(",{step},"));
        push_num(&mut row, finite(p, || format!("dt at step {step}"), dt)?);
        for w in walls {
            for (k, v) in [("fx", w.force[0]), ("fy", w.force[1]), ("moment", w.moment)] {
                row.push(',');
                push_num(
                    &mut row,
                    finite(p, || format!("wall {} {k} at step {step}", w.name), v)?,
                );
            }
        }
        for (k, g) in gauges.iter().enumerate() {
            for (c, v) in ["x", "y"].into_iter().zip(g) {
                row.push(',');
                push_num(
                    &mut row,
                    finite(p, || format!("gauge {k} {c} at step {step}"), *v)?,
                );
            }
        }
        for (name, v) in ENERGY_COLUMNS.iter().zip(energy_values(e)) {
            row.push(',');
            push_num(&mut row, finite(p, || format!("{name} at step {step}"), v)?);
        }
        for b in broken {
            row.push_str(&format!(",{},{}", b[0], b[1]));
        }
        for e in elements {
            row.push_str(&format!(",{e}"));
        }
        row.push('\n');
        self.rows.push_str(&row);
        Ok(())
    }

    /// Rewrites the file atomically with every row so far.
    pub fn flush(&self) -> Result<(), OutputError> {
        let mut text = String::with_capacity(self.header.len() + self.rows.len());
        text.push_str(&self.header);
        text.push_str(&self.rows);
        write_atomic(&self.path, text.as_bytes())
    }

    /// The rows written so far (for checkpoints).
    pub fn rows(&self) -> &str {
        &self.rows
    }

    /// Continues from rows saved in a checkpoint.
    pub fn set_rows(&mut self, rows: String) {
        self.rows = rows;
    }

    pub fn header(&self) -> &str {
        &self.header
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_rows_and_nan_refused() {
        let dir = std::env::temp_dir().join(format!("dem-history-{}", std::process::id()));
        let path = dir.join("history.csv");
        let mut h = History::new(&path, &["floor", "left wall"], &["gb"]);
        let mut w = vec![
            Wall::new("floor", [0.0, 0.0], [1.0, 0.0], 0),
            Wall::new("left wall", [0.0, 0.0], [0.0, 1.0], 0),
        ];
        w[0].force = [0.5, -2.0];
        let e = EnergyReport {
            kinetic_translation: 1.5,
            ..EnergyReport::default()
        };
        h.push(0.001, 10, 1e-4, &w, &[], &e, &[[3, 1]], &[])
            .unwrap();
        w[1].moment = f64::NAN;
        let err = h
            .push(0.002, 20, 1e-4, &w, &[], &e, &[[3, 1]], &[])
            .unwrap_err();
        assert!(
            err.to_string().contains("left wall moment at step 20"),
            "{err}"
        );
        h.flush().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2);
        assert!(lines[0].starts_with("time,step,dt,floor_fx,floor_fy,floor_moment,left_wall_fx"));
        assert!(lines[0].ends_with("broken_gb_tension,broken_gb_shear"));
        assert_eq!(lines[0].split(',').count(), lines[1].split(',').count());
        assert!(lines[1].starts_with("0.001,10,0.0001,0.5,-2,0,0,0,0,1.5,"));
        assert!(lines[1].ends_with(",3,1"));

        // Flat-joint groups add their broken-element column after the broken bonds.
        let mut h = History::new(&path, &["floor", "left wall"], &["gb", "fj"])
            .with_element_columns(&["fj"]);
        w[1].moment = 0.0;
        h.push(0.001, 10, 1e-4, &w, &[], &e, &[[3, 1], [0, 0]], &[7])
            .unwrap_or_else(|e| panic!("{e}"));
        let row = h.rows().to_string();
        assert!(h
            .header()
            .ends_with("broken_fj_tension,broken_fj_shear,broken_fj_elements\n"));
        assert!(row.ends_with(",3,1,0,0,7\n"), "{row}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
