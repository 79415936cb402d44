//! The engine design report (`enginedyn report`, INTERFACE "The design
//! report"): one self-contained page that opens with the figures a
//! reviewer checks first and then gives each study its section, with the
//! settings it used, its tables and its charts. The studies are computed
//! elsewhere (`enginedyn_session::design`); this module lays out what they
//! give: the full-load line, the map's contours, the crank-train loads at a
//! point, the firing-order ranking.

use crate::chart::{Chart, Figure, Series};
use crate::contour::{ContourChart, Mark, Node};
use crate::html::esc;
use enginedyn_balance::Study as FiringStudy;
use enginedyn_engine::Engine;
use enginedyn_numerics::format::{csv, fixed, human, sig};
use enginedyn_pipeline::{Analysis, Summary};
use std::fmt::Write as _;

/// A figure of the one-screen summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Headline {
    /// What it is ("rated power").
    pub label: String,
    /// The value as shown.
    pub value: String,
    /// Its unit.
    pub unit: String,
    /// Where it holds ("at 5600 rpm, full load").
    pub at: String,
    /// The section that gives it (its anchor).
    pub section: &'static str,
}

/// One section of the page.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Section {
    /// Its anchor (`full-load`).
    pub id: &'static str,
    /// Its heading.
    pub heading: String,
    /// The settings it used: (what, value).
    pub settings: Vec<(String, String)>,
    /// Tables and text, already HTML.
    pub body: String,
    /// Charts: (file name, SVG text), shown in order after the body.
    pub charts: Vec<(String, String)>,
    /// What the study noted, shown last.
    pub notes: Vec<String>,
}

/// The whole page.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DesignPage {
    /// The title (the engine's name).
    pub title: String,
    /// Under the title: what the report covers and what computed it.
    pub lead: String,
    /// The one-screen summary.
    pub headlines: Vec<Headline>,
    /// The sections, in order.
    pub sections: Vec<Section>,
}

/// A speed × load map as the report reads it: `rows` loads (lowest first)
/// of `rpms.len()` points each.
#[derive(Debug, Clone)]
pub struct MapView<'a> {
    /// The speeds (rpm).
    pub rpms: &'a [f64],
    /// Each row's load as named ("50 %", "IMEP 8 bar").
    pub load_names: Vec<String>,
    /// The points, row by row.
    pub cells: Vec<&'a Summary>,
    /// Each point's IMEP target (bar), in the order of `cells`.
    pub imep_targets: Vec<f64>,
    /// The rated-power point (rpm, kW) and the peak-torque point (rpm, N m).
    pub rated: Option<(f64, f64)>,
    /// See `rated`.
    pub peak: Option<(f64, f64)>,
    /// Whether the effective figures are brake ones (`[friction]`).
    pub brake: bool,
}

impl MapView<'_> {
    /// The top row: the full-load line.
    pub fn full_load(&self) -> &[&Summary] {
        let n = self.rpms.len();
        let start = self.cells.len().saturating_sub(n);
        &self.cells[start..]
    }

    /// "BMEP" with friction, else "effective mean pressure (IMEP × η_m)".
    pub fn mep_label(&self) -> &'static str {
        if self.brake {
            "BMEP (bar)"
        } else {
            "effective mean pressure, IMEP × η_m (bar)"
        }
    }

    /// "brake" with friction, else "effective".
    pub fn basis(&self) -> &'static str {
        if self.brake { "brake" } else { "effective" }
    }
}

