//! The integration tests of this crate, one module a file, linked as one
//! test binary (`cargo test --test all`): one link instead of one a file,
//! which is most of a debug test build's time. A new file in this folder
//! gets a `mod` line here; `tests/tests/layout.rs` checks that none is
//! left out.

mod burn_rules;
mod campaign;
mod charts_tables;
mod combustion;
mod defaults;
mod design_model;
mod design_report;
mod docs;
mod firing_orders;
mod fuzz_paths;
mod glitch;
mod hostile;
mod hostile44;
mod hostile_input2;
mod inputs;
mod layout;
mod map_logs;
mod measured;
mod names;
mod new_user;
mod out_folders;
mod plausibility;
mod sheets_hostile;
mod split_pins;
mod stale_outputs;
mod synth;
mod template;
mod tolerance;
mod torsion_bounds;
mod torsion_peaks;
