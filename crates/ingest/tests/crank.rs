//! The crank's own signals in a time record: an encoder and a 60-2 tooth
//! wheel follow the speed within each revolution, which one TDC pulse a
//! revolution cannot.
//!
//! The record is generated: the crank turns as θ(t) = θ₀ + Ω t + A sin(Ω t)
//! (the speed Ω (1 + A cos Ω t), ±10 % within every revolution, each
//! revolution lasting exactly 2π/Ω), sampled at 100 kHz; the pressure is
//! `synth`'s cycle at the true angle; each signal is a pulse train whose
//! edges are linear ramps two samples wide centred on the true edge time, so
//! half the range is crossed where the edge lies. The independent IMEP is
//! `synth`'s cycle integrated on the 0.1° grid directly (no time record).

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Wheel, load};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
use enginedyn_synth::{CycleModel, CycleSolution};
use std::f64::consts::PI;

const FS: f64 = 100_000.0;
const RPM: f64 = 2000.0;
/// The speed's swing within a revolution (relative).
const SWING: f64 = 0.1;
/// The crank angle (deg from firing TDC) at t = 0.
const THETA0: f64 = -200.0;
/// Samples: 5 cycles at 2000 rpm and more.
const SAMPLES: usize = 33_000;
/// Where the 60-2 wheel's first tooth after the gap lies (deg from cylinder
/// 1's TDC): TDC is 84° after it.
const WHEEL_TDC_DEG: f64 = 84.0;
const STEP: f64 = 0.1;

fn cylinder() -> Cylinder {
    let cs = CrankSlider::new(0.027, 0.084, 0.0).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.068, 8.5).unwrap()
}

fn omega() -> f64 {
    RPM * PI / 30.0
}

/// The true crank angle (deg) at `t`.
fn theta(t: f64) -> f64 {
    let w = omega();
    THETA0 + (w * t + SWING * (w * t).sin()).to_degrees()
}

/// The time the crank reaches `deg` (Newton on the exact motion).
fn time_of(deg: f64) -> f64 {
    let w = omega();
    let target = (deg - THETA0).to_radians();
    let mut t = target / w;
    for _ in 0..50 {
        let f = w * t + SWING * (w * t).sin() - target;
        let df = w * (1.0 + SWING * (w * t).cos());
        let dt = f / df;
        t -= dt;
        if dt.abs() < 1e-16 {
            break;
        }
    }
    t
}

/// A ramp from 0 to 1, two samples wide, centred on 0.
fn ramp(x: f64) -> f64 {
    (x * FS / 2.0 + 0.5).clamp(0.0, 1.0)
}

/// A pulse train: high from each rising edge time to its falling edge
/// time, `edges` in time order (rise, fall).
struct Train {
    edges: Vec<(f64, f64)>,
    i: usize,
}

impl Train {
    /// Pulses rising at crank angles `rise(j)` for j over the record,
    /// `width` degrees wide.
    fn new(rises: impl Iterator<Item = f64>, width: f64) -> Self {
        let end = SAMPLES as f64 / FS + 0.01;
        let edges = rises
            .map(|a| (time_of(a), time_of(a + width)))
            .filter(|e| e.1 > -0.01 && e.0 < end)
            .collect();
        Self { edges, i: 0 }
    }

    fn value(&mut self, t: f64) -> f64 {
        while self.i + 1 < self.edges.len() && self.edges[self.i].1 + 2.0 / FS < t {
            self.i += 1;
        }
        let mut v = 0.0;
        for &(r, f) in self.edges.iter().skip(self.i.saturating_sub(1)).take(3) {
            v += ramp(t - r) - ramp(t - f);
        }
        v
    }
}

