//! SVG charts with one look: the same size, fonts, palette and axes style.
//! A [`Figure`] holds one or more [`Chart`] panels side by side.

use crate::ReportError;
use enginedyn_engine::Engine;
use enginedyn_kinematics::Table;
use enginedyn_numerics::format::{trim_zeros, trimmed};
use enginedyn_pipeline::Analysis;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
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
pub(crate) const PANEL: (u32, u32) = (900, 520);
/// Most points drawn per series; finer curves are thinned (display only).
const MAX_POINTS: usize = 1500;

/// One named curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// (x, y) points; a point that is not finite lifts the pen (on log
    /// axes, so does one at or below 0).
    pub points: Vec<(f64, f64)>,
    /// Drawn dashed and grey (reference lines such as a mean or a target).
    pub dashed: bool,
    /// Drawn as a marker at each point, no line (a scatter's points).
    pub marker: bool,
    /// Its own colour (a sequence of many lines, as a map's loads), in
    /// place of the palette's next.
    pub color: Option<RGBColor>,
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
        let n = pts.len();
        let stride = n.div_ceil(MAX_POINTS).max(1);
        // Every `stride`-th point, and the last (the curve's end stays put).
        let points = pts
            .enumerate()
            .filter(|(k, _)| k % stride == 0 || *k + 1 == n)
            .map(|(_, p)| p)
            .collect();
        Self {
            name: name.into(),
            points,
            dashed: false,
            marker: false,
            color: None,
        }
    }
    /// A dashed horizontal line at `y` over `[x0, x1]`.
    pub fn hline(name: impl Into<String>, y: f64, x0: f64, x1: f64) -> Self {
        Self {
            name: name.into(),
            points: vec![(x0, y), (x1, y)],
            dashed: true,
            marker: false,
            color: None,
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
        return if log {
            ((0.1, 10.0), (0.1, 10.0))
        } else {
            ((0.0, 1.0), (0.0, 1.0))
        };
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
    // A scatter's points never sit on the frame: both axes padded.
    if series.iter().any(|s| s.marker) {
        return (widen(xr, 0.06), widen(yr, 0.08));
    }
    let x = if xr.1 > xr.0 { xr } else { widen(xr, 0.0) };
    (x, widen(yr, 0.06))
}

/// Decimals that write `step` exactly (0.25 → 2, 5 → 0), at most 12.
fn decimals(step: f64) -> usize {
    let mut d = 0;
    while d < 12 {
        let s = step * 10f64.powi(d as i32);
        if (s - s.round()).abs() <= 1e-6 * s.abs().max(1e-300) {
            break;
        }
        d += 1;
    }
    d
}

/// A tick label for `v` on an axis whose ticks are `step` apart: a value
/// within a millionth of the step of zero is written `0` (no `-2e-16`),
/// others with as many decimals as the step needs and no trailing zeros
/// (`0.3`, not `0.30000000000000004`); magnitudes of a million and more,
/// or under 1e-4, in exponent form (`2.5e6`, `-3e-5`). A `step` of 0 (or
/// not finite) means unknown: three decimals at most.
///
/// ```
/// use enginedyn_report::tick_label;
/// assert_eq!(tick_label(-2e-16, 0.5), "0");
/// assert_eq!(tick_label(0.1 + 0.2, 0.1), "0.3");
/// assert_eq!(tick_label(250.0, 50.0), "250");
/// assert_eq!(tick_label(2.5e6, 5e5), "2.5e6");
/// ```
pub fn tick_label(v: f64, step: f64) -> String {
    if !v.is_finite() {
        return v.to_string();
    }
    let step = step.abs();
    let known = step.is_finite() && step > 0.0;
    if v == 0.0 || (known && v.abs() < step * 1e-6) {
        return "0".into();
    }
    let a = v.abs();
    let s = if !(1e-4..1e6).contains(&a) {
        // Significant digits enough to tell neighbouring ticks apart.
        let digits = if known {
            ((a.log10().floor() - step.log10().floor()).max(0.0) as usize).min(6)
        } else {
            2
        };
        trim_zeros(&format!("{v:.digits$e}"))
    } else {
        trimmed(v, if known { decimals(step) } else { 3 })
    };
    if s.chars().all(|c| matches!(c, '-' | '0' | '.')) {
        "0".into()
    } else {
        s
    }
}

/// A step of 1, 2 or 5 times a power of ten giving about `n` intervals
/// over `span`.
fn nice_step(span: f64, n: f64) -> f64 {
    let raw = span / n;
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    let k = if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    };
    k * p
}

/// An axis's ticks, in the coordinates the chart is built on (log10 of the
/// value on a log axis): labelled (bold) positions with their labels, and
/// the light grid between them.
#[derive(Debug, Clone, Default)]
pub(crate) struct Ticks {
    bold: Vec<f64>,
    labels: Vec<String>,
    light: Vec<f64>,
}

impl Ticks {
    /// The labelled positions.
    pub(crate) fn bold(&self) -> &[f64] {
        &self.bold
    }

    /// The label of the bold tick at `v` (the nearest one).
    pub(crate) fn label(&self, v: f64) -> String {
        self.bold
            .iter()
            .zip(&self.labels)
            .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
            .map(|(_, l)| l.clone())
            .unwrap_or_default()
    }

    /// Linear ticks over `[lo, hi]`, about `n` intervals, multiples of
    /// the step (at most a few dozen whatever the range).
    pub(crate) fn linear(lo: f64, hi: f64, n: f64, step: Option<f64>) -> Self {
        let span = hi - lo;
        if !(span.is_finite() && span > 0.0) {
            return Self {
                bold: vec![lo],
                labels: vec![tick_label(lo, 0.0)],
                light: Vec::new(),
            };
        }
        let step = step
            .filter(|s| s.is_finite() && *s > 0.0 && span / s <= 24.0)
            .unwrap_or_else(|| nice_step(span, n));
        let k0 = (lo / step).ceil();
        let k1 = (hi / step).floor();
        if !(k0.is_finite() && k1.is_finite()) || k1 - k0 > 60.0 {
            return Self {
                bold: vec![lo, hi],
                labels: vec![tick_label(lo, span), tick_label(hi, span)],
                light: Vec::new(),
            };
        }
        let bold: Vec<f64> = (0..=(k1 - k0).max(0.0) as usize)
            .map(|k| (k0 + k as f64) * step)
            .filter(|v| (lo..=hi).contains(v))
            .collect();
        let labels = bold.iter().map(|&v| tick_label(v, step)).collect();
        let sub = step / 5.0;
        let j0 = (lo / sub).ceil();
        let j1 = (hi / sub).floor();
        let light = (0..=(j1 - j0).clamp(0.0, 400.0) as usize)
            .map(|j| (j0 + j as f64) * sub)
            .collect();
        Self {
            bold,
            labels,
            light,
        }
    }

