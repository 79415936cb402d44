//! Tick labels, legend keys and the tornado chart's size.

use enginedyn_report::{
    Chart, Figure, ScatterChart, ScatterGroup, ScatterPoint, Series, TornadoBar, TornadoPanel,
    tick_label, tornado_svg,
};

#[test]
fn tick_labels_are_clean_numbers() {
    assert_eq!(tick_label(-2e-16, 0.1), "0");
    assert_eq!(tick_label(2.2e-17, 1e-3), "0");
    assert_eq!(tick_label(-0.0, 1.0), "0");
    assert_eq!(tick_label(0.1 + 0.2, 0.1), "0.3");
    assert_eq!(tick_label(-0.30000000000000004, 0.05), "-0.3");
    assert_eq!(tick_label(0.25, 0.25), "0.25");
    assert_eq!(tick_label(4900.0, 5.0), "4900");
    assert_eq!(tick_label(2.5e6, 5e5), "2.5e6");
    assert_eq!(tick_label(3e-5, 1e-5), "3e-5");
    // Not a round-off: a real small value on a fine axis.
    assert_eq!(tick_label(2e-4, 1e-4), "0.0002");
}

/// Polylines inside the legend frame: (stroke, width, x-extent).
fn keys(svg: &str) -> Vec<(String, String, f64)> {
    let frame = svg
        .split("<rect ")
        .find(|t| t.contains("stroke=\"#C8C8C8\"") && t.contains("fill=\"none\""))
        .expect("a legend frame");
    let num = |t: &str, k: &str| -> f64 {
        let i = t.find(&format!(" {k}=\"")).unwrap() + k.len() + 3;
        t[i..i + t[i..].find('"').unwrap()].parse().unwrap()
    };
    let frame = format!(" {frame}");
    let (x, y) = (num(&frame, "x"), num(&frame, "y"));
    let (x1, y1) = (x + num(&frame, "width"), y + num(&frame, "height"));
    svg.split("<polyline ")
        .skip(1)
        .filter_map(|t| {
            let t = format!(" {}", &t[..t.find("/>")?]);
            let get = |k: &str| {
                let i = t.find(&format!(" {k}=\""))? + k.len() + 3;
                Some(t[i..i + t[i..].find('"')?].to_string())
            };
            let pts: Vec<(f64, f64)> = get("points")?
                .split_whitespace()
                .filter_map(|p| {
                    let (a, b) = p.split_once(',')?;
                    Some((a.parse().ok()?, b.parse().ok()?))
                })
                .collect();
            let inside = pts
                .iter()
                .all(|p| p.0 > x && p.0 < x1 && p.1 > y && p.1 < y1);
            inside.then(|| {
                (
                    get("stroke").unwrap_or_default(),
                    get("stroke-width").unwrap_or_default(),
                    pts.iter().map(|p| p.0).fold(f64::MIN, f64::max)
                        - pts.iter().map(|p| p.0).fold(f64::MAX, f64::min),
                )
            })
        })
        .collect()
}

#[test]
fn legend_keys_repeat_the_line_style() {
    let x = [0.0, 1.0, 2.0, 3.0];
    let chart = Chart {
        title: "t".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        series: vec![
            Series::new("curve", x.iter().copied(), &[1.0, 3.0, 2.0, 4.0]),
            Series::hline("mean", 2.5, 0.0, 3.0),
        ],
        log: false,
        equal: false,
        angle_ticks: None,
    };
    let svg = Figure::single("t.svg", chart).render().unwrap();
    let k = keys(&svg);
    let solid: Vec<_> = k.iter().filter(|k| k.0 == "#1F77B4").collect();
    let dashed: Vec<_> = k.iter().filter(|k| k.0 == "#5A5A5A").collect();
    assert_eq!(solid.len(), 1, "{k:?}");
    assert_eq!(solid[0].1, "2");
    // The dashed series' key is dashes (6 on, 4 off) of its own width.
    assert!(dashed.len() >= 2, "{k:?}");
    assert!(dashed.iter().all(|d| d.1 == "1" && d.2 <= 6.0), "{k:?}");
}

