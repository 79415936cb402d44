//! Many diagrams: the files a batch reads (folders, patterns, lists,
//! shards; a file's identity, `canonical_key`, and its name in a table,
//! `shown`, which `campaign` re-exports) and the per-file loop, in
//! parallel, where one file's failure or panic is that file's error and
//! never the batch's.

use crate::diagram::{load_file_hashed, parse_file_hashed, parse_only};
use crate::error::{Error, Result};
use crate::session::{Session, within};
use crate::speed::resolve_rpm;
use enginedyn_ingest::{Cancel, Quantity};
use enginedyn_pipeline::Analysis;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The extensions (any case) of the files a folder gives: every kind the
/// reader reads (INTERFACE.md, `batch`).
pub const KINDS: [&str; 8] = ["csv", "txt", "dat", "tsv", "xlsx", "xls", "ods", "mf4"];

/// The most names a passed-over note lists.
const PASSED_OVER_SHOWN: usize = 5;

/// A file's name as a message line or table shows it: on one line.
pub fn one_line(s: &str) -> String {
    enginedyn_numerics::format::table_text(s).into_owned()
}

/// Files, folders (every file of the [`KINDS`] inside, sorted; a note
/// counts the files of other kinds passed over) and glob patterns, in the
/// order given; with the notes on what was passed over.
pub fn expand(inputs: &[String]) -> Result<(Vec<PathBuf>, Vec<String>)> {
    let mut files = Vec::new();
    let mut notes = Vec::new();
    for input in inputs {
        let p = Path::new(input);
        if p.is_dir() {
            let mut inside = Vec::new();
            let mut other = Vec::new();
            let entries = std::fs::read_dir(p)
                .map_err(|e| Error::usage(format!("{input}: cannot list: {e}")))?;
            for e in entries.flatten() {
                let f = e.path();
                let readable = f
                    .extension()
                    .and_then(|x| x.to_str())
                    .is_some_and(|x| KINDS.iter().any(|k| x.eq_ignore_ascii_case(k)));
                if readable {
                    inside.push(f);
                } else if !f.is_dir() {
                    other.push(e.file_name().to_string_lossy().into_owned());
                }
            }
            inside.sort();
            files.extend(inside);
            notes.extend(passed_over(input, other));
        } else if p.exists() {
            files.push(p.to_path_buf());
        } else if input.contains(['*', '?', '[']) {
            let matched: Vec<PathBuf> = glob::glob(input)
                .map_err(|e| Error::usage(format!("{input}: not a valid pattern: {e}")))?
                .filter_map(std::result::Result::ok)
                .collect();
            if matched.is_empty() {
                return Err(Error::usage(format!("{input}: no file matches")));
            }
            files.extend(matched);
        } else {
            // A missing file is that file's own error row, not the batch's.
            files.push(p.to_path_buf());
        }
    }
    Ok((files, notes))
}

/// The error for a batch with no file at all.
pub fn no_files() -> Error {
    Error::usage(format!(
        "no diagram files found (a folder gives its .{} files)",
        KINDS.join(", .")
    ))
}

/// The note on the files of other kinds a folder held: how many, and the
/// first few names; `None` when there were none.
fn passed_over(folder: &str, mut names: Vec<String>) -> Option<String> {
    if names.is_empty() {
        return None;
    }
    names.sort();
    let mut shown: Vec<String> = names
        .iter()
        .take(PASSED_OVER_SHOWN)
        .map(|n| one_line(n))
        .collect();
    if names.len() > PASSED_OVER_SHOWN {
        shown.push("…".to_string());
    }
    Some(format!(
        "{} passed over in {}: {} (a folder gives its .{} files)",
        if names.len() == 1 {
            "1 file of another kind".to_string()
        } else {
            format!("{} files of other kinds", names.len())
        },
        one_line(folder),
        shown.join(", "),
        KINDS.join(", .")
    ))
}

