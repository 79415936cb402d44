//! The combustion outputs of `run --out`: `heat_release.svg` (the rate and
//! the mass fraction burned with CA10/50/90 marked, the filter and γ in the
//! caption), `ca50_imep.svg` (CA50 against IMEP per cycle, with more than
//! one cycle) and the `report.html` section.

use crate::chart::{Chart, Figure, Series};
use crate::esc;
use enginedyn_engine::Engine;
use enginedyn_pipeline::Analysis;
use std::fmt::Write as _;

/// The angle (deg, from firing TDC in `[-cycle/2, cycle/2)`) of grid
/// index `k`.
fn angle(k: usize, n: usize, step_deg: f64) -> f64 {
    let a = k as f64 * step_deg;
    if k >= n / 2 {
        a - n as f64 * step_deg
    } else {
        a
    }
}

/// The points of `y` over the burn window, in angle order.
fn over_window(y: &[f64], step_deg: f64, (a, b): (f64, f64)) -> Vec<(f64, f64)> {
    let n = y.len();
    let mut pts: Vec<(f64, f64)> = (0..n)
        .map(|k| (angle(k, n, step_deg), y[k]))
        .filter(|(x, _)| *x >= a - 1e-9 && *x <= b + 1e-9)
        .collect();
    pts.sort_by(|p, q| p.0.total_cmp(&q.0));
    pts
}

/// `heat_release.svg` and, with more than one burning cycle,
/// `ca50_imep.svg`.
pub fn combustion_figures(engine: &Engine, a: &Analysis) -> Vec<Figure> {
    let (Some(c), Some(curves)) = (&a.summary.combustion, &a.heat_release) else {
        return Vec::new();
    };
    let step = a.step.to_degrees();
    let w = c.window_deg;
    let name = engine.name();
    let caption = format!("{}, {}", c.gamma, c.smoothing);
    let rate = Chart {
        x_label: "crank angle from firing TDC of cylinder 1 (deg)".into(),
        ..Chart::angle(
            format!(
                "{name} — heat release rate, {}",
                crate::chart::point(&a.summary)
            ),
            "dQ/dφ (J/deg), net apparent",
            vec![Series::from_points(
                format!("dQ/dφ, cylinder 1 (γ {caption})"),
                over_window(&curves.rate_j_deg, step, w).into_iter(),
            )],
        )
    };
    let mut mfb_series = Vec::new();
    match &curves.mfb {
        Some(m) => {
            mfb_series.push(Series::from_points(
                "mass fraction burned",
                over_window(m, step, w).into_iter(),
            ));
            for (pct, label) in [(10.0, "CA10"), (50.0, "CA50"), (90.0, "CA90")] {
                if let Some(x) = c.level(pct) {
                    mfb_series.push(Series {
                        name: format!("{label} {:.1}°", x),
                        points: vec![(x, 0.0), (x, pct / 100.0), (w.0, pct / 100.0)],
                        dashed: true,
                        marker: false,
                        color: None,
                    });
                }
            }
        }
        None => {
            let q = over_window(&curves.cumulative_j, step, w);
            mfb_series.push(Series::from_points(
                "cumulative heat release (J): no combustion",
                q.into_iter(),
            ));
        }
    }
    let mfb = Chart::angle(
        format!("mass fraction burned (min–max rule, {}…{}°)", w.0, w.1),
        if curves.mfb.is_some() {
            "mass fraction burned"
        } else {
            "heat released (J)"
        },
        mfb_series,
    );
    let mut figs = vec![Figure {
        file: "heat_release.svg".into(),
        panels: vec![rate, mfb],
    }];
    if a.burn_cycles.len() > 1 {
        figs.push(Figure::single("ca50_imep.svg", scatter(name, a)));
    }
    if let Some((m, threshold)) = &a.most_knocking {
        figs.push(Figure::single(
            "knock.svg",
            knock_chart(name, m, *threshold),
        ));
    }
    figs
}

/// The band-passed pressure of the most knocking cycle over the knock
/// window, beside ± the threshold.
fn knock_chart(name: &str, m: &enginedyn_pipeline::MostKnocking, threshold: f64) -> Chart {
    let (x0, x1) = (
        m.trace.first().map_or(0.0, |p| p.0),
        m.trace.last().map_or(0.0, |p| p.0),
    );
    let which = if m.cylinder > 0 {
        format!("cycle {} of cylinder {}", m.cycle, m.cylinder)
    } else {
        format!("cycle {}", m.cycle)
    };
    let bar = threshold / 1e5;
    let mut over = Series::hline(
        format!("± threshold {bar} bar (--knock-threshold)"),
        bar,
        x0,
        x1,
    );
    over.points
        .extend([(f64::NAN, f64::NAN), (x0, -bar), (x1, -bar)]);
    Chart {
        title: format!(
            "{name} — knock: the band-passed pressure of {which}, MAPO {:.3} bar",
            m.mapo_pa / 1e5
        ),
        x_label: "crank angle from firing TDC (deg)".into(),
        y_label: "band-passed pressure (bar)".into(),
        series: vec![
            Series::from_points(
                format!("band-passed pressure, {which}"),
                m.trace
                    .iter()
                    .map(|&(x, p)| (x, p / 1e5))
                    .collect::<Vec<_>>()
                    .into_iter(),
            ),
            over,
        ],
        log: false,
        equal: false,
        angle_ticks: None,
    }
}

