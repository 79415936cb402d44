//! Sensitivities `d result / d parameter`: analytic for the geometry (the
//! kinematics gives them in closed form), central differences of full
//! pipeline runs for everything else, with the step chosen and checked.

use crate::ToleranceError;
use crate::keys::{Input, OUTPUTS, Output, Parameter};
use crate::perturb::{Evaluator, Outputs};
use enginedyn_kinematics::Mechanism;
use rayon::prelude::*;
use std::f64::consts::PI;

/// How a sensitivity was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Closed form of the geometry (head fixed).
    Analytic,
    /// Central difference `(y(x + h) - y(x - h)) / 2h` of full runs.
    Central,
    /// The result has a kink at nominal, from full runs on either side: it
    /// cancels to 0 there (the slope of the V, `(y+ + y- - 2 y0) / 2h`,
    /// not negative) or it is the largest of several equal peaks (the
    /// steeper one-sided slope). Either way `|s| t` is what the tolerance
    /// alone can cause to first order, and the linear stack-up is an upper
    /// bound, not a prediction.
    OneSided,
}

impl Method {
    /// As printed.
    pub fn name(self) -> &'static str {
        match self {
            Method::Analytic => "analytic",
            Method::Central => "central",
            Method::OneSided => "one-sided",
        }
    }
}

/// One sensitivity with how it was found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensitivity {
    /// `d result / d parameter` in the result's unit per the key's unit.
    pub value: f64,
    /// How.
    pub method: Method,
    /// The difference step used (key unit; 0 for analytic).
    pub step: f64,
    /// Relative change of the estimate when the step was last halved (0
    /// for analytic).
    pub check: f64,
    /// The step check passed: the change was below [`STEP_CHECK`] of the
    /// value, or below what rounding leaves (a derivative that is 0).
    pub converged: bool,
    /// Slopes toward `+` and `-` (key unit), from the same runs.
    pub one_sided: (f64, f64),
}

/// Largest relative change of a difference quotient under halving of the
/// step that counts as converged.
pub const STEP_CHECK: f64 = 1e-3;
/// First step as a fraction of the tolerance.
const FIRST_STEP: f64 = 0.25;
/// Halvings tried before giving up on the step check.
const HALVINGS: usize = 6;
/// A result is 0 when it is below this fraction of its scale (what it
/// would be if nothing cancelled).
pub const ZERO: f64 = 1e-9;

/// True when a nominal value counts as 0 for its scale.
pub fn is_zero(value: f64, scale: f64) -> bool {
    scale == 0.0 || value.abs() <= ZERO * scale
}

/// Analytic derivative of a geometric result for one input (result unit
/// per key unit), head fixed: `y_TDC = sqrt((L+R)² - e²)`, stroke
/// `y_TDC - sqrt((L-R)² - e²)`, `V_c' = V_c - A_p dy_TDC`, `eps = 1 + A_p s / V_c`;
/// a Scotch yoke has `y_TDC = R + const`, `s = 2R` (the slot's tilt acts
/// in second order only). `None` for a result that is not geometric.
pub fn geometric(ev: &Evaluator, input: &Input, output: Output) -> Option<f64> {
    if !output.is_geometric() {
        return None;
    }
    let engine = ev.engine();
    let cyl = engine.cylinder();
    let (d_r, d_l, d_e, d_d) = match input.parameter {
        Parameter::Stroke => (0.5e-3, 0.0, 0.0, 0.0),
        Parameter::RodLength => (0.0, 1e-3, 0.0, 0.0),
        Parameter::PinOffset => (0.0, 0.0, 1e-3, 0.0),
        Parameter::Bore => (0.0, 0.0, 0.0, 1e-3),
        _ => (0.0, 0.0, 0.0, 0.0),
    };
    let (dy_top, ds) = match engine.mechanism() {
        Mechanism::CrankSlider(cs) => {
            let (r, l, e) = (cs.r(), cs.l(), cs.e());
            // Pin heights at TDC and BDC from the kinematics crate; only
            // their derivatives are written here.
            let y_top = cs.y_tdc();
            let y_bottom = y_top - cs.stroke();
            let dy_top = ((l + r) * (d_r + d_l) - e * d_e) / y_top;
            let dy_bottom = ((l - r) * (d_l - d_r) - e * d_e) / y_bottom;
            (dy_top, dy_top - dy_bottom)
        }
        Mechanism::ScotchYoke(_) => (d_r, 2.0 * d_r),
    };
    let a = cyl.piston_area();
    let da = PI * cyl.bore() / 2.0 * d_d;
    let s = engine.mechanism().stroke();
    let vc = cyl.clearance_volume();
    let dvc = -a * dy_top;
    Some(match output {
        Output::Stroke => ds,
        Output::ClearanceVolume => dvc,
        _ => (da * s + a * ds) / vc - a * s * dvc / (vc * vc),
    })
}

