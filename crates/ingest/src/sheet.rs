//! The spreadsheet source: `.xlsx`, `.xls` and `.ods` workbooks, read by
//! calamine, a sheet's rows handed to the reader as rows of cells (the same
//! rules as text: header, banners, layouts). Row numbers in messages are the
//! sheet's own (1-based), columns count from A = 1.

use crate::error::IngestError;
use crate::reader::Reader;
use crate::row::{SheetCell, SheetRow};
use crate::{Header, ParseOptions, Sheet, Streamed};
use calamine::{Data, Reader as _};

/// The largest workbook read (bytes): it is held in memory.
pub const MAX_WORKBOOK: usize = 256 << 20;

/// Reads a sheet of the workbook in `bytes`.
pub(crate) fn read<F: FnMut(Streamed) -> Result<(), IngestError>>(
    bytes: Vec<u8>,
    opts: &ParseOptions,
    sink: F,
) -> Result<Header, IngestError> {
    // calamine parses a format of many parts; should it ever panic on a
    // damaged file, that is this file's error, not the command's end.
    let (names, _, range) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        open_sheet(bytes, opts)
    }))
    .unwrap_or_else(|_| {
        Err(IngestError::Data(
            "the spreadsheet is damaged (calamine could not read it): open it and save it again, or export the diagram as CSV".into(),
        ))
    })?;
    let mut rd = Reader::new(opts, sink);
    if names.len() > 1 && opts.sheet.is_none() {
        rd.head.notes.push(format!(
            "read sheet 1 `{}` of {} (--sheet chooses another)",
            enginedyn_numerics::format::quote(&names[0]),
            names.len()
        ));
    }
    // Where the first of several sheets holds no diagram, say that others exist.
    let hint = |e: IngestError| -> IngestError {
        if names.len() < 2 || opts.sheet.is_some() {
            return e;
        }
        let more = format!(
            " (this is sheet 1 `{}` of {}: --sheet N or --sheet NAME reads another)",
            enginedyn_numerics::format::quote(&names[0]),
            names.len()
        );
        match e {
            IngestError::At {
                line,
                column,
                message,
            } => IngestError::At {
                line,
                column,
                message: message + &more,
            },
            IngestError::Data(m) => IngestError::Data(m + &more),
            e => e,
        }
    };
    read_rows(&range, opts, &mut rd).map_err(hint)?;
    rd.end().map_err(hint)
}

fn read_rows<F: FnMut(Streamed) -> Result<(), IngestError>>(
    range: &calamine::Range<Data>,
    opts: &ParseOptions,
    rd: &mut Reader<'_, F>,
) -> Result<(), IngestError> {
    let (row0, col0) = range.start().unwrap_or((0, 0));
    let mut cells: Vec<SheetCell> = Vec::new();
    for (i, row) in range.rows().enumerate() {
        let line = row0 as usize + i + 1;
        if line <= opts.skip_lines {
            continue;
        }
        cells.clear();
        // Columns before the used range are empty: keep positions as in the sheet.
        cells.resize(col0 as usize, SheetCell::Empty);
        cells.extend(row.iter().map(|d| match d {
            Data::Float(v) => SheetCell::Number(*v),
            Data::Int(v) => SheetCell::Number(*v as f64),
            Data::String(s) => SheetCell::Text(s.clone()),
            Data::Bool(b) => SheetCell::Text(b.to_string()),
            Data::DateTime(d) => SheetCell::Number(d.as_f64()),
            Data::DateTimeIso(s) | Data::DurationIso(s) => SheetCell::Text(s.clone()),
            Data::Error(e) => SheetCell::Text(format!("#{e:?}")),
            Data::Empty => SheetCell::Empty,
        }));
        let row = SheetRow(&cells);
        use crate::row::Cells;
        if row.used() == 0 {
            continue;
        }
        if let SheetCell::Text(t) = &cells[first_used(&cells)] {
            let t = t.trim_start();
            if t.starts_with('#') {
                let all: Vec<String> = (0..row.len()).map(|k| row.text(k).into_owned()).collect();
                rd.comment(line, &all.join(" "))?;
                continue;
            }
        }
        rd.row(line, &row, || None)?;
    }
    Ok(())
}

/// The workbook's sheet names, the chosen sheet and its cells.
fn open_sheet(
    bytes: Vec<u8>,
    opts: &ParseOptions,
) -> Result<(Vec<String>, usize, calamine::Range<Data>), IngestError> {
    let mut book = calamine::open_workbook_auto_from_rs(std::io::Cursor::new(bytes)).map_err(|e| {
        IngestError::Data(format!(
            "not a text file: a ZIP or OLE archive that is no spreadsheet calamine reads (.xlsx, .xls, .ods: {e}); export the diagram as CSV"
        ))
    })?;
    let names = book.sheet_names();
    if names.is_empty() {
        return Err(IngestError::Data("the workbook has no sheet".into()));
    }
    let index = match &opts.sheet {
        None => 0,
        Some(Sheet::Index(n)) if (1..=names.len()).contains(n) => n - 1,
        Some(Sheet::Name(s)) if names.iter().any(|x| x == s) => {
            names.iter().position(|x| x == s).unwrap_or(0)
        }
        Some(Sheet::Name(s)) if names.iter().any(|x| x.eq_ignore_ascii_case(s)) => names
            .iter()
            .position(|x| x.eq_ignore_ascii_case(s))
            .unwrap_or(0),
        Some(which) => {
            return Err(IngestError::Data(format!(
                "--sheet {}: the workbook's sheets are {} (give a name or a number from 1 to {})",
                match which {
                    Sheet::Index(n) => n.to_string(),
                    Sheet::Name(s) => format!("`{}`", enginedyn_numerics::format::quote(s)),
                },
                names
                    .iter()
                    .enumerate()
                    .map(|(i, n)| format!("{} `{}`", i + 1, enginedyn_numerics::format::quote(n)))
                    .collect::<Vec<_>>()
                    .join(", "),
                names.len()
            )));
        }
    };
    let range = book
        .worksheet_range(&names[index])
        .map_err(|e| IngestError::Data(format!("sheet `{}`: {e}", names[index])))?;
    Ok((names, index, range))
}

fn first_used(cells: &[SheetCell]) -> usize {
    cells
        .iter()
        .position(|c| !matches!(c, SheetCell::Empty))
        .unwrap_or(0)
}
