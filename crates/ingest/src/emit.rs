//! The emitter: each finished trace checked ([`crate::trace::finish`], the
//! plausibility pass), moved to its firing TDC ([`crate::axis`]) and handed
//! on, the gap rule applied and the notes about traces gathered. Every
//! layout hands its traces here; it depends on none of them.

use crate::error::{IngestError, at};
use crate::plausible::LOW_INTAKE_PA;
use crate::probe::Probe;
use crate::trace::{self, Checked, Gap};
use crate::{Header, ParseOptions, Quantity, Streamed, Trace};

/// Checks each finished trace and hands it on, applying the gap rule: a
/// single cycle (per cylinder) with a gap is held to the end and bridged up
/// to `--max-gap`; once a cylinder has several cycles, those with a gap are
/// left out of the averages.
pub(crate) struct Emitter<'o, F> {
    opts: &'o ParseOptions,
    sink: F,
    /// Pressures must be absolute (not to be pegged): checked for sign.
    absolute: bool,
    pv_notes: Vec<String>,
    /// Per cylinder (0: one trace for all): traces seen and handed on.
    seen: Vec<(usize, usize)>,
    held: Vec<Option<(Trace, Checked, Quantity, usize)>>,
    /// Cycles left out: (cycle, cylinder, the gap).
    skipped: Vec<(i64, i64, Gap)>,
    bridged: Vec<(String, Gap)>,
    /// Gaps wider than `--max-gap` that the data settle, with the share of
    /// the cycle's work the two interpolants differ by over them.
    settled: Vec<(String, Gap, f64)>,
    /// Glitches ([`crate::plausible::glitches`]): the first few said by
    /// trace, line, value and cubic (Pa), and how many in all.
    glitches: (Vec<(String, usize, f64, f64)>, usize),
    /// Samples below zero, traces with any, the lowest (Pa).
    below: (usize, usize, f64),
    /// Traces whose mean around intake BDC is below [`LOW_INTAKE_PA`], the
    /// lowest such mean and the highest of their peaks (Pa).
    low_intake: (usize, f64, f64),
    total: usize,
    /// The value columns as messages name them (`Roles::labels`).
    pub labels: Vec<String>,
    /// The values are volts times `--gain`.
    pub volts: bool,
    /// The traces are p–V data (placed on angles by volume).
    pv: bool,
    /// The traces come from a time record (its own firing-TDC rule).
    pub time: bool,
    /// Where each trace's firing TDC lies (the 360° rule, the cylinders' axis).
    aligner: crate::axis::Aligner,
    /// A headerless file being probed for the readings that fit.
    pub probe: Option<Probe>,
    /// A diagram `enginedyn synth` wrote: exact by construction, so the
    /// plausibility rules of measured data (the compression check, the
    /// intake level) do not question it.
    pub synthetic: bool,
}

impl<'o, F: FnMut(Streamed) -> Result<(), IngestError>> Emitter<'o, F> {
    pub(crate) fn new(opts: &'o ParseOptions, sink: F) -> Self {
        Self {
            opts,
            sink,
            absolute: !opts.relative,
            pv_notes: Vec::new(),
            seen: Vec::new(),
            held: Vec::new(),
            skipped: Vec::new(),
            bridged: Vec::new(),
            settled: Vec::new(),
            glitches: (Vec::new(), 0),
            below: (0, 0, 0.0),
            low_intake: (0, f64::INFINITY, 0.0),
            total: 0,
            labels: Vec::new(),
            volts: false,
            pv: false,
            time: false,
            aligner: crate::axis::Aligner::new(opts),
            probe: None,
            synthetic: opts.synthetic,
        }
    }

    /// Where a long record's firing TDC lies before its first cut
    /// ([`crate::axis::Aligner::firing_offset`]).
    pub(crate) fn firing_offset(
        &self,
        angles: &[f64],
        values: &[f64],
        quantity: Quantity,
        cylinder: i64,
    ) -> f64 {
        if self.pv || self.time {
            return 0.0;
        }
        self.aligner
            .firing_offset(angles, values, quantity, cylinder)
    }

