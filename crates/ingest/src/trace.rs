//! The trace builder: the one rule for which angle continues a cycle, and
//! the checks a finished cycle passes before it goes on the grid (coverage
//! and gaps, plausible values, samples below zero).

use crate::error::IngestError;
use crate::{Quantity, Trace};
use enginedyn_kinematics::Cylinder;

/// The angles of the cycle being built: where it started, where it is, and
/// whether its angles have wrapped past the cycle's end once (360 … 719.5,
/// 0 … 359.5 in a file whose cycles start at 360).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Track {
    first: f64,
    last: f64,
    /// 0, or the cycle once the angles wrapped.
    wrap: f64,
    cycle: f64,
    /// `cycle - EPS`: how far past the first angle an angle may lie.
    limit: f64,
}

/// The tolerance (deg) of angle comparisons against a cycle's length.
const EPS: f64 = 1e-9;

impl Track {
    /// A cycle starting at `a` (deg).
    pub(crate) fn new(a: f64, cycle: f64) -> Self {
        Self {
            first: a,
            last: a,
            wrap: 0.0,
            cycle,
            limit: cycle - EPS,
        }
    }

    /// The acceptance rule: `a`, moved by the wrap, when it continues the
    /// cycle (rises, and stays less than a cycle after the first angle).
    /// Every path asks this; the fast paths stop at `None` and leave the
    /// row to [`Self::accept`].
    #[inline(always)]
    pub(crate) fn continues(&self, a: f64) -> Option<f64> {
        let w = a + self.wrap;
        (w > self.last && w - self.first < self.limit).then_some(w)
    }

    /// [`Self::continues`] asked of each of `a` in turn, each taken
    /// ([`Self::take`]) before the next is asked: the last moved angle
    /// when all continue, else `None` (and nothing is taken). Without a
    /// branch an angle, for the fast paths' blocks of rows.
    #[inline(always)]
    pub(crate) fn continues_all<const B: usize>(&self, a: &[f64; B]) -> Option<f64> {
        // Each angle against the one before it, the first against the
        // last taken: in lanes, with no chain from one angle to the next.
        let w = a.map(|a| a + self.wrap);
        let mut before = [self.last; B];
        before[1..].copy_from_slice(&w[..B - 1]);
        let mut all = true;
        for k in 0..B {
            all &= (w[k] > before[k]) & (w[k] - self.first < self.limit);
        }
        all.then(|| w[B - 1])
    }

    /// What [`Self::continues`] adds to an angle: 0, or the cycle once the
    /// angles wrapped.
    #[inline(always)]
    pub(crate) fn shift(&self) -> f64 {
        self.wrap
    }

    /// Marks `w` (from [`Self::continues`]) as taken.
    #[inline(always)]
    pub(crate) fn take(&mut self, w: f64) {
        self.last = w;
    }

    /// [`Self::continues`], else the one wrap a cycle may make: an angle
    /// below the first that, a cycle on, still continues the cycle.
    pub(crate) fn accept(&mut self, a: f64) -> Option<f64> {
        if let Some(w) = self.continues(a) {
            self.last = w;
            return Some(w);
        }
        let w = a + self.cycle;
        if self.wrap == 0.0 && a < self.first && w > self.last && w - self.first < self.limit {
            self.wrap = self.cycle;
            self.last = w;
            return Some(w);
        }
        None
    }

    /// True when `a` is the cycle's first angle a cycle on: the closing
    /// point a digitised cycle often repeats.
    pub(crate) fn closes(&self, a: f64) -> bool {
        (a + self.wrap - self.first - self.cycle).abs() < EPS
    }

    /// True when `a` (not continuing) starts a new cycle: it runs a cycle
    /// past the first angle, or jumps back by more than half a cycle.
    pub(crate) fn starts_next(&self, a: f64) -> bool {
        let w = a + self.wrap;
        w - self.first >= self.limit || self.last - w > self.cycle / 2.0
    }

    /// True when `a` (not continuing) runs on past the cycle: it rises,
    /// a cycle or more after the first angle, and the angles never wrapped
    /// (a record whose angle runs on: 0 … 36,000°).
    pub(crate) fn runs_on(&self, a: f64) -> bool {
        self.wrap == 0.0 && a > self.last && a - self.first >= self.limit
    }

    /// True once the angles wrapped past the cycle's end.
    pub(crate) fn wrapped(&self) -> bool {
        self.wrap != 0.0
    }

