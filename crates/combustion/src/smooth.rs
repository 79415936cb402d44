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
    /// The weights as polynomials in the offset, for the running sums of
    /// [`Self::values_into`] and [`Self::slopes_into`] (`None`: the plain
    /// weight sums, for the filter off and for narrow windows).
    moments: Option<Moments>,
}

/// Fewest points either side of the centre for which the running sums
/// replace the plain weight sums (a narrower window's sum costs less than
/// the sums' update).
pub const MOMENTS_MIN_HALF: usize = 8;

/// A cubic Savitzky–Golay filter's weights as polynomials in the offset
/// `i` from the centre: the value's are even, `a + b i²`, the slope's odd,
/// `c i + d i³` (per index; the fit's coefficients, so the odd part of the
/// value's and the even part of the slope's are zero but for rounding).
/// A weight sum is then a combination of the moments `T_j = Σ i^j p_(c+i)`,
/// which slide one point along in O(1): `T_j(c + 1)` is the binomial
/// combination of `U_j = T_j(c) − (−m)^j p_(c−m) + (m + 1)^j p_(c+m+1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Moments {
    /// Half the window (points).
    pub(crate) m: usize,
    /// `a`, `b` of the value's weights.
    pub(crate) value: [f64; 2],
    /// `c`, `d` of the slope's weights (per index).
    pub(crate) slope: [f64; 2],
    /// The moments are summed afresh every this many points, which bounds
    /// the rounding the updates carry (it grows as the cube of the points
    /// since the last fresh sum over the square of `m`).
    pub(crate) refresh: usize,
}

impl Moments {
    /// The stretch of fresh sums ([`Self::refresh`]) for `m` points either
    /// side, when the running sums are taken at all.
    pub(crate) fn refresh_of(m: usize) -> Option<usize> {
        (m >= MOMENTS_MIN_HALF).then(|| (4 * m).clamp(32, 128))
    }

