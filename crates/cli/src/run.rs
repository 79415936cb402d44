//! `enginedyn run`: one operating point.

use crate::Failure;
use crate::args::{DiagramArgs, RunArgs};
use enginedyn_engine::Engine;
use enginedyn_ingest::{GridOptions, ParseOptions, Peg, Quantity, Resampled};
use std::path::{Path, PathBuf};

/// The bundled example, compiled in so `enginedyn run` works from anywhere.
pub(crate) const EXAMPLE_ENGINE: &str = include_str!("../../../data/vaz2108.toml");
pub(crate) const EXAMPLE_DIAGRAM: &str = include_str!("../../../data/vaz2108.csv");
const EXAMPLE_NAME: &str = "data/vaz2108.toml (bundled)";

/// Where the engine came from: a file or the bundled example.
pub struct Loaded {
    pub engine: Engine,
    pub path: Option<PathBuf>,
}

/// Reads the engine file, or the bundled example when none is given.
pub fn load_engine(path: Option<&Path>) -> Result<Loaded, Failure> {
    match path {
        Some(p) => {
            let engine = enginedyn_engine::file::read(p)
                .map_err(|e| Failure::from(e).in_file(p.display()))?;
            Ok(Loaded {
                engine,
                path: Some(p.to_path_buf()),
            })
        }
        None => {
            let engine = enginedyn_engine::file::parse(EXAMPLE_ENGINE, "vaz2108")
                .map_err(|e| Failure::usage(format!("{EXAMPLE_NAME}: {e}")))?;
            Ok(Loaded { engine, path: None })
        }
    }
}

/// How to read and grid a diagram, from the diagram and method flags.
pub fn diagram_options(
    engine: &Engine,
    d: &DiagramArgs,
    step: f64,
    interp: enginedyn_ingest::Interp,
    rpm: Option<f64>,
) -> Result<(ParseOptions, GridOptions), Failure> {
    let pv_start_bdc = d.pv_start == crate::args::PvStart::Bdc;
    let peg = match (d.peg_bar, d.peg) {
        (Some(p), _) if p.is_finite() && p > 0.0 => Some(Peg::Bar(p * 1e5)),
        (Some(p), _) => {
            return Err(Failure::usage(format!(
                "--peg-bar {p}: an absolute pressure in bar above 0 is needed"
            )));
        }
        (None, Some(crate::args::PegArg::Polytropic(n))) => Some(Peg::Polytropic(n)),
        (None, None) => None,
    };
    let cylinder = Some(*engine.cylinder());
    let parse = ParseOptions {
        cycle_deg: engine.cycle().to_degrees(),
        tdc_deg: d.tdc_deg.unwrap_or(0.0),
        tdc_given: d.tdc_deg.is_some(),
        relative: peg.is_some(),
        skip_lines: d.skip_lines.map_or(0, |n| n as usize),
        sheet: d.sheet.as_ref().map(|s| match s.trim().parse::<usize>() {
            Ok(n) => enginedyn_ingest::Sheet::Index(n),
            Err(_) => enginedyn_ingest::Sheet::Name(s.clone()),
        }),
        group: d.group.map(|n| n as usize),
        max_gap_deg: d.max_gap.unwrap_or(enginedyn_ingest::MAX_GAP_DEG),
        tdc_time: d.tdc_time,
        gain_bar_per_v: d.gain,
        rpm,
        gauge: d.gauge,
        columns: d
            .columns
            .as_ref()
            .map(|c| c.iter().map(|s| s.trim().to_ascii_lowercase()).collect()),
        cylinder,
        pv_start_bdc,
        max_cylinder: engine.cylinders(),
        firing_deg: engine
            .firing_angles()
            .iter()
            .map(|t| t.to_degrees())
            .collect(),
        cylinder_axis: d.cylinder_axis.map(|a| match a {
            crate::args::CylinderAxisArg::Shared => enginedyn_ingest::CylinderAxis::Shared,
            crate::args::CylinderAxisArg::Own => enginedyn_ingest::CylinderAxis::Own,
        }),
        as_cylinder: 0,
        torque: false,
    };
    let mut grid = GridOptions {
        step_deg: step,
        interp,
        peg,
        cylinder,
        volume_law: None,
    };
    // Built once here for every file the command reads.
    grid.share_volume_law(parse.cycle_deg);
    Ok((parse, grid))
}

