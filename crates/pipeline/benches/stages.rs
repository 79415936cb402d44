//! Criterion benchmarks of each stage on the bundled VAZ-2108 example at the
//! default 0.1° grid: parse, grid (interpolation), kinematics, forces,
//! summation, flywheel, the whole analysis, and the charts.
//! `cargo bench -p enginedyn-pipeline`.

use criterion::{Criterion, criterion_group, criterion_main};
use enginedyn_engine::RodModel;
use enginedyn_forces::{Setup, cylinder_forces};
use enginedyn_ingest::{GridOptions, Interp, ParseOptions, load, parse};
use enginedyn_kinematics::{Model, Table};
use enginedyn_numerics::integrate::Rule;
use enginedyn_pipeline::{Options, analyse};
use std::hint::black_box;

const ENGINE: &str = include_str!("../../../data/vaz2108.toml");
const DIAGRAM: &str = include_str!("../../../data/vaz2108.csv");

fn stages(c: &mut Criterion) {
    let engine = enginedyn_engine::file::parse(ENGINE, "vaz2108").unwrap();
    let cyl = *engine.cylinder();
    let mut po = ParseOptions::new(720.0);
    po.cylinder = Some(cyl);
    let grid = GridOptions::new(0.1, Interp::Auto);
    c.bench_function("parse 1440 rows", |b| {
        b.iter(|| parse(black_box(DIAGRAM.as_bytes()), &po).unwrap())
    });
    c.bench_function("parse + spline onto 7200 points", |b| {
        b.iter(|| load(black_box(DIAGRAM.as_bytes()), &po, &grid).unwrap())
    });
    let r = load(DIAGRAM.as_bytes(), &po, &grid).unwrap();
    let h = 0.1_f64.to_radians();
    let mut kin = Table::default();
    c.bench_function("kinematics, 7200 points", |b| {
        b.iter(|| {
            engine
                .mechanism()
                .fill(Model::Exact, 0.0, h, 7200, &mut kin)
                .unwrap()
        })
    });
    engine
        .mechanism()
        .fill(Model::Exact, 0.0, h, 7200, &mut kin)
        .unwrap();
    let setup = Setup::new(&engine, RodModel::TwoMass, 513.0);
    c.bench_function("forces, 7200 points", |b| {
        b.iter(|| cylinder_forces(&setup, &kin, black_box(&r.pressure), 0.0, h))
    });
    let f = cylinder_forces(&setup, &kin, &r.pressure, 0.0, h);
    c.bench_function("summation by firing order, 4 cylinders", |b| {
        b.iter(|| enginedyn_torque::sum(&engine, h, |_| black_box(&f.torque)))
    });
    let t = enginedyn_torque::sum(&engine, h, |_| &f.torque);
    c.bench_function("uniformity and flywheel", |b| {
        b.iter(|| {
            let u = enginedyn_flywheel::Uniformity::new(black_box(&t.total), h, Rule::Trapezoid);
            enginedyn_flywheel::analyse(&u, engine.flywheel(), 513.0, 0.0).unwrap()
        })
    });
    c.bench_function("whole analysis (pipeline::analyse)", |b| {
        b.iter(|| analyse(&engine, black_box(&r), 4900.0, &Options::default()).unwrap())
    });
    let a = analyse(&engine, &r, 4900.0, &Options::default()).unwrap();
    c.bench_function("all charts, report.html and CSVs", |b| {
        b.iter(|| enginedyn_report::run_files(&engine, black_box(&a), false).unwrap())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(300)).measurement_time(std::time::Duration::from_secs(1));
    targets = stages
}
criterion_main!(benches);
