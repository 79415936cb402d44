//! The crank train as the firing-order search sees it, and the enumeration of
//! crank arrangements up to equivalence.

use crate::BalanceError;
use enginedyn_engine::{Engine, Layout, Stroke};
use std::collections::HashSet;

/// Angles closer than this (deg) are the same.
pub(crate) const ANGLE_TOL: f64 = 1e-6;

/// `a mod m` in `[0, m)`, values within [`ANGLE_TOL`] of `m` folded to 0.
pub(crate) fn wrap_deg(a: f64, m: f64) -> f64 {
    let r = a.rem_euclid(m);
    if m - r < ANGLE_TOL { 0.0 } else { r }
}

/// Does `crank_deg` give split pins: a vee's crank with one lag per
/// cylinder instead of one per throw?
pub(crate) fn is_split(layout: Layout, throws: usize, crank_deg: &[f64]) -> bool {
    matches!(layout, Layout::Vee { .. }) && crank_deg.len() == 2 * throws
}

/// Lag (deg) of cylinder `i`'s pin on `crank_deg` (one lag per throw, or
/// split: one per cylinder), the cylinder being on throw `throw` of `throws`.
pub(crate) fn pin_deg(crank_deg: &[f64], throws: usize, throw: usize, i: usize) -> f64 {
    if crank_deg.len() == throws {
        crank_deg[throw]
    } else {
        crank_deg[i]
    }
}

/// Layout, numbering and banks of an engine (PHYSICS.md), taken from the
/// engine itself so that the throw and bank conventions have one home
/// ([`Engine::throw_of`], [`Engine::bank_angle_of`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Train {
    /// Two- or four-stroke.
    pub stroke: Stroke,
    /// Layout (inline, vee with its bank angle, boxer).
    pub layout: Layout,
    /// Number of throws.
    pub throws: usize,
    /// Throw (0-based) of each cylinder.
    pub throw: Vec<usize>,
    /// Bank angle `gamma_i` of each cylinder (deg).
    pub gamma_deg: Vec<f64>,
    /// Bank (0 or 1) of each cylinder.
    pub bank: Vec<usize>,
    /// Place of each cylinder along its own bank from the free end (0-based):
    /// cylinders of one bank whose places differ by 1 are neighbours.
    pub place: Vec<usize>,
}

impl Train {
    /// The train of `engine`.
    pub fn of_engine(engine: &Engine) -> Train {
        let z = engine.cylinders();
        let throw: Vec<usize> = (0..z).map(|i| engine.throw_of(i)).collect();
        let gamma_deg: Vec<f64> = (0..z)
            .map(|i| engine.bank_angle_of(i).to_degrees())
            .collect();
        let bank: Vec<usize> = gamma_deg
            .iter()
            .map(|g| usize::from(g.abs() > ANGLE_TOL))
            .collect();
        let place = (0..z)
            .map(|i| match engine.layout() {
                Layout::Inline | Layout::Vee { .. } => throw[i],
                Layout::Boxer => throw[i] / 2,
            })
            .collect();
        Train {
            stroke: engine.stroke_kind(),
            layout: engine.layout(),
            throws: engine.throws(),
            throw,
            gamma_deg,
            bank,
            place,
        }
    }

    /// The same train with bank 2 at another bank angle (deg); a vee only
    /// (other layouts are returned unchanged).
    pub fn with_bank_angle(&self, deg: f64) -> Train {
        let mut t = self.clone();
        if let Layout::Vee { .. } = t.layout {
            t.layout = Layout::Vee {
                bank_angle: deg.to_radians(),
            };
            for (g, &b) in t.gamma_deg.iter_mut().zip(&t.bank) {
                *g = if b == 1 { deg } else { 0.0 };
            }
        }
        t
    }

    /// Number of cylinders.
    pub fn cylinders(&self) -> usize {
        self.throw.len()
    }

    /// Number of banks (1 inline, 2 vee and boxer).
    pub fn banks(&self) -> usize {
        self.bank.iter().max().map_or(1, |b| b + 1)
    }

    /// Cycle (deg): 720 or 360.
    pub fn cycle_deg(&self) -> f64 {
        self.stroke.cycle().to_degrees()
    }

    /// Lag (deg) of cylinder `i`'s pin on `crank_deg` (one lag per throw,
    /// or for a vee with split pins one per cylinder).
    pub fn pin_deg(&self, crank_deg: &[f64], i: usize) -> f64 {
        pin_deg(crank_deg, self.throws, self.throw[i], i)
    }

    /// Whether `crank_deg` has the right length for this train: one lag
    /// per throw, or for a vee one per cylinder (split pins).
    pub fn fits(&self, crank_deg: &[f64]) -> bool {
        crank_deg.len() == self.throws || is_split(self.layout, self.throws, crank_deg)
    }

    /// The even firing interval (deg), `cycle / z`.
    pub fn interval_deg(&self) -> f64 {
        self.cycle_deg() / self.cylinders() as f64
    }
}

