//! The spreadsheet source: `.xlsx`, `.xls` and `.ods` workbooks, read by
//! calamine, a sheet's rows handed to the reader as rows of cells (the same
//! rules as text: header, banners, layouts). Row numbers in messages are the
//! sheet's own (1-based), columns count from A = 1.
//!
//! What a hostile workbook cannot do here:
//! - stop the command with a panic, or print one: the whole read runs inside
//!   one `catch_unwind` with panic messages silenced for this thread
//!   ([`guarded`]); a panic is this file's error;
//! - unpack without end, or into memory: every ZIP part calamine reads is
//!   unpacked a second time, in step with it ([`Watch`]), counting its bytes
//!   (at most [`MAX_SHEET_BYTES`]: the declared size may lie) and the
//!   longest stretch of XML calamine would hold at once (a text or a tag, at
//!   most [`MAX_XML_SPAN`]); past either, calamine's read fails;
//! - hold a worker on empty rows: a run of more than [`MAX_EMPTY_ROWS`] empty
//!   rows ends the sheet's data, with a note (calamine's cell reader passes
//!   over empty `<row/>` elements without returning, so the watch also
//!   counts them, and stops the stream once such a run has gone by);
//! - pass a date, a formula never calculated or an error value off as a number
//!   ([`SheetCell`]).

use crate::error::IngestError;
use crate::reader::Reader;
use crate::row::{DateCell, SheetCell, SheetRow};
use crate::{Header, ParseOptions, Sheet, Streamed};
use calamine::{Data, DataType, Reader as _};
use std::cell::{Cell, RefCell};
use std::io::{Read, Seek, SeekFrom};

/// The largest workbook read (bytes): it is held in memory.
pub const MAX_WORKBOOK: usize = 256 << 20;

/// The most columns a sheet's row may reach (Excel's own limit, XFD).
pub const MAX_SHEET_COLUMNS: usize = 16_384;

/// The most bytes one sheet (one part of a workbook's ZIP archive) may
/// unpack to.
pub const MAX_SHEET_BYTES: u64 = 1 << 30;

/// The longest run of empty rows inside a sheet's data: a longer one ends it.
pub const MAX_EMPTY_ROWS: u32 = 10_000;

/// The longest stretch of a workbook's XML without a tag boundary (a
/// cell's text, a tag with its attributes): calamine holds one whole.
pub const MAX_XML_SPAN: u64 = 16 << 20;

/// The damaged-workbook error.
fn damaged() -> IngestError {
    IngestError::Data(
        "the spreadsheet is damaged (calamine could not read it): open it and save it again, or export the diagram as CSV".into(),
    )
}

/// Why the watch stopped calamine, as this file's error.
fn cut_error(cut: Cut) -> IngestError {
    IngestError::Data(match cut {
        Cut::Bound => "a sheet (a part of the workbook's ZIP archive) unpacks to more than 1 GiB, the bound on one sheet (a ZIP bomb?): export the diagram as CSV".into(),
        Cut::Span => "the workbook's XML holds a text or tag of more than 16 MiB, the bound on one (no spreadsheet writes one): export the diagram as CSV".into(),
        // Only a sheet's data ends at a run of empty rows (`stream_rows`).
        Cut::EmptyRows => "the spreadsheet is damaged (more than 10,000 empty rows where calamine reads no sheet): open it and save it again, or export the diagram as CSV".into(),
    })
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
    guarded(|| read_book(&bytes, opts, &mut sink)).unwrap_or_else(|| Err(damaged()))
}

