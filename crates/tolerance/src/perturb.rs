//! One evaluation of the key results for a set of deviations: the engine
//! rebuilt with the deviations, its diagram moved by the TDC error, and the
//! real pipeline run on both.

use crate::ToleranceError;
use crate::keys::{Input, OUTPUTS, Output, Parameter};
use enginedyn_balance::{CylinderMass, free_forces};
use enginedyn_engine::{Engine, EngineBuilder, RodModel};
use enginedyn_ingest::Resampled;
use enginedyn_kinematics::{CrankSlider, Mechanism, ScotchYoke};
use enginedyn_numerics::{InterpKind, Periodic};
use enginedyn_pipeline::{Options, Scope};
use std::f64::consts::PI;

/// The key results of one evaluation, indexed like [`Output::ALL`]; `None`
/// where a result does not exist (order 0.5 of a two-stroke, the flywheel
/// of a motored engine).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outputs(pub [Option<f64>; OUTPUTS]);

impl Outputs {
    /// One result.
    pub fn get(&self, o: Output) -> Option<f64> {
        self.0[o.index()]
    }
}

/// The geometry of a cylinder with the head fixed: true stroke, smallest
/// and largest volume (m, m³).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Largest minus smallest piston travel (m).
    pub stroke: f64,
    /// Smallest volume, the clearance (m³).
    pub clearance: f64,
    /// Largest volume (m³).
    pub largest: f64,
}

impl Geometry {
    /// Largest over smallest volume.
    pub fn compression_ratio(&self) -> f64 {
        self.largest / self.clearance
    }
}

/// Height of the piston pin (crank-slider) or of the yoke's slot centre
/// above the crank axis at the nominal TDC (m): what a fixed head sees.
fn top(mech: &Mechanism) -> f64 {
    match mech {
        Mechanism::CrankSlider(cs) => cs.y_tdc(),
        Mechanism::ScotchYoke(y) => y.r(),
    }
}

/// The cylinder's geometry from the piston's travel
/// ([`Mechanism::travel`]: a tilted yoke slot lifts the piston above its
/// square-slot TDC and lengthens the stroke).
pub fn geometry(engine: &Engine) -> Geometry {
    let cyl = engine.cylinder();
    let a = cyl.piston_area();
    let vc = cyl.clearance_volume();
    let (x_min, x_max) = engine.mechanism().travel();
    Geometry {
        stroke: x_max - x_min,
        clearance: vc + a * x_min,
        largest: vc + a * x_max,
    }
}

/// Evaluates the key results for any deviations of the inputs, by running
/// the real pipeline ([`enginedyn_pipeline::analyse`]) on the engine
/// rebuilt with them.
///
/// - Geometry (`stroke_mm`, `rod_length_mm`, `pin_offset_mm`, `bore_mm`,
///   the yoke's slot): a new mechanism; the head is fixed, so the
///   clearance becomes `V_c - A_p (y_TDC' - y_TDC)` (PHYSICS.md) and the
///   compression ratio follows. A bore error keeps `V_c` (the chamber is
///   in the head and the piston crown). The diagram stays on its angles:
///   it is the measured input. Those angles count from firing TDC
///   (PHYSICS.md), so a pin offset error moves the crank's TDC angle by
///   `de / (L + R)` and the diagram with it; the Scotch yoke's formula
///   counts from the crank on the axis, so a slot tilt `g` shifts the
///   piston's motion by `-g` under the diagram: to first order a TDC
///   error of `-g`, as seed 004's position error of the piston says.
/// - `tdc_deg` = δ: the diagram's firing TDC really lies δ after the
///   declared one, so the pressure at cycle angle φ is the trace's value
///   at φ + δ (a periodic cubic spline through the gridded trace).
/// - `piston_group_kg` per cylinder: each cylinder gets its own trace.
///   A piston-mass deviation `dm` acts on the piston along its axis
///   exactly as a gas pressure `-dm w² (d²x/dφ²) / A_p` would (the forces
///   crate adds `P_g` and `-m_j a` before anything else, for every rod
///   model), so it enters the pipeline as that pressure; the pipeline then
///   sums the cylinders' own torques and takes the largest pin load of any.
/// - `throw_angle_deg` per throw: the cylinders on throw `k` fire `d_alpha_k`
///   later; the pipeline's summation shifts their torques.
/// - `rod_kg`: every rod, split as the rod model says.
///
/// Free forces and moments come from `enginedyn_balance::free_forces` with
/// each cylinder's own reciprocating mass and its throw's perturbed lag.
#[derive(Debug, Clone)]
pub struct Evaluator {
    engine: Engine,
    inputs: Vec<Input>,
    rpm: f64,
    options: Options,
    rod_model: RodModel,
    /// The traces on the grid (Pa): one for all cylinders, or one each.
    traces: Vec<Vec<f64>>,
    /// Periodic splines of `traces` when the TDC varies.
    splines: Option<Vec<Periodic>>,
    /// One trace per cylinder (the piston masses vary).
    per_cylinder: bool,
    /// The diagram's other fields, handed to the pipeline with each run.
    template: Resampled,
    step: f64,
}

