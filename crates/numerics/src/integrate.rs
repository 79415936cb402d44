//! Integration rules on uniformly sampled data.
//!
//! On a smooth periodic integrand the trapezoid rule over a full period is
//! spectrally accurate, so means and cycle integrals need nothing better;
//! Simpson matters for the running integral (`E(phi)`) between samples.

/// Integration rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rule {
    /// Trapezoid rule.
    Trapezoid,
    /// Simpson's rule (composite; 3/8-style closing for odd steps).
    Simpson,
}

impl Rule {
    /// The name used on the command line and in `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Rule::Trapezoid => "trapezoid",
            Rule::Simpson => "simpson",
        }
    }
}

/// Mean over one period of `n` uniform samples (the wrap interval included).
/// Trapezoid: the plain mean. Simpson (even `n`): weights 4/3, 2/3
/// alternating; odd `n` falls back to the trapezoid.
pub fn periodic_mean(rule: Rule, y: &[f64]) -> f64 {
    let n = y.len();
    if n == 0 {
        return 0.0;
    }
    periodic_integral(rule, y, 1.0) / n as f64
}

/// Integral over the whole period of `n` samples `h` apart, closing the wrap
/// interval from the last sample back to the first.
pub fn periodic_integral(rule: Rule, y: &[f64], h: f64) -> f64 {
    let n = y.len();
    match rule {
        Rule::Simpson if n % 2 == 0 && n >= 4 => {
            let s: f64 = y
                .iter()
                .enumerate()
                .map(|(k, v)| if k % 2 == 0 { 2.0 * v } else { 4.0 * v })
                .sum();
            s * h / 3.0
        }
        _ => y.iter().sum::<f64>() * h,
    }
}

/// Running integral: `out[0] = 0`, `out[i]` = integral from sample 0 to i.
/// Trapezoid: cumulative trapezoid (error O(h²)). Simpson: composite Simpson
/// at even `i`; at odd `i` the value at `i - 1` plus the quadratic through
/// samples `i - 1, i, i + 1` (or `i - 2, i - 1, i` at the end) integrated
/// over the last interval (error O(h³) locally, O(h⁴) at even points).
pub fn cumulative(rule: Rule, y: &[f64], h: f64, out: &mut [f64]) {
    let n = y.len().min(out.len());
    if n == 0 {
        return;
    }
    out[0] = 0.0;
    match rule {
        Rule::Trapezoid => {
            for i in 1..n {
                out[i] = out[i - 1] + 0.5 * h * (y[i - 1] + y[i]);
            }
        }
        Rule::Simpson => {
            if n < 3 {
                for i in 1..n {
                    out[i] = out[i - 1] + 0.5 * h * (y[i - 1] + y[i]);
                }
                return;
            }
            for i in 1..n {
                if i % 2 == 0 {
                    out[i] = out[i - 2] + h / 3.0 * (y[i - 2] + 4.0 * y[i - 1] + y[i]);
                } else if i + 1 < n {
                    // ∫ over [x_{i-1}, x_i] of the parabola through i-1, i, i+1.
                    out[i] = out[i - 1] + h / 12.0 * (5.0 * y[i - 1] + 8.0 * y[i] - y[i + 1]);
                } else {
                    // Last interval: the parabola through i-2, i-1, i.
                    out[i] = out[i - 1] + h / 12.0 * (-y[i - 2] + 8.0 * y[i - 1] + 5.0 * y[i]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn periodic_rules_exact_on_trig() {
        let n = 64;
        let h = TAU / n as f64;
        let y: Vec<f64> = (0..n).map(|k| (k as f64 * h).cos().powi(2)).collect();
        for r in [Rule::Trapezoid, Rule::Simpson] {
            assert!((periodic_integral(r, &y, h) - TAU / 2.0).abs() < 1e-12);
            assert!((periodic_mean(r, &y) - 0.5).abs() < 1e-12);
        }
    }

    /// Simpson is exact for cubics at even indices; trapezoid errs by h² f''/12 per unit length.
    #[test]
    fn cumulative_orders() {
        let h = 0.1;
        let y: Vec<f64> = (0..21).map(|k| (k as f64 * h).powi(3)).collect();
        let mut out = vec![0.0; 21];
        cumulative(Rule::Simpson, &y, h, &mut out);
        for i in (0..21).step_by(2) {
            let x = i as f64 * h;
            assert!((out[i] - x.powi(4) / 4.0).abs() < 1e-12, "{i}");
        }
        // Quadratic pieces are exact for quadratics at odd indices too.
        let y: Vec<f64> = (0..21).map(|k| (k as f64 * h).powi(2)).collect();
        cumulative(Rule::Simpson, &y, h, &mut out);
        for (i, v) in out.iter().enumerate() {
            assert!((v - (i as f64 * h).powi(3) / 3.0).abs() < 1e-12, "{i}");
        }
        let err = |n: usize, r: Rule| {
            let h = 1.0 / n as f64;
            let y: Vec<f64> = (0..=n).map(|k| (k as f64 * h).sin()).collect();
            let mut out = vec![0.0; n + 1];
            cumulative(r, &y, h, &mut out);
            (0..=n)
                .map(|i| (out[i] - (1.0 - (i as f64 * h).cos())).abs())
                .fold(0.0, f64::max)
        };
        let t = (err(20, Rule::Trapezoid) / err(40, Rule::Trapezoid)).log2();
        let s = (err(20, Rule::Simpson) / err(40, Rule::Simpson)).log2();
        assert!((1.8..2.2).contains(&t), "trapezoid order {t}");
        assert!(s > 2.8, "simpson order {s}");
    }
}
