//! The fixed, typed tables of a campaign (INTERFACE.md, "Parquet tables"):
//! `summary/4`, `cycles/3` and `traces/1`, each column's name, logical type
//! and how to get its value. **The one definition**: the Parquet writers
//! (`enginedyn-tables`) and `summary.csv` (`report::summary_csv`,
//! `report::flatten`) are built from it; the summary's values come from
//! [`KEYS`] by the column's key, so a figure has one accessor.
//!
//! [`SUMMARY`] lists its columns in `summary.json`'s order (the order of
//! `summary.csv`); each column's [`Group`] places it in the Parquet table
//! ([`summary_columns`]: the fixed keys, then the optional ones, then
//! `models.*` and `notes`). A new column is appended to its table and bumps
//! the table's number (`summary/4`).

use crate::KEYS;
pub use crate::column::{ColumnType, Group};
use crate::summary::{Columns, Field, Key, Summary, Value};
use enginedyn_combustion::BurnPoints;
use enginedyn_ingest::{CycleCombustion, Resampled};
use std::borrow::Cow;
use std::sync::LazyLock;

/// The schema names and versions written as `enginedyn.schema`.
pub const SUMMARY_SCHEMA: &str = "summary/4";
/// See [`SUMMARY_SCHEMA`].
pub const CYCLES_SCHEMA: &str = "cycles/3";
/// See [`SUMMARY_SCHEMA`].
pub const TRACES_SCHEMA: &str = "traces/1";
/// See [`SUMMARY_SCHEMA`]: a map's table (`sweep --load|--imep
/// --parquet`, `report --parquet`), the summary's columns and
/// [`MAP_COLUMNS`] after them.
pub const MAP_SCHEMA: &str = "map/1";

/// The columns a map's table adds after the summary's (float64): the IMEP
/// asked for (never null), the load in percent of the full-load line (null
/// with `--imep`), and the point the map's one flywheel was sized at (null
/// when none was).
pub const MAP_COLUMNS: [(&str, bool); 4] = [
    ("imep_target_bar", false),
    ("load_pct", true),
    ("flywheel_sized_at_rpm", true),
    ("flywheel_sized_at_imep_bar", true),
];

/// One point of a map as its table holds it: the summary's record and the
/// values of [`MAP_COLUMNS`] in order.
#[derive(Debug, Clone)]
pub struct MapRecord<'a> {
    /// The point's summary record.
    pub summary: SummaryRecord<'a>,
    /// [`MAP_COLUMNS`]' values.
    pub map: [Option<f64>; 4],
}

/// One value of a column in one row.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell<'a> {
    /// The key is absent from this summary (an optional key that does not
    /// apply): no `summary.csv` column of its own, null in Parquet.
    Absent,
    /// Null: the figure does not exist for the case (never a NaN or an
    /// infinity: those become null).
    Null,
    /// A number.
    Float(f64),
    /// A whole number.
    Int(i64),
    /// True or false.
    Bool(bool),
    /// Text.
    Text(Cow<'a, str>),
    /// Numbers (a list column; non-finite entries are null).
    Floats(Vec<f64>),
}

impl Cell<'_> {
    /// A number, null when absent or not finite.
    pub fn num(x: Option<f64>) -> Self {
        match x {
            Some(x) if x.is_finite() => Cell::Float(x),
            _ => Cell::Null,
        }
    }

    /// Null or absent.
    pub fn is_null(&self) -> bool {
        matches!(self, Cell::Null | Cell::Absent)
    }

    /// The same value, owning its text.
    pub fn into_owned(self) -> Cell<'static> {
        match self {
            Cell::Absent => Cell::Absent,
            Cell::Null => Cell::Null,
            Cell::Float(x) => Cell::Float(x),
            Cell::Int(i) => Cell::Int(i),
            Cell::Bool(b) => Cell::Bool(b),
            Cell::Text(t) => Cell::Text(Cow::Owned(t.into_owned())),
            Cell::Floats(v) => Cell::Floats(v),
        }
    }
}

