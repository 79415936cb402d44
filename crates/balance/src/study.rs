//! One crank or every crank: orders, criteria, scores, ranked.

use crate::BalanceError;
use crate::crank::{
    CrankSet, Train, canonical_deg, crank_arrangements, grid_unit, is_mirror_symmetric, pin_deg,
};
use crate::free::{CylinderMass, FreeForces, free_forces};
use crate::journal::{JournalCriteria, engine_with, journal_criteria};
use crate::order::{FiringOrder, OrderCriteria, criteria, firing_orders};
use crate::score::{Terms, Weights};
use enginedyn_engine::{Engine, EngineError, RodModel};
use rayon::prelude::*;

/// Most firing orders (over all cranks) carried through to the journal
/// torques with `--all-cranks`: beyond it only the best cranks by the
/// diagram-free score whose orders fit are kept (at least one crank).
pub const MAX_RANKED_ORDERS: usize = 2048;

/// One cylinder's torque over its own cycle angle on a uniform grid.
#[derive(Debug, Clone, Copy)]
pub struct CylinderTorque<'a> {
    /// Grid step (rad).
    pub step: f64,
    /// Torque (N m), one value per grid point over the cycle.
    pub torque: &'a [f64],
}

/// What a study needs.
#[derive(Debug, Clone, Copy)]
pub struct Setup<'a> {
    /// The engine: layout, masses, geometry, and its own crank.
    pub engine: &'a Engine,
    /// Rod model for the reciprocating mass.
    pub rod_model: RodModel,
    /// Speed (rad/s) for the free forces.
    pub omega: f64,
    /// Cylinder torque from the diagram; `None`: journal criteria not computed.
    pub torque: Option<CylinderTorque<'a>>,
    /// Score weights.
    pub weights: Weights,
}

/// One firing order with its criteria and score.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderStudy {
    /// The order and its firing angles.
    pub order: FiringOrder,
    /// Diagram-free criteria.
    pub criteria: OrderCriteria,
    /// Journal torques (with a diagram).
    pub journal: Option<JournalCriteria>,
    /// The score's terms.
    pub terms: Terms,
    /// The weighted score (lower is better).
    pub score: f64,
}

/// One crank with its orders, best first.
#[derive(Debug, Clone, PartialEq)]
pub struct CrankStudy {
    /// Throw lags (deg), throw 1 at 0.
    pub crank_angles_deg: Vec<f64>,
    /// Throw k and throw n + 1 - k at the same angle.
    pub mirror_symmetric: bool,
    /// This is the engine's own crank (up to equivalence).
    pub engine_crank: bool,
    /// Free forces and moments (the same for every order of the crank).
    pub free: FreeForces,
    /// Its even firing orders, best first.
    pub orders: Vec<OrderStudy>,
}

impl CrankStudy {
    /// The best order's score (infinite without orders).
    pub fn best_score(&self) -> f64 {
        self.orders.first().map_or(f64::INFINITY, |o| o.score)
    }
}

/// The result: cranks best first (one unless `--all-cranks`), and notes.
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// Cranks, best first.
    pub cranks: Vec<CrankStudy>,
    /// Which cranks were searched.
    pub set: CrankSet,
    /// What the reader should know (restrictions, missing data).
    pub notes: Vec<String>,
}

/// The cylinders of `engine` on another crank (throw lags, deg: one per
/// throw, or for a vee with split pins one per cylinder), with PHYSICS.md's
/// axial positions about the engine's middle.
pub fn cylinders_on(engine: &Engine, rod_model: RodModel, crank_deg: &[f64]) -> Vec<CylinderMass> {
    CylinderMass::of_engine(engine, rod_model)
        .into_iter()
        .enumerate()
        .map(|(i, c)| CylinderMass {
            throw_angle: pin_deg(crank_deg, engine.throws(), engine.throw_of(i), i).to_radians(),
            ..c
        })
        .collect()
}

