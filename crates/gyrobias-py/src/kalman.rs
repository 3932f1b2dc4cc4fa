//! Bindings of `gyrocore::kalman`.

use gyrocore::kalman::{self, DiscreteNoise, Form};
use numpy::PyUntypedArrayMethods;
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArray1,
    PyReadonlyArrayDyn,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::array::{c_order, c_order_mut};
use crate::count;
use crate::error::core;

/// Designed fixed-gain filter (immutable; safe to share between threads).
#[pyclass(name = "FixedGainKalman", module = "gyrobias._core.kalman", frozen)]
struct FixedGainKalman {
    inner: kalman::FixedGainKalman,
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
impl FixedGainKalman {
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
        let noise = core(DiscreteNoise::from_coefficients(fs, arw, rrw))?;
        let form = core(Form::parse(form))?;
        Ok(FixedGainKalman {
            inner: core(kalman::FixedGainKalman::design(
                noise, q_omega, bandwidth, form,
            ))?,
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
    #[allow(clippy::type_complexity, clippy::needless_pass_by_value)]
    fn frequency_response<'py>(
        &self,
        py: Python<'py>,
        freqs: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
        let f = c_order(&freqs);
        let mut re = vec![0.0; f.len()];
        let mut im = vec![0.0; f.len()];
        core(self.inner.frequency_response_into(&f, &mut re, &mut im))?;
        Ok((re.into_pyarray(py), im.into_pyarray(py)))
    }

    /// The state before the first sample for initial estimates rate0 = ω̂₀, bias0 = b̂₀
    /// (`gyrocore::kalman::FixedGainKalman::initial_state`).
    #[allow(clippy::needless_pass_by_value)]
    fn initial_state(&self, rate0: Vec<f64>, bias0: Vec<f64>) -> PyResult<KalmanState> {
        Ok(KalmanState(core(self.inner.initial_state(&rate0, &bias0))?))
    }

    /// `(p, g1, g2, 1 − p)` as the kernels use them
    /// (`gyrocore::kalman::FixedGainKalman::kernel_coefficients`).
    fn kernel_coefficients(&self) -> (f64, f64, f64, f64) {
        let [p, g1, g2, k] = self.inner.kernel_coefficients();
        (p, g1, g2, k)
    }

    /// The state before the first sample, computed in float32 arithmetic
    /// (`gyrocore::kalman::FixedGainKalman::initial_state_in::<f32>`).
    #[allow(clippy::needless_pass_by_value)]
    fn initial_state_f32(&self, rate0: Vec<f32>, bias0: Vec<f32>) -> PyResult<KalmanState> {
        Ok(KalmanState(core(
            self.inner.initial_state_in(&rate0, &bias0),
        )?))
    }

    /// Float32 filtering of a (samples,) or (samples × axes) float32 array `z` from `state`
    /// into new float32 arrays; returns (rate, bias, new state)
    /// (`gyrocore::kalman::FixedGainKalman::filter_into_f32`).
    #[allow(clippy::needless_pass_by_value, clippy::type_complexity)]
    fn filter_f32<'py>(
        &self,
        py: Python<'py>,
        z: PyReadonlyArrayDyn<'py, f32>,
        state: &KalmanState,
    ) -> PyResult<(
        Bound<'py, PyArrayDyn<f32>>,
        Bound<'py, PyArrayDyn<f32>>,
        KalmanState,
    )> {
        let n_axes = axes_of(z.shape())?;
        let shape = z.shape().to_vec();
        let data = c_order(&z);
        let mut rate = vec![0.0_f32; data.len()];
        let mut bias = vec![0.0_f32; data.len()];
        let mut next = state.0.clone();
        core(py.detach(|| {
            self.inner
                .filter_into_f32(&data, n_axes, &mut next, &mut rate, &mut bias)
        }))?;
        Ok((
            rate.into_pyarray(py).reshape(shape.clone())?,
            bias.into_pyarray(py).reshape(shape)?,
            KalmanState(next),
        ))
    }

    /// The default state before the first row of a (samples,) or (samples × axes) array `z`:
    /// `[z₀, 0]` per axis (`gyrocore::kalman::FixedGainKalman::initial_state_from_first_sample`).
    #[allow(clippy::needless_pass_by_value)]
    fn initial_state_from_first_sample(
        &self,
        z: PyReadonlyArrayDyn<'_, f64>,
    ) -> PyResult<KalmanState> {
        let n_axes = axes_of(z.shape())?;
        let data = c_order(&z);
        Ok(KalmanState(core(
            self.inner.initial_state_from_first_sample(&data, n_axes),
        )?))
    }

    /// The estimates (rate, bias) per axis that a state stands for
    /// (`gyrocore::kalman::FixedGainKalman::estimates`).
    fn estimates(&self, state: &KalmanState) -> PyResult<(Vec<f64>, Vec<f64>)> {
        core(self.inner.estimates(&state.0))
    }

