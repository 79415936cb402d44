//! Piston kinematics: the one home of every motion formula in enginedyn.
//!
//! A [`Mechanism`] (crank-slider with an optional pin offset, or Scotch yoke)
//! is evaluated with a [`Model`] (the exact closed form or the harmonic
//! series of order 2, 4 or 6) at a *cycle angle* `phi`, counted from the
//! cylinder's firing TDC. Every quantity is SI and per radian of crank angle:
//! multiply `dx` by `w` for the piston speed and `d2x` by `w^2` for its
//! acceleration. [`Cylinder`] adds the bore and compression ratio and gives the
//! volume law. Conventions (signs, offset direction, TDC angle) are those of
//! the project's `PHYSICS.md`.
//!
//! Choosing a model (largest error over the cycle for `lambda = 0.26`,
//! `k = 0`, relative to `R` and to `R w^2`; the test
//! `documented_series_errors` checks every figure):
//!
//! | model | error in `x` | error in `a` | use when |
//! | --- | --- | --- | --- |
//! | `Exact` | rounding | rounding | always; the default |
//! | `Series2` | 2.3e-3 R (`~ lambda^3/8`) | 9.3e-3 R w^2 | hand checks, balance of orders 1 and 2 |
//! | `Series4` | 7.8e-5 R | 4.7e-4 R w^2 | torsional work needing order 4 |
//! | `Series6` | 3.3e-6 R | 2.7e-5 R w^2 | reproducing series tables |
//!
//! Each order gains about `lambda^2` (a factor 15–20 here). With a pin
//! offset only `Series2` is defined.
//!
//! The series exist because the harmonic form shows which engine orders the
//! inertia forces excite; for numbers use `Exact`: it costs one square root
//! more per point.
//!
//! ```
//! use enginedyn_kinematics::{CrankSlider, Mechanism, Model};
//! // VAZ-2108 type: R = 35.5 mm, lambda = 0.26, no offset.
//! let m = Mechanism::CrankSlider(CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap());
//! let w = 4900.0 * std::f64::consts::PI / 30.0;
//! let s = m.state(Model::Exact, 0.0).unwrap();
//! // At TDC the acceleration is R w^2 (1 + lambda).
//! let a_tdc = s.d2x * w * w;
//! assert!((a_tdc - 0.0355 * w * w * 1.26).abs() < 1e-9 * a_tdc);
//! assert_eq!(s.x, 0.0);
//! ```

use std::f64::consts::PI;

/// The lowest engine speed (rpm) a command runs at: below it the speed
/// squared underflows the flywheel sizing (INTERFACE.md, "Limits").
pub const MIN_RPM: f64 = 1e-3;
/// The highest engine speed (rpm) (INTERFACE.md, "Limits").
pub const MAX_RPM: f64 = 100_000.0;

/// Errors of an impossible mechanism or an undefined model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KinematicsError {
    /// A length that must be positive is not.
    #[error("{what} must be positive and finite, got {value}")]
    NonPositive {
        /// Which quantity.
        what: &'static str,
        /// The value given (m).
        value: f64,
    },
    /// The crank cannot turn a full revolution: `lambda (1 + |k|) >= 1`.
    #[error(
        "the crank cannot turn: lambda (1 + |k|) = {value:.4} must be below 1 (lambda = {lambda:.4}, k = e/R = {k:.4})"
    )]
    Impossible {
        /// `R/L`.
        lambda: f64,
        /// `e/R`.
        k: f64,
        /// `lambda (1 + |k|)`.
        value: f64,
    },
    /// Series of order 4 and 6 are defined for a central crank only.
    #[error(
        "{model} is defined for a central crank only (pin offset {offset_m} m); use series2 or exact"
    )]
    SeriesWithOffset {
        /// The model asked for.
        model: &'static str,
        /// The offset (m).
        offset_m: f64,
    },
    /// The requested displacement lies outside the stroke.
    #[error("displacement {x} m lies outside the stroke [0, {stroke}] m")]
    OutsideStroke {
        /// The displacement asked for (m).
        x: f64,
        /// The stroke (m).
        stroke: f64,
    },
}

