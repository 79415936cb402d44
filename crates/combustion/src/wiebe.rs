//! The Wiebe burn law, single and double, and its conversion from the
//! design figures CA50 and the 10–90 duration (PHYSICS.md "Combustion").

use crate::{CombustionError, check_range};

/// The default Wiebe efficiency `a`: 99.9 % burnt at the end of the
/// duration (`1 − exp(−6.908)`).
pub const DEFAULT_A: f64 = 6.908;

/// One Wiebe function `xb(φ) = 1 − exp(−a ((φ − φ0)/Δφ)^(m+1))` for
/// `φ ≥ φ0` (0 before). Angles in degrees from firing TDC.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wiebe {
    start_deg: f64,
    duration_deg: f64,
    a: f64,
    m: f64,
}

impl Wiebe {
    /// A checked law: start within −180…180°, duration 1–360°, `a` 0.1–20,
    /// `m` 0–10.
    pub fn new(start_deg: f64, duration_deg: f64, a: f64, m: f64) -> Result<Self, CombustionError> {
        check_range("start_deg", start_deg, -180.0, 180.0)?;
        check_range("duration_deg", duration_deg, 1.0, 360.0)?;
        check_range("wiebe_a", a, 0.1, 20.0)?;
        check_range("wiebe_m", m, 0.0, 10.0)?;
        Ok(Self {
            start_deg,
            duration_deg,
            a,
            m,
        })
    }

    /// The law whose 50 % point is `ca50_deg` and whose 10–90 duration is
    /// `d_10_90_deg`, for shape `m` and efficiency `a`:
    /// `Δφ = D / [(ln 10/a)^(1/(m+1)) − (ln(10/9)/a)^(1/(m+1))]`,
    /// `φ0 = CA50 − Δφ (ln 2/a)^(1/(m+1))`.
    pub fn from_ca50(
        ca50_deg: f64,
        d_10_90_deg: f64,
        m: f64,
        a: f64,
    ) -> Result<Self, CombustionError> {
        check_range("ca50_deg", ca50_deg, -90.0, 120.0)?;
        check_range("duration_10_90_deg", d_10_90_deg, 0.5, 240.0)?;
        check_range("wiebe_a", a, 0.1, 20.0)?;
        check_range("wiebe_m", m, 0.0, 10.0)?;
        let e = 1.0 / (m + 1.0);
        let span = (10f64.ln() / a).powf(e) - ((10.0f64 / 9.0).ln() / a).powf(e);
        let duration = d_10_90_deg / span;
        let start = ca50_deg - duration * (2f64.ln() / a).powf(e);
        Self::new(start, duration, a, m)
    }

    /// A law from parameters already known to be in range (literal
    /// presets, `const`): [`Wiebe::check`] checks it as [`Wiebe::new`] would.
    pub const fn preset(start_deg: f64, duration_deg: f64, a: f64, m: f64) -> Self {
        Self {
            start_deg,
            duration_deg,
            a,
            m,
        }
    }

    /// Checks the parameters as [`Wiebe::new`] does (a law made by
    /// [`Wiebe::preset`]).
    pub fn check(&self) -> Result<(), CombustionError> {
        Self::new(self.start_deg, self.duration_deg, self.a, self.m).map(|_| ())
    }

    /// Start φ0 (deg).
    pub fn start_deg(&self) -> f64 {
        self.start_deg
    }
    /// Duration Δφ (deg).
    pub fn duration_deg(&self) -> f64 {
        self.duration_deg
    }
    /// Efficiency `a`.
    pub fn a(&self) -> f64 {
        self.a
    }
    /// Shape `m`.
    pub fn m(&self) -> f64 {
        self.m
    }

    /// Burnt fraction at `deg` (0 before the start; the law goes on past
    /// the duration towards 1).
    #[inline]
    pub fn fraction(&self, deg: f64) -> f64 {
        if deg <= self.start_deg {
            return 0.0;
        }
        let t = (deg - self.start_deg) / self.duration_deg;
        1.0 - (-self.a * t.powf(self.m + 1.0)).exp()
    }

    /// `dxb/dφ` (per degree) at `deg`.
    #[inline]
    pub fn rate(&self, deg: f64) -> f64 {
        if deg <= self.start_deg {
            return 0.0;
        }
        let m1 = self.m + 1.0;
        let t = (deg - self.start_deg) / self.duration_deg;
        self.a * m1 * t.powf(self.m) * (-self.a * t.powf(m1)).exp() / self.duration_deg
    }

    /// The angle (deg) where the fraction `x` (0 < x < 1) has burnt:
    /// `φ0 + Δφ (−ln(1−x)/a)^(1/(m+1))`.
    pub fn angle_of(&self, x: f64) -> f64 {
        self.start_deg + self.duration_deg * ((-(1.0 - x).ln()) / self.a).powf(1.0 / (self.m + 1.0))
    }
}

/// A burn law: one Wiebe, or two weighted (a diesel's premixed and
/// diffusion burn), the weights adding to 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BurnLaw {
    first: Wiebe,
    second: Option<(Wiebe, f64)>,
}

impl BurnLaw {
    /// A single Wiebe.
    pub fn single(w: Wiebe) -> Self {
        Self {
            first: w,
            second: None,
        }
    }

