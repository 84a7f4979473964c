//! Errors of bad input: each names the field and the value.

/// Input the solver refuses, naming the field (e.g. `radius`, `walls[2].normal`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SphereError {
    /// A value out of its range.
    #[error("{field}: {reason}")]
    Invalid {
        /// The field, e.g. `radius` or `pack.box_hi`.
        field: String,
        /// What is wrong, with the value.
        reason: String,
    },
    /// Random sequential insertion could not place a sphere.
    #[error(
        "{field}: could not insert sphere {index} of radius {radius} without overlap after \
         {attempts} attempts ({placed} placed): the box is too small for the spheres"
    )]
    InsertionFailed {
        field: String,
        index: usize,
        radius: f64,
        attempts: usize,
        placed: usize,
    },
}

impl SphereError {
    /// An [`SphereError::Invalid`].
    pub fn invalid(field: impl Into<String>, reason: impl Into<String>) -> SphereError {
        SphereError::Invalid {
            field: field.into(),
            reason: reason.into(),
        }
    }
}

/// `v` if finite and > 0, else an error naming `field`.
pub(crate) fn positive(field: &str, v: f64) -> Result<f64, SphereError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(SphereError::invalid(
            field,
            format!("must be a finite number > 0, got {v}"),
        ))
    }
}

/// `v` if finite, else an error naming `field`.
pub(crate) fn finite3(field: &str, v: &nalgebra::Vector3<f64>) -> Result<(), SphereError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(SphereError::invalid(
            field,
            format!("must be finite, got ({}, {}, {})", v.x, v.y, v.z),
        ))
    }
}