    /// Log ticks over `[lo, hi]` (values, both positive), positions in
    /// log10: decades, and 2 and 5 times a decade on short ranges; a light
    /// line at each integer multiple of a decade when the range spans few
    /// decades. Labels are distinct: each position is labelled once.
    fn log(lo: f64, hi: f64) -> Self {
        let (l0, l1) = (lo.log10(), hi.log10());
        if !(l0.is_finite() && l1.is_finite() && l1 > l0) {
            return Self::linear(l0, l0 + 1.0, 1.0, None);
        }
        let d0 = l0.floor() as i64;
        let d1 = l1.ceil() as i64;
        let decades = (d1 - d0).max(1);
        // Every `stride`-th decade labelled on very long ranges.
        let stride = (decades as f64 / 10.0).ceil().max(1.0) as i64;
        let mantissas: &[f64] = if l1 - l0 < 0.7 {
            &[1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
        } else if l1 - l0 < 2.2 {
            &[1.0, 2.0, 5.0]
        } else {
            &[1.0]
        };
        let mut t = Self::default();
        for d in d0..=d1 {
            let base = 10f64.powi(d as i32);
            if decades <= 8 {
                for m in 2..=9 {
                    let v = (m as f64 * base).log10();
                    if (l0..=l1).contains(&v) {
                        t.light.push(v);
                    }
                }
            }
            if d.rem_euclid(stride) != 0 {
                continue;
            }
            for &m in mantissas {
                let value = m * base;
                let v = value.log10();
                if (l0..=l1).contains(&v) {
                    t.bold.push(v);
                    t.labels.push(log_label(value));
                }
            }
        }
        if t.bold.len() < 3 {
            // A range within one decade: plain linear ticks, placed in log10.
            let lin = Self::linear(lo, hi, 5.0, None);
            let keep: Vec<usize> = (0..lin.bold.len()).filter(|&k| lin.bold[k] > 0.0).collect();
            t.bold = keep.iter().map(|&k| lin.bold[k].log10()).collect();
            t.labels = keep.iter().map(|&k| lin.labels[k].clone()).collect();
            t.light.clear();
        }
        t
    }
}

/// A label for a round value on a log axis: `0.01`, `0.5`, `20`, `1e-3`,
/// `2e5`.
fn log_label(v: f64) -> String {
    let v: f64 = format!("{v:.2e}").parse().unwrap_or(v);
    if (0.01..1e4).contains(&v) {
        tick_label(v, v / 100.0)
    } else {
        trim_zeros(&format!("{v:.1e}"))
    }
}

pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Font sizes as given to plotters (its SVG writes them 1/1.24 smaller).
const TITLE_FONT: u32 = 20;
const LABEL_FONT: u32 = 16;
const DESC_FONT: u32 = 17;
const LEGEND_FONT: u32 = 16;
/// The colour of the legend's frame (tests find the legend by it).
pub(crate) const LEGEND_FRAME: RGBColor = RGBColor(200, 200, 200);

/// Width of `text` in pixels at plotters font size `size` (an estimate for
/// a sans-serif face; SVG cannot measure).
pub(crate) fn text_width(text: &str, size: u32) -> i32 {
    (text.chars().count() as f64 * size as f64 / 1.24 * 0.58).ceil() as i32
}

/// How a legend key is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Key {
    /// A line in the series' colour, width and dash.
    Line {
        color: RGBColor,
        width: u32,
        dashed: bool,
    },
    /// A dashed line of its own pattern (on, off, on, off; px): the second
    /// and later reference lines of a chart, told apart from the first.
    Dash {
        color: RGBColor,
        width: u32,
        pattern: [i32; 4],
    },
    /// A marker of a [`ScatterChart`] group.
    Marker {
        shape: usize,
        color: RGBColor,
        filled: bool,
    },
}

const KEY_W: i32 = 28;
const ITEM_GAP: i32 = 22;
const ROW_H: i32 = 22;

/// Lays legend items out in rows of at most `width` pixels: each item's
/// row and x offset, and the number of rows.
fn legend_layout(items: &[(String, Key)], width: i32) -> (Vec<(usize, i32)>, usize) {
    let mut out = Vec::with_capacity(items.len());
    let (mut row, mut x) = (0usize, 0i32);
    for (name, _) in items {
        let w = KEY_W + 6 + text_width(name, LEGEND_FONT);
        if x > 0 && x + w > width {
            row += 1;
            x = 0;
        }
        out.push((row, x));
        x += w + ITEM_GAP;
    }
    (out, if items.is_empty() { 0 } else { row + 1 })
}

/// Draws a marker of shape `shape` (circle, square, triangle, diamond,
/// inverted triangle, cross, repeating) centred at pixel `(x, y)`.
pub(crate) fn draw_marker(
    area: &Area,
    (x, y): (i32, i32),
    shape: usize,
    color: RGBColor,
    filled: bool,
    r: i32,
) -> Result<(), Box<dyn std::error::Error>> {
    let style = if filled {
        color.filled()
    } else {
        color.stroke_width(2)
    };
    let poly = |pts: Vec<(i32, i32)>| -> Result<(), Box<dyn std::error::Error>> {
        if filled {
            area.draw(&Polygon::new(pts, style))?;
        } else {
            let mut closed = pts.clone();
            closed.push(pts[0]);
            area.draw(&PathElement::new(closed, style))?;
        }
        Ok(())
    };
    match shape % 6 {
        0 => area.draw(&Circle::new((x, y), r, style))?,
        1 => {
            let s = r * 9 / 10;
            area.draw(&Rectangle::new([(x - s, y - s), (x + s, y + s)], style))?
        }
        2 => poly(vec![(x, y - r - 1), (x + r + 1, y + r), (x - r - 1, y + r)])?,
        3 => poly(vec![
            (x, y - r - 2),
            (x + r + 1, y),
            (x, y + r + 2),
            (x - r - 1, y),
        ])?,
        4 => poly(vec![(x, y + r + 1), (x + r + 1, y - r), (x - r - 1, y - r)])?,
        _ => {
            let s = color.stroke_width(2);
            area.draw(&PathElement::new(vec![(x - r, y - r), (x + r, y + r)], s))?;
            area.draw(&PathElement::new(vec![(x - r, y + r), (x + r, y - r)], s))?;
        }
    }
    Ok(())
}

/// The band above a plot: the title, centred, and under it the legend in
/// rows, framed, outside the plot area so that it never covers data.
/// Returns the band's height for `items` at `width`.
pub(crate) fn head_height(items: &[(String, Key)], width: i32) -> u32 {
    let (_, rows) = legend_layout(items, width - 40);
    (34 + if rows > 0 {
        rows as i32 * ROW_H + 10
    } else {
        0
    }) as u32
}

