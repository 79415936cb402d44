//! The one plausibility pass over finished traces (INTERFACE.md,
//! "Plausibility, so a wrong column is never averaged in" and "Hostile
//! input"): whether a trace can be what its column claims, a cylinder
//! pressure or a torque, before it reaches any average. Every layout's
//! traces pass here once, from [`crate::trace::finish`]; no layout checks
//! values of its own.
//!
//! - Absolute pressure: the peak lies from 0.05 bar to 1000 bar (below is a
//!   unit mix-up, above a unit or `--gain` mix-up: no engine's cylinder
//!   reaches 1000 bar); a trace below zero over more than half its cycle is
//!   gauge data; samples below zero elsewhere are counted for one note.
//! - Relative pressure (to be pegged): it swings by at least 0.05 bar and
//!   by at most 1000 bar, whatever the offset pegging adds.
//! - Compression (when the engine, and so its compression ratio ε, is
//!   known): the peak reaches at least half the pressure compression alone
//!   gives, `p_in ε_c^1.3` ([`compression_pressure`]). A wrong column (an
//!   injection or ignition signal, a needle lift, volts without `--gain`)
//!   fails here and the error says what the column looks like
//!   ([`looks_like`]).
//! - Torque: at most 1e9 N m in magnitude.
//!
//! # The compression bound, and why it reads so
//!
//! INTERFACE.md: the bound is half of "the trace's own pressure at intake
//! BDC × ε^1.3". Taken literally, a signal that sits at 0 (an injection
//! signal's 0 V) has a bound of 0 and passes. So `p_in`, the pressure the
//! charge is compressed from, is the trace's own only where it can be an
//! intake's:
//!
//! - Its level at intake BDC ([`intake_levels`]: the mean over ±5°). Which
//!   angle is intake BDC is decided after this pass ([`crate::axis`]: the
//!   360° rule, a cylinder's trace on cylinder 1's axis), so each
//!   candidate is tried (540°, 180°, 180° before the peak) and the trace
//!   passes from any.
//! - A level of at least [`LOW_INTAKE_PA`] (0.2 bar absolute, below any
//!   running engine's intake; a throttled petrol engine's is about 0.3) is
//!   the intake's: `p_in` is that level. A motored trace's peak *is* its
//!   compression pressure, about `p_in ε^1.3` less the heat lost, so it
//!   passes at half of it; so does a throttled engine at 0.3 bar.
//! - A lower level is no intake's: the trace is either gauge data read as
//!   absolute (its intake near the atmosphere: `p_in` is the level plus
//!   1.01325 bar, and its peak is measured on the same footing) or no
//!   pressure at all. A gauge trace still rises by its compression
//!   pressure and passes (with the gauge warning); a flat signal with a
//!   pulse does not.
//! - A relative trace (to be pegged) has no level of its own: its swing
//!   must reach what compression adds to the lowest intake,
//!   `LOW_INTAKE_PA (½ ε_c^1.3 − 1)`.
//! - `ε_c`: a four-stroke compresses from near BDC, `ε_c = ε`; a
//!   two-stroke from its ports' closing, at the latest halfway up the
//!   stroke, `ε_c = 1 + (ε − 1)/2` (the ratio it is left with).

use crate::columns::ATM;
use crate::error::IngestError;
use crate::{Quantity, Trace};
use enginedyn_numerics::scan::Steps;

/// The highest absolute pressure a cylinder reaches (Pa): 1000 bar, above
/// the largest diesel's 250–300 bar peak by a margin no measured trace
/// comes near, and below what any unit or gain mix-up gives.
pub(crate) const MAX_PEAK_PA: f64 = 1e8;

/// The lowest peak (Pa), and the least swing of a relative trace: 0.05 bar.
pub(crate) const MIN_PEAK_PA: f64 = 5e3;

/// The largest engines make about 1e7 N m: beyond 1e9 is a unit mix-up.
pub(crate) const MAX_TORQUE_NM: f64 = 1e9;

/// The lowest mean absolute pressure around intake BDC (Pa) a running
/// engine's intake holds (a throttled petrol engine's is about 0.3 bar):
/// below it a trace is gauge data or no pressure. The gauge warning's
/// threshold too.
pub(crate) const LOW_INTAKE_PA: f64 = 0.2e5;

/// The highest mean absolute pressure around intake BDC (Pa) an engine's
/// intake holds: 6 bar, above the most a turbocharger gives (4 to 5 bar
/// absolute on the largest diesels). Above it the values are in another
/// unit: a pressure in psi reads 14.5 at the atmosphere.
pub(crate) const HIGH_INTAKE_PA: f64 = 6e5;

/// Bar per psi.
const BAR_PER_PSI: f64 = 0.068_947_572_931_683_6;

/// A trace in MPa read as bar has its intake at a tenth of a running
/// engine's (0.02 to 0.2 "bar") and its peak at a tenth of an engine's
/// (below 25 "bar"): what the low-intake warning adds then, naming MPa.
pub(crate) fn mpa_hint(level: f64, peak: f64) -> String {
    if level >= 0.1 * LOW_INTAKE_PA && peak <= 25e5 {
        format!(
            "; or a pressure in MPa read as bar ({} MPa is {} bar): convert it, or name the column's unit (`pressure [MPa]`)",
            enginedyn_numerics::format::sig(level / 1e5, 3),
            enginedyn_numerics::format::sig(level / 1e4, 3)
        )
    } else {
        String::new()
    }
}

/// The polytropic exponent of the compression bound (INTERFACE.md).
const POLYTROPE: f64 = 1.3;

/// The share of the compression pressure a cylinder's peak reaches at
/// least (INTERFACE.md: half), leaving room for heat loss, blow-by and a
/// late inlet closing.
const COMPRESSION_SHARE: f64 = 0.5;

/// What a message needs to name the trace's source.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Context<'a> {
    /// The column as messages name it ("column 2 `P [bar]` (in bar)").
    pub column: &'a str,
    /// `--gain` (bar per volt), when given.
    pub gain: Option<f64>,
    /// Pressures must be absolute (not to be pegged): checked for sign.
    pub absolute: bool,
    /// `--gauge` was given (how to word a trace below vacuum).
    pub gauge: bool,
    /// The engine's compression ratio, when the engine is known: the
    /// compression bound is checked only then.
    pub compression_ratio: Option<f64>,
    /// `--despike`: each glitch is replaced by the cubic through its
    /// neighbours ([`glitches`]).
    pub despike: bool,
    /// A trace covering less than half its cycle is judged on its
    /// coverage, not its values (`false` while probing a headerless file,
    /// whose columns are judged on their values whatever they cover).
    pub coverage_first: bool,
}

