//! The tolerance study's outputs (`enginedyn tolerance`, INTERFACE.md):
//! the printed table, `tolerance.csv`, `tolerance.json`, the tornado
//! panels of `tolerance.svg`, and the section `run --out` adds to
//! `report.html` for an engine file with `[tolerances]`. The study itself
//! is `enginedyn_tolerance`'s; this module only writes it.

use crate::{Extra, ReportError, TornadoBar, TornadoPanel};
use enginedyn_engine::Engine;
use enginedyn_tolerance::{Method, Output, Row, Stack, Study};
use std::fmt::Write as _;

/// Contributions shown per result on standard output and per tornado panel.
const SHOWN: usize = 6;

/// What `tolerance --out DIR` writes: the table, the stack-up, the chart.
pub const TOLERANCE_FILES: [&str; 3] = ["tolerance.csv", "tolerance.json", "tolerance.svg"];

/// `tolerance.svg` of `enginedyn tolerance`: one tornado panel per result
/// ([`tolerance_panels`]), titled with the speed, the grid and the Monte
/// Carlo run.
pub fn tolerance_svg(engine: &Engine, rpm: f64, study: &Study) -> Result<String, ReportError> {
    let title = format!(
        "{} — tolerances at {rpm:.0} rpm: each parameter alone at ±t (linear model, {}° grid){}",
        engine.name(),
        study.step_deg,
        match &study.monte_carlo {
            Some(m) => format!(
                "; σ lines: RSS and Monte Carlo ({} samples, seed {}, {}° grid)",
                m.samples, m.seed, m.step_deg
            ),
            None => String::new(),
        }
    );
    crate::tornado_svg(TOLERANCE_FILES[2], &title, &tolerance_panels(study), 4)
}

/// What `run --out` adds to `report.html` for an engine file with
/// `[tolerances]`: the section "Tolerances" (the stack-up per result with
/// its three largest contributions; with the run's `summary`, a result that
/// is a summary key shows the run's own value as nominal) and the tornado
/// chart `tolerance.svg`, for a linear-model study on the `step_deg` grid.
pub fn tolerance_extra(
    engine: &Engine,
    step_deg: f64,
    study: &Study,
    summary: Option<&enginedyn_pipeline::Summary>,
) -> Result<Extra, ReportError> {
    let title = format!(
        "{} — tolerances: each parameter alone at ±t (linear model, {step_deg}° grid)",
        engine.name()
    );
    let svg = crate::tornado_svg("tolerance.svg", &title, &tolerance_panels(study), 4)?;
    Ok(Extra {
        sections: vec![("Tolerances".to_string(), html_table(study, summary))],
        charts: vec![("tolerance.svg".to_string(), svg)],
    })
}

/// A number with about four significant digits, exponent form when tiny or huge.
fn num(x: f64) -> String {
    let a = x.abs();
    if !x.is_finite() {
        "—".into()
    } else if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e6).contains(&a) {
        format!("{x:.3e}")
    } else {
        let digits = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{x:.digits$}")
    }
}

/// A result's nominal as every output writes it: 0 when it is rounding
/// noise against the result's scale (`Stack::zero`: a balanced engine's
/// order-0.5 torque of 1.6e-13 N m cancels to 0).
fn shown_nominal(st: &Stack) -> f64 {
    if st.zero { 0.0 } else { st.nominal }
}

/// [`shown_nominal`] of result `o`.
fn nominal_of(s: &Study, o: Output) -> Option<f64> {
    s.stacks.iter().find(|st| st.output == o).map(shown_nominal)
}

fn opt(x: Option<f64>) -> String {
    x.map(num).unwrap_or_else(|| "—".into())
}

/// A result's unit for a printed value (empty for a ratio).
fn unit(o: Output) -> &'static str {
    o.unit()
}

/// Rows of one result with a deviation, largest first.
fn ranked(study: &Study, o: Output) -> Vec<&Row> {
    let mut rows: Vec<&Row> = study.rows_of(o).filter(|r| r.deviation > 0.0).collect();
    rows.sort_by(|a, b| b.deviation.total_cmp(&a.deviation));
    rows
}

