//! `enginedyn torsion`: the crankshaft's torsional vibration (INTERFACE.md,
//! "Torsion"). The excitation comes from the pipeline once (gas and inertia
//! parts of each cylinder's torque by order); the chain from `[torsion]`.

use crate::Failure;
use crate::args::TorsionArgs;
use enginedyn_numerics::format::{csv, fixed, human};
use enginedyn_pipeline::torsion::{Study, TorsionStudyError, Train};
use serde_json::{Value, json};

/// Speeds without `--rpm`: 20 % to 120 % of the operating speed.
const DEFAULT_SPEEDS: usize = 50;

fn study_failure(file: &str, e: TorsionStudyError) -> Failure {
    match e {
        TorsionStudyError::Engine(e) => Failure::usage(format!("{file}: {e}")),
        TorsionStudyError::Chain(e) => Failure::usage(format!("{file}: [torsion]: {e}")),
        TorsionStudyError::Pipeline(e) => Failure::data(e.to_string()),
    }
}

/// Everything a torsion study needs, built from the command's inputs.
pub struct Prepared {
    /// The chain with its defaults noted.
    pub train: Train,
    /// The excitation by order.
    pub excitation: enginedyn_pipeline::torsion::Excitation,
    /// Notes from reading the inputs.
    pub notes: Vec<String>,
}

/// The chain and excitation of `engine` from its `[torsion]` section and
/// a pressure trace already on the grid; `analysis` is the run at the
/// operating speed (its sized flywheel is the default flywheel).
pub fn prepare(
    file: &str,
    engine: &enginedyn_engine::Engine,
    spec: &enginedyn_engine::torsion::TorsionSpec,
    resampled: &enginedyn_ingest::Resampled,
    analysis: &enginedyn_pipeline::Analysis,
    opts: &enginedyn_pipeline::Options,
) -> Result<Prepared, Failure> {
    let rod_model = opts.rod_model.unwrap_or(engine.rod_model());
    let train = enginedyn_pipeline::torsion::crank_train(
        engine,
        spec,
        rod_model,
        analysis.flywheel.as_ref().map(|f| f.inertia),
    )
    .map_err(|e| study_failure(file, e))?;
    let excitation = enginedyn_pipeline::torsion::excitation(
        engine,
        resampled,
        opts,
        enginedyn_pipeline::MAX_ORDER,
    )
    .map_err(|e| Failure::data(e.to_string()))?;
    Ok(Prepared {
        train,
        excitation,
        notes: Vec::new(),
    })
}

/// What `torsion --out DIR` writes (`chain.json` too with `--chain`).
const FILES: [&str; 5] = [
    "modes.csv",
    "torsion.csv",
    "torsion.json",
    "campbell.svg",
    "torsion.svg",
];

