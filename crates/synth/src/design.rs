//! Synthesis for design: the pressure of an engine that has no measured
//! diagram yet, from a burn law (the combustion crate's Wiebe, single or
//! double), the analysis' γ model and a load (an IMEP target or the heat
//! released), on the cycle model of [`crate::CycleSolution`]
//! (PHYSICS.md "Combustion", "Synthesis").
//!
//! From IVC to EVO the first law `d(pV)/dphi = (g - 1)(Q_f dx_b/dphi -
//! p dV/dphi)`, that is `dp/dphi = ((g - 1) Q_f dx_b/dphi - g p dV/dphi) /
//! V`, with `g` the analysis' model ([`GammaModel`]: a constant, or Brunt's
//! γ(T) with `T = T_ivc p V / (p_ivc V_ivc)`); the gas exchange as the
//! presets have it. An IMEP target is met by solving for `Q_f` (a secant
//! on IMEP(Q_f), to 1e-9 relative; the trace is nearly but not exactly
//! affine in `Q_f`: the blow-down and γ(T) are not).
//!
//! ```
//! use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
//! use enginedyn_synth::{BurnLaw, DesignModel, GammaModel, Load, Wiebe, DEFAULT_A, design};
//! let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
//! let cyl = Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap();
//! let burn = BurnLaw::single(Wiebe::from_ca50(8.0, 20.0, 2.0, DEFAULT_A).unwrap());
//! let model = DesignModel::new(burn, Load::Imep { pa: 9.0e5 }, GammaModel::Constant(1.32), false);
//! let d = design(&cyl, &model).unwrap();
//! assert!((d.imep_pa / 9.0e5 - 1.0).abs() < 1e-6);
//! ```

use crate::{BurnLaw, CycleModel, CycleSolution, GammaModel, Gas, Losses, SynthError};
use enginedyn_combustion::charge::{Charge, ChargeKind};
use enginedyn_kinematics::Cylinder;

/// Exhaust valve opening of a design four-stroke without `evo_deg` (deg
/// after firing TDC; 50° before BDC, the petrol preset's).
pub const DEFAULT_EVO_DEG: f64 = 130.0;
/// Intake (port) closing of a design two-stroke without `ivc_deg` (deg).
pub const DEFAULT_IVC_DEG_TWO_STROKE: f64 = -100.0;
/// Exhaust (port) opening of a design two-stroke without `evo_deg` (deg).
pub const DEFAULT_EVO_DEG_TWO_STROKE: f64 = 100.0;
/// The blow-down after EVO (deg), shortened when the exchange blend would
/// start sooner.
pub const DESIGN_BLOWDOWN_DEG: f64 = 40.0;
/// The largest internal step of a design trace's closed part (deg): RK4
/// at 0.1° on tables of V, dV/dphi and dx_b/dphi built once per design
/// (the secant integrates the cycle 3 to 5 times).
pub const DESIGN_STEP_DEG: f64 = 0.1;
/// The step (deg) of [`imep_of`]'s trapezoid on `p dV/dphi` (0.05°:
/// converged to 1e-6 relative); the solver itself takes Simpson's rule on
/// the RK4 nodes of the closed part and at 0.1° or finer on the rest.
pub const IMEP_WORK_STEP_DEG: f64 = 0.05;

/// The exhaust back pressure (Pa) of a design cycle with intake pressure
/// `intake_pa`: 1.1 bar for a naturally aspirated engine (a silencer's
/// back pressure), 86 % of a higher boost (a turbine inlet's, as the
/// diesel preset has it): `max(1.1 bar, 0.86 p_in)`.
pub fn exhaust_pressure_for(intake_pa: f64) -> f64 {
    (0.86 * intake_pa).max(1.1e5)
}

/// The load of a design cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Load {
    /// The net IMEP asked for (Pa): the heat released is solved for.
    Imep {
        /// Pa.
        pa: f64,
    },
    /// The heat released into the gas per cycle (J).
    Heat {
        /// J.
        j: f64,
    },
}

