//! Cycles from angled samples: every angle source (pulse, encoder, wheel)
//! hands its samples here as a revolution counted from its reference TDC
//! and the degrees within it. On a four-stroke the firing TDC is decided
//! once: by `--tdc-deg`, a `cam` pulse, or the pressure-peak rule (of the
//! two TDCs of a cycle, the one after which the mean pressure over the next
//! 90° is higher: expansion, not intake), the samples held meanwhile (four
//! revolutions at most). A cycle is handed on when it is whole.

use crate::emit::Emitter;
use crate::error::{IngestError, at};
use crate::plausible::Recurrence;
use crate::{Quantity, Streamed, Trace};
use std::collections::VecDeque;

/// Revolutions held until the pressure-peak rule decides the firing TDC.
const DECIDE_REVS: i64 = 4;

/// The other cylinders of a time record with one pressure column per
/// cylinder: every cylinder lies on the angle that the first one's (the
/// reference cylinder's) samples are given, so each sample's other values
/// wait here until the sample is placed (in line order) and then go into
/// the cycle beside it.
#[derive(Debug)]
pub(super) struct Others {
    /// The cylinder numbers: the reference cylinder's, then the others'
    /// (empty for one pressure column: its traces are every cylinder's).
    pub cylinders: Vec<i64>,
    /// Each cylinder's index among the file's value columns (for the
    /// column an error names).
    pub columns: Vec<usize>,
    lines: VecDeque<usize>,
    values: VecDeque<f64>,
    /// The most samples that may wait ([`MAX_WAITING`]).
    cap: usize,
}

/// The most samples whose other cylinders' values may wait for the crank
/// reference to place them (a revolution and the firing-TDC decision's
/// four take far fewer): memory stays bounded (128 MiB for four
/// cylinders) when a record's reference never comes.
pub(super) const MAX_WAITING: usize = 1 << 22;

impl Default for Others {
    fn default() -> Self {
        Self {
            cylinders: Vec::new(),
            columns: Vec::new(),
            lines: VecDeque::new(),
            values: VecDeque::new(),
            cap: MAX_WAITING,
        }
    }
}

impl Others {
    /// Values per sample.
    fn n(&self) -> usize {
        self.cylinders.len().saturating_sub(1)
    }

    /// The other cylinders' values of the sample on `line`; an error when
    /// more than [`MAX_WAITING`] samples wait.
    pub(super) fn hold(
        &mut self,
        line: usize,
        values: impl Iterator<Item = f64>,
    ) -> Result<(), IngestError> {
        if self.lines.len() >= self.cap {
            return Err(at(
                line,
                None,
                format!(
                    "the crank reference placed none of the last {} samples on an angle: a record with one pressure column per cylinder holds the other cylinders' samples until it does, and no more than that many",
                    self.cap
                ),
            ));
        }
        self.lines.push_back(line);
        self.values.extend(values);
        Ok(())
    }

    /// Puts the other values of the sample on `line` into `b`, beside it;
    /// drops those of samples before it that no cycle took.
    pub(super) fn place(&mut self, line: usize, b: &mut Building) {
        let n = self.n();
        if n == 0 {
            return;
        }
        while self.lines.front().is_some_and(|&l| l < line) {
            self.lines.pop_front();
            self.values.drain(..n);
        }
        let here = self.lines.front() == Some(&line);
        for (k, o) in b.others.iter_mut().enumerate() {
            // Every sample is held before it is placed: NaN (refused by the
            // trace's checks) only if that ever failed.
            o.push(if here { self.values[k] } else { f64::NAN });
        }
        if here {
            self.lines.pop_front();
            self.values.drain(..n);
        }
    }

    /// Hands on a whole cycle: one trace, or one per cylinder.
    pub(super) fn emit<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &self,
        b: Building,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let Building {
            mut trace,
            others,
            line,
            ..
        } = b;
        if self.cylinders.is_empty() {
            return out.trace(trace, line, Quantity::Pressure, false, 0);
        }
        let rest: Vec<Trace> = others
            .into_iter()
            .zip(&self.cylinders[1..])
            .map(|(values, &cylinder)| Trace {
                cycle: trace.cycle,
                cylinder,
                angle_deg: trace.angle_deg.clone(),
                values,
                rpm: trace.rpm,
            })
            .collect();
        trace.cylinder = self.cylinders[0];
        out.trace(trace, line, Quantity::Pressure, false, self.columns[0])?;
        for (t, &col) in rest.into_iter().zip(&self.columns[1..]) {
            out.trace(t, line, Quantity::Pressure, false, col)?;
        }
        Ok(())
    }
}