pub fn run(a: &TorsionArgs) -> Result<(), Failure> {
    let loaded = enginedyn_session::Loaded::from_file(&a.engine)?;
    let engine = &loaded.engine;
    // Something in the way of an output is refused before the study runs.
    let mut names = FILES.to_vec();
    if a.chain {
        names.push("chain.json");
    }
    let out = crate::open_out(a.out.as_deref(), &names, "torsion")?;
    let file = a.engine.display().to_string();
    let spec = enginedyn_engine::file::read_torsion(&a.engine)
        .map_err(|e| Failure::usage(format!("{file}: {e}")))?
        .ok_or_else(|| {
            Failure::usage(format!(
                "{file}: no [torsion] section: give at least `journal_stiffness_nm_rad` (or `journal_diameter_mm` and `journal_length_mm`) under [torsion]"
            ))
        })?;
    let step = a.method.step();
    enginedyn_session::diagram::check_step(engine, step)?;
    let opts = a.method.options();
    let (parse, grid) = enginedyn_session::diagram::diagram_options(
        engine,
        &a.diagram_args.reader(None),
        step,
        opts.interp,
    )?;
    let path = enginedyn_session::diagram::diagram_path(a.diagram.as_deref(), &loaded)?;
    let resampled = enginedyn_session::diagram::load_diagram(
        enginedyn_session::Input::File(&path),
        &parse,
        &grid,
    )?;
    let speed = enginedyn_session::speed::resolve_rpm(None, resampled.rpm, engine)?;
    let rpms = match &a.rpm {
        Some(spec) => enginedyn_session::speed::speeds(spec)?,
        None => default_speeds(speed.rpm),
    };
    let analysis = enginedyn_pipeline::analyse(engine, &resampled, speed.rpm, &opts)
        .map_err(|e| Failure::data(e.to_string()))?;
    let prepared = prepare(&file, engine, &spec, &resampled, &analysis, &opts)?;
    let study = enginedyn_pipeline::torsion::study(&prepared.train, &prepared.excitation, &rpms)
        .map_err(|e| study_failure(&file, e))?;
    // Implausible values first, as warnings (they may mean a wrong
    // result), then what was assumed.
    let warnings = &prepared.train.warnings;
    crate::say_all(warnings);
    let mut notes = prepared.train.notes.clone();
    notes.extend(prepared.notes.iter().cloned());
    if let Some(n) = &speed.note {
        notes.push(format!("flywheel sized and diagram taken at {n}"));
    }
    notes.extend(study.notes.iter().cloned());
    crate::say_all(&notes);
    let notes: Vec<String> = warnings.iter().chain(&notes).cloned().collect();
    let doc = torsion_json(engine, &study, &opts, &notes);
    let text = serde_json::to_string_pretty(&doc).map_err(|e| Failure::data(e.to_string()))?;
    if let Some(dir) = &out {
        let mut files = vec![
            ("modes.csv".to_string(), modes_csv(&study).into_bytes()),
            ("torsion.csv".to_string(), torsion_csv(&study).into_bytes()),
            ("torsion.json".to_string(), format!("{text}\n").into_bytes()),
        ];
        let charts = enginedyn_report::torsion_charts(engine.name(), &study)
            .map_err(|e| Failure::data(e.to_string()))?;
        files.extend(charts.into_iter().map(|(f, svg)| (f, svg.into_bytes())));
        if a.chain {
            let chain = chain_json(&prepared, &study, &rpms)?;
            files.push(("chain.json".to_string(), chain.into_bytes()));
        }
        crate::write_out_to(dir, &files, a.json)?;
    }
    if a.json {
        crate::emit(&format!("{text}\n"));
    } else if a.out.is_none() {
        crate::emit(&table(&study));
    }
    Ok(())
}

fn column(name: &str) -> String {
    name.replace(' ', "_")
}

/// The elastic modes (1..), each normalised to the free end (to its
/// largest component when the free end is a node).
fn normalised(study: &Study, m: usize) -> Vec<f64> {
    let v = study.modes.shape(m);
    let fe = v[study.layout.free_end];
    let big = v.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let by = if fe.abs() > 1e-6 * big { fe } else { big };
    v.iter().map(|x| x / by).collect()
}

fn modes_csv(study: &Study) -> String {
    let mut o = String::from("mode,frequency_hz");
    for n in &study.layout.names {
        o.push(',');
        o.push_str(&enginedyn_numerics::format::csv_text(&column(n)));
    }
    o.push('\n');
    for m in 1..study.modes.len() {
        o.push_str(&format!("{m},{}", csv(study.modes.frequency_hz(m))));
        for x in normalised(study, m) {
            o.push(',');
            o.push_str(&csv(x));
        }
        o.push('\n');
    }
    o
}

fn order_name(k: f64) -> String {
    human(k)
}

/// The largest section at a row: (1-based section, torque).
fn largest(torques: &[f64]) -> (usize, f64) {
    torques.iter().enumerate().fold(
        (0, 0.0_f64),
        |(bi, bv), (i, &v)| if v > bv { (i + 1, v) } else { (bi, bv) },
    )
}

