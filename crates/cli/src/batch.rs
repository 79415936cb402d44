//! `enginedyn batch` (many diagrams in parallel) and `enginedyn sweep` (one
//! diagram over a range of speeds).

use crate::Failure;
use crate::args::{BatchArgs, SweepArgs};
use enginedyn_session::batch::{one_line, run_folder};
use enginedyn_session::{Loaded, Session, Work};
use std::io::IsTerminal;
use std::time::Instant;

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
    /// With `--parquet`: its rows of the campaign's tables.
    campaign: Option<enginedyn_session::campaign::Row>,
    /// Its notes, said at the end grouped by kind with the others'.
    notes: Vec<String>,
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

/// The session a batch's options make.
fn session_of(a: &BatchArgs) -> Result<Session, Failure> {
    if let Some(t) = a.tolerance {
        enginedyn_session::options::check_tolerance(t, "--tolerance")?;
    }
    let mut session = Session::new(
        Loaded::from_file(&a.engine)?,
        a.diagram_args.reader(None),
        a.method.method(a.tolerance),
        // Without --detail only summary.csv is written: skip the report curves.
        if a.detail {
            enginedyn_pipeline::Scope::Full
        } else {
            enginedyn_pipeline::Scope::Summary
        },
    )?;
    // The cycles and traces tables need each file's grid; else it is freed.
    session.keep_grid = a.parquet.is_some();
    Ok(session)
}

/// The progress bar: on a terminal, and not with `--quiet`.
fn progress(a: &BatchArgs, n: usize) -> indicatif::ProgressBar {
    if !std::io::stderr().is_terminal() || a.quiet {
        return indicatif::ProgressBar::hidden();
    }
    let b = indicatif::ProgressBar::new(n as u64);
    b.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} diagrams  {elapsed} ({eta} left)",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    b
}

/// The output folder (`--out`), locked for the whole batch (a second batch
/// into it waits or exits 2) and cleaned of what a killed run left; every
/// name the batch will write checked before the first is written.
fn out_dir(
    a: &BatchArgs,
    files: &[std::path::PathBuf],
) -> Result<(Option<enginedyn_report::OutDir>, Vec<String>), Failure> {
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
    let dir = a
        .out
        .as_deref()
        .map(|d| {
            enginedyn_report::OutDir::open_for(d, names, &folders).map(|o| o.for_command("batch"))
        })
        .transpose()?;
    Ok((dir, folders))
}

/// A failed file's row.
fn failed_row(a: &BatchArgs, file: &std::path::Path, e: enginedyn_session::Error) -> Row {
    let shown = enginedyn_session::campaign::shown(file);
    let campaign = a
        .parquet
        .is_some()
        .then(|| enginedyn_session::campaign::Row::failed(file, &e));
    Row {
        json: a.json.then(|| json_row(&shown, &e.message, None)),
        file: shown,
        error: e.message,
        cells: Vec::new(),
        key: None,
        folder: None,
        campaign,
        notes: Vec::new(),
    }
}