/// Runs at `x ± h` for one input.
fn pair(ev: &Evaluator, j: usize, h: f64) -> Result<(Outputs, Outputs), ToleranceError> {
    let mut dev = vec![0.0; ev.inputs().len()];
    dev[j] = h;
    let plus = ev.evaluate(&dev)?;
    dev[j] = -h;
    let minus = ev.evaluate(&dev)?;
    Ok((plus, minus))
}

/// Difference quotients of one result at one step: central, and the
/// slopes toward `+` and `-` (half their difference is the slope of a V).
#[derive(Debug, Clone, Copy)]
struct Quotients {
    central: f64,
    forward: f64,
    backward: f64,
}

fn quotients(y0: f64, plus: f64, minus: f64, h: f64) -> Quotients {
    Quotients {
        central: (plus - minus) / (2.0 * h),
        forward: (plus - y0) / h,
        backward: (y0 - minus) / h,
    }
}

/// The sensitivities of every result to one input (by central
/// differences, or analytic for the geometry), `None` where the result
/// does not exist at nominal.
fn input_sensitivities(
    ev: &Evaluator,
    j: usize,
    nominal: &Outputs,
    scale: &[f64; OUTPUTS],
) -> Result<[Option<Sensitivity>; OUTPUTS], ToleranceError> {
    let input = ev.inputs()[j];
    let t = input.tolerance;
    let mut levels: Vec<(f64, Outputs, Outputs)> = Vec::new();
    let mut h = FIRST_STEP * t;
    for _ in 0..2 {
        let (p, m) = pair(ev, j, h)?;
        levels.push((h, p, m));
        h /= 2.0;
    }
    let mut out = [None; OUTPUTS];
    let mut pending: Vec<Output> = Output::ALL.to_vec();
    loop {
        pending.retain(|&o| {
            let Some(y0) = nominal.get(o) else {
                return false;
            };
            if let Some(d) = geometric(ev, &input, o) {
                out[o.index()] = Some(Sensitivity {
                    value: d,
                    method: Method::Analytic,
                    step: 0.0,
                    check: 0.0,
                    converged: true,
                    one_sided: (d, d),
                });
                return false;
            }
            let q: Vec<(f64, Quotients)> = levels
                .iter()
                .filter_map(|(h, p, m)| Some((*h, quotients(y0, p.get(o)?, m.get(o)?, *h))))
                .collect();
            if q.len() < 2 {
                return false; // the result vanishes next to nominal: nothing to say
            }
            let zero = is_zero(y0, scale[o.index()]);
            // For a result at a kink the estimate is the steeper side.
            let steeper = |q: &Quotients| {
                if q.forward.abs() >= q.backward.abs() {
                    q.forward
                } else {
                    q.backward
                }
            };
            let floor = ZERO * scale[o.index()].max(y0.abs()) / t;
            let n = q.len();
            let (_, a) = q[n - 2];
            let (hb, b) = q[n - 1];
            // A kink: the one-sided slopes differ, and by the same amount at
            // both steps (curvature would halve the difference).
            let gap_a = a.forward - a.backward;
            let gap_b = b.forward - b.backward;
            let kink = zero
                || (gap_b.abs() > 0.1 * b.forward.abs().max(b.backward.abs())
                    && gap_b.abs() > floor
                    && (gap_a - gap_b).abs() < 0.25 * gap_b.abs());
            // A result that cancels grows with |dx| both ways: the V's slope.
            let v_slope = |q: &Quotients| 0.5 * (q.forward - q.backward);
            let (va, vb, method) = if zero {
                (v_slope(&a), v_slope(&b), Method::OneSided)
            } else if kink {
                (steeper(&a), steeper(&b), Method::OneSided)
            } else {
                (a.central, b.central, Method::Central)
            };
            let change = (va - vb).abs();
            let converged = change <= STEP_CHECK * vb.abs() + floor;
            // Below what rounding leaves, the derivative is 0.
            let vb = if vb.abs() <= floor && converged {
                0.0
            } else {
                vb
            };
            if converged || levels.len() >= HALVINGS + 2 {
                out[o.index()] = Some(Sensitivity {
                    value: vb,
                    method,
                    step: hb,
                    check: if vb != 0.0 { change / vb.abs() } else { 0.0 },
                    converged,
                    one_sided: (b.forward, b.backward),
                });
                return false;
            }
            true
        });
        if pending.is_empty() {
            break;
        }
        let h = levels.last().map(|l| l.0 / 2.0).unwrap_or(t);
        let (p, m) = pair(ev, j, h)?;
        levels.push((h, p, m));
    }
    Ok(out)
}

/// Sensitivities of every result to every input, `[input][output]`
/// (inputs in parallel). `nominal` and `scale` are [`Evaluator::nominal`]'s.
pub fn sensitivities(
    ev: &Evaluator,
    nominal: &Outputs,
    scale: &[f64; OUTPUTS],
) -> Result<Vec<[Option<Sensitivity>; OUTPUTS]>, ToleranceError> {
    (0..ev.inputs().len())
        .into_par_iter()
        .map(|j| input_sensitivities(ev, j, nominal, scale))
        .collect()
}
