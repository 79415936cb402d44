//! `enginedyn tolerance` (INTERFACE.md): each tolerance's influence on the
//! key results, their stack-up, and the Monte Carlo check; `--out DIR`
//! writes `tolerance.csv`, `tolerance.json` and `tolerance.svg`.

use crate::Failure;
use crate::args::ToleranceArgs;
use enginedyn_engine::Engine;
use enginedyn_ingest::Quantity;
use enginedyn_report::{TornadoBar, TornadoPanel};
use enginedyn_session::diagram::{check_step, diagram_options, load_diagram};
use enginedyn_session::speed::resolve_rpm;
use enginedyn_session::{Input, Loaded};
use enginedyn_tolerance::{Evaluator, Method, Output, Row, Stack, Study};
use std::fmt::Write as _;

/// Monte Carlo runs on this grid (deg) unless the method step is coarser:
/// every sample is a full pipeline run, and 0.5° keeps 10,000 samples of a
/// four-cylinder engine within seconds.
const MONTE_CARLO_STEP: f64 = 0.5;
/// Contributions shown per result on standard output and per tornado panel.
const SHOWN: usize = 6;

/// Runs `enginedyn tolerance`.
/// What `tolerance --out DIR` writes.
const FILES: [&str; 3] = ["tolerance.csv", "tolerance.json", "tolerance.svg"];

pub fn run(a: &ToleranceArgs) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.input.engine)?;
    let engine = &loaded.engine;
    let file = a.input.engine.display().to_string();
    let text = std::fs::read_to_string(&a.input.engine)
        .map_err(|e| Failure::usage(format!("{file}: cannot read: {e}")))?;
    let tolerances = enginedyn_engine::file::tolerances(&text)
        .map_err(|e| Failure::usage(format!("{file}: {e}")))?;
    if tolerances.is_empty() {
        return Err(Failure::usage(format!(
            "{file}: no [tolerances] section: give the ± deviations to study, e.g.\n\
             [tolerances]\nstroke_mm = 0.02\nrod_length_mm = 0.05\npiston_group_kg = 0.005\n\
             throw_angle_deg = 0.2\ntdc_deg = 0.1"
        )));
    }
    // Something in the way of an output is refused before the study runs
    // (and a file with nothing to study leaves no folder behind).
    let out = crate::open_out(a.out.as_deref(), &FILES, "tolerance")?;
    let (inputs, input_notes) = enginedyn_tolerance::inputs(engine, &tolerances)
        .map_err(|e| Failure::usage(format!("{file}: {e}")))?;
    let step = a.method.step();
    check_step(engine, step)?;
    let opts = a.method.options();
    let diagram = enginedyn_session::diagram::diagram_path(a.input.diagram.as_deref(), &loaded)?;
    let shown = diagram.display().to_string();
    let load = |step: f64| {
        let (parse, grid) = diagram_options(
            engine,
            &a.diagram_args.reader(a.input.rpm),
            step,
            opts.interp,
        )?;
        let r = load_diagram(Input::File(&diagram), &parse, &grid)?;
        if r.quantity != Quantity::Pressure {
            return Err(Failure::data(format!(
                "{shown}: a turning-moment file: the tolerance study needs a pressure diagram"
            )));
        }
        Ok(r)
    };
    let table_diagram = load(step)?;
    let speed = resolve_rpm(a.input.rpm, table_diagram.rpm, engine)?;
    let rpm = speed.rpm;
    let mc_step = step.max(MONTE_CARLO_STEP);
    let mc_diagram = if (mc_step - step).abs() < 1e-12 {
        table_diagram.clone()
    } else {
        load(mc_step)?
    };
    let failure = |e: enginedyn_tolerance::ToleranceError| Failure::usage(format!("{file}: {e}"));
    let table = Evaluator::new(engine, &table_diagram, rpm, opts, &inputs).map_err(failure)?;
    let mc_opts = enginedyn_pipeline::Options {
        step_deg: mc_step,
        ..opts
    };
    let mc = Evaluator::new(engine, &mc_diagram, rpm, mc_opts, &inputs).map_err(failure)?;
    let mut study =
        enginedyn_tolerance::study(&table, &mc, a.samples as usize, a.seed).map_err(failure)?;
    study.notes.splice(0..0, input_notes);
    study.notes.extend(offset_note(engine, &study));
    study.notes.extend(speed.note);
    crate::say_all(&study.notes);
    crate::emit(&text_table(engine, &shown, rpm, &study));
    if let Some(dir) = &out {
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
        let svg = enginedyn_report::tornado_svg(FILES[2], &title, &panels(&study), 4)
            .map_err(|e| Failure::data(e.to_string()))?;
        let [table, doc, chart] = FILES.map(String::from);
        let files = vec![
            (table, csv(&study).into_bytes()),
            (
                doc,
                (serde_json::to_string_pretty(&json(&study)).unwrap_or_default() + "\n")
                    .into_bytes(),
            ),
            (chart, svg.into_bytes()),
        ];
        crate::write_out_to(dir, &files, false)?;
    }
    Ok(())
}

