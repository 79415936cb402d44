//! `enginedyn report`: the engine design report (INTERFACE.md "The design
//! report"); the studies are `enginedyn_session::design`'s, the page
//! `enginedyn_report`'s.

use crate::Failure;
use crate::args::ReportArgs;
use enginedyn_session::Loaded;
use enginedyn_session::design::{Request, report};

/// Runs `enginedyn report`.
pub fn run(a: &ReportArgs) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.engine)?;
    // Something in the way of the page or the tables is refused before
    // the studies run.
    let out = crate::open_out(Some(&a.out), &["report.html"], "report")?
        .ok_or_else(|| Failure::usage("report needs --out DIR".to_string()))?;
    out.check_tables()?;
    let req = Request {
        diagram: a.diagram.as_deref(),
        rpm: a.rpm.as_deref(),
        load: a.load.as_deref(),
        parquet: a.parquet,
    };
    let r = report(
        loaded,
        a.diagram_args.reader(None),
        a.method.method(None),
        &req,
    )?;
    crate::say_all(&r.notes);
    let names: Vec<&str> = r.files.iter().map(|(n, _)| n.as_str()).collect();
    out.check::<&str, &str>(&names, &[])?;
    out.write_tables(&r.tables)?;
    for note in out.write(&r.files)? {
        crate::say(None, &note);
    }
    crate::emit(&r.text);
    crate::emit(&format!(
        "wrote report.html, {} charts and tables/ to {}\n",
        r.files.len() - 1,
        out.path().display()
    ));
    Ok(())
}
