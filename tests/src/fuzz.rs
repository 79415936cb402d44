//! The checks the fuzz targets (`fuzz/fuzz_targets/*.rs`, nightly,
//! libFuzzer) and the stable property tests (`tests/tests/fuzz_paths.rs`,
//! in CI) run on the same inputs: the paths the CLI takes, not a side door.
//!
//! - [`diagram_stream`]: the streaming reader and the grid accumulator
//!   (`ingest::load`, what `run` and `batch` call), under the option
//!   combinations the CLI produces;
//! - [`engine_file`]: the engine-file parser and builder;
//! - [`whole_run`]: a diagram through the whole pipeline and every output
//!   file of `run --out` (charts and page included) on a small grid.
//!
//! The contract each asserts: no panic, no hang, and no NaN or infinity in
//! anything produced (bad input is an error): on the grid, in the summary
//! (every null with a note) and in curves.csv (no cell left empty).

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Peg};

const ENGINE: &str = include_str!("../../data/vaz2108.toml");

/// The option combinations of the CLI for a diagram, indexed by one byte.
fn options(pick: u8) -> (ParseOptions, GridOptions) {
    let two_stroke = pick & 1 != 0;
    let mut parse = ParseOptions::new(if two_stroke { 360.0 } else { 720.0 });
    parse.gauge = pick & 2 != 0;
    if pick & 4 != 0 {
        parse.tdc_deg = 123.4;
    }
    if pick & 8 != 0 {
        // One cycle per column (`...`) or two named columns.
        let last = if pick & 64 != 0 {
            "pressure_bar..."
        } else {
            "pressure_bar"
        };
        parse.columns = Some(vec!["crank_deg".into(), last.into()]);
    }
    parse.max_cylinder = 4;
    let mut grid = GridOptions::new(4.0, Interp::Auto);
    match pick >> 4 & 3 {
        1 => grid.peg = Some(Peg::Bar(1e5)),
        2 => grid.interp = Interp::Linear,
        3 => grid.interp = Interp::Pchip,
        _ => {}
    }
    if pick & 128 != 0 {
        // A time record's flags: a clock, a charge amplifier, pegging.
        parse.tdc_time = Some(0.001);
        parse.rpm = Some(1500.0);
        parse.gain_bar_per_v = Some(20.0);
        parse.max_gap_deg = 90.0;
        grid.peg = Some(Peg::Bar(1e5));
    }
    // As the CLI: pegged traces are relative.
    parse.relative = grid.peg.is_some();
    (parse, grid)
}

/// [`options`], and the second round's flags (issue 29) picked by `more`:
/// a speed that may contradict a pulse, `--tdc-time` beyond any record, a
/// gain a million times too large, a skipped line, a second sheet, the
/// widest `--max-gap`.
fn options2(pick: u8, more: u8) -> (ParseOptions, GridOptions) {
    let (mut parse, mut grid) = options(pick);
    if more & 1 != 0 {
        parse.rpm = Some(4900.0);
    }
    if more & 2 != 0 {
        parse.tdc_time = Some(1e9);
        parse.rpm.get_or_insert(1500.0);
    }
    if more & 4 != 0 {
        parse.gain_bar_per_v = Some(1e6);
        grid.peg = Some(Peg::Bar(1e5));
        parse.relative = true;
    }
    if more & 8 != 0 {
        parse.skip_lines = 1;
    }
    if more & 16 != 0 {
        parse.sheet = Some(enginedyn_ingest::Sheet::Index(2));
    }
    if more & 32 != 0 {
        parse.max_gap_deg = enginedyn_ingest::MAX_GAP_BOUND_DEG;
    }
    (parse, grid)
}

/// The highest pressure (Pa) a grid may hold: the plausibility pass's
/// 1000 bar, plus the pegging offset and an interpolant's overshoot.
const MAX_GRID_PA: f64 = 1.1e8;

