//! The crankshaft's torsional vibration from the pipeline (PHYSICS.md,
//! "Torsional vibration"): the chain built from the engine file's
//! `[torsion]` ([`crank_train`]), the excitation split by order from each
//! cylinder's torque ([`excitation`]: gas and inertia parts once, the
//! inertia part per unit ω², so no rerun per speed), and the response over
//! speed ([`study`]).

use crate::{Options, PipelineError, Tables, prepare};
use enginedyn_engine::torsion::{Key, PerItem, TorsionSpec, shaft_stiffness};
use enginedyn_engine::{Engine, EngineError};
use enginedyn_forces::{Setup, cylinder_forces};
use enginedyn_ingest::Resampled;
use enginedyn_numerics::format::{fixed, human, sig};
use enginedyn_torsion::{
    Complex64, CrankTrain, Crossing, Damper, Layout, Modes, Solver, Synthesis, critical_speed_rpm,
    crossings,
};
use std::f64::consts::PI;

/// Why a torsion study cannot run.
#[derive(Debug, thiserror::Error)]
pub enum TorsionStudyError {
    /// A `[torsion]` key is missing or does not fit the engine (exit 2).
    #[error(transparent)]
    Engine(#[from] EngineError),
    /// The operating point cannot be analysed.
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
    /// The chain cannot be built or solved.
    #[error(transparent)]
    Chain(#[from] enginedyn_torsion::TorsionError),
}

/// The crank train as a chain, with what the report needs beside it.
#[derive(Debug, Clone)]
pub struct Train {
    /// The chain's parts.
    pub train: CrankTrain,
    /// Diameter for the shear stress of each section of the layout (m);
    /// `None` where none is known (a load coupling, no diameter given).
    pub diameters: Vec<Option<f64>>,
    /// How each default was taken.
    pub notes: Vec<String>,
    /// Values that look wrong but are computed
    /// ([`TorsionSpec::plausibility_notes`]): each names its key and the
    /// likely mistake.
    pub warnings: Vec<String>,
    /// The key each mass of the chain comes from, in the chain's order
    /// (`torsion.throw_inertia_kg_m2[2]`, or what stood in for it).
    pub mass_keys: Vec<String>,
    /// The key each spring of the chain comes from, in the chain's order.
    pub spring_keys: Vec<String>,
}

fn missing(key: &'static str, why: &'static str) -> EngineError {
    EngineError::Missing { key, why }
}

fn count_error(key: &'static str, got: usize, need: usize, what: &str) -> EngineError {
    EngineError::Invalid {
        key,
        value: format!("{got} values"),
        expected: format!("one value, or {need} ({what})"),
    }
}

/// The chain of `engine` from its `[torsion]`: each default as
/// INTERFACE.md's table gives it, noted. `sized_flywheel` is the sized
/// flywheel's inertia (kg m²), the default of `flywheel_inertia_kg_m2`
/// (with `other_rotating_inertia_kg_m2` added).
pub fn crank_train(
    engine: &Engine,
    spec: &TorsionSpec,
    rod_model: enginedyn_engine::RodModel,
    sized_flywheel: Option<f64>,
) -> Result<Train, TorsionStudyError> {
    let t = engine.throws();
    let mut notes = Vec::new();
    let warnings = spec.plausibility_notes(engine, rod_model);
    let throws = throw_inertias(engine, spec, rod_model, &mut notes)?;
    notes.push(
        "each throw carries the reciprocating mass's mean inertia m_j R² (1/2 + λ²/8): its variation over the cycle (secondary resonances) is neglected".into(),
    );
    let journal_all = journal_stiffnesses(spec, t, &mut notes)?;
    let journals = if t > 1 {
        journal_all.clone()
    } else {
        Vec::new()
    };
    let last_journal = *journal_all.last().unwrap_or(&0.0);
    let flywheel = flywheel_mass(engine, spec, sized_flywheel, last_journal, &mut notes)?;
    let (front, load) = end_masses(spec)?;
    if spec.damping_ratio == 0.0 {
        notes.push(match spec.damper {
            Some(d) if d.damping > 0.0 => "torsion.damping_ratio = 0: only the damper's damping_nm_s_rad damps the chain; a mode that barely moves the damper ring has almost no damping, and the response near its resonances is not trustworthy".into(),
            _ => "torsion.damping_ratio = 0: undamped resonances have no finite amplitude; the response near them is not trustworthy".into(),
        });
    }
    let train = CrankTrain {
        front,
        throws,
        journals,
        flywheel,
        load,
        damper: spec.damper.map(|d| Damper {
            inertia: d.inertia,
            stiffness: d.stiffness,
            damping: d.damping,
        }),
        damping_ratio: spec.damping_ratio,
    };
    let diameters = section_diameters(spec, t, front.is_some(), load.is_some(), &mut notes)?;
    let (mass_keys, spring_keys) = chain_keys(spec, &train);
    Ok(Train {
        train,
        diameters,
        notes,
        warnings,
        mass_keys,
        spring_keys,
    })
}

/// How many journals `torsion`'s per-journal lists hold for `t` throws:
/// one between each two throws, and one for a single throw.
fn journals_needed(t: usize) -> usize {
    t.saturating_sub(1).max(1)
}

/// Each throw's inertia (kg m²): `torsion.throw_inertia_kg_m2`, else
/// estimated from the engine's masses (noted).
fn throw_inertias(
    engine: &Engine,
    spec: &TorsionSpec,
    rod_model: enginedyn_engine::RodModel,
    notes: &mut Vec<String>,
) -> Result<Vec<f64>, EngineError> {
    let t = engine.throws();
    Ok(match &spec.throw_inertia {
        Some(v) => v.expand(t).ok_or_else(|| {
            count_error(
                "torsion.throw_inertia_kg_m2",
                v.values().len(),
                t,
                "one per throw",
            )
        })?,
        None => {
            let est: Vec<f64> = (0..t).map(|k| engine.throw_inertia(k, rod_model)).collect();
            notes.push(format!(
                "torsion.throw_inertia_kg_m2 estimated from the masses: the rotating masses m_r R² plus each cylinder's reciprocating mean m_j R² (1/2 + λ²/8), {} kg m² per throw; the webs and counterweights beyond crank_unbalanced_kg are not in it (a real throw has more): give the throw inertia for a trustworthy frequency",
                human(est.iter().copied().fold(0.0, f64::max))
            ));
            est
        }
    })
}

/// Each journal's stiffness (N m/rad), one per journal between `t` throws
/// (one for a single throw): `torsion.journal_stiffness_nm_rad`, else from
/// the journals' diameters and lengths (noted).
fn journal_stiffnesses(
    spec: &TorsionSpec,
    t: usize,
    notes: &mut Vec<String>,
) -> Result<Vec<f64>, EngineError> {
    let journal_key = "torsion.journal_stiffness_nm_rad";
    let journals_needed = journals_needed(t);
    match (
        &spec.journal_stiffness,
        &spec.journal_diameter,
        &spec.journal_length,
    ) {
        (Some(k), _, _) => k.expand(journals_needed).ok_or_else(|| {
            count_error(
                journal_key,
                k.values().len(),
                journals_needed,
                "one per journal between throws",
            )
        }),
        (None, Some(d), Some(l)) => {
            let k = journal_stiffness_from_geometry(spec, t, d, l)?;
            notes.push(format!(
                "journal stiffness from journal_diameter_mm and journal_length_mm as a plain steel shaft G π d⁴ / (32 l), G = 80.8 GPa: {} N m/rad (webs and pins make a real throw softer)",
                human(k[0])
            ));
            Ok(k)
        }
        _ => Err(missing(
            journal_key,
            "the stiffness between throws, or journal_diameter_mm and journal_length_mm",
        )),
    }
}

/// Each journal's stiffness as a plain steel shaft of diameter `d` and
/// length `l` ([`shaft_stiffness`]), held to the journal stiffness's
/// bounds.
fn journal_stiffness_from_geometry(
    spec: &TorsionSpec,
    t: usize,
    d: &PerItem,
    l: &PerItem,
) -> Result<Vec<f64>, EngineError> {
    let n = journals_needed(t);
    let d = d.expand(n).ok_or_else(|| {
        count_error(
            "torsion.journal_diameter_mm",
            d.values().len(),
            n,
            "one per journal between throws",
        )
    })?;
    let l = l.expand(n).ok_or_else(|| {
        count_error(
            "torsion.journal_length_mm",
            l.values().len(),
            n,
            "one per journal between throws",
        )
    })?;
    // Each diameter and length is within its bounds, but d⁴ / l need
    // not be: the stiffness itself against the journal's bounds.
    d.iter()
        .zip(&l)
        .enumerate()
        .map(|(i, (d, l))| {
            let k = shaft_stiffness(*d, *l);
            Key::JournalStiffness.check(None, k).map_err(|_| {
                let item = |key: Key, v: &PerItem| {
                    key.item(matches!(v, PerItem::Each(_)).then_some(i))
                };
                let (lo, hi) = Key::JournalStiffness.bound().hard;
                EngineError::InvalidItem {
                    key: format!(
                        "{}` and `{}",
                        item(Key::JournalDiameter, spec.journal_diameter.as_ref().unwrap_or(&PerItem::One(0.0))),
                        item(Key::JournalLength, spec.journal_length.as_ref().unwrap_or(&PerItem::One(0.0)))
                    ),
                    value: format!(
                        "{} mm and {} mm, a stiffness G π d⁴ / (32 l) of {} N m/rad",
                        human(d * 1e3),
                        human(l * 1e3),
                        human(k)
                    ),
                    expected: format!(
                        "a stiffness from {} to {} N m/rad, {}'s bounds: beyond, the chain's frequencies overflow or lose all precision",
                        human(lo),
                        human(hi),
                        Key::JournalStiffness.name()
                    ),
                }
            })
        })
        .collect()
}

/// The flywheel's (inertia kg m², stiffness N m/rad): each from
/// `[torsion]`, else the sized flywheel plus the other rotating inertia,
/// and the last journal's stiffness (noted).
fn flywheel_mass(
    engine: &Engine,
    spec: &TorsionSpec,
    sized_flywheel: Option<f64>,
    last_journal: f64,
    notes: &mut Vec<String>,
) -> Result<(f64, f64), EngineError> {
    let flywheel_k = match spec.flywheel_stiffness {
        Some(k) => k,
        None => {
            notes.push(format!(
                "torsion.flywheel_stiffness_nm_rad not given: the journal stiffness, {} N m/rad",
                human(last_journal)
            ));
            last_journal
        }
    };
    let flywheel_j = match (spec.flywheel_inertia, sized_flywheel) {
        (Some(j), _) => j,
        (None, Some(f)) => {
            let j = f + engine.flywheel().other_rotating_inertia;
            notes.push(format!(
                "torsion.flywheel_inertia_kg_m2 not given: the sized flywheel plus other_rotating_inertia_kg_m2, {} kg m²",
                human(j)
            ));
            j
        }
        (None, None) => {
            return Err(missing(
                "torsion.flywheel_inertia_kg_m2",
                "no flywheel was sized (the engine delivers no work): give the flywheel's inertia",
            ));
        }
    };
    if !(flywheel_j > 0.0) {
        return Err(missing(
            "torsion.flywheel_inertia_kg_m2",
            "the sized flywheel is 0 (none needed): give the flywheel's inertia",
        ));
    }
    Ok((flywheel_j, flywheel_k))
}

/// A (inertia, stiffness) at an end of the chain.
type EndMass = Option<(f64, f64)>;

/// The front mass (before throw 1) and the driven load (after the
/// flywheel), each with its spring, where `[torsion]` gives them.
fn end_masses(spec: &TorsionSpec) -> Result<(EndMass, EndMass), EngineError> {
    let front = if spec.front_inertia > 0.0 {
        let k = spec.front_stiffness.ok_or_else(|| {
            missing(
                "torsion.front_stiffness_nm_rad",
                "the spring from the front mass to throw 1",
            )
        })?;
        Some((spec.front_inertia, k))
    } else {
        None
    };
    let load = match (spec.load_inertia, spec.load_stiffness) {
        (Some(j), Some(k)) => Some((j, k)),
        (None, None) => None,
        (Some(_), None) => {
            return Err(missing(
                "torsion.load_stiffness_nm_rad",
                "the coupling's stiffness to the load",
            ));
        }
        (None, Some(_)) => {
            return Err(missing(
                "torsion.load_inertia_kg_m2",
                "the driven load's inertia",
            ));
        }
    };
    Ok((front, load))
}

/// Section diameters for the shear stress: the crankshaft's sections
/// (front, journals, flywheel) from shaft_diameter_mm, else the journal
/// diameter; none for a load coupling (all noted).
fn section_diameters(
    spec: &TorsionSpec,
    t: usize,
    has_front: bool,
    has_load: bool,
    notes: &mut Vec<String>,
) -> Result<Vec<Option<f64>>, EngineError> {
    let journals_needed = journals_needed(t);
    let crank_sections = usize::from(has_front) + t;
    let per_journal = |v: &PerItem, key: &'static str| -> Result<Vec<f64>, EngineError> {
        match v {
            PerItem::One(d) => Ok(vec![*d; crank_sections]),
            PerItem::Each(list) if list.len() == crank_sections => Ok(list.clone()),
            PerItem::Each(list) if list.len() == journals_needed => {
                let mut out = Vec::with_capacity(crank_sections);
                if has_front {
                    out.push(list[0]);
                }
                out.extend(list.iter().take(t - 1));
                out.push(list[list.len() - 1]);
                Ok(out)
            }
            PerItem::Each(list) => Err(count_error(
                key,
                list.len(),
                journals_needed,
                "one per journal, or one per section",
            )),
        }
    };
    let mut diameters: Vec<Option<f64>> = match (&spec.shaft_diameter, &spec.journal_diameter) {
        (Some(d), _) => per_journal(d, "torsion.shaft_diameter_mm")?
            .into_iter()
            .map(Some)
            .collect(),
        (None, Some(d)) => per_journal(d, "torsion.journal_diameter_mm")?
            .into_iter()
            .map(Some)
            .collect(),
        (None, None) => {
            notes.push(
                "no torsion.shaft_diameter_mm or journal_diameter_mm: section stresses are null"
                    .into(),
            );
            vec![None; crank_sections]
        }
    };
    if has_load {
        diameters.push(None);
        notes.push(
            "the load coupling's stress is not computed (null): it is no crankshaft section".into(),
        );
    }
    Ok(diameters)
}

/// The key of each mass and spring of `train`'s chain, in the chain's
/// order ([`CrankTrain::chain`]), with the 1-based index of a list's item;
/// a default names the key that was not given.
fn chain_keys(spec: &TorsionSpec, train: &CrankTrain) -> (Vec<String>, Vec<String>) {
    let each = |v: &Option<PerItem>, i: usize| matches!(v, Some(PerItem::Each(_))).then_some(i);
    let mut masses = Vec::new();
    let mut springs = Vec::new();
    if train.damper.is_some() {
        masses.push(Key::DamperInertia.item(None));
        springs.push(Key::DamperStiffness.item(None));
    }
    if train.front.is_some() {
        masses.push(Key::FrontInertia.item(None));
        springs.push(Key::FrontStiffness.item(None));
    }
    let journal = |i: usize| match (&spec.journal_stiffness, &spec.journal_diameter) {
        (Some(_), _) | (None, None) => Key::JournalStiffness.item(each(&spec.journal_stiffness, i)),
        (None, Some(_)) => format!(
            "{} and {}",
            Key::JournalDiameter.item(each(&spec.journal_diameter, i)),
            Key::JournalLength.item(each(&spec.journal_length, i))
        ),
    };
    let t = train.throws.len();
    for k in 0..t {
        masses.push(if spec.throw_inertia.is_some() {
            Key::ThrowInertia.item(each(&spec.throw_inertia, k))
        } else {
            format!("{} (not given: estimated)", Key::ThrowInertia.item(None))
        });
        if k + 1 < t {
            springs.push(journal(k));
        }
    }
    springs.push(if spec.flywheel_stiffness.is_some() {
        Key::FlywheelStiffness.item(None)
    } else {
        format!(
            "{} (not given: {})",
            Key::FlywheelStiffness.item(None),
            journal(t.saturating_sub(2))
        )
    });
    masses.push(if spec.flywheel_inertia.is_some() {
        Key::FlywheelInertia.item(None)
    } else {
        format!(
            "{} (not given: the sized flywheel)",
            Key::FlywheelInertia.item(None)
        )
    });
    if train.load.is_some() {
        springs.push(Key::LoadStiffness.item(None));
        masses.push(Key::LoadInertia.item(None));
    }
    (masses, springs)
}

/// Each throw's excitation by order, gas and inertia apart.
#[derive(Debug, Clone)]
pub struct Excitation {
    /// Revolutions per cycle (2 four-stroke, 1 two-stroke).
    pub revolutions: f64,
    /// Engine orders (per revolution), 1/revolutions to the highest.
    pub orders: Vec<f64>,
    /// `gas[o][t]`: throw t's gas torque of order o (N m, complex amplitude
    /// against the engine's cycle angle, each cylinder lagging by its
    /// firing angle).
    pub gas: Vec<Vec<Complex64>>,
    /// `inertia[o][t]`: throw t's inertia torque of order o per unit ω²
    /// (N m s²).
    pub inertia: Vec<Vec<Complex64>>,
    /// Firings per revolution, `z / revolutions`: the major orders are its
    /// multiples ([`enginedyn_torsion::is_major_order`]).
    pub firings_per_revolution: f64,
}

impl Excitation {
    /// Throw torques of order index `o` at crank speed `omega` (rad/s).
    pub fn at(&self, o: usize, omega: f64, out: &mut [Complex64]) {
        let w2 = omega * omega;
        for ((x, g), i) in out.iter_mut().zip(&self.gas[o]).zip(&self.inertia[o]) {
            *x = g + i * w2;
        }
    }
}

/// Each cylinder's torque split into orders up to `max_order` with
/// `enginedyn_torque::harmonics`, gas (at the diagram's pressure) and
/// inertia (per unit ω²) apart, summed per throw with the lag `k θ_i` of
/// each cylinder's firing angle.
pub fn excitation(
    engine: &Engine,
    pressure: &Resampled,
    opts: &Options,
    max_order: f64,
) -> Result<Excitation, PipelineError> {
    let n = pressure.pressure.len();
    // Speed 30/π rpm is 1 rad/s: the inertia torque per unit ω².
    let (engine, h, _) = prepare(engine, 30.0 / PI, n, opts)?;
    let tables = Tables::new(&engine, n, opts)?;
    let setup = Setup::new(&engine, engine.rod_model(), 1.0);
    let z = engine.cylinders();
    let traces = crate::cylinder_traces(pressure, z)?;
    let revolutions = engine.cycle() / (2.0 * PI);
    let mut per_trace = Vec::with_capacity(traces.len());
    for p in &traces {
        let f = cylinder_forces(&setup, &tables.kinematics, p, 0.0, h);
        let gas: Vec<f64> = f
            .torque
            .iter()
            .zip(&f.inertia_torque)
            .map(|(m, i)| m - i)
            .collect();
        let g = enginedyn_torque::harmonics(&gas, revolutions, max_order)?;
        let i = enginedyn_torque::harmonics(&f.inertia_torque, revolutions, max_order)?;
        per_trace.push((g, i));
    }
    let orders: Vec<f64> = per_trace[0].0.iter().skip(1).map(|x| x.order).collect();
    let t = engine.throws();
    let mut gas = vec![vec![Complex64::new(0.0, 0.0); t]; orders.len()];
    let mut inertia = gas.clone();
    for c in 0..z {
        let (g, i) = &per_trace[c.min(per_trace.len() - 1)];
        let throw = engine.throw_of(c);
        let theta = engine.firing_angle(c);
        for (o, &k) in orders.iter().enumerate() {
            let lag = Complex64::from_polar(1.0, -k * theta);
            gas[o][throw] += Complex64::from_polar(g[o + 1].amplitude, g[o + 1].phase) * lag;
            inertia[o][throw] += Complex64::from_polar(i[o + 1].amplitude, i[o + 1].phase) * lag;
        }
    }
    Ok(Excitation {
        revolutions,
        orders,
        gas,
        inertia,
        firings_per_revolution: z as f64 / revolutions,
    })
}

/// One speed's response.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Speed (rpm).
    pub rpm: f64,
    /// The free end's vibratory angle, half peak-to-peak of all orders
    /// together (deg), relative to the chain's rigid rotation.
    pub free_end_deg: f64,
    /// Each section's vibratory torque, half peak-to-peak (N m).
    pub section_torque: Vec<f64>,
    /// Each section's shear stress `16 T / (π d³)` (Pa), where a diameter
    /// is known.
    pub section_stress: Vec<Option<f64>>,
    /// The free end's amplitude of each order alone (deg).
    pub order_deg: Vec<f64>,
}

