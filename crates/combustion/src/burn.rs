//! The analysis of one cycle on the uniform grid: the net apparent heat
//! release (single zone, first law), the burn points by the min–max rule,
//! the pressure rise and the gross work (PHYSICS.md "Combustion").

use crate::{CombustionError, GammaModel, Smoothing, check_range, smooth::Filter};

/// The burn levels reported by default (percent).
pub const DEFAULT_LEVELS: [f64; 4] = [5.0, 10.0, 50.0, 90.0];
/// The default burn window (deg from firing TDC).
pub const DEFAULT_WINDOW: (f64, f64) = (-90.0, 120.0);
/// A cycle burns when its heat released is at least this share of
/// `p_max V(p_max) / (γ − 1)`, the charge's energy at the peak.
pub const NO_COMBUSTION_SHARE: f64 = 0.05;

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
}

impl Default for Options {
    fn default() -> Self {
        Self {
            gamma: GammaModel::default(),
            smoothing: Smoothing::default(),
            window_deg: DEFAULT_WINDOW,
            levels_pct: DEFAULT_LEVELS.to_vec(),
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
}

impl CycleGrid<'_> {
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
fn wrap(k: i64, n: i64) -> usize {
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
    /// Start of combustion (deg): where the cumulative is least before EOC.
    pub soc_deg: f64,
    /// End of combustion (deg): where the cumulative is largest.
    pub eoc_deg: f64,
    /// The angle of each level of [`Options::levels_pct`] (deg), in order.
    pub levels_deg: Vec<f64>,
    /// The largest dp/dφ between SOC and EOC (Pa/°).
    pub dp_max_pa_deg: f64,
    /// Its angle (deg).
    pub dp_max_angle_deg: f64,
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
    /// `Q(EOC) − Q(SOC)` (J), whether or not it clears the bound.
    pub heat_released_j: f64,
    /// The no-combustion bound (J): `0.05 p_max V(p_max) / (γ − 1)`.
    pub bound_j: f64,
    /// The burn points; `None` when the heat released is under the bound.
    pub burn: Option<BurnPoints>,
    /// `∫ p dV` over −180…180° (J): the gross work (the whole cycle for a
    /// two-stroke).
    pub gross_work_j: f64,
}

/// The cumulative heat release over the window: from the pressure as read
/// (one pass, no derivative), and from the smoothed pressure where the
/// rules need it (near SOC, EOC and each level's crossing): the smoothing
/// touches only the energy term `E(pV)`, as the work is an integral.
struct Window<'a> {
    g: &'a CycleGrid<'a>,
    f: &'a Filter,
    gamma: GammaModel,
    /// First grid index of the window (may be negative: it wraps).
    i0: i64,
    /// `pV` at IVC (γ(T) only).
    ivc: f64,
    /// The cumulative heat release from the pressure as read (J); the
    /// work `∫ p dV` from the window's start is `q − E(pV) + e0`.
    q: Vec<f64>,
    /// The largest pressure in the window and its index.
    peak: (f64, usize),
    /// The index of the largest cumulative (the first, if tied): EOC as read.
    eoc0: usize,
    /// The index of the smallest cumulative up to [`Self::eoc0`]: SOC as read.
    soc0: usize,
}

/// The one pass over the window: the trapezoidal work `∫ p dV`, the energy
/// term, the cumulative, the pressure peak, and the cumulative's extremes
/// (its largest value, and the smallest before that).
struct Pass {
    q: Vec<f64>,
    half_h: f64,
    work: f64,
    /// `p dV/dφ` at the previous point.
    prev: f64,
    peak: (f64, usize),
    min: (f64, usize),
    max: (f64, usize),
    /// The index of the smallest cumulative before [`Self::max`].
    soc: usize,
}

impl Pass {
    fn new(len: usize, half_h: f64) -> Self {
        Self {
            q: Vec::with_capacity(len),
            half_h,
            work: 0.0,
            prev: 0.0,
            peak: (f64::NEG_INFINITY, 0),
            min: (f64::INFINITY, 0),
            max: (f64::NEG_INFINITY, 0),
            soc: 0,
        }
    }

