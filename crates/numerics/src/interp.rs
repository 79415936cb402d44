//! Periodic interpolation through samples of one period.
//!
//! | kind | continuity | overshoot | cost |
//! | --- | --- | --- | --- |
//! | `Linear` | C0 | none | cheapest; error `h^2 f''/8` |
//! | `Spline` | C2 | can ring next to a sharp peak | error `~h^4 f''''/384` |
//! | `Pchip` | C1 | none (monotone between samples) | error `~h^3` |

use crate::NumericsError;

/// Interpolation method (all periodic).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InterpKind {
    /// Periodic piecewise linear.
    Linear,
    /// Periodic cubic spline (C2, periodic end conditions).
    Spline,
    /// Periodic monotone cubic Hermite (Fritsch–Carlson).
    Pchip,
}

impl InterpKind {
    /// The name used on the command line and in `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            InterpKind::Linear => "linear",
            InterpKind::Spline => "spline",
            InterpKind::Pchip => "pchip",
        }
    }
}

/// A periodic interpolant. Knots `xs` rise strictly within one period; the
/// last interval wraps from `xs[n-1]` to `xs[0] + period`. Each interval holds
/// a cubic Hermite segment (value and slope at both ends).
#[derive(Debug, Clone, PartialEq)]
pub struct Periodic {
    kind: InterpKind,
    xs: Vec<f64>,
    ys: Vec<f64>,
    /// Slope at each knot.
    d: Vec<f64>,
    period: f64,
}

impl Periodic {
    /// Builds the interpolant; errors on mismatched, too few, non-finite or
    /// non-rising samples, or a span not shorter than a positive period.
    pub fn new(
        kind: InterpKind,
        xs: &[f64],
        ys: &[f64],
        period: f64,
    ) -> Result<Periodic, NumericsError> {
        let n = xs.len();
        if n != ys.len() {
            return Err(NumericsError::LengthMismatch {
                xs: n,
                ys: ys.len(),
            });
        }
        let need = if kind == InterpKind::Linear { 2 } else { 3 };
        if n < need {
            return Err(NumericsError::TooFewPoints {
                got: n,
                need,
                method: kind.name(),
            });
        }
        for (index, &value) in xs.iter().chain(ys).enumerate() {
            if !value.is_finite() {
                return Err(NumericsError::NonFinite {
                    index: index % n,
                    value,
                });
            }
        }
        for i in 1..n {
            if xs[i] <= xs[i - 1] {
                return Err(NumericsError::NotIncreasing {
                    index: i,
                    value: xs[i],
                    previous: xs[i - 1],
                });
            }
        }
        let span = xs[n - 1] - xs[0];
        if !(period.is_finite() && period > 0.0 && span < period) {
            return Err(NumericsError::Period { span, period });
        }
        let h: Vec<f64> = (0..n)
            .map(|i| {
                if i + 1 < n {
                    xs[i + 1] - xs[i]
                } else {
                    xs[0] + period - xs[n - 1]
                }
            })
            .collect();
        let delta: Vec<f64> = (0..n).map(|i| (ys[(i + 1) % n] - ys[i]) / h[i]).collect();
        let d = match kind {
            InterpKind::Linear => vec![0.0; n],
            InterpKind::Spline => spline_slopes(&h, &delta),
            InterpKind::Pchip => pchip_slopes(&h, &delta),
        };
        Ok(Periodic {
            kind,
            xs: xs.to_vec(),
            ys: ys.to_vec(),
            d,
            period,
        })
    }

    /// The method.
    pub fn kind(&self) -> InterpKind {
        self.kind
    }

    fn interval_len(&self, i: usize) -> f64 {
        let n = self.xs.len();
        if i + 1 < n {
            self.xs[i + 1] - self.xs[i]
        } else {
            self.xs[0] + self.period - self.xs[n - 1]
        }
    }

