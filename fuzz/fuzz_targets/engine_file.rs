//! Fuzzes `enginedyn_tests::fuzz::engine_file` (see that module): the path the
//! CLI takes, with the checks the stable property tests of
//! `tests/tests/fuzz_paths.rs` run in CI.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    enginedyn_tests::fuzz::engine_file(data);
});
