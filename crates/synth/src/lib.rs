//! Synthetic indicator diagrams from a documented cycle model, so the
//! bundled data can be regenerated and tests can use diagrams whose physics
//! is known.
//!
//! The model is a single-zone first-law cycle: from intake valve closing to
//! exhaust valve opening the pressure follows
//! `dp/dphi = ((g - 1) dQ/dphi - g p dV/dphi) / V` (RK4, 0.02° steps) with
//! a Wiebe heat release `x_b = 1 - exp(-a ((phi - soc)/dur)^(m+1))` and the
//! ratio of specific heats blended from compression to expansion with the
//! burnt fraction; gas exchange is a blow-down to the exhaust pressure, the
//! exhaust stroke, a blended valve overlap and the intake stroke. The volume
//! law is the kinematics crate's (`Cylinder::volume`).
//!
//! ```
//! use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
//! use enginedyn_synth::{pressure_trace, CycleModel};
//! let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
//! let cyl = Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap();
//! let trace = pressure_trace(&cyl, &CycleModel::petrol_full_load(), 1.0).unwrap();
//! assert_eq!(trace.len(), 720);
//! let peak = trace.iter().map(|p| p.1).fold(0.0, f64::max);
//! assert!(peak > 40e5 && peak < 90e5);
//! ```

use enginedyn_kinematics::Cylinder;
use std::f64::consts::PI;

/// Why a trace cannot be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SynthError {
    /// A model parameter out of range.
    #[error("{name} = {value}: {expected}")]
    Parameter {
        /// Parameter.
        name: &'static str,
        /// Value given.
        value: f64,
        /// What is expected.
        expected: &'static str,
    },
}

/// The cycle model's parameters. Angles in degrees of cycle angle from
/// firing TDC (negative before it); pressures absolute.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleModel {
    /// Intake manifold pressure (Pa): the cylinder pressure on the intake stroke.
    pub intake_pressure_pa: f64,
    /// Exhaust back pressure (Pa) on the exhaust stroke.
    pub exhaust_pressure_pa: f64,
    /// Intake valve closing (deg, e.g. -130 = 130° before firing TDC).
    pub ivc_deg: f64,
    /// Exhaust valve opening (deg after firing TDC).
    pub evo_deg: f64,
    /// Ratio of specific heats of the unburnt charge (compression).
    pub gamma_compression: f64,
    /// Ratio of specific heats of the burnt gas (expansion).
    pub gamma_expansion: f64,
    /// Net heat released into the gas per cycle (J): fuel energy less wall losses.
    pub heat_released_j: f64,
    /// Start of combustion (deg, negative: before TDC).
    pub soc_deg: f64,
    /// Combustion duration (deg).
    pub burn_duration_deg: f64,
    /// Wiebe efficiency parameter `a` (5 ≈ 99.3 % burnt at the end).
    pub wiebe_a: f64,
    /// Wiebe shape parameter `m`.
    pub wiebe_m: f64,
    /// Blow-down duration after EVO (deg).
    pub blowdown_deg: f64,
}

impl CycleModel {
    /// A naturally aspirated petrol engine at full load near rated speed:
    /// intake 0.95 bar, exhaust 1.15 bar, IVC 50° after BDC, EVO 50° before
    /// BDC, spark-ignited burn from 20° BTDC over 45° (Wiebe a = 5, m = 2; 50 %
    /// burnt about 3° after TDC), 650 J released into the gas,
    /// gamma 1.36 → 1.26 (Heywood, ch. 9, typical full-load values).
    pub fn petrol_full_load() -> Self {
        Self {
            intake_pressure_pa: 0.95e5,
            exhaust_pressure_pa: 1.15e5,
            ivc_deg: -130.0,
            evo_deg: 130.0,
            gamma_compression: 1.36,
            gamma_expansion: 1.26,
            heat_released_j: 650.0,
            soc_deg: -20.0,
            burn_duration_deg: 45.0,
            wiebe_a: 5.0,
            wiebe_m: 2.0,
            blowdown_deg: 45.0,
        }
    }
    /// A turbocharged diesel at full load: intake 2.2 bar, exhaust 1.9 bar,
    /// burn from 6° BTDC over 70° (m = 1), gamma 1.37 → 1.28.
    pub fn diesel_full_load() -> Self {
        Self {
            intake_pressure_pa: 2.2e5,
            exhaust_pressure_pa: 1.9e5,
            ivc_deg: -145.0,
            evo_deg: 125.0,
            gamma_compression: 1.37,
            gamma_expansion: 1.28,
            heat_released_j: 7000.0,
            soc_deg: -6.0,
            burn_duration_deg: 70.0,
            wiebe_a: 5.0,
            wiebe_m: 1.0,
            blowdown_deg: 45.0,
        }
    }

