//! `[combustion]` of the engine file, checked: the burn law and the load
//! of a synthesised diagram (INTERFACE.md "Combustion", PHYSICS.md
//! "Synthesis"). SI inside; the laws are `enginedyn_combustion`'s.

pub use enginedyn_combustion::{BurnLaw, GammaModel, Wiebe};

/// Intake valve closing without `ivc_deg` (deg): four-stroke.
pub const DEFAULT_IVC_DEG: f64 = -140.0;
/// Intake (port) closing without `ivc_deg` (deg): two-stroke.
pub const DEFAULT_IVC_DEG_TWO_STROKE: f64 = -100.0;
/// Exhaust valve opening without `evo_deg` (deg): four-stroke.
pub const DEFAULT_EVO_DEG: f64 = 130.0;
/// Exhaust (port) opening without `evo_deg` (deg): two-stroke.
pub const DEFAULT_EVO_DEG_TWO_STROKE: f64 = 100.0;
/// Intake pressure without `intake_pressure_bar` (Pa).
pub const DEFAULT_INTAKE_PA: f64 = 1.0e5;

/// The load of a synthesised cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CombustionLoad {
    /// The net IMEP asked for (Pa).
    Imep(f64),
    /// The heat released into the gas per cylinder and cycle (J).
    Heat(f64),
}

/// A checked `[combustion]` section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CombustionSpec {
    /// The burn law (one Wiebe, or two with `[combustion.second]`).
    pub burn: BurnLaw,
    /// The load, when the file gives one (`imep_bar` or
    /// `heat_released_j`); without it a command needs `--imep`.
    pub load: Option<CombustionLoad>,
    /// Intake pressure (Pa, absolute).
    pub intake_pressure_pa: f64,
    /// Charge temperature at IVC (K).
    pub intake_temp_k: f64,
    /// The γ model (a Brunt model's IVC is [`Self::ivc_deg`]).
    pub gamma: GammaModel,
    /// Intake valve closing (deg from firing TDC, negative).
    pub ivc_deg: f64,
    /// Exhaust valve opening (deg from firing TDC).
    pub evo_deg: f64,
}
