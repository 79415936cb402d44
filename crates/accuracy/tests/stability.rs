//! The stability map: where each method fails or degrades, and that the
//! tool then warns or refuses instead of returning garbage. One test per
//! condition; the map is summarised in the crate docs (and README.md).

use enginedyn_engine::Engine;
use enginedyn_ingest::{Diagram, GridOptions, Interp, Quantity, Resampled, Trace};
use enginedyn_kinematics::Model;
use enginedyn_pipeline::{Analysis, Options, analyse};
use std::path::PathBuf;

fn vaz_text() -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/vaz2108.toml");
    std::fs::read_to_string(p).unwrap()
}

fn engine(text: &str) -> Result<Engine, String> {
    enginedyn_engine::file::parse(text, "test").map_err(|e| e.to_string())
}

/// Cylinder pressure of the generated petrol cycle on a grid of `step`.
fn generated(e: &Engine, step: f64) -> Resampled {
    let (sol, _) = enginedyn_accuracy::generated(e).unwrap();
    let n = (720.0 / step).round() as usize;
    Resampled::from_grid(
        step,
        (0..n).map(|k| sol.pressure(k as f64 * step)).collect(),
    )
}

fn run(e: &Engine, p: &Resampled, o: Options) -> Result<Analysis, String> {
    analyse(e, p, 4900.0, &o).map_err(|e| e.to_string())
}

/// The default methods on the generated diagram at 0.5°.
fn run_coarse(e: &Engine) -> Analysis {
    let o = Options {
        step_deg: 0.5,
        ..Options::default()
    };
    run(e, &generated(e, 0.5), o).unwrap()
}

fn has_note(a: &Analysis, part: &str) -> bool {
    a.summary.notes.iter().any(|n| n.contains(part))
}

#[test]
fn lambda_near_its_limit() {
    // At the limit the crank cannot turn: refused, naming the key and bound.
    let err = engine(&vaz_text().replace("lambda = 0.26", "lambda = 1.0")).unwrap_err();
    assert!(err.contains("lambda"), "{err}");
    // Close to it the series degrade: series2 misses the acceleration by
    // several percent, and says so; exact stays quiet.
    let e = engine(
        &vaz_text()
            .replace("lambda = 0.26", "lambda = 0.45")
            .replace(
                "rod_cg_from_small_end_mm = 99.0",
                "rod_cg_from_small_end_mm = 57.0",
            ),
    )
    .unwrap();
    let p = generated(&e, 0.5);
    let o = Options {
        step_deg: 0.5,
        ..Options::default()
    };
    let s2 = run(
        &e,
        &p,
        Options {
            kinematics: Model::Series2,
            ..o
        },
    )
    .unwrap();
    assert!(
        has_note(&s2, "series2 kinematics misses"),
        "{:?}",
        s2.summary.notes
    );
    let ex = run(&e, &p, o).unwrap();
    assert!(!has_note(&ex, "kinematics misses"));
    let err = e.mechanism().series_error(Model::Series2).unwrap();
    assert!(err > 0.01, "{err}");
    // At the usual lambda the same series is within 1 %: no note.
    let usual = engine(&vaz_text()).unwrap();
    assert!(usual.mechanism().series_error(Model::Series2).unwrap() < 0.01);
}

#[test]
fn large_pin_offset() {
    let text = vaz_text().replace("pin_offset_mm = 0.0", "pin_offset_mm = 20.0");
    let e = engine(&text).unwrap();
    let p = generated(&e, 0.5);
    let o = Options {
        step_deg: 0.5,
        ..Options::default()
    };
    // Higher series are not defined with an offset: refused.
    for m in [Model::Series4, Model::Series6] {
        let err = run(&e, &p, Options { kinematics: m, ..o }).unwrap_err();
        assert!(err.contains("offset"), "{err}");
    }
    // Series2 with a large offset is allowed but flagged when it degrades.
    let k = e.mechanism().series_error(Model::Series2).unwrap();
    let a = run(
        &e,
        &p,
        Options {
            kinematics: Model::Series2,
            ..o
        },
    )
    .unwrap();
    assert_eq!(has_note(&a, "series2 kinematics misses"), k > 0.01);
    // Too large an offset for the crank to turn: refused.
    assert!(engine(&vaz_text().replace("pin_offset_mm = 0.0", "pin_offset_mm = 120.0")).is_err());
}

