//! History CSV: one row every N steps with time, step, dt, the reaction force and moment of every
//! wall, the energy terms and balance ([`EnergyReport`]: kinetic, strain in contacts and bonds,
//! gravity potential, boundary work, damping, friction, released at breaks, total, initial,
//! relative balance error), and the broken bonds per group and mode (cumulative).
//!
//! Rows are kept as text and the file is rewritten atomically at each flush (checkpoints, the end
//! of the run, and at most every few seconds), so it is always complete and a restart continues
//! it exactly (the rows travel in the checkpoint).
//!
//! On request ([`History::keep_record`]) the same numbers are also kept as a typed [`Record`],
//! series by wall, gauge, energy term and bond group: what the lab tests analyse, in memory,
//! instead of reading the file back by column name. A restart rebuilds it from the
//! checkpoint's rows. A plain run keeps only the text.

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

/// A history's numbers in memory, column by column, named by what they measure: the walls',
/// gauges' and bond groups' series under the scene's names, the energy terms by field. The
/// values are those the file reads back (shortest round-trip text; a zero is written `0`, so a
/// −0 is kept as +0).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Record {
    pub time: Vec<f64>,
    pub step: Vec<u64>,
    pub dt: Vec<f64>,
    /// One per wall, in scene order.
    pub walls: Vec<WallSeries>,
    /// One per position gauge, in scene order.
    pub gauges: Vec<GaugeSeries>,
    pub energy: EnergySeries,
    /// One per bond group, in scene order.
    pub groups: Vec<GroupSeries>,
}

/// A wall's reaction: the force of the discs on it (N) and its moment about its pivot (N·m).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WallSeries {
    pub name: String,
    pub fx: Vec<f64>,
    pub fy: Vec<f64>,
    pub moment: Vec<f64>,
}

/// A position gauge: the mean position of its discs (m).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GaugeSeries {
    pub name: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

/// The energy terms of [`EnergyReport`] (J), one series each, in the file's column order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EnergySeries {
    pub kinetic_translation: Vec<f64>,
    pub kinetic_rotation: Vec<f64>,
    pub strain_contact: Vec<f64>,
    pub strain_bond: Vec<f64>,
    pub gravity_potential: Vec<f64>,
    pub boundary_work: Vec<f64>,
    pub damping: Vec<f64>,
    pub friction: Vec<f64>,
    pub bond_break: Vec<f64>,
    pub total: Vec<f64>,
    pub initial: Vec<f64>,
    pub balance_error: Vec<f64>,
}

impl EnergySeries {
    /// The series in [`ENERGY_COLUMNS`] order.
    fn columns_mut(&mut self) -> [&mut Vec<f64>; 12] {
        [
            &mut self.kinetic_translation,
            &mut self.kinetic_rotation,
            &mut self.strain_contact,
            &mut self.strain_bond,
            &mut self.gravity_potential,
            &mut self.boundary_work,
            &mut self.damping,
            &mut self.friction,
            &mut self.bond_break,
            &mut self.total,
            &mut self.initial,
            &mut self.balance_error,
        ]
    }
}

/// A bond group's broken bonds so far by mode, and for a flat-joint group its broken elements.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GroupSeries {
    pub name: String,
    pub tension: Vec<u64>,
    pub shear: Vec<u64>,
    /// Flat-joint groups only.
    pub elements: Option<Vec<u64>>,
}

impl Record {
    /// Rows recorded.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// The wall named `name`.
    pub fn wall(&self, name: &str) -> Option<&WallSeries> {
        self.walls.iter().find(|w| w.name == name)
    }

    /// The gauge named `name`.
    pub fn gauge(&self, name: &str) -> Option<&GaugeSeries> {
        self.gauges.iter().find(|g| g.name == name)
    }

    /// The bond group named `name`.
    pub fn group(&self, name: &str) -> Option<&GroupSeries> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// Bonds (both modes) and flat-joint elements broken by the last row, summed over the
    /// groups; 0 without rows.
    pub fn broken_at_end(&self) -> u64 {
        let last = |v: &Vec<u64>| v.last().copied().unwrap_or(0);
        (self.groups.iter())
            .map(|g| last(&g.tension) + last(&g.shear) + g.elements.as_ref().map_or(0, last))
            .sum()
    }

