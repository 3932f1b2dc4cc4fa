//! One-dimensional minimisation without derivatives: Brent's method (Brent 1973, "Algorithms
//! for Minimization without Derivatives", ch. 5, procedure `localmin`).
//!
//! Golden-section steps guarantee convergence on any continuous function; successive parabolic
//! interpolation gives superlinear convergence near a smooth minimum. The search stays inside
//! `[a, b]` and stops when the bracket is within `2·tol` of the estimate, where
//! `tol = √ε·|x| + xtol/3`.

/// Result of [`brent_minimize`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Minimum {
    /// Abscissa of the minimum found.
    pub x: f64,
    /// Function value there.
    pub fx: f64,
    /// Function evaluations used.
    pub evaluations: usize,
}

/// Minimises `f` on `[a, b]` (`a < b`) to an absolute tolerance of about `xtol` in `x`, using
/// at most `max_evaluations` evaluations.
pub fn brent_minimize(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    xtol: f64,
    max_evaluations: usize,
) -> Minimum {
    const GOLD: f64 = 0.381_966_011_250_105_1; // (3 − √5)/2
    let eps = f64::EPSILON.sqrt();
    let (mut a, mut b) = if a <= b { (a, b) } else { (b, a) };
    let mut x = a + GOLD * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = f(x);
    let (mut fw, mut fv) = (fx, fx);
    let mut evaluations = 1;
    let mut d = 0.0_f64;
    let mut e = 0.0_f64;
    while evaluations < max_evaluations {
        let mid = 0.5 * (a + b);
        let tol = eps * x.abs() + xtol / 3.0;
        let tol2 = 2.0 * tol;
        if (x - mid).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol {
            // Parabola through (v, fv), (w, fw), (x, fx).
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = if x < mid { tol } else { -tol };
                }
                golden = false;
            }
        }
        if golden {
            e = if x < mid { b - x } else { a - x };
            d = GOLD * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else if d > 0.0 {
            x + tol
        } else {
            x - tol
        };
        let fu = f(u);
        evaluations += 1;
        if fu <= fx {
            if u < x {
                b = x;
            } else {
                a = x;
            }
            v = w;
            fv = fw;
            w = x;
            fw = fx;
            x = u;
            fx = fu;
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                v = w;
                fv = fw;
                w = u;
                fw = fu;
            } else if fu <= fv || v == x || v == w {
                v = u;
                fv = fu;
            }
        }
    }
    Minimum { x, fx, evaluations }
}

/// Golden-section search for the minimum of a unimodal `f` on `[a, b]`: at most `iterations`
/// reductions of the bracket by 0.618, stopping early once it is within `rel_tol·|b|`
/// (0: never). Returns `(x, f(x))` at the better of the two interior points; ties go to the
/// lower one. Shared by the profiled correlation times and line frequencies of the noise fit
/// and the line detector's frequency refinement (a maximum: minimise `−f`).
pub(crate) fn golden_section(
    mut a: f64,
    mut b: f64,
    iterations: usize,
    rel_tol: f64,
    f: &mut dyn FnMut(f64) -> f64,
) -> (f64, f64) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let mut f1 = f(x1);
    let mut f2 = f(x2);
    for _ in 0..iterations {
        if f1 <= f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = f(x2);
        }
        if (b - a).abs() <= rel_tol * b.abs() {
            break;
        }
    }
    if f1 <= f2 { (x1, f1) } else { (x2, f2) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    // Brent stops within 2·tol = 2(√ε·|x| + xtol/3) of the minimum: ~3e-8 here.
    fn finds_smooth_and_boundary_minima() {
        let m = brent_minimize(|x| (x - 0.3).powi(2) + 1.0, -0.5, 2.0, 1e-10, 100);
        assert!((m.x - 0.3).abs() < 1e-7 && m.evaluations < 30, "{m:?}");
        let m = brent_minimize(|x| (x - 0.3).abs(), -0.5, 2.0, 1e-10, 200);
        assert!((m.x - 0.3).abs() < 1e-7);
        let m = brent_minimize(|x| x, -0.5, 2.0, 1e-10, 200);
        assert!((m.x + 0.5).abs() < 1e-7);
        let m = brent_minimize(f64::cos, 0.0, 6.0, 1e-12, 100);
        assert!((m.x - std::f64::consts::PI).abs() < 1e-7);
    }
}