/// A design cycle: the burn law, the γ model, the load and the gas
/// exchange. Angles in degrees from firing TDC, pressures absolute in Pa.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignModel {
    /// The burn law.
    pub burn: BurnLaw,
    /// The load.
    pub load: Load,
    /// The analysis' γ model (a Brunt model's `ivc_deg` must be
    /// [`Self::ivc_deg`]).
    pub gamma: GammaModel,
    /// Intake pressure (Pa), the cylinder's at IVC.
    pub intake_pressure_pa: f64,
    /// Exhaust back pressure (Pa).
    pub exhaust_pressure_pa: f64,
    /// Intake valve closing (deg, negative).
    pub ivc_deg: f64,
    /// Exhaust valve opening (deg).
    pub evo_deg: f64,
    /// Blow-down after EVO (deg).
    pub blowdown_deg: f64,
    /// A two-stroke (360°) cycle.
    pub two_stroke: bool,
    /// The air and fuel (PHYSICS "Load by the intake"): a spark-ignition
    /// engine meets an IMEP target by its intake pressure (at most
    /// [`Self::intake_pressure_pa`]), a compression-ignition one by its
    /// fuel, never richer than `λ_min`. `None`: the intake pressure stays
    /// and the heat released follows the load, unbounded but by the
    /// engine file's own check.
    pub air: Option<Air>,
}

/// The charge of a design cycle and the temperature its air is trapped at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Air {
    /// SI or CI, λ, the fuel.
    pub charge: Charge,
    /// The charge temperature at IVC (K).
    pub intake_temp_k: f64,
}

impl DesignModel {
    /// A design cycle with the defaults: intake 1 bar, exhaust
    /// [`exhaust_pressure_for`] it, IVC the Brunt model's (else −140°;
    /// −100° for a two-stroke), EVO 130° (100°), blow-down
    /// [`DESIGN_BLOWDOWN_DEG`].
    pub fn new(burn: BurnLaw, load: Load, gamma: GammaModel, two_stroke: bool) -> Self {
        let ivc_deg = match gamma {
            GammaModel::Brunt { ivc_deg, .. } => ivc_deg,
            GammaModel::Constant(_) if two_stroke => DEFAULT_IVC_DEG_TWO_STROKE,
            GammaModel::Constant(_) => crate::DEFAULT_IVC_DEG,
        };
        let evo_deg = if two_stroke {
            DEFAULT_EVO_DEG_TWO_STROKE
        } else {
            DEFAULT_EVO_DEG
        };
        let mut m = Self {
            burn,
            load,
            gamma,
            intake_pressure_pa: 1.0e5,
            exhaust_pressure_pa: exhaust_pressure_for(1.0e5),
            ivc_deg,
            evo_deg,
            blowdown_deg: DESIGN_BLOWDOWN_DEG,
            two_stroke,
            air: None,
        };
        m.fit_blowdown();
        m
    }

    /// Shortens the blow-down to end where the exchange blend starts
    /// (a late EVO), never below 1°.
    pub fn fit_blowdown(&mut self) {
        let cycle = if self.two_stroke { 360.0 } else { 720.0 };
        let room = cycle / 2.0 - crate::EXCHANGE_BLEND_DEG / 2.0 - self.evo_deg;
        self.blowdown_deg = DESIGN_BLOWDOWN_DEG.min(room).max(1.0);
    }

    /// The cycle model releasing `heat_j` (J).
    pub fn cycle_model(&self, heat_j: f64) -> CycleModel {
        CycleModel {
            intake_pressure_pa: self.intake_pressure_pa,
            exhaust_pressure_pa: self.exhaust_pressure_pa,
            ivc_deg: self.ivc_deg,
            evo_deg: self.evo_deg,
            gas: Gas::Model(self.gamma),
            heat_released_j: heat_j,
            burn: self.burn,
            blowdown_deg: self.blowdown_deg,
            two_stroke: self.two_stroke,
            losses: Losses::NONE,
        }
    }

    /// Length of the cycle (deg).
    pub fn cycle_deg(&self) -> f64 {
        if self.two_stroke { 360.0 } else { 720.0 }
    }
}

/// A design cycle solved: its model (with the heat released), the
/// solution, and the IMEP it gives.
#[derive(Debug, Clone)]
pub struct Design {
    /// The cycle model, `heat_released_j` the load's.
    pub model: CycleModel,
    /// The solved cycle.
    pub solution: CycleSolution,
    /// The heat released into the gas per cycle (J): given, or solved for.
    pub heat_released_j: f64,
    /// The net IMEP of the cycle (Pa), by the trapezoid on `p dV/dphi` at
    /// [`IMEP_WORK_STEP_DEG`].
    pub imep_pa: f64,
    /// Cycles integrated to find it (1 for a heat given).
    pub evaluations: usize,
    /// The intake pressure of the cycle (Pa): the model's, or the one a
    /// spark-ignition engine's throttle gives for the load.
    pub intake_pressure_pa: f64,
    /// The air ratio of the cycle, with [`DesignModel::air`].
    pub lambda: Option<f64>,
}