    /// Runs over grid indices `i0..=i1` (in at most two contiguous pieces
    /// of the periodic grid), `energy` the term `E(pV)`.
    #[inline]
    fn run(&mut self, g: &CycleGrid, (i0, i1): (i64, i64), energy: impl Fn(f64) -> f64) {
        let n = g.n();
        // The cumulative starts at 0: the energy term from its value at the
        // start, and the first trapezoid adds nothing.
        let e0 = energy(g.at(g.pressure, i0) * g.at(g.volume, i0));
        self.prev = -g.at(g.pressure, i0) * g.at(g.dvolume, i0);
        let mut k = i0;
        while k <= i1 {
            let start = wrap(k, n);
            let end = (start + (i1 - k + 1) as usize).min(n as usize);
            let p = &g.pressure[start..end];
            let v = &g.volume[start..end];
            let dv = &g.dvolume[start..end];
            // The state in locals (registers), not behind `self`, which the
            // stores into `q` could alias.
            let (half_h, mut work, mut prev) = (self.half_h, self.work, self.prev);
            let (mut peak, mut min, mut max, mut soc) = (self.peak, self.min, self.max, self.soc);
            let mut j = self.q.len();
            self.q
                .extend(p.iter().zip(v).zip(dv).map(|((&p, &v), &dv)| {
                    let pdv = p * dv;
                    work += half_h * (prev + pdv);
                    prev = pdv;
                    let q = work + energy(p * v) - e0;
                    if p > peak.0 {
                        peak = (p, j);
                    }
                    if q < min.0 {
                        min = (q, j);
                    }
                    if q > max.0 {
                        max = (q, j);
                        soc = min.1;
                    }
                    j += 1;
                    q
                }));
            (self.work, self.prev) = (work, prev);
            (self.peak, self.min, self.max, self.soc) = (peak, min, max, soc);
            k += (end - start) as i64;
        }
    }
}

impl Window<'_> {
    /// The cumulative heat release at window index `j` from the smoothed
    /// pressure (J).
    fn smoothed(&self, j: usize) -> f64 {
        let k = self.i0 + j as i64;
        let v = self.g.at(self.g.volume, k);
        let raw = self
            .gamma
            .energy(self.g.at(self.g.pressure, k) * v, self.ivc);
        let ps = self.f.value(self.g.pressure, k);
        self.q[j] - raw + self.gamma.energy(ps * v, self.ivc)
    }

    /// The index in `lo..=hi` where the smoothed cumulative is largest
    /// (`max`) or smallest.
    fn extreme(&self, lo: usize, hi: usize, max: bool) -> (usize, f64) {
        let mut best = (lo, self.smoothed(lo));
        for j in lo + 1..=hi {
            let v = self.smoothed(j);
            if (max && v > best.1) || (!max && v < best.1) {
                best = (j, v);
            }
        }
        best
    }
}

/// The index range `[i0, i1]` of grid points inside `window_deg`.
fn window_indices(step: f64, (a, b): (f64, f64)) -> (i64, i64) {
    (
        (a / step - 1e-9).ceil() as i64,
        (b / step + 1e-9).floor() as i64,
    )
}

/// `pV` at intake valve closing, for γ(T) (1 for a constant γ: unused).
fn pv_ivc(g: &CycleGrid, opts: &Options, f: &Filter) -> f64 {
    match opts.gamma {
        GammaModel::Constant(_) => 1.0,
        GammaModel::Brunt { ivc_deg, .. } => {
            let k = (ivc_deg / g.step_deg).round() as i64;
            f.value(g.pressure, k) * g.at(g.volume, k)
        }
    }
}

fn cumulative<'a>(
    g: &'a CycleGrid<'a>,
    opts: &Options,
    f: &'a Filter,
) -> Result<Window<'a>, CombustionError> {
    if g.pressure.len() != g.volume.len() || g.pressure.len() != g.dvolume.len() {
        return Err(CombustionError::Input(
            "pressure and volume law of different lengths".into(),
        ));
    }
    let (i0, i1) = window_indices(g.step_deg, opts.window_deg);
    if i1 - i0 < 4 || (i1 - i0) as f64 * g.step_deg >= g.cycle_deg() {
        return Err(CombustionError::Input(format!(
            "the burn window {}…{}° does not fit the {}° cycle at a {}° step",
            opts.window_deg.0,
            opts.window_deg.1,
            g.cycle_deg(),
            g.step_deg
        )));
    }
    let ivc = pv_ivc(g, opts, f);
    let gamma = opts.gamma;
    let mut pass = Pass::new((i1 - i0 + 1) as usize, 0.5 * g.step_deg.to_radians());
    // A constant γ takes the product form (no call, no division); each
    // form is its own loop.
    match gamma {
        GammaModel::Constant(c) => {
            let inv = 1.0 / (c - 1.0);
            pass.run(g, (i0, i1), |pv| pv * inv);
        }
        GammaModel::Brunt { .. } => pass.run(g, (i0, i1), |pv| gamma.energy(pv, ivc)),
    }
    Ok(Window {
        g,
        f,
        gamma,
        i0,
        ivc,
        q: pass.q,
        peak: pass.peak,
        eoc0: pass.max.1,
        soc0: pass.soc,
    })
}

/// The first angle after `from` (SOC, or the crossing of the level below)
/// where the smoothed cumulative reaches `target`, linearly interpolated
/// between grid points, and its index; the crossing is found on the
/// cumulative as read, then taken on the smoothed one.
fn crossing(win: &Window, soc: usize, from: usize, eoc: usize, target: f64) -> (f64, usize) {
    let mut j = (from.max(soc + 1)..=eoc)
        .find(|&j| win.q[j] >= target)
        .unwrap_or(eoc);
    // The smoothed curve may cross a little earlier: step back while it has.
    while j > soc + 1 && win.smoothed(j - 1) >= target {
        j -= 1;
    }
    let (a, b) = (win.smoothed(j - 1), win.smoothed(j));
    let t = if b > a {
        ((target - a) / (b - a)).clamp(0.0, 1.0)
    } else {
        1.0
    };
    ((win.i0 as f64 + (j - 1) as f64 + t) * win.g.step_deg, j)
}

