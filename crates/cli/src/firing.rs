//! `enginedyn firing-orders` (INTERFACE.md).

use crate::Failure;
use crate::args::FiringOrdersArgs;

/// Runs `enginedyn firing-orders`.
pub fn run(_a: &FiringOrdersArgs) -> Result<(), Failure> {
    Err(Failure::usage(
        "`enginedyn firing-orders` is not implemented yet",
    ))
}
