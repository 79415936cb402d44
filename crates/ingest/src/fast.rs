//! The fast paths: tight loops over the read buffer for the rows that only
//! continue the cycles being read (plain decimals, the same cycle and
//! cylinder, an angle the trace builder's [`Track::continues`] accepts). At
//! the first row that does anything else they stop without reading it and
//! return "switch to the general path" (as ripgrep's searcher does), which
//! reads that row exactly as it would have without them: the acceptance
//! rule lives in the builder alone. A binary source's columns, decoded
//! whole, take the same paths without the parsing ([`long_columns`],
//! [`per_column_columns`]).

use crate::Trace;
use crate::layout::{Long, PerColumn};
use crate::number::{PLAIN_CELLS, Shapes, plain_row, shaped_cell};
use crate::template::{ROW, Template};
#[cfg(doc)]
use crate::trace::Track;

/// Rows [`long`] holds before it appends them to the trace.
const BATCH: usize = 64;

/// Angles and values of rows read, appended to the trace a batch at a
/// time: a store each in the row loop, where a push would check and store
/// the vector's length every row.
struct Batch {
    angles: [f64; BATCH],
    values: [f64; BATCH],
    k: usize,
}

impl Batch {
    #[inline(always)]
    fn push(&mut self, a: f64, v: f64, tr: &mut Trace) {
        self.angles[self.k % BATCH] = a;
        self.values[self.k % BATCH] = v;
        self.k += 1;
        if self.k == BATCH {
            self.flush(tr);
        }
    }

    /// Appends the rows held to the trace.
    #[inline(never)]
    fn flush(&mut self, tr: &mut Trace) {
        tr.angle_deg.extend_from_slice(&self.angles[..self.k]);
        tr.values.extend_from_slice(&self.values[..self.k]);
        self.k = 0;
    }
}

/// Plain rows of `w` that continue the long layout's current trace are
/// appended to it; returns the bytes and rows used. A row that repeats the
/// one before but for the angle's step is checked against a [`Template`]
/// (one comparison for the cells before the value) and only its value is
/// read; others are read by [`plain_row`] and may seed the next template.
/// Its own function, so that its few variables live in registers.
#[inline(never)]
pub(crate) fn long(w: &[u8], eof: bool, sep: u8, l: &mut Long) -> (usize, usize) {
    let (x, value, ncols) = (l.x, l.value, l.ncols);
    let (scale, offset, tdc) = (l.scale, l.offset, l.tdc);
    let (cycle_col, cyl_col) = (l.cycle_col, l.cyl_col);
    let Some(cur) = l.cur.as_mut() else {
        return (0, 0);
    };
    if ncols > PLAIN_CELLS {
        return (0, 0);
    }
    let tr = &mut cur.trace;
    // A copy in registers, written back at the end.
    let mut track = cur.track;
    let mut vals = [0.0; PLAIN_CELLS];
    let mut shapes = [Shapes::default(); PLAIN_CELLS];
    let decimal_comma = sep != b',';
    let (mut used, mut n) = (0, 0);
    // Templates (template.rs) need the value last, after cells that are
    // cycle, cylinder or the angle only.
    let templates = value + 1 == ncols
        && (0..value).all(|i| i == x || cycle_col == Some(i) || cyl_col == Some(i));
    let mut template: Option<Template> = None;
    let mut batch = Batch {
        angles: [0.0; BATCH],
        values: [0.0; BATCH],
        k: 0,
    };
    // Rows to wait before seeding again after a template that read nothing.
    let mut backoff = 0usize;
    let (cycle_bits, cyl_bits) = ((tr.cycle as f64).to_bits(), (tr.cylinder as f64).to_bits());
    // Rows are read while more than 512 bytes are left, or to the end of
    // the file.
    let stop = if eof {
        usize::MAX
    } else {
        w.len().saturating_sub(512)
    };
    while used < stop {
        if let Some(t) = template.as_mut() {
            if let Some(row) = w
                .get(used..used + ROW)
                .and_then(|r| <&[u8; ROW]>::try_from(r).ok())
                && let Some((x_raw, v, len)) = t.next(row, decimal_comma)
            {
                let Some(a) = track.continues(x_raw - tdc) else {
                    break;
                };
                track.take(a);
                batch.push(a, v * scale + offset, tr);
                used += len;
                n += 1;
                continue;
            }
            if t.rows == 0 {
                backoff = 32;
            }
            template = None;
        }
        let Some((k, len)) = plain_row(&w[used..], sep, decimal_comma, eof, &mut vals, &mut shapes)
        else {
            break;
        };
        // Exactly the trace's numbers: `1.5` after `1` is not cylinder 1
        // (the general path says why).
        if k != ncols
            || cycle_col.is_some_and(|i| vals[i].to_bits() != cycle_bits)
            || cyl_col.is_some_and(|i| vals[i].to_bits() != cyl_bits)
        {
            break;
        }
        let Some(a) = track.continues(vals[x] - tdc) else {
            break;
        };
        if templates {
            if backoff == 0 {
                template = Template::seed(&w[used..used + len], sep, x, value, a - track.last());
            } else {
                backoff -= 1;
            }
        }
        track.take(a);
        batch.push(a, vals[value] * scale + offset, tr);
        used += len;
        n += 1;
    }
    batch.flush(tr);
    cur.track = track;
    (used, n)
}