/// One column: its name, logical type, whether it may be null, where it
/// stands, and how its value is got from a row.
#[derive(Debug, Clone, Copy)]
pub struct Column<G> {
    /// The name, as INTERFACE.md gives it.
    pub name: &'static str,
    /// The logical type.
    pub ty: ColumnType,
    /// Whether it may be null.
    pub nullable: bool,
    /// Where it stands (summary columns; [`Group::Row`] elsewhere).
    pub group: Group,
    /// Its value in a row.
    pub get: G,
}

/// How a [`SUMMARY`] column gets its value: from the row itself, or from
/// a summary key ([`KEYS`]) or one field of an object key.
#[derive(Debug, Clone, Copy)]
pub enum SummaryGet {
    /// A column of the row's own (`file`, `error`, provenance).
    Row(for<'r, 'a> fn(&'r SummaryRecord<'a>) -> Cell<'r>),
    /// A summary key of its own.
    Key(&'static Key),
    /// A field of an object key (`models.kinematics`).
    Field(&'static Field),
}
/// How a [`CYCLES`] column gets its value.
pub type CycleGet = for<'r, 'a> fn(&'r CycleRow<'a>) -> Cell<'r>;
/// How a [`TRACES`] column gets its value.
pub type TraceGet = for<'r, 'a> fn(&'r TracePoint<'a>) -> Cell<'r>;

/// One row of `summary/4`: a diagram file and its summary, or its error.
#[derive(Debug, Clone, Copy)]
pub struct SummaryRecord<'a> {
    /// The path as given.
    pub file: &'a str,
    /// Why it failed; `None` when it ran.
    pub error: Option<&'a str>,
    /// The engine's `name`.
    pub engine: &'a str,
    /// The diagram file's SHA-256 (hex), when it could be read.
    pub diagram_blake3: Option<&'a str>,
    /// The summary, when it ran.
    pub summary: Option<&'a Summary>,
}

impl<'a> SummaryRecord<'a> {
    /// A record of `summary` alone (no file): what `summary.csv`'s
    /// flattened cells are built from.
    pub fn of(summary: &'a Summary) -> Self {
        Self {
            file: "",
            error: None,
            engine: "",
            diagram_blake3: None,
            summary: Some(summary),
        }
    }
}

fn text<'r>(s: &'r str) -> Cell<'r> {
    Cell::Text(Cow::Borrowed(s))
}

fn opt_text<'r>(s: Option<&'r str>) -> Cell<'r> {
    s.map_or(Cell::Null, text)
}

/// `summary/4`, in `summary.json`'s order (that of `summary.csv`): the
/// row's own columns and the provenance, then one column per key of
/// [`KEYS`] (an object's field by field, as its
/// [`Columns`] say). The Parquet table's order is [`summary_columns`].
/// Every column but `file` and `engine` may be null (a failed file has no
/// figures).
pub static SUMMARY: LazyLock<Vec<Column<SummaryGet>>> = LazyLock::new(|| {
    let row = |name, nullable, group, get| Column {
        name,
        ty: ColumnType::Utf8,
        nullable,
        group,
        get: SummaryGet::Row(get),
    };
    let mut c = vec![
        row("file", false, Group::Row, |r| text(r.file)),
        row("error", true, Group::Row, |r| opt_text(r.error)),
        row("engine", false, Group::Provenance, |r| text(r.engine)),
        row("diagram_blake3", true, Group::Provenance, |r| {
            opt_text(r.diagram_blake3)
        }),
    ];
    let key_columns = |k: &'static Key| -> Vec<Column<SummaryGet>> {
        match k.columns {
            Columns::One(ty, group) => vec![Column {
                name: k.key,
                ty,
                nullable: true,
                group,
                get: SummaryGet::Key(k),
            }],
            Columns::Object(fields) => fields
                .iter()
                .map(|f| Column {
                    name: f.column,
                    ty: f.ty,
                    nullable: true,
                    group: f.group,
                    get: SummaryGet::Field(f),
                })
                .collect(),
        }
    };
    let appended_4 = |k: &Key| match k.columns {
        Columns::One(_, group) => group == Group::Appended4,
        Columns::Object(fields) => fields.iter().all(|f| f.group == Group::Appended4),
    };
    for k in KEYS.iter().filter(|k| !appended_4(k)) {
        c.extend(key_columns(k));
    }
    // summary/3: every burn level asked for, and its angle (the mean
    // trace's), as lists: a level beyond the four fixed ones has no
    // column of its own in a table whose columns are fixed.
    let list = |name, get| Column {
        name,
        ty: ColumnType::Float64List,
        nullable: true,
        group: Group::Appended3,
        get: SummaryGet::Row(get),
    };
    c.push(list("burn_levels_pct", |r| {
        levels_cell(r.summary, |(pct, _)| Some(*pct))
    }));
    c.push(list("burn_levels_deg", |r| {
        levels_cell(r.summary, |(_, deg)| *deg)
    }));
    // summary/4: the brake figures and `design.*`, after the lists.
    for k in KEYS.iter().filter(|k| appended_4(k)) {
        c.extend(key_columns(k));
    }
    c
});

