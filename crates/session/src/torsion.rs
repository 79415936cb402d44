//! The torsion study (`enginedyn torsion`, INTERFACE.md "Torsion"): the
//! crankshaft's torsional vibration over speed. The excitation comes from
//! the pipeline once (gas and inertia parts of each cylinder's torque by
//! order); the chain from `[torsion]`. And the section `run --out` adds to
//! `report.html` for an engine file with `[torsion]`.

use crate::diagram::{Input, check_step, diagram_options, load_diagram};
use crate::engine::Loaded;
use crate::error::{Error, Result};
use crate::options::{Method, Reader};
use crate::speed::resolve_rpm;
use enginedyn_engine::Engine;
use enginedyn_pipeline::torsion::{Excitation, Study, TorsionStudyError, Train};

/// Speeds without a range given: 20 % to 120 % of the operating speed.
pub const DEFAULT_SPEEDS: usize = 50;

fn study_failure(file: &str, e: TorsionStudyError) -> Error {
    match e {
        TorsionStudyError::Engine(e) => Error::usage(format!("{file}: {e}")),
        TorsionStudyError::Chain(e) => Error::usage(format!("{file}: [torsion]: {e}")),
        TorsionStudyError::Pipeline(e) => Error::data(e.to_string()),
    }
}

/// The chain and its excitation, built from the engine and a pressure trace.
#[derive(Debug)]
pub struct Prepared {
    /// The chain with its defaults noted.
    pub train: Train,
    /// The excitation by order.
    pub excitation: Excitation,
}

/// The chain and excitation of `engine` from its `[torsion]` section and
/// a pressure trace already on the grid; `analysis` is the run at the
/// operating speed (its sized flywheel is the default flywheel); `file`
/// names the engine file in errors.
pub fn prepare(
    file: &str,
    engine: &Engine,
    spec: &enginedyn_engine::torsion::TorsionSpec,
    resampled: &enginedyn_ingest::Resampled,
    analysis: &enginedyn_pipeline::Analysis,
    opts: &enginedyn_pipeline::Options,
) -> Result<Prepared> {
    let rod_model = opts.rod_model.unwrap_or(engine.rod_model());
    let train = enginedyn_pipeline::torsion::crank_train(
        engine,
        spec,
        rod_model,
        analysis.flywheel.as_ref().map(|f| f.inertia),
    )
    .map_err(|e| study_failure(file, e))?;
    let excitation = enginedyn_pipeline::torsion::excitation(
        engine,
        resampled,
        opts,
        enginedyn_pipeline::MAX_ORDER,
    )
    .map_err(|e| Error::data(e.to_string()))?;
    Ok(Prepared { train, excitation })
}

/// The default speeds: 20 % to 120 % of `rpm` in [`DEFAULT_SPEEDS`] steps.
pub fn default_speeds(rpm: f64) -> Vec<f64> {
    (0..DEFAULT_SPEEDS)
        .map(|k| rpm * (0.2 + 1.0 * k as f64 / (DEFAULT_SPEEDS - 1) as f64))
        .collect()
}

/// The `[torsion]` section of `loaded`'s engine file: a usage error naming
/// the file when it is missing or wrong.
pub fn spec(loaded: &Loaded) -> Result<enginedyn_engine::torsion::TorsionSpec> {
    let file = loaded.shown();
    enginedyn_engine::file::parse_torsion(&loaded.text)
        .map_err(|e| Error::usage(format!("{file}: {e}")))?
        .ok_or_else(|| {
            Error::usage(format!(
                "{file}: no [torsion] section: give at least `journal_stiffness_nm_rad` (or `journal_diameter_mm` and `journal_length_mm`) under [torsion]"
            ))
        })
}

/// A torsion study's result.
#[derive(Debug)]
pub struct TorsionStudy {
    /// The study over the speeds.
    pub study: Study,
    /// The chain and excitation it ran on.
    pub prepared: Prepared,
    /// The speeds (rpm).
    pub rpms: Vec<f64>,
    /// Implausible values (they may mean a wrong result), said first.
    pub warnings: Vec<String>,
    /// What was assumed: the chain's defaults, the speed's source, the
    /// study's own notes.
    pub notes: Vec<String>,
    /// The options the excitation was computed with.
    pub opts: enginedyn_pipeline::Options,
}

