//! Harmonic content of a periodic signal by direct Fourier sums, and its
//! inverse: [`synthesize`] for any orders, [`Synthesis`] (tabulated, for
//! many signals of whole harmonics with complex amplitudes) for the time
//! synthesis of a forced response.
//!
//! The signal is sampled uniformly over one period of `n` samples, and that
//! period covers `cycles_per_period` periods of a *base* variable `θ`
//! (radians): `θ_i = 2π · cycles_per_period · i / n`. Order `k` is the
//! component `cos(k θ + phase)`, which completes `k · cycles_per_period`
//! cycles over the samples. For example, a signal over 720° analysed in
//! orders of a 360° base has `cycles_per_period = 2`: order 0.5 is one cycle
//! over the samples, order 2 four cycles.

use crate::NumericsError;
use crate::extremes::periodic_min_max;
use std::f64::consts::TAU;

/// Relative tolerance on `order · cycles_per_period` being a whole number.
const WHOLE_TOL: f64 = 1e-9;

/// Harmonic content of a periodic signal sampled uniformly over one period
/// (`n = y.len()` samples, `x_i = i · period / n`).
///
/// For each of `orders` returns the one-sided amplitude `A` and phase (in
/// radians, in `(-π, π]`) with `y(x) ≈ mean + Σ A cos(order θ + phase)`,
/// `θ = 2π x / base_period` running over `0..2π · cycles_per_period` across
/// the samples. Order 0 gives `A = mean` and phase 0. Each order costs one
/// pass over the samples; the cosine and sine of the `n` sample angles are
/// tabulated once per call.
///
/// # Errors
///
/// [`NumericsError::TooFewPoints`] for no samples,
/// [`NumericsError::Parameter`] for a `cycles_per_period` that is not
/// positive and finite, [`NumericsError::NonFinite`] for a NaN or infinite
/// sample, and [`NumericsError::Order`] for an order that is negative or
/// non-finite, does not complete a whole number of cycles over the samples,
/// or reaches the Nyquist limit (`2 · order · cycles_per_period ≥ n`).
///
/// ```
/// use enginedyn_numerics::fourier::harmonics;
/// use std::f64::consts::TAU;
/// // 1 + 2 cos(3θ + 0.5) over one base period.
/// let n = 64;
/// let y: Vec<f64> = (0..n).map(|i| 1.0 + 2.0 * (3.0 * TAU * i as f64 / n as f64 + 0.5).cos()).collect();
/// let h = harmonics(&y, 1.0, &[0.0, 3.0])?;
/// assert!((h[0].0 - 1.0).abs() < 1e-12);
/// assert!((h[1].0 - 2.0).abs() < 1e-12 && (h[1].1 - 0.5).abs() < 1e-12);
/// # Ok::<(), enginedyn_numerics::NumericsError>(())
/// ```
pub fn harmonics(
    y: &[f64],
    cycles_per_period: f64,
    orders: &[f64],
) -> Result<Vec<(f64, f64)>, NumericsError> {
    let n = y.len();
    if n == 0 {
        return Err(NumericsError::TooFewPoints {
            got: 0,
            need: 1,
            method: "harmonics",
        });
    }
    if !(cycles_per_period.is_finite() && cycles_per_period > 0.0) {
        return Err(NumericsError::Parameter {
            name: "cycles_per_period",
            value: cycles_per_period,
            why: "must be positive and finite",
        });
    }
    if let Some(index) = y.iter().position(|v| !v.is_finite()) {
        return Err(NumericsError::NonFinite {
            what: "y",
            index,
            value: y[index],
        });
    }
    // Whole cycles over the samples for each order, checked before any work.
    let cycles: Vec<usize> = orders
        .iter()
        .map(|&order| whole_cycles(order, cycles_per_period, n))
        .collect::<Result<_, _>>()?;
    let mean = y.iter().sum::<f64>() / n as f64;
    // cos and sin of 2π j / n, j in 0..n: exact argument reduction, no
    // trigonometry per sample and order.
    let table: Vec<(f64, f64)> = if cycles.iter().any(|&m| m > 0) {
        (0..n)
            .map(|j| {
                let (s, c) = (TAU * j as f64 / n as f64).sin_cos();
                (c, s)
            })
            .collect()
    } else {
        Vec::new()
    };
    let out = cycles
        .iter()
        .map(|&m| {
            if m == 0 {
                return (mean, 0.0);
            }
            let (mut re, mut im) = (0.0, 0.0);
            let mut j = 0; // (m k) mod n
            for &v in y {
                let (c, s) = table[j];
                re += v * c;
                im += v * s;
                j += m;
                if j >= n {
                    j -= n;
                }
            }
            // A cos(w k + φ) = A cos φ cos(w k) - A sin φ sin(w k).
            let a_cos = 2.0 * re / n as f64;
            let a_sin = -2.0 * im / n as f64;
            (a_cos.hypot(a_sin), a_sin.atan2(a_cos))
        })
        .collect();
    Ok(out)
}

