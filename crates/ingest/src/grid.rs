//! From traces to the uniform grid: interpolation, pegging, per-cycle
//! statistics and the ensemble average, one trace at a time so a file of any
//! length needs memory for one cycle only.

use crate::{IngestError, Interp, Quantity, Trace};
use enginedyn_kinematics::{Cylinder, VolumeGrid};
use enginedyn_numerics::{InterpKind, Periodic};
use std::sync::Arc;

/// Pegging of relative (piezoelectric) traces, per cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Peg {
    /// Shift so the mean over ±5° around intake BDC is this absolute pressure (Pa).
    Bar(f64),
    /// Fit the offset so `p V^n` is constant on compression from 100° to 30° BTDC.
    Polytropic(f64),
}

/// What the grid stage needs.
#[derive(Debug, Clone, PartialEq)]
pub struct GridOptions {
    /// Grid step (deg); must divide the cycle.
    pub step_deg: f64,
    /// Interpolation.
    pub interp: Interp,
    /// Pegging, if any.
    pub peg: Option<Peg>,
    /// The volume law, for per-cycle IMEP and polytropic pegging.
    pub cylinder: Option<Cylinder>,
    /// `cylinder`'s volume on this grid, built once by
    /// [`GridOptions::share_volume_law`] for every file read with these
    /// options; without it (or when it does not fit) each file builds its own.
    pub volume_law: Option<Arc<VolumeGrid>>,
    /// The combustion analysis of every pressure cycle (needs `cylinder`);
    /// `None`: no analysis.
    pub combustion: Option<Arc<enginedyn_combustion::Options>>,
}

impl GridOptions {
    /// A plain grid: no pegging, no volume law.
    pub fn new(step_deg: f64, interp: Interp) -> Self {
        Self {
            step_deg,
            interp,
            peg: None,
            cylinder: None,
            volume_law: None,
            combustion: None,
        }
    }

    /// Builds the volume law once for a cycle of `cycle_deg`, to be shared by
    /// every file read with these options (nothing without a cylinder or
    /// with a step that does not divide the cycle).
    pub fn share_volume_law(&mut self, cycle_deg: f64) {
        self.volume_law = match (self.cylinder, grid_points(self.step_deg, cycle_deg)) {
            (Some(c), Some(n)) => {
                Some(Arc::new(VolumeGrid::new(&c, self.step_deg.to_radians(), n)))
            }
            _ => None,
        };
    }
}

/// The number of grid points of `step_deg` in a cycle of `cycle_deg`, when
/// the step divides it into at least 8.
fn grid_points(step_deg: f64, cycle_deg: f64) -> Option<usize> {
    let n = (cycle_deg / step_deg).round() as usize;
    (step_deg > 0.0 && n >= 8 && ((n as f64) * step_deg - cycle_deg).abs() <= 1e-9 * cycle_deg)
        .then_some(n)
}

/// What one measured cycle says of its combustion.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleCombustion {
    /// Gross IMEP (Pa): `∫ p dV` over −180…180° / V_d.
    pub imep_gross_pa: f64,
    /// Heat released (J), `Q(EOC) − Q(SOC)`, whether or not it clears the
    /// no-combustion bound.
    pub heat_released_j: f64,
    /// The no-combustion bound (J).
    pub bound_j: f64,
    /// The trace's noise (Pa, one sample's standard deviation).
    pub noise_pa: f64,
    /// The heat clears the bound but the noise hides the burn.
    pub unresolved: bool,
    /// With a wall-heat model: the gross heat released (J).
    pub heat_released_gross_j: Option<f64>,
    /// With a wall-heat model: the heat lost to the walls between SOC and
    /// EOC (J).
    pub wall_heat_j: Option<f64>,
    /// Knock, when measured: MAPO and IMPO, or why the data do not
    /// resolve the band.
    pub knock:
        Option<Result<enginedyn_combustion::KnockFigures, enginedyn_combustion::knock::Unresolved>>,
    /// The burn points, `None` without combustion.
    pub burn: Option<enginedyn_combustion::BurnPoints>,
}

