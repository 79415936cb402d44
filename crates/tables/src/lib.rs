//! A campaign's fixed, typed tables as Parquet (INTERFACE.md, "Campaigns:
//! shards and Parquet" and "Parquet tables"): `summary/4`, `cycles/3` and
//! `traces/1`, built from the one definition in
//! [`enginedyn_pipeline::schema`], each part a file
//! `DIR/TABLE/part-IIIII-of-NNNNN.parquet` written whole or not at all; and
//! the merge check ([`check_campaign`]) that `enginedyn merge` and Python's
//! `check_campaign` call before writing `DIR/_manifest.json`.
//!
//! ```no_run
//! use enginedyn_pipeline::schema::SummaryRecord;
//! use enginedyn_tables::{Meta, Table, summary_parquet, write_part};
//! # fn demo(s: &enginedyn_pipeline::Summary) -> Result<(), enginedyn_tables::TablesError> {
//! let meta = Meta::new("3f…", "9a…", serde_json::json!({"step_deg": 0.1}));
//! let rows = [SummaryRecord {
//!     file: "run_2200.csv",
//!     error: None,
//!     engine: "VAZ-2108",
//!     diagram_blake3: Some("ab…"),
//!     summary: Some(s),
//! }];
//! let bytes = summary_parquet(&rows, &meta)?;
//! write_part("campaign".as_ref(), Table::Summary, 0, 1, &bytes)?;
//! let manifest = enginedyn_tables::check_campaign("campaign".as_ref(), None)?;
//! enginedyn_tables::write_manifest("campaign".as_ref(), &manifest)?;
//! # Ok(()) }
//! ```

use arrow_array::builder::{
    BooleanBuilder, Float64Builder, Int16Builder, Int32Builder, Int64Builder, ListBuilder,
    StringBuilder,
};
use arrow_array::{ArrayRef, RecordBatch};
use arrow_schema::{DataType, Field, Schema, SchemaRef};
use enginedyn_pipeline::schema::{
    self, Cell, Column, ColumnType, CycleRow, MapRecord, SummaryRecord, TracePoint,
};
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod campaign;
mod merge;
mod set;
pub use campaign::{
    CAMPAIGN_KEY, Campaign, FILES_KEY, Identity, Prepared, escape_name, list_blake3, prepare,
    short, staging_prefix, unescape_name,
};
pub use merge::{MANIFEST, Manifest, check_campaign, remove_manifest, write_manifest};
pub use set::PartSet;

/// The most parts a campaign has (`--shard I/N`: N ≤ 100,000).
pub const MAX_PARTS: usize = 100_000;

