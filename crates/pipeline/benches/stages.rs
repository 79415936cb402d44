//! Criterion benchmarks of each stage on the bundled VAZ-2108 example at the
//! default 0.1° grid: parse, grid (interpolation), kinematics, forces,
//! summation, flywheel, the whole analysis, and the charts; then one file
//! of the issue-8 bench batch (inline-6, 50 cycles at 0.1°, the layout of
//! `../shared/bench/make_batch.py`): read only, read and grid, and the
//! analysis with shared `Tables` as `batch` runs it.
//! `GLIBC_TUNABLES=glibc.malloc.trim_threshold=67108864 cargo bench -p
//! enginedyn-pipeline` (the setting the CLI makes itself at start).

use criterion::{Criterion, criterion_group, criterion_main};
use enginedyn_engine::RodModel;
use enginedyn_forces::{Setup, cylinder_forces};
use enginedyn_ingest::{GridOptions, Interp, ParseOptions, load, parse};
use enginedyn_kinematics::{Model, Table};
use enginedyn_numerics::integrate::Rule;
use enginedyn_pipeline::{Options, Scope, Tables, analyse, analyse_with};
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
        b.iter(|| enginedyn_torque::sum(&engine, h, |_| black_box(&f.torque), true))
    });
    c.bench_function(
        "summation by firing order, 4 cylinders, extremes only",
        |b| b.iter(|| enginedyn_torque::sum(&engine, h, |_| black_box(&f.torque), false)),
    );
    let t = enginedyn_torque::sum(&engine, h, |_| &f.torque, true);
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
    let inputs = enginedyn_report::Inputs::new(
        enginedyn_report::Source::Bundled(b"engine"),
        &[enginedyn_report::Source::Bundled(b"diagram")],
    )
    .unwrap();
    c.bench_function("all charts, report.html and CSVs", |b| {
        b.iter(|| enginedyn_report::run_files(&engine, black_box(&a), false, &inputs).unwrap())
    });
}

const BENCH_ENGINE: &str = r#"name = "bench inline-6 diesel"
cycle = "four-stroke"
cylinders = 6
layout = "inline"
firing_order = [1, 5, 3, 6, 2, 4]
bore_mm = 130.0
stroke_mm = 150.0
rod_length_mm = 265.0
compression_ratio = 17.0
[masses]
piston_group_kg = 3.9
rod_kg = 4.2
[operating]
rpm = 2200
[flywheel]
speed_fluctuation = 0.005
"#;

/// One file of the bench batch, per file as `batch` handles it: the
/// compute after reading is (read and grid − read only) + analysis.
fn batch_file(c: &mut Criterion) {
    let engine = enginedyn_engine::file::parse(BENCH_ENGINE, "bench").unwrap();
    let mut po = ParseOptions::new(720.0);
    po.cylinder = Some(*engine.cylinder());
    let mut grid = GridOptions::new(0.1, Interp::Auto);
    grid.cylinder = Some(*engine.cylinder());
    // The bundled VAZ trace on 0.1°, scaled per cycle, written like
    // make_batch.py: cycle,crank_deg,pressure_bar with %d,%.1f,%.5f.
    let vaz = load(
        DIAGRAM.as_bytes(),
        &po,
        &GridOptions::new(0.1, Interp::Auto),
    )
    .unwrap();
    let mut text = String::from("cycle,crank_deg,pressure_bar\n");
    for cycle in 0..50 {
        let f = 1.0 + 0.002 * f64::from(cycle % 7);
        for (k, p) in vaz.pressure.iter().enumerate() {
            let a = k as f64 * 0.1;
            text.push_str(&format!("{cycle},{a:.1},{:.5}\n", p * f / 1e5));
        }
    }
    let bytes = text.into_bytes();
    c.bench_function("bench file: read only, 360000 rows", |b| {
        b.iter(|| enginedyn_ingest::parse_stream(black_box(&bytes[..]), &po, |_| Ok(())).unwrap())
    });
    c.bench_function("bench file: read and grid (50 cycles)", |b| {
        b.iter(|| load(black_box(&bytes[..]), &po, &grid).unwrap())
    });
    let r = load(&bytes[..], &po, &grid).unwrap();
    let opts = Options {
        scope: Scope::Summary,
        ..Options::default()
    };
    let tables = Tables::new(&engine, 7200, &opts).unwrap();
    c.bench_function(
        "bench file: analysis, shared tables, 6 x 7200 cylinder-samples",
        |b| b.iter(|| analyse_with(Some(&tables), &engine, black_box(&r), 2200.0, &opts).unwrap()),
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(300)).measurement_time(std::time::Duration::from_secs(1));
    targets = stages, batch_file
}
criterion_main!(benches);
