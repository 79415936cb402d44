//! Forces on one cylinder's crank train over a cycle: gas, reciprocating
//! inertia, side thrust, rod force, radial and tangential force, crank-pin
//! load and the cylinder's torque, with the sign conventions of PHYSICS.md.
//!
//! Input is the cylinder's pressure on a uniform grid of its own cycle angle
//! (from its firing TDC) and the mechanism's motion on the same grid (from
//! the kinematics crate, the one home of the motion formulas).
//!
//! ```
//! use enginedyn_forces::{cylinder_forces, Setup};
//! use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism, Model, Table};
//! let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
//! let cyl = Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap();
//! let n = 720;
//! let step = 4.0 * std::f64::consts::PI / n as f64;
//! let mut kin = Table::default();
//! cyl.mechanism().fill(Model::Exact, 0.0, step, n, &mut kin).unwrap();
//! let pressure = vec![101_325.0; n]; // motored at crankcase pressure: inertia only
//! let setup = Setup { mechanism: *cyl.mechanism(), area: cyl.piston_area(),
//!     crankcase_pressure: 101_325.0, omega: 500.0, m_recip: 0.6, m_big_end: 0.38,
//!     rod_couple: None, rod_centre: None, rigid: None };
//! let f = cylinder_forces(&setup, &kin, &pressure, 0.0, step);
//! // T R = P dx/dphi at every angle.
//! for k in 0..n { assert!((f.tangential[k] * 0.0355 - f.total[k] * kin.dx[k]).abs() < 1e-9); }
//! ```

use enginedyn_kinematics::{Mechanism, Table};

/// Everything the force formulas need besides pressure and motion (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setup {
    /// The mechanism (for the rod's centre-of-mass path).
    pub mechanism: Mechanism,
    /// Piston area `A_p` (m²).
    pub area: f64,
    /// Crankcase pressure `p_0` (Pa, absolute).
    pub crankcase_pressure: f64,
    /// Crank speed `w` (rad/s).
    pub omega: f64,
    /// Reciprocating mass `m_j` (kg).
    pub m_recip: f64,
    /// Rod big-end mass `m_B` (kg) for its centrifugal force.
    pub m_big_end: f64,
    /// Rigid rod: `I_G - m_rod l_A l_B` (kg m²), the couple's coefficient.
    pub rod_couple: Option<f64>,
    /// Three-mass rod: the centre mass `m_0` (kg) and `l_A / L`.
    pub rod_centre: Option<(f64, f64)>,
    /// Three-mass and rigid rods: the rod as a body, for the Newton–Euler
    /// side thrust, rod force and crank-pin load.
    pub rigid: Option<RigidRod>,
}

/// A connecting rod as a planar rigid body plus the piston it carries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidRod {
    /// Piston group mass (kg), without any rod share.
    pub m_piston: f64,
    /// Rod mass (kg).
    pub m_rod: f64,
    /// Small end to centre of mass `l_A` (m).
    pub l_a: f64,
    /// Rod length `L` (m).
    pub l: f64,
    /// Moment of inertia about the centre of mass (kg m²).
    pub i_g: f64,
    /// Big-end mass of the two-mass split `m_rod l_A / L` (kg): the radial
    /// force `K` is reported without its centrifugal force, as for the two-mass rod.
    pub m_big_end_two_mass: f64,
}

/// Newton–Euler forces on piston and rod at one angle (N): side thrust,
/// rod force along the rod at the small end, and the rod's load on the
/// crank pin, radial (toward the axis) and tangential (driving).
struct NewtonEuler {
    side: f64,
    rod: f64,
    pin_radial: f64,
    pin_tangential: f64,
}

