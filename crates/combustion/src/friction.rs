//! Friction and brake figures (PHYSICS.md "Friction and brake figures"):
//! the friction mean effective pressure by Chen and Flynn,
//! `FMEP = A + B p_max + C c_m + D c_m²` (S. K. Chen and P. F. Flynn,
//! "Development of a single cylinder compression ignition research
//! engine", SAE 650733, 1965), then `BMEP = IMEP − FMEP`, the brake torque
//! and power from BMEP, and the mechanical efficiency BMEP/IMEP.
//!
//! The engine file gives the constants in bar and m/s (`[friction]`:
//! `a_bar`, `b`, `c_bar_s_m`, `d_bar_s2_m2`); inside they are SI.
//!
//! ```
//! use enginedyn_combustion::friction::ChenFlynn;
//! let f = ChenFlynn::PETROL;
//! // 60 bar peak, 10 m/s mean piston speed.
//! let fmep_bar = f.fmep_pa(60e5, 10.0) / 1e5;
//! assert!((fmep_bar - (0.4 + 0.005 * 60.0 + 0.09 * 10.0 + 0.0009 * 100.0)).abs() < 1e-12);
//! let b = f.brake(10e5, 60e5, 10.0);
//! assert!((b.bmep_pa + b.fmep_pa - 10e5).abs() < 1e-6);
//! ```

/// The Chen–Flynn constants, SI: `FMEP = a + b p_max + c c_m + d c_m²`
/// (Pa; `p_max` Pa, `c_m` m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChenFlynn {
    /// The constant part (Pa).
    pub a_pa: f64,
    /// The share of the peak pressure (dimensionless).
    pub b: f64,
    /// The part linear in the mean piston speed (Pa s/m).
    pub c_pa_s_m: f64,
    /// The part quadratic in the mean piston speed (Pa s²/m²).
    pub d_pa_s2_m2: f64,
}

impl ChenFlynn {
    /// The defaults for a spark-ignition (petrol) engine: A 0.4 bar, B
    /// 0.005, C 0.09 bar s/m, D 0.0009 bar s²/m². They give an FMEP of
    /// about 1.1 bar at 5 m/s and 60 bar, 2.2 bar at 14 m/s (a 1.3–1.6 l
    /// four at 2,000 and 6,000 rpm), within the motored-friction
    /// correlation of Barnes-Moss for such engines (Heywood, *Internal
    /// Combustion Engine Fundamentals*, 1988, §13.6) less its pumping
    /// part; `docs/design.md` sets them side by side.
    pub const PETROL: ChenFlynn = ChenFlynn {
        a_pa: 0.4e5,
        b: 0.005,
        c_pa_s_m: 0.09e5,
        d_pa_s2_m2: 0.0009e5,
    };
    /// The defaults for a compression-ignition (diesel) engine: A 0.4 bar,
    /// B 0.004, C 0.08 bar s/m, D 0.0009 bar s²/m²: about 2.0 bar at a
    /// heavy-duty engine's rated point (180 bar, 10 m/s) and 1.2 bar at
    /// 6 m/s and 100 bar, the range Heywood (1988, §13.6) gives for
    /// diesels.
    pub const DIESEL: ChenFlynn = ChenFlynn {
        a_pa: 0.4e5,
        b: 0.004,
        c_pa_s_m: 0.08e5,
        d_pa_s2_m2: 0.0009e5,
    };

    /// FMEP (Pa) at the peak pressure `p_max_pa` (Pa, absolute) and the
    /// mean piston speed `c_m` (m/s).
    pub fn fmep_pa(&self, p_max_pa: f64, c_m: f64) -> f64 {
        self.a_pa + self.b * p_max_pa + self.c_pa_s_m * c_m + self.d_pa_s2_m2 * c_m * c_m
    }

    /// The brake figures of a cycle of net IMEP `imep_pa` and peak
    /// `p_max_pa` at the mean piston speed `c_m`.
    pub fn brake(&self, imep_pa: f64, p_max_pa: f64, c_m: f64) -> Brake {
        let fmep_pa = self.fmep_pa(p_max_pa, c_m);
        let bmep_pa = imep_pa - fmep_pa;
        Brake {
            fmep_pa,
            bmep_pa,
            mechanical_efficiency: (imep_pa > 0.0).then(|| bmep_pa / imep_pa),
        }
    }
}

/// The brake figures of one operating point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Brake {
    /// The friction mean effective pressure (Pa).
    pub fmep_pa: f64,
    /// The brake mean effective pressure, IMEP − FMEP (Pa; negative where
    /// the engine does not overcome its friction).
    pub bmep_pa: f64,
    /// BMEP/IMEP (`None` for a cycle without positive IMEP).
    pub mechanical_efficiency: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fmep_is_the_polynomial_and_bmep_the_rest() {
        let f = ChenFlynn::DIESEL;
        let fmep = f.fmep_pa(180e5, 10.0) / 1e5;
        assert!((fmep - (0.4 + 0.72 + 0.8 + 0.09)).abs() < 1e-12, "{fmep}");
        let b = f.brake(20e5, 180e5, 10.0);
        assert!((b.bmep_pa / 1e5 - (20.0 - fmep)).abs() < 1e-12);
        assert!((b.mechanical_efficiency.unwrap() - (20.0 - fmep) / 20.0).abs() < 1e-12);
        assert_eq!(f.brake(0.0, 50e5, 5.0).mechanical_efficiency, None);
    }
}
