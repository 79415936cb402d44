//! Rows that repeat the row before them but for the angle, one step on.
//!
//! In a measured or exported diagram the cells before the value (cycle,
//! cylinder, angle) change from row to row only by the angle's step: after
//! `3,127.4,` comes `3,127.5,`. A [`Template`] holds the text the next row
//! must start with and the angle it stands for; a row that starts with
//! exactly those bytes has those cells (one 16-byte comparison instead of
//! reading them digit by digit), and only its value is read. Any other row
//! fails the comparison and is read in full by the caller, which may then
//! seed a new template. The angle is kept as the integer its digits spell,
//! so the value it gives is bit for bit what reading the cell gives.

use crate::number::{POW10, Shape, Shapes, decimal_value, lanes_differ, word};

/// Longest text a template holds: the cells before the value, with their
/// separators.
const PREFIX: usize = 16;
/// Bytes of window a row on the template path needs (prefix, value, line
/// end; longer rows fail and take the general path).
pub(crate) const ROW: usize = 64;

/// The expected start of the next row and the angle it stands for.
#[derive(Clone)]
pub(crate) struct Template {
    /// The cells before the value, with separators, as the next row must
    /// start: little-endian bytes in two words, zero beyond `len`. Words,
    /// because byte stores followed by a wider load of the same bytes stall
    /// on store forwarding.
    text: [u64; 2],
    /// Length of the text.
    len: usize,
    /// The first `len` bytes set.
    mask: [u64; 2],
    /// Where the angle cell's characters are in `text`.
    x: (usize, usize),
    /// The angle cell's digits as an integer.
    m: u64,
    /// The step, in units of the angle's last digit.
    step: u64,
    /// Fraction digits of the angle cell.
    frac: usize,
    /// The angle cell outgrew its width (`9.9` after `99.9`): no more rows.
    dead: bool,
    /// Rows read so far.
    pub(crate) rows: usize,
    /// The angle cell's last digit: its index in `text` and its value (a
    /// step that leaves it below 10 is one addition).
    last: (usize, u64),
    /// The digit before it (the point passed over): its index and value,
    /// 10 when there is none. A carry into it below 9 is two additions.
    before: (usize, u64),
    /// The shape of the last value read, which the next is read by first.
    shapes: Shapes,
    /// The whole row as the last one read by its shape, when it fits:
    /// checked in words at once ([`Template::next`]'s first try).
    row: Option<RowShape>,
    /// Row shapes built so far (at most [`ROW_BUILDS`]).
    builds: usize,
}

/// Longest row (text, value, line end) a [`RowShape`] checks, in words.
const ROW_WORDS: usize = 3;

/// Row shapes a template builds before it keeps to the cell-by-cell read:
/// values or line ends whose shapes keep changing.
const ROW_BUILDS: usize = 16;

/// What the bytes after the template's text must be, for a row like the
/// last one read: the value's sign and point exactly and digits where it
/// had digits, then the same line end. With the text it checks a whole
/// row in [`ROW_WORDS`] words or fewer, each with one mask test
/// ([`lanes_differ`]), where the cell-by-cell read tests the text, the
/// sign, the digits and the line end one after another, each behind its
/// own branch.
#[derive(Clone, Copy)]
struct RowShape {
    /// The bytes after the text that must be as they are (zero in the
    /// text's lanes, which `Template::text` fills).
    expect: [u64; ROW_WORDS],
    /// Lanes compared exactly: the text, the sign, the point, the line end.
    exact: [u64; ROW_WORDS],
    /// 0x80 in the lanes that must hold a digit.
    digits: [u64; ROW_WORDS],
    /// Whether the row reaches the third word.
    third: bool,
    /// Where the value's bytes after its sign start.
    at: usize,
    /// The row's length, line end included.
    len: usize,
    /// The value's shape.
    shape: Shape,
}

