//! Where a signal rises: the one edge rule of every time-record signal (the
//! `tdc` pulse, an encoder, a tooth wheel, a cam).
//!
//! Edges have hysteresis, as a counter input does (INTERFACE.md, "The
//! crank's own signals"): a rising edge is the signal reaching two thirds
//! of its range after it was below one third, so a lone sample halfway
//! (noise, a sample caught mid-transition) makes no edge. Its time is
//! still where the signal rises through half its range, interpolated
//! between the two samples that straddle it (never the first sample above).

/// A signal's rising edges between `lo` and `hi` (its range).
#[derive(Debug, Clone, Copy)]
pub(super) struct Rise {
    /// One third, half and two thirds of the range.
    low: f64,
    half: f64,
    high: f64,
    prev: Option<(f64, f64)>,
    /// Below one third since the last edge.
    armed: bool,
    /// The last rise through half the range since the signal was below
    /// one third: its time (s) and the line of the sample past it.
    crossed: Option<(f64, usize)>,
}

impl Rise {
    /// Edges of a signal ranging from `lo` to `hi`.
    pub(super) fn new(lo: f64, hi: f64) -> Self {
        let r = hi - lo;
        Self {
            low: lo + r / 3.0,
            // As the half-way level was always computed: the same edges.
            half: 0.5 * (lo + hi),
            high: lo + 2.0 * r / 3.0,
            prev: None,
            armed: false,
            crossed: None,
        }
    }

    /// The sample `v` at time `t` on `line`: an edge when the signal
    /// reached two thirds of its range here, having been below one third:
    /// the time where it last rose through half the range, and the line of
    /// the sample past it (where the edge is, as errors name it).
    #[inline]
    pub(super) fn sample(&mut self, t: f64, v: f64, line: usize) -> Option<(f64, usize)> {
        let half = self.half;
        if let Some((tp, vp)) = self.prev
            && vp < half
            && v >= half
        {
            self.crossed = Some((tp + (half - vp) / (v - vp) * (t - tp), line));
        }
        self.prev = Some((t, v));
        if v < self.low {
            self.armed = true;
            self.crossed = None;
            return None;
        }
        if self.armed && v >= self.high {
            self.armed = false;
            return self.crossed.take();
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_are_interpolated_between_samples() {
        let mut r = Rise::new(0.0, 1.0);
        assert_eq!(r.sample(0.0, 0.0, 0).map(|e| e.0), None);
        // 0.2 then 0.8 at t = 1, 2: half-way at 1.5.
        assert_eq!(r.sample(1.0, 0.2, 0).map(|e| e.0), None);
        let e = r.sample(2.0, 0.8, 0).map(|e| e.0).unwrap();
        assert!((e - 1.5).abs() < 1e-15, "{e}");
        // Staying above is no edge; falling and rising again is one.
        assert_eq!(r.sample(3.0, 1.0, 0).map(|e| e.0), None);
        assert_eq!(r.sample(4.0, 0.0, 0).map(|e| e.0), None);
        let e = r.sample(5.0, 1.0, 0).map(|e| e.0).unwrap();
        assert!((e - 4.5).abs() < 1e-15, "{e}");
        // Exactly at half counts as risen through it.
        let mut r = Rise::new(0.0, 1.0);
        r.sample(0.0, 0.0, 0);
        assert_eq!(r.sample(1.0, 0.5, 0).map(|e| e.0), None);
        assert_eq!(r.sample(2.0, 1.0, 0).map(|e| e.0), Some(1.0));
    }

    /// A lone sample halfway (or just above) makes no edge, low or high;
    /// a slow rise is timed at half the range, not where it reached two
    /// thirds.
    #[test]
    fn edges_have_hysteresis() {
        let mut r = Rise::new(0.0, 1.0);
        for (t, v) in [(0.0, 0.0), (1.0, 0.6), (2.0, 0.0), (3.0, 0.55), (4.0, 0.1)] {
            assert_eq!(r.sample(t, v, 0).map(|e| e.0), None, "{t}");
        }
        let e = r.sample(5.0, 1.0, 0).map(|e| e.0).unwrap();
        assert!((e - (4.0 + 0.4 / 0.9)).abs() < 1e-12, "{e}");
        // High, a dip to halfway and back: no second edge.
        assert_eq!(r.sample(6.0, 0.45, 0).map(|e| e.0), None);
        assert_eq!(r.sample(7.0, 1.0, 0).map(|e| e.0), None);
        // A slow rise: 0.2, 0.4, 0.6, 0.8: half crossed between 0.4 and 0.6.
        let mut r = Rise::new(0.0, 1.0);
        let got: Vec<Option<f64>> = [0.2, 0.4, 0.6, 0.8]
            .iter()
            .enumerate()
            .map(|(i, &v)| r.sample(i as f64, v, 0).map(|e| e.0))
            .collect();
        assert_eq!(got[..3], [None, None, None]);
        assert!((got[3].unwrap() - 1.5).abs() < 1e-12, "{got:?}");
    }
}
