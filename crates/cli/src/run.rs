//! `enginedyn run`: one operating point.

use crate::Failure;
use crate::args::RunArgs;
use enginedyn_session::{Input, Loaded, Session, shown_of};
use std::path::PathBuf;

pub fn run(a: &RunArgs) -> Result<(), Failure> {
    let loaded = Loaded::load(a.engine.as_deref())?;
    let method = a.method.method(a.tolerance);
    let session = Session::new(
        loaded,
        a.diagram_args.reader(a.rpm),
        method,
        enginedyn_pipeline::Scope::Full,
    )?;
    if let Some(path) = &a.torque {
        let outcome = session.analyse_torque(Input::File(path))?;
        let shown = path.display().to_string();
        return finish(a, &session, &shown, &[Input::File(path)], &outcome);
    }
    // An engine file and no --diagram: its `diagram`, else the diagram
    // synthesised from its [combustion] (the session decides).
    let fallback = match (a.diagram.as_slice(), &session.loaded.path) {
        ([], Some(_)) => Some(enginedyn_session::synth::default_diagram(
            &session.loaded,
            a.rpm,
            session.method.step(),
        )?),
        _ => None,
    };
    let files = match &fallback {
        Some(_) => Vec::new(),
        None => diagram_files(a, &session.loaded)?,
    };
    let inputs: Vec<Input<'_>> = match &fallback {
        Some(d) => vec![d.input()],
        None => files
            .iter()
            .map(|f| match f {
                Some(p) => Input::File(p),
                None => Input::Bundled(enginedyn_session::EXAMPLE),
            })
            .collect(),
    };
    let mut outcome = session.analyse(&inputs)?;
    if let Some(note) = fallback.as_ref().and_then(|d| d.note()) {
        outcome.analysis.summary.notes.insert(0, note.to_string());
    }
    if let Some(d) = &fallback {
        outcome.analysis.summary.design = d.design_summary();
        outcome
            .analysis
            .summary
            .notes
            .extend(d.warnings().iter().cloned());
    }
    finish(a, &session, &shown_of(&inputs), &inputs, &outcome)
}

/// The diagram files of `run` (`None`: the bundled example): one file, or
/// one per cylinder in order 1..z.
fn diagram_files(a: &RunArgs, loaded: &Loaded) -> Result<Vec<Option<PathBuf>>, Failure> {
    let z = loaded.engine.cylinders();
    match (a.diagram.as_slice(), &loaded.path) {
        ([], None) => Ok(vec![None]),
        ([], Some(_)) => Ok(vec![Some(enginedyn_session::diagram::diagram_path(
            None, loaded,
        )?)]),
        ([one], _) => Ok(vec![Some(one.clone())]),
        (many, _) => {
            if many.len() != z {
                return Err(Failure::usage(format!(
                    "{} diagrams given: several --diagram files are one trace per cylinder, and the engine has {z}",
                    many.len()
                )));
            }
            Ok(many.iter().cloned().map(Some).collect())
        }
    }
}

/// Prints and writes the results of one operating point.
fn finish(
    a: &RunArgs,
    session: &Session,
    shown: &str,
    files: &[Input<'_>],
    outcome: &enginedyn_session::Outcome,
) -> Result<(), Failure> {
    let loaded = &session.loaded;
    let engine = &loaded.engine;
    let analysis = &outcome.analysis;
    crate::say_all(&analysis.summary.notes);
    let inputs = enginedyn_session::inputs::of_hashed(loaded, files, &outcome.diagram_blake3)?;
    if a.json {
        let json = enginedyn_report::summary_json(&analysis.summary, &inputs);
        crate::emit(&(serde_json::to_string_pretty(&json).unwrap_or_default() + "\n"));
    } else {
        crate::emit(&enginedyn_report::summary_table(
            engine,
            shown,
            &analysis.summary,
        ));
    }
    if let Some(dir) = &a.out {
        let centered = a.angles == crate::args::Angles::Centered;
        let opts = &outcome.opts;
        // With a [tolerances] section the page carries the tolerance table.
        let text = &loaded.text;
        let mut extra = enginedyn_session::tolerance::report_extra(engine, text, analysis, *opts)?
            .unwrap_or_default();
        // With a [torsion] section, the torsional vibration too.
        if let Some(t) = enginedyn_session::torsion::report_extra(engine, text, analysis, *opts)? {
            extra.sections.extend(t.sections);
            extra.charts.extend(t.charts);
        }
        let files = enginedyn_report::run_files_with(engine, analysis, centered, &inputs, &extra)?;
        crate::write_out(dir, &files, a.json)?;
    }
    Ok(())
}
