//! Conservative (overbounding) noise coefficients (Lethander & Taylor, NAVIGATION 70(3), 2023).
//!
//! A filter tuned with the *best-fit* noise coefficients is over-confident about half of the
//! time: the estimate scatters around the truth. A *conservative* set overbounds it. Following
//! Lethander & Taylor, the model Allan variance is required to lie on or above the measured
//! curve's upper confidence bound at every τ used:
//!
//! ```text
//! σ²_model(τ_i) = Σ_j c_j g_j(τ_i) ≥ U_i = σ̂²_i · edf_i / χ²_{edf_i}(1 − p),   c ≥ 0,
//! ```
//!
//! with `p` the one-sided confidence level (the true variance lies below `U_i` with probability
//! `p` at each τ), `g_j` the term basis functions ([`super::Term::basis`]) and `edf_i` the
//! equivalent degrees of freedom of each estimate. Among all such models the one chosen is the
//! tightest in the mean ratio to the bound,
//!
//! ```text
//! minimise  (1/n) Σ_i σ²_model(τ_i) / U_i   subject to the constraints above,
//! ```
//!
//! a linear programme in `c` (Lethander & Taylor minimise the distance between the model and the
//! bounded curve in the same spirit; the linear objective makes the optimum global and exact).
//! No term may fall below the reference (best-fit) set, `c ≥ c_ref` — a conservative set
//! inflates, it never trades one term for another below its estimate — so each term's
//! *inflation factor* `√(c_j / c_ref,j)` against the reference is ≥ 1.
//!
//! **Solver.** With `p ≤ 5` unknowns and `n` constraints the dual programme
//! `max Σ y_i s.t. Ãᵀy ≤ d, y ≥ 0` (rows scaled by `1/U_i`, columns by their maximum) has the
//! slack basis as a feasible start, so the primal simplex method on the dual needs no phase 1.
//! Bland's rule prevents cycling. The primal solution is the dual's shadow prices. A final
//! scaling to a smallest ratio of `1 + 16ε` makes the overbound hold exactly in floating point.

use super::curve::Curve;
use super::model::{Term, model_variance};
use crate::stats::chi2_ppf;
use crate::{Error, Result};

/// Pivot and optimality tolerance of the simplex method (the scaled tableau is O(1)).
const TOL: f64 = 1e-11;
/// Smallest model/bound ratio after the final rescaling.
const MARGIN: f64 = 1.0 + 16.0 * f64::EPSILON;

/// Result of [`overbound`]: the tightest non-negative combination of the design's columns that
/// lies on or above the bound at every row.
#[derive(Debug, Clone, PartialEq)]
pub struct Overbound {
    /// Coefficients (one per design column), all ≥ 0.
    pub coefficients: Vec<f64>,
    /// `(design · c)_i / bound_i` per row, all ≥ 1.
    pub ratio: Vec<f64>,
    /// Mean of `ratio` (the minimised objective).
    pub objective: f64,
    /// Simplex pivots made.
    pub pivots: usize,
}

/// Tightest overbound: minimise `Σ_i (A c)_i / b_i` subject to `A c ≥ b`, `c ≥ 0`.
///
/// `design` is the row-major `rows × cols` matrix `A` (`A_ij ≥ 0`, finite; every column must
/// have a positive entry) and `bound` the `rows` positive, finite bounds `b`.
///
/// # Errors
/// See [`overbound_above`].
pub fn overbound(design: &[f64], rows: usize, cols: usize, bound: &[f64]) -> Result<Overbound> {
    overbound_above(design, rows, cols, bound, &vec![0.0; cols])
}

