//! The integration tests of this crate, one module a file, linked as one
//! test binary (`cargo test --test all`): one link instead of one a file,
//! which is most of a debug test build's time. A new file in this folder
//! gets a `mod` line here; `tests/tests/layout.rs` checks that none is
//! left out.

mod binary_sources;
mod crank;
mod cycles_kept;
mod formats;
mod layouts;
mod mdf;
mod mdf_columns;
mod no_header;
mod no_panic;
mod pv_peg_stats;
mod rows;
mod units_named;
mod windows;
