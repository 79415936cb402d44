//! Tornado charts: per result, one horizontal bar per parameter from the
//! result's change at `-t` to its change at `+t`, the largest on top, in the
//! look of the other charts (palette, fonts, grid), several panels on a grid.

use crate::ReportError;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::chart::{GREY, PALETTE, tick as chart_tick};

/// The palette of `chart.rs`: blue for `+t`, red for `-t`, green for marks.
const PLUS: RGBColor = PALETTE[0];
const MINUS: RGBColor = PALETTE[1];
const MARK: RGBColor = PALETTE[2];
/// One panel (px).
const PANEL: (u32, u32) = (520, 330);
/// Height of the figure's title band (px).
const TITLE: u32 = 64;

/// One parameter's bar: the result's change (in the panel's unit) with the
/// parameter at `-t` and at `+t`.
#[derive(Debug, Clone, PartialEq)]
pub struct TornadoBar {
    /// Parameter name, drawn left of the bar.
    pub label: String,
    /// Change at `-t`.
    pub minus: f64,
    /// Change at `+t`.
    pub plus: f64,
}

/// One result's tornado.
#[derive(Debug, Clone, PartialEq)]
pub struct TornadoPanel {
    /// Caption (the result and its nominal).
    pub title: String,
    /// X axis: the change and its unit.
    pub x_label: String,
    /// Bars, largest first (drawn top down).
    pub bars: Vec<TornadoBar>,
    /// Symmetric marks `±value` drawn as dashed vertical lines, with their
    /// legend text (e.g. the RSS and Monte Carlo standard deviations); the
    /// first is grey, the second green.
    pub marks: Vec<(String, f64)>,
}

/// Renders tornado panels, `columns` to a row, under `title`, to an SVG
/// document. `file` names the chart in errors.
pub fn tornado_svg(
    file: &str,
    title: &str,
    panels: &[TornadoPanel],
    columns: usize,
) -> Result<String, ReportError> {
    let err = |e: &dyn std::fmt::Display| ReportError::Chart {
        name: file.to_string(),
        message: e.to_string(),
    };
    let columns = columns.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(columns).max(1);
    let size = (PANEL.0 * columns as u32, PANEL.1 * rows as u32 + TITLE);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        root.draw(&Text::new(
            title.to_string(),
            (14, 12),
            ("sans-serif", 18).into_font().color(&BLACK),
        ))
        .map_err(|e| err(&e))?;
        legend(&root, panels.first().map(|p| p.marks.as_slice())).map_err(|e| err(&e))?;
        let body = root.margin(TITLE, 0, 0, 0);
        let areas = body.split_evenly((rows, columns));
        for (panel, area) in panels.iter().zip(&areas) {
            draw_panel(&root, area, panel).map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

/// Tick labels as `chart.rs` writes them: no trailing zeros, exponents
/// only for very small or large values.
fn tick(v: f64) -> String {
    chart_tick(&v)
}

/// One legend for the figure, on the title band's second line: the two
/// sides of a bar and the marks (dashed lines) the panels share.
fn legend(root: &Area, marks: Option<&[(String, f64)]>) -> Result<(), Box<dyn std::error::Error>> {
    let mut items: Vec<(String, RGBColor, bool)> = vec![
        ("parameter at +t".into(), PLUS, false),
        ("parameter at −t".into(), MINUS, false),
    ];
    for (k, (name, _)) in marks.unwrap_or_default().iter().enumerate() {
        items.push((format!("± {name}"), if k == 0 { GREY } else { MARK }, true));
    }
    let font = ("sans-serif", 13).into_font().color(&BLACK);
    let step = 190;
    let mut x = 14;
    let y = 46;
    for (name, color, dashed) in items {
        if dashed {
            root.draw(&PathElement::new(
                vec![(x, y), (x + 7, y)],
                color.stroke_width(2),
            ))?;
            root.draw(&PathElement::new(
                vec![(x + 11, y), (x + 18, y)],
                color.stroke_width(2),
            ))?;
        } else {
            root.draw(&Rectangle::new(
                [(x, y - 6), (x + 18, y + 6)],
                color.mix(0.85).filled(),
            ))?;
        }
        root.draw(&Text::new(
            name,
            (x + 24, y),
            font.clone().pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        x += step;
    }
    Ok(())
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

fn draw_panel(
    root: &Area,
    area: &Area,
    p: &TornadoPanel,
) -> Result<(), Box<dyn std::error::Error>> {
    let n = p.bars.len().max(1);
    let reach = p
        .bars
        .iter()
        .flat_map(|b| [b.minus.abs(), b.plus.abs()])
        .chain(p.marks.iter().map(|m| m.1.abs()))
        .filter(|v| v.is_finite())
        .fold(0.0_f64, f64::max);
    let half = if reach > 0.0 { reach * 1.12 } else { 1.0 };
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", 15))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(150)
        .build_cartesian_2d(-half..half, 0.0..n as f64)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_labels(0)
        .x_desc(p.x_label.as_str())
        .x_labels(7)
        .x_label_formatter(&|v| tick(if v.abs() < 1e-9 * half { 0.0 } else { *v }))
        .label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 13))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    // Largest on top: bar i occupies [n - i - 1, n - i] with a margin. When
    // both sides move the result the same way (a kink), `+t` takes the upper
    // half of the slot and `-t` the lower, so neither hides the other.
    for (i, b) in p.bars.iter().enumerate() {
        let y0 = (n - i - 1) as f64 + 0.18;
        let y1 = (n - i) as f64 - 0.18;
        let mid = 0.5 * (y0 + y1);
        let same_side = b.plus * b.minus > 0.0;
        for (v, color, lo, hi) in [(b.plus, PLUS, mid, y1), (b.minus, MINUS, y0, mid)] {
            let (lo, hi) = if same_side { (lo, hi) } else { (y0, y1) };
            if v.is_finite() && v != 0.0 {
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(0.0, lo), (v, hi)],
                    color.mix(0.85).filled(),
                )))?;
            }
        }
        let (x, y) = chart.backend_coord(&(-half, 0.5 * (y0 + y1)));
        root.draw(&Text::new(
            b.label.clone(),
            (x - 6, y),
            ("sans-serif", 12)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Right, VPos::Center)),
        ))?;
    }
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(0.0, 0.0), (0.0, n as f64)],
        BLACK.stroke_width(1),
    )))?;
    for (k, (_, v)) in p.marks.iter().enumerate() {
        if !(v.is_finite() && *v > 0.0) {
            continue;
        }
        let color = if k == 0 { GREY } else { MARK };
        let style = color.stroke_width(2);
        for side in [-1.0, 1.0] {
            let x = side * v;
            chart.draw_series(DashedLineSeries::new(
                [(x, 0.0), (x, n as f64)],
                5,
                4,
                style,
            ))?;
        }
    }
    Ok(())
}
