//! A row of cells, whatever the source: a text line split by its
//! delimiter, numbers the fast path already read, or a spreadsheet row.

use crate::error::{IngestError, at};
use std::borrow::Cow;

/// The cells of one row.
pub(crate) trait Cells {
    /// Number of cells, empty ones included.
    fn len(&self) -> usize;
    /// True when cell `i` is empty or absent.
    fn is_blank(&self, i: usize) -> bool;
    /// Cell `i` as text (empty when absent).
    fn text(&self, i: usize) -> Cow<'_, str>;
    /// Cell `i` as a number; an error names `line` and the column.
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError>;
    /// The row as written, where the source has it (a text line).
    fn raw(&self) -> Option<Cow<'_, str>> {
        None
    }
    /// Cells up to the last one that is not empty.
    fn used(&self) -> usize {
        let mut n = self.len();
        while n > 0 && self.is_blank(n - 1) {
            n -= 1;
        }
        n
    }
    /// True for a data row: its first cell that is not empty is a number,
    /// and so is another (a status or comment column may hold text).
    fn is_data(&self) -> bool {
        let n = self.used();
        let Some(first) = (0..n).find(|&i| !self.is_blank(i)) else {
            return false;
        };
        self.number(first, 0).is_ok()
            && (n == first + 1
                || (first + 1..n).any(|i| !self.is_blank(i) && self.number(i, 0).is_ok()))
    }
}

/// A text line and the byte ranges of its cells.
pub(crate) struct TextRow<'a> {
    pub line: &'a [u8],
    pub spans: &'a [(usize, usize)],
    pub decimal_comma: bool,
}

impl Cells for TextRow<'_> {
    fn len(&self) -> usize {
        self.spans.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        self.spans.get(i).is_none_or(|(s, e)| s == e)
    }
    fn raw(&self) -> Option<Cow<'_, str>> {
        Some(String::from_utf8_lossy(self.line))
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        match self.spans.get(i) {
            Some(&(s, e)) => String::from_utf8_lossy(&self.line[s..e]),
            None => Cow::Borrowed(""),
        }
    }
    #[inline]
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        match self.spans.get(i) {
            Some(&(s, e)) => {
                crate::number::number(&self.line[s..e], self.decimal_comma, line, i + 1)
            }
            None => Err(missing(i, line)),
        }
    }
}

/// Numbers the fast path read from a plain row.
pub(crate) struct Numbers<'a>(pub &'a [f64]);

impl Cells for Numbers<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        i >= self.0.len()
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        Cow::Owned(self.0.get(i).map(|v| v.to_string()).unwrap_or_default())
    }
    #[inline]
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        self.0.get(i).copied().ok_or_else(|| missing(i, line))
    }
}

/// A spreadsheet cell.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum SheetCell {
    Number(f64),
    Text(String),
    Empty,
}

/// A spreadsheet row.
pub(crate) struct SheetRow<'a>(pub &'a [SheetCell]);

impl Cells for SheetRow<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        match self.0.get(i) {
            None | Some(SheetCell::Empty) => true,
            Some(SheetCell::Text(t)) => t.trim().is_empty(),
            Some(SheetCell::Number(_)) => false,
        }
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        match self.0.get(i) {
            Some(SheetCell::Text(t)) => Cow::Borrowed(t.as_str()),
            Some(SheetCell::Number(v)) => Cow::Owned(v.to_string()),
            _ => Cow::Borrowed(""),
        }
    }
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        match self.0.get(i) {
            Some(SheetCell::Number(v)) if v.is_finite() => Ok(*v),
            // Numbers stored as text (a CSV pasted into a sheet): read as text is.
            Some(SheetCell::Text(t)) => {
                crate::number::number(t.trim().as_bytes(), true, line, i + 1)
            }
            _ => Err(missing(i, line)),
        }
    }
}

fn missing(i: usize, line: usize) -> IngestError {
    at(line, Some(i + 1), "an empty cell where a number is needed")
}