impl Context<'_> {
    /// What the values were read as: the column, and `--gain` if given.
    fn source(&self) -> String {
        match self.gain {
            Some(g) => format!(
                "{} times --gain {} bar/V",
                self.column,
                enginedyn_numerics::format::human(g)
            ),
            None => self.column.to_string(),
        }
    }

    /// What to check first when a value is out of range.
    fn suspect(&self) -> &'static str {
        if self.gain.is_some() {
            "is --gain (bar per volt) right?"
        } else {
            "is the column's unit right?"
        }
    }
}

/// A glitch departs from the cubic through its neighbours by more than
/// this (Pa): 10 bar (INTERFACE.md, "Plausibility").
pub(crate) const GLITCH_PA: f64 = 10e5;

/// … and by more than this share of the cycle's peak: 20 %.
pub(crate) const GLITCH_SHARE: f64 = 0.2;

/// A lone sample that departs from the cubic through its neighbours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Glitch {
    /// Its index in the trace, in the order the file gives the samples
    /// (its line is the trace's first line plus this, one sample a row).
    pub at: usize,
    /// Its value (Pa).
    pub value: f64,
    /// The cubic through its neighbours at its angle (Pa): what
    /// `--despike` puts in its place.
    pub cubic: f64,
}

/// The glitch rule (INTERFACE.md, "Plausibility"): a lone sample of a
/// pressure trace that departs from the cubic through its neighbours (two
/// each side, the trace taken as periodic over its `cycle`) by more than
/// [`GLITCH_PA`] and by more than [`GLITCH_SHARE`] of the cycle's peak
/// (the highest of the other samples; a relative trace's swing) is a
/// glitch. "Lone": its departure is the largest of the five samples around
/// it (a spike also pulls its neighbours' cubics, by 2/3 and 1/6 of its
/// height on even steps). Returns the glitches, in file order; none for a
/// torque, p–V data or fewer than 8 samples. Angles rising, spanning less
/// than a cycle.
/// `steps`: the angles' ([`enginedyn_numerics::scan::steps`]).
pub(crate) fn glitches(
    tr: &Trace,
    steps: &Steps,
    cycle: f64,
    quantity: Quantity,
    absolute: bool,
) -> Vec<Glitch> {
    let (a, p) = (&tr.angle_deg, &tr.values);
    let n = p.len();
    if quantity != Quantity::Pressure || n < 8 {
        return Vec::new();
    }
    // Sample i + k, any k in −2..=2, periodic: its angle and value.
    let at = |i: usize, k: isize| -> (f64, f64) {
        let j = i as isize + k;
        let (j, turn) = if j < 0 {
            (j + n as isize, -cycle)
        } else if j >= n as isize {
            (j - n as isize, cycle)
        } else {
            (j, 0.0)
        };
        (a[j as usize] + turn, p[j as usize])
    };
    // The cubic through i−2, i−1, i+1, i+2 at sample i's angle (Lagrange).
    let cubic = |i: usize| -> f64 {
        let x = a[i];
        let pts = [at(i, -2), at(i, -1), at(i, 1), at(i, 2)];
        // Evenly spaced samples (the usual case): the weights are fixed,
        // (−1, 4, 4, −1)/6, no divisions.
        let h = x - pts[1].0;
        let even = [pts[1].0 - pts[0].0, pts[2].0 - x, pts[3].0 - pts[2].0]
            .iter()
            .all(|d| (d - h).abs() <= 1e-9 * h.abs());
        if even {
            return even_cubic(pts[0].1, pts[1].1, pts[2].1, pts[3].1);
        }
        let mut sum = 0.0;
        for (m, &(xm, ym)) in pts.iter().enumerate() {
            let mut w = 1.0;
            for (l, &(xl, _)) in pts.iter().enumerate() {
                if l != m {
                    w *= (x - xl) / (xm - xl);
                }
            }
            sum += w * ym;
        }
        sum
    };
    let off = |i: usize| (p[i] - cubic(i)).abs();
    // Evenly spaced samples: the interior with the fixed weights (the same
    // number `cubic` gives there), the ends by `off`.
    let candidates: Vec<usize> = if evenly_spaced(a, steps) {
        let mut c: Vec<usize> = [0, 1]
            .into_iter()
            .filter(|&i| p[i].is_finite() && off(i) > GLITCH_PA)
            .collect();
        interior_candidates(p, &mut c);
        c.extend(
            [n - 2, n - 1]
                .into_iter()
                .filter(|&i| p[i].is_finite() && off(i) > GLITCH_PA),
        );
        c
    } else {
        (0..n)
            .filter(|&i| p[i].is_finite() && off(i) > GLITCH_PA)
            .collect()
    };
    if candidates.is_empty() {
        return Vec::new();
    }
    // The two highest and the lowest values: the peak of the others.
    let (mut top, mut second, mut low) = ((f64::NEG_INFINITY, n), f64::NEG_INFINITY, f64::INFINITY);
    for (i, &v) in p.iter().enumerate() {
        if v > top.0 {
            second = top.0;
            top = (v, i);
        } else if v > second {
            second = v;
        }
        low = low.min(v);
    }
    let mut found = Vec::new();
    for i in candidates {
        let peak = if top.1 == i { second } else { top.0 };
        let scale = if absolute { peak } else { peak - low };
        let d = off(i);
        let lone = [-2isize, -1, 1, 2].iter().all(|&k| {
            let j = (i as isize + k).rem_euclid(n as isize) as usize;
            off(j) < d
        });
        if lone && d > GLITCH_SHARE * scale {
            found.push(Glitch {
                at: i,
                value: p[i],
                cubic: cubic(i),
            });
        }
    }
    found
}

/// The glitch rule's test of even spacing: every step within `1e-9` of
/// the mean step `(a[n-1] - a[0]) / (n - 1)`, from the steps' range
/// ([`Steps::all_within`]). At least two angles.
fn evenly_spaced(a: &[f64], steps: &Steps) -> bool {
    let n = a.len();
    let h = (a[n - 1] - a[0]) / (n - 1) as f64;
    steps.all_within(h, 1e-9 * h.abs())
}

/// The fixed weights' cubic through `w[0], w[1], w[3], w[4]` at `w[2]`'s
/// angle, evenly spaced: `(−1, 4, 4, −1)/6`.
#[inline(always)]
fn even_cubic(w0: f64, w1: f64, w3: f64, w4: f64) -> f64 {
    (4.0 * (w1 + w3) - (w0 + w4)) / 6.0
}

/// Samples the glitch scan judges at once: a block with no sample off its
/// cubic by more than [`GLITCH_PA`] holds no candidate.
const GLITCH_BLOCK: usize = 64;

/// Lanes of the glitch scan's block maximum.
const GLITCH_LANES: usize = 4;

