//! The merge check: every part of every table, one schema, one engine and
//! one set of options; then the campaign's manifest (`_manifest.json`).

use crate::{
    CAMPAIGN_KEY, Campaign, ENGINE_PARSED_KEY, FILES_KEY, META_KEYS, Table, TablesError,
    parse_part_name, part_name, unescape_name,
};
use arrow_array::{Array, BooleanArray};
use arrow_schema::SchemaRef;
use parquet::arrow::ProjectionMask;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The manifest's file name in a campaign's folder.
pub const MANIFEST: &str = "_manifest.json";

/// What a whole campaign holds (`DIR/_manifest.json`).
#[derive(Debug, Clone, PartialEq)]
pub struct Manifest {
    /// N: the parts of each table.
    pub parts: usize,
    /// The tables present (summary and cycles always, traces when written).
    pub tables: Vec<Table>,
    /// Diagram files: rows of the summary table.
    pub files: u64,
    /// Files that failed: summary rows with an error.
    pub failed: u64,
    /// Measured cycles: rows of the cycles table.
    pub cycles: u64,
    /// Of those, the cycles left out of the averages (`used` false).
    pub cycles_skipped: u64,
    /// The version of enginedyn that wrote the parts.
    pub enginedyn_version: String,
    /// The engine file's BLAKE3 (of the first part; parts whose engine
    /// files differ only in their bytes are one campaign).
    pub engine_blake3: String,
    /// The campaign's file list (its BLAKE3).
    pub list_blake3: String,
    /// The options used.
    pub options: serde_json::Value,
}

impl Manifest {
    /// The manifest as `_manifest.json` writes it.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "parts": self.parts,
            "tables": self.tables.iter().map(|t| t.schema_name()).collect::<Vec<_>>(),
            "files": self.files,
            "failed": self.failed,
            "cycles": self.cycles,
            "cycles_skipped": self.cycles_skipped,
            "enginedyn_version": self.enginedyn_version,
            "engine_blake3": self.engine_blake3,
            "list_blake3": self.list_blake3,
            "options": self.options,
        })
    }
}

/// Removes `DIR/_manifest.json` (a failed merge, a campaign replaced):
/// no manifest vouches for a folder that is not one campaign.
pub fn remove_manifest(dir: &Path) -> Result<(), TablesError> {
    let path = dir.join(MANIFEST);
    match std::fs::symlink_metadata(&path) {
        Ok(m) if m.is_file() => std::fs::remove_file(&path).map_err(|e| read_err(&path, e)),
        _ => Ok(()),
    }
}

/// The enginedyn metadata of the part at `path`.
pub(crate) fn metadata(path: &Path) -> Result<BTreeMap<String, String>, TablesError> {
    Ok(footer(path)?.0.meta)
}

/// Writes `DIR/_manifest.json` whole or not at all.
pub fn write_manifest(dir: &Path, m: &Manifest) -> Result<PathBuf, TablesError> {
    let text = serde_json::to_string_pretty(&m.json()).unwrap_or_default() + "\n";
    enginedyn_report::replace_file(dir, MANIFEST, text.as_bytes())?;
    Ok(dir.join(MANIFEST))
}

