//! Root finding and one-dimensional minimisation.

use crate::NumericsError;

/// Brent's method for a root of `f` on `[a, b]` (a sign change or a zero at
/// an end is required), to the absolute tolerance `tol` in x.
pub fn brent<F: FnMut(f64) -> f64>(
    mut f: F,
    a: f64,
    b: f64,
    tol: f64,
) -> Result<f64, NumericsError> {
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
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
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
            // a and c coincide after a bisection step: secant instead of inverse quadratic.
            if a.to_bits() == c.to_bits() {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
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
    Err(NumericsError::NoConvergence(200))
}

/// Golden-section minimisation of `f` on `[a, b]` to the x tolerance `tol`;
/// returns `(x_min, f_min)`. For unimodal `f` on the bracket.
pub fn minimize<F: FnMut(f64) -> f64>(mut f: F, a: f64, b: f64, tol: f64) -> (f64, f64) {
    let g = 0.5 * (5.0_f64.sqrt() - 1.0);
    let (mut a, mut b) = (a.min(b), a.max(b));
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..300 {
        if (b - a).abs() <= tol {
            break;
        }
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    if fc < fd { (c, fc) } else { (d, fd) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_sqrt2() {
        let r = brent(|x| x * x - 2.0, 0.0, 2.0, 1e-14).unwrap();
        assert!((r - 2.0_f64.sqrt()).abs() < 1e-12);
        assert!(matches!(
            brent(|x| x * x + 1.0, 0.0, 2.0, 1e-12),
            Err(NumericsError::NoBracket { .. })
        ));
    }

    #[test]
    fn golden_minimum() {
        let (x, fx) = minimize(|x| (x - 1.0).powi(2) + 3.0, -2.0, 5.0, 1e-10);
        // A minimum is only located to about sqrt(eps) in x; f to rounding.
        assert!((x - 1.0).abs() < 1e-7 && (fx - 3.0).abs() < 1e-14);
    }
}