/// The net IMEP (Pa) of a solved cycle: `∮ p dV / V_d`, the trapezoid on
/// `p dV/dphi` at [`IMEP_WORK_STEP_DEG`] with the exact volume law.
pub fn imep_of(cyl: &Cylinder, sol: &CycleSolution) -> f64 {
    let cycle = sol.model().cycle_deg();
    let n = (cycle / IMEP_WORK_STEP_DEG).round() as usize;
    let h = cycle / n as f64;
    let work: f64 = (0..n)
        .map(|k| {
            let deg = k as f64 * h;
            sol.pressure(deg) * cyl.dvolume(deg.to_radians())
        })
        .sum::<f64>()
        * h.to_radians();
    work / cyl.swept_volume()
}

/// What every cycle of one design shares, built once: the closed part's
/// V, dV/dphi (per degree) and burn rate at each RK4 node and half step,
/// and dV/dphi on the open part's Simpson grid.
struct Grid {
    h: f64,
    n: usize,
    v: Vec<f64>,
    dv: Vec<f64>,
    rate: Vec<f64>,
    open: Vec<(f64, f64)>,
    open_h: f64,
}

/// What a [`Grid`] is made of: the cylinder, the burn law and the closed
/// part's span; a map's points share them (the load and the intake
/// pressure do not enter the grid).
#[derive(Debug, Clone, Copy, PartialEq)]
struct GridKey {
    cyl: Cylinder,
    burn: BurnLaw,
    ivc_deg: f64,
    evo_deg: f64,
    two_stroke: bool,
}

thread_local! {
    /// The last grid built on this thread: a map's next point reuses it
    /// (the same tables, so the same cycle to the bit) instead of some
    /// 11,000 volume, slope and burn-rate evaluations.
    static LAST_GRID: std::cell::RefCell<Option<(GridKey, std::rc::Rc<Grid>)>> =
        const { std::cell::RefCell::new(None) };
}

/// The grid of `model` on `cyl`: this thread's last one when it is made of
/// the same ([`GridKey`]), else a new one (kept for the next call).
fn shared_grid(cyl: &Cylinder, model: &DesignModel) -> Result<std::rc::Rc<Grid>, SynthError> {
    model.cycle_model(0.0).check()?;
    let key = GridKey {
        cyl: *cyl,
        burn: model.burn,
        ivc_deg: model.ivc_deg,
        evo_deg: model.evo_deg,
        two_stroke: model.two_stroke,
    };
    let hit = LAST_GRID.with(|g| {
        g.borrow()
            .as_ref()
            .filter(|(k, _)| *k == key)
            .map(|(_, grid)| grid.clone())
    });
    if let Some(grid) = hit {
        return Ok(grid);
    }
    let grid = std::rc::Rc::new(Grid::new(cyl, model)?);
    LAST_GRID.with(|g| *g.borrow_mut() = Some((key, grid.clone())));
    Ok(grid)
}

impl Grid {
    fn new(cyl: &Cylinder, model: &DesignModel) -> Result<Self, SynthError> {
        model.cycle_model(0.0).check()?;
        let span = model.evo_deg - model.ivc_deg;
        // An even count of steps, for Simpson's rule on the nodes.
        let n = ((span / DESIGN_STEP_DEG / 2.0).ceil() as usize * 2).max(2);
        let h = span / n as f64;
        let (mut v, mut dv, mut rate) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..=2 * n {
            let deg = model.ivc_deg + k as f64 * h / 2.0;
            let phi = deg.to_radians();
            v.push(cyl.volume(phi));
            dv.push(cyl.dvolume(phi) * (std::f64::consts::PI / 180.0));
            rate.push(model.burn.rate(deg));
        }
        let open_span = model.cycle_deg() - span;
        let m = ((open_span / DESIGN_STEP_DEG / 2.0).ceil() as usize * 2).max(2);
        let open_h = open_span / m as f64;
        let open = (0..=m)
            .map(|k| {
                let deg = model.evo_deg + k as f64 * open_h;
                (
                    deg,
                    cyl.dvolume(deg.to_radians()) * (std::f64::consts::PI / 180.0),
                )
            })
            .collect();
        Ok(Self {
            h,
            n,
            v,
            dv,
            rate,
            open,
            open_h,
        })
    }

