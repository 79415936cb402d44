//! Criterion benchmark of `enginedyn torsion`'s computation on the bundled
//! inline-6 diesel (6 throws, its `[torsion]` section): the excitation
//! (each cylinder's gas and per-ω² inertia torque split into orders up to
//! 24, computed once) and the study over 50 speeds (modes, the forced
//! response of every order at every speed, the time synthesis). Target of
//! issue 24: under 50 ms. `cargo bench -p enginedyn-pipeline --bench torsion`.

use criterion::{Criterion, criterion_group, criterion_main};
use enginedyn_ingest::{GridOptions, Interp, ParseOptions, load};
use enginedyn_pipeline::{MAX_ORDER, Options, analyse, torsion};
use std::hint::black_box;

const ENGINE: &str = include_str!("../../../data/i6_diesel.toml");
const DIAGRAM: &str = include_str!("../../../data/i6_diesel.csv");

fn bench(c: &mut Criterion) {
    let engine = enginedyn_engine::file::parse(ENGINE, "i6_diesel").unwrap();
    let spec = enginedyn_engine::file::parse_torsion(ENGINE)
        .unwrap()
        .expect("the bundled i6 has [torsion]");
    let mut po = ParseOptions::new(720.0);
    po.cylinder = Some(*engine.cylinder());
    let grid = GridOptions::new(0.1, Interp::Auto);
    let r = load(DIAGRAM.as_bytes(), &po, &grid).unwrap();
    let rpm = r.rpm.or(engine.operating().rpm).unwrap();
    let opts = Options::default();
    let a = analyse(&engine, &r, rpm, &opts).unwrap();
    let train = torsion::crank_train(
        &engine,
        &spec,
        engine.rod_model(),
        a.flywheel.as_ref().map(|f| f.inertia),
    )
    .unwrap();
    let rpms: Vec<f64> = (0..50).map(|k| rpm * (0.2 + k as f64 / 49.0)).collect();
    c.bench_function("torsion: excitation, orders to 24", |b| {
        b.iter(|| torsion::excitation(&engine, black_box(&r), &opts, MAX_ORDER).unwrap())
    });
    let ex = torsion::excitation(&engine, &r, &opts, MAX_ORDER).unwrap();
    c.bench_function("torsion: study, 50 speeds", |b| {
        b.iter(|| torsion::study(&train, black_box(&ex), &rpms).unwrap())
    });
    c.bench_function(
        "torsion: excitation and study (the command's compute)",
        |b| {
            b.iter(|| {
                let ex = torsion::excitation(&engine, black_box(&r), &opts, MAX_ORDER).unwrap();
                torsion::study(&train, &ex, &rpms).unwrap()
            })
        },
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
