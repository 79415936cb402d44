//! `enginedyn tolerance` (INTERFACE.md).

use crate::Failure;
use crate::args::ToleranceArgs;

/// Runs `enginedyn tolerance`.
pub fn run(_a: &ToleranceArgs) -> Result<(), Failure> {
    Err(Failure::usage(
        "`enginedyn tolerance` is not implemented yet",
    ))
}
