//! The TDC offset a measured trace suggests: where firing TDC lies on the
//! trace's angle axis, from a motored or fuel-cut cycle.
//!
//! # Method
//!
//! After Tunestål's heat-release shaping (P. Tunestål, "TDC Offset
//! Estimation from Motored Cylinder Pressure Data based on Heat Release
//! Shaping", *Oil & Gas Science and Technology – Rev. IFP Energies
//! nouvelles* 66(4), 705–716, 2011, DOI 10.2516/ogst/2011144; first at IFAC
//! E-COSM'09, IFAC Proceedings Volumes 42(26), 241–247, 2009): without
//! combustion the only heat release is the loss to the walls, so the TDC
//! offset and the ratio of specific heats are the pair that gives the
//! trace the loss it should have, found by nonlinear least squares. A
//! motored trace's peak is not TDC: heat transfer (and blow-by) puts it a
//! fraction of a degree before (the "thermodynamic loss angle", Y. Nilsson
//! and L. Eriksson, "Determining TDC Position Using Symmetry and Other
//! Methods", SAE 2004-01-1458, 2004), which is what the loss term accounts
//! for.
//!
//! Tunestål takes the loss power as constant over a narrow window around
//! TDC. On traces with Woschni wall heat and blow-by (`enginedyn_synth::Losses`)
//! that left about half the loss angle as bias in this project's trials
//! (0.1°–0.4°), so here the loss has the shape of Hohenberg's correlation
//! (G. F. Hohenberg, "Advanced Approaches for Heat Transfer Calculations",
//! SAE 790825, 1979), `h ∝ V^-0.06 p^0.8 T^-0.4` over the chamber's area
//! `A = pi B²/2 + 4V/B`, with its magnitude and the wall temperature
//! unknown. With the first law of a closed single zone,
//! `d ln p = -n d ln V - (n - 1) dQ_wall / (p V)`, and `T ∝ p V`, the model
//! of the closed part around TDC is
//!
//! `ln p = a - n ln V(phi - d) - c1 H1(phi) - c2 H2(phi)`,
//! `H_i = ∫ g_i dphi`, `g1 = A V^-0.06 p^0.8 (p V)^-0.4`, `g2 = g1 / (p V)`
//!
//! (`c2 / c1` is minus the wall temperature in the units of `p V`, so no
//! gas or wall temperature is assumed). For a trial offset `d` the model
//! is linear in `a`, `n`, `c1`, `c2`: weighted least squares (weights `p`,
//! so the residuals are pressure errors) over ±90° around the trial TDC
//! (±75° on a two-stroke, whose ports open earlier; the valves or ports
//! must be closed over the window and the 6° of the search beyond it),
//! the window's last 3° tapered so the misfit is continuous in `d`. The
//! offset is the `d` of least misfit in ±6° (a scan at 0.25°, then Brent's
//! minimisation). The window moves with `d`, so the estimate moves with
//! the declared TDC: applying it and fitting again gives 0 (to 0.002° on
//! the tests' traces). Blow-by takes enthalpy away with a shape close to
//! the heat loss's (about `sqrt(T) / V`) and is absorbed by the two terms.
//!
//! On the generated motored traces of `crates/pipeline/tests/tdc.rs`
//! (Woschni wall heat up to twice the correlation, walls at 350–450 K,
//! 2 % blow-by, noise of 0.01–0.05 bar; petrol, diesel and two-stroke
//! geometries; TDC shifted by -3° to +3°) the estimates are within 0.11°;
//! the compression ratio off by 0.4 moves them by less than 0.05°, a
//! pegging error of 0.1 bar by less than 0.05°.
//!
//! # When there is no estimate
//!
//! [`Untrusted`] says why:
//!
//! - the grid is coarser than 1°, or the pressure is not positive in the
//!   window;
//! - the cycle burns. Combustion adds heat the model has no term for, so a
//!   fired trace gets no estimate, however it is phased. The test compares
//!   `ln p` over 5° bands mirrored about a centre at or after TDC: each
//!   expansion band is then at least as far from TDC as its compression
//!   band, so on a motored trace it is lower. Before the fit the centre is
//!   the pressure peak plus 2° (a motored peak is at most 2° before TDC,
//!   typically 0.4°–1.3°), whatever the declared TDC; after it, the fitted
//!   TDC. An excess above 2 % and three standard deviations of the bands'
//!   noise is heat added;
//! - the least misfit lies at the end of the ±6° search;
//! - the fitted exponent is not that of air (1.2 to 1.5);
//! - the trace is too noisy: the offset's standard error (the misfit's
//!   curvature against the long-run variance of the residuals' noise, their
//!   scatter about a ±5° running mean with its autocovariances to 1.5°) is
//!   above 0.05°. The smooth misfit of an imperfect model (the compression
//!   ratio a little off) is a bias, not noise, and is left out.
//!
//! The fit sees the trace on the analysis grid: a file sampled coarsely and
//! interpolated onto a fine grid is judged by the interpolant.