pub(crate) fn draw_head(
    head: &Area,
    title: &str,
    items: &[(String, Key)],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let (w, _) = head.dim_in_pixel();
    let w = w as i32;
    head.draw(&Text::new(
        title.to_string(),
        (w / 2, 10),
        ("sans-serif", TITLE_FONT)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Top)),
    ))?;
    if items.is_empty() {
        return Ok(());
    }
    let (place, rows) = legend_layout(items, w - 40);
    // Each row centred.
    let mut row_w = vec![0i32; rows];
    for ((name, _), &(row, x)) in items.iter().zip(&place) {
        row_w[row] = row_w[row].max(x + KEY_W + 6 + text_width(name, LEGEND_FONT));
    }
    let widest = row_w.iter().copied().max().unwrap_or(0);
    let top = 36;
    let left = (w - widest) / 2;
    head.draw(&Rectangle::new(
        [
            (left - 8, top - 3),
            (left + widest + 8, top + rows as i32 * ROW_H + 3),
        ],
        LEGEND_FRAME.stroke_width(1),
    ))?;
    let font = ("sans-serif", LEGEND_FONT)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    for ((name, key), &(row, x)) in items.iter().zip(&place) {
        let x = (w - row_w[row]) / 2 + x;
        let y = top + row as i32 * ROW_H + ROW_H / 2;
        match *key {
            Key::Line {
                color,
                width,
                dashed,
            } => {
                let style = color.stroke_width(width);
                if dashed {
                    // The series' own dash: 6 on, 4 off.
                    for k in 0..3 {
                        let a = x + k * 10;
                        head.draw(&PathElement::new(vec![(a, y), (a + 6, y)], style))?;
                    }
                } else {
                    head.draw(&PathElement::new(vec![(x, y), (x + KEY_W - 2, y)], style))?;
                }
            }
            Key::Dash {
                color,
                width,
                pattern,
            } => {
                let style = color.stroke_width(width);
                let (mut a, mut k) = (x, 0);
                while a < x + KEY_W - 2 {
                    let b = (a + pattern[k % 4]).min(x + KEY_W - 2);
                    if k % 2 == 0 {
                        head.draw(&PathElement::new(vec![(a, y), (b, y)], style))?;
                    }
                    a = b;
                    k += 1;
                }
            }
            Key::Marker {
                shape,
                color,
                filled,
            } => draw_marker(head, (x + KEY_W / 2 - 1, y), shape, color, filled, 5)?,
        }
        head.draw(&Text::new(name.clone(), (x + KEY_W + 6, y), font.clone()))?;
    }
    Ok(())
}

/// The dashed series' styles after the first (grey, width 1, 6 on 4 off),
/// in turn: colour, width and pattern (on, off, on, off; px). Two
/// reference lines of one chart (an indicated and an effective mean) are
/// told apart by colour and dash.
const DASHES: [(RGBColor, u32, [i32; 4]); 2] = [
    (RGBColor(0, 0, 0), 2, [12, 4, 3, 4]),
    (RGBColor(150, 150, 150), 2, [2, 3, 2, 3]),
];

/// How a series is drawn: colour, width, dash (the legend key repeats it).
fn series_keys(series: &[Series]) -> Vec<(String, Key)> {
    let mut solid = 0;
    let mut dashed = 0;
    series
        .iter()
        .map(|s| {
            let key = if s.marker {
                solid += 1;
                Key::Marker {
                    shape: 0,
                    color: s.color.unwrap_or(PALETTE[(solid - 1) % PALETTE.len()]),
                    filled: true,
                }
            } else if s.dashed {
                dashed += 1;
                if dashed == 1 {
                    Key::Line {
                        color: GREY,
                        width: 1,
                        dashed: true,
                    }
                } else {
                    let (color, width, pattern) = DASHES[(dashed - 2) % DASHES.len()];
                    Key::Dash {
                        color,
                        width,
                        pattern,
                    }
                }
            } else {
                solid += 1;
                Key::Line {
                    color: s.color.unwrap_or(PALETTE[(solid - 1) % PALETTE.len()]),
                    width: 2,
                    dashed: false,
                }
            };
            (s.name.clone(), key)
        })
        .collect()
}

/// A linear coordinate over `[lo, hi]` whose grid is the given ticks
/// (plotters' own key points round badly and crowd on log ranges).
pub(crate) struct AxisRange {
    lo: f64,
    hi: f64,
    bold: Vec<f64>,
    light: Vec<f64>,
}

impl AxisRange {
    pub(crate) fn new((lo, hi): (f64, f64), t: &Ticks) -> Self {
        Self {
            lo,
            hi,
            bold: t.bold.clone(),
            light: t.light.clone(),
        }
    }
}

impl AxisRange {
    /// The pixel of `v` between the pixel limits, unrounded: what
    /// plotters' whole-pixel `map` rounds down.
    fn map_fine(&self, v: f64, limit: (i32, i32)) -> f64 {
        let span = self.hi - self.lo;
        if span == 0.0 || !span.is_finite() {
            return ((limit.0 + limit.1) / 2) as f64;
        }
        let u = ((v - self.lo) / span).clamp(-10.0, 10.0);
        if !u.is_finite() {
            return limit.0 as f64;
        }
        limit.0 as f64 + (limit.1 - limit.0) as f64 * u
    }
}

/// The pixel of a data point on `chart`, unrounded (in the whole SVG's
/// coordinates): plotters maps to whole pixels, which shows as stair-steps
/// on a smooth curve, so curves are written by [`svg_polyline`] from these.
pub(crate) fn fine_pixel(chart: &Plot, (x, y): (f64, f64)) -> (f64, f64) {
    let (px, py) = chart.plotting_area().get_pixel_range();
    let spec = chart.as_coord_spec();
    // ChartBuilder's limits: the last pixel inside, y from the bottom up.
    (
        spec.x_spec().map_fine(x, (px.start, px.end - 1)),
        spec.y_spec().map_fine(y, (py.end - 1, py.start)),
    )
}

/// An SVG polyline through pixel points at a hundredth of a pixel, in the
/// attribute order plotters writes (`fill`, `opacity`, `stroke`,
/// `stroke-width`, `points`), with round joins and an optional dash
/// pattern (on, off, …; px).
/// A filled circle of radius `r` (px) at pixel `c`, with a white rim so
/// that points on one another stay apart.
pub(crate) fn svg_circle(c: (f64, f64), r: f64, color: RGBColor) -> String {
    format!(
        "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"#{:02X}{:02X}{:02X}\" stroke=\"#FFFFFF\" stroke-width=\"0.8\"/>\n",
        trimmed(c.0, 2),
        trimmed(c.1, 2),
        trimmed(r, 2),
        color.0,
        color.1,
        color.2
    )
}