/// Appends the interior candidates of the even glitch rule (samples 2 to
/// `n − 3`, in order): finite samples off the fixed weights' cubic by more
/// than [`GLITCH_PA`]. Each block of [`GLITCH_BLOCK`] samples is first
/// judged whole, branch-free: the largest departure (NaN skipped) against
/// the threshold. Only a block that exceeds it (a candidate, or an
/// infinite sample) is looked at sample by sample.
fn interior_candidates(p: &[f64], out: &mut Vec<usize>) {
    let n = p.len();
    if n < 5 {
        return;
    }
    let inner = n - 4;
    let mut from = 0;
    while from < inner {
        let len = GLITCH_BLOCK.min(inner - from);
        // Samples `from + 2 .. from + 2 + len`, with two neighbours each side.
        let q = &p[from..from + len + 4];
        if block_departs(q, len) {
            for (j, w) in q.windows(5).enumerate() {
                let fit = even_cubic(w[0], w[1], w[3], w[4]);
                if w[2].is_finite() && (w[2] - fit).abs() > GLITCH_PA {
                    out.push(from + j + 2);
                }
            }
        }
        from += len;
    }
}

/// Whether some sample `q[2 .. len + 2]` departs from its even cubic by
/// more than [`GLITCH_PA`] (a NaN departure does not; an infinite one
/// does). `q` holds `len + 4` samples.
#[inline(always)]
fn block_departs(q: &[f64], len: usize) -> bool {
    let (w0, w1, w2, w3, w4) = (
        &q[..len],
        &q[1..len + 1],
        &q[2..len + 2],
        &q[3..len + 3],
        &q[4..len + 4],
    );
    const L: usize = GLITCH_LANES;
    let mut top = [0.0f64; L];
    let lanes = w0
        .chunks_exact(L)
        .zip(w1.chunks_exact(L))
        .zip(w2.chunks_exact(L))
        .zip(w3.chunks_exact(L))
        .zip(w4.chunks_exact(L));
    for ((((a, b), c), d), e) in lanes {
        for j in 0..L {
            let off = (c[j] - even_cubic(a[j], b[j], d[j], e[j])).abs();
            top[j] = if off > top[j] { off } else { top[j] };
        }
    }
    for i in len - len % L..len {
        let off = (w2[i] - even_cubic(w0[i], w1[i], w3[i], w4[i])).abs();
        top[0] = if off > top[0] { off } else { top[0] };
    }
    top.iter().any(|&d| d > GLITCH_PA)
}

/// Checks a finished trace (angles rising, `wrap_step` from its last angle
/// to its first a cycle on) and returns its samples below zero absolute
/// pressure and the lowest of them (Pa). `name` names the trace.
pub(crate) fn check(
    tr: &Trace,
    wrap_step: f64,
    cycle: f64,
    quantity: Quantity,
    ctx: &Context<'_>,
    name: &dyn Fn() -> String,
) -> Result<(usize, f64), IngestError> {
    let bar = |pa: f64| enginedyn_numerics::format::sig(pa / 1e5, 4);
    let (vlo, vhi) = enginedyn_numerics::scan::min_max(&tr.values);
    if quantity != Quantity::Pressure {
        let peak = vlo.abs().max(vhi.abs()).max(0.0);
        if peak > MAX_TORQUE_NM {
            return Err(IngestError::Data(format!(
                "{}: torque {} N m in {} is implausible: is the torque column in N m?",
                name(),
                enginedyn_numerics::format::sig(peak, 4),
                ctx.column
            )));
        }
        return Ok((0, 0.0));
    }
    if !ctx.absolute {
        let swing = vhi - vlo;
        if swing < MIN_PEAK_PA {
            return Err(IngestError::Data(format!(
                "{}: the pressure from {} varies by {} bar only over the cycle: {}",
                name(),
                ctx.source(),
                enginedyn_numerics::format::sig(swing / 1e5, 3),
                ctx.suspect()
            )));
        }
        if swing > MAX_PEAK_PA {
            return Err(IngestError::Data(format!(
                "{}: the pressure from {} swings by {} bar over the cycle, so its peak lies above 1000 bar absolute whatever the pegging: not a cylinder pressure; {}",
                name(),
                ctx.source(),
                bar(swing),
                ctx.suspect()
            )));
        }
        if let Some(eps) = ctx.compression_ratio {
            // The lowest candidate level: the largest rise (a level that
            // rises enough leaves the lowest rising more).
            let need = LOW_INTAKE_PA * (compression_pressure(eps, cycle, 1.0) - 1.0);
            if let Some(level) = lowest_level(tr, cycle, |l| vhi - l >= need)
                && vhi - level < need
            {
                return Err(IngestError::Data(
                    format!(
                        "{}: {} is not a cylinder pressure: it rises by {} bar from its level at BDC, less than the {} bar that compression at ε = {} adds even to the lowest intake pressure ({} bar absolute); it looks like {}",
                        name(),
                        ctx.source(),
                        bar(vhi - level),
                        bar(need),
                        enginedyn_numerics::format::human(eps),
                        enginedyn_numerics::format::human(LOW_INTAKE_PA / 1e5),
                        looks_like(tr, level, vhi, cycle, ctx)
                    ) + NO_COMPRESSION,
                ));
            }
        }
        return Ok((0, 0.0));
    }
    let peak = vhi.max(0.0);
    if peak > MAX_PEAK_PA {
        return Err(IngestError::Data(format!(
            "{}: peak pressure {} bar absolute from {} is above the 1000 bar a cylinder reaches: not a cylinder pressure; {}",
            name(),
            bar(peak),
            ctx.source(),
            ctx.suspect()
        )));
    }
    if peak < MIN_PEAK_PA {
        return Err(IngestError::Data(format!(
            "{}: peak pressure {} bar from {} is implausible: {}",
            name(),
            bar(peak),
            ctx.source(),
            ctx.suspect()
        )));
    }
    if vlo >= 0.0 {
        compression(tr, vhi, cycle, ctx, name)?;
        return Ok((0, 0.0));
    }
    // The share of the cycle below zero: each sample stands for half the
    // steps either side of it.
    let n = tr.values.len();
    let (mut count, mut span) = (0usize, 0.0);
    for i in 0..n {
        if tr.values[i] < 0.0 {
            count += 1;
            let before = if i == 0 {
                wrap_step
            } else {
                tr.angle_deg[i] - tr.angle_deg[i - 1]
            };
            let after = if i + 1 == n {
                wrap_step
            } else {
                tr.angle_deg[i + 1] - tr.angle_deg[i]
            };
            span += 0.5 * (before + after);
        }
    }
    if span > 0.5 * cycle {
        return Err(IngestError::Data(if ctx.gauge {
            format!(
                "{} lies below vacuum (below −1.01325 bar gauge) over {:.0} % of its cycle: is the pressure column's unit right?",
                name(),
                100.0 * span / cycle
            )
        } else {
            format!(
                "{} is below zero absolute pressure over {:.0} % of its cycle (lowest {} bar): gauge data? give --gauge; a relative (piezo) trace: --peg-bar P or --peg polytropic",
                name(),
                100.0 * span / cycle,
                enginedyn_numerics::format::sig(vlo / 1e5, 3)
            )
        }));
    }
    compression(tr, vhi, cycle, ctx, name)?;
    Ok((count, vlo))
}