#[test]
fn tornado_fits_the_page_unscaled() {
    let panel = TornadoPanel {
        title: "torque_max_nm = 375.3 N m".into(),
        x_label: "change (% of nominal)".into(),
        bars: (0..7)
            .map(|k| TornadoBar {
                label: format!("throw_angle_deg[{k}]"),
                minus: -0.1 * k as f64,
                plus: 0.12 * k as f64,
            })
            .collect(),
        marks: vec![("RSS σ".into(), 0.2)],
    };
    let svg = tornado_svg("t.svg", "title", &vec![panel; 16], 4).unwrap();
    let width: u32 = svg
        .split("width=\"")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    // report.html is 1280 px wide: wider charts are scaled down, and
    // their 12 px labels become unreadable.
    assert!(width <= 1280, "tornado {width} px wide");
    assert!(svg.contains("throw_angle_deg[6]"));
}

#[test]
fn scatter_labels_every_point() {
    let group = |name: &str, style, pts: &[(f64, f64, &str)]| ScatterGroup {
        name: name.into(),
        style,
        filled: true,
        points: pts
            .iter()
            .map(|&(x, y, l)| ScatterPoint {
                x,
                y,
                label: l.into(),
            })
            .collect(),
    };
    let chart = ScatterChart {
        file: "a.svg".into(),
        title: "t".into(),
        x_label: "time per analysis (ms)".into(),
        y_label: "largest relative error of the key results".into(),
        groups: vec![
            group(
                "kinematics",
                0,
                &[(1.0, 1e-2, "series2"), (1.1, 1e-6, "exact")],
            ),
            group("grid step", 3, &[(0.05, 1e-3, "2°"), (0.1, 1e-4, "1°")]),
        ],
        steps: Some((
            "Pareto front".into(),
            vec![(0.05, 1e-3), (0.1, 1e-4), (1.1, 1e-6)],
        )),
        guides: vec![(1e-3, "tolerance 1e-3: cheapest 2°".into())],
    };
    let svg = chart.render().unwrap();
    for text in [
        ">series2<",
        ">exact<",
        ">2°<",
        ">1°<",
        ">Pareto front<",
        "tolerance 1e-3",
        ">1e-3<",
    ] {
        let plain = text.trim_matches(['<', '>']);
        assert!(
            svg.contains(text) || svg.contains(&format!("\n{plain}\n")),
            "{text} missing"
        );
    }
}