/// Studies the engine's own crank, or with `all_cranks` every crank
/// arrangement for its layout and cylinder count (see
/// [`crate::crank_arrangements`]).
pub fn study(setup: &Setup, all_cranks: bool) -> Result<Study, BalanceError> {
    let engine = setup.engine;
    let train = Train::of_engine(engine);
    let own = own_crank(engine);
    let mut notes = Vec::new();
    let (cranks, set) = if all_cranks {
        every_crank(&train, &mut notes)?
    } else {
        match &own {
            Some(own) => (vec![own.clone()], CrankSet::All),
            None => {
                return Err(BalanceError::Engine(EngineError::Missing {
                    key: "firing_order",
                    why: "required to study the engine's own crank; --all-cranks runs without it",
                }));
            }
        }
    };
    let mut studies = diagram_free(setup, &train, own.as_deref(), cranks, all_cranks)?;
    if !all_cranks && studies.first().is_some_and(|c| c.orders.is_empty()) {
        notes.push(format!(
            "the crank {:?} admits no even firing order (every {}°)",
            own.as_deref().unwrap_or_default(),
            enginedyn_numerics::format::human(train.interval_deg())
        ));
    }
    keep_best(&mut studies, &mut notes);
    match setup.torque {
        Some(t) => add_journals(setup, t, &mut studies)?,
        None => notes.push(
            "no indicator diagram: the main-journal torques are null and take no part in the score"
                .to_string(),
        ),
    }
    sort(&mut studies);
    Ok(Study {
        cranks: studies,
        set,
        notes,
    })
}

/// The engine's own crank (throw lags, deg), `None` for an engine without
/// a firing order of its own. Degrees to 1e-9, so that 240° reads 240 and
/// not 239.99999999999997.
fn own_crank(engine: &Engine) -> Option<Vec<f64>> {
    engine.firing_order_given().then(|| {
        engine
            .crank_angles()
            .iter()
            .map(|a| (a.to_degrees() * 1e9).round() / 1e9)
            .collect()
    })
}

/// Every crank arrangement of `train` (`--all-cranks`) and which set they
/// are, with notes: only the mirror-symmetric ones past the enumeration
/// limit; split crank pins when no shared-pin crank fires evenly.
fn every_crank(
    train: &Train,
    notes: &mut Vec<String>,
) -> Result<(Vec<Vec<f64>>, CrankSet), BalanceError> {
    let (mut c, set) = crank_arrangements(train)?;
    if set == CrankSet::MirrorSymmetric {
        notes.push(format!(
            "--all-cranks: more than {} throw sequences for {} cylinders; only the {} mirror-symmetric cranks are ranked",
            crate::crank::FULL_ENUMERATION_LIMIT,
            train.cylinders(),
            c.len()
        ));
    }
    if c.is_empty() {
        let shared = format!(
            "no crank of this layout fires evenly every {}° with shared pins (the bank angle must be a multiple of {}°)",
            enginedyn_numerics::format::human(train.interval_deg()),
            enginedyn_numerics::format::human(grid_unit(train))
        );
        match split_pin_cranks(train)? {
            Some((split, delta, effective)) => {
                let (by, way) = if delta < 0.0 {
                    (-delta, "ahead of")
                } else {
                    (delta, "behind")
                };
                notes.push(format!(
                    "{shared}; ranked instead: split crank pins, each bank-2 pin {}° {way} its bank-1 partner \
                     (the smallest split that fires evenly: bank angle + split = {}°), \
                     written per cylinder as `crank_angles_deg` takes them",
                    (by * 1e6).round() / 1e6,
                    (effective * 1e6).round() / 1e6,
                ));
                c = split;
            }
            None => notes.push(shared),
        }
    }
    Ok((c, set))
}

