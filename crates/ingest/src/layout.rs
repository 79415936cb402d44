//! Layouts: how rows become traces. The long layout (one sample per row,
//! cycles one after another, perhaps a `cycle` or `cylinder` column), one
//! cycle per column (cycles side by side), and the time record
//! ([`crate::time`]).

use crate::columns::{Axis, Roles, same};
use crate::emit::Emitter;
use crate::error::{IngestError, at, shown_number};
use crate::row::Cells;
use crate::time::TimeRecord;
use crate::trace::Track;
use crate::values::value_scale;
use crate::{Header, MAX_CYCLE, MAX_CYLINDERS, ParseOptions, Quantity, Streamed, Trace};

/// How rows become traces.
pub(crate) enum Layout {
    Long(Long),
    PerColumn(PerColumn),
    Time(Box<TimeRecord>),
}

impl Layout {
    pub(crate) fn new(
        roles: Roles,
        opts: &ParseOptions,
        rpm: Option<(f64, &'static str)>,
        line: usize,
    ) -> Result<Self, IngestError> {
        if let Axis::Time(_) = roles.axis {
            return Ok(Layout::Time(Box::new(TimeRecord::new(
                &roles, opts, rpm, line,
            )?)));
        }
        if roles.values.len() > 1 {
            return Ok(Layout::PerColumn(PerColumn::new(&roles, opts, line)?));
        }
        Ok(Layout::Long(Long::new(&roles, opts, line)?))
    }

    pub(crate) fn row<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        cells: &impl Cells,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        match self {
            Layout::Long(l) => l.row(line, cells, out),
            Layout::PerColumn(p) => p.row(line, cells, out),
            Layout::Time(t) => t.row(line, cells, out),
        }
    }

    pub(crate) fn end<F: FnMut(Streamed) -> Result<(), IngestError>>(
        self,
        out: &mut Emitter<'_, F>,
        head: &mut Header,
    ) -> Result<(), IngestError> {
        match self {
            Layout::Long(l) => {
                // Say what was decided: cycles found one after another in
                // one column, the angle starting again.
                let stacked = (l.cycle_col.is_none() && l.cyl_col.is_none() && l.stacked > 0)
                    .then_some(l.stacked + 1);
                let (ran_on, cycle) = (l.ran_on, l.cycle_deg);
                let (partial, whole, cut) = l.end(out)?;
                if ran_on {
                    head.notes.push(ran_on_note(whole, cut, cycle, &partial));
                } else if let Some(n) = stacked {
                    head.notes.push(format!(
                        "{n} cycles one after another in one column (each where the angle starts again), numbered 1 to {n}"
                    ));
                }
                Ok(())
            }
            Layout::PerColumn(p) => p.end(out),
            Layout::Time(t) => t.end(out, head),
        }
    }
}

/// The note of a record whose angle runs on: `whole` cycles cut at the
/// file's angle `cut` (deg, modulo the `cycle`), the `partial` ones at the
/// ends left out, each said by its samples and the degrees they span (its
/// samples times the record's step, so the same count reads the same).
fn ran_on_note(whole: usize, cut: f64, cycle: f64, partial: &[(&str, usize, f64)]) -> String {
    let mut n = format!(
        "the angle runs on over {whole} whole cycle{}: {}, numbered 1 to {whole}",
        if whole == 1 { "" } else { "s" },
        crate::trace::window_said(
            cycle,
            &format!(
                " (the file's angle {} plus a multiple of {}°)",
                enginedyn_numerics::format::trimmed(cut, 3),
                enginedyn_numerics::format::trimmed(cycle, 3)
            )
        ),
    );
    if !partial.is_empty() {
        let said: Vec<String> = partial
            .iter()
            .map(|(at, samples, step)| {
                let span = if step.is_finite() {
                    format!(
                        ", {}° of the {}° cycle",
                        enginedyn_numerics::format::trimmed(*samples as f64 * step, 1),
                        enginedyn_numerics::format::trimmed(cycle, 3)
                    )
                } else {
                    String::new()
                };
                format!(
                    "{at} ({samples} sample{}{span})",
                    if *samples == 1 { "" } else { "s" }
                )
            })
            .collect();
        n.push_str(&format!(
            "; the partial cycle{} at {} left out: the record begins or ends within {}",
            if partial.len() > 1 { "s" } else { "" },
            said.join(" and "),
            if partial.len() > 1 { "them" } else { "it" }
        ));
    }
    n
}

