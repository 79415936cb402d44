//! The analysis of one cycle on the uniform grid: the net apparent heat
//! release (single zone, first law), the burn points by the min–max rule,
//! the pressure rise and the gross work (PHYSICS.md "Combustion").

use crate::knock::{Knock, KnockFigures, Unresolved};
use crate::sweep::{ByPoint, Linear};
use crate::wall::{Trapped, WallHeat};
use crate::{CombustionError, GammaModel, Smoothing, check_range, smooth::Filter};
use wide::{CmpGt, CmpLt};

/// The burn levels reported by default (percent).
pub const DEFAULT_LEVELS: [f64; 4] = [5.0, 10.0, 50.0, 90.0];
/// The default burn window (deg from firing TDC).
pub const DEFAULT_WINDOW: (f64, f64) = (-90.0, 120.0);
/// A cycle burns when its heat released is at least this share of
/// `p_max V(p_max) / (γ − 1)`, the charge's energy at the peak.
pub const NO_COMBUSTION_SHARE: f64 = 0.05;
/// SOC: the last burnt fraction at or under this before CA50.
pub const SOC_FRACTION: f64 = 0.005;
/// EOC: the first burnt fraction at or over this after CA50.
pub const EOC_FRACTION: f64 = 0.995;
/// The burn points are null when the trace's noise leaves CA50 uncertain
/// by more than this (deg, one standard uncertainty).
pub const MAX_CA50_UNCERTAINTY_DEG: f64 = 1.0;
/// Nor is a release resolved under this many standard deviations of the
/// cumulative's noise at the window's largest volume.
pub const NOISE_FLOOR: f64 = 10.0;
/// The most points the smoothing filter may span: each point of the
/// analysis and the curves is a dot product of this many weights, so the
/// bound keeps a cycle under a second at any step.
pub const MAX_FILTER_POINTS: usize = 401;

/// How a cycle is analysed.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// The γ model.
    pub gamma: GammaModel,
    /// The smoothing before any derivative and the SOC/EOC search.
    pub smoothing: Smoothing,
    /// The burn window (deg from firing TDC): SOC and EOC lie inside it.
    pub window_deg: (f64, f64),
    /// The burn levels to report (percent, 1–99, rising).
    pub levels_pct: Vec<f64>,
    /// The wall-heat model: with one, the burn points come from the gross
    /// cumulative (`None`: the net figures).
    pub wall_heat: Option<WallHeat>,
    /// Knock: MAPO and IMPO of each cycle (`None`, the default: not
    /// measured; it costs an FFT pair a cycle).
    pub knock: Option<Knock>,
    /// The speed (rpm) of a cycle whose grid gives none
    /// ([`CycleGrid::rpm`]): the command line's or the engine file's. The
    /// wall heat and knock need one.
    pub rpm: Option<f64>,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            gamma: GammaModel::default(),
            smoothing: Smoothing::default(),
            window_deg: DEFAULT_WINDOW,
            levels_pct: DEFAULT_LEVELS.to_vec(),
            wall_heat: None,
            knock: None,
            rpm: None,
        }
    }
}

impl Options {
    /// Checks every part: γ, the filter, the window (within −180…180°,
    /// at least 10° long) and the levels (1–99 %, at most 16).
    pub fn check(&self) -> Result<(), CombustionError> {
        self.gamma.check()?;
        self.smoothing.check()?;
        let (a, b) = self.window_deg;
        check_range("burn window start", a, -180.0, 170.0)?;
        check_range("burn window end", b, a + 10.0, 180.0)?;
        if self.levels_pct.is_empty() || self.levels_pct.len() > 16 {
            return Err(CombustionError::Input(format!(
                "{} burn levels: give 1 to 16",
                self.levels_pct.len()
            )));
        }
        for &l in &self.levels_pct {
            check_range("burn level (%)", l, 1.0, 99.0)?;
        }
        if let Some(w) = &self.wall_heat {
            w.check()?;
        }
        if let Some(k) = &self.knock {
            k.check()?;
        }
        Ok(())
    }

    /// Checks what depends on the grid: [`Self::check_filter`] and
    /// [`Self::check_window`].
    pub fn check_grid(&self, step_deg: f64, cycle_deg: f64) -> Result<(), CombustionError> {
        self.check_filter(step_deg)?;
        self.check_window(step_deg, cycle_deg)
    }

    /// The filter spans at most [`MAX_FILTER_POINTS`] points at `step_deg`.
    pub fn check_filter(&self, step_deg: f64) -> Result<(), CombustionError> {
        let points = 2 * self.smoothing.half_points(step_deg) + 1;
        if let (true, Smoothing::SavitzkyGolay { width_deg }) =
            (points > MAX_FILTER_POINTS, self.smoothing)
        {
            return Err(CombustionError::Input(format!(
                "--smooth SG:{} at a {}° step spans {points} points, over the {MAX_FILTER_POINTS} the analysis takes: \
                 a width up to {}° at this step, or a coarser --step",
                enginedyn_numerics::format::human(width_deg),
                enginedyn_numerics::format::human(step_deg),
                enginedyn_numerics::format::human((MAX_FILTER_POINTS - 1) as f64 * step_deg)
            )));
        }
        Ok(())
    }

    /// The window holds at least 5 grid points of `step_deg` and less
    /// than the cycle.
    pub fn check_window(&self, step_deg: f64, cycle_deg: f64) -> Result<(), CombustionError> {
        let (i0, i1) = window_indices(step_deg, self.window_deg);
        if i1 - i0 < 4 || (i1 - i0) as f64 * step_deg >= cycle_deg {
            return Err(CombustionError::Input(format!(
                "the burn window {}:{} does not fit the {}° cycle at a {}° step: it needs at least 5 grid points",
                self.window_deg.0, self.window_deg.1, cycle_deg, step_deg
            )));
        }
        Ok(())
    }

    /// The index of a level (percent) among [`Self::levels_pct`].
    pub fn level_index(&self, pct: f64) -> Option<usize> {
        self.levels_pct.iter().position(|l| (l - pct).abs() < 1e-9)
    }
}

/// One cycle's pressure on the grid `k * step_deg` from firing TDC, with
/// the volume law on the same grid.
#[derive(Debug, Clone, Copy)]
pub struct CycleGrid<'a> {
    /// Absolute pressure (Pa), one cycle, periodic.
    pub pressure: &'a [f64],
    /// Volume (m³).
    pub volume: &'a [f64],
    /// `dV/dφ` (m³/rad).
    pub dvolume: &'a [f64],
    /// Grid step (deg).
    pub step_deg: f64,
    /// The speed over this cycle (rpm): the wall heat needs it (`dt/dφ`,
    /// the mean piston speed), and knock (the band in degrees).
    pub rpm: Option<f64>,
    /// The spacing of the samples the grid was made from (deg; `None`: the
    /// grid's own step): knock needs samples that resolve its band.
    pub sample_step_deg: Option<f64>,
}

impl<'a> CycleGrid<'a> {
    /// A cycle on its grid without a speed, its samples at the grid's own
    /// step (no wall heat by time, no knock): what a study of one diagram
    /// on its grid gives.
    pub fn new(pressure: &'a [f64], volume: &'a [f64], dvolume: &'a [f64], step_deg: f64) -> Self {
        Self {
            pressure,
            volume,
            dvolume,
            step_deg,
            rpm: None,
            sample_step_deg: None,
        }
    }

    fn n(&self) -> i64 {
        self.pressure.len() as i64
    }
    fn cycle_deg(&self) -> f64 {
        self.pressure.len() as f64 * self.step_deg
    }
    #[inline]
    fn at(&self, v: &[f64], k: i64) -> f64 {
        v[wrap(k, self.n())]
    }
}

/// `k` wrapped into `0..n` (a compare, not a division, for the indices
/// within a cycle of the grid that the analysis uses).
#[inline]
pub(crate) fn wrap(k: i64, n: i64) -> usize {
    if k < 0 {
        (if k >= -n { k + n } else { k.rem_euclid(n) }) as usize
    } else if k >= n {
        (if k < 2 * n { k - n } else { k.rem_euclid(n) }) as usize
    } else {
        k as usize
    }
}

/// The burn points of a cycle that burns.
#[derive(Debug, Clone, PartialEq)]
pub struct BurnPoints {
    /// Start of combustion (deg): the last angle before CA50 where the
    /// burnt fraction is at most [`SOC_FRACTION`], interpolated.
    pub soc_deg: f64,
    /// End of combustion (deg): the first angle after CA50 where the
    /// burnt fraction reaches [`EOC_FRACTION`], interpolated.
    pub eoc_deg: f64,
    /// The angle of each level of [`Options::levels_pct`] (deg), in order.
    pub levels_deg: Vec<f64>,
    /// The largest dp/dφ between SOC and EOC (Pa/°).
    pub dp_max_pa_deg: f64,
    /// Its angle (deg).
    pub dp_max_angle_deg: f64,
    /// SOC lies on the window's start: the burn may start before it.
    pub cut_at_start: bool,
    /// EOC lies on the window's end: the burn runs past it, and the heat
    /// released and the late burn points are cut short.
    pub cut_at_end: bool,
}

impl BurnPoints {
    /// The angle of level `pct` when it was asked for.
    pub fn level(&self, opts: &Options, pct: f64) -> Option<f64> {
        opts.level_index(pct).map(|i| self.levels_deg[i])
    }
}

/// What one cycle says of its combustion.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleBurn {
    /// `Q_max − Q_min` (J) of the smoothed cumulative in the window,
    /// whether or not it clears the bound.
    pub heat_released_j: f64,
    /// The no-combustion bound (J): `0.05 p_max V(p_max) / (γ − 1)`.
    pub bound_j: f64,
    /// The trace's noise (Pa): the RMS residual of the smoothing fit over
    /// the window, scaled to one sample's.
    pub noise_pa: f64,
    /// The standard uncertainty of CA50 (deg) that the noise gives, when
    /// the heat released clears the bound.
    pub ca50_uncertainty_deg: Option<f64>,
    /// The heat released clears the bound, but the noise hides the burn:
    /// CA50 uncertain by more than [`MAX_CA50_UNCERTAINTY_DEG`], or the
    /// release under [`NOISE_FLOOR`] σ of the cumulative's noise.
    pub unresolved: bool,
    /// The burn points; `None` when the heat released is under the bound,
    /// or [`Self::unresolved`].
    pub burn: Option<BurnPoints>,
    /// `∫ p dV` over −180…180° (J): the gross work (the whole cycle for a
    /// two-stroke).
    pub gross_work_j: f64,
    /// With a wall-heat model: `Q_max − Q_min` of the gross cumulative
    /// (J), whose burn points [`Self::burn`] then are.
    pub heat_released_gross_j: Option<f64>,
    /// With a wall-heat model: the heat lost to the walls between SOC and
    /// EOC (J), when the cycle burns.
    pub wall_heat_j: Option<f64>,
    /// Knock, when measured: its figures, or why the data do not resolve
    /// the band.
    pub knock: Option<Result<KnockFigures, Unresolved>>,
}

