//! Synthetic indicator diagrams from a documented cycle model, so that the
//! bundled example can be regenerated exactly and tests can use diagrams
//! whose physics is known.
//!
//! Two kinds of diagram:
//!
//! - [`CycleModel`] → [`pressure_trace`]: a single-zone, first-law cycle.
//!   From intake valve closing (IVC) to exhaust valve opening (EVO) the
//!   pressure follows `dp/dphi = ((g - 1) dQ/dphi - g p dV/dphi) / V`
//!   (classical RK4 on an internal step of at most 0.025°, cubic Hermite
//!   interpolation to the output angles) with a Wiebe heat release
//!   `x_b = 1 - exp(-a ((phi - soc)/dur)^(m+1))`, `dQ = Q dx_b`, and the
//!   ratio of specific heats `g` blended from compression to expansion with
//!   `x_b`. Gas exchange is a blow-down to the exhaust pressure, the exhaust
//!   stroke, a cosine-blended valve overlap around gas-exchange TDC and the
//!   intake stroke (for a two-stroke: blow-down, then a blend to the
//!   scavenge pressure around BDC). The curve is periodic, positive,
//!   continuous and continuously differentiable ([`CycleSolution`] lists
//!   the joins). Optional [`Losses`] add Woschni's wall heat transfer and
//!   blow-by through an equivalent orifice to the closed part (off in
//!   every preset); with `heat_released_j = 0` the cycle is motored (a
//!   fuel cut), the trace that a TDC calibration needs.
//! - [`AnalyticDiagram`] → [`analytic_pressure`]: a smooth periodic
//!   pressure known in closed form (a base pressure plus a periodically
//!   wrapped Gaussian peak), for accuracy studies of interpolation and
//!   quadrature; [`analytic_work`] gives its `∮ p dV` to rounding.
//!
//! The volume law is the kinematics crate's ([`Cylinder::volume`],
//! [`Cylinder::dvolume`]): piston motion is never re-derived here.
//! Angles are cycle angles in degrees from firing TDC, pressures absolute
//! in Pa, as in the project's `PHYSICS.md`.
//!
//! ```
//! use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
//! use enginedyn_synth::{CycleModel, indicated_work, peak_pressure, pressure_trace};
//! // VAZ-2108 type cylinder: R = 35.5 mm, lambda = 0.26, bore 76 mm, CR 9.9.
//! let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
//! let cyl = Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap();
//! let model = CycleModel::petrol_full_load();
//! let trace = pressure_trace(&cyl, &model, 1.0).unwrap();
//! assert_eq!(trace.len(), 720);
//! let imep_bar = indicated_work(&cyl, &trace, 720.0) / cyl.swept_volume() / 1e5;
//! assert!(imep_bar > 9.5 && imep_bar < 11.5);
//! let (deg, p) = peak_pressure(&trace).unwrap();
//! assert!(p > 50e5 && p < 75e5 && deg > 10.0 && deg < 20.0);
//! ```

use enginedyn_kinematics::{Cylinder, KinematicsError};
use std::f64::consts::PI;

pub mod bundled;
mod design;
pub use design::{
    Air, DEFAULT_EVO_DEG, DEFAULT_EVO_DEG_TWO_STROKE, DEFAULT_IVC_DEG_TWO_STROKE,
    DESIGN_BLOWDOWN_DEG, DESIGN_STEP_DEG, Design, DesignModel, IMEP_WORK_STEP_DEG, Load, design,
    design_trace, exhaust_pressure_for, imep_of,
};
pub use enginedyn_combustion::{
    BurnLaw, CombustionError, DEFAULT_A, DEFAULT_GAMMA, DEFAULT_INTAKE_TEMP_K, DEFAULT_IVC_DEG,
    GammaModel, Wiebe,
};

/// Largest internal step of the closed-part integration (deg).
pub const CLOSED_STEP_DEG: f64 = 0.025;
/// Width of the blend from the intake pressure into the compression
/// polytrope just before IVC (deg): it makes the join at IVC C1.
pub const IVC_RAMP_DEG: f64 = 10.0;
/// Width of the cosine blend from the exhaust to the intake pressure (deg),
/// centred on gas-exchange TDC (360°; BDC, 180°, for a two-stroke).
pub const EXCHANGE_BLEND_DEG: f64 = 30.0;

/// Why a trace cannot be generated. Messages carry the bad value and what
/// was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SynthError {
    /// A model or output parameter out of range.
    #[error("{name} = {value}: expected {expected}")]
    Parameter {
        /// The parameter's name (a [`CycleModel`] field or `step_deg`).
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is expected.
        expected: String,
    },
    /// The burn law or the γ model out of range (the combustion crate's
    /// message names the key).
    #[error("{0}")]
    Combustion(#[from] CombustionError),
    /// A cylinder the kinematics crate refuses (its message names the
    /// dimension).
    #[error("{0}")]
    Geometry(#[from] KinematicsError),
    /// A design load that no heat release gives: an IMEP target below the
    /// motored cycle's, or one the solver could not meet.
    #[error("{0}")]
    Load(String),
    /// The closed-part integration left the physical range (pressure not
    /// positive or not finite), e.g. an absurd heat release.
    #[error("closed-part integration failed at {deg}° (pressure {pressure_pa} Pa)")]
    Diverged {
        /// Cycle angle (deg) where it happened.
        deg: f64,
        /// The pressure reached (Pa).
        pressure_pa: f64,
    },
}

/// Gas constant of the charge, air (J/(kg K)): the trapped mass from the
/// state at IVC and the gas temperature `T = p V / (m R)`.
pub const GAS_CONSTANT: f64 = 287.0;

/// Woschni's gas-velocity factor `C1` for compression, combustion and
/// expansion (m/s per m/s of mean piston speed).
pub const WOSCHNI_C1: f64 = 2.28;

/// Woschni's combustion term `C2` (m/(s K)) for a direct-injection engine,
/// used after the start of combustion of a fired cycle.
pub const WOSCHNI_C2: f64 = 3.24e-3;

/// The closed part's losses: wall heat transfer and blow-by. Off in
/// [`Losses::NONE`] (every preset), so the bundled diagrams stay the
/// lossless single-zone cycle.
///
/// - **Wall heat transfer** after Woschni (G. Woschni, "A universally
///   applicable equation for the instantaneous heat transfer coefficient
///   in the internal combustion engine", SAE 670931, 1967):
///   `h = 3.26 B^-0.2 p^0.8 T^-0.55 w^0.8` (W/(m² K); bore `B` in m, `p`
///   in kPa, `T` in K), gas velocity `w = C1 c_m + C2 (V_d T_1 / (p_1 V_1))
///   (p - p_mot)` with [`WOSCHNI_C1`], [`WOSCHNI_C2`] after the start of a
///   fired cycle's combustion (0 before it and in a motored cycle), `c_m`
///   the mean piston speed, state 1 at IVC and `p_mot` the compression
///   polytrope through it. The heat flows to the wall through
///   `A = pi B^2 / 2 + 4 V / B` (flat head and piston crown, and the liner
///   above the piston) at `h A (T - T_wall)`, times `woschni_scale`.
/// - **Blow-by** through an equivalent orifice of area `blowby_area_m2`
///   (discharge coefficient included) to the crankcase: isentropic
///   compressible flow `m' = A p / sqrt(R T) psi(p_cc / p)`, choked below
///   the critical pressure ratio; none while the cylinder pressure is at or
///   below the crankcase pressure (no flow back). The gas leaves with its
///   enthalpy, so the first law gains `g p (dm/m)`.
///
/// With either on, the closed part integrates the pressure and the trapped
/// mass together:
/// `dp/dphi = ((g - 1)(dQ - dQ_wall) - g p dV) / V + g p (dm/dphi) / m`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Losses {
    /// Engine speed (rpm): turns the heat flow and the blow-by, rates in
    /// time, into rates per degree.
    pub rpm: f64,
    /// Gas temperature at IVC (K); with the IVC pressure and volume it
    /// gives the trapped mass.
    pub ivc_temperature_k: f64,
    /// Mean temperature of the combustion-chamber walls (K).
    pub wall_temperature_k: f64,
    /// Multiplier of Woschni's coefficient: 0 for no wall heat transfer, 1
    /// for the correlation as published.
    pub woschni_scale: f64,
    /// Effective blow-by orifice area (m²): 0 for none.
    pub blowby_area_m2: f64,
    /// Crankcase pressure (Pa), where the blow-by goes.
    pub crankcase_pressure_pa: f64,
}

