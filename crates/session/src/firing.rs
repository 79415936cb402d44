//! The firing-order study (`enginedyn firing-orders`, INTERFACE.md): the
//! even firing orders of the engine's crank (or of every crank), ranked by
//! `enginedyn_balance::score`, with the diagram's journal torques when
//! there is a diagram.

use crate::diagram::{Input, check_step, diagram_options, load_diagram};
use crate::error::{Error, Result};
use crate::options::{Method, Reader};
use crate::speed::resolve_rpm;
use enginedyn_balance::{CylinderTorque, Setup, Study, Weights};
use enginedyn_engine::Engine;
use enginedyn_ingest::Quantity;
use std::path::Path;

/// The score's weights as the user wrote them
/// (`intervals=1,neighbours=1,journal=1,balance=1`), or the defaults.
pub fn weights(given: Option<&str>) -> Result<Weights> {
    match given {
        Some(w) => Weights::parse(w).map_err(|e| Error::usage(e.to_string())),
        None => Ok(Weights::default()),
    }
}

/// The engine a firing-order study reads from `path`: with `all_cranks`
/// the engine file may leave `firing_order` out (that is how a user finds
/// one), else it is checked whole.
pub fn engine(path: &Path, all_cranks: bool) -> Result<Engine> {
    if all_cranks {
        enginedyn_engine::file::read_for_crank_search(path)
            .map_err(|e| Error::usage(format!("{}: {e}", path.display())))
    } else {
        Ok(crate::Loaded::from_file(path)?.engine)
    }
}

/// A firing-order study's result.
#[derive(Debug)]
pub struct FiringOrders {
    /// The study; its `notes` hold every note in the order said (the
    /// engine's, the diagram's, the speed's, the study's).
    pub study: Study,
    /// How the tables name the diagram (`none` without one).
    pub diagram: String,
    /// The speed (rpm).
    pub rpm: f64,
}

/// The firing orders of `engine` (every crank arrangement with
/// `all_cranks`), scored with `weights`; the journal torques from
/// `diagram` (`None`: the engine file's `diagram`, when it has one) read
/// with `reader` (its `rpm` the speed given) and computed with `method`.
pub fn study(
    engine: &Engine,
    reader: &Reader,
    method: &Method,
    diagram: Option<Input<'_>>,
    weights: Weights,
    all_cranks: bool,
) -> Result<FiringOrders> {
    let step = method.step();
    check_step(engine, step)?;
    let opts = method.options();
    let rod_model = opts.rod_model.unwrap_or(engine.rod_model());
    let mut notes: Vec<String> = engine.notes().to_vec();
    let diagram = diagram.or_else(|| engine.diagram().map(Input::File));
    let (shown, rpm, analysis) = match diagram {
        Some(input) => {
            let (parse, grid) = diagram_options(engine, reader, step, opts.interp)?;
            let resampled = load_diagram(input, &parse, &grid)?;
            let shown = input.shown();
            if resampled.quantity != Quantity::Pressure {
                return Err(Error::data(format!(
                    "{shown}: a turning-moment (torque) file; firing-orders reads a pressure diagram"
                )));
            }
            if !resampled.cylinders.is_empty() {
                notes.push(
                    "the diagram has one trace per cylinder: the journal torques use cylinder 1's torque for every cylinder"
                        .to_string(),
                );
            }
            notes.extend(resampled.notes.iter().cloned());
            let speed = resolve_rpm(reader.rpm, resampled.rpm, engine)?;
            notes.extend(speed.note);
            let rpm = speed.rpm;
            let analysis = enginedyn_pipeline::analyse(engine, &resampled, rpm, &opts)
                .map_err(|e| Error::usage(e.to_string()))?;
            (shown, rpm, Some(analysis))
        }
        None => {
            let speed = resolve_rpm(reader.rpm, None, engine)?;
            notes.extend(speed.note);
            ("none".to_string(), speed.rpm, None)
        }
    };
    let mut result = ranked(
        engine,
        rod_model,
        rpm,
        analysis.as_ref(),
        weights,
        all_cranks,
    )?;
    notes.append(&mut result.notes);
    result.notes = notes;
    Ok(FiringOrders {
        study: result,
        diagram: shown,
        rpm,
    })
}

/// The firing-order study of `engine` at `rpm` with `rod_model`, its
/// journal torques from `analysis` (cylinder 1's torque for every
/// cylinder; `None`: the diagram-free criteria only): the one place the
/// balance study is set up, for `firing-orders` and the design report.
pub fn ranked(
    engine: &Engine,
    rod_model: enginedyn_engine::RodModel,
    rpm: f64,
    analysis: Option<&enginedyn_pipeline::Analysis>,
    weights: Weights,
    all_cranks: bool,
) -> Result<enginedyn_balance::Study> {
    let setup = Setup {
        engine,
        rod_model,
        omega: rpm * std::f64::consts::PI / 30.0,
        torque: analysis.map(|an| CylinderTorque {
            step: an.step,
            torque: &an.cylinder_torque,
        }),
        weights,
    };
    enginedyn_balance::study(&setup, all_cranks).map_err(|e| Error::usage(e.to_string()))
}
