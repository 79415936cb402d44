//! A file without a header: its columns probed against the plausibility
//! pass, and the no-header error offering only the readings that fit.

use crate::error::{IngestError, at};

/// The error of a file without a header row (`k` columns, its first data
/// row on `line`). `verdicts`, when the columns were probed: for each
/// column after the first, read as `pressure_bar`, `Ok` when its traces
/// pass the plausibility pass, else why not; the hint then offers only the
/// reading that fits.
pub(crate) fn no_header(
    k: usize,
    line: usize,
    verdicts: Option<&[Result<(), String>]>,
) -> IngestError {
    let Some(v) = verdicts else {
        return at(
            line,
            None,
            if k == 1 {
                "no header row, one column of numbers: a pressure-only record sampled on the crank angle (a DAQ clocked by the encoder) reads with --angle-step DEG (the angle between rows) and --columns pressure_bar (its unit); --tdc-deg X places firing TDC on that axis".to_string()
            } else if k > 2 {
                format!(
                    "no header row: name the columns with --columns (here {k} of them: crank_deg,pressure_bar... reads the angle and one cycle per column; `_` skips a column), or add a header"
                )
            } else {
                "no header row: name the columns with --columns crank_deg,pressure_bar (or add a header)".to_string()
            },
        );
    };
    let why: Vec<String> = v
        .iter()
        .enumerate()
        .filter_map(|(j, r)| {
            // The plausibility pass names the column; other checks do not.
            r.as_ref().err().map(|m| {
                if m.starts_with("column ") {
                    m.clone()
                } else {
                    format!("column {}: {m}", j + 2)
                }
            })
        })
        .collect();
    let fit = v.iter().filter(|r| r.is_ok()).count();
    let reading = if fit == v.len() {
        if k > 2 {
            "crank_deg,pressure_bar... reads the angle and one cycle per column".to_string()
        } else {
            "crank_deg,pressure_bar reads them".to_string()
        }
    } else if fit > 0 {
        let names: Vec<&str> = std::iter::once("crank_deg")
            .chain(
                v.iter()
                    .map(|r| if r.is_ok() { "pressure_bar" } else { "_" }),
            )
            .collect();
        format!(
            "{} reads {} as cylinder pressure and skips the rest, which cannot be one",
            names.join(","),
            if fit == 1 {
                "the one column that fits"
            } else {
                "the columns that fit"
            }
        )
    } else {
        String::new()
    };
    let message = if reading.is_empty() {
        format!(
            "no header row, and no column after the first reads as a cylinder pressure in bar ({}): name the columns with --columns in their units (pressure_kpa, pressure_mpa, pressure_psi; a voltage: pressure_v with --gain), or add a header",
            why.join("; ")
        )
    } else {
        format!(
            "no header row: name the columns with --columns (here {k} of them: {reading}; `_` skips a column), or add a header{}",
            if why.is_empty() {
                String::new()
            } else {
                format!(" ({})", why.join("; "))
            }
        )
    };
    at(line, None, message)
}

/// A file without a header, its columns read as `crank_deg,pressure_bar...`
/// only to judge each against the plausibility pass; nothing is handed on.
/// Memory: one cycle of every column, as for one cycle per column.
pub(crate) struct Probe {
    /// The first data row.
    pub(crate) line: usize,
    /// The file's columns.
    pub(crate) k: usize,
    /// Per value column: its first trace's verdict, once it has one.
    pub(crate) verdicts: Vec<Option<Result<(), String>>>,
    /// Every column judged: the error is the hint.
    pub(crate) done: bool,
    /// Data rows read.
    pub(crate) rows: usize,
}

/// The most values a probe of a headerless file reads before it gives the
/// plain hint (32 MiB: a 720-row cycle of 5,800 columns, a 0.1° cycle of
/// 580).
pub(crate) const PROBE_VALUES: usize = 1 << 22;

impl Probe {
    /// The no-header error: with the readings that fit once every column
    /// has a verdict, else the plain one.
    pub(crate) fn error(&self) -> IngestError {
        let v: Option<Vec<Result<(), String>>> = self.verdicts.iter().cloned().collect();
        no_header(self.k, self.line, v.as_deref().filter(|_| self.done))
    }
}
