//! The reader: rows of cells from a source, in three phases (the preamble of
//! titles and banners, the header, the data), into finished traces for the
//! grid. The source (text or spreadsheet) hands it rows; the column resolver
//! says what the columns hold; the layout turns rows into traces; the
//! emitter checks each finished trace and applies the gap rule.

use crate::columns::{Axis, Roles, expand};
use crate::emit::Emitter;
use crate::error::{IngestError, at};
use crate::layout::Layout;
use crate::probe::{PROBE_VALUES, Probe, no_header};
use crate::row::Cells;
use crate::{Header, ParseOptions, Streamed};

/// The most columns a diagram may have (INTERFACE.md, "Bounds"): as many
/// as a spreadsheet's row.
pub(crate) const MAX_COLUMNS: usize = 16_384;

/// Text rows above the data that the reader looks at for a header.
pub(crate) const PREAMBLE_LINES: usize = 50;

/// A text row above the data.
pub(crate) struct TextLine {
    pub line: usize,
    pub cells: Vec<String>,
    /// The same line split at runs of two or more spaces (space-delimited
    /// files whose names hold single spaces: `Crank Angle [deg]`).
    pub wide: Option<Vec<String>>,
    /// The line as written (text files), else its cells joined by a space:
    /// what a banner's note quotes and its speed is read from.
    pub raw: String,
}

/// Where the reader is.
pub(crate) enum Phase {
    /// Before the first data row: text rows kept to find the header in.
    Preamble(Vec<TextLine>),
    /// Data rows, read by their layout.
    Data(Box<Layout>),
}

/// The reader's state.
pub(crate) struct Reader<'o, F> {
    pub opts: &'o ParseOptions,
    pub head: Header,
    pub phase: Phase,
    pub out: Emitter<'o, F>,
    /// Where the file's speed came from, for messages that name it.
    pub rpm_source: &'static str,
    /// The angle, pressure and volume columns (cells a source may refuse:
    /// `Cells::measured`).
    pub measured: Vec<usize>,
    /// The names are the program's, not a file's (arrays in memory): no
    /// note says how they were read.
    pub names_given: bool,
}

impl<'o, F: FnMut(Streamed) -> Result<(), IngestError>> Reader<'o, F> {
    pub(crate) fn new(opts: &'o ParseOptions, sink: F) -> Self {
        Self {
            opts,
            head: Header::default(),
            phase: Phase::Preamble(Vec::new()),
            out: Emitter::new(opts, sink),
            rpm_source: "the `# rpm` line",
            measured: Vec::new(),
            names_given: false,
        }
    }

    /// A comment line (`#` …): a speed line is read, anything else skipped.
    pub(crate) fn comment(&mut self, line: usize, text: &str) -> Result<(), IngestError> {
        if is_synthetic(text) {
            self.head.synthetic = true;
            self.out.synthetic = true;
        }
        match parse_rpm(text) {
            Some(Ok(r))
                if self
                    .head
                    .rpm
                    .is_some_and(|was| was.to_bits() != r.to_bits()) =>
            {
                Err(at(
                    line,
                    None,
                    format!(
                        "a second speed line says {r} rpm, an earlier one {} rpm",
                        self.head.rpm.unwrap_or_default()
                    ),
                ))
            }
            Some(Ok(r)) => {
                self.head.rpm = Some(r);
                Ok(())
            }
            Some(Err(message)) => Err(at(line, None, message)),
            None => Ok(()),
        }
    }

    /// True while no data row has been read.
    pub(crate) fn in_preamble(&self) -> bool {
        matches!(self.phase, Phase::Preamble(_))
    }