/// Figures of one measured cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleStats {
    /// Cylinder number (0: one trace for all).
    pub cylinder: i64,
    /// Cycle number.
    pub cycle: i64,
    /// IMEP (Pa), when the volume law is known.
    pub imep_pa: Option<f64>,
    /// Peak pressure (Pa).
    pub p_max: f64,
    /// Its angle (deg from firing TDC, in `[-cycle/2, cycle/2)`).
    pub p_max_angle_deg: f64,
    /// Pegging offset added (Pa).
    pub peg_offset: f64,
    /// The speed over this cycle (rpm), when the file measures it cycle by
    /// cycle (a time record's TDC pulses).
    pub rpm: Option<f64>,
    /// The combustion analysis, when it was asked for and the volume law
    /// is known.
    pub combustion: Option<CycleCombustion>,
}

/// A measured cycle left out of the averages, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct SkippedCycle {
    /// Cylinder number (0: one trace for all).
    pub cylinder: i64,
    /// Cycle number.
    pub cycle: i64,
    /// Why, as the note on the skipped cycles says it.
    pub reason: String,
}

/// Pegging as reported in `summary.json`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PegReport {
    /// The method.
    pub method: Peg,
    /// Mean offset over the cycles (Pa).
    pub mean_offset: f64,
}

/// Values on the uniform grid `k * step_deg`, `k = 0..n`, from firing TDC.
#[derive(Debug, Clone, PartialEq)]
pub struct Resampled {
    /// Grid step (deg).
    pub step_deg: f64,
    /// What the values are.
    pub quantity: Quantity,
    /// Mean over every trace (Pa, or N m for torque): the diagram for all cylinders.
    pub pressure: Vec<f64>,
    /// Per-cylinder means (`[k]` = cylinder `k + 1`), when the traces name cylinders.
    pub cylinders: Vec<Vec<f64>>,
    /// Interpolant used (for `auto`, the one it chose).
    pub interp: InterpKind,
    /// How many traces each interpolant took, the most used first where
    /// `auto` chose trace by trace (empty for data made on the grid).
    pub interp_counts: Vec<(InterpKind, usize)>,
    /// Number of cycles averaged (per cylinder).
    pub cycles: usize,
    /// Per-cycle figures.
    pub stats: Vec<CycleStats>,
    /// Pegging applied.
    pub pegging: Option<PegReport>,
    /// Speed from the file.
    pub rpm: Option<f64>,
    /// True when the file held p–V data (placed on angles by the volume law).
    pub pv: bool,
    /// Cycles left out of the averages (a gap in the data).
    pub cycles_skipped: usize,
    /// Those cycles, in the order they were read (one per
    /// `cycles_skipped`).
    pub skipped: Vec<SkippedCycle>,
    /// The coarsest mean spacing of the file's samples (deg): the grid
    /// step when the data lay on the grid.
    pub sample_step_deg: f64,
    /// Things worth telling the user.
    pub notes: Vec<String>,
    /// The combustion options the cycles were analysed with.
    pub combustion: Option<Arc<enginedyn_combustion::Options>>,
    /// The file says it was synthesised (`enginedyn synth`): its firing
    /// TDC is exact, so no rule questions it.
    pub synthetic: bool,
    /// With knock measured: the cycle of the largest MAPO (cylinder,
    /// cycle, MAPO in Pa) and its band-passed pressure over the knock
    /// window (deg, Pa), for the chart.
    pub most_knocking: Option<MostKnocking>,
}

/// A cycle's band-passed pressure when its MAPO is the largest so far
/// (`kept`), else `None`: computed again only then (a new largest is
/// rare).
fn most_knocking(
    opts: &GridOptions,
    kept: Option<&MostKnocking>,
    p: &[f64],
    tr: &Trace,
    c: Option<&CycleCombustion>,
) -> Option<MostKnocking> {
    let f = c?.knock.as_ref()?.as_ref().ok()?;
    if kept.is_some_and(|m| m.mapo_pa >= f.mapo_pa) {
        return None;
    }
    let o = opts.combustion.as_deref()?;
    let (k, rpm) = (o.knock.as_ref()?, tr.rpm.or(o.rpm)?);
    Some(MostKnocking {
        cylinder: tr.cylinder,
        cycle: tr.cycle,
        mapo_pa: f.mapo_pa,
        trace: enginedyn_combustion::band_passed_window(p, opts.step_deg, rpm, k),
    })
}

