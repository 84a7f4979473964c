//! Reading a run's `history.csv` (written by [`dem_core::output::history`]) back as named columns,
//! for the analyses of the lab tests.

use std::path::Path;

/// A history table: column names and rows of numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub names: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

/// Errors reading a history file; each names the file and, where it applies, the line.
#[derive(Debug, thiserror::Error)]
pub enum HistoryError {
    #[error("{file}: cannot read: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}: line {line}: {reason}")]
    Parse {
        file: String,
        line: usize,
        reason: String,
    },
    #[error("{file}: no column named `{column}`")]
    NoColumn { file: String, column: String },
}

impl Table {
    /// Reads a CSV history (header line, then numbers).
    pub fn read(path: &Path) -> Result<Table, HistoryError> {
        let file = path.display().to_string();
        let text = clumpgen::io::read_input_string(path).map_err(|source| HistoryError::Io {
            file: file.clone(),
            source,
        })?;
        Table::parse(&text).map_err(|(line, reason)| HistoryError::Parse { file, line, reason })
    }

    /// Parses CSV text; errors give the 1-based line and the reason.
    pub fn parse(text: &str) -> Result<Table, (usize, String)> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let Some((_, header)) = lines.next() else {
            return Err((1, "empty file: no header".into()));
        };
        let names: Vec<String> = header.split(',').map(|s| s.trim().to_string()).collect();
        let mut rows = Vec::new();
        for (i, l) in lines {
            let row: Result<Vec<f64>, String> = l
                .split(',')
                .map(|v| v.trim().parse::<f64>().map_err(|e| format!("`{v}`: {e}")))
                .collect();
            let row = row.map_err(|r| (i + 1, r))?;
            if row.len() != names.len() {
                return Err((
                    i + 1,
                    format!("{} values for {} columns", row.len(), names.len()),
                ));
            }
            rows.push(row);
        }
        Ok(Table { names, rows })
    }

    /// Index of column `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// Column `name` as a vector; `file` names the source in the error.
    pub fn column(&self, name: &str, file: &str) -> Result<Vec<f64>, HistoryError> {
        let i = self.index(name).ok_or_else(|| HistoryError::NoColumn {
            file: file.to_string(),
            column: name.to_string(),
        })?;
        Ok(self.rows.iter().map(|r| r[i]).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_columns_and_names_bad_lines() {
        let t = Table::parse("time,step,top_fy\n0,0,0\n1e-6,10,-2.5\n").unwrap();
        assert_eq!(t.column("top_fy", "h").unwrap(), vec![0.0, -2.5]);
        assert!(matches!(
            t.column("nope", "h"),
            Err(HistoryError::NoColumn { .. })
        ));
        let e = Table::parse("a,b\n1,2\n3,x\n").unwrap_err();
        assert_eq!(e.0, 3);
        assert!(Table::parse("a,b\n1\n").is_err());
    }
}
