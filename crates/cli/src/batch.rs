//! `enginedyn batch` (many diagrams in parallel) and `enginedyn sweep` (one
//! diagram over a range of speeds).

use crate::Failure;
use crate::args::{BatchArgs, SweepArgs};
use crate::run::{
    check_step, diagram_options, load_diagram, load_diagram_timed, load_engine, parse_diagram,
    resolve_rpm, within,
};
use enginedyn_ingest::Quantity;
use rayon::prelude::*;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// The extensions (any case) of the files a folder gives: every kind the
/// reader reads (INTERFACE.md, `batch`).
pub const KINDS: [&str; 8] = ["csv", "txt", "dat", "tsv", "xlsx", "xls", "ods", "mf4"];

/// The most names a passed-over note lists.
const PASSED_OVER_SHOWN: usize = 5;

/// Files, folders (every file of the [`KINDS`] inside, sorted; a note
/// counts the files of other kinds passed over) and glob patterns, in the
/// order given.
fn expand(inputs: &[String]) -> Result<Vec<PathBuf>, Failure> {
    let mut files = Vec::new();
    for input in inputs {
        let p = Path::new(input);
        if p.is_dir() {
            let mut inside = Vec::new();
            let mut other = Vec::new();
            let entries = std::fs::read_dir(p)
                .map_err(|e| Failure::usage(format!("{input}: cannot list: {e}")))?;
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
            if let Some(note) = passed_over(input, other) {
                crate::say(None, &note);
            }
        } else if p.exists() {
            files.push(p.to_path_buf());
        } else if input.contains(['*', '?', '[']) {
            let matched: Vec<PathBuf> = glob::glob(input)
                .map_err(|e| Failure::usage(format!("{input}: not a valid pattern: {e}")))?
                .filter_map(Result::ok)
                .collect();
            if matched.is_empty() {
                return Err(Failure::usage(format!("{input}: no file matches")));
            }
            files.extend(matched);
        } else {
            // A missing file is that file's own error row, not the batch's.
            files.push(p.to_path_buf());
        }
    }
    if files.is_empty() {
        return Err(Failure::usage(format!(
            "no diagram files found (a folder gives its .{} files)",
            KINDS.join(", .")
        )));
    }
    Ok(files)
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
fn run_folder(i: usize, file: &Path) -> String {
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

/// A file's name as a message line or table shows it: on one line.
fn one_line(s: &str) -> String {
    enginedyn_numerics::format::table_text(s).into_owned()
}

/// One diagram's outcome.
struct Row {
    file: String,
    error: String,
    cells: Vec<(String, String)>,
    /// Key figures for the tables, one per `report::KEY_FIGURES` column.
    key: Option<Vec<Option<f64>>>,
    folder: Option<String>,
    /// With `--json`: its `summary.json` object, on one line.
    json: Option<String>,
}

/// A batch row as `--json` prints it: `file`, `error` (null when it ran),
/// then its `summary.json` keys when it ran.
fn json_row(file: &str, error: &str, summary: Option<serde_json::Value>) -> String {
    let mut o = serde_json::Map::new();
    o.insert("file".into(), file.into());
    o.insert(
        "error".into(),
        if error.is_empty() {
            serde_json::Value::Null
        } else {
            error.into()
        },
    );
    if let Some(serde_json::Value::Object(m)) = summary {
        o.extend(m);
    }
    serde_json::to_string(&serde_json::Value::Object(o)).unwrap_or_default()
}

/// A JSON array of objects already written as text, one a line.
fn json_array<'a>(objects: impl Iterator<Item = &'a str>) -> String {
    let mut s = String::from("[");
    for (k, o) in objects.enumerate() {
        s.push_str(if k == 0 { "\n" } else { ",\n" });
        s.push_str(o);
    }
    s.push_str("\n]\n");
    s
}

pub fn run(a: &BatchArgs) -> Result<(), Failure> {
    if let Some(t) = a.tolerance
        && !(1e-6..=0.5).contains(&t)
    {
        return Err(Failure::usage(format!(
            "--tolerance {t}: a relative error between 1e-6 and 0.5 is needed"
        )));
    }
    let loaded = load_engine(Some(&a.engine))?;
    let engine = &loaded.engine;
    let step = a.method.step();
    check_step(engine, step)?;
    let opts = enginedyn_pipeline::Options {
        // Without --detail only summary.csv is written: skip the report curves.
        scope: if a.detail {
            enginedyn_pipeline::Scope::Full
        } else {
            enginedyn_pipeline::Scope::Summary
        },
        ..a.method.options()
    };
    let (parse, grid) = diagram_options(engine, &a.diagram_args, step, opts.interp, None)?;
    // The motion and volume law on the grid, built once for every file.
    let n = (engine.cycle().to_degrees() / step).round() as usize;
    let tables = enginedyn_pipeline::Tables::new(engine, n, &opts).ok();
    let files = expand(&a.diagrams)?;
    // What each summary came from (`inputs`): the engine hashed once, each
    // diagram as it is analysed; only when a summary.json is written.
    let engine_inputs = if a.detail || a.json {
        Some(crate::inputs::of(&loaded, &[])?)
    } else {
        None
    };
    // The output folder, locked for the whole batch (a second batch into
    // it waits or exits 2), cleaned of what a killed run left; every name
    // the batch will write (summary.csv, index.html, each run folder)
    // checked before the first is written: something in the way is exit 2.
    let folders: Vec<String> = if a.detail {
        files
            .iter()
            .enumerate()
            .map(|(i, f)| run_folder(i, f))
            .collect()
    } else {
        Vec::new()
    };
    let names: &[&str] = if a.detail {
        &["summary.csv", "index.html"]
    } else {
        &["summary.csv"]
    };
    let out_dir = a
        .out
        .as_deref()
        .map(|d| {
            enginedyn_report::OutDir::open_for(d, names, &folders).map(|o| o.for_command("batch"))
        })
        .transpose()?;
    let jobs = a.jobs.unwrap_or(0) as usize;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| Failure::usage(format!("--jobs {jobs}: {e}")))?;
    let bar = if std::io::stderr().is_terminal() {
        let b = indicatif::ProgressBar::new(files.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} diagrams  {elapsed} ({eta} left)",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let started = Instant::now();
    // Time after parsing, every file and thread: putting the traces on the
    // grid, and the analysis with its summary row.
    let grid_ns = AtomicU64::new(0);
    let analysis_ns = AtomicU64::new(0);
    let rows: Vec<Row> = pool.install(|| {
        files
            .par_iter()
            .enumerate()
            .map(|(i, f)| {
                let shown = f.display().to_string();
                let (mut on_grid, mut analysis) = (Duration::ZERO, Duration::ZERO);
                // One item never takes the batch down: a panic in it (a
                // bug) becomes its error row, and the others finish.
                let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| -> Result<Row, Failure> {
                    if a.parse_only {
                        parse_only(f, &parse)?;
                        return Ok(Row {
                            file: shown.clone(),
                            error: String::new(),
                            cells: Vec::new(),
                            key: None,
                            folder: None,
                            json: None,
                        });
                    }
                    let an = match a.tolerance {
                        Some(t) => {
                            let d = parse_diagram(f, &parse)?;
                            if d.quantity != Quantity::Pressure {
                                return Err(Failure::data(
                                    "a turning-moment file, not a pressure diagram",
                                ));
                            }
                            let speed = resolve_rpm(None, d.rpm, engine)?;
                            let (mut an, choice) = within(
                                engine,
                                &[(shown.clone(), d)],
                                &grid,
                                speed.rpm,
                                t,
                                &a.method.kept(),
                            )?;
                            an.summary.estimated_relative_error = Some(choice.estimated);
                            an.summary.notes.extend(choice.notes);
                            an.summary.notes.extend(speed.note);
                            an
                        }
                        None => {
                            let resampled =
                                load_diagram_timed(Some(f), &parse, &grid, &mut on_grid)?;
                            let analysed = Instant::now();
                            if resampled.quantity != Quantity::Pressure {
                                return Err(Failure::data(
                                    "a turning-moment file, not a pressure diagram",
                                ));
                            }
                            let speed = resolve_rpm(None, resampled.rpm, engine)?;
                            let mut an = enginedyn_pipeline::analyse_with(
                                tables.as_ref(),
                                engine,
                                &resampled,
                                speed.rpm,
                                &opts,
                            )
?;
                            an.summary.notes.extend(speed.note);
                            analysis += analysed.elapsed();
                            an
                        }
                    };
                    let s = &an.summary;
                    let inputs = engine_inputs
                        .as_ref()
                        .map(|e| e.with_diagrams(&[enginedyn_report::Source::File(f)]))
                        .transpose()?;
                    let mut folder = None;
                    if let Some(dir) = &out_dir
                        && let Some(name) = folders.get(i)
                        && let Some(inputs) = &inputs
                    {
                        let name = name.clone();
                        let files = enginedyn_report::run_files(engine, &an, a.angles == crate::args::Angles::Centered, inputs)
                            .map_err(|e| Failure::data(e.to_string()))?;
                        dir.write_folder(&name, &files)?;
                        folder = Some(name);
                    }
                    let json = match &inputs {
                        Some(inputs) if a.json => Some(json_row(
                            &shown,
                            "",
                            Some(enginedyn_report::summary_json(s, inputs)),
                        )),
                        _ => None,
                    };
                    if !s.notes.is_empty() {
                        bar.suspend(|| {
                            for n in &s.notes {
                                crate::say(Some(&one_line(&shown)), n);
                            }
                        });
                    }
                    let flattened = Instant::now();
                    let cells = enginedyn_report::flatten(s);
                    analysis += flattened.elapsed();
                    Ok(Row {
                        file: shown.clone(),
                        error: String::new(),
                        cells,
                        key: Some(enginedyn_report::key_figures(
                            &enginedyn_report::KEY_FIGURES,
                            s,
                        )),
                        folder,
                        json,
                    })
                }))
                .unwrap_or_else(|panic| {
                    let why = panic
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| panic.downcast_ref::<String>().cloned())
                        .unwrap_or_default();
                    Err(Failure::data(format!(
                        "internal error while analysing this file ({}): a bug in enginedyn, please report it with the file",
                        crate::quote(&why)
                    )))
                });
                bar.inc(1);
                grid_ns.fetch_add(on_grid.as_nanos() as u64, Ordering::Relaxed);
                analysis_ns.fetch_add(analysis.as_nanos() as u64, Ordering::Relaxed);
                result.unwrap_or_else(|e| {
                    // The row names the file: the message alone.
                    let msg = e.message;
                    bar.suspend(|| eprintln!("error: {}: {msg}", one_line(&shown)));
                    Row {
                        json: a.json.then(|| json_row(&shown, &msg, None)),
                        file: shown,
                        error: msg,
                        cells: Vec::new(),
                        key: None,
                        folder: None,
                    }
                })
            })
            .collect()
    });
    bar.finish_and_clear();
    if a.stage_times {
        let secs = |ns: AtomicU64| Duration::from_nanos(ns.into_inner()).as_secs_f64();
        eprintln!(
            "stage times over {} diagrams: grid {:.6} s, analysis {:.6} s",
            rows.len(),
            secs(grid_ns),
            secs(analysis_ns)
        );
    }
    let failed = rows.iter().filter(|r| !r.error.is_empty()).count();
    let table: Vec<enginedyn_report::CsvRow> = rows
        .iter()
        .map(|r| (r.file.clone(), r.error.clone(), r.cells.clone()))
        .collect();
    let csv = enginedyn_report::summary_csv(&table);
    let eta = engine.operating().mechanical_efficiency;
    let key_rows: Vec<enginedyn_report::KeyRow> = rows
        .iter()
        .map(|r| enginedyn_report::KeyRow {
            name: r.file.clone(),
            figures: r.key.clone(),
            error: r.error.clone(),
            folder: r.folder.clone(),
        })
        .collect();
    // `--json`: the summary.json objects, each with `file` and `error`.
    let json = a.json.then(|| {
        let each: Vec<String> = rows
            .iter()
            .map(|r| {
                r.json
                    .clone()
                    .unwrap_or_else(|| json_row(&r.file, &r.error, None))
            })
            .collect();
        json_array(each.iter().map(String::as_str))
    });
    match &out_dir {
        Some(dir) => {
            let mut out = vec![("summary.csv".to_string(), csv.into_bytes())];
            if a.detail {
                out.push((
                    "index.html".to_string(),
                    enginedyn_report::index_html(engine.name(), &key_rows, eta).into_bytes(),
                ));
            }
            for note in dir.write(&out)? {
                crate::say(None, &note);
            }
            eprintln!(
                "{} ({} failed) in {:.2} s; wrote {}",
                enginedyn_report::count(rows.len(), "diagram"),
                failed,
                started.elapsed().as_secs_f64(),
                dir.path().join("summary.csv").display()
            );
            if let Some(json) = &json {
                crate::emit(json);
            }
        }
        None if a.json => crate::emit(&json.unwrap_or_default()),
        None if a.csv || a.parse_only => crate::emit(&csv),
        None => {
            let mut text = crate::table::heading(
                engine,
                "batch, ",
                f64::NAN,
                &enginedyn_report::count(rows.len(), "diagram"),
            );
            text.push('\n');
            text.push_str(&enginedyn_report::key_table(
                "diagram",
                &enginedyn_report::KEY_FIGURES,
                &key_rows,
                eta,
            ));
            crate::emit(&text);
        }
    }
    if failed > 0 {
        return Err(Failure::data(format!(
            "{failed} of {} diagrams failed (their rows say why)",
            rows.len()
        )));
    }
    Ok(())
}

