//! The analysis of one cycle on the uniform grid: the net apparent heat
//! release (single zone, first law), the burn points by the min–max rule,
//! the pressure rise and the gross work (PHYSICS.md "Combustion").

use crate::knock::{Knock, KnockFigures, Unresolved};
use crate::wall::{Trapped, WallHeat};
use crate::{CombustionError, GammaModel, Smoothing, check_range, smooth::Filter};

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

/// The cumulative heat release over the window, smoothed: the work `∫ p
/// dV` from the pressure as read (an integral needs no smoothing), the
/// energy term `E(pV)` from the smoothed pressure. Its reference (the
/// value at the window's start) cancels in every figure.
struct Window<'a> {
    g: &'a CycleGrid<'a>,
    f: &'a Filter,
    /// First grid index of the window (may be negative: it wraps).
    i0: i64,
    /// The smoothed cumulative (J), one value a window point.
    qs: Vec<f64>,
    /// The largest pressure in the window and its index.
    peak: (f64, usize),
    /// The sum of squared residuals `p − p_smooth` of the noise fit.
    residual2: f64,
    /// `Σ (h dV)²` over the window (m⁶): the work's noise gain.
    dv2: f64,
    /// The largest volume in the window (m³).
    v_max: f64,
    /// The window's pressure with the filter's reach either side
    /// ([`Filter::reach`]): window index `j` is `pw[j + reach]`.
    pw: Vec<f64>,
}

/// The one pass over the window: the trapezoidal work `∫ p dV`, the
/// smoothed pressure and with it the energy term, the pressure peak, and
/// the residuals of the noise fit.
fn pass(
    g: &CycleGrid,
    f: &Filter,
    (i0, i1): (i64, i64),
    energy: impl Fn(f64) -> f64,
) -> (Vec<f64>, Vec<f64>, (f64, usize), [f64; 3]) {
    let h = g.step_deg.to_radians();
    let len = (i1 - i0 + 1) as usize;
    // The window's pressure with the filter's reach either side, copied
    // out once: every weight sum then reads one contiguous slice.
    let m = f.reach();
    let pw: Vec<f64> = (i0 - m as i64..=i1 + m as i64)
        .map(|k| g.at(g.pressure, k))
        .collect();
    let mut qs = Vec::with_capacity(len);
    let (mut work, mut prev) = (0.0, g.at(g.pressure, i0) * g.at(g.dvolume, i0));
    let mut peak = (f64::NEG_INFINITY, 0);
    let (mut res2, mut dv2, mut v_max) = (0.0, 0.0, 0.0f64);
    for j in 0..len {
        let k = i0 + j as i64;
        let (p, v, dv) = (pw[j + m], g.at(g.volume, k), g.at(g.dvolume, k));
        let pdv = p * dv;
        if j > 0 {
            work += 0.5 * h * (prev + pdv);
        }
        prev = pdv;
        let ps = f.value_in(&pw, j + m);
        let r = p - f.fit_in(&pw, j + m, ps);
        res2 += r * r;
        dv2 += (h * dv) * (h * dv);
        v_max = v_max.max(v);
        if p > peak.0 {
            peak = (p, j);
        }
        qs.push(work + energy(ps * v));
    }
    (qs, pw, peak, [res2, dv2, v_max])
}