    /// One row of cells. `wide` splits a text row at runs of spaces, for
    /// space-delimited headers.
    pub(crate) fn row(
        &mut self,
        line: usize,
        cells: &impl Cells,
        wide: impl FnOnce() -> Option<Vec<String>>,
    ) -> Result<(), IngestError> {
        match &mut self.phase {
            Phase::Data(layout) => {
                if let Some(p) = self.out.probe.as_mut() {
                    p.rows += 1;
                    // A probe holds at most PROBE_VALUES values: past them,
                    // the plain hint (a guess is not worth reading on).
                    if p.rows.saturating_mul(p.k) > PROBE_VALUES {
                        return Err(p.error());
                    }
                }
                let r = cells
                    .measured(&self.measured, line)
                    .and_then(|()| layout.row(line, cells, &mut self.out));
                self.out.probed(r)
            }
            Phase::Preamble(text) => {
                if cells.is_data() {
                    let text = std::mem::take(text);
                    let layout = self.start(line, cells, text);
                    let layout = self.out.probed(layout)?;
                    self.phase = Phase::Data(Box::new(layout));
                    let Phase::Data(layout) = &mut self.phase else {
                        return Ok(());
                    };
                    let r = cells
                        .measured(&self.measured, line)
                        .and_then(|()| layout.row(line, cells, &mut self.out));
                    return self.out.probed(r);
                }
                if text.len() >= PREAMBLE_LINES {
                    return Err(at(
                        line,
                        None,
                        format!(
                            "no data row in the first {PREAMBLE_LINES} lines that are not comments: not a diagram? (--skip-lines N skips a longer preamble)"
                        ),
                    ));
                }
                let n = cells.used();
                let split: Vec<String> = (0..n)
                    .map(|i| cells.text(i).trim().trim_matches('"').to_string())
                    .collect();
                text.push(TextLine {
                    line,
                    raw: cells
                        .raw()
                        .map_or_else(|| split.join(" "), |r| r.trim().to_string()),
                    cells: split,
                    wide: wide(),
                });
                Ok(())
            }
        }
    }

    /// Rows `0..n` of columns decoded whole (a binary source: one column a
    /// channel), row `r` on line `line0 + r`. Runs of rows that continue
    /// the cycles being read go from the columns straight into the traces
    /// ([`crate::fast::long_columns`], [`crate::fast::per_column_columns`]),
    /// and a time record's samples into its crank signal's state machine
    /// (`TimeRecord::columns`);
    /// a row they stop at (a cycle's first, a value that is no number) is
    /// read as the cells `cells(r)` by [`Self::row`], as a text row is, so
    /// the rules of a row live in one place.
    pub(crate) fn columns<C: Cells, V: AsRef<[f64]>>(
        &mut self,
        line0: usize,
        cols: &[V],
        n: usize,
        cells: impl Fn(usize) -> C,
    ) -> Result<(), IngestError> {
        let mut r = 0;
        while r < n {
            // (Not while a headerless file is probed: every row counts there.)
            if let (Phase::Data(layout), None) = (&mut self.phase, &self.out.probe) {
                r += match &mut **layout {
                    Layout::Long(l) => crate::fast::long_columns(l, cols, r, n),
                    Layout::PerColumn(p) => crate::fast::per_column_columns(p, cols, r, n),
                    Layout::Time(t) => t.columns(line0, cols, r, n, &mut self.out)?,
                };
                if r >= n {
                    break;
                }
            }
            self.row(line0 + r, &cells(r), || None)?;
            r += 1;
        }
        Ok(())
    }

    /// The first data row: find the header among the text rows above it,
    /// resolve the columns and choose the layout.
    fn start(
        &mut self,
        line: usize,
        cells: &impl Cells,
        text: Vec<TextLine>,
    ) -> Result<Layout, IngestError> {
        let k = cells.used();
        if k > MAX_COLUMNS {
            return Err(at(
                line,
                None,
                format!(
                    "{k} columns: more than the bound of {MAX_COLUMNS} a diagram may have (as in a spreadsheet); read no further"
                ),
            ));
        }
        let (roles, header_at) = self.resolve_columns(line, k, &text)?;
        // Lines above the header: titles and banners.
        let banner = header_at.map_or(0, |h| h);
        if banner > 0 {
            self.note_banner(&text[..banner]);
        }
        if let Some(h) = header_at.and_then(|h| text.get(h))
            && let Some(e) = side_table(&h.cells)
        {
            self.note_side_table(&h.cells, e);
        }
        self.note_columns(&roles);
        self.keep_roles(&roles);
        // Volts are relative, so `value_scale` refuses them unless pegged:
        // `opts.relative` alone says whether traces are checked for sign.
        Layout::new(
            roles,
            self.opts,
            self.head.rpm.map(|r| (r, self.rpm_source)),
            line,
        )
    }

