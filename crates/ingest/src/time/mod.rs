//! Time records: a data acquisition system sampling in time, not on a
//! crank-angle encoder's clock. The crank angle comes from one angle
//! source, each in a module of its own:
//!
//! - [`pulse`]: a `tdc` pulse per revolution, the speed taken revolution by
//!   revolution, the angle linear in time within each;
//! - [`clock`]: a constant speed and the time of one firing TDC (`--rpm`,
//!   `--tdc-time`);
//! - [`encoder`] and [`wheel`]: the crank's own signals, an encoder's edges
//!   or a tooth wheel's teeth ([`teeth`]: edges checked period by period,
//!   the angle interpolated in time between them).
//!
//! Every edge is where its signal rises through half its range, counted
//! once it reaches two thirds from below one third ([`edges`]).
//! The sources hand their samples to [`cycles`], which decides the firing
//! TDC on a four-stroke and hands whole cycles to the emitter.
//!
//! Memory is bounded: the first [`PROBE`] samples are held to find the
//! signals' ranges, then one revolution at a time (four at the start of a
//! four-stroke, until the firing TDC is known).

mod clock;
mod cycles;
mod edges;
mod encoder;
mod pulse;
mod teeth;
mod wheel;

pub use wheel::Wheel;

use crate::columns::{Axis, Roles, ValueCol};
use crate::emit::Emitter;
use crate::error::{IngestError, at, shown_number};
use crate::plausible::{Recurrence, TdcPlacement};
use crate::row::Cells;
use crate::values::value_scale;
use crate::{Header, ParseOptions, Quantity, Streamed};
use cycles::{Cycles, Firing, Others};

/// The most pulses a revolution `--encoder-ppr` may give (INTERFACE.md).
pub const MAX_ENCODER_PPR: u32 = 100_000;

/// The largest `--wheel-tdc-deg` either way (deg): a revolution.
pub const MAX_WHEEL_TDC_DEG: f64 = 360.0;

/// Samples held to find the signals' ranges (their half-way levels).
pub(crate) const PROBE: usize = 1 << 16;

/// A measured speed this far (relative) from `--rpm` or the file's speed is
/// an error: one of them is wrong (INTERFACE.md, "Hostile input").
const SPEED_DISAGREES: f64 = 0.1;

/// Two speeds this close (relative) are the same speed: no note.
const SAME_SPEED: f64 = 1e-9;

/// Where the angle comes from.
enum Source {
    Pulse(pulse::Pulse),
    Clock(clock::Clock),
    Crank(Box<teeth::Crank>),
}

/// The signal slots: the crank signal (or the `tdc` pulse alone), the `tdc`
/// pulse beside an encoder, the `cam`.
type Signals = [Option<usize>; 3];

/// A sample held to find the levels: time, value, line, the signals.
type Held = (f64, f64, usize, [f64; 3]);