/// The diagram-free pass over every crank: its even firing orders with
/// their criteria and scores, and its free forces. With `all_cranks` a
/// crank without orders is left out; the engine's `own` crank is studied
/// as the engine file has it.
fn diagram_free(
    setup: &Setup,
    train: &Train,
    own: Option<&[f64]>,
    cranks: Vec<Vec<f64>>,
    all_cranks: bool,
) -> Result<Vec<CrankStudy>, BalanceError> {
    let engine = setup.engine;
    let unit = grid_unit(train);
    let own_key = own.and_then(|own| crank_key(train, own, unit));
    let mut studies = Vec::with_capacity(cranks.len());
    for crank in cranks {
        let engine_crank = own_key.is_some() && crank_key(train, &crank, unit) == own_key;
        // The engine's own crank as the engine file has it, not its
        // canonical form, so that its orders read in the engine's numbering.
        let crank = match own {
            Some(own) if engine_crank && all_cranks && !firing_orders(train, own)?.is_empty() => {
                own.to_vec()
            }
            _ => crank,
        };
        let orders = firing_orders(train, &crank)?;
        if orders.is_empty() && all_cranks {
            continue;
        }
        let free = free_forces(
            &cylinders_on(engine, setup.rod_model, &crank),
            engine.mechanism().r(),
            engine.mechanism().lambda(),
            setup.omega,
        );
        let balance = balance_term(engine, setup, &free);
        let orders = orders
            .into_iter()
            .map(|o| order_study(setup, train, balance, o))
            .collect();
        studies.push(CrankStudy {
            engine_crank,
            mirror_symmetric: is_mirror_symmetric(&crank[..train.throws]),
            crank_angles_deg: crank,
            free,
            orders,
        });
    }
    Ok(studies)
}

/// One firing order's diagram-free criteria and score, its crank's
/// balance term given; the journal term 0 until a diagram adds it.
fn order_study(setup: &Setup, train: &Train, balance: f64, o: FiringOrder) -> OrderStudy {
    let z = train.cylinders() as f64;
    let criteria = criteria(train, &o);
    let terms = Terms {
        intervals: round_score(criteria.interval_spread),
        neighbours: round_score(criteria.neighbour_consecutive as f64 / z),
        journal: 0.0,
        balance: round_score(balance),
    };
    OrderStudy {
        score: round_score(terms.score(&setup.weights)),
        order: o,
        criteria,
        journal: None,
        terms,
    }
}

/// Past [`MAX_RANKED_ORDERS`] orders, only the best cranks by the
/// diagram-free score whose orders fit (at least one), with a note.
fn keep_best(studies: &mut Vec<CrankStudy>, notes: &mut Vec<String>) {
    let total: usize = studies.iter().map(|c| c.orders.len()).sum();
    if total > MAX_RANKED_ORDERS {
        sort(studies);
        let mut kept = 0;
        let mut orders = 0;
        for c in studies.iter() {
            if kept > 0 && orders + c.orders.len() > MAX_RANKED_ORDERS {
                break;
            }
            kept += 1;
            orders += c.orders.len();
        }
        notes.push(format!(
            "--all-cranks: {} crank arrangements with {total} orders; the {kept} best by the diagram-free score are ranked",
            studies.len()
        ));
        studies.truncate(kept);
    }
}

/// Each order's main-journal torques from the cylinder torque `t`, and
/// its score with the journal term.
fn add_journals(
    setup: &Setup,
    t: CylinderTorque,
    studies: &mut [CrankStudy],
) -> Result<(), BalanceError> {
    let engine = setup.engine;
    studies.par_iter_mut().try_for_each(|c| {
        c.orders.par_iter_mut().try_for_each(|o| {
            let e = engine_with(engine, &c.crank_angles_deg, &o.order.order)?;
            let j = journal_criteria(&e, t.step, t.torque)?;
            o.terms.journal = round_score(journal_term(&j));
            o.score = round_score(o.terms.score(&setup.weights));
            o.journal = Some(j);
            Ok::<(), BalanceError>(())
        })
    })
}

/// A crank's identity up to equivalence: shared pins by their canonical
/// form ([`crate::crank_arrangements`]'s equivalence); split pins (a vee's
/// crank with one lag per cylinder) only turned so that cylinder 1's pin is
/// at 0, each pin to 1e-6°. `None` for a shared-pin crank off the firing
/// grid.
fn crank_key(train: &Train, crank_deg: &[f64], unit: f64) -> Option<Vec<i64>> {
    if crank_deg.len() == train.throws {
        canonical_deg(crank_deg, unit).map(|c| c.into_iter().map(|a| a as i64).collect())
    } else {
        let base = crank_deg[0];
        let mut key = vec![-1];
        key.extend(
            crank_deg.iter().map(|a| {
                (crate::crank::wrap_deg(a - base, 360.0) * 1e6).round() as i64 % 360_000_000
            }),
        );
        Some(key)
    }
}