/// Why a table could not be written or a campaign not checked.
#[derive(Debug, thiserror::Error)]
pub enum TablesError {
    /// Building or writing Parquet failed.
    #[error("{table} table: {source}")]
    Parquet {
        /// The table.
        table: Table,
        /// What arrow-rs said.
        source: parquet::errors::ParquetError,
    },
    /// A value the column cannot hold (a bug, or a number out of the
    /// column's range).
    #[error("{table} table, column `{column}`, row {row}: {what}")]
    Value {
        /// The table.
        table: Table,
        /// The column.
        column: &'static str,
        /// The row (0-based, in the rows written at once).
        row: usize,
        /// What is wrong.
        what: String,
    },
    /// A part number outside `0..parts`, or a count outside
    /// `1..=MAX_PARTS`.
    #[error("part {part} of {parts}: parts are numbered 0 to N-1, N from 1 to {MAX_PARTS}")]
    PartNumber {
        /// The part.
        part: usize,
        /// The count.
        parts: usize,
    },
    /// Writing a part or the manifest failed.
    #[error(transparent)]
    Write(#[from] enginedyn_report::ReportError),
    /// Reading a campaign's folder or part failed.
    #[error("cannot read {}: {message}", path.display())]
    Read {
        /// The file or folder.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A table has no part at all.
    #[error("{}: no part of the {table} table (part-IIIII-of-NNNNN.parquet)", folder.display())]
    NoParts {
        /// The table.
        table: Table,
        /// Its folder.
        folder: PathBuf,
    },
    /// A part is missing.
    #[error("{}: missing (part {part} of {parts} of the {table} table)", path.display())]
    Missing {
        /// The table.
        table: Table,
        /// The part's path.
        path: PathBuf,
        /// Its number.
        part: usize,
        /// The count.
        parts: usize,
    },
    /// Parts of different counts (`-of-NNNNN`) side by side, or a part of
    /// another count than `--parts`.
    #[error("{}: a part of {found} parts, but {} is of {expected}: parts of two campaigns in one folder", path.display(), other.display())]
    Counts {
        /// The part whose count differs.
        path: PathBuf,
        /// Its count.
        found: usize,
        /// The count expected.
        expected: usize,
        /// What the expected count comes from (another part, or `--parts N`).
        other: PathBuf,
    },
    /// Something other than enginedyn's part at a part's path.
    #[error("{}: {what} is in the way of a part (only enginedyn's own parts are replaced): move it, or write the campaign to another folder", path.display())]
    InTheWay {
        /// Its path.
        path: PathBuf,
        /// What it is.
        what: &'static str,
    },
    /// The folder holds parts of another campaign.
    #[error("{}: holds {theirs}, not this one ({ours}): {why}; give --replace (Python: overwrite=True) to remove enginedyn's parts there first, or write to another folder", path.display())]
    OtherCampaign {
        /// A part of the other campaign.
        path: PathBuf,
        /// The other campaign.
        theirs: String,
        /// This one.
        ours: String,
        /// How they differ.
        why: String,
    },
    /// A part that is not of the campaign (its identity, its files).
    #[error("{}: {what}", path.display())]
    NotOfCampaign {
        /// The part.
        path: PathBuf,
        /// What is wrong, naming the file when it is one file.
        what: String,
    },
    /// A part's schema or metadata differs from the first part's.
    #[error("{}: {what} differs from {}'s ({detail})", path.display(), reference.display())]
    Differs {
        /// The part that differs.
        path: PathBuf,
        /// The part it is compared with.
        reference: PathBuf,
        /// What differs: "the schema", "`engine.sha256`", …
        what: String,
        /// How.
        detail: String,
    },
}

/// One of a campaign's tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Table {
    /// `summary/4`: one row per diagram file.
    Summary,
    /// `cycles/3`: one row per file × cylinder × measured cycle.
    Cycles,
    /// `traces/1`: one row per file × cylinder × grid angle (opt-in).
    Traces,
    /// `map/1`: one row per point of a speed × load map (not a campaign's).
    Map,
}

impl Table {
    /// Every table, in the order a campaign's folder lists them.
    pub const ALL: [Table; 3] = [Table::Summary, Table::Cycles, Table::Traces];

    /// Its folder in a campaign (`summary`, `cycles`, `traces`).
    pub fn folder(self) -> &'static str {
        match self {
            Table::Summary => "summary",
            Table::Cycles => "cycles",
            Table::Traces => "traces",
            Table::Map => "map",
        }
    }

    /// Its schema and version, the `enginedyn.schema` metadata.
    pub fn schema_name(self) -> &'static str {
        match self {
            Table::Summary => schema::SUMMARY_SCHEMA,
            Table::Cycles => schema::CYCLES_SCHEMA,
            Table::Traces => schema::TRACES_SCHEMA,
            Table::Map => schema::MAP_SCHEMA,
        }
    }

    /// Its columns as (name, type, nullable), in the table's order.
    pub fn columns(self) -> Vec<(&'static str, ColumnType, bool)> {
        fn of<G>(c: &Column<G>) -> (&'static str, ColumnType, bool) {
            (c.name, c.ty, c.nullable)
        }
        match self {
            Table::Summary => schema::summary_columns().into_iter().map(of).collect(),
            Table::Cycles => schema::CYCLES.iter().map(of).collect(),
            Table::Traces => schema::TRACES.iter().map(of).collect(),
            Table::Map => {
                let mut c: Vec<_> = schema::summary_columns().into_iter().map(of).collect();
                c.extend(
                    schema::MAP_COLUMNS
                        .iter()
                        .map(|&(name, nullable)| (name, ColumnType::Float64, nullable)),
                );
                c
            }
        }
    }

    /// Its Arrow schema (no metadata: that is the file's).
    pub fn arrow_schema(self) -> SchemaRef {
        let fields: Vec<Field> = self
            .columns()
            .into_iter()
            .map(|(name, ty, nullable)| Field::new(name, data_type(ty), nullable))
            .collect();
        Arc::new(Schema::new(fields))
    }
}

