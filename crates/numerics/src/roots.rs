//! Root finding and one-dimensional minimisation (Brent's methods).

use crate::NumericsError;

/// Iteration cap of [`brent`].
pub const MAX_ITERATIONS: usize = 200;

/// Same float, bit for bit (the algorithms below test whether two of their
/// points are the very same one).
#[inline]
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits()
}

/// Brent's method (inverse quadratic interpolation, secant and bisection)
/// for a root of `f` on `[a, b]`, to the absolute tolerance `tol` in x.
///
/// `f(a)` and `f(b)` must have opposite signs, or one of them be zero (that
/// end is returned). A negative or NaN `tol` counts as zero, which asks for
/// the root to within a few ulps.
///
/// # Errors
///
/// [`NumericsError::NoBracket`] when `f(a)` and `f(b)` have the same sign
/// or either is NaN; [`NumericsError::NoConvergence`] after
/// [`MAX_ITERATIONS`] steps (possible only for an unreachable tolerance or a
/// function that is not continuous across the sign change).
///
/// ```
/// let r = enginedyn_numerics::roots::brent(|x| x * x - 2.0, 0.0, 2.0, 1e-14)?;
/// assert!((r - 2f64.sqrt()).abs() < 1e-12);
/// # Ok::<(), enginedyn_numerics::NumericsError>(())
/// ```
pub fn brent<F: FnMut(f64) -> f64>(
    mut f: F,
    a: f64,
    b: f64,
    tol: f64,
) -> Result<f64, NumericsError> {
    let tol = tol.max(0.0);
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (f(a), f(b));
    if fa == 0.0 {
        return Ok(a);
    }
    if fb == 0.0 {
        return Ok(b);
    }
    if !(fa * fb < 0.0) {
        return Err(NumericsError::NoBracket { a, b, fa, fb });
    }
    // b: best estimate; c: the other end of the bracket; a: previous b.
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..MAX_ITERATIONS {
        if fb * fc > 0.0 {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            (a, b, c) = (b, c, b);
            (fa, fb, fc) = (fb, fc, fb);
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol1 || fb == 0.0 {
            return Ok(b);
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if same(a, c) {
                // Two distinct points only: secant.
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                // Inverse quadratic interpolation through a, b, c.
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = d;
            }
        } else {
            d = m;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(m) };
        fb = f(b);
    }
    Err(NumericsError::NoConvergence(MAX_ITERATIONS))
}

/// Brent's minimisation (golden-section search accelerated by parabolic
/// interpolation) of `f` on `[a, b]` (either order) to the x tolerance
/// `tol`; returns `(x_min, f(x_min))`.
///
/// For a unimodal `f` this is the minimum on the interval (the answer may
/// sit within `tol` of an end when the minimum is at that end); otherwise a
/// local minimum. The effective tolerance is never below `√ε |x|`, as a
/// minimum cannot be located more closely in floating point. Non-finite
/// ends give `(NaN, NaN)` without calling `f`. `f` is evaluated at most 500
/// times.
///
/// ```
/// let (x, fx) = enginedyn_numerics::roots::minimize(|x| (x - 1.0).powi(2), -2.0, 5.0, 1e-10);
/// assert!((x - 1.0).abs() < 1e-7 && fx < 1e-14);
/// ```
pub fn minimize<F: FnMut(f64) -> f64>(mut f: F, a: f64, b: f64, tol: f64) -> (f64, f64) {
    if !(a.is_finite() && b.is_finite()) {
        return (f64::NAN, f64::NAN);
    }
    // 1 - 1/φ: the golden-section fraction.
    let golden = 0.5 * (3.0 - 5.0_f64.sqrt());
    let sqrt_eps = f64::EPSILON.sqrt();
    let tol = tol.max(0.0);
    let (mut a, mut b) = (a.min(b), a.max(b));
    // x: best point; w: second best; v: previous w.
    let mut x = a + golden * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = f(x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e) = (0.0_f64, 0.0_f64);
    for _ in 0..500 {
        let xm = 0.5 * (a + b);
        let tol1 = sqrt_eps * x.abs() + tol / 3.0;
        let tol2 = 2.0 * tol1;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut parabolic = false;
        if e.abs() > tol1 {
            // Parabola through x, w, v: step p / q from x.
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            let e_old = e;
            e = d;
            if p.abs() < (0.5 * q * e_old).abs() && p > q * (a - x) && p < q * (b - x) {
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = tol1.copysign(xm - x);
                }
                parabolic = true;
            }
        }
        if !parabolic {
            e = if x >= xm { a - x } else { b - x };
            d = golden * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else {
            x + tol1.copysign(d)
        };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv) = (w, fw);
            (w, fw) = (x, fx);
            (x, fx) = (u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || same(w, x) {
                (v, fv) = (w, fw);
                (w, fw) = (u, fu);
            } else if fu <= fv || same(v, x) || same(v, w) {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The root of x² - 2 is √2 (analytic), to 1e-12; ends in either order.
    #[test]
    fn brent_sqrt2() {
        for (a, b) in [(0.0, 2.0), (2.0, 0.0), (1.0, 100.0)] {
            let r = brent(|x| x * x - 2.0, a, b, 1e-14).unwrap();
            assert!((r - 2.0_f64.sqrt()).abs() < 1e-12, "[{a}, {b}]: {r}");
        }
        // Zero tolerance: to a few ulps.
        let r = brent(|x| x * x - 2.0, 0.0, 2.0, 0.0).unwrap();
        assert!((r - 2.0_f64.sqrt()).abs() < 1e-15);
    }

    /// Roots of cos (π/2, analytic) and of x³ - x - 1 (the plastic number
    /// 1.324717957244746, OEIS A060006), within the requested tolerance.
    #[test]
    fn brent_other_roots() {
        let r = brent(f64::cos, 0.0, 3.0, 1e-13).unwrap();
        assert!((r - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let r = brent(|x| x * x * x - x - 1.0, 1.0, 2.0, 1e-13).unwrap();
        assert!((r - 1.324_717_957_244_746).abs() < 1e-12);
        // A coarse tolerance is honoured too.
        let r = brent(|x| x * x - 2.0, 0.0, 2.0, 1e-3).unwrap();
        assert!((r - 2.0_f64.sqrt()).abs() < 1e-3);
        // A zero at an end is returned as is.
        assert!((brent(|x| x - 1.0, 1.0, 5.0, 1e-12).unwrap() - 1.0).abs() < 1e-300);
        assert!((brent(|x| x - 5.0, 1.0, 5.0, 1e-12).unwrap() - 5.0).abs() < 1e-300);
    }

    #[test]
    fn brent_errors() {
        let e = brent(|x| x * x + 1.0, 0.0, 2.0, 1e-12).unwrap_err();
        assert_eq!(
            e,
            NumericsError::NoBracket {
                a: 0.0,
                b: 2.0,
                fa: 1.0,
                fb: 5.0
            }
        );
        assert!(e.to_string().contains("f(b) = 5"), "{e}");
        let e = brent(|_| f64::NAN, 0.0, 2.0, 1e-12).unwrap_err();
        assert!(matches!(e, NumericsError::NoBracket { .. }), "{e}");
        // A jump across zero at x = 0 with f never zero and zero tolerance:
        // the bracket halves towards 0 from both sides and needs ~1000
        // halvings to meet, more than the cap.
        let step = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
        let e = brent(step, -1.0, 1.0, 0.0).unwrap_err();
        assert_eq!(e, NumericsError::NoConvergence(MAX_ITERATIONS));
    }

    /// Minimum of (x - 1)² + 3 at x = 1, value 3 (analytic). A minimum is
    /// only located to about √ε in x (1e-7); the value to rounding (1e-14).
    #[test]
    fn minimum_of_parabola() {
        for (a, b) in [(-2.0, 5.0), (5.0, -2.0), (0.99, 1.02)] {
            let (x, fx) = minimize(|x| (x - 1.0).powi(2) + 3.0, a, b, 1e-10);
            assert!((x - 1.0).abs() < 1e-7, "{x}");
            assert!((fx - 3.0).abs() < 1e-14, "{fx}");
        }
    }

    /// Other shapes: a kink (|x - 0.3|, min 0 at 0.3), a quartic (flat
    /// bottom: x only to ε^(1/4)), the minimum of cos on [2, 5] at π (value
    /// -1), and a monotone function whose minimum is the interval's end.
    #[test]
    fn minimum_other_shapes() {
        let (x, fx) = minimize(|x| (x - 0.3).abs(), -1.0, 2.0, 1e-10);
        assert!((x - 0.3).abs() < 1e-8 && fx < 1e-8, "{x} {fx}");
        let (x, fx) = minimize(|x| (x - 2.0).powi(4), 0.0, 3.0, 1e-10);
        assert!((x - 2.0).abs() < 1e-3 && fx < 1e-12, "{x} {fx}");
        let (x, fx) = minimize(f64::cos, 2.0, 5.0, 1e-10);
        assert!((x - std::f64::consts::PI).abs() < 1e-7 && (fx + 1.0).abs() < 1e-14);
        let (x, fx) = minimize(|x| x, 1.0, 2.0, 1e-9);
        assert!(
            (x - 1.0).abs() < 1e-7 && (fx - 1.0).abs() < 1e-7,
            "{x} {fx}"
        );
        let mut calls = 0;
        let (x, _) = minimize(
            |_| {
                calls += 1;
                f64::NAN
            },
            0.0,
            1.0,
            0.0,
        );
        assert!(x.is_finite() && calls <= 501);
        let (x, fx) = minimize(|x| x, f64::NAN, 1.0, 1e-9);
        assert!(x.is_nan() && fx.is_nan());
    }
}
