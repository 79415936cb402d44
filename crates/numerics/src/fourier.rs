//! Harmonic content of a periodic signal by direct Fourier sums.

use crate::NumericsError;
use std::f64::consts::TAU;

/// Amplitude and phase of the given orders of a signal sampled at `n`
/// uniform points over one period that spans `cycles_per_period` base
/// periods (a 720° torque trace in orders per revolution: 2). Returns
/// `(A, phase)` with `y ≈ mean + Σ A cos(order θ + phase)`, `θ` the base
/// angle in radians from the first sample; order 0 gives `(mean, 0)`.
/// Orders that do not complete a whole number of cycles over the samples,
/// or reach the Nyquist limit, are errors.
pub fn harmonics(
    y: &[f64],
    cycles_per_period: f64,
    orders: &[f64],
) -> Result<Vec<(f64, f64)>, NumericsError> {
    let n = y.len();
    orders
        .iter()
        .map(|&order| {
            let m = order * cycles_per_period;
            if !(m >= 0.0) || (m - m.round()).abs() > 1e-9 {
                return Err(NumericsError::Order {
                    order,
                    why: "not a whole number of cycles over the samples",
                });
            }
            let m = m.round() as usize;
            if 2 * m >= n {
                return Err(NumericsError::Order {
                    order,
                    why: "at or above the Nyquist limit of the samples",
                });
            }
            if m == 0 {
                return Ok((y.iter().sum::<f64>() / n as f64, 0.0));
            }
            let (mut re, mut im) = (0.0, 0.0);
            let w = TAU * m as f64 / n as f64;
            for (k, v) in y.iter().enumerate() {
                let (s, c) = (w * k as f64).sin_cos();
                re += v * c;
                im += v * s;
            }
            // y_k ≈ A cos(w k + phase) = A cos(phase) cos(w k) - A sin(phase) sin(w k)
            let a_c = 2.0 * re / n as f64;
            let a_s = 2.0 * im / n as f64;
            Ok((a_c.hypot(a_s), (-a_s).atan2(a_c)))
        })
        .collect()
}

/// Rebuilds a signal at `n` sample points from its harmonics.
pub fn synthesize(
    n: usize,
    cycles_per_period: f64,
    orders: &[f64],
    harmonics: &[(f64, f64)],
    out: &mut [f64],
) {
    for (k, o) in out.iter_mut().enumerate().take(n) {
        let theta = TAU * cycles_per_period * k as f64 / n as f64;
        *o = orders
            .iter()
            .zip(harmonics)
            .map(|(&ord, &(a, ph))| {
                if ord == 0.0 {
                    a
                } else {
                    a * (ord * theta + ph).cos()
                }
            })
            .sum();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_known_harmonics() {
        let n = 1440;
        let orders = [0.0, 0.5, 2.0, 3.5];
        let given = [(3.0, 0.0), (2.0, 0.3), (1.0, -1.0), (0.0, 0.0)];
        let mut y = vec![0.0; n];
        synthesize(n, 2.0, &orders, &given, &mut y);
        let h = harmonics(&y, 2.0, &orders).unwrap();
        for (g, r) in given.iter().zip(&h) {
            assert!((g.0 - r.0).abs() < 1e-10);
            if g.0 > 0.0 {
                assert!((g.1 - r.1).abs() < 1e-10);
            }
        }
        assert!(harmonics(&y, 2.0, &[0.25]).is_err());
        assert!(harmonics(&y, 2.0, &[720.0]).is_err());
    }
}
