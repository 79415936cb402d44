//! Cells to numbers: the decimal readers every path shares, all bit-identical
//! to `str::parse` where they accept a cell.

use crate::error::{IngestError, at};

/// Exact powers of ten: a decimal of at most 15 digits is an exact integer
/// over one of these, so one division rounds it correctly (Clinger).
pub(crate) const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// The value of a plain decimal from its digits: `m` (at most 15 digits
/// in all, the caller has counted them) with `frac` of them after the
/// point, negated for `neg`. `m < 10^15 < 2^53` is exact as an i64 (one
/// instruction, where u64 takes several) and as an f64; the one division
/// by an exact power of ten then rounds correctly (Clinger's fast path, the
/// value `str::parse` gives), and is skipped for integers. Every fast
/// reader of decimals (`plain_row`, `fast_decimal`, the row templates)
/// ends here.
#[inline(always)]
pub(crate) fn decimal_value(m: u64, frac: usize, neg: bool) -> f64 {
    let x = m as i64 as f64;
    let v = if frac == 0 { x } else { x / POW10[frac & 15] };
    if neg { -v } else { v }
}

/// The eight bytes of `b` from `i`, the first in the lowest byte (the one
/// little-endian word reader of the crate's fast paths).
#[inline(always)]
pub(crate) fn word(b: &[u8], i: usize) -> u64 {
    let mut w = [0; 8];
    w.copy_from_slice(&b[i..i + 8]);
    u64::from_le_bytes(w)
}

/// Bytes repeated in every lane of a word.
const LANES: u64 = 0x0101_0101_0101_0101;

/// The bytes of `w` less `'0'` in each lane: digits become 0 to 9, every
/// other byte 10 or more (no borrow: an exclusive or).
#[inline(always)]
fn less_zeros(w: u64) -> u64 {
    w ^ (0x30 * LANES)
}

/// The index of the first byte of `x` (from [`less_zeros`]) that is not a
/// digit, 8 when all are. A lane of 10 or more has its high bit set after
/// adding 0x76 (or had it before); a sum may carry into the next lane, but
/// only out of a lane that is no digit, and the bytes after the first
/// non-digit do not count.
#[inline(always)]
fn digits_in(x: u64) -> usize {
    let high = (x.wrapping_add(0x76 * LANES) | x) & (0x80 * LANES);
    (high.trailing_zeros() / 8) as usize
}

/// The first `k` bytes of `x` (`k` at most 7) moved to the top of the
/// word, zeros below them. Two shifts: `k` may be 0, and a shift by 64
/// overflows.
#[inline(always)]
fn top(x: u64, k: usize) -> u64 {
    (x << (8 * (7 - k))) << 8
}

/// The number the digits of `x` spell (each byte 0 to 9, the first byte
/// the most significant; zero bytes are leading zeros): pairs, quads and
/// the two halves combined by three multiplications (Lemire's SWAR method).
#[inline(always)]
fn eight_digits(x: u64) -> u64 {
    let v = (x.wrapping_mul(10 << 8 | 1)) >> 8;
    let v = ((v & 0x00ff_00ff_00ff_00ff).wrapping_mul(100 << 16 | 1)) >> 16;
    ((v & 0x0000_ffff_0000_ffff).wrapping_mul(10_000 << 32 | 1)) >> 32
}

/// Powers of ten as integers, for the fraction digits of [`swar_digits`].
const POW10_INT: [u64; 8] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000, 10_000_000];

/// The common shape of a plain decimal read by words instead of bytes:
/// at `b[s..]`, at most 7 digits, then optionally a point (`.`, or `,`
/// where `decimal_comma`) and at most 7 more, at least one digit in all
/// (`87.14250`, `5.`, `.5`, `720`). Returns the digits as one integer, the
/// number of them after the point and the index after the cell; `None`
/// where the shape is not this one or `b` holds fewer than 16 bytes from
/// `s`, and the byte-at-a-time reader decides (where both read a cell they
/// read the same: `swar_digits_equal_digit_runs`).
#[inline(always)]
pub(crate) fn swar_digits(b: &[u8], s: usize, decimal_comma: bool) -> Option<(u64, usize, usize)> {
    if b.len() < s + 16 {
        return None;
    }
    let w = less_zeros(word(b, s));
    let int = digits_in(w);
    if int == 8 {
        return None;
    }
    let c = b[s + int];
    if c != b'.' && !(decimal_comma && c == b',') {
        return (int > 0).then(|| (eight_digits(top(w, int)), 0, s + int));
    }
    let f = less_zeros(word(b, s + int + 1));
    let frac = digits_in(f);
    if frac == 8 || int + frac == 0 {
        return None;
    }
    // The integer digits above the fraction's in one word when they fit.
    let m = if int + frac <= 8 {
        eight_digits((top(w, int) >> (8 * frac)) | top(f, frac))
    } else {
        eight_digits(top(w, int)) * POW10_INT[frac] + eight_digits(top(f, frac))
    };
    Some((m, frac, s + int + 1 + frac))
}

