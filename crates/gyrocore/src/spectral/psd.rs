//! One-sided power spectral density of regularly sampled data by Welch's method
//! (Welch 1967; the conventions of `scipy.signal.welch(..., scaling="density",
//! detrend="constant", average="mean")`).
//!
//! The series is cut into segments of `nperseg` samples overlapping by `noverlap`
//! (`⌊(n − noverlap)/(nperseg − noverlap)⌋` segments). Each segment has its mean removed, is
//! multiplied by the window $w$ and transformed, $X_k = \sum_j w_j x_j e^{-2\pi i jk/L}$. The
//! one-sided density is
//! $$ P(f_k) = \frac{c_k\,\overline{|X_k|^2}}{f_s \sum_j w_j^2},\quad f_k = k f_s/L,\
//!   k = 0..\lfloor L/2\rfloor, $$
//! with $c_k = 2$ except at DC and, for even $L$, the Nyquist bin ($c_k = 1$), averaged over the
//! segments. Units: (input unit)²/Hz; its integral over $[0, f_s/2]$ is the variance. White
//! noise of standard deviation $\sigma$ has $P = 2\sigma^2/f_s$, i.e. the one-sided noise
//! density $\sqrt{P} = \sigma\sqrt{2/f_s}$ (datasheet convention; the IEEE-952 angle random walk
//! is $N = \sqrt{P/2}$, SPEC §1).

use std::sync::Arc;

use rayon::prelude::*;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

use crate::{Error, Result, validate};

/// Segment window of [`welch`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Window {
    /// Periodic Hann window $w_j = \tfrac12 - \tfrac12\cos(2\pi j/L)$ (SciPy's `"hann"`).
    Hann,
    /// Rectangular window (with one segment: the plain periodogram).
    Boxcar,
}

impl Window {
    /// Parses `"hann"` or `"boxcar"`.
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "hann" => Ok(Self::Hann),
            "boxcar" => Ok(Self::Boxcar),
            other => Err(Error::invalid(
                "window",
                format!("must be 'hann' or 'boxcar', got {other:?}"),
            )),
        }
    }
}

/// Welch PSD of `x` sampled at `fs` Hz; returns `(freqs, psd)` (see the module docs).
///
/// Errors: non-finite `x`; `fs` ≤ 0 or subnormal (no finite period, so the density would
/// overflow); `nperseg < 2` or larger than the series;
/// `noverlap ≥ nperseg`.
pub fn welch(
    x: &[f64],
    fs: f64,
    nperseg: usize,
    noverlap: usize,
    window: Window,
) -> Result<(Vec<f64>, Vec<f64>)> {
    validate::sample_period(fs)?;
    validate::finite("x", x)?;
    if nperseg < 2 {
        return Err(Error::invalid(
            "nperseg",
            format!("must be >= 2, got {nperseg}"),
        ));
    }
    if nperseg > x.len() {
        return Err(Error::invalid(
            "nperseg",
            format!(
                "must be at most the length of x ({} samples), got {nperseg} (x is too short: \
                 {nperseg} samples needed)",
                x.len()
            ),
        ));
    }
    if noverlap >= nperseg {
        return Err(Error::invalid(
            "noverlap",
            format!("must be < nperseg = {nperseg}, got {noverlap}"),
        ));
    }
    let step = nperseg - noverlap;
    let nseg = (x.len() - noverlap) / step;
    let win: Vec<f64> = match window {
        Window::Hann => (0..nperseg)
            .map(|j| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * j as f64 / nperseg as f64).cos())
            .collect(),
        Window::Boxcar => vec![1.0; nperseg],
    };
    let wss: f64 = win.iter().map(|w| w * w).sum();
    let nbins = nperseg / 2 + 1;
    let fft: Arc<dyn rustfft::Fft<f64>> = FftPlanner::new().plan_fft_forward(nperseg);
    let sum = (0..nseg)
        .into_par_iter()
        .fold(
            || (vec![0.0; nbins], vec![Complex::new(0.0, 0.0); nperseg]),
            |(mut acc, mut buf), s| {
                let seg = &x[s * step..s * step + nperseg];
                let mean = seg.iter().sum::<f64>() / nperseg as f64;
                for ((b, &v), &w) in buf.iter_mut().zip(seg).zip(&win) {
                    *b = Complex::new((v - mean) * w, 0.0);
                }
                fft.process(&mut buf);
                for (a, b) in acc.iter_mut().zip(&buf) {
                    *a += b.norm_sqr();
                }
                (acc, buf)
            },
        )
        .map(|(acc, _)| acc)
        .reduce(
            || vec![0.0; nbins],
            |mut a, b| {
                for (x, y) in a.iter_mut().zip(&b) {
                    *x += y;
                }
                a
            },
        );
    let scale = 1.0 / (fs * wss * nseg as f64);
    let psd: Vec<f64> = sum
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            let one_sided = if k == 0 || (nperseg % 2 == 0 && k == nperseg / 2) {
                1.0
            } else {
                2.0
            };
            p * scale * one_sided
        })
        .collect();
    if psd.iter().any(|p| !p.is_finite()) {
        // |X|² of data near 1e154 and above (or at a tiny fs) leaves float64: refused with
        // the reason rather than returned as inf
        return Err(Error::invalid(
            "x",
            "gives a power spectral density beyond float64's range (data of this magnitude \
             square to more than 1.8e308): rescale the data (another unit)",
        ));
    }
    let freqs = (0..nbins).map(|k| k as f64 * fs / nperseg as f64).collect();
    Ok((freqs, psd))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parseval_for_boxcar_periodogram() {
        // One boxcar segment: Σ P·Δf equals the (population) variance of x exactly.
        let x: Vec<f64> = (0..64).map(|i| f64::from(i * 37 % 11).sin()).collect();
        let (f, p) = welch(&x, 10.0, 64, 0, Window::Boxcar).unwrap();
        let df = f[1] - f[0];
        let mean = x.iter().sum::<f64>() / 64.0;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 64.0;
        assert!((p.iter().sum::<f64>() * df - var).abs() < 1e-12);
        assert!(welch(&x, 10.0, 65, 0, Window::Hann).is_err());
        assert!(welch(&x, 10.0, 32, 32, Window::Hann).is_err());
    }
}