/// Samples of the generated diagram every `spacing` degrees.
fn samples(e: &Engine, spacing: f64) -> Diagram {
    let (sol, _) = enginedyn_accuracy::generated(e).unwrap();
    let n = (720.0 / spacing).round() as usize;
    Diagram {
        quantity: Quantity::Pressure,
        rpm: None,
        traces: vec![Trace {
            cycle: 0,
            cylinder: 0,
            angle_deg: (0..n).map(|k| k as f64 * spacing).collect(),
            values: (0..n).map(|k| sol.pressure(k as f64 * spacing)).collect(),
            rpm: None,
        }],
        cycle_deg: 720.0,
        pv: false,
        cycles_skipped: 0,
        skipped: Vec::new(),
        notes: Vec::new(),
        peak_rule: None,
    }
}

#[test]
fn coarse_data_as_in_hand_methods() {
    let e = engine(&vaz_text()).unwrap();
    let truth = run(&e, &generated(&e, 0.1), Options::default()).unwrap();
    // The gas force peak: what coarse sampling misses first.
    let rel = |a: &Analysis| {
        (a.summary.gas_force_max_n.unwrap() - truth.summary.gas_force_max_n.unwrap()).abs()
            / truth.summary.gas_force_max_n.unwrap()
    };
    // 10° steps: a note says the peaks are guesses; the spline still beats
    // linear interpolation, and both stay finite.
    let coarse = samples(&e, 10.0);
    let mut errs = Vec::new();
    for interp in [Interp::Linear, Interp::Spline] {
        let r = enginedyn_ingest::resample_with(&coarse, &GridOptions::new(0.1, interp)).unwrap();
        assert!(
            r.notes.iter().any(|n| n.contains("a point every 10°")),
            "{:?}",
            r.notes
        );
        let a = run(
            &e,
            &r,
            Options {
                interp,
                ..Options::default()
            },
        )
        .unwrap();
        assert!(a.summary.mean_torque_nm.unwrap().is_finite());
        errs.push(rel(&a));
    }
    assert!(errs[0] > 0.01, "linear from 10° data: {:.3e}", errs[0]);
    assert!(errs[1] < errs[0], "{errs:?}");
    // 1° data: no such note.
    let fine = samples(&e, 1.0);
    let r = enginedyn_ingest::resample_with(&fine, &GridOptions::new(0.1, Interp::Auto)).unwrap();
    assert!(!r.notes.iter().any(|n| n.contains("a point every")));
}

#[test]
fn noisy_data_and_spline_overshoot_at_the_peak() {
    let e = engine(&vaz_text()).unwrap();
    let mut d = samples(&e, 1.0);
    // A sharp knock-like spike at 10° after TDC: the spline would ring.
    let t = &mut d.traces[0];
    t.values[10] *= 1.6;
    // Measurement noise of ±0.3 bar.
    let mut x = 12345u64;
    for v in t.values.iter_mut() {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *v += ((x >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.6e5;
    }
    let r = enginedyn_ingest::resample_with(&d, &GridOptions::new(0.1, Interp::Auto)).unwrap();
    assert!(
        r.notes.iter().any(|n| n.contains("overshoots")),
        "{:?}",
        r.notes
    );
    assert_eq!(r.interp.name(), "pchip");
    // Pchip never leaves the data's range: the peak is the spike itself.
    let peak = r.pressure.iter().fold(0.0_f64, |a, &b| a.max(b));
    let data_peak = d.traces[0].values.iter().fold(0.0_f64, |a, &b| a.max(b));
    assert!(peak <= data_peak * (1.0 + 1e-12));
    // Forced spline: it rings around the spike, leaving the range of the
    // two samples it lies between by more than 0.5 % of the peak.
    let s = enginedyn_ingest::resample_with(&d, &GridOptions::new(0.1, Interp::Spline)).unwrap();
    let v = &d.traces[0].values;
    let ring = s
        .pressure
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            let i = k / 10;
            let (a, b) = (v[i], v[(i + 1) % v.len()]);
            (p - a.max(b)).max(a.min(b) - p)
        })
        .fold(0.0_f64, f64::max);
    assert!(ring > 0.005 * data_peak, "{ring}");
}