/// The cycle of the largest MAPO and its band-passed pressure.
#[derive(Debug, Clone, PartialEq)]
pub struct MostKnocking {
    /// Cylinder number (0: one trace for all).
    pub cylinder: i64,
    /// Cycle number.
    pub cycle: i64,
    /// Its MAPO (Pa).
    pub mapo_pa: f64,
    /// The band-passed pressure over the knock window: (deg, Pa).
    pub trace: Vec<(f64, f64)>,
}

impl Resampled {
    /// A resampled curve from values already on the grid (tests, generated data).
    pub fn from_grid(step_deg: f64, values: Vec<f64>) -> Self {
        Self {
            step_deg,
            quantity: Quantity::Pressure,
            pressure: values,
            cylinders: Vec::new(),
            interp: InterpKind::Linear,
            interp_counts: Vec::new(),
            cycles: 1,
            stats: Vec::new(),
            pegging: None,
            rpm: None,
            pv: false,
            cycles_skipped: 0,
            skipped: Vec::new(),
            sample_step_deg: step_deg,
            notes: Vec::new(),
            combustion: None,
            synthetic: false,
            most_knocking: None,
        }
    }
}

/// Lanes of the accumulation pass: with four, every running value stays in
/// a vector register (with eight, some were spilled to the stack).
const LANES: usize = 4;
/// Samples per block of the accumulation pass: each block's largest sample
/// is compared once, so the peak's index is then looked for in one block
/// (a search of the whole cycle cost as much as the pass itself).
const BLOCK: usize = 64;

/// What [`accumulate`] finds in one cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Pass {
    /// Every sample finite (and, for pressure, not negative).
    sane: bool,
    /// The largest sample.
    peak: f64,
    /// Its first index.
    at: usize,
    /// `sum src_k dv_k`.
    p_dv: f64,
}

/// One pass over a cycle's samples `src`: adds them to `sum`, checks them,
/// and finds their peak and `sum src_k dv_k` (`dv` as long as `src`,
/// finite). Not inlined: on its own the compiler keeps the lanes in
/// registers and vectorises them.
#[inline(never)]
fn accumulate(src: &[f64], sum: &mut [f64], dv: &[f64]) -> Pass {
    let n = src.len().min(sum.len()).min(dv.len());
    let (src, sum, dv) = (&src[..n], &mut sum[..n], &dv[..n]);
    let mut dot = [0.0; LANES];
    let mut lo = [f64::INFINITY; LANES];
    let (mut peak, mut peak_block) = (f64::NEG_INFINITY, 0);
    let whole = n / BLOCK * BLOCK;
    for (b, ((p, s), d)) in src[..whole]
        .chunks_exact(BLOCK)
        .zip(sum[..whole].chunks_exact_mut(BLOCK))
        .zip(dv[..whole].chunks_exact(BLOCK))
        .enumerate()
    {
        let mut hi = [f64::NEG_INFINITY; LANES];
        for ((p, s), d) in p
            .chunks_exact(LANES)
            .zip(s.chunks_exact_mut(LANES))
            .zip(d.chunks_exact(LANES))
        {
            for j in 0..LANES {
                let x = p[j];
                s[j] += x;
                dot[j] += x * d[j];
                lo[j] = if x < lo[j] { x } else { lo[j] };
                hi[j] = if x > hi[j] { x } else { hi[j] };
            }
        }
        let h = hi
            .iter()
            .fold(f64::NEG_INFINITY, |a, &b| if b > a { b } else { a });
        if h > peak {
            peak = h;
            peak_block = b;
        }
    }
    // The first index of the peak lies in the first block that holds it.
    let mut at = src[peak_block * BLOCK..whole]
        .iter()
        .position(|&x| x >= peak)
        .map_or(0, |k| peak_block * BLOCK + k);
    let mut tail = 0.0;
    for k in whole..n {
        let x = src[k];
        sum[k] += x;
        tail += x * dv[k];
        lo[0] = if x < lo[0] { x } else { lo[0] };
        if x > peak {
            peak = x;
            at = k;
        }
    }
    let low = lo.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    let p_dv = (dot[0] + dot[1]) + (dot[2] + dot[3]) + tail;
    // A NaN or an infinity makes the products NaN or infinite (also where
    // dv is 0); finite samples of any plausible size keep them finite.
    let finite = p_dv.is_finite() && low.is_finite() && peak.is_finite();
    Pass {
        sane: finite,
        peak,
        at,
        p_dv,
    }
}