/// The buffers of one cycle's analysis, kept from cycle to cycle (one
/// set a thread: [`analyse_with`] allocates nothing once they have grown to
/// the window).
#[derive(Debug, Default)]
struct Scratch {
    /// The window's pressure with the filter's reach either side
    /// ([`Filter::reach`]): window index `j` is `pw[j + reach]` (the
    /// plain weight sums' pass only).
    pw: Vec<f64>,
    /// The smoothed pressure (Pa) at every window point, when the wall
    /// heat wants it (the plain pass: always).
    ps: Vec<f64>,
    /// The smoothed cumulative (J), one value a window point.
    qs: Vec<f64>,
    /// The smoothed slope (Pa/°): with the running sums at every window
    /// point ([`crate::sweep`]), else over the span the pressure rise
    /// searches only.
    slope: Vec<f64>,
    /// [`Self::slope`] holds every window point's.
    slopes: bool,
    /// The wall heat's cumulative (J), one value a window point.
    wall: Vec<f64>,
    /// The sweep's own buffers.
    sweep: crate::sweep::Bufs,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::default();
}

/// `out` becomes `v[start..start + len]` of the periodic `v`, in at most a
/// few contiguous copies (no per-point wrap).
pub(crate) fn copy_periodic(v: &[f64], start: i64, len: usize, out: &mut Vec<f64>) {
    out.clear();
    let n = v.len();
    let mut k = wrap(start, n as i64);
    while out.len() < len {
        let take = (n - k).min(len - out.len());
        out.extend_from_slice(&v[k..k + take]);
        k = 0;
    }
}

/// The cumulative heat release over the window, smoothed: the work `∫ p
/// dV` from the pressure as read (an integral needs no smoothing), the
/// energy term `E(pV)` from the smoothed pressure. Its reference (the
/// value at the window's start) cancels in every figure.
struct Window<'a> {
    g: &'a CycleGrid<'a>,
    f: &'a Filter,
    /// First grid index of the window (may be negative: it wraps).
    i0: i64,
    /// `i0` wrapped into the cycle: the window starts there in the volume
    /// law.
    k0: usize,
    /// The window's pressure, smoothed pressure and smoothed cumulative
    /// ([`Scratch`]).
    s: &'a mut Scratch,
    /// The cumulative's extremes ([`extremes`]) when the pass found them
    /// (`None` once the cumulative has changed).
    extremes: Option<(usize, usize)>,
    /// The largest pressure in the window and its index.
    peak: (f64, usize),
    /// The sum of squared residuals `p − p_smooth` of the noise fit.
    residual2: f64,
    /// `Σ (h dV)²` over the window (m⁶): the work's noise gain.
    dv2: f64,
    /// The largest volume in the window (m³).
    v_max: f64,
    /// The SOC/EOC searches may rest on bounds of the band ([`rule`]):
    /// false only in a test, which checks they change no answer.
    v_bounds: bool,
}

/// What [`pass`] finds besides the cumulative.
struct Passed {
    /// The largest pressure in the window and its index.
    peak: (f64, usize),
    /// `Σ (p − fit)²`, `Σ (h dV)²` and the largest volume.
    sums: [f64; 3],
    /// The cumulative's extremes ([`extremes`]).
    extremes: (usize, usize),
}

/// The running figures of [`piece`], carried from one piece of the volume
/// law to the next: the work, the last `p dV/dφ`, `Σ (p − p_smooth)²`,
/// `Σ (h dV)²` and the largest volume (at least 0).
#[derive(Clone, Copy)]
struct Acc {
    work: f64,
    prev: f64,
    res2: f64,
    dv2: f64,
    v_max: f64,
}

/// The one pass over the window: the trapezoidal work `∫ p dV`, the
/// smoothed pressure and with it the energy term, the residuals of the
/// noise fit and the volume law's sums; then the pressure peak and the
/// cumulative's extremes. A filter with running sums takes
/// [`crate::sweep`] (everything in one sweep; the volume law's figures
/// from `law` when given; the smoothed pressure kept when `want_ps`), then
/// [`extremes_adding`]. Else (the plain weight sums: a narrow filter, none,
/// or the tests' reference) the window's pressure (with the filter's reach
/// either side) is copied out once and smoothed, the volume law read in
/// its (at most two) contiguous pieces, the peak and the extremes each a
/// scan of its own ([`first_max`], [`extremes`]).
fn pass<E: crate::sweep::Energy>(
    g: &CycleGrid,
    f: &Filter,
    (i0, i1): (i64, i64),
    e: &E,
    s: &mut Scratch,
    (want_ps, law): (bool, Option<&WindowLaw>),
) -> Passed {
    let h = g.step_deg.to_radians();
    let len = (i1 - i0 + 1) as usize;
    if let Some(mo) = f.moments() {
        // The running sums: one sweep of everything ([`crate::sweep`]).
        let out = crate::sweep::Outs {
            qs: &mut s.qs,
            slope: &mut s.slope,
            ps: want_ps.then_some(&mut s.ps),
        };
        let given = law.map(|l| (l.dv2, l.v_max));
        let w = crate::sweep::sweep(
            g,
            mo,
            f.step_deg(),
            (i0, i1),
            e,
            (out, law.map(|l| &l.pairs[..])),
            &mut s.sweep,
        );
        s.slopes = true;
        let (dv2, v_max) = given.unwrap_or((w.dv2, w.v_max));
        return Passed {
            peak: w.peak,
            sums: [w.res2, dv2, v_max],
            extremes: extremes_adding(&mut s.qs, w.rest),
        };
    }
    let m = f.reach();
    copy_periodic(g.pressure, i0 - m as i64, len + 2 * m, &mut s.pw);
    s.ps.resize(len, 0.0);
    f.values_into(&s.pw, m, &mut s.ps);
    s.slopes = false;
    s.qs.resize(len, 0.0);
    let (n, k0) = (g.volume.len(), wrap(i0, g.n()));
    let a = Acc {
        work: 0.0,
        prev: s.pw[m] * g.dvolume[k0],
        res2: 0.0,
        dv2: 0.0,
        v_max: 0.0,
    };
    let first = (n - k0).min(len);
    let energy = |pv: f64| e.of(pv);
    let (pw, ps, qs) = (&s.pw[m..m + len], &s.ps[..], &mut s.qs[..]);
    let (q0, q1) = qs.split_at_mut(first);
    let law0 = (&g.volume[k0..k0 + first], &g.dvolume[k0..k0 + first]);
    let law1 = (&g.volume[..len - first], &g.dvolume[..len - first]);
    let a = piece(a, true, (&pw[..first], &ps[..first], q0), law0, h, &energy);
    let mut a = piece(
        a,
        first == 0,
        (&pw[first..], &ps[first..], q1),
        law1,
        h,
        &energy,
    );
    if !f.fits_by_value() {
        // The fit is the five-point one (the filter off): it takes no
        // smoothed value, the slice only gives the count.
        a.res2 = f.residual2_in(&s.pw, m, &s.pw[m..m + len]);
    }
    Passed {
        peak: first_max(pw),
        sums: [a.res2, a.dv2, a.v_max],
        extremes: extremes(&s.qs),
    }
}

/// [`pass`] over the window points that lie on one contiguous piece `(V,
/// dV)` of the volume law (`start`: the piece begins the window, whose
/// first point adds no trapezoid).
#[inline(always)]
fn piece(
    mut a: Acc,
    start: bool,
    (pw, ps, qs): (&[f64], &[f64], &mut [f64]),
    (v, dv): (&[f64], &[f64]),
    h: f64,
    energy: &impl Fn(f64) -> f64,
) -> Acc {
    let point = |a: &mut Acc, q: &mut f64, p: f64, ps: f64, v: f64, dv: f64, first: bool| {
        let pdv = p * dv;
        if !first {
            a.work += 0.5 * h * (a.prev + pdv);
        }
        a.prev = pdv;
        let r = p - ps;
        a.res2 += r * r;
        a.dv2 += (h * dv) * (h * dv);
        // As `f64::max` (a NaN volume is passed over), in one compare.
        if v > a.v_max {
            a.v_max = v;
        }
        *q = a.work + energy(ps * v);
    };
    let skip = usize::from(start && !qs.is_empty());
    if skip == 1 {
        point(&mut a, &mut qs[0], pw[0], ps[0], v[0], dv[0], true);
    }
    let law = v[skip..].iter().zip(&dv[skip..]);
    for (((q, &p), &ps), (&v, &dv)) in qs[skip..]
        .iter_mut()
        .zip(&pw[skip..])
        .zip(&ps[skip..])
        .zip(law)
    {
        point(&mut a, q, p, ps, v, dv, false);
    }
    a
}

/// The largest value of `x` and its index (the first, if tied; NaN passed
/// over; `(−∞, 0)` when none is over −∞), as a running `if x > max` finds
/// them, in scans that vectorise: each block's largest in four lanes, the
/// first block that holds the largest, then its first index there.
fn first_max(x: &[f64]) -> (f64, usize) {
    let (top, block) = block_extreme(x, f64::NEG_INFINITY, |v, m| v > m);
    if top == f64::NEG_INFINITY {
        return (top, 0);
    }
    let at = first_equal(x, block * BLOCK, top);
    (x[at], at)
}

/// The points a block of [`block_extreme`] spans.
const BLOCK: usize = 64;

/// The extreme of `x` by `better` (a strict compare: `v > m`) from
/// `init`, and the first [`BLOCK`] that holds it (NaN passed over):
/// each block's extreme in four lanes, kept where it beats the blocks
/// before.
#[inline(always)]
fn block_extreme(x: &[f64], init: f64, better: impl Fn(f64, f64) -> bool) -> (f64, usize) {
    let (mut best, mut at) = (init, 0);
    for (b, block) in x.chunks(BLOCK).enumerate() {
        let mut lanes = [init; 4];
        let chunks = block.chunks_exact(4);
        let rest = chunks.remainder();
        for c in chunks {
            for (m, &v) in lanes.iter_mut().zip(c) {
                *m = if better(v, *m) { v } else { *m };
            }
        }
        for &v in lanes.iter().chain(rest) {
            if better(v, best) {
                best = v;
                at = b;
            }
        }
    }
    (best, at)
}

/// The first index of `x` from `from` on whose value equals `y` (the block
/// there holds one; ±0 equal, as the running compares take them).
fn first_equal(x: &[f64], from: usize, y: f64) -> usize {
    use wide::{CmpEq, f64x2};
    // Two points a compare (an ordered `==`: ±0 equal, NaN never).
    let yv = f64x2::splat(y);
    let pairs = x[from..].chunks_exact(2);
    let rest = pairs.remainder();
    for (k, c) in pairs.enumerate() {
        let m = f64x2::new([c[0], c[1]]).cmp_eq(yv).move_mask();
        if m != 0 {
            return from + 2 * k + m.trailing_zeros() as usize;
        }
    }
    let equal = |v: &f64| v.partial_cmp(&y) == Some(std::cmp::Ordering::Equal);
    match rest.iter().position(equal) {
        Some(i) => x.len() - rest.len() + i,
        None => from,
    }
}

