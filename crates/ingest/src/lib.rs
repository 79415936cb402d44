//! Indicator diagrams in: CSV text (as indicating systems, digitisers and
//! spreadsheets write it) to cylinder pressure on a uniform crank-angle grid.
//!
//! Two steps: [`parse`] reads the text into [`Diagram`] (absolute pressure in
//! Pa at cycle angles from firing TDC, one trace per measured cycle and
//! cylinder), checking every cell; [`resample`] interpolates each trace onto
//! the uniform grid with a periodic interpolant and averages the cycles.
//!
//! ```
//! use enginedyn_ingest::{parse, resample, Interp, ParseOptions};
//! let csv = "# rpm = 2000\ncrank_deg,pressure_bar\n0,40\n180,2\n360,1\n540,1\n";
//! let d = parse(csv.as_bytes(), &ParseOptions::new(720.0)).unwrap();
//! assert_eq!(d.rpm, Some(2000.0));
//! let g = resample(&d, 1.0, Interp::Linear).unwrap();
//! assert_eq!(g.pressure.len(), 720);
//! assert!((g.pressure[90] - 21e5).abs() < 1e-6); // halfway between 40 and 2 bar
//! ```

use enginedyn_numerics::{InterpKind, Periodic};
use std::io::BufRead;

/// What went wrong, with the line and column where it did (1-based).
#[derive(Debug, thiserror::Error)]
pub enum IngestError {
    /// The file could not be read.
    #[error("cannot read: {0}")]
    Io(#[from] std::io::Error),
    /// A problem at a place in the file.
    #[error("line {line}{}: {message}", column.map(|c| format!(", column {c}")).unwrap_or_default())]
    At {
        /// 1-based line.
        line: usize,
        /// 1-based column, when one cell is at fault.
        column: Option<usize>,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A problem with the data as a whole.
    #[error("{0}")]
    Data(String),
}

fn at(line: usize, column: Option<usize>, message: impl Into<String>) -> IngestError {
    IngestError::At {
        line,
        column,
        message: message.into(),
    }
}

/// How to read a diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct ParseOptions {
    /// Cycle length (deg): 720 four-stroke, 360 two-stroke.
    pub cycle_deg: f64,
    /// The file's angle value that is firing TDC.
    pub tdc_deg: f64,
    /// Pressures are gauge (relative to 1.01325 bar).
    pub gauge: bool,
    /// Column names replacing the header (`_` skips a column).
    pub columns: Option<Vec<String>>,
}

impl ParseOptions {
    /// Defaults for a cycle of `cycle_deg` degrees.
    pub fn new(cycle_deg: f64) -> Self {
        Self {
            cycle_deg,
            tdc_deg: 0.0,
            gauge: false,
            columns: None,
        }
    }
}

/// One measured trace: samples of one cycle of one cylinder.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trace {
    /// Cycle number from the `cycle` column (0 when absent).
    pub cycle: i64,
    /// Cylinder number from the `cylinder` column (0 when absent: all).
    pub cylinder: i64,
    /// Cycle angles (deg from firing TDC), strictly increasing, span < cycle.
    pub angle_deg: Vec<f64>,
    /// Absolute pressure (Pa), or torque (N m) for a turning-moment file.
    pub values: Vec<f64>,
}

/// What a diagram's values are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Quantity {
    /// Cylinder pressure (Pa, absolute).
    #[default]
    Pressure,
    /// One cylinder's torque (N m), `torque_cylinder_nm`.
    CylinderTorque,
    /// The engine's torque (N m), `torque_engine_nm`.
    EngineTorque,
}

/// A parsed diagram.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Diagram {
    /// Pressure, or torque from a turning-moment file.
    pub quantity: Quantity,
    /// Speed from a `# rpm = N` comment line.
    pub rpm: Option<f64>,
    /// Traces in file order.
    pub traces: Vec<Trace>,
    /// Cycle length (deg).
    pub cycle_deg: f64,
    /// Things worth telling the user.
    pub notes: Vec<String>,
}

/// Interpolation choice (`--interp`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interp {
    /// Linear on grid data, else spline unless it overshoots, then pchip.
    #[default]
    Auto,
    /// Periodic piecewise linear.
    Linear,
    /// Periodic cubic spline.
    Spline,
    /// Periodic monotone cubic (Fritsch–Carlson).
    Pchip,
}