/// [`overbound`] with lower bounds: `c ≥ floor` instead of `c ≥ 0` (a conservative set never
/// goes below the best fit). With `c = floor + d` the constraints become
/// `A d ≥ b − A·floor` on the rows the floor does not already satisfy, and the objective keeps
/// every row.
///
/// # Errors
/// [`Error::ShapeMismatch`] for inconsistent sizes, [`Error::InvalidParameter`] for negative or
/// non-finite entries (`design`, `bound`, `floor`), a row no column can raise or a zero column
/// (`design`); [`Error::Singular`] if the simplex method does not terminate (it cannot, with
/// Bland's rule, unless rounding dominates).
pub fn overbound_above(
    design: &[f64],
    rows: usize,
    cols: usize,
    bound: &[f64],
    floor: &[f64],
) -> Result<Overbound> {
    if rows == 0 || cols == 0 {
        return Err(Error::TooShort {
            name: "design",
            needed: 1,
            got: 0,
        });
    }
    if design.len() != rows * cols {
        return Err(Error::ShapeMismatch {
            name: "design",
            reason: format!("{} values for {rows} × {cols}", design.len()),
        });
    }
    if bound.len() != rows {
        return Err(Error::ShapeMismatch {
            name: "bound",
            reason: format!("{} values for {rows} rows", bound.len()),
        });
    }
    if floor.len() != cols {
        return Err(Error::ShapeMismatch {
            name: "floor",
            reason: format!("{} values for {cols} columns", floor.len()),
        });
    }
    if let Some(i) = design.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(Error::invalid(
            "design",
            format!("design[{i}] = {} is not finite and >= 0", design[i]),
        ));
    }
    if let Some(i) = bound.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(Error::invalid(
            "bound",
            format!("bound[{i}] = {} is not finite and > 0", bound[i]),
        ));
    }
    if let Some(j) = floor.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(Error::invalid(
            "floor",
            format!("floor[{j}] = {} is not finite and >= 0", floor[j]),
        ));
    }
    if let Some(j) = (0..cols).find(|&j| (0..rows).all(|i| design[i * cols + j] == 0.0)) {
        return Err(Error::invalid(
            "design",
            format!("column {j} is zero: the term contributes nothing"),
        ));
    }
    let row = |i: usize| &design[i * cols..(i + 1) * cols];
    // Objective weights over every row: w_j = Σ_i A_ij / b_i.
    let weight: Vec<f64> = (0..cols)
        .map(|j| (0..rows).map(|i| design[i * cols + j] / bound[i]).sum())
        .collect();
    // Rows the floor leaves unsatisfied, with their residual bound r_i = b_i − (A·floor)_i.
    let mut active = Vec::new();
    let mut residual = Vec::new();
    for i in 0..rows {
        let base: f64 = row(i).iter().zip(floor).map(|(a, f)| a * f).sum();
        let r = bound[i] - base;
        if r > 1e-12 * bound[i] {
            if row(i).iter().all(|v| *v == 0.0) {
                return Err(Error::invalid(
                    "design",
                    format!("row {i} is zero: no term can raise the model there"),
                ));
            }
            active.push(i);
            residual.push(r);
        }
    }
    let mut coefficients = floor.to_vec();
    let mut pivots = 0usize;
    if !active.is_empty() {
        let n = active.len();
        // Column scales s_j = max over the active rows of A_ij / r_i; a column that is zero on
        // all of them cannot help and stays at its floor.
        let scale: Vec<f64> = (0..cols)
            .map(|j| {
                active
                    .iter()
                    .zip(&residual)
                    .map(|(&i, r)| design[i * cols + j] / r)
                    .fold(0.0_f64, f64::max)
            })
            .collect();
        if let Some(j) = scale.iter().position(|s| !s.is_finite()) {
            return Err(Error::invalid(
                "design",
                format!("column {j} overflows after scaling by the bound"),
            ));
        }
        let used: Vec<usize> = (0..cols).filter(|&j| scale[j] > 0.0).collect();
        let p = used.len();
        // Dual in scaled variables: max Σ y_i s.t. Ãᵀy ≤ w̃, y ≥ 0, with
        // ã_ij = A_ij/(r_i s_j) and w̃_j = w_j/s_j; tableau [Ãᵀ | I], slack basis.
        let width = n + p;
        let mut tableau = vec![0.0_f64; p * width];
        let mut rhs = vec![0.0_f64; p];
        for (k, &j) in used.iter().enumerate() {
            for (col, (&i, r)) in active.iter().zip(&residual).enumerate() {
                tableau[k * width + col] = design[i * cols + j] / (r * scale[j]);
            }
            tableau[k * width + n + k] = 1.0;
            rhs[k] = weight[j] / scale[j];
        }
        let mut basis: Vec<usize> = (n..width).collect();
        let cost = |k: usize| if k < n { 1.0 } else { 0.0 };
        let max_pivots = 50 * width + 100;
        let mut reduced = vec![0.0_f64; width];
        loop {
            for (k, r) in reduced.iter_mut().enumerate() {
                let mut s = cost(k);
                for (row, &b) in basis.iter().enumerate() {
                    s -= cost(b) * tableau[row * width + k];
                }
                *r = s;
            }
            // Bland: the lowest-index improving column enters.
            let Some(enter) = (0..width).find(|&k| reduced[k] > TOL) else {
                break;
            };
            let mut leave: Option<(usize, f64)> = None;
            for row in 0..p {
                let t = tableau[row * width + enter];
                if t > TOL {
                    let q = rhs[row] / t;
                    let better = match leave {
                        None => true,
                        Some((l, best)) => q < best || (q == best && basis[row] < basis[l]),
                    };
                    if better {
                        leave = Some((row, q));
                    }
                }
            }
            let Some((pivot_row, _)) = leave else {
                return Err(Error::Singular {
                    reason: "overbound: the dual programme is unbounded (the bound cannot be met)"
                        .into(),
                });
            };
            let pv = tableau[pivot_row * width + enter];
            for k in 0..width {
                tableau[pivot_row * width + k] /= pv;
            }
            rhs[pivot_row] /= pv;
            for row in 0..p {
                if row == pivot_row {
                    continue;
                }
                let f = tableau[row * width + enter];
                if f != 0.0 {
                    for k in 0..width {
                        tableau[row * width + k] -= f * tableau[pivot_row * width + k];
                    }
                    rhs[row] -= f * rhs[pivot_row];
                }
            }
            basis[pivot_row] = enter;
            pivots += 1;
            if pivots > max_pivots {
                return Err(Error::Singular {
                    reason: format!(
                        "overbound: the simplex method did not finish in {max_pivots} pivots"
                    ),
                });
            }
        }
        // Shadow prices of the dual's rows: x_k = −(reduced cost of slack k); d_j = x_k / s_j.
        for (k, &j) in used.iter().enumerate() {
            coefficients[j] += (-reduced[n + k]).max(0.0) / scale[j];
        }
    }
    let ratios = |c: &[f64]| -> Vec<f64> {
        (0..rows)
            .map(|i| row(i).iter().zip(c).map(|(a, c)| a * c).sum::<f64>() / bound[i])
            .collect()
    };
    let mut ratio = ratios(&coefficients);
    let min = ratio.iter().copied().fold(f64::INFINITY, f64::min);
    if min.is_nan() || min <= 1.0 - 1e-6 {
        return Err(Error::Singular {
            reason: format!("overbound: the simplex solution violates a bound (ratio {min})"),
        });
    }
    // Remove the rounding of the pivots with a margin of a few ulps, so that the constraints
    // hold exactly however a caller sums `A c` (the objective moves by ~1e-15 relative).
    if min < MARGIN {
        let f = MARGIN / min;
        for c in &mut coefficients {
            *c *= f;
        }
        ratio = ratios(&coefficients);
    }
    let objective = ratio.iter().sum::<f64>() / rows as f64;
    Ok(Overbound {
        coefficients,
        ratio,
        objective,
        pivots,
    })
}