    /// Value on interval `i` at offset `t` (0 ≤ t ≤ h) from its left knot.
    #[inline]
    fn segment(&self, i: usize, t: f64) -> f64 {
        let n = self.xs.len();
        let j = (i + 1) % n;
        let h = self.interval_len(i);
        let (y0, y1) = (self.ys[i], self.ys[j]);
        if self.kind == InterpKind::Linear {
            return y0 + (y1 - y0) * t / h;
        }
        let s = t / h;
        let (h00, h10, h01, h11) = (
            (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s),
            s * (1.0 - s) * (1.0 - s),
            s * s * (3.0 - 2.0 * s),
            s * s * (s - 1.0),
        );
        h00 * y0 + h10 * h * self.d[i] + h01 * y1 + h11 * h * self.d[j]
    }

    /// Wraps `x` into `[xs[0], xs[0] + period)`.
    fn wrap(&self, x: f64) -> f64 {
        let x0 = self.xs[0];
        x0 + (x - x0).rem_euclid(self.period)
    }

    /// Value at any `x` (wrapped into the period); binary search for the interval.
    pub fn eval(&self, x: f64) -> f64 {
        let x = self.wrap(x);
        let i = self.xs.partition_point(|&k| k <= x).saturating_sub(1);
        self.segment(i, x - self.xs[i])
    }

    /// Fills `out[k] = f(start + k * step)`, walking the intervals with a
    /// moving index: O(n + m), no search per point, no allocation.
    pub fn eval_uniform(&self, start: f64, step: f64, out: &mut [f64]) {
        let n = self.xs.len();
        let x0 = self.xs[0];
        let first = self.wrap(start);
        let mut i = self.xs.partition_point(|&k| k <= first).saturating_sub(1);
        // Position relative to x0, growing without wrapping; `base` counts periods.
        let mut base = 0.0;
        for (k, o) in out.iter_mut().enumerate() {
            let x = (first - x0) + step * k as f64;
            // Advance while x lies beyond the current interval's right end.
            loop {
                let left = base + self.xs[i] - x0;
                let right = left + self.interval_len(i);
                if x < right || !right.is_finite() {
                    *o = self.segment(i, (x - left).max(0.0));
                    break;
                }
                i += 1;
                if i == n {
                    i = 0;
                    base += self.period;
                }
            }
        }
    }

    /// Largest amount by which the interpolant leaves the local data range
    /// `[min(y_i, y_i+1), max(y_i, y_i+1)]` inside any interval, from the
    /// cubic's stationary points (0 for linear; 0 for pchip by construction).
    pub fn max_overshoot(&self) -> f64 {
        if self.kind == InterpKind::Linear {
            return 0.0;
        }
        let n = self.xs.len();
        let mut worst = 0.0_f64;
        for i in 0..n {
            let j = (i + 1) % n;
            let h = self.interval_len(i);
            let (y0, y1) = (self.ys[i], self.ys[j]);
            let (m0, m1) = (self.d[i] * h, self.d[j] * h);
            // p(s) = a s^3 + b s^2 + c s + y0 on s in [0, 1].
            let a = 2.0 * y0 + m0 - 2.0 * y1 + m1;
            let b = -3.0 * y0 - 2.0 * m0 + 3.0 * y1 - m1;
            let c = m0;
            let (lo, hi) = (y0.min(y1), y0.max(y1));
            let mut check = |s: f64| {
                if s > 0.0 && s < 1.0 {
                    let v = self.segment(i, s * h);
                    worst = worst.max(v - hi).max(lo - v);
                }
            };
            // p'(s) = 3a s^2 + 2b s + c = 0.
            let qa = 3.0 * a;
            let qb = 2.0 * b;
            if qa.abs() < 1e-300 {
                if qb.abs() > 1e-300 {
                    check(-c / qb);
                }
            } else {
                let disc = qb * qb - 4.0 * qa * c;
                if disc >= 0.0 {
                    let r = disc.sqrt();
                    check((-qb + r) / (2.0 * qa));
                    check((-qb - r) / (2.0 * qa));
                }
            }
        }
        worst
    }
}

