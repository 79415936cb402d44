//! accuracy.svg: every setting labelled, the axes named, the cheapest
//! setting per tolerance written on its guide.

use enginedyn_accuracy::{Accuracy, Row, Study, figure};

fn row(study: Study, setting: &str, time_s: f64, error: f64) -> Row {
    Row {
        study,
        setting: setting.into(),
        time_s,
        errors: vec![Some(error)],
    }
}

#[test]
fn every_setting_is_a_labelled_marker() {
    let a = Accuracy {
        rows: vec![
            row(Study::Kinematics, "series2", 1.0e-3, 1.2e-2),
            row(Study::Kinematics, "exact", 1.1e-3, 4e-6),
            row(
                Study::Interpolation,
                "pchip (generated, from 0.500° samples)",
                1.2e-2,
                1.7e-5,
            ),
            row(Study::GridStep, "2° (generated)", 2.6e-5, 1.6e-3),
            row(Study::GridStep, "1° (generated)", 5.2e-5, 4.2e-4),
            row(
                Study::GridStep,
                "1° (this diagram: difference from 0.01°)",
                8.7e-5,
                4.1e-4,
            ),
        ],
        reference_time_s: 1e-2,
        notes: Vec::new(),
    };
    let chart = figure(&a, "test engine");
    assert_eq!(chart.x_label, "time per analysis (ms)");
    assert_eq!(chart.y_label, "largest relative error of the key results");
    let labels: Vec<&str> = chart
        .groups
        .iter()
        .flat_map(|g| g.points.iter().map(|p| p.label.as_str()))
        .collect();
    assert_eq!(labels.len(), a.rows.len());
    for l in ["series2", "exact", "pchip", "2°", "1°"] {
        assert!(labels.contains(&l), "{l} not in {labels:?}");
    }
    // Studies differ in marker; the two bases of one study in fill.
    let kin = chart
        .groups
        .iter()
        .find(|g| g.name == "kinematics")
        .unwrap();
    let grid: Vec<_> = chart
        .groups
        .iter()
        .filter(|g| g.name.starts_with("grid_step"))
        .collect();
    assert_eq!(grid.len(), 2);
    assert!(grid.iter().all(|g| g.style != kin.style));
    assert_ne!(grid[0].filled, grid[1].filled);
    // Times in ms.
    assert!((kin.points[0].x - 1.0).abs() < 1e-12);
    // The guides name the cheapest setting within each tolerance.
    let g3 = chart
        .guides
        .iter()
        .find(|g| (g.0 - 1e-3).abs() < 1e-12)
        .unwrap();
    assert!(g3.1.contains("1°"), "{}", g3.1);
    let g2 = chart
        .guides
        .iter()
        .find(|g| (g.0 - 1e-2).abs() < 1e-12)
        .unwrap();
    assert!(g2.1.contains("2°"), "{}", g2.1);
    // The Pareto front's corners, fastest first.
    let (_, corners) = chart.steps.as_ref().unwrap();
    assert_eq!(corners.first().map(|c| c.0), Some(2.6e-2));
    let svg = chart.render().unwrap();
    assert!(svg.contains("series2") && svg.contains("tolerance 1e-3"));
}
