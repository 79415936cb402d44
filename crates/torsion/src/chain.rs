//! The chain, its modes and its forced response.

use crate::{Complex64, TorsionError, check};
use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// A free-free chain of rigid inertias on torsional springs, numbered from
/// the free end (SI: kg m², N m/rad, N m s/rad). Build it with
/// [`Chain::new`]; every value is checked there and in the `with_` methods.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    inertia: Vec<f64>,
    stiffness: Vec<f64>,
    spring_damping: Vec<f64>,
    mass_damping: Vec<f64>,
    damping_ratio: f64,
}

impl Chain {
    /// `n` inertias (each above 0) and the `n − 1` spring stiffnesses
    /// between neighbours (each above 0), undamped.
    ///
    /// # Errors
    ///
    /// [`TorsionError::Shape`] for no masses or a spring count other than
    /// `n − 1`; [`TorsionError::Invalid`] for a value not above 0 or not
    /// finite.
    pub fn new(inertia: Vec<f64>, stiffness: Vec<f64>) -> Result<Self, TorsionError> {
        let n = inertia.len();
        if n == 0 {
            return Err(TorsionError::Shape {
                what: "masses",
                got: 0,
                need: 1,
            });
        }
        if stiffness.len() != n - 1 {
            return Err(TorsionError::Shape {
                what: "springs",
                got: stiffness.len(),
                need: n - 1,
            });
        }
        for (i, &j) in inertia.iter().enumerate() {
            check(|| format!("inertia {}", i + 1), j, j > 0.0, "above 0 kg m²")?;
        }
        for (i, &k) in stiffness.iter().enumerate() {
            check(
                || format!("stiffness {}", i + 1),
                k,
                k > 0.0,
                "above 0 N m/rad",
            )?;
        }
        // Each mass's k/J (the diagonal of M^-1/2 K M^-1/2) finite: values
        // each finite but far apart (1e308 N m/rad, 1e-300 kg m²) overflow.
        for i in 0..n {
            let ratio = springs_at(&stiffness, i) / inertia[i];
            check(
                || format!("stiffness over inertia of mass {}", i + 1),
                ratio,
                true,
                "a finite (k_left + k_right) / J: springs and inertia too far apart for double precision",
            )?;
        }
        Ok(Self {
            spring_damping: vec![0.0; n - 1],
            mass_damping: vec![0.0; n],
            inertia,
            stiffness,
            damping_ratio: 0.0,
        })
    }

    /// The same chain with modal damping ratio `zeta` (≥ 0, below 1) on
    /// every mode.
    ///
    /// # Errors
    ///
    /// [`TorsionError::Invalid`] for a ratio outside `[0, 1)`.
    pub fn with_damping_ratio(mut self, zeta: f64) -> Result<Self, TorsionError> {
        check(
            || "damping ratio".into(),
            zeta,
            (0.0..1.0).contains(&zeta),
            "from 0 to below 1",
        )?;
        self.damping_ratio = zeta;
        Ok(self)
    }

    /// The same chain with a viscous damper `c` (≥ 0) across spring `j`
    /// (0-based), acting on the relative velocity of masses `j` and `j+1`.
    ///
    /// # Errors
    ///
    /// [`TorsionError::Shape`] for a spring that does not exist,
    /// [`TorsionError::Invalid`] for a negative or non-finite `c`.
    pub fn with_spring_damping(mut self, j: usize, c: f64) -> Result<Self, TorsionError> {
        if j >= self.spring_damping.len() {
            return Err(TorsionError::Shape {
                what: "spring index",
                got: j + 1,
                need: self.spring_damping.len(),
            });
        }
        check(
            || format!("damping across spring {}", j + 1),
            c,
            c >= 0.0,
            "0 or more N m s/rad",
        )?;
        self.spring_damping[j] += c;
        Ok(self)
    }

