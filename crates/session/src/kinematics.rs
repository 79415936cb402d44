//! The piston table (`enginedyn kinematics`): the crank mechanism's motion
//! over one revolution at the engine's speed.

use crate::engine::Loaded;
use crate::error::{Error, Result};
use crate::speed::resolve_rpm;
use enginedyn_kinematics::{Model, Table};
use std::f64::consts::PI;

/// The printed table's step (deg) when none is given: as the seeds print it.
pub const TABLE_STEP_DEG: f64 = 30.0;
/// The files' step (deg) when none is given.
pub const FILE_STEP_DEG: f64 = 0.1;

/// The piston motion of one engine at one speed, with one kinematics model.
#[derive(Debug)]
pub struct Kinematics<'a> {
    /// The engine.
    pub loaded: &'a Loaded,
    /// The model.
    pub model: Model,
    /// The speed (rpm).
    pub rpm: f64,
    /// The crank's angular speed (rad/s).
    pub omega: f64,
    /// Where the speed came from (when not the engine file's), then the
    /// engine's implausible values at that speed.
    pub notes: Vec<String>,
}

impl<'a> Kinematics<'a> {
    /// `loaded`'s mechanism with `model` at `rpm` (`None`: the engine
    /// file's `operating.rpm`).
    pub fn new(loaded: &'a Loaded, rpm: Option<f64>, model: Model) -> Result<Self> {
        let engine = &loaded.engine;
        let speed = resolve_rpm(rpm, None, engine)?;
        let mut notes: Vec<String> = speed.note.into_iter().collect();
        notes.extend(engine.plausibility_notes(Some(speed.rpm)));
        Ok(Self {
            loaded,
            model,
            rpm: speed.rpm,
            omega: speed.rpm * PI / 30.0,
            notes,
        })
    }

    /// The motion every `step` degrees from 0 to 360 inclusive (the table
    /// closes the revolution, as the seeds print it); the step must divide
    /// 360°.
    pub fn table(&self, step: f64) -> Result<Table> {
        let n = (360.0 / step).round();
        if !(step > 0.0) || (n * step - 360.0).abs() > 1e-9 || n < 1.0 {
            return Err(Error::usage(format!(
                "--step {step}: the step must divide 360°"
            )));
        }
        let rows = n as usize + 1;
        let mut t = Table::default();
        self.loaded
            .engine
            .mechanism()
            .fill(self.model, 0.0, step.to_radians(), rows, &mut t)
            .map_err(|e| {
                Error::usage(format!(
                    "{}: --kinematics {}: {e}",
                    self.loaded.shown(),
                    self.model.name()
                ))
            })?;
        Ok(t)
    }
}