/// Half the pressure compression alone gives (Pa) from `p_in` (Pa) at
/// compression ratio `eps`: `½ p_in ε_c^1.3`, `ε_c` the ratio left after
/// the inlet (four-stroke, `cycle` 720°) or the ports (two-stroke) close
/// (the module's docs).
pub(crate) fn compression_pressure(eps: f64, cycle: f64, p_in: f64) -> f64 {
    let eps_c = if cycle > 400.0 {
        eps
    } else {
        1.0 + 0.5 * (eps - 1.0)
    };
    COMPRESSION_SHARE * p_in * eps_c.powf(POLYTROPE)
}

/// The compression bound of an absolute trace whose peak is `peak` (Pa).
fn compression(
    tr: &Trace,
    peak: f64,
    cycle: f64,
    ctx: &Context<'_>,
    name: &dyn Fn() -> String,
) -> Result<(), IngestError> {
    let Some(eps) = ctx.compression_ratio else {
        return Ok(());
    };
    high_intake(tr, cycle, ctx, name)?;
    // Each candidate for intake BDC: passed from any (the module's docs).
    let mut worst: Option<(f64, f64, f64, f64)> = None;
    for level in intake_levels(tr, cycle) {
        // A level no intake holds: read as gauge (the module's docs).
        let (p_in, shift) = if level >= LOW_INTAKE_PA {
            (level, 0.0)
        } else {
            ((level + ATM).max(LOW_INTAKE_PA), ATM)
        };
        let need = compression_pressure(eps, cycle, p_in);
        if peak + shift >= need {
            return Ok(());
        }
        // The error gives the candidate that came nearest.
        if worst.is_none_or(|w| need - peak - shift < w.1 - peak - w.3) {
            worst = Some((level, need, p_in, shift));
        }
    }
    let Some((level, need, p_in, shift)) = worst else {
        return Ok(());
    };
    let bar = |pa: f64| enginedyn_numerics::format::sig(pa / 1e5, 3);
    let from = if shift > 0.0 {
        format!(
            "{} bar at BDC (its own {} bar is below the {} bar absolute any running engine's intake holds, so it is read as gauge, its peak too: {} bar)",
            bar(p_in),
            bar(level),
            enginedyn_numerics::format::human(LOW_INTAKE_PA / 1e5),
            bar(peak + shift)
        )
    } else {
        format!("its own {} bar at BDC", bar(p_in))
    };
    // Read as gauge: the values may as well be MPa read as bar.
    let mpa = if shift > 0.0 && ctx.gain.is_none() {
        mpa_hint(level, peak)
    } else {
        String::new()
    };
    Err(IngestError::Data(
        format!(
            "{}: {} is not a cylinder pressure: its peak {} bar is below {} bar, half of what compression alone gives at ε = {} from {from}; it looks like {}{mpa}",
            name(),
            ctx.source(),
            bar(peak),
            bar(need),
            enginedyn_numerics::format::human(eps),
            looks_like(tr, level, peak, cycle, ctx)
        ) + NO_COMPRESSION,
    ))
}

/// The intake level's upper bound: every candidate level above
/// [`HIGH_INTAKE_PA`] is no intake's, and the error names the likely unit.
fn high_intake(
    tr: &Trace,
    cycle: f64,
    ctx: &Context<'_>,
    name: &dyn Fn() -> String,
) -> Result<(), IngestError> {
    // A level at or below the bound leaves the lowest there too.
    let Some(level) = lowest_level(tr, cycle, |l| l <= HIGH_INTAKE_PA) else {
        return Ok(());
    };
    if !(level.is_finite() && level > HIGH_INTAKE_PA) {
        return Ok(());
    }
    let bar = |pa: f64| enginedyn_numerics::format::sig(pa / 1e5, 3);
    let why = match ctx.gain {
        Some(_) => "is --gain (bar per volt) right?".to_string(),
        None => format!(
            "a pressure in psi read as bar ({} psi is {} bar)? convert it, or name the column's unit (`pressure [psi]`)",
            bar(level),
            bar(level * BAR_PER_PSI)
        ),
    };
    // Every error of the bounds that assume a compressing engine names
    // the flag that lifts them (INTERFACE.md, "Plausibility").
    Err(IngestError::Data(
        format!(
            "{}: the pressure around intake BDC from {} is {} bar absolute, above the {} bar any engine's intake holds: {why}",
            name(),
            ctx.source(),
            bar(level),
            enginedyn_numerics::format::human(HIGH_INTAKE_PA / 1e5),
        ) + NO_COMPRESSION,
    ))
}

/// What the compression bound's refusal says last: the flag that lifts it.
const NO_COMPRESSION: &str = "; a cylinder pressure of no compressing engine (a steam engine, a compressor, a textbook problem with a constant pressure) reads with --no-compression-check";

/// The trace's candidate levels at intake BDC (Pa), from the likeliest:
/// 540° (four-stroke) and 180°, in the file's angles from firing TDC,
/// then 180° before its peak (its own firing TDC, whatever the axis: a
/// cylinder's trace on cylinder 1's axis, or one whose firing TDC lies at
/// the file's 360°, which [`crate::axis`] decides after this pass). The
/// last is found only when asked for: most traces pass from the first.
pub(crate) fn intake_levels(tr: &Trace, cycle: f64) -> impl Iterator<Item = f64> + '_ {
    let fixed: &[f64] = if cycle > 400.0 {
        &[540.0, 180.0]
    } else {
        &[180.0]
    };
    fixed
        .iter()
        .map(move |&b| level_at(tr, b, cycle))
        .chain(std::iter::once_with(move || {
            let peak = tr
                .values
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map_or(0, |m| m.0);
            level_at(tr, tr.angle_deg[peak] - 180.0, cycle)
        }))
}

/// The lowest of the trace's candidate levels ([`intake_levels`], folded
/// by `f64::min` from `inf`), or `None` as soon as one is `enough`: a test
/// that the lowest then passes too (the later candidates, the peak's
/// above all, are found only when asked for).
fn lowest_level(tr: &Trace, cycle: f64, enough: impl Fn(f64) -> bool) -> Option<f64> {
    let mut low = f64::INFINITY;
    for level in intake_levels(tr, cycle) {
        if enough(level) {
            return None;
        }
        low = low.min(level);
    }
    Some(low)
}

