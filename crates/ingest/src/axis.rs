//! Where each trace's firing TDC lies on the file's angles (INTERFACE.md,
//! "Per-cylinder traces on one axis or their own" and `--tdc-deg`).
//!
//! Two decisions, both from where a trace's pressure peak lies, each said
//! in a note:
//!
//! - **Firing TDC at 360°.** Without `--tdc-deg`, a four-stroke p–φ file
//!   whose (cylinder 1's) pressure peak follows the file's 360° rather than
//!   its 0° has its firing TDC at 360° (a 0–720° export from intake TDC),
//!   the rule that picks the firing pulse of a time record.
//! - **One axis for all cylinders, or each its own.** Multi-channel
//!   indicating systems export every cylinder over cylinder 1's crank
//!   angle; others give each cylinder over its own firing TDC. On a shared
//!   axis cylinder i's peak follows its firing angle θ_i, on its own axis
//!   it follows 0. A trace is moved onto its own firing TDC when the file
//!   is on a shared axis. `--cylinder-axis` settles it; traces that fit
//!   neither are an error naming the cylinder.
//!
//! A peak "follows" a TDC when it lies from [`FOLLOWS_BEFORE`] before it to
//! [`FOLLOWS_AFTER`] after it: a motored cycle peaks a degree or two before
//! TDC (heat loss), a fired one 5–40° after.

use crate::error::IngestError;
use crate::{Quantity, Trace};

/// How far before a TDC a pressure peak may lie and still follow it (deg).
pub const FOLLOWS_BEFORE: f64 = 15.0;

/// How far after a TDC a pressure peak may lie and still follow it (deg).
pub const FOLLOWS_AFTER: f64 = 60.0;

/// Whether per-cylinder traces share cylinder 1's crank angle
/// (`--cylinder-axis shared|own`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CylinderAxis {
    /// Every cylinder over cylinder 1's angle (its TDC at its firing angle).
    Shared,
    /// Each cylinder over its own angle from its own firing TDC.
    Own,
}

impl CylinderAxis {
    /// As the option spells it.
    pub fn name(self) -> &'static str {
        match self {
            CylinderAxis::Shared => "shared",
            CylinderAxis::Own => "own",
        }
    }
}

/// The decisions for one file, made trace by trace as they stream.
#[derive(Debug)]
pub(crate) struct Aligner {
    cycle: f64,
    /// Firing angle of each cylinder (deg, cylinder 1's 0); empty: unknown.
    firing: Vec<f64>,
    forced: Option<CylinderAxis>,
    /// The file is this cylinder's (several `--diagram` files); 0: none.
    as_cylinder: i64,
    /// The 360° rule may apply (a four-stroke p–φ pressure file read
    /// without `--tdc-deg`, not a time record).
    may_shift: bool,
    /// The 360° decision, and the peak angle it came from.
    tdc360: Option<(bool, f64)>,
    /// The axis decision, and why.
    axis: Option<(CylinderAxis, String)>,
    /// A cylinder whose trace could not tell the axes apart (its firing
    /// angle within the window of 0), read on its own axis before the file
    /// decided.
    ambiguous: Option<i64>,
    /// Cylinders seen (for the note).
    cylinders: usize,
}

/// `x` wrapped into `[-cycle/2, cycle/2)`.
fn wrapped(x: f64, cycle: f64) -> f64 {
    (x + cycle / 2.0).rem_euclid(cycle) - cycle / 2.0
}

/// True when a peak at `p` follows a TDC at `tdc` (deg).
fn follows(p: f64, tdc: f64, cycle: f64) -> bool {
    let d = wrapped(p - tdc, cycle);
    (-FOLLOWS_BEFORE..FOLLOWS_AFTER).contains(&d)
}

/// Moves a trace's angles (rising, in `[0, cycle)`) by `-s` degrees,
/// rotated so they rise again.
fn rotate(tr: &mut Trace, s: f64, cycle: f64) {
    let k = tr.angle_deg.partition_point(|&a| a < s);
    for (i, a) in tr.angle_deg.iter_mut().enumerate() {
        *a = if i >= k { *a - s } else { *a - s + cycle };
        if *a >= cycle {
            *a -= cycle;
        }
    }
    tr.angle_deg.rotate_left(k);
    tr.values.rotate_left(k);
}

fn fmt(x: f64) -> String {
    enginedyn_numerics::format::trimmed(x, 1)
}