/// True when `n` angles from `first`, whose successive steps lie in
/// `steps = (lo, hi)`, are each within 1e-9° of `k h`, from the steps alone:
/// `a_k = a_0 +` the `k` steps before it (each step's subtraction rounds by
/// under 2^-53 of it: 1e-13 in all over a cycle), so
/// `|a_k - k h| <= |a_0| + k max|step - h|`. Evenly spaced text at 0.1°
/// passes (a test); `false` says only that the bound does not settle it.
fn steps_settle(first: f64, n: usize, h: f64, (lo, hi): (f64, f64)) -> bool {
    let worst = (lo - h).abs().max((hi - h).abs());
    first.abs() + n.saturating_sub(1) as f64 * worst < 0.9e-9
}

/// Interpolates traces onto the grid one at a time and keeps running sums.
pub struct Accumulator {
    opts: GridOptions,
    cycle_deg: f64,
    quantity: Quantity,
    n: usize,
    buf: Vec<f64>,
    sum: Vec<f64>,
    count: usize,
    per_cylinder: Vec<(Vec<f64>, usize)>,
    stats: Vec<CycleStats>,
    interp: Option<InterpKind>,
    /// How many traces each interpolant took (by `InterpKind as usize`).
    interp_counts: [usize; 3],
    /// The most knocking cycle so far, for the chart.
    most_knocking: Option<MostKnocking>,
    /// The volume law on the grid, when the cylinder is known.
    law: Option<Arc<VolumeGrid>>,
    /// The grid's angles `k step` (deg), for the on-grid test.
    angles: Vec<f64>,
    notes: Vec<String>,
    /// Traces whose spline overshot (pchip used instead), and the worst
    /// overshoot (fraction of the peak): said once, with a count.
    overshoot: (usize, f64),
    /// Traces coarser than 2° on average, the coarsest spacing (deg) and
    /// the interpolant used: said once, with a count.
    sparse: (usize, f64, Option<InterpKind>),
    /// The coarsest mean spacing of a trace's samples (deg); the grid step
    /// for traces on the grid.
    spacing: f64,
    /// The smoothing filter of the combustion analysis, built once.
    filter: Option<enginedyn_combustion::Filter>,
    /// The volume law's figures over the burn window, taken once from
    /// `law` (which it lives beside) for every cycle's analysis.
    window_law: Option<enginedyn_combustion::WindowLaw>,
}

impl Accumulator {
    /// A new accumulator for a cycle of `cycle_deg` and values of `quantity`.
    pub fn new(opts: GridOptions, cycle_deg: f64, quantity: Quantity) -> Result<Self, IngestError> {
        let step = opts.step_deg;
        let Some(n) = grid_points(step, cycle_deg) else {
            return Err(IngestError::Data(format!(
                "grid step {step}° must divide the {cycle_deg}° cycle into at least 8 steps"
            )));
        };
        let law = opts.cylinder.map(|c| match &opts.volume_law {
            Some(law) if law.fits(&c, step.to_radians(), n) => Arc::clone(law),
            _ => Arc::new(VolumeGrid::new(&c, step.to_radians(), n)),
        });
        if matches!(opts.peg, Some(Peg::Polytropic(_))) && law.is_none() {
            return Err(IngestError::Data(
                "--peg polytropic needs the engine's volume law".into(),
            ));
        }
        let window_law = match (&law, opts.combustion.as_deref()) {
            (Some(law), Some(c)) => {
                enginedyn_combustion::WindowLaw::new(law.volume(), law.dvolume(), step, c)
            }
            _ => None,
        };
        Ok(Self {
            cycle_deg,
            quantity,
            n,
            buf: vec![0.0; n],
            sum: vec![0.0; n],
            count: 0,
            per_cylinder: Vec::new(),
            stats: Vec::new(),
            interp: None,
            interp_counts: [0; 3],
            most_knocking: None,
            law,
            angles: (0..n).map(|k| k as f64 * step).collect(),
            notes: Vec::new(),
            overshoot: (0, 0.0),
            sparse: (0, 0.0, None),
            spacing: step,
            filter: opts
                .combustion
                .as_ref()
                .map(|c| enginedyn_combustion::Filter::new(c.smoothing, step)),
            window_law,
            opts,
        })
    }

    /// Adds one trace (angles in `[0, cycle)`, rising).
    pub fn add(&mut self, tr: &Trace) -> Result<(), IngestError> {
        self.add_with_steps(tr, None)
    }