/// Analyses one cycle (checked options: [`Options::check`]).
pub fn analyse(g: &CycleGrid, opts: &Options) -> Result<CycleBurn, CombustionError> {
    let f = Filter::new(opts.smoothing, g.step_deg);
    analyse_with(g, opts, &f)
}

/// [`analyse`] with the filter built once for many cycles.
pub fn analyse_with(
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
) -> Result<CycleBurn, CombustionError> {
    let win = cumulative(g, opts, f)?;
    let last = win.q.len() - 1;
    let deg = |j: f64| (win.i0 as f64 + j) * g.step_deg;
    // SOC and EOC on the cumulative as read, then taken where the smoothed
    // cumulative has its extreme within a filter's width of them.
    let (eoc0, soc0) = (win.eoc0, win.soc0);
    let r = f.half_points().max(1);
    let (eoc, q_eoc) = win.extreme(eoc0.saturating_sub(r), (eoc0 + r).min(last), true);
    let (soc, q_soc) = win.extreme(soc0.saturating_sub(r), (soc0 + r).min(eoc), false);
    let released = q_eoc - q_soc;
    let gamma = opts.gamma.nominal();
    let (p_max, at) = win.peak;
    let bound = NO_COMBUSTION_SHARE * p_max * g.at(g.volume, win.i0 + at as i64) / (gamma - 1.0);
    let mut out = CycleBurn {
        heat_released_j: released,
        bound_j: bound,
        burn: None,
        gross_work_j: gross_work(g),
    };
    if !(released >= bound) || eoc <= soc {
        return Ok(out);
    }
    // Levels rise, so each search starts where the one below it crossed.
    let mut from = soc + 1;
    let levels_deg = opts
        .levels_pct
        .iter()
        .map(|l| {
            let (deg, j) = crossing(&win, soc, from, eoc, q_soc + l / 100.0 * released);
            from = j.saturating_sub(win.f.half_points() + 1).max(soc + 1);
            deg
        })
        .collect();
    let (dp_max, dp_at) = pressure_rise(&win, soc, eoc);
    out.burn = Some(BurnPoints {
        soc_deg: deg(soc as f64),
        eoc_deg: deg(eoc as f64),
        levels_deg,
        dp_max_pa_deg: dp_max,
        dp_max_angle_deg: deg(dp_at),
    });
    Ok(out)
}

/// The largest smoothed dp/dφ (Pa/°) between SOC and EOC and its window
/// index: found on the difference across the filter's width (one
/// subtraction a point), then taken on the filter's own slope around it
/// and refined by the parabola through it and its neighbours.
fn pressure_rise(win: &Window, soc: usize, eoc: usize) -> (f64, f64) {
    let g = win.g;
    let m = win.f.half_points().max(1) as i64;
    let at = |j: usize| win.i0 + j as i64;
    // The difference across the filter's width, every half width: a rise
    // narrower than that is one the filter does not keep either.
    let stride = (m as usize / 2).max(1);
    let (mut best, mut arg) = (f64::NEG_INFINITY, soc);
    for j in (soc..=eoc).step_by(stride) {
        let d = g.at(g.pressure, at(j) + m) - g.at(g.pressure, at(j) - m);
        if d > best {
            best = d;
            arg = j;
        }
    }
    let slope = |j: usize| win.f.slope(g.pressure, at(j));
    let lo = arg.saturating_sub(m as usize + stride).max(soc);
    let hi = (arg + m as usize + stride).min(eoc);
    let (mut top, mut j_top) = (slope(lo), lo);
    for j in lo + 1..=hi {
        let s = slope(j);
        if s > top {
            top = s;
            j_top = j;
        }
    }
    let (mut value, mut x) = (top, j_top as f64);
    if j_top > 0 && j_top < win.q.len() - 1 {
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
    /// `Q(φ) − Q(SOC)` (J) inside the window; 0 before it, its end value
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
    let w = cumulative(g, opts, &f)?;
    let n = g.pressure.len();
    let ivc = pv_ivc(g, opts, &f);
    let deg_per_rad = 180.0 / std::f64::consts::PI;
    let mut rate = Vec::with_capacity(n);
    for k in 0..n as i64 {
        let p = f.value(g.pressure, k);
        let dp = f.slope(g.pressure, k);
        let (v, dv) = (g.at(g.volume, k), g.at(g.dvolume, k) / deg_per_rad);
        let gm = opts.gamma.gamma(p * v, ivc);
        rate.push(gm / (gm - 1.0) * p * dv + v * dp / (gm - 1.0));
    }
    let qs: Vec<f64> = (0..w.q.len()).map(|j| w.smoothed(j)).collect();
    let base = burn.burn.as_ref().map_or(0.0, |b| {
        qs[((b.soc_deg / g.step_deg).round() as i64 - w.i0) as usize]
    });
    let mut cumulative = vec![0.0; n];
    let mut mfb = burn.burn.as_ref().map(|_| vec![0.0; n]);
    let last = w.q.len() - 1;
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