impl Row {
    /// The largest section's vibratory torque: (section index into
    /// [`Layout::sections`], torque in N m); `None` without sections.
    pub fn largest_section(&self) -> Option<(usize, f64)> {
        self.section_torque.iter().copied().enumerate().fold(
            None,
            |best: Option<(usize, f64)>, (i, t)| match best {
                Some((_, b)) if !(t > b) => best,
                _ => Some((i, t)),
            },
        )
    }
}

/// How closely a peak's speed is found (rpm): Brent's method stops within
/// this, well inside the 0.1 rpm INTERFACE.md asks for.
pub const PEAK_TOLERANCE_RPM: f64 = 0.01;

/// A resonance in the speed range: where an engine order's line meets an
/// undamped natural frequency, and that order's response peak near it
/// (the damping, a tuned damper above all, moves the peak off the
/// crossing).
#[derive(Debug, Clone, PartialEq)]
pub struct Resonance {
    /// Engine order.
    pub order: f64,
    /// Mode (1 = the first elastic mode).
    pub mode: usize,
    /// Where the order meets the mode's undamped natural frequency (rpm):
    /// [`enginedyn_torsion::critical_speed_rpm`], `60 f / k`.
    pub crossing_rpm: f64,
    /// Speed of that order's free-end response peak near the crossing
    /// (rpm): climbed to from the crossing over the grid speeds and refined
    /// between them by Brent's method to [`PEAK_TOLERANCE_RPM`]
    /// ([`enginedyn_torsion::climb`]), within the speed range and the
    /// mode's band (up to the geometric means of its natural frequency and
    /// its neighbours', so that two modes never claim one peak). An
    /// undamped chain has no finite peak: the crossing.
    pub rpm: f64,
    /// The free end's amplitude of that order at `rpm` (deg).
    pub amplitude_deg: f64,
    /// The free end's amplitude of that order at the crossing (deg).
    pub crossing_amplitude_deg: f64,
    /// `None` for a peak; else where the order's amplitude still rises:
    /// no peak of this mode in the speed range, and `rpm` is that end.
    pub edge: Option<PeakEdge>,
}

