//! Heat lost to the chamber walls, for the gross heat release (PHYSICS.md
//! "Wall heat and gross heat release"): `dQ_gross = dQ_net + dQ_wall`,
//! `dQ_wall = h A (T − T_w) dt/dφ`, the bulk gas temperature `T = pV/(mR)`
//! from the trapped charge at IVC (`mR = p_ivc V_ivc / T_ivc`), the chamber
//! area `A` = piston crown + flat head + the liner over the gas column, and
//! the heat-transfer coefficient `h` of Woschni (1967) or Hohenberg (1979).

use crate::{CombustionError, check_range};

/// Default mean wall temperature (K).
pub const DEFAULT_WALL_TEMP_K: f64 = 450.0;
/// The bounds of the mean wall temperature (K).
pub const WALL_TEMP_RANGE_K: (f64, f64) = (250.0, 1000.0);

/// Woschni's `C1` (gas exchange excluded: compression and combustion).
pub const WOSCHNI_C1: f64 = 2.28;
/// Woschni's `C2` from the start of combustion (m/(s K)).
pub const WOSCHNI_C2: f64 = 3.24e-3;

/// The heat-transfer correlation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallModel {
    /// Woschni (1967): `h = 3.26 B^−0.2 p^0.8 T^−0.55 w^0.8` (B m, p kPa,
    /// T K), `w = C1 c_m + C2 (V_d T_ivc)/(p_ivc V_ivc) (p − p_mot)`.
    Woschni,
    /// Hohenberg (1979): `h = 130 V^−0.06 p^0.8 T^−0.4 (c_m + 1.4)^0.8`
    /// (V m³, p bar, T K).
    Hohenberg,
}

impl WallModel {
    /// The name the flag and `models.wall_heat` use.
    pub fn name(self) -> &'static str {
        match self {
            WallModel::Woschni => "woschni",
            WallModel::Hohenberg => "hohenberg",
        }
    }
}

/// The wall-heat model of an analysis, with the engine's chamber.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallHeat {
    /// The correlation.
    pub model: WallModel,
    /// Mean wall temperature (K).
    pub wall_temp_k: f64,
    /// Charge temperature at IVC (K).
    pub intake_temp_k: f64,
    /// Intake valve closing (deg from firing TDC): the trapped state.
    pub ivc_deg: f64,
    /// Bore (m).
    pub bore_m: f64,
    /// Stroke (m), for the mean piston speed.
    pub stroke_m: f64,
    /// Swept volume of one cylinder (m³), for Woschni's combustion term.
    pub swept_m3: f64,
}

impl WallHeat {
    /// Checks the temperatures (wall 250–1000 K, intake 200–1000 K), IVC
    /// (−270…0°) and the chamber (positive).
    pub fn check(&self) -> Result<(), CombustionError> {
        let (w, t, a) = (
            WALL_TEMP_RANGE_K,
            crate::gamma::INTAKE_TEMP_RANGE_K,
            crate::gamma::IVC_RANGE_DEG,
        );
        check_range("wall_temp_k", self.wall_temp_k, w.0, w.1)?;
        check_range("intake_temp_k", self.intake_temp_k, t.0, t.1)?;
        check_range("ivc_deg", self.ivc_deg, a.0, a.1)?;
        for (name, v) in [
            ("bore", self.bore_m),
            ("stroke", self.stroke_m),
            ("swept volume", self.swept_m3),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(CombustionError::Input(format!(
                    "wall heat: the {name} is {v}: a positive value is needed"
                )));
            }
        }
        Ok(())
    }

    /// `models.wall_heat`: `woschni (T_w 450 K)`.
    pub fn describe(&self) -> String {
        format!(
            "{} (T_w {} K)",
            self.model.name(),
            enginedyn_numerics::format::human(self.wall_temp_k)
        )
    }

    /// The chamber area (m²) over a gas column of volume `v`: piston crown
    /// and flat head (each πB²/4) and the liner `4V/B`.
    pub fn area(&self, v: f64) -> f64 {
        let b = self.bore_m;
        0.5 * std::f64::consts::PI * b * b + 4.0 * v / b
    }

    /// The heat-transfer coefficient (W/m²K) at pressure `p` (Pa), gas
    /// temperature `t` (K), volume `v` (m³) and mean piston speed `cm`
    /// (m/s); `dp_comb` is Woschni's `(V_d T_ivc)/(p_ivc V_ivc) (p − p_mot)`
    /// term already multiplied by `C2` (m/s; 0 before SOC).
    pub fn coefficient(&self, p: f64, t: f64, v: f64, cm: f64, w_comb: f64) -> f64 {
        self.coefficient_with(self.fixed(cm), p, t, v, cm, w_comb)
    }

    /// The factor of [`Self::coefficient`] that a cycle does not change
    /// (at mean piston speed `cm`): Woschni's `3.26 B^−0.2`, Hohenberg's
    /// `(c_m + 1.4)^0.8`.
    fn fixed(&self, cm: f64) -> f64 {
        match self.model {
            WallModel::Woschni => 3.26 * self.bore_m.powf(-0.2),
            WallModel::Hohenberg => (cm + 1.4).powf(0.8),
        }
    }

    /// [`Self::coefficient`] given [`Self::fixed`] (the same products in
    /// the same order).
    fn coefficient_with(&self, fixed: f64, p: f64, t: f64, v: f64, cm: f64, w_comb: f64) -> f64 {
        let (p, t) = (p.max(0.0), t.max(1.0));
        match self.model {
            WallModel::Woschni => {
                let w = (WOSCHNI_C1 * cm + w_comb).max(0.0);
                fixed * (p / 1e3).powf(0.8) * t.powf(-0.55) * w.powf(0.8)
            }
            WallModel::Hohenberg => {
                130.0 * v.powf(-0.06) * (p / 1e5).powf(0.8) * t.powf(-0.4) * fixed
            }
        }
    }
}