/// Opens a diagram (or torque) file for reading: a regular file only. A
/// FIFO or a device is refused before anything is read (opening a FIFO
/// would block a batch forever; a device may never end), and so is a
/// folder.
pub fn open_diagram(p: &Path) -> Result<std::fs::File, Failure> {
    let shown = p.display();
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Open never blocks (a FIFO without a writer); reads of a regular
        // file are unaffected by the flag.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options
        .open(p)
        .map_err(|e| Failure::data(format!("cannot open: {e}")).in_file(&shown))?;
    let meta = file
        .metadata()
        .map_err(|e| Failure::data(format!("cannot open: {e}")).in_file(&shown))?;
    if !meta.is_file() {
        let what = if meta.is_dir() {
            "a folder"
        } else {
            "not a regular file (a FIFO, socket or device)"
        };
        return Err(
            Failure::data(format!("{what}: a diagram is read from a regular file")).in_file(shown),
        );
    }
    Ok(file)
}

/// Reads one diagram file (or the bundled one for `None`) straight onto the grid.
pub fn load_diagram(
    path: Option<&Path>,
    parse: &ParseOptions,
    grid: &GridOptions,
) -> Result<Resampled, Failure> {
    let mut unused = std::time::Duration::ZERO;
    load_diagram_timed(path, parse, grid, &mut unused)
}

/// [`load_diagram`], adding the time spent after parsing (putting the
/// traces on the grid) to `on_grid`.
pub fn load_diagram_timed(
    path: Option<&Path>,
    parse: &ParseOptions,
    grid: &GridOptions,
    on_grid: &mut std::time::Duration,
) -> Result<Resampled, Failure> {
    match path {
        Some(p) => {
            let file = open_diagram(p)?;
            enginedyn_ingest::load_timed(
                // The reader keeps its own 64 KiB blocks: a small BufReader
                // passes those reads straight through instead of copying.
                std::io::BufReader::with_capacity(1 << 12, file),
                parse,
                grid,
                on_grid,
            )
            .map_err(|e| Failure::from(e).in_file(p.display()))
        }
        None => enginedyn_ingest::load_timed(EXAMPLE_DIAGRAM.as_bytes(), parse, grid, on_grid)
            .map_err(|e| Failure::data(format!("data/vaz2108.csv (bundled): {e}"))),
    }
}

/// The diagram a command needs: the flag, else the engine file's `diagram`
/// key, else a usage error that says so.
pub fn diagram_path(flag: Option<&Path>, loaded: &Loaded) -> Result<PathBuf, Failure> {
    match flag {
        Some(p) => Ok(p.to_path_buf()),
        None => loaded
            .engine
            .diagram()
            .map(Path::to_path_buf)
            .ok_or_else(|| {
                Failure::usage(format!(
                    "no indicator diagram: give --diagram or `diagram =` in {}",
                    loaded
                        .path
                        .as_deref()
                        .map(|p| p.display().to_string())
                        .unwrap_or_else(|| "the engine file".into())
                ))
            }),
    }
}

/// Reads a whole diagram file into memory (every trace), for commands that
/// put it on several grids.
pub fn parse_diagram(
    path: &Path,
    parse: &ParseOptions,
) -> Result<enginedyn_ingest::Diagram, Failure> {
    let file = open_diagram(path)?;
    enginedyn_ingest::parse(std::io::BufReader::with_capacity(1 << 12, file), parse)
        .map_err(|e| Failure::from(e).in_file(path.display()))
}

/// One trace per file and cylinder, in cylinder order 1..z, as one diagram.
fn merge_per_cylinder(files: Vec<(String, Resampled)>) -> Result<Resampled, Failure> {
    if files.len() == 1 {
        // One file: all cylinders, or its own `cylinder` column.
        return files
            .into_iter()
            .next()
            .map(|(_, r)| r)
            .ok_or_else(|| Failure::usage("no diagram"));
    }
    let mut it = files.into_iter();
    let Some((_, mut first)) = it.next() else {
        return Err(Failure::usage("no diagram"));
    };
    if !first.cylinders.is_empty() {
        return Err(Failure::usage(
            "several --diagram files are one trace per cylinder: a file with a `cylinder` column must come alone",
        ));
    }
    let mut cylinders = vec![std::mem::take(&mut first.pressure)];
    for (name, r) in it {
        if !r.cylinders.is_empty() {
            return Err(Failure::usage(format!(
                "{name}: has a `cylinder` column; with several --diagram files each file is one cylinder"
            )));
        }
        first.cycles = first.cycles.min(r.cycles);
        first.stats.extend(r.stats);
        for n in r.notes {
            // One axis note for the files (each file's says the same kind).
            let same_kind = n.starts_with("cylinder traces ")
                && first
                    .notes
                    .iter()
                    .any(|m| m.starts_with("cylinder traces "));
            if !first.notes.contains(&n) && !same_kind {
                first.notes.push(n);
            }
        }
        cylinders.push(r.pressure);
    }
    first.pressure = cylinders[0].clone();
    first.cylinders = cylinders;
    Ok(first)
}

