//! One diagram over a range of speeds (`enginedyn sweep`): the gas load
//! the same at every speed, inertia growing with ω², one flywheel for the
//! whole sweep. Each speed's analysis is kept as its summary alone
//! ([`Point`]), so memory does not grow with the curves of every speed.

use crate::diagram::{Input, load_diagram};
use crate::error::Result;
use crate::session::Session;
use enginedyn_numerics::format::human;
use enginedyn_pipeline::Point;
use rayon::prelude::*;

/// A sweep's results.
#[derive(Debug)]
pub struct Sweep {
    /// One point per speed, in order, each with its notes.
    pub points: Vec<Point>,
    /// The speed the one flywheel was sized at (rpm).
    pub sized_at: f64,
    /// Where that speed came from.
    pub source: &'static str,
    /// Whether a flywheel part was sized (and applied at every speed).
    pub flywheel: bool,
}

impl Session {
    /// The analyses of `diagram` at every speed of `rpms` (`shown`: how
    /// the notes name the speeds given, e.g. `1000:3000:500`).
    pub fn sweep(&self, diagram: Input<'_>, rpms: &[f64], shown: &str) -> Result<Sweep> {
        let engine = self.engine();
        let resampled = load_diagram(diagram, &self.parse, &self.grid)?;
        let analyse = |rpm: f64| {
            enginedyn_pipeline::analyse_with(self.tables(), engine, &resampled, rpm, &self.opts)
                .map(Point::of)
                .map_err(|e| crate::Error::usage(e.to_string()))
        };
        // One flywheel for the whole sweep: sized at the engine file's speed
        // (else the diagram's), the same part on every row.
        let (sized_at, source) = match (engine.operating().rpm, resampled.rpm) {
            (Some(r), _) => (r, "the engine file's operating.rpm"),
            (None, Some(r)) => (r, "the diagram's `# rpm` line"),
            (None, None) => (
                rpms[rpms.len() / 2],
                "the middle of the sweep (no speed in the engine file or diagram)",
            ),
        };
        let mut points: Vec<Point> = rpms
            .par_iter()
            .map(|&rpm| analyse(rpm))
            .collect::<Result<_>>()?;
        // The sizing speed's own run when it is one of the sweep's.
        let part = match points
            .iter()
            .find(|p| p.summary.rpm.to_bits() == sized_at.to_bits())
        {
            Some(p) => p.flywheel.clone(),
            None => analyse(sized_at)?.flywheel,
        };
        let file_rpm = engine.operating().rpm;
        for p in &mut points {
            if let Some(part) = &part {
                p.with_flywheel(part);
            }
            let rpm = p.summary.rpm;
            let notes = &mut p.summary.notes;
            if file_rpm.is_none_or(|f| f.to_bits() != rpm.to_bits()) {
                notes.push(format!(
                    "speed {} rpm from --rpm {}{}",
                    human(rpm),
                    shown,
                    file_rpm.map_or(
                        " (the engine file gives no operating.rpm)".to_string(),
                        |f| format!(", not the engine file's operating.rpm = {} rpm", human(f))
                    )
                ));
            }
            if part.is_some() {
                notes.push(format!(
                    "flywheel sized once at {} rpm ({source}): the same part at every speed; speed_fluctuation_achieved is the δ it gives here",
                    human(sized_at)
                ));
            }
        }
        Ok(Sweep {
            points,
            sized_at,
            source,
            flywheel: part.is_some(),
        })
    }
}