/// `order · cycles_per_period` as a whole number of cycles below Nyquist.
fn whole_cycles(order: f64, cycles_per_period: f64, n: usize) -> Result<usize, NumericsError> {
    let m = order * cycles_per_period;
    if !(m.is_finite() && m >= 0.0) {
        return Err(NumericsError::Order {
            order,
            why: "must be a non-negative finite number",
        });
    }
    let r = m.round();
    if (m - r).abs() > WHOLE_TOL * r.max(1.0) {
        return Err(NumericsError::Order {
            order,
            why: "not a whole number of cycles over the samples",
        });
    }
    if 2.0 * r >= n as f64 {
        return Err(NumericsError::Order {
            order,
            why: "at or above the Nyquist limit of the samples",
        });
    }
    Ok(r as usize)
}

/// Rebuilds a signal at `n` uniform sample points from its harmonics:
/// `out[i] = Σ A cos(order θ_i + phase)` with
/// `θ_i = 2π · cycles_per_period · i / n` and `(A, phase)` from
/// `harmonics` (so order 0 with `(mean, 0)` contributes the mean).
///
/// Orders and harmonics are paired up to the shorter of the two. Every
/// entry of `out` is filled: points past `n` continue the signal (it is
/// periodic in `n` when every order completes whole cycles). `n = 0` fills
/// `out` with NaN.
pub fn synthesize(
    n: usize,
    cycles_per_period: f64,
    orders: &[f64],
    harmonics: &[(f64, f64)],
    out: &mut [f64],
) {
    if n == 0 {
        out.fill(f64::NAN);
        return;
    }
    for (i, o) in out.iter_mut().enumerate() {
        *o = orders
            .iter()
            .zip(harmonics)
            .map(|(&order, &(a, phase))| {
                // Cycles completed by sample i, reduced to [0, 1) before
                // scaling by 2π for an accurate angle.
                let cycles = order * cycles_per_period * i as f64 / n as f64;
                a * (TAU * (cycles - cycles.floor()) + phase).cos()
            })
            .sum();
    }
}

/// A complex amplitude: harmonic `h` with amplitude `X` is `Re(X e^{i h θ})`.
pub type Complex64 = num_complex::Complex<f64>;

/// Samples per period of the highest harmonic.
const PER_PERIOD: usize = 16;

/// Time synthesis of harmonics over one base period (an engine cycle):
/// harmonic `h` completes `h` periods over it, and a term `(h, X)` is
/// `Re(X e^{i h 2π s/N})` at sample `s` of `N`. The cosine and sine of the
/// `N` sample angles are tabulated once.
#[derive(Debug, Clone)]
pub struct Synthesis {
    cos: Vec<f64>,
    sin: Vec<f64>,
}

impl Synthesis {
    /// Tables for harmonics up to `max_harmonic`: 16 samples per period of
    /// the highest, at least 64.
    pub fn new(max_harmonic: usize) -> Self {
        let n = (PER_PERIOD * max_harmonic).max(64);
        let (sin, cos) = (0..n)
            .map(|s| (TAU * s as f64 / n as f64).sin_cos())
            .unzip();
        Self { cos, sin }
    }

    /// Samples per period.
    pub fn samples(&self) -> usize {
        self.cos.len()
    }

    /// The signal `Σ Re(X e^{i h θ})` on the samples, into `out`.
    pub fn signal(&self, terms: &[(usize, Complex64)], out: &mut Vec<f64>) {
        let n = self.cos.len();
        out.clear();
        out.resize(n, 0.0);
        for &(h, x) in terms {
            let h = h % n;
            let mut idx = 0;
            for v in out.iter_mut() {
                *v += x.re * self.cos[idx] - x.im * self.sin[idx];
                idx += h;
                if idx >= n {
                    idx -= n;
                }
            }
        }
    }