impl Losses {
    /// No wall heat transfer and no blow-by (the other fields are unused).
    pub const NONE: Self = Self {
        rpm: 0.0,
        ivc_temperature_k: 330.0,
        wall_temperature_k: 400.0,
        woschni_scale: 0.0,
        blowby_area_m2: 0.0,
        crankcase_pressure_pa: 1.0e5,
    };

    /// Losses of a warm engine at `rpm`: Woschni's correlation as
    /// published, walls at 400 K (coolant at about 90 °C plus the gas-side
    /// film), 330 K at IVC (intake air warmed by the ports and the residual
    /// gas), and a 0.2 mm² blow-by orifice to a crankcase at 1 bar (about
    /// 1.5 % of the trapped mass a cycle for a 0.3 l cylinder motored at
    /// 1500 rpm; less at higher speed).
    pub fn warm_engine(rpm: f64) -> Self {
        Self {
            rpm,
            woschni_scale: 1.0,
            blowby_area_m2: 0.2e-6,
            ..Self::NONE
        }
    }

    /// True when there is wall heat transfer or blow-by.
    pub fn any(&self) -> bool {
        self.woschni_scale > 0.0 || self.blowby_area_m2 > 0.0
    }
}

/// The ratio of specific heats in the closed part's first-law step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Gas {
    /// The presets' blend: `compression` while nothing has burnt (the
    /// compression polytropic exponent, e.g. 1.35), going to `expansion`
    /// (e.g. 1.28) as the burnt fraction `x_b` goes to 1:
    /// `g = compression + (expansion - compression) x_b`; `compression`
    /// throughout a motored cycle.
    Blend {
        /// γ of the unburnt charge.
        compression: f64,
        /// γ of the burnt gas.
        expansion: f64,
    },
    /// The analysis' γ model (PHYSICS.md "Combustion"): a constant, or
    /// Brunt's γ(T) with `T = T_ivc p V / (p_ivc V_ivc)` from the state at
    /// the cycle's IVC (the model's own `ivc_deg` must be the cycle's).
    /// The step is then `d(pV)/dphi = (g - 1)(dQ/dphi - p dV/dphi)`, the
    /// first law whose integral is the analysis' cumulative heat release
    /// `Q = ∫ p dV + ∫ d(pV)/(g(T) - 1)`: a trace made so and analysed with
    /// the same model gives its burn back.
    Model(GammaModel),
}

/// The cycle model's parameters. Angles in degrees of cycle angle from
/// firing TDC (negative before it), pressures absolute in Pa.
///
/// Parameters come unchecked; [`CycleSolution::new`] (and so
/// [`pressure_trace`]) checks them once with [`CycleModel::check`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleModel {
    /// Intake manifold pressure (Pa): the cylinder pressure on the intake
    /// stroke and at IVC (the scavenge pressure of a two-stroke).
    pub intake_pressure_pa: f64,
    /// Exhaust back pressure (Pa): the cylinder pressure on the exhaust
    /// stroke after blow-down.
    pub exhaust_pressure_pa: f64,
    /// Intake valve closing (deg from firing TDC, negative: before it;
    /// `-130` is 590°, 50° after intake BDC). For a two-stroke: the port
    /// or valve closing that starts compression.
    pub ivc_deg: f64,
    /// Exhaust valve opening (deg after firing TDC; `130` is 50° before BDC).
    pub evo_deg: f64,
    /// The ratio of specific heats `g` of the first-law step: the presets'
    /// blend, or the analysis' γ model.
    pub gas: Gas,
    /// Net heat released into the gas per cycle (J): fuel energy times
    /// combustion efficiency, less wall heat losses. 0 gives a motored
    /// cycle (then `g = gamma_compression` throughout).
    pub heat_released_j: f64,
    /// The burn law (the combustion crate's Wiebe, single or double):
    /// start (SOC, the spark or injection timing plus the ignition delay),
    /// duration (at whose end the fraction `1 - exp(-a)` has burnt, 99.3 %
    /// for `a = 5`), efficiency `a` and shape `m` (2.0 for a spark-ignition
    /// engine, a burn rate peaking late; 0.5–1 for a diesel's early
    /// premixed peak).
    pub burn: BurnLaw,
    /// Duration of the exhaust blow-down after EVO (deg): the pressure
    /// leaves the expansion polytrope at EVO and reaches the exhaust
    /// pressure this many degrees later (cosine blend in `ln p`).
    pub blowdown_deg: f64,
    /// Two-stroke cycle (360°) instead of four-stroke (720°).
    pub two_stroke: bool,
    /// Wall heat transfer and blow-by on the closed part ([`Losses::NONE`]
    /// in every preset: the bundled diagrams have neither).
    pub losses: Losses,
}

impl CycleModel {
    /// A naturally aspirated petrol engine at wide-open throttle near its
    /// rated speed, tuned to a VAZ-2108 type cylinder (0.322 l swept,
    /// compression ratio 9.9) at 4900 rpm: IMEP 10.47 bar, peak 56.3 bar at
    /// 13° after TDC.
    ///
    /// - intake 0.95 bar (manifold loss at full throttle), exhaust 1.15 bar
    ///   (silencer back pressure near rated speed);
    /// - IVC 50° after BDC (−130°), EVO 50° before BDC (130°), typical
    ///   cam timing of a 1980s overhead-cam engine;
    /// - `g` 1.35 on compression, 1.28 on expansion (polytropic exponents
    ///   of a hot engine, Heywood ch. 9 and Kolchin & Demidov);
    /// - 660 J released into the gas (≈ 2050 J per litre swept: the fuel of
    ///   a slightly rich full-load charge, ≈ 1000 J, less incomplete
    ///   combustion and ≈ 30 % wall losses);
    /// - spark plus ignition delay: burn from 17° before TDC over 42°,
    ///   Wiebe `a = 5`, `m = 2` (50 % burnt 4.7° after TDC, peak pressure
    ///   13° after TDC as at best-torque spark timing);
    /// - blow-down over 40°.
    ///
    /// For a different swept volume scale `heat_released_j` in proportion.
    pub fn petrol_full_load() -> Self {
        Self {
            intake_pressure_pa: 0.95e5,
            exhaust_pressure_pa: 1.15e5,
            ivc_deg: -130.0,
            evo_deg: 130.0,
            gas: Gas::Blend {
                compression: 1.35,
                expansion: 1.28,
            },
            heat_released_j: 660.0,
            burn: BurnLaw::single(Wiebe::preset(-17.0, 42.0, 5.0, 2.0)),
            blowdown_deg: 40.0,
            two_stroke: false,
            losses: Losses::NONE,
        }
    }

    /// A turbocharged direct-injection diesel at full load, tuned to a
    /// 0.5 l cylinder (bore 84 mm, stroke 90 mm, compression ratio 17):
    /// IMEP 20.0 bar, peak 146 bar at 9.5° after TDC.
    ///
    /// - boost 2.2 bar, exhaust back pressure 1.9 bar (turbine inlet);
    /// - IVC 35° after BDC (−145°), EVO 55° before BDC (125°);
    /// - `g` 1.36 → 1.28;
    /// - 1700 J released into the gas (≈ 3400 J per litre swept, lean
    ///   full-load charge at λ ≈ 1.4 less wall losses);
    /// - injection plus delay: burn from 8° before TDC over 60°, Wiebe
    ///   `a = 5`, `m = 0.8` (an early, premixed-like burn rate);
    /// - blow-down over 45°.
    ///
    /// For a different swept volume scale `heat_released_j` in proportion.
    pub fn diesel_full_load() -> Self {
        Self {
            intake_pressure_pa: 2.2e5,
            exhaust_pressure_pa: 1.9e5,
            ivc_deg: -145.0,
            evo_deg: 125.0,
            gas: Gas::Blend {
                compression: 1.36,
                expansion: 1.28,
            },
            heat_released_j: 1700.0,
            burn: BurnLaw::single(Wiebe::preset(-8.0, 60.0, 5.0, 0.8)),
            blowdown_deg: 45.0,
            two_stroke: false,
            losses: Losses::NONE,
        }
    }

    /// A crankcase-scavenged two-stroke petrol engine at full load: exhaust
    /// port open from 100° after to 100° before TDC, scavenge 1.05 bar,
    /// exhaust 1.15 bar, burn from 20° BTDC over 45°, 400 J into the gas
    /// (tuned for a 0.33 l cylinder: IMEP about 6.5 bar).
    pub fn petrol_two_stroke() -> Self {
        Self {
            intake_pressure_pa: 1.05e5,
            exhaust_pressure_pa: 1.15e5,
            ivc_deg: -100.0,
            evo_deg: 100.0,
            gas: Gas::Blend {
                compression: 1.35,
                expansion: 1.28,
            },
            heat_released_j: 400.0,
            burn: BurnLaw::single(Wiebe::preset(-20.0, 45.0, 5.0, 2.0)),
            blowdown_deg: 50.0,
            two_stroke: true,
            losses: Losses::NONE,
        }
    }