/// A time record being read.
pub(crate) struct TimeRecord {
    t_col: usize,
    t_scale: f64,
    p_col: usize,
    p_scale: f64,
    offset: f64,
    cycle_deg: f64,
    tdc_deg: Option<f64>,
    source: Source,
    cycles: Cycles,
    sig: Signals,
    /// Samples held until the signals' half-way levels are known.
    probe: Option<Vec<Held>>,
    last_t: Option<f64>,
    /// The first sample's time (s).
    first_t: Option<f64>,
    /// `--tdc-time` (s), when it gives the firing TDC.
    tdc_time: Option<f64>,
    /// The last line read.
    last_line: usize,
    /// The speed the file (`# rpm` line or banner) gives, and which.
    file_rpm: Option<(f64, &'static str)>,
    /// `--rpm`.
    flag_rpm: Option<f64>,
    /// The engine file's `operating.rpm`.
    operating_rpm: Option<f64>,
    /// Columns of the crank's signals that this source does not use.
    unused: Vec<String>,
    /// The other cylinders' pressure columns, with one pressure column per
    /// cylinder: read on the reference cylinder's angle
    /// ([`cycles::Others`]).
    others: Vec<OtherColumn>,
    /// One row's values of `others`.
    row_others: Vec<f64>,
}

/// Another cylinder's pressure column: its index, scale and offset.
type OtherColumn = (usize, f64, f64);

/// The reference cylinder's value column and the others', with one
/// pressure column per cylinder (`P_Cyl1` …): every cylinder is read on
/// the angle of cylinder 1, whose TDC the record's crank reference marks.
fn per_cylinder(
    roles: &Roles,
    opts: &ParseOptions,
    line: usize,
) -> Result<(ValueCol, Vec<OtherColumn>, Others), IngestError> {
    if roles.values.len() == 1 {
        return Ok((roles.values[0], Vec::new(), Others::default()));
    }
    let mut order: Vec<usize> = (0..roles.values.len()).collect();
    order.sort_by_key(|&i| roles.values[i].cylinder);
    let first = roles.values[order[0]];
    if first.cylinder != 1 {
        return Err(at(
            line,
            Some(first.col + 1),
            format!(
                "{} pressure columns, one per cylinder, but none of cylinder 1: a time record's crank reference is cylinder 1's TDC, and its pressure places the others",
                roles.values.len()
            ),
        ));
    }
    let mut others = Vec::with_capacity(order.len() - 1);
    for &i in &order[1..] {
        let v = roles.values[i];
        let (scale, offset) = value_scale(roles, v.scale, opts, line)?;
        others.push((v.col, scale, offset));
    }
    let mut o = Others::default();
    o.cylinders = order.iter().map(|&i| roles.values[i].cylinder).collect();
    o.columns = order;
    Ok((first, others, o))
}

/// The angle source that a time record's columns and flags choose, with
/// what goes with it.
struct Chosen {
    source: Source,
    /// How the firing TDC is told on a four-stroke.
    firing: Firing,
    sig: Signals,
    /// `--tdc-time` (s), when it gives the firing TDC.
    tdc_time: Option<f64>,
}

impl Chosen {
    /// A crank signal of `kind` in column `col`, with the `cam` column and
    /// the `tdc` column or `--tdc-time` beside it.
    fn crank(
        kind: teeth::Kind,
        col: usize,
        cam: Option<usize>,
        firing: Firing,
        (tdc_col, tdc_time): (Option<usize>, Option<f64>),
    ) -> Self {
        Chosen {
            source: Source::Crank(Box::new(teeth::Crank::new(kind, col, cam))),
            firing,
            sig: [Some(col), tdc_col, cam],
            tdc_time,
        }
    }
}

/// The 1-based column of 0-based `c`, for an error.
fn col_of(c: usize) -> Option<usize> {
    Some(c + 1)
}

/// An encoder of `ppr` pulses a revolution (`--encoder-ppr`), with a `tdc`
/// column or `--tdc-time` for 0°; a wheel column beside it is `unused`.
fn encoder_source(
    roles: &Roles,
    opts: &ParseOptions,
    ppr: u32,
    line: usize,
    unused: &mut Vec<String>,
) -> Result<Chosen, IngestError> {
    let Some(col) = roles.encoder else {
        return Err(at(
            line,
            None,
            "--encoder-ppr is given, but the record has no `encoder` column",
        ));
    };
    if !(1..=MAX_ENCODER_PPR).contains(&ppr) {
        return Err(at(
            line,
            col_of(col),
            format!(
                "--encoder-ppr {ppr}: an encoder gives 1 to {MAX_ENCODER_PPR} pulses a revolution"
            ),
        ));
    }
    if let Some(w) = roles.wheel {
        unused.push(format!(
            "column {} (a tooth wheel; the encoder gives the angle)",
            w + 1
        ));
    }
    let (tdc_col, time) = match (roles.tdc, opts.tdc_time) {
        (Some(c), _) => (Some(c), None),
        (None, Some(t)) => (None, Some(t)),
        (None, None) => {
            return Err(at(
                line,
                col_of(col),
                "an encoder gives the angle's steps, not where 0° is: give a `tdc` column (a pulse per revolution) or --tdc-time T (the time of a firing TDC, in seconds)",
            ));
        }
    };
    let firing = match (time, roles.cam) {
        (Some(_), _) => Firing::Given,
        (None, Some(_)) => Firing::Cam,
        (None, None) => Firing::Pressure,
    };
    let kind = teeth::Kind::Encoder(encoder::Encoder {
        ppr,
        tdc_col,
        tdc_time: time,
        pulses: 0,
    });
    Ok(Chosen::crank(kind, col, roles.cam, firing, (tdc_col, time)))
}

/// A tooth wheel `w` (`--wheel`) with `--wheel-tdc-deg`; a `tdc` or
/// encoder column beside it is `unused`.
fn wheel_source(
    roles: &Roles,
    opts: &ParseOptions,
    w: Wheel,
    line: usize,
    unused: &mut Vec<String>,
) -> Result<Chosen, IngestError> {
    let Some(col) = roles.wheel else {
        return Err(at(
            line,
            None,
            "--wheel is given, but the record has no `wheel` column",
        ));
    };
    let Some(a) = opts.wheel_tdc_deg else {
        return Err(at(
            line,
            col_of(col),
            format!(
                "a `wheel` column needs --wheel-tdc-deg A: the angle from the {w} wheel's first tooth after the gap to cylinder 1's TDC"
            ),
        ));
    };
    if !(a.is_finite() && a.abs() <= MAX_WHEEL_TDC_DEG) {
        return Err(at(
            line,
            col_of(col),
            format!(
                "--wheel-tdc-deg {}: from -{MAX_WHEEL_TDC_DEG} to {MAX_WHEEL_TDC_DEG}°",
                shown_number(a)
            ),
        ));
    }
    if let Some(c) = roles.tdc {
        unused.push(format!(
            "column {} (a TDC pulse; the wheel's gap and --wheel-tdc-deg give TDC)",
            c + 1
        ));
    }
    if let Some(c) = roles.encoder {
        unused.push(format!(
            "column {} (an encoder; the wheel gives the angle)",
            c + 1
        ));
    }
    let kind = teeth::Kind::Wheel {
        gaps: wheel::Gaps::new(w),
        tdc_deg: a,
    };
    let firing = if roles.cam.is_some() {
        Firing::Cam
    } else {
        Firing::Pressure
    };
    Ok(Chosen::crank(kind, col, roles.cam, firing, (None, None)))
}

/// No crank signal: a `tdc` pulse per revolution, else a constant speed
/// (`--rpm`, or the file's `rpm`) from `--tdc-time`; a cam column is then
/// `unused`, an encoder or wheel column without its flag an error.
fn pulse_or_clock_source(
    roles: &Roles,
    opts: &ParseOptions,
    rpm: Option<(f64, &'static str)>,
    line: usize,
    unused: &mut Vec<String>,
) -> Result<Chosen, IngestError> {
    if let Some(c) = roles.encoder {
        return Err(at(
            line,
            col_of(c),
            "an `encoder` column needs --encoder-ppr N, its pulses a revolution",
        ));
    }
    if let Some(c) = roles.wheel {
        return Err(at(
            line,
            col_of(c),
            "a `wheel` column needs --wheel T-M (60-2, 36-1, 36-2 or 58x) and --wheel-tdc-deg A",
        ));
    }
    if let Some(c) = roles.cam {
        unused.push(format!("column {} (a cam pulse tells the firing revolution of an encoder's or a tooth wheel's angle)", c + 1));
    }
    match (roles.tdc, opts.tdc_time) {
        (Some(col), _) => Ok(Chosen {
            source: Source::Pulse(pulse::Pulse::new(col)),
            firing: Firing::Pressure,
            sig: [Some(col), None, None],
            tdc_time: None,
        }),
        (None, Some(t)) => {
            let Some(rpm) = opts.rpm.or(rpm.map(|r| r.0)) else {
                return Err(at(
                    line,
                    Some(roles.x + 1),
                    "a time record with --tdc-time needs the speed: --rpm N (or a `# rpm = N` line)",
                ));
            };
            Ok(Chosen {
                source: Source::Clock(clock::Clock::new(t, rpm, opts.cycle_deg)),
                firing: Firing::Given,
                sig: [None; 3],
                tdc_time: Some(t),
            })
        }
        (None, None) => Err(at(
            line,
            Some(roles.x + 1),
            "a time record needs the crank angle: a `tdc` column (a pulse per revolution), an `encoder` column with --encoder-ppr N, a `wheel` column with --wheel T-M, or --rpm N and --tdc-time T (the time of a firing TDC, in seconds)",
        )),
    }
}

impl TimeRecord {
    pub(crate) fn new(
        roles: &Roles,
        opts: &ParseOptions,
        rpm: Option<(f64, &'static str)>,
        line: usize,
    ) -> Result<Self, IngestError> {
        let Axis::Time(t_scale) = roles.axis else {
            return Err(IngestError::Data(
                "a time record needs a time column".into(),
            ));
        };
        if roles.quantity != Quantity::Pressure {
            return Err(at(line, None, "a time record holds pressure, not torque"));
        }
        let (v, others, cylinders) = per_cylinder(roles, opts, line)?;
        let (p_scale, offset) = value_scale(roles, v.scale, opts, line)?;
        let tdc_deg = opts.tdc_given.then_some(opts.tdc_deg);
        let mut unused = Vec::new();
        let Chosen {
            source,
            firing,
            sig,
            tdc_time,
        } = match (opts.encoder_ppr, opts.wheel) {
            (Some(_), Some(_)) => {
                return Err(at(
                    line,
                    None,
                    "--encoder-ppr and --wheel both given: a time record's angle comes from one crank signal",
                ));
            }
            (Some(ppr), None) => encoder_source(roles, opts, ppr, line, &mut unused)?,
            (None, Some(w)) => wheel_source(roles, opts, w, line, &mut unused)?,
            (None, None) => pulse_or_clock_source(roles, opts, rpm, line, &mut unused)?,
        };
        let probe = (!matches!(source, Source::Clock(_))).then(Vec::new);
        let mut cycles = Cycles::new(opts.cycle_deg, tdc_deg, firing);
        let mut source = source;
        match &mut source {
            Source::Clock(c) => c.others = cylinders,
            _ => cycles.others = cylinders,
        }
        if let Source::Crank(c) = &source {
            cycles.recur = Some(match &c.kind {
                teeth::Kind::Encoder(e) => (
                    Recurrence::default(),
                    "--encoder-ppr",
                    f64::from(e.ppr),
                    "pulses",
                ),
                teeth::Kind::Wheel { gaps, .. } => (
                    Recurrence::default(),
                    "--wheel",
                    f64::from(gaps.wheel.positions()),
                    "tooth positions",
                ),
            });
        }
        Ok(Self {
            t_col: roles.x,
            t_scale,
            p_col: v.col,
            p_scale,
            offset,
            cycle_deg: opts.cycle_deg,
            tdc_deg,
            source,
            cycles,
            sig,
            probe,
            last_t: None,
            first_t: None,
            tdc_time,
            last_line: line,
            file_rpm: rpm,
            flag_rpm: opts.rpm,
            operating_rpm: opts.operating_rpm,
            unused,
            row_others: Vec::with_capacity(others.len()),
            others,
        })
    }

    pub(crate) fn row<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        cells: &impl Cells,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        self.sample(line, |col| cells.number(col, line), out)
    }

    /// Rows `from..n` of columns decoded whole (a binary source), row `r`
    /// on line `line0 + r`, each sampled as [`Self::row`] samples a row of
    /// cells, the numbers taken from the columns; returns how many. It
    /// stops at a row with a value that is not finite, or a column missing
    /// or short: the general path reads that row and names what is wrong.
    pub(crate) fn columns<C: AsRef<[f64]>, F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line0: usize,
        cols: &[C],
        from: usize,
        n: usize,
        out: &mut Emitter<'_, F>,
    ) -> Result<usize, IngestError> {
        let mut read: Vec<&[f64]> = Vec::with_capacity(2 + self.others.len() + 3);
        for c in [self.t_col, self.p_col]
            .into_iter()
            .chain(self.others.iter().map(|o| o.0))
            .chain(self.sig.into_iter().flatten())
        {
            let Some(col) = cols.get(c) else {
                return Ok(0);
            };
            read.push(col.as_ref());
        }
        let end = read.iter().fold(n, |e, c| e.min(c.len()));
        let mut r = from;
        while r < end && read.iter().all(|c| c[r].is_finite()) {
            self.sample(line0 + r, |col| Ok(cols[col].as_ref()[r]), out)?;
            r += 1;
        }
        Ok(r - from)
    }

    /// One sample: `number(col)` gives the number of column `col` (the
    /// unscaled value), read only when the sample needs it, in the order a
    /// row's checks need them, so that a row's first error is the same
    /// from any source.
    fn sample<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        number: impl Fn(usize) -> Result<f64, IngestError>,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let t = number(self.t_col)? * self.t_scale;
        let p = number(self.p_col)? * self.p_scale + self.offset;
        if let Some(was) = self.last_t
            && t <= was
        {
            return Err(at(
                line,
                Some(self.t_col + 1),
                format!(
                    "time {} does not rise after {}: a time record's samples must be in time order",
                    shown_number(t / self.t_scale),
                    shown_number(was / self.t_scale)
                ),
            ));
        }
        self.last_t = Some(t);
        self.last_line = line;
        if self.first_t.is_none() {
            self.first_t = Some(t);
            if let Some(t0) = self.tdc_time
                && t0 < t
            {
                return Err(at(
                    line,
                    Some(self.t_col + 1),
                    format!(
                        "--tdc-time {} s is before the record, which starts at {} s: T must be the time of a firing TDC within the record",
                        enginedyn_numerics::format::human(t0),
                        enginedyn_numerics::format::human(t)
                    ),
                ));
            }
        }
        if !self.others.is_empty() {
            self.row_others.clear();
            for &(col, scale, offset) in &self.others {
                self.row_others.push(number(col)? * scale + offset);
            }
            let held = match &mut self.source {
                Source::Clock(c) => &mut c.others,
                _ => &mut self.cycles.others,
            };
            held.hold(line, self.row_others.iter().copied())?;
        }
        if let Source::Clock(c) = &mut self.source {
            let a = (t - c.t0) * c.deg_per_s - self.tdc_deg.unwrap_or(0.0);
            return c.sample(a, p, line, out);
        }
        let mut v = [0.0; 3];
        for (x, c) in v.iter_mut().zip(self.sig) {
            if let Some(c) = c {
                *x = number(c)?;
            }
        }
        match &mut self.probe {
            Some(held) => {
                held.push((t, p, line, v));
                if held.len() >= PROBE {
                    self.settle(out)?;
                }
                Ok(())
            }
            None => self.signal(t, p, line, v, out),
        }
    }