/// The run folder of the `i`-th diagram (from 0) of a batch: its number
/// from 1 in 4 digits, as index.html numbers its rows, then its file's stem
/// as a folder name every system holds (`numerics::format::folder_name`:
/// control characters and `<>:"/\|?*` become `_`).
pub fn run_folder(i: usize, file: &Path) -> String {
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "diagram".into());
    format!(
        "{:04}_{}",
        i + 1,
        enginedyn_numerics::format::folder_name(&stem)
    )
}

/// A batch file analysed: the analysis, and the diagram on the grid it
/// came from (with its per-cycle figures; `None` with a tolerance, which
/// puts the diagram on several grids).
#[derive(Debug)]
pub struct Analysed {
    /// The analysis.
    pub analysis: Analysis,
    /// The diagram on the grid.
    pub resampled: Option<enginedyn_ingest::Resampled>,
    /// The BLAKE3 of the diagram file's bytes, hashed as they were read.
    pub diagram_blake3: String,
}

/// What a batch does with each file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Work {
    /// Read it onto the grid and analyse it.
    Analyse,
    /// Read every cell and build every trace, compute nothing (the parse
    /// floor of the benchmark).
    ParseOnly,
}

/// Time after parsing, for one file: putting the traces on the grid, and
/// the analysis (with what the caller does with it).
#[derive(Debug, Clone, Copy, Default)]
pub struct Times {
    /// Putting the traces on the grid.
    pub grid: Duration,
    /// The analysis.
    pub analysis: Duration,
}

/// One file's outcome in a batch.
#[derive(Debug)]
pub struct Item<T> {
    /// Its index in the list (from 0).
    pub index: usize,
    /// The file.
    pub file: PathBuf,
    /// What the caller made of its analysis, or why it failed.
    pub result: Result<T>,
    /// Where its time went.
    pub times: Times,
}

impl Session {
    /// One batch file analysed (`None` for [`Work::ParseOnly`]): like
    /// `analyse` of one file, with the batch's shared tables; with a
    /// tolerance, the cheapest setting within it.
    pub fn analyse_item(
        &self,
        file: &Path,
        work: Work,
        times: &mut Times,
    ) -> Result<Option<Analysed>> {
        if work == Work::ParseOnly {
            parse_only(file, &self.parse)?;
            return Ok(None);
        }
        let engine = self.engine();
        let turning = || Error::data("a turning-moment file, not a pressure diagram");
        if let Some(t) = self.method.tolerance {
            let (d, diagram_blake3) = parse_file_hashed(file, &self.parse)?;
            if d.quantity != Quantity::Pressure {
                return Err(turning());
            }
            let speed = resolve_rpm(self.reader.rpm, d.rpm, engine)?;
            let (mut an, choice) = within(
                engine,
                &[(file.display().to_string(), d)],
                &self.grid,
                speed.rpm,
                t,
                &self.method.kept(),
            )?;
            an.summary.estimated_relative_error = Some(choice.estimated);
            an.summary.notes.extend(choice.notes);
            an.summary.notes.extend(speed.note);
            return Ok(Some(Analysed {
                analysis: an,
                resampled: None,
                diagram_blake3,
            }));
        }
        let (resampled, diagram_blake3) =
            load_file_hashed(file, &self.parse, &self.grid, &mut times.grid)?;
        let started = Instant::now();
        if resampled.quantity != Quantity::Pressure {
            return Err(turning());
        }
        let speed = resolve_rpm(self.reader.rpm, resampled.rpm, engine)?;
        let mut an = enginedyn_pipeline::analyse_with(
            self.tables(),
            engine,
            &resampled,
            speed.rpm,
            &self.opts,
        )?;
        an.summary.notes.extend(speed.note);
        times.analysis += started.elapsed();
        Ok(Some(Analysed {
            analysis: an,
            // Freed here unless a campaign's tables want it.
            resampled: self.keep_grid.then_some(resampled),
            diagram_blake3,
        }))
    }

