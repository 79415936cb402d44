//! The torsion charts of the bundled engines with `[torsion]`: every
//! resonance of a major order labelled `order × mode`, no two labels
//! overlapping (and [`LABEL_GAP`] apart), no label on a marker, no leader
//! through another label or marker, major order lines heavier than the
//! others, the order numbers at the lines' ends. `ENGINEDYN_CHARTS_OUT=DIR` also writes the
//! SVGs there, to look at.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, load};
use enginedyn_pipeline::torsion::{Study, crank_train, excitation, study};
use enginedyn_pipeline::{MAX_ORDER, Options, analyse};
use enginedyn_report::{CampbellChart, LABEL_GAP, PlacedLabel, segment_hits, torsion_charts};

/// The study `enginedyn torsion` runs on a bundled engine: its default
/// speeds, 20 % to 120 % of the operating speed in 50 steps.
fn bundled(stem: &str) -> (String, Study) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/");
    let text = std::fs::read_to_string(format!("{dir}{stem}.toml")).unwrap();
    let engine = enginedyn_engine::file::parse(&text, stem).unwrap();
    let spec = enginedyn_engine::file::parse_torsion(&text)
        .unwrap()
        .expect("[torsion]");
    let csv = std::fs::read(format!("{dir}{stem}.csv")).unwrap();
    let mut po = ParseOptions::new(engine.cycle().to_degrees());
    po.cylinder = Some(*engine.cylinder());
    let r = load(&csv[..], &po, &GridOptions::new(0.5, Interp::Auto)).unwrap();
    let rpm = r.rpm.or(engine.operating().rpm).unwrap();
    let opts = Options {
        step_deg: 0.5,
        ..Default::default()
    };
    let a = analyse(&engine, &r, rpm, &opts).unwrap();
    let train = crank_train(
        &engine,
        &spec,
        engine.rod_model(),
        a.flywheel.as_ref().map(|f| f.inertia),
    )
    .unwrap();
    let ex = excitation(&engine, &r, &opts, MAX_ORDER).unwrap();
    let rpms: Vec<f64> = (0..50).map(|k| rpm * (0.2 + k as f64 / 49.0)).collect();
    (
        engine.name().to_string(),
        study(&train, &ex, &rpms).unwrap(),
    )
}

fn overlapping(a: &PlacedLabel, b: &PlacedLabel) -> bool {
    let (p, q) = (a.bounds, b.bounds);
    p.0 < q.2 && q.0 < p.2 && p.1 < q.3 && q.1 < p.3
}

fn check(stem: &str, majors: f64) {
    let (name, s) = bundled(stem);
    assert!((s.firings_per_revolution - majors).abs() < 1e-12);
    let chart = CampbellChart::from_study(&name, &s);
    let layout = chart.layout().unwrap();
    let svg = torsion_charts(&name, &s).unwrap();
    // Written before the checks, to look at when one fails.
    if let Some(dir) = std::env::var_os("ENGINEDYN_CHARTS_OUT") {
        let dir = std::path::Path::new(&dir).join(stem);
        std::fs::create_dir_all(&dir).unwrap();
        for (file, text) in &svg {
            std::fs::write(dir.join(file), text).unwrap();
        }
    }
    // Every resonance is marked; every major one is labelled.
    assert_eq!(chart.marks.len(), s.resonances.len());
    let majors: Vec<String> = chart
        .marks
        .iter()
        .filter(|m| m.major)
        .map(|m| {
            format!(
                "{} × mode {}",
                enginedyn_numerics::format::human(m.order),
                m.mode
            )
        })
        .collect();
    assert!(!majors.is_empty(), "{stem}: no major resonance in range");
    for text in &majors {
        assert!(
            layout.resonances.iter().any(|l| &l.text == text),
            "{stem}: {text} is not labelled"
        );
    }
    // Thinned: fewer labels than resonances where they crowd, none overlap,
    // each inside the plot.
    let all: Vec<&PlacedLabel> = layout.resonances.iter().chain(&layout.orders).collect();
    for (i, a) in all.iter().enumerate() {
        for b in &all[i + 1..] {
            assert!(!overlapping(a, b), "{stem}: {} overlaps {}", a.text, b.text);
        }
    }
    for l in &layout.resonances {
        let (b, p) = (l.bounds, layout.plot);
        assert!(
            b.0 >= p.0 && b.1 >= p.1 && b.2 <= p.2 && b.3 <= p.3,
            "{}",
            l.text
        );
    }
    // Labels read apart: a clear gap between any two resonance labels.
    let labels = &layout.resonances;
    for (i, a) in labels.iter().enumerate() {
        for b in &labels[i + 1..] {
            let g = LABEL_GAP;
            let (p, q) = (a.bounds, b.bounds);
            let apart = p.2 + g <= q.0 || q.2 + g <= p.0 || p.3 + g <= q.1 || q.3 + g <= p.1;
            assert!(
                apart,
                "{stem}: {} and {} closer than {g} px",
                a.text, b.text
            );
        }
    }
    // No label (its white ground a pixel wider) on any marker.
    assert_eq!(layout.markers.len(), chart.marks.len());
    for l in labels {
        let g = (l.bounds.0 - 1, l.bounds.1, l.bounds.2 + 1, l.bounds.3);
        for (k, m) in layout.markers.iter().enumerate() {
            let hit = g.0 < m.2 && m.0 < g.2 && g.1 < m.3 && m.1 < g.3;
            let mark = &chart.marks[k];
            assert!(
                !hit,
                "{stem}: {} covers the marker of {} × mode {} at {:?}",
                l.text,
                enginedyn_numerics::format::human(mark.order),
                mark.mode,
                m
            );
        }
    }
    // A leader runs from its marker to its label and through nothing else.
    for d in &layout.leaders {
        let own = &labels[d.label];
        for (k, l) in labels.iter().enumerate() {
            if k != d.label {
                assert!(
                    !segment_hits(d.from, d.to, l.bounds),
                    "{stem}: the leader of {} crosses {}",
                    own.text,
                    l.text
                );
            }
        }
        for (k, m) in layout.markers.iter().enumerate() {
            if k != d.marker {
                assert!(
                    !segment_hits(d.from, d.to, *m),
                    "{stem}: the leader of {} crosses a marker at {m:?}",
                    own.text
                );
            }
        }
    }
    // Every major order that reaches the plot has its number at its end.
    let top = chart.modes.iter().map(|m| m.1).fold(0.0, f64::max) * 1.1;
    for &k in &s.orders {
        let major = enginedyn_torsion::is_major_order(k, s.firings_per_revolution);
        if !major || enginedyn_torsion::order_frequency_hz(k, chart.speed.0) >= top {
            continue;
        }
        let text = enginedyn_numerics::format::human(k);
        assert!(
            layout.orders.iter().any(|l| l.text == text && l.major),
            "{stem}: major order {text} has no number"
        );
    }
    // Major lines heavy and dark, the others light and thin (SVG strokes).
    let campbell = &svg[0].1;
    assert!(campbell.contains(r##"stroke="#1E1E1E" stroke-width="2""##));
    assert!(campbell.contains(r##"stroke="#BEBEBE" stroke-width="1""##));
}

#[test]
fn inline_six_diesel_campbell() {
    // Four-stroke six: 3 firings per revolution.
    check("i6_diesel", 3.0);
}

#[test]
fn cross_plane_v8_campbell() {
    // Four-stroke eight: 4 firings per revolution.
    check("v8_crossplane", 4.0);
}