thread_local! {
    /// True while this thread is inside [`guarded`].
    static GUARDED: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f`, a panic in it caught (`None`) and its message kept off
/// standard error. The panic hook is process-wide and batch reads files on
/// several threads, so it is installed once: a hook that says nothing for a
/// thread inside a guarded read and hands every other panic to the hook
/// that was there before (which prints it as before).
pub(crate) fn guarded<T>(f: impl FnOnce() -> T) -> Option<T> {
    static QUIET_HOOK: std::sync::Once = std::sync::Once::new();
    QUIET_HOOK.call_once(|| {
        let before = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !GUARDED.with(Cell::get) {
                before(info);
            }
        }));
    });
    let was = GUARDED.with(|g| g.replace(true));
    let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(was));
    out.ok()
}

fn read_book<F: FnMut(Streamed) -> Result<(), IngestError>>(
    bytes: &[u8],
    opts: &ParseOptions,
    mut sink: F,
) -> Result<Header, IngestError> {
    let watch = RefCell::new(Watch::new(zip_parts(bytes)));
    let watched = || Watched {
        bytes,
        pos: 0,
        watch: &watch,
    };
    let cut = || watch.borrow().cut;
    if let Ok(mut book) = calamine::Xlsx::new(watched()) {
        let names = book.sheet_names();
        let mut tried = Tried::default();
        for index in sheets(&names, opts)? {
            let mut rd = Reader::new(opts, &mut sink);
            let streamed = book
                .worksheet_cells_reader(&names[index])
                .map_err(|e| match cut() {
                    Some(c) => cut_error(c),
                    None => IngestError::Data(format!("sheet `{}`: {e}", names[index])),
                })
                .and_then(|mut cells| stream_rows(&mut cells, opts, &mut rd, &watch));
            match tried.next(finish(rd, streamed, &names, index, opts), cut().is_none()) {
                Some(r) => return r,
                None => continue,
            }
        }
        return tried.none(&names);
    }
    if let Some(c) = cut() {
        return Err(cut_error(c));
    }
    // An .xls or .ods is laid out sheet by sheet as calamine opens it: what
    // each sheet spans is bounded first.
    if let Some(o) = crate::xls::oversized(bytes).or_else(|| crate::ods::oversized(bytes)) {
        return Err(IngestError::Data(o.to_string()));
    }
    let mut book = calamine::open_workbook_auto_from_rs(watched()).map_err(|e| match cut() {
        Some(c) => cut_error(c),
        None => IngestError::Data(format!(
            "not a text file: a ZIP or OLE archive that is no spreadsheet calamine reads (.xlsx, .xls, .ods: {e}); export the diagram as CSV"
        )),
    })?;
    let names = book.sheet_names();
    let mut tried = Tried::default();
    for index in sheets(&names, opts)? {
        let range = book
            .worksheet_range(&names[index])
            .map_err(|e| match cut() {
                Some(c) => cut_error(c),
                None => IngestError::Data(format!("sheet `{}`: {e}", names[index])),
            });
        let formulas = book.worksheet_formula(&names[index]).ok();
        let mut rd = Reader::new(opts, &mut sink);
        let rows = range.and_then(|range| read_rows(&range, formulas.as_ref(), opts, &mut rd));
        match tried.next(finish(rd, rows, &names, index, opts), cut().is_none()) {
            Some(r) => return r,
            None => continue,
        }
    }
    tried.none(&names)
}

/// A sheet's read, and whether it found a diagram: a sheet whose rows never
/// left the preamble (no header over data: a cover page, notes, a table of
/// settings) holds none, and the next sheet is tried (INTERFACE.md: the
/// default sheet is the first that holds a diagram).
type SheetRead = Result<Header, (IngestError, bool)>;

/// The sheets tried so far without a diagram: the first one's error.
#[derive(Default)]
struct Tried {
    first: Option<IngestError>,
    count: usize,
}

impl Tried {
    /// The read to return (`Some`), or `None` to try the next sheet. A bound
    /// passed (`clean` false) ends the search.
    fn next(&mut self, read: SheetRead, clean: bool) -> Option<Result<Header, IngestError>> {
        match read {
            Ok(h) => Some(Ok(h)),
            Err((e, true)) if clean => {
                self.count += 1;
                self.first.get_or_insert(e);
                None
            }
            Err((e, _)) => Some(Err(e)),
        }
    }

    /// No sheet holds a diagram: the first sheet's error, with every sheet
    /// listed by number and name (at most 20 named).
    fn none(self, names: &[String]) -> Result<Header, IngestError> {
        let e = self
            .first
            .unwrap_or_else(|| IngestError::Data("the workbook has no sheet".into()));
        if names.len() < 2 || self.count < 2 {
            return Err(e);
        }
        Err(add(
            e,
            &format!(
                " (this is sheet 1 `{}`; no sheet of {} holds a diagram: {}; --sheet N or --sheet NAME reads another)",
                enginedyn_numerics::format::quote(&names[0]),
                names.len(),
                listed(names)
            ),
        ))
    }
}

/// Every sheet by number and name (at most 20 named), so the user can pick
/// one without opening the workbook.
fn listed(names: &[String]) -> String {
    let mut l: Vec<String> = names
        .iter()
        .take(20)
        .enumerate()
        .map(|(i, n)| format!("{} `{}`", i + 1, enginedyn_numerics::format::quote(n)))
        .collect();
    if names.len() > 20 {
        l.push("…".into());
    }
    l.join(", ")
}

/// `more` added to an error's message.
fn add(e: IngestError, more: &str) -> IngestError {
    match e {
        IngestError::At {
            line,
            column,
            message,
        } => IngestError::At {
            line,
            column,
            message: message + more,
        },
        IngestError::Data(m) => IngestError::Data(m + more),
        e => e,
    }
}

/// The reader's end of sheet `index`, and what a workbook of several sheets
/// adds to a note: which sheet was read, and that --sheet reads another.
/// `rows` says where the sheet's data ended early (a run of empty rows). An
/// error says whether the sheet held no diagram (its rows never left the
/// preamble), so that the next may be tried.
fn finish<F: FnMut(Streamed) -> Result<(), IngestError>>(
    rd: Reader<'_, F>,
    rows: Result<Option<String>, IngestError>,
    names: &[String],
    index: usize,
    opts: &ParseOptions,
) -> SheetRead {
    let several = names.len() > 1 && opts.sheet.is_none();
    // A sheet with a diagram that fails: which sheet it is, and the others.
    let hint = |e: IngestError, none: bool| -> (IngestError, bool) {
        if !several || none {
            return (e, none);
        }
        let more = format!(
            " (this is sheet {} `{}` of {}: {}; --sheet N or --sheet NAME reads another)",
            index + 1,
            enginedyn_numerics::format::quote(&names[index]),
            names.len(),
            listed(names)
        );
        (add(e, &more), none)
    };
    let none = several && rd.in_preamble();
    let ended = rows.map_err(|e| hint(e, none))?;
    let none = several && rd.in_preamble();
    let mut head = rd
        .end()
        .map_err(|e| match &ended {
            Some(why) => add(e, &format!(" ({why})")),
            None => e,
        })
        .map_err(|e| hint(e, none))?;
    head.notes.extend(ended);
    if several {
        head.notes.push(if index == 0 {
            format!(
                "read sheet 1 `{}` of {} (--sheet chooses another)",
                enginedyn_numerics::format::quote(&names[0]),
                names.len()
            )
        } else {
            format!(
                "read sheet {} `{}` of {}, the first that holds a diagram (sheet 1 `{}` holds none; --sheet chooses another)",
                index + 1,
                enginedyn_numerics::format::quote(&names[index]),
                names.len(),
                enginedyn_numerics::format::quote(&names[0]),
            )
        });
    }
    Ok(head)
}

/// Where a run of empty rows ([`MAX_EMPTY_ROWS`]) ended the data: after 0-based row `last`
/// (the last row with a cell that is not empty), or before any.
fn ended_at(last: Option<u32>) -> String {
    match last {
        Some(r) => format!(
            "the sheet's data ends at row {}: more than 10,000 empty rows follow, and the rest of the sheet is not read",
            r as u64 + 1
        ),
        None => "the sheet starts with more than 10,000 empty rows, and the rest of it is not read"
            .to_string(),
    }
}

/// More than [`MAX_EMPTY_ROWS`] empty rows lie between the last row with a
/// cell that is not empty (`last`) and 0-based row `r`.
fn too_many_empty(last: Option<u32>, r: u32) -> bool {
    let first_empty = last.map_or(0, |l| l as u64 + 1);
    (r as u64).saturating_sub(first_empty) > MAX_EMPTY_ROWS as u64
}

/// An .xlsx sheet's cells, streamed into rows (cells come row by row).
/// Returns why the data ended early, if it did.
fn stream_rows<F: FnMut(Streamed) -> Result<(), IngestError>>(
    cells: &mut calamine::XlsxCellReader<'_, Watched<'_>>,
    opts: &ParseOptions,
    rd: &mut Reader<'_, F>,
    watch: &RefCell<Watch>,
) -> Result<Option<String>, IngestError> {
    let mut row: Vec<SheetCell> = Vec::new();
    let mut at_row: Option<u32> = None;
    let mut last_used: Option<u32> = None;
    loop {
        let c = match cells.next_cell_with_formula_metadata() {
            Ok(Some(c)) => c,
            Ok(None) => break,
            Err(e) => {
                let cut = watch.borrow().cut;
                return match cut {
                    // The watch saw a run of empty rows go by and stopped
                    // the stream: the data ends with the row before it.
                    Some(Cut::EmptyRows) => {
                        if let Some(prev) = at_row
                            && hand_row(prev as usize + 1, &row, opts, rd)?
                        {
                            last_used = Some(prev);
                        }
                        Ok(Some(ended_at(last_used)))
                    }
                    Some(c) => Err(cut_error(c)),
                    None => Err(unreadable(e)),
                };
            }
        };
        let (r, col) = c.pos;
        if at_row != Some(r) {
            if let Some(prev) = at_row
                && hand_row(prev as usize + 1, &row, opts, rd)?
            {
                last_used = Some(prev);
            }
            row.clear();
            if too_many_empty(last_used, r) {
                return Ok(Some(ended_at(last_used)));
            }
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
        row[col] = sheet_cell(&c.value, c.formula.is_some());
    }
    if let Some(prev) = at_row {
        hand_row(prev as usize + 1, &row, opts, rd)?;
    }
    Ok(None)
}

/// calamine's error reading a sheet's cells.
fn unreadable(e: calamine::XlsxError) -> IngestError {
    match e {
        calamine::XlsxError::CellError(v) => IngestError::Data(format!(
            "a cell holds the error value `{}`, which calamine cannot read (it reads #DIV/0!, #N/A, #NAME?, #NULL!, #NUM!, #REF!, #VALUE!): clear the cell or export the diagram as CSV",
            enginedyn_numerics::format::quote(&v)
        )),
        e => IngestError::Data(format!("the spreadsheet is damaged: {e}")),
    }
}

/// One sheet row (1-based `line`) to the reader: skipped lines, empty
/// rows and comments (`#` in the first cell) as in text. True when the
/// row has a cell that is not empty.
fn hand_row<F: FnMut(Streamed) -> Result<(), IngestError>>(
    line: usize,
    cells: &[SheetCell],
    opts: &ParseOptions,
    rd: &mut Reader<'_, F>,
) -> Result<bool, IngestError> {
    use crate::row::Cells;
    let row = SheetRow(cells);
    if row.used() == 0 {
        return Ok(false);
    }
    if line <= opts.skip_lines {
        return Ok(true);
    }
    if let SheetCell::Text(t) = &cells[first_used(cells)]
        && t.trim_start().starts_with('#')
    {
        let all: Vec<String> = (0..row.len()).map(|k| row.text(k).into_owned()).collect();
        rd.comment(line, &all.join(" "))?;
        return Ok(true);
    }
    rd.row(line, &row, || None)?;
    Ok(true)
}

fn read_rows<F: FnMut(Streamed) -> Result<(), IngestError>>(
    range: &calamine::Range<Data>,
    formulas: Option<&calamine::Range<String>>,
    opts: &ParseOptions,
    rd: &mut Reader<'_, F>,
) -> Result<Option<String>, IngestError> {
    let (row0, col0) = range.start().unwrap_or((0, 0));
    let mut cells: Vec<SheetCell> = Vec::new();
    let mut last_used: Option<u32> = None;
    for (i, row) in range.rows().enumerate() {
        let r = row0.saturating_add(i as u32);
        if too_many_empty(last_used, r) {
            return Ok(Some(ended_at(last_used)));
        }
        cells.clear();
        // Columns before the used range are empty: keep positions as in the sheet.
        cells.resize(col0 as usize, SheetCell::Empty);
        cells.extend(row.iter().enumerate().map(|(j, d)| {
            let formula = d.is_empty()
                && formulas
                    .and_then(|f| f.get_value((r, col0.saturating_add(j as u32))))
                    .is_some_and(|f| !f.is_empty());
            sheet_cell(d, formula)
        }));
        if hand_row(r as usize + 1, &cells, opts, rd)? {
            last_used = Some(r);
        }
    }
    Ok(None)
}

/// The sheets to try in order: the one `--sheet` names, or every sheet
/// (the first that holds a diagram is read).
fn sheets(names: &[String], opts: &ParseOptions) -> Result<std::ops::Range<usize>, IngestError> {
    if names.is_empty() {
        return Err(IngestError::Data("the workbook has no sheet".into()));
    }
    let one = match &opts.sheet {
        None => return Ok(0..names.len()),
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
    Ok(one..one + 1)
}

/// A cell as the reader sees it: a number, text, a date (refused where an
/// angle, pressure or volume is needed), a formula never calculated
/// (`formula`: the cell has one), an error value, or nothing.
fn sheet_cell(d: &impl DataType, formula: bool) -> SheetCell {
    if let Some(v) = d.get_float() {
        SheetCell::Number(v)
    } else if let Some(v) = d.get_int() {
        SheetCell::Number(v as f64)
    } else if let Some(t) = d.get_datetime() {
        SheetCell::Date(Box::new(excel_date(&t)))
    } else if let Some(t) = d.get_string() {
        SheetCell::Text(t.to_string())
    } else if let Some(b) = d.get_bool() {
        SheetCell::Text(b.to_string())
    } else if let Some(e) = d.get_error() {
        SheetCell::Error(error_shown(e))
    } else if let Some(s) = d.get_datetime_iso() {
        SheetCell::Date(Box::new(DateCell {
            kind: if s.contains(['-', '/']) {
                "a date"
            } else {
                "a time"
            },
            shown: s.to_string(),
            serial: None,
        }))
    } else if let Some(s) = d.get_duration_iso() {
        SheetCell::Date(Box::new(DateCell {
            kind: "a duration",
            shown: s.to_string(),
            serial: None,
        }))
    } else if d.is_empty() {
        if formula {
            SheetCell::Formula
        } else {
            SheetCell::Empty
        }
    } else {
        SheetCell::Text(d.as_string().unwrap_or_default())
    }
}

/// An error value as the spreadsheet shows it.
fn error_shown(e: &calamine::CellErrorType) -> &'static str {
    use calamine::CellErrorType as E;
    match e {
        E::Div0 => "#DIV/0!",
        E::NA => "#N/A",
        E::Name => "#NAME?",
        E::Null => "#NULL!",
        E::Num => "#NUM!",
        E::Ref => "#REF!",
        E::Value => "#VALUE!",
        E::GettingData => "#GETTING_DATA",
    }
}

/// A date- or time-formatted number: what its format makes of it.
fn excel_date(t: &calamine::ExcelDateTime) -> DateCell {
    let serial = t.as_f64();
    let (y, mo, d, h, mi, s, _) = t.to_ymd_hms_milli();
    let (kind, shown) = if t.is_duration() {
        let secs = (serial * 86_400.0).round();
        (
            "a duration",
            format!(
                "{}:{:02}:{:02}",
                (secs / 3600.0).trunc(),
                ((secs / 60.0).trunc() % 60.0) as u32,
                (secs % 60.0) as u32
            ),
        )
    } else if (0.0..1.0).contains(&serial) {
        ("a time of day", format!("{h:02}:{mi:02}:{s:02}"))
    } else if serial.fract() == 0.0 {
        ("a date", format!("{y:04}-{mo:02}-{d:02}"))
    } else {
        (
            "a date and time",
            format!("{y:04}-{mo:02}-{d:02} {h:02}:{mi:02}:{s:02}"),
        )
    };
    DateCell {
        kind,
        shown,
        serial: Some(serial),
    }
}

fn first_used(cells: &[SheetCell]) -> usize {
    cells
        .iter()
        .position(|c| !matches!(c, SheetCell::Empty))
        .unwrap_or(0)
}

/// One part of a workbook's ZIP archive: where its packed bytes lie.
#[derive(Debug, Clone)]
struct Part {
    /// Its packed bytes: `start..end` of the file.
    start: u64,
    end: u64,
    deflated: bool,
    /// An XML part (`.xml`, `.rels`): its text is scanned.
    xml: bool,
}

/// The parts of the ZIP archive in `bytes` (none when it is no ZIP
/// archive), ordered by where their bytes start.
fn zip_parts(bytes: &[u8]) -> Vec<Part> {
    let Ok(zip) = zip::ZipArchive::new(std::io::Cursor::new(bytes)) else {
        return Vec::new();
    };
    let mut parts: Vec<Part> = (0..zip.len())
        .filter_map(|i| {
            let e = zip.by_index_data(i).ok()?;
            // The data follows the local header: 30 bytes, the name and
            // the extra field (their lengths at offsets 26 and 28).
            let h = usize::try_from(e.header_start()).ok()?;
            let local = bytes.get(h..h.checked_add(30)?)?;
            if local[..4] != *b"PK\x03\x04" {
                return None;
            }
            let name_len = u16::from_le_bytes([local[26], local[27]]) as u64;
            let extra_len = u16::from_le_bytes([local[28], local[29]]) as u64;
            let start = e.header_start() + 30 + name_len + extra_len;
            let name = e.name().ok()?;
            Some(Part {
                xml: name.ends_with(".xml") || name.ends_with(".rels"),
                start,
                end: start.saturating_add(e.compressed_size()),
                deflated: e.compression() == zip::CompressionMethod::Deflated,
            })
        })
        .collect();
    parts.sort_by_key(|p| p.start);
    parts
}

/// Why the watch stopped calamine's stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Cut {
    /// A run of more than [`MAX_EMPTY_ROWS`] empty rows went by.
    EmptyRows,
    /// A part unpacked to more than [`MAX_SHEET_BYTES`].
    Bound,
    /// A stretch of XML longer than [`MAX_XML_SPAN`].
    Span,
}

