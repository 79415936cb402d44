//! `enginedyn accuracy` (INTERFACE.md): each method's error against the most
//! exact one and its run time, as a table, `accuracy.csv` and `accuracy.svg`.

use crate::Failure;
use crate::args::AccuracyArgs;
use enginedyn_accuracy::{Input, KEYS, pareto};
use enginedyn_ingest::{Interp, Quantity};
use enginedyn_session::Loaded;
use enginedyn_session::diagram::{diagram_options, diagram_path, parse_diagram};
use enginedyn_session::speed::resolve_rpm;
use std::fmt::Write as _;

/// Runs `enginedyn accuracy`.
/// What `accuracy --out DIR` writes.
const FILES: [&str; 2] = ["accuracy.csv", "accuracy.svg"];

pub fn run(a: &AccuracyArgs) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.input.engine)?;
    let engine = &loaded.engine;
    // Something in the way of an output is refused before the study runs.
    let out = crate::open_out(a.out.as_deref(), &FILES, "accuracy")?;
    let path = diagram_path(a.input.diagram.as_deref(), &loaded)?;
    let (parse, grid) = diagram_options(
        engine,
        &a.diagram_args.reader(a.input.rpm),
        0.1,
        Interp::Spline,
    )?;
    let diagram = parse_diagram(enginedyn_session::Input::File(&path), &parse)?;
    if diagram.quantity != Quantity::Pressure {
        return Err(Failure::data(format!(
            "{}: a turning-moment file; the accuracy study needs pressure",
            path.display()
        )));
    }
    let speed = resolve_rpm(a.input.rpm, diagram.rpm, engine)?;
    if let Some(n) = &speed.note {
        crate::say(None, n);
    }
    let rpm = speed.rpm;
    let input = Input {
        engine,
        diagram: &diagram,
        grid,
        rpm,
    };
    let study = enginedyn_accuracy::study(&input).map_err(|e| Failure::data(e.to_string()))?;
    for n in &study.notes {
        eprintln!("note: {n}");
    }
    let front = pareto(&study.rows);
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{} at {rpm} rpm: errors against exact kinematics, the {} rod, the periodic spline, 0.01° and the trapezoid rule (reference run {:.2} ms)\n",
        engine.name(),
        enginedyn_accuracy::best_rod(engine).name(),
        study.reference_time_s * 1e3
    );
    let _ = writeln!(
        t,
        "{:<14} {:<52} {:>10} {:>10}  worst key",
        "study", "setting", "time ms", "max error"
    );
    for (i, r) in study.rows.iter().enumerate() {
        let worst = r
            .errors
            .iter()
            .zip(KEYS)
            .filter_map(|(e, k)| Some((e.as_ref()?, k)))
            .max_by(|a, b| a.0.total_cmp(b.0))
            .map_or("", |(_, k)| *k);
        let _ = writeln!(
            t,
            "{:<14} {:<52} {:>10.3} {:>10}  {}{}",
            r.study.name(),
            r.setting,
            r.time_s * 1e3,
            r.max_relative_error()
                .map(|e| format!("{e:.1e}"))
                .unwrap_or_else(|| "-".into()),
            worst,
            if front.contains(&i) { "  (Pareto)" } else { "" }
        );
    }
    crate::emit(&t);
    if let Some(dir) = &out {
        let svg = enginedyn_accuracy::figure(&study, engine.name())
            .render()
            .map_err(|e| Failure::data(e.to_string()))?;
        let [csv, chart] = FILES.map(String::from);
        let files = vec![
            (csv, enginedyn_accuracy::csv(&study).into_bytes()),
            (chart, svg.into_bytes()),
        ];
        crate::write_out_to(dir, &files, false)?;
    }
    Ok(())
}
