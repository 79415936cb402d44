//! Textbook balance facts, seed 001's firing-order exercises, and the
//! bundled engines. Tolerances: closed-form figures to 1e-9 relative (the
//! phasor sums are exact up to rounding).

use enginedyn_balance::*;
use enginedyn_engine::{Engine, RodModel};
use std::f64::consts::SQRT_2;

/// An engine with `m_j = 1 kg` (two-mass rod: 0.7 kg piston group plus the
/// rod's small-end share 0.3 kg), `R = 0.05 m`, `lambda = 0.25`, `s = 0.1 m`.
fn engine(head: &str) -> Engine {
    let toml = format!(
        "{head}\nbore_mm = 80.0\nstroke_mm = 100.0\nlambda = 0.25\ncompression_ratio = 10.0\n\
         cylinder_spacing_mm = 100.0\n[masses]\npiston_group_kg = 0.7\nrod_kg = 1.0\n\
         rod_cg_from_small_end_mm = 140.0\n[operating]\nrpm = 3000\n"
    );
    enginedyn_engine::file::parse(&toml, "test").expect("test engine")
}

const OMEGA: f64 = 100.0;
const LAMBDA: f64 = 0.25;

/// Free forces of `e` in units of `m_j R w^2` and `m_j R w^2 s`.
fn unit_free(e: &Engine) -> FreeForces {
    let mj = e.reciprocating_mass(RodModel::TwoMass);
    assert!((mj - 1.0).abs() < 1e-12, "m_j = {mj}");
    let f = mj * e.mechanism().r() * OMEGA * OMEGA;
    FreeForces::of_engine(e, RodModel::TwoMass, OMEGA).scaled(f, f * e.cylinder_spacing())
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-9 * want.abs().max(1.0),
        "{what}: got {got}, want {want}"
    );
}

fn crank_deg(e: &Engine) -> Vec<f64> {
    e.crank_angles()
        .iter()
        .map(|a| (a.to_degrees() * 1e9).round() / 1e9)
        .collect()
}

#[test]
fn inline_four_second_order_force_no_first_order_moment() {
    let e = engine("cycle = \"four-stroke\"\ncylinders = 4\nfiring_order = [1, 3, 4, 2]");
    assert_eq!(crank_deg(&e), vec![0.0, 180.0, 180.0, 0.0]);
    let f = unit_free(&e);
    close(f.free_force_1_n, 0.0, "F1");
    close(f.free_force_2_n, 4.0 * LAMBDA, "F2 = 4 lambda m_j R w^2");
    close(f.free_moment_1_nm, 0.0, "M1");
    close(f.free_moment_2_nm, 0.0, "M2");
}

#[test]
fn inline_six_fully_balanced() {
    let e = engine("cycle = \"four-stroke\"\ncylinders = 6\nfiring_order = [1, 5, 3, 6, 2, 4]");
    let f = unit_free(&e);
    for (v, what) in [
        (f.free_force_1_n, "F1"),
        (f.free_force_2_n, "F2"),
        (f.free_moment_1_nm, "M1"),
        (f.free_moment_2_nm, "M2"),
        (f.free_moment_1_residual_nm, "M1 residual"),
    ] {
        close(v, 0.0, what);
    }
}

#[test]
fn inline_three_moments() {
    for cycle in ["four-stroke", "two-stroke"] {
        let e = engine(&format!(
            "cycle = \"{cycle}\"\ncylinders = 3\nfiring_order = [1, 3, 2]"
        ));
        let f = unit_free(&e);
        close(f.free_force_1_n, 0.0, "F1");
        close(f.free_force_2_n, 0.0, "F2");
        close(f.free_moment_1_nm, 3f64.sqrt(), "M1 = sqrt 3");
        close(
            f.free_moment_2_nm,
            3f64.sqrt() * LAMBDA,
            "M2 = sqrt 3 lambda",
        );
        // Counterweights take the half rotating with the crank.
        close(
            f.free_moment_1_residual_nm,
            3f64.sqrt() / 2.0,
            "M1 residual",
        );
    }
}