/// The lanes of a word from `from` to before `to` (at most 8), all bits set.
fn lanes(from: usize, to: usize) -> u64 {
    let upto = |k: usize| {
        if k >= 8 {
            u64::MAX
        } else {
            (1u64 << (8 * k)) - 1
        }
    };
    upto(to) & !upto(from)
}

/// The shape of a plain decimal cell of at most 8 bytes after its sign
/// (`87.14250`, `-0.5`, `720`): its sign, where its digits and point are.
/// Learned from one cell ([`Shape::of`]), it reads the next cell of the
/// same shape in one word: a mask test that its digits are digits and its
/// point the point, then the digits moved together and converted at once
/// ([`Shape::read`]). The rows of a file mostly repeat their value's
/// shape, so the lengths need not be found again in every row.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape {
    neg: bool,
    /// 0x80 in each lane that must hold a digit.
    digits: u64,
    /// The point's byte in its lane, and that lane's bits (0 for none).
    point: u64,
    point_lane: u64,
    /// The digits before the point and their shift to the top of the
    /// word, then those after it and theirs (together, the digits fill
    /// the top of the word in order).
    int: (u64, u32),
    frac: (u64, u32),
    /// Fraction digits, and bytes after the sign.
    frac_digits: usize,
    len: usize,
}

impl Shape {
    /// The shape of the cell `b[i..end]` as [`plain_cell`] read it (no
    /// white space, at most 15 digits); `None` when it takes over 8 bytes
    /// after the sign.
    pub(crate) fn of(b: &[u8], i: usize, end: usize, decimal_comma: bool) -> Option<Shape> {
        let neg = b.get(i) == Some(&b'-');
        let s = i + usize::from(neg);
        let len = end.checked_sub(s)?;
        if !(1..=8).contains(&len) {
            return None;
        }
        let cell = &b[s..end];
        let point = cell
            .iter()
            .position(|&c| c == b'.' || (decimal_comma && c == b','));
        let high = |from: usize, to: usize| lanes(from, to) & (0x80 * LANES);
        let shift = |k: usize| (8 * (8 - k)) as u32;
        Some(match point {
            // Digits, a point, digits: moved up over the point, to the top.
            Some(p) if len >= 2 => Shape {
                neg,
                digits: high(0, p) | high(p + 1, len),
                point: u64::from(cell[p]) << (8 * p),
                point_lane: lanes(p, p + 1),
                int: (lanes(0, p), shift(len) + 8),
                frac: (lanes(p + 1, len), shift(len)),
                frac_digits: len - p - 1,
                len,
            },
            Some(_) => return None,
            None => Shape {
                neg,
                digits: high(0, len),
                point: 0,
                point_lane: 0,
                int: (lanes(0, len), shift(len)),
                frac: (0, 0),
                frac_digits: 0,
                len,
            },
        })
    }

    /// The cell at `b[i..]` when it has this shape as far as its bytes go:
    /// its value and the index after its last byte, which the caller must
    /// see is no digit and no point (else the cell is longer); `None`
    /// when the shape differs or fewer than 9 bytes are left.
    #[inline(always)]
    pub(crate) fn read(&self, b: &[u8], i: usize) -> Option<(f64, usize)> {
        if b.len() < i + 9 {
            return None;
        }
        let s = i + usize::from(self.neg);
        if (b[i] == b'-') != self.neg {
            return None;
        }
        let w = word(b, s);
        if lanes_differ(w, self.point, self.point_lane, self.digits) != 0 {
            return None;
        }
        Some((self.value_of(w), s + self.len))
    }

    /// The value of a cell of this shape whose bytes after the sign are
    /// the first of `w` (the lanes beyond the cell are not read), its
    /// digits and point checked already (by [`Shape::read`], or by a row
    /// pattern built from [`Shape::cell_bytes`]).
    #[inline(always)]
    pub(crate) fn value_of(&self, w: u64) -> f64 {
        let x = less_zeros(w);
        let m = eight_digits(((x & self.int.0) << self.int.1) | ((x & self.frac.0) << self.frac.1));
        decimal_value(m, self.frac_digits, self.neg)
    }

    /// Whether the cell starts with a minus sign.
    pub(crate) fn neg(&self) -> bool {
        self.neg
    }

    /// The cell's bytes after its sign.
    pub(crate) fn cell_len(&self) -> usize {
        self.len
    }

    /// What each byte of the cell after its sign must be: `None` for a
    /// digit, else the byte itself (the point).
    pub(crate) fn cell_bytes(&self) -> impl Iterator<Item = Option<u8>> + '_ {
        (0..self.len).map(|k| {
            let shift = 8 * k;
            ((self.point_lane >> shift) & 0xff != 0).then_some((self.point >> shift) as u8)
        })
    }
}

