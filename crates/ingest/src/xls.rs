//! The bound on what calamine lays out when it opens an `.xls`.
//!
//! calamine reads every sheet of an `.xls` workbook as it opens it, and
//! turns each sheet's cells into a dense table spanning every row and
//! column between the first and the last cell address (`Range::from_sparse`),
//! after reserving room for what the sheet's DIMENSIONS record declares.
//! A damaged file (a cell's row or column bytes changed, a DIMENSIONS
//! record of billions of rows) makes that a table of billions of cells:
//! gigabytes allocated before any bound of the reader can act. So the
//! workbook stream is read first (the `cfb` crate), and its sheets' cell
//! addresses and dimensions are scanned the way calamine reads them: a
//! sheet spanning more than [`MAX_SHEET_CELLS`] is refused before calamine
//! sees the file.

use enginedyn_numerics::format::count;
use std::io::Read;

/// The most cells one sheet of an `.xls` may span (rows × columns between
/// its first and last cell, or as its DIMENSIONS record declares): 65,536
/// rows × 64 columns. A diagram of a whole cycle at 0.1° in ten columns
/// spans 72,000.
pub(crate) const MAX_SHEET_CELLS: u64 = 1 << 22;

/// An `.xls` sheet over the bound: its place among the workbook's sheets
/// (from 1), the rows and columns it spans, and what says so.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Oversized {
    /// `.xls` or `.ods`.
    pub(crate) kind: &'static str,
    pub(crate) sheet: usize,
    pub(crate) rows: u64,
    pub(crate) cols: u64,
    pub(crate) by: &'static str,
}

impl std::fmt::Display for Oversized {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the spreadsheet is damaged: sheet {} of the {} spans {} rows × {} columns ({}), more than the {} cells a sheet may span; open it and save it again, or export the diagram as CSV",
            self.sheet,
            self.kind,
            count(self.rows),
            count(self.cols),
            self.by,
            count(MAX_SHEET_CELLS)
        )
    }
}

/// The first sheet of the `.xls` in `bytes` that spans more than
/// [`MAX_SHEET_CELLS`]. `None` when every sheet is within the bound, and
/// when the file is no `.xls` this scan can read (not an OLE compound file,
/// no workbook stream, a password, a damaged container): calamine then
/// judges it as before.
pub(crate) fn oversized(bytes: &[u8]) -> Option<Oversized> {
    const OLE: [u8; 8] = [0xD0, 0xCF, 0x11, 0xE0, 0xA1, 0xB1, 0x1A, 0xE1];
    if !bytes.starts_with(&OLE) {
        return None;
    }
    let mut file = cfb::CompoundFile::open(std::io::Cursor::new(bytes)).ok()?;
    // The streams calamine reads, in its order.
    let mut stream = None;
    for name in ["/Workbook", "/Book"] {
        if let Ok(s) = file.open_stream(name) {
            stream = Some(s);
            break;
        }
    }
    let mut workbook = Vec::new();
    // A stream never holds more than the file.
    stream?
        .take(bytes.len() as u64)
        .read_to_end(&mut workbook)
        .ok()?;
    scan(&workbook)
}

/// The records of a BIFF stream from its start: type and data, CONTINUE
/// records passed over (no cell address starts one), ending at the first
/// record cut short.
fn records(mut s: &[u8]) -> impl Iterator<Item = (u16, &[u8])> {
    std::iter::from_fn(move || {
        loop {
            let head = s.get(..4)?;
            let typ = u16::from_le_bytes([head[0], head[1]]);
            let len = usize::from(u16::from_le_bytes([head[2], head[3]]));
            let data = s.get(4..4 + len)?;
            s = &s[4 + len..];
            if typ != 0x003C {
                return Some((typ, data));
            }
        }
    })
}

fn u16_at(d: &[u8], at: usize) -> Option<u32> {
    d.get(at..at + 2)
        .map(|b| u32::from(u16::from_le_bytes([b[0], b[1]])))
}

