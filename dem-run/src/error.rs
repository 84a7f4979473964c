//! The run layer's error: what kind of thing went wrong, and a message that names the file,
//! line or field and the reason (the text the CLI prints after `error:`).

use std::fmt;
use std::path::Path;

/// What kind of thing went wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A study file, a sweep's `cases.jsonl` or an option the layer refuses: the message names
    /// the file and field (or the option) and why.
    Input,
    /// A file or folder that cannot be read, written or created.
    Io,
    /// A case's process could not be started or waited for.
    Process,
}

/// An error of the run layer (module docs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    kind: ErrorKind,
    message: String,
}

/// The run layer's result.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Input the layer refuses; `message` names the file and field, or the option.
    pub fn input(message: impl Into<String>) -> Self {
        Self {
            kind: ErrorKind::Input,
            message: message.into(),
        }
    }

    /// `path` could not be read, written or created.
    pub fn io(path: &Path, e: impl fmt::Display) -> Self {
        Self {
            kind: ErrorKind::Io,
            message: format!("{}: {e}", path.display()),
        }
    }

    /// A case's process could not be started or waited for.
    pub fn process(message: impl Into<String>) -> Self {
        Self {
            kind: ErrorKind::Process,
            message: message.into(),
        }
    }

    pub fn kind(&self) -> ErrorKind {
        self.kind
    }

    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// `Error::input(format!(…))`: a refused input, its message formatted in place.
macro_rules! refuse {
    ($($t:tt)*) => {
        $crate::error::Error::input(format!($($t)*))
    };
}
pub(crate) use refuse;
