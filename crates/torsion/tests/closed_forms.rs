//! Closed forms and invariants of the torsion chain. Each tolerance is
//! written beside its assertion; a wrong model (a missing factor, a wrong
//! sign, damping on the rigid mode) misses by far more.

use enginedyn_torsion::{Chain, Complex64, CrankTrain, Damper, Solver, Synthesis, TorsionError};
use std::f64::consts::{PI, TAU};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[test]
fn two_masses_frequency_and_shape() {
    let (j1, j2, k) = (0.7, 2.3, 3.4e4);
    let modes = Chain::new(vec![j1, j2], vec![k]).unwrap().modes().unwrap();
    let closed = (k * (j1 + j2) / (j1 * j2)).sqrt() / TAU;
    // 1e-13: the symmetric eigen solver's rounding only.
    assert!(rel(modes.frequency_hz(1), closed) < 1e-13);
    assert!(modes.omega[0].abs() < 1e-300);
    // Mode 1: J1 v1 + J2 v2 = 0 (orthogonal to the rigid rotation).
    let v = modes.shape(1);
    assert!(rel(v[1] / v[0], -j1 / j2) < 1e-12);
}

#[test]
fn equal_masses_on_equal_springs() {
    // Free-free chain of n equal masses: w_m = 2 sqrt(k/J) sin(m pi / 2n).
    for n in [2_usize, 3, 6, 9, 14] {
        let (j, k) = (0.37, 2.9e5);
        let modes = Chain::new(vec![j; n], vec![k; n - 1])
            .unwrap()
            .modes()
            .unwrap();
        for m in 1..n {
            let closed = 2.0 * (k / j).sqrt() * (m as f64 * PI / (2 * n) as f64).sin();
            // 1e-12 relative, as the issue asks.
            assert!(
                rel(modes.omega[m], closed) < 1e-12,
                "n {n} m {m}: {} against {closed}",
                modes.omega[m]
            );
        }
    }
}

#[test]
fn modes_are_mass_orthogonal() {
    let j = [0.05, 0.021, 0.019, 0.022, 0.02, 0.023, 0.018, 0.6, 1.4];
    let k = [2.1e5, 8.0e5, 7.5e5, 8.2e5, 7.9e5, 8.1e5, 9.0e5, 3.0e4];
    let chain = Chain::new(j.to_vec(), k.to_vec()).unwrap();
    let modes = chain.modes().unwrap();
    let kk = chain.stiffness_matrix();
    let n = j.len();
    let wmax = modes.omega[n - 1];
    for a in 0..n {
        for b in 0..n {
            let m: f64 = (0..n)
                .map(|i| modes.shapes[(i, a)] * j[i] * modes.shapes[(i, b)])
                .sum();
            let expect = if a == b { 1.0 } else { 0.0 };
            // Phi^T M Phi = I to 1e-12.
            assert!((m - expect).abs() < 1e-12, "M {a} {b}: {m}");
            let kab = (modes.shapes.column(a).transpose() * &kk * modes.shapes.column(b))[(0, 0)];
            let expect = if a == b { modes.omega[a].powi(2) } else { 0.0 };
            // Phi^T K Phi = diag(w^2) to 1e-12 of the largest w^2.
            assert!(
                (kab - expect).abs() < 1e-12 * wmax * wmax,
                "K {a} {b}: {kab}"
            );
        }
    }
}

/// A two-mass chain in its relative coordinate `q = θ1 − θ2` is exactly a
/// one-degree-of-freedom system: `M q'' + c q' + k q = T J2/(J1+J2)` with
/// `M = J1 J2/(J1+J2)` and modal damping `c = 2 ζ w_n M`.
#[test]
fn one_degree_of_freedom_at_and_off_resonance() {
    let (j1, j2, k, zeta, t) = (0.4, 1.6, 5.0e4, 0.03, 120.0);
    let chain = Chain::new(vec![j1, j2], vec![k])
        .unwrap()
        .with_damping_ratio(zeta)
        .unwrap();
    let solver = Solver::new(&chain).unwrap();
    let m = j1 * j2 / (j1 + j2);
    let wn = (k / m).sqrt();
    for ratio in [0.3, 0.9, 1.0, 1.1, 2.5] {
        let w = ratio * wn;
        let theta = solver
            .respond(w, &[Complex64::new(t, 0.0), Complex64::new(0.0, 0.0)])
            .unwrap();
        let q = theta[0] - theta[1];
        let closed = Complex64::new(t * j2 / (j1 + j2), 0.0)
            / Complex64::new(k - w * w * m, 2.0 * zeta * wn * m * w);
        // 1e-10 relative: rounding of a 2 x 2 complex solve.
        assert!((q - closed).norm() < 1e-10 * closed.norm(), "ratio {ratio}");
        // The rigid rotation: (J1 θ1 + J2 θ2)/(J1+J2) = T / (−w² (J1+J2)).
        let mean = (theta[0] * j1 + theta[1] * j2) / (j1 + j2);
        let rigid = -t / (w * w * (j1 + j2));
        assert!((mean - rigid).norm() < 1e-10 * rigid.abs());
        if (ratio - 1.0_f64).abs() < 1e-12 {
            // At resonance |q| = T J2/(J1+J2) / (2 ζ k).
            assert!(rel(q.norm(), t * j2 / (j1 + j2) / (2.0 * zeta * k)) < 1e-10);
        }
    }
}

