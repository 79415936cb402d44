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