/// Result of [`conservative`].
#[derive(Debug, Clone, PartialEq)]
pub struct Conservative {
    /// Conservative squared coefficients `(Q², N², B², K², R²)` in the data's base units.
    pub squared: [f64; 5],
    /// Amplitude inflation `√(c_j / c_ref,j)` per term (≥ 1 for the allowed terms): NaN where
    /// both are zero, `+∞` where only the reference is zero.
    pub inflation: [f64; 5],
    /// Indices of the curve points used.
    pub used: Vec<usize>,
    /// EDF of each used point.
    pub edf: Vec<f64>,
    /// Upper confidence bound `U_i` of the Allan variance at each used point.
    pub bound: Vec<f64>,
    /// `σ²_model(τ_i) / U_i` at each used point (all ≥ 1).
    pub ratio: Vec<f64>,
    /// τ range of the used points (s).
    pub tau_range: (f64, f64),
}

/// The term contributing most to the model `c` at `tau` (white rate if the model is empty);
/// selects the SP1065 EDF approximation when the curve has no EDF of its own.
fn dominant_term(c: &[f64; 5], tau: f64) -> Term {
    Term::ALL
        .into_iter()
        .map(|t| (t, c[t.index()] * t.basis(tau)))
        .filter(|(_, v)| *v > 0.0)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(Term::AngleRandomWalk, |(t, _)| t)
}

