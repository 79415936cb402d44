//! The text source: lines of a CSV-like file as byte slices, the delimiter
//! detected, cells split without allocation, handed to the reader as rows
//! (and, while they only continue the cycles being read, to the fast paths).

use crate::error::{IngestError, at};
use crate::layout::Layout;
use crate::number::{PLAIN_CELLS, Shapes, plain_row};
use crate::reader::{Phase, Reader};
use crate::row::{Numbers, TextRow};
use crate::{Header, ParseOptions, Streamed};

/// A row's delimiter.
#[derive(Clone, Copy, PartialEq, Debug)]
pub(crate) enum Delim {
    Comma,
    Semicolon,
    Tab,
    Space,
}

impl Delim {
    pub(crate) fn detect(line: &[u8]) -> Delim {
        if line.contains(&b'\t') {
            Delim::Tab
        } else if line.contains(&b';') {
            Delim::Semicolon
        } else if line.contains(&b',') {
            Delim::Comma
        } else {
            Delim::Space
        }
    }
    /// Byte ranges of the cells of `line`, trimmed of ASCII white space
    /// (a reused buffer and a byte scan: no allocation per line).
    pub(crate) fn split(self, line: &[u8], out: &mut Vec<(usize, usize)>) {
        out.clear();
        let b = line;
        let trimmed = |mut s: usize, mut e: usize| {
            while s < e && b[s].is_ascii_whitespace() {
                s += 1;
            }
            while e > s && b[e - 1].is_ascii_whitespace() {
                e -= 1;
            }
            (s, e)
        };
        let sep = match self {
            Delim::Comma => b',',
            Delim::Semicolon => b';',
            Delim::Tab => b'\t',
            Delim::Space => {
                let mut i = 0;
                while i < b.len() {
                    while i < b.len() && b[i].is_ascii_whitespace() {
                        i += 1;
                    }
                    let s = i;
                    while i < b.len() && !b[i].is_ascii_whitespace() {
                        i += 1;
                    }
                    if i > s {
                        out.push((s, i));
                    }
                }
                return;
            }
        };
        let mut start = 0;
        for (i, &c) in b.iter().enumerate() {
            if c == sep {
                out.push(trimmed(start, i));
                start = i + 1;
            }
        }
        out.push(trimmed(start, b.len()));
    }
    /// A decimal comma is accepted where the comma is not the delimiter.
    pub(crate) fn decimal_comma(self) -> bool {
        self != Delim::Comma
    }
    /// The one-byte separator, `None` for runs of white space.
    pub(crate) fn byte(self) -> Option<u8> {
        match self {
            Delim::Comma => Some(b','),
            Delim::Semicolon => Some(b';'),
            Delim::Tab => Some(b'\t'),
            Delim::Space => None,
        }
    }
}

/// The longest line read (bytes): 1 MiB (INTERFACE.md, "Bounds").
pub const MAX_LINE: usize = 1 << 20;

/// The error a line longer than [`MAX_LINE`] gives.
#[derive(Debug)]
struct LineTooLong;

impl std::fmt::Display for LineTooLong {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a line longer than the 1 MiB bound")
    }
}

impl std::error::Error for LineTooLong {}

/// Lines of a reader as byte slices, read in large blocks (no per-line
/// allocation or UTF-8 check; cells are checked where they are used).
struct Lines<R> {
    reader: R,
    buf: Vec<u8>,
    start: usize,
    end: usize,
    eof: bool,
}

impl<R: std::io::Read> Lines<R> {
    fn new(reader: R) -> Self {
        Self {
            reader,
            buf: vec![0; 1 << 16],
            start: 0,
            end: 0,
            eof: false,
        }
    }

    /// The unread bytes: at least 4 KiB (longer than any plain row) unless
    /// the file ends first, and whether it does.
    #[inline(always)]
    fn window(&mut self) -> std::io::Result<(&[u8], bool)> {
        if !self.eof && self.end - self.start < 4096 {
            self.refill()?;
        }
        Ok((&self.buf[self.start..self.end], self.eof))
    }

