//! Results out: `summary.json`, `curves.csv`, `harmonics.csv` and SVG charts
//! (plotters, SVG backend only, no system fonts), written atomically: every
//! file of an output folder appears whole or not at all.
//!
//! ```no_run
//! # fn demo(engine: &enginedyn_engine::Engine, a: &enginedyn_pipeline::Analysis) {
//! let inputs = enginedyn_report::Inputs::new(
//!     enginedyn_report::Source::File("engine.toml".as_ref()),
//!     &[enginedyn_report::Source::File("diagram.csv".as_ref())],
//! )
//! .unwrap();
//! let files = enginedyn_report::run_files(engine, a, false, &inputs).unwrap();
//! enginedyn_report::write_all(std::path::Path::new("out"), &files).unwrap();
//! # }
//! ```

use enginedyn_engine::Engine;
use enginedyn_numerics::format::csv_text;
use enginedyn_pipeline::schema::{self, Cell, Group};
use enginedyn_pipeline::{Analysis, Summary, Value};
use std::path::{Path, PathBuf};

mod chart;
mod combustion;
mod contour;
mod design;
mod firing;
mod html;
mod kinematics;
mod out;
mod tables;
mod text;
mod tolerance;
mod tornado;
mod torsion;
mod torsion_tables;
pub use chart::{
    Chart, Figure, RUN_CHARTS, ScatterChart, ScatterGroup, ScatterLayout, ScatterPoint, Series,
    kinematics_chart, periodic, run_figures, run_figures_with, tick_label,
};
pub use combustion::{combustion_figures, combustion_section};
pub use contour::{ContourChart, Mark, Node, band, iso_segment, levels, scale_colour, triangles};
pub use design::{
    DesignPage, Headline, MapView, Section, crank_train, design_html, firing_ranking,
    full_load_figure, full_load_table, map_contours, shown, table_csv, tables_readme, text_table,
};
pub use firing::{FIRING_FILES, crank_end_view, firing_csv, firing_json, firing_table};
pub use html::{engine_rows, esc, percent_encode, report_html, table as html_table};
pub use kinematics::{KINEMATICS_FILES, kinematics_csv, kinematics_svg, kinematics_table};
pub use out::{
    LOCK_WAIT, MANIFEST, MAX_OUTPUT_READ, OutDir, STAGING_PREFIX, Staged, TABLES, TABLES_MARKER,
    blake3_file, blake3_hex, check_marked, injected_failure, read_output, replace_file,
    replace_marked_file, sha256_file, sha256_hex,
};
pub use tables::{
    KEY_FIGURES, KeyRow, SWEEP_FIGURES, count, index_html, key_figures, key_heading, key_table,
    sweep_figure, sweep_map_figure,
};
pub use text::{heading, summary_table};
pub use tolerance::{
    TOLERANCE_FILES, tolerance_csv, tolerance_extra, tolerance_json, tolerance_panels,
    tolerance_svg, tolerance_table,
};
pub use tornado::{TornadoBar, TornadoPanel, tornado_svg};
pub use torsion::{
    CampbellChart, CampbellLayout, CampbellMark, LABEL_GAP, Leader, PlacedLabel, segment_hits,
    torsion_charts, torsion_response,
};
pub use torsion_tables::{
    ChainCheck, ChainDump, TORSION_FILES, chain_json, modes_csv, torsion_csv, torsion_extra,
    torsion_json, torsion_table,
};

/// Why output could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Writing a file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Reading an input file (to record its hash) failed.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Another command is writing the folder.
    #[error(
        "{}: another enginedyn command is writing this folder (waited {} s for it): let it finish, or choose another --out",
        path.display(),
        waited.as_secs()
    )]
    Locked {
        /// The folder.
        path: PathBuf,
        /// How long this command waited.
        waited: std::time::Duration,
    },
    /// Something not enginedyn's is where an output goes: it is never
    /// moved or removed, and nothing is written.
    #[error(
        "{}: {what} is in the way; enginedyn replaces only a file it wrote{}, never anything else, so nothing was written: move it away or choose another --out",
        path.display(),
        if *run_folder { " or a run folder holding an earlier run's summary.json" } else if *tables { " or a tables folder holding an earlier report's README.txt" } else { "" }
    )]
    InTheWay {
        /// What is in the way.
        path: PathBuf,
        /// What it is: "a folder", "a symbolic link", "a FIFO", "a read-only file", …
        what: &'static str,
        /// Whether a batch's run folder goes there.
        run_folder: bool,
        /// Whether the design report's `tables` folder goes there.
        tables: bool,
    },
    /// A chart could not be drawn.
    #[error("chart {name}: {message}")]
    Chart {
        /// The chart's file name.
        name: String,
        /// What plotters said.
        message: String,
    },
}