pub(crate) fn svg_polyline(
    pts: &[(f64, f64)],
    color: RGBColor,
    width: f64,
    dash: Option<&[i32]>,
) -> String {
    let mut o = format!(
        "<polyline fill=\"none\" opacity=\"1\" stroke=\"#{:02X}{:02X}{:02X}\" stroke-width=\"{}\"",
        color.0,
        color.1,
        color.2,
        trimmed(width, 2)
    );
    if let Some(d) = dash {
        let d: Vec<String> = d.iter().map(i32::to_string).collect();
        o.push_str(&format!(" stroke-dasharray=\"{}\"", d.join(" ")));
    }
    o.push_str(" stroke-linejoin=\"round\" points=\"");
    o.push_str(&svg_points(pts));
    o.push_str("\"/>\n");
    o
}

/// Pixel points as an SVG `points` attribute's value, at a hundredth of a
/// pixel.
pub(crate) fn svg_points(pts: &[(f64, f64)]) -> String {
    let mut o = String::with_capacity(pts.len() * 14);
    for &(x, y) in pts {
        o.push_str(&trimmed(x, 2));
        o.push(',');
        o.push_str(&trimmed(y, 2));
        o.push(' ');
    }
    o
}

/// Inserts SVG elements at the end of a document (drawn last, on top).
pub(crate) fn append_svg(svg: &mut String, elements: &[String]) {
    if let Some(i) = svg.rfind("</svg>") {
        svg.insert_str(i, &elements.concat());
    }
}

impl Ranged for AxisRange {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        (self.map_fine(*v, limit) + 1e-3).floor() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

pub(crate) type Plot<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<AxisRange, AxisRange>>;

/// Axes on `body`: ticks from [`Ticks`], the grid, axis labels.
fn axes<'a, 'b>(
    body: &'a Area<'b>,
    x: ((f64, f64), &Ticks),
    y: ((f64, f64), &Ticks),
    labels: (&str, &str),
) -> Result<Plot<'a, 'b>, Box<dyn std::error::Error>> {
    axes_with(body, x, y, labels, (6, 14))
}

/// [`axes`] with the plot's `(top, right)` margins in pixels (room for
/// labels outside the plot, such as an order line's number at its end).
pub(crate) fn axes_with<'a, 'b>(
    body: &'a Area<'b>,
    (x, xt): ((f64, f64), &Ticks),
    (y, yt): ((f64, f64), &Ticks),
    (x_label, y_label): (&str, &str),
    (top, right): (u32, u32),
) -> Result<Plot<'a, 'b>, Box<dyn std::error::Error>> {
    let y_width = yt
        .labels
        .iter()
        .map(|l| text_width(l, LABEL_FONT))
        .max()
        .unwrap_or(20);
    let mut chart = ChartBuilder::on(body)
        .margin(14)
        .margin_top(top)
        .margin_right(right)
        .x_label_area_size(48)
        .y_label_area_size(y_width as u32 + 44)
        .build_cartesian_2d(AxisRange::new(x, xt), AxisRange::new(y, yt))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&|v| xt.label(*v))
        .y_label_formatter(&|v| yt.label(*v))
        .label_style(("sans-serif", LABEL_FONT))
        .axis_desc_style(("sans-serif", DESC_FONT))
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    Ok(chart)
}

impl Chart {
    /// Draws the panel on `area`; returns its curves as SVG elements at
    /// sub-pixel precision ([`svg_polyline`]), for the caller to append.
    fn draw(&self, area: &Area) -> Result<Vec<String>, Box<dyn std::error::Error>> {
        let ((mut x0, mut x1), (mut y0, mut y1)) = bounds(&self.series, self.log);
        let keys = series_keys(&self.series);
        // A series without a name draws no legend entry (marks that a
        // named series already stands for).
        let legend: Vec<(String, Key)> = keys
            .iter()
            .filter(|(n, _)| !n.is_empty())
            .cloned()
            .collect();
        let (w, _) = area.dim_in_pixel();
        let (head, body) = area.split_vertically(head_height(&legend, w as i32));
        draw_head(&head, &self.title, &legend)?;
        if self.equal {
            let r = [x0.abs(), x1.abs(), y0.abs(), y1.abs()]
                .into_iter()
                .fold(0.0_f64, f64::max);
            let (w, h) = body.dim_in_pixel();
            let aspect = (w as f64 - 110.0) / (h as f64 - 70.0);
            (x0, x1, y0, y1) = (-r * aspect, r * aspect, -r, r);
        }
        if let (false, Some(step)) = (self.log, self.angle_ticks) {
            // An angle axis runs over whole dead-centre intervals, so that
            // it ends on a labelled 720 (360, or 360 centred).
            if step > 0.0 && x1 > x0 && (x1 - x0) / step < 100.0 {
                (x0, x1) = (
                    (x0 / step + 1e-9).floor() * step,
                    (x1 / step - 1e-9).ceil() * step,
                );
            }
        }
        let (xt, yt, xr, yr) = if self.log {
            (
                Ticks::log(x0, x1),
                Ticks::log(y0, y1),
                (x0.log10(), x1.log10()),
                (y0.log10(), y1.log10()),
            )
        } else {
            let angle_step = self
                .angle_ticks
                .map(|s| if x1 - x0 <= 1080.0 { s / 2.0 } else { s });
            let (_, h) = body.dim_in_pixel();
            (
                Ticks::linear(x0, x1, 9.0, angle_step),
                Ticks::linear(y0, y1, (h as f64 / 70.0).clamp(4.0, 8.0), None),
                (x0, x1),
                (y0, y1),
            )
        };
        let chart = axes(&body, (xr, &xt), (yr, &yt), (&self.x_label, &self.y_label))?;
        let mut out = Vec::new();
        if let (false, Some(step)) = (self.log, self.angle_ticks) {
            // Dead-centre markers every `step` degrees (no legend entry).
            let n = ((x1 - x0) / step + 1e-9).floor().clamp(0.0, 100.0) as usize;
            for k in 1..=n {
                let x = x0 + k as f64 * step;
                out.push(svg_polyline(
                    &[fine_pixel(&chart, (x, y0)), fine_pixel(&chart, (x, y1))],
                    RGBColor(170, 170, 170),
                    1.0,
                    Some(&[3, 5]),
                ));
            }
        }
        for (s, (_, key)) in self.series.iter().zip(&keys) {
            let (color, width, dash): (RGBColor, u32, Option<&[i32]>) = match key {
                Key::Line {
                    color,
                    width,
                    dashed,
                } => (*color, *width, dashed.then_some(&[6, 4][..])),
                Key::Dash {
                    color,
                    width,
                    pattern,
                } => (*color, *width, Some(&pattern[..])),
                Key::Marker { color, .. } => {
                    for &(x, y) in s
                        .points
                        .iter()
                        .filter(|(x, y)| x.is_finite() && y.is_finite())
                    {
                        let (px, py) = fine_pixel(&chart, (x, y));
                        out.push(svg_circle((px, py), 3.5, *color));
                    }
                    continue;
                }
            };
            // A point that is not finite lifts the pen: one polyline per run.
            let shown = |&(x, y): &(f64, f64)| {
                x.is_finite() && y.is_finite() && (!self.log || (x > 0.0 && y > 0.0))
            };
            for run in s.points.split(|p| !shown(p)) {
                let pts: Vec<(f64, f64)> = run
                    .iter()
                    .map(|&(x, y)| {
                        let p = if self.log {
                            (x.log10(), y.log10())
                        } else {
                            (x, y)
                        };
                        fine_pixel(&chart, p)
                    })
                    .collect();
                if !pts.is_empty() {
                    out.push(svg_polyline(&pts, color, width as f64, dash));
                }
            }
        }
        Ok(out)
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
        let err = |e: &dyn std::fmt::Display| ReportError::Chart {
            name: self.file.clone(),
            message: e.to_string(),
        };
        let n = self.panels.len().max(1) as u32;
        let size = if n == 1 {
            PANEL
        } else {
            (PANEL.0 * n * 7 / 10, PANEL.1)
        };
        let mut svg = String::new();
        let mut curves = Vec::new();
        {
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            root.fill(&WHITE).map_err(|e| err(&e))?;
            let areas = root.split_evenly((1, n as usize));
            for (chart, area) in self.panels.iter().zip(&areas) {
                curves.extend(chart.draw(area).map_err(|e| err(&e))?);
            }
            root.present().map_err(|e| err(&e))?;
        }
        append_svg(&mut svg, &curves);
        Ok(svg)
    }
}
/// A periodic curve sampled at `k * step_deg` (k = 0 … y.len() − 1) as a
/// series over one whole period, back to its start at the period's end:
/// from 0, or with `centered` from minus half the period (the samples
/// rotated by half, as `curves.csv` writes them with `--angles centered`).
pub fn periodic(name: impl Into<String>, y: &[f64], step_deg: f64, centered: bool) -> Series {
    let n = y.len();
    if n == 0 {
        return Series::from_points(name, std::iter::empty::<(f64, f64)>());
    }
    let shift = if centered { n / 2 } else { 0 };
    let x0 = -(shift as f64) * step_deg;
    Series::from_points(
        name,
        (0..n + 1).map(move |k| (x0 + k as f64 * step_deg, y[(k + shift) % n])),
    )
}