impl Evaluator {
    /// Prepares evaluations of `engine` with `pressure` (on the grid of
    /// `options.step_deg`) at `rpm`, for deviations of `inputs`.
    pub fn new(
        engine: &Engine,
        pressure: &Resampled,
        rpm: f64,
        options: Options,
        inputs: &[Input],
    ) -> Result<Self, ToleranceError> {
        if pressure.quantity != enginedyn_ingest::Quantity::Pressure {
            return Err(ToleranceError::Input(
                "the tolerance study needs a pressure diagram, not a turning moment".into(),
            ));
        }
        // The summary figures and the engine torque are all it reads: no
        // main-bearing loads, no full harmonic table (`run`); the two orders
        // it needs come from the same torque crate.
        let options = Options {
            scope: Scope::Keys,
            ..options
        };
        let rod_model = options.rod_model.unwrap_or(engine.rod_model());
        let engine = engine.with_rod_model(rod_model)?;
        let n = pressure.pressure.len();
        if n < 8 {
            return Err(ToleranceError::Input(
                "the diagram has too few points".into(),
            ));
        }
        let step = engine.cycle() / n as f64;
        let traces = if pressure.cylinders.is_empty() {
            vec![pressure.pressure.clone()]
        } else {
            pressure.cylinders.clone()
        };
        let has = |p: Parameter| inputs.iter().any(|i| i.parameter == p);
        let splines = if has(Parameter::Tdc) {
            let xs: Vec<f64> = (0..n).map(|k| k as f64 * step).collect();
            Some(
                traces
                    .iter()
                    .map(|t| Periodic::new(InterpKind::Spline, &xs, t, engine.cycle()))
                    .collect::<Result<Vec<_>, _>>()?,
            )
        } else {
            None
        };
        let mut template = pressure.clone();
        template.pressure = Vec::new();
        template.cylinders = Vec::new();
        template.stats = Vec::new();
        template.notes = Vec::new();
        Ok(Self {
            engine,
            inputs: inputs.to_vec(),
            rpm,
            options,
            rod_model,
            traces,
            splines,
            per_cylinder: has(Parameter::PistonGroup),
            template,
            step,
        })
    }

    /// The inputs, in the order deviations are given.
    pub fn inputs(&self) -> &[Input] {
        &self.inputs
    }

    /// The nominal engine (with the rod model of the options).
    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    /// The method settings.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// The speed (rpm).
    pub fn rpm(&self) -> f64 {
        self.rpm
    }

    /// The sum of the deviations of a one-value parameter (key unit, 0 when absent).
    fn common(&self, dev: &[f64], p: Parameter) -> f64 {
        self.inputs
            .iter()
            .zip(dev)
            .filter(|(i, _)| i.parameter == p && i.index.is_none())
            .map(|(_, d)| d)
            .sum()
    }

    /// Per-cylinder or per-throw deviations of `p` (key unit), `len` long.
    fn each(&self, dev: &[f64], p: Parameter, len: usize) -> Vec<f64> {
        let mut v = vec![0.0; len];
        for (i, d) in self.inputs.iter().zip(dev) {
            if let (true, Some(k)) = (i.parameter == p, i.index)
                && k < len
            {
                v[k] += d;
            }
        }
        v
    }

