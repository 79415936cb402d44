//! Contour charts of a speed × load map: a figure (peak pressure, speed
//! fluctuation, required inertia…) over speed and mean effective
//! pressure, filled in bands of one colour scale, with iso-lines at the
//! bands' edges, the full-load line drawn over them and the rated-power
//! and peak-torque points marked.
//!
//! The map's nodes lie on a grid that is regular in (speed, load %) but
//! not in (speed, BMEP): each cell is split into two triangles and the
//! figure taken as linear on each (in both the coordinates and the value),
//! so a band or an iso-line is exact wherever the figure is linear in the
//! plotted coordinates, and never leaves the cell it was computed from.

use crate::ReportError;
use crate::chart::{
    Key, LEGEND_FRAME, Ticks, append_svg, axes_with, draw_head, fine_pixel, head_height,
    svg_points, svg_polyline, text_width,
};
use enginedyn_numerics::format::trimmed;
use plotters::prelude::*;

/// One node of a map: its place on the chart and the figure there
/// (`None`: not computed there, as a flywheel figure of a point that
/// delivers no work).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    /// Speed (rpm).
    pub x: f64,
    /// Load coordinate (bar of mean effective pressure).
    pub y: f64,
    /// The figure.
    pub z: Option<f64>,
}

/// A marked point (rated power, peak torque) with its legend text.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// Legend text, with the figure and its unit.
    pub name: String,
    /// Where (chart coordinates).
    pub at: (f64, f64),
}

/// A contour chart of a map.
#[derive(Debug, Clone, PartialEq)]
pub struct ContourChart {
    /// File name (`map_p_max.svg`).
    pub file: String,
    /// Title: the figure and its unit.
    pub title: String,
    /// X axis quantity and unit.
    pub x_label: String,
    /// Y axis quantity and unit.
    pub y_label: String,
    /// The colour bar's unit.
    pub unit: String,
    /// Nodes along x (speeds) in one row.
    pub columns: usize,
    /// The nodes, row by row (a row a load, lowest first), each row
    /// `columns` long.
    pub nodes: Vec<Node>,
    /// The full-load line (its legend text and points), drawn over the
    /// bands.
    pub line: Option<(String, Vec<(f64, f64)>)>,
    /// Marked points.
    pub marks: Vec<Mark>,
}

/// A vertex of a triangle: (x, y, value).
type Vertex = (f64, f64, f64);

/// The triangles of a grid of `columns` × `rows` nodes (indices into the
/// row-major nodes): each cell split along its rising diagonal.
pub fn triangles(columns: usize, rows: usize) -> Vec<[usize; 3]> {
    let mut t = Vec::with_capacity(2 * columns.saturating_sub(1) * rows.saturating_sub(1));
    for j in 0..rows.saturating_sub(1) {
        for i in 0..columns.saturating_sub(1) {
            let a = j * columns + i;
            let (b, c, d) = (a + 1, a + columns, a + columns + 1);
            t.push([a, b, d]);
            t.push([a, d, c]);
        }
    }
    t
}

/// The part of a polygon (vertices carrying a value linear over it) where
/// `keep(value)` holds, cut where the value crosses `level`
/// (Sutherland–Hodgman against one half-plane of the value).
fn clip(poly: &[Vertex], level: f64, above: bool) -> Vec<Vertex> {
    let inside = |v: &Vertex| if above { v.2 >= level } else { v.2 <= level };
    let mut out = Vec::with_capacity(poly.len() + 2);
    for (k, cur) in poly.iter().enumerate() {
        let prev = &poly[(k + poly.len() - 1) % poly.len()];
        let (ci, pi) = (inside(cur), inside(prev));
        if ci != pi {
            let t = (level - prev.2) / (cur.2 - prev.2);
            out.push((
                prev.0 + t * (cur.0 - prev.0),
                prev.1 + t * (cur.1 - prev.1),
                level,
            ));
        }
        if ci {
            out.push(*cur);
        }
    }
    out
}

