//! The charts read at a glance, checked on the SVG geometry: legends never
//! cover data, tick labels carry no round-off, log axes have distinct
//! labels and no band of crowded grid lines.

use enginedyn_ingest::{GridOptions, ParseOptions};
use enginedyn_pipeline::{Analysis, Options};
use enginedyn_report::{Chart, Figure, Series, run_figures};
use std::path::Path;

/// The value of attribute `name` in the tag `tag`.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let i = tag.find(&key)? + key.len();
    let j = tag[i..].find('"')?;
    Some(&tag[i..i + j])
}

/// Every tag `<kind …>` in the document.
fn tags<'a>(svg: &'a str, kind: &str) -> Vec<&'a str> {
    let open = format!("<{kind} ");
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find(&open) {
        let end = rest[i..].find('>').map_or(rest.len(), |j| i + j + 1);
        out.push(&rest[i..end]);
        rest = &rest[end..];
    }
    out
}

/// Text contents of every `<text>` element.
fn texts(svg: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<text") {
        let Some(a) = rest[i..].find('>') else { break };
        let Some(b) = rest[i + a..].find("</text>") else {
            break;
        };
        out.push(rest[i + a + 1..i + a + b].trim().to_string());
        rest = &rest[i + a + b..];
    }
    out
}

/// The legend frames: rectangles stroked in the legend frame's grey with
/// no fill, as (x0, y0, x1, y1).
fn legend_boxes(svg: &str) -> Vec<(f64, f64, f64, f64)> {
    tags(svg, "rect")
        .into_iter()
        .filter(|t| attr(t, "stroke") == Some("#C8C8C8") && attr(t, "fill") == Some("none"))
        .filter_map(|t| {
            let v = |k| attr(t, k)?.parse::<f64>().ok();
            let (x, y, w, h) = (v("x")?, v("y")?, v("width")?, v("height")?);
            Some((x, y, x + w, y + h))
        })
        .collect()
}

/// Data lines: polylines in a series colour (the palette or the dashed
/// grey), as point lists.
fn data_lines(svg: &str) -> Vec<Vec<(f64, f64)>> {
    const SERIES: [&str; 9] = [
        "#1F77B4", "#D62728", "#2CA02C", "#FF7F0E", "#9467BD", "#8C564B", "#E377C2", "#17BECF",
        "#5A5A5A",
    ];
    tags(svg, "polyline")
        .into_iter()
        .filter(|t| attr(t, "stroke").is_some_and(|s| SERIES.contains(&s)))
        .map(|t| {
            attr(t, "points")
                .unwrap_or("")
                .split_whitespace()
                .filter_map(|p| {
                    let (x, y) = p.split_once(',')?;
                    Some((x.parse().ok()?, y.parse().ok()?))
                })
                .collect()
        })
        .collect()
}

/// Points of the data lines inside a legend box (segments sampled every
/// pixel or so), with the chart's name.
fn covered(name: &str, svg: &str) -> Vec<String> {
    let boxes = legend_boxes(svg);
    let mut hits = Vec::new();
    for line in data_lines(svg) {
        // A legend key: a short horizontal stroke inside the box.
        let key = line.len() == 2
            && (line[0].1 - line[1].1).abs() < 0.5
            && (line[1].0 - line[0].0).abs() <= 30.0
            && boxes.iter().any(|b| {
                line.iter()
                    .all(|p| p.0 > b.0 && p.0 < b.2 && p.1 > b.1 && p.1 < b.3)
            });
        if key {
            continue;
        }
        let segments = line.windows(2).map(|w| (w[0], w[1]));
        let single = line.first().map(|&p| (p, p));
        for (a, b) in segments.chain(single) {
            let n = ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as usize).clamp(1, 2000);
            for k in 0..=n {
                let t = k as f64 / n as f64;
                let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                for bx in &boxes {
                    if x > bx.0 && x < bx.2 && y > bx.1 && y < bx.3 {
                        hits.push(format!("{name}: ({x:.0}, {y:.0}) inside legend {bx:?}"));
                    }
                }
            }
        }
    }
    hits
}

