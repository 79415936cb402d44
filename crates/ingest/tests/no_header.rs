//! A file without a header (INTERFACE.md, "Plausibility"): the hint offers
//! only the readings that fit the data, and probing for them reads a
//! bounded amount.

use enginedyn_ingest::{ParseOptions, parse};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};

/// The bundled single's cylinder (ε 8.5).
fn opts() -> ParseOptions {
    let crank = CrankSlider::new(0.027, 0.084, 0.0).unwrap();
    ParseOptions {
        cylinder: Some(Cylinder::new(Mechanism::CrankSlider(crank), 0.068, 8.5).unwrap()),
        ..ParseOptions::new(720.0)
    }
}

/// Angle, a pressure (1 bar, a 40 bar peak at 10°), a needle-lift-like
/// pulse (0.02, 5 from −12° to 6°), and the pressure again.
#[test]
fn the_hint_skips_the_column_that_cannot_be_a_pressure() {
    let mut s = String::new();
    for k in 0..720 {
        let a = f64::from(k) - 360.0;
        let p = 1.0 + 40.0 * (-((a - 10.0) / 30.0).powi(2)).exp();
        let inj = if (-12.0..6.0).contains(&a) { 5.0 } else { 0.02 };
        s.push_str(&format!("{a} {p:.4} {inj} {p:.4}\n"));
    }
    let e = parse(s.as_bytes(), &opts()).unwrap_err().to_string();
    assert!(
        e.starts_with("line 1: no header row")
            && e.contains("crank_deg,pressure_bar,_,pressure_bar reads the columns that fit")
            && e.contains("column 3 `pressure_bar` (in bar) is not a cylinder pressure"),
        "{e}"
    );
    // Without the engine there is no compression bound: every column fits.
    let e = parse(s.as_bytes(), &ParseOptions::new(720.0))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("crank_deg,pressure_bar... reads the angle and one cycle per column"),
        "{e}"
    );
}

/// A first column rising so slowly that no cycle ends within the probe's
/// 4,194,304 values (4,096 columns, 1,100 rows): the plain hint, read no
/// further than the bound.
#[test]
fn probing_stops_at_its_bound() {
    let row: String = std::iter::repeat_n(" 1.5", 4095).collect();
    let mut s = String::new();
    for k in 0..1100 {
        s.push_str(&format!("{}{row}\n", f64::from(k) * 0.001));
    }
    let e = parse(s.as_bytes(), &opts()).unwrap_err().to_string();
    assert!(
        e.starts_with("line 1: no header row: name the columns with --columns (here 4096 of them: crank_deg,pressure_bar... reads the angle and one cycle per column")
            && !e.contains("is not a cylinder pressure"),
        "{e}"
    );
    // Within the bound (1,000 rows), every column is judged: a constant
    // 1.5 bar is no cylinder pressure.
    let short: String = s.lines().take(1000).map(|l| format!("{l}\n")).collect();
    let e = parse(short.as_bytes(), &opts()).unwrap_err().to_string();
    assert!(
        e.contains("no column after the first reads as a cylinder pressure in bar"),
        "{}",
        &e[..300]
    );
}