/// Where a resonance's search ended without a peak.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PeakEdge {
    /// The amplitude still rises at an end of the speed range.
    RangeEnd,
    /// The amplitude still rises at the edge of the mode's band (the
    /// geometric mean of its frequency and its neighbour's, as a speed of
    /// the order): it rises towards the neighbouring mode's resonance (a
    /// mode the damper damps out has no peak of its own).
    ModeBand,
}

impl PeakEdge {
    /// As `torsion.json` and the tables write it.
    pub fn name(self) -> &'static str {
        match self {
            Self::RangeEnd => "range end",
            Self::ModeBand => "mode band edge",
        }
    }
}

/// The largest value of a response over the speed range, found between
/// the grid speeds as well as on them.
#[derive(Debug, Clone, PartialEq)]
pub struct Largest {
    /// Speed (rpm).
    pub rpm: f64,
    /// The value (deg for the free end, N m for a section's torque).
    pub value: f64,
    /// For the largest section torque: the section (index into
    /// [`Layout::sections`]).
    pub section: Option<usize>,
    /// Still rising at an end of the speed range.
    pub at_range_end: bool,
}

/// The torsion study over speed.
#[derive(Debug, Clone)]
pub struct Study {
    /// Where each part sits in the chain.
    pub layout: Layout,
    /// Inertias (kg m²) and stiffnesses (N m/rad) of the chain.
    pub inertia: Vec<f64>,
    /// Spring stiffnesses (N m/rad).
    pub stiffness: Vec<f64>,
    /// Modes of the undamped chain, mass-normalised; `modes.csv` divides
    /// each by its value at [`Layout::free_end`] (the front mass, else
    /// throw 1), so the free end reads 1.
    pub modes: Modes,
    /// Engine orders.
    pub orders: Vec<f64>,
    /// Firings per revolution (`z / 2` four-stroke, `z` two-stroke): the
    /// major orders are its multiples.
    pub firings_per_revolution: f64,
    /// One row per speed.
    pub rows: Vec<Row>,
    /// Resonances in the speed range, the largest peak amplitude first
    /// (ties by crossing speed).
    pub resonances: Vec<Resonance>,
    /// The free end's largest vibratory angle (all orders, deg) over the
    /// speed range; `None` without speeds.
    pub max_free_end: Option<Largest>,
    /// The largest section torque (N m) over the speed range and its
    /// section; `None` without speeds or sections.
    pub max_section_torque: Option<Largest>,
    /// Stability notes (modes beyond the orders computed, …) and what the
    /// peak search found (resonances with no peak inside the range).
    pub notes: Vec<String>,
}

