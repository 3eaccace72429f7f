//! Errors that point into a source file (FLL engines, Rhai scripts, maps): every bad input
//! names its file, 1-based line and column, and what is wrong (DESIGN.md §7).

use std::fmt;

/// An error located in a source text.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct SourceError {
    /// File name as given by the user (or a label such as `<fll>` for in-memory text).
    pub file: String,
    /// 1-based line (0 when the error concerns the whole file).
    pub line: usize,
    /// 1-based column (0 when unknown).
    pub col: usize,
    /// What is wrong.
    pub message: String,
}

impl SourceError {
    /// A located error.
    pub fn new(file: &str, line: usize, col: usize, message: impl Into<String>) -> Self {
        SourceError { file: file.to_string(), line, col, message: message.into() }
    }
}

impl fmt::Display for SourceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.col) {
            (0, _) => write!(f, "{}: {}", self.file, self.message),
            (l, 0) => write!(f, "{}:{l}: {}", self.file, self.message),
            (l, c) => write!(f, "{}:{l}:{c}: {}", self.file, self.message),
        }
    }
}
