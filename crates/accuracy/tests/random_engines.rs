//! `--tolerance REL` over random engines: every key result of the chosen
//! setting, the piston speed and acceleration extremes included, stays
//! within REL of the reference setting (exact kinematics, the most exact
//! rod, the spline, 0.01°, the trapezoid). The engines span λ 0.2–0.35,
//! pin offsets, two-stroke, vee and Scotch yoke; REL runs from 3e-2 to
//! 1e-5. The diagram is the project's cycle model for each engine.

use enginedyn_accuracy::{KEYS, Kept, choose, generated, reference, relative_errors};
use enginedyn_engine::Engine;
use enginedyn_ingest::{Interp, Resampled};
use enginedyn_pipeline::{Options, Scope, Summary};
use proptest::prelude::*;

/// One random engine as an engine file would give it.
#[derive(Debug, Clone)]
struct Spec {
    mechanism: u8, // 0 crank-slider inline, 1 vee, 2 two-stroke, 3 Scotch yoke
    lambda: f64,
    offset_mm: f64,
    rod_inertia: bool,
    rpm: f64,
}

fn engine(s: &Spec) -> Engine {
    let (cycle, layout, z, firing) = match s.mechanism {
        1 => (
            "four-stroke",
            "layout = \"vee\"\nbank_angle_deg = 90.0\n",
            8,
            "[1, 5, 4, 8, 6, 3, 7, 2]",
        ),
        2 => ("two-stroke", "", 3, "[1, 3, 2]"),
        _ => ("four-stroke", "", 4, "[1, 3, 4, 2]"),
    };
    let stroke = 80.0;
    let mut text = format!(
        "cycle = \"{cycle}\"\ncylinders = {z}\n{layout}firing_order = {firing}\nbore_mm = 82.0\nstroke_mm = {stroke}\ncompression_ratio = 10.0\ncylinder_spacing_mm = 95.0\n"
    );
    if s.mechanism == 3 {
        text.push_str("mechanism = \"scotch-yoke\"\n[masses]\npiston_group_kg = 0.45\nyoke_kg = 0.5\nslider_block_kg = 0.1\n");
    } else {
        text.push_str(&format!(
            "lambda = {}\npin_offset_mm = {}\n[masses]\npiston_group_kg = 0.45\nrod_kg = 0.55\n",
            s.lambda, s.offset_mm
        ));
        if s.rod_inertia {
            let l = stroke / 2.0 / s.lambda * 1e-3;
            // 0.8 of m l_A l_B with the default 27.5 % split: m_0 > 0.
            text.push_str(&format!(
                "rod_inertia_kg_m2 = {}\n",
                0.8 * 0.55 * 0.725 * l * 0.275 * l
            ));
        }
    }
    text.push_str(&format!(
        "crank_unbalanced_kg = 0.3\n[operating]\nrpm = {}\n",
        s.rpm
    ));
    enginedyn_engine::file::parse(&text, "random").unwrap()
}

fn spec() -> impl Strategy<Value = Spec> {
    (
        0u8..4,
        0.2..0.35f64,
        prop_oneof![Just(0.0), -8.0..8.0f64],
        any::<bool>(),
        1500.0..6500.0f64,
    )
        .prop_map(|(mechanism, lambda, offset_mm, rod_inertia, rpm)| Spec {
            mechanism,
            lambda,
            offset_mm,
            rod_inertia,
            rpm,
        })
}

fn summary(engine: &Engine, sol: &enginedyn_synth::CycleSolution, rpm: f64, o: Options) -> Summary {
    let r = on_grid(engine, sol, o.step_deg);
    enginedyn_pipeline::analyse(
        engine,
        &r,
        rpm,
        &Options {
            scope: Scope::Summary,
            ..o
        },
    )
    .unwrap()
    .summary
}

fn on_grid(engine: &Engine, sol: &enginedyn_synth::CycleSolution, step: f64) -> Resampled {
    let n = (engine.cycle().to_degrees() / step).round() as usize;
    Resampled::from_grid(
        step,
        (0..n).map(|k| sol.pressure(k as f64 * step)).collect(),
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn every_key_result_stays_within_rel(s in spec(), rel_exp in 0usize..5) {
        let rel = [3e-2, 1e-2, 1e-3, 1e-4, 1e-5][rel_exp];
        let e = engine(&s);
        let (sol, _) = generated(&e).unwrap();
        let reference = summary(&e, &sol, s.rpm, reference(&e));
        let resample = |step: f64, _: Interp| Ok(on_grid(&e, &sol, step));
        let c = match choose(&e, s.rpm, rel, &Kept::default(), &resample) {
            Ok(c) => c,
            // A tolerance no setting can meet is refused, never missed.
            Err(err) => {
                prop_assert!(err.to_string().contains("loosen the tolerance"), "{err}");
                return Ok(());
            }
        };
        let got = summary(&e, &sol, s.rpm, c.options);
        for (k, err) in KEYS.iter().zip(relative_errors(&got, &reference)) {
            if let Some(err) = err {
                prop_assert!(err <= rel, "{s:?} REL {rel}: {k} off by {err:.2e} with {:?}", c.options);
            }
        }
    }
}
