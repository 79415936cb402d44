//! The torsion study's charts: the Campbell diagram (`campbell.svg`) and
//! the forced response over speed (`torsion.svg`). The formulas (an order's
//! frequency `k n / 60`, the critical speed `60 f / k`, which orders are
//! major) are `enginedyn_torsion`'s; this module only draws them.

use crate::chart::{
    Area, GREY, Key, PALETTE, Ticks, axes_with, draw_head, draw_marker, head_height, overlap,
    text_width,
};
use crate::{Chart, Figure, ReportError, Series};
use enginedyn_numerics::format::{fixed, human};
use enginedyn_pipeline::torsion::Study;
use enginedyn_torsion::{critical_speed_rpm, is_major_order, order_frequency_hz};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The Campbell diagram's size (px): taller than the run charts, for the
/// fan of order lines and the labels.
const CAMPBELL: (u32, u32) = (1000, 640);
/// Font sizes as plotters takes them (the SVG writes them 1/1.24 smaller).
const MARK_FONT: u32 = 14;
const ORDER_FONT: u32 = 14;
/// Major order lines: heavy and dark; the other orders light.
const MAJOR: RGBColor = RGBColor(30, 30, 30);
const MINOR: RGBColor = RGBColor(190, 190, 190);
/// Room outside the plot for the order numbers: above it (lines that leave
/// through the top) and right of it (lines that end at the top speed).
const TOP_ROOM: u32 = 22;
const RIGHT_ROOM: u32 = 40;

/// A resonance on a Campbell diagram: an engine order meeting a natural
/// frequency in the speed range.
#[derive(Debug, Clone, PartialEq)]
pub struct CampbellMark {
    /// The critical speed (rpm).
    pub rpm: f64,
    /// The mode's natural frequency (Hz).
    pub frequency_hz: f64,
    /// Engine order (per revolution).
    pub order: f64,
    /// Mode (1 = the first elastic mode).
    pub mode: usize,
    /// A major order (a multiple of the firings per revolution).
    pub major: bool,
    /// The peak of that order's free-end amplitude near the crossing
    /// (deg): the labels go to the strongest resonances first.
    pub amplitude_deg: f64,
}

/// A Campbell diagram: natural frequencies (horizontal lines) against
/// speed, the engine orders' lines `k n / 60`, and the resonances where
/// they meet, labelled `order × mode`. Major orders are drawn heavy and
/// dark, the others light; each order's number stands at its line's end
/// (thinned where they would crowd: the major orders first, half orders
/// unnumbered). Every resonance is marked; the labels go to the major
/// orders' first, then to the others by amplitude (those of a tenth of the
/// largest resonance or more), where they fit without overlapping.
#[derive(Debug, Clone, PartialEq)]
pub struct CampbellChart {
    /// File name, used in errors.
    pub file: String,
    /// Caption.
    pub title: String,
    /// The speed range (rpm).
    pub speed: (f64, f64),
    /// The modes drawn: (mode number, natural frequency in Hz).
    pub modes: Vec<(usize, f64)>,
    /// Engine orders (per revolution).
    pub orders: Vec<f64>,
    /// Firings per revolution: the major orders are its multiples.
    pub firings_per_revolution: f64,
    /// The resonances.
    pub marks: Vec<CampbellMark>,
}

/// A label placed on a Campbell diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedLabel {
    /// Its text ("4.5 × mode 1", or an order's number).
    pub text: String,
    /// Whether it belongs to a major order.
    pub major: bool,
    /// Its box in pixels of the whole chart: (left, top, right, bottom).
    pub bounds: (i32, i32, i32, i32),
}

/// Where a Campbell diagram's labels went.
#[derive(Debug, Clone, PartialEq)]
pub struct CampbellLayout {
    /// The plot area in pixels: (left, top, right, bottom).
    pub plot: (i32, i32, i32, i32),
    /// Resonance labels ("order × mode").
    pub resonances: Vec<PlacedLabel>,
    /// Order numbers at the lines' ends.
    pub orders: Vec<PlacedLabel>,
    /// Every resonance marker as drawn, in the order of
    /// [`CampbellChart::marks`]: its box in pixels (left, top, right,
    /// bottom), the ring's stroke included. A label's white ground is its
    /// box a pixel wider on each side.
    pub markers: Vec<(i32, i32, i32, i32)>,
    /// Leader lines from a marker to a label placed further out.
    pub leaders: Vec<Leader>,
}