/// The free end's vibratory angle (relative to the rigid rotation `Σ J θ / Σ J`).
fn vibratory(theta: &[Complex64], inertia: &[f64], total: f64, at: usize) -> Complex64 {
    let mean: Complex64 = theta
        .iter()
        .zip(inertia)
        .map(|(a, j)| a * *j)
        .sum::<Complex64>()
        / total;
    theta[at] - mean
}

/// Refuses a chain whose natural frequencies in reach of the orders at
/// `rpms` cannot be resolved: every `ω_n²` is known to about `n ε` times
/// the largest ([`enginedyn_torsion::Chain::frequency_floor`]), so a mass
/// that alone rings at an absurd frequency (an inertia of 1e-12 kg m² on
/// a crankshaft's springs) leaves the low modes with no good digits. The
/// error names that mass's key and its springs'.
fn resolvable(
    train: &Train,
    chain: &enginedyn_torsion::Chain,
    modes: &Modes,
    excitation: &Excitation,
    rpms: &[f64],
) -> Result<(), EngineError> {
    // Below this ω² a mode has fewer than six good digits.
    let fuzzy = 1e6 * chain.frequency_floor();
    let slowest = rpms.iter().copied().fold(f64::INFINITY, f64::min);
    let lowest = excitation.orders.first().copied().unwrap_or(0.0) * slowest * PI / 30.0;
    if !(lowest * lowest <= fuzzy) {
        return Ok(());
    }
    let Some(m) = (1..modes.len()).find(|&m| modes.omega[m].powi(2) < fuzzy) else {
        return Ok(());
    };
    let (i, ratio) = chain.stiffest_mass();
    let hz = |w2: f64| human(w2.max(0.0).sqrt() / (2.0 * PI));
    let mut springs: Vec<&str> = [i.checked_sub(1), Some(i)]
        .into_iter()
        .flatten()
        .filter_map(|s| train.spring_keys.get(s).map(String::as_str))
        .collect();
    springs.dedup();
    Err(EngineError::InvalidItem {
        key: train
            .mass_keys
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("mass {}", i + 1)),
        value: format!("{} kg m²", human(chain.inertia()[i])),
        expected: format!(
            "on its springs ({}) this mass alone rings at {} Hz, so the chain's natural frequencies below about {} Hz cannot be resolved in double precision, and mode {m} (about {} Hz) is among them, in reach of the orders from {} Hz at these speeds: check the units of these keys",
            springs.join(", "),
            hz(ratio),
            hz(fuzzy),
            hz(modes.omega[m].powi(2)),
            hz(lowest * lowest)
        ),
    })
}

