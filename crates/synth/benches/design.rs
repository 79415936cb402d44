//! Criterion benchmark of one synthesised operating point (issue 35: at
//! most 5 ms at 0.1°): the design cycle of a petrol four's cylinder (CA50
//! 8°, 10–90 in 20°, m = 2) solved for IMEP 9 bar and sampled at 0.1°,
//! with a constant γ and with Brunt's γ(T); and a diesel's double Wiebe.
//! `cargo bench -p enginedyn-synth --bench design`.

use criterion::{Criterion, criterion_group, criterion_main};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
use enginedyn_synth::{BurnLaw, DEFAULT_A, DesignModel, GammaModel, Load, Wiebe, design_trace};
use std::hint::black_box;

fn points(c: &mut Criterion) {
    let cs = CrankSlider::new(0.0355, 0.0355 / 0.26, 0.0).unwrap();
    let cyl = Cylinder::new(Mechanism::CrankSlider(cs), 0.076, 9.9).unwrap();
    let petrol = BurnLaw::single(Wiebe::from_ca50(8.0, 20.0, 2.0, DEFAULT_A).unwrap());
    let diesel = BurnLaw::double(
        Wiebe::new(-4.0, 10.0, DEFAULT_A, 2.0).unwrap(),
        Wiebe::new(-2.0, 60.0, DEFAULT_A, 0.8).unwrap(),
        0.8,
    )
    .unwrap();
    let brunt = GammaModel::Brunt {
        ivc_deg: -140.0,
        intake_temp_k: 320.0,
    };
    for (name, burn, g) in [
        ("petrol, γ 1.32", petrol, GammaModel::Constant(1.32)),
        ("petrol, γ(T)", petrol, brunt),
        (
            "diesel double Wiebe, γ 1.32",
            diesel,
            GammaModel::Constant(1.32),
        ),
    ] {
        let m = DesignModel::new(burn, Load::Imep { pa: 9.0e5 }, g, false);
        c.bench_function(
            &format!("design point at 0.1°, IMEP 9 bar solved: {name}"),
            |b| b.iter(|| design_trace(black_box(&cyl), black_box(&m), 0.1).unwrap()),
        );
        let h = DesignModel {
            load: Load::Heat { j: 600.0 },
            ..m
        };
        c.bench_function(&format!("design point at 0.1°, heat given: {name}"), |b| {
            b.iter(|| design_trace(black_box(&cyl), black_box(&h), 0.1).unwrap())
        });
    }
}

criterion_group!(benches, points);
criterion_main!(benches);