/// What a result came from (`summary.json`'s `inputs`): the engine file
/// and the diagram (or torque) files as given, their BLAKE3 hashes, and
/// the version of enginedyn. No date: a rerun is byte-identical.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Inputs {
    /// The engine file's path as given, or `bundled` for the bundled example.
    pub engine_file: String,
    /// The BLAKE3 of the engine file's bytes (of the bundled TOML text).
    pub engine_blake3: String,
    /// The diagram files' paths as given (`bundled` for the bundled one).
    pub diagram_files: Vec<String>,
    /// Their BLAKE3 hashes, in the same order.
    pub diagram_blake3: Vec<String>,
    /// The version of enginedyn that computed the result.
    pub enginedyn_version: &'static str,
}

/// Where an input came from: a file, or text bundled into the binary.
#[derive(Debug, Clone, Copy)]
pub enum Source<'a> {
    /// A file, named as the user gave it.
    File(&'a Path),
    /// The bundled example's text.
    Bundled(&'a [u8]),
    /// Text given in memory (an engine from a string, arrays), under the
    /// name `inputs` gives it.
    Text(&'a str, &'a [u8]),
    /// A file already hashed as it was read (BLAKE3 in hex): not read again.
    Hashed(&'a Path, &'a str),
}

impl Source<'_> {
    /// The name `inputs` gives it and its hash (the file read now).
    fn record(&self) -> Result<(String, String), ReportError> {
        Ok(match self {
            Source::File(p) => (p.display().to_string(), out::blake3_file(p)?),
            Source::Bundled(text) => ("bundled".to_string(), out::blake3_hex(text)),
            Source::Text(name, text) => (name.to_string(), out::blake3_hex(text)),
            Source::Hashed(p, hash) => (p.display().to_string(), hash.to_string()),
        })
    }
}

impl Inputs {
    /// The record of `engine` and `diagrams` (each file read and hashed).
    pub fn new(engine: Source<'_>, diagrams: &[Source<'_>]) -> Result<Self, ReportError> {
        let (engine_file, engine_blake3) = engine.record()?;
        Self {
            engine_file,
            engine_blake3,
            diagram_files: Vec::new(),
            diagram_blake3: Vec::new(),
            enginedyn_version: env!("CARGO_PKG_VERSION"),
        }
        .with_diagrams(diagrams)
    }

    /// The same engine with other diagrams (a batch's files: the engine
    /// hashed once).
    pub fn with_diagrams(&self, diagrams: &[Source<'_>]) -> Result<Self, ReportError> {
        let (diagram_files, diagram_blake3) = diagrams
            .iter()
            .map(Source::record)
            .collect::<Result<Vec<_>, _>>()?
            .into_iter()
            .unzip();
        Ok(Self {
            diagram_files,
            diagram_blake3,
            ..self.clone()
        })
    }

    /// `inputs` as `summary.json` writes it.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "engine_file": self.engine_file,
            "engine_blake3": self.engine_blake3,
            "diagram_files": self.diagram_files,
            "diagram_blake3": self.diagram_blake3,
            "enginedyn_version": self.enginedyn_version,
        })
    }
}

/// The summary as a JSON object, keys in INTERFACE.md's order, `inputs`
/// right after `notes`. Non-finite numbers never reach the output: they
/// become `null`.
pub fn summary_json(summary: &Summary, inputs: &Inputs) -> serde_json::Value {
    fn conv(v: &Value) -> serde_json::Value {
        match v {
            Value::Num(Some(x)) if x.is_finite() => serde_json::Value::from(*x),
            Value::Num(_) => serde_json::Value::Null,
            Value::Int(i) => serde_json::Value::from(*i),
            Value::Text(s) => serde_json::Value::from(*s),
            Value::Str(s) => serde_json::Value::from(s.as_str()),
            Value::List(l) => serde_json::Value::from(l.clone()),
            Value::Map(m) => {
                serde_json::Value::Object(m.iter().map(|(k, v)| (k.to_string(), conv(v))).collect())
            }
        }
    }
    let mut o = serde_json::Map::new();
    for (k, v) in summary.fields() {
        o.insert(k.to_string(), conv(&v));
        if k == "notes" {
            o.insert("inputs".to_string(), inputs.json());
        }
    }
    if !o.contains_key("inputs") {
        o.insert("inputs".to_string(), inputs.json());
    }
    serde_json::Value::Object(o)
}

