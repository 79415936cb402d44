//! One operating point, end to end: a checked engine and its pressure on the
//! crank-angle grid in, every curve and summary figure out. This crate only
//! wires the stage crates together (kinematics → forces → torque →
//! flywheel); it holds no formula of its own, and it does no I/O.
//!
//! ```no_run
//! use enginedyn_pipeline::{analyse, Options};
//! # fn demo(engine: &enginedyn_engine::Engine, pressure: &enginedyn_ingest::Resampled) {
//! let a = analyse(engine, pressure, 4900.0, &Options::default()).unwrap();
//! println!("mean torque {:.1} N m", a.summary.mean_torque_nm.unwrap());
//! # }
//! ```

use enginedyn_engine::{Engine, RodModel};
use enginedyn_flywheel::{Flywheel, Uniformity};
use enginedyn_forces::{Forces, Setup, cylinder_forces};
use enginedyn_ingest::{Interp, Peg, Quantity, Resampled, mean_std};
use enginedyn_kinematics::{Model, Table};
use enginedyn_numerics::{extremes::periodic_abs_max, integrate, integrate::Rule, roots};
use enginedyn_torque::{EngineTorque, Harmonic};
use std::f64::consts::PI;
use std::sync::Arc;

pub mod column;
pub mod combustion;
pub mod notes;
pub mod schema;
mod summary;
pub mod tdc;
pub mod torsion;
pub use combustion::CombustionSummary;
pub use enginedyn_ingest::MostKnocking;
pub use summary::{
    Basis, BrakeSummary, Columns, CycleSummary, DesignSummary, Field, KEYS, Key, Pegging, Shown,
    Summary, Value, key,
};

/// Why an operating point cannot be analysed.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// A model is not defined for this mechanism.
    #[error(transparent)]
    Kinematics(#[from] enginedyn_kinematics::KinematicsError),
    /// The engine and a method option disagree.
    #[error(transparent)]
    Engine(#[from] enginedyn_engine::EngineError),
    /// Inconsistent input.
    #[error("{0}")]
    Input(String),
    /// A numerical step failed.
    #[error(transparent)]
    Numerics(#[from] enginedyn_numerics::NumericsError),
}

/// The method settings (INTERFACE.md's method options).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Grid step (deg).
    pub step_deg: f64,
    /// Kinematics model.
    pub kinematics: Model,
    /// Rod model; `None` takes the engine file's.
    pub rod_model: Option<RodModel>,
    /// Interpolation asked for.
    pub interp: Interp,
    /// Integration rule.
    pub integration: Rule,
    /// How much to compute besides the key results.
    pub scope: Scope,
}

/// How much of the analysis to compute. Every scope computes the key
/// results (mean torque and power, torque extremes, excess work and the
/// flywheel, force maxima, IMEP) the same way, so they agree bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Scope {
    /// The key results only, for runs that are compared rather than shown
    /// (method studies, the `--tolerance` ladder): no TDC-offset estimate,
    /// no cycle statistics, and the piston speed and acceleration maxima
    /// (which need a search of their own) left `NaN`.
    Keys,
    /// What `summary.json` holds and no more (a batch without `--detail`).
    Summary,
    /// Also the curves only reports show (main-bearing loads, torque
    /// harmonics).
    Full,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            step_deg: 0.1,
            kinematics: Model::Exact,
            rod_model: None,
            interp: Interp::Auto,
            integration: Rule::Trapezoid,
            scope: Scope::Full,
        }
    }
}

/// Everything computed for one operating point.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// Grid step (rad).
    pub step: f64,
    /// Cylinder 1's pressure (Pa, absolute) on the grid; empty for torque input.
    pub pressure: Vec<f64>,
    /// Cylinder 1's volume (m³); empty for torque input (shared with
    /// [`Tables`]).
    pub volume: Arc<Vec<f64>>,
    /// Cylinder 1's motion (shared with [`Tables`]).
    pub kinematics: Arc<Table>,
    /// Cylinder 1's torque (N m); empty when only the engine torque is known.
    pub cylinder_torque: Vec<f64>,
    /// Cylinder 1's forces and torque (empty vectors without pressure).
    pub forces: Forces,
    /// Engine and journal torques (indicated).
    pub torque: EngineTorque,
    /// Main-bearing load magnitudes (N), bearing 1 at the free end.
    pub bearings: Vec<Vec<f64>>,
    /// Uniformity of the indicated engine torque.
    pub uniformity: Uniformity,
    /// Flywheel, when the engine delivers work.
    pub flywheel: Option<Flywheel>,
    /// Harmonics of cylinder 1's torque.
    pub cylinder_harmonics: Vec<Harmonic>,
    /// Harmonics of the engine torque.
    pub engine_harmonics: Vec<Harmonic>,
    /// The summary figures.
    pub summary: Summary,
    /// Cylinder 1's mean trace's heat release on the grid, when the
    /// combustion analysis ran and the scope is [`Scope::Full`].
    pub heat_release: Option<enginedyn_combustion::Curves>,
    /// Each used cycle that burns: `(cylinder, cycle, IMEP bar, CA50 deg)`
    /// (the CA50–IMEP scatter).
    pub burn_cycles: Vec<(i64, i64, f64, f64)>,
    /// With knock measured: the most knocking cycle's band-passed pressure
    /// and the threshold (Pa), for `knock.svg`.
    pub most_knocking: Option<(enginedyn_ingest::MostKnocking, f64)>,
}

/// Below this IMEP (Pa) an engine runs near idle: idle IMEP is about
/// 1–2 bar gross.
pub const IDLE_IMEP_PA: f64 = 1.5e5;

/// Highest engine order in `harmonics.csv`.
pub const MAX_ORDER: f64 = 24.0;

