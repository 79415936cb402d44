//! The toleranced parameters and the key results of INTERFACE.md, and the
//! scalar inputs of the linear model that the `[tolerances]` section becomes.

use crate::ToleranceError;
use enginedyn_engine::Engine;
use enginedyn_kinematics::Mechanism;

/// A toleranced parameter: a key of the `[tolerances]` section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Parameter {
    /// `stroke_mm`: the crank throw, on `2R`.
    Stroke,
    /// `rod_length_mm`: the rod's centre distance (crank-slider).
    RodLength,
    /// `pin_offset_mm`: the piston pin's offset (crank-slider).
    PinOffset,
    /// `bore_mm`.
    Bore,
    /// `piston_group_kg`: each cylinder's piston group on its own.
    PistonGroup,
    /// `rod_kg`: every rod's mass (crank-slider).
    RodMass,
    /// `throw_angle_deg`: each throw's lag behind throw 1 on its own.
    ThrowAngle,
    /// `tdc_deg`: where the diagram's firing TDC really lies.
    Tdc,
    /// `yoke_slot_squareness_deg`: the yoke slot's tilt from square (Scotch yoke).
    YokeSlotSquareness,
}

impl Parameter {
    /// Every parameter, in INTERFACE.md's order.
    pub const ALL: [Parameter; 9] = [
        Parameter::Stroke,
        Parameter::RodLength,
        Parameter::PinOffset,
        Parameter::Bore,
        Parameter::PistonGroup,
        Parameter::RodMass,
        Parameter::ThrowAngle,
        Parameter::Tdc,
        Parameter::YokeSlotSquareness,
    ];

    /// The engine-file key.
    pub fn key(self) -> &'static str {
        match self {
            Parameter::Stroke => "stroke_mm",
            Parameter::RodLength => "rod_length_mm",
            Parameter::PinOffset => "pin_offset_mm",
            Parameter::Bore => "bore_mm",
            Parameter::PistonGroup => "piston_group_kg",
            Parameter::RodMass => "rod_kg",
            Parameter::ThrowAngle => "throw_angle_deg",
            Parameter::Tdc => "tdc_deg",
            Parameter::YokeSlotSquareness => "yoke_slot_squareness_deg",
        }
    }

    /// Parses [`Parameter::key`].
    pub fn from_key(key: &str) -> Option<Parameter> {
        Parameter::ALL.into_iter().find(|p| p.key() == key)
    }

    /// The unit the key is written in.
    pub fn unit(self) -> &'static str {
        match self {
            Parameter::Stroke | Parameter::RodLength | Parameter::PinOffset | Parameter::Bore => {
                "mm"
            }
            Parameter::PistonGroup | Parameter::RodMass => "kg",
            Parameter::ThrowAngle | Parameter::Tdc | Parameter::YokeSlotSquareness => "deg",
        }
    }

    /// What it is, as an engineer names it (charts and readable tables).
    pub fn label(self) -> &'static str {
        match self {
            Parameter::Stroke => "stroke (2R)",
            Parameter::RodLength => "rod length",
            Parameter::PinOffset => "pin offset",
            Parameter::Bore => "bore",
            Parameter::PistonGroup => "piston group mass",
            Parameter::RodMass => "rod mass",
            Parameter::ThrowAngle => "throw angle",
            Parameter::Tdc => "firing TDC position",
            Parameter::YokeSlotSquareness => "yoke slot squareness",
        }
    }

    /// SI units per written unit (m per mm, rad per deg, 1 for kg).
    pub fn to_si(self) -> f64 {
        match self.unit() {
            "mm" => 1e-3,
            "deg" => std::f64::consts::PI / 180.0,
            _ => 1.0,
        }
    }

    /// Varies per cylinder (`Some("cylinder")`) or per throw, or is one value.
    fn per(self) -> Option<&'static str> {
        match self {
            Parameter::PistonGroup => Some("cylinder"),
            Parameter::ThrowAngle => Some("throw"),
            _ => None,
        }
    }
}

/// A key result of INTERFACE.md's `tolerance` command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Output {
    /// `mean_torque_nm` (effective when a mechanical efficiency is given).
    MeanTorque,
    /// `imep_bar`.
    Imep,
    /// `torque_max_nm`.
    TorqueMax,
    /// `torque_min_nm`.
    TorqueMin,
    /// `excess_work_j`.
    ExcessWork,
    /// `required_inertia_kg_m2`.
    RequiredInertia,
    /// `crankpin_load_max_n` (over every cylinder).
    CrankpinLoadMax,
    /// `compression_ratio`: largest over smallest volume, head fixed.
    CompressionRatio,
    /// `clearance_volume_m3`: the smallest volume, head fixed.
    ClearanceVolume,
    /// `stroke_m`: the true stroke.
    Stroke,
    /// `free_force_1_n`.
    FreeForce1,
    /// `free_force_2_n`.
    FreeForce2,
    /// `free_moment_1_nm`.
    FreeMoment1,
    /// `free_moment_2_nm`.
    FreeMoment2,
    /// `torque_order_0_5_nm`: the engine torque's harmonic of order 0.5.
    TorqueOrderHalf,
    /// `torque_order_1_nm`: the engine torque's harmonic of order 1.
    TorqueOrder1,
}

