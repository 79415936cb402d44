//! `enginedyn firing-orders` end to end: the bundled engines, seed 001's
//! exercises, the output folder, and the exit codes.

use enginedyn_tests::{data, ok_json as json, run};
use serde_json::Value;

fn orders(doc: &Value) -> Vec<Vec<u64>> {
    let mut o: Vec<Vec<u64>> = doc["orders"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| {
            o["firing_order"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_u64().unwrap())
                .collect()
        })
        .collect();
    o.sort();
    o
}

/// An engine file without a diagram, `m_j = 1 kg`, `R = 50 mm`, `lambda = 0.25`.
fn engine_file(dir: &std::path::Path, head: &str) -> String {
    let path = dir.join("engine.toml");
    std::fs::write(
        &path,
        format!(
            "{head}\nbore_mm = 80.0\nstroke_mm = 100.0\nlambda = 0.25\ncompression_ratio = 10.0\n\
             cylinder_spacing_mm = 100.0\n[masses]\npiston_group_kg = 0.7\nrod_kg = 1.0\n\
             rod_cg_from_small_end_mm = 140.0\n[operating]\nrpm = 3000\n"
        ),
    )
    .unwrap();
    path.display().to_string()
}

#[test]
fn vaz2108_orders_and_second_order_force() {
    let doc = json(&[
        "firing-orders",
        "--engine",
        &data("vaz2108.toml"),
        "--json",
        "--step",
        "0.5",
    ]);
    assert_eq!(
        doc["crank_angles_deg"],
        serde_json::json!([0.0, 180.0, 180.0, 0.0])
    );
    assert_eq!(orders(&doc), vec![vec![1, 2, 4, 3], vec![1, 3, 4, 2]]);
    // 4 lambda m_j R w^2: R = 35.5 mm, lambda = 0.26 (L = R / lambda),
    // m_j = 0.45 + 0.52 (L - 99 mm) / L, 4900 rpm.
    let l = 35.5 / 0.26;
    let mj = 0.45 + 0.52 * (l - 99.0) / l;
    let w = 4900.0 * std::f64::consts::PI / 30.0;
    let f2 = 4.0 * 0.26 * mj * 0.0355 * w * w;
    let ff = &doc["free_forces"];
    let got = ff["free_force_2_n"].as_f64().unwrap();
    assert!((got - f2).abs() < 1e-9 * f2, "{got} vs {f2}");
    for key in [
        "free_force_1_n",
        "free_moment_1_nm",
        "free_moment_2_nm",
        "free_moment_1_residual_nm",
    ] {
        assert_eq!(ff[key].as_f64(), Some(0.0), "{key}");
    }
    for o in doc["orders"].as_array().unwrap() {
        for key in [
            "firing_order",
            "intervals_deg",
            "neighbour_consecutive",
            "max_journal_torque_nm",
            "max_journal_harmonic_nm",
            "journal_harmonic_order",
            "score",
        ] {
            assert!(o.get(key).is_some(), "order key {key}");
        }
        assert_eq!(o["neighbour_consecutive"], 2);
        assert!(o["max_journal_torque_nm"].as_f64().unwrap() > 0.0);
    }
}

#[test]
fn bundled_engines_fire_in_an_order_their_crank_admits() {
    // (file, orders on its crank, first-order moment after counterweights is 0)
    for (file, n, residual_zero) in [
        ("i6_diesel.toml", 4, true),
        ("v8_crossplane.toml", 8, true),
        ("v12_60.toml", 32, true),
        ("i3_two_stroke.toml", 1, false),
        ("single.toml", 1, true),
    ] {
        let doc = json(&[
            "firing-orders",
            "--engine",
            &data(file),
            "--json",
            "--step",
            "1",
        ]);
        assert_eq!(doc["orders"].as_array().unwrap().len(), n, "{file}");
        let residual = doc["free_forces"]["free_moment_1_residual_nm"]
            .as_f64()
            .unwrap();
        assert_eq!(residual == 0.0, residual_zero, "{file}: {residual}");
    }
    let v8 = json(&[
        "firing-orders",
        "--engine",
        &data("v8_crossplane.toml"),
        "--json",
        "--step",
        "1",
    ]);
    assert!(orders(&v8).contains(&vec![1, 5, 4, 8, 7, 2, 6, 3]));
    assert!(v8["free_forces"]["free_moment_1_nm"].as_f64().unwrap() > 0.0);
    let v12 = json(&[
        "firing-orders",
        "--engine",
        &data("v12_60.toml"),
        "--json",
        "--step",
        "1",
    ]);
    let best = &v12["orders"][0];
    assert_eq!(
        best["firing_order"],
        serde_json::json!([1, 7, 5, 11, 3, 9, 6, 12, 2, 8, 4, 10])
    );
    assert_eq!(best["scheme"], "alternating");
}

