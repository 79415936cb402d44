//! Periodic interpolation through samples of one period.
//!
//! | kind | continuity | overshoot | error on smooth data |
//! | --- | --- | --- | --- |
//! | [`Linear`](InterpKind::Linear) | C0 | none | `h² max|f''| / 8` |
//! | [`Spline`](InterpKind::Spline) | C2 | can ring next to a sharp step | `5 h⁴ max|f''''| / 384` |
//! | [`Pchip`](InterpKind::Pchip) | C1 | none (monotone between samples) | `O(h³)` |
//!
//! Every kind stores one cubic per interval (linear: a cubic with zero
//! quadratic and cubic terms) in powers of the offset from the interval's
//! left knot, so evaluation is a search for the interval and a Horner step.

use crate::NumericsError;

/// Interpolation method (all periodic).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InterpKind {
    /// Periodic piecewise linear.
    Linear,
    /// Periodic cubic spline: C2, periodic end conditions.
    Spline,
    /// Periodic monotone piecewise cubic Hermite (pchip): slopes are the
    /// weighted harmonic mean of the neighbouring secants, zero at local
    /// extrema, which keeps every interval within the Fritsch–Carlson
    /// monotonicity region.
    Pchip,
}

impl InterpKind {
    /// The name used on the command line and in reports:
    /// `"linear"`, `"spline"` or `"pchip"`.
    pub fn name(self) -> &'static str {
        match self {
            InterpKind::Linear => "linear",
            InterpKind::Spline => "spline",
            InterpKind::Pchip => "pchip",
        }
    }

    /// Fewest samples the method accepts.
    fn min_points(self) -> usize {
        match self {
            InterpKind::Linear => 2,
            InterpKind::Spline | InterpKind::Pchip => 3,
        }
    }
}

/// A periodic interpolant through samples (knots strictly increasing, all
/// within one period: `xs[last] - xs[0] < period`).
///
/// The segment from `xs[last]` wraps to `xs[0] + period`, where the
/// interpolant takes the value `ys[0]` again. Evaluation at any `x` first
/// wraps `x` into `[xs[0], xs[0] + period)`.
///
/// ```
/// use enginedyn_numerics::{InterpKind, Periodic};
/// // A triangle wave of period 4: 0 at x = 0, 2 at x = 2, back to 0 at x = 4.
/// let f = Periodic::new(InterpKind::Linear, &[0.0, 2.0], &[0.0, 2.0], 4.0)?;
/// assert!((f.eval(3.0) - 1.0).abs() < 1e-15); // on the wrap interval
/// assert!((f.eval(-1.0) - 1.0).abs() < 1e-15); // the same point one period back
/// # Ok::<(), enginedyn_numerics::NumericsError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Periodic {
    kind: InterpKind,
    /// First knot: the origin of the offsets below.
    x0: f64,
    period: f64,
    /// Knot offsets from `x0` (`t[0] = 0`), strictly increasing, `< period`.
    t: Vec<f64>,
    /// Per interval `i`: `[c0, c1, c2, c3]` with
    /// `p(s) = c0 + s (c1 + s (c2 + s c3))`, `s` the offset from knot `i`.
    coef: Vec<[f64; 4]>,
}