impl RowShape {
    /// The pattern of a row with `text_len` bytes of text, then a value of
    /// `shape`, then the line end `end`; `None` when it is longer than
    /// [`ROW_WORDS`] words.
    fn new(text_len: usize, shape: &Shape, end: &[u8]) -> Option<Self> {
        const N: usize = 8 * ROW_WORDS;
        let (mut expect, mut exact, mut digits) = ([0u8; N], [0u8; N], [0u8; N]);
        exact[..text_len.min(N)].fill(0xff);
        let sign = shape.neg().then_some(Some(b'-'));
        let len = text_len + usize::from(shape.neg()) + shape.cell_len() + end.len();
        if len > N {
            return None;
        }
        let cells = sign
            .into_iter()
            .chain(shape.cell_bytes())
            .chain(end.iter().map(|&c| Some(c)));
        for (i, c) in (text_len..).zip(cells) {
            match c {
                Some(c) => (expect[i], exact[i]) = (c, 0xff),
                None => digits[i] = 0x80,
            }
        }
        let words = |b: [u8; N]| std::array::from_fn(|k| word(&b, 8 * k));
        Some(Self {
            expect: words(expect),
            exact: words(exact),
            digits: words(digits),
            third: len > 16,
            at: text_len + usize::from(shape.neg()),
            len,
            shape: *shape,
        })
    }
}

impl Template {
    /// A template from `row` (a plain row just read in full), whose cell
    /// `x` is the angle, `step` (file units) after the angle of the row
    /// before, and whose cell `value` (all cells before it being cycle,
    /// cylinder or the angle) is the last. `None` when the row does not
    /// fit: a prefix over 16 bytes, a signed or over-long angle, a step that
    /// is not a whole number of the angle's last digit.
    #[inline(never)]
    pub(crate) fn seed(row: &[u8], sep: u8, x: usize, value: usize, step: f64) -> Option<Self> {
        let (mut cells, mut start, mut len, mut span) = (0, 0, 0, None);
        for (i, &c) in row.iter().take(PREFIX).enumerate() {
            if c == sep {
                if cells == x {
                    span = Some((start, i));
                }
                cells += 1;
                start = i + 1;
                if cells == value {
                    len = i + 1;
                    break;
                }
            }
        }
        let (s, e) = span?;
        if len == 0 {
            return None;
        }
        let (mut m, mut digits, mut frac) = (0u64, 0usize, None::<usize>);
        for &c in &row[s..e] {
            match c {
                b'0'..=b'9' => {
                    m = m * 10 + u64::from(c - b'0');
                    digits += 1;
                    if let Some(f) = frac.as_mut() {
                        *f += 1;
                    }
                    if digits > 15 {
                        return None;
                    }
                }
                b'.' | b',' if frac.is_none() => frac = Some(0),
                _ => return None,
            }
        }
        let frac = frac.unwrap_or(0);
        if digits == 0 {
            return None;
        }
        let units = step * POW10[frac];
        let whole = units.round();
        if !(1.0..1e9).contains(&whole) || (units - whole).abs() > 1e-6 {
            return None;
        }
        let mut text = [0; PREFIX];
        text[..len].copy_from_slice(&row[..len]);
        let mask = if len == PREFIX {
            u128::MAX
        } else {
            (1u128 << (8 * len)) - 1
        };
        let text = u128::from_le_bytes(text);
        let mut t = Self {
            text: [text as u64, (text >> 64) as u64],
            len,
            mask: [mask as u64, (mask >> 64) as u64],
            x: (s, e),
            m,
            step: whole as u64,
            frac,
            dead: false,
            rows: 0,
            last: (0, 10),
            before: (0, 10),
            shapes: Shapes::default(),
            row: None,
            builds: 0,
        };
        if let Some(j) = (s..e).rev().find(|&j| t.digit(j).is_some()) {
            t.last = (j, t.digit(j).unwrap_or(10));
            t.before = t.digit_before(j);
        }
        t.advance();
        (!t.dead).then_some(t)
    }

    /// The angle cell's value (file units) as reading it gives.
    fn angle(&self) -> f64 {
        decimal_value(self.m, self.frac, false)
    }

