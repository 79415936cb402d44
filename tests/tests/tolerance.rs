//! `enginedyn tolerance` end to end: every bundled engine gives the table,
//! the stack-up, the Monte Carlo check and the three files.

use enginedyn_tests::binary;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(binary())
        .args(args)
        .output()
        .expect("run enginedyn")
}

fn data(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(file)
}

const BUNDLED: [&str; 7] = [
    "vaz2108",
    "single",
    "i3_two_stroke",
    "i6_diesel",
    "v8_crossplane",
    "v12_60",
    "scotch_yoke",
];

const RESULTS: [&str; 16] = [
    "mean_torque_nm",
    "imep_bar",
    "torque_max_nm",
    "torque_min_nm",
    "excess_work_j",
    "required_inertia_kg_m2",
    "crankpin_load_max_n",
    "compression_ratio",
    "clearance_volume_m3",
    "stroke_m",
    "free_force_1_n",
    "free_force_2_n",
    "free_moment_1_nm",
    "free_moment_2_nm",
    "torque_order_0_5_nm",
    "torque_order_1_nm",
];

const STACK_KEYS: [&str; 6] = [
    "nominal",
    "worst_case",
    "rss",
    "monte_carlo_std",
    "monte_carlo_max_dev",
    "linearity_error",
];

/// Runs the study on the 0.5° grid (fast in a debug build) with `samples`
/// Monte Carlo samples into a temporary folder.
fn study(engine: &str, samples: &str, extra: &[&str]) -> (Output, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let engine = data(&format!("{engine}.toml"));
    let mut args = vec![
        "tolerance",
        "--engine",
        engine.to_str().unwrap(),
        "--step",
        "0.5",
        "--samples",
        samples,
        "--out",
        dir.path().to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    (run(&args), dir)
}

fn csv_rows(dir: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(dir.join("tolerance.csv"))
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// Every bundled engine: exit 0, the readable table on standard output,
/// `tolerance.csv` with INTERFACE.md's columns and one row per parameter
/// and result, `tolerance.json` with the stack-up keys for every result,
/// and a whole SVG tornado chart.
#[test]
fn every_bundled_engine_gives_the_study() {
    for name in BUNDLED {
        let (out, dir) = study(name, "100", &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
        let stdout = String::from_utf8_lossy(&out.stdout);
        for part in ["stack-up", "worst case", "RSS σ", "MC σ", "contributions"] {
            assert!(stdout.contains(part), "{name}: no {part} in\n{stdout}");
        }
        let rows = csv_rows(dir.path());
        assert_eq!(
            rows[0],
            [
                "parameter",
                "tolerance",
                "result",
                "nominal",
                "sensitivity",
                "influence",
                "deviation"
            ]
        );
        for r in &rows[1..] {
            assert_eq!(r.len(), 7, "{name}: {r:?}");
            assert!(RESULTS.contains(&r[2].as_str()), "{name}: {r:?}");
            for k in [1, 3, 4, 6] {
                assert!(r[k].parse::<f64>().unwrap().is_finite(), "{name}: {r:?}");
            }
            // deviation = |sensitivity| × tolerance
            let (t, s, d): (f64, f64, f64) = (
                r[1].parse().unwrap(),
                r[4].parse().unwrap(),
                r[6].parse().unwrap(),
            );
            assert!(
                (d - s.abs() * t).abs() <= 1e-12 * d.abs().max(1e-300),
                "{r:?}"
            );
        }
        let json: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join("tolerance.json")).unwrap(),
        )
        .unwrap();
        for result in RESULTS {
            if name == "i3_two_stroke" && result == "torque_order_0_5_nm" {
                assert!(json.get(result).is_none(), "a two-stroke has no order 0.5");
                continue;
            }
            let r = json
                .get(result)
                .unwrap_or_else(|| panic!("{name}: no {result}"));
            for k in STACK_KEYS {
                assert!(r.get(k).is_some(), "{name}: {result} lacks {k}");
            }
            assert!(r["monte_carlo_std"].is_number(), "{name}: {result}");
            let (wc, rss) = (
                r["worst_case"].as_f64().unwrap(),
                r["rss"].as_f64().unwrap(),
            );
            assert!(
                rss <= wc + 1e-300,
                "{name}: {result}: RSS above the worst case"
            );
            // linearity_error = |monte_carlo_std - rss| / rss
            if rss > 0.0 {
                let mc = r["monte_carlo_std"].as_f64().unwrap();
                let lin = r["linearity_error"].as_f64().unwrap();
                assert!((lin - (mc - rss).abs() / rss).abs() < 1e-12 * lin.max(1.0));
            } else {
                assert!(r["linearity_error"].is_null());
            }
        }
        let svg = std::fs::read_to_string(dir.path().join("tolerance.svg")).unwrap();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("mean torque = "));
        // The three files and the manifest of what the run wrote.
        let leftovers: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n != enginedyn_report::MANIFEST)
            .collect();
        assert_eq!(leftovers.len(), 3, "{name}: {leftovers:?}");
    }
}

