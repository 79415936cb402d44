//! The whole tolerance study: the table of sensitivities, influences and
//! deviations, the stack-up per result and its Monte Carlo check.

use crate::ToleranceError;
use crate::keys::{Input, Output};
use crate::linear::{Method, Sensitivity, is_zero, sensitivities};
use crate::monte_carlo::{MonteCarlo, monte_carlo};
use crate::perturb::{Evaluator, Outputs};

/// One row of `tolerance.csv`: one input's effect on one result.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The toleranced input.
    pub input: Input,
    /// The result.
    pub output: Output,
    /// The result's nominal value.
    pub nominal: f64,
    /// `d result / d parameter` (result unit per key unit) and how it was found.
    pub sensitivity: Sensitivity,
    /// Relative influence coefficient of seed 004, `(dy/y) / (dx/x)` =
    /// `s x0 / y0`; `None` when the result's or the parameter's nominal is 0.
    pub influence: Option<f64>,
    /// What the tolerance alone causes: `|s| t`.
    pub deviation: f64,
}

/// The stack-up of one result and its Monte Carlo check.
#[derive(Debug, Clone, PartialEq)]
pub struct Stack {
    /// The result.
    pub output: Output,
    /// Nominal value (on the table's grid).
    pub nominal: f64,
    /// `Σ deviation`.
    pub worst_case: f64,
    /// `sqrt(Σ deviation²) / √3`: the standard deviation the linear model
    /// predicts for uniform deviations on `[-t, t]`.
    pub rss: f64,
    /// The nominal is 0 (the result cancels): no relative influence, a kink.
    pub zero: bool,
    /// Some sensitivity is one-sided (a kink at nominal).
    pub kink: bool,
    /// Monte Carlo standard deviation.
    pub monte_carlo_std: Option<f64>,
    /// Monte Carlo mean.
    pub monte_carlo_mean: Option<f64>,
    /// Largest `|y - nominal|` over the samples.
    pub monte_carlo_max_dev: Option<f64>,
    /// `|monte_carlo_std - rss| / rss`; `None` when `rss` is 0 or the
    /// spread is below [`RESOLUTION`] of the nominal.
    pub linearity_error: Option<f64>,
    /// What the reader should know about this result.
    pub note: Option<String>,
}

/// Everything `enginedyn tolerance` reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// The inputs (one per parameter, per cylinder or per throw).
    pub inputs: Vec<Input>,
    /// Nominal results on the table's grid.
    pub nominal: Outputs,
    /// Grid step of the table (deg).
    pub step_deg: f64,
    /// One row per input and existing result, inputs outer.
    pub rows: Vec<Row>,
    /// One stack-up per existing result, in [`Output::ALL`]'s order.
    pub stacks: Vec<Stack>,
    /// The Monte Carlo run, unless no samples were asked for.
    pub monte_carlo: Option<MonteCarlo>,
    /// Study-wide notes.
    pub notes: Vec<String>,
}

impl Study {
    /// The rows of one result.
    pub fn rows_of(&self, o: Output) -> impl Iterator<Item = &Row> {
        self.rows.iter().filter(move |r| r.output == o)
    }
}

/// Linearity error above which a note says the result is not linear over
/// the tolerance box.
pub const NONLINEAR: f64 = 0.1;

/// Spread (RSS or Monte Carlo standard deviation) relative to the nominal
/// below which linearity is not judged: results that hardly move (the
/// crank-pin load maximum under a TDC error, whose peak shifts along with
/// the pressure) move at the level of the grid's resolution of extremes
/// (refined between samples to third order), where Monte Carlo and RSS
/// agree no better than that resolution. Test
/// `linearity_error_grows_with_a_large_tdc_error` (`tests/closed_forms.rs`)
/// holds a case: a ±0.1° TDC error moves that maximum by a standard
/// deviation below 1 N on tens of kN.
pub const RESOLUTION: f64 = 1e-4;

