//! The integration tests of this crate, one module a file, linked as one
//! test binary (`cargo test --test all`): one link instead of one a file,
//! which is most of a debug test build's time. A new file in this folder
//! gets a `mod` line here; `tests/tests/layout.rs` checks that none is
//! left out.

mod engine_file;
mod provenance;
mod studies;
