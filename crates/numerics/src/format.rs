//! Numbers written as people write them: in notes and messages (`human`),
//! in tables (`fixed`, never `-0.00`) and in CSV files (`csv`, shortest
//! round-trip, exponent notation only for tiny and huge magnitudes). The
//! one home of number formatting; every crate that writes text calls it.
//!
//! Also the one home of how a name or a text cell is made safe where it
//! goes: a CSV text cell no spreadsheet takes for a formula ([`csv_text`]),
//! a name in a text table on one line ([`table_text`]), a name as a folder
//! name every system can hold ([`folder_name`]).

use std::borrow::Cow;

/// `x` with `digits` decimals: no `-0.00` (a value that rounds to zero has
/// no sign); 10 digits and more ask for scientific notation with two
/// decimals (`3.31e-15`).
pub fn fixed(x: f64, digits: usize) -> String {
    let s = if digits >= 10 {
        format!("{x:.2e}")
    } else {
        format!("{x:.digits$}")
    };
    match s.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| matches!(b, b'0' | b'.')) => rest.to_string(),
        _ => s,
    }
}

/// A number in a note or message: six significant digits at most, trailing
/// zeros dropped, plain between 1e-4 and 1e9 and `1.5e-7` outside
/// (`-7.66`, `4900`, `0.086`; never `-7.662e0`).
pub fn human(x: f64) -> String {
    sig(x, 6)
}

/// A count in a message, its thousands grouped by commas (`4,194,304`,
/// `65,536`, `255`), as the limits are written in the docs.
pub fn count(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A number with at most `n` significant digits (1 to 15), written as
/// [`human`] writes it (`sig(0.0019677, 2)` is `0.002`, `sig(1.61e-2, 2)`
/// is `0.016`).
pub fn sig(x: f64, n: usize) -> String {
    let n = n.clamp(1, 15);
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if !(1e-4..1e9).contains(&a) {
        return trim_zeros(&format!("{x:.p$e}", p = n - 1));
    }
    let digits = (n as i32 - 1 - a.log10().floor() as i32).clamp(0, 15) as usize;
    trimmed(x, digits)
}

/// `x` with at most `digits` decimals: [`fixed`] with trailing zeros and a
/// bare point dropped (`0.086`, `45.2`, `120`; never `-0`).
pub fn trimmed(x: f64, digits: usize) -> String {
    trim_zeros(&fixed(x, digits))
}

/// A number's text with trailing zeros after the point and a bare point
/// dropped, in the mantissa of an exponent form too (`2.50e6` → `2.5e6`,
/// `1.000` → `1`).
pub fn trim_zeros(s: &str) -> String {
    let (m, e) = match s.split_once(['e', 'E']) {
        Some((m, e)) => (m, Some(e)),
        None => (s, None),
    };
    let m = if m.contains('.') {
        m.trim_end_matches('0').trim_end_matches('.')
    } else {
        m
    };
    match e {
        Some(e) => format!("{m}e{e}"),
        None => m.to_string(),
    }
}

/// A number in a CSV cell (INTERFACE.md): the shortest form that reads back
/// to the same `f64`, in exponent notation below 1e-5 and from 1e16 in
/// magnitude (`1e-7`, `2.5e20`), plain between (`0.00012`, `4900`); never
/// 30 digits of zeros. Non-finite values are empty cells.
pub fn csv(x: f64) -> String {
    let mut s = String::new();
    csv_into(&mut s, x);
    s
}

/// [`csv`], appended to `out`.
pub fn csv_into(out: &mut String, x: f64) {
    use std::fmt::Write as _;
    if !x.is_finite() {
        return;
    }
    let a = x.abs();
    let _ = if a != 0.0 && !(1e-5..1e16).contains(&a) {
        write!(out, "{x:e}")
    } else {
        write!(out, "{x}")
    };
}

/// Text from the user's input as a message quotes it: at most 80
/// characters (the rest elided, with the length in all), control
/// characters escaped, so that a 200 MB line or a terminal escape never
/// reaches the screen whole.
pub fn quote(s: &str) -> String {
    const MAX: usize = 80;
    let mut out = String::new();
    for (n, c) in s.chars().enumerate() {
        if n == MAX {
            out.push_str(&format!("… ({} characters in all)", s.chars().count()));
            break;
        }
        push_escaped(&mut out, c);
    }
    out
}

/// `c`, escaped when it is a control character (`\n`, `\u{1b}`): the one
/// rule of [`quote`] and [`table_text`].
fn push_escaped(out: &mut String, c: char) {
    if c.is_control() {
        out.extend(c.escape_default());
    } else {
        out.push(c);
    }
}

/// A text cell of a CSV file (INTERFACE.md, "Other outputs"): text that
/// starts with `=`, `+`, `-`, `@`, a tab or a carriage return gets a
/// leading `'`, so that no spreadsheet evaluates it as a formula (Excel and
/// LibreOffice do, quoted or not). For text only: numbers are written by
/// [`csv`] and never pass here (`-3.2` stays `-3.2`). Quoting the cell
/// (commas, quotes, line breaks) is the CSV writer's part.
pub fn csv_text(s: &str) -> Cow<'_, str> {
    if s.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        Cow::Owned(format!("'{s}"))
    } else {
        Cow::Borrowed(s)
    }
}

