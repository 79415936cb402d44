//! Engine-free numerics for enginedyn: periodic interpolation (linear, cubic
//! spline, monotone cubic), integration rules, root finding and harmonic
//! analysis. Nothing here knows about engines; everything works on plain
//! slices of `f64`.
//!
//! ```
//! use enginedyn_numerics::{InterpKind, Periodic};
//! // A periodic spline through samples of cos(x) on [0, 2pi).
//! let n = 32;
//! let xs: Vec<f64> = (0..n).map(|k| k as f64 * std::f64::consts::TAU / n as f64).collect();
//! let ys: Vec<f64> = xs.iter().map(|x| x.cos()).collect();
//! let f = Periodic::new(InterpKind::Spline, &xs, &ys, std::f64::consts::TAU).unwrap();
//! assert!((f.eval(1.0) - 1.0_f64.cos()).abs() < 1e-5);
//! ```

mod error;
pub mod fourier;
pub mod integrate;
pub mod interp;
pub mod roots;

pub use error::NumericsError;
pub use interp::{InterpKind, Periodic};
