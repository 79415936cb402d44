//! The crank train's reduced inertias: per throw and whole, one home.

use enginedyn_engine::{RodModel, file::parse};

const V8: &str = r#"
cycle = "four-stroke"
cylinders = 8
layout = "vee"
bank_angle_deg = 90
firing_order = [1, 5, 4, 8, 7, 2, 6, 3]
crank_angles_deg = [0, 90, 270, 180]
bore_mm = 100.0
stroke_mm = 90.0
rod_length_mm = 150.0
compression_ratio = 10.0
[masses]
piston_group_kg = 0.6
rod_kg = 0.7
crank_unbalanced_kg = 0.4
[operating]
rpm = 5000
"#;

#[test]
fn throw_inertias_add_up_to_the_crank_train() {
    let e = parse(V8, "v8").unwrap();
    for model in [RodModel::TwoMass, RodModel::Rigid] {
        let sum: f64 = (0..e.throws()).map(|k| e.throw_inertia(k, model)).sum();
        let whole = e.crank_train_inertia(model);
        assert!((sum - whole).abs() <= 1e-12 * whole, "{sum} {whole}");
    }
    // By hand, two-mass rod (l_A = 0.725 L): m_A = 0.275 m_rod, m_B = 0.725 m_rod;
    // one throw carries two rods: m_r = 0.4 + 2 * 0.725 * 0.7, m_j = 0.6 + 0.275 * 0.7.
    let r: f64 = 0.045;
    let lambda = 0.045 / 0.150;
    let mr = 0.4 + 2.0 * 0.725 * 0.7;
    let mj = 0.6 + 0.275 * 0.7;
    let expect = mr * r * r + 2.0 * mj * r * r * (0.5 + lambda * lambda / 8.0);
    let got = e.throw_inertia(2, RodModel::TwoMass);
    assert!((got - expect).abs() <= 1e-12 * expect, "{got} {expect}");
    assert_eq!(e.cylinders_on_throw(0), 2);
}
