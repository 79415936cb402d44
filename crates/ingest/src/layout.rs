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
                l.end(out)?;
                if let Some(n) = stacked {
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
    last_len: usize,
    max_cyl: usize,
    explicit: bool,
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
            last_len: 16,
            max_cyl: opts.max_cylinder.clamp(1, MAX_CYLINDERS),
            explicit: opts.columns.is_some(),
        })
    }

    /// True when the fast path may continue this layout's traces.
    pub(crate) fn fast(&self) -> bool {
        !self.pv && same(self.x_scale, 1.0) && self.cur.is_some()
    }

    fn row<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        line: usize,
        cells: &impl Cells,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        width(cells, self.ncols, self.explicit, line)?;
        let x_raw = cells.number(self.x, line)?;
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
                    self.x + 1,
                    x_raw,
                    &c.track,
                    self.tdc,
                    self.cycle_deg,
                ));
            }
            if closes || c.track.starts_next(a) {
                self.auto_cycle += 1;
                self.stacked += 1;
                return self.start(line, self.auto_cycle, cyl, a, p, closes, out);
            }
            Err(not_rising(
                line,
                self.x + 1,
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

    fn flush<F: FnMut(Streamed) -> Result<(), IngestError>>(
        &mut self,
        out: &mut Emitter<'_, F>,
    ) -> Result<(), IngestError> {
        if let Some(c) = self.cur.take() {
            // A lone closing point: the end of the cycle before, not a cycle.
            if c.closing && c.trace.angle_deg.len() == 1 {
                return Ok(());
            }
            self.last_len = c.trace.angle_deg.len();
            out.trace(c.trace, c.line, self.quantity, self.pv, 0)?;
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