    /// [`Self::add`], given the smallest and largest step between the
    /// trace's successive angles when they are known ([`crate::Streamed`]).
    pub fn add_with_steps(
        &mut self,
        tr: &Trace,
        steps: Option<(f64, f64)>,
    ) -> Result<(), IngestError> {
        let on_grid = self.on_grid(tr, steps);
        let (kind, tested) = self.choose(tr, on_grid)?;
        let pressure = self.quantity == Quantity::Pressure;
        // Every interpolant passes through its samples: data already on the
        // grid is its own interpolation (and, unpegged, is read in place).
        let in_place = on_grid && (self.opts.peg.is_none() || !pressure);
        if on_grid && !in_place {
            self.buf.copy_from_slice(&tr.values);
        } else if !on_grid {
            let spacing = self.cycle_deg / tr.angle_deg.len() as f64;
            self.spacing = self.spacing.max(spacing);
            if spacing > 2.0 {
                self.sparse.0 += 1;
                self.sparse.1 = self.sparse.1.max(spacing);
                self.sparse.2.get_or_insert(kind);
            }
            // `auto` already built the spline to test it: use that one.
            let f = match tested {
                Some(f) if kind == InterpKind::Spline => f,
                _ => Periodic::new(kind, &tr.angle_deg, &tr.values, self.cycle_deg)
                    .map_err(|e| IngestError::Data(format!("cycle {}: {e}", tr.cycle)))?,
            };
            f.eval_uniform(0.0, self.opts.step_deg, &mut self.buf);
        }
        let peg_offset = if pressure && !in_place {
            self.peg()?
        } else {
            0.0
        };
        let src: &[f64] = if in_place { &tr.values } else { &self.buf };
        // One pass: the check, the sums, the peak and p dV. A failed check
        // ends the whole read, so the sums it touched are never used.
        let dv: &[f64] = match &self.law {
            Some(law) => law.dvolume(),
            // No volume law: p dV is not wanted (no IMEP without the
            // cylinder); any finite weights of cycle length keep the pass
            // and its check (a NaN or an infinity makes p dV non-finite).
            None => &self.angles,
        };
        let pass = accumulate(src, &mut self.sum, dv);
        if !pass.sane {
            let k = src.iter().position(|p| !p.is_finite()).unwrap_or(0);
            return Err(IngestError::Data(format!(
                "cycle {}: the {} interpolant gives {:.4e} at {}°{}",
                tr.cycle,
                kind.name(),
                src[k],
                k as f64 * self.opts.step_deg,
                if peg_offset != 0.0 {
                    " after pegging: check the pegging pressure"
                } else if kind != InterpKind::Pchip {
                    "; try --interp pchip"
                } else {
                    ""
                }
            )));
        }
        if pressure {
            let mut angle = pass.at as f64 * self.opts.step_deg;
            if angle >= self.cycle_deg / 2.0 {
                angle -= self.cycle_deg;
            }
            let imep_pa = self
                .opts
                .cylinder
                .map(|c| pass.p_dv * self.opts.step_deg.to_radians() / c.swept_volume());
            let spacing = (!on_grid).then(|| self.cycle_deg / tr.angle_deg.len() as f64);
            let combustion = self.combustion(src, tr.rpm, spacing)?;
            if let Some(m) = most_knocking(
                &self.opts,
                self.most_knocking.as_ref(),
                src,
                tr,
                combustion.as_ref(),
            ) {
                self.most_knocking = Some(m);
            }
            self.stats.push(CycleStats {
                cylinder: tr.cylinder,
                cycle: tr.cycle,
                imep_pa,
                p_max: pass.peak,
                p_max_angle_deg: angle,
                peg_offset,
                rpm: tr.rpm,
                combustion,
            });
        }
        self.count += 1;
        if tr.cylinder > 0 {
            let i = (tr.cylinder - 1) as usize;
            if self.per_cylinder.len() <= i {
                self.per_cylinder.resize(i + 1, (Vec::new(), 0));
            }
            let (s, c) = &mut self.per_cylinder[i];
            if s.is_empty() {
                s.resize(self.n, 0.0);
            }
            for (a, p) in s.iter_mut().zip(src) {
                *a += p;
            }
            *c += 1;
        }
        self.interp.get_or_insert(kind);
        self.interp_counts[kind as usize] += 1;
        Ok(())
    }

