//! The fuzz targets' checks (`enginedyn_tests::fuzz`), run on stable in CI
//! as property tests: arbitrary bytes, and valid diagram and engine files
//! with random edits (cells swapped for edge values, bytes changed, lines
//! cut), through the streaming reader, the engine-file parser and a whole
//! run. `PROPTEST_CASES` sets a longer search.

use enginedyn_tests::fuzz::{diagram_stream, engine_file, whole_run};
use proptest::prelude::*;

fn config(cases: u32) -> ProptestConfig {
    let base = if std::env::var_os("PROPTEST_CASES").is_some() {
        ProptestConfig::default()
    } else {
        ProptestConfig::with_cases(cases)
    };
    ProptestConfig {
        failure_persistence: None,
        ..base
    }
}

/// Cells that broke readers before: tiny, huge, signed zeros, words, and
/// numbers too big for an integer.
const EDGE: &[&str] = &[
    "1e-310",
    "1e308",
    "-0",
    "0",
    "nan",
    "inf",
    "-1",
    "1.5",
    "3e8",
    "4294967296",
    "18446744073709551617",
    "",
    "\"",
    "1,5",
    "#",
    "x",
];

/// A small valid diagram: `cycle`, angle and pressure columns, and a
/// `cylinder` column with the bundled engine's 4 cylinders when
/// `per_cylinder`.
fn diagram(step: u32, cycles: u32, per_cylinder: bool) -> String {
    let mut s = String::from("# rpm = 3000\n");
    s.push_str(if per_cylinder {
        "cycle,cylinder,crank_deg,pressure_bar\n"
    } else {
        "cycle,crank_deg,pressure_bar\n"
    });
    for c in 1..=cycles {
        for z in 1..=if per_cylinder { 4 } else { 1 } {
            for k in 0..(720 / step) {
                let a = (k * step) as f64;
                let d = (a - 10.0 + 360.0).rem_euclid(720.0) - 360.0;
                let p = 1.0 + 50.0 * (-(d / 30.0).powi(2)).exp();
                let cyl = if per_cylinder {
                    format!("{z},")
                } else {
                    String::new()
                };
                s.push_str(&format!("{c},{cyl}{a},{p:.4}\n"));
            }
        }
    }
    s
}

/// A text with edits: some cells replaced by edge values, some bytes
/// changed, maybe cut short.
fn edited(base: String) -> impl Strategy<Value = Vec<u8>> {
    let n = base.len().max(1);
    (
        prop::collection::vec((0..n, 0..EDGE.len()), 0..4),
        prop::collection::vec((0..n, any::<u8>()), 0..3),
        prop::option::weighted(0.2, 0..n),
    )
        .prop_map(move |(cells, bytes, cut)| {
            let mut text = base.clone().into_bytes();
            for (at, e) in cells {
                // Replace the cell that holds byte `at` by an edge value.
                let start = text[..at.min(text.len())]
                    .iter()
                    .rposition(|b| *b == b',' || *b == b'\n')
                    .map_or(0, |k| k + 1);
                let end = text[start..]
                    .iter()
                    .position(|b| *b == b',' || *b == b'\n')
                    .map_or(text.len(), |k| start + k);
                text.splice(start..end, EDGE[e].bytes());
            }
            for (at, b) in bytes {
                if let Some(x) = text.get_mut(at) {
                    *x = b;
                }
            }
            if let Some(c) = cut {
                text.truncate(c);
            }
            text
        })
}

fn diagrams() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        prop::collection::vec(any::<u8>(), 0..600),
        (
            prop_oneof![Just(2u32), Just(5), Just(8), Just(10)],
            1..3u32,
            any::<bool>()
        )
            .prop_flat_map(|(step, cycles, cyl)| edited(diagram(step, cycles, cyl))),
    ]
}

fn engines() -> impl Strategy<Value = Vec<u8>> {
    let base = include_str!("../../data/vaz2108.toml").to_string();
    let edge = prop::sample::select(EDGE.to_vec());
    prop_oneof![
        prop::collection::vec(any::<u8>(), 0..300),
        edited(base.clone()),
        // A value after `= ` swapped for an edge value.
        (0..40usize, edge).prop_map(move |(k, e)| {
            let mut lines: Vec<String> = base.lines().map(str::to_string).collect();
            let idx = k % lines.len();
            if let Some((key, _)) = lines[idx].split_once('=') {
                lines[idx] = format!("{key}= {e}");
            }
            lines.join("\n").into_bytes()
        }),
    ]
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn streaming_reader(data in diagrams(), pick in any::<u8>(), more in any::<u8>()) {
        diagram_stream(&data, pick, more);
    }

    #[test]
    fn engine_files(data in engines()) {
        engine_file(&data);
    }
}

proptest! {
    #![proptest_config(config(24))]

    #[test]
    fn whole_runs(data in diagrams()) {
        let _ = whole_run(&data);
    }
}

/// The MDF4 fixtures asammdf wrote (`tests/fixtures/measured`), bytes
/// changed anywhere (its blocks of metadata lie after the data) and maybe
/// cut: the MDF4 source under the CLI's option combinations.
fn mdf_files() -> impl Strategy<Value = Vec<u8>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/measured/");
    let files: Vec<Vec<u8>> = ["mdf_angle_master.mf4", "mdf_time_master_dz.mf4"]
        .iter()
        .map(|f| std::fs::read(format!("{dir}{f}")).expect("an MDF4 fixture"))
        .collect();
    (
        0..files.len(),
        prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 0..6),
        prop::option::weighted(0.2, any::<prop::sample::Index>()),
    )
        .prop_map(move |(f, edits, cut)| {
            let mut b = files[f].clone();
            for (at, x) in edits {
                let i = at.index(b.len());
                b[i] = x;
            }
            if let Some(c) = cut {
                b.truncate(c.index(b.len()));
            }
            b
        })
}

proptest! {
    #![proptest_config(config(48))]

    #[test]
    fn mdf_sources(data in mdf_files(), pick in any::<u8>(), more in any::<u8>()) {
        diagram_stream(&data, pick, more);
    }
}

/// The generators reach the deep paths: unedited diagrams run whole, one
/// trace for all cylinders and one per cylinder.
#[test]
fn valid_diagrams_run_whole() {
    assert!(whole_run(diagram(5, 2, false).as_bytes()));
    assert!(whole_run(diagram(8, 1, true).as_bytes()));
}

/// The committed seeds of the fuzzer (`fuzz/seeds/diagram_stream`, the
/// second round's hostile inputs, written by `fuzz/seeds/make_seeds.py`):
/// each passes the streaming reader's checks under the options its first
/// two bytes pick.
#[test]
fn fuzz_seeds() {
    let dir = format!(
        "{}/../fuzz/seeds/diagram_stream",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut n = 0;
    for e in std::fs::read_dir(dir).expect("the seed folder") {
        let bytes = std::fs::read(e.unwrap().path()).unwrap();
        if let [pick, more, rest @ ..] = &bytes[..] {
            diagram_stream(rest, *pick, *more);
            n += 1;
        }
    }
    assert!(n >= 20, "{n} seeds");
}