impl Aligner {
    pub(crate) fn new(opts: &crate::ParseOptions) -> Self {
        Self {
            cycle: opts.cycle_deg,
            firing: opts.firing_deg.clone(),
            forced: opts.cylinder_axis,
            as_cylinder: opts.as_cylinder as i64,
            may_shift: opts.cycle_deg > 400.0 && !opts.tdc_given,
            tdc360: None,
            axis: None,
            ambiguous: None,
            cylinders: 0,
        }
    }

    /// Moves `tr` (checked, angles rising in `[0, cycle)`) onto its firing
    /// TDC: true when it moved. `time` and `pv`: a time record or p–V data,
    /// whose angles come from their own rules.
    pub(crate) fn align(
        &mut self,
        tr: &mut Trace,
        quantity: Quantity,
        time: bool,
        pv: bool,
    ) -> Result<bool, IngestError> {
        if quantity != Quantity::Pressure || tr.values.is_empty() {
            return Ok(false);
        }
        let peak_at = |tr: &Trace| {
            let i = enginedyn_numerics::scan::arg_min_max(&tr.values).1;
            tr.angle_deg[i]
        };
        let cylinder = if tr.cylinder > 0 {
            tr.cylinder
        } else {
            self.as_cylinder
        };
        let mut shift = 0.0;
        if self.may_shift && !time && !pv && cylinder <= 1 && self.tdc360.is_none() {
            let p = peak_at(tr);
            let at360 = follows(p, 360.0, self.cycle) && !follows(p, 0.0, self.cycle);
            self.tdc360 = Some((at360, p));
        }
        if let Some((true, _)) = self.tdc360 {
            shift += 360.0;
        }
        let theta = usize::try_from(cylinder - 1)
            .ok()
            .and_then(|i| self.firing.get(i).copied());
        // A time record's angle is its own rule's (its crank reference and
        // the firing TDC it decided), except for the cylinders of a record
        // with one pressure column per cylinder: those all lie on cylinder
        // 1's angle, as the peaks then show.
        if let Some(theta) = theta.filter(|_| !time || tr.cylinder > 0) {
            let p = wrapped(peak_at(tr) - shift, self.cycle).rem_euclid(self.cycle);
            let distinct = wrapped(theta, self.cycle).abs() > 1e-6;
            let own = follows(p, 0.0, self.cycle);
            let shared = follows(p, theta, self.cycle);
            if cylinder as usize > self.cylinders {
                self.cylinders = cylinder as usize;
            }
            let axis = match self.forced {
                Some(a) => a,
                None if !distinct => self.axis.as_ref().map_or(CylinderAxis::Own, |a| a.0),
                None => {
                    let fits = match (own, shared) {
                        (true, false) => Some(CylinderAxis::Own),
                        (false, true) => Some(CylinderAxis::Shared),
                        (true, true) => None,
                        (false, false) => {
                            return Err(IngestError::Data(format!(
                                "cylinder {cylinder}'s pressure peak at {}° follows neither its own firing TDC (0°) nor its firing angle on cylinder 1's axis ({}°): are the cylinders numbered as the engine file's firing order says? (--cylinder-axis shared|own settles the axis)",
                                fmt(p),
                                fmt(theta)
                            )));
                        }
                    };
                    match (fits, &self.axis) {
                        (Some(a), None) => {
                            if let (CylinderAxis::Shared, Some(c)) = (a, self.ambiguous) {
                                return Err(IngestError::Data(format!(
                                    "cylinder {c}'s trace was read on its own axis before cylinder {cylinder}'s peak showed a shared one (its firing angle is too close to cylinder 1's to tell): give --cylinder-axis shared or own"
                                )));
                            }
                            let why = match a {
                                CylinderAxis::Shared => format!(
                                    "cylinder {cylinder}'s pressure peak at {}° follows its firing angle {}° on cylinder 1's axis",
                                    fmt(p),
                                    fmt(theta)
                                ),
                                CylinderAxis::Own => format!(
                                    "cylinder {cylinder}'s pressure peak at {}° follows 0°, not its firing angle {}°",
                                    fmt(p),
                                    fmt(theta)
                                ),
                            };
                            self.axis = Some((a, why));
                            a
                        }
                        (Some(a), Some((d, _))) if a != *d => {
                            return Err(IngestError::Data(format!(
                                "cylinder {cylinder}'s pressure peak at {}° says the cylinders are each on {} axis, an earlier trace said {}: traces that fit neither one axis nor the other (--cylinder-axis shared|own settles it)",
                                fmt(p),
                                if a == CylinderAxis::Own {
                                    "their own"
                                } else {
                                    "one shared"
                                },
                                if *d == CylinderAxis::Own {
                                    "their own"
                                } else {
                                    "one shared"
                                },
                            )));
                        }
                        (Some(a), Some(_)) => a,
                        (None, Some((d, _))) => *d,
                        (None, None) => {
                            self.ambiguous.get_or_insert(cylinder);
                            CylinderAxis::Own
                        }
                    }
                }
            };
            if axis == CylinderAxis::Shared && distinct {
                shift += theta;
            }
        }
        let shift = shift.rem_euclid(self.cycle);
        if shift > 0.0 {
            rotate(tr, shift, self.cycle);
            return Ok(true);
        }
        Ok(false)
    }

