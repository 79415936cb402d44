//! Which notes may mean a wrong result (INTERFACE.md, "Standard output"):
//! on standard error a note that only says what was decided or assumed
//! (columns read, a banner skipped, a default taken) starts `note:`; one
//! that may mean a wrong result (data that look wrong, a figure that cannot
//! be trusted) starts `warning:`. The one home of that choice: every front
//! end prints notes through [`severity`].
//!
//! A note is a decision when it begins as one of [`DECIDED`] says; any
//! other note is a warning, so a new note is heard until it is listed here.
//!
//! ```
//! use enginedyn_pipeline::notes::{severity, Severity};
//! assert_eq!(severity("columns read: `CA [deg]` as crank angle (deg)"), Severity::Note);
//! assert_eq!(severity("near idle or motoring (mean torque 3 N m …)"), Severity::Warning);
//! ```

/// How a note is printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// What was decided or assumed: `note:`.
    Note,
    /// What may be wrong: `warning:`.
    Warning,
}

impl Severity {
    /// The word that starts its line on standard error.
    pub fn label(self) -> &'static str {
        match self {
            Severity::Note => "note",
            Severity::Warning => "warning",
        }
    }
}

/// How the notes that say what was decided or assumed begin.
pub const DECIDED: &[&str] = &[
    // The reader: columns, banners, layouts, sheets, axes, speeds.
    "columns read",
    "skipped ",
    "read sheet ",
    "read group ",
    "speed ",
    "time record: the angle from",
    "the angle runs on over ",
    "firing TDC at the file's 360°",
    "cylinder traces ",
    "one trace per cylinder",
    "no TDC offset estimate",
    "at the highest load (",
    "idle criterion: ",
    "the periodic spline overshoots",
    "--despike replaced ",
    // The engine file's defaults and estimates.
    "cylinder_spacing_mm not given",
    "defaults taken",
    "torsion.flywheel_inertia_kg_m2 not given",
    "torsion.flywheel_stiffness_nm_rad not given",
    "torsion.throw_inertia_kg_m2 estimated",
    "journal stiffness from journal_diameter_mm",
    // The torsion model's assumptions and what it leaves out.
    "each throw carries the reciprocating mass's mean inertia",
    "flywheel sized ",
    "pin offset: series4 and series6",
    // Methods chosen (--tolerance, accuracy) and what a spread is over.
    "--tolerance",
    "interpolation and grid-step errors against",
    "imep_std_bar, imep_cov",
    // The combustion analysis: a cycle that does not burn (motored, a fuel cut).
    "no combustion in ",
    // Knock the data cannot resolve (their sampling): null, said once.
    "knock not measured",
    // batch over folders (one file, or several).
    "1 file of another kind passed over",
    // A campaign's list: a file named twice (by any path); --replace.
    "1 file named more than once",
    "parts of another campaign removed (--replace)",
    // Synthesis for design: the diagram made from [combustion].
    "diagram synthesised from [combustion]",
];

/// Whether `note` only says what was decided or assumed.
pub fn severity(note: &str) -> Severity {
    let decided = DECIDED.iter().any(|d| note.starts_with(d))
        // "4 pressure columns: one cycle per column", "3 files of other kinds …"
        || note
            .split_once(' ')
            .is_some_and(|(n, rest)| {
                n.bytes().all(|b| b.is_ascii_digit())
                    && (rest.starts_with("pressure columns")
                        || rest.starts_with("files of other kinds")
                        || rest.starts_with("files named more than once")
                        || rest.starts_with("cycles one after another"))
            })
        // "the rigid rod, not the engine file's two-mass": a method --tolerance chose.
        || (note.starts_with("the ") && note.contains(" rod, not the engine file's"))
        || note.contains(" kinematics, not exact (the default)")
        || note.contains(": a side table, left out")
        // Torsion: a resonance without a peak of its own, orders not computed.
        || note.contains(" resonances have no peak near their crossing")
        || note.contains(" in the speed range: those orders are not computed");
    if decided {
        Severity::Note
    } else {
        Severity::Warning
    }
}