#[test]
fn cross_plane_v8_first_order_moment_all_cancelled_by_counterweights() {
    let e = engine(
        "cycle = \"four-stroke\"\ncylinders = 8\nlayout = \"vee\"\nbank_angle_deg = 90.0\n\
         firing_order = [1, 5, 4, 8, 7, 2, 6, 3]\ncrank_angles_deg = [0.0, 90.0, 270.0, 180.0]",
    );
    let f = unit_free(&e);
    close(f.free_force_1_n, 0.0, "F1");
    close(f.free_force_2_n, 0.0, "F2");
    // |sum a_k exp(-j alpha_k)| = |-1.5 + 0.5j + 0.5j - 1.5| = sqrt 10.
    close(f.free_moment_1_nm, 10f64.sqrt(), "M1 = sqrt 10");
    close(f.free_moment_2_nm, 0.0, "M2");
    close(f.free_moment_1_residual_nm, 0.0, "M1 after counterweights");
}

#[test]
fn flat_plane_v8_keeps_a_second_order_force() {
    let e = engine(
        "cycle = \"four-stroke\"\ncylinders = 8\nlayout = \"vee\"\nbank_angle_deg = 90.0\n\
         firing_order = [1, 5, 3, 7, 4, 8, 2, 6]\ncrank_angles_deg = [0.0, 180.0, 180.0, 0.0]",
    );
    let f = unit_free(&e);
    close(f.free_force_1_n, 0.0, "F1");
    // Two inline fours' 4 lambda at +-45° to the vertical: 4 sqrt 2 lambda, horizontal.
    close(
        f.free_force_2_n,
        4.0 * SQRT_2 * LAMBDA,
        "F2 = 4 sqrt 2 lambda",
    );
    close(f.free_moment_1_nm, 0.0, "M1");
    close(f.free_moment_2_nm, 0.0, "M2");
}

#[test]
fn single_cylinder_forces_about_its_own_plane() {
    let e = engine("cycle = \"four-stroke\"\ncylinders = 1");
    let f = unit_free(&e);
    close(f.free_force_1_n, 1.0, "F1");
    close(f.free_force_2_n, LAMBDA, "F2");
    close(f.free_moment_1_nm, 0.0, "M1");
}

#[test]
fn moments_depend_on_the_reference_point_only_with_a_free_force() {
    // Inline four, flat crank: shifting every axial position by 1 m changes
    // the second-order moment by 1 m times the second-order force.
    let e = engine("cycle = \"four-stroke\"\ncylinders = 4\nfiring_order = [1, 3, 4, 2]");
    let mut cyl = CylinderMass::of_engine(&e, RodModel::TwoMass);
    let r = e.mechanism().r();
    let base = free_forces(&cyl, r, LAMBDA, OMEGA);
    for c in &mut cyl {
        c.axial_position += 1.0;
    }
    let moved = free_forces(&cyl, r, LAMBDA, OMEGA);
    close(
        moved.free_moment_1_nm,
        base.free_moment_1_nm,
        "M1 (no first-order force)",
    );
    close(
        moved.free_moment_2_nm,
        base.free_force_2_n,
        "M2 about a point 1 m away",
    );
}

/// Seed 001, exercise 1: an eight-cylinder inline four-stroke on the
/// mirror-symmetric crank of 1-4-2-3-8-5-7-6. The seed lists eight orders,
/// each marked by the cylinder pairs swapped from the first.
#[test]
fn seed_001_inline_eight_orders() {
    let e =
        engine("cycle = \"four-stroke\"\ncylinders = 8\nfiring_order = [1, 4, 2, 3, 8, 5, 7, 6]");
    let crank = crank_deg(&e);
    assert_eq!(
        crank,
        vec![0.0, 180.0, 270.0, 90.0, 90.0, 270.0, 180.0, 0.0]
    );
    assert!(is_mirror_symmetric(&crank));
    let train = Train::of_engine(&e);
    let orders = firing_orders(&train, &crank).unwrap();
    // The seed's list, with our own count of neighbour-consecutive firings
    // (cyclic, closing back to cylinder 1 as the seed writes them).
    let seed: [([usize; 8], usize); 8] = [
        ([1, 4, 2, 3, 8, 5, 7, 6], 2), // 2-3, 7-6
        ([1, 4, 2, 6, 8, 5, 7, 3], 0), // (3/6)
        ([1, 4, 7, 3, 8, 5, 2, 6], 0), // (2/7)
        ([1, 4, 7, 6, 8, 5, 2, 3], 2), // (3/6, 2/7): 7-6, 2-3
        ([1, 5, 2, 3, 8, 4, 7, 6], 2), // (4/5): 2-3, 7-6
        ([1, 5, 2, 6, 8, 4, 7, 3], 0), // (4/5, 3/6)
        ([1, 5, 7, 3, 8, 4, 2, 6], 0), // (4/5, 2/7)
        ([1, 5, 7, 6, 8, 4, 2, 3], 2), // (4/5, 3/6, 2/7): 7-6, 2-3
    ];
    let got: Vec<(Vec<usize>, usize)> = orders
        .iter()
        .map(|o| (o.order.clone(), criteria(&train, o).neighbour_consecutive))
        .collect();
    let want: Vec<(Vec<usize>, usize)> = seed.iter().map(|(o, n)| (o.to_vec(), *n)).collect();
    assert_eq!(got, want);
    // Every order fires every 90°.
    for o in &orders {
        assert!(
            criteria(&train, o)
                .intervals_deg
                .iter()
                .all(|&i| (i - 90.0).abs() < 1e-9)
        );
    }
}