    /// The combustion analysis of one cycle's pressure on the grid, when it
    /// is asked for and the volume law is known.
    fn combustion(
        &self,
        p: &[f64],
        rpm: Option<f64>,
        sample_step_deg: Option<f64>,
    ) -> Result<Option<CycleCombustion>, IngestError> {
        let (Some(opts), Some(filter), Some(law), Some(cyl)) = (
            self.opts.combustion.as_deref(),
            self.filter.as_ref(),
            self.law.as_deref(),
            self.opts.cylinder,
        ) else {
            return Ok(None);
        };
        let grid = enginedyn_combustion::CycleGrid {
            pressure: p,
            volume: law.volume(),
            dvolume: law.dvolume(),
            step_deg: self.opts.step_deg,
            rpm,
            sample_step_deg,
        };
        let r =
            enginedyn_combustion::analyse_with_law(&grid, opts, filter, self.window_law.as_ref())
                .map_err(|e| IngestError::Data(e.to_string()))?;
        Ok(Some(CycleCombustion {
            imep_gross_pa: r.gross_work_j / cyl.swept_volume(),
            heat_released_j: r.heat_released_j,
            bound_j: r.bound_j,
            noise_pa: r.noise_pa,
            unresolved: r.unresolved,
            heat_released_gross_j: r.heat_released_gross_j,
            wall_heat_j: r.wall_heat_j,
            knock: r.knock,
            burn: r.burn,
        }))
    }

    /// Pegs `buf` in place; returns the offset added (Pa).
    fn peg(&mut self) -> Result<f64, IngestError> {
        let step = self.opts.step_deg;
        let offset = match self.opts.peg {
            None => return Ok(0.0),
            Some(Peg::Bar(target)) => {
                let samples = self
                    .buf
                    .iter()
                    .enumerate()
                    .map(|(k, p)| (k as f64 * step, *p));
                target - intake_bdc_mean(samples, self.cycle_deg).unwrap_or(0.0)
            }
            Some(Peg::Polytropic(n)) => {
                // (p + d) V^n = C on 100°..30° BTDC: p V^n = C - d V^n, a line in V^n.
                // `new` refuses polytropic pegging without the volume law.
                let volume = self.law.as_deref().map_or(&[][..], VolumeGrid::volume);
                let (mut sx, mut sy, mut sxx, mut sxy, mut m) = (0.0, 0.0, 0.0, 0.0, 0.0);
                for (k, (p, v)) in self.buf.iter().zip(volume).enumerate() {
                    let a = k as f64 * step - self.cycle_deg;
                    if (-100.0..=-30.0).contains(&a) {
                        let x = v.powf(n);
                        let y = p * x;
                        sx += x;
                        sy += y;
                        sxx += x * x;
                        sxy += x * y;
                        m += 1.0;
                    }
                }
                let den = m * sxx - sx * sx;
                if m < 3.0 || den.abs() < f64::MIN_POSITIVE {
                    return Err(IngestError::Data(
                        "--peg polytropic: too few points between 100° and 30° before TDC".into(),
                    ));
                }
                -(m * sxy - sx * sy) / den
            }
        };
        for p in &mut self.buf {
            *p += offset;
        }
        Ok(offset)
    }

    /// True when the trace's angles are the grid's, one for one (each
    /// within 1e-9°).
    fn on_grid(&self, tr: &Trace, steps: Option<(f64, f64)>) -> bool {
        let (n, h) = (self.n, self.opts.step_deg);
        if tr.angle_deg.len() != n {
            return false;
        }
        if steps.is_some_and(|s| steps_settle(tr.angle_deg[0], n, h, s)) {
            return true;
        }
        tr.angle_deg
            .iter()
            .zip(&self.angles)
            .fold(true, |ok, (a, g)| ok & ((a - g).abs() < 1e-9))
    }