/// The grid step must be positive and divide the cycle.
pub fn check_step(engine: &Engine, step: f64) -> Result<(), Failure> {
    let cycle_deg = engine.cycle().to_degrees();
    let n = (cycle_deg / step).round();
    if !(step.is_finite() && step > 0.0)
        || (n * step - cycle_deg).abs() > 1e-9 * cycle_deg
        || n < 8.0
    {
        return Err(Failure::usage(format!(
            "--step {step}: the step must divide the {cycle_deg}° cycle (0.1, 0.2, 0.25, 0.5, 1, …)"
        )));
    }
    Ok(())
}

pub use enginedyn_engine::{MAX_RPM, MIN_RPM};

/// The speed a command runs at, and the note saying where it came from
/// when it is not the engine file's `operating.rpm`.
#[derive(Debug, Clone)]
pub struct Speed {
    /// rpm.
    pub rpm: f64,
    /// "speed 2200 rpm from the diagram's `# rpm` line (…)", when it
    /// differs from the engine file's.
    pub note: Option<String>,
}

impl Speed {
    /// Says the note on standard error, for commands whose output carries
    /// no notes of its own.
    pub fn warn(&self) {
        if let Some(n) = &self.note {
            crate::say(None, n);
        }
    }
}

/// The speed: `--rpm`, else the diagram's `# rpm` line, else the engine file's.
pub fn resolve_rpm(
    flag: Option<f64>,
    diagram: Option<f64>,
    engine: &Engine,
) -> Result<Speed, Failure> {
    let file = engine.operating().rpm;
    let (rpm, source) = match (flag, diagram, file) {
        (Some(r), _, _) => (r, "--rpm"),
        (None, Some(r), _) => (r, "the diagram file"),
        (None, None, Some(r)) => (r, "operating.rpm"),
        (None, None, None) => {
            return Err(Failure::usage(
                "no engine speed: give --rpm, a `# rpm = N` line in the diagram, or `rpm` in [operating]",
            ));
        }
    };
    if !(rpm.is_finite() && (MIN_RPM..=MAX_RPM).contains(&rpm)) {
        let why = if rpm.is_finite() && rpm <= 0.0 {
            "the engine speed must be above 0 (a reversed engine is the same engine turning forward)"
        } else {
            "the engine speed must be from 0.001 to 100000 rpm"
        };
        return Err(match source {
            "--rpm" => Failure::usage(format!("--rpm {}: {why}", crate::human(rpm))),
            "operating.rpm" => {
                Failure::usage(format!("operating.rpm = {}: {why}", crate::human(rpm)))
            }
            _ => Failure::data(format!("`# rpm` line: {} rpm: {why}", crate::human(rpm))),
        });
    }
    let note = match file {
        // Two speeds within 1e-9 of each other are one speed.
        Some(f) if (f - rpm).abs() <= 1e-9 * f.abs() => None,
        Some(f) => Some(format!(
            "speed {} rpm from {source}, not the engine file's operating.rpm = {} rpm",
            crate::human(rpm),
            crate::human(f)
        )),
        None => Some(format!(
            "speed {} rpm from {source} (the engine file gives no operating.rpm)",
            crate::human(rpm)
        )),
    };
    Ok(Speed { rpm, note })
}