    /// The last angle taken, as the file wrote it.
    pub(crate) fn last_raw(&self) -> f64 {
        self.last - self.wrap
    }

    /// The last angle taken, moved by the wrap.
    #[inline(always)]
    pub(crate) fn last(&self) -> f64 {
        self.last
    }

    /// The first angle.
    pub(crate) fn first(&self) -> f64 {
        self.first
    }
}

/// The window rule (INTERFACE.md, "A cycle is the window around its firing
/// TDC"), the one place where a record longer than a cycle is cut, for the
/// long layout and every time record alike: cycle `c` holds the angles
/// (deg from the first firing TDC) from `c·cycle − cycle/2` up to
/// `c·cycle + cycle/2`, −360…+360° around its firing TDC on a four-stroke
/// (cut at the gas-exchange TDC), −180…+180° on a two-stroke (cut at BDC),
/// so that each cycle holds its own compression, combustion and expansion.
/// Returns the window holding angle `a` and where it begins (deg). A
/// cycle's samples keep their angles from its own firing TDC
/// (`a − c·cycle`, in `[−cycle/2, cycle/2)`); [`finish`] moves them into
/// `[0, cycle)`, so the grid is the periodic one from firing TDC.
pub(crate) fn window(a: f64, cycle: f64) -> (i64, f64) {
    let half = cycle / 2.0;
    // A sample on a window's edge (within rounding) begins that window.
    let c = ((a + half) / cycle + 1e-12).floor() as i64;
    (c, c as f64 * cycle - half)
}

/// How a note names the window rule for a cycle of `cycle` degrees: where
/// cycles are cut (`at`, said after it when given) and the window around
/// firing TDC.
pub(crate) fn window_said(cycle: f64, at: &str) -> String {
    let half = enginedyn_numerics::format::trimmed(cycle / 2.0, 3);
    format!(
        "cut at each {}{at}, each cycle the window −{half}…+{half}° around its firing TDC",
        if cycle > 400.0 {
            "gas-exchange TDC"
        } else {
            "BDC"
        }
    )
}

/// The widest gap of a trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Gap {
    /// Where it starts (deg, cycle angle).
    pub from: f64,
    /// Its width (deg).
    pub width: f64,
    /// The cycle's median step (deg).
    pub median: f64,
    /// The sample before it, counted in the order the file gives them
    /// (its line is the trace's first line plus this, one sample a row).
    pub at: usize,
}

/// What the checks of a finished trace found.
#[derive(Debug, Clone, Default)]
pub(crate) struct Checked {
    /// The smallest and largest step between its angles, when they did
    /// not have to move into the cycle.
    pub steps: Option<(f64, f64)>,
    /// Its widest gap, when it has one.
    pub gap: Option<Gap>,
    /// Samples below zero absolute pressure, and the lowest (Pa).
    pub below_zero: (usize, f64),
    /// Its glitches ([`crate::plausible::glitches`]), replaced by their
    /// cubic when `--despike` was given.
    pub glitches: Vec<crate::plausible::Glitch>,
    /// Its angles rise, none NaN (as [`finish`] hands them on).
    pub rising: bool,
}

/// A gap is a spacing of more than this many median steps (INTERFACE.md).
pub(crate) const GAP_STEPS: f64 = 5.0;