/// How piston motion is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Model {
    /// The exact closed form (any offset).
    #[default]
    Exact,
    /// Harmonics up to `cos 2phi` (any offset, second order in `lambda`).
    Series2,
    /// Harmonics up to `cos 4phi` (central crank only).
    Series4,
    /// Harmonics up to `cos 6phi` (central crank only).
    Series6,
}

impl Model {
    /// Every model, most exact first.
    pub const ALL: [Model; 4] = [Model::Exact, Model::Series2, Model::Series4, Model::Series6];

    /// The name used on the command line and in `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Model::Exact => "exact",
            Model::Series2 => "series2",
            Model::Series4 => "series4",
            Model::Series6 => "series6",
        }
    }

    /// Parses a name as written by [`Model::name`].
    pub fn from_name(s: &str) -> Option<Model> {
        Model::ALL.into_iter().find(|m| m.name() == s)
    }

    /// Series coefficients `(A2, A4, A6)` of PHYSICS.md for this order.
    fn coefficients(self, lambda: f64) -> (f64, f64, f64) {
        let l3 = lambda.powi(3);
        let l5 = lambda.powi(5);
        match self {
            Model::Exact | Model::Series2 => (lambda, 0.0, 0.0),
            Model::Series4 => (lambda + l3 / 4.0, l3 / 4.0, 0.0),
            Model::Series6 => (
                lambda + l3 / 4.0 + 15.0 * l5 / 128.0,
                l3 / 4.0 + 3.0 * l5 / 16.0,
                9.0 * l5 / 128.0,
            ),
        }
    }
}

/// Motion of the piston and rod at one crank angle, per radian of crank angle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct State {
    /// Piston displacement from TDC, positive toward the crankshaft (m).
    pub x: f64,
    /// `dx/dphi` (m/rad); the piston speed is `w dx/dphi`.
    pub dx: f64,
    /// `d2x/dphi2` (m/rad²); the acceleration is `w^2 d2x/dphi2`.
    pub d2x: f64,
    /// Rod angle `beta` (rad), `sin beta = lambda (sin phi_g - k)`.
    pub beta: f64,
    /// `dbeta/dphi`.
    pub dbeta: f64,
    /// `d2beta/dphi2`.
    pub d2beta: f64,
    /// Radial force factor `cos(phi_g + beta)/cos(beta)`: the crank pin's
    /// radial force per unit piston force (exact for every model).
    pub k_factor: f64,
    /// Tangential force factor `sin(phi_g + beta)/cos(beta)` = `(dx/dphi)/R` exactly.
    pub t_factor: f64,
    /// `tan beta`: side thrust per unit piston force (0 without a rod).
    pub tan_beta: f64,
    /// `1/cos beta`: rod force per unit piston force (1 without a rod).
    pub sec_beta: f64,
}

/// A crank-slider: crank radius `r`, rod length `l`, pin offset `e` (m).
///
/// Construction checks that the crank can turn (`lambda (1 + |k|) < 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrankSlider {
    r: f64,
    l: f64,
    e: f64,
}

impl CrankSlider {
    /// A checked crank-slider.
    pub fn new(r: f64, l: f64, e: f64) -> Result<Self, KinematicsError> {
        positive("crank radius", r)?;
        positive("rod length", l)?;
        if !e.is_finite() {
            return Err(KinematicsError::NonPositive {
                what: "pin offset (finite)",
                value: e,
            });
        }
        let lambda = r / l;
        let k = e / r;
        let value = lambda * (1.0 + k.abs());
        if value >= 1.0 {
            return Err(KinematicsError::Impossible { lambda, k, value });
        }
        Ok(Self { r, l, e })
    }

