//! Free forces and moments of the reciprocating masses (PHYSICS.md, "Engine").
//!
//! Each cylinder's inertia force along its own axis, in the series2 model
//! `m_j R w^2 (cos phi_g + lambda cos 2phi_g)`, is split into two vectors
//! of constant length in the plane square to the crankshaft, one rotating
//! with the crank and one against it (order 1 at `w`, order 2 at `2w`). Their
//! sums over the cylinders give the free force of each order; weighted by the
//! cylinder's axial position they give the free moment. A figure is the
//! largest magnitude of the resultant over a turn: `|forward| + |backward|`
//! (for an inline engine the two are equal, and this is the textbook
//! `m_j R w^2 |sum exp(j alpha_i)|`).
//!
//! Counterweights on the crank can only make a vector that rotates with the
//! crank; they cancel the forward first-order part, and the first-order
//! moment left after them is `|backward|` (half the amplitude for an
//! inline engine, nothing for a 90° cross-plane V8). Rotating masses are
//! taken as balanced by counterweights, as PHYSICS.md says.
//!
//! **Reference point of the moments.** Moments are taken about the origin of
//! the axial coordinate the caller gives ([`CylinderMass::axial_position`]).
//! [`FreeForces::of_engine`] puts it at the engine's middle, PHYSICS.md's
//! `a_k = (k - (n+1)/2) s` for throw `k` of `n`. When the free force of an
//! order is not zero, that order's moment depends on the reference point
//! (moving it by `d` changes the moment by up to `d` × the force).

use enginedyn_engine::{Engine, RodModel};

/// One cylinder as the free forces see it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CylinderMass {
    /// Reciprocating mass `m_j` (kg).
    pub reciprocating_mass: f64,
    /// Lag `alpha_i` of the cylinder's crank pin behind cylinder 1's (rad):
    /// its throw's, or with split pins its own pin's.
    pub throw_angle: f64,
    /// Bank angle `gamma_i` (rad): 0 on bank 1; the crank pin reaches this
    /// cylinder's TDC `gamma_i` after bank 1's (PHYSICS.md).
    pub bank_angle: f64,
    /// Axial position of the cylinder's throw along the crankshaft (m),
    /// measured from the moments' reference point, positive toward the
    /// flywheel.
    pub axial_position: f64,
}

/// Free forces and moments of the reciprocating masses, before counterweights
/// unless said otherwise; largest magnitudes over a turn (N, N m). Field names
/// are INTERFACE.md's keys.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FreeForces {
    /// First-order free force (N).
    pub free_force_1_n: f64,
    /// Second-order free force (N).
    pub free_force_2_n: f64,
    /// First-order free moment (N m).
    pub free_moment_1_nm: f64,
    /// Second-order free moment (N m).
    pub free_moment_2_nm: f64,
    /// First-order free moment left after counterweights that cancel its part
    /// rotating with the crank (N m).
    pub free_moment_1_residual_nm: f64,
}

/// A sum of phasors, with the sum of their lengths to tell rounding from a
/// true remainder.
#[derive(Debug, Clone, Copy, Default)]
struct Phasor {
    re: f64,
    im: f64,
    scale: f64,
}

impl Phasor {
    fn add_polar(&mut self, r: f64, angle: f64) {
        self.re += r * angle.cos();
        self.im += r * angle.sin();
        self.scale += r.abs();
    }
    /// The length; 0 when it is rounding noise (below 1e-12 of the terms),
    /// so that a balanced engine reads exactly 0.
    fn abs(self) -> f64 {
        let a = self.re.hypot(self.im);
        if a <= 1e-12 * self.scale { 0.0 } else { a }
    }
}

/// The forward and backward phasor sums of one order: `(forward, backward)`
/// magnitudes of `sum w_i m_i cos(n phi_g,i) e_i` for weights `w_i`.
fn order_parts(cyl: &[CylinderMass], n: f64, weight: impl Fn(&CylinderMass) -> f64) -> (f64, f64) {
    // m cos(n (phi - alpha - gamma)) exp(j gamma)
    //   = m/2 [exp(j(n phi - n alpha - (n - 1) gamma)) + exp(-j(n phi - n alpha - (n + 1) gamma))]
    let mut fwd = Phasor::default();
    let mut bwd = Phasor::default();
    for c in cyl {
        let w = weight(c) * c.reciprocating_mass / 2.0;
        fwd.add_polar(w, -n * c.throw_angle - (n - 1.0) * c.bank_angle);
        bwd.add_polar(w, n * c.throw_angle + (n + 1.0) * c.bank_angle);
    }
    (fwd.abs(), bwd.abs())
}