    /// While probing a headerless file, any error but the probe's own
    /// verdict (a first column that is no angle, a cell that is no number)
    /// is the plain no-header error: the guessed names are not the user's.
    pub(crate) fn probed<T>(&self, r: Result<T, IngestError>) -> Result<T, IngestError> {
        match (&self.probe, r) {
            (Some(p), Err(_)) if !p.done => Err(p.error()),
            (_, r) => r,
        }
    }

    /// A finished trace, its first line, what it holds, whether p–V.
    pub(crate) fn trace(
        &mut self,
        tr: Trace,
        line: usize,
        q: Quantity,
        pv: bool,
        value: usize,
    ) -> Result<(), IngestError> {
        let opts = self.opts;
        self.pv = pv;
        let tr = if pv {
            let cyl = opts.cylinder.as_ref().ok_or_else(|| {
                IngestError::Data("p–V data needs the engine's volume law".into())
            })?;
            crate::pv::to_angles(
                tr,
                cyl,
                opts.cycle_deg,
                opts.pv_start_bdc,
                line,
                &mut self.pv_notes,
            )?
        } else {
            tr
        };
        // A trace's errors name the line it starts on.
        let ctx = crate::plausible::Context {
            column: self
                .labels
                .get(value)
                .map_or("the pressure column", String::as_str),
            gain: opts.gain_bar_per_v.filter(|_| self.volts),
            absolute: self.absolute,
            gauge: opts.gauge,
            compression_ratio: opts
                .cylinder
                .as_ref()
                .filter(|_| opts.compression_check && !self.synthetic)
                .map(|c| c.compression_ratio()),
            despike: opts.despike,
            coverage_first: self.probe.is_none(),
        };
        if let Some(p) = self.probe.as_mut() {
            let prefix = format!("{}: ", trace::describe(tr.cycle, tr.cylinder));
            let verdict = trace::finish(tr, opts.cycle_deg, q, &ctx)
                .map(|_| ())
                .map_err(|e| {
                    let m = e.to_string();
                    m.strip_prefix(&prefix).map_or(m.clone(), str::to_string)
                });
            if let Some(slot @ None) = p.verdicts.get_mut(value) {
                *slot = Some(verdict);
            }
            if p.verdicts.iter().all(Option::is_some) {
                p.done = true;
                return Err(p.error());
            }
            return Ok(());
        }
        let (mut tr, mut c) = trace::finish(tr, opts.cycle_deg, q, &ctx).map_err(|e| match e {
            IngestError::Data(m) => at(line, None, m),
            e => e,
        })?;
        if self
            .aligner
            .align(&mut tr, q, self.time, pv)
            .map_err(|e| match e {
                IngestError::Data(m) => at(line, None, m),
                e => e,
            })?
        {
            // Moved: its steps now include the joined ends, and its angles
            // are no longer known to rise.
            c.steps = None;
            c.rising = false;
        }
        if self.absolute
            && !self.synthetic
            && q == Quantity::Pressure
            && !pv
            && let Some(m) = if c.rising {
                enginedyn_numerics::intake_bdc_mean_rising(
                    &tr.angle_deg,
                    &tr.values,
                    opts.cycle_deg,
                )
            } else {
                crate::grid::intake_bdc_mean(
                    tr.angle_deg.iter().copied().zip(tr.values.iter().copied()),
                    opts.cycle_deg,
                )
            }
            && m < LOW_INTAKE_PA
        {
            self.low_intake.0 += 1;
            self.low_intake.1 = self.low_intake.1.min(m);
            let peak = tr.values.iter().copied().fold(0.0, f64::max);
            self.low_intake.2 = self.low_intake.2.max(peak);
        }
        for g in &c.glitches {
            if self.glitches.0.len() < GLITCHES_SAID {
                self.glitches.0.push((
                    trace::describe(tr.cycle, tr.cylinder),
                    line + g.at,
                    g.value,
                    g.cubic,
                ));
            }
            self.glitches.1 += 1;
        }
        if c.below_zero.0 > 0 {
            self.below.0 += c.below_zero.0;
            self.below.1 += 1;
            self.below.2 = self.below.2.min(c.below_zero.1);
        }
        self.total += 1;
        let k = usize::try_from(tr.cylinder).unwrap_or(0);
        if self.seen.len() <= k {
            self.seen.resize(k + 1, (0, 0));
            self.held.resize_with(k + 1, || None);
        }
        self.seen[k].0 += 1;
        if self.seen[k].0 == 2
            && let Some((t, c, _, _)) = self.held[k].take()
            && let Some(g) = c.gap
        {
            self.skipped.push((t.cycle, t.cylinder, g));
        }
        match c.gap {
            Some(_) if self.seen[k].0 == 1 => {
                self.held[k] = Some((tr, c, q, line));
                Ok(())
            }
            Some(g) => {
                self.skipped.push((tr.cycle, tr.cylinder, g));
                Ok(())
            }
            None => self.send(tr, c, q),
        }
    }