pub fn run(a: &RunArgs) -> Result<(), Failure> {
    let step = a.method.step();
    let loaded = load_engine(a.engine.as_deref())?;
    let engine = &loaded.engine;
    check_step(engine, step)?;
    let opts = a.method.options();
    let (parse, grid) = diagram_options(engine, &a.diagram_args, step, opts.interp, a.rpm)?;
    if let Some(path) = &a.torque {
        let shown = path.display().to_string();
        let torque_grid = GridOptions {
            peg: None,
            ..grid.clone()
        };
        let torque_parse = ParseOptions {
            torque: true,
            ..parse.clone()
        };
        let resampled = load_diagram(Some(path), &torque_parse, &torque_grid)?;
        if resampled.quantity == Quantity::Pressure {
            return Err(Failure::data(format!(
                "{shown}: a pressure diagram; --torque reads `crank_deg` with `torque_cylinder_nm` or `torque_engine_nm` (use --diagram for pressure)"
            )));
        }
        let speed = resolve_rpm(a.rpm, resampled.rpm, engine)?;
        let mut analysis = enginedyn_pipeline::analyse_torque(
            engine,
            &resampled,
            resampled.quantity,
            speed.rpm,
            &opts,
        )?;
        analysis.summary.notes.extend(speed.note);
        return finish(a, &loaded, &shown, &analysis, &opts);
    }
    let (shown, files) = diagram_files(a, &loaded)?;
    if let Some(tolerance) = a.tolerance {
        return run_within(a, &loaded, &shown, &files, &parse, &grid, tolerance);
    }
    let several = files.len() > 1;
    let loaded_files = files
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let name = p
                .as_deref()
                .map_or(shown.clone(), |p| p.display().to_string());
            // Several files: the k-th is cylinder k + 1's (its axis judged so).
            let parse = ParseOptions {
                as_cylinder: if several { k + 1 } else { 0 },
                ..parse.clone()
            };
            Ok((name, load_diagram(p.as_deref(), &parse, &grid)?))
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    let resampled = merge_per_cylinder(loaded_files)?;
    if resampled.quantity != Quantity::Pressure {
        return Err(Failure::data(format!(
            "{shown}: a turning-moment (torque) file: give it with --torque"
        )));
    }
    let speed = resolve_rpm(a.rpm, resampled.rpm, engine)?;
    let mut analysis = enginedyn_pipeline::analyse(engine, &resampled, speed.rpm, &opts)?;
    analysis.summary.notes.extend(speed.note);
    finish(a, &loaded, &shown, &analysis, &opts)
}

/// The diagram files of `run` (`None`: the bundled example) and how to
/// name them: one file, or one per cylinder in order 1..z.
pub(crate) fn diagram_files(
    a: &RunArgs,
    loaded: &Loaded,
) -> Result<(String, Vec<Option<PathBuf>>), Failure> {
    let z = loaded.engine.cylinders();
    match (a.diagram.as_slice(), &loaded.path) {
        ([], None) => Ok(("data/vaz2108.csv (bundled)".to_string(), vec![None])),
        ([], Some(_)) => {
            let d = diagram_path(None, loaded)?;
            Ok((d.display().to_string(), vec![Some(d)]))
        }
        ([one], _) => Ok((one.display().to_string(), vec![Some(one.clone())])),
        (many, _) => {
            if many.len() != z {
                return Err(Failure::usage(format!(
                    "{} diagrams given: several --diagram files are one trace per cylinder, and the engine has {z}",
                    many.len()
                )));
            }
            Ok((
                format!("{} files, one per cylinder", many.len()),
                many.iter().cloned().map(Some).collect(),
            ))
        }
    }
}

/// `run --tolerance REL`: the diagram read once, the cheapest method
/// setting within the tolerance chosen on its cycle average, then the run
/// with that setting.
fn run_within(
    a: &RunArgs,
    loaded: &Loaded,
    shown: &str,
    files: &[Option<PathBuf>],
    parse: &ParseOptions,
    grid: &GridOptions,
    tolerance: f64,
) -> Result<(), Failure> {
    let several = files.len() > 1;
    let diagrams = files
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let parse = &ParseOptions {
                as_cylinder: if several { k + 1 } else { 0 },
                ..parse.clone()
            };
            let d = match p {
                Some(p) => parse_diagram(p, parse)?,
                None => enginedyn_ingest::parse(EXAMPLE_DIAGRAM.as_bytes(), parse)
                    .map_err(|e| Failure::data(format!("data/vaz2108.csv (bundled): {e}")))?,
            };
            let name = p
                .as_deref()
                .map_or(shown.to_string(), |p| p.display().to_string());
            if d.quantity != Quantity::Pressure {
                return Err(Failure::data(format!(
                    "{name}: a turning-moment (torque) file: give it with --torque"
                )));
            }
            Ok((name, d))
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    let engine = &loaded.engine;
    let speed = resolve_rpm(a.rpm, diagrams[0].1.rpm, engine)?;
    let (analysis, choice) = within(
        engine,
        &diagrams,
        grid,
        speed.rpm,
        tolerance,
        &a.method.kept(),
    )?;
    let mut analysis = analysis;
    analysis.summary.estimated_relative_error = Some(choice.estimated);
    analysis.summary.notes.extend(choice.notes);
    analysis.summary.notes.extend(speed.note);
    let opts = enginedyn_pipeline::Options {
        scope: enginedyn_pipeline::Scope::Full,
        ..choice.options
    };
    finish(a, loaded, shown, &analysis, &opts)
}