/// Axes: `u` along the cylinder from the crank axis toward the head, `v`
/// across it; the rod runs from the small end A to the big end B along
/// `e = (-cos beta, sin beta)`. Gas force `gas` is positive toward the crank.
fn newton_euler(
    rod: &RigidRod,
    gas: f64,
    st: (f64, f64, f64, f64),
    phi_g: f64,
    r: f64,
    w2: f64,
) -> NewtonEuler {
    let (d2x, beta, _dbeta, d2beta) = st;
    let (sb, cb) = beta.sin_cos();
    let (sg, cg) = phi_g.sin_cos();
    // Accelerations (m/s²): the small end moves on the axis, the big end on the crank circle.
    let a_a = (-w2 * d2x, 0.0);
    let a_b = (-w2 * r * cg, -w2 * r * sg);
    let rho = rod.l_a / rod.l;
    let a_g = (a_a.0 + rho * (a_b.0 - a_a.0), a_a.1 + rho * (a_b.1 - a_a.1));
    // Piston along u: m_p a_u = -gas + F_Au (F_A: force of the rod on the piston).
    let f_au = rod.m_piston * a_a.0 + gas;
    // Moments about G: L (e × F_A) = -I_G beta_tt - l_B m (e × a_G), beta_tt = w² beta''.
    let e = (-cb, sb);
    let cross = |p: (f64, f64), q: (f64, f64)| p.0 * q.1 - p.1 * q.0;
    let l_b = rod.l - rod.l_a;
    let rhs = (-rod.i_g * w2 * d2beta - l_b * rod.m_rod * cross(e, a_g)) / rod.l;
    // e × F_A = -cos(beta) F_Av - sin(beta) F_Au.
    let f_av = -(rhs + sb * f_au) / cb;
    // Rod translation: F_B (crank pin on rod) = m a_G + F_A; the pin carries Q = -F_B.
    let q = (-(rod.m_rod * a_g.0 + f_au), -(rod.m_rod * a_g.1 + f_av));
    NewtonEuler {
        side: -f_av,
        rod: f_au * cb - f_av * sb,
        pin_radial: -(q.0 * cg + q.1 * sg),
        pin_tangential: -q.0 * sg + q.1 * cg,
    }
}

/// Force curves on the grid (N, N m), one value per grid angle.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Forces {
    /// Gas force `P_g = (p - p_0) A_p`.
    pub gas: Vec<f64>,
    /// Reciprocating inertia force `P_j = -m_j a`.
    pub inertia: Vec<f64>,
    /// `P = P_g + P_j`, positive toward the crankshaft.
    pub total: Vec<f64>,
    /// Side thrust `N = P tan beta`.
    pub side: Vec<f64>,
    /// Rod force `S = P / cos beta` (positive: compression); 0 for a yoke.
    pub rod: Vec<f64>,
    /// Radial force on the pin `K = P cos(phi_g + beta)/cos(beta)` (positive
    /// toward the crank axis), without the big end's centrifugal force.
    pub radial: Vec<f64>,
    /// Tangential force `T = M / R` (positive driving).
    pub tangential: Vec<f64>,
    /// Crank-pin load magnitude, `|(T, K - K_rB)|`.
    pub pin_load: Vec<f64>,
    /// Crank-pin load's radial part `K - K_rB` (positive toward the crank
    /// axis); its direction is [`Forces::pin_angle_deg`].
    pub pin_radial: Vec<f64>,
    /// Cylinder torque `M` (N m).
    pub torque: Vec<f64>,
    /// The part of `M` due to the crank train's inertia alone (N m).
    pub inertia_torque: Vec<f64>,
}

impl Forces {
    /// Crank-pin load direction at sample `k` (deg), `atan2(T, K - K_rB)`:
    /// 0 toward the crank axis, positive in the direction of rotation
    /// (computed on demand: only reports show it).
    pub fn pin_angle_deg(&self, k: usize) -> f64 {
        self.tangential[k].atan2(self.pin_radial[k]).to_degrees()
    }
}

/// `f(a, b)` for every pair: one loop over two slices that the compiler
/// vectorises (no capacity check per element, unlike `push`).
fn zip_map(a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64) -> Vec<f64> {
    a.iter().zip(b).map(|(&a, &b)| f(a, b)).collect()
}