impl Window<'_> {
    /// The pressure noise of one sample (Pa), from the fit's residuals: a
    /// least-squares fit keeps `1 − w₀` of white noise's variance in the
    /// residual (w₀ its centre weight).
    fn noise(&self) -> f64 {
        let n = self.s.qs.len() as f64;
        (self.residual2 / n / (1.0 - self.f.fit_centre())).sqrt()
    }

    /// The first index in `from..=to` where the cumulative reaches
    /// `target`, and the angle (deg) where it crosses, linearly
    /// interpolated from the point before.
    #[inline]
    fn rising(&self, from: usize, to: usize, target: f64) -> (usize, f64) {
        self.rising_by(from, to, |_| target, (target, target))
    }

    /// [`Self::rising`] to a level that may change along the window,
    /// within `(lo, hi)` over `from..=to`: a value under `lo` does not
    /// reach it, one at or over `hi` does where the volume is at least 0
    /// (the bounds of [`rule`] take σ at volume 0 for the band's least),
    /// without `target` taken there.
    #[inline]
    fn rising_by(
        &self,
        from: usize,
        to: usize,
        target: impl Fn(usize) -> f64,
        (lo, hi): (f64, f64),
    ) -> (usize, f64) {
        let qs = &self.s.qs[..=to];
        // Points under `lo` and not at or over `hi` stop no search: passed
        // over eight at a time ([`skip_rising`]).
        let mut j = skip_rising(qs, from, to, (lo, hi));
        while j < to {
            let q = qs[j];
            if (q >= hi && self.vol(j) >= 0.0) || (!(q < lo) && q >= target(j)) {
                break;
            }
            j += 1;
        }
        // `to` itself when nothing earlier reaches the level (as found or
        // not).
        let j = j.min(to);
        let t = if j == 0 {
            0.0
        } else {
            let (a, b, y) = (self.s.qs[j - 1], self.s.qs[j], target(j));
            if b > a {
                ((y - a) / (b - a)).clamp(0.0, 1.0)
            } else {
                1.0
            }
        };
        (j, self.deg(j as f64 - 1.0 + t))
    }

    /// The last index in `to..=from` (searching back from `from`) where
    /// the cumulative is at most `target(j)`, and the angle (deg) where it
    /// leaves that level, interpolated towards the next point; `target`
    /// lies within `(lo, hi)` over the span, as [`Self::rising_by`].
    #[inline]
    fn falling_by(
        &self,
        from: usize,
        to: usize,
        target: impl Fn(usize) -> f64,
        (lo, hi): (f64, f64),
    ) -> (usize, f64) {
        let qs = &self.s.qs[..=from];
        // Points over `hi` and not at or under `lo` stop no search: passed
        // over eight at a time ([`skip_falling`]).
        let mut j = skip_falling(qs, from, to, (lo, hi));
        while j > to {
            let q = qs[j];
            if (q <= lo && self.vol(j) >= 0.0) || (!(q > hi) && q <= target(j)) {
                break;
            }
            j -= 1;
        }
        let j = j.max(to);
        let t = if j + 1 < self.s.qs.len() {
            let (a, b, y) = (self.s.qs[j], self.s.qs[j + 1], target(j));
            if b > a {
                ((y - a) / (b - a)).clamp(0.0, 1.0)
            } else {
                0.0
            }
        } else {
            0.0
        };
        (j, self.deg(j as f64 + t))
    }

    /// The burn runs past the window's start (`start`) or end: the
    /// extreme lies within a degree of that edge, and the cumulative
    /// changes there by more than the SOC/EOC band (0.5 % of the heat) over
    /// two degrees.
    fn cut(&self, extreme: usize, released: f64, start: bool) -> bool {
        let last = self.s.qs.len() - 1;
        let deg = |d: f64| ((d / self.g.step_deg).round() as usize).clamp(1, last);
        let (one, two) = (deg(1.0), deg(2.0));
        let band = SOC_FRACTION * released;
        if start {
            extreme <= one && self.s.qs[two] - self.s.qs[0] > band
        } else {
            extreme + one >= last && self.s.qs[last] - self.s.qs[last - two] > band
        }
    }

    /// The volume (m³) at window index `j`.
    #[inline]
    fn vol(&self, j: usize) -> f64 {
        let (v, k) = (self.g.volume, self.k0 + j);
        v[if k >= v.len() { k - v.len() } else { k }]
    }

    /// The angle (deg) of window index `j` (fractional).
    fn deg(&self, j: f64) -> f64 {
        (self.i0 as f64 + j) * self.g.step_deg
    }
}

/// The first index from `from` (by eights, before `to`) at which a point
/// of the next eight may stop [`Window::rising_by`]: each point passed
/// over lies under `lo` and not at or over `hi` (a NaN `lo` passes none).
#[inline]
fn skip_rising(qs: &[f64], from: usize, to: usize, (lo, hi): (f64, f64)) -> usize {
    // `q < lo && !(q >= hi)` as one compare `q < under`.
    let under = match (lo.is_nan(), hi.is_nan()) {
        (true, _) => f64::NAN,
        (false, true) => lo,
        (false, false) => lo.min(hi),
    };
    skip_by_eights(qs, from, to, |x| x.cmp_lt(wide::f64x2::splat(under)))
}

/// [`skip_rising`] for [`Window::falling_by`], back from `from` (by
/// eights, after `to`): each point passed over lies over `hi` and not at
/// or under `lo` (a NaN `hi` passes none).
#[inline]
fn skip_falling(qs: &[f64], from: usize, to: usize, (lo, hi): (f64, f64)) -> usize {
    // `q > hi && !(q <= lo)` as one compare `q > over`.
    let over = match (hi.is_nan(), lo.is_nan()) {
        (true, _) => f64::NAN,
        (false, true) => hi,
        (false, false) => hi.max(lo),
    };
    if from < to + 8 {
        return from;
    }
    // The same scan on the reversed span: index `from − i` is `i` there.
    let span = &qs[to + 1..=from];
    let back = span.len() - skip_by_eights_rev(span, |x| x.cmp_gt(wide::f64x2::splat(over)));
    to + back
}

/// The first index from `from` by eights (before `to`) whose eight points
/// do not all pass `pass` (a lane mask, two points at a time).
#[inline(always)]
fn skip_by_eights(
    qs: &[f64],
    from: usize,
    to: usize,
    pass: impl Fn(wide::f64x2) -> wide::f64x2,
) -> usize {
    use wide::f64x2;
    let mut j = from;
    while j + 8 <= to {
        let c = &qs[j..j + 8];
        let m = pass(f64x2::new([c[0], c[1]]))
            & pass(f64x2::new([c[2], c[3]]))
            & pass(f64x2::new([c[4], c[5]]))
            & pass(f64x2::new([c[6], c[7]]));
        if m.move_mask() != 0b11 {
            break;
        }
        j += 8;
    }
    j
}

/// How many points at the end of `span` pass `pass`, counted by eights
/// (a multiple of 8: the last eight that do not all pass ends the count).
#[inline(always)]
fn skip_by_eights_rev(span: &[f64], pass: impl Fn(wide::f64x2) -> wide::f64x2) -> usize {
    use wide::f64x2;
    let mut n = 0;
    while n + 8 <= span.len() {
        let c = &span[span.len() - n - 8..span.len() - n];
        let m = pass(f64x2::new([c[0], c[1]]))
            & pass(f64x2::new([c[2], c[3]]))
            & pass(f64x2::new([c[4], c[5]]))
            & pass(f64x2::new([c[6], c[7]]));
        if m.move_mask() != 0b11 {
            break;
        }
        n += 8;
    }
    n
}

/// The index range `[i0, i1]` of grid points inside `window_deg`.
fn window_indices(step: f64, (a, b): (f64, f64)) -> (i64, i64) {
    (
        (a / step - 1e-9).ceil() as i64,
        (b / step + 1e-9).floor() as i64,
    )
}

/// `pV` at intake valve closing, for γ(T) (1 for a constant γ: unused).
fn pv_ivc(g: &CycleGrid, opts: &Options, f: &Filter) -> Result<f64, CombustionError> {
    let GammaModel::Brunt { ivc_deg, .. } = opts.gamma else {
        return Ok(1.0);
    };
    let (p, v) = ivc_state(
        g,
        f,
        ivc_deg,
        "γ(T) cannot scale its temperature from there",
    )?;
    Ok(p * v)
}

/// The smoothed pressure and the volume at IVC, checked to be a state a
/// temperature can scale from: a pressure of at least
/// [`MIN_IVC_PRESSURE_PA`] and within a factor of [`IVC_PRESSURE_RATIO`]
/// of the mean around intake BDC (`why` says what needs it).
fn ivc_state(
    g: &CycleGrid,
    f: &Filter,
    ivc_deg: f64,
    why: &str,
) -> Result<(f64, f64), CombustionError> {
    let k = (ivc_deg / g.step_deg).round() as i64;
    let p = f.value(g.pressure, k);
    // Intake BDC lies 180° before firing TDC (both strokes): the grid's
    // samples within 6° of it, for the one rule of the mean there.
    let (half, bdc) = (
        (6.0 / g.step_deg).ceil() as i64,
        (-180.0 / g.step_deg).round() as i64,
    );
    let cycle = g.cycle_deg();
    let mean = enginedyn_numerics::intake_bdc_mean(
        (bdc - half..=bdc + half).map(|k| {
            (
                (k as f64 * g.step_deg).rem_euclid(cycle),
                g.at(g.pressure, k),
            )
        }),
        cycle,
    )
    .unwrap_or(0.0);
    let plausible = p >= MIN_IVC_PRESSURE_PA
        && (mean <= 0.0 || (p / mean <= IVC_PRESSURE_RATIO && mean / p <= IVC_PRESSURE_RATIO));
    if !plausible {
        return Err(CombustionError::Input(format!(
            "the pressure at intake valve closing ({ivc_deg}°) is {} bar, against {} bar around intake BDC: \
             {why} (a dropout or a wrong IVC?); check the trace there or set --ivc-deg",
            enginedyn_numerics::format::sig(p / 1e5, 3),
            enginedyn_numerics::format::sig(mean / 1e5, 3)
        )));
    }
    Ok((p, g.at(g.volume, k)))
}

/// The lowest pressure at IVC that γ(T) scales from (Pa).
pub const MIN_IVC_PRESSURE_PA: f64 = 0.1e5;
/// How far the pressure at IVC may lie from the mean around intake BDC
/// (a factor either way).
pub const IVC_PRESSURE_RATIO: f64 = 3.0;

fn cumulative<'a>(
    g: &'a CycleGrid<'a>,
    opts: &Options,
    f: &'a Filter,
    s: &'a mut Scratch,
    law: Option<&WindowLaw>,
) -> Result<Window<'a>, CombustionError> {
    if g.pressure.len() != g.volume.len() || g.pressure.len() != g.dvolume.len() {
        return Err(CombustionError::Input(
            "pressure and volume law of different lengths".into(),
        ));
    }
    opts.check_grid(g.step_deg, g.cycle_deg())?;
    let (i0, i1) = window_indices(g.step_deg, opts.window_deg);
    let ivc = pv_ivc(g, opts, f)?;
    let gamma = opts.gamma;
    let want_ps = opts.wall_heat.is_some();
    // The volume law's window figures, when given for this grid's law.
    let law = law.filter(|l| l.fits(g, (i0, i1), f));
    // A constant γ takes the product form (no call, no division).
    let passed = match gamma {
        GammaModel::Constant(c) => {
            let inv = 1.0 / (c - 1.0);
            pass(g, f, (i0, i1), &Linear(inv), s, (want_ps, law))
        }
        GammaModel::Brunt { .. } => {
            let e = ByPoint(|pv| gamma.energy(pv, ivc));
            pass(g, f, (i0, i1), &e, s, (want_ps, law))
        }
    };
    let [residual2, dv2, v_max] = passed.sums;
    Ok(Window {
        g,
        f,
        i0,
        k0: wrap(i0, g.n()),
        s,
        extremes: Some(passed.extremes),
        peak: passed.peak,
        residual2,
        dv2,
        v_max,
        v_bounds: true,
    })
}

