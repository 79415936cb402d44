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

use enginedyn_kinematics::Cylinder;
use std::io::BufRead;

mod grid;
mod pv;
mod template;
use template::{ROW, Template};

/// Exact powers of ten: a decimal of at most 15 digits is an exact integer
/// over one of these, so one division rounds it correctly (Clinger).
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// The value of a plain decimal from its digits: `m` (at most 15 digits
/// in all, the caller has counted them) with `frac` of them after the
/// point, negated for `neg`. `m < 10^15 < 2^53` is exact as an i64 (one
/// instruction, where u64 takes several) and as an f64; the one division
/// by an exact power of ten then rounds correctly (Clinger's fast path, the
/// value `str::parse` gives), and is skipped for integers. Every fast
/// reader of decimals (`plain_row`, `fast_decimal`, the row templates)
/// ends here.
#[inline(always)]
fn decimal_value(m: u64, frac: usize, neg: bool) -> f64 {
    let x = m as i64 as f64;
    let v = if frac == 0 { x } else { x / POW10[frac & 15] };
    if neg { -v } else { v }
}
pub use grid::{Accumulator, CycleStats, GridOptions, Peg, PegReport, Resampled, mean_std};

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

/// A number from a cell as a message quotes it: every digit it holds
/// (`4294967296`, `1.5`), never rounded to fewer.
fn shown_number(x: f64) -> String {
    enginedyn_numerics::format::csv(x)
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
    /// The volume law, needed for p–V data.
    pub cylinder: Option<Cylinder>,
    /// p–V data starts at the BDC before firing TDC (`--pv-start bdc`).
    pub pv_start_bdc: bool,
    /// The highest cylinder number a `cylinder` column may hold (the
    /// engine's cylinder count; 24, the most an engine file allows, when
    /// not known).
    pub max_cylinder: usize,
}

/// The most cylinders an engine file allows (INTERFACE.md).
pub const MAX_CYLINDERS: usize = 24;

/// The largest cycle number a `cycle` column may hold: every whole number
/// up to it is an exact `f64`.
pub const MAX_CYCLE: f64 = 9_007_199_254_740_992.0;