/// Seed 001, exercise 2: a 12-cylinder vee two-stroke, alternating scheme,
/// each bank firing 1-5-3-6-2-4. Bank 1 fires every 60°; bank 2 must fill
/// the 30° gaps, so its throw + bank angle must be an odd multiple of 30°:
/// 30°, 90° or 150°.
#[test]
fn seed_001_v12_two_stroke_bank_angle() {
    // Bank 1 order 1-5-3-6-2-4 every 60°: throw lags 0, 240, 120, 300, 60, 180.
    let crank = [0.0, 240.0, 120.0, 300.0, 60.0, 180.0];
    let e = engine(
        "cycle = \"two-stroke\"\ncylinders = 12\nlayout = \"vee\"\nbank_angle_deg = 30.0\n\
         firing_order = [1, 7, 5, 11, 3, 9, 6, 12, 2, 8, 4, 10]",
    );
    assert_eq!(crank_deg(&e), crank.to_vec());
    let train = Train::of_engine(&e);
    let angles = even_firing_bank_angles(&train, &crank).unwrap();
    let degs: Vec<f64> = angles.iter().map(|a| a.0).collect();
    assert_eq!(degs, vec![30.0, 90.0, 150.0]);
    let expected = [
        (30.0, vec![1, 7, 5, 11, 3, 9, 6, 12, 2, 8, 4, 10]),
        (90.0, vec![1, 10, 5, 7, 3, 11, 6, 9, 2, 12, 4, 8]),
        (150.0, vec![1, 8, 5, 10, 3, 7, 6, 11, 2, 9, 4, 12]),
    ];
    for (deg, order) in expected {
        let t = train.with_bank_angle(deg);
        let orders = firing_orders(&t, &crank).unwrap();
        assert_eq!(orders.len(), 1, "a two-stroke crank fixes its order");
        assert_eq!(orders[0].order, order, "bank angle {deg}");
        let c = criteria(&t, &orders[0]);
        assert_eq!(c.scheme, Some(Scheme::Alternating));
        assert!(c.intervals_deg.iter().all(|&i| (i - 30.0).abs() < 1e-9));
        assert_eq!(c.bank_intervals_deg, vec![vec![60.0; 6], vec![60.0; 6]]);
        assert_eq!(c.neighbour_consecutive, 0);
    }
    // 60°: bank 2 would fire together with bank 1.
    assert!(
        firing_orders(&train.with_bank_angle(60.0), &crank)
            .unwrap()
            .is_empty()
    );
}

/// A 90° V8 on a crank with 0-90-180-270 throws fires evenly only in an
/// interleaved scheme: the banks' own intervals are uneven.
#[test]
fn v8_interleaved_scheme() {
    let e = engine(
        "cycle = \"four-stroke\"\ncylinders = 8\nlayout = \"vee\"\nbank_angle_deg = 90.0\n\
         firing_order = [1, 5, 4, 8, 7, 2, 6, 3]\ncrank_angles_deg = [0.0, 90.0, 270.0, 180.0]",
    );
    let train = Train::of_engine(&e);
    let orders = firing_orders(&train, &crank_deg(&e)).unwrap();
    assert!(orders.iter().any(|o| o.order == e.firing_order()));
    for o in &orders {
        let c = criteria(&train, o);
        assert_eq!(c.scheme, Some(Scheme::Interleaved));
        assert!(c.interval_spread > 0.0);
        assert!(c.intervals_deg.iter().all(|&i| (i - 90.0).abs() < 1e-9));
    }
}