    /// The engine with the deviations `dev` (key units, one per input).
    pub fn perturbed_engine(&self, dev: &[f64]) -> Result<Engine, ToleranceError> {
        let e = &self.engine;
        let mm = 1e-3;
        let d_r = 0.5 * self.common(dev, Parameter::Stroke) * mm;
        let tilt = self.common(dev, Parameter::YokeSlotSquareness).to_radians();
        let mech = match e.mechanism() {
            Mechanism::CrankSlider(cs) => Mechanism::CrankSlider(CrankSlider::new(
                cs.r() + d_r,
                cs.l() + self.common(dev, Parameter::RodLength) * mm,
                cs.e() + self.common(dev, Parameter::PinOffset) * mm,
            )?),
            Mechanism::ScotchYoke(y) => Mechanism::ScotchYoke(ScotchYoke::new(y.r() + d_r, tilt)?),
        };
        let cyl = e.cylinder();
        let bore = cyl.bore() + self.common(dev, Parameter::Bore) * mm;
        let area = PI * bore * bore / 4.0;
        // The head is fixed: the piston rises as far as the top moves.
        let clearance = cyl.clearance_volume() - area * (top(&mech) - top(e.mechanism()));
        if !(clearance > 0.0) {
            return Err(ToleranceError::Input(format!(
                "the deviations lift the piston into the head (clearance {clearance:.3e} m³)"
            )));
        }
        let compression_ratio = 1.0 + area * mech.stroke() / clearance;
        let mut masses = *e.masses();
        masses.rod += self.common(dev, Parameter::RodMass);
        let throws = self.each(dev, Parameter::ThrowAngle, e.throws());
        let firing_angles = (0..e.cylinders())
            .map(|i| e.firing_angle(i) + throws[e.throw_of(i)].to_radians())
            .collect();
        Ok(EngineBuilder {
            name: e.name().to_string(),
            stroke: e.stroke_kind(),
            layout: e.layout(),
            cylinders: e.cylinders(),
            firing_order: Some(e.firing_order().to_vec()),
            firing_angles: Some(firing_angles),
            crank_angles: None,
            split_pins: e.split_pins(),
            mechanism: mech,
            bore,
            compression_ratio,
            cylinder_spacing: Some(e.cylinder_spacing()),
            rod_model: e.rod_model(),
            diagram: None,
            rod_cg_from_small_end: Some(masses.rod_cg_from_small_end),
            masses,
            operating: *e.operating(),
            flywheel: *e.flywheel(),
        }
        .build()?)
    }

    /// The traces the pipeline sees for `dev` on `engine` (Pa).
    fn traces(&self, dev: &[f64], engine: &Engine) -> Result<Vec<Vec<f64>>, ToleranceError> {
        let n = self.traces[0].len();
        let tdc = self.common(dev, Parameter::Tdc).to_radians();
        let mut traces = match &self.splines {
            Some(splines) if tdc != 0.0 => splines
                .iter()
                .map(|s| {
                    let mut t = vec![0.0; n];
                    s.eval_uniform(tdc, self.step, &mut t);
                    t
                })
                .collect(),
            _ => self.traces.clone(),
        };
        if self.per_cylinder {
            let z = engine.cylinders();
            if traces.len() == 1 {
                traces = vec![traces[0].clone(); z];
            }
            let dm = self.each(dev, Parameter::PistonGroup, z);
            let mech = engine.mechanism();
            let w = self.rpm * PI / 30.0;
            let per_pa = w * w / engine.cylinder().piston_area();
            let mut kin = enginedyn_kinematics::Table::default();
            mech.fill(self.options.kinematics, 0.0, self.step, n, &mut kin)?;
            for (t, dm) in traces.iter_mut().zip(dm) {
                if dm != 0.0 {
                    for (p, a) in t.iter_mut().zip(&kin.d2x) {
                        *p -= dm * per_pa * a;
                    }
                }
            }
        }
        Ok(traces)
    }

    /// The key results for the deviations `dev` (key units, one per input).
    pub fn evaluate(&self, dev: &[f64]) -> Result<Outputs, ToleranceError> {
        Ok(self.run(dev)?.0)
    }

    /// The nominal results and each result's scale: what its value would be
    /// if nothing cancelled (`z` times a cylinder's harmonic, the free
    /// forces' sum of magnitudes), so that a result that cancels to 0 is
    /// recognised as 0 (and one that is 0 whatever happens, scale 0).
    pub fn nominal(&self) -> Result<(Outputs, [f64; OUTPUTS]), ToleranceError> {
        self.run(&vec![0.0; self.inputs.len()])
    }