/// The response of the chain to the excitation at any speed: one order's
/// free-end amplitude, or a whole [`Row`].
struct Response<'a> {
    solver: Solver,
    excitation: &'a Excitation,
    layout: &'a Layout,
    diameters: &'a [Option<f64>],
    inertia: Vec<f64>,
    stiffness: Vec<f64>,
    total: f64,
    harmonics: Vec<usize>,
    synth: Synthesis,
    scratch: Vec<f64>,
    throw_t: Vec<Complex64>,
    torque: Vec<Complex64>,
}

impl Response<'_> {
    /// The chain's angles under order index `o` at crank speed `omega`.
    fn theta(
        &mut self,
        o: usize,
        omega: f64,
    ) -> Result<Vec<Complex64>, enginedyn_torsion::TorsionError> {
        self.excitation.at(o, omega, &mut self.throw_t);
        self.torque
            .iter_mut()
            .for_each(|x| *x = Complex64::new(0.0, 0.0));
        for (t, &i) in self.layout.throws.iter().enumerate() {
            self.torque[i] = self.throw_t[t];
        }
        self.solver
            .respond(self.excitation.orders[o] * omega, &self.torque)
    }

    /// The free end's amplitude of order index `o` alone at `rpm` (deg).
    fn order_deg(&mut self, o: usize, rpm: f64) -> Result<f64, enginedyn_torsion::TorsionError> {
        let th = self.theta(o, rpm * PI / 30.0)?;
        Ok(
            vibratory(&th, &self.inertia, self.total, self.layout.free_end)
                .norm()
                .to_degrees(),
        )
    }

    /// Every order at `rpm`, summed in time.
    fn row(&mut self, rpm: f64) -> Result<Row, enginedyn_torsion::TorsionError> {
        let omega = rpm * PI / 30.0;
        let orders = self.excitation.orders.len();
        let mut responses = Vec::with_capacity(orders);
        for o in 0..orders {
            responses.push(self.theta(o, omega)?);
        }
        let free: Vec<(usize, Complex64)> = responses
            .iter()
            .zip(&self.harmonics)
            .map(|(th, &h)| {
                (
                    h,
                    vibratory(th, &self.inertia, self.total, self.layout.free_end),
                )
            })
            .collect();
        let order_deg = free.iter().map(|(_, x)| x.norm().to_degrees()).collect();
        let free_end_deg = self
            .synth
            .half_peak_to_peak(&free, &mut self.scratch)
            .to_degrees();
        let sections = &self.layout.sections;
        let mut section_torque = Vec::with_capacity(sections.len());
        let mut section_stress = Vec::with_capacity(sections.len());
        let mut terms = Vec::with_capacity(free.len());
        for (s, sec) in sections.iter().enumerate() {
            let j = sec.spring;
            terms.clear();
            terms.extend(
                responses
                    .iter()
                    .zip(&self.harmonics)
                    .map(|(th, &h)| (h, (th[j] - th[j + 1]) * self.stiffness[j])),
            );
            let tq = self.synth.half_peak_to_peak(&terms, &mut self.scratch);
            section_torque.push(tq);
            section_stress.push(
                self.diameters
                    .get(s)
                    .copied()
                    .flatten()
                    .map(|d| 16.0 * tq / (PI * d * d * d)),
            );
        }
        Ok(Row {
            rpm,
            free_end_deg,
            section_torque,
            section_stress,
            order_deg,
        })
    }
}