/// The page's style: print-friendly, one column, tables that scroll
/// rather than overflow.
const STYLE: &str = "body{font-family:sans-serif;margin:24px auto;max-width:1100px;color:#222;line-height:1.35}\
h1{font-size:24px;margin-bottom:4px}h2{font-size:19px;margin-top:36px;border-bottom:2px solid #ccc;padding-bottom:3px}\
h3{font-size:15px;margin:18px 0 6px}p.lead{color:#555;margin-top:0}\
table{border-collapse:collapse;font-size:14px;margin:6px 0 12px}td,th{padding:3px 10px;border-bottom:1px solid #eee;text-align:left;vertical-align:top}\
td.v{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}th.v{text-align:right}\
.scroll{overflow-x:auto}.settings{font-size:13px;color:#444;background:#f6f6f6;padding:6px 10px;margin:6px 0 10px}\
.settings span{margin-right:16px;display:inline-block}.cards{display:grid;grid-template-columns:repeat(auto-fill,minmax(240px,1fr));gap:10px;margin:10px 0}\
.card{border:1px solid #ddd;border-radius:4px;padding:8px 12px}.card .l{font-size:13px;color:#555}.card .n{font-size:22px;font-variant-numeric:tabular-nums}\
.card .u{font-size:14px;color:#333;margin-left:4px}.card .a{font-size:12px;color:#666}.card a{color:inherit;text-decoration:none}\
figure{margin:12px 0}figure svg{max-width:100%;height:auto}figcaption{font-size:13px;color:#555}\
ul.notes{font-size:13px;color:#444}nav{font-size:14px;margin:8px 0 0}nav a{margin-right:14px}\
@media print{h2{break-before:page}figure{break-inside:avoid}}";

/// The page as HTML: the title, the summary cards, a contents line, then
/// every section with its settings, body, charts (inlined SVG) and notes.
pub fn design_html(page: &DesignPage) -> String {
    let mut o = String::with_capacity(1 << 20);
    let _ = write!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title>\n<style>{STYLE}</style></head><body>\n<h1>{}</h1>\n<p class=\"lead\">{}</p>\n",
        esc(&page.title),
        esc(&page.title),
        esc(&page.lead)
    );
    let _ = writeln!(o, "<div class=\"cards\">");
    for h in &page.headlines {
        let _ = writeln!(
            o,
            "<div class=\"card\"><a href=\"#{}\"><div class=\"l\">{}</div><div><span class=\"n\">{}</span><span class=\"u\">{}</span></div><div class=\"a\">{}</div></a></div>",
            h.section,
            esc(&h.label),
            esc(&h.value),
            esc(&h.unit),
            esc(&h.at)
        );
    }
    let _ = writeln!(o, "</div>\n<nav>");
    for s in &page.sections {
        let _ = write!(o, "<a href=\"#{}\">{}</a>", s.id, esc(&s.heading));
    }
    let _ = writeln!(o, "</nav>");
    for s in &page.sections {
        let _ = writeln!(o, "<h2 id=\"{}\">{}</h2>", s.id, esc(&s.heading));
        if !s.settings.is_empty() {
            let _ = write!(o, "<div class=\"settings\">");
            for (k, v) in &s.settings {
                let _ = write!(o, "<span><b>{}</b>: {}</span>", esc(k), esc(v));
            }
            let _ = writeln!(o, "</div>");
        }
        o.push_str(&s.body);
        for (name, svg) in &s.charts {
            let body = svg.find("<svg").map_or(svg.as_str(), |i| &svg[i..]);
            let _ = writeln!(
                o,
                "<figure id=\"{}\">{body}<figcaption>{}</figcaption></figure>",
                esc(name.trim_end_matches(".svg")),
                esc(name)
            );
        }
        if !s.notes.is_empty() {
            let _ = writeln!(o, "<ul class=\"notes\">");
            for n in &s.notes {
                let _ = writeln!(o, "<li>{}</li>", esc(n));
            }
            let _ = writeln!(o, "</ul>");
        }
    }
    let _ = writeln!(o, "</body></html>");
    o
}

