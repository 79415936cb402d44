//! The smoothing applied before any derivative of the pressure and before
//! the SOC/EOC search: a Savitzky–Golay filter, cubic, symmetric (so
//! zero-phase), applied on the periodic grid. Its derivative is the
//! derivative of the same local cubic; without smoothing, a central
//! difference.

use crate::{CombustionError, check_range};

/// Default filter width (deg).
pub const DEFAULT_WIDTH_DEG: f64 = 2.0;
/// Fewest points a cubic fit can smooth over (a cubic through 4 points
/// passes through them all).
pub const MIN_POINTS: usize = 5;

/// How the pressure is smoothed before it is differentiated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Smoothing {
    /// No smoothing: the pressure as read, central differences.
    Off,
    /// Savitzky–Golay, cubic, over `width_deg` (at least
    /// [`MIN_POINTS`] grid points).
    SavitzkyGolay {
        /// Width of the window (deg), 0.1–20.
        width_deg: f64,
    },
}

impl Default for Smoothing {
    fn default() -> Self {
        Smoothing::SavitzkyGolay {
            width_deg: DEFAULT_WIDTH_DEG,
        }
    }
}

impl Smoothing {
    /// Checks the width (0.1–20°).
    pub fn check(&self) -> Result<(), CombustionError> {
        match *self {
            Smoothing::Off => Ok(()),
            Smoothing::SavitzkyGolay { width_deg } => check_range("smooth", width_deg, 0.1, 20.0),
        }
    }

    /// Half the window in grid points at `step_deg` (0 when off).
    pub fn half_points(&self, step_deg: f64) -> usize {
        match *self {
            Smoothing::Off => 0,
            Smoothing::SavitzkyGolay { width_deg } => {
                ((width_deg / (2.0 * step_deg)).round() as usize).max(MIN_POINTS / 2)
            }
        }
    }

    /// The filter as `models.smoothing` and the charts name it:
    /// `Savitzky-Golay cubic, 2° (21 points), zero-phase` or `off`.
    pub fn describe(&self, step_deg: f64) -> String {
        match *self {
            Smoothing::Off => "off (central differences)".into(),
            Smoothing::SavitzkyGolay { width_deg } => {
                let m = self.half_points(step_deg);
                format!(
                    "Savitzky-Golay cubic, {}° ({} points), zero-phase",
                    enginedyn_numerics::format::human(width_deg),
                    2 * m + 1
                )
            }
        }
    }
}

/// The smoothing and derivative weights of one [`Smoothing`] at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct Filter {
    value: Vec<f64>,
    slope: Vec<f64>,
    step_deg: f64,
    /// The cubic fit that measures the noise: the filter's own, or the
    /// five-point one when the filter is off.
    fit: Option<Vec<f64>>,
    /// `√Σ w²` of the value weights: the share of white noise's standard
    /// deviation the smoothed value keeps.
    gain: f64,
}

impl Filter {
    /// The weights for `smoothing` on a grid of `step_deg`.
    pub fn new(smoothing: Smoothing, step_deg: f64) -> Self {
        let m = smoothing.half_points(step_deg);
        if m == 0 {
            return Self {
                value: vec![1.0],
                slope: vec![-0.5, 0.0, 0.5],
                step_deg,
                fit: Some(savitzky_golay(MIN_POINTS / 2, 0)),
                gain: 1.0,
            };
        }
        let value = savitzky_golay(m, 0);
        let gain = value.iter().map(|w| w * w).sum::<f64>().sqrt();
        Self {
            value,
            slope: savitzky_golay(m, 1),
            step_deg,
            fit: None,
            gain,
        }
    }

    /// How far the weights reach either side of their centre (points): the
    /// margin a slice needs for [`Self::value_in`], [`Self::slope_in`] and
    /// [`Self::fit_in`].
    pub fn reach(&self) -> usize {
        let fit = self.fit.as_ref().map_or(0, |w| w.len() / 2);
        (self.value.len() / 2).max(self.slope.len() / 2).max(fit)
    }

    /// [`Self::value`] at index `c` of a slice that holds [`Self::reach`]
    /// points either side of it (no wrapping: the fast path of a window
    /// copied out once).
    #[inline]
    pub fn value_in(&self, s: &[f64], c: usize) -> f64 {
        let m = self.value.len() / 2;
        dot(&self.value, &s[c - m..=c + m])
    }

    /// [`Self::slope`] at index `c` of such a slice.
    #[inline]
    pub fn slope_in(&self, s: &[f64], c: usize) -> f64 {
        let m = self.slope.len() / 2;
        dot(&self.slope, &s[c - m..=c + m]) / self.step_deg
    }

    /// The noise fit (the filter's own, or the five-point cubic when the
    /// filter is off) at index `c` of such a slice, given the smoothed value.
    #[inline]
    pub fn fit_in(&self, s: &[f64], c: usize, smoothed: f64) -> f64 {
        match &self.fit {
            None => smoothed,
            Some(w) => {
                let m = w.len() / 2;
                dot(w, &s[c - m..=c + m])
            }
        }
    }

    /// The noise fit's centre weight `w₀`: white noise keeps `1 − w₀` of
    /// its variance in the fit's residual.
    pub fn fit_centre(&self) -> f64 {
        let w = self.fit.as_ref().unwrap_or(&self.value);
        w[w.len() / 2]
    }

    /// The share of a sample's white noise (standard deviation) that the
    /// smoothed value keeps: `√Σ w²`.
    pub fn gain(&self) -> f64 {
        self.gain
    }