/// The whole-degree bank angles in (0°, 180°) at which a vee with these
/// throws (`crank_deg`, shared pins) fires evenly, each with its schemes
/// (alternating or interleaved, one per even order).
pub fn even_firing_bank_angles(
    train: &Train,
    crank_deg: &[f64],
) -> Result<Vec<(f64, Vec<crate::Scheme>)>, BalanceError> {
    let mut out = Vec::new();
    for deg in 1..180 {
        let t = train.with_bank_angle(deg as f64);
        let orders = crate::firing_orders(&t, crank_deg)?;
        if !orders.is_empty() {
            let schemes = orders
                .iter()
                .filter_map(|o| crate::criteria(&t, o).scheme)
                .collect();
            out.push((deg as f64, schemes));
        }
    }
    Ok(out)
}

/// Is the crank mirror-symmetric (throw `k` and throw `n + 1 - k` at the same
/// angle)?
pub fn is_mirror_symmetric(crank_deg: &[f64]) -> bool {
    let n = crank_deg.len();
    (0..n / 2).all(|k| {
        let d = wrap_deg(crank_deg[k] - crank_deg[n - 1 - k], 360.0);
        d < ANGLE_TOL || 360.0 - d < ANGLE_TOL
    })
}

/// How `--all-cranks` chose its cranks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrankSet {
    /// Every crank arrangement that admits even firing, up to equivalence.
    All,
    /// Only the mirror-symmetric ones: the full set was larger than
    /// [`FULL_ENUMERATION_LIMIT`] arrangements before collapsing.
    MirrorSymmetric,
}

/// Largest number of throw sequences (throw 1 at 0°) searched in full before
/// `--all-cranks` falls back to mirror-symmetric cranks, when those exist.
pub const FULL_ENUMERATION_LIMIT: usize = 50_000;
/// Largest number of throw sequences searched at all.
pub const HARD_ENUMERATION_LIMIT: usize = 1_000_000;

/// The crank arrangements (throw lags in deg, throw 1 at 0°) on which `train`
/// can fire evenly, each once up to equivalence: turning all throws by one
/// angle, reversing the shaft end for end, and mirroring (all lags negated).
/// Each is given by its lexicographically smallest form. Throw angles are
/// multiples of the firing grid `gcd(cycle/z, 360°)`; a vee whose bank angle
/// is not a multiple of it has none (a shared-pin V6 at 90°).
///
/// Up to [`FULL_ENUMERATION_LIMIT`] sequences are searched in full; beyond
/// that only mirror-symmetric cranks (if the layout has any), else up to
/// [`HARD_ENUMERATION_LIMIT`], else [`BalanceError::TooManyCranks`].
pub fn crank_arrangements(train: &Train) -> Result<(Vec<Vec<f64>>, CrankSet), BalanceError> {
    let z = train.cylinders();
    let interval = train.interval_deg();
    let (unit, m) = grid(train);
    // Slots per residue (mod 360°) of an even firing.
    let mut cap = vec![0usize; m];
    for k in 0..z {
        let r = (wrap_deg(k as f64 * interval, 360.0) / unit).round() as usize % m;
        cap[r] += 1;
    }
    // Each throw's cylinders as residue offsets (their bank angles).
    let mut on_throw: Vec<Vec<usize>> = vec![Vec::new(); train.throws];
    for i in 0..z {
        let g = train.gamma_deg[i] / unit;
        if (g - g.round()).abs() > 1e-6 {
            return Ok((Vec::new(), CrankSet::All));
        }
        on_throw[train.throw[i]].push(g.round() as usize % m);
    }
    let search = Search {
        m,
        cap: &cap,
        on_throw: &on_throw,
    };
    let (mut found, mut set) = match search.run(false, FULL_ENUMERATION_LIMIT) {
        Some(f) => (f, CrankSet::All),
        None => match search.run(true, HARD_ENUMERATION_LIMIT) {
            Some(f) if !f.is_empty() => (f, CrankSet::MirrorSymmetric),
            _ => match search.run(false, HARD_ENUMERATION_LIMIT) {
                Some(f) => (f, CrankSet::All),
                None => {
                    return Err(BalanceError::TooManyCranks {
                        what: format!(
                            "{z} cylinders ({}, {})",
                            train.layout.name(),
                            train.stroke.name()
                        ),
                        limit: HARD_ENUMERATION_LIMIT,
                    });
                }
            },
        },
    };
    if found.is_empty() {
        set = CrankSet::All;
    }
    found.sort();
    Ok((
        found
            .into_iter()
            .map(|c| {
                c.into_iter()
                    .map(|a| (a as f64 * unit * 1e9).round() / 1e9)
                    .collect()
            })
            .collect(),
        set,
    ))
}