pub(crate) fn read_err(path: &Path, e: impl std::fmt::Display) -> TablesError {
    TablesError::Read {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// A part found in a table's folder: (part, parts, path).
type Found = (usize, usize, PathBuf);

/// The parts in a table's folder, by part. Names that are not parts
/// (hidden staging folders, the user's files) are passed over.
fn listed(folder: &Path) -> Result<Vec<Found>, TablesError> {
    let entries = match std::fs::read_dir(folder) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(read_err(folder, e)),
    };
    let mut out = Vec::new();
    for e in entries {
        let e = e.map_err(|e| read_err(folder, e))?;
        if let Some((i, n)) = e.file_name().to_str().and_then(parse_part_name) {
            out.push((i, n, e.path()));
        }
    }
    out.sort();
    Ok(out)
}

/// What one part's footer says.
struct Footer {
    schema: SchemaRef,
    meta: BTreeMap<String, String>,
    rows: u64,
}

fn footer(
    path: &Path,
) -> Result<(Footer, ParquetRecordBatchReaderBuilder<std::fs::File>), TablesError> {
    let file = std::fs::File::open(path).map_err(|e| read_err(path, e))?;
    let b = ParquetRecordBatchReaderBuilder::try_new(file).map_err(|e| read_err(path, e))?;
    let fm = b.metadata().file_metadata();
    let meta = fm
        .key_value_metadata()
        .map(|kv| {
            kv.iter()
                .filter(|k| META_KEYS.contains(&k.key.as_str()))
                .map(|k| (k.key.clone(), k.value.clone().unwrap_or_default()))
                .collect()
        })
        .unwrap_or_default();
    let f = Footer {
        schema: b.schema().clone(),
        meta,
        rows: u64::try_from(fm.num_rows()).unwrap_or(0),
    };
    Ok((f, b))
}

/// How two schemas differ, in words; `None` when their columns are the
/// same (names, types, nullability, order).
fn schema_difference(a: &SchemaRef, b: &SchemaRef) -> Option<String> {
    let (fa, fb) = (a.fields(), b.fields());
    for k in 0..fa.len().max(fb.len()) {
        let show = |f: Option<&arrow_schema::FieldRef>| {
            f.map_or("nothing".to_string(), |f| {
                format!(
                    "`{}` {}{}",
                    f.name(),
                    f.data_type(),
                    if f.is_nullable() { "" } else { " not null" }
                )
            })
        };
        let (x, y) = (fa.get(k), fb.get(k));
        let same = match (x, y) {
            (Some(x), Some(y)) => {
                x.name() == y.name()
                    && x.data_type() == y.data_type()
                    && x.is_nullable() == y.is_nullable()
            }
            _ => false,
        };
        if !same {
            return Some(format!(
                "column {}: {} here, {} there",
                k + 1,
                show(x),
                show(y)
            ));
        }
    }
    None
}

/// Counts the non-null values of the column `name` (`error`), or the
/// false ones of a boolean column (`used`), reading that column alone.
fn count_column(
    path: &Path,
    b: ParquetRecordBatchReaderBuilder<std::fs::File>,
    name: &str,
) -> Result<u64, TablesError> {
    let Some(index) = b.schema().fields().iter().position(|f| f.name() == name) else {
        return Err(read_err(path, format!("no column `{name}`")));
    };
    let mask = ProjectionMask::roots(b.parquet_schema(), [index]);
    let reader = b
        .with_projection(mask)
        .build()
        .map_err(|e| read_err(path, e))?;
    let mut n = 0u64;
    for batch in reader {
        let batch = batch.map_err(|e| read_err(path, e))?;
        let col = batch.column(0);
        n += match col.as_any().downcast_ref::<BooleanArray>() {
            Some(used) => used.false_count() as u64,
            None => (col.len() - col.null_count()) as u64,
        };
    }
    Ok(n)
}

/// Checks the campaign in `dir` (`enginedyn merge DIR [--parts N]`, and
/// Python's `check_campaign`): every part `0..N` of the summary and cycles
/// tables, and of traces when any traces part exists, is there; all parts
/// of a table have one schema (the table's, named in `enginedyn.schema`);
/// every part was written by one enginedyn for one engine file and one set
/// of options. N is `parts` when given, else the count the part names
/// give (`-of-NNNNN`), refused when they give two. Returns the manifest;
/// writes nothing ([`write_manifest`] does).
pub fn check_campaign(dir: &Path, parts: Option<usize>) -> Result<Manifest, TablesError> {
    if let Some(n) = parts {
        part_name(0, n)?;
    }
    let mut found: Vec<(Table, Vec<Found>)> = Vec::new();
    for table in Table::ALL {
        let folder = dir.join(table.folder());
        let list = listed(&folder)?;
        if list.is_empty() {
            if table == Table::Traces {
                continue;
            }
            return Err(TablesError::NoParts { table, folder });
        }
        found.push((table, list));
    }
    // One count: `--parts N`, else the first part's.
    let (n, origin) = match parts {
        Some(n) => (n, PathBuf::from(format!("--parts {n}"))),
        None => {
            let (_, n, p) = &found[0].1[0];
            (*n, p.clone())
        }
    };
    for (_, list) in &found {
        if let Some((_, m, p)) = list.iter().find(|(_, m, _)| *m != n) {
            return Err(TablesError::Counts {
                path: p.clone(),
                found: *m,
                expected: n,
                other: origin,
            });
        }
    }
    let mut reference: Option<(PathBuf, BTreeMap<String, String>, Campaign)> = None;
    let (mut files, mut failed, mut cycles, mut cycles_skipped) = (0, 0, 0, 0);
    let mut tables_named: Option<Vec<Table>> = None;
    let mut in_parts: Vec<(Vec<u8>, usize)> = Vec::new();
    for (table, list) in &found {
        // Every part 0..N, in order (the list is sorted, of one count).
        for i in 0..n {
            if list.get(i).map(|(k, _, _)| *k) != Some(i) {
                return Err(TablesError::Missing {
                    table: *table,
                    path: dir.join(table.folder()).join(part_name(i, n)?),
                    part: i,
                    parts: n,
                });
            }
        }
        let mut first: Option<(PathBuf, SchemaRef)> = None;
        for &(part, _, ref path) in list {
            let (f, builder) = footer(path)?;
            let differs = |what: &str, detail: String, reference: &Path| TablesError::Differs {
                path: path.clone(),
                reference: reference.to_path_buf(),
                what: what.to_string(),
                detail,
            };
            // The table's own schema name and columns.
            let named = f.meta.get(META_KEYS[0]).map_or("", String::as_str);
            if named != table.schema_name() {
                return Err(differs(
                    "the schema",
                    format!(
                        "`enginedyn.schema` is `{named}` here, `{}` there",
                        table.schema_name()
                    ),
                    &first
                        .as_ref()
                        .map_or_else(|| PathBuf::from(table.schema_name()), |f| f.0.clone()),
                ));
            }
            match &first {
                Some((p, s)) => {
                    if let Some(d) = schema_difference(&f.schema, s) {
                        return Err(differs("the schema", d, p));
                    }
                }
                None => {
                    if let Some(d) = schema_difference(&f.schema, &table.arrow_schema()) {
                        return Err(differs("the schema", d, Path::new(table.schema_name())));
                    }
                    first = Some((path.clone(), f.schema.clone()));
                }
            }
            // One enginedyn, one engine, one set of options, one campaign.
            let campaign = same_campaign(path, part, n, &f, &mut reference)?;
            if *table == Table::Summary {
                tables_named = Some(campaign.tables.clone());
                let listed = files_of(path, &f)?;
                in_parts.extend(listed.into_iter().map(|k| (k, part)));
            }
            match table {
                Table::Summary => {
                    files += f.rows;
                    failed += count_column(path, builder, "error")?;
                }
                Table::Cycles => {
                    cycles += f.rows;
                    cycles_skipped += count_column(path, builder, "used")?;
                }
                Table::Traces | Table::Map => {}
            }
        }
    }
    let tables: Vec<Table> = found.iter().map(|(t, _)| *t).collect();
    let (first, meta, campaign) = reference.unwrap_or_default();
    if let Some(named) = tables_named.filter(|t| *t != tables) {
        let shown = |t: &[Table]| t.iter().map(|t| t.folder()).collect::<Vec<_>>().join(", ");
        return Err(TablesError::NotOfCampaign {
            path: first,
            what: format!(
                "its part holds the tables {}, but the folder has parts of {}: a part stopped before it was whole, or parts of two runs",
                shown(&named),
                shown(&tables)
            ),
        });
    }
    check_files(dir, n, &campaign.list_blake3, in_parts)?;
    let get = |k: &str| meta.get(k).cloned().unwrap_or_default();
    let options_text = get(META_KEYS[4]);
    let options =
        serde_json::from_str(&options_text).unwrap_or(serde_json::Value::String(options_text));
    Ok(Manifest {
        parts: n,
        tables,
        files,
        failed,
        cycles,
        cycles_skipped,
        enginedyn_version: get(META_KEYS[1]),
        engine_blake3: get(META_KEYS[2]),
        list_blake3: campaign.list_blake3,
        options,
    })
}

/// The campaign a part names, checked against the part's own name (`part`
/// of `n`) and the first part's (`reference`, set from this one when
/// `None`): one enginedyn, one parsed engine, one set of resolved options,
/// one file list and one set of tables.
fn same_campaign(
    path: &Path,
    part: usize,
    n: usize,
    f: &Footer,
    reference: &mut Option<(PathBuf, BTreeMap<String, String>, Campaign)>,
) -> Result<Campaign, TablesError> {
    let not = |what: String| TablesError::NotOfCampaign {
        path: path.to_path_buf(),
        what,
    };
    let c = f
        .meta
        .get(CAMPAIGN_KEY)
        .and_then(|c| Campaign::parse(c))
        .ok_or_else(|| {
            not(format!(
                "no `{CAMPAIGN_KEY}` metadata: not a part of a campaign (written outside one, or by an older enginedyn); write the campaign again"
            ))
        })?;
    if (c.part, c.parts) != (part, n) {
        return Err(not(format!(
            "its metadata says part {} of {}, but its name says part {part} of {n}: a copy of another part?",
            c.part, c.parts
        )));
    }
    let Some((p, m, first)) = reference.as_ref() else {
        *reference = Some((path.to_path_buf(), f.meta.clone(), c.clone()));
        return Ok(c);
    };
    let differs = |what: &str, detail: String| TablesError::Differs {
        path: path.to_path_buf(),
        reference: p.clone(),
        what: what.to_string(),
        detail,
    };
    if c.list_blake3 != first.list_blake3 {
        return Err(differs(
            "the file list",
            format!(
                "list_blake3 {} here, {} there: a part of another campaign, or of the list before it changed",
                crate::short(&c.list_blake3),
                crate::short(&first.list_blake3)
            ),
        ));
    }
    for key in [META_KEYS[1], ENGINE_PARSED_KEY] {
        let (here, there) = (f.meta.get(key), m.get(key));
        if here != there {
            return Err(differs(
                &format!("`{key}`"),
                format!(
                    "`{}` here, `{}` there",
                    here.map_or("", String::as_str),
                    there.map_or("", String::as_str)
                ),
            ));
        }
    }
    let options = |m: &BTreeMap<String, String>| {
        m.get(META_KEYS[4])
            .and_then(|t| serde_json::from_str::<serde_json::Value>(t).ok())
    };
    let (here, there) = (options(&f.meta), options(m));
    if here != there {
        let show = |o: Option<serde_json::Value>| o.map_or_else(String::new, |o| o.to_string());
        return Err(differs(
            "the options",
            format!("`{}` here, `{}` there", show(here), show(there)),
        ));
    }
    if c.tables != first.tables {
        return Err(differs(
            "the tables held",
            format!("{} here, {} there", c.tables_shown(), first.tables_shown()),
        ));
    }
    Ok(c)
}

/// The canonical paths a summary part's rows are of (`enginedyn.files`),
/// one per row.
fn files_of(path: &Path, f: &Footer) -> Result<Vec<Vec<u8>>, TablesError> {
    let not = |what: String| TablesError::NotOfCampaign {
        path: path.to_path_buf(),
        what,
    };
    let list: Vec<String> = f
        .meta
        .get(FILES_KEY)
        .and_then(|t| serde_json::from_str(t).ok())
        .ok_or_else(|| not(format!("no `{FILES_KEY}` metadata")))?;
    if list.len() as u64 != f.rows {
        return Err(not(format!(
            "{} rows for {} files: rows added or doubled after it was written",
            f.rows,
            list.len()
        )));
    }
    Ok(list.iter().map(|s| unescape_name(s)).collect())
}

/// Every file of the list once, in the part the shard rule gives it (the
/// paths sorted bytewise, path k in part k mod N), and the files together
/// the list the parts name (`list_blake3`).
fn check_files(
    dir: &Path,
    n: usize,
    list_blake3: &str,
    mut files: Vec<(Vec<u8>, usize)>,
) -> Result<(), TablesError> {
    let part_path = |i: usize| -> PathBuf {
        dir.join(Table::Summary.folder())
            .join(part_name(i, n).unwrap_or_default())
    };
    files.sort();
    for w in files.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(TablesError::NotOfCampaign {
                path: part_path(w[1].1),
                what: format!(
                    "{} is there and in {}: a file twice",
                    crate::escape_name(&w[0].0),
                    part_path(w[0].1).display()
                ),
            });
        }
    }
    for (k, (file, part)) in files.iter().enumerate() {
        if k % n != *part {
            return Err(TablesError::NotOfCampaign {
                path: part_path(*part),
                what: format!(
                    "{} is there, but the shard rule puts it in part {} of {n}",
                    crate::escape_name(file),
                    k % n
                ),
            });
        }
    }
    let names: Vec<&[u8]> = files.iter().map(|(f, _)| f.as_slice()).collect();
    let union = crate::list_blake3(&names);
    if union != list_blake3 {
        return Err(TablesError::NotOfCampaign {
            path: part_path(0),
            what: format!(
                "the parts hold {} files whose list (list_blake3 {}) is not the campaign's ({}): a file missing or one too many",
                files.len(),
                crate::short(&union),
                crate::short(list_blake3)
            ),
        });
    }
    Ok(())
}