/// A table of text cells as HTML (every cell escaped here), in a box that
/// scrolls sideways on a narrow screen; `numeric` columns right-aligned.
pub fn text_table(head: &[&str], rows: &[Vec<String>], numeric: &[bool]) -> String {
    let mut o = String::from("<div class=\"scroll\"><table><tr>");
    for (k, h) in head.iter().enumerate() {
        let class = if numeric.get(k).copied().unwrap_or(false) {
            " class=\"v\""
        } else {
            ""
        };
        let _ = write!(o, "<th{class}>{}</th>", esc(h));
    }
    o.push_str("</tr>\n");
    for r in rows {
        o.push_str("<tr>");
        for (k, c) in r.iter().enumerate() {
            if numeric.get(k).copied().unwrap_or(false) {
                let _ = write!(o, "<td class=\"v\">{}</td>", esc(c));
            } else {
                let _ = write!(o, "<td>{}</td>", esc(c));
            }
        }
        o.push_str("</tr>\n");
    }
    o.push_str("</table></div>\n");
    o
}

/// The same rows as CSV (a header of `keys`; numbers as [`csv()`] writes
/// them, text cells never starting a formula).
pub fn table_csv(keys: &[&str], rows: &[Vec<Option<f64>>]) -> String {
    let mut o = keys.join(",");
    o.push('\n');
    for r in rows {
        let cells: Vec<String> = r.iter().map(|v| v.map_or(String::new(), csv)).collect();
        o.push_str(&cells.join(","));
        o.push('\n');
    }
    o
}

/// A figure shown with `digits` decimals, `–` when absent (the report's
/// tables and cards).
pub fn shown(v: Option<f64>, digits: usize) -> String {
    v.map_or("–".to_string(), |x| fixed(x, digits))
}

/// The full-load line's columns: (CSV key, heading with unit, decimals,
/// the figure).
type Column = (
    &'static str,
    &'static str,
    usize,
    fn(&Summary) -> Option<f64>,
);

const FULL_LOAD: [Column; 11] = [
    ("rpm", "speed (rpm)", 0, |s| Some(s.rpm)),
    ("imep_bar", "IMEP (bar)", 2, |s| s.imep_bar),
    ("fmep_bar", "FMEP (bar)", 2, |s| {
        s.brake.as_ref().map(|b| b.fmep_bar)
    }),
    ("bmep_bar", "BMEP (bar)", 2, |s| {
        s.brake.as_ref().map(|b| b.bmep_bar)
    }),
    ("indicated_torque_nm", "indicated torque (N m)", 1, |s| {
        s.indicated_mean_torque_nm
    }),
    ("torque_nm", "brake torque (N m)", 1, |s| s.mean_torque_nm),
    ("indicated_power_kw", "indicated power (kW)", 1, |s| {
        s.indicated_power_kw
    }),
    ("power_kw", "brake power (kW)", 1, |s| s.power_kw),
    ("mechanical_efficiency", "η_m", 3, |s| {
        Some(s.mechanical_efficiency)
    }),
    ("p_max_bar", "p_max (bar)", 1, |s| s.p_max_bar),
    ("p_max_angle_deg", "p_max at (° after TDC)", 1, |s| {
        s.p_max_angle_deg
    }),
];

/// The full-load line as a table (HTML) and as CSV: a row a speed.
pub fn full_load_table(view: &MapView<'_>) -> (String, String) {
    let cols: Vec<&Column> = FULL_LOAD
        .iter()
        .filter(|c| view.brake || !matches!(c.0, "fmep_bar" | "bmep_bar"))
        .collect();
    let heads: Vec<String> = cols
        .iter()
        .map(|c| {
            if view.brake {
                c.1.to_string()
            } else {
                c.1.replace("brake", "effective")
            }
        })
        .collect();
    let head: Vec<&str> = heads.iter().map(String::as_str).collect();
    let rows: Vec<Vec<String>> = view
        .full_load()
        .iter()
        .map(|s| cols.iter().map(|c| shown((c.3)(s), c.2)).collect())
        .collect();
    let numeric = vec![true; cols.len()];
    let keys: Vec<&str> = cols.iter().map(|c| c.0).collect();
    let values: Vec<Vec<Option<f64>>> = view
        .full_load()
        .iter()
        .map(|s| cols.iter().map(|c| (c.3)(s)).collect())
        .collect();
    (
        text_table(&head, &rows, &numeric),
        table_csv(&keys, &values),
    )
}