fn bundled(name: &str) -> (enginedyn_engine::Engine, Analysis) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let engine = enginedyn_engine::file::read(&root.join(format!("{name}.toml"))).unwrap();
    let cycle = engine.cycle().to_degrees();
    let parse = ParseOptions {
        cylinder: Some(*engine.cylinder()),
        ..ParseOptions::new(cycle)
    };
    let grid = GridOptions {
        cylinder: Some(*engine.cylinder()),
        ..GridOptions::new(1.0, enginedyn_ingest::Interp::Auto)
    };
    let file = std::fs::File::open(engine.diagram().unwrap()).unwrap();
    let resampled = enginedyn_ingest::load(std::io::BufReader::new(file), &parse, &grid).unwrap();
    let rpm = resampled.rpm.or(engine.operating().rpm).unwrap();
    let opts = Options {
        step_deg: 1.0,
        ..Options::default()
    };
    let a = enginedyn_pipeline::analyse(&engine, &resampled, rpm, &opts).unwrap();
    (engine, a)
}

#[test]
fn legends_never_cover_data_in_the_bundled_charts() {
    let mut hits = Vec::new();
    let mut legends = 0;
    for name in ["vaz2108", "single", "i3_two_stroke", "v8_crossplane"] {
        let (engine, a) = bundled(name);
        for fig in run_figures(&engine, &a) {
            let svg = fig.render().unwrap();
            legends += legend_boxes(&svg).len();
            hits.extend(covered(&format!("{name}/{}", fig.file), &svg));
        }
    }
    assert!(legends >= 20, "legends found: {legends}");
    assert!(
        hits.is_empty(),
        "{} points under a legend, e.g. {:?}",
        hits.len(),
        &hits[..hits.len().min(5)]
    );
}

fn line_chart(y: &[f64], log: bool) -> String {
    let x: Vec<f64> = (0..y.len())
        .map(|k| {
            if log {
                1000.0 + 100.0 * k as f64
            } else {
                k as f64
            }
        })
        .collect();
    let chart = Chart {
        title: "t".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        series: vec![
            Series::from_points(
                "a",
                x.iter()
                    .copied()
                    .zip(y.iter().copied())
                    .collect::<Vec<_>>()
                    .into_iter(),
            ),
            Series::hline("b", y[0], x[0], x[x.len() - 1]),
        ],
        log,
        equal: false,
        angle_ticks: None,
    };
    Figure::single("t.svg", chart).render().unwrap()
}

/// Labels that read as numbers.
fn numbers(svg: &str) -> Vec<String> {
    texts(svg)
        .into_iter()
        .filter(|t| t.parse::<f64>().is_ok())
        .collect()
}

#[test]
fn tick_labels_carry_no_round_off() {
    for (lo, hi) in [
        (-0.7, 0.3),
        (-0.35, 0.25),
        (-1.3, 0.9),
        (-0.03, 0.05),
        (-7.0, 3.0),
        (-2.1e-3, 1.3e-3),
    ] {
        let y: Vec<f64> = (0..50).map(|k| lo + (hi - lo) * k as f64 / 49.0).collect();
        let svg = line_chart(&y, false);
        for label in numbers(&svg) {
            let v: f64 = label.parse().unwrap();
            assert!(
                v == 0.0 || v.abs() > 1e-9 * (hi - lo),
                "range {lo}..{hi}: round-off label {label}"
            );
            assert!(label.len() <= 7, "range {lo}..{hi}: long label {label}");
            assert!(label != "-0", "range {lo}..{hi}: -0");
        }
    }
}

