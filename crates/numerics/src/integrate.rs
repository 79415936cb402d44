//! Integration rules on uniformly sampled data.
//!
//! On a smooth periodic integrand the trapezoid rule over a full period is
//! spectrally accurate (exact for trigonometric polynomials below the
//! Nyquist limit), so means and cycle integrals need nothing better;
//! Simpson matters for the running integral between samples.

/// Integration rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rule {
    /// Trapezoid rule.
    Trapezoid,
    /// Composite Simpson rule (a quadratic closing step where the number
    /// of intervals is odd).
    Simpson,
}

impl Rule {
    /// The name used on the command line and in reports: `"trapezoid"` or
    /// `"simpson"`.
    pub fn name(self) -> &'static str {
        match self {
            Rule::Trapezoid => "trapezoid",
            Rule::Simpson => "simpson",
        }
    }
}

/// Mean of a periodic function sampled at `n = y.len()` uniform points over
/// one period (the wrap interval from the last sample back to the first
/// included).
///
/// Trapezoid: the plain mean. Simpson with even `n`: the composite periodic
/// Simpson weights `2/3, 4/3, 2/3, 4/3, …` (divided by `n`); odd `n` falls
/// back to the trapezoid. An empty slice gives NaN.
pub fn periodic_mean(rule: Rule, y: &[f64]) -> f64 {
    if y.is_empty() {
        return f64::NAN;
    }
    periodic_integral(rule, y, 1.0) / y.len() as f64
}

/// Integral over the whole period of `n = y.len()` samples `h` apart,
/// closing the period with the wrap interval from the last sample back to
/// the first (`x_n = x_0 + n h` carries `y_0` again).
///
/// Trapezoid: `h Σ y`. Simpson with even `n`: `h/3 Σ w_k y_k` with
/// `w = 2, 4, 2, 4, …`; odd `n` falls back to the trapezoid.
pub fn periodic_integral(rule: Rule, y: &[f64], h: f64) -> f64 {
    match rule {
        Rule::Simpson if y.len().is_multiple_of(2) => {
            let (even, odd) = y
                .chunks_exact(2)
                .fold((0.0, 0.0), |(e, o), p| (e + p[0], o + p[1]));
            (2.0 * even + 4.0 * odd) * h / 3.0
        }
        _ => y.iter().sum::<f64>() * h,
    }
}