/// A cycle being assembled.
pub(super) struct Building {
    /// The window's index: its firing TDC `index` cycles after the first.
    pub index: i64,
    pub trace: Trace,
    /// The other cylinders' values at the same angles ([`Others`]).
    pub others: Vec<Vec<f64>>,
    pub line: usize,
    /// It began where its window begins, not midway.
    pub from_start: bool,
    /// Where the source began the revolution of its first sample (deg from
    /// its firing TDC; `-inf` when not known): a partial first window that
    /// began at or before its firing TDC may join the next ([`one_cycle`]).
    pub since: f64,
    /// The time (s) and angle (deg) of its first and last samples, for its
    /// speed.
    span: Option<((f64, f64), (f64, f64))>,
}

impl Building {
    pub(super) fn new(
        index: i64,
        line: usize,
        capacity: usize,
        from_start: bool,
        others: &Others,
    ) -> Self {
        Self {
            index,
            trace: Trace {
                cycle: index + 1,
                cylinder: 0,
                angle_deg: Vec::with_capacity(capacity),
                values: Vec::with_capacity(capacity),
                rpm: None,
            },
            // Each with the capacity (`vec![v; n]` clones would not keep it).
            others: (0..others.n())
                .map(|_| Vec::with_capacity(capacity))
                .collect(),
            line,
            from_start,
            since: f64::NEG_INFINITY,
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

/// A record that holds no whole window but one whole cycle from firing TDC
/// to firing TDC (a record of one cycle, begun at or just before its
/// firing TDC): the partial window `first` (from its firing TDC on) and the
/// one after it, `next` (up to its firing TDC), joined into that cycle,
/// read as a one-cycle diagram is. The callers have checked that `first`
/// begins at its firing TDC and `next` reaches its own; `None` when they
/// are not neighbours.
pub(super) fn one_cycle(first: Building, next: Building, cycle: f64) -> Option<Building> {
    if next.index != first.index + 1 {
        return None;
    }
    let mut b = first;
    let k = b.trace.angle_deg.partition_point(|&a| a < -1e-9);
    b.trace.angle_deg.drain(..k);
    b.trace.values.drain(..k);
    for o in &mut b.others {
        o.drain(..k.min(o.len()));
    }
    let m = next.trace.angle_deg.partition_point(|&a| a < -1e-9);
    b.trace
        .angle_deg
        .extend(next.trace.angle_deg[..m].iter().map(|a| a + cycle));
    b.trace.values.extend_from_slice(&next.trace.values[..m]);
    for (o, n) in b.others.iter_mut().zip(&next.others) {
        o.extend_from_slice(&n[..m.min(n.len())]);
    }
    if let (Some((s0, _)), Some((_, e1))) = (b.span, next.span) {
        b.span = Some((s0, e1));
    }
    b.from_start = true;
    Some(b)
}

/// How the firing TDC is found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Firing {
    /// Known from the start: two-stroke, `--tdc-deg`, `--tdc-time`.
    Given,
    /// The pressure-peak rule.
    Pressure,
    /// The `cam` column.
    Cam,
}

/// The cycles of a time record being assembled.
pub(super) struct Cycles {
    cycle_deg: f64,
    tdc_deg: Option<f64>,
    /// Which revolutions (their count from the reference, mod 2) begin at
    /// firing TDC, once known.
    pub parity: Option<i64>,
    pub firing: Firing,
    /// Samples held until the firing TDC is known: revolution, degrees
    /// within it, value, line.
    held: Vec<(i64, f64, f64, usize, f64)>,
    cur: Option<Building>,
    pub complete: usize,
    pub partial: usize,
    /// The furthest angle the source reached: revolution, degrees within.
    reach: Option<(i64, f64)>,
    /// Samples in the last whole cycle: the next one's capacity.
    last_len: usize,
    /// A crank signal's angle: its pressure peaks must recur once a cycle
    /// (the plausibility pass), with the flag, the count and what it
    /// counts that the error names.
    pub recur: Option<(Recurrence, &'static str, f64, &'static str)>,
    /// A cycle's error held while the recurrence is unknown: a wrong count
    /// makes a cycle of no cylinder's pressure, and the count is the cause.
    deferred: Option<IngestError>,
    /// The other cylinders' values.
    pub others: Others,
    /// The first partial window, kept while no cycle is whole
    /// ([`one_cycle`]).
    first_part: Option<Building>,
    /// The record held no whole window: its one cycle from firing TDC to
    /// firing TDC was read ([`one_cycle`]).
    pub joined: bool,
}

impl Cycles {
    pub(super) fn new(cycle_deg: f64, tdc_deg: Option<f64>, firing: Firing) -> Self {
        let given = cycle_deg < 400.0 || tdc_deg.is_some() || firing == Firing::Given;
        Self {
            cycle_deg,
            tdc_deg,
            parity: given.then_some(0),
            firing: if given { Firing::Given } else { firing },
            held: Vec::new(),
            cur: None,
            complete: 0,
            partial: 0,
            reach: None,
            last_len: 1024,
            recur: None,
            deferred: None,
            others: Others::default(),
            first_part: None,
            joined: false,
        }
    }

    /// The angle (deg from the first firing TDC) where revolution `k` begins.
    fn start(&self, k: i64, parity: i64) -> f64 {
        match self.tdc_deg {
            Some(x) => 360.0 * k as f64 - x,
            None => 360.0 * (k - parity) as f64,
        }
    }

    /// A sample `within` degrees into revolution `k` from the reference,
    /// taken at time `t` (s).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn push<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        k: i64,
        within: f64,
        p: f64,
        line: usize,
        t: f64,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        match self.parity {
            Some(par) => self.place(k, within, p, line, t, par, out),
            None => {
                if self.held.first().is_some_and(|h| k >= h.0 + DECIDE_REVS) {
                    self.decide(line, out)?;
                    return self.push(k, within, p, line, t, out);
                }
                self.held.push((k, within, p, line, t));
                Ok(())
            }
        }
    }

    /// The source has reached `within` degrees into revolution `k`: a whole
    /// cycle ending there is complete; after four revolutions the firing
    /// TDC is decided.
    pub(super) fn reached<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        k: i64,
        within: f64,
        line: usize,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        self.reach = Some((k, within));
        if self.parity.is_none()
            && let Some(h) = self.held.first()
            && k as f64 + within / 360.0 >= (h.0 + DECIDE_REVS) as f64
        {
            self.decide(line, out)?;
        }
        Ok(())
    }

