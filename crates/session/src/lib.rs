//! enginedyn's application layer, under both front ends (the `enginedyn`
//! command line and the Python package): an engine with its tables built
//! once, reader and method options with their bounds checked in one place
//! ([`options`]), "analyse one diagram" ([`Session::analyse`]), "analyse
//! many" ([`Session::batch`]), the studies, and errors that carry their
//! class ([`Error`], [`Class`]) for the front end to map to an exit code or
//! an exception.
//!
//! The studies: each a function of the engine ([`Loaded`]), the reader and
//! method options, the diagram ([`Input`]; `None`: the engine file's
//! `diagram`) and the study's own parameters, returning a typed result
//! with its notes; nothing prints, and `enginedyn_report` writes the
//! tables and charts.
//!
//! - [`tolerance::study`]: each `[tolerances]` deviation's influence on the
//!   key results, their stack-up and the Monte Carlo check
//!   (`enginedyn tolerance`); [`tolerance::report_extra`], its linear model
//!   in `run --out`'s `report.html`.
//! - [`torsion::study`]: the crankshaft's torsional modes and forced
//!   response over speed from `[torsion]` (`enginedyn torsion`);
//!   [`torsion::report_extra`], its section of `report.html`.
//! - [`firing::study`]: the even firing orders of the crank (or of every
//!   crank), ranked, with the diagram's journal torques
//!   (`enginedyn firing-orders`).
//! - [`accuracy::study`]: each method choice's error and run time against
//!   the most exact one (`enginedyn accuracy`).
//! - [`kinematics::Kinematics`]: the piston table over one revolution
//!   (`enginedyn kinematics`).
//!
//! ```
//! use enginedyn_session::{Input, Loaded, Method, Reader, Session, EXAMPLE};
//! let session = Session::new(
//!     Loaded::bundled(EXAMPLE).unwrap(),
//!     Reader::default(),
//!     Method { step_deg: Some(0.5), ..Method::default() },
//!     enginedyn_pipeline::Scope::Summary,
//! )
//! .unwrap();
//! let out = session.analyse(&[Input::Bundled(EXAMPLE)]).unwrap();
//! assert!(out.analysis.summary.imep_bar.unwrap() > 5.0);
//! ```

pub mod accuracy;
pub mod batch;
pub mod burn;
pub mod campaign;
pub mod design;
pub mod diagram;
pub mod engine;
pub mod error;
pub mod firing;
pub mod hashing;
pub mod inputs;
pub mod kinematics;
pub mod map;
pub mod options;
mod session;
pub mod speed;
pub mod sweep;
pub mod synth;
pub mod tolerance;
pub mod torsion;

pub use batch::{Analysed, Item, Times, Work};
pub use diagram::Input;
pub use engine::{BUNDLED, Bundled, EXAMPLE, Loaded};
pub use error::{Class, Error, Result};
pub use options::{Method, Reader};
pub use session::{Outcome, Session, shown_of, within};