    /// Every file of `files` on `jobs` threads (0: one per core): each
    /// analysed ([`Session::analyse_item`]), then handed to `each` with its
    /// index; `done` sees every item as it ends (a progress bar). A panic in
    /// a file's work (a bug) becomes its error, and the others finish.
    pub fn batch<T: Send>(
        &self,
        files: &[PathBuf],
        jobs: usize,
        work: Work,
        each: impl Fn(usize, &Path, Option<Analysed>, &mut Times) -> Result<T> + Sync,
        done: impl Fn(&Item<T>) + Sync,
    ) -> Result<Vec<Item<T>>> {
        self.batch_cancellable(files, jobs, work, each, done, &Cancel::default())
    }

    /// [`Session::batch`], stopped by `cancel`: once it is set, the files
    /// not yet begun are neither read nor listed (the items stop short).
    pub fn batch_cancellable<T: Send>(
        &self,
        files: &[PathBuf],
        jobs: usize,
        work: Work,
        each: impl Fn(usize, &Path, Option<Analysed>, &mut Times) -> Result<T> + Sync,
        done: impl Fn(&Item<T>) + Sync,
        cancel: &Cancel,
    ) -> Result<Vec<Item<T>>> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(jobs)
            .build()
            .map_err(|e| Error::usage(format!("--jobs {jobs}: {e}")))?;
        // A file's hash goes to a thread of its own only while a core is
        // idle: each worker counts the others as busy.
        let workers = pool.current_num_threads().min(files.len().max(1));
        let _others = crate::hashing::reading(workers - 1);
        Ok(pool.install(|| {
            files
                .par_iter()
                .enumerate()
                .map(|(index, f)| {
                    // Cancelled: no more items, the batch stops here.
                    if cancel.is_cancelled() {
                        return None;
                    }
                    let mut times = Times::default();
                    let result = guarded(|| {
                        let an = self.analyse_item(f, work, &mut times)?;
                        each(index, f, an, &mut times)
                    });
                    let item = Item {
                        index,
                        file: f.clone(),
                        result,
                        times,
                    };
                    done(&item);
                    Some(item)
                })
                .while_some()
                .collect()
        }))
    }
}

/// Runs `work`; a panic in it (a bug) becomes an error that says so.
pub fn guarded<T>(work: impl FnOnce() -> Result<T>) -> Result<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)).unwrap_or_else(|panic| {
        let why = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(Error::data(format!(
            "internal error while analysing this file ({}): a bug in enginedyn, please report it with the file",
            enginedyn_numerics::format::quote(&why)
        )))
    })
}

/// A file's identity in a campaign: its canonical path's bytes (links and
/// `.`/`..` resolved), else, for a file that cannot be resolved (missing),
/// its absolute path. `a.csv`, `./a.csv` and `/abs/a.csv` are one file.
pub fn canonical_key(p: &Path) -> Vec<u8> {
    let c = std::fs::canonicalize(p)
        .or_else(|_| std::path::absolute(p))
        .unwrap_or_else(|_| p.to_path_buf());
    c.into_os_string().into_encoded_bytes()
}

/// A path as a table's `file` column holds it: the path as given, a name
/// that is not UTF-8 escaped as `\xNN` without loss.
pub fn shown(p: &Path) -> String {
    enginedyn_tables::escape_name(p.as_os_str().as_encoded_bytes())
}

/// The most shards of a campaign (INTERFACE.md, "Campaigns").
pub const MAX_SHARDS: usize = 100_000;

/// One slice of a campaign: the `index`-th of `count` (from 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which slice (0 ≤ index < count).
    pub index: usize,
    /// How many slices.
    pub count: usize,
}

impl Shard {
    /// The whole list as one shard (part 0 of 1).
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// A shard, checked: 0 ≤ index < count ≤ 100,000.
    pub fn new(index: usize, count: usize) -> std::result::Result<Self, String> {
        if count == 0 || count > MAX_SHARDS || index >= count {
            return Err(format!(
                "{index}/{count}: a shard is I/N with 0 ≤ I < N ≤ {MAX_SHARDS}"
            ));
        }
        Ok(Self { index, count })
    }

