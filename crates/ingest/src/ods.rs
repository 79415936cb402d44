//! The bound on what calamine lays out for an `.ods` sheet.
//!
//! calamine reads an `.ods` sheet row by row into a list of cells (a cell
//! repeated `table:number-columns-repeated` times written out that many
//! times, up to 16,384 columns a row), then into a dense table spanning
//! every row and column between the first and the last cell that holds
//! something, rows repeated `table:number-rows-repeated` times written out
//! (up to 1,048,576 rows and 100 million cells: gigabytes). A 35 KB file
//! of repeated cells took 3.1 GB and 7.6 s before calamine gave up. So the
//! sheet's XML is read first, with the XML reader calamine uses, and what
//! calamine would write out is counted as it counts it: a sheet over
//! [`MAX_SHEET_CELLS`] is refused before calamine sees the file.

use crate::sheet::{MAX_SHEET_BYTES, MAX_XML_SPAN};
use crate::xls::{MAX_SHEET_CELLS, Oversized};
use quick_xml::events::{BytesStart, Event};
use std::io::Read;

/// calamine's own caps on a sheet: rows, and columns a row.
const MAX_ROWS: u64 = 1 << 20;
const MAX_COLUMNS: u64 = 16_384;

/// The first sheet of the `.ods` in `bytes` that calamine would write out
/// as more than [`MAX_SHEET_CELLS`] cells; `None` when every sheet is
/// within, or the file is no `.ods` this scan reads (calamine then judges
/// it, under the workbook's watch).
pub(crate) fn oversized(bytes: &[u8]) -> Option<Oversized> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).ok()?;
    let content = zip.by_name("content.xml").ok()?;
    let mut xml =
        quick_xml::Reader::from_reader(std::io::BufReader::new(content.take(MAX_SHEET_BYTES)));
    // As calamine reads it.
    let c = xml.config_mut();
    c.expand_empty_elements = true;
    c.check_end_names = false;
    c.trim_text(false);
    let (mut buf, mut sheet, mut t) = (Vec::new(), 0, Table::default());
    loop {
        buf.clear();
        match xml.read_event_into(&mut buf) {
            Ok(Event::Start(e)) => match e.name().0 {
                "table:table" => {
                    sheet += 1;
                    t = Table::default();
                }
                "table:table-row" => t.row(count(&e, "table:number-rows-repeated")?),
                "table:table-cell" | "table:covered-table-cell" => {
                    t.cell(count(&e, "table:number-columns-repeated")?, holds(&e))
                }
                _ => {}
            },
            Ok(Event::End(e)) if e.name().0 == "table:table-row" => t.row_end(),
            Ok(Event::Eof) | Err(_) => return t.over(sheet),
            Ok(_) => {}
        }
        if let Some(o) = t.over(sheet) {
            return Some(o);
        }
        // A stretch the workbook's watch stops calamine at anyway.
        if buf.len() as u64 > MAX_XML_SPAN {
            return None;
        }
    }
}

/// A repeat count attribute (1 when absent); `None` for one that is no
/// number (calamine stops there with an error).
fn count(e: &BytesStart<'_>, name: &str) -> Option<u64> {
    for a in e.attributes().flatten() {
        if a.key.0 == name {
            return a.value.trim().parse().ok();
        }
    }
    Some(1)
}

/// True for a cell calamine keeps (a value, a string type, a formula):
/// one without is empty, written out only before a cell that is not.
fn holds(e: &BytesStart<'_>) -> bool {
    e.attributes().flatten().any(|a| match a.key.0 {
        "office:value"
        | "office:string-value"
        | "office:date-value"
        | "office:time-value"
        | "office:boolean-value"
        | "table:formula" => true,
        "office:value-type" => a.value == "string",
        _ => false,
    })
}

/// One sheet as calamine counts it.
#[derive(Default)]
struct Table {
    /// Rows so far (repeats counted, capped as calamine caps them).
    rows: u64,
    /// The current row: its first row, its repeats, the cells written out
    /// and the empty ones waiting for a cell that holds something.
    at: u64,
    repeats: u64,
    written: u64,
    waiting: u64,
    /// Cells written out in all rows (calamine's list before the table).
    cells: u64,
    widest: u64,
    /// The rows and columns of cells that hold something: first, last.
    span: Option<((u64, u64), (u64, u64))>,
}