impl Interp {
    /// Every choice.
    pub const ALL: [Interp; 4] = [Interp::Auto, Interp::Linear, Interp::Spline, Interp::Pchip];
    /// As on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Interp::Auto => "auto",
            Interp::Linear => "linear",
            Interp::Spline => "spline",
            Interp::Pchip => "pchip",
        }
    }
    /// Parses [`Interp::name`].
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// Pressure on the uniform grid `k * step_deg`, `k = 0..n`, from firing TDC.
#[derive(Debug, Clone, PartialEq)]
pub struct Resampled {
    /// Grid step (deg).
    pub step_deg: f64,
    /// Mean absolute pressure over the traces (Pa).
    pub pressure: Vec<f64>,
    /// Interpolant used (for `auto`, the one it chose).
    pub interp: InterpKind,
    /// Number of cycles averaged.
    pub cycles: usize,
    /// Per-cycle pressures on the grid, when more than one cycle was read.
    pub per_cycle: Vec<Vec<f64>>,
    /// Things worth telling the user.
    pub notes: Vec<String>,
}

const ATM: f64 = 101_325.0;

/// Pa per unit, from exact definitions (1 psi = 0.45359237 kg × 9.80665 m/s² / (0.0254 m)²).
pub fn pressure_unit(name: &str) -> Option<f64> {
    Some(match name {
        "pressure_bar" => 1e5,
        "pressure_mpa" => 1e6,
        "pressure_kpa" => 1e3,
        "pressure_pa" => 1.0,
        "pressure_psi" => 0.453_592_37 * 9.806_65 / (0.0254 * 0.0254),
        "pressure_kgf_cm2" => 98_066.5,
        _ => return None,
    })
}

const ANGLE: &str = "crank_deg";
const KNOWN: &[&str] = &[
    "crank_deg",
    "volume_cm3",
    "volume_m3",
    "volume_l",
    "pressure_bar",
    "pressure_mpa",
    "pressure_kpa",
    "pressure_pa",
    "pressure_psi",
    "pressure_kgf_cm2",
    "torque_cylinder_nm",
    "torque_engine_nm",
    "cycle",
    "cylinder",
    "_",
];

#[derive(Clone, Copy, PartialEq)]
enum Delim {
    Comma,
    Semicolon,
    Tab,
    Space,
}

impl Delim {
    fn detect(line: &str) -> Delim {
        if line.contains('\t') {
            Delim::Tab
        } else if line.contains(';') {
            Delim::Semicolon
        } else if line.contains(',') {
            Delim::Comma
        } else {
            Delim::Space
        }
    }
    /// Byte ranges of the cells of `line`, trimmed of ASCII white space
    /// (a reused buffer and a byte scan: no allocation per line).
    fn split(self, line: &str, out: &mut Vec<(usize, usize)>) {
        out.clear();
        let b = line.as_bytes();
        let trimmed = |mut s: usize, mut e: usize| {
            while s < e && b[s].is_ascii_whitespace() {
                s += 1;
            }
            while e > s && b[e - 1].is_ascii_whitespace() {
                e -= 1;
            }
            (s, e)
        };
        let sep = match self {
            Delim::Comma => b',',
            Delim::Semicolon => b';',
            Delim::Tab => b'\t',
            Delim::Space => {
                let mut i = 0;
                while i < b.len() {
                    while i < b.len() && b[i].is_ascii_whitespace() {
                        i += 1;
                    }
                    let s = i;
                    while i < b.len() && !b[i].is_ascii_whitespace() {
                        i += 1;
                    }
                    if i > s {
                        out.push((s, i));
                    }
                }
                return;
            }
        };
        let mut start = 0;
        for (i, &c) in b.iter().enumerate() {
            if c == sep {
                out.push(trimmed(start, i));
                start = i + 1;
            }
        }
        out.push(trimmed(start, b.len()));
    }
    /// A decimal comma is accepted where the comma is not the delimiter.
    fn decimal_comma(self) -> bool {
        self != Delim::Comma
    }
}

fn number(cell: &str, decimal_comma: bool, line: usize, col: usize) -> Result<f64, IngestError> {
    let parsed = if decimal_comma && cell.contains(',') {
        cell.replacen(',', ".", 1).parse::<f64>()
    } else if cell.as_bytes().first() == Some(&b'"') {
        cell.trim_matches('"').parse::<f64>()
    } else {
        cell.parse::<f64>()
    };
    match parsed {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(at(line, Some(col), format!("{v} is not a finite number"))),
        Err(_) => Err(at(line, Some(col), format!("`{cell}` is not a number"))),
    }
}

fn parse_rpm(comment: &str) -> Option<f64> {
    let c = comment.trim_start_matches('#').trim();
    let rest = c.strip_prefix("rpm")?.trim_start();
    let rest = rest.strip_prefix('=').or_else(|| rest.strip_prefix(':'))?;
    rest.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| *v > 0.0 && v.is_finite())
}

