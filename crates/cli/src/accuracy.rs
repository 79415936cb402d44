//! `enginedyn accuracy` (INTERFACE.md).

use crate::Failure;
use crate::args::AccuracyArgs;

/// Runs `enginedyn accuracy`.
pub fn run(_a: &AccuracyArgs) -> Result<(), Failure> {
    Err(Failure::usage(
        "`enginedyn accuracy` is not implemented yet",
    ))
}
