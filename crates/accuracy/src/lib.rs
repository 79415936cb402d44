//! Accuracy against speed: each method choice's error on the key results
//! and its run time ([`study`], `enginedyn accuracy`), and the cheapest
//! setting whose estimated error stays within a tolerance ([`choose`],
//! `--tolerance`).
//!
//! The reference is the most exact setting: exact kinematics, the rigid rod
//! (two-mass when the engine file gives no rod inertia), the periodic
//! spline, a 0.01° grid and the trapezoid rule. The grid study varies the
//! step from the reference; the kinematics, rod, interpolation and
//! integration studies vary one choice from the everyday setting (the
//! reference's methods on the 0.1° grid), so each row says what that run
//! costs and how far from the reference it lands. Interpolation and grid-step errors are
//! measured on a generated diagram whose pressure is known at every angle
//! (the project's cycle model, [`enginedyn_synth::CycleSolution`]): an
//! interpolant cannot be judged against another interpolant of the same
//! samples. On the user's own data the same studies are reported as
//! differences from the reference only.
//!
//! # Stability map
//!
//! Where each method fails or degrades, and what the tool does then (each
//! is pinned by a test in `tests/stability.rs` or the crate named):
//!
//! | condition | what degrades | what the tool does |
//! | --- | --- | --- |
//! | `lambda (1 + k) >= 1` | the crank cannot turn | refused, naming the key and the bound (exit 2) |
//! | lambda near the limit (0.45) | series kinematics: series2 misses the acceleration by several % | a note when the truncation exceeds 1 %; `exact` is always there |
//! | large pin offset | series4/6 undefined; series2 degrades | series4/6 refused; series2 noted as above |
//! | p–V data near TDC and BDC | the volume is flat in the angle: angle errors blow up | warned with the angle error it means (ingest test `pv_outside_the_cylinder_and_crowding`) |
//! | coarse data (10° steps, hand methods) | peaks fall between points: linear misses the gas-force peak by over 1 %, the spline by less | a note above 2° spacing; `accuracy` measures it |
//! | noisy data, a sharp peak | the spline rings (overshoot) | `auto` switches to pchip (never leaves the data range), with a note |
//! | very small delta (1e-5) | the flywheel becomes impractical | exact figures (the speed trace gives delta to 1e-9) and a note |
//! | one cylinder | large psi and flywheel | computed exactly; nothing is wrong |
//! | IMEP under 1.5 bar (near idle; mean torque under 5 % of the swing for turning-moment input) | mu and psi follow every small error of the mean | a note |
//! | negative mean torque (motoring) | no flywheel can be sized | flywheel figures `null` with a note, exit 0 |
//! | a pressure jump in the data | grid differences stay large down to the finest steps | `--tolerance` refuses a tolerance it cannot meet (exit 2; `tests/within.rs`) |
//! | coarse grids (several degrees) | extremes fall between grid points | taken on the local cubic between samples ([`enginedyn_numerics::extremes`]); `--tolerance` takes a step only once three grids agree |
//!
//! ```
//! use enginedyn_accuracy::{KEYS, relative_errors};
//! use enginedyn_pipeline::Summary;
//! let mut a = Summary::empty();
//! a.mean_torque_nm = Some(100.0);
//! let mut b = a.clone();
//! b.mean_torque_nm = Some(101.0);
//! let e = relative_errors(&b, &a);
//! assert_eq!(KEYS[0].key, "mean_torque_nm");
//! assert!((e[0].unwrap() - 0.01).abs() < 1e-12);
//! ```

use enginedyn_engine::{Engine, RodModel};
use enginedyn_ingest::{Diagram, GridOptions, Interp, Resampled, Trace};
use enginedyn_kinematics::Model;
use enginedyn_numerics::integrate::Rule;
use enginedyn_pipeline::{Key, Options, Scope, Summary, key};
use enginedyn_synth::{CycleModel, CycleSolution};
use std::time::Instant;

/// What went wrong.
#[derive(Debug, thiserror::Error)]
pub enum AccuracyError {
    /// A pipeline run failed.
    #[error(transparent)]
    Pipeline(#[from] enginedyn_pipeline::PipelineError),
    /// Resampling the diagram failed.
    #[error(transparent)]
    Ingest(#[from] enginedyn_ingest::IngestError),
    /// The generated diagram could not be built.
    #[error("generated diagram: {0}")]
    Synth(String),
    /// No method setting meets the tolerance.
    #[error(
        "no method setting meets --tolerance {tolerance}: even a {step}° grid leaves an estimated {best:.2e} of grid error, and half the tolerance is its budget; loosen the tolerance"
    )]
    Unreachable {
        /// Asked for.
        tolerance: f64,
        /// Best estimated relative error found.
        best: f64,
        /// Finest step tried (deg).
        step: f64,
    },
    /// An option kept beside `--tolerance` cannot meet it.
    #[error(
        "{option} cannot meet --tolerance {tolerance}: with it the key results are estimated {estimated:.2e} off; drop {option} to let --tolerance choose, or loosen the tolerance"
    )]
    KeptUnreachable {
        /// Asked for.
        tolerance: f64,
        /// The option, as given.
        option: String,
        /// The estimated error with it.
        estimated: f64,
    },
    /// A bad tolerance value.
    #[error("--tolerance {0}: a relative error between 1e-6 and 0.5 is needed")]
    BadTolerance(f64),
}