    /// The roles of the `k` columns of the first data row (on `line`) and
    /// the header's index among the `text` rows above it (`None`: none):
    /// from --columns, from the no-header probe, or from the header found.
    fn resolve_columns(
        &mut self,
        line: usize,
        k: usize,
        text: &[TextLine],
    ) -> Result<(Roles, Option<usize>), IngestError> {
        match &self.opts.columns {
            Some(given) => Ok((
                self.given_columns(given, k, line)?,
                text.len().checked_sub(1),
            )),
            // No header: the columns read as `crank_deg,pressure_bar...`
            // until each has a verdict, for a hint that offers only the
            // readings that fit (INTERFACE.md, "Plausibility").
            None if text.is_empty()
                && !self.opts.torque
                && k >= 2
                && self.opts.angle_step_deg.is_none() =>
            {
                let names = expand(&["crank_deg".into(), "pressure_bar...".into()], k);
                let roles = Roles::resolve(&names, true, line, false)
                    .map_err(|_| no_header(k, line, None))?;
                self.out.probe = Some(Probe {
                    line,
                    k,
                    verdicts: vec![None; roles.values.len()],
                    done: false,
                    rows: 1,
                });
                Ok((roles, None))
            }
            None => header(
                text,
                k,
                line,
                self.opts.torque,
                self.opts.angle_step_deg.is_some(),
            ),
        }
    }

    /// The roles of the `k` columns named by --columns (`given`), which
    /// must name each column once.
    fn given_columns(&self, given: &[String], k: usize, line: usize) -> Result<Roles, IngestError> {
        let names = expand(given, k);
        if let Some(extra) = (k..names.len()).find(|&i| names[i].trim() != "_") {
            return Err(at(
                line,
                Some(extra + 1),
                format!(
                    "--columns names {} columns, this file's rows have {k}: `{}` names column {}, which no row has",
                    names.len(),
                    enginedyn_numerics::format::quote(&names[extra]),
                    extra + 1
                ),
            ));
        }
        if names.len() < k {
            return Err(at(
                line,
                Some(names.len() + 1),
                format!(
                    "{k} columns, --columns names {}: name every column (`_` skips one), or end the list with `...` to repeat the last name over the rest (one cycle per column)",
                    names.len()
                ),
            ));
        }
        Roles::resolve_with(
            &names,
            true,
            line,
            self.opts.torque,
            self.opts.angle_step_deg.is_some(),
        )
    }

    /// The note on the lines `above` the header (at least one: titles and
    /// banners), and the speed a banner gives when no `# rpm` line did.
    fn note_banner(&mut self, above: &[TextLine]) {
        let banner = above.len();
        let first = above[0].raw.clone();
        let shown: String = first.chars().take(60).collect();
        self.head.notes.push(format!(
            "skipped {banner} line{} above the {} (a title or banner: `{}{}`)",
            if banner > 1 { "s" } else { "" },
            if self.opts.columns.is_some() {
                "data"
            } else {
                "header"
            },
            enginedyn_numerics::format::quote(&shown),
            if first.chars().count() > 60 {
                "…"
            } else {
                ""
            }
        ));
        if self.head.rpm.is_none()
            && let Some((r, at_line)) = above
                .iter()
                .find_map(|t| banner_rpm(&t.raw).map(|r| (r, t.line)))
        {
            match r {
                Ok(r) => {
                    self.head.rpm = Some(r);
                    self.rpm_source = "the banner";
                    self.head.notes.push(format!(
                        "speed {} rpm from the banner on line {at_line}",
                        enginedyn_numerics::format::human(r)
                    ));
                }
                Err((tok, why)) => self.head.notes.push(format!(
                    "the banner on line {at_line} gives the speed `{}`, which {}: not used (the engine file's or --rpm's speed stands)",
                    enginedyn_numerics::format::quote(&tok),
                    match why {
                        crate::SpeedError::Number(e) => e.to_string(),
                        e => e.to_string(),
                    }
                )),
            }
        }
    }

