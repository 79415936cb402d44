//! Values in another unit than their column says (INTERFACE.md, "Python
//! package": arrays pass the same plausibility as files, and a message
//! names the likely unit): a pressure in psi or MPa read as bar, a time in
//! ms read as seconds. The rules are the reader's, for a file and for
//! arrays alike.

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

/// A firing cycle in bar: 1 bar at intake, a 40 bar peak at 10°, times
/// `scale`.
fn cycle(scale: f64) -> String {
    let mut s = String::from("crank_deg,pressure_bar\n");
    for k in 0..720 {
        let a = f64::from(k) - 360.0;
        let p = 1.0 + 40.0 * (-((a - 10.0) / 30.0).powi(2)).exp();
        s.push_str(&format!("{a},{}\n", p * scale));
    }
    s
}

#[test]
fn a_pressure_in_psi_read_as_bar_is_refused_naming_psi() {
    let e = parse(cycle(14.503_773_8).as_bytes(), &opts())
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "line 2: cycle 1: the pressure around intake BDC from column 2 `pressure_bar` (in bar) is 14.5 bar absolute, above the 6 bar any engine's intake holds: a pressure in psi read as bar (14.5 psi is 1 bar)? convert it, or name the column's unit (`pressure [psi]`); a cylinder pressure of no compressing engine (a steam engine, a compressor, a textbook problem with a constant pressure) reads with --no-compression-check"
    );
    // In bar it reads.
    parse(cycle(1.0).as_bytes(), &opts()).unwrap();
}

#[test]
fn a_pressure_in_mpa_read_as_bar_is_refused_naming_mpa() {
    let e = parse(cycle(0.1).as_bytes(), &opts())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "; or a pressure in MPa read as bar (0.1 MPa is 1 bar): convert it, or name the column's unit (`pressure [MPa]`)"
        ),
        "{e}"
    );
}

/// A time record at 3000 rpm: a TDC pulse a revolution, 20 cycles,
/// sampled every 0.1 ms, its time column in `unit` seconds.
fn record(unit: f64) -> String {
    let mut s = String::from("time_s,pressure_bar,tdc\n");
    let rev = 60.0 / 3000.0;
    let n = (40.0 * rev / 1e-4) as usize;
    for k in 0..n {
        let t = k as f64 * 1e-4;
        let deg = (t / rev * 360.0) % 720.0;
        let a = if deg > 360.0 { deg - 720.0 } else { deg };
        let p = 1.0 + 40.0 * (-((a - 10.0) / 30.0).powi(2)).exp();
        let pulse = if (t / rev).fract() < 0.02 { 5.0 } else { 0.0 };
        s.push_str(&format!("{},{p},{pulse}\n", t * unit));
    }
    s
}

#[test]
fn a_time_in_ms_read_as_seconds_is_refused_against_operating_rpm() {
    let o = ParseOptions {
        operating_rpm: Some(3000.0),
        ..opts()
    };
    let d = parse(record(1.0).as_bytes(), &o).unwrap();
    assert!((d.rpm.unwrap() - 3000.0).abs() < 1.0, "{:?}", d.rpm);
    let e = parse(record(1e3).as_bytes(), &o).unwrap_err().to_string();
    assert_eq!(
        e,
        "the `tdc` column (column 3) gives 3 rpm, 0.001 times the engine file's operating.rpm = 3000 rpm: a time in ms read as seconds? name the time column's unit (`time [ms]`) or convert it to seconds"
    );
    // Without operating.rpm, the speed is taken as measured.
    parse(record(1e3).as_bytes(), &opts()).unwrap();
}

/// Issue 43, item 8: a textbook steam-engine problem at a constant 11 bar
/// absolute is refused by the intake level (over 6 bar: psi read as
/// bar?), and the error names `--no-compression-check`, which lifts the
/// intake level with the other bounds that assume a compressing engine:
/// with it the trace reads, its mean 11 bar (to the printed digits).
#[test]
fn a_constant_pressure_is_refused_naming_the_flag_that_reads_it() {
    let mut s = String::from("crank_deg,pressure_bar\n");
    for k in 0..720 {
        s.push_str(&format!("{},11.0\n", f64::from(k) - 360.0));
    }
    let e = parse(s.as_bytes(), &opts()).unwrap_err().to_string();
    assert!(
        e.contains("11 bar absolute, above the 6 bar") && e.contains("--no-compression-check"),
        "{e}"
    );
    let lifted = ParseOptions {
        compression_check: false,
        ..opts()
    };
    let grid = enginedyn_ingest::GridOptions::new(0.5, enginedyn_ingest::Interp::Auto);
    let r = enginedyn_ingest::load(s.as_bytes(), &lifted, &grid).unwrap();
    let mean = r.pressure.iter().sum::<f64>() / r.pressure.len() as f64;
    assert!((mean - 11e5).abs() < 1e-6, "{mean}");
}
