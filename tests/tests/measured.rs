//! Measured diagrams as other tools write them (issue 22): every fixture of
//! `tests/fixtures/measured/expected.json` read by the binary with the flags
//! a user would give, against the outcome and the IMEP its generator
//! computed independently (`make_fixtures.py`: ∮ p dV in NumPy from the
//! slider-crank volume law), to the tolerance stated there for each file.

use enginedyn_tests::run;
use serde_json::Value;

fn root() -> String {
    format!("{}/..", env!("CARGO_MANIFEST_DIR"))
}

fn check(e: &Value) -> Vec<String> {
    let file = format!("{}/{}", root(), e["file"].as_str().unwrap_or_default());
    let engine = format!("{}/data/single.toml", root());
    let mut args: Vec<String> = vec![
        "run".into(),
        "--engine".into(),
        engine,
        "--diagram".into(),
        file,
    ];
    for f in e["flags"].as_array().into_iter().flatten() {
        args.push(f.as_str().unwrap_or_default().into());
    }
    args.push("--json".into());
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = run(&refs);
    let mut bad = Vec::new();
    let code = out.status.code().unwrap_or(-1);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if i64::from(code) != e["exit"].as_i64().unwrap_or(-2) {
        bad.push(format!("exit {code}, expected {}: {stderr}", e["exit"]));
        return bad;
    }
    let want = e["notes_or_error_contain"].as_str();
    if code != 0 {
        if let Some(w) = want
            && !stderr.contains(w)
        {
            bad.push(format!("error lacks {w:?}: {stderr}"));
        }
        // Every error names the file.
        if !stderr.contains(e["file"].as_str().unwrap_or("?")) {
            bad.push(format!("error does not name the file: {stderr}"));
        }
        return bad;
    }
    let s: Value = match serde_json::from_slice(&out.stdout) {
        Ok(s) => s,
        Err(err) => return vec![format!("no JSON: {err}")],
    };
    let notes: Vec<&str> = s["notes"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(Value::as_str)
        .collect();
    if let Some(w) = want
        && !notes.join(" | ").contains(w)
    {
        bad.push(format!("notes lack {w:?}: {notes:?}"));
    }
    if let Some(imep) = e["imep_bar"].as_f64() {
        let tol = e["imep_rel_tol"].as_f64().unwrap_or(1e-9);
        match s["imep_bar"].as_f64() {
            Some(got) if ((got - imep) / imep).abs() <= tol => {}
            got => bad.push(format!("imep_bar {got:?}, expected {imep} within {tol}")),
        }
    }
    for key in ["cycles", "cycles_skipped"] {
        if let Some(want) = e[key].as_i64() {
            let default = if key == "cycles" { 1 } else { 0 };
            let got = s[key].as_i64().unwrap_or(default);
            if got != want {
                bad.push(format!("{key} {got}, expected {want}"));
            }
        }
    }
    if let Some(p) = e.get("pegging").filter(|p| p.is_object()) {
        let got = s["pegging"]["offset_bar"].as_f64().unwrap_or(f64::NAN);
        let want = p["offset_bar"].as_f64().unwrap_or(0.0);
        let tol = p["offset_abs_tol"].as_f64().unwrap_or(1e-9);
        if !((got - want).abs() <= tol) {
            bad.push(format!("pegging offset {got} bar, expected {want} ± {tol}"));
        }
    }
    bad
}

/// Every class of issue 22 reads with the tool's flags alone, and agrees
/// with the independent IMEP; every refusal is exit 1 naming the file.
#[test]
fn fixtures_as_other_tools_write_them() {
    let text = std::fs::read_to_string(format!("{}/tests/fixtures/measured/expected.json", root()))
        .expect("expected.json");
    let doc: Value = serde_json::from_str(&text).expect("expected.json is JSON");
    let fixtures = doc["fixtures"].as_array().expect("fixtures");
    assert!(fixtures.len() >= 30, "{} fixtures", fixtures.len());
    let mut failed = Vec::new();
    for e in fixtures {
        let bad = check(e);
        if !bad.is_empty() {
            failed.push(format!("{}: {}", e["id"], bad.join("; ")));
        }
    }
    assert!(
        failed.is_empty(),
        "{} failed:\n{}",
        failed.len(),
        failed.join("\n")
    );
}

/// A diagram digitised every 5° gets no TDC offset estimate, for its own
/// spacing, though the grid it is interpolated onto is 0.1°: the fit would
/// judge the interpolant, not the data.
#[test]
fn coarse_data_gets_no_tdc_estimate() {
    let file = format!("{}/tests/fixtures/measured/digitised_sparse.csv", root());
    let engine = format!("{}/data/single.toml", root());
    let j = enginedyn_tests::ok_json(&["run", "--engine", &engine, "--diagram", &file, "--json"]);
    assert!(
        j.get("tdc_offset_estimate_deg").is_none_or(Value::is_null),
        "{j}"
    );
    let notes = j["notes"].to_string();
    assert!(
        notes.contains("no TDC offset estimate: the points are 5.")
            && notes.contains("apart, coarser than the 1° the fit needs"),
        "{notes}"
    );
}