/// Running integral of samples `y` spaced `h` apart: `out[0] = 0`,
/// `out[i]` = the integral from `x_0` to `x_i`.
///
/// Trapezoid: the cumulative trapezoid (error O(h²)). Simpson: composite
/// Simpson at even `i` (exact for cubics); at odd `i` the value at `i - 1`
/// plus the integral over the last interval of the parabola through samples
/// `i - 1, i, i + 1` (through `i - 2, i - 1, i` at the end of the data): the
/// standard cumulative Simpson, locally third order (error O(h⁴) per
/// interval). Fewer than 3 samples use the trapezoid.
///
/// `out.len()` should equal `y.len()`; only the first `min` of the two are
/// computed and any further entries of `out` are set to NaN.
pub fn cumulative(rule: Rule, y: &[f64], h: f64, out: &mut [f64]) {
    let n = y.len().min(out.len());
    out[n..].fill(f64::NAN);
    if n == 0 {
        return;
    }
    let (y, out) = (&y[..n], &mut out[..n]);
    out[0] = 0.0;
    if rule == Rule::Trapezoid || n < 3 {
        for i in 1..n {
            out[i] = out[i - 1] + 0.5 * h * (y[i - 1] + y[i]);
        }
        return;
    }
    for i in 1..n {
        out[i] = if i % 2 == 0 {
            out[i - 2] + h / 3.0 * (y[i - 2] + 4.0 * y[i - 1] + y[i])
        } else if i + 1 < n {
            out[i - 1] + h / 12.0 * (5.0 * y[i - 1] + 8.0 * y[i] - y[i + 1])
        } else {
            out[i - 1] + h / 12.0 * (-y[i - 2] + 8.0 * y[i - 1] + 5.0 * y[i])
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    const RULES: [Rule; 2] = [Rule::Trapezoid, Rule::Simpson];

    #[test]
    fn names() {
        assert_eq!(Rule::Trapezoid.name(), "trapezoid");
        assert_eq!(Rule::Simpson.name(), "simpson");
    }

    /// ∫₀^{2π} cos²x dx = π, mean 1/2 (analytic); both periodic rules are
    /// exact on this trigonometric polynomial (1e-12), for even and odd n
    /// (odd n: Simpson falls back to the trapezoid).
    #[test]
    fn periodic_rules_exact_on_trig() {
        for n in [8, 64, 65, 7200] {
            let h = TAU / n as f64;
            let y: Vec<f64> = (0..n).map(|k| (k as f64 * h).cos().powi(2)).collect();
            for r in RULES {
                assert!(
                    (periodic_integral(r, &y, h) - PI).abs() < 1e-12,
                    "{r:?} {n}"
                );
                assert!((periodic_mean(r, &y) - 0.5).abs() < 1e-12, "{r:?} {n}");
            }
        }
        assert!(periodic_mean(Rule::Simpson, &[]).is_nan());
        assert!(periodic_integral(Rule::Trapezoid, &[], 1.0).abs() < 1e-300);
    }

    /// Hand-computed weights: trapezoid h Σy; Simpson h/3 (2, 4, 2, 4).
    #[test]
    fn periodic_weights() {
        let y = [1.0, 2.0, 3.0, 4.0];
        assert!((periodic_integral(Rule::Trapezoid, &y, 0.5) - 5.0).abs() < 1e-15);
        let s = 0.5 / 3.0 * (2.0 + 8.0 + 6.0 + 16.0);
        assert!((periodic_integral(Rule::Simpson, &y, 0.5) - s).abs() < 1e-15);
        assert!((periodic_mean(Rule::Simpson, &y) - s / 0.5 / 4.0).abs() < 1e-15);
        // Odd n: Simpson is the trapezoid.
        let y = [1.0, 2.0, 3.0];
        assert!((periodic_integral(Rule::Simpson, &y, 0.5) - 3.0).abs() < 1e-15);
    }

    /// Simpson is exact for cubics at even indices: ∫₀ˣ t³ dt = x⁴/4. The
    /// trapezoid error on x³ is exactly h² (f'(x) - f'(0)) / 12 = h² x² / 4
    /// (Euler–Maclaurin; the h⁴ term needs f''' to change, and it is constant).
    #[test]
    fn cumulative_cubic() {
        let h = 0.1;
        let y: Vec<f64> = (0..21).map(|k| (k as f64 * h).powi(3)).collect();
        let mut out = vec![0.0; 21];
        cumulative(Rule::Simpson, &y, h, &mut out);
        for i in (0..21).step_by(2) {
            let x = i as f64 * h;
            assert!((out[i] - x.powi(4) / 4.0).abs() < 1e-12, "{i}");
        }
        cumulative(Rule::Trapezoid, &y, h, &mut out);
        for (i, v) in out.iter().enumerate() {
            let x = i as f64 * h;
            assert!(
                (v - x.powi(4) / 4.0 - h * h * x * x / 4.0).abs() < 1e-12,
                "{i}"
            );
        }
        // The quadratic closing steps are exact on quadratics at odd indices
        // too, the last one included (21 samples end on an even index; 20 do not).
        for n in [20, 21] {
            let y: Vec<f64> = (0..n).map(|k| (k as f64 * h).powi(2)).collect();
            let mut out = vec![0.0; n];
            cumulative(Rule::Simpson, &y, h, &mut out);
            for (i, v) in out.iter().enumerate() {
                assert!((v - (i as f64 * h).powi(3) / 3.0).abs() < 1e-12, "{n} {i}");
            }
        }
    }

    /// Max error of the running integral of sin on [0, 1] against
    /// 1 - cos x (analytic), with `n` intervals.
    fn sin_error(n: usize, r: Rule) -> f64 {
        let h = 1.0 / n as f64;
        let y: Vec<f64> = (0..=n).map(|k| (k as f64 * h).sin()).collect();
        let mut out = vec![0.0; n + 1];
        cumulative(r, &y, h, &mut out);
        (0..=n)
            .map(|i| (out[i] - (1.0 - (i as f64 * h).cos())).abs())
            .fold(0.0, f64::max)
    }

    /// Observed orders from halving h: trapezoid 2 (1.9..2.1), Simpson
    /// between 3 and 4.5 (locally third order: O(h⁴) per interval).
    #[test]
    fn cumulative_convergence_orders() {
        for (a, b) in [(20, 40), (40, 80)] {
            let t = (sin_error(a, Rule::Trapezoid) / sin_error(b, Rule::Trapezoid)).log2();
            let s = (sin_error(a, Rule::Simpson) / sin_error(b, Rule::Simpson)).log2();
            assert!((1.9..2.1).contains(&t), "trapezoid order {t}");
            assert!((3.0..4.5).contains(&s), "simpson order {s}");
        }
    }

    /// Short inputs and a mismatched `out` do not panic.
    #[test]
    fn short_and_mismatched() {
        for r in RULES {
            let mut out = [9.0; 4];
            cumulative(r, &[], 1.0, &mut out);
            assert!(out.iter().all(|v| v.is_nan()));
            cumulative(r, &[1.0, 3.0], 0.5, &mut out);
            // Trapezoid on one interval: 0.5 (1 + 3) / 2 = 1.
            assert!(out[0].abs() < 1e-15 && (out[1] - 1.0).abs() < 1e-15);
            assert!(out[2].is_nan() && out[3].is_nan());
            let mut short = [0.0; 2];
            cumulative(r, &[1.0, 1.0, 1.0, 1.0], 1.0, &mut short);
            assert!((short[1] - 1.0).abs() < 1e-15);
        }
    }
}