impl Window<'_> {
    /// The pressure noise of one sample (Pa), from the fit's residuals: a
    /// least-squares fit keeps `1 − w₀` of white noise's variance in the
    /// residual (w₀ its centre weight).
    fn noise(&self) -> f64 {
        let n = self.qs.len() as f64;
        (self.residual2 / n / (1.0 - self.f.fit_centre())).sqrt()
    }

    /// The first index in `from..=to` where the cumulative reaches
    /// `target`, and the angle (deg) where it crosses, linearly
    /// interpolated from the point before.
    fn rising(&self, from: usize, to: usize, target: f64) -> (usize, f64) {
        self.rising_by(from, to, |_| target)
    }

    /// [`Self::rising`] to a level that may change along the window.
    fn rising_by(&self, from: usize, to: usize, target: impl Fn(usize) -> f64) -> (usize, f64) {
        let j = (from..=to).find(|&j| self.qs[j] >= target(j)).unwrap_or(to);
        let t = if j == 0 {
            0.0
        } else {
            let (a, b, y) = (self.qs[j - 1], self.qs[j], target(j));
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
    /// leaves that level, interpolated towards the next point.
    fn falling_by(&self, from: usize, to: usize, target: impl Fn(usize) -> f64) -> (usize, f64) {
        let j = (to..=from)
            .rev()
            .find(|&j| self.qs[j] <= target(j))
            .unwrap_or(to);
        let t = if j + 1 < self.qs.len() {
            let (a, b, y) = (self.qs[j], self.qs[j + 1], target(j));
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
        let last = self.qs.len() - 1;
        let deg = |d: f64| ((d / self.g.step_deg).round() as usize).clamp(1, last);
        let (one, two) = (deg(1.0), deg(2.0));
        let band = SOC_FRACTION * released;
        if start {
            extreme <= one && self.qs[two] - self.qs[0] > band
        } else {
            extreme + one >= last && self.qs[last] - self.qs[last - two] > band
        }
    }

    /// The angle (deg) of window index `j` (fractional).
    fn deg(&self, j: f64) -> f64 {
        (self.i0 as f64 + j) * self.g.step_deg
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
    // A constant γ takes the product form (no call, no division).
    let (qs, pw, peak, [residual2, dv2, v_max]) = match gamma {
        GammaModel::Constant(c) => {
            let inv = 1.0 / (c - 1.0);
            pass(g, f, (i0, i1), |pv| pv * inv)
        }
        GammaModel::Brunt { .. } => pass(g, f, (i0, i1), |pv| gamma.energy(pv, ivc)),
    };
    Ok(Window {
        g,
        f,
        i0,
        qs,
        peak,
        residual2,
        dv2,
        v_max,
        pw,
    })
}

/// Analyses one cycle (checked options: [`Options::check`]).
pub fn analyse(g: &CycleGrid, opts: &Options) -> Result<CycleBurn, CombustionError> {
    let f = Filter::new(opts.smoothing, g.step_deg);
    analyse_with(g, opts, &f)
}

/// The smoothed cumulative's extremes: the index of its largest value
/// (the first, if tied) and of the smallest before it.
fn extremes(qs: &[f64]) -> (usize, usize) {
    let (mut min, mut max, mut soc) = ((f64::INFINITY, 0), (f64::NEG_INFINITY, 0), 0);
    for (j, &q) in qs.iter().enumerate() {
        if q < min.0 {
            min = (q, j);
        }
        if q > max.0 {
            max = (q, j);
            soc = min.1;
        }
    }
    (soc, max.1)
}

/// [`analyse`] with the filter built once for many cycles.
pub fn analyse_with(
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
) -> Result<CycleBurn, CombustionError> {
    let mut win = cumulative(g, opts, f)?;
    let mut net = rule(&win, g, opts, f);
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
    let w = wall_cumulative(&win, g, opts, f, wall, net.burn.as_ref().map(|b| b.soc_deg))?;
    for (q, w) in win.qs.iter_mut().zip(&w) {
        *q += w;
    }
    let mut gross = rule(&win, g, opts, f);
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
/// window point: `dQ_wall/dφ` from the smoothed pressure, integrated by
/// the trapezoid.
fn wall_cumulative(
    win: &Window,
    g: &CycleGrid,
    opts: &Options,
    f: &Filter,
    wall: &WallHeat,
    soc_deg: Option<f64>,
) -> Result<Vec<f64>, CombustionError> {
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
    let half = 0.5 * g.step_deg;
    let mut out = Vec::with_capacity(win.qs.len());
    let (mut total, mut prev) = (0.0, 0.0);
    for j in 0..win.qs.len() {
        let k = win.i0 + j as i64;
        let burning = soc_deg.is_some_and(|soc| k as f64 * g.step_deg >= soc);
        let p = f.value_in(&win.pw, j + f.reach());
        let r = wall.rate(&s, p, g.at(g.volume, k), burning);
        if j > 0 {
            total += half * (prev + r);
        }
        prev = r;
        out.push(total);
    }
    Ok(out)
}

/// The burn rule on the window's cumulative (PHYSICS "Burn points"): the
/// extremes, the no-combustion bound, the noise, the crossings, SOC and
/// EOC, and the pressure rise.
fn rule(win: &Window, g: &CycleGrid, opts: &Options, f: &Filter) -> CycleBurn {
    let (jmin, jmax) = extremes(&win.qs);
    let (q_min, q_max) = (win.qs[jmin], win.qs[jmax]);
    let released = q_max - q_min;
    let gamma = opts.gamma.nominal();
    let (p_max, at) = win.peak;
    let bound = NO_COMBUSTION_SHARE * p_max * g.at(g.volume, win.i0 + at as i64) / (gamma - 1.0);
    let noise = win.noise();
    let mut out = CycleBurn {
        heat_released_j: released,
        bound_j: bound,
        noise_pa: noise,
        ca50_uncertainty_deg: None,
        unresolved: false,
        burn: None,
        gross_work_j: gross_work(g),
        heat_released_gross_j: None,
        wall_heat_j: None,
        knock: None,
    };
    if !(released >= bound) || jmax <= jmin {
        return out;
    }
    let x = |frac: f64| q_min + frac * released;
    let (j10, ca10) = win.rising(jmin + 1, jmax, x(0.1));
    let (j50, _) = win.rising(j10, jmax, x(0.5));
    let (_, ca90) = win.rising(j50, jmax, x(0.9));
    // The noise carried into the smoothed cumulative at window index j:
    // the energy term's (the work integrates the noise away, nearly).
    let vol = |j: usize| g.at(g.volume, win.i0 + j as i64);
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
    let (j_soc, soc) = win.falling_by(j50, jmin, |j| x(SOC_FRACTION) + band(jmin, j));
    let (j_eoc, eoc) = win.rising_by(j50, jmax, |j| x(EOC_FRACTION) - band(jmax, j));
    // Levels rise, so each search starts where the one below it crossed.
    let mut from = jmin + 1;
    let levels_deg = opts
        .levels_pct
        .iter()
        .map(|l| {
            let (j, deg) = win.rising(from, jmax, x(l / 100.0));
            from = j.max(jmin + 1);
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
fn pressure_rise(win: &Window, soc: usize, eoc: usize) -> (f64, f64) {
    let m = win.f.reach();
    let slope = |j: usize| win.f.slope_in(&win.pw, j + m);
    let (mut top, mut j_top) = (f64::NEG_INFINITY, soc);
    for j in soc..=eoc.max(soc) {
        let s = slope(j);
        if s > top {
            top = s;
            j_top = j;
        }
    }
    let (mut value, mut x) = (top, j_top as f64);
    if j_top > 0 && j_top < win.qs.len() - 1 {
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
    let w = cumulative(g, opts, &f)?;
    let n = g.pressure.len();
    let ivc = pv_ivc(g, opts, &f)?;
    let deg_per_rad = 180.0 / std::f64::consts::PI;
    let mut rate = Vec::with_capacity(n);
    for k in 0..n as i64 {
        let p = f.value(g.pressure, k);
        let dp = f.slope(g.pressure, k);
        let (v, dv) = (g.at(g.volume, k), g.at(g.dvolume, k) / deg_per_rad);
        let gm = opts.gamma.gamma(p * v, ivc);
        rate.push(gm / (gm - 1.0) * p * dv + v * dp / (gm - 1.0));
    }
    let qs = &w.qs;
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
