//! Numerical building blocks for enginedyn, with no knowledge of the domain:
//! everything works on plain `f64` slices and closures.
//!
//! - [`interp`]: periodic interpolation through samples of one period
//!   (linear, C2 cubic spline, monotone cubic), with a fast uniform-grid
//!   evaluator and an analytic overshoot measure.
//! - [`integrate`]: trapezoid and Simpson rules for periodic means, cycle
//!   integrals and running integrals of uniformly sampled data.
//! - [`extremes`]: extremes of a periodic sampled curve, refined between
//!   samples by the local Catmull-Rom cubic.
//! - [`roots`]: Brent's root finder and minimiser.
//! - [`scan`]: extremes and step range of samples in vector lanes.
//! - [`format`](mod@format): numbers as people write them (notes, tables, CSV cells).
//! - [`fourier`]: amplitudes and phases of chosen harmonic orders, and the
//!   inverse.
//!
//! Bad input gives a [`NumericsError`] carrying the offending value; no
//! routine panics on it.
//!
//! ```
//! use enginedyn_numerics::{InterpKind, Periodic, integrate::{self, Rule}};
//! use std::f64::consts::TAU;
//!
//! // A periodic spline through 32 samples of cos x on [0, 2π) ...
//! let xs: Vec<f64> = (0..32).map(|k| k as f64 * TAU / 32.0).collect();
//! let ys: Vec<f64> = xs.iter().map(|x| x.cos()).collect();
//! let f = Periodic::new(InterpKind::Spline, &xs, &ys, TAU)?;
//! assert!((f.eval(1.0) - 1.0_f64.cos()).abs() < 1e-5);
//!
//! // ... resampled on a finer grid, whose mean of cos² is 1/2.
//! let mut fine = vec![0.0; 720];
//! f.eval_uniform(0.0, TAU / 720.0, &mut fine);
//! let sq: Vec<f64> = fine.iter().map(|v| v * v).collect();
//! assert!((integrate::periodic_mean(Rule::Trapezoid, &sq) - 0.5).abs() < 1e-5);
//! # Ok::<(), enginedyn_numerics::NumericsError>(())
//! ```

mod error;
pub mod extremes;
pub mod format;
pub mod fourier;
pub mod integrate;
pub mod interp;
pub mod roots;
pub mod scan;

pub use error::NumericsError;
pub use interp::{InterpKind, Periodic};

/// Mean, standard deviation (sample, n − 1) of values; NaN for none, a
/// deviation of 0 for one.
pub fn mean_std(v: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = v.clone().count() as f64;
    if n == 0.0 {
        return (f64::NAN, f64::NAN);
    }
    let mean = v.clone().sum::<f64>() / n;
    let var = if n > 1.0 {
        v.map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
}

/// The mean of `samples` (angle from firing TDC in `[0, cycle)`, value)
/// over ±5° around intake BDC, 540° four-stroke or 180° two-stroke: where
/// `--peg-bar` pegs and the gauge warning looks. `None` without a sample
/// there.
pub fn intake_bdc_mean(samples: impl Iterator<Item = (f64, f64)>, cycle_deg: f64) -> Option<f64> {
    let (bdc, half) = intake_bdc_window(cycle_deg);
    let (mut sum, mut n) = (0.0, 0usize);
    for (a, p) in samples {
        if (a - bdc).abs() <= half {
            sum += p;
            n += 1;
        }
    }
    (n > 0).then(|| sum / n as f64)
}

/// Where [`intake_bdc_mean`] looks: intake BDC (deg) and the half width.
fn intake_bdc_window(cycle_deg: f64) -> (f64, f64) {
    (if cycle_deg > 400.0 { 540.0 } else { 180.0 }, 5.0 + 1e-9)
}

/// [`intake_bdc_mean`] of `angles` that rise (none NaN) and their
/// `values`, the same number: `a − bdc` rounds monotonically in `a`, so
/// the samples it takes are one run, found by bisection, and summed in the
/// same order.
pub fn intake_bdc_mean_rising(angles: &[f64], values: &[f64], cycle_deg: f64) -> Option<f64> {
    let (bdc, half) = intake_bdc_window(cycle_deg);
    let m = angles.len().min(values.len());
    let a = &angles[..m];
    let i = a.partition_point(|&x| x - bdc < -half);
    let j = a.partition_point(|&x| x - bdc <= half).max(i);
    let (mut sum, mut n) = (0.0, 0usize);
    for &p in &values[i..j] {
        sum += p;
        n += 1;
    }
    (n > 0).then(|| sum / n as f64)
}

#[cfg(test)]
mod tests {
    /// The bisection takes the samples the plain test takes, at the
    /// window's edges to the last bit (±5° plus 1e-9, a step of an ulp
    /// either side), for both cycles, with a NaN value, and none.
    #[test]
    fn intake_bdc_mean_rising_is_the_plain_mean() {
        let up = |x: f64| f64::from_bits(x.to_bits() + 1);
        let down = |x: f64| f64::from_bits(x.to_bits() - 1);
        let mut taken = 0;
        for (cycle, bdc) in [(720.0, 540.0), (360.0, 180.0)] {
            let edges = [bdc - 5.0 - 1e-9, bdc + 5.0 + 1e-9, bdc - 5.0, bdc + 5.0];
            let mut sets: Vec<Vec<f64>> = vec![
                (0..7200).map(|k| k as f64 * 0.1).collect(),
                (0..720).map(|k| k as f64).collect(),
                (0..7).map(|k| k as f64 * 100.0).collect(),
                vec![],
            ];
            for e in edges {
                for x in [down(down(e)), down(e), e, up(e), up(up(e))] {
                    sets.push(vec![bdc - 20.0, x, bdc + 20.0]);
                    sets.push(vec![x]);
                }
            }
            sets.push(vec![bdc - 5.0 - 1e-9, bdc, bdc + 5.0 + 1e-9]);
            for a in sets {
                let mut v: Vec<f64> = a.iter().map(|x| 1e5 + x * 3.7).collect();
                for nan in [false, true] {
                    if nan && !v.is_empty() {
                        let k = v.len() / 2;
                        v[k] = f64::NAN;
                    }
                    let plain =
                        super::intake_bdc_mean(a.iter().copied().zip(v.iter().copied()), cycle);
                    let fast = super::intake_bdc_mean_rising(&a, &v, cycle);
                    assert_eq!(plain.map(f64::to_bits), fast.map(f64::to_bits), "{a:?}");
                    taken += usize::from(plain.is_some());
                }
            }
        }
        assert!(taken > 20, "{taken}");
    }
}
