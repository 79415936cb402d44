//! What `batch` and `sweep` show: batch's `index.html`, the readable table
//! of key figures (one row per diagram or speed) printed without `--out`,
//! and the sweep chart. The key figures' labels, units and decimals come
//! from [`enginedyn_pipeline::KEYS`].

use crate::html::{esc, percent_encode};
use crate::{Chart, Figure, Series, fixed};
use enginedyn_numerics::format::table_text;
use enginedyn_pipeline::{Key, Summary, key};
use std::fmt::Write as _;

/// The key figures of a batch or sweep row, in this order.
pub const KEY_FIGURES: [&Key; 10] = [
    key("rpm"),
    key("imep_bar"),
    key("mean_torque_nm"),
    key("power_kw"),
    key("torque_max_nm"),
    key("torque_min_nm"),
    key("crankpin_load_max_n"),
    key("required_inertia_kg_m2"),
    key("ca50_deg"),
    key("dp_dphi_max_bar_deg"),
];

/// The key figures of a sweep's printed table (the speed is the row).
pub const SWEEP_FIGURES: [&Key; 8] = [
    key("mean_torque_nm"),
    key("power_kw"),
    key("indicated_mean_torque_nm"),
    key("torque_max_nm"),
    key("torque_min_nm"),
    key("crankpin_load_max_n"),
    key("gas_force_max_n"),
    key("speed_fluctuation_achieved"),
];

/// A key figure's column: heading, unit, SI-to-display scale and decimals.
struct Column {
    heading: String,
    unit: &'static str,
    scale: f64,
    digits: usize,
}

impl Column {
    /// "IMEP (bar)"; the heading alone for a pure number.
    fn with_unit(&self) -> String {
        if self.unit.is_empty() {
            self.heading.clone()
        } else {
            format!("{} ({})", self.heading, self.unit)
        }
    }
}

fn columns(keys: &[&Key], s: &Summary) -> Vec<Column> {
    keys.iter()
        .map(|k| {
            let (label, unit, scale, digits) = key_heading(k).unwrap_or((k.key, "", 1.0, 0));
            Column {
                heading: k
                    .shown
                    .as_ref()
                    .map_or(label.into(), |sh| crate::label(sh, s)),
                unit,
                scale,
                digits,
            }
        })
        .collect()
}

/// How a key figure's column is headed: its label (without the
/// indicated/effective basis), unit, SI-to-display scale and decimals; the
/// speed, shown otherwise in the readable tables, as "speed (rpm)". `None`
/// for the keys no table shows as a figure (`models`, `notes`, …).
pub fn key_heading(k: &Key) -> Option<(&'static str, &'static str, f64, usize)> {
    match (k.shown.as_ref(), k.key) {
        (Some(sh), _) => Some((sh.label, sh.unit, sh.scale, sh.digits)),
        (None, "rpm") => Some(("speed", "rpm", 1.0, 0)),
        (None, _) => None,
    }
}

/// A summary's figures of `keys` ([`KEY_FIGURES`], [`SWEEP_FIGURES`]) in
/// SI units.
pub fn key_figures(keys: &[&Key], s: &Summary) -> Vec<Option<f64>> {
    keys.iter().map(|k| k.number(s)).collect()
}

/// One diagram (or speed) of a batch (or sweep) as the tables show it.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyRow {
    /// The diagram's file, or the speed.
    pub name: String,
    /// Its key figures ([`key_figures`]), or `None` when it failed.
    pub figures: Option<Vec<Option<f64>>>,
    /// Why it failed (empty when it ran).
    pub error: String,
    /// Its run folder under the batch folder, with `--detail`.
    pub folder: Option<String>,
}

/// "1 diagram", "2 diagrams".
pub fn count(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}