use enginedyn_kinematics::Cylinder;
use enginedyn_numerics::{format, roots};
use std::f64::consts::PI;

/// The largest offset looked for (deg either way).
pub const MAX_OFFSET_DEG: f64 = 6.0;

/// The coarsest grid step the fit accepts (deg).
pub const MAX_STEP_DEG: f64 = 1.0;

/// The largest standard error (deg) of an estimate that is reported: a
/// quarter of the 0.2° an estimate is to be within, so that noise alone
/// leaves it there (two standard errors) with room for the method's bias.
pub const MAX_STD_ERROR_DEG: f64 = 0.05;

/// Half the fit's window around the trial TDC (deg), four-stroke: the
/// valves are closed from about 130° before to 130° after firing TDC.
pub const HALF_WINDOW_FOUR_STROKE_DEG: f64 = 90.0;

/// Half the fit's window, two-stroke (deg): ports open 90°–110° from TDC.
pub const HALF_WINDOW_TWO_STROKE_DEG: f64 = 75.0;

/// The largest thermodynamic loss angle (deg), motored peak before TDC:
/// typically 0.4°–1.3° on motored engines, 1.2° on the heaviest losses the
/// tests generate.
const MAX_LOSS_ANGLE_DEG: f64 = 2.0;

/// The window's tapered ends (deg): weights fall linearly to 0 over them.
const TAPER_DEG: f64 = 3.0;

/// The polytropic exponents of air taken as plausible.
const EXPONENT_RANGE: (f64, f64) = (1.2, 1.5);

/// Expansion pressure above compression pressure at the same distance from
/// TDC by more than this fraction means heat was added: combustion.
const BURN_EXCESS: f64 = 0.02;

/// Residual noise is measured about the residuals' running mean over this
/// half-width (deg): wider than the noise's correlation (a file step up to
/// 1°), narrower than the model's misfit (tens of degrees).
const NOISE_SMOOTHING_DEG: f64 = 5.0;

/// The noise's autocovariances are summed to this lag (deg): files with
/// a step up to 1° interpolated onto a finer grid.
const NOISE_LAGS_DEG: f64 = 1.5;

/// The scan's step over the trial offsets (deg).
const SCAN_STEP_DEG: f64 = 0.25;

/// A trustworthy estimate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Where firing TDC lies on the trace's angle axis (deg): positive when
    /// it comes after the declared one. Declaring TDC at the angle the file
    /// now calls `offset_deg` (`--tdc-deg` plus it) corrects the trace.
    pub offset_deg: f64,
    /// The fitted polytropic exponent `n` (the ratio of specific heats).
    pub exponent: f64,
    /// Standard error of the offset from the fit's residuals (deg).
    pub std_error_deg: f64,
}

/// Why a trace gives no estimate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Untrusted {
    /// The step between points (deg), of the grid or of the data it was
    /// interpolated from, is coarser than [`MAX_STEP_DEG`].
    Coarse {
        /// The step (deg).
        step_deg: f64,
    },
    /// The pressure is not positive (or not finite) in the window.
    NotPositive {
        /// Where (deg from the declared TDC).
        at_deg: f64,
    },
    /// The cycle burns: the expansion pressure exceeds the compression
    /// pressure at the same distance from TDC.
    Burns {
        /// By this fraction.
        excess: f64,
        /// At this distance from TDC (deg).
        at_deg: f64,
    },
    /// The least misfit lies at the end of the ±6° scan.
    Beyond,
    /// The fitted exponent is not that of air.
    Exponent {
        /// The exponent fitted.
        n: f64,
    },
    /// The standard error (deg) exceeds [`MAX_STD_ERROR_DEG`].
    Noisy {
        /// The standard error (deg).
        std_error_deg: f64,
    },
}