/// What the front ends hand to [`complete`].
struct Parts {
    h: f64,
    rod_model: RodModel,
    pressure: Vec<f64>,
    volume: Arc<Vec<f64>>,
    kinematics: Arc<Table>,
    forces: Forces,
    cylinder_torque: Vec<f64>,
    torque: EngineTorque,
    bearings: Vec<Vec<f64>>,
    /// `∮ p dV` per cylinder (J), when pressure is known.
    work: Option<f64>,
    /// Force extremes over every cylinder, when pressure is known.
    force_max: Option<ForceMax>,
    notes: Vec<String>,
    interpolation: String,
    cycles: usize,
    /// Measured cycles left out of the averages (a gap in the data).
    cycles_skipped: usize,
    stats: Option<CycleSummary>,
    tdc_offset: Option<f64>,
    pegging: Option<Pegging>,
    /// Piston speed and acceleration extremes per unit crank speed, when
    /// [`Tables`] hold them.
    motion: Option<Extremes>,
}

/// Largest force magnitudes over every cylinder (N).
struct ForceMax {
    gas: f64,
    side: f64,
    rod: f64,
    pin: f64,
}

/// Statistics over the measured cycles, when there are several.
fn cycle_summary(r: &Resampled) -> Option<CycleSummary> {
    let st = &r.stats;
    if st.len() < 2 {
        return None;
    }
    let (p_mean, p_std) = mean_std(st.iter().map(|s| s.p_max));
    let (a_mean, a_std) = mean_std(st.iter().map(|s| s.p_max_angle_deg));
    let imep = st
        .iter()
        .all(|s| s.imep_pa.is_some())
        .then(|| mean_std(st.iter().filter_map(|s| s.imep_pa)));
    Some(CycleSummary {
        cycles: r.cycles,
        imep_std_bar: imep.map(|(_, s)| s / 1e5),
        imep_cov: imep.and_then(|(m, s)| (m.abs() > 0.0).then(|| s / m.abs())),
        p_max_mean_bar: p_mean / 1e5,
        p_max_cov: p_std / p_mean,
        p_max_angle_mean_deg: a_mean,
        p_max_angle_std_deg: a_std,
    })
}

/// How far a cycle's IMEP may lie from the median of the file's cycles, in
/// scaled median absolute deviations, before a note names it
/// (INTERFACE.md, "Plausibility").
const OUTLIER_MADS: f64 = 5.0;

/// The fewest cycles whose outliers a note names (INTERFACE.md).
const OUTLIER_MIN_CYCLES: usize = 8;

/// The least deviation from the median (a share of it) a note names.
const OUTLIER_MIN_SHARE: f64 = 0.02;

/// A CoV of IMEP above this gets a note.
const HIGH_COV: f64 = 0.10;

