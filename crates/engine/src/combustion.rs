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

/// The highest net IMEP a synthesised cycle is asked for (bar): a
/// high-boost racing or heavy-duty diesel engine reaches 30–35 bar, so
/// more is a unit slip (`imep_bar`, `--imep`).
pub const MAX_IMEP_BAR: f64 = 40.0;
/// The lowest absolute intake pressure (bar): a throttled petrol engine
/// at idle, 0.2–0.3 bar.
pub const MIN_INTAKE_BAR: f64 = 0.2;
/// The highest absolute intake pressure (bar): a two-stage charged
/// engine at full load, 4–5 bar.
pub const MAX_INTAKE_BAR: f64 = 6.0;
/// The most heat one kilogram of trapped air can release with any fuel
/// (J/kg): the fuel's lower heating value over its stoichiometric
/// air-fuel ratio, 3.0 MJ/kg for petrol and diesel, 3.5 MJ/kg for
/// hydrogen (the highest).
pub const MAX_HEAT_PER_KG_AIR: f64 = 3.5e6;
/// The gas constant of air (J/(kg K)).
pub const R_AIR: f64 = 287.05;

/// The most heat (J) a cylinder of `bdc_volume_m3` (the whole cylinder:
/// swept plus clearance) can release per cycle when it traps air at
/// `intake_pressure_pa` and `intake_temp_k`: every bit of its volume air
/// (no residual gas), burnt at [`MAX_HEAT_PER_KG_AIR`].
pub fn max_heat_released_j(bdc_volume_m3: f64, intake_pressure_pa: f64, intake_temp_k: f64) -> f64 {
    MAX_HEAT_PER_KG_AIR * intake_pressure_pa * bdc_volume_m3 / (R_AIR * intake_temp_k)
}

/// The range of intake valve (or port) closing (deg from firing TDC) the
/// cycle model takes: a four-stroke's −270° to below 0°, a two-stroke's
/// −155° to below 0° (its ports open around BDC). The engine file's
/// `ivc_deg` and the analysis' `--ivc-deg` are held to it alike.
pub fn ivc_range(two_stroke: bool) -> (f64, f64) {
    if two_stroke {
        (-155.0, 0.0)
    } else {
        (-270.0, 0.0)
    }
}

/// `ivc_deg` within [`ivc_range`] (`lo ≤ ivc < 0`), or what is expected.
pub fn check_ivc(ivc_deg: f64, two_stroke: bool) -> Result<f64, String> {
    let (lo, hi) = ivc_range(two_stroke);
    if ivc_deg.is_finite() && ivc_deg >= lo && ivc_deg < hi {
        Ok(ivc_deg)
    } else {
        Err(format!(
            "{lo} to below {hi}° for a {}",
            if two_stroke {
                "two-stroke"
            } else {
                "four-stroke"
            }
        ))
    }
}

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