    /// The word of `text` that holds byte `j` and the byte's shift there.
    fn at(j: usize) -> (usize, usize) {
        (j / 8 % 2, 8 * (j % 8))
    }

    /// The digit byte `j` of `text` holds, if a digit.
    fn digit(&self, j: usize) -> Option<u64> {
        let (word, shift) = Self::at(j);
        let c = (self.text[word] >> shift) as u8;
        c.is_ascii_digit().then(|| u64::from(c - b'0'))
    }

    /// Moves the text and the angle one step on: most steps only add to
    /// the last digit; a carry takes [`Self::carry`].
    #[inline(always)]
    fn advance(&mut self) {
        let (j, d) = self.last;
        if d + self.step < 10 {
            let (word, shift) = Self::at(j);
            self.m += self.step;
            self.text[word] += self.step << shift;
            self.last.1 = d + self.step;
        } else {
            self.carry();
        }
    }

    /// The digit before byte `j` of the angle cell (a point passed over):
    /// its index and value, or value 10 when there is none.
    fn digit_before(&self, j: usize) -> (usize, u64) {
        (self.x.0..j)
            .rev()
            .find_map(|i| self.digit(i).map(|d| (i, d)))
            .unwrap_or((0, 10))
    }

    /// [`Self::advance`] when the last digit carries: into the digit
    /// before it when that is below 9 (`87.9` → `88.0`, nine carries in
    /// ten), else [`Self::carry_digits`].
    #[inline(never)]
    fn carry(&mut self) {
        let ((j, d), (b, e)) = (self.last, self.before);
        if self.step < 10 && e < 9 {
            self.m += self.step;
            let (word, shift) = Self::at(j);
            self.text[word] -= (10 - self.step) << shift;
            let (word, shift) = Self::at(b);
            self.text[word] += 1 << shift;
            self.last.1 = d + self.step - 10;
            self.before.1 = e + 1;
            return;
        }
        self.carry_digits();
        self.before = self.digit_before(self.last.0);
    }

    /// [`Self::advance`] digit by digit, with its carries; the cell grown
    /// beyond its width makes the template dead.
    fn carry_digits(&mut self) {
        self.m += self.step;
        if self.step < 10 {
            // The last digit wraps, and one carries into the digits before
            // it: nines become zeros up to the digit that takes it.
            let (mut j, d) = self.last;
            let (word, shift) = Self::at(j);
            self.text[word] -= (10 - self.step) << shift;
            self.last.1 = d + self.step - 10;
            loop {
                if j == self.x.0 {
                    self.dead = true;
                    return;
                }
                j -= 1;
                let (word, shift) = Self::at(j);
                match self.digit(j) {
                    None => {}
                    Some(9) => self.text[word] -= 9 << shift,
                    Some(_) => {
                        self.text[word] += 1 << shift;
                        return;
                    }
                }
            }
        }
        let (mut carry, mut j) = (self.step, self.x.1);
        while carry > 0 {
            if j == self.x.0 {
                self.dead = true;
                return;
            }
            j -= 1;
            let Some(digit) = self.digit(j) else {
                continue;
            };
            let d = digit + carry % 10;
            carry = carry / 10 + d / 10;
            let (word, shift) = Self::at(j);
            let w = &mut self.text[word];
            *w = (*w & !(0xff << shift)) | ((u64::from(b'0') + d % 10) << shift);
        }
        self.last.1 = self.digit(self.last.0).unwrap_or(10);
    }

