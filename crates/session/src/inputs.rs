//! `summary.json`'s `inputs`: what a result came from (the engine file and
//! the diagram files as given, their SHA-256 hashes, the version).

use crate::diagram::Input;
use crate::engine::Loaded;
use crate::error::Result;
use enginedyn_report::{Inputs, Source};

/// The engine's record (its file, the bundled example's text, or the text
/// it was given as) with the `diagrams`.
pub fn of(loaded: &Loaded, diagrams: &[Input<'_>]) -> Result<Inputs> {
    let engine = match (&loaded.path, loaded.bundled) {
        (Some(p), _) => Source::File(p),
        (None, Some(b)) => Source::Bundled(b.engine.as_bytes()),
        (None, None) => Source::Text("text", loaded.text.as_bytes()),
    };
    let diagrams: Vec<Source<'_>> = diagrams
        .iter()
        .map(|d| match d {
            Input::File(p) => Source::File(p),
            Input::Bundled(b) => Source::Bundled(b.diagram.as_bytes()),
            Input::Synthesised(s) => Source::Text("synthesised", s.text.as_bytes()),
        })
        .collect();
    Ok(Inputs::new(engine, &diagrams)?)
}