/// The workbook's bytes as calamine reads them, each read shown to the
/// [`Watch`] first.
#[derive(Clone)]
struct Watched<'b> {
    bytes: &'b [u8],
    pos: u64,
    watch: &'b RefCell<Watch>,
}

impl Read for Watched<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let mut watch = self.watch.borrow_mut();
        if watch.cut.is_some() {
            return Err(std::io::Error::other("stopped: past a bound"));
        }
        let from = usize::try_from(self.pos)
            .unwrap_or(usize::MAX)
            .min(self.bytes.len());
        let n = buf.len().min(self.bytes.len() - from);
        buf[..n].copy_from_slice(&self.bytes[from..from + n]);
        watch.saw(self.pos, &self.bytes[from..from + n]);
        match watch.cut {
            // Past a bound: calamine gets none of these bytes, so it holds
            // no more of the part than it had.
            Some(Cut::Bound | Cut::Span) => Err(std::io::Error::other("stopped: past a bound")),
            // The rows before an empty run are in these bytes: calamine
            // gets them, and stops at its next read.
            _ => {
                self.pos += n as u64;
                Ok(n)
            }
        }
    }
}

impl Seek for Watched<'_> {
    fn seek(&mut self, to: SeekFrom) -> std::io::Result<u64> {
        let len = self.bytes.len() as i128;
        let at = match to {
            SeekFrom::Start(p) => p as i128,
            SeekFrom::End(d) => len + d as i128,
            SeekFrom::Current(d) => self.pos as i128 + d as i128,
        };
        if at < 0 {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "seek before the start",
            ));
        }
        self.pos = u64::try_from(at).unwrap_or(u64::MAX);
        Ok(self.pos)
    }
}

