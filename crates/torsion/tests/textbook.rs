//! A printed Holzer table reproduced by the chain's solver, and the
//! Campbell diagram's formulas.
//!
//! Source: W. T. Thomson, *Theory of Vibration with Applications*
//! (Taylor & Francis printing, 2010, of the Thomson & Dahleh 5th edition),
//! section 12.4 "Holzer Method", pp. 388–389: the worked example's Table
//! 12.4-1, a free three-disc system with J = 5, 11, 22 kg m² and
//! k = 0.10e6, 0.20e6 N m/rad, tabulated at the trial frequencies ω = 20
//! and 40 rad/s from θ₁ = 1 (T_i: the torque in the shaft after disc i,
//! Σ ω² J θ up to it; T₃ the residual, zero at a natural frequency):
//!
//! | ω | θ₂ | θ₃ | T₁ | T₂ | T₃ |
//! |---|----|----|----|----|----|
//! | 20 | 0.980 | 0.9484 | 2.0e3 | 6.312e3 | 14.66e3 |
//! | 40 | 0.920 | 0.799 | 8.0e3 | 24.19e3 | 52.32e3 |
//!
//! The pages read give the natural frequencies only as the zeros of a plot
//! of T₃ against ω (Fig. 12.4-3), no printed digits, so they are checked
//! here against the Holzer recurrence itself (a zero residual), not
//! against the book.
//!
//! A Holzer row at a trial ω is the chain's forced response with the
//! residual torque applied at the last disc: rows 1 and 2 of
//! `(K − ω² M) θ = T` hold with no torque, and the sum of all three rows
//! (K's rows sum to 0) makes the torque at disc 3 `−ω² Σ J θ = −T₃`. So the solver, given a torque `−T₃` at disc 3, must
//! return the table's angles with θ₁ = 1, and each section's torque
//! `k_j (θ_j − θ_{j+1})` must be the table's `T_j`.

use enginedyn_torsion::{
    Chain, Complex64, Solver, critical_speed_rpm, crossings, is_major_order, order_frequency_hz,
};

const J: [f64; 3] = [5.0, 11.0, 22.0];
const K: [f64; 2] = [0.10e6, 0.20e6];

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The response to a unit torque at disc 3, scaled to θ₁ = 1, and the
/// torque that scale means (the residual −T₃ of Holzer's table).
fn holzer_row(omega: f64) -> (Vec<f64>, f64) {
    let chain = Chain::new(J.to_vec(), K.to_vec()).unwrap();
    let solver = Solver::new(&chain).unwrap();
    let zero = Complex64::new(0.0, 0.0);
    let theta = solver
        .respond(omega, &[zero, zero, Complex64::new(1.0, 0.0)])
        .unwrap();
    // Undamped: the response is real.
    assert!(theta.iter().all(|t| t.im.abs() < 1e-15 * t.re.abs()));
    let scale = 1.0 / theta[0].re;
    (theta.iter().map(|t| t.re * scale).collect(), -scale)
}

/// Thomson's Table 12.4-1, each value to half its last printed digit.
#[test]
fn thomson_table_12_4_1() {
    // (ω, θ₂, θ₃, T₂, T₃) as printed, with half a unit of the last digit.
    let rows = [
        (
            20.0,
            (0.980, 5e-4),
            (0.9484, 5e-5),
            (6.312e3, 0.5),
            (14.66e3, 5.0),
        ),
        (
            40.0,
            (0.920, 5e-4),
            (0.799, 5e-4),
            (24.19e3, 5.0),
            (52.32e3, 5.0),
        ),
    ];
    for (omega, th2, th3, t2, t3) in rows {
        let (theta, residual) = holzer_row(omega);
        assert!(
            (theta[1] - th2.0).abs() <= th2.1,
            "ω {omega}: θ₂ {}",
            theta[1]
        );
        assert!(
            (theta[2] - th3.0).abs() <= th3.1,
            "ω {omega}: θ₃ {}",
            theta[2]
        );
        // T₁ = ω² J₁ θ₁ is the torque in the first shaft.
        let s1 = K[0] * (theta[0] - theta[1]);
        assert!(rel(s1, omega * omega * J[0]) < 1e-12, "ω {omega}: T₁ {s1}");
        let s2 = K[1] * (theta[1] - theta[2]);
        assert!((s2 - t2.0).abs() <= t2.1, "ω {omega}: T₂ {s2}");
        assert!((residual - t3.0).abs() <= t3.1, "ω {omega}: T₃ {residual}");
    }
}