/// Samples `(rpm, value)` sorted by speed, one per speed (the first given
/// of equal speeds kept).
fn sorted(mut samples: Vec<(f64, f64)>) -> (Vec<f64>, Vec<f64>) {
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    samples.dedup_by(|b, a| a.0.to_bits() == b.0.to_bits());
    samples.into_iter().unzip()
}

/// The largest of `value` over `rows` and the extra rows at `extra`,
/// refined between its neighbours by [`enginedyn_torsion::climb`] on
/// `value` of a whole row.
fn largest(
    response: &mut Response<'_>,
    rows: &[Row],
    extra: &[Row],
    value: impl Fn(&Row) -> Option<f64>,
) -> Result<Option<(f64, f64, bool)>, enginedyn_torsion::TorsionError> {
    let (xs, ys) = sorted(
        rows.iter()
            .chain(extra)
            .filter_map(|r| value(r).map(|v| (r.rpm, v)))
            .collect(),
    );
    if xs.is_empty() {
        return Ok(None);
    }
    let best = enginedyn_numerics::scan::arg_min_max(&ys).1;
    let p = enginedyn_torsion::climb(
        &xs,
        &ys,
        best,
        |rpm| Ok(value(&response.row(rpm)?).unwrap_or(f64::NEG_INFINITY)),
        PEAK_TOLERANCE_RPM,
    )?;
    Ok(Some((p.x, p.y, p.at_end)))
}

