//! The torsion study's tables (`enginedyn torsion`, INTERFACE.md
//! "Torsion"): `modes.csv`, `torsion.csv`, `torsion.json`, the printed
//! tables, `chain.json`, and the section `run --out` adds to `report.html`;
//! the charts beside them are `torsion.rs`'s.

use crate::{Extra, ReportError};
use enginedyn_numerics::format::{csv, fixed, human};
use enginedyn_pipeline::torsion::Study;
use serde_json::{Value, json};

/// What `torsion --out DIR` writes (`chain.json` too with `--chain`).
pub const TORSION_FILES: [&str; 5] = [
    "modes.csv",
    "torsion.csv",
    "torsion.json",
    "campbell.svg",
    "torsion.svg",
];

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

/// `modes.csv`: each elastic mode's frequency and shape (normalised to the
/// free end), one column per mass.
pub fn modes_csv(study: &Study) -> String {
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

/// `torsion.csv`: per speed, the free-end amplitude, each section's torque
/// and stress, the largest section, and each order's amplitude.
pub fn torsion_csv(study: &Study) -> String {
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

/// `torsion.json` (and `torsion --json`): the natural frequencies, the
/// resonances, the maxima, the chain, the models and the `notes`.
pub fn torsion_json(
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

/// The torsion section of `run`'s `report.html` for an engine file with
/// `[torsion]`: the modes and the worst resonances as tables, the `notes`,
/// and the Campbell and response charts, over the speeds `rpms`.
pub fn torsion_extra(
    name: &str,
    study: &Study,
    rpms: &[f64],
    notes: &[String],
) -> Result<Extra, ReportError> {
    let esc = crate::esc;
    let modes = mode_rows(study);
    let resonances = worst_resonances(study, 8);
    let mut body = format!(
        "<p>The crankshaft as a chain of inertias on torsional springs from <code>[torsion]</code>, excited by this run's pressure and inertia torques, {} to {} rpm (<code>enginedyn torsion</code> writes modes.csv, torsion.csv and torsion.json).</p>\n",
        fixed(rpms.first().copied().unwrap_or(f64::NAN), 0),
        fixed(rpms.last().copied().unwrap_or(f64::NAN), 0)
    );
    let heads = mode_heads(study);
    let heads: Vec<&str> = heads.iter().map(String::as_str).collect();
    let mut numeric = vec![true; heads.len()];
    numeric[0] = false;
    body.push_str(
        "<p>Natural frequencies and mode shapes: the relative amplitude of each mass, the free end = 1.</p>\n",
    );
    body.push_str(&crate::html_table(&heads, &modes, &numeric));
    body.push_str(
        "<p>The worst resonances: where an order meets a natural frequency (the crossing), and the peak of that order's free-end amplitude near it, which the damping moves off the crossing; the largest peak first.</p>\n",
    );
    body.push_str(&crate::html_table(
        &RESONANCE_HEADS,
        &resonances,
        &[false, true, true, true, true],
    ));
    if !notes.is_empty() {
        body.push_str("<ul>");
        for n in notes {
            body.push_str(&format!("<li>{}</li>", esc(n)));
        }
        body.push_str("</ul>\n");
    }
    let charts = crate::torsion_charts(name, study)?;
    Ok(Extra {
        sections: vec![("Torsional vibration".to_string(), body)],
        charts,
    })
}

/// What `torsion --chain` writes (`chain.json`, for
/// benches/torsion_compare.py): the chain and a few forced responses.
#[derive(Debug, Clone, Default)]
pub struct ChainDump {
    /// Each mass's inertia (kg m²).
    pub inertia: Vec<f64>,
    /// Each spring's stiffness (N m/rad).
    pub stiffness: Vec<f64>,
    /// Each spring's damping (N m s/rad).
    pub spring_damping: Vec<f64>,
    /// The modal damping ratio.
    pub damping_ratio: f64,
    /// The masses' names.
    pub names: Vec<String>,
    /// The elastic modes' frequencies (Hz).
    pub natural_frequencies_hz: Vec<f64>,
    /// Forced responses at a few speeds and orders.
    pub checks: Vec<ChainCheck>,
}

/// One forced response of [`ChainDump`].
#[derive(Debug, Clone)]
pub struct ChainCheck {
    /// The speed (rpm).
    pub rpm: f64,
    /// The engine order.
    pub order: f64,
    /// The excitation's angular frequency (rad/s).
    pub omega_rad_s: f64,
    /// The complex torque on each mass (N m).
    pub torque: Vec<enginedyn_torsion::Complex64>,
    /// The complex response of each mass (rad).
    pub response: Vec<enginedyn_torsion::Complex64>,
}

/// `chain.json`: [`ChainDump`] as pretty JSON (complex numbers as `[re, im]`).
pub fn chain_json(d: &ChainDump) -> Result<String, serde_json::Error> {
    let pairs = |v: &[enginedyn_torsion::Complex64]| {
        v.iter().map(|c| json!([c.re, c.im])).collect::<Vec<_>>()
    };
    let checks: Vec<Value> = d
        .checks
        .iter()
        .map(|c| {
            json!({
                "rpm": c.rpm, "order": c.order, "omega_rad_s": c.omega_rad_s,
                "torque": pairs(&c.torque), "response": pairs(&c.response),
            })
        })
        .collect();
    let doc = json!({
        "inertia_kg_m2": d.inertia,
        "stiffness_nm_rad": d.stiffness,
        "spring_damping_nm_s_rad": d.spring_damping,
        "damping_ratio": d.damping_ratio,
        "names": d.names,
        "natural_frequencies_hz": d.natural_frequencies_hz,
        "checks": checks,
    });
    serde_json::to_string_pretty(&doc)
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

/// The printed tables: the modes and the worst resonances.
pub fn torsion_table(study: &Study) -> String {
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
