//! The charge a cylinder traps and the fuel it can burn (PHYSICS.md "Load
//! by the intake"): the air `m_a = p_intake V_ivc / (R T_intake)`, the
//! heat its fuel releases `η_c m_a LHV / (λ AFR_st)`. A spark-ignition
//! engine keeps λ (the fuel follows the air, the throttle sets the air); a
//! compression-ignition engine keeps its boost and sets the fuel, never
//! richer than `λ_min`.
//!
//! ```
//! use enginedyn_combustion::charge::{Charge, ChargeKind};
//! let si = Charge::default_for(ChargeKind::Si);
//! let air = si.trapped_air_kg(1.0e5, 4.0e-4, 320.0);
//! let q = si.heat_j(air, si.lambda);
//! assert!((si.lambda_of(air, q) - 1.0).abs() < 1e-12);
//! ```

/// The gas constant of air (J/(kg K)).
pub const R_AIR: f64 = 287.05;

/// How an engine makes its load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChargeKind {
    /// Spark ignition: the throttle sets the air, the fuel follows at λ.
    Si,
    /// Compression ignition: the boost sets the air, the load the fuel.
    Ci,
}

impl ChargeKind {
    /// `"si"` or `"ci"`, as the engine file spells it.
    pub fn name(self) -> &'static str {
        match self {
            ChargeKind::Si => "si",
            ChargeKind::Ci => "ci",
        }
    }
}

/// The air and fuel of a design cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Charge {
    /// SI or CI.
    pub kind: ChargeKind,
    /// The air ratio a spark-ignition engine runs at (1.0).
    pub lambda: f64,
    /// The richest air ratio a compression-ignition engine burns cleanly
    /// (1.2): it bounds the fuel, and so the load.
    pub lambda_min: f64,
    /// The fuel's lower heating value (J/kg).
    pub lhv_j_kg: f64,
    /// The stoichiometric air-fuel ratio (kg air per kg fuel).
    pub afr_stoich: f64,
    /// The share of the fuel's energy released in the cylinder.
    pub combustion_efficiency: f64,
}

impl Charge {
    /// The defaults of INTERFACE.md "The design model": petrol (λ 1.0,
    /// 43.4 MJ/kg, 14.7) or diesel (λ_min 1.2, 42.7 MJ/kg, 14.5), η_c 0.98.
    pub fn default_for(kind: ChargeKind) -> Self {
        match kind {
            ChargeKind::Si => Self {
                kind,
                lambda: 1.0,
                lambda_min: 1.2,
                lhv_j_kg: 43.4e6,
                afr_stoich: 14.7,
                combustion_efficiency: 0.98,
            },
            ChargeKind::Ci => Self {
                kind,
                lambda: 1.2,
                lambda_min: 1.2,
                lhv_j_kg: 42.7e6,
                afr_stoich: 14.5,
                combustion_efficiency: 0.98,
            },
        }
    }

    /// The air trapped at intake valve closing (kg): `p V / (R T)`.
    pub fn trapped_air_kg(&self, intake_pa: f64, v_ivc_m3: f64, intake_temp_k: f64) -> f64 {
        intake_pa * v_ivc_m3 / (R_AIR * intake_temp_k)
    }

    /// The heat (J) the fuel for `air_kg` of air at `lambda` releases.
    pub fn heat_j(&self, air_kg: f64, lambda: f64) -> f64 {
        self.combustion_efficiency * air_kg * self.lhv_j_kg / (lambda * self.afr_stoich)
    }

    /// The air ratio at which `air_kg` of air releases `heat_j`.
    pub fn lambda_of(&self, air_kg: f64, heat_j: f64) -> f64 {
        self.combustion_efficiency * air_kg * self.lhv_j_kg / (heat_j * self.afr_stoich)
    }

    /// The richest λ the load may ask for: λ of a spark-ignition engine,
    /// `λ_min` of a compression-ignition one.
    pub fn richest(&self) -> f64 {
        match self.kind {
            ChargeKind::Si => self.lambda,
            ChargeKind::Ci => self.lambda_min,
        }
    }
}
