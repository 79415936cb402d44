//! Time records: a data acquisition system sampling in time, not on a
//! crank-angle encoder. The crank angle comes from a TDC pulse per
//! revolution (the speed taken revolution by revolution, the angle linear in
//! time within each), or from a constant speed and the time of one firing
//! TDC (`--rpm`, `--tdc-time`). On a four-stroke the firing TDC is the pulse
//! the pressure peak follows: of the two pulses of a cycle, the one after
//! which the mean pressure over the next 90° is higher (expansion, not
//! intake).
//!
//! Memory is bounded: the first [`PROBE`] samples are held to find the
//! pulse's range, then one revolution at a time (four at the start of a
//! four-stroke, until the firing pulse is known).

use crate::columns::{Axis, Roles};
use crate::error::{IngestError, at, shown_number};
use crate::layout::value_scale;
use crate::reader::Emitter;
use crate::row::Cells;
use crate::{Header, ParseOptions, Quantity, Streamed, Trace};

/// Samples held to find the pulse's range (its half-way level).
pub(crate) const PROBE: usize = 1 << 16;

/// A pulse speed this far (relative) from `--rpm` or the file's speed is
/// an error: one of them is wrong (INTERFACE.md, "Hostile input").
const SPEED_DISAGREES: f64 = 0.1;

/// Two speeds this close (relative) are the same speed: no note.
const SAME_SPEED: f64 = 1e-9;

/// A revolution at least this much longer or shorter than the one before
/// is a missed or an extra pulse.
const REV_JUMP: f64 = 0.3;

/// A cycle being assembled.
struct Building {
    /// Cycle index from the first firing TDC (0-based).
    index: i64,
    trace: Trace,
    line: usize,
    /// It began at its firing TDC (pulse mode), not midway.
    from_start: bool,
    /// Pulse mode: the time (s) and angle (deg) of its first and last
    /// samples, for its speed.
    span: Option<((f64, f64), (f64, f64))>,
}

impl Building {
    fn new(index: i64, line: usize, capacity: usize, from_start: bool) -> Self {
        Self {
            index,
            trace: Trace {
                cycle: index + 1,
                cylinder: 0,
                angle_deg: Vec::with_capacity(capacity),
                values: Vec::with_capacity(capacity),
                rpm: None,
            },
            line,
            from_start,
            span: None,
        }
    }

    /// Notes a sample at time `t` (s), angle `a` (deg) for the speed.
    fn timed(&mut self, t: f64, a: f64) {
        let first = self.span.map_or((t, a), |s| s.0);
        self.span = Some((first, (t, a)));
    }

    /// Its speed (rpm): the angle its samples cover over their time.
    fn rpm(&self) -> Option<f64> {
        let ((t0, a0), (t1, a1)) = self.span?;
        let rpm = (a1 - a0) / (t1 - t0) / 6.0;
        (t1 > t0 && rpm.is_finite() && rpm > 0.0).then_some(rpm)
    }
}

struct Rev {
    /// Its pulse count from the first pulse (0-based).
    k: i64,
    t0: f64,
    t1: f64,
    samples: Vec<(f64, f64)>,
    line: usize,
}

enum Mode {
    /// From the TDC pulse column.
    Pulse {
        col: usize,
        threshold: Option<f64>,
        probe: Vec<(f64, f64, f64, usize)>,
        prev: Option<(f64, f64)>,
        /// The last pulse's time and pulse count.
        last_edge: Option<(f64, i64)>,
        rev: Vec<(f64, f64)>,
        rev_line: usize,
        /// Revolutions held until the firing pulse is known.
        held: Vec<Rev>,
        /// Which pulse parity is firing TDC (four-stroke).
        parity: Option<i64>,
        speeds: (f64, f64, f64, usize),
        before_first: usize,
    },
    /// From a constant speed: firing TDC at `t0` (s), `deg_per_s`.
    Clock { t0: f64, deg_per_s: f64 },
}