/// A name as a text table shows it: on one line, control characters
/// escaped (`new\nline`, `\u{1b}`), nothing else changed and nothing cut.
pub fn table_text(s: &str) -> Cow<'_, str> {
    if s.chars().any(char::is_control) {
        let mut out = String::with_capacity(s.len() + 8);
        for c in s.chars() {
            push_escaped(&mut out, c);
        }
        Cow::Owned(out)
    } else {
        Cow::Borrowed(s)
    }
}

/// The longest folder name [`folder_name`] gives, in bytes (file systems
/// hold 255; a little is left for what is put before it).
pub const MAX_FOLDER_NAME: usize = 200;

/// `name` as a folder name that every system holds and line-oriented
/// scripts read: control characters and `<>:"/\|?*` (which Windows
/// refuses) become `_`, and a name longer than [`MAX_FOLDER_NAME`] bytes is
/// cut at a character's edge.
pub fn folder_name(name: &str) -> String {
    let mut out = String::with_capacity(name.len().min(MAX_FOLDER_NAME));
    for c in name.chars() {
        let c = if c.is_control()
            || matches!(c, '<' | '>' | ':' | '"' | '/' | '\\' | '|' | '?' | '*')
        {
            '_'
        } else {
            c
        };
        if out.len() + c.len_utf8() > MAX_FOLDER_NAME {
            break;
        }
        out.push(c);
    }
    out
}

/// Whether `typed` is close enough to `known` for a "did you mean": similar
/// as a whole (at most about half the letters changed, Damerau–Levenshtein)
/// or the beginning of it (`cyl` for `cylinders`, `bore` for `bore_mm`);
/// never a name that merely shares a first letter. The one rule every
/// suggestion follows (engine keys, diagram columns).
pub fn close_name(typed: &str, known: &str) -> bool {
    let typed = typed.to_ascii_lowercase();
    name_similarity(&typed, known) >= 0.5 || typed.len() >= 3 && known.starts_with(&typed)
}

