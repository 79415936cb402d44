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
    record_of(variation, pulse_deg, from_deg, &[])
}

/// [`record`] with one pressure column per cylinder, `P_Cyl{i} [bar]`,
/// cylinder i firing `firing[i - 1]` degrees after cylinder 1 (empty: one
/// `pressure_bar` column).
fn record_of(variation: f64, pulse_deg: f64, from_deg: f64, firing: &[f64]) -> String {
    // The record ends at the gas-exchange TDC after cycle CYCLES − 1's
    // window, its last pulse unseen: CYCLES whole windows from −360°.
    let revs = 2 * CYCLES + 3;
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
    let mut rec = if firing.is_empty() {
        String::from("time_s,pressure_bar,tdc\n")
    } else {
        let names: Vec<String> = (1..=firing.len())
            .map(|i| format!("P_Cyl{i} [bar]"))
            .collect();
        format!("time_s,{},tdc\n", names.join(","))
    };
    let dt = 1.0 / 72_000.0;
    let mut t = starts[0] + (starts[1] - starts[0]) * (from_deg + 720.0) / 360.0;
    while t < starts[revs] {
        let th = theta(t);
        let from_pulse = (th - pulse_deg + 180.0).rem_euclid(360.0) - 180.0;
        let pulse =
            0.3 + 4.7 * ((from_pulse + 0.5) / 1.0).clamp(0.0, 1.0) * f64::from(from_pulse < 3.0);
        // Cycle k is the window −360…+360° around its firing TDC.
        let (cycle_angle, k) = (th.rem_euclid(720.0), ((th + 360.0) / 720.0).floor());
        let k = if k < 0.0 {
            0
        } else {
            (k as usize).min(CYCLES - 1)
        };
        let cells: Vec<String> = if firing.is_empty() {
            vec![cell(cycle_angle, k)]
        } else {
            firing
                .iter()
                .map(|f| cell((cycle_angle - f).rem_euclid(720.0), k))
                .collect()
        };
        rec.push_str(&format!("{t:.9},{},{pulse:.6}\n", cells.join(",")));
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

/// Issue 37, item 15: a time record with one pressure column per
/// cylinder (`P_Cyl1` … `P_Cyl4`, as a 4-channel MDF4 or DAQ export names
/// them) reads as four cylinders, every one on cylinder 1's crank angle
/// (its TDC pulse and its pressure place the firing TDC), each then moved
/// onto its own firing TDC: each cylinder's cycles are the long layout's.
/// Today's main refused it as "one cycle per column is read against crank
/// angle, not time".
#[test]
fn a_time_record_with_a_pressure_column_per_cylinder() {
    let (mut o, g) = options();
    let firing = [0.0, 540.0, 180.0, 360.0];
    o.firing_deg = firing.to_vec();
    let text = record_of(0.01, 0.0, -380.0, &firing);
    let got = load(text.as_bytes(), &o, &g).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(got.cylinders.len(), 4, "{:?}", got.notes);
    let want = long_imeps();
    for c in 1..=4 {
        let imeps: Vec<f64> = got
            .stats
            .iter()
            .filter(|s| s.cylinder == c)
            .map(|s| s.imep_pa.unwrap())
            .collect();
        assert_eq!(imeps.len(), CYCLES, "cylinder {c}: {:?}", got.notes);
        for (a, b) in want.iter().zip(&imeps) {
            assert!(((a - b) / a).abs() < 2e-5, "cylinder {c}: {a} vs {b}");
        }
    }
    assert!(
        got.notes.iter().any(|n| n.contains("one per cylinder")),
        "{:?}",
        got.notes
    );
    // Without cylinder 1 there is no reference: an error that says so.
    let (o, _) = options();
    let no_first = text.replacen("P_Cyl1 [bar]", "P_Cyl5 [bar]", 1);
    let e = load(no_first.as_bytes(), &o, &g).unwrap_err().to_string();
    assert!(e.contains("none of cylinder 1"), "{e}");
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

/// Issue 36, item 5 and issue 43, item 1: a long record whose angle runs
/// on, starting 132.5° after firing TDC, is cut at each gas-exchange TDC
/// (each cycle the window −360…+360° around its firing TDC): its whole
/// cycles are the cycles as measured, to the bit; the partial ones at the
/// two ends are left out with a note calling them partial, never a
/// dropout, and no note says the angle starts again.
#[test]
fn a_record_whose_angle_runs_on_is_cut_at_the_gas_exchange_tdc() {
    let (o, _) = options();
    let start = 132.5;
    let mut text = String::from("crank_deg,pressure_bar\n");
    let rows = (8.0 * 720.0 / 0.5) as usize;
    for i in 0..rows {
        let a = start + i as f64 * 0.5;
        // Cycle k is the window −360…+360° around its firing TDC.
        let k = ((a + 360.0) / 720.0).floor() as usize;
        text.push_str(&format!("{a},{}\n", cell(a.rem_euclid(720.0), k)));
    }
    let got = read(&text, &o);
    // The whole cycles are k = 1 … 7.
    let mut long = String::from("cycle,crank_deg,pressure_bar\n");
    for k in 1..8 {
        for i in 0..1440 {
            let a = i as f64 * 0.5;
            long.push_str(&format!("{k},{a},{}\n", cell(a, k)));
        }
    }
    let want = read(&long, &o);
    assert_eq!(got.cycles, 7, "{:?}", got.notes);
    assert_eq!(got.cycles_skipped, 0, "{:?}", got.notes);
    let (g, w) = (imeps(&got), imeps(&want));
    for (a, b) in g.iter().zip(&w) {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{g:?} {w:?}");
    }
    let notes = got.notes.join("\n");
    assert!(notes.contains("partial cycles at the start"), "{notes}");
    assert!(
        !notes.contains("dropout") && !notes.contains("starts again"),
        "{notes}"
    );
    // Cycles that do start again keep that note.
    assert!(
        want.notes.iter().all(|n| !n.contains("starts again")),
        "{:?}",
        want.notes
    );
}

/// Issue 36, item 4: a names row over a units row is one header whatever
/// a column the reader does not know holds (`Q_1` over `J/°CA`): four
/// cylinders, not four cycles, and `Q_1` left out with a note.
#[test]
fn names_over_units_with_an_unknown_column() {
    let (o, _) = options();
    let mut text = String::from("CA,PCYL1,PCYL2,PCYL3,PCYL4,Q_1\ndeg,bar,bar,bar,bar,J/°CA\n");
    for i in 0..1440 {
        let a = i as f64 * 0.5;
        text.push_str(&format!(
            "{a},{},{},{},{},{:.3}\n",
            cell(a, 0),
            cell(a, 1),
            cell(a, 2),
            cell(a, 3),
            (a / 100.0).sin()
        ));
    }
    let got = read(&text, &o);
    assert_eq!(got.cylinders.len(), 4, "{:?}", got.notes);
    assert_eq!(got.cycles, 1, "{:?}", got.notes);
    assert!(
        got.notes
            .iter()
            .any(|n| n.contains("left out") && n.contains("Q_1")),
        "{:?}",
        got.notes
    );
}

/// Issue 36, item 8: the data settle a gap of at most 90° that holds no
/// TDC. A 200° gap over the gas-exchange TDC, where two interpolants agree,
/// is refused, saying why; a 60° one on the exhaust stroke is bridged.
#[test]
fn the_data_settle_no_wide_gap_and_none_over_a_tdc() {
    let (o, _) = options();
    let with_gap = |from: f64, to: f64| {
        let mut t = String::from("crank_deg,pressure_bar\n");
        for i in 0..1440 {
            let a = i as f64 * 0.5;
            if a > from && a < to {
                continue;
            }
            t.push_str(&format!("{a},{}\n", cell(a, 0)));
        }
        t
    };
    let (_, g) = options();
    let e = load(with_gap(250.0, 450.0).as_bytes(), &o, &g)
        .unwrap_err()
        .to_string();
    assert!(e.contains("wider than 90°"), "{e}");
    let e = load(with_gap(330.0, 400.0).as_bytes(), &o, &g)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("holds a TDC (the gas-exchange TDC at 360°)"),
        "{e}"
    );
    let r = read(&with_gap(200.0, 260.0), &o);
    assert!(
        r.notes.iter().any(|n| n.contains("the data settle it")),
        "{:?}",
        r.notes
    );
}

/// Issue 36, item 12: a file cut short is judged on its coverage before
/// the plausibility pass: "the data cover 148° of the 720° cycle", never
/// "not a cylinder pressure".
#[test]
fn a_file_cut_short_is_judged_on_coverage() {
    let (o, g) = options();
    let mut t = String::from("crank_deg,pressure_bar\n");
    for i in 0..=148 {
        let a = -360.0 + i as f64;
        t.push_str(&format!("{a},{}\n", cell(a, 0)));
    }
    let e = load(t.as_bytes(), &o, &g).unwrap_err().to_string();
    assert!(
        e.contains("the data cover 148° of the 720° cycle") && !e.contains("not a cylinder"),
        "{e}"
    );
}

/// Issue 36, item 6: a pressure-only record sampled on the crank angle
/// (no angle column: the DAQ was clocked by the encoder) reads with
/// `--angle-step`, `--tdc-deg` placing firing TDC on that axis: the whole
/// cycles of the record of item 5, to the bit. A one-column file without
/// a header gets a hint that proposes it.
#[test]
fn a_record_sampled_on_the_crank_angle_reads_with_angle_step() {
    let (mut o, g) = options();
    let start = 132.5;
    let mut text = String::from("pressure_bar\n");
    let rows = (8.0 * 720.0 / 0.5) as usize;
    for i in 0..rows {
        let a = start + i as f64 * 0.5;
        let k = ((a + 360.0) / 720.0).floor() as usize;
        text.push_str(&format!("{}\n", cell(a.rem_euclid(720.0), k)));
    }
    let e = load(text.as_bytes(), &o, &g).unwrap_err().to_string();
    assert!(e.contains("--angle-step"), "{e}");
    o.angle_step_deg = Some(0.5);
    o.tdc_deg = 720.0 - start;
    o.tdc_given = true;
    let got = read(&text, &o);
    let mut long = String::from("cycle,crank_deg,pressure_bar\n");
    for k in 1..8 {
        for i in 0..1440 {
            let a = i as f64 * 0.5;
            long.push_str(&format!("{k},{a},{}\n", cell(a, k)));
        }
    }
    let (o2, _) = options();
    let want = read(&long, &o2);
    assert_eq!(got.cycles, 7, "{:?}", got.notes);
    let (a, b) = (imeps(&got), imeps(&want));
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-9 * y.abs(), "{a:?} {b:?}");
    }
    // Without a header: the hint proposes --angle-step.
    let bare = text.replacen("pressure_bar\n", "", 1);
    let (o3, _) = options();
    let e = load(bare.as_bytes(), &o3, &g).unwrap_err().to_string();
    assert!(
        e.contains("--angle-step DEG") && e.contains("--columns pressure_bar"),
        "{e}"
    );
    // A file with an angle column refuses it.
    let e = load(long.as_bytes(), &o, &g).unwrap_err().to_string();
    assert!(e.contains("--angle-step"), "{e}");
}

