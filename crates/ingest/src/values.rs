//! How a value column's cells become SI: Pa per file unit and the offset
//! added (gauge pressure, a charge amplifier's volts times `--gain`). Shared
//! by every layout and the time record's angle sources.

use crate::columns::{ATM, Roles};
use crate::error::{IngestError, at};
use crate::{ParseOptions, Quantity};

/// Pa per file unit and the offset added (Pa) for value column `v`.
pub(crate) fn value_scale(
    roles: &Roles,
    scale: f64,
    opts: &ParseOptions,
    line: usize,
) -> Result<(f64, f64), IngestError> {
    if roles.volts {
        let col = roles.values.first().map_or(1, |v| v.col + 1);
        let Some(gain) = opts.gain_bar_per_v else {
            return Err(at(
                line,
                Some(col),
                "a voltage column (`pressure_v`) needs --gain BAR_PER_V, the charge amplifier's setting",
            ));
        };
        if !opts.relative {
            return Err(at(
                line,
                Some(col),
                "a charge amplifier's voltage is relative pressure: give --peg-bar P (the pressure at intake BDC, bar) or --peg polytropic to peg each cycle",
            ));
        }
        return Ok((scale * gain * 1e5, 0.0));
    }
    let gauge = opts.gauge && roles.quantity == Quantity::Pressure;
    Ok((scale, if gauge { ATM } else { 0.0 }))
}