/// The readable table of a batch or sweep (standard output without
/// `--out`): one row per diagram or speed, the figures of `keys` (numbered
/// columns, their labels and units listed below), failed rows with their
/// error; names and errors on one line, control characters escaped. `eta` is the mechanical efficiency the effective figures carry.
pub fn key_table(first: &str, keys: &[&Key], rows: &[KeyRow], eta: Option<f64>) -> String {
    let s = basis(eta);
    let cols = columns(keys, &s);
    let head: Vec<String> = std::iter::once(first.to_string())
        .chain(cols.iter().map(|c| c.with_unit()))
        .collect();
    let body: Vec<Vec<String>> =
        rows.iter()
            .map(|r| {
                // A name on one line: control characters escaped (`\n`).
                let mut cells = vec![table_text(&r.name).into_owned()];
                match &r.figures {
                    Some(f) => cells.extend(f.iter().zip(&cols).map(|(v, c)| {
                        v.map_or("—".to_string(), |x| fixed(x * c.scale, c.digits))
                    })),
                    None => cells.push(format!("error: {}", table_text(&r.error))),
                }
                cells
            })
            .collect();
    // Each heading on its own line above its column would be too wide: the
    // headings are numbered and listed under the table instead.
    let mut width = vec![0usize; head.len()];
    width[0] = head[0].chars().count();
    for row in &body {
        if row.len() == head.len() {
            for (w, c) in width.iter_mut().zip(row) {
                *w = (*w).max(c.chars().count());
            }
        } else {
            width[0] = width[0].max(row[0].chars().count());
        }
    }
    for (k, w) in width.iter_mut().enumerate().skip(1) {
        *w = (*w).max(format!("[{k}]").len());
    }
    let mut o = String::new();
    let mut line = format!("{:<w$}", head[0], w = width[0]);
    for (k, w) in width.iter().enumerate().skip(1) {
        let _ = write!(line, "  {:>w$}", format!("[{k}]"));
    }
    let _ = writeln!(o, "{}", line.trim_end());
    for row in &body {
        let mut line = format!("{:<w$}", row[0], w = width[0]);
        if row.len() == head.len() {
            for (c, w) in row.iter().zip(&width).skip(1) {
                let _ = write!(line, "  {c:>w$}");
            }
        } else {
            let _ = write!(line, "  {}", row[1]);
        }
        let _ = writeln!(o, "{}", line.trim_end());
    }
    o.push('\n');
    for (k, h) in head.iter().enumerate().skip(1) {
        let _ = writeln!(o, "[{k}] {h}");
    }
    o
}

/// A summary standing for the rows' basis in the labels: `eta` the
/// mechanical efficiency, `None` the brake figures of `[friction]`.
fn basis(eta: Option<f64>) -> Summary {
    let mut s = Summary::empty();
    match eta {
        Some(e) => s.mechanical_efficiency = e,
        None => {
            s.brake = Some(enginedyn_pipeline::BrakeSummary {
                fmep_bar: f64::NAN,
                bmep_bar: f64::NAN,
                brake_torque_nm: f64::NAN,
                brake_power_kw: f64::NAN,
                mechanical_efficiency: None,
            })
        }
    }
    s
}

