//! Many diagrams: the files a batch reads (folders, patterns, lists,
//! shards) and the per-file loop, in parallel, where one file's failure
//! or panic is that file's error and never the batch's.

use crate::diagram::{Input, load_diagram_timed, parse_diagram, parse_only};
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
            let d = parse_diagram(Input::File(file), &self.parse)?;
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
            }));
        }
        let resampled =
            load_diagram_timed(Input::File(file), &self.parse, &self.grid, &mut times.grid)?;
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

    /// This shard's files of `files`: the paths sorted bytewise, path k
    /// going to shard k mod N, so that every shard of one list sees the
    /// same order and the N shards together hold each file once.
    pub fn take(&self, files: &[PathBuf]) -> Vec<PathBuf> {
        let mut sorted: Vec<&PathBuf> = files.iter().collect();
        sorted.sort_by(|a, b| {
            a.as_os_str()
                .as_encoded_bytes()
                .cmp(b.as_os_str().as_encoded_bytes())
        });
        sorted
            .into_iter()
            .enumerate()
            .filter(|(k, _)| k % self.count == self.index)
            .map(|(_, p)| p.clone())
            .collect()
    }
}

/// The most paths a list names (INTERFACE.md, "Limits": a campaign's list).
pub const MAX_LISTED: usize = 10_000_000;

/// The diagram paths a list file names, one a line: blank lines and `#`
/// lines skipped, a relative path taken relative to the list's folder.
pub fn files_from(list: &Path) -> Result<Vec<PathBuf>> {
    let shown = list.display();
    let file = crate::diagram::open_diagram(list)
        .map_err(|e| Error::usage(format!("--files-from: {}", e.message)).in_file(&shown))?;
    let base = list.parent().unwrap_or(Path::new("."));
    let mut files = Vec::new();
    use std::io::BufRead;
    for (k, line) in std::io::BufReader::new(file).lines().enumerate() {
        let line = line.map_err(|e| {
            Error::usage(format!("--files-from: line {}: cannot read: {e}", k + 1)).in_file(&shown)
        })?;
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        if files.len() == MAX_LISTED {
            return Err(Error::usage(format!(
                "--files-from: more than {MAX_LISTED} paths: split the list into several campaigns"
            ))
            .in_file(&shown));
        }
        let p = Path::new(t);
        files.push(if p.is_relative() {
            base.join(p)
        } else {
            p.to_path_buf()
        });
    }
    Ok(files)
}