    /// Length of the cycle (deg): 720 for a four-stroke, 360 for a two-stroke.
    pub fn cycle_deg(&self) -> f64 {
        if self.two_stroke { 360.0 } else { 720.0 }
    }

    /// Centre of the exhaust-to-intake blend (deg): gas-exchange TDC (360°)
    /// for a four-stroke, BDC (180°) for a two-stroke.
    pub fn exchange_centre_deg(&self) -> f64 {
        self.cycle_deg() / 2.0
    }

    /// Checks every parameter and the order of the events over the cycle:
    /// `IVC < SOC < EVO`, IVC before firing TDC and EVO after it, the
    /// blow-down over before the exchange blend starts, and the blend over
    /// before the ramp into IVC starts.
    pub fn check(&self) -> Result<(), SynthError> {
        let c = self.exchange_centre_deg();
        let half = EXCHANGE_BLEND_DEG / 2.0;
        let ivc_min = c + half + IVC_RAMP_DEG - self.cycle_deg();
        let test = |name, value: f64, ok: bool, expected: String| {
            if ok && value.is_finite() {
                Ok(())
            } else {
                Err(SynthError::Parameter {
                    name,
                    value,
                    expected,
                })
            }
        };
        let pos = || "positive".to_string();
        test(
            "intake_pressure_pa",
            self.intake_pressure_pa,
            self.intake_pressure_pa > 0.0,
            pos(),
        )?;
        test(
            "exhaust_pressure_pa",
            self.exhaust_pressure_pa,
            self.exhaust_pressure_pa > 0.0,
            pos(),
        )?;
        test(
            "ivc_deg",
            self.ivc_deg,
            self.ivc_deg >= ivc_min && self.ivc_deg < 0.0,
            format!("in [{ivc_min}, 0): after the exchange blend and its ramp, before firing TDC"),
        )?;
        test(
            "evo_deg",
            self.evo_deg,
            self.evo_deg > 0.0 && self.evo_deg < c - half,
            format!("in (0, {})", c - half),
        )?;
        test(
            "blowdown_deg",
            self.blowdown_deg,
            self.blowdown_deg > 0.0 && self.evo_deg + self.blowdown_deg <= c - half,
            format!(
                "positive, with evo_deg + blowdown_deg <= {} (the exchange blend starts there)",
                c - half
            ),
        )?;
        self.check_gas_and_burn()?;
        let l = &self.losses;
        test(
            "losses.woschni_scale",
            l.woschni_scale,
            l.woschni_scale >= 0.0,
            "0 or more".into(),
        )?;
        test(
            "losses.blowby_area_m2",
            l.blowby_area_m2,
            l.blowby_area_m2 >= 0.0,
            "0 or more".into(),
        )?;
        if l.any() {
            test("losses.rpm", l.rpm, l.rpm > 0.0, pos())?;
            test(
                "losses.ivc_temperature_k",
                l.ivc_temperature_k,
                l.ivc_temperature_k > 0.0,
                pos(),
            )?;
            test(
                "losses.wall_temperature_k",
                l.wall_temperature_k,
                l.wall_temperature_k > 0.0,
                pos(),
            )?;
            test(
                "losses.crankcase_pressure_pa",
                l.crankcase_pressure_pa,
                l.crankcase_pressure_pa > 0.0,
                pos(),
            )?;
        }
        Ok(())
    }

    /// The γ model and the burn law: each γ above 1 (a Brunt model's IVC
    /// the cycle's), the Wiebe laws in range, the burn starting between
    /// IVC and EVO, the heat 0 or more.
    fn check_gas_and_burn(&self) -> Result<(), SynthError> {
        let param = |name, value: f64, expected: String| SynthError::Parameter {
            name,
            value,
            expected,
        };
        match self.gas {
            Gas::Blend {
                compression,
                expansion,
            } => {
                for (name, g) in [
                    ("gamma_compression", compression),
                    ("gamma_expansion", expansion),
                ] {
                    if !(g > 1.0 && g.is_finite()) {
                        return Err(param(name, g, "above 1".into()));
                    }
                }
            }
            Gas::Model(g) => {
                g.check()?;
                if let GammaModel::Brunt { ivc_deg, .. } = g
                    && ivc_deg.to_bits() != self.ivc_deg.to_bits()
                {
                    return Err(param(
                        "ivc_deg",
                        ivc_deg,
                        format!(
                            "the cycle's ivc_deg ({}): γ(T) takes its state at the cycle's intake closing",
                            self.ivc_deg
                        ),
                    ));
                }
            }
        }
        if !(self.heat_released_j >= 0.0 && self.heat_released_j.is_finite()) {
            return Err(param(
                "heat_released_j",
                self.heat_released_j,
                "0 or more".into(),
            ));
        }
        self.burn.check()?;
        let start = self.burn.start_deg();
        if !(start > self.ivc_deg && start < self.evo_deg) {
            return Err(param(
                "start_deg",
                start,
                format!(
                    "between ivc_deg ({}) and evo_deg ({}): the burn starts in the closed part",
                    self.ivc_deg, self.evo_deg
                ),
            ));
        }
        Ok(())
    }

    /// Burnt mass fraction at cycle angle `deg` (the burn law, e.g. a
    /// Wiebe `1 - exp(-a ((deg - soc)/dur)^(m+1))` after SOC, 0 before).
    /// Angles are taken as they come, not wrapped (the closed part runs
    /// from `ivc_deg` < 0 to `evo_deg`).
    pub fn burnt_fraction(&self, deg: f64) -> f64 {
        self.burn.fraction(deg)
    }

    /// Burn rate `dx_b/dphi` (per degree) at cycle angle `deg`.
    pub fn burn_rate(&self, deg: f64) -> f64 {
        self.burn.rate(deg)
    }

    /// `p V` at IVC (Pa m³): the intake pressure times the volume there,
    /// the reference state of Brunt's γ(T).
    pub fn pv_at_ivc(&self, cyl: &Cylinder) -> f64 {
        self.intake_pressure_pa * cyl.volume(self.ivc_deg.to_radians())
    }

    /// The ratio of specific heats used in the first-law step at `deg`,
    /// for the state `pv` (Pa m³) given `pv_ivc` ([`Self::pv_at_ivc`]):
    /// the blend `compression + (expansion - compression) x_b` (or
    /// `compression` throughout a motored cycle), or the γ model at `pv`.
    #[inline]
    pub fn gamma(&self, deg: f64, pv: f64, pv_ivc: f64) -> f64 {
        match self.gas {
            Gas::Blend {
                compression,
                expansion,
            } => {
                if self.heat_released_j > 0.0 {
                    compression + (expansion - compression) * self.burnt_fraction(deg)
                } else {
                    compression
                }
            }
            Gas::Model(g) => g.gamma(pv, pv_ivc),
        }
    }

    /// γ of the unburnt charge at IVC: the blend's `compression`, or the
    /// γ model at the IVC state. The compression polytrope of the ramp
    /// into IVC (and Woschni's motored pressure) uses it.
    pub fn gamma_unburnt(&self) -> f64 {
        match self.gas {
            Gas::Blend { compression, .. } => compression,
            Gas::Model(g) => g.gamma(1.0, 1.0),
        }
    }

    /// `dp/dphi` (Pa per degree) of the closed part at `deg`, pressure `p`:
    /// `((g - 1) Q dx_b/dphi - g p dV/dphi) / V`. With the blend the term in
    /// `dg/dphi` of a variable-`g` first law is neglected (it is of the
    /// order of the heat release's uncertainty); with a γ model the step
    /// is `d(pV) = (g - 1)(dQ - p dV)`, the same expression, which the
    /// analysis' `Q = ∫ p dV + ∫ d(pV)/(g - 1)` integrates back exactly.
    pub fn closed_rate(&self, cyl: &Cylinder, deg: f64, p: f64) -> f64 {
        self.closed_rate_at(cyl, deg, p, self.pv_at_ivc(cyl))
    }

    /// [`Self::closed_rate`] given `pv_ivc` ([`Self::pv_at_ivc`]).
    #[inline]
    pub fn closed_rate_at(&self, cyl: &Cylinder, deg: f64, p: f64, pv_ivc: f64) -> f64 {
        let phi = deg.to_radians();
        let v = cyl.volume(phi);
        let dv = cyl.dvolume(phi) * (PI / 180.0);
        let g = self.gamma(deg, p * v, pv_ivc);
        let dq = self.heat_released_j * self.burn_rate(deg);
        ((g - 1.0) * dq - g * p * dv) / v
    }

