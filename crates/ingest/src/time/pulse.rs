//! The `tdc` pulse: one pulse a revolution, the speed taken revolution by
//! revolution and the angle linear in time within each. A revolution is
//! held until its closing pulse.

use super::cycles::Cycles;
use super::edges::Rise;
use crate::Streamed;
use crate::emit::Emitter;
use crate::error::{IngestError, at};

/// A revolution at least this much longer or shorter than the mean of the
/// ones before is a missed or an extra pulse.
const REV_JUMP: f64 = 0.3;

/// The angle from a TDC pulse per revolution.
pub(super) struct Pulse {
    /// The `tdc` column (0-based).
    pub col: usize,
    rise: Rise,
    /// The last pulse's time and pulse count.
    last_edge: Option<(f64, i64)>,
    /// The samples since it: time, value, line.
    rev: Vec<(f64, f64, usize)>,
    /// The slowest and fastest revolution (rpm), the sum of 1/duration
    /// (1/s) and the revolutions.
    pub speeds: (f64, f64, f64, usize),
    /// Samples before the first pulse.
    pub before_first: usize,
    /// The last sample before the first pulse.
    prev: Option<(f64, f64, usize)>,
}

impl Pulse {
    pub(super) fn new(col: usize) -> Self {
        Self {
            col,
            rise: Rise::new(0.0, 0.0),
            last_edge: None,
            rev: Vec::new(),
            speeds: (f64::INFINITY, 0.0, 0.0, 0),
            before_first: 0,
            prev: None,
        }
    }

    /// The pulse's range, once known.
    pub(super) fn level(&mut self, (lo, hi): (f64, f64)) {
        self.rise = Rise::new(lo, hi);
    }

    /// A sample: time, pressure, the pulse's value.
    pub(super) fn sample<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        t: f64,
        p: f64,
        pulse: f64,
        line: usize,
        cycles: &mut Cycles,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let mut finished = None;
        // The pulse rises through half its range between the samples.
        if let Some((te, _)) = self.rise.sample(t, pulse, line) {
            match self.last_edge {
                Some((t0, k)) => {
                    let d = te - t0;
                    let speeds = &mut self.speeds;
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
                            Some(self.col + 1),
                            format!(
                                "the `tdc` column's pulses are {} s apart: {} rpm, outside the engine speed bound (0.001 to 100000 rpm); a `tdc` column holds one pulse a revolution (a crank encoder is an `encoder` column, a tooth wheel a `wheel` column)",
                                enginedyn_numerics::format::sig(d, 4),
                                enginedyn_numerics::format::sig(rpm, 4)
                            ),
                        ));
                    }
                    speeds.0 = speeds.0.min(rpm);
                    speeds.1 = speeds.1.max(rpm);
                    speeds.2 += 1.0 / d;
                    speeds.3 += 1;
                    // The edge is counted once the pulse reaches two
                    // thirds of its range (edges.rs), perhaps a sample
                    // after the one past its time: that sample is the next
                    // revolution's.
                    let mut samples = std::mem::take(&mut self.rev);
                    let after = samples.partition_point(|s| s.0 < te);
                    self.rev = samples.split_off(after);
                    finished = Some((k, t0, te, samples));
                    self.last_edge = Some((te, k + 1));
                }
                None => {
                    self.last_edge = Some((te, 0));
                    // The sample past the edge before the one that counted it.
                    if let Some(s) = self.prev.filter(|s| s.0 >= te) {
                        self.rev.push(s);
                        self.before_first -= 1;
                    }
                }
            }
        }
        if self.last_edge.is_some() {
            self.rev.push((t, p, line));
        } else {
            self.before_first += 1;
            self.prev = Some((t, p, line));
        }
        if let Some((k, t0, t1, samples)) = finished {
            // A whole revolution: its samples linear in time between pulses.
            let dur = t1 - t0;
            for (t, p, l) in samples {
                cycles.push(k, 360.0 * (t - t0) / dur, p, l, t, out)?;
            }
            cycles.reached(k, 360.0, line, out)?;
        }
        Ok(())
    }
}