impl Periodic {
    /// Builds the interpolant of `kind` through `(xs[i], ys[i])`, periodic
    /// with `period`.
    ///
    /// # Errors
    ///
    /// [`NumericsError::LengthMismatch`] if `xs` and `ys` differ in length,
    /// [`NumericsError::TooFewPoints`] below 3 points (2 for linear),
    /// [`NumericsError::NonFinite`] for a NaN or infinite sample,
    /// [`NumericsError::NotIncreasing`] if `xs` does not rise strictly, and
    /// [`NumericsError::Period`] if the period is not positive and finite or
    /// the samples span a period or more.
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
        let need = kind.min_points();
        if n < need {
            return Err(NumericsError::TooFewPoints {
                got: n,
                need,
                method: kind.name(),
            });
        }
        check_finite("x", xs)?;
        check_finite("y", ys)?;
        for i in 1..n {
            if !(xs[i] > xs[i - 1]) {
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
        let x0 = xs[0];
        let t: Vec<f64> = xs.iter().map(|x| x - x0).collect();
        // Offsets can round together when |x0| dwarfs the spacing.
        for i in 1..n {
            if !(t[i] > t[i - 1]) {
                return Err(NumericsError::NotIncreasing {
                    index: i,
                    value: xs[i],
                    previous: xs[i - 1],
                });
            }
        }
        let h: Vec<f64> = (0..n)
            .map(|i| if i + 1 < n { t[i + 1] } else { period } - t[i])
            .collect();
        let delta: Vec<f64> = (0..n).map(|i| (ys[(i + 1) % n] - ys[i]) / h[i]).collect();
        let coef = match kind {
            InterpKind::Linear => (0..n).map(|i| [ys[i], delta[i], 0.0, 0.0]).collect(),
            InterpKind::Spline => hermite(ys, &h, &delta, &spline_slopes(&h, &delta)),
            InterpKind::Pchip => hermite(ys, &h, &delta, &pchip_slopes(&h, &delta)),
        };
        Ok(Periodic {
            kind,
            x0,
            period,
            t,
            coef,
        })
    }

    /// The method.
    pub fn kind(&self) -> InterpKind {
        self.kind
    }

    /// The period.
    pub fn period(&self) -> f64 {
        self.period
    }

    /// Number of knots (equal to the number of intervals, the wrap interval
    /// included).
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Always `false`: an interpolant has at least two knots.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Length of interval `i` (the last one wraps to the first knot).
    #[inline]
    fn interval_len(&self, i: usize) -> f64 {
        let next = self.t.get(i + 1).copied().unwrap_or(self.period);
        next - self.t[i]
    }

    /// Value on interval `i` at offset `s` from its left knot.
    #[inline]
    fn segment(&self, i: usize, s: f64) -> f64 {
        let [c0, c1, c2, c3] = self.coef[i];
        c0 + s * (c1 + s * (c2 + s * c3))
    }

    /// First and second derivative on interval `i` at offset `s`.
    #[cfg(test)]
    fn segment_derivatives(&self, i: usize, s: f64) -> (f64, f64) {
        let [_, c1, c2, c3] = self.coef[i];
        (c1 + s * (2.0 * c2 + 3.0 * s * c3), 2.0 * c2 + 6.0 * s * c3)
    }

    /// Offset of `x` from the first knot, wrapped into `[0, period)`
    /// (NaN for a non-finite `x`). Both evaluators go through here, so they
    /// agree to the bit.
    #[inline]
    fn offset(&self, x: f64) -> f64 {
        let u = x - self.x0;
        if u >= 0.0 && u < self.period {
            return u;
        }
        let mut u = u % self.period;
        if u < 0.0 {
            u += self.period;
        }
        // `u + period` may round up to the period itself.
        if u >= self.period {
            u -= self.period;
        }
        u
    }

    /// The interval holding offset `u`: the last knot at or before it.
    #[inline]
    fn locate(&self, u: f64) -> usize {
        self.t.partition_point(|&k| k <= u).saturating_sub(1)
    }

    /// Value at any `x`, wrapped into the period; the interval is found by
    /// binary search (O(log n)). A non-finite `x` gives NaN.
    pub fn eval(&self, x: f64) -> f64 {
        let u = self.offset(x);
        let i = self.locate(u);
        self.segment(i, u - self.t[i])
    }

    /// Fills `out[i] = f(start + i * step)` for `i` in `0..out.len()`: a
    /// uniform grid, evaluated with a moving interval index.
    ///
    /// Each point steps the index forward (or back) from the previous
    /// point's interval, so a grid finer than the knots costs O(n + m)
    /// with no search per point and no allocation; only a wrap past the
    /// period, or a step that skips many knots at once, falls back to a
    /// binary search. Results equal [`eval`](Self::eval) at the same points
    /// exactly. Any finite `step` works, negative or wider than the period.
    pub fn eval_uniform(&self, start: f64, step: f64, out: &mut [f64]) {
        /// Knots walked before a binary search is cheaper.
        const WALK: usize = 8;
        let n = self.t.len();
        let mut i = 0;
        for (k, o) in out.iter_mut().enumerate() {
            let u = self.offset(start + step * k as f64);
            let mut walked = 0;
            if u >= self.t[i] {
                while i + 1 < n && self.t[i + 1] <= u {
                    i += 1;
                    walked += 1;
                    if walked == WALK {
                        i = self.locate(u);
                        break;
                    }
                }
            } else if u >= 0.0 {
                while self.t[i] > u {
                    i -= 1; // t[0] = 0 <= u stops the walk
                    walked += 1;
                    if walked == WALK {
                        i = self.locate(u);
                        break;
                    }
                }
            }
            // A NaN offset matches neither branch and evaluates to NaN.
            *o = self.segment(i, u - self.t[i]);
        }
    }

    /// Largest amount by which the interpolant leaves the local data range
    /// `[min(y_i, y_{i+1}), max(y_i, y_{i+1})]` inside any interval (the wrap
    /// interval included), found analytically from each cubic's stationary
    /// points. Zero for linear; zero up to rounding (≲ 1e-15 of the data
    /// scale) for pchip, which stays within the range by construction.
    pub fn max_overshoot(&self) -> f64 {
        if self.kind == InterpKind::Linear {
            return 0.0;
        }
        let n = self.t.len();
        let mut worst = 0.0_f64;
        for i in 0..n {
            let h = self.interval_len(i);
            let [y0, c1, c2, c3] = self.coef[i];
            let y1 = self.coef[(i + 1) % n][0];
            let (lo, hi) = (y0.min(y1), y0.max(y1));
            let mut check = |s: f64| {
                if s > 0.0 && s < h {
                    let v = self.segment(i, s);
                    worst = worst.max(v - hi).max(lo - v);
                }
            };
            // p'(s) = a s² + b s + c.
            let (a, b, c) = (3.0 * c3, 2.0 * c2, c1);
            if a == 0.0 {
                if b != 0.0 {
                    check(-c / b);
                }
                continue;
            }
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                continue;
            }
            // Cancellation-free roots: q / a and c / q.
            let q = -0.5 * (b + disc.sqrt().copysign(b));
            check(q / a);
            if q != 0.0 {
                check(c / q);
            }
        }
        worst
    }
}