/// Analyses one cycle (checked options: [`Options::check`]).
pub fn analyse(g: &CycleGrid, opts: &Options) -> Result<CycleBurn, CombustionError> {
    let f = Filter::new(opts.smoothing, g.step_deg);
    analyse_with(g, opts, &f)
}

/// The smoothed cumulative's extremes: the index of its largest value
/// (the first, if tied) and of the smallest before it (the first, if
/// tied), as a running minimum's index where the running maximum was last
/// raised gives them (NaN passed over; 0 for none): each block's largest
/// and smallest in one scan ([`block_bounds`]), then the blocks that hold
/// them.
fn extremes(qs: &[f64]) -> (usize, usize) {
    let mut blocks = [[0.0; 2]; MAX_BLOCKS];
    let size = block_size(qs.len());
    let nb = qs.len().div_ceil(size);
    for (b, c) in blocks.iter_mut().zip(qs.chunks(size)) {
        *b = block_bounds(c);
    }
    pick_extremes(qs, &blocks[..nb], size)
}

/// [`extremes`] after adding `rest.1` to the points from `rest.0` on, in
/// the same scan.
fn extremes_adding(qs: &mut [f64], (from, add): (usize, f64)) -> (usize, usize) {
    let mut blocks = [[0.0; 2]; MAX_BLOCKS];
    let size = block_size(qs.len());
    let nb = qs.len().div_ceil(size);
    let mut at = 0;
    for (b, c) in blocks.iter_mut().zip(qs.chunks_mut(size)) {
        let n = c.len();
        *b = if at >= from {
            block_bounds_adding(c, add)
        } else if at + n <= from {
            block_bounds(c)
        } else {
            // The block the second half starts in.
            for q in &mut c[from - at..] {
                *q += add;
            }
            block_bounds(c)
        };
        at += n;
    }
    pick_extremes(qs, &blocks[..nb], size)
}

/// At most this many blocks in [`extremes`]' scan.
const MAX_BLOCKS: usize = 128;

/// The points a block of [`extremes`] spans for `len` points: at least
/// 128, and no more than [`MAX_BLOCKS`] blocks.
fn block_size(len: usize) -> usize {
    len.div_ceil(MAX_BLOCKS).max(128)
}

/// `[largest, smallest]` of `c` (NaN passed over; −∞ and +∞ for none), in
/// four lanes.
#[inline(always)]
fn block_bounds(c: &[f64]) -> [f64; 2] {
    use wide::f64x2;
    let mut acc = Bounds::new();
    let fours = c.chunks_exact(4);
    let rest = fours.remainder();
    for q in fours {
        acc.take(f64x2::new([q[0], q[1]]), f64x2::new([q[2], q[3]]));
    }
    acc.end(rest)
}

/// [`block_bounds`] after adding `add` to each point (stored).
#[inline(always)]
fn block_bounds_adding(c: &mut [f64], add: f64) -> [f64; 2] {
    use wide::f64x2;
    let mut acc = Bounds::new();
    let plus = f64x2::splat(add);
    let mut fours = c.chunks_exact_mut(4);
    for q in &mut fours {
        let (a, b) = (
            f64x2::new([q[0], q[1]]) + plus,
            f64x2::new([q[2], q[3]]) + plus,
        );
        let (x, y) = (a.to_array(), b.to_array());
        q.copy_from_slice(&[x[0], x[1], y[0], y[1]]);
        acc.take(a, b);
    }
    let rest = fours.into_remainder();
    for q in rest.iter_mut() {
        *q += add;
    }
    acc.end(rest)
}

/// The running largest and smallest of [`block_bounds`], four lanes.
struct Bounds {
    hi: [wide::f64x2; 2],
    lo: [wide::f64x2; 2],
}

impl Bounds {
    #[inline(always)]
    fn new() -> Self {
        use wide::f64x2;
        Self {
            hi: [f64x2::splat(f64::NEG_INFINITY); 2],
            lo: [f64x2::splat(f64::INFINITY); 2],
        }
    }
    #[inline(always)]
    fn take(&mut self, a: wide::f64x2, b: wide::f64x2) {
        use crate::smooth::Lane;
        self.hi = [a.gt_max(self.hi[0]), b.gt_max(self.hi[1])];
        self.lo = [a.lt_min(self.lo[0]), b.lt_min(self.lo[1])];
    }
    /// The block's `[largest, smallest]`, with the points `rest` after the
    /// lanes'.
    #[inline(always)]
    fn end(self, rest: &[f64]) -> [f64; 2] {
        use crate::smooth::Lane;
        let (mut top, mut low) = (f64::NEG_INFINITY, f64::INFINITY);
        for x in self.hi {
            let [a, b] = x.to_array();
            top = a.gt_max(b.gt_max(top));
        }
        for x in self.lo {
            let [a, b] = x.to_array();
            low = a.lt_min(b.lt_min(low));
        }
        for &q in rest {
            top = q.gt_max(top);
            low = q.lt_min(low);
        }
        [top, low]
    }
}

/// [`extremes`] from the blocks' `[largest, smallest]` (`size` points
/// each): the first block that holds the largest and its first index
/// there; the smallest in the blocks before it and in its block up to
/// that index, and its first index.
fn pick_extremes(qs: &[f64], blocks: &[[f64; 2]], size: usize) -> (usize, usize) {
    let (mut top, mut bt) = (f64::NEG_INFINITY, 0);
    for (b, &[hi, _]) in blocks.iter().enumerate() {
        if hi > top {
            top = hi;
            bt = b;
        }
    }
    let jmax = if top == f64::NEG_INFINITY {
        0
    } else {
        first_equal(qs, bt * size, top)
    };
    let (mut low, mut bl) = (f64::INFINITY, 0);
    for (b, &[_, lo]) in blocks[..bt].iter().enumerate() {
        if lo < low {
            low = lo;
            bl = b;
        }
    }
    // Jmax's block up to it: its smallest, and where it first lies when it
    // is under the blocks' before.
    let part = qs.get((bt * size).min(jmax)..=jmax).unwrap_or(&[]);
    let [_, least] = block_bounds(part);
    let mut found = None;
    if least < low {
        low = least;
        found = Some(first_equal(qs, bt * size, least));
    }
    let jmin = match found {
        Some(j) => j,
        None if low == f64::INFINITY => 0,
        None => first_equal(qs, bl * size, low),
    };
    (jmin, jmax)
}

/// [`analyse`] with the filter built once for many cycles (and the
/// buffers kept from cycle to cycle, one set a thread).
pub fn analyse_with(
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
) -> Result<CycleBurn, CombustionError> {
    analyse_with_law(g, opts, f, None)
}

/// [`analyse_with`] with the volume law's window figures taken once for
/// many cycles ([`WindowLaw`]; used where it was made from this grid's
/// volume law and window, else each cycle takes its own): the same
/// numbers, bit for bit.
pub fn analyse_with_law(
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
    law: Option<&WindowLaw>,
) -> Result<CycleBurn, CombustionError> {
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut s) => analyse_in(g, opts, f, &mut s, law),
        Err(_) => analyse_in(g, opts, f, &mut Scratch::default(), law),
    })
}

/// The volume law's figures over the burn window (`Σ (h dV/dφ)²`, the
/// work's noise gain, and the largest volume), taken once for the many
/// cycles analysed on one law ([`analyse_with_law`]) instead of in each
/// cycle's pass; the same sums in the same order as the pass takes them.
/// It names the slices it was made from: it serves a grid whose volume
/// law is those very slices (the same memory, so it must not outlive
/// them: keep it beside the law it was made from), with the same window
/// and step.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowLaw {
    /// The addresses and length of the volume and `dV/dφ` slices.
    from: (usize, usize, usize),
    /// The grid step (deg), bit for bit, and the window's grid indices.
    step_bits: u64,
    window: (i64, i64),
    /// `Σ (h dV)²` (m⁶) and the largest volume (m³, at least 0).
    dv2: f64,
    v_max: f64,
    /// The filter's running sums it was laid out for (half the filter and
    /// the stretch, points; `None`: the filter takes none), and the law
    /// as the sweep's lanes read it ([`crate::sweep::law_pairs`]).
    stretch: Option<(usize, usize)>,
    pairs: Vec<[wide::f64x2; 2]>,
}

impl WindowLaw {
    /// The figures of the law `(volume, dvolume)` on a grid of `step_deg`
    /// over `opts`' burn window (`None` when the window does not fit the
    /// grid: [`Options::check_window`]).
    pub fn new(volume: &[f64], dvolume: &[f64], step_deg: f64, opts: &Options) -> Option<Self> {
        let n = volume.len();
        if dvolume.len() != n || n == 0 {
            return None;
        }
        opts.check_window(step_deg, n as f64 * step_deg).ok()?;
        let (i0, i1) = window_indices(step_deg, opts.window_deg);
        let h = step_deg.to_radians();
        let (mut dv2, mut v_max) = (0.0, 0.0);
        // The window's points in order: from its start to the cycle's end,
        // then on from the cycle's start.
        let (k0, len) = (wrap(i0, n as i64), (i1 - i0 + 1) as usize);
        let first = (n - k0).min(len);
        for (a, b) in [(k0, k0 + first), (0, len - first)] {
            for (&v, &d) in volume[a..b].iter().zip(&dvolume[a..b]) {
                dv2 += (h * d) * (h * d);
                if v > v_max {
                    v_max = v;
                }
            }
        }
        let m = opts.smoothing.half_points(step_deg);
        let stretch = crate::smooth::Moments::refresh_of(m).map(|l| (m, l));
        let pairs = stretch.map_or_else(Vec::new, |(_, l)| {
            crate::sweep::law_pairs(volume, dvolume, i0, len, l)
        });
        Some(Self {
            from: (volume.as_ptr() as usize, dvolume.as_ptr() as usize, n),
            step_bits: step_deg.to_bits(),
            window: (i0, i1),
            dv2,
            v_max,
            stretch,
            pairs,
        })
    }

    /// Made from `g`'s volume law (the same slices), step and window, for
    /// the filter `f`.
    fn fits(&self, g: &CycleGrid, window: (i64, i64), f: &Filter) -> bool {
        let from = (
            g.volume.as_ptr() as usize,
            g.dvolume.as_ptr() as usize,
            g.volume.len(),
        );
        self.from == from
            && self.step_bits == g.step_deg.to_bits()
            && self.window == window
            && self.stretch == f.moments().map(|mo| (mo.m, mo.refresh))
    }
}

/// [`analyse_with_law`] in the buffers `s`.
fn analyse_in(
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
    s: &mut Scratch,
    law: Option<&WindowLaw>,
) -> Result<CycleBurn, CombustionError> {
    let mut wall_buf = std::mem::take(&mut s.wall);
    let r = analyse_window(g, opts, f, s, &mut wall_buf, law);
    s.wall = wall_buf;
    r
}