pub fn run(a: &BatchArgs) -> Result<(), Failure> {
    let session = session_of(a)?;
    let engine = session.engine();
    let listed = enginedyn_session::batch::listed(
        &a.diagrams,
        a.files_from.as_deref(),
        a.shard,
        a.parquet.is_some(),
    )?;
    for note in &listed.notes {
        crate::say(None, note);
    }
    let files = &listed.files;
    // A campaign's folder checked before any work: another campaign's
    // parts refused (or replaced), anything else in the way refused.
    let plan = match &a.parquet {
        Some(dir) => {
            let shard = a.shard.unwrap_or(enginedyn_session::batch::Shard::WHOLE);
            let plan = session
                .plan_keys(dir, shard, &listed.keys, a.traces, a.replace)
                .map_err(|e| parquet_failure(dir, e))?;
            if !plan.removed.is_empty() {
                let removed: Vec<String> = plan
                    .removed
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect();
                crate::say(
                    None,
                    &format!(
                        "parts of another campaign removed (--replace): {}",
                        removed.join(", ")
                    ),
                );
            }
            Some(plan)
        }
        None => None,
    };
    // What each summary came from (`inputs`): the engine hashed once, each
    // diagram as it is read; only when a summary.json is written.
    let engine_inputs = (a.detail || a.json)
        .then(|| enginedyn_session::inputs::of(&session.loaded, &[]))
        .transpose()?;
    let (out_dir, folders) = out_dir(a, files)?;
    let bar = progress(a, files.len());
    let started = Instant::now();
    let work = if a.parse_only {
        Work::ParseOnly
    } else {
        Work::Analyse
    };
    let ctx = RowContext {
        a,
        session: &session,
        engine_inputs: engine_inputs.as_ref(),
        out_dir: out_dir.as_ref(),
        folders: &folders,
    };
    let items = session.batch(
        files,
        a.jobs.unwrap_or(0) as usize,
        work,
        |i, f, an, times| ctx.row(i, f, an, times),
        |item| {
            bar.inc(1);
            if let Err(e) = &item.result {
                let shown = enginedyn_session::campaign::shown(&item.file);
                bar.suspend(|| eprintln!("error: {}: {}", one_line(&shown), e.message));
            }
        },
    )?;
    bar.finish_and_clear();
    if a.stage_times {
        let grid: f64 = items.iter().map(|i| i.times.grid.as_secs_f64()).sum();
        let analysis: f64 = items.iter().map(|i| i.times.analysis.as_secs_f64()).sum();
        eprintln!(
            "stage times over {} diagrams: grid {grid:.6} s, analysis {analysis:.6} s",
            items.len(),
        );
    }
    let mut rows: Vec<Row> = items
        .into_iter()
        .map(|item| item.result.unwrap_or_else(|e| failed_row(a, &item.file, e)))
        .collect();
    let failed = rows.iter().filter(|r| !r.error.is_empty()).count();
    // The files' notes grouped by kind, one line a kind with its count
    // and the range of its numbers (INTERFACE.md, "A batch's log").
    let names: Vec<String> = rows.iter().map(|r| one_line(&r.file)).collect();
    crate::say_grouped(
        names
            .iter()
            .zip(&rows)
            .map(|(f, r)| (f.as_str(), r.notes.as_slice())),
        "files",
        a.quiet,
    );
    let mut written_to: Vec<String> = Vec::new();
    // The campaign's part: whole or not at all; one that cannot be
    // written is exit 2 (so a dependent job can trust every part exists).
    if let (Some(plan), Some(dir)) = (&plan, &a.parquet) {
        let campaign: Vec<enginedyn_session::campaign::Row> =
            rows.iter_mut().filter_map(|r| r.campaign.take()).collect();
        let written = session
            .write_plan(plan, &campaign)
            .map_err(|e| parquet_failure(dir, e))?;
        written_to.extend(written.iter().map(|p| p.display().to_string()));
        if !a.quiet {
            eprintln!(
                "wrote {} ({} of {} files failed): {}",
                enginedyn_report::count(written.len(), "part"),
                failed,
                rows.len(),
                written_to.join(", ")
            );
        }
    }
    if let Some(csv) = print_outputs(a, engine, &rows, out_dir.as_ref(), started, failed)? {
        written_to.push(csv);
    }
    if a.quiet {
        // The one line a job's log keeps on standard output.
        crate::emit(&format!(
            "{} read, {failed} failed{}\n",
            enginedyn_report::count(rows.len(), "file"),
            if written_to.is_empty() {
                String::new()
            } else {
                format!("; wrote {}", written_to.join(", "))
            }
        ));
    }
    if failed > 0 && a.parquet.is_none() {
        return Err(Failure::data(format!(
            "{failed} of {} diagrams failed (their rows say why)",
            rows.len()
        )));
    }
    Ok(())
}

/// A campaign that cannot be written there: exit 2, naming the folder.
fn parquet_failure(dir: &std::path::Path, e: enginedyn_session::Error) -> Failure {
    Failure::usage(format!("--parquet {}: {}", dir.display(), e.message))
}

/// What every file's row needs.
struct RowContext<'a> {
    a: &'a BatchArgs,
    session: &'a Session,
    engine_inputs: Option<&'a enginedyn_report::Inputs>,
    out_dir: Option<&'a enginedyn_report::OutDir>,
    folders: &'a [String],
}

impl RowContext<'_> {
    /// One file's row: its summary's cells and key figures, its run
    /// folder (`--detail`), its JSON (`--json`), its campaign rows.
    fn row(
        &self,
        i: usize,
        f: &std::path::Path,
        an: Option<enginedyn_session::Analysed>,
        times: &mut enginedyn_session::batch::Times,
    ) -> enginedyn_session::Result<Row> {
        let a = self.a;
        let shown = enginedyn_session::campaign::shown(f);
        let Some(enginedyn_session::Analysed {
            analysis: an,
            resampled,
            diagram_blake3,
        }) = an
        else {
            return Ok(Row {
                file: shown,
                error: String::new(),
                cells: Vec::new(),
                key: None,
                folder: None,
                json: None,
                campaign: None,
                notes: Vec::new(),
            });
        };
        let s = &an.summary;
        let inputs = self
            .engine_inputs
            .map(|e| e.with_diagrams(&[enginedyn_report::Source::Hashed(f, &diagram_blake3)]))
            .transpose()?;
        let campaign = a
            .parquet
            .is_some()
            .then(|| self.session.row(f, &an, resampled, diagram_blake3));
        let mut folder = None;
        if let Some(dir) = self.out_dir
            && let Some(name) = self.folders.get(i)
            && let Some(inputs) = &inputs
        {
            let files = enginedyn_report::run_files(
                self.session.engine(),
                &an,
                a.angles == crate::args::Angles::Centered,
                inputs,
            )
            .map_err(|e| enginedyn_session::Error::data(e.to_string()))?;
            dir.write_folder(name, &files)?;
            folder = Some(name.clone());
        }
        let json = match &inputs {
            Some(inputs) if a.json => Some(json_row(
                &shown,
                "",
                Some(enginedyn_report::summary_json(s, inputs)),
            )),
            _ => None,
        };
        // The notes are said at the end, grouped by kind over the files.
        let notes = s.notes.clone();
        let flattened = Instant::now();
        let cells = enginedyn_report::flatten(s);
        times.analysis += flattened.elapsed();
        Ok(Row {
            file: shown,
            error: String::new(),
            cells,
            key: Some(enginedyn_report::key_figures(
                &enginedyn_report::KEY_FIGURES,
                s,
            )),
            folder,
            json,
            campaign,
            notes,
        })
    }
}