/// The firing grid modulo one turn: `unit = gcd(cycle/z, 360°)` (deg) and
/// the number `m = 360°/unit` of its residues. With `cycle = r · 360°`,
/// `unit = 360° · gcd(r, z) / z` exactly.
fn grid(train: &Train) -> (f64, usize) {
    let z = train.cylinders();
    let r = (train.cycle_deg() / 360.0).round() as usize;
    let (mut a, mut b) = (r, z);
    while b != 0 {
        (a, b) = (b, a % b);
    }
    let m = z / a;
    (360.0 / m as f64, m)
}

struct Search<'a> {
    m: usize,
    cap: &'a [usize],
    on_throw: &'a [Vec<usize>],
}

impl Search<'_> {
    /// Every admissible throw sequence (throw 1 at residue 0), collapsed to
    /// canonical forms; `None` when more than `limit` sequences exist.
    fn run(&self, mirror: bool, limit: usize) -> Option<Vec<Vec<usize>>> {
        let n = self.on_throw.len();
        let mut seq = vec![0usize; n];
        let mut count = vec![0usize; self.m];
        let mut seen = HashSet::new();
        let mut visited = 0usize;
        // Throw 1 at 0 (and, mirrored, throw n as well).
        let placed = if mirror { n.div_ceil(2) } else { n };
        if !self.place(0, 0, mirror, &mut seq, &mut count) {
            return Some(Vec::new());
        }
        let ok = self.dfs(
            1,
            placed,
            mirror,
            &mut seq,
            &mut count,
            &mut seen,
            &mut visited,
            limit,
        );
        ok.then(|| seen.into_iter().collect())
    }

    /// Puts throw `k` (and its mirror partner) at residue `a`; false if a
    /// residue would overflow (then nothing is changed).
    fn place(
        &self,
        k: usize,
        a: usize,
        mirror: bool,
        seq: &mut [usize],
        count: &mut [usize],
    ) -> bool {
        let n = seq.len();
        let mut throws = vec![k];
        if mirror && n - 1 - k != k {
            throws.push(n - 1 - k);
        }
        let mut added: Vec<usize> = Vec::new();
        for &t in &throws {
            for &g in &self.on_throw[t] {
                let r = (a + g) % self.m;
                if count[r] >= self.cap[r] {
                    for &r in &added {
                        count[r] -= 1;
                    }
                    return false;
                }
                count[r] += 1;
                added.push(r);
            }
            seq[t] = a;
        }
        true
    }

    fn unplace(&self, k: usize, a: usize, mirror: bool, seq: &[usize], count: &mut [usize]) {
        let n = seq.len();
        let mut throws = vec![k];
        if mirror && n - 1 - k != k {
            throws.push(n - 1 - k);
        }
        for &t in &throws {
            for &g in &self.on_throw[t] {
                count[(a + g) % self.m] -= 1;
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn dfs(
        &self,
        k: usize,
        placed: usize,
        mirror: bool,
        seq: &mut Vec<usize>,
        count: &mut Vec<usize>,
        seen: &mut HashSet<Vec<usize>>,
        visited: &mut usize,
        limit: usize,
    ) -> bool {
        if k == placed {
            *visited += 1;
            if *visited > limit {
                return false;
            }
            seen.insert(canonical(seq, self.m));
            return true;
        }
        for a in 0..self.m {
            if self.place(k, a, mirror, seq, count) {
                let ok = self.dfs(k + 1, placed, mirror, seq, count, seen, visited, limit);
                self.unplace(k, a, mirror, seq, count);
                if !ok {
                    return false;
                }
            }
        }
        true
    }
}

/// The smallest of the crank's equivalent forms: turned so throw 1 is at 0,
/// reversed end for end, mirrored (residues modulo `m`).
pub(crate) fn canonical(seq: &[usize], m: usize) -> Vec<usize> {
    let norm = |v: Vec<usize>| -> Vec<usize> {
        let b = v[0];
        v.into_iter().map(|a| (a + m - b) % m).collect()
    };
    let rev: Vec<usize> = seq.iter().rev().copied().collect();
    let neg = |v: &[usize]| -> Vec<usize> { v.iter().map(|&a| (m - a) % m).collect() };
    [
        norm(seq.to_vec()),
        norm(rev.clone()),
        norm(neg(seq)),
        norm(neg(&rev)),
    ]
    .into_iter()
    .min()
    .unwrap_or_default()
}

/// The canonical form of a crank given in degrees, on a grid of `unit` deg;
/// `None` if an angle is off the grid.
pub(crate) fn canonical_deg(crank_deg: &[f64], unit: f64) -> Option<Vec<usize>> {
    let m = (360.0 / unit).round() as usize;
    let seq: Option<Vec<usize>> = crank_deg
        .iter()
        .map(|a| {
            let u = wrap_deg(*a, 360.0) / unit;
            ((u - u.round()).abs() < 1e-6).then(|| u.round() as usize % m)
        })
        .collect();
    seq.map(|s| canonical(&s, m))
}

/// The firing grid (deg) of `train`: `gcd(cycle/z, 360°)`.
pub(crate) fn grid_unit(train: &Train) -> f64 {
    grid(train).0
}