    /// Reads `I/N`.
    pub fn read(s: &str) -> std::result::Result<Self, String> {
        let bad = || {
            format!(
                "`{}`: a shard is I/N with 0 ≤ I < N ≤ {MAX_SHARDS} (e.g. 3/16)",
                enginedyn_numerics::format::quote(s)
            )
        };
        let (i, n) = s.trim().split_once('/').ok_or_else(bad)?;
        let i: usize = i.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        Self::new(i, n).map_err(|_| bad())
    }

    /// This shard's files of `files`: the files sorted bytewise by their
    /// identity ([`canonical_key`]), file k going to
    /// shard k mod N, so that every shard of one list sees the same order
    /// and the N shards together hold each file once.
    pub fn take(&self, files: &[PathBuf]) -> Vec<PathBuf> {
        let keyed: Vec<(Vec<u8>, PathBuf)> = files
            .iter()
            .map(|p| (canonical_key(p), p.clone()))
            .collect();
        self.take_keyed(&keyed)
    }

    /// [`Shard::take`] of files whose identities are known; a file named
    /// twice is taken once (as first named).
    pub fn take_keyed(&self, files: &[(Vec<u8>, PathBuf)]) -> Vec<PathBuf> {
        shard_order(files)
            .into_iter()
            .enumerate()
            .filter(|(k, _)| k % self.count == self.index)
            .map(|(_, (_, p))| p.clone())
            .collect()
    }

    /// Every shard of `count` at once ([`Shard::take_keyed`] of each),
    /// the list sorted once.
    pub fn split_keyed(files: &[(Vec<u8>, PathBuf)], count: usize) -> Vec<Vec<PathBuf>> {
        let mut parts = vec![Vec::new(); count.max(1)];
        for (k, (_, p)) in shard_order(files).into_iter().enumerate() {
            parts[k % count.max(1)].push(p.clone());
        }
        parts
    }
}

/// The shard rule's order: by identity, bytewise, each file once (of one
/// file's names, the first given; the sort is stable).
pub fn shard_order(files: &[(Vec<u8>, PathBuf)]) -> Vec<&(Vec<u8>, PathBuf)> {
    let mut sorted: Vec<&(Vec<u8>, PathBuf)> = files.iter().collect();
    sorted.sort_by(|a, b| a.0.cmp(&b.0));
    sorted.dedup_by(|a, b| a.0 == b.0);
    sorted
}

/// A batch's files: this shard's, and the identity of every file of the
/// whole list (a campaign's `list_blake3`).
#[derive(Debug, Clone)]
pub struct Listed {
    /// The files this run analyses (this shard's), each once.
    pub files: Vec<PathBuf>,
    /// Every file of the list (all shards), by identity.
    pub keys: Vec<Vec<u8>>,
    /// What was passed over or named twice.
    pub notes: Vec<String>,
}

/// The files of `diagrams` (files, folders, patterns) and of the list
/// `files_from`, then `shard`'s slice. A campaign's list (`campaign`:
/// `--files-from`, `--shard` or `--parquet`) holds each file once by its
/// canonical path; a plain batch runs what it is given, a file named
/// twice twice (each its own run folder).
pub fn listed(
    diagrams: &[String],
    files_from: Option<&Path>,
    shard: Option<Shard>,
    campaign: bool,
) -> Result<Listed> {
    let (mut files, mut notes) = expand(diagrams)?;
    if let Some(list) = files_from {
        files.extend(self::files_from(list)?);
    }
    if files.is_empty() {
        return Err(no_files());
    }
    if !(campaign || files_from.is_some() || shard.is_some()) {
        return Ok(Listed {
            files,
            keys: Vec::new(),
            notes,
        });
    }
    let (keyed, twice) = unique(files);
    notes.extend(twice);
    let files = match shard {
        Some(s) => s.take_keyed(&keyed),
        None => keyed.iter().map(|(_, p)| p.clone()).collect(),
    };
    Ok(Listed {
        files,
        keys: keyed.into_iter().map(|(k, _)| k).collect(),
        notes,
    })
}

/// The most groups of one file named twice a note lists.
const DUPLICATES_SHOWN: usize = 5;

