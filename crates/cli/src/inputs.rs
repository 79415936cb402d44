//! `summary.json`'s `inputs`: what a command's results came from (the
//! engine file and the diagram files as given, their SHA-256 hashes, the
//! version), built here from the paths the command read.

use crate::Failure;
use crate::args::RunArgs;
use crate::run::{EXAMPLE_DIAGRAM, EXAMPLE_ENGINE, Loaded};
use enginedyn_report::{Inputs, Source};
use std::path::{Path, PathBuf};

/// The engine's record (its file, or the bundled example's text) with the
/// `diagrams` (`None`: the bundled diagram).
pub fn of(loaded: &Loaded, diagrams: &[Option<&Path>]) -> Result<Inputs, Failure> {
    let engine = match &loaded.path {
        Some(p) => Source::File(p),
        None => Source::Bundled(EXAMPLE_ENGINE.as_bytes()),
    };
    let diagrams: Vec<Source<'_>> = diagrams
        .iter()
        .map(|d| d.map_or(Source::Bundled(EXAMPLE_DIAGRAM.as_bytes()), Source::File))
        .collect();
    Ok(Inputs::new(engine, &diagrams)?)
}

/// `run`'s inputs: the engine and the `--torque` file, else the diagram
/// files (one, or one per cylinder).
pub fn of_run(a: &RunArgs, loaded: &Loaded) -> Result<Inputs, Failure> {
    let files: Vec<Option<PathBuf>> = match &a.torque {
        Some(p) => vec![Some(p.clone())],
        None => crate::run::diagram_files(a, loaded)?.1,
    };
    let paths: Vec<Option<&Path>> = files.iter().map(Option::as_deref).collect();
    of(loaded, &paths)
}