/// The part of triangle `tri` whose value lies in the band from `lo` to
/// `hi`: a convex polygon of up to five vertices, empty when the band
/// misses it. A flat triangle lies in one band only: the one with `lo ≤ z
/// < hi`, or `z = hi` in the top band (`top`), so that the bands tile the
/// map once.
pub fn band(tri: [Vertex; 3], lo: f64, hi: f64, top: bool) -> Vec<(f64, f64)> {
    let z = tri[0].2;
    if tri.iter().all(|v| v.2.total_cmp(&z).is_eq()) {
        let inside = (lo <= z && z < hi) || (top && z.total_cmp(&hi).is_eq());
        return if inside {
            tri.iter().map(|v| (v.0, v.1)).collect()
        } else {
            Vec::new()
        };
    }
    let p = clip(&tri, lo, true);
    let p = if p.is_empty() { p } else { clip(&p, hi, false) };
    if p.len() < 3 {
        return Vec::new();
    }
    p.into_iter().map(|(x, y, _)| (x, y)).collect()
}

/// Where the value of triangle `tri` equals `level`: a segment, or `None`
/// when the level misses it or only touches a vertex.
pub fn iso_segment(tri: [Vertex; 3], level: f64) -> Option<((f64, f64), (f64, f64))> {
    let mut pts = Vec::with_capacity(2);
    for k in 0..3 {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        // Half-open at the upper end: a vertex on the level counts for
        // one of its two edges only.
        let crosses = (a.2 < level && b.2 >= level) || (b.2 < level && a.2 >= level);
        if crosses {
            let t = (level - a.2) / (b.2 - a.2);
            pts.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
    match pts.as_slice() {
        [p, q] if p != q => Some((*p, *q)),
        _ => None,
    }
}

/// The band edges of values over `[lo, hi]`: round numbers (1, 2 or 5
/// times a power of ten apart), about eight bands, the first at or below
/// `lo` and the last at or above `hi`; a single value gets one band
/// around it.
pub fn levels(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) {
        return Vec::new();
    }
    let (lo, hi) = if hi - lo <= 1e-9 * lo.abs().max(hi.abs()).max(1e-300) {
        let d = lo.abs().max(1e-12) * 0.05;
        (lo - d, hi + d)
    } else {
        (lo, hi)
    };
    let t = Ticks::linear(lo, hi, 8.0, None);
    let step = match t.bold() {
        [a, b, ..] => b - a,
        _ => hi - lo,
    };
    let first = (lo / step).floor() * step;
    let n = ((hi - first) / step).ceil().clamp(1.0, 40.0) as usize;
    (0..=n).map(|k| first + k as f64 * step).collect()
}

/// The colour of the band at `u` in [0, 1] on a perceptually even scale
/// from dark blue through green to yellow (viridis' anchors, linearly
/// between them).
pub fn scale_colour(u: f64) -> RGBColor {
    const ANCHORS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let u = if u.is_finite() {
        u.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = u * (ANCHORS.len() - 1) as f64;
    let k = (s.floor() as usize).min(ANCHORS.len() - 2);
    let f = s - k as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (ANCHORS[k], ANCHORS[k + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Width of the colour bar's column (px).
const BAR_COLUMN: u32 = 130;
/// The full-load line's colour and the marks' colours.
const LINE: RGBColor = RGBColor(0, 0, 0);
const MARKS: [RGBColor; 2] = [RGBColor(214, 39, 40), RGBColor(255, 255, 255)];

impl ContourChart {
    /// The values' range over the nodes that have one.
    fn range(&self) -> Option<(f64, f64)> {
        let zs = self
            .nodes
            .iter()
            .filter_map(|n| n.z)
            .filter(|z| z.is_finite());
        let (lo, hi) = zs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
            (a.min(z), b.max(z))
        });
        (lo <= hi).then_some((lo, hi))
    }

    /// The triangles whose three nodes all have a value, as vertices.
    fn valued_triangles(&self) -> Vec<[Vertex; 3]> {
        let rows = self.nodes.len() / self.columns.max(1);
        triangles(self.columns, rows)
            .into_iter()
            .filter_map(|t| {
                let v = |k: usize| {
                    let n = self.nodes[k];
                    n.z.filter(|z| z.is_finite()).map(|z| (n.x, n.y, z))
                };
                Some([v(t[0])?, v(t[1])?, v(t[2])?])
            })
            .collect()
    }

    /// The legend: the full-load line and the marks.
    fn legend(&self) -> Vec<(String, Key)> {
        let mut items = Vec::new();
        if let Some((name, _)) = &self.line {
            items.push((
                name.clone(),
                Key::Line {
                    color: LINE,
                    width: 3,
                    dashed: false,
                },
            ));
        }
        for (k, m) in self.marks.iter().enumerate() {
            items.push((
                m.name.clone(),
                Key::Marker {
                    shape: if k == 0 { 0 } else { 1 },
                    color: if k == 0 { MARKS[0] } else { LINE },
                    filled: k == 0,
                },
            ));
        }
        items
    }

    /// Renders to an SVG document (900 × 560 px).
    pub fn render(&self) -> Result<String, ReportError> {
        let err = |e: &dyn std::fmt::Display| ReportError::Chart {
            name: self.file.clone(),
            message: e.to_string(),
        };
        let mut svg = String::new();
        let top;
        {
            let root = SVGBackend::with_string(&mut svg, (900, 560)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| err(&e))?;
            top = self.draw(&root).map_err(|e| err(&e))?;
            root.present().map_err(|e| err(&e))?;
        }
        append_svg(&mut svg, &top);
        Ok(svg)
    }

    fn draw(&self, root: &crate::chart::Area) -> Result<Vec<String>, Box<dyn std::error::Error>> {
        let legend = self.legend();
        let (w, _) = root.dim_in_pixel();
        let (head, body) = root.split_vertically(head_height(&legend, w as i32));
        draw_head(&head, &self.title, &legend)?;
        let (bw, _) = body.dim_in_pixel();
        let (plot_area, bar_area) = body.split_horizontally(bw - BAR_COLUMN);
        let pts = self
            .nodes
            .iter()
            .map(|n| (n.x, n.y))
            .chain(self.line.iter().flat_map(|(_, l)| l.iter().copied()));
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for (x, y) in pts.filter(|(x, y)| x.is_finite() && y.is_finite()) {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        let pad = |a: f64, b: f64, f: f64| {
            let d = if b > a {
                (b - a) * f
            } else {
                a.abs().max(1.0) * 0.1
            };
            (a - d, b + d)
        };
        let (x0, x1) = pad(x0, x1, 0.02);
        let (y0, y1) = pad(y0.min(0.0), y1, 0.06);
        let (_, h) = plot_area.dim_in_pixel();
        let xt = Ticks::linear(x0, x1, 9.0, None);
        let yt = Ticks::linear(y0, y1, (h as f64 / 70.0).clamp(4.0, 8.0), None);
        let chart = axes_with(
            &plot_area,
            ((x0, x1), &xt),
            ((y0, y1), &yt),
            (&self.x_label, &self.y_label),
            (6, 14),
        )?;
        let mut out = Vec::new();
        let px = |p: (f64, f64)| fine_pixel(&chart, p);
        let Some((lo, hi)) = self.range() else {
            // Nothing to fill: say so in the plot.
            out.push(svg_text(
                px(((x0 + x1) / 2.0, (y0 + y1) / 2.0)),
                "no value at any point of the map",
                15,
                "middle",
            ));
            return Ok(out);
        };
        let lv = levels(lo, hi);
        let bands = lv.len().saturating_sub(1).max(1);
        let colour = |k: usize| scale_colour((k as f64 + 0.5) / bands as f64);
        let tris = self.valued_triangles();
        for tri in &tris {
            for k in 0..bands {
                let poly = band(*tri, lv[k], lv[k + 1], k + 1 == bands);
                if !poly.is_empty() {
                    let p: Vec<(f64, f64)> = poly.into_iter().map(px).collect();
                    out.push(svg_polygon(&p, colour(k)));
                }
            }
        }
        // Iso-lines at the inner band edges.
        for &level in lv.iter().skip(1).take(lv.len().saturating_sub(2)) {
            for tri in &tris {
                if let Some((a, b)) = iso_segment(*tri, level) {
                    out.push(svg_polyline(
                        &[px(a), px(b)],
                        RGBColor(255, 255, 255),
                        0.7,
                        None,
                    ));
                }
            }
        }
        if let Some((_, line)) = &self.line {
            let p: Vec<(f64, f64)> = line
                .iter()
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .map(|&q| px(q))
                .collect();
            out.push(svg_polyline(&p, LINE, 3.0, None));
        }
        for (k, m) in self.marks.iter().enumerate() {
            let (x, y) = px(m.at);
            out.push(if k == 0 {
                format!(
                    "<circle cx=\"{}\" cy=\"{}\" r=\"6\" fill=\"#D62728\" stroke=\"#FFFFFF\" stroke-width=\"1.5\"/>\n",
                    trimmed(x, 2),
                    trimmed(y, 2)
                )
            } else {
                format!(
                    "<rect x=\"{}\" y=\"{}\" width=\"11\" height=\"11\" fill=\"none\" stroke=\"#000000\" stroke-width=\"2\"/>\n",
                    trimmed(x - 5.5, 2),
                    trimmed(y - 5.5, 2)
                )
            });
        }
        self.colour_bar(&bar_area, &lv, &colour)?;
        Ok(out)
    }

    /// The colour bar: a box a band, its edges labelled, the unit above.
    fn colour_bar(
        &self,
        area: &crate::chart::Area,
        lv: &[f64],
        colour: &dyn Fn(usize) -> RGBColor,
    ) -> Result<(), Box<dyn std::error::Error>> {
        use plotters::style::text_anchor::{HPos, Pos, VPos};
        let (_, h) = area.dim_in_pixel();
        let bands = lv.len().saturating_sub(1).max(1);
        let (top, bottom) = (40, h as i32 - 70);
        let band_h = ((bottom - top) / bands as i32).clamp(8, 40);
        let bottom = top + band_h * bands as i32;
        let (x, bar_w) = (14, 22);
        let font = ("sans-serif", 15)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        area.draw(&Text::new(self.unit.clone(), (x, top - 18), font.clone()))?;
        for k in 0..bands {
            let y = bottom - (k as i32 + 1) * band_h;
            area.draw(&Rectangle::new(
                [(x, y), (x + bar_w, y + band_h)],
                colour(k).filled(),
            ))?;
        }
        area.draw(&Rectangle::new(
            [(x, top), (x + bar_w, bottom)],
            LEGEND_FRAME.stroke_width(1),
        ))?;
        let step = if lv.len() > 1 { lv[1] - lv[0] } else { 0.0 };
        // At most about twelve labels: every n-th edge.
        let every = lv.len().div_ceil(12).max(1);
        let width = BAR_COLUMN as i32 - x - bar_w - 10;
        for (k, &v) in lv.iter().enumerate().filter(|(k, _)| k % every == 0) {
            let y = bottom - k as i32 * band_h;
            let label = crate::tick_label(v, step);
            if text_width(&label, 15) <= width {
                area.draw(&Text::new(label, (x + bar_w + 6, y), font.clone()))?;
            }
        }
        Ok(())
    }
}

/// A filled SVG polygon through pixel points, edged in its own colour (no
/// hairline seams between neighbouring pieces of one band).
fn svg_polygon(pts: &[(f64, f64)], color: RGBColor) -> String {
    let hex = format!("#{:02X}{:02X}{:02X}", color.0, color.1, color.2);
    format!(
        "<polygon fill=\"{hex}\" stroke=\"{hex}\" stroke-width=\"0.6\" points=\"{}\"/>\n",
        svg_points(pts)
    )
}

/// SVG text at a pixel point, escaped.
fn svg_text((x, y): (f64, f64), text: &str, size: u32, anchor: &str) -> String {
    format!(
        "<text x=\"{}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"{size}\" text-anchor=\"{anchor}\" fill=\"#555555\">{}</text>\n",
        trimmed(x, 2),
        trimmed(y, 2),
        crate::esc(text)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid regular in (speed, load) but sheared in y (as BMEP over a
    /// load in percent is), carrying `f(x, y)` at each node.
    fn sheared(f: impl Fn(f64, f64) -> f64) -> (usize, Vec<Node>) {
        let (cols, rows) = (7, 5);
        let mut nodes = Vec::new();
        for j in 0..rows {
            for i in 0..cols {
                let x = 1000.0 + 500.0 * i as f64;
                let top = 8.0 + 3.0 * (i as f64 * 0.7).sin();
                let y = top * (j + 1) as f64 / rows as f64;
                nodes.push(Node {
                    x,
                    y,
                    z: Some(f(x, y)),
                });
            }
        }
        (cols, nodes)
    }

    fn area(p: &[(f64, f64)]) -> f64 {
        let n = p.len();
        (0..n)
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % n]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum::<f64>()
            .abs()
            / 2.0
    }

    fn vertices(cols: usize, nodes: &[Node]) -> Vec<[Vertex; 3]> {
        triangles(cols, nodes.len() / cols)
            .into_iter()
            .map(|t| t.map(|k| (nodes[k].x, nodes[k].y, nodes[k].z.unwrap_or(f64::NAN))))
            .collect()
    }

    #[test]
    fn iso_lines_of_a_linear_figure_lie_on_its_level() {
        // z = 0.002 x + 1.5 y is linear in the plotted coordinates: every
        // iso-line point satisfies it to rounding, however the grid shears.
        let f = |x: f64, y: f64| 0.002 * x + 1.5 * y;
        let (cols, nodes) = sheared(f);
        let mut segments = 0;
        for level in levels(2.0, 20.0) {
            for tri in vertices(cols, &nodes) {
                if let Some((a, b)) = iso_segment(tri, level) {
                    segments += 1;
                    for p in [a, b] {
                        assert!((f(p.0, p.1) - level).abs() < 1e-9, "{p:?} off {level}");
                    }
                }
            }
        }
        assert!(segments > 20, "{segments} segments");
    }

    #[test]
    fn the_bands_tile_the_map_exactly() {
        // The bands of every triangle add up to the triangle: the map is
        // covered once, with no gap and no overlap, on a figure with a
        // narrow spike and a flat stretch.
        let f = |x: f64, y: f64| {
            if (x - 2500.0).abs() < 1.0 {
                40.0
            } else if x < 1600.0 {
                5.0
            } else {
                y
            }
        };
        let (cols, nodes) = sheared(f);
        let zs: Vec<f64> = nodes.iter().filter_map(|n| n.z).collect();
        let lo = zs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = zs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let lv = levels(lo, hi);
        assert!(lv[0] <= lo && *lv.last().unwrap() >= hi, "{lv:?}");
        for tri in vertices(cols, &nodes) {
            let whole = area(&[
                (tri[0].0, tri[0].1),
                (tri[1].0, tri[1].1),
                (tri[2].0, tri[2].1),
            ]);
            let n = lv.len() - 1;
            let parts: f64 = (0..n)
                .map(|k| area(&band(tri, lv[k], lv[k + 1], k + 1 == n)))
                .sum();
            assert!(
                (parts - whole).abs() <= 1e-9 * whole,
                "{parts} against {whole}"
            );
        }
    }

    #[test]
    fn levels_are_round_and_cover_the_range() {
        assert_eq!(
            levels(0.0, 10.0),
            vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0]
        );
        let l = levels(17.3, 98.6);
        assert!(l[0] <= 17.3 && *l.last().unwrap() >= 98.6);
        assert!((l[1] - l[0] - 10.0).abs() < 1e-12, "{l:?}");
        // One value: one band around it.
        let one = levels(0.02, 0.02);
        assert!(
            one.len() >= 2 && one[0] < 0.02 && *one.last().unwrap() > 0.02,
            "{one:?}"
        );
        assert!(levels(f64::NAN, 1.0).is_empty());
    }

    #[test]
    fn a_chart_without_values_says_so() {
        let chart = ContourChart {
            file: "x.svg".into(),
            title: "t".into(),
            x_label: "speed (rpm)".into(),
            y_label: "BMEP (bar)".into(),
            unit: "bar".into(),
            columns: 2,
            nodes: vec![
                Node {
                    x: 1000.0,
                    y: 1.0,
                    z: None
                };
                4
            ],
            line: None,
            marks: Vec::new(),
        };
        let svg = chart.render().unwrap();
        assert!(svg.contains("no value at any point of the map"));
    }
}