    /// `(dp/dphi, dm/dphi)` (Pa and kg per degree) of the closed part with
    /// [`Losses`], at `deg`, pressure `p` and trapped mass `m`: the first
    /// law of [`Self::closed_rate`] less the wall heat flow, plus the
    /// blow-by's enthalpy. Without losses it is `(closed_rate, 0)`.
    /// `at_ivc` is the trapped state `(p, V, T)` at IVC, for Woschni's
    /// combustion term.
    pub fn closed_rate_with_losses(
        &self,
        cyl: &Cylinder,
        deg: f64,
        p: f64,
        m: f64,
        at_ivc: (f64, f64, f64),
    ) -> (f64, f64) {
        let l = &self.losses;
        let pv_ivc = at_ivc.0 * at_ivc.1;
        if !l.any() {
            return (self.closed_rate_at(cyl, deg, p, pv_ivc), 0.0);
        }
        let phi = deg.to_radians();
        let v = cyl.volume(phi);
        let dv = cyl.dvolume(phi) * (PI / 180.0);
        let g = self.gamma(deg, p * v, pv_ivc);
        let dq = self.heat_released_j * self.burn_rate(deg);
        let t = p * v / (m * GAS_CONSTANT);
        // Seconds per degree of crank angle.
        let per_deg = (PI / 180.0) / (l.rpm * PI / 30.0);
        let mut q_wall = 0.0;
        if l.woschni_scale > 0.0 {
            let b = cyl.bore();
            let mean_speed = 2.0 * cyl.mechanism().stroke() * l.rpm / 60.0;
            let (p1, v1, t1) = at_ivc;
            let mut w = WOSCHNI_C1 * mean_speed;
            if self.heat_released_j > 0.0 && deg > self.burn.start_deg() {
                let p_mot = p1 * (v1 / v).powf(self.gamma_unburnt());
                w += WOSCHNI_C2 * cyl.swept_volume() * t1 / (p1 * v1) * (p - p_mot);
            }
            let h =
                3.26 * b.powf(-0.2) * (p / 1e3).powf(0.8) * t.powf(-0.55) * w.max(0.0).powf(0.8);
            let area = PI * b * b / 2.0 + 4.0 * v / b;
            q_wall = l.woschni_scale * h * area * (t - l.wall_temperature_k) * per_deg;
        }
        let mut dm = 0.0;
        let pc = l.crankcase_pressure_pa;
        if l.blowby_area_m2 > 0.0 && p > pc {
            let r = pc / p;
            let critical = (2.0 / (g + 1.0)).powf(g / (g - 1.0));
            let psi = if r <= critical {
                g.sqrt() * (2.0 / (g + 1.0)).powf((g + 1.0) / (2.0 * (g - 1.0)))
            } else {
                (2.0 * g / (g - 1.0) * (r.powf(2.0 / g) - r.powf((g + 1.0) / g))).sqrt()
            };
            dm = -l.blowby_area_m2 * p / (GAS_CONSTANT * t).sqrt() * psi * per_deg;
        }
        (
            ((g - 1.0) * (dq - q_wall) - g * p * dv) / v + g * p * dm / m,
            dm,
        )
    }
}

/// The solved cycle: evaluates the model's pressure at any cycle angle.
///
/// The pieces, in cycle order (four-stroke angles; a two-stroke has its
/// exchange blend centred on 180° instead of 360°):
///
/// 1. closed part, IVC → EVO: the first-law ODE, RK4 at
///    [`CLOSED_STEP_DEG`] or finer, cubic Hermite between nodes (with the
///    ODE's own slope, so C1 and fourth order);
/// 2. blow-down, EVO → EVO + `blowdown_deg`: `ln p` blends (cosine) from
///    the expansion polytrope through `p(EVO)` (exponent `g(EVO)`) to
///    `ln p_exhaust`; C1 at both ends;
/// 3. exhaust stroke at the exhaust pressure until 345°;
/// 4. 345°–375°: cosine blend to the intake pressure (valve overlap);
/// 5. intake stroke at the intake pressure until IVC − [`IVC_RAMP_DEG`];
/// 6. the last [`IVC_RAMP_DEG`] before IVC: `ln p` blends (cosine) from
///    `ln p_intake` to the compression polytrope through `p_intake` at
///    IVC, so that the join at IVC is C1. (A C1 join that starts compression
///    at the intake pressure must dip below it first: by 1.9 %, 0.018 bar,
///    4° before IVC for the petrol preset.) With [`Losses`] the closed
///    part's slope at IVC also holds the wall heat flow and the blow-by,
///    which the ramp does not: the join is then continuous but not C1.
///
/// Each join is continuous by construction; the value at the cycle's end
/// equals that at 0 (the angle is wrapped).
#[derive(Debug, Clone)]
pub struct CycleSolution {
    cyl: Cylinder,
    model: CycleModel,
    h: f64,
    p: Vec<f64>,
    dp: Vec<f64>,
    p_evo: f64,
    g_evo: f64,
    v_evo: f64,
    v_ivc: f64,
    blowby_fraction: f64,
}

impl CycleSolution {
    /// Checks the model and integrates its closed part on `cyl` at
    /// [`CLOSED_STEP_DEG`] or finer.
    pub fn new(cyl: &Cylinder, model: &CycleModel) -> Result<Self, SynthError> {
        Self::with_step(cyl, model, CLOSED_STEP_DEG)
    }

    /// [`Self::new`] with the closed part's RK4 at `max_step_deg` or finer
    /// (0.001–0.5°).
    pub fn with_step(
        cyl: &Cylinder,
        model: &CycleModel,
        max_step_deg: f64,
    ) -> Result<Self, SynthError> {
        model.check()?;
        if !(0.001..=0.5).contains(&max_step_deg) {
            return Err(SynthError::Parameter {
                name: "max_step_deg",
                value: max_step_deg,
                expected: "0.001 to 0.5".into(),
            });
        }
        let span = model.evo_deg - model.ivc_deg;
        let n = (span / max_step_deg).ceil() as usize;
        let h = span / n as f64;
        // The trapped state at IVC; the mass changes only with blow-by
        // (without losses its rate is 0 and the pressure steps are those of
        // `closed_rate` alone).
        let v_ivc = cyl.volume(model.ivc_deg.to_radians());
        let p_ivc = model.intake_pressure_pa;
        let t_ivc = model.losses.ivc_temperature_k;
        let m_ivc = p_ivc * v_ivc / (GAS_CONSTANT * t_ivc);
        let f = |deg: f64, p: f64, m: f64| {
            model.closed_rate_with_losses(cyl, deg, p, m, (p_ivc, v_ivc, t_ivc))
        };
        let mut p = Vec::with_capacity(n + 1);
        let mut dp = Vec::with_capacity(n + 1);
        let (mut pi, mut mi) = (p_ivc, m_ivc);
        let mut k1 = f(model.ivc_deg, pi, mi);
        p.push(pi);
        dp.push(k1.0);
        for i in 0..n {
            let a = model.ivc_deg + h * i as f64;
            let k2 = f(a + h / 2.0, pi + h / 2.0 * k1.0, mi + h / 2.0 * k1.1);
            let k3 = f(a + h / 2.0, pi + h / 2.0 * k2.0, mi + h / 2.0 * k2.1);
            let k4 = f(a + h, pi + h * k3.0, mi + h * k3.1);
            pi += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            mi += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            let b = model.ivc_deg + h * (i + 1) as f64;
            if !(pi > 0.0 && pi.is_finite() && mi > 0.0) {
                return Err(SynthError::Diverged {
                    deg: b,
                    pressure_pa: pi,
                });
            }
            k1 = f(b, pi, mi);
            p.push(pi);
            dp.push(k1.0);
        }
        Ok(Self {
            blowby_fraction: 1.0 - mi / m_ivc,
            cyl: *cyl,
            model: *model,
            h,
            p_evo: pi,
            g_evo: model.gamma(
                model.evo_deg,
                pi * cyl.volume(model.evo_deg.to_radians()),
                p_ivc * v_ivc,
            ),
            v_evo: cyl.volume(model.evo_deg.to_radians()),
            v_ivc: cyl.volume(model.ivc_deg.to_radians()),
            p,
            dp,
        })
    }

    /// The model solved.
    pub fn model(&self) -> &CycleModel {
        &self.model
    }

    /// The highest pressure of the closed part at its integration nodes
    /// (Pa): the cycle's peak, to the node step.
    pub fn max_pressure(&self) -> f64 {
        self.p.iter().copied().fold(f64::MIN, f64::max)
    }