/// Reads a p–φ diagram from CSV text.
pub fn parse(reader: impl BufRead, opts: &ParseOptions) -> Result<Diagram, IngestError> {
    let mut d = Diagram {
        cycle_deg: opts.cycle_deg,
        ..Diagram::default()
    };
    let mut names: Option<Vec<String>> = opts.columns.clone();
    let mut header_from_file = false;
    let mut delim = None;
    let mut spans: Vec<(usize, usize)> = Vec::new();
    let (mut i_angle, mut i_p, mut i_cycle, mut i_cyl) = (0, 0, None, None);
    let mut scale = 1e5;
    let mut have_cols = false;
    let mut current: Option<Trace> = None;
    let mut rows = 0usize;
    let mut buf = String::new();
    let mut reader = reader;
    let mut lineno = 0;
    loop {
        buf.clear();
        if reader.read_line(&mut buf)? == 0 {
            break;
        }
        lineno += 1;
        // A byte-order mark may open the file; ASCII trimming is all a line needs.
        let line = buf.strip_prefix('\u{feff}').unwrap_or(&buf);
        let t = line.trim_ascii();
        if t.is_empty() {
            continue;
        }
        if t.starts_with('#') {
            if let Some(r) = parse_rpm(t) {
                d.rpm = Some(r);
            }
            continue;
        }
        let dl = *delim.get_or_insert_with(|| Delim::detect(t));
        dl.split(t, &mut spans);
        let cell = |i: usize| &t[spans[i].0..spans[i].1];
        let undecided = !header_from_file && rows == 0 && current.is_none();
        let first_is_number =
            || !spans.is_empty() && number(cell(0), dl.decimal_comma(), 0, 0).is_ok();
        if undecided && !first_is_number() {
            // A header row: it names the columns unless --columns replaces them.
            header_from_file = true;
            if names.is_none() {
                names = Some(
                    (0..spans.len())
                        .map(|i| cell(i).trim_matches('"').to_ascii_lowercase())
                        .collect(),
                );
            }
            let n = names.as_ref().map(Vec::len).unwrap_or(0);
            if n != spans.len() && opts.columns.is_some() {
                return Err(at(
                    lineno,
                    None,
                    format!(
                        "--columns names {n} columns, the header has {}",
                        spans.len()
                    ),
                ));
            }
            if let Some(n) = names.as_ref() {
                (i_angle, i_p, i_cycle, i_cyl, scale, d.quantity) = columns(n, lineno)?;
                have_cols = true;
            }
            continue;
        }
        if !have_cols {
            let Some(n) = names.as_ref() else {
                return Err(at(
                    lineno,
                    None,
                    "no header row: name the columns with --columns crank_deg,pressure_bar (or add a header)",
                ));
            };
            (i_angle, i_p, i_cycle, i_cyl, scale, d.quantity) = columns(n, lineno)?;
            have_cols = true;
        }
        let ncols = names.as_ref().map(Vec::len).unwrap_or(0);
        if spans.len() < ncols {
            return Err(at(
                lineno,
                None,
                format!("{} cells, the header names {ncols}", spans.len()),
            ));
        }
        let dc = dl.decimal_comma();
        let angle = number(cell(i_angle), dc, lineno, i_angle + 1)?;
        let p_raw = number(cell(i_p), dc, lineno, i_p + 1)?;
        let cyc = match i_cycle {
            Some(i) => number(cell(i), dc, lineno, i + 1)? as i64,
            None => 0,
        };
        let cyl = match i_cyl {
            Some(i) => number(cell(i), dc, lineno, i + 1)? as i64,
            None => 0,
        };
        let is_pressure = d.quantity == Quantity::Pressure;
        let p = p_raw * scale + if opts.gauge && is_pressure { ATM } else { 0.0 };
        if is_pressure && p < 0.0 {
            return Err(at(
                lineno,
                Some(i_p + 1),
                format!(
                    "negative absolute pressure ({p_raw}){}",
                    if opts.gauge {
                        ""
                    } else {
                        ": if the trace is gauge pressure, give --gauge"
                    }
                ),
            ));
        }
        let a = angle - opts.tdc_deg;
        match current.as_mut() {
            Some(tr) if tr.cycle == cyc && tr.cylinder == cyl => {
                let last = *tr.angle_deg.last().unwrap_or(&f64::NEG_INFINITY);
                let first = tr.angle_deg[0];
                if a <= last {
                    return Err(at(
                        lineno,
                        Some(i_angle + 1),
                        format!(
                            "angle {angle} does not rise after {}: angles must increase within a cycle",
                            last + opts.tdc_deg
                        ),
                    ));
                }
                if a - first >= opts.cycle_deg - 1e-9 {
                    if (a - first - opts.cycle_deg).abs() < 1e-9 {
                        // A digitised cycle repeating its first angle at the end.
                        continue;
                    }
                    return Err(at(
                        lineno,
                        Some(i_angle + 1),
                        format!(
                            "angle {angle} lies more than one {}° cycle after the first ({}); \
                             give a `cycle` column to separate cycles",
                            opts.cycle_deg,
                            first + opts.tdc_deg
                        ),
                    ));
                }
                tr.angle_deg.push(a);
                tr.values.push(p);
            }
            _ => {
                if let Some(tr) = current.take() {
                    d.traces.push(finish(tr, opts.cycle_deg)?);
                }
                current = Some(Trace {
                    cycle: cyc,
                    cylinder: cyl,
                    angle_deg: vec![a],
                    values: vec![p],
                });
            }
        }
        rows += 1;
    }
    if let Some(tr) = current.take() {
        d.traces.push(finish(tr, opts.cycle_deg)?);
    }
    if d.traces.is_empty() {
        return Err(IngestError::Data("no data rows".into()));
    }
    let peak = d
        .traces
        .iter()
        .flat_map(|t| t.values.iter())
        .fold(0.0_f64, |a, &b| a.max(b));
    // 5 kPa to 10 kbar absolute: anything outside is a unit mix-up.
    if d.quantity == Quantity::Pressure && !(5e3..=1e9).contains(&peak) {
        return Err(IngestError::Data(format!(
            "peak pressure {:.3e} bar is implausible: is the pressure column's unit right?",
            peak / 1e5
        )));
    }
    Ok(d)
}

