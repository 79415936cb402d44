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
        let c = (a / self.cycle_deg).floor() as i64;
        let within = a - c as f64 * self.cycle_deg;
        if self.cur.as_ref().is_none_or(|b| b.index != c) {
            self.close(out)?;
            self.cur = Some(Building::new(c, line, 0, true, &self.others));
        }
        if let Some(b) = self.cur.as_mut() {
            if let Some(&prev) = b.trace.angle_deg.last()
                && self.step_deg == 0.0
            {
                self.step_deg = within - prev;
            }
            b.trace.angle_deg.push(within);
            b.trace.values.push(p);
            self.others.place(line, b);
        }
        Ok(())
    }

    /// The cycle being assembled is whole when its samples reach both its
    /// ends (within two sample steps).
    pub(super) fn close<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if let Some(b) = self.cur.take() {
            let first = b.trace.angle_deg.first().copied().unwrap_or(0.0);
            let last = b.trace.angle_deg.last().copied().unwrap_or(0.0);
            let step = self.step_deg.max(1e-9);
            if first <= 2.0 * step && self.cycle_deg - last <= 2.0 * step {
                self.complete += 1;
                self.others.emit(b, out)?;
            } else {
                self.partial += 1;
            }
        }
        Ok(())
    }
}