impl ParseOptions {
    /// Defaults for a cycle of `cycle_deg` degrees.
    pub fn new(cycle_deg: f64) -> Self {
        Self {
            cycle_deg,
            tdc_deg: 0.0,
            gauge: false,
            columns: None,
            cylinder: None,
            pv_start_bdc: false,
            max_cylinder: MAX_CYLINDERS,
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
    /// True for p–V data.
    pub pv: bool,
    /// Things worth telling the user.
    pub notes: Vec<String>,
}

impl Diagram {
    /// The cycles of each cylinder averaged into one trace per cylinder,
    /// when they share their angles (a multi-cycle file from an indicating
    /// system). Averaging first and interpolating after equals the reverse
    /// for the linear interpolants (linear, spline) and nearly so for pchip;
    /// `None` when the angles differ between cycles or there is one trace
    /// per cylinder already.
    pub fn averaged(&self) -> Option<Diagram> {
        let mut out: Vec<(Trace, usize)> = Vec::new();
        for t in &self.traces {
            match out.iter_mut().find(|(a, _)| a.cylinder == t.cylinder) {
                Some((a, n)) => {
                    if a.angle_deg.len() != t.angle_deg.len()
                        || a.angle_deg
                            .iter()
                            .zip(&t.angle_deg)
                            .any(|(x, y)| (x - y).abs() > 1e-9)
                    {
                        return None;
                    }
                    for (s, v) in a.values.iter_mut().zip(&t.values) {
                        *s += v;
                    }
                    *n += 1;
                }
                None => out.push((t.clone(), 1)),
            }
        }
        if out.len() == self.traces.len() {
            return None;
        }
        Some(Diagram {
            traces: out
                .into_iter()
                .map(|(mut t, n)| {
                    t.values.iter_mut().for_each(|v| *v /= n as f64);
                    t
                })
                .collect(),
            quantity: self.quantity,
            rpm: self.rpm,
            cycle_deg: self.cycle_deg,
            pv: self.pv,
            notes: Vec::new(),
        })
    }
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
    fn detect(line: &[u8]) -> Delim {
        if line.contains(&b'\t') {
            Delim::Tab
        } else if line.contains(&b';') {
            Delim::Semicolon
        } else if line.contains(&b',') {
            Delim::Comma
        } else {
            Delim::Space
        }
    }
    /// Byte ranges of the cells of `line`, trimmed of ASCII white space
    /// (a reused buffer and a byte scan: no allocation per line).
    fn split(self, line: &[u8], out: &mut Vec<(usize, usize)>) {
        out.clear();
        let b = line;
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
    /// The one-byte separator, `None` for runs of white space.
    fn byte(self) -> Option<u8> {
        match self {
            Delim::Comma => Some(b','),
            Delim::Semicolon => Some(b';'),
            Delim::Tab => Some(b'\t'),
            Delim::Space => None,
        }
    }
}

/// Most cells a row may have for the one-pass path of [`plain_row`].
const PLAIN_CELLS: usize = 8;

/// One pass over a row of plain decimals (`-12.5`, at most 15 digits, `sep`
/// between cells, nothing else) at the start of `b`, up to and with its
/// `\n` (or `\r\n`; the end of `b` ends the row only when `b` ends the
/// file, `eof`): the number of cells (values in `out`) and of bytes used.
/// Any other row (white space, quotes, exponents, too many cells, a comment)
/// gives `None` and takes the general path, which also reports errors;
/// where both apply they give the same values as [`fast_decimal`] and
/// `str::parse`.
#[inline(always)]
fn plain_row(
    b: &[u8],
    sep: u8,
    decimal_comma: bool,
    eof: bool,
    out: &mut [f64; PLAIN_CELLS],
) -> Option<(usize, usize)> {
    let (mut i, mut n) = (0usize, 0usize);
    loop {
        let neg = match b.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            _ => false,
        };
        // Integer digits, then an optional point and fraction digits; the
        // counts come from positions, so the digit loops do nothing else.
        let mut m = 0u64;
        let s = i;
        i = digit_run(b, i, &mut m);
        let int_digits = i - s;
        let mut frac = 0;
        if let Some(&c) = b.get(i)
            && (c == b'.' || (decimal_comma && c == b','))
        {
            i += 1;
            let f = i;
            i = digit_run(b, i, &mut m);
            frac = i - f;
        }
        let digits = int_digits + frac;
        if digits == 0 || digits > 15 {
            return None;
        }
        out[n & (PLAIN_CELLS - 1)] = decimal_value(m, frac, neg);
        n += 1;
        match b.get(i) {
            None if eof => return Some((n, i)),
            Some(b'\n') => return Some((n, i + 1)),
            Some(b'\r') if b.get(i + 1) == Some(&b'\n') => return Some((n, i + 2)),
            Some(&c) if c == sep && n < PLAIN_CELLS => i += 1,
            _ => return None,
        }
    }
}

/// The tight loop of [`parse_stream`]: plain rows of `w` that continue
/// trace `tr` (same cycle and cylinder, rising angle within one cycle, no
/// negative pressure) are appended to it; returns the bytes and rows used.
/// It stops at the first row that does anything else, which the general
/// path then reads exactly as it would have without this loop. A row that
/// repeats the one before but for the angle's step is checked against a
/// [`Template`] (one comparison for the cells before the value) and only
/// its value is read; others are read by [`plain_row`] and may seed the
/// next template. Its own function, so that its few variables live in
/// registers.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn continue_trace(
    w: &[u8],
    eof: bool,
    sep: u8,
    ncols: usize,
    cols: &Cols,
    opts: &ParseOptions,
    offset: f64,
    tr: &mut Trace,
) -> (usize, usize) {
    let mut vals = [0.0; PLAIN_CELLS];
    let is_pressure = cols.quantity == Quantity::Pressure;
    let (x, value, scale) = (cols.x, cols.value, cols.scale);
    let (tdc, cycle) = (opts.tdc_deg, opts.cycle_deg - 1e-9);
    let decimal_comma = sep != b',';
    let first = tr.angle_deg[0];
    let mut last = *tr.angle_deg.last().unwrap_or(&first);
    let (mut used, mut n) = (0, 0);
    // Templates (template.rs) need the value last, after cells that are
    // cycle, cylinder or the angle only.
    let templates = value + 1 == ncols
        && (0..value).all(|i| i == x || cols.cycle == Some(i) || cols.cylinder == Some(i));
    let mut template: Option<Template> = None;
    // Rows to wait before seeding again after a template that read nothing.
    let mut backoff = 0usize;
    while eof || used + 512 < w.len() {
        if let Some(t) = template.as_mut() {
            if let Some(row) = w
                .get(used..used + ROW)
                .and_then(|r| <&[u8; ROW]>::try_from(r).ok())
                && let Some((x_raw, v, len)) = t.next(row, decimal_comma)
            {
                let a = x_raw - tdc;
                let p = v * scale + offset;
                if (is_pressure && p < 0.0) || a <= last || a - first >= cycle {
                    break;
                }
                tr.angle_deg.push(a);
                tr.values.push(p);
                last = a;
                used += len;
                n += 1;
                continue;
            }
            if t.rows == 0 {
                backoff = 32;
            }
            template = None;
        }
        let Some((k, len)) = plain_row(&w[used..], sep, decimal_comma, eof, &mut vals) else {
            break;
        };
        let same = k >= ncols
            // Exactly the trace's numbers: `1.5` after `1` is not cylinder 1
            // (the general path says why).
            && cols.cycle.is_none_or(|i| vals[i].to_bits() == (tr.cycle as f64).to_bits())
            && cols.cylinder.is_none_or(|i| vals[i].to_bits() == (tr.cylinder as f64).to_bits());
        let a = vals[x] - tdc;
        let p = vals[value] * scale + offset;
        if !same || (is_pressure && p < 0.0) || a <= last || a - first >= cycle {
            break;
        }
        if templates {
            if backoff == 0 {
                template = Template::seed(&w[used..used + len], sep, x, value, a - last);
            } else {
                backoff -= 1;
            }
        }
        tr.angle_deg.push(a);
        tr.values.push(p);
        last = a;
        used += len;
        n += 1;
    }
    (used, n)
}

/// Reads the decimal digits of `b` from `i` into `m` (`m = 10 m + d` for
/// each); returns the index after the last digit. `m` wraps beyond 19
/// digits, which the caller rejects by counting them. (Eight digits at a
/// time by SWAR was tried: fewer instructions, but slower on these short
/// numbers.)
#[inline(always)]
fn digit_run(b: &[u8], mut i: usize, m: &mut u64) -> usize {
    while i < b.len() {
        let d = b[i].wrapping_sub(b'0');
        if d >= 10 {
            break;
        }
        *m = m.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    i
}

/// The longest line read (bytes): 1 MiB (INTERFACE.md, "Bounds").
pub const MAX_LINE: usize = 1 << 20;

/// The error a line longer than [`MAX_LINE`] gives.
#[derive(Debug)]
struct LineTooLong;

impl std::fmt::Display for LineTooLong {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("longer than 1 MiB with no line end")
    }
}

impl std::error::Error for LineTooLong {}

/// Lines of a reader as byte slices, read in large blocks (no per-line
/// allocation or UTF-8 check; cells are checked where they are used).
struct Lines<R> {
    reader: R,
    buf: Vec<u8>,
    start: usize,
    end: usize,
    eof: bool,
}

impl<R: std::io::Read> Lines<R> {
    fn new(reader: R) -> Self {
        Self {
            reader,
            buf: vec![0; 1 << 16],
            start: 0,
            end: 0,
            eof: false,
        }
    }