/// The diesel's compression ratio against its rod length in the CSV is the
/// closed form `(eps - 1)² / S` = 16² / 150 per mm; a balanced engine's
/// first-order free force is 0 with no relative influence.
#[test]
fn the_csv_holds_the_closed_forms() {
    let (out, dir) = study("i6_diesel", "0", &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows = csv_rows(dir.path());
    let row = rows
        .iter()
        .find(|r| r[0] == "rod_length_mm" && r[2] == "compression_ratio")
        .unwrap();
    let s: f64 = row[4].parse().unwrap();
    assert!((s - 256.0 / 150.0).abs() < 1e-9, "{s}");
    for r in rows.iter().filter(|r| r[2] == "free_force_1_n") {
        assert_eq!(r[5], "", "{r:?}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("tolerance.json")).unwrap())
            .unwrap();
    assert!(
        json["free_force_1_n"]["monte_carlo_std"].is_null(),
        "--samples 0"
    );
    assert_eq!(json["free_force_1_n"]["zero_nominal"], true);
}

/// The same seed writes the same numbers; another seed others.
#[test]
fn the_seed_reproduces_the_monte_carlo() {
    let json = |seed: &str| {
        let (out, dir) = study("single", "100", &["--seed", seed]);
        assert!(out.status.success());
        std::fs::read_to_string(dir.path().join("tolerance.json")).unwrap()
    };
    let a = json("5");
    assert_eq!(a, json("5"));
    assert_ne!(a, json("6"));
}

/// An engine file without `[tolerances]` (or with a key the mechanism does
/// not have) is a bad engine file: exit 2, saying what is missing, nothing
/// written.
#[test]
fn no_tolerances_is_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(data("vaz2108.toml")).unwrap();
    let head = &text[..text.find("[tolerances]").unwrap()];
    let diagram = data("vaz2108.csv");
    let head = head.replace(
        "diagram = \"vaz2108.csv\"",
        &format!("diagram = {:?}", diagram.to_str().unwrap()),
    );
    let engine = dir.path().join("plain.toml");
    std::fs::write(&engine, &head).unwrap();
    let out_dir = dir.path().join("out");
    let out = run(&[
        "tolerance",
        "--engine",
        engine.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("[tolerances]") && err.contains("plain.toml"),
        "{err}"
    );
    assert!(!out_dir.exists());
    let yoke_rod = dir.path().join("yoke.toml");
    let yoke = std::fs::read_to_string(data("scotch_yoke.toml"))
        .unwrap()
        .replace("tdc_deg = 0.1", "tdc_deg = 0.1\nrod_length_mm = 0.05")
        .replace(
            "diagram = \"scotch_yoke.csv\"",
            &format!("diagram = {:?}", data("scotch_yoke.csv").to_str().unwrap()),
        );
    std::fs::write(&yoke_rod, yoke).unwrap();
    let out = run(&["tolerance", "--engine", yoke_rod.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("rod_length_mm"));
}