#[test]
fn log_axes_have_distinct_labels_and_no_band() {
    // A p–V loop's range (litres against bar), and an error range.
    for (ylo, yhi) in [(0.9_f64, 60.0_f64), (1e-7, 0.1), (3.0, 8.0)] {
        let y: Vec<f64> = (0..32)
            .map(|k| ylo * (yhi / ylo).powf(k as f64 / 31.0))
            .collect();
        let svg = line_chart(&y, true);
        let labels = numbers(&svg);
        let mut seen = std::collections::HashSet::new();
        for l in &labels {
            assert!(
                seen.insert(l.clone()),
                "{ylo}..{yhi}: doubled label {l} in {labels:?}"
            );
        }
        assert!(labels.len() >= 4, "{ylo}..{yhi}: labels {labels:?}");
        if ylo < 1e-6 {
            for decade in ["1e-3", "1e-5", "0.01"] {
                assert!(
                    labels.iter().any(|l| l == decade),
                    "no {decade} in {labels:?}"
                );
            }
        }
        // No shaded band: grid lines at least 3 px apart.
        let mut ys: Vec<f64> = tags(&svg, "polyline")
            .into_iter()
            .filter(|t| {
                attr(t, "stroke").is_some_and(|s| s != "#000000") && !data_lines(&svg).is_empty()
            })
            .filter_map(|t| {
                let p: Vec<&str> = attr(t, "points")?.split_whitespace().collect();
                let (a, b) = (p.first()?.split_once(',')?, p.get(1)?.split_once(',')?);
                (p.len() == 2 && a.1 == b.1 && a.0 != b.0).then(|| a.1.parse().ok())?
            })
            .collect();
        ys.sort_by(f64::total_cmp);
        ys.dedup();
        let gap = ys
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        assert!(gap >= 3.0, "{ylo}..{yhi}: grid lines {gap} px apart");
    }
}

/// The polylines of a given stroke colour, as point lists (in document
/// order), with their `stroke-dasharray` if any.
type Line = (Vec<(f64, f64)>, Option<String>);

fn lines_of(svg: &str, stroke: &str) -> Vec<Line> {
    tags(svg, "polyline")
        .into_iter()
        .filter(|t| attr(t, "stroke") == Some(stroke))
        .map(|t| {
            let pts = attr(t, "points")
                .unwrap_or("")
                .split_whitespace()
                .filter_map(|p| {
                    let (x, y) = p.split_once(',')?;
                    Some((x.parse().ok()?, y.parse().ok()?))
                })
                .collect();
            (pts, attr(t, "stroke-dasharray").map(str::to_string))
        })
        .collect()
}

fn svg_of(figs: &[enginedyn_report::Figure], file: &str) -> String {
    figs.iter()
        .find(|f| f.file == file)
        .unwrap_or_else(|| panic!("no {file}"))
        .render()
        .unwrap()
}

/// Smooth curves are written at sub-pixel precision: plotters' whole
/// pixels drew them as stair-steps (every coordinate a whole number).
#[test]
fn curves_are_drawn_between_whole_pixels() {
    let (engine, a) = bundled("vaz2108");
    let figs = run_figures(&engine, &a);
    for (file, stroke) in [
        ("torque.svg", "#D62728"),
        ("torque.svg", "#1F77B4"),
        ("crankpin_polar.svg", "#1F77B4"),
    ] {
        let svg = svg_of(&figs, file);
        let (pts, _) = lines_of(&svg, stroke)
            .into_iter()
            .max_by_key(|l| l.0.len())
            .unwrap();
        assert!(pts.len() > 500, "{file}: {} points", pts.len());
        let frac = |v: f64| ((v - v.floor()) * 100.0).round() as i64 % 100;
        let off_grid = pts
            .iter()
            .filter(|p| frac(p.0) != 0 || frac(p.1) != 0)
            .count();
        assert!(
            off_grid * 10 >= pts.len() * 9,
            "{file} {stroke}: {off_grid} of {} points between whole pixels",
            pts.len()
        );
        let distinct: std::collections::HashSet<i64> = pts.iter().map(|p| frac(p.1)).collect();
        assert!(
            distinct.len() > 50,
            "{file} {stroke}: {} distinct hundredths of a pixel",
            distinct.len()
        );
        // Consecutive points of a smooth curve never repeat a pixel row
        // for long: a stair-step holds y over several points.
        let mut run = 0;
        let mut longest = 0;
        for w in pts.windows(2) {
            run = if (w[1].1 - w[0].1).abs() < 1e-9 {
                run + 1
            } else {
                0
            };
            longest = longest.max(run);
        }
        assert!(longest < 3, "{file} {stroke}: y held over {longest} steps");
    }
}