/// The trace's level at angle `bdc` (deg, any turn; Pa): the mean of its
/// samples within ±5°, or its linear interpolant there when no sample lies
/// so near. Angles rising, spanning less than a cycle.
fn level_at(tr: &Trace, bdc: f64, cycle: f64) -> f64 {
    let a = &tr.angle_deg;
    let first = a[0];
    // The angle in the trace's own cycle, [first, first + cycle).
    let b = first + (bdc - first).rem_euclid(cycle);
    let (mut sum, mut n) = (0.0, 0usize);
    let mut add = |lo: f64, hi: f64| {
        let i = a.partition_point(|&x| x < lo);
        let j = a.partition_point(|&x| x <= hi);
        for v in &tr.values[i..j.max(i)] {
            sum += v;
            n += 1;
        }
    };
    add(b - 5.0, b + 5.0);
    // A window past the trace's end continues at its start, one before
    // its start at its end.
    add(b - 5.0 - cycle, b + 5.0 - cycle);
    add(b - 5.0 + cycle, b + 5.0 + cycle);
    if n > 0 {
        return sum / n as f64;
    }
    // No sample near: the linear interpolant (the wrap included; `b` is
    // at or after the first angle).
    let k = a.partition_point(|&x| x <= b);
    let m = a.len();
    let (x0, y0, x1, y1) = if k == m {
        (a[m - 1], tr.values[m - 1], a[0] + cycle, tr.values[0])
    } else {
        (a[k - 1], tr.values[k - 1], a[k], tr.values[k])
    };
    y0 + (y1 - y0) * (b - x0) / (x1 - x0)
}

/// What a trace refused by the compression bound looks like, for its
/// error: flat with a narrow pulse (an injection or ignition signal),
/// nearly flat, or a signal in other units.
fn looks_like(tr: &Trace, level: f64, peak: f64, cycle: f64, ctx: &Context<'_>) -> String {
    let n = tr.values.len();
    let half = level + 0.5 * (peak - level);
    let above = tr.values.iter().filter(|&&v| v > half).count();
    // Each sample stands for cycle / n degrees on average.
    let width = cycle * above as f64 / n as f64;
    let at = tr.angle_deg[tr
        .values
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |m| m.0)]
    .rem_euclid(cycle);
    // From firing TDC, either way: −10°, not 710°.
    let at = if at > cycle / 2.0 { at - cycle } else { at };
    let volts = if ctx.gain.is_some() {
        ""
    } else {
        "; a voltage is a `pressure_v` column with --gain BAR_PER_V"
    };
    if peak - level <= 0.05 * peak.abs().max(1.0) {
        format!("a nearly flat signal (a temperature, a speed, a manifold pressure?){volts}")
    } else if width <= cycle / 12.0 {
        format!(
            "a flat signal with a pulse {}° wide at {}°: an injection, needle-lift or ignition signal?{volts}",
            enginedyn_numerics::format::trimmed(width, 1),
            enginedyn_numerics::format::trimmed(at, 1)
        )
    } else {
        format!("a signal that never rises as a compression does: another quantity or unit?{volts}")
    }
}

/// Where the mean fired trace's pressure peak may lie (deg from firing
/// TDC): a fired cylinder's peak lies some 5° to 25° after it, a motored
/// one's within ±5° (INTERFACE.md, "Plausibility").
pub(crate) const PEAK_WINDOW_DEG: (f64, f64) = (-15.0, 60.0);

/// Where a suggested crank reference puts the peak (deg after firing TDC).
const PEAK_AIM_DEG: f64 = 10.0;

/// How far (relative) the pressure peaks of a time record may recur from
/// once a cycle of the signal's angle (INTERFACE.md: 2 %).
pub(crate) const RECUR_OFF: f64 = 0.02;

/// What placed firing TDC on the angle, as the peak-angle rule's error
/// names it.
#[derive(Debug, Clone, PartialEq)]
pub enum TdcPlacement {
    /// `--tdc-deg X` (given or not: the file's angle X is firing TDC).
    TdcDeg {
        /// The file's angle taken as firing TDC.
        deg: f64,
        /// `--tdc-deg` was given.
        given: bool,
    },
    /// `--tdc-time T` (s) at this speed (rpm).
    TdcTime {
        /// The time given (s).
        t: f64,
        /// The speed (rpm) that turns a shift in degrees into seconds.
        rpm: f64,
    },
    /// `--wheel-tdc-deg A` within the revolution; the firing revolution
    /// from a `cam` column when `cam`, else the pressure-peak rule.
    WheelTdcDeg {
        /// The angle given.
        deg: f64,
        /// A `cam` column chose the firing revolution.
        cam: bool,
    },
    /// A `tdc` column's pulse; the firing revolution from a `cam` column
    /// when `cam`, else the pressure-peak rule.
    TdcColumn {
        /// A `cam` column chose the firing revolution.
        cam: bool,
    },
}

/// The peak-angle rule (INTERFACE.md, "Plausibility"): the mean trace's
/// pressure peak (`mean`, on the grid `k step` deg from firing TDC over
/// one cycle) lies within [`PEAK_WINDOW_DEG`] of firing TDC; otherwise an
/// error naming what placed TDC and the shift that puts the peak at +10°.
/// `whose`: "" or " of cylinder 2".
pub(crate) fn peak_angle(
    mean: &[f64],
    step: f64,
    cycle: f64,
    placed: &TdcPlacement,
    whose: &str,
) -> Result<(), IngestError> {
    if mean.is_empty() || !(step > 0.0) {
        return Ok(());
    }
    let peak = (0..mean.len()).fold(0, |b, j| if mean[j] > mean[b] { j } else { b });
    let raw = peak as f64 * step;
    // From firing TDC, either way: −10°, not 710°.
    let at = if raw > cycle / 2.0 { raw - cycle } else { raw };
    if (PEAK_WINDOW_DEG.0..=PEAK_WINDOW_DEG.1).contains(&at) {
        return Ok(());
    }
    let fmt = |x: f64| enginedyn_numerics::format::trimmed(x, 1);
    // Firing TDC this many degrees later puts the peak at +10°.
    let shift = at - PEAK_AIM_DEG;
    let signed = |x: f64| {
        if x >= 0.0 {
            format!("+{}", fmt(x))
        } else {
            fmt(x)
        }
    };
    let how = match placed {
        TdcPlacement::TdcDeg { deg, given } => format!(
            "firing TDC is the file's angle {}{}; --tdc-deg {} puts the peak at +10°",
            fmt(*deg),
            if *given {
                " (--tdc-deg)"
            } else {
                " (--tdc-deg not given)"
            },
            fmt(deg + shift)
        ),
        TdcPlacement::TdcTime { t, rpm } if *rpm > 0.0 => format!(
            "firing TDC is at --tdc-time {} s; --tdc-time {} s ({}° at {} rpm) puts the peak at +10°",
            enginedyn_numerics::format::sig(*t, 6),
            enginedyn_numerics::format::sig(t + shift / (6.0 * rpm), 6),
            signed(shift),
            enginedyn_numerics::format::sig(*rpm, 5)
        ),
        TdcPlacement::TdcTime { t, .. } => format!(
            "firing TDC is at --tdc-time {} s; a --tdc-time {}° later puts the peak at +10°",
            enginedyn_numerics::format::sig(*t, 6),
            signed(shift)
        ),
        TdcPlacement::WheelTdcDeg { deg, cam } => {
            // The wheel gives TDC within a revolution; a shift beyond half
            // of one is the other revolution as well.
            let within = shift - 360.0 * (shift / 360.0).round();
            let other = (shift - within).abs() > 1.0;
            format!(
                "cylinder 1's TDC is --wheel-tdc-deg {} after the first tooth after the gap{}; {} puts the peak at +10°",
                fmt(*deg),
                if *cam {
                    ", the firing revolution the one after each `cam` pulse"
                } else {
                    ""
                },
                match (other, *cam) {
                    (false, _) => format!("--wheel-tdc-deg {}", fmt(deg + within)),
                    (true, true) => format!(
                        "--wheel-tdc-deg {} with the `cam` pulse on the other revolution (is it?)",
                        fmt(deg + within)
                    ),
                    (true, false) => format!(
                        "--wheel-tdc-deg {} with firing TDC on the other revolution (--tdc-deg 360)",
                        fmt(deg + within)
                    ),
                }
            )
        }
        TdcPlacement::TdcColumn { cam } => {
            let within = shift - 360.0 * (shift / 360.0).round();
            let other = (shift - within).abs() > 1.0;
            format!(
                "firing TDC is at the `tdc` column's pulse{}; --tdc-deg {} puts the peak at +10°",
                match (other, *cam) {
                    (true, true) =>
                        ", on the revolution after each `cam` pulse: a cam pulse on the other revolution?",
                    (_, true) => ", on the revolution after each `cam` pulse",
                    _ => "",
                },
                fmt(shift.rem_euclid(cycle))
            )
        }
    };
    // A peak a revolution from TDC on a four-stroke: the phasing, the
    // gas-exchange TDC taken for firing TDC.
    let phasing = if cycle > 400.0 && (at.abs() - 360.0).abs() <= 30.0 {
        " The peak lies a revolution from firing TDC: the phasing is wrong (the gas-exchange TDC was taken for firing TDC), not the pegging or the compression ratio."
    } else {
        ""
    };
    Err(IngestError::Data(format!(
        "the mean trace{whose} peaks {}° from firing TDC, outside the {}° to +{}° where a cylinder's pressure peaks (a fired one 5° to 25° after TDC, a motored one within ±5°): the crank reference is wrong, a shift of {}°; {how}.{phasing} (--no-compression-check lifts this rule for a trace of no compressing engine)",
        signed(at),
        fmt(PEAK_WINDOW_DEG.0),
        fmt(PEAK_WINDOW_DEG.1),
        signed(shift),
    )))
}

