//! `enginedyn run`: one operating point.

use crate::Failure;
use crate::args::{DiagramArgs, RunArgs};
use enginedyn_engine::Engine;
use enginedyn_ingest::{Diagram, ParseOptions, Quantity};
use std::path::{Path, PathBuf};

/// The bundled example, compiled in so `enginedyn run` works from anywhere.
const EXAMPLE_ENGINE: &str = include_str!("../../../data/vaz2108.toml");
const EXAMPLE_DIAGRAM: &str = include_str!("../../../data/vaz2108.csv");
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
                .map_err(|e| Failure::usage(format!("{}: {e}", p.display())))?;
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

/// Reads one diagram file (or the bundled one for `None`).
pub fn read_diagram(
    path: Option<&Path>,
    engine: &Engine,
    d: &DiagramArgs,
) -> Result<Diagram, Failure> {
    if d.peg_bar.is_some() || d.peg.is_some() || d.pv_start.is_some() {
        return Err(Failure::usage(
            "--peg-bar, --peg and --pv-start are not supported by this build yet",
        ));
    }
    let opts = ParseOptions {
        cycle_deg: engine.cycle().to_degrees(),
        tdc_deg: d.tdc_deg,
        gauge: d.gauge,
        columns: d
            .columns
            .as_ref()
            .map(|c| c.iter().map(|s| s.trim().to_ascii_lowercase()).collect()),
    };
    match path {
        Some(p) => {
            let file = std::fs::File::open(p)
                .map_err(|e| Failure::data(format!("{}: cannot open: {e}", p.display())))?;
            enginedyn_ingest::parse(std::io::BufReader::new(file), &opts)
                .map_err(|e| Failure::data(format!("{}: {e}", p.display())))
        }
        None => enginedyn_ingest::parse(EXAMPLE_DIAGRAM.as_bytes(), &opts)
            .map_err(|e| Failure::data(format!("data/vaz2108.csv (bundled): {e}"))),
    }
}

/// The speed: `--rpm`, else the diagram's `# rpm` line, else the engine file's.
pub fn resolve_rpm(
    flag: Option<f64>,
    diagram: Option<f64>,
    engine: &Engine,
) -> Result<f64, Failure> {
    let rpm = flag
        .or(diagram)
        .or(engine.operating().rpm)
        .ok_or_else(|| {
            Failure::usage(
                "no engine speed: give --rpm, a `# rpm = N` line in the diagram, or `rpm` in [operating]",
            )
        })?;
    if !(rpm.is_finite() && rpm > 0.0) {
        return Err(Failure::usage(format!(
            "--rpm {rpm}: a positive speed is needed"
        )));
    }
    Ok(rpm)
}

pub fn run(a: &RunArgs) -> Result<(), Failure> {
    if a.tolerance.is_some() {
        return Err(Failure::usage(
            "--tolerance needs the accuracy study, which this build does not have yet; choose the method with --step, --kinematics, --interp",
        ));
    }
    if let Some(angles) = &a.angles {
        return Err(Failure::usage(format!(
            "--angles {angles}: not supported by this build yet"
        )));
    }
    let step = a.method.step;
    if !(step.is_finite() && step > 0.0) {
        return Err(Failure::usage(format!(
            "--step {step}: a positive grid step in degrees is needed"
        )));
    }
    let loaded = load_engine(a.engine.as_deref())?;
    let engine = &loaded.engine;
    let cycle_deg = engine.cycle().to_degrees();
    let n = (cycle_deg / step).round();
    if (n * step - cycle_deg).abs() > 1e-9 * cycle_deg || n < 8.0 {
        return Err(Failure::usage(format!(
            "--step {step}: the step must divide the {cycle_deg}° cycle (0.1, 0.2, 0.25, 0.5, 1, …)"
        )));
    }
    let opts = a.method.options();
    if let Some(path) = &a.torque {
        let diagram = read_diagram(Some(path), engine, &a.diagram_args)?;
        let shown = path.display().to_string();
        if diagram.quantity == Quantity::Pressure {
            return Err(Failure::data(format!(
                "{shown}: a pressure diagram; --torque reads `crank_deg` with `torque_cylinder_nm` or `torque_engine_nm` (use --diagram for pressure)"
            )));
        }
        let rpm = resolve_rpm(a.rpm, diagram.rpm, engine)?;
        let resampled = enginedyn_ingest::resample(&diagram, step, opts.interp)
            .map_err(|e| Failure::data(format!("{shown}: {e}")))?;
        let analysis =
            enginedyn_pipeline::analyse_torque(engine, &resampled, diagram.quantity, rpm, &opts)
                .map_err(|e| Failure::usage(e.to_string()))?;
        return finish(a, engine, &shown, &analysis);
    }
    let diagram_path: Option<PathBuf> = match (a.diagram.as_slice(), &loaded.path) {
        ([], None) => None,
        ([], Some(p)) => Some(engine.diagram().map(Path::to_path_buf).ok_or_else(|| {
            Failure::usage(format!(
                "no indicator diagram: give --diagram or `diagram =` in {}",
                p.display()
            ))
        })?),
        ([one], _) => Some(one.clone()),
        (many, _) => {
            return Err(Failure::usage(format!(
                "{} diagrams given: one trace per cylinder is not supported by this build yet; give one diagram for all cylinders",
                many.len()
            )));
        }
    };
    let diagram = read_diagram(diagram_path.as_deref(), engine, &a.diagram_args)?;
    let rpm = resolve_rpm(a.rpm, diagram.rpm, engine)?;
    let shown = diagram_path
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "data/vaz2108.csv (bundled)".into());
    let resampled = enginedyn_ingest::resample(&diagram, step, opts.interp)
        .map_err(|e| Failure::data(format!("{shown}: {e}")))?;
    if diagram.quantity != Quantity::Pressure {
        return Err(Failure::data(format!(
            "{shown}: a turning-moment (torque) file: give it with --torque"
        )));
    }
    let analysis = enginedyn_pipeline::analyse(engine, &resampled, rpm, &opts)
        .map_err(|e| Failure::usage(e.to_string()))?;
    finish(a, engine, &shown, &analysis)
}

/// Prints and writes the results of one operating point.
fn finish(
    a: &RunArgs,
    engine: &Engine,
    shown: &str,
    analysis: &enginedyn_pipeline::Analysis,
) -> Result<(), Failure> {
    for note in &analysis.summary.notes {
        eprintln!("warning: {note}");
    }
    if a.json {
        let json = enginedyn_report::summary_json(&analysis.summary);
        crate::emit(&(serde_json::to_string_pretty(&json).unwrap_or_default() + "\n"));
    } else {
        crate::emit(&crate::table::summary_table(
            engine,
            shown,
            &analysis.summary,
        ));
    }
    if let Some(dir) = &a.out {
        let files = enginedyn_report::run_files(engine, analysis)
            .map_err(|e| Failure::data(e.to_string()))?;
        enginedyn_report::write_all(dir, &files).map_err(|e| Failure::data(e.to_string()))?;
        if !a.json {
            crate::emit(&format!(
                "wrote {} files to {}\n",
                files.len(),
                dir.display()
            ));
        }
    }
    Ok(())
}
