//! A response's peak between grid speeds: climb the sampled curve from a
//! starting sample to its local maximum, then refine between that
//! sample's neighbours with Brent's method ([`enginedyn_numerics::roots::minimize`]).
//! The one home of "the peak near here" for the torsion study: the
//! resonances' peaks and the largest free-end angle and section torque.

use enginedyn_numerics::roots::minimize;

/// The peak [`climb`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// Where (the sample axis's unit, rpm in the study).
    pub x: f64,
    /// The function's value there.
    pub y: f64,
    /// The curve still rises at an end of the samples: the peak is the
    /// end, not a maximum inside the range.
    pub at_end: bool,
}

/// The local maximum of `f` reached from sample `start` of the sampled
/// curve `(xs, ys)` (`xs` strictly increasing, `ys[i] = f(xs[i])`):
/// uphill sample by sample (towards the higher neighbour while one is
/// higher), then Brent's method on `f` between the neighbours of the
/// highest sample reached, to `tol` in x. The answer never leaves
/// `[xs[0], xs[n - 1]]`, and is never lower than the best sample.
///
/// `f` may fail (a solve); the first error is returned.
///
/// ```
/// use enginedyn_torsion::climb;
/// // A peak at 1.3 between samples 1 and 2, climbed to from sample 0.
/// let f = |x: f64| -> Result<f64, ()> { Ok(1.0 / (1.0 + (x - 1.3).powi(2))) };
/// let xs = [0.0, 1.0, 2.0, 3.0];
/// let ys: Vec<f64> = xs.iter().map(|&x| f(x).unwrap()).collect();
/// let p = climb(&xs, &ys, 0, f, 1e-6)?;
/// assert!((p.x - 1.3).abs() < 1e-5 && !p.at_end);
/// # Ok::<(), ()>(())
/// ```
///
/// # Errors
///
/// The first error `f` returned.
pub fn climb<E, F: FnMut(f64) -> Result<f64, E>>(
    xs: &[f64],
    ys: &[f64],
    start: usize,
    mut f: F,
    tol: f64,
) -> Result<Peak, E> {
    let n = xs.len().min(ys.len());
    if n == 0 {
        return Ok(Peak {
            x: f64::NAN,
            y: f64::NAN,
            at_end: false,
        });
    }
    let mut i = start.min(n - 1);
    loop {
        let left = (i > 0 && ys[i - 1] > ys[i]).then(|| ys[i - 1]);
        let right = (i + 1 < n && ys[i + 1] > ys[i]).then(|| ys[i + 1]);
        i = match (left, right) {
            (Some(l), Some(r)) => {
                if r > l {
                    i + 1
                } else {
                    i - 1
                }
            }
            (Some(_), None) => i - 1,
            (None, Some(_)) => i + 1,
            (None, None) => break,
        };
    }
    let best = Peak {
        x: xs[i],
        y: ys[i],
        at_end: n > 1 && (i == 0 || i == n - 1),
    };
    if n == 1 {
        return Ok(best);
    }
    let (a, b) = (xs[i.saturating_sub(1)], xs[(i + 1).min(n - 1)]);
    let mut failed = None;
    let (x, neg) = minimize(
        |x| match f(x) {
            Ok(y) if y.is_finite() => -y,
            Ok(_) => f64::INFINITY,
            Err(e) => {
                failed.get_or_insert(e);
                f64::INFINITY
            }
        },
        a,
        b,
        tol,
    );
    if let Some(e) = failed {
        return Err(e);
    }
    let y = -neg;
    if !(y > best.y) {
        return Ok(best);
    }
    // Inside the range unless the refined peak sits at an end (within the
    // tolerance Brent's method keeps from its ends).
    let near = |e: f64| (x - e).abs() <= 2.0 * tol + f64::EPSILON.sqrt() * e.abs();
    Ok(Peak {
        x,
        y,
        at_end: near(xs[0]) || near(xs[n - 1]),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lorentz(c: f64, w: f64) -> impl Fn(f64) -> Result<f64, ()> {
        move |x| Ok(1.0 / (1.0 + ((x - c) / w).powi(2)))
    }

    fn sampled(f: &impl Fn(f64) -> Result<f64, ()>, xs: &[f64]) -> Vec<f64> {
        xs.iter().map(|&x| f(x).unwrap()).collect()
    }

    /// A narrow peak between two samples, climbed to from either side.
    #[test]
    fn peak_between_samples() {
        let xs: Vec<f64> = (0..21).map(|k| 1000.0 + 50.0 * k as f64).collect();
        let f = lorentz(1437.3, 20.0);
        let ys = sampled(&f, &xs);
        for start in [0, 5, 20] {
            let p = climb(&xs, &ys, start, &f, 0.01).unwrap();
            assert!((p.x - 1437.3).abs() < 0.01, "{start}: {}", p.x);
            assert!((p.y - 1.0).abs() < 1e-6);
            assert!(!p.at_end);
        }
    }

    /// A curve still rising at the range's end: the end, said so.
    #[test]
    fn rising_to_the_end() {
        let xs: Vec<f64> = (0..11).map(|k| k as f64).collect();
        let f = lorentz(20.0, 3.0);
        let ys = sampled(&f, &xs);
        let p = climb(&xs, &ys, 2, &f, 1e-3).unwrap();
        assert!(p.at_end);
        assert!((p.x - 10.0).abs() < 1e-9 && (p.y - ys[10]).abs() < 1e-12);
        // Falling from the start: the start.
        let g = lorentz(0.0, 3.0);
        let ys = sampled(&g, &xs);
        let p = climb(&xs, &ys, 7, &g, 1e-3).unwrap();
        assert!(p.at_end && p.x.abs() < 1e-9);
    }

    /// Errors of `f` come back; one sample is its own peak.
    #[test]
    fn errors_and_one_sample() {
        let xs = [0.0, 1.0, 2.0];
        let ys = [0.0, 1.0, 0.0];
        let e = climb(&xs, &ys, 0, |_| Err::<f64, _>("no"), 1e-3);
        assert_eq!(e, Err("no"));
        let p = climb(&[5.0], &[2.0], 0, |_| Err::<f64, &str>("unused"), 1e-3).unwrap();
        assert_eq!(
            (p.x.to_bits(), p.y.to_bits(), p.at_end),
            (5f64.to_bits(), 2f64.to_bits(), false)
        );
    }
}