/// A leader line from a resonance's marker to its label.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leader {
    /// The label's index in [`CampbellLayout::resonances`].
    pub label: usize,
    /// The marker's index in [`CampbellLayout::markers`].
    pub marker: usize,
    /// From the marker's centre (pixels).
    pub from: (i32, i32),
    /// To the label's edge (pixels).
    pub to: (i32, i32),
}

/// The clear gap (px) kept between two labels, so that each reads apart.
pub const LABEL_GAP: i32 = 4;

/// Whether the segment `a`–`b` passes through the box `r` (left, top,
/// right, bottom; edges included), sampled every half pixel.
pub fn segment_hits(a: (i32, i32), b: (i32, i32), r: (i32, i32, i32, i32)) -> bool {
    let (dx, dy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
    let steps = (2.0 * dx.abs().max(dy.abs())).ceil().max(1.0) as i32;
    (0..=steps).any(|i| {
        let t = i as f64 / steps as f64;
        let (x, y) = (a.0 as f64 + t * dx, a.1 as f64 + t * dy);
        x >= r.0 as f64 && x <= r.2 as f64 && y >= r.1 as f64 && y <= r.3 as f64
    })
}

/// A box in pixels: (left, top, right, bottom).
type Bounds = (i32, i32, i32, i32);

fn text_height(size: u32) -> i32 {
    (size as f64 / 1.24).ceil() as i32 + 2
}

fn inflate(b: (i32, i32, i32, i32), d: i32) -> (i32, i32, i32, i32) {
    (b.0 - d, b.1 - d, b.2 + d, b.3 + d)
}

fn inside(b: (i32, i32, i32, i32), area: (i32, i32, i32, i32)) -> bool {
    b.0 >= area.0 && b.1 >= area.1 && b.2 <= area.2 && b.3 <= area.3
}

impl CampbellChart {
    /// The Campbell diagram of a torsion study: the modes that meet an
    /// order in the speed range (and mode 1 always), every order the study
    /// computed, and its resonances.
    pub fn from_study(name: &str, study: &Study) -> Self {
        let lo = study.rows.first().map_or(0.0, |r| r.rpm);
        let hi = study.rows.last().map_or(lo, |r| r.rpm);
        let modes = (1..study.modes.len())
            .filter(|&m| m == 1 || study.resonances.iter().any(|r| r.mode == m))
            .map(|m| (m, study.modes.frequency_hz(m)))
            .collect();
        let marks = study
            .resonances
            .iter()
            .map(|r| CampbellMark {
                rpm: r.crossing_rpm,
                frequency_hz: study.modes.frequency_hz(r.mode),
                order: r.order,
                mode: r.mode,
                major: is_major_order(r.order, study.firings_per_revolution),
                amplitude_deg: r.amplitude_deg,
            })
            .collect();
        Self {
            file: "campbell.svg".into(),
            title: format!("{name} — Campbell diagram: natural frequencies and engine orders"),
            speed: (lo, hi),
            modes,
            orders: study.orders.clone(),
            firings_per_revolution: study.firings_per_revolution,
            marks,
        }
    }

    /// Renders to an SVG document.
    pub fn render(&self) -> Result<String, ReportError> {
        let mut svg = String::new();
        self.draw(&mut svg)?;
        Ok(svg)
    }

    /// Where the labels go (the same layout [`CampbellChart::render`] draws).
    pub fn layout(&self) -> Result<CampbellLayout, ReportError> {
        let mut svg = String::new();
        self.draw(&mut svg)
    }

    fn draw(&self, svg: &mut String) -> Result<CampbellLayout, ReportError> {
        self.draw_svg(svg).map_err(|e| ReportError::Chart {
            name: self.file.clone(),
            message: e.to_string(),
        })
    }

    /// The frequency axis's top: above the highest mode drawn, with room
    /// for its labels.
    fn top_hz(&self) -> f64 {
        let f = self.modes.iter().map(|m| m.1).fold(0.0, f64::max);
        let f = if f > 0.0 {
            f
        } else {
            let k = self.orders.iter().copied().fold(0.0, f64::max);
            order_frequency_hz(k, self.speed.1)
        };
        if f.is_finite() && f > 0.0 {
            f * 1.1
        } else {
            1.0
        }
    }

    fn keys(&self) -> Vec<(String, Key)> {
        let mut keys: Vec<(String, Key)> = self
            .modes
            .iter()
            .enumerate()
            .map(|(i, &(m, f))| {
                (
                    format!("mode {m}: {} Hz", fixed(f, 1)),
                    Key::Line {
                        color: PALETTE[i % PALETTE.len()],
                        width: 2,
                        dashed: false,
                    },
                )
            })
            .collect();
        keys.push((
            format!(
                "major orders (multiples of {})",
                human(self.firings_per_revolution)
            ),
            Key::Line {
                color: MAJOR,
                width: 2,
                dashed: false,
            },
        ));
        keys.push((
            "other orders".into(),
            Key::Line {
                color: MINOR,
                width: 1,
                dashed: false,
            },
        ));
        keys.push((
            "resonance (order × mode): major order".into(),
            Key::Marker {
                shape: 0,
                color: MAJOR,
                filled: true,
            },
        ));
        keys.push((
            "other order".into(),
            Key::Marker {
                shape: 0,
                color: GREY,
                filled: false,
            },
        ));
        keys
    }

    fn draw_svg(&self, svg: &mut String) -> Result<CampbellLayout, Box<dyn std::error::Error>> {
        let root = SVGBackend::with_string(svg, CAMPBELL).into_drawing_area();
        root.fill(&WHITE)?;
        let (mut lo, mut hi) = self.speed;
        if !(hi > lo) {
            (lo, hi) = (lo * 0.9, hi * 1.1 + 1.0);
        }
        let top = self.top_hz();
        let keys = self.keys();
        let (head, body) = root.split_vertically(head_height(&keys, CAMPBELL.0 as i32));
        draw_head(&head, &self.title, &keys)?;
        let (_, h) = body.dim_in_pixel();
        let xt = Ticks::linear(lo, hi, 9.0, None);
        let yt = Ticks::linear(0.0, top, (h as f64 / 70.0).clamp(4.0, 8.0), None);
        let chart = axes_with(
            &body,
            ((lo, hi), &xt),
            ((0.0, top), &yt),
            ("engine speed (rpm)", "frequency (Hz)"),
            (TOP_ROOM, RIGHT_ROOM),
        )?;
        // Pixels of the whole chart (the root area's own coordinates).
        let px = |x: f64, y: f64| chart.backend_coord(&(x, y));
        let (l, t) = px(lo, top);
        let (r, b) = px(hi, 0.0);
        let plot = (l, t, r, b);
        self.draw_orders(&root, &px, (lo, hi, top))?;
        let mode_rows: Vec<i32> = self.modes.iter().map(|&(_, f)| px(lo, f).1).collect();
        for (i, &y) in mode_rows.iter().enumerate() {
            root.draw(&PathElement::new(
                vec![(l, y), (r, y)],
                PALETTE[i % PALETTE.len()].stroke_width(2),
            ))?;
        }
        let order_labels = self.order_labels(&root, &px, (lo, hi, top), plot)?;
        let (resonances, markers, leaders) = self.mark_resonances(&root, &px, plot, &mode_rows)?;
        root.present()?;
        Ok(CampbellLayout {
            plot,
            resonances,
            orders: order_labels,
            markers,
            leaders,
        })
    }

    /// Where order `k`'s line ends: at the top speed, or where it leaves
    /// through the top of the plot; `None` when it starts above the top.
    fn line_end(k: f64, (lo, hi, top): (f64, f64, f64)) -> Option<((f64, f64), (f64, f64))> {
        let start = order_frequency_hz(k, lo);
        if !(k > 0.0) || start >= top {
            return None;
        }
        let end_hz = order_frequency_hz(k, hi);
        let end = if end_hz <= top {
            (hi, end_hz)
        } else {
            (critical_speed_rpm(top, k), top)
        };
        Some(((lo, start), end))
    }

    fn draw_orders(
        &self,
        root: &Area,
        px: &dyn Fn(f64, f64) -> (i32, i32),
        range: (f64, f64, f64),
    ) -> Result<(), Box<dyn std::error::Error>> {
        // The light lines first, so that the major ones lie on top.
        for major in [false, true] {
            for &k in &self.orders {
                if is_major_order(k, self.firings_per_revolution) != major {
                    continue;
                }
                let Some((a, e)) = Self::line_end(k, range) else {
                    continue;
                };
                let style = if major {
                    MAJOR.stroke_width(2)
                } else {
                    MINOR.stroke_width(1)
                };
                root.draw(&PathElement::new(vec![px(a.0, a.1), px(e.0, e.1)], style))?;
            }
        }
        Ok(())
    }

    /// Each order's number at its line's end, outside the plot: the major
    /// orders first, then the other whole orders, each where it overlaps
    /// no number already placed (half orders that are not major go
    /// unnumbered: their lines lie midway).
    fn order_labels(
        &self,
        root: &Area,
        px: &dyn Fn(f64, f64) -> (i32, i32),
        range: (f64, f64, f64),
        plot: (i32, i32, i32, i32),
    ) -> Result<Vec<PlacedLabel>, Box<dyn std::error::Error>> {
        let th = text_height(ORDER_FONT);
        let rank = |k: f64| {
            if is_major_order(k, self.firings_per_revolution) {
                0
            } else if (k - k.round()).abs() < 1e-9 {
                1
            } else {
                2
            }
        };
        let mut orders: Vec<f64> = self
            .orders
            .iter()
            .copied()
            .filter(|&k| rank(k) < 2)
            .collect();
        orders.sort_by(|a, b| rank(*a).cmp(&rank(*b)).then(a.total_cmp(b)));
        let (w_all, h_all) = CAMPBELL;
        let canvas = (0, 0, w_all as i32, h_all as i32);
        let mut placed: Vec<PlacedLabel> = Vec::new();
        for k in orders {
            let Some((_, e)) = Self::line_end(k, range) else {
                continue;
            };
            let (ex, ey) = px(e.0, e.1);
            let text = human(k);
            let w = text_width(&text, ORDER_FONT);
            let b = if (e.0 - range.1).abs() < 1e-9 * range.1.abs().max(1.0) {
                (plot.2 + 4, ey - th / 2, plot.2 + 4 + w, ey - th / 2 + th)
            } else {
                (ex - w / 2, plot.1 - th - 2, ex - w / 2 + w, plot.1 - 2)
            };
            if !inside(b, canvas) || placed.iter().any(|p| overlap(inflate(p.bounds, 1), b) > 0) {
                continue;
            }
            let major = rank(k) == 0;
            placed.push(PlacedLabel {
                text,
                major,
                bounds: b,
            });
        }
        for p in &placed {
            let color = if p.major { MAJOR } else { GREY };
            root.draw(&Text::new(
                p.text.clone(),
                (p.bounds.0, p.bounds.1 + 1),
                ("sans-serif", ORDER_FONT)
                    .into_font()
                    .color(&color)
                    .pos(Pos::new(HPos::Left, VPos::Top)),
            ))?;
        }
        Ok(placed)
    }

    /// Markers at every resonance and the `order × mode` labels: major
    /// orders first (further out, with a leader, when the near places are
    /// taken), then the others by amplitude where a near place is free. A
    /// label covers no marker, keeps [`LABEL_GAP`] from every other label
    /// and crosses no leader; a leader crosses no other label or marker.
    #[allow(clippy::type_complexity)]
    fn mark_resonances(
        &self,
        root: &Area,
        px: &dyn Fn(f64, f64) -> (i32, i32),
        plot: (i32, i32, i32, i32),
        mode_rows: &[i32],
    ) -> Result<(Vec<PlacedLabel>, Vec<Bounds>, Vec<Leader>), Box<dyn std::error::Error>> {
        let space = LabelSpace::new(&self.marks, px, plot, mode_rows);
        self.draw_markers(root, &space.at)?;
        let Placement {
            placed, leaders, ..
        } = space.place_retrying(&self.label_order());
        self.draw_resonance_labels(root, &placed, &leaders)?;
        let placed = placed.into_iter().map(|(_, p)| p).collect();
        Ok((placed, space.markers, leaders))
    }

    /// Mode `mode`'s colour: its line's, grey for a mode not drawn.
    fn mode_colour(&self, mode: usize) -> RGBColor {
        self.modes
            .iter()
            .position(|&(m, _)| m == mode)
            .map_or(GREY, |i| PALETTE[i % PALETTE.len()])
    }

    /// The resonance markers at `at` (their centres, in the order of
    /// [`Self::marks`]): majors under the minors' rings, so that none
    /// hides one.
    fn draw_markers(
        &self,
        root: &Area,
        at: &[(i32, i32)],
    ) -> Result<(), Box<dyn std::error::Error>> {
        for pass in [false, true] {
            for (m, &p) in self.marks.iter().zip(at) {
                if m.major != pass {
                    continue;
                }
                if m.major {
                    draw_marker(root, p, 0, self.mode_colour(m.mode), true, 5)?;
                    root.draw(&Circle::new(p, 5, MAJOR.stroke_width(1)))?;
                } else {
                    draw_marker(root, p, 0, self.mode_colour(m.mode), false, 3)?;
                }
            }
        }
        Ok(())
    }

    /// The order in which the resonances get their labels: the major
    /// orders' first, then by amplitude, largest first.
    fn label_order(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.marks.len()).collect();
        order.sort_by(|&a, &b| {
            let (ma, mb) = (&self.marks[a], &self.marks[b]);
            mb.major
                .cmp(&ma.major)
                .then(mb.amplitude_deg.total_cmp(&ma.amplitude_deg))
        });
        order
    }

    /// The leaders, then each placed label on its white ground (the major
    /// orders' black, the others dark grey).
    fn draw_resonance_labels(
        &self,
        root: &Area,
        placed: &[(usize, PlacedLabel)],
        leaders: &[Leader],
    ) -> Result<(), Box<dyn std::error::Error>> {
        for l in leaders {
            let mode = self.marks[l.marker].mode;
            root.draw(&PathElement::new(
                vec![l.from, l.to],
                self.mode_colour(mode).mix(0.7).stroke_width(1),
            ))?;
        }
        for (i, p) in placed {
            let g = ground(p.bounds);
            root.draw(&Rectangle::new(
                [(g.0, g.1), (g.2, g.3)],
                WHITE.mix(0.85).filled(),
            ))?;
            let color = if self.marks[*i].major {
                BLACK
            } else {
                RGBColor(70, 70, 70)
            };
            root.draw(&Text::new(
                p.text.clone(),
                (p.bounds.0, p.bounds.1 + 1),
                ("sans-serif", MARK_FONT)
                    .into_font()
                    .color(&color)
                    .pos(Pos::new(HPos::Left, VPos::Top)),
            ))?;
        }
        Ok(())
    }
}