    /// The next row, when it starts with the template's text and its value
    /// is a plain decimal ending the line: the angle and the value (file
    /// units) and the row's length; the template then moves one step on.
    /// A row shaped as the last one is checked in words at once
    /// ([`RowShape`]); any other is read cell by cell, and its shape kept
    /// for the next.
    #[inline(always)]
    pub(crate) fn next(
        &mut self,
        row: &[u8; ROW],
        decimal_comma: bool,
    ) -> Option<(f64, f64, usize)> {
        if let Some(r) = &self.row {
            let differ = |k: usize| {
                let text = if k < 2 { self.text[k] } else { 0 };
                lanes_differ(
                    word(row, 8 * k),
                    text | r.expect[k],
                    r.exact[k],
                    r.digits[k],
                )
            };
            let mut bad = differ(0) | differ(1);
            if r.third {
                bad |= differ(2);
            }
            if bad == 0 {
                let (v, len) = (r.shape.value_of(word(row, r.at)), r.len);
                return Some(self.step_on(v, len));
            }
        }
        let differ = ((word(row, 0) ^ self.text[0]) & self.mask[0])
            | ((word(row, 8) ^ self.text[1]) & self.mask[1]);
        if self.dead || differ != 0 {
            return None;
        }
        let (v, len) = self.value(row, decimal_comma)?;
        if self.builds < ROW_BUILDS
            && let Some(shape) = self.shapes.shape()
        {
            self.builds += 1;
            let value_end = self.len + usize::from(shape.neg()) + shape.cell_len();
            self.row = row
                .get(value_end..len)
                .and_then(|end| RowShape::new(self.len, shape, end))
                .filter(|r| r.len == len);
        }
        Some(self.step_on(v, len))
    }

    /// The angle of the row just read, with its value `v` and length
    /// `len`; the template moves one step on (a dead one reads no more).
    #[inline(always)]
    fn step_on(&mut self, v: f64, len: usize) -> (f64, f64, usize) {
        let a = self.angle();
        self.advance();
        if self.dead {
            self.row = None;
        }
        self.rows += 1;
        (a, v, len)
    }

    /// The value cell after the template's text, a plain decimal (`-12.5`,
    /// at most 15 digits) up to the end of the line (`\n` or `\r\n`): its
    /// value, as `str::parse` gives it, and the index after the line end.
    /// Read by the last value's shape when it has it (the line end after
    /// it shows that the cell ends there), else learned
    /// ([`Shapes::learn`]).
    #[inline(always)]
    fn value(&mut self, row: &[u8; ROW], decimal_comma: bool) -> Option<(f64, usize)> {
        if let Some((v, i)) = self.shapes.read(row, self.len)
            && let Some(end) = line_end(row, i)
        {
            return Some((v, end));
        }
        let (v, i) = self.shapes.learn(row, self.len, decimal_comma)?;
        line_end(row, i).map(|end| (v, end))
    }
}