/// Number of key results.
pub const OUTPUTS: usize = 16;

impl Output {
    /// Every result, in INTERFACE.md's order.
    pub const ALL: [Output; OUTPUTS] = [
        Output::MeanTorque,
        Output::Imep,
        Output::TorqueMax,
        Output::TorqueMin,
        Output::ExcessWork,
        Output::RequiredInertia,
        Output::CrankpinLoadMax,
        Output::CompressionRatio,
        Output::ClearanceVolume,
        Output::Stroke,
        Output::FreeForce1,
        Output::FreeForce2,
        Output::FreeMoment1,
        Output::FreeMoment2,
        Output::TorqueOrderHalf,
        Output::TorqueOrder1,
    ];

    /// The result's key, its unit in the name.
    pub fn key(self) -> &'static str {
        match self {
            Output::MeanTorque => "mean_torque_nm",
            Output::Imep => "imep_bar",
            Output::TorqueMax => "torque_max_nm",
            Output::TorqueMin => "torque_min_nm",
            Output::ExcessWork => "excess_work_j",
            Output::RequiredInertia => "required_inertia_kg_m2",
            Output::CrankpinLoadMax => "crankpin_load_max_n",
            Output::CompressionRatio => "compression_ratio",
            Output::ClearanceVolume => "clearance_volume_m3",
            Output::Stroke => "stroke_m",
            Output::FreeForce1 => "free_force_1_n",
            Output::FreeForce2 => "free_force_2_n",
            Output::FreeMoment1 => "free_moment_1_nm",
            Output::FreeMoment2 => "free_moment_2_nm",
            Output::TorqueOrderHalf => "torque_order_0_5_nm",
            Output::TorqueOrder1 => "torque_order_1_nm",
        }
    }

    /// The unit, as printed.
    pub fn unit(self) -> &'static str {
        match self {
            Output::MeanTorque
            | Output::TorqueMax
            | Output::TorqueMin
            | Output::FreeMoment1
            | Output::FreeMoment2
            | Output::TorqueOrderHalf
            | Output::TorqueOrder1 => "N m",
            Output::Imep => "bar",
            Output::ExcessWork => "J",
            Output::RequiredInertia => "kg m²",
            Output::CrankpinLoadMax | Output::FreeForce1 | Output::FreeForce2 => "N",
            Output::CompressionRatio => "",
            Output::ClearanceVolume => "m³",
            Output::Stroke => "m",
        }
    }

    /// What it is, as an engineer names it (charts and readable tables);
    /// [`Output::unit`] beside it.
    pub fn label(self) -> &'static str {
        match self {
            Output::MeanTorque => "mean torque",
            Output::Imep => "IMEP",
            Output::TorqueMax => "torque max",
            Output::TorqueMin => "torque min",
            Output::ExcessWork => "excess work ΔE",
            Output::RequiredInertia => "required inertia I₀",
            Output::CrankpinLoadMax => "crank-pin load max",
            Output::CompressionRatio => "compression ratio",
            Output::ClearanceVolume => "clearance volume",
            Output::Stroke => "stroke",
            Output::FreeForce1 => "free force, 1st order",
            Output::FreeForce2 => "free force, 2nd order",
            Output::FreeMoment1 => "free moment, 1st order",
            Output::FreeMoment2 => "free moment, 2nd order",
            Output::TorqueOrderHalf => "torque harmonic, order 0.5",
            Output::TorqueOrder1 => "torque harmonic, order 1",
        }
    }

    /// Index in [`Output::ALL`].
    pub fn index(self) -> usize {
        Output::ALL
            .iter()
            .position(|&o| o == self)
            .unwrap_or_default()
    }

    /// Geometry alone (no pressure): its derivatives are analytic.
    pub fn is_geometric(self) -> bool {
        matches!(
            self,
            Output::CompressionRatio | Output::ClearanceVolume | Output::Stroke
        )
    }
}

/// One scalar input of the linear model: a parameter, for a per-cylinder or
/// per-throw parameter one cylinder or throw, with its ± tolerance. Values
/// are in the key's unit (mm, kg, deg).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Input {
    /// The parameter.
    pub parameter: Parameter,
    /// 0-based cylinder (`piston_group_kg`) or throw (`throw_angle_deg`).
    pub index: Option<usize>,
    /// The ± tolerance (key unit).
    pub tolerance: f64,
    /// The parameter's nominal value (key unit): 0 for `tdc_deg` and the
    /// slot's squareness, the throw's lag for `throw_angle_deg`.
    pub nominal: f64,
}

