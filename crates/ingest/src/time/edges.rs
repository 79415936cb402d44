//! Where a signal rises through half its range: the one edge rule of every
//! time-record signal (the `tdc` pulse, an encoder, a tooth wheel, a cam).

/// A signal's rising edges through `level`, each timed by linear
/// interpolation between the two samples that straddle the level (never
/// the first sample above it).
#[derive(Debug, Clone, Copy)]
pub(super) struct Rise {
    level: f64,
    prev: Option<(f64, f64)>,
}

impl Rise {
    /// Edges through `level` (half the signal's range).
    pub(super) fn new(level: f64) -> Self {
        Self { level, prev: None }
    }

    /// The sample `v` at time `t`: the time of the edge between it and the
    /// sample before, when the signal rose through the level there.
    #[inline]
    pub(super) fn sample(&mut self, t: f64, v: f64) -> Option<f64> {
        let thr = self.level;
        let edge = match self.prev {
            Some((tp, vp)) if vp < thr && v >= thr => Some(tp + (thr - vp) / (v - vp) * (t - tp)),
            _ => None,
        };
        self.prev = Some((t, v));
        edge
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_are_interpolated_between_samples() {
        let mut r = Rise::new(0.5);
        assert_eq!(r.sample(0.0, 0.0), None);
        // 0.2 then 0.8 at t = 1, 2: half-way at 1.5.
        assert_eq!(r.sample(1.0, 0.2), None);
        let e = r.sample(2.0, 0.8).unwrap();
        assert!((e - 1.5).abs() < 1e-15, "{e}");
        // Staying above is no edge; falling and rising again is one.
        assert_eq!(r.sample(3.0, 1.0), None);
        assert_eq!(r.sample(4.0, 0.0), None);
        let e = r.sample(5.0, 1.0).unwrap();
        assert!((e - 4.5).abs() < 1e-15, "{e}");
        // Exactly at the level counts as risen.
        let mut r = Rise::new(0.5);
        r.sample(0.0, 0.0);
        assert_eq!(r.sample(1.0, 0.5), Some(1.0));
    }
}