/// Each note once, in order, with its severity: what a front end prints.
pub fn printed<'a>(notes: impl IntoIterator<Item = &'a String>) -> Vec<(Severity, &'a str)> {
    let mut seen: Vec<&str> = Vec::new();
    let mut out = Vec::new();
    for n in notes {
        if !seen.contains(&n.as_str()) {
            seen.push(n);
            out.push((severity(n), n.as_str()));
        }
    }
    out
}

/// The most items a group names: a kind that concerns fewer items than
/// this lists them; more are only counted (INTERFACE.md, "A batch's log").
pub const NAMED_BELOW: usize = 4;

/// Where the numbers of `note` lie (byte ranges): an optional sign, digits,
/// decimals and an exponent (`-3`, `+5.3`, `1.5e-7`, `−2`); digits that are
/// part of a word (`CA50`, `P_Cyl1`, `file2.csv`) are not numbers, and a
/// unit after a number is text (`570 mm`, `3.6mm`).
fn numbers(note: &str) -> Vec<std::ops::Range<usize>> {
    let b = note.as_bytes();
    let word = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if !b[i].is_ascii_digit() {
            i += 1;
            continue;
        }
        let prev = note[..i].chars().next_back();
        if prev.is_some_and(|c| c.is_alphabetic() || c == '_') {
            // A word's digits, with its dotted parts (`v1.2`).
            while i < b.len()
                && (word(b[i]) || (b[i] == b'.' && b.get(i + 1).is_some_and(|&c| word(c))))
            {
                i += 1;
            }
            continue;
        }
        let mut start = i;
        if let Some(c) = prev.filter(|c| matches!(c, '-' | '+' | '−')) {
            let before = note[..i - c.len_utf8()].chars().next_back();
            if before.is_none_or(|d| !(d.is_alphanumeric() || matches!(d, '_' | '.' | ')'))) {
                start -= c.len_utf8();
            }
        }
        let digits = |mut j: usize| {
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            j
        };
        i = digits(i);
        if b.get(i) == Some(&b'.') && b.get(i + 1).is_some_and(u8::is_ascii_digit) {
            i = digits(i + 1);
        }
        if matches!(b.get(i), Some(b'e' | b'E')) {
            let mut j = i + 1;
            if matches!(b.get(j), Some(b'+' | b'-')) {
                j += 1;
            }
            if b.get(j).is_some_and(u8::is_ascii_digit) {
                i = digits(j);
            }
        }
        out.push(start..i);
    }
    out
}

/// A note's kind: what it says, its numbers each replaced by a
/// placeholder (`\u{1}`, which no note holds). Notes of one kind differ
/// only in their numbers; notes with different counts of numbers are
/// different kinds.
pub fn kind(note: &str) -> String {
    let mut k = String::with_capacity(note.len());
    let mut at = 0;
    for r in numbers(note) {
        k.push_str(&note[at..r.start]);
        k.push('\u{1}');
        at = r.end;
    }
    k.push_str(&note[at..]);
    k
}

/// A number's value and its text as a note wrote it.
type Value<'a> = (f64, &'a str);

/// One kind's notes over the items: the items it concerns and, per number
/// position, the smallest and largest value with their text.
struct Group<'a> {
    first: &'a str,
    items: Vec<&'a str>,
    ranges: Vec<(Value<'a>, Value<'a>)>,
}

impl<'a> Group<'a> {
    fn add(&mut self, note: &'a str) {
        for (r, range) in numbers(note).into_iter().zip(&mut self.ranges) {
            let text = &note[r];
            let v = text.replace('−', "-").parse::<f64>().unwrap_or(f64::NAN);
            if v < range.0.0 {
                range.0 = (v, text);
            }
            if v > range.1.0 {
                range.1 = (v, text);
            }
        }
    }