/// The key results whose errors are measured: every `summary.json` figure
/// a method setting can move, kinematic extremes included (the speed, the
/// geometry, the mean piston speed, the journal's number and the energy
/// balance's own round-off are not results of a method).
pub const KEYS: &[&Key] = &[
    key("mean_torque_nm"),
    key("power_kw"),
    key("indicated_mean_torque_nm"),
    key("indicated_power_kw"),
    key("torque_max_nm"),
    key("torque_min_nm"),
    key("torque_nonuniformity"),
    key("excess_work_j"),
    key("excess_work_coefficient"),
    key("required_inertia_kg_m2"),
    key("flywheel_inertia_kg_m2"),
    key("flywheel_gd2_n_m2"),
    key("flywheel_outer_diameter_m"),
    key("flywheel_mass_kg"),
    key("flywheel_width_m"),
    key("speed_fluctuation_achieved"),
    key("piston_speed_max_m_s"),
    key("piston_accel_max_m_s2"),
    key("piston_accel_min_m_s2"),
    key("gas_force_max_n"),
    key("side_force_max_n"),
    key("rod_force_max_n"),
    key("crankpin_load_max_n"),
    key("crankpin_load_mean_n"),
    key("journal_torque_max_nm"),
    key("imep_bar"),
    key("indicated_work_per_cylinder_j"),
];

/// A key result's value in a summary (`None` when absent or not computed:
/// the kinematic extremes are `NaN` in [`Scope::Keys`]).
pub fn key_value(s: &Summary, key: &Key) -> Option<f64> {
    key.number(s).filter(|x| x.is_finite())
}

/// Relative errors of `got` against `reference`, key by key of [`KEYS`]
/// (`None` where either lacks the figure). Torque figures are relative to
/// the larger of their own size and a tenth of the torque swing, so that a
/// torque minimum near zero does not turn a small absolute error into a
/// huge relative one.
pub fn relative_errors(got: &Summary, reference: &Summary) -> Vec<Option<f64>> {
    let swing = match (reference.torque_max_nm, reference.torque_min_nm) {
        (Some(a), Some(b)) => 0.1 * (a - b).abs(),
        _ => 0.0,
    };
    KEYS.iter()
        .map(|k| {
            let (g, r) = (key_value(got, k)?, key_value(reference, k)?);
            let floor = if k.key.contains("torque_") && !k.key.contains("nonuniformity") {
                swing
            } else {
                0.0
            };
            let den = r.abs().max(floor);
            Some(if den > 0.0 {
                (g - r).abs() / den
            } else {
                (g - r).abs()
            })
        })
        .collect()
}

fn max_error(e: &[Option<f64>]) -> Option<f64> {
    e.iter().flatten().copied().reduce(f64::max)
}

/// One method study (the `study` column of `accuracy.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Study {
    /// Exact or series kinematics.
    Kinematics,
    /// Two-mass, three-mass or rigid rod.
    RodModel,
    /// Linear, spline or pchip.
    Interpolation,
    /// Crank-angle grid step.
    GridStep,
    /// Trapezoid or Simpson.
    Integration,
}

impl Study {
    /// As written in `accuracy.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Study::Kinematics => "kinematics",
            Study::RodModel => "rod_model",
            Study::Interpolation => "interpolation",
            Study::GridStep => "grid_step",
            Study::Integration => "integration",
        }
    }
}

/// One method setting measured.
#[derive(Debug, Clone)]
pub struct Row {
    /// Which study.
    pub study: Study,
    /// The setting, spelled as the option (with the basis when not the reference).
    pub setting: String,
    /// Run time of one analysis with this setting (s, best of a few).
    pub time_s: f64,
    /// Relative error per key of [`KEYS`].
    pub errors: Vec<Option<f64>>,
}

impl Row {
    /// The largest relative error over the keys.
    pub fn max_relative_error(&self) -> Option<f64> {
        max_error(&self.errors)
    }
}

/// The whole study.
#[derive(Debug, Clone)]
pub struct Accuracy {
    /// Every setting measured.
    pub rows: Vec<Row>,
    /// The reference setting's own run time (s).
    pub reference_time_s: f64,
    /// What the reader should know.
    pub notes: Vec<String>,
}

/// What the studies need: the engine, the parsed diagram and how to put it
/// on a grid (pegging, volume law), and the speed.
pub struct Input<'a> {
    /// The engine.
    pub engine: &'a Engine,
    /// The parsed diagram (every trace).
    pub diagram: &'a Diagram,
    /// Grid options besides step and interpolation (pegging, volume law).
    pub grid: GridOptions,
    /// Speed (rpm).
    pub rpm: f64,
}

/// The most exact rod model the engine file supports.
pub fn best_rod(engine: &Engine) -> RodModel {
    if engine.masses().rod_inertia.is_some() {
        RodModel::Rigid
    } else {
        RodModel::TwoMass
    }
}

/// The reference setting.
pub fn reference(engine: &Engine) -> Options {
    Options {
        step_deg: 0.01,
        kinematics: Model::Exact,
        rod_model: Some(best_rod(engine)),
        interp: Interp::Spline,
        integration: Rule::Trapezoid,
        scope: Scope::Keys,
    }
}