/// summary.csv, index.html and the table or JSON on standard output (with
/// `--quiet`, neither the table nor the line that says what was written);
/// returns where summary.csv was written.
fn print_outputs(
    a: &BatchArgs,
    engine: &enginedyn_engine::Engine,
    rows: &[Row],
    out_dir: Option<&enginedyn_report::OutDir>,
    started: Instant,
    failed: usize,
) -> Result<Option<String>, Failure> {
    let table: Vec<enginedyn_report::CsvRow> = rows
        .iter()
        .map(|r| (r.file.clone(), r.error.clone(), r.cells.clone()))
        .collect();
    let csv = enginedyn_report::summary_csv(&table);
    let eta = enginedyn_report::effective_of(engine);
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
    match out_dir {
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
            let written = dir.path().join("summary.csv").display().to_string();
            if a.quiet {
                return Ok(Some(written));
            }
            eprintln!(
                "{} ({} failed) in {:.2} s; wrote {written}",
                enginedyn_report::count(rows.len(), "diagram"),
                failed,
                started.elapsed().as_secs_f64(),
            );
            if let Some(json) = &json {
                crate::emit(json);
            }
            return Ok(Some(written));
        }
        None if a.quiet => {}
        None if a.json => crate::emit(&json.unwrap_or_default()),
        None if a.csv || a.parse_only => crate::emit(&csv),
        None => {
            let mut text = enginedyn_report::heading(
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
    Ok(None)
}

/// What `sweep --out DIR` writes.
const SWEEP_FILES: [&str; 2] = ["sweep.csv", "sweep.svg"];

pub fn sweep(a: &SweepArgs) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.engine)?;
    // Something in the way of an output is refused before the sweep runs.
    let out = crate::open_out(a.out.as_deref(), &SWEEP_FILES, "sweep")?;
    let session = Session::new(
        loaded,
        a.diagram_args.reader(None),
        a.method.method(None),
        // sweep.csv and sweep.svg need the summary figures only.
        enginedyn_pipeline::Scope::Summary,
    )?;
    let engine = session.engine();
    let rpms = enginedyn_session::speed::speeds(&a.rpm)?;
    // The diagram given, else the engine file's, else its [combustion]'s.
    let diagram = match a.diagram.as_deref() {
        Some(p) => enginedyn_session::synth::DefaultDiagram::File(p.to_path_buf()),
        None => {
            enginedyn_session::synth::default_diagram(&session.loaded, None, session.method.step())?
        }
    };
    // A design cycle that changes with speed (a boost or burn curve) is
    // made at each speed: the map's path, at the file's load.
    if let enginedyn_session::synth::DefaultDiagram::Synthesised(s) = &diagram
        && session
            .loaded
            .engine
            .combustion()
            .is_some_and(|c| c.varies_with_speed())
    {
        let imep = s
            .imep_target_bar
            .unwrap_or((s.imep_bar * 1e6).round() / 1e6);
        let load = format!("{0}:{0}:1", crate::human(imep));
        return crate::sweep_map::run_loads(
            a,
            enginedyn_session::map::Loads::Imep(vec![imep]),
            &load,
        );
    }
    let input = diagram.input();
    let shown = input.shown();
    if let Some(note) = diagram.note() {
        crate::say(None, note);
    }
    let enginedyn_session::sweep::Sweep {
        points,
        sized_at,
        source,
        flywheel,
    } = session.sweep(input, &rpms, &a.rpm)?;
    // The speeds' notes grouped by kind, one line a kind.
    let names: Vec<String> = points
        .iter()
        .map(|p| format!("{} rpm", crate::human(p.summary.rpm)))
        .collect();
    crate::say_grouped(
        names
            .iter()
            .zip(&points)
            .map(|(n, p)| (n.as_str(), p.summary.notes.as_slice())),
        "points",
        false,
    );
    let table: Vec<enginedyn_report::CsvRow> = points
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
        let inputs = enginedyn_session::inputs::of(&session.loaded, &[input])?;
        let each: Vec<String> = points
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
                points.iter().map(|an| &an.summary).collect();
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
            let rows: Vec<enginedyn_report::KeyRow> = points
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
            let mut text = enginedyn_report::heading(engine, "sweep, ", f64::NAN, &shown);
            if flywheel {
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
                enginedyn_report::effective_of(engine),
            ));
            crate::emit(&text);
        }
    }
    Ok(())
}