/// Forces and torque of one cylinder. `pressure` (Pa, absolute) and `kin`
/// are on the same uniform grid of cycle angle `start + k * step` (rad).
///
/// Torque is `M = P_g dx/dphi + M_inertia` by virtual work; for the two-mass
/// rod with exact kinematics it equals `T R` with
/// `T = P sin(phi_g + beta)/cos(beta)` (a test). With series kinematics `dx`
/// is the series' own, so the energy balance holds for every model.
///
/// Each curve is one loop over whole slices (vectorised); the rod models'
/// extra terms are added in loops of their own, in the order of the formulas.
pub fn cylinder_forces(
    setup: &Setup,
    kin: &Table,
    pressure: &[f64],
    start: f64,
    step: f64,
) -> Forces {
    let n = pressure.len().min(kin.len());
    let w2 = setup.omega * setup.omega;
    let r = setup.mechanism.r();
    let k_rb = setup.m_big_end * r * w2;
    let (dx, d2x) = (&kin.dx[..n], &kin.d2x[..n]);
    let (p0, area, m_recip) = (setup.crankcase_pressure, setup.area, setup.m_recip);
    let gas: Vec<f64> = pressure[..n].iter().map(|p| (p - p0) * area).collect();
    let inertia: Vec<f64> = d2x.iter().map(|a| -m_recip * a * w2).collect();
    let total = zip_map(&gas, &inertia, |g, i| g + i);
    let mut inertia_torque = zip_map(&inertia, dx, |i, d| i * d);
    if let Some(c) = setup.rod_couple {
        // Rigid rod: the couple -(I_G - m l_A l_B) w^2 beta'' works through beta'.
        for (m, (b2, b1)) in inertia_torque
            .iter_mut()
            .zip(kin.d2beta.iter().zip(&kin.dbeta))
        {
            *m += -c * w2 * b2 * b1;
        }
    }
    if let Some((m0, ratio)) = setup.rod_centre {
        for (k, m) in inertia_torque.iter_mut().enumerate() {
            let phi = start + step * k as f64;
            *m += -m0 * w2 * setup.mechanism.rod_point_dot(phi, ratio);
        }
    }
    let mut torque = zip_map(&gas, dx, |g, d| g * d);
    for (t, m) in torque.iter_mut().zip(&inertia_torque) {
        *t += m;
    }
    let (side, rod, radial, pin_radial, tangential) = match &setup.rigid {
        Some(body) => {
            let mut out: [Vec<f64>; 5] = Default::default();
            for v in &mut out {
                v.reserve_exact(n);
            }
            let k_rb2 = body.m_big_end_two_mass * r * w2;
            for k in 0..n {
                let phi_g = start + step * k as f64 + setup.mechanism.phi_tdc();
                let st = (d2x[k], kin.beta[k], kin.dbeta[k], kin.d2beta[k]);
                let ne = newton_euler(body, gas[k], st, phi_g, r, w2);
                // T from the Newton–Euler pin load; T R equals the virtual-work
                // torque to rounding (a test), so the torque stays one curve.
                for (v, x) in out.iter_mut().zip([
                    ne.side,
                    ne.rod,
                    ne.pin_radial + k_rb2,
                    ne.pin_radial,
                    ne.pin_tangential,
                ]) {
                    v.push(x);
                }
            }
            let [side, rod, radial, pin_radial, tangential] = out;
            (side, rod, radial, pin_radial, tangential)
        }
        None => {
            let radial = zip_map(&total, &kin.k_factor, |t, k| t * k);
            let rod = if matches!(setup.mechanism, Mechanism::CrankSlider(_)) {
                zip_map(&total, &kin.sec_beta, |t, s| t * s)
            } else {
                vec![0.0; n]
            };
            let pin_radial = radial.iter().map(|k| k - k_rb).collect();
            (
                zip_map(&total, &kin.tan_beta, |t, b| t * b),
                rod,
                radial,
                pin_radial,
                torque.iter().map(|m| m / r).collect(),
            )
        }
    };
    // Forces stay far below 1e150 N: no overflow for hypot to guard against.
    let pin_load = zip_map(&tangential, &pin_radial, |t, k| (t * t + k * k).sqrt());
    Forces {
        gas,
        inertia,
        total,
        side,
        rod,
        radial,
        tangential,
        pin_load,
        pin_radial,
        torque,
        inertia_torque,
    }
}

impl Setup {
    /// The setup of one cylinder of `engine` with the rod model `rod` at
    /// speed `omega` (rad/s), with the masses split as PHYSICS.md says.
    pub fn new(
        engine: &enginedyn_engine::Engine,
        rod: enginedyn_engine::RodModel,
        omega: f64,
    ) -> Self {
        use enginedyn_engine::RodModel;
        let split = engine.rod_masses(rod);
        let masses = engine.masses();
        let rigid = match (engine.mechanism(), rod, masses.rod_inertia) {
            (Mechanism::CrankSlider(cs), RodModel::Rigid | RodModel::ThreeMass, Some(i_g)) => {
                Some(RigidRod {
                    m_piston: masses.piston_group,
                    m_rod: masses.rod,
                    l_a: masses.rod_cg_from_small_end,
                    l: cs.l(),
                    i_g,
                    m_big_end_two_mass: engine.rod_masses(RodModel::TwoMass).big_end,
                })
            }
            _ => None,
        };
        let (rod_couple, rod_centre) = match (engine.mechanism(), rod, masses.rod_inertia) {
            (Mechanism::CrankSlider(cs), RodModel::Rigid, Some(ig)) => {
                let la = masses.rod_cg_from_small_end;
                (Some(ig - masses.rod * la * (cs.l() - la)), None)
            }
            (Mechanism::CrankSlider(cs), RodModel::ThreeMass, Some(_)) => (
                None,
                Some((split.centre, masses.rod_cg_from_small_end / cs.l())),
            ),
            _ => (None, None),
        };
        Setup {
            mechanism: *engine.mechanism(),
            area: engine.cylinder().piston_area(),
            crankcase_pressure: engine.operating().crankcase_pressure,
            omega,
            m_recip: engine.reciprocating_mass(rod),
            m_big_end: split.big_end,
            rod_couple,
            rod_centre,
            rigid,
        }
    }
}
