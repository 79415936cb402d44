//! Multi-cylinder torque: each cylinder's torque placed at its firing angle
//! and summed into the engine torque and the torque on every main journal
//! (counted from the free end, PHYSICS.md), plus torque harmonics by engine
//! order.
//!
//! ```
//! use enginedyn_torque::shift_add;
//! // A cylinder torque curve on a 4-point grid over the cycle, added in twice:
//! // once as it is and once delayed by one grid step.
//! let m1 = [1.0, 2.0, 3.0, 4.0];
//! let mut sum = [0.0; 4];
//! shift_add(&m1, 0.0, 1.0, &mut sum);
//! shift_add(&m1, 1.0, 1.0, &mut sum);
//! assert_eq!(sum, [5.0, 3.0, 5.0, 7.0]);
//! ```

use enginedyn_engine::Engine;
use enginedyn_numerics::extremes::periodic_abs_max;
use enginedyn_numerics::{NumericsError, fourier};

/// Adds `m(phi - theta)` to `out(phi)` on a periodic uniform grid of
/// spacing `step`: the curve delayed by `theta` (same unit as `step`). A
/// delay that is a whole number of steps is exact; otherwise the curve is
/// interpolated linearly between grid points.
pub fn shift_add(m: &[f64], theta: f64, step: f64, out: &mut [f64]) {
    let n = m.len();
    if n == 0 {
        return;
    }
    let s = theta / step;
    let whole = s.floor();
    let frac = s - whole;
    let base = (whole as i64).rem_euclid(n as i64) as usize;
    if frac.abs() < 1e-9 || (1.0 - frac).abs() < 1e-9 {
        let base = if frac > 0.5 { (base + 1) % n } else { base };
        // out[k] += m[k - base]: two contiguous runs, no index arithmetic.
        let (head, tail) = out.split_at_mut(base);
        for (o, v) in head.iter_mut().zip(&m[n - base..]) {
            *o += v;
        }
        for (o, v) in tail.iter_mut().zip(&m[..n - base]) {
            *o += v;
        }
    } else {
        for (k, o) in out.iter_mut().enumerate() {
            let i0 = (k + n - base) % n; // m at phi - whole*step
            let i1 = (i0 + n - 1) % n; // one step further back
            *o += (1.0 - frac) * m[i0] + frac * m[i1];
        }
    }
}

/// True when every firing angle falls on the grid (no interpolation needed).
pub fn on_grid(engine: &Engine, step: f64) -> bool {
    engine.firing_angles().iter().all(|t| {
        let s = t / step;
        (s - s.round()).abs() < 1e-9
    })
}

/// Engine torque and the torques on the main journals.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EngineTorque {
    /// Engine torque `M(phi)` (N m) on the grid of cylinder 1's cycle angle.
    pub total: Vec<f64>,
    /// `journals[K]`: torque on the main journal after throw `K + 1`, counted
    /// from the free end; the last equals `total`. Empty when [`sum`] was
    /// asked for the extremes only.
    pub journals: Vec<Vec<f64>>,
    /// `crankpins[K]`: torque twisting the crank pin of throw `K + 1`: the
    /// journal torque before it plus the half of the throw's own torque that
    /// its free-end web passes on (the statically determinate split of the
    /// tangential force between the two webs). Empty when only the engine
    /// torque is known, or when [`sum`] was asked for the extremes only.
    pub crankpins: Vec<Vec<f64>>,
    /// `journal_abs_max[K]`: the largest magnitude of `journals[K]`, refined
    /// between samples ([`periodic_abs_max`]); always there.
    pub journal_abs_max: Vec<f64>,
}

impl EngineTorque {
    /// Only the engine torque known: it is the last journal's.
    pub fn engine_only(total: Vec<f64>) -> Self {
        Self {
            journal_abs_max: vec![periodic_abs_max(&total)],
            journals: vec![total.clone()],
            crankpins: Vec::new(),
            total,
        }
    }
}

/// Sums cylinder torques by firing angle. `cylinder_torque(i)` gives
/// cylinder `i`'s torque over its own cycle angle on the grid (the same curve
/// for every cylinder with one diagram for all). With `curves` false the
/// journal and crank-pin curves are not kept (each journal's largest torque
/// is): the sum then writes two curves, the running total and one throw's
/// torque, whatever the number of throws.
pub fn sum<'a>(
    engine: &Engine,
    step: f64,
    cylinder_torque: impl Fn(usize) -> &'a [f64],
    curves: bool,
) -> EngineTorque {
    let n = cylinder_torque(0).len();
    let throws = engine.throws();
    let (mut journals, mut crankpins) = if curves {
        (Vec::with_capacity(throws), Vec::with_capacity(throws))
    } else {
        (Vec::new(), Vec::new())
    };
    let mut journal_abs_max = Vec::with_capacity(throws);
    let mut acc = vec![0.0; n];
    // One throw's torque at a time, its cylinders in firing-table order.
    let mut throw = vec![0.0; n];
    for t in 0..throws {
        throw.fill(0.0);
        for i in (0..engine.cylinders()).filter(|&i| engine.throw_of(i) == t) {
            shift_add(cylinder_torque(i), engine.firing_angle(i), step, &mut throw);
        }
        if curves {
            crankpins.push(acc.iter().zip(&throw).map(|(a, v)| a + 0.5 * v).collect());
        }
        for (a, v) in acc.iter_mut().zip(&throw) {
            *a += v;
        }
        journal_abs_max.push(periodic_abs_max(&acc));
        if curves {
            journals.push(acc.clone());
        }
    }
    EngineTorque {
        total: acc,
        journals,
        crankpins,
        journal_abs_max,
    }
}