/// A resonance label's white ground: a pixel wider than its text.
fn ground(b: Bounds) -> Bounds {
    (b.0 - 1, b.1, b.2 + 1, b.3)
}

/// Where a label's leader from the marker at `(x, y)` ends: on the
/// label's edge nearest the marker.
fn leader_end((x, y): (i32, i32), b: Bounds) -> (i32, i32) {
    (x.clamp(b.0, b.2), if b.1 > y { b.1 } else { b.3 })
}

/// The resonance labels placed so far.
#[derive(Default)]
struct Placement {
    /// The labels with their marks' indices.
    placed: Vec<(usize, PlacedLabel)>,
    /// Leaders to the labels placed further out.
    leaders: Vec<Leader>,
    /// The major resonances left without a label.
    missed: Vec<usize>,
}

/// What the resonance labels are placed among: the markers, the plot and
/// the mode lines.
struct LabelSpace<'a> {
    marks: &'a [CampbellMark],
    /// Each marker's centre (pixels).
    at: Vec<(i32, i32)>,
    /// Each marker's box as drawn (the major's ring has a 1 px stroke).
    markers: Vec<Bounds>,
    plot: Bounds,
    /// Mode lines: a label may cross one, at a cost.
    lines: Vec<Bounds>,
    /// A label's height.
    th: i32,
    /// The other orders' resonances are labelled only where they matter:
    /// a tenth of the largest resonance's amplitude or more.
    floor: f64,
}