fn six_throw() -> CrankTrain {
    CrankTrain {
        front: Some((0.08, 3.0e5)),
        throws: vec![0.045, 0.047, 0.046, 0.046, 0.047, 0.045],
        journals: vec![9.0e5; 5],
        flywheel: (1.8, 1.1e6),
        load: Some((0.9, 4.0e4)),
        damper: Some(Damper {
            inertia: 0.05,
            stiffness: 1.5e5,
            damping: 25.0,
        }),
        damping_ratio: 0.02,
    }
}

/// Torques at every throw for harmonic `h` of a cycle (an arbitrary but
/// fixed pattern with phases).
fn torques(n: usize, throws: &[usize], h: usize) -> Vec<Complex64> {
    let mut t = vec![Complex64::new(0.0, 0.0); n];
    for (c, &i) in throws.iter().enumerate() {
        let a = 300.0 / (1.0 + h as f64) * (1.0 + 0.1 * c as f64);
        t[i] = Complex64::from_polar(a, -(h as f64) * 2.0 * PI * c as f64 / 3.0 + 0.2 * h as f64);
    }
    t
}

#[test]
fn power_in_equals_power_damped() {
    let (chain, layout) = six_throw().chain().unwrap();
    let solver = Solver::new(&chain).unwrap();
    let n = chain.len();
    let harmonics: Vec<usize> = (1..=48).collect();
    let synth = Synthesis::new(48);
    for rpm in [800.0, 1500.0, 2300.0, 3700.0] {
        let w = rpm * PI / 30.0 / 2.0; // a four-stroke cycle: harmonic h is order h/2
        let mut p_in = 0.0;
        let mut p_out = 0.0;
        let mut resp = Vec::new();
        for &h in &harmonics {
            let t = torques(n, &layout.throws, h);
            let theta = solver.respond(h as f64 * w, &t).unwrap();
            let (a, b) = (
                Solver::power_in(h as f64 * w, &t, &theta),
                solver.power_damped(h as f64 * w, &theta),
            );
            // Order by order, 1e-9 relative.
            assert!(rel(a, b) < 1e-9, "rpm {rpm} h {h}: {a} {b}");
            p_in += a;
            p_out += b;
            resp.push((h, t, theta));
        }
        assert!(rel(p_in, p_out) < 1e-9);
        // The same over a cycle in time: mean of Σ T_i θ'_i against
        // mean of θ'ᵀ C θ' on the synthesis grid (exact for these harmonics).
        let mut torque_t = vec![Vec::new(); n];
        let mut speed_t = vec![Vec::new(); n];
        for i in 0..n {
            let tt: Vec<(usize, Complex64)> = resp.iter().map(|(h, t, _)| (*h, t[i])).collect();
            synth.signal(&tt, &mut torque_t[i]);
            let vv: Vec<(usize, Complex64)> = resp
                .iter()
                .map(|(h, _, th)| (*h, th[i] * Complex64::new(0.0, *h as f64 * w)))
                .collect();
            synth.signal(&vv, &mut speed_t[i]);
        }
        let c = solver.damping_matrix();
        let s = synth.samples();
        let (mut e_in, mut e_out) = (0.0, 0.0);
        for k in 0..s {
            for i in 0..n {
                e_in += torque_t[i][k] * speed_t[i][k];
                for j in 0..n {
                    e_out += speed_t[i][k] * c[(i, j)] * speed_t[j][k];
                }
            }
        }
        // Time domain: 1e-9 relative, and equal to the harmonic sums.
        assert!(rel(e_in, e_out) < 1e-9, "rpm {rpm}: {e_in} {e_out}");
        assert!(rel(e_in / s as f64, p_in) < 1e-9);
    }
}

