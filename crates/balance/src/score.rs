//! The score that ranks firing orders and cranks (lower is better).
//!
//! ```text
//! score = w_intervals  · I
//!       + w_neighbours · N
//!       + w_journal    · J
//!       + w_balance    · B
//! ```
//!
//! - `I`: unevenness of the banks' own firing intervals, the mean over banks
//!   of `(max - min) / (cycle / bank cylinders)` (0 inline and for the
//!   alternating scheme; the engine itself always fires evenly here).
//! - `N`: consecutive firings of neighbouring cylinders of one bank, per
//!   cylinder: `neighbour_consecutive / z`.
//! - `J`: main-journal torques against the engine torque, which is the same
//!   for every even firing order (it is the last journal's):
//!   `[(1 - T_e / T) + (1 - H_e / H)] / 2`, `T` the largest journal torque,
//!   `T_e` the largest engine torque, `H` the largest harmonic (order > 0)
//!   of any journal, `H_e` the engine torque's largest harmonic: the share of
//!   the worst journal's figures that the engine's own do not reach, in
//!   [0, 1). 0 when no journal is worse than the engine torque; 0 without a
//!   diagram.
//! - `B`: the free forces and moments (reciprocating masses) in cylinders'
//!   worth: `(F1 + F2) / (m_j R w^2) + (M1_res + M2) / (m_j R w^2 s)`, `M1_res`
//!   the first-order moment left after counterweights. The same for every
//!   order of one crank; it ranks cranks (`--all-cranks`).
//!
//! Default weights are all 1. With them balance dominates between cranks (an
//! inline four's flat crank scores `B = 4 lambda`, its 0-180-0-180 crank one
//! more and 0-0-180-180 two more), and between the orders of one crank the
//! neighbour count and the journal torques decide. Seed 001 lists the
//! criteria as even intervals, balance, no neighbours firing in a row,
//! torsional vibration; with equal weights one neighbour pair more in an
//! inline six (`1/6`) weighs as much as a journal whose largest harmonic is
//! 1.5 times the engine torque's (`(1 - 1/1.5)/2`).
//!
//! The terms are rounded to 1e-9, so that orders equal but for float noise
//! tie (ties are broken by the firing order, then by the crank angles).

use crate::BalanceError;

/// Weights of the score's terms (`--weights intervals=1,neighbours=1,journal=1,balance=1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights {
    /// Weight of `I`, the banks' interval unevenness.
    pub intervals: f64,
    /// Weight of `N`, neighbour-consecutive firings per cylinder.
    pub neighbours: f64,
    /// Weight of `J`, the journal torques against the engine torque.
    pub journal: f64,
    /// Weight of `B`, the free forces and moments.
    pub balance: f64,
}

impl Default for Weights {
    fn default() -> Self {
        Self {
            intervals: 1.0,
            neighbours: 1.0,
            journal: 1.0,
            balance: 1.0,
        }
    }
}

impl Weights {
    /// Parses `key=value` pairs separated by commas; keys not given keep
    /// their default of 1.
    ///
    /// ```
    /// let w = enginedyn_balance::Weights::parse("balance=2, journal=0").unwrap();
    /// assert_eq!((w.balance, w.journal, w.neighbours), (2.0, 0.0, 1.0));
    /// assert!(enginedyn_balance::Weights::parse("noise=1").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<Weights, BalanceError> {
        let mut w = Weights::default();
        for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (key, value) = part
                .split_once('=')
                .ok_or_else(|| BalanceError::BadWeight {
                    key: part.to_string(),
                    value: String::new(),
                })?;
            let (key, value) = (key.trim(), value.trim());
            let v: f64 = value
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| BalanceError::BadWeight {
                    key: key.to_string(),
                    value: value.to_string(),
                })?;
            match key {
                "intervals" => w.intervals = v,
                "neighbours" | "neighbors" => w.neighbours = v,
                "journal" => w.journal = v,
                "balance" => w.balance = v,
                _ => {
                    return Err(BalanceError::UnknownWeight {
                        key: key.to_string(),
                    });
                }
            }
        }
        Ok(w)
    }
}

/// The score's terms for one order on one crank.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Terms {
    /// `I`.
    pub intervals: f64,
    /// `N`.
    pub neighbours: f64,
    /// `J` (0 without a diagram).
    pub journal: f64,
    /// `B`.
    pub balance: f64,
}

impl Terms {
    /// The weighted sum.
    pub fn score(&self, w: &Weights) -> f64 {
        w.intervals * self.intervals
            + w.neighbours * self.neighbours
            + w.journal * self.journal
            + w.balance * self.balance
    }
}