/// The fixed columns of `summary.csv` after `file` and `error`: the summary
/// keys of INTERFACE.md in their order, `models` flattened (the columns of
/// [`schema::SUMMARY`] that are neither the row's own, provenance nor
/// optional).
pub fn summary_columns() -> Vec<String> {
    schema::SUMMARY
        .iter()
        .filter(|c| c.group > Group::Provenance && !c.group.optional())
        .map(|c| c.name.to_string())
        .collect()
}

/// A value as a `summary.csv` cell: null as an empty cell, numbers in
/// shortest round-trip form, text as
/// [`enginedyn_numerics::format::csv_text`] writes it (never a formula).
fn csv_cell(c: &Cell<'_>) -> String {
    match c {
        Cell::Float(x) => enginedyn_numerics::format::csv(*x),
        Cell::Int(i) => i.to_string(),
        Cell::Bool(b) => b.to_string(),
        Cell::Text(t) => csv_text(t).into_owned(),
        Cell::Floats(v) => v
            .iter()
            .map(|x| enginedyn_numerics::format::csv(*x))
            .collect::<Vec<_>>()
            .join(" "),
        Cell::Null | Cell::Absent => String::new(),
    }
}

/// The summary as (column, cell) pairs, from [`schema::SUMMARY`]: `models`
/// and `pegging` flattened to `models.kinematics` …, `notes` joined with
/// ` | `, cells as `summary.csv` writes them. Fixed keys first, then the
/// optional keys present.
pub fn flatten(s: &Summary) -> Vec<(String, String)> {
    let record = schema::SummaryRecord::of(s);
    let mut cells: Vec<(String, String)> = schema::SUMMARY
        .iter()
        // The level lists are `caK_deg` columns here (below).
        .filter(|c| c.group > Group::Provenance && c.ty != schema::ColumnType::Float64List)
        .filter_map(|c| {
            let cell = c.cell(&record);
            (cell != Cell::Absent).then(|| (c.name.to_string(), csv_cell(&cell)))
        })
        .collect();
    // The burn levels asked for beyond the four fixed ones (`--burn-points
    // 3,7,33`): `caK_deg`, as in `summary.json`.
    cells.extend(
        enginedyn_pipeline::combustion::extra_levels(s)
            .map(|(key, deg)| (key.to_string(), csv_cell(&Cell::num(deg)))),
    );
    cells
}

/// One row of `summary.csv`: the file, its error (empty when it ran), and
/// its flattened summary (empty when it failed).
pub type CsvRow = (String, String, Vec<(String, String)>);

/// Writes `summary.csv`: `file`, `error`, the fixed columns, then every
/// optional column any row has (in order of first appearance). Rows are
/// (file, error, flattened summary or empty); the file and error cells are
/// written as [`enginedyn_numerics::format::csv_text`] writes text.
pub fn summary_csv(rows: &[CsvRow]) -> String {
    let mut columns = summary_columns();
    for (_, _, r) in rows {
        for (k, _) in r {
            if !columns.contains(k) {
                columns.push(k.clone());
            }
        }
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    // `file` and `error`, the row's own columns.
    let mut header: Vec<String> = schema::SUMMARY
        .iter()
        .filter(|c| c.group == Group::Row)
        .map(|c| c.name.to_string())
        .collect();
    header.extend(columns.iter().cloned());
    let _ = w.write_record(&header);
    for (file, error, r) in rows {
        let mut rec = vec![csv_text(file).into_owned(), csv_text(error).into_owned()];
        for c in &columns {
            rec.push(
                r.iter()
                    .find(|(k, _)| k == c)
                    .map(|(_, v)| v.clone())
                    .unwrap_or_default(),
            );
        }
        let _ = w.write_record(&rec);
    }
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}

/// One line of the readable summary (the printed table and the HTML page).
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The summary key it shows.
    pub key: &'static str,
    /// Section heading the row belongs to.
    pub section: &'static str,
    /// What it is, as an engineer names it, with "indicated" or
    /// "effective (η_m = 0.80)" for torque and power.
    pub label: String,
    /// The value in `unit`, `None` when it does not exist for the case.
    pub value: Option<f64>,
    /// Display unit.
    pub unit: &'static str,
    /// Decimals shown.
    pub digits: usize,
}