#[test]
fn without_a_diagram_the_journal_figures_are_null() {
    let dir = tempfile::tempdir().unwrap();
    let engine = engine_file(
        dir.path(),
        "cycle = \"four-stroke\"\ncylinders = 8\nfiring_order = [1, 4, 2, 3, 8, 5, 7, 6]",
    );
    let doc = json(&["firing-orders", "--engine", &engine, "--json"]);
    // Seed 001's eight orders.
    let mut seed = vec![
        vec![1, 4, 2, 3, 8, 5, 7, 6],
        vec![1, 4, 2, 6, 8, 5, 7, 3],
        vec![1, 4, 7, 3, 8, 5, 2, 6],
        vec![1, 4, 7, 6, 8, 5, 2, 3],
        vec![1, 5, 2, 3, 8, 4, 7, 6],
        vec![1, 5, 2, 6, 8, 4, 7, 3],
        vec![1, 5, 7, 3, 8, 4, 2, 6],
        vec![1, 5, 7, 6, 8, 4, 2, 3],
    ];
    seed.sort();
    assert_eq!(orders(&doc), seed);
    for o in doc["orders"].as_array().unwrap() {
        assert!(o["max_journal_torque_nm"].is_null());
        assert!(o["max_journal_harmonic_nm"].is_null());
        assert!(o["journal_harmonic_order"].is_null());
    }
    // Best first: the four orders that fire no neighbours in a row.
    let firsts: Vec<u64> = doc["orders"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["neighbour_consecutive"].as_u64().unwrap())
        .collect();
    assert_eq!(firsts, vec![0, 0, 0, 0, 2, 2, 2, 2]);
    assert!(
        doc["notes"]
            .as_array()
            .unwrap()
            .iter()
            .any(|n| n.as_str().unwrap().contains("no indicator diagram"))
    );
}

#[test]
fn seed_001_v12_two_stroke_alternating() {
    let dir = tempfile::tempdir().unwrap();
    let engine = engine_file(
        dir.path(),
        "cycle = \"two-stroke\"\ncylinders = 12\nlayout = \"vee\"\nbank_angle_deg = 30.0\n\
         firing_order = [1, 7, 5, 11, 3, 9, 6, 12, 2, 8, 4, 10]",
    );
    let doc = json(&["firing-orders", "--engine", &engine, "--json"]);
    assert_eq!(doc["orders"].as_array().unwrap().len(), 1);
    let o = &doc["orders"][0];
    assert_eq!(o["scheme"], "alternating");
    assert_eq!(o["intervals_deg"], serde_json::json!(vec![30.0; 12]));
    assert_eq!(
        o["bank_intervals_deg"],
        serde_json::json!(vec![vec![60.0; 6]; 2])
    );
}

#[test]
fn all_cranks_inline_six_mirror_crank_first() {
    let doc = json(&[
        "firing-orders",
        "--engine",
        &data("i6_diesel.toml"),
        "--all-cranks",
        "--json",
        "--step",
        "1",
    ]);
    let cranks = doc["cranks"].as_array().unwrap();
    assert!(cranks.len() > 1);
    let best = &cranks[0];
    assert_eq!(best["engine_crank"], true);
    assert_eq!(best["mirror_symmetric"], true);
    assert_eq!(
        best["crank_angles_deg"],
        serde_json::json!([0.0, 120.0, 240.0, 240.0, 120.0, 0.0])
    );
    assert_eq!(
        best["orders"][0]["firing_order"],
        serde_json::json!([1, 5, 3, 6, 2, 4])
    );
    for c in &cranks[1..] {
        assert_eq!(c["mirror_symmetric"], false);
    }
}

#[test]
fn out_folder_and_weights() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fo");
    let o = run(&[
        "firing-orders",
        "--engine",
        &data("v8_crossplane.toml"),
        "--step",
        "1",
        "--weights",
        "journal=0,neighbours=2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("interleaved") && stdout.contains("wrote 2 files"));
    let csv = std::fs::read_to_string(out.join("firing_orders.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for col in [
        "firing_order",
        "intervals_deg",
        "neighbour_consecutive",
        "max_journal_torque_nm",
        "score",
    ] {
        assert!(header.contains(&col), "{col}");
    }
    assert_eq!(lines.count(), 8);
    let svg = std::fs::read_to_string(out.join("crank_end_view.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("throw 4"));
}

#[test]
fn bad_input_exits_2() {
    let engine = data("vaz2108.toml");
    for args in [
        vec![
            "firing-orders",
            "--engine",
            engine.as_str(),
            "--weights",
            "vibes=1",
        ],
        vec![
            "firing-orders",
            "--engine",
            engine.as_str(),
            "--weights",
            "balance=-1",
        ],
        vec!["firing-orders", "--engine", "/nonexistent/engine.toml"],
        vec![
            "firing-orders",
            "--engine",
            engine.as_str(),
            "--step",
            "0.7",
        ],
    ] {
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
    }
}
