//! What can go wrong, and where.

/// What went wrong, with the line and column where it did (1-based).
#[derive(Debug, thiserror::Error)]
pub enum IngestError {
    /// The file could not be read.
    #[error("cannot read: {0}")]
    Io(#[from] std::io::Error),
    /// A problem at a place in the file.
    #[error("line {line}{}: {message}", column.map(|c| format!(", column {c}")).unwrap_or_default())]
    At {
        /// 1-based line.
        line: usize,
        /// 1-based column, when one cell is at fault.
        column: Option<usize>,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A problem with the data as a whole.
    #[error("{0}")]
    Data(String),
}

pub(crate) fn at(line: usize, column: Option<usize>, message: impl Into<String>) -> IngestError {
    IngestError::At {
        line,
        column,
        message: message.into(),
    }
}

/// A number from a cell as a message quotes it: every digit it holds
/// (`4294967296`, `1.5`), never rounded to fewer.
pub(crate) fn shown_number(x: f64) -> String {
    enginedyn_numerics::format::csv(x)
}