/// The full-load curve: torque (brake and indicated) and power over
/// speed, the rated-power and peak-torque points marked.
pub fn full_load_figure(name: &str, view: &MapView<'_>) -> Figure {
    let line = view.full_load();
    let pts = |f: fn(&Summary) -> Option<f64>| -> Vec<(f64, f64)> {
        line.iter()
            .map(|s| (s.rpm, f(s).unwrap_or(f64::NAN)))
            .collect()
    };
    let basis = view.basis();
    let mark = |name: String, at: Option<(f64, f64)>| Series {
        name,
        points: at.into_iter().collect(),
        dashed: false,
        marker: true,
        color: Some(plotters::style::RGBColor(214, 39, 40)),
    };
    let torque = Chart {
        title: format!("{name} — torque at full load"),
        x_label: "speed (rpm)".into(),
        y_label: "torque (N m)".into(),
        series: vec![
            Series::from_points(
                format!("{basis} torque"),
                pts(|s| s.mean_torque_nm).into_iter(),
            ),
            Series::from_points(
                "indicated torque",
                pts(|s| s.indicated_mean_torque_nm).into_iter(),
            ),
            mark(
                match view.peak {
                    Some((r, t)) => format!("peak {} N m at {} rpm", fixed(t, 1), human(r)),
                    None => "peak torque".into(),
                },
                view.peak,
            ),
        ],
        log: false,
        equal: false,
        angle_ticks: None,
    };
    let power = Chart {
        title: "power at full load".into(),
        x_label: "speed (rpm)".into(),
        y_label: "power (kW)".into(),
        series: vec![
            Series::from_points(format!("{basis} power"), pts(|s| s.power_kw).into_iter()),
            Series::from_points("indicated power", pts(|s| s.indicated_power_kw).into_iter()),
            mark(
                match view.rated {
                    Some((r, p)) => format!("rated {} kW at {} rpm", fixed(p, 1), human(r)),
                    None => "rated power".into(),
                },
                view.rated,
            ),
        ],
        log: false,
        equal: false,
        angle_ticks: None,
    };
    Figure {
        file: "full_load.svg".into(),
        panels: vec![torque, power],
    }
}