    /// The first note with each number replaced by its range (`1.4–9.5`),
    /// or kept where every note gives the same value.
    fn text(&self) -> String {
        let mut out = String::with_capacity(self.first.len() + 16);
        let mut at = 0;
        for (r, ((lo, lo_text), (hi, hi_text))) in numbers(self.first).into_iter().zip(&self.ranges)
        {
            out.push_str(&self.first[at..r.start]);
            if lo < hi {
                out.push_str(&format!("{lo_text}–{hi_text}"));
            } else {
                out.push_str(&self.first[r.clone()]);
            }
            at = r.end;
        }
        out.push_str(&self.first[at..]);
        out
    }
}

/// Many items' notes (the files of a batch, the points of a sweep: `(name,
/// notes)` each, items without notes too, so that they count) grouped by
/// [`kind`], each kind one line with its severity, in the order first met
/// (INTERFACE.md, "A batch's log is read by people and by job schedulers"):
///
/// - a kind of one item: `NAME: NOTE`, as the note is;
/// - of fewer than [`NAMED_BELOW`] items: `K of N ITEMS (A, B): NOTE`;
/// - of more: `K of N ITEMS: NOTE`,
///
/// where NOTE has each number that differs over the kind's notes replaced
/// by its range, smallest–largest (`rim 1.4–9.5 mm wide at 570–1140 mm`).
/// `items` names the items in the plural (`files`, `points`). The one
/// grouping of notes: `batch` and `sweep` print through it, and so does the
/// Python package's `Session.batch`.
///
/// ```
/// use enginedyn_pipeline::notes::{grouped, Severity};
/// let a = vec!["the flywheel (rim) is 1.4 mm wide at 1140 mm".to_string()];
/// let b = vec!["the flywheel (rim) is 9.5 mm wide at 570 mm".to_string()];
/// let lines = grouped([("a.csv", &a[..]), ("b.csv", &b[..])], "files");
/// assert_eq!(lines, [(Severity::Warning,
///     "2 of 2 files (a.csv, b.csv): the flywheel (rim) is 1.4–9.5 mm wide at 570–1140 mm".to_string())]);
/// ```
pub fn grouped<'a>(
    per_item: impl IntoIterator<Item = (&'a str, &'a [String])>,
    items: &str,
) -> Vec<(Severity, String)> {
    let mut order: Vec<String> = Vec::new();
    let mut groups: std::collections::HashMap<String, Group<'a>> = std::collections::HashMap::new();
    let mut total = 0usize;
    for (name, notes) in per_item {
        total += 1;
        for n in notes {
            let g = groups.entry(kind(n)).or_insert_with_key(|k| {
                order.push(k.clone());
                let ranges = numbers(n)
                    .into_iter()
                    .map(|_| ((f64::INFINITY, ""), (f64::NEG_INFINITY, "")))
                    .collect();
                Group {
                    first: n,
                    items: Vec::new(),
                    ranges,
                }
            });
            g.add(n);
            if g.items.last() != Some(&name) {
                g.items.push(name);
            }
        }
    }
    order
        .iter()
        .map(|k| {
            let g = &groups[k];
            let text = g.text();
            let line = match g.items.as_slice() {
                [one] => format!("{one}: {text}"),
                named if named.len() < NAMED_BELOW => {
                    format!(
                        "{} of {total} {items} ({}): {text}",
                        named.len(),
                        named.join(", ")
                    )
                }
                many => format!("{} of {total} {items}: {text}", many.len()),
            };
            (severity(g.first), line)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decisions_are_notes_and_the_rest_warnings() {
        for n in [
            "4 pressure columns, one per cylinder (their names say which)",
            "speed 4900 rpm from the banner on line 1",
            "skipped 1 line above the header (a title or banner: `x`)",
            "no TDC offset estimate: the estimate needs a motored or fuel-cut cycle",
            "the rigid rod, not the engine file's two-mass",
            "series4 kinematics, not exact (the default): within 1e-3",
            "--tolerance 0.001: grid 0.9375° (estimated 0.00023 from the step before)",
        ] {
            assert_eq!(severity(n), Severity::Note, "{n}");
        }
        for n in [
            "near idle or motoring",
            "the banner on line 1 gives the speed `4,9`, which is not a number: not used",
            "bore_mm = 0.086: metres?",
            "a new note nobody listed",
        ] {
            assert_eq!(severity(n), Severity::Warning, "{n}");
        }
    }

    fn numbers_of(note: &str) -> Vec<&str> {
        numbers(note).into_iter().map(|r| &note[r]).collect()
    }

    #[test]
    fn numbers_with_signs_decimals_units_and_exponents() {
        assert_eq!(
            numbers_of(
                "rim 1.4 mm wide at 570mm, -3 bar, +5.3°, −2 J, 1.5e-7 kg m², 3E+2 Pa, 2e N"
            ),
            ["1.4", "570", "-3", "+5.3", "−2", "1.5e-7", "3E+2", "2"]
        );
        // Digits of a word are no number; a range's dash is no sign.
        assert_eq!(
            numbers_of("CA50 at 8° in P_Cyl1 of run2.csv, v1.2, 10–90 in 40°, x-5"),
            ["8", "10", "90", "40", "5"]
        );
        // A sentence's full stop is not a decimal point.
        assert_eq!(numbers_of("at 12. Then 0.5."), ["12", "0.5"]);
    }

    #[test]
    fn a_kind_is_the_text_without_its_numbers() {
        assert_eq!(kind("δ 0.01 at 1000 rpm"), kind("δ 0.0125 at -2e3 rpm"));
        // Different counts of numbers: different kinds.
        assert_ne!(kind("speed 1000 rpm"), kind("speed 1000 rpm at 2 bar"));
        assert_ne!(kind("CA50 8°"), kind("CA10 8°"));
    }

    #[test]
    fn notes_grouped_by_kind_with_counts_names_and_ranges() {
        let thin = |w: &str, d: &str| {
            vec![format!(
                "the flywheel (rim) is {w} mm wide at {d} mm diameter; set flywheel.outer_diameter_mm"
            )]
        };
        let decided = vec!["speed 1000 rpm from --rpm 1000:3000:500".to_string()];
        let files: Vec<(String, Vec<String>)> = vec![
            ("a.csv".into(), thin("1.4", "1140")),
            ("b.csv".into(), thin("9.5", "570")),
            ("c.csv".into(), thin("-2.5e-1", "600")),
            ("d.csv".into(), thin("3", "600")),
            ("e.csv".into(), decided.clone()),
            ("f.csv".into(), Vec::new()),
        ];
        let lines = grouped(
            files.iter().map(|(f, n)| (f.as_str(), n.as_slice())),
            "files",
        );
        assert_eq!(
            lines,
            [
                (
                    Severity::Warning,
                    "4 of 6 files: the flywheel (rim) is -2.5e-1–9.5 mm wide at 570–1140 mm diameter; set flywheel.outer_diameter_mm".to_string()
                ),
                (Severity::Note, format!("e.csv: {}", decided[0])),
            ]
        );
        // Fewer than four: named. The same value everywhere: kept as is.
        let lines = grouped(
            files[..2].iter().map(|(f, _)| (f.as_str(), &decided[..])),
            "points",
        );
        assert_eq!(
            lines,
            [(
                Severity::Note,
                format!("2 of 2 points (a.csv, b.csv): {}", decided[0])
            )]
        );
        // One item's two notes of a kind: one item, its range.
        let two = ["gap 2° at 10°".to_string(), "gap 3° at 10°".to_string()];
        assert_eq!(
            grouped([("a", &two[..])], "files")[0].1,
            "a: gap 2–3° at 10°"
        );
    }

    #[test]
    fn each_note_is_printed_once() {
        let notes: Vec<String> = ["a", "b", "a"].iter().map(|s| s.to_string()).collect();
        assert_eq!(printed(&notes).len(), 2);
    }
}