/// The response of `train` to `excitation` at each speed of `rpms`.
pub fn study(
    train: &Train,
    excitation: &Excitation,
    rpms: &[f64],
) -> Result<Study, TorsionStudyError> {
    let (chain, layout) = train.train.chain()?;
    let solver = Solver::new(&chain)?;
    resolvable(train, &chain, solver.modes(), excitation, rpms)?;
    let inertia = chain.inertia().to_vec();
    let stiffness = chain.stiffness().to_vec();
    let total: f64 = inertia.iter().sum();
    let n = chain.len();
    let revs = excitation.revolutions;
    let harmonics: Vec<usize> = excitation
        .orders
        .iter()
        .map(|&k| (k * revs).round() as usize)
        .collect();
    let max_h = harmonics.last().copied().unwrap_or(1);
    let modes = solver.modes().clone();
    let mut response = Response {
        solver,
        excitation,
        layout: &layout,
        diameters: &train.diameters,
        inertia: inertia.clone(),
        stiffness: stiffness.clone(),
        total,
        harmonics,
        synth: Synthesis::new(max_h),
        scratch: Vec::new(),
        throw_t: vec![Complex64::new(0.0, 0.0); layout.throws.len()],
        torque: vec![Complex64::new(0.0, 0.0); n],
    };
    let mut rows = Vec::with_capacity(rpms.len());
    for &rpm in rpms {
        rows.push(response.row(rpm)?);
    }
    let range = rpms
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| {
            (a.min(r), b.max(r))
        });
    let mut notes = Vec::new();
    let top = excitation.orders.last().copied().unwrap_or(0.0);
    // Mode 0 (the rigid rotation, 0 Hz) meets no order.
    let freqs: Vec<f64> = (0..modes.len()).map(|m| modes.frequency_hz(m)).collect();
    let found = crossings(&freqs, &excitation.orders, range.0, range.1);
    let resonances = resonances(
        &mut response,
        &found,
        &rows,
        &freqs,
        range,
        chain.is_damped(),
    )?;
    // The largest free-end angle and section torque: on the grid, at every
    // resonance's peak, and refined between.
    let mut peaks: Vec<f64> = resonances.iter().map(|r| r.rpm).collect();
    peaks.sort_by(f64::total_cmp);
    peaks.dedup_by(|b, a| (*b - *a).abs() < PEAK_TOLERANCE_RPM);
    let mut extra = Vec::with_capacity(peaks.len());
    for &rpm in &peaks {
        extra.push(response.row(rpm)?);
    }
    let max_free_end = largest(&mut response, &rows, &extra, |r| Some(r.free_end_deg))?.map(
        |(rpm, value, at_range_end)| Largest {
            rpm,
            value,
            section: None,
            at_range_end,
        },
    );
    let max_section_torque = largest_section_torque(&mut response, &rows, &extra)?;
    notes.extend(peak_edge_notes(&resonances));
    notes.extend(orders_beyond_note(&freqs, range.0, top));
    drop(response);
    Ok(Study {
        layout,
        inertia,
        stiffness,
        modes,
        orders: excitation.orders.clone(),
        firings_per_revolution: excitation.firings_per_revolution,
        rows,
        resonances,
        max_free_end,
        max_section_torque,
        notes,
    })
}

/// Each crossing in `found` as a [`Resonance`], largest amplitude first:
/// with `damped`, its peak climbed to within the mode's band of the speed
/// `range` (lo, hi rpm); undamped, the crossing itself (no finite peak).
/// `rows` are the grid's rows, `freqs` the modes' frequencies (Hz).
fn resonances(
    response: &mut Response<'_>,
    found: &[Crossing],
    rows: &[Row],
    freqs: &[f64],
    range: (f64, f64),
    damped: bool,
) -> Result<Vec<Resonance>, enginedyn_torsion::TorsionError> {
    // Each crossing's own amplitude: a sample of its order's curve beside
    // the grid speeds (a sharp peak near it is then never missed).
    let mut at_crossing = Vec::with_capacity(found.len());
    for c in found {
        at_crossing.push(response.order_deg(c.order, c.rpm)?);
    }
    let mut resonances = Vec::with_capacity(found.len());
    for (i, c) in found.iter().enumerate() {
        let k = response.excitation.orders[c.order];
        let band = mode_band(freqs, c.mode, k, range);
        let (rpm, amplitude_deg, edge) = if damped {
            let samples = band_samples(response, i, band, found, &at_crossing, rows, range)?;
            climb_in_band(response, c, samples, range)?
        } else {
            // No damping: no finite peak; the crossing, as the note says.
            (c.rpm, at_crossing[i], None)
        };
        resonances.push(Resonance {
            order: k,
            mode: c.mode,
            crossing_rpm: c.rpm,
            rpm,
            amplitude_deg,
            crossing_amplitude_deg: at_crossing[i],
            edge,
        });
    }
    resonances.sort_by(|a, b| {
        b.amplitude_deg
            .total_cmp(&a.amplitude_deg)
            .then(a.crossing_rpm.total_cmp(&b.crossing_rpm))
    });
    Ok(resonances)
}

/// Mode `m`'s band as speeds (rpm) of order `k`: up to the geometric means
/// with its neighbours' frequencies `freqs`, inside the speed `range`.
fn mode_band(freqs: &[f64], m: usize, k: f64, (lo, hi): (f64, f64)) -> (f64, f64) {
    let below = if m > 1 {
        (freqs[m - 1] * freqs[m]).sqrt()
    } else {
        0.0
    };
    let above = freqs
        .get(m + 1)
        .map_or(f64::INFINITY, |f| (freqs[m] * f).sqrt());
    (
        critical_speed_rpm(below, k).max(lo),
        critical_speed_rpm(above, k).min(hi),
    )
}