/// A pin-offset tolerance moves TDC: say by how much, since a diagram whose
/// TDC comes from the crank's geometry carries that as a TDC error.
fn offset_note(engine: &Engine, study: &Study) -> Option<String> {
    let input = study
        .inputs
        .iter()
        .find(|i| i.parameter == enginedyn_tolerance::Parameter::PinOffset)?;
    let enginedyn_kinematics::Mechanism::CrankSlider(cs) = engine.mechanism() else {
        return None;
    };
    let shift = (input.tolerance * 1e-3 / (cs.l() + cs.r())).to_degrees();
    Some(format!(
        "pin_offset_mm ± {} moves TDC by ± {shift:.3}° (δe / (L + R)); the diagram is taken on \
         its true firing TDC (PHYSICS.md); if its TDC comes from the crank's geometry instead, \
         add that to tdc_deg",
        input.tolerance
    ))
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
fn text_table(engine: &Engine, diagram: &str, rpm: f64, s: &Study) -> String {
    let mut o = crate::table::heading(engine, "tolerance study, ", rpm, diagram);
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
fn csv(s: &Study) -> String {
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
fn json(s: &Study) -> serde_json::Value {
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
fn panels(s: &Study) -> Vec<TornadoPanel> {
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

/// The tolerance table and tornado chart for `report.html` when the engine
/// file has a `[tolerances]` section: the linear model only (sensitivities
/// by the real pipeline, no Monte Carlo; `enginedyn tolerance` adds it), on
/// the run's pressure trace at 0.5° (every n-th point of the run's grid)
/// with the run's methods. `None` without tolerances or without pressure.
pub fn report_extra(
    engine: &Engine,
    engine_text: &str,
    analysis: &enginedyn_pipeline::Analysis,
    opts: enginedyn_pipeline::Options,
) -> Result<Option<enginedyn_report::Extra>, Failure> {
    if analysis.pressure.is_empty() {
        return Ok(None);
    }
    let file = engine.name().to_string();
    let tolerances = enginedyn_engine::file::tolerances(engine_text)
        .map_err(|e| Failure::usage(format!("{file}: {e}")))?;
    if tolerances.is_empty() {
        return Ok(None);
    }
    let (inputs, _) = enginedyn_tolerance::inputs(engine, &tolerances)
        .map_err(|e| Failure::usage(format!("{file}: {e}")))?;
    // Every n-th point: 0.5° when the run's grid divides it.
    let every = (MONTE_CARLO_STEP / opts.step_deg).round().max(1.0) as usize;
    let step = if ((every as f64) * opts.step_deg - MONTE_CARLO_STEP).abs() < 1e-9 {
        MONTE_CARLO_STEP
    } else {
        opts.step_deg
    };
    let stride = if step == MONTE_CARLO_STEP { every } else { 1 };
    let pressure: Vec<f64> = analysis.pressure.iter().step_by(stride).copied().collect();
    let trace = enginedyn_ingest::Resampled::from_grid(step, pressure);
    let o = enginedyn_pipeline::Options {
        step_deg: step,
        scope: enginedyn_pipeline::Scope::Keys,
        ..opts
    };
    let failure = |e: enginedyn_tolerance::ToleranceError| Failure::usage(format!("{file}: {e}"));
    let ev = Evaluator::new(engine, &trace, analysis.summary.rpm, o, &inputs).map_err(failure)?;
    let study = enginedyn_tolerance::study(&ev, &ev, 0, 1).map_err(failure)?;
    let title = format!(
        "{} — tolerances: each parameter alone at ±t (linear model, {step}° grid)",
        engine.name()
    );
    let svg = enginedyn_report::tornado_svg("tolerance.svg", &title, &panels(&study), 4)
        .map_err(|e| Failure::data(e.to_string()))?;
    Ok(Some(enginedyn_report::Extra {
        sections: vec![(
            "Tolerances".to_string(),
            html_table(&study, Some(&analysis.summary)),
        )],
        charts: vec![("tolerance.svg".to_string(), svg)],
    }))
}

/// The stack-up per result with its three largest contributions, as HTML
/// (report's table and escaping). With the run's `summary`, a result that
/// is a summary key shows the run's own value as nominal (the study runs on
/// a coarser grid; its deviations are what it adds).
fn html_table(s: &Study, summary: Option<&enginedyn_pipeline::Summary>) -> String {
    use enginedyn_report::esc;
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
    o.push_str(&enginedyn_report::html_table(
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
