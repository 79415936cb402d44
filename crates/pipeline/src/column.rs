//! The vocabulary of the campaign tables' columns: a column's logical
//! type and the group it stands in. Both the summary keys
//! (`summary.rs`: which column each key makes) and the
//! table definitions ([`crate::schema`], which build the tables from the
//! keys) use it, so it has a home of its own below both.

/// A column's logical type (the Arrow type the tables crate maps it to).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColumnType {
    /// UTF-8 text.
    Utf8,
    /// True or false.
    Bool,
    /// 16-bit signed integer.
    Int16,
    /// 32-bit signed integer.
    Int32,
    /// 64-bit signed integer.
    Int64,
    /// 64-bit float.
    Float64,
    /// A list of 64-bit floats (the burn levels asked for and their
    /// angles: as many as `--burn-points` gives).
    Float64List,
}

impl ColumnType {
    /// The name INTERFACE.md gives it (`utf8`, `float64`, …).
    pub fn name(self) -> &'static str {
        match self {
            ColumnType::Utf8 => "utf8",
            ColumnType::Bool => "bool",
            ColumnType::Int16 => "int16",
            ColumnType::Int32 => "int32",
            ColumnType::Int64 => "int64",
            ColumnType::Float64 => "float64",
            ColumnType::Float64List => "list<float64>",
        }
    }
}

/// Where a column of [`SUMMARY`](crate::schema::SUMMARY) stands: in the Parquet table the groups
/// follow in this order; in `summary.csv` the optional groups come last,
/// and only the columns some row has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Group {
    /// The row's own columns (`file`, `error`; every column of `cycles/3`
    /// and `traces/1`).
    Row,
    /// What the figures came from (`engine`, `diagram_blake3`): Parquet
    /// only (`summary.json` keeps them in `inputs`).
    Provenance,
    /// The fixed keys of `summary.json` (numbers).
    Fixed,
    /// The optional keys (present when they apply).
    Optional,
    /// `pegging.*` (optional).
    Pegging,
    /// `models.*` text.
    ModelsText,
    /// `models.*` numbers.
    ModelsNumber,
    /// `notes`, joined with ` | `.
    Notes,
    /// The combustion keys and their `models.*` (optional; appended in
    /// `summary/2`).
    Combustion,
    /// Appended in `summary/3`: the mean trace's peak pressure and its
    /// angle (optional), and the burn levels asked for and their angles as
    /// lists (Parquet only: `summary.csv` has a `caK_deg` column a level).
    Appended3,
    /// Appended in `summary/4`: the brake figures (`[friction]`) and the
    /// design model's `design.*` (optional).
    Appended4,
}

impl Group {
    /// True for the optional keys (absent when they do not apply).
    pub fn optional(self) -> bool {
        matches!(
            self,
            Group::Optional
                | Group::Pegging
                | Group::Combustion
                | Group::Appended3
                | Group::Appended4
        )
    }

    /// True for the columns of `summary.csv` (all but the provenance).
    pub fn in_csv(self) -> bool {
        self != Group::Provenance
    }
}