/// Free forces and moments of the reciprocating masses `cyl` on a crank of
/// radius `r` (m), rod ratio `lambda` (0 for a Scotch yoke), at `omega`
/// (rad/s); series2 model, before counterweights, plus the first-order
/// moment left after counterweights. Moments are about the origin of
/// [`CylinderMass::axial_position`] (see the module docs).
///
/// ```
/// use enginedyn_balance::{free_forces, CylinderMass};
/// // Inline three, throws 0°, 240°, 120°, spacing 1 m, m_j R w^2 = 1:
/// let cyl: Vec<CylinderMass> = [0.0_f64, 240.0, 120.0].iter().enumerate()
///     .map(|(k, a)| CylinderMass {
///         reciprocating_mass: 1.0,
///         throw_angle: a.to_radians(),
///         bank_angle: 0.0,
///         axial_position: k as f64 - 1.0,
///     })
///     .collect();
/// let f = free_forces(&cyl, 1.0, 0.25, 1.0);
/// assert!(f.free_force_1_n < 1e-12);
/// assert!((f.free_moment_1_nm - 3f64.sqrt()).abs() < 1e-12);
/// assert!((f.free_moment_2_nm - 0.25 * 3f64.sqrt()).abs() < 1e-12);
/// assert!((f.free_moment_1_residual_nm - 3f64.sqrt() / 2.0).abs() < 1e-12);
/// ```
pub fn free_forces(cyl: &[CylinderMass], r: f64, lambda: f64, omega: f64) -> FreeForces {
    let scale = r * omega * omega;
    let (f1f, f1b) = order_parts(cyl, 1.0, |_| 1.0);
    let (f2f, f2b) = order_parts(cyl, 2.0, |_| 1.0);
    let (m1f, m1b) = order_parts(cyl, 1.0, |c| c.axial_position);
    let (m2f, m2b) = order_parts(cyl, 2.0, |c| c.axial_position);
    FreeForces {
        free_force_1_n: scale * (f1f + f1b),
        free_force_2_n: lambda * scale * (f2f + f2b),
        free_moment_1_nm: scale * (m1f + m1b),
        free_moment_2_nm: lambda * scale * (m2f + m2b),
        free_moment_1_residual_nm: scale * m1b,
    }
}

impl CylinderMass {
    /// The cylinders of `engine` with the reciprocating mass of `rod_model`,
    /// their pins' lags ([`Engine::pin_angle`]) and bank angles, and axial
    /// positions (a split throw's two pins at the throw's station) about the
    /// engine's middle: `(k - (n+1)/2) s` for throw `k` of `n` (PHYSICS.md).
    pub fn of_engine(engine: &Engine, rod_model: RodModel) -> Vec<CylinderMass> {
        let m = engine.reciprocating_mass(rod_model);
        let n = engine.throws() as f64;
        let s = engine.cylinder_spacing();
        (0..engine.cylinders())
            .map(|i| {
                let k = engine.throw_of(i);
                CylinderMass {
                    reciprocating_mass: m,
                    throw_angle: engine.pin_angle(i),
                    bank_angle: engine.bank_angle_of(i),
                    axial_position: (k as f64 + 1.0 - (n + 1.0) / 2.0) * s,
                }
            })
            .collect()
    }
}

impl FreeForces {
    /// The free forces of `engine` (reciprocating mass of `rod_model`) at
    /// `omega` (rad/s), moments about the engine's middle.
    pub fn of_engine(engine: &Engine, rod_model: RodModel, omega: f64) -> FreeForces {
        let mech = engine.mechanism();
        free_forces(
            &CylinderMass::of_engine(engine, rod_model),
            mech.r(),
            mech.lambda(),
            omega,
        )
    }

    /// The forces divided by `force_unit` and the moments by `moment_unit`
    /// (e.g. `m_j R w^2` and `m_j R w^2 s`: figures in cylinders' worth).
    pub fn scaled(&self, force_unit: f64, moment_unit: f64) -> FreeForces {
        FreeForces {
            free_force_1_n: self.free_force_1_n / force_unit,
            free_force_2_n: self.free_force_2_n / force_unit,
            free_moment_1_nm: self.free_moment_1_nm / moment_unit,
            free_moment_2_nm: self.free_moment_2_nm / moment_unit,
            free_moment_1_residual_nm: self.free_moment_1_residual_nm / moment_unit,
        }
    }
}
