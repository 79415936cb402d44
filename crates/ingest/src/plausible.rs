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
//! - Torque: at most 1e9 N m in magnitude.

use crate::error::IngestError;
use crate::{Quantity, Trace};

/// The highest absolute pressure a cylinder reaches (Pa): 1000 bar, above
/// the largest diesel's 250–300 bar peak by a margin no measured trace
/// comes near, and below what any unit or gain mix-up gives.
pub(crate) const MAX_PEAK_PA: f64 = 1e8;

/// The lowest peak (Pa), and the least swing of a relative trace: 0.05 bar.
pub(crate) const MIN_PEAK_PA: f64 = 5e3;

/// The largest engines make about 1e7 N m: beyond 1e9 is a unit mix-up.
pub(crate) const MAX_TORQUE_NM: f64 = 1e9;

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
    Ok((count, vlo))
}