/// Checks a trace (its coverage and gaps here, its values by the one
/// plausibility pass, [`crate::plausible::check`]) and moves its angles
/// into `[0, cycle)`, rotating so they rise.
pub(crate) fn finish(
    mut tr: Trace,
    cycle: f64,
    quantity: Quantity,
    ctx: &crate::plausible::Context<'_>,
) -> Result<(Trace, Checked), IngestError> {
    let n = tr.angle_deg.len();
    // Built only for a message: no allocation per trace on the way through.
    let (cycle_no, cylinder_no) = (tr.cycle, tr.cylinder);
    let name = || describe(cycle_no, cylinder_no);
    if n < 4 {
        return Err(IngestError::Data(format!(
            "{} has {n} points: at least 4 are needed",
            name()
        )));
    }
    let first = tr.angle_deg[0];
    let last = tr.angle_deg[n - 1];
    let steps = enginedyn_numerics::scan::steps(&tr.angle_deg);
    let (lo, hi) = (steps.lo, steps.hi);
    let wrap_step = first + cycle - last;
    // The median step; evenly spaced data (the usual case) needs no sort.
    let median = if hi - lo <= 1e-9 * hi.abs() + 1e-12 {
        lo
    } else {
        let mut steps: Vec<f64> = tr.angle_deg.windows(2).map(|w| w[1] - w[0]).collect();
        steps.push(wrap_step);
        let k = steps.len() / 2;
        *steps.select_nth_unstable_by(k, f64::total_cmp).1
    };
    let limit = GAP_STEPS * median;
    let mut gap: Option<Gap> = None;
    let mut note_gap = |at: usize, from: f64, width: f64| {
        if width > limit && gap.is_none_or(|g| width > g.width) {
            gap = Some(Gap {
                from: from.rem_euclid(cycle),
                width,
                median,
                at,
            });
        }
    };
    note_gap(n - 1, last, wrap_step);
    if hi > limit {
        for (i, w) in tr.angle_deg.windows(2).enumerate() {
            note_gap(i, w[0], w[1] - w[0]);
        }
    }
    // The glitch rule, before the bounds: `--despike` puts each glitch's
    // cubic in its place, and the bounds judge what is left.
    let glitches = crate::plausible::glitches(&tr, &steps, cycle, quantity, ctx.absolute);
    if ctx.despike {
        for g in &glitches {
            tr.values[g.at] = g.cubic;
        }
    }
    // Coverage is judged before the values (INTERFACE.md): a trace that
    // covers less than half its cycle is left out or refused by the gap
    // rule as a file cut short, never judged on the shape of what is left.
    let below_zero =
        if ctx.coverage_first && gap.is_some_and(|g| g.width > crate::MAX_GAP_BOUND_DEG) {
            (0, 0.0)
        } else {
            crate::plausible::check(&tr, wrap_step, cycle, quantity, ctx, &name)?
        };
    let checked = |steps, rising| Checked {
        steps,
        gap,
        below_zero,
        glitches,
        rising,
    };
    // Already in [0, cycle) and rising (the usual case): nothing to move.
    if first >= 0.0 && last < cycle && lo > 0.0 {
        return Ok((tr, checked(Some((lo, hi)), steps.rising())));
    }
    // Wrapped and turned in place: no second copy of the angles.
    let fast = wrap_rising(&mut tr.angle_deg, cycle, &steps);
    let start = match fast {
        Some(start) => start,
        None => {
            for a in &mut tr.angle_deg {
                *a = wrap(*a, cycle);
            }
            let wrapped = &tr.angle_deg;
            (0..n)
                .min_by(|&i, &j| wrapped[i].total_cmp(&wrapped[j]))
                .unwrap_or(0)
        }
    };
    tr.angle_deg.rotate_left(start);
    tr.values.rotate_left(start);
    if !never_falls(&tr.angle_deg) {
        return Err(IngestError::Data(format!(
            "{}: two points fall on the same crank angle once wrapped into the cycle",
            name()
        )));
    }
    // Rising, and none NaN where they were rising numbers to begin with.
    Ok((tr, checked(None, fast.is_some())))
}

/// An angle moved into `[0, cycle)`: `rem_euclid`, and 0 where that
/// rounds up to the cycle.
fn wrap(a: f64, cycle: f64) -> f64 {
    let w = enginedyn_numerics::scan::rem_euclid(a, cycle);
    if w >= cycle { 0.0 } else { w }
}

/// No angle at or below the one before it (`w[1] <= w[0]` nowhere; a NaN
/// compares as neither), in one branch-free pass.
#[allow(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "NaN is no step down, as before"
)]
fn never_falls(a: &[f64]) -> bool {
    const L: usize = 4;
    if a.len() < 2 {
        return true;
    }
    let (x, y) = (&a[..a.len() - 1], &a[1..]);
    let (cx, cy) = (x.chunks_exact(L), y.chunks_exact(L));
    let tail = cx
        .remainder()
        .iter()
        .zip(cy.remainder())
        .all(|(u, v)| !(v <= u));
    let mut ok = [true; L];
    for (u, v) in cx.zip(cy) {
        for j in 0..L {
            ok[j] &= !(v[j] <= u[j]);
        }
    }
    tail && ok.iter().all(|&o| o)
}

