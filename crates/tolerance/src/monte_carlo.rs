//! Monte Carlo over the tolerance box: every deviation drawn independently
//! and uniformly on `[-t, t]` from a seeded ChaCha8 generator (the same
//! seed gives the same samples on every platform and thread count), each
//! sample a full pipeline run.

use crate::ToleranceError;
use crate::keys::{OUTPUTS, Output};
use crate::perturb::{Evaluator, Outputs};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// What the samples show, per result (indexed like [`Output::ALL`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MonteCarlo {
    /// Samples drawn.
    pub samples: usize,
    /// Seed of the generator.
    pub seed: u64,
    /// Grid step of the runs (deg).
    pub step_deg: f64,
    /// The nominal results on this grid (the deviations are measured from them).
    pub nominal: Outputs,
    /// Mean of each result over the samples where it exists.
    pub mean: [Option<f64>; OUTPUTS],
    /// Standard deviation (`n - 1` in the denominator).
    pub std: [Option<f64>; OUTPUTS],
    /// Largest `|y - nominal|`.
    pub max_dev: [Option<f64>; OUTPUTS],
    /// Samples in which a result did not exist (e.g. a motored sample's
    /// flywheel), per result.
    pub missing: [usize; OUTPUTS],
}

/// The deviations of `samples` samples (key units), one row per sample,
/// drawn in order from `ChaCha8Rng::seed_from_u64(seed)`: each input's
/// `t (2u - 1)` with `u` uniform on `[0, 1)`.
pub fn draw(tolerances: &[f64], samples: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..samples)
        .map(|_| {
            tolerances
                .iter()
                .map(|t| t * (2.0 * rng.random::<f64>() - 1.0))
                .collect()
        })
        .collect()
}

/// Runs the Monte Carlo check: `samples` samples from `seed`, in parallel;
/// the statistics are accumulated in sample order, so they do not depend on
/// the number of threads.
pub fn monte_carlo(
    ev: &Evaluator,
    samples: usize,
    seed: u64,
) -> Result<MonteCarlo, ToleranceError> {
    let (nominal, _) = ev.nominal()?;
    let tol: Vec<f64> = ev.inputs().iter().map(|i| i.tolerance).collect();
    let devs = draw(&tol, samples, seed);
    let runs: Vec<Outputs> = devs
        .par_iter()
        .map(|d| ev.evaluate(d))
        .collect::<Result<_, _>>()?;
    let mut mean = [None; OUTPUTS];
    let mut std = [None; OUTPUTS];
    let mut max_dev = [None; OUTPUTS];
    let mut missing = [0; OUTPUTS];
    for o in Output::ALL {
        let i = o.index();
        let Some(y0) = nominal.get(o) else {
            continue;
        };
        // Welford's running mean and variance, in sample order.
        let (mut n, mut m, mut m2, mut worst) = (0usize, 0.0, 0.0, 0.0_f64);
        for r in &runs {
            match r.get(o) {
                Some(y) => {
                    n += 1;
                    let d = y - m;
                    m += d / n as f64;
                    m2 += d * (y - m);
                    worst = worst.max((y - y0).abs());
                }
                None => missing[i] += 1,
            }
        }
        if n > 0 {
            mean[i] = Some(m);
            max_dev[i] = Some(worst);
        }
        if n > 1 {
            std[i] = Some((m2 / (n - 1) as f64).sqrt());
        }
    }
    Ok(MonteCarlo {
        samples,
        seed,
        step_deg: ev.options().step_deg,
        nominal,
        mean,
        std,
        max_dev,
        missing,
    })
}