/// The state a cycle's wall heat is computed from: the trapped charge at
/// IVC and the speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trapped {
    /// `p_ivc` (Pa).
    pub p_ivc: f64,
    /// `V_ivc` (m³).
    pub v_ivc: f64,
    /// γ at IVC, for the motored pressure `p_ivc (V_ivc/V)^γ`.
    pub gamma_ivc: f64,
    /// Speed (rpm).
    pub rpm: f64,
}

impl WallHeat {
    /// `dQ_wall/dφ` (J/°) at pressure `p` (Pa) and volume `v` (m³);
    /// `burning` switches Woschni's combustion term on (from SOC).
    pub fn rate(&self, s: &Trapped, p: f64, v: f64, burning: bool) -> f64 {
        self.in_cycle(s).rate(p, v, burning)
    }

    /// [`Self::rate`] with what a cycle does not change taken once.
    pub(crate) fn in_cycle(&self, s: &Trapped) -> CycleWall<'_> {
        let cm = 2.0 * self.stroke_m * s.rpm / 60.0;
        CycleWall {
            w: self,
            s: *s,
            mr: s.p_ivc * s.v_ivc / self.intake_temp_k,
            cm,
            fixed: self.fixed(cm),
            c2: WOSCHNI_C2 * self.swept_m3 * self.intake_temp_k / (s.p_ivc * s.v_ivc),
            per_deg: 6.0 * s.rpm,
        }
    }
}

/// [`WallHeat::rate`] over one cycle: the trapped charge's `mR`, the mean
/// piston speed, the fixed factor of the coefficient, Woschni's
/// `C2 V_d T_ivc/(p_ivc V_ivc)` and `6 n` taken once (the same numbers).
#[derive(Debug, Clone, Copy)]
pub(crate) struct CycleWall<'a> {
    w: &'a WallHeat,
    s: Trapped,
    mr: f64,
    cm: f64,
    fixed: f64,
    c2: f64,
    per_deg: f64,
}