/// The labels of a figure's angle axis: numbers among the texts.
fn has_label(svg: &str, label: &str) -> bool {
    texts(svg).iter().any(|t| t == label)
}

/// Every angle axis ends on its labelled dead centre (720, two-stroke
/// 360), and `centered` runs it from minus half the cycle to plus half,
/// the curves rotated by half a cycle.
#[test]
fn angle_axes_end_on_a_labelled_dead_centre() {
    for (name, cycle) in [("vaz2108", 720.0), ("i3_two_stroke", 360.0)] {
        let (engine, a) = bundled(name);
        let half = format!("{}", cycle / 2.0);
        let end = format!("{cycle}");
        let plain = run_figures(&engine, &a);
        let centred = enginedyn_report::run_figures_with(&engine, &a, true);
        let mut angle_charts = 0;
        for (p, c) in plain.iter().zip(&centred) {
            let (p, c) = (p.render().unwrap(), c.render().unwrap());
            if !texts(&p).iter().any(|t| t.starts_with("crank angle")) {
                continue;
            }
            angle_charts += 1;
            assert!(
                has_label(&p, "0") && has_label(&p, &end),
                "{name}: no {end}"
            );
            assert!(!has_label(&c, &end), "{name}: centred axis to {end}");
            assert!(
                has_label(&c, &format!("-{half}")) && has_label(&c, &half),
                "{name}: centred axis not ±{half}"
            );
        }
        assert!(angle_charts >= 5, "{name}: {angle_charts} angle charts");
        // The engine torque, one point per degree: the centred curve's
        // first point is the plain one's at half the cycle, and both start
        // at the axis's left end and reach its right end.
        let n = (cycle / a.step.to_degrees()).round() as usize;
        let line = |figs: &[enginedyn_report::Figure]| {
            lines_of(&svg_of(figs, "torque.svg"), "#D62728")
                .into_iter()
                .max_by_key(|l| l.0.len())
                .unwrap()
                .0
        };
        let (p, c) = (line(&plain), line(&centred));
        assert_eq!(p.len(), n + 1, "{name}: closed over the cycle");
        assert_eq!(c.len(), n + 1);
        for k in [0, 1, n / 4, n / 2, n - 1, n] {
            let j = (k + n / 2) % n;
            assert!((c[k].1 - p[j].1).abs() < 0.02, "{name}: point {k}");
        }
        assert!((c[0].0 - p[0].0).abs() < 1e-9 && (c[n].0 - p[n].0).abs() < 1e-9);
    }
}

/// The indicated and the effective mean torque are two reference lines of
/// their own colour and dash, each named in the legend.
#[test]
fn torque_means_are_told_apart() {
    let (engine, a) = bundled("vaz2108");
    assert!(a.summary.mechanical_efficiency < 1.0);
    let svg = svg_of(&run_figures(&engine, &a), "torque.svg");
    let words = texts(&svg);
    for label in ["mean, indicated", "mean, effective"] {
        assert!(words.iter().any(|t| t.starts_with(label)), "{label}");
    }
    // The plot's dashed lines: dead-centre markers (#AAAAAA) aside.
    let dashed: Vec<(String, String, f64)> = tags(&svg, "polyline")
        .into_iter()
        .filter(|t| attr(t, "stroke-dasharray").is_some() && attr(t, "stroke") != Some("#AAAAAA"))
        .map(|t| {
            let y: f64 = attr(t, "points")
                .unwrap()
                .split_whitespace()
                .next()
                .unwrap()
                .split_once(',')
                .unwrap()
                .1
                .parse()
                .unwrap();
            (
                attr(t, "stroke").unwrap().to_string(),
                attr(t, "stroke-dasharray").unwrap().to_string(),
                y,
            )
        })
        .collect();
    assert_eq!(dashed.len(), 2, "{dashed:?}");
    assert_ne!(dashed[0].0, dashed[1].0, "same colour: {dashed:?}");
    assert_ne!(dashed[0].1, dashed[1].1, "same dash: {dashed:?}");
    // Effective below indicated (η_m < 1): y pixels grow downwards.
    assert!(dashed[1].2 > dashed[0].2, "{dashed:?}");
}