    /// The steepest pressure rise of the closed part (Pa/deg) and its
    /// angle (deg), from the integration's own derivative at its nodes.
    pub fn max_rise(&self) -> (f64, f64) {
        let (k, r) = self
            .dp
            .iter()
            .enumerate()
            .fold((0, f64::MIN), |a, (k, &r)| if r > a.1 { (k, r) } else { a });
        (r, self.model.ivc_deg + k as f64 * self.h)
    }

    /// The fraction of the trapped mass lost by blow-by from IVC to EVO
    /// (0 without it).
    pub fn blowby_fraction(&self) -> f64 {
        self.blowby_fraction
    }

    /// Pressure at EVO (Pa), the end of the closed part.
    pub fn pressure_at_evo(&self) -> f64 {
        self.p_evo
    }

    /// Closed part at `d` in `[ivc, evo]`: cubic Hermite between RK4 nodes.
    fn closed(&self, d: f64) -> f64 {
        let n = self.p.len() - 1;
        let x = (d - self.model.ivc_deg) / self.h;
        let i = (x.floor().max(0.0) as usize).min(n - 1);
        let t = x - i as f64;
        let (t2, t3) = (t * t, t * t * t);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        h00 * self.p[i]
            + h10 * self.h * self.dp[i]
            + h01 * self.p[i + 1]
            + h11 * self.h * self.dp[i + 1]
    }

    /// Pressure (Pa) at cycle angle `deg` (any value: wrapped to the cycle).
    pub fn pressure(&self, deg: f64) -> f64 {
        let m = &self.model;
        let cycle = m.cycle_deg();
        // In the cycle already (every caller's grid): as rem_euclid gives it,
        // without its fmod.
        let mut d = if (0.0..cycle).contains(&deg) {
            deg
        } else {
            deg.rem_euclid(cycle)
        };
        if d >= cycle {
            d -= cycle; // rem_euclid can round up to the modulus
        }
        if d >= cycle + m.ivc_deg {
            d -= cycle;
        }
        let (pin, pex) = (m.intake_pressure_pa, m.exhaust_pressure_pa);
        let c = m.exchange_centre_deg();
        let half = EXCHANGE_BLEND_DEG / 2.0;
        let vol = |deg: f64| self.cyl.volume(deg.to_radians());
        // Now d is in [ivc, cycle + ivc): the closed part comes first.
        if d <= m.evo_deg {
            return self.closed(d);
        }
        if d < m.evo_deg + m.blowdown_deg {
            let t = (d - m.evo_deg) / m.blowdown_deg;
            let ln_poly = self.p_evo.ln() + self.g_evo * (self.v_evo / vol(d)).ln();
            return (ln_poly + (pex.ln() - ln_poly) * blend(t)).exp();
        }
        if d < c - half {
            return pex;
        }
        if d < c + half {
            return pex + (pin - pex) * blend((d - (c - half)) / EXCHANGE_BLEND_DEG);
        }
        let ramp_start = cycle + m.ivc_deg - IVC_RAMP_DEG;
        if d < ramp_start {
            return pin;
        }
        let t = (d - ramp_start) / IVC_RAMP_DEG;
        let ln_poly = pin.ln() + m.gamma_unburnt() * (self.v_ivc / vol(d)).ln();
        (pin.ln() + (ln_poly - pin.ln()) * blend(t)).exp()
    }
}

/// Cosine blend from 0 at `t <= 0` to 1 at `t >= 1`, with zero slope at both ends.
fn blend(t: f64) -> f64 {
    0.5 - 0.5 * (PI * t.clamp(0.0, 1.0)).cos()
}

/// Checks an output step: positive, dividing the cycle into at least 8 parts.
fn steps_in_cycle(step_deg: f64, cycle: f64) -> Result<usize, SynthError> {
    let n = (cycle / step_deg).round();
    if !(step_deg > 0.0) || !n.is_finite() || n < 8.0 || (n * step_deg - cycle).abs() > 1e-9 {
        return Err(SynthError::Parameter {
            name: "step_deg",
            value: step_deg,
            expected: format!("a step dividing the {cycle}° cycle into at least 8 parts"),
        });
    }
    Ok(n as usize)
}

/// Pressure (Pa) over one cycle of `model` on `cyl` at `step_deg`:
/// `(crank_deg, pressure_pa)` for `crank_deg = k step_deg` in `[0, cycle)`,
/// from firing TDC. `step_deg` must divide the cycle (720° or 360°).
pub fn pressure_trace(
    cyl: &Cylinder,
    model: &CycleModel,
    step_deg: f64,
) -> Result<Vec<(f64, f64)>, SynthError> {
    let n = steps_in_cycle(step_deg, model.cycle_deg())?;
    let sol = CycleSolution::new(cyl, model)?;
    Ok((0..n)
        .map(|k| {
            let deg = k as f64 * step_deg;
            (deg, sol.pressure(deg))
        })
        .collect())
}

/// Indicated work `∮ p dV` (J) of a trace over one cycle of `cycle_deg`
/// (720 or 360): the trapezoid rule on `p dV/dphi` with the exact volume
/// law, closing the cycle from the last point back to the first. Angles in
/// degrees, ascending within one cycle; unevenly spaced points are fine.
/// Returns 0 for fewer than two points.
pub fn indicated_work(cyl: &Cylinder, trace: &[(f64, f64)], cycle_deg: f64) -> f64 {
    if trace.len() < 2 {
        return 0.0;
    }
    let f = |(deg, p): (f64, f64)| p * cyl.dvolume(deg.to_radians());
    let mut sum = 0.0;
    for i in 0..trace.len() {
        let a = trace[i];
        let (b, dphi) = if i + 1 < trace.len() {
            (trace[i + 1], trace[i + 1].0 - a.0)
        } else {
            (trace[0], trace[0].0 + cycle_deg - a.0)
        };
        sum += 0.5 * (f(a) + f(b)) * dphi.to_radians();
    }
    sum
}

/// The largest pressure of a trace and its angle, `(crank_deg, pressure)`;
/// the first one on a tie, `None` for an empty trace.
pub fn peak_pressure(trace: &[(f64, f64)]) -> Option<(f64, f64)> {
    trace
        .iter()
        .copied()
        .reduce(|best, x| if x.1 > best.1 { x } else { best })
}

/// Writes a trace as an indicator-diagram CSV (INTERFACE.md): each comment
/// as a `# ` line, a `# rpm = N` line when `rpm` is given, the header
/// `crank_deg,pressure_bar`, then rows with the angle to 0.1° and the
/// pressure to 1e-5 bar (`pressure_bar = Pa / 1e5`). Line ends are `\n`.
pub fn write_csv(
    mut w: impl std::io::Write,
    trace: &[(f64, f64)],
    rpm: Option<f64>,
    comment_lines: &[&str],
) -> std::io::Result<()> {
    for c in comment_lines {
        writeln!(w, "# {c}")?;
    }
    if let Some(r) = rpm {
        writeln!(w, "# rpm = {r}")?;
    }
    writeln!(w, "crank_deg,pressure_bar")?;
    for (deg, p) in trace {
        writeln!(w, "{deg:.*},{:.*}", ANGLE_DIGITS, PRESSURE_DIGITS, p / 1e5)?;
    }
    w.flush()
}

/// The decimals [`write_csv`] writes an angle (deg) with.
pub const ANGLE_DIGITS: usize = 1;
/// The decimals [`write_csv`] writes a pressure (bar) with.
pub const PRESSURE_DIGITS: usize = 5;

/// The rows [`write_csv`] writes, as the reader reads them back: the angle
/// to [`ANGLE_DIGITS`] and the pressure (bar) to [`PRESSURE_DIGITS`]
/// decimals, each the `f64` nearest the decimal (an integer over a power
/// of ten, divided once, is that), as columns `(crank_deg, pressure_bar)`.
pub fn csv_values(trace: &[(f64, f64)]) -> (Vec<f64>, Vec<f64>) {
    let to = |x: f64, digits: usize| {
        let scale = 10f64.powi(digits as i32);
        (x * scale).round() / scale
    };
    trace
        .iter()
        .map(|&(deg, p)| (to(deg, ANGLE_DIGITS), to(p / 1e5, PRESSURE_DIGITS)))
        .unzip()
}