/// The kinematics chart (shared by `run` and `kinematics`): the seeds'
/// coefficients A = x/R, B = v/(R w), C = a/(R w^2) and the rod angle over
/// the table's period, from a table on the grid `k * step_deg`.
pub fn kinematics_chart(title: impl Into<String>, t: &Table, r: f64, step_deg: f64) -> Chart {
    kinematics_chart_with(title, t, r, step_deg, false)
}

/// [`kinematics_chart`], centred on TDC with `centered`.
fn kinematics_chart_with(
    title: impl Into<String>,
    t: &Table,
    r: f64,
    step_deg: f64,
    centered: bool,
) -> Chart {
    let scale = |v: &[f64], f: f64| v.iter().map(|x| x * f).collect::<Vec<_>>();
    let curve = |name: &str, v: &[f64], f: f64| periodic(name, &scale(v, f), step_deg, centered);
    let mut c = Chart::angle(
        title,
        "x/R, v/(Rω), a/(Rω²); β (deg/10)",
        vec![
            curve("A = x/R", &t.x, 1.0 / r),
            curve("B = v/(Rω)", &t.dx, 1.0 / r),
            curve("C = a/(Rω²)", &t.d2x, 1.0 / r),
            curve("rod angle β (deg/10)", &t.beta, 18.0 / std::f64::consts::PI),
        ],
    );
    c.x_label = "crank angle from TDC (deg)".into();
    c
}

/// The file names of [`run_figures`] for a pressure diagram, in report
/// order (a turning-moment run has no pressure, forces or crank-pin chart).
pub const RUN_CHARTS: [&str; 8] = [
    "pressure.svg",
    "kinematics.svg",
    "forces.svg",
    "torque.svg",
    "journal_torques.svg",
    "crankpin_polar.svg",
    "flywheel.svg",
    "harmonics.svg",
];

/// The charts of `run --out DIR`, in report order (angles from 0).
pub fn run_figures(engine: &Engine, a: &Analysis) -> Vec<Figure> {
    run_figures_with(engine, a, false)
}

/// [`run_figures`]; with `centered` the angle axes run from minus half the
/// cycle to plus half (−360…360, two-stroke −180…180), the curves rotated
/// accordingly (`--angles centered`).
pub fn run_figures_with(engine: &Engine, a: &Analysis, centered: bool) -> Vec<Figure> {
    let n = a.torque.total.len();
    let step_deg = a.step.to_degrees();
    let cycle = n as f64 * step_deg;
    // Reference lines span the axis: [0, cycle), or centred.
    let (lo, hi) = if centered {
        let lo = -((n / 2) as f64) * step_deg;
        (lo, lo + cycle)
    } else {
        (0.0, cycle)
    };
    let axis = RunAxis {
        step_deg,
        centered,
        lo,
        hi,
    };
    let name = engine.name();
    let has_pressure = !a.pressure.is_empty();
    let mut figs = Vec::new();
    if has_pressure {
        figs.push(pressure_figure(name, a, &axis));
    }
    // Kinematics over the cycle of cylinder 1.
    figs.push(Figure::single(
        "kinematics.svg",
        kinematics_chart_with(
            format!("{name} — piston motion ({})", a.summary.kinematics),
            &a.kinematics,
            engine.mechanism().r(),
            step_deg,
            centered,
        ),
    ));
    if has_pressure {
        figs.push(forces_figure(name, a, &axis));
    }
    figs.push(torque_figure(engine, a, &axis));
    figs.push(journal_torques_figure(name, a, &axis));
    if has_pressure {
        figs.push(crankpin_figure(name, a));
    }
    figs.push(flywheel_figure(name, a, &axis));
    figs.push(harmonics_figure(name, a));
    figs
}

/// The crank-angle axis of [`run_figures_with`]'s charts: the curves'
/// step (deg) and whether they are centred on TDC, and the span (`lo`,
/// `hi`, deg) of reference lines.
struct RunAxis {
    step_deg: f64,
    centered: bool,
    lo: f64,
    hi: f64,
}

impl RunAxis {
    /// A curve over the cycle on this axis ([`periodic`]).
    fn curve(&self, name: &str, y: &[f64]) -> Series {
        periodic(name, y, self.step_deg, self.centered)
    }
}