    /// The same chain with an absolute viscous damper `c` (≥ 0) on mass `i`
    /// (0-based), acting on its velocity relative to the mean rotation.
    ///
    /// # Errors
    ///
    /// As [`Chain::with_spring_damping`].
    pub fn with_mass_damping(mut self, i: usize, c: f64) -> Result<Self, TorsionError> {
        if i >= self.mass_damping.len() {
            return Err(TorsionError::Shape {
                what: "mass index",
                got: i + 1,
                need: self.mass_damping.len(),
            });
        }
        check(
            || format!("damping on mass {}", i + 1),
            c,
            c >= 0.0,
            "0 or more N m s/rad",
        )?;
        self.mass_damping[i] += c;
        Ok(self)
    }

    /// Number of masses.
    pub fn len(&self) -> usize {
        self.inertia.len()
    }

    /// Never true: a chain has at least one mass.
    pub fn is_empty(&self) -> bool {
        self.inertia.is_empty()
    }

    /// The inertias (kg m²) from the free end.
    pub fn inertia(&self) -> &[f64] {
        &self.inertia
    }

    /// The spring stiffnesses (N m/rad) from the free end.
    pub fn stiffness(&self) -> &[f64] {
        &self.stiffness
    }

    /// The modal damping ratio.
    pub fn damping_ratio(&self) -> f64 {
        self.damping_ratio
    }

    /// The dampers across the springs (N m s/rad).
    pub fn spring_damping(&self) -> &[f64] {
        &self.spring_damping
    }

    /// The absolute dampers on the masses (N m s/rad).
    pub fn mass_damping(&self) -> &[f64] {
        &self.mass_damping
    }

    /// The mass (0-based) with the largest `(k_left + k_right) / J` (s⁻²),
    /// and that ratio: the diagonal of `M^-1/2 K M^-1/2`, so the largest
    /// `ω_n²` lies between it and twice it.
    pub fn stiffest_mass(&self) -> (usize, f64) {
        (0..self.len())
            .map(|i| (i, springs_at(&self.stiffness, i) / self.inertia[i]))
            .fold((0, 0.0), |best, x| if x.1 > best.1 { x } else { best })
    }

    /// What the eigen solver cannot resolve (s⁻²): every `ω_n²` of
    /// [`Chain::modes`] is known to about `n ε` times the largest, so a
    /// mode with `ω_n²` near this floor has lost all its precision, and one
    /// under `1e6` times it has fewer than six good digits.
    pub fn frequency_floor(&self) -> f64 {
        self.len() as f64 * f64::EPSILON * 2.0 * self.stiffest_mass().1
    }

    /// Whether the chain has any damping (modal or discrete).
    pub fn is_damped(&self) -> bool {
        self.damping_ratio > 0.0
            || self.spring_damping.iter().any(|&c| c > 0.0)
            || self.mass_damping.iter().any(|&c| c > 0.0)
    }

    /// The tridiagonal stiffness matrix `K`.
    pub fn stiffness_matrix(&self) -> DMatrix<f64> {
        tridiagonal(self.len(), &self.stiffness)
    }

