//! The ratio of specific heats γ of the cylinder charge: constant, or a
//! function of the mean gas temperature after Brunt.

use crate::CombustionError;

/// Default constant γ of the analysis (PHYSICS.md "Combustion").
pub const DEFAULT_GAMMA: f64 = 1.32;
/// Default intake valve closing for γ(T) (deg from firing TDC).
pub const DEFAULT_IVC_DEG: f64 = -140.0;
/// The bounds of an IVC angle (deg from firing TDC) and of the charge
/// temperature there (K): γ(T)'s and the wall heat's state alike.
pub const IVC_RANGE_DEG: (f64, f64) = (-270.0, 0.0);
/// See [`IVC_RANGE_DEG`].
pub const INTAKE_TEMP_RANGE_K: (f64, f64) = (200.0, 1000.0);
/// Default charge temperature at intake valve closing for γ(T) (K).
pub const DEFAULT_INTAKE_TEMP_K: f64 = 320.0;

/// Brunt's γ(T) = 1.338 − 6.0e−5 T + 1.0e−8 T² (T in K).
pub fn brunt(t_k: f64) -> f64 {
    1.338 - 6.0e-5 * t_k + 1.0e-8 * t_k * t_k
}

/// How γ is found at each point of the closed part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GammaModel {
    /// One γ throughout.
    Constant(f64),
    /// Brunt's γ(T), the mean gas temperature scaled from the state at
    /// intake valve closing: `T = T_ivc p V / (p_ivc V_ivc)`.
    Brunt {
        /// Intake valve closing (deg from firing TDC, negative before it).
        ivc_deg: f64,
        /// Charge temperature at intake valve closing (K).
        intake_temp_k: f64,
    },
}

impl Default for GammaModel {
    fn default() -> Self {
        GammaModel::Constant(DEFAULT_GAMMA)
    }
}

impl GammaModel {
    /// Brunt's model with the default IVC state.
    pub fn brunt_default() -> Self {
        GammaModel::Brunt {
            ivc_deg: DEFAULT_IVC_DEG,
            intake_temp_k: DEFAULT_INTAKE_TEMP_K,
        }
    }

    /// Checks the parameters: a constant γ in 1.01–1.67, IVC within
    /// −270…0°, T_ivc in 200–1000 K.
    pub fn check(&self) -> Result<(), CombustionError> {
        match *self {
            GammaModel::Constant(g) => {
                crate::check_range("gamma", g, 1.01, 1.67)?;
            }
            GammaModel::Brunt {
                ivc_deg,
                intake_temp_k,
            } => {
                crate::check_range("ivc_deg", ivc_deg, IVC_RANGE_DEG.0, IVC_RANGE_DEG.1)?;
                let (lo, hi) = INTAKE_TEMP_RANGE_K;
                crate::check_range("intake_temp_k", intake_temp_k, lo, hi)?;
            }
        }
        Ok(())
    }

    /// γ for a charge at `pv` (Pa·m³), given `pv_ivc`, the product at IVC
    /// (unused for a constant γ).
    #[inline]
    pub fn gamma(&self, pv: f64, pv_ivc: f64) -> f64 {
        match *self {
            GammaModel::Constant(g) => g,
            GammaModel::Brunt { intake_temp_k, .. } => brunt(intake_temp_k * pv / pv_ivc),
        }
    }

    /// A γ representative of the burnt charge, for bounds that need one
    /// number (the no-combustion bound): the constant, or 1.30.
    pub fn nominal(&self) -> f64 {
        match *self {
            GammaModel::Constant(g) => g,
            GammaModel::Brunt { .. } => 1.30,
        }
    }

    /// The model as `models.gamma` says it: `1.32`, or
    /// `brunt (T_ivc 320 K at -140°)`.
    pub fn describe(&self) -> String {
        match *self {
            GammaModel::Constant(g) => format!("{g}"),
            GammaModel::Brunt {
                ivc_deg,
                intake_temp_k,
            } => format!("brunt (T_ivc {intake_temp_k} K at {ivc_deg}°)"),
        }
    }

    /// An antiderivative of `d(pV) / (γ − 1)` at the state `pv` (J), given
    /// `pv_ivc`: the change of the charge's sensible energy between two
    /// states is the difference of two values, so the cumulative heat
    /// release takes no derivative of p. Exact for both models: `pV/(γ−1)`
    /// for a constant γ; for Brunt's quadratic in T (no real root),
    /// `(pV_ivc/T_ivc) · 2/√(4AC−B²) · atan((2CT + B)/√(4AC−B²))` with
    /// `γ − 1 = A + B T + C T²`.
    #[inline]
    pub fn energy(&self, pv: f64, pv_ivc: f64) -> f64 {
        match *self {
            GammaModel::Constant(g) => pv / (g - 1.0),
            GammaModel::Brunt { intake_temp_k, .. } => {
                const A: f64 = 1.338 - 1.0;
                const B: f64 = -6.0e-5;
                const C: f64 = 1.0e-8;
                let t = intake_temp_k * pv / pv_ivc;
                let d = (4.0 * A * C - B * B).sqrt();
                pv_ivc / intake_temp_k * 2.0 / d * ((2.0 * C * t + B) / d).atan()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brunt_values() {
        // 300 K: 1.338 - 0.018 + 0.0009 = 1.3209; 2000 K: 1.338 - 0.12 + 0.04 = 1.258.
        assert!((brunt(300.0) - 1.3209).abs() < 1e-12);
        assert!((brunt(2000.0) - 1.258).abs() < 1e-12);
    }

    #[test]
    fn energy_constant_is_exact() {
        let g = GammaModel::Constant(1.4);
        assert!((g.energy(140.0, 1.0) - g.energy(100.0, 1.0) - 100.0).abs() < 1e-12);
    }

    #[test]
    fn energy_brunt_matches_a_fine_sum() {
        let g = GammaModel::brunt_default();
        let (a, b, ivc) = (50.0, 400.0, 50.0);
        let coarse = g.energy(b, ivc) - g.energy(a, ivc);
        let n = 100_000;
        let h = (b - a) / n as f64;
        let fine: f64 = (0..n)
            .map(|k| {
                let x = a + (k as f64 + 0.5) * h;
                h / (g.gamma(x, ivc) - 1.0)
            })
            .sum();
        assert!((coarse - fine).abs() < 1e-9 * fine.abs(), "{coarse} {fine}");
    }

    #[test]
    fn checks() {
        assert!(GammaModel::Constant(1.0).check().is_err());
        assert!(GammaModel::Constant(1.32).check().is_ok());
        assert!(
            GammaModel::Brunt {
                ivc_deg: -140.0,
                intake_temp_k: 50.0
            }
            .check()
            .is_err()
        );
    }
}