/// `accuracy.svg` as `enginedyn_accuracy::figure` builds it, from a
/// committed `accuracy.csv`: a group per study and basis (filled: against
/// the reference or the generated diagram's truth; hollow: differences on
/// this diagram), each point labelled with its setting, the Pareto front,
/// and guides at 1e-2, 1e-3 and 1e-4 naming the cheapest setting.
fn accuracy_chart(path: &std::path::Path) -> ScatterChart {
    let mut r = csv::Reader::from_path(path).unwrap();
    let mut groups: Vec<ScatterGroup> = Vec::new();
    let mut rows: Vec<(String, String, f64, f64)> = Vec::new();
    for rec in r.records() {
        let rec = rec.unwrap();
        let (study, setting) = (rec[0].to_string(), rec[1].to_string());
        let (Ok(t), Ok(e)) = (rec[2].parse::<f64>(), rec[3].parse::<f64>()) else {
            continue;
        };
        let (x, y) = (t * 1e3, e.max(1e-12));
        let differences = setting.contains("difference");
        let basis = if setting.contains("generated") {
            " (generated diagram)"
        } else if differences {
            " (this diagram, difference)"
        } else {
            ""
        };
        let name = format!("{study}{basis}");
        let label = setting.split(" (").next().unwrap().replace(" at ", " ");
        let style = [
            "kinematics",
            "rod_model",
            "interpolation",
            "grid_step",
            "integration",
        ]
        .iter()
        .position(|s| *s == study)
        .unwrap();
        let p = ScatterPoint { x, y, label };
        match groups.iter_mut().find(|g| g.name == name) {
            Some(g) => g.points.push(p),
            None => groups.push(ScatterGroup {
                name,
                style,
                filled: !differences,
                points: vec![p],
            }),
        }
        rows.push((study, setting, x, y));
    }
    let mut front: Vec<&(String, String, f64, f64)> = rows
        .iter()
        .filter(|a| {
            !rows
                .iter()
                .any(|b| b.2 <= a.2 && b.3 <= a.3 && (b.2 < a.2 || b.3 < a.3))
        })
        .collect();
    front.sort_by(|a, b| a.2.total_cmp(&b.2));
    let guides = [1e-2, 1e-3, 1e-4]
        .into_iter()
        .map(|tol: f64| {
            let text = match front.iter().find(|r| r.3 <= tol) {
                Some(r) => format!(
                    "tolerance {tol:.0e}: cheapest {} {}, {:.3} ms",
                    r.0,
                    r.1.split(" (").next().unwrap(),
                    r.2
                ),
                None => format!("tolerance {tol:.0e}: no setting"),
            };
            (tol, text)
        })
        .collect();
    ScatterChart {
        file: "accuracy.svg".into(),
        title: "accuracy against cost of each method setting".into(),
        x_label: "time per analysis (ms)".into(),
        y_label: "largest relative error of the key results".into(),
        groups,
        steps: Some((
            "Pareto front (nothing both faster and more exact)".into(),
            front.iter().map(|r| (r.2, r.3)).collect(),
        )),
        guides,
    }
}

fn overlapping(p: (i32, i32, i32, i32), q: (i32, i32, i32, i32)) -> bool {
    p.0 < q.2 && q.0 < p.2 && p.1 < q.3 && q.1 < p.3
}

/// No label of `accuracy.svg` covers a marker or another label (the
/// guides are named in the legend), in the committed accuracy studies of
/// every bundled engine (their crowded corner near the reference settings
/// included) and in a cluster of coincident points; every label stays
/// inside the plot.
#[test]
fn accuracy_labels_cover_no_marker_and_no_label() {
    let reports = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reports");
    let mut charts: Vec<(String, ScatterChart)> = Vec::new();
    for e in std::fs::read_dir(&reports).unwrap() {
        let path = e.unwrap().path().join("accuracy.csv");
        if path.exists() {
            charts.push((path.display().to_string(), accuracy_chart(&path)));
        }
    }
    assert!(charts.len() >= 6, "{} accuracy studies", charts.len());
    // Eight settings on one spot and six a hair apart.
    let pile = ScatterGroup {
        name: "pile".into(),
        style: 0,
        filled: true,
        points: (0..14)
            .map(|k| ScatterPoint {
                x: if k < 8 {
                    0.5
                } else {
                    0.5 * (1.0 + 0.01 * k as f64)
                },
                y: 1e-6,
                label: format!("setting {k}"),
            })
            .collect(),
    };
    let mut crowded = charts[0].1.clone();
    crowded.groups.push(pile);
    charts.push(("crowded".into(), crowded));
    for (name, chart) in &charts {
        let l = chart.layout().unwrap();
        let n: usize = chart.groups.iter().map(|g| g.points.len()).sum();
        assert_eq!(l.labels.len(), n, "{name}: every point labelled");
        for (i, a) in l.labels.iter().enumerate() {
            let p = l.plot;
            assert!(
                a.bounds.0 >= p.0 && a.bounds.1 >= p.1 && a.bounds.2 <= p.2 && a.bounds.3 <= p.3,
                "{name}: {} outside the plot",
                a.text
            );
            for m in &l.markers {
                assert!(
                    !overlapping(a.bounds, *m),
                    "{name}: {} covers a marker",
                    a.text
                );
            }
            for b in &l.labels[i + 1..] {
                assert!(
                    !overlapping(a.bounds, b.bounds),
                    "{name}: {} covers {}",
                    a.text,
                    b.text
                );
            }
        }
    }
}
