//! The arrays source: named columns already in memory (a NumPy caller's
//! arrays), handed to the reader row by row as a file's rows would be, so
//! that every rule of the reader (column roles, cycles, gaps, the axis,
//! plausibility) applies to them unchanged. Line 0 is the names; line k is
//! the k-th sample (from 1).

use crate::error::{IngestError, at};
use crate::reader::Reader;
use crate::row::Cells;
use crate::{Header, ParseOptions, Streamed};
use std::borrow::Cow;

/// The names row.
struct Names<'a>(&'a [String]);

impl Cells for Names<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        self.0.get(i).is_none_or(|s| s.trim().is_empty())
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        Cow::Borrowed(self.0.get(i).map_or("", String::as_str))
    }
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        Err(at(line, Some(i + 1), "a name, not a number"))
    }
}

/// One sample of every column: a value that is not finite (NaN, ±inf) is
/// an error at its sample and column, as an unreadable cell is.
struct Sample(Vec<f64>);

impl Cells for Sample {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn is_blank(&self, i: usize) -> bool {
        i >= self.0.len()
    }
    fn text(&self, i: usize) -> Cow<'_, str> {
        Cow::Owned(self.0.get(i).map(|v| v.to_string()).unwrap_or_default())
    }
    fn number(&self, i: usize, line: usize) -> Result<f64, IngestError> {
        match self.0.get(i) {
            Some(v) if v.is_finite() => Ok(*v),
            Some(v) => Err(at(
                line,
                Some(i + 1),
                format!(
                    "{v} is not a finite number: drop the samples where a value is missing (from every array alike: a gap up to max_gap_deg is bridged), or give each sample's cycle (cycle=) so that a dropout's cycle is left out"
                ),
            )),
            None => Err(at(line, Some(i + 1), "no value")),
        }
    }
}

/// Hands `columns` (all of one length), named by `names`, to the reader.
pub(crate) fn read<F: FnMut(Streamed) -> Result<(), IngestError>>(
    names: &[String],
    columns: &[&[f64]],
    opts: &ParseOptions,
    sink: F,
) -> Result<Header, IngestError> {
    if names.len() != columns.len() {
        return Err(IngestError::Data(format!(
            "{} names for {} columns",
            names.len(),
            columns.len()
        )));
    }
    let n = columns.first().map_or(0, |c| c.len());
    if let Some((k, c)) = columns.iter().enumerate().find(|(_, c)| c.len() != n) {
        return Err(IngestError::Data(format!(
            "column `{}` has {} values, `{}` has {n}: the columns must be of one length",
            names[k],
            c.len(),
            names[0]
        )));
    }
    let mut rd = Reader::new(opts, sink);
    rd.names_given = true;
    rd.row(0, &Names(names), || None)?;
    // Handed over as columns (slices of the caller's, no copy), a block of
    // rows at a time (the reader takes runs that continue a cycle whole; a
    // row it stops at is read as the cells of `Sample`, as every row was
    // before), cancellable between blocks.
    let mut start = 0;
    while start < n {
        opts.cancel.check()?;
        let end = (start + BLOCK_ROWS).min(n);
        let cols: Vec<&[f64]> = columns.iter().map(|c| &c[start..end]).collect();
        let cols = &*cols;
        rd.columns(start + 1, cols, end - start, |r| {
            Sample(cols.iter().map(|c| c[r]).collect())
        })?;
        start = end;
    }
    rd.end()
}