    /// One sample once the levels are known.
    fn signal<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        t: f64,
        p: f64,
        line: usize,
        v: [f64; 3],
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        match &mut self.source {
            Source::Pulse(s) => s.sample(t, p, v[0], line, &mut self.cycles, out),
            Source::Crank(s) => s.sample(t, p, line, v, &mut self.cycles, out),
            Source::Clock(_) => Ok(()),
        }
    }

    /// Finds each signal's range from the held samples, then reads
    /// them.
    fn settle<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let Some(held) = self.probe.take() else {
            return Ok(());
        };
        let mut levels = [None; 3];
        for (slot, col) in self.sig.iter().enumerate() {
            let Some(col) = *col else { continue };
            let (lo, hi) = held
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), s| {
                    (l.min(s.3[slot]), h.max(s.3[slot]))
                });
            if !(hi - lo > 1e-9 * hi.abs().max(lo.abs()).max(1e-300)) {
                let what = match (slot, &self.source) {
                    (0, Source::Crank(c)) => match c.kind {
                        teeth::Kind::Encoder(_) => {
                            "the `encoder` column is constant over the first {} samples: no edges to take the angle from"
                        }
                        teeth::Kind::Wheel { .. } => {
                            "the `wheel` column is constant over the first {} samples: no teeth to take the angle from"
                        }
                    },
                    (2, _) => {
                        "the `cam` column is constant over the first {} samples: no pulse to tell the firing revolution from"
                    }
                    _ => {
                        "the TDC pulse column is constant over the first {} samples: no pulse to take the angle from"
                    }
                };
                return Err(IngestError::At {
                    line: held.first().map_or(1, |s| s.2),
                    column: Some(col + 1),
                    message: what.replace("{}", &held.len().to_string()),
                });
            }
            levels[slot] = Some((lo, hi));
        }
        match &mut self.source {
            Source::Pulse(s) => s.level(levels[0].unwrap_or((0.0, 0.0))),
            Source::Crank(s) => s.levels(levels[0].unwrap_or((0.0, 0.0)), levels[1], levels[2]),
            Source::Clock(_) => {}
        }
        for (t, p, line, v) in held {
            self.signal(t, p, line, v, out)?;
        }
        Ok(())
    }

    pub(crate) fn end<F: FnMut(Streamed) -> Result<(), IngestError>>(
        mut self,
        out: &mut Emitter<'_, F>,
        head: &mut Header,
    ) -> Result<(), IngestError> {
        self.settle(out)?;
        if let (Some(t0), Some(first), Some(last)) = (self.tdc_time, self.first_t, self.last_t)
            && t0 > last
        {
            return Err(IngestError::Data(format!(
                "--tdc-time {} s is after the record, which spans {} to {} s: T must be the time of a firing TDC within the record",
                enginedyn_numerics::format::human(t0),
                enginedyn_numerics::format::human(first),
                enginedyn_numerics::format::human(last)
            )));
        }
        let line = self.last_line;
        let (mut said, speed, complete, partial) = match &mut self.source {
            Source::Pulse(s) => end_pulse(
                s,
                &mut self.cycles,
                (self.tdc_deg, self.cycle_deg),
                line,
                out,
            )?,
            Source::Crank(s) => end_crank(
                s,
                &mut self.cycles,
                (self.tdc_deg, self.cycle_deg),
                line,
                out,
            )?,
            Source::Clock(c) => {
                c.close(out, true)?;
                (
                    format!(
                        "time record: the angle from a constant {} rpm and firing TDC at t = {} s",
                        fmt(c.deg_per_s / 6.0, 3),
                        enginedyn_numerics::format::sig(c.t0, 6)
                    ),
                    None,
                    c.complete,
                    c.partial,
                )
            }
        };
        if complete == 0 {
            return Err(IngestError::Data(format!(
                "time record: no whole {}° cycle, the window from half a cycle before a firing TDC to half a cycle after ({said})",
                fmt(self.cycle_deg, 0)
            )));
        }
        head.tdc_placement = Some(self.placement());
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let joined = self.cycles.joined || matches!(&self.source, Source::Clock(c) if c.joined);
        if joined {
            let half = fmt(self.cycle_deg / 2.0, 3);
            said.push_str(&format!(
                "; no whole window −{half}…+{half}° around a firing TDC, but one whole cycle from firing TDC to firing TDC: read as a one-cycle diagram"
            ));
        } else {
            said.push_str(&format!(
                "; {complete} whole cycle{}, {}",
                plural(complete),
                crate::trace::window_said(self.cycle_deg, "")
            ));
        }
        if partial > 0 {
            said.push_str(&format!(
                ", {partial} partial {} at the ends left out",
                if partial == 1 { "one" } else { "ones" }
            ));
        }
        head.notes.push(said);
        if !self.unused.is_empty() {
            head.notes
                .push(format!("time record: not used: {}", self.unused.join("; ")));
        }
        if let Some(measured) = speed {
            self.check_speed(measured, head)?;
        }
        Ok(())
    }

    /// The speed the signal `measured` against `--rpm` and the file's:
    /// an error when they disagree by more than [`SPEED_DISAGREES`], a note
    /// where they differ at all; the header's speed when it has none.
    fn check_speed(&self, measured: Measured, head: &mut Header) -> Result<(), IngestError> {
        let Measured {
            mean,
            what,
            every,
            wrong,
            whose,
        } = measured;
        let given = self
            .flag_rpm
            .map(|r| (r, "--rpm"))
            .into_iter()
            .chain(self.file_rpm);
        for (r, source) in given {
            let off = (r - mean).abs() / mean;
            if off > SPEED_DISAGREES {
                let between = if every.is_empty() {
                    String::new()
                } else {
                    format!(
                        " ({every} {} s on average)",
                        enginedyn_numerics::format::sig(60.0 / mean, 4)
                    )
                };
                return Err(IngestError::Data(format!(
                    "{what} gives {} rpm{between}, {source} {} rpm: {:.0} % apart; is the speed or {wrong} wrong?",
                    fmt(mean, 1),
                    fmt(r, 1),
                    100.0 * off
                )));
            }
            if off > SAME_SPEED {
                head.notes.push(format!(
                    "{source} says {} rpm, {whose} {} rpm",
                    fmt(r, 1),
                    fmt(mean, 1)
                ));
            }
        }
        if self.flag_rpm.is_none() && self.file_rpm.is_none() {
            far_from_operating(mean, self.operating_rpm, &what)?;
        }
        if head.rpm.is_none() {
            head.rpm = Some(mean);
        }
        Ok(())
    }
}