impl std::fmt::Display for Untrusted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Untrusted::Coarse { step_deg } => write!(
                f,
                "the points are {}° apart, coarser than the {}° the fit needs",
                format::sig(step_deg, 3),
                format::human(MAX_STEP_DEG)
            ),
            Untrusted::NotPositive { at_deg } => write!(
                f,
                "the pressure is not positive at {}° from TDC, inside the fit's window",
                format::trimmed(at_deg, 2)
            ),
            Untrusted::Burns { excess, at_deg } => write!(
                f,
                "the estimate needs a motored or fuel-cut cycle: this one burns (the expansion pressure exceeds the compression pressure {}° from TDC by {} %)",
                format::trimmed(at_deg, 1),
                format::sig(100.0 * excess, 2)
            ),
            Untrusted::Beyond => write!(
                f,
                "the trace fits best with TDC more than {}° from the declared one: check --tdc-deg",
                format::human(MAX_OFFSET_DEG)
            ),
            Untrusted::Exponent { n } => write!(
                f,
                "the fitted polytropic exponent {} is not that of air ({} to {}): check the pegging and the compression ratio",
                format::sig(n, 3),
                format::human(EXPONENT_RANGE.0),
                format::human(EXPONENT_RANGE.1)
            ),
            Untrusted::Noisy { std_error_deg } => write!(
                f,
                "the trace is too noisy: the fit's standard error is {}°, above {}°",
                format::sig(std_error_deg, 2),
                format::human(MAX_STD_ERROR_DEG)
            ),
        }
    }
}

/// Whether points `step_deg` apart are fine enough for the fit: the grid's
/// step, and the file's own spacing when it was interpolated onto a finer
/// grid (the fit would judge the interpolant, not the data).
pub fn fine_enough(step_deg: f64) -> Result<(), Untrusted> {
    if step_deg > 0.0 && step_deg <= MAX_STEP_DEG * (1.0 + 1e-9) {
        Ok(())
    } else {
        Err(Untrusted::Coarse { step_deg })
    }
}