    /// A `cam` pulse says revolutions of parity `par` begin at firing TDC.
    pub(super) fn cam<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        par: i64,
        line: usize,
        col: usize,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if self.firing != Firing::Cam {
            return Ok(());
        }
        match self.parity {
            Some(was) if was != par => Err(at(
                line,
                Some(col + 1),
                "this `cam` pulse falls in the other revolution than the ones before: a `cam` column holds one pulse a cycle (every 720°)",
            )),
            Some(_) => Ok(()),
            None => {
                self.parity = Some(par);
                for (k, w, p, l, t) in std::mem::take(&mut self.held) {
                    self.place(k, w, p, l, t, par, out)?;
                }
                Ok(())
            }
        }
    }

    /// Which revolutions begin at firing TDC: those after which the
    /// pressure over the next 90° is higher on average.
    fn decide<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let held = std::mem::take(&mut self.held);
        if self.firing == Firing::Cam {
            return Err(at(
                line,
                None,
                format!(
                    "no `cam` pulse in the first {DECIDE_REVS} revolutions: a `cam` column holds one pulse a cycle"
                ),
            ));
        }
        let mut score = [0.0f64; 2];
        let mut i = 0;
        while i < held.len() {
            let k = held[i].0;
            let (mut s, mut n) = (0.0, 0usize);
            while i < held.len() && held[i].0 == k {
                if held[i].1 < 90.0 {
                    s += held[i].2;
                    n += 1;
                }
                i += 1;
            }
            if n > 0 {
                score[k.rem_euclid(2) as usize] += s / n as f64;
            }
        }
        let par = if score[1] > score[0] { 1 } else { 0 };
        self.parity = Some(par);
        for (k, w, p, l, t) in held {
            self.place(k, w, p, l, t, par, out)?;
        }
        Ok(())
    }

    /// Puts a sample on its crank angle and into its cycle.
    #[allow(clippy::too_many_arguments)]
    fn place<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        k: i64,
        within: f64,
        p: f64,
        line: usize,
        t: f64,
        parity: i64,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        // The revolution's first angle from firing TDC: the TDCs are 360°
        // apart; --tdc-deg may put firing TDC anywhere between them.
        let start = self.start(k, parity);
        let a = start + within;
        if let Some(r) = self.recur.as_mut() {
            r.0.sample(a, p);
        }
        // The window around its firing TDC (the one rule, `trace::window`).
        let (c, begins) = crate::trace::window(a, self.cycle_deg);
        if self.cur.as_ref().is_none_or(|b| b.index != c) {
            // A cycle is whole from its start when an earlier sample was
            // placed, or this revolution begins at or before it.
            let from_start = self.cur.is_some() || start <= begins + 1e-6;
            self.close(out, true)?;
            let mut b = Building::new(c, line, self.last_len, from_start, &self.others);
            b.since = start - c as f64 * self.cycle_deg;
            self.cur = Some(b);
        }
        if let Some(b) = self.cur.as_mut() {
            b.trace.angle_deg.push(a - b.index as f64 * self.cycle_deg);
            b.trace.values.push(p);
            self.others.place(line, b);
            b.timed(t, a);
        }
        Ok(())
    }

    /// Hands the cycle being assembled on when it is whole: it began at its
    /// window's start (the gas-exchange TDC before its firing TDC, BDC on a
    /// two-stroke) and the record `reached` its end.
    fn close<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
        reached: bool,
    ) -> Result<(), IngestError> {
        if let Some(mut b) = self.cur.take() {
            if self.deferred.is_some() {
                return Ok(());
            }
            if b.from_start && reached {
                self.complete += 1;
                self.last_len = b.trace.angle_deg.len();
                b.trace.rpm = b.rpm();
                if let Err(e) = self.others.emit(b, out) {
                    if self.recur.is_none() {
                        return Err(e);
                    }
                    self.deferred = Some(e);
                }
            } else {
                self.partial += 1;
                if self.complete == 0 && self.first_part.is_none() {
                    self.first_part = Some(b);
                }
            }
        }
        Ok(())
    }

    /// The end of the record: the firing TDC decided from what is held, the
    /// last cycle handed on when the source reached its end.
    pub(super) fn finish<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if self.parity.is_none() && !self.held.is_empty() {
            self.decide(line, out)?;
        }
        let par = self.parity.unwrap_or(0);
        let reach = self
            .reach
            .map_or(f64::NEG_INFINITY, |(k, w)| self.start(k, par) + w);
        // Where the last window ends: its firing TDC and half a cycle.
        let end = self
            .cur
            .as_ref()
            .map_or(f64::INFINITY, |b| (b.index as f64 + 0.5) * self.cycle_deg);
        let whole = reach >= end - 1e-6;
        // No whole window: the one cycle from firing TDC to firing TDC, when
        // the record holds it.
        let tdc = self
            .cur
            .as_ref()
            .map_or(f64::INFINITY, |b| b.index as f64 * self.cycle_deg);
        if !whole
            && self.complete == 0
            && self.deferred.is_none()
            && reach >= tdc - 1e-6
            && self.first_part.as_ref().is_some_and(|f| f.since <= 1e-6)
            && let (Some(f), Some(e)) = (self.first_part.take(), self.cur.take())
        {
            match one_cycle(f, e, self.cycle_deg) {
                Some(b) => {
                    self.joined = true;
                    self.partial -= 1;
                    self.cur = Some(b);
                    self.close(out, true)?;
                }
                None => self.partial += 1,
            }
        } else {
            self.close(out, whole)?;
        }
        if let Some((r, flag, count, what)) = &self.recur {
            r.check(self.cycle_deg, flag, *count, what)?;
        }
        match self.deferred.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The other cylinders' values go into the cycle beside their sample,
    /// those of samples no cycle took are dropped, and the wait is bounded.
    #[test]
    fn others_ride_along_and_wait_bounded() {
        let mut o = Others {
            cylinders: vec![1, 2, 3],
            columns: vec![0, 1, 2],
            cap: 3,
            ..Others::default()
        };
        for line in 1..=3 {
            o.hold(line, [10.0 * line as f64, 100.0 * line as f64].into_iter())
                .unwrap();
        }
        let e = o.hold(4, [0.0, 0.0].into_iter()).unwrap_err().to_string();
        assert!(e.contains("none of the last 3 samples"), "{e}");
        let mut b = Building::new(0, 1, 4, true, &o);
        // Sample 1 was dropped by the source; 2 and 3 are placed.
        o.place(2, &mut b);
        o.place(3, &mut b);
        assert_eq!(b.others, vec![vec![20.0, 30.0], vec![200.0, 300.0]]);
        assert!(b.others.iter().all(|v| v.capacity() >= 4));
        // A sample never held (a bug) is NaN, refused by the trace's checks.
        o.place(9, &mut b);
        assert!(b.others[0][2].is_nan());
        o.hold(10, [1.0, 2.0].into_iter()).unwrap();
    }
}