/// How alike two names are, 0 to 1 (normalised Damerau–Levenshtein): the
/// ranking of "did you mean" candidates.
pub fn name_similarity(a: &str, b: &str) -> f64 {
    strsim::normalized_damerau_levenshtein(a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_has_no_negative_zero() {
        assert_eq!(fixed(-0.001, 2), "0.00");
        assert_eq!(fixed(-0.0, 0), "0");
        assert_eq!(fixed(-0.006, 2), "-0.01");
        assert_eq!(fixed(3.31e-15, 12), "3.31e-15");
    }

    #[test]
    fn human_numbers() {
        assert_eq!(human(-7.662), "-7.662");
        assert_eq!(human(-7.66), "-7.66");
        assert_eq!(human(4900.0), "4900");
        assert_eq!(human(0.086), "0.086");
        assert_eq!(human(1e300), "1e300");
        assert_eq!(human(1.5e-7), "1.5e-7");
        assert_eq!(human(123456.789), "123457");
        assert_eq!(human(0.0), "0");
        assert_eq!(sig(0.0019677, 2), "0.002");
        assert_eq!(sig(1.61e-2, 2), "0.016");
        assert_eq!(sig(3.3e-7, 2), "3.3e-7");
        assert_eq!(sig(375.347, 3), "375");
        assert_eq!(trim_zeros("2.50e6"), "2.5e6");
        assert_eq!(trim_zeros("1.000"), "1");
        assert_eq!(trim_zeros("120"), "120");
        assert_eq!(trimmed(-0.0001, 2), "0");
    }

    /// A text cell a spreadsheet would evaluate gets a leading `'`; other
    /// text is unchanged.
    #[test]
    fn csv_text_cells_are_never_formulas() {
        for (raw, cell) in [
            (
                "=HYPERLINK(\"http://x\",\"y\").csv",
                "'=HYPERLINK(\"http://x\",\"y\").csv",
            ),
            ("+cmd.csv", "'+cmd.csv"),
            ("-2+3", "'-2+3"),
            ("@SUM(1).csv", "'@SUM(1).csv"),
            ("\tx", "'\tx"),
            ("\rx", "'\rx"),
        ] {
            assert_eq!(csv_text(raw), cell);
        }
        for plain in ["a.csv", "", "runs/=x.csv", "x=1", "'quoted", " =1"] {
            assert_eq!(csv_text(plain), plain);
        }
    }

    #[test]
    fn names_on_one_line_and_as_folders() {
        assert_eq!(table_text("new\nline.csv"), "new\\nline.csv");
        assert_eq!(table_text("a\u{1b}[31m\tb"), "a\\u{1b}[31m\\tb");
        assert_eq!(table_text("ünïcode ok.csv"), "ünïcode ok.csv");
        assert_eq!(folder_name("new\nline"), "new_line");
        assert_eq!(
            folder_name("<img src=x onerror=alert(1)>"),
            "_img src=x onerror=alert(1)_"
        );
        assert_eq!(folder_name("a<>:\"/\\|?*b\u{7f}"), "a_________b_");
        assert_eq!(folder_name("plain name"), "plain name");
        let long = "é".repeat(300);
        let cut = folder_name(&long);
        assert!(cut.len() <= MAX_FOLDER_NAME && cut.chars().all(|c| c == 'é'));
        assert_eq!(cut.chars().count(), MAX_FOLDER_NAME / 2);
    }

    #[test]
    fn close_names() {
        assert!(close_name("lamda", "lambda") && close_name("bore", "bore_mm"));
        assert!(close_name("Pressure_Bar", "pressure_bar") && close_name("cyl", "cylinders"));
        assert!(!close_name("r", "rod_length_mm") && !close_name("foo", "crank_deg"));
        assert!(!close_name("time_s", "crank_deg"));
    }

    #[test]
    fn quotes_are_short_and_escaped() {
        assert_eq!(quote("1,x"), "1,x");
        assert_eq!(quote("a\u{1b}[31mb\n"), "a\\u{1b}[31mb\\n");
        let long = "7".repeat(200_000);
        let q = quote(&long);
        assert!(
            q.starts_with(&"7".repeat(80)) && q.ends_with("… (200000 characters in all)"),
            "{q}"
        );
        assert!(q.chars().count() < 120);
    }

    /// Exponent form only outside [1e-5, 1e16), and every cell reads back
    /// to the same number.
    #[test]
    fn csv_cells_round_trip() {
        assert_eq!(csv(1e-7), "1e-7");
        assert_eq!(csv(-2.5e-12), "-2.5e-12");
        assert_eq!(csv(0.00012), "0.00012");
        assert_eq!(csv(1e20), "1e20");
        assert_eq!(csv(4900.0), "4900");
        assert_eq!(csv(0.0), "0");
        assert_eq!(csv(f64::NAN), "");
        for x in [
            1e-7,
            3.0e-300,
            1.2345678901234567e-6,
            9.99e15,
            1e16,
            -0.1,
            123.456,
        ] {
            assert_eq!(csv(x).parse::<f64>().unwrap().to_bits(), x.to_bits(), "{x}");
        }
    }

    #[test]
    fn counts_are_grouped_by_thousands() {
        for (n, want) in [
            (0, "0"),
            (255, "255"),
            (1_000, "1,000"),
            (65_536, "65,536"),
            (4_194_304, "4,194,304"),
            (u64::MAX, "18,446,744,073,709,551,615"),
        ] {
            assert_eq!(count(n), want);
        }
    }
}