impl Row {
    /// The value as shown: fixed decimals (never `-0.00`), or scientific
    /// for the tiny energy-balance error; `—` when absent.
    pub fn shown(&self) -> String {
        match self.value {
            None => "—".to_string(),
            Some(x) => fixed(x, self.digits),
        }
    }
}

pub use enginedyn_numerics::format::{fixed, human};

/// The label of a shown key: "mean torque, effective (η_m = 0.80)" (or
/// "…, brake (Chen–Flynn friction)" with `[friction]`) and "mean torque,
/// indicated" for torque and power, the plain label else.
pub fn label(shown: &enginedyn_pipeline::Shown, s: &Summary) -> String {
    use enginedyn_pipeline::Basis;
    match shown.basis {
        Basis::None => shown.label.to_string(),
        Basis::Indicated => format!("{}, indicated", shown.label),
        Basis::Effective => format!("{}, {}", shown.label, effective(s)),
    }
}

/// What the effective torque and power of `s` are: "brake (Chen–Flynn
/// friction)" with the engine file's `[friction]`, else "effective (η_m =
/// 0.80)".
pub fn effective(s: &Summary) -> String {
    if s.brake.is_some() {
        "brake (Chen–Flynn friction)".to_string()
    } else {
        format!("effective (η_m = {:.2})", s.mechanical_efficiency)
    }
}

/// The basis of the effective figures of `engine`'s runs, as the readable
/// tables take it: `None` with `[friction]` (the brake figures), else
/// `operating.mechanical_efficiency`.
pub fn effective_of(engine: &Engine) -> Option<f64> {
    match engine.friction() {
        Some(_) => None,
        None => Some(engine.operating().mechanical_efficiency),
    }
}

/// The summary as labelled rows in display units, grouped by section: the
/// one list both the printed table and `report.html` show, built from
/// [`enginedyn_pipeline::KEYS`] (optional keys only when present).
pub fn summary_rows(s: &Summary) -> Vec<Row> {
    enginedyn_pipeline::KEYS
        .iter()
        .filter_map(|k| {
            let shown = k.shown.as_ref()?;
            // Absent optional keys and non-numbers have no row; a null has one.
            let value = (k.get)(s)?.as_number()?;
            Some(Row {
                key: k.key,
                section: shown.section,
                label: label(shown, s),
                value: value.map(|v| v * shown.scale),
                unit: shown.unit,
                digits: shown.digits,
            })
        })
        .collect()
}

/// Formats a number for CSV: shortest round-trip form, exponent notation
/// only for tiny and huge magnitudes.
fn num(out: &mut String, x: f64) {
    enginedyn_numerics::format::csv_into(out, x);
}

/// `curves.csv`: one row per grid angle of cylinder 1 over the cycle. Columns
/// that do not exist for the case (the pressure and force columns of a
/// turning-moment run) are empty cells. `centered` writes the angles in
/// `[-cycle/2, cycle/2)`, rows from `-cycle/2`, as indicating software shows them.
pub fn curves_csv(a: &Analysis, centered: bool) -> String {
    let n = a.torque.total.len();
    let mut s = String::with_capacity(n * 420);
    s.push_str(&curve_names(a).join(","));
    s.push('\n');
    let mut row = Vec::new();
    for row_index in 0..n {
        curve_row(a, row_index, centered, &mut row);
        for (i, x) in row.iter().enumerate() {
            if i > 0 {
                s.push(',');
            }
            if let Some(x) = x {
                num(&mut s, *x);
            }
        }
        s.push('\n');
    }
    s
}