/// A list of the summary's burn levels (`pick`: the level or its angle),
/// null without combustion or without a summary.
fn levels_cell(
    s: Option<&Summary>,
    pick: impl Fn(&(f64, Option<f64>)) -> Option<f64>,
) -> Cell<'static> {
    match s.and_then(|s| s.combustion.as_ref()) {
        Some(c) if !c.levels.is_empty() => Cell::Floats(
            c.levels
                .iter()
                .map(|l| pick(l).filter(|x| x.is_finite()).unwrap_or(f64::NAN))
                .collect(),
        ),
        _ => Cell::Null,
    }
}

/// A summary value as a cell (`None`: absent).
fn value_cell(v: Option<Value>) -> Cell<'static> {
    match v {
        None => Cell::Absent,
        Some(Value::Num(x)) => Cell::num(x),
        Some(Value::Int(i)) => i64::try_from(i).map_or(Cell::Null, Cell::Int),
        Some(Value::Text(t)) => Cell::Text(Cow::Borrowed(t)),
        Some(Value::Str(t)) => Cell::Text(Cow::Owned(t)),
        Some(Value::List(l)) => Cell::Text(Cow::Owned(l.join(" | "))),
        Some(Value::Map(_)) => Cell::Null,
    }
}

impl Column<SummaryGet> {
    /// This column's value in `r`: absent when the key is (an optional
    /// key that does not apply), null without a summary.
    pub fn cell<'r>(&self, r: &'r SummaryRecord<'_>) -> Cell<'r> {
        let get = match self.get {
            SummaryGet::Row(get) => return get(r),
            SummaryGet::Key(k) => k.get,
            SummaryGet::Field(f) => f.get,
        };
        match r.summary {
            Some(s) => value_cell(get(s)),
            None => Cell::Null,
        }
    }
}

impl Column<CycleGet> {
    /// This column's value in `r`.
    pub fn cell<'r>(&self, r: &'r CycleRow<'_>) -> Cell<'r> {
        (self.get)(r)
    }
}

impl Column<TraceGet> {
    /// This column's value in `r`.
    pub fn cell<'r>(&self, r: &'r TracePoint<'_>) -> Cell<'r> {
        (self.get)(r)
    }
}

/// The columns of `summary/4` in the Parquet table's order: `file`,
/// `error`, `engine`, `diagram_blake3`, the fixed keys, the optional keys,
/// `pegging.*`, the text of `models.*`, `models.grid_step_deg`, `notes`.
pub fn summary_columns() -> Vec<&'static Column<SummaryGet>> {
    let mut c: Vec<_> = SUMMARY.iter().collect();
    // Stable: within a group, summary.json's order.
    c.sort_by_key(|c| c.group);
    c
}

/// One row of `cycles/3`: a measured cycle of one cylinder of one file,
/// used or left out. SI units; the columns convert.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleRow<'a> {
    /// The diagram file, as given.
    pub file: &'a str,
    /// Cylinder (0: a trace that stands for every cylinder).
    pub cylinder: i64,
    /// Cycle number, as numbered in the file (else from 1).
    pub cycle: i64,
    /// Why it was left out of the averages; `None` when used.
    pub skip_reason: Option<&'a str>,
    /// IMEP (Pa), when the volume law is known.
    pub imep_pa: Option<f64>,
    /// Peak pressure (Pa).
    pub p_max_pa: Option<f64>,
    /// Its angle (deg from firing TDC, in `[-cycle/2, cycle/2)`).
    pub p_max_angle_deg: Option<f64>,
    /// The pegging offset added (Pa), when the trace was pegged.
    pub peg_offset_pa: Option<f64>,
    /// The speed over this cycle (rpm): a time record's, else the run's.
    pub rpm: f64,
    /// The cycle's combustion analysis, and the options it ran with.
    pub combustion: Option<(&'a CycleCombustion, &'a enginedyn_combustion::Options)>,
}