/// The record as CSV: `time_s`, `pressure_bar`, then the signal columns.
/// `edit` may change a signal's value at sample i.
fn record(
    columns: &[&str],
    sol: &CycleSolution,
    mut edit: impl FnMut(usize, &mut [f64]),
) -> String {
    let first = (THETA0 / 360.0).floor() as i64 - 1;
    let revs = first..first + 20;
    let mut tdc = Train::new(revs.clone().map(|k| 360.0 * k as f64), 3.0);
    let mut enc = Train::new((360 * first..360 * (first + 20)).map(|j| j as f64), 0.5);
    let mut enc720 = Train::new(
        (720 * first..720 * (first + 20)).map(|j| j as f64 * 0.5),
        0.25,
    );
    let gap_at = -WHEEL_TDC_DEG;
    let mut wheel = Train::new(
        revs.flat_map(|k| (0..58).map(move |j| gap_at + 360.0 * k as f64 + 6.0 * j as f64)),
        3.0,
    );
    // The cam: one pulse a cycle, rising 120° before firing TDC.
    let mut cam = Train::new(
        (first / 2 - 1..first / 2 + 10).map(|k| 720.0 * k as f64 - 120.0),
        30.0,
    );
    let mut out = format!("time_s,pressure_bar,{}\n", columns.join(","));
    let mut v = vec![0.0; columns.len()];
    for i in 0..SAMPLES {
        let t = i as f64 / FS;
        let p = sol.pressure(theta(t).rem_euclid(720.0)) / 1e5;
        for (x, c) in v.iter_mut().zip(columns) {
            *x = 5.0
                * match *c {
                    "tdc" => tdc.value(t),
                    "encoder" => enc.value(t),
                    "encoder720" => enc720.value(t),
                    "wheel" => wheel.value(t),
                    "cam" => cam.value(t),
                    _ => 0.0,
                };
        }
        edit(i, &mut v);
        out.push_str(&format!("{t:.10},{p:.7}"));
        for x in &v {
            out.push_str(&format!(",{x:.5}"));
        }
        out.push('\n');
    }
    out
}

fn imep(cyl: &Cylinder, p: &[f64]) -> f64 {
    let h = STEP.to_radians();
    let w: f64 = p
        .iter()
        .enumerate()
        .map(|(i, p)| p * cyl.dvolume(i as f64 * h))
        .sum::<f64>()
        * h;
    w / cyl.swept_volume()
}

fn solution(cyl: &Cylinder) -> CycleSolution {
    CycleSolution::new(cyl, &CycleModel::petrol_full_load()).unwrap()
}

fn read(csv: &str, opts: &ParseOptions) -> Result<enginedyn_ingest::Resampled, String> {
    let grid = GridOptions::new(STEP, Interp::Auto);
    load(csv.as_bytes(), opts, &grid).map_err(|e| e.to_string())
}

#[test]
fn encoder_and_wheel_follow_the_speed_the_pulse_misses_it() {
    let cyl = cylinder();
    let sol = solution(&cyl);
    let n = (720.0 / STEP).round() as usize;
    let truth: Vec<f64> = (0..n).map(|i| sol.pressure(i as f64 * STEP)).collect();
    let want = imep(&cyl, &truth);
    let rel = |got: &enginedyn_ingest::Resampled| (imep(&cyl, &got.pressure) - want).abs() / want;

    let mut opts = ParseOptions::new(720.0);
    opts.encoder_ppr = Some(360);
    let enc = read(&record(&["tdc", "encoder"], &sol, |_, _| {}), &opts).unwrap();
    let mut opts = ParseOptions::new(720.0);
    opts.wheel = Some(Wheel::parse("60-2").unwrap());
    opts.wheel_tdc_deg = Some(WHEEL_TDC_DEG);
    let whl = read(&record(&["wheel"], &sol, |_, _| {}), &opts).unwrap();
    let pulse = read(
        &record(&["tdc"], &sol, |_, _| {}),
        &ParseOptions::new(720.0),
    )
    .unwrap();
    let (e, w, p) = (rel(&enc), rel(&whl), rel(&pulse));
    eprintln!(
        "IMEP {:.6} bar; relative errors: encoder {e:.2e}, wheel {w:.2e}, pulse {p:.2e}; cycles {} {} {}",
        want / 1e5,
        enc.cycles,
        whl.cycles,
        pulse.cycles
    );
    assert!(enc.cycles >= 3 && whl.cycles >= 3 && pulse.cycles >= 3);
    assert!(e < 1e-4, "encoder: {e:.2e}");
    assert!(w < 1e-4, "wheel: {w:.2e}");
    // One pulse a revolution puts the angle linear in time within it: up to
    // 0.1 rad (5.7°) off here.
    assert!(p > 1e-3, "pulse: {p:.2e}");
    // The speed note: the range within the revolutions, ±10 %.
    let note = whl
        .notes
        .iter()
        .find(|n| n.contains("tooth wheel"))
        .unwrap_or_else(|| panic!("{:?}", whl.notes));
    let range = note.split("revolutions read ").nth(1).unwrap();
    let mut it = range.split(" rpm").next().unwrap().split(" to ");
    let lo: f64 = it.next().unwrap().parse().unwrap();
    let hi: f64 = it.next().unwrap().parse().unwrap();
    assert!(
        (lo - 1800.0).abs() < 2.0 && (hi - 2200.0).abs() < 2.0,
        "{note}"
    );
    assert!(
        enc.notes.iter().any(|n| n.contains("`encoder` column's")),
        "{:?}",
        enc.notes
    );
    // The mean speed is the file's speed.
    let rpm = whl.rpm.unwrap();
    assert!((rpm - RPM).abs() < 0.5, "{rpm}");
}