    /// The closed part releasing `q` (J): RK4 on the tables, then the
    /// solution; and the cycle's `∮ p dV` (J).
    fn cycle(
        &self,
        cyl: &Cylinder,
        model: &DesignModel,
        q: f64,
    ) -> Result<(CycleSolution, f64), SynthError> {
        let g = model.gamma;
        let pv_ivc = model.intake_pressure_pa * self.v[0];
        let f = |k: usize, p: f64| {
            let v = self.v[k];
            let gam = g.gamma(p * v, pv_ivc);
            ((gam - 1.0) * q * self.rate[k] - gam * p * self.dv[k]) / v
        };
        let h = self.h;
        let mut p = Vec::with_capacity(self.n + 1);
        let mut dp = Vec::with_capacity(self.n + 1);
        let mut pi = model.intake_pressure_pa;
        let mut k1 = f(0, pi);
        p.push(pi);
        dp.push(k1);
        for i in 0..self.n {
            let k2 = f(2 * i + 1, pi + h / 2.0 * k1);
            let k3 = f(2 * i + 1, pi + h / 2.0 * k2);
            let k4 = f(2 * i + 2, pi + h * k3);
            pi += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            if !(pi > 0.0 && pi.is_finite()) {
                return Err(SynthError::Diverged {
                    deg: model.ivc_deg + h * (i + 1) as f64,
                    pressure_pa: pi,
                });
            }
            k1 = f(2 * i + 2, pi);
            p.push(pi);
            dp.push(k1);
        }
        // Simpson on the nodes of the closed part.
        let node = |i: usize| p[i] * self.dv[2 * i];
        let mut closed = node(0) + node(self.n);
        for i in 1..self.n {
            closed += if i % 2 == 1 { 4.0 } else { 2.0 } * node(i);
        }
        closed *= h / 3.0;
        let m = model.cycle_model(q);
        let v_evo = self.v[2 * self.n];
        let sol = CycleSolution {
            cyl: *cyl,
            model: m,
            h,
            p_evo: pi,
            g_evo: g.gamma(pi * v_evo, pv_ivc),
            v_evo,
            v_ivc: self.v[0],
            blowby_fraction: 0.0,
            p,
            dp,
        };
        // Simpson on the open part, EVO to the next IVC.
        let last = self.open.len() - 1;
        let mut open = 0.0;
        for (k, &(deg, dv)) in self.open.iter().enumerate() {
            let w = if k == 0 || k == last {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            open += w * sol.pressure(deg) * dv;
        }
        open *= self.open_h / 3.0;
        Ok((sol, closed + open))
    }
}

/// The cycle of `model` on `cyl` releasing `heat_j`, and its IMEP.
fn solve_at(
    cyl: &Cylinder,
    model: &DesignModel,
    grid: &Grid,
    heat_j: f64,
) -> Result<(Design, f64), SynthError> {
    model.cycle_model(heat_j).check()?;
    let (solution, work) = grid.cycle(cyl, model, heat_j)?;
    let m = *solution.model();
    let imep = work / cyl.swept_volume();
    Ok((
        Design {
            model: m,
            solution,
            heat_released_j: heat_j,
            imep_pa: imep,
            evaluations: 1,
            intake_pressure_pa: model.intake_pressure_pa,
            lambda: model.air.map(|a| {
                let air =
                    a.charge
                        .trapped_air_kg(model.intake_pressure_pa, grid.v[0], a.intake_temp_k);
                a.charge.lambda_of(air, heat_j)
            }),
        },
        imep,
    ))
}

/// Solves the design cycle of `model` on `cyl`. Without
/// [`DesignModel::air`], or for a compression-ignition engine, the load
/// sets the heat released (for an IMEP target a secant on IMEP(Q_f) from
/// the motored cycle and a first guess at 35 % indicated efficiency, to
/// 1e-9 relative; refused at or below the motored cycle's IMEP); the
/// compression-ignition engine's trapped air bounds it (`λ ≥ λ_min`). A
/// spark-ignition engine's load sets its intake pressure instead, the
/// fuel following the air at λ ([`Air`]); a load beyond what the
/// full-load intake pressure gives is refused, naming the most it gives.
pub fn design(cyl: &Cylinder, model: &DesignModel) -> Result<Design, SynthError> {
    let grid = shared_grid(cyl, model)?;
    let grid = grid.as_ref();
    if let Load::Imep { pa } = model.load
        && !(pa.is_finite() && pa > 0.0)
    {
        return Err(SynthError::Parameter {
            name: "imep_bar",
            value: pa / 1e5,
            expected: "above 0".into(),
        });
    }
    match model.air {
        Some(air) if air.charge.kind == ChargeKind::Si => by_throttle(cyl, model, grid, air),
        Some(air) => {
            let d = by_fuel(cyl, model, grid)?;
            within_air(cyl, model, grid, air, d)
        }
        None => by_fuel(cyl, model, grid),
    }
}

/// The heat the trapped air of `model` (at its intake pressure) burns at
/// the richest λ the charge allows (J).
fn air_heat(model: &DesignModel, grid: &Grid, air: Air) -> f64 {
    let m = air
        .charge
        .trapped_air_kg(model.intake_pressure_pa, grid.v[0], air.intake_temp_k);
    air.charge.heat_j(m, air.charge.richest())
}

/// What a load beyond the trapped air is told: the most it gives and the
/// keys that raise it.
fn beyond_air(model: &DesignModel, most_imep_pa: f64, air: Air, asked: &str) -> SynthError {
    let (lambda, raise) = match air.charge.kind {
        ChargeKind::Si => (
            format!("λ {}", air.charge.lambda),
            "raise intake_pressure_bar (a charged engine) or lower lambda",
        ),
        ChargeKind::Ci => (
            format!("λ_min {}", air.charge.lambda_min),
            "raise intake_pressure_bar (the boost) or lower lambda_min",
        ),
    };
    SynthError::Load(format!(
        "{asked}: beyond what the trapped air burns: the air of intake_pressure_bar = {} at intake_temp_k = {} burnt at {lambda} gives at most IMEP {:.2} bar; {raise}",
        model.intake_pressure_pa / 1e5,
        air.intake_temp_k,
        most_imep_pa / 1e5
    ))
}

/// A compression-ignition cycle `d` whose fuel its air must burn: refused
/// when the heat released needs more fuel than `λ_min` allows.
fn within_air(
    cyl: &Cylinder,
    model: &DesignModel,
    grid: &Grid,
    air: Air,
    d: Design,
) -> Result<Design, SynthError> {
    let q_max = air_heat(model, grid, air);
    if d.heat_released_j <= q_max * (1.0 + 1e-9) {
        return Ok(d);
    }
    let (_, most) = solve_at(cyl, model, grid, q_max)?;
    let asked = match model.load {
        Load::Imep { pa } => format!("imep_bar = {}", pa / 1e5),
        Load::Heat { j } => format!("heat_released_j = {j}"),
    };
    Err(beyond_air(model, most, air, &asked))
}

/// A spark-ignition cycle: the intake pressure (the throttle) that meets
/// the load, the fuel following the air at λ. A heat released gives it
/// in closed form; an IMEP target by a secant on IMEP(p_intake) (nearly
/// affine: the closed part scales with p, the pumping loop is affine in
/// it) from the full-load intake pressure, to 1e-9 relative.
fn by_throttle(
    cyl: &Cylinder,
    model: &DesignModel,
    grid: &Grid,
    air: Air,
) -> Result<Design, SynthError> {
    let full = model.intake_pressure_pa;
    let q_full = air_heat(model, grid, air);
    let at = |p: f64| -> Result<(Design, f64), SynthError> {
        let mut m = *model;
        m.intake_pressure_pa = p;
        m.exhaust_pressure_pa = exhaust_pressure_for(p);
        solve_at(cyl, &m, grid, q_full * p / full)
    };
    let target = match model.load {
        Load::Heat { j } => {
            if j > q_full * (1.0 + 1e-9) {
                let (_, most) = at(full)?;
                return Err(beyond_air(
                    model,
                    most,
                    air,
                    &format!("heat_released_j = {j}"),
                ));
            }
            return Ok(at(full * j / q_full)?.0);
        }
        Load::Imep { pa } => pa,
    };
    let (mut best, i_full) = at(full)?;
    if target > i_full * (1.0 + 1e-9) {
        return Err(beyond_air(
            model,
            i_full,
            air,
            &format!("imep_bar = {}", target / 1e5),
        ));
    }
    let f0 = i_full - target;
    if (f0 / target).abs() <= 1e-9 {
        best.evaluations = 1;
        return Ok(best);
    }
    secant(
        target,
        (full, f0),
        full * target / i_full,
        1,
        at,
        (
            "the intake pressure",
            "below what the throttled engine gives at any intake pressure (its pumping loop costs more)",
        ),
    )
}

/// A secant on `IMEP(x) − target` from `(x0, f0)` and the first guess
/// `x1`, to 1e-9 relative, `evaluations` cycles already integrated: the
/// design at the root. `at(x)` integrates the cycle at `x`; `(what,
/// none)` name `x` when it is not found in 40 cycles, and what it means
/// when a step leaves `x > 0`.
fn secant(
    target: f64,
    (mut x0, mut f0): (f64, f64),
    mut x1: f64,
    mut evaluations: usize,
    mut at: impl FnMut(f64) -> Result<(Design, f64), SynthError>,
    (what, none): (&str, &str),
) -> Result<Design, SynthError> {
    loop {
        if !(x1.is_finite() && x1 > 0.0) {
            return Err(SynthError::Load(format!(
                "imep_bar = {}: {none}",
                target / 1e5
            )));
        }
        let (mut d, i1) = at(x1)?;
        evaluations += 1;
        let f1 = i1 - target;
        if (f1 / target).abs() <= 1e-9 {
            d.evaluations = evaluations;
            return Ok(d);
        }
        if evaluations >= 40 || (f1 - f0).abs() <= f64::EPSILON * target {
            return Err(SynthError::Load(format!(
                "imep_bar = {}: {what} was not found (IMEP {} bar after {evaluations} cycles)",
                target / 1e5,
                d.imep_pa / 1e5
            )));
        }
        let x2 = x1 - f1 * (x1 - x0) / (f1 - f0);
        (x0, f0) = (x1, f1);
        x1 = x2;
    }
}

/// The cycle whose heat released meets the load: for an IMEP target, the
/// heat released that meets it (secant on IMEP(Q_f) from the motored cycle
/// and a first guess at 35 % indicated efficiency, to 1e-9 relative;
/// refused when the target is at or below the motored cycle's IMEP).
fn by_fuel(cyl: &Cylinder, model: &DesignModel, grid: &Grid) -> Result<Design, SynthError> {
    let target = match model.load {
        Load::Heat { j } => return Ok(solve_at(cyl, model, grid, j)?.0),
        Load::Imep { pa } => pa,
    };
    let (_, i0) = solve_at(cyl, model, grid, 0.0)?;
    if target <= i0 {
        return Err(SynthError::Load(format!(
            "imep_bar = {}: at or below the motored cycle's {:.4} bar (no heat release gives it)",
            target / 1e5,
            i0 / 1e5
        )));
    }
    secant(
        target,
        (0.0, i0 - target),
        (target - i0) * cyl.swept_volume() / 0.35,
        1,
        |q| solve_at(cyl, model, grid, q),
        ("the heat released", "no positive heat release meets it"),
    )
}

/// The design trace of `model` on `cyl` at `step_deg` (dividing the
/// cycle): `(crank_deg, pressure_pa)` for `crank_deg = k step_deg` in
/// `[0, cycle)` from firing TDC, as [`crate::pressure_trace`] gives a
/// preset's. The lossless design cycle does not depend on the speed.
pub fn design_trace(
    cyl: &Cylinder,
    model: &DesignModel,
    step_deg: f64,
) -> Result<Vec<(f64, f64)>, SynthError> {
    let n = crate::steps_in_cycle(step_deg, model.cycle_deg())?;
    let d = design(cyl, model)?;
    Ok(d.sample(n, step_deg))
}

impl Design {
    /// The solved pressure at `n` angles `k step_deg`.
    pub fn sample(&self, n: usize, step_deg: f64) -> Vec<(f64, f64)> {
        (0..n)
            .map(|k| {
                let deg = k as f64 * step_deg;
                (deg, self.solution.pressure(deg))
            })
            .collect()
    }
}