impl std::fmt::Display for Table {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.folder())
    }
}

/// The Arrow type of a logical type.
pub fn data_type(ty: ColumnType) -> DataType {
    match ty {
        ColumnType::Utf8 => DataType::Utf8,
        ColumnType::Bool => DataType::Boolean,
        ColumnType::Int16 => DataType::Int16,
        ColumnType::Int32 => DataType::Int32,
        ColumnType::Int64 => DataType::Int64,
        ColumnType::Float64 => DataType::Float64,
        ColumnType::Float64List => {
            DataType::List(Arc::new(Field::new("item", DataType::Float64, true)))
        }
    }
}

/// What every part carries as key-value metadata besides its schema's
/// name: the version of enginedyn, the engine file's BLAKE3 and the parsed
/// engine's, the resolved options (JSON), and, in a campaign, its identity
/// and (summary parts) the canonical paths of its files.
#[derive(Debug, Clone, PartialEq)]
pub struct Meta {
    /// `enginedyn.version`.
    pub enginedyn_version: String,
    /// `engine.blake3`: of the engine file's bytes.
    pub engine_blake3: String,
    /// `engine.parsed_blake3`: of the engine as parsed (what `merge`
    /// compares: a blank line more is the same engine).
    pub engine_parsed_blake3: String,
    /// `options`, written as compact JSON text: the options resolved.
    pub options: serde_json::Value,
    /// `enginedyn.campaign`, when the part is one of a campaign.
    pub campaign: Option<Campaign>,
    /// `enginedyn.files` (summary parts): each row's canonical path,
    /// escaped ([`escape_name`]).
    pub files: Option<Vec<String>>,
}

/// The metadata key of the parsed engine's hash.
pub const ENGINE_PARSED_KEY: &str = "engine.parsed_blake3";

/// The metadata keys, in the order written (the last two in a campaign).
pub const META_KEYS: [&str; 7] = [
    "enginedyn.schema",
    "enginedyn.version",
    "engine.blake3",
    ENGINE_PARSED_KEY,
    "options",
    CAMPAIGN_KEY,
    FILES_KEY,
];

impl Meta {
    /// This version of enginedyn's metadata for an engine (the file's hash
    /// and the parsed engine's) and options, outside a campaign.
    pub fn new(
        engine_blake3: impl Into<String>,
        engine_parsed_blake3: impl Into<String>,
        options: serde_json::Value,
    ) -> Self {
        Self {
            enginedyn_version: env!("CARGO_PKG_VERSION").to_string(),
            engine_blake3: engine_blake3.into(),
            engine_parsed_blake3: engine_parsed_blake3.into(),
            options,
            campaign: None,
            files: None,
        }
    }

    /// The key-value pairs of `table`'s parts ([`META_KEYS`]).
    pub fn key_values(&self, table: Table) -> Vec<(&'static str, String)> {
        let mut kv = vec![
            (META_KEYS[0], table.schema_name().to_string()),
            (META_KEYS[1], self.enginedyn_version.clone()),
            (META_KEYS[2], self.engine_blake3.clone()),
            (META_KEYS[3], self.engine_parsed_blake3.clone()),
            (META_KEYS[4], self.options.to_string()),
        ];
        if let Some(c) = &self.campaign {
            kv.push((META_KEYS[5], c.json().to_string()));
        }
        if let (Some(f), Table::Summary) = (&self.files, table) {
            kv.push((META_KEYS[6], serde_json::Value::from(f.clone()).to_string()));
        }
        kv
    }

