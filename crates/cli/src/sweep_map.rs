//! `enginedyn sweep --rpm A:B:S --imep X:Y:Z`: a speed × load map from the
//! engine file's `[combustion]` (INTERFACE.md "Combustion"); the map is
//! `enginedyn_session::map`'s, its tables and chart `enginedyn_report`'s.

use crate::Failure;
use crate::args::SweepArgs;
use enginedyn_session::map::{Loads, SweepMap};
use enginedyn_session::{Loaded, Session};

const FILES: [&str; 2] = ["sweep.csv", "sweep.svg"];
/// The map's table in `--parquet DIR`.
pub const MAP_PARQUET: &str = "map.parquet";

/// A JSON array of objects already written as text, one a line.
fn json_array(objects: &[String]) -> String {
    let mut s = String::from("[");
    for (k, o) in objects.iter().enumerate() {
        s.push_str(if k == 0 { "\n" } else { ",\n" });
        s.push_str(o);
    }
    s.push_str("\n]\n");
    s
}

/// Runs the map and prints or writes it.
pub fn run(a: &SweepArgs) -> Result<(), Failure> {
    let shown_loads = a
        .map
        .imep
        .as_deref()
        .or(a.map.load.as_deref())
        .unwrap_or_default();
    let loads = match &a.map.load {
        Some(l) => Loads::Percent(enginedyn_session::options::load_range(l)?),
        None => Loads::Imep(enginedyn_session::options::imep_range(shown_loads)?),
    };
    run_loads(a, loads, shown_loads)
}

/// The map of `loads` (`shown_loads`: as the notes name them).
pub fn run_loads(a: &SweepArgs, loads: Loads, shown_loads: &str) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.engine)?;
    enginedyn_session::synth::spec(&loaded)?;
    let out = crate::open_out(a.out.as_deref(), &FILES, "sweep")?;
    // The table's place is checked before the map runs.
    let parquet = a
        .map
        .parquet
        .as_deref()
        .map(|d| enginedyn_report::Staged::new(d, MAP_PARQUET))
        .transpose()?;
    let session = Session::new(
        loaded,
        a.diagram_args.reader(None),
        a.method.method(None),
        enginedyn_pipeline::Scope::Summary,
    )?;
    let rpms = enginedyn_session::speed::speeds(&a.rpm)?;
    let map = session.sweep_map(&rpms, &loads, &a.rpm, shown_loads)?;
    if let Some(mut staged) = parquet {
        use std::io::Write as _;
        let bytes = map.parquet(&session)?;
        staged
            .write_all(&bytes)
            .map_err(|e| Failure::data(format!("{}: {e}", staged.path().display())))?;
        let path = staged.path().to_path_buf();
        staged.commit()?;
        eprintln!("wrote {}", path.display());
    }
    crate::say_all(&map.notes);
    // The points' notes grouped by kind, one line a kind.
    let names: Vec<String> = map
        .points
        .iter()
        .map(|p| {
            format!(
                "{}, {} rpm",
                p.load_name(),
                crate::human(p.point.summary.rpm)
            )
        })
        .collect();
    crate::say_grouped(
        names
            .iter()
            .zip(&map.points)
            .map(|(n, p)| (n.as_str(), p.point.summary.notes.as_slice())),
        "points",
        false,
    );
    let engine = session.engine();
    let csv = map.csv();
    let json = if a.json {
        let each = map
            .points
            .iter()
            .zip(&map.diagrams_for_points())
            .map(|(p, d)| {
                let mut doc = enginedyn_report::summary_json(&p.point.summary, &d.inputs);
                if let Some(o) = doc.as_object_mut() {
                    for (k, v) in map.point_keys(p) {
                        o.insert(k.into(), v.into());
                    }
                }
                serde_json::to_string(&doc).unwrap_or_default()
            })
            .collect::<Vec<String>>();
        Some(json_array(&each))
    } else {
        None
    };
    match &out {
        Some(dir) => {
            let per_load: Vec<(f64, Vec<&enginedyn_pipeline::Summary>)> = map
                .loads
                .values()
                .iter()
                .enumerate()
                .map(|(l, &v)| {
                    let ss = map
                        .points
                        .iter()
                        .filter(|p| p.load == l)
                        .map(|p| &p.point.summary)
                        .collect();
                    (v, ss)
                })
                .collect();
            let fig = enginedyn_report::sweep_map_figure(engine.name(), &per_load);
            let svg = fig.render().map_err(|e| Failure::data(e.to_string()))?;
            let [table, chart] = FILES.map(String::from);
            for note in dir.write(&[(table, csv.into_bytes()), (chart, svg.into_bytes())])? {
                crate::say(None, &note);
            }
            eprintln!(
                "{} speeds × {} loads; wrote sweep.csv and sweep.svg to {}",
                map.rpms.len(),
                map.loads.values().len(),
                dir.path().display()
            );
            if let Some(json) = &json {
                crate::emit(json);
            }
        }
        None if a.json => crate::emit(&json.unwrap_or_default()),
        None if a.csv => crate::emit(&csv),
        None => crate::emit(&table_text(engine, &map)),
    }
    Ok(())
}

/// The readable table: a row per load and speed.
fn table_text(engine: &enginedyn_engine::Engine, map: &SweepMap) -> String {
    let rows: Vec<enginedyn_report::KeyRow> = map
        .points
        .iter()
        .map(|p| enginedyn_report::KeyRow {
            name: format!(
                "{}, {} rpm",
                p.load_name(),
                crate::human(p.point.summary.rpm)
            ),
            figures: Some(enginedyn_report::key_figures(
                &enginedyn_report::SWEEP_FIGURES,
                &p.point.summary,
            )),
            error: String::new(),
            folder: None,
        })
        .collect();
    let mut text = enginedyn_report::heading(
        engine,
        "sweep over speed and load, ",
        f64::NAN,
        "synthesised from [combustion]",
    );
    if let Some((rpm, imep)) = map.sized_at {
        text.push_str(&format!(
            "flywheel sized once at {} rpm and IMEP {} bar (the point that needs the most); δ is what it gives at each point\n",
            crate::human(rpm),
            crate::human(imep)
        ));
    }
    text.push('\n');
    text.push_str(&enginedyn_report::key_table(
        "IMEP target, speed",
        &enginedyn_report::SWEEP_FIGURES,
        &rows,
        enginedyn_report::effective_of(engine),
    ));
    text
}
