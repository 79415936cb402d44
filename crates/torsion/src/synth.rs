//! Several harmonics summed in time over one period.

use crate::Complex64;
use enginedyn_numerics::extremes::periodic_min_max;
use std::f64::consts::TAU;

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
    /// refined between samples (`numerics::extremes`); `scratch` holds the
    /// samples.
    pub fn half_peak_to_peak(&self, terms: &[(usize, Complex64)], scratch: &mut Vec<f64>) -> f64 {
        self.signal(terms, scratch);
        let (lo, hi) = periodic_min_max(scratch);
        0.5 * (hi - lo)
    }
}