/// The lanes of the word `w` that are not as a pattern wants them: nonzero
/// when a lane set in `exact` differs from `expect`'s, or a lane with 0x80
/// set in `digits` holds no ASCII digit (judged as in `digits_in`;
/// `expect` is not read there). A lane that is no digit is always flagged.
/// Adding 0x76 carries out of a lane only where it holds a byte of 0x80 or
/// more, and only into the lane above it (a later byte); a carry never
/// clears a flag: a miss at worst, never a wrong read.
#[inline(always)]
pub(crate) fn lanes_differ(w: u64, expect: u64, exact: u64, digits: u64) -> u64 {
    let x = less_zeros(w);
    ((w ^ expect) & exact) | ((x.wrapping_add(0x76 * LANES) | x) & digits)
}

/// Cells a reader of many may read otherwise than by the shape before
/// (each learning its shape) before it gives the shapes up: values whose
/// lengths vary from cell to cell.
pub(crate) const SHAPE_MISSES: usize = 16;

/// A reader's last cell shape and its misses (see [`shaped_cell`]).
#[derive(Clone, Copy, Default)]
pub(crate) struct Shapes {
    shape: Option<Shape>,
    misses: usize,
}

impl Shapes {
    /// The last shape learned, if any.
    pub(crate) fn shape(&self) -> Option<&Shape> {
        self.shape.as_ref()
    }

    /// The cell at `b[i..]` by the last shape learned, as [`Shape::read`]
    /// gives it (the caller sees that the byte after it ends it).
    #[inline(always)]
    pub(crate) fn read(&self, b: &[u8], i: usize) -> Option<(f64, usize)> {
        self.shape.as_ref().and_then(|sh| sh.read(b, i))
    }

    /// [`plain_cell`], learning the shape of what it read, up to
    /// [`SHAPE_MISSES`] times.
    #[inline(never)]
    pub(crate) fn learn(
        &mut self,
        b: &[u8],
        i: usize,
        decimal_comma: bool,
    ) -> Option<(f64, usize)> {
        let (v, e) = plain_cell(b, i, decimal_comma)?;
        self.shape = None;
        if self.misses < SHAPE_MISSES {
            self.misses += 1;
            self.shape = Shape::of(b, i, e, decimal_comma);
        }
        Some((v, e))
    }
}

/// [`plain_cell`] by the shape of the cell read before it: what
/// `plain_cell` gives (`shaped_cells_read_what_plain_cell_reads`), in
/// fewer steps when the shape holds, the byte after it being no digit and
/// no point. Other cells are read by `plain_cell` and their shapes
/// learned ([`Shapes::learn`]).
#[inline(always)]
pub(crate) fn shaped_cell(
    b: &[u8],
    i: usize,
    decimal_comma: bool,
    shapes: &mut Shapes,
) -> Option<(f64, usize)> {
    if let Some((v, e)) = shapes.read(b, i)
        && b.get(e)
            .is_some_and(|&c| !c.is_ascii_digit() && c != b'.' && !(decimal_comma && c == b','))
    {
        return Some((v, e));
    }
    shapes.learn(b, i, decimal_comma)
}

/// One plain decimal (`-12.5`, at most 15 digits, a decimal comma where
/// `decimal_comma`) at `b[i..]`: its value and the index after it, or
/// `None`. Every fast reader of a row's cells reads them here.
#[inline(always)]
pub(crate) fn plain_cell(b: &[u8], mut i: usize, decimal_comma: bool) -> Option<(f64, usize)> {
    let neg = match b.get(i) {
        Some(b'-') => {
            i += 1;
            true
        }
        _ => false,
    };
    if let Some((m, frac, end)) = swar_digits(b, i, decimal_comma) {
        return Some((decimal_value(m, frac, neg), end));
    }
    // Integer digits, then an optional point and fraction digits; the
    // counts come from positions, so the digit loops do nothing else.
    let mut m = 0u64;
    let s = i;
    i = digit_run(b, i, &mut m);
    let int_digits = i - s;
    let mut frac = 0;
    if let Some(&c) = b.get(i)
        && (c == b'.' || (decimal_comma && c == b','))
    {
        i += 1;
        let f = i;
        i = digit_run(b, i, &mut m);
        frac = i - f;
    }
    let digits = int_digits + frac;
    if digits == 0 || digits > 15 {
        return None;
    }
    Some((decimal_value(m, frac, neg), i))
}

/// Most cells a row may have for the one-pass path of [`plain_row`].
pub(crate) const PLAIN_CELLS: usize = 8;