    /// Crank radius `R` (m).
    pub fn r(&self) -> f64 {
        self.r
    }
    /// Rod length `L` (m).
    pub fn l(&self) -> f64 {
        self.l
    }
    /// Pin offset `e` (m).
    pub fn e(&self) -> f64 {
        self.e
    }
    /// `lambda = R/L`.
    pub fn lambda(&self) -> f64 {
        self.r / self.l
    }
    /// `k = e/R`.
    pub fn k(&self) -> f64 {
        self.e / self.r
    }
    /// Geometric angle of TDC, `asin(e/(L+R))` (rad).
    pub fn phi_tdc(&self) -> f64 {
        if self.e == 0.0 {
            return 0.0;
        }
        (self.e / (self.l + self.r)).asin()
    }
    /// Geometric angle of BDC, `pi + asin(e/(L-R))` (rad).
    pub fn phi_bdc(&self) -> f64 {
        PI + (self.e / (self.l - self.r)).asin()
    }
    /// Distance of the piston pin from the crank axis at TDC (m).
    pub fn y_tdc(&self) -> f64 {
        ((self.l + self.r).powi(2) - self.e * self.e).sqrt()
    }
    /// True stroke (m): `2R` without offset, longer with one.
    pub fn stroke(&self) -> f64 {
        self.y_tdc() - ((self.l - self.r).powi(2) - self.e * self.e).sqrt()
    }

    /// The exact motion at cycle angle `phi` (rad from firing TDC).
    pub fn exact(&self, phi: f64) -> State {
        let (r, lambda, k) = (self.r, self.lambda(), self.k());
        let phi_g = phi + self.phi_tdc();
        let (s, c) = phi_g.sin_cos();
        let sin_b = lambda * (s - k);
        let cos_b = (1.0 - sin_b * sin_b).sqrt();
        let dbeta = lambda * c / cos_b;
        // sin and cos of phi_g + beta from those of phi_g and beta.
        let (sp, cp) = (s * cos_b + c * sin_b, c * cos_b - s * sin_b);
        State {
            // Rounding can leave -1e-19 at TDC; the piston never rises above it.
            x: (self.y_tdc() - (r * c + self.l * cos_b)).max(0.0),
            dx: r * sp / cos_b,
            d2x: r * (cp / cos_b + lambda * c * c / cos_b.powi(3)),
            beta: sin_b.asin(),
            dbeta,
            d2beta: -lambda * s / cos_b + dbeta * dbeta * sin_b / cos_b,
            k_factor: cp / cos_b,
            t_factor: sp / cos_b,
            tan_beta: sin_b / cos_b,
            sec_beta: 1.0 / cos_b,
        }
    }

    /// `r_G' · r_G''` (m²/rad³) for the point at `ratio = l_A/L` along the rod
    /// from the small end, `r_G = r_A + ratio (r_B - r_A)`: the three-mass
    /// rod's centre mass adds the torque `-m_0 w^2 r_G' · r_G''`.
    pub fn rod_point_dot(&self, phi: f64, ratio: f64) -> f64 {
        let st = self.exact(phi);
        let (s, c) = (phi + self.phi_tdc()).sin_cos();
        let r = self.r;
        // Axes: u along the cylinder from the crank axis, v across it.
        let (au1, au2) = (-st.dx, -st.d2x); // the small end moves on the axis
        let (bu1, bv1, bu2, bv2) = (-r * s, r * c, -r * c, -r * s);
        let (gu1, gv1) = (au1 + ratio * (bu1 - au1), ratio * bv1);
        let (gu2, gv2) = (au2 + ratio * (bu2 - au2), ratio * bv2);
        gu1 * gu2 + gv1 * gv2
    }