/// The readable table: stack-up per result, then each result's largest
/// contributions with sensitivity, influence and deviation.
pub fn tolerance_table(engine: &Engine, diagram: &str, rpm: f64, s: &Study) -> String {
    let mut o = crate::heading(engine, "tolerance study, ", rpm, diagram);
    let _ = writeln!(
        o,
        "sensitivities: full pipeline runs on the {}° grid (central differences, geometry analytic)",
        s.step_deg
    );
    match &s.monte_carlo {
        Some(m) => {
            let _ = writeln!(
                o,
                "Monte Carlo: {} samples, seed {}, uniform on ±t, on the {}° grid",
                m.samples, m.seed, m.step_deg
            );
        }
        None => {
            let _ = writeln!(o, "Monte Carlo: not run (--samples 0)");
        }
    }
    let _ = writeln!(o, "\ntolerances (±)");
    let mut seen = Vec::new();
    for i in &s.inputs {
        if seen.contains(&i.parameter) {
            continue;
        }
        seen.push(i.parameter);
        let per = match (i.per(), i.parameter) {
            (Some(what), _) => format!(", each {what} on its own"),
            (None, enginedyn_tolerance::Parameter::Tdc) => {
                " (+: the true firing TDC lies after the declared one)".into()
            }
            _ => String::new(),
        };
        let _ = writeln!(
            o,
            "  {:<26} {} {}{per}",
            i.parameter.key(),
            num(i.tolerance),
            i.parameter.unit()
        );
    }
    let _ = writeln!(
        o,
        "\nstack-up: worst case Σ|s|t, RSS σ = sqrt(Σ(s t)²)/√3, Monte Carlo σ and largest |deviation|"
    );
    let _ = writeln!(
        o,
        "  {:<24} {:>12} {:>11} {:>11} {:>11} {:>11} {:>9}  unit",
        "result", "nominal", "worst case", "RSS σ", "MC σ", "MC max", "lin. err"
    );
    for st in &s.stacks {
        let lin = match (st.linearity_error, st.zero) {
            (Some(e), false) => format!("{:.1} %", 100.0 * e),
            (Some(_), true) => "kink".into(),
            (None, _) => "—".into(),
        };
        let _ = writeln!(
            o,
            "  {:<24} {:>12} {:>11} {:>11} {:>11} {:>11} {:>9}  {}",
            st.output.key(),
            num(shown_nominal(st)),
            num(st.worst_case),
            num(st.rss),
            opt(st.monte_carlo_std),
            opt(st.monte_carlo_max_dev),
            lin,
            unit(st.output)
        );
    }
    let _ = writeln!(
        o,
        "\ncontributions, largest first: sensitivity s (result unit per parameter unit), influence K = (dy/y)/(dx/x), deviation |s| t"
    );
    let mut untouched = Vec::new();
    for st in &s.stacks {
        let rows = ranked(s, st.output);
        if rows.is_empty() {
            untouched.push(st.output.key());
            continue;
        }
        let nominal = shown_nominal(st);
        let shown = format!("{} {}", num(nominal), unit(st.output));
        let _ = writeln!(
            o,
            "  {} = {}{}",
            st.output.key(),
            shown.trim_end(),
            if st.zero {
                " (0: it cancels; one-sided slopes)"
            } else {
                ""
            }
        );
        let total: f64 = rows.iter().map(|r| r.deviation.powi(2)).sum();
        for r in rows.iter().take(SHOWN) {
            let per_unit = match unit(st.output) {
                "" => format!("1/{}", r.input.parameter.unit()),
                u => format!("{u}/{}", r.input.parameter.unit()),
            };
            let _ = writeln!(
                o,
                "    {:<24} ±{:<9} s {:>11} {:<10} K {:>9}  dev {:>10}  {:>3.0} % of variance{}",
                r.input.name(),
                num(r.input.tolerance),
                num(r.sensitivity.value),
                per_unit,
                r.influence.map(num).unwrap_or_else(|| "—".into()),
                num(r.deviation),
                100.0 * r.deviation.powi(2) / total,
                if r.sensitivity.method == Method::OneSided {
                    " (kink)"
                } else {
                    ""
                }
            );
        }
        if rows.len() > SHOWN {
            let _ = writeln!(o, "    … {} more in tolerance.csv", rows.len() - SHOWN);
        }
    }
    if !untouched.is_empty() {
        let _ = writeln!(o, "  not moved by any tolerance: {}", untouched.join(", "));
    }
    let notes: Vec<(&Stack, &String)> = s
        .stacks
        .iter()
        .filter_map(|st| st.note.as_ref().map(|n| (st, n)))
        .collect();
    if !notes.is_empty() {
        let _ = writeln!(o, "\nnotes");
        for (st, n) in notes {
            let _ = writeln!(o, "  {}: {n}", st.output.key());
        }
    }
    o
}

