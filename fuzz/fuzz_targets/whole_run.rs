//! Fuzzes `enginedyn_tests::fuzz::whole_run` (see that module): the path the
//! CLI takes, with the checks the stable property tests of
//! `tests/tests/fuzz_paths.rs` run in CI.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = enginedyn_tests::fuzz::whole_run(data);
});