/// Plain rows of `w` that continue the cycles of a one-cycle-per-column
/// layout: the angle, then a value for every column (a delimiter may close
/// the row). Every cell of a row is read before any is kept, so a row it
/// stops at is left whole for the general path.
#[inline(never)]
pub(crate) fn per_column(
    w: &[u8],
    eof: bool,
    sep: u8,
    pc: &mut PerColumn,
    row: &mut Vec<f64>,
) -> (usize, usize) {
    let Some(mut track) = pc.track else {
        return (0, 0);
    };
    let m = pc.cols.len();
    // Columns in file order, one after another after the angle.
    if pc.x != 0 || pc.cols.iter().enumerate().any(|(j, c)| c.0 != j + 1) {
        return (0, 0);
    }
    let decimal_comma = sep != b',';
    let (mut used, mut n) = (0, 0);
    row.resize(m + 1, 0.0);
    // The values mostly share one shape (`87.14250`); the angle has its own.
    let (mut angle_shape, mut value_shape) = (Shapes::default(), Shapes::default());
    'rows: while eof || used + 4096 < w.len() {
        let b = &w[used..];
        let mut i = 0;
        for (j, cell) in row.iter_mut().enumerate() {
            let shapes = if j == 0 {
                &mut angle_shape
            } else {
                &mut value_shape
            };
            let Some((v, end)) = shaped_cell(b, i, decimal_comma, shapes) else {
                break 'rows;
            };
            *cell = v;
            i = end;
            // A delimiter after every cell; after the last it may close the row.
            if b.get(i) == Some(&sep) {
                i += 1;
            } else if j < m {
                break 'rows;
            }
        }
        // The row ends here.
        let end = match b.get(i) {
            Some(b'\n') => i + 1,
            Some(b'\r') if b.get(i + 1) == Some(&b'\n') => i + 2,
            None if eof && i > 0 => i,
            _ => break,
        };
        let Some(a) = track.continues(row[0] - pc.tdc) else {
            break;
        };
        track.take(a);
        pc.angles.push(a);
        for (j, &(_, scale, _)) in pc.cols.iter().enumerate() {
            pc.values.push(row[j + 1] * scale + pc.offset);
        }
        used += end;
        n += 1;
    }
    pc.track = Some(track);
    (used, n)
}

