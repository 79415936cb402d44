//! SVG charts with one look: the same size, fonts, palette and axes style.

use crate::ReportError;
use enginedyn_engine::Engine;
use enginedyn_pipeline::Analysis;
use plotters::prelude::*;

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(90, 90, 90),
];
const SIZE: (u32, u32) = (900, 520);
/// Most points drawn per series; finer curves are thinned (display only).
const MAX_POINTS: usize = 1500;

/// One named curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Drawn dashed (reference lines such as a mean).
    pub dashed: bool,
}

impl Series {
    /// A solid series from x and y slices, thinned for display.
    pub fn new(name: impl Into<String>, x: impl Iterator<Item = f64>, y: &[f64]) -> Self {
        let stride = y.len().div_ceil(MAX_POINTS).max(1);
        let points = x
            .zip(y.iter().copied())
            .enumerate()
            .filter(|(k, _)| k % stride == 0)
            .map(|(_, p)| p)
            .collect();
        Self {
            name: name.into(),
            points,
            dashed: false,
        }
    }
    /// A dashed horizontal line at `y` over `[x0, x1]`.
    pub fn hline(name: impl Into<String>, y: f64, x0: f64, x1: f64) -> Self {
        Self {
            name: name.into(),
            points: vec![(x0, y), (x1, y)],
            dashed: true,
        }
    }
}

/// A line chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// File name (`torque.svg`), also used in errors.
    pub file: String,
    /// Caption.
    pub title: String,
    /// X axis quantity and unit.
    pub x_label: String,
    /// Y axis quantity and unit.
    pub y_label: String,
    /// Curves.
    pub series: Vec<Series>,
    /// Logarithmic axes.
    pub log: bool,
    /// Same scale on both axes (polar diagrams).
    pub equal: bool,
}

fn bounds(series: &[Series], log: bool) -> ((f64, f64), (f64, f64)) {
    let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
    let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
    for s in series {
        for &(x, y) in &s.points {
            if !x.is_finite() || !y.is_finite() || (log && (x <= 0.0 || y <= 0.0)) {
                continue;
            }
            xr = (xr.0.min(x), xr.1.max(x));
            yr = (yr.0.min(y), yr.1.max(y));
        }
    }
    let pad = |(a, b): (f64, f64), frac: f64| {
        if !a.is_finite() {
            return (0.0, 1.0);
        }
        let d = if b > a {
            (b - a) * frac
        } else {
            a.abs().max(1.0) * 0.1
        };
        (a - d, b + d)
    };
    if log {
        let f = |(a, b): (f64, f64)| {
            if a.is_finite() {
                (a / 1.1, b * 1.1)
            } else {
                (1.0, 10.0)
            }
        };
        (f(xr), f(yr))
    } else {
        ((xr.0.min(xr.1), xr.1), pad(yr, 0.05))
    }
}

impl Chart {
    /// Renders to an SVG document.
    pub fn render(&self) -> Result<String, ReportError> {
        let err = |e: &dyn std::fmt::Display| ReportError::Chart {
            name: self.file.clone(),
            message: e.to_string(),
        };
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            root.fill(&WHITE).map_err(|e| err(&e))?;
            let ((x0, x1), (mut y0, mut y1)) = bounds(&self.series, self.log);
            let (mut x0, mut x1) = if x1 > x0 {
                (x0, x1)
            } else {
                (x0 - 1.0, x0 + 1.0)
            };
            if self.equal {
                let r = [x0.abs(), x1.abs(), y0.abs(), y1.abs()]
                    .into_iter()
                    .fold(0.0_f64, f64::max);
                // Plot area is wider than tall: widen x to keep one scale.
                let aspect = (SIZE.0 as f64 - 120.0) / (SIZE.1 as f64 - 110.0);
                (x0, x1, y0, y1) = (-r * aspect, r * aspect, -r, r);
            }
            let mut builder = ChartBuilder::on(&root);
            builder
                .caption(&self.title, ("sans-serif", 20))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(75);
            macro_rules! draw {
                ($chart:expr) => {{
                    let mut chart = $chart;
                    chart
                        .configure_mesh()
                        .x_desc(self.x_label.as_str())
                        .y_desc(self.y_label.as_str())
                        .label_style(("sans-serif", 13))
                        .axis_desc_style(("sans-serif", 15))
                        .light_line_style(RGBColor(235, 235, 235))
                        .draw()
                        .map_err(|e| err(&e))?;
                    for (i, s) in self.series.iter().enumerate() {
                        let color = if s.dashed { PALETTE[5] } else { PALETTE[i % 5] };
                        let style = color.stroke_width(if s.dashed { 1 } else { 2 });
                        let pts = s.points.iter().copied().filter(|(x, y)| {
                            x.is_finite() && y.is_finite() && (!self.log || (*x > 0.0 && *y > 0.0))
                        });
                        let drawn = if s.dashed {
                            chart.draw_series(DashedLineSeries::new(pts, 6, 4, style))
                        } else {
                            chart.draw_series(LineSeries::new(pts, style))
                        }
                        .map_err(|e| err(&e))?;
                        drawn.label(s.name.as_str()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                        });
                    }
                    chart
                        .configure_series_labels()
                        .background_style(WHITE.mix(0.85))
                        .border_style(RGBColor(200, 200, 200))
                        .label_font(("sans-serif", 13))
                        .position(SeriesLabelPosition::UpperRight)
                        .draw()
                        .map_err(|e| err(&e))?;
                }};
            }
            if self.log {
                draw!(
                    builder
                        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                        .map_err(|e| err(&e))?
                );
            } else {
                draw!(
                    builder
                        .build_cartesian_2d(x0..x1, y0..y1)
                        .map_err(|e| err(&e))?
                );
            }
            root.present().map_err(|e| err(&e))?;
        }
        Ok(svg)
    }
}

/// The charts of `run --out DIR`: (file name, SVG).
pub fn run_charts(engine: &Engine, a: &Analysis) -> Result<Vec<(String, String)>, ReportError> {
    let n = a.pressure.len();
    let deg = || (0..n).map(|k| (k as f64 * a.step).to_degrees());
    let cycle = (n as f64 * a.step).to_degrees();
    let angle = "crank angle from firing TDC of cylinder 1 (deg)".to_string();
    let title = |what: &str| format!("{} — {what}", engine.name());
    let mean = a.uniformity.mean;
    let mut charts = vec![Chart {
        file: "torque.svg".into(),
        title: title(&format!("torque at {:.0} rpm", a.summary.rpm)),
        x_label: angle.clone(),
        y_label: "torque (N m)".into(),
        series: vec![
            Series::new("cylinder 1", deg(), &a.forces.torque),
            Series::new(
                format!("engine ({} cylinders)", engine.cylinders()),
                deg(),
                &a.torque.total,
            ),
            Series::hline(format!("mean (indicated) {mean:.1} N m"), mean, 0.0, cycle),
        ],
        log: false,
        equal: false,
    }];
    let bar: Vec<f64> = a.pressure.iter().map(|p| p / 1e5).collect();
    charts.push(Chart {
        file: "pressure.svg".into(),
        title: title("cylinder pressure"),
        x_label: angle.clone(),
        y_label: "pressure (bar, absolute)".into(),
        series: vec![Series::new("p(φ)", deg(), &bar)],
        log: false,
        equal: false,
    });
    charts
        .iter()
        .map(|c| Ok((c.file.clone(), c.render()?)))
        .collect()
}
