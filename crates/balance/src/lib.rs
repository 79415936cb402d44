//! Crank arrangements, even firing orders and free forces and moments of
//! the reciprocating masses: what `enginedyn firing-orders` ranks.
//!
//! - [`free_forces`]: free forces and moments of first and second order
//!   (series2), before counterweights, and the first-order moment left after
//!   them, per cylinder mass, throw, bank and axial position
//!   ([`FreeForces::of_engine`] for a checked engine).
//! - [`firing_orders`]: every even firing order a crank admits, each once
//!   (the same sequence started elsewhere is the same order), listed from
//!   cylinder 1; [`criteria`]: intervals per bank, alternating or
//!   interleaved scheme of a vee (seed 001), consecutive firings of
//!   neighbouring cylinders.
//! - [`crank_arrangements`]: the cranks that fire evenly for a layout and
//!   cylinder count, up to equivalence (turning, reversing end for end,
//!   mirroring). Beyond [`FULL_ENUMERATION_LIMIT`] throw sequences (an
//!   inline 12 four-stroke has 1.25 million) only the mirror-symmetric
//!   cranks are searched; where there are none (odd counts, two-strokes)
//!   up to [`HARD_ENUMERATION_LIMIT`] sequences, else an error (inline 11,
//!   two-stroke inline 11 and 12). [`study`] then carries at most
//!   [`MAX_RANKED_ORDERS`] orders to the journal torques, the best cranks by
//!   the diagram-free score first; each restriction is stated in the notes.
//! - [`journal_criteria`]: main-journal torques of one order by the torque
//!   crate's summation of the diagram's cylinder torque.
//! - [`study`]: all of it, scored ([`score`] documents the score) and ranked.
//!
//! Conventions are PHYSICS.md's and come from the engine crate
//! ([`enginedyn_engine::Engine::throw_of`], `bank_angle_of`): throw lags
//! `alpha_k` behind throw 1, bank angle `gamma`, firing at
//! `alpha + gamma (+ 360°)`, cylinders and journals counted from the free end.
//!
//! ```
//! use enginedyn_balance::{Train, criteria, firing_orders};
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
//! "#;
//! let engine = enginedyn_engine::file::parse(toml, "i4").unwrap();
//! let train = Train::of_engine(&engine);
//! // The flat crank 0-180-180-0 admits two even orders.
//! let orders = firing_orders(&train, &[0.0, 180.0, 180.0, 0.0]).unwrap();
//! let listed: Vec<_> = orders.iter().map(|o| o.order.clone()).collect();
//! assert_eq!(listed, vec![vec![1, 2, 4, 3], vec![1, 3, 4, 2]]);
//! // 1-3-4-2-(1) fires 3 after 4 and 1 after 2: two neighbour pairs.
//! assert_eq!(criteria(&train, &orders[1]).neighbour_consecutive, 2);
//! ```

mod crank;
mod free;
mod journal;
mod order;
pub mod score;
mod study;

pub use crank::{
    CrankSet, FULL_ENUMERATION_LIMIT, HARD_ENUMERATION_LIMIT, Train, crank_arrangements,
    even_firing_bank_angles, is_mirror_symmetric,
};
pub use free::{CylinderMass, FreeForces, free_forces};
pub use journal::{
    HARMONIC_SAMPLE_DEG, JournalCriteria, MAX_HARMONIC_ORDER, engine_with, journal_criteria,
};
pub use order::{FiringOrder, MAX_ORDERS, OrderCriteria, Scheme, criteria, firing_orders};
pub use score::{Terms, Weights};
pub use study::{
    CrankStudy, CylinderTorque, MAX_RANKED_ORDERS, OrderStudy, Setup, Study, cylinders_on, study,
};

use enginedyn_engine::EngineError;
use enginedyn_numerics::NumericsError;

/// Why a firing-order study cannot be done.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BalanceError {
    /// A `--weights` key that does not exist.
    #[error("--weights: unknown key `{key}`; expected intervals, neighbours, journal or balance")]
    UnknownWeight {
        /// The key as given.
        key: String,
    },
    /// A `--weights` entry that is not `key=number` with a number of 0 or more.
    #[error("--weights: `{key}={value}`: expected key=number with a number of 0 or more")]
    BadWeight {
        /// The key.
        key: String,
        /// The value as given.
        value: String,
    },
    /// A crank with the wrong number of throws.
    #[error("crank: {got} throw angles for {throws} throws")]
    CrankLength {
        /// Angles given.
        got: usize,
        /// Throws of the layout.
        throws: usize,
    },
    /// More firing orders than are listed.
    #[error("more than {limit} even firing orders on this crank; too many to list")]
    TooManyOrders {
        /// The limit.
        limit: usize,
    },
    /// More crank arrangements than are searched.
    #[error(
        "--all-cranks: more than {limit} throw sequences for {what} and no mirror-symmetric crank to fall back on"
    )]
    TooManyCranks {
        /// The engine, in words.
        what: String,
        /// The limit.
        limit: usize,
    },
    /// A crank and order the engine crate rejects.
    #[error("engine: {0}")]
    Engine(#[from] EngineError),
    /// Harmonics of a journal torque failed.
    #[error("journal torque harmonics: {0}")]
    Numerics(#[from] NumericsError),
}
