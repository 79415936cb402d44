//! Main-journal torques of one firing order, by the torque crate's summation
//! of the engine's own cylinder torque.

use crate::BalanceError;
use enginedyn_engine::{Engine, EngineBuilder};

/// The main-journal figures of one firing order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JournalCriteria {
    /// Largest torque magnitude on any main journal over the cycle (N m).
    pub max_torque_nm: f64,
    /// The journal that carries it (1-based, the journal after throw K).
    pub max_torque_journal: usize,
    /// Largest harmonic amplitude (order > 0) of any journal's torque (N m).
    pub max_harmonic_nm: f64,
    /// Its engine order.
    pub harmonic_order: f64,
    /// The journal whose harmonic it is (1-based).
    pub harmonic_journal: usize,
    /// Largest engine torque magnitude (the last journal) (N m): the same for
    /// every even firing order, the yardstick of the score.
    pub engine_torque_max_nm: f64,
    /// Largest harmonic (order > 0) of the engine torque (N m).
    pub engine_harmonic_max_nm: f64,
}

/// Highest engine order searched for the largest journal harmonic (as in
/// `harmonics.csv`).
pub const MAX_HARMONIC_ORDER: f64 = 24.0;

/// Sampling of the journal torques for their harmonics (deg).
pub const HARMONIC_SAMPLE_DEG: f64 = 1.0;

/// The engine `engine` with another crank (throw lags, deg: one per throw,
/// or for a vee with split pins one per cylinder) and firing
/// order, firing angles derived by the engine crate (each cylinder at the
/// first angle its throw allows after the one before it: for an order from
/// [`crate::firing_orders`] that is the even firing).
pub fn engine_with(
    engine: &Engine,
    crank_deg: &[f64],
    order: &[usize],
) -> Result<Engine, BalanceError> {
    let cyl = engine.cylinder();
    EngineBuilder {
        name: engine.name().to_string(),
        stroke: engine.stroke_kind(),
        layout: engine.layout(),
        cylinders: engine.cylinders(),
        firing_order: Some(order.to_vec()),
        firing_angles: None,
        crank_angles: Some(crank_deg.iter().map(|a| a.to_radians()).collect()),
        split_pins: crate::crank::is_split(engine.layout(), engine.throws(), crank_deg),
        mechanism: *engine.mechanism(),
        bore: cyl.bore(),
        compression_ratio: cyl.compression_ratio(),
        cylinder_spacing: Some(engine.cylinder_spacing()),
        rod_model: engine.rod_model(),
        diagram: engine.diagram().map(std::path::Path::to_path_buf),
        masses: *engine.masses(),
        rod_cg_from_small_end: Some(engine.masses().rod_cg_from_small_end),
        operating: *engine.operating(),
        flywheel: *engine.flywheel(),
    }
    .build()
    .map_err(BalanceError::Engine)
}

/// Journal torques of `engine` (already carrying the crank and firing order
/// to judge) from one cylinder's torque `cylinder_torque` over its own cycle
/// angle on a grid of `step` rad: summed by [`enginedyn_torque::sum`] on the
/// full grid (the largest torque), harmonics by
/// [`enginedyn_torque::harmonics`] up to order [`MAX_HARMONIC_ORDER`] of the
/// journal torques taken every [`HARMONIC_SAMPLE_DEG`] (every grid point
/// when the grid is coarser). That keeps `--all-cranks` fast; only orders
/// above `360/HARMONIC_SAMPLE_DEG - 24` fold onto the orders searched, and a
/// torque curve has nothing there worth counting.
pub fn journal_criteria(
    engine: &Engine,
    step: f64,
    cylinder_torque: &[f64],
) -> Result<JournalCriteria, BalanceError> {
    let t = enginedyn_torque::sum(engine, step, |_| cylinder_torque, true);
    let revolutions = engine.cycle() / std::f64::consts::TAU;
    let mut c = JournalCriteria {
        max_torque_nm: 0.0,
        max_torque_journal: 1,
        max_harmonic_nm: 0.0,
        harmonic_order: 0.0,
        harmonic_journal: 1,
        engine_torque_max_nm: 0.0,
        engine_harmonic_max_nm: 0.0,
    };
    let last = t.journals.len().saturating_sub(1);
    let n = cylinder_torque.len();
    let mut stride = ((HARMONIC_SAMPLE_DEG.to_radians() / step).floor() as usize).max(1);
    while !n.is_multiple_of(stride) {
        stride -= 1;
    }
    let mut sampled = Vec::with_capacity(n / stride);
    for (k, j) in t.journals.iter().enumerate() {
        let peak = j.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if peak > c.max_torque_nm {
            c.max_torque_nm = peak;
            c.max_torque_journal = k + 1;
        }
        sampled.clear();
        sampled.extend(j.iter().step_by(stride));
        let h = enginedyn_torque::harmonics(&sampled, revolutions, MAX_HARMONIC_ORDER)?;
        let top = h.iter().filter(|h| h.order > 0.0).fold(
            None::<&enginedyn_torque::Harmonic>,
            |best, h| match best {
                Some(b) if b.amplitude >= h.amplitude => Some(b),
                _ => Some(h),
            },
        );
        if let Some(top) = top {
            if top.amplitude > c.max_harmonic_nm {
                c.max_harmonic_nm = top.amplitude;
                c.harmonic_order = top.order;
                c.harmonic_journal = k + 1;
            }
            if k == last {
                c.engine_harmonic_max_nm = top.amplitude;
            }
        }
        if k == last {
            c.engine_torque_max_nm = peak;
        }
    }
    Ok(c)
}