/// A row with more cells than the names cover (`explicit`: named by
/// `--columns`) is an error that says so: a column is never dropped.
fn width(cells: &impl Cells, ncols: usize, explicit: bool, line: usize) -> Result<(), IngestError> {
    let used = if cells.len() > ncols { cells.used() } else { 0 };
    if used <= ncols {
        return Ok(());
    }
    Err(at(
        line,
        Some(ncols + 1),
        if explicit {
            format!(
                "{used} columns, --columns names {ncols}: name every column (`_` skips one), or end the list with `...` to repeat the last name over the rest (one cycle per column)"
            )
        } else {
            format!("{used} cells, the header names {ncols}: every column needs a name")
        },
    ))
}

/// Angle `a` does not continue its cycle and starts none: why.
fn not_rising(
    line: usize,
    col: usize,
    raw: f64,
    track: &Track,
    tdc: f64,
    cycle: f64,
) -> IngestError {
    let last = track.last_raw() + tdc;
    if raw <= last {
        at(
            line,
            Some(col),
            format!(
                "angle {} does not rise after {}: angles must increase within a cycle (they may wrap once past its end)",
                shown_number(raw),
                shown_number(last)
            ),
        )
    } else {
        at(
            line,
            Some(col),
            format!(
                "angle {} lies more than one {}° cycle after the first ({}); give a `cycle` column to separate cycles",
                shown_number(raw),
                shown_number(cycle),
                shown_number(track.first() + tdc)
            ),
        )
    }
}

/// The cycle being read in the long layout.
pub(crate) struct Current {
    pub trace: Trace,
    /// Its first line.
    pub line: usize,
    pub track: Track,
    /// Started by a closing point (the first angle of the cycle before, a
    /// cycle on): dropped when nothing continues it.
    closing: bool,
}

/// One sample per row.
pub(crate) struct Long {
    pub x: usize,
    pub value: usize,
    /// Degrees (p–φ) or m³ (p–V) per file unit.
    pub x_scale: f64,
    pub pv: bool,
    pub scale: f64,
    pub offset: f64,
    pub tdc: f64,
    pub cycle_deg: f64,
    pub cycle_col: Option<usize>,
    pub cyl_col: Option<usize>,
    pub ncols: usize,
    pub quantity: Quantity,
    pub cur: Option<Current>,
    auto_cycle: i64,
    /// Cycles started by the angle starting again (no `cycle` column).
    stacked: usize,
    /// The angle runs on past the cycle (no `cycle` column): cycles are
    /// the windows around each firing TDC (cut at each gas-exchange TDC),
    /// and the partial ones at the ends left out.
    ran_on: bool,
    /// The partial cycles left out: which end, their samples and the
    /// record's step (deg).
    partial: Vec<(&'static str, usize, f64)>,
    /// The cylinder whose record was last cut at its first window's end.
    cut_for: Option<i64>,
    /// Where the cycles are cut (deg, the file's angle modulo the cycle).
    cut_deg: f64,
    /// Cycles handed on (whole ones, in a record whose angle runs on).
    whole: usize,
    /// The cycle before a closing point (its first angle a cycle on), held
    /// until the next row says whether the point closes it (a digitised
    /// cycle) or begins the next cycle of a record whose angle runs on.
    held: Option<Box<Current>>,
    last_len: usize,
    max_cyl: usize,
    explicit: bool,
    /// `--angle-step` (deg): no x column, row k lies at k times it.
    step: Option<f64>,
    /// Data rows read (the next row's k).
    rows: u64,
}

impl Long {
    fn new(roles: &Roles, opts: &ParseOptions, line: usize) -> Result<Self, IngestError> {
        let v = roles.values[0];
        let (scale, offset) = value_scale(roles, v.scale, opts, line)?;
        let (x_scale, pv) = match roles.axis {
            Axis::Angle(s) => (s, false),
            Axis::Volume(s) => (s, true),
            Axis::Time(s) => (s, false),
        };
        Ok(Self {
            x: roles.x,
            value: v.col,
            x_scale,
            pv,
            scale,
            offset,
            tdc: opts.tdc_deg,
            cycle_deg: opts.cycle_deg,
            cycle_col: roles.cycle,
            cyl_col: roles.cylinder,
            ncols: roles.ncols,
            quantity: roles.quantity,
            cur: None,
            auto_cycle: 1,
            stacked: 0,
            ran_on: false,
            partial: Vec::new(),
            cut_for: None,
            cut_deg: 0.0,
            whole: 0,
            held: None,
            last_len: 16,
            max_cyl: opts.max_cylinder.clamp(1, MAX_CYLINDERS),
            explicit: opts.columns.is_some(),
            step: opts
                .angle_step_deg
                .filter(|_| roles.x == crate::columns::STEPPED_X),
            rows: 0,
        })
    }