/// The map's contour charts: peak pressure, the speed fluctuation the one
/// flywheel gives, each point's own required inertia and (with friction)
/// the mechanical efficiency, over speed and mean effective pressure, the
/// full-load line and its two named points drawn on each.
pub fn map_contours(name: &str, view: &MapView<'_>) -> Vec<ContourChart> {
    type Field = (
        &'static str,
        &'static str,
        &'static str,
        f64,
        fn(&Summary) -> Option<f64>,
    );
    let mut fields: Vec<Field> = vec![
        (
            "map_p_max.svg",
            "peak cylinder pressure p_max",
            "bar",
            1.0,
            |s| s.p_max_bar,
        ),
        (
            "map_delta.svg",
            "speed fluctuation δ with the map's flywheel",
            "δ (‰)",
            1e3,
            |s| s.speed_fluctuation_achieved,
        ),
        (
            "map_inertia.svg",
            "inertia each point needs for its δ",
            "kg m²",
            1.0,
            |s| s.required_inertia_kg_m2,
        ),
    ];
    if view.brake {
        fields.push((
            "map_eta_m.svg",
            "mechanical efficiency η_m (Chen–Flynn)",
            "η_m",
            1.0,
            |s| s.brake.as_ref().and_then(|b| b.mechanical_efficiency),
        ));
    }
    let y = |s: &Summary| s.effective_mep_bar().unwrap_or(f64::NAN);
    let line: Vec<(f64, f64)> = view.full_load().iter().map(|s| (s.rpm, y(s))).collect();
    let at = |rpm: f64| {
        view.full_load()
            .iter()
            .find(|s| s.rpm.to_bits() == rpm.to_bits())
            .map(|s| (s.rpm, y(s)))
    };
    let mut marks = Vec::new();
    if let Some((r, p)) = view.rated
        && let Some(pt) = at(r)
    {
        marks.push(Mark {
            name: format!("rated power {} kW at {} rpm", fixed(p, 1), human(r)),
            at: pt,
        });
    }
    if let Some((r, t)) = view.peak
        && let Some(pt) = at(r)
    {
        marks.push(Mark {
            name: format!("peak torque {} N m at {} rpm", fixed(t, 1), human(r)),
            at: pt,
        });
    }
    fields
        .into_iter()
        .map(|(file, what, unit, scale, get)| ContourChart {
            file: file.into(),
            title: format!("{name} — {what}"),
            x_label: "speed (rpm)".into(),
            y_label: view.mep_label().into(),
            unit: unit.into(),
            columns: view.rpms.len(),
            nodes: view
                .cells
                .iter()
                .map(|s| Node {
                    x: s.rpm,
                    y: y(s),
                    z: get(s).map(|v| v * scale),
                })
                .collect(),
            line: Some(("full-load line".into(), line.clone())),
            marks: marks.clone(),
        })
        .collect()
}

/// The crank-train loads at one operating point (`what`: "rated power"):
/// a table of the largest loads and each main bearing's, and the charts
/// (crank-pin polar, journal torques, main-bearing loads) named with
/// `prefix`.
pub fn crank_train(
    engine: &Engine,
    a: &Analysis,
    prefix: &str,
) -> Result<(String, Vec<(String, String)>), crate::ReportError> {
    let s = &a.summary;
    let kn = |v: Option<f64>| shown(v.map(|x| x / 1e3), 2);
    let mut rows = vec![
        vec![
            "peak cylinder pressure".into(),
            shown(s.p_max_bar, 1),
            "bar".into(),
        ],
        vec![
            "largest gas force".into(),
            kn(s.gas_force_max_n),
            "kN".into(),
        ],
        vec![
            "largest rod force".into(),
            kn(s.rod_force_max_n),
            "kN".into(),
        ],
        vec![
            "largest piston side force".into(),
            kn(s.side_force_max_n),
            "kN".into(),
        ],
        vec![
            "largest crank-pin load".into(),
            kn(s.crankpin_load_max_n),
            "kN".into(),
        ],
        vec![
            "mean crank-pin load".into(),
            kn(s.crankpin_load_mean_n),
            "kN".into(),
        ],
        vec![
            format!("largest journal torque (journal {})", s.journal_most_loaded),
            shown(Some(s.journal_torque_max_nm), 1),
            "N m".into(),
        ],
    ];
    for (k, b) in a.bearings.iter().enumerate() {
        let max = b.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mean = b.iter().sum::<f64>() / b.len().max(1) as f64;
        rows.push(vec![
            format!("main bearing {} (from the free end): largest / mean", k + 1),
            format!("{} / {}", fixed(max / 1e3, 2), fixed(mean / 1e3, 2)),
            "kN".into(),
        ]);
    }
    let table = text_table(&["load", "value", "unit"], &rows, &[false, true, false]);
    let wanted = ["crankpin_polar.svg", "journal_torques.svg"];
    let mut charts = Vec::new();
    for f in crate::run_figures(engine, a)
        .into_iter()
        .filter(|f| wanted.contains(&f.file.as_str()))
    {
        let file = format!("{prefix}_{}", f.file);
        let fig = Figure { file, ..f };
        charts.push((fig.file.clone(), fig.render()?));
    }
    if !a.bearings.is_empty() {
        let fig = bearings_figure(engine.name(), a, prefix);
        charts.push((fig.file.clone(), fig.render()?));
    }
    Ok((table, charts))
}