    /// A single cycle's gap wider than `--max-gap`: where it is, and the
    /// `--max-gap` that bridges it, when the flag's bound allows one.
    /// `share`: how far the linear and cubic interpolants' `∫ p dV` over
    /// it differ, as a share of the cycle's work, when measured.
    fn gap_error(
        &self,
        tr: &Trace,
        g: trace::Gap,
        line: usize,
        share: Option<(f64, Option<String>)>,
    ) -> IngestError {
        let cycle = self.opts.cycle_deg;
        let max_gap = self.opts.max_gap_deg;
        let needed = g.width.ceil();
        let now = if (max_gap - crate::MAX_GAP_DEG).abs() < 1e-9 {
            format!("the default --max-gap bridges gaps up to {}°", fmt(max_gap))
        } else {
            format!(
                "--max-gap {} bridges gaps up to {}° (the default: {}°)",
                fmt(max_gap),
                fmt(max_gap),
                fmt(crate::MAX_GAP_DEG)
            )
        };
        let settle = share.map_or(String::new(), |(s, over)| {
            let differ = format!(
                "; the linear and the cubic interpolants' ∫ p dV over it differ by {} % of the cycle's work",
                enginedyn_numerics::format::sig(100.0 * s, 2),
            );
            match (s >= trace::SETTLED_SHARE, over) {
                (true, over) => format!(
                    "{differ}, more than the {} % that would let the data settle it{}",
                    enginedyn_numerics::format::human(100.0 * trace::SETTLED_SHARE),
                    over.map_or(String::new(), |why| format!(
                        ", nor do they settle a gap that {why}"
                    ))
                ),
                (false, Some(why)) => format!("{differ}, but the data settle no gap that {why}"),
                (false, None) => differ,
            }
        });
        let hint = if needed <= crate::MAX_GAP_BOUND_DEG {
            format!(
                "{now}{settle}; --max-gap {} would bridge this one",
                fmt(needed)
            )
        } else {
            format!(
                "that is less than half the cycle, which no --max-gap bridges (its bound is {}°): is the file cut short?",
                fmt(crate::MAX_GAP_BOUND_DEG)
            )
        };
        // The gap's own line: one sample a row from the trace's first line
        // (p–V data is reordered by volume, so it names the first line).
        let gap_line = if self.pv { line } else { line + g.at };
        at(
            gap_line,
            None,
            format!(
                "{} has a gap of {}° from {}° to {}° (its steps are {}°): the data cover {}° of the {}° cycle; {hint}",
                trace::describe(tr.cycle, tr.cylinder),
                fmt(g.width),
                fmt(g.from),
                fmt((g.from + g.width) % cycle),
                fmt(g.median),
                fmt(cycle - g.width),
                fmt(cycle),
            ),
        )
    }