/// Rows handed to the reader at a time (the cancellation's granularity).
const BLOCK_ROWS: usize = 65_536;

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain definition: every sample handed over as its own row, as
    /// the reader read arrays before they went as columns.
    fn by_rows(
        names: &[String],
        columns: &[&[f64]],
        opts: &ParseOptions,
    ) -> Result<(Header, Vec<String>), IngestError> {
        let mut got = Vec::new();
        let mut rd = Reader::new(opts, |s: Streamed| {
            got.push(format!("{:?} {:?} {:?}", s.trace, s.quantity, s.steps));
            Ok(())
        });
        rd.names_given = true;
        rd.row(0, &Names(names), || None)?;
        for k in 0..columns[0].len() {
            let row: Vec<f64> = columns.iter().map(|c| c[k]).collect();
            rd.row(k + 1, &Sample(row), || None)?;
        }
        let h = rd.end()?;
        Ok((h, got))
    }

    fn by_columns(
        names: &[String],
        columns: &[&[f64]],
        opts: &ParseOptions,
    ) -> Result<(Header, Vec<String>), IngestError> {
        let mut got = Vec::new();
        let h = read(names, columns, opts, |s: Streamed| {
            got.push(format!("{:?} {:?} {:?}", s.trace, s.quantity, s.steps));
            Ok(())
        })?;
        Ok((h, got))
    }

    /// Arrays read as columns give what they gave row by row, on data
    /// shaped against the shortcut: a record across the block boundary, a
    /// cycle column that changes inside a block and at its edge, a NaN in
    /// the middle (the same error, at the same sample and column), an
    /// angle that steps back, a gap.
    #[test]
    fn columns_read_as_the_rows_did() {
        let opts = ParseOptions::new(720.0);
        let names: Vec<String> = ["crank_deg", "pressure_bar", "cycle"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let n = BLOCK_ROWS + 7_300;
        let step = 0.1;
        let per_cycle = 7_200;
        let angle: Vec<f64> = (0..n)
            .map(|k| (k % per_cycle) as f64 * step - 360.0)
            .collect();
        let pressure: Vec<f64> = (0..n)
            .map(|k| 1.0 + 40.0 * (-(((k % per_cycle) as f64 * step - 360.0) / 30.0).powi(2)).exp())
            .collect();
        let cycle: Vec<f64> = (0..n).map(|k| (k / per_cycle) as f64).collect();
        let mut cases: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> =
            vec![(angle.clone(), pressure.clone(), cycle.clone())];
        let mut nan = pressure.clone();
        nan[BLOCK_ROWS + 11] = f64::NAN;
        cases.push((angle.clone(), nan, cycle.clone()));
        let mut back = angle.clone();
        back[BLOCK_ROWS - 1] -= 5.0;
        cases.push((back, pressure.clone(), cycle.clone()));
        let mut gap_a = angle.clone();
        let mut gap_p = pressure.clone();
        let mut gap_c = cycle.clone();
        for v in [&mut gap_a, &mut gap_p, &mut gap_c] {
            v.drain(100..130);
        }
        cases.push((gap_a, gap_p, gap_c));
        for (k, (a, p, c)) in cases.iter().enumerate() {
            let cols: [&[f64]; 3] = [a, p, c];
            let rows = by_rows(&names, &cols, &opts);
            let columns = by_columns(&names, &cols, &opts);
            if k == 0 {
                let traces = rows.as_ref().map(|(_, t)| t.len());
                assert!(matches!(traces, Ok(t) if t >= 10), "{traces:?}");
            }
            if k == 1 {
                assert!(rows.is_err(), "a NaN is refused");
            }
            assert_eq!(format!("{rows:?}"), format!("{columns:?}"), "case {k}");
        }
    }
    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// The blocks of rows the columns' fast path checks at once
        /// (`fast::long_columns`) stop where the rows would: one sample
        /// spoiled anywhere in a block (any place in it), each way a row
        /// can stop the run.
        #[test]
        fn a_spoiled_sample_stops_the_columns_where_it_stops_the_rows(
            at in 0usize..400,
            how in 0usize..9,
            with_cycle in proptest::bool::ANY,
        ) {
            let opts = ParseOptions::new(720.0);
            let mut names = vec!["crank_deg".to_string(), "pressure_bar".to_string()];
            if with_cycle {
                names.push("cycle".into());
            }
            let n = 7_400;
            let mut a: Vec<f64> = (0..n).map(|k| (k % 7_200) as f64 * 0.1 - 360.0).collect();
            let mut p: Vec<f64> = (0..n).map(|k| 2.0 + ((k % 7_200) as f64 * 1e-3).sin()).collect();
            let mut c: Vec<f64> = (0..n).map(|k| (k / 7_200) as f64).collect();
            let k = 100 + at;
            match how {
                0 => p[k] = f64::NAN,
                1 => p[k] = f64::INFINITY,
                2 => a[k] = f64::NAN,
                3 => a[k] = f64::NEG_INFINITY,
                4 => a[k] = a[k - 1],
                5 => a[k] = a[k - 1] + 800.0,
                6 => c[k] = 7.0,
                7 => p[k] = -f64::INFINITY,
                _ => a[k] -= 0.05,
            }
            let mut cols: Vec<&[f64]> = vec![&a, &p];
            if with_cycle {
                cols.push(&c);
            }
            let rows = by_rows(&names, &cols, &opts);
            let columns = by_columns(&names, &cols, &opts);
            proptest::prop_assert_eq!(format!("{rows:?}"), format!("{columns:?}"));
        }
    }

    /// A measured-like fixture's columns (a CSV of numbers under a header).
    fn fixture(name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
        let path = format!(
            "{}/../../tests/fixtures/measured/{name}",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(&path).unwrap();
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let names: Vec<String> = lines
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect();
        let mut cols = vec![Vec::new(); names.len()];
        for l in lines {
            for (c, v) in cols.iter_mut().zip(l.split(',')) {
                c.push(v.trim().parse::<f64>().unwrap());
            }
        }
        (names, cols)
    }

    /// Time records read as columns (their samples straight into the crank
    /// signal's state machine) give what they gave row by row, for each
    /// kind of crank signal, on data shaped against the shortcut: a NaN in
    /// the pressure, in the pulse and in the encoder column (the same error
    /// at the same sample and column), a time that does not rise, a record
    /// across the block boundary.
    #[test]
    fn time_records_read_by_columns_as_by_rows() {
        let mut encoder = ParseOptions::new(720.0);
        encoder.encoder_ppr = Some(360);
        let mut pulse = ParseOptions::new(720.0);
        pulse.gain_bar_per_v = Some(20.0);
        pulse.relative = true;
        let mut clock = pulse.clone();
        clock.rpm = Some(1000.0);
        clock.tdc_time = Some(0.0123);
        let cases = [
            ("daq_100khz_encoder_360.csv", encoder),
            ("daq_72khz_tdc.csv", pulse),
            ("daq_72khz_time_ms.csv", clock),
        ];
        for (name, opts) in cases {
            let (names, cols) = fixture(name);
            let n = cols[0].len();
            let mut variants = vec![("as written".to_string(), cols.clone())];
            for c in 1..cols.len() {
                let mut v = cols.clone();
                v[c][n / 2] = f64::NAN;
                variants.push((format!("NaN in column {}", c + 1), v));
            }
            let mut back = cols.clone();
            back[0][n / 3] = back[0][n / 3 - 2];
            variants.push(("time steps back".into(), back));
            // Longer than a block: the record twice over, the time running on.
            let mut long = cols.clone();
            let span = cols[0][n - 1] - cols[0][0] + (cols[0][1] - cols[0][0]);
            while long[0].len() <= BLOCK_ROWS {
                let shift = long[0][long[0].len() - 1] - cols[0][0] + span / n as f64;
                for (k, c) in long.iter_mut().enumerate() {
                    let more: Vec<f64> = cols[k]
                        .iter()
                        .map(|v| if k == 0 { v + shift } else { *v })
                        .collect();
                    c.extend(more);
                }
            }
            variants.push(("across a block".into(), long));
            for (what, v) in &variants {
                let refs: Vec<&[f64]> = v.iter().map(Vec::as_slice).collect();
                let rows = by_rows(&names, &refs, &opts);
                let columns = by_columns(&names, &refs, &opts);
                if what == "as written" {
                    assert!(
                        matches!(&rows, Ok((_, t)) if !t.is_empty()),
                        "{name}: {rows:?}"
                    );
                }
                assert_eq!(
                    format!("{rows:?}"),
                    format!("{columns:?}"),
                    "{name}, {what}"
                );
            }
        }
    }
}
