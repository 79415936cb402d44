//! Whatever path a row takes through the reader (the row templates, the
//! one-pass plain row, the general split-and-parse), the trace holds
//! exactly the values `str::parse` gives for its cells: every angle and
//! pressure is compared bit for bit with a reference built here, on files
//! whose rows now follow a template and now break it (irregular steps,
//! changing decimals, cells growing a digit, line ends, separators).

use enginedyn_ingest::{ParseOptions, parse};
use proptest::prelude::*;

/// Per cycle, the angles (deg) and pressures (Pa) a file must give.
type Traces = Vec<(Vec<f64>, Vec<f64>)>;

/// One generated file and the traces it must give.
#[allow(clippy::too_many_arguments)]
fn file(
    sep: char,
    cycle_column: bool,
    step_hundredths: u32,
    decimals: usize,
    cycles: usize,
    jitter: &[(usize, u32)],
    crlf: bool,
    pressure_decimals: usize,
) -> (String, Traces) {
    let point = if sep == ';' { "," } else { "." };
    let end = if crlf { "\r\n" } else { "\n" };
    let mut text = if cycle_column {
        format!("cycle{sep}crank_deg{sep}pressure_bar{end}")
    } else {
        format!("crank_deg{sep}pressure_bar{end}")
    };
    let mut traces = Vec::new();
    let n = 72000 / step_hundredths as usize;
    for c in 0..cycles {
        let (mut angles, mut values) = (Vec::new(), Vec::new());
        for k in 0..n {
            // Hundredths of a degree; a jittered row moves by a little, and
            // every so often a row shows one more decimal than the others.
            let mut h = k as u32 * step_hundredths;
            if let Some((_, d)) = jitter.iter().find(|(at, _)| *at == k) {
                h += d % step_hundredths.max(2) / 2;
            }
            let extra = usize::from(k % 997 == 5);
            let a = format!("{:.*}", decimals + extra, f64::from(h) / 100.0);
            let p_bar =
                1.0 + 80.0 * (-((k as f64 - 100.0) / 300.0).powi(2)).exp() + c as f64 * 0.37;
            let p = format!("{p_bar:.pressure_decimals$}");
            let (a_text, p_text) = (a.replace('.', point), p.replace('.', point));
            if cycle_column {
                text.push_str(&format!("{c}{sep}{a_text}{sep}{p_text}{end}"));
            } else {
                text.push_str(&format!("{a_text}{sep}{p_text}{end}"));
            }
            angles.push(a.parse::<f64>().unwrap());
            values.push(p.parse::<f64>().unwrap() * 1e5);
        }
        traces.push((angles, values));
    }
    (text, traces)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn every_path_reads_what_str_parse_reads(
        sep in prop::sample::select(vec![',', ';']),
        cycle_column in any::<bool>(),
        step_hundredths in prop::sample::select(vec![10u32, 25, 50, 100, 200]),
        extra_decimals in 0usize..2,
        cycles in 1usize..3,
        jitter in prop::collection::vec((0usize..7200, 1u32..400), 0..6),
        crlf in any::<bool>(),
        pressure_decimals in 0usize..7,
    ) {
        let needed = match step_hundredths { 10 | 50 => 1, 25 => 2, _ => 0 };
        let decimals = needed.max(usize::from(jitter.is_empty()) * extra_decimals)
            + usize::from(!jitter.is_empty()) * 2;
        let (text, want) = file(
            sep, cycle_column, step_hundredths, decimals, cycles, &jitter, crlf, pressure_decimals,
        );
        let d = parse(text.as_bytes(), &ParseOptions::new(720.0)).unwrap();
        prop_assert_eq!(d.traces.len(), want.len());
        for (t, (angles, values)) in d.traces.iter().zip(&want) {
            prop_assert_eq!(t.angle_deg.len(), angles.len());
            for k in 0..angles.len() {
                prop_assert_eq!(t.angle_deg[k].to_bits(), angles[k].to_bits(), "angle row {}", k);
                prop_assert_eq!(t.values[k].to_bits(), values[k].to_bits(), "value row {}", k);
            }
        }
    }
}

/// Every trace's angles and values, as bits.
type Bits = Vec<(Vec<u64>, Vec<u64>)>;

/// What a file reads as: every trace's angles and values (bits), or the
/// error's message.
fn read_bits(text: &str) -> Result<Bits, String> {
    let d = parse(text.as_bytes(), &ParseOptions::new(720.0)).map_err(|e| e.to_string())?;
    Ok(d.traces
        .iter()
        .map(|t| {
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect();
            (bits(&t.angle_deg), bits(&t.values))
        })
        .collect())
}