impl<'a> LabelSpace<'a> {
    /// The markers of `marks` in pixels (`px`), the mode lines at
    /// `mode_rows` across `plot`.
    fn new(
        marks: &'a [CampbellMark],
        px: &dyn Fn(f64, f64) -> (i32, i32),
        plot: Bounds,
        mode_rows: &[i32],
    ) -> Self {
        let mut markers: Vec<Bounds> = Vec::with_capacity(marks.len());
        let mut at = Vec::with_capacity(marks.len());
        for m in marks {
            let p = px(m.rpm, m.frequency_hz);
            let r = if m.major { 6 } else { 4 };
            markers.push((p.0 - r, p.1 - r, p.0 + r, p.1 + r));
            at.push(p);
        }
        let lines = mode_rows
            .iter()
            .map(|&y| (plot.0, y - 1, plot.2, y + 1))
            .collect();
        let floor = 0.1 * marks.iter().map(|m| m.amplitude_deg).fold(0.0, f64::max);
        LabelSpace {
            marks,
            at,
            markers,
            plot,
            lines,
            th: text_height(MARK_FONT),
            floor,
        }
    }

    /// Places the labels in `order`, then again with each major resonance
    /// left without a label put first, so that crowds of markers (the low
    /// speeds of a high mode) still get every major label; the try with
    /// the fewest left out is kept.
    fn place_retrying(&self, order: &[usize]) -> Placement {
        let mut first: Vec<usize> = Vec::new();
        let mut best = self.place(order);
        for _ in 0..self.marks.len() {
            let Some(&next) = best.missed.first() else {
                break;
            };
            if first.contains(&next) {
                break;
            }
            first.push(next);
            let tried: Vec<usize> = first
                .iter()
                .copied()
                .chain(order.iter().copied().filter(|i| !first.contains(i)))
                .collect();
            let attempt = self.place(&tried);
            if attempt.missed.len() <= best.missed.len() {
                best = attempt;
            }
        }
        best
    }

