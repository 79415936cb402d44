//! Tornado charts: per result, one horizontal bar per parameter from the
//! result's change at `-t` to its change at `+t`, the largest on top, in the
//! look of the other charts (palette, fonts, grid), several panels on a grid.

use crate::ReportError;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::chart::{AxisRange, GREY, PALETTE, Ticks, text_width};

/// The palette of `chart.rs`: blue for `+t`, red for `-t`, green for marks.
const PLUS: RGBColor = PALETTE[0];
const MINUS: RGBColor = PALETTE[1];
const MARK: RGBColor = PALETTE[2];
/// Width of one panel (px): two fit the page of report.html (1280 px)
/// unscaled, so the text is read at the size it is written.
const PANEL_W: u32 = 630;
/// Panels to a row at most: more would be scaled down on the page.
const MAX_COLUMNS: usize = 2;
/// Height of the figure's title band (px).
const TITLE: u32 = 70;
/// Font sizes as given to plotters (its SVG writes them 1/1.24 smaller).
const CAPTION_FONT: u32 = 18;
const LABEL_FONT: u32 = 15;

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

/// Renders tornado panels, `columns` to a row (two at most, so that
/// report.html shows them unscaled), under `title`, to an SVG document.
/// Panels grow with their number of bars. `file` names the chart in errors.
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
    let columns = columns.clamp(1, panels.len().clamp(1, MAX_COLUMNS));
    let rows = panels.len().div_ceil(columns).max(1);
    let most = panels.iter().map(|p| p.bars.len()).max().unwrap_or(1);
    let panel_h = (110 + 36 * most.min(40) as u32).max(280);
    let size = (PANEL_W * columns as u32, panel_h * rows as u32 + TITLE);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        root.draw(&Text::new(
            title.to_string(),
            (14, 12),
            ("sans-serif", 21).into_font().color(&BLACK),
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
    let font = ("sans-serif", LABEL_FONT).into_font().color(&BLACK);
    let mut x = 14;
    let y = 50;
    for (name, color, dashed) in items {
        if dashed {
            // The marks' own dash: 5 on, 4 off, width 2.
            for k in 0..3 {
                let a = x + k * 9;
                root.draw(&PathElement::new(
                    vec![(a, y), (a + 5, y)],
                    color.stroke_width(2),
                ))?;
            }
        } else {
            root.draw(&Rectangle::new(
                [(x, y - 6), (x + 18, y + 6)],
                color.mix(0.85).filled(),
            ))?;
        }
        let w = text_width(&name, LABEL_FONT);
        root.draw(&Text::new(
            name,
            (x + 24, y),
            font.clone().pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        x += 24 + w + 30;
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
    let xt = Ticks::linear(-half, half, 6.0, None);
    // Room for the longest bar label, up to 45 % of the panel.
    let (w, _) = area.dim_in_pixel();
    let label_w = p
        .bars
        .iter()
        .map(|b| text_width(&b.label, LABEL_FONT))
        .max()
        .unwrap_or(0)
        .clamp(60, (w as i32) * 45 / 100);
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", CAPTION_FONT))
        .margin(10)
        .margin_right(18)
        .x_label_area_size(46)
        .y_label_area_size(label_w as u32 + 14)
        .build_cartesian_2d(AxisRange::new((-half, half), &xt), 0.0..n as f64)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_labels(0)
        .x_desc(p.x_label.as_str())
        .x_label_formatter(&|v| xt.label(*v))
        .label_style(("sans-serif", LABEL_FONT))
        .axis_desc_style(("sans-serif", LABEL_FONT))
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
            ("sans-serif", LABEL_FONT)
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