/// `data` through the streaming reader onto a 4° grid, under the option
/// combination `pick` and `more`: an error, or finite values within the
/// plausibility bound on a whole grid.
pub fn diagram_stream(data: &[u8], pick: u8, more: u8) {
    let (parse, grid) = options2(pick, more);
    let Ok(r) = enginedyn_ingest::load(data, &parse, &grid) else {
        return;
    };
    let n = (parse.cycle_deg / grid.step_deg).round() as usize;
    assert_eq!(r.pressure.len(), n, "grid length");
    for trace in std::iter::once(&r.pressure).chain(&r.cylinders) {
        assert_eq!(trace.len(), n, "a cylinder's grid length");
        assert!(
            trace.iter().all(|p| p.is_finite()),
            "a non-finite value on the grid"
        );
        assert!(
            trace.iter().all(|p| *p <= MAX_GRID_PA),
            "a pressure above the plausibility bound on the grid"
        );
    }
}

/// `data` as an engine file: an error, or an engine whose notes and
/// derived figures are finite.
pub fn engine_file(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(e) = enginedyn_engine::file::parse(&text, "fuzz") else {
        return;
    };
    let _ = e.plausibility_notes(e.operating().rpm);
    for rod in enginedyn_engine::RodModel::ALL {
        if let Ok(e) = e.with_rod_model(rod) {
            assert!(e.reciprocating_mass(rod).is_finite());
        }
    }
    assert!(e.cylinder().swept_volume().is_finite());
}

/// `data` as the bundled engine's diagram through the whole pipeline and
/// every file of `run --out` on a 4° grid: an error, or outputs without a
/// NaN or an infinity. True when it got as far as the outputs.
pub fn whole_run(data: &[u8]) -> bool {
    let engine = enginedyn_engine::file::parse(ENGINE, "vaz2108").expect("the bundled engine");
    let (mut parse, mut grid) = options(0);
    parse.cylinder = Some(*engine.cylinder());
    grid.cylinder = Some(*engine.cylinder());
    let Ok(r) = enginedyn_ingest::load(data, &parse, &grid) else {
        return false;
    };
    if r.quantity != enginedyn_ingest::Quantity::Pressure {
        return false;
    }
    let rpm = r.rpm.unwrap_or(4900.0);
    let opts = enginedyn_pipeline::Options {
        step_deg: 4.0,
        ..enginedyn_pipeline::Options::default()
    };
    let Ok(a) = enginedyn_pipeline::analyse(&engine, &r, rpm, &opts) else {
        return false;
    };
    // The writers turn a non-finite number into a null or an empty cell,
    // so the check is on what the pipeline produced: every figure it gives
    // is finite, every null has a note, and no curve cell is left empty.
    let s = &a.summary;
    for key in enginedyn_pipeline::KEYS {
        if let Some(v) = (key.get)(s).and_then(|v| v.as_number()) {
            match v {
                Some(x) => assert!(x.is_finite(), "{} = {x}", key.key),
                None => assert!(!s.notes.is_empty(), "{} is null with no note", key.key),
            }
        }
    }
    let inputs = enginedyn_report::Inputs::new(
        enginedyn_report::Source::Bundled(b"engine"),
        &[enginedyn_report::Source::Bundled(b"diagram")],
    )
    .expect("hashes of bytes");
    let files =
        enginedyn_report::run_files(&engine, &a, false, &inputs).expect("the outputs render");
    let curves = files
        .iter()
        .find(|(name, _)| name == "curves.csv")
        .map(|(_, b)| String::from_utf8_lossy(b).into_owned())
        .expect("curves.csv");
    let columns = curves.lines().next().unwrap_or("").split(',').count();
    for (k, line) in curves.lines().enumerate().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells.len(), columns, "curves.csv line {}", k + 1);
        assert!(
            !cells.contains(&""),
            "curves.csv line {}: an empty cell (a NaN)",
            k + 1
        );
    }
    true
}
