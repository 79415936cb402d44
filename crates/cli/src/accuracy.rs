//! `enginedyn accuracy` (INTERFACE.md): each method's error against the most
//! exact one and its run time, as a table, `accuracy.csv` and `accuracy.svg`.

use crate::Failure;
use crate::args::AccuracyArgs;
use enginedyn_session::{Input, Loaded};

/// What `accuracy --out DIR` writes.
const FILES: [&str; 2] = ["accuracy.csv", "accuracy.svg"];

/// Runs `enginedyn accuracy`.
pub fn run(a: &AccuracyArgs) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.input.engine)?;
    let engine = &loaded.engine;
    // Something in the way of an output is refused before the study runs.
    let out = crate::open_out(a.out.as_deref(), &FILES, "accuracy")?;
    let s = enginedyn_session::accuracy::study(
        &loaded,
        &a.diagram_args.reader(a.input.rpm),
        a.input.diagram.as_deref().map(Input::File),
    )?;
    if let Some(n) = &s.speed_note {
        crate::say(None, n);
    }
    for n in &s.study.notes {
        eprintln!("note: {n}");
    }
    crate::emit(&enginedyn_accuracy::table(&s.study, engine, s.rpm));
    if let Some(dir) = &out {
        let svg = enginedyn_accuracy::figure(&s.study, engine.name())
            .render()
            .map_err(|e| Failure::data(e.to_string()))?;
        let [csv, chart] = FILES.map(String::from);
        let files = vec![
            (csv, enginedyn_accuracy::csv(&s.study).into_bytes()),
            (chart, svg.into_bytes()),
        ];
        crate::write_out_to(dir, &files, false)?;
    }
    Ok(())
}
