//! Issue 31, "Plausibility, so a wrong column is never averaged in" and
//! "Units are not angles" and "Say what was decided" (its first parts): a
//! cycle far from the others is named, a CoV of IMEP above 10 % is noted,
//! `kW` is never a crank angle, a side table is left out, and cycles
//! stacked in one column are counted in a note.

use enginedyn_tests::{data, data_rows, run};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Twenty cycles of `data/single.csv`'s, each scaled about 1 bar by
/// 1 + 0.01 sin(k), and cycle 7 by 0.3 (a misfire: its IMEP is 0.3 times
/// the cycle's, ∮ p dV being linear in p).
#[test]
fn a_misfire_is_named_and_a_high_cov_noted() {
    let t = tempfile::tempdir().unwrap();
    let rows = data_rows("single.csv");
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

/// "Say what was decided": the default sheet is the first that holds a
/// diagram (issue 36, item 10: sheet 1 `Info` failed the file), with a note
/// naming it.
#[test]
fn the_default_sheet_is_the_first_that_holds_a_diagram() {
    let f = format!(
        "{}/fixtures/measured/excel_title_second_sheet.xlsx",
        env!("CARGO_MANIFEST_DIR")
    );
    let o = run(&["run", "--engine", &data("single.toml"), "--diagram", &f]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("read sheet 2 `Cylinder 1` of 2, the first that holds a diagram"),
        "{}",
        stderr(&o)
    );
}

fn measured(name: &str) -> String {
    format!("{}/fixtures/measured/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// `expected.json`'s entry of `id`.
fn expected(id: &str) -> serde_json::Value {
    let text = std::fs::read_to_string(measured("expected.json")).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    doc["fixtures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["id"] == id)
        .cloned()
        .unwrap_or_else(|| panic!("no entry {id}"))
}

/// Issue 31's first class: a headerless file of angle, pressure and an
/// injection signal. The hint offers only the reading that fits
/// (`crank_deg,pressure_bar,_`), never `pressure_bar...`; the old hint
/// followed literally refuses the injection column as no cylinder pressure
/// (before: 5 more "cycles", IMEP about half, exit 0); the offered reading
/// gives the independent IMEP.
#[test]
fn an_injection_column_is_refused_and_the_hint_offers_what_fits() {
    let f = measured("inj_three_columns.txt");
    let engine = data("single.toml");
    let o = run(&["run", "--engine", &engine, "--diagram", &f]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("line 1: no header row")
            && e.contains("crank_deg,pressure_bar,_ reads the one column that fits")
            && !e.contains("pressure_bar..."),
        "{e}"
    );
    assert!(e.contains("a flat signal with a pulse"), "{e}");
    let o = run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        &f,
        "--columns",
        "crank_deg,pressure_bar...",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains(
            "column 3 `pressure_bar` (in bar) is not a cylinder pressure: its peak 4.83 bar"
        ) && e.contains("an injection, needle-lift or ignition signal?"),
        "{e}"
    );
    let j = enginedyn_tests::ok_json(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        &f,
        "--columns",
        "crank_deg,pressure_bar,_",
        "--json",
    ]);
    let want = expected("inj_three_columns.txt --columns crank_deg,pressure_bar,_")["imep_bar"]
        .as_f64()
        .unwrap();
    let got = j["imep_bar"].as_f64().unwrap();
    assert!(((got - want) / want).abs() < 1e-9, "{got} {want}");
    assert_eq!(j["cycles"].as_u64(), Some(5));
}

/// A headerless file whose columns all fit keeps the one-cycle-per-column
/// hint; one whose first column is no angle gets the plain hint.
#[test]
fn the_hint_keeps_pressure_bar_dots_when_every_column_fits() {
    let engine = data("single.toml");
    let o = run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        &measured("percol_savetxt_trailing_tab.txt"),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("crank_deg,pressure_bar... reads the angle and one cycle per column"),
        "{}",
        stderr(&o)
    );
    let t = tempfile::tempdir().unwrap();
    let f = t.path().join("falling.csv");
    std::fs::write(&f, "5,1,2\n4,1,2\n3,1,2\n2,1,2\n1,1,2\n").unwrap();
    let o = run(&["run", "--engine", &engine, "--diagram", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("line 1: no header row: name the columns with --columns (here 3 of them: crank_deg,pressure_bar... reads"),
        "{}",
        stderr(&o)
    );
}

/// Every diagram bundled in `data/` passes the compression bound with its
/// engine (ε from 7.5 two-stroke to 17 diesel).
#[test]
fn every_bundled_diagram_passes_the_compression_bound() {
    for name in [
        "i3_two_stroke",
        "i6_diesel",
        "scotch_yoke",
        "single",
        "v12_60",
        "v6_90",
        "v8_crossplane",
        "vaz2108",
    ] {
        let o = run(&["run", "--engine", &data(&format!("{name}.toml")), "--json"]);
        assert_eq!(o.status.code(), Some(0), "{name}: {}", stderr(&o));
    }
}

/// "Gaps": a 33.5° gap in a digitised cycle's exhaust stroke, wider than
/// `--max-gap 30`, is bridged: the note gives the interpolants' difference
/// over it, 3.92e-5 of |W| by the generator's own calculation (0.0039 %);
/// the same gap over the peak (5.8 %) is refused, naming `--max-gap`.
#[test]
fn a_gap_the_data_settle_is_bridged_one_over_the_peak_refused() {
    let engine = data("single.toml");
    let e = expected("digitised_gap_exhaust.csv");
    let share = e["gap_work_share"].as_f64().unwrap();
    let j = enginedyn_tests::ok_json(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        &measured("digitised_gap_exhaust.csv"),
        "--json",
    ]);
    let notes = j["notes"].to_string();
    let figure = two_figures(100.0 * share);
    assert!(
        notes.contains(&format!(
            "cycle 1 has a gap of 33.5° from 250° (its steps are 2.5°), wider than --max-gap 30°: bridged, as the data settle it: the linear and the cubic interpolants' ∫ p dV over it differ by {figure} % of the cycle's work"
        )),
        "{figure}: {notes}"
    );
    let o = run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        &measured("digitised_gap_peak.csv"),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let s = stderr(&o);
    let peak = expected("digitised_gap_peak.csv")["gap_work_share"]
        .as_f64()
        .unwrap();
    assert!(
        s.contains(&format!(
            "differ by {} % of the cycle's work, more than the 0.1 %",
            two_figures(100.0 * peak)
        )) && s.contains("--max-gap 34 would bridge this one"),
        "{s}"
    );
    // A narrower --max-gap changes nothing: the data settle the exhaust gap.
    let o = run(&[
        "run",
        "--engine",
        &engine,
        "--diagram",
        &measured("digitised_gap_exhaust.csv"),
        "--max-gap",
        "10",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// Two significant figures, as the notes write a share (`0.0039`, `5.8`).
fn two_figures(x: f64) -> String {
    let digits = (1 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.digits$}");
    s
}
