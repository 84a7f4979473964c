//! Field checks shared by the scene loaders: JSON parsing with the path of the offending value,
//! and value checks that name the file and the field.

use super::SceneError;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

/// Deserialises JSON, reporting the JSON path of the first offending value.
pub(crate) fn parse_json<T: DeserializeOwned>(text: &str, file: &str) -> Result<T, SceneError> {
    let mut de = serde_json::Deserializer::from_str(text);
    let value: T = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        SceneError::Json {
            file: file.to_string(),
            path,
            reason: e.into_inner().to_string(),
        }
    })?;
    de.end().map_err(|e| SceneError::Json {
        file: file.to_string(),
        path: ".".into(),
        reason: e.to_string(),
    })?;
    Ok(value)
}

/// Field checks of one file.
pub(crate) struct Ck {
    pub file: String,
}

impl Ck {
    pub fn err(&self, field: impl Into<String>, reason: impl Into<String>) -> SceneError {
        SceneError::Field {
            file: self.file.clone(),
            field: field.into(),
            reason: reason.into(),
        }
    }

    pub fn finite(&self, field: &str, v: f64) -> Result<f64, SceneError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(field, "must be a finite number"))
        }
    }

    pub fn positive(&self, field: &str, v: f64) -> Result<f64, SceneError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be positive (got {v})")))
        }
    }

    pub fn non_negative(&self, field: &str, v: f64) -> Result<f64, SceneError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be zero or positive (got {v})")))
        }
    }

    /// `lo <= v < hi` (or `<= hi` when `closed`).
    pub fn range(
        &self,
        field: &str,
        v: f64,
        lo: f64,
        hi: f64,
        closed: bool,
    ) -> Result<f64, SceneError> {
        let ok = v.is_finite() && v >= lo && (v < hi || (closed && v == hi));
        if ok {
            Ok(v)
        } else {
            let close = if closed { "]" } else { ")" };
            Err(self.err(field, format!("must lie in [{lo}, {hi}{close} (got {v})")))
        }
    }
}

/// The folder of a file ("." for a bare name).
pub(crate) fn dir_of(p: &Path) -> PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}