    fn send(&mut self, tr: Trace, c: Checked, q: Quantity) -> Result<(), IngestError> {
        let k = usize::try_from(tr.cylinder).unwrap_or(0);
        self.seen[k].1 += 1;
        (self.sink)(Streamed {
            trace: tr,
            quantity: q,
            steps: c.steps,
        })
    }

    pub(crate) fn end(&mut self, head: &mut Header) -> Result<(), IngestError> {
        let max_gap = self.opts.max_gap_deg;
        for k in 0..self.held.len() {
            let Some((tr, c, q, line)) = self.held[k].take() else {
                continue;
            };
            let Some(g) = c.gap else { continue };
            if g.width > max_gap + 1e-9 {
                // Wider than --max-gap: bridged when the data settle it.
                let share = self
                    .opts
                    .cylinder
                    .as_ref()
                    .filter(|_| q == Quantity::Pressure && g.width <= crate::MAX_GAP_BOUND_DEG)
                    .and_then(|cyl| trace::gap_work_share(&tr, cyl, self.opts.cycle_deg));
                let over = trace::unsettled(g, self.opts.cycle_deg);
                match share {
                    Some(s) if s < trace::SETTLED_SHARE && over.is_none() => {
                        self.settled
                            .push((trace::describe(tr.cycle, tr.cylinder), g, s));
                        self.send(tr, c, q)?;
                        continue;
                    }
                    _ => return Err(self.gap_error(&tr, g, line, share.map(|s| (s, over)))),
                }
            }
            self.bridged
                .push((trace::describe(tr.cycle, tr.cylinder), g));
            self.send(tr, c, q)?;
        }
        for (k, (seen, sent)) in self.seen.iter().enumerate() {
            if *seen > 0 && *sent == 0 {
                return Err(IngestError::Data(format!(
                    "every one of the {seen} cycles{} has a gap (a spacing of more than 5 median steps): none is left to average",
                    if k > 0 {
                        format!(" of cylinder {k}")
                    } else {
                        String::new()
                    }
                )));
            }
        }
        if let Some((name, g)) = self.bridged.first() {
            head.notes.push(format!(
                "{name} has a gap of {}° from {}° (its steps are {}°){}: bridged by the interpolant (--max-gap {}°); the pressure there is its guess, and peak pressure and IMEP are uncertain by what the gap hides",
                fmt(g.width),
                fmt(g.from),
                fmt(g.median),
                if self.bridged.len() > 1 { format!(", and {} more traces have one", self.bridged.len() - 1) } else { String::new() },
                fmt(max_gap)
            ));
        }
        for (name, g, share) in &self.settled {
            head.notes.push(format!(
                "{name} has a gap of {}° from {}° (its steps are {}°), wider than --max-gap {}°: bridged, as the data settle it: the linear and the cubic interpolants' ∫ p dV over it differ by {} % of the cycle's work (under {} %)",
                fmt(g.width),
                fmt(g.from),
                fmt(g.median),
                fmt(max_gap),
                enginedyn_numerics::format::sig(100.0 * share, 2),
                enginedyn_numerics::format::human(100.0 * trace::SETTLED_SHARE)
            ));
        }
        if let Some((cycle, cylinder, g)) = self
            .skipped
            .iter()
            .max_by(|a, b| a.2.width.total_cmp(&b.2.width))
            .cloned()
        {
            head.notes.push(format!(
                "{} of {} cycles left out of the averages for {GAP} ({DROPOUT}; the widest: {}, {}° from {}°)",
                self.skipped.len(),
                self.total,
                trace::describe(cycle, cylinder),
                fmt(g.width),
                fmt(g.from)
            ));
            head.cycles_skipped = self.skipped.len();
            head.skipped = self
                .skipped
                .iter()
                .map(|&(cycle, cylinder, g)| crate::SkippedCycle {
                    cylinder,
                    cycle,
                    reason: format!("{GAP} ({DROPOUT}): {}° from {}°", fmt(g.width), fmt(g.from)),
                })
                .collect();
        }
        if let Some(n) = glitch_note(&self.glitches, self.opts.despike) {
            head.notes.push(n);
        }
        if self.below.0 > 0 {
            head.notes.push(format!(
                "{} sample{} below zero absolute pressure (lowest {} bar){}: kept, as sensor noise or drift in the gas exchange",
                self.below.0,
                if self.below.0 > 1 { "s" } else { "" },
                enginedyn_numerics::format::sig(self.below.2 / 1e5, 3),
                if self.total > 1 { format!(" in {} of {} traces", self.below.1, self.total) } else { String::new() }
            ));
        }
        if self.low_intake.0 > 0 {
            head.notes.push(format!(
                "the pressure around intake BDC averages {} bar absolute{}, below the {} bar an engine's intake holds: gauge data (relative to the atmosphere) read as absolute? give --gauge, or peg a relative trace (--peg-bar P)",
                enginedyn_numerics::format::sig(self.low_intake.1 / 1e5, 3),
                if self.total > 1 {
                    format!(" (lowest) in {} of {} traces", self.low_intake.0, self.total)
                } else {
                    String::new()
                },
                enginedyn_numerics::format::human(LOW_INTAKE_PA / 1e5)
            ) + &crate::plausible::mpa_hint(self.low_intake.1, self.low_intake.2));
        }
        head.notes.append(&mut self.pv_notes);
        head.notes.extend(self.aligner.notes());
        Ok(())
    }
}