/// A campaign's list: each file once by its identity
/// ([`canonical_key`]), in the order first named, with
/// a note naming the files named more than once.
pub fn unique(files: Vec<PathBuf>) -> (Vec<(Vec<u8>, PathBuf)>, Option<String>) {
    let mut seen: std::collections::HashMap<Vec<u8>, usize> = std::collections::HashMap::new();
    let mut out: Vec<(Vec<u8>, PathBuf)> = Vec::with_capacity(files.len());
    let mut again: Vec<Vec<PathBuf>> = Vec::new();
    let mut group_of: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    for p in files {
        let key = canonical_key(&p);
        match seen.get(&key) {
            Some(&k) => {
                let g = *group_of.entry(k).or_insert_with(|| {
                    again.push(vec![out[k].1.clone()]);
                    again.len() - 1
                });
                again[g].push(p);
            }
            None => {
                seen.insert(key.clone(), out.len());
                out.push((key, p));
            }
        }
    }
    if again.is_empty() {
        return (out, None);
    }
    let name = |p: &PathBuf| one_line(&shown(p));
    let mut groups: Vec<String> = again
        .iter()
        .take(DUPLICATES_SHOWN)
        .map(|g| {
            format!(
                "{} as {}",
                name(&g[0]),
                g[1..].iter().map(name).collect::<Vec<_>>().join(", ")
            )
        })
        .collect();
    if again.len() > DUPLICATES_SHOWN {
        groups.push(format!("and {} more", again.len() - DUPLICATES_SHOWN));
    }
    let n = again.len();
    let note = format!(
        "{} named more than once, analysed once by {} canonical path: {}",
        if n == 1 {
            "1 file".to_string()
        } else {
            format!("{n} files")
        },
        if n == 1 { "its" } else { "their" },
        groups.join("; ")
    );
    (out, Some(note))
}

/// The most paths a list names (INTERFACE.md, "Limits": a campaign's list).
pub const MAX_LISTED: usize = 10_000_000;

/// The diagram paths a list file names, one a line: a line loses only
/// its line end (`\n` or `\r\n`; a leading space is part of the name),
/// blank lines and `#` lines are skipped, a relative path is taken
/// relative to the list's folder, and a name that is not UTF-8 is kept as
/// its bytes.
pub fn files_from(list: &Path) -> Result<Vec<PathBuf>> {
    let shown = list.display();
    let file = crate::diagram::open_diagram(list)
        .map_err(|e| Error::usage(format!("--files-from: {}", e.message)).in_file(&shown))?;
    let base = list.parent().unwrap_or(Path::new("."));
    let mut files = Vec::new();
    use std::io::BufRead;
    let mut reader = std::io::BufReader::new(file);
    let mut line = Vec::new();
    for k in 1.. {
        line.clear();
        let n = reader.read_until(b'\n', &mut line).map_err(|e| {
            Error::usage(format!("--files-from: line {k}: cannot read: {e}")).in_file(&shown)
        })?;
        if n == 0 {
            break;
        }
        let mut t: &[u8] = &line;
        t = t.strip_suffix(b"\n").unwrap_or(t);
        t = t.strip_suffix(b"\r").unwrap_or(t);
        if t.iter().all(u8::is_ascii_whitespace) || t.starts_with(b"#") {
            continue;
        }
        if files.len() == MAX_LISTED {
            return Err(Error::usage(format!(
                "--files-from: more than {MAX_LISTED} paths: split the list into several campaigns"
            ))
            .in_file(&shown));
        }
        let p = path_of(t);
        files.push(if p.is_relative() { base.join(&p) } else { p });
    }
    Ok(files)
}

/// A path from a list's bytes, kept as they are.
#[cfg(unix)]
fn path_of(bytes: &[u8]) -> PathBuf {
    use std::os::unix::ffi::OsStrExt;
    PathBuf::from(std::ffi::OsStr::from_bytes(bytes))
}

/// A path from a list's bytes (UTF-8 on this system).
#[cfg(not(unix))]
fn path_of(bytes: &[u8]) -> PathBuf {
    PathBuf::from(String::from_utf8_lossy(bytes).into_owned())
}
