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

pub(crate) fn number(
    cell: &[u8],
    decimal_comma: bool,
    line: usize,
    col: usize,
) -> Result<f64, IngestError> {
    if let Some(v) = fast_decimal(cell) {
        return Ok(v);
    }
    let Ok(cell) = std::str::from_utf8(cell) else {
        return Err(at(
            line,
            Some(col),
            format!(
                "`{}` is not a number",
                enginedyn_numerics::format::quote(&String::from_utf8_lossy(cell))
            ),
        ));
    };
    let parsed = if decimal_comma && cell.contains(',') {
        cell.replacen(',', ".", 1).parse::<f64>()
    } else if cell.as_bytes().first() == Some(&b'"') {
        cell.trim_matches('"').parse::<f64>()
    } else {
        cell.parse::<f64>()
    };
    match parsed {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(at(line, Some(col), format!("{v} is not a finite number"))),
        Err(_) => Err(at(
            line,
            Some(col),
            format!(
                "`{}` is not a number",
                enginedyn_numerics::format::quote(cell)
            ),
        )),
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