/// [`wrap`] over angles that rise (`steps`: theirs, [`Steps::rising`]),
/// done as one subtraction a sample: each angle less `base`, the whole
/// cycles below the first, or `base + cycle` from where that reaches the
/// cycle. Returns where the wrapped angles' first smallest lies (where
/// they are to be turned to), or `None`, untouched, where the shortcut
/// does not hold (then [`wrap`] each).
///
/// Why it is `wrap` to the bit: a difference `w = a − M` (`M` a whole
/// number of cycles, exact) that lies strictly inside `(0, cycle)` is
/// `a.rem_euclid(cycle)`: the exact `a − M` then lies there too (rounding
/// is monotone and 0 and the cycle are numbers), so `M` is `⌊a/cycle⌋`
/// cycles, and `rem_euclid`'s exact remainder (plus a cycle when `a` is
/// below zero) rounds to `w`. A difference of 0 is exact (`a = M`):
/// `rem_euclid` gives +0 for a positive `a`, and `a` itself for ±0, as
/// `a − M` does for `M` = +0 (not for a negative `a`: −0). The samples
/// rise, so the differences of each stretch do too (monotone again): the
/// stretch's first and last decide for all of them.
///
/// [`Steps::rising`]: enginedyn_numerics::scan::Steps::rising
fn wrap_rising(
    a: &mut [f64],
    cycle: f64,
    steps: &enginedyn_numerics::scan::Steps,
) -> Option<usize> {
    let n = a.len();
    // Whole cycles below 2^53 (exact multiples), the angles below 1e15.
    let whole = cycle > 0.0 && cycle < 1e6 && cycle.fract() == 0.0;
    let small = n >= 2 && a[0].abs() < 1e15 && a[n - 1].abs() < 1e15;
    if !(small && whole && steps.rising()) {
        return None;
    }
    let base = (a[0] / cycle).floor() * cycle;
    let next = base + cycle;
    // The first angle the second stretch holds.
    let s = a.partition_point(|&x| x - base < cycle);
    // A stretch's first difference is above zero, or zero where
    // `rem_euclid` gives the same +0 or −0: `a` a positive whole number of
    // cycles, or ±0 less +0. Its last lies below the cycle.
    let first = |x: f64, m: f64| {
        let w = x - m;
        w > 0.0 || (w == 0.0 && (x > 0.0 || (x == 0.0 && m.to_bits() == 0)))
    };
    let ok = s > 0
        && first(a[0], base)
        && a[s - 1] - base < cycle
        && (s == n || (first(a[s], next) && a[n - 1] - next < cycle));
    if !ok {
        return None;
    }
    for x in &mut a[..s] {
        *x -= base;
    }
    for x in &mut a[s..] {
        *x -= next;
    }
    // Each stretch rises from its first: the first smallest is one of those.
    Some(if s < n && a[s] < a[0] { s } else { 0 })
}

/// The share of the cycle's work under which the data settle a gap wider
/// than `--max-gap` (INTERFACE.md, "Gaps"): 0.1 %.
pub(crate) const SETTLED_SHARE: f64 = 1e-3;

/// The widest gap the data may settle (deg): INTERFACE.md, "Gaps".
pub(crate) const SETTLED_MAX_DEG: f64 = 90.0;

/// Why the data cannot settle gap `g` whatever the interpolants say
/// (INTERFACE.md, "Gaps"): wider than [`SETTLED_MAX_DEG`], or over a TDC
/// (firing, or the gas exchange's on a four-stroke), where the pressure
/// turns and two interpolants that agree can both miss it. `None` when it
/// may be settled.
pub(crate) fn unsettled(g: Gap, cycle: f64) -> Option<String> {
    if g.width > SETTLED_MAX_DEG + 1e-9 {
        return Some(format!(
            "is wider than {}°",
            enginedyn_numerics::format::human(SETTLED_MAX_DEG)
        ));
    }
    let tdcs: &[(f64, &str)] = if cycle > 400.0 {
        &[(0.0, "firing"), (360.0, "gas-exchange")]
    } else {
        &[(0.0, "firing")]
    };
    // A TDC strictly inside the gap (from `from` to `from + width`, any turn).
    for &(t, which) in tdcs {
        let d = (t - g.from).rem_euclid(cycle);
        if d > 1e-9 && d < g.width - 1e-9 {
            return Some(format!(
                "holds a TDC (the {which} TDC at {}°)",
                enginedyn_numerics::format::human(t)
            ));
        }
    }
    None
}

