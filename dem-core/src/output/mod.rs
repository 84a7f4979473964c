//! Run outputs: history CSV ([`history`]), VTK PolyData snapshots and their ParaView collection
//! ([`vtk`]), the run summary ([`summary`]) and the bond break log (`breaks`).
//!
//! Every file is written atomically (temporary file in the same folder, then rename), so a
//! reader or a crashed run never sees half a file, and every writer refuses non-finite numbers:
//! the blow-up guard stops a run before its outputs, so a NaN reaching a writer is a bug, and it
//! is reported instead of written.

pub mod driver;
pub mod history;
mod run_controls;
pub mod summary;
pub mod vtk;

use std::path::Path;

/// Errors writing outputs.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{file}: cannot write: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}: {what} is not finite ({value}); not written")]
    NonFinite {
        file: String,
        what: String,
        value: f64,
    },
    #[error("{file}: this input is the run's own output `{name}` in {out}: the run would overwrite it; copy it elsewhere or give another --out")]
    InputIsOutput {
        file: String,
        name: String,
        out: String,
    },
}

/// Writes `bytes` atomically to `path` (parent folders created).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    clumpgen::io::write_atomic(path, bytes).map_err(|source| OutputError::Io {
        file: path.display().to_string(),
        source,
    })
}

/// Appends `v` in its shortest round-trip form (plain decimals for moderate magnitudes,
/// exponent notation otherwise), so text outputs read back bit-identical.
pub(crate) fn push_num(out: &mut String, v: f64) {
    use std::fmt::Write;
    let a = v.abs();
    if v == 0.0 {
        out.push('0');
    } else if (1e-4..1e15).contains(&a) {
        let _ = write!(out, "{v}");
    } else {
        let _ = write!(out, "{v:e}");
    }
}

/// Fails on a non-finite value, naming the file and the quantity.
pub(crate) fn finite(
    file: &Path,
    what: impl FnOnce() -> String,
    v: f64,
) -> Result<f64, OutputError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(OutputError::NonFinite {
            file: file.display().to_string(),
            what: what(),
            value: v,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::push_num;

    #[test]
    fn numbers_round_trip() {
        for v in [
            0.0,
            1.0,
            -2.5,
            1e-7,
            3.3e-300,
            1.2345678901234567e20,
            0.1 + 0.2,
            -1e-4,
        ] {
            let mut s = String::new();
            push_num(&mut s, v);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{s}");
        }
        let mut s = String::new();
        push_num(&mut s, 1e-30);
        assert_eq!(s, "1e-30");
    }
}