/// A measured speed this many times off the engine file's `operating.rpm`
/// (either way) is a unit mix-up, not the engine at another speed.
const SPEED_UNIT_FACTOR: f64 = 50.0;

/// The speed `what` measures (`mean`, rpm) against `operating.rpm`: far
/// off, an error naming the likely unit of the time.
fn far_from_operating(mean: f64, operating: Option<f64>, what: &str) -> Result<(), IngestError> {
    let Some(r) = operating else {
        return Ok(());
    };
    let ratio = mean / r;
    if (1.0 / SPEED_UNIT_FACTOR..=SPEED_UNIT_FACTOR).contains(&ratio) {
        return Ok(());
    }
    // The unit whose factor brings the speed back within the band.
    let near = |x: f64| (1.0 / SPEED_UNIT_FACTOR..=SPEED_UNIT_FACTOR).contains(&(ratio / x));
    let unit = if near(1e-3) {
        "a time in ms read as seconds? name the time column's unit (`time [ms]`) or convert it to seconds"
    } else if near(1e-6) {
        "a time in µs read as seconds? name the time column's unit (`time [us]`) or convert it to seconds"
    } else if near(1e3) {
        "a time in seconds read as ms? check the time column's unit"
    } else {
        "is the time column's unit right? (if the engine ran so, give --rpm)"
    };
    let fmt = |x: f64| enginedyn_numerics::format::sig(x, 4);
    Err(IngestError::Data(format!(
        "{what} gives {} rpm, {} times the engine file's operating.rpm = {} rpm: {unit}",
        fmt(mean),
        fmt(ratio),
        fmt(r)
    )))
}