    /// The x column as messages name it (1-based); with `--angle-step`
    /// the value column, as there is none.
    fn x_col(&self) -> usize {
        if self.step.is_some() {
            self.value + 1
        } else {
            self.x + 1
        }
    }

    /// True when the fast path may continue this layout's traces.
    pub(crate) fn fast(&self) -> bool {
        !self.pv
            && same(self.x_scale, 1.0)
            && self.cur.is_some()
            && self.step.is_none()
            && self.held.is_none()
    }

    /// True when decoded columns may continue this layout's traces
    /// ([`crate::fast::long_columns`]): as [`Self::fast`], but any scale of
    /// the angle (the columns' path multiplies as [`Self::row`] does).
    pub(crate) fn columnar(&self) -> bool {
        !self.pv && self.cur.is_some() && self.step.is_none() && self.held.is_none()
    }

    fn row<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        cells: &impl Cells,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        width(cells, self.ncols, self.explicit, line)?;
        let x_raw = match self.step {
            // Row k of a record sampled on the crank angle: k times the step.
            Some(step) => {
                self.rows += 1;
                (self.rows - 1) as f64 * step
            }
            None => cells.number(self.x, line)?,
        };
        let p_raw = cells.number(self.value, line)?;
        let cyc = match self.cycle_col {
            Some(i) => Some(whole_cycle(cells.number(i, line)?, line, i)?),
            None => None,
        };
        let cyl = match self.cyl_col {
            Some(i) => cylinder_number(cells.number(i, line)?, line, i, self.max_cyl)?,
            None => 0,
        };
        let p = p_raw * self.scale + self.offset;
        if self.pv {
            let v = x_raw * self.x_scale;
            let cyc = cyc.unwrap_or(self.auto_cycle);
            match self.cur.as_mut() {
                Some(c) if c.trace.cycle == cyc && c.trace.cylinder == cyl => {
                    c.trace.angle_deg.push(v);
                    c.trace.values.push(p);
                    Ok(())
                }
                _ => self.start(line, cyc, cyl, v, p, false, out),
            }
        } else {
            let a = x_raw * self.x_scale - self.tdc;
            let x_col = self.x_col();
            if let Some(prev) = self.held.take() {
                let runs = cyc.is_none()
                    && self
                        .cur
                        .as_ref()
                        .is_some_and(|c| c.trace.cylinder == cyl && c.track.continues(a).is_some());
                if runs {
                    // The angle runs on: the closing point was the next
                    // cycle's first sample.
                    let mut prev = *prev;
                    if let Some(lone) = self.cur.take() {
                        prev.trace.angle_deg.extend(lone.trace.angle_deg);
                        prev.trace.values.extend(lone.trace.values);
                    }
                    self.cur = Some(prev);
                    self.auto_cycle -= 1;
                    self.stacked -= 1;
                    return self.run_on(line, cyl, a, p, out);
                }
                self.send(*prev, out)?;
            }
            let Some(c) = self.cur.as_mut() else {
                let cyc = cyc.unwrap_or(self.auto_cycle);
                return self.start(line, cyc, cyl, a, p, false, out);
            };
            let same_cycle = cyc.is_none_or(|n| n == c.trace.cycle);
            if c.trace.cylinder != cyl || !same_cycle {
                if c.trace.cylinder != cyl {
                    self.auto_cycle = 1;
                }
                let cyc = cyc.unwrap_or(self.auto_cycle);
                return self.start(line, cyc, cyl, a, p, false, out);
            }
            if let Some(w) = c.track.accept(a) {
                c.trace.angle_deg.push(w);
                c.trace.values.push(p);
                return Ok(());
            }
            let closes = c.track.closes(a);
            if self.cycle_col.is_some() {
                if closes {
                    // A digitised cycle repeating its first angle at the end.
                    return Ok(());
                }
                return Err(not_rising(
                    line,
                    x_col,
                    x_raw,
                    &c.track,
                    self.tdc,
                    self.cycle_deg,
                ));
            }
            let runs_on = c.track.runs_on(a);
            if closes && !self.ran_on && !c.track.wrapped() {
                // A closing point, or the next cycle's first sample: the
                // next row tells.
                self.held = self.cur.take().map(Box::new);
                self.auto_cycle += 1;
                self.stacked += 1;
                return self.start(line, self.auto_cycle, cyl, a, p, true, out);
            }
            if runs_on {
                return self.run_on(line, cyl, a, p, out);
            }
            if closes || c.track.starts_next(a) {
                self.auto_cycle += 1;
                self.stacked += 1;
                return self.start(line, self.auto_cycle, cyl, a, p, closes, out);
            }
            Err(not_rising(
                line,
                x_col,
                x_raw,
                &c.track,
                self.tdc,
                self.cycle_deg,
            ))
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn start<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        cycle: i64,
        cylinder: i64,
        a: f64,
        p: f64,
        closing: bool,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        self.flush(out)?;
        let mut angle_deg = Vec::with_capacity(self.last_len.max(16));
        let mut values = Vec::with_capacity(self.last_len.max(16));
        angle_deg.push(a);
        values.push(p);
        self.cur = Some(Current {
            trace: Trace {
                cycle,
                cylinder,
                angle_deg,
                values,
                rpm: None,
            },
            line,
            track: Track::new(a, self.cycle_deg),
            closing,
        });
        Ok(())
    }

