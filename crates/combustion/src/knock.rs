//! Knock, cycle by cycle (PHYSICS.md "Knock"): the pressure band-passed
//! (default 4–20 kHz, zero-phase: the bins of the periodic cycle's
//! spectrum outside the band dropped, the band in Hz turned into the
//! grid's angle by the cycle's speed; a 4th-order Butterworth pair run
//! forwards and backwards lost 4–10 % of a damped oscillation's first
//! crest to its transient); **MAPO** = max |p_bp| and **IMPO**
//! = ∫ |p_bp| dφ over a window after TDC (default −10…+70°). A cycle
//! knocks when its MAPO exceeds the threshold (default 1.0 bar). Data
//! whose sampling does not resolve the band (fewer than
//! [`MIN_SAMPLES_PER_PERIOD`] samples a period of its upper edge) give no
//! figures, never a number.

use crate::{CombustionError, check_range};

/// Default band (Hz).
pub const DEFAULT_BAND_HZ: (f64, f64) = (4.0e3, 20.0e3);
/// Default window (deg from firing TDC).
pub const DEFAULT_WINDOW_DEG: (f64, f64) = (-10.0, 70.0);
/// Default threshold on MAPO (Pa).
pub const DEFAULT_THRESHOLD_PA: f64 = 1.0e5;
/// Fewest samples a period of the band's upper edge that resolve it.
pub const MIN_SAMPLES_PER_PERIOD: f64 = 2.5;

/// How knock is measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knock {
    /// The band (Hz), low and high edge.
    pub band_hz: (f64, f64),
    /// The window (deg from firing TDC) MAPO and IMPO are taken over.
    pub window_deg: (f64, f64),
    /// A cycle knocks when its MAPO exceeds this (Pa).
    pub threshold_pa: f64,
}

impl Default for Knock {
    fn default() -> Self {
        Self {
            band_hz: DEFAULT_BAND_HZ,
            window_deg: DEFAULT_WINDOW_DEG,
            threshold_pa: DEFAULT_THRESHOLD_PA,
        }
    }
}

impl Knock {
    /// Checks the band (0.5–100 kHz, the high edge above the low by a
    /// fifth), the window (−180…180°, at least 5° long) and the threshold
    /// (0.01–100 bar).
    pub fn check(&self) -> Result<(), CombustionError> {
        let (lo, hi) = self.band_hz;
        check_range("knock band low (Hz)", lo, 500.0, 100e3)?;
        check_range("knock band high (Hz)", hi, 1.2 * lo, 200e3)?;
        let (a, b) = self.window_deg;
        check_range("knock window start", a, -180.0, 175.0)?;
        check_range("knock window end", b, a + 5.0, 180.0)?;
        check_range("knock threshold (Pa)", self.threshold_pa, 1e3, 1e7)
    }
}

/// One cycle's knock figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnockFigures {
    /// MAPO: the largest |p_bp| in the window (Pa).
    pub mapo_pa: f64,
    /// IMPO: ∫ |p_bp| dφ over the window (Pa·deg).
    pub impo_pa_deg: f64,
    /// Its angle (deg from firing TDC).
    pub mapo_angle_deg: f64,
}

/// Why a cycle has no knock figures: its samples do not resolve the band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unresolved {
    /// Samples a period of the band's upper edge.
    pub samples_per_period: f64,
    /// The highest upper edge the sampling resolves (Hz).
    pub highest_hz: f64,
}

thread_local! {
    /// FFT plans, kept per thread (a batch's cycles share a length).
    static PLANNER: std::cell::RefCell<rustfft::FftPlanner<f64>> =
        std::cell::RefCell::new(rustfft::FftPlanner::new());
}

/// `p` band-passed to `band_hz` (zero-phase: whole bins of the periodic
/// cycle kept or dropped, so the band passes at unit gain), sampled at
/// `fs` Hz.
fn band_pass(p: &[f64], fs: f64, (lo, hi): (f64, f64)) -> Vec<f64> {
    use rustfft::num_complex::Complex;
    let n = p.len();
    let mut buf: Vec<Complex<f64>> = p.iter().map(|&x| Complex::new(x, 0.0)).collect();
    let (fwd, inv) = PLANNER.with(|pl| {
        let mut pl = pl.borrow_mut();
        (pl.plan_fft_forward(n), pl.plan_fft_inverse(n))
    });
    fwd.process(&mut buf);
    for (m, c) in buf.iter_mut().enumerate() {
        let f = m.min(n - m) as f64 * fs / n as f64;
        if f < lo || f > hi {
            *c = Complex::new(0.0, 0.0);
        }
    }
    inv.process(&mut buf);
    let scale = 1.0 / n as f64;
    buf.iter().map(|c| c.re * scale).collect()
}