/// What is known of crossing `i`'s order curve in its mode's `band`,
/// `(rpm, deg)` sorted by speed: the crossing, the band's ends inside the
/// speed `range`, the other crossings of the order and the grid's rows.
fn band_samples(
    response: &mut Response<'_>,
    i: usize,
    band: (f64, f64),
    found: &[Crossing],
    at_crossing: &[f64],
    rows: &[Row],
    (lo, hi): (f64, f64),
) -> Result<(Vec<f64>, Vec<f64>), enginedyn_torsion::TorsionError> {
    let c = &found[i];
    let o = c.order;
    let inside = |x: f64| x >= band.0 && x <= band.1;
    let mut samples: Vec<(f64, f64)> = vec![(c.rpm, at_crossing[i])];
    for e in [band.0, band.1] {
        if e > lo && e < hi {
            samples.push((e, response.order_deg(o, e)?));
        }
    }
    samples.extend(
        found
            .iter()
            .zip(at_crossing)
            .filter(|(d, _)| d.order == o && inside(d.rpm))
            .map(|(d, &a)| (d.rpm, a)),
    );
    samples.extend(
        rows.iter()
            .filter(|r| inside(r.rpm))
            .map(|r| (r.rpm, r.order_deg[o])),
    );
    Ok(sorted(samples))
}

/// The peak of crossing `c`'s order curve climbed from the crossing over
/// `samples` (speeds, values): its speed, amplitude and, where it is at an
/// end, which end (of the speed `range`, or of the mode's band).
fn climb_in_band(
    response: &mut Response<'_>,
    c: &Crossing,
    (xs, ys): (Vec<f64>, Vec<f64>),
    (lo, hi): (f64, f64),
) -> Result<(f64, f64, Option<PeakEdge>), enginedyn_torsion::TorsionError> {
    let o = c.order;
    let start = xs.partition_point(|&x| x < c.rpm);
    let p = enginedyn_torsion::climb(
        &xs,
        &ys,
        start,
        |rpm| response.order_deg(o, rpm),
        PEAK_TOLERANCE_RPM,
    )?;
    let near = |e: f64| (p.x - e).abs() <= 2.0 * PEAK_TOLERANCE_RPM + 1e-9 * e.abs();
    let edge = if !p.at_end {
        None
    } else if near(lo) || near(hi) {
        Some(PeakEdge::RangeEnd)
    } else {
        Some(PeakEdge::ModeBand)
    };
    Ok((p.x, p.y, edge))
}

/// The largest section torque over `rows` and `extra`, refined between
/// ([`largest`]), with the section it is in.
fn largest_section_torque(
    response: &mut Response<'_>,
    rows: &[Row],
    extra: &[Row],
) -> Result<Option<Largest>, enginedyn_torsion::TorsionError> {
    Ok(
        match largest(response, rows, extra, |r| r.largest_section().map(|s| s.1))? {
            Some((rpm, _, at_range_end)) => {
                let row = response.row(rpm)?;
                row.largest_section().map(|(s, value)| Largest {
                    rpm,
                    value,
                    section: Some(s),
                    at_range_end,
                })
            }
            None => None,
        },
    )
}

/// One note for each kind of [`PeakEdge`] among `resonances`: which have
/// no peak near their crossing, and why.
fn peak_edge_notes(resonances: &[Resonance]) -> Vec<String> {
    let mut notes = Vec::new();
    for edge in [PeakEdge::RangeEnd, PeakEdge::ModeBand] {
        let ends: Vec<&Resonance> = resonances.iter().filter(|r| r.edge == Some(edge)).collect();
        if ends.is_empty() {
            continue;
        }
        let shown = 6;
        let mut list: Vec<String> = ends
            .iter()
            .take(shown)
            .map(|r| {
                format!(
                    "{} × mode {} (crossing {} rpm; {} deg at {} rpm)",
                    human(r.order),
                    r.mode,
                    fixed(r.crossing_rpm, 0),
                    sig(r.amplitude_deg, 3),
                    fixed(r.rpm, 0)
                )
            })
            .collect();
        if ends.len() > shown {
            list.push(format!("{} smaller", ends.len() - shown));
        }
        let why = match edge {
            PeakEdge::RangeEnd => {
                "the order's free-end amplitude still rises at the speed range's end, whose value is reported"
            }
            PeakEdge::ModeBand => {
                "the order's free-end amplitude still rises where the mode's band meets the next mode's (the geometric mean of their frequencies), towards the next mode's resonance: a mode the damping smooths out has no peak of its own; the band edge's value is reported"
            }
        };
        notes.push(format!(
            "{} of {} resonances have no peak near their crossing ({why}): {}",
            ends.len(),
            resonances.len(),
            list.join(", ")
        ));
    }
    notes
}

/// The note on modes (frequencies `freqs`, Hz) that orders above the
/// highest computed, `top`, meet in the speed range from `lo` rpm; said
/// once, with the modes it concerns.
fn orders_beyond_note(freqs: &[f64], lo: f64, top: f64) -> Option<String> {
    let beyond: Vec<(usize, f64)> = (1..freqs.len())
        .map(|m| (m, freqs[m]))
        .filter(|&(_, f)| lo > 0.0 && critical_speed_rpm(f, top) > lo)
        .collect();
    let (Some(&(m0, f0)), Some(&(m1, f1))) = (beyond.first(), beyond.last()) else {
        return None;
    };
    let which = if m0 == m1 {
        format!("mode {m0} ({} Hz) meets", human(f0))
    } else {
        format!(
            "{} modes, {m0} to {m1} ({} to {} Hz), meet",
            beyond.len(),
            human(f0),
            human(f1)
        )
    };
    Some(format!(
        "{which} orders above {} in the speed range: those orders are not computed, so their resonances there are missing",
        human(top)
    ))
}