/// Conservative coefficients: the tightest model of the `allowed` terms whose Allan variance
/// overbounds the one-sided upper `confidence` bound of `curve` at every point with τ in
/// `tau_range` (all points if `None`) and σ² > 0.
///
/// `reference` holds the squared coefficients the inflation factors are reported against (the
/// best fit); it also selects the EDF approximation when `curve.edf` is `None`.
///
/// # Errors
/// Invalid curve ([`Curve::validate`]), `confidence` outside (0, 1), a negative or non-finite
/// reference, no allowed term, fewer than one point in the range.
pub fn conservative(
    curve: &Curve<'_>,
    reference: &[f64; 5],
    allowed: [bool; 5],
    tau_range: Option<(f64, f64)>,
    confidence: f64,
) -> Result<Conservative> {
    curve.validate()?;
    if !(confidence > 0.0 && confidence < 1.0) {
        return Err(Error::invalid(
            "confidence",
            format!("must lie strictly between 0 and 1, got {confidence}"),
        ));
    }
    if let Some(j) = reference.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(Error::invalid(
            "reference",
            format!(
                "squared coefficient {} = {} is not finite and >= 0",
                Term::ALL[j].symbol(),
                reference[j]
            ),
        ));
    }
    let terms: Vec<Term> = Term::ALL
        .into_iter()
        .filter(|t| allowed[t.index()])
        .collect();
    if terms.is_empty() {
        return Err(Error::invalid(
            "terms",
            "no term allowed in the conservative model",
        ));
    }
    let (lo, hi) = tau_range.unwrap_or((0.0, f64::INFINITY));
    if lo.is_nan() || hi.is_nan() || hi <= lo {
        return Err(Error::invalid(
            "tau_range",
            format!("must be (low, high) with low < high, got ({lo}, {hi})"),
        ));
    }
    let used: Vec<usize> = (0..curve.len())
        .filter(|&i| curve.taus[i] >= lo && curve.taus[i] <= hi && curve.variance[i] > 0.0)
        .collect();
    if used.is_empty() {
        return Err(Error::TooShort {
            name: "allan",
            needed: 1,
            got: 0,
        });
    }
    let q = 1.0 - confidence;
    let mut edf = Vec::with_capacity(used.len());
    let mut bound = Vec::with_capacity(used.len());
    for &i in &used {
        let tau = curve.taus[i];
        let e = curve.edf_at(i, dominant_term(reference, tau));
        bound.push(curve.variance[i] * e / chi2_ppf(q, e)?);
        edf.push(e);
    }
    let cols = terms.len();
    let mut design = Vec::with_capacity(used.len() * cols);
    for &i in &used {
        design.extend(terms.iter().map(|t| t.basis(curve.taus[i])));
    }
    let floor: Vec<f64> = terms.iter().map(|t| reference[t.index()]).collect();
    let solved = overbound_above(&design, used.len(), cols, &bound, &floor)?;
    let mut squared = [0.0_f64; 5];
    for (t, c) in terms.iter().zip(&solved.coefficients) {
        squared[t.index()] = *c;
    }
    let inflation = std::array::from_fn(|j| {
        let (c, r) = (squared[j], reference[j]);
        if r > 0.0 {
            (c / r).sqrt()
        } else if c > 0.0 {
            f64::INFINITY
        } else {
            f64::NAN
        }
    });
    debug_assert!(
        used.iter()
            .zip(&bound)
            .all(|(&i, u)| model_variance(&squared, curve.taus[i]) >= u * (1.0 - 1e-12))
    );
    Ok(Conservative {
        squared,
        inflation,
        tau_range: (curve.taus[used[0]], curve.taus[used[used.len() - 1]]),
        used,
        edf,
        bound,
        ratio: solved.ratio,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Next `k`-combination of `0..total` in lexicographic order; false after the last.
    fn next(pick: &mut [usize], total: usize) -> bool {
        let k = pick.len();
        for i in (0..k).rev() {
            if pick[i] < total - (k - i) {
                pick[i] += 1;
                for j in i + 1..k {
                    pick[j] = pick[j - 1] + 1;
                }
                return true;
            }
        }
        false
    }

    /// Brute force: the LP optimum is at a vertex where `cols` of the `rows + cols` constraints
    /// (rows of `A c ≥ b` or `c_j ≥ 0`) are tight; enumerate them all.
    fn brute_force(design: &[f64], rows: usize, cols: usize, bound: &[f64], floor: &[f64]) -> f64 {
        let total = rows + cols;
        let mut best = f64::INFINITY;
        let mut pick = vec![0usize; cols];
        for (i, p) in pick.iter_mut().enumerate() {
            *p = i;
        }
        loop {
            // Solve the cols × cols system by Gaussian elimination with partial pivoting.
            let mut m = vec![vec![0.0; cols + 1]; cols];
            for (r, &c) in pick.iter().enumerate() {
                if c < rows {
                    m[r][..cols].copy_from_slice(&design[c * cols..(c + 1) * cols]);
                    m[r][cols] = bound[c];
                } else {
                    m[r][c - rows] = 1.0;
                    m[r][cols] = floor[c - rows];
                }
            }
            let mut ok = true;
            for k in 0..cols {
                let piv = (k..cols)
                    .max_by(|&a, &b| m[a][k].abs().total_cmp(&m[b][k].abs()))
                    .unwrap();
                if m[piv][k].abs() < 1e-12 {
                    ok = false;
                    break;
                }
                m.swap(k, piv);
                for r in 0..cols {
                    if r != k {
                        let f = m[r][k] / m[k][k];
                        for c in k..=cols {
                            m[r][c] -= f * m[k][c];
                        }
                    }
                }
            }
            if ok {
                let x: Vec<f64> = (0..cols).map(|k| m[k][cols] / m[k][k]).collect();
                let feasible = x.iter().zip(floor).all(|(v, f)| *v >= f - 1e-12)
                    && (0..rows).all(|i| {
                        (0..cols).map(|j| design[i * cols + j] * x[j]).sum::<f64>()
                            >= bound[i] * (1.0 - 1e-9)
                    });
                if feasible {
                    let obj = (0..rows)
                        .map(|i| {
                            (0..cols).map(|j| design[i * cols + j] * x[j]).sum::<f64>() / bound[i]
                        })
                        .sum::<f64>()
                        / rows as f64;
                    best = best.min(obj);
                }
            }
            if !next(&mut pick, total) {
                break;
            }
        }
        best
    }

    #[test]
    fn matches_vertex_enumeration() {
        let mut stream = crate::random::NormalStream::new(0x9e37_79b9_7f4a_7c15);
        let mut uniform = || stream.uniform();
        for case in 0..40 {
            let cols = 1 + case % 5;
            let rows = 3 + case % 9;
            let taus: Vec<f64> = (0..rows).map(|i| 0.01 * 2f64.powi(i as i32)).collect();
            let terms = &Term::ALL[..cols];
            let design: Vec<f64> = taus
                .iter()
                .flat_map(|t| terms.iter().map(|term| term.basis(*t)))
                .collect();
            let bound: Vec<f64> = taus
                .iter()
                .map(|t| (0.5 + uniform()) * (1.0 / t + 1.0))
                .collect();
            // Half the cases with a floor (a "best fit" at 0–80 % of the bound's level).
            let floor: Vec<f64> = (0..cols)
                .map(|_| if case % 2 == 0 { 0.0 } else { 0.8 * uniform() })
                .collect();
            let lp = overbound_above(&design, rows, cols, &bound, &floor).unwrap();
            assert!(lp.ratio.iter().all(|r| *r >= 1.0), "{:?}", lp.ratio);
            assert!(lp.coefficients.iter().zip(&floor).all(|(c, f)| c >= f));
            let brute = brute_force(&design, rows, cols, &bound, &floor);
            assert!(
                (lp.objective - brute).abs() <= 1e-9 * brute,
                "case {case}: {} vs {brute}",
                lp.objective
            );
        }
    }

    #[test]
    fn single_term_is_the_largest_ratio() {
        // One column: c = max_i b_i / a_i.
        let design = [1.0, 0.5, 0.25];
        let bound = [1.0, 1.0, 0.1];
        let lp = overbound(&design, 3, 1, &bound).unwrap();
        assert!((lp.coefficients[0] - 2.0).abs() < 1e-12);
        assert!(lp.ratio.iter().all(|r| *r >= 1.0));
    }

    #[test]
    fn bad_input_names_the_argument() {
        let e = overbound(&[1.0, -1.0], 2, 1, &[1.0, 1.0]).unwrap_err();
        assert!(matches!(e, Error::InvalidParameter { name: "design", .. }));
        let e = overbound(&[1.0, 0.0, 0.0, 0.0], 2, 2, &[1.0, 1.0]).unwrap_err();
        assert!(matches!(e, Error::InvalidParameter { name: "design", .. }));
        let e = overbound(&[1.0, 1.0], 2, 1, &[1.0, 0.0]).unwrap_err();
        assert!(matches!(e, Error::InvalidParameter { name: "bound", .. }));
        assert!(overbound(&[1.0], 2, 1, &[1.0, 1.0]).is_err());
        let e = overbound_above(&[1.0, 1.0], 2, 1, &[1.0, 1.0], &[-1.0]).unwrap_err();
        assert!(matches!(e, Error::InvalidParameter { name: "floor", .. }));
        // A floor that already overbounds is the answer (up to the rounding margin).
        let lp = overbound_above(&[1.0, 2.0], 2, 1, &[1.0, 1.0], &[3.0]).unwrap();
        assert!((lp.coefficients[0] - 3.0).abs() < 1e-12);
    }

    #[test]
    fn conservative_overbounds_the_upper_bound() {
        let m: Vec<usize> = (0..14).map(|k| 1usize << k).collect();
        let taus: Vec<f64> = m.iter().map(|&m| m as f64 * 0.01).collect();
        let truth = [0.0, 1e-4, 1e-6, 1e-7, 0.0];
        // A wiggly "measured" curve around the truth.
        let var: Vec<f64> = taus
            .iter()
            .enumerate()
            .map(|(i, t)| model_variance(&truth, *t) * (1.0 + 0.3 * ((i as f64) * 1.7).sin()))
            .collect();
        let n_terms: Vec<usize> = m.iter().map(|&m| 400_001 - 2 * m).collect();
        let curve = Curve {
            taus: &taus,
            variance: &var,
            m: &m,
            n_terms: &n_terms,
            overlapping: true,
            edf: None,
        };
        let allowed = [false, true, true, true, false];
        let c = conservative(&curve, &truth, allowed, None, 0.95).unwrap();
        for (k, &i) in c.used.iter().enumerate() {
            assert!(model_variance(&c.squared, taus[i]) >= c.bound[k]);
            assert!(c.bound[k] > var[i]);
        }
        assert_eq!(c.squared[0], 0.0);
        assert!(c.inflation[0].is_nan());
        assert!(
            c.inflation[1..4].iter().all(|f| *f >= 1.0),
            "{:?}",
            c.inflation
        );
        assert!(conservative(&curve, &truth, allowed, None, 1.0).is_err());
        assert!(conservative(&curve, &truth, [false; 5], None, 0.9).is_err());
    }
}