impl TimeRecord {
    /// What placed firing TDC (the peak-angle rule's error names it).
    fn placement(&self) -> TdcPlacement {
        if let Some(x) = self.tdc_deg {
            return TdcPlacement::TdcDeg {
                deg: x,
                given: true,
            };
        }
        let cam = self.cycles.firing == Firing::Cam;
        match &self.source {
            Source::Clock(c) => TdcPlacement::TdcTime {
                t: c.t0,
                rpm: c.deg_per_s / 6.0,
            },
            Source::Pulse(_) => TdcPlacement::TdcColumn { cam: false },
            Source::Crank(s) => match (&s.kind, self.tdc_time) {
                (teeth::Kind::Wheel { tdc_deg, .. }, _) => {
                    TdcPlacement::WheelTdcDeg { deg: *tdc_deg, cam }
                }
                (teeth::Kind::Encoder(_), Some(t)) => TdcPlacement::TdcTime {
                    t,
                    rpm: s.mean_rpm().unwrap_or(0.0),
                },
                (teeth::Kind::Encoder(_), None) => TdcPlacement::TdcColumn { cam },
            },
        }
    }
}

/// `x` with `d` decimals, trailing zeros trimmed.
fn fmt(x: f64, d: usize) -> String {
    enginedyn_numerics::format::trimmed(x, d)
}

