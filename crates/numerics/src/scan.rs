//! Scans of sampled curves in independent lanes: a plain `fold` with
//! `f64::max` is one chain of dependent instructions (about four cycles a
//! sample), while eight lanes let the compiler use vector min and max
//! instructions. The results are the same as the plain fold's; only the
//! time differs.
//!
//! ```
//! use enginedyn_numerics::scan::{min_max, step_range};
//!
//! assert_eq!(min_max(&[2.0, f64::NAN, -1.0, 3.0]), (-1.0, 3.0));
//! assert_eq!(step_range(&[0.0, 0.5, 1.5, 2.0]), (0.5, 1.0));
//! ```

const LANES: usize = 8;

/// Running smallest and largest values in independent lanes (NaN never
/// wins a comparison, so it is skipped).
struct Lanes {
    lo: [f64; LANES],
    hi: [f64; LANES],
}

impl Lanes {
    fn new() -> Self {
        Self {
            lo: [f64::INFINITY; LANES],
            hi: [f64::NEG_INFINITY; LANES],
        }
    }

    #[inline(always)]
    fn push(&mut self, j: usize, x: f64) {
        self.lo[j] = if x < self.lo[j] { x } else { self.lo[j] };
        self.hi[j] = if x > self.hi[j] { x } else { self.hi[j] };
    }

    fn finish(&self) -> (f64, f64) {
        let lo = self
            .lo
            .iter()
            .fold(f64::INFINITY, |a, &b| if b < a { b } else { a });
        let hi = self
            .hi
            .iter()
            .fold(f64::NEG_INFINITY, |a, &b| if b > a { b } else { a });
        (lo, hi)
    }
}

/// The smallest and largest of `v` (NaN samples are skipped); `(inf, -inf)`
/// when there is nothing else.
pub fn min_max(v: &[f64]) -> (f64, f64) {
    let mut l = Lanes::new();
    let chunks = v.chunks_exact(LANES);
    let rest = chunks.remainder();
    for c in chunks {
        for j in 0..LANES {
            l.push(j, c[j]);
        }
    }
    for (j, &x) in rest.iter().enumerate() {
        l.push(j, x);
    }
    l.finish()
}

/// The first index of the smallest and of the largest sample of `v` (NaN
/// samples are skipped; index 0 when nothing else is there).
pub fn arg_min_max(v: &[f64]) -> (usize, usize) {
    let (lo, hi) = min_max(v);
    (
        v.iter().position(|&x| x <= lo).unwrap_or(0),
        v.iter().position(|&x| x >= hi).unwrap_or(0),
    )
}

/// The smallest and largest step `v[k + 1] - v[k]`; `(inf, -inf)` for
/// fewer than two samples.
pub fn step_range(v: &[f64]) -> (f64, f64) {
    if v.len() < 2 {
        return (f64::INFINITY, f64::NEG_INFINITY);
    }
    let mut l = Lanes::new();
    let (a, b) = (&v[..v.len() - 1], &v[1..]);
    let (ca, cb) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for j in 0..LANES {
            l.push(j, y[j] - x[j]);
        }
    }
    for (j, (x, y)) in ra.iter().zip(rb).enumerate() {
        l.push(j, y - x);
    }
    l.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn plain(v: &[f64]) -> (f64, f64) {
        v.iter()
            .filter(|x| !x.is_nan())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            })
    }

    proptest! {
        /// The lanes give the plain fold's extremes, first indices and
        /// step range, at every length (remainders included) and with NaN.
        #[test]
        fn lanes_equal_the_plain_fold(
            mut v in proptest::collection::vec(-1e6f64..1e6, 0..40),
            nan_at in proptest::option::of(0usize..40),
        ) {
            if let Some(k) = nan_at && k < v.len() {
                v[k] = f64::NAN;
            }
            let (lo, hi) = min_max(&v);
            let (plo, phi) = plain(&v);
            prop_assert_eq!(lo.to_bits(), plo.to_bits());
            prop_assert_eq!(hi.to_bits(), phi.to_bits());
            let (kmin, kmax) = arg_min_max(&v);
            if v.iter().any(|x| !x.is_nan()) {
                prop_assert_eq!(v[kmin].to_bits(), plo.to_bits());
                prop_assert_eq!(v[kmax].to_bits(), phi.to_bits());
                prop_assert!(v[..kmin].iter().all(|&x| x.is_nan() || x > plo));
                prop_assert!(v[..kmax].iter().all(|&x| x.is_nan() || x < phi));
            }
            if !v.iter().any(|x| x.is_nan()) {
                let steps: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
                let (slo, shi) = step_range(&v);
                let (elo, ehi) = plain(&steps);
                prop_assert_eq!(slo.to_bits(), elo.to_bits());
                prop_assert_eq!(shi.to_bits(), ehi.to_bits());
            }
        }
    }
}