    #[cold]
    fn refill(&mut self) -> std::io::Result<()> {
        while !self.eof && self.end - self.start < 4096 {
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.start = 0;
            match self.reader.read(&mut self.buf[self.end..]) {
                Ok(0) => self.eof = true,
                Ok(k) => self.end += k,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        Ok(())
    }

    /// Marks `k` bytes of [`Self::window`] read.
    #[inline]
    fn consume(&mut self, k: usize) {
        self.start += k;
    }

    /// The next line without its `\n`, or `None` at the end.
    fn next_line(&mut self) -> std::io::Result<Option<&[u8]>> {
        loop {
            if let Some(k) = memchr::memchr(b'\n', &self.buf[self.start..self.end]) {
                let s = self.start;
                self.start += k + 1;
                return Ok(Some(&self.buf[s..s + k]));
            }
            if self.eof {
                if self.start < self.end {
                    let s = self.start;
                    self.start = self.end;
                    return Ok(Some(&self.buf[s..self.end]));
                }
                return Ok(None);
            }
            // Keep the partial line, make room, read more.
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.start = 0;
            if self.end == self.buf.len() {
                // A line is bounded: past it the file is not a diagram
                // (a binary file, /dev/zero), and holding it would grow
                // without bound.
                if self.buf.len() > MAX_LINE {
                    return Err(std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        LineTooLong,
                    ));
                }
                let grown = (self.buf.len() * 2).min(MAX_LINE + 1);
                self.buf.resize(grown, 0);
            }
            match self.reader.read(&mut self.buf[self.end..]) {
                Ok(0) => self.eof = true,
                Ok(k) => self.end += k,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
}

/// True for Excel's delimiter line `sep=X` (X one byte; any case, a
/// carriage return after it allowed).
pub(crate) fn sep_line(line: &[u8]) -> bool {
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    line.len() == 5 && line[..4].eq_ignore_ascii_case(b"sep=")
}

/// The same line split at runs of two or more blanks: header names that
/// hold single spaces in a space-delimited file.
fn wide_split(line: &[u8]) -> Vec<String> {
    crate::row::decode(line)
        .split("  ")
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.trim_matches('"').to_string())
        .collect()
}

/// Reads text rows and hands them to the reader.
pub(crate) fn read<R: std::io::Read, F: FnMut(Streamed) -> Result<(), IngestError>>(
    reader: R,
    opts: &ParseOptions,
    sink: F,
) -> Result<Header, IngestError> {
    let mut lines = Lines::new(reader);
    let mut rd = Reader::new(opts, sink);
    // The delimiter: each line's own above the data, fixed by the first data
    // row (or by Excel's `sep=` line).
    let mut delim: Option<Delim> = None;
    let mut spans: Vec<(usize, usize)> = Vec::new();
    let mut lineno = 0usize;
    let mut vals = [0.0; PLAIN_CELLS];
    let mut shapes = [Shapes::default(); PLAIN_CELLS];
    let mut row_buf: Vec<f64> = Vec::new();
    loop {
        // (Not while a headerless file is probed: every row counts there.)
        if let (Some(sep), Phase::Data(layout), None) =
            (delim.and_then(Delim::byte), &mut rd.phase, &rd.out.probe)
        {
            // Runs of plain rows that continue the cycles being read.
            let (w, eof) = lines.window()?;
            let (used, n) = match &mut **layout {
                Layout::Long(l) if l.fast() => crate::fast::long(w, eof, sep, l),
                Layout::PerColumn(p) if p.fast() => {
                    crate::fast::per_column(w, eof, sep, p, &mut row_buf)
                }
                _ => (0, 0),
            };
            lineno += n;
            lines.consume(used);
            // A plain row straight from the read buffer: no line search, one pass.
            let ncols = match &**layout {
                Layout::Long(l) => l.ncols,
                _ => usize::MAX,
            };
            if ncols <= PLAIN_CELLS {
                let (w, eof) = lines.window()?;
                if let Some((k, used)) = plain_row(w, sep, sep != b',', eof, &mut vals, &mut shapes)
                    && k == ncols
                {
                    lines.consume(used);
                    lineno += 1;
                    rd.row(lineno, &Numbers(&vals[..k]), || None)?;
                    continue;
                }
            }
        }
        let raw = match lines.next_line() {
            Ok(Some(raw)) => raw,
            Ok(None) => break,
            Err(e) if e.get_ref().is_some_and(|e| e.is::<LineTooLong>()) => {
                return Err(at(
                    lineno + 1,
                    None,
                    "this line is longer than the 1 MiB bound of a line: not a diagram (a binary file or a device?); read no further",
                ));
            }
            Err(e) => return Err(e.into()),
        };
        lineno += 1;
        if lineno <= opts.skip_lines {
            continue;
        }
        // A byte-order mark may open the file; ASCII trimming is all a line needs.
        let line = raw.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(raw);
        let t = line.trim_ascii();
        if t.is_empty() {
            continue;
        }
        if memchr::memchr(0, t).is_some() {
            return Err(at(
                lineno,
                None,
                "this line holds a NUL byte: a damaged file, or binary data inside text; read no further",
            ));
        }
        if t[0] == b'#' {
            if let Ok(s) = std::str::from_utf8(t) {
                rd.comment(lineno, s)?;
            }
            continue;
        }
        let preamble = rd.in_preamble();
        // Excel writes `sep=;` above the header to name the delimiter.
        if preamble && delim.is_none() && sep_line(line) {
            delim = Some(match line[4] {
                b',' => Delim::Comma,
                b';' => Delim::Semicolon,
                b'\t' => Delim::Tab,
                b' ' => Delim::Space,
                other => {
                    return Err(at(
                        lineno,
                        None,
                        format!(
                            "`sep={}`: cells are delimited by commas, semicolons, tabs or spaces",
                            other as char
                        ),
                    ));
                }
            });
            continue;
        }
        let d = delim.unwrap_or_else(|| Delim::detect(t));
        d.split(t, &mut spans);
        let row = TextRow {
            line: t,
            spans: &spans,
            decimal_comma: d.decimal_comma(),
        };
        rd.row(lineno, &row, || (d == Delim::Space).then(|| wide_split(t)))?;
        if preamble && !rd.in_preamble() {
            delim = Some(d);
        }
    }
    rd.end()
}

/// UTF-16 text (Excel's "Unicode text", LabVIEW and some DAQ software)
/// turned into UTF-8 as it streams; the byte-order mark becomes UTF-8's,
/// which the reader skips. An unpaired surrogate becomes U+FFFD, which no
/// number cell holds, so it is an error where a number is needed.
pub(crate) struct Utf16<R> {
    inner: R,
    little: bool,
    raw: Vec<u8>,
    out: Vec<u8>,
    pos: usize,
    eof: bool,
}

impl<R: std::io::Read> Utf16<R> {
    pub(crate) fn new(inner: R, little: bool) -> Self {
        Self {
            inner,
            little,
            raw: Vec::with_capacity(1 << 16),
            out: Vec::with_capacity(1 << 16),
            pos: 0,
            eof: false,
        }
    }

    fn refill(&mut self) -> std::io::Result<()> {
        self.out.clear();
        self.pos = 0;
        while self.out.is_empty() && !self.eof {
            let have = self.raw.len();
            self.raw.resize(have + (1 << 15), 0);
            let n = loop {
                match self.inner.read(&mut self.raw[have..]) {
                    Ok(n) => break n,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => return Err(e),
                }
            };
            self.raw.truncate(have + n);
            self.eof = n == 0;
            let mut units: Vec<u16> = self
                .raw
                .chunks_exact(2)
                .map(|b| {
                    if self.little {
                        u16::from_le_bytes([b[0], b[1]])
                    } else {
                        u16::from_be_bytes([b[0], b[1]])
                    }
                })
                .collect();
            let mut used = units.len() * 2;
            // Keep a high surrogate whose pair has not arrived yet.
            if !self.eof && units.last().is_some_and(|u| (0xD800..0xDC00).contains(u)) {
                units.pop();
                used -= 2;
            }
            for c in char::decode_utf16(units) {
                let mut b = [0u8; 4];
                let c = c.unwrap_or(char::REPLACEMENT_CHARACTER);
                self.out.extend_from_slice(c.encode_utf8(&mut b).as_bytes());
            }
            self.raw.drain(..used);
        }
        Ok(())
    }

    /// True once the end is read with a byte left over: the text was cut
    /// mid-character.
    pub(crate) fn ends_mid_character(&self) -> bool {
        self.eof && self.raw.len() % 2 == 1
    }
}

impl<R: std::io::Read> std::io::Read for Utf16<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.pos == self.out.len() {
            self.refill()?;
        }
        let n = buf.len().min(self.out.len() - self.pos);
        buf[..n].copy_from_slice(&self.out[self.pos..self.pos + n]);
        self.pos += n;
        Ok(n)
    }
}