/// Batch's `index.html`: every diagram with its key figures, linking to its
/// report (links percent-encoded), failed rows with their error.
pub fn index_html(title: &str, rows: &[KeyRow], eta: Option<f64>) -> String {
    let s = basis(eta);
    let cols = columns(&KEY_FIGURES, &s);
    let mut o = String::new();
    let _ = write!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{} — batch</title><style>\
body{{font-family:sans-serif;margin:24px}}table{{border-collapse:collapse;font-size:14px}}\
td,th{{padding:3px 10px;border-bottom:1px solid #eee;text-align:left}}td.v{{text-align:right}}.err{{color:#b00}}\
</style></head><body><h1>{} — {}</h1>\n<table><tr><th>#</th><th>diagram</th>",
        esc(title),
        esc(title),
        count(rows.len(), "diagram")
    );
    for c in &cols {
        let _ = write!(o, "<th>{}</th>", esc(&c.with_unit()));
    }
    o.push_str("<th>report</th></tr>\n");
    for (i, r) in rows.iter().enumerate() {
        // Rows count from 1, as the run folders NNNN_STEM do.
        let _ = write!(o, "<tr><td>{}</td><td>{}</td>", i + 1, esc(&r.name));
        match (&r.figures, &r.folder) {
            (Some(k), Some(folder)) => {
                for (v, c) in k.iter().zip(&cols) {
                    let _ = write!(
                        o,
                        "<td class=\"v\">{}</td>",
                        v.map_or("—".to_string(), |x| fixed(x * c.scale, c.digits))
                    );
                }
                let _ = writeln!(
                    o,
                    "<td><a href=\"{}/report.html\">report</a></td></tr>",
                    esc(&percent_encode(folder))
                );
            }
            _ => {
                let _ = writeln!(
                    o,
                    "<td colspan=\"{}\" class=\"err\">{}</td></tr>",
                    cols.len() + 1,
                    esc(&r.error)
                );
            }
        }
    }
    o.push_str("</table></body></html>\n");
    o
}

/// `sweep.svg`: torque, peak forces and the required inertia against speed,
/// one unit per panel. A sweep runs one diagram at every speed: the title
/// says that the pressures are the same at every speed.
pub fn sweep_figure(engine_name: &str, summaries: &[&Summary]) -> Figure {
    let get = |f: fn(&Summary) -> Option<f64>| -> Vec<(f64, f64)> {
        summaries
            .iter()
            .filter_map(|s| f(s).map(|v| (s.rpm, v)))
            .collect()
    };
    let panel = |title: &str, y: &str, series: Vec<Series>| Chart {
        title: title.into(),
        x_label: "engine speed (rpm)".into(),
        y_label: y.into(),
        series,
        log: false,
        equal: false,
        angle_ticks: None,
    };
    let s = |name: &str, pts: Vec<(f64, f64)>| Series {
        name: name.into(),
        points: pts,
        dashed: false,
        marker: false,
        color: None,
    };
    let eta = summaries
        .first()
        .map_or_else(|| "effective".to_string(), |s| crate::effective(s));
    Figure {
        file: "sweep.svg".into(),
        panels: vec![
            panel(
                &format!("{engine_name} — torque, the same pressures at every speed"),
                "torque (N m)",
                vec![
                    s(&format!("mean, {eta}"), get(|x| x.mean_torque_nm)),
                    s("mean, indicated", get(|x| x.indicated_mean_torque_nm)),
                    s("max, indicated", get(|x| x.torque_max_nm)),
                    s("min, indicated", get(|x| x.torque_min_nm)),
                ],
            ),
            // One unit per panel: the crank-pin load against the peak gas
            // force shows inertia taking over as speed rises.
            panel(
                "peak forces: gas load fixed, inertia growing with n²",
                "force (kN)",
                vec![
                    s(
                        "crank-pin load max",
                        get(|x| x.crankpin_load_max_n.map(|v| v / 1e3)),
                    ),
                    s("gas force max", get(|x| x.gas_force_max_n.map(|v| v / 1e3))),
                ],
            ),
            panel(
                "flywheel",
                "speed fluctuation δ with the flywheel sized once",
                vec![s("δ achieved", get(|x| x.speed_fluctuation_achieved))],
            ),
        ],
    }
}

/// The most loads a map's legend names.
const LEGEND_LOADS: usize = 8;

/// The colour of load `l` of `n`: blue (the lowest) through green to red
/// (the highest), so that no two loads share one.
fn load_colour(l: usize, n: usize) -> plotters::style::RGBColor {
    const STOPS: [(f64, f64, f64); 4] = [
        (31.0, 119.0, 180.0),
        (44.0, 160.0, 44.0),
        (255.0, 127.0, 14.0),
        (214.0, 39.0, 40.0),
    ];
    let t = if n > 1 {
        l as f64 / (n - 1) as f64
    } else {
        0.0
    } * (STOPS.len() - 1) as f64;
    let k = (t.floor() as usize).min(STOPS.len() - 2);
    let f = t - k as f64;
    let mix = |a: f64, b: f64| (a + f * (b - a)).round() as u8;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    plotters::style::RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// `sweep.svg` of a speed × load map (`sweep --imep`): the effective
/// mean torque, the power and the speed fluctuation against speed, one
/// line per load (`loads`: each IMEP target in bar with its summaries in
/// speed order).
pub fn sweep_map_figure(engine_name: &str, loads: &[(f64, Vec<&Summary>)]) -> Figure {
    // Many loads: each its colour on a blue-to-red scale, the legend naming
    // at most eight of them (the first and the last among them), so that
    // it never covers the plot; one speed: a marker a point.
    let named = |l: usize| {
        let n = loads.len();
        n <= LEGEND_LOADS || l + 1 == n || (l * (LEGEND_LOADS - 1)) % (n - 1) < LEGEND_LOADS - 1
    };
    let single = loads.iter().all(|(_, ss)| ss.len() < 2);
    let lines = |f: fn(&Summary) -> Option<f64>| -> Vec<Series> {
        loads
            .iter()
            .enumerate()
            .map(|(l, (imep, ss))| Series {
                name: if named(l) {
                    format!("IMEP {} bar", enginedyn_numerics::format::human(*imep))
                } else {
                    String::new()
                },
                points: ss.iter().filter_map(|s| f(s).map(|v| (s.rpm, v))).collect(),
                dashed: false,
                marker: single,
                color: (loads.len() > 8).then(|| load_colour(l, loads.len())),
            })
            .collect()
    };
    let panel = |title: String, y: &str, series: Vec<Series>| Chart {
        title,
        x_label: "engine speed (rpm)".into(),
        y_label: y.into(),
        series,
        log: false,
        equal: false,
        angle_ticks: None,
    };
    let eta = loads
        .first()
        .and_then(|(_, ss)| ss.first())
        .map_or_else(|| "effective".to_string(), |s| crate::effective(s));
    Figure {
        file: "sweep.svg".into(),
        panels: vec![
            panel(
                format!("{engine_name} — mean torque, a line per load"),
                &format!("mean torque, {eta} (N m)"),
                lines(|x| x.mean_torque_nm),
            ),
            panel(
                "power, a line per load (synthesised diagrams)".into(),
                &format!("power, {eta} (kW)"),
                lines(|x| x.power_kw),
            ),
            panel(
                "flywheel sized once, at the point that needs the most".into(),
                "speed fluctuation δ achieved",
                lines(|x| x.speed_fluctuation_achieved),
            ),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns' headings come from KEYS, with units, and failed rows
    /// carry their error.
    #[test]
    fn key_table_rows() {
        let mut s = Summary::empty();
        s.rpm = 1500.0;
        s.mean_torque_nm = Some(-0.0001);
        s.imep_bar = Some(10.4714);
        let rows = [
            KeyRow {
                name: "a.csv".into(),
                figures: Some(key_figures(&KEY_FIGURES, &s)),
                error: String::new(),
                folder: None,
            },
            KeyRow {
                name: "b.csv".into(),
                figures: None,
                error: "line 3: bad".into(),
                folder: None,
            },
        ];
        let t = key_table("diagram", &KEY_FIGURES, &rows, Some(0.8));
        assert!(t.contains("[2] IMEP (bar)"), "{t}");
        assert!(
            t.contains("[3] mean torque, effective (η_m = 0.80) (N m)"),
            "{t}"
        );
        assert!(t.contains("10.471"), "{t}");
        assert!(t.contains("1500"), "{t}");
        assert!(!t.contains("-0.00"), "{t}");
        assert!(t.contains("error: line 3: bad"), "{t}");
    }

    /// A name with a line break or an escape stays on its row, escaped;
    /// the columns keep their place.
    #[test]
    fn control_characters_print_escaped() {
        let row = |name: &str, error: &str| KeyRow {
            name: name.into(),
            figures: error
                .is_empty()
                .then(|| key_figures(&KEY_FIGURES, &Summary::empty())),
            error: error.into(),
            folder: None,
        };
        let rows = [
            row("new\nline.csv", ""),
            row("plain.csv", ""),
            row("bad\u{1b}[31m.csv", "line 1:\nbad"),
        ];
        let t = key_table("diagram", &KEY_FIGURES, &rows, Some(0.8));
        let lines: Vec<&str> = t.lines().collect();
        assert!(lines[1].starts_with("new\\nline.csv "), "{t}");
        assert!(lines[2].starts_with("plain.csv "), "{t}");
        assert_eq!(lines[3], "bad\\u{1b}[31m.csv  error: line 1:\\nbad", "{t}");
        assert_eq!(lines[1].chars().count(), lines[2].chars().count(), "{t}");
        assert!(!t.contains('\u{1b}'), "{t}");
    }

    /// Links are percent-encoded (`run#1` and `a?b` are path characters
    /// there) and rows count from 1.
    #[test]
    fn index_links_and_numbers() {
        let rows = [KeyRow {
            name: "run#1.csv".into(),
            figures: Some(key_figures(&KEY_FIGURES, &Summary::empty())),
            error: String::new(),
            folder: Some("0001_run#1 a?b".into()),
        }];
        let html = index_html("E", &rows, Some(1.0));
        assert!(
            html.contains("href=\"0001_run%231%20a%3Fb/report.html\""),
            "{html}"
        );
        assert!(html.contains("<tr><td>1</td>"), "{html}");
    }

    /// The sweep chart says that one pressure trace serves every speed.
    #[test]
    fn sweep_title_says_the_pressures_are_the_same() {
        let mut a = Summary::empty();
        a.rpm = 2000.0;
        a.mean_torque_nm = Some(100.0);
        let mut b = a.clone();
        b.rpm = 4000.0;
        let fig = sweep_figure("E", &[&a, &b]);
        assert!(
            fig.panels[0]
                .title
                .contains("the same pressures at every speed"),
            "{}",
            fig.panels[0].title
        );
        let svg = fig.render().unwrap();
        assert!(svg.contains("the same pressures at every speed"));
    }
}