/// The columns of `curves.csv`, in its order.
pub fn curve_names(a: &Analysis) -> Vec<String> {
    let mut names: Vec<String> = [
        "crank_deg",
        "pressure_bar",
        "volume_m3",
        "piston_x_m",
        "piston_v_m_s",
        "piston_a_m_s2",
        "rod_angle_deg",
        "force_gas_n",
        "force_inertia_n",
        "force_total_n",
        "force_side_n",
        "force_rod_n",
        "force_radial_n",
        "force_tangential_n",
        "crankpin_load_n",
        "crankpin_load_angle_deg",
        "torque_cylinder_nm",
        "torque_engine_nm",
        "excess_energy_j",
    ]
    .map(String::from)
    .to_vec();
    names.extend((1..=a.torque.journals.len()).map(|k| format!("torque_journal_{k}_nm")));
    names.extend((1..=a.bearings.len()).map(|k| format!("main_bearing_{k}_n")));
    names.extend((1..=a.torque.crankpins.len()).map(|k| format!("torque_crankpin_{k}_nm")));
    if a.flywheel.is_some() {
        names.push("speed_rad_s".into());
    }
    if a.heat_release.is_some() {
        names.extend(["heat_release_rate_j_deg", "heat_release_j", "mfb"].map(String::from));
    }
    names
}

/// The columns of `curves.csv` as numbers, NaN where its cell is empty
/// (the same values, bit for bit, as the file holds).
pub fn curve_columns(a: &Analysis, centered: bool) -> Vec<(String, Vec<f64>)> {
    let names = curve_names(a);
    let n = a.torque.total.len();
    let mut columns = vec![Vec::with_capacity(n); names.len()];
    let mut row = Vec::new();
    for row_index in 0..n {
        curve_row(a, row_index, centered, &mut row);
        for (c, x) in columns.iter_mut().zip(&row) {
            c.push(x.unwrap_or(f64::NAN));
        }
    }
    names.into_iter().zip(columns).collect()
}

/// Row `row_index` of `curves.csv` into `row` (`None`: an empty cell).
fn curve_row(a: &Analysis, row_index: usize, centered: bool, row: &mut Vec<Option<f64>>) {
    let n = a.torque.total.len();
    let w = a.summary.omega_rad_s;
    let f = &a.forces;
    let kin = &a.kinematics;
    let at = |v: &[f64], k: usize| v.get(k).copied();
    let cycle = (n as f64 * a.step).to_degrees();
    let k = if centered {
        (row_index + n / 2) % n
    } else {
        row_index
    };
    let mut angle = (k as f64 * a.step).to_degrees();
    if centered && k >= n / 2 {
        angle -= cycle;
    }
    row.clear();
    row.extend([
        Some(round_angle(angle)),
        at(&a.pressure, k).map(|p| p / 1e5),
        at(&a.volume, k),
        at(&kin.x, k),
        at(&kin.dx, k).map(|v| v * w),
        at(&kin.d2x, k).map(|v| v * w * w),
        at(&kin.beta, k).map(f64::to_degrees),
        at(&f.gas, k),
        at(&f.inertia, k),
        at(&f.total, k),
        at(&f.side, k),
        at(&f.rod, k),
        at(&f.radial, k),
        at(&f.tangential, k),
        at(&f.pin_load, k),
        (k < f.pin_radial.len()).then(|| f.pin_angle_deg(k)),
        at(&a.cylinder_torque, k),
        at(&a.torque.total, k),
        at(&a.uniformity.excess_energy, k),
    ]);
    row.extend(
        a.torque
            .journals
            .iter()
            .chain(&a.bearings)
            .chain(&a.torque.crankpins)
            .map(|j| at(j, k))
            .chain(a.flywheel.iter().map(|fw| at(&fw.speed, k))),
    );
    if let Some(h) = &a.heat_release {
        row.extend([
            at(&h.rate_j_deg, k),
            at(&h.cumulative_j, k),
            h.mfb.as_ref().and_then(|m| at(m, k)),
        ]);
    }
}

/// Grid angles are printed without binary noise (0.30000000000000004 → 0.3).
fn round_angle(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}

/// `harmonics.csv`: amplitude and phase by engine order (cylinder columns
/// empty when only the engine torque is known).
pub fn harmonics_csv(a: &Analysis) -> String {
    let mut s = HARMONIC_NAMES.join(",");
    s.push('\n');
    for row in harmonic_rows(a) {
        for (i, x) in row.iter().enumerate() {
            if i > 0 {
                s.push(',');
            }
            if let Some(x) = x {
                num(&mut s, *x);
            }
        }
        s.push('\n');
    }
    s
}