/// The speed a crank signal measured, and how to name it in a message.
struct Measured {
    /// Mean speed (rpm).
    mean: f64,
    /// The column it is taken from.
    what: String,
    /// How often the signal comes ("a pulse every"), or empty.
    every: &'static str,
    /// What may be wrong when it disagrees with a given speed.
    wrong: &'static str,
    /// Whose speed it is, in a note.
    whose: String,
}

/// What a source's end says: the note, the speed measured, and the whole
/// and partial cycles.
type Ended = (String, Option<Measured>, usize, usize);

/// The end of a record whose angle comes from `tdc` pulses: the speed
/// revolution by revolution. `tdc` is `--tdc-deg` (when given) and the
/// cycle (deg).
fn end_pulse<F: FnMut(Streamed) -> Result<(), IngestError>>(
    s: &pulse::Pulse,
    cycles: &mut Cycles,
    (tdc_deg, cycle_deg): (Option<f64>, f64),
    line: usize,
    out: &mut Emitter<'_, F>,
) -> Result<Ended, IngestError> {
    let speeds = s.speeds;
    if speeds.3 == 0 {
        return Err(IngestError::Data(
            "time record: fewer than two TDC pulses, so no revolution to take the speed from"
                .into(),
        ));
    }
    cycles.finish(line, out)?;
    let mean = speeds.2 / speeds.3 as f64 * 60.0;
    let mut said = format!(
        "time record: the angle from {} TDC pulses, the speed revolution by revolution ({} to {} rpm, mean {}); firing TDC {}",
        speeds.3 + 1,
        fmt(speeds.0, 1),
        fmt(speeds.1, 1),
        fmt(mean, 1),
        match (tdc_deg, cycle_deg < 400.0) {
            (Some(x), _) => format!("{}° after the first pulse (--tdc-deg)", fmt(x, 3)),
            (None, true) => "at every pulse (two-stroke)".to_string(),
            (None, false) => format!(
                "at every second pulse from pulse {}, the one the pressure peak follows",
                cycles.parity.unwrap_or(0) + 1
            ),
        }
    );
    if s.before_first > 0 {
        said.push_str("; samples before the first pulse left out");
    }
    let tdc = format!("the `tdc` column (column {})", s.col + 1);
    Ok((
        said,
        Some(Measured {
            mean,
            what: tdc,
            every: "a pulse every",
            wrong: "the pulse column",
            whose: "the `tdc` column's pulses".to_string(),
        }),
        cycles.complete,
        cycles.partial,
    ))
}