/// Slopes of the periodic C2 cubic spline: the cyclic tridiagonal system
/// `h_i d_{i-1} + 2 (h_{i-1} + h_i) d_i + h_{i-1} d_{i+1} = 3 (h_i δ_{i-1} + h_{i-1} δ_i)`,
/// solved in O(n) by the Thomas algorithm with a Sherman–Morrison correction.
fn spline_slopes(h: &[f64], delta: &[f64]) -> Vec<f64> {
    let n = h.len();
    let prev = |i: usize| (i + n - 1) % n;
    // Row i: sub a_i (coefficient of d_{i-1}), diag b_i, super c_i (of d_{i+1}).
    let a: Vec<f64> = (0..n).map(|i| h[i]).collect();
    let b: Vec<f64> = (0..n).map(|i| 2.0 * (h[prev(i)] + h[i])).collect();
    let c: Vec<f64> = (0..n).map(|i| h[prev(i)]).collect();
    let r: Vec<f64> = (0..n)
        .map(|i| 3.0 * (h[i] * delta[prev(i)] + h[prev(i)] * delta[i]))
        .collect();
    if n == 3 {
        // Dense 3×3 solve (the cyclic corners coincide with the band).
        let mut m = [[0.0; 4]; 3];
        for i in 0..3 {
            m[i][i] += b[i];
            m[i][prev(i)] += a[i];
            m[i][(i + 1) % 3] += c[i];
            m[i][3] = r[i];
        }
        return gauss3(m);
    }
    // Sherman–Morrison: A = T + u v^T with corners a_0 (row 0, col n-1) and c_{n-1} (row n-1, col 0).
    let gamma = -b[0];
    let mut bb = b.clone();
    bb[0] -= gamma;
    bb[n - 1] -= c[n - 1] * a[0] / gamma;
    let x = thomas(&a, &bb, &c, &r);
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = c[n - 1];
    let z = thomas(&a, &bb, &c, &u);
    let fact = (x[0] + a[0] * x[n - 1] / gamma) / (1.0 + z[0] + a[0] * z[n - 1] / gamma);
    x.iter().zip(&z).map(|(x, z)| x - fact * z).collect()
}

fn gauss3(mut m: [[f64; 4]; 3]) -> Vec<f64> {
    for col in 0..3 {
        let piv = (col..3)
            .max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))
            .unwrap_or(col);
        m.swap(col, piv);
        let pivot_row = m[col];
        for (row, r) in m.iter_mut().enumerate() {
            if row != col {
                let f = r[col] / pivot_row[col];
                for (x, p) in r.iter_mut().zip(pivot_row).skip(col) {
                    *x -= f * p;
                }
            }
        }
    }
    (0..3).map(|i| m[i][3] / m[i][i]).collect()
}

/// Tridiagonal solve; `a[i]` multiplies x[i-1] (a[0] unused), `c[i]` x[i+1].
fn thomas(a: &[f64], b: &[f64], c: &[f64], r: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut cp = vec![0.0; n];
    let mut dp = vec![0.0; n];
    cp[0] = c[0] / b[0];
    dp[0] = r[0] / b[0];
    for i in 1..n {
        let m = b[i] - a[i] * cp[i - 1];
        cp[i] = c[i] / m;
        dp[i] = (r[i] - a[i] * dp[i - 1]) / m;
    }
    let mut x = vec![0.0; n];
    x[n - 1] = dp[n - 1];
    for i in (0..n - 1).rev() {
        x[i] = dp[i] - cp[i] * x[i + 1];
    }
    x
}

