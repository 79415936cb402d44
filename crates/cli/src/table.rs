//! The readable summary table printed by `run`.

use enginedyn_engine::Engine;
use enginedyn_pipeline::Summary;
use std::fmt::Write as _;

/// The summary as an aligned table, grouped as an engineer reads it (the
/// rows are `report::summary_rows`, the same the HTML page shows).
pub fn summary_table(engine: &Engine, diagram: &str, s: &Summary) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{} — {} {} {}-cylinder, {:.0} rpm",
        engine.name(),
        engine.stroke_kind().name(),
        engine.layout().name(),
        engine.cylinders(),
        s.rpm
    );
    let _ = writeln!(o, "diagram: {diagram}");
    let _ = writeln!(
        o,
        "models: kinematics {}, rod {}, interpolation {}, step {}°, integration {}",
        s.kinematics, s.rod_model, s.interpolation, s.grid_step_deg, s.integration
    );
    let mut section = "";
    for row in enginedyn_report::summary_rows(s) {
        if row.section != section {
            section = row.section;
            let _ = writeln!(o, "\n{section}");
        }
        let _ = writeln!(o, "  {:<34} {:>16} {}", row.label, row.shown(), row.unit);
    }
    let _ = writeln!(
        o,
        "  {:<34} {:>16} (after throw)",
        "most loaded journal", s.journal_most_loaded
    );
    o
}
