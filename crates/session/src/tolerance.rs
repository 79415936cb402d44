//! The tolerance study (`enginedyn tolerance`, INTERFACE.md): each
//! tolerance of the engine file's `[tolerances]` alone at ±t through the
//! real pipeline, their stack-up, and the Monte Carlo check; and the
//! linear-model section `run --out` adds to `report.html`.

use crate::diagram::{Input, check_step, diagram_options, load_diagram};
use crate::engine::Loaded;
use crate::error::{Error, Result};
use crate::options::{Method, Reader};
use crate::speed::resolve_rpm;
use enginedyn_engine::Engine;
use enginedyn_ingest::Quantity;
use enginedyn_tolerance::{Evaluator, Study};

/// Monte Carlo runs on this grid (deg) unless the method step is coarser:
/// every sample is a full pipeline run, and 0.5° keeps 10,000 samples of a
/// four-cylinder engine within seconds. `report.html`'s linear model runs
/// on it too.
pub const MONTE_CARLO_STEP: f64 = 0.5;

/// The deviations of an engine file's `[tolerances]` section (key, ± value
/// in the key's unit), read and found not empty.
#[derive(Debug, Clone)]
pub struct Tolerances(pub Vec<(String, f64)>);

impl Tolerances {
    /// The `[tolerances]` section of `loaded`'s engine file: a usage error
    /// naming the file when it cannot be read or is missing or empty (with
    /// an example of the section).
    pub fn of(loaded: &Loaded) -> Result<Self> {
        let file = loaded.shown();
        let tolerances = enginedyn_engine::file::tolerances(&loaded.text)
            .map_err(|e| Error::usage(format!("{file}: {e}")))?;
        if tolerances.is_empty() {
            return Err(Error::usage(format!(
                "{file}: no [tolerances] section: give the ± deviations to study, e.g.\n\
                 [tolerances]\nstroke_mm = 0.02\nrod_length_mm = 0.05\npiston_group_kg = 0.005\n\
                 throw_angle_deg = 0.2\ntdc_deg = 0.1"
            )));
        }
        Ok(Self(tolerances))
    }
}

/// A tolerance study's result: the study, the speed and the diagram.
#[derive(Debug)]
pub struct ToleranceStudy {
    /// The study; its `notes` hold every note in the order said (the
    /// inputs', the study's, the pin offset's TDC shift, the speed's).
    pub study: Study,
    /// The speed it ran at (rpm).
    pub rpm: f64,
    /// How messages name the diagram.
    pub diagram: String,
}

/// The tolerance study of `loaded` with `tolerances` on `diagram` (`None`:
/// the engine file's `diagram`), read with `reader` (its `rpm` the speed
/// given) and computed with `method`: sensitivities on the method's grid,
/// then `samples` Monte Carlo samples from `seed` on the grid of
/// [`MONTE_CARLO_STEP`] (or the method's, when coarser).
pub fn study(
    loaded: &Loaded,
    tolerances: &Tolerances,
    reader: &Reader,
    method: &Method,
    diagram: Option<Input<'_>>,
    samples: usize,
    seed: u64,
) -> Result<ToleranceStudy> {
    let engine = &loaded.engine;
    let file = loaded.shown();
    let (inputs, input_notes) = enginedyn_tolerance::inputs(engine, &tolerances.0)
        .map_err(|e| Error::usage(format!("{file}: {e}")))?;
    let step = method.step();
    check_step(engine, step)?;
    let opts = method.options();
    let fallback;
    let diagram = match diagram {
        Some(d) => d,
        None => {
            fallback = crate::synth::default_diagram(loaded, reader.rpm, step)?;
            fallback.input()
        }
    };
    let shown = diagram.shown();
    let load = |step: f64| {
        let (parse, grid) = diagram_options(engine, reader, step, opts.interp)?;
        let r = load_diagram(diagram, &parse, &grid)?;
        if r.quantity != Quantity::Pressure {
            return Err(Error::data(format!(
                "{shown}: a turning-moment file: the tolerance study needs a pressure diagram"
            )));
        }
        Ok(r)
    };
    let table_diagram = load(step)?;
    let speed = resolve_rpm(reader.rpm, table_diagram.rpm, engine)?;
    let rpm = speed.rpm;
    let mc_step = step.max(MONTE_CARLO_STEP);
    let mc_diagram = if (mc_step - step).abs() < 1e-12 {
        table_diagram.clone()
    } else {
        load(mc_step)?
    };
    let failure = |e: enginedyn_tolerance::ToleranceError| Error::usage(format!("{file}: {e}"));
    let table = Evaluator::new(engine, &table_diagram, rpm, opts, &inputs).map_err(failure)?;
    let mc_opts = enginedyn_pipeline::Options {
        step_deg: mc_step,
        ..opts
    };
    let mc = Evaluator::new(engine, &mc_diagram, rpm, mc_opts, &inputs).map_err(failure)?;
    let mut study = enginedyn_tolerance::study(&table, &mc, samples, seed).map_err(failure)?;
    study.notes.splice(0..0, input_notes);
    study.notes.extend(offset_note(engine, &study));
    study.notes.extend(speed.note);
    if let Input::Synthesised(s) = diagram {
        study.notes.insert(0, s.note.clone());
    }
    Ok(ToleranceStudy {
        study,
        rpm,
        diagram: shown,
    })
}