fn ranked(head: &str) -> Study {
    let e = engine(head);
    let setup = Setup {
        engine: &e,
        rod_model: RodModel::TwoMass,
        omega: OMEGA,
        torque: None,
        weights: Weights::default(),
    };
    study(&setup, true).unwrap()
}

#[test]
fn all_cranks_inline_four_ranked_as_textbooks() {
    let s = ranked("cycle = \"four-stroke\"\ncylinders = 4\nfiring_order = [1, 3, 4, 2]");
    let cranks: Vec<Vec<f64>> = s
        .cranks
        .iter()
        .map(|c| c.crank_angles_deg.clone())
        .collect();
    // Flat (mirror) crank first: no first-order moment; then 0-180-0-180
    // (moment 2 m_j R w^2 s) before 0-0-180-180 (4 m_j R w^2 s).
    assert_eq!(
        cranks,
        vec![
            vec![0.0, 180.0, 180.0, 0.0],
            vec![0.0, 180.0, 0.0, 180.0],
            vec![0.0, 0.0, 180.0, 180.0],
        ]
    );
    assert!(s.cranks[0].engine_crank && s.cranks[0].mirror_symmetric);
}

#[test]
fn all_cranks_inline_six_ranked_as_textbooks() {
    let s = ranked("cycle = \"four-stroke\"\ncylinders = 6\nfiring_order = [1, 5, 3, 6, 2, 4]");
    assert_eq!(s.set, CrankSet::All);
    let best = &s.cranks[0];
    assert_eq!(
        best.crank_angles_deg,
        vec![0.0, 120.0, 240.0, 240.0, 120.0, 0.0]
    );
    assert!(best.mirror_symmetric);
    assert!(best.free.free_moment_1_nm < 1e-9 && best.free.free_moment_2_nm < 1e-9);
    // The mirror-symmetric crank is the only fully balanced one.
    for c in &s.cranks[1..] {
        assert!(!c.mirror_symmetric);
        assert!(c.free.free_moment_1_nm > 1e-6 || c.free.free_moment_2_nm > 1e-6);
    }
    // Its orders: 1-5-3-6-2-4 with no neighbours in a row is the best.
    assert_eq!(best.orders[0].order.order, vec![1, 5, 3, 6, 2, 4]);
    assert_eq!(best.orders[0].criteria.neighbour_consecutive, 0);
}

#[test]
fn all_cranks_inline_eight_ranked_as_textbooks() {
    let s =
        ranked("cycle = \"four-stroke\"\ncylinders = 8\nfiring_order = [1, 4, 2, 3, 8, 5, 7, 6]");
    assert_eq!(s.set, CrankSet::All);
    // The fully balanced cranks (first and second order) come first, and
    // they are exactly the mirror-symmetric ones.
    let balanced = |c: &CrankStudy| {
        let f = c.free;
        f.free_force_1_n + f.free_force_2_n + f.free_moment_1_nm + f.free_moment_2_nm < 1e-6
    };
    let n_bal = s.cranks.iter().filter(|c| balanced(c)).count();
    assert!(n_bal >= 1);
    for (k, c) in s.cranks.iter().enumerate() {
        assert_eq!(balanced(c), k < n_bal, "crank {:?}", c.crank_angles_deg);
        assert_eq!(
            c.mirror_symmetric,
            balanced(c),
            "crank {:?}",
            c.crank_angles_deg
        );
    }
    // The seed's crank is among them, and its best orders fire no neighbours in a row.
    let seed = s
        .cranks
        .iter()
        .find(|c| c.engine_crank)
        .expect("seed crank listed");
    assert!(balanced(seed));
    assert_eq!(seed.orders[0].criteria.neighbour_consecutive, 0);
}

#[test]
fn all_cranks_inline_twelve_mirror_symmetric_and_fast() {
    let t = std::time::Instant::now();
    let s = ranked(
        "cycle = \"four-stroke\"\ncylinders = 12\nfiring_order = [1, 7, 5, 11, 3, 9, 6, 12, 2, 8, 4, 10]",
    );
    assert_eq!(s.set, CrankSet::MirrorSymmetric);
    assert!(s.notes.iter().any(|n| n.contains("mirror-symmetric")));
    assert!(
        s.cranks
            .iter()
            .all(|c| c.mirror_symmetric && c.orders.len() == 32)
    );
    // Unoptimised test build: generous; the release binary takes a fraction.
    assert!(t.elapsed().as_secs_f64() < 30.0);
}