/// The columns of `harmonics.csv`.
pub const HARMONIC_NAMES: [&str; 5] = [
    "order",
    "cylinder_amplitude_nm",
    "cylinder_phase_deg",
    "engine_amplitude_nm",
    "engine_phase_deg",
];

/// The rows of `harmonics.csv` (`None`: an empty cell).
pub fn harmonic_rows(a: &Analysis) -> impl Iterator<Item = [Option<f64>; 5]> + '_ {
    a.engine_harmonics.iter().enumerate().map(|(i, e)| {
        let c = a.cylinder_harmonics.get(i);
        [
            Some(e.order),
            c.map(|c| c.amplitude),
            c.map(|c| c.phase.to_degrees()),
            Some(e.amplitude),
            Some(e.phase.to_degrees()),
        ]
    })
}

/// Every file of `run --out DIR`, as (name, contents); `centered` as in
/// [`curves_csv`], for the charts' angle axes too; `inputs` what the
/// results came from.
pub fn run_files(
    engine: &Engine,
    a: &Analysis,
    centered: bool,
    inputs: &Inputs,
) -> Result<Vec<(String, Vec<u8>)>, ReportError> {
    run_files_with(engine, a, centered, inputs, &Extra::default())
}

/// What a run folder holds besides the standard files: page sections
/// (heading, HTML body) and charts (file name, SVG text), such as the
/// tolerance table and its tornado chart.
#[derive(Debug, Clone, Default)]
pub struct Extra {
    /// (heading, HTML body) sections placed before the charts.
    pub sections: Vec<(String, String)>,
    /// (file name, SVG text) charts written and shown after the standard ones.
    pub charts: Vec<(String, String)>,
}

/// [`run_files`] with extra sections and charts.
pub fn run_files_with(
    engine: &Engine,
    a: &Analysis,
    centered: bool,
    inputs: &Inputs,
    extra: &Extra,
) -> Result<Vec<(String, Vec<u8>)>, ReportError> {
    let json =
        serde_json::to_string_pretty(&summary_json(&a.summary, inputs)).unwrap_or_default() + "\n";
    let mut files = vec![
        ("summary.json".to_string(), json.into_bytes()),
        (
            "curves.csv".to_string(),
            curves_csv(a, centered).into_bytes(),
        ),
        ("harmonics.csv".to_string(), harmonics_csv(a).into_bytes()),
    ];
    let mut charts = Vec::new();
    for fig in chart::run_figures_with(engine, a, centered)
        .into_iter()
        .chain(combustion::combustion_figures(engine, a))
    {
        charts.push((fig.file.clone(), fig.render()?));
    }
    charts.extend(extra.charts.iter().cloned());
    let sections: Vec<(String, String)> = combustion::combustion_section(a)
        .into_iter()
        .chain(extra.sections.iter().cloned())
        .collect();
    files.push((
        "report.html".to_string(),
        html::report_html(engine, a, inputs, &sections, &charts).into_bytes(),
    ));
    for (name, svg) in charts {
        files.push((name, svg.into_bytes()));
    }
    Ok(files)
}

