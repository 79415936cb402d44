//! Fuzzes `enginedyn_tests::fuzz::diagram_stream` (see that module): the path the
//! CLI takes, with the checks the stable property tests of
//! `tests/tests/fuzz_paths.rs` run in CI.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The first two bytes pick the CLI option combination.
    if let [pick, more, rest @ ..] = data {
        enginedyn_tests::fuzz::diagram_stream(rest, *pick, *more);
    }
});