impl CycleRow<'_> {
    /// A knock figure of this cycle, when measured and resolved.
    fn knock(&self, get: impl Fn(&enginedyn_combustion::KnockFigures) -> f64) -> Cell<'static> {
        Cell::num(
            self.combustion
                .and_then(|(c, _)| c.knock.as_ref()?.as_ref().ok().map(&get)),
        )
    }

    /// A burn point of this cycle, when it burns.
    fn burn(
        &self,
        get: impl Fn(&BurnPoints, &enginedyn_combustion::Options) -> Option<f64>,
    ) -> Cell<'static> {
        Cell::num(
            self.combustion
                .and_then(|(c, o)| c.burn.as_ref().and_then(|b| get(b, o))),
        )
    }
}

/// A float column of `cycles/3`'s combustion part.
macro_rules! burn_column {
    ($name:literal, $get:expr) => {
        Column {
            name: $name,
            ty: ColumnType::Float64,
            nullable: true,
            group: Group::Row,
            get: $get,
        }
    };
}

/// Pa to bar, in the tables.
fn bar(x: Option<f64>) -> Cell<'static> {
    Cell::num(x.map(|p| p / 1e5))
}

/// `cycles/3`, in its order.
pub const CYCLES: &[Column<CycleGet>] = &[
    Column {
        name: "file",
        ty: ColumnType::Utf8,
        nullable: false,
        group: Group::Row,
        get: |r| text(r.file),
    },
    Column {
        name: "cylinder",
        ty: ColumnType::Int16,
        nullable: false,
        group: Group::Row,
        get: |r| Cell::Int(r.cylinder),
    },
    Column {
        name: "cycle",
        ty: ColumnType::Int64,
        nullable: false,
        group: Group::Row,
        get: |r| Cell::Int(r.cycle),
    },
    Column {
        name: "used",
        ty: ColumnType::Bool,
        nullable: false,
        group: Group::Row,
        get: |r| Cell::Bool(r.skip_reason.is_none()),
    },
    Column {
        name: "skip_reason",
        ty: ColumnType::Utf8,
        nullable: true,
        group: Group::Row,
        get: |r| opt_text(r.skip_reason),
    },
    Column {
        name: "imep_bar",
        ty: ColumnType::Float64,
        nullable: true,
        group: Group::Row,
        get: |r| bar(r.imep_pa),
    },
    Column {
        name: "p_max_bar",
        ty: ColumnType::Float64,
        nullable: true,
        group: Group::Row,
        get: |r| bar(r.p_max_pa),
    },
    Column {
        name: "p_max_angle_deg",
        ty: ColumnType::Float64,
        nullable: true,
        group: Group::Row,
        get: |r| Cell::num(r.p_max_angle_deg),
    },
    Column {
        name: "peg_offset_bar",
        ty: ColumnType::Float64,
        nullable: true,
        group: Group::Row,
        get: |r| bar(r.peg_offset_pa),
    },
    Column {
        name: "rpm",
        ty: ColumnType::Float64,
        nullable: false,
        group: Group::Row,
        get: |r| Cell::num(Some(r.rpm)),
    },
    burn_column!("imep_gross_bar", |r| bar(r
        .combustion
        .map(|(c, _)| c.imep_gross_pa))),
    burn_column!("pmep_bar", |r| bar(r
        .combustion
        .and_then(|(c, _)| r.imep_pa.map(|i| i - c.imep_gross_pa)))),
    burn_column!("ca5_deg", |r| r.burn(|b, o| b.level(o, 5.0))),
    burn_column!("ca10_deg", |r| r.burn(|b, o| b.level(o, 10.0))),
    burn_column!("ca50_deg", |r| r.burn(|b, o| b.level(o, 50.0))),
    burn_column!("ca90_deg", |r| r.burn(|b, o| b.level(o, 90.0))),
    burn_column!("burn_10_90_deg", |r| r
        .burn(crate::combustion::duration_10_90_of)),
    burn_column!("soc_deg", |r| r.burn(|b, _| Some(b.soc_deg))),
    burn_column!("eoc_deg", |r| r.burn(|b, _| Some(b.eoc_deg))),
    burn_column!("heat_released_j", |r| Cell::num(
        r.combustion
            .and_then(|(c, _)| c.burn.as_ref().map(|_| c.heat_released_j))
    )),
    burn_column!("dp_dphi_max_bar_deg", |r| r
        .burn(|b, _| Some(b.dp_max_pa_deg / 1e5))),
    burn_column!("dp_dphi_max_angle_deg", |r| r
        .burn(|b, _| Some(b.dp_max_angle_deg))),
    Column {
        name: "combustion",
        ty: ColumnType::Bool,
        nullable: true,
        group: Group::Row,
        get: |r| match r.combustion {
            Some((c, _)) => Cell::Bool(c.burn.is_some()),
            None => Cell::Null,
        },
    },
    // cycles/3: knock, every burn level asked for and its angle.
    burn_column!("mapo_bar", |r| r.knock(|k| k.mapo_pa / 1e5)),
    burn_column!("impo_bar_deg", |r| r.knock(|k| k.impo_pa_deg / 1e5)),
    // (the levels as lists)
    Column {
        name: "burn_levels_pct",
        ty: ColumnType::Float64List,
        nullable: true,
        group: Group::Row,
        get: |r| match r.combustion {
            Some((c, o)) if c.burn.is_some() => Cell::Floats(o.levels_pct.clone()),
            _ => Cell::Null,
        },
    },
    Column {
        name: "burn_levels_deg",
        ty: ColumnType::Float64List,
        nullable: true,
        group: Group::Row,
        get: |r| match r.combustion.and_then(|(c, _)| c.burn.as_ref()) {
            Some(b) => Cell::Floats(b.levels_deg.clone()),
            None => Cell::Null,
        },
    },
];

