//! Scene files (`dem.scene/1`, documented field by field in `docs/scene-schema.md`): parsing
//! with exact error locations ([`mod@resolve`]), the checked SI model ([`model`]), and the
//! construction of a `World` from it.

pub(crate) mod bondspec;
pub mod build;
pub(crate) mod check;
mod controls;
mod mix;
pub mod model;
pub mod resolve;
pub mod schema;

pub use build::build;
pub use model::Scene;
pub use resolve::{load, parse, resolve};

/// One bond group of a scene file, `bond_groups[index]` of `file`, checked and resolved as the
/// loader does (defaults, ranges; errors name the file and field): for tools that read a
/// scene's bond models without loading the whole scene.
pub fn bond_group(
    file: &str,
    index: usize,
    spec: &schema::BondGroupSpec,
) -> Result<crate::bond::BondGroup, SceneError> {
    bondspec::bond_group(
        &check::Ck {
            file: file.to_string(),
        },
        index,
        spec,
    )
}

/// Errors loading a scene; each names the file and the field (JSON path) at fault.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{file}: cannot read: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}: at {path}: {reason}")]
    Json {
        file: String,
        path: String,
        reason: String,
    },
    #[error("{file}: field {field}: {reason}")]
    Field {
        file: String,
        field: String,
        reason: String,
    },
    #[error("{file}: cannot build {what}: {reason}")]
    Build {
        file: String,
        what: String,
        reason: String,
    },
}