impl Table {
    fn row(&mut self, repeats: u64) {
        let r = repeats.min(MAX_ROWS.saturating_sub(self.rows));
        (self.at, self.repeats, self.written, self.waiting) = (self.rows, r, 0, 0);
        self.rows += r;
    }

    fn cell(&mut self, repeats: u64, holds: bool) {
        // The empty cells before it are written out first, then it.
        let empty = self.waiting.min(MAX_COLUMNS - self.written);
        self.written += empty;
        self.cells += empty;
        let n = repeats.min(MAX_COLUMNS - self.written);
        if !holds {
            self.waiting = n;
            return;
        }
        self.waiting = 0;
        if n > 0 && self.repeats > 0 {
            let (r0, r1) = (self.at, self.at + self.repeats - 1);
            let (c0, c1) = (self.written, self.written + n - 1);
            self.span = Some(match self.span {
                None => ((r0, c0), (r1, c1)),
                Some((lo, hi)) => ((lo.0.min(r0), lo.1.min(c0)), (hi.0.max(r1), hi.1.max(c1))),
            });
        }
        self.written += n;
        self.cells += n;
        self.widest = self.widest.max(self.written);
    }

    fn row_end(&mut self) {
        self.waiting = 0;
    }

    /// The sheet when over the bound: calamine's list of cells, or its
    /// table.
    fn over(&self, sheet: usize) -> Option<Oversized> {
        let o = |rows, cols, by| {
            Some(Oversized {
                kind: ".ods",
                sheet,
                rows,
                cols,
                by,
            })
        };
        if self.cells > MAX_SHEET_CELLS {
            return o(self.rows, self.widest, "its rows' cells written out");
        }
        let ((r0, c0), (r1, c1)) = self.span?;
        let (rows, cols) = (r1 - r0 + 1, c1 - c0 + 1);
        if rows.saturating_mul(cols) > MAX_SHEET_CELLS {
            return o(rows, cols, "between its first and last cell");
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_ods::ods_with;

    fn row(rows: u64, cells: &str) -> String {
        format!(r#"<table:table-row table:number-rows-repeated="{rows}">{cells}</table:table-row>"#)
    }

    fn cell(cols: u64, value: bool) -> String {
        let v = if value {
            r#" office:value-type="float" office:value="1""#
        } else {
            ""
        };
        format!(r#"<table:table-cell table:number-columns-repeated="{cols}"{v}/>"#)
    }

    #[test]
    fn a_sheet_is_measured_as_calamine_writes_it_out() {
        assert_eq!(oversized(&ods_with("")), None, "the fixture");
        // LibreOffice's own tail: empty cells and rows repeated, kept empty.
        let tail = row(1_048_000, &cell(1_024, false));
        assert_eq!(oversized(&ods_with(&tail)), None);
        // 6,000 rows of 16,000 cells that hold a value (96 million), under
        // the fixture's header row.
        let got = oversized(&ods_with(&row(6_000, &cell(16_000, true)))).unwrap();
        assert_eq!((got.sheet, got.rows, got.cols), (1, 6_001, 16_000));
        // Two values far apart, the rows between empty and repeated.
        let far = format!(
            "{}{}{}",
            row(1, &cell(1, true)),
            row(1_000_000, &cell(3, false)),
            row(1, &format!("{}{}", cell(2_000, false), cell(1, true)))
        );
        let got = oversized(&ods_with(&far)).unwrap();
        assert_eq!(got.by, "between its first and last cell");
        // Many rows, each of 16,384 cells written out, below the table's
        // span bound but not the list's.
        let many: String = (0..300).map(|_| row(1, &cell(16_384, true))).collect();
        let got = oversized(&ods_with(&many)).unwrap();
        assert_eq!(got.by, "its rows' cells written out");
        // Within: a diagram's worth.
        let fine: String = (0..7_200).map(|_| row(1, &cell(3, true))).collect();
        assert_eq!(oversized(&ods_with(&fine)), None);
        // Not an .ods.
        assert_eq!(oversized(b"crank_deg,pressure_bar\n"), None);
    }
}