/// The TDC offset of `p`, the pressure (Pa, absolute) on the uniform grid
/// `phi_k = k h` (rad) over one cycle from the declared firing TDC, for
/// `cylinder`'s volume law; a cycle of 360° or less is a two-stroke's.
pub fn estimate(p: &[f64], h: f64, cylinder: &Cylinder) -> Result<Estimate, Untrusted> {
    let step_deg = h.to_degrees();
    fine_enough(step_deg)?;
    if p.is_empty() {
        return Err(Untrusted::Coarse { step_deg });
    }
    let cycle_deg = p.len() as f64 * step_deg;
    let half = if cycle_deg < 540.0 {
        HALF_WINDOW_TWO_STROKE_DEG
    } else {
        HALF_WINDOW_FOUR_STROKE_DEG
    };
    let trace = Segment::new(p, h, half + MAX_OFFSET_DEG + MAX_LOSS_ANGLE_DEG + 5.0)?;
    // Cheap first, and whatever the declared TDC: a motored peak lies at
    // most 2° before TDC, so the point 2° + x after the peak is at least as
    // far from TDC as the point 2° - x, and lower on a motored trace; higher
    // means heat added.
    let peak = (0..trace.p.len()).fold(0, |b, j| if trace.p[j] > trace.p[b] { j } else { b });
    let peak_deg = trace.first_deg + peak as f64 * trace.step_deg;
    if let Some(burn) = trace.burns(peak_deg + MAX_LOSS_ANGLE_DEG, half, 10.0) {
        return Err(burn);
    }
    let fit = Fit {
        trace: &trace,
        p04: trace.p.iter().map(|x| x.powf(0.4)).collect(),
        table: VolumeTable::new(cylinder, h, half),
        half_deg: half,
    };
    // The scan on every point about 0.5° apart; the minimum on all.
    let stride = ((0.5 / step_deg).round() as usize).max(1);
    let scan = (-MAX_OFFSET_DEG / SCAN_STEP_DEG).round() as i32
        ..=(MAX_OFFSET_DEG / SCAN_STEP_DEG).round() as i32;
    let (best, _) = scan
        .map(|i| i as f64 * SCAN_STEP_DEG)
        .map(|d| (d, fit.misfit(d, stride)))
        .fold((0.0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
    if best.abs() > MAX_OFFSET_DEG - 0.5 * SCAN_STEP_DEG {
        return Err(Untrusted::Beyond);
    }
    let (d, s0) = roots::minimize(
        |d| fit.misfit(d, 1),
        best - SCAN_STEP_DEG,
        best + SCAN_STEP_DEG,
        1e-4,
    );
    // With the offset known, the exact mirror test: any excess of the
    // expansion over the compression pressure is heat added.
    if let Some(burn) = trace.burns(d, half, 10.0) {
        return Err(burn);
    }
    let solved = fit.solve(d, 1, true);
    let n = solved.coef[1];
    if !(EXPONENT_RANGE.0..=EXPONENT_RANGE.1).contains(&n) {
        return Err(Untrusted::Exponent { n });
    }
    // The misfit's curvature in d (the squared sensitivity of the
    // residuals to d, summed) against the noise's long-run variance (a
    // file coarser than the grid, interpolated onto it, has noise
    // correlated over a step of the file).
    let e = 0.05;
    let curvature = (fit.misfit(d + e, 1) - 2.0 * s0 + fit.misfit(d - e, 1)) / (2.0 * e * e);
    let variance = solved.noise;
    let std_error_deg = if curvature > 0.0 {
        (variance / curvature).sqrt()
    } else {
        f64::INFINITY
    };
    if !(std_error_deg <= MAX_STD_ERROR_DEG) {
        return Err(Untrusted::Noisy { std_error_deg });
    }
    Ok(Estimate {
        offset_deg: d,
        exponent: n,
        std_error_deg,
    })
}

/// The trace around the declared TDC: angles `first_deg + j step` for
/// `j < p.len()`, unwrapped across the cycle's end.
struct Segment {
    step_deg: f64,
    first_deg: f64,
    p: Vec<f64>,
    ln_p: Vec<f64>,
}

impl Segment {
    /// The points within `reach_deg` of the declared TDC; an error when a
    /// pressure there is not positive.
    fn new(p: &[f64], h: f64, reach_deg: f64) -> Result<Self, Untrusted> {
        let n = p.len();
        let step_deg = h.to_degrees();
        let k = ((reach_deg / step_deg).ceil() as usize).min((n - 1) / 2);
        let values: Vec<f64> = (0..=2 * k).map(|j| p[(j + n - k) % n]).collect();
        let first_deg = -(k as f64) * step_deg;
        if let Some(j) = values.iter().position(|&x| !(x > 0.0 && x.is_finite())) {
            return Err(Untrusted::NotPositive {
                at_deg: first_deg + j as f64 * step_deg,
            });
        }
        Ok(Self {
            step_deg,
            first_deg,
            ln_p: values.iter().map(|x| x.ln()).collect(),
            p: values,
        })
    }

    /// Index range of the angles within `[from, to]` (deg).
    fn span(&self, from: f64, to: f64) -> std::ops::Range<usize> {
        let lo = ((from - self.first_deg) / self.step_deg - 1e-9)
            .ceil()
            .max(0.0) as usize;
        let hi = ((to - self.first_deg) / self.step_deg + 1e-9).floor();
        let hi = if hi < 0.0 { 0 } else { hi as usize + 1 };
        lo.min(self.p.len())..hi.min(self.p.len())
    }

    /// `ln p` over `[from, to]` (deg): the mean and its variance, from the
    /// scatter about a straight line through the band (noise, not the
    /// pressure's own rise).
    fn band(&self, from: f64, to: f64) -> Option<(f64, f64)> {
        let last = self.first_deg + (self.p.len() - 1) as f64 * self.step_deg;
        if from < self.first_deg || to > last {
            return None;
        }
        let r = self.span(from, to);
        let m = r.len() as f64;
        if m < 3.0 {
            return None;
        }
        let ys = &self.ln_p[r];
        let mid = 0.5 * (m - 1.0);
        let mean = ys.iter().sum::<f64>() / m;
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for (i, y) in ys.iter().enumerate() {
            let x = i as f64 - mid;
            sxy += x * (y - mean);
            sxx += x * x;
        }
        let slope = sxy / sxx;
        let sse: f64 = ys
            .iter()
            .enumerate()
            .map(|(i, y)| (y - mean - slope * (i as f64 - mid)).powi(2))
            .sum();
        Some((mean, sse / (m - 2.0) / m))
    }

    /// The largest excess of the expansion over the compression pressure,
    /// mirrored about `centre_deg`, over 5° bands from `from_deg` to
    /// `half_deg` away: `Some` when it shows combustion, beyond
    /// [`BURN_EXCESS`] and three standard deviations of the bands' noise.
    fn burns(&self, centre_deg: f64, half_deg: f64, from_deg: f64) -> Option<Untrusted> {
        let mut worst: Option<(f64, f64)> = None;
        let mut x = from_deg;
        while x + 2.5 <= half_deg {
            let after = self.band(centre_deg + x - 2.5, centre_deg + x + 2.5);
            let before = self.band(centre_deg - x - 2.5, centre_deg - x + 2.5);
            if let (Some((a, va)), Some((b, vb))) = (after, before) {
                let excess = a - b;
                if excess - 3.0 * (va + vb).sqrt() > BURN_EXCESS.ln_1p()
                    && worst.is_none_or(|(e, _)| excess > e)
                {
                    worst = Some((excess, x));
                }
            }
            x += 5.0;
        }
        worst.map(|(e, x)| Untrusted::Burns {
            excess: e.exp() - 1.0,
            at_deg: x,
        })
    }
}

/// The volume law's terms of the model on the trace's grid around TDC,
/// `t_i = (i - centre) h`, with their slopes, for cubic Hermite
/// interpolation at the shifted angles `phi - d` (every point of a trial
/// shares one fraction of a step, and the volume law is smooth: the
/// interpolation error is below 1e-9 of the volume at a 1° step). Built
/// once, so the fit evaluates no transcendental function per point and
/// trial.
struct VolumeTable {
    centre: usize,
    /// `ln V` and its slope (per step).
    ln_v: Vec<(f64, f64)>,
    /// `V` and its slope (per step).
    v: Vec<(f64, f64)>,
    /// `A V^-0.46` and its slope (per step), `A = pi B²/2 + 4 V / B`.
    q: Vec<(f64, f64)>,
}

impl VolumeTable {
    /// The table over `|t| <= reach_deg` on steps of `h` (rad).
    fn new(cylinder: &Cylinder, h: f64, reach_deg: f64) -> Self {
        let centre = (reach_deg.to_radians() / h).ceil() as usize + 2;
        let bore = cylinder.bore();
        let ends = PI * bore * bore / 2.0;
        let (mut ln_v, mut v, mut q) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..=2 * centre {
            let t = (i as f64 - centre as f64) * h;
            let (vol, dvol) = (cylinder.volume(t), cylinder.dvolume(t) * h);
            let area = ends + 4.0 * vol / bore;
            let darea = 4.0 * dvol / bore;
            let power = vol.powf(-0.46);
            ln_v.push((vol.ln(), dvol / vol));
            v.push((vol, dvol));
            q.push((
                area * power,
                darea * power - 0.46 * area * power * dvol / vol,
            ));
        }
        Self { centre, ln_v, v, q }
    }
}

/// Cubic Hermite weights at the fraction `f` of a step: value at the left
/// node, slope there, value at the right node, slope there.
fn hermite(f: f64) -> [f64; 4] {
    let (f2, f3) = (f * f, f * f * f);
    [
        2.0 * f3 - 3.0 * f2 + 1.0,
        f3 - 2.0 * f2 + f,
        -2.0 * f3 + 3.0 * f2,
        f3 - f2,
    ]
}

fn at(table: &[(f64, f64)], i: usize, w: &[f64; 4]) -> f64 {
    w[0] * table[i].0 + w[1] * table[i].1 + w[2] * table[i + 1].0 + w[3] * table[i + 1].1
}

/// The model of the closed part around a trial TDC.
struct Fit<'a> {
    trace: &'a Segment,
    /// `p^0.4` on the trace, for the heat loss's `p^0.8 (p V)^-0.4`.
    p04: Vec<f64>,
    table: VolumeTable,
    half_deg: f64,
}

/// The model fitted at one trial offset.
struct Solved {
    /// The weighted misfit (sum of squares).
    misfit: f64,
    /// `[a, n, c1, c2]`.
    coef: [f64; 4],
    /// The long-run variance of the residuals' noise, when asked for.
    noise: f64,
}

impl Fit<'_> {
    /// The weighted misfit with TDC at `delta_deg` on the trace's axis,
    /// from every `stride`-th point.
    fn misfit(&self, delta_deg: f64, stride: usize) -> f64 {
        self.solve(delta_deg, stride, false).misfit
    }

    /// The model fitted with TDC at `delta_deg`, from every `stride`-th
    /// point of the window; the residuals' correlation when `residuals`.
    fn solve(&self, delta_deg: f64, stride: usize, residuals: bool) -> Solved {
        let failed = || Solved {
            misfit: f64::INFINITY,
            coef: [f64::NAN; 4],
            noise: f64::INFINITY,
        };
        let tr = self.trace;
        let range = tr.span(delta_deg - self.half_deg, delta_deg + self.half_deg);
        let idx: Vec<usize> = range.step_by(stride).collect();
        let m = idx.len();
        if m < 16 {
            return failed();
        }
        // Point j of the trace sits at t = (j - K + u) steps from the trial
        // TDC, u = -d / step: table node j - K + floor(u) + centre, plus
        // the fraction u - floor(u).
        let u = -delta_deg / tr.step_deg;
        let whole = u.floor();
        let w = hermite(u - whole);
        let k0 = self.table.centre as f64 + whole + tr.first_deg / tr.step_deg;
        let h = stride as f64 * tr.step_deg.to_radians();
        let mut a = vec![0.0; 4 * m];
        let mut b = vec![0.0; m];
        let (mut h1, mut h2) = (0.0, 0.0);
        let (mut g1_prev, mut g2_prev) = (0.0, 0.0);
        let mut g_max: f64 = 0.0;
        // g1 = A V^-0.06 p^0.8 (p V)^-0.4 = (A V^-0.46) p^0.4, g2 = g1 / (p V),
        // integrated by the trapezoid rule (columns 2 and 3 hold the
        // integrals, scaled afterwards).
        for (i, &j) in idx.iter().enumerate() {
            let node = (k0 + j as f64).round() as usize;
            let t = &self.table;
            let ln_v = at(&t.ln_v, node, &w);
            let v = at(&t.v, node, &w);
            let g1 = at(&t.q, node, &w) * self.p04[j];
            let g2 = g1 / (tr.p[j] * v);
            if i > 0 {
                h1 += 0.5 * (g1_prev + g1) * h;
                h2 += 0.5 * (g2_prev + g2) * h;
            }
            (g1_prev, g2_prev) = (g1, g2);
            g_max = g_max.max(g1);
            let t_deg = tr.first_deg + j as f64 * tr.step_deg - delta_deg;
            let taper = ((self.half_deg - t_deg.abs()) / TAPER_DEG).clamp(0.0, 1.0);
            let weight = tr.p[j] * taper;
            a[i] = weight;
            a[m + i] = -weight * ln_v;
            a[2 * m + i] = -weight * h1;
            a[3 * m + i] = -weight * h2;
            b[i] = weight * tr.ln_p[j];
        }
        // Scale the loss columns to the size of the others (g2 / g1 is
        // about 1 / (p V) ~ 1e-2 1/J): the fit does not change, its
        // conditioning does.
        let g2_scale =
            tr.p[idx[m / 2]] * at(&self.table.v, self.table.centre, &[1.0, 0.0, 0.0, 0.0]);
        for i in 0..m {
            a[2 * m + i] /= g_max;
            a[3 * m + i] *= g2_scale / g_max;
        }
        let original = residuals.then(|| (a.clone(), b.clone()));
        let Some((mut coef, misfit)) = least_squares(&mut a, &mut b, m) else {
            return failed();
        };
        let mut noise = f64::INFINITY;
        if let Some((a, b)) = original {
            let r: Vec<f64> = (0..m)
                .map(|i| b[i] - (0..4).map(|c| a[c * m + i] * coef[c]).sum::<f64>())
                .collect();
            let points = |deg: f64| ((deg / (stride as f64 * tr.step_deg)).round() as usize).max(1);
            noise = long_run_variance(&r, points(NOISE_SMOOTHING_DEG), points(NOISE_LAGS_DEG));
        }
        coef[2] /= g_max;
        coef[3] *= g2_scale / g_max;
        Solved {
            misfit,
            coef,
            noise,
        }
    }
}