    fn check(&self) -> Result<(), SynthError> {
        let p = |name, value: f64, ok: bool, expected| {
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
        p(
            "intake_pressure_pa",
            self.intake_pressure_pa,
            self.intake_pressure_pa > 0.0,
            "positive",
        )?;
        p(
            "exhaust_pressure_pa",
            self.exhaust_pressure_pa,
            self.exhaust_pressure_pa > 0.0,
            "positive",
        )?;
        p(
            "ivc_deg",
            self.ivc_deg,
            (-180.0..0.0).contains(&self.ivc_deg),
            "in [-180, 0)",
        )?;
        p(
            "evo_deg",
            self.evo_deg,
            (0.0..=180.0).contains(&self.evo_deg),
            "in [0, 180]",
        )?;
        p(
            "gamma_compression",
            self.gamma_compression,
            self.gamma_compression > 1.0,
            "above 1",
        )?;
        p(
            "gamma_expansion",
            self.gamma_expansion,
            self.gamma_expansion > 1.0,
            "above 1",
        )?;
        p(
            "heat_released_j",
            self.heat_released_j,
            self.heat_released_j >= 0.0,
            "0 or more",
        )?;
        p(
            "burn_duration_deg",
            self.burn_duration_deg,
            self.burn_duration_deg > 0.0,
            "positive",
        )?;
        p(
            "blowdown_deg",
            self.blowdown_deg,
            self.blowdown_deg > 0.0 && self.evo_deg + self.blowdown_deg < 330.0,
            "positive, ending before 330°",
        )?;
        Ok(())
    }

    /// Burnt mass fraction at `deg` (Wiebe).
    pub fn burnt_fraction(&self, deg: f64) -> f64 {
        if deg <= self.soc_deg {
            return 0.0;
        }
        let t = (deg - self.soc_deg) / self.burn_duration_deg;
        1.0 - (-self.wiebe_a * t.powf(self.wiebe_m + 1.0)).exp()
    }

    /// `dx_b/dphi` per degree.
    fn burn_rate(&self, deg: f64) -> f64 {
        if deg <= self.soc_deg {
            return 0.0;
        }
        let m1 = self.wiebe_m + 1.0;
        let t = (deg - self.soc_deg) / self.burn_duration_deg;
        self.wiebe_a * m1 * t.powf(self.wiebe_m) * (-self.wiebe_a * t.powf(m1)).exp()
            / self.burn_duration_deg
    }
}

/// Pressure (Pa) over one four-stroke cycle at `step_deg` from firing TDC:
/// `(crank_deg, pressure)` for `crank_deg` in `[0, 720)`.
pub fn pressure_trace(
    cyl: &Cylinder,
    model: &CycleModel,
    step_deg: f64,
) -> Result<Vec<(f64, f64)>, SynthError> {
    model.check()?;
    let n = (720.0 / step_deg).round() as usize;
    if !(step_deg > 0.0) || n < 8 || ((n as f64) * step_deg - 720.0).abs() > 1e-9 {
        return Err(SynthError::Parameter {
            name: "step_deg",
            value: step_deg,
            expected: "a step dividing 720° into at least 8 parts",
        });
    }
    // Closed part: IVC (negative) to EVO, integrated on a fine grid.
    let h = 0.02;
    let steps = ((model.evo_deg - model.ivc_deg) / h).round() as usize;
    let mut closed = Vec::with_capacity(steps + 1);
    let mut p = model.intake_pressure_pa;
    closed.push(p);
    let rhs = |deg: f64, p: f64| {
        let phi = deg.to_radians();
        let v = cyl.volume(phi);
        let dv = cyl.dvolume(phi) * PI / 180.0; // per degree
        let xb = model.burnt_fraction(deg);
        let g = model.gamma_compression + (model.gamma_expansion - model.gamma_compression) * xb;
        let dq = model.heat_released_j * model.burn_rate(deg);
        ((g - 1.0) * dq - g * p * dv) / v
    };
    for i in 0..steps {
        let a = model.ivc_deg + h * i as f64;
        let k1 = rhs(a, p);
        let k2 = rhs(a + h / 2.0, p + h / 2.0 * k1);
        let k3 = rhs(a + h / 2.0, p + h / 2.0 * k2);
        let k4 = rhs(a + h, p + h * k3);
        p += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        closed.push(p);
    }
    let p_evo = p;
    let closed_at = |deg: f64| {
        let x = (deg - model.ivc_deg) / h;
        let i = (x.floor() as usize).min(steps - 1);
        let f = x - i as f64;
        closed[i] * (1.0 - f) + closed[i + 1] * f
    };
    let blend = |t: f64| 0.5 - 0.5 * (PI * t.clamp(0.0, 1.0)).cos();
    let (pin, pex) = (model.intake_pressure_pa, model.exhaust_pressure_pa);
    let at = |deg: f64| -> f64 {
        // deg in [0, 720); the closed part runs from ivc+720 through 720 to evo.
        let d = if deg >= 720.0 + model.ivc_deg {
            deg - 720.0
        } else {
            deg
        };
        if d >= model.ivc_deg && d <= model.evo_deg {
            closed_at(d)
        } else if d < model.evo_deg + model.blowdown_deg {
            let t = (d - model.evo_deg) / model.blowdown_deg;
            (p_evo.ln() + (pex.ln() - p_evo.ln()) * blend(t)).exp()
        } else if d < 345.0 {
            pex
        } else if d < 375.0 {
            pex + (pin - pex) * blend((d - 345.0) / 30.0)
        } else {
            pin
        }
    };
    Ok((0..n)
        .map(|k| {
            let deg = k as f64 * step_deg;
            (deg, at(deg))
        })
        .collect())
}

/// Indicated work `∮ p dV` (J) of a trace from [`pressure_trace`], by the
/// periodic trapezoid rule with the exact `dV/dphi`.
pub fn indicated_work(cyl: &Cylinder, trace: &[(f64, f64)]) -> f64 {
    let h = (720.0 / trace.len() as f64).to_radians();
    trace
        .iter()
        .map(|&(deg, p)| p * cyl.dvolume(deg.to_radians()))
        .sum::<f64>()
        * h
}

/// Writes a trace as a diagram CSV: `# ` comment lines, a `# rpm = N` line
/// when given, the header `crank_deg,pressure_bar`, rows to 0.1° and 1e-5 bar.
pub fn write_csv(
    mut w: impl std::io::Write,
    trace: &[(f64, f64)],
    rpm: Option<f64>,
    comments: &[&str],
) -> std::io::Result<()> {
    for c in comments {
        writeln!(w, "# {c}")?;
    }
    if let Some(r) = rpm {
        writeln!(w, "# rpm = {r}")?;
    }
    writeln!(w, "crank_deg,pressure_bar")?;
    for (deg, p) in trace {
        writeln!(w, "{deg:.1},{:.5}", p / 1e5)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use enginedyn_kinematics::{CrankSlider, Mechanism};

    fn vaz() -> Cylinder {
        let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
        Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap()
    }

    /// Without heat release the closed part is an isentrope: p V^g = const
    /// (RK4 at 0.02°: 1e-8 relative).
    #[test]
    fn no_heat_is_isentropic() {
        let cyl = vaz();
        let mut m = CycleModel::petrol_full_load();
        m.heat_released_j = 0.0;
        m.gamma_expansion = m.gamma_compression;
        let t = pressure_trace(&cyl, &m, 0.5).unwrap();
        let g = m.gamma_compression;
        let c0 = m.intake_pressure_pa * cyl.volume(m.ivc_deg.to_radians()).powf(g);
        for &(deg, p) in &t {
            let d = if deg >= 720.0 + m.ivc_deg {
                deg - 720.0
            } else {
                deg
            };
            if d >= m.ivc_deg && d <= m.evo_deg {
                let c = p * cyl.volume(d.to_radians()).powf(g);
                assert!((c / c0 - 1.0).abs() < 1e-8, "at {deg}: {}", c / c0 - 1.0);
            }
        }
    }

    /// The petrol preset on the VAZ geometry: IMEP 9.5–11.5 bar, peak 50–75
    /// bar at 10–20° after TDC, continuous, positive, pumping loop negative.
    #[test]
    fn petrol_preset_is_a_plausible_full_load_diagram() {
        let cyl = vaz();
        let m = CycleModel::petrol_full_load();
        let t = pressure_trace(&cyl, &m, 0.5).unwrap();
        let imep = indicated_work(&cyl, &t) / cyl.swept_volume() / 1e5;
        assert!((9.5..11.5).contains(&imep), "imep {imep}");
        let (deg, peak) = t
            .iter()
            .fold((0.0, 0.0), |a, &b| if b.1 > a.1 { b } else { a });
        assert!((50e5..75e5).contains(&peak), "peak {peak}");
        assert!((10.0..20.0).contains(&deg), "peak at {deg}");
        assert!(t.iter().all(|&(_, p)| p > 0.0));
        for i in 0..t.len() {
            let j = (i + 1) % t.len();
            assert!((t[j].1 - t[i].1).abs() < 0.05 * peak, "jump at {}", t[i].0);
        }
        assert!(m.intake_pressure_pa < m.exhaust_pressure_pa);
    }
}