impl TorsionStudy {
    /// Every note, the warnings first (as `torsion.json` lists them).
    pub fn all_notes(&self) -> Vec<String> {
        self.warnings.iter().chain(&self.notes).cloned().collect()
    }
}

/// The torsion study of `loaded` (its `[torsion]`: [`spec`]) excited by
/// `diagram` (`None`: the engine file's `diagram`) read with `reader` and
/// computed with `method`, over `rpms` (`None`: [`default_speeds`] around
/// the diagram's or the engine file's speed). The flywheel is sized and
/// the diagram taken at that speed.
pub fn study(
    loaded: &Loaded,
    spec: &enginedyn_engine::torsion::TorsionSpec,
    reader: &Reader,
    method: &Method,
    diagram: Option<Input<'_>>,
    rpms: Option<Vec<f64>>,
) -> Result<TorsionStudy> {
    if let Some(r) = &rpms {
        check_speeds(r)?;
    }
    let engine = &loaded.engine;
    let file = loaded.shown();
    let step = method.step();
    check_step(engine, step)?;
    let opts = method.options();
    let (parse, grid) = diagram_options(engine, reader, step, opts.interp)?;
    let fallback;
    let diagram = match diagram {
        Some(d) => d,
        None => {
            fallback = crate::synth::default_diagram(loaded, reader.rpm, step)?;
            fallback.input()
        }
    };
    let resampled = load_diagram(diagram, &parse, &grid)?;
    let speed = resolve_rpm(None, resampled.rpm, engine)?;
    let rpms = rpms.unwrap_or_else(|| default_speeds(speed.rpm));
    let analysis = enginedyn_pipeline::analyse(engine, &resampled, speed.rpm, &opts)
        .map_err(|e| Error::data(e.to_string()))?;
    let prepared = prepare(&file, engine, spec, &resampled, &analysis, &opts)?;
    let study = enginedyn_pipeline::torsion::study(&prepared.train, &prepared.excitation, &rpms)
        .map_err(|e| study_failure(&file, e))?;
    let warnings = prepared.train.warnings.clone();
    let mut notes = prepared.train.notes.clone();
    if let Input::Synthesised(s) = diagram {
        notes.insert(0, s.note.clone());
    }
    if let Some(n) = &speed.note {
        notes.push(format!("flywheel sized and diagram taken at {n}"));
    }
    notes.extend(study.notes.iter().cloned());
    Ok(TorsionStudy {
        study,
        prepared,
        rpms,
        warnings,
        notes,
        opts,
    })
}

/// Speeds given as numbers (a Python caller's; the CLI's come from
/// [`crate::speed::speeds`], which holds the same bounds): at least one,
/// at most [`crate::speed::MAX_SPEEDS`], each above 0 and at most
/// [`crate::speed::MAX_RPM`].
pub fn check_speeds(rpms: &[f64]) -> Result<()> {
    use crate::speed::{MAX_RPM, MAX_SPEEDS};
    if rpms.is_empty() || rpms.len() > MAX_SPEEDS {
        return Err(Error::usage(format!(
            "{} speeds: a torsion study takes 1 to {MAX_SPEEDS}",
            rpms.len()
        )));
    }
    if let Some(bad) = rpms
        .iter()
        .find(|r| !(r.is_finite() && **r > 0.0 && **r <= MAX_RPM))
    {
        return Err(Error::usage(format!(
            "speed {} rpm: each speed must be above 0 and at most {MAX_RPM} rpm",
            enginedyn_numerics::format::human(*bad)
        )));
    }
    Ok(())
}