    /// Angle `a` runs on past the cycle being read (INTERFACE.md, "A cycle
    /// is the window around its firing TDC"). The first time (for each
    /// cylinder), the cycle read so far, which began at the record's first
    /// sample, is cut where the window rule ([`crate::trace::window`]) cuts
    /// it: at the gas-exchange TDC (a two-stroke's BDC) after the first
    /// sample. What lies before is a cycle of its own when it reaches back
    /// to its window's start (within a step and a half), else a partial
    /// one, left out; what follows begins the next cycle. From then on
    /// every cycle begins at a window's start, and the next one where the
    /// angle reaches a cycle past it.
    fn run_on<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        cyl: i64,
        a: f64,
        p: f64,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        self.ran_on = true;
        if self.cut_for != Some(cyl)
            && let Some(c) = self.cur.take()
        {
            self.cut_for = Some(cyl);
            self.cur = self.first_cut(c, cyl, out)?;
            // `a` continues the new cycle, or begins the one after.
            if let Some(c) = self.cur.as_mut()
                && let Some(w) = c.track.accept(a)
            {
                c.trace.angle_deg.push(w);
                c.trace.values.push(p);
                return Ok(());
            }
        }
        self.auto_cycle += 1;
        self.start(line, self.auto_cycle, cyl, a, p, false, out)
    }