    fn state(&self, model: Model, phi: f64) -> Result<State, KinematicsError> {
        let exact = self.exact(phi);
        if model == Model::Exact {
            return Ok(exact);
        }
        let (r, lambda, k) = (self.r, self.lambda(), self.k());
        let phi_g = phi + self.phi_tdc();
        let (s, c) = phi_g.sin_cos();
        // The series approximate the piston's motion only; the rod angle stays exact.
        let rod = |x, dx, d2x| State {
            x,
            dx,
            d2x,
            ..exact
        };
        match model {
            Model::Exact => Ok(exact),
            Model::Series2 => {
                let (s2, c2) = (2.0 * phi_g).sin_cos();
                let x = r * ((1.0 - c) + lambda / 4.0 * (1.0 - c2) - k * lambda * s);
                let dx = r * (s + lambda / 2.0 * s2 - k * lambda * c);
                let d2x = r * (c + lambda * c2 + k * lambda * s);
                Ok(rod(x, dx, d2x))
            }
            Model::Series4 | Model::Series6 => {
                if self.e != 0.0 {
                    return Err(KinematicsError::SeriesWithOffset {
                        model: model.name(),
                        offset_m: self.e,
                    });
                }
                let (a2, a4, a6) = model.coefficients(lambda);
                let a0 = 1.0 + a2 / 4.0 - a4 / 16.0 + a6 / 36.0;
                let (s2, c2) = (2.0 * phi).sin_cos();
                let (s4, c4) = (4.0 * phi).sin_cos();
                let (s6, c6) = (6.0 * phi).sin_cos();
                let x = r * (a0 - c - a2 / 4.0 * c2 + a4 / 16.0 * c4 - a6 / 36.0 * c6);
                let dx = r * (s + a2 / 2.0 * s2 - a4 / 4.0 * s4 + a6 / 6.0 * s6);
                let d2x = r * (c + a2 * c2 - a4 * c4 + a6 * c6);
                Ok(rod(x, dx, d2x))
            }
        }
    }
}

/// A Scotch yoke: crank radius `r` (m) and the slot's tilt from square to the
/// cylinder axis `gamma_s` (rad, 0 nominally). Pure harmonic motion, no rod.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScotchYoke {
    r: f64,
    slot_tilt: f64,
}

impl ScotchYoke {
    /// A checked yoke.
    pub fn new(r: f64, slot_tilt: f64) -> Result<Self, KinematicsError> {
        positive("crank radius", r)?;
        if !slot_tilt.is_finite() || slot_tilt.abs() >= PI / 4.0 {
            return Err(KinematicsError::NonPositive {
                what: "45° minus the slot tilt",
                value: PI / 4.0 - slot_tilt.abs(),
            });
        }
        Ok(Self { r, slot_tilt })
    }
    /// Crank radius (m).
    pub fn r(&self) -> f64 {
        self.r
    }
    /// Slot tilt `gamma_s` (rad).
    pub fn slot_tilt(&self) -> f64 {
        self.slot_tilt
    }
    /// Lowest and highest piston travel from its angle-0 position (m):
    /// `x = R (1 - cos(phi + gamma_s) / cos gamma_s)` spans
    /// `R (1 - 1/cos gamma_s)` to `R (1 + 1/cos gamma_s)`; a tilted slot
    /// lifts the piston above its square-slot TDC and lengthens the stroke.
    pub fn travel(&self) -> (f64, f64) {
        let c = 1.0 / self.slot_tilt.cos();
        (self.r * (1.0 - c), self.r * (1.0 + c))
    }
    fn state(&self, phi: f64) -> State {
        let (s, c) = phi.sin_cos();
        let t = self.slot_tilt.tan();
        let r = self.r;
        State {
            x: r * (1.0 - c) + r * s * t,
            dx: r * (s + c * t),
            d2x: r * (c - s * t),
            k_factor: c,
            t_factor: s,
            sec_beta: 1.0,
            ..State::default()
        }
    }
}

/// The mechanism turning crank rotation into piston travel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mechanism {
    /// Crank, connecting rod and piston.
    CrankSlider(CrankSlider),
    /// Crank and slotted yoke.
    ScotchYoke(ScotchYoke),
}

