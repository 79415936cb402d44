//! The even firing orders of one crank and the criteria that tell them apart.

use crate::BalanceError;
use crate::crank::{ANGLE_TOL, Train, wrap_deg};

/// Most firing orders listed for one crank.
pub const MAX_ORDERS: usize = 200_000;

/// One even firing order of a crank.
#[derive(Debug, Clone, PartialEq)]
pub struct FiringOrder {
    /// Cylinder numbers (1-based) in firing order, starting with cylinder 1.
    pub order: Vec<usize>,
    /// Firing angle of each cylinder 1..z (deg, cylinder 1 at 0).
    pub angles_deg: Vec<f64>,
}

/// Every even firing order (`cycle / z` apart) that the crank `crank_deg`
/// (throw lags, deg: one per throw, or for a vee with split pins one per
/// cylinder) admits on `train`, each once: an order and the same
/// sequence started elsewhere are one, listed from cylinder 1.
///
/// A cylinder on throw `k` with bank angle `gamma` can fire only at
/// `alpha_k + gamma (+ 360°)` (PHYSICS.md); the search assigns cylinders to
/// the `z` even firing slots by that rule, cylinder 1 in slot 0. A
/// four-stroke inline engine with an even cylinder count thus has
/// `2^(z/2 - 1)` orders on any crank that fires evenly: each throw's two
/// cylinders fire 360° apart, and only which fires first is free. Sorted
/// lexicographically.
pub fn firing_orders(train: &Train, crank_deg: &[f64]) -> Result<Vec<FiringOrder>, BalanceError> {
    let z = train.cylinders();
    if !train.fits(crank_deg) {
        return Err(BalanceError::CrankLength {
            got: crank_deg.len(),
            throws: train.throws,
        });
    }
    let cycle = train.cycle_deg();
    let interval = cycle / z as f64;
    let base = train.pin_deg(crank_deg, 0) + train.gamma_deg[0];
    // Admissible slots of each cylinder.
    let slots: Vec<Vec<usize>> = (0..z)
        .map(|i| {
            let own = train.pin_deg(crank_deg, i) + train.gamma_deg[i] - base;
            (0..z)
                .filter(|&s| {
                    let d = wrap_deg(s as f64 * interval - own, 360.0);
                    d < ANGLE_TOL || 360.0 - d < ANGLE_TOL
                })
                .collect()
        })
        .collect();
    if !slots[0].contains(&0) {
        return Ok(Vec::new());
    }
    let mut taken = vec![false; z];
    let mut slot_of = vec![0usize; z];
    taken[0] = true;
    let mut out = Vec::new();
    assign(1, &slots, &mut taken, &mut slot_of, &mut out)?;
    let mut orders: Vec<FiringOrder> = out
        .into_iter()
        .map(|slot_of| {
            let mut order = vec![0usize; z];
            for (i, &s) in slot_of.iter().enumerate() {
                order[s] = i + 1;
            }
            FiringOrder {
                order,
                angles_deg: slot_of.iter().map(|&s| s as f64 * interval).collect(),
            }
        })
        .collect();
    orders.sort_by(|a, b| a.order.cmp(&b.order));
    Ok(orders)
}

fn assign(
    i: usize,
    slots: &[Vec<usize>],
    taken: &mut [bool],
    slot_of: &mut [usize],
    out: &mut Vec<Vec<usize>>,
) -> Result<(), BalanceError> {
    if i == slots.len() {
        if out.len() >= MAX_ORDERS {
            return Err(BalanceError::TooManyOrders { limit: MAX_ORDERS });
        }
        out.push(slot_of.to_vec());
        return Ok(());
    }
    for &s in &slots[i] {
        if !taken[s] {
            taken[s] = true;
            slot_of[i] = s;
            assign(i + 1, slots, taken, slot_of, out)?;
            taken[s] = false;
        }
    }
    Ok(())
}

/// How a two-bank engine shares its firings between the banks (seed 001).
/// "The same order" compares places along the bank (throws of a vee).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheme {
    /// Seed 001's alternating scheme: the banks fire in turn, each evenly at
    /// twice the engine's interval, both in the same order.
    Alternating,
    /// The banks fire in turn, each evenly, but in different orders (the
    /// seed's two schemes leave this case out).
    AlternatingMixed,
    /// Seed 001's interleaved scheme: the banks' own intervals are uneven,
    /// skipped and made up between the banks so that the engine still fires
    /// evenly.
    Interleaved,
}