#[test]
fn very_small_speed_fluctuation() {
    let text = vaz_text().replace("speed_fluctuation = 0.01", "speed_fluctuation = 0.00001");
    let e = engine(&text).unwrap();
    let a = run_coarse(&e);
    let s = &a.summary;
    // The numbers stay exact (the speed trace gives the delta asked for) …
    let achieved = s.speed_fluctuation_achieved.unwrap();
    assert!((achieved - 1e-5).abs() < 1e-9, "{achieved}");
    // … and the tool says the flywheel is impractical.
    assert!(has_note(&a, "wider"), "{:?}", s.notes);
}

#[test]
fn single_cylinder() {
    let text = vaz_text()
        .replace("cylinders = 4", "cylinders = 1")
        .replace("firing_order = [1, 3, 4, 2]", "");
    let e = engine(&text).unwrap();
    let a = run_coarse(&e);
    let s = &a.summary;
    // Large but finite and consistent: psi of a single four-stroke is several.
    assert!(s.excess_work_coefficient.unwrap() > 1.0);
    assert!(s.energy_balance_error.unwrap() < 1e-9);
    assert!(s.required_inertia_kg_m2.unwrap().is_finite());
}

/// A motored-like trace: polytropic compression and expansion, the
/// expansion `factor` times the compression pressure at equal volume.
fn polytropic(e: &Engine, factor: f64) -> Resampled {
    let cyl = e.cylinder();
    let v0 = cyl.volume(std::f64::consts::PI);
    let n = 1440;
    Resampled::from_grid(
        0.5,
        (0..n)
            .map(|k| {
                let deg = k as f64 * 0.5;
                let p = 0.9e5 * (v0 / cyl.volume(deg.to_radians())).powf(1.3);
                // Expansion stroke 0..180°; smooth blend near TDC and BDC.
                let w = (deg.to_radians()).sin().max(0.0).sqrt();
                let f = if deg < 180.0 {
                    1.0 + (factor - 1.0) * w
                } else {
                    1.0
                };
                p * f
            })
            .collect(),
    )
}

#[test]
fn near_zero_and_negative_mean_torque() {
    let e = engine(&vaz_text()).unwrap();
    let o = Options {
        step_deg: 0.5,
        ..Options::default()
    };
    // Motoring: negative mean torque; no flywheel, a note, no failure.
    let motored = run(&e, &polytropic(&e, 0.95), o).unwrap();
    let s = &motored.summary;
    assert!(s.mean_torque_nm.unwrap() < 0.0);
    assert!(s.required_inertia_kg_m2.is_none() && s.flywheel_mass_kg.is_none());
    assert!(!s.notes.is_empty());
    // Barely positive: figures exist, with the warning that they are fragile.
    let idle = run(&e, &polytropic(&e, 1.004), o).unwrap();
    let mean = idle.summary.mean_torque_nm.unwrap();
    assert!(mean > 0.0, "{mean}");
    assert!(
        has_note(&idle, "near idle or motoring (IMEP"),
        "{:?}",
        idle.summary.notes
    );
    assert!(idle.summary.torque_nonuniformity.unwrap() > 20.0);
}
