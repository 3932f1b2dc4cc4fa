//! Least-squares spectral analysis (LSSA) of unequally spaced, weighted series
//! (\[TS\] §2.2 eqs. 5–12; Vaníček 1969; Pagiatakis 1999; SPEC §8).
//!
//! The series $f(t_i)$, $i = 1..n$ (times strictly increasing, otherwise arbitrary: gaps and
//! irregular spacing are what LSSA is for) has weight matrix $P = C_f^{-1}$: identity, diagonal
//! weights, or the inverse of a full covariance matrix $C_f$ (then everything below is computed
//! on the data whitened once with the Cholesky factor, $C_f = LL^T$, $\tilde f = L^{-1}f$).
//!
//! **Known constituents** $\Phi_K$ ($u$ columns: the datum bias, optionally a linear trend, a
//! cos/sin pair for every known period, and any user-supplied columns) are fitted first, giving the residual
//! $g = f - \Phi_K N_{11}^{-1}\Phi_K^T P f$ with $N_{11} = \Phi_K^T P \Phi_K$.
//!
//! **Spectrum.** At every frequency $\omega$ the pair $\Phi_\omega = [\cos\omega t, \sin\omega t]$
//! is fitted simultaneously with $\Phi_K$ (made $P$-orthogonal to it), and
//! $$ s(\omega) = \frac{r^T (N_{22} - N_{12}^T N_{11}^{-1} N_{12})^{-1} r}{g^T P g},\qquad
//!    r = \Phi_\omega^T P g,\ N_{12} = \Phi_K^T P \Phi_\omega,\ N_{22} = \Phi_\omega^T P
//!    \Phi_\omega, $$
//! the fraction of the residual's weighted quadratic norm explained by the sinusoid,
//! $s \in [0, 1]$. With only the datum bias and no weights this is astropy's `LombScargle`
//! (standard normalisation, `fit_mean=True`). Where the pair is numerically rank deficient
//! (e.g. exactly the Nyquist frequency of a regular grid, where $\sin\omega t_i = 0$) the
//! pseudo-inverse is used (the cosine alone is fitted). A known constituent leaves no peak at
//! its own frequency and does not shift the others.
//!
//! **Significance** (Pagiatakis 1999, unknown variance factor): $s$ is Beta-distributed and the
//! critical value at level $\alpha$ is $s_{crit} = 1 - \alpha^{2/(n-u-2)}$ ([`critical_value`];
//! $n$ = 600, $u$ = 1, $\alpha$ = 0.01 → 0.01530931).
//!
//! **Cost.** $O(n)$ per frequency after $O(n u^2)$ setup, parallel over chunks of frequencies.
//! On a uniform frequency grid the sines and cosines are advanced by the rotation
//! $e^{i\,\Delta\omega\,t_i}$ and re-seeded exactly every [`RESEED`] frequencies, so only one
//! `sin_cos` per point and chunk is evaluated (rounding drift below $10^{-14}$). With a full
//! covariance the whitening costs $O(n^2)$ per frequency; $n$ is capped at [`MAX_COV_SIZE`].

use rayon::prelude::*;

use crate::{Error, Result, validate};

/// Largest series accepted with a full covariance matrix (8 n² bytes, O(n²) per frequency).
pub const MAX_COV_SIZE: usize = 4000;

/// Number of frequencies advanced by rotation between exact re-seeds (one rayon task).
pub const RESEED: usize = 32;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Optional parts of an LSSA problem.
#[derive(Debug, Clone, Copy, Default)]
pub struct LssaOptions<'a> {
    /// Diagonal weights $P_{ii}$ (e.g. $1/\sigma_i^2$), all finite and > 0.
    pub weights: Option<&'a [f64]>,
    /// Full covariance matrix $C_f$, row-major $n\times n$, symmetric positive definite.
    pub cov: Option<&'a [f64]>,
    /// Fit a linear trend as a known constituent.
    pub trend: bool,
    /// Periods (in the unit of `t`) of known sinusoids fitted as constituents.
    pub known_periods: &'a [f64],
    /// Further known constituents: a row-major `n × k` matrix of user columns and its `k`.
    pub columns: Option<(&'a [f64], usize)>,
}

