//! SVG charts with one look: the same size, fonts, palette and axes style.
//! A [`Figure`] holds one or more [`Chart`] panels side by side.

use crate::ReportError;
use enginedyn_engine::Engine;
use enginedyn_kinematics::Table;
use enginedyn_pipeline::Analysis;
use plotters::coord::Shift;
use plotters::prelude::*;

pub(crate) const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];
pub(crate) const GREY: RGBColor = RGBColor(90, 90, 90);
const PANEL: (u32, u32) = (900, 520);
/// Most points drawn per series; finer curves are thinned (display only).
const MAX_POINTS: usize = 1500;

/// One named curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Drawn dashed and grey (reference lines such as a mean or a target).
    pub dashed: bool,
}

impl Series {
    /// A solid series from x values and a y slice, thinned for display.
    pub fn new(name: impl Into<String>, x: impl Iterator<Item = f64>, y: &[f64]) -> Self {
        let pts: Vec<(f64, f64)> = x.zip(y.iter().copied()).collect();
        Self::from_points(name, pts.into_iter())
    }
    /// A solid series from points, thinned for display.
    pub fn from_points(
        name: impl Into<String>,
        pts: impl ExactSizeIterator<Item = (f64, f64)>,
    ) -> Self {
        let stride = pts.len().div_ceil(MAX_POINTS).max(1);
        let points = pts
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

/// One panel: axes, curves and a legend.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
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
    /// Same scale on both axes, origin centred (polar diagrams).
    pub equal: bool,
    /// Spacing of dashed dead-centre markers on an angle axis (deg), e.g. 180.
    pub angle_ticks: Option<f64>,
}

impl Chart {
    /// A line chart over crank angle with dead-centre markers every 180°.
    pub fn angle(
        title: impl Into<String>,
        y_label: impl Into<String>,
        series: Vec<Series>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: "crank angle from firing TDC of cylinder 1 (deg)".into(),
            y_label: y_label.into(),
            series,
            log: false,
            equal: false,
            angle_ticks: Some(180.0),
        }
    }
}

/// A chart file: panels side by side.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// File name (`torque.svg`), also used in errors.
    pub file: String,
    /// Panels, left to right.
    pub panels: Vec<Chart>,
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
    if !xr.0.is_finite() {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    if log {
        return ((xr.0 / 1.1, xr.1 * 1.1), (yr.0 / 1.2, yr.1 * 1.2));
    }
    let widen = |(a, b): (f64, f64), frac: f64| {
        let d = if b > a {
            (b - a) * frac
        } else {
            a.abs().max(1.0) * 0.1
        };
        (a - d, b + d)
    };
    let x = if xr.1 > xr.0 { xr } else { widen(xr, 0.0) };
    (x, widen(yr, 0.06))
}

