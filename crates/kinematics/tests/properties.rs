//! Property tests: derivatives against finite differences, offset dead centres
//! against brute force, the mechanism's existence bound.

use enginedyn_kinematics::{CrankSlider, KinematicsError, Mechanism, Model};
use proptest::prelude::*;
use std::f64::consts::PI;

fn mech(lambda: f64, k: f64) -> Mechanism {
    let r = 0.04;
    Mechanism::CrankSlider(CrankSlider::new(r, r / lambda, k * r).unwrap())
}

proptest! {
    /// Analytic dx/dphi, d2x/dphi2 and the rod angle's derivatives against
    /// central differences (h = 1e-4 rad: truncation ~h^2 = 1e-8 relative).
    #[test]
    fn derivatives_match_finite_differences(phi in 0.0..(2.0 * PI), lambda in 0.1..0.4, k in -0.5f64..0.5) {
        prop_assume!(lambda * (1.0 + k.abs()) < 0.95);
        let m = mech(lambda, k);
        let h = 1e-4;
        for model in [Model::Exact, Model::Series2] {
            let s = m.state(model, phi).unwrap();
            let p = m.state(model, phi + h).unwrap();
            let q = m.state(model, phi - h).unwrap();
            let r = 0.04;
            prop_assert!(((p.x - q.x) / (2.0 * h) - s.dx).abs() < 1e-7 * r, "dx {model:?}");
            prop_assert!(((p.dx - q.dx) / (2.0 * h) - s.d2x).abs() < 1e-6 * r, "d2x {model:?}");
            prop_assert!(((p.beta - q.beta) / (2.0 * h) - s.dbeta).abs() < 1e-7);
            prop_assert!(((p.dbeta - q.dbeta) / (2.0 * h) - s.d2beta).abs() < 1e-6);
        }
    }

    /// With an offset TDC and BDC are where x is extreme, and the stroke is
    /// their distance: checked by a brute-force scan (0.001° then golden refinement).
    #[test]
    fn offset_dead_centres_brute_force(lambda in 0.15..0.35, k in -0.6f64..0.6) {
        prop_assume!(lambda * (1.0 + k.abs()) < 0.95);
        let m = mech(lambda, k);
        let Mechanism::CrankSlider(cs) = m else { unreachable!() };
        // y = R cos(phi_g) + sqrt(L^2 - (e - R sin phi_g)^2), brute force over phi_g.
        let y = |g: f64| cs.r() * g.cos() + (cs.l().powi(2) - (cs.e() - cs.r() * g.sin()).powi(2)).sqrt();
        let n = 360_000;
        let (mut gmax, mut ymax, mut gmin, mut ymin) = (0.0, f64::MIN, 0.0, f64::MAX);
        for i in 0..n {
            let g = 2.0 * PI * i as f64 / n as f64 - PI / 2.0;
            let v = y(g);
            if v > ymax { ymax = v; gmax = g; }
            if v < ymin { ymin = v; gmin = g; }
        }
        let step = 2.0 * PI / n as f64;
        prop_assert!((cs.phi_tdc() - gmax).abs() < step);
        prop_assert!((cs.phi_bdc() - gmin).abs() < step);
        // The scan finds the extremes to R·step² ≈ 1.2e-11 m.
        prop_assert!((cs.stroke() - (ymax - ymin)).abs() < 5e-11);
        prop_assert!(m.exact(0.0).x.abs() < 1e-12);
        prop_assert!((m.exact(m.bdc_after_tdc()).x - cs.stroke()).abs() < 1e-12);
    }

    /// The angle for a displacement inverts x(phi) on each stroke.
    #[test]
    fn angle_at_inverts_position(frac in 0.0..1.0, lambda in 0.15..0.35, k in -0.4f64..0.4) {
        prop_assume!(lambda * (1.0 + k.abs()) < 0.95);
        let m = mech(lambda, k);
        let x = frac * m.stroke();
        for down in [true, false] {
            let phi = m.angle_at(x, down).unwrap();
            prop_assert!((m.exact(phi).x - x).abs() < 1e-12);
            let on_stroke = if down { phi <= m.bdc_after_tdc() + 1e-12 } else { phi >= m.bdc_after_tdc() - 1e-12 };
            prop_assert!(on_stroke);
        }
    }
}

#[test]
fn impossible_mechanisms_are_rejected() {
    let e = CrankSlider::new(0.05, 0.1, 0.05).unwrap_err();
    assert!(matches!(e, KinematicsError::Impossible { .. }));
    assert!(e.to_string().contains("must be below 1"));
    assert!(CrankSlider::new(0.05, 0.05, 0.0).is_err());
    assert!(CrankSlider::new(-0.05, 0.2, 0.0).is_err());
    assert!(CrankSlider::new(0.05, f64::NAN, 0.0).is_err());
    let m = mech(0.25, 0.1);
    assert!(matches!(
        m.check(Model::Series4),
        Err(KinematicsError::SeriesWithOffset { .. })
    ));
    assert!(m.check(Model::Series2).is_ok());
}