/// Result of [`lssa`].
#[derive(Debug, Clone, PartialEq)]
pub struct LssaResult {
    /// Spectral values $s(\omega_j) \in [0, 1]$.
    pub spectrum: Vec<f64>,
    /// Number of known-constituent parameters $u$.
    pub n_known: usize,
    /// Estimated known-constituent parameters, in the order bias, trend (per unit of `t`),
    /// (cos, sin) amplitude per known period, then one per user column; time measured from
    /// `t_ref`.
    pub known_params: Vec<f64>,
    /// Reference time of the parameters: the midpoint of the series.
    pub t_ref: f64,
    /// Weighted quadratic norm of the residual $g^T P g$.
    pub residual_norm: f64,
}

/// Pagiatakis' critical spectral value $1 - \alpha^{2/(n-u-2)}$.
pub fn critical_value(n: usize, n_known: usize, alpha: f64) -> Result<f64> {
    if !(alpha > 0.0 && alpha < 1.0) {
        return Err(Error::invalid(
            "alpha",
            format!("must lie strictly between 0 and 1, got {alpha}"),
        ));
    }
    validate::min_len("t", n, n_known + 3)?;
    let dof = (n - n_known - 2) as f64;
    Ok(-(2.0 * alpha.ln() / dof).exp_m1())
}

/// The default frequency grid $f_k = k/(n\,\overline{\Delta t})$, $k = 1..\lfloor(n-1)/2\rfloor$,
/// with $\overline{\Delta t} = (t_{n} - t_1)/(n-1)$: the Fourier frequencies for regular
/// sampling, strictly below the (average) Nyquist frequency.
pub fn default_frequencies(t: &[f64]) -> Result<Vec<f64>> {
    validate::min_len("t", t.len(), 3)?;
    validate::finite("t", t)?;
    check_increasing(t)?;
    let n = t.len();
    let mean_dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let df = 1.0 / (n as f64 * mean_dt);
    Ok((1..=(n - 1) / 2).map(|k| k as f64 * df).collect())
}

fn check_increasing(t: &[f64]) -> Result<()> {
    for i in 1..t.len() {
        if t[i] <= t[i - 1] {
            let what = if t[i] == t[i - 1] {
                "duplicate"
            } else {
                "unsorted"
            };
            return Err(Error::invalid(
                "t",
                format!(
                    "times must be strictly increasing ({what} time at index {i}: t[{i}] = {} after t[{}] = {})",
                    t[i],
                    i - 1,
                    t[i - 1]
                ),
            ));
        }
    }
    Ok(())
}

/// Small dense symmetric positive-definite inverse (u ≤ a few dozen) via nalgebra's Cholesky.
fn spd_inverse(a: &[f64], u: usize) -> Option<Vec<f64>> {
    let m = nalgebra::DMatrix::from_row_slice(u, u, a);
    let chol = m.cholesky()?;
    // Reject numerically dependent columns: a pivot L_ii² tiny against its diagonal entry.
    let l = chol.l_dirty();
    if (0..u).any(|i| l[(i, i)] * l[(i, i)] <= 1e-12 * a[i * u + i]) {
        return None;
    }
    let inv = chol.inverse();
    let mut out = vec![0.0; u * u];
    for i in 0..u {
        for j in 0..u {
            out[i * u + j] = inv[(i, j)];
        }
    }
    Some(out)
}