/// Writes the files of one operating point into `dir` as `run --out DIR`
/// does (and Python's `Result.to_folder`, the same function): through an
/// [`OutDir`] of the command `run`, every file checked, staged, then moved
/// into place, nothing in the way (a link, a folder, a read-only file)
/// ever replaced. Returns the notes [`OutDir::write`] returns.
pub fn write_run(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<Vec<String>, ReportError> {
    OutDir::open(dir)?.for_command("run").write(files)
}

/// Writes `files` (name, bytes) into `dir` through an [`OutDir`]: locked,
/// staged, each file whole or not at all. Commands that write several times
/// (a batch) open the [`OutDir`] once and keep it.
/// Returns the notes [`OutDir::write`] returns.
pub fn write_all(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<Vec<String>, ReportError> {
    OutDir::open(dir)?.write(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `flatten` (from the schema) gives the cells the summary's fields
    /// (`KEYS`) give, flattened as `summary.csv` always wrote them: every
    /// subset of the optional keys, nulls, text and a non-finite number.
    #[test]
    fn flatten_is_the_summary_fields_flattened() {
        fn by_keys(s: &Summary) -> Vec<(String, String)> {
            fn cell(v: &Value) -> String {
                match v {
                    Value::Num(Some(x)) if x.is_finite() => enginedyn_numerics::format::csv(*x),
                    Value::Num(_) | Value::Map(_) => String::new(),
                    Value::Int(i) => i.to_string(),
                    Value::Text(t) => csv_text(t).into_owned(),
                    Value::Str(t) => csv_text(t).into_owned(),
                    Value::List(l) => csv_text(&l.join(" | ")).into_owned(),
                }
            }
            let mut out = Vec::new();
            for (k, v) in s.fields() {
                match &v {
                    Value::Map(m) => {
                        out.extend(m.iter().map(|(f, v)| (format!("{k}.{f}"), cell(v))))
                    }
                    _ => out.push((k.to_string(), cell(&v))),
                }
            }
            out
        }
        for mask in 0..32u32 {
            let mut s = Summary::empty();
            s.rpm = 2200.0;
            s.imep_bar = Some(f64::NAN);
            s.mean_torque_nm = Some(-1.5e-7);
            s.journal_most_loaded = 3;
            s.kinematics = "exact";
            s.notes = vec!["=x".into(), "y".into()];
            if mask & 1 != 0 {
                s.cycles = Some(20);
                s.cycles_skipped = Some(2);
            }
            if mask & 2 != 0 {
                s.cycle_stats = Some(enginedyn_pipeline::CycleSummary {
                    cycles: 20,
                    imep_std_bar: None,
                    imep_cov: Some(0.02),
                    p_max_mean_bar: 55.0,
                    p_max_cov: 0.03,
                    p_max_angle_mean_deg: 11.5,
                    p_max_angle_std_deg: 0.7,
                });
            }
            if mask & 4 != 0 {
                s.pegging = Some(enginedyn_pipeline::Pegging {
                    method: "polytropic",
                    offset_bar: 0.25,
                    polytropic_n: Some(1.32),
                });
            }
            if mask & 8 != 0 {
                s.tdc_offset_estimate_deg = Some(-0.4);
            }
            if mask & 16 != 0 {
                s.estimated_relative_error = Some(3e-6);
            }
            assert_eq!(flatten(&s), by_keys(&s), "mask {mask}");
        }
        let fixed: Vec<String> = by_keys(&Summary::empty())
            .into_iter()
            .map(|c| c.0)
            .collect();
        assert_eq!(summary_columns(), fixed);
    }

    /// Text cells that a spreadsheet would evaluate get a leading `'`;
    /// numbers, negative ones too, are never altered.
    #[test]
    fn summary_csv_cells_are_never_formulas() {
        let mut s = Summary::empty();
        s.mean_torque_nm = Some(-3.2);
        s.notes = vec!["=1+1 in the file".into(), "second".into()];
        let rows = [
            (
                "=HYPERLINK(\"http://x\",\"y\").csv".to_string(),
                String::new(),
                flatten(&s),
            ),
            ("+cmd.csv".to_string(), "-bad".to_string(), Vec::new()),
            ("@SUM(1).csv".to_string(), String::new(), Vec::new()),
        ];
        let text = summary_csv(&rows);
        let mut r = csv::Reader::from_reader(text.as_bytes());
        let head = r.headers().unwrap().clone();
        let col = |k: &str| head.iter().position(|h| h == k).unwrap();
        let recs: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
        assert_eq!(&recs[0][0], "'=HYPERLINK(\"http://x\",\"y\").csv");
        assert_eq!(&recs[0][col("mean_torque_nm")], "-3.2");
        assert_eq!(&recs[0][col("notes")], "'=1+1 in the file | second");
        assert_eq!(&recs[1][0], "'+cmd.csv");
        assert_eq!(&recs[1][1], "'-bad");
        assert_eq!(&recs[2][0], "'@SUM(1).csv");
        // JSON keeps the raw text.
        let inputs = Inputs::new(Source::Bundled(b"engine"), &[Source::Bundled(b"p")]).unwrap();
        assert_eq!(summary_json(&s, &inputs)["notes"][0], "=1+1 in the file");
    }
}