fn torsion_csv(study: &Study) -> String {
    let mut o = String::from("rpm,free_end_amplitude_deg");
    for s in 1..=study.layout.sections.len() {
        o.push_str(&format!(",section_{s}_torque_nm,section_{s}_stress_mpa"));
    }
    o.push_str(",max_section,max_section_torque_nm");
    for &k in &study.orders {
        o.push_str(&format!(",order_{}_deg", order_name(k)));
    }
    o.push('\n');
    for r in &study.rows {
        o.push_str(&csv(r.rpm));
        o.push(',');
        o.push_str(&csv(r.free_end_deg));
        for (t, s) in r.section_torque.iter().zip(&r.section_stress) {
            o.push(',');
            o.push_str(&csv(*t));
            o.push(',');
            if let Some(s) = s {
                o.push_str(&csv(s / 1e6));
            }
        }
        let (sec, val) = largest(&r.section_torque);
        o.push_str(&format!(",{sec},{}", csv(val)));
        for x in &r.order_deg {
            o.push(',');
            o.push_str(&csv(*x));
        }
        o.push('\n');
    }
    o
}

fn torsion_json(
    engine: &enginedyn_engine::Engine,
    study: &Study,
    opts: &enginedyn_pipeline::Options,
    notes: &[String],
) -> Value {
    let freqs: Vec<f64> = (1..study.modes.len())
        .map(|m| study.modes.frequency_hz(m))
        .collect();
    let resonance = |r: &enginedyn_pipeline::torsion::Resonance| {
        json!({
            "order": r.order,
            "mode": r.mode,
            "crossing_rpm": r.crossing_rpm,
            "rpm": r.rpm,
            "amplitude_deg": r.amplitude_deg,
            "crossing_amplitude_deg": r.crossing_amplitude_deg,
            "edge": r.edge.map(|e| e.name()),
        })
    };
    let fe = study.max_free_end.as_ref();
    let tq = study.max_section_torque.as_ref();
    json!({
        "engine": engine.name(),
        "natural_frequencies_hz": freqs,
        "resonances": study.resonances.iter().map(resonance).collect::<Vec<_>>(),
        "max_free_end_amplitude_deg": fe.map(|m| m.value),
        "max_free_end_amplitude_rpm": fe.map(|m| m.rpm),
        "max_section_torque_nm": tq.map(|m| m.value),
        "max_section_torque_rpm": tq.map(|m| m.rpm),
        "max_section_torque_section": tq.and_then(|m| m.section).map(|s| s + 1),
        "masses": study.layout.names.iter().zip(&study.inertia).map(|(n, j)| json!({"name": n, "inertia_kg_m2": j})).collect::<Vec<_>>(),
        "sections": study.layout.sections.iter().enumerate().map(|(i, s)| json!({
            "section": i + 1,
            "between": s.name,
            "stiffness_nm_rad": study.stiffness[s.spring],
        })).collect::<Vec<_>>(),
        "models": {
            "kinematics": opts.kinematics.name(),
            "rod_model": opts.rod_model.unwrap_or(engine.rod_model()).name(),
            "step_deg": opts.step_deg,
            "highest_order": study.orders.last(),
            "damping": "modal ratio on every mode plus the damper's viscous coefficient",
            "free_end_amplitude": "half peak-to-peak of all orders summed in time, relative to the chain's rigid rotation",
            "resonance_peak": "the order's free-end amplitude climbed to from the crossing over the speeds and refined between them by Brent's method to 0.01 rpm, within the speed range and the mode's band (to the geometric means of its natural frequency and its neighbours'); edge names the end where it still rises (no peak)",
            "maxima": "the largest on the speeds and at the resonances' peaks, refined between them by Brent's method to 0.01 rpm",
        },
        "notes": notes,
    })
}