/// The operating point as a chart's title names it: `4900 rpm`, and for a
/// diagram synthesised from `[combustion]` `4900 rpm, synthesised at IMEP
/// 10 bar`, so that a chart is never taken for a measurement.
pub(crate) fn point(s: &enginedyn_pipeline::Summary) -> String {
    match (&s.design, s.imep_bar) {
        (Some(_), Some(imep)) => format!(
            "{:.0} rpm, synthesised at IMEP {} bar",
            s.rpm,
            crate::human((imep * 100.0).round() / 100.0)
        ),
        (Some(_), None) => format!("{:.0} rpm, synthesised", s.rpm),
        _ => format!("{:.0} rpm", s.rpm),
    }
}

/// Values in N as kN.
fn kilo(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x / 1e3).collect()
}

/// Pressure: p–φ, and p–V on log-log axes.
fn pressure_figure(name: &str, a: &Analysis, axis: &RunAxis) -> Figure {
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
    Figure {
        file: "pressure.svg".into(),
        panels: vec![
            Chart::angle(
                format!("{name} — cylinder pressure, {}", point(&a.summary)),
                "pressure (bar, absolute)",
                vec![axis.curve("p(φ)", &bar)],
            ),
            pv,
        ],
    }
}

/// Forces on cylinder 1.
fn forces_figure(name: &str, a: &Analysis, axis: &RunAxis) -> Figure {
    let f = &a.forces;
    Figure::single(
        "forces.svg",
        Chart::angle(
            format!(
                "{name} — forces on cylinder 1 ({} rod), {}",
                a.summary.rod_model,
                point(&a.summary)
            ),
            "force (kN), positive toward the crank / driving",
            vec![
                axis.curve("gas P_g", &kilo(&f.gas)),
                axis.curve("inertia P_j", &kilo(&f.inertia)),
                axis.curve("total P", &kilo(&f.total)),
                axis.curve("side thrust N", &kilo(&f.side)),
                axis.curve("radial K", &kilo(&f.radial)),
                axis.curve("tangential T", &kilo(&f.tangential)),
            ],
        ),
    )
}

/// Torque: indicated curves; the effective mean beside the indicated one
/// when a mechanical efficiency below 1 sets them apart.
fn torque_figure(engine: &Engine, a: &Analysis, axis: &RunAxis) -> Figure {
    let name = engine.name();
    let (lo, hi) = (axis.lo, axis.hi);
    let mean = a.uniformity.mean;
    let eta = a.summary.mechanical_efficiency;
    let mut torque = vec![
        axis.curve("cylinder 1, indicated", &a.forces.torque),
        axis.curve(
            &format!("engine ({} cylinders), indicated", engine.cylinders()),
            &a.torque.total,
        ),
        Series::hline(
            format!("mean, indicated {} N m", crate::fixed(mean, 1)),
            mean,
            lo,
            hi,
        ),
    ];
    if (eta - 1.0).abs() > 1e-12 {
        torque.push(Series::hline(
            format!(
                "mean, {} {} N m",
                crate::effective(&a.summary),
                crate::fixed(mean * eta, 1)
            ),
            mean * eta,
            lo,
            hi,
        ));
    }
    Figure::single(
        "torque.svg",
        Chart::angle(
            format!("{name} — torque, {}", point(&a.summary)),
            "torque (N m)",
            torque,
        ),
    )
}

/// Journal torques, counted from the free end.
fn journal_torques_figure(name: &str, a: &Analysis, axis: &RunAxis) -> Figure {
    let journals = a
        .torque
        .journals
        .iter()
        .enumerate()
        .map(|(k, j)| axis.curve(&format!("journal after throw {}", k + 1), j))
        .collect();
    Figure::single(
        "journal_torques.svg",
        Chart::angle(
            format!("{name} — main-journal torques (from the free end)"),
            "torque (N m)",
            journals,
        ),
    )
}

/// Crank-pin load, crank-fixed axes.
fn crankpin_figure(name: &str, a: &Analysis) -> Figure {
    let f = &a.forces;
    let pin: Vec<(f64, f64)> = (0..a.torque.total.len())
        .map(|k| (f.tangential[k] / 1e3, f.pin_radial[k] / 1e3))
        .collect();
    let mut polar_pts = pin.clone();
    polar_pts.push(pin[0]);
    Figure::single(
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
    )
}

/// Flywheel: excess energy and the speed trace with I_0.
fn flywheel_figure(name: &str, a: &Analysis, axis: &RunAxis) -> Figure {
    let (lo, hi) = (axis.lo, axis.hi);
    let mut panels = vec![Chart::angle(
        format!(
            "{name} — excess energy E(φ), ΔE = {:.1} J",
            a.uniformity.excess_work
        ),
        "E (J)",
        vec![axis.curve("E(φ)", &a.uniformity.excess_energy)],
    )];
    if let Some(fw) = &a.flywheel {
        let rpm_trace: Vec<f64> = fw
            .speed
            .iter()
            .map(|w| w * 30.0 / std::f64::consts::PI)
            .collect();
        let (slow, fast) = rpm_trace
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
                axis.curve("n(φ)", &rpm_trace),
                // The two limits in one style: one series, the pen lifted
                // between them.
                Series {
                    name: format!("max {fast:.1}, min {slow:.1}"),
                    points: vec![
                        (lo, fast),
                        (hi, fast),
                        (f64::NAN, f64::NAN),
                        (lo, slow),
                        (hi, slow),
                    ],
                    dashed: true,
                    marker: false,
                    color: None,
                },
            ],
        ));
    }
    Figure {
        file: "flywheel.svg".into(),
        panels,
    }
}

/// Harmonics as stems by engine order.
fn harmonics_figure(name: &str, a: &Analysis) -> Figure {
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
    Figure::single(
        "harmonics.svg",
        Chart {
            title: format!(
                "{name} — torque harmonics by engine order, {}",
                point(&a.summary)
            ),
            x_label: "engine order (per revolution)".into(),
            y_label: "amplitude (N m)".into(),
            series: vec![
                Series {
                    name: "cylinder 1".into(),
                    points: cyl,
                    dashed: false,
                    marker: false,
                    color: None,
                },
                Series {
                    name: "engine".into(),
                    points: eng,
                    dashed: false,
                    marker: false,
                    color: None,
                },
            ],
            log: false,
            equal: false,
            angle_ticks: None,
        },
    )
}

/// One labelled point of a [`ScatterChart`].
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterPoint {
    /// Position (data units).
    pub x: f64,
    /// Position (data units).
    pub y: f64,
    /// Text beside the marker ("series2", "1°").
    pub label: String,
}