impl Mechanism {
    /// Crank radius `R` (m).
    pub fn r(&self) -> f64 {
        match self {
            Mechanism::CrankSlider(m) => m.r,
            Mechanism::ScotchYoke(m) => m.r,
        }
    }
    /// `R/L`, 0 for the yoke.
    pub fn lambda(&self) -> f64 {
        match self {
            Mechanism::CrankSlider(m) => m.lambda(),
            Mechanism::ScotchYoke(_) => 0.0,
        }
    }
    /// Geometric angle of firing TDC (rad).
    pub fn phi_tdc(&self) -> f64 {
        match self {
            Mechanism::CrankSlider(m) => m.phi_tdc(),
            Mechanism::ScotchYoke(_) => 0.0,
        }
    }
    /// True stroke (m).
    pub fn stroke(&self) -> f64 {
        let (lo, hi) = self.travel();
        hi - lo
    }
    /// Lowest and highest piston travel `x` (m), counted from the piston's
    /// position at firing TDC (cycle angle 0): `(0, stroke)` for the crank
    /// slider, see [`ScotchYoke::travel`] for the yoke.
    pub fn travel(&self) -> (f64, f64) {
        match self {
            Mechanism::CrankSlider(m) => (0.0, m.stroke()),
            Mechanism::ScotchYoke(m) => m.travel(),
        }
    }
    /// Cycle angle of BDC after firing TDC (rad): `pi` unless offset.
    pub fn bdc_after_tdc(&self) -> f64 {
        match self {
            Mechanism::CrankSlider(m) => m.phi_bdc() - m.phi_tdc(),
            Mechanism::ScotchYoke(_) => PI,
        }
    }

    /// The exact motion at cycle angle `phi` (rad from firing TDC).
    pub fn exact(&self, phi: f64) -> State {
        match self {
            Mechanism::CrankSlider(m) => m.exact(phi),
            Mechanism::ScotchYoke(m) => m.state(phi),
        }
    }

    /// `r_G' · r_G''` for a point on the rod (see [`CrankSlider::rod_point_dot`]); 0 for the yoke.
    pub fn rod_point_dot(&self, phi: f64, ratio: f64) -> f64 {
        match self {
            Mechanism::CrankSlider(m) => m.rod_point_dot(phi, ratio),
            Mechanism::ScotchYoke(_) => 0.0,
        }
    }

    /// The series' truncation error: the largest difference of its piston
    /// acceleration from the exact one over a revolution (1° steps), as a
    /// fraction of the largest exact acceleration. 0 for the exact model
    /// and for the Scotch yoke (pure harmonic motion).
    pub fn series_error(&self, model: Model) -> Result<f64, KinematicsError> {
        if model == Model::Exact {
            return Ok(0.0);
        }
        let (mut diff, mut peak) = (0.0_f64, 0.0_f64);
        for k in 0..360 {
            let phi = (k as f64).to_radians();
            let (m, e) = (self.state(model, phi)?, self.exact(phi));
            diff = diff.max((m.d2x - e.d2x).abs());
            peak = peak.max(e.d2x.abs());
        }
        Ok(if peak > 0.0 { diff / peak } else { 0.0 })
    }

    /// Checks that `model` is defined for this mechanism.
    pub fn check(&self, model: Model) -> Result<(), KinematicsError> {
        self.state(model, 0.0).map(|_| ())
    }

    /// The motion at cycle angle `phi` (rad from TDC).
    pub fn state(&self, model: Model, phi: f64) -> Result<State, KinematicsError> {
        match self {
            Mechanism::CrankSlider(m) => m.state(model, phi),
            Mechanism::ScotchYoke(m) => Ok(m.state(phi)),
        }
    }

    /// Evaluates the motion on the uniform grid `phi_k = start + k * step`
    /// (rad), filling `out` (resized to `n`, reusing its allocations).
    pub fn fill(
        &self,
        model: Model,
        start: f64,
        step: f64,
        n: usize,
        out: &mut Table,
    ) -> Result<(), KinematicsError> {
        self.check(model)?;
        out.resize(n);
        // The motion repeats every revolution: a grid over whole revolutions
        // (the four-stroke cycle is two) is computed over the first only.
        let m = revolutions(step, n);
        let per_rev = n / m;
        for k in 0..per_rev {
            let s = self.state(model, start + step * k as f64)?;
            out.x[k] = s.x;
            out.dx[k] = s.dx;
            out.d2x[k] = s.d2x;
            out.beta[k] = s.beta;
            out.dbeta[k] = s.dbeta;
            out.d2beta[k] = s.d2beta;
            out.k_factor[k] = s.k_factor;
            out.t_factor[k] = s.t_factor;
            out.tan_beta[k] = s.tan_beta;
            out.sec_beta[k] = s.sec_beta;
        }
        for col in [
            &mut out.x,
            &mut out.dx,
            &mut out.d2x,
            &mut out.beta,
            &mut out.dbeta,
            &mut out.d2beta,
            &mut out.k_factor,
            &mut out.t_factor,
            &mut out.tan_beta,
            &mut out.sec_beta,
        ] {
            for k in per_rev..n {
                col[k] = col[k - per_rev];
            }
        }
        Ok(())
    }

