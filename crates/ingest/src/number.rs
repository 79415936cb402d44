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
/// `str::parse`.
#[inline(always)]
pub(crate) fn plain_row(
    b: &[u8],
    sep: u8,
    decimal_comma: bool,
    eof: bool,
    out: &mut [f64; PLAIN_CELLS],
) -> Option<(usize, usize)> {
    let (mut i, mut n) = (0usize, 0usize);
    loop {
        let (v, end) = plain_cell(b, i, decimal_comma)?;
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
            if let Some((n, used)) = plain_row(line.as_bytes(), sep, dc, false, &mut out) {
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
                plain_row(row.as_bytes(), b',', false, true, &mut out).is_none(),
                "{row}"
            );
        }
        // The end of the window ends a row only at the end of the file.
        assert_eq!(plain_row(b"1,2", b',', false, false, &mut out), None);
        assert_eq!(plain_row(b"1,2", b',', false, true, &mut out), Some((2, 3)));
        assert_eq!(plain_row(b"1,2 \n", b',', false, true, &mut out), None);
        assert_eq!(
            plain_row(b"3;-0,25;7\r\n4", b';', true, false, &mut out),
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
