//! Property tests of the periodic interpolants on random smooth periodic
//! data (a mean plus a few random harmonics, sampled at jittered knots).

use enginedyn_numerics::{InterpKind, Periodic};
use proptest::prelude::*;
use std::f64::consts::TAU;

const KINDS: [InterpKind; 3] = [InterpKind::Linear, InterpKind::Spline, InterpKind::Pchip];

/// Knots, values and period of a random smooth periodic sample set.
#[derive(Debug, Clone)]
struct Data {
    xs: Vec<f64>,
    ys: Vec<f64>,
    period: f64,
}

/// `n` knots on `[x0, x0 + period)`, each jittered by up to ±40 % of a
/// spacing; values `mean + Σ a_j cos(2π k_j x / period + φ_j)`.
fn data() -> impl Strategy<Value = Data> {
    (
        3usize..80,
        0.1f64..1000.0,
        -500.0f64..500.0,
        -10.0f64..10.0,
        prop::collection::vec((1u32..6, 0.0f64..5.0, 0.0f64..TAU), 1..4),
        prop::collection::vec(-0.4f64..0.4, 80),
    )
        .prop_map(|(n, period, x0, mean, terms, jitter)| {
            let xs: Vec<f64> = (0..n)
                .map(|k| x0 + (k as f64 + jitter[k]) * period / n as f64)
                .collect();
            let ys = xs
                .iter()
                .map(|x| {
                    mean + terms
                        .iter()
                        .map(|&(k, a, ph)| a * (TAU * f64::from(k) * x / period + ph).cos())
                        .sum::<f64>()
                })
                .collect();
            Data { xs, ys, period }
        })
}

/// Largest |y|, at least 1: the scale for absolute tolerances.
fn scale(ys: &[f64]) -> f64 {
    ys.iter().fold(1.0, |m, y| m.max(y.abs()))
}

proptest! {
    /// Every kind returns the data at the knots (1e-9 of the data scale),
    /// also one period later.
    #[test]
    fn interpolates_at_knots(d in data()) {
        let tol = 1e-9 * scale(&d.ys);
        for kind in KINDS {
            let f = Periodic::new(kind, &d.xs, &d.ys, d.period).unwrap();
            for (x, y) in d.xs.iter().zip(&d.ys) {
                prop_assert!((f.eval(*x) - y).abs() <= tol, "{kind:?} at {x}");
                prop_assert!((f.eval(x + d.period) - y).abs() <= tol, "{kind:?} at {x} + period");
            }
        }
    }

    /// eval is periodic: eval(x) = eval(x + period) = eval(x - 3 period)
    /// within 1e-9 of the data scale, anywhere.
    #[test]
    fn eval_is_periodic(d in data(), fr in prop::collection::vec(-2.0f64..2.0, 20)) {
        let tol = 1e-9 * scale(&d.ys);
        for kind in KINDS {
            let f = Periodic::new(kind, &d.xs, &d.ys, d.period).unwrap();
            for &r in &fr {
                let x = d.xs[0] + r * d.period;
                let v = f.eval(x);
                prop_assert!((v - f.eval(x + d.period)).abs() <= tol, "{kind:?} at {x}");
                prop_assert!((v - f.eval(x - 3.0 * d.period)).abs() <= tol, "{kind:?} at {x}");
            }
        }
    }

    /// Pchip never leaves the local data range (its analytic overshoot is
    /// rounding only), and the spline's analytic overshoot is at least what
    /// a scan of 64 points per interval sees.
    #[test]
    fn overshoot_bounds(d in data()) {
        let tol = 1e-12 * scale(&d.ys);
        let p = Periodic::new(InterpKind::Pchip, &d.xs, &d.ys, d.period).unwrap();
        let s = Periodic::new(InterpKind::Spline, &d.xs, &d.ys, d.period).unwrap();
        prop_assert!(p.max_overshoot() <= tol, "{}", p.max_overshoot());
        let n = d.xs.len();
        let mut scan = 0.0_f64;
        for i in 0..n {
            let (a, b) = (d.xs[i], if i + 1 < n { d.xs[i + 1] } else { d.xs[0] + d.period });
            let (y0, y1) = (d.ys[i], d.ys[(i + 1) % n]);
            let (lo, hi) = (y0.min(y1), y0.max(y1));
            for k in 1..64 {
                let x = a + (b - a) * f64::from(k) / 64.0;
                let pv = p.eval(x);
                prop_assert!(pv >= lo - tol && pv <= hi + tol, "pchip {pv} at {x}");
                let sv = s.eval(x);
                scan = scan.max(sv - hi).max(lo - sv);
            }
        }
        prop_assert!(s.max_overshoot() >= scan - tol, "{} < {scan}", s.max_overshoot());
    }

    /// The uniform-grid evaluator agrees with eval at every grid point.
    #[test]
    fn eval_uniform_agrees(d in data(), start in -3.0f64..3.0, step in -0.5f64..0.5, m in 0usize..400) {
        let tol = 1e-12 * scale(&d.ys);
        let (start, step) = (d.xs[0] + start * d.period, step * d.period / 7.0);
        let mut out = vec![0.0; m];
        for kind in KINDS {
            let f = Periodic::new(kind, &d.xs, &d.ys, d.period).unwrap();
            f.eval_uniform(start, step, &mut out);
            for (k, v) in out.iter().enumerate() {
                let w = f.eval(start + step * k as f64);
                prop_assert!((v - w).abs() <= tol, "{kind:?} {k}: {v} vs {w}");
            }
        }
    }
}