/// Issue 36, item 9: a constant-pressure steam engine's diagram (a
/// textbook problem) is refused by the compression bound, naming
/// `--no-compression-check`; with it, it reads; the 1000 bar bound stays.
#[test]
fn no_compression_check_reads_a_steam_engine() {
    let (mut o, g) = options();
    let steam = |peak: f64| {
        let mut t = String::from("crank_deg,pressure_bar\n");
        for i in 0..720 {
            let a = i as f64;
            // Admission at 8 bar from TDC to 100°, exhaust at 1.2 bar.
            let p = if a < 100.0 { peak } else { 1.2 };
            t.push_str(&format!("{a},{p}\n"));
        }
        t
    };
    let e = load(steam(8.0).as_bytes(), &o, &g).unwrap_err().to_string();
    assert!(
        e.contains("not a cylinder pressure") && e.contains("--no-compression-check"),
        "{e}"
    );
    o.compression_check = false;
    let r = load(steam(8.0).as_bytes(), &o, &g).unwrap();
    let imep = imeps(&r)[0];
    assert!(imep > 0.0, "{imep}");
    let e = load(steam(1500.0).as_bytes(), &o, &g)
        .unwrap_err()
        .to_string();
    assert!(e.contains("above the 1000 bar"), "{e}");
}

