//! Manufacturing and measurement tolerances: how far each one moves the key
//! results, their stack-up, and a Monte Carlo check of the linear answer
//! (`enginedyn tolerance`, INTERFACE.md).
//!
//! The method is seed 004's small deviations: each result `y` is linearised
//! in the deviations `dx_i`, `dy = Σ (∂y/∂x_i) dx_i`, and each parameter's
//! relative influence coefficient is `K_i = (∂y/∂x_i)(x_i0 / y0)`, so that
//! `dy/y0 = Σ K_i dx_i/x_i0`. The derivatives come from the real pipeline:
//! analytic for the geometry (stroke, clearance, compression ratio, head
//! fixed), central differences of full [`enginedyn_pipeline::analyse`]
//! runs for everything else, with the step halved until the quotient
//! settles ([`linear`]). The stack-up is the worst case `Σ |s_i| t_i` and
//! the root-sum-square `sqrt(Σ (s_i t_i)²)/√3`, the standard deviation the
//! linear model predicts for deviations uniform on `[-t, t]`; a seeded
//! Monte Carlo run ([`monte_carlo`]) over the same box checks it, and
//! their relative difference is the linearity error.
//!
//! Results that cancel to 0 at nominal (the free forces of a balanced
//! engine, low torque orders of an even-firing one) have a kink there: the
//! linear model gives one-sided slopes and an upper bound, the Monte Carlo
//! spread is the answer; [`Stack::zero`] says so.
//!
//! ```
//! use enginedyn_tolerance::{Evaluator, Output, inputs, study};
//! let toml = r#"
//! cycle = "four-stroke"
//! cylinders = 1
//! bore_mm = 76.0
//! stroke_mm = 71.0
//! rod_length_mm = 136.5
//! compression_ratio = 9.9
//! [masses]
//! piston_group_kg = 0.45
//! rod_kg = 0.52
//! [operating]
//! rpm = 3000
//! [tolerances]
//! rod_length_mm = 0.1
//! "#;
//! let engine = enginedyn_engine::file::parse(toml, "demo").unwrap();
//! let tol = enginedyn_engine::file::tolerances(toml).unwrap();
//! let (inputs, _) = inputs(&engine, &tol).unwrap();
//! // A pressure peak at firing TDC on a 1° grid over the 720° cycle.
//! let p: Vec<f64> = (0..720)
//!     .map(|k| if k < 360 { k as f64 } else { k as f64 - 720.0 })
//!     .map(|deg| 1e5 + 20e5 * (-(deg / 40.0).powi(2)).exp())
//!     .collect();
//! let diagram = enginedyn_ingest::Resampled::from_grid(1.0, p);
//! let opts = enginedyn_pipeline::Options { step_deg: 1.0, ..Default::default() };
//! let ev = Evaluator::new(&engine, &diagram, 3000.0, opts, &inputs).unwrap();
//! let s = study(&ev, &ev, 200, 1).unwrap();
//! // A longer rod raises the piston against the fixed head:
//! // d eps / dL = (eps - 1)² / S for a central crank (L and S in mm).
//! let row = s.rows_of(Output::CompressionRatio).next().unwrap();
//! let expected = (9.9_f64 - 1.0).powi(2) / 71.0; // per mm
//! assert!((row.sensitivity.value - expected).abs() < 1e-9 * expected);
//! ```

mod keys;
pub mod linear;
pub mod monte_carlo;
mod perturb;
mod study;

pub use keys::{Input, OUTPUTS, Output, Parameter, inputs};
pub use linear::{Method, Sensitivity};
pub use monte_carlo::MonteCarlo;
pub use perturb::{Evaluator, Geometry, Outputs, geometry};
pub use study::{NONLINEAR, RESOLUTION, Row, Stack, Study, study};

/// Why a tolerance study cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum ToleranceError {
    /// A key the `[tolerances]` section does not know.
    #[error("unknown key `{0}` in [tolerances]")]
    UnknownKey(String),
    /// A tolerance outside its bounds.
    #[error("tolerances.{key} = {value}: expected {expected}")]
    Invalid {
        /// The key.
        key: &'static str,
        /// The value as given.
        value: f64,
        /// What is expected.
        expected: String,
    },
    /// A key that does not apply to this mechanism.
    #[error("tolerances.{key}: does not apply: {why}")]
    NotApplicable {
        /// The key.
        key: &'static str,
        /// Why not.
        why: &'static str,
    },
    /// Nothing to vary.
    #[error(
        "no tolerances: the engine file needs a [tolerances] section with at least one deviation above 0 (keys: stroke_mm, rod_length_mm, pin_offset_mm, bore_mm, piston_group_kg, rod_kg, throw_angle_deg, tdc_deg, yoke_slot_squareness_deg)"
    )]
    NoTolerances,
    /// Inconsistent input.
    #[error("{0}")]
    Input(String),
    /// A perturbed engine is rejected.
    #[error("a perturbed engine: {0}")]
    Engine(#[from] enginedyn_engine::EngineError),
    /// A perturbed mechanism cannot exist.
    #[error("a perturbed mechanism: {0}")]
    Kinematics(#[from] enginedyn_kinematics::KinematicsError),
    /// The pipeline failed.
    #[error(transparent)]
    Pipeline(#[from] enginedyn_pipeline::PipelineError),
    /// Interpolating the diagram failed.
    #[error(transparent)]
    Numerics(#[from] enginedyn_numerics::NumericsError),
}