/// One pass over a row of plain decimals (`-12.5`, at most 15 digits, `sep`
/// between cells, nothing else) at the start of `b`, up to and with its
/// `\n` (or `\r\n`; the end of `b` ends the row only when `b` ends the
/// file, `eof`): the number of cells (values in `out`) and of bytes used.
/// Any other row (white space, quotes, exponents, too many cells, a comment)
/// gives `None` and takes the general path, which also reports errors;
/// where both apply they give the same values as [`fast_decimal`] and
/// `str::parse`. Each cell is read by the shape of the cell above it
/// (`shapes`, one a column, kept from row to row by the caller).
#[inline(always)]
pub(crate) fn plain_row(
    b: &[u8],
    sep: u8,
    decimal_comma: bool,
    eof: bool,
    out: &mut [f64; PLAIN_CELLS],
    shapes: &mut [Shapes; PLAIN_CELLS],
) -> Option<(usize, usize)> {
    let (mut i, mut n) = (0usize, 0usize);
    loop {
        let (v, end) = shaped_cell(b, i, decimal_comma, &mut shapes[n & (PLAIN_CELLS - 1)])?;
        i = end;
        out[n & (PLAIN_CELLS - 1)] = v;
        n += 1;
        match b.get(i) {
            None if eof => return Some((n, i)),
            Some(b'\n') => return Some((n, i + 1)),
            Some(b'\r') if b.get(i + 1) == Some(&b'\n') => return Some((n, i + 2)),
            Some(&c) if c == sep && n < PLAIN_CELLS => i += 1,
            _ => return None,
        }
    }
}

/// Reads the decimal digits of `b` from `i` into `m` (`m = 10 m + d` for
/// each); returns the index after the last digit. `m` wraps beyond 19
/// digits, which the caller rejects by counting them. (Eight digits at a
/// time by SWAR was tried: fewer instructions, but slower on these short
/// numbers.)
#[inline(always)]
pub(crate) fn digit_run(b: &[u8], mut i: usize, m: &mut u64) -> usize {
    while i < b.len() {
        let d = b[i].wrapping_sub(b'0');
        if d >= 10 {
            break;
        }
        *m = m.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    i
}

/// Clinger's fast path: a plain decimal of at most 15 digits is an exact
/// integer over an exact power of ten, so one division rounds it correctly
/// (the same value `str::parse` gives). Anything else returns `None`.
#[inline]
pub(crate) fn fast_decimal(b: &[u8]) -> Option<f64> {
    let (neg, b) = match b.first() {
        Some(b'-') => (true, &b[1..]),
        Some(b'+') => (false, &b[1..]),
        _ => (false, b),
    };
    if b.is_empty() || b.len() > 16 {
        return None;
    }
    let (mut m, mut digits, mut frac, mut dot) = (0u64, 0usize, 0usize, false);
    for &c in b {
        match c {
            b'0'..=b'9' => {
                m = m * 10 + u64::from(c - b'0');
                digits += 1;
                frac += usize::from(dot);
            }
            b'.' if !dot => dot = true,
            _ => return None,
        }
    }
    if digits == 0 || digits > 15 {
        return None;
    }
    Some(decimal_value(m, frac, neg))
}

/// A cell's number: the fast path for plain decimals, else [`read_number`]
/// (quotes around the cell are dropped); an error names the cell.
pub(crate) fn number(
    cell: &[u8],
    decimal_comma: bool,
    line: usize,
    col: usize,
) -> Result<f64, IngestError> {
    if let Some(v) = fast_decimal(cell) {
        return Ok(v);
    }
    let text = String::from_utf8_lossy(cell);
    let inner = text.strip_prefix('"').and_then(|t| t.strip_suffix('"'));
    read_number(inner.unwrap_or(&text), decimal_comma).map_err(|e| {
        at(
            line,
            Some(col),
            format!("`{}` {e}", enginedyn_numerics::format::quote(&text)),
        )
    })
}

/// Why a token is not read as a number (the message follows the quoted
/// token: "`4,9` is not a number: …").
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum NumberError {
    /// Nothing, or something else than a number.
    #[error("is not a number")]
    NotANumber,
    /// `nan`, `inf`, or a value beyond the largest `f64`.
    #[error("is not a finite number")]
    NotFinite,
    /// Digit groups that are not thousands (`4,9`, `12,34`).
    #[error(
        "is not a number: a comma, space or ' between digits is read as a thousands separator only between exact groups of three digits (4,900); write a decimal point"
    )]
    Grouping,
}

/// Thousands separators a number may carry between exact groups of three
/// digits: `4,900`, `4 900`, `4'900` (and the no-break spaces).
const GROUPS: [char; 5] = [',', ' ', '\'', '\u{a0}', '\u{202f}'];