/// Issue 36, items 3 and 12: the mean trace's peak lies between −15° and
/// +60° of firing TDC. A motored trace read with `--tdc-deg` 360° off is
/// refused naming the phasing (not the pegging or the compression
/// ratio), `--tdc-deg` and the angle that puts the peak at +10°; a fired
/// one 96° off names the shift.
#[test]
fn a_tdc_a_revolution_off_names_the_phasing() {
    let (mut o, g) = options();
    let motored = |a: f64| {
        let d = (a + 360.0).rem_euclid(720.0) - 360.0;
        1.0 + 14.0 * (-(d / 70.0).powi(2)).exp()
    };
    let mut t = String::from("crank_deg,pressure_bar\n");
    for i in 0..1440 {
        let a = i as f64 * 0.5;
        t.push_str(&format!("{a},{:.6}\n", motored(a)));
    }
    read(&t, &o);
    o.tdc_deg = 360.0;
    o.tdc_given = true;
    let e = load(t.as_bytes(), &o, &g).unwrap_err().to_string();
    assert!(
        e.contains("the phasing is wrong")
            && e.contains("the file's angle 360 (--tdc-deg)")
            && e.contains("--tdc-deg 710 puts the peak at +10°"),
        "{e}"
    );
    // Fired, TDC placed 96° early: the peak 96° late.
    let mut f = String::from("crank_deg,pressure_bar\n");
    for i in 0..1440 {
        let a = i as f64 * 0.5;
        f.push_str(&format!("{a},{}\n", cell(a, 0)));
    }
    let right = read(&f, &options().0);
    let at = right
        .pressure
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .unwrap()
        .0 as f64
        * right.step_deg;
    o.tdc_deg = -96.0;
    let e = load(f.as_bytes(), &o, &g).unwrap_err().to_string();
    let want = format!(
        "--tdc-deg {} puts the peak at +10°",
        enginedyn_numerics::format::trimmed(-96.0 + at + 96.0 - 10.0, 1)
    );
    assert!(e.contains(&want) && !e.contains("phasing"), "{want}: {e}");
}

/// Issue 36, item 3: the peak-angle rule holds for each cylinder's mean
/// too. Four cylinders, each on its own firing TDC (`--cylinder-axis
/// own`), all read with TDC placed 96° early: refused on cylinder 1,
/// naming the shift; read right, they pass.
#[test]
fn each_cylinders_mean_peaks_near_its_tdc() {
    let (mut o, g) = options();
    o.cylinder_axis = Some(enginedyn_ingest::CylinderAxis::Own);
    let mut t = String::from("cylinder,crank_deg,pressure_bar\n");
    for c in 1..=4 {
        for i in 0..1440 {
            let a = i as f64 * 0.5;
            t.push_str(&format!("{c},{a},{}\n", cell(a, c)));
        }
    }
    let right = read(&t, &o);
    assert_eq!(right.cylinders.len(), 4);
    o.tdc_deg = -96.0;
    o.tdc_given = true;
    let e = load(t.as_bytes(), &o, &g).unwrap_err().to_string();
    assert!(
        e.contains("the mean trace of cylinder 1 peaks +") && e.contains("--tdc-deg"),
        "{e}"
    );
}