/// The cheapest setting within `tolerance` for these diagrams (one, or one
/// per cylinder) and the analysis with it (with the report curves).
pub fn within(
    engine: &Engine,
    diagrams: &[(String, enginedyn_ingest::Diagram)],
    grid: &GridOptions,
    rpm: f64,
    tolerance: f64,
    kept: &enginedyn_accuracy::Kept,
) -> Result<(enginedyn_pipeline::Analysis, enginedyn_accuracy::Choice), Failure> {
    let resample = |ds: &[(String, &enginedyn_ingest::Diagram)], g: &GridOptions| {
        let each = ds
            .iter()
            .map(|(n, d)| {
                enginedyn_ingest::resample_with(d, g)
                    .map(|r| (n.clone(), r))
                    .map_err(|e| Failure::from(e).in_file(n))
            })
            .collect::<Result<Vec<_>, Failure>>()?;
        merge_per_cylinder(each)
    };
    // The choice on the cycle average (cheap); the run on every cycle.
    let averaged: Vec<(String, enginedyn_ingest::Diagram)> = diagrams
        .iter()
        .map(|(n, d)| (n.clone(), d.averaged().unwrap_or_else(|| d.clone())))
        .collect();
    let avg_refs: Vec<(String, &enginedyn_ingest::Diagram)> =
        averaged.iter().map(|(n, d)| (n.clone(), d)).collect();
    let full_refs: Vec<(String, &enginedyn_ingest::Diagram)> =
        diagrams.iter().map(|(n, d)| (n.clone(), d)).collect();
    let on = |step: f64, interp| GridOptions {
        step_deg: step,
        interp,
        ..grid.clone()
    };
    let choice = enginedyn_accuracy::choose(engine, rpm, tolerance, kept, &|step, interp| {
        resample(&avg_refs, &on(step, interp))
            .map_err(|f| enginedyn_accuracy::AccuracyError::Synth(f.message))
    })
    .map_err(|e| match e {
        enginedyn_accuracy::AccuracyError::Unreachable { .. }
        | enginedyn_accuracy::AccuracyError::KeptUnreachable { .. }
        | enginedyn_accuracy::AccuracyError::BadTolerance(_) => Failure::usage(e.to_string()),
        other => Failure::data(other.to_string()),
    })?;
    let opts = enginedyn_pipeline::Options {
        scope: enginedyn_pipeline::Scope::Full,
        ..choice.options
    };
    let resampled = resample(&full_refs, &on(opts.step_deg, opts.interp))?;
    let analysis = enginedyn_pipeline::analyse(engine, &resampled, rpm, &opts)?;
    Ok((analysis, choice))
}

/// Prints and writes the results of one operating point.
fn finish(
    a: &RunArgs,
    loaded: &Loaded,
    shown: &str,
    analysis: &enginedyn_pipeline::Analysis,
    opts: &enginedyn_pipeline::Options,
) -> Result<(), Failure> {
    let engine = &loaded.engine;
    crate::say_all(&analysis.summary.notes);
    let inputs = crate::inputs::of_run(a, loaded)?;
    if a.json {
        let json = enginedyn_report::summary_json(&analysis.summary, &inputs);
        crate::emit(&(serde_json::to_string_pretty(&json).unwrap_or_default() + "\n"));
    } else {
        crate::emit(&crate::table::summary_table(
            engine,
            shown,
            &analysis.summary,
        ));
    }
    if let Some(dir) = &a.out {
        let centered = a.angles == crate::args::Angles::Centered;
        // With a [tolerances] section the page carries the tolerance table.
        let text = match &loaded.path {
            Some(p) => std::fs::read_to_string(p)
                .map_err(|e| Failure::usage(format!("{}: cannot read: {e}", p.display())))?,
            None => EXAMPLE_ENGINE.to_string(),
        };
        let mut extra =
            crate::tolerance::report_extra(engine, &text, analysis, *opts)?.unwrap_or_default();
        // With a [torsion] section, the torsional vibration too.
        if let Some(t) = crate::torsion::report_extra(engine, &text, analysis, *opts)? {
            extra.sections.extend(t.sections);
            extra.charts.extend(t.charts);
        }
        let files = enginedyn_report::run_files_with(engine, analysis, centered, &inputs, &extra)?;
        crate::write_out(dir, &files, a.json)?;
    }
    Ok(())
}