/// Tick labels without trailing zeros: 0, 90, 1.5, 2e5.
pub(crate) fn tick(v: &f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e6).contains(&a) {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.3}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" { "0".into() } else { s.to_string() }
    }
}

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// The corner of the plot with the fewest points, for the legend (upper
/// right on a tie): a p–V loop leaves the upper right empty, an error
/// against time chart the lower left.
fn legend_corner(
    series: &[Series],
    log: bool,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> SeriesLabelPosition {
    let unit = |v: f64, a: f64, b: f64| {
        if log {
            (v.ln() - a.ln()) / (b.ln() - a.ln())
        } else {
            (v - a) / (b - a)
        }
    };
    // Upper right, upper left, lower left, lower right.
    let mut count = [0usize; 4];
    for s in series {
        for &(x, y) in &s.points {
            let (u, v) = (unit(x, x0, x1), unit(y, y0, y1));
            if !(u.is_finite() && v.is_finite()) {
                continue;
            }
            let (right, left, top, bottom) = (u > 0.55, u < 0.45, v > 0.6, v < 0.4);
            for (k, hit) in [right && top, left && top, left && bottom, right && bottom]
                .into_iter()
                .enumerate()
            {
                count[k] += usize::from(hit);
            }
        }
    }
    match (0..4).min_by_key(|&k| (count[k], k)).unwrap_or(0) {
        1 => SeriesLabelPosition::UpperLeft,
        2 => SeriesLabelPosition::LowerLeft,
        3 => SeriesLabelPosition::LowerRight,
        _ => SeriesLabelPosition::UpperRight,
    }
}

impl Chart {
    fn draw(&self, area: &Area, file: &str) -> Result<(), ReportError> {
        let err = |e: &dyn std::fmt::Display| ReportError::Chart {
            name: file.to_string(),
            message: e.to_string(),
        };
        let ((mut x0, mut x1), (mut y0, mut y1)) = bounds(&self.series, self.log);
        if self.equal {
            let r = [x0.abs(), x1.abs(), y0.abs(), y1.abs()]
                .into_iter()
                .fold(0.0_f64, f64::max);
            let (w, h) = area.dim_in_pixel();
            let aspect = (w as f64 - 100.0) / (h as f64 - 100.0);
            (x0, x1, y0, y1) = (-r * aspect, r * aspect, -r, r);
        }
        let mut builder = ChartBuilder::on(area);
        builder
            .caption(&self.title, ("sans-serif", 18))
            .margin(14)
            .x_label_area_size(42)
            .y_label_area_size(70);
        macro_rules! finish {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(self.x_label.as_str())
                    .y_desc(self.y_label.as_str())
                    .x_label_formatter(&tick)
                    .y_label_formatter(&tick)
                    .label_style(("sans-serif", 13))
                    .axis_desc_style(("sans-serif", 14))
                    .light_line_style(RGBColor(238, 238, 238))
                    .bold_line_style(RGBColor(215, 215, 215))
                    .draw()
                    .map_err(|e| err(&e))?;
                let mut solid = 0;
                for s in &self.series {
                    let color = if s.dashed {
                        GREY
                    } else {
                        solid += 1;
                        PALETTE[(solid - 1) % PALETTE.len()]
                    };
                    let style = color.stroke_width(if s.dashed { 1 } else { 2 });
                    let pts: Vec<(f64, f64)> = s
                        .points
                        .iter()
                        .copied()
                        .filter(|(x, y)| {
                            x.is_finite() && y.is_finite() && (!self.log || (*x > 0.0 && *y > 0.0))
                        })
                        .collect();
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
                    .position(legend_corner(&self.series, self.log, (x0, x1), (y0, y1)))
                    .draw()
                    .map_err(|e| err(&e))?;
            }};
        }
        if self.log {
            finish!(
                builder
                    .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                    .map_err(|e| err(&e))?
            );
        } else if let Some(step) = self.angle_ticks {
            let mut chart = builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| err(&e))?;
            // Dead-centre markers every `step` degrees (no legend entry).
            let n = ((x1 - x0) / step).floor() as usize;
            for k in 1..=n {
                let x = x0 + k as f64 * step;
                chart
                    .draw_series(DashedLineSeries::new(
                        [(x, y0), (x, y1)],
                        3,
                        5,
                        RGBColor(170, 170, 170).stroke_width(1),
                    ))
                    .map_err(|e| err(&e))?;
            }
            finish!(chart);
        } else {
            finish!(
                builder
                    .build_cartesian_2d(x0..x1, y0..y1)
                    .map_err(|e| err(&e))?
            );
        }
        Ok(())
    }
}

impl Figure {
    /// One panel in a file.
    pub fn single(file: impl Into<String>, chart: Chart) -> Self {
        Self {
            file: file.into(),
            panels: vec![chart],
        }
    }

    /// Renders to an SVG document.
    pub fn render(&self) -> Result<String, ReportError> {
        let n = self.panels.len().max(1) as u32;
        let size = if n == 1 {
            PANEL
        } else {
            (PANEL.0 * n * 7 / 10, PANEL.1)
        };
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            root.fill(&WHITE).map_err(|e| ReportError::Chart {
                name: self.file.clone(),
                message: e.to_string(),
            })?;
            let areas = root.split_evenly((1, n as usize));
            for (chart, area) in self.panels.iter().zip(&areas) {
                chart.draw(area, &self.file)?;
            }
            root.present().map_err(|e| ReportError::Chart {
                name: self.file.clone(),
                message: e.to_string(),
            })?;
        }
        Ok(svg)
    }
}