    /// The unread bytes: at least 4 KiB (longer than any plain row) unless
    /// the file ends first, and whether it does.
    #[inline(always)]
    fn window(&mut self) -> std::io::Result<(&[u8], bool)> {
        if !self.eof && self.end - self.start < 4096 {
            self.refill()?;
        }
        Ok((&self.buf[self.start..self.end], self.eof))
    }

    #[cold]
    fn refill(&mut self) -> std::io::Result<()> {
        while !self.eof && self.end - self.start < 4096 {
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.start = 0;
            match self.reader.read(&mut self.buf[self.end..]) {
                Ok(0) => self.eof = true,
                Ok(k) => self.end += k,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        Ok(())
    }

    /// Marks `k` bytes of [`Self::window`] read.
    #[inline]
    fn consume(&mut self, k: usize) {
        self.start += k;
    }

    /// The next line without its `\n`, or `None` at the end.
    fn next_line(&mut self) -> std::io::Result<Option<&[u8]>> {
        loop {
            if let Some(k) = memchr::memchr(b'\n', &self.buf[self.start..self.end]) {
                let s = self.start;
                self.start += k + 1;
                return Ok(Some(&self.buf[s..s + k]));
            }
            if self.eof {
                if self.start < self.end {
                    let s = self.start;
                    self.start = self.end;
                    return Ok(Some(&self.buf[s..self.end]));
                }
                return Ok(None);
            }
            // Keep the partial line, make room, read more.
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.start = 0;
            if self.end == self.buf.len() {
                // A line is bounded: past it the file is not a diagram
                // (a binary file, /dev/zero), and holding it would grow
                // without bound.
                if self.buf.len() > MAX_LINE {
                    return Err(std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        LineTooLong,
                    ));
                }
                let grown = (self.buf.len() * 2).min(MAX_LINE + 1);
                self.buf.resize(grown, 0);
            }
            match self.reader.read(&mut self.buf[self.end..]) {
                Ok(0) => self.eof = true,
                Ok(k) => self.end += k,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
}

/// Clinger's fast path: a plain decimal of at most 15 digits is an exact
/// integer over an exact power of ten, so one division rounds it correctly
/// (the same value `str::parse` gives). Anything else returns `None`.
#[inline]
fn fast_decimal(b: &[u8]) -> Option<f64> {
    let (neg, b) = match b.first() {
        Some(b'-') => (true, &b[1..]),
        Some(b'+') => (false, &b[1..]),
        _ => (false, b),
    };
    if b.is_empty() || b.len() > 16 {
        return None;
    }
    let (mut m, mut digits, mut frac, mut dot) = (0u64, 0usize, 0usize, false);
    for &c in b {
        match c {
            b'0'..=b'9' => {
                m = m * 10 + u64::from(c - b'0');
                digits += 1;
                frac += usize::from(dot);
            }
            b'.' if !dot => dot = true,
            _ => return None,
        }
    }
    if digits == 0 || digits > 15 {
        return None;
    }
    Some(decimal_value(m, frac, neg))
}

fn number(cell: &[u8], decimal_comma: bool, line: usize, col: usize) -> Result<f64, IngestError> {
    if let Some(v) = fast_decimal(cell) {
        return Ok(v);
    }
    let Ok(cell) = std::str::from_utf8(cell) else {
        return Err(at(
            line,
            Some(col),
            format!(
                "`{}` is not a number",
                enginedyn_numerics::format::quote(&String::from_utf8_lossy(cell))
            ),
        ));
    };
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
        Err(_) => Err(at(
            line,
            Some(col),
            format!(
                "`{}` is not a number",
                enginedyn_numerics::format::quote(cell)
            ),
        )),
    }
}

/// The speed a comment line gives: `None` when the comment is not a speed
/// line (`# rpm = N` or `# rpm: N`, any case), an error when it is one
/// whose value is not a positive number. Text after the number (a unit) is
/// ignored, and so are delimiters at the end of the line. A comma inside
/// the number is refused: `1,800` may be a thousands separator or a
/// decimal comma, and either reading would go unnoticed.
fn parse_rpm(comment: &str) -> Option<Result<f64, String>> {
    // A spreadsheet export closes the line with empty cells: `# rpm = 2200,,`.
    let c = comment
        .trim_start_matches('#')
        .trim_end_matches([',', ';', '\t', ' '])
        .trim();
    let rest = c
        .get(..3)
        .filter(|k| k.eq_ignore_ascii_case("rpm"))
        .map(|_| c[3..].trim_start())?;
    let rest = rest.strip_prefix('=').or_else(|| rest.strip_prefix(':'))?;
    let value = rest.split_whitespace().next().unwrap_or("");
    let hint = if value.contains(',') {
        " (write 1800 or 1800.5: a comma may be a decimal or a thousands separator)"
    } else {
        ""
    };
    use enginedyn_kinematics::{MAX_RPM, MIN_RPM};
    Some(match value.parse::<f64>() {
        Ok(v) if (MIN_RPM..=MAX_RPM).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{}`: the speed must be a number of rpm from 0.001 to 100000{hint}",
            enginedyn_numerics::format::quote(comment.trim())
        )),
    })
}

/// What a file says about itself besides its traces.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Header {
    /// Pressure, or torque from a turning-moment file.
    pub quantity: Quantity,
    /// Speed from a `# rpm = N` comment line.
    pub rpm: Option<f64>,
    /// True for p–V data.
    pub pv: bool,
    /// Things worth telling the user.
    pub notes: Vec<String>,
}

/// Reads a diagram (p–φ, p–V or turning moment) into memory: every trace.
pub fn parse(reader: impl BufRead, opts: &ParseOptions) -> Result<Diagram, IngestError> {
    let mut traces = Vec::new();
    let h = parse_stream(reader, opts, |t| {
        traces.push(t.trace);
        Ok(())
    })?;
    Ok(Diagram {
        quantity: h.quantity,
        rpm: h.rpm,
        traces,
        cycle_deg: opts.cycle_deg,
        pv: h.pv,
        notes: h.notes,
    })
}

/// Reads a diagram and puts it on the grid as it streams: memory is bounded
/// by one cycle, whatever the file's length.
pub fn load(
    reader: impl BufRead,
    opts: &ParseOptions,
    grid: &GridOptions,
) -> Result<Resampled, IngestError> {
    let mut unused = std::time::Duration::ZERO;
    load_timed(reader, opts, grid, &mut unused)
}

/// [`load`], adding to `on_grid` the time spent after the reader hands each
/// trace over: putting it on the grid, its checks and statistics, and the
/// averages at the end. What is left of the whole call is the reading and
/// parsing (how `enginedyn batch` tells the compute stages from the parse).
pub fn load_timed(
    reader: impl BufRead,
    opts: &ParseOptions,
    grid: &GridOptions,
    on_grid: &mut std::time::Duration,
) -> Result<Resampled, IngestError> {
    let mut acc: Option<Accumulator> = None;
    let h = parse_stream(reader, opts, |t| {
        let started = std::time::Instant::now();
        if acc.is_none() {
            acc = Some(Accumulator::new(grid.clone(), opts.cycle_deg, t.quantity)?);
        }
        let added = match acc.as_mut() {
            Some(a) => a.add_with_steps(&t.trace, t.steps),
            None => Ok(()),
        };
        *on_grid += started.elapsed();
        added
    })?;
    let started = std::time::Instant::now();
    let resampled = match acc {
        Some(a) => {
            let pv = h.pv;
            a.finish(h.rpm, h.notes).map(|mut r| {
                r.pv = pv;
                r
            })
        }
        None => Err(IngestError::Data("no data rows".into())),
    };
    *on_grid += started.elapsed();
    resampled
}

/// Puts an in-memory diagram on the grid (the same path as [`load`]).
pub fn resample(d: &Diagram, step_deg: f64, interp: Interp) -> Result<Resampled, IngestError> {
    resample_with(d, &GridOptions::new(step_deg, interp))
}

/// [`resample`] with pegging and the volume law.
pub fn resample_with(d: &Diagram, grid: &GridOptions) -> Result<Resampled, IngestError> {
    let mut acc = Accumulator::new(grid.clone(), d.cycle_deg, d.quantity)?;
    for t in &d.traces {
        acc.add(t)?;
    }
    let mut r = acc.finish(d.rpm, d.notes.clone())?;
    r.pv = d.pv;
    Ok(r)
}

/// A finished trace and what its values are.
pub struct Streamed {
    /// The trace, angles in `[0, cycle)`.
    pub trace: Trace,
    /// What its values are.
    pub quantity: Quantity,
    /// The smallest and largest step between successive angles (deg) of
    /// `trace` as handed over, when the reader's checks measured them (not
    /// after wrapping into the cycle): lets [`Accumulator::add_with_steps`]
    /// see that a trace lies on the grid without comparing every angle.
    pub steps: Option<(f64, f64)>,
}

/// Reads the text and hands each finished trace to `sink`, in file order.
pub fn parse_stream(
    reader: impl BufRead,
    opts: &ParseOptions,
    mut sink: impl FnMut(Streamed) -> Result<(), IngestError>,
) -> Result<Header, IngestError> {
    let mut head = Header::default();
    let mut names: Option<Vec<String>> = opts.columns.clone();
    let mut header_from_file = false;
    let mut delim = None;
    let mut spans: Vec<(usize, usize)> = Vec::new();
    let mut cols = Cols::default();
    let mut have_cols = false;
    let mut current: Option<Trace> = None;
    let mut current_line = 0usize;
    let mut auto_cycle = 0i64;
    let mut rows = 0usize;
    let mut lines = Lines::new(reader);
    let mut lineno = 0;
    let mut pv_notes = Vec::new();
    let mut vals = [0.0; PLAIN_CELLS];
    let mut last_len = 0usize;
    let mut emit = |tr: Trace, line: usize, q: Quantity, is_pv: bool| -> Result<(), IngestError> {
        let tr = if is_pv {
            let cyl = opts.cylinder.as_ref().ok_or_else(|| {
                IngestError::Data("p–V data needs the engine's volume law".into())
            })?;
            pv::to_angles(
                tr,
                cyl,
                opts.cycle_deg,
                opts.pv_start_bdc,
                line,
                &mut pv_notes,
            )?
        } else {
            tr
        };
        let (tr, steps) = finish(tr, opts.cycle_deg, q)?;
        sink(Streamed {
            trace: tr,
            quantity: q,
            steps,
        })
    };
    loop {
        // Runs of plain rows that continue the current p–φ trace: a tight
        // loop over the read buffer. Any other row (a new cycle or cylinder,
        // a falling angle, anything unusual) leaves it for the general path
        // below, which decides exactly as it would have without this loop.
        if let (Some(sep), true, false, Some(tr)) = (
            delim.and_then(Delim::byte),
            have_cols,
            cols.pv,
            current.as_mut(),
        ) {
            let ncols = names.as_ref().map(Vec::len).unwrap_or(0);
            let offset = if opts.gauge && cols.quantity == Quantity::Pressure {
                ATM
            } else {
                0.0
            };
            let (w, eof) = lines.window()?;
            let (used, n) = continue_trace(w, eof, sep, ncols, &cols, opts, offset, tr);
            lineno += n;
            rows += n;
            lines.consume(used);
        }
        // Plain rows straight from the read buffer: no line search, one pass.
        let fast = match delim.and_then(Delim::byte) {
            Some(sep) if have_cols => {
                let ncols = names.as_ref().map(Vec::len).unwrap_or(0);
                let dc = sep != b',';
                let (w, eof) = lines.window()?;
                plain_row(w, sep, dc, eof, &mut vals)
                    .filter(|&(k, _)| k >= ncols)
                    .map(|(_, used)| used)
            }
            _ => None,
        };
        let (x_raw, p_raw, cyc_raw, cyl_raw) = if let Some(used) = fast {
            lines.consume(used);
            lineno += 1;
            (
                vals[cols.x],
                vals[cols.value],
                cols.cycle.map(|i| vals[i]),
                cols.cylinder.map(|i| vals[i]),
            )
        } else {
            let raw = match lines.next_line() {
                Ok(raw) => raw,
                Err(e) if e.get_ref().is_some_and(|e| e.is::<LineTooLong>()) => {
                    return Err(at(
                        lineno + 1,
                        None,
                        "longer than 1 MiB with no line end: not a diagram (a binary file or a device?); read no further",
                    ));
                }
                Err(e) => return Err(e.into()),
            };
            let Some(raw) = raw else {
                break;
            };
            lineno += 1;
            // A byte-order mark may open the file; ASCII trimming is all a line needs.
            let line = raw.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(raw);
            let t = line.trim_ascii();
            if t.is_empty() {
                continue;
            }
            if t[0] == b'#' {
                match std::str::from_utf8(t).ok().and_then(parse_rpm) {
                    Some(Ok(r)) if head.rpm.is_some_and(|was| was.to_bits() != r.to_bits()) => {
                        return Err(at(
                            lineno,
                            None,
                            format!(
                                "a second speed line says {r} rpm, an earlier one {} rpm",
                                head.rpm.unwrap_or_default()
                            ),
                        ));
                    }
                    Some(Ok(r)) => head.rpm = Some(r),
                    Some(Err(message)) => return Err(at(lineno, None, message)),
                    None => {}
                }
                continue;
            }
            // Excel writes `sep=;` above the header to name the delimiter.
            if delim.is_none() && !header_from_file && rows == 0 && sep_line(line) {
                delim = Some(match line[4] {
                    b',' => Delim::Comma,
                    b';' => Delim::Semicolon,
                    b'\t' => Delim::Tab,
                    b' ' => Delim::Space,
                    other => {
                        return Err(at(
                            lineno,
                            None,
                            format!(
                                "`sep={}`: cells are delimited by commas, semicolons, tabs or spaces",
                                other as char
                            ),
                        ));
                    }
                });
                continue;
            }
            let dl = *delim.get_or_insert_with(|| Delim::detect(t));
            let dc = dl.decimal_comma();
            {
                dl.split(t, &mut spans);
                let cell = |i: usize| &t[spans[i].0..spans[i].1];
                let undecided = !header_from_file && rows == 0 && current.is_none();
                let first_is_number = || !spans.is_empty() && number(cell(0), dc, 0, 0).is_ok();
                if undecided && !first_is_number() {
                    // A header row: it names the columns unless --columns replaces them.
                    header_from_file = true;
                    if names.is_none() {
                        let mut named: Vec<String> = (0..spans.len())
                            .map(|i| {
                                String::from_utf8_lossy(cell(i))
                                    .trim_matches('"')
                                    .to_ascii_lowercase()
                            })
                            .collect();
                        // A delimiter at the end of every row (spreadsheet
                        // exports): the empty last columns are skipped.
                        for n in named.iter_mut().rev().take_while(|n| n.is_empty()) {
                            *n = "_".into();
                        }
                        names = Some(named);
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
                        cols = columns(n, lineno)?;
                        head.quantity = cols.quantity;
                        head.pv = cols.pv;
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
                    cols = columns(n, lineno)?;
                    head.quantity = cols.quantity;
                    head.pv = cols.pv;
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
                (
                    number(cell(cols.x), dc, lineno, cols.x + 1)?,
                    number(cell(cols.value), dc, lineno, cols.value + 1)?,
                    match cols.cycle {
                        Some(i) => Some(number(cell(i), dc, lineno, i + 1)?),
                        None => None,
                    },
                    match cols.cylinder {
                        Some(i) => Some(number(cell(i), dc, lineno, i + 1)?),
                        None => None,
                    },
                )
            }
        };
        // Cycle and cylinder cells are whole numbers within bounds: a
        // cylinder above the engine's, `1.5` or a 20-digit number is an
        // error at its line, never a truncation or an allocation.
        let mut cyc = match cyc_raw {
            Some(c) if c.fract() == 0.0 && (0.0..=MAX_CYCLE).contains(&c) => c as i64,
            Some(c) => {
                return Err(at(
                    lineno,
                    cols.cycle.map(|i| i + 1),
                    format!(
                        "cycle {}: cycle numbers are whole numbers from 0 to 2^53",
                        shown_number(c)
                    ),
                ));
            }
            None => auto_cycle,
        };
        let max_cyl = opts.max_cylinder.clamp(1, MAX_CYLINDERS);
        let cyl = match cyl_raw {
            None => 0,
            Some(c) if c.fract() == 0.0 && c >= 1.0 && c <= max_cyl as f64 => c as i64,
            Some(c) => {
                return Err(at(
                    lineno,
                    cols.cylinder.map(|i| i + 1),
                    format!(
                        "cylinder {}: cylinders are whole numbers from 1 to {max_cyl}{}",
                        shown_number(c),
                        if max_cyl < MAX_CYLINDERS {
                            ", the engine's cylinder count"
                        } else {
                            ""
                        }
                    ),
                ));
            }
        };
        let is_pressure = cols.quantity == Quantity::Pressure;
        let p = p_raw * cols.scale + if opts.gauge && is_pressure { ATM } else { 0.0 };
        if is_pressure && p < 0.0 {
            return Err(at(
                lineno,
                Some(cols.value + 1),
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
        // p–V rows carry volume (m³); p–φ rows carry the cycle angle.
        let a = if cols.pv {
            x_raw * cols.x_scale
        } else {
            x_raw - opts.tdc_deg
        };
        if !cols.pv
            && cols.cycle.is_none()
            && let Some(tr) = current.as_ref()
            && tr.cylinder == cyl
        {
            let first = tr.angle_deg[0];
            let last = *tr.angle_deg.last().unwrap_or(&first);
            // Without a cycle column a new cycle starts where the angle runs
            // one cycle past the first, or jumps back by more than half a cycle.
            if a - first >= opts.cycle_deg - 1e-9 || last - a > opts.cycle_deg / 2.0 {
                auto_cycle += 1;
                cyc = auto_cycle;
            }
        }
        match current.as_mut() {
            Some(tr) if tr.cycle == cyc && tr.cylinder == cyl => {
                if !cols.pv {
                    let last = *tr.angle_deg.last().unwrap_or(&f64::NEG_INFINITY);
                    let first = tr.angle_deg[0];
                    if a <= last {
                        return Err(at(
                            lineno,
                            Some(cols.x + 1),
                            format!(
                                "angle {x_raw} does not rise after {}: angles must increase within a cycle",
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
                            Some(cols.x + 1),
                            format!(
                                "angle {x_raw} lies more than one {}° cycle after the first ({}); \
                                 give a `cycle` column to separate cycles",
                                opts.cycle_deg,
                                first + opts.tdc_deg
                            ),
                        ));
                    }
                }
                tr.angle_deg.push(a);
                tr.values.push(p);
            }
            _ => {
                if let Some(tr) = current.take() {
                    last_len = tr.angle_deg.len();
                    emit(tr, current_line, cols.quantity, cols.pv)?;
                }
                current_line = lineno;
                let mut angle_deg = Vec::with_capacity(last_len.max(16));
                let mut values = Vec::with_capacity(last_len.max(16));
                angle_deg.push(a);
                values.push(p);
                current = Some(Trace {
                    cycle: cyc,
                    cylinder: cyl,
                    angle_deg,
                    values,
                });
            }
        }
        rows += 1;
    }
    if let Some(tr) = current.take() {
        // A lone closing point (first angle + cycle) after the last cycle.
        let lone_closing = tr.angle_deg.len() == 1 && cols.cycle.is_none() && auto_cycle > 0;
        if !lone_closing {
            emit(tr, current_line, cols.quantity, cols.pv)?;
        }
    }
    if rows == 0 {
        return Err(IngestError::Data("no data rows".into()));
    }
    head.notes.extend(pv_notes);
    Ok(head)
}

/// True for Excel's delimiter line `sep=X` (X one byte; any case, a
/// carriage return after it allowed).
fn sep_line(line: &[u8]) -> bool {
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    line.len() == 5 && line[..4].eq_ignore_ascii_case(b"sep=")
}

/// Where the columns are and what they hold.
#[derive(Debug, Clone, Copy, Default)]
struct Cols {
    /// Angle (p–φ) or volume (p–V) column.
    x: usize,
    /// Volume unit (m³ per file unit) for p–V data.
    x_scale: f64,
    /// True for p–V data.
    pv: bool,
    /// Pressure or torque column.
    value: usize,
    /// Pressure unit (Pa per file unit), 1 for torque.
    scale: f64,
    cycle: Option<usize>,
    cylinder: Option<usize>,
    quantity: Quantity,
}

fn columns(names: &[String], line: usize) -> Result<Cols, IngestError> {
    for (i, n) in names.iter().enumerate() {
        if !KNOWN.contains(&n.as_str()) {
            let hint = KNOWN
                .iter()
                .filter(|k| **k != "_")
                .max_by(|a, b| similarity(n, a).total_cmp(&similarity(n, b)))
                .filter(|k| enginedyn_numerics::format::close_name(n, k))
                .map(|k| format!("; did you mean `{k}`?"))
                .unwrap_or_default();
            return Err(at(
                line,
                Some(i + 1),
                format!(
                    "unknown column `{}`{hint} (known: {}; `_` skips a column; --columns renames them all)",
                    enginedyn_numerics::format::quote(n),
                    KNOWN[..KNOWN.len() - 1].join(", ")
                ),
            ));
        }
    }
    let find = |k: &str| names.iter().position(|n| n == k);
    let volume = names
        .iter()
        .enumerate()
        .find_map(|(i, n)| match n.as_str() {
            "volume_cm3" => Some((i, 1e-6)),
            "volume_m3" => Some((i, 1.0)),
            "volume_l" => Some((i, 1e-3)),
            _ => None,
        });
    let (x, x_scale, pv) = match (find(ANGLE), volume) {
        (Some(i), None) => (i, 1.0, false),
        (None, Some((i, s))) => (i, s, true),
        (Some(_), Some(_)) => {
            return Err(at(
                line,
                None,
                "both `crank_deg` and a volume column: give one (skip the other with `_` in --columns)",
            ));
        }
        (None, None) => {
            return Err(at(
                line,
                None,
                "no `crank_deg` (p–φ) or `volume_cm3`/`volume_m3`/`volume_l` (p–V) column",
            ));
        }
    };
    let base = Cols {
        x,
        x_scale,
        pv,
        cycle: find("cycle"),
        cylinder: find("cylinder"),
        ..Cols::default()
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
        if pv {
            return Err(at(
                line,
                None,
                "a turning-moment file needs `crank_deg`, not a volume",
            ));
        }
        return Ok(Cols {
            value: i,
            scale: 1.0,
            quantity: q,
            ..base
        });
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
    Ok(Cols {
        value: i_p,
        scale,
        quantity: Quantity::Pressure,
        ..base
    })
}

fn similarity(a: &str, b: &str) -> f64 {
    enginedyn_numerics::format::name_similarity(a, b)
}

/// Checks a trace (points, coverage, plausible values) and moves its angles
/// into `[0, cycle)`, rotating so they rise. Returns it with the smallest and
/// largest step between its angles when they did not have to move.
fn finish(
    mut tr: Trace,
    cycle: f64,
    quantity: Quantity,
) -> Result<(Trace, Option<(f64, f64)>), IngestError> {
    let n = tr.angle_deg.len();
    if n < 4 {
        return Err(IngestError::Data(format!(
            "cycle {} has {n} points: at least 4 are needed",
            tr.cycle
        )));
    }
    let first = tr.angle_deg[0];
    let span = tr.angle_deg[n - 1] - first;
    // The median step; evenly spaced data (the usual case) needs no sort.
    let (lo, hi) = enginedyn_numerics::scan::step_range(&tr.angle_deg);
    let median = if hi - lo <= 1e-9 * hi.abs() + 1e-12 {
        lo
    } else {
        let mut gaps: Vec<f64> = tr.angle_deg.windows(2).map(|w| w[1] - w[0]).collect();
        gaps.sort_by(f64::total_cmp);
        gaps[gaps.len() / 2]
    };
    let wrap_gap = cycle - span;
    if wrap_gap > (3.0 * median).max(1.0) + 1e-9 {
        return Err(IngestError::Data(format!(
            "cycle {} covers {:.2}° to {:.2}° only, not the full {cycle}° cycle (a gap of {wrap_gap:.2}° where steps are {median:.3}°)",
            tr.cycle,
            first,
            first + span
        )));
    }
    if quantity != Quantity::Pressure {
        let (lo, hi) = enginedyn_numerics::scan::min_max(&tr.values);
        let peak = lo.abs().max(hi.abs()).max(0.0);
        // The largest engines make about 1e7 N m: beyond 1e9 is a unit mix-up.
        if peak > 1e9 {
            return Err(IngestError::Data(format!(
                "cycle {}: torque {} N m is implausible: is the torque column in N m?",
                tr.cycle,
                enginedyn_numerics::format::sig(peak, 4)
            )));
        }
    }
    if quantity == Quantity::Pressure {
        let peak = enginedyn_numerics::scan::min_max(&tr.values).1.max(0.0);
        // 5 kPa to 10 kbar absolute: anything outside is a unit mix-up.
        if !(5e3..=1e9).contains(&peak) {
            return Err(IngestError::Data(format!(
                "cycle {}: peak pressure {} bar is implausible: is the pressure column's unit right?",
                tr.cycle,
                enginedyn_numerics::format::sig(peak / 1e5, 4)
            )));
        }
    }
    // Already in [0, cycle) and rising (the usual case): nothing to move.
    if first >= 0.0 && tr.angle_deg[n - 1] < cycle && lo > 0.0 {
        return Ok((tr, Some((lo, hi))));
    }
    let wrapped: Vec<f64> = tr
        .angle_deg
        .iter()
        .map(|a| {
            let w = a.rem_euclid(cycle);
            if w >= cycle { 0.0 } else { w }
        })
        .collect();
    let start = (0..n)
        .min_by(|&i, &j| wrapped[i].total_cmp(&wrapped[j]))
        .unwrap_or(0);
    tr.angle_deg = wrapped[start..]
        .iter()
        .chain(&wrapped[..start])
        .copied()
        .collect();
    tr.values.rotate_left(start);
    if tr.angle_deg.windows(2).any(|w| w[1] <= w[0]) {
        return Err(IngestError::Data(format!(
            "cycle {}: two points fall on the same crank angle once wrapped into the cycle",
            tr.cycle
        )));
    }
    Ok((tr, None))
}

#[cfg(test)]
mod tests {
    use super::{Delim, PLAIN_CELLS, fast_decimal, plain_row};
    use proptest::prelude::*;

    proptest! {
        /// The one-pass row parser gives, cell by cell, exactly what the
        /// general path (split, then `str::parse`) gives, or declines.
        #[test]
        fn plain_row_equals_split_and_parse(
            cells in prop::collection::vec((-1e7f64..1e7, 0usize..8), 1..6),
            sep in prop::sample::select(vec![b',', b';', b'\t']),
        ) {
            let dc = sep != b',';
            let row = cells
                .iter()
                .map(|(x, d)| {
                    let s = format!("{x:.d$}");
                    if dc && d % 2 == 1 { s.replace('.', ",") } else { s }
                })
                .collect::<Vec<_>>()
                .join(std::str::from_utf8(&[sep]).unwrap());
            let mut out = [0.0; PLAIN_CELLS];
            let line = format!("{row}\n");
            if let Some((n, used)) = plain_row(line.as_bytes(), sep, dc, false, &mut out) {
                prop_assert_eq!(used, line.len());
                let delim = match sep { b',' => Delim::Comma, b';' => Delim::Semicolon, _ => Delim::Tab };
                let mut spans = Vec::new();
                delim.split(row.as_bytes(), &mut spans);
                prop_assert_eq!(n, spans.len());
                for (k, (s, e)) in spans.iter().enumerate() {
                    let cell = row[*s..*e].replace(',', ".");
                    prop_assert_eq!(out[k].to_bits(), cell.parse::<f64>().unwrap().to_bits());
                }
            }
        }
    }

    #[test]
    fn plain_row_declines_what_it_cannot_do() {
        let mut out = [0.0; PLAIN_CELLS];
        for row in [
            "1, 2",
            "1,2,",
            "\"1\",2",
            "1e5,2",
            "+1,2",
            "1,2,3,4,5,6,7,8,9",
            "1.2.3,4",
            "1234567890123456,1",
        ] {
            assert!(
                plain_row(row.as_bytes(), b',', false, true, &mut out).is_none(),
                "{row}"
            );
        }
        // The end of the window ends a row only at the end of the file.
        assert_eq!(plain_row(b"1,2", b',', false, false, &mut out), None);
        assert_eq!(plain_row(b"1,2", b',', false, true, &mut out), Some((2, 3)));
        assert_eq!(plain_row(b"1,2 \n", b',', false, true, &mut out), None);
        assert_eq!(
            plain_row(b"3;-0,25;7\r\n4", b';', true, false, &mut out),
            Some((3, 11))
        );
        assert_eq!(out[..3], [3.0, -0.25, 7.0]);
    }

    proptest! {
        /// The fast path gives exactly what `str::parse` gives, or declines.
        #[test]
        fn fast_decimal_equals_std(x in -1e9f64..1e9, digits in 0usize..9) {
            let s = format!("{x:.digits$}");
            if let Some(v) = fast_decimal(s.as_bytes()) {
                prop_assert_eq!(v.to_bits(), s.parse::<f64>().unwrap().to_bits());
            }
        }
    }

    #[test]
    fn fast_decimal_declines_what_it_cannot_do() {
        for s in [
            "",
            "-",
            ".",
            "1e5",
            "1.2.3",
            "nan",
            "1234567890123456",
            "0x10",
            "1,5",
        ] {
            assert!(fast_decimal(s.as_bytes()).is_none(), "{s}");
        }
        assert_eq!(
            fast_decimal(b"-0").map(f64::to_bits),
            Some((-0.0f64).to_bits())
        );
        assert_eq!(fast_decimal(b"87.19176"), Some(87.19176));
    }
}
