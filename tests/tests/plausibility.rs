//! Issue 31, "Plausibility, so a wrong column is never averaged in" and
//! "Units are not angles" and "Say what was decided" (its first parts): a
//! cycle far from the others is named, a CoV of IMEP above 10 % is noted,
//! `kW` is never a crank angle, a side table is left out, and cycles
//! stacked in one column are counted in a note.

use enginedyn_tests::{data, run};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Twenty cycles of `data/single.csv`'s, each scaled about 1 bar by
/// 1 + 0.01 sin(k), and cycle 7 by 0.3 (a misfire: its IMEP is 0.3 times
/// the cycle's, ∮ p dV being linear in p).
#[test]
fn a_misfire_is_named_and_a_high_cov_noted() {
    let t = tempfile::tempdir().unwrap();
    let rows: Vec<(String, f64)> = std::fs::read_to_string(data("single.csv"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .map(|l| {
            let (a, p) = l.split_once(',').unwrap();
            (a.to_string(), p.parse().unwrap())
        })
        .collect();
    let mut s = String::from("cycle,crank_deg,pressure_bar\n");
    for c in 1..=20 {
        let k = if c == 7 {
            0.3
        } else {
            1.0 + 0.01 * f64::from(c).sin()
        };
        for (a, p) in &rows {
            s.push_str(&format!("{c},{a},{:.5}\n", 1.0 + k * (p - 1.0)));
        }
    }
    let f = t.path().join("misfire.csv");
    std::fs::write(&f, s).unwrap();
    let o = run(&[
        "run",
        "--engine",
        &data("single.toml"),
        "--diagram",
        f.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("warning: cycle 7: IMEP 2.97 bar") && e.contains("a misfire?"),
        "{e}"
    );
    assert!(e.contains("varies by 16 % (CoV) over 20 cycles"), "{e}");
    // Steady cycles: neither note.
    let o = run(&["run", "--engine", &data("single.toml"), "--json"]);
    assert!(!stderr(&o).contains("misfire"), "{}", stderr(&o));
}

/// A dynamometer's results table (`Speed [rpm]`, `P [kW]`, `Torque [Nm]`)
/// was read as a diagram, its power as the crank angle.
#[test]
fn kilowatts_are_never_a_crank_angle() {
    let t = tempfile::tempdir().unwrap();
    let f = t.path().join("results.csv");
    let mut s = String::from("P [kW],Pressure [bar]\n");
    for k in 0..720 {
        s.push_str(&format!(
            "{k},{}\n",
            1.0 + 40.0 * (-(f64::from(k) / 30.0).powi(2)).exp()
        ));
    }
    std::fs::write(&f, s).unwrap();
    let o = run(&[
        "run",
        "--engine",
        &data("single.toml"),
        "--diagram",
        f.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("no crank angle"), "{}", stderr(&o));
}

/// A names row with a side table beyond an empty column (`crank_radius_mm`,
/// `52`): left out with one note, not "left out (the angle is used)", and
/// the diagram reads as without it.
#[test]
fn a_side_table_is_left_out_with_one_note() {
    let t = tempfile::tempdir().unwrap();
    let rows: Vec<String> = std::fs::read_to_string(data("single.csv"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .map(str::to_string)
        .collect();
    let mut s = String::from("Crank_Angle [deg],Pressure [bar],,crank_radius_mm,52\n");
    for (i, r) in rows.iter().enumerate() {
        let side = match i {
            0 => ",,bore_mm,68",
            1 => ",,stroke_mm,54",
            _ => ",,,",
        };
        s.push_str(&format!("{r}{side}\n"));
    }
    let f = t.path().join("side.csv");
    std::fs::write(&f, s).unwrap();
    let engine = data("single.toml");
    let side = run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        f.to_str().unwrap(),
        "--json",
    ]);
    let plain = run(&["run", "--engine", &engine, "--json"]);
    assert_eq!(side.status.code(), Some(0), "{}", stderr(&side));
    let j: serde_json::Value = serde_json::from_slice(&side.stdout).unwrap();
    let k: serde_json::Value = serde_json::from_slice(&plain.stdout).unwrap();
    assert_eq!(j["imep_bar"], k["imep_bar"]);
    let e = stderr(&side);
    assert!(
        e.contains("note: columns 4 to 5 (`crank_radius_mm`, `52`) lie right of the empty column 3: a side table, left out"),
        "{e}"
    );
    assert!(!e.contains("the angle is used"), "{e}");
}

/// "Say what was decided": five cycles stacked in one column, the angle
/// starting again at -360° each time, are split and the note says so.
#[test]
fn stacked_cycles_are_noted_with_their_count() {
    let t = tempfile::tempdir().unwrap();
    let rows: Vec<(f64, String)> = std::fs::read_to_string(data("single.csv"))
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
        .map(|l| {
            let (a, p) = l.split_once(',').unwrap();
            (a.parse::<f64>().unwrap(), p.to_string())
        })
        .collect();
    let mut s = String::from("crank_deg,pressure_bar\n");
    for _ in 0..5 {
        for (a, p) in &rows {
            s.push_str(&format!("{},{p}\n", a - 360.0));
        }
    }
    let f = t.path().join("stacked.csv");
    std::fs::write(&f, s).unwrap();
    let engine = data("single.toml");
    let o = run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        f.to_str().unwrap(),
        "--tdc-deg",
        "-360",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("note: 5 cycles one after another in one column"),
        "{e}"
    );
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["cycles"].as_u64(), Some(5));
}

/// "Say what was decided": a workbook whose default sheet holds no diagram
/// gets an error that lists every sheet by number and name.
#[test]
fn the_default_sheet_error_lists_the_sheets() {
    let f = format!(
        "{}/fixtures/measured/excel_title_second_sheet.xlsx",
        env!("CARGO_MANIFEST_DIR")
    );
    let o = run(&["run", "--engine", &data("single.toml"), "--diagram", &f]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o)
            .contains("of 2: 1 `Info`, 2 `Cylinder 1`; --sheet N or --sheet NAME reads another"),
        "{}",
        stderr(&o)
    );
}