    /// Places the labels in `order`, each at its cheapest free spot.
    fn place(&self, order: &[usize]) -> Placement {
        let mut done = Placement::default();
        for &i in order {
            let m = &self.marks[i];
            if !m.major && !(m.amplitude_deg >= self.floor) {
                continue;
            }
            let text = format!("{} × mode {}", human(m.order), m.mode);
            let w = text_width(&text, MARK_FONT);
            let Some((b, ring)) = self.best_spot(i, w, &done) else {
                if m.major {
                    done.missed.push(i);
                }
                continue;
            };
            if ring > 1 {
                done.leaders.push(Leader {
                    label: done.placed.len(),
                    marker: i,
                    from: self.at[i],
                    to: leader_end(self.at[i], b),
                });
            }
            done.placed.push((
                i,
                PlacedLabel {
                    text,
                    major: m.major,
                    bounds: b,
                },
            ));
        }
        done
    }

    /// The cheapest free box `w` wide for mark `i`'s label and its ring
    /// (1: beside the marker; further out, for a major order, with a
    /// leader). The cost counts the mode lines crossed, the ring and the
    /// offset from centred.
    fn best_spot(&self, i: usize, w: i32, done: &Placement) -> Option<(Bounds, i32)> {
        let (x, y) = self.at[i];
        let th = self.th;
        let rings = if self.marks[i].major { 4 } else { 1 };
        let mut best: Option<(Bounds, i64, i32)> = None;
        for ring in 1..=rings {
            let d = 6 + (ring - 1) * (th + 2);
            // Above or below the marker, from beside it on the left (the
            // label's right end on the diagonal) to beside it on the right,
            // every few pixels: the nearer to centred, the cheaper.
            let mut shifts: Vec<i32> = (0..)
                .map(|k| -w - d + 6 * k)
                .take_while(|&dx| dx <= d)
                .collect();
            shifts.extend([d, -w / 2]);
            for (dx, dy) in shifts.iter().flat_map(|&dx| [(dx, -d - th), (dx, d)]) {
                let b = (x + dx, y + dy, x + dx + w, y + dy + th);
                if !self.free(i, b, ring, done) {
                    continue;
                }
                let crossing: i64 = self.lines.iter().map(|l| overlap(*l, b) as i64).sum();
                let off = i64::from((dx + w / 2).abs() / 12);
                let cost = crossing + 40 * i64::from(ring) + off;
                if best.is_none_or(|(_, c, _)| cost < c) {
                    best = Some((b, cost, ring));
                }
            }
            // A farther ring cannot beat this one.
            if best.is_some_and(|(_, c, _)| c <= 40 * i64::from(ring + 1)) {
                break;
            }
        }
        best.map(|(b, _, ring)| (b, ring))
    }