/// Row-major lower Cholesky factor of a symmetric positive-definite `n × n` matrix.
fn cholesky_lower(cov: &[f64], n: usize) -> Result<Vec<f64>> {
    let scale = cov.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    for i in 0..n {
        for j in 0..i {
            if (cov[i * n + j] - cov[j * n + i]).abs() > 1e-12 * scale {
                return Err(Error::invalid(
                    "cov",
                    format!("must be symmetric (cov[{i}, {j}] != cov[{j}, {i}])"),
                ));
            }
        }
    }
    let m = nalgebra::DMatrix::from_row_slice(n, n, cov);
    let chol = m.cholesky().ok_or_else(|| Error::Singular {
        reason: "cov is not positive definite (Cholesky factorisation failed)".into(),
    })?;
    let l = chol.l();
    let mut out = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            out[i * n + j] = l[(i, j)];
        }
    }
    Ok(out)
}

/// Solves `L x = b` in place for row-major lower-triangular `L`.
fn forward_substitute(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let row = &l[i * n..i * n + i];
        let dot: f64 = row.iter().zip(&b[..i]).map(|(a, x)| a * x).sum();
        b[i] = (b[i] - dot) / l[i * n + i];
    }
}

/// Sums over the points of one frequency, accumulated in 4 lanes (vectorisable).
#[derive(Default, Clone, Copy)]
struct Sums {
    cc: f64,
    cs: f64,
    ss: f64,
    cg: f64,
    sg: f64,
    pc: f64,
    ps: f64,
}

const LANES: usize = 4;

/// Accumulates the weighted sums for the current (c, s); when `rot` is given, advances (c, s)
/// by the per-point rotation afterwards.
fn accumulate(
    c: &mut [f64],
    s: &mut [f64],
    rot: Option<(&[f64], &[f64])>,
    w: &[f64],
    wg: &[f64],
    wphi0: &[f64],
) -> Sums {
    let n = c.len();
    let body = n - n % LANES;
    let mut acc = [[0.0_f64; LANES]; 7];
    let mut i = 0;
    while i < body {
        for l in 0..LANES {
            let k = i + l;
            let (ck, sk) = (c[k], s[k]);
            let wc = w[k] * ck;
            let ws = w[k] * sk;
            acc[0][l] += wc * ck;
            acc[1][l] += wc * sk;
            acc[2][l] += ws * sk;
            acc[3][l] += wg[k] * ck;
            acc[4][l] += wg[k] * sk;
            acc[5][l] += wphi0[k] * ck;
            acc[6][l] += wphi0[k] * sk;
            if let Some((rc, rs)) = rot {
                c[k] = ck * rc[k] - sk * rs[k];
                s[k] = sk * rc[k] + ck * rs[k];
            }
        }
        i += LANES;
    }
    let mut tot = [0.0_f64; 7];
    for (t, a) in tot.iter_mut().zip(acc.iter()) {
        *t = (a[0] + a[1]) + (a[2] + a[3]);
    }
    for k in body..n {
        let (ck, sk) = (c[k], s[k]);
        tot[0] += w[k] * ck * ck;
        tot[1] += w[k] * ck * sk;
        tot[2] += w[k] * sk * sk;
        tot[3] += wg[k] * ck;
        tot[4] += wg[k] * sk;
        tot[5] += wphi0[k] * ck;
        tot[6] += wphi0[k] * sk;
        if let Some((rc, rs)) = rot {
            c[k] = ck * rc[k] - sk * rs[k];
            s[k] = sk * rc[k] + ck * rs[k];
        }
    }
    Sums {
        cc: tot[0],
        cs: tot[1],
        ss: tot[2],
        cg: tot[3],
        sg: tot[4],
        pc: tot[5],
        ps: tot[6],
    }
}

