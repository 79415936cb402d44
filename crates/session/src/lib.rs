//! enginedyn's application layer, under both front ends (the `enginedyn`
//! command line and the Python package): an engine with its tables built
//! once, reader and method options with their bounds checked in one place
//! ([`options`]), "analyse one diagram" ([`Session::analyse`]), "analyse
//! many" ([`Session::batch`]), and errors that carry their class
//! ([`Error`], [`Class`]) for the front end to map to an exit code or an
//! exception.
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

pub mod batch;
pub mod diagram;
pub mod engine;
pub mod error;
pub mod inputs;
pub mod options;
mod session;
pub mod speed;
pub mod sweep;

pub use batch::{Item, Times, Work};
pub use diagram::Input;
pub use engine::{BUNDLED, Bundled, EXAMPLE, Loaded};
pub use error::{Class, Error, Result};
pub use options::{Method, Reader};
pub use session::{Outcome, Session, shown_of, within};