    /// Half the smoothing window in points (0 without smoothing).
    pub fn half_points(&self) -> usize {
        self.value.len() / 2
    }

    /// The smoothed value at index `k` of the periodic `p` (any integer:
    /// it wraps).
    #[inline]
    pub fn value(&self, p: &[f64], k: i64) -> f64 {
        apply(&self.value, p, k)
    }

    /// The smoothed derivative at index `k`, per degree.
    #[inline]
    pub fn slope(&self, p: &[f64], k: i64) -> f64 {
        apply(&self.slope, p, k) / self.step_deg
    }
}

#[inline]
fn apply(w: &[f64], p: &[f64], k: i64) -> f64 {
    let n = p.len() as i64;
    let m = (w.len() / 2) as i64;
    let start = k - m;
    if start >= 0 && k + m < n {
        return dot(w, &p[start as usize..(k + m + 1) as usize]);
    }
    w.iter()
        .enumerate()
        .map(|(j, a)| {
            let i = start + j as i64;
            let i = if i < 0 {
                i + n
            } else if i >= n {
                i - n
            } else {
                i
            };
            a * p[if (0..n).contains(&i) {
                i
            } else {
                i.rem_euclid(n)
            } as usize]
        })
        .sum()
}

/// `Σ w_i s_i` in four interleaved partial sums (the compiler keeps them
/// in one vector register; a single running sum is a chain of dependent
/// additions).
#[inline]
fn dot(w: &[f64], s: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (wc, sc) = (w.chunks_exact(4), s.chunks_exact(4));
    let (wr, sr) = (wc.remainder(), sc.remainder());
    for (a, b) in wc.zip(sc) {
        for j in 0..4 {
            acc[j] += a[j] * b[j];
        }
    }
    let tail: f64 = wr.iter().zip(sr).map(|(a, b)| a * b).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Weights of a cubic least-squares fit over `-m..=m` that give the fit's
/// value (`deriv` 0) or its derivative per index (`deriv` 1) at the centre.
/// The fit is solved in `u = i/m` (well conditioned for any `m`).
fn savitzky_golay(m: usize, deriv: usize) -> Vec<f64> {
    let mf = m as f64;
    let us: Vec<f64> = (-(m as i64)..=m as i64).map(|i| i as f64 / mf).collect();
    // Normal equations G x = e_deriv, G_ab = sum u^(a+b).
    let mut g = [[0.0f64; 5]; 4];
    for (a, row) in g.iter_mut().enumerate() {
        for b in 0..4 {
            row[b] = us.iter().map(|u| u.powi((a + b) as i32)).sum();
        }
        row[4] = if a == deriv { 1.0 } else { 0.0 };
    }
    // Gaussian elimination with partial pivoting on the 4 x 4 system.
    for c in 0..4 {
        let piv = (c..4)
            .max_by(|&i, &j| g[i][c].abs().total_cmp(&g[j][c].abs()))
            .unwrap_or(c);
        g.swap(c, piv);
        for r in 0..4 {
            if r != c {
                let f = g[r][c] / g[c][c];
                for k in c..5 {
                    g[r][k] -= f * g[c][k];
                }
            }
        }
    }
    let x: Vec<f64> = (0..4).map(|r| g[r][4] / g[r][r]).collect();
    let scale = if deriv == 1 { 1.0 / mf } else { 1.0 };
    us.iter()
        .map(|u| scale * (x[0] + x[1] * u + x[2] * u * u + x[3] * u * u * u))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn five_point_weights_are_the_textbook_ones() {
        // Savitzky & Golay (1964): quadratic/cubic smoothing over 5 points
        // is (-3, 12, 17, 12, -3)/35; the cubic derivative (1, -8, 0, 8, -1)/12.
        let v = savitzky_golay(2, 0);
        for (a, b) in v.iter().zip([-3.0, 12.0, 17.0, 12.0, -3.0]) {
            assert!((a - b / 35.0).abs() < 1e-14, "{v:?}");
        }
        let d = savitzky_golay(2, 1);
        for (a, b) in d.iter().zip([1.0, -8.0, 0.0, 8.0, -1.0]) {
            assert!((a - b / 12.0).abs() < 1e-14, "{d:?}");
        }
    }

    #[test]
    fn cubics_pass_unchanged_and_wrap() {
        let f = Filter::new(Smoothing::default(), 0.1);
        let n = 400;
        let cubic = |k: f64| 2.0 + 0.3 * k - 0.01 * k * k + 1e-4 * k * k * k;
        let p: Vec<f64> = (0..n).map(|k| cubic(k as f64)).collect();
        for k in 20..380 {
            assert!((f.value(&p, k) - p[k as usize]).abs() < 1e-9);
            let kf = k as f64;
            let d = (0.3 - 0.02 * kf + 3e-4 * kf * kf) / 0.1;
            assert!((f.slope(&p, k) - d).abs() < 1e-8 * d.abs().max(1.0));
        }
        // A constant wraps to itself at both ends.
        let c = vec![5.0; 50];
        assert!((f.value(&c, 0) - 5.0).abs() < 1e-12 && (f.value(&c, 49) - 5.0).abs() < 1e-12);
    }

    #[test]
    fn widths() {
        assert_eq!(Smoothing::default().half_points(0.1), 10);
        assert_eq!(Smoothing::default().half_points(0.5), 2);
        assert_eq!(Smoothing::default().half_points(1.0), 2);
        assert_eq!(Smoothing::Off.half_points(0.1), 0);
        assert!(Smoothing::SavitzkyGolay { width_deg: 0.0 }.check().is_err());
    }
}