    /// The same series, with no rows.
    fn names_only(&self) -> Record {
        let mut r = Record::named(
            self.walls.iter().map(|w| w.name.as_str()),
            self.gauges.iter().map(|g| g.name.as_str()),
            self.groups.iter().map(|g| g.name.as_str()),
        );
        for (g, o) in r.groups.iter_mut().zip(&self.groups) {
            g.elements = o.elements.as_ref().map(|_| Vec::new());
        }
        r
    }

    /// Series of these names, with no rows (no flat-joint element series).
    fn named<'a>(
        walls: impl Iterator<Item = &'a str>,
        gauges: impl Iterator<Item = &'a str>,
        groups: impl Iterator<Item = &'a str>,
    ) -> Record {
        Record {
            walls: (walls.map(String::from))
                .map(|name| WallSeries {
                    name,
                    ..WallSeries::default()
                })
                .collect(),
            gauges: (gauges.map(String::from))
                .map(|name| GaugeSeries {
                    name,
                    ..GaugeSeries::default()
                })
                .collect(),
            groups: (groups.map(String::from))
                .map(|name| GroupSeries {
                    name,
                    ..GroupSeries::default()
                })
                .collect(),
            ..Record::default()
        }
    }

    /// Flat-joint groups (those with an element series).
    fn element_groups(&self) -> usize {
        self.groups.iter().filter(|g| g.elements.is_some()).count()
    }

    /// Appends one row's values; zeros as the file writes them.
    fn push(&mut self, r: &Row) {
        let z = |v: f64| if v == 0.0 { 0.0 } else { v };
        self.time.push(z(r.time));
        self.step.push(r.step);
        self.dt.push(z(r.dt));
        for (s, w) in self.walls.iter_mut().zip(r.walls) {
            s.fx.push(z(w.force[0]));
            s.fy.push(z(w.force[1]));
            s.moment.push(z(w.moment));
        }
        for (s, g) in self.gauges.iter_mut().zip(r.gauges) {
            s.x.push(z(g[0]));
            s.y.push(z(g[1]));
        }
        for (s, v) in self
            .energy
            .columns_mut()
            .into_iter()
            .zip(energy_values(r.energy))
        {
            s.push(z(v));
        }
        for (s, b) in self.groups.iter_mut().zip(r.broken) {
            s.tension.push(b[0]);
            s.shear.push(b[1]);
        }
        let mut el = r.elements.iter();
        for s in self.groups.iter_mut() {
            if let Some(v) = s.elements.as_mut() {
                v.push(el.next().copied().unwrap_or(0));
            }
        }
    }

    /// Appends the rows of history text (as [`History::rows`] holds them); errors give the
    /// 1-based row and the reason.
    fn parse_rows(&mut self, text: &str) -> Result<(), (usize, String)> {
        let width = 3 + 3 * self.walls.len() + 2 * self.gauges.len() + 12;
        let width = width + 2 * self.groups.len() + self.element_groups();
        for (i, line) in text.lines().enumerate() {
            let v: Vec<&str> = line.split(',').collect();
            if v.len() != width {
                return Err((i + 1, format!("{} values for {width} columns", v.len())));
            }
            let f = |k: usize| -> Result<f64, (usize, String)> {
                v[k].parse::<f64>()
                    .map_err(|e| (i + 1, format!("column {}: `{}`: {e}", k + 1, v[k])))
            };
            let u = |k: usize| -> Result<u64, (usize, String)> {
                v[k].parse::<u64>()
                    .map_err(|e| (i + 1, format!("column {}: `{}`: {e}", k + 1, v[k])))
            };
            self.time.push(f(0)?);
            self.step.push(u(1)?);
            self.dt.push(f(2)?);
            let mut k = 3;
            for w in self.walls.iter_mut() {
                w.fx.push(f(k)?);
                w.fy.push(f(k + 1)?);
                w.moment.push(f(k + 2)?);
                k += 3;
            }
            for g in self.gauges.iter_mut() {
                g.x.push(f(k)?);
                g.y.push(f(k + 1)?);
                k += 2;
            }
            for s in self.energy.columns_mut() {
                s.push(f(k)?);
                k += 1;
            }
            for g in self.groups.iter_mut() {
                g.tension.push(u(k)?);
                g.shear.push(u(k + 1)?);
                k += 2;
            }
            for g in self.groups.iter_mut() {
                if let Some(e) = g.elements.as_mut() {
                    e.push(u(k)?);
                    k += 1;
                }
            }
        }
        Ok(())
    }
}