    /// `(1 − f) · first + f · second`, `f` (the second burn's fraction)
    /// within 0–1.
    pub fn double(first: Wiebe, second: Wiebe, fraction: f64) -> Result<Self, CombustionError> {
        check_range("fraction", fraction, 0.0, 1.0)?;
        Ok(Self {
            first,
            second: Some((second, fraction)),
        })
    }

    /// Checks each Wiebe ([`Wiebe::check`]) and the second burn's fraction.
    pub fn check(&self) -> Result<(), CombustionError> {
        self.first.check()?;
        if let Some((w, f)) = self.second {
            w.check()?;
            check_range("fraction", f, 0.0, 1.0)?;
        }
        Ok(())
    }

    /// The end of the burn (deg): the latest start plus duration.
    pub fn end_deg(&self) -> f64 {
        let first = self.first.start_deg + self.first.duration_deg;
        match self.second {
            Some((w, f)) if f > 0.0 => first.max(w.start_deg + w.duration_deg),
            _ => first,
        }
    }

    /// The first (or only) Wiebe.
    pub fn first(&self) -> &Wiebe {
        &self.first
    }
    /// The second Wiebe and its fraction.
    pub fn second(&self) -> Option<&(Wiebe, f64)> {
        self.second.as_ref()
    }

    /// The earliest start of the burn (deg).
    pub fn start_deg(&self) -> f64 {
        match self.second {
            Some((w, f)) if f > 0.0 => self.first.start_deg.min(w.start_deg),
            _ => self.first.start_deg,
        }
    }

    /// Burnt fraction at `deg`.
    #[inline]
    pub fn fraction(&self, deg: f64) -> f64 {
        match self.second {
            None => self.first.fraction(deg),
            Some((w, f)) => (1.0 - f) * self.first.fraction(deg) + f * w.fraction(deg),
        }
    }

    /// `dxb/dφ` (per degree).
    #[inline]
    pub fn rate(&self, deg: f64) -> f64 {
        match self.second {
            None => self.first.rate(deg),
            Some((w, f)) => (1.0 - f) * self.first.rate(deg) + f * w.rate(deg),
        }
    }

    /// The angle (deg) where the fraction `x` (0 < x < 1) has burnt: closed
    /// form for one Wiebe, bisection to 1e-12° for two (the fraction rises
    /// monotonically).
    pub fn angle_of(&self, x: f64) -> f64 {
        let Some((w, _)) = self.second else {
            return self.first.angle_of(x);
        };
        let mut lo = self.start_deg();
        let mut hi = self.first.angle_of(x).max(w.angle_of(x));
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.fraction(mid) < x {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-12 {
                break;
            }
        }
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ca50_and_duration_come_back() {
        for &(ca50, d, m) in &[(8.0, 20.0, 2.0), (-3.0, 35.0, 1.0), (15.0, 12.0, 0.5)] {
            let w = Wiebe::from_ca50(ca50, d, m, DEFAULT_A).unwrap();
            assert!((w.angle_of(0.5) - ca50).abs() < 1e-12);
            assert!((w.angle_of(0.9) - w.angle_of(0.1) - d).abs() < 1e-12);
            assert!((w.fraction(ca50) - 0.5).abs() < 1e-12);
        }
    }

    #[test]
    fn end_of_duration_is_99_9_percent() {
        let w = Wiebe::new(-10.0, 40.0, DEFAULT_A, 2.0).unwrap();
        assert!((w.fraction(30.0) - 0.999).abs() < 1e-4);
        assert!(
            w.fraction(-10.0).abs() < f64::MIN_POSITIVE,
            "nothing burnt before the start"
        );
    }

    #[test]
    fn rate_is_the_derivative_of_the_fraction() {
        let w = Wiebe::new(-15.0, 45.0, 5.0, 1.5).unwrap();
        let law = BurnLaw::double(w, Wiebe::new(0.0, 60.0, 5.0, 0.8).unwrap(), 0.7).unwrap();
        for k in 1..100 {
            let x = -13.95 + k as f64 * 0.7;
            let h = 1e-5;
            let fd = (law.fraction(x + h) - law.fraction(x - h)) / (2.0 * h);
            assert!((fd - law.rate(x)).abs() < 1e-7, "{x}: {fd} {}", law.rate(x));
        }
    }

    #[test]
    fn double_angle_of_inverts_the_fraction() {
        let pre = Wiebe::new(-6.0, 10.0, DEFAULT_A, 2.0).unwrap();
        let diff = Wiebe::new(-2.0, 60.0, DEFAULT_A, 0.8).unwrap();
        let law = BurnLaw::double(pre, diff, 0.8).unwrap();
        for x in [0.05, 0.1, 0.5, 0.9] {
            let a = law.angle_of(x);
            assert!((law.fraction(a) - x).abs() < 1e-10);
        }
    }

    #[test]
    fn bounds_name_the_key() {
        let e = Wiebe::from_ca50(8.0, -1.0, 2.0, DEFAULT_A).unwrap_err();
        assert!(e.to_string().contains("duration_10_90_deg"), "{e}");
    }
}
