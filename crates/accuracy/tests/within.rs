//! `--tolerance` on every bundled engine: the chosen setting's results stay
//! within the tolerance of the reference run (exact kinematics, the most
//! exact rod, the periodic spline, 0.01°, trapezoid), and it is cheaper
//! than the default when the tolerance allows; and the accuracy study's
//! errors fall as the methods get finer.

use enginedyn_accuracy::{
    Input, KEYS, Kept, Study, choose, pareto, reference, relative_errors, study,
};
use enginedyn_engine::Engine;
use enginedyn_ingest::{Diagram, GridOptions, Interp, ParseOptions};
use std::path::PathBuf;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data")
}

fn bundled() -> Vec<(Engine, Diagram)> {
    let mut out = Vec::new();
    let mut files: Vec<PathBuf> = std::fs::read_dir(data())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    for f in files {
        let engine = enginedyn_engine::file::read(&f).unwrap();
        let Some(d) = engine.diagram() else { continue };
        let opts = ParseOptions::new(engine.cycle().to_degrees());
        let text = std::fs::read(d).unwrap();
        let diagram = enginedyn_ingest::parse(text.as_slice(), &opts).unwrap();
        out.push((engine, diagram));
    }
    assert!(out.len() >= 6, "the bundled engines with diagrams");
    out
}

fn summary(
    engine: &Engine,
    d: &Diagram,
    rpm: f64,
    o: &enginedyn_pipeline::Options,
) -> enginedyn_pipeline::Summary {
    let g = GridOptions::new(o.step_deg, o.interp);
    let r = enginedyn_ingest::resample_with(d, &g).unwrap();
    enginedyn_pipeline::analyse(engine, &r, rpm, o)
        .unwrap()
        .summary
}

#[test]
fn tolerance_is_kept_against_the_reference() {
    for (engine, d) in bundled() {
        let rpm = d.rpm.or(engine.operating().rpm).unwrap();
        // The kinematic extremes are key results too (Scope::Summary).
        let full = |o: enginedyn_pipeline::Options| enginedyn_pipeline::Options {
            scope: enginedyn_pipeline::Scope::Summary,
            ..o
        };
        let reference = summary(&engine, &d, rpm, &full(reference(&engine)));
        for tol in [3e-2, 1e-2, 3e-3, 1e-3, 1e-4, 1e-5] {
            let resample = |step: f64, interp: Interp| {
                Ok(enginedyn_ingest::resample_with(
                    &d,
                    &GridOptions::new(step, interp),
                )?)
            };
            let c = choose(&engine, rpm, tol, &Kept::default(), &resample).unwrap();
            let got = summary(&engine, &d, rpm, &full(c.options));
            let errors = relative_errors(&got, &reference);
            for (k, e) in KEYS.iter().zip(&errors) {
                if let Some(e) = e {
                    assert!(
                        *e <= tol,
                        "{}: --tolerance {tol}: {k} off by {e:.2e} with {:?}",
                        engine.name(),
                        c.options
                    );
                }
            }
            // The estimate is an upper bound of the true error here.
            let worst = errors.iter().flatten().fold(0.0_f64, |a, &e| a.max(e));
            assert!(
                worst <= c.estimated,
                "{}: --tolerance {tol}: estimated {:.2e}, true {worst:.2e}",
                engine.name(),
                c.estimated
            );
            if tol >= 1e-3 {
                // Cheaper than the default 0.1° grid.
                assert!(
                    c.options.step_deg > 0.1,
                    "{}: {:?}",
                    engine.name(),
                    c.options
                );
            }
        }
    }
}

