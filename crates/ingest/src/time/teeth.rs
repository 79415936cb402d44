//! The crank's own signals: an encoder's or a tooth wheel's edges, checked
//! period by period and numbered in tooth steps, the angle interpolated in
//! time between them. Shared by [`super::encoder`] and [`super::wheel`].
//!
//! A period is judged against its neighbours' median (the [`NEIGHBOURS`]
//! periods on each side, so an edge is numbered once that many more have
//! come): within 40 % it is one step; on a wheel, within 40 % of the gap's
//! M + 1 steps it is the gap; anything else is an edge missing or extra, an
//! error at the line of the edge that ends it (INTERFACE.md, "The crank's
//! own signals"). Memory is bounded: the samples since the last numbered
//! edge (a few teeth) and the periods around it.

use std::collections::VecDeque;

use super::PROBE;
use super::cycles::Cycles;
use super::edges::Rise;
use super::encoder::Encoder;
use super::wheel::Gaps;
use crate::Streamed;
use crate::emit::Emitter;
use crate::error::{IngestError, at};

/// Periods on each side a period is judged against.
pub(super) const NEIGHBOURS: usize = 3;

/// A period this far (relative) from its neighbours' median is an edge
/// missing or extra (INTERFACE.md).
pub(super) const PERIOD_OFF: f64 = 0.4;

/// Which signal numbers the edges.
pub(super) enum Kind {
    Encoder(Encoder),
    Wheel { gaps: Gaps, tdc_deg: f64 },
}

/// A mark in time placed on the angle when its edges are numbered.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Mark {
    Tdc,
    Cam,
}

/// The angle from an encoder or a tooth wheel.
pub(super) struct Crank {
    pub kind: Kind,
    /// The signal column (0-based), for messages.
    pub col: usize,
    /// The `cam` column (0-based).
    pub cam_col: Option<usize>,
    /// Degrees a step.
    step_deg: f64,
    /// Steps the wheel's gap spans (M + 1).
    gap_steps: Option<i64>,
    rise: Rise,
    tdc_rise: Option<Rise>,
    cam_rise: Option<Rise>,
    /// The last periods numbered, per step (s).
    before: VecDeque<f64>,
    /// Edges not yet numbered, after the last numbered one (time, line).
    edges: VecDeque<(f64, usize)>,
    /// The last numbered edge: time and position (steps from the first).
    last: Option<(f64, i64)>,
    /// Its line.
    last_line: usize,
    /// The last numbered edges (up to four): time, position, line.
    hist: VecDeque<(f64, i64, usize)>,
    /// The first numbered edge, for the mean speed.
    first: Option<(f64, i64)>,
    /// Samples after the last numbered edge: time, value, line.
    pending: VecDeque<(f64, f64, usize)>,
    /// Marks after the last numbered edge, in time order.
    marks: VecDeque<(f64, usize, Mark)>,
    /// The signal angle (deg from the first edge) of the reference TDC.
    pub reference: Option<f64>,
    /// Samples before the reference TDC, left out.
    pub before_first: usize,
    /// The slowest and fastest period's speed (rpm).
    pub speeds: (f64, f64),
    /// Edges read.
    pub edge_count: usize,
}

impl Crank {
    pub(super) fn new(kind: Kind, col: usize, cam_col: Option<usize>) -> Self {
        let (step_deg, gap_steps) = match &kind {
            Kind::Encoder(e) => (360.0 / f64::from(e.ppr), None),
            Kind::Wheel { gaps, .. } => (
                gaps.wheel.step_deg(),
                Some(i64::from(gaps.wheel.missing()) + 1),
            ),
        };
        let mut marks = VecDeque::new();
        if let Kind::Encoder(Encoder {
            tdc_time: Some(t0), ..
        }) = &kind
        {
            marks.push_back((*t0, 0, Mark::Tdc));
        }
        Self {
            kind,
            col,
            cam_col,
            step_deg,
            gap_steps,
            rise: Rise::new(0.0, 0.0),
            tdc_rise: None,
            cam_rise: None,
            before: VecDeque::with_capacity(NEIGHBOURS + 1),
            edges: VecDeque::with_capacity(NEIGHBOURS + 3),
            last: None,
            last_line: 0,
            hist: VecDeque::with_capacity(5),
            first: None,
            pending: VecDeque::new(),
            marks,
            reference: None,
            before_first: 0,
            speeds: (f64::INFINITY, 0.0),
            edge_count: 0,
        }
    }