/// Fritsch–Carlson slopes: weighted harmonic mean of neighbouring secants,
/// zero at local extrema, so each interval stays within its end values.
fn pchip_slopes(h: &[f64], delta: &[f64]) -> Vec<f64> {
    let n = h.len();
    (0..n)
        .map(|i| {
            let p = (i + n - 1) % n;
            let (d0, d1) = (delta[p], delta[i]);
            if d0 * d1 <= 0.0 {
                0.0
            } else {
                let (h0, h1) = (h[p], h[i]);
                let w1 = 2.0 * h1 + h0;
                let w2 = h1 + 2.0 * h0;
                (w1 + w2) / (w1 / d0 + w2 / d1)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn linear_exact_and_wraps() {
        let f = Periodic::new(InterpKind::Linear, &[0.0, 1.0, 3.0], &[0.0, 2.0, 6.0], 4.0).unwrap();
        assert!((f.eval(0.5) - 1.0).abs() < 1e-15);
        assert!((f.eval(2.0) - 4.0).abs() < 1e-15);
        // Wrap interval 3 → 4(=0): from 6 down to 0.
        assert!((f.eval(3.5) - 3.0).abs() < 1e-15);
        assert!((f.eval(-0.5) - 3.0).abs() < 1e-15);
        assert!((f.eval(7.5) - 3.0).abs() < 1e-15);
    }

    fn uneven(n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| (k as f64 + 0.3 * ((k * 7 % 5) as f64 / 5.0 - 0.4)) * TAU / n as f64)
            .collect()
    }

    /// Periodic spline error falls as h^4 (order between 3.5 and 4.5) on sin.
    #[test]
    fn spline_converges_at_fourth_order() {
        let err = |n: usize| {
            let xs = uneven(n);
            let ys: Vec<f64> = xs.iter().map(|x| x.sin()).collect();
            let f = Periodic::new(InterpKind::Spline, &xs, &ys, TAU).unwrap();
            (0..1000)
                .map(|k| {
                    let x = k as f64 * TAU / 1000.0;
                    (f.eval(x) - x.sin()).abs()
                })
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (err(16), err(32));
        let order = (e1 / e2).log2();
        assert!(e1 < 2e-4, "{e1}");
        assert!((3.5..4.5).contains(&order), "order {order}");
    }

    /// C2 at every knot, the wrap knot included (one-sided differences, 1e-5 relative).
    #[test]
    fn spline_is_c2() {
        let xs = uneven(12);
        let ys: Vec<f64> = xs.iter().map(|x| (2.0 * x).cos() + x.sin()).collect();
        let f = Periodic::new(InterpKind::Spline, &xs, &ys, TAU).unwrap();
        let e = 1e-4;
        for &x in &xs {
            let d_l = (f.eval(x) - f.eval(x - e)) / e;
            let d_r = (f.eval(x + e) - f.eval(x)) / e;
            assert!((d_l - d_r).abs() < 1e-3, "slope jump at {x}");
            let dd_l = (f.eval(x) - 2.0 * f.eval(x - e) + f.eval(x - 2.0 * e)) / (e * e);
            let dd_r = (f.eval(x + 2.0 * e) - 2.0 * f.eval(x + e) + f.eval(x)) / (e * e);
            assert!(
                (dd_l - dd_r).abs() < 2e-2 * (1.0 + dd_l.abs()),
                "curvature jump at {x}"
            );
        }
    }

    fn step() -> (Vec<f64>, Vec<f64>) {
        let xs: Vec<f64> = (0..12).map(|k| k as f64).collect();
        let ys: Vec<f64> = (0..12)
            .map(|k| if (3..8).contains(&k) { 1.0 } else { 0.0 })
            .collect();
        (xs, ys)
    }

    /// Pchip never leaves [0, 1] on a step; the spline does, and its
    /// analytic overshoot matches a dense scan.
    #[test]
    fn pchip_no_overshoot_spline_overshoot_measured() {
        let (xs, ys) = step();
        let p = Periodic::new(InterpKind::Pchip, &xs, &ys, 12.0).unwrap();
        let s = Periodic::new(InterpKind::Spline, &xs, &ys, 12.0).unwrap();
        let mut scan = 0.0_f64;
        for k in 0..120_000 {
            let x = k as f64 * 1e-4;
            let v = p.eval(x);
            assert!((-1e-15..=1.0 + 1e-15).contains(&v), "pchip {v} at {x}");
            let i = x.floor() as usize % 12;
            let (lo, hi) = (ys[i].min(ys[(i + 1) % 12]), ys[i].max(ys[(i + 1) % 12]));
            let w = s.eval(x);
            scan = scan.max(w - hi).max(lo - w);
        }
        assert!(p.max_overshoot() < 1e-12);
        assert!(s.max_overshoot() > 0.05);
        assert!(
            (s.max_overshoot() - scan).abs() < 1e-6,
            "{} vs {scan}",
            s.max_overshoot()
        );
    }

    /// Monotone data stays monotone under pchip; linear data is reproduced.
    #[test]
    fn pchip_monotone_and_linear() {
        let xs: Vec<f64> = (0..10).map(|k| k as f64 * k as f64 * 0.1).collect();
        let ys: Vec<f64> = xs.iter().map(|x| x.powi(3)).collect();
        let f = Periodic::new(InterpKind::Pchip, &xs, &ys, 20.0).unwrap();
        let mut last = f64::NEG_INFINITY;
        for k in 0..=810 {
            let v = f.eval(k as f64 * 0.01);
            assert!(v >= last - 1e-12);
            last = v;
        }
        let ys: Vec<f64> = xs.iter().map(|x| 2.0 * x + 1.0).collect();
        let f = Periodic::new(InterpKind::Pchip, &xs, &ys, 20.0).unwrap();
        assert!((f.eval(3.3) - 7.6).abs() < 1e-12);
    }

    #[test]
    fn eval_uniform_matches_eval() {
        let xs = uneven(9);
        let ys: Vec<f64> = xs.iter().map(|x| x.cos() * 3.0 + 1.0).collect();
        for kind in [InterpKind::Linear, InterpKind::Spline, InterpKind::Pchip] {
            let f = Periodic::new(kind, &xs, &ys, TAU).unwrap();
            for start in [-7.3, 0.0, 0.01, 5.9] {
                let mut out = vec![0.0; 500];
                f.eval_uniform(start, 0.0917, &mut out);
                for (k, v) in out.iter().enumerate() {
                    let w = f.eval(start + 0.0917 * k as f64);
                    assert!((v - w).abs() < 1e-12, "{kind:?} {start} {k}: {v} vs {w}");
                }
            }
        }
    }

    #[test]
    fn errors() {
        use NumericsError as E;
        let k = InterpKind::Spline;
        assert!(matches!(
            Periodic::new(k, &[0.0, 1.0], &[1.0], 4.0),
            Err(E::LengthMismatch { .. })
        ));
        assert!(matches!(
            Periodic::new(k, &[0.0, 1.0], &[1.0, 2.0], 4.0),
            Err(E::TooFewPoints { .. })
        ));
        assert!(matches!(
            Periodic::new(k, &[0.0, 1.0, 2.0], &[1.0, f64::NAN, 2.0], 4.0),
            Err(E::NonFinite { .. })
        ));
        assert!(matches!(
            Periodic::new(k, &[0.0, 2.0, 1.0], &[1.0, 1.0, 2.0], 4.0),
            Err(E::NotIncreasing { .. })
        ));
        assert!(matches!(
            Periodic::new(k, &[0.0, 1.0, 4.0], &[1.0, 1.0, 2.0], 4.0),
            Err(E::Period { .. })
        ));
        assert!(matches!(
            Periodic::new(k, &[0.0, 1.0, 2.0], &[1.0, 1.0, 2.0], -1.0),
            Err(E::Period { .. })
        ));
    }
}