/// The chain and a few forced responses (`torsion --chain`'s `chain.json`,
/// for benches/torsion_compare.py): at four speeds of the study, every
/// fifth order.
pub fn chain_dump(t: &TorsionStudy) -> Result<enginedyn_report::ChainDump> {
    let (chain, layout) = t
        .prepared
        .train
        .train
        .chain()
        .map_err(|e| Error::usage(e.to_string()))?;
    let solver = enginedyn_torsion::Solver::new(&chain).map_err(|e| Error::usage(e.to_string()))?;
    let ex = &t.prepared.excitation;
    let rpms = &t.rpms;
    let mut checks = Vec::new();
    let picks = [
        0,
        rpms.len() / 3,
        2 * rpms.len() / 3,
        rpms.len().saturating_sub(1),
    ];
    for &i in &picks {
        let Some(&rpm) = rpms.get(i) else { continue };
        let omega = rpm * std::f64::consts::PI / 30.0;
        for o in (0..ex.orders.len()).step_by(5) {
            let mut tt = vec![enginedyn_torsion::Complex64::new(0.0, 0.0); layout.throws.len()];
            ex.at(o, omega, &mut tt);
            let mut torque = vec![enginedyn_torsion::Complex64::new(0.0, 0.0); chain.len()];
            for (k, &m) in layout.throws.iter().enumerate() {
                torque[m] = tt[k];
            }
            let w = ex.orders[o] * omega;
            let response = solver
                .respond(w, &torque)
                .map_err(|e| Error::usage(e.to_string()))?;
            checks.push(enginedyn_report::ChainCheck {
                rpm,
                order: ex.orders[o],
                omega_rad_s: w,
                torque,
                response,
            });
        }
    }
    let study = &t.study;
    Ok(enginedyn_report::ChainDump {
        inertia: chain.inertia().to_vec(),
        stiffness: chain.stiffness().to_vec(),
        spring_damping: chain.spring_damping().to_vec(),
        damping_ratio: chain.damping_ratio(),
        names: layout.names.clone(),
        natural_frequencies_hz: (1..study.modes.len())
            .map(|m| study.modes.frequency_hz(m))
            .collect(),
        checks,
    })
}

/// The torsion section of `run`'s report.html when the engine file has a
/// `[torsion]` section: the modes and the worst resonances as tables, the
/// Campbell and response charts, over the default speeds around the run's,
/// excited by the run's pressure (cylinder 1's trace for every cylinder).
pub fn report_extra(
    engine: &Engine,
    engine_text: &str,
    analysis: &enginedyn_pipeline::Analysis,
    opts: enginedyn_pipeline::Options,
) -> Result<Option<enginedyn_report::Extra>> {
    let rpms = default_speeds(analysis.summary.rpm);
    Ok(report_extra_over(engine, engine_text, analysis, opts, &rpms)?.map(|(extra, _)| extra))
}

/// [`report_extra`] over the speeds `rpms` (the design report's: its map's
/// speed range at full load), with the study it shows.
pub fn report_extra_over(
    engine: &Engine,
    engine_text: &str,
    analysis: &enginedyn_pipeline::Analysis,
    opts: enginedyn_pipeline::Options,
    rpms: &[f64],
) -> Result<Option<(enginedyn_report::Extra, Study)>> {
    let file = engine.name().to_string();
    let Some(spec) = enginedyn_engine::file::parse_torsion(engine_text)
        .map_err(|e| Error::from(e).in_file(&file))?
    else {
        return Ok(None);
    };
    if analysis.pressure.is_empty() {
        return Ok(None);
    }
    let trace = enginedyn_ingest::Resampled::from_grid(opts.step_deg, analysis.pressure.clone());
    let prepared = prepare(&file, engine, &spec, &trace, analysis, &opts)?;
    let study = enginedyn_pipeline::torsion::study(&prepared.train, &prepared.excitation, rpms)
        .map_err(|e| study_failure(&file, e))?;
    let mut notes = prepared.train.warnings.clone();
    notes.extend(prepared.train.notes.iter().cloned());
    notes.extend(study.notes.iter().cloned());
    let extra = enginedyn_report::torsion_extra(engine.name(), &study, rpms, &notes)
        .map_err(|e| Error::data(e.to_string()))?;
    Ok(Some((extra, study)))
}