#[test]
fn orders_per_crank_count() {
    // Four-stroke inline, even z: 2^(z/2 - 1) orders on a crank that fires evenly.
    for z in [2usize, 4, 6, 8, 10, 12] {
        let order: Vec<String> = (1..=z).map(|i| i.to_string()).collect();
        let e = engine(&format!(
            "cycle = \"four-stroke\"\ncylinders = {z}\nfiring_order = [{}]",
            order.join(", ")
        ));
        let n = firing_orders(&Train::of_engine(&e), &crank_deg(&e))
            .unwrap()
            .len();
        assert_eq!(n, 1 << (z / 2 - 1), "z = {z}");
    }
    // Odd z and two-stroke: the crank fixes the order.
    for head in [
        "cycle = \"four-stroke\"\ncylinders = 5\nfiring_order = [1, 2, 4, 5, 3]",
        "cycle = \"two-stroke\"\ncylinders = 6\nfiring_order = [1, 6, 2, 4, 3, 5]",
    ] {
        let e = engine(head);
        let o = firing_orders(&Train::of_engine(&e), &crank_deg(&e)).unwrap();
        assert_eq!(o.len(), 1);
        assert_eq!(o[0].order, e.firing_order());
    }
}

#[test]
fn boxer_orders() {
    // Flat four boxer 1-3-2-4 (odd cylinders bank 1).
    let e = engine(
        "cycle = \"four-stroke\"\ncylinders = 4\nlayout = \"boxer\"\nfiring_order = [1, 4, 2, 3]",
    );
    let train = Train::of_engine(&e);
    let orders = firing_orders(&train, &crank_deg(&e)).unwrap();
    assert!(orders.iter().any(|o| o.order == e.firing_order()));
    let f = unit_free(&e);
    // Opposed pistons on throws 180° apart move together: no free force.
    close(f.free_force_1_n, 0.0, "F1");
    close(f.free_force_2_n, 0.0, "F2");
}

/// Cylinder torque `cos(phi / 2)` (engine order 0.5) on an inline four
/// 1-3-4-2: the journal after throw 2 carries `|1 + j| = sqrt 2`; the
/// engine torque has no order 0.5 at all.
#[test]
fn journal_torques_of_a_half_order_cylinder_torque() {
    let e = engine("cycle = \"four-stroke\"\ncylinders = 4\nfiring_order = [1, 3, 4, 2]");
    let n = 720;
    let step = (720.0f64 / n as f64).to_radians();
    let m: Vec<f64> = (0..n).map(|k| (k as f64 * step / 2.0).cos()).collect();
    for order in [[1, 3, 4, 2], [1, 2, 4, 3]] {
        let v = engine_with(&e, &crank_deg(&e), &order).unwrap();
        let j = journal_criteria(&v, step, &m).unwrap();
        close(j.max_harmonic_nm, SQRT_2, "largest journal harmonic");
        close(j.harmonic_order, 0.5, "its order");
        assert_eq!(j.harmonic_journal, 2);
        close(j.max_torque_nm, SQRT_2, "largest journal torque");
        assert!(j.engine_torque_max_nm < 1e-9);
    }
}

/// The journal harmonics are taken from the journal torque every 1°: on a
/// 0.1° grid they agree with a 1° grid's for a torque of orders to 12.
#[test]
fn journal_harmonics_do_not_depend_on_the_grid() {
    let e = engine("cycle = \"four-stroke\"\ncylinders = 6\nfiring_order = [1, 5, 3, 6, 2, 4]");
    let m = |phi: f64| {
        (phi / 2.0).cos()
            + 0.3 * (3.0 * phi + 1.0).cos()
            + 0.1 * (7.5 * phi - 0.4).cos()
            + 0.05 * (12.0 * phi).sin()
    };
    let at = |step_deg: f64| {
        let n = (720.0 / step_deg).round() as usize;
        let step = step_deg.to_radians();
        let torque: Vec<f64> = (0..n).map(|k| m(k as f64 * step)).collect();
        journal_criteria(&e, step, &torque).unwrap()
    };
    let (fine, coarse) = (at(0.1), at(1.0));
    close(
        fine.max_harmonic_nm,
        coarse.max_harmonic_nm,
        "largest harmonic",
    );
    close(fine.harmonic_order, coarse.harmonic_order, "its order");
    close(
        fine.engine_harmonic_max_nm,
        coarse.engine_harmonic_max_nm,
        "engine's",
    );
    assert_eq!(fine.harmonic_journal, coarse.harmonic_journal);
}

