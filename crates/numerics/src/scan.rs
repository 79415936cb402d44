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

/// The steps `v[k + 1] - v[k]` of a sampled axis, from one pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Steps {
    /// The smallest step (NaN steps skipped); `inf` when there is none.
    pub lo: f64,
    /// The largest step (NaN steps skipped); `-inf` when there is none.
    pub hi: f64,
    /// Some step is NaN (a NaN sample, or `inf - inf`).
    pub nan: bool,
}

impl Steps {
    /// Every step is above zero and none is NaN: the samples rise
    /// strictly (and none is NaN: a NaN sample makes its steps NaN).
    pub fn rising(&self) -> bool {
        self.lo > 0.0 && !self.nan
    }

    /// Every step lies within `tol` of `h`, `|step - h| <= tol` as each
    /// step would compute it: `step - h` rounds monotonically in the step,
    /// so the smallest and the largest step decide for all of them (a NaN
    /// step never lies within).
    pub fn all_within(&self, h: f64, tol: f64) -> bool {
        !self.nan && self.hi - h <= tol && self.lo - h >= -tol
    }
}

/// The smallest and largest step `v[k + 1] - v[k]` and whether any is NaN
/// ([`Steps`]); `(inf, -inf, false)` for fewer than two samples.
pub fn steps(v: &[f64]) -> Steps {
    if v.len() < 2 {
        return Steps {
            lo: f64::INFINITY,
            hi: f64::NEG_INFINITY,
            nan: false,
        };
    }
    let mut l = Lanes::new();
    // The steps summed: NaN once any step is NaN (or two infinite steps
    // cancel); only then are they looked at one by one. Summed in two
    // lanes, pairwise within a chunk (the shape the compiler keeps in
    // vector registers).
    let mut sum = [0.0f64; 2];
    let (a, b) = (&v[..v.len() - 1], &v[1..]);
    let (ca, cb) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        let mut d = [0.0; LANES];
        for j in 0..LANES {
            d[j] = y[j] - x[j];
        }
        for (j, &dj) in d.iter().enumerate() {
            l.push(j, dj);
        }
        sum[0] += (d[0] + d[2]) + (d[4] + d[6]);
        sum[1] += (d[1] + d[3]) + (d[5] + d[7]);
    }
    for (j, (x, y)) in ra.iter().zip(rb).enumerate() {
        let d = y - x;
        l.push(j, d);
        sum[0] += d;
    }
    let (lo, hi) = l.finish();
    let nan = (sum[0] + sum[1]).is_nan() && v.windows(2).any(|w| (w[1] - w[0]).is_nan());
    Steps { lo, hi, nan }
}

/// The smallest and largest step `v[k + 1] - v[k]` (NaN steps skipped);
/// `(inf, -inf)` for fewer than two samples.
pub fn step_range(v: &[f64]) -> (f64, f64) {
    let s = steps(v);
    (s.lo, s.hi)
}

/// `x.rem_euclid(c)`, bit for bit, without the software `fmod` that `%`
/// on `f64` calls (about a hundred instructions: a fifth of reading a
/// record whose angle runs on) when `c` is a whole number of degrees (a
/// cycle, 360 or 720). The remainder of `|x|` is `|x| − k c` with
/// `k = ⌊|x|/c⌋` corrected by one where the division rounded across an
/// integer: exact, as `fmod` is (Sterbenz), as long as `k c` is exact (a
/// whole `c` under 2²⁰ and `|x|` under 2⁵²). Otherwise, and for NaN or
/// infinities, `f64::rem_euclid` itself.
pub fn rem_euclid(x: f64, c: f64) -> f64 {
    let a = x.abs();
    // A whole `c` (the cast is exact under 2⁶⁴) and `⌊|x|/c⌋` by truncation,
    // exact for a quotient at least 0 and under 2⁵² (`|x|` under 4.5e15,
    // `c` at least 1): no calls to `trunc` and `floor`, which the baseline
    // x86-64 target makes (one a sample where a trace is wrapped).
    let fast = a < 4.5e15 && c > 0.0 && c < 1e6 && c - (c as u64) as f64 == 0.0;
    if !fast {
        return x.rem_euclid(c);
    }
    let k = ((a / c) as u64) as f64;
    let mut m = a - k * c;
    if m < 0.0 {
        m += c;
    } else if m >= c {
        m -= c;
    }
    // `fmod` keeps the sign of `x` (−0 too); `rem_euclid` then adds `c`
    // to a negative remainder.
    let r = m.copysign(x);
    if r < 0.0 { r + c } else { r }
}