/// The parse floor of the benchmark: every cell read and checked, each
/// cycle's trace built and dropped, nothing put on the grid or computed.
fn parse_only(f: &Path, parse: &enginedyn_ingest::ParseOptions) -> Result<(), Failure> {
    let file = crate::run::open_diagram(f)?;
    enginedyn_ingest::parse_stream(
        std::io::BufReader::with_capacity(1 << 12, file),
        parse,
        |_| Ok(()),
    )
    .map_err(|e| Failure::from(e).in_file(f.display()))?;
    Ok(())
}

/// The most speeds one sweep computes (INTERFACE.md, "Limits").
pub const MAX_SPEEDS: usize = 10_000;

/// Parses FROM:TO:STEP; TO is included when it falls on the step.
pub(crate) fn speeds(spec: &str) -> Result<Vec<f64>, Failure> {
    let bad = || {
        Failure::usage(format!(
            "--rpm {spec}: expected FROM:TO:STEP with 0 < FROM <= TO <= {} rpm and STEP > 0",
            crate::run::MAX_RPM
        ))
    };
    let parts: Vec<f64> = spec
        .split(':')
        .map(|x| enginedyn_ingest::read_number(x, false))
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    let [from, to, step] = parts[..] else {
        return Err(bad());
    };
    if !(from > 0.0 && to >= from && step > 0.0 && to <= crate::run::MAX_RPM) {
        return Err(bad());
    }
    let n = ((to - from) / step + 1e-9).floor();
    if n + 1.0 > MAX_SPEEDS as f64 {
        return Err(Failure::usage(format!(
            "--rpm {spec}: {} speeds; a sweep computes at most {MAX_SPEEDS}",
            n + 1.0
        )));
    }
    Ok((0..=n as usize).map(|k| from + k as f64 * step).collect())
}