/// The end of a record whose angle comes from a crank signal (an encoder
/// or a tooth wheel): its edges checked for a reference and a speed within
/// the engine's bounds. `tdc` is `--tdc-deg` (when given) and the cycle
/// (deg).
fn end_crank<F: FnMut(Streamed) -> Result<(), IngestError>>(
    s: &mut teeth::Crank,
    cycles: &mut Cycles,
    (tdc_deg, cycle_deg): (Option<f64>, f64),
    line: usize,
    out: &mut Emitter<'_, F>,
) -> Result<Ended, IngestError> {
    s.end(cycles, out)?;
    let Some(mean) = s.mean_rpm() else {
        return Err(IngestError::Data(format!(
            "time record: {} edges in the `{}` column, too few to take the angle from",
            s.edge_count,
            name(&s.kind)
        )));
    };
    if s.reference.is_none() {
        return Err(IngestError::Data(match &s.kind {
            teeth::Kind::Wheel { gaps, .. } => format!(
                "time record: no gap among the `wheel` column's {} teeth: not a {} wheel (--wheel), or fewer than a revolution of it",
                s.edge_count, gaps.wheel
            ),
            teeth::Kind::Encoder(e) => match e.tdc_time {
                Some(t0) => format!(
                    "time record: --tdc-time {} s comes before the `encoder` column's first edge: 0° must lie between its edges",
                    enginedyn_numerics::format::human(t0)
                ),
                None => {
                    "time record: no `tdc` pulse after the `encoder` column's first edge, so no 0°"
                        .into()
                }
            },
        }));
    }
    if !(enginedyn_kinematics::MIN_RPM..=enginedyn_kinematics::MAX_RPM).contains(&mean) {
        return Err(IngestError::Data(format!(
            "the `{}` column's edges give {} rpm, outside the engine speed bound (0.001 to 100000 rpm): is --{} right?",
            name(&s.kind),
            enginedyn_numerics::format::sig(mean, 4),
            match s.kind {
                teeth::Kind::Encoder(_) => "encoder-ppr",
                teeth::Kind::Wheel { .. } => "wheel",
            }
        )));
    }
    cycles.finish(line, out)?;
    let source = crank_said(s);
    let firing = match (tdc_deg, cycle_deg < 400.0, cycles.firing) {
        (Some(x), _, _) => format!("{}° after the first TDC (--tdc-deg)", fmt(x, 3)),
        (None, true, _) => "at every TDC (two-stroke)".to_string(),
        (None, false, Firing::Given) => "at --tdc-time and every 720° from it".to_string(),
        (None, false, Firing::Cam) => "at the TDC after each `cam` pulse".to_string(),
        (None, false, Firing::Pressure) => {
            "at every second TDC, the one the pressure peak follows".to_string()
        }
    };
    let mut said = format!(
        "time record: {source}; the speed within the revolutions read {} to {} rpm (mean {}); firing TDC {firing}",
        fmt(s.speeds.0, 1),
        fmt(s.speeds.1, 1),
        fmt(mean, 1),
    );
    if s.before_first > 0 {
        said.push_str("; samples before the first TDC left out");
    }
    let what = format!("the `{}` column (column {})", name(&s.kind), s.col + 1);
    let flag = match s.kind {
        teeth::Kind::Encoder(_) => "--encoder-ppr",
        teeth::Kind::Wheel { .. } => "--wheel",
    };
    Ok((
        said,
        Some(Measured {
            mean,
            what,
            every: "",
            wrong: flag,
            whose: format!("the `{}` column's edges", name(&s.kind)),
        }),
        cycles.complete,
        cycles.partial,
    ))
}