/// The noise in residuals `r`, as the variance of the mean it gives per
/// point (the long-run variance: the autocovariances summed over `lags`
/// either way with Bartlett's weights, the Newey–West estimate), from their
/// scatter about their running mean over `2 width + 1` points (so the
/// model's smooth misfit, a bias and no noise, drops out).
fn long_run_variance(r: &[f64], width: usize, lags: usize) -> f64 {
    let m = r.len();
    let mut prefix = Vec::with_capacity(m + 1);
    prefix.push(0.0);
    for x in r {
        prefix.push(prefix[prefix.len() - 1] + x);
    }
    let high: Vec<f64> = (0..m)
        .map(|i| {
            let (lo, hi) = (i.saturating_sub(width), (i + width + 1).min(m));
            r[i] - (prefix[hi] - prefix[lo]) / (hi - lo) as f64
        })
        .collect();
    let covariance =
        |k: usize| high[k..].iter().zip(&high).map(|(a, b)| a * b).sum::<f64>() / m as f64;
    let mut sum = covariance(0);
    for k in 1..=lags.min(m - 1) {
        sum += 2.0 * (1.0 - k as f64 / (lags + 1) as f64) * covariance(k);
    }
    sum.max(0.0)
}

/// Least squares of the `m × 4` column-major `a` against `b` by
/// Householder reflections (both overwritten): the coefficients and the
/// sum of the squared residuals; `None` when `a` is rank deficient.
fn least_squares(a: &mut [f64], b: &mut [f64], m: usize) -> Option<([f64; 4], f64)> {
    const N: usize = 4;
    let mut diag = [0.0; N];
    for k in 0..N {
        let col = k * m;
        let norm = a[col + k..col + m]
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        let alpha = if a[col + k] > 0.0 { -norm } else { norm };
        // v = x - alpha e_k, stored in place of the column's tail.
        a[col + k] -= alpha;
        let vv: f64 = a[col + k..col + m].iter().map(|x| x * x).sum();
        diag[k] = alpha;
        if vv == 0.0 {
            continue;
        }
        let reflect = |target: &mut [f64], v: &[f64]| {
            let dot: f64 = target.iter().zip(v).map(|(t, v)| t * v).sum();
            let f = 2.0 * dot / vv;
            target.iter_mut().zip(v).for_each(|(t, v)| *t -= f * v);
        };
        let (left, right) = a.split_at_mut((k + 1) * m);
        let v = &left[col + k..col + m];
        for j in 0..N - k - 1 {
            reflect(&mut right[j * m + k..(j + 1) * m], v);
        }
        reflect(&mut b[k..m], v);
    }
    // R x = (Q^T b)[..4]: R's diagonal is `diag`, above it `a`.
    let mut x = [0.0; N];
    for k in (0..N).rev() {
        let mut s = b[k];
        for j in k + 1..N {
            s -= a[j * m + k] * x[j];
        }
        if diag[k].abs() < 1e-13 * diag[0].abs() {
            return None;
        }
        x[k] = s / diag[k];
    }
    Some((x, b[N..m].iter().map(|r| r * r).sum()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Householder solver against a known line and plane.
    #[test]
    fn least_squares_recovers_exact_coefficients() {
        let m = 50;
        let truth = [1.5, -2.0, 0.25, 3.0];
        let mut a = vec![0.0; 4 * m];
        let mut b = vec![0.0; m];
        for i in 0..m {
            let x = i as f64 / 7.0;
            let row = [1.0, x, x * x, (x * 0.3).sin()];
            for c in 0..4 {
                a[c * m + i] = row[c];
            }
            b[i] = row.iter().zip(truth).map(|(r, t)| r * t).sum();
        }
        let (x, misfit) = least_squares(&mut a, &mut b, m).unwrap();
        assert!(misfit < 1e-20, "{misfit}");
        for (got, want) in x.iter().zip(truth) {
            assert!((got - want).abs() < 1e-10, "{got} vs {want}");
        }
        // Two equal columns: rank deficient.
        let mut a = vec![1.0; 4 * m];
        let mut b = vec![1.0; m];
        assert!(least_squares(&mut a, &mut b, m).is_none());
    }
}