fn fmt(x: f64) -> String {
    enginedyn_numerics::format::trimmed(x, 2)
}

/// Why a cycle is left out of the averages: the note on the skipped cycles
/// and each cycle's `skip_reason` (the `cycles` table) say it in these words.
const GAP: &str = "a gap in the data";
/// What such a gap is.
const DROPOUT: &str = "a dropout: a spacing of more than 5 median steps";

/// Glitches said one by one in the note; the rest are counted.
const GLITCHES_SAID: usize = 5;

/// The note of the glitch rule ([`crate::plausible::glitches`]): with
/// `--despike` how many were replaced (a decision), else a warning naming
/// each one's line and value and the flag.
fn glitch_note(g: &(Vec<(String, usize, f64, f64)>, usize), despike: bool) -> Option<String> {
    let (said, count) = (&g.0, g.1);
    if count == 0 {
        return None;
    }
    let bar = |pa: f64| enginedyn_numerics::format::sig(pa / 1e5, 4);
    let each: Vec<String> = said
        .iter()
        .map(|(name, line, value, cubic)| {
            format!(
                "{name}, line {line}: {} bar where its neighbours' cubic gives {} bar",
                bar(*value),
                bar(*cubic)
            )
        })
        .collect();
    let more = if count > said.len() {
        format!(" and {} more", count - said.len())
    } else {
        String::new()
    };
    let s = if count == 1 { "" } else { "s" };
    Some(if despike {
        format!(
            "--despike replaced {count} glitch{} by the cubic through its neighbours (two each side): {}{more}",
            if count == 1 { "" } else { "es" },
            each.join("; ")
        )
    } else {
        format!(
            "{count} glitch{} (a lone sample off the cubic through its neighbours, two each side, by more than {} bar and {} % of the cycle's peak): {}{more}; kept: --despike replaces {} by that cubic",
            if count == 1 { "" } else { "es" },
            enginedyn_numerics::format::human(crate::plausible::GLITCH_PA / 1e5),
            enginedyn_numerics::format::human(100.0 * crate::plausible::GLITCH_SHARE),
            each.join("; "),
            if s.is_empty() { "it" } else { "each" }
        )
    })
}