/// Rows `from..n` of decoded columns (a binary source, one column a
/// channel) that continue the long layout's current trace, appended to it;
/// returns how many. What [`long`] takes, with the numbers already read:
/// the angle and the value finite, the cycle and cylinder exactly the
/// trace's, the angle one [`Track::continues`] accepts. The row it stops at
/// is left to the general path, which reads it as it would have anyway.
#[inline(never)]
pub(crate) fn long_columns<C: AsRef<[f64]>>(
    l: &mut Long,
    cols: &[C],
    from: usize,
    n: usize,
) -> usize {
    if !l.columnar() || cols.len() > l.ncols {
        return 0;
    }
    // An optional column: `Some(None)` when there is none, `None` when the
    // index lies past the columns (the general path names that).
    let optional = |i: Option<usize>| match i {
        None => Some(None),
        Some(i) => cols.get(i).map(|c| Some(c.as_ref())),
    };
    let (Some(xs), Some(ps)) = (cols.get(l.x), cols.get(l.value)) else {
        return 0;
    };
    let (xs, ps) = (xs.as_ref(), ps.as_ref());
    let (Some(cycles), Some(cylinders)) = (optional(l.cycle_col), optional(l.cyl_col)) else {
        return 0;
    };
    let (x_scale, scale, offset, tdc) = (l.x_scale, l.scale, l.offset, l.tdc);
    let Some(cur) = l.cur.as_mut() else {
        return 0;
    };
    let tr = &mut cur.trace;
    let mut track = cur.track;
    let (cycle_bits, cyl_bits) = ((tr.cycle as f64).to_bits(), (tr.cylinder as f64).to_bits());
    let end = [Some(xs), Some(ps), cycles, cylinders]
        .into_iter()
        .flatten()
        .fold(n, |e, c| e.min(c.len()));
    // The run the trace takes, found first; then its angles and values
    // appended in one reserved pass each, the angle as `continues` gives it
    // (moved by the track's wrap, which the run does not change).
    let mut r = from;
    // Whole blocks of rows first, each checked without a branch a row; the
    // block that stops the run is then read row by row below.
    // (An angle that is not finite never continues the track, so only the
    // values are checked for that here.)
    const B: usize = 8;
    let ids: Vec<(&[f64], u64)> = [
        cycles.map(|c| (c, cycle_bits)),
        cylinders.map(|c| (c, cyl_bits)),
    ]
    .into_iter()
    .flatten()
    .collect();
    while r + B <= end {
        let (x, p) = (&xs[r..r + B], &ps[r..r + B]);
        let a: [f64; B] = std::array::from_fn(|k| x[k] * x_scale - tdc);
        let mut ok = true;
        for k in 0..B {
            ok &= p[k].is_finite();
        }
        for &(c, bits) in &ids {
            ok &= c[r..r + B]
                .iter()
                .fold(true, |all, v| all & (v.to_bits() == bits));
        }
        let Some(w) = track.continues_all(&a).filter(|_| ok) else {
            break;
        };
        track.take(w);
        r += B;
    }
    while r < end {
        let (x, p) = (xs[r], ps[r]);
        if !x.is_finite()
            || !p.is_finite()
            || cycles.is_some_and(|c| c[r].to_bits() != cycle_bits)
            || cylinders.is_some_and(|c| c[r].to_bits() != cyl_bits)
        {
            break;
        }
        let Some(a) = track.continues(x * x_scale - tdc) else {
            break;
        };
        track.take(a);
        r += 1;
    }
    let shift = track.shift();
    tr.angle_deg
        .extend(xs[from..r].iter().map(|&x| (x * x_scale - tdc) + shift));
    tr.values
        .extend(ps[from..r].iter().map(|&p| p * scale + offset));
    cur.track = track;
    r - from
}

/// Rows `from..n` of decoded columns that continue the cycles of a
/// one-cycle-per-column layout; returns how many. As [`per_column`]: every
/// value of a row is checked (finite) before any is kept, so the row it
/// stops at is left whole to the general path.
#[inline(never)]
pub(crate) fn per_column_columns<C: AsRef<[f64]>>(
    pc: &mut PerColumn,
    cols: &[C],
    from: usize,
    n: usize,
) -> usize {
    let Some(mut track) = pc.track else {
        return 0;
    };
    if cols.len() > pc.ncols || pc.cols.iter().any(|c| c.0 >= cols.len()) {
        return 0;
    }
    let cols: Vec<&[f64]> = cols.iter().map(AsRef::as_ref).collect();
    let Some(xs) = cols.get(pc.x) else {
        return 0;
    };
    let end = pc
        .cols
        .iter()
        .fold(n.min(xs.len()), |e, c| e.min(cols[c.0].len()));
    let mut r = from;
    'rows: while r < end {
        let x = xs[r];
        if !x.is_finite() {
            break;
        }
        let Some(a) = track.continues(x * pc.x_scale - pc.tdc) else {
            break;
        };
        for &(c, _, _) in &pc.cols {
            if !cols[c][r].is_finite() {
                break 'rows;
            }
        }
        track.take(a);
        pc.angles.push(a);
        for &(c, scale, _) in &pc.cols {
            pc.values.push(cols[c][r] * scale + pc.offset);
        }
        r += 1;
    }
    pc.track = Some(track);
    r - from
}
