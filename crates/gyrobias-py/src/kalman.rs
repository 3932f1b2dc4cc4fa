//! Bindings of `gyrocore::kalman`.

use gyrocore::kalman::{self, DiscreteNoise, FilterState, Form};
use numpy::PyUntypedArrayMethods;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::error::core;

/// Designed fixed-gain filter (immutable; safe to share between threads).
#[pyclass(name = "FixedGainKalmanCore", module = "gyrobias._core", frozen)]
struct FixedGainKalmanCore {
    inner: kalman::FixedGainKalman,
}

fn design(
    fs: f64,
    arw: f64,
    rrw: f64,
    q_omega: Option<f64>,
    bandwidth: Option<f64>,
    form: &str,
) -> PyResult<kalman::FixedGainKalman> {
    let noise = core(DiscreteNoise::from_coefficients(fs, arw, rrw))?;
    let form = core(Form::parse(form))?;
    match (q_omega, bandwidth) {
        (Some(q), None) => core(kalman::FixedGainKalman::new(noise, q, form)),
        (None, Some(bw)) => core(kalman::FixedGainKalman::with_bandwidth(noise, bw, form)),
        _ => Err(pyo3::exceptions::PyValueError::new_err(
            "give exactly one of q_omega and bandwidth",
        )),
    }
}

fn vec2(py: Python<'_>, v: [f64; 2]) -> Bound<'_, PyArray1<f64>> {
    v.to_vec().into_pyarray(py)
}

/// Row-major 2×2 array from `m[(row, col)]` (nalgebra stores column-major: never copy its
/// storage order into NumPy).
fn mat2(py: Python<'_>, m: [[f64; 2]; 2]) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let rows = vec![m[0].to_vec(), m[1].to_vec()];
    Ok(PyArray2::from_vec2(py, &rows)?)
}

macro_rules! rows {
    ($m:expr) => {{
        let m = $m;
        [[m[(0, 0)], m[(0, 1)]], [m[(1, 0)], m[(1, 1)]]]
    }};
}

#[pymethods]
impl FixedGainKalmanCore {
    #[new]
    #[pyo3(signature = (fs, arw, rrw, q_omega, bandwidth, form))]
    fn new(
        fs: f64,
        arw: f64,
        rrw: f64,
        q_omega: Option<f64>,
        bandwidth: Option<f64>,
        form: &str,
    ) -> PyResult<Self> {
        Ok(FixedGainKalmanCore {
            inner: design(fs, arw, rrw, q_omega, bandwidth, form)?,
        })
    }

    #[getter]
    fn q_omega(&self) -> f64 {
        self.inner.q_omega()
    }
    #[getter]
    fn r_d(&self) -> f64 {
        self.inner.noise().r_d
    }
    #[getter]
    fn q_b(&self) -> f64 {
        self.inner.noise().q_b
    }
    #[getter]
    fn kappa(&self) -> f64 {
        self.inner.kappa()
    }
    #[getter]
    fn pole(&self) -> f64 {
        self.inner.pole()
    }
    #[getter]
    fn dc_gain(&self) -> f64 {
        self.inner.dc_gain()
    }
    #[getter]
    fn white_noise_gain(&self) -> f64 {
        self.inner.white_noise_gain()
    }
    #[getter]
    fn bandwidth(&self) -> Option<f64> {
        self.inner.bandwidth()
    }
    #[getter]
    fn gain<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec2(py, self.inner.gain().into())
    }
    #[getter]
    fn continuous_gain<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec2(py, self.inner.continuous_gain().into())
    }
    #[getter]
    fn g<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec2(py, self.inner.g().into())
    }
    #[getter]
    fn a<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        mat2(py, rows!(self.inner.a()))
    }
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        mat2(py, rows!(self.inner.b()))
    }

    /// Complex response z → rate estimate at `freqs` (Hz) as (real, imag).
    #[allow(clippy::type_complexity)]
    fn frequency_response<'py>(
        &self,
        py: Python<'py>,
        freqs: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
        let f = freqs.as_slice()?;
        let mut re = vec![0.0; f.len()];
        let mut im = vec![0.0; f.len()];
        core(self.inner.frequency_response_into(f, &mut re, &mut im))?;
        Ok((re.into_pyarray(py), im.into_pyarray(py)))
    }

    /// Filters a C-contiguous (samples × axes) array from the state (rate, level) per axis.
    ///
    /// Returns (rate, bias) as flat arrays in the layout of `z` and the new (rate, level).
    #[allow(clippy::type_complexity, clippy::needless_pass_by_value)]
    fn filter<'py>(
        &self,
        py: Python<'py>,
        z: PyReadonlyArray2<'py, f64>,
        rate0: Vec<f64>,
        level0: Vec<f64>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Vec<f64>,
        Vec<f64>,
    )> {
        let n_axes = z.shape()[1];
        let data = z.as_slice()?;
        let mut state = FilterState {
            rate: rate0,
            level: level0,
        };
        let inner = &self.inner;
        let (rate, bias, state) = core(py.detach(move || {
            let (r, b) = inner.filter(data, n_axes, &mut state)?;
            Ok((r, b, state))
        }))?;
        Ok((
            rate.into_pyarray(py),
            bias.into_pyarray(py),
            state.rate,
            state.level,
        ))
    }
}

/// Closed-form steady-state gain [k1, k2] (SPEC §6).
#[pyfunction]
fn kalman_steady_state_gain(
    py: Python<'_>,
    q_omega: f64,
    q_b: f64,
    r_d: f64,
) -> PyResult<Bound<'_, PyArray1<f64>>> {
    Ok(vec2(
        py,
        core(kalman::steady_state_gain(q_omega, q_b, r_d))?.into(),
    ))
}

/// Gain after `iterations` steps of [NR] eqs. 9–11 from P0 = 0.
#[pyfunction]
fn kalman_riccati_gain(
    py: Python<'_>,
    q_omega: f64,
    q_b: f64,
    r_d: f64,
    iterations: usize,
) -> PyResult<Bound<'_, PyArray1<f64>>> {
    Ok(vec2(
        py,
        core(kalman::riccati_gain(q_omega, q_b, r_d, iterations))?.into(),
    ))
}

/// Per-step q_omega for a target −3 dB bandwidth (Hz).
#[pyfunction]
fn kalman_q_omega_for_bandwidth(
    bandwidth: f64,
    fs: f64,
    arw: f64,
    rrw: f64,
    form: &str,
) -> PyResult<f64> {
    let noise = core(DiscreteNoise::from_coefficients(fs, arw, rrw))?;
    let form = core(Form::parse(form))?;
    core(kalman::q_omega_for_bandwidth(bandwidth, &noise, form))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<FixedGainKalmanCore>()?;
    m.add_function(wrap_pyfunction!(kalman_steady_state_gain, m)?)?;
    m.add_function(wrap_pyfunction!(kalman_riccati_gain, m)?)?;
    m.add_function(wrap_pyfunction!(kalman_q_omega_for_bandwidth, m)?)
}
