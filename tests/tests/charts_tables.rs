//! Charts and tables that read right (issue 30, item 13), end to end: the
//! tolerance chart's readable names and units, a nominal in rounding noise
//! written 0, `firing-orders`' column words and legend, and `--angles
//! centered` reaching the charts.

use enginedyn_tests::{data, run};

/// Texts of every `<text>` element of an SVG document.
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = &t[t.find('>')? + 1..];
            Some(body[..body.find("</text>")?].trim().to_string())
        })
        .collect()
}

fn ok(args: &[&str]) -> std::process::Output {
    let out = run(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The tornado panels name parameters and results as an engineer does,
/// with units (`stroke (2R), mm`, `mean torque = … N m`), never by their
/// keys; a balanced four's order-0.5 torque (1.6e-13 N m, rounding noise
/// against its scale) is written 0 in the table, the CSV and the JSON.
#[test]
fn tolerance_outputs_read_right() {
    let dir = tempfile::tempdir().unwrap();
    let engine = data("vaz2108.toml");
    let out = ok(&[
        "tolerance",
        "--engine",
        &engine,
        "--step",
        "0.5",
        "--samples",
        "0",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let svg = std::fs::read_to_string(dir.path().join("tolerance.svg")).unwrap();
    let words = texts(&svg);
    for want in [
        "stroke (2R), mm",
        "rod mass, kg",
        "firing TDC position, deg",
        "piston group mass, cylinder 1, kg",
        "throw angle, throw 2, deg",
    ] {
        assert!(words.iter().any(|t| t == want), "no `{want}` in {words:?}");
    }
    for want in [
        "mean torque = ",
        "IMEP = ",
        "torque harmonic, order 0.5 = 0 N m",
    ] {
        assert!(
            words.iter().any(|t| t.starts_with(want)),
            "no `{want}` in {words:?}"
        );
    }
    for t in &words {
        for key in ["_mm", "_kg", "_deg", "_nm", "_bar", "_n ", "_j ", "_m3"] {
            assert!(!t.contains(key), "raw key in `{t}`");
        }
    }
    // The printed stack-up, the CSV and the JSON write the cancelled
    // harmonic as 0, not 1.607e-13.
    let stdout = String::from_utf8_lossy(&out.stdout);
    let row = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("torque_order_0_5_nm "))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert_eq!(row.split_whitespace().nth(1), Some("0"), "{row}");
    assert!(!stdout.contains("e-13"), "{stdout}");
    let csv = std::fs::read_to_string(dir.path().join("tolerance.csv")).unwrap();
    let rows: Vec<&str> = csv
        .lines()
        .filter(|l| l.contains(",torque_order_0_5_nm,"))
        .collect();
    assert!(!rows.is_empty());
    for r in rows {
        assert_eq!(r.split(',').nth(3), Some("0"), "{r}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("tolerance.json")).unwrap())
            .unwrap();
    assert_eq!(json["torque_order_0_5_nm"]["nominal"], 0.0);
    assert_eq!(json["torque_order_0_5_nm"]["zero_nominal"], true);
}

/// `firing-orders` says "intervals" on an inline engine ("bank intervals"
/// on a vee) and explains its journal columns under the table.
#[test]
fn firing_orders_table_explains_its_columns() {
    let out = ok(&["firing-orders", "--engine", &data("vaz2108.toml")]);
    let text = String::from_utf8_lossy(&out.stdout);
    let head = text
        .lines()
        .find(|l| l.trim_start().starts_with("rank"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        head.contains("intervals (deg)") && !head.contains("bank"),
        "{head}"
    );
    assert!(head.contains("after throw"), "{head}");
    for want in [
        "intervals: crank degrees between consecutive firings",
        "after throw K: the journal that carries it, the one after throw K counted from the free end",
        "harmonic N m / order: the largest harmonic amplitude of any journal's torque, and its engine order",
    ] {
        assert!(text.contains(want), "no `{want}` in\n{text}");
    }
    // The best order's largest journal torque: after throw 4, as `run` reports
    // journal_most_loaded = 4 for the bundled engine.
    let best = text
        .lines()
        .find(|l| l.trim_start().starts_with("1  1-"))
        .unwrap_or_else(|| panic!("{text}"));
    let cells: Vec<&str> = best.split_whitespace().collect();
    assert_eq!(cells.len(), 9, "{best}");
    let after: usize = cells[5].parse().unwrap();
    assert_eq!(after, 4, "{best}");

    let out = ok(&["firing-orders", "--engine", &data("v8_crossplane.toml")]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("bank intervals (deg)"), "{text}");
    assert!(text.contains("the banks split by |"), "{text}");
}

/// `run --angles centered` draws the angle axes from -360 to 360 (the
/// two-stroke from -180 to 180), as `curves.csv` writes them.
#[test]
fn centred_angles_reach_the_charts() {
    for (engine, half) in [("vaz2108", "360"), ("i3_two_stroke", "180")] {
        let dir = tempfile::tempdir().unwrap();
        ok(&[
            "run",
            "--engine",
            &data(&format!("{engine}.toml")),
            "--step",
            "1",
            "--angles",
            "centered",
            "--out",
            dir.path().to_str().unwrap(),
        ]);
        let csv = std::fs::read_to_string(dir.path().join("curves.csv")).unwrap();
        let first = csv.lines().nth(1).unwrap().split(',').next().unwrap();
        assert_eq!(first, format!("-{half}"));
        for chart in ["pressure.svg", "torque.svg", "flywheel.svg"] {
            let svg = std::fs::read_to_string(dir.path().join(chart)).unwrap();
            let words = texts(&svg);
            assert!(
                words.iter().any(|t| *t == format!("-{half}")) && words.iter().any(|t| t == half),
                "{engine}/{chart}: no ±{half} in {words:?}"
            );
        }
    }
}