    /// Where a long record's firing TDC lies before any trace is cut
    /// (deg: 0, or 360 when the 360° rule will move the first trace): the
    /// window rule cuts a record whose angle runs on at the gas-exchange
    /// TDC, half a cycle from its firing TDC, so the cut must know which of
    /// the file's two TDCs fires. `angles` (deg from the file's firing
    /// TDC, rising) and `values` span a cycle of cylinder `cylinder`'s
    /// pressure (0: every cylinder's). The same peak rule as [`Self::align`].
    pub(crate) fn firing_offset(
        &self,
        angles: &[f64],
        values: &[f64],
        quantity: Quantity,
        cylinder: i64,
    ) -> f64 {
        if !self.may_shift || quantity != Quantity::Pressure || cylinder > 1 || values.is_empty() {
            return 0.0;
        }
        if let Some((at360, _)) = self.tdc360 {
            return if at360 { 360.0 } else { 0.0 };
        }
        // The peak as `align` finds it on the trace moved into the cycle:
        // of equal values, the one at the lowest angle there.
        let at = |i: usize| angles[i].rem_euclid(self.cycle);
        let i = (0..values.len())
            .max_by(|&i, &j| {
                values[i]
                    .total_cmp(&values[j])
                    .then(at(j).total_cmp(&at(i)))
            })
            .unwrap_or(0);
        let p = at(i);
        if follows(p, 360.0, self.cycle) && !follows(p, 0.0, self.cycle) {
            360.0
        } else {
            0.0
        }
    }

    /// The notes saying what was decided.
    pub(crate) fn notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        if let Some((true, p)) = self.tdc360 {
            notes.push(format!(
                "firing TDC at the file's 360°: the pressure peak at {}° follows 360°, not 0° (a 0–720° export from the intake TDC); the angles are moved by 360° (--tdc-deg 0 --no-compression-check keeps them)",
                fmt(p)
            ));
        }
        if self.cylinders > 1 || self.as_cylinder > 1 {
            match (self.forced, &self.axis) {
                (Some(a), _) => notes.push(format!(
                    "cylinder traces on {} (--cylinder-axis {})",
                    if a == CylinderAxis::Shared {
                        "one shared crank angle, cylinder 1's: each moved to its own firing TDC by its firing angle"
                    } else {
                        "their own crank angles from their own firing TDCs"
                    },
                    a.name()
                )),
                (None, Some((CylinderAxis::Shared, why))) => notes.push(format!(
                    "cylinder traces on one shared crank angle, cylinder 1's ({why}): each moved to its own firing TDC by its firing angle (--cylinder-axis own says otherwise)"
                )),
                (None, Some((CylinderAxis::Own, why))) => notes.push(format!(
                    "cylinder traces each on its own crank angle from its own firing TDC ({why}; --cylinder-axis shared says otherwise)"
                )),
                (None, None) => {}
            }
        }
        notes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_keeps_samples_and_order() {
        let mut t = Trace {
            cycle: 1,
            cylinder: 2,
            angle_deg: (0..720).map(f64::from).collect(),
            values: (0..720).map(f64::from).collect(),
            rpm: None,
        };
        rotate(&mut t, 540.0, 720.0);
        assert_eq!(t.angle_deg[0].to_bits(), 0.0f64.to_bits());
        assert_eq!(t.values[0].to_bits(), 540.0f64.to_bits());
        assert_eq!(t.values[180].to_bits(), 0.0f64.to_bits());
        assert!(t.angle_deg.windows(2).all(|w| w[1] > w[0]));
        assert_eq!(t.angle_deg.len(), 720);
    }

    #[test]
    fn a_peak_follows_its_tdc() {
        assert!(follows(719.0, 0.0, 720.0));
        assert!(follows(15.0, 0.0, 720.0));
        assert!(!follows(200.0, 0.0, 720.0));
        assert!(follows(372.0, 360.0, 720.0));
        assert!(!follows(372.0, 0.0, 720.0));
    }
}