    /// Filters a (samples,) or (samples × axes) array `z` from `state` into the preallocated
    /// C-contiguous `rate` and `bias` arrays of the same shape; returns the new state
    /// (`gyrocore::kalman::FixedGainKalman::filter_into`).
    /// Allocation is left to the caller (NumPy's allocator asks the kernel for huge pages,
    /// which halves the page-fault cost of large outputs).
    #[allow(clippy::needless_pass_by_value)]
    fn filter_into<'py>(
        &self,
        py: Python<'py>,
        z: PyReadonlyArrayDyn<'py, f64>,
        rate: &Bound<'py, PyArrayDyn<f64>>,
        bias: &Bound<'py, PyArrayDyn<f64>>,
        state: &KalmanState,
    ) -> PyResult<KalmanState> {
        let overlap = |e: numpy::BorrowError| {
            PyValueError::new_err(format!(
                "out arrays must be writeable and overlap neither each other nor z ({e})"
            ))
        };
        let mut rate = rate.try_readwrite().map_err(overlap)?;
        let mut bias = bias.try_readwrite().map_err(overlap)?;
        let n_axes = axes_of(z.shape())?;
        if rate.shape() != z.shape() || bias.shape() != z.shape() {
            return Err(PyValueError::new_err(format!(
                "out arrays must have the shape of z {:?}",
                z.shape()
            )));
        }
        let data = c_order(&z);
        let data = &data[..];
        let rate_out = c_order_mut("rate", &mut rate)?;
        let bias_out = c_order_mut("bias", &mut bias)?;
        let mut next = state.0.clone();
        let inner = &self.inner;
        let mut run = |rate_out: &mut [f64], bias_out: &mut [f64]| {
            inner.filter_into(data, n_axes, &mut next, rate_out, bias_out)
        };
        // Releasing the GIL costs about a microsecond: not worth it for small chunks.
        if data.len() >= 1 << 14 {
            core(py.detach(|| run(rate_out, bias_out)))?;
        } else {
            core(run(rate_out, bias_out))?;
        }
        Ok(KalmanState(next))
    }
}

/// The axis count of a (samples,) or (samples × axes) array: the layout the core reads.
fn axes_of(shape: &[usize]) -> PyResult<usize> {
    match *shape {
        [_] => Ok(1),
        [_, a] => Ok(a),
        _ => Err(PyValueError::new_err(format!(
            "z must be a 1-D or 2-D array, got shape {shape:?}"
        ))),
    }
}

/// Carried state of the fixed-gain filter (immutable, picklable): a thin wrapper of
/// `gyrocore::kalman::KalmanState`, which owns its checks.
#[pyclass(
    name = "KalmanState",
    module = "gyrobias._core.kalman",
    frozen,
    eq,
    skip_from_py_object
)]
#[derive(Clone, PartialEq)]
pub(crate) struct KalmanState(kalman::KalmanState);

#[pymethods]
impl KalmanState {
    #[new]
    #[pyo3(signature = (level, offset, rate, bias, gain, samples=0))]
    fn new(
        level: Vec<f64>,
        offset: Vec<f64>,
        rate: Vec<f64>,
        bias: Vec<f64>,
        gain: [f64; 2],
        #[pyo3(from_py_with = count::samples)] samples: u64,
    ) -> PyResult<Self> {
        Ok(KalmanState(core(kalman::KalmanState::new(
            level, offset, rate, bias, gain, samples,
        ))?))
    }
    #[getter]
    fn level<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.0.level())
    }
    #[getter]
    fn offset<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.0.offset())
    }
    #[getter]
    fn rate<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.0.rate())
    }
    #[getter]
    fn bias<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.0.bias())
    }
    #[getter]
    fn gain(&self) -> (f64, f64) {
        let [g1, g2] = self.0.gain();
        (g1, g2)
    }
    #[getter]
    fn samples(&self) -> u64 {
        self.0.samples()
    }
    #[getter]
    fn n_axes(&self) -> usize {
        self.0.n_axes()
    }
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let s = &slf.get().0;
        let args = (
            s.level().to_vec(),
            s.offset().to_vec(),
            s.rate().to_vec(),
            s.bias().to_vec(),
            slf.get().gain(),
            s.samples(),
        )
            .into_pyobject(py)?;
        Ok((slf.get_type().into_any(), args))
    }
    fn __repr__(&self) -> String {
        format!(
            "KalmanState(rate={:?}, bias={:?}, samples={})",
            self.0.rate(),
            self.0.bias(),
            self.0.samples()
        )
    }
}

/// Closed-form steady-state gain [k1, k2] (SPEC §6; `gyrocore::kalman::steady_state_gain`).
#[pyfunction]
fn steady_state_gain(
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

/// Gain after `iterations` steps of [NR] eqs. 9–11 from P0 = 0
/// (`gyrocore::kalman::riccati_gain`).
#[pyfunction]
fn riccati_gain(
    py: Python<'_>,
    q_omega: f64,
    q_b: f64,
    r_d: f64,
    #[pyo3(from_py_with = count::iterations)] iterations: usize,
) -> PyResult<Bound<'_, PyArray1<f64>>> {
    Ok(vec2(
        py,
        core(kalman::riccati_gain(q_omega, q_b, r_d, iterations))?.into(),
    ))
}

/// Per-step q_omega for a target −3 dB bandwidth (Hz)
/// (`gyrocore::kalman::q_omega_for_bandwidth`).
#[pyfunction]
fn q_omega_for_bandwidth(bandwidth: f64, fs: f64, arw: f64, rrw: f64, form: &str) -> PyResult<f64> {
    let noise = core(DiscreteNoise::from_coefficients(fs, arw, rrw))?;
    let form = core(Form::parse(form))?;
    core(kalman::q_omega_for_bandwidth(bandwidth, &noise, form))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<FixedGainKalman>()?;
    m.add_class::<KalmanState>()?;
    m.add_function(wrap_pyfunction!(steady_state_gain, m)?)?;
    m.add_function(wrap_pyfunction!(riccati_gain, m)?)?;
    m.add_function(wrap_pyfunction!(q_omega_for_bandwidth, m)?)
}