/// [`analyse_in`], the wall heat's cumulative in `w`.
fn analyse_window(
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
    s: &mut Scratch,
    w: &mut Vec<f64>,
    law: Option<&WindowLaw>,
) -> Result<CycleBurn, CombustionError> {
    let mut win = cumulative(g, opts, f, s, law)?;
    let gross_work_j = gross_work(g);
    let mut net = rule(&mut win, g, opts, f, gross_work_j);
    let knock = opts.knock.as_ref().map(|k| {
        let rpm = g.rpm.or(opts.rpm).unwrap_or(0.0);
        let spacing = g.sample_step_deg.unwrap_or(g.step_deg);
        crate::knock::knock(g.pressure, g.step_deg, spacing, rpm, k)
    });
    let Some(wall) = &opts.wall_heat else {
        net.knock = knock;
        return Ok(net);
    };
    // The gross cumulative: the net one plus the heat lost to the walls
    // (Woschni's combustion term from the net SOC).
    let soc = net.burn.as_ref().map(|b| b.soc_deg);
    wall_cumulative(&win, g, opts, f, wall, soc, w)?;
    for (q, w) in win.s.qs.iter_mut().zip(w.iter()) {
        *q += w;
    }
    win.extremes = None;
    let mut gross = rule(&mut win, g, opts, f, gross_work_j);
    let at = |deg: f64| {
        let x = (deg / g.step_deg - win.i0 as f64).clamp(0.0, (w.len() - 1) as f64);
        let (j, t) = (x.floor() as usize, x.fract());
        w[j] + t * (w[(j + 1).min(w.len() - 1)] - w[j])
    };
    gross.wall_heat_j = gross.burn.as_ref().map(|b| at(b.eoc_deg) - at(b.soc_deg));
    gross.heat_released_gross_j = Some(gross.heat_released_j);
    gross.heat_released_j = net.heat_released_j;
    gross.knock = knock;
    Ok(gross)
}

/// The heat lost to the walls (J) from the window's start, at every
/// window point, into `out`: `dQ_wall/dφ` from the smoothed pressure,
/// integrated by the trapezoid.
fn wall_cumulative(
    win: &Window,
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
    wall: &WallHeat,
    soc_deg: Option<f64>,
    out: &mut Vec<f64>,
) -> Result<(), CombustionError> {
    let rpm = g.rpm.or(opts.rpm).filter(|r| r.is_finite() && *r > 0.0).ok_or_else(|| {
        CombustionError::Input(
            "the wall heat needs the engine's speed (dt/dφ and the mean piston speed): give --rpm".into(),
        )
    })?;
    let (p_ivc, v_ivc) = ivc_state(
        g,
        f,
        wall.ivc_deg,
        "the wall heat cannot take the trapped mass from there",
    )?;
    let gamma_ivc = opts.gamma.gamma(p_ivc * v_ivc, p_ivc * v_ivc);
    let s = Trapped {
        p_ivc,
        v_ivc,
        gamma_ivc,
        rpm,
    };
    let rate = wall.in_cycle(&s);
    let half = 0.5 * g.step_deg;
    out.clear();
    let (mut total, mut prev) = (0.0, 0.0);
    for (j, &p) in win.s.ps.iter().enumerate() {
        let (k, v) = (win.i0 + j as i64, win.vol(j));
        let burning = soc_deg.is_some_and(|soc| k as f64 * g.step_deg >= soc);
        let r = rate.rate(p, v, burning);
        if j > 0 {
            total += half * (prev + r);
        }
        prev = r;
        out.push(total);
    }
    Ok(())
}

/// The burn rule on the window's cumulative (PHYSICS "Burn points"): the
/// extremes, the no-combustion bound, the noise, the crossings, SOC and
/// EOC, and the pressure rise.
fn rule(
    win: &mut Window,
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
    gross_work_j: f64,
) -> CycleBurn {
    let (jmin, jmax) = win.extremes.unwrap_or_else(|| extremes(&win.s.qs));
    let (q_min, q_max) = (win.s.qs[jmin], win.s.qs[jmax]);
    let released = q_max - q_min;
    let gamma = opts.gamma.nominal();
    let (p_max, at) = win.peak;
    let bound = NO_COMBUSTION_SHARE * p_max * win.vol(at) / (gamma - 1.0);
    let noise = win.noise();
    let mut out = CycleBurn {
        heat_released_j: released,
        bound_j: bound,
        noise_pa: noise,
        ca50_uncertainty_deg: None,
        unresolved: false,
        burn: None,
        gross_work_j,
        heat_released_gross_j: None,
        wall_heat_j: None,
        knock: None,
    };
    if !(released >= bound) || jmax <= jmin {
        return out;
    }
    let x = |frac: f64| q_min + frac * released;
    // Each fraction's first crossing, searched from the crossing of the
    // largest fraction under it found so far (the cumulative reaches a
    // fraction no sooner than a smaller one), and found once.
    let mut known = [(0.0f64, 0usize, 0.0f64); 20];
    let mut count = 0;
    let mut crossing = |frac: f64| {
        let mut from = jmin + 1;
        for &(f, j, deg) in &known[..count] {
            if f.total_cmp(&frac).is_eq() {
                return (j, deg);
            }
            if f < frac {
                from = from.max(j);
            }
        }
        let (j, deg) = win.rising(from, jmax, x(frac));
        if count < known.len() {
            known[count] = (frac, j, deg);
            count += 1;
        }
        (j, deg)
    };
    // All in rising order first: one scan from the smallest cumulative up.
    let mut fracs = [1.0f64; 19];
    for (f, l) in fracs.iter_mut().zip(opts.levels_pct.iter().take(16)) {
        *f = l / 100.0;
    }
    let wanted = opts.levels_pct.len().min(16);
    fracs[wanted..wanted + 3].copy_from_slice(&[0.1, 0.5, 0.9]);
    let fracs = &mut fracs[..wanted + 3];
    fracs.sort_by(f64::total_cmp);
    for &f in fracs.iter() {
        crossing(f);
    }
    let ((_, ca10), (j50, _), (_, ca90)) = (crossing(0.1), crossing(0.5), crossing(0.9));
    // The noise carried into the smoothed cumulative at window index j:
    // the energy term's (the work integrates the noise away, nearly).
    let vol = |j: usize| win.vol(j);
    let sigma = |v: f64| v * f.gain() * noise / (gamma - 1.0);
    let sq = |j: usize| sigma(vol(j)).powi(2);
    // CA50's target is the extremes' mean; over the central burn the
    // cumulative rises 80 % of the heat in CA90 − CA10.
    let sigma_q = (sq(j50) + 0.25 * (sq(jmin) + sq(jmax)) + noise * noise * win.dv2).sqrt();
    let uncertainty = sigma_q * (ca90 - ca10).max(g.step_deg) / (0.8 * released);
    out.ca50_uncertainty_deg = Some(uncertainty);
    // A release under NOISE_FLOOR σ of the cumulative's noise where it is
    // largest (the window's largest volume) is not told from noise: a
    // step of noise passes for a burn of a degree.
    out.unresolved =
        !(uncertainty <= MAX_CA50_UNCERTAINTY_DEG) || released < NOISE_FLOOR * sigma(win.v_max);
    if out.unresolved {
        return out;
    }
    // The bands widen by the noise (3 σ of the cumulative at the extreme
    // it is measured from and where it is sought), so that noise on a
    // flat cumulative does not cross them; on a clean trace they are the
    // 0.5 % and 99.5 % of PHYSICS.
    let band = |at: usize, j: usize| 3.0 * (sigma(vol(at)) + sigma(vol(j)));
    // The bands' bounds over the window: σ rises with the volume (each
    // factor at least 0, and rounding keeps the order), so volume 0 and
    // the window's largest bound every point's band where the volume is
    // at least 0 (the searches check that where a bound decides; NaN
    // bounds leave every point to its own band).
    let bounds = |at: usize| {
        let a = sigma(vol(at));
        match win.v_bounds {
            true => (3.0 * (a + sigma(0.0)), 3.0 * (a + sigma(win.v_max))),
            false => (f64::NAN, f64::NAN),
        }
    };
    let (soc_band, eoc_band) = (bounds(jmin), bounds(jmax));
    let (x_soc, x_eoc) = (x(SOC_FRACTION), x(EOC_FRACTION));
    let (j_soc, soc) = win.falling_by(
        j50,
        jmin,
        |j| x(SOC_FRACTION) + band(jmin, j),
        (x_soc + soc_band.0, x_soc + soc_band.1),
    );
    let (j_eoc, eoc) = win.rising_by(
        j50,
        jmax,
        |j| x(EOC_FRACTION) - band(jmax, j),
        (x_eoc - eoc_band.1, x_eoc - eoc_band.0),
    );
    // Levels rise, so each search starts where the one below it crossed
    // (a level under the one before it, which the options do not allow,
    // is searched from there as ever).
    let mut below = (0.0, jmin + 1);
    let levels_deg = opts
        .levels_pct
        .iter()
        .map(|l| {
            let frac = l / 100.0;
            let (j, deg) = if frac >= below.0 {
                crossing(frac)
            } else {
                win.rising(below.1, jmax, x(frac))
            };
            below = (frac, j.max(jmin + 1));
            deg
        })
        .collect();
    let (dp_max, dp_at) = pressure_rise(win, j_soc, j_eoc);
    out.burn = Some(BurnPoints {
        soc_deg: soc,
        eoc_deg: eoc,
        levels_deg,
        dp_max_pa_deg: dp_max,
        dp_max_angle_deg: win.deg(dp_at),
        cut_at_start: win.cut(jmin, released, true),
        cut_at_end: win.cut(jmax, released, false),
    });
    out
}

/// The largest smoothed dp/dφ (Pa/°) between window indices `soc` and
/// `eoc` and its window index: the filter's own slope at every grid
/// point of that span (no coarser pre-search, which can step over a
/// diesel's premixed spike), refined by the parabola through the largest
/// and its neighbours.
fn pressure_rise(win: &mut Window, soc: usize, eoc: usize) -> (f64, f64) {
    // The slopes over the span and a point either side (the refinement's
    // neighbours), in one sweep.
    let last = win.s.qs.len() - 1;
    let (lo, hi) = (soc.saturating_sub(1), (eoc.max(soc) + 1).min(last));
    let buf = if win.s.slopes {
        &win.s.slope[lo..=hi]
    } else {
        let buf = &mut win.s.slope;
        buf.resize(hi - lo + 1, 0.0);
        win.f.slopes_into(&win.s.pw, lo + win.f.reach(), buf);
        &buf[..]
    };
    let slope = |j: usize| buf[j - lo];
    // The largest (the first, if tied) as a running `if s > top` from −∞
    // at SOC.
    let (top, at) = first_max(&buf[soc - lo..=eoc.max(soc) - lo]);
    let j_top = soc + at;
    let (mut value, mut x) = (top, j_top as f64);
    if j_top > 0 && j_top < last {
        let (a, c) = (slope(j_top - 1), slope(j_top + 1));
        let den = a - 2.0 * top + c;
        if den < 0.0 {
            let t = (0.5 * (a - c) / den).clamp(-0.5, 0.5);
            x += t;
            value = top - 0.25 * (a - c) * t;
        }
    }
    (value, x)
}

