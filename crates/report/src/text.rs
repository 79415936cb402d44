//! The printed tables' common parts: the heading every command's table
//! starts with, and `run`'s summary table.

use enginedyn_engine::Engine;
use enginedyn_numerics::format::human;
use enginedyn_pipeline::Summary;
use std::fmt::Write as _;

/// The first lines of every printed table: the engine, what was done
/// (`what`, e.g. "tolerance study, "; may be empty), the speed (none when
/// `rpm` is not finite) and the diagram.
pub fn heading(engine: &Engine, what: &str, rpm: f64, diagram: &str) -> String {
    let speed = if rpm.is_finite() {
        format!(", {} rpm", human(rpm.round()))
    } else {
        String::new()
    };
    format!(
        "{} — {what}{} {} {}-cylinder{speed}\ndiagram: {}\n",
        engine.name(),
        engine.stroke_kind().name(),
        engine.layout().name(),
        engine.cylinders(),
        // A file name on one line, control characters escaped.
        enginedyn_numerics::format::table_text(diagram),
    )
}

/// The summary as an aligned table, grouped as an engineer reads it (the
/// rows are [`crate::summary_rows`], the same the HTML page shows).
pub fn summary_table(engine: &Engine, diagram: &str, s: &Summary) -> String {
    let mut o = heading(engine, "", s.rpm, diagram);
    let _ = writeln!(
        o,
        "models: kinematics {}, rod {}, interpolation {}, step {}°, integration {}",
        s.kinematics, s.rod_model, s.interpolation, s.grid_step_deg, s.integration
    );
    let rows = crate::summary_rows(s);
    let width = rows
        .iter()
        .map(|r| r.label.chars().count())
        .max()
        .unwrap_or(0);
    let mut section = "";
    for row in rows {
        if row.section != section {
            section = row.section;
            let _ = writeln!(o, "\n{section}");
        }
        let line = format!("  {:<width$} {:>12} {}", row.label, row.shown(), row.unit);
        let _ = writeln!(o, "{}", line.trim_end());
    }

    o
}
