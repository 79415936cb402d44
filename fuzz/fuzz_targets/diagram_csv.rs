//! Fuzzes the indicator-diagram CSV reader: any bytes go to
//! `enginedyn_ingest::parse` under every combination of cycle (720°, 360°),
//! gauge pressure (off, on), TDC offset (0°, 123.4°) and `--columns`
//! (none, `crank_deg,pressure_bar`). Whatever parses is resampled to a 1°
//! grid with `Interp::Auto`.
//!
//! The contract: no panic, and no NaN or infinity out of either function
//! (bad input is an error). A crash here is a bug in `crates/ingest`.

#![no_main]

use enginedyn_ingest::{Interp, ParseOptions, parse, resample};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for cycle in [720.0, 360.0] {
        for gauge in [false, true] {
            for tdc in [0.0, 123.4] {
                for columns in [false, true] {
                    let mut opts = ParseOptions::new(cycle);
                    opts.gauge = gauge;
                    opts.tdc_deg = tdc;
                    if columns {
                        opts.columns = Some(vec!["crank_deg".into(), "pressure_bar".into()]);
                    }
                    check(data, &opts);
                }
            }
        }
    }
});

/// Parses `data` with `opts` and, when that succeeds, resamples to 1° and
/// asserts that the grid is complete and finite.
fn check(data: &[u8], opts: &ParseOptions) {
    let Ok(diagram) = parse(data, opts) else {
        return;
    };
    let Ok(r) = resample(&diagram, 1.0, Interp::Auto) else {
        return;
    };
    let n = (opts.cycle_deg / 1.0).round() as usize;
    assert_eq!(r.pressure.len(), n, "grid length with {opts:?}");
    if let Some(k) = r.pressure.iter().position(|p| !p.is_finite()) {
        panic!(
            "resample gave {} at {k}° with {opts:?} ({:?}, {} traces)",
            r.pressure[k],
            diagram.quantity,
            diagram.traces.len()
        );
    }
}
