//! A constant speed and the time of one firing TDC (`--rpm`, `--tdc-time`):
//! the angle linear in time over the whole record.

use super::cycles::{Building, Others};
use crate::Streamed;
use crate::emit::Emitter;
use crate::error::IngestError;

/// The angle from a constant speed: firing TDC at `t0` (s), `deg_per_s`.
pub(super) struct Clock {
    pub t0: f64,
    pub deg_per_s: f64,
    cycle_deg: f64,
    /// The angle step between the first samples (deg).
    step_deg: f64,
    cur: Option<Building>,
    pub complete: usize,
    pub partial: usize,
    /// The other cylinders' values.
    pub others: Others,
    /// The first partial window, kept while no cycle is whole.
    first_part: Option<Box<Building>>,
    /// The record held no whole window: its one cycle from firing TDC to
    /// firing TDC was read ([`super::cycles::one_cycle`]).
    pub joined: bool,
}

impl Clock {
    pub(super) fn new(t0: f64, rpm: f64, cycle_deg: f64) -> Self {
        Self {
            t0,
            deg_per_s: rpm * 6.0,
            cycle_deg,
            step_deg: 0.0,
            cur: None,
            complete: 0,
            partial: 0,
            others: Others::default(),
            first_part: None,
            joined: false,
        }
    }

    /// A sample at angle `a` (deg) from firing TDC.
    pub(super) fn sample<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        a: f64,
        p: f64,
        line: usize,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        // The window around its firing TDC (the one rule, `trace::window`);
        // `within` from the window's start.
        let (c, begins) = crate::trace::window(a, self.cycle_deg);
        let within = a - begins;
        if self.cur.as_ref().is_none_or(|b| b.index != c) {
            self.close(out, false)?;
            self.cur = Some(Building::new(c, line, 0, true, &self.others));
        }
        if let Some(b) = self.cur.as_mut() {
            let angle = within - 0.5 * self.cycle_deg;
            if let Some(&prev) = b.trace.angle_deg.last()
                && self.step_deg == 0.0
            {
                self.step_deg = angle - prev;
            }
            b.trace.angle_deg.push(angle);
            b.trace.values.push(p);
            self.others.place(line, b);
        }
        Ok(())
    }

    /// The cycle being assembled is whole when its samples reach both its
    /// ends (within two sample steps). At the record's `end`, when no
    /// window was whole, the one cycle from firing TDC to firing TDC it
    /// holds ([`super::cycles::one_cycle`]).
    pub(super) fn close<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
        end: bool,
    ) -> Result<(), IngestError> {
        let step = self.step_deg.max(1e-9);
        let near = |b: &Building, at: f64, first: bool| {
            let a = if first {
                b.trace.angle_deg.first()
            } else {
                b.trace.angle_deg.last()
            };
            a.is_some_and(|&a| {
                (a - at).abs() <= 2.0 * step || (first && a < at) || (!first && a > at)
            })
        };
        if end
            && self.complete == 0
            && self.first_part.as_ref().is_some_and(|f| near(f, 0.0, true))
            && self.cur.as_ref().is_some_and(|e| near(e, 0.0, false))
            && let (Some(f), Some(e)) = (self.first_part.take(), self.cur.take())
        {
            if let Some(b) = super::cycles::one_cycle(*f, e, self.cycle_deg) {
                self.joined = true;
                self.partial -= 1;
                self.complete += 1;
                return self.others.emit(b, out);
            }
            self.partial += 1;
            return Ok(());
        }
        if let Some(b) = self.cur.take() {
            // From the window's start (the angles are from its firing TDC).
            let half = 0.5 * self.cycle_deg;
            let first = b.trace.angle_deg.first().map_or(0.0, |a| a + half);
            let last = b.trace.angle_deg.last().map_or(0.0, |a| a + half);
            if first <= 2.0 * step && self.cycle_deg - last <= 2.0 * step {
                self.complete += 1;
                self.others.emit(b, out)?;
            } else {
                self.partial += 1;
                if self.complete == 0 && self.first_part.is_none() {
                    self.first_part = Some(Box::new(b));
                }
            }
        }
        Ok(())
    }
}