    /// The first cut of a record whose angle runs on: `c`, read from the
    /// record's first sample, is cut at the end of the window holding that
    /// sample; its head handed on when whole, else noted as partial. The
    /// tail is returned as the cycle being read.
    fn first_cut<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        mut c: Current,
        cyl: i64,
        out: &mut Emitter<'_, F>,
    ) -> Result<Option<Current>, IngestError> {
        let cycle = self.cycle_deg;
        let first = c.track.first();
        let n = c.trace.angle_deg.len();
        // The record's step, from what is read so far (about a cycle).
        let step = if n >= 2 {
            (c.trace.angle_deg[n - 1] - first) / (n - 1) as f64
        } else {
            f64::INFINITY
        };
        // Which of the file's TDCs fires decides where the gas exchange's lies.
        let off = out.firing_offset(&c.trace.angle_deg, &c.trace.values, self.quantity, cyl);
        let begins = crate::trace::window(first - off, cycle).1 + off;
        let b = begins + cycle;
        self.cut_deg = (b + self.tdc).rem_euclid(cycle);
        let k = c.trace.angle_deg.partition_point(|&x| x < b - 1e-9);
        if k == n {
            return Ok(Some(c));
        }
        let tail_a = c.trace.angle_deg.split_off(k);
        let tail_v = c.trace.values.split_off(k);
        let whole_head = k >= 4 && first - begins <= 1.5 * step;
        let tail_line = c.line + k;
        let cycle_no = c.trace.cycle;
        if whole_head {
            self.whole += 1;
            self.last_len = k;
            out.trace(c.trace, c.line, self.quantity, self.pv, 0)?;
            self.auto_cycle += 1;
        } else {
            self.partial.push(("the start", k, step));
        }
        let mut track = Track::new(tail_a[0], cycle);
        for &x in &tail_a[1..] {
            track.accept(x);
        }
        Ok(Some(Current {
            trace: Trace {
                cycle: if whole_head { cycle_no + 1 } else { cycle_no },
                cylinder: cyl,
                angle_deg: tail_a,
                values: tail_v,
                rpm: None,
            },
            line: tail_line,
            track,
            closing: false,
        }))
    }

    fn flush<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if let Some(c) = self.cur.take() {
            // A lone closing point: the end of the cycle before, not a cycle.
            if c.closing && c.trace.angle_deg.len() == 1 {
                return Ok(());
            }
            self.send(c, out)?;
        }
        Ok(())
    }

    /// Hands a cycle on.
    fn send<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        c: Current,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        self.last_len = c.trace.angle_deg.len();
        self.whole += 1;
        out.trace(c.trace, c.line, self.quantity, self.pv, 0)
    }

    /// The end of the file: the last cycle handed on, unless the angle
    /// ran on and it stops short of the next firing TDC (by more than a
    /// step and a half): a partial cycle, left out. Returns the partial
    /// cycles left out, the whole ones handed on and where they were cut.
    #[allow(clippy::type_complexity)]
    fn end<F: FnMut(Streamed) -> Result<(), IngestError>>(
        mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(Vec<(&'static str, usize, f64)>, usize, f64), IngestError> {
        if let Some(prev) = self.held.take() {
            self.send(*prev, out)?;
        }
        if self.ran_on
            && let Some(c) = self.cur.as_ref()
        {
            let a = &c.trace.angle_deg;
            let n = a.len();
            let (first, last) = (a[0], a[n - 1]);
            let step = if n >= 2 {
                (last - first) / (n - 1) as f64
            } else {
                f64::INFINITY
            };
            if n == 1 {
                // The first angle of a cycle after the last: the record's
                // closing point.
                self.cur = None;
            } else if n < 4 || first + self.cycle_deg - last > 1.5 * step {
                self.partial.push(("the end", n, step));
                self.cur = None;
            }
        }
        self.flush(out)?;
        Ok((self.partial, self.whole, self.cut_deg))
    }
}

/// A `cycle` cell: a whole number within bounds, never a truncation.
fn whole_cycle(c: f64, line: usize, col: usize) -> Result<i64, IngestError> {
    if c.fract() == 0.0 && (0.0..=MAX_CYCLE).contains(&c) {
        return Ok(c as i64);
    }
    Err(at(
        line,
        Some(col + 1),
        format!(
            "cycle {}: cycle numbers are whole numbers from 0 to 2^53",
            shown_number(c)
        ),
    ))
}

/// A `cylinder` cell: a whole number from 1 to the engine's cylinders.
fn cylinder_number(c: f64, line: usize, col: usize, max_cyl: usize) -> Result<i64, IngestError> {
    if c.fract() == 0.0 && c >= 1.0 && c <= max_cyl as f64 {
        return Ok(c as i64);
    }
    Err(at(
        line,
        Some(col + 1),
        format!(
            "cylinder {}: cylinders are whole numbers from 1 to {max_cyl}{}",
            shown_number(c),
            if max_cyl < MAX_CYLINDERS {
                ", the engine's cylinder count"
            } else {
                ""
            }
        ),
    ))
}

/// One cycle (or one cylinder) per column: an angle column and several
/// value columns, whose cycles run side by side.
pub(crate) struct PerColumn {
    pub x: usize,
    pub x_scale: f64,
    pub tdc: f64,
    pub cycle_deg: f64,
    /// Column, Pa per unit, cylinder (0: the columns are cycles).
    pub cols: Vec<(usize, f64, i64)>,
    pub offset: f64,
    pub ncols: usize,
    pub quantity: Quantity,
    /// The cycle's angles, one a row (deg, moved by the wrap).
    pub angles: Vec<f64>,
    /// The cycle's values, row by row, one per column (`cols`): 8 bytes a
    /// value (INTERFACE.md, "Bounds"); NaN marks an empty cell, a missing
    /// sample of that column's cycle (a cell's number is always finite).
    pub values: Vec<f64>,
    pub track: Option<Track>,
    pub line: usize,
    block: i64,
    closing: bool,
    explicit: bool,
    /// Rows in the cycle before: the next one's capacity.
    last_len: usize,
}

impl PerColumn {
    fn new(roles: &Roles, opts: &ParseOptions, line: usize) -> Result<Self, IngestError> {
        let max_cyl = opts.max_cylinder.clamp(1, MAX_CYLINDERS) as i64;
        let mut cols = Vec::with_capacity(roles.values.len());
        let mut offset = 0.0;
        for v in &roles.values {
            let (scale, off) = value_scale(roles, v.scale, opts, line)?;
            offset = off;
            let cylinder = if roles.per_cylinder { v.cylinder } else { 0 };
            if cylinder > max_cyl {
                return Err(at(
                    line.saturating_sub(1).max(1),
                    Some(v.col + 1),
                    format!("the column names cylinder {cylinder}; the engine has {max_cyl}"),
                ));
            }
            cols.push((v.col, scale, cylinder));
        }
        let x_scale = match roles.axis {
            Axis::Angle(s) => s,
            _ => 1.0,
        };
        Ok(Self {
            x: roles.x,
            x_scale,
            tdc: opts.tdc_deg,
            cycle_deg: opts.cycle_deg,
            angles: Vec::new(),
            values: Vec::new(),
            cols,
            offset,
            ncols: roles.ncols,
            quantity: roles.quantity,
            track: None,
            line,
            block: 0,
            closing: false,
            explicit: opts.columns.is_some(),
            last_len: 16,
        })
    }

    /// True when the fast path may continue this layout's traces.
    pub(crate) fn fast(&self) -> bool {
        same(self.x_scale, 1.0) && self.track.is_some()
    }

    fn row<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        cells: &impl Cells,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        width(cells, self.ncols, self.explicit, line)?;
        let x_raw = cells.number(self.x, line)?;
        let a = x_raw * self.x_scale - self.tdc;
        let w = match self.track.as_mut() {
            None => {
                self.start(line, a, false, out)?;
                a
            }
            Some(t) => match t.accept(a) {
                Some(w) => w,
                None => {
                    let closes = t.closes(a);
                    if closes || t.starts_next(a) {
                        self.start(line, a, closes, out)?;
                        a
                    } else {
                        return Err(not_rising(
                            line,
                            self.x + 1,
                            x_raw,
                            t,
                            self.tdc,
                            self.cycle_deg,
                        ));
                    }
                }
            },
        };
        // Every cell is read before any is kept, so an error leaves the
        // cycle as it was.
        let start = self.values.len();
        for &(col, scale, _) in &self.cols {
            // An empty cell is a missing sample of that cycle.
            let v = if cells.is_blank(col) {
                f64::NAN
            } else {
                match cells.number(col, line) {
                    Ok(x) => x * scale + self.offset,
                    Err(e) => {
                        self.values.truncate(start);
                        return Err(e);
                    }
                }
            };
            self.values.push(v);
        }
        self.angles.push(w);
        if self.closing && self.angles.len() > 1 {
            self.closing = false;
        }
        Ok(())
    }

    fn start<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        a: f64,
        closing: bool,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        self.flush(out)?;
        self.block += 1;
        self.angles = Vec::with_capacity(self.last_len);
        self.values = Vec::with_capacity(self.last_len * self.cols.len());
        self.track = Some(Track::new(a, self.cycle_deg));
        self.line = line;
        self.closing = closing;
        Ok(())
    }

    /// Hands the cycle's columns on, one trace at a time (one column's
    /// samples, empty cells left out), so only one is ever built.
    fn flush<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        let angles = std::mem::take(&mut self.angles);
        let values = std::mem::take(&mut self.values);
        if self.track.is_none() {
            return Ok(());
        }
        self.last_len = angles.len().max(16);
        if self.closing && angles.len() <= 1 {
            return Ok(());
        }
        let m = self.cols.len();
        let per_cylinder = self.cols.iter().any(|c| c.2 > 0);
        for (j, c) in self.cols.iter().enumerate() {
            let mut t = Trace {
                cycle: if per_cylinder {
                    self.block
                } else {
                    (self.block - 1) * m as i64 + j as i64 + 1
                },
                cylinder: c.2,
                angle_deg: Vec::with_capacity(angles.len()),
                values: Vec::with_capacity(angles.len()),
                rpm: None,
            };
            for (r, &a) in angles.iter().enumerate() {
                let v = values[r * m + j];
                if !v.is_nan() {
                    t.angle_deg.push(a);
                    t.values.push(v);
                }
            }
            out.trace(t, self.line, self.quantity, false, j)?;
        }
        Ok(())
    }

    fn end<F: FnMut(Streamed) -> Result<(), IngestError>>(
        mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        self.flush(out)
    }
}