/// Unpacks, a second time, each ZIP part calamine reads, in step with it
/// (from the packed bytes it reads), counting the bytes, the longest
/// stretch of XML without a tag boundary and the empty `<row>` elements.
/// Once a part passes [`MAX_SHEET_BYTES`] or [`MAX_XML_SPAN`], the read
/// that took it there fails, so calamine never holds those bytes; once a
/// run of more than [`MAX_EMPTY_ROWS`] empty rows goes by, the next read
/// fails ([`Cut`]), and calamine stops within the packed bytes it already
/// holds (its buffer: 8 KiB). The rows themselves are read, and the data ended, by
/// [`stream_rows`] from the cells' own row numbers; the watch only stops
/// the work calamine would do past them.
struct Watch {
    parts: Vec<Part>,
    stream: Option<Stream>,
    cut: Option<Cut>,
}

impl Watch {
    fn new(parts: Vec<Part>) -> Self {
        Self {
            parts,
            stream: None,
            cut: None,
        }
    }

    /// Bytes `data` of the file, from `pos`, handed to calamine.
    fn saw(&mut self, pos: u64, data: &[u8]) {
        if self.cut.is_some() || data.is_empty() {
            return;
        }
        let end = pos + data.len() as u64;
        if let Some(s) = self.stream.as_mut()
            && s.next == pos
            && pos < s.end
        {
            let hi = end.min(s.end);
            s.next = hi;
            self.cut = s.feed(&data[..(hi - pos) as usize]);
            return;
        }
        // A part read from its start (the ZIP reader reads each part front
        // to back from there; other reads, of headers and the directory,
        // may touch a part's bytes in passing). Parts that overlap start a
        // stream of their own where each starts.
        let Some(p) = self.parts.iter().find(|p| pos <= p.start && p.start < end) else {
            return;
        };
        let mut s = Stream::new(p);
        let hi = end.min(p.end);
        s.next = hi;
        self.cut = s.feed(&data[(p.start - pos) as usize..(hi - pos) as usize]);
        self.stream = Some(s);
    }
}