/// At each natural frequency of the eigen solver, Holzer's recurrence
/// (the book's procedure, written out here) leaves no residual torque.
#[test]
fn natural_frequencies_zero_the_holzer_residual() {
    let modes = Chain::new(J.to_vec(), K.to_vec()).unwrap().modes().unwrap();
    let holzer = |w: f64| {
        let (mut theta, mut torque) = (1.0, 0.0);
        for i in 0..J.len() {
            torque += w * w * J[i] * theta;
            if i < K.len() {
                theta -= torque / K[i];
            }
        }
        torque
    };
    let total: f64 = J.iter().sum();
    for m in 1..3 {
        let w = modes.omega[m];
        // The residual against its scale ω² ΣJ: 1e-9 (rounding; a
        // frequency 1e-6 off leaves about 1e-6).
        let r = holzer(w) / (w * w * total);
        assert!(r.abs() < 1e-9, "mode {m} at {w} rad/s: residual {r}");
        let off = holzer(w * (1.0 + 1e-6)) / (w * w * total);
        assert!(off.abs() > 1e-7, "mode {m}: the check can fail ({off})");
    }
    // The two elastic modes lie between the table's trial frequencies and
    // beyond: 123.67 and 202.66 rad/s (the residual changes sign there).
    assert!(
        (modes.omega[1] - 123.666).abs() < 1e-2,
        "{}",
        modes.omega[1]
    );
    assert!(
        (modes.omega[2] - 202.658).abs() < 1e-2,
        "{}",
        modes.omega[2]
    );
}

#[test]
fn critical_speeds_and_order_lines() {
    // 60 f / k and its inverse (1e-15: one rounding).
    assert!(rel(critical_speed_rpm(45.0, 1.5), 1800.0) < 1e-15);
    assert!(rel(order_frequency_hz(1.5, 1800.0), 45.0) < 1e-15);
    assert!(rel(critical_speed_rpm(160.0, 6.0), 1600.0) < 1e-15);
    for (f, k) in [(160.612, 4.5), (422.045, 9.5), (37.1, 0.5)] {
        let n = critical_speed_rpm(f, k);
        assert!(rel(order_frequency_hz(k, n), f) < 1e-15);
    }
}

#[test]
fn major_orders_are_multiples_of_the_firings() {
    // Inline six four-stroke: 3 firings per revolution.
    let six: Vec<f64> = (1..=16)
        .map(|h| h as f64 * 0.5)
        .filter(|&k| is_major_order(k, 3.0))
        .collect();
    assert_eq!(six, vec![3.0, 6.0]);
    // V8 four-stroke: 4 per revolution; three-cylinder two-stroke: 3.
    assert!(is_major_order(8.0, 4.0) && !is_major_order(6.0, 4.0) && !is_major_order(2.0, 4.0));
    assert!(is_major_order(3.0, 3.0) && !is_major_order(1.5, 3.0));
    // A single-cylinder four-stroke: every half order is major.
    assert!(is_major_order(0.5, 0.5) && is_major_order(2.5, 0.5));
    assert!(!is_major_order(3.0, 0.0) && !is_major_order(0.0, 3.0));
}

#[test]
fn crossings_in_the_range_only() {
    let freqs = [0.0, 45.0, 160.0];
    let orders: Vec<f64> = (1..=48).map(|h| h as f64 * 0.5).collect();
    let (lo, hi) = (440.0, 2640.0);
    let c = crossings(&freqs, &orders, lo, hi);
    // Every crossing in range, none outside, each by 60 f / k.
    let mut expected = 0;
    for (m, &f) in freqs.iter().enumerate().skip(1) {
        for (o, &k) in orders.iter().enumerate() {
            let n = 60.0 * f / k;
            let hit = c.iter().find(|x| x.mode == m && x.order == o);
            if (lo..=hi).contains(&n) {
                expected += 1;
                assert!(rel(hit.expect("a crossing in range is found").rpm, n) < 1e-15);
            } else {
                assert!(
                    hit.is_none(),
                    "mode {m} order {k} at {n} rpm is out of range"
                );
            }
        }
    }
    assert_eq!(c.len(), expected);
    // 45 Hz: orders 1.5 to 6 (1800 … 450 rpm); 160 Hz: orders 4 to 21.5.
    assert_eq!(c.iter().filter(|x| x.mode == 1).count(), 10);
    assert_eq!(c.iter().filter(|x| x.mode == 2).count(), 36);
}
