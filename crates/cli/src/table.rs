//! The readable summary table printed by `run`.

use enginedyn_engine::Engine;
use enginedyn_pipeline::Summary;
use std::fmt::Write as _;

/// The first lines of every printed table: the engine, what was done
/// (`what`, e.g. "tolerance study, "; may be empty), the speed and the diagram.
pub fn heading(engine: &Engine, what: &str, rpm: f64, diagram: &str) -> String {
    let speed = if rpm.is_finite() {
        format!(", {} rpm", crate::human(rpm.round()))
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
/// rows are `report::summary_rows`, the same the HTML page shows).
pub fn summary_table(engine: &Engine, diagram: &str, s: &Summary) -> String {
    let mut o = heading(engine, "", s.rpm, diagram);
    let _ = writeln!(
        o,
        "models: kinematics {}, rod {}, interpolation {}, step {}°, integration {}",
        s.kinematics, s.rod_model, s.interpolation, s.grid_step_deg, s.integration
    );
    let rows = enginedyn_report::summary_rows(s);
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
