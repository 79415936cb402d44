//! `enginedyn torsion`: the crankshaft's torsional vibration (INTERFACE.md,
//! "Torsion"); the study is `enginedyn_session::torsion`'s, its tables and
//! charts `enginedyn_report`'s.

use crate::Failure;
use crate::args::TorsionArgs;
use enginedyn_report::TORSION_FILES as FILES;
use enginedyn_session::{Input, Loaded};

/// Runs `enginedyn torsion`.
pub fn run(a: &TorsionArgs) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.engine)?;
    let engine = &loaded.engine;
    // Something in the way of an output is refused before the study runs.
    let mut names = FILES.to_vec();
    if a.chain {
        names.push("chain.json");
    }
    let out = crate::open_out(a.out.as_deref(), &names, "torsion")?;
    let spec = enginedyn_session::torsion::spec(&loaded)?;
    let rpms = a
        .rpm
        .as_deref()
        .map(enginedyn_session::speed::speeds)
        .transpose()?;
    let t = enginedyn_session::torsion::study(
        &loaded,
        &spec,
        &a.diagram_args.reader(None),
        &a.method.method(None),
        a.diagram.as_deref().map(Input::File),
        rpms,
    )?;
    // Implausible values first, as warnings (they may mean a wrong
    // result), then what was assumed.
    crate::say_all(&t.warnings);
    crate::say_all(&t.notes);
    let doc = enginedyn_report::torsion_json(engine, &t.study, &t.opts, &t.all_notes());
    let text = serde_json::to_string_pretty(&doc).map_err(|e| Failure::data(e.to_string()))?;
    if let Some(dir) = &out {
        let mut files = vec![
            (
                "modes.csv".to_string(),
                enginedyn_report::modes_csv(&t.study).into_bytes(),
            ),
            (
                "torsion.csv".to_string(),
                enginedyn_report::torsion_csv(&t.study).into_bytes(),
            ),
            ("torsion.json".to_string(), format!("{text}\n").into_bytes()),
        ];
        let charts = enginedyn_report::torsion_charts(engine.name(), &t.study)
            .map_err(|e| Failure::data(e.to_string()))?;
        files.extend(charts.into_iter().map(|(f, svg)| (f, svg.into_bytes())));
        if a.chain {
            let chain = enginedyn_report::chain_json(&enginedyn_session::torsion::chain_dump(&t)?)
                .map_err(|e| Failure::data(e.to_string()))?;
            files.push(("chain.json".to_string(), chain.into_bytes()));
        }
        crate::write_out_to(dir, &files, a.json)?;
    }
    if a.json {
        crate::emit(&format!("{text}\n"));
    } else if a.out.is_none() {
        crate::emit(&enginedyn_report::torsion_table(&t.study));
    }
    Ok(())
}