    fn run(&self, dev: &[f64]) -> Result<(Outputs, [f64; OUTPUTS]), ToleranceError> {
        if dev.len() != self.inputs.len() {
            return Err(ToleranceError::Input(format!(
                "{} deviations for {} inputs",
                dev.len(),
                self.inputs.len()
            )));
        }
        let engine = self.perturbed_engine(dev)?;
        let traces = self.traces(dev, &engine)?;
        let mut resampled = self.template.clone();
        resampled.pressure = traces[0].clone();
        if traces.len() > 1 || self.per_cylinder {
            resampled.cylinders = traces;
        }
        let a = enginedyn_pipeline::analyse(&engine, &resampled, self.rpm, &self.options)?;
        let s = &a.summary;
        let g = geometry(&engine);
        let omega = self.rpm * PI / 30.0;
        let z = engine.cylinders();
        let dm = self.each(dev, Parameter::PistonGroup, z);
        let mut cyl = CylinderMass::of_engine(&engine, self.rod_model);
        for (c, d) in cyl.iter_mut().zip(&dm) {
            c.reciprocating_mass += d;
        }
        let mech = engine.mechanism();
        let free = free_forces(&cyl, mech.r(), mech.lambda(), omega);
        // Orders 0.5 and 1 of the engine's and cylinder 1's torque, by the
        // torque crate's harmonics, as the pipeline's detailed run gives them.
        let revolutions = engine.cycle() / (2.0 * PI);
        let engine_orders = enginedyn_torque::harmonics(&a.torque.total, revolutions, 1.0)?;
        let cylinder_orders = enginedyn_torque::harmonics(&a.cylinder_torque, revolutions, 1.0)?;
        let harmonic = |of_cylinder: bool, order: f64| {
            let h = if of_cylinder {
                &cylinder_orders
            } else {
                &engine_orders
            };
            h.iter()
                .find(|x| (x.order - order).abs() < 1e-9)
                .map(|x| x.amplitude)
        };
        let mut v = [None; OUTPUTS];
        let mut scale = [0.0; OUTPUTS];
        for o in Output::ALL {
            let (value, gross) = match o {
                Output::MeanTorque => (s.mean_torque_nm, None),
                Output::Imep => (s.imep_bar, None),
                Output::TorqueMax => (s.torque_max_nm, None),
                Output::TorqueMin => (s.torque_min_nm, None),
                Output::ExcessWork => (s.excess_work_j, None),
                Output::RequiredInertia => (s.required_inertia_kg_m2, None),
                Output::CrankpinLoadMax => (s.crankpin_load_max_n, None),
                Output::CompressionRatio => (Some(g.compression_ratio()), None),
                Output::ClearanceVolume => (Some(g.clearance), None),
                Output::Stroke => (Some(g.stroke), None),
                Output::FreeForce1
                | Output::FreeForce2
                | Output::FreeMoment1
                | Output::FreeMoment2 => {
                    let (value, order) = match o {
                        Output::FreeForce1 => (free.free_force_1_n, 1.0),
                        Output::FreeForce2 => (free.free_force_2_n, mech.lambda()),
                        Output::FreeMoment1 => (free.free_moment_1_nm, 1.0),
                        _ => (free.free_moment_2_nm, mech.lambda()),
                    };
                    let arm = |c: &CylinderMass| match o {
                        Output::FreeMoment1 | Output::FreeMoment2 => c.axial_position.abs(),
                        _ => 1.0,
                    };
                    let gross: f64 = cyl
                        .iter()
                        .map(|c| c.reciprocating_mass * arm(c))
                        .sum::<f64>()
                        * mech.r()
                        * omega
                        * omega
                        * order;
                    (Some(value), Some(gross))
                }
                Output::TorqueOrderHalf | Output::TorqueOrder1 => {
                    let order = if o == Output::TorqueOrderHalf {
                        0.5
                    } else {
                        1.0
                    };
                    let engine_h = harmonic(false, order);
                    let gross = harmonic(true, order).map(|c| c * z as f64);
                    (engine_h, gross)
                }
            };
            v[o.index()] = value;
            scale[o.index()] = gross.or(value).map(f64::abs).unwrap_or(0.0);
        }
        Ok((Outputs(v), scale))
    }
}
