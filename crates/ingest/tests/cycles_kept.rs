//! What the `cycles` table is built from: the cycles left out of the
//! averages are kept with their reason, and a time record's cycles carry
//! the speed measured over each.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, load};

fn fixture(name: &str) -> Vec<u8> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    std::fs::read(format!("{root}/tests/fixtures/measured/{name}")).unwrap()
}

/// `dropout_20cycles.csv`: 2 of 20 cycles have a run of missing rows;
/// both are listed with the reason the note gives, and used plus skipped
/// are the file's 20 cycles, each once.
#[test]
fn skipped_cycles_are_listed_with_their_reason() {
    let grid = GridOptions::new(0.5, Interp::Auto);
    let r = load(
        &fixture("dropout_20cycles.csv")[..],
        &ParseOptions::new(720.0),
        &grid,
    )
    .unwrap();
    assert_eq!(r.cycles_skipped, 2);
    assert_eq!(r.skipped.len(), 2);
    let mut all: Vec<i64> = r
        .stats
        .iter()
        .map(|s| s.cycle)
        .chain(r.skipped.iter().map(|s| s.cycle))
        .collect();
    all.sort_unstable();
    assert_eq!(all, (1..=20).collect::<Vec<i64>>());
    let note = r
        .notes
        .iter()
        .find(|n| n.starts_with("2 of 20 cycles left out"))
        .unwrap();
    for s in &r.skipped {
        assert_eq!(s.cylinder, 0);
        assert!(
            s.reason.starts_with(
                "a gap in the data (a dropout: a spacing of more than 5 median steps): "
            ),
            "{}",
            s.reason
        );
        // The note names the widest gap in the same words.
        assert!(note.contains("for a gap in the data (a dropout: a spacing of more than 5 median steps; the widest: cycle "));
        assert!(s.reason.ends_with('°'), "{}", s.reason);
    }
    // No time record: no speed of its own.
    assert!(r.stats.iter().all(|s| s.rpm.is_none()));
}

/// A time record whose speed steps up cycle by cycle (1000, 1100, 1200,
/// 1300 rpm, constant within each cycle): each cycle's `rpm` is its
/// speed, within the pulse edge's timing (half a sample at 72 kHz over a
/// 0.1 s cycle: under 1e-4; 1e-3 allowed).
#[test]
fn a_time_record_times_each_cycle() {
    let dt = 1.0 / 72_000.0;
    // Each cycle is the window −360…+360° around its firing TDC (even
    // pulses): revolutions 1–2, 3–4, 5–6, 7–8; 0 and 9 are partial ones.
    let speeds = [
        1000.0, 1000.0, 1000.0, 1100.0, 1100.0, 1200.0, 1200.0, 1300.0, 1300.0, 1300.0,
    ];
    let revs = speeds.len();
    // Pulse times: one a revolution, the first at 0.01 s.
    let mut edges = vec![0.01];
    for rpm in speeds {
        let last = *edges.last().unwrap();
        edges.push(last + 60.0 / rpm);
    }
    let end = edges[revs] + 0.01;
    let mut text = String::from("time_s,pressure_bar,tdc\n");
    let mut k = 0usize;
    loop {
        let t = k as f64 * dt;
        if t > end {
            break;
        }
        // The crank angle from the first pulse (even pulses: firing TDC).
        let rev = edges.windows(2).position(|w| t < w[1]).unwrap_or(revs);
        let angle = if t < edges[0] {
            -360.0 * (edges[0] - t) * speeds[0] / 60.0
        } else if rev < revs {
            360.0 * rev as f64 + 360.0 * (t - edges[rev]) / (edges[rev + 1] - edges[rev])
        } else {
            360.0 * revs as f64 + 360.0 * (t - edges[revs]) * speeds[revs - 1] / 60.0
        };
        let a = (angle + 360.0).rem_euclid(720.0) - 360.0;
        let p = 1.0 + 40.0 * (-((a - 10.0) / 30.0).powi(2)).exp();
        let pulse = if edges.iter().any(|&e| t >= e && t < e + 5.0 * dt) {
            5.0
        } else {
            0.0
        };
        text.push_str(&format!("{t:.9},{p:.6},{pulse}\n"));
        k += 1;
    }
    let grid = GridOptions::new(0.5, Interp::Auto);
    let r = load(text.as_bytes(), &ParseOptions::new(720.0), &grid).unwrap();
    let got: Vec<f64> = r.stats.iter().map(|s| s.rpm.unwrap()).collect();
    assert_eq!(got.len(), 4, "{:?}", r.notes);
    for (g, want) in got.iter().zip([1000.0, 1100.0, 1200.0, 1300.0]) {
        assert!((g / want - 1.0).abs() < 1e-3, "{got:?}");
    }
}