/// Grid steps studied (deg), coarse to fine; only those that divide the
/// cycle and put every firing angle on the grid are used.
pub const STEPS: [f64; 10] = [10.0, 5.0, 4.0, 2.0, 1.0, 0.5, 0.25, 0.2, 0.1, 0.05];

/// The halving ladders of grid steps [`choose`] climbs down (deg): powers
/// of two, and 15° halved, whose steps divide the 90° and 60° firing
/// intervals of V8s and V12s (and 180°, 120°) from 15° down.
pub const LADDERS: [[f64; 9]; 2] = [
    [16.0, 8.0, 4.0, 2.0, 1.0, 0.5, 0.25, 0.125, 0.0625],
    [
        15.0, 7.5, 3.75, 1.875, 0.9375, 0.46875, 0.234375, 0.1171875, 0.05859375,
    ],
];

/// The ladder for `engine`: the steps of [`LADDERS`] that fit it, from the
/// ladder whose coarsest fitting step is the coarsest (the powers of two
/// on a tie).
pub fn ladder(engine: &Engine) -> Vec<f64> {
    ladder_steps(engine)
}

fn ladder_steps(engine: &Engine) -> Vec<f64> {
    let fitting = |l: &[f64; 9]| -> Vec<f64> {
        l.iter()
            .copied()
            .filter(|&s| step_fits(engine, s))
            .collect()
    };
    let (a, b) = (fitting(&LADDERS[0]), fitting(&LADDERS[1]));
    if b.first().copied().unwrap_or(0.0) > a.first().copied().unwrap_or(0.0) {
        b
    } else {
        a
    }
}

/// True when `step` divides the cycle and every firing angle.
pub fn step_fits(engine: &Engine, step: f64) -> bool {
    let fits = |a: f64| {
        let k = a / step;
        (k - k.round()).abs() < 1e-6
    };
    fits(engine.cycle().to_degrees()) && engine.firing_angles().iter().all(|a| fits(a.to_degrees()))
}

/// Runs `f` a few times (at least once, up to 5 or 0.2 s) and returns its
/// value and its shortest run time.
fn timed<T>(mut f: impl FnMut() -> Result<T, AccuracyError>) -> Result<(T, f64), AccuracyError> {
    let start = Instant::now();
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..5 {
        let t = Instant::now();
        let v = f()?;
        best = best.min(t.elapsed().as_secs_f64());
        out = Some(v);
        if start.elapsed().as_secs_f64() > 0.2 {
            break;
        }
    }
    match out {
        Some(v) => Ok((v, best)),
        None => unreachable!("the loop runs at least once"),
    }
}

fn run(input: &Input, opts: &Options) -> Result<Summary, AccuracyError> {
    let grid = GridOptions {
        step_deg: opts.step_deg,
        interp: opts.interp,
        ..input.grid.clone()
    };
    let r = enginedyn_ingest::resample_with(input.diagram, &grid)?;
    Ok(enginedyn_pipeline::analyse(input.engine, &r, input.rpm, opts)?.summary)
}

fn run_grid(
    engine: &Engine,
    p: &Resampled,
    rpm: f64,
    opts: &Options,
) -> Result<Summary, AccuracyError> {
    Ok(enginedyn_pipeline::analyse(engine, p, rpm, opts)?.summary)
}

/// The generated diagram for the closed-form studies: the project's cycle
/// model for this engine's cylinder (diesel above a compression ratio of
/// 14, petrol below; the two-stroke model for a two-stroke).
pub fn generated(engine: &Engine) -> Result<(CycleSolution, &'static str), AccuracyError> {
    let cyl = engine.cylinder();
    let (model, name) = if engine.cycle().to_degrees() < 400.0 {
        (CycleModel::petrol_two_stroke(), "two-stroke")
    } else if cyl.compression_ratio() >= 14.0 {
        (CycleModel::diesel_full_load(), "diesel")
    } else {
        (CycleModel::petrol_full_load(), "petrol")
    };
    let sol = CycleSolution::new(cyl, &model).map_err(|e| AccuracyError::Synth(e.to_string()))?;
    Ok((sol, name))
}

/// The generated pressure on a grid of `step` degrees.
fn on_grid(sol: &CycleSolution, cycle_deg: f64, step: f64) -> Resampled {
    let n = (cycle_deg / step).round() as usize;
    Resampled::from_grid(
        step,
        (0..n).map(|k| sol.pressure(k as f64 * step)).collect(),
    )
}

/// The median spacing of the diagram's first trace (deg).
fn data_step(d: &Diagram) -> Option<f64> {
    let t = d.traces.first()?;
    let mut gaps: Vec<f64> = t.angle_deg.windows(2).map(|w| w[1] - w[0]).collect();
    if gaps.is_empty() {
        return None;
    }
    gaps.sort_by(f64::total_cmp);
    Some(gaps[gaps.len() / 2])
}