fn u32_at(d: &[u8], at: usize) -> Option<u32> {
    d.get(at..at + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// The sheets of the workbook stream, scanned as calamine reads them.
fn scan(wb: &[u8]) -> Option<Oversized> {
    // The globals: where each sheet starts (BoundSheet8), and a password.
    let mut starts = Vec::new();
    for (typ, d) in records(wb) {
        match typ {
            0x0085 => starts.extend(u32_at(d, 0)),
            0x002F if u16_at(d, 0) != Some(0) => return None,
            0x000A => break,
            _ => {}
        }
    }
    for (k, &at) in starts.iter().enumerate() {
        let Some(sheet) = wb.get(at as usize..) else {
            continue;
        };
        if let Some((rows, cols, by)) = span(sheet) {
            return Some(Oversized {
                kind: ".xls",
                sheet: k + 1,
                rows,
                cols,
                by,
            });
        }
    }
    None
}

/// Rows and columns a sheet's records make calamine lay out, when over the
/// bound: its cell addresses' span, or its DIMENSIONS record's.
fn span(sheet: &[u8]) -> Option<(u64, u64, &'static str)> {
    let (mut lo, mut hi) = ((u32::MAX, u32::MAX), (0u32, 0u32));
    let mut cell = |row: u32, col: u32| {
        lo = (lo.0.min(row), lo.1.min(col));
        hi = (hi.0.max(row), hi.1.max(col));
    };
    // Nested substreams (a chart's) are passed over, as calamine does.
    let (mut seen_bof, mut depth) = (false, 0usize);
    for (typ, d) in records(sheet) {
        if depth > 0 {
            match typ {
                0x0809 => depth += 1,
                0x000A => depth -= 1,
                _ => {}
            }
            continue;
        }
        let at = |c: usize| u16_at(d, c);
        match typ {
            0x0809 if seen_bof => depth += 1,
            0x0809 => seen_bof = true,
            0x000A => break,
            0x0200 => {
                let (rows, cols) = dimensions(d)?;
                if rows.saturating_mul(cols) > MAX_SHEET_CELLS {
                    return Some((rows, cols, "as its DIMENSIONS record declares"));
                }
            }
            // Number, Label, RString, BoolErr, Rk, LabelSst, Formula: the
            // row and the column first.
            0x0203 | 0x0204 | 0x00D6 | 0x0205 | 0x027E | 0x00FD | 0x0006 => {
                if let (Some(r), Some(c)) = (at(0), at(2)) {
                    cell(r, c);
                }
            }
            // MulRk: the row, the first column, …, the last column.
            0x00BD if d.len() >= 6 => {
                if let (Some(r), Some(c), Some(last)) = (at(0), at(2), at(d.len() - 2)) {
                    cell(r, c);
                    cell(r, last.max(c));
                }
            }
            _ => {}
        }
    }
    if lo.0 > hi.0 {
        return None;
    }
    let (rows, cols) = (u64::from(hi.0 - lo.0) + 1, u64::from(hi.1 - lo.1) + 1);
    (rows * cols > MAX_SHEET_CELLS).then_some((rows, cols, "between its first and last cell"))
}

/// The rows and columns calamine reserves for a DIMENSIONS record
/// (BIFF5's 10 bytes of 16-bit fields, BIFF8's 14 or 16 with 32-bit
/// rows), its own corrections included: a first column past 255 or after
/// the last is taken as 0. `None` for a record of another length (calamine
/// then stops with an error).
fn dimensions(d: &[u8]) -> Option<(u64, u64)> {
    let (rf, rl, mut cf, cl) = match d.len() {
        10 => (u16_at(d, 0)?, u16_at(d, 2)?, u16_at(d, 4)?, u16_at(d, 6)?),
        14 | 16 => (u32_at(d, 0)?, u32_at(d, 4)?, u16_at(d, 8)?, u16_at(d, 10)?),
        _ => return None,
    };
    if cf > 0xFF || cl < cf {
        cf = 0;
    }
    if rl < 1 || cl < 1 {
        return Some((1, 1));
    }
    // calamine's `end - start + 1` in 32 bits, as it computes it.
    let rows = (rl - 1).wrapping_sub(rf).wrapping_add(1);
    let cols = (cl - 1).wrapping_sub(cf).wrapping_add(1);
    Some((u64::from(rows), u64::from(cols)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(typ: u16, data: &[u8]) -> Vec<u8> {
        let mut r = typ.to_le_bytes().to_vec();
        r.extend_from_slice(&(data.len() as u16).to_le_bytes());
        r.extend_from_slice(data);
        r
    }

    fn rk(row: u16, col: u16) -> Vec<u8> {
        let mut d = row.to_le_bytes().to_vec();
        d.extend_from_slice(&col.to_le_bytes());
        d.extend_from_slice(&[0; 6]);
        record(0x027E, &d)
    }

    /// A workbook stream: globals naming one sheet, then the sheet's
    /// records between its BOF and EOF.
    fn workbook(sheet: &[Vec<u8>]) -> Vec<u8> {
        let bof = record(0x0809, &[0; 16]);
        let eof = record(0x000A, &[]);
        let mut globals = bof.clone();
        let bound_len = 4 + 8;
        let at = (globals.len() + bound_len + eof.len()) as u32;
        let mut b = at.to_le_bytes().to_vec();
        b.extend_from_slice(&[0; 4]);
        globals.extend(record(0x0085, &b));
        globals.extend(&eof);
        globals.extend(bof);
        for r in sheet {
            globals.extend(r);
        }
        globals.extend(eof);
        globals
    }

    #[test]
    fn a_sheet_is_measured_by_its_cells_and_its_dimensions() {
        // A diagram's span: 7,201 rows × 3 columns.
        let fine = workbook(&[rk(0, 0), rk(7_200, 2)]);
        assert_eq!(scan(&fine), None);
        // One cell's row and column bytes changed: 65,536 × 256.
        let far = workbook(&[rk(0, 0), rk(65_535, 255)]);
        let got = scan(&far).unwrap();
        assert_eq!((got.sheet, got.rows, got.cols), (1, 65_536, 256));
        // The bound itself is within; one more row is not.
        let rows = (MAX_SHEET_CELLS / 128) as u16;
        assert_eq!(scan(&workbook(&[rk(0, 0), rk(rows - 1, 127)])), None);
        assert!(scan(&workbook(&[rk(0, 0), rk(rows, 127)])).is_some());
        // A MulRk's last column counts.
        let mut mul = 5u16.to_le_bytes().to_vec();
        mul.extend_from_slice(&0u16.to_le_bytes());
        mul.extend_from_slice(&[0; 6]);
        mul.extend_from_slice(&60_000u16.to_le_bytes());
        let wide = workbook(&[rk(0, 0), rk(100, 0), record(0x00BD, &mul)]);
        assert_eq!(scan(&wide).map(|o| o.cols), Some(60_001));
        // DIMENSIONS of four billion rows (BIFF8), before any cell.
        let mut dim = 0u32.to_le_bytes().to_vec();
        dim.extend_from_slice(&u32::MAX.to_le_bytes());
        dim.extend_from_slice(&0u16.to_le_bytes());
        dim.extend_from_slice(&3u16.to_le_bytes());
        dim.extend_from_slice(&[0; 2]);
        let got = scan(&workbook(&[record(0x0200, &dim), rk(0, 0)])).unwrap();
        assert_eq!((got.rows, got.cols), (u64::from(u32::MAX), 3));
        // A chart's substream inside the sheet is passed over.
        let chart = [
            rk(0, 0),
            record(0x0809, &[0; 16]),
            rk(65_535, 255),
            record(0x000A, &[]),
            rk(10, 1),
        ];
        assert_eq!(scan(&workbook(&chart)), None);
    }

    #[test]
    fn the_fixture_is_within_and_other_files_are_left_to_calamine() {
        let xls = std::fs::read(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/fixtures/measured/libreoffice_cycles.xls"
        ))
        .unwrap();
        assert_eq!(oversized(&xls), None);
        assert_eq!(oversized(b"crank_deg,pressure_bar\n"), None);
        assert_eq!(oversized(&xls[..600]), None, "a container cut short");
    }
}