/// Points drawn with one marker: shape and colour from `style`, filled or
/// hollow.
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterGroup {
    /// Legend text.
    pub name: String,
    /// Marker shape and colour index (circle, square, triangle, diamond,
    /// inverted triangle, cross; the palette's colours in order).
    pub style: usize,
    /// Filled marker (hollow when false).
    pub filled: bool,
    /// The points.
    pub points: Vec<ScatterPoint>,
}

/// A log-log chart of labelled markers in groups, a step line (a Pareto
/// front) and horizontal guides named in the legend (e.g. tolerances): the accuracy
/// chart.
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterChart {
    /// File name, used in errors.
    pub file: String,
    /// Caption.
    pub title: String,
    /// X axis quantity and unit.
    pub x_label: String,
    /// Y axis quantity and unit.
    pub y_label: String,
    /// Marker groups.
    pub groups: Vec<ScatterGroup>,
    /// Legend text and corner points of the step line: from each point
    /// right to the next one's x, then down (or up) to it, and on to the
    /// right edge after the last.
    pub steps: Option<(String, Vec<(f64, f64)>)>,
    /// Horizontal guides: y and the text naming the line in the legend.
    pub guides: Vec<(f64, String)>,
}

/// The size of the accuracy chart (px): wider than the run charts, for the
/// labels; report.html shows it unscaled.
const SCATTER: (u32, u32) = (1200, 760);
const POINT_FONT: u32 = 15;

pub(crate) fn overlap(a: (i32, i32, i32, i32), b: (i32, i32, i32, i32)) -> i32 {
    let w = (a.2.min(b.2) - a.0.max(b.0)).max(0);
    let h = (a.3.min(b.3) - a.1.max(b.1)).max(0);
    w * h
}

/// Where a [`ScatterChart`]'s marks and texts went, in pixels of the whole
/// chart: (left, top, right, bottom).
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterLayout {
    /// The plot area.
    pub plot: (i32, i32, i32, i32),
    /// Each marker's box.
    pub markers: Vec<(i32, i32, i32, i32)>,
    /// Each point's label.
    pub labels: Vec<crate::PlacedLabel>,
}

/// Half the size of a marker's box (px): the largest shape, a diamond of
/// radius 6 reaching 8 px up and down, with its stroke.
const MARK_HALF: i32 = 9;

impl ScatterChart {
    /// Renders to an SVG document.
    pub fn render(&self) -> Result<String, ReportError> {
        let mut svg = String::new();
        self.draw(&mut svg).map_err(|e| ReportError::Chart {
            name: self.file.clone(),
            message: e.to_string(),
        })?;
        Ok(svg)
    }

    /// Where the markers and labels are placed (as
    /// [`ScatterChart::render`] draws them).
    pub fn layout(&self) -> Result<ScatterLayout, ReportError> {
        let mut svg = String::new();
        self.draw(&mut svg).map_err(|e| ReportError::Chart {
            name: self.file.clone(),
            message: e.to_string(),
        })
    }

    fn draw(&self, svg: &mut String) -> Result<ScatterLayout, Box<dyn std::error::Error>> {
        use plotters::style::text_anchor::{HPos, Pos, VPos};
        let root = SVGBackend::with_string(svg, SCATTER).into_drawing_area();
        root.fill(&WHITE)?;
        let (x0, x1, y0, y1) = self.range();
        let keys = self.legend(y0, y1);
        let (head, body) = root.split_vertically(head_height(&keys, SCATTER.0 as i32));
        draw_head(&head, &self.title, &keys)?;
        let (xt, yt) = (Ticks::log(x0, x1), Ticks::log(y0, y1));
        let (lx, ly) = ((x0.log10(), x1.log10()), (y0.log10(), y1.log10()));
        let chart = axes(&body, (lx, &xt), (ly, &yt), (&self.x_label, &self.y_label))?;
        let plot = chart.plotting_area().strip_coord_spec();
        let base = plot.get_base_pixel();
        let (pw, ph) = plot.dim_in_pixel();
        let px = |x: f64, y: f64| {
            let (a, b) = chart.backend_coord(&(x.log10(), y.log10()));
            (a - base.0, b - base.1)
        };
        let th = (POINT_FONT as f64 / 1.24).ceil() as i32 + 2;
        // Boxes no label may touch: markers and placed labels.
        let mut hard: Vec<(i32, i32, i32, i32)> = Vec::new();
        let mut layout = ScatterLayout {
            plot: (base.0, base.1, base.0 + pw as i32, base.1 + ph as i32),
            markers: Vec::new(),
            labels: Vec::new(),
        };
        let whole =
            |b: (i32, i32, i32, i32)| (b.0 + base.0, b.1 + base.1, b.2 + base.0, b.3 + base.1);
        self.draw_guides(&plot, &px, (x0, y0, y1))?;
        let steps = self.draw_steps(&plot, &px, x1)?;
        // Markers, then labels placed greedily: never on a marker or
        // another label, as near their point as that allows, off the step
        // line where they can be.
        let mut marks = Vec::new();
        for g in &self.groups {
            let color = PALETTE[g.style % PALETTE.len()];
            for p in &g.points {
                if !(p.x > 0.0 && p.y > 0.0 && p.x.is_finite() && p.y.is_finite()) {
                    continue;
                }
                let at = px(p.x, p.y);
                draw_marker(&plot, at, g.style, color, g.filled, 6)?;
                marks.push((at, p.label.clone(), color));
                let b = (
                    at.0 - MARK_HALF,
                    at.1 - MARK_HALF,
                    at.0 + MARK_HALF,
                    at.1 + MARK_HALF,
                );
                hard.push(b);
                layout.markers.push(whole(b));
            }
        }
        for (at, label, color) in &marks {
            if label.is_empty() {
                continue;
            }
            let w = text_width(label, POINT_FONT);
            let area = (pw as i32, ph as i32);
            let Some(b) = place_point_label(*at, (w, th), area, &hard, &steps) else {
                continue;
            };
            draw_point_leader(&plot, *at, b, (w, th), *color)?;
            plot.draw(&Text::new(
                label.clone(),
                (b.0, b.1 + 1),
                ("sans-serif", POINT_FONT)
                    .into_font()
                    .color(&BLACK)
                    .pos(Pos::new(HPos::Left, VPos::Top)),
            ))?;
            hard.push(b);
            layout.labels.push(crate::PlacedLabel {
                text: label.clone(),
                major: false,
                bounds: whole(b),
            });
        }
        root.present()?;
        Ok(layout)
    }