/// One number, read whole, by the one rule for cells, banners, comment
/// lines and flags (INTERFACE.md, "Hostile input"): an optional sign,
/// digits, an optional fraction after `.` (or `,` where `decimal_comma`,
/// where a point still reads as one),
/// an optional exponent (`4.9e3` is 4900). A comma, space or `'` between
/// digits is a thousands separator only between exact groups of three
/// (`4,900`, `1 234 567`), one kind in a number; anything else is refused,
/// never read as its prefix. The value must be finite.
///
/// ```
/// use enginedyn_ingest::read_number;
/// assert_eq!(read_number("4.9e3", false), Ok(4900.0));
/// assert_eq!(read_number("4,900", false), Ok(4900.0));
/// assert_eq!(read_number("4'900.5", false), Ok(4900.5));
/// assert_eq!(read_number("2,5", true), Ok(2.5));
/// assert!(read_number("4,9", false).is_err());
/// assert!(read_number("nan", false).is_err());
/// assert!(read_number("4900rpm", false).is_err());
/// ```
pub fn read_number(token: &str, decimal_comma: bool) -> Result<f64, NumberError> {
    let t = token.trim();
    let (sign, body) = match t.as_bytes().first() {
        Some(b'-' | b'+') => t.split_at(1),
        _ => ("", t),
    };
    // Mantissa and exponent.
    let (mant, exp) = match body.find(['e', 'E']) {
        Some(i) => (&body[..i], Some(&body[i + 1..])),
        None => (body, None),
    };
    // With a decimal comma a point still reads as one (`0.5` in a `;` file).
    let point = if decimal_comma && mant.contains(',') {
        ','
    } else {
        '.'
    };
    let (int, frac) = match mant.find(point) {
        Some(i) => (&mant[..i], Some(&mant[i + 1..])),
        None => (mant, None),
    };
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    // The integer part: plain digits, or exact groups of three.
    let mut plain = String::with_capacity(t.len());
    plain.push_str(sign);
    match GROUPS.iter().find(|&&g| g != point && int.contains(g)) {
        None => {
            if !(int.is_empty() || digits(int)) {
                return Err(if int.chars().any(|c| GROUPS.contains(&c)) {
                    NumberError::Grouping
                } else {
                    not_a_number(t)
                });
            }
            plain.push_str(int);
        }
        Some(&g) => {
            let mut parts = int.split(g);
            let head = parts.next().unwrap_or("");
            if !(digits(head) && head.len() <= 3) {
                return Err(NumberError::Grouping);
            }
            plain.push_str(head);
            for p in parts {
                if !(digits(p) && p.len() == 3) {
                    return Err(NumberError::Grouping);
                }
                plain.push_str(p);
            }
        }
    }
    if let Some(f) = frac {
        if !(f.is_empty() || digits(f)) {
            return Err(if f.chars().any(|c| GROUPS.contains(&c)) {
                NumberError::Grouping
            } else {
                not_a_number(t)
            });
        }
        plain.push('.');
        plain.push_str(f);
    }
    if int.is_empty() && frac.is_none_or(str::is_empty) {
        return Err(not_a_number(t));
    }
    if let Some(e) = exp {
        let unsigned = e.strip_prefix(['-', '+']).unwrap_or(e);
        if !digits(unsigned) {
            return Err(NumberError::NotANumber);
        }
        plain.push('e');
        plain.push_str(e);
    }
    match plain.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(NumberError::NotFinite),
        Err(_) => Err(NumberError::NotANumber),
    }
}

/// `nan` and `inf` are words for numbers that are not finite.
fn not_a_number(t: &str) -> NumberError {
    let l = t.trim_start_matches(['-', '+']).to_ascii_lowercase();
    if matches!(l.as_str(), "nan" | "inf" | "infinity") {
        NumberError::NotFinite
    } else {
        NumberError::NotANumber
    }
}

/// Why a speed is not used.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum SpeedError {
    /// Not a number.
    #[error("{0}")]
    Number(NumberError),
    /// A number outside the speed bound.
    #[error("is outside the engine speed bound (above 0, from 0.001 to 100000 rpm)")]
    Bound(f64),
}

/// A speed in rpm, read by [`read_number`] and held to the speed bound
/// (`kinematics::MIN_RPM` … `MAX_RPM`): the one reader of `--rpm`, the
/// `# rpm` line and a banner's speed.
///
/// ```
/// use enginedyn_ingest::read_rpm;
/// assert_eq!(read_rpm("4.9e3"), Ok(4900.0));
/// assert!(read_rpm("1e308").is_err());
/// assert!(read_rpm("-4900").is_err());
/// assert!(read_rpm("0").is_err());
/// ```
pub fn read_rpm(token: &str) -> Result<f64, SpeedError> {
    check_rpm(read_number(token, false).map_err(SpeedError::Number)?)
}

/// A speed already a number (a keyword argument) held to the speed bound
/// (`MIN_RPM` to `MAX_RPM`), as [`read_rpm`] holds one read from text.
pub fn check_rpm(v: f64) -> Result<f64, SpeedError> {
    use enginedyn_kinematics::{MAX_RPM, MIN_RPM};
    if (MIN_RPM..=MAX_RPM).contains(&v) {
        Ok(v)
    } else {
        Err(SpeedError::Bound(v))
    }
}

#[cfg(test)]
mod tests {
    use super::{PLAIN_CELLS, fast_decimal, plain_row};
    use crate::text::Delim;
    use proptest::prelude::*;

