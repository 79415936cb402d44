//! Issue 43, item 1 (INTERFACE.md, "A cycle is the window around its
//! firing TDC"): a record longer than a cycle is cut at each gas-exchange
//! TDC, so each cycle holds its own compression, combustion and expansion.
//! The cycles are built with loads far apart (0.5 to 1.5 times the
//! combustion), so a cut that joins the expansion of one to the
//! compression of the next shows at once in the per-cycle IMEP.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Resampled, load};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};

fn cylinder() -> Cylinder {
    let cs = CrankSlider::new(0.027, 0.027 / 0.3, 0.0).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.068, 8.5).unwrap()
}

fn options() -> (ParseOptions, GridOptions) {
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cylinder());
    let mut g = GridOptions::new(0.5, Interp::Auto);
    g.cylinder = Some(cylinder());
    (o, g)
}

/// Cycle k's load: 0.5 … 1.5, no two alike.
fn load_of(k: i64) -> f64 {
    0.5 + (k.rem_euclid(5) as f64) * 0.25
}

/// Cycle k's pressure (bar) at `d` degrees from its own firing TDC, `d`
/// in −360…+360: compression, and a combustion bump times its load; the
/// gas exchange flat at 1 bar, so the windows join without a step.
fn p_of(d: f64, k: i64) -> f64 {
    1.0 + 14.0 * (-(d / 70.0).powi(2)).exp()
        + 45.0 * load_of(k) * (-((d - 20.0) / 22.0).powi(2)).exp()
}

/// A long record without a `cycle` column, the angle running on from
/// `from` (deg from the first firing TDC) for `rows` samples of 0.5°.
fn record(from: f64, rows: usize) -> String {
    let mut s = String::from("crank_deg,pressure_bar\n");
    for i in 0..rows {
        let a = from + i as f64 * 0.5;
        let k = ((a + 360.0) / 720.0).floor() as i64;
        s.push_str(&format!("{a},{:.6}\n", p_of(a - 720.0 * k as f64, k)));
    }
    s
}

/// Cycle k alone, a one-cycle diagram from −360 to 359.5.
fn alone(k: i64) -> Resampled {
    let (o, g) = options();
    let mut s = String::from("crank_deg,pressure_bar\n");
    for i in 0..1440 {
        let d = -360.0 + i as f64 * 0.5;
        s.push_str(&format!("{d},{:.6}\n", p_of(d, k)));
    }
    load(s.as_bytes(), &o, &g).unwrap()
}

fn imeps(r: &Resampled) -> Vec<f64> {
    r.stats.iter().map(|s| s.imep_pa.unwrap()).collect()
}

/// A record of exactly N whole windows (−360 … N·720 − 360, as an
/// indicating system's angle master writes it) gives N cycles, each the
/// IMEP of its own cycle read alone (to the bit: the same samples on the
/// same grid); today's main cut it at each firing TDC: N − 1 cycles, each
/// mixing two loads.
#[test]
fn a_record_of_n_whole_windows_gives_n_cycles() {
    let (o, g) = options();
    for n in [1usize, 2, 10] {
        let r = load(record(-360.0, n * 1440).as_bytes(), &o, &g).unwrap();
        assert_eq!(r.cycles, n, "{:?}", r.notes);
        let got = imeps(&r);
        for (k, x) in got.iter().enumerate() {
            let want = imeps(&alone(k as i64))[0];
            assert!(
                (x - want).abs() <= 1e-9 * want.abs(),
                "cycle {k}: {x} vs {want}"
            );
        }
        // The loads differ: so do the IMEPs (a mixed cut would average them).
        if n > 1 {
            assert!((got[1] - got[0]).abs() > 0.05 * got[0].abs(), "{got:?}");
        }
        let notes = r.notes.join("\n");
        assert!(
            !notes.contains("partial") && !notes.contains("starts again"),
            "{notes}"
        );
        if n > 1 {
            assert!(notes.contains("cut at each gas-exchange TDC"), "{notes}");
        }
    }
}

/// A record whose angle runs on from 0 (0 … 36,000° less a step: fifty
/// cycles' span) is cut at each gas-exchange TDC, never at its first
/// sample: the 49 whole windows (360 … 35,640°), the partial halves at
/// both ends left out with a note that calls them partial and says the
/// same for the same amount (720 samples, 360°, at each end).
#[test]
fn a_record_running_on_from_zero_gives_its_whole_windows() {
    let (o, g) = options();
    let r = load(record(0.0, 72_000).as_bytes(), &o, &g).unwrap();
    assert_eq!(r.cycles, 49, "{:?}", r.notes);
    let notes = r.notes.join("\n");
    assert!(
        notes.contains(
            "the partial cycles at the start (720 samples, 360° of the 720° cycle) and the end (720 samples, 360° of the 720° cycle) left out"
        ),
        "{notes}"
    );
    assert!(
        !notes.contains("dropout") && !notes.contains("starts again"),
        "{notes}"
    );
    // Cycle 1 is the window around the firing TDC at 720°: load_of(1).
    let got = imeps(&r);
    for (i, x) in got.iter().enumerate().take(6) {
        let want = imeps(&alone(i as i64 + 1))[0];
        assert!(
            (x - want).abs() <= 1e-9 * want.abs(),
            "cycle {}: {x} vs {want}",
            i + 1
        );
    }
}

/// The same for a two-stroke (cut at BDC, −180…+180°): three whole
/// windows from −180°.
#[test]
fn a_two_stroke_record_is_cut_at_bdc() {
    let mut o = ParseOptions::new(360.0);
    o.cylinder = None;
    let g = GridOptions::new(0.5, Interp::Auto);
    let mut s = String::from("crank_deg,pressure_bar\n");
    for i in 0..3 * 720 {
        let a = -180.0 + i as f64 * 0.5;
        let k = ((a + 180.0) / 360.0).floor() as i64;
        let d = a - 360.0 * k as f64;
        s.push_str(&format!(
            "{a},{:.6}\n",
            1.0 + 20.0 * load_of(k) * (-((d - 10.0) / 25.0).powi(2)).exp()
        ));
    }
    let r = load(s.as_bytes(), &o, &g).unwrap();
    assert_eq!(r.cycles, 3, "{:?}", r.notes);
    let peaks: Vec<f64> = r.stats.iter().map(|c| c.p_max / 1e5).collect();
    for (k, p) in peaks.iter().enumerate() {
        let want = 1.0 + 20.0 * load_of(k as i64);
        assert!((p - want).abs() < 1e-3, "{peaks:?}");
    }
    assert!(
        r.notes.join("\n").contains("cut at each BDC"),
        "{:?}",
        r.notes
    );
}
