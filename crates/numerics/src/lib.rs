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
    let bdc = if cycle_deg > 400.0 { 540.0 } else { 180.0 };
    let (mut sum, mut n) = (0.0, 0usize);
    for (a, p) in samples {
        if (a - bdc).abs() <= 5.0 + 1e-9 {
            sum += p;
            n += 1;
        }
    }
    (n > 0).then(|| sum / n as f64)
}
