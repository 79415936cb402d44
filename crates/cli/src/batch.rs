//! `enginedyn batch` (many diagrams in parallel) and `enginedyn sweep` (one
//! diagram over a range of speeds).

use crate::Failure;
use crate::args::{BatchArgs, SweepArgs};
use crate::run::{
    check_step, diagram_options, load_diagram, load_diagram_timed, load_engine, parse_diagram,
    resolve_rpm, within,
};
use enginedyn_engine::Engine;
use enginedyn_ingest::Quantity;
use enginedyn_report::{Chart, Figure, Series};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Files, folders (every `.csv` inside, sorted) and glob patterns, in the
/// order given.
fn expand(inputs: &[String]) -> Result<Vec<PathBuf>, Failure> {
    let mut files = Vec::new();
    for input in inputs {
        let p = Path::new(input);
        if p.is_dir() {
            let mut inside: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| Failure::usage(format!("{input}: cannot list: {e}")))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.extension().is_some_and(|x| x.eq_ignore_ascii_case("csv")))
                .collect();
            inside.sort();
            files.extend(inside);
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
        return Err(Failure::usage("no diagram files found"));
    }
    Ok(files)
}

/// One diagram's outcome.
struct Row {
    file: String,
    error: String,
    cells: Vec<(String, String)>,
    /// Key figures for index.html, one per [`KEY_FIGURES`] column.
    key: Option<Vec<Option<f64>>>,
    folder: Option<String>,
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
    let step = a.method.step;
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
    let (parse, grid) = diagram_options(engine, &a.diagram_args, step, opts.interp)?;
    // The motion and volume law on the grid, built once for every file.
    let n = (engine.cycle().to_degrees() / step).round() as usize;
    let tables = enginedyn_pipeline::Tables::new(engine, n, &opts).ok();
    let files = expand(&a.diagrams)?;
    let jobs = a.jobs.unwrap_or(0);
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
                let result = (|| -> Result<Row, Failure> {
                    if a.parse_only {
                        parse_only(f, &parse)?;
                        return Ok(Row {
                            file: shown.clone(),
                            error: String::new(),
                            cells: Vec::new(),
                            key: None,
                            folder: None,
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
                            let rpm = resolve_rpm(None, d.rpm, engine)?;
                            let (mut an, choice) =
                                within(engine, &[(shown.clone(), d)], &grid, rpm, t)?;
                            an.summary.estimated_relative_error = Some(choice.estimated);
                            an.summary.notes.extend(choice.notes);
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
                            let rpm = resolve_rpm(None, resampled.rpm, engine)?;
                            let an = enginedyn_pipeline::analyse_with(
                                tables.as_ref(),
                                engine,
                                &resampled,
                                rpm,
                                &opts,
                            )
                            .map_err(|e| Failure::usage(e.to_string()))?;
                            analysis += analysed.elapsed();
                            an
                        }
                    };
                    let s = &an.summary;
                    let mut folder = None;
                    if a.detail
                        && let Some(dir) = &a.out
                    {
                        let stem = f
                            .file_stem()
                            .map(|s| s.to_string_lossy().into_owned())
                            .unwrap_or_else(|| "diagram".into());
                        let name = format!("{i:04}_{stem}");
                        let files = enginedyn_report::run_files(engine, &an, false)
                            .map_err(|e| Failure::data(e.to_string()))?;
                        enginedyn_report::write_all(&dir.join(&name), &files)
                            .map_err(|e| Failure::data(e.to_string()))?;
                        folder = Some(name);
                    }
                    let flattened = Instant::now();
                    let cells = enginedyn_report::flatten(s);
                    analysis += flattened.elapsed();
                    Ok(Row {
                        file: shown.clone(),
                        error: String::new(),
                        cells,
                        key: Some(KEY_FIGURES.iter().map(|(_, _, get)| get(s)).collect()),
                        folder,
                    })
                })();
                bar.inc(1);
                grid_ns.fetch_add(on_grid.as_nanos() as u64, Ordering::Relaxed);
                analysis_ns.fetch_add(analysis.as_nanos() as u64, Ordering::Relaxed);
                result.unwrap_or_else(|e| {
                    let msg = e
                        .message
                        .strip_prefix(&format!("{shown}: "))
                        .unwrap_or(&e.message)
                        .to_string();
                    bar.suspend(|| eprintln!("error: {shown}: {msg}"));
                    Row {
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
    match &a.out {
        Some(dir) => {
            let mut out = vec![("summary.csv".to_string(), csv.into_bytes())];
            if a.detail {
                out.push((
                    "index.html".to_string(),
                    index_html(engine, &rows).into_bytes(),
                ));
            }
            enginedyn_report::write_all(dir, &out).map_err(|e| Failure::data(e.to_string()))?;
            eprintln!(
                "{} ({} failed) in {:.2} s; wrote {}",
                diagrams(rows.len()),
                failed,
                started.elapsed().as_secs_f64(),
                dir.join("summary.csv").display()
            );
        }
        None => crate::emit(&csv),
    }
    if failed > 0 {
        return Err(Failure {
            code: 1,
            message: format!(
                "{failed} of {} diagrams failed (their rows say why)",
                rows.len()
            ),
        });
    }
    Ok(())
}

/// The parse floor of the benchmark: every cell read and checked, each
/// cycle's trace built and dropped, nothing put on the grid or computed.
fn parse_only(f: &Path, parse: &enginedyn_ingest::ParseOptions) -> Result<(), Failure> {
    let file = std::fs::File::open(f)
        .map_err(|e| Failure::data(format!("{}: cannot open: {e}", f.display())))?;
    enginedyn_ingest::parse_stream(
        std::io::BufReader::with_capacity(1 << 12, file),
        parse,
        |_| Ok(()),
    )
    .map_err(|e| Failure::data(format!("{}: {e}", f.display())))?;
    Ok(())
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The columns of index.html: heading, decimals shown, the figure (in the
/// heading's unit) from a diagram's summary.
type KeyFigure = (
    &'static str,
    usize,
    fn(&enginedyn_pipeline::Summary) -> Option<f64>,
);
const KEY_FIGURES: [KeyFigure; 8] = [
    ("speed (rpm)", 0, |s| Some(s.rpm)),
    ("IMEP (bar)", 3, |s| s.imep_bar),
    ("mean torque (N m)", 2, |s| s.mean_torque_nm),
    ("power (kW)", 2, |s| s.power_kw),
    ("torque max (N m)", 1, |s| s.torque_max_nm),
    ("torque min (N m)", 1, |s| s.torque_min_nm),
    ("crank-pin load max (kN)", 2, |s| {
        s.crankpin_load_max_n.map(|v| v / 1e3)
    }),
    ("required inertia (kg m²)", 5, |s| s.required_inertia_kg_m2),
];

/// "1 diagram", "2 diagrams".
fn diagrams(n: usize) -> String {
    format!("{n} diagram{}", if n == 1 { "" } else { "s" })
}

/// A table of every diagram with its key figures, linking to its report.
fn index_html(engine: &Engine, rows: &[Row]) -> String {
    let mut o = String::new();
    let _ = write!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{} — batch</title><style>\
body{{font-family:sans-serif;margin:24px}}table{{border-collapse:collapse;font-size:14px}}\
td,th{{padding:3px 10px;border-bottom:1px solid #eee;text-align:left}}td.v{{text-align:right}}.err{{color:#b00}}\
</style></head><body><h1>{} — {}</h1>\n<table><tr><th>#</th><th>diagram</th>",
        esc(engine.name()),
        esc(engine.name()),
        diagrams(rows.len())
    );
    for (heading, _, _) in &KEY_FIGURES {
        let _ = write!(o, "<th>{}</th>", esc(heading));
    }
    o.push_str("<th>report</th></tr>\n");
    for (i, r) in rows.iter().enumerate() {
        let _ = write!(o, "<tr><td>{i}</td><td>{}</td>", esc(&r.file));
        match (&r.key, &r.folder) {
            (Some(k), Some(folder)) => {
                for (v, (_, d, _)) in k.iter().zip(&KEY_FIGURES) {
                    let _ = write!(
                        o,
                        "<td class=\"v\">{}</td>",
                        v.map_or("—".to_string(), |x| format!("{x:.d$}"))
                    );
                }
                let _ = writeln!(
                    o,
                    "<td><a href=\"{}/report.html\">report</a></td></tr>",
                    esc(folder)
                );
            }
            _ => {
                let _ = writeln!(
                    o,
                    "<td colspan=\"{}\" class=\"err\">{}</td></tr>",
                    KEY_FIGURES.len() + 1,
                    esc(&r.error)
                );
            }
        }
    }
    o.push_str("</table></body></html>\n");
    o
}

/// Parses FROM:TO:STEP; TO is included when it falls on the step.
fn speeds(spec: &str) -> Result<Vec<f64>, Failure> {
    let bad = || {
        Failure::usage(format!(
            "--rpm {spec}: expected FROM:TO:STEP with 0 < FROM <= TO and STEP > 0"
        ))
    };
    let parts: Vec<f64> = spec
        .split(':')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    let [from, to, step] = parts[..] else {
        return Err(bad());
    };
    if !(from > 0.0 && to >= from && step > 0.0 && to.is_finite()) {
        return Err(bad());
    }
    let n = ((to - from) / step + 1e-9).floor() as usize;
    if n > 100_000 {
        return Err(Failure::usage(format!(
            "--rpm {spec}: {n} speeds is too many"
        )));
    }
    Ok((0..=n).map(|k| from + k as f64 * step).collect())
}

pub fn sweep(a: &SweepArgs) -> Result<(), Failure> {
    let loaded = load_engine(Some(&a.engine))?;
    let engine = &loaded.engine;
    let step = a.method.step;
    check_step(engine, step)?;
    let rpms = speeds(&a.rpm)?;
    let opts = enginedyn_pipeline::Options {
        // sweep.csv and sweep.svg need the summary figures only.
        scope: enginedyn_pipeline::Scope::Summary,
        ..a.method.options()
    };
    let (parse, grid) = diagram_options(engine, &a.diagram_args, step, opts.interp)?;
    let path = crate::run::diagram_path(a.diagram.as_deref(), &loaded)?;
    let resampled = load_diagram(Some(&path), &parse, &grid)?;
    let shown = path.display().to_string();
    let tables = enginedyn_pipeline::Tables::new(engine, resampled.pressure.len(), &opts).ok();
    // The pressures stay the same at every speed: gas load fixed, inertia growing with w^2.
    let results: Vec<_> = rpms
        .par_iter()
        .map(|&rpm| {
            enginedyn_pipeline::analyse_with(tables.as_ref(), engine, &resampled, rpm, &opts)
        })
        .collect::<Result<_, _>>()
        .map_err(|e| Failure::usage(e.to_string()))?;
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
    match &a.out {
        Some(dir) => {
            let get = |f: fn(&enginedyn_pipeline::Summary) -> Option<f64>| -> Vec<(f64, f64)> {
                results
                    .iter()
                    .filter_map(|an| f(&an.summary).map(|v| (an.summary.rpm, v)))
                    .collect()
            };
            let panel = |title: &str, y: &str, series: Vec<Series>| Chart {
                title: title.into(),
                x_label: "engine speed (rpm)".into(),
                y_label: y.into(),
                series,
                log: false,
                equal: false,
                angle_ticks: None,
            };
            let s = |name: &str, pts: Vec<(f64, f64)>| Series {
                name: name.into(),
                points: pts,
                dashed: false,
            };
            let fig = Figure {
                file: "sweep.svg".into(),
                panels: vec![
                    panel(
                        &format!("{} — torque against speed", engine.name()),
                        "torque (N m)",
                        vec![
                            s("mean", get(|x| x.mean_torque_nm)),
                            s("max", get(|x| x.torque_max_nm)),
                            s("min", get(|x| x.torque_min_nm)),
                        ],
                    ),
                    // One unit per panel: the crank-pin load against the
                    // peak gas force shows inertia taking over as speed rises.
                    panel(
                        "peak forces",
                        "force (kN)",
                        vec![
                            s(
                                "crank-pin load max",
                                get(|x| x.crankpin_load_max_n.map(|v| v / 1e3)),
                            ),
                            s("gas force max", get(|x| x.gas_force_max_n.map(|v| v / 1e3))),
                        ],
                    ),
                    panel(
                        "flywheel",
                        "required inertia I₀ (kg m²)",
                        vec![s("required inertia I₀", get(|x| x.required_inertia_kg_m2))],
                    ),
                ],
            };
            let svg = fig.render().map_err(|e| Failure::data(e.to_string()))?;
            enginedyn_report::write_all(
                dir,
                &[
                    ("sweep.csv".to_string(), csv.into_bytes()),
                    ("sweep.svg".to_string(), svg.into_bytes()),
                ],
            )
            .map_err(|e| Failure::data(e.to_string()))?;
            eprintln!(
                "{} speeds; wrote sweep.csv and sweep.svg to {}",
                rpms.len(),
                dir.display()
            );
        }
        None => crate::emit(&csv),
    }
    Ok(())
}
