//! One data set written in every layout (issue 22): long, one cycle per
//! column (with and without a header, a trailing tab), wrapped cycles, a
//! spreadsheet, and a DAQ time record sampled from it, read back to the
//! same cycles and IMEP: to the bit where the samples are the same numbers,
//! to the stated interpolation error for the time record.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Resampled, load, parse};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};

const CYCLES: usize = 5;

fn cylinder() -> Cylinder {
    let cs = CrankSlider::new(0.027, 0.027 / 0.3, 0.0).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.068, 8.5).unwrap()
}

/// A smooth fired-looking pressure (bar) at cycle angle `deg`, cycle `k`.
fn p_of(deg: f64, k: usize) -> f64 {
    let d = (deg - 12.0 + 360.0).rem_euclid(720.0) - 360.0;
    let compression = 1.0 + 14.0 * (-(d / 70.0).powi(2)).exp();
    compression + 45.0 * (1.0 + 0.02 * k as f64) * (-((d - 8.0) / 22.0).powi(2)).exp()
}

/// The cells as written: six decimals, the same text in every layout.
fn cell(deg: f64, k: usize) -> String {
    format!("{:.6}", p_of(deg, k))
}

fn options() -> (ParseOptions, GridOptions) {
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cylinder());
    let mut g = GridOptions::new(0.5, Interp::Auto);
    g.cylinder = Some(cylinder());
    (o, g)
}

fn imeps(r: &Resampled) -> Vec<f64> {
    r.stats.iter().map(|s| s.imep_pa.unwrap()).collect()
}

fn read(text: &str, o: &ParseOptions) -> Resampled {
    let (_, g) = options();
    load(text.as_bytes(), o, &g).unwrap_or_else(|e| panic!("{e}\n{}", &text[..200]))
}

#[test]
fn every_layout_gives_the_same_cycles() {
    let (o, _) = options();
    let angles: Vec<f64> = (0..1440).map(|i| i as f64 * 0.5).collect();
    let mut long = String::from("cycle,crank_deg,pressure_bar\n");
    for k in 0..CYCLES {
        for &a in &angles {
            long.push_str(&format!("{},{a},{}\n", k + 1, cell(a, k)));
        }
    }
    let want = read(&long, &o);
    assert_eq!(want.cycles, CYCLES);

    // One cycle per column, no header, a trailing tab (np.savetxt and kin).
    let mut per_col = String::new();
    let mut header = String::from("crank_deg");
    for k in 0..CYCLES {
        header.push_str(&format!("\tPressure [bar] {}", k + 1));
    }
    header.push('\n');
    for &a in &angles {
        per_col.push_str(&format!("{a}\t"));
        for k in 0..CYCLES {
            per_col.push_str(&cell(a, k));
            per_col.push('\t');
        }
        per_col.push('\n');
    }
    let mut o_cols = o.clone();
    o_cols.columns = Some(vec!["crank_deg".into(), "pressure_bar...".into()]);
    let got = read(&per_col, &o_cols);
    assert_eq!(imeps(&got), imeps(&want), "per column, --columns …");
    assert_eq!(got.pressure, want.pressure);
    // The same with a numbered header instead of --columns.
    let got = read(&(header + &per_col), &o);
    assert_eq!(imeps(&got), imeps(&want), "per column, header");
    // Without `...` the columns beyond the named ones are an error.
    o_cols.columns = Some(vec!["crank_deg".into(), "pressure_bar".into()]);
    let e = parse(per_col.as_bytes(), &o_cols).unwrap_err().to_string();
    assert!(e.contains("--columns names 2") && e.contains("..."), "{e}");

    // Cycles starting at firing TDC 360, their angles wrapping once.
    let mut wrapped = String::from("crank_deg;pressure_bar\n");
    for k in 0..CYCLES {
        for &a in angles[720..].iter().chain(&angles[..720]) {
            let cycle_angle = (a - 360.0).rem_euclid(720.0);
            wrapped.push_str(&format!("{a};{}\n", cell(cycle_angle, k).replace('.', ",")));
        }
    }
    let mut o_wrap = o.clone();
    o_wrap.tdc_deg = 360.0;
    let got = read(&wrapped, &o_wrap);
    assert_eq!(got.cycles, CYCLES);
    assert_eq!(imeps(&got), imeps(&want), "wrapped, decimal comma");
}