    /// The note on the header's `cells` right of the empty column `e`: a
    /// side table, left out.
    fn note_side_table(&mut self, cells: &[String], e: usize) {
        let names: Vec<String> = cells[e..]
            .iter()
            .filter(|c| !c.trim().is_empty())
            .take(4)
            .map(|c| format!("`{}`", enginedyn_numerics::format::quote(c)))
            .collect();
        self.head.notes.push(format!(
            "columns {} to {} ({}{}) lie right of the empty column {}: a side table, left out",
            e + 2,
            cells.len(),
            names.join(", "),
            if cells[e..].iter().filter(|c| !c.trim().is_empty()).count() > 4 {
                ", …"
            } else {
                ""
            },
            e + 1
        ));
    }

    /// The notes on how the columns were read (none for names the program
    /// gave): the resolver's, and how several pressure columns read.
    fn note_columns(&mut self, roles: &Roles) {
        if let Some(n) = roles.note.as_ref().filter(|_| !self.names_given) {
            self.head.notes.push(n.clone());
        }
        if roles.values.len() > 1 && !self.names_given {
            self.head.notes.push(if roles.per_cylinder {
                format!(
                    "{} pressure columns, one per cylinder (their names say which)",
                    roles.values.len()
                )
            } else {
                format!(
                    "{} pressure columns: one cycle per column",
                    roles.values.len()
                )
            });
        }
    }

    /// What the emitter, the header and the row reader keep of the
    /// columns' roles: labels, volts, the axis, the measured columns.
    fn keep_roles(&mut self, roles: &Roles) {
        self.out.labels = roles.labels.clone();
        self.out.volts = roles.volts;
        self.out.time = matches!(roles.axis, Axis::Time(_));
        self.head.quantity = roles.quantity;
        self.head.pv = matches!(roles.axis, Axis::Volume(_));
        self.measured = roles.values.iter().map(|v| v.col).collect();
        if matches!(roles.axis, Axis::Angle(_) | Axis::Volume(_))
            && roles.x != crate::columns::STEPPED_X
        {
            self.measured.push(roles.x);
        }
    }

    /// The end of the source.
    pub(crate) fn end(mut self) -> Result<Header, IngestError> {
        match std::mem::replace(&mut self.phase, Phase::Preamble(Vec::new())) {
            Phase::Preamble(text) => {
                return Err(match text.last() {
                    Some(t) => at(t.line, None, "no data rows after the header"),
                    None => IngestError::Data("no data rows".into()),
                });
            }
            Phase::Data(layout) => {
                let r = (*layout).end(&mut self.out, &mut self.head);
                self.out.probed(r)?;
                // Every trace handed over and still no verdict for each
                // column: nothing fits that can be said.
                if let Some(p) = &self.out.probe {
                    return Err(p.error());
                }
            }
        }
        self.out.end(&mut self.head)?;
        Ok(self.head)
    }
}