    proptest! {
        /// The one-pass row parser gives, cell by cell, exactly what the
        /// general path (split, then `str::parse`) gives, or declines.
        #[test]
        fn plain_row_equals_split_and_parse(
            cells in prop::collection::vec((-1e7f64..1e7, 0usize..8), 1..6),
            sep in prop::sample::select(vec![b',', b';', b'\t']),
        ) {
            let dc = sep != b',';
            let row = cells
                .iter()
                .map(|(x, d)| {
                    let s = format!("{x:.d$}");
                    if dc && d % 2 == 1 { s.replace('.', ",") } else { s }
                })
                .collect::<Vec<_>>()
                .join(std::str::from_utf8(&[sep]).unwrap());
            let mut out = [0.0; PLAIN_CELLS];
            let line = format!("{row}\n");
            if let Some((n, used)) = plain_row(line.as_bytes(), sep, dc, false, &mut out, &mut Default::default()) {
                prop_assert_eq!(used, line.len());
                let delim = match sep { b',' => Delim::Comma, b';' => Delim::Semicolon, _ => Delim::Tab };
                let mut spans = Vec::new();
                delim.split(row.as_bytes(), &mut spans);
                prop_assert_eq!(n, spans.len());
                for (k, (s, e)) in spans.iter().enumerate() {
                    let cell = row[*s..*e].replace(',', ".");
                    prop_assert_eq!(out[k].to_bits(), cell.parse::<f64>().unwrap().to_bits());
                }
            }
        }
    }

    /// The byte-at-a-time reading of a plain decimal's digits at `b[s..]`
    /// (what `plain_cell` did before words): the digits as one integer,
    /// those after the point, the index after the cell; `None` for no
    /// digits or over 15.
    fn digits_by_bytes(b: &[u8], s: usize, dc: bool) -> Option<(u64, usize, usize)> {
        let mut m = 0;
        let mut i = super::digit_run(b, s, &mut m);
        let int = i - s;
        let mut frac = 0;
        if let Some(&c) = b.get(i)
            && (c == b'.' || (dc && c == b','))
        {
            let f = i + 1;
            i = super::digit_run(b, f, &mut m);
            frac = i - f;
        }
        (int + frac > 0 && int + frac <= 15).then_some((m, frac, i))
    }

    /// Bytes that make hostile cells: digits, points, commas, signs, an
    /// exponent, white space, line ends, the bytes either side of the
    /// digits and of the nibble test (`/`, `:`, `*`, `?`, `p`, `@`), a
    /// NUL and non-ASCII (UTF-8 of `é`, a lone 0xff).
    const HOSTILE: &[u8] =
        b"0123456789012345678901234567890123456789..,,-+eE \t\n\r/:*?p@\0\xc3\xa9\xff";

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// Where the word reader reads a cell it reads what the byte reader
        /// reads, at every start of a random hostile string (any byte).
        #[test]
        fn swar_digits_equal_digit_runs(
            b in prop::collection::vec(
                prop_oneof![3 => prop::sample::select(HOSTILE), 1 => any::<u8>()],
                0..48,
            ),
            dc in any::<bool>(),
        ) {
            for s in 0..=b.len() {
                if let Some(got) = super::swar_digits(&b, s, dc) {
                    prop_assert_eq!(Some(got), digits_by_bytes(&b, s, dc), "{:?} from {}", b, s);
                }
            }
        }

        /// A cell of plain decimals (every length of integer and fraction
        /// digits up to 25, leading zeros, a sign) in a buffer of any length reads
        /// as `str::parse` reads it, or is declined when over 15 digits.
        #[test]
        fn plain_cell_equals_std(
            int in prop::collection::vec(b'0'..=b'9', 0..25),
            frac in prop::option::of(prop::collection::vec(b'0'..=b'9', 0..25)),
            neg in any::<bool>(),
            tail in prop::sample::select(vec![&b"\n"[..], b"\r\n", b",1\n", b"", b" ", b"e5", b"\xc3\xa9"]),
            pad in 0usize..24,
        ) {
            let mut cell = Vec::new();
            if neg {
                cell.push(b'-');
            }
            cell.extend_from_slice(&int);
            if let Some(f) = &frac {
                cell.push(b'.');
                cell.extend_from_slice(f);
            }
            let digits = int.len() + frac.as_ref().map_or(0, Vec::len);
            let mut b = cell.clone();
            b.extend_from_slice(tail);
            b.extend(std::iter::repeat_n(b'x', pad));
            let got = super::plain_cell(&b, 0, false);
            if digits == 0 || digits > 15 {
                prop_assert_eq!(got, None);
            } else {
                let want: f64 = std::str::from_utf8(&cell).unwrap().parse().unwrap();
                let (v, end) = got.unwrap();
                prop_assert_eq!(v.to_bits(), want.to_bits());
                prop_assert_eq!(end, cell.len());
            }
        }