/// Column indices of angle, value, cycle, cylinder, the unit factor and what the value is.
type Cols = (usize, usize, Option<usize>, Option<usize>, f64, Quantity);

fn columns(names: &[String], line: usize) -> Result<Cols, IngestError> {
    for (i, n) in names.iter().enumerate() {
        if !KNOWN.contains(&n.as_str()) {
            let hint = KNOWN
                .iter()
                .filter(|k| **k != "_")
                .max_by(|a, b| similarity(n, a).total_cmp(&similarity(n, b)))
                .map(|k| format!("; did you mean `{k}`?"))
                .unwrap_or_default();
            return Err(at(
                line,
                Some(i + 1),
                format!(
                    "unknown column `{n}`{hint} (known: {}; `_` skips a column)",
                    KNOWN[..KNOWN.len() - 1].join(", ")
                ),
            ));
        }
    }
    let find = |k: &str| names.iter().position(|n| n == k);
    let Some(i_angle) = find(ANGLE) else {
        if names.iter().any(|n| n.starts_with("volume_")) {
            return Err(at(
                line,
                None,
                "p–V data (a volume column) is not read yet: give crank_deg",
            ));
        }
        return Err(at(line, None, "no `crank_deg` column"));
    };
    let torque = names
        .iter()
        .enumerate()
        .find_map(|(i, n)| match n.as_str() {
            "torque_cylinder_nm" => Some((i, Quantity::CylinderTorque)),
            "torque_engine_nm" => Some((i, Quantity::EngineTorque)),
            _ => None,
        });
    if let Some((i, q)) = torque {
        return Ok((i_angle, i, find("cycle"), find("cylinder"), 1.0, q));
    }
    let Some((i_p, scale)) = names
        .iter()
        .enumerate()
        .find_map(|(i, n)| pressure_unit(n).map(|s| (i, s)))
    else {
        return Err(at(
            line,
            None,
            "no pressure column (pressure_bar, pressure_mpa, pressure_kpa, pressure_pa, pressure_psi or pressure_kgf_cm2)",
        ));
    };
    Ok((
        i_angle,
        i_p,
        find("cycle"),
        find("cylinder"),
        scale,
        Quantity::Pressure,
    ))
}

fn similarity(a: &str, b: &str) -> f64 {
    // Shared prefix length, then length difference: enough to point at a typo.
    let common = a.chars().zip(b.chars()).take_while(|(x, y)| x == y).count();
    common as f64 - 0.01 * (a.len() as f64 - b.len() as f64).abs()
}