    /// The campaign's identity as [`prepare`] compares it; `None` outside
    /// a campaign.
    pub fn identity(&self) -> Option<Identity> {
        let c = self.campaign.as_ref()?;
        Some(Identity {
            list_blake3: c.list_blake3.clone(),
            parts: c.parts,
            engine: self.engine_parsed_blake3.clone(),
            options: self.options.clone(),
        })
    }
}

/// The name of part `part` of `parts`: `part-00003-of-00016.parquet`
/// (five digits, six for 100000).
pub fn part_name(part: usize, parts: usize) -> Result<String, TablesError> {
    if parts == 0 || parts > MAX_PARTS || part >= parts {
        return Err(TablesError::PartNumber { part, parts });
    }
    Ok(format!("part-{part:05}-of-{parts:05}.parquet"))
}

/// `(part, parts)` from a part's file name, `None` for any other name.
pub fn parse_part_name(name: &str) -> Option<(usize, usize)> {
    let rest = name.strip_prefix("part-")?.strip_suffix(".parquet")?;
    let (i, n) = rest.split_once("-of-")?;
    let number = |s: &str| {
        (s.len() >= 5 && s.len() <= 6 && s.bytes().all(|b| b.is_ascii_digit()))
            .then(|| s.parse::<usize>().ok())
            .flatten()
    };
    let (i, n) = (number(i)?, number(n)?);
    // The one spelling `part_name` writes.
    (part_name(i, n).ok()? == name).then_some((i, n))
}

/// Where part `part` of `parts` of `table` lies in the campaign `dir`.
pub fn part_path(
    dir: &Path,
    table: Table,
    part: usize,
    parts: usize,
) -> Result<PathBuf, TablesError> {
    Ok(dir.join(table.folder()).join(part_name(part, parts)?))
}

/// Rows of one table, ready to be written: [`SummaryRecord`],
/// [`CycleRow`], [`TracePoint`].
pub trait Rows {
    /// Their table.
    const TABLE: Table;
    /// The record batch of `rows`.
    fn batch(rows: &[Self]) -> Result<RecordBatch, TablesError>
    where
        Self: Sized;
}

impl Rows for SummaryRecord<'_> {
    const TABLE: Table = Table::Summary;
    fn batch(rows: &[Self]) -> Result<RecordBatch, TablesError> {
        let columns = schema::summary_columns();
        let arrays = columns
            .iter()
            .map(|c| array(Self::TABLE, c.name, c.ty, c.nullable, rows, |r| c.cell(r)))
            .collect::<Result<Vec<_>, _>>()?;
        record_batch(Self::TABLE, arrays)
    }
}

impl Rows for CycleRow<'_> {
    const TABLE: Table = Table::Cycles;
    fn batch(rows: &[Self]) -> Result<RecordBatch, TablesError> {
        let arrays = schema::CYCLES
            .iter()
            .map(|c| array(Self::TABLE, c.name, c.ty, c.nullable, rows, |r| c.cell(r)))
            .collect::<Result<Vec<_>, _>>()?;
        record_batch(Self::TABLE, arrays)
    }
}

impl Rows for TracePoint<'_> {
    const TABLE: Table = Table::Traces;
    fn batch(rows: &[Self]) -> Result<RecordBatch, TablesError> {
        let arrays = schema::TRACES
            .iter()
            .map(|c| array(Self::TABLE, c.name, c.ty, c.nullable, rows, |r| c.cell(r)))
            .collect::<Result<Vec<_>, _>>()?;
        record_batch(Self::TABLE, arrays)
    }
}

