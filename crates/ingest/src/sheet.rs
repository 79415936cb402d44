//! The spreadsheet source: `.xlsx`, `.xls` and `.ods` workbooks, read by
//! calamine, a sheet's rows handed to the reader as rows of cells (the same
//! rules as text: header, banners, layouts). Row numbers in messages are the
//! sheet's own (1-based), columns count from A = 1.

use crate::error::IngestError;
use crate::reader::Reader;
use crate::row::{SheetCell, SheetRow};
use crate::{Header, ParseOptions, Sheet, Streamed};
use calamine::{Data, DataType, Reader as _};

/// The largest workbook read (bytes): it is held in memory.
pub const MAX_WORKBOOK: usize = 256 << 20;

/// The most columns a sheet's row may reach (Excel's own limit, XFD).
pub const MAX_SHEET_COLUMNS: usize = 16_384;

/// The damaged-workbook error.
fn damaged() -> IngestError {
    IngestError::Data(
        "the spreadsheet is damaged (calamine could not read it): open it and save it again, or export the diagram as CSV".into(),
    )
}

/// Reads a sheet of the workbook in `bytes`: an .xlsx cell by cell as it
/// streams (no sheet-sized table, whatever cell addresses it claims), an
/// .xls or .ods through calamine's table of the sheet.
pub(crate) fn read<F: FnMut(Streamed) -> Result<(), IngestError>>(
    bytes: Vec<u8>,
    opts: &ParseOptions,
    sink: F,
) -> Result<Header, IngestError> {
    // calamine parses a format of many parts; should it ever panic on a
    // damaged file, that is this file's error, not the command's end.
    let mut sink = sink;
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        read_book(&bytes, opts, &mut sink)
    }))
    .unwrap_or_else(|_| Err(damaged()))
}

fn read_book<F: FnMut(Streamed) -> Result<(), IngestError>>(
    bytes: &[u8],
    opts: &ParseOptions,
    sink: F,
) -> Result<Header, IngestError> {
    if let Ok(mut book) = calamine::Xlsx::new(std::io::Cursor::new(bytes)) {
        let names = book.sheet_names();
        let index = choose(&names, opts)?;
        let mut rd = Reader::new(opts, sink);
        let streamed = book
            .worksheet_cells_reader(&names[index])
            .map_err(|e| IngestError::Data(format!("sheet `{}`: {e}", names[index])))
            .and_then(|mut cells| stream_rows(&mut cells, opts, &mut rd));
        return finish(rd, streamed, &names, opts);
    }
    let (names, _, range) = open_sheet(bytes, opts)?;
    let mut rd = Reader::new(opts, sink);
    let rows = read_rows(&range, opts, &mut rd);
    finish(rd, rows, &names, opts)
}