/// One part being unpacked by the watch.
struct Stream {
    /// The file offset of the next packed byte expected, and of the end.
    next: u64,
    end: u64,
    /// `None` for a stored part.
    inflate: Option<Box<flate2::Decompress>>,
    /// The packed data is not deflate after all (calamine will say so).
    broken: bool,
    out: Vec<u8>,
    unpacked: u64,
    /// `None` for a part that is not XML.
    scan: Option<Scan>,
}

impl Stream {
    fn new(p: &Part) -> Self {
        Self {
            next: p.start,
            end: p.end,
            inflate: p.deflated.then(|| Box::new(flate2::Decompress::new(false))),
            broken: false,
            out: vec![0; if p.deflated { 1 << 16 } else { 0 }],
            unpacked: 0,
            scan: p.xml.then(Scan::default),
        }
    }

    /// Unpacked bytes `b`: counted and scanned.
    fn take(unpacked: &mut u64, scan: &mut Option<Scan>, b: &[u8]) -> Option<Cut> {
        *unpacked += b.len() as u64;
        if *unpacked > MAX_SHEET_BYTES {
            return Some(Cut::Bound);
        }
        scan.as_mut().and_then(|s| s.bytes(b))
    }

    fn feed(&mut self, mut packed: &[u8]) -> Option<Cut> {
        if self.broken {
            return None;
        }
        let Some(z) = self.inflate.as_mut() else {
            return Self::take(&mut self.unpacked, &mut self.scan, packed);
        };
        loop {
            let (was_in, was_out) = (z.total_in(), z.total_out());
            let status = z.decompress(packed, &mut self.out, flate2::FlushDecompress::None);
            let used = (z.total_in() - was_in) as usize;
            let made = (z.total_out() - was_out) as usize;
            packed = &packed[used..];
            let Ok(status) = status else {
                self.broken = true;
                return None;
            };
            if let Some(cut) = Self::take(&mut self.unpacked, &mut self.scan, &self.out[..made]) {
                return Some(cut);
            }
            if status == flate2::Status::StreamEnd || (used == 0 && made == 0) {
                return None;
            }
        }
    }
}