#[test]
fn unreachable_and_bad_tolerances_are_refused() {
    let (engine, d) = bundled().remove(0);
    let rpm = d.rpm.or(engine.operating().rpm).unwrap();
    let resample = |step: f64, interp: Interp| {
        Ok(enginedyn_ingest::resample_with(
            &d,
            &GridOptions::new(step, interp),
        )?)
    };
    for bad in [0.0, -1.0, 0.9, f64::NAN] {
        assert!(choose(&engine, rpm, bad, &Kept::default(), &resample).is_err());
    }
    // The bundled smooth diagram meets even 1e-6 (Simpson's rule and
    // extremes refined between samples) ...
    let c = choose(&engine, rpm, 1e-6, &Kept::default(), &resample).unwrap();
    assert!(c.estimated <= 1e-6, "{c:?}");
    // ... a pressure jump does not: the interpolant's 0.1° ramp is what the
    // finest ladder steps resolve, and their differences stay large.
    let cycle = engine.cycle().to_degrees();
    let mut csv = String::from("crank_deg,pressure_bar\n");
    for k in 0..(cycle * 10.0) as usize {
        let a = k as f64 / 10.0;
        let p = if (5.0..25.0).contains(&a) { 60.0 } else { 1.0 };
        csv.push_str(&format!("{a},{p}\n"));
    }
    let jump = enginedyn_ingest::parse(csv.as_bytes(), &ParseOptions::new(cycle)).unwrap();
    let resample = |step: f64, interp: Interp| {
        Ok(enginedyn_ingest::resample_with(
            &jump,
            &GridOptions::new(step, interp),
        )?)
    };
    let e = choose(&engine, rpm, 1e-6, &Kept::default(), &resample).unwrap_err();
    assert!(e.to_string().contains("loosen the tolerance"), "{e}");
}

#[test]
fn errors_fall_as_methods_get_finer() {
    let (engine, d) = bundled()
        .into_iter()
        .find(|(e, _)| e.name().contains("VAZ"))
        .unwrap();
    let rpm = d.rpm.or(engine.operating().rpm).unwrap();
    let a = study(&Input {
        engine: &engine,
        diagram: &d,
        grid: GridOptions::new(0.1, Interp::Spline),
        rpm,
    })
    .unwrap();
    let err = |study: Study, setting: &str| {
        a.rows
            .iter()
            .find(|r| r.study == study && r.setting == setting)
            .and_then(|r| r.max_relative_error())
            .unwrap_or_else(|| panic!("{setting}"))
    };
    // Series truncation: each order better, until the 0.1° grid's own
    // error (the exact row) is what remains.
    let (s2, s4, s6) = (
        err(Study::Kinematics, "series2"),
        err(Study::Kinematics, "series4"),
        err(Study::Kinematics, "series6"),
    );
    let exact = err(Study::Kinematics, "exact");
    assert!(s2 > 10.0 * s4 && s4 > s6, "{s2} {s4} {s6}");
    assert!((s6 - exact).abs() < 1e-5, "{s6} {exact}");
    assert!(exact < 1e-4, "{exact}");
    // The three-mass rod keeps the rod's inertia: as exact as the rigid rod.
    let rigid = err(Study::RodModel, "rigid");
    assert!((err(Study::RodModel, "three-mass") - rigid).abs() < 1e-9);
    assert!(err(Study::RodModel, "two-mass") > 1e-3);
    // Grid step on the generated diagram: coarse steps worse, to second order.
    let g10 = err(Study::GridStep, "10° (generated)");
    let g1 = err(Study::GridStep, "1° (generated)");
    let g01 = err(Study::GridStep, "0.1° (generated)");
    assert!(g10 > 10.0 * g1 && g1 > 10.0 * g01, "{g10} {g1} {g01}");
    // From 0.5° samples the spline beats linear interpolation by far.
    let lin = a
        .rows
        .iter()
        .find(|r| r.setting.starts_with("linear (generated"))
        .and_then(|r| r.max_relative_error())
        .unwrap();
    let spl = a
        .rows
        .iter()
        .find(|r| r.setting.starts_with("spline (generated"))
        .and_then(|r| r.max_relative_error())
        .unwrap();
    assert!(spl < 0.1 * lin, "spline {spl:.2e} linear {lin:.2e}");
    // The Pareto front is non-dominated and ordered by time.
    let front = pareto(&a.rows);
    assert!(!front.is_empty());
    for w in front.windows(2) {
        let (x, y) = (&a.rows[w[0]], &a.rows[w[1]]);
        assert!(x.time_s <= y.time_s);
        assert!(x.max_relative_error().unwrap() >= y.max_relative_error().unwrap());
    }
}