#[test]
fn huge_stiffness_turns_rigid() {
    let train = six_throw();
    let free_vibration = |scale: f64| {
        let mut t = train.clone();
        t.front = t.front.map(|(j, k)| (j, k * scale));
        t.journals.iter_mut().for_each(|k| *k *= scale);
        t.flywheel.1 *= scale;
        t.load = t.load.map(|(j, k)| (j, k * scale));
        t.damper = t.damper.map(|d| Damper {
            stiffness: d.stiffness * scale,
            ..d
        });
        let (chain, layout) = t.chain().unwrap();
        let solver = Solver::new(&chain).unwrap();
        let total: f64 = chain.inertia().iter().sum();
        let w = 2000.0 * PI / 30.0 / 2.0;
        (1..=48)
            .map(|h| {
                let theta = solver
                    .respond(h as f64 * w, &torques(chain.len(), &layout.throws, h))
                    .unwrap();
                let mean = theta
                    .iter()
                    .zip(chain.inertia())
                    .map(|(a, j)| a * *j)
                    .sum::<Complex64>()
                    / total;
                (theta[layout.free_end] - mean).norm()
            })
            .sum::<f64>()
    };
    let soft = free_vibration(1.0);
    let stiff = free_vibration(1e8);
    assert!(soft > 1e-5, "{soft}");
    // Twist falls as 1/k far above every resonance: 1e8 stiffer, 1e-7 left.
    assert!(stiff < 1e-7 * soft, "{stiff} against {soft}");
}

#[test]
fn one_harmonic_synthesised_is_its_amplitude() {
    let synth = Synthesis::new(48);
    let mut scratch = Vec::new();
    for h in [1_usize, 7, 23, 48] {
        let x = Complex64::from_polar(2.5, 0.37 * h as f64);
        let a = synth.half_peak_to_peak(&[(h, x)], &mut scratch);
        // 16 samples per period of the highest harmonic, refined between
        // samples: 5e-4 relative at the highest (2.6e-4 measured; the
        // unrefined largest sample misses by up to 1.9e-2).
        assert!(rel(a, 2.5) < 5e-4, "h {h}: {a}");
    }
    // Two orders in phase at sample 0: cos θ + cos 2θ peaks at 2, bottoms at −1.125.
    let a = synth.half_peak_to_peak(
        &[(1, Complex64::new(1.0, 0.0)), (2, Complex64::new(1.0, 0.0))],
        &mut scratch,
    );
    assert!(rel(a, (2.0 + 1.125) / 2.0) < 1e-4, "{a}");
}

#[test]
fn layout_names_sections_and_free_end() {
    let (chain, layout) = six_throw().chain().unwrap();
    assert_eq!(chain.len(), 10);
    assert_eq!(layout.names[0], "damper ring");
    assert_eq!(layout.free_end, 1);
    assert_eq!(layout.throws, vec![2, 3, 4, 5, 6, 7]);
    assert_eq!(layout.flywheel, 8);
    assert_eq!(layout.sections.len(), 8);
    assert_eq!(layout.sections[0].name, "front–throw 1");
    assert_eq!(layout.sections[7].name, "flywheel–load");
}

#[test]
fn bad_chains_are_refused() {
    assert!(matches!(
        Chain::new(vec![1.0, 2.0], vec![]),
        Err(TorsionError::Shape {
            what: "springs",
            ..
        })
    ));
    let e = Chain::new(vec![1.0, -2.0], vec![1e4]).unwrap_err();
    assert!(e.to_string().contains("inertia 2"), "{e}");
    assert!(Chain::new(vec![1.0, 2.0], vec![f64::NAN]).is_err());
    let c = Chain::new(vec![1.0, 2.0], vec![1e4]).unwrap();
    assert!(c.clone().with_damping_ratio(1.5).is_err());
    let s = Solver::new(&c).unwrap();
    assert!(s.respond(0.0, &[Complex64::new(1.0, 0.0); 2]).is_err());
    assert!(s.respond(10.0, &[Complex64::new(1.0, 0.0); 3]).is_err());
}