impl CycleWall<'_> {
    /// `dQ_wall/dφ` (J/°) at pressure `p` (Pa) and volume `v` (m³).
    #[inline]
    pub(crate) fn rate(&self, p: f64, v: f64, burning: bool) -> f64 {
        let (w, s) = (self.w, &self.s);
        let t = p * v / self.mr;
        let w_comb = if burning && w.model == WallModel::Woschni {
            let p_mot = s.p_ivc * (s.v_ivc / v).powf(s.gamma_ivc);
            self.c2 * (p - p_mot)
        } else {
            0.0
        };
        let h = w.coefficient_with(self.fixed, p, t, v, self.cm, w_comb);
        // dt/dφ = 1/(6 n) s/° at n rpm.
        h * w.area(v) * (t - w.wall_temp_k) / self.per_deg
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chamber(model: WallModel) -> WallHeat {
        WallHeat {
            model,
            wall_temp_k: 450.0,
            intake_temp_k: 320.0,
            ivc_deg: -140.0,
            bore_m: 0.076,
            stroke_m: 0.071,
            swept_m3: 0.000322,
        }
    }

    /// The rate with the cycle's factors taken once against the formula
    /// written out per point, as it was: bit for bit.
    #[test]
    fn the_cycle_rate_is_the_formula_per_point() {
        let s = Trapped {
            p_ivc: 1.1e5,
            v_ivc: 3.1e-4,
            gamma_ivc: 1.36,
            rpm: 2400.0,
        };
        for model in [WallModel::Woschni, WallModel::Hohenberg] {
            let w = chamber(model);
            for (p, v, burning) in [
                (1.2e5, 3.0e-4, false),
                (45e5, 4.0e-5, true),
                (60e5, 3.7e-5, false),
                (20e5, 9.0e-5, true),
            ] {
                let mr = s.p_ivc * s.v_ivc / w.intake_temp_k;
                let t = p * v / mr;
                let cm = 2.0 * w.stroke_m * s.rpm / 60.0;
                let w_comb = if burning && model == WallModel::Woschni {
                    let p_mot = s.p_ivc * (s.v_ivc / v).powf(s.gamma_ivc);
                    WOSCHNI_C2 * w.swept_m3 * w.intake_temp_k / (s.p_ivc * s.v_ivc) * (p - p_mot)
                } else {
                    0.0
                };
                let (pc, tc) = (p.max(0.0), t.max(1.0));
                let h = match model {
                    WallModel::Woschni => {
                        let wv = (WOSCHNI_C1 * cm + w_comb).max(0.0);
                        3.26 * w.bore_m.powf(-0.2)
                            * (pc / 1e3).powf(0.8)
                            * tc.powf(-0.55)
                            * wv.powf(0.8)
                    }
                    WallModel::Hohenberg => {
                        130.0
                            * v.powf(-0.06)
                            * (pc / 1e5).powf(0.8)
                            * tc.powf(-0.4)
                            * (cm + 1.4).powf(0.8)
                    }
                };
                let want = h * w.area(v) * (t - w.wall_temp_k) / (6.0 * s.rpm);
                assert_eq!(w.rate(&s, p, v, burning).to_bits(), want.to_bits());
                assert_eq!(
                    w.coefficient(p, t, v, cm, w_comb).to_bits(),
                    h.to_bits(),
                    "{model:?}"
                );
            }
        }
    }

    /// Hand-computed values: Hohenberg at 40 bar, 1800 K, 60 cm³, c_m 11.6
    /// m/s: 130 · 6e-5^−0.06 · 40^0.8 · 1800^−0.4 · 13^0.8.
    #[test]
    fn coefficients_by_hand() {
        let h = chamber(WallModel::Hohenberg).coefficient(40e5, 1800.0, 60e-6, 11.6, 0.0);
        let want =
            130.0 * 6e-5f64.powf(-0.06) * 40f64.powf(0.8) * 1800f64.powf(-0.4) * 13f64.powf(0.8);
        assert!((h / want - 1.0).abs() < 1e-12, "{h} {want}");
        // Woschni: 3.26 · 0.076^−0.2 · 4000^0.8 · 1800^−0.55 · (2.28 · 11.6)^0.8.
        let h = chamber(WallModel::Woschni).coefficient(40e5, 1800.0, 60e-6, 11.6, 0.0);
        let want = 3.26
            * 0.076f64.powf(-0.2)
            * 4000f64.powf(0.8)
            * 1800f64.powf(-0.55)
            * (2.28f64 * 11.6).powf(0.8);
        assert!((h / want - 1.0).abs() < 1e-12, "{h} {want}");
        // The area at TDC of a 9.9:1 chamber: πB²/2 + 4 V_c/B.
        let w = chamber(WallModel::Woschni);
        let vc = 0.000322 / 8.9;
        let a = std::f64::consts::PI * 0.076 * 0.076 / 2.0 + 4.0 * vc / 0.076;
        assert!((w.area(vc) - a).abs() < 1e-15);
    }
}