impl Scheme {
    /// As printed: `alternating`, `alternating-mixed` or `interleaved`.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Alternating => "alternating",
            Scheme::AlternatingMixed => "alternating-mixed",
            Scheme::Interleaved => "interleaved",
        }
    }
}

/// What separates the orders of one crank, without a diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderCriteria {
    /// Engine firing intervals (deg), from cylinder 1 in firing order; the
    /// last closes the cycle.
    pub intervals_deg: Vec<f64>,
    /// Each bank's own firing intervals (deg), in that bank's firing order
    /// from its first cylinder to fire after cylinder 1's firing.
    pub bank_intervals_deg: Vec<Vec<f64>>,
    /// Two banks: alternating (same or different orders) or interleaved;
    /// `None` inline.
    pub scheme: Option<Scheme>,
    /// Consecutive firings, in each bank's own firing sequence (cyclic), of
    /// neighbouring cylinders of that bank. Inline this is the engine's
    /// firing order itself, closing back to cylinder 1 (seed 001 writes
    /// `1-4-2-3-8-5-7-6-1`).
    pub neighbour_consecutive: usize,
    /// The neighbouring pairs counted, in firing sequence.
    pub neighbour_pairs: Vec<(usize, usize)>,
    /// Non-uniformity of the bank intervals: the mean over banks of
    /// `(max - min) / (cycle / bank cylinders)`; 0 for an even bank.
    pub interval_spread: f64,
}

/// The diagram-free criteria of order `o` on `train`.
pub fn criteria(train: &Train, o: &FiringOrder) -> OrderCriteria {
    let z = train.cylinders();
    let cycle = train.cycle_deg();
    let round = |x: f64| (x * 1e6).round() / 1e6;
    let seq_intervals = |cyls: &[usize]| -> Vec<f64> {
        (0..cyls.len())
            .map(|k| {
                let a = o.angles_deg[cyls[k] - 1];
                let b = o.angles_deg[cyls[(k + 1) % cyls.len()] - 1];
                let d = wrap_deg(b - a, cycle);
                round(if d < ANGLE_TOL { cycle } else { d })
            })
            .collect()
    };
    let intervals_deg = seq_intervals(&o.order);
    let banks = train.banks();
    let bank_seq: Vec<Vec<usize>> = (0..banks)
        .map(|b| {
            o.order
                .iter()
                .copied()
                .filter(|&c| train.bank[c - 1] == b)
                .collect()
        })
        .collect();
    let bank_intervals_deg: Vec<Vec<f64>> = bank_seq.iter().map(|s| seq_intervals(s)).collect();
    let mut neighbour_pairs = Vec::new();
    for s in &bank_seq {
        if s.len() < 2 {
            continue;
        }
        for k in 0..s.len() {
            let (a, b) = (s[k], s[(k + 1) % s.len()]);
            if train.place[a - 1].abs_diff(train.place[b - 1]) == 1 {
                neighbour_pairs.push((a, b));
            }
        }
    }
    let interval_spread = bank_intervals_deg
        .iter()
        .map(|iv| {
            let even = cycle / iv.len() as f64;
            let max = iv.iter().copied().fold(f64::MIN, f64::max);
            let min = iv.iter().copied().fold(f64::MAX, f64::min);
            (max - min) / even
        })
        .sum::<f64>()
        / banks as f64;
    let scheme = (banks == 2).then(|| {
        let alternates =
            (0..z).all(|k| train.bank[o.order[k] - 1] != train.bank[o.order[(k + 1) % z] - 1]);
        let places =
            |s: &[usize]| -> Vec<usize> { s.iter().map(|&c| train.place[c - 1]).collect() };
        let (t1, t2) = (places(&bank_seq[0]), places(&bank_seq[1]));
        let same_order = t1.len() == t2.len()
            && (0..t2.len()).any(|r| (0..t1.len()).all(|k| t1[k] == t2[(k + r) % t2.len()]));
        match (alternates && interval_spread < 1e-9, same_order) {
            (true, true) => Scheme::Alternating,
            (true, false) => Scheme::AlternatingMixed,
            (false, _) => Scheme::Interleaved,
        }
    });
    OrderCriteria {
        intervals_deg,
        bank_intervals_deg,
        scheme,
        neighbour_consecutive: neighbour_pairs.len(),
        neighbour_pairs,
        interval_spread,
    }
}