        /// A cell read by the shape of another reads as `plain_cell`
        /// reads it, or is declined: cells of every shape up to 8 bytes
        /// and of others, hostile bytes after them.
        #[test]
        fn shape_reads_what_plain_cell_reads(
            learned in "-?[0-9]{0,8}([.,][0-9]{0,8})?",
            cell in prop::collection::vec(
                prop_oneof![4 => prop::sample::select(&b"0123456789"[..]), 1 => prop::sample::select(HOSTILE)],
                0..12,
            ),
            neg in any::<bool>(),
            dc in any::<bool>(),
            tail in prop::collection::vec(prop::sample::select(HOSTILE), 0..12),
        ) {
            let learned = learned.as_bytes();
            let Some((_, end)) = super::plain_cell(learned, 0, dc) else {
                return Ok(());
            };
            let Some(shape) = super::Shape::of(learned, 0, end, dc) else {
                prop_assert!(end - usize::from(learned[0] == b'-') > 8);
                return Ok(());
            };
            // The learned cell itself reads back.
            let mut own = learned[..end].to_vec();
            own.extend_from_slice(b"\n        ");
            prop_assert_eq!(shape.read(&own, 0), super::plain_cell(&own, 0, dc));
            let mut b = if neg { vec![b'-'] } else { vec![] };
            b.extend_from_slice(&cell);
            b.extend_from_slice(&tail);
            b.extend_from_slice(b"\n        ");
            if let Some((v, e)) = shape.read(&b, 0) {
                let after = b[e];
                if !after.is_ascii_digit() && after != b'.' && !(dc && after == b',') {
                    prop_assert_eq!(Some((v, e)), super::plain_cell(&b, 0, dc), "{:?}", b);
                }
            }
        }

        /// Cells one after another through one reader's shapes read as
        /// `plain_cell` reads each, whatever the shape before (runs of one
        /// shape, then others, hostile ones, more than SHAPE_MISSES changes).
        #[test]
        fn shaped_cells_read_what_plain_cell_reads(
            cells in prop::collection::vec(
                prop_oneof![
                    3 => Just("87.14250".to_string()),
                    1 => "-?[0-9]{0,9}([.,][0-9]{0,9})?",
                    1 => "[-0-9.,e \n]{0,10}",
                ],
                1..60,
            ),
            dc in any::<bool>(),
        ) {
            let mut shapes = super::Shapes::default();
            for cell in &cells {
                let mut b = cell.as_bytes().to_vec();
                b.extend_from_slice(b";\n        x");
                prop_assert_eq!(
                    super::shaped_cell(&b, 0, dc, &mut shapes),
                    super::plain_cell(&b, 0, dc),
                    "{:?}", cell
                );
            }
        }

