//! Torsional vibration of a chain of rigid inertias on torsional springs:
//! natural frequencies and mass-normalised modes, the damped forced response
//! to harmonic torques, and the time synthesis of several orders.
//!
//! Engine-free: a [`Chain`] is a list of inertias `J_1 … J_n` (kg m²) and
//! the springs `k_1 … k_{n-1}` (N m/rad) between neighbours, with modal
//! damping (one ratio `ζ` for every mode) plus discrete dampers (across a
//! spring, or from a mass to the frame). [`CrankTrain`] lays a crankshaft
//! out as such a chain from the free end (an optional tuned damper ring, an
//! optional front mass, one mass per throw, the flywheel, an optional driven
//! load) and names its masses and sections. PHYSICS.md ("Torsional
//! vibration") gives the equations:
//!
//! - modes from `K v = ω² M v`, solved as the symmetric `M^-1/2 K M^-1/2`
//!   ([`Chain::modes`]); mode 0 is the rigid rotation;
//! - forced response at `ω`: `(K − ω² M + i ω C) Θ = T`, with
//!   `C = M Φ diag(2 ζ ω_n) Φᵀ M` plus the discrete dampers ([`Solver`]);
//! - several orders summed in time with their phases ([`Synthesis`]);
//! - where engine orders meet the natural frequencies: the critical speed
//!   `60 f / k` ([`critical_speed_rpm`], [`crossings`]) and the major
//!   orders ([`is_major_order`]), which the Campbell diagram draws;
//! - a response's peak between sampled speeds ([`climb`]: uphill over the
//!   samples, then Brent's method between the best one's neighbours),
//!   which the study uses for each resonance's peak and the largest
//!   free-end angle and section torque.
//!
//! Mode shapes here are mass-normalised (`vᵀ M v = 1`, [`Modes`]). What
//! `enginedyn torsion` writes to `modes.csv` is each elastic mode divided
//! by its value at the free end ([`Layout::free_end`]: the front mass, else
//! throw 1; a damper ring sits before it in the chain and is listed first),
//! so the free end reads 1 (by the largest component instead, if the free
//! end is a node).
//!
//! ```
//! use enginedyn_torsion::{Chain, Solver, Complex64};
//! // Two discs of 1 and 3 kg m² on a 1e5 N m/rad shaft.
//! let chain = Chain::new(vec![1.0, 3.0], vec![1e5])?.with_damping_ratio(0.02)?;
//! let solver = Solver::new(&chain)?;
//! let f = solver.modes().frequency_hz(1);
//! let closed = (1e5_f64 * 4.0 / 3.0).sqrt() / std::f64::consts::TAU;
//! assert!((f - closed).abs() < 1e-12 * closed);
//! // 100 N m on disc 1 at the resonance: the damped response.
//! let w = solver.modes().omega[1];
//! let theta = solver.respond(w, &[Complex64::new(100.0, 0.0), Complex64::new(0.0, 0.0)])?;
//! assert!(theta[0].norm() > 1e-3);
//! # Ok::<(), enginedyn_torsion::TorsionError>(())
//! ```

mod campbell;
mod chain;
mod peak;
mod train;

pub use campbell::{Crossing, critical_speed_rpm, crossings, is_major_order, order_frequency_hz};
pub use chain::{Chain, Modes, Solver};
pub use enginedyn_numerics::fourier::Synthesis;
pub use nalgebra::Complex;
pub use peak::{Peak, climb};
pub use train::{CrankTrain, Damper, Layout, Section};

/// A complex amplitude `X` of `Re(X e^{i ω t})`.
pub use enginedyn_numerics::fourier::Complex64;

/// Why a chain cannot be built or solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TorsionError {
    /// A parameter is out of its range.
    #[error("{what} {value}: expected {expected}")]
    Invalid {
        /// Which parameter (with its index, if any).
        what: String,
        /// The value given.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// The number of springs, dampers or loads does not fit the masses.
    #[error("{what}: {got} given, {need} needed")]
    Shape {
        /// What was counted.
        what: &'static str,
        /// How many were given.
        got: usize,
        /// How many the chain needs.
        need: usize,
    },
    /// The eigen solver did not converge (never seen on a chain).
    #[error("the symmetric eigen solver did not converge")]
    Eigen,
    /// The dynamic stiffness of an undamped chain is singular: an undamped
    /// resonance hit exactly.
    #[error(
        "the dynamic stiffness is singular at {omega} rad/s: an undamped resonance hit exactly (give a damping ratio above 0)"
    )]
    Singular {
        /// The excitation's angular frequency (rad/s).
        omega: f64,
    },
    /// The dynamic stiffness cannot be solved in double precision, though
    /// the chain is damped (so no resonance is the cause) or its entries
    /// overflow: its inertias, stiffnesses and the frequency are too far
    /// apart.
    #[error(
        "the dynamic stiffness cannot be solved at {omega} rad/s: {}the chain's inertias and stiffnesses (k/J up to {stiffest} s⁻²) and the frequency are too far apart for double precision; check their units",
        if *damped { "the chain is damped, so no resonance is the cause: " } else { "" }
    )]
    Precision {
        /// The excitation's angular frequency (rad/s).
        omega: f64,
        /// The largest `(k_left + k_right) / J` of the chain's masses (s⁻²).
        stiffest: f64,
        /// Whether the chain has any damping.
        damped: bool,
    },
}

pub(crate) fn check(
    what: impl FnOnce() -> String,
    value: f64,
    ok: bool,
    expected: &'static str,
) -> Result<(), TorsionError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(TorsionError::Invalid {
            what: what(),
            value,
            expected,
        })
    }
}
