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
/// The CA50 a running engine's burn law may have (deg from firing TDC):
/// earlier, the charge burns against the rising piston (a CA50 of −60°
/// gives 187 bar at TDC); later, most of it burns in the exhaust.
pub const CA50_RANGE_DEG: (f64, f64) = (-30.0, 60.0);
/// The steepest pressure rise a design cycle may have (bar/°): more is
/// the rate of a knocking or detonating engine, not a design.
pub const MAX_PRESSURE_RISE_BAR_DEG: f64 = 15.0;

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
pub use enginedyn_combustion::charge::R_AIR;

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

/// A value over engine speed: `{rpm = [...], bar = [...]}` in the engine
/// file. Linear between its points, held at its ends.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The speeds (rpm), rising.
    pub rpm: Vec<f64>,
    /// The value at each speed (SI).
    pub values: Vec<f64>,
}

impl Curve {
    /// The value at `rpm`: linear between the two points around it, the
    /// end value outside.
    pub fn at(&self, rpm: f64) -> f64 {
        let (x, y) = (&self.rpm, &self.values);
        let last = x.len() - 1;
        if rpm <= x[0] {
            return y[0];
        }
        if rpm >= x[last] {
            return y[last];
        }
        let k = x.partition_point(|&r| r <= rpm).clamp(1, last);
        let t = (rpm - x[k - 1]) / (x[k] - x[k - 1]);
        y[k - 1] + t * (y[k] - y[k - 1])
    }
}

/// A value given once or as a curve over speed.
#[derive(Debug, Clone, PartialEq)]
pub enum OverSpeed {
    /// The same at every speed.
    Fixed(f64),
    /// A curve over speed.
    Curve(Curve),
}

impl OverSpeed {
    /// The value at `rpm` (a curve's first point when no speed is known).
    pub fn at(&self, rpm: Option<f64>) -> f64 {
        match (self, rpm) {
            (OverSpeed::Fixed(v), _) => *v,
            (OverSpeed::Curve(c), Some(r)) => c.at(r),
            (OverSpeed::Curve(c), None) => c.values[0],
        }
    }

    /// The highest value at any speed.
    pub fn max(&self) -> f64 {
        match self {
            OverSpeed::Fixed(v) => *v,
            OverSpeed::Curve(c) => c.values.iter().copied().fold(f64::MIN, f64::max),
        }
    }

    /// Whether the value changes with speed.
    pub fn varies(&self) -> bool {
        matches!(self, OverSpeed::Curve(_))
    }
}

/// The burn law of the first burn when its 10–90 duration is a curve over
/// speed: CA50, m and a, the duration taken at each speed.
#[derive(Debug, Clone, PartialEq)]
pub struct DurationCurve {
    /// CA50 (deg).
    pub ca50_deg: f64,
    /// The 10–90 duration over speed (deg).
    pub duration_deg: Curve,
    /// The Wiebe shape m.
    pub m: f64,
    /// The Wiebe efficiency a.
    pub a: f64,
}

/// The full-load line, `[combustion.full_load]`: the highest load at each
/// speed, as IMEP (or BMEP, turned into IMEP with `[friction]`).
#[derive(Debug, Clone, PartialEq)]
pub struct FullLoad {
    /// The speeds (rpm) and the mean effective pressure at each (Pa).
    pub curve: Curve,
    /// Whether the curve is BMEP (else IMEP).
    pub brake: bool,
}

/// A checked `[combustion]` section.
#[derive(Debug, Clone, PartialEq)]
pub struct CombustionSpec {
    /// The burn law (one Wiebe, or two with `[combustion.second]`); with a
    /// 10–90 duration over speed, the law at the curve's first speed
    /// ([`Self::burn_at`] gives it at any).
    pub burn: BurnLaw,
    /// The 10–90 duration over speed, when the file gives a curve.
    pub duration_curve: Option<DurationCurve>,
    /// The air and fuel (`charge` and its keys), when the file says how
    /// the engine makes its load; `None`: the intake pressure stays, the
    /// fuel follows the load (as before the design model).
    pub charge: Option<enginedyn_combustion::charge::Charge>,
    /// The intake pressure over speed (Pa; [`Self::intake_pressure_pa`] is
    /// its value at the first speed).
    pub intake: OverSpeed,
    /// The full-load line, when given.
    pub full_load: Option<FullLoad>,
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

impl CombustionSpec {
    /// The burn law at `rpm` (a 10–90 duration over speed taken there).
    pub fn burn_at(
        &self,
        rpm: Option<f64>,
    ) -> Result<BurnLaw, enginedyn_combustion::CombustionError> {
        let Some(d) = &self.duration_curve else {
            return Ok(self.burn);
        };
        let first = Wiebe::from_ca50(
            d.ca50_deg,
            OverSpeed::Curve(d.duration_deg.clone()).at(rpm),
            d.m,
            d.a,
        )?;
        Ok(match self.burn.second() {
            Some(&(w, f)) => BurnLaw::double(first, w, f)?,
            None => BurnLaw::single(first),
        })
    }

    /// The intake pressure at `rpm` (Pa).
    pub fn intake_at(&self, rpm: Option<f64>) -> f64 {
        self.intake.at(rpm)
    }

    /// Whether the design cycle changes with speed (a curve over speed).
    pub fn varies_with_speed(&self) -> bool {
        self.intake.varies() || self.duration_curve.is_some()
    }
}