/// How far the data settle a single cycle's widest gap (INTERFACE.md,
/// "Gaps"): the linear and the periodic cubic spline interpolants
/// integrated over it, `∫ p dV` (composite Simpson on 0.05° or finer, `dV`
/// from the volume law), their difference as a share of the cycle's
/// `|W| = |∮ p dV|` (the spline's, Simpson on a 0.1° grid). Two
/// interpolants that agree over a gap leave nothing there for the data to
/// decide: typically a sparse stretch of the gas exchange, where the
/// pressure is nearly flat and `dV` small against the cycle's work. `tr`:
/// angles in `[0, cycle)`, rising. `None` when the interpolants cannot be
/// built or the cycle does no work.
pub(crate) fn gap_work_share(tr: &Trace, cyl: &Cylinder, cycle: f64) -> Option<f64> {
    use enginedyn_numerics::integrate::{Rule, cumulative, periodic_integral};
    use enginedyn_numerics::{InterpKind, Periodic};
    let a = &tr.angle_deg;
    let n = a.len();
    let lin = Periodic::new(InterpKind::Linear, a, &tr.values, cycle).ok()?;
    let cubic = Periodic::new(InterpKind::Spline, a, &tr.values, cycle).ok()?;
    // The widest spacing, the wrap from the last angle to the first included.
    let (mut from, mut width) = (a[n - 1], a[0] + cycle - a[n - 1]);
    for w in a.windows(2) {
        if w[1] - w[0] > width {
            (from, width) = (w[0], w[1] - w[0]);
        }
    }
    let rad = 1f64.to_radians();
    // Over the gap: (cubic - linear) dV/dφ, φ in radians.
    let panels = 2 * ((width / 0.1).ceil() as usize).max(32);
    let h = width / panels as f64;
    let f: Vec<f64> = (0..=panels)
        .map(|k| {
            let x = from + h * k as f64;
            (cubic.eval(x) - lin.eval(x)) * cyl.dvolume(x * rad)
        })
        .collect();
    let mut run = vec![0.0; f.len()];
    cumulative(Rule::Simpson, &f, h * rad, &mut run);
    let diff = run[panels];
    // The cycle's work.
    let step = 0.1;
    let m = (cycle / step).round() as usize;
    let (_, dv) = cyl.fill_volume(step * rad, m);
    let mut p = vec![0.0; m];
    cubic.eval_uniform(0.0, step, &mut p);
    for (x, d) in p.iter_mut().zip(&dv) {
        *x *= d;
    }
    let work = periodic_integral(Rule::Simpson, &p, step * rad);
    (work.abs() > 0.0 && diff.is_finite()).then(|| (diff / work).abs())
}