/// A closed-form test diagram: a base pressure plus a Gaussian peak,
/// wrapped periodically over the cycle,
/// `p(phi) = p0 + A sum_k exp(-((phi - phi_pk + k P)/w)^2)`, `P` the cycle.
/// The sum over images (`|k| <= 2` after wrapping `phi - phi_pk` into
/// `[-P/2, P/2)`) makes `p` smooth and exactly periodic for `w <= P/4`.
/// Every derivative is known, so interpolation and quadrature errors can be
/// measured against it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalyticDiagram {
    /// Base pressure `p0` (Pa, absolute).
    pub base_pa: f64,
    /// Height of the peak above the base, `A` (Pa).
    pub amplitude_pa: f64,
    /// Angle of the peak, `phi_pk` (deg from firing TDC).
    pub peak_deg: f64,
    /// Width `w` of the Gaussian (deg): the pressure is `p0 + A/e` at
    /// `phi_pk ± w`. At most a quarter of the cycle.
    pub width_deg: f64,
    /// Cycle length `P` (deg): 720 or 360.
    pub cycle_deg: f64,
}

impl AnalyticDiagram {
    /// A full-load petrol-like shape: 1 bar base, 55 bar peak above it at
    /// 14° after TDC, width 25°, four-stroke.
    pub fn petrol_like() -> Self {
        Self {
            base_pa: 1.0e5,
            amplitude_pa: 55.0e5,
            peak_deg: 14.0,
            width_deg: 25.0,
            cycle_deg: 720.0,
        }
    }

    /// Checks the parameters (positive base, amplitude at least 0, a width
    /// in `(0, cycle/4]`, a cycle of 720 or 360, everything finite).
    pub fn check(&self) -> Result<(), SynthError> {
        let err = |name, value, expected: &str| {
            Err(SynthError::Parameter {
                name,
                value,
                expected: expected.into(),
            })
        };
        if !((self.cycle_deg - 720.0).abs() < 1e-9 || (self.cycle_deg - 360.0).abs() < 1e-9) {
            return err("cycle_deg", self.cycle_deg, "720 or 360");
        }
        if !(self.base_pa > 0.0 && self.base_pa.is_finite()) {
            return err("base_pa", self.base_pa, "positive");
        }
        if !(self.amplitude_pa >= 0.0 && self.amplitude_pa.is_finite()) {
            return err("amplitude_pa", self.amplitude_pa, "0 or more");
        }
        if !self.peak_deg.is_finite() {
            return err("peak_deg", self.peak_deg, "finite");
        }
        if !(self.width_deg > 0.0 && self.width_deg <= self.cycle_deg / 4.0) {
            return err("width_deg", self.width_deg, "in (0, cycle_deg/4]");
        }
        Ok(())
    }

    /// `(sum_k g_k, sum_k g_k'(phi))` of the wrapped Gaussian (per radian).
    fn wrapped(&self, phi_rad: f64) -> (f64, f64) {
        let period = self.cycle_deg.to_radians();
        let w = self.width_deg.to_radians();
        let d0 =
            (phi_rad - self.peak_deg.to_radians() + period / 2.0).rem_euclid(period) - period / 2.0;
        let (mut g, mut dg) = (0.0, 0.0);
        for k in -2..=2 {
            let u = (d0 + k as f64 * period) / w;
            let e = (-u * u).exp();
            g += e;
            dg += -2.0 * u / w * e;
        }
        (g, dg)
    }

    /// Pressure (Pa) at cycle angle `phi_rad` (rad from firing TDC).
    pub fn pressure(&self, phi_rad: f64) -> f64 {
        self.base_pa + self.amplitude_pa * self.wrapped(phi_rad).0
    }

    /// `dp/dphi` (Pa/rad) at `phi_rad`, exact.
    pub fn dpressure(&self, phi_rad: f64) -> f64 {
        self.amplitude_pa * self.wrapped(phi_rad).1
    }

    /// The diagram sampled at `step_deg` over `[0, cycle)`, as
    /// [`pressure_trace`] gives it.
    pub fn trace(&self, step_deg: f64) -> Result<Vec<(f64, f64)>, SynthError> {
        self.check()?;
        let n = steps_in_cycle(step_deg, self.cycle_deg)?;
        Ok((0..n)
            .map(|k| {
                let deg = k as f64 * step_deg;
                (deg, self.pressure(deg.to_radians()))
            })
            .collect())
    }
}

/// The closed-form test diagram's pressure (Pa) at `phi_rad` (rad from
/// firing TDC); see [`AnalyticDiagram`].
pub fn analytic_pressure(phi_rad: f64, diagram: &AnalyticDiagram) -> f64 {
    diagram.pressure(phi_rad)
}

/// `∮ p dV` (J) of the analytic diagram on `cyl`, to rounding: the
/// integrand `p dV/dphi` is smooth and periodic, so the periodic trapezoid
/// rule converges geometrically; 0.01° steps (72 000 points over 720°) are
/// far past convergence for any width of 1° or more.
pub fn analytic_work(cyl: &Cylinder, diagram: &AnalyticDiagram) -> f64 {
    let n = (diagram.cycle_deg * 100.0).round() as usize;
    let h = diagram.cycle_deg.to_radians() / n as f64;
    (0..n)
        .map(|k| {
            let phi = k as f64 * h;
            diagram.pressure(phi) * cyl.dvolume(phi)
        })
        .sum::<f64>()
        * h
}

#[cfg(test)]
mod tests {
    use super::*;
    use enginedyn_kinematics::{CrankSlider, Mechanism};

    /// VAZ-2108 type cylinder (seed 000): R = 35.5 mm, lambda = 0.26,
    /// bore 76 mm, compression ratio 9.9.
    fn vaz() -> Cylinder {
        let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
        Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap()
    }

    /// A 0.5 l diesel cylinder: bore 84 mm, stroke 90 mm, lambda 0.3, CR 17.
    fn diesel_cyl() -> Cylinder {
        let cs = CrankSlider::new(0.045, 0.045 / 0.3, 0.0).unwrap();
        Cylinder::new(Mechanism::CrankSlider(cs), 0.084, 17.0).unwrap()
    }

