//! A tooth wheel with missing teeth (`--wheel T-M`): T tooth positions a
//! revolution, M of them missing in one gap. The gap is found from the
//! tooth periods ([`super::teeth`]); the first tooth after it is the
//! wheel's 0°, and `--wheel-tdc-deg A` puts cylinder 1's TDC A° after it.
//! Every gap must come T positions after the one before.

use crate::error::{IngestError, at};

/// The most tooth positions a wheel may have.
const MAX_POSITIONS: u32 = 1000;

/// A tooth wheel with missing teeth: T tooth positions a revolution, M of
/// them missing in one gap (`60-2`, `36-1`, `36-2`; `58x` is `60-2`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Wheel {
    positions: u32,
    missing: u32,
}

impl Wheel {
    /// A wheel of `positions` tooth positions with `missing` of them missing:
    /// 4 to 1000 positions, 1 missing at least and at most half of them
    /// less one (a wheel keeps more teeth than its gap spans).
    pub fn new(positions: u32, missing: u32) -> Result<Self, String> {
        if !(4..=MAX_POSITIONS).contains(&positions) {
            return Err(format!(
                "a tooth wheel of {positions} tooth positions: from 4 to {MAX_POSITIONS} are read"
            ));
        }
        if missing == 0 || missing + 1 > positions / 2 {
            return Err(format!(
                "a {positions}-{missing} wheel: from 1 to {} of {positions} teeth may be missing in its gap",
                positions / 2 - 1
            ));
        }
        Ok(Self { positions, missing })
    }

    /// Reads `T-M` (`60-2`, `36-1`, `36-2`) or `58x` (a 60-2 wheel).
    pub fn parse(s: &str) -> Result<Self, String> {
        let t = s.trim().to_ascii_lowercase();
        let shown = enginedyn_numerics::format::quote(s.trim());
        let bad = || {
            format!(
                "`{shown}`: a tooth wheel is T-M, T tooth positions a revolution and M of them missing (60-2, 36-1, 36-2, or 58x for 60-2)"
            )
        };
        if t == "58x" {
            return Self::new(60, 2);
        }
        let (a, b) = t.split_once('-').ok_or_else(bad)?;
        let whole = |x: &str| -> Result<u32, String> {
            let x = x.trim();
            if x.is_empty() || !x.bytes().all(|c| c.is_ascii_digit()) {
                return Err(bad());
            }
            x.parse::<u32>().map_err(|_| bad())
        };
        Self::new(whole(a)?, whole(b)?).map_err(|e| format!("`{shown}`: {e}"))
    }

    /// Tooth positions a revolution (T).
    pub fn positions(self) -> u32 {
        self.positions
    }

    /// Teeth missing in the gap (M).
    pub fn missing(self) -> u32 {
        self.missing
    }

    /// The angle between tooth positions (deg).
    pub(super) fn step_deg(self) -> f64 {
        360.0 / f64::from(self.positions)
    }
}

impl std::fmt::Display for Wheel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}-{}", self.positions, self.missing)
    }
}

impl std::str::FromStr for Wheel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::parse(s)
    }
}

/// The gaps found so far: where the first and the last ended (tooth
/// positions from the first edge), and how many.
pub(super) struct Gaps {
    pub wheel: Wheel,
    pub first: Option<i64>,
    last: Option<i64>,
    pub count: usize,
}

impl Gaps {
    pub(super) fn new(wheel: Wheel) -> Self {
        Self {
            wheel,
            first: None,
            last: None,
            count: 0,
        }
    }

    /// A gap ending at tooth position `n`, its closing edge on `line`:
    /// a revolution after the one before, or an error naming the teeth
    /// between them.
    pub(super) fn gap(&mut self, n: i64, line: usize, col: usize) -> Result<(), IngestError> {
        let t = i64::from(self.wheel.positions);
        if let Some(was) = self.last
            && n - was != t
        {
            let teeth = n - was - i64::from(self.wheel.missing);
            return Err(at(
                line,
                Some(col + 1),
                format!(
                    "{teeth} teeth between two gaps of the `wheel` column, where a {} wheel has {}: a missing or an extra tooth, or another wheel (--wheel)",
                    self.wheel,
                    t - i64::from(self.wheel.missing)
                ),
            ));
        }
        self.first.get_or_insert(n);
        self.last = Some(n);
        self.count += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wheels_as_written() {
        for (s, t, m) in [
            ("60-2", 60, 2),
            ("36-1", 36, 1),
            ("36-2", 36, 2),
            ("58x", 60, 2),
            (" 58X ", 60, 2),
        ] {
            let w = Wheel::parse(s).unwrap();
            assert_eq!((w.positions(), w.missing()), (t, m), "{s}");
        }
        assert_eq!(Wheel::parse("60-2").unwrap().to_string(), "60-2");
        assert!((Wheel::parse("60-2").unwrap().step_deg() - 6.0).abs() < 1e-15);
        for bad in [
            "60",
            "60/2",
            "60-",
            "-2",
            "60-0",
            "60-30",
            "3-1",
            "2000-2",
            "60-2.5",
            "sixty-two",
            "",
        ] {
            let e = Wheel::parse(bad).unwrap_err();
            assert!(e.contains("60-2") || e.contains("wheel"), "{bad}: {e}");
        }
    }

    #[test]
    fn gaps_a_revolution_apart() {
        let mut g = Gaps::new(Wheel::new(60, 2).unwrap());
        g.gap(10, 5, 2).unwrap();
        g.gap(70, 9, 2).unwrap();
        let e = g.gap(129, 13, 2).unwrap_err().to_string();
        assert!(e.starts_with("line 13, column 3: 57 teeth"), "{e}");
        assert_eq!((g.first, g.count), (Some(10), 2));
    }
}
