//! Engine orders against natural frequencies: the Campbell diagram's
//! formulas (PHYSICS.md, "Torsional vibration"). The one home of the
//! critical speed `60 f / k`; the report only draws what these return.

/// Frequency (Hz) of engine order `order` (per revolution) at `rpm`:
/// `k n / 60`, the order's line on a Campbell diagram.
///
/// ```
/// // Order 4.5 at 2000 rpm: 150 Hz.
/// assert_eq!(enginedyn_torsion::order_frequency_hz(4.5, 2000.0), 150.0);
/// ```
pub fn order_frequency_hz(order: f64, rpm: f64) -> f64 {
    order * rpm / 60.0
}

/// Critical speed (rpm) at which engine order `order` meets a natural
/// frequency of `frequency_hz`: `60 f / k`.
///
/// ```
/// // A 160 Hz mode meets order 6 at 1600 rpm.
/// assert_eq!(enginedyn_torsion::critical_speed_rpm(160.0, 6.0), 1600.0);
/// ```
pub fn critical_speed_rpm(frequency_hz: f64, order: f64) -> f64 {
    60.0 * frequency_hz / order
}

/// Whether `order` is a major order: a whole multiple of the firings per
/// revolution (`z / 2` for a four-stroke, `z` for a two-stroke: 3, 6, 9 …
/// for an inline six four-stroke, 4, 8 … for a V8), at which every
/// cylinder's harmonic adds in phase on an evenly firing engine. Orders
/// within 1e-9 of a multiple count (halves are exact in binary).
///
/// ```
/// use enginedyn_torsion::is_major_order;
/// assert!(is_major_order(6.0, 3.0));
/// assert!(!is_major_order(4.5, 3.0));
/// ```
pub fn is_major_order(order: f64, firings_per_revolution: f64) -> bool {
    if !(firings_per_revolution > 0.0 && order > 0.0) {
        return false;
    }
    let q = order / firings_per_revolution;
    (q - q.round()).abs() < 1e-9 && q.round() >= 1.0
}

/// Where an engine order meets a natural frequency in a speed range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// Index of the mode in the frequencies given.
    pub mode: usize,
    /// Index of the order in the orders given.
    pub order: usize,
    /// The critical speed (rpm), [`critical_speed_rpm`].
    pub rpm: f64,
}

/// Every crossing of `orders` (per revolution, each above 0) with the
/// natural `frequencies_hz` whose critical speed lies in `[lo, hi]` rpm
/// (ends included), mode by mode and within a mode by order as given.
/// Frequencies not above 0 (the rigid rotation) meet no order.
///
/// ```
/// use enginedyn_torsion::crossings;
/// // A 100 Hz mode and orders 3 and 6 between 1000 and 3000 rpm:
/// // order 3 at 2000 rpm, order 6 at 1000 rpm (the end counts).
/// let c = crossings(&[0.0, 100.0], &[3.0, 6.0], 1000.0, 3000.0);
/// assert_eq!(c.len(), 2);
/// assert_eq!((c[0].mode, c[0].order, c[0].rpm), (1, 0, 2000.0));
/// assert_eq!((c[1].mode, c[1].order, c[1].rpm), (1, 1, 1000.0));
/// ```
pub fn crossings(frequencies_hz: &[f64], orders: &[f64], lo: f64, hi: f64) -> Vec<Crossing> {
    let mut out = Vec::new();
    for (m, &f) in frequencies_hz.iter().enumerate() {
        if !(f > 0.0) {
            continue;
        }
        for (o, &k) in orders.iter().enumerate() {
            if !(k > 0.0) {
                continue;
            }
            let rpm = critical_speed_rpm(f, k);
            if rpm >= lo && rpm <= hi {
                out.push(Crossing {
                    mode: m,
                    order: o,
                    rpm,
                });
            }
        }
    }
    out
}