fn check_finite(what: &'static str, v: &[f64]) -> Result<(), NumericsError> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(NumericsError::NonFinite {
            what,
            index,
            value: v[index],
        }),
        None => Ok(()),
    }
}

/// Power-form coefficients of the cubic Hermite segments with knot values
/// `y`, interval lengths `h`, secants `delta` and knot slopes `d`.
fn hermite(y: &[f64], h: &[f64], delta: &[f64], d: &[f64]) -> Vec<[f64; 4]> {
    let n = y.len();
    (0..n)
        .map(|i| {
            let (d0, d1) = (d[i], d[(i + 1) % n]);
            [
                y[i],
                d0,
                (3.0 * delta[i] - 2.0 * d0 - d1) / h[i],
                (d0 + d1 - 2.0 * delta[i]) / (h[i] * h[i]),
            ]
        })
        .collect()
}

/// Knot slopes of the periodic C2 cubic spline. Continuity of the second
/// derivative at knot `i` (intervals `h_{i-1}` before it, `h_i` after) gives
/// the cyclic tridiagonal system
/// `h_i d_{i-1} + 2 (h_{i-1} + h_i) d_i + h_{i-1} d_{i+1} = 3 (h_i δ_{i-1} + h_{i-1} δ_i)`,
/// strictly diagonally dominant for any positive `h`.
fn spline_slopes(h: &[f64], delta: &[f64]) -> Vec<f64> {
    let n = h.len();
    let prev = |i: usize| (i + n - 1) % n;
    let sub: Vec<f64> = h.to_vec();
    let diag: Vec<f64> = (0..n).map(|i| 2.0 * (h[prev(i)] + h[i])).collect();
    let sup: Vec<f64> = (0..n).map(|i| h[prev(i)]).collect();
    let rhs: Vec<f64> = (0..n)
        .map(|i| 3.0 * (h[i] * delta[prev(i)] + h[prev(i)] * delta[i]))
        .collect();
    solve_cyclic(&sub, &diag, &sup, &rhs)
}