/// A hostile cell among plain rows reads (or fails, with the same line,
/// column and message) exactly as the general path reads it: the same
/// file with a space after every delimiter takes the general path for
/// every row. The cell is put where the fast paths read in words (the
/// value after a row template, the one-pass row), near the start, across
/// the 64 KiB read block's edge (the header padded byte by byte to move
/// it) and as the last row, with and without a final line end.
#[test]
fn hostile_cells_read_as_the_general_path_reads_them() {
    let mut cells: Vec<String> = [
        "",
        " ",
        "-0",
        "+5",
        ".5",
        "5.",
        "-.5",
        ".",
        "-",
        "1e3",
        "1E-3",
        "nan",
        "inf",
        "-inf",
        " 87.5",
        "87.5 ",
        "87 .5",
        "8\u{e9}",
        "\u{e9}",
        "0x10",
        "1..2",
        "1.2.3",
        "87,5",
        "\"87.5\"",
        "0000000087.14250",
        "87.14250000000000",
        "9999999.9999999",
        "99999999.99999999",
    ]
    .iter()
    .map(|c| c.to_string())
    .collect();
    for n in [1usize, 7, 8, 9, 15, 16, 17, 19, 20, 25] {
        let digits: String = (0..n).map(|k| char::from(b'1' + (k % 9) as u8)).collect();
        for p in [0, 1, n / 2, n - 1, n] {
            cells.push(format!("{}.{}", &digits[..p], &digits[p..]));
        }
        cells.push(digits);
    }
    let rows = 4000;
    let row = |k: usize, v: &str| format!("0,{:.1},{v}", k as f64 / 10.0);
    let plain = |k: usize| format!("{:.5}", 80.0 + (k % 13) as f64 * 0.123_45);
    let mut checked = 0;
    for (c, cell) in cells.iter().enumerate() {
        let end = if c % 2 == 0 { "\n" } else { "\r\n" };
        let pad = c % 17;
        let header = format!("cycle,crank_deg,pressure_bar{}{end}", " ".repeat(pad));
        // The row whose value cell straddles byte 65,536.
        let mut at = header.len();
        let edge = (0..rows)
            .find(|&k| {
                at += row(k, &plain(k)).len() + end.len();
                at > 65_536 - 4
            })
            .unwrap();
        for (hostile, last_end) in [
            (1, true),
            (200, true),
            (edge, true),
            (rows - 1, true),
            (rows - 1, false),
        ] {
            let text: String = (0..rows)
                .map(|k| {
                    let v = if k == hostile { cell.clone() } else { plain(k) };
                    let e = if k == rows - 1 && !last_end { "" } else { end };
                    format!("{}{e}", row(k, &v))
                })
                .collect();
            let text = format!("{header}{text}");
            let spaced = text.replace(',', ", ");
            let (fast, general) = (read_bits(&text), read_bits(&spaced));
            assert_eq!(fast, general, "{cell:?} in row {hostile}");
            checked += 1;
        }
    }
    assert_eq!(checked, cells.len() * 5);
}

/// The same for one cycle per column (the fast path reads every cell of a
/// row by the shape of the cell before): a hostile cell in any column,
/// the values' shapes changing between columns and rows.
#[test]
fn hostile_cells_per_column_read_as_the_general_path_reads_them() {
    let cells = [
        "",
        "-0",
        "+5",
        ".5",
        "5.",
        "1e3",
        "nan",
        " 87.5",
        "87.5 ",
        "8\u{e9}",
        "87.142501",
        "187.1425",
        "-87.14250",
        "0000000087.14250",
        "1234567890123456",
        "\"87.5\"",
    ];
    let rows = 7200;
    for (c, cell) in cells.iter().enumerate() {
        let end = if c % 2 == 0 { "\n" } else { "\r\n" };
        let mut text = format!("crank_deg,pressure_bar_1,pressure_bar_2,pressure_bar_3{end}");
        for k in 0..rows {
            let v = |j: usize| {
                if k == 1000 + 7 * c && j == c % 3 {
                    cell.to_string()
                } else if (k / 500 + j).is_multiple_of(4) {
                    format!("{:.3}", 60.0 + (k % 11) as f64 * 0.5)
                } else {
                    format!("{:.5}", 80.0 + (k % 13) as f64 * 0.123_45)
                }
            };
            text.push_str(&format!(
                "{:.1},{},{},{}{end}",
                k as f64 / 10.0,
                v(0),
                v(1),
                v(2)
            ));
        }
        let spaced = text.replace(',', ", ");
        let fast = read_bits(&text);
        if ["87.142501", "187.1425", "5.", ".5"].contains(cell) {
            assert_eq!(fast.as_ref().map(Vec::len), Ok(3), "{cell:?}");
        }
        assert_eq!(fast, read_bits(&spaced), "{cell:?}");
    }
}