        /// Eight digits by words are the number they spell.
        #[test]
        fn eight_digits_spell_their_number(n in 0u64..100_000_000, k in 0usize..8) {
            let text = format!("{n:08}");
            let w = super::less_zeros(u64::from_le_bytes(text.as_bytes().try_into().unwrap()));
            prop_assert_eq!(super::eight_digits(w), n);
            // The first k digits alone, moved up.
            let want = if k == 0 { 0 } else { text[..k].parse::<u64>().unwrap() };
            prop_assert_eq!(super::eight_digits(super::top(w, k)), want);
        }
    }

    /// Every split of up to 16 digits around a point, and the cells a
    /// word reader might get wrong, at every offset in a 16-byte window and
    /// at the end of the buffer.
    #[test]
    fn plain_cell_hostile_cells() {
        let mut cells: Vec<String> = Vec::new();
        for n in 1..=25 {
            let digits: String = (0..n).map(|k| char::from(b'1' + (k % 9) as u8)).collect();
            cells.push(digits.clone());
            cells.push(format!("-{digits}"));
            cells.push(format!("000{digits}"));
            for p in 0..=n {
                cells.push(format!("{}.{}", &digits[..p], &digits[p..]));
            }
        }
        for c in [
            "-0",
            "+5",
            ".5",
            "5.",
            "-.5",
            "-5.",
            ".",
            "-",
            "-.",
            "1e3",
            "1E3",
            "nan",
            "inf",
            "-inf",
            " 5",
            "5 ",
            "5\u{e9}",
            "\u{e9}5",
            "0.0",
            "00.00",
            "1..2",
            "1.2.3",
            "12,5",
            "9999999.9999999",
            "99999999.999999",
        ] {
            cells.push(c.into());
        }
        for cell in &cells {
            for pad in 0..20 {
                for end in ["\n", "\r\n", ",", ""] {
                    let text = format!("{}{cell}{end}{}", "7,".repeat(pad), "0".repeat(pad));
                    let b = text.as_bytes();
                    let s = 2 * pad;
                    let got = super::plain_cell(b, s, false);
                    if let Some((v, e)) = got {
                        let want: f64 = text[s..e].parse().unwrap();
                        assert_eq!(v.to_bits(), want.to_bits(), "{text:?}");
                    }
                    if plain(cell) && (!end.is_empty() || pad == 0) {
                        let (v, e) = got.unwrap_or_else(|| panic!("{text:?} declined"));
                        assert_eq!(&text[s..e], cell, "{text:?}");
                        assert_eq!(fast_decimal(cell.as_bytes()), Some(v), "{cell}");
                    }
                }
            }
        }
    }

    /// A plain decimal: an optional `-`, digits (1 to 15) and at most one
    /// point.
    fn plain(cell: &str) -> bool {
        let body = cell.strip_prefix('-').unwrap_or(cell);
        let digits = body.bytes().filter(u8::is_ascii_digit).count();
        body.bytes().all(|c| c.is_ascii_digit() || c == b'.')
            && body.matches('.').count() <= 1
            && (1..=15).contains(&digits)
    }

    #[test]
    fn plain_row_declines_what_it_cannot_do() {
        let mut out = [0.0; PLAIN_CELLS];
        for row in [
            "1, 2",
            "1,2,",
            "\"1\",2",
            "1e5,2",
            "+1,2",
            "1,2,3,4,5,6,7,8,9",
            "1.2.3,4",
            "1234567890123456,1",
        ] {
            assert!(
                plain_row(
                    row.as_bytes(),
                    b',',
                    false,
                    true,
                    &mut out,
                    &mut Default::default()
                )
                .is_none(),
                "{row}"
            );
        }
        // The end of the window ends a row only at the end of the file.
        assert_eq!(
            plain_row(
                b"1,2",
                b',',
                false,
                false,
                &mut out,
                &mut Default::default()
            ),
            None
        );
        assert_eq!(
            plain_row(b"1,2", b',', false, true, &mut out, &mut Default::default()),
            Some((2, 3))
        );
        assert_eq!(
            plain_row(
                b"1,2 \n",
                b',',
                false,
                true,
                &mut out,
                &mut Default::default()
            ),
            None
        );
        assert_eq!(
            plain_row(
                b"3;-0,25;7\r\n4",
                b';',
                true,
                false,
                &mut out,
                &mut Default::default()
            ),
            Some((3, 11))
        );
        assert_eq!(out[..3], [3.0, -0.25, 7.0]);
    }

    proptest! {
        /// The fast path gives exactly what `str::parse` gives, or declines.
        #[test]
        fn fast_decimal_equals_std(x in -1e9f64..1e9, digits in 0usize..9) {
            let s = format!("{x:.digits$}");
            if let Some(v) = fast_decimal(s.as_bytes()) {
                prop_assert_eq!(v.to_bits(), s.parse::<f64>().unwrap().to_bits());
            }
        }
    }

    #[test]
    fn numbers_are_read_whole() {
        use super::{NumberError, read_number};
        let ok = |s: &str, dc: bool, v: f64| {
            assert_eq!(read_number(s, dc).map(f64::to_bits), Ok(v.to_bits()), "{s}");
        };
        ok("4.9e3", false, 4900.0);
        ok("4,900", false, 4900.0);
        ok("4 900", false, 4900.0);
        ok("4'900", false, 4900.0);
        ok("1,234,567.25", false, 1_234_567.25);
        ok("-4900", false, -4900.0);
        ok("+.5", false, 0.5);
        ok("1e-300", false, 1e-300);
        ok("2,5", true, 2.5);
        ok("1 234,5", true, 1234.5);
        for (s, dc, e) in [
            ("4,9", false, NumberError::Grouping),
            ("4,9000", false, NumberError::Grouping),
            ("1234,567", false, NumberError::Grouping),
            ("4,900 000", false, NumberError::Grouping),
            ("1.234,5", false, NumberError::Grouping),
            ("nan", false, NumberError::NotFinite),
            ("-inf", false, NumberError::NotFinite),
            ("1e400", false, NumberError::NotFinite),
            ("4900rpm", false, NumberError::NotANumber),
            ("4.9.3", false, NumberError::NotANumber),
            ("1e", false, NumberError::NotANumber),
            ("", false, NumberError::NotANumber),
            ("-", false, NumberError::NotANumber),
            ("0x10", false, NumberError::NotANumber),
        ] {
            assert_eq!(read_number(s, dc), Err(e), "{s}");
        }
    }

    proptest! {
        /// Every number `str::parse` reads plainly, the one rule reads the same.
        #[test]
        fn read_number_equals_std(x in -1e300f64..1e300, digits in 0usize..17, exp in any::<bool>()) {
            let s = if exp { format!("{x:e}") } else { format!("{x:.digits$}") };
            prop_assert_eq!(
                super::read_number(&s, false).map(f64::to_bits),
                Ok(s.parse::<f64>().unwrap().to_bits())
            );
        }
    }

    #[test]
    fn fast_decimal_declines_what_it_cannot_do() {
        for s in [
            "",
            "-",
            ".",
            "1e5",
            "1.2.3",
            "nan",
            "1234567890123456",
            "0x10",
            "1,5",
        ] {
            assert!(fast_decimal(s.as_bytes()).is_none(), "{s}");
        }
        assert_eq!(
            fast_decimal(b"-0").map(f64::to_bits),
            Some((-0.0f64).to_bits())
        );
        assert_eq!(fast_decimal(b"87.19176"), Some(87.19176));
    }
}