/// Where the scanner is in the XML.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
enum At {
    /// Between tags.
    #[default]
    Text,
    /// After `<`.
    Open,
    /// After `<!` (`n` bytes of what follows seen).
    Bang,
    /// In `<!-- … -->`: how many `-` just went by.
    Comment(u8),
    /// In `<![CDATA[ … ]]>`: how many `]` just went by.
    CData(u8),
    /// In `<? … ?>`: whether `?` just went by.
    Pi(bool),
    /// In `<!DOCTYPE …>`.
    Decl,
    /// In a tag's name.
    Name,
    /// In a tag, after its name: whether `/` just went by.
    Attrs(bool),
    /// In a quoted attribute value.
    Quote(u8),
}

/// Counts runs of empty `<row>` elements (those without a `<c>` cell) in a
/// sheet's XML, byte by byte as it unpacks.
#[derive(Debug, Default)]
struct Scan {
    at: At,
    /// The tag being read is an end tag.
    end_tag: bool,
    /// Its local name (after any `prefix:`), up to 16 bytes.
    name: [u8; 16],
    name_len: usize,
    in_sheet: bool,
    /// Past `</sheetData>` (or lost): rows no longer counted.
    rows_done: bool,
    row_open: bool,
    row_has_cell: bool,
    /// Empty rows in a row.
    run: u32,
    /// Bytes since the last tag boundary (`<` or `>`).
    span: u64,
}