/// The index after the line end (`\n` or `\r\n`) at `row[i]`, or `None`
/// (also past the window's end).
#[inline(always)]
fn line_end(row: &[u8; ROW], i: usize) -> Option<usize> {
    match (row.get(i), row.get(i + 1)) {
        (Some(b'\n'), _) => Some(i + 1),
        (Some(b'\r'), Some(b'\n')) => Some(i + 2),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn window(text: &str) -> [u8; ROW] {
        let mut w = [b' '; ROW];
        w[..text.len()].copy_from_slice(text.as_bytes());
        w
    }

    /// The text moves on with carries across the decimal point; a row
    /// that differs anywhere in the prefix, or an angle that needs one
    /// more digit, ends the template.
    #[test]
    fn steps_carries_and_ends() {
        let mut t = Template::seed(b"3,8.9,12.5\n", b',', 1, 2, 0.1).unwrap();
        assert_eq!(t.next(&window("3,9.0,7\n"), false), Some((9.0, 7.0, 8)));
        assert_eq!(
            t.next(&window("3,9.1,-0.25\r\n"), false),
            Some((9.1, -0.25, 13))
        );
        assert_eq!(t.next(&window("4,9.2,1\n"), false), None, "another cycle");
        let mut t = Template::seed(b"3,9.8,1\n", b',', 1, 2, 0.1).unwrap();
        assert_eq!(t.next(&window("3,9.9,1\n"), false), Some((9.9, 1.0, 8)));
        assert!(t.dead, "10.0 does not fit the cell of 9.9");
        assert_eq!(t.next(&window("3,10.0,1\n"), false), None);
        // A step of 0.25 on two decimals, a decimal comma, a tab.
        let mut t = Template::seed(b"1,75\t2\n", b'\t', 0, 1, 0.25).unwrap();
        assert_eq!(t.next(&window("2,00\t3,5\n"), true), Some((2.0, 3.5, 9)));
        assert_eq!(t.next(&window("2,25\t3,5 \n"), true), None, "a space");
    }

    /// Stepped on row after row (steps below 10 units, which take the
    /// one-addition path and the nines' carry, and larger ones), the
    /// angle is what reading the row's cell gives, and the template dies
    /// exactly when the cell would need one more character.
    #[test]
    fn steps_match_the_cells_they_stand_for() {
        for frac in 0..4usize {
            for step in [1u64, 2, 3, 7, 9, 10, 11, 25, 99, 100, 250, 999] {
                for start in [0u64, 1, 8, 9, 95, 98, 99, 990, 995, 9_990, 997_654] {
                    let text = |m: u64| {
                        let s = format!("{m:0w$}", w = frac + 1);
                        let (i, f) = s.split_at(s.len() - frac);
                        if frac == 0 {
                            i.to_string()
                        } else {
                            format!("{i}.{f}")
                        }
                    };
                    let row = |m: u64| format!("4,{},1.5\r\n", text(m));
                    let step_deg = step as f64 / POW10[frac];
                    let seed = row(start);
                    let Some(mut t) = Template::seed(seed.as_bytes(), b',', 1, 2, step_deg) else {
                        // The cells too long, or the next row's angle a
                        // character longer.
                        let grows = text(start + step).len() != text(start).len();
                        assert!(seed.len() > 2 + PREFIX || grows, "{seed:?} by {step}");
                        continue;
                    };
                    let mut m = start + step;
                    // Up to the cell's growth, or far enough past the carries.
                    for _ in 0..3000 {
                        let r = row(m);
                        let got = t.next(&window(&r), false);
                        if text(m).len() != text(start).len() {
                            assert_eq!(got, None, "{r:?} after {seed:?}");
                            break;
                        }
                        let want: f64 = text(m).parse().unwrap();
                        assert_eq!(got, Some((want, 1.5, r.len())), "{r:?} after {seed:?}");
                        m += step;
                    }
                }
            }
        }
    }

    /// Values whose shape changes from row to row (lengths, sign, point,
    /// a digit more than the shape, line ends) read as `str::parse` reads
    /// them, whether by the learned shape or not, and past the changes
    /// after which no shape is learned.
    #[test]
    fn values_of_changing_shapes() {
        let values = [
            "87.14250",
            "87.14251",
            "-87.14250",
            "87.1425",
            "87.142501",
            "187.1425",
            "7",
            "-0",
            "12345678",
            "1234567.8",
            ".5",
            "5.",
            "0.000001",
            "99999999",
            "87.14250",
            "87.14252",
        ];
        let mut t = Template::seed(b"3,0.0,1\n", b',', 1, 2, 0.1).unwrap();
        for round in 0..3 {
            for (k, v) in values.iter().enumerate() {
                let m = (round * values.len() + k + 1) as f64;
                let end = if k % 3 == 0 { "\r\n" } else { "\n" };
                let r = format!("3,{:.1},{v}{end}", m / 10.0);
                let want: f64 = v.parse().unwrap();
                assert_eq!(
                    t.next(&window(&r), false),
                    Some((m / 10.0, want, r.len())),
                    "{r:?}"
                );
                // A digit more than the value's shape, or a space, is not
                // this row's end: the row is refused and the template kept.
                for bad in [format!("{v}1"), format!("{v} ")] {
                    let r = format!("3,{:.1},{bad}\n", (m + 1.0) / 10.0);
                    let got = t.clone().next(&window(&r), false);
                    let want = bad.parse::<f64>().ok().filter(|_| bad.len() <= 16);
                    assert_eq!(
                        got.map(|g| g.1),
                        want.filter(|_| !bad.ends_with(' ')),
                        "{r:?}"
                    );
                }
            }
        }
    }

    /// A row read as the last (by the whole-row pattern, [`RowShape`])
    /// against the plain rule, with one byte of it changed at every place
    /// (the cells before the value, the value's sign, digits and point, the
    /// line end, the byte after it) to bytes chosen to defeat a word-wide
    /// test: digits, separators, signs, line ends, an exponent, NUL and
    /// bytes of 0x80 and more (whose carries cross lanes). The plain rule:
    /// the text before the value exactly the template's, then a plain
    /// decimal up to a line end, read as `str::parse` reads it.
    #[test]
    fn a_row_read_whole_is_the_plain_row() {
        fn plain(row: &[u8], text: &[u8]) -> Option<(f64, usize)> {
            let rest = row.strip_prefix(text)?;
            let end = rest.iter().position(|&c| c == b'\n')?;
            let (cell, len) = match rest[..end].strip_suffix(b"\r") {
                Some(c) => (c, text.len() + end + 1),
                None => (&rest[..end], text.len() + end + 1),
            };
            let digits = cell.iter().filter(|c| c.is_ascii_digit()).count();
            let body = cell.strip_prefix(b"-").unwrap_or(cell);
            let points = body.iter().filter(|&&c| c == b'.').count();
            let ok = (1..=15).contains(&digits)
                && points <= 1
                && body.iter().all(|&c| c.is_ascii_digit() || c == b'.');
            ok.then(|| (std::str::from_utf8(cell).unwrap().parse().unwrap(), len))
        }
        let bytes = [
            b'0', b'5', b'9', b'.', b',', b'-', b'+', b' ', b'\r', b'\n', b'e', b'/', b':', 0,
            0x7f, 0x80, 0x89, 0x8a, 0xb9, 0xba, 0xff,
        ];
        for (text, value, end) in [
            ("3,127.", "87.14250", "\n"),
            ("12,5.", "-0.5", "\r\n"),
            ("7,360.", "1234567", "\n"),
            ("1,99.", "-12.5", "\n"),
        ] {
            let seed = format!("{text}1,{value}{end}");
            let mut t = Template::seed(seed.as_bytes(), b',', 1, 2, 0.1).unwrap();
            // Two rows read, the second by the pattern the first built.
            for m in 2..4 {
                let r = format!("{text}{m},{value}{end}");
                let got = t.next(&window(&r), false).map(|g| g.1);
                assert_eq!(got, Some(value.parse().unwrap()), "{r:?}");
                assert!(t.row.is_some(), "{r:?}: a row shape built");
            }
            let good = format!("{text}4,{value}{end}xy");
            let prefix = format!("{text}4,");
            for at in 0..good.len() {
                for &b in &bytes {
                    let mut r = good.clone().into_bytes();
                    r[at] = b;
                    let mut w = [b' '; ROW];
                    w[..r.len()].copy_from_slice(&r);
                    let got = t.clone().next(&w, false).map(|(_, v, len)| (v, len));
                    let want = plain(&r, prefix.as_bytes());
                    assert_eq!(
                        got.map(|(v, l)| (v.to_bits(), l)),
                        want.map(|(v, l)| (v.to_bits(), l)),
                        "{:?}",
                        String::from_utf8_lossy(&r)
                    );
                }
            }
        }
    }

    /// Rows a template cannot stand for are refused at the seed.
    #[test]
    fn seeds_refused() {
        for (row, step, why) in [
            (&b"-1.0,2\n"[..], 0.1, "sign"),
            (b"1.0,2\n", 0.05, "half a digit"),
            (b"1.0,2\n", -0.1, "falling"),
            (b"12345678901234.5,2\n", 0.1, "over 16 bytes"),
            (b"1.0e1,2\n", 0.1, "exponent"),
        ] {
            assert!(Template::seed(row, b',', 0, 1, step).is_none(), "{why}");
        }
    }
}