    /// Cycle angle (rad, in `[0, 2pi)`) at which the piston is `x` from TDC,
    /// on the down-stroke (`down = true`, TDC to BDC) or the up-stroke.
    /// Exact kinematics; bisection refined to 1e-13 rad.
    pub fn angle_at(&self, x: f64, down: bool) -> Result<f64, KinematicsError> {
        let stroke = self.stroke();
        if !(-1e-12 * stroke..=stroke * (1.0 + 1e-12)).contains(&x) {
            return Err(KinematicsError::OutsideStroke { x, stroke });
        }
        let bdc = self.bdc_after_tdc();
        let (mut lo, mut hi) = if down { (0.0, bdc) } else { (bdc, 2.0 * PI) };
        let f = |phi: f64| self.exact(phi).x - x;
        // x rises on the down-stroke and falls on the up-stroke.
        let sign = if down { 1.0 } else { -1.0 };
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if sign * f(mid) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-13 {
                break;
            }
        }
        Ok(0.5 * (lo + hi))
    }
}

/// Motion on a crank-angle grid, one vector per quantity (see [`State`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    /// Displacement (m).
    pub x: Vec<f64>,
    /// `dx/dphi` (m/rad).
    pub dx: Vec<f64>,
    /// `d2x/dphi2` (m/rad²).
    pub d2x: Vec<f64>,
    /// Rod angle (rad).
    pub beta: Vec<f64>,
    /// `dbeta/dphi`.
    pub dbeta: Vec<f64>,
    /// `d2beta/dphi2`.
    pub d2beta: Vec<f64>,
    /// `cos(phi_g + beta)/cos(beta)`.
    pub k_factor: Vec<f64>,
    /// `sin(phi_g + beta)/cos(beta)`.
    pub t_factor: Vec<f64>,
    /// `tan beta`.
    pub tan_beta: Vec<f64>,
    /// `1/cos beta`.
    pub sec_beta: Vec<f64>,
}

impl Table {
    fn resize(&mut self, n: usize) {
        for v in [
            &mut self.x,
            &mut self.dx,
            &mut self.d2x,
            &mut self.beta,
            &mut self.dbeta,
            &mut self.d2beta,
            &mut self.k_factor,
            &mut self.t_factor,
            &mut self.tan_beta,
            &mut self.sec_beta,
        ] {
            v.resize(n, 0.0);
        }
    }
    /// Number of grid points.
    pub fn len(&self) -> usize {
        self.x.len()
    }
    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}

/// A cylinder: its mechanism, bore and compression ratio. Gives the volume law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    mechanism: Mechanism,
    bore: f64,
    compression_ratio: f64,
}

