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

mod arrays;
mod axis;
mod cancel;
mod columns;
mod decode;
mod emit;
mod error;
mod fast;
mod grid;
mod layout;
mod mdf;
mod number;
mod ods;
mod plausible;
mod probe;
mod pv;
mod reader;
mod row;
mod sheet;
mod template;
/// The hostile `.ods` sheets of the tests (shared with `tests/memory.rs`).
#[cfg(test)]
#[path = "../tests/support/ods_with.rs"]
mod test_ods;
mod text;
mod time;
mod trace;
mod values;
mod xls;

pub use axis::CylinderAxis;
pub use cancel::{CANCELLED, Cancel, Cancellable, cancel_error};
pub use columns::{canonical, pressure_unit};
pub use error::IngestError;
pub use grid::{
    Accumulator, CycleCombustion, CycleStats, GridOptions, MostKnocking, Peg, PegReport, Resampled,
    SkippedCycle, mean_std,
};
pub use mdf::{MAX_MDF, MAX_MDF_BLOCK, MAX_MDF_CHANNELS, MAX_MDF_DECODED, MAX_MDF_GROUPS};
pub use number::{NumberError, SpeedError, check_rpm, read_number, read_rpm};
pub use plausible::TdcPlacement;
pub use reader::SYNTHETIC_MARK;
pub use sheet::MAX_WORKBOOK;
pub use text::MAX_LINE;
pub use time::{MAX_ENCODER_PPR, MAX_WHEEL_TDC_DEG, Wheel};

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
    /// The engine's cylinder: its volume law (p–V data; the gap rule's
    /// `∫ p dV`, which bridges a single cycle's gap wider than `max_gap_deg`
    /// when the data settle it) and its compression ratio (plausibility's
    /// compression bound). `None`: no p–V data, and neither check.
    pub cylinder: Option<Cylinder>,
    /// p–V data starts at the BDC before firing TDC (`--pv-start bdc`).
    pub pv_start_bdc: bool,
    /// The highest cylinder number a `cylinder` column may hold (the
    /// engine's cylinder count; 24, the most an engine file allows, when
    /// not known).
    pub max_cylinder: usize,
    /// `tdc_deg` was given (`--tdc-deg`): a time record then takes firing
    /// TDC from it instead of from the pressure peak.
    pub tdc_given: bool,
    /// The traces are relative and will be pegged (`--peg-bar`, `--peg
    /// polytropic`): never checked for sign.
    pub relative: bool,
    /// Lines to skip at the top of a file (`--skip-lines`).
    pub skip_lines: usize,
    /// The sheet of a workbook (`--sheet`); the first when `None`.
    pub sheet: Option<Sheet>,
    /// The channel group of an MDF4 file (`--group`, 1-based); the first
    /// that holds a pressure when `None`.
    pub group: Option<usize>,
    /// The widest gap (deg) bridged in a single cycle (`--max-gap`).
    pub max_gap_deg: f64,
    /// A time record's firing TDC time (s) (`--tdc-time`).
    pub tdc_time: Option<f64>,
    /// A charge amplifier's gain (bar per volt) for `pressure_v` (`--gain`).
    pub gain_bar_per_v: Option<f64>,
    /// The speed given on the command line (rpm), for a time record without
    /// a TDC pulse.
    pub rpm: Option<f64>,
    /// Each cylinder's firing angle (deg, cylinder 1's 0), for deciding
    /// whether per-cylinder traces share cylinder 1's axis; empty when the
    /// engine is not known.
    pub firing_deg: Vec<f64>,
    /// `--cylinder-axis`: the axis decision, not taken from the peaks.
    pub cylinder_axis: Option<CylinderAxis>,
    /// The file holds this cylinder's traces (one of several `--diagram`
    /// files); 0 when it names its own cylinders or stands for all.
    pub as_cylinder: usize,
    /// A turning-moment file is expected (`--torque`): errors speak of torque.
    pub torque: bool,
    /// A time record's `encoder` column gives this many pulses a revolution
    /// (`--encoder-ppr`, 1 to [`MAX_ENCODER_PPR`]).
    pub encoder_ppr: Option<u32>,
    /// A time record's `wheel` column is this tooth wheel (`--wheel`).
    pub wheel: Option<Wheel>,
    /// The angle (deg) from the wheel's first tooth after the gap to
    /// cylinder 1's TDC (`--wheel-tdc-deg`).
    pub wheel_tdc_deg: Option<f64>,
    /// The checks that assume a compressing engine (the compression bound,
    /// the peak-angle rule) are made; `false` for `--no-compression-check`
    /// (a steam engine, a compressor, a textbook problem).
    pub compression_check: bool,
    /// The data are a cycle enginedyn synthesised (handed over as arrays,
    /// without the mark its text carries, [`SYNTHETIC_MARK`]): its TDC is
    /// exact and it is not held to the plausibility rules of measured data.
    pub synthetic: bool,
    /// `--despike`: each glitch (a lone sample off the cubic through its
    /// neighbours by more than 10 bar and 20 % of the cycle's peak) is
    /// replaced by that cubic, with a note counting them; without it each
    /// is a warning naming its line and value.
    pub despike: bool,
    /// A record sampled on the crank angle without an angle column
    /// (`--angle-step`): row k of the data lies at k times this (deg).
    pub angle_step_deg: Option<f64>,
    /// Stops the read when set (another thread's Ctrl-C, a stop button).
    pub cancel: Cancel,
    /// The engine file's `operating.rpm`: a time record's measured speed
    /// far from it (a time in ms read as seconds) is an error naming the
    /// likely unit.
    pub operating_rpm: Option<f64>,
}