    /// The axes' ranges (x0, x1, y0, y1): the finite positive points and
    /// step corners, with room for the labels to the right (a decade
    /// each way when there is none).
    fn range(&self) -> (f64, f64, f64, f64) {
        let pts = self
            .groups
            .iter()
            .flat_map(|g| g.points.iter().map(|p| (p.x, p.y)))
            .chain(self.steps.iter().flat_map(|s| s.1.iter().copied()))
            .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0);
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for (x, y) in pts {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (0.1, 10.0, 1e-6, 1e-2);
        }
        // Room for the labels to the right.
        (x0 / 1.3, x1 * 2.5, y0 / 2.0, y1 * 2.0)
    }

    /// The legend: each group's marker, the step line, and the guides
    /// within `y0..=y1`. The guides are named in the legend: a text on its
    /// line would cover the markers that crowd near it.
    fn legend(&self, y0: f64, y1: f64) -> Vec<(String, Key)> {
        let mut keys: Vec<(String, Key)> = self
            .groups
            .iter()
            .map(|g| {
                (
                    g.name.clone(),
                    Key::Marker {
                        shape: g.style,
                        color: PALETTE[g.style % PALETTE.len()],
                        filled: g.filled,
                    },
                )
            })
            .collect();
        if let Some((name, _)) = &self.steps {
            keys.push((
                name.clone(),
                Key::Line {
                    color: BLACK,
                    width: 2,
                    dashed: false,
                },
            ));
        }
        for (y, text) in &self.guides {
            if (y0..=y1).contains(y) {
                keys.push((
                    text.clone(),
                    Key::Line {
                        color: GUIDE,
                        width: 1,
                        dashed: true,
                    },
                ));
            }
        }
        keys
    }

    /// Guides within `y0..=y1`, faint dashes across the plot from `x0`
    /// (the legend names them); `px` maps data to the plot's pixels.
    fn draw_guides(
        &self,
        plot: &Area,
        px: &dyn Fn(f64, f64) -> (i32, i32),
        (x0, y0, y1): (f64, f64, f64),
    ) -> Result<(), Box<dyn std::error::Error>> {
        let pw = plot.dim_in_pixel().0;
        for (y, _) in &self.guides {
            if !(y0..=y1).contains(y) {
                continue;
            }
            let (_, py) = px(x0, *y);
            for k in 0..(pw as i32 / 12 + 1) {
                let a = k * 12;
                plot.draw(&PathElement::new(
                    vec![(a, py), ((a + 6).min(pw as i32), py)],
                    GUIDE.stroke_width(1),
                ))?;
            }
        }
        Ok(())
    }

    /// The step line, on to `x1` after its last corner; the boxes of its
    /// segments (pixels of the plot), which labels keep off where they can.
    fn draw_steps(
        &self,
        plot: &Area,
        px: &dyn Fn(f64, f64) -> (i32, i32),
        x1: f64,
    ) -> Result<Vec<PixelBox>, Box<dyn std::error::Error>> {
        let Some((_, corners)) = &self.steps else {
            return Ok(Vec::new());
        };
        let mut c: Vec<(f64, f64)> = corners
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
            .collect();
        c.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut line = Vec::with_capacity(2 * c.len() + 1);
        for (k, &(x, y)) in c.iter().enumerate() {
            if k > 0 {
                line.push(px(x, c[k - 1].1));
            }
            line.push(px(x, y));
        }
        if let Some(&(_, y)) = c.last() {
            line.push(px(x1, y));
        }
        plot.draw(&PathElement::new(
            line.clone(),
            BLACK.mix(0.8).stroke_width(2),
        ))?;
        Ok(line
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                (
                    a.0.min(b.0) - 2,
                    a.1.min(b.1) - 2,
                    a.0.max(b.0) + 2,
                    a.1.max(b.1) + 2,
                )
            })
            .collect())
    }
}

/// The colour of a [`ScatterChart`]'s guides.
const GUIDE: RGBColor = RGBColor(150, 150, 150);

/// A box in pixels: (left, top, right, bottom).
type PixelBox = (i32, i32, i32, i32);

/// Where the label of `size` (w, h px) of the marker at `(x, y)` goes in a
/// plot of `area` (w, h px): candidates ring by ring (right, left, above,
/// below, the diagonals and between), the first ring with a place on no
/// `hard` box (markers, labels) and off the `soft` ones (the step line);
/// else the cheapest place seen.
fn place_point_label(
    (x, y): (i32, i32),
    (w, th): (i32, i32),
    (pw, ph): (i32, i32),
    hard: &[PixelBox],
    soft: &[PixelBox],
) -> Option<PixelBox> {
    let mut best: Option<(PixelBox, i64)> = None;
    for ring in 1..=14 {
        let d = MARK_HALF + 2 + 9 * (ring - 1);
        let mut found = false;
        for (dx, dy) in [
            (d, -th / 2),
            (-d - w, -th / 2),
            (-w / 2, -d - th),
            (-w / 2, d),
            (d, -d - th / 2),
            (d, d - th / 2),
            (-d - w, -d - th / 2),
            (-d - w, d - th / 2),
            (d / 2, -d - th),
            (d / 2, d),
            (-d / 2 - w, -d - th),
            (-d / 2 - w, d),
        ] {
            let b = (x + dx, y + dy, x + dx + w, y + dy + th);
            let outside = b.0 < 0 || b.1 < 0 || b.2 > pw || b.3 > ph;
            let blocked = outside || hard.iter().any(|t| overlap(*t, b) > 0);
            let on_soft: i64 = soft.iter().map(|t| overlap(*t, b) as i64).sum();
            let cost = if blocked { 1 << 40 } else { 0 } + on_soft * 4 + ring as i64 * 40;
            if best.is_none_or(|(_, c)| cost < c) {
                best = Some((b, cost));
            }
            found |= !blocked && on_soft == 0;
        }
        if found {
            break;
        }
    }
    best.map(|(b, _)| b)
}

/// A leader from the marker at `(x, y)` to its label `b` of `size` (w, h
/// px) when the label was placed away from it: from the marker's edge to
/// the label's nearest side.
fn draw_point_leader(
    plot: &Area,
    (x, y): (i32, i32),
    b: PixelBox,
    (w, th): (i32, i32),
    color: RGBColor,
) -> Result<(), Box<dyn std::error::Error>> {
    let (cx, cy) = ((b.0 + b.2) / 2, (b.1 + b.3) / 2);
    if (cx - x).abs() > w / 2 + 2 * MARK_HALF || (cy - y).abs() > th + 2 * MARK_HALF {
        let ex = cx.clamp(b.0, b.2);
        let ey = if cy > y { b.1 } else { b.3 };
        let (vx, vy) = ((ex - x) as f64, (ey - y) as f64);
        let len = vx.hypot(vy).max(1.0);
        let start = (
            x + (vx / len * MARK_HALF as f64) as i32,
            y + (vy / len * MARK_HALF as f64) as i32,
        );
        plot.draw(&PathElement::new(
            vec![start, (ex, ey)],
            color.mix(0.6).stroke_width(1),
        ))?;
    }
    Ok(())
}