/// `∫ p dV` (J) over −180…180°, trapezoidal on `p dV/dφ` (the whole cycle
/// for a two-stroke; the ends lie at BDC, where `dV/dφ` is nearly 0).
pub fn gross_work(g: &CycleGrid) -> f64 {
    let h = g.step_deg.to_radians();
    let dot = |p: &[f64], d: &[f64]| p.iter().zip(d).map(|(p, d)| p * d).sum::<f64>();
    let n = g.pressure.len();
    let half = (180.0 / g.step_deg).round() as usize;
    if g.cycle_deg() <= 360.0 + 1e-9 || 2 * half >= n {
        return dot(g.pressure, g.dvolume) * h;
    }
    // −180…0 is the cycle's end, n − half … n − 1; 0…180 its start.
    let (p, d) = (g.pressure, g.dvolume);
    let ends = 0.5 * (p[n - half] * d[n - half] + p[half] * d[half]);
    (dot(&p[n - half..], &d[n - half..]) + dot(&p[..=half], &d[..=half]) - ends) * h
}

/// The heat release over the whole cycle, for `curves.csv` and the chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Curves {
    /// `dQ/dφ` (J/°) at every grid point, from the smoothed pressure and
    /// slope.
    pub rate_j_deg: Vec<f64>,
    /// `Q(φ) − Q_min` (J) inside the window; 0 before it, its end value
    /// after it.
    pub cumulative_j: Vec<f64>,
    /// The mass fraction burned: 0 before SOC, `xb` between SOC and EOC, 1
    /// after; `None` without combustion.
    pub mfb: Option<Vec<f64>>,
}