/// Every study of the module docs.
pub fn study(input: &Input) -> Result<Accuracy, AccuracyError> {
    let engine = input.engine;
    let reference = reference(engine);
    let mut notes = Vec::new();
    if best_rod(engine) != RodModel::Rigid {
        notes.push(
            "no masses.rod_inertia_kg_m2: the reference rod is the two-mass model, and the rod study has nothing to compare".into(),
        );
    }
    let (ref_summary, reference_time_s) = timed(|| run(input, &reference))?;
    let mut rows = Vec::new();
    let mut vary = |study: Study, setting: String, opts: Options| -> Result<(), AccuracyError> {
        let (s, t) = timed(|| run(input, &opts))?;
        rows.push(Row {
            study,
            setting,
            time_s: t,
            errors: relative_errors(&s, &ref_summary),
        });
        Ok(())
    };
    // Model choices are varied from the everyday setting (the 0.1° grid,
    // otherwise the reference's methods), so their rows show what a run
    // costs and how far it lands from the reference; the grid study shows
    // the grid's own share.
    let base = Options {
        step_deg: if step_fits(engine, 0.1) {
            0.1
        } else {
            reference.step_deg
        },
        ..reference
    };
    let offset = engine.mechanism().phi_tdc() != 0.0;
    for m in [Model::Exact, Model::Series2, Model::Series4, Model::Series6] {
        if offset && matches!(m, Model::Series4 | Model::Series6) {
            continue;
        }
        let o = Options {
            kinematics: m,
            ..base
        };
        vary(Study::Kinematics, m.name().into(), o)?;
    }
    if offset {
        notes.push("pin offset: series4 and series6 are not defined, left out".into());
    }
    let rods: &[RodModel] = if best_rod(engine) == RodModel::Rigid {
        &[RodModel::TwoMass, RodModel::ThreeMass, RodModel::Rigid]
    } else {
        &[RodModel::TwoMass]
    };
    for &r in rods {
        let o = Options {
            rod_model: Some(r),
            ..base
        };
        vary(Study::RodModel, r.name().into(), o)?;
    }
    for rule in [Rule::Trapezoid, Rule::Simpson] {
        for step in [1.0, 0.1] {
            if !step_fits(engine, step) {
                continue;
            }
            let o = Options {
                integration: rule,
                step_deg: step,
                ..reference
            };
            vary(Study::Integration, format!("{} at {step}°", rule.name()), o)?;
        }
    }
    // The user's data: interpolation and grid step as differences only.
    for interp in [Interp::Linear, Interp::Spline, Interp::Pchip] {
        let o = Options { interp, ..base };
        vary(
            Study::Interpolation,
            format!(
                "{} (this diagram: difference from spline at 0.01°)",
                interp.name()
            ),
            o,
        )?;
    }
    for step in STEPS.into_iter().filter(|&s| step_fits(engine, s)) {
        let o = Options {
            step_deg: step,
            ..reference
        };
        vary(
            Study::GridStep,
            format!("{step}° (this diagram: difference from 0.01°)"),
            o,
        )?;
    }
    rows.extend(against_generated(input, &reference, &mut notes)?);
    Ok(Accuracy {
        rows,
        reference_time_s,
        notes,
    })
}

/// The studies against the generated diagram, known at every angle (true
/// errors): interpolation from samples at this diagram's spacing, and the
/// grid step; their note goes to `notes`.
fn against_generated(
    input: &Input,
    reference: &Options,
    notes: &mut Vec<String>,
) -> Result<Vec<Row>, AccuracyError> {
    let engine = input.engine;
    let cycle = engine.cycle().to_degrees();
    let mut rows = Vec::new();
    // The generated diagram, known at every angle: true errors.
    let (sol, model) = generated(engine)?;
    let truth = on_grid(&sol, cycle, reference.step_deg);
    let truth_summary = run_grid(engine, &truth, input.rpm, reference)?;
    let sampling = data_step(input.diagram)
        .filter(|&s| s > 0.11)
        .unwrap_or(1.0);
    notes.push(format!(
        "interpolation and grid-step errors against the generated {model} diagram, known at every angle; interpolation from samples every {sampling:.3}° (this diagram's spacing, or 1° when it is finer than 0.1°)"
    ));
    let n_data = (cycle / sampling).round() as usize;
    let samples = Diagram {
        quantity: enginedyn_ingest::Quantity::Pressure,
        rpm: None,
        traces: vec![Trace {
            cycle: 0,
            cylinder: 0,
            angle_deg: (0..n_data)
                .map(|k| k as f64 * cycle / n_data as f64)
                .collect(),
            values: (0..n_data)
                .map(|k| sol.pressure(k as f64 * cycle / n_data as f64))
                .collect(),
            rpm: None,
        }],
        cycle_deg: cycle,
        pv: false,
        cycles_skipped: 0,
        skipped: Vec::new(),
        notes: Vec::new(),
        peak_rule: None,
    };
    for interp in [Interp::Linear, Interp::Spline, Interp::Pchip] {
        let opts = Options {
            interp,
            ..*reference
        };
        let grid = GridOptions {
            step_deg: reference.step_deg,
            interp,
            ..input.grid.clone()
        };
        let (s, t) = timed(|| {
            let r = enginedyn_ingest::resample_with(&samples, &grid)?;
            run_grid(engine, &r, input.rpm, &opts)
        })?;
        rows.push(Row {
            study: Study::Interpolation,
            setting: format!("{} (generated, from {sampling:.3}° samples)", interp.name()),
            time_s: t,
            errors: relative_errors(&s, &truth_summary),
        });
    }
    for step in STEPS.into_iter().filter(|&s| step_fits(engine, s)) {
        let p = on_grid(&sol, cycle, step);
        let opts = Options {
            step_deg: step,
            ..*reference
        };
        let (s, t) = timed(|| run_grid(engine, &p, input.rpm, &opts))?;
        rows.push(Row {
            study: Study::GridStep,
            setting: format!("{step}° (generated)"),
            time_s: t,
            errors: relative_errors(&s, &truth_summary),
        });
    }
    Ok(rows)
}