/// $r^T M^+ r$ for a symmetric positive semi-definite 2×2 `M = [[a, b], [b, d]]`.
fn quad_pinv(a: f64, b: f64, d: f64, r1: f64, r2: f64) -> f64 {
    let tr = a + d;
    if tr.is_nan() || tr <= 0.0 {
        return 0.0;
    }
    let det = a * d - b * b;
    if det > 1e-11 * tr * tr {
        return (d * r1 * r1 - 2.0 * b * r1 * r2 + a * r2 * r2) / det;
    }
    // Rank one: project r on the dominant eigenvector (eigenvalue λ ≈ trace).
    let half = 0.5 * (a - d);
    let lam = 0.5 * tr + (half * half + b * b).sqrt();
    let (v1, v2) = if b.abs() > 0.0 || a != d {
        let (x, y) = if a >= d { (lam - d, b) } else { (b, lam - a) };
        let norm = (x * x + y * y).sqrt();
        (x / norm, y / norm)
    } else {
        (1.0, 0.0)
    };
    let proj = v1 * r1 + v2 * r2;
    proj * proj / lam
}

/// Least-squares spectrum of `y(t)` at `freqs` (cycles per unit of `t`); see the module docs.
///
/// Errors: non-finite input; `t` not strictly increasing (unsorted or duplicate times);
/// lengths that differ; fewer than `u + 3` points; frequencies ≤ 0 or equal to a known
/// period's frequency; non-positive weights; both `weights` and `cov`; a `cov` that is not
/// `n × n`, not symmetric, not positive definite, or larger than [`MAX_COV_SIZE`]; known
/// constituents that are linearly dependent at the given times; `y` explained exactly by them.
pub fn lssa(t: &[f64], y: &[f64], freqs: &[f64], opts: &LssaOptions<'_>) -> Result<LssaResult> {
    let n = t.len();
    validate::finite("t", t)?;
    validate::finite("y", y)?;
    if y.len() != n {
        return Err(Error::ShapeMismatch {
            name: "y",
            reason: format!("y has {} values but t has {n}", y.len()),
        });
    }
    validate::min_len("freqs", freqs.len(), 1)?;
    validate::finite("freqs", freqs)?;
    if let Some(i) = freqs.iter().position(|&f| f <= 0.0) {
        return Err(Error::invalid(
            "freqs",
            format!("frequencies must be > 0, got {} at index {i}", freqs[i]),
        ));
    }
    let periods = opts.known_periods;
    validate::finite("known_periods", periods)?;
    for (i, &p) in periods.iter().enumerate() {
        if p <= 0.0 {
            return Err(Error::invalid(
                "known_periods",
                format!("periods must be > 0, got {p}"),
            ));
        }
        if periods[..i].iter().any(|&q| (q - p).abs() <= 1e-12 * p) {
            return Err(Error::invalid(
                "known_periods",
                format!("period {p} is given twice"),
            ));
        }
    }
    for &f in freqs {
        if let Some(&p) = periods.iter().find(|&&p| (f * p - 1.0).abs() <= 1e-9) {
            return Err(Error::invalid(
                "freqs",
                format!(
                    "frequency {f} equals the known period {p} (f = 1/P): the constituent is already fitted there, so its spectral value is undefined"
                ),
            ));
        }
    }
    let n_user = opts.columns.map_or(0, |(_, k)| k);
    let u = 1 + usize::from(opts.trend) + 2 * periods.len() + n_user;
    validate::min_len("t", n, u + 3)?;
    check_increasing(t)?;
    if opts.weights.is_some() && opts.cov.is_some() {
        return Err(Error::invalid(
            "cov",
            "give either weights or cov, not both",
        ));
    }
    let mut w = match opts.weights {
        Some(wt) => {
            if wt.len() != n {
                return Err(Error::ShapeMismatch {
                    name: "weights",
                    reason: format!("weights has {} values but t has {n}", wt.len()),
                });
            }
            validate::finite("weights", wt)?;
            if let Some(i) = wt.iter().position(|&v| v <= 0.0) {
                return Err(Error::invalid(
                    "weights",
                    format!("weights must be > 0, got {} at index {i}", wt[i]),
                ));
            }
            wt.to_vec()
        }
        None => vec![1.0; n],
    };
    let chol = match opts.cov {
        Some(cov) => {
            if n > MAX_COV_SIZE {
                return Err(Error::invalid(
                    "cov",
                    format!(
                        "a full covariance is supported up to n = {MAX_COV_SIZE} points (O(n²) memory and work per frequency), got n = {n}; use diagonal weights"
                    ),
                ));
            }
            if cov.len() != n * n {
                return Err(Error::ShapeMismatch {
                    name: "cov",
                    reason: format!("cov has {} values, expected {n} × {n}", cov.len()),
                });
            }
            validate::finite("cov", cov)?;
            Some(cholesky_lower(cov, n)?)
        }
        None => None,
    };

    if let Some((cols, k)) = opts.columns {
        if k == 0 || cols.len() != n * k {
            return Err(Error::ShapeMismatch {
                name: "columns",
                reason: format!("{} values do not form {n} rows of {k} columns", cols.len()),
            });
        }
        validate::finite("columns", cols)?;
    }
    let t_ref = 0.5 * (t[0] + t[n - 1]);
    let half_span = 0.5 * (t[n - 1] - t[0]);
    let ts: Vec<f64> = t.iter().map(|&v| v - t_ref).collect();

    // Known design, one column per parameter.
    let mut cols: Vec<Vec<f64>> = vec![vec![1.0; n]];
    if opts.trend {
        cols.push(ts.iter().map(|&v| v / half_span).collect());
    }
    for &p in periods {
        let (sn, cs): (Vec<f64>, Vec<f64>) = ts.iter().map(|&v| (TWO_PI * v / p).sin_cos()).unzip();
        cols.push(cs);
        cols.push(sn);
    }
    if let Some((user, k)) = opts.columns {
        for j in 0..k {
            cols.push((0..n).map(|i| user[i * k + j]).collect());
        }
    }
    let mut yw = y.to_vec();
    if let Some(l) = &chol {
        forward_substitute(l, n, &mut yw);
        for col in &mut cols {
            forward_substitute(l, n, col);
        }
        w.fill(1.0);
    }

    // Fit the known constituents.
    let mut n11 = vec![0.0; u * u];
    let mut rhs = vec![0.0; u];
    for a in 0..u {
        for b in 0..=a {
            let v: f64 = (0..n).map(|i| w[i] * cols[a][i] * cols[b][i]).sum();
            n11[a * u + b] = v;
            n11[b * u + a] = v;
        }
        rhs[a] = (0..n).map(|i| w[i] * cols[a][i] * yw[i]).sum();
    }
    let n11_inv = spd_inverse(&n11, u).ok_or_else(|| Error::Singular {
        reason: "the known constituents (bias, trend, known periods, columns) are linearly dependent at these times".into(),
    })?;
    let mut params: Vec<f64> = (0..u)
        .map(|a| (0..u).map(|b| n11_inv[a * u + b] * rhs[b]).sum())
        .collect();
    let mut g = yw.clone();
    for (col, &x) in cols.iter().zip(&params) {
        for (gi, &ci) in g.iter_mut().zip(col) {
            *gi -= x * ci;
        }
    }
    let residual_norm: f64 = g.iter().zip(&w).map(|(gi, wi)| wi * gi * gi).sum();
    let total: f64 = yw.iter().zip(&w).map(|(v, wi)| wi * v * v).sum();
    if residual_norm <= 1e-28 * total || residual_norm == 0.0 {
        return Err(Error::Singular {
            reason: "y is explained exactly by the known constituents (zero residual): the spectrum is undefined".into(),
        });
    }
    if opts.trend {
        params[1] /= half_span;
    }
    let wg: Vec<f64> = g.iter().zip(&w).map(|(a, b)| a * b).collect();
    let wphi: Vec<Vec<f64>> = cols
        .iter()
        .map(|c| c.iter().zip(&w).map(|(a, b)| a * b).collect())
        .collect();

    // Uniform grid → rotation recurrence.
    let m = freqs.len();
    let uniform = m >= 2 && {
        let df = (freqs[m - 1] - freqs[0]) / (m - 1) as f64;
        df > 0.0
            && freqs
                .iter()
                .enumerate()
                .all(|(j, &f)| (f - (freqs[0] + j as f64 * df)).abs() <= 1e-12 * freqs[m - 1])
    };
    let rotation: Option<(Vec<f64>, Vec<f64>)> = uniform.then(|| {
        let df = (freqs[m - 1] - freqs[0]) / (m - 1) as f64;
        let (rs, rc): (Vec<f64>, Vec<f64>) =
            ts.iter().map(|&v| (TWO_PI * df * v).sin_cos()).unzip();
        (rc, rs)
    });

    let mut spectrum = vec![0.0; m];
    spectrum
        .par_chunks_mut(RESEED)
        .enumerate()
        .for_each(|(chunk, out)| {
            let j0 = chunk * RESEED;
            let mut c = vec![0.0; n];
            let mut s = vec![0.0; n];
            let mut cw = if chol.is_some() {
                vec![0.0; n]
            } else {
                Vec::new()
            };
            let mut sw = cw.clone();
            let mut z = vec![0.0; 2 * u];
            let mut pc = vec![0.0; u];
            let mut ps = vec![0.0; u];
            for (jj, o) in out.iter_mut().enumerate() {
                let f = freqs[j0 + jj];
                if rotation.is_none() || jj == 0 {
                    for ((ci, si), &v) in c.iter_mut().zip(s.iter_mut()).zip(&ts) {
                        (*si, *ci) = (TWO_PI * f * v).sin_cos();
                    }
                }
                // Fuse the rotation into the accumulation when nothing else needs (c, s).
                let fuse = chol.is_none() && u == 1;
                let (cur_c, cur_s): (&mut [f64], &mut [f64]) = if let Some(l) = &chol {
                    cw.copy_from_slice(&c);
                    sw.copy_from_slice(&s);
                    forward_substitute(l, n, &mut cw);
                    forward_substitute(l, n, &mut sw);
                    (&mut cw, &mut sw)
                } else {
                    (&mut c, &mut s)
                };
                let rot = rotation
                    .as_ref()
                    .filter(|_| fuse)
                    .map(|(rc, rs)| (rc.as_slice(), rs.as_slice()));
                let sums = accumulate(cur_c, cur_s, rot, &w, &wg, &wphi[0]);
                // N12 columns (pc_k, ps_k); the first came with the sums.
                pc[0] = sums.pc;
                ps[0] = sums.ps;
                for (k, col) in wphi.iter().enumerate().skip(1) {
                    pc[k] = col.iter().zip(cur_c.iter()).map(|(a, b)| a * b).sum();
                    ps[k] = col.iter().zip(cur_s.iter()).map(|(a, b)| a * b).sum();
                }
                if !fuse {
                    if let Some((rc, rs)) = &rotation {
                        rotate(&mut c, &mut s, rc, rs);
                    }
                }
                // Z = N11⁻¹ N12 (u × 2), M = N22 − N12ᵀ Z.
                for a in 0..u {
                    let row = &n11_inv[a * u..(a + 1) * u];
                    z[2 * a] = row.iter().zip(&pc).map(|(x, y)| x * y).sum();
                    z[2 * a + 1] = row.iter().zip(&ps).map(|(x, y)| x * y).sum();
                }
                let mut m11 = sums.cc;
                let mut m12 = sums.cs;
                let mut m22 = sums.ss;
                for a in 0..u {
                    m11 -= pc[a] * z[2 * a];
                    m12 -= pc[a] * z[2 * a + 1];
                    m22 -= ps[a] * z[2 * a + 1];
                }
                let q = quad_pinv(m11, m12, m22, sums.cg, sums.sg);
                *o = (q / residual_norm).clamp(0.0, 1.0);
            }
        });

    Ok(LssaResult {
        spectrum,
        n_known: u,
        known_params: params,
        t_ref,
        residual_norm,
    })
}

