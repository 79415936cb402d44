//! Campaigns: a batch's rows kept for the Parquet tables (`summary/2`,
//! `cycles/2`, `traces/1`), its parts written whole into a folder shared by
//! every shard, and the merge check. `enginedyn batch --parquet`,
//! `enginedyn merge` and the Python package's `write_parquet`,
//! `run_shard` and `check_campaign` all come here.

use crate::batch::Shard;
use crate::error::{Class, Error, Result};
use crate::session::Session;
use enginedyn_ingest::Resampled;
use enginedyn_pipeline::Summary;
use enginedyn_pipeline::schema::{SummaryRecord, cycle_rows, trace_points};
use enginedyn_tables::{Meta, Table, TablesError};
use std::path::{Path, PathBuf};

/// One file of a campaign as its tables hold it.
#[derive(Debug, Clone)]
pub struct Row {
    /// The path as given.
    pub file: String,
    /// Why it failed; `None` when it ran.
    pub error: Option<String>,
    /// Its diagram file's SHA-256, when it could be read.
    pub diagram_sha256: Option<String>,
    /// Its summary, when it ran.
    pub summary: Option<Summary>,
    /// Its traces on the grid with their per-cycle figures (for the
    /// `cycles` and `traces` tables), when it ran on one diagram.
    pub resampled: Option<Resampled>,
}

impl Row {
    /// A failed file's row.
    pub fn failed(file: &Path, error: &Error) -> Self {
        Self {
            file: file.display().to_string(),
            error: Some(error.message.clone()),
            diagram_sha256: enginedyn_report::sha256_file(file).ok(),
            summary: None,
            resampled: None,
        }
    }
}

/// A tables error with its class: a campaign that is incomplete or
/// inconsistent is the data's; one that cannot be written is I/O.
fn tables_error(e: TablesError) -> Error {
    let class = match &e {
        TablesError::Missing { .. }
        | TablesError::NoParts { .. }
        | TablesError::Counts { .. }
        | TablesError::Differs { .. }
        | TablesError::Read { .. } => Class::Diagram,
        TablesError::PartNumber { .. } => Class::Usage,
        _ => Class::Io,
    };
    let message = e.to_string();
    match class {
        Class::Diagram => Error::data(message),
        Class::Usage => Error::usage(message),
        _ => Error::io(message),
    }
}

impl Session {
    /// The options a campaign's parts record (`options` metadata): the
    /// method and reader options as given, by their names.
    pub fn options_json(&self) -> serde_json::Value {
        serde_json::json!({
            "method": self.method.json(),
            "reader": self.reader.json(),
        })
    }

    /// The key-value metadata of this session's parts.
    pub fn meta(&self) -> Result<Meta> {
        let engine = crate::inputs::of(&self.loaded, &[])?;
        Ok(Meta::new(engine.engine_sha256, self.options_json()))
    }

    /// A campaign row of a file analysed (`resampled` kept for the cycles
    /// and traces tables); `sha256`: the file's hash when the caller has it
    /// already (a `summary.json`'s `inputs`), else it is read and hashed.
    pub fn row(
        &self,
        file: &Path,
        analysis: &enginedyn_pipeline::Analysis,
        resampled: Option<Resampled>,
        sha256: Option<String>,
    ) -> Row {
        Row {
            file: file.display().to_string(),
            error: None,
            diagram_sha256: sha256.or_else(|| enginedyn_report::sha256_file(file).ok()),
            summary: Some(analysis.summary.clone()),
            resampled,
        }
    }

    /// Writes `rows` as part `shard` of the campaign in `dir`: the
    /// `summary` and `cycles` parts, and `traces` when asked, each whole
    /// or not at all. Returns the paths written.
    pub fn write_parts(
        &self,
        dir: &Path,
        shard: Shard,
        rows: &[Row],
        traces: bool,
    ) -> Result<Vec<PathBuf>> {
        let meta = self.meta()?;
        let bytes = self.summary_with(rows, &meta)?;
        let cycle_bytes = self.cycles_with(rows, &meta)?;
        let (i, n) = (shard.index, shard.count);
        let mut written = vec![
            enginedyn_tables::write_part(dir, Table::Summary, i, n, &bytes)
                .map_err(tables_error)?,
            enginedyn_tables::write_part(dir, Table::Cycles, i, n, &cycle_bytes)
                .map_err(tables_error)?,
        ];
        if traces {
            let mut w = enginedyn_tables::stage_part(dir, Table::Traces, i, n, &meta)
                .map_err(tables_error)?;
            for r in rows {
                if let Some(res) = &r.resampled {
                    w.write(&trace_points(&r.file, res)).map_err(tables_error)?;
                }
            }
            written.push(enginedyn_tables::commit_part(w).map_err(tables_error)?);
        }
        Ok(written)
    }

    /// The `summary` table of `rows` as Parquet bytes (what a part holds).
    pub fn summary_bytes(&self, rows: &[Row]) -> Result<Vec<u8>> {
        self.summary_with(rows, &self.meta()?)
    }

    /// The `cycles` table of `rows` as Parquet bytes.
    pub fn cycles_bytes(&self, rows: &[Row]) -> Result<Vec<u8>> {
        self.cycles_with(rows, &self.meta()?)
    }

    fn summary_with(&self, rows: &[Row], meta: &Meta) -> Result<Vec<u8>> {
        let engine = self.engine().name();
        let summary: Vec<SummaryRecord<'_>> = rows
            .iter()
            .map(|r| SummaryRecord {
                file: &r.file,
                error: r.error.as_deref(),
                engine,
                diagram_sha256: r.diagram_sha256.as_deref(),
                summary: r.summary.as_ref(),
            })
            .collect();
        enginedyn_tables::summary_parquet(&summary, meta).map_err(tables_error)
    }

    fn cycles_with(&self, rows: &[Row], meta: &Meta) -> Result<Vec<u8>> {
        let cycles: Vec<_> = rows
            .iter()
            .filter_map(|r| Some((r, r.resampled.as_ref()?, r.summary.as_ref()?)))
            .flat_map(|(r, res, s)| cycle_rows(&r.file, res, s.rpm))
            .collect();
        enginedyn_tables::cycles_parquet(&cycles, meta).map_err(tables_error)
    }
}

/// `enginedyn merge DIR [--parts N]`: checks every part of every table is
/// there with one schema, then writes `DIR/_manifest.json`; returns the
/// manifest and its path.
pub fn merge(dir: &Path, parts: Option<usize>) -> Result<(serde_json::Value, PathBuf)> {
    let m = enginedyn_tables::check_campaign(dir, parts).map_err(tables_error)?;
    let path = enginedyn_tables::write_manifest(dir, &m).map_err(tables_error)?;
    Ok((m.json(), path))
}

/// The merge check alone (no manifest written).
pub fn check(dir: &Path, parts: Option<usize>) -> Result<serde_json::Value> {
    let m = enginedyn_tables::check_campaign(dir, parts).map_err(tables_error)?;
    Ok(m.json())
}