/// `tolerance.csv`: one row per input and result.
pub fn tolerance_csv(s: &Study) -> String {
    let mut o =
        String::from("parameter,tolerance,result,nominal,sensitivity,influence,deviation\n");
    let cell = enginedyn_numerics::format::csv;
    let text = enginedyn_numerics::format::csv_text;
    for r in &s.rows {
        let _ = writeln!(
            o,
            "{},{},{},{},{},{},{}",
            text(&r.input.name()),
            cell(r.input.tolerance),
            text(r.output.key()),
            cell(nominal_of(s, r.output).unwrap_or(r.nominal)),
            cell(r.sensitivity.value),
            r.influence.map(cell).unwrap_or_default(),
            cell(r.deviation)
        );
    }
    o
}

/// `tolerance.json`: per result, the stack-up and its Monte Carlo check.
pub fn tolerance_json(s: &Study) -> serde_json::Value {
    let n = |x: Option<f64>| match x {
        Some(v) if v.is_finite() => serde_json::Value::from(v),
        _ => serde_json::Value::Null,
    };
    let mut map = serde_json::Map::new();
    for st in &s.stacks {
        let mut m = serde_json::Map::new();
        m.insert("nominal".into(), n(Some(shown_nominal(st))));
        m.insert("worst_case".into(), n(Some(st.worst_case)));
        m.insert("rss".into(), n(Some(st.rss)));
        m.insert("monte_carlo_std".into(), n(st.monte_carlo_std));
        m.insert("monte_carlo_max_dev".into(), n(st.monte_carlo_max_dev));
        m.insert("linearity_error".into(), n(st.linearity_error));
        m.insert("monte_carlo_mean".into(), n(st.monte_carlo_mean));
        m.insert("zero_nominal".into(), st.zero.into());
        m.insert("kink".into(), st.kink.into());
        m.insert(
            "note".into(),
            st.note
                .clone()
                .map(serde_json::Value::from)
                .unwrap_or(serde_json::Value::Null),
        );
        map.insert(st.output.key().into(), serde_json::Value::Object(m));
    }
    serde_json::Value::Object(map)
}

/// One tornado panel per result that some tolerance moves: bars in % of
/// the nominal (absolute for a result whose nominal is 0), the side at
/// `+t` and at `-t` from the one-sided slopes, so a kink shows.
pub fn tolerance_panels(s: &Study) -> Vec<TornadoPanel> {
    let mut out = Vec::new();
    for st in &s.stacks {
        let rows = ranked(s, st.output);
        if rows.is_empty() {
            continue;
        }
        let (scale, x_label) = if st.zero {
            (1.0, format!("change ({})", unit(st.output)))
        } else {
            (
                100.0 / st.nominal.abs(),
                "change (% of nominal)".to_string(),
            )
        };
        let bar = |r: &Row| {
            let (fwd, bwd) = if r.sensitivity.method == Method::OneSided {
                r.sensitivity.one_sided
            } else {
                (r.sensitivity.value, r.sensitivity.value)
            };
            TornadoBar {
                label: r.input.label(),
                minus: -bwd * r.input.tolerance * scale,
                plus: fwd * r.input.tolerance * scale,
            }
        };
        // One more bar rather than "1 others": the rest in one RSS bar.
        let own = if rows.len() == SHOWN + 1 {
            SHOWN + 1
        } else {
            SHOWN
        };
        let mut bars: Vec<TornadoBar> = rows.iter().take(own).map(|r| bar(r)).collect();
        if rows.len() > own {
            let rest = rows[own..]
                .iter()
                .map(|r| (r.deviation * scale).powi(2))
                .sum::<f64>()
                .sqrt();
            bars.push(TornadoBar {
                label: format!("{} others (RSS)", rows.len() - own),
                minus: -rest,
                plus: rest,
            });
        }
        let mut marks = vec![("RSS σ (linear)".to_string(), st.rss * scale)];
        if let Some(m) = st.monte_carlo_std {
            marks.push(("Monte Carlo σ".to_string(), m * scale));
        }
        let shown = shown_nominal(st);
        let nominal = format!("{} {}", num(shown), unit(st.output));
        out.push(TornadoPanel {
            title: format!("{} = {}", st.output.label(), nominal.trim_end()),
            x_label,
            bars,
            marks,
        });
    }
    out
}