/// The heat-release curves of one cycle (typically the mean trace), with
/// its [`CycleBurn`].
pub fn curves(g: &CycleGrid, opts: &Options, burn: &CycleBurn) -> Result<Curves, CombustionError> {
    let f = Filter::new(opts.smoothing, g.step_deg);
    let mut scratch = Scratch::default();
    let w = cumulative(g, opts, &f, &mut scratch, None)?;
    let n = g.pressure.len();
    let ivc = pv_ivc(g, opts, &f)?;
    let deg_per_rad = 180.0 / std::f64::consts::PI;
    // The smoothed pressure and slope over the whole cycle, in one sweep
    // each over the cycle copied out with the filter's reach either side.
    let m = f.reach();
    let mut pc = Vec::new();
    copy_periodic(g.pressure, -(m as i64), n + 2 * m, &mut pc);
    let (mut ps, mut dps) = (vec![0.0; n], vec![0.0; n]);
    f.values_into(&pc, m, &mut ps);
    f.slopes_into(&pc, m, &mut dps);
    let mut rate = Vec::with_capacity(n);
    for (((&p, &dp), &v), &dv) in ps.iter().zip(&dps).zip(g.volume).zip(g.dvolume) {
        let dv = dv / deg_per_rad;
        let gm = opts.gamma.gamma(p * v, ivc);
        rate.push(gm / (gm - 1.0) * p * dv + v * dp / (gm - 1.0));
    }
    let qs = &w.s.qs;
    // The burnt fraction's reference: the smallest cumulative before the
    // largest (PHYSICS "Burn points").
    let base = qs[extremes(qs).0];
    let mut cumulative = vec![0.0; n];
    let mut mfb = burn.burn.as_ref().map(|_| vec![0.0; n]);
    let last = qs.len() - 1;
    let half = (n / 2) as i64;
    // Walk one cycle from the window's start `a = i0 + j`: inside the
    // window its values; after it (up to half a cycle), the end values;
    // the rest lies before the window (0).
    for j in 0..n {
        let a = w.i0 + j as i64;
        let k = a.rem_euclid(n as i64) as usize;
        let (q, x) = if j <= last {
            let q = qs[j] - base;
            let x = burn.burn.as_ref().map(|b| {
                let deg = a as f64 * g.step_deg;
                if deg < b.soc_deg {
                    0.0
                } else if deg > b.eoc_deg {
                    1.0
                } else {
                    (q / burn.heat_released_j).clamp(0.0, 1.0)
                }
            });
            (q, x)
        } else if a < half {
            (qs[last] - base, Some(1.0))
        } else {
            (0.0, Some(0.0))
        };
        cumulative[k] = q;
        if let (Some(m), Some(x)) = (mfb.as_mut(), x) {
            m[k] = x;
        }
    }
    Ok(Curves {
        rate_j_deg: rate,
        cumulative_j: cumulative,
        mfb,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{WallHeat, WallModel};
    use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};

    fn cylinder() -> Cylinder {
        let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
        Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap()
    }

    /// A closed charge (γ 1.33) from 1 bar at −180° burning `heat_j` by a
    /// Wiebe law from −10° over 50°, stepped on the grid itself; 1 bar on
    /// the gas-exchange half.
    fn fired(v: &[f64], step: f64, heat_j: f64) -> Vec<f64> {
        let n = v.len();
        let g = 1.33;
        let xb = |deg: f64| {
            let x = ((deg + 10.0) / 50.0).max(0.0);
            1.0 - (-5.0 * x * x * x).exp()
        };
        let mut p = vec![1e5; n];
        let k0 = n - (180.0 / step).round() as usize;
        let mut prev = (1e5, v[k0], xb(-180.0));
        for j in 1..=(360.0 / step).round() as usize {
            let k = (k0 + j) % n;
            let deg = -180.0 + j as f64 * step;
            let (q, vk) = (heat_j * xb(deg), v[k]);
            let pk = prev.0 + ((g - 1.0) * (q - prev.2) - g * prev.0 * (vk - prev.1)) / vk;
            p[k] = pk;
            prev = (pk, vk, q);
        }
        p
    }

    fn noise(p: &mut [f64], sd: f64, seed: u64) {
        let mut s = seed;
        for x in p {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            *x += sd * (((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5) * 3.46;
        }
    }

    /// The grid index of `deg` in a 720° cycle.
    fn at(deg: f64, step: f64, n: usize) -> usize {
        ((deg / step).round() as i64).rem_euclid(n as i64) as usize
    }

    fn close(a: f64, b: f64, rel: f64) -> bool {
        a.total_cmp(&b).is_eq() || (a - b).abs() <= rel * a.abs().max(b.abs())
    }

    /// Every output of the two analyses equal: within 1e-12 relative,
    /// angles within 1e-9°. The noise is a residual `p − p_smooth`, which
    /// neither sum gets closer than the rounding of `p`: within `1e-14
    /// p_max` (Pa), and the CA50 uncertainty (∝ the noise) by as much.
    fn same(a: &CycleBurn, b: &CycleBurn, what: &str, p_max: f64) {
        let rel = |x: f64, y: f64, name: &str| {
            assert!(close(x, y, 1e-12), "{what}: {name} {x} against {y}");
        };
        rel(a.heat_released_j, b.heat_released_j, "heat released");
        rel(a.bound_j, b.bound_j, "bound");
        let floor = 1e-14 * p_max;
        assert!(
            (a.noise_pa - b.noise_pa).abs() <= 1e-12 * a.noise_pa + floor,
            "{what}: noise {} against {}",
            a.noise_pa,
            b.noise_pa
        );
        let noise_rel = 1e-12 + floor / b.noise_pa;
        rel(a.gross_work_j, b.gross_work_j, "gross work");
        assert_eq!(a.unresolved, b.unresolved, "{what}");
        let opt = |x: Option<f64>, y: Option<f64>, name: &str| match (x, y) {
            (Some(x), Some(y)) => rel(x, y, name),
            (x, y) => assert_eq!(x, y, "{what}: {name}"),
        };
        if let (Some(x), Some(y)) = (a.ca50_uncertainty_deg, b.ca50_uncertainty_deg) {
            assert!(
                close(x, y, noise_rel),
                "{what}: CA50 uncertainty {x} against {y}"
            );
        }
        opt(
            a.ca50_uncertainty_deg.map(|_| 0.0),
            b.ca50_uncertainty_deg.map(|_| 0.0),
            "CA50 uncertainty",
        );
        opt(
            a.heat_released_gross_j,
            b.heat_released_gross_j,
            "gross heat",
        );
        opt(a.wall_heat_j, b.wall_heat_j, "wall heat");
        assert_eq!(a.burn.is_some(), b.burn.is_some(), "{what}: burns");
        if let (Some(x), Some(y)) = (&a.burn, &b.burn) {
            let deg = |x: f64, y: f64, name: &str| {
                assert!((x - y).abs() <= 1e-9, "{what}: {name} {x} against {y}");
            };
            deg(x.soc_deg, y.soc_deg, "SOC");
            deg(x.eoc_deg, y.eoc_deg, "EOC");
            for (l, (p, q)) in x.levels_deg.iter().zip(&y.levels_deg).enumerate() {
                deg(*p, *q, &format!("level {l}"));
            }
            rel(x.dp_max_pa_deg, y.dp_max_pa_deg, "dp/dφ max");
            deg(x.dp_max_angle_deg, y.dp_max_angle_deg, "dp/dφ max angle");
            assert_eq!(
                (x.cut_at_start, x.cut_at_end),
                (y.cut_at_start, y.cut_at_end),
                "{what}"
            );
        }
    }

    /// Woschni's wall heat on the test cylinder (the tests' one setting).
    fn woschni(cyl: &Cylinder) -> WallHeat {
        WallHeat {
            model: WallModel::Woschni,
            wall_temp_k: 450.0,
            intake_temp_k: 320.0,
            ivc_deg: -140.0,
            bore_m: 0.076,
            stroke_m: 0.071,
            swept_m3: cyl.swept_volume(),
        }
    }

    /// The analysis with the running sums against the same with the plain
    /// weight sums, on traces shaped to defeat them: noise, a premixed
    /// spike and a one-point spike, a flat stretch, a step, a long filter,
    /// a fine grid, the wall heat and γ(T), a motored cycle, a wide window.
    #[test]
    fn the_running_sums_give_the_plain_analysis() {
        let cyl = cylinder();
        let woschni = woschni(&cyl);
        let (mut checked, mut burning) = (0, 0);
        for step in [0.1f64, 0.05] {
            let n = (720.0 / step).round() as usize;
            let (v, dv) = cyl.fill_volume(step.to_radians(), n);
            let clean = fired(&v, step, 600.0);
            let mut traces: Vec<(&str, Vec<f64>)> = vec![("clean", clean.clone())];
            let mut p = clean.clone();
            noise(&mut p, 0.05e5, 7);
            traces.push(("noisy", p.clone()));
            // A premixed spike of 10 bar (σ 0.2°) at 3°, one point of 30 bar
            // at 20°.
            for (k, x) in p.iter_mut().enumerate() {
                let deg = if k as f64 * step >= 360.0 {
                    k as f64 * step - 720.0
                } else {
                    k as f64 * step
                };
                *x += 10e5 * (-(deg - 3.0) * (deg - 3.0) / 0.08).exp();
            }
            p[at(20.0, step, n)] += 30e5;
            traces.push(("spikes", p));
            let mut p = clean.clone();
            let (a, b) = (at(15.0, step, n), at(35.0, step, n));
            let flat = p[a];
            p[a..b].fill(flat);
            traces.push(("flat", p));
            let mut p = clean.clone();
            p[at(40.0, step, n)..at(180.0, step, n)]
                .iter_mut()
                .for_each(|x| *x += 3e5);
            traces.push(("step", p));
            traces.push(("motored", fired(&v, step, 0.0)));
            let options = [
                Options::default(),
                Options {
                    smoothing: Smoothing::SavitzkyGolay { width_deg: 20.0 },
                    ..Options::default()
                },
                Options {
                    smoothing: Smoothing::SavitzkyGolay { width_deg: 5.0 },
                    gamma: GammaModel::Brunt {
                        intake_temp_k: 320.0,
                        ivc_deg: -140.0,
                    },
                    wall_heat: Some(woschni),
                    rpm: Some(2000.0),
                    ..Options::default()
                },
                Options {
                    wall_heat: Some(WallHeat {
                        model: WallModel::Hohenberg,
                        ..woschni
                    }),
                    rpm: Some(2000.0),
                    window_deg: (-170.0, 170.0),
                    ..Options::default()
                },
            ];
            for (name, p) in &traces {
                for opts in &options {
                    if opts.check_filter(step).is_err() {
                        continue;
                    }
                    let g = CycleGrid::new(p, &v, &dv, step);
                    let f = Filter::new(opts.smoothing, step);
                    let what = format!("{name} at {step}°, {:?}", opts.smoothing);
                    let fast = analyse_with(&g, opts, &f).unwrap();
                    let plain = analyse_with(&g, opts, &f.clone().plain()).unwrap();
                    let p_max = p.iter().fold(0.0f64, |a, x| a.max(*x));
                    same(&fast, &plain, &what, p_max);
                    // With the volume law's window figures given.
                    let law = WindowLaw::new(&v, &dv, step, opts).unwrap();
                    let given = analyse_with_law(&g, opts, &f, Some(&law)).unwrap();
                    same(&given, &plain, &format!("{what}, the law given"), p_max);
                    burning += usize::from(fast.burn.is_some());
                    // The cumulative itself, point by point.
                    let (mut s1, mut s2) = (Scratch::default(), Scratch::default());
                    let plain_f = f.clone().plain();
                    let mut w1 = cumulative(&g, opts, &f, &mut s1, None).unwrap();
                    let w2 = cumulative(&g, opts, &plain_f, &mut s2, None).unwrap();
                    let scale = w2.s.qs.iter().fold(0.0f64, |a, q| a.max(q.abs()));
                    for (j, (a, b)) in w1.s.qs.iter().zip(&w2.s.qs).enumerate() {
                        assert!(
                            (a - b).abs() <= 1e-12 * scale,
                            "{what}: Q at {j}: {a} against {b}"
                        );
                    }
                    // The SOC/EOC searches' bounds change no answer: the
                    // rule with them voided gives the same figures.
                    let bounded = rule(&mut w1, &g, opts, &f, 0.0);
                    w1.v_bounds = false;
                    assert_eq!(bounded, rule(&mut w1, &g, opts, &f, 0.0), "{what}");
                    checked += 1;
                }
            }
        }
        assert!(checked >= 40 && burning >= 30, "{checked} {burning}");
    }

    /// The sweep ([`crate::sweep`]) against the plain pass and the filter's
    /// own sweep ([`Filter::values_slopes_into`]), the serial work and
    /// energy term, and the scans, on traces shaped to defeat it:
    /// noise, a one-point spike of 10⁴ bar, a flat top tied over several
    /// stretches, a NaN and an infinite sample, a motored cycle; windows
    /// that lie over the cycle's end or not, whose filter's reach does, of
    /// one stretch or a few, across nearly a whole two-stroke cycle; both
    /// lanes' tails; filters of 8, 10, 20 and 100 points either side; with
    /// the volume law's figures given and taken. The largest pressure
    /// (value and index) and the largest volume are the plain pass's bit
    /// for bit, `Σ (h dV)²` too when given (else within 1e-13: two lanes'
    /// sums); the smoothed pressure and slope the filter's sweep's bit for
    /// bit (a NaN stays in its stretch's running sums, as there); the
    /// cumulative point by point within 1e-12 of its largest (the second
    /// lane's work added after), the residuals' sum within 1e-12 relative,
    /// and the extremes the same points (or points whose cumulatives agree
    /// within 1e-12 of the largest: a tie the rounding settles).
    #[test]
    fn the_sweep_gives_the_plain_pass() {
        let cyl = cylinder();
        let woschni = woschni(&cyl);
        let mut checked = 0;
        for (cycle, step) in [(720.0f64, 0.1f64), (720.0, 0.05), (360.0, 0.1)] {
            let n = (cycle / step).round() as usize;
            let (v, dv) = cyl.fill_volume(step.to_radians(), n);
            let deg = |k: usize| {
                let d = k as f64 * step;
                if d >= cycle / 2.0 { d - cycle } else { d }
            };
            let clean = if cycle > 360.0 {
                fired(&v, step, 600.0)
            } else {
                (0..n)
                    .map(|k| 1e5 + 4e6 * (-(deg(k) - 8.0).powi(2) / 400.0).exp())
                    .collect()
            };
            let mut traces: Vec<(&str, Vec<f64>)> = vec![("clean", clean.clone())];
            let mut p = clean.clone();
            noise(&mut p, 0.05e5, 11);
            traces.push(("noisy", p));
            let mut p = clean.clone();
            p[at(5.0, step, n)] = 1e9;
            traces.push(("spike", p));
            let mut p = clean.clone();
            let top = p.iter().fold(0.0f64, |a, x| a.max(*x));
            let (a, b) = (at(-20.0, step, n), at(30.0, step, n));
            let (a, b) = (a.min(b), a.max(b));
            p[a..b].fill(top);
            traces.push(("flat top", p));
            let mut p = clean.clone();
            p[at(-30.0, step, n)] = f64::NAN;
            traces.push(("NaN", p));
            let mut p = clean.clone();
            p[at(60.0, step, n)] = f64::INFINITY;
            traces.push(("infinite", p));
            if cycle > 360.0 {
                traces.push(("motored", fired(&v, step, 0.0)));
            }
            let windows = [
                DEFAULT_WINDOW,
                (10.0, 120.0),
                (0.0, 100.0),
                (-175.0, 175.0),
                (-90.0, -80.0),
                (-170.0, 172.0),
            ];
            for (name, p) in &traces {
                for window_deg in windows {
                    for width_deg in [1.6, 2.0, 4.0, 20.0] {
                        for wall_heat in [None, Some(woschni)] {
                            let opts = Options {
                                smoothing: Smoothing::SavitzkyGolay { width_deg },
                                window_deg,
                                wall_heat,
                                rpm: Some(2000.0),
                                ..Options::default()
                            };
                            let f = Filter::new(opts.smoothing, step);
                            if opts.check_grid(step, cycle).is_err() || f.moments().is_none() {
                                continue;
                            }
                            let g = CycleGrid::new(p, &v, &dv, step);
                            let what = format!(
                                "{name}, {cycle}° at {step}°, {window_deg:?}, SG {width_deg}°, {wall_heat:?}"
                            );
                            let law = WindowLaw::new(&v, &dv, step, &opts).unwrap();
                            let mut s0 = Scratch::default();
                            let plain_f = f.clone().plain();
                            let w0 = cumulative(&g, &opts, &plain_f, &mut s0, None).unwrap();
                            for given in [None, Some(&law)] {
                                let mut s1 = Scratch::default();
                                let w1 = cumulative(&g, &opts, &f, &mut s1, given).unwrap();
                                let what = format!("{what}, law given {}", given.is_some());
                                assert_eq!(
                                    (w1.peak.0.to_bits(), w1.peak.1),
                                    (w0.peak.0.to_bits(), w0.peak.1),
                                    "{what}: peak"
                                );
                                assert_eq!(w1.v_max.to_bits(), w0.v_max.to_bits(), "{what}");
                                if given.is_some() {
                                    assert_eq!(w1.dv2.to_bits(), w0.dv2.to_bits(), "{what}");
                                } else {
                                    assert!(close(w1.dv2, w0.dv2, 1e-13), "{what}: dv2");
                                }
                                // The reference of the rest: the filter's own sweep
                                // over the window copied out ([`Filter::values_slopes_into`],
                                // the same stretches), the serial work and energy term.
                                let (i0, i1) = window_indices(step, window_deg);
                                let len = (i1 - i0 + 1) as usize;
                                let m = f.reach();
                                let mut pw = Vec::new();
                                copy_periodic(p, i0 - m as i64, len + 2 * m, &mut pw);
                                let mut vs = vec![[0.0; 2]; len];
                                assert!(f.values_slopes_into(&pw, m, &mut vs));
                                let bits = |x: f64, y: f64| x.to_bits() == y.to_bits();
                                for (j, (d, r)) in w1.s.slope.iter().zip(&vs).enumerate() {
                                    assert!(
                                        bits(*d, r[1]),
                                        "{what}: slope at {j}: {d} against {}",
                                        r[1]
                                    );
                                }
                                if wall_heat.is_some() {
                                    for (j, (x, r)) in w1.s.ps.iter().zip(&vs).enumerate() {
                                        assert!(
                                            bits(*x, r[0]),
                                            "{what}: p at {j}: {x} against {}",
                                            r[0]
                                        );
                                    }
                                }
                                let (h, inv) =
                                    (step.to_radians(), 1.0 / (opts.gamma.nominal() - 1.0));
                                let (mut work, mut prev, mut res2) = (0.0, 0.0, 0.0);
                                let mut q0 = Vec::with_capacity(len);
                                for (j, r) in vs.iter().enumerate() {
                                    let k = wrap(i0 + j as i64, n as i64);
                                    let (pj, ps) = (pw[m + j], r[0]);
                                    let pdv = pj * dv[k];
                                    if j > 0 {
                                        work += 0.5 * h * (prev + pdv);
                                    }
                                    prev = pdv;
                                    res2 += (pj - ps) * (pj - ps);
                                    q0.push(work + ps * v[k] * inv);
                                }
                                assert!(
                                    res2.total_cmp(&w1.residual2).is_eq()
                                        || close(w1.residual2, res2, 1e-12),
                                    "{what}: residuals {} against {res2}",
                                    w1.residual2
                                );
                                let q1 = &w1.s.qs;
                                let scale = q0
                                    .iter()
                                    .filter(|q| q.is_finite())
                                    .fold(0.0f64, |a, q| a.max(q.abs()));
                                for (j, (a, b)) in q1.iter().zip(&q0).enumerate() {
                                    assert!(
                                        a.total_cmp(b).is_eq() || (a - b).abs() <= 1e-12 * scale,
                                        "{what}: Q at {j}: {a} against {b}"
                                    );
                                }
                                let (e1, e0) = (w1.extremes.unwrap(), extremes(&q0));
                                let tie = |a: usize, b: usize| {
                                    a == b || (q0[a] - q0[b]).abs() <= 1e-12 * scale
                                };
                                assert!(
                                    tie(e1.0, e0.0) && tie(e1.1, e0.1),
                                    "{what}: {e1:?} {e0:?}"
                                );
                                checked += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(checked >= 500, "{checked}");
    }

    /// [`WindowLaw`] serves only the law, window, step and filter it was
    /// made from: another copy of the same law (other memory), another
    /// window or filter take their own figures, and give the same
    /// analysis.
    #[test]
    fn a_window_law_serves_its_own_law_only() {
        let cyl = cylinder();
        let step = 0.1f64;
        let n = 7200;
        let (v, dv) = cyl.fill_volume(step.to_radians(), n);
        let mut p = fired(&v, step, 600.0);
        noise(&mut p, 0.02e5, 5);
        let (v2, dv2) = (v.clone(), dv.clone());
        let opts = Options::default();
        let law = WindowLaw::new(&v, &dv, step, &opts).unwrap();
        let grid = CycleGrid::new(&p, &v, &dv, step);
        let other = CycleGrid {
            volume: &v2,
            dvolume: &dv2,
            ..grid
        };
        let f = Filter::new(opts.smoothing, step);
        let (i0, i1) = window_indices(step, opts.window_deg);
        assert!(law.fits(&grid, (i0, i1), &f));
        assert!(!law.fits(&other, (i0, i1), &f));
        assert!(!law.fits(&grid, (i0 + 1, i1), &f));
        let f5 = Filter::new(Smoothing::SavitzkyGolay { width_deg: 5.0 }, step);
        assert!(!law.fits(&grid, (i0, i1), &f5));
        let plain = analyse_with(&grid, &opts, &f.clone().plain()).unwrap();
        for (g, o) in [(&grid, &opts), (&other, &opts)] {
            let a = analyse_with_law(g, o, &f, Some(&law)).unwrap();
            same(&a, &plain, "given or not", 1e7);
        }
        let wide = Options {
            window_deg: (-100.0, 120.0),
            ..Options::default()
        };
        let a = analyse_with_law(&grid, &wide, &f, Some(&law)).unwrap();
        let b = analyse_with(&grid, &wide, &f.clone().plain()).unwrap();
        same(&a, &b, "another window", 1e7);
        // The figures are the serial pass's, bit for bit.
        let (mut s, plain_f) = (Scratch::default(), f.clone().plain());
        let w = cumulative(&grid, &opts, &plain_f, &mut s, None).unwrap();
        assert_eq!(
            (law.dv2.to_bits(), law.v_max.to_bits()),
            (w.dv2.to_bits(), w.v_max.to_bits())
        );
    }

    /// The running loop the scans replace: the largest sample and its
    /// index (the first of ties), and the index of the smallest before it
    /// with the largest's (`(soc, max)`, as [`extremes`] gives them).
    fn running_extremes(x: &[f64]) -> ((f64, usize), (usize, usize)) {
        let (mut min, mut max, mut soc) = ((f64::INFINITY, 0), (f64::NEG_INFINITY, 0), 0);
        for (j, &q) in x.iter().enumerate() {
            if q < min.0 {
                min = (q, j);
            }
            if q > max.0 {
                max = (q, j);
                soc = min.1;
            }
        }
        (max, (soc, max.1))
    }

    /// [`extremes_adding`] against adding first and the running loop, on
    /// data shaped to defeat it: the offset from every place about a
    /// block's edges, offsets of 0, ±1e9, ±∞ and NaN, ties across the
    /// part that takes it and the part that does not, NaN, ±∞, ±0.
    #[test]
    fn adding_while_scanning_is_adding_then_scanning() {
        let running = |x: &[f64]| running_extremes(x).1;
        let mut cases: Vec<Vec<f64>> = Vec::new();
        for len in [
            1usize, 5, 63, 64, 65, 128, 129, 255, 256, 257, 700, 2101, 9000,
        ] {
            let mut p = vec![0.0; len];
            noise(&mut p, 1.0, len as u64);
            cases.push(p.clone());
            cases.push(vec![2.5; len]);
            cases.push((0..len).map(|k| (k as f64 * 0.01).sin()).collect());
            let mut t = p.clone();
            t[len / 3] = f64::NAN;
            t[len - 1] = f64::INFINITY;
            t[0] = -0.0;
            cases.push(t);
            let mut t = p;
            t[len / 2] = f64::NEG_INFINITY;
            cases.push(t);
        }
        for x in &cases {
            let len = x.len();
            let froms = [0, 1, 63, 64, 65, 127, 128, 129, len / 2, len - 1, len];
            for from in froms.into_iter().filter(|&f| f <= len) {
                for add in [
                    0.0,
                    1.5,
                    -1e9,
                    1e9,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::NAN,
                ] {
                    let mut want = x.clone();
                    want[from..].iter_mut().for_each(|q| *q += add);
                    let mut got = x.clone();
                    let e = extremes_adding(&mut got, (from, add));
                    assert!(
                        got.iter()
                            .zip(&want)
                            .all(|(a, b)| a.to_bits() == b.to_bits()),
                        "{len} {from} {add}"
                    );
                    assert_eq!(e, running(&want), "{len} {from} {add}");
                    assert_eq!(extremes(&want), running(&want), "{len} {from} {add}");
                }
            }
        }
    }

    /// The scans of [`first_max`] and [`extremes`] against the running
    /// loop they replace, on data shaped to defeat them: ties (the first
    /// wins), the extreme in the last point or a block's first, NaN, ±∞,
    /// ±0, flat data, noise, and every length about a block's.
    #[test]
    fn the_scans_find_what_the_running_loop_finds() {
        let running = running_extremes;
        let mut cases: Vec<Vec<f64>> = vec![
            vec![],
            vec![f64::NAN],
            vec![f64::NAN; 5],
            vec![f64::NEG_INFINITY, f64::NEG_INFINITY],
            vec![f64::NAN, f64::NEG_INFINITY, 1.0],
            vec![f64::INFINITY, 2.0, f64::INFINITY],
            vec![-0.0, 0.0, -0.0],
            vec![0.0, -0.0, 0.0, -1.0, -0.0],
        ];
        for len in [
            1usize, 3, 4, 5, 7, 8, 63, 64, 65, 127, 128, 129, 130, 300, 2101,
        ] {
            let mut p = vec![0.0; len];
            noise(&mut p, 1.0, len as u64);
            cases.push(p.clone());
            cases.push(vec![3.5; len]);
            let mut spike = p.clone();
            spike[len - 1] = 1e9;
            cases.push(spike);
            let mut low = p.clone();
            low[len - 1] = -1e9;
            cases.push(low);
            for at in [0, len / 2, len.saturating_sub(64), 64.min(len - 1)] {
                let mut tie = p.clone();
                tie[at] = 7.0;
                tie[len - 1] = 7.0;
                tie[len / 3] = -7.0;
                tie[len / 4] = -7.0;
                cases.push(tie.clone());
                tie[at] = f64::NAN;
                cases.push(tie);
            }
            let mut nan = p.clone();
            for k in (0..len).step_by(3) {
                nan[k] = f64::NAN;
            }
            cases.push(nan);
            // Rising then falling (the cumulative's shape).
            cases.push((0..len).map(|k| (k as f64 * 0.01).sin()).collect());
        }
        for (c, x) in cases.iter().enumerate() {
            let (max, ext) = running(x);
            let got = first_max(x);
            assert_eq!(
                (got.0.to_bits(), got.1),
                (max.0.to_bits(), max.1),
                "case {c}: {x:?}"
            );
            assert_eq!(extremes(x), ext, "case {c}: {x:?}");
        }
    }

    /// The searches' skips pass over only points that stop no search, on
    /// data shaped to defeat them (NaN, ±∞, ties with the bounds, a point
    /// just over in each place of an eight), with NaN and infinite bounds
    /// and the bounds either way round; and they stop no later than the
    /// first eight that holds a point to check.
    #[test]
    fn the_searches_skip_only_what_stops_no_search() {
        let mut p = vec![0.0; 203];
        noise(&mut p, 1.0, 5);
        let mut cases = vec![p.clone(), vec![0.25; 203]];
        for k in [0usize, 7, 8, 9, 100, 101, 150, 202] {
            let mut c = p.clone();
            c[k] = f64::NAN;
            cases.push(c.clone());
            c[k] = 0.3;
            cases.push(c.clone());
            c[k] = f64::INFINITY;
            cases.push(c.clone());
            c[k] = f64::NEG_INFINITY;
            cases.push(c);
        }
        let values = [
            f64::NAN,
            f64::NEG_INFINITY,
            -0.5,
            0.0,
            0.25,
            0.3,
            0.5,
            f64::INFINITY,
        ];
        for q in &cases {
            for &lo in &values {
                for &hi in &values {
                    let rising = |x: f64| x < lo && !(x >= hi);
                    let falling = |x: f64| x > hi && !(x <= lo);
                    for (from, to) in [(0, 202), (3, 202), (0, 17), (5, 5), (9, 4), (0, 7)] {
                        let j = skip_rising(q, from, to, (lo, hi));
                        assert!(j >= from && (j == from || j <= to), "{lo} {hi} {from} {to}");
                        assert!(q[from..j].iter().all(|&x| rising(x)), "{lo} {hi}");
                        let stop = (from..to).find(|&k| !rising(q[k])).unwrap_or(to.max(from));
                        assert!(j + 8 > stop || j == from.max(stop), "{lo} {hi} {j} {stop}");
                        let (f, t) = (to.max(from), from.min(to));
                        let j = skip_falling(q, f, t, (lo, hi));
                        assert!(j <= f && (j == f || j >= t), "{lo} {hi} {f} {t}");
                        assert!(q[j + 1..=f].iter().all(|&x| falling(x)), "{lo} {hi}");
                    }
                }
            }
        }
    }

    /// `curves`' rate against the plain weight sums at every grid point
    /// (the wrapping [`Filter::value`] and [`Filter::slope`]).
    #[test]
    fn the_curves_keep_the_plain_rate() {
        let cyl = cylinder();
        let step = 0.1f64;
        let n = (720.0 / step).round() as usize;
        let (v, dv) = cyl.fill_volume(step.to_radians(), n);
        let mut p = fired(&v, step, 600.0);
        noise(&mut p, 0.05e5, 3);
        for smoothing in [
            Smoothing::default(),
            Smoothing::SavitzkyGolay { width_deg: 12.0 },
        ] {
            let opts = Options {
                smoothing,
                ..Options::default()
            };
            let g = CycleGrid::new(&p, &v, &dv, step);
            let burn = analyse(&g, &opts).unwrap();
            let c = curves(&g, &opts, &burn).unwrap();
            let f = Filter::new(smoothing, step).plain();
            let gm = opts.gamma.nominal();
            let deg_per_rad = 180.0 / std::f64::consts::PI;
            let rate: Vec<f64> = (0..n)
                .map(|k| {
                    let (ps, dp) = (f.value(&p, k as i64), f.slope(&p, k as i64));
                    gm / (gm - 1.0) * ps * dv[k] / deg_per_rad + v[k] * dp / (gm - 1.0)
                })
                .collect();
            let scale = rate.iter().fold(0.0f64, |a, r| a.max(r.abs()));
            for (k, (a, b)) in c.rate_j_deg.iter().zip(&rate).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "{smoothing:?}: rate at {k}: {a} against {b}"
                );
            }
        }
    }
}