/// A time record being read.
pub(crate) struct TimeRecord {
    t_col: usize,
    t_scale: f64,
    p_col: usize,
    p_scale: f64,
    offset: f64,
    cycle_deg: f64,
    tdc_deg: Option<f64>,
    mode: Mode,
    last_t: Option<f64>,
    /// The cycle being assembled.
    cur: Option<Building>,
    complete: usize,
    partial: usize,
    /// Clock mode: the angle step between the first samples (deg).
    step_deg: f64,
    /// Pulse mode: the angle (from firing TDC) the placed revolutions reach.
    reach: f64,
    /// Samples in the last whole cycle: the next one's capacity.
    last_len: usize,
    /// The first sample's time (s).
    first_t: Option<f64>,
    /// The speed the file (`# rpm` line or banner) gives, and which.
    file_rpm: Option<(f64, &'static str)>,
    /// `--rpm`.
    flag_rpm: Option<f64>,
    /// The `tdc` column (0-based), for messages.
    tdc_col: Option<usize>,
}

impl TimeRecord {
    pub(crate) fn new(
        roles: &Roles,
        opts: &ParseOptions,
        rpm: Option<(f64, &'static str)>,
        line: usize,
    ) -> Result<Self, IngestError> {
        let Axis::Time(t_scale) = roles.axis else {
            return Err(IngestError::Data(
                "a time record needs a time column".into(),
            ));
        };
        if roles.quantity != Quantity::Pressure {
            return Err(at(line, None, "a time record holds pressure, not torque"));
        }
        let v = roles.values[0];
        let (p_scale, offset) = value_scale(roles, v.scale, opts, line)?;
        let mode = match (roles.tdc, opts.tdc_time) {
            (Some(col), _) => Mode::Pulse {
                col,
                threshold: None,
                probe: Vec::new(),
                prev: None,
                last_edge: None,
                rev: Vec::new(),
                rev_line: line,
                held: Vec::new(),
                parity: if opts.cycle_deg < 400.0 || opts.tdc_given {
                    Some(0)
                } else {
                    None
                },
                speeds: (f64::INFINITY, 0.0, 0.0, 0),
                before_first: 0,
            },
            (None, Some(t)) => {
                let Some(rpm) = opts.rpm.or(rpm.map(|r| r.0)) else {
                    return Err(at(
                        line,
                        Some(roles.x + 1),
                        "a time record with --tdc-time needs the speed: --rpm N (or a `# rpm = N` line)",
                    ));
                };
                Mode::Clock {
                    t0: t,
                    deg_per_s: rpm * 6.0,
                }
            }
            (None, None) => {
                return Err(at(
                    line,
                    Some(roles.x + 1),
                    "a time record needs the crank angle: a `tdc` column (a pulse per revolution), or --rpm N and --tdc-time T (the time of a firing TDC, in seconds)",
                ));
            }
        };
        Ok(Self {
            t_col: roles.x,
            t_scale,
            p_col: v.col,
            p_scale,
            offset,
            cycle_deg: opts.cycle_deg,
            tdc_deg: opts.tdc_given.then_some(opts.tdc_deg),
            mode,
            last_t: None,
            cur: None,
            complete: 0,
            partial: 0,
            step_deg: 0.0,
            reach: f64::NEG_INFINITY,
            last_len: 1024,
            first_t: None,
            file_rpm: rpm,
            flag_rpm: opts.rpm,
            tdc_col: roles.tdc,
        })
    }

    pub(crate) fn row<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        cells: &impl Cells,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let t = cells.number(self.t_col, line)? * self.t_scale;
        let p = cells.number(self.p_col, line)? * self.p_scale + self.offset;
        if let Some(was) = self.last_t
            && t <= was
        {
            return Err(at(
                line,
                Some(self.t_col + 1),
                format!(
                    "time {} does not rise after {}: a time record's samples must be in time order",
                    shown_number(t / self.t_scale),
                    shown_number(was / self.t_scale)
                ),
            ));
        }
        self.last_t = Some(t);
        if self.first_t.is_none() {
            self.first_t = Some(t);
            if let Mode::Clock { t0, .. } = self.mode
                && t0 < t
            {
                return Err(at(
                    line,
                    Some(self.t_col + 1),
                    format!(
                        "--tdc-time {} s is before the record, which starts at {} s: T must be the time of a firing TDC within the record",
                        enginedyn_numerics::format::human(t0),
                        enginedyn_numerics::format::human(t)
                    ),
                ));
            }
        }
        match &mut self.mode {
            Mode::Clock { t0, deg_per_s } => {
                let a = (t - *t0) * *deg_per_s - self.tdc_deg.unwrap_or(0.0);
                self.clock_sample(a, p, line, out)
            }
            Mode::Pulse {
                col,
                threshold,
                probe,
                ..
            } => {
                let pulse = cells.number(*col, line)?;
                match threshold {
                    Some(_) => self.pulse_sample(t, p, pulse, line, out),
                    None => {
                        probe.push((t, p, pulse, line));
                        if probe.len() >= PROBE {
                            self.settle(out)?;
                        }
                        Ok(())
                    }
                }
            }
        }
    }

