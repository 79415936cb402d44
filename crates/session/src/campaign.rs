//! Campaigns: a batch's rows kept for the Parquet tables (`summary/2`,
//! `cycles/2`, `traces/1`), its parts written whole into a folder shared by
//! every shard, and the merge check. `enginedyn batch --parquet`,
//! `enginedyn merge` and the Python package's `write_parquet`,
//! `run_shard` and `check_campaign` all come here; the campaign's identity
//! and its checks live in `enginedyn_tables`.

use crate::batch::{Shard, shard_order};
pub use crate::batch::{canonical_key, shown};
use crate::error::{Class, Error, Result};
use crate::session::Session;
use enginedyn_ingest::Resampled;
use enginedyn_pipeline::Summary;
use enginedyn_pipeline::schema::{SummaryRecord, cycle_rows, trace_points};
use enginedyn_tables::{Campaign, Meta, PartSet, Table, TablesError};
use std::path::{Path, PathBuf};

/// The identities of a list, each once.
fn unique_keys(keys: &[Vec<u8>]) -> Vec<&[u8]> {
    let mut k: Vec<&[u8]> = keys.iter().map(Vec::as_slice).collect();
    k.sort_unstable();
    k.dedup();
    k
}

/// A campaign's list cut into `parts` shards, each file's identity taken
/// once: the list's BLAKE3 (`enginedyn.campaign`'s `list_blake3`) and
/// each part's files by the shard rule. What a scheduler plans on its
/// client, so that a task handles its own files only.
pub fn list_plan(list: &[PathBuf], parts: usize) -> Result<(String, Vec<Vec<PathBuf>>)> {
    Shard::new(0, parts).map_err(|e| Error::usage(format!("parts: {e}")))?;
    let keyed: Vec<(Vec<u8>, PathBuf)> =
        list.iter().map(|p| (canonical_key(p), p.clone())).collect();
    let unique: Vec<&[u8]> = shard_order(&keyed)
        .into_iter()
        .map(|(k, _)| k.as_slice())
        .collect();
    let hash = enginedyn_tables::list_blake3(&unique);
    Ok((hash, Shard::split_keyed(&keyed, parts)))
}

/// One file of a campaign as its tables hold it.
#[derive(Debug, Clone)]
pub struct Row {
    /// The path as given (escaped: [`shown`]).
    pub file: String,
    /// Its identity ([`canonical_key`]).
    pub key: Vec<u8>,
    /// Why it failed; `None` when it ran.
    pub error: Option<String>,
    /// Its diagram file's BLAKE3, when it could be read.
    pub diagram_blake3: Option<String>,
    /// Its summary, when it ran.
    pub summary: Option<Summary>,
    /// Its traces on the grid with their per-cycle figures (for the
    /// `cycles` and `traces` tables), when it ran on one diagram.
    pub resampled: Option<Resampled>,
}

/// The largest failed file hashed for its row (bytes): 1 GiB, the largest
/// file a reader holds whole (an MDF4 file); a larger one's row has no
/// hash, so that a failed file costs no more than its reading would have.
pub const MAX_FAILED_HASHED: u64 = 1 << 30;

impl Row {
    /// A failed file's row, the file hashed when it is a regular file of
    /// at most [`MAX_FAILED_HASHED`] bytes. It is opened as a diagram is
    /// ([`crate::diagram::open_diagram`]): a FIFO, a device or a folder is
    /// refused at once, never waited on or read; and no more than the
    /// size it had when opened is read.
    pub fn failed(file: &Path, error: &Error) -> Self {
        Self {
            file: shown(file),
            key: canonical_key(file),
            error: Some(error.message.clone()),
            diagram_blake3: failed_blake3(file),
            summary: None,
            resampled: None,
        }
    }
}

