//! A crank encoder (`encoder` column, `--encoder-ppr N`): the angle
//! advances 360/N° at each rising edge ([`super::teeth`] times and checks
//! the edges) and is 0 at the `tdc` pulse's rise or at `--tdc-time`. Each
//! later `tdc` pulse must fall a whole number of revolutions after the
//! first by the encoder's count: else an edge was missed or added, or N is
//! not the encoder's.

use crate::error::{IngestError, at};

/// Where the encoder's 0° comes from.
pub(super) struct Encoder {
    pub ppr: u32,
    /// The `tdc` column (0-based), when it gives 0°.
    pub tdc_col: Option<usize>,
    /// `--tdc-time`, when it gives 0° (a firing TDC).
    pub tdc_time: Option<f64>,
    /// `tdc` pulses read on the encoder's angle.
    pub pulses: usize,
}

impl Encoder {
    /// A `tdc` pulse (or `--tdc-time`) at encoder angle `theta` (deg from
    /// the first edge), given the reference so far: the reference it sets.
    pub(super) fn tdc(
        &mut self,
        reference: Option<f64>,
        theta: f64,
        line: usize,
    ) -> Result<f64, IngestError> {
        self.pulses += 1;
        let Some(r) = reference else {
            return Ok(theta);
        };
        let d = theta - r;
        let revs = (d / 360.0).round();
        let half_step = 180.0 / f64::from(self.ppr);
        if revs < 1.0 || (d - 360.0 * revs).abs() > half_step {
            return Err(at(
                line,
                self.tdc_col.map(|c| c + 1),
                format!(
                    "this `tdc` pulse comes {}° after the first by the encoder's edges (--encoder-ppr {}): not a whole number of revolutions; an encoder edge missed or extra, or the encoder has another number of pulses a revolution",
                    enginedyn_numerics::format::sig(d, 6),
                    self.ppr
                ),
            ));
        }
        Ok(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn later_pulses_a_whole_number_of_revolutions_on() {
        let mut e = Encoder {
            ppr: 360,
            tdc_col: Some(2),
            tdc_time: None,
            pulses: 0,
        };
        assert_eq!(e.tdc(None, 12.25, 3).unwrap().to_bits(), 12.25f64.to_bits());
        assert_eq!(
            e.tdc(Some(12.25), 372.5, 9).unwrap().to_bits(),
            12.25f64.to_bits()
        );
        // A missed pulse is harmless: two revolutions on.
        assert_eq!(
            e.tdc(Some(12.25), 732.0, 11).unwrap().to_bits(),
            12.25f64.to_bits()
        );
        // One edge short: 359° on.
        let m = e.tdc(Some(12.25), 371.25, 17).unwrap_err().to_string();
        assert!(
            m.starts_with("line 17, column 3: this `tdc` pulse comes 359°"),
            "{m}"
        );
        assert_eq!(e.pulses, 4);
    }
}
