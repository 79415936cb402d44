//! `enginedyn firing-orders` (INTERFACE.md): the even firing orders of the
//! engine's crank (or of every crank with `--all-cranks`), ranked; the study
//! is `enginedyn_session::firing`'s, its table, CSV, JSON and end view
//! `enginedyn_report`'s.

use crate::Failure;
use crate::args::FiringOrdersArgs;
use enginedyn_report::FIRING_FILES as FILES;
use enginedyn_session::Input;
use enginedyn_session::firing::{engine, study, weights};

/// Runs `enginedyn firing-orders`.
pub fn run(a: &FiringOrdersArgs) -> Result<(), Failure> {
    let weights = weights(a.weights.as_deref())?;
    let engine = engine(&a.input.engine, a.all_cranks)?;
    // Something in the way of an output is refused before the search.
    let out = crate::open_out(a.out.as_deref(), &FILES, "firing-orders")?;
    let f = study(
        &engine,
        &a.diagram_args.reader(a.input.rpm),
        &a.method.method(None),
        a.input.diagram.as_deref().map(Input::File),
        weights,
        a.all_cranks,
    )?;
    crate::say_all(&f.study.notes);
    if a.json {
        let doc = enginedyn_report::firing_json(&f.study, a.all_cranks);
        crate::emit(&(serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"));
    } else {
        crate::emit(&enginedyn_report::firing_table(
            &engine,
            &f.diagram,
            f.rpm,
            &weights,
            &f.study,
            a.all_cranks,
        ));
    }
    if let Some(dir) = &out {
        let svg = enginedyn_report::crank_end_view(&engine, &f.study)
            .render()
            .map_err(|e| Failure::data(e.to_string()))?;
        let [table, chart] = FILES.map(String::from);
        let files = vec![
            (table, enginedyn_report::firing_csv(&f.study).into_bytes()),
            (chart, svg.into_bytes()),
        ];
        crate::write_out_to(dir, &files, a.json)?;
    }
    Ok(())
}
