//! The engine model: geometry, masses, layout, firing and flywheel targets,
//! checked once, and the TOML engine file that describes it.
//!
//! The engine file is read in two steps (the way ripgrep reads its flags):
//! [`file::parse`] turns the TOML text into the raw keys as written (rejecting
//! unknown keys with the nearest known one), then [`Engine`] is built from
//! them, checking every bound and deriving the firing angles and crank throws.
//! Only a checked [`Engine`] reaches the computing crates; inside it
//! everything is SI (m, kg, Pa, rad).
//!
//! ```
//! let toml = r#"
//! cycle = "four-stroke"
//! cylinders = 4
//! firing_order = [1, 3, 4, 2]
//! bore_mm = 76.0
//! stroke_mm = 71.0
//! lambda = 0.26
//! compression_ratio = 9.9
//! [masses]
//! piston_group_kg = 0.45
//! rod_kg = 0.52
//! [operating]
//! rpm = 4900
//! "#;
//! let engine = enginedyn_engine::file::parse(toml, "vaz").unwrap();
//! assert_eq!(engine.cylinders(), 4);
//! // Even firing, 180° apart in the order 1-3-4-2: cylinder 3 fires at 180°.
//! assert!((engine.firing_angle(2).to_degrees() - 180.0).abs() < 1e-9);
//! ```

pub mod combustion;
pub mod file;
pub mod keys;
mod model;
pub mod template;
pub mod torsion;

pub use model::*;