    fn new(m: usize) -> Option<Self> {
        let refresh = Self::refresh_of(m)?;
        let (v, d) = (savitzky_golay_poly(m, 0), savitzky_golay_poly(m, 1));
        // Weights in u = i/m: value x0 + x2 u², slope (x1 u + x3 u³)/m.
        let m2 = (m * m) as f64;
        Some(Self {
            m,
            value: [v[0], v[2] / m2],
            slope: [d[1] / m2, d[3] / (m2 * m2)],
            refresh,
        })
    }
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
                moments: None,
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
            moments: Moments::new(m),
        }
    }

    /// The running sums' figures, when the filter takes them.
    pub(crate) fn moments(&self) -> Option<&Moments> {
        self.moments.as_ref()
    }

    /// The grid step (deg) the weights were made for.
    pub(crate) fn step_deg(&self) -> f64 {
        self.step_deg
    }

    /// The same filter with the plain weight sums only (the reference
    /// the running sums are tested against).
    #[cfg(test)]
    pub(crate) fn plain(mut self) -> Self {
        self.moments = None;
        self
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

    /// [`Self::value_in`] at the centres `from..from + out.len()` of such a
    /// slice, into `out`: for a wide window, by running sums (O(1) a
    /// point; equal to the weight sums but for rounding: the tests hold
    /// them within 1e-13 of the slice's largest magnitude).
    pub fn values_into(&self, s: &[f64], from: usize, out: &mut [f64]) {
        match &self.moments {
            Some(mo) => mo.values(s, from, out),
            None => {
                for (j, y) in out.iter_mut().enumerate() {
                    *y = self.value_in(s, from + j);
                }
            }
        }
    }

    /// [`Self::value_in`] and, with the running sums, [`Self::slope_in`] at
    /// the centres `from..from + out.len()`, into `out` as `[value, slope]`
    /// in one sweep; true when the slopes were made (without running sums
    /// only the values are, the slopes left NaN: a slope is a dot product
    /// of its own there, cheaper taken only where it is wanted). The values
    /// are [`Self::values_into`]'s bit for bit; the slopes are
    /// [`Self::slopes_into`]'s but for rounding (within 1e-13 of the
    /// slice's largest magnitude, as both are of the weight sums).
    pub fn values_slopes_into(&self, s: &[f64], from: usize, out: &mut [[f64; 2]]) -> bool {
        match &self.moments {
            Some(mo) => {
                mo.values_slopes(s, from, out, self.step_deg);
                true
            }
            None => {
                for (j, y) in out.iter_mut().enumerate() {
                    *y = [self.value_in(s, from + j), f64::NAN];
                }
                false
            }
        }
    }

    /// [`Self::slope_in`] at the centres `from..from + out.len()`, into
    /// `out` (running sums as [`Self::values_into`]).
    pub fn slopes_into(&self, s: &[f64], from: usize, out: &mut [f64]) {
        match &self.moments {
            Some(mo) => mo.slopes(s, from, out, self.step_deg),
            None => {
                for (j, y) in out.iter_mut().enumerate() {
                    *y = self.slope_in(s, from + j);
                }
            }
        }
    }

    /// The noise fit is the smoothed value itself (the filter on): the
    /// residual is `p − p_smooth`.
    pub fn fits_by_value(&self) -> bool {
        self.fit.is_none()
    }

    /// `Σ (p − fit)²` over the centres `from..from + smoothed.len()` of
    /// such a slice, given the smoothed values there ([`Self::fit_in`]).
    pub fn residual2_in(&self, s: &[f64], from: usize, smoothed: &[f64]) -> f64 {
        let mut sum = 0.0;
        match &self.fit {
            None => {
                for (p, ps) in s[from..].iter().zip(smoothed) {
                    let r = p - ps;
                    sum += r * r;
                }
            }
            Some(_) => {
                for (j, &ps) in smoothed.iter().enumerate() {
                    let r = s[from + j] - self.fit_in(s, from + j, ps);
                    sum += r * r;
                }
            }
        }
        sum
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

/// `T_j = Σ i^j (p_(c+i) − r)` for `j` in `0..K` over a window `w` of
/// `2m + 1` points centred on `c`, the plain sums.
#[inline]
pub(crate) fn moments<const K: usize>(w: &[f64], r: f64, m: usize) -> [f64; K] {
    let mut t = [0.0f64; K];
    let mut x = -(m as f64);
    for &p in w {
        let mut term = p - r;
        for tj in &mut t {
            *tj += term;
            term *= x;
        }
        x += 1.0;
    }
    t
}

/// One number of the running sums, or two side by side: two stretches in
/// the two lanes of one vector register, each lane's numbers those of the
/// same steps on its stretch alone (IEEE arithmetic lane by lane).
pub(crate) trait Lane:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
{
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
    /// `f` applied lane by lane.
    fn map(self, f: impl Fn(f64) -> f64) -> Self;
    /// `if self > m { self } else { m }` lane by lane (a NaN `self` gives
    /// `m`: the running largest that passes NaN over).
    fn gt_max(self, m: Self) -> Self;
    /// `if self < m { self } else { m }` lane by lane (a NaN `self` gives
    /// `m`).
    fn lt_min(self, m: Self) -> Self;
}

impl Lane for f64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        f(self)
    }
    #[inline(always)]
    fn gt_max(self, m: Self) -> Self {
        if self > m { self } else { m }
    }
    #[inline(always)]
    fn lt_min(self, m: Self) -> Self {
        if self < m { self } else { m }
    }
}