/// CA50 against IMEP, a marker per cycle (a cylinder a series), with the
/// mean and the ±σ box of both (the axes padded: no cycle on the frame).
fn scatter(name: &str, a: &Analysis) -> Chart {
    let pts = &a.burn_cycles;
    let mut cylinders: Vec<i64> = pts.iter().map(|p| p.0).collect();
    cylinders.sort_unstable();
    cylinders.dedup();
    let mut series: Vec<Series> = cylinders
        .iter()
        .map(|&cyl| Series {
            name: if cyl > 0 {
                format!("cylinder {cyl}")
            } else {
                "each cycle".into()
            },
            points: pts
                .iter()
                .filter(|p| p.0 == cyl)
                .map(|p| (p.3, p.2))
                .collect(),
            dashed: false,
            marker: true,
            color: None,
        })
        .collect();
    let (mx, sx) = enginedyn_numerics::mean_std(pts.iter().map(|p| p.3));
    let (my, sy) = enginedyn_numerics::mean_std(pts.iter().map(|p| p.2));
    if sx.is_finite() && sy.is_finite() {
        let (x0, x1, y0, y1) = (mx - sx, mx + sx, my - sy, my + sy);
        series.push(Series {
            name: format!("mean CA50 {mx:.1}° ± {sx:.1}°, IMEP {my:.2} ± {sy:.2} bar (±σ box)"),
            points: vec![
                (x0, y0),
                (x1, y0),
                (x1, y1),
                (x0, y1),
                (x0, y0),
                (f64::NAN, f64::NAN),
                (x0, my),
                (x1, my),
                (f64::NAN, f64::NAN),
                (mx, y0),
                (mx, y1),
            ],
            dashed: true,
            marker: false,
            color: None,
        });
    }
    Chart {
        title: format!("{name} — CA50 against IMEP, {} cycles", pts.len()),
        x_label: "CA50 (deg from firing TDC)".into(),
        y_label: "IMEP (bar)".into(),
        series,
        log: false,
        equal: false,
        angle_ticks: None,
    }
}

/// The `report.html` section "Combustion": the figures of the mean trace,
/// their spread over the cycles, and the method.
pub fn combustion_section(a: &Analysis) -> Option<(String, String)> {
    let c = a.summary.combustion.as_ref()?;
    let mut o = String::from("<table>\n");
    let mut row = |k: &str, v: Option<f64>, unit: &str, digits: usize| {
        let shown = v.map_or("—".to_string(), |x| crate::fixed(x, digits));
        let _ = writeln!(
            o,
            "<tr><th>{}</th><td class=\"v\">{}</td><td>{}</td></tr>",
            esc(k),
            esc(&shown),
            esc(unit)
        );
    };
    for (pct, deg) in &c.levels {
        row(&format!("CA{pct}"), *deg, "deg", 2);
    }
    row("burn duration 10–90 %", c.burn_10_90_deg, "deg", 2);
    row("start / end of combustion: SOC", c.soc_deg, "deg", 1);
    row("start / end of combustion: EOC", c.eoc_deg, "deg", 1);
    row("net heat released per cylinder", c.heat_released_j, "J", 1);
    row(
        "max pressure rise dp/dφ",
        c.dp_dphi_max_bar_deg,
        "bar/deg",
        3,
    );
    row("  at", c.dp_dphi_max_angle_deg, "deg", 1);
    row("IMEP gross (−180…180°)", c.imep_gross_bar, "bar", 3);
    row(
        "PMEP (net − gross; negative: a pumping loss)",
        c.pmep_bar,
        "bar",
        3,
    );
    row("CA50 std over cycles", c.ca50_std_deg, "deg", 3);
    row(
        "10–90 duration std over cycles",
        c.burn_10_90_std_deg,
        "deg",
        3,
    );
    row(
        "max dp/dφ std over cycles",
        c.dp_dphi_max_std_bar_deg,
        "bar/deg",
        3,
    );
    row("IMEP LNV (lowest / mean)", c.imep_lnv, "", 4);
    let _ = writeln!(
        o,
        "</table>\n<p>Single-zone net apparent heat release (first law), γ {}; {}; burn points by the min–max rule in the window {}°. No wall-heat model (gross heat release) and no knock metrics.</p>",
        esc(&c.gamma),
        esc(&c.smoothing),
        esc(&c.burn_window)
    );
    Some(("Combustion".into(), o))
}