/// Where a crank signal's angle came from, for the record's note.
fn crank_said(s: &teeth::Crank) -> String {
    match &s.kind {
        teeth::Kind::Encoder(e) => format!(
            "the angle from the `encoder` column's {} edges ({} a revolution), interpolated in time between edges (the cubic through the edges around); 0° {}",
            s.edge_count,
            e.ppr,
            match e.tdc_time {
                Some(t0) => format!(
                    "at t = {} s (--tdc-time)",
                    enginedyn_numerics::format::sig(t0, 6)
                ),
                None => format!("at the rise of the `tdc` pulse ({} pulses)", e.pulses),
            }
        ),
        teeth::Kind::Wheel { gaps, tdc_deg } => format!(
            "the angle from the {} tooth wheel in the `wheel` column ({} teeth, the gap found {} times from the tooth periods), interpolated in time between teeth (the cubic through the teeth around); cylinder 1's TDC {}° after the first tooth after the gap (--wheel-tdc-deg)",
            gaps.wheel,
            s.edge_count,
            gaps.count,
            fmt(*tdc_deg, 3)
        ),
    }
}

/// The crank signal's column name.
fn name(kind: &teeth::Kind) -> &'static str {
    match kind {
        teeth::Kind::Encoder(_) => "encoder",
        teeth::Kind::Wheel { .. } => "wheel",
    }
}
