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
struct Sample<'a>(&'a [f64]);

impl Cells for Sample<'_> {
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
    let mut row = vec![0.0; columns.len()];
    for k in 0..n {
        if k % 65_536 == 0 {
            opts.cancel.check()?;
        }
        for (v, c) in row.iter_mut().zip(columns) {
            *v = c[k];
        }
        rd.row(k + 1, &Sample(&row), || None)?;
    }
    rd.end()
}