/// Moves a trace's angles into [0, cycle), rotating so they rise, and checks coverage.
fn finish(mut tr: Trace, cycle: f64) -> Result<Trace, IngestError> {
    let n = tr.angle_deg.len();
    if n < 4 {
        return Err(IngestError::Data(format!(
            "cycle {} has {n} points: at least 4 are needed",
            tr.cycle
        )));
    }
    let first = tr.angle_deg[0];
    let span = tr.angle_deg[n - 1] - first;
    let mut gaps: Vec<f64> = tr.angle_deg.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.sort_by(f64::total_cmp);
    let median = gaps[gaps.len() / 2];
    let wrap_gap = cycle - span;
    if wrap_gap > (3.0 * median).max(1.0) + 1e-9 {
        return Err(IngestError::Data(format!(
            "cycle {} covers {:.2}° to {:.2}° only, not the full {cycle}° cycle (a gap of {wrap_gap:.2}° where steps are {median:.3}°)",
            tr.cycle,
            first,
            first + span
        )));
    }
    let wrapped: Vec<f64> = tr.angle_deg.iter().map(|a| a.rem_euclid(cycle)).collect();
    let start = (0..n)
        .min_by(|&i, &j| wrapped[i].total_cmp(&wrapped[j]))
        .unwrap_or(0);
    tr.angle_deg = wrapped[start..]
        .iter()
        .chain(&wrapped[..start])
        .copied()
        .collect();
    tr.values.rotate_left(start);
    Ok(tr)
}

/// Resamples every trace onto the grid `k * step_deg` over the cycle and
/// averages them (one trace for all cylinders; per-cylinder traces later).
pub fn resample(d: &Diagram, step_deg: f64, interp: Interp) -> Result<Resampled, IngestError> {
    let cycle = d.cycle_deg;
    let n = (cycle / step_deg).round() as usize;
    if !(step_deg > 0.0) || n < 8 || ((n as f64) * step_deg - cycle).abs() > 1e-9 * cycle {
        return Err(IngestError::Data(format!(
            "grid step {step_deg}° must divide the {cycle}° cycle into at least 8 steps"
        )));
    }
    let mut notes = Vec::new();
    let mut sum = vec![0.0; n];
    let mut per_cycle = Vec::new();
    let mut used = None;
    let mut buf = vec![0.0; n];
    for tr in &d.traces {
        let kind = choose(tr, step_deg, n, interp, &mut notes)?;
        let f = Periodic::new(kind, &tr.angle_deg, &tr.values, cycle)
            .map_err(|e| IngestError::Data(format!("cycle {}: {e}", tr.cycle)))?;
        f.eval_uniform(0.0, step_deg, &mut buf);
        let pressure = d.quantity == Quantity::Pressure;
        if let Some(k) = buf
            .iter()
            .position(|p| !p.is_finite() || (pressure && *p < 0.0))
        {
            return Err(IngestError::Data(format!(
                "cycle {}: the {} interpolant gives {} Pa at {}°; use --interp pchip",
                tr.cycle,
                kind.name(),
                buf[k],
                k as f64 * step_deg
            )));
        }
        for (s, p) in sum.iter_mut().zip(&buf) {
            *s += p;
        }
        if d.traces.len() > 1 {
            per_cycle.push(buf.clone());
        }
        used.get_or_insert(kind);
    }
    let m = d.traces.len() as f64;
    for s in &mut sum {
        *s /= m;
    }
    notes.dedup();
    Ok(Resampled {
        step_deg,
        pressure: sum,
        interp: used.unwrap_or(InterpKind::Linear),
        cycles: d.traces.len(),
        per_cycle,
        notes,
    })
}

fn choose(
    tr: &Trace,
    step: f64,
    n: usize,
    interp: Interp,
    notes: &mut Vec<String>,
) -> Result<InterpKind, IngestError> {
    Ok(match interp {
        Interp::Linear => InterpKind::Linear,
        Interp::Spline => InterpKind::Spline,
        Interp::Pchip => InterpKind::Pchip,
        Interp::Auto => {
            let on_grid = tr.angle_deg.len() == n
                && tr
                    .angle_deg
                    .iter()
                    .enumerate()
                    .all(|(k, a)| (a - k as f64 * step).abs() < 1e-9);
            if on_grid {
                InterpKind::Linear
            } else {
                let s = Periodic::new(
                    InterpKind::Spline,
                    &tr.angle_deg,
                    &tr.values,
                    step * n as f64,
                )
                .map_err(|e| IngestError::Data(e.to_string()))?;
                let peak = tr.values.iter().fold(0.0_f64, |a, &b| a.max(b.abs()));
                if s.max_overshoot() > 0.005 * peak {
                    notes.push(format!(
                        "the periodic spline overshoots the data by {:.2} % of the peak: pchip used instead",
                        100.0 * s.max_overshoot() / peak
                    ));
                    InterpKind::Pchip
                } else {
                    InterpKind::Spline
                }
            }
        }
    })
}