    /// Natural frequencies and mass-normalised modes (`vᵀ M v = 1`),
    /// ascending; mode 0 is the rigid rotation, set exactly (0 rad/s, every
    /// mass `1/sqrt(ΣJ)`). Each mode's first clearly non-zero component is
    /// positive.
    ///
    /// # Errors
    ///
    /// [`TorsionError::Eigen`] if the solver does not converge.
    pub fn modes(&self) -> Result<Modes, TorsionError> {
        let n = self.len();
        let d: Vec<f64> = self.inertia.iter().map(|j| 1.0 / j.sqrt()).collect();
        let mut a = self.stiffness_matrix();
        for r in 0..n {
            for c in 0..n {
                a[(r, c)] *= d[r] * d[c];
            }
        }
        let eig = SymmetricEigen::try_new(a, f64::EPSILON, 10_000).ok_or(TorsionError::Eigen)?;
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&x, &y| eig.eigenvalues[x].total_cmp(&eig.eigenvalues[y]));
        let mut omega = Vec::with_capacity(n);
        let mut shapes = DMatrix::<f64>::zeros(n, n);
        let total: f64 = self.inertia.iter().sum();
        for (m, &col) in order.iter().enumerate() {
            if m == 0 {
                omega.push(0.0);
                shapes.column_mut(0).fill(1.0 / total.sqrt());
                continue;
            }
            omega.push(eig.eigenvalues[col].max(0.0).sqrt());
            let u = eig.eigenvectors.column(col);
            let big = u.amax();
            let sign = u
                .iter()
                .zip(&d)
                .map(|(x, di)| x * di)
                .find(|x| x.abs() > 1e-9 * big)
                .map_or(1.0, f64::signum);
            for r in 0..n {
                shapes[(r, m)] = sign * u[r] * d[r];
            }
        }
        Ok(Modes { omega, shapes })
    }
}

/// The springs on mass `i` of a chain with springs `s`: `s[i-1] + s[i]`.
fn springs_at(s: &[f64], i: usize) -> f64 {
    let left = if i > 0 { s[i - 1] } else { 0.0 };
    left + s.get(i).copied().unwrap_or(0.0)
}

/// The `n × n` chain matrix of springs (or dampers) `s` between neighbours.
fn tridiagonal(n: usize, s: &[f64]) -> DMatrix<f64> {
    let mut k = DMatrix::<f64>::zeros(n, n);
    for (j, &kj) in s.iter().enumerate() {
        k[(j, j)] += kj;
        k[(j + 1, j + 1)] += kj;
        k[(j, j + 1)] -= kj;
        k[(j + 1, j)] -= kj;
    }
    k
}

/// Natural frequencies and mass-normalised modes of a [`Chain`].
#[derive(Debug, Clone, PartialEq)]
pub struct Modes {
    /// Natural angular frequencies (rad/s), ascending; `omega[0] = 0`.
    pub omega: Vec<f64>,
    /// Mode shapes, one column per mode, `Φᵀ M Φ = I`.
    pub shapes: DMatrix<f64>,
}

impl Modes {
    /// Number of modes (the chain's masses).
    pub fn len(&self) -> usize {
        self.omega.len()
    }

    /// Never true.
    pub fn is_empty(&self) -> bool {
        self.omega.is_empty()
    }

    /// Natural frequency of mode `m` (Hz).
    pub fn frequency_hz(&self, m: usize) -> f64 {
        self.omega[m] / std::f64::consts::TAU
    }

    /// Mode `m`'s mass-normalised shape, one value per mass.
    pub fn shape(&self, m: usize) -> Vec<f64> {
        self.shapes.column(m).iter().copied().collect()
    }
}

/// The chain's matrices and modes, ready for forced responses.
#[derive(Debug, Clone)]
pub struct Solver {
    inertia: Vec<f64>,
    damped: bool,
    stiffest: f64,
    k: DMatrix<f64>,
    c: DMatrix<f64>,
    modes: Modes,
}

impl Solver {
    /// Solves the modes and builds `C = M Φ diag(2 ζ ω_n) Φᵀ M` plus the
    /// chain's discrete dampers.
    ///
    /// # Errors
    ///
    /// As [`Chain::modes`].
    pub fn new(chain: &Chain) -> Result<Self, TorsionError> {
        let modes = chain.modes()?;
        let n = chain.len();
        let j = chain.inertia();
        let mut c = tridiagonal(n, chain.spring_damping());
        for (i, &ci) in chain.mass_damping().iter().enumerate() {
            c[(i, i)] += ci;
        }
        let zeta = chain.damping_ratio();
        if zeta > 0.0 {
            for m in 1..n {
                let g = 2.0 * zeta * modes.omega[m];
                let v = modes.shapes.column(m);
                for r in 0..n {
                    let a = g * j[r] * v[r];
                    for s in 0..n {
                        c[(r, s)] += a * j[s] * v[s];
                    }
                }
            }
        }
        Ok(Self {
            inertia: j.to_vec(),
            damped: chain.is_damped(),
            stiffest: chain.stiffest_mass().1,
            k: chain.stiffness_matrix(),
            c,
            modes,
        })
    }