/// The chain and a few forced responses for benches/torsion_compare.py.
fn chain_json(prepared: &Prepared, study: &Study, rpms: &[f64]) -> Result<String, Failure> {
    let (chain, layout) = prepared
        .train
        .train
        .chain()
        .map_err(|e| Failure::usage(e.to_string()))?;
    let solver =
        enginedyn_torsion::Solver::new(&chain).map_err(|e| Failure::usage(e.to_string()))?;
    let ex = &prepared.excitation;
    let mut checks = Vec::new();
    let picks = [
        0,
        rpms.len() / 3,
        2 * rpms.len() / 3,
        rpms.len().saturating_sub(1),
    ];
    for &i in &picks {
        let Some(&rpm) = rpms.get(i) else { continue };
        let omega = rpm * std::f64::consts::PI / 30.0;
        for o in (0..ex.orders.len()).step_by(5) {
            let mut tt = vec![enginedyn_torsion::Complex64::new(0.0, 0.0); layout.throws.len()];
            ex.at(o, omega, &mut tt);
            let mut torque = vec![enginedyn_torsion::Complex64::new(0.0, 0.0); chain.len()];
            for (t, &m) in layout.throws.iter().enumerate() {
                torque[m] = tt[t];
            }
            let w = ex.orders[o] * omega;
            let theta = solver
                .respond(w, &torque)
                .map_err(|e| Failure::usage(e.to_string()))?;
            let pairs = |v: &[enginedyn_torsion::Complex64]| {
                v.iter().map(|c| json!([c.re, c.im])).collect::<Vec<_>>()
            };
            checks.push(json!({
                "rpm": rpm, "order": ex.orders[o], "omega_rad_s": w,
                "torque": pairs(&torque), "response": pairs(&theta),
            }));
        }
    }
    let doc = json!({
        "inertia_kg_m2": chain.inertia(),
        "stiffness_nm_rad": chain.stiffness(),
        "spring_damping_nm_s_rad": chain.spring_damping(),
        "damping_ratio": chain.damping_ratio(),
        "names": layout.names,
        "natural_frequencies_hz": (1..study.modes.len()).map(|m| study.modes.frequency_hz(m)).collect::<Vec<_>>(),
        "checks": checks,
    });
    serde_json::to_string_pretty(&doc).map_err(|e| Failure::data(e.to_string()))
}

/// The default speeds: 20 % to 120 % of `rpm` in [`DEFAULT_SPEEDS`] steps.
fn default_speeds(rpm: f64) -> Vec<f64> {
    (0..DEFAULT_SPEEDS)
        .map(|k| rpm * (0.2 + 1.0 * k as f64 / (DEFAULT_SPEEDS - 1) as f64))
        .collect()
}

/// The torsion section of `run`'s report.html when the engine file has a
/// `[torsion]` section: the modes and the worst resonances as tables, the
/// Campbell and response charts, over the default speeds around the run's,
/// excited by the run's pressure (cylinder 1's trace for every cylinder).
pub fn report_extra(
    engine: &enginedyn_engine::Engine,
    engine_text: &str,
    analysis: &enginedyn_pipeline::Analysis,
    opts: enginedyn_pipeline::Options,
) -> Result<Option<enginedyn_report::Extra>, Failure> {
    let file = engine.name().to_string();
    let Some(spec) = enginedyn_engine::file::parse_torsion(engine_text)
        .map_err(|e| Failure::from(e).in_file(&file))?
    else {
        return Ok(None);
    };
    if analysis.pressure.is_empty() {
        return Ok(None);
    }
    let trace = enginedyn_ingest::Resampled::from_grid(opts.step_deg, analysis.pressure.clone());
    let prepared = prepare(&file, engine, &spec, &trace, analysis, &opts)?;
    let rpms = default_speeds(analysis.summary.rpm);
    let study = enginedyn_pipeline::torsion::study(&prepared.train, &prepared.excitation, &rpms)
        .map_err(|e| study_failure(&file, e))?;
    let esc = enginedyn_report::esc;
    let modes = mode_rows(&study);
    let resonances = worst_resonances(&study, 8);
    let mut notes = prepared.train.warnings.clone();
    notes.extend(prepared.train.notes.iter().cloned());
    notes.extend(study.notes.iter().cloned());
    let mut body = format!(
        "<p>The crankshaft as a chain of inertias on torsional springs from <code>[torsion]</code>, excited by this run's pressure and inertia torques, {} to {} rpm (<code>enginedyn torsion</code> writes modes.csv, torsion.csv and torsion.json).</p>\n",
        fixed(rpms[0], 0),
        fixed(rpms[rpms.len() - 1], 0)
    );
    let heads = mode_heads(&study);
    let heads: Vec<&str> = heads.iter().map(String::as_str).collect();
    let mut numeric = vec![true; heads.len()];
    numeric[0] = false;
    body.push_str(
        "<p>Natural frequencies and mode shapes: the relative amplitude of each mass, the free end = 1.</p>\n",
    );
    body.push_str(&enginedyn_report::html_table(&heads, &modes, &numeric));
    body.push_str(
        "<p>The worst resonances: where an order meets a natural frequency (the crossing), and the peak of that order's free-end amplitude near it, which the damping moves off the crossing; the largest peak first.</p>\n",
    );
    body.push_str(&enginedyn_report::html_table(
        &RESONANCE_HEADS,
        &resonances,
        &[false, true, true, true, true],
    ));
    if !notes.is_empty() {
        body.push_str("<ul>");
        for n in &notes {
            body.push_str(&format!("<li>{}</li>", esc(n)));
        }
        body.push_str("</ul>\n");
    }
    let charts = enginedyn_report::torsion_charts(engine.name(), &study)
        .map_err(|e| Failure::data(e.to_string()))?;
    Ok(Some(enginedyn_report::Extra {
        sections: vec![("Torsional vibration".to_string(), body)],
        charts,
    }))
}

