//! The speed a command runs at, and where it came from.

use crate::error::{Error, Result};
use enginedyn_engine::Engine;
pub use enginedyn_engine::{MAX_RPM, MIN_RPM};
use enginedyn_numerics::format::human;

/// The speed a command runs at, and the note saying where it came from
/// when it is not the engine file's `operating.rpm`.
#[derive(Debug, Clone)]
pub struct Speed {
    /// rpm.
    pub rpm: f64,
    /// "speed 2200 rpm from the diagram's `# rpm` line (…)", when it
    /// differs from the engine file's.
    pub note: Option<String>,
}

/// The speed: the one given, else the diagram's, else the engine file's.
pub fn resolve_rpm(given: Option<f64>, diagram: Option<f64>, engine: &Engine) -> Result<Speed> {
    let file = engine.operating().rpm;
    let (rpm, source) = match (given, diagram, file) {
        (Some(r), _, _) => (r, "--rpm"),
        (None, Some(r), _) => (r, "the diagram file"),
        (None, None, Some(r)) => (r, "operating.rpm"),
        (None, None, None) => {
            return Err(Error::usage(
                "no engine speed: give --rpm, a `# rpm = N` line in the diagram, or `rpm` in [operating]",
            ));
        }
    };
    if !(rpm.is_finite() && (MIN_RPM..=MAX_RPM).contains(&rpm)) {
        let why = if rpm.is_finite() && rpm <= 0.0 {
            "the engine speed must be above 0 (a reversed engine is the same engine turning forward)"
        } else {
            "the engine speed must be from 0.001 to 100000 rpm"
        };
        return Err(match source {
            "--rpm" => Error::usage(format!("--rpm {}: {why}", human(rpm))),
            "operating.rpm" => Error::engine(format!("operating.rpm = {}: {why}", human(rpm))),
            _ => Error::data(format!("`# rpm` line: {} rpm: {why}", human(rpm))),
        });
    }
    let note = match file {
        // Two speeds within 1e-9 of each other are one speed.
        Some(f) if (f - rpm).abs() <= 1e-9 * f.abs() => None,
        Some(f) => Some(format!(
            "speed {} rpm from {source}, not the engine file's operating.rpm = {} rpm",
            human(rpm),
            human(f)
        )),
        None => Some(format!(
            "speed {} rpm from {source} (the engine file gives no operating.rpm)",
            human(rpm)
        )),
    };
    Ok(Speed { rpm, note })
}

/// The most speeds one sweep computes (INTERFACE.md, "Limits").
pub const MAX_SPEEDS: usize = 10_000;

/// Parses FROM:TO:STEP; TO is included when it falls on the step.
pub fn speeds(spec: &str) -> Result<Vec<f64>> {
    let bad = || {
        Error::usage(format!(
            "--rpm {spec}: expected FROM:TO:STEP with 0 < FROM <= TO <= {MAX_RPM} rpm and STEP > 0"
        ))
    };
    let parts: Vec<f64> = spec
        .split(':')
        .map(|x| enginedyn_ingest::read_number(x, false))
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| bad())?;
    let [from, to, step] = parts[..] else {
        return Err(bad());
    };
    speed_range(from, to, step, spec)
}

/// The speeds FROM, FROM + STEP, … up to TO (included when it falls on the
/// step); `shown` is how the error names the range (`FROM:TO:STEP`).
pub fn speed_range(from: f64, to: f64, step: f64, shown: &str) -> Result<Vec<f64>> {
    if !(from > 0.0 && to >= from && step > 0.0 && to <= MAX_RPM) {
        return Err(Error::usage(format!(
            "--rpm {shown}: expected FROM:TO:STEP with 0 < FROM <= TO <= {MAX_RPM} rpm and STEP > 0"
        )));
    }
    let n = ((to - from) / step + 1e-9).floor();
    if n + 1.0 > MAX_SPEEDS as f64 {
        return Err(Error::usage(format!(
            "--rpm {shown}: {} speeds; a sweep computes at most {MAX_SPEEDS}",
            n + 1.0
        )));
    }
    Ok((0..=n as usize).map(|k| from + k as f64 * step).collect())
}