/// One torque harmonic: amplitude (N m) and phase (rad) of
/// `A cos(k phi + phase)`, `phi` in radians of crank angle from firing TDC.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Harmonic {
    /// Engine order `k` (per revolution).
    pub order: f64,
    /// One-sided amplitude (N m); the mean for order 0.
    pub amplitude: f64,
    /// Phase (rad).
    pub phase: f64,
}

/// Harmonics of a torque sampled over one cycle (`revolutions` = 2 for a
/// four-stroke, 1 for a two-stroke), orders 0 to `max_order` in steps of
/// `1/revolutions`.
pub fn harmonics(
    torque: &[f64],
    revolutions: f64,
    max_order: f64,
) -> Result<Vec<Harmonic>, NumericsError> {
    let step = 1.0 / revolutions;
    let count = (max_order / step).round() as usize;
    let orders: Vec<f64> = (0..=count).map(|i| i as f64 * step).collect();
    let h = fourier::harmonics(torque, revolutions, &orders)?;
    Ok(orders
        .iter()
        .zip(h)
        .map(|(&order, (amplitude, phase))| Harmonic {
            order,
            amplitude,
            phase,
        })
        .collect())
}

/// Loads on the main bearings (N, magnitude) over the cycle, from each
/// cylinder's crank-pin load placed at its firing angle. `tangential(i)` is
/// `T` and `radial(i)` is `K - K_rB` (toward the axis) of cylinder `i` over
/// its own cycle angle on the grid; `unbalance` is the throw's own
/// centrifugal force `m_crank R w^2` (N). Each cylinder's load acts at its
/// own crank pin ([`Engine::pin_angle`]); on a throw with split pins the
/// throw's unbalance is shared equally among its pins.
///
/// Statically determinate split: each throw sits midway between two main
/// bearings and hands half of its force (a vector in engine-fixed axes) to
/// each; bearing `K` (1-based, `throws + 1` of them, counted from the free
/// end) carries half of throw `K - 1` and half of throw `K`. A continuous
/// crankshaft on more bearings is statically indeterminate and shares loads
/// differently (neighbouring throws relieve each other); this split is the
/// textbook first estimate.
pub fn main_bearing_loads<'a>(
    engine: &Engine,
    step: f64,
    tangential: impl Fn(usize) -> &'a [f64],
    radial: impl Fn(usize) -> &'a [f64],
    unbalance: f64,
) -> Vec<Vec<f64>> {
    let n = tangential(0).len();
    let throws = engine.throws();
    // Per throw: force on the throw in engine-fixed axes (x along cylinder 1, y across).
    let mut fx = vec![vec![0.0; n]; throws];
    let mut fy = vec![vec![0.0; n]; throws];
    let mut t = vec![0.0; n];
    let mut r = vec![0.0; n];
    let unit: Vec<(f64, f64)> = (0..n).map(|j| (j as f64 * step).sin_cos()).collect();
    for k in 0..throws {
        // The throw's pins: one shared by its cylinders, or one each (split
        // pins, the throw's own unbalance shared equally among them).
        let on_throw: Vec<usize> = (0..engine.cylinders())
            .filter(|&i| engine.throw_of(i) == k)
            .collect();
        let pins: Vec<Vec<usize>> = if engine.split_pins() {
            on_throw.iter().map(|&i| vec![i]).collect()
        } else {
            vec![on_throw]
        };
        let share = unbalance / pins.len().max(1) as f64;
        for (p, cylinders) in pins.iter().enumerate() {
            t.iter_mut().for_each(|v| *v = 0.0);
            r.iter_mut().for_each(|v| *v = 0.0);
            for &i in cylinders {
                shift_add(tangential(i), engine.firing_angle(i), step, &mut t);
                shift_add(radial(i), engine.firing_angle(i), step, &mut r);
            }
            let lag = cylinders.first().map_or(0.0, |&i| engine.pin_angle(i));
            // cos and sin of (phi_j - lag) by rotating the table of phi_j.
            let (sl, cl) = lag.sin_cos();
            for j in 0..n {
                let (sj, cj) = unit[j];
                let (c, s) = (cj * cl + sj * sl, sj * cl - cj * sl);
                // Radial toward the axis along -r̂, tangential along t̂ = (-sin, cos);
                // the unbalance pulls outward along r̂.
                let radial_out = share - r[j];
                let (x, y) = (radial_out * c - t[j] * s, radial_out * s + t[j] * c);
                if p == 0 {
                    fx[k][j] = x;
                    fy[k][j] = y;
                } else {
                    fx[k][j] += x;
                    fy[k][j] += y;
                }
            }
        }
    }
    (0..=throws)
        .map(|b| {
            (0..n)
                .map(|j| {
                    let (mut x, mut y) = (0.0, 0.0);
                    for k in [b.wrapping_sub(1), b] {
                        if k < throws {
                            x += 0.5 * fx[k][j];
                            y += 0.5 * fy[k][j];
                        }
                    }
                    (x * x + y * y).sqrt()
                })
                .collect()
        })
        .collect()
}
