//! The accuracy study (`enginedyn accuracy`, INTERFACE.md): each method
//! choice's error against the most exact one and its run time
//! (`enginedyn_accuracy::study`), on the user's diagram.

use crate::diagram::{Input, diagram_options, diagram_path, parse_diagram};
use crate::engine::Loaded;
use crate::error::{Error, Result};
use crate::options::Reader;
use crate::speed::resolve_rpm;
use enginedyn_accuracy::Accuracy;
use enginedyn_ingest::{Interp, Quantity};

/// An accuracy study's result.
#[derive(Debug)]
pub struct AccuracyStudy {
    /// The study (its own notes in `study.notes`).
    pub study: Accuracy,
    /// The speed (rpm).
    pub rpm: f64,
    /// Where the speed came from, when not the engine file's.
    pub speed_note: Option<String>,
}

/// The accuracy study of `loaded` on `diagram` (`None`: the engine file's
/// `diagram`), read with `reader` (its `rpm` the speed given). The diagram
/// is read whole (every study puts it on several grids).
pub fn study(
    loaded: &Loaded,
    reader: &Reader,
    diagram: Option<Input<'_>>,
) -> Result<AccuracyStudy> {
    let engine = &loaded.engine;
    let path;
    let input = match diagram {
        Some(d) => d,
        None => {
            path = diagram_path(None, loaded)?;
            Input::File(&path)
        }
    };
    let (parse, grid) = diagram_options(engine, reader, 0.1, Interp::Spline)?;
    let diagram = parse_diagram(input, &parse)?;
    if diagram.quantity != Quantity::Pressure {
        return Err(Error::data(format!(
            "{}: a turning-moment file; the accuracy study needs pressure",
            input.shown()
        )));
    }
    let speed = resolve_rpm(reader.rpm, diagram.rpm, engine)?;
    let rpm = speed.rpm;
    let study = enginedyn_accuracy::study(&enginedyn_accuracy::Input {
        engine,
        diagram: &diagram,
        grid,
        rpm,
    })
    .map_err(|e| Error::data(e.to_string()))?;
    Ok(AccuracyStudy {
        study,
        rpm,
        speed_note: speed.note,
    })
}