/// The split-pin cranks of a vee on which no shared-pin crank fires evenly:
/// a vee whose bank-2 pins lag their bank-1 partners by `delta` fires as a
/// shared-pin vee at the bank angle `bank + delta`. Of the angles on the
/// firing grid the one nearest the bank angle that has cranks is taken
/// (ties: the bank-2 pins lagging); each of its cranks is written per
/// cylinder: bank 1's throws, then the same plus `delta`. Returns the cranks,
/// `delta` (deg, in (-180°, 180°]) and the effective bank angle; `None` for
/// other layouts or when no angle has cranks.
#[allow(clippy::type_complexity)]
fn split_pin_cranks(train: &Train) -> Result<Option<(Vec<Vec<f64>>, f64, f64)>, BalanceError> {
    let enginedyn_engine::Layout::Vee { bank_angle } = train.layout else {
        return Ok(None);
    };
    let bank = bank_angle.to_degrees();
    let unit = grid_unit(train);
    let m = (360.0 / unit).round() as usize;
    let mut candidates: Vec<(f64, f64)> = (0..m)
        .map(|k| {
            let effective = k as f64 * unit;
            let mut delta = crate::crank::wrap_deg(effective - bank, 360.0);
            if delta > 180.0 {
                delta -= 360.0;
            }
            // To 1e-9°, so that a bank angle read as 59.99999999999999°
            // ties as it should.
            ((delta * 1e9).round() / 1e9, effective)
        })
        .collect();
    candidates.sort_by(|a, b| {
        a.0.abs()
            .total_cmp(&b.0.abs())
            .then_with(|| b.0.total_cmp(&a.0))
    });
    for (delta, effective) in candidates {
        let (cranks, _) = crank_arrangements(&train.with_bank_angle(effective))?;
        if cranks.is_empty() {
            continue;
        }
        let round = |x: f64| (crate::crank::wrap_deg(x, 360.0) * 1e9).round() / 1e9;
        let split = cranks
            .into_iter()
            .map(|c| {
                let mut pins: Vec<f64> = c.iter().map(|&a| round(a)).collect();
                pins.extend(c.iter().map(|&a| round(a + delta)));
                pins
            })
            .collect();
        return Ok(Some((split, delta, effective)));
    }
    Ok(None)
}

/// `B` of the score (see [`crate::score`]).
fn balance_term(engine: &Engine, setup: &Setup, f: &FreeForces) -> f64 {
    let unit = engine.reciprocating_mass(setup.rod_model)
        * engine.mechanism().r()
        * setup.omega
        * setup.omega;
    if !(unit > 0.0) {
        return 0.0;
    }
    let s = f.scaled(unit, unit * engine.cylinder_spacing());
    s.free_force_1_n + s.free_force_2_n + s.free_moment_1_residual_nm + s.free_moment_2_nm
}

/// `J` of the score (see [`crate::score`]).
fn journal_term(j: &JournalCriteria) -> f64 {
    // Share of the journal's figure above the engine's own: 0 when the
    // engine torque is the worst journal, toward 1 when a journal is far worse.
    let excess = |journal: f64, engine: f64| {
        if journal > 0.0 {
            (1.0 - engine / journal).max(0.0)
        } else {
            0.0
        }
    };
    (excess(j.max_torque_nm, j.engine_torque_max_nm)
        + excess(j.max_harmonic_nm, j.engine_harmonic_max_nm))
        / 2.0
}

/// Scores to 1e-9, so that float noise does not order equal scores.
fn round_score(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}

fn sort(studies: &mut [CrankStudy]) {
    for c in studies.iter_mut() {
        c.orders.sort_by(|a, b| {
            a.score
                .total_cmp(&b.score)
                .then_with(|| a.order.order.cmp(&b.order.order))
        });
    }
    studies.sort_by(|a, b| {
        a.best_score().total_cmp(&b.best_score()).then_with(|| {
            let key = |c: &CrankStudy| -> Vec<i64> {
                c.crank_angles_deg
                    .iter()
                    .map(|x| (x * 1e6).round() as i64)
                    .collect()
            };
            key(a).cmp(&key(b))
        })
    });
}