impl Input {
    /// As written in `tolerance.csv`: `stroke_mm`, `piston_group_kg[3]`
    /// (cylinder 3), `throw_angle_deg[2]` (throw 2).
    pub fn name(&self) -> String {
        match self.index {
            Some(i) => format!("{}[{}]", self.parameter.key(), i + 1),
            None => self.parameter.key().to_string(),
        }
    }
    /// Readable, with its unit: `stroke (2R), mm`, `piston group mass,
    /// cylinder 3, kg`, `throw angle, throw 2, deg`.
    pub fn label(&self) -> String {
        match (self.index, self.per()) {
            (Some(i), Some(per)) => format!(
                "{}, {per} {}, {}",
                self.parameter.label(),
                i + 1,
                self.parameter.unit()
            ),
            _ => format!("{}, {}", self.parameter.label(), self.parameter.unit()),
        }
    }
    /// What the index counts, for a per-cylinder or per-throw parameter.
    pub fn per(&self) -> Option<&'static str> {
        self.parameter.per()
    }
}

/// The inputs of the linear model from the `[tolerances]` section's
/// (key, value) pairs: one per parameter, one per cylinder for
/// `piston_group_kg`, one per throw after the first for `throw_angle_deg`
/// (throw 1 is the reference). Zero tolerances are dropped. Keys that do
/// not apply to the mechanism are errors; so is an empty section. The
/// strings of the second value are notes (a throw tolerance on a one-throw
/// crank).
pub fn inputs(
    engine: &Engine,
    tolerances: &[(String, f64)],
) -> Result<(Vec<Input>, Vec<String>), ToleranceError> {
    let mut out = Vec::new();
    let mut notes = Vec::new();
    let yoke = matches!(engine.mechanism(), Mechanism::ScotchYoke(_));
    for (key, &value) in tolerances.iter().map(|(k, v)| (k, v)) {
        let Some(p) = Parameter::from_key(key) else {
            return Err(ToleranceError::UnknownKey(key.clone()));
        };
        if !(value.is_finite() && value >= 0.0) {
            return Err(ToleranceError::Invalid {
                key: p.key(),
                value,
                expected: "a deviation of 0 or more".into(),
            });
        }
        let rod_only = matches!(
            p,
            Parameter::RodLength | Parameter::PinOffset | Parameter::RodMass
        );
        if yoke && rod_only {
            return Err(ToleranceError::NotApplicable {
                key: p.key(),
                why: "a Scotch yoke has no connecting rod or pin offset",
            });
        }
        if !yoke && p == Parameter::YokeSlotSquareness {
            return Err(ToleranceError::NotApplicable {
                key: p.key(),
                why: "only a Scotch yoke has a slot (mechanism = \"scotch-yoke\")",
            });
        }
        let limit = match p {
            Parameter::Tdc | Parameter::ThrowAngle => Some((30.0, "30°")),
            Parameter::YokeSlotSquareness => Some((10.0, "10°")),
            _ => None,
        };
        if let Some((max, shown)) = limit
            && value > max
        {
            return Err(ToleranceError::Invalid {
                key: p.key(),
                value,
                expected: format!("a small deviation, at most {shown}"),
            });
        }
        if value == 0.0 {
            continue;
        }
        let mech = engine.mechanism();
        let m = engine.masses();
        let scalar = |nominal: f64| Input {
            parameter: p,
            index: None,
            tolerance: value,
            nominal,
        };
        match p {
            Parameter::Stroke => out.push(scalar(2.0 * mech.r() * 1e3)),
            Parameter::RodLength | Parameter::PinOffset => {
                if let Mechanism::CrankSlider(cs) = mech {
                    let v = if p == Parameter::RodLength {
                        cs.l()
                    } else {
                        cs.e()
                    };
                    out.push(scalar(v * 1e3));
                }
            }
            Parameter::Bore => out.push(scalar(engine.cylinder().bore() * 1e3)),
            Parameter::RodMass => out.push(scalar(m.rod)),
            Parameter::Tdc | Parameter::YokeSlotSquareness => out.push(scalar(0.0)),
            Parameter::PistonGroup => {
                for i in 0..engine.cylinders() {
                    out.push(Input {
                        index: Some(i),
                        ..scalar(m.piston_group)
                    });
                }
            }
            Parameter::ThrowAngle => {
                if engine.throws() < 2 {
                    notes.push(
                        "throw_angle_deg: the crank has one throw, the reference; nothing to vary"
                            .into(),
                    );
                }
                for k in 1..engine.throws() {
                    out.push(Input {
                        index: Some(k),
                        ..scalar(engine.crank_angles()[k].to_degrees())
                    });
                }
            }
        }
    }
    if out.is_empty() {
        return Err(ToleranceError::NoTolerances);
    }
    // INTERFACE.md's order, whatever the file's.
    out.sort_by_key(|i| {
        (
            Parameter::ALL.iter().position(|&p| p == i.parameter),
            i.index,
        )
    });
    Ok((out, notes))
}