/// What `sweep --out DIR` writes.
const SWEEP_FILES: [&str; 2] = ["sweep.csv", "sweep.svg"];

pub fn sweep(a: &SweepArgs) -> Result<(), Failure> {
    let loaded = load_engine(Some(&a.engine))?;
    let engine = &loaded.engine;
    // Something in the way of an output is refused before the sweep runs.
    let out = crate::open_out(a.out.as_deref(), &SWEEP_FILES, "sweep")?;
    let step = a.method.step();
    check_step(engine, step)?;
    let rpms = speeds(&a.rpm)?;
    let opts = enginedyn_pipeline::Options {
        // sweep.csv and sweep.svg need the summary figures only.
        scope: enginedyn_pipeline::Scope::Summary,
        ..a.method.options()
    };
    let (parse, grid) = diagram_options(engine, &a.diagram_args, step, opts.interp, None)?;
    let path = crate::run::diagram_path(a.diagram.as_deref(), &loaded)?;
    let resampled = load_diagram(Some(&path), &parse, &grid)?;
    let shown = path.display().to_string();
    let tables = enginedyn_pipeline::Tables::new(engine, resampled.pressure.len(), &opts).ok();
    let analyse = |rpm: f64| {
        enginedyn_pipeline::analyse_with(tables.as_ref(), engine, &resampled, rpm, &opts)
            .map_err(|e| Failure::usage(e.to_string()))
    };
    // One flywheel for the whole sweep: sized at the engine file's speed
    // (else the diagram's), the same part on every row.
    let (sized_at, source) = match (engine.operating().rpm, resampled.rpm) {
        (Some(r), _) => (r, "the engine file's operating.rpm"),
        (None, Some(r)) => (r, "the diagram's `# rpm` line"),
        (None, None) => (
            rpms[rpms.len() / 2],
            "the middle of the sweep (no speed in the engine file or diagram)",
        ),
    };
    // The pressures stay the same at every speed: gas load fixed, inertia growing with w^2.
    let mut results: Vec<enginedyn_pipeline::Analysis> = rpms
        .par_iter()
        .map(|&rpm| analyse(rpm))
        .collect::<Result<_, _>>()?;
    // The sizing speed's own run when it is one of the sweep's.
    let part = match results
        .iter()
        .find(|an| an.summary.rpm.to_bits() == sized_at.to_bits())
    {
        Some(an) => an.flywheel.clone(),
        None => analyse(sized_at)?.flywheel,
    };
    let file_rpm = engine.operating().rpm;
    for an in &mut results {
        if let Some(part) = &part {
            enginedyn_pipeline::with_flywheel(an, part);
        }
        let rpm = an.summary.rpm;
        let notes = &mut an.summary.notes;
        if file_rpm.is_none_or(|f| f.to_bits() != rpm.to_bits()) {
            notes.push(format!(
                "speed {} rpm from --rpm {}{}",
                crate::human(rpm),
                a.rpm,
                file_rpm.map_or(
                    " (the engine file gives no operating.rpm)".to_string(),
                    |f| {
                        format!(
                            ", not the engine file's operating.rpm = {} rpm",
                            crate::human(f)
                        )
                    }
                )
            ));
        }
        if part.is_some() {
            notes.push(format!(
                "flywheel sized once at {} rpm ({source}): the same part at every speed; speed_fluctuation_achieved is the δ it gives here",
                crate::human(sized_at)
            ));
        }
    }
    let table: Vec<enginedyn_report::CsvRow> = results
        .iter()
        .map(|an| {
            (
                shown.clone(),
                String::new(),
                enginedyn_report::flatten(&an.summary),
            )
        })
        .collect();
    let csv = enginedyn_report::summary_csv(&table);
    // `--json`: the per-speed summary.json objects.
    let json = if a.json {
        let inputs = crate::inputs::of(&loaded, &[Some(&path)])?;
        let each: Vec<String> = results
            .iter()
            .map(|an| {
                serde_json::to_string(&enginedyn_report::summary_json(&an.summary, &inputs))
                    .unwrap_or_default()
            })
            .collect();
        Some(json_array(each.iter().map(String::as_str)))
    } else {
        None
    };
    match &out {
        Some(dir) => {
            let summaries: Vec<&enginedyn_pipeline::Summary> =
                results.iter().map(|an| &an.summary).collect();
            let fig = enginedyn_report::sweep_figure(engine.name(), &summaries);
            let svg = fig.render().map_err(|e| Failure::data(e.to_string()))?;
            let [table, chart] = SWEEP_FILES.map(String::from);
            for note in dir.write(&[(table, csv.into_bytes()), (chart, svg.into_bytes())])? {
                crate::say(None, &note);
            }
            eprintln!(
                "{} speeds; wrote sweep.csv and sweep.svg to {}",
                rpms.len(),
                dir.path().display()
            );
            if let Some(json) = &json {
                crate::emit(json);
            }
        }
        None if a.json => crate::emit(&json.unwrap_or_default()),
        None if a.csv => crate::emit(&csv),
        None => {
            let rows: Vec<enginedyn_report::KeyRow> = results
                .iter()
                .map(|an| enginedyn_report::KeyRow {
                    name: crate::human(an.summary.rpm),
                    figures: Some(enginedyn_report::key_figures(
                        &enginedyn_report::SWEEP_FIGURES,
                        &an.summary,
                    )),
                    error: String::new(),
                    folder: None,
                })
                .collect();
            let mut text = crate::table::heading(engine, "sweep, ", f64::NAN, &shown);
            if part.is_some() {
                text.push_str(&format!(
                    "flywheel sized once at {} rpm ({source}); δ is what it gives at each speed\n",
                    crate::human(sized_at)
                ));
            }
            text.push('\n');
            text.push_str(&enginedyn_report::key_table(
                "rpm",
                &enginedyn_report::SWEEP_FIGURES,
                &rows,
                engine.operating().mechanical_efficiency,
            ));
            crate::emit(&text);
        }
    }
    Ok(())
}