#[cfg(test)]
mod tests {
    /// The same bits as `f64::rem_euclid` over angles as files hold them
    /// (running on, negative, on and beside multiples of the cycle,
    /// −0, huge, NaN) for the cycles a record has.
    #[test]
    fn rem_euclid_is_the_std_ones_bit_for_bit() {
        let mut xs: Vec<f64> = vec![
            0.0, -0.0, 720.0, -720.0, 1440.0, 1e-300, -1e-300, 4.6e15, -9e18, 1e300,
        ];
        for k in -3000..3000 {
            let a = k as f64 * 0.1;
            xs.extend([
                a,
                a * 7.3,
                a + 1e-13,
                a - 1e-13,
                k as f64 * 720.0,
                k as f64 * 360.0 + 0.05,
            ]);
            xs.push(f64::from_bits((k as f64 * 720.0).to_bits().wrapping_sub(1)));
        }
        // Whole cycles take the fast path; the others, `f64::rem_euclid`.
        for &c in &[720.0, 360.0, 1.0, 3.0, 0.1, 1.0 / 3.0] {
            for &x in &xs {
                let (got, want) = (super::rem_euclid(x, c), x.rem_euclid(c));
                assert_eq!(
                    got.to_bits(),
                    want.to_bits(),
                    "{x} mod {c}: {got} vs {want}"
                );
            }
        }
        assert!(super::rem_euclid(f64::NAN, 720.0).is_nan());
        assert!(super::rem_euclid(f64::INFINITY, 720.0).is_nan());
    }

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
            // With NaN: the range of the steps that are numbers, and the flag.
            let s = super::steps(&v);
            let all: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
            let (elo, ehi) = plain(&all);
            prop_assert_eq!(s.lo.to_bits(), elo.to_bits());
            prop_assert_eq!(s.hi.to_bits(), ehi.to_bits());
            prop_assert_eq!(s.nan, all.iter().any(|d| d.is_nan()));
            prop_assert_eq!(s.rising(), all.iter().all(|&d| d > 0.0));
        }

        /// `all_within` is the plain test of every step, on axes shaped
        /// to sit at its edges: steps nudged by about the tolerance either
        /// way, a NaN or an infinite sample, repeated samples.
        #[test]
        fn all_within_is_every_steps_test(
            h in prop_oneof![Just(0.1), Just(1.0), Just(0.25), 1e-3f64..10.0],
            nudges in proptest::collection::vec(
                prop_oneof![Just(0.0), Just(1.0), Just(-1.0), Just(0.999_999), Just(1.000_001), -3.0f64..3.0],
                2..40,
            ),
            odd in proptest::option::of((0usize..40, prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)])),
            start in prop_oneof![Just(0.0), Just(-360.0), Just(36_000.0), -1e4f64..1e4],
        ) {
            let tol = 1e-9 * h;
            let mut v: Vec<f64> = nudges
                .iter()
                .enumerate()
                .map(|(k, e)| start + k as f64 * h + e * tol)
                .collect();
            if let Some((k, x)) = odd && k < v.len() {
                v[k] = x;
            }
            let hs = [h, (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64, h * (1.0 + 1e-9)];
            let s = super::steps(&v);
            for hh in hs {
                let t = 1e-9 * hh.abs();
                let plain = v.windows(2).all(|w| ((w[1] - w[0]) - hh).abs() <= t);
                prop_assert_eq!(s.all_within(hh, t), plain, "{:?} {}", v, hh);
            }
        }
    }
}