/// The header among the text rows above the data (`k` cells wide): the
/// last row, or the last two as names and units, or the one before a
/// units row. Returns the roles and the header's index in `text`.
fn header(
    text: &[TextLine],
    k: usize,
    line: usize,
    torque: bool,
    stepped: bool,
) -> Result<(Roles, Option<usize>), IngestError> {
    let Some(last) = text.len().checked_sub(1) else {
        return Err(no_header(k, line, None));
    };
    let resolve = |names: &[String], explicit: bool, line: usize, torque: bool| {
        Roles::resolve_with(names, explicit, line, torque, stepped)
    };
    let fit = |t: &TextLine| -> Vec<String> {
        let mut n = match &t.wide {
            Some(w) if t.cells.len() != k && w.len() == k => w.clone(),
            _ => t.cells.clone(),
        };
        // A delimiter at the end of every row (spreadsheet exports): the
        // empty last columns are skipped.
        for x in n.iter_mut().rev().take_while(|x| x.is_empty()) {
            *x = "_".into();
        }
        // Columns right of an empty column are a side table: left out.
        if let Some(e) = side_table(&n) {
            for x in &mut n[e..] {
                *x = "_".into();
            }
        }
        n
    };
    let check = |names: &[String], at_line: usize| -> Result<(), IngestError> {
        if names.len() < k {
            return Err(at(
                line,
                Some(names.len() + 1),
                format!(
                    "{k} cells, the header on line {at_line} names {}: every column needs a name",
                    names.len()
                ),
            ));
        }
        Ok(())
    };
    let names = fit(&text[last]);
    // A units row under a names row (`CA | PCYL1` over `deg | bar`): one
    // header, the names with their units, before the units alone.
    if last > 0 && crate::columns::units_row(&names) {
        let above = fit(&text[last - 1]);
        if above.len() == names.len()
            && let Ok(r) = resolve(
                &join_units(&above, &names),
                false,
                text[last - 1].line,
                torque,
            )
        {
            check(&above, text[last - 1].line)?;
            return Ok((r, Some(last - 1)));
        }
    }
    let first_try = resolve(&names, false, text[last].line, torque);
    if let Ok(r) = first_try {
        check(&names, text[last].line)?;
        return Ok((r, Some(last)));
    }
    if last > 0 {
        // Names, then units on the next row.
        let (a, b) = (fit(&text[last - 1]), fit(&text[last]));
        if a.len() == b.len() {
            let joined = join_units(&a, &b);
            if let Ok(r) = resolve(&joined, false, text[last - 1].line, torque) {
                check(&joined, text[last - 1].line)?;
                return Ok((r, Some(last - 1)));
            }
        }
        if let Ok(r) = resolve(&a, false, text[last - 1].line, torque) {
            check(&a, text[last - 1].line)?;
            return Ok((r, Some(last - 1)));
        }
    }
    Err(first_try
        .err()
        .unwrap_or_else(|| IngestError::Data("no header".into())))
}

/// Where a side table starts: the first empty header cell with a named
/// one to its right (INTERFACE.md, "Units are not angles": columns right of
/// an empty column are a side table).
fn side_table(names: &[String]) -> Option<usize> {
    let named = |x: &String| !x.trim().is_empty() && x != "_";
    let e = names.iter().position(|x| x.trim().is_empty())?;
    names[e + 1..].iter().any(named).then_some(e)
}

/// Names with the units of the row below them: `PCYL1 [bar]`.
fn join_units(names: &[String], units: &[String]) -> Vec<String> {
    names
        .iter()
        .zip(units)
        .map(|(n, u)| {
            if u == "_" || u.is_empty() || u == "-" {
                n.clone()
            } else {
                format!("{n} [{}]", u.trim_matches(['[', ']', '(', ')']))
            }
        })
        .collect()
}

/// The first line `enginedyn synth` writes: the diagram is synthetic,
/// its firing TDC exact by construction.
pub const SYNTHETIC_MARK: &str = "synthetic indicator diagram, not measured: enginedyn synth";

/// True for the comment line that marks a synthesised diagram.
fn is_synthetic(comment: &str) -> bool {
    comment
        .trim_start_matches('#')
        .trim_start()
        .starts_with(SYNTHETIC_MARK)
}