impl Rows for MapRecord<'_> {
    const TABLE: Table = Table::Map;
    fn batch(rows: &[Self]) -> Result<RecordBatch, TablesError> {
        let mut arrays = schema::summary_columns()
            .iter()
            .map(|c| {
                array(Self::TABLE, c.name, c.ty, c.nullable, rows, |r| {
                    c.cell(&r.summary)
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        for (k, &(name, nullable)) in schema::MAP_COLUMNS.iter().enumerate() {
            arrays.push(array(
                Self::TABLE,
                name,
                ColumnType::Float64,
                nullable,
                rows,
                |r| r.map[k].map_or(Cell::Null, Cell::Float),
            )?);
        }
        record_batch(Self::TABLE, arrays)
    }
}

/// A map's table (`map/1`) as Parquet bytes.
pub fn map_parquet(rows: &[MapRecord<'_>], meta: &Meta) -> Result<Vec<u8>, TablesError> {
    parquet_bytes(rows, meta)
}

fn record_batch(table: Table, arrays: Vec<ArrayRef>) -> Result<RecordBatch, TablesError> {
    RecordBatch::try_new(table.arrow_schema(), arrays).map_err(|e| TablesError::Parquet {
        table,
        source: e.into(),
    })
}

/// One column's array from `rows`, each value checked against the type.
fn array<R>(
    table: Table,
    column: &'static str,
    ty: ColumnType,
    nullable: bool,
    rows: &[R],
    get: impl for<'r> Fn(&'r R) -> Cell<'r>,
) -> Result<ArrayRef, TablesError> {
    let bad = |row: usize, what: String| TablesError::Value {
        table,
        column,
        row,
        what,
    };
    let n = rows.len();
    // A null where none may be, or a value of another kind.
    let check = |row: usize, c: &Cell<'_>| -> Result<(), TablesError> {
        // A NaN or an infinity is written as null.
        let null = c.is_null() || matches!(c, Cell::Float(x) if !x.is_finite());
        if null && !nullable {
            return Err(bad(row, "null in a column that is never null".into()));
        }
        Ok(())
    };
    let mismatch = |row: usize, c: &Cell<'_>| bad(row, format!("{c:?} in a {} column", ty.name()));
    macro_rules! ints {
        ($builder:ident, $t:ty) => {{
            let mut b = $builder::with_capacity(n);
            for (k, r) in rows.iter().enumerate() {
                let c = get(r);
                check(k, &c)?;
                match c {
                    Cell::Int(i) => b.append_value(<$t>::try_from(i).map_err(|_| {
                        bad(k, format!("{i} is out of the range of {}", ty.name()))
                    })?),
                    Cell::Null | Cell::Absent => b.append_null(),
                    c => return Err(mismatch(k, &c)),
                }
            }
            Arc::new(b.finish()) as ArrayRef
        }};
    }
    Ok(match ty {
        ColumnType::Utf8 => {
            let mut b = StringBuilder::with_capacity(n, 16 * n);
            for (k, r) in rows.iter().enumerate() {
                let c = get(r);
                check(k, &c)?;
                match c {
                    Cell::Text(t) => b.append_value(t),
                    Cell::Null | Cell::Absent => b.append_null(),
                    c => return Err(mismatch(k, &c)),
                }
            }
            Arc::new(b.finish())
        }
        ColumnType::Float64 => {
            let mut b = Float64Builder::with_capacity(n);
            for (k, r) in rows.iter().enumerate() {
                let c = get(r);
                check(k, &c)?;
                match c {
                    Cell::Float(x) if x.is_finite() => b.append_value(x),
                    Cell::Int(i) => b.append_value(i as f64),
                    Cell::Null | Cell::Absent | Cell::Float(_) => b.append_null(),
                    c => return Err(mismatch(k, &c)),
                }
            }
            Arc::new(b.finish())
        }
        ColumnType::Bool => {
            let mut b = BooleanBuilder::with_capacity(n);
            for (k, r) in rows.iter().enumerate() {
                let c = get(r);
                check(k, &c)?;
                match c {
                    Cell::Bool(v) => b.append_value(v),
                    Cell::Null | Cell::Absent => b.append_null(),
                    c => return Err(mismatch(k, &c)),
                }
            }
            Arc::new(b.finish())
        }
        ColumnType::Int16 => ints!(Int16Builder, i16),
        ColumnType::Int32 => ints!(Int32Builder, i32),
        ColumnType::Int64 => ints!(Int64Builder, i64),
        ColumnType::Float64List => {
            let mut b = ListBuilder::with_capacity(Float64Builder::new(), n);
            for (k, r) in rows.iter().enumerate() {
                let c = get(r);
                check(k, &c)?;
                match c {
                    Cell::Floats(v) => {
                        for x in v {
                            // A NaN or an infinity is a null item.
                            b.values().append_option(x.is_finite().then_some(x));
                        }
                        b.append(true);
                    }
                    Cell::Null | Cell::Absent => b.append_null(),
                    c => return Err(mismatch(k, &c)),
                }
            }
            Arc::new(b.finish())
        }
    })
}

/// Rows per row group: a campaign's summary part is one group; a traces
/// part is read a group at a time.
const ROW_GROUP: usize = 1 << 20;

/// One part of one table being written to `W`: rows are added a file at a
/// time ([`PartWriter::write`]), so a traces part never holds every file's
/// rows at once.
pub struct PartWriter<W: Write + Send> {
    table: Table,
    writer: ArrowWriter<W>,
    /// The table's schema with the metadata on it too, so that Arrow
    /// readers (pyarrow's `schema.metadata`, polars) see it as well as
    /// Parquet's key-value metadata.
    schema: SchemaRef,
}

impl<W: Write + Send> PartWriter<W> {
    /// A part of `table` with `meta`, written to `out`.
    pub fn new(table: Table, out: W, meta: &Meta) -> Result<Self, TablesError> {
        let kv = meta
            .key_values(table)
            .into_iter()
            .map(|(k, v)| KeyValue::new(k.to_string(), v))
            .collect();
        let props = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_max_row_group_row_count(Some(ROW_GROUP))
            .set_key_value_metadata(Some(kv))
            .build();
        let schema: SchemaRef = std::sync::Arc::new(
            table.arrow_schema().as_ref().clone().with_metadata(
                meta.key_values(table)
                    .into_iter()
                    .map(|(k, v)| (k.to_string(), v))
                    .collect::<std::collections::HashMap<String, String>>(),
            ),
        );
        let writer = ArrowWriter::try_new(out, schema.clone(), Some(props))
            .map_err(|source| TablesError::Parquet { table, source })?;
        Ok(Self {
            table,
            writer,
            schema,
        })
    }

    /// Adds `rows` (of this part's table).
    pub fn write<R: Rows>(&mut self, rows: &[R]) -> Result<(), TablesError> {
        if R::TABLE != self.table {
            return Err(TablesError::Value {
                table: self.table,
                column: "",
                row: 0,
                what: format!("rows of the {} table", R::TABLE),
            });
        }
        if rows.is_empty() {
            return Ok(());
        }
        let batch = R::batch(rows)?
            .with_schema(self.schema.clone())
            .map_err(|e| TablesError::Parquet {
                table: self.table,
                source: e.into(),
            })?;
        self.writer
            .write(&batch)
            .map_err(|source| TablesError::Parquet {
                table: self.table,
                source,
            })
    }

    /// Ends the part (its footer written) and returns the writer.
    pub fn finish(self) -> Result<W, TablesError> {
        let table = self.table;
        self.writer
            .into_inner()
            .map_err(|source| TablesError::Parquet { table, source })
    }
}

/// A whole part of `R`'s table holding `rows`, as bytes.
pub fn parquet_bytes<R: Rows>(rows: &[R], meta: &Meta) -> Result<Vec<u8>, TablesError> {
    let mut w = PartWriter::new(R::TABLE, Vec::new(), meta)?;
    w.write(rows)?;
    w.finish()
}

/// A `summary/4` part holding `rows` (in the shard's order), as bytes.
pub fn summary_parquet(rows: &[SummaryRecord<'_>], meta: &Meta) -> Result<Vec<u8>, TablesError> {
    parquet_bytes(rows, meta)
}

/// A `cycles/3` part holding `rows` (file order, then cylinder, then
/// cycle: [`schema::cycle_rows`] per file), as bytes.
pub fn cycles_parquet(rows: &[CycleRow<'_>], meta: &Meta) -> Result<Vec<u8>, TablesError> {
    parquet_bytes(rows, meta)
}

/// A `traces/1` part holding `rows` ([`schema::trace_points`] per file),
/// as bytes.
pub fn traces_parquet(rows: &[TracePoint<'_>], meta: &Meta) -> Result<Vec<u8>, TablesError> {
    parquet_bytes(rows, meta)
}

/// Writes part `part` of `parts` of `table` into the campaign `dir`
/// (`DIR/TABLE/part-IIIII-of-NNNNN.parquet`) whole or not at all
/// ([`enginedyn_report::replace_file`]): a part is replaced only by the
/// same part, and only when it is a regular file.
pub fn write_part(
    dir: &Path,
    table: Table,
    part: usize,
    parts: usize,
    bytes: &[u8],
) -> Result<PathBuf, TablesError> {
    let name = part_name(part, parts)?;
    let folder = dir.join(table.folder());
    enginedyn_report::replace_file(&folder, &name, bytes)?;
    Ok(folder.join(name))
}

/// A part written straight to its staged file (for a part too large to
/// hold, such as traces): add rows with [`PartWriter::write`], then
/// [`commit_part`].
pub fn stage_part(
    dir: &Path,
    table: Table,
    part: usize,
    parts: usize,
    meta: &Meta,
) -> Result<PartWriter<enginedyn_report::Staged>, TablesError> {
    let name = part_name(part, parts)?;
    let staged = enginedyn_report::Staged::new(&dir.join(table.folder()), &name)?;
    PartWriter::new(table, staged, meta)
}

/// Ends a part begun by [`stage_part`] and moves it into place whole.
pub fn commit_part(w: PartWriter<enginedyn_report::Staged>) -> Result<PathBuf, TablesError> {
    let staged = w.finish()?;
    let path = staged.path().to_path_buf();
    staged.commit()?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn part_names() {
        assert_eq!(part_name(3, 16).unwrap(), "part-00003-of-00016.parquet");
        assert_eq!(
            part_name(99_999, 100_000).unwrap(),
            "part-99999-of-100000.parquet"
        );
        assert!(part_name(16, 16).is_err());
        assert!(part_name(0, 0).is_err());
        assert!(part_name(0, 100_001).is_err());
        assert_eq!(
            parse_part_name("part-00003-of-00016.parquet"),
            Some((3, 16))
        );
        assert_eq!(
            parse_part_name("part-99999-of-100000.parquet"),
            Some((99_999, 100_000))
        );
        for bad in [
            "part-3-of-16.parquet",
            "part-00016-of-00016.parquet",
            "part-000003-of-00016.parquet",
            "part-00003-of-00016.parquet.tmp",
            ".part-00003-of-00016.parquet",
            "part-0000x-of-00016.parquet",
        ] {
            assert_eq!(parse_part_name(bad), None, "{bad}");
        }
    }

    /// A value out of a column's range, or a null where none may be, is an
    /// error naming the column and row, never a wrong number.
    #[test]
    fn values_are_checked() {
        let meta = Meta::new("x", "y", serde_json::json!({}));
        let row = |cylinder| CycleRow {
            file: "f",
            cylinder,
            cycle: 1,
            skip_reason: None,
            imep_pa: None,
            p_max_pa: None,
            p_max_angle_deg: None,
            peg_offset_pa: None,
            rpm: 1000.0,
            combustion: None,
        };
        let e = cycles_parquet(&[row(1), row(40_000)], &meta).unwrap_err();
        assert_eq!(
            e.to_string(),
            "cycles table, column `cylinder`, row 1: 40000 is out of the range of int16"
        );
        let mut r = row(1);
        r.rpm = f64::NAN;
        let e = cycles_parquet(&[r], &meta).unwrap_err();
        assert!(e.to_string().contains("column `rpm`, row 0: null"), "{e}");
        let p = TracePoint {
            file: "f",
            cylinder: 1,
            crank_deg: f64::INFINITY,
            pressure_pa: 1e5,
        };
        let e = traces_parquet(&[p], &meta).unwrap_err();
        assert!(
            e.to_string().contains("column `crank_deg`, row 0: null"),
            "{e}"
        );
    }
}