impl Scan {
    fn bytes(&mut self, b: &[u8]) -> Option<Cut> {
        let mut i = 0;
        while i < b.len() {
            // Text and quoted values are skipped in one step each; every
            // other byte is one step of the machine.
            let step = match self.at {
                At::Text => memchr::memchr(b'<', &b[i..]),
                At::Quote(q) => memchr::memchr(q, &b[i..]),
                _ => Some(0),
            };
            let Some(k) = step else {
                self.span += (b.len() - i) as u64;
                return (self.span > MAX_XML_SPAN).then_some(Cut::Span);
            };
            self.span += k as u64;
            if self.span > MAX_XML_SPAN {
                return Some(Cut::Span);
            }
            i += k;
            let c = b[i];
            i += 1;
            self.span += 1;
            match self.at {
                At::Text => {
                    self.span = 0;
                    self.at = At::Open;
                }
                At::Quote(_) => self.at = At::Attrs(false),
                At::Open => {
                    self.end_tag = false;
                    self.name_len = 0;
                    self.at = match c {
                        b'!' => At::Bang,
                        b'?' => At::Pi(false),
                        b'/' => {
                            self.end_tag = true;
                            At::Name
                        }
                        _ => {
                            self.push_name(c);
                            At::Name
                        }
                    };
                }
                At::Bang => {
                    self.at = match c {
                        b'-' => At::Comment(0),
                        b'[' => At::CData(0),
                        _ => At::Decl,
                    };
                }
                At::Comment(n) => {
                    self.at = match c {
                        b'-' => At::Comment(n.saturating_add(1)),
                        b'>' if n >= 2 => self.text(),
                        _ => At::Comment(0),
                    };
                }
                At::CData(n) => {
                    self.at = match c {
                        b']' => At::CData(n.saturating_add(1)),
                        b'>' if n >= 2 => self.text(),
                        _ => At::CData(0),
                    };
                }
                At::Pi(q) => {
                    self.at = match c {
                        b'>' if q => self.text(),
                        _ => At::Pi(c == b'?'),
                    };
                }
                At::Decl => match c {
                    // A document type with declarations of its own: a
                    // sheet never has one; stop counting rows.
                    b'[' => self.rows_done = true,
                    b'>' => self.at = self.text(),
                    _ => {}
                },
                At::Name => match c {
                    b'>' => {
                        if let Some(cut) = self.tag(false) {
                            return Some(cut);
                        }
                    }
                    b'/' => self.at = At::Attrs(true),
                    b' ' | b'\t' | b'\r' | b'\n' => self.at = At::Attrs(false),
                    b':' => self.name_len = 0,
                    _ => self.push_name(c),
                },
                At::Attrs(slash) => match c {
                    b'>' => {
                        if let Some(cut) = self.tag(slash) {
                            return Some(cut);
                        }
                    }
                    b'"' | b'\'' => self.at = At::Quote(c),
                    b'/' => self.at = At::Attrs(true),
                    b' ' | b'\t' | b'\r' | b'\n' => self.at = At::Attrs(slash),
                    _ => self.at = At::Attrs(false),
                },
            }
        }
        None
    }

    /// Back between tags: a new stretch of text starts.
    fn text(&mut self) -> At {
        self.span = 0;
        At::Text
    }

    fn push_name(&mut self, c: u8) {
        if self.name_len < self.name.len() {
            self.name[self.name_len] = c;
        }
        self.name_len += 1;
    }

    /// A tag ends (`closed`: `<…/>`).
    fn tag(&mut self, closed: bool) -> Option<Cut> {
        self.at = self.text();
        let name = if self.name_len <= self.name.len() {
            &self.name[..self.name_len]
        } else {
            &[]
        };
        if self.rows_done {
            return None;
        }
        match (self.end_tag, name) {
            (true, b"sheetData") => self.rows_done = true,
            (true, b"row") if self.row_open => {
                self.row_open = false;
                if !self.row_has_cell {
                    return self.empty_row();
                }
                self.run = 0;
            }
            (false, b"sheetData") if closed => self.rows_done = true,
            (false, b"sheetData") => self.in_sheet = true,
            (false, b"row") if self.in_sheet && closed => return self.empty_row(),
            (false, b"row") if self.in_sheet => {
                self.row_open = true;
                self.row_has_cell = false;
            }
            (false, b"c") if self.in_sheet => {
                self.row_has_cell = true;
                self.run = 0;
            }
            _ => {}
        }
        None
    }