#[test]
fn weights_parse() {
    assert_eq!(Weights::parse("").unwrap(), Weights::default());
    let w = Weights::parse("intervals=0,neighbours=2.5,journal=1,balance=4").unwrap();
    assert_eq!((w.intervals, w.neighbours, w.balance), (0.0, 2.5, 4.0));
    assert!(matches!(
        Weights::parse("balance=-1"),
        Err(BalanceError::BadWeight { .. })
    ));
    assert!(matches!(
        Weights::parse("balance"),
        Err(BalanceError::BadWeight { .. })
    ));
    assert!(matches!(
        Weights::parse("vibes=1"),
        Err(BalanceError::UnknownWeight { .. })
    ));
}

/// A 90° V6 on split pins, each bank-2 pin 30° behind its bank-1 partner
/// (throws 0-120-240; the GM 4.3 even-fire crank): it fires every 120°.
const V6_90_SPLIT: &str = "cycle = \"four-stroke\"\ncylinders = 6\nlayout = \"vee\"\n\
     bank_angle_deg = 90.0\nfiring_order = [1, 4, 3, 6, 2, 5]\n\
     crank_angles_deg = [0.0, 120.0, 240.0, 30.0, 150.0, 270.0]";

/// Closed form. Each bank is an inline three on 0-120-240 with throws at
/// `a_k = (k - 2) s`: no free force of either order, a couple of
/// `A = |sum a_k exp(j alpha_k)| = |-1 + exp(j240°)| = sqrt 3` (m_j R w² s)
/// along its own axis. Bank 2's couple lags bank 1's by bank + split =
/// 120°, its axis 90° on: rotating with the crank `(A/2)|1 + exp(j(90 - 120)°)|
/// = A cos 15°`, against it `(A/2)|1 + exp(j(90 + 120)°)| = A sin 15°`. So
/// `M1 = sqrt 3 (cos 15° + sin 15°) = 3/sqrt 2`, of which counterweights
/// leave `sqrt 3 sin 15° = 0.4483` (the residual couple the 4.3 Vortec's
/// balance shaft is for); second order: the lag doubles to 240°, the parts
/// swap, `M2 = lambda sqrt 3 (sin 15° + cos 15°)`.
#[test]
fn split_pin_v6_90_free_forces_closed_form() {
    let e = engine(V6_90_SPLIT);
    assert!(e.split_pins());
    let f = unit_free(&e);
    let (c15, s15) = (15f64.to_radians().cos(), 15f64.to_radians().sin());
    let root3 = 3f64.sqrt();
    close(f.free_force_1_n, 0.0, "F1");
    close(f.free_force_2_n, 0.0, "F2");
    close(f.free_moment_1_nm, root3 * (c15 + s15), "M1");
    close(f.free_moment_1_nm, 3.0 / SQRT_2, "M1 = 3/sqrt 2");
    close(
        f.free_moment_1_residual_nm,
        root3 * s15,
        "M1 after counterweights",
    );
    close(f.free_moment_2_nm, LAMBDA * root3 * (c15 + s15), "M2");
    // The engine's crank admits its order, every 120°, the banks alternating.
    let train = Train::of_engine(&e);
    let orders = firing_orders(&train, &crank_deg(&e)).unwrap();
    let own = orders
        .iter()
        .find(|o| o.order == e.firing_order())
        .expect("the engine's order");
    let c = criteria(&train, own);
    assert_eq!(c.intervals_deg, vec![120.0; 6]);
    assert_eq!(c.scheme, Some(Scheme::Alternating));
}

