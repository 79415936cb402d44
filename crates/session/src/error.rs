//! Errors that carry their class: what the user must fix, and where.
//!
//! Every library error converts into [`Error`] with its [`Class`] (the
//! `From` impls below), so that `?` picks the class; [`Error::in_file`]
//! adds the file. The CLI maps the class to its exit code
//! ([`Class::exit_code`]); the Python package maps it to its exception
//! type (`DiagramError`, `EngineFileError`, `UsageError`, `OSError`).

/// What kind of failure: who has to change what.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// A diagram or torque file that cannot be used (exit 1).
    Diagram,
    /// A bad engine file (exit 2).
    EngineFile,
    /// A bad option or command line, or an output folder in the way (exit 2).
    Usage,
    /// A file that cannot be opened, read or written (exit 1).
    Io,
}

impl Class {
    /// The exit code of the command line (INTERFACE.md, "Exit codes"):
    /// 1 for the data (or a file that cannot be read or written), 2 for the
    /// command line or the engine file.
    pub fn exit_code(self) -> u8 {
        match self {
            Class::Diagram | Class::Io => 1,
            Class::EngineFile | Class::Usage => 2,
        }
    }
}

/// An error on its way to the user: the message, the file it is about,
/// and where in it when known.
#[derive(Debug, Clone)]
pub struct Error {
    /// What kind of failure.
    pub class: Class,
    /// What went wrong, with line and key.
    pub message: String,
    /// The file it is about, shown before the message.
    pub file: Option<String>,
    /// The 1-based line in a diagram, when one is at fault.
    pub line: Option<usize>,
    /// The 1-based column in a diagram, when one cell is at fault.
    pub column: Option<usize>,
    /// The engine-file key at fault, when one is.
    pub key: Option<String>,
    /// What the system said, for a file that cannot be opened or read (a
    /// front end maps `NotFound` to its own "no such file").
    pub io_kind: Option<std::io::ErrorKind>,
}

impl Error {
    fn new(class: Class, message: impl Into<String>) -> Self {
        Self {
            class,
            message: message.into(),
            file: None,
            line: None,
            column: None,
            key: None,
            io_kind: None,
        }
    }
    /// A bad command line or option (exit 2).
    pub fn usage(message: impl Into<String>) -> Self {
        Self::new(Class::Usage, message)
    }
    /// A bad engine file (exit 2).
    pub fn engine(message: impl Into<String>) -> Self {
        Self::new(Class::EngineFile, message)
    }
    /// A bad diagram or torque file (exit 1).
    pub fn data(message: impl Into<String>) -> Self {
        Self::new(Class::Diagram, message)
    }
    /// A file that cannot be opened, read or written (exit 1).
    pub fn io(message: impl Into<String>) -> Self {
        Self::new(Class::Io, message)
    }
    /// A file that cannot be opened or read, with what the system said.
    pub fn io_from(message: impl Into<String>, e: &std::io::Error) -> Self {
        Self {
            io_kind: Some(e.kind()),
            ..Self::io(message)
        }
    }
    /// Whether the work was stopped by its cancel token
    /// ([`enginedyn_ingest::Cancel`]), not failed.
    pub fn is_cancelled(&self) -> bool {
        self.class == Class::Io && self.message.ends_with(enginedyn_ingest::CANCELLED)
    }
    /// The same failure, about `file` (kept when it already names one).
    pub fn in_file(mut self, file: impl std::fmt::Display) -> Self {
        self.file.get_or_insert_with(|| file.to_string());
        self
    }
    /// The exit code of the command line for this failure.
    pub fn exit_code(&self) -> u8 {
        self.class.exit_code()
    }
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.file {
            Some(file) => write!(f, "{file}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for Error {}

/// A diagram or torque file that cannot be read: its line and column kept.
impl From<enginedyn_ingest::IngestError> for Error {
    fn from(e: enginedyn_ingest::IngestError) -> Self {
        use enginedyn_ingest::IngestError as I;
        let (line, column) = match &e {
            I::At { line, column, .. } => (Some(*line), *column),
            _ => (None, None),
        };
        let class = match &e {
            I::Io(_) => Class::Io,
            _ => Class::Diagram,
        };
        let io_kind = match &e {
            I::Io(io) => Some(io.kind()),
            _ => None,
        };
        Error {
            line,
            column,
            io_kind,
            ..Self::new(class, e.to_string())
        }
    }
}

/// A bad engine file: its key kept.
impl From<enginedyn_engine::EngineError> for Error {
    fn from(e: enginedyn_engine::EngineError) -> Self {
        Error {
            key: e.key().map(str::to_string),
            ..Self::engine(e.to_string())
        }
    }
}

/// The engine and the method options disagree (a model the mechanism does
/// not have, a grid the data does not fit): a usage error.
impl From<enginedyn_pipeline::PipelineError> for Error {
    fn from(e: enginedyn_pipeline::PipelineError) -> Self {
        Error::usage(e.to_string())
    }
}

/// A tolerance no setting meets is the command line's; a diagram the
/// studies cannot use is the data's.
impl From<enginedyn_accuracy::AccuracyError> for Error {
    fn from(e: enginedyn_accuracy::AccuracyError) -> Self {
        use enginedyn_accuracy::AccuracyError as A;
        match e {
            A::Unreachable { .. } | A::KeptUnreachable { .. } | A::BadTolerance(_) => {
                Error::usage(e.to_string())
            }
            other => Error::data(other.to_string()),
        }
    }
}

/// Output errors: another command holding the folder, or something not
/// enginedyn's in the way of an output, is a usage error (choose another
/// folder); a write that fails is an I/O error.
impl From<enginedyn_report::ReportError> for Error {
    fn from(e: enginedyn_report::ReportError) -> Self {
        use enginedyn_report::ReportError as R;
        match e {
            R::Locked { .. } | R::InTheWay { .. } => Error::usage(e.to_string()),
            other => Error::io(other.to_string()),
        }
    }
}

/// Result with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
