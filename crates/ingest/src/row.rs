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
    /// Checks that the cells of columns `cols` (angle, pressure or volume
    /// columns) may hold such a value: a spreadsheet cell formatted as a
    /// date or time may not. Text cells always may.
    #[inline(always)]
    fn measured(&self, _cols: &[usize], _line: usize) -> Result<(), IngestError> {
        Ok(())
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
        Some(decode(self.line))
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        match self.spans.get(i) {
            Some(&(s, e)) => decode(&self.line[s..e]),
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
    /// A number formatted as a date, time or duration (Excel's serial day
    /// number where there is one), or an ISO date or duration (.ods).
    Date(Box<DateCell>),
    /// A formula the file stores no value for: never calculated.
    Formula,
    /// An error value, as the spreadsheet shows it (`#DIV/0!`).
    Error(&'static str),
}

/// A date- or time-formatted cell: what the format makes of it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DateCell {
    /// `a date`, `a time of day`, `a date and time`, `a duration`.
    pub kind: &'static str,
    /// The cell as the spreadsheet shows it (`2020-01-01`).
    pub shown: String,
    /// Excel's serial number (days), where the file stores one.
    pub serial: Option<f64>,
}

/// A spreadsheet row.
pub(crate) struct SheetRow<'a>(pub &'a [SheetCell]);

/// Excel's name of a column (1-based: 1 is `A`, 27 is `AA`).
pub(crate) fn column_name(mut col: usize) -> String {
    let mut name = Vec::new();
    while col > 0 {
        col -= 1;
        name.push(b'A' + (col % 26) as u8);
        col /= 26;
    }
    name.reverse();
    String::from_utf8(name).unwrap_or_default()
}

impl SheetRow<'_> {
    /// Cell `i` holds something a measured value or a number stands for:
    /// a date, a formula or an error value (read, and refused, where a
    /// number is needed).
    fn value_like(&self, i: usize) -> bool {
        matches!(
            self.0.get(i),
            Some(SheetCell::Date(_) | SheetCell::Formula | SheetCell::Error(_))
        )
    }
}

impl Cells for SheetRow<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        match self.0.get(i) {
            None | Some(SheetCell::Empty) => true,
            Some(SheetCell::Text(t)) => t.trim().is_empty(),
            Some(
                SheetCell::Number(_)
                | SheetCell::Date(_)
                | SheetCell::Formula
                | SheetCell::Error(_),
            ) => false,
        }
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        match self.0.get(i) {
            Some(SheetCell::Text(t)) => Cow::Borrowed(t.as_str()),
            Some(SheetCell::Number(v)) => Cow::Owned(v.to_string()),
            Some(SheetCell::Date(d)) => Cow::Borrowed(d.shown.as_str()),
            Some(SheetCell::Error(e)) => Cow::Borrowed(e),
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
            // Outside an angle, pressure or volume column (`measured`
            // refuses it there) a date is its serial number.
            Some(SheetCell::Date(d)) if d.serial.is_some_and(f64::is_finite) => {
                Ok(d.serial.unwrap_or_default())
            }
            Some(SheetCell::Date(d)) => Err(date_error(d, i, line)),
            Some(SheetCell::Formula) => Err(at(
                line,
                Some(i + 1),
                format!(
                    "cell {}{line} holds a formula that was never calculated (the file stores no value for it): open the file in a spreadsheet program and save it, which calculates it",
                    column_name(i + 1)
                ),
            )),
            Some(SheetCell::Error(e)) => Err(at(
                line,
                Some(i + 1),
                format!(
                    "cell {}{line} holds `{e}`, an error value of the spreadsheet, where a number is needed",
                    column_name(i + 1)
                ),
            )),
            _ => Err(missing(i, line)),
        }
    }
    fn measured(&self, cols: &[usize], line: usize) -> Result<(), IngestError> {
        for &i in cols {
            if let Some(SheetCell::Date(d)) = self.0.get(i) {
                return Err(date_error(d, i, line));
            }
        }
        Ok(())
    }
    /// As for text, but a date, formula or error cell first in the row is
    /// passed over (a timestamp column, a date banner), and one after the
    /// first number counts as a number (it is read, and refused, where a
    /// number is needed).
    fn is_data(&self) -> bool {
        let n = self.used();
        let Some(first) = (0..n).find(|&i| !self.is_blank(i) && !self.value_like(i)) else {
            return false;
        };
        self.number(first, 0).is_ok()
            && (n == first + 1
                || (first + 1..n).any(|i| {
                    !self.is_blank(i) && (self.value_like(i) || self.number(i, 0).is_ok())
                }))
    }
}

/// A date- or time-formatted cell where an angle, pressure or volume is
/// needed.
fn date_error(d: &DateCell, i: usize, line: usize) -> IngestError {
    at(
        line,
        Some(i + 1),
        format!(
            "cell {}{line} is formatted as {} (it shows {}{}), where an angle, pressure or volume is needed: format the column as numbers in the spreadsheet (or export the diagram as CSV)",
            column_name(i + 1),
            d.kind,
            enginedyn_numerics::format::quote(&d.shown),
            d.serial
                .map(|s| format!(", Excel's day number {}", crate::error::shown_number(s)))
                .unwrap_or_default()
        ),
    )
}

fn missing(i: usize, line: usize) -> IngestError {
    at(line, Some(i + 1), "an empty cell where a number is needed")
}

/// Text as a file holds it: UTF-8 when it is, else Windows-1252 (what
/// Windows tools write: `°` as the byte 0xB0), so a header is echoed as
/// its author wrote it, never with U+FFFD.
pub(crate) fn decode(bytes: &[u8]) -> Cow<'_, str> {
    match std::str::from_utf8(bytes) {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(bytes.iter().map(|&b| cp1252(b)).collect()),
    }
}

/// One Windows-1252 byte: Latin-1 but for 0x80-0x9F (the five bytes it
/// leaves undefined kept as their C1 code points).
fn cp1252(b: u8) -> char {
    const HIGH: [char; 32] = [
        '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8d}', 'Ž',
        '\u{8f}', '\u{90}', '‘', '’', '“', '”', '•', '–', '—', '˜', '™', 'š', '›', 'œ', '\u{9d}',
        'ž', 'Ÿ',
    ];
    match b {
        0x80..=0x9f => HIGH[(b - 0x80) as usize],
        _ => b as char,
    }
}