/// The speed a comment line gives: `None` when the comment is not a speed
/// line (`# rpm = N` or `# rpm: N`, any case), an error when it is one
/// whose value is not a speed (read whole by [`crate::read_rpm`]: `1,800`
/// is 1800, `1,8` is refused). A unit after the number is ignored, and so
/// are delimiters at the end of the line.
pub(crate) fn parse_rpm(comment: &str) -> Option<Result<f64, String>> {
    // A spreadsheet export closes the line with empty cells: `# rpm = 2200,,`.
    let c = comment
        .trim_start_matches('#')
        .trim_end_matches([',', ';', '\t', ' '])
        .trim();
    let rest = c
        .get(..3)
        .filter(|k| k.eq_ignore_ascii_case("rpm"))
        .map(|_| c[3..].trim_start())?;
    let rest = rest.strip_prefix('=').or_else(|| rest.strip_prefix(':'))?;
    let value = speed_token(rest);
    Some(crate::read_rpm(&value).map_err(|e| {
        let why = match e {
            crate::SpeedError::Number(n) => {
                format!("`{}` {n}", enginedyn_numerics::format::quote(&value))
            }
            crate::SpeedError::Bound(v) => format!("{} rpm", enginedyn_numerics::format::human(v)),
        };
        format!(
            "`{}`: {why}; the speed must be a number of rpm from 0.001 to 100000",
            enginedyn_numerics::format::quote(comment.trim()),
        )
    }))
}

/// The token of a speed after its `=`: up to a run of two spaces, a tab or
/// a `;`, single spaces kept only between digits (`4 900`), a trailing
/// unit (`rpm`, `1/min`, `U/min`, `min-1`) and trailing commas dropped.
fn speed_token(rest: &str) -> String {
    let r = rest.trim_start();
    let chars: Vec<char> = r.chars().collect();
    let mut tok = String::new();
    for (i, &c) in chars.iter().enumerate() {
        if c == '\t' || c == ';' {
            break;
        }
        if c == ' ' {
            // A thousands group: three digits, then no more digits.
            let group = |k: usize| chars.get(k).is_some_and(char::is_ascii_digit);
            let between = i > 0
                && chars[i - 1].is_ascii_digit()
                && (1..=3).all(|k| group(i + k))
                && !group(i + 4);
            if between {
                tok.push(c);
                continue;
            }
            break;
        }
        tok.push(c);
    }
    let mut t = tok.trim_end_matches([',', '.']).to_string();
    for unit in ["rpm", "1/min", "u/min", "min-1", "min^-1"] {
        if t.len() > unit.len() && t.to_ascii_lowercase().ends_with(unit) {
            t.truncate(t.len() - unit.len());
            break;
        }
    }
    t
}

/// A speed in a banner line (`----Engine speed[rpm] = 1000.0 …`): the
/// value after the `=` or `:` that follows `rpm` (or `speed` on a line
/// that says rpm), read whole by the one number rule: `Some(Ok)` a speed,
/// `Some(Err)` the token and why it is not used, `None` no speed here.
fn banner_rpm(line: &str) -> Option<Result<f64, (String, crate::SpeedError)>> {
    let l = line.to_ascii_lowercase();
    if !l.contains("rpm") && !l.contains("1/min") && !l.contains("u/min") {
        return None;
    }
    let key = ["speed", "drehzahl", "rpm", "n ="]
        .iter()
        .filter_map(|k| l.find(k))
        .min()?;
    // The unit may sit between the key and the `=`: `speed[rpm] = 4900`,
    // `Drehzahl [1/min];3600` (cells joined by a space).
    let rest = &line[key..];
    let from = rest.find(['=', ':']).map(|i| i + 1).or_else(|| {
        // No `=`: the first digit after the key's unit.
        let after_unit = ["1/min", "u/min", "rpm", "]", ")"]
            .iter()
            .filter_map(|u| rest.to_ascii_lowercase().find(u).map(|i| i + u.len()))
            .max()
            .unwrap_or(0);
        rest[after_unit..]
            .find(|c: char| c.is_ascii_digit() || c == '-' || c == '+')
            .map(|i| i + after_unit)
    })?;
    let tok = speed_token(&rest[from..]);
    if tok.is_empty() {
        return None;
    }
    Some(crate::read_rpm(&tok).map_err(|e| (tok, e)))
}