/// A workbook's sheet (`--sheet NAME|N`).
#[derive(Debug, Clone, PartialEq)]
pub enum Sheet {
    /// 1-based.
    Index(usize),
    /// By name.
    Name(String),
}

/// The widest gap bridged in a single digitised cycle by default (deg).
pub const MAX_GAP_DEG: f64 = 30.0;

/// The largest `--max-gap` (deg): a wider gap leaves less than half a
/// four-stroke cycle of data, which no interpolant can stand for.
pub const MAX_GAP_BOUND_DEG: f64 = 360.0;

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
            tdc_given: false,
            relative: false,
            skip_lines: 0,
            sheet: None,
            group: None,
            max_gap_deg: MAX_GAP_DEG,
            tdc_time: None,
            gain_bar_per_v: None,
            rpm: None,
            firing_deg: Vec::new(),
            cylinder_axis: None,
            as_cylinder: 0,
            torque: false,
            encoder_ppr: None,
            wheel: None,
            wheel_tdc_deg: None,
            compression_check: true,
            synthetic: false,
            despike: false,
            angle_step_deg: None,
            cancel: Cancel::default(),
            operating_rpm: None,
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
    /// The speed over this cycle (rpm), when the file measures it cycle by
    /// cycle (a time record's TDC pulses).
    pub rpm: Option<f64>,
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
    /// Cycles left out of the averages (a gap in the data).
    pub cycles_skipped: usize,
    /// Those cycles and why.
    pub skipped: Vec<SkippedCycle>,
    /// Things worth telling the user.
    pub notes: Vec<String>,
    /// What placed firing TDC, when the peak-angle rule applies to the
    /// averaged traces ([`resample_with`] checks it): a pressure on crank
    /// angle read with the compression checks.
    pub peak_rule: Option<TdcPlacement>,
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
            cycles_skipped: self.cycles_skipped,
            skipped: self.skipped.clone(),
            notes: Vec::new(),
            peak_rule: self.peak_rule.clone(),
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

/// What a file says about itself besides its traces.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Header {
    /// Pressure, or torque from a turning-moment file.
    pub quantity: Quantity,
    /// The file says it was synthesised by `enginedyn synth` (its first
    /// comment line): its firing TDC is exact, never questioned.
    pub synthetic: bool,
    /// Speed from a `# rpm = N` comment line.
    pub rpm: Option<f64>,
    /// True for p–V data.
    pub pv: bool,
    /// Cycles left out of the averages (a gap in the data).
    pub cycles_skipped: usize,
    /// Those cycles and why.
    pub skipped: Vec<SkippedCycle>,
    /// Things worth telling the user.
    pub notes: Vec<String>,
    /// What placed firing TDC, when not `--tdc-deg` (or its default 0):
    /// the peak-angle rule's error names it.
    pub tdc_placement: Option<TdcPlacement>,
}