/// The worst resonances' rows, the largest peak first: order, mode, the
/// crossing and the peak speed (rpm; "(range end)" or "(mode band edge)"
/// where the amplitude still rises there: no peak), the peak's free-end
/// amplitude (deg).
fn worst_resonances(study: &Study, count: usize) -> Vec<Vec<String>> {
    study
        .resonances
        .iter()
        .take(count)
        .map(|r| {
            let end = r.edge.map_or(String::new(), |e| format!(" ({})", e.name()));
            vec![
                order_name(r.order),
                r.mode.to_string(),
                fixed(r.crossing_rpm, 0),
                format!("{}{end}", fixed(r.rpm, 1)),
                enginedyn_numerics::format::sig(r.amplitude_deg, 3),
            ]
        })
        .collect()
}

/// The worst resonances' column heads.
const RESONANCE_HEADS: [&str; 5] = [
    "order",
    "mode",
    "crossing (rpm)",
    "peak (rpm)",
    "free-end amplitude at the peak (deg)",
];

/// The mode table's rows: mode, frequency, then the relative amplitude of
/// each mass (normalised to the free end), under [`mode_heads`].
fn mode_rows(study: &Study) -> Vec<Vec<String>> {
    (1..study.modes.len())
        .map(|m| {
            let mut row = vec![m.to_string(), fixed(study.modes.frequency_hz(m), 1)];
            row.extend(normalised(study, m).iter().map(|x| fixed(*x, 2)));
            row
        })
        .collect()
}

/// The mode table's column heads: mode, frequency, and each mass by name
/// (damper ring, front, throw 1 … throw n, flywheel, load).
fn mode_heads(study: &Study) -> Vec<String> {
    let mut heads = vec!["mode".to_string(), "frequency (Hz)".to_string()];
    heads.extend(study.layout.names.iter().cloned());
    heads
}

/// Rows under heads, each column right-aligned to its widest cell, two
/// spaces apart.
fn text_table(heads: &[String], rows: &[Vec<String>]) -> String {
    let width = |c: usize| {
        rows.iter()
            .filter_map(|r| r.get(c))
            .chain(heads.get(c))
            .map(|x| x.chars().count())
            .max()
            .unwrap_or(0)
    };
    let widths: Vec<usize> = (0..heads.len()).map(width).collect();
    let line = |cells: &[String]| {
        let mut o = cells
            .iter()
            .zip(&widths)
            .map(|(c, &w)| format!("{c:>w$}"))
            .collect::<Vec<_>>()
            .join("  ");
        o.push('\n');
        o
    };
    let mut o = line(heads);
    for r in rows {
        o.push_str(&line(r));
    }
    o
}

fn table(study: &Study) -> String {
    let mut o = String::from(
        "natural frequencies and mode shapes (relative amplitude of each mass, the free end = 1)\n",
    );
    o.push_str(&text_table(&mode_heads(study), &mode_rows(study)));
    o.push_str(
        "\nworst resonances in the speed range, by the peak of the order's free-end amplitude near the crossing\n",
    );
    let heads: Vec<String> = RESONANCE_HEADS.iter().map(|h| h.to_string()).collect();
    let worst = worst_resonances(study, 8);
    if worst.is_empty() {
        o.push_str("(none)\n");
    } else {
        o.push_str(&text_table(&heads, &worst));
    }
    o
}
