//! A solver failure is blamed on its true cause (issue 29, item 11): an
//! undamped resonance only when the chain is undamped and the system is
//! finite; a damped chain, or one whose values overflow, is told that
//! its values are too far apart for double precision.

use enginedyn_torsion::{Chain, Complex64, Solver};

fn unit_torque() -> Vec<Complex64> {
    vec![Complex64::new(100.0, 0.0), Complex64::new(0.0, 0.0)]
}

/// A damped chain driven at a frequency whose square overflows: no
/// resonance, so the message must not ask for damping. An undamped chain
/// at its own natural frequency: the resonance is the cause, and the
/// message says so.
#[test]
fn failures_are_blamed_on_their_cause() {
    let chain = Chain::new(vec![1.0, 3.0], vec![1e5])
        .unwrap()
        .with_damping_ratio(0.02)
        .unwrap();
    let solver = Solver::new(&chain).unwrap();
    let err = solver
        .respond(1e200, &unit_torque())
        .expect_err("ω² overflows")
        .to_string();
    assert!(
        !err.contains("undamped") && !err.contains("give a damping ratio"),
        "{err}"
    );
    assert!(
        err.contains("the chain is damped, so no resonance is the cause")
            && err.contains("too far apart for double precision"),
        "{err}"
    );
    // ω² = k (1/J1 + 1/J2) = 1 exactly: K − ω² M is singular.
    let chain = Chain::new(vec![1.0, 1.0], vec![0.5]).unwrap();
    let solver = Solver::new(&chain).unwrap();
    let err = solver
        .respond(1.0, &unit_torque())
        .expect_err("an undamped resonance hit exactly")
        .to_string();
    assert!(
        err.contains("an undamped resonance hit exactly (give a damping ratio above 0)"),
        "{err}"
    );
}

/// Values each finite but whose k/J overflows (1e308 N m/rad: the
/// stiffness matrix's diagonal is 2e308) are refused when the chain is
/// built, not solved into a NaN or blamed on a resonance.
#[test]
fn overflowing_chain_is_refused() {
    let err = Chain::new(vec![1.0, 1.0, 1.0], vec![1e308, 1e308])
        .expect_err("2e308 overflows")
        .to_string();
    assert!(err.contains("too far apart for double precision"), "{err}");
    // A subnormal inertia: 2e6 / 1e-310 is infinite.
    let err = Chain::new(vec![1e-310, 1.0], vec![2e6])
        .expect_err("k/J overflows")
        .to_string();
    assert!(err.contains("mass 1"), "{err}");
}