/// Notes on the measured cycles (INTERFACE.md, "Plausibility"): cycles
/// whose IMEP lies more than [`OUTLIER_MADS`] scaled MADs and more than
/// [`OUTLIER_MIN_SHARE`] of the median from the median, among at least
/// [`OUTLIER_MIN_CYCLES`] (kept, and named: a misfire?), and a CoV of IMEP
/// above [`HIGH_COV`].
/// Per cylinder when the traces name cylinders.
fn cycle_notes(r: &Resampled) -> Vec<String> {
    let mut notes = Vec::new();
    let mut cylinders: Vec<i64> = r.stats.iter().map(|s| s.cylinder).collect();
    cylinders.sort_unstable();
    cylinders.dedup();
    let bar = |x: f64| enginedyn_numerics::format::sig(x / 1e5, 3);
    for c in cylinders {
        let v: Vec<(i64, f64)> = r
            .stats
            .iter()
            .filter(|s| s.cylinder == c)
            .filter_map(|s| s.imep_pa.map(|i| (s.cycle, i)))
            .collect();
        if v.len() < 3 {
            continue;
        }
        let of = if c > 0 {
            format!(" of cylinder {c}")
        } else {
            String::new()
        };
        let median = |mut x: Vec<f64>| {
            x.sort_by(f64::total_cmp);
            let n = x.len();
            if n % 2 == 1 {
                x[n / 2]
            } else {
                0.5 * (x[n / 2 - 1] + x[n / 2])
            }
        };
        let med = median(v.iter().map(|p| p.1).collect());
        // The scaled MAD estimates the standard deviation of normal data.
        let mad = 1.4826 * median(v.iter().map(|p| (p.1 - med).abs()).collect());
        let floor = 1e-9 * med.abs().max(1.0);
        let out: Vec<&(i64, f64)> = if v.len() < OUTLIER_MIN_CYCLES {
            Vec::new()
        } else {
            v.iter()
                .filter(|p| {
                    let d = (p.1 - med).abs();
                    d > OUTLIER_MADS * mad.max(floor) && d >= OUTLIER_MIN_SHARE * med.abs()
                })
                .collect()
        };
        if let Some(first) = out.first() {
            let others: Vec<f64> = v
                .iter()
                .filter(|p| !out.iter().any(|o| o.0 == p.0))
                .map(|p| p.1)
                .collect();
            let (m, sd) = enginedyn_ingest::mean_std(others.iter().copied());
            notes.push(format!(
                "cycle {}{of}: IMEP {} bar, the others {} ± {}: a misfire?{} (kept in the averages; more than {} scaled median absolute deviations and more than 2 % from the median)",
                first.0,
                bar(first.1),
                bar(m),
                bar(sd),
                if out.len() > 1 {
                    format!(
                        " and {} more such cycle{} ({})",
                        out.len() - 1,
                        if out.len() > 2 { "s" } else { "" },
                        out[1..]
                            .iter()
                            .take(8)
                            .map(|o| o.0.to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                } else {
                    String::new()
                },
                OUTLIER_MADS
            ));
        }
        let (m, sd) = enginedyn_ingest::mean_std(v.iter().map(|p| p.1));
        if m.abs() > 0.0 && sd / m.abs() > HIGH_COV {
            notes.push(format!(
                "the IMEP{of} varies by {:.0} % (CoV) over {} cycles, above 10 %: an unsteady operating point, misfires, or a column that is not this cylinder's pressure?",
                100.0 * sd / m.abs(),
                v.len()
            ));
        }
    }
    notes
}

/// What the cycle statistics' spread is over, when it is not cycle to
/// cycle of one cylinder: traces of several cylinders mix the spread
/// between cylinders into it.
fn spread_note(r: &Resampled) -> Option<String> {
    let st = &r.stats;
    if st.len() < 2 {
        return None;
    }
    let mut cylinders: Vec<i64> = st.iter().map(|s| s.cylinder).filter(|&c| c > 0).collect();
    cylinders.sort_unstable();
    cylinders.dedup();
    let k = cylinders.len();
    if k < 2 {
        return None;
    }
    Some(if st.len() == k {
        format!(
            "imep_std_bar, imep_cov and the peak-pressure spread are over {k} cylinders, one cycle each: cylinder to cylinder, not cycle to cycle"
        )
    } else {
        format!(
            "imep_std_bar, imep_cov and the peak-pressure spread are over {} traces of {k} cylinders: cylinder to cylinder and cycle to cycle together",
            st.len()
        )
    })
}

/// Checks the speed and grid, applies the rod model; returns the engine to
/// use, the grid step (rad) and the notes so far.
fn prepare(
    engine: &Engine,
    rpm: f64,
    n: usize,
    opts: &Options,
) -> Result<(Engine, f64, Vec<String>), PipelineError> {
    if !(rpm.is_finite() && rpm > 0.0) {
        return Err(PipelineError::Input(format!(
            "speed {rpm} rpm: a positive speed is needed"
        )));
    }
    let rod_model = opts.rod_model.unwrap_or(engine.rod_model());
    let engine = engine.with_rod_model(rod_model)?;
    let h = engine.cycle() / n.max(1) as f64;
    if ((h.to_degrees() - opts.step_deg) / opts.step_deg).abs() > 1e-9 {
        return Err(PipelineError::Input(format!(
            "the data grid step {}° differs from the method step {}°",
            h.to_degrees(),
            opts.step_deg
        )));
    }
    let mut notes = engine.notes().to_vec();
    // Implausible engine data is computed, with a note naming the key.
    notes.extend(engine.plausibility_notes(Some(rpm)));
    // Defaults that shape the results, said (issue 30, item 11).
    notes.extend(engine.defaults_note());
    let series = engine.mechanism().series_error(opts.kinematics)?;
    if series > 0.01 {
        notes.push(format!(
            "{} kinematics misses the piston acceleration by up to {:.1} % here (lambda {:.3}): use --kinematics exact",
            opts.kinematics.name(),
            100.0 * series,
            engine.mechanism().lambda()
        ));
    }
    Ok((engine, h, notes))
}

/// `models.interpolation`: the interpolant named, or, where `auto` chose
/// differently trace by trace, each with its count (`spline (32 traces),
/// pchip (28)`), the most used first.
fn interp_name(opts: &Options, chosen: &Resampled) -> String {
    match opts.interp {
        Interp::Auto if chosen.interp_counts.len() > 1 => {
            let mut c = chosen.interp_counts.clone();
            c.sort_by_key(|k| std::cmp::Reverse(k.1));
            c.iter()
                .enumerate()
                .map(|(i, (k, n))| {
                    let unit = if i == 0 { " traces" } else { "" };
                    format!("{} ({n}{unit})", k.name())
                })
                .collect::<Vec<_>>()
                .join(", ")
        }
        Interp::Auto => chosen.interp.name().to_string(),
        other => other.name().to_string(),
    }
}

/// The grid tables of an engine that depend on neither the speed nor the
/// pressure: the piston motion and the volume law. A batch or a sweep
/// builds them once and hands them to [`analyse_with`] for every diagram
/// or speed.
#[derive(Debug, Clone)]
pub struct Tables {
    mechanism: enginedyn_kinematics::Mechanism,
    cylinder: enginedyn_kinematics::Cylinder,
    model: Model,
    n: usize,
    h: f64,
    kinematics: Arc<Table>,
    volume: Arc<Vec<f64>>,
    dvolume: Arc<Vec<f64>>,
    /// Piston speed and acceleration extremes per unit crank speed (scopes
    /// above [`Scope::Keys`] only).
    motion: Option<Extremes>,
}

impl Tables {
    /// The tables of `engine` on a grid of `n` points over its cycle, with
    /// the kinematics model of `opts`.
    pub fn new(engine: &Engine, n: usize, opts: &Options) -> Result<Self, PipelineError> {
        let h = engine.cycle() / n.max(1) as f64;
        let mech = *engine.mechanism();
        let cyl = *engine.cylinder();
        let mut kin = Table::default();
        mech.fill(opts.kinematics, 0.0, h, n, &mut kin)?;
        let (volume, dvolume) = cyl.fill_volume(h, n);
        let motion = if opts.scope > Scope::Keys {
            Some(motion_extremes(engine, opts.kinematics)?)
        } else {
            None
        };
        Ok(Self {
            mechanism: mech,
            cylinder: cyl,
            model: opts.kinematics,
            n,
            h,
            kinematics: Arc::new(kin),
            volume: Arc::new(volume),
            dvolume: Arc::new(dvolume),
            motion,
        })
    }

    /// True when these are the tables `analyse` would build.
    fn fit(&self, engine: &Engine, n: usize, h: f64, opts: &Options) -> bool {
        self.mechanism == *engine.mechanism()
            && self.cylinder == *engine.cylinder()
            && self.model == opts.kinematics
            && self.n == n
            && self.h.to_bits() == h.to_bits()
    }
}

/// One diagram for all cylinders, or each cylinder its own trace (each over
/// its own cycle angle from its own firing TDC); an error when the diagram
/// has traces for another number of cylinders than the engine's `z`.
fn cylinder_traces(pressure: &Resampled, z: usize) -> Result<Vec<&[f64]>, PipelineError> {
    if pressure.cylinders.is_empty() {
        Ok(vec![&pressure.pressure])
    } else if pressure.cylinders.len() == z {
        Ok(pressure.cylinders.iter().map(Vec::as_slice).collect())
    } else {
        Err(PipelineError::Input(format!(
            "the diagram has traces for {} cylinders, the engine has {z}",
            pressure.cylinders.len()
        )))
    }
}

/// Analyses one operating point at `rpm` from a resampled pressure trace.
pub fn analyse(
    engine: &Engine,
    pressure: &Resampled,
    rpm: f64,
    opts: &Options,
) -> Result<Analysis, PipelineError> {
    analyse_with(None, engine, pressure, rpm, opts)
}

/// [`analyse`] with the engine's [`Tables`] built beforehand (tables that
/// do not fit this engine, grid or model are ignored and built again).
pub fn analyse_with(
    tables: Option<&Tables>,
    engine: &Engine,
    pressure: &Resampled,
    rpm: f64,
    opts: &Options,
) -> Result<Analysis, PipelineError> {
    let n = pressure.pressure.len();
    let (engine, h, mut notes) = prepare(engine, rpm, n, opts)?;
    let engine = &engine;
    let rod_model = engine.rod_model();
    notes.extend(pressure.notes.iter().cloned());
    let omega = rpm * PI / 30.0;
    let mech = engine.mechanism();
    let built;
    let tables = match tables {
        Some(t) if t.fit(engine, n, h, opts) => t,
        _ => {
            built = Tables::new(engine, n, opts)?;
            &built
        }
    };
    let kin = &*tables.kinematics;
    let setup = Setup::new(engine, rod_model, omega);
    if setup.rod_centre.is_some_and(|(m0, _)| m0 < 0.0) {
        notes.push(format!(
            "three-mass rod: the centre mass m_0 = {:.4} kg is negative (I_G > m l_A l_B): \
             mass lies beyond the bearing centres; the model is still exact",
            setup.rod_centre.map(|c| c.0).unwrap_or_default()
        ));
    }
    let z = engine.cylinders();
    let traces = cylinder_traces(pressure, z)?;
    let all: Vec<Forces> = traces
        .iter()
        .map(|p| cylinder_forces(&setup, kin, p, 0.0, h))
        .collect();
    let of = |i: usize| &all[i.min(all.len() - 1)];
    let torque = enginedyn_torque::sum(engine, h, |i| &of(i).torque, opts.scope == Scope::Full);
    let bearings = if opts.scope == Scope::Full {
        let unbalance = engine.masses().crank_unbalanced * mech.r() * omega * omega;
        enginedyn_torque::main_bearing_loads(
            engine,
            h,
            |i| &of(i).tangential,
            |i| &of(i).pin_radial,
            unbalance,
        )
    } else {
        Vec::new()
    };
    let (volume, dvolume) = (&tables.volume, &tables.dvolume);
    // Indicated work from the exact volume law, W = ∮ p dV, mean over cylinders.
    let work = traces
        .iter()
        .map(|p| {
            let p_dv: Vec<f64> = p.iter().zip(dvolume.iter()).map(|(p, dv)| p * dv).collect();
            integrate::periodic_integral(opts.integration, &p_dv, h)
        })
        .sum::<f64>()
        / traces.len() as f64;
    if traces.len() > 1 {
        notes.push(format!(
            "one trace per cylinder: forces and torque per cylinder; curves.csv shows cylinder 1, IMEP is the mean over the {z} cylinders"
        ));
    }
    // Force extremes over every cylinder, refined between samples.
    let extreme = |get: fn(&Forces) -> &Vec<f64>| {
        all.iter()
            .map(|f| periodic_abs_max(get(f)))
            .fold(0.0_f64, f64::max)
    };
    let force_max = ForceMax {
        gas: extreme(|f| &f.gas),
        side: extreme(|f| &f.side),
        rod: extreme(|f| &f.rod),
        pin: extreme(|f| &f.pin_load),
    };
    let tdc_offset = tdc_offset(engine, pressure, traces[0], (h, opts), &mut notes);
    if opts.scope > Scope::Keys {
        notes.extend(spread_note(pressure));
        notes.extend(cycle_notes(pressure));
    }
    let forces = all.into_iter().next().unwrap_or_default();
    let parts = Parts {
        h,
        rod_model,
        pressure: traces[0].to_vec(),
        volume: Arc::clone(volume),
        kinematics: Arc::clone(&tables.kinematics),
        cylinder_torque: forces.torque.clone(),
        forces,
        force_max: Some(force_max),
        torque,
        bearings,
        work: Some(work),
        notes,
        interpolation: interp_name(opts, pressure),
        cycles: pressure.cycles,
        cycles_skipped: pressure.cycles_skipped,
        stats: (opts.scope > Scope::Keys)
            .then(|| cycle_summary(pressure))
            .flatten(),
        tdc_offset,
        pegging: pressure.pegging.map(|g| match g.method {
            Peg::Bar(_) => Pegging {
                method: "bar",
                offset_bar: g.mean_offset / 1e5,
                polytropic_n: None,
            },
            Peg::Polytropic(n) => Pegging {
                method: "polytropic",
                offset_bar: g.mean_offset / 1e5,
                polytropic_n: Some(n),
            },
        }),
        motion: tables.motion,
    };
    let mut analysis = complete(engine, parts, rpm, opts)?;
    if pressure.quantity == Quantity::Pressure {
        pressure_figures(
            &mut analysis,
            engine,
            pressure,
            &traces,
            tables,
            (rpm, opts),
        );
    }
    Ok(analysis)
}

/// Measured p–φ data: where the trace puts firing TDC, or why it cannot
/// tell (a note either way when there is something to say); never for a
/// synthesised diagram, whose TDC is exact by construction.
fn tdc_offset(
    engine: &Engine,
    pressure: &Resampled,
    trace: &[f64],
    (h, opts): (f64, &Options),
    notes: &mut Vec<String>,
) -> Option<f64> {
    if pressure.synthetic {
        // A synthesised diagram's TDC is exact by construction.
        None
    } else if opts.scope > Scope::Keys && !pressure.pv && pressure.quantity == Quantity::Pressure {
        // A file sampled coarsely is judged by its own step, not the
        // interpolant's grid.
        let estimate = tdc::fine_enough(pressure.sample_step_deg)
            .and_then(|()| tdc::estimate(trace, h, engine.cylinder()))
            .map_err(|e| e.to_string());
        match estimate {
            Ok(e) => {
                if e.offset_deg.abs() > 0.3 {
                    let fmt = &enginedyn_numerics::format::fixed;
                    let sign = if e.offset_deg > 0.0 { "+" } else { "" };
                    notes.push(format!(
                        "the trace suggests firing TDC lies {sign}{}° from the declared one (a fit of its compression and expansion with wall heat loss: n = {}, standard error {}°): add it to --tdc-deg; 1° of TDC error moves IMEP by about 4 % at full load",
                        fmt(e.offset_deg, 2),
                        fmt(e.exponent, 3),
                        enginedyn_numerics::format::sig(e.std_error_deg, 1),
                    ));
                }
                Some(e.offset_deg)
            }
            Err(why) => {
                notes.push(format!("no TDC offset estimate: {why}"));
                None
            }
        }
    } else {
        None
    }
}

/// What a pressure trace adds to an analysis: the mean trace's peak, the
/// brake figures from it (with `[friction]`), and the combustion analysis.
fn pressure_figures(
    analysis: &mut Analysis,
    engine: &Engine,
    pressure: &Resampled,
    traces: &[&[f64]],
    tables: &Tables,
    (rpm, opts): (f64, &Options),
) {
    // The mean trace's peak (cylinder 1's), the first a reviewer checks.
    (analysis.summary.p_max_bar, analysis.summary.p_max_angle_deg) =
        peak_of(traces[0], pressure.step_deg);
    brake_figures(engine, &mut analysis.summary);
    let imep_pa = analysis.summary.imep_bar.map(|i| i * 1e5);
    let swept = engine.cylinder().swept_volume();
    let with_curves = opts.scope == Scope::Full;
    if let Some(found) = combustion::analyse(
        pressure,
        traces,
        (&tables.volume, &tables.dvolume),
        swept,
        (imep_pa, rpm),
        with_curves,
    ) {
        analysis.summary.notes.extend(found.notes);
        analysis.summary.combustion = Some(found.summary);
        analysis.heat_release = found.curves;
        analysis.burn_cycles = found.scatter;
        analysis.most_knocking = pressure.most_knocking.clone().zip(
            pressure
                .combustion
                .as_deref()
                .and_then(|o| o.knock.as_ref())
                .map(|k| k.threshold_pa),
        );
    }
}

/// The brake figures of `s` by the engine file's `[friction]` (Chen–Flynn
/// on the mean trace's peak and the mean piston speed): FMEP, BMEP = IMEP
/// − FMEP, the brake torque `BMEP z V_d / Φ` (Φ the cycle, rad) and power,
/// and BMEP/IMEP, which the effective torque and power then carry in place
/// of `operating.mechanical_efficiency`. Nothing without `[friction]`, an
/// IMEP or a peak.
pub fn brake_figures(engine: &Engine, s: &mut Summary) {
    let (Some(f), Some(imep), Some(p_max)) = (engine.friction(), s.imep_bar, s.p_max_bar) else {
        return;
    };
    let b = f.brake(imep * 1e5, p_max * 1e5, s.piston_speed_mean_m_s);
    let displacement = engine.cylinders() as f64 * engine.cylinder().swept_volume();
    let torque = b.bmep_pa * displacement / engine.cycle();
    let power_kw = torque * s.omega_rad_s / 1e3;
    s.brake = Some(summary::BrakeSummary {
        fmep_bar: b.fmep_pa / 1e5,
        bmep_bar: b.bmep_pa / 1e5,
        brake_torque_nm: torque,
        brake_power_kw: power_kw,
        mechanical_efficiency: b.mechanical_efficiency,
    });
    s.mean_torque_nm = Some(torque);
    s.power_kw = Some(power_kw);
    if let Some(eta) = b.mechanical_efficiency {
        s.mechanical_efficiency = eta;
    }
    if b.bmep_pa <= 0.0 {
        s.notes.push(format!(
            "the engine does not overcome its friction here: FMEP {:.3} bar (Chen–Flynn, [friction]) against IMEP {imep:.3} bar, so BMEP and the brake torque are negative",
            b.fmep_pa / 1e5
        ));
    }
}

/// The peak of a periodic trace (Pa) on the grid of `step_deg`, in bar,
/// and its angle from firing TDC in `[-cycle/2, cycle/2)`.
fn peak_of(trace: &[f64], step_deg: f64) -> (Option<f64>, Option<f64>) {
    let Some((k, p)) = trace.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else {
        return (None, None);
    };
    let (deg, cycle) = (k as f64 * step_deg, trace.len() as f64 * step_deg);
    (
        p.is_finite().then_some(p / 1e5),
        Some(if deg >= cycle / 2.0 { deg - cycle } else { deg }),
    )
}

/// Analyses one operating point from a turning-moment diagram (torque of one
/// cylinder, summed by firing order, or of the whole engine): no pressure,
/// so the pressure and force figures are absent (`None`), with a note.
pub fn analyse_torque(
    engine: &Engine,
    torque: &Resampled,
    quantity: Quantity,
    rpm: f64,
    opts: &Options,
) -> Result<Analysis, PipelineError> {
    let n = torque.pressure.len();
    let (engine, h, mut notes) = prepare(engine, rpm, n, opts)?;
    let engine = &engine;
    notes.extend(torque.notes.iter().cloned());
    let mut kin = Table::default();
    engine
        .mechanism()
        .fill(opts.kinematics, 0.0, h, n, &mut kin)?;
    notes.push(
        "turning-moment input: no pressure, so IMEP, indicated work, the energy balance and the forces are not computed".into(),
    );
    let m = torque.pressure.clone();
    let (cylinder_torque, engine_torque) = match quantity {
        Quantity::CylinderTorque => {
            let t = enginedyn_torque::sum(engine, h, |_| &m, opts.scope == Scope::Full);
            (m.clone(), t)
        }
        Quantity::EngineTorque => {
            notes.push(
                "engine torque given: the torques of the other main journals are unknown; the last journal carries the engine torque".into(),
            );
            (Vec::new(), EngineTorque::engine_only(m.clone()))
        }
        Quantity::Pressure => {
            return Err(PipelineError::Input(
                "a pressure diagram given as turning-moment input".into(),
            ));
        }
    };
    let parts = Parts {
        h,
        rod_model: engine.rod_model(),
        pressure: Vec::new(),
        volume: Arc::default(),
        kinematics: Arc::new(kin),
        forces: Forces::default(),
        cylinder_torque,
        torque: engine_torque,
        bearings: Vec::new(),
        work: None,
        notes,
        interpolation: interp_name(opts, torque),
        cycles: torque.cycles,
        cycles_skipped: torque.cycles_skipped,
        force_max: None,
        stats: None,
        tdc_offset: None,
        pegging: None,
        motion: None,
    };
    complete(engine, parts, rpm, opts)
}

/// Uniformity, flywheel, harmonics and the summary, shared by both inputs.
fn complete(
    engine: &Engine,
    parts: Parts,
    rpm: f64,
    opts: &Options,
) -> Result<Analysis, PipelineError> {
    let Parts {
        h,
        rod_model,
        pressure,
        volume,
        kinematics,
        forces,
        cylinder_torque,
        torque,
        bearings,
        work,
        mut notes,
        interpolation,
        cycles,
        cycles_skipped,
        force_max,
        stats,
        tdc_offset,
        pegging,
        motion,
    } = parts;
    let omega = rpm * PI / 30.0;
    let cycle = engine.cycle();
    let mech = engine.mechanism();
    if !enginedyn_torque::on_grid(engine, h) {
        notes.push(format!(
            "firing angles fall between grid points of {}°: cylinder torques shifted by linear interpolation",
            opts.step_deg
        ));
    }
    let uniformity = Uniformity::new(&torque.total, h, opts.integration);
    // Idle is judged by the load (IMEP), not by the torque swing: a fired
    // single cylinder swings far more than its mean at full load.
    let swing = uniformity.max - uniformity.min;
    let imep = work.map(|w| w / engine.cylinder().swept_volume());
    let idle = match imep {
        Some(p) => uniformity.mean > 0.0 && p < IDLE_IMEP_PA,
        None => uniformity.mean > 0.0 && uniformity.mean < 0.05 * swing,
    };
    if idle {
        let load = imep.map_or(String::new(), |p| {
            format!("IMEP {} bar, ", enginedyn_numerics::format::human(p / 1e5))
        });
        notes.push(format!(
            "near idle or motoring ({load}mean torque {} N m against a swing of {} N m): mu and psi are large and follow every small error of the mean",
            enginedyn_numerics::format::human(uniformity.mean),
            enginedyn_numerics::format::human(swing)
        ));
    }
    let z = engine.cylinders() as f64;
    let energy_balance_error = work.map(|w| {
        let mean_from_work = z * w / cycle;
        (uniformity.mean - mean_from_work).abs() / mean_from_work.abs().max(1e-300)
    });
    let mut engine_inertia = engine.flywheel().other_rotating_inertia;
    if engine.flywheel().include_crank_train {
        engine_inertia += engine.crank_train_inertia(rod_model);
    }
    let flywheel =
        match enginedyn_flywheel::analyse(&uniformity, engine.flywheel(), omega, engine_inertia) {
            Ok(f) => {
                notes.extend(f.notes.iter().cloned());
                Some(f)
            }
            Err(e) => {
                notes.push(e.to_string());
                None
            }
        };
    let revs = cycle / (2.0 * PI);
    let cylinder_harmonics = if cylinder_torque.is_empty() || opts.scope < Scope::Full {
        Vec::new()
    } else {
        enginedyn_torque::harmonics(&cylinder_torque, revs, MAX_ORDER)?
    };
    let engine_harmonics = if opts.scope == Scope::Full {
        enginedyn_torque::harmonics(&torque.total, revs, MAX_ORDER)?
    } else {
        Vec::new()
    };
    let ext = if opts.scope > Scope::Keys {
        let unit = match motion {
            Some(m) => m,
            None => motion_extremes(engine, opts.kinematics)?,
        };
        let w2 = omega * omega;
        Extremes {
            speed_max: unit.speed_max * omega,
            accel_max: unit.accel_max * w2,
            accel_min: unit.accel_min * w2,
        }
    } else {
        Extremes {
            speed_max: f64::NAN,
            accel_max: f64::NAN,
            accel_min: f64::NAN,
        }
    };
    let eta = engine.operating().mechanical_efficiency;
    let (j_max, j_idx) = torque
        .journal_abs_max
        .iter()
        .enumerate()
        .map(|(k, &j)| (j, k))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
    // Journal numbering: with engine-torque input only the last journal is known.
    let j_idx = if torque.journal_abs_max.len() == 1 {
        engine.throws() - 1
    } else {
        j_idx
    };
    let has_forces = force_max.is_some();
    let cyl = engine.cylinder();
    let summary = Summary {
        rpm,
        omega_rad_s: omega,
        imep_bar: work.map(|w| w / cyl.swept_volume() / 1e5),
        indicated_work_per_cylinder_j: work,
        mean_torque_nm: Some(uniformity.mean * eta),
        power_kw: Some(uniformity.mean * eta * omega / 1e3),
        indicated_mean_torque_nm: Some(uniformity.mean),
        indicated_power_kw: Some(uniformity.mean * omega / 1e3),
        torque_max_nm: Some(uniformity.max),
        torque_min_nm: Some(uniformity.min),
        torque_nonuniformity: uniformity.nonuniformity(),
        excess_work_j: Some(uniformity.excess_work),
        excess_work_coefficient: uniformity.excess_work_coefficient(),
        required_inertia_kg_m2: flywheel.as_ref().map(|f| f.required_inertia),
        flywheel_inertia_kg_m2: flywheel.as_ref().map(|f| f.inertia),
        flywheel_gd2_n_m2: flywheel.as_ref().and_then(|f| f.gd2),
        flywheel_outer_diameter_m: flywheel.as_ref().and_then(|f| f.outer_diameter),
        flywheel_mass_kg: flywheel.as_ref().map(|f| f.mass),
        flywheel_width_m: flywheel.as_ref().and_then(|f| f.width),
        speed_fluctuation_achieved: flywheel.as_ref().map(|f| f.speed_fluctuation_achieved),
        stroke_m: mech.stroke(),
        lambda: mech.lambda(),
        piston_speed_mean_m_s: mech.stroke() * omega / PI,
        piston_speed_max_m_s: ext.speed_max,
        piston_accel_max_m_s2: ext.accel_max,
        piston_accel_min_m_s2: ext.accel_min,
        gas_force_max_n: force_max.as_ref().map(|f| f.gas),
        side_force_max_n: force_max.as_ref().map(|f| f.side),
        rod_force_max_n: force_max.as_ref().map(|f| f.rod),
        crankpin_load_max_n: force_max.as_ref().map(|f| f.pin),
        crankpin_load_mean_n: has_forces
            .then(|| integrate::periodic_mean(opts.integration, &forces.pin_load)),
        journal_torque_max_nm: j_max,
        journal_most_loaded: j_idx + 1,
        energy_balance_error,
        kinematics: opts.kinematics.name(),
        rod_model: rod_model.name(),
        interpolation,
        grid_step_deg: opts.step_deg,
        integration: opts.integration.name(),
        cycles: (cycles > 1 || cycles_skipped > 0).then_some(cycles),
        cycles_skipped: (cycles > 1 || cycles_skipped > 0).then_some(cycles_skipped),
        cycle_stats: stats,
        pegging,
        tdc_offset_estimate_deg: tdc_offset,
        estimated_relative_error: None,
        mechanical_efficiency: eta,
        combustion: None,
        p_max_bar: None,
        p_max_angle_deg: None,
        brake: None,
        design: None,
        notes,
    };
    Ok(Analysis {
        step: h,
        pressure,
        volume,
        kinematics,
        cylinder_torque,
        forces,
        torque,
        bearings,
        uniformity,
        flywheel,
        cylinder_harmonics,
        engine_harmonics,
        summary,
        heat_release: None,
        burn_cycles: Vec::new(),
        most_knocking: None,
    })
}

/// Puts the flywheel `part` (sized at another speed, as `sweep` does: one
/// part for every speed) on this operating point: its figures replace the
/// ones sized here, and `speed_fluctuation_achieved` becomes the δ the part
/// gives at this speed. Nothing changes without a flywheel here (motoring).
pub fn with_flywheel(a: &mut Analysis, part: &Flywheel) {
    let Some(here) = &a.flywheel else {
        return;
    };
    let f = enginedyn_flywheel::same_part(&a.uniformity, part, a.summary.omega_rad_s);
    put_part(&mut a.summary, here, part, &f);
    a.flywheel = Some(f);
}

/// The summary of a point that sized `here` once `part` stands in its
/// place (`f`: the part at this point): the part's figures and the δ it
/// gives here, beside the inertia this point itself needs.
fn put_part(s: &mut Summary, here: &Flywheel, part: &Flywheel, f: &Flywheel) {
    // The notes about the flywheel sized here are about another part.
    s.notes.retain(|n| !here.notes.contains(n));
    s.notes.extend(part.notes.iter().cloned());
    // The inertia this point needs is its own (`here`), whatever part
    // stands in its place: the part's is the sizing point's.
    s.required_inertia_kg_m2 = Some(here.required_inertia);
    s.flywheel_inertia_kg_m2 = Some(f.inertia);
    s.flywheel_gd2_n_m2 = f.gd2;
    s.flywheel_outer_diameter_m = f.outer_diameter;
    s.flywheel_mass_kg = Some(f.mass);
    s.flywheel_width_m = f.width;
    s.speed_fluctuation_achieved = Some(f.speed_fluctuation_achieved);
}

/// One operating point as a sweep or map keeps it: the summary, the
/// flywheel sized here (without its speed trace) and what a flywheel sized
/// elsewhere needs of this point ([`enginedyn_flywheel::EnergySpan`]). A
/// few kB where an [`Analysis`] holds every curve on the grid (about 1 MB at
/// 0.1°), so a map's memory does not grow with its points' curves.
#[derive(Debug, Clone)]
pub struct Point {
    /// The summary figures and notes.
    pub summary: Summary,
    /// The flywheel sized at this point, when the engine delivers work
    /// (its `speed` trace left empty).
    pub flywheel: Option<Flywheel>,
    /// The excess energy's extremes, for [`Point::with_flywheel`] (a few
    /// samples, not the curve).
    pub energy: enginedyn_flywheel::EnergySpan,
}

impl Point {
    /// What a sweep keeps of `a`; the rest is dropped.
    pub fn of(a: Analysis) -> Self {
        let energy = a.uniformity.span();
        let flywheel = a.flywheel.map(|f| Flywheel {
            speed: Vec::new(),
            ..f
        });
        Point {
            summary: a.summary,
            flywheel,
            energy,
        }
    }

    /// [`with_flywheel`] on the kept point: the same summary.
    pub fn with_flywheel(&mut self, part: &Flywheel) {
        let Some(here) = &self.flywheel else {
            return;
        };
        let f = enginedyn_flywheel::same_part_at(&self.energy, part, self.summary.omega_rad_s);
        put_part(&mut self.summary, here, part, &f);
        self.flywheel = Some(f);
    }
}

#[derive(Debug, Clone, Copy)]
struct Extremes {
    speed_max: f64,
    accel_max: f64,
    accel_min: f64,
}

/// Extremes of piston speed and acceleration per unit crank speed
/// (`dx/dphi` and `d2x/dphi2`: multiply by `omega` and `omega²`),
/// searched for (a 0.5° scan refined by minimisation), not read at the
/// dead centres.
fn motion_extremes(engine: &Engine, model: Model) -> Result<Extremes, PipelineError> {
    let mech = engine.mechanism();
    mech.check(model)?;
    let st = |x: f64| mech.state(model, x).unwrap_or_default();
    let revolution = 2.0 * PI;
    let scan = 720;
    let h = revolution / scan as f64;
    // One scan for the three curves (speed, acceleration up and down),
    // then each largest value refined by Brent's minimisation.
    let mut best = [(f64::NEG_INFINITY, 0.0); 3];
    for k in 0..scan {
        let x = k as f64 * h;
        let s = st(x);
        for (b, v) in best.iter_mut().zip([s.dx.abs(), s.d2x, -s.d2x]) {
            if v > b.0 {
                *b = (v, x);
            }
        }
    }
    let refine = |f: &dyn Fn(f64) -> f64, (value, at): (f64, f64)| -> f64 {
        let (_, fmin) = roots::minimize(|x| -f(x), at - h, at + h, 1e-12);
        (-fmin).max(value)
    };
    Ok(Extremes {
        speed_max: refine(&|x| st(x).dx.abs(), best[0]),
        accel_max: refine(&|x| st(x).d2x, best[1]),
        accel_min: -refine(&|x| -st(x).d2x, best[2]),
    })
}

#[cfg(test)]
mod outlier_tests {
    use super::*;

    fn with_imeps(imeps: &[f64]) -> Resampled {
        let mut r = Resampled::from_grid(1.0, vec![1e5; 720]);
        r.stats = imeps
            .iter()
            .enumerate()
            .map(|(i, &p)| enginedyn_ingest::CycleStats {
                cylinder: 0,
                cycle: i as i64 + 1,
                imep_pa: Some(p * 1e5),
                p_max: 40e5,
                p_max_angle_deg: 12.0,
                peg_offset: 0.0,
                rpm: None,
                combustion: None,
            })
            .collect();
        r
    }

    fn misfire(imeps: &[f64]) -> Option<String> {
        cycle_notes(&with_imeps(imeps))
            .into_iter()
            .find(|n| n.contains("a misfire?"))
    }

    /// INTERFACE.md, "Plausibility": the outlier note needs at least 8
    /// cycles and a deviation of at least 2 % of the median.
    #[test]
    fn outliers_need_cycles_and_a_spread() {
        // 1 ppm off among identical cycles: no misfire.
        let mut ppm = vec![9.9; 10];
        ppm[2] = 9.9 * (1.0 - 1e-6);
        assert_eq!(misfire(&ppm), None);
        // Three cycles, one 1.6 % low: too few, and too small.
        assert_eq!(misfire(&[9.9, 9.9 * 0.984, 9.91]), None);
        // Seven cycles, one at 0.4 bar: too few.
        assert_eq!(misfire(&[8.9, 9.0, 8.8, 0.4, 8.9, 9.1, 8.95]), None);
        // Eight: named.
        let n = misfire(&[8.9, 9.0, 8.8, 0.4, 8.9, 9.1, 8.95, 8.85]).unwrap();
        assert!(n.starts_with("cycle 4: IMEP 0.4 bar"), "{n}");
        // 1.5 % off a tight spread among 10 cycles: more than 5 MADs, less
        // than 2 %: no note; 2.5 % off: named.
        let mut tight = vec![
            9.0, 9.001, 8.999, 9.0005, 8.9995, 9.0, 9.001, 8.999, 9.0, 9.0,
        ];
        tight[5] = 9.0 * 0.985;
        assert_eq!(misfire(&tight), None);
        tight[5] = 9.0 * 0.975;
        assert!(misfire(&tight).unwrap().starts_with("cycle 6:"));
    }
}