/// Reads a diagram (p–φ, p–V or turning moment) into memory: every trace.
pub fn parse(reader: impl BufRead, opts: &ParseOptions) -> Result<Diagram, IngestError> {
    let mut traces = Vec::new();
    let h = parse_stream(reader, opts, |t| {
        traces.push(t.trace);
        Ok(())
    })?;
    let peak_rule = (h.quantity == Quantity::Pressure && !h.pv && opts.compression_check)
        .then(|| placement(h.tdc_placement, opts));
    Ok(Diagram {
        quantity: h.quantity,
        rpm: h.rpm,
        traces,
        cycle_deg: opts.cycle_deg,
        pv: h.pv,
        cycles_skipped: h.cycles_skipped,
        skipped: h.skipped,
        notes: h.notes,
        peak_rule,
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
    load_from(|sink| parse_stream(reader, opts, sink), opts, grid, on_grid)
}

/// [`load`] of named columns already in memory (all of one length): the
/// same reader, rule for rule, as a file with that header and those rows.
/// Line numbers in errors are sample numbers from 1.
pub fn load_columns(
    names: &[String],
    columns: &[&[f64]],
    opts: &ParseOptions,
    grid: &GridOptions,
) -> Result<Resampled, IngestError> {
    let mut unused = std::time::Duration::ZERO;
    load_from(
        |sink| arrays::read(names, columns, opts, sink),
        opts,
        grid,
        &mut unused,
    )
}

/// Every trace `source` hands over put on the grid as it comes.
fn load_from(
    source: impl FnOnce(
        &mut dyn FnMut(Streamed) -> Result<(), IngestError>,
    ) -> Result<Header, IngestError>,
    opts: &ParseOptions,
    grid: &GridOptions,
    on_grid: &mut std::time::Duration,
) -> Result<Resampled, IngestError> {
    let mut acc: Option<Accumulator> = None;
    let h = source(&mut |t| {
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
            let (pv, cycles_skipped) = (h.pv, h.cycles_skipped);
            let placed = h.tdc_placement.clone();
            let synthetic = h.synthetic || opts.synthetic;
            a.finish(h.rpm, h.notes)
                .and_then(|r| {
                    // A synthesised diagram's TDC is exact by construction.
                    if !synthetic {
                        peak_angle(&r, h.quantity, pv, placed, opts)?;
                    }
                    Ok(r)
                })
                .map(|mut r| {
                    r.synthetic = synthetic;
                    r.pv = pv;
                    r.cycles_skipped = cycles_skipped;
                    r.skipped = h.skipped;
                    r
                })
        }
        None => Err(IngestError::Data("no data rows".into())),
    };
    *on_grid += started.elapsed();
    resampled
}

/// The peak-angle rule of the plausibility pass
/// ([`plausible::peak_angle`]) on each cylinder's mean trace (or the one
/// mean), for cylinder pressure on crank angle that a compressing engine
/// made.
fn peak_angle(
    r: &Resampled,
    quantity: Quantity,
    pv: bool,
    placed: Option<TdcPlacement>,
    opts: &ParseOptions,
) -> Result<(), IngestError> {
    if quantity != Quantity::Pressure || pv || !opts.compression_check {
        return Ok(());
    }
    peak_rule(r, opts.cycle_deg, &placement(placed, opts))
}

/// What placed firing TDC: the reader's word, else `--tdc-deg` (or its
/// default 0).
fn placement(placed: Option<TdcPlacement>, opts: &ParseOptions) -> TdcPlacement {
    placed.unwrap_or(TdcPlacement::TdcDeg {
        deg: opts.tdc_deg,
        given: opts.tdc_given,
    })
}

/// The peak-angle rule on the one mean, or on cylinder 1's: cylinder 1's
/// mean lies on its own firing TDC whether the file's cylinders share its
/// axis or each has its own (the others are moved onto theirs later, by
/// the firing order), so a crank reference wrong for all is named there.
fn peak_rule(r: &Resampled, cycle: f64, placed: &TdcPlacement) -> Result<(), IngestError> {
    match r.cylinders.first() {
        None => plausible::peak_angle(&r.pressure, r.step_deg, cycle, placed, ""),
        Some(first) => plausible::peak_angle(first, r.step_deg, cycle, placed, " of cylinder 1"),
    }
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
    if let Some(placed) = &d.peak_rule {
        peak_rule(&r, d.cycle_deg, placed)?;
    }
    r.pv = d.pv;
    r.cycles_skipped = d.cycles_skipped;
    r.skipped = d.skipped.clone();
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

/// What a file is, from its first bytes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// Text (ASCII or UTF-8).
    Text,
    /// UTF-16 text with its byte-order mark; little-endian when true.
    Utf16(bool),
    /// A UTF-16 byte-order mark over 8-bit text.
    Utf16Mark,
    /// A ZIP (.xlsx, .ods) or OLE (.xls) container: perhaps a workbook.
    Workbook,
    /// An ASAM MDF file (finished or not).
    Mdf,
    /// Any other binary file, as the message names it.
    Binary(&'static str),
}

/// What the first bytes of a file say it is.
fn kind(head: &[u8]) -> Kind {
    const MAGIC: &[(&[u8], Kind)] = &[
        (b"PK\x03\x04", Kind::Workbook),
        (b"\xD0\xCF\x11\xE0\xA1\xB1\x1A\xE1", Kind::Workbook),
        (b"MDF     ", Kind::Mdf),
        (b"UnFinMF ", Kind::Mdf),
        (b"\xFF\xFE", Kind::Utf16(true)),
        (b"\xFE\xFF", Kind::Utf16(false)),
        (b"\x89PNG", Kind::Binary("a PNG image")),
        (b"\xFF\xD8\xFF", Kind::Binary("a JPEG image")),
        (b"%PDF", Kind::Binary("a PDF document")),
        (b"\x1F\x8B", Kind::Binary("a gzip archive")),
        (
            b"\x89HDF",
            Kind::Binary("an HDF5 file (a MATLAB v7.3 .mat?)"),
        ),
        (b"MATLAB 5.0 MAT-file", Kind::Binary("a MATLAB .mat file")),
        (b"TDSm", Kind::Binary("a National Instruments TDMS file")),
        (b"\x7FELF", Kind::Binary("a program")),
        (b"7z\xBC\xAF", Kind::Binary("a 7-Zip archive")),
        (b"Rar!", Kind::Binary("a RAR archive")),
    ];
    if let Some((_, k)) = MAGIC.iter().find(|(m, _)| head.starts_with(m)) {
        // A UTF-16 mark over 8-bit text: UTF-16 of a diagram's ASCII holds
        // a zero byte in every character, text after a wrong mark none.
        if let Kind::Utf16(_) = k
            && head.len() >= 18
            && !head[2..].contains(&0)
        {
            return Kind::Utf16Mark;
        }
        return *k;
    }
    // Text has few control characters; a NUL or two in text is a damaged
    // line, which the text reader names.
    let control = head
        .iter()
        .filter(|&&b| b == 0 || (b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0C)))
        .count();
    let nuls = head.iter().filter(|&&b| b == 0).count();
    if nuls > 2 || control * 20 > head.len() {
        Kind::Binary("binary data")
    } else {
        Kind::Text
    }
}

/// Reads the text (or spreadsheet) and hands each finished trace to
/// `sink`, in file order (a single cycle with a gap last: it is held until
/// the file shows whether more cycles follow).
pub fn parse_stream(
    mut reader: impl BufRead,
    opts: &ParseOptions,
    sink: impl FnMut(Streamed) -> Result<(), IngestError>,
) -> Result<Header, IngestError> {
    let head = reader.fill_buf()?;
    match kind(&head[..head.len().min(4096)]) {
        Kind::Utf16(little) => {
            let mut utf16 = text::Utf16::new(reader, little);
            let mut h = text::read(&mut utf16, opts, sink)?;
            if utf16.ends_mid_character() {
                h.notes.push(
                    "the UTF-16 text ends mid-character (an odd number of bytes): truncated? its last byte is left out, and with it perhaps the last digit of the last value".into(),
                );
            }
            Ok(h)
        }
        Kind::Utf16Mark => Err(IngestError::Data(
            "the file starts with a UTF-16 byte-order mark, but what follows is 8-bit text (no zero bytes, as UTF-16 of digits has): the mark is wrong; save the file as UTF-8, or remove its first two bytes".into(),
        )),
        Kind::Text => {
            let mut h = text::read(reader, opts, sink)?;
            if opts.sheet.is_some() {
                h.notes
                    .push("--sheet applies to spreadsheets; this file is text".into());
            }
            if opts.group.is_some() {
                h.notes
                    .push("--group applies to MDF4 files; this file is text".into());
            }
            Ok(h)
        }
        Kind::Workbook => {
            let bytes = whole(&mut reader, MAX_WORKBOOK, "a workbook", "export the sheet as CSV")?;
            let mut h = sheet::read(bytes, opts, sink)?;
            if opts.group.is_some() {
                h.notes
                    .push("--group applies to MDF4 files; this file is a spreadsheet".into());
            }
            Ok(h)
        }
        Kind::Mdf => {
            let bytes = whole(
                &mut reader,
                MAX_MDF,
                "an MDF4 file",
                "cut it to the records wanted (asammdf's `cut` or `filter`), or export the channels as CSV",
            )?;
            mdf::read(bytes, opts, sink)
        }
        Kind::Binary(what) => Err(IngestError::Data(format!(
            "not a text file: it starts like {what}; a diagram is CSV text (comma, semicolon, tab or space delimited), a spreadsheet (.xlsx, .xls, .ods) or an MDF4 file (.mf4){}",
            if what.contains("TDMS") {
                "; the Python package reads TDMS: `enginedyn.io.read_tdms(path, group, …)` (npTDMS), its result for `analyse_arrays` or `analyse_time_record`"
            } else {
                ""
            }
        ))),
    }
}

/// The most bytes of a file's buffer a thread keeps for the next file read
/// whole ([`spare`]).
const SPARE_BYTES: usize = 16 << 20;

thread_local! {
    /// The buffer the last MDF4 file was read into, kept for the next one:
    /// a batch of them then writes into memory already mapped instead of
    /// faulting in fresh pages for every file (measured: half the time of
    /// reading a 7 MB file went to the kernel doing that).
    static SPARE: std::cell::RefCell<Vec<u8>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Gives a file's buffer back for the next file read whole, if it is at
/// most [`SPARE_BYTES`] (a thread holds at most that between files).
pub(crate) fn spare(bytes: Vec<u8>) {
    if bytes.capacity() <= SPARE_BYTES {
        SPARE.with(|s| *s.borrow_mut() = bytes);
    }
}

/// A file read whole into memory, at most `bound` bytes (a workbook, an
/// MDF4 file: formats read where their own pointers lead), into the buffer
/// the thread kept from the last one ([`spare`]).
fn whole(
    reader: &mut impl BufRead,
    bound: usize,
    what: &str,
    instead: &str,
) -> Result<Vec<u8>, IngestError> {
    let mut bytes = SPARE.with(|s| std::mem::take(&mut *s.borrow_mut()));
    bytes.clear();
    std::io::Read::read_to_end(
        &mut std::io::Read::take(reader, bound as u64 + 1),
        &mut bytes,
    )?;
    if bytes.len() > bound {
        return Err(IngestError::Data(format!(
            "{what} over {} MiB, the bound on one held in memory: {instead} (CSV is read as it streams, of any length)",
            bound >> 20
        )));
    }
    Ok(bytes)
}