/// Solves the cyclic tridiagonal system
/// `sub[i] x[i-1] + diag[i] x[i] + sup[i] x[i+1] = rhs[i]` (indices mod n,
/// n ≥ 3) in O(n): the Thomas algorithm on the system with its two corner
/// entries removed, corrected by Sherman–Morrison.
fn solve_cyclic(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[f64]) -> Vec<f64> {
    let n = diag.len();
    // Corners: row 0, column n-1 holds sub[0]; row n-1, column 0 holds sup[n-1].
    let (top, bottom) = (sub[0], sup[n - 1]);
    // A = T + u vᵀ with u = (γ, 0, …, 0, bottom), v = (1, 0, …, 0, top / γ).
    let gamma = -diag[0];
    let mut t_diag = diag.to_vec();
    t_diag[0] -= gamma;
    t_diag[n - 1] -= bottom * top / gamma;
    let x = thomas(sub, &t_diag, sup, rhs);
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = bottom;
    let z = thomas(sub, &t_diag, sup, &u);
    let fact = (x[0] + top * x[n - 1] / gamma) / (1.0 + z[0] + top * z[n - 1] / gamma);
    x.iter().zip(&z).map(|(x, z)| x - fact * z).collect()
}

/// Tridiagonal solve; `sub[i]` multiplies `x[i-1]` (`sub[0]` unused),
/// `sup[i]` multiplies `x[i+1]` (`sup[n-1]` unused).
fn thomas(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[f64]) -> Vec<f64> {
    let n = diag.len();
    let mut cp = vec![0.0; n];
    let mut x = vec![0.0; n];
    cp[0] = sup[0] / diag[0];
    x[0] = rhs[0] / diag[0];
    for i in 1..n {
        let m = diag[i] - sub[i] * cp[i - 1];
        cp[i] = sup[i] / m;
        x[i] = (rhs[i] - sub[i] * x[i - 1]) / m;
    }
    for i in (0..n - 1).rev() {
        x[i] -= cp[i] * x[i + 1];
    }
    x
}