    /// Finds the pulse's half-way level from the held samples, then reads them.
    fn settle<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let Mode::Pulse {
            threshold,
            probe,
            col,
            ..
        } = &mut self.mode
        else {
            return Ok(());
        };
        let held = std::mem::take(probe);
        let (lo, hi) = held
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), s| {
                (l.min(s.2), h.max(s.2))
            });
        if !(hi - lo > 1e-9 * hi.abs().max(lo.abs()).max(1e-300)) {
            return Err(IngestError::At {
                line: held.first().map_or(1, |s| s.3),
                column: Some(*col + 1),
                message: format!(
                    "the TDC pulse column is constant over the first {} samples: no pulse to take the angle from",
                    held.len()
                ),
            });
        }
        *threshold = Some(0.5 * (lo + hi));
        for (t, p, pulse, line) in held {
            self.pulse_sample(t, p, pulse, line, out)?;
        }
        Ok(())
    }

    fn pulse_sample<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        t: f64,
        p: f64,
        pulse: f64,
        line: usize,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let Mode::Pulse {
            col,
            threshold,
            prev,
            last_edge,
            rev,
            rev_line,
            speeds,
            before_first,
            ..
        } = &mut self.mode
        else {
            return Ok(());
        };
        let thr = threshold.unwrap_or(0.0);
        let mut finished: Option<Rev> = None;
        if let Some((tp, vp)) = *prev
            && vp < thr
            && pulse >= thr
        {
            // The pulse rises through half its range between the samples.
            let te = tp + (thr - vp) / (pulse - vp) * (t - tp);
            match *last_edge {
                Some((t0, k)) => {
                    let d = te - t0;
                    if speeds.3 > 0 {
                        let mean = (speeds.2 / speeds.3 as f64).recip();
                        if (d - mean).abs() > REV_JUMP * mean {
                            return Err(at(
                                line,
                                None,
                                format!(
                                    "this revolution lasts {} s, the ones before {} s: a missed or an extra TDC pulse",
                                    enginedyn_numerics::format::sig(d, 4),
                                    enginedyn_numerics::format::sig(mean, 4)
                                ),
                            ));
                        }
                    }
                    let rpm = 60.0 / d;
                    if !(enginedyn_kinematics::MIN_RPM..=enginedyn_kinematics::MAX_RPM)
                        .contains(&rpm)
                    {
                        return Err(at(
                            line,
                            Some(*col + 1),
                            format!(
                                "the `tdc` column's pulses are {} s apart: {} rpm, outside the engine speed bound (0.001 to 100000 rpm); a `tdc` column holds one pulse a revolution (a crank encoder or a tooth wheel is another signal)",
                                enginedyn_numerics::format::sig(d, 4),
                                enginedyn_numerics::format::sig(rpm, 4)
                            ),
                        ));
                    }
                    speeds.0 = speeds.0.min(rpm);
                    speeds.1 = speeds.1.max(rpm);
                    speeds.2 += 1.0 / d;
                    speeds.3 += 1;
                    finished = Some(Rev {
                        k,
                        t0,
                        t1: te,
                        samples: std::mem::take(rev),
                        line: *rev_line,
                    });
                    *last_edge = Some((te, k + 1));
                }
                None => *last_edge = Some((te, 0)),
            }
            *rev_line = line;
        }
        *prev = Some((t, pulse));
        if last_edge.is_some() {
            rev.push((t, p));
        } else {
            *before_first += 1;
        }
        match finished {
            Some(r) => self.revolution(r, out),
            None => Ok(()),
        }
    }

    /// A whole revolution: held until the firing pulse is known, then placed.
    fn revolution<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        r: Rev,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let Mode::Pulse { held, parity, .. } = &mut self.mode else {
            return Ok(());
        };
        if let Some(par) = *parity {
            return self.place(r, par, out);
        }
        held.push(r);
        if held.len() >= 4 {
            self.decide(out)?;
        }
        Ok(())
    }

    /// Which pulses are firing TDC: those after which the pressure over the
    /// next 90° is higher on average.
    fn decide<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let Mode::Pulse { held, parity, .. } = &mut self.mode else {
            return Ok(());
        };
        let revs = std::mem::take(held);
        let mut score = [0.0f64; 2];
        for r in &revs {
            let quarter = r.t0 + 0.25 * (r.t1 - r.t0);
            let (s, n) = r
                .samples
                .iter()
                .filter(|(t, _)| *t < quarter)
                .fold((0.0, 0usize), |(s, n), (_, p)| (s + p, n + 1));
            if n > 0 {
                score[(r.k % 2) as usize] += s / n as f64;
            }
        }
        let par = if score[1] > score[0] { 1 } else { 0 };
        *parity = Some(par);
        for r in revs {
            self.place(r, par, out)?;
        }
        Ok(())
    }

    /// Puts a revolution's samples on crank angles and into its cycle.
    fn place<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        r: Rev,
        parity: i64,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        // The revolution's first angle from firing TDC: the pulses are 360°
        // apart; --tdc-deg may put firing TDC anywhere between them.
        let start = match self.tdc_deg {
            Some(x) => 360.0 * r.k as f64 - x,
            None => 360.0 * (r.k - parity) as f64,
        };
        let dur = r.t1 - r.t0;
        for (t, p) in r.samples {
            let a = start + 360.0 * (t - r.t0) / dur;
            let c = (a / self.cycle_deg + 1e-12).floor() as i64;
            if self.cur.as_ref().is_none_or(|b| b.index != c) {
                // A cycle is whole from its start when an earlier revolution
                // was placed, or this one begins at or before it.
                let from_start = self.cur.is_some() || start <= c as f64 * self.cycle_deg + 1e-6;
                self.close_cycle(out, true)?;
                self.cur = Some(Building::new(c, r.line, self.last_len, from_start));
            }
            if let Some(b) = self.cur.as_mut() {
                b.trace.angle_deg.push(a - b.index as f64 * self.cycle_deg);
                b.trace.values.push(p);
                b.timed(t, a);
            }
        }
        self.reach = start + 360.0;
        Ok(())
    }

    /// Hands the cycle being assembled on when it is whole: it began at its
    /// firing TDC and the record `reached` its end.
    fn close_cycle<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
        reached: bool,
    ) -> Result<(), IngestError> {
        if let Some(mut b) = self.cur.take() {
            if b.from_start && reached {
                self.complete += 1;
                self.last_len = b.trace.angle_deg.len();
                b.trace.rpm = b.rpm();
                out.trace(b.trace, b.line, Quantity::Pressure, false, 0)?;
            } else {
                self.partial += 1;
            }
        }
        Ok(())
    }

    /// Clock mode: the cycle being assembled is whole when its samples
    /// reach both its ends (within two sample steps).
    fn close_clock<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if let Some(b) = self.cur.take() {
            let first = b.trace.angle_deg.first().copied().unwrap_or(0.0);
            let last = b.trace.angle_deg.last().copied().unwrap_or(0.0);
            let step = self.step_deg.max(1e-9);
            if first <= 2.0 * step && self.cycle_deg - last <= 2.0 * step {
                self.complete += 1;
                out.trace(b.trace, b.line, Quantity::Pressure, false, 0)?;
            } else {
                self.partial += 1;
            }
        }
        Ok(())
    }

    /// Clock mode: a sample at angle `a` from firing TDC.
    fn clock_sample<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        a: f64,
        p: f64,
        line: usize,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let c = (a / self.cycle_deg).floor() as i64;
        let within = a - c as f64 * self.cycle_deg;
        if self.cur.as_ref().is_none_or(|b| b.index != c) {
            self.close_clock(out)?;
            self.cur = Some(Building::new(c, line, 0, true));
        }
        if let Some(b) = self.cur.as_mut() {
            if let Some(&prev) = b.trace.angle_deg.last()
                && self.step_deg == 0.0
            {
                self.step_deg = within - prev;
            }
            b.trace.angle_deg.push(within);
            b.trace.values.push(p);
        }
        Ok(())
    }

    pub(crate) fn end<F: FnMut(Streamed) -> Result<(), IngestError>>(
        mut self,
        out: &mut Emitter<'_, F>,
        head: &mut Header,
    ) -> Result<(), IngestError> {
        if let Mode::Pulse {
            threshold: None, ..
        } = self.mode
        {
            self.settle(out)?;
        }
        if let Mode::Pulse {
            held, parity: None, ..
        } = &self.mode
            && !held.is_empty()
        {
            self.decide(out)?;
        }
        if let (Mode::Clock { t0, .. }, Some(first), Some(last)) =
            (&self.mode, self.first_t, self.last_t)
            && *t0 > last
        {
            return Err(IngestError::Data(format!(
                "--tdc-time {} s is after the record, which spans {} to {} s: T must be the time of a firing TDC within the record",
                enginedyn_numerics::format::human(*t0),
                enginedyn_numerics::format::human(first),
                enginedyn_numerics::format::human(last)
            )));
        }
        let fmt = |x: f64, d: usize| enginedyn_numerics::format::trimmed(x, d);
        let (mut said, speed) = match &self.mode {
            Mode::Pulse {
                speeds,
                parity,
                before_first,
                ..
            } => {
                if speeds.3 == 0 {
                    return Err(IngestError::Data(
                        "time record: fewer than two TDC pulses, so no revolution to take the speed from".into(),
                    ));
                }
                let mean = speeds.2 / speeds.3 as f64 * 60.0;
                let mut said = format!(
                    "time record: the angle from {} TDC pulses, the speed revolution by revolution ({} to {} rpm, mean {}); firing TDC {}",
                    speeds.3 + 1,
                    fmt(speeds.0, 1),
                    fmt(speeds.1, 1),
                    fmt(mean, 1),
                    match (self.tdc_deg, self.cycle_deg < 400.0) {
                        (Some(x), _) => format!("{}° after the first pulse (--tdc-deg)", fmt(x, 3)),
                        (None, true) => "at every pulse (two-stroke)".to_string(),
                        (None, false) => format!(
                            "at every second pulse from pulse {}, the one the pressure peak follows",
                            parity.unwrap_or(0) + 1
                        ),
                    }
                );
                if *before_first > 0 {
                    said.push_str("; samples before the first pulse left out");
                }
                (said, Some(mean))
            }
            Mode::Clock { t0, deg_per_s } => (
                format!(
                    "time record: the angle from a constant {} rpm and firing TDC at t = {} s",
                    fmt(deg_per_s / 6.0, 3),
                    enginedyn_numerics::format::sig(*t0, 6)
                ),
                None,
            ),
        };
        match self.mode {
            Mode::Pulse { .. } => {
                // The last cycle is whole when the last revolution reached its end.
                let end = self
                    .cur
                    .as_ref()
                    .map_or(f64::INFINITY, |b| (b.index + 1) as f64 * self.cycle_deg);
                let reached = self.reach >= end - 1e-6;
                self.close_cycle(out, reached)?
            }
            Mode::Clock { .. } => self.close_clock(out)?,
        }
        if self.complete == 0 {
            return Err(IngestError::Data(format!(
                "time record: no whole {}° cycle between firing TDCs ({said})",
                fmt(self.cycle_deg, 0)
            )));
        }
        said.push_str(&format!("; {} whole cycles", self.complete));
        if self.partial > 0 {
            said.push_str(&format!(
                ", {} partial ones at the ends left out",
                self.partial
            ));
        }
        head.notes.push(said);
        if let Some(mean) = speed {
            let col = self
                .tdc_col
                .map_or(String::new(), |c| format!(" (column {})", c + 1));
            let given = self
                .flag_rpm
                .map(|r| (r, "--rpm"))
                .into_iter()
                .chain(self.file_rpm);
            for (r, source) in given {
                let off = (r - mean).abs() / mean;
                if off > SPEED_DISAGREES {
                    return Err(IngestError::Data(format!(
                        "the `tdc` column{col} gives {} rpm (a pulse every {} s on average), {source} {} rpm: {:.0} % apart; is the speed or the pulse column wrong?",
                        fmt(mean, 1),
                        enginedyn_numerics::format::sig(60.0 / mean, 4),
                        fmt(r, 1),
                        100.0 * off
                    )));
                }
                if off > SAME_SPEED {
                    head.notes.push(format!(
                        "{source} says {} rpm, the `tdc` column's pulses {} rpm",
                        fmt(r, 1),
                        fmt(mean, 1)
                    ));
                }
            }
            if head.rpm.is_none() {
                head.rpm = Some(mean);
            }
        }
        Ok(())
    }
}