/// Runs the study: sensitivities on `table`'s grid, then `samples` Monte
/// Carlo samples from `seed` on `mc`'s grid (coarser is faster; the two
/// evaluators must share engine and inputs). `samples = 0` skips the
/// Monte Carlo.
pub fn study(
    table: &Evaluator,
    mc: &Evaluator,
    samples: usize,
    seed: u64,
) -> Result<Study, ToleranceError> {
    if table.inputs() != mc.inputs() {
        return Err(ToleranceError::Input(
            "the table and the Monte Carlo evaluators have different inputs".into(),
        ));
    }
    let (nominal, scale) = table.nominal()?;
    let sens = sensitivities(table, &nominal, &scale)?;
    let carlo = (samples > 0)
        .then(|| monte_carlo(mc, samples, seed))
        .transpose()?;
    let mut notes = Vec::new();
    let mut rows = Vec::new();
    for (input, s) in table.inputs().iter().zip(&sens) {
        for o in Output::ALL {
            let (Some(y0), Some(sensitivity)) = (nominal.get(o), s[o.index()]) else {
                continue;
            };
            let zero = is_zero(y0, scale[o.index()]);
            let influence =
                (!zero && input.nominal != 0.0).then(|| sensitivity.value * input.nominal / y0);
            if !sensitivity.converged {
                notes.push(format!(
                    "{} on {}: the difference quotient still changed by {:.2} % at the smallest step {:.3e} {}",
                    input.name(),
                    o.key(),
                    100.0 * sensitivity.check,
                    sensitivity.step,
                    input.parameter.unit()
                ));
            }
            rows.push(Row {
                input: *input,
                output: o,
                nominal: y0,
                sensitivity,
                influence,
                deviation: sensitivity.value.abs() * input.tolerance,
            });
        }
    }
    let mut stacks = Vec::new();
    for o in Output::ALL {
        let Some(y0) = nominal.get(o) else {
            notes.push(match o {
                Output::TorqueOrderHalf => {
                    "torque_order_0_5_nm: a two-stroke cycle has no order 0.5".to_string()
                }
                _ => format!("{}: does not exist for this engine (motoring?)", o.key()),
            });
            continue;
        };
        let devs: Vec<&Row> = rows.iter().filter(|r| r.output == o).collect();
        let worst_case: f64 = devs.iter().map(|r| r.deviation).sum();
        let rss = devs.iter().map(|r| r.deviation.powi(2)).sum::<f64>().sqrt() / 3f64.sqrt();
        let zero = is_zero(y0, scale[o.index()]);
        let kink = devs
            .iter()
            .any(|r| r.sensitivity.method == Method::OneSided);
        let i = o.index();
        let (mc_std, mc_mean, mc_max) = match &carlo {
            Some(c) => (c.std[i], c.mean[i], c.max_dev[i]),
            None => (None, None, None),
        };
        let resolved = rss.max(mc_std.unwrap_or(0.0)) > RESOLUTION * y0.abs();
        let linearity_error = match mc_std {
            Some(s) if rss > 0.0 && (resolved || zero) => Some((s - rss).abs() / rss),
            _ => None,
        };
        let mut said = Vec::new();
        if scale[i] == 0.0 {
            said.push("0 whatever the deviations (nothing to vary it)".to_string());
        } else if zero {
            said.push(
                "nominal 0 (it cancels): no relative influence, and a kink at 0 where the linear \
                 model says nothing; the sensitivities are one-sided slopes, the worst case an \
                 upper bound, and the Monte Carlo spread is the answer"
                    .to_string(),
            );
        } else if kink {
            said.push(
                "a kink at nominal (several equal peaks compete, or a part of it cancels): \
                 one-sided slopes, so the linear stack-up is an upper bound"
                    .to_string(),
            );
        }
        if !zero
            && let Some(e) = linearity_error
            && e > NONLINEAR
        {
            said.push(format!(
                "not linear over the tolerance box: Monte Carlo differs from RSS by {:.0} %",
                100.0 * e
            ));
        }
        if !resolved && !zero && rss > 0.0 && mc_std.is_some() {
            said.push(format!(
                "spread below {RESOLUTION:.0e} of the nominal, the grid's resolution of extremes: \
                 linearity not judged"
            ));
        }
        if let Some(c) = &carlo
            && c.missing[i] > 0
        {
            said.push(format!("{} samples without this result", c.missing[i]));
        }
        stacks.push(Stack {
            output: o,
            nominal: y0,
            worst_case,
            rss,
            zero,
            kink,
            monte_carlo_std: mc_std,
            monte_carlo_mean: mc_mean,
            monte_carlo_max_dev: mc_max,
            linearity_error,
            note: (!said.is_empty()).then(|| said.join("; ")),
        });
    }
    Ok(Study {
        inputs: table.inputs().to_vec(),
        nominal,
        step_deg: table.options().step_deg,
        rows,
        stacks,
        monte_carlo: carlo,
        notes,
    })
}