/// The kinematics chart (shared by `run` and `kinematics`): the seeds'
/// coefficients A = x/R, B = v/(R w), C = a/(R w^2) and the rod angle over
/// one revolution, from a table on the grid `k * step_deg`.
pub fn kinematics_chart(title: impl Into<String>, t: &Table, r: f64, step_deg: f64) -> Chart {
    let deg = || (0..t.len()).map(|k| k as f64 * step_deg);
    let scale = |v: &[f64], f: f64| v.iter().map(|x| x * f).collect::<Vec<_>>();
    let mut c = Chart::angle(
        title,
        "x/R, v/(Rω), a/(Rω²); β (deg/10)",
        vec![
            Series::new("A = x/R", deg(), &scale(&t.x, 1.0 / r)),
            Series::new("B = v/(Rω)", deg(), &scale(&t.dx, 1.0 / r)),
            Series::new("C = a/(Rω²)", deg(), &scale(&t.d2x, 1.0 / r)),
            Series::new(
                "rod angle β (deg/10)",
                deg(),
                &scale(&t.beta, 18.0 / std::f64::consts::PI),
            ),
        ],
    );
    c.x_label = "crank angle from TDC (deg)".into();
    c
}

/// The charts of `run --out DIR`, in report order.
pub fn run_figures(engine: &Engine, a: &Analysis) -> Vec<Figure> {
    let n = a.torque.total.len();
    let has_pressure = !a.pressure.is_empty();
    let deg = || (0..n).map(|k| (k as f64 * a.step).to_degrees());
    let cycle = (n as f64 * a.step).to_degrees();
    let name = engine.name();
    let rpm = a.summary.rpm;
    let kn = |v: &[f64]| v.iter().map(|x| x / 1e3).collect::<Vec<_>>();
    let mut figs = Vec::new();

    // Pressure: p–φ, and p–V on log-log axes.
    if has_pressure {
        let bar: Vec<f64> = a.pressure.iter().map(|p| p / 1e5).collect();
        let litre: Vec<f64> = a.volume.iter().map(|v| v * 1e3).collect();
        let mut pv = Chart {
            title: "p–V (log-log)".into(),
            x_label: "cylinder volume (l)".into(),
            y_label: "pressure (bar, absolute)".into(),
            series: vec![Series::from_points(
                "cylinder 1",
                litre
                    .iter()
                    .copied()
                    .zip(bar.iter().copied())
                    .collect::<Vec<_>>()
                    .into_iter(),
            )],
            log: true,
            equal: false,
            angle_ticks: None,
        };
        let first = pv.series[0].points[0];
        pv.series[0].points.push(first); // close the loop
        figs.push(Figure {
            file: "pressure.svg".into(),
            panels: vec![
                Chart::angle(
                    format!("{name} — cylinder pressure, {rpm:.0} rpm"),
                    "pressure (bar, absolute)",
                    vec![Series::new("p(φ)", deg(), &bar)],
                ),
                pv,
            ],
        });
    }

    // Kinematics over the cycle of cylinder 1.
    let r = engine.mechanism().r();
    figs.push(Figure::single(
        "kinematics.svg",
        kinematics_chart(
            format!("{name} — piston motion ({})", a.summary.kinematics),
            &a.kinematics,
            r,
            a.step.to_degrees(),
        ),
    ));

    // Forces on cylinder 1.
    let f = &a.forces;
    if has_pressure {
        figs.push(Figure::single(
            "forces.svg",
            Chart::angle(
                format!(
                    "{name} — forces on cylinder 1 ({} rod), {rpm:.0} rpm",
                    a.summary.rod_model
                ),
                "force (kN), positive toward the crank / driving",
                vec![
                    Series::new("gas P_g", deg(), &kn(&f.gas)),
                    Series::new("inertia P_j", deg(), &kn(&f.inertia)),
                    Series::new("total P", deg(), &kn(&f.total)),
                    Series::new("side thrust N", deg(), &kn(&f.side)),
                    Series::new("radial K", deg(), &kn(&f.radial)),
                    Series::new("tangential T", deg(), &kn(&f.tangential)),
                ],
            ),
        ));
    }

    // Torque.
    let mean = a.uniformity.mean;
    figs.push(Figure::single(
        "torque.svg",
        Chart::angle(
            format!("{name} — torque, {rpm:.0} rpm"),
            "torque (N m)",
            vec![
                Series::new("cylinder 1", deg(), &f.torque),
                Series::new(
                    format!("engine ({} cylinders)", engine.cylinders()),
                    deg(),
                    &a.torque.total,
                ),
                Series::hline(format!("mean (indicated) {mean:.1} N m"), mean, 0.0, cycle),
            ],
        ),
    ));

    // Journal torques, counted from the free end.
    let journals = a
        .torque
        .journals
        .iter()
        .enumerate()
        .map(|(k, j)| Series::new(format!("journal after throw {}", k + 1), deg(), j))
        .collect();
    figs.push(Figure::single(
        "journal_torques.svg",
        Chart::angle(
            format!("{name} — main-journal torques (from the free end)"),
            "torque (N m)",
            journals,
        ),
    ));

    // Crank-pin load, crank-fixed axes.
    if has_pressure {
        let pin: Vec<(f64, f64)> = (0..n)
            .map(|k| (f.tangential[k] / 1e3, f.pin_radial[k] / 1e3))
            .collect();
        let mut polar_pts = pin.clone();
        polar_pts.push(pin[0]);
        figs.push(Figure::single(
            "crankpin_polar.svg",
            Chart {
                title: format!(
                    "{name} — crank-pin load in crank axes, max {:.1} kN",
                    a.summary.crankpin_load_max_n.unwrap_or(0.0) / 1e3
                ),
                x_label: "tangential T (kN), + direction of rotation".into(),
                y_label: "radial K − K_rB (kN), + toward the axis".into(),
                series: vec![Series::from_points("pin load", polar_pts.into_iter())],
                log: false,
                equal: true,
                angle_ticks: None,
            },
        ));
    }

    // Flywheel: excess energy and the speed trace with I_0.
    let mut panels = vec![Chart::angle(
        format!(
            "{name} — excess energy E(φ), ΔE = {:.1} J",
            a.uniformity.excess_work
        ),
        "E (J)",
        vec![Series::new("E(φ)", deg(), &a.uniformity.excess_energy)],
    )];
    if let Some(fw) = &a.flywheel {
        let rpm_trace: Vec<f64> = fw
            .speed
            .iter()
            .map(|w| w * 30.0 / std::f64::consts::PI)
            .collect();
        let (lo, hi) = rpm_trace
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        panels.push(Chart::angle(
            format!(
                "speed with I₀ = {:.4} kg m², δ = {:.4}",
                fw.required_inertia, fw.speed_fluctuation_achieved
            ),
            "speed (rpm)",
            vec![
                Series::new("n(φ)", deg(), &rpm_trace),
                Series::hline(format!("max {hi:.1}"), hi, 0.0, cycle),
                Series::hline(format!("min {lo:.1}"), lo, 0.0, cycle),
            ],
        ));
    }
    figs.push(Figure {
        file: "flywheel.svg".into(),
        panels,
    });

    // Harmonics as stems by engine order.
    let stems = |h: &[enginedyn_torque::Harmonic], offset: f64| -> Vec<(f64, f64)> {
        h.iter()
            .filter(|x| x.order > 0.0)
            .flat_map(|x| {
                [
                    (x.order + offset, 0.0),
                    (x.order + offset, x.amplitude),
                    (x.order + offset, 0.0),
                ]
            })
            .collect()
    };
    let cyl = stems(&a.cylinder_harmonics, -0.08);
    let eng = stems(&a.engine_harmonics, 0.08);
    figs.push(Figure::single(
        "harmonics.svg",
        Chart {
            title: format!("{name} — torque harmonics by engine order, {rpm:.0} rpm"),
            x_label: "engine order (per revolution)".into(),
            y_label: "amplitude (N m)".into(),
            series: vec![
                Series {
                    name: "cylinder 1".into(),
                    points: cyl,
                    dashed: false,
                },
                Series {
                    name: "engine".into(),
                    points: eng,
                    dashed: false,
                },
            ],
            log: false,
            equal: false,
            angle_ticks: None,
        },
    ));
    figs
}