impl Lane for wide::f64x2 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        wide::f64x2::splat(x)
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        let [a, b] = self.to_array();
        wide::f64x2::new([f(a), f(b)])
    }
    #[inline(always)]
    fn gt_max(self, m: Self) -> Self {
        // SSE2's MAXPD is `self > m ? self : m` (either NaN: `m`), exactly
        // the running compare; elsewhere the compare and a blend.
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        {
            self.fast_max(m)
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        {
            use wide::CmpGt;
            self.cmp_gt(m).blend(self, m)
        }
    }
    #[inline(always)]
    fn lt_min(self, m: Self) -> Self {
        // MINPD: `self < m ? self : m` (either NaN: `m`).
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        {
            self.fast_min(m)
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        {
            use wide::CmpLt;
            self.cmp_lt(m).blend(self, m)
        }
    }
}

/// What a sweep gives at each centre from the moments `T` (about the
/// stretch's sample `r`): `K` numbers.
pub(crate) trait Outputs<const K: usize> {
    fn y<T: Lane>(&self, t: &[T; 4], r: T) -> [T; K];
}

/// The smoothed value, `r + (a T0 + b T2)` (`Σ w = 1` puts `r` back).
pub(crate) struct Value(pub(crate) [f64; 2]);
/// The slope per degree, `(c T1 + d T3) / step` (`Σ w = 0` drops `r`).
pub(crate) struct Slope(pub(crate) [f64; 2], pub(crate) f64);
/// Both, `[value, slope]`.
pub(crate) struct ValueSlope(pub(crate) Value, pub(crate) Slope);

impl Outputs<1> for Value {
    #[inline(always)]
    fn y<T: Lane>(&self, t: &[T; 4], r: T) -> [T; 1] {
        let [a, b] = self.0;
        [r + (T::splat(a) * t[0] + T::splat(b) * t[2])]
    }
}

impl Outputs<1> for Slope {
    #[inline(always)]
    fn y<T: Lane>(&self, t: &[T; 4], _: T) -> [T; 1] {
        let ([c, d], step) = (self.0, self.1);
        [(T::splat(c) * t[1] + T::splat(d) * t[3]) / T::splat(step)]
    }
}

impl Outputs<2> for ValueSlope {
    #[inline(always)]
    fn y<T: Lane>(&self, t: &[T; 4], r: T) -> [T; 2] {
        let ([v], [d]) = (self.0.y(t, r), self.1.y(t, r));
        [v, d]
    }
}

/// One slide of the moments by a point: `qo` leaves at offset `−m`, `qi`
/// enters at `m + 1`, and the offsets shift by one (`c` holds `m`, `m +
/// 1`, their squares and cubes). `T3` only when `SLOPE`; it feeds none of
/// the others.
#[inline(always)]
pub(crate) fn slide<T: Lane, const SLOPE: bool>(t: &mut [T; 4], qo: T, qi: T, c: &[T; 6]) {
    let u0 = t[0] - qo + qi;
    let u1 = t[1] + c[0] * qo + c[1] * qi;
    let u2 = t[2] - c[2] * qo + c[3] * qi;
    if SLOPE {
        let u3 = t[3] + c[4] * qo + c[5] * qi;
        t[3] = u3 - T::splat(3.0) * (u2 - u1) - u0;
    }
    t[0] = u0;
    t[1] = u1 - u0;
    t[2] = u2 - T::splat(2.0) * u1 + u0;
}

impl Moments {
    /// The smoothed values at the centres `from..from + out.len()` of `s`
    /// (which holds `m` points either side of them). Each stretch of
    /// [`Self::refresh`] centres starts from plain sums, taken about that
    /// stretch's first sample `r` (the moments of `p − r`, so a flat or
    /// slow stretch carries little rounding); `Σ w = 1` puts `r` back.
    fn values(&self, s: &[f64], from: usize, out: &mut [f64]) {
        let (out, _) = out.as_chunks_mut::<1>();
        self.sweep::<false, 1>(s, from, out, &Value(self.value));
    }

    /// The slopes (per degree at `step_deg`) at the centres `from..from +
    /// out.len()` of `s`, as [`Self::values`] (`Σ w = 0` drops `r`).
    fn slopes(&self, s: &[f64], from: usize, out: &mut [f64], step_deg: f64) {
        let (out, _) = out.as_chunks_mut::<1>();
        self.sweep::<true, 1>(s, from, out, &Slope(self.slope, step_deg));
    }

    /// [`Self::values`] and [`Self::slopes`] in one sweep: `[value,
    /// slope]` at each centre. The values are those of [`Self::values`] bit
    /// for bit (the slope's moment `T3` feeds none of `T0`, `T1`, `T2`);
    /// the slopes are [`Self::slopes`]' but for rounding, their stretches
    /// starting where the values' do.
    fn values_slopes(&self, s: &[f64], from: usize, out: &mut [[f64; 2]], step_deg: f64) {
        let both = ValueSlope(Value(self.value), Slope(self.slope, step_deg));
        self.sweep::<true, 2>(s, from, out, &both);
    }

    /// The sweep of [`Self::values`] and [`Self::slopes`]: the `K` outputs
    /// `y(T, r)` at every centre. Stretches go two at a time (two lanes of the same
    /// steps, which the compiler keeps in one vector register; each lane's
    /// numbers are those of one stretch alone), the rest one at a time.
    #[inline(always)]
    fn sweep<const SLOPE: bool, const K: usize>(
        &self,
        s: &[f64],
        from: usize,
        out: &mut [[f64; K]],
        y: &impl Outputs<K>,
    ) {
        let m = self.m;
        assert!(
            from >= m && from + out.len() + m <= s.len(),
            "slice too short"
        );
        let (mf, mp) = (m as f64, (m + 1) as f64);
        let c = [mf, mp, mf * mf, mp * mp, mf * mf * mf, mp * mp * mp];
        // A stretch's first centre: the plain sums about its sample.
        let start = |c0: usize| {
            let (w, r) = (&s[c0 - m..=c0 + m], s[c0]);
            let t = if SLOPE {
                moments::<4>(w, r, m)
            } else {
                let [t0, t1, t2] = moments::<3>(w, r, m);
                [t0, t1, t2, 0.0]
            };
            (t, r)
        };
        let step = self.refresh;
        let pairs = out.len() / (2 * step) * (2 * step);
        let (two, one) = out.split_at_mut(pairs);
        let c2 = c.map(wide::f64x2::splat);
        for (k, o) in two.chunks_exact_mut(2 * step).enumerate() {
            let (oa, ob) = o.split_at_mut(step);
            let (ca, cb) = (from + 2 * k * step, from + (2 * k + 1) * step);
            let r = wide::f64x2::new([s[ca], s[cb]]);
            let t = two_starts::<SLOPE>((&s[ca - m..=ca + m], &s[cb - m..=cb + m]), r, m);
            let first = y.y(&t, r).map(wide::f64x2::to_array);
            oa[0] = std::array::from_fn(|o| first[o][0]);
            ob[0] = std::array::from_fn(|o| first[o][1]);
            // Centre c0 + k drops s[c0 + k − 1 − m] and takes s[c0 + k + m].
            let outs = (&s[ca - m..], &s[cb - m..]);
            let ins = (&s[ca + m + 1..], &s[cb + m + 1..]);
            two_lanes::<SLOPE, K>((&mut oa[1..], &mut ob[1..]), outs, ins, (t, r), &c2, y);
        }
        for (k, o) in one.chunks_mut(step).enumerate() {
            let c0 = from + pairs + k * step;
            let (mut t, r) = start(c0);
            o[0] = y.y(&t, r);
            let points = s[c0 - m..].iter().zip(&s[c0 + m + 1..]);
            for (yk, (&po, &pi)) in o[1..].iter_mut().zip(points) {
                slide::<f64, SLOPE>(&mut t, po - r, pi - r, &c);
                *yk = y.y(&t, r);
            }
        }
    }
}

/// [`moments`] of two windows `w` (each of `2m + 1` points) about their
/// samples `r`, side by side in the lanes of one vector register: lane by
/// lane the same steps (`T3` only when `SLOPE`).
#[inline(always)]
pub(crate) fn two_starts<const SLOPE: bool>(
    (wa, wb): (&[f64], &[f64]),
    r: wide::f64x2,
    m: usize,
) -> [wide::f64x2; 4] {
    let mut t = [wide::f64x2::splat(0.0); 4];
    let mut x = -(m as f64);
    for (&pa, &pb) in wa.iter().zip(wb) {
        let xv = wide::f64x2::splat(x);
        let mut term = wide::f64x2::new([pa, pb]) - r;
        t[0] += term;
        term *= xv;
        t[1] += term;
        term *= xv;
        t[2] += term;
        if SLOPE {
            t[3] += term * xv;
        }
        x += 1.0;
    }
    t
}

/// The slides of two stretches side by side in the lanes of one vector
/// register from their first centres' moments `t` (about `r`): `outs`
/// the samples leaving, `ins` those entering, each lane's outputs into
/// its stretch. A function of its own, so that the compiler keeps the
/// moments in vector registers whatever is inlined about it.
#[inline(never)]
fn two_lanes<const SLOPE: bool, const K: usize>(
    (oa, ob): (&mut [[f64; K]], &mut [[f64; K]]),
    outs: (&[f64], &[f64]),
    ins: (&[f64], &[f64]),
    (mut t, r): ([wide::f64x2; 4], wide::f64x2),
    c: &[wide::f64x2; 6],
    y: &impl Outputs<K>,
) {
    let lanes = oa.iter_mut().zip(ob.iter_mut());
    let (outs, ins) = (outs.0.iter().zip(outs.1), ins.0.iter().zip(ins.1));
    for (((ya, yb), (&poa, &pob)), (&pia, &pib)) in lanes.zip(outs).zip(ins) {
        let (qo, qi) = (
            wide::f64x2::new([poa, pob]) - r,
            wide::f64x2::new([pia, pib]) - r,
        );
        slide::<_, SLOPE>(&mut t, qo, qi, c);
        let both = y.y(&t, r).map(wide::f64x2::to_array);
        *ya = std::array::from_fn(|o| both[o][0]);
        *yb = std::array::from_fn(|o| both[o][1]);
    }
}

/// Weights of a cubic least-squares fit over `-m..=m` that give the fit's
/// value (`deriv` 0) or its derivative per index (`deriv` 1) at the centre.
fn savitzky_golay(m: usize, deriv: usize) -> Vec<f64> {
    let mf = m as f64;
    let x = savitzky_golay_poly(m, deriv);
    let scale = if deriv == 1 { 1.0 / mf } else { 1.0 };
    (-(m as i64)..=m as i64)
        .map(|i| i as f64 / mf)
        .map(|u| scale * (x[0] + x[1] * u + x[2] * u * u + x[3] * u * u * u))
        .collect()
}

/// The weights of [`savitzky_golay`] as a cubic in `u = i/m`: the weight
/// at offset `i` is `x0 + x1 u + x2 u² + x3 u³` (the derivative's, per
/// `u`: divide by `m` for per index). The fit is solved in `u` (well
/// conditioned for any `m`).
fn savitzky_golay_poly(m: usize, deriv: usize) -> [f64; 4] {
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
    std::array::from_fn(|r| g[r][4] / g[r][r])
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

    /// Signals shaped to defeat running sums: a pressure trace with noise,
    /// a one-point spike of 100 times the base, a flat stretch, a step of
    /// 80 times, white noise about zero, and ±1e7 alternating.
    fn hostile(n: usize, seed: u64) -> Vec<(&'static str, Vec<f64>)> {
        let mut st = seed | 1;
        let mut rnd = move || {
            st ^= st << 13;
            st ^= st >> 7;
            st ^= st << 17;
            (st >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let pressure = (0..n)
            .map(|k| {
                let x = (k as f64 - n as f64 / 2.0) / (n as f64 / 10.0);
                1e5 + 6e6 * (-x * x).exp() + 5e3 * rnd()
            })
            .collect();
        let mut spike = vec![1e5; n];
        spike[n / 2] = 1e7;
        let step = (0..n).map(|k| if k < n / 2 { 1e5 } else { 8e6 }).collect();
        let noise = (0..n).map(|_| 1e6 * rnd()).collect();
        let alt = (0..n)
            .map(|k| if k % 2 == 0 { 1e7 } else { -1e7 })
            .collect();
        vec![
            ("pressure", pressure),
            ("spike", spike),
            ("flat", vec![3.3e6; n]),
            ("step", step),
            ("noise", noise),
            ("alternating", alt),
        ]
    }

    /// The running sums at centres `from..from + len` of `s` against the
    /// plain weight sums: within `tol` of the slice's largest magnitude
    /// (the slope's per index).
    fn check_against_plain(f: &Filter, s: &[f64], from: usize, len: usize, tol: f64, what: &str) {
        let (mut v, mut d) = (vec![0.0; len], vec![0.0; len]);
        f.values_into(s, from, &mut v);
        f.slopes_into(s, from, &mut d);
        // The one sweep of both: the values and (with running sums) the
        // slopes of the two sweeps from the same start, bit for bit.
        let mut both = vec![[0.0; 2]; len];
        let slopes = f.values_slopes_into(s, from, &mut both);
        assert_eq!(slopes, f.moments.is_some(), "{what}");
        for (j, (b, (v, d))) in both.iter().zip(v.iter().zip(&d)).enumerate() {
            assert_eq!(b[0].to_bits(), v.to_bits(), "{what}: value at {j}");
            if slopes {
                assert_eq!(b[1].to_bits(), d.to_bits(), "{what}: slope at {j}");
            }
        }
        let scale = s.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        for j in 0..len {
            let (a, b) = (f.value_in(s, from + j), f.slope_in(s, from + j));
            assert!(
                (v[j] - a).abs() <= tol * scale,
                "{what}: value at {j}: {} against {a}",
                v[j]
            );
            assert!(
                (d[j] - b).abs() * f.step_deg <= tol * scale,
                "{what}: slope at {j}: {} against {b}",
                d[j]
            );
        }
    }

    #[test]
    fn running_sums_match_the_weight_sums_on_hostile_data() {
        for m in [8usize, 9, 10, 16, 37, 64, 100, 200] {
            let f = Filter::new(
                Smoothing::SavitzkyGolay {
                    width_deg: (2 * m) as f64 * 0.1,
                },
                0.1,
            );
            assert_eq!(f.half_points(), m);
            assert!(f.moments.is_some());
            for (name, s) in hostile(3001, m as u64) {
                check_against_plain(&f, &s, m, s.len() - 2 * m, 1e-13, name);
                // A start off the slice's reach, and stretches of one point
                // and of the refresh length and either side of it.
                let r = f.moments.unwrap().refresh;
                for len in [1, 2, r - 1, r, r + 1, 3 * r + 5] {
                    check_against_plain(&f, &s, m + 7, len, 1e-13, name);
                }
            }
        }
    }

    #[test]
    fn two_lanes_give_each_stretch_its_own_numbers() {
        // The sweep two stretches at a time against one stretch a call (a
        // call of one stretch takes the one-lane path): bit for bit.
        for m in [8usize, 10, 50] {
            let f = Filter::new(
                Smoothing::SavitzkyGolay {
                    width_deg: (2 * m) as f64 * 0.1,
                },
                0.1,
            );
            let r = f.moments.unwrap().refresh;
            for (name, s) in hostile(2000, 11) {
                let len = s.len() - 2 * m;
                let (mut v, mut d) = (vec![0.0; len], vec![0.0; len]);
                f.values_into(&s, m, &mut v);
                f.slopes_into(&s, m, &mut d);
                for (k, (vb, db)) in v.chunks(r).zip(d.chunks(r)).enumerate() {
                    let (mut v1, mut d1) = (vec![0.0; vb.len()], vec![0.0; db.len()]);
                    f.values_into(&s, m + k * r, &mut v1);
                    f.slopes_into(&s, m + k * r, &mut d1);
                    for j in 0..vb.len() {
                        assert_eq!(vb[j].to_bits(), v1[j].to_bits(), "{name} m {m} at {k}.{j}");
                        assert_eq!(db[j].to_bits(), d1[j].to_bits(), "{name} m {m} at {k}.{j}");
                    }
                }
            }
        }
    }

    #[test]
    fn narrow_and_off_filters_keep_the_weight_sums() {
        for (smoothing, step) in [
            (Smoothing::Off, 0.1),
            (Smoothing::default(), 0.5),
            (Smoothing::SavitzkyGolay { width_deg: 1.4 }, 0.1),
        ] {
            let f = Filter::new(smoothing, step);
            assert!(f.moments.is_none(), "{smoothing:?}");
            let m = f.reach();
            for (_, s) in hostile(400, 3) {
                let len = s.len() - 2 * m;
                let (mut v, mut d) = (vec![0.0; len], vec![0.0; len]);
                f.values_into(&s, m, &mut v);
                f.slopes_into(&s, m, &mut d);
                let mut both = vec![[0.0; 2]; len];
                assert!(!f.values_slopes_into(&s, m, &mut both));
                for j in 0..len {
                    assert_eq!(v[j].to_bits(), f.value_in(&s, m + j).to_bits());
                    assert_eq!(d[j].to_bits(), f.slope_in(&s, m + j).to_bits());
                    assert_eq!(both[j][0].to_bits(), v[j].to_bits());
                }
            }
        }
    }

    #[test]
    fn the_moments_are_the_weights_polynomials() {
        for m in [8usize, 10, 33, 200] {
            let f = Filter::new(
                Smoothing::SavitzkyGolay {
                    width_deg: (2 * m) as f64 * 0.1,
                },
                0.1,
            );
            let mo = f.moments.unwrap();
            for (k, (w, d)) in f.value.iter().zip(&f.slope).enumerate() {
                let i = k as f64 - m as f64;
                let (a, b) = (
                    mo.value[0] + mo.value[1] * i * i,
                    i * (mo.slope[0] + mo.slope[1] * i * i),
                );
                assert!((a - w).abs() < 1e-15, "m {m}, i {i}: {a} against {w}");
                assert!((b - d).abs() < 1e-15, "m {m}, i {i}: {b} against {d}");
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        #[test]
        fn running_sums_match_the_weight_sums(
            m in 8usize..=200,
            seed in 1u64..u64::MAX,
            base in -1e6f64..1e7,
            spikes in proptest::collection::vec((0usize..4000, -1e7f64..1e7), 0..6),
            steps in proptest::collection::vec((0usize..4000, -1e7f64..1e7), 0..3),
            amp in 0.0f64..1e6,
            from_extra in 0usize..50,
        ) {
            let f = Filter::new(
                Smoothing::SavitzkyGolay { width_deg: (2 * m) as f64 * 0.1 },
                0.1,
            );
            let n = 2 * m + 600 + from_extra;
            let mut st = seed;
            let mut s: Vec<f64> = (0..n)
                .map(|k| {
                    st ^= st << 13;
                    st ^= st >> 7;
                    st ^= st << 17;
                    let x = k as f64 / n as f64;
                    base + amp * ((st >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
                        + 3e6 * (-(x - 0.5) * (x - 0.5) * 80.0).exp()
                })
                .collect();
            for (at, h) in spikes {
                s[at % n] += h;
            }
            for (at, h) in steps {
                for x in &mut s[at % n..] {
                    *x += h;
                }
            }
            check_against_plain(&f, &s, m + from_extra, n - 2 * m - from_extra, 1e-13, "proptest");
        }
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