/// Main-bearing load magnitudes over the cycle, a line a bearing.
fn bearings_figure(name: &str, a: &Analysis, prefix: &str) -> Figure {
    let step = a.step.to_degrees();
    let series = a
        .bearings
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let kn: Vec<f64> = b.iter().map(|x| x / 1e3).collect();
            crate::periodic(format!("bearing {}", k + 1), &kn, step, false)
        })
        .collect();
    Figure::single(
        format!("{prefix}_main_bearings.svg"),
        Chart::angle(
            format!(
                "{name} — main-bearing loads, {}",
                crate::chart::point(&a.summary)
            ),
            "load magnitude (kN)",
            series,
        ),
    )
}

/// The engine crank's firing orders ranked (at most `top`), and the free
/// forces and moments of its reciprocating masses, as HTML.
pub fn firing_ranking(s: &FiringStudy, top: usize) -> String {
    let Some(c) = s
        .cranks
        .iter()
        .find(|c| c.engine_crank)
        .or(s.cranks.first())
    else {
        return "<p>No crank to rank.</p>\n".into();
    };
    let f = &c.free;
    let mut o = String::from(
        "<h3>Free forces and moments (reciprocating masses, before counterweights)</h3>\n",
    );
    o.push_str(&text_table(
        &["order", "free force (N)", "free moment (N m)"],
        &[
            vec![
                "1st".into(),
                sig(f.free_force_1_n, 4),
                format!(
                    "{} ({} left after counterweights)",
                    sig(f.free_moment_1_nm, 4),
                    sig(f.free_moment_1_residual_nm, 4)
                ),
            ],
            vec![
                "2nd".into(),
                sig(f.free_force_2_n, 4),
                sig(f.free_moment_2_nm, 4),
            ],
        ],
        &[false, true, true],
    ));
    let _ = writeln!(
        o,
        "<h3>Firing orders of the crank {}, ranked (best first)</h3>",
        esc(&c
            .crank_angles_deg
            .iter()
            .map(|a| human(*a))
            .collect::<Vec<_>>()
            .join("-"))
    );
    let dashed = |v: &[usize]| {
        v.iter()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join("-")
    };
    let rows: Vec<Vec<String>> = c
        .orders
        .iter()
        .take(top)
        .enumerate()
        .map(|(k, ord)| {
            let j = ord.journal.as_ref();
            vec![
                (k + 1).to_string(),
                dashed(&ord.order.order),
                ord.criteria
                    .intervals_deg
                    .iter()
                    .map(|a| human((a * 10.0).round() / 10.0))
                    .collect::<Vec<_>>()
                    .join(" "),
                ord.criteria.neighbour_consecutive.to_string(),
                j.map_or("–".into(), |j| {
                    format!(
                        "{} (journal {})",
                        fixed(j.max_torque_nm, 1),
                        j.max_torque_journal
                    )
                }),
                fixed(ord.score, 3),
            ]
        })
        .collect();
    o.push_str(&text_table(
        &[
            "rank",
            "firing order",
            "intervals (°)",
            "neighbours in a row",
            "largest journal torque (N m)",
            "score",
        ],
        &rows,
        &[true, false, false, true, true, true],
    ));
    if c.orders.len() > top {
        let _ = writeln!(
            o,
            "<p>{} more in <code>tables/firing_orders.csv</code>.</p>",
            c.orders.len() - top
        );
    }
    o
}

/// `README.txt` of the tables folder: what each table holds.
pub fn tables_readme(files: &[(&str, &str)]) -> String {
    let mut o = String::from(
        "Tables of the engine design report (enginedyn report); report.html shows them.\n\n",
    );
    for (file, what) in files {
        let _ = writeln!(o, "{file}: {what}");
    }
    o
}