/// "cycle 3", "cycle 3 of cylinder 2", as messages name a trace.
pub(crate) fn describe(cycle: i64, cylinder: i64) -> String {
    if cylinder > 0 {
        format!("cycle {cycle} of cylinder {cylinder}")
    } else {
        format!("cycle {cycle}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps_once_and_closes() {
        let mut t = Track::new(360.0, 720.0);
        assert_eq!(t.accept(719.5), Some(719.5));
        assert_eq!(t.accept(0.0), Some(720.0));
        assert_eq!(t.accept(359.5), Some(1079.5));
        // A second wrap is no continuation, the first angle again closes.
        assert_eq!(t.accept(0.0), None);
        assert!(t.closes(360.0));
        assert!(t.starts_next(360.0));
        // Falling by a little is neither.
        let mut u = Track::new(0.0, 720.0);
        u.accept(10.0);
        assert_eq!(u.accept(9.0), None);
        assert!(!u.starts_next(9.0));
    }

    fn ctx(absolute: bool) -> crate::plausible::Context<'static> {
        crate::plausible::Context {
            column: "column 2 `p` (in Pa)",
            gain: None,
            absolute,
            gauge: false,
            compression_ratio: None,
            despike: false,
            coverage_first: true,
        }
    }

    fn trace(angles: &[f64], p: f64) -> Trace {
        Trace {
            cycle: 1,
            cylinder: 0,
            angle_deg: angles.to_vec(),
            values: vec![p; angles.len()],
            rpm: None,
        }
    }

    #[test]
    fn gaps_are_found_anywhere() {
        let mut a: Vec<f64> = (0..720).map(f64::from).collect();
        let (_, c) = finish(trace(&a, 1e6), 720.0, Quantity::Pressure, &ctx(true)).unwrap();
        assert!(c.gap.is_none());
        a.retain(|x| !(100.0..130.0).contains(x));
        let (_, c) = finish(trace(&a, 1e6), 720.0, Quantity::Pressure, &ctx(true)).unwrap();
        let g = c.gap.unwrap();
        assert_eq!((g.from, g.width, g.median, g.at), (99.0, 31.0, 1.0, 99));
        // At the wrap: 170° of 720°.
        let short: Vec<f64> = (0..=170).map(f64::from).collect();
        let (_, c) = finish(trace(&short, 1e6), 720.0, Quantity::Pressure, &ctx(true)).unwrap();
        assert_eq!(c.gap.map(|g| g.width), Some(550.0));
    }

    /// The gap rule's figure: nearly nothing over a flat stretch of the
    /// exhaust stroke, much over the peak; unchanged by a constant added
    /// (both interpolants keep it, and `∮ dV = 0`) or by a scale.
    #[test]
    fn the_data_settle_a_gap_in_the_gas_exchange_only() {
        use enginedyn_kinematics::{CrankSlider, Mechanism};
        let crank = CrankSlider::new(0.027, 0.084, 0.0).unwrap();
        let cyl = Cylinder::new(Mechanism::CrankSlider(crank), 0.068, 8.5).unwrap();
        let p = |a: f64| {
            let c = if a > 360.0 { a - 720.0 } else { a };
            1e5 + 40e5 * (-((c - 10.0) / 30.0).powi(2)).exp() + 0.2e5 * (a.to_radians()).sin()
        };
        let with_gap = |from: f64| {
            let a: Vec<f64> = (0..288)
                .map(|k| f64::from(k) * 2.5)
                .filter(|&x| !(x > from && x < from + 33.5))
                .chain([from + 33.5])
                .collect();
            let mut a = a;
            a.sort_by(f64::total_cmp);
            a.dedup();
            Trace {
                cycle: 1,
                cylinder: 0,
                values: a.iter().map(|&x| p(x)).collect(),
                angle_deg: a,
                rpm: None,
            }
        };
        let exhaust = gap_work_share(&with_gap(250.0), &cyl, 720.0).unwrap();
        assert!(exhaust < 0.5 * SETTLED_SHARE, "{exhaust}");
        let peak = gap_work_share(&with_gap(5.0), &cyl, 720.0).unwrap();
        assert!(peak > 10.0 * SETTLED_SHARE, "{peak}");
        let mut moved = with_gap(5.0);
        moved.values.iter_mut().for_each(|v| *v = 3.0 * *v + 2e5);
        let again = gap_work_share(&moved, &cyl, 720.0).unwrap();
        assert!((again - peak).abs() < 1e-9 * peak, "{again} {peak}");
    }

    /// The wrap as it reads: each angle by `rem_euclid` (0 where that
    /// rounds up to the cycle), turned to the first smallest, refused when
    /// two then meet or fall.
    fn plain_wrap(a: &[f64], v: &[f64], cycle: f64) -> Option<(Vec<f64>, Vec<f64>)> {
        let mut a: Vec<f64> = a.iter().map(|&x| wrap(x, cycle)).collect();
        let start = (0..a.len())
            .min_by(|&i, &j| a[i].total_cmp(&a[j]))
            .unwrap_or(0);
        let mut v = v.to_vec();
        a.rotate_left(start);
        v.rotate_left(start);
        (!a.windows(2).any(|w| w[1] <= w[0])).then_some((a, v))
    }

    /// `finish` wraps and turns a trace as the plain wrap does, bit for bit
    /// (−0 included), and refuses the same ones: angles running on, from
    /// below zero, from a negative whole cycle, a hair below zero and a
    /// hair more than that, over a cycle's edge exactly, past a cycle, at
    /// 1e15, with a NaN, an infinity, a cycle that is no whole number.
    #[test]
    fn the_wrap_is_the_plain_one() {
        let run = |start: f64, step: f64, n: usize| -> Vec<f64> {
            (0..n).map(|k| start + step * k as f64).collect()
        };
        let mut sets: Vec<(Vec<f64>, f64)> = vec![
            (run(36_000.05, 0.1, 7200), 720.0),
            (run(36_000.0, 0.1, 7200), 720.0),
            (run(-360.0, 0.5, 1440), 720.0),
            (run(-720.0, 1.0, 720), 720.0),
            (run(-1440.0, 1.0, 700), 720.0),
            (run(-180.25, 0.5, 720), 360.0),
            (run(700.0, 1.0, 41), 720.0),
            (run(700.5, 1.0, 41), 720.0),
            (run(0.3, 0.5, 1600), 720.0),
            (run(1e15 - 100.0, 0.5, 100), 720.0),
            (run(-1e15, 0.5, 100), 720.0),
            (run(0.1, 0.1, 100), 720.5),
            (run(-33.3, 0.1, 7000), 720.0),
            ([vec![-0.0], run(0.5, 0.5, 1600)].concat(), 720.0),
            ([vec![-720.0, -0.0], run(0.5, 0.5, 1400)].concat(), 720.0),
            (run(35_640.0, 0.1, 7200), 720.0),
            (run(-360.0, 0.1, 7200), 720.0),
        ];
        for hair in [1e-20, 1e-13, 1e-12, 5e-14] {
            let mut a = run(0.5, 0.5, 1400);
            a.insert(0, -hair);
            sets.push((a, 720.0));
        }
        let mut nan = run(-100.0, 1.0, 600);
        nan[300] = f64::NAN;
        sets.push((nan, 720.0));
        let mut inf = run(-100.0, 1.0, 600);
        inf[599] = f64::INFINITY;
        sets.push((inf, 720.0));
        let mut fast = 0;
        for (a, cycle) in sets {
            let v: Vec<f64> = (0..a.len()).map(|k| 2e5 + k as f64).collect();
            let tr = Trace {
                cycle: 1,
                cylinder: 0,
                angle_deg: a.clone(),
                values: v.clone(),
                rpm: None,
            };
            let got = finish(tr, cycle, Quantity::Pressure, &ctx(true));
            let want = plain_wrap(&a, &v, cycle);
            match (got, want) {
                (Ok((t, c)), Some((wa, wv))) => {
                    let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&t.angle_deg), bits(&wa), "{}", a[0]);
                    assert_eq!(bits(&t.values), bits(&wv), "{}", a[0]);
                    fast += usize::from(c.rising);
                }
                (Err(e), None) => assert!(e.to_string().contains("same crank angle"), "{e}"),
                (got, want) => panic!(
                    "{}: {:?} vs {:?}",
                    a[0],
                    got.map(|x| x.1.gap),
                    want.is_some()
                ),
            }
        }
        // Handed on as rising: the 12 sets the shortcut takes (a negative
        // whole cycle, a hair under zero that rounds to a cycle, −0 from
        // −0, 1e15, NaN and infinity are not among them) and the one
        // already in the cycle.
        assert_eq!(fast, 13);
    }

    /// The branch-free "never falls" is the plain test, NaN and ties
    /// included, at lengths around its lanes.
    #[test]
    fn never_falls_is_the_plain_test() {
        for n in 0..20 {
            for k in 0..n.max(1) {
                for x in [f64::NAN, 0.0, -1.0, 3.0, f64::INFINITY] {
                    let mut a: Vec<f64> = (0..n).map(|i| i as f64).collect();
                    if k < n {
                        a[k] = x;
                    }
                    let plain = !a.windows(2).any(|w| w[1] <= w[0]);
                    assert_eq!(never_falls(&a), plain, "{a:?}");
                }
            }
        }
    }

    #[test]
    fn below_zero_over_half_the_cycle_is_refused() {
        let a: Vec<f64> = (0..720).map(f64::from).collect();
        let mut t = trace(&a, 2e5);
        t.values[0] = 50e5;
        for v in &mut t.values[100..300] {
            *v = -0.5e5;
        }
        let (_, c) = finish(t.clone(), 720.0, Quantity::Pressure, &ctx(true)).unwrap();
        assert_eq!(c.below_zero, (200, -0.5e5));
        for v in &mut t.values[300..500] {
            *v = -0.5e5;
        }
        let e = finish(t.clone(), 720.0, Quantity::Pressure, &ctx(true)).unwrap_err();
        assert!(e.to_string().contains("--gauge"), "{e}");
        // A relative trace is not checked for sign.
        assert!(finish(t, 720.0, Quantity::Pressure, &ctx(false)).is_ok());
    }
}
