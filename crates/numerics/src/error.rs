//! The numerics crate's errors.

/// What a numerical routine could not do, with the offending value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NumericsError {
    /// Abscissae and values of different lengths.
    #[error("{xs} abscissae but {ys} values")]
    LengthMismatch {
        /// Number of x values.
        xs: usize,
        /// Number of y values.
        ys: usize,
    },
    /// Too few points for the method.
    #[error("{got} points: {method} needs at least {need}")]
    TooFewPoints {
        /// Points given.
        got: usize,
        /// Points needed.
        need: usize,
        /// The method or routine that needs them.
        method: &'static str,
    },
    /// A NaN or infinity in the input.
    #[error("non-finite value {what}[{index}] = {value}")]
    NonFinite {
        /// Which input holds it (`"x"`, `"y"`).
        what: &'static str,
        /// Index within that input.
        index: usize,
        /// The value.
        value: f64,
    },
    /// Abscissae not strictly increasing.
    #[error("abscissae must rise strictly: x[{index}] = {value} after {previous}")]
    NotIncreasing {
        /// Index.
        index: usize,
        /// Value at index.
        value: f64,
        /// The value before it.
        previous: f64,
    },
    /// The samples span a period or more, or the period is not a positive
    /// finite number.
    #[error(
        "samples span {span}, the period is {period}: the span must be shorter than a positive, finite period"
    )]
    Period {
        /// Span of the samples (last abscissa minus first).
        span: f64,
        /// Period.
        period: f64,
    },
    /// A scalar parameter outside its valid range.
    #[error("{name} = {value}: {why}")]
    Parameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        why: &'static str,
    },
    /// No sign change on the bracket.
    #[error("no sign change on [{a}, {b}]: f(a) = {fa}, f(b) = {fb}")]
    NoBracket {
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
        /// f(a).
        fa: f64,
        /// f(b).
        fb: f64,
    },
    /// Iteration did not converge.
    #[error("no convergence after {0} iterations")]
    NoConvergence(usize),
    /// A harmonic order that does not fit the samples.
    #[error("order {order}: {why}")]
    Order {
        /// The order asked for.
        order: f64,
        /// Why it cannot be computed.
        why: &'static str,
    },
}
