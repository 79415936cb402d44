//! Split crank pins and the crank search end to end: the bundled 90° V6,
//! `firing-orders --all-cranks` without a firing order, and the crank end
//! view's legend.

use enginedyn_tests::{data, ok_json, run};

/// The bundled V6 runs end to end; its diagram's IMEP (10.228 bar, the
/// generator's own figure in the CSV header) comes back to 1e-3 bar.
#[test]
fn bundled_v6_runs() {
    let s = ok_json(&["run", "--engine", &data("v6_90.toml"), "--json"]);
    let imep = s["imep_bar"].as_f64().unwrap();
    assert!((imep - 10.228).abs() < 1e-3, "IMEP {imep}");
    let fo = ok_json(&["firing-orders", "--engine", &data("v6_90.toml"), "--json"]);
    assert_eq!(
        fo["crank_angles_deg"],
        serde_json::json!([0.0, 120.0, 240.0, 30.0, 150.0, 270.0])
    );
    let best = &fo["orders"][0];
    assert_eq!(best["firing_order"], serde_json::json!([1, 4, 3, 6, 2, 5]));
    assert_eq!(best["intervals_deg"], serde_json::json!(vec![120.0; 6]));
}

/// An engine file without `firing_order`: `run` refuses it (exit 2) and
/// names the command that finds one; `firing-orders --all-cranks` runs.
#[test]
fn all_cranks_without_firing_order() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("v6.toml");
    std::fs::write(
        &path,
        "cycle = \"four-stroke\"\ncylinders = 6\nlayout = \"vee\"\nbank_angle_deg = 90\n\
         bore_mm = 101.6\nstroke_mm = 88.4\nrod_length_mm = 144.8\ncompression_ratio = 9.2\n\
         cylinder_spacing_mm = 111.8\n[masses]\npiston_group_kg = 0.75\nrod_kg = 0.65\n\
         [operating]\nrpm = 4400\n",
    )
    .unwrap();
    let p = path.to_str().unwrap();
    let out = run(&["run", "--engine", p, "--diagram", &data("v6_90.csv")]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("missing key `firing_order`") && err.contains("firing-orders --all-cranks"),
        "{err}"
    );
    let doc = ok_json(&["firing-orders", "--all-cranks", "--engine", p, "--json"]);
    let crank = &doc["cranks"][0];
    assert_eq!(
        crank["crank_angles_deg"],
        serde_json::json!([0.0, 120.0, 240.0, 30.0, 150.0, 270.0])
    );
    assert_eq!(
        crank["orders"][0]["firing_order"],
        serde_json::json!([1, 4, 3, 6, 2, 5])
    );
    // With the diagram the journal torques are ranked too.
    let doc = ok_json(&[
        "firing-orders",
        "--all-cranks",
        "--engine",
        p,
        "--diagram",
        &data("v6_90.csv"),
        "--json",
    ]);
    assert!(
        doc["cranks"][0]["orders"][0]["max_journal_torque_nm"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    // Without --all-cranks the order is still needed.
    let out = run(&["firing-orders", "--engine", p]);
    assert_eq!(out.status.code(), Some(2));
}

/// The end view names each cylinder's place in the firing sequence
/// ("cyl 1 fires 1st") and, with split pins, draws each cylinder's own pin.
#[test]
fn end_view_legend_reads_fires_first() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("vaz");
    let out = run(&[
        "firing-orders",
        "--engine",
        &data("vaz2108.toml"),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(out_dir.join("crank_end_view.svg")).unwrap();
    // The view shows the best order (ranked by the score): each cylinder
    // by its place in it.
    let doc = ok_json(&["firing-orders", "--engine", &data("vaz2108.toml"), "--json"]);
    let best: Vec<u64> = doc["orders"][0]["firing_order"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .collect();
    for (place, c) in best.iter().zip(["1st", "2nd", "3rd", "4th"]) {
        let want = format!("cyl {c} fires {place}", c = place, place = c);
        assert!(svg.contains(&want), "{want} not in the end view");
    }
    let out_dir = dir.path().join("v6");
    let out = run(&[
        "firing-orders",
        "--engine",
        &data("v6_90.toml"),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(out_dir.join("crank_end_view.svg")).unwrap();
    for want in [
        "throw 1, pin at 0°: cyl 1 fires 1st",
        "throw 1, pin at 30°: cyl 4 fires 2nd",
        "throw 3, pin at 270°: cyl 6 fires 4th",
    ] {
        assert!(svg.contains(want), "{want} not in the end view");
    }
}