    /// The ranges of the signal, the `tdc` pulse and the `cam`.
    pub(super) fn levels(
        &mut self,
        signal: (f64, f64),
        tdc: Option<(f64, f64)>,
        cam: Option<(f64, f64)>,
    ) {
        self.rise = Rise::new(signal.0, signal.1);
        self.tdc_rise = tdc.map(|(lo, hi)| Rise::new(lo, hi));
        self.cam_rise = cam.map(|(lo, hi)| Rise::new(lo, hi));
    }

    /// The mean speed (rpm) from the first to the last numbered edge.
    pub(super) fn mean_rpm(&self) -> Option<f64> {
        match (self.first, self.last) {
            (Some((t0, n0)), Some((t1, n1))) if n1 > n0 && t1 > t0 => {
                Some((n1 - n0) as f64 * self.step_deg / (t1 - t0) / 6.0)
            }
            _ => None,
        }
    }

    /// A sample: time, pressure, and the signals (crank, `tdc`, `cam`).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn sample<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        t: f64,
        p: f64,
        line: usize,
        sig: [f64; 3],
        cycles: &mut Cycles,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if let Some((te, l)) = self
            .tdc_rise
            .as_mut()
            .and_then(|r| r.sample(t, sig[1], line))
        {
            self.mark(te, l, Mark::Tdc);
        }
        if let Some((tc, l)) = self
            .cam_rise
            .as_mut()
            .and_then(|r| r.sample(t, sig[2], line))
        {
            self.mark(tc, l, Mark::Cam);
        }
        let edge = self.rise.sample(t, sig[0], line);
        if let Some((te, l)) = edge {
            self.edge_count += 1;
            self.edges.push_back((te, l));
        }
        if self.edges.is_empty() && self.last.is_none() {
            // Before the first edge: no angle, ever.
            self.before_first += 1;
        } else {
            self.pending.push_back((t, p, line));
            if self.pending.len() > PROBE {
                let from = self.pending.front().map_or(line, |s| s.2);
                return Err(at(
                    from,
                    Some(self.col + 1),
                    format!(
                        "no edge of the `{}` column for {} samples from this line on: the signal stopped, or it is no {}",
                        self.name(),
                        self.pending.len(),
                        self.name()
                    ),
                ));
            }
        }
        if edge.is_some() {
            self.number(false, cycles, out)?;
        }
        Ok(())
    }

    fn name(&self) -> &'static str {
        match self.kind {
            Kind::Encoder(_) => "encoder",
            Kind::Wheel { .. } => "wheel",
        }
    }

    /// A mark at time `t`, kept in time order.
    fn mark(&mut self, t: f64, line: usize, m: Mark) {
        let i = self
            .marks
            .iter()
            .rposition(|x| x.0 <= t)
            .map_or(0, |i| i + 1);
        self.marks.insert(i, (t, line, m));
    }

    /// Numbers every edge whose period has its neighbours (all of them at
    /// the end of the record, `flush`).
    fn number<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        flush: bool,
        cycles: &mut Cycles,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if self.last.is_none()
            && let Some(&(t0, l0)) = self.edges.front()
        {
            // The first edge: position 0. The samples before it have no angle.
            while self.pending.front().is_some_and(|s| s.0 < t0) {
                self.pending.pop_front();
                self.before_first += 1;
            }
            while self.marks.front().is_some_and(|m| m.0 < t0) {
                self.marks.pop_front();
            }
            self.last = Some((t0, 0));
            self.last_line = l0;
            self.hist.push_back((t0, 0, l0));
            self.first = self.last;
            self.edges.pop_front();
        }
        while self.edges.len() > NEIGHBOURS || (flush && !self.edges.is_empty()) {
            let Some((t0, n0)) = self.last else { break };
            let (t1, line) = self.edges[0];
            let d = t1 - t0;
            let mut near: Vec<f64> = self.before.iter().copied().collect();
            let mut prev = t1;
            for &(t, _) in self.edges.iter().skip(1).take(NEIGHBOURS) {
                near.push(t - prev);
                prev = t;
            }
            let steps = if near.len() >= 2 {
                near.sort_by(f64::total_cmp);
                let m = near.len() / 2;
                let median = if near.len() % 2 == 1 {
                    near[m]
                } else {
                    0.5 * (near[m - 1] + near[m])
                };
                self.judge(t0, d, median, line)?
            } else {
                1
            };
            self.before.push_back(d / steps as f64);
            if self.before.len() > NEIGHBOURS {
                self.before.pop_front();
            }
            self.edges.pop_front();
            self.numbered(t0, t1, n0 + steps, steps, line, cycles, out)?;
        }
        Ok(())
    }

    /// How many steps the period `d` from the last numbered edge (at `t0`)
    /// spans, against its neighbours' `median`; `line` is its closing
    /// edge's. An error names the line of the edge at fault: of a short
    /// period, the edge whose removal leaves the period nearest the median
    /// (the one before, or the closing one); of a long one, the first
    /// sample where the missing edge was due.
    fn judge(&self, t0: f64, d: f64, median: f64, line: usize) -> Result<i64, IngestError> {
        let r = d / median;
        if (r - 1.0).abs() <= PERIOD_OFF {
            return Ok(1);
        }
        if let Some(g) = self.gap_steps
            && (r / g as f64 - 1.0).abs() <= PERIOD_OFF
        {
            return Ok(g);
        }
        let (what, line) = if r < 1.0 {
            let prev = self.before.back().map(|p| d + p);
            let next = match (self.edges.front(), self.edges.get(1)) {
                (Some(a), Some(b)) => Some(d + b.0 - a.0),
                _ => None,
            };
            let off = |x: Option<f64>| x.map_or(f64::INFINITY, |x| (x - median).abs());
            let at_line = if off(prev) < off(next) {
                self.last_line
            } else {
                line
            };
            (
                "an extra edge (or noise crossing half the signal's range)".to_string(),
                at_line,
            )
        } else {
            let due = t0 + median;
            let at_line = self
                .pending
                .iter()
                .find(|s| s.0 >= due)
                .map_or(line, |s| s.2);
            (
                match &self.kind {
                    Kind::Wheel { gaps, .. } => format!(
                        "a missing edge, or a gap other than a {} wheel's ({} periods; --wheel)",
                        gaps.wheel,
                        gaps.wheel.missing() + 1
                    ),
                    Kind::Encoder(_) => "a missing edge".to_string(),
                },
                at_line,
            )
        };
        Err(at(
            line,
            Some(self.col + 1),
            format!(
                "the `{}` column's period from t = {} s to {} s is {} times its neighbours' median {} s (more than 40 % off): {what}",
                self.name(),
                enginedyn_numerics::format::sig(t0, 9),
                enginedyn_numerics::format::sig(t0 + d, 9),
                enginedyn_numerics::format::sig(r, 3),
                enginedyn_numerics::format::sig(median, 4)
            ),
        ))
    }

    /// An edge numbered: position `n1` at `t1`, `steps` after the one at
    /// `t0`. The samples and marks of the interval before the one it ends
    /// get their angles (an interval is placed once the edge after it is
    /// numbered: its angle is the cubic through the edges around it).
    #[allow(clippy::too_many_arguments)]
    fn numbered<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        t0: f64,
        t1: f64,
        n1: i64,
        steps: i64,
        line: usize,
        cycles: &mut Cycles,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if let Kind::Wheel { gaps, tdc_deg } = &mut self.kind
            && Some(steps) == self.gap_steps
        {
            gaps.gap(n1, line, self.col)?;
            if self.reference.is_none() {
                // The first tooth after the gap is the wheel's 0°.
                self.reference = Some(n1 as f64 * self.step_deg + *tdc_deg);
            }
        }
        let rpm = steps as f64 * self.step_deg / (t1 - t0) / 6.0;
        self.speeds = (self.speeds.0.min(rpm), self.speeds.1.max(rpm));
        self.last = Some((t1, n1));
        self.last_line = line;
        self.hist.push_back((t1, n1, line));
        if self.hist.len() > 4 {
            self.hist.pop_front();
        }
        if self.hist.len() >= 3 {
            self.place(self.hist.len() - 2, cycles, out)?;
        }
        Ok(())
    }

    /// Places the samples and marks before numbered edge `hist[end]` (after
    /// `hist[end - 1]`): the angle is the polynomial in time through the
    /// numbered edges from two before the interval to one after it (a cubic
    /// within the record, lower at its ends).
    fn place<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        end: usize,
        cycles: &mut Cycles,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let (t1, n1, line) = self.hist[end];
        let (tr, nr, _) = self.hist[end - 1];
        let step = self.step_deg;
        let mut pts = [(0.0, 0.0); 4];
        let mut m = 0;
        for &(t, n, _) in self
            .hist
            .iter()
            .skip(end.saturating_sub(2))
            .take((end + 2).min(self.hist.len()) - end.saturating_sub(2))
        {
            pts[m] = (t - tr, (n - nr) as f64 * step);
            m += 1;
        }
        let pts = &pts[..m];
        let angle = |t: f64| nr as f64 * step + lagrange(pts, t - tr);
        loop {
            let sample = self.pending.front().copied().filter(|s| s.0 < t1);
            let mark = self.marks.front().copied().filter(|m| m.0 < t1);
            match (sample, mark) {
                (_, Some(m)) if sample.is_none_or(|s| m.0 <= s.0) => {
                    self.marks.pop_front();
                    self.on_mark(angle(m.0), m.1, m.2, cycles, out)?;
                }
                (Some((t, p, l)), _) => {
                    self.pending.pop_front();
                    // Before the first TDC: a revolution's samples begin
                    // at its TDC, as the cycles expect.
                    let Some(a) = self.reference.map(|r| angle(t) - r).filter(|a| *a >= 0.0) else {
                        self.before_first += 1;
                        continue;
                    };
                    let k = (a / 360.0).floor();
                    cycles.push(k as i64, a - 360.0 * k, p, l, t, out)?;
                }
                _ => break,
            }
        }
        if let Some(r) = self.reference {
            let a = n1 as f64 * step - r;
            let k = (a / 360.0).floor();
            cycles.reached(k as i64, a - 360.0 * k, line, out)?;
        }
        Ok(())
    }

    /// A `tdc` or `cam` mark at signal angle `theta`.
    fn on_mark<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        theta: f64,
        line: usize,
        m: Mark,
        cycles: &mut Cycles,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        match (m, &mut self.kind) {
            (Mark::Tdc, Kind::Encoder(e)) => {
                self.reference = Some(e.tdc(self.reference, theta, line)?);
            }
            (Mark::Cam, _) => {
                if let Some(r) = self.reference {
                    // The TDC after the cam pulse's rise is firing TDC.
                    let k = ((theta - r) / 360.0).floor() as i64;
                    cycles.cam((k + 1).rem_euclid(2), line, self.cam_col.unwrap_or(0), out)?;
                }
            }
            (Mark::Tdc, Kind::Wheel { .. }) => {}
        }
        Ok(())
    }

    /// The end of the record: the last edges numbered with the neighbours
    /// there are; samples after the last edge have no angle.
    pub(super) fn end<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        cycles: &mut Cycles,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        self.number(true, cycles, out)?;
        if self.hist.len() >= 2 {
            self.place(self.hist.len() - 1, cycles, out)?;
        }
        Ok(())
    }
}

/// The polynomial through `pts` (x, y), at `x`: Lagrange's form, for up
/// to four points.
fn lagrange(pts: &[(f64, f64)], x: f64) -> f64 {
    let mut sum = 0.0;
    for (i, &(xi, yi)) in pts.iter().enumerate() {
        let mut w = yi;
        for (j, &(xj, _)) in pts.iter().enumerate() {
            if j != i {
                w *= (x - xj) / (xi - xj);
            }
        }
        sum += w;
    }
    sum
}