/// The line of the first sample at or after time `t` (the header is line 1).
fn line_at(t: f64) -> usize {
    (t * FS).ceil() as usize + 2
}

/// The error's line, from "line N, column C: …".
fn error_line(e: &str) -> usize {
    e.strip_prefix("line ")
        .and_then(|r| r.split(',').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no line in: {e}"))
}

#[test]
fn an_edge_missing_or_extra_is_an_error_at_its_line() {
    let cyl = cylinder();
    let sol = solution(&cyl);
    let mut opts = ParseOptions::new(720.0);
    opts.encoder_ppr = Some(360);
    // The encoder's pulse at 1000° removed: the edge was due there.
    let (from, to) = (time_of(1000.0) - 1.5 / FS, time_of(1000.5) + 1.5 / FS);
    let csv = record(&["tdc", "encoder"], &sol, |i, v| {
        let t = i as f64 / FS;
        if (from..to).contains(&t) {
            v[1] = 0.0;
        }
    });
    let e = read(&csv, &opts).unwrap_err();
    assert!(
        e.contains("column 4") && e.contains("a missing edge"),
        "{e}"
    );
    // Where it was due, from its neighbours' median period: within a sample.
    let due = line_at(time_of(1000.0));
    assert!(error_line(&e).abs_diff(due) <= 1, "due at line {due}: {e}");

    // One sample high in the low half of the pulse at 1500°: an extra edge,
    // named at its own line.
    let extra = (time_of(1500.75) * FS).round() as usize;
    let csv = record(&["tdc", "encoder"], &sol, |i, v| {
        if i == extra {
            v[1] = 5.0;
        }
    });
    let e = read(&csv, &opts).unwrap_err();
    assert!(e.contains("an extra edge"), "{e}");
    assert_eq!(error_line(&e), extra + 2, "{e}");

    // The 60-2 wheel read as a 36-1 one: its gap spans 3 periods, not 2, an
    // error where the first missing tooth was due (the tooth at 270°, six
    // degrees after the last before the gap).
    let csv = record(&["wheel"], &sol, |_, _| {});
    let mut opts = ParseOptions::new(720.0);
    opts.wheel = Some(Wheel::parse("36-1").unwrap());
    opts.wheel_tdc_deg = Some(WHEEL_TDC_DEG);
    let e = read(&csv, &opts).unwrap_err();
    assert!(e.contains("36-1") && e.contains("--wheel"), "{e}");
    let due = line_at(time_of(-96.0));
    assert!(error_line(&e).abs_diff(due) <= 1, "due at line {due}: {e}");
    // As a 36-2 wheel the gap fits, but the second comes 60 positions after
    // the first: an error at the tooth that closes it.
    opts.wheel = Some(Wheel::parse("36-2").unwrap());
    let e = read(&csv, &opts).unwrap_err();
    assert!(
        e.contains("58 teeth between two gaps") && e.contains("36-2 wheel has 34"),
        "{e}"
    );
    assert_eq!(error_line(&e), line_at(time_of(276.0)), "{e}");
    // A spec that is no wheel is refused before anything is read.
    assert!(Wheel::parse("60/2").is_err());
}

#[test]
fn a_crank_signal_needs_its_flags() {
    let cyl = cylinder();
    let sol = solution(&cyl);
    let enc = record(&["tdc", "encoder"], &sol, |_, _| {});
    // Without --encoder-ppr: an error naming the flag, never the pulse's
    // 5 % wrong angle.
    let e = read(&enc, &ParseOptions::new(720.0)).unwrap_err();
    assert!(e.contains("--encoder-ppr") && e.contains("column 4"), "{e}");
    // A wrong --encoder-ppr: the TDC pulses are no whole number of
    // revolutions apart on its angle.
    let mut opts = ParseOptions::new(720.0);
    opts.encoder_ppr = Some(400);
    let e = read(&enc, &opts).unwrap_err();
    assert!(e.contains("not a whole number of revolutions"), "{e}");
    // The wheel needs --wheel-tdc-deg.
    let whl = record(&["wheel"], &sol, |_, _| {});
    let mut opts = ParseOptions::new(720.0);
    opts.wheel = Some(Wheel::parse("60-2").unwrap());
    let e = read(&whl, &opts).unwrap_err();
    assert!(e.contains("--wheel-tdc-deg"), "{e}");
    // An encoder given 0° by --tdc-time (a firing TDC) reads as with the pulse.
    let mut opts = ParseOptions::new(720.0);
    opts.encoder_ppr = Some(360);
    opts.tdc_time = Some(time_of(720.0));
    let only_enc = enc.replace(
        "time_s,pressure_bar,tdc,encoder",
        "time_s,pressure_bar,_,encoder",
    );
    let mut o2 = opts.clone();
    o2.columns = None;
    let got = read(&only_enc, &o2).unwrap();
    let n = (720.0 / STEP).round() as usize;
    let truth: Vec<f64> = (0..n).map(|i| sol.pressure(i as f64 * STEP)).collect();
    let rel = (imep(&cyl, &got.pressure) - imep(&cyl, &truth)).abs() / imep(&cyl, &truth);
    assert!(rel < 1e-4, "{rel:.2e}");
}

#[test]
fn a_cam_pulse_tells_the_firing_revolution() {
    let cyl = cylinder();
    let sol = solution(&cyl);
    let n = (720.0 / STEP).round() as usize;
    let truth: Vec<f64> = (0..n).map(|i| sol.pressure(i as f64 * STEP)).collect();
    let want = imep(&cyl, &truth);
    let mut opts = ParseOptions::new(720.0);
    opts.wheel = Some(Wheel::parse("58x").unwrap());
    opts.wheel_tdc_deg = Some(WHEEL_TDC_DEG);
    let got = read(&record(&["wheel", "cam"], &sol, |_, _| {}), &opts).unwrap();
    let rel = (imep(&cyl, &got.pressure) - want).abs() / want;
    assert!(rel < 1e-4, "{rel:.2e}");
    assert!(
        got.notes
            .iter()
            .any(|n| n.contains("after each `cam` pulse")),
        "{:?}",
        got.notes
    );
    // The cam moved a revolution on (the sensor read on the other cam
    // lobe): the firing TDC moves with it, and the cycle read is another.
    let moved = record(&["wheel", "cam"], &sol, |i, v| {
        let t = i as f64 / FS;
        let a = theta(t).rem_euclid(720.0);
        v[1] = if (240.0..270.0).contains(&a) {
            5.0
        } else {
            0.0
        };
    });
    // (IMEP cannot tell: the volume repeats every revolution, so ∮ p dV of
    // a cycle read 360° late is the same; the pressure peak moves, 360°
    // late: the peak-angle rule refuses it, naming the `cam` column and
    // the shift (issue 36, item 3).
    let e = read(&moved, &opts).unwrap_err();
    assert!(
        e.contains("after each `cam` pulse")
            && e.contains("`cam` pulse on the other revolution")
            && e.contains("the phasing is wrong"),
        "{e}"
    );
}

/// The peak of `r`'s mean trace (deg from firing TDC, on the grid).
fn peak_deg(r: &enginedyn_ingest::Resampled) -> f64 {
    let i = (0..r.pressure.len())
        .max_by(|&a, &b| r.pressure[a].total_cmp(&r.pressure[b]))
        .unwrap();
    i as f64 * STEP
}

/// Issue 36, item 3: a wrong count of the crank signal is refused, naming
/// the flag and the count the pressure peaks suggest: `--encoder-ppr 720`
/// on a 360-pulse encoder (the peaks every 360° of its angle), 360 on a
/// 720-pulse one (every 1440°).
#[test]
fn the_pressure_peaks_recur_once_a_cycle_of_the_signal() {
    let cyl = cylinder();
    let sol = solution(&cyl);
    let mut opts = ParseOptions::new(720.0);
    opts.cylinder = Some(cyl);
    opts.tdc_time = Some(time_of(720.0));
    let enc = record(&["encoder"], &sol, |_, _| {});
    opts.encoder_ppr = Some(360);
    let right = read(&enc, &opts).unwrap();
    assert!(peak_deg(&right) < 40.0, "{}", peak_deg(&right));
    opts.encoder_ppr = Some(720);
    let e = read(&enc, &opts).unwrap_err();
    assert!(
        e.contains("--encoder-ppr") && e.contains("says 720 pulses") && e.contains("suggest 360"),
        "{e}"
    );
    let enc720 = record(&["encoder720"], &sol, |_, _| {});
    opts.encoder_ppr = Some(720);
    let right = read(&enc720, &opts).unwrap();
    assert!(peak_deg(&right) < 40.0, "{}", peak_deg(&right));
    opts.encoder_ppr = Some(360);
    let e = read(&enc720, &opts).unwrap_err();
    assert!(
        e.contains("--encoder-ppr") && e.contains("says 360 pulses") && e.contains("suggest 720"),
        "{e}"
    );
}

/// Issue 36, item 3: the mean trace's peak lies between −15° and +60° of
/// firing TDC: `--wheel-tdc-deg 0` for 84 is refused, naming the flag and
/// the angle that puts the peak at +10°; so is a wheel record played
/// backwards.
#[test]
fn the_peak_lies_near_firing_tdc() {
    let cyl = cylinder();
    let sol = solution(&cyl);
    let whl = record(&["wheel"], &sol, |_, _| {});
    let mut opts = ParseOptions::new(720.0);
    opts.cylinder = Some(cyl);
    opts.wheel = Some(Wheel::parse("60-2").unwrap());
    opts.wheel_tdc_deg = Some(WHEEL_TDC_DEG);
    let right = read(&whl, &opts).unwrap();
    let at = peak_deg(&right);
    assert!((0.0..40.0).contains(&at), "{at}");
    opts.wheel_tdc_deg = Some(0.0);
    let e = read(&whl, &opts).unwrap_err();
    let want = format!(
        "--wheel-tdc-deg {} puts the peak at +10°",
        enginedyn_numerics::format::trimmed(at + WHEEL_TDC_DEG - 10.0, 1)
    );
    assert!(
        e.contains("--wheel-tdc-deg 0 after the first tooth") && e.contains(&want),
        "{want}: {e}"
    );
    // Played backwards: the rows in reverse order, the time still rising.
    let mut lines: Vec<&str> = whl.lines().collect();
    let header = lines.remove(0);
    let times: Vec<&str> = lines.iter().map(|l| l.split(',').next().unwrap()).collect();
    let mut back = format!("{header}\n");
    for (t, l) in times.iter().zip(lines.iter().rev()) {
        let rest = l.split_once(',').unwrap().1;
        back.push_str(&format!("{t},{rest}\n"));
    }
    opts.wheel_tdc_deg = Some(WHEEL_TDC_DEG);
    let e = read(&back, &opts).unwrap_err();
    assert!(
        e.contains("--wheel-tdc-deg") || e.contains("--wheel"),
        "{e}"
    );
}

/// Issue 36, item 7: edges have hysteresis. One encoder sample halfway in
/// the low half of a pulse (a sample caught mid-transition) makes no
/// edge: the record reads, to the IMEP of the clean edges.
#[test]
fn a_lone_sample_halfway_makes_no_edge() {
    let cyl = cylinder();
    let sol = solution(&cyl);
    let mut opts = ParseOptions::new(720.0);
    opts.encoder_ppr = Some(360);
    let clean = read(&record(&["tdc", "encoder"], &sol, |_, _| {}), &opts).unwrap();
    let odd = (time_of(1500.75) * FS).round() as usize;
    let csv = record(&["tdc", "encoder"], &sol, |i, v| {
        if i == odd {
            v[1] = 2.6;
        }
    });
    let got = read(&csv, &opts).unwrap();
    let (a, b) = (imep(&cyl, &clean.pressure), imep(&cyl, &got.pressure));
    assert!((a - b).abs() <= 1e-12 * a.abs(), "{a} {b}");
    assert_eq!(got.cycles, clean.cycles);
}