/// The rows of `cycles/3` for one file: every measured cycle of
/// `resampled`, used ([`Resampled::stats`]) or left out
/// ([`Resampled::skipped`], with the reason), by cylinder, then cycle;
/// `run_rpm` is the speed of cycles the file does not time.
pub fn cycle_rows<'a>(file: &'a str, resampled: &'a Resampled, run_rpm: f64) -> Vec<CycleRow<'a>> {
    let pegged = resampled.pegging.is_some();
    let mut rows: Vec<CycleRow<'a>> = resampled
        .stats
        .iter()
        .map(|s| CycleRow {
            file,
            cylinder: s.cylinder,
            cycle: s.cycle,
            skip_reason: None,
            imep_pa: s.imep_pa,
            p_max_pa: Some(s.p_max),
            p_max_angle_deg: Some(s.p_max_angle_deg),
            peg_offset_pa: pegged.then_some(s.peg_offset),
            rpm: s.rpm.unwrap_or(run_rpm),
            combustion: s.combustion.as_ref().zip(resampled.combustion.as_deref()),
        })
        .chain(resampled.skipped.iter().map(|s| CycleRow {
            file,
            cylinder: s.cylinder,
            cycle: s.cycle,
            skip_reason: Some(s.reason.as_str()),
            imep_pa: None,
            p_max_pa: None,
            p_max_angle_deg: None,
            peg_offset_pa: None,
            rpm: run_rpm,
            combustion: None,
        }))
        .collect();
    rows.sort_by_key(|r| (r.cylinder, r.cycle));
    rows
}

/// One row of `traces/1`: the cycle-averaged absolute pressure of one
/// cylinder at one grid angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TracePoint<'a> {
    /// The diagram file, as given.
    pub file: &'a str,
    /// Cylinder (0: a trace that stands for every cylinder).
    pub cylinder: i64,
    /// The grid angle (deg from firing TDC, in `[0, cycle)`).
    pub crank_deg: f64,
    /// The pressure (Pa, absolute).
    pub pressure_pa: f64,
}