fn rotate(c: &mut [f64], s: &mut [f64], rc: &[f64], rs: &[f64]) {
    for k in 0..c.len() {
        let (ck, sk) = (c[k], s[k]);
        c[k] = ck * rc[k] - sk * rs[k];
        s[k] = sk * rc[k] + ck * rs[k];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(n: usize) -> (Vec<f64>, Vec<f64>) {
        // Irregular times with a gap, a 0.37-cycle sinusoid and deterministic "noise".
        let mut t = Vec::with_capacity(n);
        let mut tk = 0.0;
        for i in 0..n {
            tk += 0.5 + 0.9 * ((i as f64 * 0.754_877_666).fract());
            if i == n / 2 {
                tk += 20.0;
            }
            t.push(tk);
        }
        let y = t
            .iter()
            .enumerate()
            .map(|(i, &v)| (TWO_PI * 0.37 * v).sin() + 0.3 * ((i as f64 * 0.618_034).fract() - 0.5))
            .collect();
        (t, y)
    }

    #[test]
    fn critical_value_spec() {
        assert!((critical_value(600, 1, 0.01).unwrap() - 0.01530931).abs() < 5e-9);
        assert!(critical_value(3, 1, 0.01).is_err());
        assert!(critical_value(600, 1, 1.0).is_err());
    }

    #[test]
    fn recurrence_equals_direct() {
        let (t, y) = series(301);
        let freqs: Vec<f64> = (1..200).map(|k| f64::from(k) * 0.005).collect();
        let a = lssa(&t, &y, &freqs, &LssaOptions::default()).unwrap();
        // A non-uniform grid takes the direct path: perturb one frequency, compare the rest.
        let mut f2 = freqs.clone();
        f2[0] *= 1.0 + 1e-6;
        let b = lssa(&t, &y, &f2, &LssaOptions::default()).unwrap();
        for j in 1..freqs.len() {
            assert!((a.spectrum[j] - b.spectrum[j]).abs() < 1e-13);
        }
        let peak = (0..freqs.len())
            .max_by(|&i, &j| a.spectrum[i].total_cmp(&a.spectrum[j]))
            .unwrap();
        assert!((freqs[peak] - 0.37).abs() < 0.006);
    }

    #[test]
    fn unit_covariance_equals_unweighted() {
        let (t, y) = series(60);
        let freqs: Vec<f64> = (1..40).map(|k| f64::from(k) * 0.013).collect();
        let mut cov = vec![0.0; 60 * 60];
        for i in 0..60 {
            cov[i * 60 + i] = 4.0;
        }
        let plain = lssa(&t, &y, &freqs, &LssaOptions::default()).unwrap();
        let opts = LssaOptions {
            cov: Some(&cov),
            trend: true,
            ..LssaOptions::default()
        };
        let with_cov = lssa(&t, &y, &freqs, &opts).unwrap();
        let opts = LssaOptions {
            trend: true,
            ..LssaOptions::default()
        };
        let trend = lssa(&t, &y, &freqs, &opts).unwrap();
        for j in 0..freqs.len() {
            assert!((with_cov.spectrum[j] - trend.spectrum[j]).abs() < 1e-12);
        }
        assert!(plain.spectrum.iter().all(|v| (0.0..=1.0).contains(v)));
    }

    #[test]
    fn rejects_bad_times_and_known_frequency() {
        let (t, y) = series(50);
        let mut bad = t.clone();
        bad.swap(3, 4);
        let e = lssa(&bad, &y, &[0.1], &LssaOptions::default()).unwrap_err();
        assert!(e.to_string().contains("unsorted"));
        bad = t.clone();
        bad[4] = bad[3];
        let e = lssa(&bad, &y, &[0.1], &LssaOptions::default()).unwrap_err();
        assert!(e.to_string().contains("duplicate"));
        let opts = LssaOptions {
            known_periods: &[10.0],
            ..LssaOptions::default()
        };
        assert!(matches!(
            lssa(&t, &y, &[0.1], &opts),
            Err(Error::InvalidParameter { name: "freqs", .. })
        ));
    }
}