/// The bundled single-cylinder diagram saved by Excel (openpyxl) reads to
/// the bit what its CSV reads.
#[test]
fn a_spreadsheet_reads_as_its_csv() {
    let root = format!("{}/../..", env!("CARGO_MANIFEST_DIR"));
    let (o, g) = options();
    let csv = std::fs::read(format!("{root}/data/single.csv")).unwrap();
    let xlsx = std::fs::read(format!("{root}/tests/fixtures/measured/excel_single.xlsx")).unwrap();
    let a = load(csv.as_slice(), &o, &g).unwrap();
    let b = load(xlsx.as_slice(), &o, &g).unwrap();
    assert_eq!(a.pressure, b.pressure);
    assert_eq!(imeps(&a), imeps(&b));
}

/// A 72 kHz record of the cycles of `p_of`: revolution j from θ = 360 j -
/// 720 (firing TDC at θ = 0) at 1000 (1 + `variation` sin j) rpm, a TDC
/// pulse per revolution rising through half its range at `pulse_deg`
/// after each TDC (an analog ramp over 1° on a 0.3 V baseline), the record
/// starting at θ = `from_deg`.
fn record(variation: f64, pulse_deg: f64, from_deg: f64) -> String {
    let revs = 2 * CYCLES + 4;
    let mut starts = vec![0.0f64];
    for j in 0..revs {
        let rpm = 1000.0 * (1.0 + variation * (j as f64).sin());
        starts.push(starts[j] + 60.0 / rpm);
    }
    let theta = |t: f64| -> f64 {
        let j = starts
            .partition_point(|&s| s <= t)
            .saturating_sub(1)
            .min(revs - 1);
        360.0 * j as f64 - 720.0 + 360.0 * (t - starts[j]) / (starts[j + 1] - starts[j])
    };
    let mut rec = String::from("time_s,pressure_bar,tdc\n");
    let dt = 1.0 / 72_000.0;
    let mut t = starts[0] + (starts[1] - starts[0]) * (from_deg + 720.0) / 360.0;
    while t < starts[revs] {
        let th = theta(t);
        let from_pulse = (th - pulse_deg + 180.0).rem_euclid(360.0) - 180.0;
        let pulse =
            0.3 + 4.7 * ((from_pulse + 0.5) / 1.0).clamp(0.0, 1.0) * f64::from(from_pulse < 3.0);
        let (cycle_angle, k) = (th.rem_euclid(720.0), (th / 720.0).floor());
        let k = if k < 0.0 {
            0
        } else {
            (k as usize).min(CYCLES - 1)
        };
        rec.push_str(&format!("{t:.9},{},{pulse:.6}\n", cell(cycle_angle, k)));
        t += dt;
    }
    rec
}

/// The long layout's per-cycle IMEP of the same cycles.
fn long_imeps() -> Vec<f64> {
    let (o, g) = options();
    let mut long = String::from("cycle,crank_deg,pressure_bar\n");
    for k in 0..CYCLES {
        for i in 0..1440 {
            let a = i as f64 * 0.5;
            long.push_str(&format!("{},{a},{}\n", k + 1, cell(a, k)));
        }
    }
    imeps(&load(long.as_bytes(), &o, &g).unwrap())
}

/// Each whole cycle's IMEP within 2e-5 of the long layout's (the spline's
/// error on the long layout's 0.5° samples against the record's 0.08°;
/// measured 3e-7 to 7e-6).
fn same_cycles(got: &Resampled) {
    let (w, gt) = (long_imeps(), imeps(got));
    assert_eq!(gt.len(), CYCLES, "whole cycles: {:?}", got.notes);
    for (a, b) in w.iter().zip(&gt) {
        assert!(((a - b) / a).abs() < 2e-5, "{a} vs {b}");
    }
}

/// A time record whose speed varies ±1 % from one revolution to the next,
/// starting 20° before the exchange TDC (so the firing pulse is the
/// second: found from the pressure), partial cycles at both ends: whole
/// cycles as the long layout reads them.
#[test]
fn a_time_record_reads_as_its_cycles() {
    let (o, g) = options();
    let got = load(record(0.01, 0.0, -380.0).as_bytes(), &o, &g).unwrap();
    same_cycles(&got);
    let rpm = got.rpm.unwrap();
    assert!((rpm - 1000.0).abs() < 10.0, "{rpm}");
    assert!(
        got.notes.iter().any(|n| n.contains("from pulse 2")),
        "{:?}",
        got.notes
    );
}

/// A pulse 20° before each TDC, the record starting before it: `--tdc-deg
/// 380` (firing TDC 380° after the first pulse) puts the cycles between
/// pulses, not on them.
#[test]
fn a_time_record_with_the_pulse_off_tdc() {
    let (mut o, g) = options();
    o.tdc_deg = 380.0;
    o.tdc_given = true;
    let got = load(record(0.0, -20.0, -400.0).as_bytes(), &o, &g).unwrap();
    same_cycles(&got);
}