/// Indices of the rows on the Pareto front: no other row is both faster
/// and more accurate. Rows without an error are left out.
pub fn pareto(rows: &[Row]) -> Vec<usize> {
    let pts: Vec<(usize, f64, f64)> = rows
        .iter()
        .enumerate()
        .filter_map(|(i, r)| Some((i, r.time_s, r.max_relative_error()?)))
        .collect();
    let mut front: Vec<usize> = pts
        .iter()
        .filter(|&&(i, t, e)| {
            !pts.iter()
                .any(|&(j, t2, e2)| j != i && t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .map(|&(i, _, _)| i)
        .collect();
    front.sort_by(|&a, &b| rows[a].time_s.total_cmp(&rows[b].time_s));
    front
}

/// The printed table of `enginedyn accuracy`: a line naming the engine, the
/// speed, the reference and its run time, then one row per setting (its
/// time, its largest relative error and the key it falls on), the Pareto
/// front marked.
pub fn table(a: &Accuracy, engine: &Engine, rpm: f64) -> String {
    use std::fmt::Write as _;
    let front = pareto(&a.rows);
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{} at {rpm} rpm: errors against exact kinematics, the {} rod, the periodic spline, 0.01° and the trapezoid rule (reference run {:.2} ms)\n",
        engine.name(),
        best_rod(engine).name(),
        a.reference_time_s * 1e3
    );
    let _ = writeln!(
        t,
        "{:<14} {:<52} {:>10} {:>10}  worst key",
        "study", "setting", "time ms", "max error"
    );
    for (i, r) in a.rows.iter().enumerate() {
        let worst = r
            .errors
            .iter()
            .zip(KEYS)
            .filter_map(|(e, k)| Some((e.as_ref()?, k)))
            .max_by(|a, b| a.0.total_cmp(b.0))
            .map_or("", |(_, k)| k.key);
        let _ = writeln!(
            t,
            "{:<14} {:<52} {:>10.3} {:>10}  {}{}",
            r.study.name(),
            r.setting,
            r.time_s * 1e3,
            r.max_relative_error()
                .map(|e| format!("{e:.1e}"))
                .unwrap_or_else(|| "-".into()),
            worst,
            if front.contains(&i) { "  (Pareto)" } else { "" }
        );
    }
    t
}

/// `accuracy.csv`: `study`, `setting`, `time_s`, `max_relative_error`,
/// then one error column per key (empty where the figure does not exist).
pub fn csv(a: &Accuracy) -> String {
    let mut out = String::from("study,setting,time_s,max_relative_error");
    for k in KEYS {
        out.push(',');
        out.push_str(k.key);
    }
    out.push('\n');
    let num = |v: Option<f64>| v.map(enginedyn_numerics::format::csv).unwrap_or_default();
    // Text cells never start a formula (`format::csv_text`).
    let text = enginedyn_numerics::format::csv_text;
    for r in &a.rows {
        out.push_str(&format!(
            "{},\"{}\",{},{}",
            text(r.study.name()),
            text(&r.setting).replace('"', "\"\""),
            enginedyn_numerics::format::csv(r.time_s),
            num(r.max_relative_error())
        ));
        for e in &r.errors {
            out.push(',');
            out.push_str(&num(*e));
        }
        out.push('\n');
    }
    out
}

/// `accuracy.svg`: every method setting as a labelled marker ("series2",
/// "1°", "pchip"), time per analysis (ms) against the largest relative
/// error of the key results, log-log. Studies are told apart by marker
/// shape and colour (named as in `accuracy.csv`); filled markers are errors against the reference or
/// the generated diagram's truth, hollow ones differences on this diagram.
/// The Pareto front is a step line, and faint guides at the tolerances
/// 1e-2, 1e-3 and 1e-4 name the cheapest setting within each.
pub fn figure(a: &Accuracy, engine_name: &str) -> enginedyn_report::ScatterChart {
    use enginedyn_report::{ScatterChart, ScatterGroup, ScatterPoint};
    // A zero error cannot sit on log axes: drawn at a floor instead.
    const FLOOR: f64 = 1e-12;
    let point = |r: &Row| Some((r.time_s * 1e3, r.max_relative_error()?.max(FLOOR)));
    let mut groups: Vec<ScatterGroup> = Vec::new();
    let mut floored = false;
    for r in &a.rows {
        let Some((x, y)) = point(r) else { continue };
        floored |= y <= FLOOR;
        let differences = r.setting.contains("difference");
        let basis = if r.setting.contains("generated") {
            " (generated diagram)"
        } else if differences {
            " (this diagram, difference)"
        } else {
            ""
        };
        let name = format!("{}{basis}", r.study.name());
        // The setting without its basis: "1°", "pchip", "simpson 1°".
        let label = r
            .setting
            .split(" (")
            .next()
            .unwrap_or(&r.setting)
            .replace(" at ", " ");
        let p = ScatterPoint { x, y, label };
        match groups.iter_mut().find(|g| g.name == name) {
            Some(g) => g.points.push(p),
            None => groups.push(ScatterGroup {
                name,
                style: r.study as usize,
                filled: !differences,
                points: vec![p],
            }),
        }
    }
    let front: Vec<usize> = pareto(&a.rows);
    let corners = front.iter().filter_map(|&i| point(&a.rows[i])).collect();
    let guides = [1e-2, 1e-3, 1e-4]
        .into_iter()
        .map(|tol| {
            let best = front
                .iter()
                .map(|&i| &a.rows[i])
                .find(|r| r.max_relative_error().is_some_and(|e| e <= tol));
            let text = match best {
                Some(r) => format!(
                    "tolerance {tol:.0e}: cheapest {} {}, {:.3} ms",
                    r.study.name(),
                    r.setting.split(" (").next().unwrap_or(&r.setting),
                    r.time_s * 1e3
                ),
                None => format!("tolerance {tol:.0e}: no setting"),
            };
            (tol, text)
        })
        .collect();
    ScatterChart {
        file: "accuracy.svg".into(),
        title: format!(
            "{engine_name}: accuracy against cost of each method setting{}",
            if floored {
                " (a zero error drawn at 1e-12)"
            } else {
                ""
            }
        ),
        x_label: "time per analysis (ms)".into(),
        y_label: "largest relative error of the key results".into(),
        groups,
        steps: Some((
            "Pareto front (nothing both faster and more exact)".into(),
            corners,
        )),
        guides,
    }
}

/// What [`choose`] picked.
#[derive(Debug, Clone)]
pub struct Choice {
    /// The method setting.
    pub options: Options,
    /// Its estimated largest relative error on the key results.
    pub estimated: f64,
    /// How the estimate was made, and each model that differs from the
    /// engine file's and the defaults, with why it may.
    pub notes: Vec<String>,
}

/// Method options given explicitly beside `--tolerance`: [`choose`] keeps
/// them and chooses the rest around them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Kept {
    /// `--step`.
    pub step_deg: Option<f64>,
    /// `--kinematics`.
    pub kinematics: Option<Model>,
    /// `--rod-model`.
    pub rod_model: Option<RodModel>,
    /// `--interp`.
    pub interp: Option<Interp>,
    /// `--integration`.
    pub integration: Option<Rule>,
}

/// The cheapest setting whose estimated error on every key result
/// ([`KEYS`], kinematic extremes included) stays within `tolerance`
/// (relative), without any run of the reference; the options in `kept`
/// are kept as given and the rest chosen around them:
///
/// - grid step: runs down the halving [`ladder`] from the coarsest step
///   that fits the engine, each compared with the one twice as coarse (a
///   Richardson-style estimate, conservative by about 3 for second-order
///   convergence) and with the difference before it over 4, since nested
///   grids can miss an extreme (a torque minimum) equally at h and 2h. From
///   the third grid on (two differences show whether the grids converge;
///   one does not), the first step is taken whose estimate is within half
///   the tolerance, or within the tolerance when its last difference alone
///   is within a quarter of it (converged; only the conservative second
///   term is large). A kept step is estimated the same way from the two
///   steps above it (or, when they do not fit the engine, as twice its
///   difference from the step half as large).
/// - models: on the ladder's grid nearest 1° (the chosen one when coarser), the
///   rod models (two-mass, three-mass) with exact kinematics, then the
///   series (2, 4, 6) with the rod chosen are compared with exact
///   kinematics and the most exact rod, every key result and the piston
///   speed and acceleration extremes included; the simplest whose
///   difference plus the grid estimate stays within the tolerance is taken.
///   The series truncation (a-priori: `lambda^(order+1)` terms) and the rod
///   couple `(I_G - m l_A l_B) w^2 beta'' beta'` are what these differences
///   measure.
///
/// Interpolation stays `auto` and integration is Simpson's rule unless
/// kept (exact like the trapezoid for the periodic cycle integrals,
/// fourth-order for the running integral `E(phi)` where the trapezoid is
/// second-order; the `integration` rows of `accuracy.csv` show the
/// difference at 1°); both effects are within the grid estimate, which is
/// made with them. Each grid run uses [`Scope::Keys`], each model run
/// [`Scope::Summary`] (the kinematic extremes); the caller repeats the
/// chosen setting with its own outputs.
pub fn choose(
    engine: &Engine,
    rpm: f64,
    tolerance: f64,
    kept: &Kept,
    resample: &dyn Fn(f64, Interp) -> Result<Resampled, AccuracyError>,
) -> Result<Choice, AccuracyError> {
    if !(1e-6..=0.5).contains(&tolerance) {
        return Err(AccuracyError::BadTolerance(tolerance));
    }
    // Each grid is resampled once and kept for the model runs.
    let cache: std::cell::RefCell<Vec<(f64, Resampled)>> = std::cell::RefCell::new(Vec::new());
    let run = |o: &Options| -> Result<Summary, AccuracyError> {
        let hit = cache
            .borrow()
            .iter()
            .position(|(h, _)| (h - o.step_deg).abs() < 1e-12);
        let k = match hit {
            Some(k) => k,
            None => {
                let r = resample(o.step_deg, o.interp)?;
                cache.borrow_mut().push((o.step_deg, r));
                cache.borrow().len() - 1
            }
        };
        let c = cache.borrow();
        run_grid(engine, &c[k].1, rpm, o)
    };
    let best = best_rod(engine);
    let base = Options {
        step_deg: 0.1,
        kinematics: Model::Exact,
        rod_model: Some(kept.rod_model.unwrap_or(best)),
        interp: kept.interp.unwrap_or(Interp::Auto),
        integration: kept.integration.unwrap_or(Rule::Simpson),
        scope: Scope::Keys,
    };
    let run_at = |step: f64| {
        run(&Options {
            step_deg: step,
            ..base
        })
    };
    let mut ladder: Vec<(f64, Summary)> = Vec::new();
    let (step, grid_est) = match kept.step_deg {
        Some(h) => (h, kept_grid(engine, h, tolerance, &run_at, &mut ladder)?),
        None => halving_ladder(engine, tolerance, &run_at, &mut ladder)?,
    };
    // Model differences hardly depend on the grid: measured on the ladder's
    // grid nearest 1° no finer than the chosen one (cheaper than the chosen
    // one when that is finer), against exact kinematics and the most exact
    // rod, with the kinematic extremes (Scope::Summary).
    let model_step = ladder
        .iter()
        .map(|(h, _)| *h)
        .filter(|h| *h >= step)
        .min_by(|a, b| a.ln().abs().total_cmp(&b.ln().abs()))
        .unwrap_or(step);
    let model_run = |m: Model, r: RodModel| {
        run(&Options {
            step_deg: model_step,
            kinematics: m,
            rod_model: Some(r),
            scope: Scope::Summary,
            ..base
        })
    };
    let reference_summary = model_run(Model::Exact, best)?;
    let model_error = |m: Model, r: RodModel| -> Result<f64, AccuracyError> {
        if m == Model::Exact && r == best {
            return Ok(0.0);
        }
        Ok(summary_difference(&model_run(m, r)?, &reference_summary))
    };
    let mut notes = vec![match kept.step_deg {
        Some(h) => format!(
            "--tolerance {tolerance}: grid {h}° kept as given (estimated {} from the steps beside it)",
            human(grid_est)
        ),
        None => format!(
            "--tolerance {tolerance}: grid {step}° (estimated {} from the step before)",
            human(grid_est)
        ),
    }];
    // The rod first (with exact kinematics), then the simplest kinematics
    // with that rod; each pair's difference is measured as a whole.
    let rod = match kept.rod_model {
        Some(r) => r,
        None => simplest_rod(best, grid_est, tolerance, &model_error)?,
    };
    let offset = engine.mechanism().phi_tdc() != 0.0;
    let candidates: Vec<Model> = match kept.kinematics {
        Some(m) => vec![m],
        None => [Model::Series2, Model::Series4, Model::Series6, Model::Exact]
            .into_iter()
            .filter(|m| !(offset && matches!(m, Model::Series4 | Model::Series6)))
            .collect(),
    };
    for m in candidates {
        let model_est = model_error(m, rod)?;
        if grid_est + model_est > tolerance {
            continue;
        }
        let options = Options {
            step_deg: step,
            kinematics: m,
            rod_model: Some(rod),
            ..base
        };
        notes.extend(why_models(engine, kept, &options, model_est, model_step));
        return Ok(Choice {
            options,
            estimated: grid_est + model_est,
            notes,
        });
    }
    // Only a kept option can leave nothing (exact kinematics with the most
    // exact rod adds no model error).
    let (option, estimated) = match (kept.kinematics, kept.rod_model) {
        (Some(m), _) => (
            format!("--kinematics {}", m.name()),
            grid_est + model_error(m, rod)?,
        ),
        (None, Some(r)) => (
            format!("--rod-model {}", r.name()),
            grid_est + model_error(Model::Exact, r)?,
        ),
        (None, None) => (format!("--step {step}"), grid_est),
    };
    Err(AccuracyError::KeptUnreachable {
        tolerance,
        option,
        estimated,
    })
}

/// The largest relative difference between two runs' results.
fn summary_difference(a: &Summary, b: &Summary) -> f64 {
    max_error(&relative_errors(a, b)).unwrap_or(0.0)
}

/// The grid error of the kept step `h` (deg): from the two steps above it
/// when they fit, else from the step half as large; the runs go to
/// `ladder`. An error when it exceeds `tolerance`.
fn kept_grid(
    engine: &Engine,
    h: f64,
    tolerance: f64,
    run_at: &dyn Fn(f64) -> Result<Summary, AccuracyError>,
    ladder: &mut Vec<(f64, Summary)>,
) -> Result<f64, AccuracyError> {
    let diff = summary_difference;
    let est = if step_fits(engine, 2.0 * h) && step_fits(engine, 4.0 * h) {
        let (s4, s2, s1) = (run_at(4.0 * h)?, run_at(2.0 * h)?, run_at(h)?);
        let est = diff(&s1, &s2).max(diff(&s2, &s4) / 4.0);
        ladder.extend([(4.0 * h, s4), (2.0 * h, s2), (h, s1)]);
        est
    } else if step_fits(engine, 0.5 * h) {
        let (s1, s_half) = (run_at(h)?, run_at(0.5 * h)?);
        let est = 2.0 * diff(&s1, &s_half);
        ladder.extend([(h, s1), (0.5 * h, s_half)]);
        est
    } else {
        return Err(AccuracyError::KeptUnreachable {
            tolerance,
            option: format!("--step {h}"),
            estimated: f64::INFINITY,
        });
    };
    if est > tolerance {
        return Err(AccuracyError::KeptUnreachable {
            tolerance,
            option: format!("--step {h}"),
            estimated: est,
        });
    }
    Ok(est)
}

/// The step (deg) a halving ladder ([`ladder_steps`]) reaches within
/// `tolerance`, and its estimated grid error; the runs go to `ladder`.
fn halving_ladder(
    engine: &Engine,
    tolerance: f64,
    run_at: &dyn Fn(f64) -> Result<Summary, AccuracyError>,
    ladder: &mut Vec<(f64, Summary)>,
) -> Result<(f64, f64), AccuracyError> {
    // A halving ladder, so that each estimate compares h with 2h.
    let steps = ladder_steps(engine);
    let mut found = None;
    let mut last = (f64::INFINITY, 0.0);
    // The previous difference, once there is one: a single
    // difference (two grids) cannot show that the grids converge,
    // so a step is taken only from the third grid on.
    let mut before: Option<f64> = None;
    for &step in &steps {
        let s = run_at(step)?;
        if let Some((h2, p)) = ladder.last()
            && (h2 / step - 2.0).abs() < 1e-9
        {
            // The difference from 2h, and the difference before it
            // over 4 (what second-order convergence leaves of it):
            // nested grids can sample an extreme equally badly at h
            // and 2h, and then the last difference alone says too
            // little.
            let d = summary_difference(p, &s);
            if let Some(b) = before {
                let est = d.max(b / 4.0);
                last = (est, step);
                // Within half the tolerance; or within it when the
                // last difference alone is within a quarter
                // (converged, and only the conservative second term
                // is large).
                if est <= 0.5 * tolerance || est <= tolerance && d <= 0.25 * tolerance {
                    found = Some((step, est));
                    ladder.push((step, s));
                    break;
                }
            } else {
                last = (d, step);
            }
            before = Some(d);
        } else {
            before = None;
        }
        ladder.push((step, s));
    }
    found.ok_or(AccuracyError::Unreachable {
        tolerance,
        best: last.0,
        step: last.1,
    })
}

/// The simplest rod model whose `model_error` with exact kinematics, added
/// to the grid estimate `grid_est`, stays within `tolerance`: two-mass,
/// then three-mass where `best` is rigid; else `best`.
fn simplest_rod(
    best: RodModel,
    grid_est: f64,
    tolerance: f64,
    model_error: &dyn Fn(Model, RodModel) -> Result<f64, AccuracyError>,
) -> Result<RodModel, AccuracyError> {
    for r in [RodModel::TwoMass, RodModel::ThreeMass] {
        if r == best || best != RodModel::Rigid && r == RodModel::ThreeMass {
            continue;
        }
        if grid_est + model_error(Model::Exact, r)? <= tolerance {
            return Ok(r);
        }
    }
    Ok(best)
}

/// The notes of a choice: each model that differs from the engine file's
/// and the defaults, and why it may.
fn why_models(
    engine: &Engine,
    kept: &Kept,
    o: &Options,
    model_est: f64,
    model_step: f64,
) -> Vec<String> {
    let mut notes = Vec::new();
    let rod = o.rod_model.unwrap_or(engine.rod_model());
    let best = best_rod(engine);
    let mut differ = Vec::new();
    if rod != engine.rod_model() {
        differ.push(format!(
            "the {} rod, not the engine file's {}{}",
            rod.name(),
            engine.rod_model().name(),
            if kept.rod_model.is_some() {
                " (kept as given)"
            } else {
                ""
            }
        ));
    }
    if o.kinematics != Model::Exact {
        differ.push(format!(
            "{} kinematics, not exact (the default){}",
            o.kinematics.name(),
            if kept.kinematics.is_some() {
                " (kept as given)"
            } else {
                ""
            }
        ));
    }
    if !differ.is_empty() {
        notes.push(format!(
            "--tolerance: {}: together {} off exact kinematics with the {} rod on the {model_step}° grid",
            differ.join("; "),
            if model_est == 0.0 { "nothing".to_string() } else { human(model_est) },
            best.name()
        ));
    }
    if o.integration != Rule::Trapezoid && kept.integration.is_none() {
        notes.push(
            "--tolerance: Simpson's rule, not the trapezoid (the default): fourth order for E(φ), the same cycle integrals"
                .to_string(),
        );
    }
    notes
}

/// An estimate in a note: two significant digits.
fn human(x: f64) -> String {
    enginedyn_numerics::format::sig(x, 2)
}