/// `traces/1`, in its order.
pub const TRACES: &[Column<TraceGet>] = &[
    Column {
        name: "file",
        ty: ColumnType::Utf8,
        nullable: false,
        group: Group::Row,
        get: |r| text(r.file),
    },
    Column {
        name: "cylinder",
        ty: ColumnType::Int16,
        nullable: false,
        group: Group::Row,
        get: |r| Cell::Int(r.cylinder),
    },
    Column {
        name: "crank_deg",
        ty: ColumnType::Float64,
        nullable: false,
        group: Group::Row,
        get: |r| Cell::Float(r.crank_deg),
    },
    Column {
        name: "pressure_bar",
        ty: ColumnType::Float64,
        nullable: false,
        group: Group::Row,
        get: |r| Cell::num(Some(r.pressure_pa / 1e5)),
    },
];

/// The rows of `traces/1` for one file: each cylinder's mean pressure on
/// the grid (cylinder 1…z when the traces name cylinders, else cylinder
/// 0), angles without binary noise (0.30000000000000004 → 0.3, as in
/// `curves.csv`). None for a turning-moment file.
pub fn trace_points<'a>(file: &'a str, r: &'a Resampled) -> Vec<TracePoint<'a>> {
    if r.quantity != enginedyn_ingest::Quantity::Pressure {
        return Vec::new();
    }
    let traces: Vec<(i64, &[f64])> = if r.cylinders.is_empty() {
        vec![(0, &r.pressure)]
    } else {
        (1..)
            .zip(&r.cylinders)
            .map(|(c, p)| (c, p.as_slice()))
            .collect()
    };
    let mut out = Vec::with_capacity(traces.iter().map(|t| t.1.len()).sum());
    for (cylinder, p) in traces {
        out.extend(p.iter().enumerate().map(|(k, &pressure_pa)| TracePoint {
            file,
            cylinder,
            crank_deg: ((k as f64 * r.step_deg) * 1e9).round() / 1e9,
            pressure_pa,
        }));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A summary with every optional key present.
    fn full() -> Summary {
        let mut s = Summary::empty();
        s.cycles = Some(10);
        s.cycles_skipped = Some(2);
        s.cycle_stats = Some(crate::CycleSummary {
            cycles: 10,
            imep_std_bar: Some(0.1),
            imep_cov: Some(0.01),
            p_max_mean_bar: 50.0,
            p_max_cov: 0.02,
            p_max_angle_mean_deg: 12.0,
            p_max_angle_std_deg: 1.0,
        });
        s.brake = Some(crate::BrakeSummary {
            fmep_bar: 1.2,
            bmep_bar: 8.8,
            brake_torque_nm: 90.0,
            brake_power_kw: 40.0,
            mechanical_efficiency: Some(0.88),
        });
        s.design = Some(crate::DesignSummary {
            charge: Some("si"),
            intake_pressure_bar: 0.7,
            lambda: Some(1.0),
        });
        s.pegging = Some(crate::Pegging {
            method: "bar",
            offset_bar: 1.0,
            polytropic_n: None,
        });
        s.tdc_offset_estimate_deg = Some(0.3);
        s.estimated_relative_error = Some(1e-4);
        s.combustion = Some(crate::CombustionSummary {
            levels: [5.0, 10.0, 50.0, 90.0]
                .map(|l| (l, Some(l / 10.0)))
                .to_vec(),
            burn_10_90_deg: Some(20.0),
            soc_deg: Some(-10.0),
            eoc_deg: Some(40.0),
            heat_released_j: Some(600.0),
            dp_dphi_max_bar_deg: Some(2.5),
            dp_dphi_max_angle_deg: Some(5.0),
            imep_gross_bar: Some(10.2),
            pmep_bar: Some(-0.2),
            ca50_std_deg: Some(1.0),
            burn_10_90_std_deg: Some(0.5),
            dp_dphi_max_std_bar_deg: Some(0.1),
            imep_lnv: Some(0.95),
            gamma: "1.32".into(),
            smoothing: "Savitzky-Golay cubic, 2° (21 points), zero-phase".into(),
            burn_window: "-90:120".into(),
            window_deg: (-90.0, 120.0),
            ..Default::default()
        });
        if let Some(c) = s.combustion.as_mut() {
            c.heat_released_gross_j = Some(Some(640.0));
            c.wall_heat_j = Some(Some(40.0));
            c.mapo_mean_bar = Some(0.2);
            c.mapo_max_bar = Some(1.4);
            c.knock_share = Some(0.05);
            c.wall_heat = "woschni (T_w 450 K)".into();
        }
        s.p_max_bar = Some(56.3);
        s.p_max_angle_deg = Some(13.0);
        s.notes = vec!["a".into(), "b".into()];
        s
    }

    /// Every summary key is a column (objects field by field), in
    /// `summary.json`'s order: a key added to `KEYS` without its column
    /// fails here.
    #[test]
    fn summary_columns_are_the_keys_in_order() {
        let s = full();
        let mut expected = vec!["file", "error", "engine", "diagram_blake3"]
            .into_iter()
            .map(String::from)
            .collect::<Vec<_>>();
        let mut appended = Vec::new();
        for (k, v) in s.fields() {
            let into = if Summary::key(k).is_some_and(|key| match key.columns {
                Columns::One(_, g) => g == Group::Appended4,
                Columns::Object(f) => f[0].group == Group::Appended4,
            }) {
                &mut appended
            } else {
                &mut expected
            };
            match v {
                Value::Map(m) => into.extend(m.iter().map(|(f, _)| format!("{k}.{f}"))),
                _ => into.push(k.to_string()),
            }
        }
        // summary/3: the level lists, after every key of before (the peak
        // pressure among them); summary/4's keys after them.
        expected.extend(["burn_levels_pct".to_string(), "burn_levels_deg".to_string()]);
        expected.extend(appended);
        let names: Vec<String> = SUMMARY.iter().map(|c| c.name.to_string()).collect();
        assert_eq!(names, expected);
        // And every one has a value in a full summary.
        let r = SummaryRecord::of(&s);
        for c in SUMMARY.iter().filter(|c| c.group > Group::Provenance) {
            assert!(!matches!(c.cell(&r), Cell::Absent), "{}", c.name);
        }
    }

    /// The Parquet order is INTERFACE.md's.
    #[test]
    fn parquet_order() {
        let names: Vec<&str> = summary_columns().iter().map(|c| c.name).collect();
        assert_eq!(names.len(), SUMMARY.len());
        assert_eq!(
            names[..5],
            ["file", "error", "engine", "diagram_blake3", "rpm"]
        );
        let at = |n: &str| names.iter().position(|x| *x == n).unwrap();
        assert_eq!(at("energy_balance_error") + 1, at("cycles"));
        assert_eq!(at("estimated_relative_error") + 1, at("pegging.method"));
        // summary/2: the combustion columns appended after `notes`;
        // summary/3: the level lists after them.
        assert_eq!(
            names[at("notes") - 5..=at("notes")],
            [
                "models.kinematics",
                "models.rod_model",
                "models.interpolation",
                "models.integration",
                "models.grid_step_deg",
                "notes"
            ]
        );
        assert_eq!(
            names[at("notes") + 1..at("notes") + 3],
            ["models.gamma", "models.smoothing"]
        );
        // summary/4: the brake figures and `design.*` after the lists.
        assert_eq!(
            names[names.len() - 8..],
            [
                "fmep_bar",
                "bmep_bar",
                "brake_torque_nm",
                "brake_power_kw",
                "mechanical_efficiency",
                "design.charge",
                "design.intake_pressure_bar",
                "design.lambda"
            ]
        );
        assert_eq!(
            names[names.len() - 20..names.len() - 8],
            [
                "dp_dphi_max_std_bar_deg",
                "imep_lnv",
                "models.wall_heat",
                "heat_released_gross_j",
                "wall_heat_j",
                "mapo_mean_bar",
                "mapo_max_bar",
                "knock_share",
                "p_max_bar",
                "p_max_angle_deg",
                "burn_levels_pct",
                "burn_levels_deg"
            ]
        );
        let ty = |n: &str| SUMMARY.iter().find(|c| c.name == n).unwrap().ty;
        assert_eq!(ty("burn_levels_deg"), ColumnType::Float64List);
        assert_eq!(ty("journal_most_loaded"), ColumnType::Int32);
        assert_eq!(ty("cycles_skipped"), ColumnType::Int64);
        assert_eq!(ty("pegging.method"), ColumnType::Utf8);
    }

    /// Absent optional keys are absent, a null figure is null, the notes
    /// are joined, a failed row is null everywhere but its own columns.
    #[test]
    fn cells() {
        let s = Summary::empty();
        let r = SummaryRecord::of(&s);
        let cell = |r: &SummaryRecord<'_>, n: &str| {
            SUMMARY
                .iter()
                .find(|c| c.name == n)
                .unwrap()
                .cell(r)
                .into_owned()
        };
        assert_eq!(cell(&r, "cycles"), Cell::Absent);
        assert_eq!(cell(&r, "pegging.offset_bar"), Cell::Absent);
        assert_eq!(cell(&r, "imep_bar"), Cell::Null);
        assert_eq!(cell(&r, "journal_most_loaded"), Cell::Int(0));
        let f = full();
        let r = SummaryRecord::of(&f);
        assert_eq!(cell(&r, "notes"), Cell::Text("a | b".into()));
        assert_eq!(cell(&r, "pegging.polytropic_n"), Cell::Null);
        assert_eq!(cell(&r, "pegging.method"), Cell::Text("bar".into()));
        assert_eq!(cell(&r, "p_max_cov"), Cell::Float(0.02));
        let failed = SummaryRecord {
            file: "x.csv",
            error: Some("line 3: no number"),
            engine: "e",
            diagram_blake3: None,
            summary: None,
        };
        assert_eq!(cell(&failed, "rpm"), Cell::Null);
        assert_eq!(
            cell(&failed, "error"),
            Cell::Text("line 3: no number".into())
        );
    }

    /// Used and skipped cycles in cylinder, then cycle order, in bar.
    #[test]
    fn cycle_rows_keep_skipped_cycles() {
        let mut r = Resampled::from_grid(1.0, vec![1e5; 720]);
        let stat = |cylinder, cycle| enginedyn_ingest::CycleStats {
            cylinder,
            cycle,
            imep_pa: Some(8e5),
            p_max: 50e5,
            p_max_angle_deg: 12.0,
            peg_offset: 0.0,
            rpm: None,
            combustion: None,
        };
        r.stats = vec![stat(1, 1), stat(1, 3), stat(0, 2)];
        r.skipped = vec![enginedyn_ingest::SkippedCycle {
            cylinder: 1,
            cycle: 2,
            reason: "a gap".into(),
        }];
        let rows = cycle_rows("f", &r, 2000.0);
        let order: Vec<(i64, i64, bool)> = rows
            .iter()
            .map(|r| (r.cylinder, r.cycle, r.skip_reason.is_none()))
            .collect();
        assert_eq!(
            order,
            [(0, 2, true), (1, 1, true), (1, 2, false), (1, 3, true)]
        );
        let get = |n: &str, row: &CycleRow<'_>| {
            CYCLES
                .iter()
                .find(|c| c.name == n)
                .unwrap()
                .cell(row)
                .into_owned()
        };
        assert_eq!(get("imep_bar", &rows[0]), Cell::Float(8.0));
        assert_eq!(get("peg_offset_bar", &rows[0]), Cell::Null);
        assert_eq!(get("imep_bar", &rows[2]), Cell::Null);
        assert_eq!(get("used", &rows[2]), Cell::Bool(false));
        assert_eq!(get("rpm", &rows[2]), Cell::Float(2000.0));
    }

    /// One point per grid angle and cylinder, angles clean.
    #[test]
    fn trace_points_per_cylinder() {
        let mut r = Resampled::from_grid(0.1, vec![2e5; 7200]);
        assert_eq!(trace_points("f", &r).len(), 7200);
        r.cylinders = vec![vec![1e5; 7200], vec![3e5; 7200]];
        let p = trace_points("f", &r);
        assert_eq!(p.len(), 14400);
        assert_eq!((p[7203].cylinder, p[7203].crank_deg), (2, 0.3));
        assert_eq!(TRACES[3].cell(&p[7203]), Cell::Float(3.0), "bar, absolute");
    }
}