/// Pchip knot slopes (Fritsch–Butland weighted harmonic mean of the
/// neighbouring secants, as in MATLAB's and SciPy's pchip), zero where the
/// secants change sign or either is zero. With `α = d_i / δ_i` and
/// `β = d_{i+1} / δ_i` this gives `0 ≤ α, β ≤ 3` on every interval: inside
/// the Fritsch–Carlson monotonicity region, so no limiting pass is needed
/// and each interval stays within its end values.
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
                let w0 = 2.0 * h1 + h0;
                let w1 = h1 + 2.0 * h0;
                (w0 + w1) / (w0 / d0 + w1 / d1)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    const KINDS: [InterpKind; 3] = [InterpKind::Linear, InterpKind::Spline, InterpKind::Pchip];

    #[test]
    fn names() {
        let names: Vec<&str> = KINDS.iter().map(|k| k.name()).collect();
        assert_eq!(names, ["linear", "spline", "pchip"]);
    }

    /// Expected values are the hand-computed piecewise-linear interpolant.
    #[test]
    fn linear_exact_and_wraps() {
        let f = Periodic::new(InterpKind::Linear, &[0.0, 1.0, 3.0], &[0.0, 2.0, 6.0], 4.0).unwrap();
        assert_eq!(f.kind(), InterpKind::Linear);
        assert_eq!(f.len(), 3);
        // Inside: the line y = 2x on [0, 3].
        for x in [0.0, 0.25, 0.5, 1.0, 1.7, 2.0, 2.9] {
            assert!((f.eval(x) - 2.0 * x).abs() < 1e-15, "{x}");
        }
        // Wrap interval 3 → 4 (≡ 0): from 6 down to 0, i.e. 6 - 6 (x - 3).
        for x in [3.0, 3.25, 3.5, 3.99] {
            let want = 6.0 - 6.0 * (x - 3.0);
            assert!((f.eval(x) - want).abs() < 1e-14, "{x}");
            assert!((f.eval(x - 4.0) - want).abs() < 1e-14, "{x} - 4");
            assert!((f.eval(x + 8.0) - want).abs() < 1e-14, "{x} + 8");
        }
        assert!(f.eval(4.0).abs() < 1e-15);
        // Two points are enough for linear: a triangle wave.
        let g = Periodic::new(InterpKind::Linear, &[1.0, 2.0], &[0.0, 1.0], 2.0).unwrap();
        assert!((g.eval(2.5) - 0.5).abs() < 1e-15);
        assert!((g.eval(0.5) - 0.5).abs() < 1e-15);
    }

    /// Knots jittered off a uniform grid of `n` over [0, 2π): up to ±12 % of a spacing.
    fn uneven(n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| (k as f64 + 0.3 * ((k * 7 % 5) as f64 / 5.0 - 0.4)) * TAU / n as f64)
            .collect()
    }

    fn max_spacing(xs: &[f64], period: f64) -> f64 {
        let n = xs.len();
        (0..n)
            .map(|i| if i + 1 < n { xs[i + 1] } else { xs[0] + period } - xs[i])
            .fold(0.0, f64::max)
    }

    fn sin_spline_error(n: usize) -> (f64, f64) {
        let xs = uneven(n);
        let ys: Vec<f64> = xs.iter().map(|x| x.sin()).collect();
        let f = Periodic::new(InterpKind::Spline, &xs, &ys, TAU).unwrap();
        let err = (0..4000)
            .map(|k| {
                let x = k as f64 * TAU / 4000.0;
                (f.eval(x) - x.sin()).abs()
            })
            .fold(0.0, f64::max);
        (err, max_spacing(&xs, TAU))
    }

    /// The periodic cubic spline error is at most `5/384 h⁴ max|f''''|`
    /// (Hall & Meyer 1976; `max|sin''''| = 1`), and halving the spacing cuts
    /// it ~16x: observed order between 3.5 and 4.5.
    #[test]
    fn spline_error_bound_and_fourth_order() {
        let (e16, h16) = sin_spline_error(16);
        let (e32, _) = sin_spline_error(32);
        let (e64, _) = sin_spline_error(64);
        assert!(e16 < 5.0 / 384.0 * h16.powi(4), "{e16} vs bound");
        for (a, b) in [(e16, e32), (e32, e64)] {
            let order = (a / b).log2();
            assert!((3.5..4.5).contains(&order), "order {order}");
        }
    }

    /// C2 at every knot, the wrap knot included: one-sided slopes and
    /// curvatures from the adjoining cubics agree to 1e-9 relative (to the
    /// larger of the two and the largest curvature at any knot).
    #[test]
    fn spline_is_c2() {
        for n in [3, 4, 5, 12, 101] {
            let xs = uneven(n);
            let ys: Vec<f64> = xs.iter().map(|x| (2.0 * x).cos() + x.sin()).collect();
            let f = Periodic::new(InterpKind::Spline, &xs, &ys, TAU).unwrap();
            let left = |i: usize| {
                let p = (i + n - 1) % n;
                f.segment_derivatives(p, f.interval_len(p))
            };
            let scale = (0..n)
                .map(|i| f.segment_derivatives(i, 0.0))
                .fold(0.0_f64, |m, (d1, d2)| m.max(d1.abs()).max(d2.abs()));
            for i in 0..n {
                let (l1, l2) = left(i);
                let (r1, r2) = f.segment_derivatives(i, 0.0);
                let p = (i + n - 1) % n;
                let v = f.segment(p, f.interval_len(p));
                assert!((v - ys[i]).abs() < 1e-12, "n {n} knot {i}: value {v}");
                assert!(
                    (l1 - r1).abs() <= 1e-9 * scale,
                    "n {n} knot {i}: {l1} vs {r1}"
                );
                assert!(
                    (l2 - r2).abs() <= 1e-9 * scale,
                    "n {n} knot {i}: {l2} vs {r2}"
                );
            }
        }
    }

    /// The periodic step 0,0,0,1,1,1 on knots 0..6, period 6.
    fn step() -> (Vec<f64>, Vec<f64>) {
        (
            (0..6).map(f64::from).collect(),
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        )
    }

    /// Dense scan of how far `f` leaves each interval's data range:
    /// `per` points per unit-length interval of the step.
    fn scan_overshoot(f: &Periodic, ys: &[f64], per: usize) -> f64 {
        let n = ys.len();
        let mut worst = 0.0_f64;
        for i in 0..n {
            let (lo, hi) = (ys[i].min(ys[(i + 1) % n]), ys[i].max(ys[(i + 1) % n]));
            for k in 0..=per {
                let v = f.eval(i as f64 + k as f64 / per as f64);
                worst = worst.max(v - hi).max(lo - v);
            }
        }
        worst
    }

    /// Pchip on a step stays inside [0, 1] (the data range) everywhere and
    /// reports no overshoot.
    #[test]
    fn pchip_step_has_no_overshoot() {
        let (xs, ys) = step();
        let p = Periodic::new(InterpKind::Pchip, &xs, &ys, 6.0).unwrap();
        for k in 0..=60_000 {
            let v = p.eval(k as f64 * 1e-4);
            assert!((0.0..=1.0).contains(&v), "pchip {v} at {}", k as f64 * 1e-4);
        }
        assert!(p.max_overshoot() <= 1e-12, "{}", p.max_overshoot());
        assert!(scan_overshoot(&p, &ys, 1000) <= 1e-12);
    }

    /// The spline rings on the step; its analytic overshoot matches a
    /// brute-force scan of 10⁶ points per interval (scan error ≤ max|f''|
    /// Δ²/8 ≈ 1e-12 for Δ = 1e-6) to 1e-9.
    #[test]
    fn spline_overshoot_matches_scan() {
        let (xs, ys) = step();
        let s = Periodic::new(InterpKind::Spline, &xs, &ys, 6.0).unwrap();
        let analytic = s.max_overshoot();
        let scan = scan_overshoot(&s, &ys, 1_000_000);
        assert!(analytic > 0.01, "{analytic}");
        assert!((analytic - scan).abs() < 1e-9, "{analytic} vs {scan}");
        assert!(
            analytic >= scan - 1e-15,
            "the scan cannot beat the stationary points"
        );
    }

    /// On every interval pchip is monotone in the direction of its data
    /// (checked on 2000 points per interval), including the falling wrap
    /// interval; on a run of equal secants it is the straight line exactly.
    #[test]
    fn pchip_monotone_and_reproduces_lines() {
        // Uneven knots; data rises fast, plateaus, rises, then wraps down.
        let xs = [0.0, 0.3, 1.0, 1.2, 2.5, 3.0, 4.1, 4.2, 5.0];
        let ys = [0.0, 2.0, 2.1, 2.1, 5.0, 9.0, 9.5, 12.0, 12.5];
        let f = Periodic::new(InterpKind::Pchip, &xs, &ys, 6.0).unwrap();
        for i in 0..xs.len() {
            let (a, b) = (xs[i], xs.get(i + 1).copied().unwrap_or(6.0));
            let dir = ys[(i + 1) % ys.len()] - ys[i];
            let mut last = f.eval(a);
            for k in 1..=2000 {
                let v = f.eval(a + (b - a) * k as f64 / 2000.0);
                assert!((v - last) * dir.signum() >= -1e-12, "interval {i}");
                last = v;
            }
        }
        assert!(f.max_overshoot() <= 1e-12);
        // y = 2x + 1 on knots 0..5 (a monotone run), back down on the wrap
        // interval [5, 8): intervals [1, 4] have equal secants on both
        // sides, so pchip is exactly the line there.
        let xs: Vec<f64> = (0..6).map(f64::from).collect();
        let ys: Vec<f64> = xs.iter().map(|x| 2.0 * x + 1.0).collect();
        let f = Periodic::new(InterpKind::Pchip, &xs, &ys, 8.0).unwrap();
        for k in 0..=300 {
            let x = 1.0 + k as f64 * 0.01;
            assert!((f.eval(x) - (2.0 * x + 1.0)).abs() < 1e-12, "{x}");
        }
    }

    /// `eval_uniform` agrees with `eval` at every grid point (1e-12; in fact
    /// bit for bit) for all kinds, for grids starting anywhere, running
    /// several periods, stepping backwards and skipping whole periods.
    #[test]
    fn eval_uniform_matches_eval() {
        let xs: Vec<f64> = uneven(9).iter().map(|x| x + 0.4).collect();
        let ys: Vec<f64> = xs.iter().map(|x| x.cos() * 3.0 + (3.0 * x).sin()).collect();
        let mut out = vec![0.0; 997];
        for kind in KINDS {
            let f = Periodic::new(kind, &xs, &ys, TAU).unwrap();
            for start in [-7.3, 0.0, 0.4, 0.41, 5.9, 6.683_185_307, 1e4] {
                for step in [0.0917, 0.01, 1e-4, 0.7, -0.0311, 13.1, TAU, 0.0] {
                    f.eval_uniform(start, step, &mut out);
                    for (k, v) in out.iter().enumerate() {
                        let w = f.eval(start + step * k as f64);
                        assert!(
                            (v - w).abs() <= 1e-12,
                            "{kind:?} {start} {step} {k}: {v} vs {w}"
                        );
                    }
                }
            }
            // Empty output and a non-finite grid do not panic.
            f.eval_uniform(0.0, 0.1, &mut []);
            f.eval_uniform(f64::NAN, 0.1, &mut out[..3]);
            assert!(out[..3].iter().all(|v| v.is_nan()));
            f.eval_uniform(0.0, f64::INFINITY, &mut out[..3]);
            assert!(out[1..3].iter().all(|v| v.is_nan()));
            assert!(f.eval(f64::NEG_INFINITY).is_nan());
        }
    }

    /// Each constructor error, with the offending value in the message.
    #[test]
    fn errors() {
        use NumericsError as E;
        let k = InterpKind::Spline;
        let e = Periodic::new(k, &[0.0, 1.0], &[1.0], 4.0).unwrap_err();
        assert_eq!(e, E::LengthMismatch { xs: 2, ys: 1 });
        let e = Periodic::new(k, &[0.0, 1.0], &[1.0, 2.0], 4.0).unwrap_err();
        assert!(
            matches!(
                e,
                E::TooFewPoints {
                    got: 2,
                    need: 3,
                    ..
                }
            ),
            "{e}"
        );
        assert_eq!(e.to_string(), "2 points: spline needs at least 3");
        let e = Periodic::new(InterpKind::Linear, &[0.0], &[1.0], 4.0).unwrap_err();
        assert!(
            matches!(
                e,
                E::TooFewPoints {
                    got: 1,
                    need: 2,
                    ..
                }
            ),
            "{e}"
        );
        let e = Periodic::new(k, &[0.0, 1.0, 2.0], &[1.0, f64::NAN, 2.0], 4.0).unwrap_err();
        assert!(
            matches!(
                e,
                E::NonFinite {
                    what: "y",
                    index: 1,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("NaN"));
        let e = Periodic::new(k, &[0.0, 1.0, f64::INFINITY], &[1.0; 3], 4.0).unwrap_err();
        assert!(
            matches!(
                e,
                E::NonFinite {
                    what: "x",
                    index: 2,
                    ..
                }
            ),
            "{e}"
        );
        let e = Periodic::new(k, &[0.0, 2.0, 1.5], &[1.0, 1.0, 2.0], 4.0).unwrap_err();
        assert!(matches!(e, E::NotIncreasing { index: 2, .. }), "{e}");
        assert!(e.to_string().contains("1.5"));
        let e = Periodic::new(k, &[0.0, 1.0, 1.0], &[1.0, 1.0, 2.0], 4.0).unwrap_err();
        assert!(matches!(e, E::NotIncreasing { index: 2, .. }), "{e}");
        // Distinct abscissae whose offsets from the first knot round together.
        let e = Periodic::new(k, &[-1e20, 0.0, 1e-10], &[1.0; 3], 1e21).unwrap_err();
        assert!(matches!(e, E::NotIncreasing { index: 2, .. }), "{e}");
        let e = Periodic::new(k, &[0.0, 1.0, 4.0], &[1.0, 1.0, 2.0], 4.0).unwrap_err();
        assert!(matches!(e, E::Period { .. }), "{e}");
        assert!(e.to_string().contains("span 4"));
        for period in [-1.0, 0.0, f64::NAN, f64::INFINITY] {
            let e = Periodic::new(k, &[0.0, 1.0, 2.0], &[1.0; 3], period).unwrap_err();
            assert!(matches!(e, E::Period { .. }), "{e}");
        }
    }

    /// Constant data gives the constant for every kind, and no overshoot.
    #[test]
    fn constant_data() {
        for kind in KINDS {
            let f = Periodic::new(kind, &[0.0, 0.5, 2.0], &[7.0; 3], 3.0).unwrap();
            for k in 0..50 {
                assert!((f.eval(k as f64 * 0.173) - 7.0).abs() < 1e-14);
            }
            assert!(f.max_overshoot().abs() < 1e-14);
        }
    }
}