/// The reader's end, and what a workbook of several sheets adds to a note
/// or an error: which sheet was read, and that --sheet reads another.
fn finish<F: FnMut(Streamed) -> Result<(), IngestError>>(
    rd: Reader<'_, F>,
    rows: Result<(), IngestError>,
    names: &[String],
    opts: &ParseOptions,
) -> Result<Header, IngestError> {
    let several = names.len() > 1 && opts.sheet.is_none();
    let hint = |e: IngestError| -> IngestError {
        if !several {
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
    rows.map_err(hint)?;
    let mut head = rd.end().map_err(hint)?;
    if several {
        head.notes.push(format!(
            "read sheet 1 `{}` of {} (--sheet chooses another)",
            enginedyn_numerics::format::quote(&names[0]),
            names.len()
        ));
    }
    Ok(head)
}

/// An .xlsx sheet's cells, streamed into rows (cells come row by row).
fn stream_rows<F: FnMut(Streamed) -> Result<(), IngestError>>(
    cells: &mut calamine::XlsxCellReader<'_, std::io::Cursor<&[u8]>>,
    opts: &ParseOptions,
    rd: &mut Reader<'_, F>,
) -> Result<(), IngestError> {
    let mut row: Vec<SheetCell> = Vec::new();
    let mut at_row: Option<u32> = None;
    while let Some(c) = cells
        .next_cell()
        .map_err(|e| IngestError::Data(format!("the spreadsheet is damaged: {e}")))?
    {
        let (r, col) = c.get_position();
        if at_row != Some(r) {
            if let Some(prev) = at_row {
                hand_row(prev as usize + 1, &row, opts, rd)?;
            }
            row.clear();
            at_row = Some(r);
        }
        let col = col as usize;
        if col >= MAX_SHEET_COLUMNS {
            return Err(IngestError::At {
                line: r as usize + 1,
                column: None,
                message: format!(
                    "a cell beyond column {MAX_SHEET_COLUMNS}, Excel's last: a damaged sheet"
                ),
            });
        }
        if row.len() <= col {
            row.resize(col + 1, SheetCell::Empty);
        }
        row[col] = sheet_cell(c.get_value());
    }
    if let Some(prev) = at_row {
        hand_row(prev as usize + 1, &row, opts, rd)?;
    }
    Ok(())
}

/// One sheet row (1-based `line`) to the reader: skipped lines, empty
/// rows and comments (`#` in the first cell) as in text.
fn hand_row<F: FnMut(Streamed) -> Result<(), IngestError>>(
    line: usize,
    cells: &[SheetCell],
    opts: &ParseOptions,
    rd: &mut Reader<'_, F>,
) -> Result<(), IngestError> {
    use crate::row::Cells;
    if line <= opts.skip_lines {
        return Ok(());
    }
    let row = SheetRow(cells);
    if row.used() == 0 {
        return Ok(());
    }
    if let SheetCell::Text(t) = &cells[first_used(cells)]
        && t.trim_start().starts_with('#')
    {
        let all: Vec<String> = (0..row.len()).map(|k| row.text(k).into_owned()).collect();
        return rd.comment(line, &all.join(" "));
    }
    rd.row(line, &row, || None)
}

fn read_rows<F: FnMut(Streamed) -> Result<(), IngestError>>(
    range: &calamine::Range<Data>,
    opts: &ParseOptions,
    rd: &mut Reader<'_, F>,
) -> Result<(), IngestError> {
    let (row0, col0) = range.start().unwrap_or((0, 0));
    let mut cells: Vec<SheetCell> = Vec::new();
    for (i, row) in range.rows().enumerate() {
        cells.clear();
        // Columns before the used range are empty: keep positions as in the sheet.
        cells.resize(col0 as usize, SheetCell::Empty);
        cells.extend(row.iter().map(sheet_cell));
        hand_row(row0 as usize + i + 1, &cells, opts, rd)?;
    }
    Ok(())
}

/// The workbook's sheet names, the chosen sheet and its cells.
fn open_sheet(
    bytes: &[u8],
    opts: &ParseOptions,
) -> Result<(Vec<String>, usize, calamine::Range<Data>), IngestError> {
    let mut book = calamine::open_workbook_auto_from_rs(std::io::Cursor::new(bytes)).map_err(|e| {
        IngestError::Data(format!(
            "not a text file: a ZIP or OLE archive that is no spreadsheet calamine reads (.xlsx, .xls, .ods: {e}); export the diagram as CSV"
        ))
    })?;
    let names = book.sheet_names();
    let index = choose(&names, opts)?;
    let range = book
        .worksheet_range(&names[index])
        .map_err(|e| IngestError::Data(format!("sheet `{}`: {e}", names[index])))?;
    Ok((names, index, range))
}

/// The sheet `--sheet` names (the first without it).
fn choose(names: &[String], opts: &ParseOptions) -> Result<usize, IngestError> {
    if names.is_empty() {
        return Err(IngestError::Data("the workbook has no sheet".into()));
    }
    Ok(match &opts.sheet {
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
    })
}

/// A cell as the reader sees it: a number (dates as Excel's serial
/// numbers), text, or nothing.
fn sheet_cell(d: &impl DataType) -> SheetCell {
    if let Some(v) = d.get_float() {
        SheetCell::Number(v)
    } else if let Some(v) = d.get_int() {
        SheetCell::Number(v as f64)
    } else if let Some(t) = d.get_datetime() {
        SheetCell::Number(t.as_f64())
    } else if let Some(t) = d.get_string() {
        SheetCell::Text(t.to_string())
    } else if let Some(b) = d.get_bool() {
        SheetCell::Text(b.to_string())
    } else if let Some(e) = d.get_error() {
        SheetCell::Text(format!("#{e:?}"))
    } else if d.is_empty() {
        SheetCell::Empty
    } else {
        // ISO dates and durations.
        SheetCell::Text(d.as_string().unwrap_or_default())
    }
}

fn first_used(cells: &[SheetCell]) -> usize {
    cells
        .iter()
        .position(|c| !matches!(c, SheetCell::Empty))
        .unwrap_or(0)
}
