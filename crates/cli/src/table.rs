//! The printed tables' heading, now `enginedyn_report::heading`: this
//! re-export stays only until `batch.rs` (being edited beside this change)
//! calls `enginedyn_report::heading` itself; then this file goes.

pub use enginedyn_report::heading;