    /// The interpolant for this trace, and the spline `auto` built to test
    /// for overshoot (to be used, not built again, when it passes).
    fn choose(
        &mut self,
        tr: &Trace,
        on_grid: bool,
    ) -> Result<(InterpKind, Option<Periodic>), IngestError> {
        Ok(match self.opts.interp {
            Interp::Linear => (InterpKind::Linear, None),
            Interp::Spline => (InterpKind::Spline, None),
            Interp::Pchip => (InterpKind::Pchip, None),
            Interp::Auto if on_grid => (InterpKind::Linear, None),
            Interp::Auto => {
                let s = Periodic::new(
                    InterpKind::Spline,
                    &tr.angle_deg,
                    &tr.values,
                    self.cycle_deg,
                )
                .map_err(|e| IngestError::Data(e.to_string()))?;
                let peak = tr.values.iter().fold(0.0_f64, |a, &b| a.max(b.abs()));
                if s.max_overshoot() > 0.005 * peak {
                    self.overshoot.0 += 1;
                    self.overshoot.1 = self.overshoot.1.max(s.max_overshoot() / peak);
                    (InterpKind::Pchip, None)
                } else {
                    (InterpKind::Spline, Some(s))
                }
            }
        })
    }

    /// The averages and statistics.
    pub fn finish(
        self,
        rpm: Option<f64>,
        mut notes: Vec<String>,
    ) -> Result<Resampled, IngestError> {
        if self.count == 0 {
            return Err(IngestError::Data("no data rows".into()));
        }
        let m = self.count as f64;
        let pressure: Vec<f64> = self.sum.iter().map(|s| s / m).collect();
        if pressure.iter().any(|p| !p.is_finite()) {
            return Err(IngestError::Data(
                "the mean over the traces overflows: values too large for the declared unit".into(),
            ));
        }
        let mut cylinders = Vec::new();
        for (i, (s, c)) in self.per_cylinder.iter().enumerate() {
            if *c == 0 {
                return Err(IngestError::Data(format!(
                    "no trace for cylinder {} (cylinders must be numbered 1, 2, …)",
                    i + 1
                )));
            }
            cylinders.push(s.iter().map(|x| x / *c as f64).collect());
        }
        let cycles = if self.per_cylinder.is_empty() {
            self.count
        } else {
            self.count / self.per_cylinder.len().max(1)
        };
        let pegging = self.opts.peg.map(|method| PegReport {
            method,
            mean_offset: self.stats.iter().map(|s| s.peg_offset).sum::<f64>()
                / self.stats.len().max(1) as f64,
        });
        notes.extend(self.notes);
        let traces = self.count;
        let of = |n: usize| {
            if traces > 1 {
                format!(" ({n} of {traces} traces)")
            } else {
                String::new()
            }
        };
        if self.sparse.0 > 0 {
            notes.push(format!(
                "the diagram has a point every {}° on average{}: between points the pressure is the {} interpolant's guess (its error grows with the spacing squared for linear, to the fourth power for the spline); peak pressure and torque extremes are uncertain, `enginedyn accuracy` measures by how much",
                enginedyn_numerics::format::sig(self.sparse.1, 2),
                of(self.sparse.0),
                self.sparse.2.unwrap_or(InterpKind::Linear).name()
            ));
        }
        if self.overshoot.0 > 0 {
            notes.push(format!(
                "the periodic spline overshoots the data by {}{} % of the peak{}: pchip used instead",
                if self.overshoot.0 > 1 { "up to " } else { "" },
                enginedyn_numerics::format::sig(100.0 * self.overshoot.1, 3),
                of(self.overshoot.0)
            ));
        }
        Ok(Resampled {
            step_deg: self.opts.step_deg,
            quantity: self.quantity,
            pressure,
            cylinders,
            interp: self.interp.unwrap_or(InterpKind::Linear),
            interp_counts: [InterpKind::Linear, InterpKind::Spline, InterpKind::Pchip]
                .into_iter()
                .filter_map(|k| {
                    let n = self.interp_counts[k as usize];
                    (n > 0).then_some((k, n))
                })
                .collect(),
            cycles,
            stats: self.stats,
            pegging,
            rpm,
            pv: false,
            cycles_skipped: 0,
            skipped: Vec::new(),
            sample_step_deg: self.spacing,
            notes,
            combustion: self.opts.combustion.clone(),
            synthetic: false,
            most_knocking: self.most_knocking,
        })
    }
}

/// Mean and sample standard deviation (numerics' one home of them).
pub use enginedyn_numerics::mean_std;

