//! The arrays source: named columns already in memory (a NumPy caller's
//! arrays), handed to the reader row by row as a file's rows would be, so
//! that every rule of the reader (column roles, cycles, gaps, the axis,
//! plausibility) applies to them unchanged. Line 0 is the names; line k is
//! the k-th sample (from 1).

use crate::error::{IngestError, at};
use crate::reader::Reader;
use crate::row::Cells;
use crate::{Header, ParseOptions, Streamed};
use std::borrow::Cow;

/// The names row.
struct Names<'a>(&'a [String]);

impl Cells for Names<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        self.0.get(i).is_none_or(|s| s.trim().is_empty())
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        Cow::Borrowed(self.0.get(i).map_or("", String::as_str))
    }
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        Err(at(line, Some(i + 1), "a name, not a number"))
    }
}

/// One sample of every column: a value that is not finite (NaN, ±inf) is
/// an error at its sample and column, as an unreadable cell is.
struct Sample(Vec<f64>);

impl Cells for Sample {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        i >= self.0.len()
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        Cow::Owned(self.0.get(i).map(|v| v.to_string()).unwrap_or_default())
    }
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        match self.0.get(i) {
            Some(v) if v.is_finite() => Ok(*v),
            Some(v) => Err(at(
                line,
                Some(i + 1),
                format!(
                    "{v} is not a finite number: drop the samples where a value is missing (from every array alike: a gap up to max_gap_deg is bridged), or give each sample's cycle (cycle=) so that a dropout's cycle is left out"
                ),
            )),
            None => Err(at(line, Some(i + 1), "no value")),
        }
    }
}

/// Hands `columns` (all of one length), named by `names`, to the reader.
pub(crate) fn read<F: FnMut(Streamed) -> Result<(), IngestError>>(
    names: &[String],
    columns: &[&[f64]],
    opts: &ParseOptions,
    sink: F,
) -> Result<Header, IngestError> {
    if names.len() != columns.len() {
        return Err(IngestError::Data(format!(
            "{} names for {} columns",
            names.len(),
            columns.len()
        )));
    }
    let n = columns.first().map_or(0, |c| c.len());
    if let Some((k, c)) = columns.iter().enumerate().find(|(_, c)| c.len() != n) {
        return Err(IngestError::Data(format!(
            "column `{}` has {} values, `{}` has {n}: the columns must be of one length",
            names[k],
            c.len(),
            names[0]
        )));
    }
    let mut rd = Reader::new(opts, sink);
    rd.names_given = true;
    rd.row(0, &Names(names), || None)?;
    // Handed over as columns (slices of the caller's, no copy), a block of
    // rows at a time (the reader takes runs that continue a cycle whole; a
    // row it stops at is read as the cells of `Sample`, as every row was
    // before), cancellable between blocks.
    let mut start = 0;
    while start < n {
        opts.cancel.check()?;
        let end = (start + BLOCK_ROWS).min(n);
        let cols: Vec<&[f64]> = columns.iter().map(|c| &c[start..end]).collect();
        let cols = &*cols;
        rd.columns(start + 1, cols, end - start, |r| {
            Sample(cols.iter().map(|c| c[r]).collect())
        })?;
        start = end;
    }
    rd.end()
}

/// Rows handed to the reader at a time (the cancellation's granularity).
const BLOCK_ROWS: usize = 65_536;

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain definition: every sample handed over as its own row, as
    /// the reader read arrays before they went as columns.
    fn by_rows(
        names: &[String],
        columns: &[&[f64]],
        opts: &ParseOptions,
    ) -> Result<(Header, Vec<String>), IngestError> {
        let mut got = Vec::new();
        let mut rd = Reader::new(opts, |s: Streamed| {
            got.push(format!("{:?} {:?} {:?}", s.trace, s.quantity, s.steps));
            Ok(())
        });
        rd.names_given = true;
        rd.row(0, &Names(names), || None)?;
        for k in 0..columns[0].len() {
            let row: Vec<f64> = columns.iter().map(|c| c[k]).collect();
            rd.row(k + 1, &Sample(row), || None)?;
        }
        let h = rd.end()?;
        Ok((h, got))
    }

    fn by_columns(
        names: &[String],
        columns: &[&[f64]],
        opts: &ParseOptions,
    ) -> Result<(Header, Vec<String>), IngestError> {
        let mut got = Vec::new();
        let h = read(names, columns, opts, |s: Streamed| {
            got.push(format!("{:?} {:?} {:?}", s.trace, s.quantity, s.steps));
            Ok(())
        })?;
        Ok((h, got))
    }

    /// Arrays read as columns give what they gave row by row, on data
    /// shaped against the shortcut: a record across the block boundary, a
    /// cycle column that changes inside a block and at its edge, a NaN in
    /// the middle (the same error, at the same sample and column), an
    /// angle that steps back, a gap.
    #[test]
    fn columns_read_as_the_rows_did() {
        let opts = ParseOptions::new(720.0);
        let names: Vec<String> = ["crank_deg", "pressure_bar", "cycle"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let n = BLOCK_ROWS + 7_300;
        let step = 0.1;
        let per_cycle = 7_200;
        let angle: Vec<f64> = (0..n)
            .map(|k| (k % per_cycle) as f64 * step - 360.0)
            .collect();
        let pressure: Vec<f64> = (0..n)
            .map(|k| 1.0 + 40.0 * (-(((k % per_cycle) as f64 * step - 360.0) / 30.0).powi(2)).exp())
            .collect();
        let cycle: Vec<f64> = (0..n).map(|k| (k / per_cycle) as f64).collect();
        let mut cases: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> =
            vec![(angle.clone(), pressure.clone(), cycle.clone())];
        let mut nan = pressure.clone();
        nan[BLOCK_ROWS + 11] = f64::NAN;
        cases.push((angle.clone(), nan, cycle.clone()));
        let mut back = angle.clone();
        back[BLOCK_ROWS - 1] -= 5.0;
        cases.push((back, pressure.clone(), cycle.clone()));
        let mut gap_a = angle.clone();
        let mut gap_p = pressure.clone();
        let mut gap_c = cycle.clone();
        for v in [&mut gap_a, &mut gap_p, &mut gap_c] {
            v.drain(100..130);
        }
        cases.push((gap_a, gap_p, gap_c));
        for (k, (a, p, c)) in cases.iter().enumerate() {
            let cols: [&[f64]; 3] = [a, p, c];
            let rows = by_rows(&names, &cols, &opts);
            let columns = by_columns(&names, &cols, &opts);
            if k == 0 {
                let traces = rows.as_ref().map(|(_, t)| t.len());
                assert!(matches!(traces, Ok(t) if t >= 10), "{traces:?}");
            }
            if k == 1 {
                assert!(rows.is_err(), "a NaN is refused");
            }
            assert_eq!(format!("{rows:?}"), format!("{columns:?}"), "case {k}");
        }
    }
}