/// The pressure peaks of a time record on its signal's angle: each peak
/// is the highest sample of a stretch above two thirds of the range seen,
/// entered from below one third (so noise makes no peak). At most
/// [`Recurrence::MAX`] peaks are kept: memory stays bounded.
#[derive(Debug, Clone, Default)]
pub(crate) struct Recurrence {
    lo: f64,
    hi: f64,
    armed: bool,
    /// The stretch above two thirds: its highest sample (angle, value).
    inside: Option<(f64, f64)>,
    /// Each stretch's highest sample (angle, value).
    peaks: Vec<(f64, f64)>,
    seen: bool,
}

impl Recurrence {
    const MAX: usize = 4096;

    /// A sample of pressure `p` at signal angle `a` (deg, rising).
    #[inline]
    pub(crate) fn sample(&mut self, a: f64, p: f64) {
        if !self.seen {
            (self.lo, self.hi, self.seen) = (p, p, true);
        }
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
        let range = self.hi - self.lo;
        if let Some((_, v)) = self.inside.as_mut() {
            if p > *v {
                self.inside = Some((a, p));
            } else if p < self.lo + range / 3.0 {
                if self.peaks.len() < Self::MAX
                    && let Some(x) = self.inside
                {
                    self.peaks.push(x);
                }
                self.inside = None;
                self.armed = true;
            }
            return;
        }
        if p < self.lo + range / 3.0 {
            self.armed = true;
        } else if self.armed && range > 0.0 && p >= self.lo + 2.0 * range / 3.0 {
            self.inside = Some((a, p));
            self.armed = false;
        }
    }