    /// The modes.
    pub fn modes(&self) -> &Modes {
        &self.modes
    }

    /// The damping matrix `C` (N m s/rad).
    pub fn damping_matrix(&self) -> &DMatrix<f64> {
        &self.c
    }

    /// The stiffness matrix `K` (N m/rad).
    pub fn stiffness_matrix(&self) -> &DMatrix<f64> {
        &self.k
    }

    /// Steady response `Θ` (rad, complex amplitudes of `Re(Θ e^{iωt})`) to
    /// the torques `T` (N m, same convention) at `omega` (rad/s, above 0):
    /// `(K − ω² M + i ω C) Θ = T`.
    ///
    /// # Errors
    ///
    /// [`TorsionError::Shape`] for a torque vector of the wrong length,
    /// [`TorsionError::Invalid`] for `omega` not above 0,
    /// [`TorsionError::Singular`] when an undamped chain's system is
    /// singular (an undamped resonance hit exactly);
    /// [`TorsionError::Precision`] when the system overflows, or a damped
    /// chain's cannot be solved (never a resonance: its values are too far
    /// apart for double precision).
    pub fn respond(
        &self,
        omega: f64,
        torque: &[Complex64],
    ) -> Result<Vec<Complex64>, TorsionError> {
        let n = self.inertia.len();
        if torque.len() != n {
            return Err(TorsionError::Shape {
                what: "torques",
                got: torque.len(),
                need: n,
            });
        }
        check(
            || "angular frequency".into(),
            omega,
            omega > 0.0,
            "above 0 rad/s",
        )?;
        let w2 = omega * omega;
        let z = DMatrix::<Complex64>::from_fn(n, n, |r, s| {
            let mass = if r == s { w2 * self.inertia[r] } else { 0.0 };
            Complex64::new(self.k[(r, s)] - mass, omega * self.c[(r, s)])
        });
        let precision = TorsionError::Precision {
            omega,
            stiffest: self.stiffest,
            damped: self.damped,
        };
        let finite = |v: &Complex64| v.re.is_finite() && v.im.is_finite();
        // Only an undamped chain with every entry finite can be singular
        // at a resonance; anything else that fails is precision lost.
        let failure = if self.damped || !z.iter().all(finite) {
            precision
        } else {
            TorsionError::Singular { omega }
        };
        let b = DVector::<Complex64>::from_column_slice(torque);
        let Some(x) = z.lu().solve(&b) else {
            return Err(failure);
        };
        if !x.iter().all(finite) {
            return Err(failure);
        }
        Ok(x.iter().copied().collect())
    }

    /// Mean power (W) the torques `T` put into the motion `Θ` at `omega`:
    /// `½ Re Σ T_i conj(i ω Θ_i)`.
    pub fn power_in(omega: f64, torque: &[Complex64], angles: &[Complex64]) -> f64 {
        torque
            .iter()
            .zip(angles)
            .map(|(t, a)| 0.5 * (t * (Complex64::i() * omega * a).conj()).re)
            .sum()
    }

    /// Mean power (W) the damping takes out of the motion `Θ` at `omega`:
    /// `½ ω² Re(Θᴴ C Θ)`.
    pub fn power_damped(&self, omega: f64, angles: &[Complex64]) -> f64 {
        let n = angles.len().min(self.inertia.len());
        let mut sum = 0.0;
        for r in 0..n {
            for s in 0..n {
                sum += self.c[(r, s)] * (angles[r].conj() * angles[s]).re;
            }
        }
        0.5 * omega * omega * sum
    }
}