/// The band-passed pressure (Pa) over the knock window of `k`, with its
/// angles (deg from firing TDC): what the chart of the most knocking cycle
/// shows. Call it where [`knock`] resolved the band.
pub fn band_passed_window(p: &[f64], step_deg: f64, rpm: f64, k: &Knock) -> Vec<(f64, f64)> {
    if p.len() < 8 || !(rpm > 0.0) {
        return Vec::new();
    }
    let n = p.len() as i64;
    let bp = band_pass(p, 6.0 * rpm / step_deg, k.band_hz);
    let i0 = (k.window_deg.0 / step_deg).ceil() as i64;
    let i1 = (k.window_deg.1 / step_deg).floor() as i64;
    (i0..=i1)
        .map(|i| (i as f64 * step_deg, bp[i.rem_euclid(n) as usize]))
        .collect()
}

/// The knock figures of one cycle's pressure `p` (Pa, periodic, one
/// cycle on the grid `k step_deg` from firing TDC) at `rpm`, or why the
/// data do not resolve the band. `sample_step_deg` is the spacing of the
/// samples the grid was made from (a grid finer than its samples adds no
/// band content).
pub fn knock(
    p: &[f64],
    step_deg: f64,
    sample_step_deg: f64,
    rpm: f64,
    k: &Knock,
) -> Result<KnockFigures, Unresolved> {
    // 1 s is 6 n degrees: a frequency f is a period of 6 n / f degrees.
    let deg_per_s = 6.0 * rpm;
    let spacing = step_deg.max(sample_step_deg);
    let per_period = deg_per_s / k.band_hz.1 / spacing;
    if !(per_period >= MIN_SAMPLES_PER_PERIOD) || !(rpm > 0.0) || p.len() < 8 {
        return Err(Unresolved {
            samples_per_period: per_period.max(0.0),
            highest_hz: (deg_per_s / (MIN_SAMPLES_PER_PERIOD * spacing)).max(0.0),
        });
    }
    let n = p.len() as i64;
    let bp = band_pass(p, deg_per_s / step_deg, k.band_hz);
    let i0 = (k.window_deg.0 / step_deg).ceil() as i64;
    let i1 = (k.window_deg.1 / step_deg).floor() as i64;
    let (mut mapo, mut at, mut impo) = (0.0f64, i0, 0.0);
    for i in i0..=i1 {
        let v = bp[i.rem_euclid(n) as usize].abs();
        if v > mapo {
            (mapo, at) = (v, i);
        }
        impo += v;
    }
    // The crest between grid points: the parabola through the largest
    // |value| and its neighbours (a 7 kHz crest at 1000 rpm and 0.1° is
    // 8.6 samples a period: the largest sample lies up to 6.6 % low).
    let v = |i: i64| bp[i.rem_euclid(n) as usize];
    let sign = v(at).signum();
    let (a, b, c) = (sign * v(at - 1), sign * v(at), sign * v(at + 1));
    let den = a - 2.0 * b + c;
    let (mut top, mut x) = (mapo, at as f64);
    if den < 0.0 {
        let t = (0.5 * (a - c) / den).clamp(-0.5, 0.5);
        x += t;
        top = b - 0.25 * (a - c) * t;
    }
    Ok(KnockFigures {
        mapo_pa: top,
        impo_pa_deg: impo * step_deg,
        mapo_angle_deg: x * step_deg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pure tone in the band passes at its amplitude; one far below it
    /// does not.
    #[test]
    fn a_tone_in_the_band_passes_and_one_below_does_not() {
        let (step, rpm) = (0.1, 2000.0);
        let n = 7200;
        let tone = |f: f64| -> Vec<f64> {
            (0..n)
                .map(|k| {
                    let t = k as f64 * step / (6.0 * rpm);
                    1e5 * (2.0 * std::f64::consts::PI * f * t).sin()
                })
                .collect()
        };
        let k = Knock::default();
        let inband = knock(&tone(8e3), step, step, rpm, &k).unwrap();
        // The crest refined between the samples (15 a period).
        assert!(
            (inband.mapo_pa / 1e5 - 1.0).abs() < 2e-3,
            "{}",
            inband.mapo_pa
        );
        let low = knock(&tone(500.0), step, step, rpm, &k).unwrap();
        assert!(low.mapo_pa < 1e3, "{}", low.mapo_pa);
    }

    #[test]
    fn coarse_data_do_not_resolve_the_band() {
        let p = vec![1e5; 720];
        // 1° at 2000 rpm: 12 kHz sampling, 0.6 samples a 20 kHz period.
        let e = knock(&p, 1.0, 1.0, 2000.0, &Knock::default()).unwrap_err();
        assert!((e.samples_per_period - 0.6).abs() < 1e-12, "{e:?}");
        assert!((e.highest_hz - 4800.0).abs() < 1e-9, "{e:?}");
        // A 0.1° grid made from 1° samples does not either.
        let p = vec![1e5; 7200];
        assert!(knock(&p, 0.1, 1.0, 2000.0, &Knock::default()).is_err());
    }
}