/// The mean over ±5° around intake BDC (numerics' one home of it).
pub(crate) use enginedyn_numerics::intake_bdc_mean;

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The plain loops `accumulate` stands for.
    fn reference(src: &[f64], sum: &mut [f64], dv: &[f64]) -> Pass {
        for (s, x) in sum.iter_mut().zip(src) {
            *s += x;
        }
        let peak = src.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        let bad = |x: f64| !x.is_finite();
        Pass {
            sane: !src.iter().any(|&x| bad(x)),
            peak,
            at: src.iter().position(|&x| x >= peak).unwrap_or(0),
            p_dv: src.iter().zip(dv).map(|(x, d)| x * d).sum(),
        }
    }

    fn on_grid_both_ways(step: f64, angles: Vec<f64>) -> (bool, bool) {
        let n = angles.len();
        let acc = Accumulator::new(
            GridOptions::new(step, Interp::Linear),
            n as f64 * step,
            Quantity::Pressure,
        )
        .unwrap();
        let steps = enginedyn_numerics::scan::step_range(&angles);
        let tr = Trace {
            cycle: 0,
            cylinder: 0,
            values: vec![1e5; n],
            angle_deg: angles,
            rpm: None,
        };
        (acc.on_grid(&tr, Some(steps)), acc.on_grid(&tr, None))
    }

    /// Angles read from decimal text at 0.1° over 720° pass on their steps
    /// alone; one angle 2e-9° off fails either way.
    #[test]
    fn on_grid_from_steps() {
        let text: Vec<f64> = (0..7200)
            .map(|k| format!("{}.{}", k / 10, k % 10).parse().unwrap())
            .collect();
        let steps = enginedyn_numerics::scan::step_range(&text);
        assert!(steps_settle(text[0], 7200, 0.1, steps), "steps {steps:?}");
        assert_eq!(on_grid_both_ways(0.1, text.clone()), (true, true));
        let mut off = text;
        off[3000] += 2e-9;
        assert_eq!(on_grid_both_ways(0.1, off), (false, false));
    }

    proptest! {
        /// The test from the steps never says "on the grid" where comparing
        /// every angle says not: angles off the grid by up to 3e-9° at a
        /// few places, or drifting, at steps from 0.01° to 1°.
        #[test]
        fn on_grid_from_steps_is_never_wrong(
            step in prop_oneof![Just(0.01), Just(0.1), Just(0.25), Just(0.5), Just(1.0)],
            offs in prop::collection::vec((0..100_000usize, -3e-9..3e-9f64), 0..4),
            drift in prop_oneof![Just(0.0), -1e-13..1e-13f64],
        ) {
            let n = (720.0 / step) as usize;
            let mut angles: Vec<f64> = (0..n).map(|k| k as f64 * step + k as f64 * drift).collect();
            for (k, d) in offs {
                angles[k % n] += d;
            }
            let (fast, full) = on_grid_both_ways(step, angles);
            prop_assert!(!fast || full);
        }

        /// Any length (whole blocks or not), ties for the peak, negative
        /// samples, a NaN or an infinity: the sums match to the bit, the
        /// check, peak and its first index exactly, p dV to rounding.
        #[test]
        fn accumulate_is_the_plain_loops(
            mut src in prop::collection::vec(prop_oneof![4 => 0.0..1e7f64, 1 => Just(1e7)], 1..300),
            bad in prop::option::of((0..300usize, prop_oneof![
                Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY), -1.0..0.0f64,
            ])),
        ) {
            if let Some((k, x)) = bad {
                let k = k % src.len();
                src[k] = x;
            }
            let dv: Vec<f64> = (0..src.len()).map(|k| (k as f64 * 0.37).sin()).collect();
            let base: Vec<f64> = (0..src.len()).map(|k| k as f64).collect();
            let (mut a, mut b) = (base.clone(), base);
            let got = accumulate(&src, &mut a, &dv);
            let want = reference(&src, &mut b, &dv);
            prop_assert_eq!(got.sane, want.sane);
            let same = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits());
            prop_assert!(same(&a, &b));
            if want.sane {
                prop_assert_eq!(got.peak.to_bits(), want.peak.to_bits());
                prop_assert_eq!(got.at, want.at);
                let scale: f64 = src.iter().zip(&dv).map(|(x, d)| (x * d).abs()).sum();
                // Summation in another order: n eps of the sum of |terms|.
                let bound = src.len() as f64 * f64::EPSILON * scale;
                prop_assert!((got.p_dv - want.p_dv).abs() <= bound);
            }
        }
    }
}
