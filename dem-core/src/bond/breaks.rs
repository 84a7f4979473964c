//! The crack record: every bond break with its time, position (the bond centre, i.e. the
//! contact point), bond group, mode and the two discs (by stable [`crate::Discs::id`]).

use super::criteria::BreakMode;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

/// One bond break.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BreakEvent {
    /// Simulation time of the step in which the bond broke (s).
    pub time: f64,
    pub step: u64,
    /// Bond centre (contact point) at the break (m).
    pub x: f64,
    pub y: f64,
    /// Bond group index (see [`super::Bonds::groups`]).
    pub group: u16,
    pub mode: BreakMode,
    /// Stable disc ids of the two bonded discs.
    pub id_i: u32,
    pub id_j: u32,
    /// Stable bond id.
    pub bond: u32,
    /// Strain energy the bond held when it broke (J).
    pub energy: f64,
}

/// All breaks in the order they happened (within a step: bond store order).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BreakLog {
    pub events: Vec<BreakEvent>,
}

impl BreakLog {
    pub fn len(&self) -> usize {
        self.events.len()
    }

    pub fn is_empty(&self) -> bool {
        self.events.is_empty()
    }

    pub fn push(&mut self, e: BreakEvent) {
        self.events.push(e);
    }

    /// The log as CSV: `time,step,x,y,group,mode,id_i,id_j,bond,energy` with group names taken
    /// from `group_names` (floats in Rust's shortest round-trip form).
    pub fn to_csv(&self, group_names: &[String]) -> String {
        let mut s = String::from("time,step,x,y,group,mode,id_i,id_j,bond,energy\n");
        for e in &self.events {
            let name = group_names
                .get(e.group as usize)
                .map(String::as_str)
                .unwrap_or("?");
            let _ = writeln!(
                s,
                "{:e},{},{:e},{:e},{},{},{},{},{},{:e}",
                e.time,
                e.step,
                e.x,
                e.y,
                csv_field(name),
                e.mode.name(),
                e.id_i,
                e.id_j,
                e.bond,
                e.energy
            );
        }
        s
    }

    /// Write the CSV atomically (temporary file in the same folder, then rename).
    pub fn write_csv(&self, path: &Path, group_names: &[String]) -> std::io::Result<()> {
        clumpgen::io::write_atomic(path, self.to_csv(group_names).as_bytes())
    }
}

/// Quote a CSV field when it holds a comma, quote or newline.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trips_values_and_quotes_names() {
        let mut log = BreakLog::default();
        log.push(BreakEvent {
            time: 1.25e-3,
            step: 7,
            x: 0.1,
            y: -2.5e-6,
            group: 1,
            mode: BreakMode::Shear,
            id_i: 3,
            id_j: 9,
            bond: 4,
            energy: 1.0 / 3.0,
        });
        let names = vec!["intra".to_string(), "grain, boundary".to_string()];
        let csv = log.to_csv(&names);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 2);
        assert!(lines[1].contains("\"grain, boundary\",shear,3,9,4,"));
        let first: f64 = lines[1].split(',').next().unwrap().parse().unwrap();
        assert_eq!(first, 1.25e-3);
        let last: f64 = lines[1].rsplit(',').next().unwrap().parse().unwrap();
        assert_eq!(last, 1.0 / 3.0);

        let dir = std::env::temp_dir().join(format!("dem-breaks-{}", std::process::id()));
        let p = dir.join("breaks.csv");
        log.write_csv(&p, &names).unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), csv);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