    /// The check (INTERFACE.md, "Plausibility"): the peaks (those reaching
    /// half the record's range) recur once a `cycle` of the signal's angle
    /// within [`RECUR_OFF`]; otherwise an error naming `flag` and the count
    /// (`count` `what` a revolution × the recurrence over the cycle) the
    /// peaks suggest.
    pub(crate) fn check(
        &self,
        cycle: f64,
        flag: &str,
        count: f64,
        what: &str,
    ) -> Result<(), IngestError> {
        let level = self.lo + 0.5 * (self.hi - self.lo);
        let kept: Vec<f64> = self
            .peaks
            .iter()
            .chain(self.inside.as_ref())
            .filter(|x| x.1 >= level)
            .map(|x| x.0)
            .collect();
        if kept.len() < 2 {
            return Ok(());
        }
        let mut d: Vec<f64> = kept.windows(2).map(|w| w[1] - w[0]).collect();
        d.sort_by(f64::total_cmp);
        let m = d.len() / 2;
        let median = if d.len() % 2 == 1 {
            d[m]
        } else {
            0.5 * (d[m - 1] + d[m])
        };
        if (median / cycle - 1.0).abs() <= RECUR_OFF {
            return Ok(());
        }
        let suggest = count * median / cycle;
        let fmt = |x: f64, n: usize| enginedyn_numerics::format::trimmed(x, n);
        Err(IngestError::Data(format!(
            "the pressure peaks recur every {}° of the crank signal's angle, not once a {}° cycle (within {} %): {flag} is wrong; it says {} {what} a revolution, the peaks suggest {}",
            fmt(median, 1),
            fmt(cycle, 0),
            fmt(100.0 * RECUR_OFF, 0),
            fmt(count, 3),
            fmt(suggest, if suggest >= 100.0 { 0 } else { 1 }),
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};

    /// The glitch rule's fast path (evenly spaced samples, fixed weights)
    /// finds what the plain definition (Lagrange's cubic at each sample's
    /// own angle, taken when the spacing is uneven by a hair) finds, with
    /// the same cubic, on data shaped to test it: glitches at both ends of
    /// the cycle (the wrap), a narrow peak that is no glitch, a flat
    /// stretch.
    #[test]
    fn the_even_spacing_shortcut_is_the_plain_rule() {
        let n = 720;
        let step = 1.0;
        let mut p: Vec<f64> = (0..n)
            .map(|k| {
                let deg = k as f64 * step - 360.0;
                1e5 + 50e5 * (-(deg / 15.0).powi(2)).exp()
            })
            .collect();
        for (k, v) in [(0, 40e5), (1, 1e5), (355, 200e5), (718, 60e5), (400, 1e5)] {
            p[k] += v;
        }
        let even: Vec<f64> = (0..n).map(|k| k as f64 * step - 360.0).collect();
        // The same angles, one nudged by a hair: the general path.
        let mut uneven = even.clone();
        uneven[500] += 1e-7;
        let tr = |a: Vec<f64>| Trace {
            cycle: 1,
            cylinder: 0,
            angle_deg: a,
            values: p.clone(),
            rpm: None,
        };
        let find = |t: Trace| {
            let steps = enginedyn_numerics::scan::steps(&t.angle_deg);
            glitches(&t, &steps, 720.0, Quantity::Pressure, true)
        };
        let fast = find(tr(even));
        let plain = find(tr(uneven));
        assert!(!fast.is_empty());
        assert_eq!(fast.len(), plain.len(), "{fast:?} {plain:?}");
        for (f, q) in fast.iter().zip(&plain) {
            assert_eq!(f.at, q.at);
            assert!((f.cubic - q.cubic).abs() < 1e-3, "{f:?} {q:?}");
        }
    }

    /// The glitch rule as it reads: every sample against the cubic through
    /// its four neighbours (`glitches` told the spacing is uneven, so it
    /// takes no shortcut); on exactly even angles its cubic is the fixed
    /// weights' one, so the shortcut must give the same glitches, bit for
    /// bit.
    fn both(p: &[f64], absolute: bool) -> (Vec<Glitch>, Vec<Glitch>) {
        let n = p.len();
        let t = Trace {
            cycle: 1,
            cylinder: 0,
            angle_deg: (0..n).map(|k| k as f64 * 0.5).collect(),
            values: p.to_vec(),
            rpm: None,
        };
        let cycle = n as f64 * 0.5;
        let steps = enginedyn_numerics::scan::steps(&t.angle_deg);
        assert!(evenly_spaced(&t.angle_deg, &steps));
        let uneven = Steps { nan: true, ..steps };
        (
            glitches(&t, &steps, cycle, Quantity::Pressure, absolute),
            glitches(&t, &uneven, cycle, Quantity::Pressure, absolute),
        )
    }

    fn same(a: &[Glitch], b: &[Glitch]) -> bool {
        a.len() == b.len()
            && a.iter().zip(b).all(|(x, y)| {
                x.at == y.at
                    && x.value.to_bits() == y.value.to_bits()
                    && x.cubic.to_bits() == y.cubic.to_bits()
            })
    }

    /// A smooth cycle of `n` samples: 1 bar, a 40 bar hump at a third.
    fn smooth(n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| {
                let x = (k as f64 - n as f64 / 3.0) / (n as f64 / 10.0);
                1e5 + 40e5 * (-x * x).exp()
            })
            .collect()
    }

    /// The block scan finds what every sample's test finds, on spikes at
    /// each end (the periodic wrap), on and around the block edges, two
    /// side by side, a flat stretch, NaN and infinite samples, a spike
    /// exactly at the threshold and a hair above, at every length from 8
    /// to 70 and around two blocks.
    #[test]
    fn the_block_scan_is_the_plain_rule() {
        let lengths: Vec<usize> = (8..=70).chain(126..=140).chain([7200]).collect();
        let mut found = 0;
        for &n in &lengths {
            let mut spots: Vec<usize> = vec![0, 1, 2, 3, n / 2, n - 4, n - 3, n - 2, n - 1];
            for edge in [GLITCH_BLOCK, 2 * GLITCH_BLOCK] {
                spots.extend((edge..edge + 6).filter(|&k| k < n));
            }
            for &k in &spots {
                let cases: Vec<Vec<(usize, f64)>> = vec![
                    vec![(k, 60e5)],
                    vec![(k, -60e5)],
                    vec![(k, 60e5), ((k + 1) % n, 60e5)],
                    vec![(k, f64::NAN)],
                    vec![(k, f64::INFINITY)],
                    vec![(k, f64::NEG_INFINITY)],
                    vec![(k, f64::NAN), ((k + 3) % n, 60e5)],
                    vec![(k, f64::INFINITY), ((k + 2) % n, 60e5)],
                ];
                for case in cases {
                    for absolute in [true, false] {
                        let mut p = smooth(n);
                        for &(at, v) in &case {
                            p[at] = if v.is_finite() { p[at] + v } else { v };
                        }
                        let (fast, plain) = both(&p, absolute);
                        assert!(same(&fast, &plain), "n {n} {case:?}: {fast:?} {plain:?}");
                        found += fast.len();
                    }
                }
                // Flat at 1 bar: exactly 10 bar above its cubic is no
                // candidate, a hair more is (and a glitch: the peak is the
                // others' 1 bar).
                for (v, want) in [(11e5, 0), (11e5 + 1e-9, 1)] {
                    let mut p = vec![1e5; n];
                    p[k] = v;
                    let (fast, plain) = both(&p, true);
                    assert!(same(&fast, &plain), "n {n} at {k}: {fast:?} {plain:?}");
                    assert_eq!(fast.len(), want, "n {n} at {k}: {fast:?}");
                }
            }
        }
        // The cases hold glitches to find: the test can fail.
        assert!(found > 1000, "{found}");
    }

    proptest::proptest! {
        /// Random traces with spikes near the threshold, NaN and infinite
        /// samples: the block scan gives the plain rule's glitches.
        #[test]
        fn the_block_scan_is_the_plain_rule_on_random_traces(
            n in 8usize..200,
            spikes in proptest::collection::vec(
                (0usize..200, proptest::prop_oneof![
                    -30e5f64..30e5,
                    proptest::strategy::Just(10e5),
                    proptest::strategy::Just(f64::NAN),
                    proptest::strategy::Just(f64::INFINITY),
                ]),
                0..6,
            ),
            flat in proptest::bool::ANY,
        ) {
            let mut p = if flat { vec![2e5; n] } else { smooth(n) };
            for (at, v) in spikes {
                let at = at % n;
                p[at] = if v.is_finite() { p[at] + v } else { v };
            }
            for absolute in [true, false] {
                let (fast, plain) = both(&p, absolute);
                proptest::prop_assert!(same(&fast, &plain), "{:?} {:?}", fast, plain);
            }
        }
    }

    /// The bundled single's geometry (R 27 mm, L 84 mm, bore 68 mm).
    fn cylinder(eps: f64) -> Cylinder {
        let crank = CrankSlider::new(0.027, 0.084, 0.0).unwrap();
        Cylinder::new(Mechanism::CrankSlider(crank), 0.068, eps).unwrap()
    }

    fn ctx(eps: f64, absolute: bool) -> Context<'static> {
        Context {
            column: "column 3 `pressure_bar` (in bar)",
            gain: None,
            absolute,
            gauge: false,
            compression_ratio: Some(eps),
            despike: false,
            coverage_first: true,
        }
    }

    fn run(tr: &Trace, cycle: f64, c: &Context<'_>) -> Result<(), String> {
        check(tr, 1.0, cycle, Quantity::Pressure, c, &|| "cycle 1".into())
            .map(|_| ())
            .map_err(|e| e.to_string())
    }

    /// A motored cycle on 1° steps from firing TDC: `p_in` (Pa) through the
    /// gas exchange, polytropic with exponent `n` from the volume at
    /// `close` degrees before firing TDC (inlet or ports closing) to the
    /// same angle after.
    fn motored(eps: f64, cycle: f64, p_in: f64, n: f64, close: f64) -> Trace {
        let cyl = cylinder(eps);
        let v_close = cyl.volume(close.to_radians());
        let angle_deg: Vec<f64> = (0..cycle as usize).map(|k| k as f64).collect();
        let values = angle_deg
            .iter()
            .map(|&a| {
                let c = if a > cycle / 2.0 { a - cycle } else { a };
                if c.abs() < close {
                    p_in * (v_close / cyl.volume(a.to_radians())).powf(n)
                } else {
                    p_in
                }
            })
            .collect();
        Trace {
            cycle: 1,
            cylinder: 0,
            angle_deg,
            values,
            rpm: None,
        }
    }

    /// Motored traces pass: their peak is the compression pressure, at a
    /// throttled petrol engine's 0.3 bar intake, with a heat-losing
    /// exponent of 1.2 and the inlet closing 50° after BDC; a diesel at
    /// 1 bar; a two-stroke whose ports close 100° before TDC; the same as
    /// gauge data, and relative (unpegged) with an arbitrary offset.
    #[test]
    fn motored_traces_pass() {
        let petrol = motored(8.5, 720.0, 0.3e5, 1.2, 130.0);
        run(&petrol, 720.0, &ctx(8.5, true)).unwrap();
        let diesel = motored(17.0, 720.0, 1e5, 1.2, 130.0);
        run(&diesel, 720.0, &ctx(17.0, true)).unwrap();
        let two = motored(7.5, 360.0, 1.05e5, 1.25, 100.0);
        run(&two, 360.0, &ctx(7.5, true)).unwrap();
        let mut gauge = diesel.clone();
        gauge.values.iter_mut().for_each(|v| *v -= ATM);
        // Below zero over the gas exchange: more than half the cycle.
        assert!(
            run(&gauge, 720.0, &ctx(17.0, true))
                .unwrap_err()
                .contains("--gauge")
        );
        gauge.values.iter_mut().for_each(|v| *v += 0.1e5);
        run(&gauge, 720.0, &ctx(17.0, true)).unwrap();
        let mut relative = petrol.clone();
        relative.values.iter_mut().for_each(|v| *v -= 3e5);
        run(&relative, 720.0, &ctx(8.5, false)).unwrap();
    }

    /// A throttled motored trace (intake 0.3 bar, exhaust 1 bar) on
    /// another cylinder's axis, its firing TDC at the file's 270°: 540°
    /// falls in its exhaust stroke and 180° in its compression, so from
    /// either it would be refused; 180° before its peak is its intake BDC,
    /// and it passes.
    #[test]
    fn intake_bdc_is_found_on_any_axis() {
        let mut t = motored(8.5, 720.0, 0.3e5, 1.2, 130.0);
        for (a, v) in t.angle_deg.iter().zip(t.values.iter_mut()) {
            if (130.0..360.0).contains(a) {
                *v = 1e5;
            }
        }
        let peak = t.values.iter().cloned().fold(0.0, f64::max);
        // Rotate: the sample at cycle angle a now sits at a + 270.
        let n = t.values.len();
        t.values.rotate_right(270 * n / 720);
        for at in [540.0, 180.0] {
            let need = compression_pressure(8.5, 720.0, level_at(&t, at, 720.0));
            assert!(need > peak, "{at}: {need} {peak}");
        }
        let levels: Vec<f64> = intake_levels(&t, 720.0).collect();
        assert!((levels[2] - 0.3e5).abs() < 1.0, "{levels:?}");
        run(&t, 720.0, &ctx(8.5, true)).unwrap();
    }

    /// The bound is half of `p_in ε^1.3`: a trace just above it passes,
    /// just below it is refused (1 bar at BDC, ε 8.5: 8.1 bar).
    #[test]
    fn the_bound_is_half_the_compression_pressure() {
        let need = compression_pressure(8.5, 720.0, 1e5);
        assert!((need - 0.5 * 1e5 * 8.5f64.powf(1.3)).abs() < 1e-9, "{need}");
        assert!((need / 1e5 - 8.1).abs() < 0.05, "{need}");
        // Two-stroke: from 1 + (ε − 1)/2.
        let two = compression_pressure(7.5, 360.0, 1e5);
        assert!((two - 0.5 * 1e5 * 4.25f64.powf(1.3)).abs() < 1e-9, "{two}");
        let mut t = motored(8.5, 720.0, 1e5, 1.3, 180.0);
        let peak = t.values.iter().cloned().fold(0.0, f64::max);
        for v in &mut t.values {
            *v = 1e5 + (*v - 1e5) * (need * 1.001 - 1e5) / (peak - 1e5);
        }
        run(&t, 720.0, &ctx(8.5, true)).unwrap();
        for v in &mut t.values {
            *v = 1e5 + (*v - 1e5) * (0.998 * need - 1e5) / (need * 1.001 - 1e5);
        }
        let e = run(&t, 720.0, &ctx(8.5, true)).unwrap_err();
        assert!(
            e.contains("is not a cylinder pressure") && e.contains("ε = 8.5"),
            "{e}"
        );
        // Unknown engine: no bound.
        let c = Context {
            compression_ratio: None,
            ..ctx(8.5, true)
        };
        run(&t, 720.0, &c).unwrap();
    }

    /// An injection signal read as bar: 0 at rest, a 5 "bar" pulse 20°
    /// wide before TDC. Its own BDC level (0) would give a bound of 0; read
    /// as gauge it needs 8.2 − 1.01 bar and is refused, said to look like a
    /// pulse. Pegged (relative), a 1 bar swing is refused too.
    #[test]
    fn an_injection_signal_is_refused() {
        let angle_deg: Vec<f64> = (0..1440).map(|k| k as f64 * 0.5 - 360.0).collect();
        let values: Vec<f64> = angle_deg
            .iter()
            .map(|&a| {
                if (-15.0..5.0).contains(&a) {
                    5e5
                } else {
                    0.002e5
                }
            })
            .collect();
        let t = Trace {
            cycle: 1,
            cylinder: 0,
            angle_deg,
            values,
            rpm: None,
        };
        let e = run(&t, 720.0, &ctx(8.5, true)).unwrap_err();
        assert!(
            e.contains("column 3 `pressure_bar` (in bar) is not a cylinder pressure")
                && e.contains("read as gauge")
                && e.contains("a flat signal with a pulse 20° wide at 4.5°: an injection"),
            "{e}"
        );
        let mut small = t.clone();
        small.values.iter_mut().for_each(|v| *v *= 0.2);
        let e = run(&small, 720.0, &ctx(8.5, false)).unwrap_err();
        assert!(e.contains("rises by 0.9996 bar"), "{e}");
    }
}
