//! Combustion, both ways: what a measured cycle says of its burn (the
//! first-law heat release, burn points, the pressure rise) and the burn law
//! that makes a pressure for an engine that has none yet (the Wiebe
//! functions `crates/synth` integrates). One home for these laws, so a
//! synthesised trace analysed with the same γ model gives back its own
//! burn angles. The volume law stays in `kinematics::Cylinder`: this crate
//! takes `V` and `dV/dφ` on the grid. Angles are degrees from firing TDC,
//! pressures absolute in Pa, SI inside (PHYSICS.md "Combustion").
//!
//! - [`gamma`]: the ratio of specific heats, constant or Brunt's γ(T);
//! - [`wiebe`]: the single and double Wiebe law and its CA50 + 10–90
//!   duration form;
//! - [`smooth`]: the Savitzky–Golay filter applied before any derivative;
//! - [`mod@knock`]: MAPO and IMPO of the band-passed pressure, cycle by cycle;
//! - [`charge`]: the air a cylinder traps and the heat its fuel gives
//!   (the design model's load by the intake);
//! - [`friction`]: Chen–Flynn FMEP and the brake figures;
//! - [`wall`]: the heat lost to the walls (Woschni, Hohenberg), for the
//!   gross heat release;
//! - [`burn`]: one cycle's heat release (cumulative without a derivative
//!   of p), burn points by the min–max rule, the pressure rise, the gross
//!   work, and the curves of the mean trace.
//!
//! ```
//! use enginedyn_combustion::{BurnLaw, Wiebe, DEFAULT_A};
//! // A petrol burn: CA50 8° after TDC, 10–90 in 20°, m = 2.
//! let law = BurnLaw::single(Wiebe::from_ca50(8.0, 20.0, 2.0, DEFAULT_A)?);
//! assert!((law.angle_of(0.5) - 8.0).abs() < 1e-12);
//! assert!((law.angle_of(0.9) - law.angle_of(0.1) - 20.0).abs() < 1e-12);
//! # Ok::<(), enginedyn_combustion::CombustionError>(())
//! ```

pub mod burn;
pub mod charge;
pub mod friction;
pub mod gamma;
pub mod knock;
pub mod smooth;
mod sweep;
pub mod wall;
pub mod wiebe;

pub use burn::{
    BurnPoints, Curves, CycleBurn, CycleGrid, DEFAULT_LEVELS, DEFAULT_WINDOW, Options, WindowLaw,
    analyse, analyse_with, analyse_with_law, curves, gross_work,
};
pub use gamma::{DEFAULT_GAMMA, DEFAULT_INTAKE_TEMP_K, DEFAULT_IVC_DEG, GammaModel, brunt};
pub use knock::{Knock, KnockFigures, band_passed_window, knock};
pub use smooth::{Filter, Smoothing};
pub use wall::{DEFAULT_WALL_TEMP_K, WallHeat, WallModel};
pub use wiebe::{BurnLaw, DEFAULT_A, Wiebe};

/// Why a law or an analysis cannot be set up. Messages carry the
/// parameter's name, the value and the range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CombustionError {
    /// A parameter out of its range.
    #[error("{name} = {value}: expected {lo} to {hi}")]
    Range {
        /// The parameter's name (as the engine file or the flag says it).
        name: &'static str,
        /// The value given.
        value: f64,
        /// Lowest value allowed.
        lo: f64,
        /// Highest value allowed.
        hi: f64,
    },
    /// The inputs do not fit together (lengths, the grid, the window).
    #[error("{0}")]
    Input(String),
}

/// `Ok` when `lo ≤ value ≤ hi` (NaN is refused).
pub(crate) fn check_range(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
) -> Result<(), CombustionError> {
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(CombustionError::Range {
            name,
            value,
            lo,
            hi,
        })
    }
}