/// One history row's values, as the driver reads them off the world.
#[derive(Debug, Clone, Copy)]
pub struct Row<'a> {
    pub time: f64,
    pub step: u64,
    pub dt: f64,
    /// Every wall, in scene order.
    pub walls: &'a [Wall],
    /// The mean position of each gauge's discs, in the order given to
    /// [`History::with_gauges`].
    pub gauges: &'a [[f64; 2]],
    pub energy: &'a EnergyReport,
    /// Broken bonds so far per group, `[tension, shear]`.
    pub broken: &'a [[u64; 2]],
    /// Broken flat-joint elements so far per flat-joint group.
    pub elements: &'a [u64],
}

/// The history file of a run.
#[derive(Debug, Clone)]
pub struct History {
    path: PathBuf,
    header: String,
    rows: String,
    /// The same rows as numbers, when kept ([`History::keep_record`]); else the series'
    /// names only (the columns: walls, gauges, bond groups, and the flat-joint groups'
    /// element series, present exactly where the file has a `broken_<group>_elements`
    /// column).
    record: Record,
    keep: bool,
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
        let record = Record::named(
            walls.iter().copied(),
            gauges.iter().copied(),
            bond_groups.iter().copied(),
        );
        History {
            path: path.to_path_buf(),
            header: h,
            rows: String::new(),
            record,
            keep: false,
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
        for g in self.record.groups.iter_mut() {
            if flat_joint_groups.contains(&g.name.as_str()) {
                g.elements = Some(Vec::new());
            }
        }
        self
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends a row (not yet written); refuses non-finite values.
    pub fn push(&mut self, r: &Row) -> Result<(), OutputError> {
        let Row {
            time,
            step,
            dt,
            walls,
            gauges,
            energy: e,
            broken,
            elements,
        } = *r;
        let names = &self.record;
        debug_assert_eq!(walls.len(), names.walls.len());
        debug_assert_eq!(gauges.len(), names.gauges.len());
        debug_assert_eq!(broken.len(), names.groups.len());
        debug_assert_eq!(elements.len(), names.element_groups());
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
        if self.keep {
            self.record.push(r);
        }
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

    /// Continues from rows saved in a checkpoint. Returns them as numbers (kept too when the
    /// record is); errors give the 1-based row and the reason (rows of another layout).
    pub fn set_rows(&mut self, rows: String) -> Result<Record, (usize, String)> {
        let mut record = self.record.names_only();
        record.parse_rows(&rows)?;
        if self.keep {
            self.record = record.clone();
        }
        self.rows = rows;
        Ok(record)
    }

    /// Keeps the rows as numbers from now on (and those so far, read from their text): for
    /// callers that analyse the run in memory (the lab tests). Off by default, so a plain run
    /// holds its history once, as text.
    pub fn keep_record(&mut self) -> Result<(), (usize, String)> {
        if !self.keep {
            let mut record = self.record.names_only();
            record.parse_rows(&self.rows)?;
            (self.record, self.keep) = (record, true);
        }
        Ok(())
    }

    /// The record, if kept, handed over (keeping stops: the history goes on as text only).
    pub fn take_record(&mut self) -> Option<Record> {
        let names = self.record.names_only();
        std::mem::take(&mut self.keep).then(|| std::mem::replace(&mut self.record, names))
    }

    /// The rows so far as numbers, if kept ([`History::keep_record`]).
    pub fn record(&self) -> Option<&Record> {
        self.keep.then_some(&self.record)
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
        h.push(&Row {
            time: 0.001,
            step: 10,
            dt: 1e-4,
            walls: &w,
            gauges: &[],
            energy: &e,
            broken: &[[3, 1]],
            elements: &[],
        })
        .unwrap();
        w[1].moment = f64::NAN;
        let err = h
            .push(&Row {
                time: 0.002,
                step: 20,
                dt: 1e-4,
                walls: &w,
                gauges: &[],
                energy: &e,
                broken: &[[3, 1]],
                elements: &[],
            })
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
        h.push(&Row {
            time: 0.001,
            step: 10,
            dt: 1e-4,
            walls: &w,
            gauges: &[],
            energy: &e,
            broken: &[[3, 1], [0, 0]],
            elements: &[7],
        })
        .unwrap_or_else(|e| panic!("{e}"));
        let row = h.rows().to_string();
        assert!(h
            .header()
            .ends_with("broken_fj_tension,broken_fj_shear,broken_fj_elements\n"));
        assert!(row.ends_with(",3,1,0,0,7\n"), "{row}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The in-memory record holds what the file reads back (−0 written `0` is +0), and a
    /// restart rebuilds the same record from the checkpoint's rows; rows of another layout are
    /// refused with their row number.
    #[test]
    fn the_record_is_what_the_file_reads_back() {
        let path = std::env::temp_dir().join("dem-history-record-unused.csv");
        let new = || {
            History::with_gauges(&path, &["top", "tool"], &["mid"], &["gb", "fj"])
                .with_element_columns(&["fj"])
        };
        let mut h = new();
        assert!(h.record().is_none(), "not kept unless asked");
        h.keep_record().unwrap();
        let mut w = vec![
            Wall::new("top", [0.0, 0.0], [1.0, 0.0], 0),
            Wall::new("tool", [0.0, 0.0], [0.0, 1.0], 0),
        ];
        let mut e = EnergyReport::default();
        for k in 0..3u32 {
            let k = f64::from(k);
            w[0].force = [-0.0, 0.1 * k + 1e-17];
            w[1].force = [3.0e20 * k, -k / 3.0];
            w[1].moment = -0.0;
            e.balance_error = 1e-7 * k;
            e.kinetic_translation = std::f64::consts::PI * k;
            let gauges = [[1.0 / 3.0, -2.5e-5 * k]];
            let broken = [[k as u64, 1], [0, 2]];
            h.push(&Row {
                time: 1e-6 * k,
                step: 10 * k as u64,
                dt: 1e-9,
                walls: &w,
                gauges: &gauges,
                energy: &e,
                broken: &broken,
                elements: &[5 + k as u64],
            })
            .unwrap();
        }
        let r = h.record().unwrap();
        assert_eq!(r.len(), 3);
        assert_eq!(r.wall("tool").unwrap().fx[2], 6.0e20);
        assert_eq!(r.wall("tool").unwrap().fy[1], -1.0 / 3.0);
        assert!(r.wall("top").unwrap().fx[0].is_sign_positive());
        assert_eq!(r.gauge("mid").unwrap().y[2], -5e-5);
        assert_eq!(r.energy.balance_error[2], 2e-7);
        assert_eq!(r.group("gb").unwrap().tension, vec![0, 1, 2]);
        assert_eq!(r.group("fj").unwrap().elements, Some(vec![5, 6, 7]));
        assert_eq!(r.group("gb").unwrap().elements, None);
        assert_eq!(r.broken_at_end(), 2 + 1 + 2 + 7);
        assert!(r.wall("nope").is_none() && r.gauge("top").is_none());

        // Every number of the text parses to the record's value, bit for bit.
        let text = h.rows().to_string();
        let values: Vec<f64> = text
            .lines()
            .flat_map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()))
            .collect();
        assert_eq!(values.len(), 3 * (3 + 6 + 2 + 12 + 4 + 1));
        assert_eq!(values[4], r.walls[0].fy[0]);
        assert_eq!(values[10].to_bits(), r.gauges[0].y[0].to_bits());

        // A restart: the rows come back as the same numbers, kept when asked (before or
        // after the rows are set).
        let mut again = new();
        assert_eq!(&again.set_rows(text.clone()).unwrap(), r);
        assert!(again.record().is_none());
        again.keep_record().unwrap();
        assert_eq!(again.record(), Some(r));
        assert_eq!(again.rows(), text);
        let mut kept = new();
        kept.keep_record().unwrap();
        kept.set_rows(text.clone()).unwrap();
        assert_eq!(kept.record(), Some(r));
        let mut other = History::new(&path, &["top"], &[]);
        let err = other.set_rows(text).unwrap_err();
        assert_eq!(err.0, 1);
        assert!(err.1.contains("columns"), "{}", err.1);
    }
}