/// A 60° V6 with each bank-2 pin 60° behind (bank + split = 120°): the same
/// couples, bank 2's axis 60° on: against the crank `(A/2)|1 + exp(j(60 +
/// 120)°)| = 0`, so counterweights cancel the whole first-order couple,
/// `M1 = A cos 30° = 1.5`; second order all against the crank,
/// `M2 = lambda A cos 30° = 1.5 lambda`.
#[test]
fn split_pin_v6_60_first_order_couple_balanced_by_counterweights() {
    let e = engine(
        "cycle = \"four-stroke\"\ncylinders = 6\nlayout = \"vee\"\nbank_angle_deg = 60.0\n\
         firing_order = [1, 4, 3, 6, 2, 5]\ncrank_angles_deg = [0, 120, 240, 60, 180, 300]",
    );
    let mut f = e.firing_angles().to_vec();
    f.sort_by(f64::total_cmp);
    for (k, a) in f.iter().enumerate() {
        close(a.to_degrees(), 120.0 * k as f64, "even firing");
    }
    let f = unit_free(&e);
    close(f.free_force_1_n, 0.0, "F1");
    close(f.free_force_2_n, 0.0, "F2");
    close(f.free_moment_1_nm, 1.5, "M1");
    close(f.free_moment_1_residual_nm, 0.0, "M1 after counterweights");
    close(f.free_moment_2_nm, 1.5 * LAMBDA, "M2");
}

/// `--all-cranks` without a firing order: no shared-pin crank of a 90° V6
/// fires evenly, so the split-pin cranks with the smallest split (30°) are
/// ranked; the best is the even-fire crank, fired 1-4-3-6-2-5.
#[test]
fn all_cranks_v6_90_without_firing_order_finds_split_pins() {
    let toml = "cycle = \"four-stroke\"\ncylinders = 6\nlayout = \"vee\"\nbank_angle_deg = 90.0\n\
         bore_mm = 80.0\nstroke_mm = 100.0\nlambda = 0.25\ncompression_ratio = 10.0\n\
         cylinder_spacing_mm = 100.0\n[masses]\npiston_group_kg = 0.7\nrod_kg = 1.0\n\
         rod_cg_from_small_end_mm = 140.0\n";
    assert!(enginedyn_engine::file::parse(toml, "v6").is_err());
    let e = enginedyn_engine::file::parse_for_crank_search(toml, "v6").unwrap();
    let setup = Setup {
        engine: &e,
        rod_model: RodModel::TwoMass,
        omega: OMEGA,
        torque: None,
        weights: Weights::default(),
    };
    let s = study(&setup, true).unwrap();
    assert_eq!(s.cranks.len(), 1, "{:?}", s.cranks);
    let c = &s.cranks[0];
    assert_eq!(
        c.crank_angles_deg,
        vec![0.0, 120.0, 240.0, 30.0, 150.0, 270.0]
    );
    assert!(!c.engine_crank, "the engine has no crank of its own");
    assert_eq!(c.orders[0].order.order, vec![1, 4, 3, 6, 2, 5]);
    for o in &c.orders {
        assert_eq!(o.criteria.intervals_deg, vec![120.0; 6]);
    }
    assert!(
        s.notes
            .iter()
            .any(|n| n.contains("each bank-2 pin 30° behind its bank-1 partner")),
        "{:?}",
        s.notes
    );
    // Its own crank alone needs a firing order.
    assert!(study(&setup, false).is_err());
}

/// Journal torques on split pins: a cylinder torque `cos(phi/2)` on the
/// 90° V6 above (firing 0, 480, 240, 120, 600, 360° for cylinders 1..6).
/// Journal after throw 1 (cylinders 1, 4): `|1 + exp(-j60°)| = sqrt 3`;
/// after throw 2 (+ 2, 5 at half-angles 240°, 300°): still `sqrt 3`; the
/// engine (all six, half-angles 60° apart) carries nothing.
#[test]
fn journal_torques_on_split_pins() {
    let e = engine(V6_90_SPLIT);
    let n = 720;
    let step = (720.0f64 / n as f64).to_radians();
    let m: Vec<f64> = (0..n).map(|k| (k as f64 * step / 2.0).cos()).collect();
    let v = engine_with(&e, &crank_deg(&e), e.firing_order()).unwrap();
    assert_eq!(v.firing_angles(), e.firing_angles());
    let j = journal_criteria(&v, step, &m).unwrap();
    close(j.max_harmonic_nm, 3f64.sqrt(), "largest journal harmonic");
    close(j.harmonic_order, 0.5, "its order");
    close(j.max_torque_nm, 3f64.sqrt(), "largest journal torque");
    assert!(j.engine_torque_max_nm < 1e-9);
}