/// A pin-offset tolerance moves TDC: say by how much, since a diagram whose
/// TDC comes from the crank's geometry carries that as a TDC error.
fn offset_note(engine: &Engine, study: &Study) -> Option<String> {
    let input = study
        .inputs
        .iter()
        .find(|i| i.parameter == enginedyn_tolerance::Parameter::PinOffset)?;
    let enginedyn_kinematics::Mechanism::CrankSlider(cs) = engine.mechanism() else {
        return None;
    };
    let shift = (input.tolerance * 1e-3 / (cs.l() + cs.r())).to_degrees();
    Some(format!(
        "pin_offset_mm ± {} moves TDC by ± {shift:.3}° (δe / (L + R)); the diagram is taken on \
         its true firing TDC (PHYSICS.md); if its TDC comes from the crank's geometry instead, \
         add that to tdc_deg",
        input.tolerance
    ))
}

/// The tolerance table and tornado chart for `report.html` when the engine
/// file has a `[tolerances]` section: the linear model only (sensitivities
/// by the real pipeline, no Monte Carlo; `enginedyn tolerance` adds it), on
/// the run's pressure trace at 0.5° (every n-th point of the run's grid)
/// with the run's methods. `None` without tolerances or without pressure.
pub fn report_extra(
    engine: &Engine,
    engine_text: &str,
    analysis: &enginedyn_pipeline::Analysis,
    opts: enginedyn_pipeline::Options,
) -> Result<Option<enginedyn_report::Extra>> {
    if analysis.pressure.is_empty() {
        return Ok(None);
    }
    let file = engine.name().to_string();
    let tolerances = enginedyn_engine::file::tolerances(engine_text)
        .map_err(|e| Error::usage(format!("{file}: {e}")))?;
    if tolerances.is_empty() {
        return Ok(None);
    }
    let (inputs, _) = enginedyn_tolerance::inputs(engine, &tolerances)
        .map_err(|e| Error::usage(format!("{file}: {e}")))?;
    // Every n-th point: 0.5° when the run's grid divides it.
    let every = (MONTE_CARLO_STEP / opts.step_deg).round().max(1.0) as usize;
    let step = if ((every as f64) * opts.step_deg - MONTE_CARLO_STEP).abs() < 1e-9 {
        MONTE_CARLO_STEP
    } else {
        opts.step_deg
    };
    let stride = if step == MONTE_CARLO_STEP { every } else { 1 };
    let pressure: Vec<f64> = analysis.pressure.iter().step_by(stride).copied().collect();
    let trace = enginedyn_ingest::Resampled::from_grid(step, pressure);
    let o = enginedyn_pipeline::Options {
        step_deg: step,
        scope: enginedyn_pipeline::Scope::Keys,
        ..opts
    };
    let failure = |e: enginedyn_tolerance::ToleranceError| Error::usage(format!("{file}: {e}"));
    let ev = Evaluator::new(engine, &trace, analysis.summary.rpm, o, &inputs).map_err(failure)?;
    let study = enginedyn_tolerance::study(&ev, &ev, 0, 1).map_err(failure)?;
    enginedyn_report::tolerance_extra(engine, step, &study, Some(&analysis.summary))
        .map(Some)
        .map_err(|e| Error::data(e.to_string()))
}