    fn empty_row(&mut self) -> Option<Cut> {
        self.run += 1;
        (self.run > MAX_EMPTY_ROWS).then_some(Cut::EmptyRows)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scan_all(xml: &str, chunk: usize) -> (Option<Cut>, u32) {
        let mut s = Scan::default();
        for piece in xml.as_bytes().chunks(chunk) {
            if let Some(c) = s.bytes(piece) {
                return (Some(c), s.run);
            }
        }
        (None, s.run)
    }

    #[test]
    fn the_scanner_counts_empty_rows_whatever_the_chunks() {
        let rows = |n: usize, row: &str| row.repeat(n);
        let head = r#"<?xml version="1.0"?><worksheet xmlns="x"><sheetData><row r="1"><c r="A1"><v>1</v></c></row>"#;
        for chunk in [1, 2, 3, 7, 64, 1 << 20] {
            // Exactly the bound: not a cut.
            let xml = format!("{head}{}</sheetData></worksheet>", rows(10_000, "<row/>"));
            assert_eq!(scan_all(&xml, chunk), (None, 10_000), "chunk {chunk}");
            // One more, in either spelling, with a prefix: a cut.
            for row in [
                "<row/>",
                "<x:row r=\"5\" spans='1:2'></x:row>",
                "<row >\n</row>",
            ] {
                let xml = format!("{head}{}", rows(10_001, row));
                assert_eq!(
                    scan_all(&xml, chunk).0,
                    Some(Cut::EmptyRows),
                    "{row} {chunk}"
                );
            }
            // Cells break the run; rows hidden in comments, CDATA, quotes
            // and instructions are no rows.
            let fake =
                r#"<!-- <row/> --><![CDATA[<row/>]]><?pi <row/> ?><row a="<row/>"><x:c/></row>"#;
            let xml = format!(
                "{head}{}{fake}{}",
                rows(9_000, "<row/>"),
                rows(9_000, "<row/>")
            );
            assert_eq!(scan_all(&xml, chunk), (None, 9_000), "chunk {chunk}");
            // Nothing after the sheet's data counts, nor before it.
            let xml = format!(
                "<worksheet>{}<sheetData/>{}",
                rows(10_001, "<row/>"),
                rows(10_001, "<row/>")
            );
            assert_eq!(scan_all(&xml, chunk).0, None);
        }
    }

    #[test]
    fn column_names_are_excels() {
        use crate::row::column_name;
        assert_eq!(column_name(1), "A");
        assert_eq!(column_name(26), "Z");
        assert_eq!(column_name(27), "AA");
        assert_eq!(column_name(16_384), "XFD");
    }

    #[test]
    fn the_scanner_bounds_a_stretch_of_xml() {
        let span = MAX_XML_SPAN as usize;
        for (xml, cut) in [
            (format!("<a>{}</a>", "x".repeat(span)), None),
            (format!("<a>{}</a>", "x".repeat(span + 1)), Some(Cut::Span)),
            (format!("<a b=\"{}\"/>", "x".repeat(span)), Some(Cut::Span)),
            (format!("<!--{}-->", "x".repeat(span)), Some(Cut::Span)),
        ] {
            assert_eq!(scan_all(&xml, 1 << 16).0, cut, "{}", xml.len());
        }
    }

    #[test]
    fn the_watch_follows_every_fixture_sheet_to_its_end() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/fixtures/measured");
        for name in [
            "excel_single.xlsx",
            "daq_72khz_tdc.xlsx",
            "libreoffice_cycles.xlsx",
            "excel_title_second_sheet.xlsx",
        ] {
            let bytes = std::fs::read(format!("{dir}/{name}")).unwrap();
            let watch = RefCell::new(Watch::new(zip_parts(&bytes)));
            let mut book = calamine::Xlsx::new(Watched {
                bytes: &bytes,
                pos: 0,
                watch: &watch,
            })
            .unwrap();
            let names = book.sheet_names();
            let mut cells = book.worksheet_cells_reader(names.last().unwrap()).unwrap();
            let mut n = 0;
            while cells.next_cell().unwrap().is_some() {
                n += 1;
            }
            let w = watch.borrow();
            assert!(n > 100, "{name}");
            assert!(w.cut.is_none(), "{name}");
            let s = w.stream.as_ref().unwrap();
            let scan = s.scan.as_ref().unwrap();
            assert!(scan.in_sheet && scan.rows_done && !s.broken, "{name}");
            assert!(s.unpacked > 10_000, "{name}: {}", s.unpacked);
        }
        // The .ods: calamine reads it whole at open, the watch in step.
        let bytes = std::fs::read(format!("{dir}/libreoffice_cycles.ods")).unwrap();
        let watch = RefCell::new(Watch::new(zip_parts(&bytes)));
        let mut book = calamine::open_workbook_auto_from_rs(Watched {
            bytes: &bytes,
            pos: 0,
            watch: &watch,
        })
        .unwrap();
        let names = book.sheet_names();
        let range = book.worksheet_range(&names[0]).unwrap();
        assert!(range.height() > 100);
        assert!(watch.borrow().cut.is_none());
    }
}