    fn in_closed(m: &CycleModel, deg: f64) -> Option<f64> {
        let d = if deg >= m.cycle_deg() + m.ivc_deg {
            deg - m.cycle_deg()
        } else {
            deg
        };
        (d >= m.ivc_deg && d <= m.evo_deg).then_some(d)
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// Without heat release the closed part is the polytrope
    /// `p V^g = p_intake V_ivc^g` (closed form); RK4 at 0.025° with cubic
    /// Hermite output meets it to 1e-6 relative (in fact ~1e-11), at the
    /// output points and between the RK4 nodes.
    #[test]
    fn motored_closed_part_is_polytropic() {
        let cyl = vaz();
        let mut m = CycleModel::petrol_full_load();
        m.heat_released_j = 0.0;
        let g = m.gamma_unburnt();
        let c0 = m.intake_pressure_pa * cyl.volume(m.ivc_deg.to_radians()).powf(g);
        let sol = CycleSolution::new(&cyl, &m).unwrap();
        let mut worst: f64 = 0.0;
        for k in 0..72_000 {
            let deg = k as f64 * 0.01 + 0.0037;
            if let Some(d) = in_closed(&m, deg) {
                let c = sol.pressure(deg) * cyl.volume(d.to_radians()).powf(g);
                worst = worst.max((c / c0 - 1.0).abs());
            }
        }
        assert!(worst < 1e-6, "p V^g drifts by {worst:e}");
        // The same through pressure_trace's output grid.
        for (deg, p) in pressure_trace(&cyl, &m, 0.5).unwrap() {
            if let Some(d) = in_closed(&m, deg) {
                let c = p * cyl.volume(d.to_radians()).powf(g);
                assert!((c / c0 - 1.0).abs() < 1e-6, "at {deg}");
            }
        }
    }

    /// The petrol preset motored (no fuel) with `losses`.
    fn motored_with(losses: Losses) -> CycleModel {
        CycleModel {
            heat_released_j: 0.0,
            losses,
            ..CycleModel::petrol_full_load()
        }
    }

    /// Blow-by alone leaves each kilogram of the remaining gas isentropic:
    /// `p (V/m)^g` is constant from IVC to EVO, so the pressure at EVO is
    /// the polytrope's times `(1 - f)^g` for the fraction `f` blown by.
    #[test]
    fn blowby_alone_keeps_the_remaining_gas_isentropic() {
        let cyl = vaz();
        let m = motored_with(Losses {
            woschni_scale: 0.0,
            ..Losses::warm_engine(1500.0)
        });
        let sol = CycleSolution::new(&cyl, &m).unwrap();
        let f = sol.blowby_fraction();
        // About 1.5 % at 1500 rpm (Losses::warm_engine's documentation).
        assert!((0.01..0.02).contains(&f), "blow-by {f}");
        let g = m.gamma_unburnt();
        let v = |d: f64| cyl.volume(d.to_radians());
        let expected =
            m.intake_pressure_pa * (v(m.ivc_deg) / v(m.evo_deg)).powf(g) * (1.0 - f).powf(g);
        let e = rel(sol.pressure_at_evo(), expected);
        assert!(e < 1e-9, "{e:e}");
        // Lossless without it: the same model with no orifice is the polytrope.
        let none = CycleSolution::new(&cyl, &motored_with(Losses::NONE)).unwrap();
        assert!(none.blowby_fraction().abs() < 1e-300);
        assert!(sol.pressure_at_evo() < none.pressure_at_evo());
    }

    /// Wall heat alone: the apparent heat release of the trace
    /// (`g/(g-1) p dV + 1/(g-1) V dp`, the first law read backwards) is the
    /// Woschni heat flow integrated along the solution, to 0.1 %; the
    /// motored peak comes 0.1°–1° before TDC and the expansion pressure is
    /// below the compression pressure at every equal volume.
    #[test]
    fn wall_heat_is_what_the_first_law_reads_back() {
        let cyl = vaz();
        let l = Losses {
            blowby_area_m2: 0.0,
            ..Losses::warm_engine(1500.0)
        };
        let m = motored_with(l);
        let sol = CycleSolution::new(&cyl, &m).unwrap();
        let g = m.gamma_unburnt();
        let (a, b) = (-100.0, 100.0);
        let n = 20_000;
        let h = (b - a) / n as f64;
        let v_ivc = cyl.volume(m.ivc_deg.to_radians());
        let mass = m.intake_pressure_pa * v_ivc / (GAS_CONSTANT * l.ivc_temperature_k);
        let (mut apparent, mut wall) = (0.0, 0.0);
        for i in 0..n {
            let (d0, d1) = (a + h * i as f64, a + h * (i + 1) as f64);
            let (p0, p1) = (sol.pressure(d0), sol.pressure(d1));
            let (v0, v1) = (cyl.volume(d0.to_radians()), cyl.volume(d1.to_radians()));
            let (pm, vm) = (0.5 * (p0 + p1), 0.5 * (v0 + v1));
            apparent += g / (g - 1.0) * pm * (v1 - v0) + vm * (p1 - p0) / (g - 1.0);
            let dm = m.closed_rate_with_losses(
                &cyl,
                0.5 * (d0 + d1),
                pm,
                mass,
                (m.intake_pressure_pa, v_ivc, l.ivc_temperature_k),
            );
            // The lossless rate less the lossy one is (g - 1) dQ_wall / V.
            let lossless = m.closed_rate(&cyl, 0.5 * (d0 + d1), pm);
            let vmid = cyl.volume((0.5 * (d0 + d1)).to_radians());
            wall += (lossless - dm.0) * vmid / (g - 1.0) * h;
        }
        assert!(wall > 0.0, "heat flows to the walls: {wall}");
        assert!(rel(-apparent, wall) < 1e-3, "{apparent} vs {wall}");
        let (deg, _) = (0..=4000)
            .map(|k| {
                let d = -2.0 + k as f64 * 1e-3;
                (d, sol.pressure(d))
            })
            .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        assert!((-1.0..-0.1).contains(&deg), "motored peak at {deg}");
        for k in 1..=100 {
            let d = k as f64;
            assert!(sol.pressure(d) < sol.pressure(-d), "at ±{d}");
        }
    }

    #[test]
    fn bad_losses_are_rejected() {
        let cyl = vaz();
        for l in [
            Losses {
                woschni_scale: -1.0,
                ..Losses::warm_engine(1500.0)
            },
            Losses {
                rpm: 0.0,
                ..Losses::warm_engine(1500.0)
            },
            Losses {
                blowby_area_m2: f64::NAN,
                ..Losses::warm_engine(1500.0)
            },
            Losses {
                wall_temperature_k: 0.0,
                ..Losses::warm_engine(1500.0)
            },
        ] {
            let e = CycleSolution::new(&cyl, &motored_with(l)).unwrap_err();
            assert!(e.to_string().starts_with("losses."), "{e}");
        }
        // Off, the speed is not needed.
        CycleSolution::new(&cyl, &motored_with(Losses::NONE)).unwrap();
    }

    /// With combustion the RK4 solution has converged: halving the internal
    /// step would change it by far less than 1e-6 (checked against an
    /// independent RK4 at 0.005°).
    #[test]
    fn fired_closed_part_is_converged() {
        let cyl = vaz();
        let m = CycleModel::petrol_full_load();
        let sol = CycleSolution::new(&cyl, &m).unwrap();
        let h = 0.005;
        let n = ((m.evo_deg - m.ivc_deg) / h).round() as usize;
        let mut p = m.intake_pressure_pa;
        let f = |d, p| m.closed_rate(&cyl, d, p);
        let mut worst: f64 = 0.0;
        for i in 0..n {
            let a = m.ivc_deg + h * i as f64;
            let k1 = f(a, p);
            let k2 = f(a + h / 2.0, p + h / 2.0 * k1);
            let k3 = f(a + h / 2.0, p + h / 2.0 * k2);
            let k4 = f(a + h, p + h * k3);
            p += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            worst = worst.max(rel(sol.pressure(a + h), p));
        }
        assert!(worst < 1e-7, "{worst:e}");
    }

    fn check_shape(cyl: &Cylinder, m: &CycleModel) {
        let sol = CycleSolution::new(cyl, m).unwrap();
        let cycle = m.cycle_deg();
        // Periodic: the value at the cycle's end is the value at 0.
        let (p0, pc) = (sol.pressure(0.0), sol.pressure(cycle));
        assert!(rel(pc, p0) < 1e-15, "{p0} vs {pc}");
        assert!(rel(sol.pressure(-0.3), sol.pressure(cycle - 0.3)) < 1e-15);
        let t = pressure_trace(cyl, m, 0.5).unwrap();
        assert_eq!(t.len(), (cycle / 0.5) as usize);
        let (_, peak) = peak_pressure(&t).unwrap();
        // Positive, and continuous: neighbours 0.5° apart (wrapping) differ
        // by less than 5 % of the peak (the steepest combustion rise is
        // ~2.5 bar/deg at ~60 bar).
        assert!(t.iter().all(|&(_, p)| p > 0.0 && p.is_finite()));
        for i in 0..t.len() {
            let j = (i + 1) % t.len();
            assert!((t[j].1 - t[i].1).abs() < 0.05 * peak, "jump at {}", t[i].0);
        }
        // Every join is continuous and C1: value and one-sided slopes agree.
        let c = m.exchange_centre_deg();
        let half = EXCHANGE_BLEND_DEG / 2.0;
        let joins = [
            0.0,
            m.evo_deg,
            m.evo_deg + m.blowdown_deg,
            c - half,
            c + half,
            cycle + m.ivc_deg - IVC_RAMP_DEG,
            cycle + m.ivc_deg,
        ];
        for &j in &joins {
            let e = 1e-7;
            let (l, r) = (sol.pressure(j - e), sol.pressure(j + e));
            assert!(rel(l, r) < 1e-6, "jump at {j}: {l} vs {r}");
            let d = 1e-3;
            let sl = (sol.pressure(j) - sol.pressure(j - d)) / d;
            let sr = (sol.pressure(j + d) - sol.pressure(j)) / d;
            // Slopes in Pa/deg; finite differences of step d carry O(d p'').
            assert!(
                (sl - sr).abs() < 1e-3 * (sl.abs().max(sr.abs()) + 1e3) + 50.0,
                "kink at {j}: {sl} vs {sr} Pa/deg"
            );
        }
    }

    #[test]
    fn petrol_trace_is_periodic_positive_continuous() {
        check_shape(&vaz(), &CycleModel::petrol_full_load());
        // The documented dip of the C1 ramp into IVC: 1.9 % about 4° before.
        let m = CycleModel::petrol_full_load();
        let sol = CycleSolution::new(&vaz(), &m).unwrap();
        let (deg, low) = (0..=1000)
            .map(|k| {
                let d = 720.0 + m.ivc_deg - IVC_RAMP_DEG + k as f64 * IVC_RAMP_DEG / 1000.0;
                (d, sol.pressure(d))
            })
            .reduce(|a, b| if b.1 < a.1 { b } else { a })
            .unwrap();
        let dip = 1.0 - low / m.intake_pressure_pa;
        assert!((0.018..0.020).contains(&dip), "dip {dip}");
        assert!((3.0..5.0).contains(&(720.0 + m.ivc_deg - deg)), "at {deg}");
        let mut motored = CycleModel::petrol_full_load();
        motored.heat_released_j = 0.0;
        check_shape(&vaz(), &motored);
    }

    #[test]
    fn diesel_and_two_stroke_traces_are_periodic_positive_continuous() {
        check_shape(&diesel_cyl(), &CycleModel::diesel_full_load());
        let m = CycleModel {
            two_stroke: true,
            ivc_deg: -110.0,
            evo_deg: 100.0,
            blowdown_deg: 45.0,
            intake_pressure_pa: 1.5e5,
            exhaust_pressure_pa: 1.2e5,
            ..CycleModel::diesel_full_load()
        };
        check_shape(&diesel_cyl(), &m);
        let t = pressure_trace(&diesel_cyl(), &m, 0.5).unwrap();
        assert_eq!(t.len(), 720);
        let w = indicated_work(&diesel_cyl(), &t, 360.0);
        assert!(w > 0.0);
    }

    fn imep_bar(cyl: &Cylinder, t: &[(f64, f64)], cycle: f64) -> f64 {
        indicated_work(cyl, t, cycle) / cyl.swept_volume() / 1e5
    }

    /// The petrol preset on the VAZ geometry: IMEP 9.5–11.5 bar (≈ 10.5),
    /// peak 50–75 bar at 10–20° after TDC (56.3 bar at 13°).
    #[test]
    fn petrol_preset_is_a_plausible_full_load_diagram() {
        let cyl = vaz();
        let m = CycleModel::petrol_full_load();
        let t = pressure_trace(&cyl, &m, 0.5).unwrap();
        let imep = imep_bar(&cyl, &t, 720.0);
        assert!((9.5..11.5).contains(&imep), "imep {imep}");
        let (deg, peak) = peak_pressure(&t).unwrap();
        assert!((50e5..75e5).contains(&peak), "peak {peak}");
        assert!((10.0..20.0).contains(&deg), "peak at {deg}");
        // The IMEP from a 0.1° trace agrees to 0.1 % (the 0.5° trace is fine
        // enough to be the bundled one).
        let fine = imep_bar(&cyl, &pressure_trace(&cyl, &m, 0.1).unwrap(), 720.0);
        assert!(rel(imep, fine) < 1e-3, "{imep} vs {fine}");
    }

    /// The diesel preset on its 0.5 l cylinder: IMEP 17–23 bar, peak
    /// 130–170 bar after TDC.
    #[test]
    fn diesel_preset_is_a_plausible_full_load_diagram() {
        let cyl = diesel_cyl();
        let t = pressure_trace(&cyl, &CycleModel::diesel_full_load(), 0.5).unwrap();
        let imep = imep_bar(&cyl, &t, 720.0);
        assert!((17.0..23.0).contains(&imep), "imep {imep}");
        let (deg, peak) = peak_pressure(&t).unwrap();
        assert!((130e5..170e5).contains(&peak), "peak {peak}");
        assert!((0.0..20.0).contains(&deg), "peak at {deg}");
    }

    /// The gas-exchange loop (BDC 180° → BDC 540°) does negative work when
    /// the intake pressure is below the exhaust pressure: about
    /// `-(p_ex - p_in) V_d` (the blow-down tail and the blends add a little).
    #[test]
    fn pumping_loop_is_negative_work() {
        let cyl = vaz();
        let m = CycleModel::petrol_full_load();
        assert!(m.intake_pressure_pa < m.exhaust_pressure_pa);
        let t = pressure_trace(&cyl, &m, 0.1).unwrap();
        let pump: Vec<_> = t
            .iter()
            .copied()
            .filter(|&(d, _)| (180.0..=540.0).contains(&d))
            .collect();
        let w: f64 = pump
            .windows(2)
            .map(|s| {
                let f = |(d, p): (f64, f64)| p * cyl.dvolume(f64::to_radians(d));
                0.5 * (f(s[0]) + f(s[1])) * (s[1].0 - s[0].0).to_radians()
            })
            .sum();
        let ideal = -(m.exhaust_pressure_pa - m.intake_pressure_pa) * cyl.swept_volume();
        assert!(w < 0.0, "pumping work {w}");
        assert!(w < 0.5 * ideal && w > 2.0 * ideal, "{w} vs {ideal}");
    }

    /// The Wiebe law: nothing before SOC, `1 - exp(-a)` at its end, rate
    /// the derivative of the fraction.
    #[test]
    fn wiebe_fraction_and_rate() {
        let m = CycleModel::petrol_full_load();
        let w = *m.burn.first();
        assert!(m.burnt_fraction(w.start_deg() - 1.0).abs() < 1e-300);
        let end = w.start_deg() + w.duration_deg();
        assert!(rel(m.burnt_fraction(end), 1.0 - (-5.0f64).exp()) < 1e-14);
        for d in [-10.0, 0.0, 10.0, 25.0] {
            let e = 1e-5;
            let fd = (m.burnt_fraction(d + e) - m.burnt_fraction(d - e)) / (2.0 * e);
            assert!((fd - m.burn_rate(d)).abs() < 1e-8, "{d}");
        }
    }

    #[test]
    fn bad_parameters_are_rejected_with_their_value() {
        let cyl = vaz();
        let mut m = CycleModel::petrol_full_load();
        m.evo_deg = 350.0;
        let e = pressure_trace(&cyl, &m, 0.5).unwrap_err();
        assert!(e.to_string().starts_with("evo_deg = 350"), "{e}");
        let m = CycleModel {
            burn: BurnLaw::single(Wiebe::new(-140.0, 42.0, 5.0, 2.0).unwrap()),
            ..CycleModel::petrol_full_load()
        };
        assert!(matches!(
            pressure_trace(&cyl, &m, 0.5),
            Err(SynthError::Parameter {
                name: "start_deg",
                ..
            })
        ));
        let m = CycleModel::petrol_full_load();
        for step in [0.0, -1.0, 0.7, f64::NAN, 100.0] {
            assert!(pressure_trace(&cyl, &m, step).is_err(), "{step}");
        }
        let m = CycleModel {
            gas: Gas::Blend {
                compression: 1.35,
                expansion: f64::NAN,
            },
            ..CycleModel::petrol_full_load()
        };
        assert!(pressure_trace(&cyl, &m, 0.5).is_err());
    }

    #[test]
    fn csv_format() {
        let mut out = Vec::new();
        let t = [(0.0, 39.987_024e5), (0.5, 1.0e5)];
        write_csv(&mut out, &t, Some(4900.0), &["made by a test"]).unwrap();
        let s = String::from_utf8(out).unwrap();
        assert_eq!(
            s,
            "# made by a test\n# rpm = 4900\ncrank_deg,pressure_bar\n0.0,39.98702\n0.5,1.00000\n"
        );
    }

    /// The analytic diagram is smooth and periodic, its derivative is exact,
    /// and its work is converged to rounding.
    #[test]
    fn analytic_diagram_is_periodic_smooth_and_its_work_converged() {
        let d = AnalyticDiagram::petrol_like();
        d.check().unwrap();
        let cyl = vaz();
        let peak = d.pressure(d.peak_deg.to_radians());
        assert!(rel(peak, d.base_pa + d.amplitude_pa) < 1e-12);
        assert!(rel(analytic_pressure(0.3, &d), d.pressure(0.3 + 4.0 * PI)) < 1e-13);
        for deg in [0.0, 14.0, 100.0, 374.0, 380.0, 700.0] {
            let phi = f64::to_radians(deg);
            let e = 1e-6;
            let fd = (d.pressure(phi + e) - d.pressure(phi - e)) / (2.0 * e);
            assert!(
                (fd - d.dpressure(phi)).abs() < 1e-5 * d.amplitude_pa,
                "{deg}"
            );
        }
        // Periodic trapezoid at 0.01° (analytic_work) against 0.005° and 0.05°.
        let w = analytic_work(&cyl, &d);
        let quad = |n: usize| {
            let h = 4.0 * PI / n as f64;
            (0..n)
                .map(|k| d.pressure(k as f64 * h) * cyl.dvolume(k as f64 * h))
                .sum::<f64>()
                * h
        };
        assert!(rel(w, quad(144_000)) < 1e-12);
        assert!(rel(w, quad(14_400)) < 1e-12);
        assert!(w > 0.0);
        // A 0.5° sample integrated by the trapezoid rule converges too.
        let t = d.trace(0.5).unwrap();
        assert!(rel(indicated_work(&cyl, &t, 720.0), w) < 1e-9);
        let bad = AnalyticDiagram {
            width_deg: 200.0,
            ..d
        };
        assert!(bad.trace(1.0).is_err());
    }
}