    /// Whether box `b` is free for mark `i`'s label on `ring`: inside the
    /// plot, on no marker, [`LABEL_GAP`] from every label and on no
    /// leader; beyond the first ring its leader also passes no other
    /// marker and no other label.
    fn free(&self, i: usize, b: Bounds, ring: i32, done: &Placement) -> bool {
        if !inside(b, self.plot)
            || self.markers.iter().any(|t| overlap(*t, ground(b)) > 0)
            || done
                .placed
                .iter()
                .any(|(_, p)| overlap(inflate(p.bounds, LABEL_GAP), b) > 0)
            || done
                .leaders
                .iter()
                .any(|l| segment_hits(l.from, l.to, inflate(b, 1)))
        {
            return false;
        }
        if ring == 1 {
            return true;
        }
        let from = self.at[i];
        let end = leader_end(from, b);
        self.markers
            .iter()
            .enumerate()
            .all(|(k, t)| k == i || !segment_hits(from, end, *t))
            && done
                .placed
                .iter()
                .all(|(_, p)| !segment_hits(from, end, inflate(p.bounds, 1)))
    }
}

/// The orders with the largest peak free-end amplitude over the speeds.
fn strongest_orders(study: &Study, count: usize) -> Vec<usize> {
    let mut peak: Vec<(usize, f64)> = (0..study.orders.len())
        .map(|o| {
            let p = study
                .rows
                .iter()
                .map(|r| r.order_deg[o])
                .fold(0.0, f64::max);
            (o, p)
        })
        .collect();
    peak.sort_by(|a, b| b.1.total_cmp(&a.1));
    peak.into_iter().take(count).map(|(o, _)| o).collect()
}

