//! `enginedyn tolerance` (INTERFACE.md): each tolerance's influence on the
//! key results, their stack-up, and the Monte Carlo check; `--out DIR`
//! writes `tolerance.csv`, `tolerance.json` and `tolerance.svg`.

use crate::Failure;
use crate::args::ToleranceArgs;
use enginedyn_report::TOLERANCE_FILES as FILES;
use enginedyn_session::tolerance::{Tolerances, study};
use enginedyn_session::{Input, Loaded};

/// Runs `enginedyn tolerance`.
pub fn run(a: &ToleranceArgs) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.input.engine)?;
    let tolerances = Tolerances::of(&loaded)?;
    // Something in the way of an output is refused before the study runs
    // (and a file with nothing to study leaves no folder behind).
    let out = crate::open_out(a.out.as_deref(), &FILES, "tolerance")?;
    let t = study(
        &loaded,
        &tolerances,
        &a.diagram_args.reader(a.input.rpm),
        &a.method.method(None),
        a.input.diagram.as_deref().map(Input::File),
        a.samples as usize,
        a.seed,
    )?;
    let engine = &loaded.engine;
    crate::say_all(&t.study.notes);
    crate::emit(&enginedyn_report::tolerance_table(
        engine, &t.diagram, t.rpm, &t.study,
    ));
    if let Some(dir) = &out {
        let svg = enginedyn_report::tolerance_svg(engine, t.rpm, &t.study)
            .map_err(|e| Failure::data(e.to_string()))?;
        let json = serde_json::to_string_pretty(&enginedyn_report::tolerance_json(&t.study))
            .unwrap_or_default()
            + "\n";
        let [table, doc, chart] = FILES.map(String::from);
        let files = vec![
            (
                table,
                enginedyn_report::tolerance_csv(&t.study).into_bytes(),
            ),
            (doc, json.into_bytes()),
            (chart, svg.into_bytes()),
        ];
        crate::write_out_to(dir, &files, false)?;
    }
    Ok(())
}
