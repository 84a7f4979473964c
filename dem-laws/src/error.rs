//! The error of reading a law specification ([`crate::GranularSpec`]).

/// A law specification that cannot be read or is not physical: names the file (when known),
/// the field path (e.g. `damping.e`) and the reason.
#[derive(Debug, thiserror::Error)]
pub enum LawError {
    /// A field is missing, has the wrong type, names an unknown model, or holds a value out
    /// of its range.
    #[error("{}{path}: {reason}", file_prefix(.file))]
    Invalid {
        /// The file the specification came from.
        file: Option<String>,
        /// Dotted path of the field, e.g. `damping.e`.
        path: String,
        /// What is wrong, with the accepted range or the known names.
        reason: String,
    },
    /// The file cannot be read.
    #[error("{file}: {source}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
}

fn file_prefix(file: &Option<String>) -> String {
    file.as_ref().map(|f| format!("{f}: ")).unwrap_or_default()
}

impl LawError {
    /// An [`LawError::Invalid`] without a file.
    pub fn invalid(path: impl Into<String>, reason: impl Into<String>) -> LawError {
        LawError::Invalid {
            file: None,
            path: path.into(),
            reason: reason.into(),
        }
    }

    /// The same error, naming `file`.
    pub fn in_file(self, file: &str) -> LawError {
        match self {
            LawError::Invalid { path, reason, .. } => LawError::Invalid {
                file: Some(file.to_string()),
                path,
                reason,
            },
            e => e,
        }
    }

    /// The field path of an [`LawError::Invalid`].
    pub fn path(&self) -> Option<&str> {
        match self {
            LawError::Invalid { path, .. } => Some(path),
            LawError::Io { .. } => None,
        }
    }
}
