//! The reader: rows of cells from a source, in three phases (the preamble of
//! titles and banners, the header, the data), into finished traces for the
//! grid. The source (text or spreadsheet) hands it rows; the column resolver
//! says what the columns hold; the layout turns rows into traces; the
//! emitter checks each finished trace and applies the gap rule.

use crate::columns::{Axis, Roles, expand};
use crate::error::{IngestError, at};
use crate::layout::Layout;
use crate::row::Cells;
use crate::trace::{self, Checked, Gap};
use crate::{Header, ParseOptions, Quantity, Streamed, Trace};

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
        }
    }

    /// A comment line (`#` …): a speed line is read, anything else skipped.
    pub(crate) fn comment(&mut self, line: usize, text: &str) -> Result<(), IngestError> {
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
                cells.measured(&self.measured, line)?;
                layout.row(line, cells, &mut self.out)
            }
            Phase::Preamble(text) => {
                if cells.is_data() {
                    let text = std::mem::take(text);
                    let layout = self.start(line, cells, text)?;
                    self.phase = Phase::Data(Box::new(layout));
                    let Phase::Data(layout) = &mut self.phase else {
                        return Ok(());
                    };
                    cells.measured(&self.measured, line)?;
                    return layout.row(line, cells, &mut self.out);
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
        let (roles, header_at) = match &self.opts.columns {
            Some(given) => {
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
                let roles = Roles::resolve(&names, true, line, self.opts.torque)?;
                (roles, text.len().checked_sub(1))
            }
            None => header(&text, k, line, self.opts.torque)?,
        };
        // Lines above the header: titles and banners.
        let banner = header_at.map_or(0, |h| h);
        if banner > 0 {
            let first = text[0].raw.clone();
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
                && let Some((r, at_line)) = text[..banner]
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
        if let Some(h) = header_at.and_then(|h| text.get(h))
            && let Some(e) = side_table(&h.cells)
        {
            let names: Vec<String> = h.cells[e..]
                .iter()
                .filter(|c| !c.trim().is_empty())
                .take(4)
                .map(|c| format!("`{}`", enginedyn_numerics::format::quote(c)))
                .collect();
            self.head.notes.push(format!(
                "columns {} to {} ({}{}) lie right of the empty column {}: a side table, left out",
                e + 2,
                h.cells.len(),
                names.join(", "),
                if h.cells[e..].iter().filter(|c| !c.trim().is_empty()).count() > 4 {
                    ", …"
                } else {
                    ""
                },
                e + 1
            ));
        }
        if let Some(n) = &roles.note {
            self.head.notes.push(n.clone());
        }
        if roles.values.len() > 1 {
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
        self.out.labels = roles.labels.clone();
        self.out.volts = roles.volts;
        self.out.time = matches!(roles.axis, Axis::Time(_));
        self.head.quantity = roles.quantity;
        self.head.pv = matches!(roles.axis, Axis::Volume(_));
        self.measured = roles.values.iter().map(|v| v.col).collect();
        if matches!(roles.axis, Axis::Angle(_) | Axis::Volume(_)) {
            self.measured.push(roles.x);
        }
        // Volts are relative, so `value_scale` refuses them unless pegged:
        // `opts.relative` alone says whether traces are checked for sign.
        Layout::new(
            roles,
            self.opts,
            self.head.rpm.map(|r| (r, self.rpm_source)),
            line,
        )
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
            Phase::Data(layout) => (*layout).end(&mut self.out, &mut self.head)?,
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
) -> Result<(Roles, Option<usize>), IngestError> {
    let Some(last) = text.len().checked_sub(1) else {
        return Err(at(
            line,
            None,
            if k > 2 {
                format!(
                    "no header row: name the columns with --columns (here {k} of them: crank_deg,pressure_bar... reads the angle and one cycle per column; `_` skips a column), or add a header"
                )
            } else {
                "no header row: name the columns with --columns crank_deg,pressure_bar (or add a header)".to_string()
            },
        ));
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
            && let Ok(r) = Roles::resolve(
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
    let first_try = Roles::resolve(&names, false, text[last].line, torque);
    if let Ok(r) = first_try {
        check(&names, text[last].line)?;
        return Ok((r, Some(last)));
    }
    if last > 0 {
        // Names, then units on the next row.
        let (a, b) = (fit(&text[last - 1]), fit(&text[last]));
        if a.len() == b.len() {
            let joined = join_units(&a, &b);
            if let Ok(r) = Roles::resolve(&joined, false, text[last - 1].line, torque) {
                check(&joined, text[last - 1].line)?;
                return Ok((r, Some(last - 1)));
            }
        }
        if let Ok(r) = Roles::resolve(&a, false, text[last - 1].line, torque) {
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

/// Checks each finished trace and hands it on, applying the gap rule: a
/// single cycle (per cylinder) with a gap is held to the end and bridged up
/// to `--max-gap`; once a cylinder has several cycles, those with a gap are
/// left out of the averages.
pub(crate) struct Emitter<'o, F> {
    opts: &'o ParseOptions,
    sink: F,
    /// Pressures must be absolute (not to be pegged): checked for sign.
    absolute: bool,
    pv_notes: Vec<String>,
    /// Per cylinder (0: one trace for all): traces seen and handed on.
    seen: Vec<(usize, usize)>,
    held: Vec<Option<(Trace, Checked, Quantity, usize)>>,
    /// Cycles left out: (cycle, cylinder, the gap).
    skipped: Vec<(i64, i64, Gap)>,
    bridged: Vec<(String, Gap)>,
    /// Samples below zero, traces with any, the lowest (Pa).
    below: (usize, usize, f64),
    /// Traces whose mean around intake BDC is below [`LOW_INTAKE_PA`], and
    /// the lowest such mean (Pa).
    low_intake: (usize, f64),
    total: usize,
    /// The value columns as messages name them (`Roles::labels`).
    pub labels: Vec<String>,
    /// The values are volts times `--gain`.
    pub volts: bool,
    /// The traces are p–V data (placed on angles by volume).
    pv: bool,
    /// The traces come from a time record (its own firing-TDC rule).
    pub time: bool,
    /// Where each trace's firing TDC lies (the 360° rule, the cylinders' axis).
    aligner: crate::axis::Aligner,
}

impl<'o, F: FnMut(Streamed) -> Result<(), IngestError>> Emitter<'o, F> {
    fn new(opts: &'o ParseOptions, sink: F) -> Self {
        Self {
            opts,
            sink,
            absolute: !opts.relative,
            pv_notes: Vec::new(),
            seen: Vec::new(),
            held: Vec::new(),
            skipped: Vec::new(),
            bridged: Vec::new(),
            below: (0, 0, 0.0),
            low_intake: (0, f64::INFINITY),
            total: 0,
            labels: Vec::new(),
            volts: false,
            pv: false,
            time: false,
            aligner: crate::axis::Aligner::new(opts),
        }
    }

    /// A finished trace, its first line, what it holds, whether p–V.
    pub(crate) fn trace(
        &mut self,
        tr: Trace,
        line: usize,
        q: Quantity,
        pv: bool,
        value: usize,
    ) -> Result<(), IngestError> {
        let opts = self.opts;
        self.pv = pv;
        let tr = if pv {
            let cyl = opts.cylinder.as_ref().ok_or_else(|| {
                IngestError::Data("p–V data needs the engine's volume law".into())
            })?;
            crate::pv::to_angles(
                tr,
                cyl,
                opts.cycle_deg,
                opts.pv_start_bdc,
                line,
                &mut self.pv_notes,
            )?
        } else {
            tr
        };
        // A trace's errors name the line it starts on.
        let ctx = crate::plausible::Context {
            column: self
                .labels
                .get(value)
                .map_or("the pressure column", String::as_str),
            gain: opts.gain_bar_per_v.filter(|_| self.volts),
            absolute: self.absolute,
            gauge: opts.gauge,
        };
        let (mut tr, mut c) = trace::finish(tr, opts.cycle_deg, q, &ctx).map_err(|e| match e {
            IngestError::Data(m) => at(line, None, m),
            e => e,
        })?;
        if self
            .aligner
            .align(&mut tr, q, self.time, pv)
            .map_err(|e| match e {
                IngestError::Data(m) => at(line, None, m),
                e => e,
            })?
        {
            // Moved: its steps now include the joined ends.
            c.steps = None;
        }
        if self.absolute
            && q == Quantity::Pressure
            && !pv
            && let Some(m) = crate::grid::intake_bdc_mean(
                tr.angle_deg.iter().copied().zip(tr.values.iter().copied()),
                opts.cycle_deg,
            )
            && m < LOW_INTAKE_PA
        {
            self.low_intake.0 += 1;
            self.low_intake.1 = self.low_intake.1.min(m);
        }
        if c.below_zero.0 > 0 {
            self.below.0 += c.below_zero.0;
            self.below.1 += 1;
            self.below.2 = self.below.2.min(c.below_zero.1);
        }
        self.total += 1;
        let k = usize::try_from(tr.cylinder).unwrap_or(0);
        if self.seen.len() <= k {
            self.seen.resize(k + 1, (0, 0));
            self.held.resize_with(k + 1, || None);
        }
        self.seen[k].0 += 1;
        if self.seen[k].0 == 2
            && let Some((t, c, _, _)) = self.held[k].take()
            && let Some(g) = c.gap
        {
            self.skipped.push((t.cycle, t.cylinder, g));
        }
        match c.gap {
            Some(_) if self.seen[k].0 == 1 => {
                self.held[k] = Some((tr, c, q, line));
                Ok(())
            }
            Some(g) => {
                self.skipped.push((tr.cycle, tr.cylinder, g));
                Ok(())
            }
            None => self.send(tr, c, q),
        }
    }

    /// A single cycle's gap wider than `--max-gap`: where it is, and the
    /// `--max-gap` that bridges it, when the flag's bound allows one.
    fn gap_error(&self, tr: &Trace, g: trace::Gap, line: usize) -> IngestError {
        let cycle = self.opts.cycle_deg;
        let max_gap = self.opts.max_gap_deg;
        let needed = g.width.ceil();
        let now = if (max_gap - crate::MAX_GAP_DEG).abs() < 1e-9 {
            format!("the default --max-gap bridges gaps up to {}°", fmt(max_gap))
        } else {
            format!(
                "--max-gap {} bridges gaps up to {}° (the default: {}°)",
                fmt(max_gap),
                fmt(max_gap),
                fmt(crate::MAX_GAP_DEG)
            )
        };
        let hint = if needed <= crate::MAX_GAP_BOUND_DEG {
            format!("{now}; --max-gap {} would bridge this one", fmt(needed))
        } else {
            format!(
                "that is less than half the cycle, which no --max-gap bridges (its bound is {}°): is the file cut short?",
                fmt(crate::MAX_GAP_BOUND_DEG)
            )
        };
        // The gap's own line: one sample a row from the trace's first line
        // (p–V data is reordered by volume, so it names the first line).
        let gap_line = if self.pv { line } else { line + g.at };
        at(
            gap_line,
            None,
            format!(
                "{} has a gap of {}° from {}° to {}° (its steps are {}°): the data covers {}° of the {}° cycle; {hint}",
                trace::describe(tr.cycle, tr.cylinder),
                fmt(g.width),
                fmt(g.from),
                fmt((g.from + g.width) % cycle),
                fmt(g.median),
                fmt(cycle - g.width),
                fmt(cycle),
            ),
        )
    }

    fn send(&mut self, tr: Trace, c: Checked, q: Quantity) -> Result<(), IngestError> {
        let k = usize::try_from(tr.cylinder).unwrap_or(0);
        self.seen[k].1 += 1;
        (self.sink)(Streamed {
            trace: tr,
            quantity: q,
            steps: c.steps,
        })
    }

    fn end(&mut self, head: &mut Header) -> Result<(), IngestError> {
        let max_gap = self.opts.max_gap_deg;
        for k in 0..self.held.len() {
            let Some((tr, c, q, line)) = self.held[k].take() else {
                continue;
            };
            let Some(g) = c.gap else { continue };
            if g.width > max_gap + 1e-9 {
                return Err(self.gap_error(&tr, g, line));
            }
            self.bridged
                .push((trace::describe(tr.cycle, tr.cylinder), g));
            self.send(tr, c, q)?;
        }
        for (k, (seen, sent)) in self.seen.iter().enumerate() {
            if *seen > 0 && *sent == 0 {
                return Err(IngestError::Data(format!(
                    "every one of the {seen} cycles{} has a gap (a spacing of more than 5 median steps): none is left to average",
                    if k > 0 {
                        format!(" of cylinder {k}")
                    } else {
                        String::new()
                    }
                )));
            }
        }
        if let Some((name, g)) = self.bridged.first() {
            head.notes.push(format!(
                "{name} has a gap of {}° from {}° (its steps are {}°){}: bridged by the interpolant (--max-gap {}°); the pressure there is its guess, and peak pressure and IMEP are uncertain by what the gap hides",
                fmt(g.width),
                fmt(g.from),
                fmt(g.median),
                if self.bridged.len() > 1 { format!(", and {} more traces have one", self.bridged.len() - 1) } else { String::new() },
                fmt(max_gap)
            ));
        }
        if let Some((cycle, cylinder, g)) = self
            .skipped
            .iter()
            .max_by(|a, b| a.2.width.total_cmp(&b.2.width))
            .cloned()
        {
            head.notes.push(format!(
                "{} of {} cycles left out of the averages for {GAP} ({DROPOUT}; the widest: {}, {}° from {}°)",
                self.skipped.len(),
                self.total,
                trace::describe(cycle, cylinder),
                fmt(g.width),
                fmt(g.from)
            ));
            head.cycles_skipped = self.skipped.len();
            head.skipped = self
                .skipped
                .iter()
                .map(|&(cycle, cylinder, g)| crate::SkippedCycle {
                    cylinder,
                    cycle,
                    reason: format!("{GAP} ({DROPOUT}): {}° from {}°", fmt(g.width), fmt(g.from)),
                })
                .collect();
        }
        if self.below.0 > 0 {
            head.notes.push(format!(
                "{} sample{} below zero absolute pressure (lowest {} bar){}: kept, as sensor noise or drift in the gas exchange",
                self.below.0,
                if self.below.0 > 1 { "s" } else { "" },
                enginedyn_numerics::format::sig(self.below.2 / 1e5, 3),
                if self.total > 1 { format!(" in {} of {} traces", self.below.1, self.total) } else { String::new() }
            ));
        }
        if self.low_intake.0 > 0 {
            head.notes.push(format!(
                "the pressure around intake BDC averages {} bar absolute{}, below the {} bar an engine's intake holds: gauge data (relative to the atmosphere) read as absolute? give --gauge, or peg a relative trace (--peg-bar P)",
                enginedyn_numerics::format::sig(self.low_intake.1 / 1e5, 3),
                if self.total > 1 {
                    format!(" (lowest) in {} of {} traces", self.low_intake.0, self.total)
                } else {
                    String::new()
                },
                enginedyn_numerics::format::human(LOW_INTAKE_PA / 1e5)
            ));
        }
        head.notes.append(&mut self.pv_notes);
        head.notes.extend(self.aligner.notes());
        Ok(())
    }
}

/// Why a cycle is left out of the averages: the note on the skipped cycles
/// and each cycle's `skip_reason` (the `cycles` table) say it in these words.
const GAP: &str = "a gap in the data";
/// What such a gap is.
const DROPOUT: &str = "a dropout: a spacing of more than 5 median steps";

/// The lowest mean absolute pressure around intake BDC (Pa) a running
/// engine's intake holds: below it the trace is likely gauge data.
const LOW_INTAKE_PA: f64 = 0.2e5;

fn fmt(x: f64) -> String {
    enginedyn_numerics::format::trimmed(x, 2)
}