impl Cylinder {
    /// A checked cylinder (bore in m, compression ratio > 1).
    pub fn new(
        mechanism: Mechanism,
        bore: f64,
        compression_ratio: f64,
    ) -> Result<Self, KinematicsError> {
        positive("bore", bore)?;
        positive("compression ratio minus 1", compression_ratio - 1.0)?;
        Ok(Self {
            mechanism,
            bore,
            compression_ratio,
        })
    }
    /// The mechanism.
    pub fn mechanism(&self) -> &Mechanism {
        &self.mechanism
    }
    /// Bore (m).
    pub fn bore(&self) -> f64 {
        self.bore
    }
    /// Compression ratio.
    pub fn compression_ratio(&self) -> f64 {
        self.compression_ratio
    }
    /// Piston area `pi D^2 / 4` (m²).
    pub fn piston_area(&self) -> f64 {
        PI * self.bore * self.bore / 4.0
    }
    /// Swept volume with the true stroke (m³).
    pub fn swept_volume(&self) -> f64 {
        self.piston_area() * self.mechanism.stroke()
    }
    /// Clearance volume `V_d / (eps - 1)` (m³).
    pub fn clearance_volume(&self) -> f64 {
        self.swept_volume() / (self.compression_ratio - 1.0)
    }
    /// Volume at cycle angle `phi` (m³), always from the exact displacement.
    pub fn volume(&self, phi: f64) -> f64 {
        self.clearance_volume() + self.piston_area() * self.mechanism.exact(phi).x
    }
    /// `dV/dphi` (m³/rad), exact.
    pub fn dvolume(&self, phi: f64) -> f64 {
        self.piston_area() * self.mechanism.exact(phi).dx
    }
    /// [`Self::volume`] and [`Self::dvolume`] on the uniform grid
    /// `phi_k = k * step`, `k < n` (one exact evaluation per angle of the
    /// first revolution; the rest repeat it).
    pub fn fill_volume(&self, step: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let (vc, area) = (self.clearance_volume(), self.piston_area());
        let per_rev = n / revolutions(step, n);
        let mut v = Vec::with_capacity(n);
        let mut dv = Vec::with_capacity(n);
        for k in 0..per_rev {
            let s = self.mechanism.exact(k as f64 * step);
            v.push(vc + area * s.x);
            dv.push(area * s.dx);
        }
        for k in per_rev..n {
            v.push(v[k - per_rev]);
            dv.push(dv[k - per_rev]);
        }
        (v, dv)
    }
}

/// A cylinder's volume law on the uniform grid `phi_k = k * step`, `k < n`
/// ([`Cylinder::fill_volume`]), built once and shared by every diagram put
/// on that grid (a batch reads many files with one engine).
///
/// ```
/// use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism, VolumeGrid};
/// let crank = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0)?;
/// let cyl = Cylinder::new(Mechanism::CrankSlider(crank), 0.082, 9.9)?;
/// let law = VolumeGrid::new(&cyl, 1f64.to_radians(), 720);
/// assert!(law.fits(&cyl, 1f64.to_radians(), 720));
/// assert!(!law.fits(&cyl, 0.5f64.to_radians(), 1440));
/// // Largest at BDC (180°), the clearance volume at TDC.
/// assert!((law.volume()[180] - cyl.volume(std::f64::consts::PI)).abs() < 1e-15);
/// # Ok::<(), enginedyn_kinematics::KinematicsError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct VolumeGrid {
    cylinder: Cylinder,
    step: f64,
    volume: Vec<f64>,
    dvolume: Vec<f64>,
}

impl VolumeGrid {
    /// The volume law of `cylinder` at `k * step` (rad), `k < n`.
    pub fn new(cylinder: &Cylinder, step: f64, n: usize) -> Self {
        let (volume, dvolume) = cylinder.fill_volume(step, n);
        Self {
            cylinder: *cylinder,
            step,
            volume,
            dvolume,
        }
    }
    /// True when this is the law [`Self::new`] would build from these
    /// arguments (compared exactly).
    pub fn fits(&self, cylinder: &Cylinder, step: f64, n: usize) -> bool {
        self.cylinder == *cylinder
            && self.step.to_bits() == step.to_bits()
            && self.volume.len() == n
    }
    /// Volume (m³) at each grid point.
    pub fn volume(&self) -> &[f64] {
        &self.volume
    }
    /// `dV/dphi` (m³/rad) at each grid point.
    pub fn dvolume(&self) -> &[f64] {
        &self.dvolume
    }
}

/// How many whole revolutions a grid of `n` steps of `step` (rad) covers
/// with a whole number of steps in each (1 when it does not).
fn revolutions(step: f64, n: usize) -> usize {
    let span = step * n as f64;
    let m = (span / (2.0 * PI)).round();
    if m >= 2.0 && (span - m * 2.0 * PI).abs() < 1e-9 * span && n.is_multiple_of(m as usize) {
        m as usize
    } else {
        1
    }
}

fn positive(what: &'static str, value: f64) -> Result<(), KinematicsError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(KinematicsError::NonPositive { what, value })
    }
}
