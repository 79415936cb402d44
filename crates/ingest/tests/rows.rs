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