/// The BLAKE3 of a failed file for its row (see [`Row::failed`]).
fn failed_blake3(file: &Path) -> Option<String> {
    let f = crate::diagram::open_diagram(file).ok()?;
    let len = f.metadata().ok()?.len();
    if len > MAX_FAILED_HASHED {
        return None;
    }
    let mut h = blake3::Hasher::new();
    let mut bounded = std::io::Read::take(f, len);
    std::io::copy(&mut bounded, &mut h).ok()?;
    Some(h.finalize().to_hex().to_string())
}

/// A tables error with its class: a campaign that is incomplete or
/// inconsistent is the data's; one that cannot be written, or a folder in
/// the way or of another campaign, is I/O (exit 2).
fn tables_error(e: TablesError) -> Error {
    let class = match &e {
        TablesError::Missing { .. }
        | TablesError::NoParts { .. }
        | TablesError::Counts { .. }
        | TablesError::Differs { .. }
        | TablesError::NotOfCampaign { .. }
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

/// Where and how a part is written, checked before any work
/// ([`Session::plan_parts`]).
#[derive(Debug, Clone)]
pub struct Plan {
    /// The campaign's folder.
    pub dir: PathBuf,
    /// The part.
    pub shard: Shard,
    /// The parts' metadata (the campaign's identity in it).
    pub meta: Meta,
    /// Whether the traces table is written.
    pub traces: bool,
    /// Parts of another campaign removed (`--replace`).
    pub removed: Vec<PathBuf>,
}

impl Session {
    /// The options a campaign's parts record (`options` metadata): the
    /// method and reader options as used, defaults filled in.
    pub fn options_json(&self) -> serde_json::Value {
        serde_json::json!({
            "method": self.method.resolved_json(self.engine().rod_model()),
            "reader": self.reader.json(),
        })
    }

    /// The key-value metadata of this session's parts (outside a campaign).
    pub fn meta(&self) -> Result<Meta> {
        let engine = crate::inputs::of(&self.loaded, &[])?;
        let parsed = enginedyn_report::blake3_hex(self.engine().meaning().as_bytes());
        Ok(Meta::new(engine.engine_blake3, parsed, self.options_json()))
    }

    /// A campaign row of a file analysed (`resampled` kept for the cycles
    /// and traces tables), with the BLAKE3 its reading gave.
    pub fn row(
        &self,
        file: &Path,
        analysis: &enginedyn_pipeline::Analysis,
        resampled: Option<Resampled>,
        blake3: String,
    ) -> Row {
        Row {
            file: shown(file),
            key: canonical_key(file),
            error: None,
            diagram_blake3: Some(blake3),
            summary: Some(analysis.summary.clone()),
            resampled,
        }
    }

    /// Before any work: part `shard` of the campaign of `list` (every file
    /// of the campaign, not only this shard's) in `dir`. Refuses a folder
    /// holding another campaign's parts (naming both) unless `replace`,
    /// which removes them; refuses anything at a part's path that is not
    /// enginedyn's (exit 2); removes what a killed run of this part left.
    pub fn plan_parts(
        &self,
        dir: &Path,
        shard: Shard,
        list: &[PathBuf],
        traces: bool,
        replace: bool,
    ) -> Result<Plan> {
        let keys: Vec<Vec<u8>> = list.iter().map(|p| canonical_key(p)).collect();
        self.plan_keys(dir, shard, &keys, traces, replace)
    }

    /// [`Session::plan_parts`] of a list given by its files' identities
    /// (a file named twice counted once).
    pub fn plan_keys(
        &self,
        dir: &Path,
        shard: Shard,
        keys: &[Vec<u8>],
        traces: bool,
        replace: bool,
    ) -> Result<Plan> {
        let list = enginedyn_tables::list_blake3(&unique_keys(keys));
        self.plan_listed(dir, shard, list, traces, replace)
    }

    /// [`Session::plan_keys`] of a list known by its hash ([`list_plan`]:
    /// computed once for every part of a campaign, not in each task).
    pub fn plan_listed(
        &self,
        dir: &Path,
        shard: Shard,
        list_blake3: String,
        traces: bool,
        replace: bool,
    ) -> Result<Plan> {
        let mut meta = self.meta()?;
        let mut tables = vec![Table::Summary, Table::Cycles];
        if traces {
            tables.push(Table::Traces);
        }
        meta.campaign = Some(Campaign {
            list_blake3,
            parts: shard.count,
            part: shard.index,
            tables,
        });
        let Some(identity) = meta.identity() else {
            return Err(Error::io("a campaign without an identity (a bug)"));
        };
        let prepared = enginedyn_tables::prepare(dir, &identity, shard.index, replace)
            .map_err(tables_error)?;
        Ok(Plan {
            dir: dir.to_path_buf(),
            shard,
            meta,
            traces,
            removed: prepared.removed,
        })
    }

    /// Writes `rows` as the part `plan` names: its tables staged together,
    /// then moved into place, the summary part last (the marker that the
    /// part is whole). Returns the paths written.
    pub fn write_plan(&self, plan: &Plan, rows: &[Row]) -> Result<Vec<PathBuf>> {
        let mut meta = plan.meta.clone();
        meta.files = Some(
            rows.iter()
                .map(|r| enginedyn_tables::escape_name(&r.key))
                .collect(),
        );
        let (i, n) = (plan.shard.index, plan.shard.count);
        let mut set = PartSet::new(&plan.dir, i, n).map_err(tables_error)?;
        set.bytes(Table::Summary, &self.summary_with(rows, &meta)?)
            .map_err(tables_error)?;
        set.bytes(Table::Cycles, &self.cycles_with(rows, &meta)?)
            .map_err(tables_error)?;
        if plan.traces {
            let mut w = set.writer(Table::Traces, &meta).map_err(tables_error)?;
            for r in rows {
                if let Some(res) = &r.resampled {
                    w.write(&trace_points(&r.file, res)).map_err(tables_error)?;
                }
            }
            set.finish(w).map_err(tables_error)?;
        }
        set.commit().map_err(tables_error)
    }

    /// [`Session::plan_parts`] then [`Session::write_plan`], the list being
    /// `list` when given, else the rows' own files (a campaign of one part).
    pub fn write_parts(
        &self,
        dir: &Path,
        shard: Shard,
        list: Option<&[PathBuf]>,
        rows: &[Row],
        traces: bool,
        replace: bool,
    ) -> Result<Vec<PathBuf>> {
        let plan = match list {
            Some(l) => self.plan_parts(dir, shard, l, traces, replace)?,
            None => {
                let keys: Vec<Vec<u8>> = rows.iter().map(|r| r.key.clone()).collect();
                self.plan_keys(dir, shard, &keys, traces, replace)?
            }
        };
        self.write_plan(&plan, rows)
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
                diagram_blake3: r.diagram_blake3.as_deref(),
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

/// `enginedyn merge DIR [--parts N]`: checks the campaign (every part of
/// every table, one schema, one campaign, every file once in its part),
/// then writes `DIR/_manifest.json`; returns the manifest and its path. A
/// campaign that fails the check has no manifest: an earlier one is
/// removed.
pub fn merge(dir: &Path, parts: Option<usize>) -> Result<(serde_json::Value, PathBuf)> {
    let m = match enginedyn_tables::check_campaign(dir, parts) {
        Ok(m) => m,
        Err(e) => {
            let err = tables_error(e);
            return Err(match enginedyn_tables::remove_manifest(dir) {
                Ok(()) => err,
                Err(r) => Error::io(format!("{}; and {r}", err.message)),
            });
        }
    };
    let path = enginedyn_tables::write_manifest(dir, &m).map_err(tables_error)?;
    Ok((m.json(), path))
}

/// The merge check alone (no manifest written).
pub fn check(dir: &Path, parts: Option<usize>) -> Result<serde_json::Value> {
    let m = enginedyn_tables::check_campaign(dir, parts).map_err(tables_error)?;
    Ok(m.json())
}