    /// Half the peak-to-peak value of the summed signal, its extremes
    /// refined between samples ([`crate::extremes`]); `scratch` holds the
    /// samples.
    pub fn half_peak_to_peak(&self, terms: &[(usize, Complex64)], scratch: &mut Vec<f64>) -> f64 {
        self.signal(terms, scratch);
        let (lo, hi) = periodic_min_max(scratch);
        0.5 * (hi - lo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Difference of two phases, wrapped into (-π, π].
    fn phase_diff(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(TAU);
        if d > PI { d - TAU } else { d }
    }

    /// A signal built by `synthesize` from known orders, amplitudes and
    /// phases (the expected values) is recovered to 1e-10, and the
    /// recovered harmonics synthesize the same signal back to 1e-10.
    #[test]
    fn recovers_known_harmonics() {
        let n = 7200;
        let orders = [0.0, 0.5, 2.0, 3.5, 24.0, 1.0];
        let given = [
            (3.0, 0.0),
            (2.0, 0.3),
            (1.0, -1.0),
            (0.25, 3.0),
            (0.01, -3.1),
            (0.0, 0.0),
        ];
        let mut y = vec![0.0; n];
        synthesize(n, 2.0, &orders, &given, &mut y);
        let got = harmonics(&y, 2.0, &orders).unwrap();
        for ((o, g), r) in orders.iter().zip(&given).zip(&got) {
            assert!((g.0 - r.0).abs() < 1e-10, "order {o}: {r:?}");
            if g.0 > 0.0 {
                assert!(phase_diff(g.1, r.1).abs() < 1e-10, "order {o}: {r:?}");
            }
        }
        let mut back = vec![0.0; n];
        synthesize(n, 2.0, &orders, &got, &mut back);
        for (a, b) in y.iter().zip(&back) {
            assert!((a - b).abs() < 1e-10);
        }
    }

    /// Hand-built samples: y_i = mean + A cos(order θ_i + φ) with
    /// θ_i = 2π · 2 · i / n directly, independent of `synthesize`; a negative
    /// mean comes back as a negative order-0 amplitude.
    #[test]
    fn matches_direct_definition() {
        let n = 1000;
        let y: Vec<f64> = (0..n)
            .map(|i| {
                let theta = TAU * 2.0 * i as f64 / n as f64;
                -1.5 + 0.7 * (1.5 * theta - 2.0).cos() + 4.0 * (10.0 * theta + 1.0).cos()
            })
            .collect();
        let h = harmonics(&y, 2.0, &[0.0, 1.5, 10.0, 7.0]).unwrap();
        assert!((h[0].0 + 1.5).abs() < 1e-12 && h[0].1.abs() < 1e-300);
        assert!((h[1].0 - 0.7).abs() < 1e-12 && (h[1].1 + 2.0).abs() < 1e-12);
        assert!((h[2].0 - 4.0).abs() < 1e-12 && (h[2].1 - 1.0).abs() < 1e-12);
        assert!(h[3].0 < 1e-12, "absent order: {:?}", h[3]);
    }

    /// Past `n`, `synthesize` continues the periodic signal.
    #[test]
    fn synthesize_continues_and_handles_edges() {
        let mut out = vec![0.0; 20];
        synthesize(10, 1.0, &[0.0, 1.0], &[(1.0, 0.0), (2.0, 0.5)], &mut out);
        for i in 0..10 {
            assert!((out[i] - out[i + 10]).abs() < 1e-12);
        }
        // θ_0 = 0: 1 + 2 cos(0.5).
        assert!((out[0] - (1.0 + 2.0 * 0.5_f64.cos())).abs() < 1e-15);
        synthesize(0, 1.0, &[1.0], &[(1.0, 0.0)], &mut out);
        assert!(out.iter().all(|v| v.is_nan()));
    }

    /// Each error, with the bad value in the message.
    #[test]
    fn errors() {
        let y = vec![1.0; 100];
        let order_err = |cpp: f64, order: f64| match harmonics(&y, cpp, &[order]) {
            Err(NumericsError::Order { order: o, why }) => {
                assert!((o - order).abs() < 1e-300 || o.is_nan());
                why
            }
            other => panic!("{other:?}"),
        };
        assert!(order_err(2.0, 0.25).contains("whole number"));
        assert!(order_err(2.0, 25.0).contains("Nyquist"));
        assert!(order_err(1.0, 50.0).contains("Nyquist"));
        assert!(harmonics(&y, 1.0, &[49.0]).is_ok());
        assert!(order_err(1.0, -1.0).contains("non-negative"));
        assert!(order_err(1.0, f64::NAN).contains("non-negative"));
        let e = harmonics(&y, 2.0, &[0.25]).unwrap_err();
        assert!(e.to_string().contains("0.25"), "{e}");
        let e = harmonics(&[], 1.0, &[0.0]).unwrap_err();
        assert!(
            matches!(e, NumericsError::TooFewPoints { got: 0, .. }),
            "{e}"
        );
        for cpp in [0.0, -2.0, f64::INFINITY] {
            let e = harmonics(&y, cpp, &[1.0]).unwrap_err();
            assert!(matches!(e, NumericsError::Parameter { .. }), "{e}");
        }
        let e = harmonics(&[1.0, f64::NAN, 2.0], 1.0, &[0.0]).unwrap_err();
        assert!(
            matches!(e, NumericsError::NonFinite { index: 1, .. }),
            "{e}"
        );
        // Nyquist with a single sample: even order 0 is fine, order 1 is not.
        assert!(harmonics(&[4.0], 1.0, &[0.0]).is_ok());
        assert!(harmonics(&[4.0], 1.0, &[1.0]).is_err());
    }
}