/// The stack-up per result with its three largest contributions, as HTML
/// (report's table and escaping). With the run's `summary`, a result that
/// is a summary key shows the run's own value as nominal (the study runs on
/// a coarser grid; its deviations are what it adds).
fn html_table(s: &Study, summary: Option<&enginedyn_pipeline::Summary>) -> String {
    use crate::esc;
    let mut list: Vec<String> = Vec::new();
    for i in &s.inputs {
        let item = format!("{} ±{}", i.parameter.key(), num(i.tolerance));
        if !list.contains(&item) {
            list.push(item);
        }
    }
    let mut o = format!(
        "<p>Each toleranced parameter alone at ±t, by the real pipeline (linear model; \
         <code>enginedyn tolerance</code> adds the Monte Carlo check). Tolerances: {}.</p>\n",
        esc(&list.join(", "))
    );
    let rows: Vec<Vec<String>> = s
        .stacks
        .iter()
        .map(|st| {
            let rows = ranked(s, st.output);
            let total: f64 = rows.iter().map(|r| r.deviation * r.deviation).sum();
            let top: Vec<String> = rows
                .iter()
                .take(3)
                .map(|r| {
                    format!(
                        "{} {:.0} %",
                        r.input.name(),
                        100.0 * r.deviation * r.deviation / total.max(f64::MIN_POSITIVE)
                    )
                })
                .collect();
            let caveat = if st.zero || st.kink {
                " (zero nominal or a kink: the linear model is only a bound)"
            } else {
                ""
            };
            let run_value = summary.and_then(|sm| {
                enginedyn_pipeline::Summary::key(st.output.key())?
                    .number(sm)
                    .filter(|x| x.is_finite())
            });
            let nominal = match run_value {
                Some(v) => v,
                None if st.zero => 0.0,
                None => st.nominal,
            };
            vec![
                esc(st.output.key()),
                num(nominal),
                num(st.worst_case),
                num(st.rss),
                esc(unit(st.output)),
                format!("{}{caveat}", esc(&top.join(", "))),
            ]
        })
        .collect();
    o.push_str(&crate::html_table(
        &[
            "result",
            "nominal",
            "worst case ±",
            "RSS σ",
            "unit",
            "largest contributions (share of variance)",
        ],
        &rows,
        &[false, true, true, true, false, false],
    ));
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tolerance outputs named as summary keys are summary keys: the
    /// table's "run value" column looks them up by name, and a key
    /// renamed in one place only would fall back to the study's nominal
    /// without a word. The others are the study's own figures.
    #[test]
    fn outputs_named_as_summary_keys_are_summary_keys() {
        let own = [
            "compression_ratio",
            "clearance_volume_m3",
            "free_force_1_n",
            "free_force_2_n",
            "free_moment_1_nm",
            "free_moment_2_nm",
            "torque_order_0_5_nm",
            "torque_order_1_nm",
        ];
        for o in Output::ALL {
            let in_summary = enginedyn_pipeline::Summary::key(o.key()).is_some();
            assert_eq!(in_summary, !own.contains(&o.key()), "{}", o.key());
        }
    }
}