/// The response chart: the free end's vibratory angle (all orders summed
/// in time, and the four strongest orders apart, major ones so named) and
/// the largest section's vibratory torque against speed.
pub fn torsion_response(name: &str, study: &Study) -> Figure {
    let rpm: Vec<f64> = study.rows.iter().map(|r| r.rpm).collect();
    let fe: Vec<f64> = study.rows.iter().map(|r| r.free_end_deg).collect();
    let mut resp = vec![Series::new(
        "all orders (half peak-to-peak)",
        rpm.iter().copied(),
        &fe,
    )];
    for o in strongest_orders(study, 4) {
        let k = study.orders[o];
        let y: Vec<f64> = study.rows.iter().map(|r| r.order_deg[o]).collect();
        let major = if is_major_order(k, study.firings_per_revolution) {
            " (major)"
        } else {
            ""
        };
        resp.push(Series::new(
            format!("order {}{major}", human(k)),
            rpm.iter().copied(),
            &y,
        ));
    }
    let tq: Vec<f64> = study
        .rows
        .iter()
        .map(|r| r.section_torque.iter().copied().fold(0.0, f64::max))
        .collect();
    Figure {
        file: "torsion.svg".into(),
        panels: vec![
            Chart {
                title: format!("{name} — free-end vibratory angle"),
                x_label: "engine speed (rpm)".into(),
                y_label: "amplitude (deg)".into(),
                series: resp,
                log: false,
                equal: false,
                angle_ticks: None,
            },
            Chart {
                title: "largest section's vibratory torque".into(),
                x_label: "engine speed (rpm)".into(),
                y_label: "torque, half peak-to-peak (N m)".into(),
                series: vec![Series::new("largest section", rpm.iter().copied(), &tq)],
                log: false,
                equal: false,
                angle_ticks: None,
            },
        ],
    }
}

/// `campbell.svg` and `torsion.svg` of a torsion study, as (file name, SVG
/// text), for `enginedyn torsion --out` and the torsion section of
/// `report.html`.
///
/// # Errors
///
/// [`ReportError::Chart`] when a chart cannot be drawn.
pub fn torsion_charts(name: &str, study: &Study) -> Result<Vec<(String, String)>, ReportError> {
    let campbell = CampbellChart::from_study(name, study);
    let response = torsion_response(name, study);
    Ok(vec![
        (campbell.file.clone(), campbell.render()?),
        (response.file.clone(), response.render()?),
    ])
}
